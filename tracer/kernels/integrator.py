"""The Whitted integrator (numba): light transport only.

Per camera sample, an explicit stack of rays (origin, direction, per-channel throughput w,
generation; generation 1 is the camera ray).  A ray that leaves the scene adds
w × environment.  At a hit the surface (:mod:`tracer.kernels.surfaces`, which this module never looks
inside) tells what it adds from the ambient light and from each light (through a shadow ray
that multiplies the transmittance of everything it crosses: one to a point light, one per
sample direction to a spherical light, :func:`sphere_light`; the radiometry, falloff included,
is on :class:`tracer.scene.PointLight`), and the weights of
its two children, a mirror ray and a transmitted ray.  A child is traced if its generation is
at most ``depth`` and, when ``threshold > 0``, the largest channel of its throughput exceeds
``threshold``; a light's shadow ray is cast only if the light's largest possible contribution
exceeds ``threshold`` (``threshold = 0`` traces every child with a non-zero weight and every
shadow ray: the coursework's exhaustive tree).

**No energy is dropped where a branch is cut.**  A child that is not traced, for depth or for
pruning, ends with what the environment sends along its direction, times the surface's cut
factor: 1 in general, and for a child that stays inside a bubble the closed form
:math:`T/(1-R)` of all the light it would still send out of the bubble
(:mod:`tracer.kernels.surfaces.soap_film`).  This is exact for every lossless surface in a uniform
environment (R + T = 1 for a film, F + (1 − F) = 1 for clear glass: the throughputs of a
ray's descendants sum to its own) and for an absorbing uniform film bubble in one.  The bias
it leaves, elsewhere: a cut child is assumed to escape, so the environment stands in for
whatever object it would have hit; inside a bubble, the light of all the later inner bounces
is sent along the first exit's direction instead of along each chord's; the inner series
assumes nothing else inside the bubble, and for a non-uniform film uses the film where the
child starts.  Pruned shadow rays drop their light (at most ``threshold`` each).

Ray counts per row (``counts``): camera, reflected, transmitted, shadow
(:data:`tracer.kernels.records.RAY_COUNT_KINDS`).

Speed (docs/performance.md): a camera ray that misses everything is resolved in the pixel
loop itself (one intersection test and an environment lookup, converted to RGB by
``rgb_round_trip``), so empty parts of the image cost about what a minimal kernel costs.  The
per-ray code (:func:`render_rows` and what it inlines) is compiled without numba's reference
counting, and the helpers that take the scene or the workspace are inlined
(``inline="always"``): a non-inlined call copies those tuples of arrays.  A ray that enters a
sphere carries the cosine it entered with (chords meet both ends at one angle), which lets the
films reuse their set-up along the path, and a ray that leaves a sphere outward skips it.
"""

import math
from typing import NamedTuple

import numpy as np
from numba import njit
from bubbleoptics.jit import JIT, JIT_INLINE, JIT_NO_NRT

from bubbleoptics.kernels import N_FILM_COEFFICIENTS

from .surfaces import (film_scatter, film_shadow, film_toward_light, phong_ambient, phong_scatter, phong_shadow,
                       phong_toward_light)
from .environment import environment_rgb
from .geometry import intersect_bvh, intersect_sphere, offset_origin, shading_normal, sphere_hit_point
from .records import FALLOFF_INVERSE_SQUARE, SURFACE_FILM
from .sampling import camera_ray, cone_sample, orthonormal_basis, sample_key, stratified_offset

__all__ = [
    "GEOM_NONE",
    "GEOM_SPHERE",
    "GEOM_TRIANGLE",
    "MAX_SHADOW_CROSSINGS",
    "N_COUNTS",
    "Workspace",
    "new_workspace",
    "closest_hit",
    "light_terms",
    "shadow_transmittance",
    "shadow_along",
    "sphere_light",
    "render_rows",
    "scene_features",
    "FEATURES",
]

#: The per-ray functions are compiled without numba's reference counting (``_nrt=False``): they
#: allocate nothing and only read arrays their caller keeps alive, and with it every read of an
#: array field of the scene or the workspace costs a call to NRT_incref and NRT_decref, which
#: would be most of a ray's time (docs/performance.md says how that is measured).

GEOM_NONE = 0
GEOM_SPHERE = 1
GEOM_TRIANGLE = 2
#: A shadow ray crosses at most this many surfaces (then counts as unblocked).
MAX_SHADOW_CROSSINGS = 64
N_COUNTS = 4
_BVH_STACK = 64  # tracer.kernels.geometry.STACK_SIZE
#: An inverse-square light nearer than this (squared distance, scene units) lights nothing, as
#: one exactly on the surface does: its 1/r^2 would overflow.
_R2_MIN = 1e-300


