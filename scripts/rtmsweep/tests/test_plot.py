"""scripts/plot-sweep on a hand-written CSV: all eight plots and the table, failed rows left out."""

import re
import pytest

from support import PLOT_SWEEP, PLOTS, check_png, sh
from rtmsweep import columns, results

COLUMNS = columns.header([])


def sweep_row(scene, partition, pes, status):
    v = {"run_id": f"{scene}-{partition}-p{pes}", "status": status, "scene": scene, "width": 64, "height": 64,
         "pes": pes, "partition": partition, "search_units": 4, "timing": "fast", "precision": "fp32"}
    if status != "ok":
        v["error"] = "rtm: deadlock: the simulation stopped, with rays outstanding"
        return v
    work, host, transfer = 1e6 / pes * (1.1 if partition == "blocks" else 1.0), 2e5, 1e4 * pes
    v.update(cycles=int(host + transfer + work + 5000), host_preprocess_cycles=int(host),
             transfer_cycles=int(transfer), pe_cycles=int(work), gather_cycles=5000,
             load_imbalance=1.0 + 0.02 * pes, pe_util_credit_stall=0.3, bottleneck="mac",
             energy_j=1e-3 * (1 + 0.01 * pes), frames_per_s_per_mm2=50.0 / (1 + 0.1 * pes))
    for part in ("front_buffer", "search", "mac", "root", "shading", "local_memory", "link", "leakage"):
        v[f"energy_{part}_j"] = 1e-4 * (1 + 0.01 * pes)
    for stage in ("front_buffer", "search", "mac", "root", "shading"):
        v[f"util_{stage}"] = 0.5 / (1 + 0.1 * pes)
        v[f"pe_util_{stage}"] = 0.6 / (1 + 0.05 * pes)
    return v


@pytest.fixture
def csv_rows():
    rows = [sweep_row("balls-4", "scanlines", p, "ok") for p in (1, 2, 4, 8)]
    rows += [sweep_row("balls-4", "blocks", p, "ok") for p in (1, 2, 4, 8)]
    rows += [sweep_row("rings-7", "scanlines", p, "ok") for p in (2, 4, 8)]  # no 1-PE run
    rows += [sweep_row("rings-7", "scanlines", 1, "deadlock"), sweep_row("rings-7", "blocks", 16, "failed")]
    return rows


def test_plot_sweep_writes_its_png_files_and_table(tmp_path, csv_rows):
    (tmp_path / "results.csv").write_text(results.format_rows(COLUMNS, csv_rows))
    r = sh(PLOT_SWEEP, tmp_path / "results.csv", tmp_path / "plots")
    assert r.returncode == 0, r.stdout + r.stderr
    ok = sum(row["status"] == "ok" for row in csv_rows)
    assert f"{ok} runs in 3 configurations (2 failed rows left out)" in r.stdout
    assert "relative to the smallest PE count" in r.stdout
    for p in PLOTS:
        check_png(tmp_path / "plots" / p)
        assert str(tmp_path / "plots" / p) in r.stdout
    # The scaling table: a header, a rule and one line per successful run, efficiency from the
    # configuration's first run (balls-4 scanlines on 2 PEs: 1,215,000 / (2 · 725,000) = 0.84).
    table = (tmp_path / "plots" / "scaling.md").read_text()
    assert table.count("\n") == 2 + ok
    assert "| balls-4 scanlines | 2 | 725,000 | 1.7 | 0.84 |" in table
    assert "| rings-7 scanlines | 2 |" in table and "| rings-7 scanlines | 1 |" not in table
    # The cost table: one line per successful run, then each scene's best.
    cost = (tmp_path / "plots" / "cost.md").read_text()
    assert cost.count("\n") == 2 + ok + 1 + 2 + 2
    # Eight equal parts of the energy: leakage an eighth, the first of the seven others a seventh.
    assert re.search(r"\| balls-4 scanlines \| 2 \|  \| 1,020 \|  \|  \| 41\.67 \|  \| 1[23] % \| front buffer 14 % \|",
                     cost), cost


