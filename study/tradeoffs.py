"""Run time against error: the tracer's settings against a converged reference render.

The analysis of ``benchmarks/time_vs_error.py`` (which renders and writes
``data/derived/time_vs_error.csv`` with the reference images), of notebook 04 and of the paper
(``paper/scripts/fig_time_vs_error.py``, ``make_numbers.py``).  Nothing here renders or imports
the tracer: settings are dicts, images arrays, and :func:`render_kwargs` turns a setting into the
keyword arguments of ``tracer.render_with_stats``.

* **Settings** (:func:`configurations`): one factor at a time around the defaults -- spectral
  sampling (RGB transport, 3-81 point-sampled bands, 3-16 band-averaged bands), pruning
  threshold, samples per pixel, trace depth -- plus a small grid of combined settings.  The
  reference (:data:`REFERENCE`): the exhaustive tree (threshold 0), 421 bands of 1 nm over
  360-780 nm, 16 stratified samples per pixel, depth 16, seed 1.  The swept renders use the
  seeds :data:`SWEEP_SEEDS` (the benchmark takes the first few); a 1-spp render samples the
  pixel centre and is the same for every seed on these scenes (no light is sampled at random),
  so only settings with several samples per pixel spread over seeds.
* **The reference's floor**: a second reference, the same settings with seed :data:`FLOOR_SEED`,
  scored against the first like any setting (the ``floor`` row).  It is what an independent
  render as good as the reference achieves: errors within about the floor are not resolved
  (:func:`assess` treats them as equal).  On the interior pixels the floor is a lower
  estimate: the mask keeps pixels where the two references agree to within :data:`AA_DE00`; on
  all pixels and on the bubble pixels (masks that do not look at the references) it is not
  conditioned.
* **Errors** (:func:`image_errors`): per-pixel CIEDE2000 on linear sRGB with negative values
  clipped to 0 (:func:`study.delta_e00_images`), its mean and 95th percentile, and
  the RMSE in linear sRGB; non-finite pixels counted and set to 0.  The same on three sets of
  pixels: all, *interior* and *bubble*.  With several seeds, each metric is the mean over seeds
  and ``<metric>_sd`` its standard deviation.
* **Interior pixels** (:func:`interior_mask`): pixels none of whose 3 x 3 neighbourhood is an
  edge, where an edge is a pixel that a silhouette crosses (its 4 x 4 sub-pixel camera rays do not
  all meet the same object first: :func:`pixel_hits`, :func:`silhouette_mask`) or where the two
  references differ by :data:`AA_DE00` (1 ΔE00) or more (a sub-pixel feature inside an object:
  a reflected edge, a highlight, fringes finer than a pixel).  Neither test looks at a
  pixel-centre render, so the mask favours no sampling pattern (a mask of where a 1-spp render
  of the reference's transport differs from the reference would keep exactly the pixels where
  the pixel centre is a good estimate, and so favour every 1-spp setting over 4 spp).
  (A plain edge detector on the reference's colours, :func:`contrast_mask`, would also discard
  the films' interference fringes, i.e. most of each bubble.)
* **Bubble pixels** (:func:`bubble_mask`): pixels all of whose sub-pixel camera rays meet a
  bubble first, found by intersecting the camera rays with the scene's spheres here (the film
  colours, without the silhouettes; reflected edges inside a bubble included).
* **The front and the defaults** (:func:`assess`): a setting qualifies when on every scene it
  meets the targets (mean ΔE00 <= :data:`TARGET_MEAN_DE00`, at least :data:`TARGET_SPEEDUP`
  times faster than the reference) and no other setting is more accurate by more than the
  reference's floor and faster by more than the timing noise (:func:`timing_tolerance`); the
  proposal is the most accurate qualifying setting among those within that noise of the
  fastest.
"""

from __future__ import annotations

import datetime
import functools
import inspect
import io
import json
import math
import os
from pathlib import Path

import numpy as np

from .fronts import pareto_front
from .metrics import delta_e00_images, finite_image, rmse
from .results import read_commented_csv

