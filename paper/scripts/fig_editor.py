"""Figure: the scene editor in a browser, the screenshot its browser test takes.

Run:  python paper/scripts/fig_editor.py [--quick]
Reads ``docs/images/editor.png`` (written by ``tests/tracer/test_editor_browser.py`` with
``BUBBLEOPTICS_UPDATE_SCREENSHOT=1``: ``tracer edit`` at 400 x 400 in headless Chromium, after
the test's edits, a picked pixel and a refused value); writes ``fig_editor.pdf``/``.png`` at the
column width.  The screenshot is placed as it is (no text is drawn on it).  Quick mode draws the
same figure.
"""

import sys

import numpy as np
from PIL import Image

import paths
import style

SCREENSHOT = paths.ROOT / "docs" / "images" / "editor.png"


def main(argv=None):
    paths.parse_args(__doc__.splitlines()[0], argv)
    with Image.open(SCREENSHOT) as image:
        pixels = np.asarray(image.convert("RGB"))
    height, width = pixels.shape[:2]
    fig = style.figure(width=style.COLUMN_WIDTH, height=style.COLUMN_WIDTH * height / width)
    fig.set_layout_engine("none")
    ax = fig.add_axes((0, 0, 1, 1))
    ax.imshow(pixels, interpolation="lanczos")
    ax.set_axis_off()
    for path in style.savefig(fig, "fig_editor"):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
