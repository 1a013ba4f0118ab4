"""A whole sweep (scripts/sweep): the spec's jobs, run by GNU parallel through scripts/sweep-run
(local cores or several hosts), one row file per run, results.csv assembled from them;
resumable. docs/sweeps.md describes the spec, the CSV and the options.
"""

import argparse
import json
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import time

import yaml

from . import columns, results, run, spec

SCRIPTS = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ROOT = os.path.dirname(SCRIPTS)
SWEEP_RUN = os.path.join(SCRIPTS, "sweep-run")
PLOT_SWEEP = os.path.join(SCRIPTS, "plot-sweep")
# The words sweep-run starts its one line of output with.
FINISHED = ("ok", "failed", "deadlock", "timeout")
SKIPPED = "skip"


def die(message, code=2):
    print(f"sweep: {message}", file=sys.stderr)
    sys.exit(code)


def find_rtm(explicit, required=True):
    """The rtm executable: EXPLICIT, else $RTM_BINARY, else the build's; None when there is
    none and it is not REQUIRED."""
    candidates = [explicit] if explicit else []
    if not explicit:
        if os.environ.get("RTM_BINARY"):
            candidates.append(os.environ["RTM_BINARY"])
        candidates.append(os.path.join(ROOT, os.environ.get("RTM_BUILD_DIR", "build"), "rtm"))
    for c in candidates:
        c = os.path.abspath(c)
        if os.path.isfile(c) and os.access(c, os.X_OK):
            return c
    if not required:
        return None
    die(f"no rtm executable at {', '.join(candidates)}; build it (scripts/setup) or pass --rtm PATH")


def config_keys(rtm):
    """The machine-configuration keys `rtm config` lists (None if it can't be run)."""
    try:
        out = subprocess.run([rtm, "config"], capture_output=True, text=True, timeout=60,
                             env=dict(os.environ, SYSTEMC_DISABLE_COPYRIGHT_MESSAGE="1")).stdout
        keys = yaml.safe_load(out)  # rtm config prints a loadable YAML file
    except (OSError, subprocess.SubprocessError, yaml.YAMLError):
        return None
    return set(keys) if isinstance(keys, dict) and keys else None


def preset_error(rtm, name):
    """rtm's message if it does not know preset NAME, else None (also when rtm can't be run: its
    runs will say)."""
    try:
        p = subprocess.run([rtm, "config", "--preset", name], capture_output=True, text=True, timeout=60,
                           env=dict(os.environ, SYSTEMC_DISABLE_COPYRIGHT_MESSAGE="1"))
    except (OSError, subprocess.SubprocessError):
        return None
    return (p.stderr.strip() or f"rtm config exited {p.returncode}") if p.returncode else None


def missing_files(spec_path, the_spec):
    """One line per file the spec names that is not here: its scenes and its config file."""
    files = the_spec.scenes + ([the_spec.config] if the_spec.config else [])
    return [f"{spec_path}: no {'config' if f == the_spec.config else 'scene'} file {shown(f)}"
            for f in dict.fromkeys(files) if not os.path.isfile(f)]


def shown(path):
    """PATH relative to the current folder when it is inside it, else as it is."""
    rel = os.path.relpath(path)
    return path if rel == os.pardir or rel.startswith(os.pardir + os.sep) else rel


def jobs_tsv(jobs):
    """GNU parallel's input: one line per job, RUN_ID, SCENE and the job's JSON."""
    return "".join(f"{j['id']}\t{j['scene']}\t{json.dumps(j, sort_keys=True)}\n" for j in jobs)


def rotate(path):
    """Moves PATH aside to PATH.1, PATH.2, ... (the first free one)."""
    if not os.path.exists(path):
        return None
    n = 1
    while os.path.exists(f"{path}.{n}"):
        n += 1
    os.rename(path, f"{path}.{n}")
    return f"{path}.{n}"


def fmt_duration(seconds):
    seconds = int(round(seconds))
    if seconds < 60:
        return f"{seconds}s"
    if seconds < 3600:
        return f"{seconds // 60}m{seconds % 60:02d}s"
    return f"{seconds // 3600}h{seconds % 3600 // 60:02d}m"


def my_rows(out, jobs, head):
    """The rows of these jobs that have their row file, by run id."""
    ids = {j["id"] for j in jobs}
    return {rid: row for rid, (h, row) in results.read_rows(out).items() if rid in ids and h == head}