class Workspace(NamedTuple):
    """One thread's scratch arrays (:func:`new_workspace`), reused by every row the thread renders."""

    stack_o: np.ndarray  # (S, 3) ray origins
    stack_d: np.ndarray  # (S, 3) directions
    stack_w: np.ndarray  # (S, C) throughputs
    stack_gen: np.ndarray  # (S,) generations
    stack_inside: np.ndarray  # (S,) int64: the sphere whose chord the ray runs along (-1: none)
    stack_chord: np.ndarray  # (S,) cos(theta) at the chord's start (its end meets it the same)
    stack_skip: np.ndarray  # (S,) int64: the sphere the ray leaves outward (-1: none)
    w: np.ndarray  # (C,) the current ray's throughput
    wr: np.ndarray  # (C,) mirror child's weight (a surface model's scatter)
    wt: np.ndarray  # (C,) transmitted child's weight
    cut_r: np.ndarray  # (C,) cut factors of the two children
    cut_t: np.ndarray
    child: np.ndarray  # (C,) a child's throughput
    light_w: np.ndarray  # (C,) a surface model's answer toward a light
    trans: np.ndarray  # (C,) shadow-ray transmittance
    R_shadow: np.ndarray  # (C,) a film crossed by a shadow ray
    T_shadow: np.ndarray
    L: np.ndarray  # (C,) radiance of the camera ray
    bvh_stack: np.ndarray  # (64,) int64
    film_coef_cos: np.ndarray  # (B,) cos(theta) of each film's kept set-up (-1: none)
    film_coef: np.ndarray  # (B, C, N_FILM_COEFFICIENTS) complex: bubbleoptics.kernels.film_setup_nb
    free_kq: np.ndarray  # (B, C) bubbleoptics.kernels.free_film_setup_nb (lossless films): kq,
    free_Fs: np.ndarray  # F_s,
    free_Fp: np.ndarray  # F_p
    film_kq: np.ndarray  # (B, C + 1) band-edge phase rates (band-averaged films)
    film_rt_cos: np.ndarray  # (B,) cos(theta) of a uniform film's kept R, T (-1: none)
    film_R: np.ndarray  # (B, C)
    film_T: np.ndarray
    counts: np.ndarray  # (N_COUNTS,) int64 rays by kind
    ones: np.ndarray  # (C,) 1.0
    cancel: np.ndarray  # (1,) int64 shared by every thread: stop as soon as it is non-zero


def new_workspace(scene, depth, cancel):
    """A :class:`Workspace` for *scene* and trace depth *depth* (its ray stack holds
    ``depth + 8`` rays: a depth-first walk keeps at most one pending sibling per level), and
    the shared cancel flag *cancel*.

    Plain NumPy, called from Python once per render thread
    (:func:`tracer.rendering.local.rows_call`): a compiled allocator cost the first render about
    1.5 s of compile, and the films' kept set-ups then last the whole render."""
    nc = scene.rgb_basis.shape[0]
    nb = scene.films.shape[0]
    size = depth + 8
    return Workspace(
        np.empty((size, 3)), np.empty((size, 3)), np.empty((size, nc)), np.empty(size, dtype=np.int64),
        np.empty(size, dtype=np.int64), np.empty(size), np.empty(size, dtype=np.int64),
        np.empty(nc), np.empty(nc), np.empty(nc), np.empty(nc), np.empty(nc), np.empty(nc), np.empty(nc),
        np.empty(nc), np.empty(nc), np.empty(nc), np.empty(nc),
        np.empty(_BVH_STACK, dtype=np.int64),
        np.full(nb, -1.0), np.empty((nb, nc, N_FILM_COEFFICIENTS), dtype=np.complex128),
        np.empty((nb, nc)), np.empty((nb, nc)), np.empty((nb, nc)), np.empty((nb, nc + 1)),
        np.full(nb, -1.0), np.empty((nb, nc)), np.empty((nb, nc)),
        np.zeros(N_COUNTS, dtype=np.int64), np.ones(nc), cancel,
    )


@njit(**JIT_INLINE)
def closest_hit(scene, ws, o, d, tmin, tmax, skip, mesh):
    """``(geometry kind, index, t, entering)`` of the nearest surface along o + t d with
    tmin < t < tmax; kind :data:`GEOM_NONE` and t = tmax when there is none.  Sphere *skip*
    (-1: none) is not tested: a ray leaving a sphere outward cannot meet it again."""
    best = tmax
    kind = GEOM_NONE
    idx = -1
    entering = True
    spheres = scene.spheres
    for i in range(spheres.shape[0]):
        if i == skip:
            continue
        s = spheres[i]
        c = s.center
        t, ent = intersect_sphere(o, d, (c[0], c[1], c[2]), s.radius, tmin, best)
        if t < best:
            best, kind, idx, entering = t, GEOM_SPHERE, i, ent
    if mesh is not None and scene.tris.shape[0] > 0:  # (no meshes: pruned when compiled)
        t, ti, _, _ = intersect_bvh(o, d, tmin, best, scene.bvh_bounds, scene.bvh_child, scene.bvh_first,
                                    scene.bvh_count, scene.tris, ws.bvh_stack)
        if t < best:
            best, kind, idx = t, GEOM_TRIANGLE, ti
            nrm = scene.triangles[ti].normal
            entering = d[0] * nrm[0] + d[1] * nrm[1] + d[2] * nrm[2] < 0.0
    return kind, idx, best, entering


