"""What the sweep tests share: the scripts, running a command, reading a CSV, checking a PNG."""

import csv
import io
import os
import subprocess
import sys

SCRIPTS = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ROOT = os.path.dirname(SCRIPTS)
SCENES = os.path.join(ROOT, "scenes", "spd")
SWEEP = os.path.join(SCRIPTS, "sweep")
SWEEP_RUN = os.path.join(SCRIPTS, "sweep-run")
PLOT_SWEEP = os.path.join(SCRIPTS, "plot-sweep")
PLOTS = ["cycles.png", "speedup.png", "utilisation.png", "pe_utilisation.png", "load_imbalance.png",
         "phases.png", "cost.png", "energy.png"]

sys.path.insert(0, SCRIPTS)  # the rtmsweep package


def env():
    return dict(os.environ, SYSTEMC_DISABLE_COPYRIGHT_MESSAGE="1", PYTHONDONTWRITEBYTECODE="1")


def sh(*cmd, cwd=None, timeout=120):
    """Runs a command (no stdin), its output captured as text."""
    return subprocess.run([str(c) for c in cmd], capture_output=True, text=True, stdin=subprocess.DEVNULL,
                          cwd=cwd, env=env(), timeout=timeout)


def write_spec(path, text):
    """A spec file whose scene_dir is the checkout's SPD scenes."""
    path.write_text(f"scene_dir: {SCENES}\n" + text)
    return path


def read_csv(path):
    """(header, rows as dicts) of a CSV file, checking that every row has every column."""
    with open(path, newline="") as f:
        records = list(csv.reader(io.StringIO(f.read())))
    head = records[0]
    for r in records[1:]:
        assert len(r) == len(head), f"{path}: a row of {len(r)} cells under {len(head)} columns: {r}"
    return head, [dict(zip(head, r)) for r in records[1:]]


def row_files(out):
    """The row files in OUT/runs/, sorted: one per run that is done."""
    runs = out / "runs"
    return sorted(n for n in os.listdir(runs) if n.endswith(".row")) if runs.is_dir() else []


def is_number(s):
    try:
        float(s)
    except (TypeError, ValueError):
        return False
    return True


def check_png(path):
    """A PNG file of a plausible plot size."""
    data = path.read_bytes() if hasattr(path, "read_bytes") else open(path, "rb").read()
    assert len(data) > 5000, path
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    assert data[12:16] == b"IHDR", path
    assert int.from_bytes(data[16:20], "big") > 300, path  # width
    assert int.from_bytes(data[20:24], "big") > 200, path  # height
