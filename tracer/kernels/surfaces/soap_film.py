"""The soap film of a bubble: a spherical thin film (numba), one of the tracer's surface models.

A bubble is a sphere whose surface is a film of thickness d(point) (:mod:`tracer.kernels.thickness`) and
index :math:`n(\\lambda) + ik` between air on both sides.  At a hit with angle of incidence θ
it answers the integrator's questions (:mod:`tracer.kernels.surfaces`):

* **scatter**: a mirror child weighted by :math:`R(\\lambda, \\theta, d)` and a child straight
  on weighted by :math:`T(\\lambda, \\theta, d)` (a free-standing film displaces a ray by less
  than its thickness and does not bend it), from the exact Airy sum of
  :mod:`bubbleoptics.kernels` for unpolarized light: at the band centres
  (:func:`~bubbleoptics.kernels.film_rt_nb`), or averaged over each band in closed form when
  ``PackedScene.band_mode`` is 1 (:func:`~bubbleoptics.kernels.film_band_average_nb`); or, for
  a bubble whose ``film_model`` is ``"two-beam"``, from the coursework's two-beam formula
  (:func:`~bubbleoptics.kernels.two_beam_r_nb`, at the band centres) with T = 1 - R;
* **toward a light**: a Phong-lobe highlight :math:`R\\,(R\\cdot V)^{s}` in the mirror direction
  (s = the film's shininess; a point light has no extent, so this lobe stands in for the
  reflected image of a small source; a spherical light sums the lobes of its sample
  directions, :func:`tracer.kernels.integrator.sphere_light`, which widens the highlight with the
  light);
* **shadow**: a shadow ray crossing the film is multiplied by T;
* **what a cut child still carries**: every chord of a sphere meets it at both ends at the
  same angle, and reflection keeps that angle, so a ray inside a bubble meets the film again
  and again at one θ.  A child that goes into the bubble's interior with throughput w
  therefore sends :math:`w\\,T\\sum_k R^k = w\\,T/(1-R)` out of it in all (exactly w for a
  lossless film, R + T = 1; less for an absorbing one).  When the integrator cuts such a
  child (depth limit or pruning) it ends the branch with that factor (see
  :func:`tracer.kernels.integrator.render_rows` for the bias this leaves).

The same chord property lets a path inside a bubble reuse the film's set-up, and a uniform
film its R(λ), T(λ): the entry hit, the exit hit and every inner bounce share one cos θ
(:func:`film_optics`; each thread keeps them per film in its
:class:`tracer.kernels.integrator.Workspace`).

Transport is unpolarized: R and T are the means of s and p at every hit, including the inner
bounces (a path inside a sphere stays in one plane of incidence, so s and p would not mix
there; the unpolarized series :math:`T/(1-R)` differs from the polarization-resolved
:math:`\\tfrac12\\sum_{s,p} T_j/(1-R_j)` only for absorbing films, at second order in the
difference between R_s and R_p).
"""

import math

from numba import njit
from bubbleoptics.jit import JIT_INLINE

from bubbleoptics.kernels import (
    COS_MIN,
    N_FILM_COEFFICIENTS,
    POL_UNPOLARIZED,
    film_band_average_nb,
    film_evaluate_nb,
    film_setup_nb,
    free_film_band_average_nb,
    free_film_evaluate_bands_nb,
    free_film_setup_bands_nb,
    normal_wavevector_nb,
    two_beam_r_nb,
)

from ..thickness import film_thickness
from ..records import FILM_MODEL_TWO_BEAM

__all__ = ["film_optics", "film_scatter", "film_toward_light", "film_shadow"]


# A highlight lobe below this is not worth a shadow ray (and its logarithm).
_SPEC_MIN = 1e-12
_LOG_SPEC_MIN = math.log(_SPEC_MIN)

