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
reference).  Each point is labelled with the value of the factor it sweeps (number of bands,
``t`` threshold, samples per pixel, ``d`` depth) where the label fits without covering another
label, a marker or a legend (:func:`place_labels`, greedy: points on the front first); the
legend is split over the four panels, each part in the free space above that panel's points
(the top of the axes is raised until it covers none).  Quick mode draws the same figure (it
only reads the file).
"""

import sys

import numpy as np

import paths
import style
from study import pareto_front, tradeoffs

CSV = paths.DERIVED / "time_vs_error.csv"
SCENES = {"builtin": "built-in scene", "bubbles": "six bubbles", "materials": "bubble and spheres",
          "thick": "thick films ({lo} to {hi} $\\mu$m)"}  # the films' range: numbers_time_vs_error.film_range_um
#: factor group -> (label, marker, colour index in the style's cycle, filled)
GROUPS = {
    "point": ("bands, point", "o", 0, True),
    "band": ("bands, averaged", "D", 5, True),
    "rgb": ("RGB transport", "X", 1, True),
    "threshold": ("threshold", "s", 4, True),
    "spp": ("samples/pixel", "^", 2, True),
    "depth": ("depth", "v", 3, True),
    "grid": ("combined", "P", 6, False),
    "ideal": ("reference, 1 spp", "h", 6, True),
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


#: which legend entries each panel holds, in the free space of its axes (upper right)
LEGEND_PANELS = {
    "builtin": ["bands, point", "bands, averaged", "RGB transport", "threshold"],
    "bubbles": ["samples/pixel", "depth", "combined", "reference, 1 spp"],
    "materials": ["defaults", "Pareto front", "front, all pixels", "target"],
    "thick": ["reference's time", "reference's floor"],
}


def label_of(r):
    """The short label of a point: the value of the factor it sweeps (bands, threshold, samples
    per pixel, depth), or None for the combined grid and the reference's transport (the legend
    names those)."""
    g = group(r)
    if g == "rgb":
        return "RGB"
    if g in ("point", "band"):
        return f"{int(r['spectral_samples'])}"
    if g == "threshold":
        return f"t {r['threshold']:g}"
    if g == "spp":
        return f"{int(r['spp'])} spp"
    if g == "depth":
        return f"d {int(r['depth'])}"
    return None


#: labelling order: points on the interior front first, then these groups
LABEL_PRIORITY = ["point", "band", "rgb", "spp", "depth", "threshold"]
#: where a label may go around its point, in points (dx, dy, horizontal, vertical alignment): next
#: to it first, then (a second pass, for the points still unlabelled) farther out with a leader line
OFFSETS = [(3.2, 0, "left", "center"), (-3.2, 0, "right", "center"), (0, 2.6, "center", "bottom"),
           (0, -2.6, "center", "top"), (2.6, 2.2, "left", "bottom"), (-2.6, 2.2, "right", "bottom"),
           (2.6, -2.2, "left", "top"), (-2.6, -2.2, "right", "top")]
FAR = 3.0  # the second pass's offsets: OFFSETS times this


def _overlaps(a, b, pad=0.0):
    return not (a.x1 + pad <= b.x0 or b.x1 + pad <= a.x0 or a.y1 + pad <= b.y0 or b.y1 + pad <= a.y0)


def place_labels(fig, ax, points, front, blocked):
    """Label *points* of *ax* with :func:`label_of`, greedily, each where it overlaps no other
    label, marker or legend (*blocked*: display boxes to avoid) and stays inside the axes; a point
    with no such place is left unlabelled.  Returns (labelled, labellable)."""
    from matplotlib import patheffects
    from matplotlib.text import Text
    from matplotlib.transforms import Bbox

    renderer = fig.canvas.get_renderer()
    px = fig.dpi / 72.0
    inside = ax.get_window_extent(renderer)
    xy = [ax.transData.transform((r["seconds"], r["interior_mean_de00"])) for r in points]
    marks = [Bbox.from_extents(x - 2.2 * px, y - 2.2 * px, x + 2.2 * px, y + 2.2 * px) for x, y in xy]
    taken = list(blocked) + marks
    order = sorted((i for i, r in enumerate(points) if label_of(r) is not None),
                   key=lambda i: (i not in front, LABEL_PRIORITY.index(group(points[i])), points[i]["seconds"]))
    placed = set()
    for far in (False, True):
        for i in order:
            if i in placed:
                continue
            for dx, dy, ha, va in OFFSETS:
                k = FAR if far else 1.0
                leader = dict(arrowstyle="-", lw=0.35, color="0.35", shrinkA=0.5, shrinkB=2.2) if far else None
                t = ax.annotate(label_of(points[i]), (points[i]["seconds"], points[i]["interior_mean_de00"]),
                                xytext=(k * dx, k * dy), textcoords="offset points", ha=ha, va=va, fontsize=7,
                                color="0.15", zorder=6, annotation_clip=False, arrowprops=leader,
                                path_effects=[patheffects.withStroke(linewidth=1.6, foreground="white")])
                t.set_in_layout(False)
                t.update_positions(renderer)
                box = Text.get_window_extent(t, renderer)  # the text alone, not its leader
                if (box.x0 >= inside.x0 and box.x1 <= inside.x1 and box.y0 >= inside.y0 and box.y1 <= inside.y1
                        and not any(_overlaps(box, b, 0.3 * px) for k, b in enumerate(taken) if k != len(blocked) + i)):
                    taken.append(box)
                    placed.add(i)
                    break
                t.remove()
    placed = len(placed)
    return placed, len(order)


def _legend_covers_points(ax, points, renderer):
    """Whether the legend of *ax* covers one of *points* (a marker's box) or the defaults' star."""
    box = ax.get_legend().get_window_extent(renderer)
    px = ax.figure.dpi / 72.0
    for r in points:
        x, y = ax.transData.transform((r["seconds"], r["interior_mean_de00"]))
        if box.x0 - 2 * px <= x <= box.x1 + 2 * px and box.y0 - 2 * px <= y <= box.y1 + 2 * px:
            return True
    return False


def main(argv=None):
    paths.parse_args(__doc__.splitlines()[0], argv)
    rows = read_rows(CSV)
    fig = style.figure(width=style.COLUMN_WIDTH, height=3.9)
    axes = fig.subplot_mosaic([["builtin", "bubbles"], ["materials", "thick"]])
    colors = [c["color"] for c in style.matplotlib.rcParams["axes.prop_cycle"]]
    handles, fronts = {}, {}
    from matplotlib.patches import Patch

    from macros import significant
    from numbers_time_vs_error import film_range_um

    lo_um, hi_um = film_range_um()
    for scene, title in SCENES.items():
        title = title.format(lo=significant(lo_um, 2), hi=significant(hi_um, 2))
        ax = axes[scene]
        sf = tradeoffs.scene_front(rows, scene)
        pts, t_ref, default, front = sf["points"], sf["reference_seconds"], sf["default"], sf["front"]
        fronts[scene] = (pts, set(int(i) for i in front))
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
        h_ref = ax.axvline(t_ref, color="k", ls=":", lw=0.6)
        if np.isfinite(floor):
            handles["reference's floor"] = ax.axhline(floor, color="0.3", ls="-.", lw=0.6, zorder=1)
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
    handles["reference's time"] = h_ref
    handles["target"] = Patch(color=colors[2], alpha=0.12, lw=0)
    listed = [name for names in LEGEND_PANELS.values() for name in names]
    if sorted(listed) != sorted(handles):
        raise ValueError(f"legend entries {sorted(listed)} are not the figure's {sorted(handles)}")
    for scene, names in LEGEND_PANELS.items():
        axes[scene].legend([handles[n] for n in names], names, loc="upper right", fontsize=7, handlelength=1.4,
                           handletextpad=0.4, borderaxespad=0.25, borderpad=0.15, labelspacing=0.15, frameon=True,
                           framealpha=0.85, edgecolor="none", facecolor="white")
    # headroom above the points for each legend: raise the top of the axes until the legend
    # covers no marker
    for _ in range(12):
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        crowded = [sc for sc in SCENES if _legend_covers_points(axes[sc], fronts[sc][0], renderer)]
        if not crowded:
            break
        for sc in crowded:
            lo, hi = axes[sc].get_ylim()
            axes[sc].set_ylim(lo, hi * 1.4)
    else:
        raise ValueError("fig_time_vs_error: no room for a legend above the points")
    fig.canvas.draw()  # the constrained layout, fixed before the labels are placed around the points
    fig.set_layout_engine("none")
    renderer = fig.canvas.get_renderer()
    for scene in SCENES:
        ax = axes[scene]
        blocked = [ax.get_legend().get_window_extent(renderer)]
        pts, front = fronts[scene]
        placed, total = place_labels(fig, ax, pts, front, blocked)
        print(f"{scene}: {placed} of {total} points labelled")
    for path in style.savefig(fig, "fig_time_vs_error"):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