def test_the_cost_table_has_a_line_per_run_and_each_scenes_best(tmp_path, csv_rows):
    for row in csv_rows:
        if row["status"] == "ok":
            row.update(area_mm2=2.0 * row["pes"], frames_per_j=1.0 / row["energy_j"])
    (tmp_path / "results.csv").write_text(results.format_rows(COLUMNS, csv_rows))
    page = tmp_path / "page.md"
    page.write_text("# P\n\nCommand: `x`\nOutput: y\n\n<!-- begin: written by scripts/plot-sweep scaling, do not edit -->\n"
                    "<!-- end: written by scripts/plot-sweep scaling -->\n")
    r = sh(PLOT_SWEEP, tmp_path / "results.csv", tmp_path / "plots", "--page", page)
    assert r.returncode == 0, r.stdout + r.stderr
    table = (tmp_path / "plots" / "cost.md").read_text()
    ok = sum(row["status"] == "ok" for row in csv_rows)
    # balls-4 scanlines on 2 PEs: 4 mm², 1.02 mJ, 50 / 1.2 = 41.67 frames/s/mm², so 166.7 frames/s.
    assert "| balls-4 scanlines | 2 | 4.000 | 1,020 |  | 166.7 | 41.67 | 980.4 | " in table
    # The most frames/s/mm² is the fewest PEs (50 / (1 + 0.1 p)); rings-7 has no 1-PE run.
    assert "| balls-4 | balls-4 blocks, 1 PE (45.45) | balls-4 blocks, 1 PE (990.1) |" in table
    assert "| rings-7 | rings-7 scanlines, 2 PEs (41.67) |" in table
    assert table.count("\n") == 2 + ok + 1 + 2 + 2
    assert table in page.read_text()


def test_no_cost_columns_no_cost_table(tmp_path, csv_rows):
    for row in csv_rows:
        row.pop("frames_per_s_per_mm2", None)
    (tmp_path / "results.csv").write_text(results.format_rows(COLUMNS, csv_rows))
    r = sh(PLOT_SWEEP, tmp_path / "results.csv", tmp_path / "plots", "--quiet")
    assert r.returncode == 0, r.stdout + r.stderr
    assert not (tmp_path / "plots" / "cost.md").exists()


def test_the_lines_are_named_by_the_settings_that_vary(tmp_path, csv_rows):
    from rtmsweep import plot
    head = columns.header(["variant", "loop_credits"])
    for row in csv_rows:
        row.update(variant="paper" if row["partition"] == "scanlines" else "improved", loop_credits=0)
    (tmp_path / "results.csv").write_text(results.format_rows(head, csv_rows))
    rows, ok, axes = plot.load(str(tmp_path / "results.csv"))
    assert len(rows) == 13 and len(ok) == 11
    assert axes == ["scene", "_size", "partition", "search_units", "timing", "precision", "variant", "loop_credits"]
    configs, varying = plot.configurations(ok, axes)
    assert varying == ["partition", "variant"]  # loop_credits is 0 throughout: not in the labels
    assert [(c.label, c.pes) for c in configs] == [("balls-4 blocks improved", [1, 2, 4, 8]),
                                                   ("balls-4 scanlines paper", [1, 2, 4, 8]),
                                                   ("rings-7 scanlines paper", [2, 4, 8])]
    _, speedup, efficiency = plot.speedup_of(configs[1])
    assert speedup[0] == 1.0 and round(efficiency[1], 2) == 0.84


def test_nothing_to_plot_is_an_error(tmp_path):
    (tmp_path / "failed.csv").write_text(results.format_rows(COLUMNS, [sweep_row("a", "blocks", 1, "failed")]))
    r = sh(PLOT_SWEEP, tmp_path / "failed.csv", tmp_path / "none")
    assert r.returncode != 0
    assert "no successful runs" in r.stderr
    assert not (tmp_path / "none").exists()
    (tmp_path / "other.csv").write_text("a,b\n1,2\n")
    r = sh(PLOT_SWEEP, tmp_path / "other.csv", tmp_path / "none")
    assert r.returncode != 0 and "no column 'status'" in r.stderr


def test_the_axes_are_the_columns_before_the_metrics():
    from rtmsweep import plot
    head = columns.header(["variant", "loop_credits"])
    assert [c for c in head if c not in plot.KNOWN] == columns.CONFIG_COLUMNS[:3] + columns.CONFIG_COLUMNS[4:] + [
        "variant", "loop_credits"]


