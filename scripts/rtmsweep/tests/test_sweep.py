"""Whole sweeps, run as a user would: scripts/sweep (GNU parallel, one rtm per configuration),
then the CSV, the per-run files, resuming after a kill, failed runs, variants and the plots."""

import json
import os
import re
import signal
import subprocess
import time

import pytest

from support import PLOTS, ROOT, SCENES, SCRIPTS, SWEEP, check_png, env, is_number, read_csv, row_files, write_spec
from rtmsweep import columns

COLUMNS = columns.header([])
TINY = os.path.join(SCRIPTS, "sweep-examples", "tiny.yaml")


def spec_order(rows):
    return [r["run_id"] for r in rows]


def test_the_stats_summary_holds_exactly_the_metric_columns(rtm, tmp_path):
    r = subprocess.run([rtm, "render", os.path.join(SCENES, "balls-1.nff"), "--size", "16x16", "-q",
                        "--out", tmp_path / "x.png"], capture_output=True, text=True, env=env())
    assert r.returncode == 0, r.stderr
    summary = json.loads((tmp_path / "x.json").read_text())["summary"]
    assert sorted(summary) == sorted(columns.SUMMARY_COLUMNS)
    assert sorted(columns.METRIC_COLUMNS) == sorted(columns.SUMMARY_COLUMNS + ["exit_code", "host", "scene_file", "commit"])


def test_the_stats_schema_documents_exactly_the_summary_columns():
    """docs/stats.schema.json describes the summary key by key: the same keys, every one required."""
    with open(os.path.join(ROOT, "docs", "stats.schema.json")) as f:
        summary = json.load(f)["$defs"]["summary"]
    assert sorted(summary["properties"]) == sorted(columns.SUMMARY_COLUMNS)
    assert sorted(summary["required"]) == sorted(columns.SUMMARY_COLUMNS)


def test_the_tiny_example_gives_one_ok_row_per_configuration(sweep, tmp_path):
    out = tmp_path / "tiny"
    r = sweep(TINY, out, "--jobs", "2")
    assert r.returncode == 0, r.stdout + r.stderr
    assert "[6/6] " in r.stdout
    assert "6 rows: 6 ok" in r.stdout
    assert f"{out}/results.csv" in r.stdout

    head, rows = read_csv(out / "results.csv")
    assert head == COLUMNS
    assert len(rows) == 6
    # The spec's order: scene by scene, the PE count fastest.
    assert [(r["scene"], r["pes"]) for r in rows] == [
        ("balls-1", "1"), ("balls-1", "2"), ("balls-1", "4"), ("rings-1", "1"), ("rings-1", "2"), ("rings-1", "4")]
    assert row_files(out) == sorted(r["run_id"] + ".row" for r in rows)
    for row in rows:
        rid = row["run_id"]
        assert row["status"] == "ok", f"{rid}: {row['error']}"
        assert row["error"] == "" and row["exit_code"] == "0"
        assert (row["width"], row["height"], row["partition"]) == ("32", "32", "scanlines")
        assert row["rays_primary"] == "1024"
        for c in ("cycles", "wall_seconds", "error_rmse", "util_mac", "load_imbalance", "host_preprocess_cycles",
                  "transfer_cycles", "pe_cycles", "gather_cycles", "link_busy_cycles"):
            assert is_number(row[c]), f"{c} = {row[c]!r}"
        # The phases add up to the frame.
        assert sum(int(row[c]) for c in ("host_preprocess_cycles", "transfer_cycles", "pe_cycles",
                                          "gather_cycles")) == int(row["cycles"])
        # The row is the run's own summary, kept in runs/ beside its row file, stderr and image.
        stats = json.loads((out / "runs" / f"{rid}.json").read_text())
        assert stats["summary"]["cycles"] == int(row["cycles"]) and stats["pes"] == int(row["pes"])
        assert row["commit"] == stats["build"]["commit"] + ("-modified" if stats["build"]["modified"] else "")
        assert read_csv(out / "runs" / f"{rid}.row") == (head, [row])
        assert (out / "runs" / f"{rid}.err").exists() and (out / "runs" / f"{rid}.png").exists()
    # More PEs, fewer cycles of PE work on these scenes (the frame's cycles need not fall: on
    # balls-1 at 32x32 the serial link's scene copy to a fourth PE costs more than its work saves).
    for scene in ("balls-1", "rings-1"):
        cycles = [int(r["pe_cycles"]) for r in rows if r["scene"] == scene]
        assert cycles[0] > cycles[1] > cycles[2], scene
    for p in PLOTS:
        check_png(out / "plots" / p)
    assert (out / "plots" / "scaling.md").exists()
    assert sorted(os.listdir(out)) == ["joblog", "jobs.tsv", "plots", "results.csv", "runs", "spec.yaml"]

    # Running it again finds everything done and runs nothing.
    again = sweep(TINY, out, "--jobs", "2", "--no-plots")
    assert again.returncode == 0, again.stderr
    assert "6 already done" in again.stdout
    assert "[1/6]" not in again.stdout
    assert read_csv(out / "results.csv") == (head, rows)


