"""Numba geometry kernels of the ray tracer: vectors, spheres, triangles, BVH traversal,
ray-origin offsets.

Every per-ray kernel is ``@njit(cache=True, error_model="numpy")``, allocates nothing, and
never returns NaN for finite input.  Vectors are plain ``(x, y, z)`` tuples of float64 (numba
``UniTuple(float64, 3)``); "no hit" is ``t = inf``.  Ray directions need not be unit length:
a hit at parameter *t* is the point ``o + t d``.

Floating-point model: :math:`\\varepsilon = 2^{-52} \\approx 2.2\\times10^{-16}` (the spacing
of doubles at 1; a correctly rounded operation has relative error at most
:math:`u = \\varepsilon/2`), :math:`\\gamma_n = nu/(1-nu)` (Higham, *Accuracy and Stability of
Numerical Algorithms*, 2nd ed., §3.1).

Sources
-------
* Spheres: Haines, Günther & Akenine-Möller, "Precision Improvements for Ray/Sphere
  Intersection", *Ray Tracing Gems* (2019), ch. 7; re-projection of the hit point onto the
  surface as in Pharr, Jakob & Humphreys, *Physically Based Rendering*, 3rd ed., §3.9.4.
* Triangles: Woop, Benthin & Wald, "Watertight Ray/Triangle Intersection", *JCGT* 2(1), 2013;
  smooth shading (:func:`shading_normal`): Phong's interpolated normals (Phong 1975), with a
  fall-back to the geometric normal where the interpolated one would send a mirror ray into the
  surface.
* BVH traversal (:func:`intersect_bvh`; the tree is built by :func:`tracer.prepare.bvh.build_bvh`,
  which re-exports it): Ize, "Robust BVH Ray Traversal", *JCGT* 2(2), 2013.
* Origin offsets: Pharr et al., §3.9.5 ("Robust spawned ray origins"), simplified to a single
  scene-wide epsilon (see :func:`origin_epsilon`).
"""

import math

import numpy as np
from numba import njit
from bubbleoptics.jit import JIT

__all__ = [
    "normalize",
    "intersect_sphere",
    "sphere_hit_point",
    "ray_shear",
    "intersect_triangle_sheared",
    "shading_normal",
    "STACK_SIZE",
    "intersect_bvh",
    "ORIGIN_EPS_RELATIVE",
    "ORIGIN_EPS_ULPS",
    "origin_epsilon",
    "offset_origin",
    "degenerate_triangles",
]


_INF = np.inf
_EPS = 2.0**-52  # spacing of doubles at 1 (np.finfo(float).eps)
# dot(v, v) between these bounds neither overflows nor loses precision to underflow
_SQ_SMALL = 1e-290
_SQ_LARGE = 1e290


# --------------------------------------------------------------------------------------------
# Vectors
# --------------------------------------------------------------------------------------------
@njit(**JIT)
def normalize(a):
    """:math:`a/|a|`; the zero vector (and a non-finite one) maps to ``(0, 0, 0)``, never NaN."""
    s = a[0] * a[0] + a[1] * a[1] + a[2] * a[2]
    if s > _SQ_SMALL and s < _SQ_LARGE:
        inv = 1.0 / math.sqrt(s)
        return (a[0] * inv, a[1] * inv, a[2] * inv)
    m = max(abs(a[0]), abs(a[1]), abs(a[2]))
    if not (m > 0.0 and m < _INF):
        return (0.0, 0.0, 0.0)
    x, y, z = a[0] / m, a[1] / m, a[2] / m
    inv = 1.0 / math.sqrt(x * x + y * y + z * z)
    return (x * inv, y * inv, z * inv)


