"""The paper's one matplotlib style, figure sizes, and saving.

``use()`` applies ``bubbleoptics.mplstyle`` (beside this file): Computer Modern serif text and
mathematics without LaTeX, 8 pt type, the Okabe-Ito colour cycle, 200 dpi, PDF fonts embedded
as TrueType.  ``figure()`` makes a figure one column (3.4 in) or the full page (7.0 in) wide on
the Agg canvas (no pyplot, no display).  ``savefig(fig, name)`` writes ``name.pdf`` and
``name.png`` into ``paths.FIGURES``, each atomically (``bubbleoptics.plotting.save_figure_atomic``),
and returns their paths, after checking that the figure is legible at print size: every text
it draws is at least ``MIN_FONT_PT`` tall (:func:`small_texts`), every text and legend lies
inside the figure's box (:func:`outside_texts`), and every raster image that carries text (a
screenshot: the script sets ``image.text_px``, the height in the image's pixels of its smallest
type) is scaled so that type prints at ``MIN_FONT_PT`` or more.  What was checked is written
beside the figure as ``name.legibility.json`` (:func:`legibility`), which
``tests/paper/test_figure_legibility.py`` reads back.  The figures are placed in the
paper at their natural size (``\\paperfigure`` in paper.tex), so these sizes are the printed
ones; ``tests/paper/test_paper_figures.py`` checks each PDF's width against its slot in paper.tex.
"""

from __future__ import annotations

import json
import logging
from pathlib import Path

import matplotlib
import matplotlib.style

import paths

__all__ = ["STYLE_FILE", "COLUMN_WIDTH", "PAGE_WIDTH", "MIN_FONT_PT", "use", "figure", "legibility", "small_texts",
           "outside_texts", "savefig"]

STYLE_FILE = Path(__file__).with_name("bubbleoptics.mplstyle")
COLUMN_WIDTH = 3.4  # in, one column of a two-column paper
PAGE_WIDTH = 7.0  # in, both columns
MIN_FONT_PT = 7.0  # the smallest type a figure may use (the captions are 9 pt)
BOX_TOLERANCE_IN = 0.005  # a text may touch the figure's edge by this much (antialiasing, rounding)


def use():
    """Apply the paper's style to matplotlib's global rcParams (idempotent)."""
    matplotlib.style.use(STYLE_FILE)
    # cmr10.ttf's header dates predate 1904; fontTools warns about it each time it embeds the font
    logging.getLogger("fontTools.ttLib.tables._h_e_a_d").setLevel(logging.ERROR)


def figure(width=COLUMN_WIDTH, height=2.4):
    """A new figure in the paper's style, *width* × *height* inches, bound to the Agg canvas.

    Add axes with ``fig.subplots(...)`` or ``fig.subplot_mosaic(...)``; the layout is
    constrained (from the style).
    """
    use()
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height))
    FigureCanvasAgg(fig)
    return fig


def _drawn_texts(fig):
    """Draw *fig* once (laying it out) and return the renderer and the visible, non-empty texts
    that were drawn: titles, labels, tick labels that exist only once the axes are laid out,
    legend entries, annotations; texts that are never drawn (ticks outside the view) are not."""
    from matplotlib.text import Text

    drawn = []
    original = Text.draw

    def recording(self, renderer):
        if self.get_visible() and self.get_text().strip():
            drawn.append(self)
        return original(self, renderer)

    Text.draw = recording
    try:
        fig.canvas.draw()
    finally:
        Text.draw = original
    return fig.canvas.get_renderer(), list(dict.fromkeys(drawn))


