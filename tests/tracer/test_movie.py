"""Movies: the commands file, the Timeline's interpolation, ``tracer movie``/``film``,
the frame cache, the encoders, and frames rendered on a Dask cluster.

Renders are tiny (a few pixels, depth 2) so the file runs in seconds once the kernels are in
numba's cache; one module-scoped LocalCluster of two workers serves the distributed tests.
"""

import dataclasses
import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest

import tracer
import tracer.movie.run as movie_module
import tracer.rendering.dask as cluster_module
from tracer.movie import check_movie_output, movie_cache_folder, render_frame_files, render_movie
from tracer.rendering import resolve_settings
from tracer.movie.commands import CommandsError
from tracer.movie.timeline import Timeline
from tracer.scene import Material, Mesh, Scene, Sphere
from cli_helpers import run, assert_one_line  # tests/support/cli_helpers.py

ROOT = Path(__file__).resolve().parents[2]
THREE = ROOT / "data" / "scenes" / "coursework_three_bubbles.txt"
MOVIES = ROOT / "data" / "movies"
TINY = ["--width", "8", "--height", "6", "--depth", "2", "--quiet"]
TINY_SETTINGS = dict(width=8, height=6, depth=2)




def three():
    return tracer.load_scene(THREE)


def pngs(folder):
    import imageio.v3 as iio

    return [iio.imread(p) for p in sorted(Path(folder).glob("*.png"))]


class Counter:
    """Wraps render_frame_files, counting calls (and optionally interrupting one)."""

    def __init__(self, interrupt_at=None):
        self.calls = 0
        self.interrupt_at = interrupt_at

    def __call__(self, frame, bits=8):
        self.calls += 1
        if self.calls == self.interrupt_at:
            raise KeyboardInterrupt
        return render_frame_files(frame, bits)


# ------------------------------------------------------------------------------------------
# the commands file: every kind of bad line is one line COMMANDS:LINE: ...
# ------------------------------------------------------------------------------------------
BAD_COMMANDS = {
    "unknown command": ("render 1\nmvoe пузырь1 1 2 3\nrender 1", 2, "unknown command; did you mean 'move'?"),
    "unknown name": ("move пузырь9 1 2 3\nrender 1", 1, "no object named 'пузырь9'"),
    "unknown name lists the known": ("scale x 2\nrender 1", 1, "'пузырь1', 'пузырь2', 'пузырь3'"),
    "too few numbers": ("move пузырь1 1 2\nrender 1", 1, "expected 'move NAME dx dy dz', found 3 fields"),
    "too many numbers": ("scale пузырь1 2 3\nrender 1", 1, "expected 'scale NAME k'"),
    "not a number": ("move пузырь1 1 x 3\nrender 1", 1, "(dy): 'x' is not a number"),
    "non-ASCII digits": ("move пузырь1 1 ١٠ 3\nrender 1", 1, "is not a number"),
    "comma decimal": ("scale пузырь1 1,5\nrender 1", 1, "'1,5' is not a number"),
    "nan": ("move пузырь1 1 nan 3\nrender 1", 1, "is nan: it must be a finite number"),
    "inf": ("rotate пузырь1 0 1 0 inf\nrender 1", 1, "it must be a finite number"),
    "too large": ("move пузырь1 1e16 0 0\nrender 1", 1, "outside -1e+15 to 1e+15"),
    "moved out of range": ("move пузырь1 9e14 0 0\nmove пузырь1 9e14 0 0\nrender 1", 2, "outside -1e+15"),
    "render 0": ("render 0", 1, "frame count must be an integer >= 1, got 0"),
    "render fraction": ("render 2.5", 1, "'2.5' is not an integer"),
    "render without count": ("render", 1, "expected 'render K'"),
    "negative scale": ("scale пузырь1 -2\nrender 1", 1, "factor must be > 0, got -2"),
    "zero axis": ("rotate пузырь1 0 0 0 30\nrender 1", 1, "axis must not be the zero vector"),
    "unknown field": ("set пузырь1 colour 1 1 1\nrender 1", 1, "has no field 'colour'"),
    "field out of range": ("set пузырь1 thickness -5\nrender 1", 1, "must be >= 0"),
    "light number out of range": ("light 2 0 0 0 1\nrender 1", 1, "no light 2: the scene has light 1"),
    "light zero": ("light 0 0 0 0 1\nrender 1", 1, "no light 0"),
    "deleted light": ("light delete 1\nlight 1 0 0 0 1\nrender 1", 2, "no light 1: the scene has no lights"),
    "negative intensity": ("light add 0 0 0 -1\nrender 1", 1, "intensity must be >= 0"),
    "camera what": ("camera zoom 2\nrender 1", 1, "found 'camera zoom'"),
    "fov out of range": ("camera fov 180\nrender 1", 1, "must be > 0 and < 180"),
    "camera onto its look-at": ("camera position 480 480 0\nrender 3", 2, "look_at coincides with its position"),
    "camera through its look-at": ("camera position 480 480 -2000\nrender 2", 2, "frame 1 of this render"),
    "negative time": ("time -1\nrender 1", 1, "time must be >= 0"),
    "open quote": ("move \"пузырь1 1 2 3\nrender 1", 1, "no closing quotation"),
    "change after the last render": ("render 2\nmove пузырь1 1 0 0\n# end\n", 2, "after the last 'render'"),
    "no render": ("# only a comment\n\n", None, "no frames: the file has no 'render K' command"),
}