# --------------------------------------------------------------------------------------------
# Spheres
# --------------------------------------------------------------------------------------------
@njit(**JIT)
def intersect_sphere(o, d, center, radius, tmin, tmax):
    """Nearest intersection of the ray :math:`o + t d` with a sphere, :math:`t_{min} < t < t_{max}`.

    Returns ``(t, entering)``: *t* (``inf`` if none) and whether it is the first root (the ray
    crosses from outside to inside; ``False`` for the second root, leaving the sphere).

    With :math:`f = o - c` and :math:`a = d\\cdot d` the roots of
    :math:`|f + t d|^2 = r^2` are :math:`t = (b' \\pm \\sqrt{a\\Delta})/a`, where

    .. math::

        b' = -f\\cdot d,\\qquad
        a\\Delta = r^2 a - |f \\times d|^2 ,

    since :math:`b'^2 - a(|f|^2 - r^2) = r^2 a - (|f|^2|d|^2 - (f\\cdot d)^2)` and the bracket is
    :math:`|f\\times d|^2` (Lagrange's identity).  :math:`|f\\times d|/\\sqrt a` is the distance
    from the centre to the ray's line, the :math:`|\\ell|` of Haines et al. (2019, eq. 7.5,
    :math:`\\ell = f - (f\\cdot d/a)\\,d`); formed from the cross product's components it keeps
    its accuracy when the sphere is tiny and far away, where the textbook :math:`b^2 - 4ac` is
    the difference of two huge, nearly equal numbers, and it needs no division (a test against
    a sphere the ray misses costs no division and no square root: docs/performance.md).  The
    roots then follow without subtracting nearly equal numbers (Press et al., *Numerical
    Recipes*, §5.6):

    .. math::

        q = b' + \\operatorname{sign}(b')\\sqrt{a\\Delta},\\qquad
        t_0 = c/q,\\quad t_1 = q/a,\\qquad c = |f|^2 - r^2 .

    A tangent ray (:math:`\\Delta = 0` exactly) gives the double root once; if also
    :math:`b' = 0` (origin at the tangent point) then :math:`q = c = 0` and the root is
    :math:`t = 0` (not 0/0).  :math:`a\\Delta < 0`, also from rounding, is a miss.  A zero
    direction or a radius :math:`\\le 0` never hits.
    """
    a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
    if not (a > 0.0) or not (radius > 0.0):
        return _INF, False
    f = (o[0] - center[0], o[1] - center[1], o[2] - center[2])
    bq = -(f[0] * d[0] + f[1] * d[1] + f[2] * d[2])
    cx = f[1] * d[2] - f[2] * d[1]
    cy = f[2] * d[0] - f[0] * d[2]
    cz = f[0] * d[1] - f[1] * d[0]
    disc_a = radius * radius * a - (cx * cx + cy * cy + cz * cz)  # a * Delta
    if not (disc_a >= 0.0):
        return _INF, False
    h = math.sqrt(disc_a)
    q = bq + h if bq >= 0.0 else bq - h
    if q == 0.0:  # b' = 0 and Delta = 0: tangent at the origin itself
        t0 = 0.0
        t1 = 0.0
    else:
        c = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]) - radius * radius
        t0 = c / q
        t1 = q / a
        if t0 > t1:
            t0, t1 = t1, t0
    if t0 > tmin and t0 < tmax:
        return t0, True
    if t1 > tmin and t1 < tmax:
        return t1, False
    return _INF, False


@njit(**JIT)
def sphere_hit_point(o, d, t, center, radius):
    """Hit point re-projected onto the sphere, and the outward unit normal: ``(p, n)``.

    :math:`n = \\operatorname{normalize}(f + t d)` with :math:`f = o - c`, and
    :math:`p = c + r\\,n`.  Re-projection removes the error of :math:`o + t d`, whose distance
    from the surface is :math:`O(\\varepsilon\\,|t d|)` along the ray (large for distant
    origins); what remains is a few ulps of the coordinates of *p* (Pharr et al., §3.9.4).
    A degenerate input (``f + t d = 0``) gives ``n = (0, 0, 0)``, ``p = c``, not NaN.
    """
    v = (o[0] - center[0] + t * d[0], o[1] - center[1] + t * d[1], o[2] - center[2] + t * d[2])
    n = normalize(v)
    p = (center[0] + radius * n[0], center[1] + radius * n[1], center[2] + radius * n[2])
    return p, n


