"""The docs cannot drift: every link and heading reference resolves, every shown transcript is
its docs/transcripts/*.t as cram runs it, and the README's Studies table is the study pages'."""

import os
import re
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))
DOCS = [os.path.join(ROOT, "README.md")] + sorted(
    os.path.join(d, f) for d, _, fs in os.walk(os.path.join(ROOT, "docs")) for f in fs if f.endswith(".md"))
LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")
# Prose references to a section: docs/x.md, "Heading" and docs/x.md ("Heading"
PROSE = re.compile(r"(docs/[\w/.-]+\.md),? \(?\"([^\"]+)\"")
FENCE = re.compile(r"^```.*?^```", re.M | re.S)


def text_of(path):
    with open(path) as f:
        return f.read()


def prose(path):
    """The file without its code blocks: commands and YAML are not links."""
    return FENCE.sub("", text_of(path))


def slug(heading):
    """GitHub's anchor of a heading."""
    s = re.sub(r"[^\w\- ]", "", heading.strip().lower().replace("`", ""))
    return s.replace(" ", "-")


def headings(path):
    return [m.group(1).strip() for m in re.finditer(r"^#{1,6} (.+)$", prose(path), re.M)]


def sections(path):
    """What a prose reference may name: a heading (or its start) or a bold paragraph lead."""
    leads = [m.group(1) for m in re.finditer(r"^(?:- )?\*\*([^*]+)\*\*", prose(path), re.M)]
    return headings(path) + leads


def plain(title):
    """A title as prose and comments name it: case numbers ("13. ") off, dashes as hyphens."""
    return re.sub(r"^\d+\. ", "", title).replace("–", "-")


def names_section(path, ref):
    ref = plain(ref)
    return any(s == ref or s.startswith(ref + " ") or s.startswith(ref + ".") or s.startswith(ref + ":")
               for s in map(plain, sections(path)))


def rel(path):
    return os.path.relpath(path, ROOT)


@pytest.mark.parametrize("doc", DOCS, ids=rel)
def test_links_resolve(doc):
    bad = []
    for target in LINK.findall(prose(doc)):
        if re.match(r"[a-z]+:", target):
            continue
        file, _, anchor = target.partition("#")
        path = os.path.normpath(os.path.join(os.path.dirname(doc), file)) if file else doc
        if not os.path.exists(path):
            bad.append(f"{target}: no such file")
        elif anchor and anchor not in {slug(h) for h in headings(path)}:
            bad.append(f"{target}: no heading #{anchor} in {rel(path)}")
    assert not bad, f"{rel(doc)}: " + "; ".join(bad)


@pytest.mark.parametrize("doc", DOCS, ids=rel)
def test_section_references_resolve(doc):
    bad = []
    for file, ref in PROSE.findall(re.sub(r"`[^`\n]*`", "", prose(doc))):
        ref = " ".join(ref.split())
        path = os.path.join(ROOT, file)
        if not os.path.exists(path):
            bad.append(f'{file}: no such file')
        elif not names_section(path, ref):
            bad.append(f'{file}, "{ref}": no such heading')
    assert not bad, f"{rel(doc)}: " + "; ".join(bad)


SOURCES = sorted(os.path.join(d, f) for top in ("model", "tb", "scripts") for d, _, fs in os.walk(os.path.join(ROOT, top))
                 for f in fs if f.endswith((".h", ".cpp", ".py", ".yaml")) or os.path.dirname(os.path.join(d, f)).endswith("scripts"))


def test_sources_name_docs_and_sections_that_exist():
    """The code's comments cite docs/x.md and docs/x.md, "Heading" too: a moved section fails here."""
    bad = []
    for src in SOURCES:
        if src == os.path.realpath(__file__):
            continue
        try:
            text = text_of(src)
        except (UnicodeDecodeError, OSError):
            continue
        for file in set(re.findall(r"\bdocs/[\w/.-]+\.md\b", text)):
            if not os.path.exists(os.path.join(ROOT, file)):
                bad.append(f"{rel(src)}: {file}: no such file")
        for file, ref in PROSE.findall(re.sub(r"\n\s*(#|//+)+\s*", " ", text)):
            path = os.path.join(ROOT, file)
            if os.path.exists(path) and not names_section(path, " ".join(ref.split())):
                bad.append(f'{rel(src)}: {file}, "{ref}": no such heading')
    assert not bad, "; ".join(bad)


def test_a_renamed_heading_fails(tmp_path):
    page = tmp_path / "a.md"
    page.write_text("# Title\n\n## The engine\n\n**A lead.** text\n")
    assert names_section(str(page), "The engine")
    assert names_section(str(page), "A lead")
    assert not names_section(str(page), "The PE engine")
    page.write_text("### 13. Why a pixel differs: the map\n\n## The host–PE link\n")
    assert names_section(str(page), "Why a pixel differs")
    assert names_section(str(page), "The host-PE link")
    assert slug("The host–PE interconnect (`link_topology`)") == "the-hostpe-interconnect-link_topology"


def test_shown_transcripts_are_the_transcripts():
    r = subprocess.run([os.path.join(ROOT, "scripts", "doc-transcripts"), "--check"], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr


def test_readme_studies_table_is_the_study_pages():
    r = subprocess.run([os.path.join(ROOT, "scripts", "study-page"), "--readme", "--check"], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr


@pytest.mark.parametrize("doc", DOCS, ids=rel)
def test_named_scene_files_exist(doc):
    """A scene a doc names (in prose or a command) is in the repository."""
    names = set(re.findall(r"\bscenes/[\w/.-]+\.(?:nff|yaml)\b", text_of(doc)))
    missing = sorted(n for n in names if not os.path.isfile(os.path.join(ROOT, n)))
    assert not missing, f"{rel(doc)}: no such scene file: {', '.join(missing)}"
