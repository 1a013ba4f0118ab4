"""scripts/bench-model: the model against the reference, and against earlier builds side by side."""

import os
import subprocess


BENCH = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "bench-model")


def test_builds_given_with_against_are_timed_in_one_table_with_their_own_references(rtm, tmp_path):
    # The same build twice stands for two earlier ones: every row has each build's time and
    # ratios, and the same binary gives the same cycles.
    build = os.path.dirname(rtm)
    r = subprocess.run([BENCH, "--runs", "1", "--size", "8x8", "--clocked-size", "8x8", "--dir", str(tmp_path),
                        "--against", build, "--against", build, "balls-1"],
                       capture_output=True, text=True, stdin=subprocess.DEVNULL, timeout=240,
                       env=dict(os.environ, RTM_BUILD_DIR=build))
    assert r.returncode == 0, r.stdout + r.stderr
    lines = r.stdout.splitlines()
    version = subprocess.run([rtm, "--version"], capture_output=True, text=True).stdout.strip()
    assert f"old1: {version}" in lines and f"old2: {version}" in lines, r.stdout
    at = next(i for i, l in enumerate(lines) if l.startswith("| scene | model |"))
    header = lines[at]
    assert header.count("wall s") == 3 and "new / old1" in header and "new / old2" in header, header
    assert header.count("× reference") == 3, header
    end = lines.index("", at)
    rows = [l.split(" | ") for l in lines[at + 2:end] if l.startswith("| balls-1 |")]
    assert len(rows) == 6, r.stdout
    for cells in rows:
        assert len(cells) == len(header.split(" | ")), cells
    assert all(cells[-1] == "True |" for cells in rows[1:]), r.stdout
    # Clocked timing: each build's simulated cycles per second on the same frame.
    at = next(i for i, l in enumerate(lines) if l.startswith("| scene | new wall s |"))
    header = lines[at]
    assert header.count("cycles/s") == 3 and "new / old2" in header, header
    cells = lines[at + 2].split(" | ")
    assert cells[0] == "| balls-1" and len(cells) == len(header.split(" | ")), lines[at + 2]
    assert cells[-1] == "True |" and all(int(c.replace(",", "")) > 0 for c in cells[6:9]), cells


def test_a_build_without_rtm_is_refused_before_anything_is_timed(tmp_path):
    r = subprocess.run([BENCH, "--dir", str(tmp_path), "--against", str(tmp_path / "nowhere"), "balls-1"],
                       capture_output=True, text=True, stdin=subprocess.DEVNULL, timeout=60)
    assert r.returncode == 2, r.stdout + r.stderr
    assert f"no rtm program at {tmp_path}/nowhere/rtm" in r.stderr and r.stdout == "", r.stdout + r.stderr


def test_paper_rows_time_both_presets_against_the_reference_on_the_benchmark_scenes(rtm, tmp_path):
    build = os.path.dirname(rtm)
    r = subprocess.run([BENCH, "--runs", "1", "--paper-only", "--paper-size", "8x8", "--dir", str(tmp_path)],
                       capture_output=True, text=True, stdin=subprocess.DEVNULL, timeout=240,
                       env=dict(os.environ, RTM_BUILD_DIR=build))
    assert r.returncode == 0, r.stdout + r.stderr
    lines = r.stdout.splitlines()
    # --paper-only: none of the quick rows; each scene's reference, then both presets with their
    # ratio to it and their cycles.
    assert not any(l.startswith("| scene | renderer | PEs |") for l in lines), r.stdout
    for scene in ("balls-4", "rings-7", "tree-11"):
        mine = [l.split(" | ") for l in lines if l.startswith(f"| {scene} |")]
        assert [cells[1] for cells in mine] == [
            "reference, 1 thread", "model fast, paper preset", "model fast, default preset"], r.stdout
        assert all(float(cells[3]) > 0 and int(cells[6].replace(",", "")) > 0 for cells in mine[1:]), r.stdout
