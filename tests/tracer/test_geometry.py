"""Tests of the tracer's geometry kernels (:mod:`tracer.kernels.geometry`) and BVH (:mod:`tracer.prepare.bvh`).

analytic: cases with a closed-form answer (the coursework's unit cases, tangent rays, watertightness
of closed meshes, no self-intersection of spawned rays).  reference: comparisons with an
independent computation (mpmath roots, a NumPy Möller-Trumbore, brute force over all
triangles).
"""

import math

import mpmath
import numpy as np
import pytest
from numba import njit

from tracer.kernels.geometry import STACK_SIZE, degenerate_triangles
from tracer.prepare.bvh import LEAF_SIZE, build_bvh
from tracer.kernels.geometry import (
    intersect_bvh,
    intersect_sphere,
    intersect_triangle_sheared,
    normalize,
    offset_origin,
    origin_epsilon,
    ray_shear,
    sphere_hit_point,
)

INF = np.inf
O3 = (0.0, 0.0, 0.0)
_JIT = dict(cache=True, error_model="numpy")


# Small vector helpers for the test tracers below (the tracer writes its arithmetic inline).
@njit(**_JIT)
def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(**_JIT)
def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@njit(**_JIT)
def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


@njit(**_JIT)
def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


@njit(**_JIT)
def scale(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


@njit(**_JIT)
def norm(a):
    return math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])


@njit(**_JIT)
def intersect_triangle(o, d, v0, v1, v2, tmin, tmax):
    """One triangle, as the BVH traversal tests it (set-up by ray_shear, then the sheared test)."""
    kx, ky, kz, sx, sy, sz = ray_shear(d)
    return intersect_triangle_sheared(o, kx, ky, kz, sx, sy, sz, v0, v1, v2, tmin, tmax)


def _tup(v):
    return (float(v[0]), float(v[1]), float(v[2]))


# --------------------------------------------------------------------------------------------
# Batch drivers (numba, so thousands of rays cost milliseconds)
# --------------------------------------------------------------------------------------------
@njit(**_JIT)
def _tri_matrix(O, D, tris, tmin, tmax):
    """t of every ray (rows) against every triangle (columns), inf where missed."""
    out = np.empty((O.shape[0], tris.shape[0]))
    for r in range(O.shape[0]):
        o = (O[r, 0], O[r, 1], O[r, 2])
        d = (D[r, 0], D[r, 1], D[r, 2])
        for i in range(tris.shape[0]):
            v0 = (tris[i, 0, 0], tris[i, 0, 1], tris[i, 0, 2])
            v1 = (tris[i, 1, 0], tris[i, 1, 1], tris[i, 1, 2])
            v2 = (tris[i, 2, 0], tris[i, 2, 1], tris[i, 2, 2])
            out[r, i] = intersect_triangle(o, d, v0, v1, v2, tmin, tmax)[0]
    return out


@njit(**_JIT)
def _bvh_batch(O, D, tmin, tmax, bounds, child, first, count, tris):
    R = O.shape[0]
    t_out = np.empty(R)
    i_out = np.empty(R, dtype=np.int64)
    uv = np.empty((R, 2))
    stack = np.empty(64, dtype=np.int64)
    for r in range(R):
        o = (O[r, 0], O[r, 1], O[r, 2])
        d = (D[r, 0], D[r, 1], D[r, 2])
        t, i, u, v = intersect_bvh(o, d, tmin, tmax, bounds, child, first, count, tris, stack)
        t_out[r] = t
        i_out[r] = i
        uv[r, 0] = u
        uv[r, 1] = v
    return t_out, i_out, uv


@njit(**_JIT)
def _bounce(O, D, sph, bounds, child, first, count, tris, eps):
    """Nearest hit of each ray among spheres and triangles, and the two spawned rays.

    Returns hit (R, 5): t, kind (0 sphere, 1 triangle, -1 none), index (sphere, or triangle in
    the BVH's order), entering (sphere only), cos = |d.n|/|d|; and (R, 4, 3): hit point, the
    outward (sphere) / geometric (triangle) unit normal, the reflected ray's origin and
    direction; the transmitted ray (same direction) starts at ``p - eps n_side``.  The origins
    are moved along the normal oriented towards the side they leave on (offset_origin).
    """
    R = O.shape[0]
    hit = np.full((R, 5), np.nan)
    geo = np.full((R, 5, 3), np.nan)
    stack = np.empty(64, dtype=np.int64)
    for r in range(R):
        o = (O[r, 0], O[r, 1], O[r, 2])
        d = (D[r, 0], D[r, 1], D[r, 2])
        best = np.inf
        kind = -1
        idx = -1
        ent = False
        for k in range(sph.shape[0]):
            t, e = intersect_sphere(o, d, (sph[k, 0], sph[k, 1], sph[k, 2]), sph[k, 3], 0.0, best)
            if t < best:
                best, kind, idx, ent = t, 0, k, e
        t, i, u, v = intersect_bvh(o, d, 0.0, best, bounds, child, first, count, tris, stack)
        if t < best:
            best, kind, idx, ent = t, 1, i, False
        hit[r, 0] = best
        hit[r, 1] = kind
        hit[r, 2] = idx
        hit[r, 3] = 1.0 if ent else 0.0
        if kind < 0:
            continue
        if kind == 0:
            p, n = sphere_hit_point(o, d, best, (sph[idx, 0], sph[idx, 1], sph[idx, 2]), sph[idx, 3])
        else:
            p = add(o, scale(d, best))
            v0 = (tris[idx, 0, 0], tris[idx, 0, 1], tris[idx, 0, 2])
            v1 = (tris[idx, 1, 0], tris[idx, 1, 1], tris[idx, 1, 2])
            v2 = (tris[idx, 2, 0], tris[idx, 2, 1], tris[idx, 2, 2])
            n = normalize(cross(sub(v1, v0), sub(v2, v0)))
        dn = dot(d, n)
        hit[r, 4] = abs(dn) / norm(d)
        side = n if dn < 0.0 else scale(n, -1.0)  # towards the incoming ray
        refl = sub(d, scale(n, 2.0 * dn))
        o_refl = offset_origin(p, side, eps)
        o_tran = offset_origin(p, side, -eps)
        for j in range(3):
            geo[r, 0, j] = p[j]
            geo[r, 1, j] = n[j]
            geo[r, 2, j] = o_refl[j]
            geo[r, 3, j] = refl[j]
            geo[r, 4, j] = o_tran[j]
    return hit, geo


