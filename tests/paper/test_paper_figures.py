"""The paper's figure scripts: ``paper/scripts/make_figures.py --quick`` builds every figure.

The figures go into a temporary folder (``BUBBLEOPTICS_FIGURES_DIR``, honoured by
``paper/scripts/paths.py``), never into the checkout.  Every ``fig_X.py`` must write
``fig_X.pdf`` and ``fig_X.png``, non-empty and valid (a PDF's header and end-of-file marker; a
PNG that Pillow decodes, at the style's 200 dpi for a one-column 3.4 in figure), and say so
on its output.  A failing script stops ``make_figures.py`` with the script's name.

Legible at print size: ``paper.tex`` places every figure at its natural size, so each PDF's page
must be as wide as its slot there (one column in ``figure``, the text width in ``figure*``, from
the geometry the paper sets), within ``SLOT_TOLERANCE``; the scripts' save helper refuses texts
smaller than 7 pt and texts outside the figure (``style.savefig``; its records are checked by
``tests/paper/test_figure_legibility.py``), and no figure may embed a Type 3 (bitmap) font (checked
with ``pdffonts`` where poppler-utils is installed).
"""

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from PIL import Image

import paper_helpers

PAPER = Path(__file__).resolve().parents[2] / "paper"
SCRIPTS = PAPER / "scripts"
FIGURE_SCRIPTS = sorted(SCRIPTS.glob("fig_*.py"))
SLOT_TOLERANCE = 0.03  # a figure may be this much narrower or wider than its slot (LaTeX scales it)
BP_PER_INCH = 72.0


def slots(tex):
    """{figure name: slot width in inches} of every ``\\paperfigure{NAME}`` in *tex*: the column
    width in a ``figure`` environment, the text width in a ``figure*``, from the geometry options."""
    geometry = re.search(r"\\usepackage\[([^]]*)\]\{geometry\}", tex).group(1)
    inches = dict(re.findall(r"(textwidth|columnsep)=([0-9.]+)in", geometry))
    text_width, sep = float(inches["textwidth"]), float(inches["columnsep"])
    widths = {"figure": (text_width - sep) / 2, "figure*": text_width}
    found = {}
    for env, body in re.findall(r"\\begin\{(figure\*?)\}(.*?)\\end\{\1\}", tex, flags=re.DOTALL):
        for name in re.findall(r"\\paperfigure\{([^}]+)\}", body):
            assert name not in found, f"{name} placed twice"
            found[name] = widths[env]
    return found


def media_box(path):
    """(width, height) in big points of the first page of a PDF (its /MediaBox)."""
    m = re.search(rb"/MediaBox\s*\[\s*([-0-9.]+)\s+([-0-9.]+)\s+([-0-9.]+)\s+([-0-9.]+)\s*\]", path.read_bytes())
    assert m, f"{path.name}: no /MediaBox"
    x0, y0, x1, y1 = map(float, m.groups())
    return x1 - x0, y1 - y0


