"""Numba scalar kernels: the one copy of every optical formula in the project.

The NumPy API (:mod:`bubbleoptics.film`, :mod:`bubbleoptics.fresnel`, ...) broadcasts over
these kernels, and the ray tracer (:mod:`tracer`) calls the very same functions per ray and
wavelength sample.  Nothing here allocates, so they are cheap to call from inside other
``@njit`` code.  Scalar kernels end in ``_nb`` (``film_rt_nb`` is this module's, ``film_rt`` the
NumPy function of :mod:`bubbleoptics.film`); the loops over arrays that the NumPy functions
call end in ``_array`` or ``_grid``.

Conventions (everywhere in bubbleoptics)
----------------------------------------
* wavelength :math:`\\lambda` and film thickness :math:`d` in nanometres;
* angles in radians; the kernels take :math:`\\cos\\theta_0` of the angle of incidence in the
  outside medium (the tracer has it from a dot product, the NumPy API from ``np.cos``);
* complex refractive index :math:`n + ik` with :math:`k \\ge 0` for absorbing media, so a wave
  :math:`\\exp(+i 2\\pi n d\\cos\\theta/\\lambda)` decays (the convention of Byrnes' ``tmm``);
* the outside (incidence) medium is lossless, :math:`n_0` real;
* polarization code ``0`` = s (TE), ``1`` = p (TM), ``2`` = unpolarized (mean of the two).

Formulation
-----------
Let :math:`q_j = n_j\\cos\\theta_j` be the normal component of the wavevector in medium *j*
divided by :math:`2\\pi/\\lambda`.  Snell's law fixes :math:`n_j\\sin\\theta_j = n_0\\sin\\theta_0`,
so :math:`q_j^2 = n_j^2 - n_0^2\\sin^2\\theta_0`, which we evaluate as

.. math::  q_j^2 = (n_j - n_0)(n_j + n_0) + q_0^2,\\qquad q_0 = n_0\\cos\\theta_0 ,

free of the catastrophic cancellation of :math:`\\sqrt{1-\\sin^2\\theta_j}` near grazing
incidence, and exact (:math:`q_j = q_0`) at index match.  The branch is the one with
:math:`\\operatorname{Im} q_j \\ge 0` (decaying) and :math:`\\operatorname{Re} q_j \\ge 0`.

The tilted admittances are :math:`\\eta_j = q_j` for s and :math:`\\eta_j = q_j/n_j^2` for p
(the reciprocal of Macleod's :math:`n/\\cos\\theta`, which gives ``tmm``'s sign convention for
:math:`r_p`).  An interface has :math:`r_{ij} = (\\eta_i-\\eta_j)/(\\eta_i+\\eta_j)`.  The Airy
sum of a film (medium 1, thickness *d*) between media 0 and 2,
:math:`r = (r_{01} + r_{12}e)/(1 + r_{01}r_{12}e)` with :math:`e = \\exp(2i\\beta)`,
:math:`\\beta = 2\\pi d q_1/\\lambda`, is rewritten (multiply through by
:math:`(\\eta_0+\\eta_1)(\\eta_1+\\eta_2)`; Born & Wolf, *Principles of Optics*, 7th ed., §1.6.4
and §7.6.1; Macleod, *Thin-Film Optical Filters*, 4th ed., §2.2) as

.. math::

    r = \\frac{\\eta_1(\\eta_0-\\eta_2)(1+e) + (\\eta_0\\eta_2-\\eta_1^2)(1-e)}
             {\\eta_1(\\eta_0+\\eta_2)(1+e) + (\\eta_0\\eta_2+\\eta_1^2)(1-e)},\\qquad
    T = \\frac{16\\,\\eta_0\\,\\operatorname{Re}\\eta_2\\,|\\eta_1|^2\\,|e|}{|\\text{denominator}|^2}.

The two differences in the numerator are computed from exact identities
(:math:`q_i - q_j = (n_i^2-n_j^2)/(q_i+q_j)` and its p analogue) so that a free-standing film
gives :math:`\\eta_0-\\eta_2 = 0` exactly and near-index-matched films lose no digits; *T* is a
product, never :math:`1-R`, so it keeps its relative accuracy as it goes to zero at grazing
incidence.  For lossless films with every wave propagating the common phase
:math:`e^{i\\beta}` cancels and, with :math:`\\sigma = \\sin\\beta/\\eta_1`,

.. math::

    R = \\frac{(\\eta_0-\\eta_2)^2\\cos^2\\beta + (\\eta_0\\eta_2-\\eta_1^2)^2\\sigma^2}
             {(\\eta_0+\\eta_2)^2\\cos^2\\beta + (\\eta_0\\eta_2+\\eta_1^2)^2\\sigma^2},\\qquad
    T = \\frac{4\\eta_0\\eta_2}{(\\eta_0+\\eta_2)^2\\cos^2\\beta + (\\eta_0\\eta_2+\\eta_1^2)^2\\sigma^2},

real arithmetic only, every term non-negative (no cancellation), and :math:`\\sigma` stays finite
(a sinc) when :math:`q_1 \\to 0`.  Otherwise :math:`1 \\pm e` are formed from ``expm1`` and
half-angle products, both free of cancellation, with :math:`|e| \\le 1` so thick absorbing films
never overflow.
"""

import cmath
import math

import numpy as np
from numba import njit, prange
from .jit import JIT, JIT_FMA, JIT_INLINE, JIT_PARALLEL

__all__ = [
    "COS_MIN",
    "POL_S",
    "POL_P",
    "POL_UNPOLARIZED",
    "N_FILM_COEFFICIENTS",
    "FILM_KQ",
    "FILM_Q1_TERM",
    "FILM_G",
    "FILM_S",
    "FILM_P",
    "FILM_PATH",
    "PATH_REAL",
    "PATH_COMPLEX",
    "PATH_TOTAL_REFLECTION",
    "normal_wavevector_nb",
    "fresnel_interface_nb",
    "fresnel_dielectric_nb",
    "film_setup_nb",
    "sin2_cos2_nb",
    "sin_cos_nb",
    "BETA_POLY_MAX",
    "film_evaluate_nb",
    "film_rt_nb",
    "free_film_setup_nb",
    "free_film_evaluate_nb",
    "free_film_band_average_nb",
    "free_film_setup_bands_nb",
    "free_film_evaluate_bands_nb",
    "two_beam_r_nb",
    "multilayer_rt_nb",
    "water_index_daimon2007_nb",
    "srgb_encode_nb",
    "srgb_decode_nb",
]

POL_S = 0
POL_P = 1
POL_UNPOLARIZED = 2

#: Smallest cos(theta_0) used: exactly grazing rays (cos = 0, e.g. tangent rays in the tracer)
#: are treated as cos = 1e-150, where R = 1 - O(1e-150); this keeps every formula finite.
COS_MIN = 1e-150

#: Length of the coefficient tuple returned by :func:`film_setup_nb`, and its entries: the phase
#: rate 2 pi q1 / lambda (complex on the complex path), 1/q1 (real path) or n1^2 (complex
#: path), 2 pi / lambda, the five s-polarized and the five p-polarized coefficients (from
#: FILM_S and FILM_P: numerator cos and sin terms, denominator cos and sin terms, transmission
#: factor), and the path taken (FILM_PATH, stored as a complex number like the rest: one of the
#: PATH_* values).
N_FILM_COEFFICIENTS = 14
FILM_KQ = 0
FILM_Q1_TERM = 1
FILM_G = 2
FILM_S = 3
FILM_P = 8
FILM_PATH = 13
PATH_REAL = 0.0  # lossless media, every wave propagating: real arithmetic
PATH_COMPLEX = 1.0  # an absorbing medium or an evanescent film
PATH_TOTAL_REFLECTION = 2.0  # lossless media, evanescent inside medium: R = 1, T = 0


_TWO_PI = 2.0 * math.pi
_Q_SMALL = 1e-60  # below this, sin(beta)/q1 is evaluated as a sinc (q1 -> 0 at the critical angle)


# --------------------------------------------------------------------------------------------
# Building blocks
# --------------------------------------------------------------------------------------------
@njit(**JIT_INLINE)
def _q_squared(n, n0, q0):
    """:math:`q^2 = (n-n_0)(n+n_0) + q_0^2`; real for real *n*, complex for complex *n*."""
    return (n - n0) * (n + n0) + q0 * q0


@njit(**JIT_INLINE)
def normal_wavevector_nb(n, n0, q0):
    """Normal wavevector component :math:`q = n\\cos\\theta` in a medium of index *n*.

    :math:`q^2 = (n-n_0)(n+n_0) + q_0^2` (Snell's law, no cancellation near grazing);
    the branch has :math:`\\operatorname{Im} q \\ge 0`, :math:`\\operatorname{Re} q \\ge 0`.

    Parameters: *n* complex index of the medium, *n0* real index of the incidence medium,
    *q0* = :math:`n_0\\cos\\theta_0` (real, >= 0).  Returns complex *q*.
    """
    z = _q_squared(n + 0j, n0, q0)
    # Im(n^2) = 2 n k >= 0; clamp rounding (and -0.0) so the principal root is the decaying one.
    return cmath.sqrt(complex(z.real, max(z.imag, 0.0)))


@njit(**JIT_INLINE)
def _eta_difference(ni, nj, qi, qj, s2, pol):
    """:math:`\\eta_i - \\eta_j` without cancellation (s: q; p: q/n^2).

    s: :math:`q_i-q_j = (n_i^2-n_j^2)/(q_i+q_j)`.
    p: :math:`q_i/n_i^2 - q_j/n_j^2 = (n_j^2-n_i^2)(n_i^2n_j^2 - s^2(n_i^2+n_j^2))
    / (n_i^2 n_j^2 (n_j^2 q_i + n_i^2 q_j))`, with :math:`s = n_0\\sin\\theta_0`.
    Falls back to the direct difference where the identity's denominator itself cancels
    (only possible for media with Re(n^2) < 0, i.e. metals at surface-plasmon conditions).
    """
    if pol == POL_S:
        den = qi + qj
        if abs(den) > 0.5 * (abs(qi) + abs(qj)):
            return (ni - nj) * (ni + nj) / den
        return qi - qj
    ni2 = ni * ni
    nj2 = nj * nj
    den = nj2 * qi + ni2 * qj
    if abs(den) > 0.5 * (abs(nj2 * qi) + abs(ni2 * qj)):
        return (nj - ni) * (nj + ni) * (ni2 * nj2 - s2 * (ni2 + nj2)) / (ni2 * nj2 * den)
    return qi / ni2 - qj / nj2


