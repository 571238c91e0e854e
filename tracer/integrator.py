"""The Whitted integrator (numba): the only module that knows the whole algorithm.

Per camera sample, an explicit stack of rays (origin, direction, per-channel throughput,
generation).  A ray that misses everything adds throughput x environment.  A hit adds the
local terms and pushes its children:

* **bubble** (a spherical thin film, :mod:`bubbleoptics.kernels`): a mirror ray weighted by
  R(λ, θ, d) and a ray straight on weighted by T(λ, θ, d) — no inner sphere, no refraction;
  point-light highlights (Phong lobe, exponent = the bubble's shininess) weighted by R;
* **material** (spheres and meshes, :class:`tracer.scene.Material`): the seed's eq. 1.4 local
  terms (ambient, diffuse and Phong specular from each light, with transmissive shadows), a
  mirror ray weighted by ``specular * color + transmission * F`` and a refracted ray (Snell)
  weighted by ``transmission * (1 - F) * color``, F the unpolarized Fresnel reflectance
  (:func:`bubbleoptics.kernels.fresnel_interface`; total internal reflection gives F = 1).

Generation 1 is the camera ray; a child is traced only if its generation is <= ``depth`` and,
when ``threshold > 0``, the largest channel of its throughput exceeds ``threshold`` (pruning);
likewise a shadow ray is cast only if the light's largest possible contribution through it
exceeds ``threshold``.  ``threshold = 0`` traces every child whose lobe exists and every
shadow ray, the seed's exhaustive tree.
Shadow rays run to each light on the lit side of the surface (none to lights behind it) and
multiply the transmittance of everything they cross: a bubble's T, glass's kt (1 - F) colour
(without bending: Whitted shadows have no caustics), zero for opaque surfaces.

Ray counts per row: [camera, reflected, transmitted, shadow].
"""

import math

import numpy as np
from numba import njit, prange

from bubbleoptics.kernels import (
    POL_UNPOLARIZED,
    film_band_average,
    film_rt,
    film_setup,
    fresnel_interface,
    normal_wavevector,
)

from .environment import environment_rgb
from .films import film_thickness
from .geometry import intersect_bvh, intersect_sphere, sphere_hit_point
from .sampling import camera_ray, stratified_offset

_JIT = dict(cache=True, error_model="numpy")
_JIT_PARALLEL = dict(cache=True, error_model="numpy", parallel=True)

HIT_NONE = 0
HIT_SPHERE = 1
HIT_BUBBLE = 2
HIT_TRIANGLE = 3
MAX_SHADOW_CROSSINGS = 64
N_COUNTS = 4


@njit(**_JIT)
def closest_hit(o, d, tmin, tmax, spheres, bubbles, tris, bounds, child, first, count, bvh_stack):
    """(kind, index, t, entering) of the nearest surface along o + t d, t in (tmin, tmax)."""
    best = tmax
    kind = HIT_NONE
    idx = -1
    entering = True
    for i in range(spheres.shape[0]):
        t, ent = intersect_sphere(o, d, (spheres[i, 0], spheres[i, 1], spheres[i, 2]), spheres[i, 3], tmin, best)
        if t < best:
            best, kind, idx, entering = t, HIT_SPHERE, i, ent
    for i in range(bubbles.shape[0]):
        t, ent = intersect_sphere(o, d, (bubbles[i, 0], bubbles[i, 1], bubbles[i, 2]), bubbles[i, 3], tmin, best)
        if t < best:
            best, kind, idx, entering = t, HIT_BUBBLE, i, ent
    if tris.shape[0] > 0:
        t, ti, _, _ = intersect_bvh(o, d, tmin, best, bounds, child, first, count, tris, bvh_stack)
        if t < best:
            best, kind, idx, entering = t, HIT_TRIANGLE, ti, True
    return kind, idx, best, entering


@njit(**_JIT)
def surface(kind, idx, o, d, t, spheres, bubbles, tri_info):
    """Hit point and outward unit normal (spheres re-projected onto their surface)."""
    if kind == HIT_SPHERE:
        return sphere_hit_point(o, d, t, (spheres[idx, 0], spheres[idx, 1], spheres[idx, 2]), spheres[idx, 3])
    if kind == HIT_BUBBLE:
        return sphere_hit_point(o, d, t, (bubbles[idx, 0], bubbles[idx, 1], bubbles[idx, 2]), bubbles[idx, 3])
    p = (o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2])
    return p, (tri_info[idx, 0], tri_info[idx, 1], tri_info[idx, 2])


