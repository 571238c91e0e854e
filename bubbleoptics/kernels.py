"""Numba scalar kernels: the one copy of every optical formula in the project.

The NumPy API (:mod:`bubbleoptics.film`, :mod:`bubbleoptics.fresnel`, ...) broadcasts over
these kernels, and the ray tracer (:mod:`tracer`) calls the very same functions per ray and
wavelength sample.  Nothing here allocates, so they are cheap to call from inside other
``@njit`` code.

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

__all__ = [
    "COS_MIN",
    "POL_S",
    "POL_P",
    "POL_UNPOLARIZED",
    "N_FILM_COEFFICIENTS",
    "normal_wavevector",
    "fresnel_interface",
    "film_setup",
    "sin2_cos2",
    "BETA_POLY_MAX",
    "film_evaluate",
    "film_rt",
    "two_beam_r",
    "multilayer_rt",
    "water_index_daimon2007",
]

POL_S = 0
POL_P = 1
POL_UNPOLARIZED = 2

#: Smallest cos(theta_0) used: exactly grazing rays (cos = 0, e.g. tangent rays in the tracer)
#: are treated as cos = 1e-150, where R = 1 - O(1e-150); this keeps every formula finite.
COS_MIN = 1e-150

#: Length of the coefficient tuple returned by :func:`film_setup`.
N_FILM_COEFFICIENTS = 14

# error_model="numpy": a float division never raises (our denominators are positive by
# construction, and the property tests check no NaN appears); without it numba guards every
# division with a branch, which stops LLVM from vectorizing the thickness loop (8x slower).
_JIT = dict(cache=True, error_model="numpy")
_JIT_PARALLEL = dict(cache=True, error_model="numpy", parallel=True)

_TWO_PI = 2.0 * math.pi
_Q_SMALL = 1e-60  # below this, sin(beta)/q1 is evaluated as a sinc (q1 -> 0 at the critical angle)


# --------------------------------------------------------------------------------------------
# Building blocks
# --------------------------------------------------------------------------------------------
@njit(**_JIT)
def _q_squared(n, n0, q0):
    """:math:`q^2 = (n-n_0)(n+n_0) + q_0^2`; real for real *n*, complex for complex *n*."""
    return (n - n0) * (n + n0) + q0 * q0


@njit(**_JIT)
def normal_wavevector(n, n0, q0):
    """Normal wavevector component :math:`q = n\\cos\\theta` in a medium of index *n*.

    :math:`q^2 = (n-n_0)(n+n_0) + q_0^2` (Snell's law, no cancellation near grazing);
    the branch has :math:`\\operatorname{Im} q \\ge 0`, :math:`\\operatorname{Re} q \\ge 0`.

    Parameters: *n* complex index of the medium, *n0* real index of the incidence medium,
    *q0* = :math:`n_0\\cos\\theta_0` (real, >= 0).  Returns complex *q*.
    """
    z = _q_squared(n + 0j, n0, q0)
    # Im(n^2) = 2 n k >= 0; clamp rounding (and -0.0) so the principal root is the decaying one.
    return cmath.sqrt(complex(z.real, max(z.imag, 0.0)))


@njit(**_JIT)
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


@njit(**_JIT)
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


@njit(**_JIT)
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
#: Largest phase for :func:`sin2_cos2` (k < 2**20 quadrants); larger phases use libm.
BETA_POLY_MAX = 2.0**20 * 1.5707963267948966
# Taylor coefficients (-1)^n/(2n+1)! and (-1)^n/(2n)!; on |r| <= pi/4 the first omitted terms
# are below 1e-19 (sin) and 3e-18 (cos) relative, i.e. well under half an ulp.
_S3, _S5, _S7, _S9 = -1 / 6, 1 / 120, -1 / 5040, 1 / 362880
_S11, _S13, _S15, _S17 = -1 / 39916800, 1 / 6227020800, -1 / 1307674368000, 1 / 355687428096000
_C2, _C4, _C6, _C8 = -1 / 2, 1 / 24, -1 / 720, 1 / 40320
_C10, _C12, _C14, _C16 = -1 / 3628800, 1 / 479001600, -1 / 87178291200, 1 / 20922789888000


@njit(**_JIT)
def sin2_cos2(beta):
    """(sin²β, cos²β) for 0 <= β <= :data:`BETA_POLY_MAX`, without branches.

    Why by hand: numba calls libm's scalar sin and cos (about 20 ns each here) and, since it
    dropped SVML, cannot vectorize them; this straight-line version lets LLVM vectorize the
    thickness loop.  Reduction β = kπ/2 + r with the three-part π/2 above (error in r below
    1 ulp of r plus 1e-27), Taylor polynomials on |r| <= π/4, and the quadrant applied as an
    exact 0/1 blend (only squares are needed, so signs drop out).  Checked against libm and
    mpmath in ``tests/test_kernels.py``.
    """
    k = math.floor(beta * _TWO_OVER_PI + 0.5)
    r = ((beta - k * _PIO2_1) - k * _PIO2_2) - k * _PIO2_3
    r2 = r * r
    sr = r + r * r2 * (_S3 + r2 * (_S5 + r2 * (_S7 + r2 * (_S9 + r2 * (_S11 + r2 * (_S13 + r2 * (_S15 + r2 * _S17)))))))
    cr = 1.0 + r2 * (_C2 + r2 * (_C4 + r2 * (_C6 + r2 * (_C8 + r2 * (_C10 + r2 * (_C12 + r2 * (_C14 + r2 * _C16)))))))
    s2 = sr * sr
    c2 = cr * cr
    odd = k - 2.0 * math.floor(0.5 * k)  # 0.0 or 1.0
    even = 1.0 - odd
    return odd * c2 + even * s2, odd * s2 + even * c2


@njit(**_JIT)
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
@njit(**_JIT)
def fresnel_interface(n1, n2, cos1):
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
    q2 = normal_wavevector(n2, n1, q1)
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


# --------------------------------------------------------------------------------------------
# Single film (the Airy sum), in two stages: setup per (lambda, theta, media), evaluate per d
# --------------------------------------------------------------------------------------------
@njit(**_JIT)
def film_setup(wavelength, cos0, n0, n1, n2):
    """Stage 1 of the exact single-film Airy sum: everything that does not depend on *d*.

    Parameters
    ----------
    wavelength : float, vacuum wavelength :math:`\\lambda` in nm (> 0).
    cos0 : float, :math:`\\cos\\theta_0` of the angle of incidence in the outside medium.
    n0 : float, real index of the outside medium.
    n1, n2 : complex, indices :math:`n+ik` of the film and of the inside medium.

    Returns a tuple of :data:`N_FILM_COEFFICIENTS` complex numbers for :func:`film_evaluate`.
    Entry 13 is 0 for the real-arithmetic path (lossless media, every wave propagating), 1 for
    the complex path, 2 for total reflection (lossless media, evanescent inside medium).  See the module docstring for the formulas.
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
            return (0j, 0j, complex(g, 0.0), 0j, 0j, 0j, 0j, 0j, 0j, 0j, 0j, 0j, 0j, 2.0 + 0j)
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
                0j,
            )
    q1 = normal_wavevector(n1, n0, q0)
    q2 = normal_wavevector(n2, n0, q0)
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
        1.0 + 0j,
    )


