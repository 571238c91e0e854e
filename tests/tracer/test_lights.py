"""Lights: inverse-square falloff in physical units, spherical area lights and their soft shadows.

The answers come from outside the renderer: the irradiance of a point source, E = I cos θ / r²;
the view factor of a sphere entirely above a surface's horizon, E = π L sin²α cos θ (so a
sphere light there acts exactly as a point light at its centre); the penumbra of a spherical
occluder, computed here by a quadrature over the light's surface (an integral over area, not
over the cone of directions the renderer samples) and, more loosely, by the overlap of two
flat discs.  Every scene is a white Lambertian floor (diffuse 1, no ambient or specular term,
so a floor pixel is its direct light only) under a black environment, in RGB transport.
"""

import math
import re

import numba
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import tracer
from tracer import Bubble, Camera, Environment, FilmProfile, Material, Mesh, PointLight, Scene, Sphere
from tracer.scene.errors import SceneError
from tracer.prepare.pack import pack_scene
from tracer.kernels.sampling import camera_ray, cone_sample, orthonormal_basis, stratified_square
from tracer.scene import MAX_LIGHT_SAMPLES
from tracer.scene.toml_read import load_toml_scene, parse_toml_text
from tracer.scene.toml_write import scene_to_toml_text

WHITE = Material(name="white", color=(1.0, 1.0, 1.0), ambient=0.0, diffuse=1.0, specular=0.0)
BLACK = Environment(kind="constant", color=(0.0, 0.0, 0.0))
OPAQUE = Material(name="occluder", color=(0.5, 0.5, 0.5), ambient=0.0, diffuse=0.0, specular=0.0)


def floor(half=20.0):
    v = np.array([[-half, 0.0, -half], [half, 0.0, -half], [half, 0.0, half], [-half, 0.0, half]])
    return Mesh(vertices=v, faces=np.array([[0, 2, 1], [0, 3, 2]]), material=WHITE, name="floor")


def floor_scene(lights, spheres=(), camera=None):
    return Scene(spheres=list(spheres), meshes=[floor()], lights=list(lights),
                 camera=camera or Camera(position=(0.0, 6.0, 0.0), look_at=(0.0, 0.0, 0.0), up=(0.0, 0.0, -1.0),
                                         fov_deg=60.0),
                 environment=BLACK, ambient=(0.0, 0.0, 0.0))


def render(scene, width, height, **kw):
    kw = dict(depth=2, threshold=0.0, spectral=False, progress=False) | kw
    return tracer.render(scene, width=width, height=height, **kw)


def floor_points(scene, width, height):
    """Where each pixel-centre camera ray meets the floor y = 0 (H, W, 3), NaN where it does not
    (the pinhole model of tracer.kernels.sampling.camera_ray, the plane intersected here)."""
    cam = pack_scene(scene).camera[0]
    o = np.asarray(cam["origin"], float)
    out = np.full((height, width, 3), np.nan)
    for y in range(height):
        for x in range(width):
            d = np.array(camera_ray(cam, x + 0.5, y + 0.5, width, height))
            if d[1] < 0:
                out[y, x] = o - o[1] / d[1] * d
    return out


def sees_floor(scene, pts):
    """Pixels whose camera ray reaches the floor before any sphere of the scene."""
    o = np.asarray(scene.camera.position, float)
    ok = np.isfinite(pts[..., 0])
    for s in scene.spheres:
        c = np.asarray(s.center, float)
        v = pts - o
        dist = np.linalg.norm(v, axis=-1)
        d = v / dist[..., None]
        b = (d * (c - o)).sum(-1)
        disc = b * b - (np.sum((c - o) ** 2) - s.radius**2)
        ok &= ~((disc > 0) & (b - np.sqrt(np.abs(disc)) < dist))
    return ok


def point_light_radiance(pts, centre, intensity, falloff):
    """A white Lambertian floor's radiance from a point source (nothing in between):
    kd/π · E with E = I cos θ / r² ("inverse_square"), or I cos θ ("none": the coursework's
    unattenuated light, whose intensity is already the radiance of a white surface facing it)."""
    v = np.asarray(centre, float) - pts
    r = np.linalg.norm(v, axis=-1)
    cos = np.clip(v[..., 1] / r, 0.0, None)
    return intensity * cos / (math.pi * r**2) if falloff == "inverse_square" else intensity * cos


