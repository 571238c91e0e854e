"""The scene editor's model (tracer.editor.model) and preview, without widgets or a browser."""

from __future__ import annotations

import doctest
import threading
import time

import numpy as np
import pytest

import tracer
from tracer.editor import EditorModel, FieldError
from tracer.editor import model as model_module
from tracer.editor.preview import PreviewRenderer, film_at_pixel
from tracer.rendering import RenderCancelled, render_with_stats

pytestmark = pytest.mark.api
SMALL = dict(width=24, height=24)


def _render(scene):
    return tracer.render(scene, progress=False, **SMALL)


def test_docstring_examples():
    assert doctest.testmod(model_module).failed == 0


def test_edits_undo_and_commands_file_replays_to_the_edited_scene(tmp_path):
    m = EditorModel()
    m.change_light(1, 1, 4, 6, "3.5")
    m.add_light("-2", 3, 5, 1)
    m.delete_light(1)
    m.change_parameters("old", profile="uniform", thickness_nm="420", n_film="1.4")
    m.change_parameters("young", swirl="0.5", top_nm=150)
    m.change_geometry("middle-aged", "0.1", 0, "-0.2", "1.3")
    m.orbit(20)
    m.zoom(1.5)
    s = m.scene
    assert [light.position for light in s.lights] == [(-2.0, 3.0, 5.0)]
    old = s.bubbles[2]
    assert (old.film.kind, old.film.thickness_nm, old.n_film) == ("uniform", 420.0, 1.4)
    assert s.bubbles[1].radius == pytest.approx(0.42 * 1.3)

    path = m.save_commands(tmp_path / "edits.txt")
    frames = tracer.Timeline.from_file(m.loaded, path).frames(dict(m.render_settings(**SMALL)))
    assert len(frames) == 1
    assert np.array_equal(_render(frames[-1].scene), _render(s))

    for _ in range(8):
        assert m.undo()
    assert not m.undo()
    assert np.array_equal(_render(m.scene), _render(tracer.default_scene()))


@pytest.mark.parametrize("call, field, text", [
    (lambda m: m.change_light(1, "abc", 0, 0, 1), "x", "x: 'abc' is not a number"),
    (lambda m: m.change_light(1, 0, 0, 0, "-1"), "intensity", "intensity must be >= 0 and <= 1e+15, got -1"),
    (lambda m: m.change_light(7, 0, 0, 0, 1), "light", "no light 7"),
    (lambda m: m.change_geometry("old", 0, 0, 0, "0"), "k", "k must be > 0"),
    (lambda m: m.change_geometry("old", "1e16", 0, 0, 1), "dx", "dx must be >= -1e+15"),
    (lambda m: m.change_parameters("old", swirl="2"), "swirl", "swirl must be >= 0 and <= 1, got 2"),
    (lambda m: m.change_parameters("old", n_film="-3"), "n_film", "n_film must be 'water' or a number"),
    (lambda m: m.change_parameters("old", thickness_nm="nan"), "thickness_nm", "thickness_nm must be"),
    (lambda m: m.set_settings(depth="0"), "depth", "depth must be an integer from 1 to 64 in the editor (its render"),
    (lambda m: m.set_settings(spp="x"), "spp", "spp must be an integer from 1 to 256 in the editor"),
    (lambda m: m.set_settings(exposure="99"), "exposure", "exposure must be a number of stops from -64 to 64"),
    (lambda m: m.zoom("0"), "zoom", "zoom must be > 0"),
])
def test_bad_values_name_the_field_and_change_nothing(call, field, text):
    m = EditorModel()
    m.change_light(1, 1, 2, 3, 4)
    before, version, commands = m.scene, m.version, m.commands_text()
    with pytest.raises(FieldError) as err:
        call(m)
    assert err.value.field == field and text in str(err.value)
    assert "\n" not in str(err.value)
    assert (m.version, m.commands_text()) == (version, commands)
    assert m.scene.lights == before.lights and m.scene.bubbles == before.bubbles


