"""Figure: our spectral reference and Cycles on the same bubbles, their colour difference, and
error against time.

Run:  python paper/scripts/fig_peer_cycles.py [--quick]
Reads ``data/derived/peer_cycles_images.npz`` and ``data/derived/peer_cycles.csv`` (written by
``benchmarks/peer_cycles.py``, which needs Blender's ``bpy`` in its own venv: ``make peers``);
writes ``fig_peer_cycles.pdf``/``.png``.  Nothing is rendered here, so quick mode draws the
same figure.

Left, one column per film thickness: (top) our reference (spectral, converged), (middle)
Cycles (two seeds averaged), both in sRGB; (bottom) the per-pixel CIEDE2000 between them.
Right: mean CIEDE2000 over the bubble against seconds per image for Cycles (1-256 spp) and our
tracer at its defaults (1-16 spp), median of the runs with min-max bars, log-log; dashed: Cycles
against its own converged image (its noise alone); the dotted line is Cycles' converged
difference from the reference.
"""

import sys

import numpy as np

import paths
import style
from bubbleoptics.colorimetry import linear_srgb_to_srgb
from study import read_commented_csv

IMAGES = paths.DERIVED / "peer_cycles_images.npz"
TABLE = paths.DERIVED / "peer_cycles.csv"
DE_MAX = 5.0  # top of the colour scale of the difference maps


def _load():
    for path in (IMAGES, TABLE):
        if not path.exists():
            raise SystemExit(f"{path} is missing: run make peers and make bench-peers first (docs/peers.md)")
    data = np.load(IMAGES)
    _, rows = read_commented_csv(TABLE)
    return data, rows


def main(argv=None):
    paths.parse_args(__doc__.splitlines()[0], argv)
    data, rows = _load()
    thicknesses = [float(t) for t in data["thicknesses"]]
    n = len(thicknesses)
    fig = style.figure(width=style.PAGE_WIDTH, height=3.6)  # both columns (paper.tex: figure*)
    grid = fig.add_gridspec(3, n + 1, width_ratios=[1.0] * n + [1.9])
    image_axes = []
    for k, d in enumerate(thicknesses):
        key = f"{d:g}"
        for row, (name, label) in enumerate((("ref", "ours (reference)"), ("cycles", "Cycles"))):
            ax = fig.add_subplot(grid[row, k])
            ax.imshow(np.clip(linear_srgb_to_srgb(np.clip(data[f"{name}_{key}"].astype(float), 0, None)), 0, 1),
                      interpolation="nearest")
            if row == 0:
                ax.set_title(f"{key} nm")
            if k == 0:
                ax.set_ylabel(label)
            image_axes.append(ax)
        ax = fig.add_subplot(grid[2, k])
        im = ax.imshow(data[f"de_{key}"].astype(float), cmap="magma", vmin=0.0, vmax=DE_MAX, interpolation="nearest")
        if k == 0:
            ax.set_ylabel(r"$\Delta E_{00}$")
        image_axes.append(ax)
    for ax in image_axes:
        ax.set_xticks([])
        ax.set_yticks([])
    bar = fig.colorbar(im, ax=image_axes[-1], fraction=0.08, pad=0.04, ticks=[0, DE_MAX])
    bar.ax.tick_params(labelsize=7)

    ax = fig.add_subplot(grid[:, n])
    colors = [c["color"] for c in style.matplotlib.rcParams["axes.prop_cycle"]]
    timing = [r for r in rows if r["section"] == "timing"]
    for ci, (renderer, label) in enumerate((("ours", "ours, defaults"), ("cycles", "Cycles"))):
        curve = sorted((r for r in timing if r["renderer"] == renderer), key=lambda r: int(r["spp"]))
        if not curve:
            continue
        t = np.array([float(r["seconds"]) for r in curve])
        lo = t - np.array([float(r["seconds_min"]) for r in curve])
        hi = np.array([float(r["seconds_max"]) for r in curve]) - t
        e = np.array([float(r["bubble_mean"]) for r in curve])
        ax.errorbar(t, e, xerr=[lo, hi], fmt="-o", color=colors[ci], markersize=3, capsize=1.5, label=label,
                    linewidth=1.0, elinewidth=0.7)
        for r, tk, ek in zip(curve, t, e):
            ax.annotate(r["spp"], (tk, ek), textcoords="offset points", xytext=(3, 3), fontsize=7, color=colors[ci])
        if renderer == "cycles" and curve[0].get("own_bubble_mean"):
            own = np.array([float(r["own_bubble_mean"]) for r in curve])
            ax.plot(t, own, "--", marker="o", markersize=2.5, color=colors[ci], markerfacecolor="white",
                    linewidth=0.8, label="Cycles vs its own converged image")
    if timing:
        d = float(timing[0]["thickness_nm"])
        floor = next((r for r in rows if r["section"] == "comparison" and r["renderer"] == "cycles"
                      and r["setting"].startswith("mean") and float(r["thickness_nm"]) == d), None)
        if floor is not None:
            ax.axhline(float(floor["bubble_mean"]), color="0.55", linestyle=":", linewidth=0.8)
            ax.annotate("Cycles converged", (0.03, float(floor["bubble_mean"])), xycoords=("axes fraction", "data"),
                        textcoords="offset points", xytext=(0, 2), fontsize=7, color="0.4")
        ax.set_title(f"film {d:g} nm: error against time", loc="left")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("seconds per image")
    ax.set_ylabel(r"mean $\Delta E_{00}$ over the bubble")
    ax.grid(True, which="major")
    ax.legend(loc="lower left", frameon=False)
    for path in style.savefig(fig, "fig_peer_cycles"):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