def _random_unit(rng, n):
    v = rng.normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)


# --------------------------------------------------------------------------------------------
# Vector helpers
# --------------------------------------------------------------------------------------------
@pytest.mark.analytic
def test_normalize_never_makes_nan_or_overflows():
    assert normalize((0.0, 0.0, 0.0)) == (0.0, 0.0, 0.0)  # never NaN
    assert normalize((0.0, -5.0, 0.0)) == (0.0, -1.0, 0.0)
    # no underflow or overflow of |v|^2
    for s in (1e-200, 1e-320, 1e200, 1e307):
        n = normalize((3.0 * s, 0.0, 4.0 * s))
        assert math.isclose(n[0], 0.6, rel_tol=1e-3) and math.isclose(n[2], 0.8, rel_tol=1e-3)
    assert normalize((np.inf, 0.0, 0.0)) == (0.0, 0.0, 0.0)


# --------------------------------------------------------------------------------------------
# Spheres: the coursework's unit cases and their siblings
# --------------------------------------------------------------------------------------------
@pytest.mark.analytic
def test_sphere_coursework_case():
    """The coursework's GoogleTest case: from (0, 3, 0) along -y, radius-2 sphere at the origin."""
    t, entering = intersect_sphere((0.0, 3.0, 0.0), (0.0, -1.0, 0.0), O3, 2.0, 0.0, INF)
    assert t == 1.0 and entering
    p, n = sphere_hit_point((0.0, 3.0, 0.0), (0.0, -1.0, 0.0), t, O3, 2.0)
    assert p == (0.0, 2.0, 0.0) and n == (0.0, 1.0, 0.0)


@pytest.mark.analytic
def test_sphere_coursework_siblings():
    # from inside: the exit point, not entering
    t, entering = intersect_sphere(O3, (1.0, 0.0, 0.0), O3, 2.0, 0.0, INF)
    assert t == 2.0 and not entering
    assert sphere_hit_point(O3, (1.0, 0.0, 0.0), t, O3, 2.0) == ((2.0, 0.0, 0.0), (1.0, 0.0, 0.0))
    # pointing away
    assert intersect_sphere((0.0, 3.0, 0.0), (0.0, 1.0, 0.0), O3, 2.0, 0.0, INF) == (INF, False)
    # tmax below the hit (and exactly at it: the interval is open)
    assert intersect_sphere((0.0, 3.0, 0.0), (0.0, -1.0, 0.0), O3, 2.0, 0.0, 0.5)[0] == INF
    assert intersect_sphere((0.0, 3.0, 0.0), (0.0, -1.0, 0.0), O3, 2.0, 0.0, 1.0)[0] == INF
    # non-unit direction: t is in units of |d|
    assert intersect_sphere((0.0, 3.0, 0.0), (0.0, -2.0, 0.0), O3, 2.0, 0.0, INF) == (0.5, True)
    assert intersect_sphere((0.0, 3.0, 0.0), (0.0, -1e-3, 0.0), O3, 2.0, 0.0, INF) == (1000.0, True)
    # tmin past the entry point: the exit point
    assert intersect_sphere((0.0, 3.0, 0.0), (0.0, -1.0, 0.0), O3, 2.0, 1.0, INF) == (5.0, False)
    # degenerate input never hits
    assert intersect_sphere((0.0, 3.0, 0.0), (0.0, 0.0, 0.0), O3, 2.0, 0.0, INF)[0] == INF
    assert intersect_sphere((0.0, 3.0, 0.0), (0.0, -1.0, 0.0), O3, 0.0, 0.0, INF)[0] == INF


@pytest.mark.analytic
@pytest.mark.parametrize("r", [2.0, 1e-3, 7.3e5, 0.1])
def test_sphere_tangent_rays(r):
    """Along x at height y = r(1 + delta): delta = 0 touches, +1e-12 misses, -1e-12 hits twice."""
    for x0 in (-10.0 * r, -3.7 * r, -r):
        o_exact = (x0, r, 0.0)
        t, ent = intersect_sphere(o_exact, (1.0, 0.0, 0.0), O3, r, 0.0, INF)
        assert t == -x0 and ent  # Delta = 0 exactly: one hit at the tangent point, no NaN
        p, n = sphere_hit_point(o_exact, (1.0, 0.0, 0.0), t, O3, r)
        assert p == (0.0, r, 0.0) and n == (0.0, 1.0, 0.0)
        assert intersect_sphere((x0, r * (1 + 1e-12), 0.0), (1.0, 0.0, 0.0), O3, r, 0.0, INF)[0] == INF
        o_in = (x0, r * (1 - 1e-12), 0.0)
        t0, ent0 = intersect_sphere(o_in, (1.0, 0.0, 0.0), O3, r, 0.0, INF)
        t1, ent1 = intersect_sphere(o_in, (1.0, 0.0, 0.0), O3, r, t0, INF)
        assert ent0 and not ent1 and t0 < -x0 < t1
        for tt in (t0, t1):
            p, _ = sphere_hit_point(o_in, (1.0, 0.0, 0.0), tt, O3, r)
            assert abs(norm(p) - r) <= 1e-15 * r
    # origin at the tangent point itself: b' = 0 and Delta = 0 give t = 0 (not 0/0)
    assert intersect_sphere((0.0, r, 0.0), (1.0, 0.0, 0.0), O3, r, -1.0, INF) == (0.0, True)
    assert intersect_sphere((0.0, r, 0.0), (1.0, 0.0, 0.0), O3, r, 0.0, INF)[0] == INF


@pytest.mark.analytic
def test_sphere_tangent_rays_random_orientation():
    """Tangent rays in random directions at heights r(1 + delta): no NaN; hits lie on the sphere."""
    rng = np.random.default_rng(7)
    n_hit = {0.0: 0, 1e-12: 0, -1e-12: 0}
    for _ in range(3000):
        r = 10 ** rng.uniform(-4, 4)
        nrm, tan = _random_unit(rng, 2)
        tan = tan - (tan @ nrm) * nrm
        tan /= np.linalg.norm(tan)
        for delta in n_hit:
            o = nrm * r * (1 + delta) - tan * r * rng.uniform(0.5, 20)
            d = tan * rng.uniform(0.1, 10)
            t, _ = intersect_sphere(_tup(o), _tup(d), O3, r, 0.0, INF)
            assert not math.isnan(t)
            if t < INF:
                n_hit[delta] += 1
                p, n = sphere_hit_point(_tup(o), _tup(d), t, O3, r)
                assert abs(norm(p) - r) <= 1e-15 * r
                assert abs(norm(n) - 1.0) <= 1e-15
    assert n_hit[1e-12] == 0 and n_hit[-1e-12] == 3000  # the margin is far above rounding


