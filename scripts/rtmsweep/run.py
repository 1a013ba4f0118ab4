"""One run of a sweep (scripts/sweep-run): renders one job with rtm and writes its row file.

    sweep-run --dir DIR --rtm RTM [--no-append] RUN_ID SCENE JOB_JSON

The run's statistics (DIR/runs/RUN_ID.json), stderr (.err), image (.png, unless the spec says
images: false) and its row file (.row: the header and its row) go to DIR/runs/ (with
--no-append: DIR/runs/RUN_ID.remote/, for GNU parallel to bring back from another host). A run
whose row file exists is done: it is not run again.

Two attempts at one run never overlap: each holds a lock on DIR/runs/RUN_ID.lock (flock; on NFS,
Linux's client makes it a lock the server keeps, unless mounted with local_lock) while it runs,
and one that had to wait takes the row the other left instead of running again. Otherwise,
sharing the run's file names, each would delete the other's statistics and output, and one would
record a finished-looking failed row ("no readable statistics"). It happens when a killed sweep
is resumed at once: GNU parallel killed does not stop its jobs over SSH, whose ssh clients live
on in process groups of their own, and a job whose connection was still being made has nothing
yet that could be seen and waited for.

Exit status: 0 when the run has its row (whatever rtm's exit code: a failed or deadlocked run
is a result too), non-zero when it has none (interrupted), so that GNU parallel's
--resume-failed runs it again. Signals that interrupt (TERM, INT, HUP, KILL) are not recorded;
a crash (SEGV, ABRT, ...) is recorded as failed.
"""

import argparse
import ctypes
import errno
import fcntl
import json
import os
import signal
import socket
import subprocess
import sys
import time

from . import checkout, columns, results

# Top-level spec axes: the rtm render option of each.
AXIS_OPTIONS = {"pes": "--pes", "partition": "--partition", "search_units": "--search-units",
                "timing": "--timing", "precision": "--precision"}
# rtm exits with this on a deadlocked simulation.
EXIT_DEADLOCK = 3
# A run killed by one of these was interrupted, not broken: no row, so a resume runs it again.
INTERRUPT_SIGNALS = {signal.SIGTERM, signal.SIGINT, signal.SIGHUP, signal.SIGKILL}


def rtm_command(rtm, job, out_png, out_json):
    """The rtm render command line of a job."""
    cmd = [rtm, "render", job["scene"]]
    if job.get("size"):
        cmd += ["--size", job["size"]]
    for key, opt in AXIS_OPTIONS.items():
        if job.get(key) is not None:
            cmd += [opt, str(job[key])]
    if job.get("preset"):
        cmd += ["--preset", job["preset"]]
    if job.get("config"):
        cmd += ["--config", job["config"]]
    for key, value in job.get("set", {}).items():
        cmd += ["--set", f"{key}={value}"]
    # GNU parallel already runs a job per core: each simulates its PEs on one thread.
    return cmd + ["--sim-threads", "1", "--out", out_png, "--stats", out_json, "-q"]


def error_line(stderr_text):
    """rtm's error message: the last stderr line starting with 'rtm:', else the last non-empty one."""
    lines = [line.strip() for line in stderr_text.splitlines() if line.strip()]
    for line in reversed(lines):
        if line.startswith("rtm:"):
            return line
    return lines[-1] if lines else ""


def build_row(job, status, error, exit_code, stats=None, host=None):
    """One CSV row (dict) of a job: its configuration (the job's settings, else what the
    statistics say the run used) and, when STATS has one, the metrics of its `summary`."""
    s = stats or {}
    cfg = s.get("config") if isinstance(s.get("config"), dict) else {}
    row = {"run_id": job["id"], "status": status, "error": error, "exit_code": exit_code,
           "host": host or socket.gethostname(), "scene_file": checkout.relative(job["scene"])}
    row["scene"] = s.get("scene") or os.path.splitext(os.path.basename(job["scene"]))[0]
    if job.get("size"):
        row["width"], row["height"] = (int(x) for x in job["size"].split("x"))
    else:
        row["width"], row["height"] = s.get("width"), s.get("height")
    for key in AXIS_OPTIONS:
        row[key] = job[key] if job.get(key) is not None else s.get(key, cfg.get(key))
    for key in job.get("set_keys", []):
        if key in ("variant", "preset"):
            row[key] = job.get(key, s.get(key))  # a job without a preset: the one rtm says it used
        else:
            row[key] = job.get("set", {}).get(key, cfg.get(key))
    build = s.get("build") if isinstance(s.get("build"), dict) else {}
    row["commit"] = build["commit"] + ("-modified" if build.get("modified") else "") if build.get("commit") else None
    summary = s.get("summary")
    if isinstance(summary, dict):
        for key in columns.SUMMARY_COLUMNS:
            row[key] = summary.get(key)
        for key in columns.INTEGER_COLUMNS:
            if isinstance(row[key], float) and row[key].is_integer():
                row[key] = int(row[key])
    return row


