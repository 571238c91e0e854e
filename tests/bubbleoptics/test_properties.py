"""Property tests (hypothesis) over the whole input domain of the public API.

Each property is a law of optics that must hold for *every* admissible input, not a value:
bounds on R and T (passive media, Born & Wolf §1.5.3), energy conservation for lossless media,
symmetry in the angle of incidence, unpolarized light as the mean of s and p (Born & Wolf
§10.9; Hecht §8.1), reciprocity (Born & Wolf §1.6.4; Hecht §4.10), and the index-matched
film being invisible.

Domain: wavelength 200-2000 nm; thickness in [0, 1e7] nm including exactly 0 and subnormal
values; angle in [-pi/2, pi/2] including exactly 0 and +-pi/2; film n 1-3 (so films both denser
and rarer than the outside), k 0-0.5; outside n 1-2 (real); inside: the outside medium (None)
or n 1-3, k 0-0.5.  The hypothesis settings come from the profile in ``conftest.py``.
"""

import math

import numpy as np
import pytest
from hypothesis import assume, example, given
from hypothesis import strategies as st

from bubbleoptics import (
    film_reflectance,
    film_rt,
    film_transmittance,
    fresnel_coefficients,
    multilayer_rt,
    two_beam_reflectance,
    water_refractive_index,
)

# ---------------------------------------------------------------------------------------------
# Strategies
# ---------------------------------------------------------------------------------------------
wavelengths = st.floats(200.0, 2000.0)
thicknesses = st.one_of(
    st.just(0.0),
    st.floats(0.0, 10.0),  # ultrathin, including subnormal numbers
    st.floats(0.0, 2000.0),  # the interference colours
    st.floats(0.0, 1e7),  # up to 1 cm
)
angles = st.one_of(
    st.sampled_from([0.0, math.pi / 2, -math.pi / 2]),
    st.floats(-math.pi / 2, math.pi / 2),
)
extinction = st.one_of(st.just(0.0), st.floats(0.0, 0.5))
outside_indices = st.floats(1.0, 2.0)


@st.composite
def complex_indices(draw, lo=1.0, hi=3.0):
    return complex(draw(st.floats(lo, hi)), draw(extinction))


inside_indices = st.one_of(st.none(), complex_indices())
polarizations = st.sampled_from(["s", "p", "unpolarized"])

#: slack on the bounds 0 <= R, T <= 1 (rounding)
SLACK = 1e-15


def _lossless(*indices):
    return all(n is None or complex(n).imag == 0 for n in indices)


def _check_bounds(R, T, lossless, energy_atol=1e-12):
    R = np.asarray(R)
    T = np.asarray(T)
    assert np.all(np.isfinite(R)) and np.all(np.isfinite(T))
    assert np.all(R >= -SLACK) and np.all(R <= 1 + SLACK), R
    assert np.all(T >= -SLACK) and np.all(T <= 1 + SLACK), T
    assert np.all(R + T <= 1 + 1e-13), R + T
    if lossless:
        np.testing.assert_allclose(R + T, 1.0, rtol=0, atol=energy_atol)


# ---------------------------------------------------------------------------------------------
# Single film
# ---------------------------------------------------------------------------------------------
@pytest.mark.property
@given(wavelengths, thicknesses, angles, complex_indices(), outside_indices, inside_indices, polarizations)
# Counterexamples found with the "thorough" profile, kept so that CI always checks them:
# total internal reflection at the back of a lossless film at grazing incidence (R must be 1).
@example(wl=1463.84375, d=6446216.0, theta=math.pi / 2, n1=2 + 0j, n0=1.6822711049877777, n2=1.375 + 0j, pol="p")
# ... and on the film's p guided-mode resonance, tan(beta) = kappa2/eta1 (see test_analytic_limits).
@example(wl=550.0, d=216.75099314913527, theta=math.pi / 2, n1=1.6 + 0j, n0=1.5, n2=1.0 + 0j, pol="p")
def test_film_bounds_and_energy(wl, d, theta, n1, n0, n2, pol):
    """A passive film neither creates nor (if lossless) destroys energy.

    0 <= R, T <= 1 and R + T <= 1 (the absorptance A = 1 - R - T >= 0 for k >= 0); for
    lossless media R + T = 1 to 1e-12 (Poynting's theorem, Born & Wolf §1.1.4 and §1.5.3),
    including total internal reflection at the back and evanescent (tunnelling) films.
    """
    R, T = film_rt(wl, d, theta, n1, n0, n2, pol)
    _check_bounds(R, T, _lossless(n1, n2))