# --------------------------------------------------------------------------------------------
# Spheres: cancellation (Haines et al. 2019) against mpmath, and why the textbook formula fails
# --------------------------------------------------------------------------------------------
def _roots_mpmath(o, d, c, r):
    """Both roots of |o + t d - c|^2 = r^2 at 60 digits, for the float64 inputs as given."""
    with mpmath.workdps(60):
        o, d, c = ([mpmath.mpf(float(x)) for x in v] for v in (o, d, c))
        r = mpmath.mpf(float(r))
        f = [o[i] - c[i] for i in range(3)]
        a = sum(x * x for x in d)
        b = sum(f[i] * d[i] for i in range(3))
        disc = b * b - a * (sum(x * x for x in f) - r * r)
        assert disc > 0
        return (-b - mpmath.sqrt(disc)) / a, (-b + mpmath.sqrt(disc)) / a


def _naive_sphere(o, d, c, r):
    """The textbook root (-b - sqrt(b^2 - 4ac)) / 2a, or inf when the discriminant is < 0."""
    f = np.subtract(o, c)
    a, b, cc = d @ d, 2.0 * (f @ d), f @ f - r * r
    disc = b * b - 4.0 * a * cc
    return (-b - math.sqrt(disc)) / (2.0 * a) if disc >= 0 else INF


@pytest.mark.reference
def test_sphere_far_tiny_against_mpmath():
    """A 1e-3 sphere 1.8e8 away: both roots to 1e-12 (in fact ~1e-16); b^2 - 4ac fails.

    b^2 and 4ac are ~1e17 and agree in all but their last digits, so the textbook discriminant
    is rounding noise (+-10): half the rays are reported as misses, the others land ~1 unit
    (1000 radii) off.  a Delta = r^2 a - |f x d|^2 has no such cancellation.
    """
    rng = np.random.default_rng(20190226)
    c = np.array([1e8, 3e7, -2e7]) * 1.7
    r = 1e-3
    axis = c / np.linalg.norm(c)
    worst_ours, worst_naive, naive_misses = 0.0, 0.0, 0
    for _ in range(60):
        u = rng.normal(size=3)
        u -= (u @ axis) * axis
        u /= np.linalg.norm(u)
        o = rng.uniform(-1, 1, 3)
        d = c + rng.uniform(0, 0.95) * r * u - o
        d = d / np.linalg.norm(d) * rng.choice([1.0, 1e-3, 7.0])
        ref0, ref1 = _roots_mpmath(o, d, c, r)
        t0, ent0 = intersect_sphere(_tup(o), _tup(d), _tup(c), r, 0.0, INF)
        t1, ent1 = intersect_sphere(_tup(o), _tup(d), _tup(c), r, t0, INF)
        assert ent0 and not ent1
        for t, ref in ((t0, ref0), (t1, ref1)):
            worst_ours = max(worst_ours, float(abs(mpmath.mpf(t) - ref) / ref))
        tn = _naive_sphere(o, d, c, r)
        naive_misses += tn == INF
        worst_naive = max(worst_naive, float(abs(mpmath.mpf(tn) - ref0) / ref0) if tn < INF else INF)
    assert worst_ours < 1e-12
    assert worst_naive > 1e-6 and naive_misses > 0


@pytest.mark.analytic
def test_sphere_hit_point_reprojection():
    """From 1e7 radii away o + t d is off the surface by ~1e-9 r; the re-projected point is not."""
    rng = np.random.default_rng(3)
    c, r = (0.25, -0.5, 1.0), 1.0
    worst_raw = worst_proj = 0.0
    for _ in range(200):
        o = np.array(c) + _random_unit(rng, 1)[0] * 1e7
        target = np.array(c) + _random_unit(rng, 1)[0] * 0.5
        d = target - o
        t, _ = intersect_sphere(_tup(o), _tup(d), c, r, 0.0, INF)
        assert t < INF
        raw = o + t * d
        p, n = sphere_hit_point(_tup(o), _tup(d), t, c, r)
        worst_raw = max(worst_raw, abs(np.linalg.norm(raw - c) - r))
        worst_proj = max(worst_proj, abs(np.linalg.norm(np.subtract(p, c)) - r))
        assert abs(dot(n, n) - 1.0) < 1e-15
    assert worst_proj < 1e-15 < 1e-12 < worst_raw


# --------------------------------------------------------------------------------------------
# Triangles
# --------------------------------------------------------------------------------------------
V0, V1, V2 = (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)


@pytest.mark.analytic
def test_triangle_inside_outside_both_faces():
    assert intersect_triangle((0.25, 0.25, 1.0), (0.0, 0.0, -1.0), V0, V1, V2, 0.0, INF) == (1.0, 0.25, 0.25)
    # back face (no culling), non-unit direction
    assert intersect_triangle((0.25, 0.5, -3.0), (0.0, 0.0, 2.0), V0, V1, V2, 0.0, INF) == (1.5, 0.25, 0.5)
    for o in ((0.6, 0.6, 1.0), (-0.1, 0.5, 1.0), (0.5, -1e-9, 1.0), (2.0, 2.0, 1.0)):
        assert intersect_triangle(o, (0.0, 0.0, -1.0), V0, V1, V2, 0.0, INF) == (INF, 0.0, 0.0)
    # behind the origin, or beyond tmax
    assert intersect_triangle((0.25, 0.25, 1.0), (0.0, 0.0, 1.0), V0, V1, V2, 0.0, INF)[0] == INF
    assert intersect_triangle((0.25, 0.25, 1.0), (0.0, 0.0, -1.0), V0, V1, V2, 0.0, 0.5)[0] == INF


