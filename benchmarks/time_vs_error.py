"""Run time against error: the tracer's settings measured against a converged reference render.

Run:  python benchmarks/time_vs_error.py [--quick] [--repeats N] [--ref-spp N] [--reuse-refs]
Writes ``data/derived/time_vs_error.csv`` and the reference images (read by
``notebooks/04_time_vs_error.ipynb`` and ``paper/scripts/fig_time_vs_error.py``).  The notebook
loads this file by path and calls the same functions (in quick mode, live and smaller).

Scenes (:func:`scene_files`): the built-in scene (``tracer.default_scene()``), six bubbles
(``data/scenes/gallery_bubbles.toml``, or ``bubbles_sky.toml`` where that file is missing) and
the seed's mixed materials (``data/scenes/fig3_5_materials.txt``: a bubble over glass, metal and
matte spheres).  160 x 160 pixels (quick: 48 x 48).

Reference (:data:`REFERENCE`): the exhaustive tree (threshold 0), 421 bands of 1 nm over
360-780 nm, 16 stratified samples per pixel, trace depth 16, seed 1 (the swept renders use the
default seed 0, so no swept render shares the reference's sample positions).  It is rendered
once per scene and timed once (20-30 s per bubble scene at 160 x 160 on two cores; the whole
benchmark takes about two minutes); its time is the denominator of ``speedup_vs_reference``.

Sweeps, one factor at a time around the current ``tracer.DEFAULTS`` (:func:`configurations`):
spectral sampling (RGB transport, 3-81 point-sampled bands, and 3-16 band-averaged bands when
``tracer.render_with_stats`` accepts ``spectral_method="band"``), pruning threshold, samples
per pixel and trace depth, plus a small grid of combined settings.  Each distinct setting is
rendered once for the errors and timed ``--repeats`` times (median), the repeats interleaved
over all settings of a scene so that a disturbance on the shared machine spreads over all of
them.  Time is ``RenderStats.render_seconds`` (compilation excluded; each setting is first
rendered at 4 x 4 to load its compiled code).

Errors against the reference (:func:`image_errors`): per-pixel CIEDE2000
(``tracer.study.delta_e00`` on linear sRGB, *negative values clipped to 0 first*: spectral
transport can leave saturated film colours slightly outside the sRGB gamut, and L*a*b* of a
negative RGB is not a colour), its mean and 95th percentile, and the RMSE over all pixels and
channels in linear sRGB (unclipped).  Non-finite pixels (RGB transport of a bubble, see below)
are counted and set to 0, as ``tracer.save_image`` does.  Besides all pixels, the same metrics
on *interior* pixels only (:func:`interior_mask`): pixels none of whose 3 x 3 neighbourhood
changes by ``AA_DE00`` (1 ΔE00) or more when the reference's transport is rendered with one
sample per pixel instead of 16 -- away from silhouettes and every other edge that
anti-aliasing changes.  There the error is the transport's (spectral sampling, pruning, depth);
at edges it is dominated by anti-aliasing, which only more samples per pixel reduce.  (A plain
edge detector on the reference's colours, :func:`contrast_mask`, would also discard the films'
interference fringes, i.e. most of each bubble, where the spectral error is.)  The reference's
transport at 1 spp is also a row of its own, factor ``floor``: the error that remains at 1 spp
however good the transport.

RGB transport: ``spectral=False`` carries three linear-sRGB channels and has no wavelength, so a
thin film cannot be evaluated at all (no interference colour is possible).  With the current
tracer a bubble in RGB mode renders black, with NaN where a film is evaluated for a highlight
or a shadow; ``nonfinite_pixels`` records how many.

The front and the defaults (:func:`assess`, used by the notebook): a setting qualifies when on
every scene it meets the targets (mean ΔE00 <= 0.5, at least 20x faster than the reference) and
no other setting is as accurate and faster by more than the timing noise
(:func:`timing_tolerance`); the proposal is the most accurate qualifying setting among those
within that noise of the fastest.
"""