# --------------------------------------------------------------------------------------------
# Triangles
# --------------------------------------------------------------------------------------------
@njit(**JIT)
def ray_shear(d):
    """Per-ray set-up of the watertight triangle test: ``(kx, ky, kz, sx, sy, sz)``.

    *kz* is the axis of the largest :math:`|d_k|` (ties: the lowest axis), *kx*, *ky* the two
    following axes cyclically, swapped when :math:`d_{kz} < 0` so the winding (and the sign of
    the edge functions) is kept; :math:`s_x = d_{kx}/d_{kz}`, :math:`s_y = d_{ky}/d_{kz}`,
    :math:`s_z = 1/d_{kz}` (Woop et al. 2013, fig. 1).  A zero direction gives ``sz = 0``,
    which :func:`intersect_triangle_sheared` treats as "never hits".
    """
    ax = abs(d[0])
    ay = abs(d[1])
    az = abs(d[2])
    kz = 0
    m = ax
    if ay > m:
        kz = 1
        m = ay
    if az > m:
        kz = 2
        m = az
    kx = kz + 1
    if kx == 3:
        kx = 0
    ky = kx + 1
    if ky == 3:
        ky = 0
    dz = d[kz]
    if not (m > 0.0):
        return 0, 1, 2, 0.0, 0.0, 0.0
    if dz < 0.0:
        kx, ky = ky, kx
    return kx, ky, kz, d[kx] / dz, d[ky] / dz, 1.0 / dz


@njit(**JIT)
def intersect_triangle_sheared(o, kx, ky, kz, sx, sy, sz, v0, v1, v2, tmin, tmax):
    """Watertight ray/triangle intersection (Woop, Benthin & Wald, JCGT 2013); both faces hit.

    The ray is ``o + t d`` with its set-up ``(kx, ky, kz, sx, sy, sz) = ray_shear(d)`` done
    once per ray (the BVH traversal tests many triangles with it).

    Returns ``(t, u, v)`` with the hit point :math:`(1-u-v)v_0 + u v_1 + v v_2` (Möller and
    Trumbore's barycentric convention), or ``(inf, 0, 0)``.

    The axes are permuted so that :math:`d_z` is the largest direction component and the
    vertices, taken relative to *o*, are sheared so that the ray becomes the +z axis:
    :math:`A_x = A_{kx} - s_x A_{kz}`, :math:`A_y = A_{ky} - s_y A_{kz}` (same for *B*, *C*).
    The 2D edge functions

    .. math::  U = C_xB_y - C_yB_x,\\quad V = A_xC_y - A_yC_x,\\quad W = B_xA_y - B_yA_x

    are the scaled barycentrics of the origin; the ray hits iff they are all :math:`\\ge 0` or
    all :math:`\\le 0` with :math:`\\det = U+V+W \\ne 0`, and
    :math:`t = (U s_z A_{kz} + V s_z B_{kz} + W s_z C_{kz})/\\det`.

    Why watertight: a vertex's sheared coordinates depend only on the vertex and the ray, so an
    edge shared by two triangles gets edge functions computed from identical operands in
    opposite order, i.e. exactly opposite values; and rounding is monotone, so the computed
    :math:`\\operatorname{fl}(\\operatorname{fl}(ab) - \\operatorname{fl}(cd))` has the sign of
    :math:`ab - cd` or is zero.  A ray truly inside a triangle (of the rounded, sheared
    vertices) therefore always passes the sign test: no ray slips between two triangles.

    The paper computes in single precision and recomputes *U*, *V*, *W* in double when one
    is exactly zero, to get its exact sign.  That fallback is not needed here: we already work
    in float64, and a spuriously zero edge function counts as "on the edge", which can only
    add a hit within rounding distance of an edge (two triangles may both report it), never
    lose one.  The integrator takes the nearest hit, so a double report is harmless.

    Zero-area triangles: repeated vertices give :math:`\\det = 0` exactly (no hit), but
    collinear vertices whose sheared coordinates are rounded may be reported hit on the segment
    (finite *t*, *u*, *v*; never NaN).  :func:`tracer.prepare.bvh.build_bvh` collapses such triangles
    (:func:`degenerate_triangles`), so :func:`intersect_bvh` never returns them.
    """
    if sz == 0.0:
        return _INF, 0.0, 0.0
    # vertices relative to the origin, each vertex transformed the same way in every triangle
    a0 = v0[0] - o[0]
    a1 = v0[1] - o[1]
    a2 = v0[2] - o[2]
    b0 = v1[0] - o[0]
    b1 = v1[1] - o[1]
    b2 = v1[2] - o[2]
    c0 = v2[0] - o[0]
    c1 = v2[1] - o[1]
    c2 = v2[2] - o[2]
    A = (a0, a1, a2)
    B = (b0, b1, b2)
    C = (c0, c1, c2)
    az_ = A[kz]
    bz_ = B[kz]
    cz_ = C[kz]
    ax = A[kx] - sx * az_
    ay = A[ky] - sy * az_
    bx = B[kx] - sx * bz_
    by = B[ky] - sy * bz_
    cx = C[kx] - sx * cz_
    cy = C[ky] - sy * cz_
    # scaled barycentrics (2D edge functions)
    U = cx * by - cy * bx
    V = ax * cy - ay * cx
    W = bx * ay - by * ax
    if (U < 0.0 or V < 0.0 or W < 0.0) and (U > 0.0 or V > 0.0 or W > 0.0):
        return _INF, 0.0, 0.0
    det = U + V + W
    if det == 0.0:  # degenerate in projection, or the ray lies in the triangle's plane
        return _INF, 0.0, 0.0
    T = U * (sz * az_) + V * (sz * bz_) + W * (sz * cz_)
    inv = 1.0 / det
    t = T * inv
    if not (t > tmin and t < tmax):  # also rejects NaN
        return _INF, 0.0, 0.0
    return t, V * inv, W * inv