@njit(**JIT)
def _film_terms(n0, n1, n2, q0, q1, q2, s2, pol):
    """Admittances and the four Airy-form factors for one polarization.

    Returns (eta0, eta2, a, b, c, D) with a = eta0 - eta2, b = eta0 eta2 - eta1^2,
    c = eta0 + eta2, D = eta0 eta2 + eta1^2 (eta1 itself is q1 or q1/n1^2).
    Type-generic: numba compiles it for real arguments (the lossless path, real arithmetic
    only) and for complex ones (pass *n0*, *q0* as complex there); one formula, two builds.
    """
    if pol == POL_S:
        e0 = q0
        e1 = q1
        e2 = q2
    else:
        e0 = q0 / (n0 * n0)
        e1 = q1 / (n1 * n1)
        e2 = q2 / (n2 * n2)
    a = _eta_difference(n0, n2, q0, q2, s2, pol)
    # eta0 eta2 - eta1^2 = eta0 (eta2 - eta0) + (eta0 - eta1)(eta0 + eta1)
    b = e0 * _eta_difference(n2, n0, q2, q0, s2, pol) + _eta_difference(n0, n1, q0, q1, s2, pol) * (e0 + e1)
    return e0, e2, a, b, e0 + e2, e0 * e2 + e1 * e1


@njit(**JIT)
def _sinc(x):
    """sin(x)/x, exact to rounding for all real x (series below 1e-4)."""
    if abs(x) < 1e-4:
        x2 = x * x
        return 1.0 - x2 / 6.0 + x2 * x2 / 120.0
    return math.sin(x) / x


# pi/2 split in three parts (Cody & Waite, "Software Manual for the Elementary Functions",
# 1980, ch. 8): the first two carry 31 and 32 significant bits, so k*_PIO2_1 and k*_PIO2_2 are
# exact for k < 2**21, and beta - k*_PIO2_1 is exact (Sterbenz); values computed with mpmath.
_PIO2_1 = 1.5707963267341256
_PIO2_2 = 6.077100506303966e-11
_PIO2_3 = 2.0222662487959506e-21
_TWO_OVER_PI = 0.6366197723675814
#: Largest phase for :func:`sin2_cos2_nb` (k < 2**20 quadrants); larger phases use libm.
BETA_POLY_MAX = 2.0**20 * 1.5707963267948966
# Taylor coefficients (-1)^n/(2n+1)!; on |r| <= pi/4 the first omitted term is below 1e-19
# relative, i.e. well under half an ulp.
_S3, _S5, _S7, _S9 = -1 / 6, 1 / 120, -1 / 5040, 1 / 362880
_S11, _S13, _S15, _S17 = -1 / 39916800, 1 / 6227020800, -1 / 1307674368000, 1 / 355687428096000
# and (-1)^n/(2n)! for cos r (the first omitted term, r^18/18!, is below 2e-18 on |r| <= pi/4)
_C2, _C4, _C6, _C8 = -1 / 2, 1 / 24, -1 / 720, 1 / 40320
_C10, _C12, _C14, _C16 = -1 / 3628800, 1 / 479001600, -1 / 87178291200, 1 / 20922789888000


@njit(**JIT_INLINE)
def sin2_cos2_nb(beta):
    """(sin²β, cos²β) for 0 <= β <= :data:`BETA_POLY_MAX`, without branches.

    Why by hand: numba calls libm's scalar sin and cos (a function call each) and, since it
    dropped SVML, cannot vectorize them; this straight-line version lets LLVM vectorize the
    thickness loop.  Reduction β = kπ/2 + r with the three-part π/2 above (error in r below
    1 ulp of r plus 1e-27), the Taylor polynomial of sin r on |r| <= π/4, cos²r = 1 - sin²r
    (at least 1/2 there, so no digit is lost), and the quadrant applied as an exact 0/1 blend
    (only squares are needed, so signs drop out).  Checked against libm and
    mpmath in ``tests/bubbleoptics/test_kernels.py``.
    """
    k, r = _reduce_pio2(beta)
    sr = _sin_poly(r)
    s2 = sr * sr
    c2 = 1.0 - s2  # |r| <= pi/4: sin^2 r <= 1/2, so cos^2 r >= 1/2 and the difference keeps its digits
    odd = k - 2.0 * np.floor(0.5 * k)  # 0.0 or 1.0
    even = 1.0 - odd
    return odd * c2 + even * s2, odd * s2 + even * c2


@njit(**JIT_INLINE)
def _reduce_pio2(x):
    """(k, r) with x = k pi/2 + r, |r| <= pi/4 (up to rounding), k a whole number as a float.

    ``np.floor`` keeps k a float: numba's ``math.floor`` returns an int64, and AVX2 has no packed
    conversion between doubles and 64-bit integers, so an integer k made LLVM convert each lane
    of a vectorized loop on its own (``free_film_evaluate_bands_nb`` took 127 ns for 16 bands
    with it and 85 ns without, docs/performance.md)."""
    k = np.floor(x * _TWO_OVER_PI + 0.5)
    return k, ((x - k * _PIO2_1) - k * _PIO2_2) - k * _PIO2_3


@njit(**JIT_INLINE)
def _sin_poly(r):
    """Taylor polynomial of sin r to r^17 (|r| <= pi/4: first omitted term below 1e-19 relative)."""
    r2 = r * r
    return r + r * r2 * (_S3 + r2 * (_S5 + r2 * (_S7 + r2 * (_S9 + r2 * (_S11 + r2 * (_S13 + r2 * (_S15 + r2 * _S17)))))))


@njit(**JIT_INLINE)
def _cos_poly(r):
    """Taylor polynomial of cos r to r^16 (|r| <= pi/4: first omitted term below 2e-18)."""
    r2 = r * r
    return 1.0 + r2 * (_C2 + r2 * (_C4 + r2 * (_C6 + r2 * (_C8 + r2 * (_C10 + r2 * (_C12 + r2 * (_C14 + r2 * _C16)))))))


@njit(**JIT_INLINE)
def sin_cos_nb(x):
    """(sin x, cos x), branch-free for |x| <= :data:`BETA_POLY_MAX`, libm beyond (and for inf, NaN).

    Why by hand: libm's ``sin`` is a call that LLVM can neither inline nor vectorize, and the
    tracer's swirling films evaluate five of them per hit (:func:`tracer.kernels.thickness.film_thickness`;
    about 23 ns each on the project's machine).  The reduction and polynomials of
    :func:`sin2_cos2_nb`; the quadrant q = k mod 4 picks and signs them as exact 0/1 blends:
    sin x = (s, c, -s, -c) and cos x = (c, -s, -c, s) for q = 0..3, s = sin r, c = cos r.
    Checked against mpmath and libm in ``tests/bubbleoptics/test_kernels.py``.
    """
    if not abs(x) <= BETA_POLY_MAX:
        return math.sin(x), math.cos(x)
    k, r = _reduce_pio2(x)
    s = _sin_poly(r)
    c = _cos_poly(r)
    q = k - 4.0 * np.floor(0.25 * k)  # 0, 1, 2 or 3 (k may be negative)
    half = np.floor(0.5 * q)  # 0 for q = 0, 1; 1 for q = 2, 3
    odd = q - 2.0 * half  # 0 or 1
    flip = odd + half - 2.0 * odd * half  # odd xor half: cos x is negative for q = 1, 2
    return (1.0 - 2.0 * half) * (odd * c + (1.0 - odd) * s), (1.0 - 2.0 * flip) * (odd * s + (1.0 - odd) * c)


@njit(**JIT)
def _phase_terms(kq, g, d):
    """Terms of :math:`e = \\exp(2i\\beta)`, :math:`\\beta = k_q d` complex with Im >= 0.

    Returns (1 + e, (1 - e)/q, |e|) where q = kq/g (so the second term stays finite as
    q -> 0).  With :math:`2i\\beta = x + iy`, :math:`x \\le 0`:
    :math:`1 - e = -\\mathrm{expm1}(x) + 2e^x\\sin^2(y/2) - 2ie^x\\sin(y/2)\\cos(y/2)` and
    :math:`1 + e = -\\mathrm{expm1}(x) + 2e^x\\cos^2(y/2) + 2ie^x\\sin(y/2)\\cos(y/2)`: sums of
    non-negative terms, no cancellation, and bounded by 2.
    """
    beta = kq * d
    x = -2.0 * beta.imag
    ex = math.exp(x)
    em = -math.expm1(x)
    sh = math.sin(beta.real)
    ch = math.cos(beta.real)
    cross = 2.0 * ex * sh * ch
    one_p_e = complex(em + 2.0 * ex * ch * ch, cross)
    if abs(beta) < 1e-2:
        # (1 - e)/q = g d (1 - e)/beta,  1 - e^z = -z (1 + z/2 + z^2/6 + ...),  z = 2 i beta
        z = 2j * beta
        series = 1.0 + z * (1 / 2 + z * (1 / 6 + z * (1 / 24 + z * (1 / 120 + z * (1 / 720 + z / 5040)))))
        u = g * d * (-2j) * series
    else:
        u = complex(em + 2.0 * ex * sh * sh, -cross) * g / kq
    return one_p_e, u, ex


# --------------------------------------------------------------------------------------------
# Single interface
# --------------------------------------------------------------------------------------------
@njit(**JIT)
def fresnel_interface_nb(n1, n2, cos1):
    """Fresnel amplitude coefficients of one interface (Born & Wolf §1.5.2; tmm conventions).

    .. math::

        r_s = \\frac{q_1-q_2}{q_1+q_2},\\; t_s = \\frac{2q_1}{q_1+q_2},\\;
        r_p = \\frac{n_2^2q_1-n_1^2q_2}{n_2^2q_1+n_1^2q_2},\\;
        t_p = \\frac{2n_1n_2q_1}{n_2^2q_1+n_1^2q_2},\\quad q_j = n_j\\cos\\theta_j,

    with the differences evaluated without cancellation.  Power coefficients:
    :math:`R = |r|^2`, :math:`T_s = \\operatorname{Re}(q_2)/q_1\\,|t_s|^2`,
    :math:`T_p = \\operatorname{Re}(n_2\\overline{\\cos\\theta_2})/q_1\\,|t_p|^2`.

    Parameters: *n1* real index of the incidence medium, *n2* complex index (k >= 0),
    *cos1* cosine of the angle of incidence.
    Returns (rs, rp, ts, tp, Rs, Rp, Ts, Tp).
    """
    c1 = max(cos1, COS_MIN)
    q1 = n1 * c1
    s2 = n1 * n1 * (1.0 - c1) * (1.0 + c1)
    q2 = normal_wavevector_nb(n2, n1, q1)
    n1c = n1 + 0j
    q1c = q1 + 0j
    rs = _eta_difference(n1c, n2, q1c, q2, s2, POL_S) / (q1c + q2)
    ts = 2.0 * q1 / (q1c + q2)
    # r_p = (Q1 - Q2)/(Q1 + Q2), Q = q/n^2
    Q1 = q1 / (n1 * n1)
    Q2 = q2 / (n2 * n2)
    rp = _eta_difference(n1c, n2, q1c, q2, s2, POL_P) / (Q1 + Q2)
    tp = 2.0 * n1 * n2 * q1 / (n2 * n2 * q1 + n1 * n1 * q2)
    if n2.imag == 0.0 and q2.imag > 0.0:
        # total internal reflection: |r| = 1 exactly (rounding would give 1 + O(eps))
        rs = rs / abs(rs)
        rp = rp / abs(rp)
        return rs, rp, ts, tp, 1.0, 1.0, 0.0, 0.0
    Rs = rs.real * rs.real + rs.imag * rs.imag
    Rp = rp.real * rp.real + rp.imag * rp.imag
    Ts = q2.real / q1 * (ts.real * ts.real + ts.imag * ts.imag)
    Tp = (n2 * (q2 / n2).conjugate()).real / q1 * (tp.real * tp.real + tp.imag * tp.imag)
    return rs, rp, ts, tp, Rs, Rp, Ts, Tp