def test_load_bad_file_keeps_scene_and_save_then_load_renders_the_same(tmp_path):
    m = EditorModel()
    m.change_geometry("old", 0.2, 0, 0, 1)
    m.set_settings(depth=4, spectral_samples=8)
    bad = tmp_path / "bad.toml"
    bad.write_text("[camera]\nfov_deg = 'wide'\n", encoding="utf-8")
    with pytest.raises(tracer.SceneError, match=f"^{bad}:"):
        m.load(bad)
    assert m.scene.bubbles[2].center[0] == pytest.approx(0.5)
    path = m.save_scene(tmp_path / "edited.toml")
    edited = m.scene
    m2 = EditorModel().load(path)
    assert m2.settings["depth"] == 4 and m2.settings["spectral_samples"] == 8
    kw = m.render_settings(**SMALL)
    assert np.array_equal(tracer.render(m2.scene, progress=False, **kw), tracer.render(edited, progress=False, **kw))


def test_render_cancel_hook():
    ev = threading.Event()
    ev.set()
    with pytest.raises(RenderCancelled):
        render_with_stats(tracer.default_scene(), width=64, height=64, progress=False, cancel=ev)
    image, _ = render_with_stats(tracer.default_scene(), progress=False, cancel=lambda: False, **SMALL)
    assert np.array_equal(image, _render(tracer.default_scene()))


def test_preview_renders_small_then_full_and_drops_overtaken_requests():
    got = []
    done = threading.Event()

    def on_image(im):
        got.append((im.version, im.stage, im.codes.shape))
        if im.version == 2 and im.stage == "full":
            done.set()

    pr = PreviewRenderer(on_image)
    scene = tracer.default_scene()
    pr.request(scene, dict(width=96, height=96, depth=2), version=1)
    pr.request(scene, dict(width=96, height=96, depth=2), version=2)
    assert done.wait(120)
    pr.close()
    assert got[-2:] == [(2, "preview", (16, 16, 3)), (2, "full", (96, 96, 3))]
    assert all(v in (1, 2) for v, _, _ in got) and got.count((1, "full", (96, 96, 3))) <= 1


def test_film_at_pixel_is_the_first_bubble_film():
    scene = tracer.default_scene()
    m = EditorModel(scene)
    m.change_parameters("old", profile="uniform", thickness_nm="300", swirl="0")
    # the pixel where the centre of "old" is seen (the camera's projection, square image)
    s = m.scene
    origin, fwd, right, up = s.camera.basis()
    p = np.asarray(s.bubbles[2].center) - origin
    t = np.tan(np.radians(s.camera.fov_deg) / 2)
    x, y = p @ right / (p @ fwd) / t, p @ up / (p @ fwd) / t
    col, row = int((x + 1) / 2 * 64), int((1 - y) / 2 * 64)
    sample = film_at_pixel(s, col, row, 64, 64)
    assert sample is not None and sample.bubble == "old" and sample.thickness_nm == pytest.approx(300.0)
    assert sample.reflectance.shape == sample.wavelengths_nm.shape
    from bubbleoptics import film_reflectance

    R = film_reflectance(sample.wavelengths_nm, 300.0, np.radians(sample.angle_deg), None)
    assert np.allclose(sample.reflectance, R)
    assert film_at_pixel(s, 0, 0, 64, 64) is None  # the sky


def test_load_coursework_format():
    m = EditorModel().load("data/scenes/coursework_three_bubbles.txt")
    assert [kind for _, kind in m.objects()].count("bubble") == 3 and m.lights
    m.change_light(1, 100, 200, 1000, 0.5)
    assert tracer.Timeline.from_text(m.loaded, m.commands_text()).frames()[-1].scene.lights[0].intensity == 0.5


# ------------------------------------------------------------------------------------------
# the Panel app's wiring, without a browser (the browser tests: tests/tracer/test_editor_browser.py)
# ------------------------------------------------------------------------------------------
def test_app_handlers_and_inline_messages():
    pytest.importorskip("panel")
    from tracer.editor.app import EditorApp

    app = EditorApp(width=32, height=32)
    assert app.preview.idle(120)
    assert app.stage == "full" and app.image.shape == (32, 32, 3)
    version, image = app.model.version, app.image
    app.light_fields["intensity"].value = "abc"
    app._guard(app.on_change_light)
    msg = app.light_fields["intensity"].message
    assert msg.visible and "is not a number" in msg.object
    assert app.model.version == version and app.image is image  # nothing changed
    app.light_fields["intensity"].value = "7"
    app._guard(app.on_change_light)
    assert not msg.visible and app.model.lights[0].intensity == 7
    assert app.preview.idle(120) and app.shown_version == app.model.version
    app._guard(app.on_clear)
    assert app.stage == "cleared"
    app.preview.close()
    cell = tracer.editor(tracer.default_scene(), width=16, height=16)  # what a notebook cell shows
    assert hasattr(cell, "_repr_mimebundle_")


