"""Figure: rays per level of the exhaustive ray tree, thin-film against two-sphere bubbles.

Run:  python paper/scripts/fig_ray_tree.py [--quick]
Reads ``data/derived/coursework_rays.csv`` (``benchmarks/coursework_rays.py``) and
``data/coursework_table_4_1.csv`` (the coursework's times, for its growth base b); writes
``fig_ray_tree.pdf``/``.png``.

Top: the rays of each level d ≥ 2 of the exhaustive tree (threshold 0, 960 x 960, one sample per
pixel; level 1 is the camera rays) for the coursework's scenes with the bubble read as one thin
film (squares) and modelled as two concentric refracting spheres (circles), one colour per number
of bubbles; log scale.  Bottom: the branching factor per level, rays(d)/rays(d − 1), with the
golden ratio (the two-sphere tree's asymptote, dotted) and the 95 % profile-likelihood intervals
of the coursework's b (its times fitted by a + c·b^d, :func:`study.fits.branching_interval`;
shaded band spanning the three columns' intervals).  Quick mode draws the same figure (it only
reads tables; the intervals skip the bootstrap).
"""

import sys

import numpy as np
from matplotlib.lines import Line2D

import paths
import style
from study import load_coursework_table
from study.coursework import load_rays, rays_series
from study.fits import branching_interval

SCENES = {1: "one bubble", 2: "two bubbles", 3: "three bubbles"}
MODELS = {"thin film": ("s", "-"), "two spheres": ("o", "--")}  # marker, line style
GOLDEN = (1 + 5**0.5) / 2


def main(argv=None):
    paths.parse_args(__doc__.splitlines()[0], argv)
    rays = load_rays(paths.DERIVED / "coursework_rays.csv")
    coursework = load_coursework_table(paths.COURSEWORK_TABLE)
    intervals = [branching_interval(coursework["depth"], coursework["seconds"][nb], n_boot=0).profile
                 for nb in SCENES]

    fig = style.figure(height=3.6)
    top, bottom = fig.subplots(2, 1, sharex=True, gridspec_kw=dict(height_ratios=(1.6, 1.0)))
    colors = [c["color"] for c in style.matplotlib.rcParams["axes.prop_cycle"]]
    for (nb, _), color in zip(SCENES.items(), colors):
        for model, (marker, ls) in MODELS.items():
            depth, level = rays_series(rays, model, nb)
            keep = depth >= 2
            top.plot(depth[keep], level[keep], ls, marker=marker, color=color, markersize=3, linewidth=0.8,
                     markerfacecolor=color if model == "two spheres" else "white", markeredgewidth=0.7)
            _, branching = rays_series(rays, model, nb, "branching")
            ok = np.isfinite(branching)
            bottom.plot(depth[ok], branching[ok], ls, marker=marker, color=color, markersize=3, linewidth=0.8,
                        markerfacecolor=color if model == "two spheres" else "white", markeredgewidth=0.7)
    top.set_yscale("log")
    top.set_ylabel("rays of level $d$")
    top.grid(True, which="major", axis="y")
    lo, hi = min(i[0] for i in intervals), max(i[1] for i in intervals)
    bottom.axhspan(lo, hi, color="0.8", linewidth=0, zorder=0)
    bottom.axhline(GOLDEN, color="0.3", linestyle=":", linewidth=0.8)
    bottom.axhline(1.0, color="0.6", linewidth=0.5)
    bottom.text(10.2, hi + 0.03, "coursework's $b$ (95 %)", ha="right", va="bottom")
    bottom.text(10.2, GOLDEN - 0.04, "golden ratio", ha="right", va="top")
    bottom.set_ylabel("rays($d$) / rays($d-1$)")
    bottom.set_xlabel("tree level $d$")
    bottom.set_xticks(range(2, 11))
    bottom.set_xlim(1.7, 10.3)
    bottom.set_ylim(0.8, 2.1)

    handles = [Line2D([], [], color="0.3", linestyle=ls, marker=m, markersize=3,
                      markerfacecolor="0.3" if model == "two spheres" else "white", label=model)
               for model, (m, ls) in MODELS.items()]
    first = top.legend(handles=handles, loc="upper left")
    top.add_artist(first)
    top.legend(handles=[Line2D([], [], color=c, label=n) for n, c in zip(SCENES.values(), colors)],
               loc="center left", bbox_to_anchor=(0.0, 0.45))
    for path in style.savefig(fig, "fig_ray_tree"):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
