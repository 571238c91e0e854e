"""The coursework's table 4.1 re-run: render time against trace depth for one, two and three bubbles.

Run:  python benchmarks/coursework_table.py [--repeats N] [--quick]
Writes ``data/derived/coursework_table.csv`` (read by :func:`bubbleoptics.study.load_timing`).

Setting of the coursework's table: 960x960, one sample per pixel, trace depth 1 to 10, the scenes
``data/scenes/coursework_{one_bubble,two_bubbles,three_bubbles}.txt`` (reconstructions: the coursework
does not give its scenes), each rendered pruned (the default threshold) and exhaustive (threshold
0, the coursework's tree), compilation excluded, median of ``--repeats`` runs, all in one process.
The coursework's own times (Apple M3 Pro, ``data/coursework_table_4_1.csv``) are written beside
ours, in the columns ``seed_seconds`` and ``speedup_vs_seed`` (names kept from the file's first
version).  Finally a fresh process is timed from start to a saved 960x960 image (compiled code
comes from numba's cache).
"""

import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from bubbleoptics.study import load_coursework_table, provenance, write_csv
from bubbleoptics.study.results import image_benchmark_arguments

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "derived" / "coursework_table.csv"
COURSEWORK_TABLE = ROOT / "data" / "coursework_table_4_1.csv"
SCENES = {1: "coursework_one_bubble.txt", 2: "coursework_two_bubbles.txt", 3: "coursework_three_bubbles.txt"}


def coursework_times():
    """{depth: {bubbles: seconds}} of the coursework's table 4.1."""
    table = load_coursework_table(COURSEWORK_TABLE)
    return {int(d): {nb: float(t[i]) for nb, t in table["seconds"].items()} for i, d in enumerate(table["depth"])}


def main(argv=None):
    args, size, repeats = image_benchmark_arguments(__doc__.splitlines()[0], OUT, 3, 1, argv)

    import tracer
    from tqdm import tqdm

    coursework = coursework_times()
    modes = {"pruned": tracer.DEFAULTS["threshold"], "exhaustive": 0.0}
    rows = []
    jobs = [(nb, depth, mode) for nb in SCENES for mode in modes for depth in range(1, 11)]
    scenes = {nb: tracer.load_scene(ROOT / "data" / "scenes" / name) for nb, name in SCENES.items()}
    tracer.render(scenes[1], width=8, height=8, depth=2, progress=False)  # load compiled code
    for nb, depth, mode in tqdm(jobs, desc="coursework table", unit="render", disable=None):
        times = []
        for _ in range(repeats):
            _, stats = tracer.render_with_stats(scenes[nb], width=size, height=size, depth=depth, spp=1,
                                                threshold=modes[mode], progress=False)
            times.append(stats.render_seconds)
        med = float(np.median(times))
        rows.append(dict(
            bubbles=nb, depth=depth, mode=mode, threshold=modes[mode], width=size, height=size,
            seconds_median=med, seconds_runs=" ".join(f"{t:.4f}" for t in times),
            rays_camera=stats.rays["camera"], rays_reflected=stats.rays["reflected"],
            rays_transmitted=stats.rays["transmitted"], rays_shadow=stats.rays["shadow"],
            rays_total=stats.rays["total"], seed_seconds=coursework[depth][nb],
            speedup_vs_seed=coursework[depth][nb] / med if size == 960 else "",
        ))

    def get(nb, depth, mode):
        return next(r for r in rows if r["bubbles"] == nb and r["depth"] == depth and r["mode"] == mode)

    print(f"\n{size}x{size}, 1 spp, median of {repeats}; seconds (compilation excluded)")
    print("depth | " + " | ".join(f"{nb} bubble{'s' if nb > 1 else ''}: coursework / pruned / exhaustive"
                                  for nb in SCENES))
    for depth in range(1, 11):
        cells = [f"{coursework[depth][nb]:8.2f} / {get(nb, depth, 'pruned')['seconds_median']:6.3f} / "
                 f"{get(nb, depth, 'exhaustive')['seconds_median']:6.3f}" for nb in SCENES]
        print(f"{depth:5d} | " + " | ".join(cells))
    for mode in modes:
        for nb in SCENES:
            g = get(nb, 10, mode)["seconds_median"] / get(nb, 1, mode)["seconds_median"]
            print(f"{mode:10s} {nb} bubble(s): depth 10 / depth 1 = {g:5.2f}x "
                  f"(coursework {coursework[10][nb] / coursework[1][nb]:.0f}x)")
    t3 = get(3, 10, "pruned")["seconds_median"]
    print(f"three bubbles, depth 10, pruned: {t3:.3f} s; the coursework's {coursework[10][3]} s is "
          f"{coursework[10][3] / t3:,.0f}x that (target: at least 10,000x)")

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
                     threshold=tracer.DEFAULTS["threshold"], width=size, height=size,
                     seconds_median=float(np.median(cold)), seconds_runs=" ".join(f"{t:.4f}" for t in cold)))

    write_csv(args.out, rows,
              provenance("benchmarks/coursework_table.py", "seed_seconds: the coursework's table 4.1 (Apple M3 Pro)"),
              float_format=None)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
