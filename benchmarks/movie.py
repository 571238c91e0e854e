"""Movie throughput: serial against a Dask LocalCluster, Dask's overhead a frame, the encoder's share.

Run:  python benchmarks/movie.py [--repeats N] [--quick]
Writes ``data/derived/movie.csv``.

The movie is ``data/movies/builtin_orbit.txt`` on the built-in scene: 48 frames at 480x480,
the render defaults otherwise (depth 10, 1 spp), written as an ``.mp4``. Every repeat starts
from an empty frame cache (a new temporary folder), so every frame is rendered.

* ``serial``: :func:`tracer.render_movie` in this process (numba's threads: all cores);
* ``dask``: the same on a running :class:`distributed.LocalCluster` of 2 one-thread workers
  (:func:`tracer.rendering.dask.local_cluster`), started once before the repeats (its start-up and the
  workers' first frame, which loads the kernels from numba's cache, are timed on their own).
  Dask's task stream gives each frame's compute time on its worker; the overhead a frame is
  ``(wall time x workers - sum of compute times) / frames``: scheduling, transfer of the
  scene and of the PNG, the cache write, and any worker left idle;
* ``tiles``: one large image (1920x1080, 4 spp; 192x108 with ``--quick``) rendered here (numba's
  threads) and as tiles of rows on the same cluster (``tracer.render(..., client=...)``,
  :func:`tracer.rendering.dask.render_tiles`), interleaved, the two images checked equal bit for bit;
* ``encode``: the assembly of the .mp4 from the cached PNGs (reading them, ffmpeg's H.264),
  part of each run above, reported as its share of the wall time.

``frame_cpu_seconds`` is the CPU time a frame (this process's for ``serial``, the workers' for
``dask``, from :func:`time.process_time`): on this shared machine the wall times are inflated
by the other processes, the CPU time is what a core of its own would take.

From the measured one-thread CPU time a frame and the overhead, the ``model`` rows
estimate a 3840x2160, 64-spp, one-minute movie (1440 frames at 24 fps) on 8, 64 and 512
one-core workers. The model assumes: the cost of a frame scales with its pixels times its
samples (camera rays dominate; the scene and the depth are the same), workers are as fast as
this machine's cores and each renders whole frames (so at most 1440 workers are used, and
with 512 workers the last of ceil(1440 / 512) = 3 rounds renders 416 frames and leaves 96
workers, 19 %, idle), the
overhead a frame stays what it is here (transfer of a 4K PNG of about 10-25 MB is not in it:
a fast network adds about 0.1-0.2 s a frame), and the encoder runs once, at the end, on one
machine, at the speed measured here scaled by pixels.
"""

import statistics
import sys
import tempfile
import time
from pathlib import Path

from study.results import image_benchmark_arguments, provenance, write_csv

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "derived" / "movie.csv"
COMMANDS = ROOT / "data" / "movies" / "builtin_orbit.txt"
WORKERS = 2
TILE_IMAGE = dict(width=1920, height=1080, spp=4)


def spread(values):
    return statistics.median(values), min(values), max(values)


def run_movie(scene, size, client=None, stream=None):
    import tracer

    with tempfile.TemporaryDirectory(prefix="movie-bench-") as tmp:
        t0 = time.perf_counter()
        if stream is not None:
            from distributed import get_task_stream

            with get_task_stream(client) as ts:
                result = tracer.render_movie(scene, COMMANDS, Path(tmp) / "orbit.mp4", width=size, height=size,
                                             client=client, progress=False)
            stream.extend(ts.data)
        else:
            result = tracer.render_movie(scene, COMMANDS, Path(tmp) / "orbit.mp4", width=size, height=size,
                                         client=client, progress=False)
        wall = time.perf_counter() - t0
    assert result.rendered == result.frames
    return wall, result