def legibility(fig):
    """What the paper's legibility rules see in *fig*, in inches from its lower left corner:
    ``{"width_in", "height_in", "texts": [{"text", "size_pt", "bbox_in"}], "legends":
    [{"bbox_in"}], "images": [{"text_px", "rows", "height_in", "text_pt"}]}``.  An image is
    listed when its script set ``image.text_px`` (its smallest type's height in image pixels);
    ``text_pt`` is that height at the size the image is drawn."""
    from matplotlib.image import AxesImage
    from matplotlib.legend import Legend

    renderer, texts = _drawn_texts(fig)
    dpi = fig.dpi

    def inches(bbox):
        return [round(v / dpi, 4) for v in (bbox.x0, bbox.y0, bbox.x1, bbox.y1)]

    images = []
    for image in fig.findobj(AxesImage):
        text_px = getattr(image, "text_px", None)
        if text_px is None or not image.get_visible():
            continue
        rows = image.get_array().shape[0]
        height_in = image.get_window_extent(renderer).height / dpi
        images.append({"text_px": float(text_px), "rows": int(rows), "height_in": round(height_in, 4),
                       "text_pt": round(float(text_px) * height_in / rows * 72.0, 3)})
    width, height = fig.get_size_inches()
    return {
        "width_in": float(width), "height_in": float(height),
        "texts": [{"text": t.get_text(), "size_pt": float(t.get_fontsize()), "bbox_in": inches(t.get_window_extent(renderer))}
                  for t in texts],
        "legends": [{"bbox_in": inches(g.get_window_extent(renderer))} for g in fig.findobj(Legend) if g.get_visible()],
        "images": images,
    }


def small_texts(fig, minimum=MIN_FONT_PT, report=None):
    """``[(text, size in pt)]`` of the drawn texts of *fig* smaller than *minimum* (a screenshot's
    type counts as the text ``<image>`` at its printed size)."""
    report = legibility(fig) if report is None else report
    small = [(t["text"], t["size_pt"]) for t in report["texts"] if t["size_pt"] < minimum - 1e-9]
    return small + [("<image>", i["text_pt"]) for i in report["images"] if i["text_pt"] < minimum - 1e-9]


def outside(bbox_in, width_in, height_in, tolerance=BOX_TOLERANCE_IN):
    """Whether a box ``[x0, y0, x1, y1]`` in inches reaches outside a figure of that size."""
    x0, y0, x1, y1 = bbox_in
    return x0 < -tolerance or y0 < -tolerance or x1 > width_in + tolerance or y1 > height_in + tolerance


def outside_texts(fig, report=None):
    """``[(text, bbox in inches)]`` of the drawn texts and legends (``<legend>``) of *fig* that
    reach outside its box, i.e. would be cut off."""
    report = legibility(fig) if report is None else report
    w, h = report["width_in"], report["height_in"]
    found = [(t["text"], t["bbox_in"]) for t in report["texts"] if outside(t["bbox_in"], w, h)]
    return found + [("<legend>", g["bbox_in"]) for g in report["legends"] if outside(g["bbox_in"], w, h)]


def savefig(fig, name):
    """Write *fig* as ``FIGURES/name.pdf`` and ``FIGURES/name.png`` (200 dpi); return the two paths.
    ``FIGURES/name.legibility.json`` gets :func:`legibility`'s report (not returned).

    Raises ``ValueError`` (and writes nothing) if some text is smaller than ``MIN_FONT_PT`` or
    some text or legend reaches outside the figure.
    The PDF carries no creation date, so an unchanged figure is byte-for-byte the same file.
    """
    from bubbleoptics.plotting import save_figure_atomic

    report = legibility(fig)
    small = small_texts(fig, report=report)
    if small:
        listed = ", ".join(f"{text!r} {size:g} pt" for text, size in small[:8])
        raise ValueError(f"{name}: {len(small)} text(s) smaller than {MIN_FONT_PT:g} pt: {listed}")
    cut = outside_texts(fig, report=report)
    if cut:
        listed = ", ".join(f"{text!r} at {box}" for text, box in cut[:8])
        raise ValueError(f"{name}: {len(cut)} text(s) or legend(s) outside the figure's box: {listed}")

    folder = paths.figures_dir()
    written = [
        Path(save_figure_atomic(fig, folder / f"{name}.pdf", metadata={"CreationDate": None})),
        Path(save_figure_atomic(fig, folder / f"{name}.png", dpi=matplotlib.rcParams["savefig.dpi"])),
    ]
    report["figure"] = name
    (folder / f"{name}.legibility.json").write_text(json.dumps(report, indent=1) + "\n", encoding="utf-8")
    return written
