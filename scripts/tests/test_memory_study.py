"""scripts/memory-study on tiny cases: the layout's sections add up and only the frame's depend on
the PE count; the interconnect's rows keep the relations docs/machine.md's formulas give; the
ports study measures each machine against its own unlimited ports; the RAM study's accesses do not
depend on the capacity, its misses and costs do."""

import csv
import os
import subprocess

import pytest
import yaml

SCRIPTS = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ROOT = os.path.dirname(SCRIPTS)
STUDY = os.path.join(SCRIPTS, "memory-study")
SCENES = os.path.join(ROOT, "scenes", "spd")
SECTIONS = ["primitives_bytes", "voxel_data_bytes", "lights_and_materials_bytes", "primary_rays_bytes",
            "frame_buffer_bytes"]


def study(tmp_path, *args, rtm):
    return subprocess.run([STUDY, *args, "--work", str(tmp_path / "work"), "--out", str(tmp_path / "out"),
                           "--rtm", rtm, "--jobs", "2"], capture_output=True, text=True, stdin=subprocess.DEVNULL,
                          timeout=120)


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def test_the_layout_sections_add_up_and_only_the_frame_depends_on_the_pe_count(tmp_path, rtm):
    r = study(tmp_path, "layout", "--scene-dir", SCENES, "--scenes", "balls-1,tree-2", "--size", "16x16",
              "--pes", "2", rtm=rtm)
    assert r.returncode == 0, r.stdout + r.stderr
    two = rows(tmp_path / "out" / "layout.csv")
    assert sorted((x["scene"], x["preset"]) for x in two) == [
        ("balls-1", "default"), ("balls-1", "paper"), ("tree-2", "default"), ("tree-2", "paper")]
    for x in two:
        assert x["status"] == "ok", x
        b = {k: int(x[k]) for k in SECTIONS}
        assert sum(b.values()) == int(x["used_bytes"]) <= int(x["capacity_bytes"])
        assert b["primitives_bytes"] + b["voxel_data_bytes"] + b["lights_and_materials_bytes"] == int(x["scene_copy_bytes"])
        assert min(b.values()) > 0 and int(x["primitives"]) > 0
    # The frame's sections follow the pixels alone: the same for every scene and preset.
    assert len({(x["primary_rays_bytes"], x["frame_buffer_bytes"]) for x in two}) == 1
    table = (tmp_path / "out" / "layout.md").read_text()
    assert "| balls-1 |" in table and "| tree-2 |" in table and "16x16 on 2 PEs" in table

    r = study(tmp_path, "layout", "--scene-dir", SCENES, "--scenes", "balls-1", "--size", "16x16", "--pes", "1",
              rtm=rtm)
    assert r.returncode == 0, r.stdout + r.stderr
    one = {x["preset"]: x for x in rows(tmp_path / "out" / "layout.csv")}
    for x in two:
        if x["scene"] == "balls-1":
            y = one[x["preset"]]
            # One PE holds both halves of the 16 rows: twice the rays and frame buffer, the same scene copy.
            assert int(y["frame_buffer_bytes"]) == 2 * int(x["frame_buffer_bytes"])
            assert int(y["primary_rays_bytes"]) == 2 * int(x["primary_rays_bytes"])
            assert y["scene_copy_bytes"] == x["scene_copy_bytes"]


def test_an_unknown_scene_is_refused_by_name(tmp_path, rtm):
    r = study(tmp_path, "layout", "--scene-dir", SCENES, "--scenes", "no-such-scene", rtm=rtm)
    assert r.returncode == 1
    assert "memory-study: no scene no-such-scene in " + SCENES in r.stderr


