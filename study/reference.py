"""Slow, literal, independent references for the thin-film optics of ``bubbleoptics``.

What this module is
-------------------
Two kinds of reference, against which the tests (``tests/bubbleoptics/test_reference_*.py``) and the
stress benchmark (``benchmarks/stability.py``, notebook 05) check the package's fast kernels.
It needs the ``test`` extra (``pip install 'bubbleoptics[test]'``: ``mpmath``, ``tmm``); nothing
imports it unless asked (``from study import reference``).

1. ``*_mp`` functions: the textbook formulas evaluated in arbitrary precision with
   ``mpmath`` (default 40 significant digits).  Every float64 input is first converted
   *exactly* to an mpmath number (``mpf(float)`` / ``mpc(complex)`` are exact: a binary64
   value has 53 bits, the working precision has ~136), so the result is the true optical
   response of the very float64 inputs the package receives, correct to far more digits
   than a float64 can hold.  The formulas are written out literally:

   * Fresnel amplitude coefficients of a plane interface (Born & Wolf, *Principles of
     Optics*, 7th ed., §1.5.2, eqs. (20)-(21)), in the sign convention of Byrnes,
     "Multilayer optical calculations", arXiv:1603.02720, §3 (the convention of the
     ``tmm`` package and of ``bubbleoptics``)::

         r_s = (n_i cos_i - n_j cos_j) / (n_i cos_i + n_j cos_j),   t_s = 2 n_i cos_i / (same)
         r_p = (n_j cos_i - n_i cos_j) / (n_j cos_i + n_i cos_j),   t_p = 2 n_i cos_i / (same)

   * the Airy summation of the multiple reflections inside one film (Born & Wolf §7.6.1,
     eqs. (57)-(58); Byrnes §4)::

         r = (r01 + r12 e) / (1 + r01 r12 e),   t = t01 t12 e^{i beta} / (1 + r01 r12 e),
         e = exp(2 i beta),  beta = 2 pi d n1 cos1 / lambda

   * the 2x2 characteristic/transfer-matrix product for a stack of layers (Born & Wolf
     §1.6; in the form of Byrnes §4, eqs. (13)-(16))::

         M~ = (1/t01) [[1, r01], [r01, 1]]  prod_j  (1/t_{j,j+1}) [[e^{-i d_j}, 0], [0, e^{i d_j}]] [[1, r_{j,j+1}], [r_{j,j+1}, 1]]
         r = M~_10 / M~_00,   t = 1 / M~_00,   d_j = 2 pi d_j n_j cos_j / lambda

   * power coefficients (Byrnes §3, eqs. (21)-(22); Born & Wolf §1.5.3)::

         R = |r|^2,  T_s = Re(n_N cos_N) / Re(n_0 cos_0) |t|^2,
                     T_p = Re(n_N conj(cos_N)) / Re(n_0 conj(cos_0)) |t|^2

   Complex angles: for a (possibly absorbing) medium j we never form an angle; we form
   the normal component ``kz_j = n_j cos_j = sqrt(n_j^2 - n0^2 sin^2 theta)`` directly, written
   as ``(n_j - n0)(n_j + n0) + n0^2 cos^2 theta`` so that nothing cancels catastrophically
   near grazing incidence (``cos theta`` itself comes from ``mpmath.cos`` of the exact float
   ``theta``).  The branch is the forward/decaying one (Byrnes, Appendix D): Im(kz) >= 0,
   and Re(kz) >= 0 when Im(kz) == 0.  ``cos_j = kz_j / n_j``.

2. ``tmm_*`` functions: thin wrappers around ``tmm.coh_tmm`` (S. J. Byrnes' ``tmm``
   package, a separately written float64 transfer-matrix code).  Useful on ordinary inputs
   (away from grazing incidence, where ``tmm``'s ``cos(arcsin(.))`` loses accuracy, and for
   single-pass absorption ``Im(delta) <= 35``, above which ``tmm`` deliberately clamps).

Why it is independent
---------------------
Nothing here imports or calls the rest of ``bubbleoptics`` (``tests/study/test_study_package.py``
checks the imports); the mpmath code shares no code and no numerical strategy with the
package's float64/numba kernels (no float64 arithmetic at all after
the exact input conversion), and ``tmm`` is a third-party implementation.  The single-film
Airy formula and the multilayer matrix product are two different formulations and are
cross-checked against each other and against ``tmm`` in ``tests/bubbleoptics/test_reference_tmm.py``.

Conventions are those of the package: wavelengths and thicknesses in nm, angles in
radians, ``n + ik`` with ``k >= 0`` absorbing (phase factor ``exp(+i 2 pi n d cos / lambda)``),
outside (incidence) medium real ``n0 > 0``; ``n_inside=None`` means "same as outside";
polarization ``"s"``, ``"p"`` or ``"unpolarized"`` (mean of s and p for both R and T).
"""

