"""Figure: error against render time, our tracer and Mitsuba 3, on a glass sphere in an environment.

Run:  python paper/scripts/fig_peer.py [--quick]
Reads ``data/derived/peer_mitsuba.csv`` (written by ``benchmarks/peer_mitsuba.py``, which needs
the optional ``mitsuba`` package); writes ``fig_peer.pdf``/``.png``.

(a) RMSE (linear RGB) and (b) mean CIEDE2000 against the reference (one above the other, one
column wide), both against seconds per 256x256 image (median of the runs, compilation
excluded; horizontal bars, the fastest to the slowest of the runs in ``seconds_runs``), log-log.  Ours: Whitted, exhaustive tree (threshold 0, solid) and pruned (threshold 1e-3, dashed), 1-64 spp.  Mitsuba 3 ``path``:
LLVM variant with the stratified and the independent sampler (1-4096 spp), scalar variant with
the stratified sampler (1-1024 spp).  Numbers beside the points: samples per pixel (every point
of the two main curves, the last point of the others).  Dotted grey:
the difference between our converged image and Mitsuba's (texture filtering), below which
neither curve can go against the other's reference.  (a) and (b) at two threads (every core,
both renderers).  (c), (d): the time Mitsuba's LLVM variant (stratified) takes to reach each
error divided by ours (exhaustive, pruned), at every error both curves reach
(:func:`study.fronts.time_ratio_curve`), with one thread and with two in both renderers.  Quick
mode draws the same figure (it only reads the table).
"""

import sys

import numpy as np
from matplotlib import ticker

import paths
import style
from study import read_commented_csv
from study.fronts import time_ratio_curve

PEER = paths.DERIVED / "peer_mitsuba.csv"

#: (renderer, variant, sampler) -> (label, colour index, line style, marker, which points get their
#: spp written beside them ("all" or "last"), label offset in points)
CURVES = {
    ("ours", "exhaustive", "stratified"): ("ours, exhaustive", 0, "-", "o", "all", (3, 3)),
    ("ours", "pruned", "stratified"): ("ours, pruned $10^{-3}$", 0, "--", "o", "last", (0, -9)),
    ("mitsuba", "llvm_ad_rgb", "stratified"): ("Mitsuba LLVM, stratified", 1, "-", "s", "all", (-3, -8)),
    ("mitsuba", "llvm_ad_rgb", "independent"): ("Mitsuba LLVM, independent", 1, ":", "s", "last", (3, 1)),
    ("mitsuba", "scalar_rgb", "stratified"): ("Mitsuba scalar, stratified", 2, "-", "^", "last", (3, 1)),
}


def read_rows(path):
    """(comment lines, rows as dicts) of the benchmark's CSV; exits with a message if it is missing."""
    if not path.exists():
        raise SystemExit(f"{path} is missing: run python benchmarks/peer_mitsuba.py first "
                         "(needs pip install mitsuba, and libllvm19 for its LLVM variant)")
    notes, rows = read_commented_csv(path)
    if not rows:
        raise SystemExit(f"{path} has no rows: run python benchmarks/peer_mitsuba.py again")
    return notes, rows


def run_range(row):
    """(fastest, slowest) of a configuration's timed runs (``seconds_runs``, space-separated);
    the median itself when the row has no runs listed."""
    runs = [float(x) for x in row.get("seconds_runs", "").split()]
    median = float(row["seconds"])
    return (min(runs + [median]), max(runs + [median]))


def curve_of(sweep, key, threads, metric):
    """(seconds, errors) of one configuration's curve at *threads* threads, by samples per pixel."""
    rows = sorted((r for r in sweep if (r["renderer"], r["variant"], r["sampler"]) == key
                   and int(r["threads"]) == threads), key=lambda r: int(r["spp"]))
    return [float(r["seconds"]) for r in rows], [float(r[metric]) for r in rows]