def test_the_topologies_keep_the_relations_of_their_formulas(tmp_path, rtm):
    spec = {"name": "net", "scene_dir": SCENES, "scenes": ["balls-1.nff"], "sizes": ["16x16"], "pes": [1, 2, 4],
            "partition": ["scanlines"], "images": False,
            "variants": {"serial": {"link_topology": "serial"},
                         "serial-broadcast": {"link_topology": "serial", "broadcast": True},
                         "star-1": {"link_topology": "star", "host_ports": 1},
                         "star-2": {"link_topology": "star", "host_ports": 2},
                         "star-broadcast": {"link_topology": "star", "host_ports": 4, "broadcast": True},
                         "tree-broadcast": {"link_topology": "tree", "broadcast": True}}}
    (tmp_path / "net.yaml").write_text(yaml.safe_dump(spec))
    r = study(tmp_path, "interconnect", "--spec", str(tmp_path / "net.yaml"), rtm=rtm)
    assert r.returncode == 0, r.stdout + r.stderr
    got = rows(tmp_path / "out" / "interconnect.csv")
    assert len(got) == 18 and all(x["status"] == "ok" for x in got)
    at = {(x["variant"], int(x["pes"])): x for x in got}

    def f(variant, pes, key):
        return float(at[variant, pes][key])

    for x in got:
        phases = sum(float(x[k]) for k in ("host_preprocess_cycles", "transfer_cycles", "pe_cycles", "gather_cycles"))
        assert abs(phases - float(x["cycles"])) <= 1, x
        assert abs(float(x["efficiency"]) - float(x["speedup"]) / int(x["pes"])) < 1e-12
        assert int(x["busiest_link_busy_cycles"]) <= int(x["link_busy_cycles"])
    assert [f(v, 1, "efficiency") for v in spec["variants"]] == [1.0] * 6
    assert at["star-2", 4]["link_topology"] == "star" and at["star-2", 4]["host_ports"] == "2"
    # The serial link carries every copy in turn: more PEs, more transfer.
    assert f("serial", 1, "transfer_cycles") < f("serial", 2, "transfer_cycles") < f("serial", 4, "transfer_cycles")
    for pes in (2, 4):
        # A one-port star is the serial link; more ports are never slower, broadcast never slower than copies.
        assert f("star-1", pes, "transfer_cycles") == f("serial", pes, "transfer_cycles")
        assert f("star-2", pes, "transfer_cycles") <= f("star-1", pes, "transfer_cycles")
        assert f("star-broadcast", pes, "transfer_cycles") <= f("star-2", pes, "transfer_cycles")
        assert f("serial-broadcast", pes, "transfer_cycles") < f("serial", pes, "transfer_cycles")
        assert f("star-2", pes, "gather_cycles") < f("serial", pes, "gather_cycles")
    # docs/machine.md: the serial link sends N copies of the scene, the broadcast one; the rays alike.
    # So the difference is (N - 1) t(S), t(b) = link_latency_ns + b / link_bandwidth_mb_s.
    config = yaml.safe_load(subprocess.run([rtm, "config"], capture_output=True, text=True, check=True).stdout)
    scene_bytes = f("serial", 4, "scene_bytes")
    t_scene_ns = config["link_latency_ns"] + scene_bytes / config["link_bandwidth_mb_s"] * 1e3
    saved = f("serial", 4, "transfer_cycles") - f("serial-broadcast", 4, "transfer_cycles")
    assert abs(saved - 3 * t_scene_ns / config["clock_ns"]) <= 1
    assert (tmp_path / "out" / "interconnect-phases.png").stat().st_size > 10000
    assert (tmp_path / "out" / "interconnect-efficiency.png").stat().st_size > 10000
    assert "| star-2 |" in (tmp_path / "out" / "interconnect.md").read_text()


def run_spec(tmp_path, name, spec, rtm):
    (tmp_path / (name + ".yaml")).write_text(yaml.safe_dump(spec))
    r = study(tmp_path, name, "--spec", str(tmp_path / (name + ".yaml")), rtm=rtm)
    assert r.returncode == 0, r.stdout + r.stderr
    return rows(tmp_path / "out" / (name + ".csv"))


def test_the_ports_study_compares_each_machine_with_its_own_unlimited_ports(tmp_path, rtm):
    spec = {"name": "ports", "scene_dir": SCENES, "scenes": ["balls-1.nff"], "sizes": ["16x16"], "pes": [1],
            "search_units": [1, 4], "set": {"memory_ports": [0, 1], "memory_banks": [0], "memory_latency": [16]}, "images": False,
            "variants": {"default": {"preset": "default"}, "paper": {"preset": "paper"}}}
    got = run_spec(tmp_path, "ports", spec, rtm)
    assert len(got) == 8 and all(x["status"] == "ok" for x in got)
    at = {(x["variant"], int(x["search_units"]), int(x["memory_ports"])): x for x in got}
    for (variant, units, ports), x in at.items():
        unlimited = at[variant, units, 0]
        assert float(x["slowdown"]) == pytest.approx(int(x["cycles"]) / int(unlimited["cycles"]))
        if ports == 0:
            # No port limit and no banks: the ideal memory, which keeps no ports.
            assert float(x["busiest_port_utilisation"]) == 0 and int(x["search_stall_cycles"]) == 0
        else:
            # One slow port shared by the search units, the lanes and the rest: they wait for it.
            assert 0 < float(x["busiest_port_utilisation"]) <= 1
            assert int(x["search_stall_cycles"]) > 0 and float(x["slowdown"]) > 1
    table = (tmp_path / "out" / "ports.md").read_text()
    assert "balls-1, 16x16, 1 PEs, paper preset" in table and "| memory ports | search units 1 | search units 4 |" in table
    assert (tmp_path / "out" / "ports.png").stat().st_size > 10000


def test_the_ram_study_counts_one_access_per_primitive_tested_whatever_its_capacity(tmp_path, rtm):
    spec = {"name": "ram", "scene_dir": SCENES, "scenes": ["balls-1.nff"], "sizes": ["16x16"], "pes": [1],
            "set": {"mac_ram_primitives": [0, 1, 4]}, "images": False,
            "variants": {"default": {"preset": "default"}, "paper": {"preset": "paper"}}}
    got = run_spec(tmp_path, "ram", spec, rtm)
    assert len(got) == 6 and all(x["status"] == "ok" for x in got)
    at = {(x["variant"], int(x["mac_ram_primitives"])): x for x in got}
    for variant in ("default", "paper"):
        every, one, four = (at[variant, c] for c in (0, 1, 4))
        assert int(every["misses"]) == 0 and float(every["hit_rate"]) == 1 and float(every["slowdown"]) == 1
        assert {int(x["hits"]) + int(x["misses"]) for x in (every, one, four)} == {int(every["hits"])}
        # A smaller RAM misses more, loads more coefficient bytes and takes longer.
        assert int(one["misses"]) >= int(four["misses"]) > 0
        assert int(one["lane_bytes"]) >= int(four["lane_bytes"]) > int(every["lane_bytes"])
        assert float(one["slowdown"]) >= float(four["slowdown"]) > 1
    assert "| 4 |" in (tmp_path / "out" / "ram.md").read_text()
    assert (tmp_path / "out" / "ram.png").stat().st_size > 10000
