"""Tests of kernel building blocks that the public functions do not expose directly."""

import math

import mpmath
import numpy as np
import pytest

from bubbleoptics.kernels import BETA_POLY_MAX, film_evaluate_nb, film_setup_nb, sin2_cos2_nb, sin_cos_nb


@pytest.mark.reference
def test_sin2_cos2_against_mpmath():
    """sin2_cos2_nb (hand-written, vectorizable) against mpmath at 40 digits.

    Covers small phases, random phases up to BETA_POLY_MAX, and the floating-point multiples
    of pi/2 where the reduced argument nearly vanishes (the hard case of argument reduction).
    Bar: 4e-16 absolute and 1e-14 relative wherever the true value is a normal double.
    """
    rng = np.random.default_rng(20261123)
    xs = np.concatenate(
        [
            [0.0, 1e-8, 1e-3, 0.5, math.pi / 4, BETA_POLY_MAX],
            rng.uniform(0, 10, 500),
            rng.uniform(0, BETA_POLY_MAX, 500),
            np.arange(1, 600) * (math.pi / 2),
            np.nextafter(np.arange(1, 100) * (math.pi / 2), 0),
        ]
    )
    worst_abs = worst_rel = 0.0
    with mpmath.workdps(40):
        for x in xs:
            s2, c2 = sin2_cos2_nb(x)
            ref_s = mpmath.sin(mpmath.mpf(float(x))) ** 2
            ref_c = mpmath.cos(mpmath.mpf(float(x))) ** 2
            for got, ref in ((s2, ref_s), (c2, ref_c)):
                err = abs(mpmath.mpf(got) - ref)
                worst_abs = max(worst_abs, float(err))
                if ref > 1e-300:
                    worst_rel = max(worst_rel, float(err / ref))
    assert worst_abs <= 4e-16, worst_abs
    assert worst_rel <= 1e-14, worst_rel


@pytest.mark.analytic
def test_sin2_cos2_identity_and_libm():
    """sin² + cos² = 1 to rounding, and agreement with libm to 4e-16 over the whole range."""
    xs = np.linspace(0, BETA_POLY_MAX, 20001)
    for x in xs:
        s2, c2 = sin2_cos2_nb(x)
        assert abs(s2 + c2 - 1.0) <= 4e-16
        assert abs(s2 - math.sin(x) ** 2) <= 4e-16 + 1e-15 * math.sin(x) ** 2


def _sin_cos_arguments():
    """Small, random, negative and near-multiple-of-pi/2 arguments, and the range's ends."""
    rng = np.random.default_rng(20261207)
    xs = np.concatenate(
        [
            [0.0, -0.0, 1e-300, 1e-8, 1e-3, 0.5, math.pi / 4, BETA_POLY_MAX, -BETA_POLY_MAX],
            rng.uniform(-20, 20, 600),
            rng.uniform(-BETA_POLY_MAX, BETA_POLY_MAX, 400),
            np.arange(-300, 300) * (math.pi / 2),
            np.nextafter(np.arange(-50, 50) * (math.pi / 2), np.inf),
            np.nextafter(np.arange(-50, 50) * (math.pi / 2), -np.inf),
        ]
    )
    return xs


@pytest.mark.reference
def test_sin_cos_against_mpmath():
    """sin_cos_nb (hand-written, inlined into the swirl) against mpmath at 40 digits.

    Every quadrant, both signs, and the floating-point multiples of pi/2 where the reduced
    argument nearly vanishes.  Bar: 2.5e-16 absolute (about one ulp of values near 1) and
    1e-15 relative where the true value exceeds 1e-300.
    """
    worst_abs = worst_rel = 0.0
    with mpmath.workdps(40):
        for x in _sin_cos_arguments():
            s, c = sin_cos_nb(x)
            for got, ref in ((s, mpmath.sin(mpmath.mpf(float(x)))), (c, mpmath.cos(mpmath.mpf(float(x))))):
                err = abs(mpmath.mpf(got) - ref)
                worst_abs = max(worst_abs, float(err))
                if abs(ref) > 1e-300:
                    worst_rel = max(worst_rel, float(err / abs(ref)))
    assert worst_abs <= 2.5e-16, worst_abs
    assert worst_rel <= 1e-15, worst_rel


