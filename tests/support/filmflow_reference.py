"""Slow, literal implementations of one film-flow step, to check the numba kernels against.

Written from the equations in the docstrings of :mod:`bubbleoptics.filmflow.models` (not from
the kernels): whole-grid NumPy for rigid drainage, and for plug flow one scipy sparse matrix
per sweep, assembled entry by entry from the face fluxes and solved by ``spsolve``.
"""

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

from bubbleoptics.filmflow.parameters import GAS_CONSTANT


def _geometry(grid):
    R = grid.radius
    dth, dph = np.pi / grid.n_theta, 2 * np.pi / grid.n_phi
    tf = np.arange(grid.n_theta + 1) * dth
    sin_f = np.sin(tf)
    sin_f[0] = sin_f[-1] = 0.0
    area = R**2 * dph * (np.cos(tf[:-1]) - np.cos(tf[1:]))
    return R, dth, dph, sin_f, area


def rigid_euler_rate(grid, params, h):
    """dh/dt of rigid drainage: upwind flux l K sin(theta_f) h_above^3 through each theta face."""
    R, dth, dph, sin_f, area = _geometry(grid)
    k = params.density * params.gravity / (12 * params.viscosity)
    flux = np.zeros((grid.n_theta + 1, grid.n_phi))
    flux[1:-1] = (R * sin_f[1:-1] * dph * k * sin_f[1:-1])[:, None] * h[:-1] ** 3
    return (flux[:-1] - flux[1:]) / area[:, None]


def rigid_step(grid, params, h, dt):
    """One SSP-RK3 step of size dt (no substeps), then evaporation E dt clamped at 0."""
    L = lambda y: rigid_euler_rate(grid, params, y)  # noqa: E731
    h1 = h + dt * L(h)
    h2 = 0.75 * h + 0.25 * (h1 + dt * L(h1))
    h3 = h / 3 + 2 / 3 * (h2 + dt * L(h2))
    return np.maximum(h3 - params.evaporation * dt, 0.0)


def _plug_sweep(h, G, vel, faces, area, dt, rho, drag, two_rt):
    """One implicit sweep over all lines at once with sparse matrices.

    *faces*: list of (lower cell, upper cell, face length, centre distance, tangential gravity,
    face-velocity index) over every open face; flux through a face counts from the lower to
    the upper cell.  *vel* is the flat face-velocity array (updated copy returned)."""
    n = h.size
    vel = vel.copy()
    rows, cols, vals = [], [], []
    rhs = area * G
    vstar, beta = {}, {}
    for lo, hi, ell, d, gt, iv in faces:
        hf = 0.5 * (h[lo] + h[hi])
        gf = 0.5 * (G[lo] + G[hi])
        # rho hf (v' - v) = dt (rho hf gt - two_rt (G'_hi - G'_lo)/d - drag v')
        vs = rho * hf * (vel[iv] + dt * gt) / (rho * hf + drag * dt)
        bt = dt * two_rt / (d * (rho * hf + drag * dt))
        vstar[iv], beta[iv] = vs, bt
        # area (G'-G) = -dt * sum of outgoing l gf v'
        cf = dt * ell * gf
        rhs[lo] -= cf * vs
        rhs[hi] += cf * vs
        for cell, sign in ((lo, 1.0), (hi, -1.0)):  # + outflow from lo, inflow to hi
            rows += [cell, cell]
            cols += [hi, lo]
            vals += [-sign * cf * bt, sign * cf * bt]
    rows += list(range(n))
    cols += list(range(n))
    vals += list(area)
    A = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
    Gp = spsolve(A.tocsc(), rhs)
    for lo, hi, ell, d, gt, iv in faces:
        vel[iv] = vstar[iv] - beta[iv] * (Gp[hi] - Gp[lo])
    rows, cols, vals = list(range(n)), list(range(n)), list(area)
    for lo, hi, ell, d, gt, iv in faces:
        f = dt * ell * vel[iv]  # volume per thickness moved from lo to hi
        up = lo if f > 0 else hi
        # cell lo loses f h'_up, cell hi gains it
        rows += [lo, hi]
        cols += [up, up]
        vals += [f, -f]
    T = sp.csr_matrix((vals, (rows, cols)), shape=(n, n)).tocsc()
    return spsolve(T, area * h), spsolve(T, area * G), vel


def plug_step(grid, params, state, dt):
    """One plug-flow step: theta sweep, phi sweep, evaporation; returns (h, G, v_theta, v_phi)."""
    R, dth, dph, sin_f, area = _geometry(grid)
    nt, nph = grid.n_theta, grid.n_phi
    idx = np.arange(nt * nph).reshape(nt, nph)
    a = np.repeat(area, nph)
    rho, drag, two_rt = params.density, params.drag, 2 * GAS_CONSTANT * params.temperature
    h, G = state.h.ravel().copy(), state.gamma.ravel().copy()
    vt = state.v_theta.ravel().copy()
    faces = [(idx[i - 1, k], idx[i, k], R * sin_f[i] * dph, R * dth, params.gravity * sin_f[i], i * nph + k)
             for i in range(1, nt) for k in range(nph)]
    h, G, vt = _plug_sweep(h, G, vt, faces, a, dt, rho, drag, two_rt)
    vp = state.v_phi.ravel().copy()
    faces = [(idx[j, k - 1], idx[j, k], R * dth, R * np.sin((j + 0.5) * dth) * dph, 0.0, j * nph + k)
             for j in range(nt) for k in range(nph)]
    h, G, vp = _plug_sweep(h, G, vp, faces, a, dt, rho, drag, two_rt)
    h = np.maximum(h - params.evaporation * dt, 0.0)
    return h.reshape(nt, nph), G.reshape(nt, nph), vt.reshape(nt + 1, nph), vp.reshape(nt, nph)