__all__ = [
    "REFERENCE", "AA_DE00", "CONTRAST_DE00", "TARGET_MEAN_DE00", "TARGET_SPEEDUP", "COLUMNS", "SCENE_LABELS",
    "CACHE_REFS_DIR", "REFS_MAX_BYTES", "MASKS",
    "settings_from_defaults", "accepts_spectral_method", "key", "row_key", "describe", "configurations",
    "render_kwargs",
    "SWEEP_SEEDS", "FLOOR_SEED", "ERROR_METRICS", "SUB_PIXELS",
    "pixel_hits", "silhouette_mask", "bubble_mask", "dilate",
    "contrast_mask", "interior_mask", "image_errors", "combine_seeds", "floor_errors",
    "reference_settings", "load_references", "save_references", "read_rows", "summary_table",
    "timing_tolerance", "scene_points", "front", "dominators", "assess", "change_advice", "scene_front",
]

#: The reference render: exhaustive, 1 nm bands (421 over 360-780 nm), 16 spp, depth 16.
REFERENCE = dict(spectral=True, spectral_samples=421, spectral_method="point", threshold=0.0, spp=16, depth=16,
                 seed=1)
#: The second reference's seed: the same render with other sample positions (the floor).
FLOOR_SEED = 2
#: Seeds of the swept renders (never a reference's); the benchmark uses the first ``--seeds``.
SWEEP_SEEDS = (0, 3, 4, 5, 6, 7, 8)
#: Sub-pixel camera rays per side for the geometry masks (:func:`pixel_hits`).
SUB_PIXELS = 4

#: The swept values of each factor (the others held at the defaults).
SPECTRAL_POINT = (3, 4, 8, 16, 32, 81)
SPECTRAL_BAND = (3, 4, 8, 16)
THRESHOLDS = (0.0, 1e-4, 1e-3, 1e-2, 3e-2, 0.1)
SPPS = (1, 4, 9, 16)
DEPTHS = (1, 2, 3, 4, 6, 8, 10)
#: The combined grid (x spectral methods): spectral samples x threshold x spp.
GRID = dict(spectral_samples=(8, 16), threshold=(1e-3, 1e-2), spp=(1, 4))

#: A pixel is an edge when the two references differ there by AA_DE00 or more (CIEDE2000; see
#: :func:`interior_mask`).  About one just-noticeable difference.
AA_DE00 = 1.0
#: Threshold of the plain colour-contrast edge detector :func:`contrast_mask` (for comparison).
CONTRAST_DE00 = 5.0

#: Targets of the study: mean ΔE00 at most this, at least this many times faster than the reference.
TARGET_MEAN_DE00 = 0.5
TARGET_SPEEDUP = 20.0


#: Where reference images go when they would take REFS_MAX_BYTES or more (outside any repository).
CACHE_REFS_DIR = (Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
                  / "bubbleoptics" / "time_vs_error_refs")
REFS_MAX_BYTES = 2_000_000

#: The ΔE00 metrics averaged over seeds, each with a ``_sd`` column (standard deviation over seeds).
ERROR_METRICS = ("mean_de00", "p95_de00", "interior_mean_de00", "interior_p95_de00", "bubble_mean_de00",
                 "bubble_p95_de00")

COLUMNS = (
    "scene", "factor", "value", "transport", "spectral_samples", "spectral_method", "resolved_method", "threshold",
    "spp", "depth", "width", "height", "seconds", "seconds_min", "seconds_max", "seconds_runs", "seeds",
    "mean_de00", "p95_de00", "max_de00", "rmse", "interior_mean_de00", "interior_p95_de00", "interior_rmse",
    "bubble_mean_de00", "bubble_p95_de00", *(f"{m}_sd" for m in ERROR_METRICS),
    "interior_fraction", "bubble_fraction", "nonfinite_pixels",
    "rays_total", "reference_seconds", "speedup_vs_reference", "is_default",
)

SCENE_LABELS = {"builtin": "built-in scene (3 bubbles)", "bubbles": "six bubbles (gallery)",
                "materials": "bubble and spheres (materials)", "thick": "thick films (1.6-3 µm)"}


def settings_from_defaults(defaults):
    """A renderer's defaults (a dict like ``tracer.DEFAULTS``) as a setting of this study.

    Example
    -------
    >>> settings_from_defaults(dict(spectral_samples=16, threshold=1e-3, spp=1, depth=10))["spectral_method"]
    'point'
    """
    d = defaults
    return dict(spectral=True, spectral_samples=int(d["spectral_samples"]),
                spectral_method=str(d.get("spectral_method", "point")), threshold=float(d["threshold"]),
                spp=int(d["spp"]), depth=int(d["depth"]))


