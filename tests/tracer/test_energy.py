"""No energy lost where a branch is cut (tracer.kernels.integrator): analytic answers in uniform light.

In a uniform environment every escaping ray sees the same radiance B, so a pixel is B times
the sum of the throughputs of its ray tree's leaves.  A lossless surface splits a ray's
throughput without loss (R + T = 1 for a free-standing film, F + (1 - F) = 1 for clear
glass), so that sum is 1 and the surface must vanish; a cut branch that dropped its
throughput would show as a dark ring.  For an absorbing uniform film the sum is known in
closed form: a camera ray meeting a bubble at angle theta sends out R + T * T / (1 - R)
(every chord of a sphere meets it at the same angle, so the inner bounces form a geometric
series), whatever the depth or pruning.
"""

import numpy as np
import pytest

import bubbleoptics as bo
import tracer
from scene_geometry import incidence_cosines, luminance  # tests/support/scene_geometry.py
from tracer.scene import Bubble, Camera, Environment, FilmProfile, Material, Scene, Sphere

BACKGROUND = (0.3, 0.5, 0.7)
SMALL = dict(width=32, height=32, progress=False)


def one_bubble(film, n_film=1.333, radius=1.0):
    return Scene(
        bubbles=[Bubble((0.0, 0.0, 0.0), radius, film, n_film=n_film)],
        camera=Camera(position=(0.0, 0.0, 3.0), look_at=(0.0, 0.0, 0.0), fov_deg=45.0),
        environment=Environment(kind="constant", color=BACKGROUND),
        ambient=(0.0, 0.0, 0.0),
    )


def background_image(scene, **kw):
    """The environment alone, rendered with the same channels as the bubble scene."""
    return tracer.render(Scene(camera=scene.camera, environment=scene.environment), spectral=True, **kw)


FILMS = [FilmProfile("uniform", thickness_nm=d) for d in (0.0, 5.0, 120.0, 450.0, 3000.0, 20000.0)] + [
    FilmProfile("draining", top_nm=0.0, bottom_nm=1000.0),
    FilmProfile("draining", top_nm=30.0, bottom_nm=20000.0, swirl=0.3, seed=4),
]


@pytest.mark.analytic
@pytest.mark.parametrize("film", FILMS, ids=lambda f: f"{f.kind}-{f.thickness_nm if f.kind == 'uniform' else f.bottom_nm}")
def test_lossless_bubble_vanishes_in_uniform_light_at_default_settings(film):
    """Lossless bubbles from 0 nm to 20 um, uniform and draining, at the default depth (10),
    pruning (1e-3), bands (16) and film method (auto: band-averaged beyond 1.5 um): every pixel
    equals the background (to 1e-9: the estimator is exact) and no
    pixel is brighter than it."""
    scene = one_bubble(film)
    img = tracer.render(scene, **SMALL)
    bg = background_image(scene, **SMALL)
    np.testing.assert_allclose(img, bg, rtol=0, atol=1e-9)
    assert np.all(luminance(img) <= luminance(bg) + 1e-12)


@pytest.mark.analytic
@pytest.mark.parametrize("depth", [1, 2, 3, 10])
@pytest.mark.parametrize("threshold", [0.0, 1e-3, 0.5])
def test_lossless_bubble_vanishes_at_any_depth_and_pruning(depth, threshold):
    """Where the tree is cut does not matter: depth 1 (camera rays only, both children end in
    the environment) through 10, exhaustive or pruned hard."""
    scene = one_bubble(FilmProfile("uniform", thickness_nm=400.0))
    img = tracer.render(scene, depth=depth, threshold=threshold, **SMALL)
    np.testing.assert_allclose(img, background_image(scene, **SMALL), rtol=0, atol=1e-9)


