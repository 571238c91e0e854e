"""The coursework's two-beam film model in rendered images: ΔE00 against the exact Airy sum.

Each scene is rendered twice with the same settings, seed and rays, once with every bubble's
``film_model = "airy"`` (the tracer's default: the sum of all reflected beams) and once with
``"two-beam"`` (the coursework's formula, ``bubbleoptics.two_beam_reflectance``, T = 1 - R), so
the two images differ by the film model only.  The settings are converged for the comparison
(:data:`SETTINGS`: 81 point bands of about 5 nm, 4 samples per pixel, depth 10, no pruning);
the colour difference ΔE00 per pixel is ``study.metrics.delta_e00_images``
(colour-science's CIEDE2000), summarized over the pixels all of whose sub-pixel rays meet a
bubble first (``study.tradeoffs.bubble_mask``: what the film model changes directly;
other pixels change only through reflections of bubbles).

Scenes: the built-in scene (three draining bubbles, 25-950 nm, under a point light), the six
gallery bubbles under the sky (``data/scenes/gallery_bubbles.toml``) and three young films
1.6-3 um thick (``data/scenes/thick_films.toml``).

Every scene is rendered again with twice the bands and with 9 samples per pixel
(:data:`CHECKS`, rows with a ``variant``; not with ``--quick``) to show that the statistics
have converged.

Writes ``data/derived/two_beam_render.csv`` (per scene: mean, median, p95 and max ΔE00 over the
bubble pixels and over all pixels, the share of bubble pixels above ΔE00 = 1 and 2, the render
seconds of both models) and ``data/derived/two_beam_render.npz`` (8-bit display images of both
models and the ΔE00 map as float16, per scene: read by ``paper/scripts/fig_two_beam_render.py``).

    python benchmarks/two_beam_render.py [--size N] [--quick]
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys
import time
from pathlib import Path

import numpy as np

from study import provenance, write_csv
from study.metrics import delta_e00_images
from study.tradeoffs import bubble_mask, pixel_hits

ROOT = Path(__file__).resolve().parents[1]
DERIVED = ROOT / "data" / "derived"
OUT_CSV = DERIVED / "two_beam_render.csv"
OUT_NPZ = DERIVED / "two_beam_render.npz"
FULL_SIZE = 200
QUICK_SIZE = 40

#: The render settings of both models: converged for the comparison (81 bands of 5.2 nm resolve
#: the fringes of the 3 um films, whose period at 400 nm is 20 nm; no pruning).
SETTINGS = dict(depth=10, spp=4, threshold=0.0, spectral_samples=81, spectral_method="point", seed=0)
QUICK_SETTINGS = dict(SETTINGS, spp=1, spectral_samples=16)

#: Convergence checks, each scene rendered again with one setting raised: the rows with a
#: ``variant`` say how much the statistics move (the main rows have variant "").
CHECKS = {"161 bands": dict(spectral_samples=161), "9 spp": dict(spp=9)}

SCENES = {"builtin": None, "bubbles": "gallery_bubbles.toml", "thick": "thick_films.toml"}
LABELS = {"builtin": "built-in scene", "bubbles": "six bubbles under the sky", "thick": "young thick films"}

COLUMNS = ("scene", "label", "variant", "width", "height", "spectral_samples", "spp", "depth", "threshold",
           "bubble_pixels", "bubble_mean_de00", "bubble_median_de00", "bubble_p95_de00", "bubble_max_de00",
           "bubble_share_above_1", "bubble_share_above_2", "all_mean_de00", "all_p95_de00", "all_max_de00",
           "seconds_airy", "seconds_two_beam")


def load(name):
    import tracer

    path = SCENES[name]
    return tracer.default_scene() if path is None else tracer.load_scene(ROOT / "data" / "scenes" / path)


def with_model(scene, model):
    """*scene* with every bubble's ``film_model`` set to *model*."""
    return dataclasses.replace(scene, bubbles=[dataclasses.replace(b, film_model=model) for b in scene.bubbles])


def bubble_pixels(scene, size):
    """Boolean (size, size): pixels all of whose sub-pixel rays meet a bubble first."""
    from tracer.prepare.pack import pack_scene

    packed = pack_scene(scene, spectral_samples=16)
    cam = packed.camera[0]
    camera = {k: np.asarray(cam[k], float) for k in ("origin", "forward", "right", "up")}
    camera["tan_half_fov"] = float(cam["tan_half_fov"])
    hits = pixel_hits(camera, packed.spheres["center"], packed.spheres["radius"], size, size)
    return bubble_mask(hits, packed.spheres["surface"] == 0)


