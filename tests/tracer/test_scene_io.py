"""Scene files: the coursework's text format, the native TOML format, the writer, the converter, and errors.

Expected values are read off the listings by eye (docs/scene-format.md gives the mapping), so
a test failing here means the loader and the documentation disagree.
"""

import dataclasses
import math
import pickle
import tomllib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from tracer.scene.errors import SceneError, SceneWarning
from tracer.scene.load import (
    coursework_to_toml,
    load_coursework_scene,
    load_scene,
    load_toml_scene,
    save_toml_scene,
    scene_to_toml_text,
)
from tracer.scene import COURSEWORK_NM_PER_UNIT, Camera, Environment, Material, Scene, Sphere
from tracer.scene.toml_read import parse_toml_text

pytestmark = pytest.mark.api

ROOT = Path(__file__).resolve().parents[2]
LISTING_3_1 = ROOT / "data" / "coursework_scenes" / "listing_3_1.txt"
LISTING_3_2 = ROOT / "data" / "coursework_scenes" / "listing_3_2.txt"
SCENES = ROOT / "data" / "scenes"


def srgb_decode(c8):
    """IEC 61966-2-1 sRGB decoding, written out here independently of colour-science."""
    c = c8 / 255.0
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def assert_same(a, b, where="scene"):
    """Dataclass trees equal field by field (arrays by value and shape), ignoring Scene.source."""
    if dataclasses.is_dataclass(a):
        assert type(a) is type(b), where
        for f in dataclasses.fields(a):
            if isinstance(a, Scene) and f.name == "source":
                continue
            assert_same(getattr(a, f.name), getattr(b, f.name), f"{where}.{f.name}")
    elif isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        assert isinstance(a, np.ndarray) and isinstance(b, np.ndarray), where
        assert a.shape == b.shape and np.array_equal(a, b), where
    elif isinstance(a, (list, tuple)):
        assert len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b)):
            assert_same(x, y, f"{where}[{i}]")
    elif isinstance(a, dict):
        assert a.keys() == b.keys(), where
        for k in a:
            assert_same(a[k], b[k], f"{where}[{k!r}]")
    else:
        assert a == b, f"{where}: {a!r} != {b!r}"


#: A material's five lines in the coursework's format.
MAT = "255 255 255\n0.1 0.5 0.5 0\n10\n1\n0\n"


def write(tmp_path, text, name="scene.txt", encoding="utf-8"):
    p = tmp_path / name
    if isinstance(text, bytes):
        p.write_bytes(text)
    else:
        p.write_text(text, encoding=encoding)
    return p


# ==========================================================================================
# The coursework's format: the two listings
# ==========================================================================================
def test_listing_3_1_tetrahedron_and_light():
    scene = load_coursework_scene(LISTING_3_1)
    assert scene.spheres == [] and scene.bubbles == []
    (mesh,) = scene.meshes
    assert mesh.name == "тетраэдр"
    np.testing.assert_array_equal(
        mesh.vertices, [[500, 300, 0], [700, 300, -300], [300, 400, 0], [300, 350, -100]]
    )
    # f 1 3 4 / f 1 2 4 / f 2 3 4 / f 1 2 3, counted from 1 in the file
    np.testing.assert_array_equal(mesh.faces, [[0, 2, 3], [0, 1, 3], [1, 2, 3], [0, 1, 2]])
    m = mesh.material
    assert (m.name, m.color) == ("тетраэдр", (1.0, 1.0, 1.0))
    assert (m.ambient, m.diffuse, m.specular, m.transmission) == (0.3, 1.0, 0.0, 0.0)
    assert (m.shininess, m.ior) == (100.0, 1.0)
    (light,) = scene.lights
    assert light.position == (1000.0, 1000.0, 1000.0)
    assert light.intensity == 0.5 and light.color == (1.0, 1.0, 1.0)
    assert scene.camera == Camera.coursework_default()
    assert scene.environment.kind == "constant" and scene.environment.color == (0.0, 0.0, 0.0)
    assert scene.ambient == (1.0, 1.0, 1.0)
    assert scene.source == str(LISTING_3_1)
    assert scene.render_defaults == {}


def test_listing_3_2_sphere_and_bubble():
    scene = load_coursework_scene(LISTING_3_2)
    (sphere,) = scene.spheres
    assert sphere.name == "сфера"
    assert sphere.center == (300.0, 400.0, 150.0) and sphere.radius == 100.0
    m = sphere.material
    assert m.color == (0.0, 0.0, 1.0)  # 0 0 255
    assert (m.ambient, m.diffuse, m.specular, m.transmission, m.shininess, m.ior) == (
        0.4, 0.1, 0.0, 1.0, 100.0, 1.0)
    (bubble,) = scene.bubbles
    assert bubble.name == "пузырь"
    assert bubble.center == (450.0, 150.0, -100.0) and bubble.radius == 100.0
    assert bubble.n_film == 1.3 and bubble.shininess == 100.0
    assert scene.lights == [] and scene.meshes == []


@pytest.mark.analytic
def test_bubble_thickness_is_radius_difference_times_coursework_scale():
    (bubble,) = load_coursework_scene(LISTING_3_2).bubbles
    assert bubble.film.kind == "uniform"
    expected = (100 - 99.9) * COURSEWORK_NM_PER_UNIT  # 0.1 unit -> 100 nm (up to float rounding)
    assert math.isclose(bubble.film.thickness_nm, 100.0, rel_tol=1e-9)
    assert math.isclose(bubble.film.thickness_nm, expected, rel_tol=1e-9)
    # taken in decimal from the digits as written, so exactly 100 rather than 99.99999999999432
    assert bubble.film.thickness_nm == 100.0


