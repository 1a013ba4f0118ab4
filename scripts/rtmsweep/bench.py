"""What a change costs a study (scripts/bench-sweep): the same sweep run whole with this build and
with each other build in turn, on the same cores, each with an empty reference cache, and their
results.csv compared: the builds' times side by side, and whether every simulated figure is the
same. docs/benchmarks.md, "A study's time".

    scripts/bench-sweep SPEC.yaml --against DIR [--against DIR ...] [--at COMMIT] [--jobs N] [--dir DIR]
                       [--page PAGE]
"""

import argparse
import collections
import os
import shutil
import subprocess
import sys
import time
from typing import NamedTuple

import yaml

from . import page, results, spec, sweep

WHO = "scripts/bench-sweep"  # the writer its study page names
# The columns that say how a run went on this machine, not what was simulated.
NOT_SIMULATED = {"wall_seconds", "host", "commit"}


class Sweep(NamedTuple):
    """One build's whole sweep: its wall time, its results.csv, the load average around it."""
    elapsed: float
    head: list
    rows: list
    load: tuple


def die(message, code=2):
    print(f"bench-sweep: {message}", file=sys.stderr)
    sys.exit(code)


def differences(new, old):
    """How OLD's results (header, rows) differ from NEW's: (run ids only in one of them, the
    simulated columns only one of them records, {column: runs whose values differ} over the
    rest). A build older than a column leaves it empty in every row."""
    (new_head, new_rows), (old_head, old_rows) = new, old
    by_id = {r["run_id"]: r for r in old_rows}
    lone = sorted(set(by_id) ^ {r["run_id"] for r in new_rows})

    def recorded(head, rows):
        return {c for c in head if c not in NOT_SIMULATED and any(r[c] != "" for r in rows)}

    new_cols, old_cols = recorded(new_head, new_rows), recorded(old_head, old_rows)
    shared = [c for c in new_head if c in new_cols & old_cols]
    one_sided = sorted(new_cols ^ old_cols)
    differing = collections.Counter()
    for r in new_rows:
        o = by_id.get(r["run_id"])
        for c in shared if o else ():
            differing[c] += r[c] != o[c]
    return lone, one_sided, {c: n for c, n in differing.items() if n}


def own_seconds(rows):
    """The runs' own wall seconds, summed."""
    return sum(float(r["wall_seconds"]) for r in rows if r.get("wall_seconds"))


def seconds_by(rows, key):
    """The runs' own wall seconds summed per value of KEY, in first-seen order."""
    sums = {}
    for r in rows:
        if r.get("wall_seconds"):
            sums[r[key]] = sums.get(r[key], 0.0) + float(r["wall_seconds"])
    return sums


def spec_at(commit, path, folder):
    """The spec file PATH as it was at COMMIT (git show), written into FOLDER with its paths made
    absolute from PATH's folder, where the old file read them from: that file's path."""
    where = os.path.dirname(os.path.abspath(path))
    shown = subprocess.run(["git", "-C", where, "show", f"{commit}:./{os.path.basename(path)}"],
                           capture_output=True, text=True)
    if shown.returncode != 0:
        die(f"--at {commit}: {shown.stderr.strip() or 'git show failed'}")
    data = yaml.safe_load(shown.stdout)
    if not isinstance(data, dict):
        die(f"--at {commit}: {path} was not a spec there")
    data["scene_dir"] = spec._path(data.get("scene_dir") or ".", where)
    if data.get("config"):
        data["config"] = spec._path(data["config"], where)
    os.makedirs(folder, exist_ok=True)
    out = os.path.join(folder, f"{os.path.splitext(os.path.basename(path))[0]}-at-{commit}.yaml")
    results.write_atomic(out, yaml.safe_dump(data, sort_keys=False))
    return out


def timed_sweep(spec_path, rtm, out, jobs):
    """Runs the sweep whole into OUT (emptied first) with RTM and its own empty reference cache."""
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    cmd = [os.path.join(sweep.SCRIPTS, "sweep"), spec_path, "--out", out, "--rtm", rtm,
           "--no-plots"] + (["--jobs", jobs] if jobs else [])
    env = dict(os.environ, RTM_CACHE_DIR=os.path.join(out, "cache"))
    load, start = os.getloadavg()[0], time.monotonic()
    done = subprocess.run(cmd, env=env, stdout=sys.stderr)  # its line a run: the progress
    elapsed = time.monotonic() - start
    if done.returncode != 0:
        die(f"the sweep with {rtm} failed (exit {done.returncode}); its runs are in {out}", 1)
    head, rows = results.read_csv(results.results_path(out))
    return Sweep(elapsed, head, rows, (load, os.getloadavg()[0]))


