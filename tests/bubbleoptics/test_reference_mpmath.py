"""THE ACCURACY BAR: ``bubbleoptics`` thin-film optics against a 40-digit mpmath reference.

The reference (``study/reference.py``) evaluates the textbook formulas -- Fresnel
coefficients (Born & Wolf, *Principles of Optics*, §1.5), the Airy sum for one film
(Born & Wolf §7.6.1) and the 2x2 transfer-matrix product for a stack (Byrnes,
"Multilayer optical calculations", arXiv:1603.02720, §4) -- in 40-digit arithmetic on the
*exact* float64 inputs the package receives.  Its own error is ~1e-35, so every difference
seen here is the package's float64 error.

Bar for film R and T over the whole input domain (wavelength 300-1000 nm, thickness
0-10 µm including exactly 0, angle 0 .. pi/2 - 1e-6 with many points near grazing, film
n 1-2.5 with k 0 or up to 0.1, outside 1.0-1.5, inside 1.0-2.0 or "same as outside"):

    |ours - ref| <= 1e-12   AND   |ours - ref| <= 1e-9 |ref|

Where the reference is *exactly* zero (no interface at all: d = 0 with equal media gives
R = 0; an evanescent exit medium gives T = 0) a relative error is undefined, and we
require instead R <= 1e-30 and |T| <= 1e-15.  For the hand-picked resonance cases
(R ~ 0 by construction) the relative bar is applied only where the reference R > 1e-20,
because there R is a difference of O(1) quantities and no float64 code can resolve it
relatively.
"""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from study import reference as ref  # the slow, literal references (mpmath, tmm)



SEED = 20_240_611
ABS_TOL = 1e-12
REL_TOL = 1e-9
ZERO_R_TOL = 1e-30  # R where the reference is exactly 0 (no interface)
ZERO_T_TOL = 1e-15  # T where the reference is exactly 0 (evanescent exit)
GRAZING = math.pi / 2 - 1e-6
POLS = ("s", "p", "unpolarized")


@pytest.fixture(scope="module")
def bo():
    import bubbleoptics

    return bubbleoptics


# ----------------------------------------------------------------------------- comparison helper
def _fmt_inputs(inp):
    return ", ".join(f"{k}={v!r}" for k, v in inp.items())


def _compare(ours, refs, inputs, what, abs_tol=ABS_TOL, rel_tol=REL_TOL, zero_tol=None,
             rel_floor=0.0):
    """Check float64 ``ours`` against mpf ``refs`` point by point; fail with the worst case.

    ``rel_tol`` is applied where ``|ref| > rel_floor``; where ``ref == 0`` exactly and
    ``zero_tol`` is given, ``|ours| <= zero_tol`` is required instead.
    Returns (worst_abs, worst_rel) for information.
    """
    ours = np.asarray(ours, dtype=float).ravel()
    assert ours.size == len(refs) == len(inputs), (ours.shape, len(refs), len(inputs))
    failures = []
    worst_abs = (0.0, None)
    worst_rel = (0.0, None)
    for o, r, inp in zip(ours, refs, inputs):
        o = float(o)
        if not np.isfinite(o):
            failures.append((math.inf, f"non-finite value {o!r} at {_fmt_inputs(inp)}; ref={float(r)!r}"))
            continue
        err = float(abs(mpmath.mpf(float(o)) - r))
        rf = float(r)
        rel = err / abs(rf) if r != 0 else (math.inf if err > 0 else 0.0)
        line = (f"{what}: {_fmt_inputs(inp)}\n    ours={o!r} ref={mpmath.nstr(r, 20)} "
                f"abs_err={err:.3e} rel_err={rel:.3e}")
        if err > worst_abs[0]:
            worst_abs = (err, line)
        if r != 0 and abs(rf) > rel_floor and rel > worst_rel[0]:
            worst_rel = (rel, line)
        score = err / abs_tol
        if r == 0 and zero_tol is not None:
            score = max(score, abs(o) / zero_tol)
        elif abs(rf) > rel_floor and r != 0:
            score = max(score, rel / rel_tol)
        if score > 1:
            failures.append((score, line))
    if failures:
        failures.sort(key=lambda x: -x[0])
        msg = [f"{len(failures)} of {len(ours)} points violate abs<={abs_tol:g}, rel<={rel_tol:g}"
               + (f", |ours|<={zero_tol:g} where ref==0" if zero_tol is not None else "")
               + "; worst first:"]
        msg += [f[1] for f in failures[:5]]
        pytest.fail("\n".join(msg))
    return worst_abs, worst_rel


