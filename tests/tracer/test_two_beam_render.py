"""The two-beam film model in the tracer (``Bubble.film_model = "two-beam"``).

The formula is bubbleoptics' (:func:`bubbleoptics.two_beam_reflectance`); what is checked here
is that the tracer selects it, refuses bad values, and renders what the formula says.  The
single-bounce set-up: a bubble at the origin seen from +z in an image environment that is white
towards +z and black towards -z.  At depth 1 a camera ray's two children are cut at once and
look up the environment in their directions (a cut child of a lossless film carries exactly its
weight): the mirror child of a ray meeting the film at less than 45 degrees goes towards +z
(white), the straight-on child towards -z (black), so each band of such a pixel is R(theta)
times the white environment's band value.
"""

import math

import numpy as np
import pytest

import bubbleoptics as bo
import tracer
from scene_geometry import incidence_cosines  # tests/support/scene_geometry.py
from tracer.scene.errors import SceneError
from tracer.scene import Bubble, Camera, Environment, FilmProfile, Scene
from tracer.scene.toml_read import parse_toml_text
from tracer.scene.toml_write import scene_to_toml_text

W = H = 20
THICKNESS_NM = 380.0
N_FILM = 1.36


def half_white_scene(model, thickness_nm=THICKNESS_NM, n_film=N_FILM):
    # an equirectangular image of two rows around up = +z: row 0 (towards +z) white, row 1 black
    image = np.zeros((2, 4, 3))
    image[0] = 1.0
    return Scene(
        bubbles=[Bubble((0.0, 0.0, 0.0), 1.0, FilmProfile("uniform", thickness_nm=thickness_nm), n_film=n_film,
                        film_model=model)],
        camera=Camera(position=(0.0, 0.0, 3.0), look_at=(0.0, 0.0, 0.0), fov_deg=45.0),
        environment=Environment(kind="image", image=image, up=(0.0, 0.0, 1.0)),
        ambient=(0.0, 0.0, 0.0),
    )


def reflected_bands(model, **kw):
    """Per-band radiance of the pixels whose mirror child goes towards +z, divided by the white
    environment's band values, and the angles of incidence of those pixels."""
    scene = half_white_scene(model, **kw)
    cube = tracer.render_spectral(scene, width=W, height=H, depth=1, threshold=0.0, spectral_method="point",
                                  progress=False)
    cosines = incidence_cosines(scene, W, H)
    near_normal = cosines > math.cos(math.radians(35.0))  # mirror child at < 70 degrees from +z
    white = tracer.prepare.pack.pack_scene(scene).rgb_basis @ np.ones(3)
    return cube.radiance[near_normal] / white, np.arccos(np.clip(cosines[near_normal], 0.0, 1.0)), cube


@pytest.mark.reference
def test_a_rendered_two_beam_pixel_is_bubbleoptics_two_beam_reflectance():
    """Each band of a single-bounce pixel equals bubbleoptics.two_beam_reflectance at the band
    centre and the pixel's angle (computed here from the ray-sphere geometry); and the Airy
    default equals bubbleoptics.film_reflectance the same way (the set-up itself is right)."""
    ratio, theta, cube = reflected_bands("two-beam")
    wl = cube.wavelengths_nm
    assert ratio.shape[0] > 20
    expected = bo.two_beam_reflectance(wl, THICKNESS_NM, theta[:, None], N_FILM)
    # 1e-9: the pixel-centre ray's angle here and in the tracer differ by rounding only
    np.testing.assert_allclose(ratio, expected, rtol=1e-9, atol=1e-12)
    airy, theta_a, _ = reflected_bands("airy")
    np.testing.assert_allclose(airy, bo.film_reflectance(wl, THICKNESS_NM, theta_a[:, None], N_FILM),
                               rtol=1e-9, atol=1e-12)


