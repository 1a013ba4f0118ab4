"""Unit tests of one run: the rtm command line, the error message, the outcome, the row; and two
attempts at one run (scripts/sweep-run, with a stand-in for rtm)."""

import json
import os
import signal
import subprocess
import sys
import time

import pytest

from rtmsweep import columns, run
from support import ROOT, SWEEP_RUN, env, read_csv

JOB = {"id": "balls-1-16x16-p2-01234567", "scene": "/scenes/balls-1.nff", "size": "16x16", "pes": 2,
       "partition": "blocks", "set": {"ray_generation": "pe", "loop_credits": "0"},
       "set_keys": ["variant", "loop_credits"], "variant": "improved", "images": True}


def summary():
    """A summary as rtm writes it: every metric, phases as floats."""
    s = {key: i + 0.5 for i, key in enumerate(columns.SUMMARY_COLUMNS)}
    s.update(cycles=1000, bottleneck="mac", error_psnr_db="inf", rays_primary=256,
             host_preprocess_cycles=100.0, transfer_cycles=200.0, pe_cycles=650.0, gather_cycles=50.0)
    return s


def test_the_rtm_command_passes_every_setting():
    job = dict(JOB, search_units=4, timing="clocked", precision="fp64", config="/m.yaml")
    assert run.rtm_command("/bin/rtm", job, "o.png", "o.json") == [
        "/bin/rtm", "render", "/scenes/balls-1.nff", "--size", "16x16", "--pes", "2", "--partition", "blocks",
        "--search-units", "4", "--timing", "clocked", "--precision", "fp64", "--config", "/m.yaml",
        "--set", "ray_generation=pe", "--set", "loop_credits=0", "--sim-threads", "1", "--out", "o.png",
        "--stats", "o.json", "-q"]
    # GNU parallel runs a job per core: each simulates on one thread.
    assert run.rtm_command("rtm", {"scene": "s.nff"}, "a", "b") == ["rtm", "render", "s.nff", "--sim-threads", "1",
                                                                    "--out", "a", "--stats", "b", "-q"]


def test_a_preset_goes_to_rtm_and_into_its_column():
    job = dict(JOB, preset="paper", config="/m.yaml", set_keys=["variant", "preset", "loop_credits"])
    cmd = run.rtm_command("/bin/rtm", job, "o.png", "o.json")
    assert cmd[cmd.index("--preset"):cmd.index("--preset") + 4] == ["--preset", "paper", "--config", "/m.yaml"]
    assert run.build_row(job, "failed", "rtm: bad", 2, None, host="h")["preset"] == "paper"
    # A job without one: the preset the run's statistics say it used (its --config file may name one).
    no_preset = dict(job)
    del no_preset["preset"]
    assert run.build_row(no_preset, "ok", "", 0, {"preset": "default", "summary": summary()}, host="h")["preset"] == \
        "default"


def test_the_error_is_rtms_last_message():
    assert run.error_line("warning\nrtm: first\nmore\nrtm: the one\ntrailing\n\n") == "rtm: the one"
    assert run.error_line("Segmentation fault\n  \n") == "Segmentation fault"
    assert run.error_line("") == ""


def test_a_row_copies_the_summary():
    stats = {"scene": "balls-1", "width": 16, "height": 16, "pes": 2, "partition": "blocks",
             "search_units": 4, "timing": "fast", "precision": "fp32",
             "config": {"loop_credits": 0, "ray_generation": "pe"}, "summary": summary(),
             "cycles": 999999, "load_imbalance": 9.9}  # only the summary counts
    row = run.build_row(JOB, "ok", "", 0, stats, host="node1")
    head = columns.header(JOB["set_keys"])
    assert set(row) == set(head)
    for key in columns.SUMMARY_COLUMNS:
        if key not in columns.INTEGER_COLUMNS:
            assert row[key] == stats["summary"][key], key
    assert row["cycles"] == 1000 and row["error_psnr_db"] == "inf"
    # The phases are whole cycle counts: integers in the CSV.
    assert [row[k] for k in columns.INTEGER_COLUMNS] == [100, 200, 650, 50]
    assert all(isinstance(row[k], int) for k in columns.INTEGER_COLUMNS)
    assert row["host"] == "node1" and row["exit_code"] == 0 and row["scene_file"] == "/scenes/balls-1.nff"
    # A scene in the checkout: its path in the checkout, the same wherever the checkout is.
    inside = run.build_row(dict(JOB, scene=os.path.join(ROOT, "scenes", "spd", "balls-1.nff")), "ok", "", 0, stats)
    assert inside["scene_file"] == "scenes/spd/balls-1.nff"
    # The configuration: the job's settings, else what the run used.
    assert (row["width"], row["height"], row["pes"], row["partition"]) == (16, 16, 2, "blocks")
    assert (row["search_units"], row["timing"], row["precision"]) == (4, "fast", "fp32")
    assert (row["variant"], row["loop_credits"]) == ("improved", "0")


def test_a_row_names_the_build_that_made_it():
    build = {"version": "0.1", "commit": "ab" * 20, "modified": False}
    assert run.build_row(JOB, "ok", "", 0, {"build": build, "summary": summary()}, host="h")["commit"] == "ab" * 20
    build["modified"] = True
    assert run.build_row(JOB, "ok", "", 0, {"build": build, "summary": summary()}, host="h")["commit"] == \
        "ab" * 20 + "-modified"
    assert run.build_row(JOB, "failed", "rtm: bad", 2, None, host="h")["commit"] is None