def tables(name, builds, versions, timed, compared, jobs):
    """The page's Markdown: each build (its `--version`), then the times, then the figures of each
    other build COMPARED with new's (differences())."""
    names = [n for n, _ in builds]
    lines = [f"Sweep `{name}`, {len(timed[0].rows)} runs, {f'{jobs} at a time' if jobs else 'one per core at a time'}, on "
             f"{os.cpu_count()} cores; the builds one after another ({', '.join(names)}).", ""]
    lines += [f"- {n}: `{v}`" for n, v in zip(names, versions)] + [""]
    lines += ["| build | sweep's wall s | runs' own s in all | new / build, wall | new / build, runs' own "
              "| load average before, after |", "|---|---|---|---|---|---|"]
    own = [own_seconds(t.rows) for t in timed]
    for i, (n, t) in enumerate(zip(names, timed)):
        ratios = " | " if i == 0 else f"{timed[0].elapsed / t.elapsed:.2f} | {own[0] / own[i]:.2f}"
        lines.append(f"| {n} | {t.elapsed:.1f} | {own[i]:.1f} | {ratios} | {t.load[0]:.2f}, {t.load[1]:.2f} |")
    variants = list(seconds_by(timed[0].rows, "variant")) if "variant" in timed[0].head else []
    if variants:
        lines += ["", "The runs' own seconds per variant:", "",
                  "| variant | " + " | ".join(names) + " | " + " | ".join(f"new / {n}" for n in names[1:]) + " |",
                  "|---|" + "---|" * (2 * len(names) - 1)]
        per = [seconds_by(t.rows, "variant") for t in timed]
        for v in variants:
            cells = [f"{p.get(v, 0):.1f}" for p in per]
            cells += [f"{per[0][v] / p[v]:.2f}" if p.get(v) else "" for p in per[1:]]
            lines.append(f"| {v} | " + " | ".join(cells) + " |")
    lines += [""]
    for n, (lone, one_sided, differing) in zip(names[1:], compared):
        same = not lone and not differing
        lines.append(f"- new against {n}: " + ("every simulated figure of every run the same"
                                                if same else "figures differ"))
        if lone:
            lines.append(f"  - runs in one only: {', '.join(lone)}")
        for c, count in sorted(differing.items()):
            lines.append(f"  - `{c}` differs in {count} runs")
        if one_sided:
            lines.append(f"  - recorded by one build only, not compared: {', '.join(one_sided)}")
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(prog="scripts/bench-sweep", description=__doc__.split("\n\n")[0])
    ap.add_argument("spec", help="the sweep spec (YAML)")
    ap.add_argument("--against", action="append", default=[], metavar="DIR", required=True,
                    help="another build (DIR/rtm), e.g. of an earlier commit; more than once for several")
    ap.add_argument("--at", metavar="COMMIT",
                    help="the spec as it was at COMMIT (for a build older than its keys)")
    ap.add_argument("--jobs", "-j", help="runs at once (default one per core)")
    ap.add_argument("--dir", default="out/bench-sweep", help="where the sweeps go (default out/bench-sweep)")
    ap.add_argument("--page", help="the study page whose part written by scripts/bench-sweep gets the tables")
    args = ap.parse_args(argv)

    if args.page:
        try:
            page.part(args.page, WHO)
        except page.PageError as e:
            die(str(e))
    if args.at:
        args.spec = spec_at(args.at, args.spec, args.dir)
    try:
        name = spec.load(args.spec).name
    except spec.SpecError as e:
        die(f"{args.spec}: {e}")
    others = []
    for i, d in enumerate(args.against):
        rtm = os.path.abspath(os.path.join(d, "rtm"))
        if not os.access(rtm, os.X_OK):
            die(f"--against {d}: no rtm program at {rtm}")
        others.append((f"old{i + 1}" if len(args.against) > 1 else "old", rtm))
    builds = [("new", sweep.find_rtm(None))] + others
    timed = []
    for n, rtm in builds:
        print(f"bench-sweep: {name} with {n} ({rtm})", file=sys.stderr)
        timed.append(timed_sweep(args.spec, rtm, os.path.join(args.dir, n), args.jobs))
    versions = [page.build_of(rtm) for _, rtm in builds]
    compared = [differences((timed[0].head, timed[0].rows), (t.head, t.rows)) for t in timed[1:]]
    body = tables(name, builds, versions, timed, compared, args.jobs)
    results.write_atomic(os.path.join(args.dir, "tables.md"), body)
    print(body, end="")
    if args.page:
        try:
            page.update(args.page, WHO, body, versions[0], runs=page.runs_line(timed[0].rows))
        except page.PageError as e:
            die(str(e))
    return 0 if all(not lone and not differing for lone, _, differing in compared) else 1
