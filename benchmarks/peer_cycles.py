"""Peer benchmark: our tracer against Blender's Cycles on soap bubbles of uniform films.

Run:  python benchmarks/peer_cycles.py [--quick] [--out PATH] [--cycles-python PATH] [--repeats N]
Writes ``data/derived/peer_cycles.csv`` and ``data/derived/peer_cycles_images.npz`` (read by
``paper/scripts/fig_peer_cycles.py`` and ``paper/scripts/numbers_cycles.py``); ``--quick`` is a
smoke test (48x48, few samples, one repeat) into a temporary folder unless ``--out`` is given.
Cycles runs in its own venv (bpy 5.0.1 needs numpy < 2; docs/peers.md): its Python is
``--cycles-python``, else ``$BUBBLEOPTICS_CYCLES_PYTHON``, else ``.venv-cycles/bin/python``
(``make peers`` creates it); without it the script says so in one line and exits with 2.
Cycles renders through ``benchmarks/cycles_render.py`` (a subprocess, the scene as JSON).

The scene (:func:`scene_description`, the same numbers for both): a bubble of radius 1 at the
origin, a uniform film of ``d`` nm and index 1.33 (10, 200, 400, 800 nm); a pinhole camera at
(0, 0, 4) looking at it, vertical field of view 40 degrees, box pixel filter; an environment
that varies with elevation only (:func:`environment_radiance`, a smooth ramp through five
distinct colours, as an equirectangular image both read).  Ours: the analytic sphere, Whitted
tree, threshold 0, depth 12; Cycles: Principled BSDF (IOR 1, transmission 1, roughness 0,
thin film) on an icosphere (20 * 4^6 triangles, radial normals), path tracing, 32 bounces.

1. **Orientation.**  The empty view and a mirror sphere in both (ours RGB, Cycles), the RMSE
   between them for the matched environment and for two wrong ones that must fail ("flipped":
   sky below; "tilted": the lookup turned 90 degrees about x, what forgetting y-up -> z-up does).
2. **References.**  Ours spectral (64 bands averaged over each band, 64 spp stratified) with
   two seeds; their mean is the reference, the CIEDE2000 between the two its own noise.  The
   same with water's dispersion (Daimon & Masumura) instead of n = 1.33: what dispersion changes.
   Cycles at ``CYCLES_REF_SPP`` spp with two seeds (mean and own noise likewise); ours at its
   defaults (16 bands, 1 spp, threshold 1e-3, depth 10).
3. **Colour differences.**  CIEDE2000 per pixel (:func:`study.delta_e00_images`),
   mean and 95th percentile over the bubble (pixels whose footprint lies inside the silhouette
   by more than 1.5 px), the edge (within 1.5 px of it) and all pixels (:func:`pixel_masks`).
4. **Decomposition** (:func:`model_image`).  A bubble of uniform film seen in an environment
   is a closed form: every hit along a ray meets the film at the same angle, so the pixel is
   R L(r_1) + sum_k T^2 R^k L(v_k) over the internal reflections.  Evaluated at pixel centres
   for (a) the exact spectral Airy reflectance with our colour pipeline (the reference's
   model), (b) the same with the Airy series cut after m = 3 (:func:`airy_cut`), (c) the exact
   reflectance per RGB channel through Rec.709 colour-matching functions normalised to unit
   area (illuminant E; each channel's light times that channel's R, as Cycles does), and
   (d) (c) with the cut and the clamp to [0, 1]: what Cycles 5.0 computes except its Fourier
   lookup table.  Steps: series cut (a->b), colour model (a->c), cut within it (c->d),
   table and the rest (d -> Cycles' render: the table, the mesh, the path tracer).
5. **Time to equal error** at 400 nm: Cycles at 1-256 spp, ours at its defaults at 1-16 spp,
   in rounds (a Cycles process doing every sample count after a warm-up render, then ours),
   ``--repeats`` rounds; median and min-max of the wall times (Cycles: around
   ``bpy.ops.render.render``, scene already synced; ours: ``render_with_stats`` render
   seconds).  Error: mean CIEDE2000 over the bubble against the reference, and against each
   renderer's own converged image (``own_bubble_mean``: Cycles' noise alone, without its
   colour model; ours' converged image is the reference).

Each phase holds ``/tmp/bubbleoptics-cpu.lock`` (``fcntl.flock``) while it runs and records
the load average before and after.
"""

from __future__ import annotations

import argparse
import contextlib
import fcntl
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "derived" / "peer_cycles.csv"
IMAGES_NAME = "peer_cycles_images.npz"
RENDER_SCRIPT = Path(__file__).resolve().parent / "cycles_render.py"
LOCK = Path("/tmp/bubbleoptics-cpu.lock")
MISSING_HINT = ("peer_cycles: no Cycles Python at {path}: run `make peers` (creates .venv-cycles with "
                "bpy 5.0.1) or set BUBBLEOPTICS_CYCLES_PYTHON")