@pytest.mark.api
@pytest.mark.parametrize("text,line,what", BAD_COMMANDS.values(), ids=BAD_COMMANDS)
def test_bad_commands_are_one_line_with_the_line(text, line, what):
    with pytest.raises(CommandsError) as info:
        Timeline.from_text(three(), text, "movie.txt")
    err = info.value
    assert err.line == line
    assert what in err.message, err.message
    assert str(err).startswith(f"movie.txt:{line}: " if line else "movie.txt: ")
    assert "\n" not in str(err)


@pytest.mark.api
def test_comments_blank_lines_quotes_and_crlf():
    scene = three()
    scene.bubbles[0].name = "a bubble"
    text = "\ufeff# a movie\r\n\r\n  render 1  # the scene as loaded\r\nmove 'a bubble' 10 0 0\r\nrender 1\r\n"
    tl = Timeline.from_text(scene, text)
    centres = [s.bubbles[0].center for s, _ in tl.scenes()]
    assert centres == [(320.0, 560.0, 0.0), (330.0, 560.0, 0.0)]


@pytest.mark.api
def test_commands_file_that_is_not_text(tmp_path):
    path = tmp_path / "c.txt"
    path.write_bytes(b"render 1\n\x00\x01")
    with pytest.raises(CommandsError, match=r"c\.txt:2: binary data"):
        Timeline.from_file(three(), path)
    with pytest.raises(CommandsError, match="no such file"):
        Timeline.from_file(three(), tmp_path / "missing.txt")


# ------------------------------------------------------------------------------------------
# interpolation: frame k of K shows k/K of every change
# ------------------------------------------------------------------------------------------
@pytest.mark.analytic
def test_first_frames_show_the_scene_as_loaded_and_moves_are_linear():
    scene = three()
    tl = Timeline.from_text(scene, "render 3\nmove пузырь1 40 -20 8\nrender 4\nrender 2\n")
    xs = [s.bubbles[0].center for s, _ in tl.scenes()]
    assert len(xs) == 9
    assert xs[:3] == [(320.0, 560.0, 0.0)] * 3
    for k in range(1, 5):
        assert xs[2 + k] == pytest.approx((320 + 40 * k / 4, 560 - 20 * k / 4, 8 * k / 4), abs=1e-12)
    assert xs[7] == xs[8] == pytest.approx((360.0, 540.0, 8.0))
    assert scene.bubbles[0].center == (320.0, 560.0, 0.0)  # the scene given is not changed


@pytest.mark.analytic
def test_render_1_jumps():
    tl = Timeline.from_text(three(), "render 1\nscale пузырь2 3\nrender 1\n")
    radii = [s.bubbles[1].radius for s, _ in tl.scenes()]
    assert radii == [100.0, 300.0]


@pytest.mark.analytic
def test_scale_set_and_time_are_linear_and_changes_compose():
    text = ("scale пузырь3 2\nset пузырь1 thickness 400\nset пузырь1 thickness 500\ntime 2\n"
            "move пузырь3 10 0 0\nmove пузырь3 10 0 0\nrender 5\n")
    tl = Timeline.from_text(three(), text)
    for k, f in enumerate(tl.frames(TINY_SETTINGS), start=1):
        t = k / 5
        assert f.scene.bubbles[2].radius == pytest.approx(100 * (1 + t))
        assert f.scene.bubbles[0].film.thickness_nm == pytest.approx(100 + t * 400)  # one line, not two
        assert f.scene.bubbles[2].center[0] == pytest.approx(480 + 20 * t)
        assert f.time == pytest.approx(2 * t)
        assert f.settings == TINY_SETTINGS and f.index == k - 1 and f.line == 7


@pytest.mark.analytic
def test_camera_orbit_turns_by_k_over_K_of_the_angle_about_the_look_at_point():
    scene = tracer.default_scene()
    cam = scene.camera
    tl = Timeline(scene).camera_orbit(90).render(3)
    look = np.array(cam.look_at)
    up = np.array(cam.up)
    v0 = np.array(cam.position) - look
    v0h = v0 - v0.dot(up) * up
    for k, (s, _) in enumerate(tl.scenes(), start=1):
        v = np.array(s.camera.position) - look
        assert np.linalg.norm(v) == pytest.approx(np.linalg.norm(v0))
        assert v.dot(up) == pytest.approx(v0.dot(up))  # stays at its height
        vh = v - v.dot(up) * up
        angle = math.degrees(math.atan2(np.cross(v0h, vh).dot(up), v0h.dot(vh)))
        assert angle == pytest.approx(90 * k / 3)
        assert s.camera.look_at == cam.look_at


