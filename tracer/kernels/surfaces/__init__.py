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

The integrator (:mod:`tracer.kernels.integrator`) calls each model's answer by the surface kind of
the hit (:data:`tracer.kernels.records.SURFACE_FILM`, :data:`~tracer.kernels.records.SURFACE_PHONG`)
and never looks inside a model.  It chooses the model itself, behind the scene's feature flags,
rather than through a dispatch function here: numba removes the code of an absent feature
before inlining only in the function it is compiling, so a dispatch function would copy every
model into every call site first and throw the unused ones away afterwards, which was about a
third of a sphere-only scene's first compile (docs/performance.md).  A new surface kind is a module
answering the four questions, a kind constant in :mod:`tracer.kernels.records`, its records in
:mod:`tracer.prepare.pack`, a feature flag (:func:`tracer.kernels.integrator.scene_features`)
and one branch at each of the integrator's four questions.

A *hit* is the tuple ``(p, n, nf, d, cos_i, entering)``: the point, the outward unit normal,
the normal facing the incoming ray, the incoming unit direction, :math:`|d\\cdot n|`, and
whether the ray arrives from outside.  Per-channel results go into the thread's
:class:`tracer.kernels.integrator.Workspace` (``wr``, ``wt``, ``cut_r``, ``cut_t``) or the array
passed in.  Every function is inlined into the integrator (``inline="always"``): the arrays
they read are then never passed across a call, which costs more than most of the work here.
"""

from .phong import phong_ambient, phong_scatter, phong_shadow, phong_toward_light
from .soap_film import film_scatter, film_shadow, film_toward_light

__all__ = ["phong_ambient", "phong_scatter", "phong_shadow", "phong_toward_light", "film_scatter", "film_shadow",
           "film_toward_light"]