@pytest.mark.analytic
@pytest.mark.parametrize("c8", [0, 1, 10, 11, 100, 128, 200, 254, 255])
def test_colours_are_decoded_from_srgb(tmp_path, c8):
    text = f"s a\n0 0 0\n1\n{c8} 0 255\n0 1 0 0\n1\n1\n0\n"
    (s,) = load_coursework_scene(write(tmp_path, text)).spheres
    assert s.material.color[0] == pytest.approx(srgb_decode(c8), rel=1e-12, abs=1e-15)
    assert s.material.color[1:] == (0.0, 1.0)


def test_light_tag_read_as_digit_one_by_the_pdf_transcription(tmp_path):
    text = LISTING_3_1.read_text(encoding="utf-8").replace("\nl\n", "\n1\n")
    assert "\n1\n1000 1000 1000" in text
    assert_same(load_coursework_scene(write(tmp_path, text)), load_coursework_scene(LISTING_3_1))


def test_comments_crlf_and_byte_order_mark_are_accepted(tmp_path):
    text = LISTING_3_2.read_text(encoding="utf-8")
    lines = text.split("\n")
    lines.insert(0, "# a comment before everything")
    lines.insert(3, "   # a comment inside a block")
    data = ("\ufeff" + "\r\n".join(lines)).encode("utf-8")
    assert_same(load_coursework_scene(write(tmp_path, data)), load_coursework_scene(LISTING_3_2))


def test_several_blank_lines_separate_blocks(tmp_path):
    text = LISTING_3_2.read_text(encoding="utf-8").replace("\n\n", "\n\n\n  \n\t\n") + "\n\n\n"
    assert_same(load_coursework_scene(write(tmp_path, text)), load_coursework_scene(LISTING_3_2))


def test_scene_without_lights_is_allowed(tmp_path):
    scene = load_coursework_scene(write(tmp_path, "s a\n0 0 0\n1\n1 2 3\n0 1 0 0\n1\n1\n0\n"))
    assert scene.lights == [] and len(scene.spheres) == 1


BUBBLE = """b пузырь
10 20 30
{r_out}
100 100 100
0.1 0.4 0 1
100
1.3
100000
{inner_centre}
{r_in}
0 0 0
0 0 0.5 1
0
1
0
"""


@pytest.mark.analytic
def test_bubble_with_equal_radii_has_a_zero_thickness_film(tmp_path):
    text = BUBBLE.format(r_out=50, inner_centre="10 20 30", r_in=50)
    (b,) = load_coursework_scene(write(tmp_path, text)).bubbles
    assert b.film.thickness_nm == 0.0 and b.radius == 50.0


@pytest.mark.analytic
def test_bubble_inner_centre_may_differ_by_rounding_only(tmp_path):
    text = BUBBLE.format(r_out=50, inner_centre="10 20 30.00000000001", r_in=49.5)
    (b,) = load_coursework_scene(write(tmp_path, text)).bubbles
    assert b.film.thickness_nm == 500.0 and b.center == (10.0, 20.0, 30.0)


def test_zero_area_faces_are_skipped_with_a_warning(tmp_path):
    text = ("t m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\n"
            "f 1 2 3\nf 1 2 4\nf 1 1 3\n-\n255 255 255\n0 1 0 0\n1\n1\n0\n")
    path = write(tmp_path, text)
    with pytest.warns(SceneWarning) as record:
        scene = load_coursework_scene(path)
    assert [str(w.message) for w in record] == [
        f"{path}:7: triangulated object 'm': face 1 2 4 has zero area and is skipped",
        f"{path}:8: triangulated object 'm': face 1 1 3 has zero area and is skipped",
    ]
    np.testing.assert_array_equal(scene.meshes[0].faces, [[0, 1, 2]])


@pytest.mark.analytic
def test_both_loaders_skip_exactly_the_faces_the_bvh_calls_degenerate(tmp_path):
    """One zero-area test (tracer.kernels.geometry.degenerate_triangles) for both formats: thinner than 16
    ulps of the coordinates is skipped, however small the triangle; thin but real is kept."""
    from tracer.kernels.geometry import degenerate_triangles

    verts = [(0, 0, 0), (1, 0, 0), (0, 1, 0),  # a good face
             (0.5, 1e-13, 0),  # 1e-13 high over a unit edge: thin, but 30 ulps of its coordinates
             (1e6, 0, 0), (1e6 + 1, 0, 0), (1e6 + 0.5, 1e-10, 0)]  # 1e-10 high at 1e6: under 16 ulps
    faces = [(0, 1, 2), (0, 1, 3), (4, 5, 6)]
    text = ("t m\n" + "".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in verts)
            + "".join(f"f {i + 1} {j + 1} {k + 1}\n" for i, j, k in faces) + "-\n" + MAT)
    toml = (f"[[meshes]]\nvertices = {[list(map(float, v)) for v in verts]}\n"
            f"faces = {[list(f) for f in faces]}\n")
    for path in (write(tmp_path, text), write(tmp_path, toml, "m.toml")):
        with pytest.warns(SceneWarning) as record:
            (mesh,) = load_scene(path).meshes
        assert len(record) == 1
        np.testing.assert_array_equal(mesh.faces, [[0, 1, 2], [0, 1, 3]])
        assert not degenerate_triangles(mesh.vertices[mesh.faces]).any()


# ------------------------------------------------------------------------------------------
# Coursework-format errors: every one names the file and the line, and says what is wrong
# ------------------------------------------------------------------------------------------
SPHERE = "s шар\n0 0 0\n1\n255 0 0\n0.1 0.5 0.5 0\n10\n1.5\n0\n"  # 8 lines
LIGHT = "l\n1 2 3\n0.5\n"
MESH_HEAD = "t т\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"  # lines 1-5


