"""Analytic limits of thin-film optics: cases whose exact answer is known in closed form.

Every expected value below is computed here from a textbook closed form with plain NumPy
(nothing is taken from ``bubbleoptics.kernels``), so each test can fail independently of the
package's formulation.  Units: nm, radians, complex index n + ik with k >= 0.

Notation used in the docstrings: media 0 (outside, incidence), 1 (film), 2 (inside);
``q_j = n_j cos(theta_j) = sqrt(n_j^2 - n_0^2 sin^2 theta_0)`` (Snell's law), tilted admittances
``eta_j = q_j`` (s) and ``eta_j = q_j / n_j^2`` (p, the sign convention of Byrnes' ``tmm``),
film phase thickness ``beta = 2 pi d q_1 / lambda``.

Sources: M. Born & E. Wolf, *Principles of Optics*, 7th ed. (1999), §1.5 (Fresnel formulae,
Brewster angle, total reflection), §1.6 (stratified media, characteristic matrices), §7.6
(multiple-beam interference, Airy formulae); E. Hecht, *Optics*, 5th ed. (2017), §4.6 (Fresnel
equations, Stokes relations §4.10), §9.7 (interference in thin films); H. A. Macleod,
*Thin-Film Optical Filters*, 4th ed. (2010), §2.2-2.6 (admittances, quarter- and half-wave
layers, incoherent thick layers); S. J. Byrnes, "Multilayer optical calculations",
arXiv:1603.02720 (sign conventions, incoherent layers).
"""

import math

import numpy as np
import pytest

from bubbleoptics import (
    film_reflectance,
    film_rt,
    film_transmittance,
    fresnel_coefficients,
    multilayer_rt,
    two_beam_reflectance,
    water_refractive_index,
)

POLS = ["s", "p", "unpolarized"]
SP = ["s", "p"]
WAVELENGTHS = np.array([200.0, 380.0, 450.0, 550.0, 633.0, 780.0, 1550.0, 2000.0])
#: Rounding allowance for a reflectance that should be within O(1e-16) of 1: a result near 1
#: is assembled from a handful of products and one quotient, each good to half an ulp
#: (1.1e-16), so we allow 16 ulp of 1.  This is the scale of float64 rounding, not of physics.
ULP16 = 16 * np.finfo(float).eps


# ---------------------------------------------------------------------------------------------
# Independent closed forms (plain NumPy, lossless media unless stated)
# ---------------------------------------------------------------------------------------------
def _q(n, n0, theta):
    """q = n cos(theta_n) = sqrt(n^2 - n0^2 sin^2 theta), forward/decaying branch."""
    q = np.sqrt(np.asarray(n, dtype=complex) ** 2 - (n0 * np.sin(theta)) ** 2 + 0j)
    return np.where(q.imag < 0, -q, q)


def _eta(n, n0, theta, pol):
    q = _q(n, n0, theta)
    return q if pol == "s" else q / np.asarray(n, dtype=complex) ** 2


def _r_interface(ni, nj, n0, theta, pol):
    """Amplitude reflection coefficient (eta_i - eta_j)/(eta_i + eta_j) of the i|j interface."""
    ei = _eta(ni, n0, theta, pol)
    ej = _eta(nj, n0, theta, pol)
    return (ei - ej) / (ei + ej)


def _mean_sp(func, pol):
    """Evaluate func(pol) for s or p, or the mean of both for unpolarized light."""
    if pol == "unpolarized":
        return 0.5 * (func("s") + func("p"))
    return func(pol)


# ---------------------------------------------------------------------------------------------
# Index match, zero thickness
# ---------------------------------------------------------------------------------------------
@pytest.mark.analytic
@pytest.mark.parametrize("pol", POLS)
@pytest.mark.parametrize("n", [1.0, 1.33, 1.5, 2.4])
def test_index_matched_film_is_invisible(pol, n):
    """A film of the same (real) index as both surrounding media is no film at all.

    With n_0 = n_1 = n_2 there is no interface, so no wave is reflected: R = 0 and T = 1 for
    every thickness, wavelength and angle of incidence, up to and including grazing incidence
    (Born & Wolf §1.5.2: r_ij = 0 when n_i = n_j; Airy sum §7.6.1 then gives r = 0, |t| = 1).
    The package evaluates q_1 - q_0 from an exact identity, so R must be exactly zero, not
    merely small.
    """
    d = np.array([0.0, 1e-3, 1.0, 123.4, 5e3, 1e6])[:, None, None]
    theta = np.array([0.0, 0.3, -0.9, 1.2, 1.5, 1.5707, 1.5707963, math.pi / 2])[None, :, None]
    wl = WAVELENGTHS[None, None, :]
    R, T = film_rt(wl, d, theta, n, n, n, pol)
    assert R.shape == (6, 8, WAVELENGTHS.size)
    assert np.all(R <= 1e-30)
    np.testing.assert_allclose(T, 1.0, rtol=0, atol=1e-13)
    # the transfer-matrix code agrees (it has no cancellation-free numerator, so allow rounding)
    Rm, Tm = multilayer_rt(wl, [n, n], [d, 2 * d], theta, n, n, pol)
    assert np.all(Rm <= 1e-28)
    np.testing.assert_allclose(Tm, 1.0, rtol=0, atol=1e-13)


@pytest.mark.analytic
@pytest.mark.parametrize("pol", SP)
@pytest.mark.parametrize(
    "n0, n1, n2",
    [
        (1.0, 1.33, 1.5),
        (1.0, 1.7 + 0.1j, 2.0 + 0.3j),
        (1.33, 1.5, 1.0),  # total reflection beyond arcsin(1/1.33)
        (1.5, 1.2 + 0.5j, 1.2),
        (1.0, 2.4, 0.5 + 2.0j),  # metal-like inside medium
    ],
)
def test_zero_thickness_film_is_the_bare_interface(pol, n0, n1, n2):
    """A film of zero thickness leaves the bare interface between media 0 and 2.

    With d = 0 the Airy sum r = (r01 + r12)/(1 + r01 r12) collapses to r02 and
    T to the interface transmittance (Born & Wolf §7.6.1 with beta = 0; Fresnel formulae
    §1.5.2), whatever the film's index.  Compared with ``fresnel_coefficients(n0, n2)`` and,
    at normal incidence, with |(n0 - n2)/(n0 + n2)|^2 and 4 n0 Re(n2)/|n0 + n2|^2.
    """
    theta = np.array([0.0, 0.2, -0.6, 0.85, 1.0, 1.3, 1.5, 1.5707])
    wl = WAVELENGTHS[:, None]
    R, T = film_rt(wl, 0.0, theta, n1, n0, n2, pol)
    f = fresnel_coefficients(n0, n2, theta)
    np.testing.assert_allclose(R, np.broadcast_to(getattr(f, "R" + pol), R.shape), rtol=0, atol=1e-13)
    np.testing.assert_allclose(T, np.broadcast_to(getattr(f, "T" + pol), T.shape), rtol=0, atol=1e-13)
    # normal incidence in closed form
    R0, T0 = film_rt(WAVELENGTHS, 0.0, 0.0, n1, n0, n2, pol)
    np.testing.assert_allclose(R0, abs((n0 - n2) / (n0 + n2)) ** 2, rtol=0, atol=1e-15)
    np.testing.assert_allclose(T0, 4 * n0 * np.real(n2) / abs(n0 + n2) ** 2, rtol=0, atol=1e-15)
    # unpolarized light is the mean of s and p
    Ru = film_reflectance(wl, 0.0, theta, n1, n0, n2, "unpolarized")
    np.testing.assert_allclose(Ru, np.broadcast_to(0.5 * (f.Rs + f.Rp), Ru.shape), rtol=0, atol=1e-13)