from __future__ import annotations

import math

try:
    import mpmath
except ImportError as exc:  # the test extra is not installed
    raise ImportError("study.reference needs mpmath (and tmm for the tmm_* functions): "
                      "pip install 'bubbleoptics[test]'") from exc

__all__ = [
    "POLARIZATIONS",
    "kz_mp",
    "fresnel_mp",
    "film_rt_mp",
    "film_amplitudes_mp",
    "multilayer_rt_mp",
    "tmm_rt",
    "tmm_multilayer_rt",
]

POLARIZATIONS = ("s", "p", "unpolarized")


# ----------------------------------------------------------------------------- helpers
def _mpf(x):
    """Exact conversion of a real float64 (or Python int) to mpf."""
    return mpmath.mpf(float(x))


def _mpc(z):
    """Exact conversion of a complex (or real) float64 to mpc."""
    z = complex(z)
    return mpmath.mpc(mpmath.mpf(z.real), mpmath.mpf(z.imag))


def _check_pol(polarization):
    if polarization not in POLARIZATIONS:
        raise ValueError(f"polarization must be one of {POLARIZATIONS}, got {polarization!r}")


def kz_mp(n_j, n0, cos0sq):
    """Normal component ``n_j cos_j = sqrt(n_j^2 - n0^2 sin^2 theta0)`` (mpc), forward branch.

    ``n0`` is the (real) incidence-medium index, ``cos0sq = cos^2 theta0``.  The radicand is
    formed as ``(n_j - n0)(n_j + n0) + n0^2 cos^2 theta0`` (Snell's law n0 sin0 = n_j sin_j,
    Born & Wolf §1.5.1), avoiding ``1 - sin^2``.  Branch (Byrnes, arXiv:1603.02720, App. D):
    the transmitted wave must decay (Im > 0) or, if it neither grows nor decays, carry power
    forward (Re >= 0).
    """
    n_j = mpmath.mpc(n_j)
    rad = (n_j - n0) * (n_j + n0) + n0 * n0 * cos0sq
    kz = mpmath.sqrt(rad)
    if kz.imag < 0 or (kz.imag == 0 and kz.real < 0):
        kz = -kz
    return kz


def _interface(n_i, kz_i, n_j, kz_j):
    """Fresnel amplitudes (rs, ts, rp, tp) from medium i into medium j (Byrnes §3, eqs. 5-8).

    Written with cos_i = kz_i / n_i exactly as in the brief's convention:
    r_s = (n_i cos_i - n_j cos_j)/(n_i cos_i + n_j cos_j), t_s = 2 n_i cos_i/(...),
    r_p = (n_j cos_i - n_i cos_j)/(n_j cos_i + n_i cos_j), t_p = 2 n_i cos_i/(...).
    """
    cos_i = kz_i / n_i
    cos_j = kz_j / n_j
    ds = n_i * cos_i + n_j * cos_j
    rs = (n_i * cos_i - n_j * cos_j) / ds
    ts = 2 * n_i * cos_i / ds
    dp = n_j * cos_i + n_i * cos_j
    rp = (n_j * cos_i - n_i * cos_j) / dp
    tp = 2 * n_i * cos_i / dp
    return rs, ts, rp, tp


def _power(r, t, n_first, kz_first, n_last, kz_last, pol):
    """R = |r|^2 and T per Byrnes eqs. (21)-(22) for polarization 's' or 'p'."""
    R = abs(r) ** 2
    if pol == "s":
        T = (kz_last.real / kz_first.real) * abs(t) ** 2
    else:
        cos_first = kz_first / n_first
        cos_last = kz_last / n_last
        T = ((n_last * mpmath.conj(cos_last)).real / (n_first * mpmath.conj(cos_first)).real) * abs(t) ** 2
    return R, T


def _mean_or_one(values_s, values_p, polarization):
    if polarization == "s":
        return values_s
    if polarization == "p":
        return values_p
    return tuple((a + b) / 2 for a, b in zip(values_s, values_p))