@njit(**JIT_INLINE)
def surface_at(scene, kind, idx, o, d, t, mesh):
    """``(surface kind, surface index, point, outward unit normal)`` of a hit (sphere hit
    points re-projected onto the sphere).

    On a triangle the normal is its geometric one, or with smooth shading
    (``triangles[idx].smooth``) the interpolated vertex normal
    (:func:`tracer.kernels.geometry.shading_normal`), which is on the same side of the ray as the
    geometric one (:func:`offset_normal` gives that one for the ray origins)."""
    if mesh is None or kind == GEOM_SPHERE:
        s = scene.spheres[idx]
        c = s.center
        p, n = sphere_hit_point(o, d, t, (c[0], c[1], c[2]), s.radius)
        return s.surface, s.index, p, n
    tri = scene.triangles[idx]
    nrm = tri.normal
    p = (o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2])
    ng = (nrm[0], nrm[1], nrm[2])
    if not tri.smooth:
        return tri.surface, tri.index, p, ng
    v = scene.tris
    vn = tri.vertex_normals
    n = shading_normal((v[idx, 0, 0], v[idx, 0, 1], v[idx, 0, 2]), (v[idx, 1, 0], v[idx, 1, 1], v[idx, 1, 2]),
                       (v[idx, 2, 0], v[idx, 2, 1], v[idx, 2, 2]), (vn[0, 0], vn[0, 1], vn[0, 2]),
                       (vn[1, 0], vn[1, 1], vn[1, 2]), (vn[2, 0], vn[2, 1], vn[2, 2]), ng, p, d)
    return tri.surface, tri.index, p, n


@njit(**JIT_INLINE)
def offset_normal(scene, kind, idx, nf, sgn, mesh):
    """The unit normal, facing the incoming ray, along which the new rays of a hit start
    (:func:`tracer.kernels.geometry.offset_origin`): *nf* (the facing normal from :func:`surface_at`
    turned by *sgn*) on a sphere, the geometric normal turned by *sgn* on a triangle, so that
    a smooth triangle's tilted shading normal never moves an origin off its side of the plane."""
    if mesh is not None and kind == GEOM_TRIANGLE:
        g = scene.triangles[idx].normal
        return (sgn * g[0], sgn * g[1], sgn * g[2])
    return nf


@njit(**JIT_INLINE)
def add_environment(scene, L, w, factor, d):
    """``L += w * factor * environment(d)`` per channel (*factor* per channel too); nothing to
    add where the environment is black (the coursework's scenes: every escaping ray)."""
    r, g, b = environment_rgb(scene.environment[0], scene.env_image, d)
    if r == 0.0 and g == 0.0 and b == 0.0:
        return
    basis = scene.rgb_basis_t  # (3, C): contiguous per primary, so that this loop vectorizes
    b0 = basis[0]
    b1 = basis[1]
    b2 = basis[2]
    for c in range(L.shape[0]):
        L[c] += w[c] * factor[c] * (b0[c] * r + b1[c] * g + b2[c] * b)


@njit(**JIT_INLINE)
def light_terms(lpos, p, nf, d):
    """(N.L, R.V) for the light at *lpos* seen from *p*: the cosine between the facing normal
    *nf* and the direction to the light, and between the light's mirror direction about *nf*
    and the direction to the viewer (-d) — the two cosines of the Phong terms of the
    coursework's eq. 1.4.  R.V is 0 when the light is behind the surface (N.L <= 0)."""
    lx = lpos[0] - p[0]
    ly = lpos[1] - p[1]
    lz = lpos[2] - p[2]
    ln = math.sqrt(lx * lx + ly * ly + lz * lz)
    if not ln > 0.0:
        return 0.0, 0.0  # a light exactly on the surface lights nothing (and makes no NaN)
    inv = 1.0 / ln
    ndl = (lx * nf[0] + ly * nf[1] + lz * nf[2]) * inv
    if ndl <= 0.0:
        return ndl, 0.0
    rl = 2.0 * ndl
    rv = -((rl * nf[0] - lx * inv) * d[0] + (rl * nf[1] - ly * inv) * d[1] + (rl * nf[2] - lz * inv) * d[2])
    return ndl, max(rv, 0.0)


