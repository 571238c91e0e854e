"""``bubbleoptics`` against ``tmm`` on ordinary inputs, and self-checks of the references.

Two sections:

* **reference self-checks** (class ``TestReferenceSelfChecks``): the slow references of
  ``study/reference.py`` checked against each other, against ``tmm.coh_tmm`` (S. J. Byrnes,
  arXiv:1603.02720) and against analytic facts -- energy conservation R + T = 1 for lossless
  media (Born & Wolf, *Principles of Optics*, §1.5.3), the quarter- and half-wave layers at normal
  incidence (Born & Wolf §7.6.1 / §1.6.4), Brewster's angle and the Stokes relations.  These do
  not import the package.
* **package vs tmm**: the package's film and multilayer R, T against ``tmm.coh_tmm`` on ordinary
  cases (away from grazing incidence, where tmm's ``cos(arcsin(.))`` is inaccurate, and with
  single-pass absorption below tmm's clamp Im(delta) <= 35): |ours - tmm| <= 1e-10.  This includes
  a dispersive film (n_film an array over wavelength), where each wavelength must use its own
  refraction angle.
"""

from __future__ import annotations

import itertools
import math

import mpmath
import numpy as np
import pytest
from study import reference as ref  # the slow, literal references (mpmath, tmm)



POLS = ("s", "p", "unpolarized")
TMM_TOL = 1e-10  # package vs tmm
SELF_TMM_TOL = 1e-12  # mpmath reference vs tmm

# Ordinary film cases: (lam, d, theta, n_film, n_outside, n_inside)
ORDINARY_FILM_CASES = (
    # free-standing water film
    [(lam, d, th, 1.333, 1.0, None)
     for lam, d, th in itertools.product((400.0, 550.0, 700.0), (100.0, 333.3, 1000.0, 2000.0),
                                         (0.0, 0.4, 0.8, 1.2))]
    # absorbing films
    + [(lam, d, th, n1, 1.0, None)
       for lam, d, th, n1 in itertools.product((450.0, 650.0), (150.0, 1200.0), (0.0, 0.7, 1.2),
                                               (1.333 + 0.01j, 1.5 + 0.1j, 2.2 + 0.05j))]
    # unequal media: air | film | glass, water | film | air (with TIR at the back), lossy substrate
    + [(lam, d, th, n1, n0, n2)
       for lam, d, th, (n1, n0, n2) in itertools.product(
           (500.0, 800.0), (120.0, 900.0), (0.0, 0.5, 1.0, 1.2),
           ((1.38, 1.0, 1.5), (1.45 + 0.02j, 1.0, 1.5), (1.6, 1.333, 1.0), (1.4, 1.2, 1.9 + 0.05j)))]
)


def _tmm_case(case, pol):
    lam, d, th, n1, n0, n2 = case
    return ref.tmm_rt(lam, d, th, n1, n0, n2, pol)


def _report(label, cases, ours, theirs, tol):
    ours = np.asarray(ours, dtype=float).ravel()
    theirs = np.asarray(theirs, dtype=float).ravel()
    err = np.abs(ours - theirs)
    if not np.all(err <= tol):  # also catches NaN
        bad = np.flatnonzero(~(err <= tol))
        i = bad[np.argmax(np.nan_to_num(err[bad], nan=np.inf))]
        pytest.fail(f"{label}: {bad.size} of {err.size} points differ by more than {tol:g}; worst: "
                    f"inputs={cases[i]!r}: ours={ours[i]!r} reference={theirs[i]!r} abs_err={err[i]:.3e} "
                    f"rel_err={err[i] / abs(theirs[i]) if theirs[i] else math.inf:.3e}")


@pytest.fixture(scope="module")
def bo():
    import bubbleoptics

    return bubbleoptics