# ----------------------------------------------------------------------------- random domain sampling
def _sample(rng, n, inside_none):
    """Random points covering the whole domain of the accuracy bar (see module docstring)."""
    lam = rng.uniform(300.0, 1000.0, n)
    d = rng.uniform(0.0, 10_000.0, n)
    d[:10] = 0.0  # exactly zero thickness
    d[10:20] = 10.0 ** rng.uniform(-3, 1, 10)  # very thin films
    # half uniform, half near grazing: theta = pi/2 - 10**-u, u ~ U[0, 6]
    theta = rng.uniform(0.0, GRAZING, n)
    near = rng.random(n) < 0.5
    theta[near] = math.pi / 2 - 10.0 ** (-rng.uniform(0.0, 6.0, near.sum()))
    theta[rng.choice(n, 8, replace=False)] = GRAZING
    theta[rng.choice(n, 5, replace=False)] = 0.0
    n1 = rng.uniform(1.0, 2.5, n).astype(complex)
    absorbing = rng.random(n) < 0.5
    n1[absorbing] += 1j * rng.uniform(0.0, 0.1, absorbing.sum())
    n0 = rng.uniform(1.0, 1.5, n)
    n0[rng.random(n) < 0.2] = 1.0
    if inside_none:
        n2 = None
    else:
        n2 = rng.uniform(1.0, 2.0, n).astype(complex)
        lossy = rng.random(n) < 0.25
        n2[lossy] += 1j * rng.uniform(0.0, 0.1, lossy.sum())
    return dict(lam=lam, d=d, theta=theta, n1=n1, n0=n0, n2=n2)


def _film_mp_lists(s, pol):
    Rs, Ts, inputs = [], [], []
    for i in range(len(s["lam"])):
        n2 = None if s["n2"] is None else complex(s["n2"][i])
        args = (float(s["lam"][i]), float(s["d"][i]), float(s["theta"][i]), complex(s["n1"][i]),
                float(s["n0"][i]), n2)
        R, T = ref.film_rt_mp(*args, polarization=pol)
        Rs.append(R)
        Ts.append(T)
        inputs.append(dict(wavelength_nm=args[0], thickness_nm=args[1], theta=args[2], n_film=args[3],
                           n_outside=args[4], n_inside=n2, polarization=pol))
    return Rs, Ts, inputs


@pytest.mark.reference
@pytest.mark.parametrize("pol", POLS)
@pytest.mark.parametrize("inside_none", [True, False], ids=["inside=None", "inside=given"])
def test_film_random_domain_vs_mpmath(bo, pol, inside_none):
    """Film R and T over the whole domain vs the 40-digit mpmath Airy-sum reference.

    Reference: ``reference.film_rt_mp`` (Born & Wolf §1.5 + §7.6.1 in mpmath, exact inputs).
    Bar: abs <= 1e-12 and rel <= 1e-9 (R <= 1e-30 / |T| <= 1e-15 where ref is exactly 0).
    """
    rng = np.random.default_rng([SEED, int(inside_none), POLS.index(pol)])
    s = _sample(rng, 400, inside_none)
    R_ref, T_ref, inputs = _film_mp_lists(s, pol)
    kw = dict(n_outside=s["n0"], n_inside=s["n2"], polarization=pol)
    R = bo.film_reflectance(s["lam"], s["d"], s["theta"], s["n1"], **kw)
    T = bo.film_transmittance(s["lam"], s["d"], s["theta"], s["n1"], **kw)
    assert np.shape(R) == (400,) and np.shape(T) == (400,)
    _compare(R, R_ref, inputs, "R", zero_tol=ZERO_R_TOL)
    _compare(T, T_ref, inputs, "T", zero_tol=ZERO_T_TOL)


# ----------------------------------------------------------------------------- hand-picked hard cases
def _film_check(bo, cases, pol, R_zero_tol=ZERO_R_TOL, T_zero_tol=ZERO_T_TOL, rel_floor=0.0):
    """cases: list of (lam, d, theta, n_film, n_outside, n_inside); scalar calls, one per case."""
    R_ref, T_ref, R, T, inputs = [], [], [], [], []
    for lam, d, th, n1, n0, n2 in cases:
        a, b = ref.film_rt_mp(lam, d, th, n1, n0, n2, polarization=pol)
        R_ref.append(a)
        T_ref.append(b)
        R.append(float(bo.film_reflectance(lam, d, th, n1, n_outside=n0, n_inside=n2, polarization=pol)))
        T.append(float(bo.film_transmittance(lam, d, th, n1, n_outside=n0, n_inside=n2, polarization=pol)))
        inputs.append(dict(wavelength_nm=lam, thickness_nm=d, theta=th, n_film=n1, n_outside=n0,
                           n_inside=n2, polarization=pol))
    _compare(R, R_ref, inputs, "R", zero_tol=R_zero_tol, rel_floor=rel_floor)
    _compare(T, T_ref, inputs, "T", zero_tol=T_zero_tol, rel_floor=rel_floor)
    return R_ref, T_ref, R, T