def sphere_with(line, value):
    lines = SPHERE.split("\n")
    lines[line - 1] = value
    return "\n".join(lines)


COURSEWORK_ERRORS = {
    "unknown tag": ("x thing\n0 0 0\n", 1, "unknown block tag 'x'"),
    "capital tag": ("S шар\n0 0 0\n1\n", 1, "unknown block tag 'S'"),
    "two numbers for a centre": (sphere_with(2, "0 0"), 2, "expected 3 numbers (x y z)"),
    "four numbers for a centre": (sphere_with(2, "0 0 0 0"), 2, "found 4 fields"),
    "not a number": (sphere_with(2, "0 a 0"), 2, "'a' is not a number"),
    "comma decimal": (sphere_with(3, "1,5"), 3, "'1,5' is not a number"),
    "NaN radius": (sphere_with(3, "nan"), 3, "must be a finite number"),
    "infinite coordinate": (sphere_with(2, "0 -inf 0"), 2, "must be a finite number"),
    "overflowing number": (sphere_with(2, "0 1e999 0"), 2, "not a finite number"),
    "zero radius": (sphere_with(3, "0"), 3, "radius must be positive"),
    "negative radius": (sphere_with(3, "-2"), 3, "radius must be positive"),
    "colour above 255": (sphere_with(4, "256 0 0"), 4, "= 256 is outside 0-255"),
    "negative colour": (sphere_with(4, "0 -1 0"), 4, "= -1 is outside 0-255"),
    "fractional colour": (sphere_with(4, "0.5 0 0"), 4, "'0.5' is not an integer 0-255"),
    "two colour fields": (sphere_with(4, "0 0"), 4, "expected 3 integers (R G B)"),
    "coefficient above 1": (sphere_with(5, "0.1 1.2 0 0"), 5, "coefficient kd = 1.2 is outside [0, 1]"),
    "negative coefficient": (sphere_with(5, "0.1 0.2 0 -0.1"), 5, "coefficient kt = -0.1 is outside [0, 1]"),
    "three coefficients": (sphere_with(5, "0.1 0.2 0"), 5, "expected 4 numbers (ka kd ks kt)"),
    "negative exponent": (sphere_with(6, "-1"), 6, "specular exponent must be >= 0"),
    "zero index": (sphere_with(7, "0"), 7, "refraction index must be > 0 and <= 100"),
    "negative dispersion": (sphere_with(8, "-0.5"), 8, "dispersion must be >= 0"),
    "sphere without a name": (sphere_with(1, "s"), 1, "needs a name"),
    "light with a name": (SPHERE + "\nl лампа\n1 2 3\n0.5\n", 10, "light's tag line is just 'l'"),
    "light intensity above 1": (SPHERE + "\nl\n1 2 3\n1.5\n", 12, "intensity 1.5 is outside [0, 1]"),
    "negative light intensity": (SPHERE + "\n1\n1 2 3\n-0.5\n", 12, "intensity -0.5 is outside [0, 1]"),
    "truncated at the end of the file": ("\n".join(SPHERE.split("\n")[:6]) + "\n", 7,
                                         "the file ends before its refraction index"),
    "truncated without a final line end": ("\n".join(SPHERE.split("\n")[:3]), 4,
                                           "the file ends before its material colour"),
    "block cut short by a blank line": ("\n".join(SPHERE.split("\n")[:5]) + "\n\n" + LIGHT, 6,
                                        "the block ends (blank line) before its specular exponent"),
    "missing blank line between blocks": (SPHERE + LIGHT, 9, "unexpected line 'l' after the end of sphere"),
    "face names a missing vertex": (MESH_HEAD + "f 1 2 3\nf 1 2 5\n-\n" + MAT, 7,
                                    "names vertex 5, but the object has 4 vertices"),
    "face counts from 0": (MESH_HEAD + "f 0 1 2\n-\n" + MAT, 6, "vertex numbers count from 1"),
    "quad face": (MESH_HEAD + "f 1 2 3 4\n-\n" + MAT, 6, "a face is 'f i j k'"),
    "non-integer face": (MESH_HEAD + "f 1 2 3.0\n-\n" + MAT, 6, "'3.0' is not an integer"),
    "vertex with two coordinates": ("t т\nv 0 0\n", 2, "expected 3 numbers (x y z)"),
    "mesh without the '-' line": (MESH_HEAD + "f 1 2 3\n" + MAT, 7, "is the '-' line before the material missing?"),
    "mesh ends without the '-' line": (MESH_HEAD + "f 1 2 3\n", 7, "without the '-' line"),
    "mesh without faces": (MESH_HEAD + "-\n" + MAT, 1, "has no faces"),
    "mesh whose faces all have zero area": ("t т\nv 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n-\n" + MAT, 1,
                                            "no usable face"),
    "inner radius above outer": (BUBBLE.format(r_out=50, inner_centre="10 20 30", r_in=51), 10,
                                 "inner radius 51 is larger than the outer radius 50"),
    "inner sphere not concentric": (BUBBLE.format(r_out=50, inner_centre="10 20 31", r_in=49), 9,
                                    "must be concentric with the outer"),
    "zero inner radius": (BUBBLE.format(r_out=50, inner_centre="10 20 30", r_in=0), 10,
                          "inner radius must be positive"),
    "bad inner material": (BUBBLE.format(r_out=50, inner_centre="10 20 30", r_in=49).replace(
        "0 0 0.5 1", "0 0 0.5 2"), 12, "inner coefficient kt = 2 is outside [0, 1]"),
    "NUL byte": (b"s a\n0 0 0\n1\x00\n", 3, "NUL byte"),
    "not UTF-8 (Windows-1251 name)": (("\n" + SPHERE).encode("cp1251"), 2, "not UTF-8"),
    "lights only": (LIGHT, None, "no objects"),
    "empty file": ("", None, "no objects: the file is empty"),
    "comments only": ("# nothing\n\n", None, "no objects"),
}