from __future__ import annotations

import argparse
import datetime
import inspect
import json
import math
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

sys.path.append(str(Path(__file__).resolve().parent))  # for scripts loaded by file path (notebooks)
from _results import write_csv as write_results_csv  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DERIVED = ROOT / "data" / "derived"
OUT_CSV = DERIVED / "time_vs_error.csv"
REFS_DIR = DERIVED / "time_vs_error_refs"
#: Where the reference images go when they would take REFS_MAX_BYTES or more in the repository.
CACHE_REFS_DIR = (Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
                  / "bubbleoptics" / "time_vs_error_refs")
REFS_MAX_BYTES = 2_000_000

FULL_SIZE = 160
QUICK_SIZE = 48

#: The reference render: exhaustive, 1 nm bands (421 over 360-780 nm), 16 spp, depth 16.
REFERENCE = dict(spectral=True, spectral_samples=421, spectral_method="point", threshold=0.0, spp=16, depth=16,
                 seed=1)

#: The swept values of each factor (the others held at the current defaults).
SPECTRAL_POINT = (3, 4, 8, 16, 32, 81)
SPECTRAL_BAND = (3, 4, 8, 16)
THRESHOLDS = (0.0, 1e-4, 1e-3, 1e-2, 3e-2, 0.1)
SPPS = (1, 4, 9, 16)
DEPTHS = (1, 2, 3, 4, 6, 8, 10)
#: The combined grid (x spectral methods): spectral samples x threshold x spp.
GRID = dict(spectral_samples=(8, 16), threshold=(1e-3, 1e-2), spp=(1, 4))

#: A pixel is *interior* when anti-aliasing changes no pixel of its 3 x 3 neighbourhood by
#: AA_DE00 or more (CIEDE2000; see :func:`interior_mask`).  About one just-noticeable difference.
AA_DE00 = 1.0
#: Threshold of the plain colour-contrast edge detector :func:`contrast_mask` (for comparison).
CONTRAST_DE00 = 5.0

#: Targets of the study: mean ΔE00 at most this, at least this many times faster than the reference.
TARGET_MEAN_DE00 = 0.5
TARGET_SPEEDUP = 20.0

COLUMNS = (
    "scene", "factor", "value", "transport", "spectral_samples", "spectral_method", "threshold", "spp", "depth",
    "width", "height", "seconds", "seconds_runs", "mean_de00", "p95_de00", "max_de00", "rmse",
    "interior_mean_de00", "interior_p95_de00", "interior_rmse", "interior_fraction", "nonfinite_pixels",
    "rays_total", "reference_seconds", "speedup_vs_reference", "is_default",
)


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


SCENE_LABELS = {"builtin": "built-in scene (3 bubbles)", "bubbles": "six bubbles (gallery)",
                "materials": "bubble and spheres (materials)"}


def load_scenes():
    """{name: tracer.Scene} of the three scenes."""
    import tracer

    return {name: tracer.default_scene() if path is None else tracer.load_scene(path)
            for name, path in scene_files().items()}


def band_method_available():
    """Whether ``tracer.render_with_stats`` accepts ``spectral_method`` (band-averaged films)."""
    import tracer

    return "spectral_method" in inspect.signature(tracer.render_with_stats).parameters


def default_settings():
    """The current ``tracer.DEFAULTS`` as a setting (see :func:`configurations`)."""
    import tracer

    d = tracer.DEFAULTS
    return dict(spectral=True, spectral_samples=int(d["spectral_samples"]),
                spectral_method=str(d.get("spectral_method", "point")), threshold=float(d["threshold"]),
                spp=int(d["spp"]), depth=int(d["depth"]))


def key(s):
    """A hashable identity of a setting (RGB transport ignores the spectral fields)."""
    if not s["spectral"]:
        return ("rgb", 0, "", float(s["threshold"]), int(s["spp"]), int(s["depth"]))
    return ("spectral", int(s["spectral_samples"]), s["spectral_method"], float(s["threshold"]), int(s["spp"]),
            int(s["depth"]))