@pytest.mark.analytic
def test_triangle_edges_and_vertices():
    edge_points = (((0.5, 0.5, 1.0), (0.5, 0.5)), ((0.5, 0.0, 1.0), (0.5, 0.0)), ((0.0, 0.5, 1.0), (0.0, 0.5)))
    for o, uv in edge_points:
        t, u, v = intersect_triangle(o, (0.0, 0.0, -1.0), V0, V1, V2, 0.0, INF)
        assert t == 1.0 and (u, v) == uv
    for vert, uv in ((V0, (0.0, 0.0)), (V1, (1.0, 0.0)), (V2, (0.0, 1.0))):
        t, u, v = intersect_triangle((vert[0], vert[1], 2.0), (0.0, 0.0, -1.0), V0, V1, V2, 0.0, INF)
        assert t == 2.0 and (u, v) == uv


@pytest.mark.analytic
def test_triangle_parallel_and_degenerate():
    # parallel above the plane, and in the plane itself
    assert intersect_triangle((0.2, 0.2, 1.0), (1.0, 0.0, 0.0), V0, V1, V2, -INF, INF)[0] == INF
    assert intersect_triangle((-1.0, 0.2, 0.0), (1.0, 0.0, 0.0), V0, V1, V2, -INF, INF)[0] == INF
    assert intersect_triangle((0.2, 0.2, 1.0), (0.0, 0.0, 0.0), V0, V1, V2, -INF, INF)[0] == INF
    rng = np.random.default_rng(11)
    # repeated vertices and exactly collinear ones: never hit, for any ray (the kernel alone)
    for _ in range(2000):
        a, b = rng.normal(size=(2, 3))
        mid = np.ldexp(np.round(np.ldexp(a, 20)), -20)  # dyadic, so the midpoint is exact
        far = mid + np.ldexp(np.round(np.ldexp(b, 20)), -20)
        for tri in ((a, a, b), (a, b, b), (b, a, b), (a, a, a), (mid, far, 2 * far - mid)):
            target = tri[0] + rng.uniform() * (tri[2] - tri[0])
            o = rng.normal(size=3) * 3
            t = intersect_triangle(_tup(o), _tup(target - o), *map(_tup, tri), -INF, INF)[0]
            if tri[0] is mid:  # collinear with rounded shear: may "hit" the segment, never NaN
                assert not math.isnan(t)
            else:
                assert t == INF
    # collinear triangles are flagged and collapsed by the BVH, so they are never hit there
    tris = []
    for _ in range(500):
        a, b = rng.normal(size=(2, 3))
        tris.append((a, b, a + rng.uniform() * (b - a)))
    tris = np.array(tris)
    assert degenerate_triangles(tris).all()
    assert not degenerate_triangles(rng.normal(size=(500, 3, 3))).any()
    bvh = build_bvh(tris)
    target = tris[:, 0] + rng.uniform(size=(500, 1)) * (tris[:, 1] - tris[:, 0])
    O = rng.normal(size=(500, 3)) * 3
    t, i, _ = _bvh_batch(O, target - O, -INF, INF, *bvh[:4], bvh.tris)
    assert np.all(t == INF) and np.all(i == -1)


def _moller_trumbore(o, d, v0, v1, v2):
    """Plain NumPy Möller & Trumbore (JGT 1997): (t, u, v), no edge-case handling."""
    e1, e2 = v1 - v0, v2 - v0
    p = np.cross(d, e2)
    det = e1 @ p
    s = o - v0
    q = np.cross(s, e1)
    return (e2 @ q) / det, (s @ p) / det, (d @ q) / det


@pytest.mark.reference
def test_triangle_against_moller_trumbore():
    """Rays through interior points of random triangles, not grazing: t, u, v to 1e-12."""
    rng = np.random.default_rng(1997)
    n = 0
    while n < 3000:
        v0, v1, v2 = rng.normal(size=(3, 3))
        bu, bv = rng.uniform(0.02, 0.96, 2)
        if bu + bv > 0.98:
            continue
        target = (1 - bu - bv) * v0 + bu * v1 + bv * v2
        o = rng.normal(size=3) * 4
        d = (target - o) * rng.uniform(0.1, 10)
        nrm = np.cross(v1 - v0, v2 - v0)
        if abs(nrm @ d) < 0.1 * np.linalg.norm(nrm) * np.linalg.norm(d):
            continue
        t, u, v = intersect_triangle(_tup(o), _tup(d), _tup(v0), _tup(v1), _tup(v2), 0.0, INF)
        t_ref, u_ref, v_ref = _moller_trumbore(o, d, v0, v1, v2)
        assert abs(t - t_ref) <= 1e-12 * t_ref
        assert abs(u - u_ref) <= 1e-12 and abs(v - v_ref) <= 1e-12
        n += 1


_TET_FACES = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def _tetrahedron(rng):
    """Random tetrahedron: vertices (4, 3) and its faces (4, 3, 3), wound outwards."""
    while True:
        v = rng.normal(size=(4, 3))
        vol = np.linalg.det(v[1:] - v[0])
        if abs(vol) > 0.3:
            break
    if vol < 0:
        v[[1, 2]] = v[[2, 1]]
    return v, v[_TET_FACES]


@pytest.mark.analytic
def test_watertight_shared_edges_and_vertices():
    """Rays from inside a tetrahedron through points on its edges and through its vertices:
    the two faces sharing the edge (three at a vertex) may both report the hit, never neither."""
    rng = np.random.default_rng(2013)
    edges = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]
    for _ in range(5):
        v, faces = _tetrahedron(rng)
        centre = v.mean(axis=0)
        for a, b in edges:
            sharing = [k for k, f in enumerate(_TET_FACES) if a in f and b in f]
            assert len(sharing) == 2
            s = rng.uniform(0, 1, (2000, 1))
            p = v[a] + s * (v[b] - v[a])
            w = rng.dirichlet(np.ones(4), 2000)
            O = 0.5 * (w @ v) + 0.5 * centre
            D = (p - O) * rng.uniform(0.01, 100, (2000, 1))
            t = _tri_matrix(O, D, faces[sharing], 0.0, INF)
            assert np.all(np.isfinite(t).any(axis=1)), "a ray slipped through a shared edge"
        # through the vertices exactly: at least one of the three faces there
        for j in range(4):
            O = 0.5 * (rng.dirichlet(np.ones(4), 500) @ v) + 0.5 * centre
            t = _tri_matrix(O, v[j] - O, faces, 0.0, INF)
            assert np.all(np.isfinite(t).any(axis=1))
        # and everywhere: a closed surface seen from inside is hit by every ray
        O = 0.5 * (rng.dirichlet(np.ones(4), 2000) @ v) + 0.5 * centre
        t = _tri_matrix(O, rng.normal(size=(2000, 3)), faces, 0.0, INF)
        assert np.all(np.isfinite(t).any(axis=1))


