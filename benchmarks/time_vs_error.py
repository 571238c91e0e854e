"""Run time against error: the tracer's settings measured against a converged reference render.

Run:  python benchmarks/time_vs_error.py [--quick] [--repeats N] [--seeds N] [--ref-spp N] [--reuse-refs]
                                         [--out CSV [--refs-dir DIR]]
Writes ``data/derived/time_vs_error.csv`` and the reference images with their masks (read by
``notebooks/04_time_vs_error.ipynb`` and ``paper/scripts/fig_time_vs_error.py``).  ``--quick``
(48 x 48, two seeds, one timed run per setting) writes nothing unless ``--out`` names a file,
with the references in ``--refs-dir`` (default: ``<out>_refs/`` beside it); the notebook runs it
so in quick mode.

This script renders; the study itself -- the settings swept, the references and their floor,
the error metrics, the interior and bubble pixels, the front and the verdict on the defaults
-- is :mod:`study.tradeoffs` (its docstring describes and justifies each), which the
notebook and the paper import as well.

Scenes (:func:`scene_files`): the built-in scene (``tracer.default_scene()``), six bubbles
(``data/scenes/gallery_bubbles.toml``, or ``bubbles_sky.toml`` where that file is missing), the
coursework's mixed materials (``data/scenes/fig3_5_materials.txt``: a bubble over glass, metal
and matte spheres) and three bubbles with films of 1.6-3 µm (``data/scenes/thick_films.toml``,
where ``spectral_method="auto"`` picks band averaging).  160 x 160 pixels (quick: 48 x 48).

Two references per scene (seeds 1 and ``FLOOR_SEED``), each timed once (10-30 s per bubble scene
at 160 x 160 on two cores; the whole benchmark takes three to five minutes on the shared machine):
the first is the reference, the second is scored against it (the ``floor`` row), and the two
with the scene's geometry give the interior mask (``tradeoffs.interior_mask``); the bubble mask
comes from the geometry alone.  Their mean time is the denominator of ``speedup_vs_reference``.
Sweeps, one factor at a time around the current ``tracer.DEFAULTS`` (band-averaged films when
``tracer.render_with_stats`` accepts ``spectral_method="band"``): each distinct setting is
rendered with ``--seeds`` seeds (default 3) for the errors (mean and standard deviation over
seeds) and timed ``--repeats`` times (default 9; median, min and max), the repeats interleaved
over all settings of a scene so that a disturbance on the shared machine spreads over all of
them.  Time is ``RenderStats.render_seconds`` (compilation excluded; each setting is first
rendered at 4 x 4 to load its compiled code).  The machine's load average before and after
goes into the CSV's first line.

RGB transport: ``spectral=False`` carries three linear-sRGB channels and has no wavelength, so a
thin film cannot be evaluated at all (no interference colour is possible).  With the current
tracer a bubble in RGB mode renders black, with NaN where a film is evaluated for a highlight
or a shadow; ``nonfinite_pixels`` records how many.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

from study import provenance, write_csv
from study.metrics import finite_image
from study.tradeoffs import (
    AA_DE00,
    CACHE_REFS_DIR,
    COLUMNS,
    FLOOR_SEED,
    REFERENCE,
    SUB_PIXELS,
    SWEEP_SEEDS,
    accepts_spectral_method,
    bubble_mask,
    combine_seeds,
    configurations,
    image_errors,
    interior_mask,
    key,
    pixel_hits,
    silhouette_mask,
    load_references,
    render_kwargs,
    save_references,
    settings_from_defaults,
    summary_table,
)

ROOT = Path(__file__).resolve().parents[1]
DERIVED = ROOT / "data" / "derived"
OUT_CSV = DERIVED / "time_vs_error.csv"
REFS_DIR = DERIVED / "time_vs_error_refs"
FULL_SIZE = 160
QUICK_SIZE = 48

# ------------------------------------------------------------------------------------------
# Scenes and settings
# ------------------------------------------------------------------------------------------
def scene_files():
    """{name: path or None (the built-in scene)} of the four scenes."""
    scenes = ROOT / "data" / "scenes"
    bubbles = scenes / "gallery_bubbles.toml"
    if not bubbles.exists():
        bubbles = scenes / "bubbles_sky.toml"
    return {"builtin": None, "bubbles": bubbles, "materials": scenes / "fig3_5_materials.txt",
            "thick": scenes / "thick_films.toml"}


def load_scenes():
    """{name: tracer.Scene} of the four scenes."""
    import tracer

    return {name: tracer.default_scene() if path is None else tracer.load_scene(path)
            for name, path in scene_files().items()}


def band_method_available():
    """Whether ``tracer.render_with_stats`` accepts ``spectral_method`` (band-averaged films)."""
    import tracer

    return accepts_spectral_method(tracer.render_with_stats)


def default_settings():
    """The current ``tracer.DEFAULTS`` as a setting of the study."""
    import tracer

    return settings_from_defaults(tracer.DEFAULTS)


def resolved_method(scene, s):
    """The film method setting *s* renders *scene* with (``tracer.prepare.pack.resolve_spectral_method``)."""
    from tracer.prepare.pack import resolve_spectral_method

    if not s["spectral"]:
        return ""
    return resolve_spectral_method(scene, int(s["spectral_samples"]), s["spectral_method"])


def seed_independent(scene, s):
    """Whether setting *s* renders *scene* the same for every seed: one sample per pixel (the pixel
    centre, ``tracer.kernels.sampling.stratified_offset``) and no light sampled at random (a light of
    radius > 0 is a sphere whose samples hash the seed); the rest of the tracer is deterministic."""
    return int(s["spp"]) == 1 and all(float(getattr(light, "radius", 0.0)) == 0.0 for light in scene.lights)


def geometry(scene, size):
    """``(hits, is_bubble)`` of *scene* at *size* x *size*: ``tradeoffs.pixel_hits`` from the packed
    scene's camera and spheres, and which spheres are bubbles (surface kind 0)."""
    from tracer.prepare.pack import pack_scene

    packed = pack_scene(scene, spectral_samples=16)
    if packed.tris.shape[0]:
        raise ValueError("the geometry masks handle spheres only; this scene has triangles")
    cam = packed.camera[0]
    camera = {k: np.asarray(cam[k], float) for k in ("origin", "forward", "right", "up")}
    camera["tan_half_fov"] = float(cam["tan_half_fov"])
    hits = pixel_hits(camera, packed.spheres["center"], packed.spheres["radius"], size, size)
    return hits, packed.spheres["surface"] == 0