@njit(**JIT)
def shading_normal(v0, v1, v2, n0, n1, n2, ng, p, d):
    """Smooth-shading normal at *p* on the triangle (v0, v1, v2), for a ray with direction *d*.

    The corner normals *n0*, *n1*, *n2* (unit, on the side of the unit geometric normal *ng*:
    :func:`tracer.prepare.meshes.corner_normals`) are interpolated with the barycentric coordinates of
    *p* (Phong, "Illumination for computer generated pictures", *CACM* 18(6), 1975),

    .. math::  \\lambda_1 = \\frac{((p - v_0)\\times e_2)\\cdot n_g}{(e_1\\times e_2)\\cdot n_g},\\quad
               \\lambda_2 = \\frac{(e_1\\times(p - v_0))\\cdot n_g}{(e_1\\times e_2)\\cdot n_g},\\quad
               \\lambda_0 = 1 - \\lambda_1 - \\lambda_2,

    clamped to the triangle (:math:`\\lambda_k \\ge 0`, summing to 1; *p* is ``o + t d``, a few
    ulps off the plane), and normalised: :math:`n_s`.  It is returned only where it is
    consistent with the geometry the ray sees; otherwise *ng* is returned (the fall-back to flat
    shading at that point):

    * the ray must arrive on the same side of both: :math:`\\operatorname{sign}(d\\cdot n_s) =
      \\operatorname{sign}(d\\cdot n_g) \\ne 0`;
    * the mirror direction :math:`r = d - 2(d\\cdot n_s)n_s` must leave on the incoming side of
      the geometric plane: with :math:`n_f` = *ng* turned towards the ray,
      :math:`r\\cdot n_f = d\\cdot n_f - 2 (d\\cdot n_s)(n_s\\cdot n_f) > 0`.

    The interpolated normal can violate both near a silhouette, where the ray grazes the
    geometric plane but the shading normal is tilted away from the ray; a mirror ray sent into
    the surface would then start in front of it and hit it from behind.  (The side of the ray,
    the ray-origin offset and "entering" stay the geometric normal's, in the integrator.)
    Never NaN for finite input: a zero interpolated normal or a degenerate triangle gives *ng*.
    """
    dg = d[0] * ng[0] + d[1] * ng[1] + d[2] * ng[2]
    if not (dg > 0.0 or dg < 0.0):
        return ng
    sg = -1.0 if dg > 0.0 else 1.0  # turns ng (and n_s) towards the ray
    e1x = v1[0] - v0[0]
    e1y = v1[1] - v0[1]
    e1z = v1[2] - v0[2]
    e2x = v2[0] - v0[0]
    e2y = v2[1] - v0[1]
    e2z = v2[2] - v0[2]
    wx = p[0] - v0[0]
    wy = p[1] - v0[1]
    wz = p[2] - v0[2]
    den = ((e1y * e2z - e1z * e2y) * ng[0] + (e1z * e2x - e1x * e2z) * ng[1]
           + (e1x * e2y - e1y * e2x) * ng[2])
    b1 = ((wy * e2z - wz * e2y) * ng[0] + (wz * e2x - wx * e2z) * ng[1] + (wx * e2y - wy * e2x) * ng[2]) / den
    b2 = ((e1y * wz - e1z * wy) * ng[0] + (e1z * wx - e1x * wz) * ng[1] + (e1x * wy - e1y * wx) * ng[2]) / den
    if not (b1 > 0.0):  # also NaN (den = 0)
        b1 = 0.0
    if not (b2 > 0.0):
        b2 = 0.0
    b0 = 1.0 - b1 - b2
    if b0 < 0.0:
        s = b1 + b2
        b1 = b1 / s
        b2 = b2 / s
        b0 = 0.0
    ns = normalize((b0 * n0[0] + b1 * n1[0] + b2 * n2[0], b0 * n0[1] + b1 * n1[1] + b2 * n2[1],
                    b0 * n0[2] + b1 * n1[2] + b2 * n2[2]))
    ds = sg * (d[0] * ns[0] + d[1] * ns[1] + d[2] * ns[2])  # d . n_s turned towards the ray
    if not (ds < 0.0):  # also the zero normal
        return ng
    cos_sg = ns[0] * ng[0] + ns[1] * ng[1] + ns[2] * ng[2]
    if not (sg * dg - 2.0 * ds * cos_sg > 0.0):
        return ng
    return ns


