"""Renderer tests with analytic answers (pbrt-style: an answer known without the renderer)."""

import math

import numpy as np
import pytest

import tracer
from scene_geometry import incidence_cosines, luminance  # tests/support/scene_geometry.py
from tracer.kernels.environment import environment_rgb
from tracer.scene import Bubble, Camera, Environment, FilmProfile, Material, PointLight, Scene, Sphere

SMALL = dict(width=24, height=24, progress=False)


def bubble_scene(thickness_nm=400.0, env=None, lights=(), n_film=1.333, **kw):
    return Scene(
        bubbles=[Bubble((0.0, 0.0, 0.0), 1.0, FilmProfile("uniform", thickness_nm=thickness_nm), n_film=n_film)],
        lights=list(lights),
        camera=Camera(position=(0.0, 0.0, 4.0), look_at=(0.0, 0.0, 0.0), fov_deg=40.0),
        environment=env or Environment(kind="constant", color=(0.3, 0.5, 0.7)),
        ambient=(0.0, 0.0, 0.0),
        **kw,
    )


@pytest.mark.analytic
@pytest.mark.parametrize("thickness", [0.0, 120.0, 450.0, 3000.0])
def test_lossless_bubble_in_uniform_environment_is_invisible(thickness):
    """R + T = 1 for a lossless film, and every escaping ray sees the same colour: the image
    equals the environment.  Only the truncation of the inner bounces loses light: a sphere
    keeps the angle of incidence, so a path inside loses R^(depth-1); where cos(theta) > 0.6,
    a water film reflects at most 4 R01/(1 + R01)^2 < 0.13 and the loss is below 1e-16 at
    depth 20.  Nowhere is the bubble brighter."""
    scene = bubble_scene(thickness)
    img = tracer.render(scene, depth=20, threshold=0.0, **SMALL)
    target = tracer.render(Scene(camera=scene.camera, environment=scene.environment), spectral=True, **SMALL)
    assert np.ptp(target.reshape(-1, 3), axis=0).max() < 1e-12  # the environment itself is uniform
    cosines = incidence_cosines(scene, SMALL["width"], SMALL["height"])
    steep = cosines > 0.6
    assert steep.sum() > 100
    np.testing.assert_allclose(img[steep], target[steep], rtol=0, atol=1e-10)
    # energy is conserved per wavelength band; luminance Y is a non-negative sum of bands
    # (the RGB channels are not: XYZ -> sRGB has negative coefficients)
    assert np.all(luminance(img) <= luminance(target) + 1e-12)
    assert np.all(luminance(img) >= 0.5 * luminance(target))


def matte_scene_with(bubbles=()):
    return Scene(
        spheres=[Sphere((0.0, -0.2, -1.5), 0.8, Material(color=(0.9, 0.4, 0.2), ambient=0.1, diffuse=0.8,
                                                          specular=0.3, shininess=30))],
        bubbles=list(bubbles),
        lights=[PointLight((2.0, 3.0, 4.0), 1.0)],
        camera=Camera(position=(0.0, 0.0, 4.0), look_at=(0.0, 0.0, 0.0), fov_deg=45.0),
        environment=Environment(kind="constant", color=(0.05, 0.05, 0.1)),
        ambient=(1.0, 1.0, 1.0),
    )


@pytest.mark.analytic
def test_zero_thickness_bubble_changes_nothing():
    """A film of zero thickness has R = 0, T = 1 exactly (Airy sum at d = 0, free-standing): the
    image with such a bubble between the camera and a lit sphere, its shadow rays crossing the
    bubble too, equals the image without it (both in spectral mode)."""
    with_bubble = matte_scene_with([Bubble((0.3, 0.2, 1.0), 0.9, FilmProfile("uniform", thickness_nm=0.0))])
    # the light and the sphere are both seen through the bubble
    img_b = tracer.render(with_bubble, depth=6, threshold=0.0, spectral=True, **SMALL)
    img_0 = tracer.render(matte_scene_with(), depth=6, threshold=0.0, spectral=True, **SMALL)
    np.testing.assert_allclose(img_b, img_0, rtol=1e-12, atol=1e-13)
    assert img_0.max() > 0.1


