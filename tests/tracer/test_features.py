"""The integrator compiled for a scene's features: the flags a scene gets, the images they give,
and what a first render and ``tracer warmup`` say.

* ``property``: a kernel compiled without the features a scene lacks renders it bit for bit as
  the kernel with every feature does (the pruned code is only code those scenes never run).
* ``api``: the flags of scenes that do and do not use each feature; the compile notice and its
  absence; ``tracer warmup``.
"""

import numpy as np
import pytest

import tracer
from cli_helpers import run  # tests/support/cli_helpers.py
from tracer.kernels.integrator import FEATURES, scene_features
from tracer.prepare.pack import pack_scene
from tracer.rendering import local
from tracer.scene import Bubble, FilmProfile, Material, Mesh, PointLight, Scene, Sphere

ROOT = __import__("pathlib").Path(__file__).resolve().parents[2]
SPHERES = ROOT / "data" / "scenes" / "coursework_two_sphere_three_bubbles.txt"
SMALL = dict(width=24, height=24, progress=False)


def _flags(scene, **kwargs):
    return dict(zip(FEATURES, scene_features(pack_scene(scene, **kwargs))))


@pytest.mark.api
def test_each_flag_follows_its_feature(monkeypatch):
    monkeypatch.delenv("TRACER_FEATURES", raising=False)
    glass = Material(color=(1.0, 1.0, 1.0), transmission=0.9, ior=1.5)
    film = FilmProfile("uniform", thickness_nm=300.0)
    plain = _flags(Scene(spheres=[Sphere((0.0, 0.0, 3.0), 1.0, glass)], lights=[PointLight((0.0, 3.0, 0.0), 1.0)]))
    assert plain == dict(mesh=None, area=None, film=None, phong=True, xfilm=None)
    bubble = _flags(Scene(bubbles=[Bubble((0.0, 0.0, 3.0), 1.0, film)]), spectral_method="point")
    assert bubble == dict(mesh=None, area=None, film=True, phong=None, xfilm=None)
    assert _flags(Scene(bubbles=[Bubble((0.0, 0.0, 3.0), 1.0, film, film_model="two-beam")]))["xfilm"] is True
    assert _flags(Scene(bubbles=[Bubble((0.0, 0.0, 3.0), 1.0, film)]), spectral_method="band")["xfilm"] is True
    assert _flags(Scene(bubbles=[Bubble((0.0, 0.0, 3.0), 1.0, film, n_film=1.33 + 0.01j)]))["xfilm"] is True
    tri = Mesh(vertices=np.array([[0.0, 0.0, 3.0], [1.0, 0.0, 3.0], [0.0, 1.0, 3.0]]), faces=np.array([[0, 1, 2]]),
               material=glass)
    assert _flags(Scene(meshes=[tri]))["mesh"] is True
    assert _flags(Scene(lights=[PointLight((0.0, 3.0, 0.0), 1.0, radius=0.5, samples=4)]))["area"] is True
    monkeypatch.setenv("TRACER_FEATURES", "all")
    assert set(_flags(Scene()).values()) == {True}


@pytest.mark.property
@pytest.mark.parametrize("scene", ["builtin", "spheres"])
def test_the_kernel_for_a_scenes_features_gives_the_full_kernels_image(scene, monkeypatch):
    sc = tracer.default_scene() if scene == "builtin" else tracer.load_scene(SPHERES)
    monkeypatch.setenv("TRACER_FEATURES", "all")
    full, full_stats = tracer.render_with_stats(sc, depth=6, **SMALL)
    monkeypatch.delenv("TRACER_FEATURES")
    assert None in scene_features(pack_scene(sc))  # a kernel without some features
    own, own_stats = tracer.render_with_stats(sc, depth=6, **SMALL)
    assert np.array_equal(own, full) and own_stats.rays == full_stats.rays


@pytest.mark.api
def test_a_first_render_says_it_compiles_unless_quiet(monkeypatch, capsys):
    monkeypatch.setattr(local, "is_compiled", lambda *args, **kwargs: False)
    monkeypatch.setattr(local, "_WARMED", set())  # as in a new process
    tracer.render(tracer.default_scene(), width=4, height=4, progress=None)
    err = capsys.readouterr().err
    assert err.count("compiling the renderer for this scene's features") == 1 and "tracer warmup" in err
    tracer.render(tracer.default_scene(), width=4, height=4, progress=False)
    assert "compiling" not in capsys.readouterr().err


@pytest.mark.api
def test_a_kernel_warmed_up_here_is_not_looked_up_again(monkeypatch):
    """After a warm-up in this process the next one neither asks numba's cache (a few ms per render)
    nor says it compiles; without that record (a new process) it asks again."""
    packed = pack_scene(tracer.default_scene())
    local.warm_up(packed)
    asked = []
    monkeypatch.setattr(local, "is_compiled", lambda *args, **kwargs: asked.append(args) or False)
    lines = []
    local.warm_up(packed, notice=lines.append, helper=True)
    assert asked == [] and lines == []
    monkeypatch.setattr(local, "_WARMED", set())
    local.warm_up(packed, notice=lines.append)
    assert len(asked) == 1 and len(lines) == 1


@pytest.mark.api
def test_is_compiled_knows_a_kernel_this_process_has():
    packed = pack_scene(tracer.default_scene())
    local.warm_up(packed)
    assert local.is_compiled(packed)


@pytest.mark.api
def test_warmup_compiles_the_scenes_feature_sets(capsys, tmp_path):
    status, out, err = run(["warmup", SPHERES, "--all"], capsys)
    assert status == 0, err
    lines = [line for line in out.splitlines() if line.startswith("tracer warmup: ")]
    assert lines and all(line.endswith(("already compiled", "compiling ...")) or " compiled in " in line
                         for line in lines), out
    assert any("mesh, area, film, phong, xfilm" in line for line in lines)  # --all
    status, _, err = run(["warmup", tmp_path / "missing.txt"], capsys)
    assert status == 2 and "missing.txt" in err
