"""The command line end to end: ``tracer image``, ``tracer research`` and ``python -m tracer``.

Most cases call ``tracer.cli.main([...])`` in-process (a subprocess costs seconds of Python and
numba start-up); a few real subprocesses prove the two entry points, their exit statuses and
that no traceback reaches the terminal.  Parser-level details of every scene error are in
tests/tracer/test_scene_io.py; here each bad scene goes through the whole command: exit status 2,
exactly one line ``FILE:LINE: what is wrong`` on stderr, nothing on stdout, no output file and
no temporary file left in the output folder.

Images are tiny (a few pixels, low depth) so the whole file runs in seconds after the kernels
are loaded from numba's cache.
"""

import json
import shutil
import struct
import subprocess
import sys
import zlib
from pathlib import Path

import numpy as np
import pytest

import tracer
from cli_helpers import run, assert_one_line  # tests/support/cli_helpers.py

pytestmark = pytest.mark.api

ROOT = Path(__file__).resolve().parents[2]
LISTING_3_1 = ROOT / "data" / "coursework_scenes" / "listing_3_1.txt"
LISTING_3_2 = ROOT / "data" / "coursework_scenes" / "listing_3_2.txt"
LISTING_3_2_TOML = ROOT / "data" / "scenes" / "listing_3_2.toml"
ONE_BUBBLE = ROOT / "data" / "scenes" / "coursework_one_bubble.txt"
SCENE_FILES = sorted(p for p in (ROOT / "data" / "scenes").iterdir() if p.suffix in (".txt", ".toml"))

TINY = ["--width", "8", "--height", "6", "--depth", "2", "--quiet"]


# ------------------------------------------------------------------------------------------
# helpers
# ------------------------------------------------------------------------------------------


def srgb_to_linear(code, top):
    """IEC 61966-2-1 sRGB decoding of integer codes 0..top, written out here (not colour-science)."""
    c = np.asarray(code, dtype=float) / top
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def linear_to_srgb(x):
    x = np.clip(np.asarray(x, dtype=float), 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)


def png_header(path):
    """(width, height, bit depth, colour type) read straight from the IHDR chunk of a PNG file."""
    data = Path(path).read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    length, tag = struct.unpack(">I4s", data[8:16])
    assert tag == b"IHDR" and length == 13
    body = data[16:29]
    assert struct.unpack(">I", data[29:33])[0] == zlib.crc32(tag + body) & 0xFFFFFFFF
    w, h, depth, ctype = struct.unpack(">IIBB", body[:10])
    return w, h, depth, ctype


def with_line(source, line, text):
    """The text of *source* with its 1-based *line* replaced by *text* (one field varied)."""
    lines = Path(source).read_text(encoding="utf-8").split("\n")
    lines[line - 1] = text
    return "\n".join(lines)


