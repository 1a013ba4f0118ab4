"""What a change costs a study (scripts/bench-sweep): the comparison of two builds' results finds
exactly the simulated figures that differ, and a whole run times the sweep with each build."""

import os

import pytest

from rtmsweep import bench, spec
from support import SCRIPTS, sh, write_spec

HEAD = ["run_id", "status", "pes", "cycles", "wall_seconds", "commit", "frame_cycles"]


def rows(*values):
    return [dict(zip(HEAD, v)) for v in values]


def test_the_same_figures_with_other_wall_times_and_builds_are_the_same():
    new = (HEAD, rows(("a", "ok", "1", "100", "1.5", "abc", "100"), ("b", "ok", "2", "60", "0.9", "abc", "60")))
    old = (HEAD, rows(("b", "ok", "2", "60", "2.0", "def", "60"), ("a", "ok", "1", "100", "3.1", "def", "100")))
    assert bench.differences(new, old) == ([], [], {})


def test_each_differing_figure_is_counted_by_its_column():
    new = (HEAD, rows(("a", "ok", "1", "100", "1", "x", "100"), ("b", "ok", "2", "60", "1", "x", "60")))
    old = (HEAD, rows(("a", "ok", "1", "101", "1", "x", "101"), ("b", "ok", "2", "60", "1", "x", "60")))
    assert bench.differences(new, old) == ([], [], {"cycles": 1, "frame_cycles": 1})


def test_a_run_or_a_column_in_one_build_only_is_named_not_compared():
    new = (HEAD, rows(("a", "ok", "1", "100", "1", "x", "100"), ("c", "ok", "4", "40", "1", "x", "40")))
    # An older build leaves a column it does not know empty in every row.
    old = (HEAD, rows(("a", "ok", "1", "100", "1", "x", ""), ("b", "ok", "2", "60", "1", "x", "")))
    assert bench.differences(new, old) == (["b", "c"], ["frame_cycles"], {})


SPEC = """name: two-runs
scenes: [balls-1.nff]
sizes: [16x16]
pes: [1, 2]
partition: [scanlines]
"""


def fake_build(folder, rtm, extra):
    """A build folder whose rtm is RTM with EXTRA added to every render: other figures."""
    os.makedirs(folder)
    path = os.path.join(folder, "rtm")
    with open(path, "w") as f:
        f.write(f'#!/bin/sh\nif [ "$1" = render ]; then exec {rtm} "$@" {extra}; fi\nexec {rtm} "$@"\n')
    os.chmod(path, 0o755)
    return folder


def test_a_sweep_timed_with_two_builds_says_whether_their_figures_agree(rtm, tmp_path):
    spec_file = write_spec(tmp_path / "two.yaml", SPEC)
    same = sh(os.path.join(SCRIPTS, "bench-sweep"), spec_file, "--against", os.path.dirname(rtm),
              "--dir", tmp_path / "same", "--jobs", "1", cwd=tmp_path, timeout=300)
    assert same.returncode == 0, same.stderr
    assert "| new | " in same.stdout and "| old | " in same.stdout
    assert "new against old: every simulated figure of every run the same" in same.stdout
    assert (tmp_path / "same" / "tables.md").read_text() == same.stdout

    slower = fake_build(str(tmp_path / "slower"), rtm, "--set root_latency=40")
    differ = sh(os.path.join(SCRIPTS, "bench-sweep"), spec_file, "--against", slower,
                "--dir", tmp_path / "differ", "--jobs", "1", cwd=tmp_path, timeout=300)
    assert differ.returncode == 1, differ.stderr
    assert "new against old: figures differ" in differ.stdout
    assert "`cycles` differs in 2 runs" in differ.stdout


def test_a_missing_build_is_an_error_naming_it(tmp_path):
    spec_file = write_spec(tmp_path / "two.yaml", SPEC)
    r = sh(os.path.join(SCRIPTS, "bench-sweep"), spec_file, "--against", tmp_path / "nowhere", cwd=tmp_path)
    assert r.returncode == 2
    assert "--against" in r.stderr and "nowhere" in r.stderr and "no rtm program" in r.stderr


def test_a_spec_as_it_was_at_a_commit_reads_the_same_scenes_from_elsewhere(tmp_path):
    tiny = os.path.join(SCRIPTS, "sweep-examples", "tiny.yaml")
    # The file as committed (HEAD), moved out of its folder: its relative scene_dir still holds.
    shown = sh("git", "-C", os.path.dirname(tiny), "show", "HEAD:./tiny.yaml")
    if shown.returncode != 0:
        pytest.skip("not a git checkout")
    old = bench.spec_at("HEAD", tiny, str(tmp_path))
    assert os.path.dirname(old) == str(tmp_path)
    assert [j["id"] for j in spec.load(old).jobs()] == [j["id"] for j in spec.load(tiny).jobs()]
    assert [j["scene"] for j in spec.load(old).jobs()] == [j["scene"] for j in spec.load(tiny).jobs()]


def test_a_commit_without_the_spec_is_an_error_naming_it(tmp_path):
    r = sh(os.path.join(SCRIPTS, "bench-sweep"), os.path.join(SCRIPTS, "sweep-examples", "tiny.yaml"),
           "--at", "no-such-commit", "--against", tmp_path, "--dir", tmp_path / "out")
    assert r.returncode == 2
    assert "--at no-such-commit" in r.stderr


def test_a_page_without_its_part_is_refused_before_any_sweep_runs(rtm, tmp_path):
    spec_file = write_spec(tmp_path / "two.yaml", SPEC)
    (tmp_path / "page.md").write_text("# A page\n\nNo markers.\n")
    r = sh(os.path.join(SCRIPTS, "bench-sweep"), spec_file, "--against", os.path.dirname(rtm),
           "--dir", tmp_path / "out", "--page", tmp_path / "page.md", cwd=tmp_path)
    assert r.returncode == 2
    assert "page.md" in r.stderr and "no part written by scripts/bench-sweep" in r.stderr
    assert not (tmp_path / "out").exists()
