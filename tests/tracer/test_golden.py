"""Golden images: small renders frozen as float arrays in tests/data/golden/NAME.npy.

Each scene is rendered in-process with ``tracer.render(scene, width=32, height=32, depth=4,
spp=1)`` (other settings at their defaults) and compared with its frozen array at rtol 1e-9,
atol 1e-12.  A numerical change anywhere in the kernels shifts these values: that is the point,
such a change must be noticed.  When the change is intended, look at the new images and rewrite
the arrays with

    NUMBA_CACHE_DIR=$(mktemp -d) TRACER_REGENERATE_GOLDEN=1 pytest tests/tracer/test_golden.py

(a fresh numba cache, because the on-disk one misses changes in called functions; see
tests/data/README.md, which also says what was checked by eye in each image).

A golden image is produced by the code under test, so it only proves that nothing changed.
Each test therefore also checks facts about its image that do not come from the renderer:
which pixels see an object, from a ray-sphere or ray-triangle intersection written here with
the camera set up from the documented conventions (docs/scene-format.md), exact zeros where a
pixel sees only the coursework's black background, colours that follow from the materials, and so on.
"""

import dataclasses
import os
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest

import tracer

pytestmark = pytest.mark.regression

ROOT = Path(__file__).resolve().parents[2]
GOLDEN = Path(__file__).resolve().parents[1] / "data" / "golden"
SIZE = 32
SETTINGS = dict(width=SIZE, height=SIZE, depth=4, spp=1)
REGENERATE = os.environ.get("TRACER_REGENERATE_GOLDEN", "") not in ("", "0")

SCENES = {
    "listing_3_1": lambda: tracer.load_scene(ROOT / "data" / "coursework_scenes" / "listing_3_1.txt"),
    "listing_3_2": lambda: tracer.load_scene(ROOT / "data" / "coursework_scenes" / "listing_3_2.txt"),
    "fig3_5_materials": lambda: tracer.load_scene(ROOT / "data" / "scenes" / "fig3_5_materials.txt"),
    "builtin": tracer.default_scene,
}


@lru_cache(maxsize=None)
def rendered(name):
    return tracer.render(SCENES[name](), **SETTINGS)


def check_golden(name, image):
    """Compare *image* with tests/data/golden/NAME.npy (or rewrite it when regenerating)."""
    path = GOLDEN / f"{name}.npy"
    if REGENERATE:
        GOLDEN.mkdir(parents=True, exist_ok=True)
        np.save(path, image)
    if not path.exists():
        pytest.fail(f"{path} is missing; create it with TRACER_REGENERATE_GOLDEN=1 pytest {__file__}")
    golden = np.load(path)
    assert golden.shape == image.shape == (SIZE, SIZE, 3) and golden.dtype == np.float64
    np.testing.assert_allclose(image, golden, rtol=1e-9, atol=1e-12,
                               err_msg=f"{name}: the render no longer matches {path}")


# ------------------------------------------------------------------------------------------
# Geometry written here, independently of the renderer
# ------------------------------------------------------------------------------------------
def camera_rays(camera, width=SIZE, height=SIZE):
    """Origin and unit directions (H, W, 3) through the pixel centres (spp = 1 samples the centre).

    The documented convention: vertical field of view ``fov_deg``; right = forward x up (negated
    when ``mirror``), the camera's up = right x forward; row 0 at the top, column 0 at the left.
    """
    pos = np.asarray(camera.position, float)
    fwd = np.asarray(camera.look_at, float) - pos
    fwd /= np.linalg.norm(fwd)
    right = np.cross(fwd, np.asarray(camera.up, float))
    right /= np.linalg.norm(right)
    up = np.cross(right, fwd)
    if camera.mirror:
        right = -right
    half = np.tan(np.radians(camera.fov_deg) / 2)
    u = ((np.arange(width) + 0.5) / width * 2 - 1) * half * width / height
    v = (1 - (np.arange(height) + 0.5) / height * 2) * half
    d = fwd + u[None, :, None] * right + v[:, None, None] * up
    return pos, d / np.linalg.norm(d, axis=2, keepdims=True)