def report(name, out, rows, jobs, plots_dir):
    """Prints how far the sweep is; returns how many of its runs have no row."""
    ids = {j["id"] for j in jobs}
    mine = [rows[j["id"]] for j in jobs if j["id"] in rows]
    by_status = {}
    for r in mine:
        by_status.setdefault(r.get("status", ""), []).append(r)
    missing = len(ids) - len(mine)
    parts = [f"{len(by_status.get('ok', []))} ok"]
    for status in sorted(by_status):
        if status != "ok":
            parts.append(f"{len(by_status[status])} {status}")
    parts.append(f"{missing} missing")
    print(f"sweep {name}: {len(ids)} runs, {len(mine)} rows: {', '.join(parts)}")
    bad = [r for r in mine if r.get("status") != "ok"]
    for r in bad[:8]:
        print(f"  {r['status']}: {r['run_id']}: {r.get('error', '')}")
    if len(bad) > 8:
        print(f"  ... {len(bad) - 8} more (status column of the CSV)")
    print(f"  results: {results.results_path(out)}")
    print(f"  runs:    {results.runs_dir(out)}/ (statistics JSON, stderr, images)")
    if plots_dir:
        print(f"  plots:   {plots_dir}/")
    if missing:
        print(f"  {missing} run(s) have no row yet: run the same command again to resume")
    return missing


def assemble(out, head, order):
    """results.csv from the row files (results.assemble), warning about rows of other columns."""
    rows, other = results.assemble(out, head, order)
    if other:
        print(f"sweep: {other} row file(s) in {results.runs_dir(out)}/ have other columns than this spec "
              f"gives (another spec's `set` keys?); left out of results.csv", file=sys.stderr)
    return rows