# ----------------------------------------------------------------------------- mpmath references
def fresnel_mp(n1, n2, theta1, dps=40):
    """Fresnel coefficients of one plane interface, medium ``n1`` -> medium ``n2``, at ``dps`` digits.

    ``n1`` is the incidence medium (real, or complex with the convention that ``n1 sin theta1``
    fixes the tangential wave vector), ``n2`` may be complex (k >= 0), ``theta1`` is the real
    angle of incidence in medium 1.  Born & Wolf §1.5.2-1.5.3; sign convention of Byrnes
    arXiv:1603.02720 §3 (= tmm's).  Returns a dict with mpc ``rs, rp, ts, tp`` and mpf
    ``Rs, Rp, Ts, Tp``.
    """
    with mpmath.workdps(dps):
        n1m, n2m, th = _mpc(n1), _mpc(n2), _mpf(theta1)
        c = mpmath.cos(th)
        s = mpmath.sin(th)
        kz1 = n1m * c
        if n1m.imag == 0:
            kz2 = kz_mp(n2m, n1m.real, c * c)
        else:  # general complex incidence medium: literal Snell, forward branch
            kz2 = mpmath.sqrt(n2m * n2m - (n1m * s) ** 2)
            if kz2.imag < 0 or (kz2.imag == 0 and kz2.real < 0):
                kz2 = -kz2
        rs, ts, rp, tp = _interface(n1m, kz1, n2m, kz2)
        Rs, Ts = _power(rs, ts, n1m, kz1, n2m, kz2, "s")
        Rp, Tp = _power(rp, tp, n1m, kz1, n2m, kz2, "p")
        return {"rs": +rs, "rp": +rp, "ts": +ts, "tp": +tp, "Rs": +Rs, "Rp": +Rp, "Ts": +Ts, "Tp": +Tp}


def film_amplitudes_mp(wavelength_nm, thickness_nm, theta, n_film, n_outside=1.0, n_inside=None,
                       polarization="s", dps=40):
    """Complex (r, t) of a single film (Airy sum, Born & Wolf §7.6.1) for 's' or 'p'."""
    if polarization not in ("s", "p"):
        raise ValueError("amplitudes are defined for 's' or 'p' only")
    with mpmath.workdps(dps):
        r, t, *_ = _film_core(wavelength_nm, thickness_nm, theta, n_film, n_outside, n_inside)[polarization]
        return +r, +t


def _film_core(wavelength_nm, thickness_nm, theta, n_film, n_outside, n_inside):
    """Both polarizations of the Airy sum; must be called inside a workdps context."""
    lam = _mpf(wavelength_nm)
    d = _mpf(thickness_nm)
    th = _mpf(theta)
    n0 = _mpf(n_outside)
    n1 = _mpc(n_film)
    c0 = mpmath.cos(th)
    c0sq = c0 * c0
    kz0 = mpmath.mpc(n0 * c0)
    n0c = mpmath.mpc(n0)
    kz1 = kz_mp(n1, n0, c0sq)
    if n_inside is None:
        n2, kz2 = n0c, kz0
    else:
        n2 = _mpc(n_inside)
        kz2 = kz_mp(n2, n0, c0sq)
    beta = 2 * mpmath.pi * d * kz1 / lam
    e = mpmath.exp(2j * beta)
    out = {}
    rs01, ts01, rp01, tp01 = _interface(n0c, kz0, n1, kz1)
    rs12, ts12, rp12, tp12 = _interface(n1, kz1, n2, kz2)
    for pol, (r01, t01, r12, t12) in {"s": (rs01, ts01, rs12, ts12), "p": (rp01, tp01, rp12, tp12)}.items():
        den = 1 + r01 * r12 * e
        r = (r01 + r12 * e) / den
        t = t01 * t12 * mpmath.exp(1j * beta) / den
        R, T = _power(r, t, n0c, kz0, n2, kz2, pol)
        out[pol] = (r, t, R, T)
    return out


def film_rt_mp(wavelength_nm, thickness_nm, theta, n_film, n_outside=1.0, n_inside=None,
               polarization="unpolarized", dps=40):
    """(R, T) of one film between two half-spaces, as mpf, computed at ``dps`` digits.

    Scalars only.  Outside (incidence) medium ``n_outside`` real > 0; film ``n_film`` complex
    (k >= 0); ``n_inside`` complex or ``None`` (= outside).  ``theta`` is the angle of incidence
    in the outside medium.  Airy sum of Born & Wolf §7.6.1 with the Fresnel coefficients of
    §1.5 in tmm's (Byrnes, arXiv:1603.02720) sign convention; "unpolarized" is the mean of the
    s and p powers (Born & Wolf §10.8 -- incoherent superposition of two orthogonal
    polarizations).

    Example
    -------
    >>> R, T = film_rt_mp(550.0, 0.0, 0.0, 1.5, 1.0, 1.5)   # no film: the bare air | glass interface
    >>> float(R), float(T)
    (0.04, 0.96)
    """
    _check_pol(polarization)
    with mpmath.workdps(dps):
        core = _film_core(wavelength_nm, thickness_nm, theta, n_film, n_outside, n_inside)
        Rs, Ts = core["s"][2], core["s"][3]
        Rp, Tp = core["p"][2], core["p"][3]
        R, T = _mean_or_one((Rs, Ts), (Rp, Tp), polarization)
        return +R, +T


