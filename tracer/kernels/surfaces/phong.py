"""The coursework's Phong/Whitted material (numba), one of the tracer's surface models.

Spheres and triangle meshes carry it.  Its record is :data:`tracer.kernels.records.PHONG` (ambient
:math:`k_a`, diffuse :math:`k_d`, specular :math:`k_s`, transmission :math:`k_t`, shininess
*s*, index *n*), its colour *C* per channel ``PackedScene.phong_color``.  At a hit:

* **ambient**: :math:`k_a C I_a` (the coursework's eq. 1.4, first term);
* **toward a light** at N·L > 0: :math:`k_d (N\\cdot L) C + k_s (R\\cdot V)^s` per unit of the
  light's radiance (eq. 1.4, the sum over lights), times the shadow ray's transmittance;
* **scatter**: a mirror child weighted by :math:`k_s C + k_t F` and a refracted child (Snell)
  weighted by :math:`k_t (1 - F) C`, F the unpolarized Fresnel reflectance of the interface
  (:func:`bubbleoptics.kernels.fresnel_dielectric_nb`; 0 when n = 1; total internal reflection
  gives F = 1 and no refracted child).  A cut child ends with the environment along it
  (factor 1: no closed form is assumed for a general material);
* **shadow**: a shadow ray crossing the surface is multiplied by :math:`k_t (1 - F) C`
  (without bending: Whitted shadows have no caustics); opaque (:math:`k_t = 0`) stops it.

Which side is "entering": spheres know it from the root of the intersection; triangles from
the sign of d·n with their outward normal.
"""

import math

from numba import njit
from bubbleoptics.jit import JIT, JIT_INLINE

from bubbleoptics.kernels import fresnel_dielectric_nb

__all__ = ["fresnel_unpolarized", "phong_ambient", "phong_scatter", "phong_toward_light", "phong_shadow"]



@njit(no_cpython_wrapper=True, no_cfunc_wrapper=True, **JIT)  # called only from the kernels
def fresnel_unpolarized(n1, n2, cos_i):
    """Unpolarized Fresnel reflectance F from index *n1* into *n2* at cos(theta) = *cos_i*, and
    q2 = n2 cos(theta_t) of the refracted ray (:func:`bubbleoptics.kernels.fresnel_dielectric_nb`:
    both indices are real).  F = 0 when n1 == n2, 1 at total internal reflection (q2 = 0 there)."""
    if n1 == n2:
        return 0.0, n1 * cos_i
    Rs, Rp, q2 = fresnel_dielectric_nb(n1, n2, cos_i)
    return 0.5 * (Rs + Rp), q2


@njit(**JIT_INLINE)
def phong_ambient(scene, m, w, L):
    """``L += w * ka * C * ambient`` (per channel)."""
    ka = scene.phong[m].ambient
    if ka > 0.0:
        col = scene.phong_color
        amb = scene.ambient
        for c in range(L.shape[0]):
            L[c] += w[c] * ka * col[m, c] * amb[c]


@njit(**JIT_INLINE)
def phong_toward_light(scene, ws, m, hit, ndl, rv, out):
    """Per unit of a light's radiance: ``out[c] = kd (N.L) C[c] + ks (R.V)^s``; False when the
    light is behind the surface or the material has neither term."""
    mat = scene.phong[m]
    kd = mat.diffuse
    ks = mat.specular
    if ndl <= 0.0 or (kd <= 0.0 and ks <= 0.0):
        return False
    spec = ks * rv**mat.shininess if (ks > 0.0 and rv > 0.0) else 0.0
    col = scene.phong_color
    for c in range(out.shape[0]):
        out[c] = kd * ndl * col[m, c] + spec
    return True


@njit(**JIT_INLINE)
def phong_scatter(scene, ws, m, hit):
    """Weights of the mirror child (``ws.wr``) and the refracted child (``ws.wt``) per channel,
    cut factors 1; returns the refracted direction (Snell's law, the incoming one when there is
    no refraction).  A zero weight means no child."""
    p, n, nf, d, cos_i, entering = hit
    mat = scene.phong[m]
    ks = mat.specular
    kt = mat.transmission
    ior = mat.ior
    F = 0.0
    tdir = d
    if kt > 0.0:
        n1 = 1.0 if entering else ior
        n2 = ior if entering else 1.0
        F, q2 = fresnel_unpolarized(n1, n2, cos_i)
        if n1 != n2 and F < 1.0:
            eta = n1 / n2
            cos_t = q2 / n2  # q2 = n2 cos(theta_t) from (n2 - n1)(n2 + n1) + q1^2: no cancellation
            k = eta * cos_i - cos_t
            tx = eta * d[0] + k * nf[0]
            ty = eta * d[1] + k * nf[1]
            tz = eta * d[2] + k * nf[2]
            tn = math.sqrt(tx * tx + ty * ty + tz * tz)
            tdir = (tx / tn, ty / tn, tz / tn)
    kt_out = kt * (1.0 - F)
    kt_mirror = kt * F
    colour = scene.phong_color
    wr = ws.wr
    wt = ws.wt
    cut_r = ws.cut_r
    cut_t = ws.cut_t
    for c in range(wr.shape[0]):
        col = colour[m, c]
        wr[c] = ks * col + kt_mirror
        wt[c] = kt_out * col
        cut_r[c] = 1.0
        cut_t[c] = 1.0
    return tdir


@njit(**JIT_INLINE)
def phong_shadow(scene, ws, m, n, cos_i, entering, trans):
    """A shadow ray crossing the surface: ``trans *= kt (1 - F) C``; False if opaque."""
    mat = scene.phong[m]
    kt = mat.transmission
    if kt <= 0.0:
        return False
    ior = mat.ior
    F = fresnel_unpolarized(1.0, ior, cos_i)[0] if entering else fresnel_unpolarized(ior, 1.0, cos_i)[0]
    col = scene.phong_color
    for c in range(trans.shape[0]):
        trans[c] *= kt * (1.0 - F) * col[m, c]
    return True