SIZE = 128
FOV_DEG = 40.0
CAMERA = dict(position=(0.0, 0.0, 4.0), look_at=(0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0))
RADIUS = 1.0
FILM_N = 1.33
THICKNESSES = (10.0, 200.0, 400.0, 800.0)
TIMING_THICKNESS = 400.0
#: thread counts of the timing rounds, both renderers (a count above the machine's is skipped)
THREADS = (2, 1)
DEPTH = 12
BOUNCES = 32
SUBDIVISIONS = 6
ENV_SHAPE = (2048, 4)  # (rows, columns): elevation only
REF_SPP, REF_BANDS, REF_METHOD, REF_SEEDS = 64, 64, "band", (9001, 9002)
CYCLES_REF_SPP, CYCLES_REF_SEEDS = 1024, (100, 101)
CYCLES_SWEEP_SPP = (1, 4, 16, 64, 256)
OURS_SWEEP_SPP = (1, 2, 4, 8, 16)
ORIENTATIONS = ("matched", "flipped", "tilted")
EDGE_PX = 1.5
AIRY_CUT = 3  # Cycles' Airy sum stops after m = 3 (intern/cycles/kernel/closure/bsdf_util.h)

#: The environment: (elevation in degrees, linear RGB) knots, blended with a smoothstep.
ENV_KNOTS = (
    (-90.0, (0.10, 0.04, 0.02)),  # dark red-brown nadir
    (-30.0, (0.10, 0.35, 0.08)),  # green ground
    (0.0, (0.90, 0.55, 0.20)),  # orange horizon
    (30.0, (0.60, 0.80, 0.95)),  # pale blue sky
    (90.0, (0.06, 0.15, 0.65)),  # deep blue zenith
)


# ---------------------------------------------------------------------------------------------
# the scene, the same for both renderers


def environment_radiance(d, up=(0.0, 1.0, 0.0)):
    """Linear RGB radiance along unit directions *d* (..., 3): a function of the elevation
    asin(d . up) alone, a smoothstep blend between the :data:`ENV_KNOTS`."""
    d = np.asarray(d, float)
    e = np.degrees(np.arcsin(np.clip(d @ np.asarray(up, float), -1.0, 1.0)))
    knots = np.array([k[0] for k in ENV_KNOTS])
    colours = np.array([k[1] for k in ENV_KNOTS])
    i = np.clip(np.searchsorted(knots, e, side="right") - 1, 0, len(knots) - 2)
    s = np.clip((e - knots[i]) / (knots[i + 1] - knots[i]), 0.0, 1.0)
    s = (s * s * (3.0 - 2.0 * s))[..., None]
    return colours[i] * (1.0 - s) + colours[i + 1] * s


def environment_image(height=ENV_SHAPE[0], width=ENV_SHAPE[1]):
    """The environment as an equirectangular float32 (height, width, 3) image, row 0 at +y
    (``tracer.kernels.environment``'s convention): row i covers polar angles [i, i + 1) pi / height and
    is sampled at its centre.  Every column is the same (elevation only)."""
    theta = (np.arange(height) + 0.5) / height * math.pi
    d = np.stack([np.sin(theta), np.cos(theta), np.zeros_like(theta)], axis=-1)
    row = environment_radiance(d)
    return np.repeat(row[:, None, :], width, axis=1).astype(np.float32)


def scene_description(kind, thickness_nm=0.0, *, size=SIZE, orientation="matched", film_n=FILM_N):
    """The scene both sides read (our frame, y up); ``cycles_render.py`` takes it as its job."""
    if kind not in ("bubble", "mirror", "empty"):
        raise ValueError(f"unknown kind {kind!r}")
    return {"width": size, "height": size, "threads": 2, "bounces": BOUNCES, "subdivisions": SUBDIVISIONS,
            "camera": dict(CAMERA, fov_deg=FOV_DEG), "orientation": orientation,
            "object": {"kind": kind, "center": [0.0, 0.0, 0.0], "radius": RADIUS,
                       "thickness_nm": float(thickness_nm), "film_ior": float(film_n)}}