@pytest.mark.analytic
def test_mirror_sphere_shows_exactly_what_it_reflects():
    """A perfect mirror (specular 1, white, no local terms) under the sky: each pixel on the
    sphere equals the environment in the mirror direction, computed here analytically."""
    scene = Scene(
        spheres=[Sphere((0.0, 0.0, 0.0), 1.0, Material(color=(1.0, 1.0, 1.0), ambient=0.0, diffuse=0.0,
                                                        specular=1.0, transmission=0.0))],
        camera=Camera(position=(0.0, 0.0, 5.0), look_at=(0.0, 0.0, 0.0), fov_deg=30.0),
        environment=Environment(kind="sky"),
    )
    w = h = 32
    img = tracer.render(scene, width=w, height=h, depth=2, threshold=0.0, progress=False)
    packed = tracer.prepare.pack.pack_scene(scene)
    cam = packed.camera[0]
    checked = 0
    for y in range(0, h, 3):
        for x in range(0, w, 3):
            d = np.array(tracer.kernels.sampling.camera_ray(cam, x + 0.5, y + 0.5, w, h))
            o = cam["origin"]
            b = o @ d
            disc = b * b - (o @ o - 1.0)
            if disc <= 1e-6:
                continue
            t = -b - math.sqrt(disc)
            n = o + t * d
            r = d - 2 * (d @ n) * n
            expected = environment_rgb(packed.environment[0], packed.env_image, (r[0], r[1], r[2]))
            np.testing.assert_allclose(img[y, x], expected, rtol=1e-9, atol=1e-12)
            checked += 1
    assert checked > 20


def scaled(scene_fn, s, shift):
    sc = scene_fn()
    for obj in sc.spheres + sc.bubbles:
        obj.center = tuple(np.asarray(obj.center) * s + shift)
        obj.radius *= s
    for lt in sc.lights:
        lt.position = tuple(np.asarray(lt.position) * s + shift)
    cam = sc.camera
    cam.position = tuple(np.asarray(cam.position) * s + shift)
    cam.look_at = tuple(np.asarray(cam.look_at) * s + shift)
    return sc


def full_scene():
    sc = matte_scene_with([Bubble((0.3, 0.2, 1.0), 0.9, FilmProfile("draining", top_nm=100, bottom_nm=900))])
    sc.spheres.append(Sphere((-1.2, 0.5, 0.0), 0.5, Material(color=(1, 1, 1), ambient=0, diffuse=0,
                                                              specular=0.1, transmission=0.9, ior=1.5)))
    return sc


@pytest.mark.analytic
@pytest.mark.parametrize("s, shift", [(1e-3, 0.0), (1e3, 0.0), (1.0, 1e5), (1e-3, 1e5)])
def test_scene_scaled_and_shifted_renders_the_same(s, shift):
    """Scaling the whole scene (objects, lights, camera) by 1e-3 or 1e3, or shifting it by 1e5,
    changes no pixel beyond what the coordinates' precision allows: ray offsets are
    proportional to the scene's scale and to its coordinates' magnitude
    (tracer.kernels.geometry.origin_epsilon)."""
    ref = tracer.render(full_scene(), depth=6, threshold=0.0, **SMALL)
    img = tracer.render(scaled(full_scene, s, shift), depth=6, threshold=0.0, **SMALL)
    assert np.isfinite(img).all()
    diff = np.abs(img - ref).max(axis=-1)
    # Shifted by 1e5 at scale 1e-3, coordinates keep ~8 significant digits relative to the
    # scene, so secondary hits move by ~1e-6 of a radius and a steep fringe of the draining
    # film may change a pixel by ~1e-4: allow that there (below one 8-bit display step);
    # scaled or shifted alone, 99 % of the pixels agree to 1e-6.
    assert diff.max() < 1e-3, diff.max()
    if s == 1e-3 and shift:
        assert np.mean(diff > 1e-4) < 0.01
    else:
        assert np.mean(diff > 1e-6) < 0.01, np.argwhere(diff > 1e-6)[:5]


@pytest.mark.analytic
def test_camera_inside_a_bubble_sees_the_environment_through_it():
    """From inside a lossless bubble in a uniform environment, the image is still the
    environment (R + T = 1 from both sides of a free-standing film)."""
    scene = bubble_scene(300.0)
    scene.camera = Camera(position=(0.0, 0.0, 0.3), look_at=(0.0, 0.0, -1.0), fov_deg=60.0)
    img = tracer.render(scene, depth=24, threshold=0.0, **SMALL)
    env = tracer.render(Scene(camera=scene.camera, environment=scene.environment), spectral=True, **SMALL)
    # from inside, every ray meets the film at cos(theta) >= sqrt(1 - 0.3^2): R is small
    np.testing.assert_allclose(img, env, rtol=0, atol=1e-10)