@njit(**_JIT)
def _real_rt(cos2, sig2, as_, bs, cs, ds, ts, ap, bp, cp, dp, tp, pol):
    """Lossless-path (R, T) from cos²β and σ² = sin²β/q1² (module docstring, real form).

    as_, bs, cs, ds, ts (s) and ap, bp, cp, dp, tp (p) are entries 3-12 of :func:`film_setup`.
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


@njit(**_JIT)
def _real_rt_c(c, cos2, sig2, pol):
    return _real_rt(cos2, sig2, c[3].real, c[4].real, c[5].real, c[6].real, c[7].real,
                    c[8].real, c[9].real, c[10].real, c[11].real, c[12].real, pol)


@njit(**_JIT)
def film_evaluate(c, d, pol):
    """Stage 2 of the Airy sum: (R, T) of the film of thickness *d* nm for polarization *pol*.

    *c* is the tuple (or a row of an array) from :func:`film_setup`; *pol* is 0 (s), 1 (p) or
    2 (unpolarized: the mean of s and p).  Returns (R, T), both in [0, 1].
    """
    flag = c[13].real
    if flag == 2.0:
        return 1.0, 0.0
    if flag == 0.0:
        beta = c[0].real * d
        if beta <= BETA_POLY_MAX:
            sn2, cs2 = sin2_cos2(beta)
        else:
            sb = math.sin(beta)
            cb = math.cos(beta)
            sn2 = sb * sb
            cs2 = cb * cb
        inv_q1 = c[1].real
        if inv_q1 > 0.0:
            sig2 = sn2 * (inv_q1 * inv_q1)
        else:
            # q1 -> 0 (film at its critical angle): sigma = d (2 pi/lambda) sinc(beta)
            sinc2 = sn2 / (beta * beta) if beta > 1e-4 else _sinc(beta) ** 2
            sig2 = (d * c[2].real) ** 2 * sinc2
        return _real_rt_c(c, cs2, sig2, pol)
    R = 0.0
    T = 0.0
    one_p_e, u, ex = _phase_terms(c[0], c[2].real, d)
    if pol != POL_P:
        num = c[3] * one_p_e + c[4] * u
        den = c[5] * one_p_e + c[6] * u
        dd = den.real * den.real + den.imag * den.imag
        R += (num.real * num.real + num.imag * num.imag) / dd
        T += c[7].real * ex / dd
    if pol != POL_S:
        up = u * c[1]
        num = c[8] * one_p_e + c[9] * up
        den = c[10] * one_p_e + c[11] * up
        dd = den.real * den.real + den.imag * den.imag
        R += (num.real * num.real + num.imag * num.imag) / dd
        T += c[12].real * ex / dd
    if pol == POL_UNPOLARIZED:
        R *= 0.5
        T *= 0.5
    return R, T


@njit(**_JIT)
def film_rt(wavelength, thickness, cos0, n0, n1, n2, pol):
    """Exact (R, T) of one film: :func:`film_evaluate` of :func:`film_setup`.

    Units: nm, cosine of the angle of incidence, real *n0*, complex *n1*, *n2*; *pol* 0/1/2.
    """
    return film_evaluate(film_setup(wavelength, cos0, n0, n1, n2), thickness, pol)


# --------------------------------------------------------------------------------------------
# The seed's two-beam model (coursework eqs. 1.1-1.3)
# --------------------------------------------------------------------------------------------
@njit(**_JIT)
def two_beam_r(wavelength, thickness, cos0, n0, n1, pol):
    """The seed's two-beam reflectance, normalised by the first interface's reflectance.

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
    q1 = normal_wavevector(n1r, n0, q0)
    _, _, _, _, Rs, Rp, _, _ = fresnel_interface(n0, n1r, c0)
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
@njit(**_JIT)
def multilayer_rt(wavelength, n_layers, d_layers, cos0, n0, n_inside, pol):
    """(R, T) of a stack of films by characteristic (transfer) matrices.

    Each layer's matrix :math:`M_j = [[\\cos\\beta_j, -i\\sin\\beta_j/\\eta_j],
    [-i\\eta_j\\sin\\beta_j, \\cos\\beta_j]]` (Macleod §2.2; Born & Wolf §1.6.2) is used scaled by
    :math:`e^{i\\beta_j}`, i.e. :math:`\\tfrac12[[1+e_j, (1-e_j)/\\eta_j], [\\eta_j(1-e_j), 1+e_j]]`,
    which stays bounded for thick absorbing layers; :math:`[B, C]^T = \\prod M_j [1, \\eta_m]^T`,
    :math:`r = (\\eta_0B - C)/(\\eta_0B + C)`,
    :math:`T = 4\\eta_0\\operatorname{Re}\\eta_m\\prod_j|e_j| / |\\eta_0B + C|^2`.

    *n_layers*, *d_layers*: 1-D arrays (complex, float nm), outermost layer first.
    For one layer this equals :func:`film_rt` to rounding (tested); the single-film kernel is
    preferred there because it also removes the cancellation in the numerator.
    """
    c0 = max(cos0, COS_MIN)
    q0 = n0 * c0
    g = _TWO_PI / wavelength
    qm = normal_wavevector(n_inside, n0, q0)
    if n_inside.imag == 0.0 and qm.imag > 0.0:
        lossless = True
        for j in range(n_layers.shape[0]):
            if n_layers[j].imag != 0.0:
                lossless = False
        if lossless:
            return 1.0, 0.0  # total reflection, as in film_setup
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
            qj = normal_wavevector(nj, n0, q0)
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