@pytest.mark.analytic
@pytest.mark.parametrize("pol", POLS)
@pytest.mark.parametrize("n1", [1.33, 2.0, 1.5 + 0.2j, 2.4 + 0.5j])
def test_zero_thickness_free_standing_film_reflects_nothing(pol, n1):
    """A free-standing film (same medium on both sides) of zero thickness reflects nothing.

    d = 0 leaves the interface between two identical media: R = 0, T = 1 exactly (Born &
    Wolf §7.6.1 with beta = 0 and r12 = -r01, so r = 0), for any film index, including
    absorbing films, and any angle.
    """
    theta = np.array([0.0, 0.5, -1.0, 1.4, 1.5707963, math.pi / 2])[:, None]
    for n0 in (1.0, 1.33):
        R, T = film_rt(WAVELENGTHS, 0.0, theta, n1, n0, None, pol)
        assert np.all(R <= 1e-30)
        np.testing.assert_allclose(T, 1.0, rtol=0, atol=1e-13)


# ---------------------------------------------------------------------------------------------
# Quarter- and half-wave layers
# ---------------------------------------------------------------------------------------------
QW_MEDIA = [(1.0, 1.33, 1.0), (1.0, 1.38, 1.52), (1.0, 2.35, 1.52), (1.33, 1.5, 1.0), (1.5, 1.2, 2.0)]


@pytest.mark.analytic
@pytest.mark.parametrize("pol", POLS)
@pytest.mark.parametrize("n0, n1, n2", QW_MEDIA)
def test_quarter_and_half_wave_at_normal_incidence(pol, n0, n1, n2):
    """Quarter-wave and half-wave layers at normal incidence (Macleod §2.6; Hecht §9.7.1).

    An odd number of quarter waves, n1 d = (2m+1) lambda/4, makes the film an admittance
    transformer: R = ((n0 n2 - n1^2)/(n0 n2 + n1^2))^2 (the single-layer antireflection
    coating when n1^2 = n0 n2).  A whole number of half waves, n1 d = m lambda/2, is an
    "absentee" layer: R is that of the bare 0|2 interface, ((n0 - n2)/(n0 + n2))^2, which is
    0 for a free-standing film.  At normal incidence all polarizations agree.
    """
    wl = WAVELENGTHS
    R_qw_expected = ((n0 * n2 - n1**2) / (n0 * n2 + n1**2)) ** 2
    R_hw_expected = ((n0 - n2) / (n0 + n2)) ** 2
    for m in range(4):
        R_qw, T_qw = film_rt(wl, (2 * m + 1) * wl / (4 * n1), 0.0, n1, n0, n2, pol)
        np.testing.assert_allclose(R_qw, R_qw_expected, rtol=0, atol=1e-13)
        np.testing.assert_allclose(T_qw, 1 - R_qw_expected, rtol=0, atol=1e-13)
        R_hw = film_reflectance(wl, (m + 1) * wl / (2 * n1), 0.0, n1, n0, n2, pol)
        np.testing.assert_allclose(R_hw, R_hw_expected, rtol=0, atol=1e-13)


@pytest.mark.analytic
@pytest.mark.parametrize("pol", SP)
@pytest.mark.parametrize("n0, n1, n2", QW_MEDIA)
def test_quarter_and_half_wave_at_oblique_incidence(pol, n0, n1, n2):
    """Quarter- and half-wave layers at oblique incidence, with tilted admittances.

    At oblique incidence the phase thickness is beta = 2 pi d q1/lambda; for beta = pi/2 the
    layer transforms admittances, R = ((eta0 eta2 - eta1^2)/(eta0 eta2 + eta1^2))^2, and for
    beta = pi it is absent, R = ((eta0 - eta2)/(eta0 + eta2))^2, with eta = q (s) or q/n^2 (p)
    (Macleod §2.6 with tilted optical admittances, §2.4).  Angles stay below any critical
    angle of the 0|2 interface so every wave propagates.
    """
    theta_max = math.asin(min(1.0, n2 / n0, n1 / n0)) if n0 > min(n1, n2) else 1.5
    theta = np.linspace(0.0, 0.98 * theta_max, 7)
    wl = WAVELENGTHS[:, None]
    q1 = _q(n1, n0, theta).real
    e0, e1, e2 = (_eta(n, n0, theta, pol).real for n in (n0, n1, n2))
    R_qw = film_reflectance(wl, wl / (4 * q1), theta, n1, n0, n2, pol)
    np.testing.assert_allclose(R_qw, np.broadcast_to(((e0 * e2 - e1**2) / (e0 * e2 + e1**2)) ** 2, R_qw.shape),
                               rtol=0, atol=1e-13)
    R_hw = film_reflectance(wl, wl / (2 * q1), theta, n1, n0, n2, pol)
    np.testing.assert_allclose(R_hw, np.broadcast_to(((e0 - e2) / (e0 + e2)) ** 2, R_hw.shape), rtol=0, atol=1e-13)