def accepts_spectral_method(render):
    """Whether the renderer function *render* (``tracer.render_with_stats``) takes
    ``spectral_method``, i.e. offers band-averaged films."""
    return "spectral_method" in inspect.signature(render).parameters


def key(s):
    """A hashable identity of a setting (RGB transport ignores the spectral fields)."""
    if not s["spectral"]:
        return ("rgb", 0, "", float(s["threshold"]), int(s["spp"]), int(s["depth"]))
    return ("spectral", int(s["spectral_samples"]), s["spectral_method"], float(s["threshold"]), int(s["spp"]),
            int(s["depth"]))


def configurations(defaults, band=True):
    """[(factor, value, setting)] of the study: one-factor sweeps around the defaults, then the grid.

    A setting is a dict with ``spectral`` (bool: spectral or RGB transport), ``spectral_samples``,
    ``spectral_method`` (``"point"``: film at the band centre; ``"band"``: band-averaged film;
    ``"auto"``: the tracer's choice between them, ``tracer.prepare.pack.resolve_spectral_method``),
    ``threshold``, ``spp`` and ``depth`` (:func:`settings_from_defaults`).  *defaults*: the
    setting the sweeps are centred on; *band*: include the band-averaged method (when the
    renderer accepts it, :func:`accepts_spectral_method`).  Settings repeat across factors
    (every sweep passes through the defaults); the benchmark renders each distinct one once.

    Example
    -------
    >>> centre = dict(spectral=True, spectral_samples=16, spectral_method="auto", threshold=1e-3, spp=1, depth=10)
    >>> configs = configurations(centre)
    >>> configs[0][:2], len({key(s) for _, _, s in configs}) < len(configs)
    (('default', 'default'), True)
    >>> [s["spectral_method"] for f, v, s in configs if (f, v) == ("spectral", "16")]
    ['point']
    """
    centre = dict(defaults)
    out = [("default", "default", dict(centre))]
    out.append(("spectral", "rgb", dict(centre, spectral=False)))
    for n in SPECTRAL_POINT:
        # point sampling at every band count, the default's too: where the defaults' "auto" picks
        # point sampling this is the defaults' own image (assess counts it as the same render),
        # where it picks band averaging (films over 1.5 µm) it shows what point samples would do
        out.append(("spectral", f"{n}", dict(centre, spectral_samples=n, spectral_method="point")))
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
    """Keyword arguments of ``tracer.render`` / ``tracer.render_with_stats`` for setting *s*, a
    *size* x *size* image and the sampling *seed*."""
    kw = dict(width=size, height=size, depth=int(s["depth"]), spp=int(s["spp"]), threshold=float(s["threshold"]),
              seed=seed, spectral=bool(s["spectral"]), progress=False)
    if s["spectral"]:
        kw["spectral_samples"] = int(s["spectral_samples"])
        kw["spectral_method"] = s["spectral_method"]  # always: the tracer's default may be "auto"
    return kw


# ------------------------------------------------------------------------------------------
# Errors
# ------------------------------------------------------------------------------------------
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
            contrast = np.maximum(contrast, delta_e00_images(shifted, ref))
    return contrast < edge_de00


def _camera(camera):
    """*camera* as a one-element :data:`tracer.kernels.records.CAMERA` array: a packed scene's
    ``camera`` is one already; a mapping gives its fields (``origin``, ``forward``, ``right``,
    ``up`` unit vectors and ``tan_half_fov``)."""
    from tracer.kernels.records import CAMERA

    if isinstance(camera, np.ndarray) and camera.dtype == CAMERA:
        return camera.reshape(1)
    rec = np.zeros(1, CAMERA)
    for name in CAMERA.names:
        rec[name] = camera[name]
    return rec


