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
    assert f"old1: {build}/rtm" in lines and f"old2: {build}/rtm" in lines, r.stdout
    at = next(i for i, l in enumerate(lines) if l.startswith("| scene | model |"))
    header = lines[at]
    assert header.count("wall s") == 3 and "new / old1" in header and "new / old2" in header, header
    assert header.count("× reference") == 3, header
    rows = [l.split(" | ") for l in lines[at + 2:] if l.startswith("| balls-1 |")]
    assert len(rows) == 6, r.stdout
    for cells in rows:
        assert len(cells) == len(header.split(" | ")), cells
    assert all(cells[-1] == "True |" for cells in rows[1:]), r.stdout


def test_a_build_without_rtm_is_refused_before_anything_is_timed(tmp_path):
    r = subprocess.run([BENCH, "--dir", str(tmp_path), "--against", str(tmp_path / "nowhere"), "balls-1"],
                       capture_output=True, text=True, stdin=subprocess.DEVNULL, timeout=60)
    assert r.returncode == 2, r.stdout + r.stderr
    assert f"no rtm program at {tmp_path}/nowhere/rtm" in r.stderr and r.stdout == "", r.stdout + r.stderr