@njit(**JIT_INLINE)
def direction_terms(u, nf, d):
    """(N.L, R.V) of :func:`light_terms` for the unit direction *u* toward the light."""
    ndl = u[0] * nf[0] + u[1] * nf[1] + u[2] * nf[2]
    if not ndl > 0.0:
        return 0.0, 0.0
    rl = 2.0 * ndl
    rv = -((rl * nf[0] - u[0]) * d[0] + (rl * nf[1] - u[1]) * d[1] + (rl * nf[2] - u[2]) * d[2])
    return ndl, max(rv, 0.0)


@njit(**JIT_INLINE)
def shadow_transmittance(scene, ws, p, lpos, trans, mesh, film, phong, xfilm):
    """Transmittance per channel (into *trans*) from *p* to the light at *lpos*; False if zero."""
    dx = lpos[0] - p[0]
    dy = lpos[1] - p[1]
    dz = lpos[2] - p[2]
    dist = math.sqrt(dx * dx + dy * dy + dz * dz)
    if not dist > 0.0:
        for c in range(trans.shape[0]):
            trans[c] = 1.0
        return True
    return shadow_along(scene, ws, p, (dx / dist, dy / dist, dz / dist), dist, trans, mesh, film, phong, xfilm)


@njit(no_cpython_wrapper=True, no_cfunc_wrapper=True, **JIT_NO_NRT)  # not inlined: one compiled shadow path for point and spherical lights
def shadow_along(scene, ws, p, d, dist, trans, mesh, film, phong, xfilm):
    """Transmittance per channel (into *trans*) of the shadow ray from *p* along the unit
    direction *d* up to the distance *dist* (may be inf); False if zero."""
    for c in range(trans.shape[0]):
        trans[c] = 1.0
    ws.counts[3] += 1
    tstart = 0.0
    for _ in range(MAX_SHADOW_CROSSINGS):
        kind, idx, t, entering = closest_hit(scene, ws, p, d, tstart, dist, -1, mesh)
        if kind == GEOM_NONE:
            return True
        skind, sidx, q, n = surface_at(scene, kind, idx, p, d, t, mesh)
        cos_i = abs(d[0] * n[0] + d[1] * n[1] + d[2] * n[2])
        # the surface model of the hit, chosen here (not in a helper): see the note on FEATURES
        if film is not None and (phong is None or skind == SURFACE_FILM):
            passes = film_shadow(scene, ws, sidx, n, cos_i, entering, trans, xfilm)
        elif phong is not None:
            passes = phong_shadow(scene, ws, sidx, n, cos_i, entering, trans)
        else:
            passes = True
        if not passes:
            return False
        tstart = t + scene.eps
        alive = False
        for c in range(trans.shape[0]):
            if trans[c] > 0.0:
                alive = True
        if not alive:
            return False
    return True