@pytest.mark.property
@given(wavelengths, thicknesses, angles, complex_indices(), outside_indices, inside_indices, polarizations)
def test_film_is_even_in_theta(wl, d, theta, n1, n0, n2, pol):
    """R and T depend on theta only through cos(theta): mirror-image incidence is identical.

    Reflecting the plane of incidence maps theta to -theta and leaves a planar film unchanged
    (Born & Wolf §1.5.2: only cos(theta) and sin^2(theta) enter).  Equality is exact.
    """
    R, T = film_rt(wl, d, theta, n1, n0, n2, pol)
    Rm, Tm = film_rt(wl, d, -theta, n1, n0, n2, pol)
    assert R == Rm and T == Tm


@pytest.mark.property
@given(wavelengths, thicknesses, angles, complex_indices(), outside_indices, inside_indices)
def test_film_unpolarized_is_mean_of_s_and_p(wl, d, theta, n1, n0, n2):
    """Unpolarized light is an incoherent equal mixture of s and p (Born & Wolf §10.9; Hecht §8.1).

    Hence R_unpolarized = (R_s + R_p)/2 and likewise T, and the mixture lies between its parts.
    ``film_rt`` with ``quantities`` "R"/"T" and the single-quantity functions agree exactly.
    """
    Rs, Ts = film_rt(wl, d, theta, n1, n0, n2, "s")
    Rp, Tp = film_rt(wl, d, theta, n1, n0, n2, "p")
    Ru, Tu = film_rt(wl, d, theta, n1, n0, n2, "unpolarized")
    assert abs(Ru - 0.5 * (Rs + Rp)) <= 1e-15
    assert abs(Tu - 0.5 * (Ts + Tp)) <= 1e-15
    assert min(Rs, Rp) - 1e-15 <= Ru <= max(Rs, Rp) + 1e-15
    assert film_reflectance(wl, d, theta, n1, n0, n2) == Ru
    assert film_transmittance(wl, d, theta, n1, n0, n2) == Tu
    assert film_rt(wl, d, theta, n1, n0, n2, quantities="R") == (Ru,)
    assert film_rt(wl, d, theta, n1, n0, n2, quantities="T") == (Tu,)


@pytest.mark.property
@given(wavelengths, thicknesses, angles, st.floats(1.0, 3.0), polarizations)
def test_index_matched_film_reflects_nothing(wl, d, theta, n, pol):
    """A film index-matched to both sides is no film (Born & Wolf §1.5.2: r = 0 for n_i = n_j).

    R = 0 (below 1e-30: exactly zero but for rounding of nothing) and T = 1 for every thickness
    and angle, up to grazing incidence; also for the film's index given as a complex number
    with k = 0.
    """
    R, T = film_rt(wl, d, theta, n, n, n, pol)
    assert 0.0 <= R <= 1e-30
    assert abs(T - 1) <= 1e-13
    R2, T2 = film_rt(wl, d, theta, complex(n, 0.0), n, None, pol)
    assert 0.0 <= R2 <= 1e-30
    assert abs(T2 - 1) <= 1e-13


@pytest.mark.property
@given(
    wavelengths,
    st.floats(0.0, 1e4),
    st.floats(-1.45, 1.45),
    complex_indices(),
    outside_indices,
    st.floats(1.0, 3.0),
    polarizations,
)
def test_film_reciprocity(wl, d, theta0, n1, n0, n2, pol):
    """Transmittance is reciprocal; for lossless films reflectance is too.

    Light crossing the film from 0 to 2 at theta0 and from 2 to 0 at theta2 (Snell:
    n0 sin theta0 = n2 sin theta2) is transmitted equally, absorbing film or not (the
    reciprocity theorem; Born & Wolf §1.6.4, Hecht §4.10 for the Stokes form).  For a lossless
    film R = 1 - T then is the same from both sides.  (Angles stay 0.12 rad from grazing so that
    recomputing theta2 from a rounded theta0 is well conditioned.)
    """
    s2 = n0 * math.sin(theta0) / n2
    assume(abs(s2) < math.sin(1.45))
    theta2 = math.asin(s2)
    R_fw, T_fw = film_rt(wl, d, theta0, n1, n0, n2, pol)
    R_bw, T_bw = film_rt(wl, d, theta2, n1, n2, n0, pol)
    assert abs(T_fw - T_bw) <= 1e-9
    if _lossless(n1):
        assert abs(R_fw - R_bw) <= 1e-9