@njit(**JIT)
def fresnel_dielectric_nb(n1, n2, cos1):
    """Power reflectances of one interface between two lossless media, in real arithmetic.

    The same formulas as :func:`fresnel_interface_nb` (Born & Wolf §1.5.2), built from the same
    cancellation-free differences (:func:`_q_squared`, :func:`_eta_difference`, which are
    type-generic) for real *n1*, *n2* > 0:

    .. math::

        q_2^2 = (n_2-n_1)(n_2+n_1) + q_1^2,\\;
        R_s = \\left(\\frac{q_1-q_2}{q_1+q_2}\\right)^2,\\;
        R_p = \\left(\\frac{q_1/n_1^2-q_2/n_2^2}{q_1/n_1^2+q_2/n_2^2}\\right)^2,
        \\quad q_j = n_j\\cos\\theta_j.

    Returns (Rs, Rp, q2): q2 = n2 cos(theta_2) >= 0 of the transmitted wave, and (1, 1, 0) at
    total internal reflection (q2^2 <= 0).  Why a second build: the complex one pays for a
    complex square root and complex divisions at every hit of the tracer's clear spheres,
    whose indices are real (checked against :func:`fresnel_interface_nb` and ``tmm`` in
    ``tests/bubbleoptics/test_kernels.py``).
    """
    c1 = max(cos1, COS_MIN)
    q1 = n1 * c1
    z = _q_squared(n2, n1, q1)
    if z <= 0.0:
        return 1.0, 1.0, 0.0
    q2 = math.sqrt(z)
    s2 = n1 * n1 * (1.0 - c1) * (1.0 + c1)
    rs = _eta_difference(n1, n2, q1, q2, s2, POL_S) / (q1 + q2)
    rp = _eta_difference(n1, n2, q1, q2, s2, POL_P) / (q1 / (n1 * n1) + q2 / (n2 * n2))
    return rs * rs, rp * rp, q2


# --------------------------------------------------------------------------------------------
# Single film (the Airy sum), in two stages: setup per (lambda, theta, media), evaluate per d
# --------------------------------------------------------------------------------------------
@njit(**JIT)
def film_setup_nb(wavelength, cos0, n0, n1, n2):
    """Stage 1 of the exact single-film Airy sum: everything that does not depend on *d*.

    Parameters
    ----------
    wavelength : float, vacuum wavelength :math:`\\lambda` in nm (> 0).
    cos0 : float, :math:`\\cos\\theta_0` of the angle of incidence in the outside medium.
    n0 : float, real index of the outside medium.
    n1, n2 : complex, indices :math:`n+ik` of the film and of the inside medium.

    Returns a tuple of :data:`N_FILM_COEFFICIENTS` complex numbers for :func:`film_evaluate_nb`
    (entries named by the ``FILM_*`` constants).  Entry :data:`FILM_PATH` is
    :data:`PATH_REAL` for the real-arithmetic path (lossless media, every wave propagating),
    :data:`PATH_COMPLEX` for the complex path, :data:`PATH_TOTAL_REFLECTION` for total
    reflection (lossless media, evanescent inside medium).  See the module docstring for the
    formulas.
    """
    c0 = max(cos0, COS_MIN)
    q0 = n0 * c0
    s2 = n0 * n0 * (1.0 - c0) * (1.0 + c0)
    g = _TWO_PI / wavelength
    if n1.imag == 0.0 and n2.imag == 0.0:
        n1r = n1.real
        n2r = n2.real
        z2 = _q_squared(n2r, n0, q0)
        if z2 < 0.0:
            # Total reflection: lossless media and an evanescent inside medium carry no energy
            # away, so R = 1 and T = 0 exactly.  (Evaluating the Airy form here loses |r| = 1
            # near the film's guided-mode resonances at grazing incidence, where its numerator
            # and denominator both vanish like q0.)
            return (0j, 0j, complex(g, 0.0), 0j, 0j, 0j, 0j, 0j, 0j, 0j, 0j, 0j, 0j, complex(PATH_TOTAL_REFLECTION, 0.0))
        z1 = _q_squared(n1r, n0, q0)
        if z1 >= 0.0:
            # lossless, every wave propagating: real arithmetic only
            q1 = math.sqrt(z1)
            q2 = math.sqrt(z2)
            s0, s2e, a_s, b_s, c_s, d_s = _film_terms(n0, n1r, n2r, q0, q1, q2, s2, POL_S)
            p0, p2e, a_p, b_p, c_p, d_p = _film_terms(n0, n1r, n2r, q0, q1, q2, s2, POL_P)
            inv_q1 = 1.0 / q1 if q1 > _Q_SMALL else 0.0
            n1sq = n1r * n1r
            return (
                complex(g * q1, 0.0),
                complex(inv_q1, 0.0),
                complex(g, 0.0),
                complex(a_s * a_s, 0.0),
                complex(b_s * b_s, 0.0),
                complex(c_s * c_s, 0.0),
                complex(d_s * d_s, 0.0),
                complex(4.0 * s0 * s2e, 0.0),
                complex(a_p * a_p, 0.0),
                complex((b_p * n1sq) ** 2, 0.0),
                complex(c_p * c_p, 0.0),
                complex((d_p * n1sq) ** 2, 0.0),
                complex(4.0 * p0 * p2e, 0.0),
                complex(PATH_REAL, 0.0),
            )
    q1 = normal_wavevector_nb(n1, n0, q0)
    q2 = normal_wavevector_nb(n2, n0, q0)
    n0c = n0 + 0j
    q0c = q0 + 0j
    s0, s2e, a_s, b_s, c_s, d_s = _film_terms(n0c, n1, n2, q0c, q1, q2, s2, POL_S)
    p0, p2e, a_p, b_p, c_p, d_p = _film_terms(n0c, n1, n2, q0c, q1, q2, s2, POL_P)
    return (
        g * q1,
        n1 * n1,
        complex(g, 0.0),
        a_s,
        b_s,
        c_s,
        d_s,
        complex(16.0 * s0.real * s2e.real, 0.0),
        a_p,
        b_p,
        c_p,
        d_p,
        complex(16.0 * p0.real * p2e.real, 0.0),
        complex(PATH_COMPLEX, 0.0),
    )


@njit(**JIT)
def _real_rt(cos2, sig2, as_, bs, cs, ds, ts, ap, bp, cp, dp, tp, pol):
    """Lossless-path (R, T) from cos²β and σ² = sin²β/q1² (module docstring, real form).

    as_, bs, cs, ds, ts (s) and ap, bp, cp, dp, tp (p) are entries 3-12 of :func:`film_setup_nb`.
    """
    R = 0.0
    T = 0.0
    if pol != POL_P:
        den = cs * cos2 + ds * sig2
        R += (as_ * cos2 + bs * sig2) / den
        T += ts / den
    if pol != POL_S:
        den = cp * cos2 + dp * sig2
        R += (ap * cos2 + bp * sig2) / den
        T += tp / den
    if pol == POL_UNPOLARIZED:
        R *= 0.5
        T *= 0.5
    return R, T


@njit(**JIT)
def _real_rt_c(c, cos2, sig2, pol):
    S = FILM_S
    P = FILM_P
    return _real_rt(cos2, sig2, c[S].real, c[S + 1].real, c[S + 2].real, c[S + 3].real, c[S + 4].real,
                    c[P].real, c[P + 1].real, c[P + 2].real, c[P + 3].real, c[P + 4].real, pol)


@njit(**JIT)
def film_evaluate_nb(c, d, pol):
    """Stage 2 of the Airy sum: (R, T) of the film of thickness *d* nm for polarization *pol*.

    *c* is the tuple (or a row of an array) from :func:`film_setup_nb`; *pol* is 0 (s), 1 (p) or
    2 (unpolarized: the mean of s and p).  Returns (R, T), both in [0, 1].
    """
    flag = c[FILM_PATH].real
    if flag == PATH_TOTAL_REFLECTION:
        return 1.0, 0.0
    if flag == PATH_REAL:
        beta = c[FILM_KQ].real * d
        if beta <= BETA_POLY_MAX:
            sn2, cs2 = sin2_cos2_nb(beta)
        else:
            sb = math.sin(beta)
            cb = math.cos(beta)
            sn2 = sb * sb
            cs2 = cb * cb
        inv_q1 = c[FILM_Q1_TERM].real
        if inv_q1 > 0.0:
            sig2 = sn2 * (inv_q1 * inv_q1)
        else:
            # q1 -> 0 (film at its critical angle): sigma = d (2 pi/lambda) sinc(beta)
            sinc2 = sn2 / (beta * beta) if beta > 1e-4 else _sinc(beta) ** 2
            sig2 = (d * c[FILM_G].real) ** 2 * sinc2
        return _real_rt_c(c, cs2, sig2, pol)
    R = 0.0
    T = 0.0
    one_p_e, u, ex = _phase_terms(c[FILM_KQ], c[FILM_G].real, d)
    if pol != POL_P:
        num = c[FILM_S] * one_p_e + c[FILM_S + 1] * u
        den = c[FILM_S + 2] * one_p_e + c[FILM_S + 3] * u
        dd = den.real * den.real + den.imag * den.imag
        R += (num.real * num.real + num.imag * num.imag) / dd
        T += c[FILM_S + 4].real * ex / dd
    if pol != POL_S:
        up = u * c[FILM_Q1_TERM]
        num = c[FILM_P] * one_p_e + c[FILM_P + 1] * up
        den = c[FILM_P + 2] * one_p_e + c[FILM_P + 3] * up
        dd = den.real * den.real + den.imag * den.imag
        R += (num.real * num.real + num.imag * num.imag) / dd
        T += c[FILM_P + 4].real * ex / dd
    if pol == POL_UNPOLARIZED:
        R *= 0.5
        T *= 0.5
    return R, T