@pytest.mark.analytic
def test_light_inside_a_bubble_lights_through_the_film():
    """A matte sphere lit by a light inside a bubble receives the light times the film's T at
    the crossing (0 < T < 1, depending on wavelength): brighter than unlit, darker than without
    the bubble, and exactly as bright with a zero-thickness film."""
    def scene(d):
        return Scene(
            spheres=[Sphere((0.0, -2.0, 0.0), 1.0, Material(color=(1, 1, 1), ambient=0, diffuse=1))],
            bubbles=[] if d is None else [Bubble((0.0, 1.0, 0.0), 0.5, FilmProfile("uniform", thickness_nm=d),
                                                 n_film=1.6)],
            lights=[PointLight((0.0, 1.0, 0.0), 1.0)],
            camera=Camera(position=(0.0, -2.0, 5.0), look_at=(0.0, -2.0, 0.0), fov_deg=30),
            environment=Environment(kind="constant", color=(0, 0, 0)),
            ambient=(0, 0, 0),
        )
    free = tracer.render(scene(None), depth=2, spectral=True, **SMALL)
    zero = tracer.render(scene(0.0), depth=2, spectral=True, **SMALL)
    film = tracer.render(scene(250.0), depth=2, spectral=True, **SMALL)
    lit = free.sum(axis=-1) > 0.05
    assert lit.sum() > 20
    np.testing.assert_allclose(zero, free, rtol=1e-12, atol=1e-14)
    assert np.all(film[lit].sum(axis=-1) < free[lit].sum(axis=-1))
    assert np.all(film[lit].sum(axis=-1) > 0.5 * free[lit].sum(axis=-1))


@pytest.mark.analytic
def test_rays_tangent_to_spheres_are_finite():
    """Pixels whose rays graze sphere and bubble silhouettes produce finite values."""
    img = tracer.render(full_scene(), width=64, height=64, depth=8, spp=4, threshold=0.0, progress=False)
    assert np.isfinite(img).all()
    assert img.min() >= 0.0


@pytest.mark.analytic
def test_same_image_whatever_the_thread_count():
    """Sample positions are hashed from (seed, pixel, sample): 1 thread and 2 threads agree
    bit for bit; a different seed changes the jitter."""
    import numba

    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = tracer.render(full_scene(), spp=4, depth=4, **SMALL)
        numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))
        two = tracer.render(full_scene(), spp=4, depth=4, **SMALL)
    finally:
        numba.set_num_threads(before)
    assert np.array_equal(one, two)
    other = tracer.render(full_scene(), spp=4, depth=4, seed=7, **SMALL)
    assert not np.array_equal(one, other)


@pytest.mark.analytic
def test_pruning_threshold_zero_traces_more_and_converges():
    """threshold = 0 (exhaustive) traces at least as many rays as pruning, and the pruned image
    differs from it by no more than the pruned throughput allows (about threshold per branch)."""
    _, st0 = tracer.render_with_stats(full_scene(), depth=8, threshold=0.0, **SMALL)
    img0 = tracer.render(full_scene(), depth=8, threshold=0.0, **SMALL)
    img1, st1 = tracer.render_with_stats(full_scene(), depth=8, threshold=1e-3, **SMALL)
    assert st0.rays["total"] >= st1.rays["total"]
    assert np.abs(img1 - img0).max() < 0.02


@pytest.mark.analytic
def test_glass_sphere_energy_in_uniform_environment():
    """A clear lossless glass sphere (transmission 1, no local terms) in a uniform environment:
    Fresnel splits energy without loss, so with enough depth it is invisible too."""
    scene = Scene(
        spheres=[Sphere((0, 0, 0), 1.0, Material(color=(1, 1, 1), ambient=0, diffuse=0, specular=0,
                                                  transmission=1.0, ior=1.5))],
        camera=Camera(position=(0, 0, 4.0), look_at=(0, 0, 0), fov_deg=40),
        environment=Environment(kind="constant", color=(0.2, 0.4, 0.6)),
    )
    img = tracer.render(scene, depth=24, threshold=0.0, **SMALL)
    steep = incidence_cosines(scene, SMALL["width"], SMALL["height"]) > 0.6
    np.testing.assert_allclose(img[steep], np.broadcast_to((0.2, 0.4, 0.6), img.shape)[steep], atol=1e-9)
    assert np.all(luminance(img) <= luminance(np.array((0.2, 0.4, 0.6))) + 1e-12)