# ============================================================================= reference self-checks
class TestReferenceSelfChecks:
    """The slow references checked against tmm, against each other and against analytic facts."""

    @pytest.fixture(autouse=True)
    def _mp_precision(self):
        # mpmath arithmetic done *in the test bodies* (R + T - 1, closed forms) at 50 digits
        with mpmath.workdps(50):
            yield

    @pytest.mark.reference
    @pytest.mark.parametrize("pol", POLS)
    def test_film_mp_vs_tmm(self, pol):
        """reference.film_rt_mp (40-digit Airy sum) vs tmm.coh_tmm: agree to 1e-12 on ordinary cases."""
        ours, theirs = [], []
        for case in ORDINARY_FILM_CASES:
            R, T = ref.film_rt_mp(*case, polarization=pol)
            ours.append((float(R), float(T)))
            theirs.append(_tmm_case(case, pol))
        ours, theirs = np.array(ours), np.array(theirs)
        _report("R (mp vs tmm)", ORDINARY_FILM_CASES, ours[:, 0], theirs[:, 0], SELF_TMM_TOL)
        _report("T (mp vs tmm)", ORDINARY_FILM_CASES, ours[:, 1], theirs[:, 1], SELF_TMM_TOL)

    @pytest.mark.reference
    @pytest.mark.parametrize("pol", POLS)
    def test_multilayer_mp_vs_film_mp(self, pol):
        """Two formulations agree: a one-layer transfer-matrix product == the Airy sum, to 1e-30.

        Also near grazing incidence and for thick absorbing films (where tmm cannot be used).
        """
        cases = list(ORDINARY_FILM_CASES) + [
            (300.0, 10_000.0, math.pi / 2 - 1e-6, 2.5 + 0.1j, 1.0, None),
            (1000.0, 10_000.0, math.pi / 2 - 1e-6, 1.333, 1.2, 1.8 + 0.01j),
            (550.0, 0.0, 1.0, 1.333, 1.0, 1.5),
        ]
        for lam, d, th, n1, n0, n2 in cases:
            a = ref.film_rt_mp(lam, d, th, n1, n0, n2, polarization=pol)
            b = ref.multilayer_rt_mp(lam, [n1], [d], th, n0, n2, polarization=pol)
            assert abs(a[0] - b[0]) <= 1e-30 and abs(a[1] - b[1]) <= 1e-30, (lam, d, th, n1, n0, n2, a, b)

    @pytest.mark.reference
    @pytest.mark.parametrize("pol", POLS)
    def test_multilayer_mp_vs_tmm(self, pol):
        """reference.multilayer_rt_mp vs tmm.coh_tmm for 3- and 5-layer stacks: agree to 1e-12."""
        stacks = [
            ([1.45, 1.333, 1.45], [2.0, 500.0, 2.0]),
            ([1.45, 1.333 + 0.02j, 1.6 + 0.1j, 1.45], [2.0, 480.0, 15.0, 2.0]),
            ([2.3, 1.38, 2.3 + 0.01j, 1.38, 1.7], [60.0, 100.0, 60.0, 100.0, 250.0]),
        ]
        cases, ours, theirs = [], [], []
        for (nl, dl), lam, th, (n0, n2) in itertools.product(stacks, (380.0, 550.0, 780.0), (0.0, 0.6, 1.1),
                                                             ((1.0, None), (1.0, 1.5), (1.333, 1.0))):
            R, T = ref.multilayer_rt_mp(lam, nl, dl, th, n0, n2, pol)
            cases.append((lam, nl, dl, th, n0, n2))
            ours.append((float(R), float(T)))
            theirs.append(ref.tmm_multilayer_rt(lam, nl, dl, th, n0, n2, pol))
        ours, theirs = np.array(ours), np.array(theirs)
        _report("R (mp vs tmm, multilayer)", cases, ours[:, 0], theirs[:, 0], SELF_TMM_TOL)
        _report("T (mp vs tmm, multilayer)", cases, ours[:, 1], theirs[:, 1], SELF_TMM_TOL)

    @pytest.mark.reference
    @pytest.mark.parametrize("pol", POLS)
    def test_lossless_energy_conservation(self, pol):
        """R + T = 1 for lossless media (Born & Wolf §1.5.3), to 1e-35, incl. grazing and TIR."""
        for lam, d, th, n1, n0, n2 in [
            (550.0, 300.0, 0.3, 1.333, 1.0, None),
            (400.0, 10_000.0, math.pi / 2 - 1e-6, 2.5, 1.0, None),
            (700.0, 1234.5, 1.0, 1.38, 1.0, 1.5),
            (633.0, 523.7, 1.2, 1.6, 1.5, 1.0),  # evanescent exit: T = 0, R = 1
            (633.0, 80.0, 1.2, 1.0, 1.5, 1.6),  # frustrated TIR: evanescent in the film
            (1000.0, 0.0, 0.9, 1.4, 1.2, 1.9),
        ]:
            R, T = ref.film_rt_mp(lam, d, th, n1, n0, n2, polarization=pol)
            assert abs(R + T - 1) <= 1e-35, (lam, d, th, n1, n0, n2, R, T)
            assert T >= 0 and R >= 0

    @pytest.mark.reference
    @pytest.mark.parametrize("pol", POLS)
    def test_absorbing_film_loses_energy(self, pol):
        """With k > 0 in the film, 0 < R + T < 1 (absorption A = 1 - R - T > 0)."""
        for th in (0.0, 0.7, 1.3, math.pi / 2 - 1e-6):
            R, T = ref.film_rt_mp(500.0, 700.0, th, 1.5 + 0.05j, 1.0, 1.3, polarization=pol)
            assert 0 < R + T < 1 and R > 0 and T > 0

    @pytest.mark.reference
    def test_quarter_and_half_wave_normal_incidence(self):
        """Quarter-wave layer: R = ((n0 n2 - n1^2)/(n0 n2 + n1^2))^2; half-wave: R = bare n0|n2 interface.

        Born & Wolf §1.6.4 (quarter-wave "absentee" and anti-reflection layers).  Inputs chosen so
        that 4 n1 d / lambda = 1 (or 2) exactly in binary floating point.
        """
        for (n0, n1, n2, lam, d) in [(1.0, 1.25, 1.5, 500.0, 100.0), (1.0, 1.5, 1.0, 600.0, 100.0),
                                     (1.0, 1.25, 1.5625, 500.0, 100.0), (1.5, 2.0, 1.0, 1000.0, 125.0),
                                     (1.25, 1.5, 1.75, 300.0, 50.0)]:
            assert 4 * n1 * d == lam
            for pol in POLS:
                R, T = ref.film_rt_mp(lam, d, 0.0, n1, n0, n2, polarization=pol, dps=50)
                with mpmath.workdps(50):
                    expect = ((mpmath.mpf(n0) * n2 - mpmath.mpf(n1) ** 2) / (mpmath.mpf(n0) * n2 + mpmath.mpf(n1) ** 2)) ** 2
                assert abs(R - expect) <= 1e-40, (n0, n1, n2, pol, R, expect)
                assert abs(R + T - 1) <= 1e-40
                # half-wave: the layer is "absent"
                R2, _ = ref.film_rt_mp(lam, 2 * d, 0.0, n1, n0, n2, polarization=pol, dps=50)
                with mpmath.workdps(50):
                    bare = ((mpmath.mpf(n0) - n2) / (mpmath.mpf(n0) + n2)) ** 2
                assert abs(R2 - bare) <= 1e-40, (n0, n1, n2, pol, R2, bare)

    @pytest.mark.reference
    def test_fresnel_mp_analytic(self):
        """fresnel_mp: normal-incidence formula, Brewster's angle, Rs+Ts = Rp+Tp = 1, Stokes relations.

        Born & Wolf §1.5.2-1.5.3 (Brewster: tan theta_B = n2/n1; Stokes: r' = -r, t t' = 1 - r^2).
        """
        for n1, n2 in [(1.0, 1.333), (1.333, 1.0), (1.0, 2.5), (1.5, 1.0)]:
            f = ref.fresnel_mp(n1, n2, 0.0)
            normal = ((mpmath.mpf(n1) - n2) / (mpmath.mpf(n1) + n2)) ** 2
            assert abs(f["Rs"] - normal) < 1e-35 and abs(f["Rp"] - normal) < 1e-35
            tb = math.atan2(n2, n1)
            assert ref.fresnel_mp(n1, n2, tb)["Rp"] < 1e-28  # float theta_B is within 1e-16 rad
            for th in (0.0, 0.3, 0.8, 1.2, math.pi / 2 - 1e-6):
                f = ref.fresnel_mp(n1, n2, th)
                assert abs(f["Rs"] + f["Ts"] - 1) < 1e-35 and abs(f["Rp"] + f["Tp"] - 1) < 1e-35
                # reverse interface at the refracted angle (only where light gets through)
                # (not at grazing: there the reverse angle sits at the critical angle, where r is
                # infinitely sensitive to the float rounding of th2)
                s2 = n1 * math.sin(th) / n2
                if s2 < 1 and th <= 1.2:
                    with mpmath.workdps(60):
                        th2 = float(mpmath.asin(mpmath.mpf(n1) * mpmath.sin(mpmath.mpf(th)) / n2))
                    g = ref.fresnel_mp(n2, n1, th2)
                    # th2 is rounded to float: the relations hold to ~1e-16 (first order in the rounding)
                    for r, t, rr, tt in (("rs", "ts", "rs", "ts"), ("rp", "tp", "rp", "tp")):
                        assert abs(f[r] + g[rr]) < 1e-14
                        assert abs(f[t] * g[tt] - (1 - f[r] ** 2)) < 1e-14

    @pytest.mark.reference
    def test_fresnel_mp_vs_tmm_interface(self):
        """fresnel_mp amplitudes vs tmm.coh_tmm on a bare interface (two semi-infinite media)."""
        import tmm

        for n1, n2, th in itertools.product((1.0, 1.333), (1.5, 2.5 + 0.1j, 1.45 + 0.01j), (0.0, 0.5, 1.1)):
            f = ref.fresnel_mp(n1, n2, th)
            for pol in ("s", "p"):
                out = tmm.coh_tmm(pol, [n1, n2], [math.inf, math.inf], th, 500.0)
                assert abs(complex(f["r" + pol]) - out["r"]) < 1e-13
                assert abs(complex(f["t" + pol]) - out["t"]) < 1e-13
                assert abs(float(f["R" + pol]) - out["R"]) < 1e-13
                assert abs(float(f["T" + pol]) - out["T"]) < 1e-13

    @pytest.mark.reference
    @pytest.mark.parametrize("pol", POLS)
    def test_zero_thickness_film_is_bare_interface(self, pol):
        """d = 0 with n_inside = n_film reduces to the single n0 | n_film interface (fresnel_mp)."""
        for n0, n1, th in [(1.0, 1.333, 0.4), (1.2, 2.5 + 0.1j, 1.3), (1.5, 1.0, 1.0), (1.0, 1.5, math.pi / 2 - 1e-6)]:
            R, T = ref.film_rt_mp(550.0, 0.0, th, n1, n0, n1, polarization=pol)
            f = ref.fresnel_mp(n0, n1, th)
            Rf = {"s": f["Rs"], "p": f["Rp"], "unpolarized": (f["Rs"] + f["Rp"]) / 2}[pol]
            Tf = {"s": f["Ts"], "p": f["Tp"], "unpolarized": (f["Ts"] + f["Tp"]) / 2}[pol]
            assert abs(R - Rf) < 1e-35 and abs(T - Tf) < 1e-35