@njit(**JIT)
def film_rt_nb(wavelength, thickness, cos0, n0, n1, n2, pol):
    """Exact (R, T) of one film: :func:`film_evaluate_nb` of :func:`film_setup_nb`.

    Units: nm, cosine of the angle of incidence, real *n0*, complex *n1*, *n2*; *pol* 0/1/2.
    """
    return film_evaluate_nb(film_setup_nb(wavelength, cos0, n0, n1, n2), thickness, pol)


# --------------------------------------------------------------------------------------------
# The coursework's two-beam model (coursework eqs. 1.1-1.3)
# --------------------------------------------------------------------------------------------
@njit(**JIT)
def two_beam_r_nb(wavelength, thickness, cos0, n0, n1, pol):
    """The coursework's two-beam reflectance, normalised by the first interface's reflectance.

    Seed eqs. (1.1)-(1.3): :math:`\\Delta = 2 d n_1\\cos\\theta_1 - \\lambda/2`,
    :math:`\\delta = 2\\pi\\Delta/\\lambda`, :math:`I = 2 I_0 (1 + \\cos\\delta)`.  With
    :math:`I_0 = R_{01}` (Fresnel reflectance of the outer surface, same polarization) and
    :math:`1 + \\cos\\delta = 2\\sin^2\\beta`, :math:`\\beta = 2\\pi d n_1\\cos\\theta_1/\\lambda`,
    this is :math:`R_{2b} = 4R_{01}\\sin^2\\beta` (written so, it has no cancellation for thin
    films).  It ignores multiple reflections, the unequal amplitudes of the two beams, absorption
    (only Re *n1* is used) and an inside medium different from the outside.  It can exceed 1
    near grazing incidence, where R01 -> 1: that is the model's defect, kept on purpose.
    """
    c0 = max(cos0, COS_MIN)
    q0 = n0 * c0
    n1r = n1.real + 0j
    q1 = normal_wavevector_nb(n1r, n0, q0)
    _, _, _, _, Rs, Rp, _, _ = fresnel_interface_nb(n0, n1r, c0)
    sb = math.sin(_TWO_PI * thickness * q1.real / wavelength)
    if pol == POL_S:
        r01 = Rs
    elif pol == POL_P:
        r01 = Rp
    else:
        r01 = 0.5 * (Rs + Rp)
    return 4.0 * r01 * sb * sb


# --------------------------------------------------------------------------------------------
# Multilayer stack: scaled characteristic matrices
# --------------------------------------------------------------------------------------------
@njit(**JIT)
def multilayer_rt_nb(wavelength, n_layers, d_layers, cos0, n0, n_inside, pol):
    """(R, T) of a stack of films by characteristic (transfer) matrices.

    Each layer's matrix :math:`M_j = [[\\cos\\beta_j, -i\\sin\\beta_j/\\eta_j],
    [-i\\eta_j\\sin\\beta_j, \\cos\\beta_j]]` (Macleod §2.2; Born & Wolf §1.6.2) is used scaled by
    :math:`e^{i\\beta_j}`, i.e. :math:`\\tfrac12[[1+e_j, (1-e_j)/\\eta_j], [\\eta_j(1-e_j), 1+e_j]]`,
    which stays bounded for thick absorbing layers; :math:`[B, C]^T = \\prod M_j [1, \\eta_m]^T`,
    :math:`r = (\\eta_0B - C)/(\\eta_0B + C)`,
    :math:`T = 4\\eta_0\\operatorname{Re}\\eta_m\\prod_j|e_j| / |\\eta_0B + C|^2`.

    *n_layers*, *d_layers*: 1-D arrays (complex, float nm), outermost layer first.
    For one layer this equals :func:`film_rt_nb` to rounding (tested); the single-film kernel is
    preferred there because it also removes the cancellation in the numerator.
    """
    c0 = max(cos0, COS_MIN)
    q0 = n0 * c0
    g = _TWO_PI / wavelength
    qm = normal_wavevector_nb(n_inside, n0, q0)
    if n_inside.imag == 0.0 and qm.imag > 0.0:
        lossless = True
        for j in range(n_layers.shape[0]):
            if n_layers[j].imag != 0.0:
                lossless = False
        if lossless:
            return 1.0, 0.0  # total reflection, as in film_setup_nb
    R = 0.0
    T = 0.0
    for p in range(2):
        if (pol == POL_S and p == 1) or (pol == POL_P and p == 0):
            continue
        if p == 0:
            eta0 = q0
            etam = qm
        else:
            eta0 = q0 / (n0 * n0)
            etam = qm / (n_inside * n_inside)
        B = 1.0 + 0j
        C = etam
        attenuation = 1.0
        for j in range(n_layers.shape[0] - 1, -1, -1):
            nj = n_layers[j]
            qj = normal_wavevector_nb(nj, n0, q0)
            one_p_e, u, ex = _phase_terms(g * qj, g, d_layers[j])
            if p == 0:
                eta = qj
                u_eta = u  # (1 - e)/eta
            else:
                eta = qj / (nj * nj)
                u_eta = u * nj * nj
            # 1 - e = u q;  scaled matrix 1/2 [[1+e, (1-e)/eta], [eta (1-e), 1+e]]
            B, C = 0.5 * (one_p_e * B + u_eta * C), 0.5 * (eta * (u * qj) * B + one_p_e * C)
            attenuation *= ex
        den = eta0 * B + C
        num = eta0 * B - C
        dd = den.real * den.real + den.imag * den.imag
        R += (num.real * num.real + num.imag * num.imag) / dd
        T += 4.0 * eta0 * etam.real * attenuation / dd
    if pol == POL_UNPOLARIZED:
        R *= 0.5
        T *= 0.5
    return R, T


# --------------------------------------------------------------------------------------------
# Dispersion
# --------------------------------------------------------------------------------------------
# Daimon & Masumura (2007), Appl. Opt. 46, 3811-3820, doi:10.1364/AO.46.003811: four-term
# Sellmeier fit for distilled water at 20.0 degC, valid 182-1129 nm; B_i dimensionless, C_i in
# um^2 (coefficients as tabulated by refractiveindex.info for that paper).
_DM2007_B = (5.684027565e-1, 1.726177391e-1, 2.086189578e-2, 1.130748688e-1)
_DM2007_C = (5.101829712e-3, 1.821153936e-2, 2.620722293e-2, 1.069792721e1)


@njit(**JIT)
def water_index_daimon2007_nb(wavelength):
    """Refractive index of water at 20 degC, Daimon & Masumura (2007), 182-1129 nm.

    .. math::  n^2 - 1 = \\sum_{i=1}^4 \\frac{B_i\\lambda^2}{\\lambda^2 - C_i},
               \\quad \\lambda \\text{ in } \\mu m .
    """
    lam2 = (wavelength * 1e-3) ** 2
    s = 1.0
    for i in range(4):
        s += _DM2007_B[i] * lam2 / (lam2 - _DM2007_C[i])
    return math.sqrt(s)


# --------------------------------------------------------------------------------------------
# Array loops used by the NumPy API (parallel over elements)
# --------------------------------------------------------------------------------------------
@njit(**JIT_PARALLEL)
def film_setup_array(wavelength, cos0, n0, n1, n2):
    """:func:`film_setup_nb` over 1-D arrays of equal length; returns (N, 14) complex."""
    n = wavelength.shape[0]
    out = np.empty((n, N_FILM_COEFFICIENTS), dtype=np.complex128)
    for i in prange(n):
        c = film_setup_nb(wavelength[i], cos0[i], n0[i], n1[i], n2[i])
        for j in range(N_FILM_COEFFICIENTS):
            out[i, j] = c[j]
    return out


_BLOCK = 512


@njit(**JIT)
def _lossless_row(c, d, pol, want_r, want_t, out_r, out_t):
    """Branch-free loop over thicknesses *d* (1-D) for one lossless row *c* of coefficients.

    Same formula as :func:`film_evaluate_nb` (:func:`_real_rt`), with the coefficients hoisted
    into scalars and :func:`sin2_cos2_nb` in place of libm, so that LLVM vectorizes it.  Only for
    rows with q1 > 0 and every phase below :data:`BETA_POLY_MAX`.
    """
    kq = c[0].real
    iq2 = c[1].real * c[1].real
    as_, bs, cs, ds, ts = c[3].real, c[4].real, c[5].real, c[6].real, c[7].real
    ap, bp, cp, dp, tp = c[8].real, c[9].real, c[10].real, c[11].real, c[12].real
    n = d.shape[0]
    if want_r and want_t:
        for j in range(n):
            sn2, cs2 = sin2_cos2_nb(kq * d[j])
            r, t = _real_rt(cs2, sn2 * iq2, as_, bs, cs, ds, ts, ap, bp, cp, dp, tp, pol)
            out_r[j] = r
            out_t[j] = t
    elif want_r:
        for j in range(n):
            sn2, cs2 = sin2_cos2_nb(kq * d[j])
            out_r[j] = _real_rt(cs2, sn2 * iq2, as_, bs, cs, ds, ts, ap, bp, cp, dp, tp, pol)[0]
    else:
        for j in range(n):
            sn2, cs2 = sin2_cos2_nb(kq * d[j])
            out_t[j] = _real_rt(cs2, sn2 * iq2, as_, bs, cs, ds, ts, ap, bp, cp, dp, tp, pol)[1]