@pytest.mark.parametrize("fmt, magic", [("pdf", b"%PDF"), ("svg", b"<?xml")])
def test_the_plots_can_be_pdf_or_svg(tmp_path, csv_rows, fmt, magic):
    (tmp_path / "results.csv").write_text(results.format_rows(COLUMNS, csv_rows))
    r = sh(PLOT_SWEEP, tmp_path / "results.csv", tmp_path / "plots", "--format", fmt, "--quiet")
    assert r.returncode == 0, r.stdout + r.stderr
    written = sorted(p.name for p in (tmp_path / "plots").iterdir())
    assert written == sorted([p.replace(".png", "." + fmt) for p in PLOTS] + ["scaling.md", "cost.md"])
    for p in PLOTS:
        data = (tmp_path / "plots" / p.replace(".png", "." + fmt)).read_bytes()
        assert data.startswith(magic) and len(data) > 5000, p
    r = sh(PLOT_SWEEP, tmp_path / "results.csv", tmp_path / "gif", "--format", "gif")
    assert r.returncode == 2 and "invalid choice: 'gif'" in r.stderr


def test_a_scene_has_one_colour_and_a_setting_one_line_style_in_every_panel(tmp_path, monkeypatch, csv_rows):
    """balls-4 and rings-7 by scanlines and blocks: the colour says the scene, the marker and line
    style the partitioning, in the per-scene panels of cycles.png as in the per-stage panels of
    utilisation.png."""
    from rtmsweep import plot
    import matplotlib.colors

    csv_rows += [sweep_row("rings-7", "blocks", p, "ok") for p in (2, 4)]
    (tmp_path / "results.csv").write_text(results.format_rows(COLUMNS, csv_rows))
    _, ok, axes = plot.load(str(tmp_path / "results.csv"))
    configs, varying = plot.configurations(ok, axes)
    assert varying == ["partition"]
    assert {c.label for c in configs} == {"balls-4 blocks", "balls-4 scanlines", "rings-7 blocks", "rings-7 scanlines"}

    # What is drawn: every data line of every panel of both plots.
    figures = []
    monkeypatch.setattr(plot, "save", lambda fig, path, written, layout=True: figures.append(fig))
    out = plot.Output(str(tmp_path), "png")
    plot.plot_cycles(configs, ["balls-4", "rings-7"], out, [])
    plot.plot_utilisation(configs, out, [], "util_", "Stage utilisation over the frame", "utilisation")
    colours, styles = {}, {}
    drawn = 0
    for fig in figures:
        for ax in fig.axes:
            for line in ax.get_lines():
                if line.get_label().startswith("_"):  # the ideal-scaling lines
                    continue
                scene, partition = line.get_label().split()
                colours.setdefault(scene, []).append(matplotlib.colors.to_rgb(line.get_color()))
                styles.setdefault(partition, []).append((line.get_marker(), line.get_linestyle()))
                drawn += 1
    assert drawn == 4 + 5 * 4  # cycles: two panels of two lines; utilisation: five stages of four
    assert all(len(set(v)) == 1 for v in list(colours.values()) + list(styles.values()))
    assert colours["balls-4"][0] != colours["rings-7"][0]
    assert styles["blocks"][0][0] != styles["scanlines"][0][0] and styles["blocks"][0][1] != styles["scanlines"][0][1]

    # The legend: the scenes by colour (in utilisation.png, where both are in a panel), the
    # partitionings by line style.
    legend = [t.get_text() for t in figures[1].axes[0].get_legend().get_texts()]
    assert legend == ["balls-4", "rings-7", "blocks", "scanlines"]


def test_a_variant_names_its_preset(tmp_path, csv_rows):
    """A variant with its own preset: the labels and the line styles are the variant's alone."""
    from rtmsweep import plot
    head = columns.header(["variant", "preset"])
    for row in csv_rows:
        paper = row["partition"] == "scanlines"
        row.update(variant="paper" if paper else "improved", preset="paper" if paper else "default")
    (tmp_path / "results.csv").write_text(results.format_rows(head, csv_rows))
    _, ok, axes = plot.load(str(tmp_path / "results.csv"))
    configs, varying = plot.configurations(ok, axes)
    assert varying == ["partition", "variant"]
    assert [c.label for c in configs] == ["balls-4 blocks improved", "balls-4 scanlines paper", "rings-7 scanlines paper"]
    assert configs[1].style() == dict(configs[2].style(), color=configs[1].colour)