@pytest.mark.property
@given(wavelengths, thicknesses, angles, complex_indices(), outside_indices, inside_indices, polarizations)
def test_thickness_zero_limit_and_film_rt_shapes(wl, d, theta, n1, n0, n2, pol):
    """d = 0 gives the bare 0|2 interface (Born & Wolf §7.6.1 with beta = 0), for any film index.

    Also: scalar inputs give 0-d NumPy results.
    """
    R0, T0 = film_rt(wl, 0.0, theta, n1, n0, n2, pol)
    f = fresnel_coefficients(n0, n0 if n2 is None else n2, theta)
    Rb = {"s": f.Rs, "p": f.Rp, "unpolarized": 0.5 * (f.Rs + f.Rp)}[pol]
    Tb = {"s": f.Ts, "p": f.Tp, "unpolarized": 0.5 * (f.Ts + f.Tp)}[pol]
    assert abs(R0 - Rb) <= 1e-13
    assert abs(T0 - Tb) <= 1e-13
    R, T = film_rt(wl, d, theta, n1, n0, n2, pol)
    assert np.ndim(R) == 0 and np.ndim(T) == 0


# ---------------------------------------------------------------------------------------------
# Interface
# ---------------------------------------------------------------------------------------------
@pytest.mark.property
@given(outside_indices, complex_indices(), angles)
# found with the "thorough" profile: total internal reflection, Rp = 1 + 1.8e-15
@example(n1=1.9375, n2=1 + 0j, theta=0.5755759779408337)
def test_fresnel_properties(n1, n2, theta):
    """Fresnel coefficients of one interface (Born & Wolf §1.5.2-1.5.3).

    * 0 <= R, T <= 1, finite; R = |r|^2.
    * R + T = 1 for s and p, absorbing second medium or not: the normal component of the
      Poynting vector is continuous across the interface (Byrnes §3 defines T as that flux).
    * Even in theta; at normal incidence R_s = R_p and r_p = -r_s (``tmm`` convention).
    * |t_s| and |t_p| are finite, Im r = 0 for real indices below the critical angle.
    """
    f = fresnel_coefficients(n1, n2, theta)
    for R, T, r in ((f.Rs, f.Ts, f.rs), (f.Rp, f.Tp, f.rp)):
        assert np.isfinite(R) and np.isfinite(T) and np.isfinite(r)
        assert -SLACK <= R <= 1 + SLACK and -SLACK <= T <= 1 + SLACK
        assert abs(R + T - 1) <= 1e-13
        assert abs(abs(r) ** 2 - R) <= 1e-15
    assert np.isfinite(f.ts) and np.isfinite(f.tp)
    g = fresnel_coefficients(n1, n2, -theta)
    assert tuple(map(complex, g)) == tuple(map(complex, f))
    if n2.imag == 0 and n1 * math.sin(abs(theta)) < n2.real:
        assert f.rs.imag == 0 or abs(f.rs.imag) <= 1e-15
        assert f.rp.imag == 0 or abs(f.rp.imag) <= 1e-15
    f0 = fresnel_coefficients(n1, n2, 0.0)
    assert abs(f0.Rs - f0.Rp) <= 1e-15
    assert abs(f0.rp + f0.rs) <= 1e-15


# ---------------------------------------------------------------------------------------------
# Multilayer
# ---------------------------------------------------------------------------------------------
layer_lists = st.lists(st.tuples(complex_indices(), thicknesses), min_size=1, max_size=4)


