"""Film thickness over a bubble (numba): uniform, draining, or a tabulated map, with swirl.

A film's parameters are one :data:`tracer.kernels.records.FILM` record (filled by
:func:`tracer.prepare.pack.pack_scene` from a :class:`tracer.scene.FilmProfile`); the point on the
bubble is given by its outward unit normal *n*.
"""

import math

from numba import njit
from bubbleoptics.jit import JIT_FMA
from bubbleoptics.kernels import sin_cos_nb

from .records import N_SWIRL_WAVES, PROFILE_DRAINING, PROFILE_UNIFORM

__all__ = ["film_thickness"]


# cos w and sin w of the swirl waves' warp offsets w = 0, 1, ..., N_SWIRL_WAVES - 1 (radians)
_COS_W = tuple(math.cos(w) for w in range(N_SWIRL_WAVES))
_SIN_W = tuple(math.sin(w) for w in range(N_SWIRL_WAVES))


@njit(**JIT_FMA)
def film_thickness(f, maps, n):
    """Film thickness in nm of film record *f* at the point whose outward unit normal is *n*.

    Draining: :math:`d = d_{top} + (d_{bottom} - d_{top})\\,((1-\\cos\\theta)/2)^{p}`, θ the polar
    angle from ``up``: with p = 1/2 this is the immobile-interface drainage law
    :math:`h \\propto \\sqrt{z}` for height z below the top (Mysels, Shinoda & Frankel 1959;
    docs/scene-format.md), floored by the top thickness.  Swirl: the thickness is multiplied
    by 1 + a·s(n)/4, s a sum of four domain-warped plane waves on the sphere, |s| <= 4:
    :math:`s = \\sum_w \\sin(k\\,n\\cdot u_w + \\phi_w + 1.5 \\sin(k \\cos\\theta / 2 + w))`.
    Map: bilinear in (θ, φ) over an (Nθ, Nφ) table stored from ``f.map_offset`` in *maps*,
    φ periodic, measured from ``ref`` towards ``up × ref``.  Never negative.

    The swirl's sines are :func:`bubbleoptics.kernels.sin_cos_nb` (inlined polynomials, not
    libm calls) and the kernel is compiled with fused multiply-add: the swirl costs about 0.57 of
    its time with libm's ``sin`` (one thread, timed in an ``@njit`` loop; docs/performance.md).
    """
    up = f.up
    cos_t = n[0] * up[0] + n[1] * up[1] + n[2] * up[2]
    if f.profile == PROFILE_UNIFORM:
        d = f.thickness_nm
    elif f.profile == PROFILE_DRAINING:
        z = min(1.0, max(0.0, 0.5 * (1.0 - cos_t)))
        zp = math.sqrt(z) if f.exponent == 0.5 else z**f.exponent  # sqrt: the common law, cheaper than the power
        d = f.top_nm + (f.bottom_nm - f.top_nm) * zp
    else:
        nt = f.map_rows
        nph = f.map_cols
        off = f.map_offset
        ref = f.ref
        theta = math.acos(min(1.0, max(-1.0, cos_t)))
        bx = up[1] * ref[2] - up[2] * ref[1]  # b = up x ref
        by = up[2] * ref[0] - up[0] * ref[2]
        bz = up[0] * ref[1] - up[1] * ref[0]
        phi = math.atan2(n[0] * bx + n[1] * by + n[2] * bz, n[0] * ref[0] + n[1] * ref[1] + n[2] * ref[2])
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
    if f.swirl != 0.0:
        k = f.swirl_scale
        # the warp sin(a + w), w = 0, 1, 2, ..., by the angle-addition formula from one sin/cos pair
        sa, ca = sin_cos_nb(0.5 * k * cos_t)
        # a loop, not the waves written out: writing them out inlined four copies of the sine's
        # polynomial and doubled this kernel's compile time (1.7-2.0 -> 3.5-3.8 s) for at most
        # 10 % of its warm time (docs/performance.md)
        s = 0.0
        waves = f.waves
        for w in range(N_SWIRL_WAVES):
            x = n[0] * waves[w, 0] + n[1] * waves[w, 1] + n[2] * waves[w, 2]
            warp = sa * _COS_W[w] + ca * _SIN_W[w]
            s += sin_cos_nb(k * x + waves[w, 3] + 1.5 * warp)[0]
        d *= 1.0 + f.swirl * 0.25 * s
    return max(d, 0.0)