@pytest.mark.analytic
def test_sin_cos_signs_identity_and_fallback():
    """sin is odd and cos even exactly (the reduction is symmetric), sin^2 + cos^2 = 1 to
    rounding, and beyond BETA_POLY_MAX, at infinities and NaN the values are libm's."""
    for x in _sin_cos_arguments():
        s, c = sin_cos_nb(x)
        s_neg, c_neg = sin_cos_nb(-x)
        assert s_neg == -s and c_neg == c, x
        assert abs(s * s + c * c - 1.0) <= 4e-16, x
    for x in (BETA_POLY_MAX * 1.5, -3e15, 1e300):
        assert sin_cos_nb(x) == (math.sin(x), math.cos(x))
    for x in (math.inf, -math.inf, math.nan):
        s, c = sin_cos_nb(x)
        assert math.isnan(s) and math.isnan(c)


@pytest.mark.reference
def test_libm_fallback_beyond_poly_range():
    """Phases beyond BETA_POLY_MAX (very thick films) take libm and stay right.

    R of a free-standing lossless film at normal incidence is periodic in d with period
    lambda/(2 n): a film one period thicker than a huge multiple of periods matches the thin one
    to the rounding of the phase (absolute 1e-9 at beta ~ 1e7 where beta itself carries 1e-9).
    """
    c = film_setup_nb(500.0, 1.0, 1.0, 1.5 + 0j, 1.0 + 0j)
    period = 500.0 / (2 * 1.5)
    d_small = 123.0
    d_big = d_small + 10**7 * period
    assert c[0].real * d_big > BETA_POLY_MAX
    r_small, _ = film_evaluate_nb(c, d_small, 2)
    r_big, t_big = film_evaluate_nb(c, d_big, 2)
    assert abs(r_big - r_small) < 1e-8
    assert abs(r_big + t_big - 1) < 1e-14


# --------------------------------------------------------------------------------------------
# The free-standing lossless film (bubbleoptics.kernels.free_film_*), the tracer's common case
# --------------------------------------------------------------------------------------------
_FREE_GRID = [
    (wl, c0, n1, d, n0)
    for wl in (380.0, 550.0, 780.0)
    for c0 in (1.0, 0.8, 0.3, 0.05, 1e-4, 0.0)
    for n1 in (1.0000001, 1.2, 1.333, 1.6, 2.5)
    for d in (0.0, 5.0, 300.0, 2000.0, 20000.0)
    for n0 in (1.0, 1.2)
    if n1 > n0
]


@pytest.mark.reference
def test_free_film_against_mpmath():
    """free_film_setup_nb/evaluate (Airy's formula with the coefficient of finesse) against the
    40-digit Airy sum of study.reference, s, p and unpolarized, from normal to
    exactly grazing incidence and from index match to n = 2.5: within 1e-13 absolute."""
    from bubbleoptics.kernels import free_film_evaluate_nb, free_film_setup_nb
    from study import reference as ref

    worst = 0.0
    for wl, c0, n1, d, n0 in _FREE_GRID[::3]:
        theta = math.acos(c0)
        c = free_film_setup_nb(wl, c0, n0, n1)
        assert c[0] >= 0.0
        for pol, name in ((0, "s"), (1, "p"), (2, "unpolarized")):
            R, T = free_film_evaluate_nb(c, d, pol)
            R_ref, T_ref = ref.film_rt_mp(wl, d, theta, n1, n0, n0, polarization=name)
            worst = max(worst, abs(R - float(R_ref)), abs(T - float(T_ref)))
    assert worst < 1e-13, worst