# ============================================================================= package vs tmm
@pytest.mark.reference
@pytest.mark.parametrize("pol", POLS)
def test_film_vs_tmm(bo, pol):
    """Package film R, T vs tmm.coh_tmm (independent float64 transfer-matrix code), |diff| <= 1e-10.

    Reference: ``tmm.coh_tmm(pol, [n0, n1, n2], [inf, d, inf], theta, lam)`` (Byrnes,
    arXiv:1603.02720), on ordinary cases (no grazing incidence), one vectorized package call.
    """
    cases = ORDINARY_FILM_CASES
    theirs = np.array([_tmm_case(c, pol) for c in cases])
    for inside_none in (True, False):
        idx = [i for i, c in enumerate(cases) if (c[5] is None) == inside_none]
        sub = [cases[i] for i in idx]
        lam, d, th, n1, n0 = (np.array([c[k] for c in sub]) for k in range(5))
        n1 = n1.astype(complex)
        n2 = None if inside_none else np.array([c[5] for c in sub], dtype=complex)
        R = bo.film_reflectance(lam, d, th, n1, n_outside=n0, n_inside=n2, polarization=pol)
        T = bo.film_transmittance(lam, d, th, n1, n_outside=n0, n_inside=n2, polarization=pol)
        _report(f"R (package vs tmm, inside None={inside_none})", sub, R, theirs[idx, 0], TMM_TOL)
        _report(f"T (package vs tmm, inside None={inside_none})", sub, T, theirs[idx, 1], TMM_TOL)


