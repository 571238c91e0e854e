"""Figure: reflectance of a water film against thickness, and its interference colours.

Run:  python paper/scripts/fig_thin_film.py [--quick]
Computes with the bubbleoptics package (no data files); writes ``fig_thin_film.pdf``/``.png``.

Top: exact (Airy) reflectance R of a free-standing water film in air (Daimon & Masumura 2007
dispersion) at normal incidence, unpolarized, against thickness 0-1000 nm, at 450, 550 and
650 nm (solid), with the coursework's two-beam model at 550 nm (dashed).  Below it, the
two-beam model's error at 550 nm, its largest value marked (:func:`two_beam_gap`, which
``numbers_physics.py`` quotes as ``\\TwoBeamErrFig``).  Bottom: the reflected
colour under D65 for 0-2000 nm at 0° and 60°, each strip with the exposure that makes its
brightest film white (×k).  Drawn with ``bubbleoptics.plotting``.  Quick mode: 5 nm steps in
thickness and wavelength instead of 1 nm.
"""

import sys

import numpy as np

import paths
import style
from bubbleoptics.plotting import film_strip_colors, plot_color_strip, plot_reflectance_vs_thickness

TWO_BEAM_NM = 550.0  # the wavelength at which the two-beam model is drawn
D_MAX_NM = 1000.0  # the reflectance panel's thickness range, 0 to this


def two_beam_gap(step=1.0):
    """``(d, R, R_two_beam, gap, peak)`` at normal incidence and ``TWO_BEAM_NM`` over the panel's
    thicknesses (every *step* nm): where ``|R_two_beam - R|`` is largest, its value, and the
    largest exact R there (the peak the gap is compared with)."""
    import bubbleoptics as bo

    d = np.arange(0.0, D_MAX_NM + step / 2, step)
    exact = bo.film_reflectance(TWO_BEAM_NM, d, 0.0)
    two_beam = bo.two_beam_reflectance(TWO_BEAM_NM, d, 0.0)
    i = int(np.argmax(np.abs(two_beam - exact)))
    return float(d[i]), float(exact[i]), float(two_beam[i]), float(abs(two_beam[i] - exact[i])), float(exact.max())


def main(argv=None):
    args = paths.parse_args(__doc__.splitlines()[0], argv)
    step = 5.0 if args.quick else 1.0
    d_r = np.arange(0.0, D_MAX_NM + step / 2, step)
    d_strip = np.arange(0.0, 2000.0 + step / 2, step)
    wl = np.arange(360.0, 780.0 + step / 2, step)

    fig = style.figure(height=3.6)
    ax, ax_gap, *strips = fig.subplots(4, 1, height_ratios=(3.0, 1.0, 0.42, 0.42))
    lines = plot_reflectance_vs_thickness(ax, d_r, (450.0, 550.0, 650.0), 0.0, label="{wavelength:g} nm")
    plot_reflectance_vs_thickness(ax, d_r, (TWO_BEAM_NM,), 0.0, model="two_beam",
                                  label=f"{TWO_BEAM_NM:g} nm, two-beam", linestyle="--", linewidth=0.8, color="0.35")
    ax.set_xlim(d_r[0], d_r[-1])
    ax.set_ylim(0.0, 0.112)  # head room for the legend above the fringes (R < 0.085)
    ax.set_ylabel("reflectance $R$")
    ax.tick_params(labelbottom=False)
    ax.set_xlabel("")  # the panel below carries the thickness axis
    # the two-beam model's error at TWO_BEAM_NM, the curve whose largest value the text quotes
    d_gap, r_exact, r_two, gap, _ = two_beam_gap(step)
    import bubbleoptics as bo

    diff = bo.two_beam_reflectance(TWO_BEAM_NM, d_r, 0.0) - bo.film_reflectance(TWO_BEAM_NM, d_r, 0.0)
    ax_gap.plot(d_r, diff, "--", color="0.35", linewidth=0.8)
    ax_gap.axhline(0.0, color="0.6", linewidth=0.5)
    ax_gap.plot(d_gap, r_two - r_exact, "o", color="0.2", markersize=2.5)
    ax_gap.annotate(f"{gap:.2g}", (d_gap, r_two - r_exact), textcoords="offset points", xytext=(4, -2),
                    fontsize=7, color="0.2", va="top")
    ax_gap.set_xlim(d_r[0], d_r[-1])
    ax_gap.set_xlabel("film thickness $d$ (nm)")
    ax_gap.set_ylabel("two-beam\n$-$ exact", fontsize=7)
    ax.legend(loc="upper center", ncol=4, columnspacing=0.8, handlelength=1.4, handletextpad=0.4,
              borderaxespad=0.2)
    r_max = max(float(np.max(line.get_ydata())) for line in lines)

    for sub, deg in zip(strips, (0.0, 60.0)):
        _, k = film_strip_colors(d_strip, np.deg2rad(deg), exposure="auto", wavelengths_nm=wl)
        # the label in mathtext: cmr10 maps U+00B0 to a ligature glyph, so no literal degree sign
        plot_color_strip(sub, d_strip, np.deg2rad(deg), wavelengths_nm=wl,
                         label=f"${deg:g}^\\circ$\n$\\times{k:.3g}$")
        sub.yaxis.label.set_fontsize(7)
        sub.tick_params(top=False, direction="out")
        sub.set_xlabel("")
    strips[0].tick_params(labelbottom=False)
    strips[1].set_xlabel("film thickness $d$ (nm)")
    print(f"largest reflectance at normal incidence: {r_max:.4f}; two-beam gap at {TWO_BEAM_NM:g} nm: {gap:.4f} "
          f"at {d_gap:g} nm")
    for path in style.savefig(fig, "fig_thin_film"):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
