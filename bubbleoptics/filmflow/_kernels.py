"""Numba kernels of the film-flow models (names end in ``_nb``); the models in
:mod:`bubbleoptics.filmflow.models` call them with plain arrays and floats, SI units.

Layout: cell fields are ``(n_theta, n_phi)`` C arrays; the θ-face velocity is
``(n_theta + 1, n_phi)`` (row i on the face between cells i - 1 and i; rows 0 and n_theta are
the poles and stay 0).  The plug-flow sweeps work along axis 0 of (n, lines) arrays with the
lines innermost: the θ sweep (:func:`plug_sweep_nb`) on the arrays as stored, the φ sweep
(:func:`plug_rows_sweep_nb`) on blocks of rows transposed into buffers, their face velocity
(n_phi + 1, rows) with face 0 (between columns n_phi - 1 and 0) repeated as row n_phi.  Every update is in finite-volume form, a difference of face fluxes, so
:math:`\\sum_j A_j h_j` changes only by rounding (and by evaporation).
"""

import numpy as np
from numba import njit, prange
from ..jit import JIT, JIT_INLINE, JIT_PARALLEL

__all__ = [
    "rigid_rate_nb",
    "rigid_step_nb",
    "evaporate_line_nb",
    "evaporate_nb",
    "plug_sweep_nb",
    "plug_rows_sweep_nb",
]


#: scratch arrays of a plug-flow sweep (each (n + 1, lines))
N_SCRATCH = 11


@njit(**JIT)
def rigid_rate_nb(h, area, face_len, sin_f, k_lub, out):
    """:math:`\\partial h/\\partial t` of rigid-interface drainage on one θ column, first-order
    upwind finite volume.

    Face flux (volume per time through a θ face): :math:`F_{i} = \\ell_i\\,K\\sin\\theta_i\\,h_{i-1}^3`,
    :math:`K = \\rho g/(12\\mu)` (*k_lub*, m⁻¹ s⁻¹), upwind because gravity drains towards +θ
    (down); :math:`F = 0` on the poles.  ``out[j] = (F_j - F_{j+1}) / A_j``.  Returns the largest
    :math:`\\partial F_{j+1}/\\partial h_j / A_j` (s⁻¹): forward Euler (and SSP-RK3) with these
    fluxes is monotone and keeps h >= 0 for dt x that <= 1.
    """
    nt = h.shape[0]
    top = 0.0
    fastest = 0.0
    for j in range(nt):
        c = face_len[j + 1] * k_lub * sin_f[j + 1]
        bottom = c * h[j] ** 3
        out[j] = (top - bottom) / area[j]
        top = bottom
        r = 3.0 * c * h[j] ** 2 / area[j]
        if r > fastest:
            fastest = r
    return fastest


@njit(**JIT)
def evaporate_line_nb(h, depth, area):
    """Thin the cells of one line by *depth* (m, = E dt), never below 0, in place; return the
    volume removed (m³, exactly what left the cells: less than depth x area where one runs dry).
    *area* is per cell of the line."""
    s = 0.0
    if depth == 0.0:
        return s
    for j in range(h.shape[0]):
        old = h[j]
        new = old - depth
        if new < 0.0:
            new = 0.0
        h[j] = new
        s += area[j] * (old - new)
    return s


@njit(**JIT_PARALLEL)
def evaporate_nb(h, depth, area):
    """:func:`evaporate_line_nb` on every row of *h* (n_theta, n_phi), row j of area area[j];
    returns the volume removed (m³)."""
    nt = h.shape[0]
    row = np.zeros(nt)
    if depth == 0.0:
        return 0.0
    for j in prange(nt):
        s = 0.0
        for k in range(h.shape[1]):
            old = h[j, k]
            new = max(old - depth, 0.0)
            h[j, k] = new
            s += old - new
        row[j] = s * area[j]
    return row.sum()