def parse_args(argv):
    ap = argparse.ArgumentParser(
        prog="scripts/sweep",
        description="Runs the cartesian product of a sweep spec (docs/sweeps.md), one rtm render per "
                    "configuration, with GNU parallel; one row per run in DIR/results.csv. "
                    "Rerunning the same command resumes an interrupted sweep.")
    ap.add_argument("spec", help="the sweep spec (YAML); relative paths in it are relative to its folder")
    ap.add_argument("--out", metavar="DIR", help="output folder (default out/sweeps/NAME)")
    ap.add_argument("--jobs", "-j", metavar="N",
                    help="runs at once (GNU parallel -j: N, N%%, +N; default all local cores, or "
                         "what --sshloginfile says per host)")
    ap.add_argument("--sshloginfile", metavar="FILE",
                    help="GNU parallel --sshloginfile: the hosts to run on (':' is this machine)")
    ap.add_argument("--no-shared-dir", action="store_true",
                    help="the remote hosts don't see DIR: copy each scene there (--transferfile) and "
                         "bring each run's files back (--return); the rows are collected here")
    ap.add_argument("--shard", metavar="I/N",
                    help="run only every N-th configuration starting at I (0-based), e.g. a Slurm "
                         "array task: --shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT")
    ap.add_argument("--rtm", metavar="PATH",
                    help="the rtm executable (default $RTM_BINARY, else ${RTM_BUILD_DIR:-build}/rtm)")
    ap.add_argument("--retry-failed", action="store_true",
                    help="drop the rows of failed, deadlocked and timed-out runs and run them again")
    ap.add_argument("--no-plots", action="store_true", help="don't run scripts/plot-sweep at the end")
    ap.add_argument("--page", metavar="PAGE",
                    help="the study page (docs/studies/*.md) whose generated part scripts/plot-sweep rewrites "
                         "with the scaling table, stamped with the rtm's --version")
    ap.add_argument("--status", action="store_true",
                    help="only print how far the sweep in DIR is, after bringing results.csv up to date with the "
                         "runs' row files (exit 0 when every run has its row)")
    ap.add_argument("--dry-run", action="store_true",
                    help="print the runs (rtm command lines) and the GNU parallel command; run nothing "
                         "(exit 2 when a scene file is missing)")
    ap.add_argument("--check", action="store_true",
                    help="only check the spec and that every scene file it names is here (exit 0, or 2 with "
                         "one line per problem); needs no rtm, but checks the keys and presets with one if "
                         "there is one")
    return ap.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)  # `scripts/sweep ... | head` ends quietly

    shard = None
    if args.shard:
        m = re.fullmatch(r"(\d+)/(\d+)", args.shard)
        if not m or int(m.group(2)) < 1 or int(m.group(1)) >= int(m.group(2)):
            die(f"--shard {args.shard}: expected I/N with 0 <= I < N")
        shard = (int(m.group(1)), int(m.group(2)))
    if args.sshloginfile and not os.path.isfile(args.sshloginfile):
        die(f"--sshloginfile {args.sshloginfile}: no such file")
    if args.no_shared_dir and not args.sshloginfile:
        die("--no-shared-dir only makes sense with --sshloginfile")
    parallel = shutil.which("parallel")
    if not parallel and not (args.status or args.check):
        die("GNU parallel is not installed (Debian: apt-get install parallel)", 1)

    rtm = find_rtm(args.rtm, required=not args.check)
    try:
        the_spec = spec.load(args.spec, config_keys(rtm) if rtm else None)
    except spec.SpecError as e:
        die(f"{args.spec}: {e}")
    for preset in the_spec.presets if rtm else []:
        error = preset_error(rtm, preset)
        if error:
            die(f"{args.spec}: preset {preset}: {error}")
    all_jobs = the_spec.jobs()
    order = [j["id"] for j in all_jobs]  # results.csv's order: every shard's runs, as the spec lists them
    jobs = all_jobs
    name = the_spec.name
    if shard:
        jobs = all_jobs[shard[0]::shard[1]]
        name += f" (shard {shard[0]}/{shard[1]})"
    missing = missing_files(args.spec, the_spec)
    if missing and (args.check or args.dry_run):
        for line in missing:
            print(f"sweep: {line}", file=sys.stderr)
        return 2
    for line in missing:
        print(f"sweep: warning: {line} (its runs will fail unless the hosts have it)", file=sys.stderr)
    if args.check:
        print(f"sweep {name}: {len(jobs)} run{'' if len(jobs) == 1 else 's'}, every file the spec names is here"
              + ("" if rtm else " (keys and presets not checked: no rtm executable)"))
        return 0

    out = os.path.abspath(args.out or os.path.join("out", "sweeps", the_spec.name))
    csv_path = results.results_path(out)
    runs = results.runs_dir(out)
    tag = f"-shard-{shard[0]}-of-{shard[1]}" if shard else ""
    jobs_path = os.path.join(out, f"jobs{tag}.tsv")
    joblog = os.path.join(out, f"joblog{tag}")
    head = columns.header(the_spec.set_keys)

    command = [SWEEP_RUN, "--dir", out, "--rtm", rtm]
    popts = ["--colsep", r"\t", "--joblog", joblog, "--resume-failed", "--halt", "never"]
    if args.jobs:
        popts += ["--jobs", args.jobs]
    if args.sshloginfile:
        popts += ["--sshloginfile", os.path.abspath(args.sshloginfile)]
    if args.no_shared_dir:
        command.append("--no-append")
        popts += ["--transferfile", "{2}", "--return", os.path.join(runs, "{1}" + results.REMOTE_SUFFIX)]
    pcmd = [parallel or "parallel"] + popts + command + ["{1}", "{2}", "{3}", "::::", jobs_path]

    if args.dry_run:
        print(f"sweep {name}: {len(jobs)} runs -> {out}")
        for job in jobs:
            cmd = run.rtm_command(rtm, job, os.path.join(runs, job["id"] + ".png"),
                                  os.path.join(runs, job["id"] + ".json"))
            print(f"{job['id']}: {shlex.join(cmd)}")
        print(f"parallel: {shlex.join(pcmd)}")
        return 0

    existing, _ = results.read_csv(csv_path)
    if args.status:
        if not existing and not os.path.isdir(runs):
            print(f"sweep {name}: nothing run yet in {out}")
            return 1
        if args.no_shared_dir:
            results.collect_remote(out)
        if os.path.isdir(runs) and (not existing or existing == head) and not results.orphans(out):
            assemble(out, head, order)  # results.csv as the row files say (a shard may have been killed)
        return 1 if report(name, out, my_rows(out, jobs, head), jobs, None) else 0

    if existing and existing != head:
        die(f"{csv_path} has other columns than this spec gives (different `set` keys?); "
            f"use another --out, or move the old results away")
    os.makedirs(runs, exist_ok=True)
    with open(args.spec) as f:
        results.write_atomic(os.path.join(out, f"spec{tag}.yaml"), f.read())

    if args.no_shared_dir:
        results.collect_remote(out)
    lost = results.orphans(out)
    if lost:
        kept = rotate(csv_path)
        print(f"sweep: warning: {len(lost)} row(s) of results.csv have no row file in {runs}/ (e.g. {lost[0]}); "
              f"results.csv is rebuilt from the row files, the old one kept as {os.path.basename(kept)}",
              file=sys.stderr)
    if args.retry_failed:
        # This shard's runs only: other shards may be retrying theirs.
        failed = [rid for rid, row in my_rows(out, jobs, head).items() if row.get("status") != "ok"]
        for rid in failed:
            os.remove(results.row_path(out, rid))
        print(f"sweep: retrying {len(failed)} run(s) that did not succeed")
        rotate(joblog)  # the joblog says they're done; the ok runs' row files still skip the rest

    # --resume-failed matches the joblog to the input line by line: if the spec changed, start a
    # new joblog (runs that have their row file are still skipped, by sweep-run).
    text = jobs_tsv(jobs)
    try:
        with open(jobs_path) as f:
            old = f.read()
    except FileNotFoundError:
        old = None
    if old is not None and old != text:
        moved = rotate(joblog)
        if moved:
            print(f"sweep: the list of runs changed; old joblog kept as {os.path.basename(moved)}")
    results.write_atomic(jobs_path, text)

    rows = assemble(out, head, order)  # resuming: results.csv as the row files say
    total = len(jobs)
    done = sum(1 for j in jobs if j["id"] in rows)
    print(f"sweep {name}: {total} runs, {done} already done, results in {csv_path}", flush=True)

    started, finished_now, skipped = time.monotonic(), 0, 0
    proc = subprocess.Popen(pcmd, stdout=subprocess.PIPE, stdin=subprocess.DEVNULL, text=True,
                            bufsize=1)

    stopped = []

    def forward(sig, _frame):
        stopped.append(sig)
        try:
            proc.send_signal(sig)
        except ProcessLookupError:
            pass

    signal.signal(signal.SIGTERM, forward)
    signal.signal(signal.SIGHUP, forward)
    interrupted = False
    try:
        for line in proc.stdout:
            line = line.rstrip("\n")
            word = line.split(" ", 1)[0]
            if word in FINISHED:
                done += 1
                finished_now += 1
                if args.no_shared_dir:  # its folder is back: parallel prints a job's output last
                    run_id = line.split(" ", 2)[1] if " " in line else ""
                    results.collect_remote(out, [run_id])
                left = total - done
                rate = (time.monotonic() - started) / finished_now
                eta = f"  eta {fmt_duration(rate * left)}" if left > 0 else ""
                print(f"[{done}/{total}] {line}{eta}", flush=True)
            elif word == SKIPPED:
                skipped += 1  # has its row file but is not in the joblog (killed before it was logged)
            else:
                print(line, flush=True)
        proc.wait()
    except KeyboardInterrupt:
        interrupted = True
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        proc.wait()  # parallel got the SIGINT too: it stops its jobs
    if stopped or (proc.returncode and proc.returncode < 0):
        interrupted = True

    if args.no_shared_dir:
        results.collect_remote(out)
    rows = assemble(out, head, order)
    if skipped:
        print(f"sweep: {skipped} run(s) already had their row; not run again")
    plots_dir = None
    if not interrupted and not args.no_plots and any(r.get("status") == "ok" for r in rows.values()):
        plots_dir = os.path.join(out, "plots")
        page = ["--page", args.page, "--part", name, "--rtm", rtm] if args.page else []
        r = subprocess.run([PLOT_SWEEP, csv_path, plots_dir, "--quiet"] + page)
        if r.returncode != 0:
            print("sweep: warning: plotting failed (scripts/plot-sweep)", file=sys.stderr)
            plots_dir = None
    missing = report(name, out, rows, jobs, plots_dir)
    if interrupted:
        print("sweep: interrupted; run the same command again to resume", file=sys.stderr)
        return 128 + (stopped[0] if stopped else signal.SIGINT)
    return 1 if missing else 0
