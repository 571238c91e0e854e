"""Rays per level of the ray tree, and run time, of the coursework's scenes with two bubble models.

Run:  python benchmarks/coursework_rays.py [--repeats N] [--quick] [--models thin,two]
Writes ``data/derived/coursework_rays.csv`` (read by :func:`study.coursework.load_rays`).

Why: the coursework's times grow by a factor *b* of about 1.7 per trace depth (its table 4.1; the fit
:func:`study.fit_affine_exponential`), ours barely grow.  Its bubble was two concentric
spheres (its scene format: an outer and an inner sphere, each with a material); ours is one
thin-film surface.  This counts the rays of each level of the exhaustive tree (threshold 0) for

* ``thin film``: ``data/scenes/coursework_{one_bubble,two_bubbles,three_bubbles}.txt`` (the
  coursework's bubble read as one sphere with a 100 nm film, as the tracer reads it), and
* ``two spheres``: ``data/scenes/coursework_two_sphere_*.txt``, the same bubbles modelled
  literally as two clear refracting spheres, index 1.3 outside radius 100, air inside radius 99.9,

at 960x960, one sample per pixel, depths 1-10.  The tracer's counters give the secondary rays
(reflected + transmitted) of the whole tree up to depth *d*; with threshold 0 the tree at depth
*d* is the tree at depth *d* − 1 plus one more generation, so the rays of level *d* are the
difference of the totals at depths *d* and *d* − 1 (:func:`study.coursework.rays_per_level`; no
change to the integrator).  Level 1 is the camera rays.

Times: each (model, bubbles, depth) cell rendered ``--repeats`` times (default 5), interleaved
(each repeat sweeps every cell), compilation excluded; median, quartiles, minimum, maximum and
all runs.  The machine's load average before and after is in the header.
"""

import argparse
import os
import sys
from pathlib import Path

import numpy as np

from study import provenance, write_csv

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "derived" / "coursework_rays.csv"
NAMES = {1: "one_bubble", 2: "two_bubbles", 3: "three_bubbles"}
MODELS = {
    "thin film": {nb: f"coursework_{name}.txt" for nb, name in NAMES.items()},
    "two spheres": {nb: f"coursework_two_sphere_{name}.txt" for nb, name in NAMES.items()},
}
SHORT = {"thin": "thin film", "two": "two spheres"}
DEPTHS = range(1, 11)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--quick", action="store_true", help="240x240, 1 repeat (smoke test)")
    parser.add_argument("--models", default="thin,two", help="comma-separated: thin, two (default both)")
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    if args.repeats < 1:
        parser.error("--repeats must be at least 1")
    try:
        models = [SHORT[m.strip()] for m in args.models.split(",") if m.strip()]
    except KeyError as exc:
        parser.error(f"--models: unknown model {exc} (choose from {', '.join(SHORT)})")
    size, repeats = (240, 1) if args.quick else (960, args.repeats)

    import tracer
    from tqdm import tqdm

    from study.coursework import rays_per_level

    load_before = os.getloadavg()[0]
    scenes = {(m, nb): tracer.load_scene(ROOT / "data" / "scenes" / MODELS[m][nb]) for m in models for nb in NAMES}
    for scene in scenes.values():  # load the compiled code
        tracer.render(scene, width=8, height=8, depth=2, threshold=0.0, progress=False)
    jobs = [(m, nb, d) for m in models for nb in NAMES for d in DEPTHS]
    times = {job: [] for job in jobs}
    rays = {}
    for _ in tqdm(range(repeats), desc="coursework rays (repeats)", unit="sweep", disable=None):
        for job in jobs:
            m, nb, d = job
            _, stats = tracer.render_with_stats(scenes[m, nb], width=size, height=size, depth=d, spp=1,
                                                threshold=0.0, progress=False)
            times[job].append(stats.render_seconds)
            if job in rays and rays[job] != stats.rays:
                raise RuntimeError(f"{job}: ray counts differ between runs ({rays[job]} and {stats.rays})")
            rays[job] = stats.rays
    load_after = os.getloadavg()[0]

    rows = []
    for m in models:
        for nb in NAMES:
            secondary = [rays[m, nb, d]["reflected"] + rays[m, nb, d]["transmitted"] for d in DEPTHS]
            level = rays_per_level(list(DEPTHS), secondary, rays[m, nb, 1]["camera"])
            for i, d in enumerate(DEPTHS):
                r = rays[m, nb, d]
                q1, med, q3 = np.percentile(times[m, nb, d], [25, 50, 75])
                rows.append(dict(
                    model=m, bubbles=nb, depth=d, threshold=0.0, width=size, height=size,
                    seconds_median=float(med), seconds_q1=float(q1), seconds_q3=float(q3),
                    seconds_min=float(np.min(times[m, nb, d])), seconds_max=float(np.max(times[m, nb, d])),
                    seconds_runs=" ".join(f"{t:.4f}" for t in times[m, nb, d]),
                    rays_camera=r["camera"], rays_reflected=r["reflected"], rays_transmitted=r["transmitted"],
                    rays_shadow=r["shadow"], rays_total=r["total"], rays_level=int(level[i]),
                    branching=level[i] / level[i - 1] if i >= 2 and level[i - 1] > 0 else "",
                ))
            print(f"{m}, {nb} bubble(s): rays per level {' '.join(str(int(v)) for v in level)}; "
                  f"t(10)/t(1) = {np.median(times[m, nb, 10]) / np.median(times[m, nb, 1]):.1f}")
    write_csv(args.out, rows,
              provenance("benchmarks/coursework_rays.py",
                         f"machine load average {load_before:.1f} before, {load_after:.1f} after (shared machine)",
                         f"{size}x{size}, 1 spp, threshold 0 (exhaustive), {repeats} interleaved runs per cell",
                         "rays_level: rays of tree level d (level 1: camera rays; else the reflected + transmitted"
                         " rays at depth d minus those at depth d-1); branching: rays_level(d) / rays_level(d-1)",
                         "regenerate with: python benchmarks/coursework_rays.py"),
              float_format="{:.6g}")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
