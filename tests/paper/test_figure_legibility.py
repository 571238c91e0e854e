"""Every figure of the paper is legible at the size it is printed.

The figures are drawn at their final width (``tests/paper/test_paper_figures.py`` checks each
PDF against its slot), so a font size in a script is the printed size.  ``style.savefig``
records, for each figure, every text it draws (size in pt and box in inches), every legend's
box, and every raster image that carries type (a screenshot, with the height of its smallest
type in its own pixels) in ``fig_X.legibility.json`` beside ``fig_X.pdf``.  From the session's
quick build (``paper_helpers.quick_figures``) these tests check that the record describes the
PDF (same page size), that no text is under ``style.MIN_FONT_PT`` (7 pt) and no screenshot's
type prints under it, that no text or legend reaches outside the figure's box (it would be cut
off), and, independently of the record, that every word ``pdftotext -bbox`` finds in the PDF
lies on its page.  Mathtext sub- and superscripts are set smaller than their text's size, as
LaTeX's are, and are not counted.
"""

import importlib
import json
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import paper_helpers

pytestmark = pytest.mark.api

PAPER = Path(__file__).resolve().parents[2] / "paper"
SCRIPTS = PAPER / "scripts"
FIGURE_SCRIPTS = sorted(SCRIPTS.glob("fig_*.py"))
MIN_PT = 7.0
TOLERANCE_IN = 0.005


@pytest.fixture(scope="module")
def figures(tmp_path_factory):
    out, returncode, output = paper_helpers.quick_figures(tmp_path_factory)
    assert returncode == 0, output[-4000:]
    return out


def record(figures, name):
    path = figures / f"{name}.legibility.json"
    assert path.exists(), f"{name}: no {path.name} (figure not saved with style.savefig?)"
    return json.loads(path.read_text(encoding="utf-8"))


def media_box_in(pdf):
    m = re.search(rb"/MediaBox\s*\[\s*([-0-9.]+)\s+([-0-9.]+)\s+([-0-9.]+)\s+([-0-9.]+)\s*\]", pdf.read_bytes())
    assert m, f"{pdf.name}: no /MediaBox"
    x0, y0, x1, y1 = map(float, m.groups())
    return (x1 - x0) / 72.0, (y1 - y0) / 72.0


def reaches_out(box, width, height):
    x0, y0, x1, y1 = box
    return x0 < -TOLERANCE_IN or y0 < -TOLERANCE_IN or x1 > width + TOLERANCE_IN or y1 > height + TOLERANCE_IN


def test_every_figure_has_a_record_of_its_pdf(figures):
    for script in FIGURE_SCRIPTS:
        report = record(figures, script.stem)
        assert report["figure"] == script.stem
        width, height = media_box_in(figures / f"{script.stem}.pdf")
        assert report["width_in"] == pytest.approx(width, abs=0.01), script.stem
        assert report["height_in"] == pytest.approx(height, abs=0.01), script.stem
        assert report["texts"], f"{script.stem}: no text recorded"


def test_no_text_is_smaller_than_7_pt(figures):
    for script in FIGURE_SCRIPTS:
        report = record(figures, script.stem)
        smallest = min(report["texts"], key=lambda t: t["size_pt"])
        assert smallest["size_pt"] >= MIN_PT - 1e-9, f"{script.stem}: {smallest['text']!r} at {smallest['size_pt']} pt"
        for image in report["images"]:
            printed = image["text_px"] * image["height_in"] / image["rows"] * 72.0
            assert printed == pytest.approx(image["text_pt"], rel=1e-3)
            assert printed >= MIN_PT, f"{script.stem}: a screenshot's {image['text_px']:g} px type prints at {printed:.2f} pt"


def test_the_editor_screenshot_is_checked_at_print_size(figures):
    """fig_editor's crops of the screenshot declare their type's pixel height, so the check above
    covers them; the render crop has no type and may be scaled freely."""
    images = record(figures, "fig_editor")["images"]
    assert len(images) >= 3
    assert min(i["text_pt"] for i in images) >= MIN_PT


def test_the_editor_crops_type_is_as_tall_as_declared():
    """The tick digits of the reflectance plot crop are at least 8 pixels tall (11-pixel type,
    digits 0.72 em): the declared text_px is not an overstatement of the screenshot."""
    import sys

    sys.path.insert(0, str(SCRIPTS))
    try:
        fig_editor = importlib.import_module("fig_editor")
    finally:
        sys.path.remove(str(SCRIPTS))
    from PIL import Image

    with Image.open(fig_editor.SCREENSHOT) as image:
        grey = np.asarray(image.convert("L"), dtype=float)
    _, box, text_px = fig_editor.CROPS["plot"]
    part = fig_editor.crop(grey, box)[:, 60:]  # right of the y axis: the x tick labels' digits
    dark = np.flatnonzero((part < 140).any(axis=1))
    runs = np.split(dark, np.flatnonzero(np.diff(dark) > 1) + 1)
    digits = [len(r) for r in runs if 6 <= len(r) <= 10]
    assert digits, "no row of tick digits found in the plot crop"
    assert min(digits) / 0.72 >= text_px - 0.5