# ---------------------------------------------------------------------------------------------
# Airy formula for a free-standing film, Brewster angle, periodicity
# ---------------------------------------------------------------------------------------------
@pytest.mark.analytic
@pytest.mark.parametrize("pol", SP)
@pytest.mark.parametrize("n0, n1", [(1.0, 1.33), (1.0, 1.5), (1.0, 2.4), (1.33, 1.0), (1.5, 1.2)])
def test_airy_formula_free_standing_film(pol, n0, n1):
    """Airy's formula for a free-standing lossless film (Born & Wolf §7.6.1, eqs. (19)-(20)).

    With the same medium on both sides, r12 = -r01, so
    R = F sin^2(beta) / (1 + F sin^2(beta)),  T = 1 / (1 + F sin^2(beta)),
    F = 4 R01 / (1 - R01)^2 (the coefficient of finesse), beta = 2 pi d n1 cos(theta1)/lambda,
    separately for s and p.  R01 comes from the interface formula written here; when
    n1 < n0 the angles stay below the critical angle (else the film is an evanescent barrier).
    """
    theta_max = math.asin(n1 / n0) if n1 < n0 else math.pi / 2
    theta = np.linspace(-0.97 * theta_max, 0.97 * theta_max, 9)[:, None, None]
    d = np.array([0.0, 0.7, 33.3, 250.0, 1234.5, 9999.0])[None, :, None]
    wl = WAVELENGTHS[None, None, :]
    R01 = abs(_r_interface(n0, n1, n0, theta, pol)) ** 2
    F = 4 * R01 / (1 - R01) ** 2
    s2 = np.sin(2 * math.pi * d * _q(n1, n0, theta).real / wl) ** 2
    R, T = film_rt(wl, d, theta, n1, n0, None, pol)
    np.testing.assert_allclose(R, F * s2 / (1 + F * s2), rtol=1e-11, atol=1e-15)
    np.testing.assert_allclose(T, 1 / (1 + F * s2), rtol=1e-11, atol=1e-15)


@pytest.mark.analytic
@pytest.mark.parametrize("n0, n1", [(1.0, 1.33), (1.0, 1.5), (1.0, 2.4), (1.33, 1.0), (1.5, 1.33)])
def test_brewster_angle_free_standing_film(n0, n1):
    """At Brewster's angle a free-standing lossless film reflects no p light at any thickness.

    At theta_B = arctan(n1/n0), r01_p = 0 (Born & Wolf §1.5.3; Hecht §4.6.3), and inside the
    film tan(theta_1) = n0/n1, which is Brewster's angle of the 1|0 interface, so r10_p = 0
    as well: every beam of the Airy sum vanishes and Rp = 0 for all d.  The float theta_B is
    within half an ulp of the true angle, so Rp = O(1e-32); s light is still reflected, and
    unpolarized R = Rs/2.
    """
    theta_b = math.atan(n1 / n0)
    d = np.concatenate([[0.0, 1e-3, 0.5], np.linspace(1.0, 1e4, 401)])[:, None]
    Rp = film_reflectance(WAVELENGTHS, d, theta_b, n1, n0, None, "p")
    assert np.all(Rp <= 1e-25)
    Tp = film_transmittance(WAVELENGTHS, d, theta_b, n1, n0, None, "p")
    np.testing.assert_allclose(Tp, 1.0, rtol=0, atol=1e-13)
    Rs = film_reflectance(WAVELENGTHS, d, theta_b, n1, n0, None, "s")
    assert Rs.max() > 0.01  # s light is reflected: the angle is not special for s
    Ru = film_reflectance(WAVELENGTHS, d, theta_b, n1, n0, None, "unpolarized")
    np.testing.assert_allclose(Ru, 0.5 * Rs, rtol=1e-14, atol=1e-30)
    # the brewster angle from the other side
    theta_b_neg = -theta_b
    assert np.all(film_reflectance(WAVELENGTHS, d, theta_b_neg, n1, n0, None, "p") <= 1e-25)


@pytest.mark.analytic
@pytest.mark.parametrize("pol", POLS)
@pytest.mark.parametrize(
    "n0, n1, n2", [(1.0, 1.33, 1.0), (1.0, 1.33, 1.5), (1.33, 2.0, 1.0), (1.5, 1.6, 1.0), (1.0, 1.2, 2.4)]
)
def test_reflectance_is_periodic_in_thickness(pol, n0, n1, n2):
    """R(d) and T(d) of a lossless film are periodic in d with period lambda/(2 n1 cos theta1).

    The thickness enters the Airy sum only through exp(2 i beta), beta = 2 pi d q1/lambda
    (Born & Wolf §7.6.1), whose period in d is lambda/(2 q1).  Checked for several periods
    and starting thicknesses, including total reflection at the back (n0 = 1.5, n2 = 1.0 at
    theta = 1.2, where R = 1 identically) and unequal media.
    """
    theta = np.array([0.0, 0.4, -0.8, 1.2, 1.5])[:, None, None]
    wl = WAVELENGTHS[None, :, None]
    d0 = np.array([0.0, 3.7, 37.5, 812.3, 1e4])[None, None, :]
    period = wl / (2 * _q(n1, n0, theta).real)
    R0, T0 = film_rt(wl, d0, theta, n1, n0, n2, pol)
    for m in (1, 3, 10):
        R, T = film_rt(wl, d0 + m * period, theta, n1, n0, n2, pol)
        np.testing.assert_allclose(R, R0, rtol=0, atol=1e-12)
        np.testing.assert_allclose(T, T0, rtol=0, atol=1e-12)
    # and not periodic with half the period (the test can fail): R(d + P/2) differs somewhere
    R_half = film_reflectance(wl, d0 + 0.5 * period + 10.0, theta, n1, n0, n2, pol)
    assert np.abs(R_half - film_reflectance(wl, d0 + 10.0, theta, n1, n0, n2, pol)).max() > 1e-3


# ---------------------------------------------------------------------------------------------
# Thin-film limit
# ---------------------------------------------------------------------------------------------
@pytest.mark.analytic
@pytest.mark.parametrize("n", [1.1, 1.33, 1.5, 2.4])
@pytest.mark.parametrize("wl", [380.0, 550.0, 780.0])
def test_thin_film_limit_normal_incidence(n, wl):
    """Very thin free-standing films: R ~ (pi d (n^2 - 1)/lambda)^2, with an O(d^2) relative error.

    At normal incidence, in air, Airy's formula (Born & Wolf §7.6.1) is
    R = F sin^2 beta/(1 + F sin^2 beta), F = (n^2 - 1)^2/(4 n^2), beta = 2 pi n d/lambda.
    Expanding for beta -> 0 (sin^2 x = x^2 - x^4/3 + 2x^6/45 - ...):

        R / R0 = 1 - c2 beta^2 + c4 beta^4 + c6 beta^6 + O(beta^8),   R0 = F beta^2 = (pi d (n^2-1)/lambda)^2,
        c2 = 1/3 + F,  c4 = 2/45 + 2F/3 + F^2,  c6 = -(1/315 + F/5 + F^2 + F^3).

    So the relative error of R0 falls like d^2, and the film reflects ~ d^2 (the black film of
    a soap bubble about to burst; Hecht §9.7).  Checked (a) down to d = 1e-6 nm, where R ~ 1e-17
    must still carry full relative precision (no cancellation), and (b) the d^2 and d^4
    coefficients of the expansion.
    """
    F = (n**2 - 1) ** 2 / (4 * n**2)
    c2 = 1 / 3 + F
    c4 = 2 / 45 + 2 * F / 3 + F**2
    c6 = -(1 / 315 + F / 5 + F**2 + F**3)
    d = np.array([1e-6, 1e-4, 1e-2, 0.03, 0.1, 0.3, 1.0, 3.0])
    beta = 2 * np.pi * n * d / wl
    assert beta.max() < 0.12
    R0 = (np.pi * d * (n**2 - 1) / wl) ** 2
    R = film_reflectance(wl, d, 0.0, n)
    ratio = R / R0
    # (a) leading order, relative error below c2 beta^2 (plus rounding)
    assert np.all(np.abs(ratio - 1) <= c2 * beta**2 + 1e-14)
    # the error really decreases like d^2: tenfold thinner, ~hundredfold more accurate
    big = d >= 0.01
    assert np.all(np.abs(ratio[big] - 1) >= 0.9 * c2 * beta[big] ** 2)
    # (b) the expansion through beta^4, remainder bounded by the beta^6 term
    expansion = 1 - c2 * beta**2 + c4 * beta**4
    assert np.all(np.abs(ratio - expansion) <= 1.5 * abs(c6) * beta**6 + 1e-14)
    # all polarizations agree at normal incidence
    for pol in ("s", "p"):
        np.testing.assert_allclose(film_reflectance(wl, d, 0.0, n, polarization=pol), R, rtol=1e-14, atol=0)