@pytest.mark.parametrize("text,line,what", COURSEWORK_ERRORS.values(), ids=COURSEWORK_ERRORS.keys())
def test_coursework_errors_name_file_line_and_problem(tmp_path, text, line, what):
    path = write(tmp_path, text)
    with pytest.raises(SceneError) as info:
        load_coursework_scene(path)
    err = info.value
    assert err.path == str(path) and err.line == line
    prefix = f"{path}:{line}: " if line is not None else f"{path}: "
    assert str(err).startswith(prefix), str(err)
    assert what in err.message, err.message
    assert str(err) == prefix + err.message


def test_missing_file_and_directory(tmp_path):
    with pytest.raises(SceneError, match=r"nope\.txt: no such file$") as info:
        load_scene(tmp_path / "nope.txt")
    assert info.value.line is None
    with pytest.raises(SceneError, match="is a directory") as info:
        load_scene(tmp_path)
    assert str(info.value) == f"{tmp_path}: is a directory, not a file"


def test_scene_error_is_a_value_error_and_pickles():
    err = SceneError("a/b.txt", 7, "radius must be positive")
    assert isinstance(err, ValueError)
    assert str(err) == "a/b.txt:7: radius must be positive"
    assert str(SceneError(Path("a/b.txt"), None, "no objects")) == "a/b.txt: no objects"
    back = pickle.loads(pickle.dumps(err))
    assert (back.path, back.line, back.message, str(back)) == (err.path, err.line, err.message, str(err))


# ==========================================================================================
# Shipped scene files
# ==========================================================================================
COURSEWORK_FILES = sorted(SCENES.glob("*.txt")) + [LISTING_3_1, LISTING_3_2]


@pytest.mark.parametrize("path", COURSEWORK_FILES, ids=lambda p: p.name)
def test_shipped_coursework_scenes_load_and_round_trip_through_toml(tmp_path, path):
    scene = load_scene(path)
    assert scene.spheres or scene.bubbles or scene.meshes
    toml_path = coursework_to_toml(path, tmp_path / "converted.toml")
    assert_same(load_scene(toml_path), scene)


def test_benchmark_scenes_hold_one_two_three_coursework_bubbles():
    for n, name in enumerate(["coursework_one_bubble", "coursework_two_bubbles", "coursework_three_bubbles"], start=1):
        scene = load_scene(SCENES / f"{name}.txt")
        assert len(scene.bubbles) == n and not scene.spheres and not scene.meshes
        assert len(scene.lights) == 1
        for b in scene.bubbles:
            assert (b.radius, b.film.thickness_nm, b.n_film) == (100.0, 100.0, 1.3)
            assert all(0 < c < 960 for c in b.center[:2])


def test_converted_listing_in_data_is_the_converter_output(tmp_path):
    shipped = SCENES / "listing_3_2.toml"
    fresh = coursework_to_toml(LISTING_3_2, tmp_path / "listing_3_2.toml")
    assert shipped.read_text(encoding="utf-8") == fresh.read_text(encoding="utf-8")
    assert_same(load_scene(shipped), load_coursework_scene(LISTING_3_2))


def test_showcase_toml_scene():
    scene = load_scene(SCENES / "bubbles_sky.toml")
    assert scene.environment.kind == "sky"
    assert [b.name for b in scene.bubbles] == ["young", "middle-aged", "old"]
    assert all(b.film.kind == "draining" and b.n_film == "water" for b in scene.bubbles)
    assert [b.film.top_nm for b in scene.bubbles] == [450.0, 120.0, 15.0]
    assert len(scene.lights) == 1 and scene.camera.fov_deg == 35.0
    assert scene.render_defaults == dict(width=640, height=480, depth=8, spp=4,
                                         spectral_samples=16, threshold=1e-3)


def test_load_scene_dispatches_on_suffix(tmp_path):
    toml_text = LISTING_3_2.read_text(encoding="utf-8")
    coursework_as_toml = write(tmp_path, toml_text, "coursework.TOML")
    with pytest.raises(SceneError, match="invalid TOML"):
        load_scene(coursework_as_toml)  # .TOML (any case) is read as TOML
    other = write(tmp_path, toml_text, "scene.scn")
    assert_same(load_scene(other), load_coursework_scene(LISTING_3_2))


# ==========================================================================================
# TOML
# ==========================================================================================
MINIMAL = """\
[[spheres]]
center = [0, 0, 0]
radius = 1
"""


def test_toml_defaults_for_a_minimal_file(tmp_path):
    scene = load_toml_scene(write(tmp_path, MINIMAL, "s.toml"))
    (s,) = scene.spheres
    assert s.center == (0.0, 0.0, 0.0) and isinstance(s.center[0], float) and s.radius == 1.0
    assert scene.camera == Camera() and scene.environment.kind == Environment().kind
    assert scene.lights == [] and scene.render_defaults == {}