@njit(no_cpython_wrapper=True, no_cfunc_wrapper=True, **JIT_NO_NRT)  # not inlined: a scene without spherical lights never compiles it
def sphere_light(scene, ws, j, c, p, p_front, nf, d, hit, skind, sidx, w, key, vertex, threshold, mesh, film, phong, xfilm):
    """Add to ``ws.L`` what spherical light *j* (centre *c*) sends to the viewer from the hit
    *hit* at *p* (surface *skind*, *sidx*; facing normal *nf*, incoming direction *d*) for
    throughput *w*: ``S · 2/(1 + cos α) · (1/N) Σ_k f(ω_k) V(ω_k)`` over N directions ω_k
    stratified uniformly over the cone of half-angle α that the sphere subtends
    (:class:`tracer.scene.PointLight` gives the radiometry and sources).

    f(ω_k) is the surface model's answer toward a light (:mod:`tracer.kernels.surfaces`) with N·L and R·V
    of the direction ω_k (diffuse, Phong and film highlights alike), V(ω_k) the transmittance
    of a shadow ray from *p_front* along ω_k to where it meets the sphere's near side.  A
    point inside the sphere (or on it) samples the whole sphere of directions, whose weight is
    4 (Ω / (π sin²α) with Ω = 4π, sin α = 1), and meets the far side; no NaN anywhere (d = 0
    included).  The directions are :func:`tracer.kernels.sampling.cone_sample` of the camera sample's
    *key* (:func:`tracer.kernels.sampling.sample_key` of seed, pixel and sample), stream ``vertex * n_lights + j`` (*vertex*:
    the hits before this one in the camera ray's tree) and sample k.  Pruning as for a point
    light, per sample: a sample whose share, times N, is at most *threshold* is skipped (so a
    light drops at most *threshold*)."""
    lt = scene.lights[j]
    a = lt.radius
    n = lt.samples
    rad = scene.light_radiance
    light_w = ws.light_w
    trans = ws.trans
    L = ws.L
    nc = L.shape[0]
    cx = c[0] - p[0]
    cy = c[1] - p[1]
    cz = c[2] - p[2]
    d2 = cx * cx + cy * cy + cz * cz
    a2 = a * a
    if not d2 < np.inf:
        return  # the light is beyond the range of doubles from here (and lights nothing)
    if d2 > a2:
        dist = math.sqrt(d2)
        s2 = a2 / d2  # sin^2(alpha)
        cos_a = math.sqrt(1.0 - s2)
        one_minus_cos = s2 / (1.0 + cos_a)  # no cancellation for a small, far light
        weight = 2.0 / (1.0 + cos_a)
        axis = (cx / dist, cy / dist, cz / dist)
        inside = False
        r2 = d2
    else:
        one_minus_cos = 2.0  # the whole sphere of directions
        weight = 4.0
        axis = (0.0, 0.0, 1.0)
        inside = True
        r2 = a2
    scale = weight / n
    if lt.falloff == FALLOFF_INVERSE_SQUARE:
        if not r2 > _R2_MIN:
            return  # a subnormal sphere around the point: lights nothing, as a point light on it
        scale /= r2  # S = I / (pi max(d, a)^2)
    b1, b2 = orthonormal_basis(axis)
    stream = vertex * scene.lights.shape[0] + j
    for k in range(n):
        om = cone_sample(key, stream, k, n, axis, b1, b2, one_minus_cos)
        ndl, rv = direction_terms(om, nf, d)
        if film is not None and (phong is None or skind == SURFACE_FILM):
            lit = film_toward_light(scene, ws, sidx, hit, ndl, rv, light_w)
        elif phong is not None:
            lit = phong_toward_light(scene, ws, sidx, hit, ndl, rv, light_w)
        else:
            lit = False
        if not lit:
            continue
        if threshold > 0.0:
            bound = 0.0
            for ch in range(nc):
                bound = max(bound, w[ch] * light_w[ch] * (rad[j, ch] * scale))
            if bound * n <= threshold:
                continue
        # where om meets the sphere: t^2 - 2 b t + (d^2 - a^2) = 0 (t may be inf for a huge one)
        b = om[0] * cx + om[1] * cy + om[2] * cz
        disc = max(0.0, b * b - (d2 - a2))  # >= 0 inside the cone, up to rounding at its rim
        t = b + math.sqrt(disc) if inside else max(0.0, b - math.sqrt(disc))
        if shadow_along(scene, ws, p_front, om, t, trans, mesh, film, phong, xfilm):
            for ch in range(nc):
                L[ch] += w[ch] * light_w[ch] * (rad[j, ch] * scale) * trans[ch]


@njit(**JIT_INLINE)
def _push(ws, sp, o, d, w, gen, inside, chord, skip):
    so = ws.stack_o
    sd = ws.stack_d
    sw = ws.stack_w
    for k in range(3):
        so[sp, k] = o[k]
        sd[sp, k] = d[k]
    for c in range(w.shape[0]):
        sw[sp, c] = w[c]
    ws.stack_gen[sp] = gen
    ws.stack_inside[sp] = inside
    ws.stack_chord[sp] = chord
    ws.stack_skip[sp] = skip
    return sp + 1


@njit(**JIT_INLINE)
def _child(scene, ws, sp, L, o, d, weight, cut, gen, depth, threshold, counter, inside, chord, skip):
    """Trace the child (origin *o*, direction *d*, throughput ``ws.w * weight``; running along a
    chord of sphere *inside* met at cos *chord*, or *inside* = -1; leaving sphere *skip*
    outward, or -1) or, if it is cut, end it with the environment along *d* times *cut*.
    Returns the stack pointer."""
    child = ws.child
    w = ws.w
    m = 0.0
    for c in range(child.shape[0]):
        child[c] = w[c] * weight[c]
        m = max(m, child[c])
    if not m > 0.0:
        return sp  # no such lobe
    if gen < depth and (threshold <= 0.0 or m > threshold):
        ws.counts[counter] += 1
        return _push(ws, sp, o, d, child, gen + 1, inside, chord, skip)
    add_environment(scene, L, child, cut, d)
    return sp


#: The features a scene may use, in the order :func:`render_rows` takes their flags.  Each flag is
#: None when the scene has no such feature, and numba then compiles the render without its code
#: (the same pruning as ``spectrum=None``): a first render compiles only what its scene uses, and
#: each combination is cached on disk on its own.
FEATURES = ("mesh", "area", "film", "phong", "xfilm")