# ------------------------------------------------------------------------------------------
# Rendering
# ------------------------------------------------------------------------------------------
def render_reference(scene, size, spp=REFERENCE["spp"], progress=None):
    """The references of *scene* at *size* x *size*, their masks, and the ideal 1-spp render.

    Returns a dict: ``image`` (the reference, seed ``REFERENCE["seed"]``, linear sRGB),
    ``image_b`` (the same settings with seed ``FLOOR_SEED``), ``seconds_runs`` (their two render
    times) and ``seconds`` (their mean), ``interior`` (``tradeoffs.interior_mask`` of the two and
    the silhouettes), ``bubble`` (``tradeoffs.bubble_mask``), ``floor_errors``
    (``tradeoffs.image_errors`` of the second reference: the floor), and ``image_ideal``,
    ``seconds_ideal``, ``ideal_errors``: the reference's transport at one sample per pixel.
    """
    import tracer

    s = dict(REFERENCE, spp=spp)
    tracer.render_with_stats(scene, **render_kwargs(s, 4, REFERENCE["seed"]))  # load compiled code
    image, stats = tracer.render_with_stats(scene, **dict(render_kwargs(s, size, REFERENCE["seed"]), progress=progress))
    image_b, stats_b = tracer.render_with_stats(scene, **dict(render_kwargs(s, size, FLOOR_SEED), progress=progress))
    ideal, stats1 = tracer.render_with_stats(scene, **render_kwargs(dict(s, spp=1), size, REFERENCE["seed"]))
    hits, is_bubble = geometry(scene, size)
    interior = interior_mask(image, image_b, silhouette_mask(hits))
    bubble = bubble_mask(hits, is_bubble)
    runs = [stats.render_seconds, stats_b.render_seconds]
    return dict(image=image, image_b=image_b, seconds=float(np.mean(runs)), seconds_runs=runs, interior=interior,
                bubble=bubble, floor_errors=image_errors(image_b, image, interior, bubble), image_ideal=ideal,
                seconds_ideal=stats1.render_seconds, ideal_errors=image_errors(ideal, image, interior, bubble))


