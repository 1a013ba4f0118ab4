"""The repository runs from itself alone: every sweep example checks out on a clean copy of HEAD
(no build, nothing beside it), and no tracked file names an absolute path of the development
machine or a folder beside the checkout."""

import os
import re
import subprocess
import sys

import pytest

SCRIPTS = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ROOT = os.path.dirname(SCRIPTS)
sys.path.insert(0, SCRIPTS)
from rtmsweep import spec as spec_module  # noqa: E402

# Absolute paths of a development machine: home folders and the work area of its checkouts.
ABSOLUTE = re.compile(r"(?<![\w.~$-])/(?:work|root|home|Users)/")
# The folder the SPD scenes and the paper were kept in beside the checkout, named without ../.
BESIDE = re.compile(r"(?<![\w/.-])shared/")
# A path that climbs out of its folder: what follows the ../ must be something the repository has.
CLIMBING = re.compile(r"(?<![\w.~$}/-])((?:\.\./)+)([\w][\w+-]*(?:\.[\w+-]+)*)")
# Texts that look like such paths and are none: the scene reader's test that a name with a path in
# it is refused, and the mesh test's scene that names a mesh one folder up in its own temporary tree.
NOT_PATHS = {("model/scene/native_test.cpp", "../x"), ("model/scene/mesh_test.cpp", "../tri.obj")}
# This file spells out what it looks for.
SELF = os.path.relpath(os.path.abspath(__file__), ROOT)


def git(*args, **kwargs):
    return subprocess.run(["git", "-C", ROOT, *args], capture_output=True, timeout=60, **kwargs)


@pytest.fixture(scope="module")
def tracked():
    r = git("ls-files", "-z")
    if r.returncode != 0:
        pytest.skip(f"{ROOT} is not a git checkout: {r.stderr.decode(errors='replace').strip()}")
    return [f for f in r.stdout.decode().split("\0") if f]


def names_in(files):
    """Every file and folder of the repository, as paths relative to its root."""
    names = {"."}
    for f in files:
        while f:
            names.add(f)
            f = os.path.dirname(f)
    return names


def outside_paths(path, text, names, folders):
    """(line number, what) of every outside path in one file's text."""
    found = []
    for n, line in enumerate(text.splitlines(), 1):
        for pattern in (ABSOLUTE, BESIDE):
            found += [(n, m.group(0)) for m in pattern.finditer(line)]
        for m in CLIMBING.finditer(line):
            if (path, m.group(0)) in NOT_PATHS:
                continue
            # Fine when it leads somewhere in the repository from some folder of it (a spec's
            # scene_dir is relative to the spec, a doc may quote it).
            if not any(os.path.normpath(os.path.join(d, m.group(0))) in names for d in folders):
                found.append((n, m.group(0)))
    return found


def test_no_tracked_file_names_a_path_outside_the_checkout(tracked):
    names = names_in(tracked)
    folders = sorted(n for n in names if n == "." or n not in tracked)
    problems = []
    for path in tracked:
        full = os.path.join(ROOT, path)
        if path == SELF or not os.path.isfile(full) or os.path.islink(full):
            continue
        with open(full, "rb") as f:
            data = f.read()
        if b"\0" in data:
            continue  # images and other binary files
        text = data.decode("utf-8", errors="replace")
        problems += [f"{path}:{n}: {what}" for n, what in outside_paths(path, text, names, folders)]
    assert not problems, "paths outside the checkout:\n" + "\n".join(problems)


def test_the_outside_path_patterns_find_what_they_are_for():
    names = names_in(["scenes/spd-corpus/balls-4.nff", "scripts/sweep-examples/tiny.yaml"])
    folders = [".", "scenes", "scenes/spd-corpus", "scripts", "scripts/sweep-examples"]
    text = ("scene_dir: ../../scenes/spd-corpus\n"         # from a spec's folder: fine
            "see ../spd-corpus/README.md\n"                # from scenes/spd (a placeholder file name): fine
            "scene_dir: ../../../shared/scenes/spd\n"      # beside the checkout
            "the paper, shared/seed/paper-en.md\n"
            "rtm: ../study-bin/rtm render x.nff\n"
            "SPD=/work/shared/scenes/spd; cd /root/x; ls /home/me\n"
            "not paths: a/../b, $HOME/../x, 1..4, ~/../x\n")
    found = outside_paths("page.md", text, names, folders)
    assert found == [(3, "../../../shared"), (4, "shared/"), (5, "../study-bin"), (6, "/work/"), (6, "/root/"),
                     (6, "/home/")], found


@pytest.fixture(scope="module")
def clean_copy(tmp_path_factory, tracked):
    """HEAD as a fresh clone has it: the committed files only, no build, nothing beside them."""
    copy = tmp_path_factory.mktemp("clean") / "rtm"
    copy.mkdir()
    archive = git("archive", "--format=tar", "HEAD")
    assert archive.returncode == 0, archive.stderr
    subprocess.run(["tar", "-x", "-C", copy], input=archive.stdout, check=True, timeout=60)
    return copy


def examples(root):
    folder = os.path.join(root, "scripts", "sweep-examples")
    return sorted(f for f in os.listdir(folder) if f.endswith(".yaml"))


@pytest.mark.parametrize("example", examples(ROOT))
def test_every_sweep_example_checks_on_a_clean_checkout(clean_copy, example):
    assert example in examples(clean_copy), f"{example} is not committed"
    spec = os.path.join("scripts", "sweep-examples", example)
    environment = {k: v for k, v in os.environ.items() if k not in ("RTM_BINARY", "RTM_BUILD_DIR")}
    r = subprocess.run([os.path.join(clean_copy, "scripts", "sweep"), spec, "--check"], cwd=clean_copy,
                       capture_output=True, text=True, stdin=subprocess.DEVNULL, timeout=60,
                       env=dict(environment, PYTHONDONTWRITEBYTECODE="1"))
    assert r.returncode == 0, r.stdout + r.stderr
    assert "every file the spec names is here" in r.stdout, r.stdout
    # ... and every one inside the copy, none found elsewhere by an absolute path.
    loaded = spec_module.load(os.path.join(clean_copy, spec))
    for scene in loaded.scenes + ([loaded.config] if loaded.config else []):
        assert os.path.commonpath([scene, str(clean_copy)]) == str(clean_copy), scene
