"""Each study script on a tiny case, so a study page's command still runs and writes its page:
error-study (spd, remedies, position), error-vs-runtime, compare-povray, bench-reference, the
leave-out table and mesh-corpus. scripts/memory-study, scripts/bench-model and scripts/sweep --page have tests of
their own (test_memory_study.py, test_bench_model.py, rtmsweep/tests)."""

import csv
import os
import shutil
import subprocess

import pytest
import yaml

SCRIPTS = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ROOT = os.path.dirname(SCRIPTS)
SPD = os.path.join(ROOT, "scenes", "spd")


def run(*cmd, timeout=300, env=None):
    r = subprocess.run([*cmd], capture_output=True, text=True, stdin=subprocess.DEVNULL, timeout=timeout, cwd=ROOT,
                       env={**os.environ, **(env or {})})
    assert r.returncode == 0, f"{' '.join(cmd)}: exit {r.returncode}\n{r.stdout}\n{r.stderr}"
    return r


def page(tmp_path, who):
    """A study page with the part WHO writes, as docs/studies/ keeps them."""
    p = tmp_path / "page.md"
    p.write_text(f"# A study\n\nCommand: `{who}`\nOutput: x\n\n<!-- begin: written by {who}, do not edit -->\n"
                 f"<!-- end: written by {who} -->\n")
    return p


