"""The Cycles peer benchmark's helpers (benchmarks/peer_cycles.py, benchmarks/cycles_render.py),
without Blender: the scene both sides read, the environment's orientation, the pixel masks, the
decomposition's Airy cut and colour model against independent checks, and the one-line error
when the Cycles Python is missing.  One test renders with Cycles and skips without
``.venv-cycles`` (``make peers``)."""

import importlib.util
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from bubbleoptics import film_reflectance

ROOT = Path(__file__).resolve().parents[2]


def _load(name):
    spec = importlib.util.spec_from_file_location(f"_bench_{name}", ROOT / "benchmarks" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


pc = _load("peer_cycles")
cr = _load("cycles_render")  # imports bpy only in main()


@pytest.mark.api
def test_scene_description_is_what_both_sides_read():
    d = pc.scene_description("bubble", 400.0, size=32)
    assert d["object"] == {"kind": "bubble", "center": [0.0, 0.0, 0.0], "radius": 1.0, "thickness_nm": 400.0,
                           "film_ior": 1.33}
    assert d["camera"]["fov_deg"] == pc.FOV_DEG and d["width"] == d["height"] == 32
    scene = pc.our_scene(d, pc.environment_image(64, 2))
    assert len(scene.bubbles) == 1 and scene.bubbles[0].film.thickness_nm == 400.0
    assert scene.bubbles[0].n_film == 1.33
    assert pc.our_scene(d, pc.environment_image(64, 2), n_film="water").bubbles[0].n_film == "water"
    with pytest.raises(ValueError, match="unknown kind"):
        pc.scene_description("cube")


@pytest.mark.analytic
def test_axes_map_from_y_up_to_blenders_z_up():
    # a proper rotation (determinant +1) taking our up (+y) to Blender's up (+z)
    m = np.array([cr.to_blender(e) for e in np.eye(3)]).T
    assert np.allclose(m @ [0, 1, 0], [0, 0, 1])
    assert np.isclose(np.linalg.det(m), 1.0) and np.allclose(m.T @ m, np.eye(3))


@pytest.mark.analytic
def test_environment_depends_on_elevation_only_and_row_zero_is_the_zenith():
    knots = pc.ENV_KNOTS
    assert np.allclose(pc.environment_radiance([0.0, 1.0, 0.0]), knots[-1][1])
    assert np.allclose(pc.environment_radiance([0.0, -1.0, 0.0]), knots[0][1])
    assert np.allclose(pc.environment_radiance([1.0, 0.0, 0.0]), knots[2][1])
    # rotating a direction about the up axis changes nothing
    rng = np.random.default_rng(1)
    d = rng.normal(size=(100, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    a = rng.uniform(0, 2 * np.pi)
    rot = np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])
    assert np.allclose(pc.environment_radiance(d), pc.environment_radiance(d @ rot.T))
    image = pc.environment_image(256, 4)
    assert image.shape == (256, 4, 3) and np.allclose(image[:, 0], image[:, 3])
    assert np.allclose(image[0, 0], knots[-1][1], atol=1e-3)  # top row: the zenith
    assert np.allclose(image[-1, 0], knots[0][1], atol=1e-3)
    # the sky is not its mirror image, so a flipped environment is a control that must fail
    assert np.abs(image - image[::-1]).max() > 0.3


@pytest.mark.analytic
def test_pixel_masks_follow_the_silhouette():
    size = 200
    m = pc.pixel_masks(size)
    rho_px = math.tan(math.asin(1.0 / 4.0)) / math.tan(math.radians(pc.FOV_DEG) / 2) * size / 2
    assert not np.any(m["bubble"] & m["edge"]) and m["all"].all()
    assert abs(m["bubble"].sum() - math.pi * (rho_px - pc.EDGE_PX) ** 2) < 4 * rho_px
    assert abs(m["edge"].sum() - 2 * math.pi * rho_px * 2 * pc.EDGE_PX) < 0.1 * m["edge"].sum()
    # the closed-form paths hit the sphere exactly on the pixels inside the silhouette
    hit, cos, _, outs = pc.sphere_paths(size, depth=3)
    assert hit[m["bubble"]].all() and not hit[~(m["bubble"] | m["edge"])].any()
    assert cos[size // 2, size // 2] > 0.999
    assert np.allclose(np.linalg.norm(outs[:, hit], axis=-1), 1.0)


@pytest.mark.reference
def test_airy_cut_without_a_cut_is_bubbleoptics_exact_reflectance():
    wl = np.linspace(380.0, 780.0, 41)
    theta = np.linspace(0.0, 1.5, 6)[:, None]
    for d in (10.0, 400.0, 800.0):
        exact = film_reflectance(wl, d, theta, 1.33)
        assert np.allclose(pc.free_film_reflectance(wl, d, np.cos(theta), 1.33), exact, atol=1e-12)
        assert np.allclose(pc.free_film_reflectance(wl, d, np.cos(theta), 1.33, m_max=80), exact, atol=1e-9)
        assert not np.allclose(pc.free_film_reflectance(wl, d, np.cos(theta), 1.33, m_max=1), exact, atol=1e-3)


@pytest.mark.analytic
def test_the_series_mean_is_the_incoherent_sum():
    # C_0, the mean over the phase, is the incoherent sum of the beams, 2 R1 / (1 + R1) for a
    # free film (Stokes), R1 the single-interface reflectance
    a = np.array([-0.3, -0.14, 0.05])
    c0 = pc.airy_cut(a, -a, np.array([0.3, 1.0, 2.0]), 0)
    r1 = a * a
    assert np.allclose(c0, 2 * r1 / (1 + r1), rtol=1e-12)


@pytest.mark.analytic
def test_rgb_colour_model_leaves_grey_grey_and_weights_one_wavelength_by_its_cmf():
    wl = np.arange(360.0, 781.0, 1.0)
    s = pc.rgb_cmfs(wl)
    assert np.allclose(s.sum(axis=1), 1.0)
    assert np.allclose(s @ np.full(wl.size, 0.37), 0.37)  # a flat reflectance: every channel the same
    # a reflectance that is 1 at one wavelength picks that wavelength's normalised CMF values
    spike = (wl == 550.0).astype(float)
    assert np.allclose(s @ spike, s[:, wl == 550.0][:, 0])
    # green's CMF peaks near 550 nm, red's beyond 580, blue's below 470
    peaks = wl[np.argmax(s, axis=1)]
    assert peaks[0] > 580 and 500 < peaks[1] < 570 and peaks[2] < 470


@pytest.mark.analytic
def test_a_film_of_zero_thickness_is_invisible_unless_the_series_is_cut():
    env = pc.environment_radiance(pc.camera_rays(24)[0])
    for model in ("exact", "rgb"):
        image = pc.model_image(model, 0.0, size=24, depth=4, bands=16)
        assert np.allclose(image, env, atol=2e-3 if model == "exact" else 1e-12), model
    # cut after m = 3 the series does not cancel at zero phase: negligibly at normal incidence,
    # much near grazing, where the interfaces reflect strongly and the series converges slowly
    assert 0 < pc.free_film_reflectance(550.0, 0.0, 1.0, 1.33, m_max=3) < 1e-6
    assert pc.free_film_reflectance(550.0, 0.0, 0.1, 1.33, m_max=3) > 0.05
    assert abs(pc.free_film_reflectance(550.0, 0.0, 1.0, 1.33)) < 1e-15


@pytest.mark.api
def test_missing_cycles_python_is_one_line_and_exit_2(tmp_path):
    out = subprocess.run([sys.executable, str(ROOT / "benchmarks" / "peer_cycles.py"), "--quick",
                          "--cycles-python", str(tmp_path / "nope" / "python"), "--out", str(tmp_path / "x.csv")],
                         capture_output=True, text=True, timeout=60, env=dict(os.environ, PYTHONPATH=str(ROOT)))
    assert out.returncode == 2
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and "make peers" in lines[0] and "BUBBLEOPTICS_CYCLES_PYTHON" in lines[0]
    assert not (tmp_path / "x.csv").exists()


def _cycles():
    python = pc.cycles_python()
    return python if python.is_file() else None


@pytest.mark.reference
@pytest.mark.skipif(_cycles() is None, reason="no .venv-cycles (make peers)")
def test_cycles_sees_the_environment_as_ours_and_the_flipped_one_fails(tmp_path):
    env = tmp_path / "env.npy"
    np.save(env, pc.environment_image(256, 4))
    desc = pc.scene_description("empty", size=16)
    ours = pc.environment_radiance(pc.camera_rays(16)[0])
    matched, flipped = (pc.run_cycles(_cycles(), dict(desc, orientation=o), env, [(1, 1)], tmp_path, o)[0][0]
                        for o in ("matched", "flipped"))
    assert np.sqrt(np.mean((matched - ours) ** 2)) < 0.01
    assert np.sqrt(np.mean((flipped - ours) ** 2)) > 0.05


@pytest.mark.api
def test_stored_peer_cycles_has_one_and_two_thread_timings():
    """Issue 23: every peer is timed with one thread and with two.  The stored CSV carries the
    two-thread sweeps in ``timing`` and the one-thread ones in ``timing_1_thread``, the same sample
    counts for each renderer, and equal-error rows for both; its header names the CPU."""
    from study.results import read_commented_csv

    notes, rows = read_commented_csv(ROOT / "data" / "derived" / "peer_cycles.csv")
    assert "CPU " in notes[0]
    for section, threads in (("timing", "2"), ("timing_1_thread", "1")):
        timing = [r for r in rows if r["section"] == section]
        assert {r["threads"] for r in timing} == {threads}
        for renderer, sweep in (("cycles", pc.CYCLES_SWEEP_SPP), ("ours", pc.OURS_SWEEP_SPP)):
            assert sorted(int(r["spp"]) for r in timing if r["renderer"] == renderer) == sorted(sweep)
    for section in ("equal_error", "equal_error_1_thread", "equal_own_error", "equal_own_error_1_thread"):
        ratios = [float(r["ratio"]) for r in rows if r["section"] == section]
        assert ratios and all(math.isfinite(x) and x > 0 for x in ratios)