@pytest.mark.analytic
def test_camera_position_look_at_and_fov_are_linear():
    scene = tracer.default_scene()
    tl = Timeline(scene).camera_position(0, 1.6, 8).camera_look_at(1, 0, 0).camera_fov(20).render(2)
    (a, _), (b, _) = tl.scenes()
    assert a.camera.position == pytest.approx((0, 1.6, 6)) and b.camera.position == pytest.approx((0, 1.6, 8))
    assert a.camera.look_at == pytest.approx((0.525, -0.025, 0))
    assert a.camera.fov_deg == pytest.approx(29) and b.camera.fov_deg == pytest.approx(20)


@pytest.mark.analytic
def test_lights_fade_in_and_out_and_are_numbered_as_the_list_is():
    scene = three()  # one light, (1000, 1000, 1000) at 0.5
    text = "light add 0 0 100 0.8\nrender 2\nlight delete 1\nlight 1 0 0 200 0.4\nrender 2\n"
    tl = Timeline.from_text(scene, text)
    lights = [[(l.position, l.intensity) for l in s.lights] for s, _ in tl.scenes()]
    assert lights[0] == [((1000, 1000, 1000), 0.5), ((0, 0, 100), pytest.approx(0.4))]
    assert lights[1] == [((1000, 1000, 1000), 0.5), ((0, 0, 100), 0.8)]
    # light 1 is deleted (fading), so "light 1" is the added one, moving and dimming
    assert lights[2] == [((1000, 1000, 1000), 0.25), ((0, 0, pytest.approx(150)), pytest.approx(0.6))]
    assert lights[3] == [((0, 0, 200), pytest.approx(0.4))]


@pytest.mark.analytic
def test_rotate_turns_mesh_vertices_about_the_centre_and_a_bubbles_film():
    verts = np.array([[0.0, 0, 0], [2, 0, 0], [0, 2, 0]])
    scene = Scene(meshes=[Mesh(verts, np.array([[0, 1, 2]]), name="tri")],
                  bubbles=[tracer.Bubble((5, 0, 0), 1.0, name="b")])
    tl = Timeline(scene).rotate("tri", 0, 0, 2, 90).rotate("b", 1, 0, 0, 90).render(2)
    (half, _), (full, _) = tl.scenes()
    c = np.array([1.0, 1.0, 0.0])  # the bounding box's middle
    expect = c + (verts - c) @ np.array([[0, 1, 0], [-1, 0, 0], [0, 0, 1]])  # +90 degrees about z
    assert np.allclose(full.meshes[0].vertices, expect)
    r = math.sqrt(0.5)
    turned = half.meshes[0].vertices[1] - c  # (1, -1, 0) at -45 degrees, turned by 45
    assert turned == pytest.approx([math.sqrt(2), 0.0, 0.0])
    assert full.bubbles[0].film.up == pytest.approx((0, 0, 1))
    assert half.bubbles[0].film.up == pytest.approx((0, r, r))
    assert np.array_equal(scene.meshes[0].vertices, verts)  # the scene given is not changed


@pytest.mark.api
def test_set_copies_a_shared_material():
    shared = Material(name="glass", color=(0.2, 0.4, 0.6), transmission=0.5)
    scene = Scene(spheres=[Sphere((0, 0, 0), 1, shared, name="a"), Sphere((3, 0, 0), 1, shared, name="b")])
    tl = Timeline(scene).set("a", "color", 1.0, 0.4, 0.0).set("a", "ior", 1.5).render(2)
    (half, _), (full, _) = tl.scenes()
    assert half.spheres[0].material.color == pytest.approx((0.6, 0.4, 0.3))
    assert full.spheres[0].material.color == (1.0, 0.4, 0.0) and full.spheres[0].material.ior == 1.5
    assert full.spheres[1].material == shared  # the other object sharing it keeps its own
    assert shared.color == (0.2, 0.4, 0.6) and shared.ior == 1.0


@pytest.mark.api
def test_duplicate_names_are_refused_and_pending_changes_are_not_frames():
    scene = Scene(spheres=[Sphere((0, 0, 0), 1, name="x"), Sphere((3, 0, 0), 1, name="x")])
    with pytest.raises(ValueError, match="2 objects are named 'x'"):
        Timeline(scene).move("x", 1, 0, 0)
    tl = Timeline(tracer.default_scene()).render(1).move("old", 1, 0, 0)
    assert tl.pending == 1
    with pytest.raises(ValueError, match="after the last render"):
        tl.frames()


@pytest.mark.api
def test_frame_keys_follow_the_description_not_the_index_or_source():
    tl = Timeline.from_text(three(), "render 2\nmove пузырь1 1 0 0\nrender 1\n")
    f0, f1, f2 = tl.frames(TINY_SETTINGS)
    assert f0.key() == f1.key() != f2.key()
    assert f0.key() != f0.key(bits=16)
    other = dataclasses.replace(f0, settings={**TINY_SETTINGS, "seed": 1})
    assert other.key() != f0.key()
    moved = dataclasses.replace(f0, scene=dataclasses.replace(f0.scene, source="elsewhere.txt"), index=7)
    assert moved.key() == f0.key()
    nudged = dataclasses.replace(f2, scene=dataclasses.replace(f2.scene, bubbles=[
        dataclasses.replace(f2.scene.bubbles[0], center=(321.0000000000001, 560.0, 0.0))] + f2.scene.bubbles[1:]))
    assert nudged.key() != f2.key()  # floats are hashed bit for bit


