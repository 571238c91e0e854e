"""Numba kernels of the film-flow models (names end in ``_nb``); the models in
:mod:`bubbleoptics.filmflow.models` call them with plain arrays and floats, SI units.

Layout: cell fields are ``(n_theta, n_phi)`` C arrays; the θ-face velocity is
``(n_theta + 1, n_phi)`` (row i on the face between cells i - 1 and i; rows 0 and n_theta are
the poles and stay 0); the φ-face velocity is ``(n_theta, n_phi)`` (column k on the face
between columns k - 1 and k, periodic).  Every update is in finite-volume form, a difference
of face fluxes, so :math:`\\sum_j A_j h_j` changes only by rounding (and by evaporation).
"""

import numpy as np
from numba import njit, prange

__all__ = [
    "tridiagonal_solve_nb",
    "cyclic_tridiagonal_solve_nb",
    "rigid_rate_nb",
    "rigid_step_nb",
    "evaporate_line_nb",
    "evaporate_nb",
    "plug_sweep_nb",
]

_JIT = dict(cache=True, error_model="numpy")
_JIT_PARALLEL = dict(cache=True, error_model="numpy", parallel=True)

# scratch rows of the line sweeps (one (N_SCRATCH, n + 1) block per line)
_A, _B, _C, _D, _X, _CP, _DP, _VSTAR, _BETA, _CC, _Q, _Z = range(12)
N_SCRATCH = 12


@njit(**_JIT)
def tridiagonal_solve_nb(a, b, c, d, x, cp, dp, n):
    """Solve :math:`a_i x_{i-1} + b_i x_i + c_i x_{i+1} = d_i`, i < n (a_0, c_{n-1} unused), by the
    Thomas algorithm (no pivoting: the film matrices are diagonally dominant M-matrices)."""
    cp[0] = c[0] / b[0]
    dp[0] = d[0] / b[0]
    for i in range(1, n):
        m = b[i] - a[i] * cp[i - 1]
        cp[i] = c[i] / m
        dp[i] = (d[i] - a[i] * dp[i - 1]) / m
    x[n - 1] = dp[n - 1]
    for i in range(n - 2, -1, -1):
        x[i] = dp[i] - cp[i] * x[i + 1]


@njit(**_JIT)
def cyclic_tridiagonal_solve_nb(a, b, c, d, x, cp, dp, z, n):
    """Solve the periodic tridiagonal system (row 0 couples to x_{n-1} by a_0, row n-1 to x_0
    by c_{n-1}), n >= 3, by the Sherman-Morrison correction of two Thomas solves (A = B + u vᵀ,
    u = (γ, 0, ..., c_{n-1}), v = (1, 0, ..., a_0/γ), γ = -b_0).  *b* is restored; *z* is
    scratch of length n."""
    gamma = -b[0]
    alpha = a[0]
    beta = c[n - 1]
    b0 = b[0]
    bn = b[n - 1]
    b[0] = b0 - gamma
    b[n - 1] = bn - alpha * beta / gamma
    tridiagonal_solve_nb(a, b, c, d, x, cp, dp, n)
    for i in range(n):  # z solves B z = u, u = (gamma, 0, ..., 0, beta)
        z[i] = 0.0
    z[0] = gamma
    z[n - 1] = beta
    tridiagonal_solve_nb(a, b, c, z, z, cp, dp, n)
    b[0] = b0
    b[n - 1] = bn
    f = (x[0] + alpha * x[n - 1] / gamma) / (1.0 + z[0] + alpha * z[n - 1] / gamma)
    for i in range(n):
        x[i] -= f * z[i]


@njit(**_JIT)
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


@njit(**_JIT)
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


@njit(**_JIT_PARALLEL)
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


@njit(**_JIT_PARALLEL)
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