def estimate_reference_seconds(scene, size, spp=REFERENCE["spp"], fraction=1 / 16):
    """Seconds one reference would take, from a render with about *fraction* of its pixels."""
    import tracer

    s = dict(REFERENCE, spp=spp)
    small = max(4, int(round(size * math.sqrt(fraction))))
    tracer.render_with_stats(scene, **render_kwargs(s, 4, REFERENCE["seed"]))
    _, stats = tracer.render_with_stats(scene, **render_kwargs(s, small, REFERENCE["seed"]))
    return stats.render_seconds * (size / small) ** 2


def run(size=FULL_SIZE, repeats=9, ref_spp=REFERENCE["spp"], scenes=None, band=None, references=None,
        progress=True, seeds=3):
    """Render the references and every setting; return (rows, references).

    Each distinct setting is rendered with the first *seeds* of ``tradeoffs.SWEEP_SEEDS`` for
    its errors (mean and standard deviation over seeds) and timed *repeats* times, interleaved
    (median, min and max).  *references*: {scene: reference dict} (:func:`render_reference`,
    or as loaded by ``tradeoffs.load_references``) to use instead of rendering them.
    """
    import tracer
    from tqdm import tqdm

    scenes = load_scenes() if scenes is None else scenes
    configs = configurations(default_settings(), band_method_available() if band is None else band)
    default_key = key(default_settings())
    distinct = {}
    for _, _, s in configs:
        distinct.setdefault(key(s), s)
    seed_list = SWEEP_SEEDS[:seeds]
    refs = {} if references is None else dict(references)
    total = sum(name not in refs for name in scenes) + len(scenes) * len(distinct) * (seeds + repeats)
    bar = tqdm(total=total, desc="time vs error", unit="render", disable=not progress, file=sys.stderr)
    rows = []
    for name, scene in scenes.items():
        if name not in refs:
            bar.set_postfix_str(f"{name}: references")
            refs[name] = render_reference(scene, size, ref_spp)
            bar.update()
        ref = refs[name]
        reference, interior, bubble = ref["image"], ref["interior"], ref["bubble"]
        errors, runs, rays = {}, {k: [] for k in distinct}, {}
        bar.set_postfix_str(f"{name}: errors")
        for k, s in distinct.items():
            tracer.render_with_stats(scene, **render_kwargs(s, 4))  # load this setting's compiled code
            per_seed = []
            for i, seed in enumerate(seed_list):
                if i and seed_independent(scene, s):  # the same image for every seed: render it once
                    per_seed.append(per_seed[0])
                else:
                    image, stats = tracer.render_with_stats(scene, **render_kwargs(s, size, seed))
                    per_seed.append(image_errors(image, reference, interior, bubble))
                    rays[k] = stats.rays["total"]
                bar.update()
            errors[k] = combine_seeds(per_seed)
        bar.set_postfix_str(f"{name}: timing")
        for _ in range(repeats):  # interleaved: one run of every setting, then the next round
            for k, s in distinct.items():
                _, stats = tracer.render_with_stats(scene, **render_kwargs(s, size))
                runs[k].append(stats.render_seconds)
                bar.update()
        exact = combine_seeds([dict(mean_de00=0.0, p95_de00=0.0, max_de00=0.0, rmse=0.0, interior_mean_de00=0.0,
                                    interior_p95_de00=0.0, interior_rmse=0.0, bubble_mean_de00=0.0,
                                    bubble_p95_de00=0.0, interior_fraction=float(interior.mean()),
                                    bubble_fraction=float(bubble.mean()), nonfinite_pixels=finite_image(reference)[1])])
        ref_setting = dict(REFERENCE, spp=ref_spp)
        # the reference's time: both references' runs (the same work with other seeds), whose mean is
        # the denominator of every speed-up
        rows.append(_row(name, scene, "reference", "reference", ref_setting, size, ref["seconds_runs"], exact,
                         None, ref["seconds"], False))
        rows.append(_row(name, scene, "floor", f"reference, seed {FLOOR_SEED}", ref_setting, size,
                         ref["seconds_runs"][1:], combine_seeds([ref["floor_errors"]]), None, ref["seconds"], False))
        rows.append(_row(name, scene, "ideal", "1 nm / exhaustive / 1 spp", dict(REFERENCE, spp=1), size,
                         [ref["seconds_ideal"]], combine_seeds([ref["ideal_errors"]]), None, ref["seconds"], False))
        for factor, value, s in configs:
            k = key(s)
            rows.append(_row(name, scene, factor, value, s, size, runs[k], errors[k], rays[k], ref["seconds"],
                             k == default_key))
    bar.close()
    return rows, refs