@pytest.mark.reference
def test_free_film_equals_the_general_kernel():
    """The symmetric case agrees with film_setup_nb/film_evaluate_nb (n2 = n0) to rounding (5e-15),
    and its band average with film_band_average_nb (1e-14: one atan2 of slightly different
    arguments); R + T = 1 to an ulp."""
    from bubbleoptics.kernels import film_band_average_nb, free_film_band_average_nb, free_film_evaluate_nb, free_film_setup_nb

    worst = worst_band = worst_sum = 0.0
    for wl, c0, n1, d, n0 in _FREE_GRID:
        c = free_film_setup_nb(wl, c0, n0, n1)
        g = film_setup_nb(wl, c0, n0, n1 + 0j, n0 + 0j)
        kq_a = free_film_setup_nb(wl - 10.0, c0, n0, n1)[0]
        kq_b = free_film_setup_nb(wl + 10.0, c0, n0, n1)[0]
        for pol in (0, 1, 2):
            R, T = free_film_evaluate_nb(c, d, pol)
            R0, T0 = film_evaluate_nb(g, d, pol)
            worst = max(worst, abs(R - R0), abs(T - T0))
            worst_sum = max(worst_sum, abs(R + T - 1.0))
            Rb, Tb = free_film_band_average_nb(c, kq_a, kq_b, d, pol)
            Rb0, Tb0 = film_band_average_nb(g, kq_a, kq_b, d, pol)
            worst_band = max(worst_band, abs(Rb - Rb0), abs(Tb - Tb0))
    assert worst < 5e-15 and worst_band < 1e-14 and worst_sum < 5e-16, (worst, worst_band, worst_sum)


@pytest.mark.analytic
def test_free_film_limits():
    """Zero thickness and index match transmit everything; p light at Brewster's angle
    (tan theta = n1/n0) is not reflected at any thickness; beyond the film's critical angle
    (n1 < n0) the closed form declines (kq = -1)."""
    from bubbleoptics.kernels import free_film_evaluate_nb, free_film_setup_nb

    assert free_film_evaluate_nb(free_film_setup_nb(500.0, 0.7, 1.0, 1.33), 0.0, 2) == (0.0, 1.0)
    assert free_film_evaluate_nb(free_film_setup_nb(500.0, 0.7, 1.33, 1.33), 812.0, 2) == (0.0, 1.0)
    brewster = math.cos(math.atan(1.5))
    R_p, T_p = free_film_evaluate_nb(free_film_setup_nb(500.0, brewster, 1.0, 1.5), 333.0, 1)
    assert R_p < 1e-30 and T_p == 1.0
    assert free_film_setup_nb(500.0, 0.2, 1.5, 1.2)[0] == -1.0


@pytest.mark.reference
@pytest.mark.parametrize("bits, dtype", [(8, np.uint8), (16, np.uint16)])
def test_srgb_quantized_codes_equal_colour_science(bits, dtype):
    """The image writer's codes (srgb_encode_quantized_array: clip, encode, round half to even)
    equal NumPy's rounding of colour-science's sRGB encoding, code for code, NaN as 0."""
    import colour

    from bubbleoptics.kernels import srgb_encode_quantized_array

    rng = np.random.default_rng(11)
    x = np.concatenate([rng.uniform(-0.1, 1.1, 200000), rng.uniform(0, 0.004, 20000),
                        [np.nan, -np.inf, np.inf, 0.0, 1.0, 0.0031308, 0.5]])
    levels = 2**bits - 1
    out = np.empty(x.size, dtype=dtype)
    srgb_encode_quantized_array(x, float(levels), out)
    clipped = np.clip(np.nan_to_num(x, nan=0.0, posinf=1.0, neginf=0.0), 0.0, 1.0)
    expected = np.round(colour.cctf_encoding(clipped, function="sRGB") * levels).astype(dtype)
    np.testing.assert_array_equal(out, expected)