# ------------------------------------------------------------------------------------------
# tracer movie / tracer film
# ------------------------------------------------------------------------------------------
DRIFT = "render 1\nmove пузырь1 160 0 0\ncamera orbit 4\nrender 3\n"
ORBIT = "render 1\nmove old 0.4 0 0\ncamera orbit 20\nrender 3\n"  # the built-in scene


@pytest.fixture
def drift(tmp_path):
    path = tmp_path / "drift.txt"
    path.write_text(DRIFT, encoding="utf-8")
    return path


#: Display options of tracer image that movies apply to every frame (ACES when OpenColorIO is there).
DISPLAY = ["--exposure", "1.5", "--view", "aces"] if importlib.util.find_spec("PyOpenColorIO") else ["--exposure", "1.5"]


@pytest.mark.reference
@pytest.mark.parametrize("scene_file,commands,display", [(THREE, DRIFT, []), (None, ORBIT, []), (None, ORBIT, DISPLAY)],
                         ids=["coursework", "built-in", "exposure-and-view"])
def test_a_frame_equals_tracer_image_of_the_scene_it_describes(tmp_path, capsys, scene_file, commands, display):
    """Each frame of a folder movie against ``tracer image`` of that frame's scene, written as
    TOML (the scene writer round-trips bit for bit), with the same display options: within
    one 8-bit step."""
    import imageio.v3 as iio

    drift = tmp_path / "commands.txt"
    drift.write_text(commands, encoding="utf-8")
    out = tmp_path / "frames"
    status, _, err = run(["film", *([scene_file] if scene_file else []), out, drift, *TINY, *display], capsys)
    assert status == 0, err
    frames = pngs(out)
    assert [p.name for p in sorted(out.iterdir())] == ["0000.png", "0001.png", "0002.png", "0003.png"]
    tl = Timeline.from_file(three() if scene_file else tracer.default_scene(), drift)
    for i, (scene, _) in enumerate(tl.scenes()):
        toml = tmp_path / f"frame{i}.toml"
        tracer.scene.load.save_toml_scene(scene, toml)
        png = tmp_path / f"frame{i}.png"
        assert run(["image", toml, png, *TINY, *display], capsys)[0] == 0
        single = iio.imread(png)
        assert np.abs(frames[i].astype(int) - single.astype(int)).max() <= 1
    if scene_file is None:
        assert np.any(frames[0] != frames[3])  # the camera did move
    if display:  # and the options did something: brighter than the movie at exposure 0
        plain = tmp_path / "plain"
        assert run(["film", plain, drift, *TINY], capsys)[0] == 0
        assert frames[0].astype(int).sum() > pngs(plain)[0].astype(int).sum()


@pytest.mark.reference
def test_spectral_out_keeps_each_frames_spectral_image_as_tracer_image_does(tmp_path, capsys, drift):
    """``--spectral-out FOLDER``: FOLDER/NNNN.npz per frame, equal to ``tracer image
    --spectral-out`` of that frame's scene (the coursework's scene is RGB-only without it:
    the option forces spectral transport, as for an image)."""
    out, spectra = tmp_path / "frames", tmp_path / "spectra"
    status, _, err = run(["movie", THREE, out, drift, *TINY, "--spectral-out", spectra], capsys)
    assert status == 0, err
    assert [p.name for p in sorted(spectra.iterdir())] == ["0000.npz", "0001.npz", "0002.npz", "0003.npz"]
    tl = Timeline.from_file(three(), drift)
    for i, (scene, _) in enumerate(tl.scenes()):
        if i not in (0, 3):
            continue
        toml = tmp_path / f"frame{i}.toml"
        tracer.scene.load.save_toml_scene(scene, toml)
        single = tmp_path / f"frame{i}.npz"
        assert run(["image", toml, tmp_path / f"frame{i}.png", *TINY, "--spectral-out", single], capsys)[0] == 0
        mine, theirs = tracer.load_spectral(spectra / f"{i:04d}.npz"), tracer.load_spectral(single)
        assert np.array_equal(mine.radiance, theirs.radiance) and np.array_equal(mine.wavelengths_nm,
                                                                                 theirs.wavelengths_nm)
    # a rerun finds every frame (and its spectrum) in the cache
    result = render_movie(three(), drift, out, **TINY_SETTINGS, spectral_out=spectra, progress=False)
    assert result.rendered == 0
    # without --spectral-out the frames are other frames (RGB transport): rendered anew
    assert render_movie(three(), drift, out, **TINY_SETTINGS, progress=False).rendered == 4


@pytest.mark.api
def test_display_settings_and_spectral_flag_are_in_the_frame_key():
    tl = Timeline(tracer.default_scene()).render(1)
    settings = resolve_settings(tracer.default_scene(), width=8, height=8)
    base = tl.frames(settings)[0].key()
    assert tl.frames(settings, {"exposure": 0.0, "view": "clip"})[0].key() == base
    assert tl.frames(settings, {"exposure": 0.5, "view": "clip"})[0].key() != base
    assert tl.frames(settings, {"exposure": 0.0, "view": "aces"})[0].key() != base
    assert tl.frames(settings, spectral=True)[0].key() != base