def multilayer_rt_mp(wavelength_nm, n_layers, thicknesses_nm, theta, n_outside=1.0, n_inside=None,
                     polarization="unpolarized", dps=40):
    """(R, T) of a stack of coherent layers by a literal 2x2 transfer-matrix product, mpf.

    ``n_layers`` and ``thicknesses_nm``: sequences of scalars, one per layer, listed from the
    outside (incidence side) inwards.  Byrnes, arXiv:1603.02720 §4, eqs. (13)-(16) (Born & Wolf
    §1.6 for the characteristic-matrix theory).  An empty stack gives the bare interface.
    mpmath's unbounded exponent range means thick absorbing layers need no clamping.
    """
    _check_pol(polarization)
    n_layers = list(n_layers)
    thicknesses_nm = list(thicknesses_nm)
    if len(n_layers) != len(thicknesses_nm):
        raise ValueError("n_layers and thicknesses_nm must have the same length")
    with mpmath.workdps(dps):
        lam = _mpf(wavelength_nm)
        th = _mpf(theta)
        n0 = _mpf(n_outside)
        c0 = mpmath.cos(th)
        c0sq = c0 * c0
        ns = [mpmath.mpc(n0)] + [_mpc(n) for n in n_layers]
        kzs = [mpmath.mpc(n0 * c0)] + [kz_mp(n, n0, c0sq) for n in ns[1:]]
        if n_inside is None:
            ns.append(ns[0])
            kzs.append(kzs[0])
        else:
            ns.append(_mpc(n_inside))
            kzs.append(kz_mp(ns[-1], n0, c0sq))
        ds = [_mpf(d) for d in thicknesses_nm]
        res = {}
        for pol in ("s", "p"):
            k = 0 if pol == "s" else 1  # index into (rs, ts, rp, tp): r at 2k, t at 2k+1
            coef = [_interface(ns[j], kzs[j], ns[j + 1], kzs[j + 1]) for j in range(len(ns) - 1)]
            r01, t01 = coef[0][2 * k], coef[0][2 * k + 1]
            M = mpmath.matrix([[1, r01], [r01, 1]]) / t01
            for j in range(1, len(ns) - 1):
                delta = 2 * mpmath.pi * ds[j - 1] * kzs[j] / lam
                rj, tj = coef[j][2 * k], coef[j][2 * k + 1]
                P = mpmath.matrix([[mpmath.exp(-1j * delta), 0], [0, mpmath.exp(1j * delta)]])
                L = mpmath.matrix([[1, rj], [rj, 1]])
                M = M * (P * L) / tj
            r = M[1, 0] / M[0, 0]
            t = 1 / M[0, 0]
            res[pol] = _power(r, t, ns[0], kzs[0], ns[-1], kzs[-1], pol)
        R, T = _mean_or_one(res["s"], res["p"], polarization)
        return +R, +T


# ----------------------------------------------------------------------------- tmm wrappers
def _tmm_pol(pol, n_list, d_list, theta, lam):
    try:
        import tmm  # third-party reference (S. J. Byrnes); imported lazily
    except ImportError as exc:
        raise ImportError("the tmm_* references need tmm: pip install 'bubbleoptics[test]'") from exc

    out = tmm.coh_tmm(pol, n_list, d_list, float(theta), float(lam))
    return float(out["R"]), float(out["T"])


def tmm_multilayer_rt(wavelength_nm, n_layers, thicknesses_nm, theta, n_outside=1.0, n_inside=None,
                      polarization="unpolarized"):
    """(R, T) floats of a layer stack from ``tmm.coh_tmm`` (Byrnes, arXiv:1603.02720).

    Scalars only.  Same argument conventions as :func:`multilayer_rt_mp`.
    """
    _check_pol(polarization)
    n_in = n_outside if n_inside is None else n_inside
    n_list = [complex(n_outside)] + [complex(n) for n in n_layers] + [complex(n_in)]
    d_list = [math.inf] + [float(d) for d in thicknesses_nm] + [math.inf]
    if polarization == "unpolarized":
        Rs, Ts = _tmm_pol("s", n_list, d_list, theta, wavelength_nm)
        Rp, Tp = _tmm_pol("p", n_list, d_list, theta, wavelength_nm)
        return (Rs + Rp) / 2, (Ts + Tp) / 2
    return _tmm_pol(polarization, n_list, d_list, theta, wavelength_nm)


def tmm_rt(wavelength_nm, thickness_nm, theta, n_film, n_outside=1.0, n_inside=None,
           polarization="unpolarized"):
    """(R, T) floats of one film from ``tmm.coh_tmm(pol, [n0, n1, n2], [inf, d, inf], theta, lam)``."""
    return tmm_multilayer_rt(wavelength_nm, [n_film], [thickness_nm], theta, n_outside, n_inside,
                             polarization)
