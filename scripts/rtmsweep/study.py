"""What the studies that read rtm's statistics share (scripts/memory-study, scripts/error-study):
run a sweep spec with scripts/sweep (resumable: run the same command again after an
interruption), then read each run's statistics JSON. `args` is the study's parsed command line:
its --jobs, --rtm, --spec, --work and --scene-dir."""

import json
import os
import subprocess

import yaml

from . import page, results
from . import spec as spec_module

SCRIPTS = os.path.dirname(os.path.dirname(os.path.realpath(__file__)))
ROOT = os.path.dirname(SCRIPTS)


class StudyError(Exception):
    """A study that cannot go on: the message says why."""


def read_json(path):
    with open(path) as f:
        return json.load(f)


def sweep(spec, out, args):
    """Runs scripts/sweep SPEC into OUT; returns the rows of SPEC's runs. Runs that failed are rows
    too (with their error); runs without a row stop the study."""
    command = [os.path.join(SCRIPTS, "sweep"), spec, "--out", out, "--no-plots"]
    if args.jobs:
        command += ["--jobs", args.jobs]
    if args.rtm:
        command += ["--rtm", args.rtm]
    code = subprocess.call(command, stdin=subprocess.DEVNULL)
    if code == 2:
        raise StudyError("scripts/sweep refused " + spec)
    if code != 0:
        raise StudyError(f"the sweep in {out} left runs without a row (exit {code}): run the same command again")
    # results.csv keeps the rows of configurations an earlier spec in OUT listed: only this one's.
    ids = {job["id"] for job in spec_module.load(spec).jobs()}
    _, rows = results.read_csv(results.results_path(out))
    return [r for r in rows if r["run_id"] in ids]


def stats_of(out, row):
    """The run's statistics, or None for a run that failed."""
    if row["status"] != "ok":
        return None
    return read_json(os.path.join(results.runs_dir(out), row["run_id"] + ".json"))


def write(path, text, who):
    """Writes a study's output file atomically and says so, as `who`."""
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    results.write_atomic(path, text)
    print(f"{who}: wrote {path}")


def spec_rows(args, default_spec, row_of):
    """Runs the study's sweep (--spec, or its default; --scene-dir replaces the spec's scene_dir)
    and returns a row_of(sweep row, stats) per run."""
    spec_path = os.path.abspath(args.spec or default_spec)
    with open(spec_path) as f:
        spec = yaml.safe_load(f)
    name = spec.get("name") or os.path.splitext(os.path.basename(spec_path))[0]
    work = os.path.join(args.work, name)
    if args.scene_dir:
        # A copy with the scene folder replaced; the run ids depend on the scenes' paths, not the spec's.
        spec["scene_dir"] = os.path.abspath(args.scene_dir)
        os.makedirs(work, exist_ok=True)
        spec_path = os.path.join(work, name + "-spec.yaml")
        with open(spec_path, "w") as f:
            yaml.safe_dump(spec, f, sort_keys=False)
    rows = []
    for r in sweep(spec_path, work, args):
        row = row_of(r, stats_of(work, r))
        row.setdefault("wall_seconds", r.get("wall_seconds"))  # the page's run time; not a CSV column unless listed
        rows.append(row)
    return rows


def write_page(args, who, text, rows):
    """With --page, writes the study page's generated part: TEXT, stamped with the build that ran
    the sweep and the rows' count and run time."""
    if not getattr(args, "page", None):
        return
    rtm = args.rtm or os.path.join(ROOT, os.environ.get("RTM_BUILD_DIR", "build"), "rtm")
    try:
        page.update(args.page, who, text, page.build_of(rtm), page.runs_line(rows))
    except page.PageError as e:
        raise StudyError(str(e))
