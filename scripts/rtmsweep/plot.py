"""The plots of a sweep's results.csv (scripts/plot-sweep); failed runs are left out.

    plot-sweep RESULTS.csv OUTDIR [--format png|pdf|svg] [--quiet]

cycles.FMT          simulated frame cycles vs PE count, one panel per scene (log-log)
speedup.FMT         speedup and parallel efficiency vs PE count
utilisation.FMT     busy fraction of each PE stage over the frame vs PE count
pe_utilisation.FMT  the same over the PEs' working windows (when the CSV has it)
load_imbalance.FMT  longest PE working window / mean, per partitioning scheme
phases.FMT          the frame split into host pre-processing, transfer, PE work and gather
cost.FMT            energy per frame and frames per second per mm2 vs PE count (when the CSV has them)
energy.FMT          the frame's energy split into each unit's, the local memories', the link's and leakage
scaling.md          a table: cycles, speedup, parallel efficiency, phase shares, load imbalance
                    and bottleneck per configuration and PE count
cost.md             a table: area, energy per frame, frames/s, frames/s/mm2 and frames/J per
                    configuration and PE count, and each scene's best (when the CSV has them)

A "configuration" (one line) is a scene with every other setting except the PE count; labels
name only the settings that vary in the CSV (a variant alone, not also its preset). Its colour
stands for its scene and its marker and line style for its other settings (partitioning, variant,
...), the same in every panel of every plot. docs/sweeps.md ("Plots") has a caption per plot.
"""

import argparse
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

from . import columns, page  # noqa: E402

# Columns that are not configuration axes; anything else in front of the metrics (the spec's
# `set` keys, `variant`) is one.
KNOWN = {"run_id", "status", "error", "pes"} | set(columns.METRIC_COLUMNS)
STAGES = [("front_buffer", "front buffer"), ("search", "object search (3DDDA)"), ("mac", "MAC"),
          ("root", "root unit"), ("shading", "shading")]
PHASES = [("host_preprocess_cycles", "host pre-processing", "#8c8c8c"),
          ("transfer_cycles", "transfer", "#e6a23c"),
          ("pe_cycles", "PE work", "#4c72b0"),
          ("gather_cycles", "gather", "#55a868")]
COLOURS = plt.get_cmap("tab10").colors
MARKERS = "osD^v<>ph*"
LINE_STYLES = ["-", "--", "-.", (0, (6, 2, 1, 2, 1, 2))]  # not ":", the ideal-scaling lines'
FORMATS = ("png", "pdf", "svg")


def num(v):
    try:
        x = float(v)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


class Config:
    """One line of the plots: the ok rows of one configuration, sorted by PE count."""

    def __init__(self, key, settings, rows, scene_index, settings_index):
        self.key, self.scene, self.settings = key, key[0], settings
        self.label = " ".join([self.scene] + ([settings] if settings else []))
        self.rows = sorted(rows, key=lambda r: r["_pes"])
        self.pes = [r["_pes"] for r in self.rows]
        self.colour = COLOURS[scene_index % len(COLOURS)]
        self.marker = MARKERS[settings_index % len(MARKERS)]
        self.linestyle = LINE_STYLES[settings_index % len(LINE_STYLES)]

    def values(self, column):
        """(pes, values) where the column has a number."""
        pts = [(r["_pes"], num(r.get(column))) for r in self.rows]
        pts = [(p, v) for p, v in pts if v is not None]
        return [p for p, _ in pts], [v for _, v in pts]

    def style(self):
        return dict(color=self.colour, marker=self.marker, linestyle=self.linestyle, markersize=4, linewidth=1.4)


def load(path):
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        header = reader.fieldnames or []
        rows = list(reader)
    for required in ("status", "scene", "pes", "cycles"):
        if required not in header:
            sys.exit(f"plot-sweep: {path}: no column {required!r} (is it a scripts/sweep results.csv?)")
    ok = []
    for r in rows:
        if r.get("status") != "ok":
            continue
        pes, cycles = num(r.get("pes")), num(r.get("cycles"))
        if pes is None or cycles is None:
            continue
        r["_pes"] = int(pes)
        r["_size"] = f"{r.get('width', '')}x{r.get('height', '')}"
        ok.append(r)
    axes = ["scene", "_size"] + [c for c in header if c not in KNOWN and c not in ("scene", "width", "height")]
    return rows, ok, axes