def scene_features(scene) -> tuple:
    """The feature flags of the packed scene *scene* (:data:`FEATURES`; True or None each):

    * ``mesh``: it has triangles (the BVH, mesh shading);
    * ``area``: a light has a radius (spherical lights and their sampled shadows);
    * ``film``, ``phong``: a sphere or a triangle carries a soap film, a Phong material;
    * ``xfilm``: a film beyond the lossless Airy film at the band centres (the two-beam model,
      band averages, an absorbing film).

    With the environment variable ``TRACER_FEATURES=all`` every flag is True: one kernel, compiled
    once, serves every scene (for a machine that renders many kinds of scene, and the tests).
    """
    import os

    from .records import FILM_MODEL_TWO_BEAM, SURFACE_FILM, SURFACE_PHONG

    if os.environ.get("TRACER_FEATURES", "") == "all":
        return (True,) * len(FEATURES)

    kinds = set(scene.spheres["surface"].tolist()) | set(scene.triangles["surface"].tolist())
    films = scene.films
    xfilm = scene.band_mode == 1 or bool((films["model"] == FILM_MODEL_TWO_BEAM).any()) or \
        not bool(films["lossless"].all())
    flags = (scene.tris.shape[0] > 0, bool((scene.lights["radius"] > 0.0).any()), SURFACE_FILM in kinds,
             SURFACE_PHONG in kinds, SURFACE_FILM in kinds and xfilm)
    return tuple(True if on else None for on in flags)