def configurations(band=None):
    """[(factor, value, setting)] of the study: one-factor sweeps around the defaults, then the grid.

    A setting is a dict with ``spectral`` (bool: spectral or RGB transport), ``spectral_samples``,
    ``spectral_method`` (``"point"``: film at the band centre; ``"band"``: band-averaged film;
    ``"auto"``: the tracer's choice between them, ``tracer.pack.resolve_spectral_method``),
    ``threshold``, ``spp`` and ``depth``.  *band*: include the band-averaged method (default:
    when the tracer accepts it).  Settings repeat across factors (every sweep passes through
    the defaults); :func:`run` renders each distinct one once.
    """
    if band is None:
        band = band_method_available()
    centre = default_settings()
    out = [("default", "default", dict(centre))]
    out.append(("spectral", "rgb", dict(centre, spectral=False)))
    for n in SPECTRAL_POINT:
        # at the default band count the sweep passes through the defaults themselves, whose method
        # may be "auto" (point sampling unless a film aliases: on the study's scenes, point)
        same = n == centre["spectral_samples"] and centre["spectral_method"] == "auto"
        out.append(("spectral", f"{n}", dict(centre) if same else dict(centre, spectral_samples=n,
                                                                         spectral_method="point")))
    if band:
        for n in SPECTRAL_BAND:
            out.append(("spectral", f"{n} band", dict(centre, spectral_samples=n, spectral_method="band")))
    for t in THRESHOLDS:
        out.append(("threshold", f"{t:g}", dict(centre, threshold=t)))
    for s in SPPS:
        out.append(("spp", f"{s}", dict(centre, spp=s)))
    for d in DEPTHS:
        out.append(("depth", f"{d}", dict(centre, depth=d)))
    methods = ("point", "band") if band else ("point",)
    for m in methods:
        for n in GRID["spectral_samples"]:
            for t in GRID["threshold"]:
                for s in GRID["spp"]:
                    label = f"{n}{' band' if m == 'band' else ''} / {t:g} / {s} spp"
                    out.append(("grid", label, dict(centre, spectral_samples=n, spectral_method=m, threshold=t, spp=s)))
    return out


def render_kwargs(s, size, seed=0):
    """Keyword arguments of ``tracer.render_with_stats`` for setting *s*."""
    kw = dict(width=size, height=size, depth=int(s["depth"]), spp=int(s["spp"]), threshold=float(s["threshold"]),
              seed=seed, spectral=bool(s["spectral"]), progress=False)
    if s["spectral"]:
        kw["spectral_samples"] = int(s["spectral_samples"])
        kw["spectral_method"] = s["spectral_method"]  # always: the tracer's default may be "auto"
    return kw


# ------------------------------------------------------------------------------------------
# Errors
# ------------------------------------------------------------------------------------------
def finite(image):
    """(image with non-finite values set to 0, number of pixels that had one)."""
    image = np.asarray(image, dtype=float)
    bad = ~np.isfinite(image).all(axis=-1)
    return np.where(np.isfinite(image), image, 0.0), int(bad.sum())


def de00_map(image, reference):
    """Per-pixel ΔE00 of two linear-sRGB images, negative values clipped to 0 first."""
    from tracer.study import delta_e00

    return delta_e00(np.clip(image, 0.0, None), np.clip(reference, 0.0, None))


def contrast_mask(reference, edge_de00=CONTRAST_DE00):
    """Boolean (H, W): pixels whose 3 x 3 neighbourhood in *reference* stays within *edge_de00*.

    For each pixel, the largest ΔE00 between it and its eight neighbours (edges replicated at
    the image border).  A plain edge detector on the reference's colours; *not* the study's
    interior (:func:`interior_mask`), because a film's interference fringes are edges of
    colour too (the notebook compares the two).
    """
    ref = np.clip(np.asarray(reference, dtype=float), 0.0, None)
    h, w, _ = ref.shape
    padded = np.pad(ref, ((1, 1), (1, 1), (0, 0)), mode="edge")
    contrast = np.zeros((h, w))
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            if dy == 0 and dx == 0:
                continue
            shifted = padded[1 + dy:1 + dy + h, 1 + dx:1 + dx + w]
            contrast = np.maximum(contrast, de00_map(shifted, ref))
    return contrast < edge_de00