@functools.cache
def _hits_kernel():
    """The numba loop of :func:`pixel_hits`, compiled on first use (the study imports numba and
    the tracer's kernels only when it intersects)."""
    from numba import njit

    from bubbleoptics.jit import JIT
    from tracer.kernels.geometry import intersect_sphere
    from tracer.kernels.sampling import camera_ray

    @njit(**JIT)
    def hits(cam, centers, radii, width, height, sub, out):
        o = (cam.origin[0], cam.origin[1], cam.origin[2])
        for y in range(height):
            for x in range(width):
                for a in range(sub):
                    for b in range(sub):
                        d = camera_ray(cam, x + (b + 0.5) / sub, y + (a + 0.5) / sub, width, height)
                        best, first = np.inf, -1
                        for i in range(centers.shape[0]):
                            c = (centers[i, 0], centers[i, 1], centers[i, 2])
                            t, _ = intersect_sphere(o, d, c, radii[i], 0.0, best)
                            if t < best:
                                best, first = t, i
                        out[y, x, a * sub + b] = first

    return hits


def pixel_hits(camera, centers, radii, width, height, sub=SUB_PIXELS):
    """Which sphere each camera ray meets first: int array (height, width, sub * sub).

    For every pixel, *sub* x *sub* rays through the centres of a regular sub-pixel grid (no
    pixel centre among them when *sub* is even), made and intersected with the spheres
    (*centers* (N, 3), *radii* (N,)) by the tracer's own kernels
    (:func:`tracer.kernels.sampling.camera_ray`, :func:`tracer.kernels.geometry.intersect_sphere`):
    the index of the nearest sphere hit at t > 0 (a camera inside a sphere meets its far side),
    -1 for none.  *camera*: a packed scene's ``camera`` record or a mapping of its fields
    (``origin``, ``forward``, ``right``, ``up``, ``tan_half_fov``).  Only spheres: the
    benchmark's scenes have no meshes (it refuses scenes that do).
    """
    cam = _camera(camera)
    centers = np.ascontiguousarray(np.asarray(centers, float).reshape(-1, 3))
    radii = np.ascontiguousarray(np.asarray(radii, float).reshape(-1))
    out = np.empty((int(height), int(width), int(sub) * int(sub)), dtype=np.int64)
    _hits_kernel()(cam[0], centers, radii, int(width), int(height), int(sub), out)
    return out


def silhouette_mask(hits):
    """Boolean (H, W): pixels a silhouette crosses, i.e. whose sub-pixel rays (:func:`pixel_hits`)
    do not all meet the same sphere first (or all miss)."""
    return (hits != hits[..., :1]).any(axis=-1)


def bubble_mask(hits, is_bubble):
    """Boolean (H, W): pixels all of whose sub-pixel rays (:func:`pixel_hits`) meet a bubble first.

    *is_bubble*: bool per sphere index (the first surface is a soap film).
    """
    flags = np.append(np.asarray(is_bubble, bool), False)  # index -1 (no hit): not a bubble
    return flags[hits].all(axis=-1)


def dilate(mask):
    """Boolean (H, W): pixels with a True pixel in their 3 x 3 neighbourhood (edges replicated)."""
    mask = np.asarray(mask, bool)
    h, w = mask.shape
    padded = np.pad(mask, 1, mode="edge")
    near = np.zeros_like(mask)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            near |= padded[1 + dy:1 + dy + h, 1 + dx:1 + dx + w]
    return near


def interior_mask(reference, reference_b, silhouettes=None, aa_de00=AA_DE00):
    """Boolean (H, W): pixels away from every edge, by a test that favours no sampling pattern.

    *reference* and *reference_b* are two independent renders with the reference's settings
    (seeds :data:`REFERENCE` ``["seed"]`` and :data:`FLOOR_SEED`: the same jittered strata, other
    positions in them).  Where a pixel holds detail finer than itself (a silhouette, a reflected
    edge, a highlight, fringes narrower than a pixel) the two disagree; a pixel is an *edge*
    when they differ by *aa_de00* or more, or when a silhouette crosses it (*silhouettes*,
    :func:`silhouette_mask`, from the geometry: a low-contrast silhouette can escape the first
    test).  A pixel is interior when its whole 3 x 3 neighbourhood is free of edges.  No
    pixel-centre render enters: the mask that used one kept exactly the pixels where a 1-spp
    render is right, and so scored every 1-spp setting better than 4 spp.
    """
    edge = delta_e00_images(reference_b, reference) >= aa_de00
    if silhouettes is not None:
        edge |= np.asarray(silhouettes, bool)
    return ~dilate(edge)