def test_toml_named_inline_and_hex_materials(tmp_path):
    text = """\
[materials.glass]
color = "#ff8000"
specular = 0.1
transmission = 0.9
ior = 1.5

[[spheres]]
name = "a"
center = [0, 0, 0]
radius = 1
material = "glass"

[[spheres]]
name = "b"
center = [3, 0, 0]
radius = 1
material = { color = [0.5, 0.25, 0.0], diffuse = 0.7 }
"""
    a, b = load_toml_scene(write(tmp_path, text, "m.toml")).spheres
    assert a.material.name == "glass" and a.material.ior == 1.5 and a.material.transmission == 0.9
    assert a.material.color == pytest.approx((1.0, srgb_decode(128), 0.0), rel=1e-12)
    assert b.material.name == "b" and b.material.color == (0.5, 0.25, 0.0) and b.material.diffuse == 0.7


def test_toml_unknown_key_is_an_error_with_its_line(tmp_path):
    text = MINIMAL + "\n[[spheres]]\ncenter = [3, 0, 0]\nradus = 1\n"
    path = write(tmp_path, text, "typo.toml")
    with pytest.raises(SceneError) as info:
        load_toml_scene(path)
    assert info.value.line == 7
    assert str(info.value).startswith(f"{path}:7: unknown key 'radus' in [[spheres]]; did you mean 'radius'?")


def test_toml_unknown_key_in_the_second_bubbles_film(tmp_path):
    text = """\
[[bubbles]]
center = [0, 0, 0]
radius = 1

[bubbles.film]
kind = "draining"
top_nm = 100

[[bubbles]]
center = [3, 0, 0]
radius = 1
[bubbles.film]
kind = "draining"
bottom_nm = 900
top = 50
"""
    with pytest.raises(SceneError) as info:
        load_toml_scene(write(tmp_path, text, "b.toml"))
    assert info.value.line == 15
    assert "unknown key 'top' in a film of kind 'draining'" in info.value.message


TOML_ERRORS = {
    "syntax": ("[[spheres]]\ncenter = [0, 0,\nradius = 1\n", 3, "invalid TOML"),
    "unknown table": (MINIMAL + "[camra]\nfov_deg = 30\n", 4, "unknown key 'camra' in the top level; did you mean 'camera'?"),
    "negative radius": (MINIMAL + "[[spheres]]\ncenter = [0, 0, 0]\nradius = -1\n", 6, "spheres[1].radius: must be > 0"),
    "missing radius": ("[[spheres]]\ncenter = [0, 0, 0]\n", 1, "[[spheres]] needs a 'radius' key"),
    "centre of two numbers": ("[[spheres]]\ncenter = [0, 0]\nradius = 1\n", 2, "spheres[0].center: must be an array of 3 numbers"),
    "string radius": ("[[spheres]]\ncenter = [0, 0, 0]\nradius = \"1\"\n", 3, "must be a number, got a string"),
    "boolean radius": ("[[spheres]]\ncenter = [0, 0, 0]\nradius = true\n", 3, "must be a number, got a boolean"),
    "nan radius": ("[[spheres]]\ncenter = [0, 0, 0]\nradius = nan\n", 3, "must be a finite number"),
    "spheres as a table": ("[spheres]\ncenter = [0, 0, 0]\n", 1, "must be an array of tables (write [[spheres]])"),
    "unknown material": (MINIMAL + "material = \"steel\"\n", 4, "no material named 'steel'"),
    "material colour above 1": ("[materials.x]\ncolor = [0.5, 1.5, 0]\n" + MINIMAL, 2, "materials.x.color: must be <= 1"),
    "bad hex colour": ("[materials.x]\ncolor = \"#12345\"\n" + MINIMAL, 2, "is not a colour"),
    "coefficient above 1": ("[materials.x]\nspecular = 2\n" + MINIMAL, 2, "materials.x.specular: must be <= 1"),
    "inline material with unknown key": (MINIMAL + "material = { colour = [1, 0, 0] }\n", 4,
                                         "unknown key 'colour' in an inline material; did you mean 'color'?"),
    "n_film not water": ("[[bubbles]]\ncenter = [0, 0, 0]\nradius = 1\nn_film = \"soap\"\n", 4,
                         "must be \"water\" or a number"),
    "film kind": ("[[bubbles]]\ncenter = [0, 0, 0]\nradius = 1\n[bubbles.film]\nkind = \"wavy\"\n", 5,
                  "bubbles[0].film.kind: must be one of"),
    "swirl above 1": ("[[bubbles]]\ncenter = [0, 0, 0]\nradius = 1\n[bubbles.film]\nkind = \"draining\"\nswirl = 1.5\n",
                      6, "bubbles[0].film.swirl: must be <= 1"),
    "key of another film kind": ("[[bubbles]]\ncenter = [0, 0, 0]\nradius = 1\n[bubbles.film]\nthickness_nm = 300\ntop_nm = 5\n",
                                 6, "unknown key 'top_nm' in a film of kind 'uniform'"),
    "map without path": ("[[bubbles]]\ncenter = [0, 0, 0]\nradius = 1\n[bubbles.film]\nkind = \"map\"\n", 4,
                         "a film of kind 'map' needs a 'path' key"),
    "map file missing": ("[[bubbles]]\ncenter = [0, 0, 0]\nradius = 1\nfilm = { kind = \"map\", path = \"no.npy\" }\n", 4,
                         "file not found: no.npy"),
    "environment key of another kind": (MINIMAL + "[environment]\nkind = \"sky\"\npath = \"sky.npy\"\n", 6,
                                        "unknown key 'path' in [environment] of kind 'sky'"),
    "environment kind": (MINIMAL + "[environment]\nkind = \"hdri\"\n", 5, "environment.kind: must be one of"),
    "camera looking at itself": (MINIMAL + "[camera]\nposition = [1, 1, 1]\nlook_at = [1, 1, 1]\n", 4,
                                 "look_at coincides with its position"),
    "camera fov": (MINIMAL + "[camera]\nfov_deg = 180\n", 5, "fov_deg: must be below 180"),
    "render width": (MINIMAL + "[render]\nwidth = 0\n", 5, "render.width: must be an integer from 1 to 65535"),
    "render float spp": (MINIMAL + "[render]\nspp = 2.0\n", 5, "render.spp: must be an integer"),
    "render typo": (MINIMAL + "[render]\nwidht = 10\n", 5, "did you mean 'width'?"),
    "light intensity": (MINIMAL + "[[lights]]\nposition = [0, 5, 0]\nintensity = -1\n", 6, "lights[0].intensity: must be >= 0"),
    "mesh without geometry": (MINIMAL + "[[meshes]]\nname = \"m\"\n", 4, "'vertices' is missing"),
    "mesh with path and vertices": (MINIMAL + "[[meshes]]\npath = \"m.obj\"\nvertices = [[0, 0, 0]]\n", 6,
                                    "either 'path' or 'vertices' and 'faces'"),
    "mesh face out of range": (MINIMAL + "[[meshes]]\nvertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\nfaces = [\n  [0, 1, 3],\n]\n",
                               6, "names vertex 3, but there are 3 vertices (indices count from 0 in TOML)"),
    "no objects": ("[camera]\nfov_deg = 30\n", None, "no objects"),
    "unit empty": (MINIMAL + "[scene]\nunit = \"\"\n", 5, "scene.unit: must not be empty"),
}