def _row(name, scene, factor, value, s, size, runs, errors, rays, ref_seconds, is_default):
    seconds = float(np.median(runs))
    return dict(
        scene=name, factor=factor, value=value, transport="spectral" if s["spectral"] else "rgb",
        spectral_samples=int(s["spectral_samples"]) if s["spectral"] else "",
        spectral_method=s["spectral_method"] if s["spectral"] else "", resolved_method=resolved_method(scene, s),
        threshold=float(s["threshold"]), spp=int(s["spp"]), depth=int(s["depth"]), width=size, height=size,
        seconds=seconds, seconds_min=float(np.min(runs)), seconds_max=float(np.max(runs)),
        seconds_runs=" ".join(f"{t:.5f}" for t in runs), rays_total="" if rays is None else int(rays),
        reference_seconds=ref_seconds, speedup_vs_reference=ref_seconds / seconds,
        is_default=int(bool(is_default)), **errors,
    )


# ------------------------------------------------------------------------------------------
# Files
# ------------------------------------------------------------------------------------------
def write_rows(rows, path, notes=()):
    """Write *rows* to *path* (:func:`study.write_csv`), each note as a leading
    ``# `` line; floats to 6 significant digits, NaN as an empty cell, columns ``tradeoffs.COLUMNS``
    (read back by ``tradeoffs.read_rows``)."""
    return write_csv(path, rows, list(notes), fieldnames=COLUMNS, float_format="{:.6g}", na_rep="",
                     lineterminator="\n", extrasaction="ignore")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help=f"{QUICK_SIZE}x{QUICK_SIZE}, one timed run, two seeds; "
                             "nothing written unless --out is given")
    parser.add_argument("--repeats", type=int, default=9, help="timed runs per setting (median, min-max)")
    parser.add_argument("--seeds", type=int, default=3,
                        help=f"seeds per setting for the errors (the first of {SWEEP_SEEDS})")
    parser.add_argument("--ref-spp", type=int, default=None,
                        help=f"samples per pixel of the references (default {REFERENCE['spp']})")
    parser.add_argument("--size", type=int, default=None, help=f"image side (default {FULL_SIZE})")
    parser.add_argument("--reuse-refs", action="store_true",
                        help="use the saved reference images (and their times) if made with the same settings")
    parser.add_argument("--out", type=Path, default=None,
                        help=f"the CSV to write (default {OUT_CSV.relative_to(ROOT)}; in quick mode none)")
    parser.add_argument("--refs-dir", type=Path, default=None,
                        help="where to write the reference images with --out (default: <out>_refs/ beside it)")
    args = parser.parse_args(argv)
    quick = args.quick or os.environ.get("BUBBLEOPTICS_QUICK", "") not in ("", "0")
    size = args.size or (QUICK_SIZE if quick else FULL_SIZE)
    repeats = 1 if quick else args.repeats
    seeds = min(2, args.seeds) if quick else args.seeds
    ref_spp = args.ref_spp or REFERENCE["spp"]

    t_start = time.perf_counter()
    load_before = os.getloadavg()[0]
    scenes = load_scenes()
    band = band_method_available()
    print(f"{size}x{size}; references: {REFERENCE['spectral_samples']} bands, {ref_spp} spp, threshold 0, "
          f"depth {REFERENCE['depth']}, seeds {REFERENCE['seed']} and {FLOOR_SEED}; defaults {default_settings()}; "
          f"band method available: {band}; {seeds} seeds, {repeats} timed runs per setting; "
          f"load average {load_before:.1f}")
    refs = None
    if args.reuse_refs:
        for folder in (REFS_DIR, CACHE_REFS_DIR):
            refs = load_references(folder, size, ref_spp)
            if refs and set(refs) >= set(scenes):
                print(f"reusing the references in {folder}")
                break
            refs = None
    if not refs:
        est = {name: 2 * estimate_reference_seconds(sc, size, ref_spp) for name, sc in scenes.items()}
        print("cost of the two references, estimated from 1/16 of the pixels: "
              + ", ".join(f"{n} {s:.0f} s" for n, s in est.items()) + f" (total {sum(est.values()):.0f} s)")
    rows, refs = run(size, repeats, ref_spp, scenes, band, refs, seeds=seeds)
    print(summary_table(rows))
    load_after = os.getloadavg()[0]
    if args.out is not None or not quick:
        out = OUT_CSV if args.out is None else args.out
        if args.out is None:  # the repository's folder, or the cache when the images are too large for it
            folder = save_references(refs, size, ref_spp, REFS_DIR, overflow=CACHE_REFS_DIR,
                                     written_by="benchmarks/time_vs_error.py")
        else:
            folder = save_references(refs, size, ref_spp, args.refs_dir or out.with_name(f"{out.stem}_refs"),
                                     written_by="benchmarks/time_vs_error.py")
        where = folder.relative_to(ROOT) if folder.is_relative_to(ROOT) else folder
        print(f"reference images: {where}"
              + (" (outside the repository: 2 MB or more)" if folder == CACHE_REFS_DIR else ""))
        notes = [
            provenance("benchmarks/time_vs_error.py" + (" --quick" if quick else ""),
                       f"machine load average {load_before:.1f} before, {load_after:.1f} after (shared machine)",
                       "regenerate with: python benchmarks/time_vs_error.py"),
            f"{size}x{size}; reference: threshold 0, {REFERENCE['spectral_samples']} bands (1 nm) over 360-780 nm, "
            f"{ref_spp} spp stratified, depth {REFERENCE['depth']}, seed {REFERENCE['seed']}; factor 'floor': the "
            f"same with seed {FLOOR_SEED} against it; images in {where}",
            f"seconds: median of {repeats} render_seconds (compilation excluded), interleaved, with min and max; "
            f"references timed once each (the reference row: both runs); sweeps around tracer.DEFAULTS {json.dumps(default_settings())}",
            f"errors: mean over seeds {list(SWEEP_SEEDS[:seeds])} (_sd: standard deviation over seeds; 1-spp renders "
            "sample the pixel centre and do not depend on the seed); dE00: study.delta_e00_images "
            "(linear sRGB, negative values clipped to 0); rmse: linear sRGB, unclipped; non-finite pixels set to 0",
            f"interior: pixels none of whose 3x3 neighbourhood is an edge: the two references differ by >= "
            f"{AA_DE00:g} dE00, or its {SUB_PIXELS}x{SUB_PIXELS} sub-pixel camera rays meet different spheres first; "
            f"bubble: pixels all of whose sub-pixel camera rays meet a bubble first; factor 'ideal': the reference's "
            "transport at 1 spp",
        ]
        write_rows(rows, out, notes)
        print(f"wrote {out}")
    print(f"total {time.perf_counter() - t_start:.0f} s; load average {load_before:.1f} before, {load_after:.1f} after")
    return 0


if __name__ == "__main__":
    sys.exit(main())