def _masked(de, image, reference, mask, prefix):
    if mask is not None and mask.any():
        return {f"{prefix}mean_de00": float(de[mask].mean()), f"{prefix}p95_de00": float(np.percentile(de[mask], 95)),
                f"{prefix}rmse": rmse(image[mask], reference[mask])}
    return {f"{prefix}mean_de00": math.nan, f"{prefix}p95_de00": math.nan, f"{prefix}rmse": math.nan}


def image_errors(image, reference, interior, bubble=None):
    """Error metrics of *image* against *reference*, over all pixels, over the *interior* ones and
    over the *bubble* ones (module docstring): ``mean_de00``, ``p95_de00``, ``max_de00``,
    ``rmse``, their ``interior_`` and ``bubble_`` versions (NaN when the set is empty or
    *bubble* is None; no ``bubble_rmse``), ``interior_fraction``, ``bubble_fraction`` and
    ``nonfinite_pixels``."""
    image, bad = finite_image(image)
    de = delta_e00_images(image, reference)
    out = dict(mean_de00=float(de.mean()), p95_de00=float(np.percentile(de, 95)), max_de00=float(de.max()),
               rmse=rmse(image, reference), nonfinite_pixels=bad, interior_fraction=float(interior.mean()),
               bubble_fraction=math.nan if bubble is None else float(np.mean(bubble)))
    out.update(_masked(de, image, reference, interior, "interior_"))
    b = _masked(de, image, reference, None if bubble is None else np.asarray(bubble, bool), "bubble_")
    b.pop("bubble_rmse")
    out.update(b)
    return out


def combine_seeds(errors):
    """One set of metrics from the :func:`image_errors` of the same setting rendered with several
    seeds: each metric's mean over seeds, ``<metric>_sd`` (sample standard deviation, 0 for one
    seed) for :data:`ERROR_METRICS`, the largest ``max_de00`` and ``nonfinite_pixels``, and
    ``seeds``.

    Example
    -------
    >>> out = combine_seeds([dict(mean_de00=1.0, max_de00=3.0), dict(mean_de00=2.0, max_de00=5.0)])
    >>> out["mean_de00"], round(out["mean_de00_sd"], 3), out["max_de00"], out["seeds"]
    (1.5, 0.707, 5.0, 2)
    """
    errors = list(errors)
    out = {}
    for k in errors[0]:
        values = np.array([e[k] for e in errors], dtype=float)
        out[k] = float(values.max()) if k in ("max_de00", "nonfinite_pixels") else float(values.mean())
    for m in ERROR_METRICS:
        if m in errors[0]:
            values = np.array([e[m] for e in errors], dtype=float)
            same = bool(np.all(values == values[0]))  # identical renders: exactly 0, not rounding noise
            out[f"{m}_sd"] = 0.0 if same or len(values) < 2 else float(values.std(ddof=1))
    out["nonfinite_pixels"] = int(out.get("nonfinite_pixels", 0))
    out["seeds"] = len(errors)
    return out


def floor_errors(rows, scene, metric="interior_mean_de00"):
    """The reference's own floor on *scene* for *metric*: the ``floor`` row's value (the second
    reference scored against the first), or 0 when the rows have none."""
    found = [r[metric] for r in rows if r["scene"] == scene and r["factor"] == "floor"]
    return float(found[0]) if found and math.isfinite(found[0]) else 0.0


# ------------------------------------------------------------------------------------------
# Files
# ------------------------------------------------------------------------------------------
#: The masks saved beside each reference image (bool (H, W) .npy files ``NAME_<mask>.npy``).
MASKS = ("interior", "bubble")


def reference_settings(size, spp):
    """What identifies a set of references: image size, :data:`REFERENCE` with *spp*, the floor's
    seed, :data:`AA_DE00` and the mask's method."""
    return dict(size=size, reference=dict(REFERENCE, spp=spp), floor_seed=FLOOR_SEED, aa_de00=AA_DE00,
                mask=f"two references and {SUB_PIXELS}x{SUB_PIXELS} sub-pixel geometry")


