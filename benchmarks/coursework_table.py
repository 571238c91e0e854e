"""The coursework's table 4.1 re-run: render time against trace depth for one, two and three bubbles.

Run:  python benchmarks/coursework_table.py [--repeats N] [--quick]
Writes ``data/derived/coursework_table.csv`` (read by :func:`study.load_timing`).

Setting of the coursework's table: 960x960, one sample per pixel, trace depth 1 to 10, the scenes
``data/scenes/coursework_{one_bubble,two_bubbles,three_bubbles}.txt`` (reconstructions: the coursework
does not give its scenes), each rendered pruned (the default threshold) and exhaustive (threshold
0, the coursework's tree), compilation excluded, all in one process.

Spread: every cell is timed ``--repeats`` times (default 9), *interleaved*: each repeat sweeps all
60 cells once, so a burst of other work on the shared machine disturbs one run of many cells
rather than every run of one cell.  Each cell's row has the median, the quartiles (numpy's linear
interpolation), the minimum and maximum and all runs.  The machine's load average (1 minute) before
and after goes into the header.

Thread scaling: each scene at depth 1 and 10, exhaustive, with ``numba.set_num_threads(1)`` and
``(2)``, interleaved the same way (rows of mode ``"threads 1"`` / ``"threads 2"``).

The coursework's own times (Apple M3 Pro, ``data/coursework_table_4_1.csv``) are written beside
ours, in the columns ``seed_seconds`` and ``speedup_vs_seed`` (names kept from the file's first
version; the speed-up is of our median).  Finally a fresh process is timed from start to a saved
960x960 image (compiled code comes from numba's cache).
"""

import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from study import load_coursework_table, provenance, write_csv
from study.results import image_benchmark_arguments

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "derived" / "coursework_table.csv"
COURSEWORK_TABLE = ROOT / "data" / "coursework_table_4_1.csv"
SCENES = {1: "coursework_one_bubble.txt", 2: "coursework_two_bubbles.txt", 3: "coursework_three_bubbles.txt"}
THREAD_DEPTHS = (1, 10)


def coursework_times():
    """{depth: {bubbles: seconds}} of the coursework's table 4.1."""
    table = load_coursework_table(COURSEWORK_TABLE)
    return {int(d): {nb: float(t[i]) for nb, t in table["seconds"].items()} for i, d in enumerate(table["depth"])}


def spread(times):
    """Median, quartiles, minimum and maximum of a list of seconds, as CSV columns."""
    q1, med, q3 = np.percentile(times, [25, 50, 75])
    return dict(seconds_median=float(med), seconds_q1=float(q1), seconds_q3=float(q3),
                seconds_min=float(np.min(times)), seconds_max=float(np.max(times)),
                seconds_runs=" ".join(f"{t:.4f}" for t in times))


