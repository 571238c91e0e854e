"""The paper's one matplotlib style, figure sizes, and saving.

``use()`` applies ``bubbleoptics.mplstyle`` (beside this file): Computer Modern serif text and
mathematics without LaTeX, 8 pt type, the Okabe-Ito colour cycle, 200 dpi, PDF fonts embedded
as TrueType.  ``figure()`` makes a figure one column (3.4 in) or the full page (7.0 in) wide on
the Agg canvas (no pyplot, no display).  ``savefig(fig, name)`` writes ``name.pdf`` and
``name.png`` into ``paths.FIGURES``, each atomically (``bubbleoptics.plotting.save_figure_atomic``),
and returns their paths, after checking that the figure is legible at print size: every text
of it is at least ``MIN_FONT_PT`` tall (:func:`small_texts`).  The figures are placed in the
paper at their natural size (``\\paperfigure`` in paper.tex), so these sizes are the printed
ones; ``tests/paper/test_paper_figures.py`` checks each PDF's width against its slot in paper.tex.
"""

from __future__ import annotations

import logging
from pathlib import Path

import matplotlib
import matplotlib.style

import paths

__all__ = ["STYLE_FILE", "COLUMN_WIDTH", "PAGE_WIDTH", "MIN_FONT_PT", "use", "figure", "small_texts", "savefig"]

STYLE_FILE = Path(__file__).with_name("bubbleoptics.mplstyle")
COLUMN_WIDTH = 3.4  # in, one column of a two-column paper
PAGE_WIDTH = 7.0  # in, both columns
MIN_FONT_PT = 7.0  # the smallest type a figure may use (the captions are 9 pt)


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


def small_texts(fig, minimum=MIN_FONT_PT):
    """``[(text, size in pt)]`` of the visible, non-empty texts of *fig* smaller than *minimum*:
    titles, labels, tick labels, legend entries, annotations."""
    from matplotlib.text import Text

    fig.canvas.draw()  # makes the tick labels that exist only once the axes are laid out
    return [(t.get_text(), t.get_fontsize()) for t in fig.findobj(Text)
            if t.get_visible() and t.get_text().strip() and t.get_fontsize() < minimum - 1e-9]


def savefig(fig, name):
    """Write *fig* as ``FIGURES/name.pdf`` and ``FIGURES/name.png`` (200 dpi); return the two paths.

    Raises ``ValueError`` (and writes nothing) if some text is smaller than ``MIN_FONT_PT``.
    The PDF carries no creation date, so an unchanged figure is byte-for-byte the same file.
    """
    from bubbleoptics.plotting import save_figure_atomic

    small = small_texts(fig)
    if small:
        listed = ", ".join(f"{text!r} {size:g} pt" for text, size in small[:8])
        raise ValueError(f"{name}: {len(small)} text(s) smaller than {MIN_FONT_PT:g} pt: {listed}")

    folder = paths.figures_dir()
    written = [
        Path(save_figure_atomic(fig, folder / f"{name}.pdf", metadata={"CreationDate": None})),
        Path(save_figure_atomic(fig, folder / f"{name}.png", dpi=matplotlib.rcParams["savefig.dpi"])),
    ]
    return written