def load_references(folder, size, spp):
    """{scene: reference dict} from *folder* (written by :func:`save_references`) if it holds
    references made with these settings (:func:`reference_settings`), else None.

    The images come back as saved (float32 widened to float64), with the masks
    (:data:`MASKS`) and what ``meta.json`` holds per scene (times, the floor's and the ideal
    render's errors); the second reference and the 1-spp render are not saved.
    """
    folder = Path(folder)
    meta_path = folder / "meta.json"
    if not meta_path.exists():
        return None
    meta = json.loads(meta_path.read_text())
    want = reference_settings(size, spp)
    if {k: meta.get(k) for k in want} != want:
        return None
    out = {}
    for name, info in meta.get("scenes", {}).items():
        files = [folder / f"{name}.npy"] + [folder / f"{name}_{m}.npy" for m in MASKS]
        if not all(f.exists() for f in files):
            return None
        out[name] = dict(image=np.load(files[0]).astype(float), **{m: np.load(f) for m, f in zip(MASKS, files[1:])},
                         **info)
    return out


def save_references(refs, size, spp, folder, overflow=None, max_bytes=REFS_MAX_BYTES, written_by=""):
    """Write the reference images (float32 .npy, linear sRGB), their masks and times; return the folder.

    *refs*: {scene: dict with ``image`` and the masks :data:`MASKS` (arrays), and any
    JSON-serialisable entries (times, ``floor_errors``...), which go to ``meta.json``; other
    arrays (the second reference, the 1-spp render) are not saved}.  Into *folder* when the
    files take less than *max_bytes* or *overflow* is None, else into *overflow* (e.g.
    :data:`CACHE_REFS_DIR`, outside a repository); each file atomically, with ``meta.json``
    (:func:`reference_settings`, the per-scene entries, *written_by*, the date).
    """
    blobs, scenes = {}, {}
    for name, ref in refs.items():
        arrays = [("", ref["image"].astype(np.float32))] + [(f"_{m}", np.asarray(ref[m], bool)) for m in MASKS]
        for suffix, array in arrays:
            buf = io.BytesIO()
            np.save(buf, array)
            blobs[f"{name}{suffix}.npy"] = buf.getvalue()
        scenes[name] = {k: v for k, v in ref.items() if k != "image" and k not in MASKS
                        and not isinstance(v, np.ndarray) and v is not None}
    meta = dict(reference_settings(size, spp), scenes=scenes,
                files="NAME.npy: the reference, float32 linear sRGB (H, W, 3); "
                      + "; ".join(f"NAME_{m}.npy: bool (H, W)" for m in MASKS),
                written_by=written_by, date=str(datetime.date.today()))
    blobs["meta.json"] = (json.dumps(meta, indent=1) + "\n").encode()
    if overflow is not None and sum(len(b) for b in blobs.values()) >= max_bytes:
        folder = overflow
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    for fname, blob in blobs.items():
        tmp = folder / f".{fname}.tmp"
        tmp.write_bytes(blob)
        os.replace(tmp, folder / fname)
    return folder


_TEXT = ("scene", "factor", "value", "transport", "spectral_method", "resolved_method", "seconds_runs")


def read_rows(path):
    """``(notes, rows)`` of a file written by ``benchmarks/time_vs_error.py``
    (:func:`study.read_commented_csv`); numbers as float (NaN when empty)."""
    notes, raw = read_commented_csv(path)
    rows = []
    for r in raw:
        rows.append({k: (v if k in _TEXT else (float(v) if v != "" else math.nan)) for k, v in r.items()})
    return notes, rows


