"""study.tradeoffs: the masks, metrics and floor of the time-against-error study.

* ``analytic``: the bubble and silhouette masks against a sphere's projection worked out in
  the image plane (not by intersecting rays); the interior mask, the seeds' statistics and the
  floor's tolerance on hand-made images and rows.
* ``regression``: on the built-in scene rendered small, the mask no longer makes 4 spp look worse
  than 1 spp by more than the reference's own floor (the old mask, from a pixel-centre render, did).
* ``api``: the reference files' round trip with the masks.
"""

import math

import numpy as np
import pytest

from study import tradeoffs

CAMERA = dict(origin=np.zeros(3), forward=np.array([0.0, 0.0, -1.0]), right=np.array([1.0, 0.0, 0.0]),
              up=np.array([0.0, 1.0, 0.0]), tan_half_fov=math.tan(math.radians(20.0)))


def _projected_disc(width, height, distance, radius, sub=tradeoffs.SUB_PIXELS):
    """For a sphere on the optical axis: which sub-pixel points of the image plane lie inside its
    outline, from the cone of tangent rays (half-angle asin(r / D)), in image-plane coordinates."""
    th = CAMERA["tan_half_fov"]
    rho = math.tan(math.asin(radius / distance))
    offsets = (np.arange(sub) + 0.5) / sub
    px = np.arange(width)[None, :, None, None] + offsets[None, None, None, :]
    py = np.arange(height)[:, None, None, None] + offsets[None, None, :, None]
    sx = (2.0 * px / width - 1.0) * th * width / height
    sy = (1.0 - 2.0 * py / height) * th
    inside = np.broadcast_to(sx**2 + sy**2 < rho**2, (height, width, sub, sub))
    return inside.reshape(height, width, sub * sub)


@pytest.mark.analytic
@pytest.mark.parametrize("size, distance, radius", [(24, 5.0, 1.0), (31, 3.0, 0.6), (40, 8.0, 2.5)])
def test_bubble_and_silhouette_masks_match_the_projected_disc(size, distance, radius):
    hits = tradeoffs.pixel_hits(CAMERA, [[0.0, 0.0, -distance]], [radius], size, size)
    inside = _projected_disc(size, size, distance, radius)
    np.testing.assert_array_equal(hits == 0, inside)
    bubble = tradeoffs.bubble_mask(hits, [True])
    np.testing.assert_array_equal(bubble, inside.all(axis=-1))
    np.testing.assert_array_equal(tradeoffs.silhouette_mask(hits), inside.any(axis=-1) & ~inside.all(axis=-1))
    # not a bubble: never in the bubble mask, the silhouette unchanged
    assert not tradeoffs.bubble_mask(hits, [False]).any()
    # the disc's area in pixels: between the wholly covered pixels and those touched at all
    th = CAMERA["tan_half_fov"]
    area = math.pi * (math.tan(math.asin(radius / distance)) / th * size / 2) ** 2
    assert bubble.sum() < area < (hits == 0).any(axis=-1).sum()


@pytest.mark.analytic
def test_pixel_hits_nearest_sphere_and_camera_inside():
    # a small sphere in front of a large one: where both project, the small (nearer) one is hit
    hits = tradeoffs.pixel_hits(CAMERA, [[0.0, 0.0, -10.0], [0.0, 0.0, -4.0]], [3.0, 0.5], 32, 32)
    near = _projected_disc(32, 32, 4.0, 0.5)
    assert (hits[near] == 1).all()
    assert (hits[~near & _projected_disc(32, 32, 10.0, 3.0)] == 0).all()
    # a camera inside a sphere meets its far side everywhere
    assert (tradeoffs.pixel_hits(CAMERA, [[0.0, 0.0, 0.0]], [1.0], 8, 8) == 0).all()


@pytest.mark.analytic
def test_interior_mask_from_two_references_and_silhouettes():
    a = np.full((12, 12, 3), 0.3)
    b = a.copy()
    b[3, 4] = [0.6, 0.3, 0.3]  # the references disagree at one pixel: a sub-pixel feature
    sil = np.zeros((12, 12), bool)
    sil[9, 9] = True  # a silhouette the colours do not show
    interior = tradeoffs.interior_mask(a, b, sil)
    expected = np.ones((12, 12), bool)
    expected[2:5, 3:6] = False
    expected[8:11, 8:11] = False
    np.testing.assert_array_equal(interior, expected)
    # a difference below the threshold is no edge
    c = a.copy()
    c[3, 4] = [0.301, 0.3, 0.3]
    assert tradeoffs.interior_mask(a, c).all()