@pytest.mark.api
def test_a_scenes_render_table_exposure_applies_to_its_movie(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    tracer.scene.load.save_toml_scene(tracer.default_scene(), scene)
    text = scene.read_text()
    scene.write_text(text.replace("[render]", "[render]\nexposure = 2.0") if "[render]" in text
                     else text + "\n[render]\nexposure = 2.0\n")
    commands = tmp_path / "c.txt"
    commands.write_text("render 1\n")
    assert run(["movie", scene, tmp_path / "bright", commands, *TINY], capsys)[0] == 0
    assert run(["movie", scene, tmp_path / "plain", commands, *TINY, "--exposure", "0"], capsys)[0] == 0
    assert run(["image", scene, tmp_path / "one.png", *TINY], capsys)[0] == 0
    import imageio.v3 as iio

    bright, plain = pngs(tmp_path / "bright")[0], pngs(tmp_path / "plain")[0]
    assert np.abs(bright.astype(int) - iio.imread(tmp_path / "one.png").astype(int)).max() <= 1
    assert bright.astype(int).sum() > plain.astype(int).sum()


@pytest.mark.api
def test_rerun_renders_only_the_missing_frames(tmp_path, capsys, drift, monkeypatch):
    out = tmp_path / "m.gif"
    counter = Counter()
    monkeypatch.setattr(movie_module, "render_frame_files", counter)
    result = render_movie(three(), drift, out, **TINY_SETTINGS, progress=False)
    assert counter.calls == result.rendered == 4 and result.frames == 4
    cache = movie_cache_folder(out)
    assert cache == tmp_path / "m.gif.cache" and len(list(cache.iterdir())) == 4
    first = out.read_bytes()
    victims = sorted(cache.iterdir())[1:3]
    for p in victims:
        p.unlink()
    counter.calls = 0
    result = render_movie(three(), drift, out, **TINY_SETTINGS, progress=False)
    assert counter.calls == result.rendered == 2
    assert out.read_bytes() == first
    counter.calls = 0
    render_movie(three(), drift, out, **TINY_SETTINGS, progress=False)
    assert counter.calls == 0


@pytest.mark.api
def test_ctrl_c_exits_130_writes_no_movie_and_keeps_the_frames_done(tmp_path, capsys, drift, monkeypatch):
    out = tmp_path / "m.mp4"
    monkeypatch.setattr(movie_module, "render_frame_files", Counter(interrupt_at=3))
    status, _, err = run(["movie", THREE, out, drift, *TINY], capsys)
    assert status == 130 and err == "tracer: interrupted\n"
    assert not out.exists()
    cache = movie_cache_folder(out)
    assert len(list(cache.glob("*.png"))) == 2
    assert not [p for p in tmp_path.rglob("*") if p.name.startswith(".")]  # no temporary file left
    counter = Counter()
    monkeypatch.setattr(movie_module, "render_frame_files", counter)
    assert run(["movie", THREE, out, drift, *TINY], capsys)[0] == 0
    assert counter.calls == 2 and out.is_file()


@pytest.mark.api
def test_mp4_is_h264_yuv420p_with_every_frame(tmp_path, capsys, drift):
    import imageio_ffmpeg

    out = tmp_path / "m.mp4"
    status, _, err = run(["movie", THREE, out, drift, "--width", "10", "--height", "6", "--depth", "2",
                          "--fps", "12", "--quiet"], capsys)
    assert status == 0, err
    reader = imageio_ffmpeg.read_frames(str(out))
    meta = next(reader)
    assert meta["codec"] == "h264" and meta["pix_fmt"].startswith("yuv420p")
    assert meta["size"] == (10, 6) and meta["fps"] == 12
    assert sum(1 for _ in reader) == 4


@pytest.mark.api
def test_gif_plays_the_frames_in_order(tmp_path, capsys):
    import imageio.v3 as iio

    out = tmp_path / "m.gif"
    orbit = tmp_path / "orbit.txt"
    orbit.write_text(ORBIT)
    assert run(["movie", out, orbit, *TINY, "--fps", "10"], capsys)[0] == 0
    gif = iio.imread(out)
    assert gif.ndim == 4 and gif.shape[1:3] == (6, 8)
    assert gif.shape[0] == 4  # four different frames
    assert np.any(gif[0] != gif[3])


@pytest.mark.api
def test_builtin_scene_when_the_scene_is_left_out(tmp_path, capsys):
    cmds = tmp_path / "c.txt"
    cmds.write_text("camera orbit 30\nrender 2\n")
    out = tmp_path / "orbit"
    assert run(["movie", out, cmds, *TINY], capsys)[0] == 0
    a, b = pngs(out)
    assert a.shape == (6, 8, 3) and np.any(a != b)


@pytest.mark.api
def test_folder_movie_replaces_a_previous_movie_but_not_other_files(tmp_path, capsys, drift):
    out = tmp_path / "frames"
    out.mkdir()
    (out / "0000.png").write_bytes(b"old")
    (out / "0099.png").write_bytes(b"old")
    assert run(["movie", THREE, out, drift, *TINY], capsys)[0] == 0
    assert sorted(p.name for p in out.iterdir()) == [f"{i:04d}.png" for i in range(4)]
    (out / "notes.txt").write_text("mine")
    status, _, err = run(["movie", THREE, out, drift, *TINY], capsys)
    assert status == 2 and "holds other files than frames" in err
    assert (out / "notes.txt").read_text() == "mine"


def _bad_movie_cases(tmp):
    good, bad = tmp / "good.txt", tmp / "bad.txt"
    yield "bad commands", ["movie", THREE, tmp / "out" / "m.mp4", bad, *TINY], f"{bad}:2: move: no object named"
    yield "missing commands", ["movie", THREE, tmp / "out" / "m", tmp / "none.txt", *TINY], "none.txt: no such file"
    yield "missing scene", ["film", tmp / "none.txt", tmp / "out" / "m.gif", good, *TINY], "none.txt: no such file"
    yield "odd size mp4", ["movie", THREE, tmp / "out" / "m.mp4", good, "--width", "7", "--height", "6"], "even width"
    yield "16 bits in a gif", ["movie", THREE, tmp / "out" / "m.gif", good, *TINY, "--bits", "16"], "16-bit frames"
    yield "missing folder", ["movie", THREE, tmp / "out" / "no" / "m.mp4", good, *TINY], "does not exist"
    yield "image suffix", ["movie", THREE, tmp / "out" / "m.png", good, *TINY], "a movie is written as .mp4, .gif"
    yield "output is a file", ["movie", THREE, tmp / "out" / "file", good, *TINY], "is a file"
    yield "bad depth", ["movie", THREE, tmp / "out" / "m.mp4", good, "--depth", "0"], "--depth: must be"
    yield "bad fps", ["movie", THREE, tmp / "out" / "m.mp4", good, "--fps", "0"], "--fps: must be"
    yield "bad workers", ["movie", THREE, tmp / "out" / "m", good, "--workers", "0"], "--workers: must be"
    yield "workers and scheduler", ["movie", THREE, tmp / "out" / "m", good, "--workers", "2", "--scheduler",
                                    "tcp://127.0.0.1:1"], "not allowed with argument"
    yield "too many paths", ["movie", THREE, tmp / "out" / "m", good, good, *TINY], "expected [SCENE] OUT COMMANDS"
    yield "bad exposure", ["movie", THREE, tmp / "out" / "m", good, *TINY, "--exposure", "65"], "--exposure"
    yield "bad view", ["movie", THREE, tmp / "out" / "m", good, *TINY, "--view", "agx"], "--view: invalid choice"
    yield "spectral into the movie", ["movie", THREE, tmp / "out" / "m", good, *TINY, "--spectral-out",
                                      tmp / "out" / "m"], "need a folder of their own"
    yield "spectral into a file name", ["movie", THREE, tmp / "out" / "m", good, *TINY, "--spectral-out",
                                        tmp / "out" / "s.npz"], "folder of frames NNNN.npz"
    yield ("spectral into a used folder", ["movie", THREE, tmp / "m", good, *TINY, "--spectral-out", tmp / "out"],
           "holds other files than frames NNNN.npz")
    yield "spectral into a missing folder", ["movie", THREE, tmp / "out" / "m", good, *TINY, "--spectral-out",
                                             tmp / "no" / "s"], "does not exist"
    yield "bad render setting in TOML", ["movie", ROOT / "data" / "scenes" / "bubbles_sky.toml",
                                         tmp / "out" / "m.mp4", good, "--spp", "0"], "--spp"


BAD_MOVIES = [c[0] for c in _bad_movie_cases(Path("/nonexistent"))]


@pytest.mark.api
@pytest.mark.parametrize("case", BAD_MOVIES)
def test_bad_movie_exits_2_with_one_line_and_writes_nothing(tmp_path, capsys, case):
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "file").write_text("keep")
    (tmp_path / "good.txt").write_text(DRIFT)
    (tmp_path / "bad.txt").write_text("render 2\nmove nobody 1 2 3\nrender 1\n")
    argv, what = next((a, w) for name, a, w in _bad_movie_cases(tmp_path) if name == case)
    before = sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*"))
    status, out, err = run(argv, capsys)
    assert status == 2 and out == ""
    assert_one_line(err)
    assert what in err, err
    assert sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*")) == before  # not even a folder