# --------------------------------------------------------------------------------------------
# BVH traversal (the builder is tracer.prepare.bvh.build_bvh)
# --------------------------------------------------------------------------------------------
#: Length of the BVH traversal stack; :func:`tracer.prepare.bvh.build_bvh` keeps trees shallower.
STACK_SIZE = 64

_U = 2.0**-53  # unit roundoff
_GAMMA3 = 3 * _U / (1 - 3 * _U)
_WIDEN = 2.0 * _GAMMA3  # Ize 2013 / pbrt: far slab distances times 1 + 2 gamma_3


@njit(**JIT)
def _slab(o, inv, bounds, node, tmin, tmax):
    """Robust ray/box test (Ize 2013): ``(hit, t_enter)`` for :math:`[t_{min}, t_{max}]`.

    Per axis, with the near plane picked by the sign of ``inv`` (so ``-0`` directions work),
    :math:`t_{near} = (p_{near} - o)\\,inv`, :math:`t_{far} = (p_{far} - o)\\,inv\\,(1 + 2\\gamma_3)`;
    the running max/min update only on a true comparison, which ignores the NaN of
    ``0 * inf`` (origin exactly on a slab plane of an axis the ray is parallel to).
    """
    tn = tmin
    tf = tmax
    for k in range(3):
        i = inv[k]
        if i >= 0.0:
            near = bounds[node, 0, k]
            far = bounds[node, 1, k]
        else:
            near = bounds[node, 1, k]
            far = bounds[node, 0, k]
        t0 = (near - o[k]) * i
        t1 = (far - o[k]) * i
        if t1 > 0.0:
            t1 = t1 * (1.0 + _WIDEN)
        else:
            t1 = t1 * (1.0 - _WIDEN)
        if t0 > tn:
            tn = t0
        if t1 < tf:
            tf = t1
    return tn <= tf, tn