@njit(**_JIT)
def _factor_lines_nb(A, B, C, CP, W, n, k0, k1):
    """LU (Thomas) factors of the tridiagonal systems of lines k0..k1-1 (line k is column k of
    the (n, m) arrays A, B, C: sub-, main, super-diagonal): CP the modified super-diagonal, W the
    reciprocal pivots.  Innermost loops run over the lines, contiguous, so they vectorise."""
    for k in range(k0, k1):
        W[0, k] = 1.0 / B[0, k]
        CP[0, k] = C[0, k] * W[0, k]
    for i in range(1, n):
        for k in range(k0, k1):
            w = 1.0 / (B[i, k] - A[i, k] * CP[i - 1, k])
            W[i, k] = w
            CP[i, k] = C[i, k] * w


@njit(**_JIT)
def _substitute_lines_nb(A, CP, W, D, X, n, k0, k1):
    """Solve with the factors of :func:`_factor_lines_nb` for right-hand sides D (n, m) into X
    (X may be D)."""
    for k in range(k0, k1):
        X[0, k] = D[0, k] * W[0, k]
    for i in range(1, n):
        for k in range(k0, k1):
            X[i, k] = (D[i, k] - A[i, k] * X[i - 1, k]) * W[i, k]
    for i in range(n - 2, -1, -1):
        for k in range(k0, k1):
            X[i, k] -= CP[i, k] * X[i + 1, k]


@njit(**_JIT)
def _lines_prepare_nb(A, B, C, CP, W, Z, n, k0, k1, cyclic):
    """Factor the line systems.  Periodic lines (row 0 coupled to row n-1 by A[0], row n-1 to
    row 0 by C[n-1]) are solved by Sherman-Morrison: the matrix is B' + u vᵀ with
    u = (γ, 0, ..., C[n-1]), v = (1, 0, ..., A[0]/γ), γ = -B[0]; B is overwritten by the
    tridiagonal B' (so B'[0] = 2 B[0], from which the solve gets γ back), and B' z = u is
    solved into Z."""
    if cyclic:
        for k in range(k0, k1):
            g = -B[0, k]
            B[0, k] -= g
            B[n - 1, k] -= A[0, k] * C[n - 1, k] / g
    _factor_lines_nb(A, B, C, CP, W, n, k0, k1)
    if cyclic:
        for i in range(1, n - 1):
            for k in range(k0, k1):
                Z[i, k] = 0.0
        for k in range(k0, k1):
            Z[0, k] = -0.5 * B[0, k]
            Z[n - 1, k] = C[n - 1, k]
        _substitute_lines_nb(A, CP, W, Z, Z, n, k0, k1)


@njit(**_JIT)
def _lines_solve_nb(A, B, CP, W, Z, D, X, n, k0, k1, cyclic):
    """Solve the line systems prepared by :func:`_lines_prepare_nb` for D into X (X may be D)."""
    _substitute_lines_nb(A, CP, W, D, X, n, k0, k1)
    if cyclic:
        for k in range(k0, k1):
            r = A[0, k] / (-0.5 * B[0, k])
            f = (X[0, k] + r * X[n - 1, k]) / (1.0 + Z[0, k] + r * Z[n - 1, k])
            for i in range(n):
                X[i, k] -= f * Z[i, k]