@pytest.mark.reference
@pytest.mark.parametrize("pol", POLS)
def test_grazing_thick_absorbing_film(bo, pol):
    """theta = pi/2 - 1e-6, d = 10 µm, n = 2.5+0.1i (and neighbours) vs the mpmath reference.

    Reference: ``reference.film_rt_mp`` (40 digits).  Near grazing T ~ cos^2(theta) ~ 1e-12 times
    the absorption, so only a code that gets cos(theta) to full relative precision passes the
    relative bar.
    """
    cases = []
    for lam in (300.0, 550.0, 1000.0):
        for n2 in (None, 1.5, 1.0 + 0.0j, 2.0 + 0.05j):
            for n0 in (1.0, 1.33):
                cases.append((lam, 10_000.0, GRAZING, 2.5 + 0.1j, n0, n2))
                cases.append((lam, 10_000.0, GRAZING, 2.5 + 0.0j, n0, n2))
                cases.append((lam, 500.0, GRAZING, 1.333, n0, n2))
                cases.append((lam, 10_000.0, math.pi / 2 - 1e-5, 2.5 + 0.1j, n0, n2))
    _film_check(bo, cases, pol)


@pytest.mark.reference
@pytest.mark.parametrize("pol", POLS)
def test_resonances(bo, pol):
    """Half-wave resonances (R ~ 0 for a free-standing film) vs the mpmath reference.

    Reference: ``reference.film_rt_mp`` (40 digits).  At resonance R is a cancellation of O(1)
    terms, so the relative bar is applied only where the reference R > 1e-20; the absolute bar
    1e-12 everywhere.  Also checks the resonance is really there (R_ref tiny).
    """
    cases = []
    # exact half-wave at normal incidence: 2 pi d n / lam = m pi exactly in real arithmetic
    for lam, n1, d in ((600.0, 1.5, 200.0), (500.0, 1.25, 200.0), (400.0, 2.0, 1000.0)):
        cases.append((lam, d, 0.0, n1, 1.0, None))
    # float-rounded half-wave orders m = 1..6 for water at 550 nm
    for m in range(1, 7):
        cases.append((550.0, m * 550.0 / (2 * 1.333), 0.0, 1.333, 1.0, None))
    # oblique resonance: d = m lam / (2 n1 cos1), cos1 = sqrt(1 - sin^2 theta / n1^2)
    for th in (0.5, 1.0, 1.5):
        cos1 = math.sqrt(1 - (math.sin(th) / 1.333) ** 2)
        for m in (1, 3):
            cases.append((550.0, m * 550.0 / (2 * 1.333 * cos1), th, 1.333, 1.0, None))
    R_ref, _, _, _ = _film_check(bo, cases, pol, rel_floor=1e-20)
    assert max(float(r) for r in R_ref) < 1e-25, "reference check: these cases should be resonances"


@pytest.mark.reference
@pytest.mark.parametrize("pol", POLS)
def test_total_internal_reflection_at_back(bo, pol):
    """n0 = 1.5 | film 1.6 | inside 1.0 at theta = 1.2 rad: beyond the critical angle at the back.

    Reference: ``reference.film_rt_mp`` (40 digits).  Lossless + evanescent exit: R = 1 and T = 0
    exactly in theory (the reference gives T == 0 exactly), so we require |T| <= 1e-15 and R to
    the usual bar.
    """
    cases = []
    for lam in (300.0, 450.0, 633.0, 1000.0):
        for d in (0.0, 1.0, 100.0, 523.7, 10_000.0):
            cases.append((lam, d, 1.2, 1.6, 1.5, 1.0))
            cases.append((lam, d, 1.2, 1.6 + 0.0j, 1.5, 1.0 + 0.0j))
    R_ref, T_ref, R, T = _film_check(bo, cases, pol)
    assert all(T_r == 0 for T_r in T_ref), "reference check: T must be exactly 0"
    assert all(abs(r - 1) < 1e-30 for r in R_ref), "reference check: R must be 1"
    assert max(abs(t) for t in T) <= 1e-15


