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
    "plug_theta_sweep_nb",
    "plug_phi_sweep_nb",
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
    """:func:`evaporate_line_nb` on every column of *h* (n_theta, n_phi); returns the volume (m³)."""
    nph = h.shape[1]
    col = np.zeros(nph)
    if depth == 0.0:
        return 0.0
    for k in prange(nph):
        line = h[:, k].copy()
        col[k] = evaporate_line_nb(line, depth, area)
        h[:, k] = line
    return col.sum()


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
def _line_solve_nb(s, n, cyclic):
    if cyclic:
        cyclic_tridiagonal_solve_nb(s[_A], s[_B], s[_C], s[_D], s[_X], s[_CP], s[_DP], s[_Z], n)
    else:
        tridiagonal_solve_nb(s[_A], s[_B], s[_C], s[_D], s[_X], s[_CP], s[_DP], n)


@njit(**_JIT)
def _plug_line_nb(h, G, v, n, area, face_len, dist, gforce, dt, rho, drag, two_rt, s, cyclic):
    """One implicit line update of plug flow along a θ column or a φ row (in place).

    *h*, *G*: the n cells of the line; *v*: its n + 1 face velocities (face i between cells i-1
    and i; for a periodic line face n is face 0); *area*, *dist* (centre spacing), *face_len*
    and *gforce* (tangential gravity, m s⁻²) per face (n + 1 each; face_len 0 closes a face).

    1. Momentum with the Marangoni force implicit, drag implicit, gravity explicit:
       :math:`\\rho h_f(v' - v) = \\Delta t[\\rho h_f g_t - 2R_gT(\\Gamma'_i - \\Gamma'_{i-1})/d - C_a v']`,
       :math:`h_f` the face mean; with surfactant continuity
       :math:`A_j(\\Gamma'_j - \\Gamma_j) = -\\Delta t(\\ell\\Gamma_f v')|^{j+1}_{j}` it gives one
       symmetric, diagonally dominant tridiagonal system for Γ' (the 1-D form of the
       system [Huang2020] solve in 2-D); it fixes v'.
    2. Transport of h and Γ by v', implicit first-order upwind: an M-matrix, so h, Γ stay >= 0
       for any dt, and exactly conservative.  Γ' of step 1 is only used to find v'.
    """
    a, b, c, d, x = s[_A], s[_B], s[_C], s[_D], s[_X]
    vstar, beta, cc, q = s[_VSTAR], s[_BETA], s[_CC], s[_Q]
    for i in range(n + 1):
        if face_len[i] == 0.0:
            vstar[i] = 0.0
            beta[i] = 0.0
            cc[i] = 0.0
            q[i] = 0.0
            continue
        lo = i - 1 if i > 0 else n - 1
        hi = i if i < n else 0
        hf = 0.5 * (h[lo] + h[hi])
        gf = 0.5 * (G[lo] + G[hi])
        den = rho * hf + drag * dt
        vstar[i] = rho * hf * (v[i] + dt * gforce[i]) / den
        beta[i] = dt * two_rt / (dist[i] * den)
        cc[i] = dt * face_len[i] * gf * beta[i]
        q[i] = dt * face_len[i] * gf * vstar[i]
    for j in range(n):
        a[j] = -cc[j]
        c[j] = -cc[j + 1]
        b[j] = area[j] + cc[j] + cc[j + 1]
        d[j] = area[j] * G[j] - (q[j + 1] - q[j])
    _line_solve_nb(s, n, cyclic)
    for i in range(n + 1):
        if face_len[i] == 0.0:
            v[i] = 0.0
            continue
        lo = i - 1 if i > 0 else n - 1
        hi = i if i < n else 0
        v[i] = vstar[i] - beta[i] * (x[hi] - x[lo])
    # implicit upwind transport: cc <- outflow-to-+ side weight p, q <- weight m
    for i in range(n + 1):
        f = dt * face_len[i] * v[i]
        cc[i] = f if f > 0.0 else 0.0
        q[i] = -f if f < 0.0 else 0.0
    for j in range(n):
        a[j] = -cc[j]
        c[j] = -q[j + 1]
        b[j] = area[j] + cc[j + 1] + q[j]
        d[j] = area[j] * h[j]
    _line_solve_nb(s, n, cyclic)
    for j in range(n):
        h[j] = x[j]
        d[j] = area[j] * G[j]
    _line_solve_nb(s, n, cyclic)
    for j in range(n):
        G[j] = x[j]


@njit(**_JIT_PARALLEL)
def plug_theta_sweep_nb(h, G, v, dt, area, face_len, dist, gforce, rho, drag, two_rt, scratch):
    """The θ half-step of plug flow: :func:`_plug_line_nb` on every column (in place).

    *v*: θ-face velocity (n_theta + 1, n_phi); *area* (n_theta,); *face_len*, *dist*, *gforce*
    (n_theta + 1,) per θ face; *scratch*: (n_phi, N_SCRATCH, n_theta + 1).
    """
    nt, nph = h.shape
    for k in prange(nph):
        s = scratch[k]
        hc = np.empty(nt)
        gc = np.empty(nt)
        vc = np.empty(nt + 1)
        for j in range(nt):
            hc[j] = h[j, k]
            gc[j] = G[j, k]
        for i in range(nt + 1):
            vc[i] = v[i, k]
        _plug_line_nb(hc, gc, vc, nt, area, face_len, dist, gforce, dt, rho, drag, two_rt, s, False)
        for j in range(nt):
            h[j, k] = hc[j]
            G[j, k] = gc[j]
        for i in range(nt + 1):
            v[i, k] = vc[i]


@njit(**_JIT_PARALLEL)
def plug_phi_sweep_nb(h, G, w, dt, area_rows, face_len, dist_rows, zero, rho, drag, two_rt, scratch):
    """The φ half-step of plug flow: :func:`_plug_line_nb` on every row, periodic (in place).

    *w*: φ-face velocity (n_theta, n_phi); *area_rows* (n_theta, n_phi) the cell areas;
    *face_len* and *zero* (n_phi + 1,): the φ-face length R Δθ and no tangential gravity;
    *dist_rows* (n_theta, n_phi + 1): the centre spacing R sin θ_j Δφ; *scratch*:
    (n_theta, N_SCRATCH, n_phi + 1).
    """
    nt, nph = h.shape
    for j in prange(nt):
        s = scratch[j]
        wr = np.empty(nph + 1)
        for k in range(nph):
            wr[k] = w[j, k]
        wr[nph] = w[j, 0]
        _plug_line_nb(h[j], G[j], wr, nph, area_rows[j], face_len, dist_rows[j], zero, dt, rho, drag, two_rt,
                      s, True)
        for k in range(nph):
            w[j, k] = wr[k]