# ------------------------------------------------------------------------------------------
# Inverse-square falloff
# ------------------------------------------------------------------------------------------
@pytest.mark.analytic
def test_inverse_square_radiance_quarters_when_the_distance_doubles():
    """The floor straight below a point light of intensity I (W/sr) at height h has irradiance
    I / h², so a white Lambertian floor has radiance I / (π h²): a quarter at 2h."""
    values = []
    for h in (1.5, 3.0, 6.0):
        scene = floor_scene([PointLight((0.0, h, 0.0), 7.0, falloff="inverse_square")])
        img = render(scene, 1, 1)  # the one pixel's ray is the camera's axis: it meets (0, 0, 0)
        np.testing.assert_allclose(img[0, 0], 7.0 / (math.pi * h * h), rtol=1e-12)
        values.append(img[0, 0, 0])
    np.testing.assert_allclose(values[0] / values[1], 4.0, rtol=1e-12)
    np.testing.assert_allclose(values[1] / values[2], 4.0, rtol=1e-12)


@pytest.mark.analytic
@pytest.mark.parametrize("falloff", ["none", "inverse_square"])
def test_point_light_on_a_plane_follows_the_cosine_law(falloff):
    """Every floor pixel: I cos θ / (π r²) with inverse-square falloff, I cos θ without."""
    centre = (0.7, 2.5, -0.4)
    scene = floor_scene([PointLight(centre, 3.0, color=(1.0, 1.0, 1.0), falloff=falloff)])
    img = render(scene, 17, 13)
    pts = floor_points(scene, 17, 13)
    assert np.isfinite(pts).all()
    expected = point_light_radiance(pts, centre, 3.0, falloff)
    np.testing.assert_allclose(img, np.repeat(expected[..., None], 3, axis=-1), rtol=1e-10, atol=1e-14)


@pytest.mark.regression
def test_unattenuated_lights_are_the_default_and_the_coursework_files_keep_them():
    """The coursework's lights and the TOML files in data/scenes do not dim with distance
    (the goldens, tests/tracer/test_golden.py, pin their images)."""
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    assert PointLight((0, 0, 0)).falloff == "none" and PointLight((0, 0, 0)).radius == 0.0
    for path in [*(root / "data" / "scenes").glob("*.toml"), *(root / "data" / "scenes").glob("*.txt"),
                 *(root / "data" / "coursework_scenes").glob("*.txt")]:
        for light in tracer.load_scene(path).lights:
            assert (light.falloff, light.radius) == ("none", 0.0), path


# ------------------------------------------------------------------------------------------
# Spherical lights: the analytic limits
# ------------------------------------------------------------------------------------------
@pytest.mark.analytic
@pytest.mark.parametrize("falloff", ["none", "inverse_square"])
def test_a_sphere_light_above_the_horizon_lights_like_a_point_at_its_centre(falloff):
    """The Lambertian sphere theorem: a sphere of radiance L_e entirely above a surface's
    horizon gives it E = π L_e sin²α cos θ = I cos θ / d², I = π a² L_e, exactly the point
    light's (here a = 1 at d from 2 to 5: α up to 30 degrees).  The renderer's estimate is a
    stratified mean over the cone, exact only in the limit; for this smooth integrand its
    error falls as 1/N (measured: a relative spread of 6e-3, 1.4e-3 and 3.5e-4 at 64, 256 and
    1024 samples), so: within 3e-3 per pixel with 1024 samples, and unbiased, the mean over
    the 225 pixels within 3e-4 (20 standard errors)."""
    centre = (0.3, 2.0, -0.2)
    point = floor_scene([PointLight(centre, 2.0, falloff=falloff)])
    sphere = floor_scene([PointLight(centre, 2.0, falloff=falloff, radius=1.0, samples=MAX_LIGHT_SAMPLES)])
    a = render(point, 15, 15)
    b = render(sphere, 15, 15)
    pts = floor_points(point, 15, 15)
    np.testing.assert_allclose(a[..., 0], point_light_radiance(pts, centre, 2.0, falloff), rtol=1e-10)
    np.testing.assert_allclose(b, a, rtol=3e-3)
    assert abs(np.mean(b / a - 1.0)) < 3e-4


