"""The studies (docs/studies/*.md) as a list, and the README's Studies table made from it.

Each page opens with its title, then the lines `Command: ...` and `Output: ...`; its run count and
run time are in the stamp of its generated part (page.py)."""

import glob
import os
import re

from . import page, results

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))
STUDIES = os.path.join(ROOT, "docs", "studies")
README = os.path.join(ROOT, "README.md")
BEGIN = "<!-- begin: written by scripts/study-page --readme, do not edit -->"
END = "<!-- end: written by scripts/study-page --readme -->"


class StudiesError(Exception):
    """A study page without what the table needs, or a README without the table's markers."""


def describe(path):
    """{"title", "command", "output", "runs", "page"} of one study page."""
    with open(path) as f:
        text = f.read()
    rel = os.path.relpath(path, ROOT)
    fields = {"page": rel}
    title = re.search(r"^# (.+)$", text, re.M)
    fields["title"] = title.group(1) if title else None
    for key in ("command", "output"):
        m = re.search(rf"^{key.capitalize()}: (.+)$", text, re.M)
        fields[key] = m.group(1).strip() if m else None
    missing = [k for k, v in fields.items() if v is None]
    if missing:
        raise StudiesError(f"{rel}: no {', '.join(missing)} line")
    parts = page.record(path)
    fields["runs"] = "; ".join(p["runs"] for p in parts if "runs" in p) or "not recorded"
    return fields


def table():
    rows = ["| study | command | runs, time on 2 cores (recorded) | output |", "|---|---|---|---|"]
    for path in sorted(glob.glob(os.path.join(STUDIES, "*.md"))):
        s = describe(path)
        rows.append(f"| [{s['title']}]({s['page']}) | {s['command']} | {s['runs']} | {s['output']} |")
    return "\n".join(rows)


def write_readme(check=False):
    with open(README) as f:
        text = f.read()
    start, stop = text.find(BEGIN), text.find(END)
    if start < 0 or stop < start:
        raise StudiesError(f"README.md: no Studies table markers ({BEGIN!r} and {END!r})")
    new = text[:start] + BEGIN + "\n" + table() + "\n" + text[stop:]
    if check:
        if new != text:
            print("study-page: README.md's Studies table differs from docs/studies: run scripts/study-page --readme")
            return 1
        return 0
    results.write_atomic(README, new)
    print("study-page: wrote README.md")
    return 0