def session_alive(sid):
    """Processes of a session that are still alive (zombies don't count)."""
    pids = []
    for name in os.listdir("/proc"):
        if not name.isdigit():
            continue
        try:
            with open(f"/proc/{name}/stat") as f:
                stat = f.read()
        except OSError:
            continue
        fields = stat[stat.rfind(")") + 2:].split()
        if int(fields[3]) == sid and fields[0] not in "ZX":
            pids.append(int(name))
    return pids


def test_a_killed_sweep_resumes_without_repeating_or_dropping_runs(sweep, rtm, tmp_path):
    spec = write_spec(tmp_path / "spec.yaml", "name: resume\nscenes: [balls-1.nff, rings-1.nff]\n"
                                              "sizes: [16x16]\npes: [1, 2, 3, 4]\n")
    out = tmp_path / "out"
    with open(tmp_path / "first.log", "w") as log:
        # A session of its own, so that its process group is the sweep's pid.
        first = subprocess.Popen([SWEEP, spec, "--out", out, "--rtm", rtm, "--jobs", "1", "--no-plots"],
                                 stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, env=env(),
                                 start_new_session=True)
    deadline = time.monotonic() + 60
    while len(row_files(out)) < 2 and time.monotonic() < deadline and first.poll() is None:
        time.sleep(0.01)
    os.killpg(first.pid, signal.SIGKILL)
    first.wait()
    # GNU parallel gives each job its own process group; the jobs notice their parent died and stop.
    gone_by = time.monotonic() + 15
    while session_alive(first.pid) and time.monotonic() < gone_by:
        time.sleep(0.05)
    assert not session_alive(first.pid), "processes left running after the kill"

    done = row_files(out)
    assert len(done) >= 2, (tmp_path / "first.log").read_text()
    assert len(done) < 8, "the sweep finished before it could be interrupted"
    finished = {n[:-4]: os.stat(out / "runs" / (n[:-4] + ".json")).st_mtime_ns for n in done}

    status = sweep(spec, out, "--status")
    assert status.returncode == 1
    assert f"{8 - len(done)} missing" in status.stdout and "run the same command again" in status.stdout
    assert len(read_csv(out / "results.csv")[1]) == len(done)  # brought up to date with the row files

    resumed = sweep(spec, out, "--jobs", "1", "--no-plots")
    assert resumed.returncode == 0, resumed.stdout + resumed.stderr
    assert f"{len(done)} already done" in resumed.stdout
    assert "8 rows: 8 ok, 0 missing" in resumed.stdout

    head, rows = read_csv(out / "results.csv")
    assert head == COLUMNS
    assert len(rows) == 8 and len({r["run_id"] for r in rows}) == 8
    assert {(r["scene"], r["pes"]) for r in rows} == {(s, p) for s in ("balls-1", "rings-1") for p in "1234"}
    assert all(r["status"] == "ok" and is_number(r["cycles"]) for r in rows)
    for rid, when in finished.items():
        assert os.stat(out / "runs" / f"{rid}.json").st_mtime_ns == when, f"{rid} was run again"
    assert sweep(spec, out, "--status").returncode == 0