@pytest.mark.analytic
def test_image_errors_on_masks():
    ref = np.full((4, 8, 3), 0.5)
    img = ref.copy()
    img[0, 0] = [0.25, 0.5, 0.5]  # one pixel off, outside the interior and inside the bubble
    interior = np.ones((4, 8), bool)
    interior[0, 0] = False
    bubble = np.zeros((4, 8), bool)
    bubble[:2, :2] = True
    e = tradeoffs.image_errors(img, ref, interior, bubble)
    assert e["interior_mean_de00"] == 0.0 and e["interior_fraction"] == 31 / 32
    assert e["bubble_fraction"] == 0.125
    assert e["bubble_mean_de00"] == pytest.approx(e["mean_de00"] * 32 / 4)
    assert e["bubble_mean_de00"] > 1.0
    assert e["p95_de00"] == 0.0 < e["bubble_p95_de00"]  # 1 pixel of 32 is off, 1 of the 4 bubble pixels
    assert math.isnan(tradeoffs.image_errors(img, ref, interior)["bubble_mean_de00"])


@pytest.mark.analytic
def test_combine_seeds_mean_and_spread():
    errs = [dict(mean_de00=m, interior_mean_de00=m / 2, max_de00=m, nonfinite_pixels=0) for m in (1.0, 2.0, 4.0)]
    out = tradeoffs.combine_seeds(errs)
    assert out["mean_de00"] == pytest.approx(7 / 3) and out["interior_mean_de00"] == pytest.approx(7 / 6)
    assert out["mean_de00_sd"] == pytest.approx(np.std([1.0, 2.0, 4.0], ddof=1))
    assert out["max_de00"] == 4.0 and out["seeds"] == 3
    assert tradeoffs.combine_seeds(errs[:1])["mean_de00_sd"] == 0.0


def _row(scene, factor, value, seconds, error, spp=1, default=False):
    return dict(scene=scene, factor=factor, value=value, transport="spectral", spectral_samples=16.0,
                spectral_method="auto", threshold=1e-3, spp=float(spp), depth=10.0, seconds=seconds,
                seconds_runs=f"{seconds}", mean_de00=error, p95_de00=error, rmse=error, interior_mean_de00=error,
                interior_p95_de00=error, speedup_vs_reference=100.0 / seconds, is_default=float(default))


@pytest.mark.analytic
def test_assess_differences_below_the_floor_are_not_resolved():
    """Two errors below the reference's floor cannot be told apart: a setting faster beyond the
    timing noise and less accurate by less than the floor then dominates; without the floor it
    does not (its error is larger)."""
    defaults = dict(spectral=True, spectral_samples=16, spectral_method="auto", threshold=1e-3, spp=1, depth=10)
    rows = []
    for scene in ("a", "b"):
        rows += [_row(scene, "reference", "reference", 100.0, 0.0, spp=16),
                 _row(scene, "floor", "reference, seed 2", 100.0, 0.05, spp=16),
                 _row(scene, "default", "default", 2.0, 0.04, default=True),
                 _row(scene, "spp", "4", 1.0, 0.045, spp=4)]
    without = tradeoffs.assess(rows, defaults, tol=0.1, use_floor=False)
    assert without["default_ok"], without["problems"]
    with_floor = tradeoffs.assess(rows, defaults, tol=0.1)
    assert with_floor["floors"] == {"a": 0.05, "b": 0.05} and tradeoffs.floor_errors(rows, "a") == 0.05
    assert not with_floor["default_ok"] and any("dominated" in p for p in with_floor["problems"])
    # the floor row is the reference's own setting, never a candidate
    assert all(k[4] != 16 for k in with_floor["candidates"])
    # above the floor, errors are compared as they are
    for r in rows:
        if r["factor"] == "floor":
            r["interior_mean_de00"] = 0.01
    assert tradeoffs.assess(rows, defaults, tol=0.1)["default_ok"]


@pytest.mark.api
def test_references_round_trip_with_masks(tmp_path):
    rng = np.random.default_rng(1)
    refs = {"s": dict(image=rng.uniform(0, 1, (4, 5, 3)), image_b=rng.uniform(0, 1, (4, 5, 3)),
                      interior=rng.uniform(size=(4, 5)) > 0.5, bubble=rng.uniform(size=(4, 5)) > 0.5, seconds=2.0,
                      seconds_runs=[1.9, 2.1], floor_errors=dict(mean_de00=0.3))}
    folder = tradeoffs.save_references(refs, 4, 16, tmp_path / "refs", written_by="test")
    back = tradeoffs.load_references(folder, 4, 16)["s"]
    np.testing.assert_array_equal(back["bubble"], refs["s"]["bubble"])
    np.testing.assert_array_equal(back["interior"], refs["s"]["interior"])
    assert back["seconds_runs"] == [1.9, 2.1] and "image_b" not in back
    assert not (folder / "s_image_b.npy").exists()
    (folder / "s_bubble.npy").unlink()
    assert tradeoffs.load_references(folder, 4, 16) is None  # a mask missing: not usable


