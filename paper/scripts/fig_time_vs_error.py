"""Figure: render time against colour error over the tracer's settings, with the Pareto front.

Run:  python paper/scripts/fig_time_vs_error.py [--quick]
Reads ``data/derived/time_vs_error.csv`` (written by ``benchmarks/time_vs_error.py``); writes
``fig_time_vs_error.pdf``/``.png``.

One panel per scene: each setting of the study as a point, render time at 160 x 160
(compilation excluded, median of the timed runs, horizontal bar: their range) against its mean
CIEDE2000 to the reference (1 nm bands, exhaustive tree, 16 samples per pixel) over the
interior pixels (away from silhouettes and sub-pixel detail, by a mask that favours no sampling
pattern: ``study.tradeoffs.interior_mask``), mean over seeds (vertical bar: +- one
standard deviation over seeds; none for 1 spp, which samples the pixel centre whatever the
seed).  Marker: the factor swept (spectral bands point-sampled or band-averaged, RGB
transport, pruning threshold, samples per pixel, depth, the combined grid).  Solid line: the
Pareto front of those points (``study.tradeoffs.scene_front``); grey dashed line: the
front of the same settings by the error over all pixels.  Star: the defaults the benchmark
ran with; dotted vertical line: the reference's time; dash-dotted horizontal line: the
reference's floor (a second reference with another seed, scored the same way: errors below it
are not resolved); shaded: the target (mean ΔE00 <= 0.5, at least 20x faster than the
reference).  Quick mode draws the same figure (it only reads the file).
"""

import sys

import numpy as np

import paths
import style
from study import pareto_front, tradeoffs

CSV = paths.DERIVED / "time_vs_error.csv"
SCENES = {"builtin": "built-in scene", "bubbles": "six bubbles", "materials": "bubble and spheres",
          "thick": "thick films (1.6 to 3 $\\mu$m)"}
#: factor group -> (label, marker, colour index in the style's cycle, filled)
GROUPS = {
    "point": ("bands, point", "o", 0, True),
    "band": ("bands, band-averaged", "D", 5, True),
    "rgb": ("RGB transport", "X", 1, True),
    "threshold": ("threshold", "s", 4, True),
    "spp": ("samples per pixel", "^", 2, True),
    "depth": ("depth", "v", 3, True),
    "grid": ("combined", "P", 6, False),
    "ideal": ("1 nm, exhaustive, 1 spp", "h", 6, True),
}


def read_rows(path):
    """The benchmark's rows (:func:`study.tradeoffs.read_rows`, numbers as float);
    exits with a message if the file is missing."""
    if not path.exists():
        raise SystemExit(f"{path} is missing: run python benchmarks/time_vs_error.py first")
    return tradeoffs.read_rows(path)[1]


def group(r):
    if r["factor"] == "spectral":
        return "rgb" if r["transport"] == "rgb" else ("band" if r["spectral_method"] == "band" else "point")
    return r["factor"] if r["factor"] in GROUPS else None


def main(argv=None):
    paths.parse_args(__doc__.splitlines()[0], argv)
    rows = read_rows(CSV)
    fig = style.figure(width=style.COLUMN_WIDTH, height=4.9)
    axes = fig.subplot_mosaic([["builtin", "bubbles"], ["materials", "thick"], ["legend", "legend"]],
                              height_ratios=[1.0, 1.0, 0.42])
    colors = [c["color"] for c in style.matplotlib.rcParams["axes.prop_cycle"]]
    handles = {}
    for scene, title in SCENES.items():
        ax = axes[scene]
        sf = tradeoffs.scene_front(rows, scene)
        pts, t_ref, default, front = sf["points"], sf["reference_seconds"], sf["default"], sf["front"]
        t = np.array([r["seconds"] for r in pts])
        e_int = np.array([r["interior_mean_de00"] for r in pts])
        e_all = np.array([r["mean_de00"] for r in pts])
        floor = sf["floor"]["interior_mean_de00"] if sf["floor"] else np.nan
        lo_t, hi_t = 0.6 * t.min(), 1.8 * t_ref
        lo_e, hi_e = 0.6 * np.nanmin(np.append(e_int, floor)), 1.6 * e_all.max()
        ax.fill_between([lo_t, t_ref / tradeoffs.TARGET_SPEEDUP], lo_e, tradeoffs.TARGET_MEAN_DE00, color=colors[2],
                        alpha=0.12, lw=0, zorder=0)
        for r in pts:
            label, marker, ci, filled = GROUPS[group(r)]
            h, = ax.plot(r["seconds"], r["interior_mean_de00"], marker, color=colors[ci], markersize=2.6,
                         markerfacecolor=colors[ci] if filled else "none", markeredgewidth=0.5, alpha=0.9, zorder=3)
            handles.setdefault(label, h)
            sd = r.get("interior_mean_de00_sd", 0.0)
            sd = 0.0 if not np.isfinite(sd) else sd
            xerr = [[r["seconds"] - r.get("seconds_min", r["seconds"])], [r.get("seconds_max", r["seconds"]) - r["seconds"]]]
            yerr = [[min(sd, 0.9 * r["interior_mean_de00"])], [sd]]  # log axis: keep the lower bar above 0
            ax.errorbar(r["seconds"], r["interior_mean_de00"], xerr=xerr, yerr=yerr, fmt="none", ecolor=colors[ci],
                        elinewidth=0.4, capsize=0, alpha=0.7, zorder=2.5)
        front_all = pareto_front(t, e_all)
        h_all, = ax.step(t[front_all], e_all[front_all], "--", where="post", color="0.55", lw=0.6, zorder=1)
        h_front, = ax.step(t[front], e_int[front], "-", where="post", color="k", lw=0.7, zorder=2)
        h_def, = ax.plot(default["seconds"], default["interior_mean_de00"], "*", markersize=7, color="#F0E442",
                         markeredgecolor="k", markeredgewidth=0.5, zorder=5)
        ax.axvline(t_ref, color="k", ls=":", lw=0.6)
        if np.isfinite(floor):
            h_floor = ax.axhline(floor, color="0.3", ls="-.", lw=0.6, zorder=1)
        ax.text(t_ref / 1.15, hi_e / 1.3, "reference", rotation=90, ha="right", va="top", fontsize=7)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlim(lo_t, hi_t)
        ax.set_ylim(lo_e, hi_e)
        ax.set_title(title, pad=2)
        ax.set_xlabel("render time (s)", labelpad=1)
        ax.set_ylabel("mean $\\Delta E_{00}$, interior", labelpad=1)
        on_front = sf["default_on_front"]
        print(f"{scene}: floor (second reference) {floor:.3f}; reference {t_ref:.1f} s; defaults {default['seconds'] * 1e3:.1f} ms, interior mean dE00 "
              f"{default['interior_mean_de00']:.3f} (all pixels {default['mean_de00']:.3f}), "
              f"{default['speedup_vs_reference']:.0f}x faster, on the front: {on_front}; front of {len(front)} points")
    handles["Pareto front"] = h_front
    handles["front, all pixels"] = h_all
    handles["defaults"] = h_def
    handles["reference's floor"] = h_floor
    from matplotlib.patches import Patch

    handles["target"] = Patch(color=colors[2], alpha=0.12, lw=0)
    leg = axes["legend"]
    leg.set_axis_off()
    leg.legend(handles.values(), handles.keys(), loc="center", fontsize=7, handlelength=1.6, borderaxespad=0,
               labelspacing=0.35, ncol=2, columnspacing=1.0)
    for path in style.savefig(fig, "fig_time_vs_error"):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