@pytest.mark.analytic
def test_light_exactly_on_a_surface_makes_no_nan():
    """A point light placed exactly on a sphere's surface (zero distance to the pixels that see
    that point) and inside a bubble's film: every pixel stays finite."""
    scene = full_scene()
    sph = scene.spheres[0]
    scene.lights = [PointLight((sph.center[0], sph.center[1], sph.center[2] + sph.radius), 1.0),
                    PointLight((0.3, 0.2 + 0.9, 1.0), 1.0)]
    scene.camera = Camera(position=(sph.center[0], sph.center[1], 4.0), look_at=sph.center, fov_deg=20)
    img = tracer.render(scene, width=33, height=33, depth=4, progress=False)
    assert np.isfinite(img).all()


@pytest.mark.analytic
@pytest.mark.parametrize("make_scene", ["builtin", "full"])
def test_adding_a_light_never_darkens_a_pixel(make_scene):
    """Light adds: every term a point light contributes (diffuse, Phong, a bubble's R-weighted
    highlight) is non-negative and nothing else depends on it, so the image with an extra light
    is at least as bright, per spectral band, everywhere.  (Regression: a highlight's shadow ray
    through a bubble once overwrote the hit's own R and T, darkening a disc around the
    highlight.)  Checked per band through luminance, a non-negative sum of bands."""
    base = tracer.default_scene() if make_scene == "builtin" else full_scene()
    base.lights = []
    lit = tracer.default_scene() if make_scene == "builtin" else full_scene()
    lit.lights = [PointLight((2.0, 3.0, 4.0), 1.5), PointLight((0.0, 0.5, 0.2), 0.7)]
    kw = dict(width=40, height=40, depth=6, threshold=0.0, spectral=True, progress=False)
    y0 = luminance(tracer.render(base, **kw))
    y1 = luminance(tracer.render(lit, **kw))
    assert np.all(y1 >= y0 - 1e-12), (np.min(y1 - y0), np.argwhere(y1 < y0 - 1e-12)[:5])
    assert np.any(y1 > y0 + 1e-3)


@pytest.mark.reference
def test_band_averaged_films_do_not_alias_thick_bubbles():
    """A 15-micron uniform bubble under the sky: with 16 bands, films evaluated at the band
    centres alias (their fringes are finer than a band), films averaged over each band do not.
    Reference: the same render with 421 one-nanometre bands (the 1 nm colour integration).
    Mean CIEDE2000 over the bubble's pixels (study.delta_e00)."""
    from study import delta_e00

    scene = bubble_scene(15000.0, env=Environment(kind="sky"))
    kw = dict(width=32, height=32, depth=4, threshold=0.0, progress=False)
    ref = tracer.render(scene, spectral_samples=421, **kw)
    point = tracer.render(scene, spectral_samples=16, spectral_method="point", **kw)
    band = tracer.render(scene, spectral_samples=16, spectral_method="band", **kw)
    on_bubble = incidence_cosines(scene, 32, 32) > 0.2
    de_point = delta_e00(np.clip(point, 0, None), np.clip(ref, 0, None))[on_bubble].mean()
    de_band = delta_e00(np.clip(band, 0, None), np.clip(ref, 0, None))[on_bubble].mean()
    assert de_band < 1.0, de_band
    assert de_point > 2 * de_band, (de_point, de_band)


@pytest.mark.analytic
def test_band_method_equals_point_method_for_a_zero_thickness_film():
    """At d = 0 the band average is the point value (no phase to average): same image."""
    scene = bubble_scene(0.0, env=Environment(kind="sky"))
    kw = dict(width=16, height=16, depth=4, threshold=0.0, progress=False)
    a = tracer.render(scene, spectral_method="point", **kw)
    b = tracer.render(scene, spectral_method="band", **kw)
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-13)


@pytest.mark.analytic
@pytest.mark.parametrize("bands", [8, 16, 32])
def test_spectral_transport_returns_rgb_colours_unchanged(bands):
    """A constant environment seen directly in a spectral scene comes back as exactly its
    linear-sRGB colour: the RGB -> bands basis is normalised so that to_rgb @ basis = I."""
    scene = bubble_scene(300.0, env=Environment(kind="constant", color=(0.2, 0.45, 0.7)))
    img = tracer.render(scene, width=12, height=12, spectral_samples=bands, progress=False)
    np.testing.assert_allclose(img[0, 0], (0.2, 0.45, 0.7), rtol=1e-12)


@pytest.mark.analytic
def test_rgb_transport_with_bubbles_is_finite():
    """Forcing RGB transport on a scene with bubbles evaluates the films at the sRGB primaries'
    dominant wavelengths: crude, but finite and with R + T = 1 (invisible in a uniform
    environment, like the spectral case)."""
    img = tracer.render(tracer.default_scene(), width=24, height=24, spectral=False, progress=False)
    assert np.isfinite(img).all()
    flat = tracer.render(bubble_scene(300.0), depth=20, threshold=0.0, spectral=False, **SMALL)
    steep = incidence_cosines(bubble_scene(300.0), SMALL["width"], SMALL["height"]) > 0.6
    np.testing.assert_allclose(flat[steep], np.broadcast_to((0.3, 0.5, 0.7), flat.shape)[steep], atol=1e-10)