@njit(**_JIT)
def water_index_daimon2007(wavelength):
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
@njit(**_JIT_PARALLEL)
def film_setup_array(wavelength, cos0, n0, n1, n2):
    """:func:`film_setup` over 1-D arrays of equal length; returns (N, 14) complex."""
    n = wavelength.shape[0]
    out = np.empty((n, N_FILM_COEFFICIENTS), dtype=np.complex128)
    for i in prange(n):
        c = film_setup(wavelength[i], cos0[i], n0[i], n1[i], n2[i])
        for j in range(N_FILM_COEFFICIENTS):
            out[i, j] = c[j]
    return out


_BLOCK = 512


@njit(**_JIT)
def _lossless_row(c, d, pol, want_r, want_t, out_r, out_t):
    """Branch-free loop over thicknesses *d* (1-D) for one lossless row *c* of coefficients.

    Same formula as :func:`film_evaluate` (:func:`_real_rt`), with the coefficients hoisted
    into scalars and :func:`sin2_cos2` in place of libm, so that LLVM vectorizes it.  Only for
    rows with q1 > 0 and every phase below :data:`BETA_POLY_MAX`.
    """
    kq = c[0].real
    iq2 = c[1].real * c[1].real
    as_, bs, cs, ds, ts = c[3].real, c[4].real, c[5].real, c[6].real, c[7].real
    ap, bp, cp, dp, tp = c[8].real, c[9].real, c[10].real, c[11].real, c[12].real
    n = d.shape[0]
    if want_r and want_t:
        for j in range(n):
            sn2, cs2 = sin2_cos2(kq * d[j])
            r, t = _real_rt(cs2, sn2 * iq2, as_, bs, cs, ds, ts, ap, bp, cp, dp, tp, pol)
            out_r[j] = r
            out_t[j] = t
    elif want_r:
        for j in range(n):
            sn2, cs2 = sin2_cos2(kq * d[j])
            out_r[j] = _real_rt(cs2, sn2 * iq2, as_, bs, cs, ds, ts, ap, bp, cp, dp, tp, pol)[0]
    else:
        for j in range(n):
            sn2, cs2 = sin2_cos2(kq * d[j])
            out_t[j] = _real_rt(cs2, sn2 * iq2, as_, bs, cs, ds, ts, ap, bp, cp, dp, tp, pol)[1]