@njit(**JIT_INLINE)
def film_optics(scene, ws, b, n_out, cos_i, R, T, xfilm):
    """Fill R[c], T[c] (unpolarized, per channel) of film *b* at the point with outward unit
    normal *n_out*, met at cos(theta) = *cos_i*.

    A lossless film (every channel's index real) uses the free-standing film's closed form
    (:func:`~bubbleoptics.kernels.free_film_setup_nb`, three numbers per channel), an absorbing
    one the general Airy sum (:func:`~bubbleoptics.kernels.film_setup_nb`); either way at the
    band centres, or averaged over each band when ``scene.band_mode`` is 1.

    Work a path inside a bubble does not need is skipped: the per-channel set-up (everything
    but the thickness) is kept per film for the last cos(theta), and a uniform film keeps its
    last R, T as well.  The integrator hands every hit at the end of a chord the exact cos of
    its start (:func:`tracer.kernels.integrator.render_rows`), so the exit hit and every inner
    bounce of a path find them (exact equality, no tolerance).

    *xfilm* None: the scene has only lossless Airy films at the band centres, and the other
    paths (two-beam, band averages, absorbing films) are not compiled
    (:func:`tracer.kernels.integrator.scene_features`).
    """
    f = scene.films[b]
    nc = R.shape[0]
    if f.uniform and ws.film_rt_cos[b] == cos_i:
        fr = ws.film_R
        ft = ws.film_T
        for c in range(nc):
            R[c] = fr[b, c]
            T[c] = ft[b, c]
        return
    d_nm = film_thickness(f, scene.film_maps, n_out)
    # Every test of xfilm comes first in its condition, so that with xfilm None (lossless Airy
    # films at the band centres only) numba prunes the other paths when it compiles.
    if xfilm is not None and f.model == FILM_MODEL_TWO_BEAM:
        _two_beam_optics(scene, ws, b, d_nm, cos_i, R, T)
        return
    kq = ws.film_kq
    fkq = ws.free_kq
    ffs = ws.free_Fs
    ffp = ws.free_Fp
    coef = ws.film_coef
    if ws.film_coef_cos[b] != cos_i:
        wl = scene.wavelengths
        if xfilm is None or f.lossless:
            free_film_setup_bands_nb(wl, scene.film_n[b], cos_i, 1.0, fkq[b], ffs[b], ffp[b])
        else:
            fn = scene.film_n
            fk = scene.film_k
            for c in range(nc):
                setup = film_setup_nb(wl[c], cos_i, 1.0, complex(fn[b, c], fk[b, c]), 1.0 + 0j)
                for k in range(N_FILM_COEFFICIENTS):
                    coef[b, c, k] = setup[k]
        if xfilm is not None and scene.band_mode == 1:
            q0 = max(cos_i, COS_MIN)
            edges = scene.band_edges
            ne = scene.film_n_edges
            ke = scene.film_k_edges
            for e in range(nc + 1):
                kq[b, e] = 2.0 * math.pi / edges[e] * normal_wavevector_nb(complex(ne[b, e], ke[b, e]), 1.0, q0).real
        ws.film_coef_cos[b] = cos_i
    if xfilm is None or (f.lossless and scene.band_mode != 1):
        free_film_evaluate_bands_nb(fkq[b], ffs[b], ffp[b], d_nm, POL_UNPOLARIZED, R, T)
    elif f.lossless:
        for c in range(nc):
            r, t = free_film_band_average_nb((fkq[b, c], ffs[b, c], ffp[b, c]), kq[b, c], kq[b, c + 1], d_nm,
                                          POL_UNPOLARIZED)
            R[c] = r
            T[c] = t
    elif scene.band_mode == 1:
        for c in range(nc):
            r, t = film_band_average_nb(coef[b, c], kq[b, c], kq[b, c + 1], d_nm, POL_UNPOLARIZED)
            R[c] = r
            T[c] = t
    else:
        for c in range(nc):
            r, t = film_evaluate_nb(coef[b, c], d_nm, POL_UNPOLARIZED)
            R[c] = r
            T[c] = t
    _keep_uniform(ws, f, b, cos_i, R, T)