@njit(nogil=True, no_cfunc_wrapper=True, **JIT_NO_NRT)
def render_rows(scene, rows, row0, rows_per_task, task0, task_step, width, height, spp, seed, depth, threshold, image, counts,
                spectrum, ws, mesh, area, film, phong, xfilm):
    """Render the rows ``rows`` (int64, distinct, any order, each from *row0* to
    ``row0 + image.shape[0] - 1``) of the (height, width) image into ``image`` (rows, width, 3:
    linear sRGB; image row *y* at ``image[y - row0]``) and their ray counts into ``counts``
    (rows, N_COUNTS).  A whole image is ``row0 = 0`` with arrays of *height* rows; a tile of
    rows ``[row0, row0 + n)`` (:func:`tracer.rendering.local.render_tile`) has arrays of n rows.

    *spectrum*: an array (rows, width, C) float64, C the scene's channels
    (``scene.rgb_basis.shape[0]``), into which each pixel's mean radiance per channel is
    written as well (the RGB pixel is ``scene.to_rgb`` times it, up to rounding), or None.
    numba compiles the two separately and prunes the per-channel code from the None one, so
    the RGB-only render carries no per-channel code (a run-time test instead would cost every
    RGB render a measurable share on the coursework's small scenes, ``benchmarks/throughput.py``);
    the first per-channel render after installing compiles its own variant.

    *mesh*, *area*, *film*, *phong*, *xfilm*: the scene's feature flags (:func:`scene_features`);
    a flag that is None compiles the render without that feature's code.

    *ws*: the calling thread's :class:`Workspace` (:func:`new_workspace`), whose ``cancel``
    (1,) int64 stops the call at its next ray once ``cancel[0]`` is non-zero (set by another
    Python thread: this kernel releases the GIL), leaving the image partial.

    The rows are cut into tasks of *rows_per_task* consecutive entries of *rows*; this call
    renders tasks ``task0, task0 + task_step, ...`` with the workspace *ws*.  The kernel itself is
    serial: :func:`tracer.rendering.local.rows_call` runs one call per thread (``task0`` the
    thread's number, ``task_step`` the number of threads), from Python threads, since the
    kernel releases the GIL.  A ``parallel=True`` loop here cost the first render about 25 s of
    numba's parfor type inference and lowering of the whole inlined integrator
    (docs/performance.md).  Rows are independent (each sample's jitter is a hash of seed,
    pixel and sample, and the films' kept set-ups are pure functions of their key), so any
    split of the rows over calls, tasks and threads gives the same image.

    Per pixel: each camera sample's nearest hit is found in the pixel loop; a miss is the
    environment, straight to RGB; a hit starts the ray tree, walked depth first on the
    workspace's stack: at every hit the surface model (:mod:`tracer.kernels.surfaces`) gives the
    two children, its ambient term and what it sends toward each light (with a shadow ray),
    and the children are pushed (:func:`_child`) or cut and ended with the environment.

    Chords: a ray that enters a sphere, or is reflected inside one, runs along a chord and
    meets the sphere again at the angle it started with.  Such a child carries that cosine, and
    when its next hit is that sphere the surface is evaluated at exactly that cosine (rather
    than the one recomputed from a hit point moved by the ray-origin offset), which keeps the
    chord property exact and lets the film reuse its set-up (:mod:`tracer.kernels.surfaces.soap_film`).

    The loops over tasks, rows, pixels and the tree are one function: numba's
    ``inline="always"`` copies a callee's IR, with all it inlines, into its caller, so every
    level of inlining copies everything below it once more, and a separately compiled callee
    is optimised by LLVM again when it is linked into its caller.  Measured on the first
    compile (docs/performance.md); the warm kernel is the same code.
    """
    n_rows = rows.shape[0]
    n_tasks = (n_rows + rows_per_task - 1) // rows_per_task
    for task in range(task0, n_tasks, task_step):
        for k in range(task * rows_per_task, min(n_rows, (task + 1) * rows_per_task)):
            y = rows[k]
            cam = scene.camera[0]
            env = scene.environment[0]
            o0 = (cam.origin[0], cam.origin[1], cam.origin[2])
            M = scene.rgb_round_trip
            to_rgb = scene.to_rgb
            basis = scene.rgb_basis
            L = ws.L
            w = ws.w
            nc = L.shape[0]
            stack_o = ws.stack_o
            stack_d = ws.stack_d
            stack_w = ws.stack_w
            light_w = ws.light_w
            trans = ws.trans
            rad = scene.light_radiance
            eps = scene.eps
            lights = scene.lights
            cancel = ws.cancel
            ray_counts = ws.counts
            iy = y - row0  # the row's place in the output arrays
            for i in range(N_COUNTS):  # the row's ray counts, from zero
                ray_counts[i] = 0
            for x in range(width):
                if cancel[0] != 0:
                    break
                pix = y * width + x
                r = 0.0
                g = 0.0
                b = 0.0
                if spectrum is not None:  # (None: pruned when compiled)
                    for c in range(nc):
                        spectrum[iy, x, c] = 0.0
                for s in range(spp):
                    fx, fy = stratified_offset(seed, pix, s, spp)
                    d0 = camera_ray(cam, x + fx, y + fy, width, height)
                    ray_counts[0] += 1
                    hit0 = closest_hit(scene, ws, o0, d0, 0.0, np.inf, -1, mesh)
                    if hit0[0] == GEOM_NONE:
                        # a camera ray that meets nothing: the environment, straight to RGB
                        er, eg, eb = environment_rgb(env, scene.env_image, d0)
                        r += M[0, 0] * er + M[0, 1] * eg + M[0, 2] * eb
                        g += M[1, 0] * er + M[1, 1] * eg + M[1, 2] * eb
                        b += M[2, 0] * er + M[2, 1] * eg + M[2, 2] * eb
                        if spectrum is not None:  # the channels the RGB above came from (M = to_rgb @ basis)
                            for c in range(nc):
                                spectrum[iy, x, c] += basis[c, 0] * er + basis[c, 1] * eg + basis[c, 2] * eb
                        continue
                    # the camera ray's tree (see the docstring)
                    key = sample_key(seed, pix, s)
                    for c in range(nc):
                        L[c] = 0.0
                        ws.child[c] = 1.0
                    sp = _push(ws, 0, o0, d0, ws.child, 1, -1, 0.0, -1)
                    first = True
                    vertex = 0  # hits so far in this camera ray's tree (a spherical light's sample stream)
                    while sp > 0:
                        if cancel[0] != 0:
                            break  # cancelled (Ctrl-C): the caller discards the image
                        sp -= 1
                        o = (stack_o[sp, 0], stack_o[sp, 1], stack_o[sp, 2])
                        d = (stack_d[sp, 0], stack_d[sp, 1], stack_d[sp, 2])
                        gen = ws.stack_gen[sp]
                        inside = ws.stack_inside[sp]
                        chord = ws.stack_chord[sp]
                        skip = ws.stack_skip[sp]
                        for c in range(nc):
                            w[c] = stack_w[sp, c]  # the stack slot is reused by the children
                        if first:
                            kind, idx, t, entering = hit0
                            first = False
                        else:
                            kind, idx, t, entering = closest_hit(scene, ws, o, d, 0.0, np.inf, skip, mesh)
                        if kind == GEOM_NONE:
                            add_environment(scene, L, w, ws.ones, d)
                            continue
                        skind, sidx, p, n = surface_at(scene, kind, idx, o, d, t, mesh)
                        dn = d[0] * n[0] + d[1] * n[1] + d[2] * n[2]
                        cos_g = abs(dn)  # geometric cos(theta), for directions
                        sgn = -1.0 if dn > 0.0 else 1.0  # nf = sgn * n faces the incoming ray
                        nf = (sgn * n[0], sgn * n[1], sgn * n[2])
                        nfo = offset_normal(scene, kind, idx, nf, sgn, mesh)  # the geometric side, for ray origins
                        on_sphere = kind == GEOM_SPHERE
                        cos_i = chord if (on_sphere and idx == inside) else cos_g  # for the surface's optics
                        hit = (p, n, nf, d, cos_i, entering)
                        # the hit's surface model, chosen here by kind behind the feature flags (see the note
                        # on FEATURES): its two children's weights into ws.wr, ws.wt, and the transmitted direction
                        if film is not None and (phong is None or skind == SURFACE_FILM):
                            tdir = film_scatter(scene, ws, sidx, hit, xfilm)
                        elif phong is not None:
                            tdir = phong_scatter(scene, ws, sidx, hit)
                        else:
                            tdir = d
                        p_front = offset_origin(p, nfo, eps)
                        # local terms: ambient and the lights
                        if phong is not None and (film is None or skind != SURFACE_FILM):
                            phong_ambient(scene, sidx, w, L)  # (a film has no ambient term)
                        for j in range(lights.shape[0]):
                            lt = lights[j]
                            lp = lt.position
                            lpos = (lp[0], lp[1], lp[2])
                            if area is not None and lt.radius > 0.0:  # (no spherical lights: pruned when compiled)
                                sphere_light(scene, ws, j, lpos, p, p_front, nf, d, hit, skind, sidx, w, key, vertex, threshold,
                                             mesh, film, phong, xfilm)
                                continue
                            scale = 1.0  # the strength's falloff: rad * 1.0 is rad exactly, so "none" leaves it unchanged
                            if lt.falloff == FALLOFF_INVERSE_SQUARE:
                                r2 = (lpos[0] - p[0]) ** 2 + (lpos[1] - p[1]) ** 2 + (lpos[2] - p[2]) ** 2
                                if not r2 > _R2_MIN:
                                    continue  # a light on the surface lights nothing (light_terms) and makes no inf
                                scale = 1.0 / r2
                            ndl, rv = light_terms(lpos, p, nf, d)
                            if film is not None and (phong is None or skind == SURFACE_FILM):
                                lit = film_toward_light(scene, ws, sidx, hit, ndl, rv, light_w)
                            elif phong is not None:
                                lit = phong_toward_light(scene, ws, sidx, hit, ndl, rv, light_w)
                            else:
                                lit = False
                            if not lit:
                                continue
                            if threshold > 0.0:
                                bound = 0.0
                                for c in range(nc):
                                    bound = max(bound, w[c] * light_w[c] * (rad[j, c] * scale))
                                if bound <= threshold:
                                    continue  # this light can add at most `threshold` here: pruned
                            if shadow_transmittance(scene, ws, p_front, lpos, trans, mesh, film, phong, xfilm):
                                for c in range(nc):
                                    L[c] += w[c] * light_w[c] * (rad[j, c] * scale) * trans[c]
                        vertex += 1
                        # children: transmitted first (deeper in the stack), reflected on top; on a sphere the
                        # one that ends up inside runs along a chord
                        p_back = offset_origin(p, nfo, -eps)
                        refl = (d[0] + 2.0 * cos_g * nf[0], d[1] + 2.0 * cos_g * nf[1], d[2] + 2.0 * cos_g * nf[2])
                        # (on a sphere the one that ends up outside leaves it for good: it need not be tested)
                        t_inside = -1
                        t_chord = 0.0
                        t_skip = -1
                        r_inside = -1
                        r_skip = -1
                        if on_sphere and entering:
                            t_inside = idx
                            t_chord = cos_i if (tdir[0] == d[0] and tdir[1] == d[1] and tdir[2] == d[2]) else \
                                abs(tdir[0] * n[0] + tdir[1] * n[1] + tdir[2] * n[2])
                            r_skip = idx
                        elif on_sphere:
                            r_inside = idx
                            t_skip = idx
                        # one inlined copy of _child for both: numba copies an inlined callee, with all it inlines,
                        # at every call site, and the second copy cost a first render about 1 s of LLVM's function
                        # passes; the loop costs about 1 % more instructions warm (docs/performance.md)
                        for side in range(2):
                            if side == 0:
                                c_o, c_d, c_w, c_cut, c_n, c_in, c_ch, c_sk = p_back, tdir, ws.wt, ws.cut_t, 2, t_inside, t_chord, t_skip
                            else:
                                c_o, c_d, c_w, c_cut, c_n, c_in, c_ch, c_sk = p_front, refl, ws.wr, ws.cut_r, 1, r_inside, cos_i, r_skip
                            sp = _child(scene, ws, sp, L, c_o, c_d, c_w, c_cut, gen, depth, threshold, c_n, c_in, c_ch, c_sk)
                    for c in range(nc):
                        r += to_rgb[0, c] * L[c]
                        g += to_rgb[1, c] * L[c]
                        b += to_rgb[2, c] * L[c]
                    if spectrum is not None:
                        for c in range(nc):
                            spectrum[iy, x, c] += L[c]
                image[iy, x, 0] = r / spp
                image[iy, x, 1] = g / spp
                image[iy, x, 2] = b / spp
                if spectrum is not None:
                    for c in range(nc):
                        spectrum[iy, x, c] /= spp
            for i in range(N_COUNTS):
                counts[iy, i] = ray_counts[i]