@pytest.mark.analytic
@pytest.mark.parametrize("pol", SP)
@pytest.mark.parametrize("theta", [0.3, 0.7, 1.3, 1.55])
def test_thin_film_limit_oblique(pol, theta):
    """Thin free-standing films at oblique incidence: R ~ F beta^2 with F = 4 R01/(1 - R01)^2.

    The expansion of Airy's formula (Born & Wolf §7.6.1) holds per polarization with
    beta = 2 pi d n cos(theta1)/lambda and R01 the interface reflectance for that polarization:
    R/(F beta^2) = 1 - (1/3 + F) beta^2 + O(beta^4).  Checked for a water-like film in air.
    """
    n, wl = 1.34, 500.0
    R01 = abs(_r_interface(1.0, n, 1.0, theta, pol)) ** 2
    F = 4 * R01 / (1 - R01) ** 2
    d = np.array([1e-5, 1e-3, 0.01, 0.1, 1.0])
    beta = 2 * np.pi * d * _q(n, 1.0, theta).real / wl
    ratio = film_reflectance(wl, d, theta, n, polarization=pol) / (F * beta**2)
    c2 = 1 / 3 + F
    c4 = 2 / 45 + 2 * F / 3 + F**2
    assert np.all(np.abs(ratio - (1 - c2 * beta**2)) <= 1.5 * c4 * beta**4 + 1e-13)


# ---------------------------------------------------------------------------------------------
# Grazing incidence
# ---------------------------------------------------------------------------------------------
@pytest.mark.analytic
@pytest.mark.parametrize("pol", POLS)
@pytest.mark.parametrize(
    "n0, n1, n2, d",
    [
        (1.0, 1.33, None, 100.0),
        (1.0, 1.33, None, 1234.5),
        (1.0, 2.4, None, 1e6),
        (1.0, 1.33, 1.5, 0.0),
        (1.0, 1.33, 1.5, 1234.5),
        (1.33, 1.5, 2.0, 77.0),
        (1.0, 1.2, 1.33, 1e5),
    ],
)
def test_grazing_incidence_lossless(pol, n0, n1, n2, d):
    """At grazing incidence every lossless film reflects totally: R -> 1, T -> 0.

    As theta -> pi/2 the outside admittance eta0 = n0 cos(theta) (s) or cos(theta)/n0 (p)
    tends to 0, so every interface with the outside medium has r -> -1 (Born & Wolf §1.5.2;
    Hecht §4.6.4, "glancing incidence").  At theta = pi/2 in float (cos = 6.1e-17) the exact
    values are 1 - R = T <= 1e-15; the computed R may differ from 1 - T by rounding (``ULP16``,
    3.6e-15), R never exceeds 1 by more than 1e-15.  (Excluded: the free-standing film of zero
    thickness, which is no film, and exact half-wave films, whose approach to the limit is not
    uniform in d.)
    """
    for theta in (math.pi / 2, -math.pi / 2):
        R, T = film_rt(WAVELENGTHS, d, theta, n1, n0, n2, pol)
        assert np.all(T >= 0)
        assert np.all(T <= 1e-15)
        assert np.all(R <= 1 + 1e-15)
        assert np.all(R >= 1 - 1e-15 - ULP16)
        assert np.all(np.abs(R + T - 1) <= ULP16)


@pytest.mark.analytic
@pytest.mark.parametrize("pol", SP)
@pytest.mark.parametrize("n1, n2", [(1.7 + 0.3j, None), (1.33 + 0.01j, None), (1.5 + 0.5j, 2.0 + 0.5j), (1.33, 1.0 + 0.5j)])
def test_grazing_incidence_absorbing(pol, n1, n2):
    """Absorbing films and media also reflect totally at grazing incidence, 1 - R = O(cos theta).

    With eta0 -> 0 the reflection coefficient tends to -1 (Born & Wolf §1.5.2), and the
    absorbed and transmitted fractions are O(eta0) = O(cos theta): (1 - R)/cos(theta) tends to
    a finite limit.  Checked: the limit estimated at cos(theta) ~ 1e-6 and ~1e-8 agrees to
    1e-3 (the next-order term is O(cos theta/|eta1 beta|), largest for the thinnest film),
    R at theta = pi/2 lies within that slope times cos(pi/2) (+ rounding, ``ULP16``) of 1, and
    R never exceeds 1 by more than 1e-15.
    """
    wl = np.array([400.0, 550.0, 700.0])
    d = np.array([100.0, 1234.5, 1e5])[:, None]
    slopes = []
    for eps in (1e-6, 1e-8):
        theta = math.pi / 2 - eps
        R = film_reflectance(wl, d, theta, n1, 1.0, n2, pol)
        slopes.append((1 - R) / math.cos(theta))
    np.testing.assert_allclose(slopes[0], slopes[1], rtol=1e-3, atol=1e-6)
    assert np.all(slopes[1] > 0)
    R = film_reflectance(wl, d, math.pi / 2, n1, 1.0, n2, pol)
    assert np.all(R <= 1 + 1e-15)
    assert np.all(1 - R <= 1.01 * slopes[1] * math.cos(math.pi / 2) + ULP16)


