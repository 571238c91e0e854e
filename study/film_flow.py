"""Small analyses of living films shared by ``notebooks/07_film_flow.ipynb`` and its test.

* :func:`film_luminance`: the luminance (CIE Y, a perfect reflector = 1) a free-standing film
  reflects, from the exact spectrum (:func:`bubbleoptics.film_reflectance`);
* :func:`first_order_range`: where a luminance-against-thickness curve is black, where its first
  maximum (the first-order white) lies and where the first order ends (the first minimum after
  it: the first-order purple, where green is cancelled);
* :func:`opd_table_luminance`: a lookup table emulated in the simplest way, the film's luminance
  tabulated every *step* nm of optical path difference (OPD = 2 n d at normal incidence) and
  interpolated linearly, to see what the interpolation does to thin (black) films;
* :func:`first_crossing` and :func:`rigid_black_time`: when a thickness first goes below a
  threshold, in a simulated series and by the rigid-drainage apex law
  :math:`h_0 (1 + t/\\tau)^{-1/2}`;
* the verification references of the models, shared by ``tests/bubbleoptics/test_film_flow.py`` and
  ``benchmarks/film_flow_verification.py``: :func:`rigid_characteristics_profile` (rigid drainage
  from a uniform start, by the characteristics of its PDE, integrated with scipy),
  :func:`plug_equilibrium_error` (plug flow against its closed-form equilibrium) and
  :func:`coarsen_cells` (a field on the grid half as fine, for self-convergence);
* the verification studies of ``benchmarks/film_flow_verification.py`` (the time step and the
  evaporation rate) and their tests: :func:`black_film_run` (an evaporating plug-flow film
  sampled every step, a :class:`BlackFilm`), :func:`equilibrium_apex_nm`,
  :func:`observed_orders` and :func:`richardson`.

Units: thickness in nm, times in s, angles in radians.  NumPy only (plus
:mod:`bubbleoptics` inside :func:`film_luminance` and :func:`opd_table_luminance`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "film_luminance",
    "FirstOrder",
    "first_order_range",
    "opd_table_luminance",
    "first_crossing",
    "rigid_black_time",
    "STILL",
    "unit_exponent_parameters",
    "plug_equilibrium_error",
    "rigid_characteristics_profile",
    "coarsen_cells",
    "plug_transient_differences",
    "BlackFilm",
    "equilibrium_apex_nm",
    "black_film_run",
    "observed_orders",
    "richardson",
]

#: Film parameters without perturbation or evaporation: the models' analytic cases.
STILL = dict(perturbation=0.0, evaporation=0.0)


def film_luminance(thickness_nm, theta=0.0, n_film=None, illuminant="D65"):
    """Reflected luminance Y of a free-standing film (exact Airy spectrum, 360-780 nm every 1 nm,
    CIE 1931 2°), Y = 1 for a perfect reflector under *illuminant* (``None``: equal energy E).
    *n_film* None is water (dispersive).  Shape of *thickness_nm*.

    >>> round(float(film_luminance(0.0)), 12)
    0.0
    """
    import bubbleoptics as bo
    from bubbleoptics.colorimetry import DEFAULT_WAVELENGTHS_NM as WL

    d = np.asarray(thickness_nm, dtype=float)
    spectra = bo.film_reflectance(WL, d[..., None], theta, n_film)
    return spectra @ bo.spectral_weights(WL, illuminant=illuminant)[1]


@dataclass(frozen=True)
class FirstOrder:
    """The first interference order of a luminance curve Y(d) (nm): ``black_below_nm`` (the
    thinnest thickness where Y reaches ``black_fraction`` of the first maximum; thinner is
    black), ``peak_nm`` (the first maximum, the first-order white), ``end_nm`` (the first minimum
    after it, where the first order ends), ``peak_Y`` and ``end_Y`` (the luminances there)."""

    black_below_nm: float
    peak_nm: float
    end_nm: float
    peak_Y: float
    end_Y: float
    black_fraction: float


def first_order_range(thickness_nm, luminance, black_fraction=0.05):
    """The first order of a sampled luminance curve (*thickness_nm* increasing from 0, *luminance*
    of the same length): the first local maximum, the first local minimum after it and, before
    the maximum, where Y first reaches *black_fraction* of it (linear interpolation between
    samples).  Extrema are the samples themselves (so they are as precise as the sampling).

    >>> d = np.linspace(0.0, 500.0, 5001)
    >>> fo = first_order_range(d, np.sin(2 * np.pi * 1.33 * d / 550.0) ** 2)
    >>> round(fo.peak_nm, 1), round(fo.end_nm, 1), round(550 / (4 * 1.33), 1), round(550 / (2 * 1.33), 1)
    (103.4, 206.8, 103.4, 206.8)
    """
    d = np.asarray(thickness_nm, dtype=float)
    y = np.asarray(luminance, dtype=float)
    if d.ndim != 1 or y.shape != d.shape or d.size < 3 or np.any(np.diff(d) <= 0):
        raise ValueError("thickness_nm must be 1-D, increasing, with >= 3 samples, and luminance of its shape")
    if not 0.0 < black_fraction < 1.0:
        raise ValueError(f"black_fraction must be in (0, 1) (got {black_fraction!r})")
    rising = np.diff(y) > 0
    falls = np.flatnonzero(rising[:-1] & ~rising[1:])  # y[i+1] is a local maximum
    if falls.size == 0:
        raise ValueError("the luminance has no local maximum in the range")
    i_peak = int(falls[0]) + 1
    after = rising[i_peak:]
    rises = np.flatnonzero(~after[:-1] & after[1:])
    if rises.size == 0:
        raise ValueError("the luminance has no minimum after its first maximum in the range")
    i_end = i_peak + int(rises[0]) + 1
    level = black_fraction * y[i_peak]
    j = int(np.flatnonzero(y[: i_peak + 1] >= level)[0])
    if j == 0:
        black = d[0]
    else:
        black = d[j - 1] + (level - y[j - 1]) * (d[j] - d[j - 1]) / (y[j] - y[j - 1])
    return FirstOrder(float(black), float(d[i_peak]), float(d[i_end]), float(y[i_peak]), float(y[i_end]),
                      float(black_fraction))


def opd_table_luminance(thickness_nm, step_opd_nm, n_film=1.33, illuminant=None, n_nodes=None):
    """The film's luminance read from a table: exact :func:`film_luminance` (constant index
    *n_film*, normal incidence) at the nodes OPD_k = k x *step_opd_nm* (thickness
    OPD_k / (2 n)), linearly interpolated at *thickness_nm*.  *n_nodes* defaults to enough nodes
    to cover the thickest film asked for.  Exact at the nodes; between them it misses the
    curvature of Y (near d = 0, Y grows as d², so the chord is too bright).

    >>> d = 18.7 / (2 * 1.33) * np.arange(3)  # three nodes: the table is exact there
    >>> bool(np.allclose(opd_table_luminance(d, 18.7), film_luminance(d, n_film=1.33, illuminant=None)))
    True
    """
    d = np.asarray(thickness_nm, dtype=float)
    step_d = float(step_opd_nm) / (2.0 * float(n_film))
    if n_nodes is None:
        n_nodes = int(np.ceil(d.max() / step_d)) + 2
    nodes = step_d * np.arange(n_nodes)
    table = film_luminance(nodes, 0.0, n_film, illuminant)
    return np.interp(d, nodes, table)


def first_crossing(times, values, threshold):
    """The first time a sampled curve *values*(*times*) goes below *threshold*, linearly
    interpolated between the two samples around the crossing; ``nan`` if it never does (and
    *times*[0] if it starts below).

    >>> first_crossing([0.0, 10.0, 20.0], [100.0, 50.0, 0.0], 30.0)
    14.0
    """
    t = np.asarray(times, dtype=float)
    v = np.asarray(values, dtype=float)
    below = np.flatnonzero(v < threshold)
    if below.size == 0:
        return float("nan")
    i = int(below[0])
    if i == 0:
        return float(t[0])
    return float(t[i - 1] + (v[i - 1] - threshold) * (t[i] - t[i - 1]) / (v[i - 1] - v[i]))


def rigid_black_time(h0_nm, tau_s, threshold_nm):
    """The time the rigid-drainage apex law :math:`h_0(1 + t/\\tau)^{-1/2}` (no evaporation)
    needs to thin from *h0_nm* to *threshold_nm*: :math:`\\tau((h_0/h)^2 - 1)` s.

    >>> rigid_black_time(2000.0, 3000.0, 1000.0)  # half the thickness: (2^2 - 1) tau
    9000.0
    """
    if not 0 < threshold_nm <= h0_nm:
        raise ValueError(f"threshold_nm must be in (0, h0_nm] (got {threshold_nm!r})")
    return float(tau_s * ((h0_nm / threshold_nm) ** 2 - 1.0))


# ---------------------------------------------------------------- verification references
def unit_exponent_parameters(**changes):
    """:class:`~bubbleoptics.filmflow.FilmParameters` (with *changes*) whose plug-flow
    equilibrium exponent is a = 1: surfactant Γ0 = ρ g R h0 / (2 R_g T)."""
    from bubbleoptics.filmflow import FilmParameters
    from bubbleoptics.filmflow.parameters import GAS_CONSTANT

    p = FilmParameters(**changes)
    return p.replace(surfactant=p.density * p.gravity * p.radius * p.h0 / (2 * GAS_CONSTANT * p.temperature))


def plug_equilibrium_error(n_theta, steps=600, dt=0.005):
    """``(max relative error, final state, exact h(θ) in m)`` of plug flow on *n_theta* rows (4
    columns), after *steps* steps of *dt* s from the uniform still film of
    :func:`unit_exponent_parameters`, against its equilibrium
    :math:`h_0 \\frac{a}{\\sinh a} e^{-a\\cos\\theta}` (area-normalised, ``docs/film-flow.md``)."""
    import math

    from bubbleoptics.filmflow import FilmGrid, PlugFlow

    p = unit_exponent_parameters(**STILL)
    g = FilmGrid(n_theta, 4, p.radius)
    m = PlugFlow(p, g)
    s = m.initial_state(0)
    for _ in range(steps):
        s = m.step(s, dt)
    a = p.equilibrium_exponent
    exact = p.h0 * a / math.sinh(a) * np.exp(-a * np.cos(g.theta))
    return np.abs(s.h / exact[:, None] - 1).max(), s, exact


def rigid_characteristics_profile(s_end, starts=201):
    """``(θ, h/h0)`` of rigid drainage at t = *s_end* τ from a uniform film, along the
    characteristics of its PDE (dθ/ds = (3/4) H² sin θ, dH/ds = −(1/2) H³ cos θ, s = t/τ) from
    *starts* points in θ ∈ [0, 2], integrated by :func:`scipy.integrate.solve_ivp` (rtol 1e-11)."""
    import math

    from scipy.integrate import solve_ivp

    def rhs(_, y):
        return [0.75 * y[1] ** 2 * math.sin(y[0]), -0.5 * y[1] ** 3 * math.cos(y[0])]

    ends = [solve_ivp(rhs, (0, s_end), [t0, 1.0], rtol=1e-11, atol=1e-13).y[:, -1]
            for t0 in np.linspace(0, 2, starts)]
    return np.array(ends).T


def coarsen_cells(grid, h):
    """Area-weighted means of 2 x 2 blocks of cells of *h* on *grid*: the field on the grid half
    as fine (for a grid against the next finer)."""
    from bubbleoptics.filmflow import FilmGrid

    coarse = FilmGrid(grid.n_theta // 2, grid.n_phi // 2, grid.radius)
    volume = (grid.area[:, None] * h).reshape(coarse.n_theta, 2, coarse.n_phi, 2).sum(axis=(1, 3))
    return volume / coarse.area[:, None]


def plug_transient_differences(rows_list, steps=20, dt=0.0025, seed=3):
    """{n: max |h_n - coarsened h_2n| / h0} for each *n* of *rows_list* but the last (each grid
    n x 2n against the next finer, which *rows_list* must contain): plug flow after *steps* steps
    of *dt* s from a smooth perturbation (seed *seed*), no evaporation; the self-convergence of
    the transient (first order: upwind transport)."""
    from bubbleoptics.filmflow import FilmGrid, FilmParameters, PlugFlow

    p = FilmParameters(evaporation=0.0, perturbation=0.1)
    fields = {}
    for n in rows_list:
        g = FilmGrid(n, 2 * n, p.radius)
        m = PlugFlow(p, g)
        s = m.initial_state(seed)
        for _ in range(steps):
            s = m.step(s, dt)
        fields[n] = (g, s.h)
    return {n: float(np.abs(fields[n][1] - coarsen_cells(*fields[2 * n])).max() / p.h0) for n in rows_list[:-1]}


# ---------------------------------------------------------------- verification: time step, evaporation
@dataclass(frozen=True)
class BlackFilm:
    """One evaporating plug-flow run, sampled after every step (so a crossing time is
    interpolated between two steps, not between saved frames): the times (s) at which the apex
    (the top cell row, mean over φ) and the thinnest cell anywhere first go below
    ``threshold_nm`` (``nan`` if not within the run), the apex thickness (nm) at ``probe_s``
    (``nan`` if the run stopped before), at the start and at the end of the run, ``t_end`` (s),
    the ``steps`` taken and their ``wall`` and ``cpu`` seconds, and the most the flow had
    drained from the apex at any step, ``drained_peak_nm`` (the apex's thinning beyond
    :math:`E\\,t`), at ``t_drained_peak`` (s)."""

    dt: float
    evaporation: float
    grid: tuple
    threshold_nm: float
    t_apex: float
    t_first: float
    probe_s: float
    apex_probe_nm: float
    apex_start_nm: float
    apex_end_nm: float
    t_end: float
    steps: int
    wall: float
    cpu: float
    drained_peak_nm: float = float("nan")
    t_drained_peak: float = float("nan")

    @property
    def evaporated_share(self):
        """The part of the apex's thinning, from its start to ``threshold_nm``, that evaporation
        did: :math:`E\\,t_{apex}/(h_{apex}(0) - h_{black})`.  At the apex
        :math:`\\partial_t h = -\\nabla_s\\cdot(h\\mathbf u) - E` and nothing clips the thickness before
        it is black, so the rest, 1 minus this, is what the flow carried away (drainage)."""
        return self.evaporation * self.t_apex * 1e9 / (self.apex_start_nm - self.threshold_nm)


def equilibrium_apex_nm(params):
    """:math:`h_{eq}(0) = h_0 (a/\\sinh a) e^{-a}` in nm: the apex of the plug-flow equilibrium
    (``docs/film-flow.md``) for *params*; its evaporation time at rate E is this / E."""
    import math

    a = params.equilibrium_exponent
    return params.h0 * 1e9 * a / math.sinh(a) * math.exp(-a)


def black_film_run(params, grid, dt, threshold_nm=30.0, probe_s=30.0, t_max=None, seed=0):
    """Plug flow (:class:`~bubbleoptics.filmflow.PlugFlow`) with *params* on *grid* ((n_theta,
    n_phi)) from ``initial_state(seed)`` in steps of *dt* s, until the apex and the thinnest
    cell are both below *threshold_nm* and *probe_s* is passed, or until *t_max* s (default
    1.5 h0/E, or 120 s without evaporation).  Returns a :class:`BlackFilm`.

    >>> from bubbleoptics.filmflow import FilmParameters
    >>> r = black_film_run(FilmParameters(evaporation=3e-7), (8, 16), 0.05, probe_s=1.0)
    >>> 5.0 < r.t_apex < 7.0, r.t_first <= r.t_apex, round(r.apex_start_nm)
    (True, True, 2017)
    """
    import math
    import time

    from bubbleoptics.filmflow import FilmGrid, PlugFlow

    if t_max is None:
        t_max = 1.5 * params.h0 / params.evaporation if params.evaporation > 0 else 120.0
    n_max = int(math.ceil(t_max / dt - 1e-9))
    model = PlugFlow(params, FilmGrid(*grid, params.radius))
    s = model.initial_state(seed)
    times, apex, thinnest = [0.0], [s.h[0].mean() * 1e9], [s.h.min() * 1e9]
    t0, c0 = time.perf_counter(), time.process_time()
    for i in range(1, n_max + 1):
        s = model.step(s, dt)
        times.append(i * dt)
        apex.append(s.h[0].mean() * 1e9)
        thinnest.append(s.h.min() * 1e9)
        if apex[-1] < threshold_nm and thinnest[-1] < threshold_nm and times[-1] >= probe_s:
            break
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    t_end = times[-1]
    drained = apex[0] - np.array(apex) - params.evaporation * 1e9 * np.array(times)
    peak = int(np.argmax(drained))
    return BlackFilm(dt=float(dt), evaporation=float(params.evaporation), grid=tuple(grid),
                     threshold_nm=float(threshold_nm),
                     t_apex=first_crossing(times, apex, threshold_nm),
                     t_first=first_crossing(times, thinnest, threshold_nm), probe_s=float(probe_s),
                     apex_probe_nm=float(np.interp(probe_s, times, apex)) if probe_s <= t_end else float("nan"),
                     apex_start_nm=float(apex[0]), apex_end_nm=float(apex[-1]), t_end=float(t_end),
                     steps=len(times) - 1, wall=wall, cpu=cpu, drained_peak_nm=float(drained[peak]),
                     t_drained_peak=float(times[peak]))


def observed_orders(values):
    """The observed orders of convergence of a quantity computed at steps halving each time
    (*values* from the coarsest step to the finest): for each three consecutive values,
    :math:`p = \\log_2(|f(\\Delta t) - f(\\Delta t/2)| / |f(\\Delta t/2) - f(\\Delta t/4)|)`, one
    fewer than the differences (``nan`` where a difference is 0).  Positive when the
    differences shrink; 1 for a first-order method in its asymptotic range.

    >>> [round(p, 6) for p in observed_orders([1 + 0.1, 1 + 0.05, 1 + 0.025, 1 + 0.0125])]
    [1.0, 1.0]
    """
    import math

    f = [float(v) for v in values]
    if len(f) < 3:
        raise ValueError(f"need at least three values at halving steps (got {len(f)})")
    d = [abs(a - b) for a, b in zip(f, f[1:])]
    return [math.log2(a / b) if a > 0 and b > 0 else float("nan") for a, b in zip(d, d[1:])]


def richardson(coarse, fine, order):
    """Richardson's estimate of the step-size limit from the values at Δt (*coarse*) and Δt/2
    (*fine*) of a method of order *order* > 0: :math:`f + (f - f_{coarse})/(2^p - 1)`; ``nan``
    when the order is not positive (the values are then not in the asymptotic range).

    >>> richardson(1.1, 1.05, 1.0)
    1.0
    """
    import math

    if not (order > 0 and math.isfinite(order)):
        return float("nan")
    return fine + (fine - coarse) / (2.0 ** order - 1.0)