def outcome(code, timed_out, timeout, message, stats_path):
    """(status, error message, statistics) of a finished rtm: its exit code, whether it ran out
    of time, its stderr's error line, and where its statistics should be."""
    if timed_out:
        return "timeout", f"timed out after {timeout:g} s", None
    if code == EXIT_DEADLOCK:
        return "deadlock", message, None
    if code != 0:
        if code < 0:
            message = f"rtm crashed ({signal.Signals(-code).name})" + (f": {message}" if message else "")
        return "failed", message, None
    try:
        with open(stats_path) as f:
            stats = json.load(f)
    except (OSError, ValueError) as e:
        return "failed", f"no readable statistics ({e})", None
    if not isinstance(stats, dict) or not isinstance(stats.get("summary"), dict):
        return "failed", "the statistics have no summary object (an rtm older than this sweep tooling?)", \
            stats if isinstance(stats, dict) else None
    return "ok", "", stats


def _set_pdeathsig(sig):
    """Linux: deliver SIG to this process when its parent dies (GNU parallel gives every job its
    own process group, so killing the sweep's group would otherwise leave jobs running)."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, int(sig), 0, 0, 0)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass


def _remove(path):
    try:
        os.remove(path)
    except FileNotFoundError:
        pass


LOCK_SUFFIX = ".lock"


def _lock_run(path, interrupted):
    """Holds the run's lock file PATH: (its descriptor, whether another attempt held it first),
    or (None, True) when a signal came while waiting; (-1, False) when the file system has no
    locks, and the run goes on unguarded. Polls, so that a signal ends the wait."""
    waited = False
    while True:
        fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o644)
        while True:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                break
            except BlockingIOError:
                if not waited:
                    print(f"sweep-run: {os.path.basename(path)[:-len(LOCK_SUFFIX)]}: another attempt at this "
                          "run is going; waiting for it", file=sys.stderr, flush=True)
                waited = True
                if interrupted:
                    os.close(fd)
                    return None, True
                time.sleep(0.05)
            except OSError as e:
                if e.errno not in (errno.ENOLCK, errno.EOPNOTSUPP, errno.EINVAL):
                    raise
                os.close(fd)
                print(f"sweep-run: {path}: no file locks here ({e.strerror}); two attempts at this run "
                      "could overlap", file=sys.stderr)
                return -1, False
        # The holder removes the file before it lets go: a lock on a removed file guards nothing.
        try:
            same = os.stat(path).st_ino == os.fstat(fd).st_ino
        except FileNotFoundError:
            same = False
        if same:
            return fd, waited
        os.close(fd)
        waited = True


def _unlock_run(path, fd):
    if fd >= 0:
        _remove(path)
        os.close(fd)


def run(args):
    job = json.loads(args.job)
    run_id = job["id"]
    if run_id != args.run_id:
        print(f"sweep-run: run id {args.run_id} does not match its job ({run_id})", file=sys.stderr)
        return 2
    runs = results.runs_dir(args.dir)
    if args.no_append:  # one folder for --return to bring back; the sweep moves its files to runs/
        runs = os.path.join(runs, run_id + results.REMOTE_SUFFIX)
    os.makedirs(runs, exist_ok=True)
    base = os.path.join(runs, run_id)

    if not args.no_append and os.path.exists(results.row_path(args.dir, run_id)):
        print(f"skip {run_id} (already has its row)", flush=True)
        return 0

    # Interrupted (parallel's --termseq, Ctrl-C, the parent dying): stop rtm, record nothing.
    parent = os.getppid()
    _set_pdeathsig(signal.SIGTERM)
    interrupted = []
    child = []

    def on_signal(sig, _frame):
        interrupted.append(sig)
        for p in child:
            try:
                p.kill()
            except ProcessLookupError:
                pass

    for sig in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP):
        signal.signal(sig, on_signal)
    if os.getppid() != parent:  # the parent died before the death signal was armed
        return 128 + signal.SIGTERM

    lock_path = os.path.join(results.runs_dir(args.dir), run_id + LOCK_SUFFIX)
    lock, waited = _lock_run(lock_path, interrupted)
    if lock is None:
        return 128 + interrupted[0]
    try:
        return _run_locked(args, job, base, interrupted, child, waited)
    finally:
        _unlock_run(lock_path, lock)


def _run_locked(args, job, base, interrupted, child, waited):
    """The run, its lock held. WAITED: another attempt held the lock first; the row it left is
    this run's (with --no-append a row that was there before is an earlier result, and the run
    goes again)."""
    run_id = job["id"]
    if (waited or not args.no_append) and os.path.exists(base + results.ROW_SUFFIX):
        print(f"skip {run_id} (already has its row)", flush=True)
        return 0

    out_png, out_json, out_err, out_log = base + ".png", base + ".json", base + ".err", base + ".out"
    for p in (out_png, out_json, out_err, out_log, base + results.ROW_SUFFIX):
        _remove(p)  # never mistake a killed earlier attempt's files for this run's
    cmd = rtm_command(args.rtm, job, out_png, out_json)
    env = dict(os.environ, SYSTEMC_DISABLE_COPYRIGHT_MESSAGE="1")
    timeout = job.get("timeout")
    started = time.monotonic()
    timed_out = False
    with open(out_err, "w") as err, open(out_log, "w") as log:
        try:
            p = subprocess.Popen(cmd, stdout=log, stderr=err, stdin=subprocess.DEVNULL, env=env,
                                 preexec_fn=lambda: _set_pdeathsig(signal.SIGKILL))
        except OSError as e:
            # This host can't run rtm at all: no row, so that a rerun tries again (elsewhere).
            print(f"sweep-run: {socket.gethostname()}: cannot start {args.rtm}: {e.strerror}", file=sys.stderr)
            return 127
        child.append(p)
        if interrupted:
            p.kill()
        try:
            p.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            timed_out = True
            p.kill()
            p.wait()
    elapsed = time.monotonic() - started
    if os.path.getsize(out_log) == 0:
        _remove(out_log)
    if interrupted:
        return 128 + interrupted[0]

    code = p.returncode
    if code < 0 and -code in INTERRUPT_SIGNALS and not timed_out:
        print(f"sweep-run: {run_id}: rtm killed by {signal.Signals(-code).name}; not recorded",
              file=sys.stderr)
        return 128 - code

    with open(out_err) as f:
        message = error_line(f.read())
    status, message, stats = outcome(code, timed_out, timeout, message, out_json)
    if not job.get("images", True):
        _remove(out_png)

    row = build_row(job, status, message, code, stats)
    results.write_row(base + results.ROW_SUFFIX, columns.header(job.get("set_keys", [])), row)

    if status == "ok":
        detail = f"cycles {row['cycles']}  wall {elapsed:.1f} s"
    else:
        detail = f"exit {code}: {message}"
    try:
        print(f"{status} {run_id}  {detail}", flush=True)
    except BrokenPipeError:  # GNU parallel is gone; the row is recorded all the same
        pass
    return 0


def main(argv=None):
    ap = argparse.ArgumentParser(prog="sweep-run", description="Runs one sweep configuration (started by scripts/sweep).")
    ap.add_argument("--dir", required=True, help="the sweep's output folder")
    ap.add_argument("--rtm", required=True, help="the rtm executable")
    # (Named when runs appended their rows to results.csv themselves; kept for the command line.)
    ap.add_argument("--no-append", action="store_true",
                    help="write the run's files, its row file included, to runs/RUN_ID.remote/ (for hosts "
                         "without the shared folder: GNU parallel brings that folder back, the sweep moves "
                         "the files to runs/)")
    ap.add_argument("run_id")
    ap.add_argument("scene")
    ap.add_argument("job", help="the job's JSON")
    return run(ap.parse_args(argv))