FAILING = """name: failing
scenes: [balls-1.nff, no-such-scene.nff]
sizes: [16x16]
set:
  search_fifo_depth: [1]
  intersect_fifo_depth: [1]
  feedback_fifo_depth: [1]
  shade_fifo_depth: [1]
  root_fifo_depth: [1]
  flow_control: [credits, none]
  loop_credits: [0, 999]
"""


def test_failed_runs_are_recorded_with_their_error_message(sweep, tmp_path):
    spec = write_spec(tmp_path / "spec.yaml", FAILING)
    out = tmp_path / "out"
    r = sweep(spec, out, "--jobs", "2", "--no-plots")
    assert r.returncode == 0, r.stdout + r.stderr  # every run has its row
    assert "8 rows: 1 ok, 1 deadlock, 6 failed, 0 missing" in r.stdout
    assert "no-such-scene.nff" in r.stderr  # warned up front

    head, rows = read_csv(out / "results.csv")
    set_keys = ["search_fifo_depth", "intersect_fifo_depth", "feedback_fifo_depth", "shade_fifo_depth",
                "root_fifo_depth", "flow_control", "loop_credits"]
    assert head == columns.header(set_keys)
    assert len(rows) == 8
    assert len(row_files(out)) == 8  # failed runs keep their rows
    kinds = {"ok": 0, "deadlock": 0, "rejected": 0, "missing": 0}
    for row in rows:
        status, error = row["status"], row["error"]
        where = f"{row['run_id']} {row['flow_control']} {row['loop_credits']}: {error}"
        assert row["search_fifo_depth"] == "1"
        if status != "ok":
            assert row["cycles"] == "", where
            assert not (out / "runs" / f"{row['run_id']}.json").exists(), where
            # The message is rtm's own, also in the run's stderr.
            assert error in (out / "runs" / f"{row['run_id']}.err").read_text(), where
        if row["scene"] == "no-such-scene":
            kinds["missing"] += 1
            assert (status, row["exit_code"]) == ("failed", "1"), where
            assert "cannot read scene file" in error, where
        elif row["loop_credits"] == "999":
            kinds["rejected"] += 1
            assert (status, row["exit_code"]) == ("failed", "2"), where
            assert "loop_credits" in error, where
        elif row["flow_control"] == "none":
            kinds["deadlock"] += 1
            assert (status, row["exit_code"]) == ("deadlock", "3"), where
            assert "deadlock" in error, where
        else:
            kinds["ok"] += 1
            assert status == "ok" and is_number(row["cycles"]), where
    assert kinds == {"ok": 1, "deadlock": 1, "rejected": 2, "missing": 4}

    # Rerunning doesn't retry them (they are results); --retry-failed does, and they fail the same way.
    again = sweep(spec, out, "--jobs", "2", "--no-plots")
    assert again.returncode == 0
    assert "[1/8]" not in again.stdout
    retry = sweep(spec, out, "--jobs", "2", "--no-plots", "--retry-failed")
    assert retry.returncode == 0, retry.stderr
    assert "retrying 7 run(s)" in retry.stdout and "1 already done" in retry.stdout and "[8/8]" in retry.stdout
    assert "1 run(s) already had their row; not run again" in retry.stdout  # the ok one
    assert "8 rows: 1 ok, 1 deadlock, 6 failed, 0 missing" in retry.stdout
    assert [r["run_id"] for r in read_csv(out / "results.csv")[1]] == [r["run_id"] for r in rows]


