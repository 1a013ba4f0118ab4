"""A study page (docs/studies/*.md): hand-written prose, the question and the findings, around
the part the study's script writes between two markers:

    <!-- begin: written by scripts/NAME, do not edit -->
    - build: `rtm ...` (what `rtm --version` printed, or "build not recorded")
    - written: YYYY-MM-DD
    - runs: N, M min of run time in all (about M/2 min on 2 cores)
    ...tables...
    <!-- end: written by scripts/NAME -->

update() replaces what lies between the markers and leaves the rest of the page as it is;
record() reads the stamp back (the README's Studies table is made from it)."""

import datetime
import os
import re
import subprocess

from . import results

BEGIN = "<!-- begin: written by {who}, do not edit -->"
END = "<!-- end: written by {who} -->"
BEGIN_RE = re.compile(r"^<!-- begin: written by (.+), do not edit -->$", re.M)
NOT_RECORDED = "build not recorded"


class PageError(Exception):
    """A page that cannot be written: the message names it and says why."""


def build_of(rtm):
    """What `RTM --version` prints (its lines joined by "; "), or NOT_RECORDED when there is no
    such program."""
    try:
        out = subprocess.run([rtm, "--version"], capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.TimeoutExpired):
        return NOT_RECORDED
    text = "; ".join(line.strip() for line in out.stdout.splitlines() if line.strip())
    return text if out.returncode == 0 and text else NOT_RECORDED


def run_time(seconds, at_once=2):
    """`runs` line's time: the runs' own seconds, summed, in minutes; AT_ONCE runs at a time
    (a sweep runs one per core: two on 2 cores)."""
    minutes = seconds / 60
    if at_once == 1:
        return f"{minutes:.1f} min of run time in all, one run at a time"
    return f"{minutes:.1f} min of run time in all (about {minutes / at_once:.0f} min on {at_once} cores)"


def runs_line(rows, key="wall_seconds", at_once=2):
    """The stamp's runs line from a study's rows (dicts): their count and their summed run time
    (KEY), saying how many have none recorded."""
    walls = [r.get(key) for r in rows]
    known = [float(w) for w in walls if w not in (None, "")]
    if not known:
        return f"{len(rows)}, run time not recorded"
    line = f"{len(rows)}, {run_time(sum(known), at_once)}"
    if len(known) < len(rows):
        line += f"; {len(rows) - len(known)} without a recorded time"
    return line


def stamp(build, date, runs=None):
    lines = [f"- build: `{build}`" if build != NOT_RECORDED else f"- build: {NOT_RECORDED}",
             f"- written: {date}"]
    if runs is not None:
        lines.append(f"- runs: {runs}")
    return "\n".join(lines)


def demoted(body):
    """BODY's headings two levels down: a script's own file starts at "#", the page's part sits
    under its "## Results"."""
    return re.sub(r"^#", "###", body, flags=re.M)


def part(page, who):
    """(PAGE's text, where its part written by WHO begins and ends); PageError when the page or
    its markers are missing: a study checks this before it runs."""
    begin, end = BEGIN.format(who=who), END.format(who=who)
    try:
        with open(page) as f:
            text = f.read()
    except OSError as e:
        raise PageError(f"{page}: cannot read the study page: {e.strerror}")
    start, stop = text.find(begin), text.find(end)
    if start < 0 or stop < start:
        raise PageError(f"{page}: no part written by {who} (the lines {begin!r} and {end!r})")
    return text, start, stop


def update(page, who, body, build, runs=None, date=None):
    """Rewrites PAGE's part written by WHO (e.g. "scripts/memory-study ports") with the stamp and
    BODY (Markdown). The page and its markers must exist: the prose around them is hand-written."""
    begin, end = BEGIN.format(who=who), END.format(who=who)
    text, start, stop = part(page, who)
    date = date or datetime.date.today().isoformat()
    generated = begin + "\n" + stamp(build, date, runs) + "\n\n" + demoted(body).strip() + "\n" + end
    results.write_atomic(page, text[:start] + generated + text[stop + len(end):])
    print(f"{who}: wrote {os.path.relpath(page)}")


def record(page):
    """{"who", "build", "written", "runs"} of each part of PAGE written by a script."""
    with open(page) as f:
        text = f.read()
    parts = []
    for m in BEGIN_RE.finditer(text):
        part = {"who": m.group(1)}
        for line in text[m.end():text.find(END.format(who=m.group(1)), m.end())].splitlines():
            field = re.match(r"^- (build|written|runs): (.*)$", line)
            if field:
                part[field.group(1)] = field.group(2).strip("`")
        parts.append(part)
    return parts
