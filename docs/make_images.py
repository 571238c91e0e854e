"""The pictures of docs/images/, from the renderer (run: python docs/make_images.py).

``views.png``: the built-in bubble scene (``tracer.default_scene()``, 400x400, the render
defaults otherwise) rendered once and shown three ways: as saved by default (exposure 0, the
``clip`` view), two stops brighter with the ``clip`` view (each channel clipped to [0, 1] in
linear light: the films' brightest fringes clip and flatten, and so do the highlights), and
two stops brighter with the ``aces`` view (OpenColorIO's ACES 2.0 sRGB output transform:
highlights roll off towards white, colours outside the gamut are compressed into it, and
mid-tones come out darker than with ``clip``).
Needs the ``view``
extra (``pip install 'bubbleoptics[view]'``).
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import tracer  # noqa: E402
from tracer.rendering.output import display_image  # noqa: E402

HERE = Path(__file__).resolve().parent / "images"
SIZE = 400
PANELS = [(0.0, "clip", "exposure 0, view clip (the default)"),
          (2.0, "clip", "exposure +2, view clip"),
          (2.0, "aces", "exposure +2, view aces (ACES 2.0)")]


def main():
    image = tracer.render(tracer.default_scene(), width=SIZE, height=SIZE, progress=False)
    fig, axes = plt.subplots(1, len(PANELS), figsize=(3.3 * len(PANELS), 3.6), dpi=150)
    for ax, (exposure, view, title) in zip(axes, PANELS):
        ax.imshow(display_image(image, exposure=exposure, view=view), interpolation="nearest")
        ax.set_title(title, fontsize=9)
        ax.set_axis_off()
    fig.tight_layout(pad=0.4)
    HERE.mkdir(exist_ok=True)
    out = HERE / "views.png"
    fig.savefig(out, metadata={"Software": None})
    print(out)


if __name__ == "__main__":
    main()
