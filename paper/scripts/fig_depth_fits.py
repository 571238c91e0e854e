"""Figure: growth laws fitted to the coursework's table 4.1, and their relative residuals.

The trace depth is written ℓ (the paper's d is the film thickness).

Run:  python paper/scripts/fig_depth_fits.py [--quick]
Reads ``data/coursework_table_4_1.csv``; writes ``fig_depth_fits.pdf``/``.png``.

Top: the coursework's times (circles) with the affine exponential a + c·b^ℓ (solid), the pure
exponential a·b^ℓ (dotted) and a fourth-degree polynomial (dashed: the coursework's law, refitted
here with the same relative weights as the other two, not the coursework's own curve, which
it fitted to the times by absolute residuals), one colour per scene.  Bottom: relative residuals
(t − t̂)/t of each law, one panel per law, titled with its number of parameters; crosses: the error (t̂ − t)/t at depths 8-10 of the same law fitted only
to depths 1-7 (TRAIN_DEPTH), which tells a law that explains the growth from one that
interpolates it.  The legend gives each column's 95 % profile-likelihood interval of b
(:func:`study.fits.branching_interval`).  All fits by study with the same weighting (relative, 1/t; the
quartic as well, so that every law sits at its own optimum of the same criterion).
Quick mode draws the same figure (the fits take milliseconds).
"""

import sys

import numpy as np

import paths
import style
import study
from study.fits import branching_interval

SCENES = {1: "one bubble", 2: "two bubbles", 3: "three bubbles"}
LAWS = {  # model name of study's fits -> panel title, line style, fitter
    "affine exponential": ("$a + c\\,b^\\ell$ (3)", "-", study.fit_affine_exponential),
    "exponential": ("$a\\,b^\\ell$ (2)", ":", study.fit_exponential),
    "polynomial, degree 4": ("quartic, refitted (5)", "--",
                             lambda d, t, relative: study.fit_polynomial(d, t, 4, relative=relative)),
}
TRAIN_DEPTH = 7  # the held-out test fits depths 1..7 and predicts 8..10


def main(argv=None):
    paths.parse_args(__doc__.splitlines()[0], argv)
    coursework = study.load_coursework_table(paths.COURSEWORK_TABLE)
    depth = coursework["depth"]
    fine = np.linspace(1.0, 10.0, 200)

    fig = style.figure(height=3.6)
    axes = fig.subplot_mosaic([["fit"] * 3, list(LAWS)], height_ratios=(2.2, 1.0), sharex=False)
    colors = [c["color"] for c in style.matplotlib.rcParams["axes.prop_cycle"]]
    worst = {law: 0.0 for law in LAWS}
    for (nb, name), color in zip(SCENES.items(), colors):
        comparison = study.compare_fits(depth, coursework["seconds"][nb])
        fits = {row["model"]: row["fit"] for row in comparison.rows}
        low, high = branching_interval(depth, coursework["seconds"][nb], n_boot=0).profile
        axes["fit"].plot(depth, coursework["seconds"][nb], "o", color=color, markerfacecolor="white",
                         markeredgewidth=0.7, label=f"{name}: ${low:.3f} \\leq b \\leq {high:.3f}$", zorder=3)
        for law, (_, ls, fitter) in LAWS.items():
            axes["fit"].plot(fine, fits[law].predict(fine), ls, color=color, linewidth=0.8)
            axes[law].plot(depth, 100 * fits[law].relative_residuals, "o-", color=color, linewidth=0.6,
                           markersize=2.2)
            held, err = study.holdout_errors(fitter, depth, coursework["seconds"][nb], TRAIN_DEPTH, relative=True)
            axes[law].plot(held, 100 * err, "x", color=color, markersize=3.5, markeredgewidth=0.8)
            worst[law] = max(worst[law], float(np.abs(fits[law].relative_residuals).max()), float(np.abs(err).max()))
            print(f"  {law}: fitted to depths 1-{TRAIN_DEPTH}, error at depth 10 {100 * err[-1]:+.1f} %")
        b = fits["affine exponential"].params["b"]
        print(f"{name}: best {comparison.best}; affine exponential b = {b:.3f}")

    ax = axes["fit"]
    ax.set_yscale("log")
    ax.set_xlabel("trace depth $\\ell$")
    ax.set_ylabel("coursework's render time $t$ (s)")
    ax.set_xticks(range(1, 11))
    ax.set_xlim(0.7, 10.3)
    from matplotlib.lines import Line2D

    law_handles = [Line2D([], [], color="0.3", linestyle=ls, label=title) for title, ls, _ in LAWS.values()]
    data_legend = ax.legend(loc="upper left")
    ax.add_artist(data_legend)
    ax.legend(handles=law_handles, loc="lower right")

    limit = 100 * max(worst.values()) * 1.1
    for i, (law, (title, _, _)) in enumerate(LAWS.items()):
        a = axes[law]
        a.axhline(0.0, color="0.6", linewidth=0.5)
        a.set_title(title, pad=2)
        a.set_ylim(-limit, limit)
        a.set_xticks([1, 5, 10])
        a.set_xlim(0.5, 10.5)
        a.set_xlabel("$\\ell$")
        if i:
            a.tick_params(labelleft=False)
        else:
            a.set_ylabel("$(t - \\hat t)/t$ (%)")
            a.text(0.97, 0.05, f"$\\times$ fitted to $\\ell \\leq {TRAIN_DEPTH}$", transform=a.transAxes, ha="right",
                   va="bottom", fontsize=7)
    for path in style.savefig(fig, "fig_depth_fits"):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
