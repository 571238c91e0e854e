"""Figure: our spectral reference and Cycles on the same bubbles, their colour difference, and
error against time.

Run:  python paper/scripts/fig_peer_cycles.py [--quick]
Reads ``data/derived/peer_cycles_images.npz`` and ``data/derived/peer_cycles.csv`` (written by
``benchmarks/peer_cycles.py``, which needs Blender's ``bpy`` in its own venv: ``make peers``);
writes ``fig_peer_cycles.pdf``/``.png``.  Nothing is rendered here, so quick mode draws the
same figure.

Left, one column per film thickness: (top) our reference (spectral, converged), (middle)
Cycles (two seeds averaged), both in sRGB, cropped to the bubble and contrast-stretched alike
(:func:`stretch`: each sRGB channel from the 1st to the 99th percentile of the reference's over
the bubble onto [0, 1], the same map for both renderers of a column, so that the film's colours,
a few per cent of the light, show); (bottom) the per-pixel CIEDE2000 between them (the scale
stops at ``DE_MAX``, larger values in its top colour, the bar's arrow).  Right: mean CIEDE2000
over the bubble against seconds per image for Cycles (1-256 spp) and our tracer at its defaults
(1-16 spp), median of the runs with min-max bars, log-log; dashed: Cycles against its own
converged image (its noise alone); the dotted line is Cycles' converged difference from the
reference, and, where ``data/derived/peer_cycles_lifting.csv`` exists
(``benchmarks/peer_cycles_lifting.py``), the short marks at the left edge are the same
difference with the reference's environment lifted to spectra by the other methods (closed
form, one mark per method).
"""

import sys

import numpy as np

import paths
import style
from bubbleoptics.colorimetry import linear_srgb_to_srgb
from study import read_commented_csv

IMAGES = paths.DERIVED / "peer_cycles_images.npz"
TABLE = paths.DERIVED / "peer_cycles.csv"
LIFTING = paths.DERIVED / "peer_cycles_lifting.csv"
DE_MAX = 5.0  # top of the colour scale of the difference maps
CROP_MARGIN = 0.06  # of the image size, around the bubble's silhouette
#: the bubble's silhouette radius over half the image (peer_cycles: radius 1 at distance 4, fov 40 deg)
RHO = float(np.tan(np.arcsin(0.25)) / np.tan(np.radians(20.0)))


def _load():
    for path in (IMAGES, TABLE):
        if not path.exists():
            raise SystemExit(f"{path} is missing: run make peers and make bench-peers first (docs/peers.md)")
    data = np.load(IMAGES)
    _, rows = read_commented_csv(TABLE)
    return data, rows