def our_scene(description, image, n_film=None):
    """The tracer scene of a :func:`scene_description` (``n_film`` overrides the film's index,
    e.g. ``"water"``)."""
    import tracer

    obj = description["object"]
    cam = description["camera"]
    spheres, bubbles = [], []
    if obj["kind"] == "mirror":
        mirror = tracer.Material(name="mirror", color=(1.0, 1.0, 1.0), ambient=0.0, diffuse=0.0, specular=1.0,
                                 transmission=0.0)
        spheres = [tracer.Sphere(tuple(obj["center"]), obj["radius"], mirror, name="mirror")]
    elif obj["kind"] == "bubble":
        film = tracer.FilmProfile(kind="uniform", thickness_nm=obj["thickness_nm"])
        bubbles = [tracer.Bubble(tuple(obj["center"]), obj["radius"], film=film,
                                 n_film=obj["film_ior"] if n_film is None else n_film)]
    return tracer.Scene(
        spheres=spheres, bubbles=bubbles,
        camera=tracer.Camera(position=tuple(cam["position"]), look_at=tuple(cam["look_at"]), up=tuple(cam["up"]),
                             fov_deg=cam["fov_deg"]),
        environment=tracer.Environment(kind="image", image=image, up=(0.0, 1.0, 0.0)),
        ambient=(0.0, 0.0, 0.0))


def camera_rays(size=SIZE, fov_deg=FOV_DEG, distance=4.0):
    """Unit directions (size, size, 3) through the pixel centres of the camera at (0, 0, distance)
    looking at the origin, y up, row 0 at the top; and the half width of a pixel in the image
    plane at unit distance."""
    t = math.tan(math.radians(fov_deg) / 2.0)
    c = (np.arange(size) + 0.5) / size * 2.0 - 1.0
    x = c[None, :] * t
    y = -c[:, None] * t
    d = np.stack(np.broadcast_arrays(x, y, -np.ones_like(x * y)), axis=-1)
    return d / np.linalg.norm(d, axis=-1, keepdims=True), t / size


def pixel_masks(size=SIZE, fov_deg=FOV_DEG, distance=4.0, radius=RADIUS, edge_px=EDGE_PX):
    """Boolean (size, size) masks ``bubble`` (the pixel centre more than *edge_px* pixels inside
    the silhouette), ``edge`` (within *edge_px* of it) and ``all``.  The silhouette of a sphere
    seen from its axis is the circle of radius tan(asin(radius / distance)) in the image plane."""
    t = math.tan(math.radians(fov_deg) / 2.0)
    c = (np.arange(size) + 0.5) / size * 2.0 - 1.0
    r = np.hypot(c[None, :] * t, c[:, None] * t)
    rho = math.tan(math.asin(radius / distance))
    pixel = 2.0 * t / size
    return {"bubble": r < rho - edge_px * pixel, "edge": np.abs(r - rho) <= edge_px * pixel,
            "all": np.ones((size, size), bool)}


def de_stats(image, reference, masks):
    """{region_mean, region_p95} of the per-pixel CIEDE2000 between two linear-RGB images."""
    from study.metrics import delta_e00_images

    de = delta_e00_images(image, reference)
    out = {}
    for name, m in masks.items():
        out[f"{name}_mean"] = float(np.mean(de[m]))
        out[f"{name}_p95"] = float(np.percentile(de[m], 95.0))
    return out


# ---------------------------------------------------------------------------------------------
# the decomposition: a closed-form image of the bubble for a given film reflectance model


def airy_cut(a, b, delta, m_max):
    """Reflectance |r|^2 of r = (a + b e^{i delta}) / (1 + a b e^{i delta}) (two interfaces of
    real amplitude reflectances *a*, *b* and round-trip phase *delta*) as its Fourier series in
    delta, C_0 + 2 sum_{m=1}^{m_max} C_m cos(m delta), cut after *m_max* (the exact value is
    :func:`bubbleoptics.film_reflectance`).  With rho = -a b and g = b (1 - a^2): C_0 = a^2 + g^2 / (1 - rho^2),
    C_m = rho^(m-1) (a g + g^2 rho / (1 - rho^2)) (expand 1 / (1 + a b e^{i delta}) as a
    geometric series and collect the terms of e^{i m delta}); Belcour & Barla's eq. 10 is the
    same series."""
    a, b, delta = np.broadcast_arrays(*(np.asarray(v, float) for v in (a, b, delta)))
    rho = -a * b
    g = b * (1.0 - a * a)
    c0 = a * a + g * g / (1.0 - rho * rho)
    k = a * g + g * g * rho / (1.0 - rho * rho)
    out = c0.copy()
    for m in range(1, m_max + 1):
        out = out + 2.0 * rho ** (m - 1) * k * np.cos(m * delta)
    return out


def free_film_reflectance(wavelength_nm, thickness_nm, cos0, n_film, m_max=None):
    """Unpolarised reflectance of a free-standing film (air | n_film | air), real index, through
    :func:`airy_cut` per polarisation (s and p Fresnel amplitudes of air -> film; film -> air is
    their negative).  ``m_max=None`` is exact: :func:`bubbleoptics.film_reflectance` itself."""
    if m_max is None:
        import bubbleoptics as bo

        return bo.film_reflectance(wavelength_nm, thickness_nm, np.arccos(np.clip(cos0, -1.0, 1.0)), n_film)
    wl = np.asarray(wavelength_nm, float)
    n = np.asarray(n_film, float)
    cos0 = np.asarray(cos0, float)
    sin2 = 1.0 - cos0**2
    cos1 = np.sqrt(1.0 - sin2 / n**2)
    rs = (cos0 - n * cos1) / (cos0 + n * cos1)
    rp = (n * cos0 - cos1) / (n * cos0 + cos1)
    delta = 4.0 * math.pi * n * thickness_nm * cos1 / wl
    return 0.5 * (airy_cut(rs, -rs, delta, m_max) + airy_cut(rp, -rp, delta, m_max))