# ------------------------------------------------------------------------------------------
# Bad scenes: exit 2, one line FILE:LINE: ..., no output, no temp file
# ------------------------------------------------------------------------------------------
# Lines of listing 3.2: 1 's сфера', 2 centre, 3 radius, 4 colour, 5 ka kd ks kt, 6 exponent,
# 7 index, 8 dispersion, 9 blank, 10 'b пузырь', 11 outer centre, 12 outer radius, 13-17 outer
# material, 18 inner centre, 19 inner radius, 20-24 inner material.
# Lines of listing 3.1: 1 't тетраэдр', 2-5 'v', 6-9 'f', 10 '-', 11-15 material, 16 blank,
# 17 'l', 18 position, 19 intensity.
BAD_SEED = {
    "centre not a number": (LISTING_3_2, 2, "300 abc 150", "'abc' is not a number"),
    "centre with two numbers": (LISTING_3_2, 2, "300 400", "expected 3 numbers (x y z)"),
    "NaN radius": (LISTING_3_2, 3, "nan", "must be a finite number"),
    "infinite bubble centre": (LISTING_3_2, 11, "450 inf -100", "must be a finite number"),
    "negative radius": (LISTING_3_2, 3, "-100", "radius must be positive, got -100"),
    "zero radius": (LISTING_3_2, 3, "0", "radius must be positive, got 0"),
    "zero outer bubble radius": (LISTING_3_2, 12, "0", "radius must be positive"),
    "negative inner radius": (LISTING_3_2, 19, "-99.9", "inner radius must be positive"),
    "inner radius above outer": (LISTING_3_2, 19, "101", "inner radius 101 is larger than the outer radius 100"),
    "inner sphere not concentric": (LISTING_3_2, 18, "450 150 -90", "must be concentric"),
    "colour above 255": (LISTING_3_2, 4, "0 0 256", "(B) = 256 is outside 0-255"),
    "negative colour in the bubble": (LISTING_3_2, 13, "100 -1 100", "(G) = -1 is outside 0-255"),
    "fractional colour": (LISTING_3_2, 4, "0 0 254.5", "is not an integer 0-255"),
    "coefficient above 1": (LISTING_3_2, 5, "0.4 0.1 0 1.5", "kt = 1.5 is outside [0, 1]"),
    "negative coefficient in the bubble": (LISTING_3_2, 14, "0.1 -0.4 0 1", "kd = -0.4 is outside [0, 1]"),
    "inner coefficient above 1": (LISTING_3_2, 21, "0 0 0.5 2", "inner coefficient kt = 2 is outside [0, 1]"),
    "zero refraction index": (LISTING_3_2, 7, "0", "refraction index must be > 0 and <= 100"),
    "negative dispersion": (LISTING_3_2, 8, "-1", "dispersion must be >= 0"),
    "face names a missing vertex": (LISTING_3_1, 9, "f 1 2 5", "names vertex 5, but the object has 4 vertices"),
    "vertex with two coordinates": (LISTING_3_1, 2, "v 500.0 300.0", "expected 3 numbers (x y z)"),
    "light intensity above 1": (LISTING_3_1, 19, "1.5", "intensity 1.5 is outside [0, 1]"),
}


def _bad_scene_cases():
    for name, (source, line, text, what) in BAD_SEED.items():
        yield pytest.param("scene.txt", with_line(source, line, text), line, what, id=name)
    faces = Path(LISTING_3_1).read_text(encoding="utf-8").split("\n")
    faces[5:9] = ["f 1 1 2"] * 4  # every face repeats a vertex: zero area, all skipped
    yield pytest.param("scene.txt", "\n".join(faces), 1, "has no usable face", id="mesh with no usable face")
    whole = Path(LISTING_3_2).read_text(encoding="utf-8").split("\n")
    yield pytest.param("scene.txt", "\n".join(whole[:16]) + "\n", 17, "the file ends before its outer dispersion",
                       id="file cut short")
    yield pytest.param("scene.txt", Path(LISTING_3_2).read_text(encoding="utf-8").encode("cp1251"), 1,
                       "not UTF-8", id="Windows-1251 instead of UTF-8")
    # a PNG given as the scene: '\x89PNG\r\n' (1), '\x1a\n' (2), then the IHDR length's NUL bytes (3)
    junk = b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR" + bytes(range(256))
    yield pytest.param("scene.txt", junk, 3, "NUL byte", id="binary junk")
    yield pytest.param("scene.toml", with_line(LISTING_3_2_TOML, 62, "radius = -100"), 62,
                       "spheres[0].radius: must be > 0, got -100", id="TOML negative radius")
    yield pytest.param("scene.toml", with_line(LISTING_3_2_TOML, 59, "    nan,"), 57,
                       "must be a finite number", id="TOML NaN centre")
    yield pytest.param("scene.toml", with_line(LISTING_3_2_TOML, 62, "radius = "), 62, "invalid TOML",
                       id="TOML syntax error")


@pytest.mark.parametrize("name,content,line,what", list(_bad_scene_cases()))
@pytest.mark.parametrize("suffix", [".png", ".npy"])
def test_bad_scene_exits_2_with_one_line_and_writes_nothing(tmp_path, capsys, name, content, line, what, suffix):
    scene = tmp_path / name
    if isinstance(content, bytes):
        scene.write_bytes(content)
    else:
        scene.write_text(content, encoding="utf-8")
    outdir = tmp_path / "out"
    outdir.mkdir()
    status, out, err = run(["image", scene, outdir / f"picture{suffix}", *TINY], capsys)
    assert status == 2
    assert out == ""
    assert_one_line(err)
    assert err.startswith(f"{scene}:{line}: "), err
    assert what in err, err
    assert list(outdir.iterdir()) == []  # no image, no temporary file