def configurations(ok, axes):
    varying = [a for a in axes[1:] if len({r.get(a, "") for r in ok}) > 1]
    if "variant" in varying and "preset" in varying and \
            len({(r.get("variant"), r.get("preset")) for r in ok}) == len({r.get("variant") for r in ok}):
        varying.remove("preset")  # each variant has one preset: the variant names it
    groups = {}
    for r in ok:
        key = tuple(r.get(a, "") for a in axes)
        groups.setdefault(key, []).append(r)
    order = lambda k: [str(x) for x in k]
    settings_of = lambda values: tuple(values[a] for a in varying)
    all_values = [dict(zip(axes, k)) for k in groups]
    all_settings = sorted({settings_of(v) for v in all_values}, key=order)
    scenes = sorted({v["scene"] for v in all_values})
    configs = []
    for key in sorted(groups, key=order):
        values = dict(zip(axes, key))
        parts = []
        for a in varying:
            v = values[a]
            if a in ("partition", "timing", "precision", "_size", "variant"):
                parts.append(str(v))
            elif a == "search_units":
                parts.append(f"{v} search units")
            else:
                parts.append(f"{a}={v}")
        configs.append(Config(key, " ".join(parts), groups[key], scenes.index(values["scene"]),
                              all_settings.index(settings_of(values))))
    return configs, varying


def grid(n, width=5.2, height=3.9, max_cols=3):
    cols = min(max_cols, n)
    rows = math.ceil(n / cols)
    fig, axs = plt.subplots(rows, cols, figsize=(width * cols, height * rows + 0.6), squeeze=False)
    flat = [a for row in axs for a in row]
    for a in flat[n:]:
        a.set_visible(False)
    return fig, flat[:n]


def pes_axis(ax, configs, log_y=False):
    ax.set_xscale("log", base=2)
    if log_y:
        ax.set_yscale("log")
    ticks = sorted({p for c in configs for p in c.pes})
    if ticks:
        ax.set_xticks(ticks)
        ax.set_xticklabels([str(t) for t in ticks], fontsize=8)
        ax.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
    ax.set_xlabel("PEs")
    ax.grid(True, which="major", alpha=0.3)


def legend(ax, configs, extra=()):
    """The scenes by colour (when there are several) and the other settings by marker and line
    style, then the extra handles."""
    scenes, settings = {}, {}
    for c in configs:
        scenes.setdefault(c.scene, Line2D([], [], color=c.colour, linewidth=2.5, label=c.scene))
        if c.settings:
            settings.setdefault(c.settings, Line2D([], [], color="0.3", marker=c.marker, linestyle=c.linestyle,
                                                   markersize=4, linewidth=1.4, label=c.settings))
    handles = (list(scenes.values()) if len(scenes) > 1 else []) + list(settings.values()) + list(extra)
    if handles:
        ax.legend(handles=handles, fontsize="small" if len(handles) <= 8 else "x-small", loc="best")


def linear(label="linear scaling"):
    return Line2D([], [], color="black", linestyle=":", linewidth=1, label=label)


class Output:
    """Where the plots go: a folder, and the file format (FORMATS)."""

    def __init__(self, folder, fmt):
        self.folder, self.fmt = folder, fmt

    def file(self, name):
        return f"{name}.{self.fmt}"

    def path(self, name):
        return os.path.join(self.folder, self.file(name))


def save(fig, path, written, layout=True):
    if layout:
        fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    written.append(path)


def plot_cycles(configs, scenes, out, written):
    fig, axs = grid(len(scenes))
    for ax, scene in zip(axs, scenes):
        mine = [c for c in configs if c.scene == scene]
        for c in mine:
            p, y = c.values("cycles")
            ax.plot(p, y, label=c.label, **c.style())
            if len(p) > 1:  # ideal: the first point's cycles divided by the PE ratio
                ax.plot(p, [y[0] * p[0] / q for q in p], color=c.colour, linestyle=":", linewidth=1)
        pes_axis(ax, mine, log_y=True)
        ax.set_ylabel("cycles (simulated frame)")
        ax.set_title(scene)
        legend(ax, mine, [linear()])
    fig.suptitle("Frame cycles")
    save(fig, out.path("cycles"), written)