# --------------------------------------------------------------------------------------------
# spectral_method="auto": band-averaged films only where point samples would alias
# --------------------------------------------------------------------------------------------
@pytest.mark.analytic
@pytest.mark.parametrize(
    "film",
    [
        FilmProfile("uniform", thickness_nm=750.0),
        FilmProfile("uniform", thickness_nm=750.0, swirl=0.4, seed=3),
        FilmProfile("draining", top_nm=40.0, bottom_nm=1300.0, swirl=0.35, seed=1),
        FilmProfile("draining", top_nm=900.0, bottom_nm=200.0, exponent=1.0),
        FilmProfile("map", table=np.linspace(10.0, 2500.0, 9 * 16).reshape(9, 16), swirl=0.2),
    ],
    ids=["uniform", "uniform-swirl", "draining-swirl", "draining-inverted", "map-swirl"],
)
def test_film_thickness_bound_holds_over_the_whole_bubble(film):
    """tracer.prepare.pack.film_thickness_bound_nm bounds the thickness the integrator evaluates
    (tracer.kernels.thickness.film_thickness) at every point of the sphere, and is attained without swirl."""
    from tracer.kernels.thickness import film_thickness
    from tracer.prepare.pack import film_thickness_bound_nm, pack_scene

    scene = Scene(bubbles=[Bubble((0.0, 0.0, 0.0), 1.0, film)])
    packed = pack_scene(scene)
    normals = np.random.default_rng(7).normal(size=(20000, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    normals = np.vstack([normals, [[0.0, 1.0, 0.0], [0.0, -1.0, 0.0]]])  # the poles: top and bottom
    d = np.array([film_thickness(packed.films[0], packed.film_maps, n) for n in normals])
    bound = film_thickness_bound_nm(film)
    assert d.max() <= bound * (1 + 1e-12), (d.max(), bound)
    if film.swirl == 0:
        assert d.max() >= bound * (1 - 1e-9), (d.max(), bound)


@pytest.mark.analytic
def test_auto_method_chooses_band_only_for_films_beyond_the_point_sampling_limit():
    """The choice follows bubbleoptics.point_sampling_limit_nm / AUTO_FRINGE_BANDS (index at
    400 nm, normal incidence): just below it point sampling, just above it band averaging; fewer bands lower
    the limit; an explicit method is kept; a bad one is refused."""
    import bubbleoptics as bo
    from tracer.prepare.pack import resolve_spectral_method

    limit16 = float(bo.point_sampling_limit_nm(16, n_film=1.333)) / tracer.prepare.pack.AUTO_FRINGE_BANDS
    below, above = bubble_scene(0.99 * limit16), bubble_scene(1.01 * limit16)
    assert resolve_spectral_method(below, 16) == "point"
    assert resolve_spectral_method(above, 16) == "band"
    assert resolve_spectral_method(below, 8) == "band"  # the 8-band limit is half the 16-band one
    assert resolve_spectral_method(above, 32) == "point"
    assert resolve_spectral_method(above, 16, "point") == "point"
    assert resolve_spectral_method(below, 16, "band") == "band"
    assert resolve_spectral_method(tracer.default_scene(), 16) == "point"  # films up to 1.28 um
    with pytest.raises(ValueError, match="spectral_method"):
        resolve_spectral_method(below, 16, "fast")


@pytest.mark.regression
@pytest.mark.parametrize("thickness_nm, expected", [(500.0, "point"), (15000.0, "band")])
def test_auto_method_renders_exactly_what_it_chose(thickness_nm, expected):
    """The default ("auto") image is the explicit method's image, and the stats report the choice."""
    scene = bubble_scene(thickness_nm, env=Environment(kind="sky"))
    kw = dict(width=16, height=16, depth=4, threshold=0.0, progress=False)
    assert tracer.DEFAULTS["spectral_method"] == "auto"
    img, stats = tracer.render_with_stats(scene, **kw)
    assert stats.spectral_method == expected
    np.testing.assert_array_equal(img, tracer.render(scene, spectral_method=expected, **kw))
    _, rgb_stats = tracer.render_with_stats(scene, spectral=False, **kw)
    assert rgb_stats.spectral_method == ""