@pytest.mark.api
def test_unreachable_scheduler_is_one_line(tmp_path, capsys, drift):
    status, _, err = run(["movie", THREE, tmp_path / "m", drift, *TINY, "--scheduler", "tcp://127.0.0.1:9"], capsys)
    assert status == 2
    assert_one_line(err)
    assert "cannot reach the Dask scheduler at tcp://127.0.0.1:9" in err
    assert not (tmp_path / "m").exists()


@pytest.mark.api
def test_check_movie_output_kinds(tmp_path):
    assert check_movie_output(tmp_path / "a.MP4")[1] == "mp4"
    assert check_movie_output(tmp_path / "a.gif")[1] == "gif"
    assert check_movie_output(tmp_path / "frames")[1] == "folder"
    assert list(tmp_path.iterdir()) == []


# ------------------------------------------------------------------------------------------
# Python API and Dask
# ------------------------------------------------------------------------------------------
@pytest.mark.api
def test_render_movie_from_a_timeline_built_in_python(tmp_path):
    scene = tracer.default_scene()
    tl = Timeline(scene).render(1).set("old", "top_nm", 300).move("old", -0.2, 0, 0).render(2)
    result = render_movie(scene, tl, tmp_path / "film", width=8, height=8, depth=2, progress=False)
    assert result.frames == 3 and result.rendered == 3
    frames = pngs(tmp_path / "film")
    assert len(frames) == 3 and np.any(frames[0] != frames[2])