def interior_mask(reference, reference_1spp, aa_de00=AA_DE00):
    """Boolean (H, W): pixels away from every edge that anti-aliasing changes.

    *reference_1spp* is the reference's transport (1 nm bands, exhaustive, depth 16) with one
    sample per pixel, at the pixel centre; its ΔE00 against the reference is the error that
    no spectral, pruning or depth setting removes at 1 spp (silhouettes, reflected edges,
    highlights smaller than a pixel).  Pixels where that is *aa_de00* or more are edges; a
    pixel is interior when its whole 3 x 3 neighbourhood is free of edges (the silhouettes
    eroded by one pixel).
    """
    edge = de00_map(reference_1spp, reference) >= aa_de00
    h, w = edge.shape
    padded = np.pad(edge, 1, mode="edge")
    near = np.zeros_like(edge)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            near |= padded[1 + dy:1 + dy + h, 1 + dx:1 + dx + w]
    return ~near


def image_errors(image, reference, interior):
    """Error metrics of *image* against *reference* (see the module docstring)."""
    image, bad = finite(image)
    de = de00_map(image, reference)
    sq = (image - reference) ** 2
    out = dict(mean_de00=float(de.mean()), p95_de00=float(np.percentile(de, 95)), max_de00=float(de.max()),
               rmse=float(np.sqrt(sq.mean())), nonfinite_pixels=bad, interior_fraction=float(interior.mean()))
    if interior.any():
        out.update(interior_mean_de00=float(de[interior].mean()),
                   interior_p95_de00=float(np.percentile(de[interior], 95)),
                   interior_rmse=float(np.sqrt(sq[interior].mean())))
    else:
        out.update(interior_mean_de00=math.nan, interior_p95_de00=math.nan, interior_rmse=math.nan)
    return out