@pytest.mark.analytic
def test_watertight_flat_quad_diagonal():
    """Two coplanar triangles sharing a diagonal (the classic crack): 10^4 rays at points of the
    diagonal from random origins on both sides; none misses both triangles.

    (The quad is convex and flat to rounding; at a fold seen edge-on, a silhouette, a ray
    through the edge may rightly miss both, so grazing rays, |cos| < 1e-3, are left out.)
    """
    rng = np.random.default_rng(42)
    misses = n = 0
    for _ in range(5):
        size = 10 ** rng.uniform(-3, 3)
        e1, e2 = _random_unit(rng, 2)
        e2 -= (e2 @ e1) * e1
        e2 /= np.linalg.norm(e2)
        xy = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) + rng.uniform(-0.3, 0.3, (4, 2))
        q = rng.normal(size=3) * 1e3 + size * (xy[:, :1] * e1 + xy[:, 1:] * e2)
        tris = np.array([q[[0, 1, 2]], q[[0, 2, 3]]])
        p = q[0] + rng.uniform(0, 1, (2000, 1)) * (q[2] - q[0])
        D = _random_unit(rng, 2000)
        D = D[np.abs(D @ np.cross(e1, e2)) > 1e-3]
        O = p[: len(D)] - D * size * rng.uniform(0.1, 10, (len(D), 1))
        t = _tri_matrix(O, D, tris, 0.0, INF)
        misses += int(np.sum(~np.isfinite(t).any(axis=1)))
        n += len(D)
    assert n > 9900 and misses == 0


# --------------------------------------------------------------------------------------------
# BVH
# --------------------------------------------------------------------------------------------
def _soup(rng, T, size=0.15):
    c = rng.uniform(-1, 1, (T, 1, 3))
    return c + size * rng.normal(size=(T, 3, 3))


def _check_structure(bvh, tris):
    T = len(tris)
    assert sorted(bvh.order.tolist()) == list(range(T))
    assert np.array_equal(bvh.tris, tris[bvh.order]) or degenerate_triangles(tris).any()
    leaves = bvh.child[:, 0] < 0
    assert np.all((bvh.child[:, 1] < 0) == leaves)
    assert np.all(bvh.count[~leaves] == 0) and np.all(bvh.count[leaves] <= LEAF_SIZE)
    covered = np.zeros(T, int)
    for n in np.flatnonzero(leaves):
        covered[bvh.first[n] : bvh.first[n] + bvh.count[n]] += 1
        box = bvh.bounds[n]
        tt = bvh.tris[bvh.first[n] : bvh.first[n] + bvh.count[n]]
        assert np.all(tt >= box[0]) and np.all(tt <= box[1])
    assert np.all(covered == 1)
    for n in np.flatnonzero(~leaves):
        for ch in bvh.child[n]:
            assert np.all(bvh.bounds[ch, 0] >= bvh.bounds[n, 0])
            assert np.all(bvh.bounds[ch, 1] <= bvh.bounds[n, 1])
    # depth below the stack size
    depth, todo = 0, [(0, 1)]
    while todo:
        n, k = todo.pop()
        depth = max(depth, k)
        if bvh.child[n, 0] >= 0:
            todo += [(bvh.child[n, 0], k + 1), (bvh.child[n, 1], k + 1)]
    assert depth < STACK_SIZE