@njit(**JIT)
def intersect_bvh(o, d, tmin, tmax, bounds, child, first, count, tris, stack):
    """Nearest triangle hit of the ray :math:`o + t d`, :math:`t_{min} < t < t_{max}`.

    Returns ``(t, i, u, v)``: *i* indexes ``tris`` (the BVH's reordered copy; the input
    triangle is ``order[i]``), ``(u, v)`` as in :func:`intersect_triangle_sheared`;
    no hit is ``(inf, -1, 0, 0)``.  ``stack`` is an int64 scratch array of at least
    :data:`STACK_SIZE` entries (``np.empty(STACK_SIZE, np.int64)``, one per thread).  Among hits at exactly equal *t* the one
    found first wins.

    Depth first: at an interior node both children's boxes are tested, the nearer one is
    visited next and the farther one pushed; a popped node is tested again against the
    current nearest hit, so boxes beyond it are skipped.
    """
    if stack.shape[0] < STACK_SIZE:
        raise ValueError("intersect_bvh: the stack must have at least STACK_SIZE entries")
    inv = (1.0 / d[0], 1.0 / d[1], 1.0 / d[2])
    kx, ky, kz, sx, sy, sz = ray_shear(d)
    best_t = tmax
    best_i = -1
    best_u = 0.0
    best_v = 0.0
    hit, _ = _slab(o, inv, bounds, 0, tmin, best_t)
    if not hit:
        return np.inf, -1, 0.0, 0.0
    node = 0
    sp = 0
    while True:
        left = child[node, 0]
        if left < 0:
            s = first[node]
            for i in range(s, s + count[node]):
                v0 = (tris[i, 0, 0], tris[i, 0, 1], tris[i, 0, 2])
                v1 = (tris[i, 1, 0], tris[i, 1, 1], tris[i, 1, 2])
                v2 = (tris[i, 2, 0], tris[i, 2, 1], tris[i, 2, 2])
                t, u, v = intersect_triangle_sheared(o, kx, ky, kz, sx, sy, sz, v0, v1, v2, tmin, best_t)
                if t < best_t:
                    best_t = t
                    best_i = i
                    best_u = u
                    best_v = v
        else:
            right = child[node, 1]
            hl, tl = _slab(o, inv, bounds, left, tmin, best_t)
            hr, tr = _slab(o, inv, bounds, right, tmin, best_t)
            if hl and hr:
                if tr < tl:
                    left, right = right, left
                stack[sp] = right
                sp += 1
                node = left
                continue
            if hl:
                node = left
                continue
            if hr:
                node = right
                continue
        # pop the next box still in front of the nearest hit
        found = False
        while sp > 0:
            sp -= 1
            n = stack[sp]
            h, _ = _slab(o, inv, bounds, n, tmin, best_t)
            if h:
                node = n
                found = True
                break
        if not found:
            break
    if best_i < 0:
        return np.inf, -1, 0.0, 0.0
    return best_t, best_i, best_u, best_v


# --------------------------------------------------------------------------------------------
# Spawned-ray origins
# --------------------------------------------------------------------------------------------
#: Offset per unit of scene size (see :func:`origin_epsilon`).
ORIGIN_EPS_RELATIVE = 1e-9
#: Offset in units of :math:`\varepsilon\,\max|x|`, the spacing of doubles at the coordinates.
ORIGIN_EPS_ULPS = 64.0


def origin_epsilon(scene_scale, max_abs_coordinate):
    """Distance by which secondary-ray origins are moved off a surface.

    .. math::  \\epsilon = 10^{-9}\\,S + 64\\,\\varepsilon\\,X ,

    *S* = the scene's size (:meth:`tracer.scene.Scene.scale`), *X* = the largest absolute
    coordinate in the scene (camera included), :math:`\\varepsilon = 2^{-52}`.

    Why proportional: a computed hit point is off the true surface by a *relative* error.
    Coordinates carry an absolute rounding error of up to :math:`\\varepsilon X` each (a scene
    1 mm across placed at :math:`10^5` has coordinate ulps of :math:`1.5\\times10^{-11}`,
    i.e. :math:`10^{-8}` of its size), and every quantity the intersection tests form from them
    (``v - o``, the sheared coordinates, :math:`f = o - c`) inherits a few of those ulps; and
    ``o + t d`` adds an error of a few :math:`\\varepsilon\\,|t d| \\lesssim \\varepsilon S`
    (pbrt's error bounds, Pharr et al. §3.9, are sums of such terms with constants
    :math:`\\gamma_n`, :math:`n \\le 7`).  A fixed offset is too small for a
    large or far-off scene and needlessly large for a small one.

    The constants: the distance of a computed hit point from its surface, and the error of
    the signed distance of a new origin to that surface as the next test computes it, are both
    bounded by small multiples of :math:`\\gamma_n(S + X)`, :math:`n \\le 7`: of order
    :math:`10\\,\\varepsilon(S+X)` (the grazing-angle growth of *t*'s error is along the ray;
    its component across the surface stays of this size).  64 ulps of the coordinates is
    several times that for the part set by *X*, which dominates when a small scene sits far from the
    origin.  The :math:`10^{-9} S` term (about :math:`4.5\\times10^{6}\\,\\varepsilon S`) is a
    wide margin for error sources not analysed here (normals or hit points the integrator forms
    its own way, e.g. ``o + t d`` or barycentric interpolation), yet a nanometre in a metre-sized
    scene, :math:`10^{5}` times below one pixel of a 10k-pixel image, so no visible geometry is
    skipped (a bubble's film thickness is not geometry: the film is a surface).
    """
    scene_term = ORIGIN_EPS_RELATIVE * abs(float(scene_scale))
    return scene_term + ORIGIN_EPS_ULPS * _EPS * abs(float(max_abs_coordinate))