@njit(**JIT_PARALLEL)
def film_evaluate_grid(coef, d, pol, want_r, want_t, out_r, out_t):
    """Evaluate the film for every (outer i, inner j): coefficients ``coef[i]``, thickness
    ``d[i, j]`` (or ``d[0, j]`` when *d* has one row).  Work is split in blocks of the inner
    axis so both cores stay busy whatever the shape.  Lossless rows whose phases stay below
    :data:`BETA_POLY_MAX` take the vectorized :func:`_lossless_row`; every other row goes
    through :func:`film_evaluate_nb` element by element.
    """
    n_outer = coef.shape[0]
    n_inner = d.shape[1]
    shared_d = d.shape[0] == 1
    n_blocks = (n_inner + _BLOCK - 1) // _BLOCK
    d_max = np.empty(d.shape[0])
    for i in range(d.shape[0]):
        d_max[i] = np.max(d[i]) if n_inner else 0.0
    for b in prange(n_outer * n_blocks):
        i = b // n_blocks
        j0 = (b - i * n_blocks) * _BLOCK
        j1 = min(j0 + _BLOCK, n_inner)
        row = coef[i]
        di = 0 if shared_d else i
        fast = (row[FILM_PATH].real == PATH_REAL and row[FILM_Q1_TERM].real > 0.0
                and row[FILM_KQ].real * d_max[di] <= BETA_POLY_MAX)
        if fast:
            _lossless_row(row, d[di, j0:j1], pol, want_r, want_t,
                          out_r[i, j0:j1] if want_r else out_r[0, 0:0],
                          out_t[i, j0:j1] if want_t else out_t[0, 0:0])
        else:
            for j in range(j0, j1):
                r, t = film_evaluate_nb(row, d[di, j], pol)
                if want_r:
                    out_r[i, j] = r
                if want_t:
                    out_t[i, j] = t


@njit(**JIT_PARALLEL)
def two_beam_array(wavelength, thickness, cos0, n0, n1, pol):
    """:func:`two_beam_r_nb` over 1-D arrays of equal length."""
    out = np.empty(wavelength.shape[0])
    for i in prange(wavelength.shape[0]):
        out[i] = two_beam_r_nb(wavelength[i], thickness[i], cos0[i], n0[i], n1[i], pol)
    return out


@njit(**JIT_PARALLEL)
def fresnel_array(n1, n2, cos1):
    """:func:`fresnel_interface_nb` over 1-D arrays; returns (4, N) complex and (4, N) float."""
    n = n1.shape[0]
    amp = np.empty((4, n), dtype=np.complex128)
    power = np.empty((4, n))
    for i in prange(n):
        rs, rp, ts, tp, Rs, Rp, Ts, Tp = fresnel_interface_nb(n1[i], n2[i], cos1[i])
        amp[0, i] = rs
        amp[1, i] = rp
        amp[2, i] = ts
        amp[3, i] = tp
        power[0, i] = Rs
        power[1, i] = Rp
        power[2, i] = Ts
        power[3, i] = Tp
    return amp, power


@njit(**JIT_PARALLEL)
def multilayer_array(wavelength, n_layers, d_layers, cos0, n0, n_inside, pol):
    """:func:`multilayer_rt_nb` over rows: *n_layers*, *d_layers* are (N, L); returns R, T (N,)."""
    n = wavelength.shape[0]
    out_r = np.empty(n)
    out_t = np.empty(n)
    for i in prange(n):
        r, t = multilayer_rt_nb(wavelength[i], n_layers[i], d_layers[i], cos0[i], n0[i], n_inside[i], pol)
        out_r[i] = r
        out_t[i] = t
    return out_r, out_t


@njit(**JIT_PARALLEL)
def water_index_array(wavelength):
    """:func:`water_index_daimon2007_nb` over a 1-D array."""
    out = np.empty(wavelength.shape[0])
    for i in prange(wavelength.shape[0]):
        out[i] = water_index_daimon2007_nb(wavelength[i])
    return out


# --------------------------------------------------------------------------------------------
# The sRGB transfer functions (IEC 61966-2-1:1999)
# --------------------------------------------------------------------------------------------
# Written here (rather than calling colour-science's cctf_encoding / cctf_decoding) so that
# saving a render needs neither colour-science's import (seconds) nor NumPy's elementwise
# temporaries (several passes over the image): the array kernels are one parallel pass.  They
# follow colour-science's eotf_inverse_sRGB and eotf_sRGB operation for operation with the C
# library's pow; NumPy's vectorised power, which colour-science calls, can differ from it by an
# ulp (tests/bubbleoptics/test_colorimetry.py: to the bit against the formula, 1e-15 against colour-science).
SRGB_LINEAR_BELOW = 0.0031308  # linear-light value where the curve turns from linear to power
SRGB_ENCODED_BELOW = SRGB_LINEAR_BELOW * 12.92  # the same point encoded (0.040449936)


@njit(**JIT)
def srgb_encode_nb(x):
    """Linear light *x* to display sRGB: 12.92 x (x <= 0.0031308), else 1.055 x^(1/2.4) - 0.055."""
    if x <= SRGB_LINEAR_BELOW:
        return x * 12.92
    return 1.055 * x ** (1 / 2.4) - 0.055


@njit(**JIT)
def srgb_decode_nb(v):
    """Display sRGB *v* to linear light: v / 12.92 (v <= 0.0031308 * 12.92), else ((v + 0.055)/1.055)^2.4."""
    if v <= SRGB_ENCODED_BELOW:
        return v / 12.92
    return ((v + 0.055) / 1.055) ** 2.4


@njit(**JIT_PARALLEL)
def srgb_encode_array(x, out):
    """:func:`srgb_encode_nb` over 1-D arrays (NaN stays NaN)."""
    for i in prange(x.shape[0]):
        out[i] = srgb_encode_nb(x[i]) if x[i] == x[i] else x[i]


@njit(**JIT_PARALLEL)
def srgb_encode_quantized_array(x, levels, out):
    """Linear light *x* (1-D) to integer sRGB codes 0..*levels* in *out* (an unsigned integer
    array): NaN as 0, clipped to [0, 1], :func:`srgb_encode_nb`, times *levels*, rounded half to
    even (as ``np.round``) -- what an 8-bit (255) or 16-bit (65535) image file stores."""
    for i in prange(x.shape[0]):
        v = x[i]
        if not v > 0.0:  # also NaN
            v = 0.0
        elif v > 1.0:
            v = 1.0
        out[i] = np.rint(srgb_encode_nb(v) * levels)


@njit(**JIT)
def srgb_decode_array(v, out):
    """:func:`srgb_decode_nb` over 1-D arrays (NaN stays NaN).  Serial: it decodes a scene's
    colours and, once per render, an environment image; a parallel build cost every first render
    about 0.2 s of compiling for those few values (docs/performance.md)."""
    for i in range(v.shape[0]):
        out[i] = srgb_decode_nb(v[i]) if v[i] == v[i] else v[i]


# --------------------------------------------------------------------------------------------
# Band-limited (band-averaged) film reflectance
# --------------------------------------------------------------------------------------------
# A colour computed from a few spectral samples aliases once the fringes get finer than the
# sampling.  These kernels average the film over a wavelength band instead, in closed form.
#
# Phase across a band.  Band [lambda_a, lambda_b] (lambda_a < lambda_b), phase rates
# kq = 2 pi q1 / lambda at its edges (kq_a > kq_b), u in [-1, 1] the normalised wavenumber
# (u = +1 at lambda_a).  The phase beta = d kq is taken linear in u,
#     beta(u) = beta_m + h u,   beta_m = d (kq_a + kq_b)/2,   h = d (kq_a - kq_b)/2,
# exact without dispersion (beta = 2 pi d q1 nu, nu = 1/lambda); for water at 20 um the
# curvature of n(nu) nu moves the phase by at most 0.04 rad inside a 26 nm band (16 bands over
# 360-780 nm) and 0.4 rad inside a 105 nm band (4 bands), at 0-60 deg.  The Fresnel-type
# coefficients (entries 1 and 3-13 of film_setup_nb, everything but the phase) are taken at the
# band centre (exact without dispersion).
#
# Lossless film, one polarization (module docstring, real form; sigma = sin(beta)/q1):
#     T(beta) = t / (C cos^2 beta + D' sin^2 beta),  C = c^2,  D' = D^2/q1^2,  t = 4 eta0 eta2,
# i.e. c[5], c[6] c[1]^2, c[7] for s and c[10], c[11] c[1]^2, c[12] for p; R = 1 - T.
#
# (1) Closed form of the average.  theta'(beta), the angle of the vector (cos beta, s sin beta)
#     with s = sqrt(D'/C), has d theta'/d beta = s/(cos^2 + s^2 sin^2) = sqrt(C D')/den, so
#     int T d beta = t theta' / sqrt(C D').  theta' gains exactly pi per period of beta and,
#     over a piece delta in [0, pi), gains an angle in [0, pi), which atan2 of the cross and
#     dot products of the two vectors returns on the right branch.  With 2h = m pi + delta:
#         Delta theta' = m pi + atan2(sqrt(CD') sin delta,
#                                     C cos b1 cos(b1 + delta) + D' sin b1 sin(b1 + delta)),
#         <T> = t Delta theta' / (2 h sqrt(C D')),    <R> = 1 - <T>,
#     b1 = d kq_b the phase at the long-wavelength edge; the second argument is evaluated as
#     ((C + D') cos delta + (C - D') cos(2 b1 + delta))/2, so a band costs four libm calls
#     and one atan2 per polarization.  No unwrapping of tan, no cancellation as 2h -> 0
#     (sin delta and atan2 keep their relative accuracy).  Uniform in phase is uniform in
#     wavenumber, not in wavelength (weight 1/nu^2): for water over 0-20 um the two band means
#     differ by up to 1.3e-3 in R with 16 bands, 4.5e-3 with 4 (the moments below give the
#     exact wavelength weight).
# (2) Fourier series (Poisson kernel, Gradshteyn & Ryzhik 1.447.3): with
#     rho = (s - 1)/(s + 1) = (sqrt D' - sqrt C)/(sqrt D' + sqrt C), |rho| < 1,
#         T(beta) = T_inc [1 + 2 sum_{n>=1} rho^n cos(2 n beta)],   T_inc = t / sqrt(C D'),
#     T_inc being the phase average, the incoherent transmittance (for a free-standing film
#     rho = R01, the single-surface reflectance, and T_inc = T01^2/(1 - R01^2)).
# (3) Legendre moments <P_j T> = (1/2) int_{-1}^{1} P_j(u) T(beta_m + h u) du.  By
#     (1/2) int P_j(u) e^{i z u} du = i^j j_j(z) (DLMF 10.54.2; j_j spherical Bessel),
#         <P_j T> = 2 T_inc sum_{n>=1} rho^n Re(i^j e^{2 i n beta_m}) j_j(2 n h),   j >= 1,
#     and <P_j R> = -<P_j T> (j >= 1).  <P_0 T> = <T> from (1), exact for any rho.
#     Any weight polynomial in u of degree <= L integrates against the film exactly with
#     moments j <= L: that is how a band's CMF (colour) or its uniform-in-wavelength weight
#     (band average) enter (see bubbleoptics.bandlimited).  The series stops before term n
#     once 2 T_inc |rho|^n/(1 - |rho|) (a bound on all the terms left, |j_l| <= 1) is below
#     the caller's tolerance, after at most _SERIES_MAX terms.  For tol = 1e-15 and water:
#     9 terms at normal incidence (rho = 0.02), 16 at 60 deg (rho_s = 0.12), 87 at 85 deg.
#
# Not covered by the closed forms: absorbing films, an evanescent film (q1 imaginary) and
# q1 -> 0.  There the moments fall back to Gauss-Legendre quadrature of the exact Airy sum
# (film_evaluate_nb) over the band with the caller's nodes (none: the band-centre point value);
# quadrature aliases like point sampling once the fringes are finer than its nodes, but an
# absorbing thick film has lost its fringes anyway.  Total reflection (flag 2): R = 1.