def _rays(rng, R, spread=2.0):
    O = rng.uniform(-spread, spread, (R, 3))
    D = rng.normal(size=(R, 3)) * rng.uniform(0.1, 10, (R, 1))
    # some axis-parallel rays, some starting exactly on box planes
    D[: R // 10, 1:] = 0.0
    D[R // 10 : R // 5, :2] = 0.0
    return O, D


@pytest.mark.reference
@pytest.mark.parametrize("T", [100, 700, 2000])
def test_bvh_equals_brute_force(T):
    rng = np.random.default_rng(T)
    tris = _soup(rng, T)
    bvh = build_bvh(tris)
    _check_structure(bvh, tris)
    O, D = _rays(rng, 1000)
    O[:50] = bvh.bounds[rng.integers(0, len(bvh.bounds), 50), 0]  # origins on box corners
    t_b, i_b, uv = _bvh_batch(O, D, 0.0, INF, *bvh[:4], bvh.tris)
    tm = _tri_matrix(O, D, tris, 0.0, INF)
    t_ref = tm.min(axis=1)
    hit = np.isfinite(t_ref)
    assert 0.03 < hit.mean() < 0.95
    assert np.array_equal(np.isfinite(t_b), hit)
    assert np.all(np.abs(t_b[hit] - t_ref[hit]) <= 1e-12 * t_ref[hit])
    assert np.all(i_b[~hit] == -1)
    # the same triangle, unless another one is hit at the very same t (a tie)
    orig = bvh.order[i_b[hit]]
    assert np.all(tm[np.flatnonzero(hit), orig] == t_ref[hit])
    assert np.mean(orig == tm[hit].argmin(axis=1)) > 0.999
    # (u, v) locate the hit point
    tri = bvh.tris[i_b[hit]]
    P = (1 - uv[hit].sum(1))[:, None] * tri[:, 0] + uv[hit, :1] * tri[:, 1] + uv[hit, 1:] * tri[:, 2]
    assert np.allclose(P, O[hit] + t_b[hit, None] * D[hit], rtol=0, atol=1e-9)
    # tmin / tmax windows
    t_w, _, _ = _bvh_batch(O, D, 0.5, 2.0, *bvh[:4], bvh.tris)
    tm_w = np.where((tm > 0.5) & (tm < 2.0), tm, INF).min(axis=1)
    assert np.array_equal(t_w, tm_w)


@pytest.mark.analytic
def test_bvh_empty_single_duplicate():
    rng = np.random.default_rng(5)
    O, D = _rays(rng, 300)
    empty = build_bvh(np.zeros((0, 3, 3)))
    assert empty.bounds.shape == (1, 2, 3) and empty.child.tolist() == [[-1, -1]] and empty.count[0] == 0
    t, i, _ = _bvh_batch(O, D, 0.0, INF, *empty[:4], empty.tris)
    assert np.all(t == INF) and np.all(i == -1)
    assert len(build_bvh([]).order) == 0

    one = np.array([[V0, V1, V2]])
    b1 = build_bvh(one)
    _check_structure(b1, one)
    t, i, uv = _bvh_batch(np.array([[0.25, 0.25, 1.0], [0.6, 0.6, 1.0]]), np.array([[0, 0, -1.0]] * 2),
                          0.0, INF, *b1[:4], b1.tris)
    assert t.tolist() == [1.0, INF] and i.tolist() == [0, -1] and uv[0].tolist() == [0.25, 0.25]

    # 1000 copies of one triangle plus points and slivers: builds, leaf sizes kept, finds hits
    base = rng.normal(size=(3, 3))
    pts = np.repeat(rng.normal(size=(50, 1, 3)), 3, axis=1)
    tris = np.concatenate([np.repeat(base[None], 1000, axis=0), pts, _soup(rng, 200)])
    bvh = build_bvh(tris)
    _check_structure(bvh, tris)
    target = base.mean(axis=0)
    O = target + _random_unit(rng, 200) * 3
    t, i, _ = _bvh_batch(O, target - O, 0.0, INF, *bvh[:4], bvh.tris)
    tm = _tri_matrix(O, target - O, tris, 0.0, INF)
    assert np.array_equal(t, tm.min(axis=1)) and np.all(t < INF)

    with pytest.raises(ValueError):
        build_bvh(np.full((2, 3, 3), np.nan))
    stack = np.empty(STACK_SIZE, dtype=np.int64)
    o = _tup(target + 1.0)
    assert intersect_bvh(o, O3, 0.0, INF, *bvh[:4], bvh.tris, stack) == (INF, -1, 0.0, 0.0)
    with pytest.raises(ValueError):
        intersect_bvh(o, (1.0, 0.0, 0.0), 0.0, INF, *bvh[:4], bvh.tris, np.empty(8, np.int64))


@pytest.mark.reference
@pytest.mark.parametrize("s, shift", [(1e-3, 0.0), (1e3, 0.0), (1e-3, 1e5), (1.0, 1e5), (1e3, 1e5)])
def test_bvh_scaled_and_shifted(s, shift):
    """x -> s x + shift (rays too, directions unchanged): the same triangles at t' = s t."""
    rng = np.random.default_rng(99)
    tris = _soup(rng, 1000)
    O, D = _rays(rng, 2000)
    base = build_bvh(tris)
    t0, i0, _ = _bvh_batch(O, D, 0.0, INF, *base[:4], base.tris)
    sh = np.array([shift, -0.7 * shift, 0.3 * shift])
    moved = build_bvh(tris * s + sh)
    t1, i1, _ = _bvh_batch(O * s + sh, D, 0.0, INF, *moved[:4], moved.tris)
    hit0, hit1 = np.isfinite(t0), np.isfinite(t1)
    assert np.mean(hit0 != hit1) < 2e-3  # rays within rounding of a silhouette edge
    both = hit0 & hit1
    same = base.order[i0[both]] == moved.order[i1[both]]
    assert same.mean() > 0.998
    # distances agree to rounding: 1e-12 relative, plus a few ulps of the shifted coordinates
    # (relative to the scene: 2.2e-16 shift / s) along the ray, i.e. divided by cos(theta)
    tri = base.tris[i0[both][same]]
    nrm = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    dd = D[both][same]
    cos = np.abs(np.einsum("ij,ij->i", nrm, dd)) / np.linalg.norm(nrm, axis=1) / np.linalg.norm(dd, axis=1)
    dist_err = np.abs(t1[both][same] / s - t0[both][same]) * np.linalg.norm(dd, axis=1)
    dist = t0[both][same] * np.linalg.norm(dd, axis=1)
    assert np.all(dist_err <= 1e-12 * dist + 16 * 2.2e-16 * shift / s / cos)


def _adversarial(case, rng):
    """Triangle sets that stress the builder (see test_bvh_adversarial_equals_brute_force)."""
    if case == "duplicates":  # 3 triangles 300 times each, and a few others
        base = rng.normal(size=(3, 3, 3))
        return np.concatenate([np.tile(base, (300, 1, 1)), _soup(rng, 100)])
    if case == "collinear":  # zero-area triangles (collinear, repeated vertices) among others
        a, b = rng.normal(size=(2, 200, 1, 3))
        s = rng.uniform(0, 1, (200, 3, 1))
        lines = a + s * (b - a)
        points = np.repeat(rng.normal(size=(100, 1, 3)), 3, axis=1)
        return np.concatenate([lines, points, _soup(rng, 500)])
    if case == "grid":  # axis-aligned triangles on an exact grid: many equal centre coordinates
        g = np.stack(np.meshgrid(np.arange(12.0), np.arange(12.0), np.arange(6.0), indexing="ij"), -1).reshape(-1, 3)
        tri = np.stack([g, g + [0.9, 0, 0], g + [0, 0.9, 0]], axis=1)
        return (tri - 6.0) / 6.0
    if case == "same centre":  # different triangles with one bounding-box centre: no bin split
        ang = rng.uniform(0, np.pi, 400)
        r = rng.uniform(0.1, 1, (400, 1))
        u = np.stack([np.cos(ang), np.sin(ang), np.zeros(400)], axis=1) * r
        w = np.array([0.0, 0.0, 1.0]) * r
        return np.stack([u + w, -u + w, -w * 0 + u * 0 - w], axis=1)
    if case == "peeling":  # sizes 16**-k at the origin: every other centre is in the largest
        size = 16.0 ** -np.arange(100.0)  # one's first bin, so binned SAH can only peel it off
        tri = np.zeros((100, 3, 3))
        tri[:, 1, 0] = size
        tri[:, 2, 1] = size
        tri[:, :, 2] = rng.uniform(0.5, 1, (100, 1)) * size[:, None]
        return tri
    raise ValueError(case)


@pytest.mark.reference
@pytest.mark.parametrize("scale_", [1.0, 1e90, 1e-90])
@pytest.mark.parametrize("case", ["duplicates", "collinear", "grid", "same centre"])
def test_bvh_adversarial_equals_brute_force(case, scale_):
    """Against the brute-force nearest hit over all (non-degenerate) triangles, at huge and tiny
    coordinates too (1e±90: the triangle test's products of three coordinates stay finite and
    normal): the same distance for every ray, and the tree's structure holds.  (Not the peeling
    set, whose triangles down to 1e-120 are far below the rounding of a ray origin at distance
    1: the triangle test may report a hit on a triangle whose box the ray misses by an ulp.)"""
    rng = np.random.default_rng(len(case))
    shift = 3.0 * scale_
    tris = _adversarial(case, rng) * scale_ + shift
    bvh = build_bvh(tris)
    _check_structure(bvh, tris)
    good = ~degenerate_triangles(tris)
    assert (case == "collinear") == (not good.all())
    # rays aimed at random points of random triangles, and random rays
    k = rng.integers(0, len(tris), 700)
    bary = rng.dirichlet(np.ones(3), 700)
    target = np.einsum("ij,ijk->ik", bary, tris[k])
    O = np.concatenate([target + _random_unit(rng, 700) * 2.0 * scale_, rng.uniform(-2, 2, (300, 3)) * scale_])
    D = np.concatenate([target - O[:700], rng.normal(size=(300, 3))])
    O[700:] += shift
    t_b, i_b, _ = _bvh_batch(O, D, 0.0, INF, *bvh[:4], bvh.tris)
    t_ref = _tri_matrix(O, D, tris[good], 0.0, INF).min(axis=1)
    assert np.array_equal(t_b, t_ref)
    assert np.isfinite(t_ref).mean() > 0.5
    assert good[bvh.order[i_b[np.isfinite(t_b)]]].all()  # a degenerate triangle is never hit


@pytest.mark.analytic
def test_bvh_depth_is_bounded_where_sah_would_peel(monkeypatch):
    """The peeling set makes a pure SAH tree one level per triangle (100), deeper than the
    traversal stack; the object-median levels keep it below 33 + log2(T / 4)."""
    import tracer.prepare.bvh as bvh_module

    tris = _adversarial("peeling", np.random.default_rng(0))
    bvh = build_bvh(tris)
    _check_structure(bvh, tris)
    monkeypatch.setattr(bvh_module, "_SAH_MAX_DEPTH", 10**6)
    with pytest.raises(RuntimeError, match="exceeds the traversal stack"):
        build_bvh(tris)


@pytest.mark.reference
def test_bvh_parallel_build_is_the_serial_tree(monkeypatch):
    """Above 2 PARALLEL_MIN triangles the subtrees below the top are built in numba threads:
    the same tree (triangle order, leaves) as one thread building it all, the same arrays for
    one and two threads, and the brute-force nearest hits."""
    import numba

    import tracer.prepare.bvh as bvh_module

    rng = np.random.default_rng(42)
    tris = _soup(rng, 2 * bvh_module.PARALLEL_MIN + 5000, size=0.02)
    threads = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = build_bvh(tris)
        numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))
        two = build_bvh(tris)
    finally:
        numba.set_num_threads(threads)
    assert all(np.array_equal(a, b) for a, b in zip(one, two))
    monkeypatch.setattr(bvh_module, "PARALLEL_MIN", 10**9)
    serial = build_bvh(tris)

    def leaves(b):
        leaf = b.child[:, 0] < 0
        return sorted(zip(b.first[leaf].tolist(), b.count[leaf].tolist()))

    assert np.array_equal(serial.order, two.order) and leaves(serial) == leaves(two)
    assert len(serial.bounds) == len(two.bounds)
    _check_structure(two, tris)
    O, D = _rays(rng, 300)
    t_b, _, _ = _bvh_batch(O, D, 0.0, INF, *two[:4], two.tris)
    assert np.array_equal(t_b, _tri_matrix(O, D, tris, 0.0, INF).min(axis=1))