def test_bad_scene_through_research_too(tmp_path, capsys):
    scene = tmp_path / "scene.txt"
    scene.write_text(with_line(LISTING_3_2, 3, "-1"), encoding="utf-8")
    status, out, err = run(["research", scene, tmp_path / "o.npy", "3", "--json", "--width", "4", "--height", "4"],
                           capsys)
    assert (status, out) == (2, "")
    assert_one_line(err)
    assert err == f"{scene}:3: sphere 'сфера': radius must be positive, got -1\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.txt"]


def test_missing_scene_file(tmp_path, capsys):
    scene = tmp_path / "nope.txt"
    status, out, err = run(["image", scene, tmp_path / "o.png", *TINY], capsys)
    assert (status, out) == (2, "")
    assert err == f"{scene}: no such file\n"
    assert list(tmp_path.iterdir()) == []


def test_a_directory_is_not_a_scene(tmp_path, capsys):
    status, out, err = run(["image", tmp_path, tmp_path / "o.png", *TINY], capsys)
    assert (status, out) == (2, "")
    assert_one_line(err)
    assert err.startswith(f"{tmp_path}: ") and "directory" in err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.skipif(not Path("/proc/self/mem").exists(), reason="needs Linux /proc")
def test_unreadable_scene_file(tmp_path, capsys):
    # /proc/self/mem exists, but reading it from offset 0 fails (EIO) even as root,
    # unlike a chmod 000 file
    status, out, err = run(["image", "/proc/self/mem", tmp_path / "o.png", *TINY], capsys)
    assert (status, out) == (2, "")
    assert_one_line(err)
    assert err.startswith("/proc/self/mem: cannot read the file")
    assert list(tmp_path.iterdir()) == []


def test_zero_area_face_is_a_one_line_warning_and_the_image_is_written(tmp_path, capsys):
    # listing 3.1 with one of its four faces made degenerate: skipped with a warning, not refused
    scene = tmp_path / "scene.txt"
    scene.write_text(with_line(LISTING_3_1, 8, "f 2 2 4"), encoding="utf-8")
    status, out, err = run(["image", scene, tmp_path / "o.png", *TINY], capsys)
    assert (status, out) == (0, "")
    assert_one_line(err)
    assert err.startswith(f"{scene}:8: ") and "zero area" in err
    assert (tmp_path / "o.png").is_file()


# ------------------------------------------------------------------------------------------
# Bad outputs and bad options
# ------------------------------------------------------------------------------------------
def test_unknown_output_suffix(tmp_path, capsys):
    status, out, err = run(["image", LISTING_3_2, tmp_path / "o.jpg", *TINY], capsys)
    assert (status, out) == (2, "")
    assert_one_line(err)
    assert ".png, .npy, .exr, .hdr or .npz" in err and "o.jpg" in err
    assert list(tmp_path.iterdir()) == []


def test_missing_output_folder(tmp_path, capsys):
    target = tmp_path / "no" / "such" / "o.png"
    status, out, err = run(["image", LISTING_3_2, target, *TINY], capsys)
    assert (status, out) == (2, "")
    assert_one_line(err)
    assert "does not exist" in err
    assert list(tmp_path.iterdir()) == []


def test_output_path_that_is_a_folder(tmp_path, capsys):
    (tmp_path / "o.png").mkdir()
    status, out, err = run(["image", LISTING_3_2, tmp_path / "o.png", *TINY], capsys)
    assert (status, out) == (2, "")
    assert_one_line(err)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["o.png"] and (tmp_path / "o.png").is_dir()


BAD_OPTIONS = {
    "width 0": (["--width", "0"], "--width"),
    "negative height": (["--height", "-3"], "--height"),
    "fractional width": (["--width", "2.5"], "--width"),
    "spp 0": (["--spp", "0"], "--spp"),
    "background with two numbers": (["--background", "1,2"], "--background"),
    "background with four numbers": (["--background", "1,2,3,4"], "--background"),
    "background not numbers": (["--background", "a,b,c"], "--background"),
    "negative background": (["--background", "-1,0,0"], "--background"),
    "NaN background": (["--background", "nan,0,0"], "--background"),
    "threshold -1": (["--threshold", "-1"], "--threshold"),
    "threshold nan": (["--threshold", "nan"], "--threshold"),
    "depth abc": (["--depth", "abc"], "--depth"),
    "depth 0": (["--depth", "0"], "--depth"),
    "spectral samples 0": (["--spectral-samples", "0"], "--spectral-samples"),
    "negative seed": (["--seed", "-1"], "--seed"),
    "bits 12": (["--bits", "12"], "--bits"),
}