@njit(**_JIT)
def _plug_lines_nb(h, G, v, n, k0, k1, area, face_len, dist, gforce, dt, rho, drag, two_rt, s, cyclic):
    """One implicit plug-flow update of lines k0..k1-1 (in place).

    Line k is column k of *h*, *G* (n cells) and of *v* (n + 1 face velocities, face i between
    cells i - 1 and i; for periodic lines face n is face 0 and both rows hold its value);
    *area* (n, m), and per face *face_len*, *dist* (centre spacing), *gforce* (tangential
    gravity, m s⁻²), all (n + 1, m); a face of length 0 is closed.  *s*: scratch (N_SCRATCH, n + 1, m).

    1. Momentum with the Marangoni force and the drag implicit, gravity explicit:
       :math:`\\rho h_f(v' - v) = \\Delta t[\\rho h_f g_t - 2R_gT(\\Gamma'_i - \\Gamma'_{i-1})/d - C_a v']`,
       :math:`h_f` the face mean; with surfactant continuity
       :math:`A_j(\\Gamma'_j - \\Gamma_j) = -\\Delta t(\\ell\\Gamma_f v')|^{j+1}_{j}` it gives one
       symmetric, diagonally dominant tridiagonal system for Γ' per line (the 1-D form of the
       system [Huang2020] solve in 2-D); it fixes v'.
    2. Transport of h and Γ by v', implicit first-order upwind: an M-matrix, so h, Γ stay >= 0
       for any dt, and exactly conservative.  Γ' of step 1 is only used to find v'.
    """
    A, B, C, D, X, CP, W = s[_A], s[_B], s[_C], s[_D], s[_X], s[_CP], s[_DP]
    VS, BE, CC, Q, Z = s[_VSTAR], s[_BETA], s[_CC], s[_Q], s[_Z]
    first = 0 if cyclic else 1
    for i in range(first, n):
        lo = i - 1 if i > 0 else n - 1
        for k in range(k0, k1):
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
    for k in range(k0, k1):
        if cyclic:
            VS[n, k], BE[n, k], CC[n, k], Q[n, k] = VS[0, k], BE[0, k], CC[0, k], Q[0, k]
        else:
            VS[0, k] = BE[0, k] = CC[0, k] = Q[0, k] = 0.0
            VS[n, k] = BE[n, k] = CC[n, k] = Q[n, k] = 0.0
    for j in range(n):
        for k in range(k0, k1):
            A[j, k] = -CC[j, k]
            C[j, k] = -CC[j + 1, k]
            B[j, k] = area[j, k] + CC[j, k] + CC[j + 1, k]
            D[j, k] = area[j, k] * G[j, k] - (Q[j + 1, k] - Q[j, k])
    _lines_prepare_nb(A, B, C, CP, W, Z, n, k0, k1, cyclic)
    _lines_solve_nb(A, B, CP, W, Z, D, X, n, k0, k1, cyclic)
    for i in range(first, n):
        lo = i - 1 if i > 0 else n - 1
        for k in range(k0, k1):
            v[i, k] = VS[i, k] - BE[i, k] * (X[i, k] - X[lo, k])
    for k in range(k0, k1):
        if cyclic:
            v[n, k] = v[0, k]
        else:
            v[0, k] = 0.0
            v[n, k] = 0.0
    # implicit upwind transport; CC <- weight p = max(f, 0), Q <- m = max(-f, 0), f = dt l v'
    for i in range(n + 1):
        for k in range(k0, k1):
            f = dt * face_len[i, k] * v[i, k]
            CC[i, k] = max(f, 0.0)
            Q[i, k] = max(-f, 0.0)
    for j in range(n):
        for k in range(k0, k1):
            A[j, k] = -CC[j, k]
            C[j, k] = -Q[j + 1, k]
            B[j, k] = area[j, k] + CC[j + 1, k] + Q[j, k]
            D[j, k] = area[j, k] * h[j, k]
            X[j, k] = area[j, k] * G[j, k]
    _lines_prepare_nb(A, B, C, CP, W, Z, n, k0, k1, cyclic)
    _lines_solve_nb(A, B, CP, W, Z, D, D, n, k0, k1, cyclic)
    _lines_solve_nb(A, B, CP, W, Z, X, X, n, k0, k1, cyclic)
    for j in range(n):
        for k in range(k0, k1):
            h[j, k] = D[j, k]
            G[j, k] = X[j, k]


@njit(**_JIT_PARALLEL)
def plug_sweep_nb(h, G, v, dt, area, face_len, dist, gforce, rho, drag, two_rt, scratch, cyclic, chunks):
    """One plug-flow half-step along axis 0 of *h*, *G* (n, m), for all m lines at once
    (:func:`_plug_lines_nb`), the lines split into *chunks* blocks run in parallel.
    θ sweep: the arrays as stored; φ sweep: their transposes, ``cyclic=True``."""
    n, m = h.shape
    size = (m + chunks - 1) // chunks
    for c in prange(chunks):
        k0 = c * size
        k1 = min(m, k0 + size)
        if k0 < k1:
            _plug_lines_nb(h, G, v, n, k0, k1, area, face_len, dist, gforce, dt, rho, drag, two_rt, scratch, cyclic)
