"""Speed of the film-flow simulation: time a step on three grids, both models.

Run:  python benchmarks/film_flow.py [--repeats N] [--quick] [--out PATH]
Writes ``data/derived/film_flow.csv``.

For each grid (64x128, 128x256, 256x512) and model (``plug_flow``, ``rigid_drainage``), with
the default :class:`bubbleoptics.filmflow.FilmParameters` and the step of Huang et al. (2020),
dt = 5 ms: a model is made, one step is run untimed (numba's cache load / compilation), then
*repeats* timed runs of *n* steps each (n so that a run takes about half a second), with 1
numba thread and with all (``--threads``); the columns give the median seconds a step and its [min, max] over the runs, the CPU seconds a
step (this process, :func:`time.process_time`; on this shared machine the wall time also
carries the other processes' load), steps per second and simulated seconds per wall second
(from the median), and the simulation cost of a 10-second movie at 30 fps played in real
time (10 s of film time = 2100 steps of 1/210 s, the largest step <= 5 ms that divides a
frame, 7 a frame, 300 saved frames; keeping the frames, h copied to nm, is timed with it in
``movie_sim_seconds``).  ``movie_render_seconds``: the tracer's cost of those 300 frames at
:data:`RENDER` (480 x 480, the render defaults: depth 10, 1 spp, 16 bands) on all cores, a
bubble of the simulated film under the sky seen from a little above (``tracer.scene.simulated``),
estimated as 300 x the median of :data:`RENDER_SAMPLES` frames spread over the movie (each
rendered once, after one untimed frame; ``movie_render_frame_seconds_min``/``_max`` give
their spread); ``movie_seconds`` is simulation plus rendering.

Rigid drainage at 5 ms is shown for comparison only: its time scale is τ ≈ 3000 s, so a movie
of it would be a time-lapse with steps of seconds (each step then takes its own CFL substeps).
"""

import argparse
import math
import os
import statistics
import sys
import time
from pathlib import Path

import numba
import numpy as np

from bubbleoptics.filmflow import FilmGrid, FilmParameters, PlugFlow, RigidDrainage
from study import provenance, write_csv

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "derived" / "film_flow.csv"
GRIDS = ((64, 128), (128, 256), (256, 512))
DT = 0.005  # s, Huang et al. (2020) config.txt timePerStep
MOVIE = dict(seconds=10.0, fps=30)
TARGET = dict(grid="128x256", steps_per_second=200)
RENDER = dict(width=480, height=480)
RENDER_SAMPLES = 12


def time_steps(model, n, repeats):
    """Wall and CPU seconds per step of *repeats* runs of *n* steps (after one untimed step)."""
    state = model.step(model.initial_state(seed=0), DT)
    walls, cpus = [], []
    for _ in range(repeats):
        w0, c0 = time.perf_counter(), time.process_time()
        for _ in range(n):
            state = model.step(state, DT)
        walls.append((time.perf_counter() - w0) / n)
        cpus.append((time.process_time() - c0) / n)
    assert np.all(np.isfinite(state.h)) and state.h.min() >= 0
    return walls, cpus


def time_movie(model):
    """Wall seconds of the simulation of a 10-s, 30-fps movie (one run; frames kept in nm):
    steps of 1/210 s (4.76 ms, the largest <= 5 ms that divides a frame), 7 a frame."""
    per_frame = math.ceil(1 / (MOVIE["fps"] * DT))
    dt = 1 / (MOVIE["fps"] * per_frame)
    model.step(model.initial_state(seed=0), dt)
    t0 = time.perf_counter()
    series = model.run(t_end=MOVIE["seconds"], dt=dt, save_every=per_frame, seed=0)
    wall = time.perf_counter() - t0
    frames = len(series) - 1
    assert frames == MOVIE["seconds"] * MOVIE["fps"], frames
    return wall, frames, int(round(MOVIE["seconds"] / dt)), series