@njit(**_JIT)
def offset(p, n, s):
    """p + s n (s carries the side and the scene-proportional epsilon)."""
    return (p[0] + s * n[0], p[1] + s * n[1], p[2] + s * n[2])


#: A uniform film's R, T are reused when cos(theta) agrees to this (absolute): the error in
#: R is then below |dR/dcos| * 1e-12 < 1e-9 even for 10-micron films.
COS_REUSE_TOL = 1e-12


@njit(**_JIT)
def bubble_rt(b, n_out, cos_i, wl, bubble_n, bubble_film, film_maps, R, T, cache_cos, cache_R, cache_T, band):
    """Fill R, T (per channel) for bubble *b* hit at outward normal *n_out*.

    Point mode: the film at each band centre (:func:`bubbleoptics.kernels.film_rt`).  Band mode
    (``band[0][0] == 1``): each band's film averaged in closed form over the band
    (:func:`bubbleoptics.kernels.film_band_average`), with the phase rate 2π q1/λ taken at the
    band edges (computed once per hit for the C + 1 shared edges).

    Skips work a uniform film does not need: inside a sphere every chord meets both of its
    ends at the same angle and reflection keeps it, so the entry hit, the exit hit and every
    inner bounce of a path share one cos(theta) and, for a uniform film, one R(λ), T(λ).
    Each bubble keeps its last (cos, R, T) per thread (*cache_cos* < 0 means empty).
    """
    band_mode, edges, n_edges, kq_edges = band
    p = bubble_film[b]
    uniform = p[0] == 0.0 and p[5] == 0.0
    nc = R.shape[0]
    if uniform and abs(cache_cos[b] - cos_i) <= COS_REUSE_TOL:
        for c in range(nc):
            R[c] = cache_R[b, c]
            T[c] = cache_T[b, c]
        return
    d_nm = film_thickness(p, film_maps, n_out)
    if band_mode[0] == 1:
        q0 = max(cos_i, 1e-150)
        for e in range(nc + 1):
            kq_edges[e] = 2.0 * math.pi / edges[e] * normal_wavevector(n_edges[b, e] + 0j, 1.0, q0).real
        for c in range(nc):
            coef = film_setup(wl[c], cos_i, 1.0, bubble_n[b, c] + 0j, 1.0 + 0j)
            r, t = film_band_average(coef, kq_edges[c], kq_edges[c + 1], d_nm, POL_UNPOLARIZED)
            R[c] = r
            T[c] = t
    else:
        for c in range(nc):
            r, t = film_rt(wl[c], d_nm, cos_i, 1.0, bubble_n[b, c] + 0j, 1.0 + 0j, POL_UNPOLARIZED)
            R[c] = r
            T[c] = t
    if uniform:
        cache_cos[b] = cos_i
        for c in range(nc):
            cache_R[b, c] = R[c]
            cache_T[b, c] = T[c]


@njit(**_JIT)
def fresnel_unpolarized(n1, n2, cos_i):
    """Unpolarized Fresnel reflectance (1 at total internal reflection)."""
    if n1 == n2:
        return 0.0
    res = fresnel_interface(n1, n2 + 0j, cos_i)
    return 0.5 * (res[4] + res[5])


@njit(**_JIT)
def shadow_transmittance(p, lpos, trans, sc, counts):
    """Transmittance (per channel, into *trans*) from p to the light at *lpos*; False if zero."""
    (spheres, bubbles, bubble_n, bubble_film, film_maps, tris, tri_info, bounds, child, first, count,
     mat_color, mat_coef, wl, eps, bvh_stack, R, T, R_sh, T_sh, cache_cos, cache_R, cache_T, band) = sc
    # R_sh, T_sh: this function's own scratch; R, T hold the caller's hit and must survive
    dx = lpos[0] - p[0]
    dy = lpos[1] - p[1]
    dz = lpos[2] - p[2]
    dist = math.sqrt(dx * dx + dy * dy + dz * dz)
    for c in range(trans.shape[0]):
        trans[c] = 1.0
    if not dist > 0.0:
        return True
    d = (dx / dist, dy / dist, dz / dist)
    counts[3] += 1
    tstart = 0.0
    for _ in range(MAX_SHADOW_CROSSINGS):
        kind, idx, t, entering = closest_hit(p, d, tstart, dist, spheres, bubbles, tris, bounds, child, first,
                                             count, bvh_stack)
        if kind == HIT_NONE:
            return True
        q, n = surface(kind, idx, p, d, t, spheres, bubbles, tri_info)
        cos_i = abs(d[0] * n[0] + d[1] * n[1] + d[2] * n[2])
        if kind == HIT_BUBBLE:
            bubble_rt(idx, n, cos_i, wl, bubble_n, bubble_film, film_maps, R_sh, T_sh, cache_cos, cache_R, cache_T, band)
            for c in range(trans.shape[0]):
                trans[c] *= T_sh[c]
        else:
            m = int(spheres[idx, 4]) if kind == HIT_SPHERE else int(tri_info[idx, 3])
            kt = mat_coef[m, 3]
            if kt <= 0.0:
                return False
            if kind == HIT_TRIANGLE:
                entering = (d[0] * n[0] + d[1] * n[1] + d[2] * n[2]) < 0.0
            ior = mat_coef[m, 5]
            F = fresnel_unpolarized(1.0, ior, cos_i) if entering else fresnel_unpolarized(ior, 1.0, cos_i)
            for c in range(trans.shape[0]):
                trans[c] *= kt * (1.0 - F) * mat_color[m, c]
        tstart = t + eps
        alive = False
        for c in range(trans.shape[0]):
            if trans[c] > 0.0:
                alive = True
        if not alive:
            return False
    return True


