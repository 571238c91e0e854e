"""A second process that compiles part of the renderer while this one compiles the rest.

The first render on a machine compiles the integrator (:func:`tracer.kernels.integrator.render_rows`)
into numba's on-disk cache, and numba compiles on one thread, under one lock per process.  About
a third of that compile is not ``render_rows`` itself but the kernels numba compiles on their own
when it types a call to them (each a fixed cost of numba's pipeline, LLVM and a cache file;
``docs/performance.md``).  Where a second core is free, :func:`start` runs ``python -m
tracer.rendering.compile_helper`` beside the first render; it compiles, for the scene's types and
in this order, the spherical lights' :func:`~tracer.kernels.integrator.sphere_light` (when the
scene has them), the shadow path :func:`~tracer.kernels.integrator.shadow_along` (with the
kernels it calls: the surface models' optics, the intersection tests), the PNG's sRGB encoder and
the environment's :func:`~tracer.kernels.environment.environment_rgb`, while this process types
``render_rows`` from its top.  numba looks in its cache before it compiles a kernel for a
signature, so each side loads what the other has already written.  The order is the one that
gained most (docs/performance.md): the shadow path is what the render reaches last of its
callees, the encoder is needed only after the render, and the environment, which the render
meets early, is usually compiled by the render first (the helper then loads it).

Nothing changes in the pixels or in the warm kernels: the helper compiles the same functions for
the same argument types (:func:`helper_signatures`; ``tests/tracer/test_compile_helper.py`` checks
each against the signatures a render compiles) into the same cache that a render without it
would fill.  numba writes each cache file to a temporary name and renames it, so the two
processes never read a half-written file.  The helper is stopped when the render's compile is
done (:func:`finish`); whatever it had not compiled yet, this process compiles when it needs it.

It does not start when fewer than two CPUs are usable, or with ``TRACER_COMPILE_HELPER=0`` (the
test suite sets it: its two workers already use both cores).  Measured by
``benchmarks/first_render.py`` (docs/performance.md).
"""

from __future__ import annotations

import importlib
import os
import pickle
import subprocess
import sys

__all__ = ["helper_signatures", "start", "finish", "enabled"]


def enabled() -> bool:
    """Whether a first render starts the helper: two or more usable CPUs and
    ``TRACER_COMPILE_HELPER`` not ``0``."""
    if os.environ.get("TRACER_COMPILE_HELPER", "1").strip() == "0":
        return False
    try:
        cpus = len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        cpus = os.cpu_count() or 1
    return cpus >= 2


def helper_signatures(packed, features=None, png_bits=8):
    """``[(module, function name, argument types), ...]``: what the helper compiles for the packed
    scene *packed* with the integrator's feature flags *features* (default: the scene's,
    :func:`tracer.kernels.integrator.scene_features`), in its order (the module's docstring).  The argument types are those the integrator passes (``numba.typeof`` of values of the
    same kinds), and the encoder's those of a *png_bits* image (:mod:`tracer.rendering.output`)."""
    import numba
    import numpy as np

    from ..kernels.integrator import FEATURES, new_workspace, scene_features

    flags = scene_features(packed) if features is None else features
    area = flags[FEATURES.index("area")]
    # the shadow path and the spherical lights take every flag but "area"
    flag_types = tuple(numba.typeof(f) for name, f in zip(FEATURES, flags) if name != "area")
    scene = numba.typeof(packed)
    ws = new_workspace(packed, 1, np.zeros(1, dtype=np.int64))
    ws_t = numba.typeof(ws)
    vec = numba.typeof((0.0, 0.0, 0.0))
    f64, i64 = numba.float64, numba.int64
    code = np.uint8 if png_bits == 8 else np.uint16
    out = []
    if area is not None:  # (the flag compiles sphere_light whether or not this scene's lights have a radius)
        hit = numba.typeof(((0.0, 0.0, 0.0),) * 4 + (0.0, True))
        w = numba.typeof(ws.w)
        # the first hit's vertex is the literal 0 (numba types that call on its own), later ones int64
        for vertex in (numba.types.literal(0), i64):
            out.append(("tracer.kernels.integrator", "sphere_light",
                        (scene, ws_t, i64, vec, vec, vec, vec, vec, hit, i64, i64, w, numba.uint64, vertex, f64)
                        + flag_types))
    out.append(("tracer.kernels.integrator", "shadow_along",
                (scene, ws_t, vec, vec, f64, numba.typeof(ws.trans)) + flag_types))
    out.append(("bubbleoptics.kernels", "srgb_encode_quantized_array",
                (numba.typeof(np.zeros(1)), f64, numba.typeof(np.zeros(1, dtype=code)))))
    out.append(("tracer.kernels.environment", "environment_rgb",
                (numba.typeof(packed.environment[0]), numba.typeof(packed.env_image), vec)))
    return out


def start(packed, features=None):
    """Start the helper process for the packed scene *packed* (see the module's docstring) and
    return it, or None where it does not run (:func:`enabled`) or cannot start."""
    if not enabled():
        return None
    try:
        payload = pickle.dumps(helper_signatures(packed, features))
        helper = subprocess.Popen([sys.executable, "-m", __name__], stdin=subprocess.PIPE,
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=os.environ.copy())
        helper.stdin.write(payload)
        helper.stdin.close()
        return helper
    except Exception:  # the helper only saves time: never a reason for a render to fail
        return None


def finish(helper):
    """Stop the *helper* (from :func:`start`; None: nothing) if it is still compiling, and reap it."""
    if helper is None:
        return
    if helper.poll() is None:
        helper.terminate()
    try:
        helper.wait(timeout=10)
    except subprocess.TimeoutExpired:
        helper.kill()
        helper.wait()


def main(stream=None):
    """The helper: compile each ``(module, function, argument types)`` of the pickled list on
    *stream* (standard input), in order, into numba's cache.  Exit status 0, or 1 at the first
    that fails (the render then compiles it itself)."""
    items = pickle.load(stream if stream is not None else sys.stdin.buffer)
    for module, name, types in items:
        try:
            getattr(importlib.import_module(module), name).compile(tuple(types))
        except Exception:
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