@pytest.mark.parametrize("option,name", BAD_OPTIONS.values(), ids=BAD_OPTIONS.keys())
def test_bad_option_value(tmp_path, capsys, option, name):
    status, out, err = run(["image", LISTING_3_2, tmp_path / "o.png", *option], capsys)
    assert (status, out) == (2, "")
    assert_one_line(err)
    assert err.startswith(f"tracer image: error: argument {name}"), err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("depth", ["0", "-1", "abc", "2.5"])
def test_research_bad_depth(tmp_path, capsys, depth):
    status, out, err = run(["research", LISTING_3_2, tmp_path / "o.png", depth], capsys)
    assert (status, out) == (2, "")
    assert_one_line(err)
    assert err.startswith("tracer research: error: argument DEPTH"), err


@pytest.mark.parametrize("argv", [["image"], ["image", "a.txt", "b.png", "c.png"], ["research", "a.txt", "b.png"],
                                  ["render", "a.txt"], []], ids=["no OUT", "three paths", "no DEPTH",
                                                                 "unknown command", "nothing"])
def test_bad_command_lines(capsys, argv):
    status, out, err = run(argv, capsys)
    assert (status, out) == (2, "")
    assert_one_line(err)
    assert err.startswith("tracer"), err


# ------------------------------------------------------------------------------------------
# Atomic writes
# ------------------------------------------------------------------------------------------
def test_existing_output_is_replaced_whole(tmp_path, capsys):
    target = tmp_path / "o.npy"
    target.write_bytes(b"old contents, much longer than nothing " * 1000)
    status, _, _ = run(["image", LISTING_3_2, target, *TINY], capsys)
    assert status == 0
    assert np.load(target).shape == (6, 8, 3)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["o.npy"]


def test_existing_output_is_untouched_by_a_bad_scene(tmp_path, capsys):
    target = tmp_path / "o.png"
    target.write_bytes(b"previous image")
    scene = tmp_path / "scene.txt"
    scene.write_text(with_line(LISTING_3_2, 4, "0 0 300"), encoding="utf-8")
    status, _, err = run(["image", scene, target, *TINY], capsys)
    assert status == 2 and err.startswith(f"{scene}:4: ")
    assert target.read_bytes() == b"previous image"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["o.png", "scene.txt"]


@pytest.mark.parametrize("suffix", [".npy", ".png"])
def test_a_write_failing_half_way_leaves_the_old_file_and_no_temp_file(tmp_path, capsys, monkeypatch, suffix):
    from PIL import Image

    # the writers: numpy.save(file, array) and PIL.Image.Image.save(self, fp, ...)
    module, where = (np, 0) if suffix == ".npy" else (Image.Image, 1)

    def half_then_fail(*args, **kwargs):
        target = args[where]
        # write something real to the temporary file, then fail as a full disk would
        if hasattr(target, "write"):
            target.write(b"\x93NUMPY partial")
        else:
            Path(target).write_bytes(b"\x89PNG partial")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(module, "save", half_then_fail)
    target = tmp_path / f"o{suffix}"
    target.write_bytes(b"previous image")
    status, out, err = run(["image", LISTING_3_2, target, *TINY], capsys)
    assert (status, out) == (2, "")
    assert_one_line(err)
    assert "No space left on device" in err
    assert target.read_bytes() == b"previous image"
    assert sorted(p.name for p in tmp_path.iterdir()) == [target.name]


# ------------------------------------------------------------------------------------------
# What is written
# ------------------------------------------------------------------------------------------
# the .npy writer must close its file itself (an unclosed file is a ResourceWarning when collected)
@pytest.mark.filterwarnings("error::ResourceWarning", "error::pytest.PytestUnraisableExceptionWarning")
def test_npy_is_float_linear_rgb_equal_to_tracer_render(tmp_path, capsys):
    target = tmp_path / "o.npy"
    argv = ["image", ONE_BUBBLE, target, "--width", "12", "--height", "7", "--depth", "3", "--spp", "2",
            "--threshold", "0", "--spectral-samples", "8", "--seed", "5"]
    status, out, err = run(argv, capsys)
    assert (status, out, err) == (0, "", "")  # no progress bar when stderr is not a terminal
    image = np.load(target)
    assert image.shape == (7, 12, 3) and image.dtype == np.float64
    expected = tracer.render(tracer.load_scene(ONE_BUBBLE), width=12, height=7, depth=3, spp=2, threshold=0.0,
                             spectral_samples=8, seed=5)
    np.testing.assert_array_equal(image, expected)
    assert image[0, 0].tolist() == [0.0, 0.0, 0.0]  # the coursework's black background, exactly
    assert image.max() > 0.0


