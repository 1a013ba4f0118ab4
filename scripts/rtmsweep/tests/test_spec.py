"""Unit tests of the spec: parsing, validation, variants, the expansion into jobs and run ids."""

import hashlib
import json
import os
import random

import pytest
import yaml

from rtmsweep import spec, sweep

KEYS = {"loop_credits", "broadcast", "ray_generation", "search_fifo_depth", "gather"}


def parse(text, config_keys=KEYS, base="/specs"):
    return spec.parse(yaml.safe_load(text), base, config_keys, default_name="test")


def test_the_product_varies_the_pe_count_fastest():
    s = parse("scenes: [a.nff, b.nff]\nsizes: [16x16, 8]\npes: [1, 2, 4]\nset: {loop_credits: [0, 1]}\n")
    jobs = s.jobs()
    assert len(jobs) == 2 * 2 * 2 * 3
    assert [j["pes"] for j in jobs[:6]] == [1, 2, 4, 1, 2, 4]
    assert [j["set"]["loop_credits"] for j in jobs[:6]] == ["0"] * 3 + ["1"] * 3
    assert jobs[0]["scene"] == "/specs/a.nff" and jobs[-1]["scene"] == "/specs/b.nff"
    assert {j["size"] for j in jobs} == {"16x16", "8x8"}
    assert jobs[0]["id"].startswith("a-16x16-p1-")
    assert len({j["id"] for j in jobs}) == len(jobs)
    assert s.set_keys == ["loop_credits"]


def test_omitted_axes_are_not_passed_on():
    job = parse("scenes: a.nff\n").jobs()[0]
    assert set(job) == {"id", "scene", "set", "set_keys", "images"}
    assert job["id"].startswith("a-") and job["set"] == {} and job["images"] is True


def test_values_become_what_rtm_reads():
    job = parse("scenes: [a.nff]\nset: {broadcast: [yes], loop_credits: [2]}\ntiming: clocked\n").jobs()[0]
    assert job["set"] == {"broadcast": "true", "loop_credits": "2"}
    assert job["timing"] == "clocked"


def test_run_ids_do_not_depend_on_the_order_of_the_lists():
    text = "scenes: [a.nff, b.nff]\npes: [1, 2, 8]\npartition: [scanlines, blocks]\nset: {loop_credits: [0, 1, 2]}\n"
    ids = {j["id"] for j in parse(text).jobs()}
    rng = random.Random(7)
    for _ in range(5):
        lists = {"scenes": ["a.nff", "b.nff"], "pes": [1, 2, 8], "partition": ["scanlines", "blocks"],
                 "loop_credits": [0, 1, 2]}
        for v in lists.values():
            rng.shuffle(v)
        shuffled = (f"scenes: {lists['scenes']}\npes: {lists['pes']}\npartition: {lists['partition']}\n"
                    f"set: {{loop_credits: {lists['loop_credits']}}}\n").replace("'", "")
        assert {j["id"] for j in parse(shuffled).jobs()} == ids


def test_a_value_listed_twice_is_one_run():
    assert len(parse("scenes: [a.nff, a.nff]\npes: [1, 1, 2]\n").jobs()) == 2


def test_paths_are_relative_to_the_spec_folder(tmp_path, monkeypatch):
    monkeypatch.setenv("SWEEP_TEST_SCENES", "/elsewhere")
    s = parse("scene_dir: ../scenes\nscenes: [x.nff, $SWEEP_TEST_SCENES/y.nff]\nconfig: m.yaml\n")
    assert s.scenes == ["/scenes/x.nff", "/elsewhere/y.nff"]
    assert s.config == "/specs/m.yaml"
    f = tmp_path / "named-after-me.yaml"
    f.write_text("scenes: [s.nff]\n")
    loaded = spec.load(str(f))
    assert loaded.name == "named-after-me" and loaded.scenes == [str(tmp_path / "s.nff")]


def test_variants_are_one_more_axis_with_their_own_settings():
    s = parse("scenes: [a.nff]\npes: [1, 2]\npartition: scanlines\nset: {loop_credits: [0]}\n"
              "variants:\n  paper: {}\n  improved: {ray_generation: pe, broadcast: true, partition: pixels}\n")
    jobs = s.jobs()
    assert s.set_keys == ["variant", "loop_credits"]
    assert [(j["variant"], j["pes"]) for j in jobs] == [("paper", 1), ("paper", 2), ("improved", 1), ("improved", 2)]
    paper, improved = jobs[0], jobs[2]
    assert paper["set"] == {"loop_credits": "0"} and paper["partition"] == "scanlines"
    assert improved["set"] == {"ray_generation": "pe", "broadcast": "true", "loop_credits": "0"}
    assert improved["partition"] == "pixels"  # the variant's value of a top-level axis wins
    assert all(j["set_keys"] == ["variant", "loop_credits"] for j in jobs)