def test_no_text_or_legend_reaches_outside_the_figure(figures):
    for script in FIGURE_SCRIPTS:
        report = record(figures, script.stem)
        w, h = report["width_in"], report["height_in"]
        for text in report["texts"]:
            assert not reaches_out(text["bbox_in"], w, h), f"{script.stem}: {text['text']!r} at {text['bbox_in']}"
        for legend in report["legends"]:
            assert not reaches_out(legend["bbox_in"], w, h), f"{script.stem}: a legend at {legend['bbox_in']}"


@pytest.mark.skipif(shutil.which("pdftotext") is None, reason="pdftotext (poppler-utils) not installed")
def test_every_word_of_each_pdf_lies_on_its_page(figures):
    word = re.compile(r'<word xMin="([-0-9.]+)" yMin="([-0-9.]+)" xMax="([-0-9.]+)" yMax="([-0-9.]+)">([^<]*)</word>')
    for script in FIGURE_SCRIPTS:
        pdf = figures / f"{script.stem}.pdf"
        out = subprocess.run(["pdftotext", "-bbox", str(pdf), "-"], capture_output=True, text=True, timeout=60)
        assert out.returncode == 0, out.stderr
        width, height = (v * 72.0 for v in media_box_in(pdf))
        words = word.findall(out.stdout)
        for x0, y0, x1, y1, text in words:
            x0, y0, x1, y1 = map(float, (x0, y0, x1, y1))
            assert x0 >= -1.0 and y0 >= -1.0 and x1 <= width + 1.0 and y1 <= height + 1.0, \
                f"{script.stem}: {text!r} at ({x0:.1f}, {y0:.1f}, {x1:.1f}, {y1:.1f}) on a {width:.0f} x {height:.0f} pt page"


@pytest.fixture
def style(tmp_path, monkeypatch):
    monkeypatch.setenv("BUBBLEOPTICS_FIGURES_DIR", str(tmp_path))
    monkeypatch.syspath_prepend(str(SCRIPTS))
    import paths
    import style

    importlib.reload(paths)
    return importlib.reload(style)


def test_the_save_helper_refuses_a_text_outside_the_figure(style, tmp_path):
    fig = style.figure()
    ax = fig.subplots()
    ax.plot([0, 1], [0, 1])
    cut = fig.text(0.95, 0.5, "cut off at the right edge")
    with pytest.raises(ValueError, match="outside the figure's box: 'cut off"):
        style.savefig(fig, "cut")
    assert not list(tmp_path.iterdir())
    cut.set_x(0.05)
    assert [p.name for p in style.savefig(fig, "ok")] == ["ok.pdf", "ok.png"]
    report = json.loads((tmp_path / "ok.legibility.json").read_text())
    assert "cut off at the right edge" in [t["text"] for t in report["texts"]]


def test_the_save_helper_refuses_a_legend_outside_the_figure(style):
    fig = style.figure()
    ax = fig.subplots()
    ax.plot([0, 1], [0, 1], label="a line")
    ax.legend(loc="center left", bbox_to_anchor=(1.3, 0.5))
    fig.set_layout_engine("none")
    with pytest.raises(ValueError, match="outside the figure's box"):
        style.savefig(fig, "legend")


def test_the_save_helper_refuses_a_screenshot_whose_type_prints_small(style):
    """A 1000-pixel-wide image with 12-pixel type across a 3.4 in figure prints it at 2.9 pt."""
    fig = style.figure(width=3.4, height=3.4)
    fig.set_layout_engine("none")
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_axis_off()
    shown = ax.imshow(np.zeros((1000, 1000, 3)))
    shown.text_px = 12.0
    fig.text(0.02, 0.02, "a label")
    with pytest.raises(ValueError, match="'<image>' 2.9"):
        style.savefig(fig, "screenshot")
    shown.text_px = 12.0 * 2.5  # the same image with 30-pixel type: 7.3 pt
    style.savefig(fig, "screenshot")


def test_texts_never_drawn_are_not_counted(style):
    """A text made invisible does not count, however small; a drawn one does."""
    fig = style.figure()
    ax = fig.subplots()
    hidden = ax.text(0.5, 0.5, "hidden", fontsize=3)
    hidden.set_visible(False)
    assert style.small_texts(fig) == []
    hidden.set_visible(True)
    assert style.small_texts(fig) == [("hidden", 3.0)]