@pytest.mark.reference
@pytest.mark.parametrize("pol", POLS)
@pytest.mark.parametrize("n_inside", [None, 1.5, 1.2 + 0.01j], ids=["inside=None", "inside=1.5", "inside=lossy"])
def test_dispersive_film_vs_tmm(bo, pol, n_inside):
    """n_film given per wavelength (81 values): each wavelength refracts at its own angle.

    Reference: tmm.coh_tmm called wavelength by wavelength with that wavelength's index
    n_film = 1.33 + 0.01 (500/lambda)^2 (+ small absorption), at 60 degrees; |diff| <= 1e-10.
    Also broadcast against a column of thicknesses: result shape (4, 81).
    """
    lam = np.linspace(380.0, 780.0, 81)
    n_film = 1.33 + 0.01 * (500.0 / lam) ** 2 + 1j * 1e-3 * (500.0 / lam)
    th = math.radians(60.0)
    d = np.array([0.0, 150.0, 480.0, 1500.0])[:, None]
    R = np.asarray(bo.film_reflectance(lam[None, :], d, th, n_film[None, :], n_outside=1.0, n_inside=n_inside,
                                       polarization=pol))
    T = np.asarray(bo.film_transmittance(lam[None, :], d, th, n_film[None, :], n_outside=1.0, n_inside=n_inside,
                                         polarization=pol))
    assert R.shape == (4, 81) and T.shape == (4, 81)
    cases, theirs = [], []
    for dj in d[:, 0]:
        for li, ni in zip(lam, n_film):
            cases.append((float(li), float(dj), th, complex(ni), 1.0, n_inside))
            theirs.append(ref.tmm_rt(li, dj, th, ni, 1.0, n_inside, pol))
    theirs = np.array(theirs)
    _report("R (dispersive film vs tmm)", cases, R, theirs[:, 0], TMM_TOL)
    _report("T (dispersive film vs tmm)", cases, T, theirs[:, 1], TMM_TOL)
    # Same with a real (lossless) dispersive index array
    n_real = 1.33 + 0.01 * (500.0 / lam) ** 2
    R = bo.film_reflectance(lam, 480.0, th, n_real, n_outside=1.0, n_inside=n_inside, polarization=pol)
    T = bo.film_transmittance(lam, 480.0, th, n_real, n_outside=1.0, n_inside=n_inside, polarization=pol)
    cases = [(float(li), 480.0, th, float(ni), 1.0, n_inside) for li, ni in zip(lam, n_real)]
    theirs = np.array([ref.tmm_rt(*c, pol) for c in cases])
    _report("R (real dispersive film vs tmm)", cases, R, theirs[:, 0], TMM_TOL)
    _report("T (real dispersive film vs tmm)", cases, T, theirs[:, 1], TMM_TOL)