@njit(**JIT_PARALLEL)
def rigid_step_nb(h, dt, area, face_len, sin_f, k_lub, evaporation, cfl, max_substeps, substeps, evaporated):
    """Advance rigid-interface drainage by *dt* seconds, in place, each θ column on its own (the
    columns do not exchange liquid): SSP-RK3 (Shu & Osher 1988) substeps of at most
    ``cfl / max rate`` each (recomputed every substep), each followed by evaporation
    ``E dt_sub``.  Writes per column the substeps taken into *substeps* (-1 if more than
    *max_substeps* were needed; the column is then partly advanced) and the evaporated volume
    (m³) into *evaporated*."""
    nt, nph = h.shape
    for k in prange(nph):
        y = h[:, k].copy()
        rate = np.empty(nt)
        y1 = np.empty(nt)
        y2 = np.empty(nt)
        done = 0.0
        n = 0
        ev = 0.0
        while done < dt:
            if n >= max_substeps:
                n = -1
                break
            r = rigid_rate_nb(y, area, face_len, sin_f, k_lub, rate)
            step = dt - done
            last = True
            if r * step > cfl:
                step = cfl / r
                last = done + step >= dt
                if last:  # rounding: never leave a sliver of a step
                    step = dt - done
            for j in range(nt):
                y1[j] = y[j] + step * rate[j]
            rigid_rate_nb(y1, area, face_len, sin_f, k_lub, rate)
            for j in range(nt):
                y2[j] = 0.75 * y[j] + 0.25 * (y1[j] + step * rate[j])
            rigid_rate_nb(y2, area, face_len, sin_f, k_lub, rate)
            for j in range(nt):
                y[j] = y[j] / 3.0 + 2.0 / 3.0 * (y2[j] + step * rate[j])
            ev += evaporate_line_nb(y, evaporation * step, area)
            done = dt if last else done + step
            n += 1
        h[:, k] = y
        substeps[k] = n
        evaporated[k] = ev


@njit(**JIT_INLINE)
def _eliminate_nb(j, k, n, a, b, c, d1, d2, CP, DP, DP2, DZ, EDGE, cyclic):
    """Forward elimination (Thomas) of row j of line k: a x_{j-1} + b x_j + c x_{j+1} = d1 (and
    = d2, a second right-hand side).  Periodic lines (row 0 coupled to x_{n-1} by its a, row
    n-1 to x_0 by its c) use Sherman-Morrison: the matrix is B' + u vᵀ with γ = -b_0,
    u = (γ, 0, ..., c_{n-1}), v = (1, 0, ..., a_0/γ), B' tridiagonal with b'_0 = b_0 - γ,
    b'_{n-1} = b_{n-1} - a_0 c_{n-1}/γ; B' z = u is eliminated alongside (DZ); γ and a_0 are
    kept in EDGE[0, k], EDGE[1, k]."""
    if cyclic:
        if j == 0:
            EDGE[0, k] = -b
            EDGE[1, k] = a
            b = b + b
        elif j == n - 1:
            b -= EDGE[1, k] * c / EDGE[0, k]
    if j == 0:
        w = 1.0 / b
        DP[0, k] = d1 * w
        DP2[0, k] = d2 * w
        if cyclic:
            DZ[0, k] = EDGE[0, k] * w
    else:
        w = 1.0 / (b - a * CP[j - 1, k])
        DP[j, k] = (d1 - a * DP[j - 1, k]) * w
        DP2[j, k] = (d2 - a * DP2[j - 1, k]) * w
        if cyclic:
            u = c if j == n - 1 else 0.0
            DZ[j, k] = (u - a * DZ[j - 1, k]) * w
    CP[j, k] = c * w


@njit(**JIT_INLINE)
def _back_nb(n, k0, k1, CP, DP, X):
    """X[j] = DP[j] - CP[j] X[j+1] from the last row up (X may be DP)."""
    for k in range(k0, k1):
        X[n - 1, k] = DP[n - 1, k]
    for j in range(n - 2, -1, -1):
        for k in range(k0, k1):
            X[j, k] = DP[j, k] - CP[j, k] * X[j + 1, k]