def test_variants_are_whole_machines_compared_side_by_side(sweep, tmp_path):
    out = tmp_path / "out"
    spec = write_spec(tmp_path / "spec.yaml", "name: variants\nscenes: [balls-1.nff]\nsizes: [16x16]\n"
                      "pes: [1, 2]\nset:\n  search_units: [2]\nvariants:\n  paper: {}\n"
                      "  improved: {ray_generation: pe, broadcast: true, gather: as_finished}\n")
    r = sweep(spec, out, "--jobs", "2", "--no-plots")
    assert r.returncode == 2, "search_units is an axis, not a set key: " + r.stdout + r.stderr
    spec = write_spec(tmp_path / "spec.yaml", "name: variants\nscenes: [balls-1.nff]\nsizes: [16x16]\n"
                      "pes: [1, 2]\nset:\n  loop_credits: [0]\nvariants:\n  paper: {}\n"
                      "  improved: {ray_generation: pe, broadcast: true, gather: as_finished, partition: pixels}\n")
    r = sweep(spec, out, "--jobs", "2", "--no-plots")
    assert r.returncode == 0, r.stdout + r.stderr
    head, rows = read_csv(out / "results.csv")
    assert head == columns.header(["variant", "loop_credits"])
    assert [(r["variant"], r["pes"]) for r in rows] == [("paper", "1"), ("paper", "2"), ("improved", "1"),
                                                        ("improved", "2")]
    for row in rows:
        assert row["status"] == "ok", row["error"]
        config = json.loads((out / "runs" / f"{row['run_id']}.json").read_text())["config"]
        improved = row["variant"] == "improved"
        assert config["ray_generation"] == ("pe" if improved else "host"), row["run_id"]
        assert config["gather"] == ("as_finished" if improved else "after_all"), row["run_id"]
        # A variant may fix a top-level axis: its runs use its value instead of the axis's.
        assert row["partition"] == ("pixels" if improved else "scanlines"), row["run_id"]


def test_a_variant_can_start_from_a_preset(sweep, tmp_path):
    out = tmp_path / "out"
    spec = write_spec(tmp_path / "spec.yaml", "name: presets\nscenes: [balls-1.nff]\nsizes: [16x16]\npes: [1]\n"
                      "variants:\n  paper: {preset: paper}\n  improved: {broadcast: true}\n")
    r = sweep(spec, out, "--jobs", "2", "--no-plots")
    assert r.returncode == 0, r.stdout + r.stderr
    head, rows = read_csv(out / "results.csv")
    assert head == columns.header(["variant", "preset"])
    assert [(r["variant"], r["preset"]) for r in rows] == [("paper", "paper"), ("improved", "default")]
    for row in rows:
        assert row["status"] == "ok", row["error"]
        stats = json.loads((out / "runs" / f"{row['run_id']}.json").read_text())
        assert stats["preset"] == row["preset"]
        assert stats["config"]["mac_schedule"] == ("full" if row["variant"] == "paper" else "sparse")
    # A preset rtm does not know stops the sweep before any run.
    bad = write_spec(tmp_path / "bad.yaml", "scenes: [balls-1.nff]\nsizes: [16x16]\npreset: papr\n")
    r = sweep(bad, tmp_path / "bad-out")
    assert r.returncode == 2
    assert "preset papr: rtm: --preset: preset: expected one of default, paper, got 'papr'" in r.stderr, r.stderr
    assert not (tmp_path / "bad-out").exists()