_SERIES_MAX = 100000
_RESYNC = 32
#: Highest Legendre order accepted by :func:`film_band_moments_nb` (its Bessel recurrences are
#: checked up to here in the tests).
BAND_ORDER_MAX = 16


@njit(**JIT)
def _sph_bessel_cs(z, sz, cz, order, out):
    """Spherical Bessel functions j_0(z) .. j_order(z) into out[0 .. order], z >= 0.

    z < 1: power series j_l(z) = z^l/(2l+1)!! sum_k (-z²/2)^k / (k! prod_{m=1}^k (2l+2m+1))
    (DLMF 10.53.1), 5 terms below z = 0.1, 9 up to 1 (next term < 3e-18 relative).  1 <= z <= order: Miller's
    backward recurrence j_{l-1} = (2l+1)/z j_l - j_{l+1} from l = order + 20 + 2z (where
    j_l(z) is below 1e-25 of j_order(z) for every z <= order <= 16), normalised by
    sum (2l+1) j_l² = 1 (DLMF 10.60.11) with the sign of the larger of j_0, j_1.
    z > order: forward recurrence from j_0 = sin z/z, j_1 = sin z/z² - cos z/z, stable for
    l < z (DLMF 10.51.1; Abramowitz & Stegun 10.1.19).  *sz*, *cz* are sin z and cos z
    (the caller often has them from a recurrence).
    """
    if z < 1.0:
        x = -0.5 * z * z
        n_series = 5 if z < 0.1 else 9  # first omitted term < 3e-18 relative
        lead = 1.0  # z^l / (2l+1)!!
        for ell in range(order + 1):
            term = 1.0
            s = 1.0
            for k in range(1, n_series + 1):
                term *= x / (k * (2.0 * ell + 2.0 * k + 1.0))
                s += term
            out[ell] = lead * s
            lead *= z / (2.0 * ell + 3.0)
        return
    iz = 1.0 / z
    j0 = sz * iz
    j1 = (j0 - cz) * iz
    if z > order:
        out[0] = j0
        if order >= 1:
            out[1] = j1
        for ell in range(1, order):
            out[ell + 1] = (2.0 * ell + 1.0) * iz * out[ell] - out[ell - 1]
        return
    top = order + 20 + int(2.0 * z)
    f_up = 0.0
    f = 1e-150
    norm = (2.0 * top + 1.0) * f * f
    for ell in range(top, 0, -1):
        f_down = (2.0 * ell + 1.0) / z * f - f_up
        f_up = f
        f = f_down
        if ell - 1 <= order:
            out[ell - 1] = f
        norm += (2.0 * ell - 1.0) * f * f
        if norm > 1e200:  # rescale (not reached for 1 <= z <= order <= 16; kept for safety)
            sc = 1e-200
            f *= sc
            f_up *= sc
            norm *= sc * sc
            for m in range(ell - 1, order + 1):
                out[m] *= sc
    scale = 1.0 / math.sqrt(norm)
    if abs(j0) >= abs(j1):
        if (out[0] < 0.0) != (j0 < 0.0):
            scale = -scale
    elif (out[1] < 0.0) != (j1 < 0.0):
        scale = -scale
    for ell in range(order + 1):
        out[ell] *= scale


@njit(**JIT)
def _sph_bessel(z, order, out):
    """Spherical Bessel functions j_0(z) .. j_order(z) into out[0 .. order] (:func:`_sph_bessel_cs`)."""
    _sph_bessel_cs(z, math.sin(z), math.cos(z), order, out)


@njit(**JIT)
def _band_trig(beta1, two_h):
    """Trigonometry of a band, shared by both polarizations and by the series.

    With 2h = m pi + delta (0 <= delta < pi), b2 = b1 + delta and sigma = b1 + b2, returns
    (m pi, sign, sin delta, cos delta, sin sigma, cos sigma), sign = (-1)^m.  Then
    cos b1 cos b2 = (cos delta + cos sigma)/2, sin b1 sin b2 = (cos delta - cos sigma)/2,
    e^{2 i beta_m} = sign e^{i sigma} and e^{2 i h} = sign e^{i delta}: four libm calls per band.
    """
    m = math.floor(two_h / math.pi)
    delta = two_h - m * math.pi
    sigma = 2.0 * beta1 + delta
    sign = 1.0 - 2.0 * (m - 2.0 * math.floor(0.5 * m))
    return m * math.pi, sign, math.sin(delta), math.cos(delta), math.sin(sigma), math.cos(sigma)


@njit(**JIT)
def _band_inverse_average(C, Dp, two_h, m_pi, s_delta, c_delta, c_sigma):
    """(1/2h) ∫ dβ/(C cos²β + D' sin²β) over [β1, β1 + 2h], 2h > 0: closed form (1) above.

    The atan2's second argument C cos b1 cos b2 + D' sin b1 sin b2 is written
    ((C + D') cos delta + (C - D') cos sigma)/2; the trigonometry comes from :func:`_band_trig`.
    """
    sq = math.sqrt(C * Dp)
    ang = math.atan2(sq * s_delta, 0.5 * ((C + Dp) * c_delta + (C - Dp) * c_sigma))
    if ang < -0.5 * math.pi:  # delta rounded to just above pi: the increment is ~pi, not ~-pi
        ang += 2.0 * math.pi
    return (m_pi + ang) / (two_h * sq)


@njit(**JIT)
def _band_phase(kq_a, kq_b, d):
    """(beta_1, 2h, sign): start phase, sweep and orientation of the band (see above)."""
    ba = kq_a * d
    bb = kq_b * d
    if ba >= bb:
        return bb, ba - bb, 1.0
    return ba, bb - ba, -1.0


@njit(**JIT)
def film_band_average_nb(c, kq_a, kq_b, d, pol):
    """(R̄, T̄): the film averaged uniformly in phase over one wavelength band, closed form.

    .. math::

        \\bar T = \\frac{t\\,\\Delta\\theta'}{2h\\sqrt{CD'}},\\quad
        \\Delta\\theta' = m\\pi + \\operatorname{atan2}\\!\\big(\\sqrt{CD'}\\sin\\delta,\\;
        C\\cos\\beta_1\\cos(\\beta_1+\\delta) + D'\\sin\\beta_1\\sin(\\beta_1+\\delta)\\big),
        \\quad \\bar R = 1 - \\bar T,

    the exact mean of the lossless :math:`T(\\beta) = t/(C\\cos^2\\beta + D'\\sin^2\\beta)`
    over :math:`\\beta \\in [\\beta_1, \\beta_1 + 2h]`, :math:`2h = m\\pi + \\delta`,
    :math:`0 \\le \\delta < \\pi` (derivation in the comment block above this section; the
    antiderivative :math:`\\arctan(\\sqrt{D'/C}\\tan\\beta)/\\sqrt{CD'}` of Gradshteyn & Ryzhik
    2.562.1, with its branches resolved by atan2).  Per polarization; unpolarized is the mean.

    Parameters
    ----------
    c : the :func:`film_setup_nb` tuple (or array row) at the band centre.
    kq_a, kq_b : float, phase rates :math:`2\\pi q_1/\\lambda` (1/nm) at the band's short and
        long edges: ``film_setup_nb(lambda_edge, ...)[0].real``.
    d : float, film thickness in nm.  *pol* : 0 (s), 1 (p), 2 (unpolarized).

    The fringes are averaged in phase, i.e. uniformly in wavenumber across the band (uniform
    in wavelength to within the band's relative width; :func:`film_band_moments_nb` gives the
    exact uniform-in-wavelength weight).  A band of zero width (kq_a == kq_b) or d = 0 gives
    the point value.  Films outside the closed form (absorbing, evanescent, q1 -> 0) return the
    band-centre point value :func:`film_evaluate_nb`; use :func:`film_band_moments_nb` with
    quadrature nodes for those.  Cheap (one atan2 per polarization): meant for the tracer.

    >>> from bubbleoptics.kernels import film_band_average_nb, film_evaluate_nb, film_setup_nb
    >>> c = film_setup_nb(549.5, 1.0, 1.0, 1.33 + 0j, 1.0 + 0j)   # band 540-559 nm, normal incidence
    >>> kq_a = film_setup_nb(540.0, 1.0, 1.0, 1.33 + 0j, 1.0 + 0j)[0].real
    >>> kq_b = film_setup_nb(559.0, 1.0, 1.0, 1.33 + 0j, 1.0 + 0j)[0].real
    >>> R, T = film_band_average_nb(c, kq_a, kq_b, 20000.0, 2)     # 20 um: 2.4 fringes in the band
    >>> round(R, 4), round(film_evaluate_nb(c, 20000.0, 2)[0], 4)  # band mean; the centre's value
    (0.0412, 0.0245)
    """
    flag = c[FILM_PATH].real
    if flag == PATH_TOTAL_REFLECTION:
        return 1.0, 0.0
    inv_q1 = c[1].real
    if flag != PATH_REAL or not inv_q1 > 0.0:
        return film_evaluate_nb(c, d, pol)
    beta1, two_h, _ = _band_phase(kq_a, kq_b, d)
    if not two_h > 0.0:
        beta = beta1
        sb = math.sin(beta)
        cb = math.cos(beta)
        return _real_rt_c(c, cb * cb, sb * sb * inv_q1 * inv_q1, pol)
    iq2 = inv_q1 * inv_q1
    m_pi, _, s_delta, c_delta, _, c_sigma = _band_trig(beta1, two_h)
    T = 0.0
    if pol != POL_P:
        T += c[7].real * _band_inverse_average(c[5].real, c[6].real * iq2, two_h, m_pi, s_delta, c_delta, c_sigma)
    if pol != POL_S:
        T += c[12].real * _band_inverse_average(c[10].real, c[11].real * iq2, two_h, m_pi, s_delta, c_delta, c_sigma)
    if pol == POL_UNPOLARIZED:
        T *= 0.5
    T = min(T, 1.0)  # rounding only: T-bar <= 1 exactly, so R-bar >= 0
    return 1.0 - T, T