def summary_table(rows):
    """Plain-text table: per scene, the reference time, then every row's time (median and range
    over the timed runs) and errors (interior and bubble: mean over seeds +- standard deviation)."""
    lines = []
    for scene in dict.fromkeys(r["scene"] for r in rows):
        sel = [r for r in rows if r["scene"] == scene]
        ref = next(r for r in sel if r["factor"] == "reference")
        lines.append(f"\n{scene}: reference {ref['seconds']:.1f} s ({int(ref['width'])}x{int(ref['height'])}, "
                     f"{int(ref['spectral_samples'])} bands, {int(ref['spp'])} spp, threshold 0, depth "
                     f"{int(ref['depth'])}); interior pixels {100 * ref['interior_fraction']:.0f} %, bubble pixels "
                     f"{100 * ref['bubble_fraction']:.0f} %")
        lines.append(f"{'factor':9s} {'value':22s} {'ms':>7s} {'range':>13s} {'mean dE':>7s} {'int. mean':>15s} "
                     f"{'int. p95':>8s} {'bubble mean':>15s} {'speed-up':>8s}")
        for r in sel:
            if r["factor"] == "reference":
                continue
            mark = " *" if r["is_default"] else ""
            lines.append(f"{r['factor']:9s} {r['value']:22s} {1e3 * r['seconds']:7.2f} "
                         f"{1e3 * r['seconds_min']:6.2f}-{1e3 * r['seconds_max']:<6.2f} {r['mean_de00']:7.3f} "
                         f"{r['interior_mean_de00']:7.4f}+-{r['interior_mean_de00_sd']:<6.4f} "
                         f"{r['interior_p95_de00']:8.3f} {r['bubble_mean_de00']:7.4f}+-{r['bubble_mean_de00_sd']:<6.4f} "
                         f"{r['speedup_vs_reference']:7.0f}x{mark}")
    return "\n".join(lines)


# ------------------------------------------------------------------------------------------
# The front and the defaults
# ------------------------------------------------------------------------------------------
#: Settings the study proposes (depth is held at the default: it is swept, not proposed).


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
    """Relative timing noise: the median over the swept settings of (slowest - fastest run) /
    median run (the references, timed once per seed, left out).

    *fallback* when no setting was timed more than once.  On the shared two-core machine of
    the benchmark this is about 0.3: two settings whose times differ by less cannot be ordered.
    """
    spreads = []
    for r in rows:
        if r["factor"] in ("reference", "floor"):
            continue
        runs = [float(x) for x in str(r["seconds_runs"]).split()]
        if len(runs) > 1:
            spreads.append((max(runs) - min(runs)) / float(np.median(runs)))
    return float(np.median(spreads)) if spreads else fallback


def scene_points(rows, scene, skip=("reference",)):
    """The rows of *scene* that are renders to compare, each setting once (the first row of it):
    all but the factors in *skip* (the reference itself; a figure that marks each point by the
    factor swept also skips ``"default"``, whose setting every sweep passes through)."""
    seen, out = set(), []
    for r in rows:
        if r["scene"] == scene and r["factor"] not in skip and row_key(r) not in seen:
            seen.add(row_key(r))
            out.append(r)
    return out


def front(rows, scene, metric="interior_mean_de00"):
    """Rows of *scene* on the Pareto front of (seconds, *metric*) (:func:`study.pareto_front`)."""
    pts = scene_points(rows, scene)
    idx = pareto_front([r["seconds"] for r in pts], [r[metric] for r in pts])
    return [pts[i] for i in idx]


def dominators(rows, scene, k, metric="interior_mean_de00", tol=0.0, resolution=0.0):
    """Rows of *scene* that dominate setting *k* beyond the timing noise *tol*.

    A row dominates when its error is no larger and its time is smaller by more than the
    noise: ``seconds <= seconds_k / (1 + tol)``.  Errors are compared as ``max(error,
    resolution)``: below the reference's own floor (:func:`floor_errors`) two errors cannot be
    told apart.
    With *tol* = 0 this is ordinary Pareto dominance (ties in both count as no dominance).
    A row whose image has exactly *k*'s errors (every metric equal: the same render, e.g. a
    film method ``"auto"`` resolves to) is the same point timed twice and never dominates it.
    Empty: *k* is on the front within the timing noise.
    """
    pts = [r for r in scene_points(rows, scene) if r["factor"] != "floor"]
    me = next(r for r in pts if row_key(r) == k)
    t, e = me["seconds"] / (1.0 + tol), max(me[metric], resolution)

    def same_render(r):
        return all(r[m] == me[m] for m in ("mean_de00", "p95_de00", "rmse", metric))

    def err(r):
        return max(r[metric], resolution)

    return [r for r in pts if row_key(r) != k and not same_render(r) and r["seconds"] <= t and err(r) <= e
            and (r["seconds"] < t or err(r) < e)]