@njit(**JIT_INLINE)
def _keep_uniform(ws, f, b, cos_i, R, T):
    """A uniform film keeps its last R, T (per channel) and the cos they are for."""
    if f.uniform:
        ws.film_rt_cos[b] = cos_i
        fr = ws.film_R
        ft = ws.film_T
        for c in range(R.shape[0]):
            fr[b, c] = R[c]
            ft[b, c] = T[c]


@njit(**JIT_INLINE)
def _two_beam_optics(scene, ws, b, d_nm, cos_i, R, T):
    """:func:`film_optics` for a film whose model is the coursework's two-beam formula:
    :math:`R = \\min(1, 4R_{01}\\sin^2\\beta)` at each band centre (unpolarized; only Re n,
    :func:`~bubbleoptics.kernels.two_beam_r_nb`), T = 1 - R (the formula gives no T; the
    clip at 1 is where it would exceed 1, near grazing incidence).  No per-film cache beyond
    the uniform film's R, T."""
    f = scene.films[b]
    wl = scene.wavelengths
    fn = scene.film_n
    for c in range(R.shape[0]):
        r = min(1.0, two_beam_r_nb(wl[c], d_nm, cos_i, 1.0, complex(fn[b, c], 0.0), POL_UNPOLARIZED))
        R[c] = r
        T[c] = 1.0 - r
    _keep_uniform(ws, f, b, cos_i, R, T)


@njit(**JIT_INLINE)
def film_scatter(scene, ws, b, hit, xfilm):
    """The two children of a film hit: their weights per channel into ``ws.wr`` (mirror: R)
    and ``ws.wt`` (straight on: T), and into ``ws.cut_r``, ``ws.cut_t`` the factors a cut
    child's environment lookup is multiplied by: :math:`T/(1-R)` for the child that stays
    inside the bubble (exactly 1 for a lossless film), 1 for the one that leaves it.  Returns
    the transmitted direction (the incoming one)."""
    p, n, nf, d, cos_i, entering = hit
    wr = ws.wr
    wt = ws.wt
    film_optics(scene, ws, b, n, cos_i, wr, wt, xfilm)
    absorbing = xfilm is not None and not scene.films[b].lossless
    cut_r = ws.cut_r
    cut_t = ws.cut_t
    for c in range(wr.shape[0]):
        inner = 1.0
        if absorbing:
            rest = 1.0 - wr[c]
            inner = min(1.0, wt[c] / rest) if rest > 0.0 else 1.0
        if entering:
            cut_r[c] = 1.0
            cut_t[c] = inner
        else:
            cut_r[c] = inner
            cut_t[c] = 1.0
    return d


@njit(**JIT_INLINE)
def film_toward_light(scene, ws, b, hit, ndl, rv, out):
    """The highlight seen from the viewer per unit of the light's radiance:
    ``out[c] = R[c] rv^shininess`` with R from :func:`film_scatter` (``ws.wr``); False when the
    lobe is negligible (the light's mirror image points away from the viewer)."""
    shin = scene.films[b].shininess
    # rv^s <= exp(s (rv - 1)) (ln x <= x - 1): skip the power where that bound is already tiny
    if rv <= 0.0 or shin * (rv - 1.0) < _LOG_SPEC_MIN:
        return False
    spec = rv**shin
    if spec < _SPEC_MIN:
        return False
    wr = ws.wr
    for c in range(out.shape[0]):
        out[c] = wr[c] * spec
    return True


@njit(**JIT_INLINE)
def film_shadow(scene, ws, b, n, cos_i, entering, trans, xfilm):
    """A shadow ray crossing film *b*: ``trans *= T`` (per channel); True (a film never stops one)."""
    T = ws.T_shadow
    film_optics(scene, ws, b, n, cos_i, ws.R_shadow, T, xfilm)
    for c in range(trans.shape[0]):
        trans[c] *= T[c]
    return True