@njit(**_JIT)
def add_env(L, thr, d, env_kind, env_params, env_image, basis):
    r, g, b = environment_rgb(env_kind, env_params, env_image, d)
    for c in range(L.shape[0]):
        L[c] += thr[c] * (basis[c, 0] * r + basis[c, 1] * g + basis[c, 2] * b)


@njit(**_JIT)
def push(st_o, st_d, st_thr, st_gen, sp, o, d, gen):
    st_o[sp, 0], st_o[sp, 1], st_o[sp, 2] = o
    st_d[sp, 0], st_d[sp, 1], st_d[sp, 2] = d
    st_gen[sp] = gen
    return sp + 1


@njit(**_JIT)
def light_terms(lpos, p, nf, d):
    """(N.L, R.V) for the light at *lpos* seen from *p*: the cosine between the facing normal
    *nf* and the direction to the light, and between the light's mirror direction about *nf*
    and the direction to the viewer (-d) — the two cosines of the Phong terms of the seed's
    eq. 1.4.  R.V is 0 when the light is behind the surface (N.L <= 0)."""
    lx = lpos[0] - p[0]
    ly = lpos[1] - p[1]
    lz = lpos[2] - p[2]
    ln = math.sqrt(lx * lx + ly * ly + lz * lz)
    if not ln > 0.0:
        return 0.0, 0.0  # a light exactly on the surface lights nothing (and makes no NaN)
    ndl = (lx * nf[0] + ly * nf[1] + lz * nf[2]) / ln
    if ndl <= 0.0:
        return ndl, 0.0
    rl = 2.0 * ndl
    rv = -((rl * nf[0] - lx / ln) * d[0] + (rl * nf[1] - ly / ln) * d[1] + (rl * nf[2] - lz / ln) * d[2])
    return ndl, max(rv, 0.0)


@njit(**_JIT)
def push_child(st_o, st_d, st_thr, st_gen, sp, o, d, gen, weight, threshold):
    """Push a child ray with throughput *weight* (per channel) if :func:`keep_child` says so;
    returns (new stack pointer, pushed?)."""
    if not keep_child(weight, threshold):
        return sp, False
    for c in range(weight.shape[0]):
        st_thr[sp, c] = weight[c]
    return push(st_o, st_d, st_thr, st_gen, sp, o, d, gen), True


@njit(**_JIT)
def max_product(a, b, j):
    """max over channels of a[c] * b[j, c] (a bound on a light's contribution)."""
    m = 0.0
    for c in range(a.shape[0]):
        m = max(m, a[c] * b[j, c])
    return m


@njit(**_JIT)
def keep_child(w, threshold):
    """Trace a child whose throughput is *w*? (its lobe exists; pruning when threshold > 0)."""
    m = 0.0
    for c in range(w.shape[0]):
        m = max(m, w[c])
    if threshold > 0.0:
        return m > threshold
    return True


