"""Surface models: what a surface reflects, transmits and sends toward a light (numba).

One module per model, each answering the same questions about a hit:

========================  ==============================  =============================
question                  :mod:`.soap_film` (bubbles)      :mod:`.phong` (the coursework)
========================  ==============================  =============================
``ambient``               nothing                          :math:`k_a C I_a`
``toward_light``          highlight :math:`R (R\\cdot V)^s`  :math:`k_d (N\\cdot L) C + k_s (R\\cdot V)^s`
``scatter``               R mirror, T straight on          :math:`k_s C + k_t F` mirror, :math:`k_t(1-F)C` refracted
``shadow``                T                                :math:`k_t (1-F) C`, or opaque
========================  ==============================  =============================

The functions here dispatch on the surface kind (:data:`tracer.kernels.records.SURFACE_FILM`,
:data:`~tracer.kernels.records.SURFACE_PHONG`); the integrator (:mod:`tracer.kernels.integrator`) calls only
these and never names a surface model.  A new surface kind is a module answering the four
questions, a kind constant in :mod:`tracer.kernels.records`, its records in :mod:`tracer.prepare.pack` and one
branch in each function below.

A *hit* is the tuple ``(p, n, nf, d, cos_i, entering)``: the point, the outward unit normal,
the normal facing the incoming ray, the incoming unit direction, :math:`|d\\cdot n|`, and
whether the ray arrives from outside.  Per-channel results go into the thread's
:class:`tracer.kernels.integrator.Workspace` (``wr``, ``wt``, ``cut_r``, ``cut_t``) or the array
passed in.  Every function is inlined into the integrator (``inline="always"``): the arrays
they read are then never passed across a call, which costs more than most of the work here.
"""

from numba import njit
from bubbleoptics.jit import JIT_INLINE

from ..records import SURFACE_FILM
from .phong import phong_ambient, phong_scatter, phong_shadow, phong_toward_light
from .soap_film import film_scatter, film_shadow, film_toward_light

__all__ = ["ambient", "toward_light", "scatter", "shadow"]



@njit(**JIT_INLINE)
def ambient(scene, kind, index, w, L, film, phong):
    """Add the surface's ambient term for throughput *w* to *L* (per channel)."""
    if phong is not None and (film is None or kind != SURFACE_FILM):
        phong_ambient(scene, index, w, L)


@njit(**JIT_INLINE)
def toward_light(scene, ws, kind, index, hit, ndl, rv, out, film, phong):
    """Per unit of a light's strength, what the surface sends to the viewer (per channel, into
    *out*); *ndl* = N·L with the facing normal, *rv* = R·V of the light's mirror direction
    (0 when the light is behind).  False: nothing (and no shadow ray needed).  A spherical
    light asks once per sample direction, with that direction's N·L and R·V
    (:func:`tracer.kernels.integrator.sphere_light`)."""
    if film is not None and (phong is None or kind == SURFACE_FILM):
        return film_toward_light(scene, ws, index, hit, ndl, rv, out)
    if phong is not None:
        return phong_toward_light(scene, ws, index, hit, ndl, rv, out)
    return False


@njit(**JIT_INLINE)
def scatter(scene, ws, kind, index, hit, film, phong, xfilm):
    """The hit's two children: weights ``ws.wr`` (mirror) and ``ws.wt`` (transmitted), their
    cut factors ``ws.cut_r``, ``ws.cut_t``; returns the transmitted direction."""
    if film is not None and (phong is None or kind == SURFACE_FILM):
        return film_scatter(scene, ws, index, hit, xfilm)
    if phong is not None:
        return phong_scatter(scene, ws, index, hit)
    return hit[3]


@njit(**JIT_INLINE)
def shadow(scene, ws, kind, index, n, cos_i, entering, trans, film, phong, xfilm):
    """A shadow ray crossing the surface: multiply *trans* (per channel) by its transmittance;
    False if the surface is opaque."""
    if film is not None and (phong is None or kind == SURFACE_FILM):
        return film_shadow(scene, ws, index, n, cos_i, entering, trans, xfilm)
    if phong is not None:
        return phong_shadow(scene, ws, index, n, cos_i, entering, trans)
    return True