# --------------------------------------------------------------------------------------------
# The free-standing lossless film (a soap bubble in air): the Airy sum's symmetric case
# --------------------------------------------------------------------------------------------
# With the same lossless medium on both sides (eta_2 = eta_0) and a lossless film with q1
# real (n1 > n0 always qualifies), the real form of the module docstring loses its first
# terms (eta_0 - eta_2 = 0) and, with sigma = sin(beta)/eta_1 and
# (eta_0^2 + eta_1^2)^2 = (eta_0^2 - eta_1^2)^2 + 4 eta_0^2 eta_1^2, becomes Airy's formula
# with the coefficient of finesse F (Born & Wolf, Principles of Optics, 7th ed., §7.6.1,
# eqs. (17)-(19); Macleod, Thin-Film Optical Filters, 4th ed., §2.2):
#     R = F sin^2 beta / (1 + F sin^2 beta),   T = 1 / (1 + F sin^2 beta),
#     F = (eta_0^2 - eta_1^2)^2 / (4 eta_0^2 eta_1^2).
# The difference comes from q1^2 - q0^2 = n1^2 - n0^2 exactly, so no digit is lost:
#     s:  F_s = (n1^2 - n0^2)^2 / (4 q0^2 q1^2),
#     p:  F_p = F_s g^2,   g = (q0^2 (n1^2 + n0^2) - n0^4) / (n0^2 n1^2)
# (g = 0 at Brewster's angle, tan theta_0 = n1/n0).  Three numbers per (lambda, theta)
# instead of film_setup_nb's fourteen, and per thickness one sin^2 and two divisions: what the
# tracer evaluates at every bubble hit.  For the band average, T(beta) = 1/(cos^2 + (1 + F)
# sin^2) is the closed form (1) of the band section with C = 1, D' = 1 + F, t = 1.


@njit(**JIT_INLINE)
def _free_film_coefficients(wavelength, cos0, n0, n1):
    """(kq, F_s, F_p, applies) of :func:`free_film_setup_nb`, branch-free (vectorizes in a loop)."""
    c0 = max(cos0, COS_MIN)
    q0 = n0 * c0
    dn2 = (n1 - n0) * (n1 + n0)  # n1^2 - n0^2 = q1^2 - q0^2
    q1sq = dn2 + q0 * q0
    applies = q1sq > 0.0
    q1sq_ok = q1sq if applies else 1.0
    Fs = dn2 * dn2 / (4.0 * q0 * q0 * q1sq_ok)
    n0sq = n0 * n0
    n1sq = n1 * n1
    g = (q0 * q0 * (n1sq + n0sq) - n0sq * n0sq) / (n0sq * n1sq)
    kq = _TWO_PI / wavelength * math.sqrt(q1sq_ok)
    return (kq if applies else -1.0), (Fs if applies else 0.0), (Fs * g * g if applies else 0.0), applies


@njit(**JIT)
def free_film_setup_nb(wavelength, cos0, n0, n1):
    """Set-up of a free-standing lossless film: ``(kq, F_s, F_p)``, or ``(-1, 0, 0)``.

    Parameters: *wavelength* λ (nm), *cos0* = cos θ0 of incidence, *n0* the real index on
    both sides, *n1* the film's real index.  ``kq`` = 2π q1/λ (1/nm), the phase rate
    (β = kq d); F_s, F_p the coefficients of finesse (section comment above).  kq = -1 when
    the case does not apply (q1² <= 0: the film is at or beyond its critical angle, possible
    only for n1 < n0); use :func:`film_setup_nb` then.

    >>> from bubbleoptics.kernels import free_film_setup_nb, free_film_evaluate_nb, film_rt_nb
    >>> c = free_film_setup_nb(550.0, 0.8, 1.0, 1.33)
    >>> R, T = free_film_evaluate_nb(c, 300.0, 2)
    >>> R0, T0 = film_rt_nb(550.0, 300.0, 0.8, 1.0, 1.33 + 0j, 1.0 + 0j, 2)
    >>> abs(R - R0) < 1e-15, abs(T - T0) < 1e-15
    (True, True)
    """
    kq, Fs, Fp, _ = _free_film_coefficients(wavelength, cos0, n0, n1)
    return kq, Fs, Fp


@njit(**JIT_INLINE)
def _free_film_from_sin2(Fs, Fp, sn2, pol):
    """(R, T) of the free-standing film from its coefficients of finesse and sin²β."""
    R = 0.0
    T = 0.0
    if pol != POL_P:
        x = Fs * sn2
        inv = 1.0 / (1.0 + x)
        R += x * inv
        T += inv
    if pol != POL_S:
        x = Fp * sn2
        inv = 1.0 / (1.0 + x)
        R += x * inv
        T += inv
    if pol == POL_UNPOLARIZED:
        R *= 0.5
        T *= 0.5
    return R, T


@njit(**JIT)
def free_film_evaluate_nb(c, d, pol):
    """(R, T) of the free-standing lossless film of thickness *d* nm, *c* from
    :func:`free_film_setup_nb` (which must apply: kq >= 0); *pol* 0 (s), 1 (p), 2 (unpolarized).
    Equal to :func:`film_evaluate_nb` of :func:`film_setup_nb` with ``n2 = n0`` to rounding."""
    beta = c[0] * d
    if beta <= BETA_POLY_MAX:
        sn2, _ = sin2_cos2_nb(beta)
    else:
        sb = math.sin(beta)
        sn2 = sb * sb
    return _free_film_from_sin2(c[1], c[2], sn2, pol)


@njit(**JIT)
def free_film_setup_bands_nb(wavelength, n1, cos0, n0, kq, Fs, Fp):
    """:func:`free_film_setup_nb` for every band at once: *wavelength* and *n1* (C,) in, *kq*,
    *Fs*, *Fp* (C,) out; returns False if the closed form does not apply to some band.  A
    branch-free loop, which LLVM vectorizes (the tracer calls it at every new angle)."""
    misses = 0
    for c in range(kq.shape[0]):
        k, fs, fp, applies = _free_film_coefficients(wavelength[c], cos0, n0, n1[c])
        kq[c] = k
        Fs[c] = fs
        Fp[c] = fp
        misses += 0 if applies else 1
    return misses == 0


@njit(**JIT_FMA)
def free_film_evaluate_bands_nb(kq, Fs, Fp, d, pol, R, T):
    """:func:`free_film_evaluate_nb` for every band at once (coefficients from
    :func:`free_film_setup_bands_nb`), into *R*, *T* (C,).  Vectorizes when every phase is within
    :data:`BETA_POLY_MAX` (films thinner than about 8 cm), else falls back band by band.
    Compiled with fused multiply-add (:data:`bubbleoptics.jit.JIT_FMA`): the tracer calls it at
    every film hit."""
    n = kq.shape[0]
    kq_max = 0.0
    for c in range(n):
        kq_max = max(kq_max, kq[c])
    if kq_max * d <= BETA_POLY_MAX:
        for c in range(n):
            sn2, _ = sin2_cos2_nb(kq[c] * d)
            r, t = _free_film_from_sin2(Fs[c], Fp[c], sn2, pol)
            R[c] = r
            T[c] = t
    else:
        for c in range(n):
            r, t = free_film_evaluate_nb((kq[c], Fs[c], Fp[c]), d, pol)
            R[c] = r
            T[c] = t


@njit(**JIT)
def free_film_band_average_nb(c, kq_a, kq_b, d, pol):
    """(R̄, T̄) of the free-standing lossless film averaged uniformly in phase over a band:
    :func:`film_band_average_nb` for this case (closed form (1) with C = 1, D' = 1 + F, t = 1).
    *c* from :func:`free_film_setup_nb` at the band centre, *kq_a*, *kq_b* its phase rate at the
    band's short and long edges."""
    beta1, two_h, _ = _band_phase(kq_a, kq_b, d)
    if not two_h > 0.0:
        return free_film_evaluate_nb((kq_b, c[1], c[2]), d, pol)
    m_pi, _, s_delta, c_delta, _, c_sigma = _band_trig(beta1, two_h)
    T = 0.0
    if pol != POL_P:
        T += _band_inverse_average(1.0, 1.0 + c[1], two_h, m_pi, s_delta, c_delta, c_sigma)
    if pol != POL_S:
        T += _band_inverse_average(1.0, 1.0 + c[2], two_h, m_pi, s_delta, c_delta, c_sigma)
    if pol == POL_UNPOLARIZED:
        T *= 0.5
    T = min(T, 1.0)  # rounding only: T-bar <= 1 exactly, so R-bar >= 0
    return 1.0 - T, T