def ratio_panels(fig, grid, sweep, counts, colors):
    """(c), (d): Mitsuba LLVM (stratified) time / ours at equal RMSE and at equal mean dE00, over
    every error both reach, one line per (ours variant, thread count)."""
    mitsuba = ("mitsuba", "llvm_ad_rgb", "stratified")
    panels = (("rmse", "RMSE", "(c)"), ("mean_de00", r"mean $\Delta E_{00}$", "(d)"))
    first = None
    for col, (metric, xlabel, tag) in enumerate(panels):
        ax = fig.add_subplot(grid[2, col], sharey=first)
        first = first or ax
        for key, style_ in ((("ours", "exhaustive", "stratified"), "-"), (("ours", "pruned", "stratified"), "--")):
            for threads in counts:
                x, ratio = time_ratio_curve(curve_of(sweep, mitsuba, threads, metric),
                                            curve_of(sweep, key, threads, metric))
                colour = colors[0] if threads == max(counts) else colors[3]
                label = f"{key[1]}, {threads} thr." if col == 0 else None
                ax.plot(x, ratio, style_, color=colour, linewidth=1.0, label=label)
        ax.axhline(1.0, color="0.55", linewidth=0.6)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.invert_xaxis()  # smaller errors (more samples) to the right
        plain = ticker.FuncFormatter(lambda v, _: f"{v:g}")
        ax.yaxis.set_major_locator(ticker.LogLocator(subs=(1.0, 2.0, 5.0)))
        ax.yaxis.set_major_formatter(plain)
        ax.yaxis.set_minor_formatter(ticker.NullFormatter())
        ax.xaxis.set_major_locator(ticker.LogLocator(subs=(1.0, 2.0, 5.0), numticks=4))
        ax.xaxis.set_major_formatter(plain)
        ax.xaxis.set_minor_formatter(ticker.NullFormatter())
        ax.set_xlabel(f"target {xlabel}")
        ax.set_title(f"{tag} Mitsuba / ours", loc="left")
        ax.grid(True, which="major")
        if col == 0:
            ax.set_ylabel("time ratio")
        else:
            ax.tick_params(labelleft=False)
    first.legend(loc="best", frameon=False, fontsize=7, handlelength=1.6)


def main(argv=None):
    paths.parse_args(__doc__.splitlines()[0], argv)
    notes, rows = read_rows(PEER)
    sweep = [r for r in rows if r["role"] == "sweep"]
    if "threads" not in sweep[0]:
        raise SystemExit(f"{PEER} has no threads column: run python benchmarks/peer_mitsuba.py again")
    counts = sorted({int(r["threads"]) for r in sweep})
    everything = sweep
    sweep = [r for r in everything if int(r["threads"]) == max(counts)]
    ours_ref = next((r for r in rows if r["role"] == "reference" and r["renderer"] == "ours"), None)

    fig = style.figure(width=style.COLUMN_WIDTH, height=5.9)  # one column (paper.tex: figure)
    grid = fig.add_gridspec(3, 2, height_ratios=(1.0, 1.0, 0.95))
    top = fig.add_subplot(grid[0, :])
    axes = [top, fig.add_subplot(grid[1, :], sharex=top)]
    colors = [c["color"] for c in style.matplotlib.rcParams["axes.prop_cycle"]]
    panels = (("rmse", "RMSE (linear RGB)", "(a)"), ("mean_de00", r"mean $\Delta E_{00}$", "(b)"))
    for ax, (metric, ylabel, tag) in zip(axes, panels):
        for key, (label, ci, ls, marker, which, offset) in CURVES.items():
            curve = sorted((r for r in sweep if (r["renderer"], r["variant"], r["sampler"]) == key),
                           key=lambda r: int(r["spp"]))
            if not curve:
                continue
            t = np.array([float(r["seconds"]) for r in curve])
            e = np.array([float(r[metric]) for r in curve])
            low_high = np.array([run_range(r) for r in curve])
            ax.errorbar(t, e, xerr=[t - low_high[:, 0], low_high[:, 1] - t], fmt="none", ecolor=colors[ci],
                        elinewidth=0.6, capsize=1.2, capthick=0.6)
            ax.plot(t, e, ls, marker=marker, color=colors[ci], label=label, markersize=2.8,
                    markerfacecolor="white" if ls != "-" else colors[ci], markeredgewidth=0.7)
            labelled = range(len(curve)) if which == "all" else [len(curve) - 1]
            for k in labelled:
                ax.annotate(curve[k]["spp"], (t[k], e[k]), textcoords="offset points", xytext=offset, fontsize=7,
                            color=colors[ci], ha="right" if offset[0] < 0 else "left")
        if ours_ref is not None:
            floor = float(ours_ref[metric])
            ax.axhline(floor, color="0.55", linestyle=":", linewidth=0.8)
            ax.annotate("ours vs Mitsuba, both converged", (0.02, floor), xycoords=("axes fraction", "data"),
                        textcoords="offset points", xytext=(0, 2), fontsize=7, color="0.4")
        ax.set_xscale("log")
        ax.set_yscale("log")
        low, high = ax.get_ylim()
        ax.set_ylim(low / 1.4, high)  # room for the labels of the last points
        ax.set_ylabel(ylabel)
        ax.set_title(f"{tag} {ylabel} against the reference, {max(counts)} threads", loc="left")
        ax.grid(True, which="major")
    left, right = axes[-1].get_xlim()
    axes[-1].set_xlim(left, right * 2.5)  # room for the labels of the slowest points
    axes[-1].set_xlabel("render time per image (s)")
    axes[0].tick_params(labelbottom=False)
    axes[0].legend(loc="upper right", frameon=False)
    ratio_panels(fig, grid, everything, counts, colors)
    reference = next((n for n in notes if n.startswith("reference")), "")
    if reference:
        print(reference)
    for path in style.savefig(fig, "fig_peer"):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
