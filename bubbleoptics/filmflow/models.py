"""The two film-flow models behind one interface: rigid-interface drainage and plug flow.

Both work in SI units on a :class:`~bubbleoptics.filmflow.FilmGrid` (θ from the top), keep the
film volume :math:`V = \\sum_{jk} A_j h_{jk}` exactly (finite volume, no flux through the
poles) apart from evaporation, and never make the thickness negative.  Common interface:
``initial_state(seed)``, ``step(state, dt)`` (a new :class:`FilmState`), ``run(t_end, dt,
save_every, seed, progress)`` (a :class:`~bubbleoptics.filmflow.ThicknessSeries` in nm).
See ``docs/film-flow.md`` for the derivations and their verification (convergence and conservation; no measured film yet).
"""

import math
import sys
from dataclasses import dataclass

import numba
import numpy as np

from . import _kernels as K
from .grid import FilmGrid
from .limits import MAX_STEPS, RUN_LIMITS, check_memory, check_number, kept_frames
from .parameters import GAS_CONSTANT, FilmParameters
from .series import ThicknessSeries

__all__ = ["FilmState", "RigidDrainage", "PlugFlow", "smooth_perturbation"]

#: the default grid of a model made without one
DEFAULT_GRID = (64, 128)
#: Courant number of the explicit rigid-drainage substeps (SSP-RK3 is monotone up to 1)
RIGID_CFL = 0.9
#: at most this many substeps in one rigid-drainage step (a step that needs more is refused)
MAX_SUBSTEPS = 100_000
#: rows of a block of the plug-flow φ sweep (transposed into buffers of (n_phi + 1) x ROW_BLOCK)
ROW_BLOCK = 8


@dataclass(frozen=True)
class FilmState:
    """The state of a film at one time (SI units; arrays are not shared between states).

    time : s.  h : (n_theta, n_phi) thickness in m.  gamma : (n_theta, n_phi) surfactant
    surface concentration in mol m⁻² (plug flow; ``None`` for rigid drainage).  v_theta :
    (n_theta + 1, n_phi) θ-face velocity in m s⁻¹ (+ = downwards, rows 0 and n_theta are the
    poles, always 0), v_phi : (n_theta, n_phi) φ-face velocity in m s⁻¹ (face k between
    columns k - 1 and k) (plug flow only).  evaporated : film volume evaporated since t = 0, m³.
    substeps : explicit substeps the last step took (rigid drainage), else 1.
    """

    time: float
    h: np.ndarray
    gamma: np.ndarray | None = None
    v_theta: np.ndarray | None = None
    v_phi: np.ndarray | None = None
    evaporated: float = 0.0
    substeps: int = 0


def smooth_perturbation(grid, seed, degree=4):
    """A smooth random field s on the cell centres, zero area mean, max |s| = 1: a random
    polynomial of degree <= *degree* in the Cartesian coordinates (x, y, z) of the unit sphere
    (so it is smooth through the poles), coefficients standard normal from
    ``numpy.random.default_rng(seed)``.  The same seed gives the same field on any machine.

    >>> g = FilmGrid(16, 32, 1.0)
    >>> s = smooth_perturbation(g, 7)
    >>> bool(abs(g.area_mean(s)) < 1e-15), float(np.abs(s).max())
    (True, 1.0)
    """
    seed = _check_seed(seed)
    rng = np.random.default_rng(seed)
    th = grid.theta[:, None]
    ph = grid.phi[None, :]
    x, y, z = np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th) * np.ones_like(ph)
    s = np.zeros((grid.n_theta, grid.n_phi))
    for a in range(degree + 1):
        for b in range(degree + 1 - a):
            for c in range(degree + 1 - a - b):
                if a + b + c:
                    s += rng.standard_normal() * x**a * y**b * z**c
    s -= grid.area_mean(s)
    return s / np.abs(s).max()


def _check_seed(seed):
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be an integer >= 0 (got {seed!r})")
    return int(seed)


def _finite(a):
    """True when every value of the float array *a* is finite: one pass, no temporary (a sum
    of finite film values cannot overflow, any NaN or infinity makes it non-finite)."""
    return bool(np.isfinite(np.sum(a)))