@pytest.mark.reference
def test_distributed_frames_are_bit_identical_to_serial(tmp_path, drift, client):
    serial = render_movie(three(), drift, tmp_path / "serial", **TINY_SETTINGS, progress=False)
    dist = render_movie(three(), drift, tmp_path / "dist", **TINY_SETTINGS, progress=False, client=client)
    assert serial.rendered == dist.rendered == 4
    for a, b in zip(sorted((tmp_path / "serial").iterdir()), sorted((tmp_path / "dist").iterdir())):
        assert a.read_bytes() == b.read_bytes()
    assert sorted(p.name for p in serial.cache.iterdir()) == sorted(p.name for p in dist.cache.iterdir())


@pytest.mark.api
def test_workers_load_the_kernels_from_numbas_cache_with_one_thread(tmp_path, drift, client):
    render_movie(three(), drift, tmp_path / "m", **TINY_SETTINGS, progress=False, client=client)
    stats = client.run(cluster_module.worker_numba_cache_stats)
    assert len(stats) == 2
    for s in stats.values():
        assert s["misses"] == 0, stats  # nothing compiled on a worker
        assert s["threads"] == 1
    assert sum(s["hits"] for s in stats.values()) >= 1


@pytest.mark.api
def test_workers_option_runs_a_local_cluster(tmp_path, capsys, drift):
    out = tmp_path / "m"
    status, stdout, err = run(["movie", THREE, out, drift, *TINY, "--workers", "2"], capsys)
    assert status == 0 and stdout == "" and err == "", err  # no cluster chatter on the terminal
    assert len(pngs(out)) == 4


@pytest.mark.api
def test_a_worker_lost_mid_movie_costs_only_its_frames(tmp_path, client):
    """One worker's process is killed while the movie renders; Dask reruns its frames on the
    other (the nanny restarts the dead one), and the movie is complete and equal to serial."""
    import os
    import threading

    scene = tracer.default_scene()
    tl = Timeline(scene).camera_orbit(90).render(16)
    options = dict(width=96, height=96, depth=10, progress=False)  # tens of ms a frame
    serial = render_movie(scene, tl, tmp_path / "serial", **options)
    victim = sorted(client.scheduler_info()["workers"])[0]
    cache = movie_cache_folder(tmp_path / "dist")
    done_at_kill = []

    def kill_after_the_first_frame():
        for _ in range(6000):
            if cache.is_dir() and any(cache.glob("[0-9a-f]*.png")):
                break
            threading.Event().wait(0.001)
        done_at_kill.append(len(list(cache.glob("[0-9a-f]*.png"))))
        try:
            client.run(os._exit, 1, workers=[victim], on_error="ignore")
        except Exception:  # the worker dies before it can answer
            pass

    killer = threading.Thread(target=kill_after_the_first_frame)
    killer.start()
    dist = render_movie(scene, tl, tmp_path / "dist", client=client, **options)
    killer.join()
    assert dist.frames == dist.rendered == 16
    assert 1 <= done_at_kill[0] < 16  # killed mid-movie
    for a, b in zip(sorted((tmp_path / "serial").iterdir()), sorted((tmp_path / "dist").iterdir())):
        assert a.read_bytes() == b.read_bytes()
    assert serial.rendered == 16
    client.wait_for_workers(2, timeout=60)  # the nanny brought it back for the tests after this one
    assert victim not in client.scheduler_info()["workers"]  # it did die


