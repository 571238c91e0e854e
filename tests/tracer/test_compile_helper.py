"""The second process that compiles part of a first render (:mod:`tracer.rendering.compile_helper`).

* ``api``: every signature the helper compiles is one that a render compiles without it (numba's
  own record: the dispatcher's overloads and its on-disk cache index, filled by the render), so
  the helper never compiles what the render will not load; the helper process's exit status;
  when it does not start.
"""

import io
import pickle
import subprocess
import sys
from importlib import import_module

import numpy as np
import pytest

import tracer
from tracer.prepare.pack import pack_scene
from tracer.rendering import compile_helper
from tracer.rendering.output import save_image

ROOT = __import__("pathlib").Path(__file__).resolve().parents[2]
SPHERES = ROOT / "data" / "scenes" / "coursework_two_sphere_three_bubbles.txt"


def _compiled(dispatcher):
    """The argument types *dispatcher* is compiled for, in this process or in numba's cache."""
    sigs = {tuple(s) for s in dispatcher.signatures}
    index = dispatcher._cache._cache_file._load_index()
    return sigs | {tuple(getattr(key[0], "args", key[0])) for key in index}


@pytest.mark.api
@pytest.mark.parametrize("scene, own_features", [("spheres", True), ("spheres", False), ("builtin", False)])
def test_the_helper_compiles_only_what_a_render_compiles(scene, own_features, monkeypatch, tmp_path):
    """The render (helper off, as in every test) compiles the integrator and its kernels; each
    signature :func:`helper_signatures` names must be among those numba compiled for it, for a
    scene's own feature set (a phong-only kernel) and for the test suite's every-feature one
    (spherical lights, films, meshes)."""
    if own_features:
        monkeypatch.delenv("TRACER_FEATURES", raising=False)
    sc = tracer.default_scene() if scene == "builtin" else tracer.load_scene(SPHERES)
    image = tracer.render(sc, width=4, height=4, progress=False)
    save_image(image, tmp_path / "tiny.png")  # the 8-bit PNG encoder
    wanted = compile_helper.helper_signatures(pack_scene(sc))
    names = [name for _, name, _ in wanted]
    assert names[-2:] == ["srgb_encode_quantized_array", "environment_rgb"] and "shadow_along" in names
    assert ("sphere_light" in names) == (not own_features)  # every-feature kernels have spherical lights
    for module, name, types in wanted:
        assert tuple(types) in _compiled(getattr(import_module(module), name)), (name, types)


@pytest.mark.api
def test_the_helper_process_reports_failure_and_success(tmp_path):
    """An item that cannot compile ends the helper with status 1 (the render compiles it itself);
    a list it can compile, in a fresh cache, with 0."""
    from bubbleoptics.kernels import srgb_encode_quantized_array  # noqa: F401 (the module exists)

    bad = [("bubbleoptics.kernels", "srgb_encode_quantized_array", ())]  # wrong number of arguments
    assert compile_helper.main(io.BytesIO(pickle.dumps(bad))) == 1
    import numba

    good = [("bubbleoptics.kernels", "srgb_encode_quantized_array",
             (numba.typeof(np.zeros(1)), numba.float64, numba.typeof(np.zeros(1, dtype=np.uint16))))]
    env = {**__import__("os").environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    done = subprocess.run([sys.executable, "-m", "tracer.rendering.compile_helper"], input=pickle.dumps(good),
                          env=env, capture_output=True, timeout=300)
    assert done.returncode == 0, done.stderr.decode()
    assert any((tmp_path / "cache").rglob("*srgb_encode_quantized_array*.nbc"))  # written to that cache


@pytest.mark.api
def test_the_helper_starts_only_with_a_second_cpu_and_when_allowed(monkeypatch):
    packed = pack_scene(tracer.load_scene(SPHERES))
    monkeypatch.setenv("TRACER_COMPILE_HELPER", "0")
    assert not compile_helper.enabled() and compile_helper.start(packed) is None
    monkeypatch.setenv("TRACER_COMPILE_HELPER", "1")
    monkeypatch.setattr(compile_helper.os, "sched_getaffinity", lambda pid: {0})
    assert not compile_helper.enabled() and compile_helper.start(packed) is None
    monkeypatch.setattr(compile_helper.os, "sched_getaffinity", lambda pid: {0, 1})
    assert compile_helper.enabled()
    compile_helper.finish(None)  # nothing to stop