def test_a_bad_spec_is_rejected_up_front(sweep, tmp_path):
    out = tmp_path / "out"
    for text, message in [("scenes: [balls-1.nff]\npe: [1, 2]\n", "unknown key(s) pe"),
                          ("scenes: [balls-1.nff]\nset: {search_fifo_dept: [4]}\n",
                           "search_fifo_dept: unknown machine configuration key"),
                          ("scenes: [balls-1.nff]\nsizes: [32by32]\n", "not WxH")]:
        r = sweep(write_spec(tmp_path / "bad.yaml", text), out)
        assert r.returncode == 2, text
        assert message in r.stderr, r.stderr
    assert not out.exists()
    # --dry-run lists the rtm command of every run and runs none.
    spec = write_spec(tmp_path / "dry.yaml", "scenes: [balls-1.nff]\nsizes: [16x16]\npes: [1, 8]\n"
                                             "set: {search_fifo_depth: [4, 8]}\n")
    r = sweep(spec, out, "--dry-run")
    assert r.returncode == 0, r.stderr
    assert "4 runs" in r.stdout
    assert "--pes 8 --set search_fifo_depth=4" in r.stdout
    assert "parallel: " in r.stdout and "--joblog" in r.stdout
    assert not out.exists()
    r = sweep(spec, out, "--status")
    assert r.returncode == 1 and "nothing run yet" in r.stdout
    assert not out.exists()


def test_check_and_dry_run_name_every_missing_file_and_exit_2(sweep, tmp_path):
    spec = write_spec(tmp_path / "spec.yaml", "scenes: [balls-1.nff, no-such-scene.nff, rings-1.nff, gone.nff]\n"
                                              "sizes: [8x8]\nconfig: no-such-config.yaml\n")
    out = tmp_path / "out"
    for option in ("--check", "--dry-run"):
        r = sweep(spec, out, option)
        assert r.returncode == 2, r.stdout + r.stderr
        assert r.stderr.splitlines() == [f"sweep: {spec}: no scene file {SCENES}/no-such-scene.nff",
                                         f"sweep: {spec}: no scene file {SCENES}/gone.nff",
                                         # in the folder the sweep is run from: named from there
                                         f"sweep: {spec}: no config file no-such-config.yaml"], r.stderr
        assert not out.exists()
    r = sweep(write_spec(tmp_path / "good.yaml", "scenes: [balls-1.nff, rings-1.nff]\npes: [1, 2]\n"), out, "--check")
    assert r.returncode == 0, r.stdout + r.stderr
    assert r.stdout == "sweep good: 4 runs, every file the spec names is here\n"
    assert not out.exists()
    # With an rtm to ask, --check refuses what rtm does not know, as a run would.
    r = sweep(write_spec(tmp_path / "bad-key.yaml", "scenes: [balls-1.nff]\nset: {no_such_key: [1]}\n"), out, "--check")
    assert r.returncode == 2 and "no_such_key: unknown machine configuration key" in r.stderr, r.stderr


def test_check_needs_no_rtm(tmp_path):
    spec = write_spec(tmp_path / "spec.yaml", "scenes: [balls-1.nff]\nset: {any_key: [1]}\n")
    environment = {k: v for k, v in env().items() if k != "RTM_BINARY"}
    environment["RTM_BUILD_DIR"] = str(tmp_path / "no-build")
    r = subprocess.run([SWEEP, spec, "--check"], capture_output=True, text=True, stdin=subprocess.DEVNULL,
                       cwd=tmp_path, env=environment, timeout=60)
    assert r.returncode == 0, r.stdout + r.stderr
    assert r.stdout == ("sweep spec: 1 run, every file the spec names is here "
                        "(keys and presets not checked: no rtm executable)\n")


def test_shards_fill_one_results_csv_in_the_specs_order(sweep, tmp_path):
    spec = write_spec(tmp_path / "spec.yaml", "name: shards\nscenes: [balls-1.nff]\nsizes: [8x8]\npes: [1, 2, 3]\n")
    out = tmp_path / "out"
    listed = sweep(spec, out, "--dry-run").stdout.splitlines()[1:-1]
    order = [line.split(":", 1)[0] for line in listed]
    r = sweep(spec, out, "--shard", "1/2", "--jobs", "1", "--no-plots")
    assert r.returncode == 0, r.stdout + r.stderr
    assert "shard 1/2" in r.stdout and "1 rows: 1 ok, 0 missing" in r.stdout
    assert spec_order(read_csv(out / "results.csv")[1]) == [order[1]]
    r = sweep(spec, out, "--shard", "0/2", "--jobs", "1", "--no-plots")
    assert r.returncode == 0, r.stdout + r.stderr
    assert "2 rows: 2 ok, 0 missing" in r.stdout
    assert spec_order(read_csv(out / "results.csv")[1]) == order
    assert {"jobs-shard-0-of-2.tsv", "jobs-shard-1-of-2.tsv", "joblog-shard-0-of-2",
            "joblog-shard-1-of-2"} <= set(os.listdir(out))
    assert sweep(spec, out, "--status").returncode == 0