def crop(image, margin=CROP_MARGIN):
    """The square around the bubble (the silhouette of the peer_cycles scene: radius 1 at
    distance 4, vertical field of view 40 degrees), *margin* of the image size around it."""
    size = image.shape[0]
    half = int(np.ceil((RHO + 2.0 * margin) * size / 2.0))
    lo, hi = max(0, size // 2 - half), min(size, size // 2 + half)
    return image[lo:hi, lo:hi]


def stretch(srgb, reference):
    """*srgb* mapped linearly, channel by channel, from the 1st-99th percentile of *reference*'s
    values (both sRGB, reference (P, 3)) onto [0, 1], clipped."""
    lo, hi = np.percentile(reference, [1.0, 99.0], axis=0)
    return np.clip((srgb - lo) / np.maximum(hi - lo, 1e-6), 0.0, 1.0)


def _lifting_floors(d):
    """{method: mean CIEDE2000 over the bubble of Cycles' render against the closed form with
    that lifting} at film *d* (the corrected liftings other than the tracer's), or {}."""
    if not LIFTING.exists():
        return {}
    _, rows = read_commented_csv(LIFTING)
    return {r["lifting"]: float(r["bubble_mean"]) for r in rows
            if r["section"] == "closed_form" and r["variant"] == "corrected" and r["lifting"] != "Mallett2019"
            and r["setting"].startswith("Cycles render") and float(r["thickness_nm"]) == d}


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
        srgb = {name: crop(np.clip(linear_srgb_to_srgb(np.clip(data[f"{name}_{key}"].astype(float), 0, None)), 0, 1))
                for name in ("ref", "cycles")}
        inside = crop(np.hypot(*np.meshgrid(*2 * [np.linspace(-1, 1, data[f"ref_{key}"].shape[0])])))
        bubble = srgb["ref"][inside < 0.9 * RHO]  # the bubble, not the background around it
        for row, (name, label) in enumerate((("ref", "ours (reference)"), ("cycles", "Cycles"))):
            ax = fig.add_subplot(grid[row, k])
            ax.imshow(stretch(srgb[name], bubble), interpolation="nearest")
            if row == 0:
                ax.set_title(f"{key} nm")
            if k == 0:
                ax.set_ylabel(label)
            image_axes.append(ax)
        ax = fig.add_subplot(grid[2, k])
        im = ax.imshow(crop(data[f"de_{key}"].astype(float)), cmap="magma", vmin=0.0, vmax=DE_MAX,
                       interpolation="nearest")
        if k == 0:
            ax.set_ylabel(r"$\Delta E_{00}$")
        image_axes.append(ax)
    for ax in image_axes:
        ax.set_xticks([])
        ax.set_yticks([])
    bar = fig.colorbar(im, ax=image_axes[-1], fraction=0.08, pad=0.04, ticks=[0, DE_MAX], extend="max")
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
                    linewidth=0.8, label="Cycles vs own converged")
    one_thread = [r for r in rows if r["section"] == "timing_1_thread"]
    for ci, renderer in enumerate(("ours", "cycles")):  # the same sweeps on one thread: thin, no markers' labels
        curve = sorted((r for r in one_thread if r["renderer"] == renderer), key=lambda r: int(r["spp"]))
        if curve:
            ax.plot([float(r["seconds"]) for r in curve], [float(r["bubble_mean"]) for r in curve], "-.",
                    marker="o", markersize=2, color=colors[ci], linewidth=0.8)
    if one_thread:  # one legend entry for both renderers' one-thread curves, in neither's colour
        ax.plot([], [], "-.", marker="o", markersize=2, color="0.3", linewidth=0.8, label="one thread (both)")
    if timing:
        d = float(timing[0]["thickness_nm"])
        floor = next((r for r in rows if r["section"] == "comparison" and r["renderer"] == "cycles"
                      and r["setting"].startswith("mean") and float(r["thickness_nm"]) == d), None)
        if floor is not None:
            ax.axhline(float(floor["bubble_mean"]), color="0.55", linestyle=":", linewidth=0.8)
            ax.annotate("Cycles converged", (0.3, float(floor["bubble_mean"])), xycoords=("axes fraction", "data"),
                        textcoords="offset points", xytext=(0, 2), fontsize=7, color="0.4")
        floors = _lifting_floors(d)
        for value in floors.values():  # at the left edge, where no curve passes at these errors
            ax.plot([0.0, 0.05], [value, value], transform=ax.get_yaxis_transform(), color="0.35", linewidth=1.2,
                    solid_capstyle="butt")
        if floors:
            ax.annotate("the same, other liftings", (0.06, max(floors.values())), xycoords=("axes fraction", "data"),
                        va="center", fontsize=7, color="0.35")
        ax.set_title(f"film {d:g} nm: error against time", loc="left")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("seconds per image")
    ax.set_ylabel(r"mean $\Delta E_{00}$ over the bubble")
    ax.grid(True, which="major")
    # the free space between the two curves, below Cycles' converged line (no corner is free)
    ax.legend(loc="upper left", bbox_to_anchor=(0.14, 0.44), frameon=False)
    for path in style.savefig(fig, "fig_peer_cycles"):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
