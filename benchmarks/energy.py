"""Energy conservation of the tracer: white-furnace renders, and what pruning changes.

Run:  python benchmarks/energy.py [--size N] [--quick]
Writes ``data/derived/energy.csv``.

In a uniform environment every escaping ray sees the same radiance, so a lossless object must
render as the environment itself: a pixel is the environment times the sum of its ray tree's
leaf throughputs, which is 1 when every split conserves energy (R + T = 1 for a free film,
F + (1 - F) = 1 for clear glass) and every cut branch is closed with what it still carries
(``tracer.kernels.integrator``; the coursework's estimator dropped them, and deep bubbles went dark).
Each case is rendered in a uniform white environment and compared with the environment alone
rendered with the same channels (as ``tests/tracer/test_energy.py`` does); reported are the largest and
the mean absolute deviation over pixels and channels (linear sRGB, environment 1), the largest
excess (a pixel brighter than the environment), and the rays traced.  Cases, each at depth 10
with no pruning (threshold 0, the exhaustive tree) and with the default pruning:

* ``bubble``: one water bubble, draining film 0-1000 nm (point-sampled bands);
* ``thick_bubble``: one bubble of 20 um (band-averaged films);
* ``two_beam_bubble``: the draining bubble with the coursework's two-beam film (T = 1 - R);
* ``glass``: a clear glass sphere (n = 1.5, transmission 1, no local terms);
* ``foam``: 1000 water bubbles of 0-2 um (``tests/tracer/test_energy.py``'s foam).

And ``absorbing_bubble``: a dyed film (n = 1.36 + 0.02i, 300 nm), whose pixels must equal the
closed form B (R + T^2 / (1 - R)) with R, T from bubbleoptics (largest relative deviation).
Finally ``pruning_builtin``: the built-in scene (non-uniform light) at depth 10, default pruning
against none: the CIEDE2000 difference (mean, p95 and max over pixels) and the rays saved.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

from study import provenance, write_csv

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "derived" / "energy.csv"
FULL_SIZE = 64
QUICK_SIZE = 16
DEPTH = 10
WHITE = (1.0, 1.0, 1.0)
COLUMNS = ("case", "depth", "threshold", "width", "height", "max_abs_deviation", "mean_abs_deviation",
           "max_excess", "max_rel_deviation_closed_form", "rays_total", "mean_de00", "p95_de00", "max_de00")


def scenes():
    """{case: tracer.Scene} of the white-furnace cases."""
    from tracer.scene import Bubble, Camera, Environment, FilmProfile, Material, Scene, Sphere

    env = Environment(kind="constant", color=WHITE)
    cam = Camera(position=(0.0, 0.0, 3.0), look_at=(0.0, 0.0, 0.0), fov_deg=45.0)

    def one(film, **kw):
        return Scene(bubbles=[Bubble((0.0, 0.0, 0.0), 1.0, film, **kw)], camera=cam, environment=env,
                     ambient=(0.0, 0.0, 0.0))

    draining = FilmProfile("draining", top_nm=0.0, bottom_nm=1000.0)
    glass = Material(color=(1, 1, 1), ambient=0, diffuse=0, specular=0, transmission=1.0, ior=1.5)
    rng = np.random.default_rng(7)
    foam = [Bubble(tuple(rng.uniform(-2, 2, 3)), float(rng.uniform(0.05, 0.3)),
                   FilmProfile("uniform", thickness_nm=float(rng.uniform(0, 2000))), n_film="water")
            for _ in range(1000)]
    return {
        "bubble": one(draining, n_film="water"),
        "thick_bubble": one(FilmProfile("uniform", thickness_nm=20000.0), n_film="water"),
        "two_beam_bubble": one(draining, n_film="water", film_model="two-beam"),
        "glass": Scene(spheres=[Sphere((0.0, 0.0, 0.0), 1.0, glass)], camera=cam, environment=env,
                       ambient=(0.0, 0.0, 0.0)),
        "foam": Scene(bubbles=foam, camera=Camera(position=(0, 0, 6.0), look_at=(0, 0, 0), fov_deg=50),
                      environment=env, ambient=(0.0, 0.0, 0.0)),
    }


def background(scene, size, spectral):
    import tracer
    from tracer.scene import Scene

    return tracer.render(Scene(camera=scene.camera, environment=scene.environment), width=size, height=size,
                         spectral=spectral, progress=False)


def furnace_rows(size):
    import tracer

    rows = []
    for case, scene in scenes().items():
        spectral = bool(scene.bubbles)
        bg = background(scene, size, spectral)
        for threshold in (0.0, tracer.DEFAULTS["threshold"]):
            img, stats = tracer.render_with_stats(scene, width=size, height=size, depth=DEPTH, threshold=threshold,
                                                  progress=False)
            dev = img - bg
            rows.append(dict(case=case, depth=DEPTH, threshold=threshold, width=size, height=size,
                             max_abs_deviation=float(np.abs(dev).max()), mean_abs_deviation=float(np.abs(dev).mean()),
                             max_excess=float(dev.max()), rays_total=stats.rays["total"]))
    return rows


def absorbing_row(size):
    """The dyed film against the closed form, on the pixels whose camera ray meets the bubble."""
    import bubbleoptics as bo
    import tracer
    from tracer.scene import Bubble, Camera, Environment, FilmProfile, Scene

    n = 1.36 + 0.02j
    scene = Scene(bubbles=[Bubble((0.0, 0.0, 0.0), 1.0, FilmProfile("uniform", thickness_nm=300.0), n_film=n)],
                  camera=Camera(position=(0.0, 0.0, 3.0), look_at=(0.0, 0.0, 0.0), fov_deg=45.0),
                  environment=Environment(kind="constant", color=WHITE), ambient=(0.0, 0.0, 0.0))
    img, stats = tracer.render_with_stats(scene, width=size, height=size, depth=DEPTH, threshold=0.0, progress=False)
    packed = tracer.prepare.pack.pack_scene(scene)
    cam = packed.camera[0]
    o = np.asarray(cam["origin"], float)
    cosines = np.zeros((size, size))
    for y in range(size):  # the ray-sphere quadratic of each pixel-centre ray (unit sphere at the origin)
        for x in range(size):
            d = np.array(tracer.kernels.sampling.camera_ray(cam, x + 0.5, y + 0.5, size, size))
            b = o @ d
            disc = b * b - (o @ o - 1.0)
            if disc > 0:
                cosines[y, x] = abs(d @ (o + (-b - math.sqrt(disc)) * d))
    hit = cosines > 1e-3
    theta = np.arccos(np.clip(cosines[hit], 0.0, 1.0))[:, None]
    wl = packed.wavelengths
    R = bo.film_reflectance(wl, 300.0, theta, n_film=n)
    T = bo.film_transmittance(wl, 300.0, theta, n_film=n)
    expected = ((packed.rgb_basis @ np.array(WHITE)) * (R + T * T / (1 - R))) @ packed.to_rgb.T
    rel = np.abs(img[hit] - expected) / np.abs(expected).max(axis=-1, keepdims=True)
    return dict(case="absorbing_bubble", depth=DEPTH, threshold=0.0, width=size, height=size,
                max_rel_deviation_closed_form=float(rel.max()), rays_total=stats.rays["total"])


def pruning_row(size):
    """The built-in scene, default pruning against the exhaustive tree."""
    import tracer
    from study.metrics import delta_e00_images

    scene = tracer.default_scene()
    full, s0 = tracer.render_with_stats(scene, width=size, height=size, depth=DEPTH, threshold=0.0, progress=False)
    pruned, s1 = tracer.render_with_stats(scene, width=size, height=size, depth=DEPTH, progress=False)
    de = delta_e00_images(pruned, full)
    return [dict(case="pruning_builtin", depth=DEPTH, threshold=0.0, width=size, height=size,
                 rays_total=s0.rays["total"]),
            dict(case="pruning_builtin", depth=DEPTH, threshold=tracer.DEFAULTS["threshold"], width=size,
                 height=size, max_abs_deviation=float(np.abs(pruned - full).max()),
                 mean_abs_deviation=float(np.abs(pruned - full).mean()), rays_total=s1.rays["total"],
                 mean_de00=float(de.mean()), p95_de00=float(np.percentile(de, 95)), max_de00=float(de.max()))]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=None, help=f"image size in pixels (default {FULL_SIZE})")
    ap.add_argument("--quick", action="store_true", help=f"{QUICK_SIZE} x {QUICK_SIZE} pixels (a smoke test)")
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args(argv)
    size = args.size or (QUICK_SIZE if args.quick else FULL_SIZE)
    if not 4 <= size <= 1000:
        ap.exit(2, f"energy.py: error: --size must be from 4 to 1000, got {size}\n")
    t0 = time.perf_counter()
    rows = furnace_rows(size) + [absorbing_row(size)] + pruning_row(size)
    comment = provenance("benchmarks/energy.py", f"{os.cpu_count()} cores visible; {time.perf_counter() - t0:.0f} s",
                         "white furnace: deviation from the environment alone (linear sRGB, environment 1)",
                         "regenerate with: python benchmarks/energy.py" + (" --quick" if args.quick else ""))
    write_csv(args.out, rows, comment, fieldnames=COLUMNS, float_format="{:.3g}", na_rep="")
    for r in rows:
        print({k: v for k, v in r.items() if k in ("case", "threshold", "max_abs_deviation", "max_excess",
                                                   "max_rel_deviation_closed_form", "rays_total", "max_de00")},
              file=sys.stderr)
    print(f"wrote {args.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
