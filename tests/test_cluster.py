"""One image as tiles of rows on a Dask cluster (tracer.cluster): the same pixels as a local
render, bit for bit, from Python and from ``tracer image --workers N``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import tracer
from tracer.cluster import check_cluster_options, connect, tile_bounds
from tracer.pack import pack_scene
from tracer.render import render_tile, render_with_stats, resolve_settings
from cli_helpers import assert_one_line, run  # tests/cli_helpers.py

ROOT = Path(__file__).resolve().parent.parent
THREE = ROOT / "data" / "scenes" / "coursework_three_bubbles.txt"


@pytest.mark.property
@given(height=st.integers(1, 5000), n_tiles=st.integers(1, 300))
def test_tiles_cover_every_row_once_in_near_equal_parts(height, n_tiles):
    bounds = tile_bounds(height, n_tiles)
    assert bounds[0][0] == 0 and bounds[-1][1] == height
    assert all(a1 == b0 for (_, a1), (b0, _) in zip(bounds, bounds[1:]))  # contiguous, no gap, no overlap
    sizes = [b - a for a, b in bounds]
    assert min(sizes) >= 1 and max(sizes) - min(sizes) <= 1
    assert len(bounds) == min(n_tiles, height)


@pytest.mark.reference
@pytest.mark.parametrize("spectral_image", [False, True])
def test_a_tile_is_those_rows_of_the_whole_image_bit_for_bit(spectral_image):
    """The reference is the whole image rendered in one call; any tile (the first, an inner
    one, the last, one row) equals its rows exactly, spectral cube and ray counts included."""
    scene = tracer.load_scene(THREE)
    s = resolve_settings(scene, width=23, height=17, depth=4, spp=2)
    whole, stats = render_with_stats(scene, **s, progress=False, spectral_image=spectral_image)
    packed = pack_scene(scene, spectral_samples=s["spectral_samples"], force_spectral=True if spectral_image else None,
                        spectral_method=s["spectral_method"])
    for a, b in [(0, 5), (5, 11), (11, 17), (8, 9)]:
        image, counts, spectrum = render_tile(packed, s, a, b, spectral_image)
        assert image.shape == (b - a, 23, 3) and counts.shape[0] == b - a
        assert np.array_equal(image, whole[a:b])
        if spectral_image:
            assert np.array_equal(spectrum, stats.spectral_image.radiance[a:b])
        else:
            assert spectrum is None


@pytest.mark.reference
def test_render_on_a_cluster_is_the_local_render_bit_for_bit(client):
    scene = tracer.default_scene()
    options = dict(width=40, height=37, depth=6, spp=2, progress=False)
    here, stats_here = render_with_stats(scene, **options)
    there, stats_there = render_with_stats(scene, **options, client=client)
    assert np.array_equal(here, there)
    assert stats_here.rays == stats_there.rays  # every row rendered once, none twice


@pytest.mark.reference
def test_spectral_image_on_a_cluster_is_the_local_one(client):
    scene = tracer.load_scene(THREE)
    here = tracer.render_spectral(scene, width=16, height=12, depth=3, progress=False)
    there = tracer.render_spectral(scene, width=16, height=12, depth=3, progress=False, client=client)
    assert np.array_equal(here.radiance, there.radiance) and np.array_equal(here.rgb, there.rgb)


@pytest.mark.reference
def test_tracer_image_workers_writes_the_local_image(tmp_path, capsys):
    local, dist = tmp_path / "local.npy", tmp_path / "dist.npy"
    small = ["--width", "30", "--height", "20", "--depth", "3", "--quiet"]
    assert run(["image", THREE, local, *small], capsys)[0] == 0
    status, stdout, err = run(["image", THREE, dist, *small, "--workers", "2"], capsys)
    assert status == 0 and stdout == "" and err == "", err  # no cluster chatter on the terminal
    assert np.array_equal(np.load(local), np.load(dist))


@pytest.mark.api
def test_workers_and_scheduler_are_exclusive_and_checked(tmp_path, capsys):
    out = tmp_path / "x.png"
    status, _, err = run(["image", out, "--workers", "2", "--scheduler", "tcp://127.0.0.1:1"], capsys)
    assert status == 2 and "not allowed with argument" in err
    assert_one_line(err)
    status, _, err = run(["image", out, "--workers", "0"], capsys)
    assert status == 2 and "--workers: must be an integer from 1 to 1024, got '0'" in err
    assert not out.exists()
    with pytest.raises(ValueError, match="at most one of client, workers and scheduler"):
        check_cluster_options(workers=2, scheduler="tcp://x:1")
    with pytest.raises(ValueError, match="workers must be an integer >= 1, got 1.5"):
        check_cluster_options(workers=1.5)


@pytest.mark.api
def test_an_unreachable_scheduler_is_one_line():
    pytest.importorskip("distributed")
    with pytest.raises(ValueError, match=r"^cannot reach the Dask scheduler at tcp://127.0.0.1:1: ") as info:
        connect("tcp://127.0.0.1:1", timeout="0.5s")
    assert "\n" not in str(info.value)