def test_rows_come_back_from_hosts_without_the_shared_folder(sweep, tmp_path):
    """--no-shared-dir: each run writes to runs/ID.remote/, which GNU parallel brings back (here
    from this machine, ':'); the sweep moves the files into runs/ and the rows into results.csv."""
    spec = write_spec(tmp_path / "spec.yaml", "name: remote\nscenes: [balls-1.nff]\nsizes: [8x8]\npes: [1, 2]\n")
    (tmp_path / "hosts").write_text(":\n")
    out = tmp_path / "out"
    r = sweep(spec, out, "--sshloginfile", tmp_path / "hosts", "--no-shared-dir", "--jobs", "2", "--no-plots")
    assert r.returncode == 0, r.stdout + r.stderr
    assert "2 rows: 2 ok, 0 missing" in r.stdout
    assert "--no-append" in sweep(spec, out, "--sshloginfile", tmp_path / "hosts", "--no-shared-dir",
                                  "--dry-run").stdout
    head, rows = read_csv(out / "results.csv")
    assert len(rows) == 2 and all(r["status"] == "ok" for r in rows)
    names = os.listdir(out / "runs")
    assert not [n for n in names if n.endswith(".remote")]
    for row in rows:
        assert {f"{row['run_id']}{ext}" for ext in (".row", ".json", ".err", ".png")} <= set(names)


@pytest.mark.parametrize("args, message", [
    (["--shard", "2/2"], "--shard 2/2: expected I/N"),
    (["--no-shared-dir"], "--no-shared-dir only makes sense with --sshloginfile"),
    (["--sshloginfile", "/no/such/hosts"], "no such file"),
])
def test_bad_options_are_usage_errors(sweep, tmp_path, args, message):
    spec = write_spec(tmp_path / "spec.yaml", "scenes: [balls-1.nff]\n")
    r = sweep(spec, tmp_path / "out", *args)
    assert r.returncode == 2 and message in r.stderr, r.stderr


def test_page_writes_the_study_page_with_the_scaling_table_and_the_build(sweep, rtm, tmp_path):
    page = tmp_path / "tiny.md"
    page.write_text("# Tiny\n\nThe question.\n\n<!-- begin: written by scripts/plot-sweep tiny, do not edit -->\n"
                    "<!-- end: written by scripts/plot-sweep tiny -->\n\nThe findings.\n")
    r = sweep(TINY, tmp_path / "tiny", "--jobs", "2", "--page", str(page))
    assert r.returncode == 0, r.stdout + r.stderr
    text = page.read_text()
    version = subprocess.run([rtm, "--version"], capture_output=True, text=True).stdout.strip().splitlines()[0]
    assert f"- build: `{version}" in text
    assert "- runs: 6, " in text and "min of run time in all" in text
    assert "| balls-1 | 1 | " in text and "| rings-1 | 4 | " in text  # the scaling table, one row per run
    assert "| configuration | PEs | area, mm² | energy per frame, µJ |" in text  # and the cost table
    assert text.count("| balls-1 | 1 | ") == 2
    # Each cost row ends in leakage's share and the dynamic part that takes most of the rest.
    cost_rows = [line for line in text.splitlines() if line.startswith("| balls-1 | 1 | ")][1:]
    assert re.search(r"\| \d+ % \| [a-zA-Z() ]+ \d+ % \|$", cost_rows[0]), cost_rows
    assert text.startswith("# Tiny\n\nThe question.\n") and text.endswith("\n\nThe findings.\n")
