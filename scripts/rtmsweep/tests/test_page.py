"""The study pages' writer: the generated part between the markers is replaced, the prose around
it kept; the stamp says the build, the date and the runs; the README table is read back from it."""

import os
import stat

import pytest

from rtmsweep import page

PAGE = """# A study

Command: `scripts/x`
Output: out/x/

The question, by hand.

<!-- begin: written by scripts/x, do not edit -->
old table
<!-- end: written by scripts/x -->

## Findings

By hand too.
"""


def test_update_replaces_only_the_generated_part(tmp_path):
    p = tmp_path / "x.md"
    p.write_text(PAGE)
    page.update(str(p), "scripts/x", "# Table\n\n| a |\n|---|\n| 1 |\n", "rtm 0.1", "2, 1.0 min", date="2026-01-02")
    text = p.read_text()
    assert "old table" not in text
    assert text.startswith("# A study\n\nCommand: `scripts/x`")
    assert text.endswith("## Findings\n\nBy hand too.\n")
    assert ("<!-- begin: written by scripts/x, do not edit -->\n- build: `rtm 0.1`\n- written: 2026-01-02\n"
            "- runs: 2, 1.0 min\n\n### Table\n\n| a |\n|---|\n| 1 |\n<!-- end: written by scripts/x -->") in text
    assert page.record(str(p)) == [{"who": "scripts/x", "build": "rtm 0.1", "written": "2026-01-02", "runs": "2, 1.0 min"}]
    # Again: the same page, the prose untouched.
    page.update(str(p), "scripts/x", "| b |\n", page.NOT_RECORDED, date="2026-01-03")
    assert page.record(str(p)) == [{"who": "scripts/x", "build": page.NOT_RECORDED, "written": "2026-01-03"}]
    assert p.read_text().count("By hand too.") == 1


def test_a_page_without_its_markers_is_refused(tmp_path):
    p = tmp_path / "x.md"
    p.write_text("# A study\n")
    with pytest.raises(page.PageError, match="no part written by scripts/y"):
        page.update(str(p), "scripts/y", "| a |\n", "rtm 0.1")
    assert p.read_text() == "# A study\n"
    with pytest.raises(page.PageError, match="cannot read"):
        page.update(str(tmp_path / "none.md"), "scripts/y", "", "rtm 0.1")


def test_runs_line_sums_the_recorded_wall_time():
    assert page.runs_line([{"wall_seconds": "60"}, {"wall_seconds": "180"}]) == \
        "2, 4.0 min of run time in all (about 2 min on 2 cores)"
    assert page.runs_line([{"wall_seconds": "120"}, {"wall_seconds": ""}]) == \
        "2, 2.0 min of run time in all (about 1 min on 2 cores); 1 without a recorded time"
    assert page.runs_line([{}]) == "1, run time not recorded"


def test_build_is_what_rtm_version_prints(tmp_path):
    fake = tmp_path / "rtm"
    fake.write_text("#!/bin/sh\necho 'rtm 9.9'\necho 'commit abc1234, tree modified'\n")
    fake.chmod(fake.stat().st_mode | stat.S_IXUSR)
    assert page.build_of(str(fake)) == "rtm 9.9; commit abc1234, tree modified"
    assert page.build_of(str(tmp_path / "missing")) == page.NOT_RECORDED