@pytest.mark.reference
@pytest.mark.parametrize("pol", POLS)
def test_index_match(bo, pol):
    """n_film == n_outside == n_inside: no interface at all, so R == 0 and T == 1.

    Reference: the mpmath reference (which gives R == 0, T == 1 to 40 digits) and the analytic fact
    itself.  Required: R <= 1e-30 and |T - 1| <= 1e-15, including at grazing incidence, where a
    code that forms cos(theta_film) via 1 - sin^2 would leave a spurious interface.
    """
    thetas = [0.0, 0.3, 1.0, 1.4, math.pi / 2 - 1e-3, math.pi / 2 - 1e-4, math.pi / 2 - 1e-5, GRAZING]
    R_all, T_all, inputs = [], [], []
    for n in (1.0, 1.333, 1.5):
        for th in thetas:
            for d in (0.0, 250.0, 10_000.0):
                for n_in in (None, n):
                    a, b = ref.film_rt_mp(550.0, d, th, n, n, n_in, polarization=pol)
                    assert a < 1e-60 and abs(b - 1) < 1e-30  # the reference itself
                    R_all.append(float(bo.film_reflectance(550.0, d, th, n, n_outside=n, n_inside=n_in,
                                                           polarization=pol)))
                    T_all.append(float(bo.film_transmittance(550.0, d, th, n, n_outside=n, n_inside=n_in,
                                                             polarization=pol)))
                    inputs.append(dict(wavelength_nm=550.0, thickness_nm=d, theta=th, n_film=n,
                                       n_outside=n, n_inside=n_in, polarization=pol))
    bad = [(R, T, inp) for R, T, inp in zip(R_all, T_all, inputs) if not (abs(R) <= 1e-30 and abs(T - 1) <= 1e-15)]
    if bad:
        worst = max(bad, key=lambda x: max(abs(x[0]) / 1e-30, abs(x[1] - 1) / 1e-15))
        pytest.fail(f"{len(bad)} of {len(inputs)} index-matched cases violate R<=1e-30, |T-1|<=1e-15; "
                    f"worst: {_fmt_inputs(worst[2])}: R={worst[0]!r}, T-1={worst[1] - 1!r}")


# ----------------------------------------------------------------------------- Fresnel coefficients
@pytest.mark.reference
def test_fresnel_dielectric_vs_mpmath():
    """The real-arithmetic build (``fresnel_dielectric_nb``, the tracer's clear spheres) against
    ``reference.fresnel_mp`` at 40 digits: Rs, Rp to 1e-13 relative (absolute 1e-300 where the
    reference is 0, at Brewster's angle none is exactly hit), q2 = n2 cos(theta2) to 1e-13,
    both directions of every pair, total internal reflection (1, 1, 0), grazing and near-equal
    indices (where a direct q1 - q2 would lose its digits)."""
    from bubbleoptics.kernels import fresnel_dielectric_nb

    ns = [1.0, 1.0 + 1e-9, 1.3, 1.333, 1.5, 2.5]
    thetas = [0.0, 0.2, 0.5, 0.9, 1.0, 1.2, 1.4, math.pi / 2 - 1e-3, math.pi / 2 - 1e-4, GRAZING]
    failures = []
    for a in ns:
        for b in ns:
            if a == b:
                continue
            for th in thetas:
                Rs, Rp, q2 = fresnel_dielectric_nb(a, b, math.cos(th))
                r = ref.fresnel_mp(a, b, th)
                with mpmath.workdps(40):
                    c1 = mpmath.cos(mpmath.mpf(th))
                    z = (mpmath.mpf(b) - a) * (mpmath.mpf(b) + a) + (a * c1) ** 2
                    q2_ref = mpmath.sqrt(z) if z > 0 else mpmath.mpf(0)
                for name, ours, want in (("Rs", Rs, r["Rs"]), ("Rp", Rp, r["Rp"]), ("q2", q2, q2_ref)):
                    want = float(mpmath.re(want))
                    err = abs(ours - want)
                    if err > 1e-13 * abs(want) + 1e-300:
                        failures.append(f"{name}: n1={a!r}, n2={b!r}, theta1={th!r}: ours={ours!r} ref={want!r}")
    assert not failures, f"{len(failures)} values off:\n" + "\n".join(failures[:10])