@pytest.mark.parametrize("text,line,what", TOML_ERRORS.values(), ids=TOML_ERRORS.keys())
def test_toml_errors_name_file_line_and_problem(tmp_path, text, line, what):
    path = write(tmp_path, text, "scene.toml")
    with pytest.raises(SceneError) as info:
        load_toml_scene(path)
    err = info.value
    assert (err.path, err.line) == (str(path), line), str(err)
    prefix = f"{path}:{line}: " if line is not None else f"{path}: "
    assert str(err).startswith(prefix) and what in err.message, str(err)


def test_toml_rejects_binary_and_non_utf8(tmp_path):
    with pytest.raises(SceneError, match=r"s\.toml:2: binary data"):
        load_scene(write(tmp_path, b"a = 1\nb = \x00\n", "s.toml"))
    with pytest.raises(SceneError, match=r"s\.toml:1: not UTF-8"):
        load_scene(write(tmp_path, "name = 'шар'\n".encode("cp1251"), "s.toml"))


def test_mesh_from_an_obj_file_with_scale_and_translate(tmp_path):
    pytest.importorskip("trimesh")
    (tmp_path / "models").mkdir()
    (tmp_path / "models" / "quad.obj").write_text(
        "# a unit square in z = 0, two triangles\n"
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n"
    )
    text = MINIMAL + """
[[meshes]]
name = "квадрат"
path = "models/quad.obj"
scale = 2.0
translate = [10, 0, -1]
material = { color = [0.2, 0.3, 0.4] }
"""
    (mesh,) = load_toml_scene(write(tmp_path, text, "mesh.toml")).meshes
    assert mesh.name == "квадрат" and mesh.material.color == (0.2, 0.3, 0.4)
    np.testing.assert_array_equal(mesh.vertices, [[10, 0, -1], [12, 0, -1], [12, 2, -1], [10, 2, -1]])
    np.testing.assert_array_equal(mesh.faces, [[0, 1, 2], [0, 2, 3]])


def test_unreadable_mesh_file(tmp_path):
    pytest.importorskip("trimesh")
    (tmp_path / "bad.obj").write_text("this is not a mesh\n")
    path = write(tmp_path, MINIMAL + "[[meshes]]\npath = \"bad.obj\"\n", "m.toml")
    with pytest.raises(SceneError) as info:
        load_toml_scene(path)
    assert info.value.line == 5 and info.value.message.startswith("meshes[0].path: ")


def test_inline_mesh_faces_count_from_zero(tmp_path):
    text = MINIMAL + """
[[meshes]]
vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
faces = [[0, 1, 2]]
"""
    (mesh,) = load_toml_scene(write(tmp_path, text, "m.toml")).meshes
    np.testing.assert_array_equal(mesh.faces, [[0, 1, 2]])
    assert mesh.vertices.dtype == np.float64 and mesh.faces.dtype == np.int64


def test_draining_and_map_films(tmp_path):
    table = np.linspace(50.0, 900.0, 12).reshape(4, 3)
    np.save(tmp_path / "film.npy", table)
    text = """\
[[bubbles]]
name = "drains"
center = [0, 0, 0]
radius = 1
n_film = 1.34
[bubbles.film]
kind = "draining"
top_nm = 80
bottom_nm = 1200
exponent = 0.4
swirl = 0.3
swirl_scale = 4
seed = 7
up = [0, 0, 1]

[[bubbles]]
name = "mapped"
center = [3, 0, 0]
radius = 1
film = { kind = "map", path = "film.npy" }
"""
    scene = load_toml_scene(write(tmp_path, text, "films.toml"))
    d, m = scene.bubbles
    assert d.n_film == 1.34 and m.n_film == "water"
    f = d.film
    assert (f.kind, f.top_nm, f.bottom_nm, f.exponent, f.swirl, f.swirl_scale, f.seed, f.up) == (
        "draining", 80.0, 1200.0, 0.4, 0.3, 4.0, 7, (0.0, 0.0, 1.0))
    assert m.film.kind == "map"
    np.testing.assert_array_equal(m.film.table, table)


