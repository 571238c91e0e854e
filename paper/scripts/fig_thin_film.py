"""Figure: reflectance of a water film against thickness, and its interference colours.

Run:  python paper/scripts/fig_thin_film.py [--quick]
Computes with the bubbleoptics package (no data files); writes ``fig_thin_film.pdf``/``.png``.

Top: exact (Airy) reflectance R of a free-standing water film in air (Daimon & Masumura 2007
dispersion) at normal incidence, unpolarized, against thickness 0-1000 nm, at 450, 550 and
650 nm (solid), with the coursework's two-beam model at 550 nm (dashed).  Bottom: the reflected
colour under D65 for 0-2000 nm at 0° and 60°, each strip with the exposure that makes its
brightest film white (×k).  Drawn with ``bubbleoptics.plotting``.  Quick mode: 5 nm steps in
thickness and wavelength instead of 1 nm.
"""

import sys

import numpy as np

import paths
import style
from bubbleoptics.plotting import film_strip_colors, plot_color_strip, plot_reflectance_vs_thickness


def main(argv=None):
    args = paths.parse_args(__doc__.splitlines()[0], argv)
    step = 5.0 if args.quick else 1.0
    d_r = np.arange(0.0, 1000.0 + step / 2, step)
    d_strip = np.arange(0.0, 2000.0 + step / 2, step)
    wl = np.arange(360.0, 780.0 + step / 2, step)

    fig = style.figure(height=2.9)
    ax, *strips = fig.subplots(3, 1, height_ratios=(3.0, 0.42, 0.42))
    lines = plot_reflectance_vs_thickness(ax, d_r, (450.0, 550.0, 650.0), 0.0, label="{wavelength:g} nm")
    plot_reflectance_vs_thickness(ax, d_r, (550.0,), 0.0, model="two_beam", label="550 nm, two-beam",
                                  linestyle="--", linewidth=0.8, color="0.35")
    ax.set_xlim(d_r[0], d_r[-1])
    ax.set_ylim(0.0, 0.112)  # head room for the legend above the fringes (R < 0.085)
    ax.set_xlabel("film thickness $d$ (nm)")
    ax.set_ylabel("reflectance $R$")
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
    print(f"largest reflectance at normal incidence: {r_max:.4f}")
    for path in style.savefig(fig, "fig_thin_film"):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