def frame_column(c):
    """The column a frame's time is in: frame_cycles (with several frames, the steady state's)
    where every run has it, else cycles (a results.csv from before it)."""
    return "frame_cycles" if len(c.values("frame_cycles")[0]) == len(c.rows) else "cycles"


def speedup_of(c):
    """PE counts, speedups and parallel efficiencies of a configuration's frames, relative to its
    first run (sorted by PE count: the 1-PE run when there is one)."""
    p, y = c.values(frame_column(c))
    speedup = [y[0] / v for v in y]
    return p, speedup, [s * p[0] / q for s, q in zip(speedup, p)]


def plot_speedup(configs, out, written, notes):
    fig, (ax_s, ax_e) = plt.subplots(1, 2, figsize=(12, 4.8))
    bases, all_speedups, without_one = [], [], []
    for c in configs:
        p, speedup, efficiency = speedup_of(c)
        if not p:
            continue
        p0 = p[0]
        bases.append(p0)
        all_speedups += speedup
        if p0 != 1:
            without_one.append(f"{c.label} (vs {p0} PEs)")
        ax_s.plot(p, speedup, label=c.label, **c.style())
        ax_e.plot(p, efficiency, label=c.label, **c.style())
    ticks = sorted({q for c in configs for q in c.pes})
    if ticks:
        for p0 in sorted(set(bases)):
            xs = [q for q in ticks if q >= p0]
            ax_s.plot(xs, [q / p0 for q in xs], color="black", linestyle=":", linewidth=1)
    pes_axis(ax_s, configs, log_y=True)
    if all_speedups:
        lo = min(all_speedups + [1.0])
        hi = max(all_speedups + [q / p0 for q in ticks for p0 in bases])
        ax_s.set_yticks([2.0 ** k for k in range(math.floor(math.log2(lo)), math.ceil(math.log2(hi)) + 1)])
        ax_s.set_ylim(lo / 1.25, hi * 1.25)
    ax_s.yaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
    ax_s.yaxis.set_minor_locator(matplotlib.ticker.NullLocator())
    pes_axis(ax_e, configs)
    ax_s.set_ylabel("speedup")
    ax_e.set_ylabel("parallel efficiency")
    ax_e.axhline(1.0, color="black", linestyle=":", linewidth=1)
    ax_e.set_ylim(0, max(1.1, ax_e.get_ylim()[1]))
    ax_s.set_title("Speedup")
    ax_e.set_title("Parallel efficiency")
    legend(ax_s, configs, [linear()])
    if without_one:  # the caption says "relative to the 1-PE run": say where that is not so
        note = "no 1-PE run, relative to the smallest PE count: " + (
            ", ".join(without_one) if len(without_one) < len(bases) else "every configuration")
        notes.append(out.file("speedup") + ": " + note)
        fig.suptitle(note, fontsize="small")
    save(fig, out.path("speedup"), written)


def plot_utilisation(configs, out, written, prefix, title, name):
    columns = [(prefix + s, label) for s, label in STAGES]
    if prefix == "pe_util_":
        columns.append(("pe_util_credit_stall", "credit stall (front buffer waiting)"))
    if not any(c.values(col)[0] for c in configs for col, _ in columns):
        return False
    fig, axs = grid(len(columns), width=4.6, height=3.6)
    for ax, (column, label) in zip(axs, columns):
        for c in configs:
            p, y = c.values(column)
            ax.plot(p, y, label=c.label, **c.style())
        pes_axis(ax, configs)
        ax.set_ylim(0, 1.05)
        ax.set_ylabel("fraction of the time")
        ax.set_title(label)
    legend(axs[0], configs)
    fig.suptitle(title)
    save(fig, out.path(name), written)
    return True