def test_map_film_must_be_two_dimensional(tmp_path):
    np.save(tmp_path / "flat.npy", np.ones(5))
    text = "[[bubbles]]\ncenter = [0, 0, 0]\nradius = 1\n[bubbles.film]\nkind = \"map\"\npath = \"flat.npy\"\n"
    with pytest.raises(SceneError, match=r":6: bubbles\[0\]\.film\.path: a thickness map is a 2-D array"):
        load_toml_scene(write(tmp_path, text, "m.toml"))


def test_image_environment_from_npy(tmp_path):
    img = np.random.default_rng(1).uniform(0, 3, size=(8, 16, 3))
    np.save(tmp_path / "env.npy", img)
    text = MINIMAL + "[environment]\nkind = \"image\"\npath = \"env.npy\"\nintensity = 2.0\nup = [0, 0, 1]\n"
    env = load_toml_scene(write(tmp_path, text, "e.toml")).environment
    assert env.kind == "image" and env.intensity == 2.0 and env.up == (0.0, 0.0, 1.0)
    assert env.image.shape == (8, 16, 3) and env.image.dtype == np.float32
    np.testing.assert_allclose(env.image, img, rtol=1e-7)


def test_image_environment_npy_of_the_wrong_shape(tmp_path):
    np.save(tmp_path / "env.npy", np.ones((4, 4)))
    text = MINIMAL + "[environment]\nkind = \"image\"\npath = \"env.npy\"\n"
    with pytest.raises(SceneError, match=r":6: environment\.path: an environment image is \(H, W, 3\)"):
        load_toml_scene(write(tmp_path, text, "e.toml"))


@pytest.mark.analytic
def test_image_environment_from_png_is_decoded_from_srgb(tmp_path):
    from PIL import Image

    px = np.array([[[0, 128, 255], [10, 200, 64]]], dtype=np.uint8)
    Image.fromarray(px).save(tmp_path / "env.png")
    text = MINIMAL + "[environment]\nkind = \"image\"\npath = \"env.png\"\n"
    env = load_toml_scene(write(tmp_path, text, "e.toml")).environment
    expected = np.vectorize(srgb_decode)(px.astype(float))
    np.testing.assert_allclose(env.image, expected, rtol=1e-6, atol=1e-7)


def test_image_environment_from_hdr_when_opencv_is_installed(tmp_path):
    cv2 = pytest.importorskip("cv2")
    img = np.array([[[0.5, 1.0, 2.0], [4.0, 0.25, 0.125]]], dtype=np.float32)  # exact in RGBE
    assert cv2.imwrite(str(tmp_path / "env.hdr"), img[..., ::-1].copy())
    text = MINIMAL + "[environment]\nkind = \"image\"\npath = \"env.hdr\"\n"
    env = load_toml_scene(write(tmp_path, text, "e.toml")).environment
    np.testing.assert_allclose(env.image, img, rtol=1e-2)


def test_image_environment_from_exr_when_openexr_is_installed(tmp_path):
    OpenEXR = pytest.importorskip("OpenEXR")
    img = np.random.default_rng(2).uniform(0, 5, size=(3, 5, 3)).astype(np.float32)
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, {"RGB": img}) as f:
        f.write(str(tmp_path / "env.exr"))
    text = MINIMAL + "[environment]\nkind = \"image\"\npath = \"env.exr\"\n"
    env = load_toml_scene(write(tmp_path, text, "e.toml")).environment
    np.testing.assert_array_equal(env.image, img)


def test_toml_round_trip_of_arrays_and_awkward_names(tmp_path):
    np.save(tmp_path / "film.npy", np.arange(6.0).reshape(3, 2) * 100)
    np.save(tmp_path / "env.npy", np.ones((2, 4, 3)))
    text = """\
[scene]
ambient = [0.1, 0.2, 0.3]

[environment]
kind = "image"
path = "env.npy"

[render]
spp = 3
threshold = 0.0

[materials.'odd "name" \\ with spaces']
color = [0.1, 0.2, 0.3]

[[spheres]]
name = "quote \\" backslash \\\\ 'single' ёж ☃"
center = [0.1, 1e-300, -2.5e10]
radius = 0.3333333333333333
material = 'odd "name" \\ with spaces'

[[bubbles]]
film = { kind = "map", path = "film.npy", up = [1, 0, 0], swirl = 0.5 }
center = [0, 0, 0]
radius = 1

[[meshes]]
vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
faces = [[0, 1, 2]]

[[lights]]
position = [1, 2, 3]
color = "#ffffff"
"""
    scene = load_toml_scene(write(tmp_path, text, "a.toml"))
    assert scene.spheres[0].name == 'quote " backslash \\ \'single\' ёж ☃'
    with pytest.raises(ValueError, match="give toml_path"):
        scene_to_toml_text(scene)
    (tmp_path / "out").mkdir()
    out = save_toml_scene(scene, tmp_path / "out" / "b.toml")
    assert (tmp_path / "out" / "b.environment.npy").is_file()
    assert (tmp_path / "out" / "b.bubble0.film.npy").is_file()
    assert_same(load_toml_scene(out), scene)


# every number the loader accepts: magnitudes up to tracer.scene.limits.MAX_MAGNITUDE, indices up to MAX_INDEX
FINITE = st.floats(min_value=-1e15, max_value=1e15)


#: The names a scene may give: text without control or format characters, at most 200 long.
NAMES = st.text(alphabet=st.characters(blacklist_categories=("Cc", "Cf", "Cs")), max_size=200)


@pytest.mark.property
@given(name=NAMES, center=st.tuples(FINITE, FINITE, FINITE), radius=st.floats(min_value=5e-324, max_value=1e15),
       ior=st.floats(min_value=5e-324, max_value=100.0))
