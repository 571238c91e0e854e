"""Figure: the scene editor in a browser, cut from the screenshot its browser test takes.

Run:  python paper/scripts/fig_editor.py [--quick]
Reads ``docs/images/editor.png`` (written by ``tests/tracer/test_editor_browser.py`` with
``BUBBLEOPTICS_UPDATE_SCREENSHOT=1``: ``tracer edit`` in headless Chromium, after the test's
edits, a picked pixel and a refused value); writes ``fig_editor.pdf``/``.png`` at the column width.

The whole screenshot (1300 pixels wide, its type 11-12 pixels) would print its type at about
4 pt in a 3.4 in column, so the figure shows four crops of it instead (:data:`CROPS`): (a) the
rendered image, which has no type and is scaled down freely; (b) the depth field with the
message that refuses its value; (c) the picked pixel's film reflectance; (d) its colour swatch
and description.  Every crop that carries type is drawn at :data:`PX_PER_IN` screenshot pixels
per inch, so its smallest type (``text_px`` pixels, measured on the screenshot: the plot's tick
digits are 8 pixels tall, i.e. 11-pixel type; the messages are 12-pixel type) prints at
``text_px / PX_PER_IN * 72`` >= 7 pt; ``style.savefig`` checks it from ``image.text_px``.
Nothing is drawn on the crops.  Quick mode draws the same figure.
"""

import sys

import numpy as np
from PIL import Image

import paths
import style

SCREENSHOT = paths.ROOT / "docs" / "images" / "editor.png"
PX_PER_IN = 108.0  # screenshot pixels per printed inch for the crops with type: 11 px type -> 7.3 pt
#: name: (title, (left, top, right, bottom) in screenshot pixels, smallest type in pixels or None)
CROPS = {
    "render": ("(a) the render", (620, 0, 1180, 560), None),
    "refused": ("(b) a refused value", (0, 965, 180, 1095), 12.0),
    "plot": ("(c) the picked pixel's reflectance", (620, 610, 920, 835), 11.0),
    "swatch": ("(d) its colour", (925, 615, 1230, 670), 12.0),
}
RENDER_IN = 1.62  # the render's printed width (it has no type)
TITLE_IN = 0.2  # room above each crop for its title
GAP_IN = 0.06


def crop(pixels, box):
    left, top, right, bottom = box
    height, width = pixels.shape[:2]
    if not (0 <= left < right <= width and 0 <= top < bottom <= height):
        raise SystemExit(f"fig_editor: crop {box} is outside the {width} x {height} screenshot {SCREENSHOT}")
    return pixels[top:bottom, left:right]


def main(argv=None):
    paths.parse_args(__doc__.splitlines()[0], argv)
    with Image.open(SCREENSHOT) as image:
        pixels = np.asarray(image.convert("RGB"))
    parts = {name: crop(pixels, box) for name, (_, box, _) in CROPS.items()}

    def size_in(name):
        rows, cols = parts[name].shape[:2]
        if CROPS[name][2] is None:
            return RENDER_IN, RENDER_IN * rows / cols
        return cols / PX_PER_IN, rows / PX_PER_IN

    width = style.COLUMN_WIDTH
    (rw, rh), (fw, fh), (pw, ph), (sw, sh) = (size_in(n) for n in CROPS)
    if rw + GAP_IN + fw > width or max(pw, sw) > width:
        raise SystemExit("fig_editor: the crops do not fit the column; narrow CROPS or lower RENDER_IN")
    top_row = TITLE_IN + max(rh, fh)
    height = top_row + GAP_IN + TITLE_IN + ph + GAP_IN + TITLE_IN + sh
    # (x, y of the lower left corner) in inches for each crop
    places = {
        "render": (0.0, height - TITLE_IN - rh),
        "refused": (width - fw, height - TITLE_IN - fh),
        "plot": (0.0, height - top_row - GAP_IN - TITLE_IN - ph),
        "swatch": (0.0, 0.0),
    }
    fig = style.figure(width=width, height=height)
    fig.set_layout_engine("none")
    for name, (title, _, text_px) in CROPS.items():
        w, h = size_in(name)
        x, y = places[name]
        ax = fig.add_axes((x / width, y / height, w / width, h / height))
        shown = ax.imshow(parts[name], interpolation="lanczos" if text_px is None else "antialiased")
        if text_px is not None:
            shown.text_px = text_px  # read by style.savefig's legibility check
        ax.set_axis_off()
        fig.text(x / width, (y + h + 0.04) / height, title, fontsize=8, ha="left", va="bottom")
    for path in style.savefig(fig, "fig_editor"):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