class _FilmModel:
    """What both models share: parameters, grid, input checks and the time loop."""

    name = "film"
    #: bytes of working arrays a model needs per cell (its scratch, a state and the next one)
    BYTES_PER_CELL = 8 * 8

    def __init__(self, params=None, grid=None):
        if params is None:
            params = FilmParameters()
        if not isinstance(params, FilmParameters):
            raise ValueError(f"params must be a FilmParameters (got {type(params).__name__})")
        if grid is None:
            grid = FilmGrid(*DEFAULT_GRID, params.radius)
        if not isinstance(grid, FilmGrid):
            raise ValueError(f"grid must be a FilmGrid (got {type(grid).__name__})")
        if grid.radius != params.radius:
            raise ValueError(f"grid.radius must equal params.radius = {params.radius} m (got {grid.radius})")
        cells = grid.n_theta * grid.n_phi
        check_memory(self.BYTES_PER_CELL * cells,
                     f"a {type(self).__name__} model of a {grid.n_theta} x {grid.n_phi} grid (its working arrays)")
        self.params = params
        self.grid = grid
        self.last_state = None  # the state at the end of the last run()
        sin_f = np.sin(grid.theta_faces)
        sin_f[0] = sin_f[-1] = 0.0
        self._sin_f = sin_f
        self._area = np.ascontiguousarray(grid.area)
        self._theta_len = np.ascontiguousarray(grid.theta_face_length)

    def __repr__(self):
        return f"{type(self).__name__}(grid {self.grid.n_theta}x{self.grid.n_phi}, R = {self.grid.radius} m)"

    def volume(self, state):
        """Film volume of *state* in m³ (exactly summed)."""
        return self.grid.volume(state.h)

    def _check_state(self, state):
        if not isinstance(state, FilmState):
            raise ValueError(f"state must be a FilmState (got {type(state).__name__})")
        if state.h.shape != (self.grid.n_theta, self.grid.n_phi):
            raise ValueError(f"state.h must have shape ({self.grid.n_theta}, {self.grid.n_phi}) (got {state.h.shape})")
        if not (_finite(state.h) and state.h.min() >= 0):
            raise ValueError("state.h must be finite and >= 0 (m)")

    def _check_dt(self, dt):
        return check_number("dt", dt, RUN_LIMITS)

    def _checked_result(self, state, dt):
        """*state* (the result of a step of *dt*) if every field of it is finite, else ValueError:
        a step never returns NaN or infinity."""
        fields = [f for f in (state.h, state.gamma, state.v_theta, state.v_phi) if f is not None]
        if not (all(_finite(f) for f in fields) and math.isfinite(state.evaporated)):
            raise ValueError(f"{self.name}: the film is no longer finite after a step of dt = {dt:g} s at t = "
                             f"{state.time:g} s (this dt or these parameters are beyond what the scheme resolves: "
                             "use a shorter dt)")
        return state

    def _initial_h(self, seed):
        p = self.params
        return p.h0 * (1.0 + p.perturbation * smooth_perturbation(self.grid, seed))

    def run(self, t_end, dt, save_every=1, seed=0, progress=False, state=None):
        """Simulate from ``initial_state(seed)`` (or *state*) for *t_end* seconds in steps of *dt*
        seconds, keeping the thickness every *save_every* steps (and at the start and the end).

        *t_end* must be a whole number of steps (to 1e-9 relative).  *progress*: ``True`` prints a
        line to stderr about every 10 %; a callable is called as ``progress(step, n_steps, state)``
        after every saved step.  Returns a :class:`ThicknessSeries` (h in nm); the state at the
        end is kept as ``self.last_state`` (pass it as *state* to go on).
        """
        t_end = check_number("t_end", t_end, RUN_LIMITS)
        dt = self._check_dt(dt)
        if isinstance(save_every, bool) or not isinstance(save_every, (int, np.integer)) or save_every < 1:
            raise ValueError(f"save_every must be an integer >= 1 (got {save_every!r})")
        ratio = t_end / dt  # finite: both are within RUN_LIMITS
        if ratio > MAX_STEPS + 0.5:
            raise ValueError(f"t_end / dt = {ratio:.4g} steps, more than the {MAX_STEPS:,} a run may take "
                             f"(t_end = {t_end:g} s, dt = {dt:g} s): use a longer dt or a shorter t_end")
        n_steps = int(round(ratio))
        if n_steps < 1 or abs(n_steps * dt - t_end) > 1e-9 * t_end:
            raise ValueError(f"t_end must be a whole number >= 1 of steps dt = {dt:g} s (got t_end = {t_end:g} s)")
        save_every = int(save_every)
        n_kept = kept_frames(n_steps, save_every)
        nt, nph = self.grid.n_theta, self.grid.n_phi
        check_memory(n_kept * (nt * nph * 4 + 8), f"run() keeping {n_kept:,} frames of {nt} x {nph} (float32; "
                                                  f"a larger save_every keeps fewer)")
        if state is None:
            state = self.initial_state(seed)
        else:
            _check_seed(seed)
            self._check_state(state)
        t0 = state.time
        h_nm = np.empty((n_kept, nt, nph), dtype=np.float32)  # filled in place: no list, no copy
        times = np.empty(n_kept)
        np.multiply(state.h, 1e9, out=h_nm[0], casting="same_kind")
        times[0] = t0
        kept = 1
        tick = max(1, n_steps // 10)
        for i in range(1, n_steps + 1):
            state = self.step(state, dt)
            if i % save_every == 0 or i == n_steps:
                np.multiply(state.h, 1e9, out=h_nm[kept], casting="same_kind")
                times[kept] = t0 + i * dt
                kept += 1
                if callable(progress):
                    progress(i, n_steps, state)
            if progress is True and (i % tick == 0 or i == n_steps):
                print(f"{self.name}: step {i}/{n_steps}, t = {t0 + i * dt:.4g} s, "
                      f"min h = {state.h.min() * 1e9:.1f} nm", file=sys.stderr)
        self.last_state = state
        parameters = dict(self.params.to_dict(), dt=dt, seed=int(seed), n_steps=n_steps, save_every=save_every,
                          grid=self.grid.to_dict())
        return ThicknessSeries(h_nm, times, self.grid, parameters, self.name)


class RigidDrainage(_FilmModel):
    """Drainage of a film between two immobile (no-slip, rigid) interfaces, with evaporation.

    .. math::  \\frac{\\partial h}{\\partial t} + \\nabla_s\\cdot\\Big(\\frac{\\rho\\,\\mathbf g_t\\,h^3}{12\\mu}\\Big)
               = -E,\\qquad \\mathbf g_t = g\\sin\\theta\\,\\mathbf e_\\theta ,

    the lubrication (Poiseuille) flux of a film of thickness h between no-slip surfaces
    [SchwartzRoy1999], driven by the tangential gravity only (no capillary or disjoining
    pressure, so columns of different φ do not exchange liquid).  On the sphere of radius R the
    divergence is :math:`(R\\sin\\theta)^{-1}\\partial_\\theta(\\sin\\theta\\,q_\\theta)`.

    At the top the film thins as :math:`dh/dt = -2Kh^3/R` (:math:`K = \\rho g/12\\mu`, E = 0), so

    .. math::  h_{apex}(t) = h_0\\,(1 + t/\\tau)^{-1/2},\\qquad \\tau = \\frac{3\\mu R}{\\rho g h_0^2}

    (derived here; the :math:`t^{-1/2}` apex law of immobile-film drainage, cf. [SchwartzRoy1999]);
    ``params.drainage_time`` is τ (≈ 3100 s for the defaults: rigid interfaces drain slowly).

    Discretisation: finite volume, first-order upwind face flux
    :math:`\\ell_i K\\sin\\theta_i h_{i-1}^3` (zero on the poles), SSP-RK3 substeps (Shu & Osher
    1988) of Courant number <= 0.9 chosen automatically inside each step, evaporation
    :math:`h \\leftarrow \\max(h - E\\,\\Delta t_{sub}, 0)` after each substep.  Volume is exact to
    rounding; the top cell obeys the apex law with rate factor :math:`(1 + \\cos\\Delta\\theta)/2`.

    >>> from bubbleoptics.filmflow import FilmParameters, FilmGrid, RigidDrainage
    >>> p = FilmParameters(perturbation=0.0, evaporation=0.0)
    >>> m = RigidDrainage(p, FilmGrid(64, 4, p.radius))
    >>> s = m.step(m.initial_state(seed=0), p.drainage_time)
    >>> round(float(s.h[0, 0] / p.h0), 3), round(2 ** -0.5, 3)  # apex after t = tau
    (0.707, 0.707)
    """

    name = "rigid_drainage"

    def __init__(self, params=None, grid=None):
        super().__init__(params, grid)
        p = self.params
        self._k_lub = p.density * p.gravity / (12.0 * p.viscosity)

    def initial_state(self, seed=0):
        """h = h0 (1 + ε s), s = :func:`smooth_perturbation` (grid, seed), ε = params.perturbation."""
        return FilmState(time=0.0, h=self._initial_h(seed))

    def step(self, state, dt):
        """Advance *state* by *dt* s (any dt > 0; explicit substeps keep it stable)."""
        self._check_state(state)
        dt = self._check_dt(dt)
        h = np.array(state.h, dtype=float, order="C")
        nph = self.grid.n_phi
        substeps = np.empty(nph, dtype=np.int64)
        evaporated = np.empty(nph)
        K.rigid_step_nb(h, dt, self._area, self._theta_len, self._sin_f, self._k_lub, self.params.evaporation,
                        RIGID_CFL, MAX_SUBSTEPS, substeps, evaporated)
        if substeps.min() < 0:
            raise ValueError(f"dt = {dt:g} s is too long for this state: it needs more than {MAX_SUBSTEPS} explicit "
                             f"substeps; use a shorter dt")
        return self._checked_result(FilmState(time=state.time + dt, h=h, evaporated=state.evaporated
                                              + math.fsum(evaporated), substeps=int(substeps.max())), dt)


class PlugFlow(_FilmModel):
    """Huang-style plug flow: thickness, surfactant and tangential velocity, with Marangoni
    force, gravity, air drag and evaporation ([Huang2020], simplified as stated here).

    .. math::

        \\rho h\\,\\partial_t\\mathbf u = -2R_gT\\,\\nabla_s\\Gamma + \\rho h\\,\\mathbf g_t - C_a\\mathbf u,\\qquad
        \\partial_t h + \\nabla_s\\cdot(h\\mathbf u) = -E,\\qquad
        \\partial_t\\Gamma + \\nabla_s\\cdot(\\Gamma\\mathbf u) = 0,

    u the depth-uniform (plug) velocity, Γ the insoluble surfactant per surface (both surfaces
    carry the Marangoni stress :math:`\\nabla\\sigma = -R_gT\\nabla\\Gamma` of the equation of state
    σ = σ_w - R_g T Γ), :math:`C_a` the air drag on both sides, E the evaporation (water leaves,
    surfactant stays).  Left out compared with [Huang2020]: the advection of u by itself
    (:math:`\\mathbf u\\cdot\\nabla\\mathbf u`), viscosity and van der Waals forces (off in their
    release too), and the external air flow.

    Equilibrium: with u = 0 and Γ/h = Γ0/h0 uniform (it stays so while E = 0: both are carried
    by the same flux), :math:`2R_gT(\\Gamma_0/h_0)\\nabla h = \\rho h\\,\\mathbf g_t` gives

    .. math::  h_{eq}(\\theta) = h_0\\,\\frac{a}{\\sinh a}\\,e^{-a\\cos\\theta},\\qquad a = \\frac{\\rho g R h_0}{2R_gT\\Gamma_0},

    normalised to the same volume :math:`4\\pi R^2 h_0` (thicker at the bottom, θ = π).

    Discretisation: finite volume on the staggered grid, Lie splitting into a θ and a φ sweep
    per step; in each, a tridiagonal solve per line (Thomas; cyclic in φ by Sherman-Morrison)
    for the surfactant with the Marangoni force and the drag implicit (so no CFL limit from the
    fast Marangoni (Gibbs) waves, which is what makes 5 ms steps possible near the poles), then
    implicit first-order upwind transport of h and Γ (positive for any dt, exactly
    conservative).  First order in time and in space for transport; the equilibrium balance is
    second order (measured: see ``docs/film-flow.md``).  A PlugFlow object owns the scratch
    arrays of its sweeps: step one model from one thread at a time (make one model a thread).

    >>> from bubbleoptics.filmflow import FilmParameters, FilmGrid, PlugFlow
    >>> p = FilmParameters(evaporation=0.0)
    >>> m = PlugFlow(p, FilmGrid(8, 16, p.radius))
    >>> s0 = m.initial_state(seed=1)
    >>> s = s0
    >>> for _ in range(20):
    ...     s = m.step(s, 0.005)
    >>> bool(abs(m.volume(s) / m.volume(s0) - 1) < 1e-12), bool(s.h.min() > 0)
    (True, True)
    """

    name = "plug_flow"
    #: its θ-sweep geometry (4) and scratch (N_SCRATCH) per face, the φ-sweep geometry (4), and
    #: two states of four fields
    BYTES_PER_CELL = 8 * (4 + K.N_SCRATCH + 4 + 8)

    def __init__(self, params=None, grid=None):
        super().__init__(params, grid)
        g, p = self.grid, self.params
        nt, nph = g.n_theta, g.n_phi
        # per-face geometry of the θ sweep as (n_theta + 1, n_phi) arrays
        self._theta_geometry = (
            np.repeat(g.area[:, None], nph, axis=1),
            np.repeat(g.theta_face_length[:, None], nph, axis=1),
            np.full((nt + 1, nph), g.theta_spacing),
            np.repeat((p.gravity * self._sin_f)[:, None], nph, axis=1),
        )
        # the φ sweep takes the rows ROW_BLOCK at a time (transposed into cache-sized buffers)
        blocks = -(-nt // ROW_BLOCK)
        rows = np.minimum(np.arange(blocks * ROW_BLOCK), nt - 1).reshape(blocks, ROW_BLOCK)
        self._phi_geometry = np.empty((blocks, 4, nph + 1, ROW_BLOCK))
        self._phi_geometry[:, 0] = g.area[rows][:, None, :]
        self._phi_geometry[:, 1] = g.phi_face_length
        self._phi_geometry[:, 2] = g.phi_spacing[rows][:, None, :]
        self._phi_geometry[:, 3] = 0.0
        self._scratch_theta = np.empty((K.N_SCRATCH, nt + 1, nph))
        self._two_rt = 2.0 * GAS_CONSTANT * p.temperature
        self._chunks = max(1, min(numba.get_num_threads(), nph // 16))
        phi_chunks = max(1, min(numba.get_num_threads(), blocks))
        self._scratch_phi = np.empty((phi_chunks, K.N_SCRATCH, nph + 1, ROW_BLOCK))
        self._buffers_phi = np.empty((phi_chunks, 3, nph + 1, ROW_BLOCK))

    def initial_state(self, seed=0):
        """h = h0 (1 + ε s1), Γ = Γ0 (h/h0)(1 + ε s2), u = 0; s1, s2 = :func:`smooth_perturbation`
        with seeds derived from *seed* (so Γ/h is perturbed independently of h)."""
        seed = _check_seed(seed)
        p, g = self.params, self.grid
        h = self._initial_h(seed)
        ratio = 1.0 + p.perturbation * smooth_perturbation(g, seed + 2**31)
        gamma = p.surfactant * (h / p.h0) * ratio
        return FilmState(time=0.0, h=h, gamma=gamma, v_theta=np.zeros((g.n_theta + 1, g.n_phi)),
                         v_phi=np.zeros((g.n_theta, g.n_phi)))

    def _check_state(self, state):
        super()._check_state(state)
        if state.gamma is None or state.v_theta is None or state.v_phi is None:
            raise ValueError("state must carry gamma, v_theta and v_phi (a PlugFlow state)")

    def surfactant(self, state):
        """Total surfactant :math:`\\sum A_j\\Gamma_{jk}` in mol (per surface), exactly summed."""
        return self.grid.volume(state.gamma)

    def step(self, state, dt):
        """Advance *state* by *dt* s: θ sweep, φ sweep, evaporation (implicit: any dt > 0 is stable)."""
        self._check_state(state)
        dt = self._check_dt(dt)
        p = self.params
        h = np.array(state.h, dtype=float, order="C")
        gam = np.array(state.gamma, dtype=float, order="C")
        v = np.array(state.v_theta, dtype=float, order="C")
        K.plug_sweep_nb(h, gam, v, dt, *self._theta_geometry, p.density, p.drag, self._two_rt,
                        self._scratch_theta, False, self._chunks)
        w = np.array(state.v_phi, dtype=float, order="C")
        K.plug_rows_sweep_nb(h, gam, w, dt, self._phi_geometry, p.density, p.drag, self._two_rt, self._scratch_phi,
                             self._buffers_phi, ROW_BLOCK)
        evaporated = K.evaporate_nb(h, p.evaporation * dt, self._area)
        return self._checked_result(FilmState(time=state.time + dt, h=h, gamma=gam, v_theta=v, v_phi=w,
                                              evaporated=state.evaporated + evaporated, substeps=1), dt)