def test_png_is_8_bit_srgb_rgb_of_the_linear_render(tmp_path, capsys):
    from PIL import Image
    import imageio.v3 as iio

    status, _, _ = run(["image", LISTING_3_2, tmp_path / "o.png", "--width", "20", "--height", "10", "--depth", "3",
                        "--quiet"], capsys)
    assert status == 0
    assert png_header(tmp_path / "o.png") == (20, 10, 8, 2)  # 8 bits, colour type 2 = RGB
    with Image.open(tmp_path / "o.png") as im:
        assert im.mode == "RGB" and im.size == (20, 10)
    data = iio.imread(tmp_path / "o.png")
    assert data.dtype == np.uint8 and data.shape == (10, 20, 3)
    linear = tracer.render(tracer.load_scene(LISTING_3_2), width=20, height=10, depth=3)
    expected = np.round(linear_to_srgb(linear) * 255)
    assert np.abs(data.astype(int) - expected).max() <= 1
    assert data.max() > 0  # the blue sphere is in view


def test_png_16_bit(tmp_path, capsys):
    from PIL import Image

    argv = ["image", LISTING_3_2, tmp_path / "o16.png", "--width", "20", "--height", "10", "--depth", "3", "--quiet"]
    status, out, err = run(argv + ["--bits", "16"], capsys)
    assert (status, out, err) == (0, "", "")
    assert png_header(tmp_path / "o16.png") == (20, 10, 16, 2)  # 16 bits per channel, RGB
    linear = tracer.render(tracer.load_scene(LISTING_3_2), width=20, height=10, depth=3)
    expected = np.round(linear_to_srgb(linear) * 65535)
    with Image.open(tmp_path / "o16.png") as im:  # Pillow reads 48-bit RGB as 8-bit RGB
        assert im.mode == "RGB" and im.size == (20, 10)
        assert np.abs(np.asarray(im).astype(int) - np.round(expected / 257)).max() <= 1
    cv2 = pytest.importorskip("cv2")
    data = cv2.imread(str(tmp_path / "o16.png"), cv2.IMREAD_UNCHANGED)
    assert data.dtype == np.uint16 and data.shape == (10, 20, 3)
    assert np.abs(data[..., ::-1].astype(int) - expected).max() <= 1


def test_background_sets_a_constant_environment(tmp_path, capsys):
    from PIL import Image

    common = ["--width", "16", "--height", "16", "--depth", "3", "--quiet"]
    status, _, _ = run(["image", ONE_BUBBLE, tmp_path / "bg.png", "--background", "0.2,0.4,0.6", *common], capsys)
    assert status == 0
    status, _, _ = run(["image", ONE_BUBBLE, tmp_path / "black.png", *common], capsys)
    assert status == 0
    with Image.open(tmp_path / "bg.png") as im:
        bg = np.asarray(im)
    with Image.open(tmp_path / "black.png") as im:
        black = np.asarray(im)
    corners = bg[[0, 0, -1, -1], [0, -1, 0, -1]]
    # the bubble scene is rendered spectrally (16 bands): a constant RGB environment comes back
    # through the spectral round trip within about 0.005 in linear light, about one 8-bit step
    np.testing.assert_allclose(srgb_to_linear(corners, 255), np.tile([0.2, 0.4, 0.6], (4, 1)), atol=2 / 255)
    assert (black[[0, 0, -1, -1], [0, -1, 0, -1]] == 0).all()  # the coursework's black background otherwise
    assert (bg != black).any(axis=2).mean() > 0.5