def test_a_preset_is_passed_on_top_level_or_per_variant_and_gets_a_column():
    s = parse("scenes: [a.nff]\npes: [1]\npreset: paper\nset: {loop_credits: [0]}\n"
              "variants:\n  paper: {}\n  improved: {preset: default, broadcast: true}\n")
    paper, improved = s.jobs()
    assert s.presets == ["paper", "default"]
    assert s.set_keys == ["variant", "preset", "loop_credits"]
    assert paper["preset"] == "paper" and improved["preset"] == "default"  # the variant's own wins
    assert improved["set"] == {"broadcast": "true", "loop_credits": "0"}
    only_variant = parse("scenes: [a.nff]\nvariants:\n  paper: {preset: paper}\n  improved: {broadcast: true}\n")
    paper, improved = only_variant.jobs()
    assert only_variant.set_keys == ["variant", "preset"]
    assert paper["preset"] == "paper" and "preset" not in improved  # rtm's default; the CSV shows what it used
    top = parse("scenes: [a.nff]\npreset: paper\n")
    assert top.set_keys == ["preset"] and top.jobs()[0]["preset"] == "paper"


def test_a_preset_changes_the_run_id_and_no_preset_keeps_the_old_one():
    plain = parse("scenes: [a.nff]\n").jobs()[0]
    paper = parse("scenes: [a.nff]\npreset: paper\n").jobs()[0]
    assert plain["id"] != paper["id"]
    assert "preset" not in plain and parse("scenes: [a.nff]\n").set_keys == []


@pytest.mark.parametrize("text, message", [
    ("scenes: [a.nff]\npreset: [paper]\n", "preset: ['paper'] is not a preset name"),
    ("scenes: [a.nff]\nvariants: {x: {preset: 'a b'}}\n", "variants: x: preset: 'a b' is not a preset name"),
    ("scenes: [a.nff]\nset: {preset: [paper]}\n", "set: preset is not a key"),
    ("scenes: [a.nff]\npe: [1, 2]\n", "unknown key(s) pe"),
    ("pes: [1]\n", "scenes: at least one scene file is required"),
    ("scenes: [a.nff]\nsizes: [32by32]\n", "not WxH"),
    ("scenes: [a.nff]\nsizes: [4x0]\n", "not WxH"),
    ("scenes: [a.nff]\npes: [0]\n", "pes: 0 is not a positive integer"),
    ("scenes: [a.nff]\npes: [true]\n", "pes: True is not a positive integer"),
    ("scenes: [a.nff]\npes: []\n", "pes: an empty list"),
    ("scenes: [a.nff]\npartition: [[scanlines]]\n", "partition: values must be scalars"),
    ("scenes: [a.nff]\nset: {search_fifo_dept: [4]}\n", "search_fifo_dept: unknown machine configuration key"),
    ("scenes: [a.nff]\nset: {search_units: [2]}\n", "set: search_units is a top-level key"),
    ("scenes: [a.nff]\nset: [loop_credits]\n", "set: expected a mapping"),
    ("scenes: [a.nff]\nvariants: [paper]\n", "variants: expected a mapping"),
    ("scenes: [a.nff]\nvariants: {'a b': {}}\n", "variants: 'a b': use letters"),
    ("scenes: [a.nff]\nvariants: {x: {pes: 4}}\n", "variants: x: pes is also a sweep axis"),
    ("scenes: [a.nff]\nset: {loop_credits: [0]}\nvariants: {x: {loop_credits: 1}}\n",
     "variants: x: loop_credits is also a sweep axis"),
    ("scenes: [a.nff]\nvariants: {x: {nonsense: 1}}\n", "variants: x: nonsense: unknown machine configuration key"),
    ("scenes: [a.nff]\ntimeout: 0\n", "timeout: 0 is not a positive number"),
    ("scenes: [a.nff]\nimages: maybe\n", "images: 'maybe' is not true or false"),
    ("name: 'my sweep'\nscenes: [a.nff]\n", "name 'my sweep': use letters"),
    ("[1, 2]\n", "expected a mapping of keys"),
])
def test_a_bad_spec_says_what_is_wrong(text, message):
    with pytest.raises(spec.SpecError) as e:
        parse(text)
    assert message in str(e.value)


