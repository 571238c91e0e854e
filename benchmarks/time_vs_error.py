"""Run time against error: the tracer's settings measured against a converged reference render.

Run:  python benchmarks/time_vs_error.py [--quick] [--repeats N] [--ref-spp N] [--reuse-refs]
                                         [--out CSV [--refs-dir DIR]]
Writes ``data/derived/time_vs_error.csv`` and the reference images (read by
``notebooks/04_time_vs_error.ipynb`` and ``paper/scripts/fig_time_vs_error.py``).  ``--quick``
(48 x 48, one timed run per setting) writes nothing unless ``--out`` names a file, with the
references in ``--refs-dir`` (default: ``<out>_refs/`` beside it); the notebook runs it so in
quick mode.

This script renders; the study itself -- the settings swept, the reference, the error metrics,
the interior pixels, the front and the verdict on the defaults -- is
:mod:`bubbleoptics.study.tradeoffs` (its docstring describes each), which the notebook and the
paper import as well.

Scenes (:func:`scene_files`): the built-in scene (``tracer.default_scene()``), six bubbles
(``data/scenes/gallery_bubbles.toml``, or ``bubbles_sky.toml`` where that file is missing) and
the coursework's mixed materials (``data/scenes/fig3_5_materials.txt``: a bubble over glass,
metal and matte spheres).  160 x 160 pixels (quick: 48 x 48).

The reference is rendered once per scene and timed once (20-30 s per bubble scene at 160 x 160
on two cores; the whole benchmark takes about two minutes); its time is the denominator of
``speedup_vs_reference``.  Sweeps, one factor at a time around the current ``tracer.DEFAULTS``
(band-averaged films when ``tracer.render_with_stats`` accepts ``spectral_method="band"``):
each distinct setting is rendered once for the errors and timed ``--repeats`` times (median),
the repeats interleaved over all settings of a scene so that a disturbance on the shared
machine spreads over all of them.  Time is ``RenderStats.render_seconds`` (compilation
excluded; each setting is first rendered at 4 x 4 to load its compiled code).

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

from bubbleoptics.study import provenance, write_csv
from bubbleoptics.study.metrics import finite_image
from bubbleoptics.study.tradeoffs import (
    AA_DE00,
    CACHE_REFS_DIR,
    COLUMNS,
    REFERENCE,
    accepts_spectral_method,
    configurations,
    image_errors,
    interior_mask,
    key,
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
    """{name: path or None (the built-in scene)} of the three scenes."""
    scenes = ROOT / "data" / "scenes"
    bubbles = scenes / "gallery_bubbles.toml"
    if not bubbles.exists():
        bubbles = scenes / "bubbles_sky.toml"
    return {"builtin": None, "bubbles": bubbles, "materials": scenes / "fig3_5_materials.txt"}


def load_scenes():
    """{name: tracer.Scene} of the three scenes."""
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


# ------------------------------------------------------------------------------------------
# Rendering
# ------------------------------------------------------------------------------------------
def render_reference(scene, size, spp=REFERENCE["spp"], progress=None):
    """The reference of *scene* at *size* x *size*, and the same transport at 1 spp.

    Returns a dict: ``image`` (the reference, linear sRGB), ``seconds`` (its render time, one
    run), ``image_1spp`` and ``seconds_1spp`` (the reference's transport with one sample per
    pixel: the anti-aliasing floor), ``interior`` (``tradeoffs.interior_mask``) and
    ``floor_errors`` (``tradeoffs.image_errors`` of the 1-spp image).
    """
    import tracer

    s = dict(REFERENCE, spp=spp)
    seed = REFERENCE["seed"]
    tracer.render_with_stats(scene, **render_kwargs(s, 4, seed))  # load compiled code
    image, stats = tracer.render_with_stats(scene, **dict(render_kwargs(s, size, seed), progress=progress))
    one, stats1 = tracer.render_with_stats(scene, **render_kwargs(dict(s, spp=1), size, seed))
    interior = interior_mask(image, one)
    return dict(image=image, seconds=stats.render_seconds, image_1spp=one, seconds_1spp=stats1.render_seconds,
                interior=interior, floor_errors=image_errors(one, image, interior))


def estimate_reference_seconds(scene, size, spp=REFERENCE["spp"], fraction=1 / 16):
    """Seconds the reference would take, from a render with about *fraction* of its pixels."""
    import tracer

    s = dict(REFERENCE, spp=spp)
    small = max(4, int(round(size * math.sqrt(fraction))))
    tracer.render_with_stats(scene, **render_kwargs(s, 4, REFERENCE["seed"]))
    _, stats = tracer.render_with_stats(scene, **render_kwargs(s, small, REFERENCE["seed"]))
    return stats.render_seconds * (size / small) ** 2


def run(size=FULL_SIZE, repeats=3, ref_spp=REFERENCE["spp"], scenes=None, band=None, references=None,
        progress=True):
    """Render the references and every setting; return (rows, references).

    *references*: {scene: reference dict} (:func:`render_reference`) to use instead of
    rendering them.
    """
    import tracer
    from tqdm import tqdm

    scenes = load_scenes() if scenes is None else scenes
    configs = configurations(default_settings(), band_method_available() if band is None else band)
    default_key = key(default_settings())
    distinct = {}
    for _, _, s in configs:
        distinct.setdefault(key(s), s)
    refs = {} if references is None else dict(references)
    total = sum(name not in refs for name in scenes) + len(scenes) * len(distinct) * (1 + repeats)
    bar = tqdm(total=total, desc="time vs error", unit="render", disable=not progress, file=sys.stderr)
    rows = []
    for name, scene in scenes.items():
        if name not in refs:
            bar.set_postfix_str(f"{name}: reference")
            refs[name] = render_reference(scene, size, ref_spp)
            bar.update()
        ref = refs[name]
        reference, interior = ref["image"], ref["interior"]
        errors, runs, rays = {}, {k: [] for k in distinct}, {}
        bar.set_postfix_str(f"{name}: errors")
        for k, s in distinct.items():
            tracer.render_with_stats(scene, **render_kwargs(s, 4))  # load this setting's compiled code
            image, stats = tracer.render_with_stats(scene, **render_kwargs(s, size))
            errors[k] = image_errors(image, reference, interior)
            rays[k] = stats.rays["total"]
            bar.update()
        bar.set_postfix_str(f"{name}: timing")
        for _ in range(repeats):  # interleaved: one run of every setting, then the next round
            for k, s in distinct.items():
                _, stats = tracer.render_with_stats(scene, **render_kwargs(s, size))
                runs[k].append(stats.render_seconds)
                bar.update()
        exact = dict(mean_de00=0.0, p95_de00=0.0, max_de00=0.0, rmse=0.0, interior_mean_de00=0.0,
                     interior_p95_de00=0.0, interior_rmse=0.0, interior_fraction=float(interior.mean()),
                     nonfinite_pixels=finite_image(reference)[1])
        rows.append(_row(name, "reference", "reference", dict(REFERENCE, spp=ref_spp), size, [ref["seconds"]],
                         exact, None, ref["seconds"], False))
        rows.append(_row(name, "floor", "1 nm / exhaustive / 1 spp", dict(REFERENCE, spp=1), size,
                         [ref["seconds_1spp"]], ref["floor_errors"], None, ref["seconds"], False))
        for factor, value, s in configs:
            k = key(s)
            rows.append(_row(name, factor, value, s, size, runs[k], errors[k], rays[k], ref["seconds"],
                             k == default_key))
    bar.close()
    return rows, refs


def _row(scene, factor, value, s, size, runs, errors, rays, ref_seconds, is_default):
    seconds = float(np.median(runs))
    return dict(
        scene=scene, factor=factor, value=value, transport="spectral" if s["spectral"] else "rgb",
        spectral_samples=int(s["spectral_samples"]) if s["spectral"] else "",
        spectral_method=s["spectral_method"] if s["spectral"] else "", threshold=float(s["threshold"]),
        spp=int(s["spp"]), depth=int(s["depth"]), width=size, height=size, seconds=seconds,
        seconds_runs=" ".join(f"{t:.5f}" for t in runs), rays_total="" if rays is None else int(rays),
        reference_seconds=ref_seconds, speedup_vs_reference=ref_seconds / seconds,
        is_default=int(bool(is_default)), **errors,
    )


# ------------------------------------------------------------------------------------------
# Files
# ------------------------------------------------------------------------------------------
def write_rows(rows, path, notes=()):
    """Write *rows* to *path* (:func:`bubbleoptics.study.write_csv`), each note as a leading
    ``# `` line; floats to 6 significant digits, NaN as an empty cell, columns ``tradeoffs.COLUMNS``
    (read back by ``tradeoffs.read_rows``)."""
    return write_csv(path, rows, list(notes), fieldnames=COLUMNS, float_format="{:.6g}", na_rep="",
                     lineterminator="\n", extrasaction="ignore")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help=f"{QUICK_SIZE}x{QUICK_SIZE}, one repeat, nothing written unless --out is given")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs per setting (median)")
    parser.add_argument("--ref-spp", type=int, default=REFERENCE["spp"], help="samples per pixel of the reference")
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

    t_start = time.perf_counter()
    scenes = load_scenes()
    band = band_method_available()
    print(f"{size}x{size}; reference: {REFERENCE['spectral_samples']} bands, {args.ref_spp} spp, threshold 0, "
          f"depth {REFERENCE['depth']}; defaults {default_settings()}; band method available: {band}")
    refs = None
    if args.reuse_refs:
        for folder in (REFS_DIR, CACHE_REFS_DIR):
            refs = load_references(folder, size, args.ref_spp)
            if refs:
                print(f"reusing the references in {folder}")
                break
    if not refs:
        est = {name: estimate_reference_seconds(sc, size, args.ref_spp) for name, sc in scenes.items()}
        print("reference cost, estimated from 1/16 of the pixels: "
              + ", ".join(f"{n} {s:.0f} s" for n, s in est.items()) + f" (total {sum(est.values()):.0f} s)")
    rows, refs = run(size, repeats, args.ref_spp, scenes, band, refs)
    print(summary_table(rows))
    if args.out is not None or not quick:
        out = OUT_CSV if args.out is None else args.out
        if args.out is None:  # the repository's folder, or the cache when the images are too large for it
            folder = save_references(refs, size, args.ref_spp, REFS_DIR, overflow=CACHE_REFS_DIR,
                                     written_by="benchmarks/time_vs_error.py")
        else:
            folder = save_references(refs, size, args.ref_spp, args.refs_dir or out.with_name(f"{out.stem}_refs"),
                                     written_by="benchmarks/time_vs_error.py")
        where = folder.relative_to(ROOT) if folder.is_relative_to(ROOT) else folder
        print(f"reference images: {where}"
              + (" (outside the repository: 2 MB or more)" if folder == CACHE_REFS_DIR else ""))
        notes = [
            provenance("benchmarks/time_vs_error.py" + (" --quick" if quick else ""),
                       "regenerate with: python benchmarks/time_vs_error.py"),
            f"{size}x{size}; reference: threshold 0, {REFERENCE['spectral_samples']} bands (1 nm) over 360-780 nm, "
            f"{args.ref_spp} spp stratified, depth {REFERENCE['depth']}, seed {REFERENCE['seed']}, timed once; "
            f"images in {where}",
            f"seconds: median of {repeats} render_seconds (compilation excluded), interleaved; sweeps around "
            f"tracer.DEFAULTS {json.dumps(default_settings())}",
            "dE00: bubbleoptics.study.delta_e00_images (linear sRGB, negative values clipped to 0); rmse: linear "
            "sRGB, unclipped; non-finite pixels set to 0",
            f"interior: pixels none of whose 3x3 neighbourhood changes by >= {AA_DE00:g} dE00 when the reference "
            "is rendered at 1 spp (factor 'floor': that 1-spp render, timed once)",
        ]
        write_rows(rows, out, notes)
        print(f"wrote {out}")
    print(f"total {time.perf_counter() - t_start:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