@njit(**JIT_INLINE)
def _correct_nb(n, k0, k1, X, DZ, EDGE):
    """Sherman-Morrison: X -= f z, f = (X_0 + r X_{n-1}) / (1 + z_0 + r z_{n-1}), r = a_0/γ
    (EDGE[1] / EDGE[0]); f is kept in EDGE[2]."""
    for k in range(k0, k1):
        r = EDGE[1, k] / EDGE[0, k]
        EDGE[2, k] = (X[0, k] + r * X[n - 1, k]) / (1.0 + DZ[0, k] + r * DZ[n - 1, k])
    for j in range(n):
        for k in range(k0, k1):
            X[j, k] -= EDGE[2, k] * DZ[j, k]


@njit(**JIT_INLINE)
def _back_substitute_nb(n, k0, k1, CP, DP, DP2, DZ, EDGE, X, X2, cyclic, two):
    """Back substitution after :func:`_eliminate_nb` on every row: the solution into X (and,
    if *two*, the second one into X2; either may be its DP), with the Sherman-Morrison
    correction for periodic lines (EDGE's rows 0, 1 hold γ and a_0 until then)."""
    _back_nb(n, k0, k1, CP, DP, X)
    if two:
        _back_nb(n, k0, k1, CP, DP2, X2)
    if cyclic:
        _back_nb(n, k0, k1, CP, DZ, DZ)
        _correct_nb(n, k0, k1, X, DZ, EDGE)
        if two:
            _correct_nb(n, k0, k1, X2, DZ, EDGE)


@njit(**JIT_INLINE)
def _marangoni_face_nb(i, lo, k, h, G, v, face_len, dist, gforce, dt, rho, drag, two_rt, VS, BE, CC, Q):
    """Face i (between cells lo and i) of step 1 of :func:`_plug_lines_nb`: v' = VS - BE ΔΓ';
    CC and Q the face's terms in the surfactant system."""
    hf = 0.5 * (h[lo, k] + h[i, k])
    gf = 0.5 * (G[lo, k] + G[i, k])
    inv = 1.0 / (rho * hf + drag * dt)
    vs = rho * hf * (v[i, k] + dt * gforce[i, k]) * inv
    be = dt * two_rt * inv / dist[i, k]
    t = dt * face_len[i, k] * gf
    VS[i, k] = vs
    BE[i, k] = be
    CC[i, k] = t * be
    Q[i, k] = t * vs