@pytest.mark.analytic
@pytest.mark.parametrize("pol", SP)
@pytest.mark.parametrize("d", [50.0, 333.3, 4567.8])
def test_grazing_transmittance_falls_like_cos_theta(pol, d):
    """Near grazing incidence T falls like cos(theta) into a denser medium, like cos^2 free-standing.

    From the Airy sum (Born & Wolf §7.6.1), T = 4 eta0 eta2/[(eta0 + eta2)^2 cos^2 beta
    + (eta0 eta2 + eta1^2)^2 sin^2(beta)/eta1^2] for a lossless film.  As eta0 -> 0
    (eta0 = n0 cos theta for s, cos(theta)/n0 for p):

    * inside medium denser than outside (eta2 stays finite):
      T/cos(theta) -> 4 eta2 n0^(+-1)/(eta2^2 cos^2 beta + eta1^2 sin^2 beta)   (+ for s, - for p);
    * free-standing film (eta2 = eta0 -> 0 too):
      T/cos^2(theta) -> 4 n0^(+-2)/(eta1^2 sin^2 beta),
      with the q_j and beta evaluated at theta = pi/2.  Checked at cos(theta) = 1e-6 and 1e-8
      (relative corrections O(cos theta) and O(cos^2 theta) respectively).
    """
    wl = np.array([400.0, 550.0, 700.0])
    n0, n1, n2 = 1.0, 1.33, 1.5
    q1 = math.sqrt(n1**2 - n0**2)
    q2 = math.sqrt(n2**2 - n0**2)
    beta = 2 * np.pi * d * q1 / wl
    if pol == "s":
        e1, e2, scale = q1, q2, n0
    else:
        e1, e2, scale = q1 / n1**2, q2 / n2**2, 1 / n0
    limit_2 = 4 * e2 * scale / (e2**2 * np.cos(beta) ** 2 + e1**2 * np.sin(beta) ** 2)
    limit_0 = 4 * scale**2 / (e1**2 * np.sin(beta) ** 2)
    ratios_2, ratios_0 = [], []
    for eps, rtol_2 in ((1e-6, 1e-5), (1e-8, 1e-7)):
        theta = math.pi / 2 - eps
        c = math.cos(theta)
        T2 = film_transmittance(wl, d, theta, n1, n0, n2, pol)
        T0 = film_transmittance(wl, d, theta, n1, n0, None, pol)
        ratios_2.append(T2 / c)
        ratios_0.append(T0 / c**2)
        np.testing.assert_allclose(T2 / c, limit_2, rtol=rtol_2)
        np.testing.assert_allclose(T0 / c**2, limit_0, rtol=1e-8)
    np.testing.assert_allclose(ratios_2[0], ratios_2[1], rtol=1e-4)
    np.testing.assert_allclose(ratios_0[0], ratios_0[1], rtol=1e-4)


# ---------------------------------------------------------------------------------------------
# Energy conservation, total internal reflection
# ---------------------------------------------------------------------------------------------
@pytest.mark.analytic
@pytest.mark.parametrize("pol", POLS)
def test_energy_conservation_lossless_random(pol):
    """R + T = 1 for lossless media (Born & Wolf §1.5.3 and §7.6.1: no absorption).

    3000 random cases (fixed seed): wavelength 200-2000 nm, thickness 0-1e7 nm (log-uniform
    and uniform), any angle in [-pi/2, pi/2] (cos(theta) down to 1e-4 here; exact grazing has its
    own tests), outside index 1-2, film 1-3, inside the outside medium or 1-3 (so total
    internal reflection at the back and evanescent, tunnelling films both occur).
    """
    rng = np.random.default_rng(1234)
    N = 3000
    wl = rng.uniform(200, 2000, N)
    d = np.where(rng.random(N) < 0.5, 10 ** rng.uniform(-3, 7, N), rng.uniform(0, 2000, N))
    d[::17] = 0.0
    theta = rng.uniform(-1.5707, 1.5707, N)
    n0 = rng.uniform(1, 2, N)
    n1 = rng.uniform(1, 3, N)
    n2 = np.where(rng.random(N) < 0.4, n0, rng.uniform(1, 3, N))
    R, T = film_rt(wl, d, theta, n1, n0, n2, pol)
    assert np.all((R >= 0) & (T >= 0))
    np.testing.assert_allclose(R + T, 1.0, rtol=0, atol=1e-13)
    # the sample does contain total internal reflection at the back and evanescent films
    assert np.any(n0 * np.sin(np.abs(theta)) > n2) and np.any(n0 * np.sin(np.abs(theta)) > n1)


@pytest.mark.analytic
@pytest.mark.parametrize("pol", POLS)
def test_total_internal_reflection_at_the_back(pol):
    """Total internal reflection behind a lossless film: R = 1, T = 0 for every thickness.

    With n0 sin(theta) > n2 the wave in medium 2 is evanescent and carries no energy (Born &
    Wolf §1.5.4), so a lossless film reflects everything: R = 1 exactly, whatever d.  The case
    of the brief: n0 = 1.5, film 1.6, inside 1.0, theta = 1.2; plus d chosen on the film's
    guided-mode resonances, tan(beta) = kappa2/eta1 (kappa2 = |eta2|, the pole of r
    as eta0 -> 0, where the numerator and denominator of the Airy sum both become small),
    and angles up to grazing.
    """
    wl = 550.0
    theta = np.array([1.2, 1.4, 1.5, math.pi / 2 - 1e-4, math.pi / 2 - 1e-6, math.pi / 2])
    for n0, n1, n2 in [(1.5, 1.6, 1.0), (1.33, 1.5, 1.0), (1.0, 1.33, 0.5)]:
        assert np.all(n0 * np.sin(theta) > n2) and np.all(n0 * np.sin(theta) < n1)
        # a plain grid of thicknesses
        R, T = film_rt(wl, np.linspace(0.0, 2000.0, 101)[:, None], theta, n1, n0, n2, pol)
        np.testing.assert_allclose(T, 0.0, rtol=0, atol=1e-15)
        np.testing.assert_allclose(R, 1.0, rtol=0, atol=1e-13, err_msg=f"grid n0={n0} n1={n1} n2={n2}")
        # the guided-mode resonances of the s and p modes, m = 0, 1, 2, and 1e-12 off them
        s = n0 * np.sin(theta)
        q1 = np.sqrt(n1**2 - s**2)
        kappa = np.sqrt(s**2 - n2**2)
        for mode in SP:
            e1, k2 = (q1, kappa) if mode == "s" else (q1 / n1**2, kappa / n2**2)
            for m in range(3):
                d_res = (np.arctan(k2 / e1) + m * np.pi) * wl / (2 * np.pi * q1)
                for d in (d_res, d_res * (1 + 1e-12)):
                    R, T = film_rt(wl, d, theta, n1, n0, n2, pol)
                    np.testing.assert_allclose(T, 0.0, rtol=0, atol=1e-15)
                    np.testing.assert_allclose(
                        R, 1.0, rtol=0, atol=1e-13,
                        err_msg=f"{mode}-mode resonance m={m}: n0={n0} n1={n1} n2={n2} d={d!r} theta={theta!r}",
                    )