@pytest.mark.reference
@pytest.mark.parametrize("pol", POLS)
def test_multilayer_vs_tmm(bo, pol):
    """Package multilayer R, T vs tmm.coh_tmm for several stacks and media, |diff| <= 1e-10.

    Reference: tmm.coh_tmm (Byrnes, arXiv:1603.02720).  Broadcast grid wavelength[:, None] x theta[None, :];
    scalar layer indices only (the dispersive case is the next test).
    """
    lam = np.linspace(380.0, 780.0, 21)
    th = np.array([0.0, 0.35, 0.7, 1.05, 1.2])
    stacks = [
        ([1.45, 1.333, 1.45], [2.0, 500.0, 2.0], 1.0, None),
        ([1.45, 1.333 + 0.02j, 1.6 + 0.1j, 1.45], [2.0, 480.0, 15.0, 2.0], 1.0, 1.5),
        ([2.3, 1.38, 2.3 + 0.01j, 1.38, 1.7], [60.0, 100.0, 60.0, 100.0, 250.0], 1.333, 1.0),
    ]
    _multilayer_grid_vs_tmm(bo, stacks, lam, th, pol)


@pytest.mark.reference
@pytest.mark.parametrize("pol", POLS)
def test_multilayer_dispersive_layer_vs_tmm(bo, pol):
    """A stack mixing scalar layers with a per-wavelength index array (water), vs tmm.coh_tmm (1e-10).

    Reference: tmm.coh_tmm called wavelength by wavelength with that wavelength's water index.
    n_layers = [1.45, n_water[:, None], 1.45] -- scalars and an array in one sequence, as the API allows.
    """
    lam = np.linspace(380.0, 780.0, 21)
    th = np.array([0.0, 0.35, 0.7, 1.05, 1.2])
    n_water = 1.33 + 0.01 * (500.0 / lam) ** 2
    surf = np.full_like(n_water, 1.45)
    stacks = [
        ([surf, n_water, surf], [2.0, 800.0, 2.0], 1.0, None),  # every entry an array
        ([1.45, n_water, 1.45], [2.0, 800.0, 2.0], 1.0, None),  # scalars and arrays mixed
        ([1.45, n_water + 0.001j, 1.6 + 0.05j], [2.0, 450.0, 10.0], 1.0, 1.5),
    ]
    _multilayer_grid_vs_tmm(bo, stacks, lam, th, pol)