def test_without_the_config_keys_any_set_key_is_taken():
    assert parse("scenes: [a.nff]\nset: {whatever: [1]}\n", config_keys=None).jobs()[0]["set"] == {"whatever": "1"}


def test_a_missing_or_broken_file_is_a_spec_error(tmp_path):
    with pytest.raises(spec.SpecError, match="cannot read"):
        spec.load(str(tmp_path / "none.yaml"))
    (tmp_path / "bad.yaml").write_text("scenes: [a\n")
    with pytest.raises(spec.SpecError, match="not valid YAML"):
        spec.load(str(tmp_path / "bad.yaml"))


# A spec's jobs as the sweep tooling gave them before it was a package: the same run ids and the
# same jobs.tsv, so sweeps started then resume now.
PINNED = """name: pin
scenes: [/scenes/a.nff, /scenes/b-2.yaml]
sizes: [16x16, 8]
pes: [1, 4]
partition: [scanlines]
set:
  loop_credits: [0, 4]
  broadcast: [true]
variants:
  paper: {}
  improved: {ray_generation: pe, partition: pixels}
config: /configs/base.yaml
timeout: 30
images: false
"""


def test_run_ids_and_jobs_are_those_of_earlier_sweeps():
    jobs = parse(PINNED).jobs()
    assert len(jobs) == 32
    assert [j["id"] for j in jobs[:4]] == ["a-16x16-p1-b1d66a84", "a-16x16-p4-bfaa1b03", "a-16x16-p1-89745e1d",
                                           "a-16x16-p4-a8c8e694"]
    assert jobs[-1]["id"] == "b-2-8x8-p4-905c427d"
    assert json.dumps(jobs[0], sort_keys=True) == (
        '{"config": "/configs/base.yaml", "id": "a-16x16-p1-b1d66a84", "images": false, "partition": "scanlines", '
        '"pes": 1, "scene": "/scenes/a.nff", "set": {"broadcast": "true", "loop_credits": "0"}, '
        '"set_keys": ["variant", "loop_credits", "broadcast"], "size": "16x16", "timeout": 30, "variant": "paper"}')
    assert hashlib.sha1(sweep.jobs_tsv(jobs).encode()).hexdigest() == "399822078e7ae751a62feb708d80460f8319b6ad"


def test_two_copies_of_a_checkout_give_the_same_run_ids(tmp_path):
    """A scene and a config in the checkout count by their paths in it: the same spec in two
    copies of the tree (each with its own rtmsweep) gives the same ids, and a sweep started in one
    resumes in the other."""
    import shutil
    import subprocess
    import sys
    from support import SCRIPTS, SCENES

    ids = []
    for copy in (tmp_path / "one", tmp_path / "elsewhere" / "two"):
        shutil.copytree(os.path.join(SCRIPTS, "rtmsweep"), copy / "scripts" / "rtmsweep",
                        ignore=shutil.ignore_patterns("tests", "__pycache__"))
        (copy / "scenes").mkdir()
        shutil.copy(os.path.join(SCENES, "balls-1.nff"), copy / "scenes")
        (copy / "base.yaml").write_text("loop_credits: 4\n")
        (copy / "spec.yaml").write_text("scenes: [scenes/balls-1.nff]\nsizes: [16x16]\npes: [1, 2]\n"
                                        "config: base.yaml\nvariants: {a: {}, b: {broadcast: true}}\n")
        r = subprocess.run([sys.executable, "-B", "-c",
                            "import sys; sys.path.insert(0, sys.argv[1]); from rtmsweep import spec\n"
                            "print(' '.join(j['id'] for j in spec.load(sys.argv[2], {'broadcast'}).jobs()))",
                            str(copy / "scripts"), str(copy / "spec.yaml")], capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        ids.append(r.stdout.split())
    assert len(ids[0]) == 4 and len(set(ids[0])) == 4
    assert ids[0] == ids[1]
    # Outside the checkout a file counts by its absolute path: other folders, other ids.
    outside = [j["id"] for j in parse("scenes: [balls-1.nff]\nsizes: [16x16]\npes: [1, 2]\n", base=str(tmp_path)).jobs()]
    other = [j["id"] for j in parse("scenes: [balls-1.nff]\nsizes: [16x16]\npes: [1, 2]\n",
                                    base=str(tmp_path / "elsewhere")).jobs()]
    assert outside != other
