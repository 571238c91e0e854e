"""The soap film of a bubble: a spherical thin film (numba), one of the tracer's surface models.

A bubble is a sphere whose surface is a film of thickness d(point) (:mod:`tracer.films`) and
index :math:`n(\\lambda) + ik` between air on both sides.  At a hit with angle of incidence θ
it answers the integrator's questions (:mod:`tracer.surfaces`):

* **scatter**: a mirror child weighted by :math:`R(\\lambda, \\theta, d)` and a child straight
  on weighted by :math:`T(\\lambda, \\theta, d)` (a free-standing film displaces a ray by less
  than its thickness and does not bend it), from the exact Airy sum of
  :mod:`bubbleoptics.kernels` for unpolarized light: at the band centres
  (:func:`~bubbleoptics.kernels.film_rt`), or averaged over each band in closed form when
  ``PackedScene.band_mode`` is 1 (:func:`~bubbleoptics.kernels.film_band_average`);
* **toward a light**: a Phong-lobe highlight :math:`R\\,(R\\cdot V)^{s}` in the mirror direction
  (s = the film's shininess; a point light has no extent, so this lobe stands in for the
  reflected image of a small source);
* **shadow**: a shadow ray crossing the film is multiplied by T;
* **what a cut child still carries**: every chord of a sphere meets it at both ends at the
  same angle, and reflection keeps that angle, so a ray inside a bubble meets the film again
  and again at one θ.  A child that goes into the bubble's interior with throughput w
  therefore sends :math:`w\\,T\\sum_k R^k = w\\,T/(1-R)` out of it in all (exactly w for a
  lossless film, R + T = 1; less for an absorbing one).  When the integrator cuts such a
  child (depth limit or pruning) it ends the branch with that factor (see
  :func:`tracer.integrator.trace_camera_ray` for the bias this leaves).

The same chord property lets a uniform film reuse R(λ), T(λ): the entry hit, the exit hit and
every inner bounce of a path share one cos θ.  Each thread keeps, per film, its last
(cos θ, R, T) in its :class:`tracer.integrator.Workspace`.

Transport is unpolarized: R and T are the means of s and p at every hit, including the inner
bounces (a path inside a sphere stays in one plane of incidence, so s and p would not mix
there; the unpolarized series :math:`T/(1-R)` differs from the polarization-resolved
:math:`\\tfrac12\\sum_{s,p} T_j/(1-R_j)` only for absorbing films, at second order in the
difference between R_s and R_p).
"""

import math

from numba import njit

from bubbleoptics.kernels import POL_UNPOLARIZED, film_band_average, film_rt, film_setup, normal_wavevector

from ..films import film_thickness

__all__ = ["COS_REUSE_TOL", "film_optics", "film_scatter", "film_toward_light", "film_shadow"]

_JIT = dict(cache=True, error_model="numpy")
_INLINE = dict(inline="always", **_JIT)

#: A uniform film's R, T are reused when cos(theta) agrees to this (absolute): the error in
#: R is then below |dR/dcos| * 1e-12 < 1e-9 even for 10-micron films.
COS_REUSE_TOL = 1e-12


@njit(**_INLINE)
def film_optics(scene, ws, b, n_out, cos_i, R, T):
    """Fill R[c], T[c] (unpolarized, per channel) of film *b* at the point with outward unit
    normal *n_out*, hit at cos(theta) = *cos_i*; reuses the thread's last values for a
    uniform film at the same angle."""
    f = scene.films[b]
    nc = R.shape[0]
    if f.uniform and abs(ws.film_cos[b] - cos_i) <= COS_REUSE_TOL:
        for c in range(nc):
            R[c] = ws.film_R[b, c]
            T[c] = ws.film_T[b, c]
        return
    d_nm = film_thickness(f, scene.film_maps, n_out)
    if scene.band_mode == 1:
        q0 = max(cos_i, 1e-150)
        kq = ws.kq_edges
        for e in range(nc + 1):
            kq[e] = 2.0 * math.pi / scene.band_edges[e] * normal_wavevector(scene.film_n_edges[b, e], 1.0, q0).real
        for c in range(nc):
            coef = film_setup(scene.wavelengths[c], cos_i, 1.0, scene.film_n[b, c], 1.0 + 0j)
            r, t = film_band_average(coef, kq[c], kq[c + 1], d_nm, POL_UNPOLARIZED)
            R[c] = r
            T[c] = t
    else:
        for c in range(nc):
            r, t = film_rt(scene.wavelengths[c], d_nm, cos_i, 1.0, scene.film_n[b, c], 1.0 + 0j, POL_UNPOLARIZED)
            R[c] = r
            T[c] = t
    if f.uniform:
        ws.film_cos[b] = cos_i
        for c in range(nc):
            ws.film_R[b, c] = R[c]
            ws.film_T[b, c] = T[c]


@njit(**_INLINE)
def film_scatter(scene, ws, b, hit):
    """The two children of a film hit: their weights per channel into ``ws.wr`` (mirror: R)
    and ``ws.wt`` (straight on: T), and into ``ws.cut_r``, ``ws.cut_t`` the factors a cut
    child's environment lookup is multiplied by: :math:`T/(1-R)` for the child that stays
    inside the bubble (exactly 1 for a lossless film), 1 for the one that leaves it.  Returns
    the transmitted direction (the incoming one)."""
    p, n, nf, d, cos_i, entering = hit
    wr = ws.wr
    wt = ws.wt
    film_optics(scene, ws, b, n, cos_i, wr, wt)
    lossless = scene.films[b].lossless
    for c in range(wr.shape[0]):
        inner = 1.0
        if not lossless:
            rest = 1.0 - wr[c]
            inner = min(1.0, wt[c] / rest) if rest > 0.0 else 1.0
        if entering:
            ws.cut_r[c] = 1.0
            ws.cut_t[c] = inner
        else:
            ws.cut_r[c] = inner
            ws.cut_t[c] = 1.0
    return d


@njit(**_INLINE)
def film_toward_light(scene, ws, b, hit, ndl, rv, out):
    """The highlight seen from the viewer per unit of the light's radiance:
    ``out[c] = R[c] rv^shininess`` with R from :func:`film_scatter` (``ws.wr``); False when the
    lobe is negligible (the light's mirror image points away from the viewer)."""
    if rv <= 0.0:
        return False
    spec = rv ** scene.films[b].shininess
    if spec < 1e-12:
        return False
    for c in range(out.shape[0]):
        out[c] = ws.wr[c] * spec
    return True


@njit(**_INLINE)
def film_shadow(scene, ws, b, n, cos_i, entering, trans):
    """A shadow ray crossing film *b*: ``trans *= T`` (per channel); True (a film never stops one)."""
    film_optics(scene, ws, b, n, cos_i, ws.R_shadow, ws.T_shadow)
    for c in range(trans.shape[0]):
        trans[c] *= ws.T_shadow[c]
    return True