@njit(**_JIT_PARALLEL)
def film_evaluate_grid(coef, d, pol, want_r, want_t, out_r, out_t):
    """Evaluate the film for every (outer i, inner j): coefficients ``coef[i]``, thickness
    ``d[i, j]`` (or ``d[0, j]`` when *d* has one row).  Work is split in blocks of the inner
    axis so both cores stay busy whatever the shape.  Lossless rows whose phases stay below
    :data:`BETA_POLY_MAX` take the vectorized :func:`_lossless_row`; every other row goes
    through :func:`film_evaluate` element by element.
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
        fast = row[13].real == 0.0 and row[1].real > 0.0 and row[0].real * d_max[di] <= BETA_POLY_MAX
        if fast:
            _lossless_row(row, d[di, j0:j1], pol, want_r, want_t,
                          out_r[i, j0:j1] if want_r else out_r[0, 0:0],
                          out_t[i, j0:j1] if want_t else out_t[0, 0:0])
        else:
            for j in range(j0, j1):
                r, t = film_evaluate(row, d[di, j], pol)
                if want_r:
                    out_r[i, j] = r
                if want_t:
                    out_t[i, j] = t


@njit(**_JIT_PARALLEL)
def two_beam_array(wavelength, thickness, cos0, n0, n1, pol):
    """:func:`two_beam_r` over 1-D arrays of equal length."""
    out = np.empty(wavelength.shape[0])
    for i in prange(wavelength.shape[0]):
        out[i] = two_beam_r(wavelength[i], thickness[i], cos0[i], n0[i], n1[i], pol)
    return out


@njit(**_JIT_PARALLEL)
def fresnel_array(n1, n2, cos1):
    """:func:`fresnel_interface` over 1-D arrays; returns (4, N) complex and (4, N) float."""
    n = n1.shape[0]
    amp = np.empty((4, n), dtype=np.complex128)
    power = np.empty((4, n))
    for i in prange(n):
        rs, rp, ts, tp, Rs, Rp, Ts, Tp = fresnel_interface(n1[i], n2[i], cos1[i])
        amp[0, i] = rs
        amp[1, i] = rp
        amp[2, i] = ts
        amp[3, i] = tp
        power[0, i] = Rs
        power[1, i] = Rp
        power[2, i] = Ts
        power[3, i] = Tp
    return amp, power


@njit(**_JIT_PARALLEL)
def multilayer_array(wavelength, n_layers, d_layers, cos0, n0, n_inside, pol):
    """:func:`multilayer_rt` over rows: *n_layers*, *d_layers* are (N, L); returns R, T (N,)."""
    n = wavelength.shape[0]
    out_r = np.empty(n)
    out_t = np.empty(n)
    for i in prange(n):
        r, t = multilayer_rt(wavelength[i], n_layers[i], d_layers[i], cos0[i], n0[i], n_inside[i], pol)
        out_r[i] = r
        out_t[i] = t
    return out_r, out_t


@njit(**_JIT_PARALLEL)
def water_index_array(wavelength):
    """:func:`water_index_daimon2007` over a 1-D array."""
    out = np.empty(wavelength.shape[0])
    for i in prange(wavelength.shape[0]):
        out[i] = water_index_daimon2007(wavelength[i])
    return out