# ------------------------------------------------------------------------------------------
# Rendering
# ------------------------------------------------------------------------------------------
def render_reference(scene, size, spp=REFERENCE["spp"], progress=None):
    """The reference of *scene* at *size* x *size*, and the same transport at 1 spp.

    Returns a dict: ``image`` (the reference, linear sRGB), ``seconds`` (its render time, one
    run), ``image_1spp`` and ``seconds_1spp`` (the reference's transport with one sample per
    pixel: the anti-aliasing floor), ``interior`` (:func:`interior_mask`) and ``floor_errors``
    (:func:`image_errors` of the 1-spp image).
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


def _settings_meta(size, spp):
    return dict(size=size, reference=dict(REFERENCE, spp=spp), aa_de00=AA_DE00)


def load_cached_references(folder, size, spp):
    """{scene: reference dict} from *folder* if it holds references made with these settings.

    The images come back as saved (float32 widened to float64); ``image_1spp`` is not saved
    (its errors and time are).
    """
    folder = Path(folder)
    meta_path = folder / "meta.json"
    if not meta_path.exists():
        return None
    meta = json.loads(meta_path.read_text())
    if {k: meta.get(k) for k in ("size", "reference", "aa_de00")} != _settings_meta(size, spp):
        return None
    out = {}
    for name in scene_files():
        info = meta.get("scenes", {}).get(name)
        if info is None or not (folder / f"{name}.npy").exists() or not (folder / f"{name}_interior.npy").exists():
            return None
        out[name] = dict(image=np.load(folder / f"{name}.npy").astype(float),
                         interior=np.load(folder / f"{name}_interior.npy"), image_1spp=None, **info)
    return out


def save_references(refs, size, spp):
    """Write the reference images (float32 .npy, linear sRGB), interior masks and times; return the folder.

    Into ``data/derived/time_vs_error_refs/`` when they take less than REFS_MAX_BYTES, else
    into CACHE_REFS_DIR (outside the repository).
    """
    import io

    blobs = {}
    for name, ref in refs.items():
        for suffix, array in (("", ref["image"].astype(np.float32)), ("_interior", ref["interior"])):
            buf = io.BytesIO()
            np.save(buf, array)
            blobs[f"{name}{suffix}.npy"] = buf.getvalue()
    meta = dict(_settings_meta(size, spp),
                scenes={name: dict(seconds=ref["seconds"], seconds_1spp=ref["seconds_1spp"],
                                   floor_errors=ref["floor_errors"]) for name, ref in refs.items()},
                files="NAME.npy: the reference, float32 linear sRGB (H, W, 3); NAME_interior.npy: bool (H, W)",
                written_by="benchmarks/time_vs_error.py", date=str(datetime.date.today()))
    blobs["meta.json"] = (json.dumps(meta, indent=1) + "\n").encode()
    folder = REFS_DIR if sum(len(b) for b in blobs.values()) < REFS_MAX_BYTES else CACHE_REFS_DIR
    folder.mkdir(parents=True, exist_ok=True)
    for fname, blob in blobs.items():
        tmp = folder / f".{fname}.tmp"
        tmp.write_bytes(blob)
        os.replace(tmp, folder / fname)
    return folder


def run(size=FULL_SIZE, repeats=3, ref_spp=REFERENCE["spp"], scenes=None, band=None, references=None,
        progress=True):
    """Render the references and every setting; return (rows, references, images).

    *references*: {scene: reference dict} (:func:`render_reference`) to use instead of
    rendering them.  *images*: {(scene, key): image} of every distinct setting (for the
    notebook's pictures).
    """
    import tracer
    from tqdm import tqdm

    scenes = load_scenes() if scenes is None else scenes
    configs = configurations(band)
    default_key = key(default_settings())
    distinct = {}
    for _, _, s in configs:
        distinct.setdefault(key(s), s)
    refs = {} if references is None else dict(references)
    total = sum(name not in refs for name in scenes) + len(scenes) * len(distinct) * (1 + repeats)
    bar = tqdm(total=total, desc="time vs error", unit="render", disable=not progress, file=sys.stderr)
    rows, images = [], {}
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
            images[name, k] = image
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
                     nonfinite_pixels=finite(reference)[1])
        rows.append(_row(name, "reference", "reference", dict(REFERENCE, spp=ref_spp), size, [ref["seconds"]],
                         exact, None, ref["seconds"], False))
        rows.append(_row(name, "floor", "1 nm / exhaustive / 1 spp", dict(REFERENCE, spp=1), size,
                         [ref["seconds_1spp"]], ref["floor_errors"], None, ref["seconds"], False))
        for factor, value, s in configs:
            k = key(s)
            rows.append(_row(name, factor, value, s, size, runs[k], errors[k], rays[k], ref["seconds"],
                             k == default_key))
    bar.close()
    return rows, refs, images


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
def write_csv(rows, path=OUT_CSV, notes=()):
    """Write *rows* to *path* (atomically, by ``benchmarks/_results.py``), each note as a leading
    ``# `` line; floats to 6 significant digits, NaN as an empty cell, columns :data:`COLUMNS`."""
    return write_results_csv(path, rows, list(notes), fieldnames=COLUMNS, float_format="{:.6g}", na_rep="",
                             lineterminator="\n", extrasaction="ignore")


_TEXT = ("scene", "factor", "value", "transport", "spectral_method", "seconds_runs")


def read_csv(path=OUT_CSV):
    """(notes, rows) of a CSV written by :func:`write_csv`; numbers as float (NaN when empty)."""
    from tracer.study import read_commented_csv

    notes, raw = read_commented_csv(path)
    rows = []
    for r in raw:
        rows.append({k: (v if k in _TEXT else (float(v) if v != "" else math.nan)) for k, v in r.items()})
    return notes, rows


def columns(rows):
    """Rows (dicts) as a dict of NumPy arrays."""
    return {c: np.array([r[c] for r in rows], dtype=str if c in _TEXT else float) for c in COLUMNS}


# ------------------------------------------------------------------------------------------
# Summary
# ------------------------------------------------------------------------------------------
def summary_table(rows):
    """Plain-text table: per scene, the reference time, then every row's time and errors."""
    lines = []
    for scene in dict.fromkeys(r["scene"] for r in rows):
        sel = [r for r in rows if r["scene"] == scene]
        ref = next(r for r in sel if r["factor"] == "reference")
        lines.append(f"\n{scene}: reference {ref['seconds']:.1f} s ({int(ref['width'])}x{int(ref['height'])}, "
                     f"{int(ref['spectral_samples'])} bands, {int(ref['spp'])} spp, threshold 0, depth "
                     f"{int(ref['depth'])}); interior pixels {100 * ref['interior_fraction']:.0f} %")
        lines.append(f"{'factor':9s} {'value':22s} {'seconds':>8s} {'mean dE':>8s} {'p95 dE':>8s} {'int. mean':>9s} "
                     f"{'rmse':>8s} {'speed-up':>9s}")
        for r in sel:
            if r["factor"] == "reference":
                continue
            mark = " *" if r["is_default"] else ""
            lines.append(f"{r['factor']:9s} {r['value']:22s} {r['seconds']:8.4f} {r['mean_de00']:8.3f} "
                         f"{r['p95_de00']:8.3f} {r['interior_mean_de00']:9.3f} {r['rmse']:8.4f} "
                         f"{r['speedup_vs_reference']:8.0f}x{mark}")
    return "\n".join(lines)


# ------------------------------------------------------------------------------------------
# The front and the defaults
# ------------------------------------------------------------------------------------------
#: Settings the study proposes (depth is held at the default: it is swept, not proposed).
PROPOSED = ("spectral_samples", "spectral_method", "threshold", "spp")


def row_key(r):
    """The setting of a CSV row, as :func:`key`."""
    spectral = r["transport"] == "spectral"
    return key(dict(spectral=spectral, spectral_samples=r["spectral_samples"] if spectral else 0,
                    spectral_method=r["spectral_method"], threshold=r["threshold"], spp=r["spp"], depth=r["depth"]))


def describe(k):
    """A setting key as text, e.g. ``16 bands (point), threshold 0.001, 1 spp, depth 10``."""
    transport, n, method, threshold, spp, depth = k
    bands = "RGB transport" if transport == "rgb" else f"{n} bands ({method})"
    return f"{bands}, threshold {threshold:g}, {spp} spp, depth {depth}"


def timing_tolerance(rows, fallback=0.3):
    """Relative timing noise: the median over settings of (slowest - fastest run) / median run.

    *fallback* when no setting was timed more than once.  On the shared two-core machine of
    the benchmark this is about 0.3: two settings whose times differ by less cannot be ordered.
    """
    spreads = []
    for r in rows:
        runs = [float(x) for x in str(r["seconds_runs"]).split()]
        if len(runs) > 1:
            spreads.append((max(runs) - min(runs)) / float(np.median(runs)))
    return float(np.median(spreads)) if spreads else fallback


def scene_points(rows, scene):
    """The rows of *scene* that are renders to compare (all but the reference itself)."""
    seen, out = set(), []
    for r in rows:
        if r["scene"] == scene and r["factor"] != "reference" and row_key(r) not in seen:
            seen.add(row_key(r))
            out.append(r)
    return out


def front(rows, scene, metric="interior_mean_de00"):
    """Rows of *scene* on the Pareto front of (seconds, *metric*) (``tracer.study.pareto_front``)."""
    from tracer.study import pareto_front

    pts = scene_points(rows, scene)
    idx = pareto_front([r["seconds"] for r in pts], [r[metric] for r in pts])
    return [pts[i] for i in idx]


def dominators(rows, scene, k, metric="interior_mean_de00", tol=0.0):
    """Rows of *scene* that dominate setting *k* beyond the timing noise *tol*.

    A row dominates when its error is no larger and its time is smaller by more than the
    noise: ``seconds <= seconds_k / (1 + tol)`` (errors are deterministic, times are not).
    With *tol* = 0 this is ordinary Pareto dominance (ties in both count as no dominance).
    Empty: *k* is on the front within the timing noise.
    """
    pts = scene_points(rows, scene)
    me = next(r for r in pts if row_key(r) == k)
    t, e = me["seconds"] / (1.0 + tol), me[metric]
    return [r for r in pts if row_key(r) != k and r["seconds"] <= t and r[metric] <= e
            and (r["seconds"] < t or r[metric] < e)]


def assess(rows, metric="interior_mean_de00", tol=None, target_error=TARGET_MEAN_DE00,
           target_speedup=TARGET_SPEEDUP, depth=None):
    """Which settings meet the targets and sit on the front in every scene; the proposal.

    Candidates: every setting rendered in every scene at trace depth *depth* (default: the
    current default depth).  A candidate *qualifies* when, in every scene, its *metric* is at
    most *target_error*, it is at least *target_speedup* times faster than the reference, and
    no other setting dominates it beyond the timing noise *tol* (:func:`dominators`; default:
    :func:`timing_tolerance`).  The *proposal* is the most accurate (smallest worst-scene
    error) of the qualifying settings whose time -- the geometric mean over scenes of
    seconds / reference seconds -- is within the timing noise of the fastest one: when
    times cannot be told apart, accuracy decides.

    Returns a dict: ``tol``, ``metric``, ``scenes``, ``candidates`` (key -> per-scene dicts
    with ``seconds``, ``error``, ``p95``, ``speedup``, ``dominated_by`` (keys), ``meets``;
    and ``qualifies``, ``cost``), ``qualifying`` (keys), ``proposal`` (key or None),
    ``default`` (the current defaults' key) and ``default_ok`` (bool), ``problems`` (text).
    """
    if tol is None:
        tol = timing_tolerance(rows)
    if depth is None:
        depth = default_settings()["depth"]
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    per_scene = {sc: {row_key(r): r for r in scene_points(rows, sc)} for sc in scenes}
    common = [k for k in per_scene[scenes[0]] if all(k in per_scene[sc] for sc in scenes) and k[5] == depth]
    p95_metric = metric.replace("mean", "p95")
    candidates = {}
    for k in common:
        info = {}
        for sc in scenes:
            r = per_scene[sc][k]
            dom = [row_key(d) for d in dominators(rows, sc, k, metric, tol)]
            info[sc] = dict(seconds=r["seconds"], error=r[metric], p95=r.get(p95_metric, math.nan),
                            speedup=r["speedup_vs_reference"], dominated_by=dom,
                            meets=r[metric] <= target_error and r["speedup_vs_reference"] >= target_speedup)
        info["qualifies"] = all(info[sc]["meets"] and not info[sc]["dominated_by"] for sc in scenes)
        info["cost"] = float(np.exp(np.mean([np.log(1.0 / info[sc]["speedup"]) for sc in scenes])))
        info["worst_error"] = max(info[sc]["error"] for sc in scenes)
        candidates[k] = info
    qualifying = sorted((k for k in candidates if candidates[k]["qualifies"]), key=lambda k: candidates[k]["cost"])
    proposal = None
    if qualifying:
        fastest = candidates[qualifying[0]]["cost"]
        tied = [k for k in qualifying if candidates[k]["cost"] <= fastest * (1.0 + tol)]
        proposal = min(tied, key=lambda k: (candidates[k]["worst_error"], candidates[k]["cost"]))
    default = key(default_settings())
    problems = []
    if default not in candidates:
        problems.append(f"the current defaults ({describe(default)}) were not rendered in every scene: "
                        "re-run benchmarks/time_vs_error.py")
    else:
        for sc in scenes:
            d = candidates[default][sc]
            if d["error"] > target_error:
                problems.append(f"{sc}: {metric} {d['error']:.3f} > {target_error}")
            if d["speedup"] < target_speedup:
                problems.append(f"{sc}: only {d['speedup']:.1f}x faster than the reference (< {target_speedup:g}x)")
            if d["dominated_by"]:
                problems.append(f"{sc}: off the front, dominated beyond the timing noise by "
                                + "; ".join(describe(k) for k in d["dominated_by"]))
    return dict(tol=tol, metric=metric, scenes=scenes, candidates=candidates, qualifying=qualifying,
                proposal=proposal, default=default, default_ok=not problems, problems=problems)


def change_advice(result):
    """Text: which defaults to change to reach the proposal (empty when they agree)."""
    if result["proposal"] is None:
        return ("no setting at the default depth meets the targets on the front in every scene; "
                "relax a target or sweep further")
    names = ("transport", "spectral_samples", "spectral_method", "threshold", "spp", "depth")
    d, p = result["default"], result["proposal"]
    changes = [f"{n}: {a!r} -> {b!r}" for n, a, b in zip(names, d, p) if a != b]
    return ("change tracer.DEFAULTS " + ", ".join(changes)) if changes else ""


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help=f"{QUICK_SIZE}x{QUICK_SIZE}, one repeat, nothing written")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs per setting (median)")
    parser.add_argument("--ref-spp", type=int, default=REFERENCE["spp"], help="samples per pixel of the reference")
    parser.add_argument("--size", type=int, default=None, help=f"image side (default {FULL_SIZE})")
    parser.add_argument("--reuse-refs", action="store_true",
                        help="use the saved reference images (and their times) if made with the same settings")
    parser.add_argument("--out", type=Path, default=OUT_CSV)
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
            refs = load_cached_references(folder, size, args.ref_spp)
            if refs:
                print(f"reusing the references in {folder}")
                break
    if not refs:
        est = {name: estimate_reference_seconds(sc, size, args.ref_spp) for name, sc in scenes.items()}
        print("reference cost, estimated from 1/16 of the pixels: "
              + ", ".join(f"{n} {s:.0f} s" for n, s in est.items()) + f" (total {sum(est.values()):.0f} s)")
    rows, refs, _ = run(size, repeats, args.ref_spp, scenes, band, refs)
    print(summary_table(rows))
    if not quick:
        folder = save_references(refs, size, args.ref_spp)
        where = folder.relative_to(ROOT) if folder.is_relative_to(ROOT) else folder
        print(f"reference images: {where}"
              + ("" if folder == REFS_DIR else " (outside the repository: 2 MB or more)"))
        notes = [
            f"written by benchmarks/time_vs_error.py on {datetime.date.today()} ({platform.machine()}, "
            f"{os.cpu_count()} cores, Python {platform.python_version()}); regenerate with: "
            "python benchmarks/time_vs_error.py",
            f"{size}x{size}; reference: threshold 0, {REFERENCE['spectral_samples']} bands (1 nm) over 360-780 nm, "
            f"{args.ref_spp} spp stratified, depth {REFERENCE['depth']}, seed {REFERENCE['seed']}, timed once; "
            f"images in {where}",
            f"seconds: median of {repeats} render_seconds (compilation excluded), interleaved; sweeps around "
            f"tracer.DEFAULTS {json.dumps(default_settings())}",
            "dE00: tracer.study.delta_e00 on linear sRGB with negative values clipped to 0; rmse: linear sRGB, "
            "unclipped; non-finite pixels set to 0",
            f"interior: pixels none of whose 3x3 neighbourhood changes by >= {AA_DE00:g} dE00 when the reference "
            "is rendered at 1 spp (factor 'floor': that 1-spp render, timed once)",
        ]
        write_csv(rows, args.out, notes)
        print(f"wrote {args.out}")
    print(f"total {time.perf_counter() - t_start:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
