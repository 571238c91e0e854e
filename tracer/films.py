"""Film thickness over a bubble's surface (numba): uniform, draining, or a tabulated map.

Parameters per bubble are packed into a float row by :func:`tracer.pack.pack_scene`:
0 kind (0 uniform, 1 draining, 2 map), 1 uniform thickness, 2 top, 3 bottom, 4 exponent,
5 swirl amplitude, 6 swirl scale, 7-9 up, 10-12 reference axis (for azimuth),
13 map offset, 14 map n_theta, 15 map n_phi, 16-31 four swirl waves (unit vector, phase).
"""

import math

from numba import njit

_JIT = dict(cache=True, error_model="numpy")

FILM_UNIFORM = 0
FILM_DRAINING = 1
FILM_MAP = 2
N_FILM_PARAMS = 32


@njit(**_JIT)
def film_thickness(p, maps, n):
    """Film thickness in nm at the point of the bubble whose outward unit normal is *n*.

    Draining: :math:`d = d_{top} + (d_{bottom} - d_{top})\\,((1-\\cos\\theta)/2)^{p}`, θ the polar
    angle from ``up``: with p = 1/2 this is the immobile-interface drainage law
    :math:`h \\propto \\sqrt{z}` for height z below the top (Mysels, Shinoda & Frankel 1959;
    docs/scene-format.md), floored by the top thickness.  Swirl: the thickness is multiplied
    by 1 + a·s(n), s a sum of four domain-warped plane waves on the sphere in [-1, 1].
    Map: bilinear in (θ, φ) over an (Nθ, Nφ) table, φ periodic.
    """
    kind = int(p[0])
    cos_t = n[0] * p[7] + n[1] * p[8] + n[2] * p[9]
    if kind == FILM_UNIFORM:
        d = p[1]
    elif kind == FILM_DRAINING:
        z = min(1.0, max(0.0, 0.5 * (1.0 - cos_t)))
        d = p[2] + (p[3] - p[2]) * z ** p[4]
    else:
        nt = int(p[14])
        nph = int(p[15])
        off = int(p[13])
        theta = math.acos(min(1.0, max(-1.0, cos_t)))
        bx = p[8] * p[12] - p[9] * p[11]  # b = up x ref
        by = p[9] * p[10] - p[7] * p[12]
        bz = p[7] * p[11] - p[8] * p[10]
        phi = math.atan2(n[0] * bx + n[1] * by + n[2] * bz, n[0] * p[10] + n[1] * p[11] + n[2] * p[12])
        if phi < 0.0:
            phi += 2.0 * math.pi
        u = theta / math.pi * (nt - 1)
        v = phi / (2.0 * math.pi) * nph
        i0 = min(nt - 2, int(u)) if nt > 1 else 0
        fu = min(1.0, u - i0) if nt > 1 else 0.0
        j0 = int(v) % nph
        j1 = (j0 + 1) % nph
        fv = v - int(v)
        i1 = i0 + 1 if nt > 1 else 0
        a = maps[off + i0 * nph + j0] * (1 - fv) + maps[off + i0 * nph + j1] * fv
        b = maps[off + i1 * nph + j0] * (1 - fv) + maps[off + i1 * nph + j1] * fv
        d = a * (1 - fu) + b * fu
    if p[5] != 0.0:
        s = 0.0
        k = p[6]
        for w in range(4):
            base = 16 + 4 * w
            x = n[0] * p[base] + n[1] * p[base + 1] + n[2] * p[base + 2]
            s += math.sin(k * x + p[base + 3] + 1.5 * math.sin(0.5 * k * cos_t + w))
        d *= 1.0 + p[5] * 0.25 * s
    return max(d, 0.0)