def test_cli_edit_bad_input_is_one_line(tmp_path, capsys):
    pytest.importorskip("panel")
    from tracer.cli import main

    bad = tmp_path / "bad.toml"
    bad.write_text("[camera]\nfov_deg = 'wide'\n", encoding="utf-8")
    assert main(["edit", str(bad), "--no-browser"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"{bad}:") and "\n" not in err
    with pytest.raises(SystemExit) as exit_:
        main(["edit", "--port", "99999"])
    assert exit_.value.code == 2
    assert "must be an integer from 0 to 65535" in capsys.readouterr().err


def test_tracer_edit_serves_and_stops_cleanly_on_ctrl_c():
    """``tracer edit`` serves the page on its port, and Ctrl-C (SIGINT) stops it with status 0
    (:func:`tracer.editor.testing.editor_server` checks the status; the browser tests' server
    is stopped with SIGTERM, checked the same way)."""
    pytest.importorskip("panel")
    import signal
    import urllib.request
    from pathlib import Path

    from tracer.editor.testing import editor_server

    with editor_server(width=16, height=16, cwd=Path(__file__).resolve().parents[2],
                       stop=signal.SIGINT) as url:
        page = urllib.request.urlopen(url, timeout=30).read().decode()
        assert "tracer scene editor" in page


def test_picking_while_the_preview_renders_is_safe():
    """numba's workqueue pool is not thread-safe: a pick (packing, spectra: parallel kernels)
    while the preview renders in its thread must wait for it (tracer.rendering.local.PARALLEL_LOCK), not
    run beside it."""
    scene = tracer.default_scene()
    done = threading.Event()
    pr = PreviewRenderer(lambda im: done.set() if im.stage == "full" else None)
    pr.request(scene, dict(width=128, height=128), version=1)
    picks = [film_at_pixel(scene, 40, 60, 128, 128) for _ in range(10)]
    assert done.wait(120) and pr.idle(120)
    pr.close()
    assert all(p is not None and p.thickness_nm == picks[0].thickness_nm for p in picks)


@pytest.mark.notebook
def test_editor_in_a_notebook_cell():
    """``tracer.editor(scene)`` as the last line of a cell, in a Jupyter kernel: the cell's output
    is Panel's app (its exec mimebundle), and its background render (which pushes the image to
    the cell) raises nothing."""
    pytest.importorskip("panel")
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    nb = nbformat.v4.new_notebook()
    nb.cells = [
        nbformat.v4.new_code_cell(f"import sys; sys.path.insert(0, {str(root)!r})\n"
                                  "import panel as pn; pn.extension()\nimport tracer\n"
                                  "app = tracer.editor(tracer.default_scene(), width=32, height=32)\napp"),
        nbformat.v4.new_code_cell("import time; time.sleep(2); print('rendered')"),
    ]
    nbclient.NotebookClient(nb, timeout=120, kernel_name="python3").execute()
    outputs = [o for c in nb.cells for o in c.get("outputs", [])]
    assert any("application/vnd.holoviews_exec.v0+json" in o.get("data", {}) for o in outputs)
    assert not [o for o in outputs if o.get("output_type") == "error" or o.get("name") == "stderr"]
    assert outputs[-1].get("text", "").strip() == "rendered"


# ------------------------------------------------------------------------------------------
# the render scheduler (every editor's renders, in turns) and the render budget
# ------------------------------------------------------------------------------------------
def _logging_job(log, name, steps, priority, started=None):
    from tracer.editor.scheduler import BACKGROUND  # noqa: F401

    def make(cancel):
        for i in range(steps):
            if started is not None:
                started.set()
            log.append((name, i))
            time.sleep(0.005)
            yield priority

    return make


def test_scheduler_runs_a_preview_before_the_next_step_of_a_long_render():
    from tracer.editor.scheduler import BACKGROUND, INTERACTIVE, RenderScheduler

    sched, log = RenderScheduler(), []
    a, b = object(), object()
    started = threading.Event()
    sched.submit(a, "render", _logging_job(log, "A", 200, BACKGROUND, started))
    assert started.wait(10)
    time.sleep(0.05)
    n_before = len(log)
    sched.submit(b, "render", _logging_job(log, "B", 1, INTERACTIVE))
    assert sched.idle(b, timeout=30)
    at = log.index(("B", 0))
    assert at - n_before <= 2  # at most the step in progress (and one racing the submit) came first
    assert sched.close(timeout=5)


def test_scheduler_shares_turns_between_owners_and_cancels():
    from tracer.editor.scheduler import BACKGROUND, RenderScheduler

    sched, log = RenderScheduler(), []
    a, b = object(), object()
    gate = threading.Event()

    def blocked(cancel):  # holds the thread until both jobs are queued
        gate.wait(10)
        yield BACKGROUND

    sched.submit(object(), "render", blocked)
    sched.submit(a, "render", _logging_job(log, "A", 10, BACKGROUND))
    sched.submit(b, "render", _logging_job(log, "B", 10, BACKGROUND))
    gate.set()
    assert sched.idle(timeout=30)
    names = [n for n, _ in log]
    assert sorted(names) == ["A"] * 10 + ["B"] * 10
    assert max(len(run) for run in "".join(names).replace("AB", "A B").replace("BA", "B A").split()) <= 2
    # a new job of the same kind replaces (cancels) the old; cancel() stops an owner's jobs
    log.clear()
    started = threading.Event()
    sched.submit(a, "render", _logging_job(log, "old", 10_000, BACKGROUND, started))
    assert started.wait(10)
    sched.submit(a, "render", _logging_job(log, "new", 3, BACKGROUND))
    assert sched.idle(a, timeout=30)
    assert [n for n, _ in log].count("new") == 3 and [n for n, _ in log].count("old") < 50
    sched.submit(b, "render", _logging_job(log, "gone", 10_000, BACKGROUND))
    sched.cancel(b)
    assert sched.idle(b, timeout=5)
    assert [n for n, _ in log].count("gone") <= 1
    assert sched.close(timeout=5)


def test_a_cancelled_render_stops_mid_stage():
    """The kernel polls the job's cancel event: a full render stops at its next ray, not at the
    end of its stage (a closed tab's render ends at once)."""
    from tracer.editor.preview import PreviewRenderer

    stages = []
    pr = PreviewRenderer(lambda im: stages.append(im.stage))
    pr.request(tracer.default_scene(), dict(width=256, height=256, spp=64, depth=10), version=1)
    t0 = time.monotonic()
    while "preview" not in stages and time.monotonic() - t0 < 120:
        time.sleep(0.01)
    pr.close()
    assert pr.idle(timeout=10)
    assert stages == ["preview"]  # the full stage (64 spp) never finished


def test_render_budget_caps_each_setting_and_their_product():
    from tracer.editor.model import EDITOR_LIMITS, MAX_WORK, EditorModel, FieldError, render_work

    m = EditorModel(size=(960, 960))
    for name, value, cap in (("depth", 1000, 64), ("spp", 65536, 256), ("spectral_samples", 421, 128)):
        with pytest.raises(FieldError, match=f"{name} must be an integer from 1 to {cap} in the editor"):
            m.set_settings(**{name: value})
        assert EDITOR_LIMITS[name] == cap
    with pytest.raises(FieldError, match="over the editor's render budget") as info:
        m.set_settings(spp=64)
    assert info.value.field == "spp" and m.settings["spp"] == 1
    m.set_settings(spp=16)  # exactly 16 times the defaults' work
    assert render_work(960, 960, m.settings) == MAX_WORK
    # a scene asking for more is loaded within the budget, and says so
    heavy = tracer.default_scene()
    heavy.render_defaults = {"depth": 1000, "spp": 4096, "spectral_samples": 64}
    m2 = EditorModel(heavy, size=(960, 960))
    assert render_work(960, 960, m2.settings) <= MAX_WORK and m2.settings["depth"] == 64
    assert any(n.startswith("depth 1000 -> 64") for n in m2.budget_notes)
    with pytest.raises(FieldError, match="at most 4096 x 4096"):
        EditorModel(size=(5000, 10))


def test_editor_refuses_a_scene_whose_names_have_control_characters():
    from tracer.editor.model import EditorModel, FieldError

    scene = tracer.default_scene()
    scene.bubbles[0].name = "young\nrender 1000000"
    with pytest.raises(FieldError, match="control character"):
        EditorModel(scene)