@pytest.mark.reference
def test_fresnel_coefficients_vs_mpmath(bo):
    """Fresnel amplitudes (rs, rp, ts, tp) to 1e-13 relative and powers to the film bar.

    Reference: ``reference.fresnel_mp`` (Born & Wolf §1.5 at 40 digits, tmm sign convention),
    including complex n2, total internal reflection and grazing incidence.  Exactly zero reference
    amplitudes (none in this grid) would be checked absolutely.
    """
    n1s = [1.0, 1.333, 1.5]
    n2s = [1.0, 1.333, 1.5, 2.5, 1.45 + 0.01j, 2.5 + 0.1j, 1.333 + 1e-6j, 0.2 + 3.0j]
    thetas = [0.0, 0.2, 0.5, 1.0, 1.2, 1.4, math.pi / 2 - 1e-3, math.pi / 2 - 1e-4, GRAZING]
    rows = []
    for a in n1s:
        for b in n2s:
            if b == a:
                continue  # no interface: amplitudes are exactly 0, covered by test_index_match
            for th in thetas:
                rows.append((a, b, th))
    n1 = np.array([r[0] for r in rows])
    n2 = np.array([r[1] for r in rows], dtype=complex)
    th = np.array([r[2] for r in rows])
    out = bo.fresnel_coefficients(n1, n2, th)
    refs = [ref.fresnel_mp(a, b, t) for a, b, t in rows]
    failures = []
    for field in ("rs", "rp", "ts", "tp"):
        ours = np.asarray(getattr(out, field), dtype=complex).ravel()
        for i, (row, o) in enumerate(zip(rows, ours)):
            r = refs[i][field]
            err = float(abs(mpmath.mpc(complex(o)) - r))
            mag = float(abs(r))
            rel = err / mag if mag else (math.inf if err else 0.0)
            if rel > 1e-13:
                failures.append((rel, f"{field}: n1={row[0]!r}, n2={row[1]!r}, theta1={row[2]!r}: ours={complex(o)!r} "
                                      f"ref={mpmath.nstr(r, 20)} abs_err={err:.3e} rel_err={rel:.3e}"))
    if failures:
        failures.sort(key=lambda x: -x[0])
        pytest.fail(f"{len(failures)} amplitude values off by > 1e-13 relative; worst first:\n"
                    + "\n".join(f[1] for f in failures[:5]))
    inputs = [dict(n1=a, n2=b, theta1=t) for a, b, t in rows]
    for field in ("Rs", "Rp", "Ts", "Tp"):
        _compare(getattr(out, field), [r[field] for r in refs], inputs, field, zero_tol=ZERO_T_TOL)


# ----------------------------------------------------------------------------- multilayer
SURFACTANT_STACK = ([1.45, 1.333, 1.45], [2.0, 500.0, 2.0])
ABSORBING_STACK = ([1.45, 1.333 + 0.02j, 1.6 + 0.1j, 1.45], [2.0, 480.0, 15.0, 2.0])


@pytest.mark.reference
@pytest.mark.parametrize("pol", POLS)
@pytest.mark.parametrize("stack", [SURFACTANT_STACK, ABSORBING_STACK], ids=["surfactant", "absorbing"])
@pytest.mark.parametrize("n_inside", [None, 1.5], ids=["inside=None", "inside=1.5"])
def test_multilayer_vs_mpmath(bo, pol, stack, n_inside):
    """Multilayer R and T vs the mpmath transfer-matrix product; abs error <= 1e-12.

    Reference: ``reference.multilayer_rt_mp`` (Byrnes arXiv:1603.02720 §4 matrix product at 40
    digits).  Grid: 15 wavelengths 300-1000 nm x 7 angles including pi/2 - 1e-6, broadcast as
    (wavelength[:, None], theta[None, :]).
    """
    n_layers, ds = stack
    lam = np.linspace(300.0, 1000.0, 15)
    th = np.array([0.0, 0.5, 1.0, 1.4, math.pi / 2 - 1e-3, math.pi / 2 - 1e-5, GRAZING])
    R = np.asarray(bo.multilayer_reflectance(lam[:, None], n_layers, ds, th[None, :], n_outside=1.0,
                                             n_inside=n_inside, polarization=pol))
    T = np.asarray(bo.multilayer_transmittance(lam[:, None], n_layers, ds, th[None, :], n_outside=1.0,
                                               n_inside=n_inside, polarization=pol))
    assert R.shape == (15, 7) and T.shape == (15, 7)
    R_ref, T_ref, inputs = [], [], []
    for li in lam:
        for ti in th:
            a, b = ref.multilayer_rt_mp(li, n_layers, ds, ti, 1.0, n_inside, pol)
            R_ref.append(a)
            T_ref.append(b)
            inputs.append(dict(wavelength_nm=float(li), n_layers=n_layers, thicknesses_nm=ds, theta=float(ti),
                               n_inside=n_inside, polarization=pol))
    _compare(R, R_ref, inputs, "R", rel_tol=math.inf)
    _compare(T, T_ref, inputs, "T", rel_tol=math.inf)
