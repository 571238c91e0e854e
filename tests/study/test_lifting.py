"""study.lifting: the RGB-to-spectrum liftings the Cycles attribution is re-run with.

* ``reference``: every lifting's spectrum, integrated by colour-science itself (``sd_to_XYZ``,
  ASTM E308 integration, D65, CIE 1931 2 degree, then its sRGB matrix), comes back to the colour
  it was lifted from within the method's stated accuracy (CIEDE2000): Mallett-Yuksel (the
  tracer's, normalised) 0.01, Jakob-Hanika 0.05 (it fits CIELAB to a hundredth of a JND), Otsu
  et al. 0.5, Smits 4 (its spectra were not fitted to these colour-matching functions: 2-3 in
  saturated greens and yellows, which is why the benchmark corrects the round trip); the band
  average is the tracer's own (the Mallett-Yuksel dataset averaged here equals
  ``rgb_reflectance_basis``).
* ``property``: spectra are non-negative, and within [0, 1] for all but Otsu's PCA; white is flat
  for the linear liftings; Smits and Mallett-Yuksel are linear in a grey scale, Jakob-Hanika
  is not; the round-trip correction is exact and leaves an exact lifting unchanged; the linear
  fit of a linear lifting is that lifting.
* ``api``: shapes and unknown names; the benchmark's environment row is the tracer's texel.
"""

import importlib.util
import sys
from pathlib import Path

import colour
import numpy as np
import pytest

from study import lifting
from study.metrics import delta_e00

ROOT = Path(__file__).resolve().parents[2]
FINE = np.arange(360.0, 781.0, 1.0)
#: the Cycles environment's five knots, white, a grey and saturated in-gamut colours
COLOURS = np.array([[0.10, 0.04, 0.02], [0.10, 0.35, 0.08], [0.90, 0.55, 0.20], [0.60, 0.80, 0.95],
                    [0.06, 0.15, 0.65], [1.0, 1.0, 1.0], [0.18, 0.18, 0.18], [0.80, 0.10, 0.10],
                    [0.05, 0.60, 0.10], [0.10, 0.10, 0.90], [0.90, 0.90, 0.05], [0.02, 0.70, 0.70]])
TOLERANCE = {"Mallett2019": 0.01, "Jakob2019": 0.05, "Otsu2018": 0.5, "Smits1999": 4.0}


@pytest.fixture(scope="module")
def fine_spectra():
    """Each lifting of :data:`COLOURS` at 1 nm (421 bands: the samples themselves)."""
    return {m: lifting.lift(COLOURS, m, FINE.size) for m in lifting.METHODS}


def _colour_science_rgb(values):
    """Linear sRGB of a 1 nm spectrum over 360-780 nm as a reflectance under D65, by colour-science."""
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    sd = colour.SpectralDistribution(values, FINE)
    XYZ = colour.sd_to_XYZ(sd, cmfs, colour.SDS_ILLUMINANTS["D65"], method="Integration") / 100.0
    return colour.RGB_COLOURSPACES["sRGB"].matrix_XYZ_to_RGB @ XYZ


@pytest.mark.reference
@pytest.mark.parametrize("method", lifting.METHODS)
def test_each_lifting_maps_back_to_its_colour_through_colour_science(method, fine_spectra):
    back = np.array([_colour_science_rgb(v) for v in fine_spectra[method]])
    de = delta_e00(back, COLOURS)
    assert de.max() < TOLERANCE[method], (method, de.round(3))


@pytest.mark.reference
@pytest.mark.parametrize("n_bands", [16, 64])
def test_band_average_is_the_tracers(n_bands):
    from bubbleoptics import rgb_reflectance_basis

    basis = colour.recovery.MSDS_BASIS_FUNCTIONS_sRGB_MALLETT2019.copy().align(colour.SpectralShape(360, 780, 1))
    np.testing.assert_allclose(lifting.band_average(basis.values.T, n_bands).T, rgb_reflectance_basis(n_bands),
                               atol=1e-6)


@pytest.mark.reference
def test_to_rgb_at_1nm_is_colour_sciences_integration(fine_spectra):
    for v in fine_spectra["Jakob2019"][:4]:
        np.testing.assert_allclose(lifting.to_rgb(v), _colour_science_rgb(v), atol=2e-4)


