"""One image as tiles of rows on a Dask cluster (tracer.rendering.dask): the same pixels as a local
render, bit for bit, from Python and from ``tracer image --workers N``."""

from __future__ import annotations

import inspect
import os
import struct
import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import tracer
from tracer.rendering.dask import (CONNECT_DEADLINE, check_cluster_options, check_scheduler_address, connect, max_workers,
                            tile_bounds)
from tracer.prepare.pack import pack_scene
from tracer.rendering import render_tile, render_with_stats, resolve_settings
from cli_helpers import assert_one_line, run  # tests/support/cli_helpers.py
from net_helpers import JUNK, tcp_server  # tests/support/net_helpers.py

ROOT = Path(__file__).resolve().parents[2]
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
    assert status == 2 and "--workers: must be an integer >= 1 (at most one per core), got '0'" in err
    assert not out.exists()
    with pytest.raises(ValueError, match="at most one of client, workers and scheduler"):
        check_cluster_options(workers=2, scheduler="tcp://x:1")
    with pytest.raises(ValueError, match=f"workers must be an integer from 1 to {max_workers()} .*, got 1.5"):
        check_cluster_options(workers=1.5)


@pytest.mark.api
def test_workers_are_capped_at_the_cores_with_the_reason(tmp_path, capsys):
    cores = max_workers()
    assert cores == len(os.sched_getaffinity(0))
    out = tmp_path / "x.png"
    status, _, err = run(["image", out, "--quiet", "--workers", str(cores + 1)], capsys)
    assert status == 2 and f"--workers must be an integer from 1 to {cores} (one single-threaded worker process " \
                           f"per core; this machine gives this process {cores}), got {cores + 1}" in err
    assert_one_line(err)
    status, _, err = run(["image", out, "--quiet", "--workers", "1" * 400], capsys)  # no int() of 400 digits
    assert status == 2 and "--workers: must be an integer >= 1" in err and len(err) < 200
    assert list(tmp_path.iterdir()) == []
    check_cluster_options(workers=cores)  # the cap itself is allowed


@pytest.mark.api
def test_an_unreachable_scheduler_is_one_line():
    pytest.importorskip("distributed")
    with pytest.raises(ValueError, match=r"^cannot reach the Dask scheduler at tcp://127.0.0.1:1: connection refused"
                                         r" \(nothing listens on that port\)$"):
        connect("tcp://127.0.0.1:1", timeout=0.5)


# ------------------------------------------------------------------ Dask addresses
@pytest.mark.api
@pytest.mark.parametrize("address, words", [
    ("tls://127.0.0.1:8786", ["--scheduler: the scheme tls:// needs TLS certificates", "security="]),
    ("inproc://x", ["--scheduler: the scheme inproc:// names a place inside one Python process"]),
    ("ucx://127.0.0.1:8786", ["--scheduler: the scheme ucx:// needs UCX"]),
    ("ws://127.0.0.1:8786", ["--scheduler: the scheme ws://", "tcp://"]),
    ("wss://127.0.0.1:8786", ["--scheduler: the scheme wss://", "tcp://"]),
    ("http://127.0.0.1:8786", ["--scheduler: unknown scheme 'http://'", "tcp://HOST:PORT"]),
    ("tcp://:8786", ["--scheduler:", "(no host)"]),
    ("tcp://127.0.0.1:99999", ["--scheduler: the port must be an integer from 1 to 65535"]),
    ("tcp://127.0.0.1:x", ["--scheduler: the port must be"]),
    ("tcp://a:b:c", ["--scheduler:", "[IPv6]:PORT"]),
    ("tcp://é:1", ["--scheduler:", "tcp://HOST:PORT"]),
    ("tcp://" + "h" * 300 + ":1", ["--scheduler:", "at most 253 characters", "..."]),
    ("tcp://user@host:1", ["--scheduler:", "letters, digits"]),
])
@pytest.mark.parametrize("command", ["image", "movie"])
def test_every_scheme_is_supported_or_refused_by_name_before_any_work(tmp_path, capsys, address, words, command):
    commands = tmp_path / "c.txt"
    commands.write_text("render 2\n")
    out = tmp_path / ("x.png" if command == "image" else "m")
    args = [command, out] + ([commands] if command == "movie" else []) + ["--quiet", "--scheduler", address]
    status, stdout, err = run(args, capsys)
    assert status == 2 and stdout == "" and all(w in err for w in words), err
    assert_one_line(err)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.txt"]  # no image, no movie, no cache


@pytest.mark.api
@pytest.mark.parametrize("address, normal", [
    ("127.0.0.1", "tcp://127.0.0.1:8786"),
    ("tcp://host.example:8786", "tcp://host.example:8786"),
    ("TCP://10.0.0.2:9000", "tcp://10.0.0.2:9000"),
    ("tcp://[::1]:8786", "tcp://[::1]:8786"),
    ("[::1]", "tcp://[::1]:8786"),
])
def test_a_tcp_address_is_normalised_as_dask_reads_it(address, normal):
    assert check_scheduler_address(address) == normal


@pytest.mark.api
@pytest.mark.parametrize("answer, reason", [
    (None, f"it accepted the connection but did not answer Dask's handshake within {CONNECT_DEADLINE:g} s"),
    (JUNK, "it answered, but not in Dask's protocol (a message header "
                                                      "claiming more bytes than memory)"),
    (struct.pack("<Q", 2**20), f"it accepted the connection but did not answer Dask's handshake within "
                               f"{CONNECT_DEADLINE:g} s"),  # 1 MiB promised, never sent
    (b"HTTP/1.1 400 Bad Request\r\n\r\n", "it answered, but not in Dask's protocol"),
], ids=["silent", "3 EiB length", "1 MiB promised", "http"])
def test_a_silent_or_wrong_server_fails_within_the_deadline_with_the_reason(tmp_path, capsys, answer, reason):
    """Connection and handshake share one deadline (CONNECT_DEADLINE); ``tracer movie`` then
    exits 2 with the address and the reason in one line, and writes nothing (no OUT.cache).
    The generous wall-clock bound only catches a hang."""
    pytest.importorskip("distributed")
    commands = tmp_path / "c.txt"
    commands.write_text("render 2\n")
    with tcp_server(answer) as address:
        start = time.monotonic()
        status, _, err = run(["movie", tmp_path / "m", commands, "--width", "4", "--height", "4", "--quiet",
                              "--scheduler", address], capsys)
        seconds = time.monotonic() - start
    assert status == 2 and err.startswith(f"tracer: error: cannot reach the Dask scheduler at {address}: {reason}"), err
    assert_one_line(err)
    assert seconds < CONNECT_DEADLINE + 10, seconds
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.txt"]


@pytest.mark.api
def test_the_deadline_is_the_configured_one():
    pytest.importorskip("distributed")
    with tcp_server(None) as address:
        start = time.monotonic()
        with pytest.raises(ValueError, match="within 0.5 s"):
            connect(address, timeout=0.5)
        assert time.monotonic() - start < 5
    assert CONNECT_DEADLINE == 3.0 and inspect.signature(connect).parameters["timeout"].default == CONNECT_DEADLINE


@pytest.mark.api
def test_a_scheduler_connects_and_a_worker_is_named_as_one(client):
    there = connect(client.scheduler.address)
    try:
        assert there.scheduler_info()["id"] == client.scheduler_info()["id"]
    finally:
        there.close()
    worker = next(iter(client.scheduler_info()["workers"]))
    with pytest.raises(ValueError, match=f"^cannot reach the Dask scheduler at {worker}: it is a Dask Worker, "
                                         "not a scheduler$"):
        connect(worker)