@njit(**JIT)
def film_band_moments_nb(c, kq_a, kq_b, d, pol, order, tol, quad_x, quad_w, out_r, out_t):
    """Legendre moments :math:`\\langle P_j R\\rangle, \\langle P_j T\\rangle`, j = 0..order, of the film over a band.

    :math:`\\langle P_j f\\rangle = \\tfrac12\\int_{-1}^{1} P_j(u) f(\\beta_m + h u)\\,du`, u the
    normalised wavenumber across the band (+1 at the short edge).  A weight
    :math:`w(u) = \\sum_j w_j P_j(u)` of degree <= *order* integrates exactly:
    :math:`\\tfrac12\\int w f\\,du = \\sum_j w_j \\langle P_j f\\rangle`.

    Lossless films: :math:`\\langle P_0 T\\rangle` from the closed form of
    :func:`film_band_average_nb`, and for j >= 1

    .. math::  \\langle P_j T\\rangle = 2T_{\\rm inc}\\sum_{n\\ge1}\\rho^n
               \\operatorname{Re}\\!\\big(i^j e^{2in\\beta_m}\\big)\\,j_j(2nh),\\qquad
               \\langle P_j R\\rangle = \\delta_{j0} - \\langle P_j T\\rangle,

    (Poisson-kernel Fourier series of the Airy function, Gradshteyn & Ryzhik 1.447.3, and
    the Legendre transform of a plane wave, DLMF 10.54.2; derivation above this section),
    summed until the omitted terms are below *tol*.  Other films (absorbing, evanescent or
    q1 -> 0): Gauss-Legendre quadrature of :func:`film_evaluate_nb` at the nodes *quad_x*,
    weights *quad_w* (on [-1, 1]; empty arrays: the band-centre point value), the phase
    moved across the band by scaling the thickness, the coefficients kept at the centre.

    Parameters: *c*, *kq_a*, *kq_b*, *d*, *pol* as :func:`film_band_average_nb`; *order*
    0..:data:`BAND_ORDER_MAX`; *tol*, the absolute error allowed in each moment j >= 1 (the
    series' remainder bound; 0 sums until the terms underflow); *out_r*, *out_t* float arrays
    of length >= order + 1, filled.

    >>> import numpy as np
    >>> from bubbleoptics.kernels import film_band_moments_nb, film_setup_nb
    >>> c = film_setup_nb(549.5, 1.0, 1.0, 1.33 + 0j, 1.0 + 0j)
    >>> kq_a, kq_b = (film_setup_nb(x, 1.0, 1.0, 1.33 + 0j, 1.0 + 0j)[0].real for x in (540.0, 559.0))
    >>> mr, mt, none = np.empty(3), np.empty(3), np.empty(0)
    >>> film_band_moments_nb(c, kq_a, kq_b, 300.0, 2, 2, 1e-15, none, none, mr, mt)
    >>> [round(float(v), 6) for v in mr]  # <R>, <P_1 R>, <P_2 R>: R rises towards the blue edge
    [0.075405, 0.000549, -5.7e-05]
    """
    for j in range(order + 1):
        out_r[j] = 0.0
        out_t[j] = 0.0
    flag = c[FILM_PATH].real
    if flag == PATH_TOTAL_REFLECTION:
        out_r[0] = 1.0
        return
    inv_q1 = c[1].real
    if flag != PATH_REAL or not inv_q1 > 0.0:
        kq0 = c[0].real
        nq = quad_x.shape[0]
        if nq == 0 or not kq0 > 0.0:
            r, t = film_evaluate_nb(c, d, pol)
            out_r[0] = r
            out_t[0] = t
            return
        kq_m = 0.5 * (kq_a + kq_b)
        kq_h = 0.5 * (kq_a - kq_b)
        for g in range(nq):
            u = quad_x[g]
            r, t = film_evaluate_nb(c, d * (kq_m + kq_h * u) / kq0, pol)
            wr = 0.5 * quad_w[g] * r
            wt = 0.5 * quad_w[g] * t
            p_prev = 1.0
            p = u
            out_r[0] += wr
            out_t[0] += wt
            for j in range(1, order + 1):
                out_r[j] += wr * p
                out_t[j] += wt * p
                p, p_prev = ((2.0 * j + 1.0) * u * p - j * p_prev) / (j + 1.0), p
        return
    beta1, two_h, orient = _band_phase(kq_a, kq_b, d)
    if not two_h > 0.0:
        sb = math.sin(beta1)
        cb = math.cos(beta1)
        r, t = _real_rt_c(c, cb * cb, sb * sb * inv_q1 * inv_q1, pol)
        out_r[0] = r
        out_t[0] = t
        return
    h = 0.5 * two_h
    beta_m = beta1 + h
    m_pi, sign, s_delta, c_delta, s_sigma, c_sigma = _band_trig(beta1, two_h)
    half = 0.5 if pol == POL_UNPOLARIZED else 1.0
    iq2 = inv_q1 * inv_q1
    cs_ = c[5].real
    ds_ = c[6].real * iq2
    cp_ = c[10].real
    dp_ = c[11].real * iq2
    if pol != POL_P:
        out_t[0] += half * c[7].real * _band_inverse_average(cs_, ds_, two_h, m_pi, s_delta, c_delta, c_sigma)
    if pol != POL_S:
        out_t[0] += half * c[12].real * _band_inverse_average(cp_, dp_, two_h, m_pi, s_delta, c_delta, c_sigma)
    out_t[0] = min(out_t[0], 1.0)  # rounding only, as in film_band_average_nb
    out_r[0] = 1.0 - out_t[0]
    if order == 0:
        return
    # per polarization: incoherent transmittance T_inc and Poisson ratio rho
    t_inc_s = 0.0
    rho_s = 0.0
    t_inc_p = 0.0
    rho_p = 0.0
    if pol != POL_P:
        sc = math.sqrt(cs_)
        sd = math.sqrt(ds_)
        t_inc_s = half * c[7].real / (sc * sd)
        rho_s = (sd - sc) / (sd + sc)
    if pol != POL_S:
        sc = math.sqrt(cp_)
        sd = math.sqrt(dp_)
        t_inc_p = half * c[12].real / (sc * sd)
        rho_p = (sd - sc) / (sd + sc)
    a = max(abs(rho_s), abs(rho_p))
    t_inc = t_inc_s + t_inc_p
    # terms n, n+1, ... add up to at most 2 T_inc a^n / (1 - a): stop once that is below tol
    lim = tol * (1.0 - a) / (2.0 * t_inc) if t_inc > 0.0 else 2.0
    # e^{2 i n beta_m} and e^{2 i n h} by rotation, recomputed from libm every _RESYNC terms
    # (rounding then grows by at most _RESYNC ulps); out_r[0..order] holds j_l(2 n h) meanwhile.
    r0 = out_r[0]
    c1 = sign * c_sigma
    s1 = sign * s_sigma
    cz1 = sign * c_delta
    sz1 = sign * s_delta
    cp = 1.0
    sp = 0.0
    cz = 1.0
    sz = 0.0
    pow_s = 1.0
    pow_p = 1.0
    pow_a = 1.0
    for n in range(1, _SERIES_MAX + 1):
        pow_a *= a
        if pow_a < lim:
            break
        pow_s *= rho_s
        pow_p *= rho_p
        amp = 2.0 * (t_inc_s * pow_s + t_inc_p * pow_p)
        if amp == 0.0:
            break
        if n % _RESYNC == 0:
            cp = math.cos(2.0 * n * beta_m)
            sp = math.sin(2.0 * n * beta_m)
            cz = math.cos(n * two_h)
            sz = math.sin(n * two_h)
        else:
            cp, sp = cp * c1 - sp * s1, sp * c1 + cp * s1
            cz, sz = cz * cz1 - sz * sz1, sz * cz1 + cz * sz1
        _sph_bessel_cs(n * two_h, sz, cz, order, out_r)
        for j in range(1, order + 1):
            k = j % 4
            if k == 0:
                re = cp
            elif k == 1:
                re = -sp
            elif k == 2:
                re = -cp
            else:
                re = sp
            out_t[j] += amp * re * out_r[j]
    out_r[0] = r0
    sgn = 1.0
    for j in range(1, order + 1):
        sgn *= orient  # P_j(-u) = (-1)^j P_j(u) when the phase falls across the band
        out_t[j] *= sgn
        out_r[j] = -out_t[j]


@njit(**JIT_PARALLEL)
def film_band_rt_grid(coef, kq_a, kq_b, d, pol, weights, tol, quad_x, quad_w, want_r, want_t, out_r, out_t):
    """Band averages with a polynomial weight per band, for every (setting i, band k, thickness j).

    ``out[i, k, j] = sum_l weights[k, l] <P_l f>`` (f = R into *out_r*, T into *out_t*; clipped
    to [0, 1] against rounding: with weights[k, 0] = 1 it is a mean of values in [0, 1]), the
    moments from :func:`film_band_moments_nb` with ``coef[i, k]`` (film_setup_nb at the band centre,
    shape (M, N, 14)), ``kq_a[i, k]``, ``kq_b[i, k]`` and thickness ``d[i, j]`` (or ``d[0, j]``
    when *d* has one row).  ``weights[k, 0] = 1`` and the rest 0 is the phase-uniform average.
    """
    n_set = coef.shape[0]
    n_band = coef.shape[1]
    n_d = d.shape[1]
    order = weights.shape[1] - 1
    shared_d = d.shape[0] == 1
    n_blocks = (n_d + _BLOCK - 1) // _BLOCK
    for b in prange(n_set * n_band * n_blocks):
        ik = b // n_blocks
        i = ik // n_band
        k = ik - i * n_band
        j0 = (b - ik * n_blocks) * _BLOCK
        j1 = min(j0 + _BLOCK, n_d)
        mr = np.empty(order + 1)
        mt = np.empty(order + 1)
        di = 0 if shared_d else i
        row = coef[i, k]
        for j in range(j0, j1):
            film_band_moments_nb(row, kq_a[i, k], kq_b[i, k], d[di, j], pol, order, tol, quad_x, quad_w, mr, mt)
            sr = 0.0
            st = 0.0
            for m in range(order + 1):
                sr += weights[k, m] * mr[m]
                st += weights[k, m] * mt[m]
            # a mean of values in [0, 1]: clip the rounding of the weighted sum
            if want_r:
                out_r[i, k, j] = min(max(sr, 0.0), 1.0)
            if want_t:
                out_t[i, k, j] = min(max(st, 0.0), 1.0)


@njit(**JIT_PARALLEL)
def film_band_weighted_sum(coef, kq_a, kq_b, d, pol, weights, tol, quad_x, quad_w, transmit, out):
    """Spectral integrals from band moments: ``out[i, j, c] = sum_k sum_l weights[c, k, l] <P_l f>_k``.

    With *weights* the band-wise Legendre coefficients of colour matching functions (times an
    illuminant), this is a film's CIE XYZ (:func:`bubbleoptics.bandlimited.film_color_bandlimited`).
    Shapes: *coef* (M, N, 14), *kq_a*, *kq_b* (M, N), *d* (M or 1, J), *weights* (C, N, L+1),
    *out* (M, J, C); f = T if *transmit* else R.
    """
    n_set = coef.shape[0]
    n_band = coef.shape[1]
    n_d = d.shape[1]
    n_c = weights.shape[0]
    order = weights.shape[2] - 1
    shared_d = d.shape[0] == 1
    n_blocks = (n_d + _BLOCK - 1) // _BLOCK
    for b in prange(n_set * n_blocks):
        i = b // n_blocks
        j0 = (b - i * n_blocks) * _BLOCK
        j1 = min(j0 + _BLOCK, n_d)
        mr = np.empty(order + 1)
        mt = np.empty(order + 1)
        di = 0 if shared_d else i
        for j in range(j0, j1):
            for c in range(n_c):
                out[i, j, c] = 0.0
            for k in range(n_band):
                film_band_moments_nb(coef[i, k], kq_a[i, k], kq_b[i, k], d[di, j], pol, order, tol, quad_x, quad_w,
                                  mr, mt)
                for c in range(n_c):
                    s = 0.0
                    for m in range(order + 1):
                        s += weights[c, k, m] * (mt[m] if transmit else mr[m])
                    out[i, j, c] += s


__all__ += ["BAND_ORDER_MAX", "film_band_average_nb", "film_band_moments_nb"]