@njit(**_JIT)
def trace_sample(o0, d0, depth, threshold, sc, env, lights, light_rad, ambient, L, scratch, counts):
    """Add the radiance (per channel) of camera ray (o0, d0) to L."""
    (spheres, bubbles, bubble_n, bubble_film, film_maps, tris, tri_info, bounds, child, first, count,
     mat_color, mat_coef, wl, eps, bvh_stack, R, T, R_sh, T_sh, cache_cos, cache_R, cache_T, band) = sc
    env_kind, env_params, env_image, basis = env
    st_o, st_d, st_thr, st_gen, trans, w = scratch
    nc = L.shape[0]
    sp = push(st_o, st_d, st_thr, st_gen, 0, o0, d0, 1)
    for c in range(nc):
        st_thr[0, c] = 1.0
    counts[0] += 1
    while sp > 0:
        sp -= 1
        o = (st_o[sp, 0], st_o[sp, 1], st_o[sp, 2])
        d = (st_d[sp, 0], st_d[sp, 1], st_d[sp, 2])
        gen = st_gen[sp]
        thr = st_thr[sp]
        kind, idx, t, entering = closest_hit(o, d, 0.0, np.inf, spheres, bubbles, tris, bounds, child, first,
                                             count, bvh_stack)
        if kind == HIT_NONE:
            add_env(L, thr, d, env_kind, env_params, env_image, basis)
            continue
        p, n = surface(kind, idx, o, d, t, spheres, bubbles, tri_info)
        dn = d[0] * n[0] + d[1] * n[1] + d[2] * n[2]
        cos_i = abs(dn)
        sgn = -1.0 if dn > 0.0 else 1.0  # nf = sgn * n faces the incoming ray
        nf = (sgn * n[0], sgn * n[1], sgn * n[2])
        refl = (d[0] + 2.0 * cos_i * nf[0], d[1] + 2.0 * cos_i * nf[1], d[2] + 2.0 * cos_i * nf[2])
        p_front = offset(p, nf, eps)
        p_back = offset(p, nf, -eps)
        # keep this ray's throughput: the stack slot may be overwritten by children
        for c in range(nc):
            w[c] = thr[c]
        if kind == HIT_BUBBLE:
            bubble_rt(idx, n, cos_i, wl, bubble_n, bubble_film, film_maps, R, T, cache_cos, cache_R, cache_T, band)
            shin = bubbles[idx, 4]
            for j in range(lights.shape[0]):
                lpos = (lights[j, 0], lights[j, 1], lights[j, 2])
                ndl, rv = light_terms(lpos, p, nf, d)
                if rv <= 0.0:
                    continue  # light behind the film, or its mirror image away from the viewer
                spec = rv**shin
                if spec < 1e-12:
                    continue
                for c in range(nc):
                    trans[c] = w[c] * R[c]
                if threshold > 0.0 and spec * max_product(trans, light_rad, j) <= threshold:
                    continue  # the highlight can add at most `threshold`: pruned like a branch
                if shadow_transmittance(p_front, lpos, trans, sc, counts):
                    for c in range(nc):
                        L[c] += w[c] * R[c] * trans[c] * light_rad[j, c] * spec
            if gen < depth:
                # transmitted first (deeper in the stack), reflected on top
                for c in range(nc):
                    trans[c] = w[c] * T[c]
                sp, pushed = push_child(st_o, st_d, st_thr, st_gen, sp, p_back, d, gen + 1, trans, threshold)
                counts[2] += pushed
                for c in range(nc):
                    trans[c] = w[c] * R[c]
                sp, pushed = push_child(st_o, st_d, st_thr, st_gen, sp, p_front, refl, gen + 1, trans, threshold)
                counts[1] += pushed
            continue
        # material surface
        m = int(spheres[idx, 4]) if kind == HIT_SPHERE else int(tri_info[idx, 3])
        ka, kd, ks, kt, shin, ior = (mat_coef[m, 0], mat_coef[m, 1], mat_coef[m, 2], mat_coef[m, 3],
                                     mat_coef[m, 4], mat_coef[m, 5])
        if ka > 0.0:
            for c in range(nc):
                L[c] += w[c] * ka * mat_color[m, c] * ambient[c]
        if kd > 0.0 or ks > 0.0:
            for j in range(lights.shape[0]):
                lpos = (lights[j, 0], lights[j, 1], lights[j, 2])
                ndl, rv = light_terms(lpos, p, nf, d)
                if ndl <= 0.0:
                    continue  # light behind the surface: no shadow ray
                spec = ks * rv**shin if (ks > 0.0 and rv > 0.0) else 0.0
                if threshold > 0.0:
                    for c in range(nc):
                        trans[c] = w[c] * (kd * ndl * mat_color[m, c] + spec)
                    if max_product(trans, light_rad, j) <= threshold:
                        continue  # this light can add at most `threshold` here: pruned
                if shadow_transmittance(p_front, lpos, trans, sc, counts):
                    for c in range(nc):
                        L[c] += w[c] * light_rad[j, c] * trans[c] * (kd * ndl * mat_color[m, c] + spec)
        if gen >= depth or (ks <= 0.0 and kt <= 0.0):
            continue
        F = 0.0
        tdir = d
        if kt > 0.0:
            if kind == HIT_TRIANGLE:
                entering = dn < 0.0
            n1 = 1.0 if entering else ior
            n2 = ior if entering else 1.0
            F = fresnel_unpolarized(n1, n2, cos_i)
            if n1 != n2 and F < 1.0:
                eta = n1 / n2
                q2 = normal_wavevector(n2 + 0j, n1, n1 * cos_i)  # n2 cos(theta_t), no cancellation
                cos_t = q2.real / n2
                k = eta * cos_i - cos_t
                tx = eta * d[0] + k * nf[0]
                ty = eta * d[1] + k * nf[1]
                tz = eta * d[2] + k * nf[2]
                tn = math.sqrt(tx * tx + ty * ty + tz * tz)
                tdir = (tx / tn, ty / tn, tz / tn)
            if F < 1.0:
                for c in range(nc):
                    trans[c] = w[c] * kt * (1.0 - F) * mat_color[m, c]
                sp, pushed = push_child(st_o, st_d, st_thr, st_gen, sp, p_back, tdir, gen + 1, trans, threshold)
                counts[2] += pushed
        if ks > 0.0 or (kt > 0.0 and F > 0.0):
            for c in range(nc):
                trans[c] = w[c] * (ks * mat_color[m, c] + kt * F)
            sp, pushed = push_child(st_o, st_d, st_thr, st_gen, sp, p_front, refl, gen + 1, trans, threshold)
            counts[1] += pushed


