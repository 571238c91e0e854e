"""The bubble series of the Measurement section (``data/measured/oospectro_bubble_*.csv``) and the
apex-thinning fits of ``paper/scripts/numbers_measured.py``.

Kinds: ``regression`` (the transcription, checked once against the source's
``spectra/known_values.py`` at oospectro tag v0.4.0, then frozen; the stored fits against a re-fit),
``analytic`` (the apex law against closed forms and this project's rigid-drainage time scale),
``api`` (the files agree with each other).
"""

import importlib
import math
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = ROOT / "paper" / "scripts"
MEASURED = ROOT / "data" / "measured"


def _numbers_measured():
    if str(SCRIPTS) not in sys.path:
        sys.path.insert(0, str(SCRIPTS))
    return importlib.import_module("numbers_measured")


@pytest.fixture(scope="module")
def nm():
    return _numbers_measured()


@pytest.fixture(scope="module")
def stated(nm):
    return nm.read_commented_csv(MEASURED / nm.BUBBLE_STATED)[1]


@pytest.mark.regression
def test_the_transcription_is_the_sources(stated):
    """69 entries, 3975 nm at index 12909 first and 118 nm at 80561 last, as in the source's
    ``sample3`` (checked by hand against known_values.py at v0.4.0); the file name is its index."""
    assert len(stated) == 69
    assert (stated[0]["time_index"], stated[0]["stated_nm"]) == ("12909", "3975")
    assert (stated[-1]["time_index"], stated[-1]["stated_nm"]) == ("80561", "118")
    assert sum(int(r["stated_nm"]) for r in stated) == 120407
    for r in stated:
        assert r["file"] == f"{int(r['time_index']):06d}.xy"
    t = [int(r["time_index"]) for r in stated]
    assert t == sorted(t) and len(set(t)) == len(t)


@pytest.mark.api
def test_every_stated_spectrum_is_in_the_file_listing(nm, stated):
    files = nm.read_commented_csv(MEASURED / nm.BUBBLE_FILE_INDEX)[1]
    index = {int(r["time_index"]) for r in files}
    assert len(files) == len(index) == 2551
    assert {int(r["time_index"]) for r in stated} <= index


@pytest.mark.analytic
def test_apex_law_without_evaporation_is_the_rigid_models(nm):
    """beta = 3, q = 0: h0 (1 + t/tau)^(-1/2) with tau = 3 mu R/(rho g h0^2) when c = rho g/(6 mu R)
    (docs/film-flow.md); the ODE path with a negligible q gives the same."""
    from bubbleoptics.filmflow import FilmParameters

    p = FilmParameters()
    c = p.density * p.gravity / (6 * p.viscosity * p.radius)
    tau = 3 * p.viscosity * p.radius / (p.density * p.gravity * p.h0**2)
    t = np.linspace(0.0, 5 * tau, 11)
    expected = p.h0 * (1 + t / tau) ** -0.5
    np.testing.assert_allclose(nm.apex_thinning(t, p.h0, c, 3.0, 0.0), expected, rtol=1e-12)
    np.testing.assert_allclose(nm.apex_thinning(t, p.h0, c, 3.0, 1e-30), expected, rtol=1e-7)


@pytest.mark.analytic
def test_apex_law_of_evaporation_alone_is_linear(nm):
    t = np.array([1.0, 2.0, 5.0])
    np.testing.assert_allclose(nm.apex_thinning(t, 3e-6, 0.0, None, 4e-8), 3e-6 - 4e-8 * (t - 1.0), rtol=1e-14)


@pytest.mark.analytic
def test_the_fit_recovers_a_known_law(nm):
    """Noise-free thicknesses of rigid drainage plus evaporation give back c and q."""
    t = np.linspace(10.0, 80.0, 40)
    h = nm.apex_thinning(t, 4e-6, 2e9, 3.0, 4e-8)
    fit = nm.fit_apex_law(t, h, 3.0, True)
    assert fit["rms_log"] < 1e-6
    assert math.isclose(fit["c"], 2e9, rel_tol=1e-4)
    assert math.isclose(fit["q"], 4e-8, rel_tol=1e-5)


@pytest.mark.regression
def test_the_stored_fit_is_reproduced(nm):
    """The committed rigid-drainage-plus-evaporation row against a re-fit of the committed series."""
    rows = nm.read_commented_csv(MEASURED / nm.BUBBLE_FITS)[1]
    row = next(r for r in rows if r["law"] == "rigid drainage + evaporation")
    t, h = nm.load_bubble(MEASURED / nm.BUBBLE_STATED)
    fit = nm.fit_apex_law(t, h, 3.0, True)
    assert math.isclose(fit["q"], float(row["q_e_m_per_s"]), rel_tol=1e-4)
    assert math.isclose(fit["rms_log"], float(row["rms_log"]), rel_tol=1e-4)
    assert float(row["q_e_low"]) < fit["q"] < float(row["q_e_high"])


@pytest.mark.api
def test_the_optics_comparison_has_the_stated_spectra(nm, stated):
    """Every stated spectrum is in the optics comparison, with the stated thickness copied right,
    and every compared spectrum lies in the film's window of the series."""
    rows = nm.read_commented_csv(MEASURED / nm.BUBBLE_COMPARISON)[1]
    by_index = {int(r["time_index"]): r for r in rows}
    for r in stated:
        assert float(by_index[int(r["time_index"])]["stated_nm"]) == float(r["stated_nm"])
    assert sum(1 for r in rows if r["stated_nm"]) == len(stated)
    assert all(nm.BUBBLE_FILM_FROM <= t < nm.BUBBLE_FILM_TO for t in by_index)
