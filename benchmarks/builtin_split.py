"""Where the built-in scene's time goes: variants of it against the floor, in one process.

Run:  python benchmarks/builtin_split.py [--repeats N] [--quick] [--out PATH]
Writes ``data/derived/builtin_split.csv`` (docs/performance.md, "What limits it", reads it).

The built-in scene (:func:`tracer.default_scene`: three bubbles of draining, swirling films of
water, a sky, one point light) is rendered at its defaults on one numba thread beside variants
that each take one thing away, so that the difference says what that thing costs:

* ``no swirl``: the films' swirl amplitude 0 (the draining law only: one ``sqrt`` per hit
  instead of the swirl's sine waves);
* ``uniform films``: every film a uniform 500 nm (the film's R and T are kept per angle, so a
  chord's second hit costs no film evaluation, :mod:`tracer.kernels.surfaces.soap_film`);
* ``n = 1.33``: a constant film index instead of water's dispersion (the same per-band work:
  a check that dispersion costs nothing at render time);
* ``no light``: the point light removed (no shadow rays, no highlights);
* ``black environment``: no sky (escaping rays add nothing and cost one test);
* ``depth 1``: only the camera rays' first hits.

Each variant's render is paired with a run of the floor kernel just before it
(:func:`study.floor.paired_render`, the same size and thread count); the ratio of the two is
robust to the machine's load.  Medians, minima and maxima over the repeats.
"""

import dataclasses
import os
import sys
from pathlib import Path

import numba
import numpy as np

from study.floor import paired_render, run_floor  # the same floor as throughput.csv
from study.results import image_benchmark_arguments, provenance, write_csv

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "derived" / "builtin_split.csv"


def variants(tracer):
    """(name, scene, depth) of the built-in scene and its variants (depth None: the default)."""
    from tracer.scene import Environment

    base = tracer.default_scene()

    def films(**change):
        return dataclasses.replace(base, bubbles=[dataclasses.replace(b, film=dataclasses.replace(b.film, **change))
                                                  for b in base.bubbles])

    return [
        ("built-in", base, None),
        ("no swirl", films(swirl=0.0), None),
        ("uniform films", films(kind="uniform", thickness_nm=500.0), None),
        ("n = 1.33", dataclasses.replace(base, bubbles=[dataclasses.replace(b, n_film=1.33) for b in base.bubbles]),
         None),
        ("no light", dataclasses.replace(base, lights=[]), None),
        ("black environment", dataclasses.replace(base, environment=Environment(kind="constant", color=(0.0, 0.0, 0.0))),
         None),
        ("depth 1", base, 1),
    ]


def main(argv=None):
    args, size, repeats = image_benchmark_arguments(__doc__.splitlines()[0], OUT, 7, 2, argv)
    import tracer
    from bubbleoptics.resources import prefer_workqueue_threads

    prefer_workqueue_threads()
    floor_out = np.zeros((size, size))
    todo = variants(tracer)
    numba.set_num_threads(1)
    run_floor(size, floor_out)
    for _, scene, depth in todo:  # compile or load every kernel before timing
        tracer.render(scene, width=8, height=8, depth=depth, progress=False)
    samples = {name: [] for name, _, _ in todo}
    for rep in range(repeats):
        for name, scene, depth in todo:
            samples[name].append(paired_render(tracer, scene, size, depth, floor_out))
        print(f"repeat {rep + 1}/{repeats} done", file=sys.stderr)
    base = np.median([s[0] for s in samples["built-in"]])
    rows = []
    for name, runs in samples.items():
        sec = np.array([r[0] for r in runs])
        ratio = sec / np.array([r[1] for r in runs])
        rows.append(dict(variant=name, width=size, height=size, threads=1, repeats=len(runs),
                         seconds_median=float(np.median(sec)), seconds_min=float(sec.min()),
                         seconds_max=float(sec.max()), ratio_to_floor_median=float(np.median(ratio)),
                         ratio_to_floor_min=float(ratio.min()), ratio_to_floor_max=float(ratio.max()),
                         share_of_builtin=float(np.median(sec) / base), rays_total=runs[0][2]))
        r = rows[-1]
        print(f"{name:20s} {r['seconds_median']:.4f} s [{r['seconds_min']:.4f}, {r['seconds_max']:.4f}]  "
              f"x floor {r['ratio_to_floor_median']:5.1f} [{r['ratio_to_floor_min']:.1f}, {r['ratio_to_floor_max']:.1f}]"
              f"  {r['share_of_builtin']:.2f} of the built-in  {r['rays_total']} rays")
    write_csv(args.out, rows, provenance("benchmarks/builtin_split.py",
                                         f"{os.cpu_count()} cores visible, numba threads 1; "
                                         "regenerate with: python benchmarks/builtin_split.py"),
              float_format="{:.6g}")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
