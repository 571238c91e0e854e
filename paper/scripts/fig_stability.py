"""Figure: numerical stability near grazing incidence, and colour aliasing of thick films.

Run:  python paper/scripts/fig_stability.py [--quick]
Reads ``data/derived/stability_grazing.csv`` and ``data/derived/stability_aliasing.csv``
(written by ``benchmarks/stability.py``); writes ``fig_stability.pdf``/``.png``.

(a) Relative error of the transmittance T at 550 nm, unpolarized, against pi/2 - theta, from
bubbleoptics, tmm and the textbook float64 formula (cos = sqrt(1 - sin^2)), each against the
same formulas at 40 digits (mpmath): thick lines the free-standing water film (500 nm), thin
lines the other films with T > 0 (on a substrate, absorbing, frustrated TIR); dotted, the
rounding law eps / (2 cos^2 theta).  Exact zeros are drawn at 1e-18.
(b) CIEDE2000 between the colour of a water film (normal incidence, D65) from N point-sampled
bands and from 1 nm spectra, 1 um running median, against thickness; dashed verticals: the
predicted onset of aliasing, where the fringe spacing at 400 nm, lambda^2 / (2 n d), equals the
band width 420 nm / N; grey line: Delta E00 = 5 (``study.stability.ONSET_DE00``),
which the running median first exceeds at the measured onset.  Dotted: the band-limited method
(bubbleoptics.film_color_bandlimited's XYZ, polynomial order 3), when the CSV has it.
(c) The colours themselves (exposure making the brightest film white), 1 nm and N bands, and
the band-limited method with 8 bands when present.
Quick mode draws the same figure (it only reads tables).
"""

import sys

import numpy as np

import paths
import style
from bubbleoptics import XYZ_to_display_sRGB
from study import read_columns
from study.stability import ONSET_DE00, running_median

GRAZING = paths.DERIVED / "stability_grazing.csv"
ALIASING = paths.DERIVED / "stability_aliasing.csv"
METHODS = {"bubbleoptics": ("bubbleoptics", "o"), "tmm": ("tmm", "s"), "naive": (r"textbook, $\sqrt{1-\sin^2}$", "^")}
FILMS_T = ("water", "matched", "absorbing", "ftir")  # films with T > 0 near grazing
FLOOR = 1e-18
EPS = np.finfo(float).eps
STRIP_BANDS = (8, 16, 32, 81)
BANDLIMITED_STRIP = 8  # the band-limited strip, when the CSV has that method
LEGEND_FREE = 0.86  # (b)'s onset lines stop at this fraction of the height, below the legend


def read_table(path):
    """Columns of a CSV as arrays (:func:`study.read_columns`); exits with a message
    if the file is missing."""
    if not path.exists():
        raise SystemExit(f"{path} is missing: run python benchmarks/stability.py first")
    return read_columns(path)


def select(table, **conditions):
    mask = np.ones(len(next(iter(table.values()))), dtype=bool)
    for key, value in conditions.items():
        mask &= table[key] == value
    return {k: v[mask] for k, v in table.items()}