def test_a_failed_row_has_no_metrics():
    row = run.build_row(JOB, "failed", "rtm: bad", 2, None, host="h")
    assert row["scene"] == "balls-1" and row["error"] == "rtm: bad" and row["exit_code"] == 2
    assert all(row.get(key) is None for key in columns.SUMMARY_COLUMNS)
    assert row["search_units"] is None  # neither the job nor statistics say


def test_the_outcome_of_a_run(tmp_path):
    stats = tmp_path / "s.json"
    assert run.outcome(1, True, 5, "x", stats) == ("timeout", "timed out after 5 s", None)
    assert run.outcome(3, False, None, "rtm: deadlock", stats) == ("deadlock", "rtm: deadlock", None)
    assert run.outcome(2, False, None, "rtm: no", stats) == ("failed", "rtm: no", None)
    assert run.outcome(-11, False, None, "", stats) == ("failed", "rtm crashed (SIGSEGV)", None)
    assert run.outcome(-6, False, None, "boom", stats) == ("failed", "rtm crashed (SIGABRT): boom", None)
    status, message, _ = run.outcome(0, False, None, "", stats)
    assert status == "failed" and message.startswith("no readable statistics")
    stats.write_text(json.dumps({"cycles": 5}))
    status, message, got = run.outcome(0, False, None, "", stats)
    assert status == "failed" and "no summary" in message and got == {"cycles": 5}
    stats.write_text(json.dumps({"summary": {"cycles": 5}}))
    assert run.outcome(0, False, None, "ignored", stats) == ("ok", "", {"summary": {"cycles": 5}})


def stand_in_rtm(tmp_path):
    """An executable taking rtm render's command line: it notes each start in CALLS, waits for
    the file GO, then writes an image and statistics with a summary. Returns (it, CALLS, GO)."""
    calls, go = tmp_path / "calls", tmp_path / "go"
    exe = tmp_path / "rtm"
    exe.write_text(f"""#!{sys.executable}
import json, os, sys, time
a = sys.argv
with open({str(calls)!r}, "a") as f:
    f.write(f"{{os.getpid()}}\\n")
while not os.path.exists({str(go)!r}):
    time.sleep(0.01)
open(a[a.index("--out") + 1], "wb").write(b"png")
with open(a[a.index("--stats") + 1], "w") as f:
    json.dump({{"summary": {{"cycles": 123}}}}, f)
""")
    exe.chmod(0o755)
    return exe, calls, go


def wait_for(condition, what, seconds=30):
    deadline = time.monotonic() + seconds
    while not condition():
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        time.sleep(0.01)


@pytest.mark.parametrize("mode", [[], ["--no-append"]], ids=["shared", "no-append"])
def test_a_second_attempt_at_a_run_waits_for_the_first_and_takes_its_row(tmp_path, mode):
    """A sweep killed and resumed at once can start a run whose first attempt still goes on (over
    SSH: GNU parallel does not stop it). Sharing the run's files, the second deleted the first's
    statistics (a finished-looking failed row, "no readable statistics", that the resume kept)
    or its output (a crash, no row). Now it waits, then takes the first's row; one stopped while
    it waits leaves nothing."""
    exe, calls, go = stand_in_rtm(tmp_path)
    out = tmp_path / "out"
    job = {"id": "r1", "scene": str(tmp_path / "s.nff"), "images": True, "set_keys": []}
    cmd = [SWEEP_RUN, "--dir", str(out), "--rtm", str(exe)] + mode + ["r1", job["scene"], json.dumps(job)]
    runs = out / "runs" / ("r1.remote" if mode else "")
    started = []

    def attempt(name):
        logs = [open(tmp_path / f"{name}.{ext}", "w") for ext in ("out", "err")]
        p = subprocess.Popen(cmd, stdout=logs[0], stderr=logs[1], stdin=subprocess.DEVNULL, env=env())
        for f in logs:
            f.close()
        started.append(p)
        return p

    def calls_made():
        return len(calls.read_text().split()) if calls.exists() else 0

    try:
        first = attempt("first")
        wait_for(lambda: calls_made() == 1, "the first attempt's rtm")
        for name in ("stopped", "second"):
            p = attempt(name)
            wait_for(lambda: "waiting for it" in (tmp_path / f"{name}.err").read_text() or p.poll() is not None
                     or calls_made() > 1, f"the {name} attempt to wait")
            assert calls_made() == 1, f"the {name} attempt started rtm again beside the first"
            assert (runs / "r1.err").exists(), f"the {name} attempt removed the first one's files"
            if name == "stopped":
                p.send_signal(signal.SIGTERM)
                assert p.wait(timeout=30) == 128 + signal.SIGTERM
        second = p
        go.write_text("")
        assert first.wait(timeout=30) == 0, (tmp_path / "first.err").read_text()
        assert second.wait(timeout=30) == 0, (tmp_path / "second.err").read_text()
    finally:
        for p in started:
            if p.poll() is None:
                p.kill()
                p.wait()
    assert calls_made() == 1
    assert (tmp_path / "second.out").read_text() == "skip r1 (already has its row)\n"
    _, rows = read_csv(runs / "r1.row")
    assert [(r["status"], r["cycles"]) for r in rows] == [("ok", "123")]
    assert not (out / "runs" / ("r1" + run.LOCK_SUFFIX)).exists()
