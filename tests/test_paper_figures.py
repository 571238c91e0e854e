"""The paper's figure scripts: ``paper/scripts/make_figures.py --quick`` builds every figure.

The figures go into a temporary folder (``BUBBLEOPTICS_FIGURES_DIR``, honoured by
``paper/scripts/paths.py``), never into the checkout.  Every ``fig_X.py`` must write
``fig_X.pdf`` and ``fig_X.png``, non-empty and valid (a PDF's header and end-of-file marker; a
PNG that Pillow decodes, at the style's 200 dpi for a one-column 3.4 in figure), and say so
on its output.  A failing script stops ``make_figures.py`` with the script's name.
"""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from PIL import Image

SCRIPTS = Path(__file__).resolve().parents[1] / "paper" / "scripts"
FIGURE_SCRIPTS = sorted(SCRIPTS.glob("fig_*.py"))


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


@pytest.mark.api
def test_make_figures_quick_writes_every_figure(tmp_path):
    out = tmp_path / "figures"  # does not exist yet: created on demand
    proc = subprocess.run([sys.executable, str(SCRIPTS / "make_figures.py"), "--quick"], env=_env(out),
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    expected = {f"{p.stem}.{ext}" for p in FIGURE_SCRIPTS for ext in ("pdf", "png")}
    written = {p.name for p in out.iterdir()}
    assert written == expected, f"missing {expected - written}, unexpected {written - expected}"
    for name in sorted(expected):
        path = out / name
        assert path.stat().st_size > 0
        assert f"wrote {path}" in proc.stdout, f"{name} not reported"
        (_assert_pdf if name.endswith(".pdf") else _assert_png)(path)
    assert not any(p.name.endswith(".tmp") for p in out.iterdir())
    assert f"{len(FIGURE_SCRIPTS)} figure script(s) done" in proc.stdout


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