@pytest.mark.api
def test_python_m_tracer_movie_on_workers_is_silent(tmp_path, drift):
    """A real ``python -m tracer`` process: the workers (spawned processes that import
    ``tracer.__main__`` as their main module) must not run the command again, and nothing but
    the movie comes out."""
    import os
    import subprocess
    import sys

    out = tmp_path / "m.gif"
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    proc = subprocess.run([sys.executable, "-m", "tracer", "movie", str(THREE), str(out), str(drift), *TINY,
                           "--workers", "2"], capture_output=True, text=True, env=env, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout == "" and proc.stderr == ""
    assert out.is_file() and len(list(movie_cache_folder(out).glob("*.png"))) == 4


# ------------------------------------------------------------------------------------------
# long movies: frames planned, keyed and rendered one at a time
# ------------------------------------------------------------------------------------------
class _StopAfter(Exception):
    pass


@pytest.mark.api
def test_a_million_frames_start_rendering_at_once_with_flat_memory(tmp_path, monkeypatch):
    """``render 1000000`` with the camera moving: the commands are checked (every frame's
    camera, as arrays), then the first frame is rendered when its key is the only one computed;
    over the first 300 frames the traced memory stays at the frame keys' array (32 bytes a
    frame) and one frame, not a million frames' scenes."""
    import tracemalloc

    from tracer.movie import frames as movie_frames

    keys, rendered_after = [], []
    real_key = movie_frames.frame_key

    def counting_key(frame, bits=8):
        keys.append(frame.index)
        return real_key(frame, bits)

    def fake_render(frame, bits=8):
        rendered_after.append(len(keys))
        if len(rendered_after) == 300:
            raise _StopAfter
        return f"png {frame.index}".encode(), None

    monkeypatch.setattr(movie_frames, "frame_key", counting_key)
    monkeypatch.setattr(movie_module, "render_frame_files", fake_render)
    scene = three()
    tl = Timeline.from_text(scene, "camera orbit 30\nmove пузырь1 100 0 0\nrender 1000000\n")
    assert len(tl) == 1_000_000
    tracemalloc.start()
    try:
        with pytest.raises(_StopAfter):
            render_movie(scene, tl, tmp_path / "m", **TINY_SETTINGS, progress=False)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert rendered_after[:3] == [1, 2, 3] and len(keys) == 300  # each frame keyed as it is scheduled
    assert peak < 32 * 1_000_000 + 16 * 2**20, peak  # the keys' array, and 16 MiB for the rest
    assert len(list(movie_cache_folder(tmp_path / "m").glob("*.png"))) == 299
    assert not (tmp_path / "m").exists()  # interrupted: no movie


@pytest.mark.api
def test_the_cameras_of_a_long_render_are_checked_like_each_frame():
    """The cameras between a render's ends are computed as arrays: the same positions as each
    frame's own scene, and a camera that passes through its look-at point, or looks along its
    up vector, half way is refused naming that frame."""
    from tracer.movie.timeline import _apply, _camera_paths

    text = "camera orbit 70\ncamera position 100 900 1500\ncamera look_at 400 300 20\ncamera orbit -30\n"
    tl = Timeline(three())
    for line in text.splitlines():
        tl.command(line)
    start, changes = tl._start, tuple(tl._pending)
    k = np.arange(1, 10)
    pos, look = _camera_paths(start.scene.camera, changes, k, 9)
    for i, kk in enumerate(k):
        cam = _apply(start, changes, kk / 9).scene.camera
        assert np.allclose(pos[i], cam.position, rtol=1e-13, atol=1e-9)
        assert np.allclose(look[i], cam.look_at, rtol=1e-13, atol=1e-9)
    assert len(Timeline.from_text(three(), text + "render 9\n")) == 9  # and every frame of it passes
    # the coursework camera: (480, 480, 2000) looking at (480, 480, 0), up -y
    for text, message in [
        ("camera position 480 480 -2000\nrender 4\n", "frame 2 of this render: camera look_at coincides"),
        ("camera position 480 -1520 -2000\ncamera orbit 90\nrender 4\n",
         "frame 2 of this render: camera up vector is parallel"),
    ]:
        with pytest.raises(CommandsError, match=message):
            Timeline.from_text(three(), text)


@pytest.mark.api
def test_distributed_frames_are_submitted_a_window_at_a_time(tmp_path, drift, client, monkeypatch):
    """A movie on a cluster keeps at most its window of frames in flight (here 8, for 2
    workers), and its frames are the serial ones."""
    submitted, peak = [], [0]
    real_submit = client.submit

    def watch(*args, **kwargs):
        future = real_submit(*args, **kwargs)
        submitted.append(future)
        peak[0] = max(peak[0], sum(not f.done() for f in submitted))
        return future

    monkeypatch.setattr(client, "submit", watch)
    tl = Timeline.from_text(three(), "move пузырь1 100 0 0\nrender 20\n")
    dist = render_movie(three(), tl, tmp_path / "dist", client=client, **TINY_SETTINGS, progress=False)
    serial = render_movie(three(), tl, tmp_path / "serial", **TINY_SETTINGS, progress=False)
    assert dist.rendered == serial.rendered == len(submitted) == 20
    assert 1 <= peak[0] <= movie_module.FRAMES_IN_FLIGHT_PER_WORKER * 2
    for a, b in zip(sorted((tmp_path / "serial").iterdir()), sorted((tmp_path / "dist").iterdir())):
        assert a.read_bytes() == b.read_bytes()


@pytest.mark.api
def test_a_long_unknown_name_is_not_echoed_in_full():
    with pytest.raises(CommandsError) as info:
        Timeline.from_text(three(), "move " + "x" * 5000 + " 1 2 3\nrender 1\n", "movie.txt")
    assert str(info.value).startswith("movie.txt:1: move: no object named 'xxx") and len(str(info.value)) < 300
