"""study.metrics: the one CIEDE2000 (colour-science's), and the errors of a render.

* ``reference``: CIEDE2000 against published values (Sharma, Wu & Dalal 2005, the pairs
  colour-science's own tests use) and against colour-science's own pipeline.
* ``analytic``: identical colours differ by 0; an exposure scales both colours alike; clipping,
  RMSE and the non-finite count on hand-made arrays.
* ``api``: shapes, broadcasting and argument errors.
"""

import colour
import numpy as np
import pytest

from study import delta_e00, delta_e00_images, delta_e00_XYZ
from study.metrics import finite_image, rmse


def _lab_to_linear_srgb(lab):
    """Inverse of delta_e00's Lab conversion.  Solves with colour's RGB -> XYZ matrix rather than
    using its XYZ -> RGB one: IEC 61966-2-1 rounds both matrices to four decimals, so they are
    not exact inverses and the round trip would be off by ~1e-4 in ΔE00."""
    space = colour.RGB_COLOURSPACES["sRGB"]
    XYZ = colour.Lab_to_XYZ(np.asarray(lab, dtype=float), space.whitepoint)
    return np.linalg.solve(space.matrix_RGB_to_XYZ, XYZ[..., None])[..., 0]


@pytest.mark.analytic
def test_delta_e00_of_identical_images_is_zero():
    rng = np.random.default_rng(0)
    image = rng.uniform(0.0, 1.5, (7, 5, 3))  # HDR values above 1 too
    d = delta_e00(image, image)
    assert d.shape == (7, 5)
    assert np.all(d == 0.0)


# Sharma, Wu & Dalal (2005), Color Res. Appl. 30, 21, table 1: pairs 1, 2, 3, 7, 17, 25, 31, 34
# (also in colour-science's own tests, colour/difference/tests/test_delta_e.py).
SHARMA = [
    ([50.0, 2.6772, -79.7751], [50.0, 0.0, -82.7485], 2.0425),
    ([50.0, 3.1571, -77.2803], [50.0, 0.0, -82.7485], 2.8615),
    ([50.0, 2.8361, -74.0200], [50.0, 0.0, -82.7485], 3.4412),
    ([50.0, 0.0, 0.0], [50.0, -1.0, 2.0], 2.3669),
    ([50.0, 2.5, 0.0], [73.0, 25.0, -18.0], 27.1492),
    ([60.2574, -34.0099, 36.2677], [60.4626, -34.1751, 39.4387], 1.2644),
    ([90.8027, -2.0831, 1.4410], [91.1528, -1.6435, 0.0447], 1.4441),
    ([2.0776, 0.0795, -1.1350], [0.9033, -0.0636, -0.5514], 0.9082),
]


@pytest.mark.reference
def test_delta_e00_published_pairs():
    """Lab pairs with published ΔE00, carried to linear sRGB (exact, unclipped) and back."""
    lab_1 = np.array([p[0] for p in SHARMA])
    lab_2 = np.array([p[1] for p in SHARMA])
    expected = np.array([p[2] for p in SHARMA])
    d = delta_e00(_lab_to_linear_srgb(lab_1), _lab_to_linear_srgb(lab_2))
    np.testing.assert_allclose(d, expected, atol=1e-4)
    np.testing.assert_allclose(d, colour.delta_E(lab_1, lab_2, method="CIE 2000"), rtol=1e-9)


@pytest.mark.reference
def test_delta_e00_equals_colour_science_on_images():
    """Two random linear-sRGB images: equal to colour-science's own RGB -> XYZ -> Lab -> ΔE00."""
    rng = np.random.default_rng(1)
    a = rng.uniform(0.0, 1.0, (6, 4, 3))
    b = np.clip(a + rng.normal(0.0, 0.05, a.shape), 0.0, None)
    space = colour.RGB_COLOURSPACES["sRGB"]
    lab = [colour.XYZ_to_Lab(colour.RGB_to_XYZ(x, space), space.whitepoint) for x in (a, b)]
    np.testing.assert_allclose(delta_e00(a, b), colour.delta_E(*lab, method="CIE 2000"), rtol=1e-12, atol=1e-12)
    # one known pair in full: sRGB red against green, both at full intensity
    assert delta_e00([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]) == pytest.approx(
        float(colour.delta_E(*[colour.XYZ_to_Lab(colour.RGB_to_XYZ(x, space), space.whitepoint)
                               for x in ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0])], method="CIE 2000")), rel=1e-12)


@pytest.mark.api
def test_delta_e00_shapes_and_errors():
    assert delta_e00(np.zeros((4, 3)), np.ones(3)).shape == (4,)  # broadcasting
    with pytest.raises(ValueError, match="3 channels"):
        delta_e00(np.zeros((4, 4)), np.zeros((4, 4)))


@pytest.mark.reference
def test_delta_e00_XYZ_equals_colour_science():
    """XYZ colours, an exposure and a white: equal to colour-science's XYZ -> Lab -> ΔE00 by hand."""
    rng = np.random.default_rng(3)
    a = rng.uniform(0.0, 0.1, (50, 3))
    b = np.clip(a + rng.normal(0.0, 0.005, a.shape), 0.0, None)
    for illuminant, k in (("D65", 1.0), ("D65", 12.5), ("E", 3.0)):
        white = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"][illuminant]
        expected = colour.delta_E(colour.XYZ_to_Lab(k * a, white), colour.XYZ_to_Lab(k * b, white), method="CIE 2000")
        np.testing.assert_allclose(delta_e00_XYZ(a, b, illuminant, exposure=k), expected, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(delta_e00_XYZ(a, b, white, exposure=k), expected, rtol=1e-12, atol=1e-12)


@pytest.mark.analytic
def test_delta_e00_XYZ_of_equal_colours_is_zero_and_exposure_matters():
    white = np.array([0.95047, 1.0, 1.08883])
    assert delta_e00_XYZ(white, white) == 0.0
    dark = 0.05 * white
    # the same pair exposed 20x is the white against its half: L* 100 against 76
    assert delta_e00_XYZ(dark, 0.5 * dark, exposure=20.0) == pytest.approx(delta_e00_XYZ(white, 0.5 * white))
    assert delta_e00_XYZ(dark, 0.5 * dark) < delta_e00_XYZ(dark, 0.5 * dark, exposure=20.0)


@pytest.mark.analytic
def test_delta_e00_images_clips_negative_values():
    a = np.array([[-0.2, 0.4, 0.6], [0.3, 0.3, 0.3]])
    clipped = np.array([[0.0, 0.4, 0.6], [0.3, 0.3, 0.3]])
    np.testing.assert_array_equal(delta_e00_images(a, clipped), [0.0, 0.0])
    assert delta_e00_images(a, clipped * 0.9).min() > 0


@pytest.mark.analytic
def test_rmse_and_finite_image():
    assert rmse(np.zeros((2, 2, 3)), np.full((2, 2, 3), 0.5)) == pytest.approx(0.5)
    image = np.zeros((2, 3, 3))
    image[0, 1, 2] = np.nan
    image[1, 2, 0] = np.inf
    clean, bad = finite_image(image)
    assert bad == 2 and np.all(np.isfinite(clean)) and np.all(clean == 0.0)