def type3_fonts(pdf):
    """The lines of ``pdffonts PDF`` that list a Type 3 font (bitmap fonts print badly)."""
    out = subprocess.run(["pdffonts", str(pdf)], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    return [line for line in out.stdout.splitlines()[2:] if "Type 3" in line]


def _env(figures_dir, **extra):
    env = dict(os.environ, BUBBLEOPTICS_FIGURES_DIR=str(figures_dir), MPLBACKEND="Agg")
    env.pop("BUBBLEOPTICS_QUICK", None)
    env.update(extra)
    return env


def _assert_pdf(path):
    data = path.read_bytes()
    assert data.startswith(b"%PDF-"), f"{path.name}: no PDF header"
    assert data.rstrip().endswith(b"%%EOF"), f"{path.name}: no PDF end-of-file marker"
    assert b"/Type /Page" in data, f"{path.name}: no page"
    assert len(data) > 5000, f"{path.name}: only {len(data)} bytes"


def _assert_png(path):
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", f"{path.name}: no PNG signature"
    with Image.open(path) as image:
        image.verify()  # checks the chunks' CRCs
    with Image.open(path) as image:
        image.load()  # decodes every pixel
        width, height = image.size
        extrema = image.convert("L").getextrema()
    assert 600 <= width <= 1500 and 300 <= height <= 1500, f"{path.name}: {width}x{height} pixels"
    assert extrema[0] < extrema[1], f"{path.name}: a blank image"


@pytest.mark.api
def test_figure_scripts_exist():
    names = {p.name for p in FIGURE_SCRIPTS}
    assert {"fig_coursework_table.py", "fig_depth_fits.py", "fig_thin_film.py"} <= names


@pytest.fixture(scope="module")
def quick_figures(tmp_path_factory):
    """(folder, output) of the session's one ``make_figures.py --quick`` into a temporary folder
    (:func:`paper_helpers.quick_figures`, shared with tests/paper/test_paper.py)."""
    out, returncode, output = paper_helpers.quick_figures(tmp_path_factory)
    assert returncode == 0, output[-4000:]
    return out, output


@pytest.mark.api
def test_make_figures_quick_writes_every_figure(quick_figures):
    out, proc = quick_figures
    expected = {f"{p.stem}.{ext}" for p in FIGURE_SCRIPTS for ext in ("pdf", "png", "legibility.json")}
    written = {p.name for p in out.iterdir()}
    assert written == expected, f"missing {expected - written}, unexpected {written - expected}"
    for name in sorted(expected):
        path = out / name
        assert path.stat().st_size > 0
        if name.endswith(".legibility.json"):
            continue  # style.savefig's record, read by tests/paper/test_figure_legibility.py
        assert f"wrote {path}" in proc, f"{name} not reported"
        (_assert_pdf if name.endswith(".pdf") else _assert_png)(path)
    assert not any(p.name.endswith(".tmp") for p in out.iterdir())
    assert f"{len(FIGURE_SCRIPTS)} figure script(s) done" in proc


def test_slots_reads_the_environments():
    tex = ("\\usepackage[letterpaper,textwidth=7.0in,columnsep=0.2in]{geometry}\n"
           "\\begin{figure}[t]\\paperfigure{fig_a}\\end{figure}\n"
           "\\begin{figure*}[t]\n\\paperfigure{fig_b}\n\\end{figure*}")
    assert slots(tex) == {"fig_a": pytest.approx(3.4), "fig_b": pytest.approx(7.0)}


@pytest.mark.api
def test_every_figure_is_drawn_at_the_width_of_its_slot(quick_figures):
    """Each figure PDF is as wide as the column or page it is placed in, so LaTeX scales it by
    less than SLOT_TOLERANCE and its type prints at the size the script set."""
    out, _ = quick_figures
    placed = slots(paper_helpers.source())
    assert sorted(placed) == sorted(p.stem for p in FIGURE_SCRIPTS), "figures placed vs figure scripts"
    for name, slot in placed.items():
        width, height = media_box(out / f"{name}.pdf")
        scale = slot * BP_PER_INCH / width
        assert abs(scale - 1.0) <= SLOT_TOLERANCE, f"{name}: {width / BP_PER_INCH:.2f} in wide in a {slot:.2f} in slot"
        assert height <= 9.1 * BP_PER_INCH, f"{name}: taller than the text"


def test_the_save_helper_refuses_small_type(tmp_path, monkeypatch):
    """style.savefig raises for a text below MIN_FONT_PT and writes nothing; at the minimum it saves."""
    monkeypatch.setenv("BUBBLEOPTICS_FIGURES_DIR", str(tmp_path))
    monkeypatch.syspath_prepend(str(SCRIPTS))
    import importlib

    import paths
    import style

    importlib.reload(paths)
    importlib.reload(style)
    fig = style.figure()
    ax = fig.subplots()
    ax.set_xlabel("legible")
    small = ax.text(0.5, 0.5, "too small", fontsize=style.MIN_FONT_PT - 0.5)
    with pytest.raises(ValueError, match="too small"):
        style.savefig(fig, "small")
    assert not list(tmp_path.iterdir())
    small.set_fontsize(style.MIN_FONT_PT)
    assert [p.name for p in style.savefig(fig, "ok")] == ["ok.pdf", "ok.png"]


@pytest.mark.api
@pytest.mark.skipif(shutil.which("pdffonts") is None, reason="pdffonts (poppler-utils) not installed")
def test_no_figure_embeds_a_type3_font(quick_figures):
    out, _ = quick_figures
    for script in FIGURE_SCRIPTS:
        assert not type3_fonts(out / f"{script.stem}.pdf"), f"{script.stem}.pdf has a Type 3 font"


@pytest.mark.api
def test_one_script_runs_alone_with_quick_flag(tmp_path):
    proc = subprocess.run([sys.executable, str(SCRIPTS / "fig_coursework_table.py"), "--quick"], env=_env(tmp_path),
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    _assert_pdf(tmp_path / "fig_coursework_table.pdf")
    _assert_png(tmp_path / "fig_coursework_table.png")


@pytest.mark.api
def test_make_figures_stops_at_the_first_failure(tmp_path):
    """A copy of make_figures.py beside three scripts; the second fails, the third never runs."""
    shutil.copy(SCRIPTS / "make_figures.py", tmp_path / "make_figures.py")
    marker = tmp_path / "third_ran"
    (tmp_path / "fig_a_ok.py").write_text("print('a ran')\n")
    (tmp_path / "fig_b_broken.py").write_text("raise SystemExit(3)\n")
    (tmp_path / "fig_c_after.py").write_text(f"open({str(marker)!r}, 'w').close()\n")
    proc = subprocess.run([sys.executable, str(tmp_path / "make_figures.py"), "--quick"], env=_env(tmp_path),
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 1
    assert "a ran" in proc.stdout
    assert "fig_b_broken.py failed (exit status 3)" in proc.stderr
    assert not marker.exists()


@pytest.mark.api
def test_quick_flag_reaches_the_scripts(tmp_path):
    """--quick becomes BUBBLEOPTICS_QUICK=1 in each script's environment."""
    shutil.copy(SCRIPTS / "make_figures.py", tmp_path / "make_figures.py")
    (tmp_path / "fig_env.py").write_text("import os; print('quick=' + os.environ.get('BUBBLEOPTICS_QUICK', ''))\n")
    run = [sys.executable, str(tmp_path / "make_figures.py")]
    assert "quick=1" in subprocess.run(run + ["--quick"], env=_env(tmp_path), capture_output=True, text=True).stdout
    assert "quick=\n" in subprocess.run(run, env=_env(tmp_path), capture_output=True, text=True).stdout