@pytest.mark.analytic
@pytest.mark.parametrize("depth", [1, 10])
def test_clear_glass_sphere_vanishes_in_uniform_light(depth):
    """A clear lossless glass sphere (transmission 1, no local terms, n = 1.5): Fresnel splits
    F + (1 - F) = 1, total internal reflection sends everything back, so it vanishes too."""
    scene = Scene(
        spheres=[Sphere((0, 0, 0), 1.0, Material(color=(1, 1, 1), ambient=0, diffuse=0, specular=0,
                                                  transmission=1.0, ior=1.5))],
        camera=Camera(position=(0, 0, 3.0), look_at=(0, 0, 0), fov_deg=45),
        environment=Environment(kind="constant", color=BACKGROUND),
    )
    img = tracer.render(scene, depth=depth, **SMALL)
    np.testing.assert_allclose(img, np.broadcast_to(BACKGROUND, img.shape), rtol=0, atol=1e-12)
    assert np.all(luminance(img) <= luminance(np.array(BACKGROUND)) + 1e-12)


@pytest.mark.analytic
@pytest.mark.parametrize("depth, threshold", [(1, 1e-3), (3, 0.0), (10, 1e-3)])
def test_absorbing_bubble_matches_the_closed_form(depth, threshold):
    """A dyed film (n = 1.36 + 0.02i, 300 nm) in uniform light: each pixel on the bubble is
    B (R + T^2 / (1 - R)) per band, with R and T of the film at that pixel's angle from
    bubbleoptics' NumPy API, whatever the depth and pruning; the bubble is darker than the
    background by exactly the light the film absorbs."""
    n = 1.36 + 0.02j
    scene = one_bubble(FilmProfile("uniform", thickness_nm=300.0), n_film=n)
    w = h = 24
    img = tracer.render(scene, width=w, height=h, depth=depth, threshold=threshold, progress=False)
    packed = tracer.prepare.pack.pack_scene(scene)
    wl = packed.wavelengths
    bands_bg = packed.rgb_basis @ np.array(BACKGROUND)
    cosines = incidence_cosines(scene, w, h)
    hit = cosines > 1e-3
    theta = np.arccos(np.clip(cosines[hit], 0, 1))[:, None]
    R = bo.film_reflectance(wl, 300.0, theta, n_film=n)
    T = bo.film_transmittance(wl, 300.0, theta, n_film=n)
    expected = (bands_bg * (R + T * T / (1 - R))) @ packed.to_rgb.T
    # 1e-7: a child ray starts 1e-9 of the scene off the film (tracer.kernels.geometry.origin_epsilon),
    # which tilts the inner chords, and so their angle and R, by about that much
    np.testing.assert_allclose(img[hit], expected, rtol=1e-7, atol=1e-12)
    # the deficit is the absorbed light: positive, and what a lossless film would not lose
    deficit = luminance(np.array(BACKGROUND)) - luminance(img[hit])
    assert np.all(deficit > 0)


@pytest.mark.analytic
def test_a_thousand_bubbles_at_depth_10_show_no_black_bubble():
    """A foam of 1000 lossless bubbles (thickness 0-2 um, radii 0.05-0.3) at depth 10 and the
    default pruning: rays cross dozens of films and the tree is cut everywhere, yet every pixel
    equals the background (the coursework's estimator, which dropped cut branches, turned
    deep bubbles black)."""
    rng = np.random.default_rng(7)
    bubbles = [Bubble(tuple(rng.uniform(-2, 2, 3)), float(rng.uniform(0.05, 0.3)),
                      FilmProfile("uniform", thickness_nm=float(rng.uniform(0, 2000))), n_film="water")
               for _ in range(1000)]
    scene = Scene(bubbles=bubbles, camera=Camera(position=(0, 0, 6.0), look_at=(0, 0, 0), fov_deg=50),
                  environment=Environment(kind="constant", color=BACKGROUND), ambient=(0, 0, 0))
    img, stats = tracer.render_with_stats(scene, width=48, height=48, depth=10, progress=False)
    assert stats.rays["transmitted"] > 10 * 48 * 48  # the foam is crossed, deeply
    np.testing.assert_allclose(img, background_image(scene, width=48, height=48, progress=False), rtol=0,
                               atol=1e-9)