@pytest.mark.analytic
def test_two_beam_and_airy_pixels_agree_to_first_order_in_the_interface_reflectance():
    """Lossless free film, one polarization j: Airy R_j = F_j s / (1 + F_j s), s = sin^2(beta),
    F_j = 4 R01_j / (1 - R01_j)^2, and the two-beam R_j = 4 R01_j s, so their ratio
    (1 - R01_j)^2 (1 + F_j s) lies in [(1 - R01_j)^2, (1 + R01_j)^2]: they agree to first order
    in R01.  The unpolarized ratio (of the sums over s and p) lies between the two
    polarizations' ratios, so within the bound of the larger one, R01_s.  Checked on the
    rendered pixels, with R01_s of each pixel's angle from the Fresnel formula (written out
    here); and the bound is tight: the ratio comes within 1% of both ends."""
    two_beam, theta, _ = reflected_bands("two-beam")
    airy, theta_a, _ = reflected_bands("airy")
    np.testing.assert_array_equal(theta, theta_a)
    c0 = np.cos(theta)[:, None]
    c1 = np.sqrt(1.0 - (np.sin(theta)[:, None] / N_FILM) ** 2)
    r01_s = ((c0 - N_FILM * c1) / (c0 + N_FILM * c1)) ** 2
    on = airy > 1e-6  # away from the dark fringes' zeros, where both vanish
    ratio = two_beam[on] / airy[on]
    lo = ((1.0 - r01_s) ** 2 * np.ones_like(airy))[on]
    hi = ((1.0 + r01_s) ** 2 * np.ones_like(airy))[on]
    assert np.all(ratio >= lo * (1 - 1e-9)) and np.all(ratio <= hi * (1 + 1e-9))
    assert (ratio / lo).min() < 1.01 and (hi / ratio).min() < 1.01
    assert ratio.min() < 0.95 and ratio.max() > 1.05  # and the two models do differ by ~2 R01


@pytest.mark.analytic
def test_a_two_beam_bubble_conserves_energy_in_uniform_light():
    """T = 1 - R: a two-beam bubble in a uniform environment vanishes like an Airy one."""
    scene = half_white_scene("two-beam")
    scene.environment = Environment(kind="constant", color=(0.3, 0.5, 0.7))
    img = tracer.render(scene, width=12, height=12, progress=False)
    np.testing.assert_allclose(img, np.broadcast_to((0.3, 0.5, 0.7), img.shape), rtol=0, atol=1e-9)


@pytest.mark.api
@pytest.mark.parametrize("bad", ["two_beam", "Airy", "", 2])
def test_a_bad_film_model_is_refused_with_one_line_naming_the_bubble(bad):
    scene = half_white_scene(bad)
    with pytest.raises(ValueError, match=r"bubble 'bubble': film_model must be one of 'airy', 'two-beam'") as e:
        tracer.prepare.pack.pack_scene(scene)
    assert "\n" not in str(e.value)


@pytest.mark.api
def test_band_averaging_refuses_a_two_beam_bubble():
    with pytest.raises(ValueError, match="two-beam"):
        tracer.render(half_white_scene("two-beam"), width=2, height=2, spectral_method="band", progress=False)


@pytest.mark.api
def test_the_toml_field_reads_writes_and_refuses():
    text = """
[[bubbles]]
center = [0, 0, 0]
radius = 1
film_model = "two-beam"
[[bubbles]]
center = [2, 0, 0]
radius = 1
"""
    scene = parse_toml_text(text)
    assert [b.film_model for b in scene.bubbles] == ["two-beam", "airy"]
    written = scene_to_toml_text(scene, "x.toml")
    assert written.count("film_model") == 1  # the default is not written
    assert [b.film_model for b in parse_toml_text(written).bubbles] == ["two-beam", "airy"]
    with pytest.raises(SceneError, match=r"film_model.*must be one of 'airy', 'two-beam', got 'exact'"):
        parse_toml_text(text.replace('"two-beam"', '"exact"'))