@pytest.mark.analytic
@pytest.mark.parametrize("falloff", ["none", "inverse_square"])
def test_radius_zero_is_exactly_the_point_light_and_small_radii_converge_to_it(falloff):
    """Radius 0 is the point light bit for bit (the sample count is then unused), and a small
    sphere converges to it linearly in its radius (the sample directions are off the centre's
    by up to α = a / d), with occluders, a glossy sphere and a bubble's highlight in the
    picture: at α ≈ 1e-6 the image is within 1e-5 of the point light's (relative to its
    brightest pixel), and 100 times nearer than at α ≈ 1e-4."""
    def scene(radius, samples):
        return Scene(
            spheres=[Sphere((0.0, 0.6, 0.0), 0.5, Material(color=(0.9, 0.5, 0.2), ambient=0.0, diffuse=0.7,
                                                            specular=0.3, shininess=40.0))],
            bubbles=[Bubble((-1.1, 0.7, 0.3), 0.5, FilmProfile("uniform", thickness_nm=420.0))],
            meshes=[floor()],
            lights=[PointLight((1.0, 3.0, 1.5), 4.0, falloff=falloff, radius=radius, samples=samples)],
            camera=Camera(position=(0.0, 2.0, 5.0), look_at=(0.0, 0.5, 0.0), fov_deg=40.0),
            environment=Environment(kind="constant", color=(0.1, 0.1, 0.15)), ambient=(0.0, 0.0, 0.0))

    kw = dict(depth=4, threshold=0.0, progress=False)
    base = tracer.render(scene(0.0, 16), width=24, height=24, **kw)
    assert np.array_equal(tracer.render(scene(0.0, 64), width=24, height=24, **kw), base)
    small = np.abs(tracer.render(scene(3.5e-4, 16), width=24, height=24, **kw) - base).max()
    tiny = np.abs(tracer.render(scene(3.5e-6, 16), width=24, height=24, **kw) - base).max()
    assert 0 < tiny <= 1e-5 * np.abs(base).max()  # sampled (not a point), and close
    assert 70 < small / tiny < 130, small / tiny