def plot_imbalance(configs, varying, scenes, out, written):
    if not any(c.values("load_imbalance")[0] for c in configs):
        return False
    fig, axs = grid(len(scenes))
    for ax, scene in zip(axs, scenes):
        mine = [c for c in configs if c.scene == scene]
        for c in mine:
            p, y = c.values("load_imbalance")
            ax.plot(p, y, label=c.label, **c.style())
        ax.axhline(1.0, color="black", linestyle=":", linewidth=1)
        pes_axis(ax, mine)
        ax.set_ylabel("longest PE window / mean")
        ax.set_title(scene)
        legend(ax, mine)
    partition = "" if "partition" in varying else configs[0].rows[0].get("partition", "")
    fig.suptitle(f"Load imbalance, {partition} partitioning" if partition else "Load imbalance")
    save(fig, out.path("load_imbalance"), written)
    return True


def stacked_shares(configs, out, written, parts, name, title, ylabel, total_unit, legend_cols, legend_room):
    """Per configuration and PE count, a bar stacked from PARTS ((column, label, colour)): each
    part's share of their sum, the sum written above the bar."""
    if not any(c.values(parts[0][0])[0] for c in configs):
        return False
    fig, axs = grid(len(configs), width=5.0, height=3.8)
    for ax, c in zip(axs, configs):
        rows = [r for r in c.rows if all(num(r.get(col)) is not None for col, _, _ in parts)]
        x = list(range(len(rows)))
        totals = [sum(num(r[col]) for col, _, _ in parts) for r in rows]
        bottom = [0.0] * len(rows)
        for col, label, colour in parts:
            share = [100.0 * num(r[col]) / t if t else 0.0 for r, t in zip(rows, totals)]
            ax.bar(x, share, bottom=bottom, color=colour, label=label, width=0.75)
            bottom = [b + s for b, s in zip(bottom, share)]
        for i, t in enumerate(totals):
            ax.text(i, 101, f"{t:.3g}{total_unit}", ha="center", va="bottom", fontsize=7)
        ax.set_xticks(x)
        ax.set_xticklabels([str(r["_pes"]) for r in rows], fontsize=8)
        ax.set_ylim(0, 112)
        ax.set_xlabel("PEs")
        ax.set_ylabel(ylabel)
        ax.set_title(c.label, fontsize=10)
    handles, labels = axs[0].get_legend_handles_labels()
    fig.suptitle(title)
    fig.tight_layout(rect=(0, legend_room / math.ceil(len(configs) / 3), 1, 1))
    fig.legend(handles, labels, loc="lower center", ncol=legend_cols, fontsize="small", frameon=False)
    save(fig, out.path(name), written, layout=False)
    return True


def plot_phases(configs, out, written):
    return stacked_shares(configs, out, written, PHASES, "phases", "Frame phases", "% of the frame's cycles", "",
                          len(PHASES), 0.06)

COST = [("energy_j", "energy per frame (J)", True), ("frames_per_s_per_mm2", "frames / s / mm² of chip", False)]


def plot_cost(configs, out, written):
    """What the machine costs (docs/cost.md): energy per frame and performance per area."""
    if not any(c.values(COST[0][0])[0] for c in configs):
        return False
    fig, axs = grid(len(COST), max_cols=2)
    for ax, (col, label, log_y) in zip(axs, COST):
        for c in configs:
            p, y = c.values(col)
            ax.plot(p, y, label=c.label, **c.style())
        pes_axis(ax, configs, log_y=log_y)
        ax.set_ylabel(label)
        legend(ax, configs)
    fig.suptitle("Cost")
    save(fig, out.path("cost"), written)
    return True


ENERGY = [("energy_front_buffer_j", "front buffer", "#dd8452"), ("energy_search_j", "object search", "#4c72b0"),
          ("energy_mac_j", "MAC", "#c44e52"), ("energy_root_j", "root unit", "#8172b3"),
          ("energy_shading_j", "shading", "#937860"), ("energy_local_memory_j", "local memory (DRAM)", "#55a868"),
          ("energy_link_j", "link", "#e6a23c"), ("energy_leakage_j", "leakage", "#8c8c8c")]


def plot_energy(configs, out, written):
    """Per configuration and PE count, a stacked bar of where the frame's energy goes."""
    return stacked_shares(configs, out, written, ENERGY, "energy", "Energy by unit", "% of the frame's energy", " J",
                          4, 0.1)