@pytest.mark.property
@pytest.mark.parametrize("method", lifting.METHODS)
def test_spectra_are_non_negative_and_bounded(method, fine_spectra):
    s = fine_spectra[method]
    assert s.min() >= 0.0
    assert s.max() <= (1.01 if method == "Otsu2018" else 1.0 + 1e-3), s.max()


@pytest.mark.property
@pytest.mark.parametrize("method", ["Mallett2019", "Smits1999"])
def test_linear_liftings_keep_white_flat_and_scale_with_grey(method, fine_spectra):
    white = fine_spectra[method][5]
    assert np.ptp(white) < 2e-3 and abs(white.mean() - 1.0) < 2e-3
    half = lifting.lift(0.5 * COLOURS[:5], method, FINE.size)
    np.testing.assert_allclose(half, 0.5 * fine_spectra[method][:5], atol=1e-9)


@pytest.mark.property
def test_jakob2019_is_smooth_and_not_linear(fine_spectra):
    s = fine_spectra["Jakob2019"]
    assert np.abs(np.diff(s, axis=1)).max() < 0.05  # a sigmoid of a quadratic: no steps at 1 nm
    assert 0.0 < s.min() and s.max() < 1.0
    half = lifting.lift(0.5 * COLOURS[2], "Jakob2019", FINE.size)
    assert np.abs(half - 0.5 * s[2]).max() > 0.01


@pytest.mark.property
@pytest.mark.parametrize("method", ["Smits1999", "Otsu2018"])
def test_correction_makes_the_round_trip_exact(method):
    raw = lifting.lift(COLOURS, method, 64)
    fixed = lifting.corrected(raw, COLOURS)
    np.testing.assert_allclose(lifting.to_rgb(fixed), COLOURS, atol=1e-12)
    assert np.abs(fixed - raw).max() < 0.1  # a small residual: the spectrum's shape stays the lifting's


@pytest.mark.property
def test_correction_leaves_the_tracers_lifting_alone_and_its_linear_fit_is_its_basis():
    from tracer.prepare.pack import channel_setup

    s = lifting.lift(COLOURS, "Mallett2019", 64)
    np.testing.assert_allclose(lifting.corrected(s, COLOURS), s, atol=1e-12)
    basis, residual = lifting.linear_fit(COLOURS, s)
    np.testing.assert_allclose(basis, channel_setup(True, 64)[2], atol=1e-10)
    assert residual < 1e-10


@pytest.mark.api
def test_shapes_and_unknown_method():
    assert lifting.lift(COLOURS[:2].reshape(1, 2, 3), "Smits1999", 16).shape == (1, 2, 16)
    with pytest.raises(ValueError, match="unknown lifting"):
        lifting.lift(COLOURS, "Meng2015", 16)
    with pytest.raises(ValueError, match="3 components"):
        lifting.lift(np.ones(4), "Smits1999", 16)
    with pytest.raises(ValueError, match="421 samples"):
        lifting.band_average(np.ones(100), 16)


@pytest.mark.api
def test_the_benchmarks_row_is_the_tracers_texel():
    spec = importlib.util.spec_from_file_location("_bench_peer_cycles", ROOT / "benchmarks" / "peer_cycles.py")
    pc = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(pc)
    sys.modules.setdefault("peer_cycles", pc)  # the benchmark imports its sibling by name
    spec = importlib.util.spec_from_file_location("_bench_lifting", ROOT / "benchmarks" / "peer_cycles_lifting.py")
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    from tracer.kernels.environment import environment_rgb
    from tracer.prepare.pack import _environment_record
    from tracer import Environment

    height = 64
    image = np.repeat(np.arange(height, dtype=float)[:, None, None], 4, axis=1).repeat(3, axis=2)
    record, texels = _environment_record(Environment(kind="image", image=image, up=(0.0, 1.0, 0.0)))
    d = np.random.default_rng(3).normal(size=(200, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    rows = [environment_rgb(record[0], texels, v)[0] for v in d]
    np.testing.assert_array_equal(bench.row_index(d, height), np.array(rows, int))