def light_surface_quadrature(p, centre, radius, occluders, n=300):
    """∫ V cos θ_p dω over the light sphere seen from the floor point *p*, as an integral over
    the sphere's surface: Σ cos θ_p cos θ_y / |y − p|² dA over the cap of the sphere that faces
    p (the points y with (y − c)·(p − c) >= a², the only ones p sees) and is not hidden by the
    occluding spheres; midpoint rule in (z, φ) around the cap's axis (dA = a² dz dφ)."""
    c = np.asarray(centre, float)
    u = (p - c) / np.linalg.norm(p - c)
    helper = np.array([1.0, 0.0, 0.0]) if abs(u[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(u, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(u, e1)
    z_min = radius / np.linalg.norm(p - c)
    z = z_min + (np.arange(n) + 0.5) / n * (1.0 - z_min)
    phi = (np.arange(2 * n) + 0.5) / (2 * n) * 2.0 * math.pi
    Z, PHI = np.meshgrid(z, phi, indexing="ij")
    s = np.sqrt(1.0 - Z * Z)
    nrm = (s * np.cos(PHI))[..., None] * e1 + (s * np.sin(PHI))[..., None] * e2 + Z[..., None] * u
    y = c + radius * nrm
    v = y - p
    r2 = (v * v).sum(-1)
    r = np.sqrt(r2)
    w = v / r[..., None]
    cos_y = -(w * nrm).sum(-1)
    cos_p = w[..., 1]
    ok = (cos_y > 0) & (cos_p > 0)
    for oc_centre, rad in occluders:
        oc = np.asarray(oc_centre, float) - p
        b = (w * oc).sum(-1)
        disc = b * b - (oc @ oc - rad * rad)
        root = np.sqrt(np.abs(disc))
        ok &= ~((disc > 0) & (b + root > 0) & (b - root < r))
    dA = radius * radius * ((1.0 - z_min) / n) * (2.0 * math.pi / (2 * n))
    return float(np.sum(np.where(ok, cos_p * cos_y / r2, 0.0)) * dA)


def lens_fraction_visible(alpha, beta, gamma):
    """The part of a disc of radius alpha left uncovered by a disc of radius beta whose centre
    is gamma away (the flat picture of two small cones: light and occluder)."""
    if gamma >= alpha + beta:
        return 1.0
    if gamma <= abs(beta - alpha):
        return 0.0 if beta >= alpha else 1.0 - (beta / alpha) ** 2
    a2, b2, g2 = alpha * alpha, beta * beta, gamma * gamma
    lens = (a2 * math.acos((g2 + a2 - b2) / (2 * gamma * alpha)) + b2 * math.acos((g2 + b2 - a2) / (2 * gamma * beta))
            - 0.5 * math.sqrt((-gamma + alpha + beta) * (gamma + alpha - beta) * (gamma - alpha + beta)
                              * (gamma + alpha + beta)))
    return 1.0 - lens / (math.pi * a2)


@pytest.mark.reference
def test_the_penumbra_of_a_sphere_matches_an_independent_quadrature_and_the_disc_overlap():
    """A sphere light (radius 0.4 at height 4) above an opaque ball (radius 0.5 at height 2):
    along a line across the ball's shadow on the floor (umbra, penumbra, full light) each
    pixel's radiance is kd/π · L_e ∫ V cos θ dω, L_e = I / (π a²).  Reference: the integral
    over the light's surface (:func:`light_surface_quadrature`), agreed with to 1.5 % of the
    unshadowed value per pixel and 0.2 % on average (the renderer's 1024 stratified samples:
    0.4 % and 3e-5 measured; the quadrature itself moves by less than 0.1 % from 150 to 600
    points a side).  The fraction of the light visible also matches the overlap of two flat
    discs of angular radii α and β at the centres' angular distance γ, to 2 % (0.9 % measured:
    the discs are a small-angle picture of the two cones, and cos θ varies across the light)."""
    centre, a, intensity = (0.0, 4.0, 0.0), 0.4, 9.0
    ball = (0.0, 2.0, 0.0), 0.5
    width = 41  # one row of pixels from x = 0.3 to 2.3 on the floor
    camera = Camera(position=(1.3, 6.0, 0.0), look_at=(1.3, 0.0, 0.0), up=(0.0, 0.0, -1.0),
                    fov_deg=2 * math.degrees(math.atan(1.0 / 6.0 / width)))
    scene = floor_scene([PointLight(centre, intensity, falloff="inverse_square", radius=a, samples=MAX_LIGHT_SAMPLES)],
                        spheres=[Sphere(*ball, OPAQUE, name="ball")], camera=camera)
    img = render(scene, width, 1)[0, :, 0]
    pts = floor_points(scene, width, 1)[0]
    ok = sees_floor(scene, pts[None])[0]
    assert ok.sum() > 30
    L_e = intensity / (math.pi * a * a)
    unshadowed = point_light_radiance(pts, centre, intensity, "inverse_square")  # the sphere theorem
    quad = np.array([L_e / math.pi * light_surface_quadrature(p, centre, a, [ball]) for p in pts])
    visible = quad / unshadowed
    assert visible[ok].min() < 0.01 and visible[ok].max() > 0.99  # umbra and full light are in view
    assert np.sum((visible[ok] > 0.05) & (visible[ok] < 0.95)) >= 8  # and a resolved penumbra
    err = (img - quad)[ok] / unshadowed[ok]
    assert np.abs(err).max() < 0.015, err
    assert abs(err.mean()) < 0.002, err.mean()
    # the flat picture: two discs
    for p, v, seen in zip(pts, img / unshadowed, ok):
        if not seen:
            continue
        to_l = np.asarray(centre) - p
        to_b = np.asarray(ball[0]) - p
        alpha = math.asin(a / np.linalg.norm(to_l))
        beta = math.asin(ball[1] / np.linalg.norm(to_b))
        gamma = math.acos(np.clip(to_l @ to_b / (np.linalg.norm(to_l) * np.linalg.norm(to_b)), -1, 1))
        assert abs(v - lens_fraction_visible(alpha, beta, gamma)) < 0.02, (p, v)


@pytest.mark.analytic
@pytest.mark.parametrize("falloff", ["none", "inverse_square"])
def test_a_point_inside_or_on_the_light_is_lit_from_its_whole_hemisphere(falloff):
    """A floor point inside the light's sphere sees radiance L_e over its whole upper
    hemisphere: E = π L_e, radiance kd L_e (L_e = I / (π a²) with inverse-square falloff, the
    strength I itself without).  At the centre (d = 0), just inside and exactly on the sphere
    (d = a), nothing is NaN; inside, the estimate is within 1 % with 1024 samples."""
    a, intensity = 0.5, 2.0
    L_e = intensity / (math.pi * a * a) if falloff == "inverse_square" else intensity
    for height in (0.0, 0.2, 0.499999, 0.5):
        scene = floor_scene([PointLight((0.0, height, 0.0), intensity, falloff=falloff, radius=a,
                                        samples=MAX_LIGHT_SAMPLES)])
        img = render(scene, 1, 1)
        assert np.isfinite(img).all()
        if height < a:
            np.testing.assert_allclose(img[0, 0], L_e, rtol=0.01)
    # a whole floor cut by the sphere: finite everywhere, and continuous across its rim
    scene = floor_scene([PointLight((0.0, 0.3, 0.0), intensity, falloff=falloff, radius=a, samples=256)])
    img = render(scene, 31, 31)
    assert np.isfinite(img).all() and img.min() >= 0.0


@pytest.mark.property
@settings(max_examples=40)
@given(cx=st.floats(-2, 2), cy=st.floats(-1, 3), radius=st.floats(0, 3), samples=st.integers(1, 40),
       falloff=st.sampled_from(["none", "inverse_square"]))
def test_any_sphere_light_gives_a_finite_non_negative_image(cx, cy, radius, samples, falloff):
    """Anywhere (below the floor, through it, around the ball), any radius (subnormal ones
    too) and sample count: finite, non-negative pixels, and none above 4 S_max, the most the
    estimate can give (its weight 2 / (1 + cos α) is at most 4, inside the light; S_max is the
    strength I without falloff and I / (π a²), at the sphere, with it)."""
    scene = floor_scene([PointLight((cx, cy, 0.1), 1.0, falloff=falloff, radius=radius, samples=samples)],
                        spheres=[Sphere((0.2, 0.5, 0.0), 0.3, OPAQUE)])
    img = render(scene, 6, 6)
    assert np.isfinite(img).all() and img.min() >= 0.0
    if radius > 1e-100:
        strength = 1.0 / (math.pi * radius**2) if falloff == "inverse_square" else 1.0
        assert img.max() <= 4.0 * strength * (1 + 1e-12)


@pytest.mark.property
@pytest.mark.parametrize("centre, radius", [((0.0, 2.0, 0.0), 1e15), ((0.0, 1e15, 0.0), 1.0),
                                            ((1e15, 1e15, 0.0), 1e14), ((0.0, 2.0, 0.0), 5e-324)])
@pytest.mark.parametrize("falloff", ["none", "inverse_square"])
def test_extreme_sphere_lights_give_finite_images(centre, radius, falloff):
    """Radii and distances at the limits of a scene (tracer.scene.limits.MAX_MAGNITUDE = 1e15) and a
    subnormal radius: finite, non-negative pixels (inside a huge light, its shadow rays are
    long; a subnormal one lights nothing)."""
    scene = floor_scene([PointLight(centre, 1.0, falloff=falloff, radius=radius, samples=4)],
                        spheres=[Sphere((0.2, 0.5, 0.0), 0.3, OPAQUE)])
    img = render(scene, 5, 5)
    assert np.isfinite(img).all() and img.min() >= 0.0


@pytest.mark.api
@pytest.mark.parametrize("centre, radius", [((0.0, 2.0, 0.0), 1e200), ((0.0, 1e300, 0.0), 1.0)])
def test_lights_beyond_the_scene_limits_are_refused(centre, radius):
    scene = floor_scene([PointLight(centre, 1.0, radius=radius, samples=4)], spheres=[])
    with pytest.raises(ValueError, match=r"light 1 (position|radius).*within -1e\+15 to 1e\+15"):
        render(scene, 5, 5)


# ------------------------------------------------------------------------------------------
# Sampling: stratified, deterministic
# ------------------------------------------------------------------------------------------
@pytest.mark.property
@given(n=st.integers(1, MAX_LIGHT_SAMPLES), key=st.integers(0, 2**64 - 1), stream=st.integers(0, 2**40))
def test_stratified_square_puts_one_point_in_each_of_n_equal_strata(n, key, stream):
    """Strata: m = floor(sqrt(n)) rows, the first n mod m of them with one stratum more, each
    row as tall as its share; every point lies in [0, 1)² and in its own stratum."""
    m = math.isqrt(n)
    q, r = divmod(n, m)
    counts = [q + 1] * r + [q] * (m - r)
    edges = np.concatenate([[0], np.cumsum(counts)]) / n
    seen = set()
    for k in range(n):
        u1, u2 = stratified_square(np.uint64(key), stream, k, n)
        assert 0.0 <= u1 < 1.0 and 0.0 <= u2 < 1.0
        row = int(np.searchsorted(edges, u1, side="right")) - 1
        col = int(u2 * counts[row])
        seen.add((row, col))
    assert len(seen) == n


@pytest.mark.property
@given(ax=st.floats(-1, 1), ay=st.floats(-1, 1), az=st.floats(-1, 1), s2=st.floats(1e-12, 1.0),
       n=st.integers(1, 64))
def test_cone_samples_lie_in_the_cone(ax, ay, az, s2, n):
    """Every sample direction is a unit vector within the cone (cos of its angle to the axis
    at least cos α), for cones from 1e-6 rad to the hemisphere; and the frame is orthonormal."""
    a = np.array([ax, ay, az])
    if np.linalg.norm(a) < 1e-3:
        a = np.array([0.0, 0.0, 1.0])
    a /= np.linalg.norm(a)
    axis = tuple(a)
    b1, b2 = orthonormal_basis(axis)
    frame = np.array([b1, b2, axis])
    np.testing.assert_allclose(frame @ frame.T, np.eye(3), atol=1e-12)
    assert np.linalg.det(frame) > 0
    cos_a = math.sqrt(1.0 - s2)
    omc = s2 / (1.0 + cos_a)
    for k in range(n):
        w = np.array(cone_sample(np.uint64(7), 3, k, n, axis, b1, b2, omc))
        assert abs(np.linalg.norm(w) - 1.0) < 1e-12
        assert w @ a >= cos_a - 1e-12


def soft_shadow_bubble_scene():
    return Scene(
        spheres=[Sphere((0.6, 0.5, 0.0), 0.5, Material(color=(0.2, 0.5, 0.9), ambient=0.05, diffuse=0.8,
                                                        specular=0.4, shininess=30.0))],
        bubbles=[Bubble((-0.6, 0.6, 0.2), 0.5, FilmProfile("draining", top_nm=80.0, bottom_nm=700.0, swirl=0.2))],
        meshes=[floor()],
        lights=[PointLight((1.5, 3.0, 2.0), 30.0, falloff="inverse_square", radius=0.6, samples=9),
                PointLight((-2.0, 2.5, 1.0), 0.3)],
        camera=Camera(position=(0.0, 1.8, 4.0), look_at=(0.0, 0.4, 0.0), fov_deg=45.0),
        environment=Environment(kind="sky"), ambient=(0.0, 0.0, 0.0))


@pytest.mark.regression
def test_sphere_light_images_are_the_same_every_run_and_on_any_thread_count():
    """The light samples are a hash of the camera sample, the point's place in the ray tree, the
    light and the sample: the same image twice, and on one thread as on two."""
    scene = soft_shadow_bubble_scene()
    kw = dict(width=20, height=16, depth=4, spp=2, progress=False)
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = tracer.render(scene, **kw)
        numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))
        two = tracer.render(scene, **kw)
        again = tracer.render(scene, **kw)
    finally:
        numba.set_num_threads(before)
    assert np.array_equal(one, two) and np.array_equal(two, again)
    assert np.isfinite(one).all()


@pytest.mark.property
def test_another_seed_gives_other_light_samples_even_at_one_sample_per_pixel():
    """At spp = 1 the camera ray is the pixel centre whatever the seed; the light samples
    still follow the seed (tracer.kernels.sampling.sample_key), so the penumbra's noise changes while
    the fully lit and fully shadowed pixels do not."""
    scene = soft_shadow_bubble_scene()
    kw = dict(width=20, height=16, depth=4, spp=1, progress=False)
    a, b = tracer.render(scene, seed=1, **kw), tracer.render(scene, seed=2, **kw)
    differs = np.any(a != b, axis=-1)
    assert 0 < differs.sum() < differs.size


@pytest.mark.analytic
def test_a_sphere_light_never_darkens_a_pixel_and_its_highlights_spread():
    """Light adds (per band: luminance is a non-negative sum of bands): the scene with the
    sphere light added is nowhere darker.  A bigger light spreads the Phong and film highlights
    over more pixels (each sample direction has its own mirror lobe)."""
    from scene_geometry import luminance  # tests/support/scene_geometry.py

    scene = soft_shadow_bubble_scene()
    kw = dict(width=32, height=24, depth=4, threshold=0.0, spectral=True, progress=False)
    lit = luminance(tracer.render(scene, **kw))
    scene.lights = scene.lights[1:]
    unlit = luminance(tracer.render(scene, **kw))
    assert np.all(lit >= unlit - 1e-12) and np.any(lit > unlit + 1e-3)

    def highlight_pixels(radius):
        glossy = Material(color=(1.0, 1.0, 1.0), ambient=0.0, diffuse=0.0, specular=1.0, shininess=200.0)
        s = soft_shadow_bubble_scene()
        s.spheres[0].material = glossy
        s.lights = [PointLight((1.5, 3.0, 2.0), 1.0, radius=radius, samples=64)]
        s.meshes = []
        s.environment = BLACK
        return np.sum(luminance(tracer.render(s, **kw)) > 1e-3)

    point, sphere = highlight_pixels(0.0), highlight_pixels(0.8)
    assert point > 0 and sphere > 2 * point, (point, sphere)


# ------------------------------------------------------------------------------------------
# Scene files and the Python API
# ------------------------------------------------------------------------------------------
MINIMAL = "[[spheres]]\ncenter = [0, 0, 0]\nradius = 1\n\n"


@pytest.mark.api
def test_toml_lights_read_their_keys():
    scene = parse_toml_text(MINIMAL + """[[lights]]
position = [1, 2, 3]
falloff = "inverse_square"
power = 100.0
radius = 0.25
samples = 36

[[lights]]
position = [0, 5, 0]
intensity = 0.5
color = "#ffffff"
""")
    physical, plain = scene.lights
    assert physical == PointLight((1.0, 2.0, 3.0), 100.0 / (4 * math.pi), (1.0, 1.0, 1.0), 0.25, "inverse_square", 36)
    assert plain == PointLight((0.0, 5.0, 0.0), 0.5)


BAD_LIGHTS = {
    "falloff": ('falloff = "quadratic"', 7, "lights[0].falloff: must be one of 'none', 'inverse_square', got 'quadratic'"),
    "radius": ("radius = -0.5", 7, "lights[0].radius: must be >= 0, got -0.5"),
    "radius type": ('radius = "big"', 7, "lights[0].radius: must be a number, got a string"),
    "samples zero": ("radius = 1\nsamples = 0", 8, f"lights[0].samples: must be an integer from 1 to {MAX_LIGHT_SAMPLES}, got 0"),
    "samples big": ("samples = 100000", 7, f"lights[0].samples: must be an integer from 1 to {MAX_LIGHT_SAMPLES}, got 100000"),
    "samples float": ("samples = 4.0", 7, "lights[0].samples: must be an integer from 1 to 1024, got 4.0"),
    "samples bool": ("samples = true", 7, "lights[0].samples: must be an integer from 1 to 1024, got True"),
    "power without falloff": ("power = 60", 7, 'lights[0].power: a power in watts needs falloff = "inverse_square"'),
    "power and intensity": ('falloff = "inverse_square"\nintensity = 1\npower = 60', 9,
                            "lights[0].power: give either 'intensity' (W/sr) or 'power' (W), not both"),
    "negative power": ('falloff = "inverse_square"\npower = -1', 8, "lights[0].power: must be >= 0, got -1"),
    "typo": ("radus = 1", 7, "unknown key 'radus' in [[lights]]; did you mean 'radius'?"),
}


@pytest.mark.api
@pytest.mark.parametrize("case", sorted(BAD_LIGHTS))
def test_bad_toml_lights_are_one_line_errors_at_their_key(case):
    body, line, message = BAD_LIGHTS[case]
    text = MINIMAL + "[[lights]]\nposition = [0, 5, 0]\n" + body + "\n"
    with pytest.raises(SceneError) as exc:
        parse_toml_text(text, "s.toml")
    assert exc.value.line == line, str(exc.value)
    assert str(exc.value).startswith(f"s.toml:{line}: {message}"), str(exc.value)
    assert "\n" not in str(exc.value)


@pytest.mark.api
def test_inverse_square_lights_need_a_scene_in_metres():
    text = '[scene]\nunit = "cm"\n\n' + MINIMAL + '[[lights]]\nposition = [0, 5, 0]\nfalloff = "inverse_square"\n'
    with pytest.raises(SceneError, match=re.escape("s.toml:10: lights[0].falloff: 'inverse_square' takes lengths in "
                                                   "metres, but [scene] unit is 'cm'")):
        parse_toml_text(text, "s.toml")
    parse_toml_text(text.replace('"cm"', '"m"'), "s.toml")
    scene = parse_toml_text(text.replace('"cm"', '"m"'))
    with pytest.raises(ValueError, match="inverse-square falloff takes lengths in metres"):
        scene_to_toml_text(scene, unit="cm")


@pytest.mark.api
def test_lights_round_trip_through_the_toml_writer(tmp_path):
    scene = soft_shadow_bubble_scene()
    scene.lights.append(PointLight((0.1, 0.2, 0.3), 1e-3 / 3, (0.9, 0.8, 0.7), 1 / 7, "none", 1024))
    path = tmp_path / "lights.toml"
    text = scene_to_toml_text(scene, path)
    path.write_text(text, encoding="utf-8")
    back = load_toml_scene(path)
    assert back.lights == scene.lights
    # a point light is written as a coursework light: no falloff, radius or samples keys
    plain = Scene(spheres=[Sphere((0, 0, 0), 1.0)], lights=[PointLight((0.0, 5.0, 0.0), 0.5)])
    lights_text = scene_to_toml_text(plain).split("[[lights]]")[1]
    assert not any(key in lights_text for key in ("falloff", "radius", "samples"))


@pytest.mark.api
@pytest.mark.parametrize("change, message", [
    (dict(radius=-1.0), "light 1: radius must be a finite number >= 0"),
    # non-finite numbers: the scene-limits check (tracer.prepare.pack.check_magnitudes) comes first
    (dict(radius=float("nan")), "light 1 radius: nan is not a finite number"),
    (dict(samples=0), f"light 1: samples must be an integer in 1..{MAX_LIGHT_SAMPLES}"),
    (dict(samples=2.5), f"light 1: samples must be an integer in 1..{MAX_LIGHT_SAMPLES}"),
    (dict(falloff="linear"), "light 1: falloff must be one of 'none', 'inverse_square'"),
    (dict(intensity=float("inf")), "light 1 intensity: inf is not a finite number"),
])
def test_python_lights_the_renderer_cannot_use_are_refused(change, message):
    scene = floor_scene([PointLight((0.0, 2.0, 0.0), **({"intensity": 1.0} | change))])
    with pytest.raises(ValueError, match=re.escape(message)):
        tracer.render(scene, width=2, height=2, progress=False)


@pytest.mark.api
def test_the_documented_soft_shadow_example_loads_and_its_picture_script_runs(tmp_path):
    """docs/scene-format.md's lights example is a valid scene (a spherical light in watts), and
    docs/images/make_soft_shadow.py renders it (quick mode) into a two-panel PNG."""
    import importlib.util
    from pathlib import Path

    from PIL import Image

    script = Path(__file__).resolve().parents[2] / "docs" / "images" / "make_soft_shadow.py"
    spec = importlib.util.spec_from_file_location("make_soft_shadow", script)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    scene = parse_toml_text(module.example_toml())
    (light,) = scene.lights
    assert light.falloff == "inverse_square" and light.radius > 0 and light.samples > 1
    np.testing.assert_allclose(light.intensity, 80.0 / (4 * math.pi))
    out = tmp_path / "soft.png"
    module.main(["--quick", "--out", str(out)])
    w, h = scene.render_defaults["width"] // 4, scene.render_defaults["height"] // 4
    with Image.open(out) as img:
        assert img.size[1] == h and img.size[0] > 2 * w