@pytest.mark.regression
def test_the_mask_no_longer_favours_one_sample_per_pixel():
    """The built-in scene at 64 x 64 (references with 81 bands: converged films, cheaper).  The old
    mask -- pixels where a pixel-centre render of the reference's transport matched the
    reference -- scored 4 spp three times worse than 1 spp (measured when this test was
    written: 0.0088 against 0.0028); the mask from two references and the geometry leaves a
    difference within the reference's own floor (0.065 against 0.054, floor 0.019).  What is
    left is quadrature, not the mask: 2 x 2 jittered samples carry a random error of first order
    in the pixel size where the centre's is of second order on smooth fringes, and from 9 spp
    on jitter wins; on the bubbles' pixels, and with the silhouettes alone masked, 4 spp is
    already the better."""
    import tracer
    from tracer.prepare.pack import pack_scene

    scene, size = tracer.default_scene(), 64
    packed = pack_scene(scene, spectral_samples=16)
    cam = packed.camera[0]
    camera = {k: np.asarray(cam[k], float) for k in ("origin", "forward", "right", "up", "tan_half_fov")}
    hits = tradeoffs.pixel_hits(camera, packed.spheres["center"], packed.spheres["radius"], size, size)
    bubble = tradeoffs.bubble_mask(hits, packed.spheres["surface"] == 0)
    ref_s = dict(tradeoffs.REFERENCE, spectral_samples=81)
    a = tracer.render(scene, **tradeoffs.render_kwargs(ref_s, size, tradeoffs.REFERENCE["seed"]))
    b = tracer.render(scene, **tradeoffs.render_kwargs(ref_s, size, tradeoffs.FLOOR_SEED))
    centre = tracer.render(scene, **tradeoffs.render_kwargs(dict(ref_s, spp=1), size, tradeoffs.REFERENCE["seed"]))
    masks = dict(new=tradeoffs.interior_mask(a, b, tradeoffs.silhouette_mask(hits)),
                 old=~tradeoffs.dilate(tradeoffs.delta_e00_images(centre, a) >= tradeoffs.AA_DE00),
                 silhouettes=~tradeoffs.dilate(tradeoffs.silhouette_mask(hits)))
    floor = tradeoffs.image_errors(b, a, masks["new"], bubble)["interior_mean_de00"]
    defaults = tradeoffs.settings_from_defaults(tracer.DEFAULTS)
    err = {}
    for spp in (1, 4, 16):
        images = [tracer.render(scene, **tradeoffs.render_kwargs(dict(defaults, spp=spp), size, seed))
                  for seed in tradeoffs.SWEEP_SEEDS[:(1 if spp == 1 else 3)]]
        for name, mask in masks.items():
            err[name, spp] = np.mean([tradeoffs.image_errors(i, a, mask, bubble)["interior_mean_de00"] for i in images])
        err["bubble", spp] = np.mean([tradeoffs.image_errors(i, a, masks["new"], bubble)["bubble_mean_de00"]
                                      for i in images])
    assert err["old", 4] > 2.0 * err["old", 1]  # the bias the referee found
    assert err["new", 4] < 1.5 * err["new", 1]
    assert abs(err["new", 4] - err["new", 1]) < floor
    assert err["new", 16] < err["new", 1] < err["new", 4]
    assert err["bubble", 4] < err["bubble", 1] and err["silhouettes", 4] < err["silhouettes", 1]


@pytest.mark.analytic
def test_scene_front_drops_the_defaults_twin():
    """A row with the defaults' own image under another setting ("point" where "auto" picks point),
    timed faster by chance, is the same render: it neither joins the front nor pushes the defaults
    off it; a different image that is faster and more accurate does."""
    rows = [_row("a", "reference", "reference", 100.0, 0.0, spp=16),
            _row("a", "default", "default", 2.0, 0.04, default=True),
            _row("a", "threshold", "0.001", 2.0, 0.04, default=True),
            _row("a", "spp", "4", 8.0, 0.02, spp=4)]
    twin = dict(_row("a", "spectral", "16", 1.5, 0.04), spectral_method="point")
    sf = tradeoffs.scene_front(rows + [twin], "a")
    assert sf["default_on_front"] and all(r["spectral_method"] != "point" for r in sf["points"])
    other = dict(twin, mean_de00=0.039, interior_mean_de00=0.039)
    assert not tradeoffs.scene_front(rows + [other], "a")["default_on_front"]


@pytest.mark.regression
def test_one_sample_per_pixel_does_not_depend_on_the_seed_on_the_studys_scenes():
    """What the benchmark relies on to render a 1-spp setting once for all seeds
    (``seed_independent``): on the study's scenes (no light of radius > 0) a 1-spp image is the
    same for any seed, a 4-spp one is not."""
    from pathlib import Path

    import tracer

    scenes = Path(__file__).resolve().parents[2] / "data" / "scenes"
    for scene in (tracer.default_scene(), tracer.load_scene(scenes / "thick_films.toml"),
                  tracer.load_scene(scenes / "fig3_5_materials.txt")):
        assert all(light.radius == 0 for light in scene.lights)
        one = [tracer.render(scene, width=24, height=24, spp=1, seed=seed, progress=False) for seed in (0, 3)]
        np.testing.assert_array_equal(one[0], one[1])
        four = [tracer.render(scene, width=24, height=24, spp=4, seed=seed, progress=False) for seed in (0, 3)]
        assert np.abs(four[0] - four[1]).max() > 0