def test_background_is_exact_for_an_rgb_scene(tmp_path, capsys):
    # listing 3.1 has no bubble, so it is rendered in RGB: a pixel that sees only the
    # environment is exactly the --background colour in the .npy
    status, _, _ = run(["image", LISTING_3_1, tmp_path / "o.npy", "--background", "0.2,0.4,0.6", *TINY], capsys)
    assert status == 0
    image = np.load(tmp_path / "o.npy")
    for corner in (image[0, 0], image[0, -1], image[-1, 0], image[-1, -1]):
        assert corner.tolist() == [0.2, 0.4, 0.6]


# ------------------------------------------------------------------------------------------
# research
# ------------------------------------------------------------------------------------------
def test_research_json(tmp_path, capsys):
    target = tmp_path / "o.npy"
    status, out, err = run(["research", LISTING_3_2, target, "4", "--json", "--width", "6", "--height", "5",
                            "--spp", "3", "--quiet"], capsys)
    assert (status, err) == (0, "")
    assert out.endswith("\n") and out.count("\n") == 1  # one JSON object on one line
    report = json.loads(out)
    assert report["render_seconds"] > 0
    rays = report["rays"]
    assert rays["camera"] == 6 * 5 * 3
    assert rays["total"] == sum(v for k, v in rays.items() if k != "total")
    assert rays["transmitted"] > 0  # the sphere has kt = 1 and the bubble transmits
    assert report["depth"] == 4 and report["width"] == 6 and report["height"] == 5 and report["spp"] == 3
    assert np.load(target).shape == (5, 6, 3)


@pytest.mark.api
def test_research_json_reports_the_spectral_method_auto_chose(tmp_path, capsys):
    """--spectral-method auto (the default) resolves per scene: a thin bubble keeps point samples,
    a 15-micron one gets band-averaged films; an explicit choice is reported as given."""
    def method(scene_text, *extra):
        scene = tmp_path / "s.toml"
        scene.write_text(scene_text, encoding="utf-8")
        status, out, err = run(["research", scene, tmp_path / "o.npy", "3", "--json", "--width", "4", "--height", "4",
                                "--quiet", *extra], capsys)
        assert (status, err) == (0, "")
        return json.loads(out)["spectral_method"]

    bubble = "[[bubbles]]\ncenter = [0, 0, 0]\nradius = 1\nfilm = {{ kind = \"uniform\", thickness_nm = {d} }}\n"
    assert method(bubble.format(d=500)) == "point"
    assert method(bubble.format(d=15000)) == "band"
    assert method(bubble.format(d=15000), "--spectral-method", "point") == "point"
    assert method(bubble.format(d=500), "--spectral-method", "band") == "band"
    assert method("[[spheres]]\ncenter = [0, 0, 0]\nradius = 1\n") == ""  # RGB transport: no film method


def test_research_depth_1_traces_camera_rays_only(tmp_path, capsys):
    status, out, _ = run(["research", LISTING_3_2, tmp_path / "o.npy", "1", "--json", "--width", "6",
                          "--height", "5", "--quiet"], capsys)
    assert status == 0
    rays = json.loads(out)["rays"]
    assert rays["camera"] == 30 and rays["reflected"] == rays["transmitted"] == 0


def test_research_text_names_the_time_and_the_rays(tmp_path, capsys):
    status, out, err = run(["research", LISTING_3_2, tmp_path / "o.png", "3", "--width", "8", "--height", "8",
                            "--spp", "2", "--quiet"], capsys)
    assert (status, err) == (0, "")
    assert " s (compilation excluded)" in out
    assert "depth 3" in out and "8x8" in out
    assert "rays:" in out and "camera 128" in out
    for kind in ("reflected", "transmitted", "shadow", "total"):
        assert kind in out
    assert (tmp_path / "o.png").is_file()


def test_toml_render_table_supplies_defaults_that_options_override(tmp_path, capsys):
    scene = tmp_path / "small.toml"
    scene.write_text("[render]\nwidth = 6\nheight = 4\nspp = 2\ndepth = 2\n\n"
                     "[[spheres]]\ncenter = [0, 0, 0]\nradius = 1\n", encoding="utf-8")
    status, out, _ = run(["research", scene, tmp_path / "r.npy", "3", "--json", "--quiet"], capsys)
    assert status == 0
    report = json.loads(out)
    assert (report["width"], report["height"], report["spp"], report["depth"]) == (6, 4, 2, 3)
    assert report["rays"]["camera"] == 6 * 4 * 2
    status, out, _ = run(["research", scene, tmp_path / "r.npy", "3", "--json", "--quiet", "--width", "3"], capsys)
    assert json.loads(out)["rays"]["camera"] == 3 * 4 * 2
    status, _, _ = run(["image", scene, tmp_path / "i.npy", "--quiet"], capsys)
    assert status == 0 and np.load(tmp_path / "i.npy").shape == (4, 6, 3)