@pytest.mark.analytic
@pytest.mark.parametrize("pol", POLS)
def test_frustrated_total_reflection(pol):
    """An evanescent (low-index) film between two denser media lets light tunnel through.

    With n1 < n0 sin(theta) < n2 the wave in the film decays, yet T > 0 (frustrated total
    internal reflection; Born & Wolf §1.5.4, Hecht §4.7), T falls like exp(-4 pi kappa1 d /
    lambda) for thick films, kappa1 = sqrt(n0^2 sin^2 theta - n1^2), and R + T = 1.
    """
    n0, n1, n2, theta = 1.5, 1.0, 1.5, 1.0
    wl = np.array([450.0, 550.0, 650.0])
    d = np.array([0.0, 10.0, 100.0, 300.0, 1000.0, 2000.0])[:, None]
    R, T = film_rt(wl, d, theta, n1, n0, n2, pol)
    np.testing.assert_allclose(R + T, 1.0, rtol=0, atol=1e-13)
    np.testing.assert_allclose(T[0], 1.0, rtol=0, atol=1e-15)  # no film, no interface
    assert np.all(np.diff(T, axis=0) < 0)  # the thicker the barrier, the less tunnels
    kappa1 = math.sqrt((n0 * math.sin(theta)) ** 2 - n1**2)
    decay = np.log(T[-1] / T[-2]) / (d[-1, 0] - d[-2, 0])
    np.testing.assert_allclose(decay, -4 * np.pi * kappa1 / wl, rtol=1e-6)


# ---------------------------------------------------------------------------------------------
# Single interface: Stokes relations, energy, Brewster, normal incidence
# ---------------------------------------------------------------------------------------------
@pytest.mark.analytic
@pytest.mark.parametrize("n1, n2", [(1.0, 1.33), (1.0, 1.5), (1.0, 2.4), (1.33, 1.0), (1.5, 1.0), (1.5, 1.33)])
def test_fresnel_stokes_relations(n1, n2):
    """Stokes relations for one interface (Hecht §4.10; Born & Wolf §1.5.2).

    For the reverse path (from medium 2 at theta2, with n1 sin theta1 = n2 sin theta2):
    r' = -r and t t' = 1 - r^2, for s and p (with the sign convention of ``tmm``,
    r_p = (n2 cos1 - n1 cos2)/(n2 cos1 + n1 cos2), both hold for p as well).  Also
    R + T = 1 each way, below the critical angle.
    """
    theta_c = math.asin(n2 / n1) if n2 < n1 else math.pi / 2
    theta1 = np.linspace(-0.95 * theta_c, 0.95 * theta_c, 41)
    theta2 = np.arcsin(n1 * np.sin(theta1) / n2)
    fw = fresnel_coefficients(n1, n2, theta1)
    bw = fresnel_coefficients(n2, n1, theta2)
    for pol in SP:
        r, t = getattr(fw, "r" + pol), getattr(fw, "t" + pol)
        r_b, t_b = getattr(bw, "r" + pol), getattr(bw, "t" + pol)
        np.testing.assert_allclose(r_b, -r, rtol=0, atol=1e-13)
        np.testing.assert_allclose(t * t_b + r**2, 1.0, rtol=0, atol=1e-13)
        np.testing.assert_allclose(np.imag(r), 0.0, atol=1e-15)
        np.testing.assert_allclose(getattr(fw, "R" + pol) + getattr(fw, "T" + pol), 1.0, rtol=0, atol=1e-14)
        np.testing.assert_allclose(getattr(bw, "R" + pol) + getattr(bw, "T" + pol), 1.0, rtol=0, atol=1e-14)
        np.testing.assert_allclose(getattr(fw, "R" + pol), abs(r) ** 2, rtol=1e-15, atol=1e-300)
        # reversibility of the power coefficients
        np.testing.assert_allclose(getattr(bw, "T" + pol), getattr(fw, "T" + pol), rtol=0, atol=1e-13)


@pytest.mark.analytic
@pytest.mark.parametrize("n1, n2", [(1.0, 1.33), (1.0, 1.5 + 0.0j), (1.33, 1.0), (1.0, 1.7 + 0.4j), (1.0, 0.2 + 3.0j)])
def test_fresnel_normal_incidence_and_energy(n1, n2):
    """Normal-incidence Fresnel coefficients and energy flux balance (Born & Wolf §1.5.2-3).

    At theta = 0: r_s = (n1 - n2)/(n1 + n2) and, in the ``tmm`` convention, r_p = -r_s;
    t_s = t_p = 2 n1/(n1 + n2); T = 4 n1 Re(n2)/|n1 + n2|^2.  At any angle, including beyond
    the critical angle and into absorbing media, the normal component of the Poynting vector is
    continuous across the interface, so R + T = 1 for s and p (Byrnes §3 defines T as that
    flux); beyond the critical angle R = 1, T = 0.
    """
    f = fresnel_coefficients(n1, n2, 0.0)
    rs = (n1 - n2) / (n1 + n2)
    np.testing.assert_allclose(f.rs, rs, rtol=1e-14, atol=1e-16)
    np.testing.assert_allclose(f.rp, -rs, rtol=1e-14, atol=1e-16)
    np.testing.assert_allclose(f.ts, 2 * n1 / (n1 + n2), rtol=1e-14)
    np.testing.assert_allclose(f.tp, 2 * n1 / (n1 + n2), rtol=1e-14)
    for T in (f.Ts, f.Tp):
        np.testing.assert_allclose(T, 4 * n1 * np.real(n2) / abs(n1 + n2) ** 2, rtol=1e-14)
    theta = np.linspace(-math.pi / 2, math.pi / 2, 181)
    f = fresnel_coefficients(n1, n2, theta)
    np.testing.assert_allclose(f.Rs + f.Ts, 1.0, rtol=0, atol=1e-14)
    np.testing.assert_allclose(f.Rp + f.Tp, 1.0, rtol=0, atol=1e-14)
    if np.imag(n2) == 0 and np.real(n2) < n1:
        beyond = n1 * np.sin(np.abs(theta)) > np.real(n2)
        np.testing.assert_allclose(f.Rs[beyond], 1.0, rtol=0, atol=1e-14)
        np.testing.assert_allclose(f.Rp[beyond], 1.0, rtol=0, atol=1e-14)
        assert np.all(f.Ts[beyond] <= 1e-15) and np.all(f.Tp[beyond] <= 1e-15)
    if np.imag(n2) == 0:
        theta_b = math.atan(np.real(n2) / n1)
        fb = fresnel_coefficients(n1, n2, theta_b)
        assert fb.Rp < 1e-30 and fb.Rs > 1e-3  # Brewster's angle (Hecht §8.6.1)