@pytest.mark.property
@given(wavelengths, layer_lists, angles, outside_indices, inside_indices, polarizations)
def test_multilayer_bounds_energy_symmetry(wl, layers, theta, n0, n2, pol):
    """A stack of passive layers: 0 <= R, T, R + T <= 1, = 1 if lossless; even in theta.

    (Born & Wolf §1.6: the characteristic-matrix product conserves the normal energy flux in
    lossless media.)  Unpolarized = mean of s and p (Born & Wolf §10.9).
    """
    n = [x[0] for x in layers]
    d = [x[1] for x in layers]
    R, T = multilayer_rt(wl, n, d, theta, n0, n2, pol)
    _check_bounds(R, T, _lossless(n2, *n))
    Rm, Tm = multilayer_rt(wl, n, d, -theta, n0, n2, pol)
    assert R == Rm and T == Tm
    Rs, Ts = multilayer_rt(wl, n, d, theta, n0, n2, "s")
    Rp, Tp = multilayer_rt(wl, n, d, theta, n0, n2, "p")
    Ru, Tu = multilayer_rt(wl, n, d, theta, n0, n2, "unpolarized")
    assert abs(Ru - 0.5 * (Rs + Rp)) <= 1e-15
    assert abs(Tu - 0.5 * (Ts + Tp)) <= 1e-15


@pytest.mark.property
@given(wavelengths, thicknesses, angles, complex_indices(), outside_indices, inside_indices, polarizations)
def test_multilayer_of_one_layer_equals_film(wl, d, theta, n1, n0, n2, pol):
    """One layer of the transfer-matrix code is the Airy sum of the film (Born & Wolf §1.6.2, §7.6.1).

    The two formulations are algebraically identical, so they agree to rounding (1e-12).
    Adding a zero-thickness layer of any index changes nothing (its matrix is the identity).
    """
    R, T = film_rt(wl, d, theta, n1, n0, n2, pol)
    Rm, Tm = multilayer_rt(wl, [n1], [d], theta, n0, n2, pol)
    assert abs(R - Rm) <= 1e-12
    assert abs(T - Tm) <= 1e-12
    Rz, Tz = multilayer_rt(wl, [1.7 + 0.2j, n1], [0.0, d], theta, n0, n2, pol)
    assert abs(Rz - Rm) <= 1e-13 and abs(Tz - Tm) <= 1e-13


# ---------------------------------------------------------------------------------------------
# Two-beam model, water
# ---------------------------------------------------------------------------------------------
@pytest.mark.property
@given(wavelengths, thicknesses, angles, complex_indices(), outside_indices, polarizations)
def test_two_beam_properties(wl, d, theta, n1, n0, pol):
    """The two-beam model 4 R01 sin^2 beta (Hecht §9.7.1) lies between 0 and 4 R01.

    It is finite, non-negative, even in theta, zero at d = 0, and bounded by 4 R01 (R01 the
    outer surface's Fresnel reflectance for that polarization).
    """
    R2 = two_beam_reflectance(wl, d, theta, n1, n0, pol)
    f = fresnel_coefficients(n0, n1.real, theta)
    R01 = {"s": f.Rs, "p": f.Rp, "unpolarized": 0.5 * (f.Rs + f.Rp)}[pol]
    assert np.isfinite(R2)
    assert 0.0 <= R2 <= 4 * R01 * (1 + 1e-14) + 1e-300
    assert two_beam_reflectance(wl, d, -theta, n1, n0, pol) == R2
    assert two_beam_reflectance(wl, 0.0, theta, n1, n0, pol) == 0.0


@pytest.mark.property
@given(st.floats(182.0, 1129.0), st.floats(0.01, 50.0))
def test_water_index_normal_dispersion(wl, step):
    """Water has normal dispersion over the whole fitted range (Daimon & Masumura 2007).

    182-1129 nm lies between water's ultraviolet and infrared absorption bands, so n falls
    with wavelength (Born & Wolf §2.3.4): n(lambda) > n(lambda + step), and 1.32 < n < 1.48.
    """
    n = water_refractive_index(wl)
    assert 1.32 < n < 1.48
    if wl + step <= 1129.0:
        assert water_refractive_index(wl + step) < n