@njit(**JIT)
def _plug_lines_nb(h, G, v, n, k0, k1, area, face_len, dist, gforce, dt, rho, drag, two_rt, s, cyclic):
    """One implicit plug-flow update of lines k0..k1-1 (in place).

    Line k is column k of *h*, *G* (n cells) and of *v* (n + 1 face velocities, face i between
    cells i - 1 and i; for periodic lines face n is face 0 and both rows hold its value);
    *area* (n, m), and per face *face_len*, *dist* (centre spacing), *gforce* (tangential
    gravity, m s⁻²), all (n + 1, m); non-periodic lines are closed at both ends (faces 0 and n
    carry nothing).  *s*: scratch (N_SCRATCH, n + 1, m).  Innermost loops run over the lines.

    1. Momentum with the Marangoni force and the drag implicit, gravity explicit:
       :math:`\\rho h_f(v' - v) = \\Delta t[\\rho h_f g_t - 2R_gT(\\Gamma'_i - \\Gamma'_{i-1})/d - C_a v']`,
       :math:`h_f` the face mean; with surfactant continuity
       :math:`A_j(\\Gamma'_j - \\Gamma_j) = -\\Delta t(\\ell\\Gamma_f v')|^{j+1}_{j}` it gives one
       symmetric, diagonally dominant tridiagonal system for Γ' per line (the 1-D form of the
       system [Huang2020] solve in 2-D); it fixes v'.
    2. Transport of h and Γ by v', implicit first-order upwind: an M-matrix, so h, Γ stay >= 0
       for any dt, and exactly conservative.  Γ' of step 1 is only used to find v'.
    Each is one forward sweep (building and eliminating the rows) and one backward sweep.
    """
    VS, BE, CC, Q, CP, DP, DP2, DZ, X, EDGE, W = s[0], s[1], s[2], s[3], s[4], s[5], s[6], s[7], s[8], s[9], s[10]
    # step 1: faces, rows and elimination in one sweep down the lines
    for k in range(k0, k1):
        if cyclic:
            _marangoni_face_nb(0, n - 1, k, h, G, v, face_len, dist, gforce, dt, rho, drag, two_rt, VS, BE, CC, Q)
            VS[n, k], BE[n, k], CC[n, k], Q[n, k] = VS[0, k], BE[0, k], CC[0, k], Q[0, k]
        else:
            VS[0, k] = BE[0, k] = CC[0, k] = Q[0, k] = 0.0
            VS[n, k] = BE[n, k] = CC[n, k] = Q[n, k] = 0.0
    for j in range(n):
        if j + 1 < n:
            for k in range(k0, k1):
                _marangoni_face_nb(j + 1, j, k, h, G, v, face_len, dist, gforce, dt, rho, drag, two_rt,
                                   VS, BE, CC, Q)
        if j == 0 or j == n - 1:
            for k in range(k0, k1):
                b = area[j, k] + CC[j, k] + CC[j + 1, k]
                d = area[j, k] * G[j, k] - (Q[j + 1, k] - Q[j, k])
                _eliminate_nb(j, k, n, -CC[j, k], b, -CC[j + 1, k], d, 0.0, CP, DP, DP2, DZ, EDGE, cyclic)
        else:  # the interior rows without branches (a = -CC_j, c = -CC_{j+1}); W keeps the pivots
            for k in range(k0, k1):
                w = 1.0 / (area[j, k] + CC[j, k] + CC[j + 1, k] + CC[j, k] * CP[j - 1, k])
                W[j, k] = w
                CP[j, k] = -CC[j + 1, k] * w
                DP[j, k] = (area[j, k] * G[j, k] - (Q[j + 1, k] - Q[j, k]) + CC[j, k] * DP[j - 1, k]) * w
            if cyclic:
                for k in range(k0, k1):
                    DZ[j, k] = CC[j, k] * DZ[j - 1, k] * W[j, k]
    _back_substitute_nb(n, k0, k1, CP, DP, DP2, DZ, EDGE, X, DP2, cyclic, False)
    # the new face velocities, and the upwind weights CC = max(f, 0), Q = max(-f, 0), f = dt l v'
    first = 0 if cyclic else 1
    for i in range(first, n):
        lo = i - 1 if i > 0 else n - 1
        for k in range(k0, k1):
            vi = VS[i, k] - BE[i, k] * (X[i, k] - X[lo, k])
            v[i, k] = vi
            f = dt * face_len[i, k] * vi
            CC[i, k] = max(f, 0.0)
            Q[i, k] = max(-f, 0.0)
    for k in range(k0, k1):
        if cyclic:
            v[n, k], CC[n, k], Q[n, k] = v[0, k], CC[0, k], Q[0, k]
        else:
            v[0, k] = v[n, k] = CC[0, k] = Q[0, k] = CC[n, k] = Q[n, k] = 0.0
    # step 2: transport of h and Γ with the same matrix (a = -CC_j, c = -Q_{j+1})
    for j in range(n):
        if j == 0 or j == n - 1:
            for k in range(k0, k1):
                b = area[j, k] + CC[j + 1, k] + Q[j, k]
                _eliminate_nb(j, k, n, -CC[j, k], b, -Q[j + 1, k], area[j, k] * h[j, k], area[j, k] * G[j, k],
                              CP, DP, DP2, DZ, EDGE, cyclic)
        else:
            for k in range(k0, k1):
                w = 1.0 / (area[j, k] + CC[j + 1, k] + Q[j, k] + CC[j, k] * CP[j - 1, k])
                W[j, k] = w
                CP[j, k] = -Q[j + 1, k] * w
                DP[j, k] = (area[j, k] * h[j, k] + CC[j, k] * DP[j - 1, k]) * w
                DP2[j, k] = (area[j, k] * G[j, k] + CC[j, k] * DP2[j - 1, k]) * w
            if cyclic:
                for k in range(k0, k1):
                    DZ[j, k] = CC[j, k] * DZ[j - 1, k] * W[j, k]
    _back_substitute_nb(n, k0, k1, CP, DP, DP2, DZ, EDGE, h, G, cyclic, True)