# ---------------------------------------------------------------------------------------------
# Incoherent (thick-film) average
# ---------------------------------------------------------------------------------------------
@pytest.mark.analytic
@pytest.mark.parametrize("pol", SP)
@pytest.mark.parametrize(
    "n0, n1, n2, theta",
    [
        (1.0, 1.33, 1.0, 0.0),
        (1.0, 1.33, 1.0, 1.2),
        (1.0, 1.33, 1.5, 0.4),
        (1.0, 2.0, 1.33, 0.8),
        (1.33, 1.5, 1.0, 0.6),
        (1.0, 2.4, 1.52, 1.45),
    ],
)
def test_thickness_average_is_the_incoherent_sum(pol, n0, n1, n2, theta):
    """Averaged over a period of thickness, the coherent R equals the incoherent sum.

    R(d) is a rational trigonometric function of beta; its mean over one period is the
    intensity sum of the multiply reflected beams with random phases (Macleod §2.7, "thick
    layers"; Byrnes §6; the average of 1/|1 - a e^{i phi}|^2 over phi is 1/(1 - |a|^2)):

        R_inc = R01 + T01 T10 R12 / (1 - R10 R12)

    per polarization (s and p separately; unpolarized is their mean).  Sampled uniformly with
    4096 points per period, the trapezoidal mean of a periodic analytic function converges
    geometrically, so the agreement is to rounding.
    """
    wl = 550.0
    q1 = _q(n1, n0, theta).real
    period = wl / (2 * q1)
    N = 4096
    d = np.arange(N) * (period / N) + 1000.0
    mean_R = film_reflectance(wl, d, theta, n1, n0, n2, pol).mean()
    mean_T = film_transmittance(wl, d, theta, n1, n0, n2, pol).mean()
    theta1 = math.asin(n0 * math.sin(theta) / n1)
    f01 = fresnel_coefficients(n0, n1, theta)
    f10 = fresnel_coefficients(n1, n0, theta1)
    f12 = fresnel_coefficients(n1, n2, theta1)
    R01, T01 = getattr(f01, "R" + pol), getattr(f01, "T" + pol)
    R10, T10 = getattr(f10, "R" + pol), getattr(f10, "T" + pol)
    R12, T12 = getattr(f12, "R" + pol), getattr(f12, "T" + pol)
    R_inc = R01 + T01 * T10 * R12 / (1 - R10 * R12)
    T_inc = T01 * T12 / (1 - R10 * R12)
    assert abs(mean_R - R_inc) <= 1e-10
    assert abs(mean_T - T_inc) <= 1e-10
    # and the coherent R really does vary over the period (the average is not trivial)
    if R12 > 1e-6:
        assert np.ptp(film_reflectance(wl, d, theta, n1, n0, n2, pol)) > 1e-3


# ---------------------------------------------------------------------------------------------
# Multilayer reductions
# ---------------------------------------------------------------------------------------------
ML_CASES = [
    (1.0, 1.33, None),
    (1.0, 1.7 + 0.1j, 1.5),
    (1.33, 1.5, 1.0),
    (1.0, 2.4 + 0.5j, 1.2 + 0.1j),
    (1.5, 1.0, 1.5),
]


@pytest.mark.analytic
@pytest.mark.parametrize("pol", POLS)
@pytest.mark.parametrize("n0, n1, n2", ML_CASES)
def test_multilayer_of_one_layer_is_the_film(pol, n0, n1, n2):
    """A stack of one layer is a single film (Born & Wolf §1.6.2 vs §7.6.1).

    The characteristic-matrix product for one layer is algebraically the Airy sum, so
    ``multilayer_rt`` with one layer equals ``film_rt`` (to 1e-13), for absorbing layers,
    unequal media, total internal reflection and tunnelling.
    """
    theta = np.array([0.0, 0.5, -1.0, 1.3, 1.5])[:, None, None]
    d = np.array([0.0, 0.5, 120.0, 987.6, 1e5])[None, :, None]
    wl = WAVELENGTHS[None, None, :]
    R, T = film_rt(wl, d, theta, n1, n0, n2, pol)
    Rm, Tm = multilayer_rt(wl, [n1], [d], theta, n0, n2, pol)
    np.testing.assert_allclose(Rm, R, rtol=0, atol=1e-13)
    np.testing.assert_allclose(Tm, T, rtol=0, atol=1e-13)


@pytest.mark.analytic
@pytest.mark.parametrize("pol", POLS)
@pytest.mark.parametrize("n0, n_inside", [(1.0, None), (1.0, 1.5), (1.33, 2.0 + 0.2j)])
def test_multilayer_absent_and_split_layers(pol, n0, n_inside):
    """Layers that change nothing (Born & Wolf §1.6.2; Macleod §2.2).

    * A layer of zero thickness has the unit characteristic matrix: inserting one (of any
      index) anywhere in a stack leaves R and T unchanged.
    * M(beta1) M(beta2) = M(beta1 + beta2) for one index: splitting a layer of thickness d into
      two of the same index with d1 + d2 = d changes nothing.
    * A layer of the (lossless) outside medium in front only delays the phase: no change.
    * A layer of a lossless inside medium at the back likewise changes nothing.
    """
    theta = np.array([0.0, 0.6, 1.2, 1.55])[:, None]
    wl = WAVELENGTHS
    n = [1.45, 1.333 + 1e-3j, 1.45]
    d1 = 1.75
    dw = 400.0 + 12.5
    d = [d1, dw, 2.0]
    R, T = multilayer_rt(wl, n, d, theta, n0, n_inside, pol)
    variants = [
        ([2.2 + 0.7j] + n, [0.0] + d),
        (n[:1] + [1.1] + n[1:], d[:1] + [0.0] + d[1:]),
        (n + [3.0], d + [0.0]),
        (n[:2] + [n[1]] + n[2:], [d1, 0.375 * dw, 0.625 * dw, 2.0]),  # 0.375 dw + 0.625 dw == dw exactly
        ([n0] + n, [321.0] + d),
    ]
    if n_inside is None or np.imag(n_inside) == 0:
        variants.append((n + [n0 if n_inside is None else n_inside], d + [654.0]))
    for n_v, d_v in variants:
        Rv, Tv = multilayer_rt(wl, n_v, d_v, theta, n0, n_inside, pol)
        np.testing.assert_allclose(Rv, R, rtol=0, atol=1e-13, err_msg=f"{n_v} {d_v}")
        np.testing.assert_allclose(Tv, T, rtol=0, atol=1e-13, err_msg=f"{n_v} {d_v}")
    # a layer of an absorbing inside medium at the back keeps R but absorbs: T drops
    if n_inside is not None and np.imag(n_inside) > 0:
        Rv, Tv = multilayer_rt(wl, n + [n_inside], d + [654.0], theta, n0, n_inside, pol)
        np.testing.assert_allclose(Rv, R, rtol=0, atol=1e-13)
        assert np.all(Tv < T)