@njit(**JIT)
def offset_origin(p, n, eps):
    """``p + eps * n``: a new ray origin moved off the surface at *p*.

    The caller passes the normal already oriented towards the side the new ray leaves on
    (``+n`` for a reflected ray, ``-n`` for a transmitted one) and *eps* from
    :func:`origin_epsilon`.  *n* should be unit length.
    """
    return (p[0] + eps * n[0], p[1] + eps * n[1], p[2] + eps * n[2])


# --------------------------------------------------------------------------------------------
# Zero-area triangles (the scene loaders skip them; the BVH build collapses any left)
# --------------------------------------------------------------------------------------------
@njit(**JIT)
def _degenerate_nb(tris, out):
    """``out[i]`` = triangle *i* has zero area (see :func:`degenerate_triangles`)."""
    for i in range(tris.shape[0]):
        size = 0.0
        for k in range(3):
            for a in range(3):
                size = max(size, abs(tris[i, k, a]))
        if not (size > 0.0):
            out[i] = True
            continue
        e = math.frexp(size)[1]
        if e < -1000:  # below 1e-301: no test could hit it (nor scale it: 2**1000 is the limit)
            out[i] = True
            continue
        s = math.ldexp(1.0, -e)  # scale by 2**-e: exact, and no squares under- or overflow
        x0 = tris[i, 0, 0] * s
        y0 = tris[i, 0, 1] * s
        z0 = tris[i, 0, 2] * s
        x1 = tris[i, 1, 0] * s
        y1 = tris[i, 1, 1] * s
        z1 = tris[i, 1, 2] * s
        x2 = tris[i, 2, 0] * s
        y2 = tris[i, 2, 1] * s
        z2 = tris[i, 2, 2] * s
        e1x = x1 - x0
        e1y = y1 - y0
        e1z = z1 - z0
        e2x = x2 - x0
        e2y = y2 - y0
        e2z = z2 - z0
        e3x = x2 - x1
        e3y = y2 - y1
        e3z = z2 - z1
        cx = e1y * e2z - e1z * e2y
        cy = e1z * e2x - e1x * e2z
        cz = e1x * e2y - e1y * e2x
        area2 = math.sqrt(cx * cx + cy * cy + cz * cz)
        longest = math.sqrt(max(e1x * e1x + e1y * e1y + e1z * e1z, e2x * e2x + e2y * e2y + e2z * e2z,
                                e3x * e3x + e3y * e3y + e3z * e3z))
        out[i] = not (area2 > 16.0 * _EPS * (size * s) * longest)


def degenerate_triangles(tris):
    """Boolean mask of zero-area triangles: height :math:`\\le 16\\varepsilon\\max|x|`.

    The height over the longest edge, :math:`h = |e_1\\times e_2|/\\max_k|e_k|`
    (:math:`e_1 = v_1 - v_0`, :math:`e_2 = v_2 - v_0`), is compared with 16 ulps of the
    triangle's largest coordinate :math:`\\max|x|`: a triangle thinner than the rounding of its
    own vertices cannot be told from a segment (e.g. a vertex computed as
    :math:`a + s(b - a)` is off the line by up to ~2 ulps).  This flags repeated and collinear
    vertices, and nothing any image could show.  Why it is needed: the watertight test rejects a
    zero-area triangle only when its edge functions cancel exactly; for collinear vertices whose
    sheared coordinates are rounded it may report a "hit" on the segment, with no defined normal.
    The one test of a zero-area face: the scene loaders skip the faces it flags, with a
    warning (:mod:`tracer.scene.block_format`, :mod:`tracer.scene.toml_read`), and
    :func:`tracer.prepare.bvh.build_bvh`
    collapses any left in a mesh built in code.  One numba pass (no (T, 3) temporaries); each
    triangle is first scaled by the power of two nearest its size (exact), so the squares in
    the test neither underflow (coordinates ~1e-150) nor overflow (~1e150); a triangle within
    1e-301 of the origin counts as zero area.
    """
    tris = np.ascontiguousarray(np.asarray(tris, dtype=np.float64).reshape(-1, 3, 3))
    out = np.empty(tris.shape[0], dtype=np.bool_)
    _degenerate_nb(tris, out)
    return out