def time_movie_render(series):
    """Seconds a frame of the simulated film's movie takes to render (:data:`RENDER`): one
    untimed frame, then :data:`RENDER_SAMPLES` frames at film times spread over the series."""
    import tracer
    from tracer.scene import Bubble, Camera, Environment, FilmProfile, Scene

    r = series.grid.radius
    film = FilmProfile(kind="simulated", series=series)
    scene = Scene(bubbles=[Bubble(center=(0.0, 0.0, 0.0), radius=r, film=film, name="bubble")],
                  camera=Camera(position=(0.0, 1.5 * r, 4.0 * r), look_at=(0.0, 0.0, 0.0), fov_deg=40.0),
                  environment=Environment(kind="sky"))
    times = np.linspace(series.times[0], series.times[-1], RENDER_SAMPLES)
    scene.bubbles[0].film.time_s = float(times[0])
    tracer.render(scene, **RENDER, progress=False)  # the kernels from numba's cache
    seconds = []
    for t in times:
        scene.bubbles[0].film.time_s = float(t)
        t0 = time.perf_counter()
        tracer.render(scene, **RENDER, progress=False)
        seconds.append(time.perf_counter() - t0)
    return seconds


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--quick", action="store_true", help="the two small grids, 2 repeats, no movie (smoke test)")
    parser.add_argument("--out", type=Path, default=OUT)
    parser.add_argument("--threads", default=None,
                        help="numba thread counts to time, comma-separated (default: 1 and all cores)")
    args = parser.parse_args(argv)
    most = numba.config.NUMBA_NUM_THREADS
    threads = sorted({1, most}) if args.threads is None else [int(x) for x in args.threads.split(",")]
    if not all(1 <= t <= most for t in threads):
        parser.error(f"--threads must be between 1 and {most}")
    repeats = 2 if args.quick else args.repeats
    grids = GRIDS[:2] if args.quick else GRIDS
    params = FilmParameters()
    load_start = os.getloadavg()[0]
    rows = []
    for nt, nph in grids:
        for cls in (PlugFlow, RigidDrainage):
            for nthreads in threads:
                numba.set_num_threads(nthreads)
                model = cls(params, FilmGrid(nt, nph, params.radius))
                n = max(10, int(0.5 / (2e-7 * nt * nph)))  # about 0.5 s a run at ~0.2 µs a cell
                walls, cpus = time_steps(model, n, repeats)
                med = statistics.median(walls)
                row = dict(model=cls.name, grid=f"{nt}x{nph}", cells=nt * nph, threads=nthreads, dt_seconds=DT,
                           steps_per_run=n, repeats=repeats, step_seconds_median=med, step_seconds_min=min(walls),
                           step_seconds_max=max(walls), step_cpu_seconds_median=statistics.median(cpus),
                           steps_per_second=1 / med, simulated_seconds_per_wall_second=DT / med)
                if not args.quick and cls is PlugFlow and nthreads == max(threads):
                    wall, frames, steps, series = time_movie(model)
                    numba.set_num_threads(most)  # the renders on all cores
                    per_frame = time_movie_render(series)
                    numba.set_num_threads(nthreads)
                    render = frames * statistics.median(per_frame)
                    row.update(movie_frames=frames, movie_steps=steps, movie_sim_seconds=wall,
                               movie_render_seconds=render, movie_render_frame_seconds_min=min(per_frame),
                               movie_render_frame_seconds_max=max(per_frame), movie_seconds=wall + render)
                rows.append(row)
                print(f"{cls.name:15s} {nt:4d}x{nph:<4d} {nthreads} thr {med * 1e3:8.3f} ms/step [{min(walls) * 1e3:.3f}, "
                      f"{max(walls) * 1e3:.3f}] cpu {statistics.median(cpus) * 1e3:.3f} ms  {1 / med:7.1f} steps/s  "
                      f"{DT / med:6.3f} sim s per s"
                      + (f"  movie sim {row['movie_sim_seconds']:.2f} s + render {row['movie_render_seconds']:.1f} s "
                         f"(a frame {row['movie_render_frame_seconds_min']:.3f}-"
                         f"{row['movie_render_frame_seconds_max']:.3f} s)" if "movie_sim_seconds" in row else ""))
    fields = ["model", "grid", "cells", "threads", "dt_seconds", "steps_per_run", "repeats", "step_seconds_median",
              "step_seconds_min", "step_seconds_max", "step_cpu_seconds_median", "steps_per_second",
              "simulated_seconds_per_wall_second", "movie_frames", "movie_steps", "movie_sim_seconds", "movie_render_seconds",
              "movie_render_frame_seconds_min", "movie_render_frame_seconds_max", "movie_seconds"]
    load = os.getloadavg()[0]
    comment = [
        provenance("benchmarks/film_flow.py", f"numba {numba.__version__}, threads {threads}, "
                   f"threading layer {numba.config.THREADING_LAYER}", f"load average {load_start:.2f} at the start, {load:.2f} at the end (other processes share the cores)",
                   "regenerate with: python benchmarks/film_flow.py" + (" --quick" if args.quick else "")
                   + (f" --threads {args.threads}" if args.threads is not None else "")),
        "step_cpu_seconds_median: CPU time of this process a step (all its threads); with 1 thread the cost of "
        "a step on one core, less affected by the other processes than the wall time (caches are still shared)",
        f"default FilmParameters, dt = {DT} s; movie: {MOVIE['seconds']:g} s of film time at {MOVIE['fps']} fps "
        f"(plug flow, 2100 steps of 1/210 s); movie_render_seconds: 300 x the median of {RENDER_SAMPLES} frames "
        f"rendered at {RENDER['width']}x{RENDER['height']} (tracer defaults, all threads)",
        f"target: {TARGET['grid']} plug flow at >= {TARGET['steps_per_second']} steps/s",
    ]
    write_csv(args.out, rows, comment, fieldnames=fields)
    print(f"wrote {args.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