def stamped(p, rtm):
    text = p.read_text()
    version = subprocess.run([rtm, "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    assert f"- build: `{version}" in text, text
    assert "- written: " in text
    return text


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def tiny_spec(tmp_path, source, **changes):
    """SOURCE (a sweep example) on balls-1 at 16x16, with the scenes of this checkout."""
    with open(os.path.join(SCRIPTS, "sweep-examples", source)) as f:
        spec = yaml.safe_load(f)
    spec.update({"scene_dir": SPD, "scenes": ["balls-1.nff"], "sizes": ["16x16"], "pes": [1]}, **changes)
    p = tmp_path / source
    p.write_text(yaml.safe_dump(spec))
    return p


@pytest.mark.parametrize("study, source", [("spd", "error-causes-spd.yaml"), ("remedies", "error-remedies.yaml")])
def test_error_study_writes_its_rows_and_page(tmp_path, rtm, study, source):
    spec = tiny_spec(tmp_path, source)
    p = page(tmp_path, f"scripts/error-study {study}")
    run(os.path.join(SCRIPTS, "error-study"), study, "--spec", str(spec), "--out", str(tmp_path / "out"),
        "--work", str(tmp_path / "work"), "--rtm", rtm, "--jobs", "2", "--page", str(p))
    out = rows(tmp_path / "out" / f"{study}.csv")
    assert out and all(r["status"] == "ok" and r["scene"] == "balls-1" for r in out), out
    text = stamped(p, rtm)
    assert f"- runs: {len(out)}, " in text and "balls-1" in text


def test_error_study_position_moves_the_scene_without_moving_its_error(tmp_path, rtm):
    p = page(tmp_path, "scripts/error-study position")
    run(os.path.join(SCRIPTS, "error-study"), "position", "--scenes", "near-eye", "--size", "16x16",
        "--out", str(tmp_path / "out"), "--work", str(tmp_path / "work"), "--rtm", rtm, "--jobs", "2",
        "--page", str(p))
    out = rows(tmp_path / "out" / "scene-position.csv")
    assert len(out) == 7 * 2  # seven placements, two frames
    grid = [r for r in out if r["frame"] == "grid"]
    # The grid frame's whole point: wherever the scene is, the same primary hits as where it was written.
    assert all(int(r["primary_ids_differing"]) == 0 for r in grid), grid
    assert all(int(r["unknown"]) == 0 for r in out), out
    text = stamped(p, rtm)
    assert "| near-eye |" in text and "- runs: 14, " in text


def test_error_study_position_names_an_unknown_scene(tmp_path, rtm):
    r = subprocess.run([os.path.join(SCRIPTS, "error-study"), "position", "--scenes", "nope", "--rtm", rtm,
                        "--out", str(tmp_path / "out"), "--work", str(tmp_path / "work")],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 1 and "no scene nope" in r.stderr, r.stderr


def test_error_vs_runtime_writes_its_runs_plots_and_page(tmp_path, rtm):
    p = page(tmp_path, "scripts/error-vs-runtime")
    run(os.path.join(SCRIPTS, "error-vs-runtime"), "--quick", "--scenes", "balls-1", "--size", "16x16",
        "--build", os.path.dirname(rtm), "--out", str(tmp_path / "out"), "--page", str(p), timeout=600)
    out = rows(tmp_path / "out" / "runs.csv")
    assert {r["config"] for r in out} >= {"default", "paper fp32", "fp64"} and all(r["scene"] == "balls-1" for r in out)
    by = {r["config"]: r for r in out}
    assert all(float(r["energy_j"]) > 0 and float(r["area_mm2"]) > 0 for r in out)
    # fp64 elements are larger than fp32 ones: the whole PE in fp64 costs area, one unit in fp64 less.
    assert float(by["fp64"]["area_mm2"]) > float(by["shading fp64"]["area_mm2"]) > float(by["default"]["area_mm2"])
    for name in ("error-vs-cycles.png", "error-vs-wall.png", "error-vs-energy.png", "pareto.md"):
        assert (tmp_path / "out" / name).stat().st_size > 0
    text = stamped(p, rtm)
    assert "balls-1" in text and "default energy per frame, µJ" in text and "default area, mm²" in text
    assert "| fp64 |" in text.split("Simulator cost")[1]
    # --replot remakes the page from runs.csv and keeps the build the page records.
    (tmp_path / "out" / "pareto.md").unlink()
    run(os.path.join(SCRIPTS, "error-vs-runtime"), "--replot", "--out", str(tmp_path / "out"), "--page", str(p))
    assert (tmp_path / "out" / "pareto.md").stat().st_size > 0
    assert "default area, mm²" in stamped(p, rtm)


@pytest.fixture
def povray():
    if not shutil.which("povray"):
        pytest.skip("povray is not installed (scripts/setup installs it)")


def test_compare_povray_agrees_on_a_tiny_scene(tmp_path, rtm, povray):
    p = page(tmp_path, "scripts/compare-povray tiny")
    r = run(os.path.join(SCRIPTS, "compare-povray"), "--size", "16x16", "--dir", str(tmp_path / "out"),
            "--page", str(p), "--part", "tiny", "balls-1", env={"RTM_BUILD_DIR": os.path.dirname(rtm)})
    assert "balls-1" in (tmp_path / "out" / "table.md").read_text(), r.stdout
    assert "balls-1" in stamped(p, rtm)


def test_bench_reference_times_both_renderers(tmp_path, rtm, povray):
    p = page(tmp_path, "scripts/bench-reference")
    run(os.path.join(SCRIPTS, "bench-reference"), "--runs", "1", "--size", "16x16", "--threads", "1",
        "--dir", str(tmp_path / "out"), "--page", str(p), "balls-1", env={"RTM_BUILD_DIR": os.path.dirname(rtm)})
    tables = (tmp_path / "out" / "tables.md").read_text()
    assert "balls-1" in tables
    assert "balls-1" in stamped(p, rtm)


def test_leave_out_table_from_a_tiny_leave_out_sweep(tmp_path, rtm):
    spec = tiny_spec(tmp_path, "leave-out.yaml")
    run(os.path.join(SCRIPTS, "sweep"), str(spec), "--out", str(tmp_path / "sweeps" / "leave-out"), "--rtm", rtm, "--jobs", "2",
        "--no-plots")
    p = page(tmp_path, "scripts/leave-out-table")
    r = run(os.path.join(SCRIPTS, "leave-out-table"), str(tmp_path / "sweeps" / "leave-out"), "--page", str(p),
            "--rtm", rtm)
    assert "balls-1" in r.stdout
    assert "balls-1" in stamped(p, rtm)


def test_mesh_corpus_lists_what_does_not_render(tmp_path, rtm):
    """A folder of two mesh files, one good and one empty: one renders, the other is listed with
    rtm's message, and the page gets the table with its stamp."""
    models = tmp_path / "models"
    models.mkdir()
    shutil.copy(os.path.join(ROOT, "scenes", "meshes", "icosahedron.obj"), models)
    (models / "empty.obj").write_text("")
    p = page(tmp_path, "scripts/mesh-corpus")
    r = run(os.path.join(SCRIPTS, "mesh-corpus"), "--models", str(models), "--dir", str(tmp_path / "out"),
            "--page", str(p), os.path.dirname(rtm))
    assert "mesh-corpus: 1 of 2 render, 1 refused, 0 broken" in r.stdout
    text = stamped(p, rtm)
    assert "- runs: 2 files, " in text
    assert "**1 of 2 files render**; 1 are refused" in text
    assert "| `empty.obj` | 1 | " in text and "icosahedron" not in text
    assert (tmp_path / "out" / "table.md").read_text() in text