def sphere_miss_distance(origin, d, center, radius):
    """Closest approach of each ray's line to the centre, in radii (< 1: the ray hits the sphere)."""
    oc = np.asarray(center, float) - origin
    along = d @ oc
    assert (along > radius).all()  # every sphere here is in front of the camera
    return np.sqrt(np.maximum(oc @ oc - along**2, 0.0)) / radius


def triangle_margin(origin, d, v0, v1, v2):
    """Smallest barycentric coordinate of each ray's hit on the triangle's plane (> 0: inside)."""
    e1, e2 = v1 - v0, v2 - v0
    p = np.cross(d, e2)
    det = p @ e1
    s = origin - v0
    u = (p @ s) / det
    q = np.cross(s, e1)
    v = (d @ q) / det
    t = (q @ e2) / det
    return np.where(t > 0, np.minimum(np.minimum(u, v), 1 - u - v), -np.inf)


def srgb8_to_linear(c8):
    c = np.asarray(c8, float) / 255
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


# ------------------------------------------------------------------------------------------
# The golden images
# ------------------------------------------------------------------------------------------
def test_listing_3_1_tetrahedron():
    image = rendered("listing_3_1")
    check_golden("listing_3_1", image)
    scene = SCENES["listing_3_1"]()
    origin, d = camera_rays(scene.camera)
    (mesh,) = scene.meshes
    vertices = np.asarray(mesh.vertices, float)
    margin = np.max([triangle_margin(origin, d, *vertices[f]) for f in mesh.faces], axis=0)
    inside, outside = margin > 0.02, margin < -0.02
    assert inside.sum() >= 10 and inside.sum() + outside.sum() >= SIZE * SIZE - 10
    # black seed background, no bubble (RGB transport): exactly zero off the tetrahedron
    assert (image[outside] == 0).all()
    # white material (255 -> 1.0), white light, Ia = 1: grey, and at least the ambient ka = 0.3
    on = image[inside]
    assert (on[:, 0] == on[:, 1]).all() and (on[:, 1] == on[:, 2]).all()
    assert on.min() >= 0.3 - 1e-12 and on.max() <= 0.3 + 1.0 * 0.5 + 1e-9  # ka + kd * intensity at most
    assert on.max() > 0.3  # some face is lit by the light, not only ambient


def test_listing_3_2_sphere_and_bubble():
    image = rendered("listing_3_2")
    check_golden("listing_3_2", image)
    scene = SCENES["listing_3_2"]()
    origin, d = camera_rays(scene.camera)
    (sphere,) = scene.spheres
    (bubble,) = scene.bubbles
    ds = sphere_miss_distance(origin, d, sphere.center, sphere.radius)
    db = sphere_miss_distance(origin, d, bubble.center, bubble.radius)
    outside = (ds > 1.02) & (db > 1.02)
    assert outside.sum() > 900
    assert (image[outside] == 0).all()  # the coursework's black environment, exactly
    for corner in (image[0, 0], image[0, -1], image[-1, 0], image[-1, -1]):
        assert corner.tolist() == [0.0, 0.0, 0.0]
    # the coursework's screen: x to the right, y downwards, 960 units across at z = 0, viewer at
    # z = 2000; the sphere's centre (300, 400, 150) projects to (285.4, 393.5): column 9, row 13
    x, y = (np.array([300.0, 400.0]) - 480) * 2000 / (2000 - 150) + 480
    centre = (int(y / 960 * SIZE), int(x / 960 * SIZE))
    assert centre == (13, 9) and ds[centre] == ds.min()
    r, g, b = image[centre]
    assert b > 0.3 and b > 20 * max(abs(r), abs(g))  # colour 0 0 255, ka = 0.4: blue
    # no light in the file, index 1: nothing shades or bends, the whole disc has one colour
    disc = image[ds < 0.95]
    assert len(disc) > 20 and np.ptp(disc, axis=0).max() < 1e-12
    # the bubble has nothing to show but the sphere: black, or the sphere's blue in reflection
    film = image[db < 0.98]
    assert (film[:, 2] >= np.abs(film[:, :2]).max(axis=1)).all()
    assert film[:, 2].max() < disc[0, 2]


