"""Figure: the coursework's two-beam film model in rendered images, against the exact Airy sum.

Run:  python paper/scripts/fig_two_beam_render.py [--quick]
Reads ``data/derived/two_beam_render.npz`` (written by ``benchmarks/two_beam_render.py``: 8-bit
display images of both models and the ΔE00 map per scene); writes ``fig_two_beam_render.pdf``/
``.png``.  One row per scene (the built-in scene, the six gallery bubbles): the exact render,
the two-beam render and the ΔE00 of the second against the first, on a scale clipped at
:data:`DE_MAX`.  Quick mode draws the same figure (it only reads the stored images).
"""

import sys

import numpy as np

import paths
import style

DATA = paths.DERIVED / "two_beam_render.npz"
SCENES = {"builtin": "built-in scene", "bubbles": "six bubbles"}
DE_MAX = 10.0


def main(argv=None):
    paths.parse_args(__doc__.splitlines()[0], argv)
    if not DATA.exists():
        print(f"fig_two_beam_render: {DATA} is missing; run benchmarks/two_beam_render.py", file=sys.stderr)
        return 2
    with np.load(DATA) as f:
        data = {k: f[k] for k in f.files}
    fig = style.figure(height=2.35)
    axes = fig.subplots(len(SCENES), 3)
    shown = None
    for row, (name, label) in zip(axes, SCENES.items()):
        row[0].imshow(data[f"{name}_airy"], interpolation="nearest")
        row[1].imshow(data[f"{name}_two_beam"], interpolation="nearest")
        shown = row[2].imshow(np.asarray(data[f"{name}_de00"], float), cmap="magma", vmin=0.0, vmax=DE_MAX,
                              interpolation="nearest")
        row[0].set_ylabel(label)
        for ax in row:
            ax.set_xticks([])
            ax.set_yticks([])
            for spine in ax.spines.values():
                spine.set_visible(False)
    for ax, title in zip(axes[0], ("exact (Airy)", "two-beam", "$\\Delta E_{00}$")):
        ax.set_title(title, fontsize=8, pad=2)
    bar = fig.colorbar(shown, ax=axes[:, 2], shrink=0.8, extend="max")
    bar.set_ticks([0, 2, 4, 6, 8, 10])
    for path in style.savefig(fig, "fig_two_beam_render"):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
