"""The thin-film demo: ``python -m bubbleoptics.demo [--out DIR]``.

Writes two figures of a free-standing water film in air (water's dispersive index, Daimon &
Masumura 2007) to DIR (default ``demo-output/``) and prints the absolute path of each:

* ``reflectance_vs_thickness.png``: R against thickness 0-2000 nm at 450, 550 and 650 nm, at
  normal incidence and at 60°, unpolarized; exact Airy sum (solid) and the coursework's two-beam model
  (dashed).
* ``interference_colors.png``: the reflected interference colours under D65 for 0-2000 nm at 0°
  and 60°.

Each file is written atomically (a temporary file in DIR, then renamed over the target).
"""

import argparse
import pathlib
import sys

import numpy as np

from .plotting import new_figure, plot_color_strip, plot_reflectance_vs_thickness, save_figure_atomic

__all__ = ["main", "write_demo_figures"]

THICKNESS_NM = np.linspace(0.0, 2000.0, 2001)
WAVELENGTHS_NM = (450.0, 550.0, 650.0)
ANGLES_DEG = (0.0, 60.0)
DPI = 150


def _reflectance_figure():
    fig, axes = new_figure(
        len(WAVELENGTHS_NM), len(ANGLES_DEG), figsize=(11, 7), sharex=True, sharey="col", squeeze=False
    )
    for col, deg in enumerate(ANGLES_DEG):
        theta = np.deg2rad(deg)
        for row, wl in enumerate(WAVELENGTHS_NM):
            ax = axes[row, col]
            plot_reflectance_vs_thickness(
                ax, THICKNESS_NM, (wl,), theta, label="exact (Airy sum)", linewidth=1.2
            )
            plot_reflectance_vs_thickness(
                ax, THICKNESS_NM, (wl,), theta, model="two_beam", label="two-beam model",
                color="0.25", linestyle="--", linewidth=0.9,
            )
            ax.set_xlim(THICKNESS_NM[0], THICKNESS_NM[-1])
            ax.set_ylim(0.0, 1.3 * max(line.get_ydata().max() for line in ax.get_lines()))
            ax.text(0.99, 0.93, f"λ = {wl:g} nm", transform=ax.transAxes, ha="right", va="top",
                    bbox=dict(boxstyle="round", facecolor="white", alpha=0.8, linewidth=0))
            if row == 0:
                ax.set_title(f"angle of incidence θ = {deg:g}°")
            if row != len(WAVELENGTHS_NM) - 1:
                ax.set_xlabel("")
            if col != 0:
                ax.set_ylabel("")
    axes[0, 0].legend(loc="upper left", ncol=2, fontsize="small", framealpha=0.9)
    fig.suptitle("Free-standing water film in air, unpolarized light: reflectance against thickness")
    return fig


def _colors_figure():
    fig, axes = new_figure(len(ANGLES_DEG), 1, figsize=(11, 3.2), sharex=True, squeeze=False)
    for ax, deg in zip(axes[:, 0], ANGLES_DEG):
        plot_color_strip(ax, THICKNESS_NM, np.deg2rad(deg))
    axes[0, 0].set_xlabel("")
    ax = axes[-1, 0]
    ax.set_xticks(np.arange(0, 2001, 200))
    ax.set_xticks(np.arange(0, 2001, 50), minor=True)
    fig.suptitle(
        "Reflected interference colours of a water film in air (D65, unpolarized); "
        "each strip's exposure (×k) puts its brightest thickness at white",
        fontsize="medium",
    )
    return fig


def write_demo_figures(out_dir="demo-output"):
    """Write both demo figures into *out_dir* (created if needed); return their absolute paths."""
    out = pathlib.Path(out_dir).resolve()
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for name, make in (("reflectance_vs_thickness.png", _reflectance_figure),
                       ("interference_colors.png", _colors_figure)):
        written.append(pathlib.Path(save_figure_atomic(make(), out / name, dpi=DPI)))
    return written


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="python -m bubbleoptics.demo",
        description="Plot the reflectance and interference colours of a soap film (water in air).",
    )
    parser.add_argument("--out", default="demo-output", metavar="DIR",
                        help="output folder, created if missing (default: %(default)s)")
    args = parser.parse_args(argv)
    for path in write_demo_figures(args.out):
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