@njit(**_JIT_PARALLEL)
def render_rows(row0, row1, width, height, spp, seed, depth, threshold, camera, to_rgb,
                spheres, bubbles, bubble_n, bubble_film, film_maps, tris, tri_info, bounds, child, first,
                count, mat_color, mat_coef, wl, eps, env_kind, env_params, env_image, basis,
                lights, light_rad, ambient, band_mode, band_edges, bubble_n_edges, image, counts):
    """Render rows [row0, row1) into image[row - row0] (linear sRGB) and counts[row - row0]."""
    nc = basis.shape[0]
    stack_size = 2 * depth + 8
    for y in prange(row0, row1):
        st_o = np.empty((stack_size, 3))
        st_d = np.empty((stack_size, 3))
        st_thr = np.empty((stack_size, nc))
        st_gen = np.empty(stack_size, dtype=np.int64)
        trans = np.empty(nc)
        w = np.empty(nc)
        R = np.empty(nc)
        T = np.empty(nc)
        R_sh = np.empty(nc)
        T_sh = np.empty(nc)
        L = np.empty(nc)
        bvh_stack = np.empty(64, dtype=np.int64)
        row_counts = np.zeros(N_COUNTS, dtype=np.int64)
        nb = bubbles.shape[0]
        cache_cos = np.full(nb, -1.0)
        cache_R = np.empty((nb, nc))
        cache_T = np.empty((nb, nc))
        kq_edges = np.empty(nc + 1)
        band = (band_mode, band_edges, bubble_n_edges, kq_edges)
        sc = (spheres, bubbles, bubble_n, bubble_film, film_maps, tris, tri_info, bounds, child, first, count,
              mat_color, mat_coef, wl, eps, bvh_stack, R, T, R_sh, T_sh, cache_cos, cache_R, cache_T, band)
        env = (env_kind, env_params, env_image, basis)
        scratch = (st_o, st_d, st_thr, st_gen, trans, w)
        o0 = (camera[0], camera[1], camera[2])
        for x in range(width):
            pix = y * width + x
            r = 0.0
            g = 0.0
            b = 0.0
            for s in range(spp):
                fx, fy = stratified_offset(seed, pix, s, spp)
                d0 = camera_ray(camera, x + fx, y + fy, width, height)
                for c in range(nc):
                    L[c] = 0.0
                trace_sample(o0, d0, depth, threshold, sc, env, lights, light_rad, ambient, L, scratch, row_counts)
                for c in range(nc):
                    r += to_rgb[0, c] * L[c]
                    g += to_rgb[1, c] * L[c]
                    b += to_rgb[2, c] * L[c]
            image[y - row0, x, 0] = r / spp
            image[y - row0, x, 1] = g / spp
            image[y - row0, x, 2] = b / spp
        for k in range(N_COUNTS):
            counts[y - row0, k] = row_counts[k]