@pytest.mark.api
def test_bvh_overwrite_collapses_in_place_only_when_asked():
    tris = np.array([[[0.0, 0, 0], [1, 1, 1], [2, 2, 2]], [[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]])
    copy = tris.copy()
    build_bvh(tris)
    assert np.array_equal(tris, copy)  # not touched
    b = build_bvh(tris, overwrite=True)
    assert np.array_equal(tris[0], np.repeat(copy[0, :1], 3, axis=0)) and np.array_equal(tris[1], copy[1])
    assert sorted(b.order.tolist()) == [0, 1]


# --------------------------------------------------------------------------------------------
# Spawned rays: no self-intersection, nothing obvious missed, at any scale and offset
# --------------------------------------------------------------------------------------------
_SPHERES = np.array([[0.0, 0.0, 0.0, 1.0], [2.5, 0.3, -0.5, 0.7], [-2.2, 1.0, 0.5, 0.9]])


def _scene(s, shift):
    rng = np.random.default_rng(1)
    v, tet = _tetrahedron(rng)
    # a closed tetrahedron inside the unit ball around (0.3, -2.6, 0.8), clear of the rest
    tet = (tet - v.mean(0)) / np.linalg.norm(v - v.mean(0), axis=1).max() + np.array([0.3, -2.6, 0.8])
    floor = np.array([[-6, -4, -6], [6, -4, -6], [6, -4, 6], [-6, -4, 6.0]])
    tris = np.concatenate([tet, floor[None, [0, 2, 1]], floor[None, [0, 3, 2]]])
    sh = np.array([shift, -0.7 * shift, 0.3 * shift])
    sph = _SPHERES.copy()
    sph[:, :3] = sph[:, :3] * s + sh
    sph[:, 3] *= s
    tris = tris * s + sh
    return sph, tris, sh


@pytest.mark.analytic
@pytest.mark.parametrize(
    "s, shift", [(1.0, 0.0), (1e-3, 0.0), (1e3, 0.0), (5e-5, 1e5), (1e-3, 1e5), (1.0, 1e5), (1e3, 1e5)]
)
def test_spawned_rays_never_self_intersect(s, shift):
    """Reflected and transmitted rays spawned with offset_origin(p, +-n, origin_epsilon(...)).

    Never again the surface they leave (spheres from outside, planar triangles), except where
    the geometry says so: a ray entering a sphere leaves it after the chord 2 r cos(theta),
    and so does a ray reflected inside it; a ray entering the closed tetrahedron leaves it
    through another face.  Scene ~20 units across, scaled by s (5e-5: 1e-3 across) and moved
    by ~1e5.
    """
    sph, tris, sh = _scene(s, shift)
    bvh = build_bvh(tris)
    in_tet = np.isin(bvh.order, [0, 1, 2, 3])
    rng = np.random.default_rng(int(s * 1e3) + int(shift))
    R = 4000
    cam = _random_unit(rng, R) * 9 * s + sh
    cam[:, 1] = np.abs(cam[:, 1] - sh[1]) + sh[1]  # above the floor
    target = rng.uniform(-3, 3, (R, 3))
    tet_centre = (bvh.tris[in_tet].reshape(-1, 3).mean(0) - sh) / s
    target[: R // 4] = rng.uniform(-0.5, 0.5, (R // 4, 3)) + tet_centre  # a quarter at the tetrahedron
    target = target * s + sh
    D = (target - cam) / s  # |d| ~ 1..10: t is in scene units / s
    all_pts = np.concatenate([cam, tris.reshape(-1, 3), sph[:, :3]])
    size = np.linalg.norm(all_pts.max(0) - all_pts.min(0)) + 2 * sph[:, 3].max()
    eps = origin_epsilon(size, np.abs(all_pts).max())
    args = (sph, *bvh[:4], bvh.tris, eps)

    hit, geo = _bounce(cam, D, *args)
    assert not np.isnan(hit[:, 0]).any()
    kind, idx = hit[:, 1], hit[:, 2]
    on_sph, on_tri = kind == 0, kind == 1
    assert on_sph.sum() > 500 and on_tri.sum() > 500 and np.all(hit[on_sph, 3] == 1)

    h_rf, _ = _bounce(geo[:, 2][kind >= 0], geo[:, 3][kind >= 0], *args)
    h_tr, g_tr = _bounce(geo[:, 4][kind >= 0], D[kind >= 0], *args)
    k0, i0, cos0 = kind[kind >= 0], idx[kind >= 0], hit[kind >= 0, 4]
    same_rf = (h_rf[:, 1] == k0) & (h_rf[:, 2] == i0)
    same_tr = (h_tr[:, 1] == k0) & (h_tr[:, 2] == i0)
    # reflected from outside a sphere, or from a plane: never the same surface
    assert not same_rf.any()
    # triangles: the transmitted ray never hits its own triangle; into the tetrahedron -> out
    assert not same_tr[k0 == 1].any()
    tri_i = i0.astype(int)
    into_tet = (k0 == 1) & in_tet[np.where(k0 == 1, tri_i, 0)]
    n_tri = geo[kind >= 0, 1]
    centre = bvh.tris[in_tet].reshape(-1, 3).mean(0)
    going_in = np.einsum("ij,ij->i", D[kind >= 0], n_tri) * np.einsum(
        "ij,ij->i", geo[kind >= 0, 0] - centre, n_tri) < 0
    # (except within 100 eps of an edge, where the moved origin may rightly be outside)
    p_hit = geo[kind >= 0, 0]
    tri = bvh.tris[np.where(k0 == 1, tri_i, 0)]
    edge_dist = np.full(len(k0), np.inf)
    for a, b in ((0, 1), (1, 2), (2, 0)):
        e, w = tri[:, b] - tri[:, a], p_hit - tri[:, a]
        f = np.clip(np.einsum("ij,ij->i", w, e) / np.einsum("ij,ij->i", e, e), 0, 1)
        edge_dist = np.minimum(edge_dist, np.linalg.norm(w - f[:, None] * e, axis=1))
    exits = into_tet & going_in & (edge_dist > 100 * eps)
    assert exits.sum() > 50
    assert np.all(h_tr[exits, 1] == 1) and np.all(in_tet[h_tr[exits, 2].astype(int)])
    # spheres: the transmitted ray leaves through the far side after the chord 2 r cos
    sp = k0 == 0
    assert np.all(same_tr[sp]) and np.all(h_tr[sp, 3] == 0)
    r = sph[i0[sp].astype(int), 3]
    dlen = np.linalg.norm(D[kind >= 0][sp], axis=1)
    chord = h_tr[sp, 0] * dlen
    ok = cos0[sp] > 1e-3
    assert np.all(np.abs(chord - 2 * r * cos0[sp])[ok] <= 4 * eps / cos0[sp][ok] + 1e-12 * r[ok])
    # second bounce inside the sphere: out again (never the same sphere), or reflected inside
    h_out, _ = _bounce(g_tr[sp, 4], D[kind >= 0][sp], *args)
    assert not ((h_out[:, 1] == 0) & (h_out[:, 2] == i0[sp])).any()
    h_in, _ = _bounce(g_tr[sp, 2], g_tr[sp, 3], *args)
    assert np.all((h_in[:, 1] == 0) & (h_in[:, 2] == i0[sp]))
    chord_in = h_in[:, 0] * np.linalg.norm(g_tr[sp, 3], axis=1)
    assert np.all(np.abs(chord_in - 2 * r * cos0[sp])[ok] <= 8 * eps / cos0[sp][ok] + 1e-12 * r[ok])


@pytest.mark.analytic
def test_offset_needs_the_coordinate_term():
    """Why 64 eps max|x|: a scene 1e-3 across at 1e5 (coordinate ulps 1.5e-11, i.e. 1.5e-8 of
    the scene) re-hits the surfaces it leaves with no offset or with only the scene-relative
    1e-9 S; with origin_epsilon it never does."""
    s = 5e-5
    sph, tris, sh = _scene(s, 1e5)
    bvh = build_bvh(tris)
    rng = np.random.default_rng(0)
    R = 4000
    cam = _random_unit(rng, R) * 9 * s + sh
    cam[:, 1] = np.abs(cam[:, 1] - sh[1]) + sh[1]
    D = (rng.uniform(-3, 3, (R, 3)) * s + sh - cam) / s
    size = 20 * s
    counts = {}
    offsets = (("none", 0.0), ("relative", 1e-9 * size), ("origin_epsilon", origin_epsilon(size, 1.1e5)))
    for name, eps in offsets:
        hit, geo = _bounce(cam, D, sph, *bvh[:4], bvh.tris, eps)
        k = hit[:, 1] >= 0
        h_rf, _ = _bounce(geo[k, 2], geo[k, 3], sph, *bvh[:4], bvh.tris, eps)
        h_tr, _ = _bounce(geo[k, 4], D[k], sph, *bvh[:4], bvh.tris, eps)
        self_rf = (h_rf[:, 1] == hit[k, 1]) & (h_rf[:, 2] == hit[k, 2])
        self_tr = (h_tr[:, 1] == 1) & (hit[k, 1] == 1) & (h_tr[:, 2] == hit[k, 2])
        counts[name] = int(self_rf.sum() + self_tr.sum())
    assert counts["origin_epsilon"] == 0
    assert counts["none"] > 100 and counts["relative"] > 10, counts