def main(argv=None):
    import numba

    import tracer
    from distributed import Client

    from tracer.rendering.dask import local_cluster

    args, size, repeats = image_benchmark_arguments(__doc__.splitlines()[0], OUT, 3, 1, argv, size=480,
                                                    quick_size=96)
    import os

    load_before = os.getloadavg()[0]
    scene = tracer.default_scene()
    tracer.render(scene, width=8, height=8, progress=False)  # the kernels from numba's cache
    rows = []
    n_frames = 48

    serial, serial_cpu = [], []
    for _ in range(repeats):
        c0 = time.process_time()
        serial.append(run_movie(scene, size))
        serial_cpu.append((time.process_time() - c0) / n_frames)
    walls = [w for w, _ in serial]
    enc = [r.encode_seconds for _, r in serial]
    med, lo, hi = spread(walls)
    rows.append(dict(case="serial", workers=1, threads=numba.get_num_threads(), frames=n_frames, width=size,
                     height=size, seconds_median=med, seconds_min=lo, seconds_max=hi,
                     frames_per_second=n_frames / med, encode_seconds_median=statistics.median(enc),
                     encode_share=statistics.median(e / w for e, w in zip(enc, walls)),
                     frame_cpu_seconds=statistics.median(serial_cpu)))
    print(f"serial: {med:.2f} s ({lo:.2f}-{hi:.2f}) for {n_frames} frames at {size}x{size}", file=sys.stderr)

    t0 = time.perf_counter()
    cluster = local_cluster(WORKERS)
    client = Client(cluster)
    startup = time.perf_counter() - t0
    try:
        t0 = time.perf_counter()
        with tempfile.TemporaryDirectory() as tmp:  # each worker's first frame: imports, numba's cache
            tl = tracer.Timeline(scene).render(1).camera_orbit(1).render(1)
            tracer.render_movie(scene, tl, Path(tmp) / "warm", width=8, height=8, client=client, progress=False)
        warm = time.perf_counter() - t0
        dist, overhead, compute, enc, walls, cpu = [], [], [], [], [], []
        for _ in range(repeats):
            stream = []
            c0 = client.run(time.process_time)
            wall, result = run_movie(scene, size, client, stream)
            c1 = client.run(time.process_time)
            cpu.append(sum(c1[w] - c0[w] for w in c1) / n_frames)
            d = [sum(s["stop"] - s["start"] for s in task["startstops"] if s["action"] == "compute")
                 for task in stream if str(task["key"]).startswith("tracer-frame-")]
            assert len(d) == n_frames, len(d)
            render_wall = wall - result.encode_seconds
            walls.append(wall)
            enc.append(result.encode_seconds)
            compute.append(statistics.mean(d))
            overhead.append((render_wall * WORKERS - sum(d)) / n_frames)
        med, lo, hi = spread(walls)
        o_med, o_lo, o_hi = spread(overhead)
        c_med = statistics.median(compute)
        rows.append(dict(case="dask", workers=WORKERS, threads=1, frames=n_frames, width=size, height=size,
                         seconds_median=med, seconds_min=lo, seconds_max=hi, frames_per_second=n_frames / med,
                         encode_seconds_median=statistics.median(enc),
                         encode_share=statistics.median(e / w for e, w in zip(enc, walls)),
                         frame_compute_seconds=c_med, frame_cpu_seconds=statistics.median(cpu),
                         overhead_per_frame_seconds=o_med,
                         overhead_min=o_lo, overhead_max=o_hi, overhead_fraction=o_med / c_med,
                         cluster_startup_seconds=startup, first_frame_seconds=warm))
        print(f"dask x{WORKERS}: {med:.2f} s ({lo:.2f}-{hi:.2f}); a frame {c_med:.3f} s on a worker, overhead "
              f"{o_med * 1000:.1f} ms ({o_lo * 1000:.1f}-{o_hi * 1000:.1f}) = {o_med / c_med:.1%}; cluster start "
              f"{startup:.1f} s, first frame {warm:.1f} s", file=sys.stderr)
        # one large image: here against tiles on the cluster, interleaved
        import numpy as np

        shrink = 10 if args.quick else 1
        big = dict(width=TILE_IMAGE["width"] // shrink, height=TILE_IMAGE["height"] // shrink, spp=TILE_IMAGE["spp"])
        here_t, tiles_t = [], []
        for _ in range(repeats):
            t0 = time.perf_counter()
            here = tracer.render(scene, **big, progress=False)
            here_t.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            there = tracer.render(scene, **big, progress=False, client=client)
            tiles_t.append(time.perf_counter() - t0)
            assert np.array_equal(here, there)
        for case, times, workers, threads in (("image here", here_t, 1, numba.get_num_threads()),
                                              ("image tiles", tiles_t, WORKERS, 1)):
            med, lo, hi = spread(times)
            rows.append(dict(case=case, workers=workers, threads=threads, frames=1, width=big["width"],
                             height=big["height"], seconds_median=med, seconds_min=lo, seconds_max=hi))
        ratio = [t / h for t, h in zip(tiles_t, here_t)]
        print(f"image {big['width']}x{big['height']} {big['spp']} spp: here {statistics.median(here_t):.2f} s, tiles "
              f"on {WORKERS} workers {statistics.median(tiles_t):.2f} s (ratio {statistics.median(ratio):.2f}, "
              f"{min(ratio):.2f}-{max(ratio):.2f}), equal bit for bit", file=sys.stderr)
    finally:
        client.close()
        cluster.close()

    # the model: a 4K, 64-spp, one-minute movie (study.movie_cost.model_movie_seconds)
    from study.movie_cost import MODEL_MOVIE as MODEL
    from study.movie_cost import model_movie_seconds

    encode_per_frame = statistics.median(enc) / n_frames  # of the measured movie
    for w in (8, 64, 512):
        seconds, frame, rounds, encode_model = model_movie_seconds(w, statistics.median(cpu), o_med, startup,
                                                                   encode_per_frame, size * size)
        rows.append(dict(case="model 3840x2160 64spp 1440 frames", workers=w, threads=1, frames=MODEL["frames"],
                         width=MODEL["width"], height=MODEL["height"], frame_compute_seconds=frame,
                         overhead_per_frame_seconds=o_med, overhead_fraction=o_med / frame,
                         seconds_median=seconds, frames_per_second=MODEL["frames"] / seconds,
                         encode_seconds_median=encode_model,
                         encode_share=encode_model / seconds,
                         efficiency=MODEL["frames"] * frame / (w * seconds)))
        print(f"model, {w} workers: {seconds / 3600:.2f} h ({rounds} rounds of {frame:.0f} s)", file=sys.stderr)

    fields = ["case", "workers", "threads", "frames", "width", "height", "seconds_median", "seconds_min",
              "seconds_max", "frames_per_second", "encode_seconds_median", "encode_share", "frame_compute_seconds",
              "frame_cpu_seconds", "overhead_per_frame_seconds", "overhead_min", "overhead_max", "overhead_fraction",
              "cluster_startup_seconds", "first_frame_seconds", "efficiency"]
    load = f"machine load average {load_before:.1f} before, {os.getloadavg()[0]:.1f} after (shared machine)"
    note = (f"{load}; {repeats} repeats, median (min-max); {n_frames} frames of data/movies/builtin_orbit.txt at "
            f"{size}x{size}, depth 10, 1 spp, .mp4; model rows: see benchmarks/movie.py's docstring")
    write_csv(args.out, rows, [provenance("benchmarks/movie.py", note,
                                          "regenerate with: python benchmarks/movie.py")], fieldnames=fields,
              na_rep="")
    print(args.out)


if __name__ == "__main__":
    main()