@njit(**JIT_PARALLEL)
def plug_sweep_nb(h, G, v, dt, area, face_len, dist, gforce, rho, drag, two_rt, scratch, cyclic, chunks):
    """One plug-flow half-step along axis 0 of *h*, *G* (n, m), for all m lines at once
    (:func:`_plug_lines_nb`), the lines split into *chunks* blocks run in parallel.
    The θ sweep runs on the arrays as stored (``cyclic=False``); periodic lines (``cyclic=True``)
    need their face velocity (n + 1, m) with row n a copy of row 0."""
    n, m = h.shape
    size = (m + chunks - 1) // chunks
    for c in prange(chunks):
        k0 = c * size
        k1 = min(m, k0 + size)
        if k0 < k1:
            _plug_lines_nb(h, G, v, n, k0, k1, area, face_len, dist, gforce, dt, rho, drag, two_rt, scratch, cyclic)


@njit(**JIT_PARALLEL)
def plug_rows_sweep_nb(h, G, w, dt, geometry, rho, drag, two_rt, scratch, buffers, block):
    """The φ half-step of plug flow on the rows of *h*, *G* (n_theta, n_phi), periodic, in place.

    The rows are taken *block* at a time, transposed into small buffers (n_phi + 1, block) so
    that :func:`_plug_lines_nb` runs with its lines innermost and in cache, and transposed
    back.  *w*: φ-face velocity (n_theta, n_phi), face k between columns k - 1 and k;
    *geometry*: (n_blocks, 4, n_phi + 1, block) area, face length, centre spacing, tangential
    gravity (0) of each block's rows; *scratch*: (n_chunks, N_SCRATCH, n_phi + 1, block);
    *buffers*: (n_chunks, 3, n_phi + 1, block).  The blocks are shared out over n_chunks
    parallel chunks.
    """
    nt, nph = h.shape
    nblocks = geometry.shape[0]
    chunks = scratch.shape[0]
    per = (nblocks + chunks - 1) // chunks
    for c in prange(chunks):
        s = scratch[c]
        hb, gb, wb = buffers[c, 0], buffers[c, 1], buffers[c, 2]
        for b in range(c * per, min(nblocks, (c + 1) * per)):
            j0 = b * block
            m = min(block, nt - j0)
            for l in range(m):
                for k in range(nph):
                    hb[k, l] = h[j0 + l, k]
                    gb[k, l] = G[j0 + l, k]
                    wb[k, l] = w[j0 + l, k]
                wb[nph, l] = w[j0 + l, 0]
            geo = geometry[b]
            _plug_lines_nb(hb, gb, wb, nph, 0, m, geo[0], geo[1], geo[2], geo[3], dt, rho, drag, two_rt, s, True)
            for l in range(m):
                for k in range(nph):
                    h[j0 + l, k] = hb[k, l]
                    G[j0 + l, k] = gb[k, l]
                    w[j0 + l, k] = wb[k, l]