def write_markdown(out, written, name, lines):
    """Writes the table's lines as NAME in the plots' folder and returns its text."""
    text = "\n".join(lines) + "\n"
    path = os.path.join(out.folder, name)
    with open(path, "w") as f:
        f.write(text)
    written.append(path)
    return text


def write_table(configs, out, written):
    """scaling.md: per configuration and PE count, cycles, speedup and parallel efficiency, where
    the frame went, and the bottleneck; with several frames a run's cycles are all of them, and a
    column gives a frame's (the steady state's), which the speedups are of."""
    frames = any(frame_column(c) == "frame_cycles" and
                 any(num(r.get("frame_cycles")) != num(r.get("cycles")) for r in c.rows) for c in configs)
    lines = ["| configuration | PEs | cycles | " + ("frame cycles | " if frames else "") +
             "speedup | efficiency | host % | transfer % | PE work % | gather % | load imbalance | bottleneck |",
             "|---|---|---|" + ("---|" if frames else "") + "---|---|---|---|---|---|---|---|"]
    fmt = lambda v, f: (f % v) if v is not None else ""
    for c in configs:
        # Every ok row has its cycles (load), so the speedups line up with the rows.
        _, speedups, efficiencies = speedup_of(c)
        for r, speed, eff in zip(c.rows, speedups, efficiencies):
            cyc, p = num(r.get("cycles")), r["_pes"]
            # Of a frame: with several frames each phase is a stage's time a frame (they overlap).
            per_frame = num(r.get("frame_cycles")) or cyc
            shares = []
            for col, _, _ in PHASES:
                v = num(r.get(col))
                shares.append(f"{100 * v / per_frame:.1f}" if v is not None and per_frame else "")
            frame = f"{per_frame:,.0f} | " if frames else ""
            lines.append(f"| {c.label} | {p} | {int(cyc):,} | {frame}{fmt(speed, '%.1f')} | {fmt(eff, '%.2f')} | " +
                         " | ".join(shares) +
                         f" | {fmt(num(r.get('load_imbalance')), '%.3f')} | {r.get('bottleneck', '')} |")
    return write_markdown(out, written, "scaling.md", lines)


def energy_shares(row):
    """Leakage's share of the row's energy, and the dynamic part (a unit, the local memories or the
    link) that takes most of the rest, with its share of it: ("58 %", "MAC 41 %")."""
    parts = {col: num(row.get(col)) for col, _, _ in ENERGY if num(row.get(col)) is not None}
    total = sum(parts.values())
    leakage = parts.pop("energy_leakage_j", 0)
    dynamic = total - leakage
    if not parts or total <= 0 or dynamic <= 0:
        return "", ""
    col = max(parts, key=parts.get)
    name = next(n for c, n, _ in ENERGY if c == col)
    return f"{100 * leakage / total:.0f} %", f"{name} {100 * parts[col] / dynamic:.0f} %"