def test_fig3_5_materials():
    image = rendered("fig3_5_materials")
    check_golden("fig3_5_materials", image)
    scene = SCENES["fig3_5_materials"]()
    origin, d = camera_rays(scene.camera)
    dist = {s.name: sphere_miss_distance(origin, d, s.center, s.radius) for s in scene.spheres + scene.bubbles}
    outside = np.min(list(dist.values()), axis=0) > 1.02
    assert (image[outside] == 0).all()  # black environment
    glass = image[dist["стеклянная_розовая"] < 0.95]
    metal = image[dist["металлическая_серая"] < 0.95]
    matte = image[dist["матовая_фиолетовая"] < 0.95]
    for disc in (glass, metal, matte):
        assert len(disc) >= 20 and (disc.max(axis=1) > 0).all()  # every sphere has ka > 0 and Ia = 1
    # colours from the materials: pink 255 180 200 (red first), purple 140 60 200 (green last)
    assert (glass[:, 0] > glass[:, 1]).all() and (glass[:, 0] > glass[:, 2]).all()
    assert (matte[:, 2] > matte[:, 0]).all() and (matte[:, 0] > matte[:, 1]).all()
    # the matte sphere has ks = kt = 0: shaded (ambient plus diffuse), with no highlight above
    # ka + kd = 1.1 times its colour
    purple = srgb8_to_linear([140, 60, 200])
    assert matte[:, 2].max() <= 1.1 * purple[2] + 0.01
    assert matte[:, 2].min() >= 0.2 * purple[2] - 0.01
    # grey metal at its centre facing the camera reflects the black space behind it: grey
    metal_dist = dist["металлическая_серая"]
    centre = metal[np.argmin(metal_dist[metal_dist < 0.95])]
    assert np.ptp(centre) < 0.01 * centre.max() and centre.max() > 0


def test_builtin_scene():
    """The built-in scene.  Its golden image moved twice in the tracer-core rewrite, both times
    on purpose (tests/data/README.md): cut branches began to end with the environment instead of
    being dropped (brighter rims, nothing darker), and chords began to meet their ends at their
    exact starting cosine (changes below 1e-6)."""
    image = rendered("builtin")
    check_golden("builtin", image)
    scene = SCENES["builtin"]()
    assert np.isfinite(image).all()
    origin, d = camera_rays(scene.camera)
    nearest = np.min([sphere_miss_distance(origin, d, b.center, b.radius) for b in scene.bubbles], axis=0)
    outside, on_film = nearest > 1.02, nearest < 0.98
    assert outside.sum() > 100 and on_film.sum() > 100
    # the same scene without its bubbles: where no bubble is in the way the pixel is unchanged,
    # where one is, the film reflects or tints what is behind it
    empty = tracer.render(dataclasses.replace(scene, bubbles=[]), spectral=True, **SETTINGS)
    np.testing.assert_array_equal(image[outside], empty[outside])
    changed = np.abs(image[on_film] - empty[on_film]).max(axis=1) > 1e-3
    assert changed.mean() > 0.9
    # the environment: daylight sky above the horizon (blue over red), a ground darker than
    # the horizon below; only directions at least 3 degrees from the horizon are judged
    up = np.asarray(scene.environment.up, float)
    elevation = d @ (up / np.linalg.norm(up))
    sky = outside & (elevation > 0.05)
    ground = outside & (elevation < -0.05)
    assert sky.sum() + ground.sum() > 100
    assert (image[sky][:, 2] > image[sky][:, 0]).all()
    assert (image[ground] < 0.5).all() and (image[ground] > 0).all()
    # thin-film interference: the films show every hue, not a tint of the surroundings
    dominant = np.bincount(image[on_film].argmax(axis=1), minlength=3)
    assert (dominant >= 5).all(), dominant
