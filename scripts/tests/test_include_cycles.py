"""The folders of model/ include one another one way only (scripts/include-cycles): the model's own
tree has no cycle, and a tree that has one is reported with the file that closes it."""

import os
import subprocess

SCRIPTS = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CHECK = os.path.join(SCRIPTS, "include-cycles")


def run(*args):
    return subprocess.run([CHECK, *args], capture_output=True, text=True)


def test_the_model_has_no_folder_cycle():
    r = run()
    assert r.returncode == 0, r.stdout + r.stderr
    assert r.stdout == ""


def test_a_cycle_is_reported_with_the_file_that_closes_it(tmp_path):
    for folder, text in {"a": '#include "b/x.h"\n', "b": '#include "c/y.h"\n', "c": '#include "a/z.h"\n',
                         "d": '#include "a/z.h"\n'}.items():
        (tmp_path / folder).mkdir()
        (tmp_path / folder / "f.h").write_text(text)
    r = run("--root", str(tmp_path))
    assert r.returncode == 1, r.stdout + r.stderr
    assert r.stdout == ("include-cycles: the folders a, b, c include one another: a -> b (" +
                        os.path.join(tmp_path.name, "a", "f.h") + "); b -> c (" +
                        os.path.join(tmp_path.name, "b", "f.h") + "); c -> a (" +
                        os.path.join(tmp_path.name, "c", "f.h") + ")\n")


def test_a_test_that_includes_a_layer_above_closes_a_cycle(tmp_path):
    for folder, text in {"a": '#include "b/x.h"\n', "b": ""}.items():
        (tmp_path / folder).mkdir()
        (tmp_path / folder / "f.h").write_text(text)
    (tmp_path / "b" / "f_test.cpp").write_text('#include "a/f.h"\n')
    r = run("--root", str(tmp_path))
    assert r.returncode == 1, r.stdout + r.stderr
    assert r.stdout == ("include-cycles: the folders a, b include one another: a -> b (" +
                        os.path.join(tmp_path.name, "a", "f.h") + "); b -> a (" +
                        os.path.join(tmp_path.name, "b", "f_test.cpp") + ")\n")