def main(argv=None):
    args, size, repeats = image_benchmark_arguments(__doc__.splitlines()[0], OUT, 9, 2, argv)

    import numba
    import tracer
    from tqdm import tqdm

    load_before = os.getloadavg()[0]
    coursework = coursework_times()
    modes = {"pruned": tracer.DEFAULTS["threshold"], "exhaustive": 0.0}
    jobs = [(nb, depth, mode) for nb in SCENES for mode in modes for depth in range(1, 11)]
    scenes = {nb: tracer.load_scene(ROOT / "data" / "scenes" / name) for nb, name in SCENES.items()}
    tracer.render(scenes[1], width=8, height=8, depth=2, progress=False)  # load compiled code
    max_threads = numba.get_num_threads()
    times = {job: [] for job in jobs}
    stats_of = {}
    for _ in tqdm(range(repeats), desc="coursework table (repeats)", unit="sweep", disable=None):
        for job in jobs:
            nb, depth, mode = job
            _, stats = tracer.render_with_stats(scenes[nb], width=size, height=size, depth=depth, spp=1,
                                                threshold=modes[mode], progress=False)
            times[job].append(stats.render_seconds)
            stats_of[job] = stats.rays
    rows = []
    for job in jobs:
        nb, depth, mode = job
        rays = stats_of[job]
        med = float(np.median(times[job]))
        rows.append(dict(
            bubbles=nb, depth=depth, mode=mode, threshold=modes[mode], width=size, height=size,
            **spread(times[job]),
            rays_camera=rays["camera"], rays_reflected=rays["reflected"],
            rays_transmitted=rays["transmitted"], rays_shadow=rays["shadow"],
            rays_total=rays["total"], seed_seconds=coursework[depth][nb],
            speedup_vs_seed=coursework[depth][nb] / med if size == 960 else "",
        ))

    # thread scaling: exhaustive, depth 1 and 10, 1 and 2 threads, interleaved
    thread_counts = sorted({1, min(2, max_threads)})
    thread_jobs = [(nb, depth, n) for nb in SCENES for depth in THREAD_DEPTHS for n in thread_counts]
    thread_times = {job: [] for job in thread_jobs}
    for _ in tqdm(range(repeats), desc="thread scaling (repeats)", unit="sweep", disable=None):
        for job in thread_jobs:
            nb, depth, n = job
            numba.set_num_threads(n)
            _, stats = tracer.render_with_stats(scenes[nb], width=size, height=size, depth=depth, spp=1,
                                                threshold=0.0, progress=False)
            thread_times[job].append(stats.render_seconds)
            stats_of[job] = stats.rays
    numba.set_num_threads(max_threads)
    for job in thread_jobs:
        nb, depth, n = job
        rays = stats_of[job]
        rows.append(dict(bubbles=nb, depth=depth, mode=f"threads {n}", threshold=0.0, width=size, height=size,
                         **spread(thread_times[job]), rays_camera=rays["camera"],
                         rays_reflected=rays["reflected"], rays_transmitted=rays["transmitted"],
                         rays_shadow=rays["shadow"], rays_total=rays["total"]))

    def get(nb, depth, mode):
        return next(r for r in rows if r["bubbles"] == nb and r["depth"] == depth and r["mode"] == mode)

    print(f"\n{size}x{size}, 1 spp, median [min, max] of {repeats}; seconds (compilation excluded)")
    for depth in range(1, 11):
        cells = []
        for nb in SCENES:
            p, e = get(nb, depth, "pruned"), get(nb, depth, "exhaustive")
            cells.append(f"{coursework[depth][nb]:8.2f} / {p['seconds_median']:.3f} [{p['seconds_min']:.3f}, "
                         f"{p['seconds_max']:.3f}] / {e['seconds_median']:.3f} [{e['seconds_min']:.3f}, "
                         f"{e['seconds_max']:.3f}]")
        print(f"{depth:5d} | " + " | ".join(cells))
    if len(thread_counts) == 2:
        for nb in SCENES:
            for depth in THREAD_DEPTHS:
                one, two = get(nb, depth, "threads 1"), get(nb, depth, f"threads {thread_counts[1]}")
                print(f"{nb} bubble(s), depth {depth}: 1 thread {one['seconds_median']:.3f} s, 2 threads "
                      f"{two['seconds_median']:.3f} s: speed-up {one['seconds_median'] / two['seconds_median']:.2f}")

    # a fresh process, start to a saved image, compiled code from the cache
    cold = []
    out_png = Path(os.environ.get("TMPDIR", "/tmp")) / "coursework_table_cold.png"
    for _ in range(repeats):
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-m", "tracer", "image", str(ROOT / "data" / "scenes" / SCENES[3]),
                        str(out_png), "--quiet", "--width", str(size), "--height", str(size)], check=True)
        cold.append(time.perf_counter() - t0)
    print(f"fresh process to a {size}x{size} image: median {np.median(cold):.2f} s "
          f"({' '.join(f'{t:.2f}' for t in cold)})")
    rows.append(dict(bubbles=3, depth=tracer.DEFAULTS["depth"], mode="fresh process, start to saved image",
                     threshold=tracer.DEFAULTS["threshold"], width=size, height=size, **spread(cold)))
    load_after = os.getloadavg()[0]

    write_csv(args.out, rows,
              provenance("benchmarks/coursework_table.py",
                         f"machine load average {load_before:.1f} before, {load_after:.1f} after (shared machine)",
                         f"{repeats} interleaved runs per cell, numba threads {max_threads} except the threads rows",
                         "seed_seconds: the coursework's table 4.1 (Apple M3 Pro)",
                         "regenerate with: python benchmarks/coursework_table.py"),
              float_format="{:.6g}")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