def assess(rows, defaults, metric="interior_mean_de00", tol=None, target_error=TARGET_MEAN_DE00,
           target_speedup=TARGET_SPEEDUP, depth=None, use_floor=True):
    """Which settings meet the targets and sit on the front in every scene; the proposal.

    *defaults*: the renderer's current defaults as a setting (:func:`settings_from_defaults`) or
    its :func:`key`: the setting the verdict ``default_ok`` is about.  Candidates: every setting
    rendered in every scene at trace depth *depth* (default: the defaults' depth).  A candidate
    *qualifies* when, in every scene, its *metric* is at most *target_error*, it is at least
    *target_speedup* times faster than the reference, and no other setting dominates it beyond
    the timing noise *tol* (:func:`dominators`; default: :func:`timing_tolerance`) and by more
    than the reference's floor on that scene (:func:`floor_errors`; 0 when *use_floor* is
    False).  The *proposal* is the most accurate (smallest worst-scene
    error) of the qualifying settings whose time -- the geometric mean over scenes of
    seconds / reference seconds -- is within the timing noise of the fastest one: when
    times cannot be told apart, accuracy decides.

    Returns a dict: ``tol``, ``metric``, ``scenes``, ``candidates`` (key -> per-scene dicts
    with ``seconds``, ``error``, ``p95``, ``speedup``, ``dominated_by`` (keys), ``meets``;
    and ``qualifies``, ``cost``), ``floors`` (scene -> the floor used), ``qualifying`` (keys),
    ``proposal`` (key or None),
    ``default`` (the defaults' key) and ``default_ok`` (bool), ``problems`` (text).
    """
    if tol is None:
        tol = timing_tolerance(rows)
    default = defaults if isinstance(defaults, tuple) else key(defaults)
    if depth is None:
        depth = default[5]
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    per_scene = {sc: {row_key(r): r for r in scene_points(rows, sc, skip=("reference", "floor"))} for sc in scenes}
    floors = {sc: floor_errors(rows, sc, metric) if use_floor else 0.0 for sc in scenes}
    common = [k for k in per_scene[scenes[0]] if all(k in per_scene[sc] for sc in scenes) and k[5] == depth]
    p95_metric = metric.replace("mean", "p95")
    candidates = {}
    for k in common:
        info = {}
        for sc in scenes:
            r = per_scene[sc][k]
            dom = [row_key(d) for d in dominators(rows, sc, k, metric, tol, floors[sc])]
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
    return dict(tol=tol, metric=metric, scenes=scenes, candidates=candidates, floors=floors, qualifying=qualifying,
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


def scene_front(rows, scene, metric="interior_mean_de00"):
    """One scene's study as the paper draws and quotes it: its settings, the front, the defaults.

    Returns a dict with ``points`` (:func:`scene_points` without the reference, the floor and
    the ``default`` rows: every setting once, under the factor it was swept in, less the rows
    whose image is the defaults' own under another setting, e.g. ``"point"`` where the
    defaults' ``"auto"`` picks point sampling: the same render timed twice), ``front``
    (indices into ``points`` on the Pareto front of (seconds, *metric*), by increasing time),
    ``default`` (the row of the defaults the benchmark ran with, ``is_default``),
    ``default_on_front``, ``reference_seconds`` and ``floor`` (the second reference's row, or
    None).
    """
    sel = [r for r in rows if r["scene"] == scene]
    if not sel:
        raise ValueError(f"no rows for scene {scene!r}")
    default = next(r for r in sel if r["is_default"] == 1)

    def twin(r):  # the defaults' own image under another name ("point" where "auto" picks point)
        return row_key(r) != row_key(default) and all(r[m] == default[m] for m in ("mean_de00", "p95_de00", "rmse",
                                                                                   metric))

    pts = [r for r in scene_points(rows, scene, skip=("reference", "default", "floor")) if not twin(r)]
    idx = pareto_front([r["seconds"] for r in pts], [r[metric] for r in pts])
    return {
        "points": pts,
        "front": idx,
        "default": default,
        "default_on_front": any(row_key(pts[i]) == row_key(default) for i in idx),
        "reference_seconds": next(r["seconds"] for r in sel if r["factor"] == "reference"),
        "floor": next((r for r in sel if r["factor"] == "floor"), None),
    }