@contextlib.contextmanager
def _quiet_numpy():
    with np.errstate(invalid="ignore", divide="ignore"):
        yield


def rgb_cmfs(wavelengths_nm):
    """(3, N) Rec.709 colour-matching functions (XYZ -> linear sRGB matrix times CIE 1931 2-degree
    x, y, z bar), each row normalised to sum 1: a flat reflectance gives (1, 1, 1) (illuminant
    E, white-balanced per channel), Cycles' colour model (intern/cycles/scene/shader.cpp,
    ``compute_thin_film_table``, tag v5.0.0)."""
    from bubbleoptics.colorimetry import XYZ_TO_LINEAR_SRGB, spectral_weights

    w = spectral_weights(np.asarray(wavelengths_nm, float), "E")
    rgb = XYZ_TO_LINEAR_SRGB @ w
    return rgb / rgb.sum(axis=1, keepdims=True)


def sphere_paths(size=SIZE, fov_deg=FOV_DEG, distance=4.0, radius=RADIUS, depth=DEPTH):
    """For every pixel centre: (hit mask, cos of the incidence angle, reflected direction of the
    first hit, the directions v_k (depth-1, size, size, 3) leaving after k internal reflections).
    Transmission goes straight on, so every hit meets the sphere at the same angle."""
    d, _ = camera_rays(size, fov_deg, distance)
    o = np.array([0.0, 0.0, distance])
    b = d @ o
    disc = b * b - (o @ o - radius * radius)
    hit = disc > 0
    t = -b - np.sqrt(np.where(hit, disc, 0.0))
    p = o + t[..., None] * d
    n = p / radius
    cos = np.clip(-(d * n).sum(-1), 0.0, 1.0)
    refl = d + 2.0 * cos[..., None] * n
    v = d.copy()
    q = p
    outs = []
    for _ in range(depth - 1):
        q = q + v * (2.0 * radius * cos)[..., None]  # the chord to the next hit
        outs.append(v.copy())
        nn = q / radius
        v = v - 2.0 * (v * nn).sum(-1)[..., None] * nn
    return hit, cos, refl, np.array(outs)


def fill_bubble(image, hit, refl, outs, R, light, to_rgb):
    """Write the bubble's pixels of *image* in place and return it: the first reflection
    ``R L(refl)`` plus the light through the film after k internal reflections,
    ``T^2 R^k L(v_k)`` (T = 1 - R, a lossless film), in the channels of *R* (P, C), then
    ``@ to_rgb.T``; *light(dirs)* is the environment in those channels, *refl* and *outs* as
    :func:`sphere_paths` returns them."""
    T = 1.0 - R
    radiance = R * light(refl[hit])
    weight = T * T
    for k in range(outs.shape[0]):
        radiance = radiance + weight * light(outs[k][hit])
        weight = weight * R
    image[hit] = radiance @ to_rgb.T
    return image


def model_image(model, thickness_nm, n_film=FILM_N, size=SIZE, depth=DEPTH, bands=REF_BANDS):
    """Closed-form image (size, size, 3) of the bubble for one reflectance *model*:
    ``"exact"``, ``"cut"`` (spectral, our colour pipeline: the tracer's channel_setup, bands,
    D65 weights, the Mallett-Yuksel basis for the environment), ``"rgb"`` (exact R per channel
    through :func:`rgb_cmfs`) or ``"cycles"`` (``"rgb"`` with the m = 3 cut and the clamp).
    Outside the bubble: the environment."""
    from tracer.prepare.pack import channel_setup

    hit, cos, refl, outs = sphere_paths(size, depth=depth)
    cam, _ = camera_rays(size)
    image = environment_radiance(cam)
    c = cos[hit]
    if model in ("exact", "cut"):
        wl, to_rgb, basis = channel_setup(True, bands)
        m_max = None if model == "exact" else AIRY_CUT
        with _quiet_numpy():
            R = free_film_reflectance(wl[None, :], thickness_nm, c[:, None], n_film, m_max)  # (P, C)
        def light(dirs):
            return environment_radiance(dirs) @ basis.T  # (P, C)
    elif model in ("rgb", "cycles"):
        wl = np.arange(360.0, 781.0, 1.0)
        s = rgb_cmfs(wl)
        m_max = None if model == "rgb" else AIRY_CUT
        with _quiet_numpy():
            R = free_film_reflectance(wl[None, :], thickness_nm, c[:, None], n_film, m_max) @ s.T  # (P, 3)
        if model == "cycles":
            R = np.clip(R, 0.0, 1.0)
        to_rgb = np.eye(3)
        light = environment_radiance
    else:
        raise ValueError(f"unknown model {model!r}")
    return fill_bubble(image, hit, refl, outs, R, light, to_rgb)