# ------------------------------------------------------------------------------------------
# Every shipped scene, and the built-in one
# ------------------------------------------------------------------------------------------
@pytest.mark.parametrize("scene", [LISTING_3_1, LISTING_3_2] + SCENE_FILES, ids=lambda p: p.name)
def test_shipped_scenes_render(tmp_path, capsys, scene):
    status, out, err = run(["image", scene, tmp_path / "o.npy", *TINY], capsys)
    assert (status, out, err) == (0, "", "")
    image = np.load(tmp_path / "o.npy")
    # (spectral colours may lie a little outside the sRGB gamut: small negative values are kept;
    # at 8 x 6 pixels a thin object may fall between pixel centres, so the image may be black)
    assert image.shape == (6, 8, 3) and np.isfinite(image).all()


def test_builtin_scene_without_a_scene_argument(tmp_path, capsys):
    from PIL import Image

    status, out, err = run(["image", tmp_path / "o.png", "--width", "16", "--height", "12", "--depth", "2",
                            "--quiet"], capsys)
    assert (status, out, err) == (0, "", "")
    with Image.open(tmp_path / "o.png") as im:
        assert im.mode == "RGB" and im.size == (16, 12)
        data = np.asarray(im).astype(int)
    expected = tracer.render(tracer.default_scene(), width=16, height=12, depth=2)
    assert np.abs(data - np.round(linear_to_srgb(expected) * 255)).max() <= 1
    assert np.ptp(data) > 20  # bubbles and surroundings, not a blank picture


# ------------------------------------------------------------------------------------------
# Real processes: the console script and python -m tracer
# ------------------------------------------------------------------------------------------
def console_script():
    script = Path(sys.executable).with_name("tracer")
    if script.exists():
        return str(script)
    found = shutil.which("tracer")
    if found is None:
        pytest.skip("the tracer console script is not installed")
    return found


def run_process(argv, cwd):
    return subprocess.run([str(a) for a in argv], cwd=cwd, capture_output=True, text=True, timeout=120)


def test_console_script_bad_scene(tmp_path):
    scene = tmp_path / "scene.txt"
    scene.write_text(with_line(LISTING_3_2, 5, "0.4 0.1 0 7"), encoding="utf-8")
    proc = run_process([console_script(), "image", "scene.txt", "o.png", *TINY], tmp_path)
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert proc.stderr == "scene.txt:5: sphere 'сфера': coefficient kt = 7 is outside [0, 1]\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.txt"]


def test_console_script_builtin_scene(tmp_path):
    # the kernel in numba's on-disk cache first (this process compiles it if no other test has yet),
    # so that the run says nothing: the first run's compile notice is test_features.py's subject
    tracer.render_with_stats(tracer.default_scene(), width=2, height=2, depth=2, progress=False)
    proc = run_process([console_script(), "image", "o.png", "--width", "8", "--height", "8", "--depth", "2"],
                       tmp_path)
    assert (proc.returncode, proc.stdout, proc.stderr) == (0, "", "")
    assert png_header(tmp_path / "o.png") == (8, 8, 8, 2)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["o.png"]


def test_python_m_tracer_research_json(tmp_path):
    proc = run_process([sys.executable, "-m", "tracer", "research", LISTING_3_2, "o.npy", "2", "--json",
                        "--width", "4", "--height", "3"], tmp_path)
    assert (proc.returncode, proc.stderr) == (0, "")
    report = json.loads(proc.stdout)
    assert report["render_seconds"] > 0 and report["rays"]["camera"] == 12
    assert np.load(tmp_path / "o.npy").shape == (3, 4, 3)


def test_python_m_tracer_bad_option(tmp_path):
    proc = run_process([sys.executable, "-m", "tracer", "image", LISTING_3_2, "o.png", "--width", "0"], tmp_path)
    assert proc.returncode == 2 and proc.stdout == ""
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr
    assert proc.stderr.startswith("tracer image: error: argument --width")
    assert list(tmp_path.iterdir()) == []