# ---------------------------------------------------------------------------------------------
# The coursework's two-beam model
# ---------------------------------------------------------------------------------------------
@pytest.mark.analytic
@pytest.mark.parametrize("pol", POLS)
@pytest.mark.parametrize("n0, n1", [(1.0, 1.33), (1.0, 2.0), (1.33, 1.5), (1.0, 1.4 + 0.05j)])
def test_two_beam_is_4R01_sin2beta(pol, n0, n1):
    """The two-beam model is R_2b = 2 R01 (1 + cos delta) = 4 R01 sin^2 beta (Hecht §9.7.1).

    Two beams of equal intensity R01, with path difference 2 d n1 cos(theta1) and a pi phase
    change at one reflection, interfere to 4 R01 sin^2 beta, beta = 2 pi d n1 cos(theta1)/lambda;
    R01 is the Fresnel reflectance of the outer surface (``fresnel_coefficients``; mean of s and
    p for unpolarized light), and only Re(n1) counts.  Zero at d = 0.
    """
    theta = np.array([0.0, 0.4, -0.9, 1.3])[:, None, None]
    d = np.array([0.0, 1.0, 100.0, 333.3, 2500.0])[None, :, None]
    wl = WAVELENGTHS[None, None, :]
    n1r = float(np.real(n1))
    f = fresnel_coefficients(n0, n1r, theta)
    R01 = {"s": f.Rs, "p": f.Rp, "unpolarized": 0.5 * (f.Rs + f.Rp)}[pol]
    beta = 2 * np.pi * d * _q(n1r, n0, theta).real / wl
    expected = 4 * R01 * np.sin(beta) ** 2
    R2 = two_beam_reflectance(wl, d, theta, n1, n0, pol)
    np.testing.assert_allclose(R2, expected, rtol=1e-12, atol=1e-15)
    assert np.all(R2[:, 0, :] == 0.0)


@pytest.mark.analytic
@pytest.mark.parametrize("pol", SP)
@pytest.mark.parametrize("theta", [0.0, 0.5, 1.0])
def test_two_beam_error_is_second_order_in_R01(pol, theta):
    """The two-beam model is the exact film to first order in R01, its error is O(R01^2).

    For a free-standing lossless film Airy's formula (Born & Wolf §7.6.1) gives, per
    polarization, with rho = R01 and s = sin^2 beta, exactly

        R_2b - R = 4 rho s - 4 rho s/((1-rho)^2 + 4 rho s) = 4 rho^2 s (4 s - 2 + rho)/((1-rho)^2 + 4 rho s),

    so |R_2b - R| <= 4 rho^2 (2 + rho)/(1 - rho)^2 ~ 8 rho^2, the maximum reached for
    quarter-wave films (s = 1), where R_2b - R = 4 rho^2 (2 + rho)/(1 + rho)^2.
    (For water, rho = 0.02, this is 3e-3: the coursework's model is good to ~10 % of R.)
    """
    wl = WAVELENGTHS[1:-2]
    n = water_refractive_index(wl)
    d = np.linspace(0.0, 1500.0, 1501)[:, None]
    rho = abs(_r_interface(1.0, n, 1.0, theta, pol)) ** 2
    s = np.sin(2 * np.pi * d * _q(n, 1.0, theta).real / wl) ** 2
    R = film_reflectance(wl, d, theta, n, polarization=pol)
    R2 = two_beam_reflectance(wl, d, theta, n, polarization=pol)
    np.testing.assert_allclose(R2 - R, 4 * rho**2 * s * (4 * s - 2 + rho) / ((1 - rho) ** 2 + 4 * rho * s),
                               rtol=0, atol=1e-14)
    assert np.all(np.abs(R2 - R) <= 4 * rho**2 * (2 + rho) / (1 - rho) ** 2 + 1e-15)
    q = _q(n, 1.0, theta).real
    d_qw = wl / (4 * q)
    diff_qw = two_beam_reflectance(wl, d_qw, theta, n, polarization=pol) - film_reflectance(
        wl, d_qw, theta, n, polarization=pol)
    np.testing.assert_allclose(diff_qw, 4 * rho**2 * (2 + rho) / (1 + rho) ** 2, rtol=1e-10)
    # at d = 0 both vanish
    assert np.all(two_beam_reflectance(wl, 0.0, theta, n, polarization=pol) == 0.0)


# ---------------------------------------------------------------------------------------------
# Water dispersion
# ---------------------------------------------------------------------------------------------
@pytest.mark.analytic
def test_water_index_values_and_normal_dispersion():
    """Water at 20 °C (Daimon & Masumura, Appl. Opt. 46, 3811 (2007)).

    * At the helium d line (587.6 nm) the fit gives n = 1.3334 (refractiveindex.info,
      "H2O, Daimon and Masumura 2007, 20.0 °C"); the handbook value of n_D at 20 °C is 1.3330
      (CRC Handbook), within 1e-3.
    * Normal dispersion (Born & Wolf §2.3.4): dn/dlambda < 0 everywhere in the visible and near
      infrared, 300-1000 nm, far from water's absorption bands.
    * 1.32 < n < 1.35 across the visible, 400-800 nm.
    """
    n_d = float(water_refractive_index(587.6))
    assert abs(n_d - 1.3334) < 1e-4
    assert abs(n_d - 1.3330) < 1e-3
    wl = np.linspace(300.0, 1000.0, 7001)
    n = water_refractive_index(wl)
    assert np.all(np.diff(n) < 0)
    vis = water_refractive_index(np.linspace(400.0, 800.0, 401))
    assert np.all((vis > 1.32) & (vis < 1.35))


@pytest.mark.reference
def test_water_index_reproduces_the_sellmeier_formula():
    """Daimon & Masumura (2007) four-term Sellmeier fit, 20.0 °C, re-evaluated independently.

    n^2 - 1 = sum_i B_i lambda^2/(lambda^2 - C_i), lambda in µm, with the coefficients as
    published in the refractiveindex.info database (file
    database/data-nk/main/H2O/Daimon-20.0C.yml, "formula 2", range 0.182-1.129 µm):
    B = 0.5684027565, 0.1726177391, 0.02086189578, 0.1130748688;
    C = 0.005101829712, 0.01821153936, 0.02620722293, 10.69792721 µm^2.
    """
    B = [5.684027565e-1, 1.726177391e-1, 2.086189578e-2, 1.130748688e-1]
    C = [5.101829712e-3, 1.821153936e-2, 2.620722293e-2, 1.069792721e1]
    wl = np.linspace(182.0, 1129.0, 948)
    lam2 = (wl / 1000.0) ** 2
    expected = np.sqrt(1 + sum(b * lam2 / (lam2 - c) for b, c in zip(B, C)))
    np.testing.assert_allclose(water_refractive_index(wl), expected, rtol=1e-14)
    # the default film is water: n_film=None equals passing the water index
    d, th = 321.0, 0.4
    np.testing.assert_array_equal(film_reflectance(wl, d, th), film_reflectance(wl, d, th, water_refractive_index(wl)))
    assert film_reflectance(wl, d, th).shape == wl.shape