def measure(name, size, settings, variant=""):
    """One scene: (CSV row, {array name: array}) of both renders and their ΔE00."""
    import tracer
    from tracer.rendering.output import display_codes

    scene = load(name)
    images, seconds = {}, {}
    for model in ("airy", "two-beam"):
        image, stats = tracer.render_with_stats(with_model(scene, model), width=size, height=size, progress=False,
                                                **settings)
        images[model], seconds[model] = image, stats.render_seconds
    de = delta_e00_images(images["two-beam"], images["airy"])
    mask = bubble_pixels(scene, size)
    b = de[mask]
    row = dict(scene=name, label=LABELS[name], variant=variant, width=size, height=size,
               spectral_samples=settings["spectral_samples"], spp=settings["spp"], depth=settings["depth"], threshold=settings["threshold"],
               bubble_pixels=int(mask.sum()), bubble_mean_de00=float(b.mean()),
               bubble_median_de00=float(np.median(b)), bubble_p95_de00=float(np.percentile(b, 95)),
               bubble_max_de00=float(b.max()), bubble_share_above_1=float(np.mean(b > 1.0)),
               bubble_share_above_2=float(np.mean(b > 2.0)), all_mean_de00=float(de.mean()),
               all_p95_de00=float(np.percentile(de, 95)), all_max_de00=float(de.max()),
               seconds_airy=seconds["airy"], seconds_two_beam=seconds["two-beam"])
    display = dict(exposure=float(scene.render_defaults.get("exposure", 0.0)),
                   view=str(scene.render_defaults.get("view", "clip")))
    arrays = {f"{name}_airy": display_codes(images["airy"], **display),
              f"{name}_two_beam": display_codes(images["two-beam"], **display),
              f"{name}_de00": de.astype(np.float16), f"{name}_bubble": mask}
    return row, arrays


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=None, help=f"image size in pixels (default {FULL_SIZE})")
    ap.add_argument("--quick", action="store_true", help="a smoke test: small images, 16 bands, 1 spp")
    ap.add_argument("--out", type=Path, default=OUT_CSV, help="CSV to write (the .npz beside it)")
    ap.add_argument("--scenes", nargs="+", choices=tuple(SCENES), default=list(SCENES))
    args = ap.parse_args(argv)
    size = args.size or (QUICK_SIZE if args.quick else FULL_SIZE)
    if not 8 <= size <= 2000:
        ap.exit(2, f"two_beam_render.py: error: --size must be from 8 to 2000, got {size}\n")
    settings = QUICK_SETTINGS if args.quick else SETTINGS
    import tracer

    tracer.render(with_model(load("builtin"), "two-beam"), width=4, height=4, progress=False)  # compile first
    load_before = Path("/proc/loadavg").read_text().split()[0] if Path("/proc/loadavg").exists() else "n/a"
    t0 = time.perf_counter()
    rows, arrays = [], {}
    for name in args.scenes:
        row, arr = measure(name, size, settings)
        rows.append(row)
        arrays.update(arr)
        if not args.quick:
            for variant, change in CHECKS.items():
                check, _ = measure(name, size, dict(settings, **change), variant)
                rows.append(check)
        print(f"{name}: bubble pixels mean {row['bubble_mean_de00']:.2f}, p95 {row['bubble_p95_de00']:.2f}, "
              f"max {row['bubble_max_de00']:.2f} ΔE00", file=sys.stderr)
    load_after = Path("/proc/loadavg").read_text().split()[0] if Path("/proc/loadavg").exists() else "n/a"
    out = Path(args.out)
    comment = provenance("benchmarks/two_beam_render.py",
                         f"{os.cpu_count()} cores visible; load average {load_before} before, {load_after} after; "
                         f"{time.perf_counter() - t0:.0f} s",
                         "settings " + ", ".join(f"{k}={v}" for k, v in settings.items()) + f", {size}x{size}",
                         "ΔE00: study.metrics.delta_e00_images (colour-science CIEDE2000) of the "
                         "two-beam render against the Airy one; bubble pixels: tradeoffs.bubble_mask",
                         "regenerate with: python benchmarks/two_beam_render.py" + (" --quick" if args.quick else ""))
    write_csv(out, rows, comment, fieldnames=COLUMNS)
    np.savez_compressed(out.with_suffix(".npz"), scenes=np.array(args.scenes), **arrays)
    print(f"wrote {out} and {out.with_suffix('.npz')}", file=sys.stderr)


if __name__ == "__main__":
    main()