# ---------------------------------------------------------------------------------------------
# running the renderers


def cycles_python(option=None):
    """The Cycles venv's Python: *option*, $BUBBLEOPTICS_CYCLES_PYTHON, .venv-cycles/bin/python."""
    return Path(option or os.environ.get("BUBBLEOPTICS_CYCLES_PYTHON") or ROOT / ".venv-cycles" / "bin" / "python")


def run_cycles(python, description, env_path, renders, folder, tag):
    """Render *description* with Cycles: *renders* = [(spp, seed), ...]; returns (images, report)."""
    folder = Path(folder)
    job = dict(description, environment=str(env_path), report=str(folder / f"{tag}.json"),
               renders=[{"spp": int(spp), "seed": int(seed), "out": str(folder / f"{tag}_{k}.npy")}
                        for k, (spp, seed) in enumerate(renders)])
    job_path = folder / f"{tag}.job.json"
    job_path.write_text(json.dumps(job))
    proc = subprocess.run([str(python), str(RENDER_SCRIPT), str(job_path)], capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"cycles_render.py failed ({proc.returncode}):\n{proc.stderr[-2000:]}")
    report = json.loads(Path(job["report"]).read_text())
    images = [np.load(r["out"]).astype(np.float64) for r in job["renders"]]
    return images, report


def render_ours(scene, spp, seed, *, size, spectral=True, bands=REF_BANDS, method=REF_METHOD, threshold=0.0,
                depth=DEPTH):
    """(image, render seconds); ``spectral=None`` with the other settings None: our defaults."""
    import tracer

    image, stats = tracer.render_with_stats(scene, width=size, height=size, depth=depth, spp=spp, threshold=threshold,
                                            seed=seed, progress=False, spectral=spectral,
                                            spectral_samples=bands, spectral_method=method)
    return image, stats.render_seconds


def render_ours_defaults(scene, spp, seed, size):
    import tracer

    d = tracer.DEFAULTS
    return render_ours(scene, spp, seed, size=size, spectral=None, bands=d["spectral_samples"],
                       method=d["spectral_method"], threshold=d["threshold"], depth=d["depth"])


def loadavg():
    try:
        return Path("/proc/loadavg").read_text().split()[0]
    except OSError:
        return "n/a"


@contextlib.contextmanager
def cpu_lock(log, phase, use=True):
    """Hold the machine's CPU lock (if present and *use*) for one phase; log the load."""
    handle = None
    if use:
        try:
            handle = open(LOCK, "a")
            fcntl.flock(handle, fcntl.LOCK_EX)
        except OSError:
            handle = None
    before = loadavg()
    t0 = time.perf_counter()
    try:
        yield
    finally:
        log.append(f"{phase}: load {before} -> {loadavg()}, {time.perf_counter() - t0:.0f} s")
        print(f"  [{log[-1]}]", flush=True)
        if handle is not None:
            fcntl.flock(handle, fcntl.LOCK_UN)
            handle.close()


# ---------------------------------------------------------------------------------------------
# the benchmark


