"""The numba options every kernel of the project is compiled with (bubbleoptics and the tracer).

``error_model="numpy"``: a float division never raises (the denominators are positive by
construction, and the property tests check that no NaN appears); without it numba guards every
division with a branch, which stops LLVM from vectorizing the thickness loop (several times
slower).  ``cache=True``: compiled code is kept in numba's on-disk cache, so a second process
starts at once.
"""

__all__ = ["JIT", "JIT_INLINE", "JIT_PARALLEL", "JIT_NO_NRT", "JIT_FMA"]

#: A kernel of its own, cached on disk.
JIT = dict(cache=True, error_model="numpy")
#: Inlined into its callers (numba IR inlining): no cache of its own.
JIT_INLINE = dict(inline="always", error_model="numpy")
#: A parallel kernel (``prange``), cached on disk.
JIT_PARALLEL = dict(cache=True, error_model="numpy", parallel=True)
#: A per-ray function that allocates nothing, compiled without numba's reference counting
#: (:mod:`tracer.kernels.integrator` says why).
JIT_NO_NRT = dict(_nrt=False, cache=True, error_model="numpy")
#: :data:`JIT` with fused multiply-add allowed (``fastmath={"contract"}``, LLVM's ``contract`` flag
#: only: no reassociation, no assumption about NaN or infinity).  A fused a*b + c is rounded once
#: instead of twice, so it is never less accurate; it is used only in the polynomial and per-band
#: kernels the tracer spends its time in (the thin-film evaluation over the bands, the swirl's
#: sines), which run a fifth to a third faster with it (docs/performance.md).  Results then
#: differ from a build without FMA at the level of rounding, as they do between libm versions.
JIT_FMA = dict(cache=True, error_model="numpy", fastmath={"contract"})