def test_toml_writer_round_trips_any_name_and_number(name, center, radius, ior):
    """Any name a scene may give to an object and a material, any number it accepts: back bit
    for bit."""
    scene = Scene(spheres=[Sphere(center=center, radius=radius, material=Material(name=name, ior=ior), name=name)])
    assert_same(parse_toml_text(scene_to_toml_text(scene)), scene)


@pytest.mark.property
@given(before=NAMES, control=st.characters(whitelist_categories=("Cc", "Cf")), after=NAMES)
def test_a_name_with_a_control_character_is_refused_at_its_line(before, control, after):
    """A newline (or any control or format character) in a name would put a line of its own
    into a movie commands file that names the object: both formats refuse it where it stands."""
    name = before[:50] + control + after[:50]
    text = scene_to_toml_text(Scene(spheres=[Sphere(center=(0.0, 0.0, 0.0), radius=1.0, name=name)]))
    line = next(i for i, ln in enumerate(text.splitlines(), 1) if ln.startswith("name = "))
    with pytest.raises(SceneError, match=r"spheres\[0\]\.name: .* has a control character \(U\+") as info:
        parse_toml_text(text, "s.toml")
    assert info.value.line == line and "\n" not in str(info.value)


def test_coursework_names_with_a_control_character_are_refused(tmp_path):
    path = write(tmp_path, "s bad\x07name\n0 0 0\n1\n255 255 255\n0.1 0.5 0.5 0\n10\n1\n", "s.txt")
    with pytest.raises(SceneError, match=r"s\.txt:1: .*control character \(U\+0007\)"):
        load_scene(path)


@pytest.mark.property
@given(st.text())
def test_keys_in_error_messages_are_written_as_toml_reads_them(key):
    from tracer.scene.toml_read import _toml_key

    assert tomllib.loads(f"{_toml_key(key)} = 1\n") == {key: 1}
    assert "\n" not in _toml_key(key)  # an error message stays one line


def test_writer_refuses_non_finite_numbers_and_leaves_the_old_file(tmp_path):
    target = write(tmp_path, "old\n", "s.toml")
    scene = Scene(spheres=[Sphere(center=(0.0, float("nan"), 0.0), radius=1.0)])
    with pytest.raises(ValueError, match="cannot write the non-finite number nan to TOML"):
        save_toml_scene(scene, target)
    assert target.read_text() == "old\n" and [p.name for p in tmp_path.iterdir()] == ["s.toml"]


def test_writer_output_is_what_tomli_w_writes_with_the_header_as_comments():
    import tomli_w

    scene = Scene(spheres=[Sphere(center=(1, 2, 3), radius=np.float32(0.5))])
    comment, body = scene_to_toml_text(scene, header="line one\n\nline three").split("\n\n", 1)
    assert comment == "# line one\n#\n# line three"
    assert body == tomli_w.dumps(tomllib.loads(body))
    assert tomllib.loads(body)["spheres"][0]["radius"] == 0.5  # numpy scalars written as numbers


def test_the_toml_example_in_the_docs_loads(tmp_path):
    doc = (ROOT / "docs" / "scene-format.md").read_text(encoding="utf-8")
    example = doc.split("### Example\n", 1)[1].split("```toml\n", 1)[1].split("```", 1)[0]
    scene = load_toml_scene(write(tmp_path, example, "example.toml"))
    assert [s.name for s in scene.spheres] == ["marble"] and scene.spheres[0].material.name == "glass"
    assert scene.bubbles[0].film.kind == "draining" and scene.meshes[0].faces.shape == (2, 3)


def test_the_simulated_film_example_in_the_docs_loads(tmp_path):
    """docs/scene-format.md's [bubbles.film] kind = "simulated" snippet, with a series file made
    by bubbleoptics.filmflow where it names one."""
    import numpy as np

    from bubbleoptics.filmflow import FilmGrid, ThicknessSeries

    doc = (ROOT / "docs" / "scene-format.md").read_text(encoding="utf-8")
    snippet = doc.split("**Simulated film.**", 1)[1].split("```toml\n", 1)[1].split("```", 1)[0]
    ThicknessSeries(np.full((2, 4, 8), 900.0), [0.0, 60.0], FilmGrid(4, 8, 0.04), {}, "test").save(
        tmp_path / "drainage.npz")
    scene = load_toml_scene(write(tmp_path, snippet, "simulated.toml"))
    film = scene.bubbles[0].film
    assert film.kind == "simulated" and film.time_s == 30.0 and film.rupture_nm == 5.0
    assert film.series.h_nm.shape == (2, 4, 8)


def test_coursework_text_can_be_parsed_from_a_string():
    from tracer.scene.block_format import parse_coursework_text

    text = LISTING_3_2.read_text(encoding="utf-8")
    assert_same(parse_coursework_text(text, LISTING_3_2), load_coursework_scene(LISTING_3_2))
    with pytest.raises(SceneError, match=r"^<string>:3: sphere 'a': radius must be positive"):
        parse_coursework_text("s a\n0 0 0\n0\n")


@pytest.mark.parametrize("suffix,module,package", [(".hdr", "cv2", "opencv-python-headless"),
                                                    (".exr", "OpenEXR", "OpenEXR")])
def test_missing_optional_image_reader_says_what_to_install(tmp_path, monkeypatch, suffix, module, package):
    monkeypatch.setitem(__import__("sys").modules, module, None)  # makes `import module` fail
    (tmp_path / f"env{suffix}").write_bytes(b"not really an image")
    text = MINIMAL + f"[environment]\nkind = \"image\"\npath = \"env{suffix}\"\n"
    with pytest.raises(SceneError, match=rf":6: environment\.path: reading \{suffix} needs .*pip install {package}"):
        load_toml_scene(write(tmp_path, text, "e.toml"))