def write_cost_table(configs, out, written):
    """cost.md (docs/cost.md): per configuration and PE count, area, energy per frame, frames per
    second, per mm² and per joule; then per scene the configurations of most frames/s/mm² and most
    frames/J. None without cost columns."""
    if not any(num(r.get("frames_per_s_per_mm2")) is not None for c in configs for r in c.rows):
        return None
    fmt = lambda v, f: (f % v) if v is not None else ""
    micro = lambda j: "" if j is None else f"{j * 1e6:,.0f}" if j >= 1e-4 else f"{j * 1e6:.4g}"
    lines = ["| configuration | PEs | area, mm² | energy per frame, µJ | power, W | frames/s | frames/s/mm² | frames/J "
             "| leakage | largest dynamic part |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for c in configs:
        for r in c.rows:
            area, per_mm2, energy = (num(r.get(k)) for k in ("area_mm2", "frames_per_s_per_mm2", "energy_j"))
            fps = per_mm2 * area if per_mm2 is not None and area is not None else None
            lines.append(f"| {c.label} | {r['_pes']} | {fmt(area, '%.3f')} | "
                         f"{micro(energy)} | {fmt(num(r.get('power_w')), '%.3g')} | {fmt(fps, '%.4g')} | "
                         f"{fmt(per_mm2, '%.4g')} | {fmt(num(r.get('frames_per_j')), '%.4g')} | "
                         f"{' | '.join(energy_shares(r))} |")
    best = lambda rows, key: max((r for r in rows if num(r[1].get(key)) is not None),
                                 key=lambda r: num(r[1].get(key)), default=None)
    pes = lambda n: f"{n} PE" if int(n) == 1 else f"{n} PEs"
    cell = lambda b, key: f"{b[0].label}, {pes(b[1]['_pes'])} ({num(b[1].get(key)):.4g})" if b else ""
    lines += ["", "| scene | most frames/s/mm² | most frames/J |", "|---|---|---|"]
    for scene in sorted({c.scene for c in configs}):
        rows = [(c, r) for c in configs if c.scene == scene for r in c.rows]
        lines.append(f"| {scene} | {cell(best(rows, 'frames_per_s_per_mm2'), 'frames_per_s_per_mm2')} | "
                     f"{cell(best(rows, 'frames_per_j'), 'frames_per_j')} |")
    return write_markdown(out, written, "cost.md", lines)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="plot-sweep", description="Plots a scripts/sweep results.csv.")
    ap.add_argument("csv", help="results.csv written by scripts/sweep")
    ap.add_argument("outdir", help="folder for the plots (created)")
    ap.add_argument("--format", choices=FORMATS, default="png", help="the plots' file format (default png)")
    ap.add_argument("--quiet", "-q", action="store_true", help="print only problems")
    ap.add_argument("--page", help="the study page (docs/studies/*.md) whose generated part to rewrite with scaling.md"
                    " (and cost.md)")
    ap.add_argument("--part", default="scaling", help="the page's part: its markers name `scripts/plot-sweep PART`")
    ap.add_argument("--rtm", help="the rtm that made the CSV: the page's stamp says what `RTM --version` prints")
    args = ap.parse_args(argv)

    try:
        rows, ok, axes = load(args.csv)
    except OSError as e:
        sys.exit(f"plot-sweep: cannot read {args.csv}: {e.strerror}")
    if not ok:
        sys.exit(f"plot-sweep: {args.csv}: no successful runs to plot ({len(rows)} rows)")
    os.makedirs(args.outdir, exist_ok=True)
    out = Output(args.outdir, args.format)
    configs, varying = configurations(ok, axes)
    scenes = sorted({c.scene for c in configs})
    written, notes = [], []

    plot_cycles(configs, scenes, out, written)
    plot_speedup(configs, out, written, notes)
    plot_utilisation(configs, out, written, "util_", "Stage utilisation over the frame", "utilisation")
    plot_utilisation(configs, out, written, "pe_util_", "Stage utilisation over the PEs' working windows",
                     "pe_utilisation")
    if not plot_imbalance(configs, varying, scenes, out, written):
        notes.append(out.file("load_imbalance") + ": skipped, no load_imbalance values")
    if not plot_phases(configs, out, written):
        notes.append(out.file("phases") + ": skipped, no phase columns")
    if not plot_cost(configs, out, written):
        notes.append(out.file("cost") + ": skipped, no cost columns")
    if not plot_energy(configs, out, written):
        notes.append(out.file("energy") + ": skipped, no energy columns")
    table = write_table(configs, out, written)
    cost = write_cost_table(configs, out, written)
    if cost:
        table += "\nWhat each configuration costs (docs/cost.md):\n\n" + cost
    if args.page:
        build = page.build_of(args.rtm) if args.rtm else page.NOT_RECORDED
        try:
            page.update(args.page, "scripts/plot-sweep " + args.part, table, build, page.runs_line(rows))
        except page.PageError as e:
            sys.exit(f"plot-sweep: {e}")

    if not args.quiet:
        skipped = len(rows) - len(ok)
        print(f"plot-sweep: {len(ok)} runs in {len(configs)} configurations"
              + (f" ({skipped} failed row{'s' if skipped > 1 else ''} left out)" if skipped else ""))
        for w in written:
            print(f"  {w}")
    for n in notes:
        print(f"plot-sweep: {n}", file=sys.stderr if args.quiet else sys.stdout)
    return 0