def main(argv=None):
    paths.parse_args(__doc__.splitlines()[0], argv)
    grazing = read_table(GRAZING)
    aliasing = read_table(ALIASING)

    fig = style.figure(width=style.PAGE_WIDTH, height=4.3)
    colors = [c["color"] for c in style.matplotlib.rcParams["axes.prop_cycle"]]
    outer = fig.add_gridspec(2, 1, height_ratios=(2.2, 1.5))
    top = outer[0].subgridspec(1, 2, width_ratios=(1.0, 1.25))
    ax_a = fig.add_subplot(top[0])
    ax_b = fig.add_subplot(top[1])
    has_bandlimited = bool(np.any(aliasing["method"] == "bandlimited"))
    n_strips = len(STRIP_BANDS) + 1 + has_bandlimited
    strips_gs = outer[1].subgridspec(n_strips, 1, hspace=0.0)
    strips = [fig.add_subplot(strips_gs[i]) for i in range(n_strips)]

    # (a) grazing incidence
    worst = {}
    for (method, (label, marker)), color in zip(METHODS.items(), colors):
        worst[method] = 0.0
        for film in FILMS_T:
            s = select(grazing, film=film, method=method, polarization="unpolarized")
            order = np.argsort(s["u"])
            x, err = 10.0 ** -s["u"][order], s["rel_err_T"][order]
            worst[method] = max(worst[method], float(np.nanmax(err)))
            main_film = film == "water"
            ax_a.loglog(x, np.maximum(err, FLOOR), color=color, lw=1.0 if main_film else 0.5,
                        alpha=1.0 if main_film else 0.45, marker=marker if main_film else None,
                        ms=2.0, markevery=2, label=label if main_film else None, zorder=3 if main_film else 2)
    s = select(grazing, film="water", method="bubbleoptics", polarization="unpolarized")
    order = np.argsort(s["u"])
    ax_a.loglog(10.0 ** -s["u"][order], EPS / (2 * s["cos_theta"][order] ** 2), ":", color="0.2", lw=0.8,
                label=r"$\varepsilon/(2\cos^2\theta)$")
    ax_a.set_ylim(FLOOR / 2, 30)
    ax_a.set_xlim(0.6e-8, 1.6)
    ax_a.set_yticks(10.0 ** np.arange(-18, 1, 3))
    ax_a.set_xlabel(r"$\pi/2 - \theta$ (rad)")
    ax_a.set_ylabel(r"relative error of $T$")
    ax_a.legend(loc="upper right", fontsize=7, handlelength=1.6)
    ax_a.grid(True, which="major")
    ax_a.set_title("(a) near grazing incidence, 550 nm", loc="left")

    # (b) aliasing: colour difference against thickness
    ref = select(aliasing, method="reference_1nm")
    d = ref["thickness_nm"]
    k = float(ref["exposure"][0])
    bands = sorted({int(n) for n in select(aliasing, method="point")["n_bands"]})
    band_colors = dict(zip(bands, style.matplotlib.colormaps["viridis"](np.linspace(0.0, 0.88, len(bands)))))
    onsets = {}
    for N in bands:
        s = select(aliasing, method="point", n_bands=N)
        ax_b.semilogy(d / 1000, np.maximum(running_median(d, s["dE00"]), 1e-5), color=band_colors[N],
                      label=f"$N = {N}$")
        pred = float(s["onset_pred_400_nm"][0])
        onsets[N] = (pred, float(s["onset_measured_nm"][0]))
        if pred <= d[-1]:
            ax_b.axvline(pred / 1000, color=band_colors[N], ls="--", lw=0.6, ymax=LEGEND_FREE)
        if has_bandlimited:
            b = select(aliasing, method="bandlimited", n_bands=N)
            if b["dE00"].size:
                ax_b.semilogy(d / 1000, np.maximum(running_median(d, b["dE00"]), 1e-5), color=band_colors[N],
                              ls=":", lw=0.9)
    ax_b.axhline(ONSET_DE00, color="0.6", lw=0.5)  # the threshold of the measured onset
    ax_b.set_ylim(2e-4 if has_bandlimited else 1e-2, 3e3)  # head room for the legend
    ax_b.set_xlim(0, d[-1] / 1000)
    ax_b.set_xlabel(r"film thickness $d$ ($\mu$m)")
    ax_b.set_ylabel(r"$\Delta E_{00}$ against 1 nm (1 $\mu$m median)")
    ax_b.legend(loc="upper center", ncol=len(bands), fontsize=7, handlelength=1.2, columnspacing=0.9)
    ax_b.set_yticks(10.0 ** np.arange(-3 if has_bandlimited else -2, 3))
    title = "(b) $\\Delta E_{00}$, $N$ bands: point-sampled (solid)"
    ax_b.set_title(title + (", band-limited (dotted)" if has_bandlimited else ""), loc="left")

    # (c) the strips
    def strip(ax, XYZ, label):
        rgb = XYZ_to_display_sRGB(k * XYZ)
        ax.imshow(rgb[None], aspect="auto", extent=(d[0] / 1000, d[-1] / 1000, 0, 1), interpolation="nearest")
        ax.set_yticks([])
        ax.set_ylabel(label, rotation=0, ha="right", va="center", fontsize=7)
        ax.tick_params(top=False, right=False, bottom=False, labelbottom=False)

    strip(strips[0], np.stack([ref["X"], ref["Y"], ref["Z"]], axis=-1), "1 nm")
    for ax, N in zip(strips[1:], STRIP_BANDS):
        s = select(aliasing, method="point", n_bands=N)
        strip(ax, np.stack([s["X"], s["Y"], s["Z"]], axis=-1), f"$N = {N}$")
        pred = onsets[N][0]
        if pred <= d[-1]:
            ax.plot(pred / 1000, 0.5, "v", color="white", mec="black", mew=0.5, ms=4.5)
        meas = onsets[N][1]
        if meas <= d[-1]:
            ax.plot(meas / 1000, 0.5, "^", color="black", mec="white", mew=0.5, ms=4.5)
    if has_bandlimited:
        b = select(aliasing, method="bandlimited", n_bands=BANDLIMITED_STRIP)
        strip(strips[-1], np.stack([b["X"], b["Y"], b["Z"]], axis=-1), f"$N = {BANDLIMITED_STRIP}$,\nband-limited")
    strips[-1].tick_params(bottom=True, direction="out", labelbottom=True)
    strips[-1].set_xlabel(r"film thickness $d$ ($\mu$m)")
    strips[0].set_title("(c) the colours: 1 nm spectra and $N$ point-sampled bands; "
                        "$\\triangledown$ predicted onset, $\\blacktriangle$ measured", loc="left")

    for method, value in worst.items():
        print(f"worst relative error of T, films with T > 0: {method} {value:.1e}")
    for N, (pred, meas) in onsets.items():
        print(f"N = {N:>2}: aliasing onset predicted {pred / 1000:.2f} um (400 nm), measured {meas / 1000:.2f} um")
    for path in style.savefig(fig, "fig_stability"):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