def _multilayer_grid_vs_tmm(bo, stacks, lam, th, pol):
    for nl, dl, n0, n2 in stacks:
        nl_b = [n[:, None] if isinstance(n, np.ndarray) else n for n in nl]
        R = np.asarray(bo.multilayer_reflectance(lam[:, None], nl_b, dl, th[None, :], n_outside=n0, n_inside=n2,
                                                 polarization=pol))
        T = np.asarray(bo.multilayer_transmittance(lam[:, None], nl_b, dl, th[None, :], n_outside=n0, n_inside=n2,
                                                   polarization=pol))
        assert R.shape == (21, 5) and T.shape == (21, 5)
        cases, theirs = [], []
        for i, li in enumerate(lam):
            nli = [complex(n[i]) if isinstance(n, np.ndarray) else n for n in nl]
            for tj in th:
                cases.append((float(li), nli, dl, float(tj), n0, n2))
                theirs.append(ref.tmm_multilayer_rt(li, nli, dl, tj, n0, n2, pol))
        theirs = np.array(theirs)
        _report("R (multilayer vs tmm)", cases, R, theirs[:, 0], TMM_TOL)
        _report("T (multilayer vs tmm)", cases, T, theirs[:, 1], TMM_TOL)


@pytest.mark.reference
@pytest.mark.parametrize("pol", POLS)
def test_single_layer_multilayer_equals_film(bo, pol):
    """The package's multilayer with one layer agrees with its film functions and with tmm (1e-10)."""
    lam = np.linspace(400.0, 700.0, 7)[:, None]
    th = np.array([0.0, 0.5, 1.0])[None, :]
    R1 = bo.film_reflectance(lam, 640.0, th, 1.4 + 0.01j, n_outside=1.0, n_inside=1.5, polarization=pol)
    R2 = bo.multilayer_reflectance(lam, [1.4 + 0.01j], [640.0], th, n_outside=1.0, n_inside=1.5, polarization=pol)
    T1 = bo.film_transmittance(lam, 640.0, th, 1.4 + 0.01j, n_outside=1.0, n_inside=1.5, polarization=pol)
    T2 = bo.multilayer_transmittance(lam, [1.4 + 0.01j], [640.0], th, n_outside=1.0, n_inside=1.5, polarization=pol)
    cases = [(float(a), float(b)) for a in lam[:, 0] for b in th[0]]
    _report("R film vs multilayer", cases, R1, R2, TMM_TOL)
    _report("T film vs multilayer", cases, T1, T2, TMM_TOL)