def equal_error_rows(d, timings, errors, own, cyc_sweep, ours_sweep, suffix, threads, add):
    """The timing rows of one thread count and the equal-error rows derived from them.

    *timings*: {(renderer, spp): [seconds, ...]}; *errors*, *own*: {(renderer, spp): de_stats row,
    bubble mean against the renderer's own converged image}.  Sections ``timing``, ``equal_error``
    and ``equal_own_error``, each with *suffix* (``""`` for two threads, ``"_1_thread"``).
    """
    from study.fronts import time_at_error

    rows, curves = [], {}
    for (renderer, s), ts in timings.items():
        row = dict(section="timing" + suffix, thickness_nm=d, renderer=renderer, threads=threads,
                   setting="defaults" if renderer == "ours" else "path tracing", spp=s,
                   seconds=float(np.median(ts)), seconds_min=float(min(ts)), seconds_max=float(max(ts)),
                   seconds_runs=" ".join(f"{t:.4f}" for t in ts), own_bubble_mean=own[(renderer, s)],
                   **errors[(renderer, s)])
        add(**row)  # add() keeps it in the benchmark's rows: not returned again
        curves.setdefault(renderer, []).append((row["seconds"], row["bubble_mean"], row["seconds_min"],
                                                row["seconds_max"]))
    # equal error: the errors Cycles reaches at each of its sample counts, where ours' curve
    # reaches them too; else ours' fastest point already beats it (a bound)
    ours_t = [c[0] for c in curves["ours"]]
    ours_e = [c[1] for c in curves["ours"]]
    bound_note = "ours' fastest setting already below this error: ratio is a lower bound"
    for t_c, e_c, lo, hi in curves["cycles"]:
        t_o = time_at_error(ours_t, ours_e, e_c)
        bound = ""
        if not math.isfinite(t_o) and e_c > max(ours_e):
            t_o, bound = min(ours_t), bound_note
        rows.append(dict(section="equal_error" + suffix, thickness_nm=d, renderer="cycles/ours", threads=threads,
                         setting=bound or "interpolated", target_bubble_mean=e_c, seconds_cycles=t_c,
                         seconds_cycles_min=lo, seconds_cycles_max=hi, seconds_ours=t_o,
                         ratio=t_c / t_o if math.isfinite(t_o) else float("nan")))
        print(f"  {threads} thread(s), equal error {e_c:.3f}: Cycles {t_c:.3f} s, ours {t_o:.4f} s, ratio "
              f"{rows[-1]['ratio']:.3g} {bound}", flush=True)
    # the same against each renderer's own converged image (noise only)
    own_o = [own[("ours", s)] for s in ours_sweep]
    for s in cyc_sweep:
        e_c, t_c = own[("cycles", s)], float(np.median(timings[("cycles", s)]))
        t_o = time_at_error(ours_t, own_o, e_c)
        bound = ""
        if not math.isfinite(t_o) and e_c > max(own_o):
            t_o, bound = min(ours_t), bound_note
        rows.append(dict(section="equal_own_error" + suffix, thickness_nm=d, renderer="cycles/ours", threads=threads,
                         setting=bound or "interpolated", spp=s, target_bubble_mean=e_c, seconds_cycles=t_c,
                         seconds_ours=t_o, ratio=t_c / t_o if math.isfinite(t_o) else float("nan")))
        print(f"  {threads} thread(s), equal error against own converged {e_c:.3f}: Cycles {t_c:.3f} s, ours "
              f"{t_o:.4f} s, ratio {rows[-1]['ratio']:.3g} {bound}", flush=True)
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="48x48, few samples, one repeat (smoke test)")
    parser.add_argument("--out", type=Path, default=None, help=f"CSV to write (default {OUT.relative_to(ROOT)})")
    parser.add_argument("--cycles-python", default=None, help="the Cycles venv's python (default "
                        "$BUBBLEOPTICS_CYCLES_PYTHON or .venv-cycles/bin/python)")
    parser.add_argument("--repeats", type=int, default=5, help="timing rounds")
    parser.add_argument("--no-lock", action="store_true", help=f"do not take {LOCK}")
    args = parser.parse_args(argv)

    python = cycles_python(args.cycles_python)
    if not (python.is_file() and os.access(python, os.X_OK)):
        print(MISSING_HINT.format(path=python), file=sys.stderr)
        return 2

    import tracer

    from study import provenance, write_csv
    from study.metrics import rmse

    quick = args.quick
    size = 48 if quick else SIZE
    repeats = 1 if quick else args.repeats
    ref_spp = 8 if quick else REF_SPP
    cyc_ref_spp = 32 if quick else CYCLES_REF_SPP
    cyc_sweep = CYCLES_SWEEP_SPP[:3] if quick else CYCLES_SWEEP_SPP
    ours_sweep = OURS_SWEEP_SPP[:3] if quick else OURS_SWEEP_SPP
    thicknesses = (10.0, 400.0) if quick else THICKNESSES
    out = args.out or (Path(tempfile.mkdtemp(prefix="peer_cycles_")) / OUT.name if quick else OUT)
    folder = Path(tempfile.mkdtemp(prefix="peer_cycles_run_"))
    log = []
    lock = not args.no_lock

    image = environment_image()
    env_path = folder / "environment.npy"
    np.save(env_path, image)
    masks = pixel_masks(size)
    rows = []
    blender = "?"

    def add(**row):
        rows.append(row)
        keys = ("bubble_mean", "bubble_p95", "edge_mean", "all_mean")
        print("  " + " ".join(f"{k}={row[k]}" for k in ("section", "thickness_nm", "renderer", "setting", "spp")
                              if k in row) + "  " + " ".join(f"{k} {row[k]:.3f}" for k in keys if k in row),
              flush=True)

    # 1. orientation
    print("orientation check (ours RGB 16 spp vs Cycles 64 spp):", flush=True)
    with cpu_lock(log, "orientation", lock):
        for kind in ("empty", "mirror"):
            desc = scene_description(kind, size=size)
            ours = render_ours(our_scene(desc, image), 16, 1, size=size, spectral=False)[0]
            for orientation in ORIENTATIONS:
                d2 = dict(desc, orientation=orientation)
                (theirs,), report = run_cycles(python, d2, env_path, [(16 if quick else 64, 1)], folder,
                                               f"orient_{kind}_{orientation}")
                blender = report["blender"]
                add(section="orientation", renderer="cycles", setting=f"{kind}/{orientation}", spp=16 if quick else 64,
                    rmse=rmse(theirs, ours), image_rms=float(np.sqrt(np.mean(ours**2))), **de_stats(theirs, ours, masks))

    # 2.-4. per thickness: references, Cycles, our defaults, dispersion, decomposition
    stored = {}
    for d in thicknesses:
        desc = scene_description("bubble", d, size=size)
        scene = our_scene(desc, image)
        print(f"\nfilm {d:g} nm:", flush=True)
        with cpu_lock(log, f"references {d:g} nm", lock):
            ref_a, t_ref = render_ours(scene, ref_spp, REF_SEEDS[0], size=size)
            ref_b, _ = render_ours(scene, ref_spp, REF_SEEDS[1], size=size)
            water, _ = render_ours(our_scene(desc, image, n_film="water"), ref_spp, REF_SEEDS[0], size=size)
            defaults, t_def = render_ours_defaults(scene, 1, 1, size)
            (cyc_a, cyc_b), report = run_cycles(python, desc, env_path,
                                                [(cyc_ref_spp, CYCLES_REF_SEEDS[0]), (cyc_ref_spp, CYCLES_REF_SEEDS[1])],
                                                folder, f"ref_{d:g}")
        ref = 0.5 * (ref_a + ref_b)
        cyc = 0.5 * (cyc_a + cyc_b)
        t_cyc = float(np.mean([r["seconds"] for r in report["renders"]]))
        common = dict(section="comparison", thickness_nm=d)
        add(**common, renderer="ours", setting="reference noise (seed A vs seed B)", spp=ref_spp,
            seconds=t_ref, **de_stats(ref_a, ref_b, masks))
        add(**common, renderer="cycles", setting="own noise (seed A vs seed B)", spp=cyc_ref_spp,
            seconds=t_cyc, **de_stats(cyc_a, cyc_b, masks))
        add(**common, renderer="cycles", setting="mean of two seeds vs reference", spp=2 * cyc_ref_spp,
            seconds=2 * t_cyc, **de_stats(cyc, ref, masks))
        add(**common, renderer="ours", setting="defaults vs reference", spp=1, seconds=t_def,
            **de_stats(defaults, ref, masks))
        add(**common, renderer="ours", setting="dispersion: water vs n = 1.33", spp=ref_spp,
            **de_stats(water, ref_a, masks))
        # decomposition (pixel centres; the bubble region only is meaningful: no anti-aliasing)
        models = {m: model_image(m, d, size=size) for m in ("exact", "cut", "rgb", "cycles")}
        steps = (("model check: exact model vs reference", models["exact"], ref),
                 ("series cut: cut vs exact", models["cut"], models["exact"]),
                 ("colour model: rgb vs exact", models["rgb"], models["exact"]),
                 ("cut and clamp in the rgb model: cycles model vs rgb", models["cycles"], models["rgb"]),
                 ("total model: cycles model vs exact", models["cycles"], models["exact"]),
                 ("table and the rest: Cycles render vs cycles model", cyc, models["cycles"]),
                 ("Cycles render vs exact model", cyc, models["exact"]))
        for label, a, b in steps:
            add(section="decomposition", thickness_nm=d, renderer="model", setting=label, **de_stats(a, b, masks))
        stored[d] = dict(ref=ref, cycles=cyc, defaults=defaults, cycles_model=models["cycles"])

    # 5. time to equal error (one thickness)
    d = TIMING_THICKNESS if TIMING_THICKNESS in thicknesses else thicknesses[-1]
    desc = scene_description("bubble", d, size=size)
    scene = our_scene(desc, image)
    ref = stored[d]["ref"]
    print(f"\ntiming at {d:g} nm, {repeats} rounds, {' and '.join(map(str, THREADS))} threads:", flush=True)
    import numba

    threads_here = [t for t in THREADS if t <= numba.config.NUMBA_NUM_THREADS]
    timings = {(t, renderer, s): [] for t in threads_here
               for renderer, sweep in (("cycles", cyc_sweep), ("ours", ours_sweep)) for s in sweep}
    errors, own = {}, {}
    for rnd in range(repeats):
        for t in threads_here:
            with cpu_lock(log, f"timing round {rnd + 1}, {t} thread{'s' if t > 1 else ''}", lock):
                renders = [(1, 500 + rnd)] + [(s, 1 + rnd) for s in cyc_sweep]
                imgs, report = run_cycles(python, dict(desc, threads=t), env_path, renders, folder, f"sweep_{rnd}_{t}")
                for s, img, r in zip(cyc_sweep, imgs[1:], report["renders"][1:]):
                    timings[(t, "cycles", s)].append(r["seconds"])
                    errors.setdefault(("cycles", s), de_stats(img, ref, masks))
                    # against Cycles' own converged image: its noise alone, without its colour model
                    own.setdefault(("cycles", s), de_stats(img, stored[d]["cycles"], masks)["bubble_mean"])
                previous = numba.get_num_threads()
                numba.set_num_threads(t)
                try:
                    render_ours_defaults(scene, 1, 99, size)  # warm (numba cache, packing)
                    for s in ours_sweep:
                        img, seconds = render_ours_defaults(scene, s, 1 + rnd, size)
                        timings[(t, "ours", s)].append(seconds)
                        errors.setdefault(("ours", s), de_stats(img, ref, masks))
                        own.setdefault(("ours", s), errors[("ours", s)]["bubble_mean"])  # ours is the reference
                finally:
                    numba.set_num_threads(previous)
    for t in threads_here:
        # two threads keep the section names the paper has always read; other counts get a suffix
        suffix = "" if t == 2 else f"_{t}_thread{'s' if t > 1 else ''}"
        rows += equal_error_rows(d, {(r, s): ts for (tt, r, s), ts in timings.items() if tt == t}, errors, own,
                                 cyc_sweep, ours_sweep, suffix, t, add)

    columns = ["section", "thickness_nm", "renderer", "threads", "setting", "spp", "seconds", "seconds_min", "seconds_max",
               "seconds_runs", "rmse", "image_rms"]
    columns += [f"{r}_{s}" for r in ("bubble", "edge", "all") for s in ("mean", "p95")] + ["own_bubble_mean"]
    columns += ["target_bubble_mean", "seconds_cycles", "seconds_cycles_min", "seconds_cycles_max", "seconds_ours",
                "ratio"]
    comments = [
        provenance(f"benchmarks/peer_cycles.py{' --quick' if quick else ''}",
                   f"Blender {blender} (Cycles, CPU), numba {numba.__version__}; the references with "
                   f"2 threads each, the timing with {' and '.join(map(str, threads_here))}",
                   "regenerate with: make bench-peers"),
        f"scene: bubble radius {RADIUS} at the origin, uniform film n = {FILM_N}; camera at (0, 0, 4), vertical fov "
        f"{FOV_DEG:g} deg, {size}x{size}, box filter; environment {ENV_SHAPE[1]}x{ENV_SHAPE[0]} equirectangular, "
        f"elevation only; ours: analytic sphere, Whitted, threshold 0, depth {DEPTH}; Cycles: Principled BSDF (IOR 1, "
        f"transmission 1, roughness 0, thin film) on an icosphere of {20 * 4**SUBDIVISIONS} triangles with radial "
        f"normals, {BOUNCES} bounces, no denoiser, no clamping, Standard view transform, 32-bit EXR",
        f"reference: ours spectral {REF_BANDS} bands ({REF_METHOD}), {ref_spp} spp, mean of seeds {REF_SEEDS}; Cycles: "
        f"mean of two seeds at {cyc_ref_spp} spp; defaults: ours at tracer.DEFAULTS, 1 spp; dE00 mean and p95 over "
        f"bubble (inside the silhouette by > {EDGE_PX} px), edge (within {EDGE_PX} px) and all pixels",
        "decomposition: closed-form images at pixel centres (exact spectral Airy, cut after m = 3, per-channel Rec.709 "
        "CMFs with illuminant E, both with the clamp); only the bubble region is free of anti-aliasing differences",
        "timing: wall seconds of bpy.ops.render.render (scene synced by a warm-up render) and of our render_with_stats "
        f"(compilation excluded), {repeats} interleaved rounds, each with {' and '.join(map(str, threads_here))} "
        "threads for both renderers (sections timing, equal_error, equal_own_error: 2 threads; the _1_thread "
        "sections: 1), median and min-max; load per phase: " + "; ".join(log),
    ]
    write_csv(out, rows, comments, fieldnames=columns, float_format="{:.6g}", extrasaction="ignore")
    # small images for the figure: reference, Cycles, their dE00 (float16)
    from study.metrics import delta_e00_images

    figure = {}
    for dd, s in stored.items():
        key = f"{dd:g}"
        figure[f"ref_{key}"] = s["ref"].astype(np.float16)
        figure[f"cycles_{key}"] = s["cycles"].astype(np.float16)
        figure[f"de_{key}"] = delta_e00_images(s["cycles"], s["ref"]).astype(np.float16)
    figure["thicknesses"] = np.array(list(stored))
    np.savez_compressed(out.parent / IMAGES_NAME, **figure)
    shutil.rmtree(folder, ignore_errors=True)
    print(f"\nwrote {out} and {out.parent / IMAGES_NAME}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
