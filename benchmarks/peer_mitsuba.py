"""Peer benchmark: our tracer against Mitsuba 3 on a clear glass sphere in an environment map.

Run:  python benchmarks/peer_mitsuba.py [--quick] [--out PATH] [--reference-seconds S]
Writes ``data/derived/peer_mitsuba.csv`` (read by ``paper/scripts/fig_peer.py``); ``--quick``
is a smoke test (64x64, low sample counts, one repeat) that writes to a temporary folder unless
``--out`` is given.  Not part of ``make test``: Mitsuba is an optional dependency
(``pip install mitsuba``; its LLVM variants need ``libLLVM``, Debian's ``libllvm19``).  Without
Mitsuba the script prints how to install it and exits with status 0.

Mitsuba has no thin film, so the common ground is a glass sphere (n = 1.5 in air) in front of an
equirectangular environment: ours traces the Whitted tree (Fresnel-weighted reflection and
refraction, both branches, total internal reflection, threshold 0, depth 12, RGB transport);
Mitsuba's ``path`` integrator samples one branch per bounce of its ``dielectric`` BSDF.  Same
pinhole camera (vertical field of view 40 degrees), 256x256, box pixel filter in both.

1. **Environment.**  A smooth procedural sky (gradient, ground, soft cells, seven Gaussian
   blobs 8-14 degrees wide), 1024x2048 float32 linear RGB, sampled at our texel centres.  Ours looks it up
   at the nearest texel; Mitsuba's ``envmap`` interpolates bilinearly.  Both use the same
   longitude convention, u = atan2(x, -z) / 2pi, and rows v = theta / pi
   (:func:`mitsuba_environment`).
2. **Orientation check.**  An empty view and a mirror sphere (which shows nearly the whole
   sphere of directions) rendered by both; the RMSE between them, and the same with three wrong
   orientations to show that the check can fail.
3. **References.**  Mitsuba (LLVM variant) at ``--reference-spp`` samples per pixel in passes
   of 256 with distinct seeds, and ours at 256 spp (another seed than the sweep's).  The RMSE
   between the two is the systematic floor (texture filtering; both integrate the same box
   pixel footprint).  The reference's own noise is estimated from its two halves.  The
   headline errors (``rmse``, ``mean_de00``) are against Mitsuba's: an independent renderer,
   whose bilinear lookup is the closer one to the continuous environment, so that any
   systematic difference counts against ours; the CSV also has the errors against ours and
   against the mean of the two.
4. **Sweeps.**  Ours at 1, 4, 16, 64 spp, exhaustive (threshold 0) and pruned (the default
   threshold 1e-3), timed by ``render_with_stats`` (compilation excluded); Mitsuba
   ``llvm_ad_rgb`` (stratified sampler, and independent) at 1-4096 spp and ``scalar_rgb``
   (stratified) at 1-1024 spp, each timed around ``mi.render`` plus the copy to NumPy (which
   waits for the JIT kernels).  Every configuration is rendered twice to warm up (Dr.Jit
   compiles a kernel per sample count), then timed in rounds over all configurations in turn,
   alternating the renderers.  The machine may be shared: before each run the script waits
   until other processes use at most 10 % of the CPUs (``/proc/stat``), measures their share
   during the run, and keeps only runs where it stayed at most 10 % ("clean"), until every
   configuration has ``--repeats`` clean runs (or ``--max-minutes`` pass; the CSV says which
   configurations fell short).  Runs shorter than 0.3 s are batches of renders (the batch's
   median is the run's time) so that the accounting has enough clock ticks.  seconds = the
   median of the clean runs; the CSV keeps every run with its share.
   Seeds differ between rounds; the error is that of the first round.  Errors: RMSE over
   pixels and channels (linear RGB) and mean CIEDE2000 (:func:`study.delta_e00_images`)
   against each reference.
5. **Time to equal error.**  log(time) interpolated linearly in log(error) along each curve, at
   each error target, between the curves of the same thread count.

**Threads.**  Every sweep runs at each count of ``--threads`` (default 1 and 2), both renderers
alike: :func:`with_threads` sets numba's count (our render threads) and Dr.Jit's thread pool
(Mitsuba's LLVM kernels and its scalar variant's blocks) before each timed run.  The scalar
variant stops at 256 spp on one thread.  The checks and references use every core.

**Variant.**  The LLVM variant is ``llvm_ad_rgb``: the wheels on PyPI ship only the ``_ad_``
variants of the LLVM and CUDA back ends (the list of mitsuba-renderer/mitsuba3 pull request
#1355); a plain ``llvm_rgb`` needs a build from source.  No parameter here has gradients
enabled, so Dr.Jit's AD layer records nothing; the kernels are the forward ones.  Renderers run
one after the other in the same process.  Mitsuba's kernels are cached by Dr.Jit in ``~/.drjit``.
"""

from __future__ import annotations

import argparse
import math
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from study import provenance, write_csv
from study.fronts import time_at_error
from study.metrics import delta_e00_images, rmse

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "derived" / "peer_mitsuba.csv"

INSTALL_HINT = "mitsuba not installed: pip install mitsuba (and apt install libllvm19 for its LLVM variants)"

SIZE = 256
DEPTH = 12  # ours: ray generations <= 12; Mitsuba: max_depth 12 (the same paths, up to 11 bounces)
FOV_DEG = 40.0
CAMERA = dict(position=(0.0, 0.0, 4.0), look_at=(0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0))
IOR = 1.5
ENV_SHAPE = (1024, 2048)
OURS_SPP = (1, 4, 16, 64)
OURS_REFERENCE_SPP = 256
MITSUBA_SPP = (1, 4, 16, 64, 256, 1024, 4096)
SCALAR_MAX_SPP = 1024  # the scalar variant is 5-10x slower; its curve is clear by then
SCALAR_MAX_SPP_ONE_THREAD = 256  # on one thread, the scalar variant's slowest points would take minutes each
REFERENCE_PASS_SPP = 256
SEED_SWEEP = 1  # first seed of the sweeps (repeats use the next ones)
SEED_OURS_REFERENCE = 9001
SEED_MITSUBA_REFERENCE = 100_000  # pass k uses this + k

#: (direction (world, y up), angular width sigma in degrees, linear RGB amplitude)
BLOBS = (
    ((-0.30, 0.25, -1.0), 8.0, (1.20, 0.45, 0.05)),  # orange, behind the sphere, upper left
    ((0.35, -0.20, -1.0), 8.0, (0.05, 0.80, 0.15)),  # green, behind the sphere, lower right
    ((0.10, 0.45, -1.0), 9.0, (0.15, 0.25, 1.10)),  # blue, behind the sphere, top
    ((0.60, 0.50, 1.0), 12.0, (1.10, 1.00, 0.80)),  # warm white, behind the camera (reflections)
    ((-0.70, 0.10, 0.60), 10.0, (0.90, 0.05, 0.40)),  # magenta, behind the camera, left
    ((-1.0, 0.20, -0.20), 10.0, (0.90, 0.75, 0.05)),  # yellow, left
    ((1.0, -0.40, 0.10), 14.0, (0.10, 0.35, 1.00)),  # blue, right, low
)

#: The reference used for the headline numbers (the CSV has the errors against all three).
HEADLINE_REFERENCE = "mitsuba"


# ---------------------------------------------------------------------------------------------
# the scene


def environment_radiance(d):
    """Linear RGB radiance of the procedural environment along unit directions *d* (..., 3), y up.

    A sky (pale horizon to blue zenith as 1 - (1 - e)^2 in the elevation e = d_y), a brown ground
    darkening downwards, blended over |e| < 0.1 with a smoothstep, modulated by soft cells
    1 + 0.35 cos(8 azimuth) sin(8 elevation), plus :data:`BLOBS`, each
    A exp(-angle^2 / (2 sigma^2)).  Smooth on the scale of a texel (0.18 degrees; the narrowest
    feature, sigma = 8 degrees, spans 45 texels), so nearest and bilinear lookups differ by a
    fraction of a percent.
    """
    d = np.asarray(d, dtype=float)
    e = d[..., 1:2]
    horizon = np.array([0.50, 0.55, 0.60])
    zenith = np.array([0.10, 0.20, 0.50])
    ground_near = np.array([0.22, 0.18, 0.14])
    ground_far = np.array([0.06, 0.05, 0.04])
    t_up = 1.0 - (1.0 - np.clip(e, 0.0, 1.0)) ** 2
    sky = horizon + (zenith - horizon) * t_up
    t_down = np.clip(-e, 0.0, 1.0)
    ground = ground_near + (ground_far - ground_near) * t_down
    s = np.clip((e + 0.1) / 0.2, 0.0, 1.0)
    s = s * s * (3.0 - 2.0 * s)
    rgb = s * sky + (1.0 - s) * ground
    # soft cells, 45 degrees in azimuth by 22.5 in elevation, so refraction shows its distortion
    azimuth = np.arctan2(d[..., 0:1], -d[..., 2:3])
    elevation = np.arcsin(np.clip(e, -1.0, 1.0))
    rgb = rgb * (1.0 + 0.35 * np.cos(8.0 * azimuth) * np.sin(8.0 * elevation))
    for direction, sigma_deg, amplitude in BLOBS:
        c = np.asarray(direction, float)
        c /= np.linalg.norm(c)
        angle = np.arccos(np.clip(d @ c, -1.0, 1.0))[..., None]
        rgb = rgb + np.asarray(amplitude) * np.exp(-0.5 * (angle / math.radians(sigma_deg)) ** 2)
    return rgb


def environment_image(height=ENV_SHAPE[0], width=ENV_SHAPE[1]):
    """The environment as an equirectangular float32 (height, width, 3) image in *our* convention.

    ``tracer.kernels.environment`` with up = +y uses the frame x' = (0, 0, -1), z' = (1, 0, 0)
    (``tracer.prepare.pack``), so texel (i, j) covers polar angle theta in [i, i + 1) pi / height and
    phi = atan2(-d_z, d_x) + pi in [j, j + 1) 2 pi / width; it is sampled at the centres.
    """
    theta = (np.arange(height) + 0.5) / height * math.pi
    alpha = (np.arange(width) + 0.5) / width * 2.0 * math.pi - math.pi  # atan2(-d_z, d_x)
    st = np.sin(theta)[:, None]
    d = np.stack(np.broadcast_arrays(st * np.cos(alpha)[None, :], np.cos(theta)[:, None],
                                     -st * np.sin(alpha)[None, :]), axis=-1)
    return environment_radiance(d).astype(np.float32)


def our_scene(kind, image, camera=None):
    """A tracer scene: ``"glass"`` (clear n = 1.5 sphere), ``"mirror"`` or ``"empty"``."""
    import tracer

    spheres = []
    if kind == "glass":
        glass = tracer.Material(name="glass", color=(1.0, 1.0, 1.0), ambient=0.0, diffuse=0.0, specular=0.0,
                                transmission=1.0, ior=IOR)
        spheres = [tracer.Sphere((0.0, 0.0, 0.0), 1.0, glass, name="glass")]
    elif kind == "mirror":
        mirror = tracer.Material(name="mirror", color=(1.0, 1.0, 1.0), ambient=0.0, diffuse=0.0, specular=1.0,
                                 transmission=0.0)
        spheres = [tracer.Sphere((0.0, 0.0, 0.0), 1.0, mirror, name="mirror")]
    elif kind != "empty":
        raise ValueError(kind)
    cam = dict(CAMERA, **(camera or {}))
    return tracer.Scene(
        spheres=spheres,
        camera=tracer.Camera(position=cam["position"], look_at=cam["look_at"], up=cam["up"], fov_deg=FOV_DEG),
        environment=tracer.Environment(kind="image", image=image, up=(0.0, 1.0, 0.0)),
        ambient=(0.0, 0.0, 0.0),
    )


def mitsuba_environment(mi, image, folder, orientation="matched"):
    """Write the image for Mitsuba as EXR; return the ``envmap`` dict.

    Both renderers map a direction d to u = atan2(d_x, -d_z) / 2 pi (mod 1), v = acos(d_y) / pi
    (row 0 at +y): ours adopted Mitsuba's ``envmap`` convention (tracer.kernels.environment;
    tests/tracer/test_environment.py renders one environment in both), so the matched orientation is
    the image as it is, with no rotation.  Both put texel centres at (j + 1/2) / width in u; in
    v Mitsuba places row i at i / (height - 1) (ours: (i + 1/2) / height), at most half a texel
    (0.09 degrees) apart, at the poles.

    *orientation*: ``"matched"``, or one of the wrong ones of the orientation check:
    ``"mirrored"`` (the image mirrored left-right), ``"rotated_90"`` and ``"rotated_-90"`` (rotated about y).
    """
    mirrored = orientation == "mirrored"
    angle = {"matched": 0.0, "mirrored": 0.0, "rotated_90": 90.0, "rotated_-90": -90.0}[orientation]
    data = np.ascontiguousarray(image[:, ::-1] if mirrored else image, dtype=np.float32)
    path = Path(folder) / f"environment_{'mirrored' if mirrored else 'plain'}.exr"
    if not path.exists():
        mi.Bitmap(data).write(str(path))
    return {"type": "envmap", "filename": str(path),
            "to_world": mi.ScalarTransform4f().rotate(axis=[0, 1, 0], angle=angle)}


def mitsuba_scene(mi, kind, envmap, *, size=SIZE, sampler="stratified", camera=None):
    """The Mitsuba scene matching :func:`our_scene` (``path`` integrator, box filter)."""
    cam = dict(CAMERA, **(camera or {}))
    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": DEPTH, "rr_depth": 1000, "hide_emitters": False},
        "sensor": {
            "type": "perspective",
            "fov": FOV_DEG,
            "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(origin=list(cam["position"]), target=list(cam["look_at"]),
                                                       up=list(cam["up"])),
            "film": {"type": "hdrfilm", "width": size, "height": size, "pixel_format": "rgb",
                     "rfilter": {"type": "box"}},
            "sampler": {"type": sampler, "sample_count": 1},
        },
        "environment": envmap,
    }
    if kind == "glass":
        scene["sphere"] = {"type": "sphere", "center": [0, 0, 0], "radius": 1.0,
                           "bsdf": {"type": "dielectric", "int_ior": IOR, "ext_ior": 1.0}}
    elif kind == "mirror":
        scene["sphere"] = {"type": "sphere", "center": [0, 0, 0], "radius": 1.0,
                           "bsdf": {"type": "conductor", "material": "none"}}
    elif kind != "empty":
        raise ValueError(kind)
    return mi.load_dict(scene)


# ---------------------------------------------------------------------------------------------
# rendering and errors


def render_ours(scene, spp, seed, size=SIZE, threshold=0.0):
    """(image, seconds, rays): RGB transport, exhaustive tree by default, compilation excluded."""
    import tracer

    image, stats = tracer.render_with_stats(scene, width=size, height=size, depth=DEPTH, spp=spp,
                                            threshold=threshold, seed=seed, progress=False)
    assert not stats.spectral
    return image, stats.render_seconds, stats.rays["total"]


def render_mitsuba(mi, scene, spp, seed):
    """(image, seconds, None) of ``mi.render``; the copy to NumPy waits for the (asynchronous)
    kernels."""
    t0 = time.perf_counter()
    image = np.array(mi.render(scene, spp=spp, seed=seed), dtype=np.float64)
    return image[..., :3], time.perf_counter() - t0, None


def mean_de00(a, b):
    """Mean CIEDE2000 of two linear-RGB images (negative values clipped to 0)."""
    return float(np.mean(delta_e00_images(a, b)))


#: A timing run counts ("clean") when other processes used at most this share of the CPUs.
QUIET_SHARE = 0.10
#: Runs shorter than this are batched (the median of the batch is the run's time), so that the
#: CPU accounting of /proc/stat (1/100 s ticks) can tell a quiet machine from a busy one.
MIN_WINDOW_SECONDS = 0.3


def cpu_counters():
    """(wall seconds, CPU seconds used by every process, by this one); (wall, nan, nan) off Linux."""
    wall = time.perf_counter()
    try:
        with open("/proc/stat") as f:
            fields = [int(v) for v in f.readline().split()[1:9]]
    except (OSError, ValueError):
        return wall, float("nan"), float("nan")
    busy = sum(fields) - fields[3] - fields[4]  # all but idle and iowait (steal counts as busy)
    own = os.times()
    return wall, busy / os.sysconf("SC_CLK_TCK"), own.user + own.system


def other_share(before, after):
    """Share of all CPUs used by other processes between two :func:`cpu_counters`."""
    wall = after[0] - before[0]
    others = (after[1] - before[1]) - (after[2] - before[2])
    return max(0.0, others) / (wall * (os.cpu_count() or 1)) if wall > 0 else float("nan")


def wait_until_quiet(deadline, window=1.0, poll=5.0):
    """Sleep until other processes use at most QUIET_SHARE of the CPUs over *window* seconds
    (or until *deadline*); returns the seconds waited."""
    t0 = time.perf_counter()
    while time.perf_counter() < deadline:
        before = cpu_counters()
        time.sleep(window)
        share = other_share(before, cpu_counters())
        if not share > QUIET_SHARE:  # also when unknown (nan)
            break
        time.sleep(poll)
    return time.perf_counter() - t0


def timed_batch(render, seed, n):
    """*n* renders with seeds seed*1000 + i: (median seconds, other processes' CPU share over the
    batch, first image, first ray count)."""
    before = cpu_counters()
    times, first = [], None
    for i in range(n):
        image, seconds, rays = render(seed * 1000 + i if n > 1 else seed)
        times.append(seconds)
        if first is None:
            first = (image, rays)
    share = other_share(before, cpu_counters())
    return float(np.median(times)), share, first[0], first[1]


# ---------------------------------------------------------------------------------------------
# the benchmark


def orientation_check(mi, image, folder, size, spp_mitsuba, spp_ours):
    """RMSE between the two renderers for the empty view and the mirror sphere, per orientation."""
    results = {}
    for orientation in ("matched", "mirrored", "rotated_90", "rotated_-90"):
        envmap = mitsuba_environment(mi, image, folder, orientation)
        for kind in ("empty", "mirror"):
            ours = render_ours(our_scene(kind, image), spp_ours, SEED_SWEEP, size)[0]
            theirs = render_mitsuba(mi, mitsuba_scene(mi, kind, envmap, size=size), spp_mitsuba, SEED_SWEEP)[0]
            scale = float(np.sqrt(np.mean(ours**2)))
            results[(orientation, kind)] = (rmse(ours, theirs), mean_de00(ours, theirs), scale)
    return results


def mitsuba_reference(mi, scene, spp_total, seconds_budget):
    """Mean of passes of REFERENCE_PASS_SPP spp (seeds SEED_MITSUBA_REFERENCE + k) until
    *spp_total* or the time budget; returns (image, spp, seconds, noise RMSE estimate)."""
    passes = max(2, spp_total // REFERENCE_PASS_SPP)
    images = []
    t0 = time.perf_counter()
    for k in range(passes):
        images.append(render_mitsuba(mi, scene, REFERENCE_PASS_SPP, SEED_MITSUBA_REFERENCE + k)[0])
        if len(images) >= 2 and len(images) % 2 == 0 and time.perf_counter() - t0 > seconds_budget:
            break
    seconds = time.perf_counter() - t0
    n = len(images) - len(images) % 2
    half_a = np.mean(images[: n // 2], axis=0)
    half_b = np.mean(images[n // 2 : n], axis=0)
    # each half has twice the variance of the full mean: RMSE(full - truth) ~ RMSE(a - b) / 2
    noise = rmse(half_a, half_b) / 2.0
    return np.mean(images[:n], axis=0), n * REFERENCE_PASS_SPP, seconds, noise


def with_threads(n, render, *args):
    """``render(*args)`` with *n* threads in both renderers: numba's (our tracer's render threads,
    :func:`tracer.rendering.local.render_threads`) and Dr.Jit's pool (Mitsuba's LLVM kernels and its
    scalar variant's blocks), set before the call, outside its timing."""
    import numba

    import drjit as dr

    if numba.get_num_threads() != n:
        numba.set_num_threads(n)
    if dr.thread_count() != n:
        dr.set_thread_count(n)
    return render(*args)


def threads_note():
    import numba

    import drjit as dr

    return (f"numba {numba.__version__} with {numba.get_num_threads()} threads "
            f"(layer {numba.config.THREADING_LAYER}), drjit {dr.__version__} with {dr.thread_count()} threads")


#: The oldest LLVM whose code generator handles Dr.Jit 1.5's kernels: with Debian 12's LLVM 14 or
#: 15 the LLVM variant aborts the process ("Cannot select: ... fminimum"), found on 2026-12-02.
MIN_LLVM = 16


def _choose_libllvm():
    """Point Dr.Jit at the newest system ``libLLVM-N.so`` (N >= MIN_LLVM) unless
    ``DRJIT_LIBLLVM_PATH`` is set: left to itself it may load an older one that aborts."""
    if os.environ.get("DRJIT_LIBLLVM_PATH"):
        return
    import glob
    import re

    found = []
    for path in glob.glob("/usr/lib/x86_64-linux-gnu/libLLVM-*.so") + glob.glob("/usr/lib/llvm-*/lib/libLLVM.so"):
        m = re.search(r"(?:libLLVM-|llvm-)(\d+)", path)
        if m and int(m.group(1)) >= MIN_LLVM:
            found.append((int(m.group(1)), path))
    if found:
        os.environ["DRJIT_LIBLLVM_PATH"] = max(found)[1]
        print(f"Dr.Jit's LLVM: {max(found)[1]}", file=sys.stderr)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="64x64, low sample counts, one repeat (smoke test)")
    parser.add_argument("--out", type=Path, default=None, help=f"CSV to write (default {OUT.relative_to(ROOT)}; "
                        "with --quick a temporary folder)")
    parser.add_argument("--repeats", type=int, default=3, help="clean timing runs per configuration")
    parser.add_argument("--max-minutes", type=float, default=60.0,
                        help="stop collecting timing runs after this long (the CSV notes configurations left short)")
    parser.add_argument("--reference-spp", type=int, default=32768)
    parser.add_argument("--reference-seconds", type=float, default=150.0,
                        help="stop the Mitsuba reference after this many seconds (an even number of passes)")
    parser.add_argument("--threads", default="1,2",
                        help="comma-separated thread counts; each sweep runs at each, both renderers alike "
                             "(numba.set_num_threads and drjit.set_thread_count before each timed run)")
    args = parser.parse_args(argv)
    try:
        thread_counts = sorted({int(t) for t in args.threads.split(",") if t.strip()})
    except ValueError:
        parser.error(f"--threads: comma-separated positive integers, got {args.threads!r}")
    if not thread_counts or min(thread_counts) < 1 or max(thread_counts) > (os.cpu_count() or 1):
        parser.error(f"--threads: each count in 1..{os.cpu_count()} (this machine's cores), got {args.threads!r}")

    _choose_libllvm()
    try:
        import drjit as dr
        import mitsuba as mi
    except ImportError:
        print(INSTALL_HINT)
        return 0

    import numba

    import tracer

    quick = args.quick
    size = 64 if quick else SIZE
    repeats = 1 if quick else args.repeats
    budget_minutes = 2.0 if quick else args.max_minutes
    ours_spp = OURS_SPP[:3] if quick else OURS_SPP
    mitsuba_spp = MITSUBA_SPP[:4] if quick else MITSUBA_SPP
    ref_spp = 1024 if quick else args.reference_spp
    ref_budget = 10.0 if quick else args.reference_seconds
    out = args.out or (Path(tempfile.mkdtemp(prefix="peer_mitsuba_")) / OUT.name if quick else OUT)

    variants = [v for v in ("llvm_ad_rgb", "scalar_rgb") if v in mi.variants()]
    llvm_ok = False
    try:
        mi.set_variant("llvm_ad_rgb")
        llvm_ok = True
    except Exception as exc:  # no libLLVM: DRJIT_LIBLLVM_PATH names the .so
        print(f"llvm_ad_rgb unavailable ({exc}); set DRJIT_LIBLLVM_PATH to libLLVM.so", file=sys.stderr)
        variants = [v for v in variants if v != "llvm_ad_rgb"]
    if not variants:
        print("neither llvm_ad_rgb nor scalar_rgb can run; nothing to do", file=sys.stderr)
        return 1
    ref_variant = variants[0]
    mi.set_variant(ref_variant)
    max_threads = max(thread_counts)
    numba.set_num_threads(max_threads)  # the checks and references; each sweep run sets its own
    dr.set_thread_count(max_threads)
    note = (threads_note() + "; sweeps at " + " and ".join(map(str, thread_counts))
            + " threads in both renderers (column threads)") if llvm_ok else ""
    print(f"mitsuba {mi.__version__}; variants {variants}; {provenance('benchmarks/peer_mitsuba.py', note)}",
          flush=True)

    image = environment_image(*((256, 512) if quick else ENV_SHAPE))
    folder = tempfile.mkdtemp(prefix="peer_env_")
    glass_ours = our_scene("glass", image)
    tracer.render(glass_ours, width=8, height=8, depth=DEPTH, threshold=0.0, progress=False)  # compile

    # 1. orientation
    print("\norientation check (RMSE and mean dE00 between the renderers; mean radiance RMS for scale):")
    check = orientation_check(mi, image, folder, size, 64 if quick else 256, 16 if quick else 64)
    for (orientation, kind), (err, de, scale) in check.items():
        print(f"  {orientation:12s} {kind:6s}  RMSE {err:.5f}  dE00 {de:.3f}  (image RMS {scale:.3f})")

    # 2. references
    envmap = mitsuba_environment(mi, image, folder)
    ref_ours, ref_ours_seconds, ref_ours_rays = render_ours(glass_ours, OURS_REFERENCE_SPP, SEED_OURS_REFERENCE,
                                                            size)
    glass_mi = mitsuba_scene(mi, "glass", envmap, size=size)
    render_mitsuba(mi, glass_mi, REFERENCE_PASS_SPP, 0)  # warm-up
    ref_mi, ref_mi_spp, ref_mi_seconds, ref_mi_noise = mitsuba_reference(mi, glass_mi, ref_spp, ref_budget)
    references = {"mitsuba": ref_mi, "ours": ref_ours, "mean": 0.5 * (ref_mi + ref_ours)}
    floor_rmse = rmse(ref_mi, ref_ours)
    floor_de = mean_de00(ref_mi, ref_ours)
    print(f"\nreferences: Mitsuba {ref_variant} {ref_mi_spp} spp ({ref_mi_seconds:.1f} s, noise RMSE"
          f" ~{ref_mi_noise:.2e}), ours {OURS_REFERENCE_SPP} spp ({ref_ours_seconds:.2f} s);"
          f" RMSE between them {floor_rmse:.2e}, mean dE00 {floor_de:.3f}", flush=True)

    # 3. sweeps: every configuration warmed up, then timed in rounds (renderers alternating) until
    # each has `repeats` runs during which other processes left the CPUs alone
    # (renderer, variant, sampler, threshold, spp, threads, render(seed) -> (image, seconds, rays))
    configs = []
    ours_configs = []
    for threads in thread_counts:
        for variant, threshold in (("exhaustive", 0.0), ("pruned", tracer.DEFAULTS["threshold"])):
            for spp in ours_spp:
                ours_configs.append(("ours", variant, "stratified", threshold, spp, threads,
                                     lambda seed, spp=spp, th=threshold, n=threads:
                                     with_threads(n, render_ours, glass_ours, spp, seed, size, th)))
    mitsuba_configs = []
    for variant, sampler in (("llvm_ad_rgb", "stratified"), ("llvm_ad_rgb", "independent"),
                             ("scalar_rgb", "stratified")):
        if variant not in variants:
            continue
        mi.set_variant(variant)
        scene_v = mitsuba_scene(mi, "glass", mitsuba_environment(mi, image, folder), size=size, sampler=sampler)

        def run(seed, spp, threads, scene_v=scene_v, variant=variant):
            mi.set_variant(variant)  # outside the timed call; a no-op when already set
            return with_threads(threads, render_mitsuba, mi, scene_v, spp, seed)

        for threads in thread_counts:
            for spp in mitsuba_spp:
                cap = 64 if quick else (SCALAR_MAX_SPP if threads > 1 else SCALAR_MAX_SPP_ONE_THREAD)
                if variant == "scalar_rgb" and spp > cap:
                    continue
                mitsuba_configs.append(("mitsuba", variant, sampler, "", spp, threads,
                                        lambda seed, spp=spp, run=run, n=threads: run(seed, spp, n)))
    for k in range(max(len(ours_configs), len(mitsuba_configs))):  # alternate the two renderers
        configs += ours_configs[k : k + 1] + mitsuba_configs[k : k + 1]

    print(f"\nsweeps: warm-up, then rounds until every configuration has {repeats} clean runs "
          f"(other processes below {QUIET_SHARE:.0%} of the CPUs; at most {budget_minutes:g} minutes)", flush=True)
    batch = {}
    for k, (*_, render) in enumerate(configs):
        render(SEED_SWEEP + 1000)  # compilation (numba: once; Dr.Jit: per sample count), caches
        seconds = render(SEED_SWEEP + 1001)[1]
        batch[k] = max(1, math.ceil(MIN_WINDOW_SECONDS / max(seconds, 1e-4)))
    runs = {k: [] for k in range(len(configs))}  # (seconds, share of the CPUs used by other processes)
    first = {}
    deadline = time.perf_counter() + 60.0 * budget_minutes
    rnd = 0
    waited = 0.0
    while True:
        todo = [k for k in range(len(configs)) if sum(sh <= QUIET_SHARE for _, sh in runs[k]) < repeats]
        if not todo or time.perf_counter() > deadline:
            break
        for k in todo:
            waited += wait_until_quiet(deadline)
            *_, render = configs[k]
            seconds, share, image_k, rays = timed_batch(render, SEED_SWEEP + rnd, batch[k])
            runs[k].append((seconds, share))
            if k not in first:
                first[k] = (image_k, rays)
        rnd += 1
        clean = min(sum(sh <= QUIET_SHARE for _, sh in runs[k]) for k in range(len(configs)))
        print(f"  round {rnd}: {len(todo)} configurations run; fewest clean runs {clean}/{repeats}", flush=True)
    short = [k for k in range(len(configs)) if sum(sh <= QUIET_SHARE for _, sh in runs[k]) < repeats]
    load_note = (f"timing runs kept when other processes used <= {QUIET_SHARE:.0%} of the CPUs (from /proc/stat), "
                 f"{rnd} rounds, {waited:.0f} s spent waiting for a quiet machine"
                 + (f"; {len(short)} configurations short of {repeats} clean runs" if short else ""))

    rows = []

    def add(renderer, variant, sampler, threshold, spp, threads, image_, rays, runs_, role="sweep"):
        clean = [t for t, sh in runs_ if sh <= QUIET_SHARE] or [t for t, _ in runs_]
        row = dict(renderer=renderer, variant=variant, sampler=sampler, threshold=threshold, spp=spp,
                   threads=threads, role=role,
                   width=size, height=size, depth=DEPTH, seconds=float(np.median(clean)),
                   seconds_min=float(min(clean)), clean_runs=sum(sh <= QUIET_SHARE for _, sh in runs_),
                   seconds_runs=" ".join(f"{t:.4f}" for t, _ in runs_),
                   other_cpu_share=" ".join(f"{sh:.2f}" for _, sh in runs_), rays="" if rays is None else rays)
        for name, ref in references.items():
            row[f"rmse_vs_{name}"] = rmse(image_, ref)
            row[f"de00_vs_{name}"] = mean_de00(image_, ref)
        row["rmse"] = row[f"rmse_vs_{HEADLINE_REFERENCE}"]
        row["mean_de00"] = row[f"de00_vs_{HEADLINE_REFERENCE}"]
        rows.append(row)
        print(f"  {renderer:7s} {variant:11s} {sampler:11s} {spp:5d} spp {threads} thr {row['seconds']:9.4f} s (min"
              f" {row['seconds_min']:8.4f})  RMSE {row['rmse']:.3e}  dE00 {row['mean_de00']:.3f}  (RMSE vs ours-ref"
              f" {row['rmse_vs_ours']:.3e}, vs mean {row['rmse_vs_mean']:.3e})", flush=True)

    print(f"\n{size}x{size}, depth {DEPTH}, median of the clean runs; errors against the {HEADLINE_REFERENCE} "
          "reference:")
    for k, (renderer, variant, sampler, threshold, spp, threads, _) in sorted(
            enumerate(configs), key=lambda kc: (kc[1][0] != "ours", kc[1][5], kc[1][1], kc[1][2], kc[1][4])):
        add(renderer, variant, sampler, threshold, spp, threads, first[k][0], first[k][1], runs[k])
    add("ours", "exhaustive", "stratified", 0.0, OURS_REFERENCE_SPP, max_threads, ref_ours, ref_ours_rays,
        [(ref_ours_seconds, float("nan"))], role="reference")
    add("mitsuba", ref_variant, "stratified", "", ref_mi_spp, max_threads, ref_mi, None,
        [(ref_mi_seconds, float("nan"))], role="reference")

    # 4. time to equal error
    summary = time_to_error_table([r for r in rows if r["role"] == "sweep"])
    print("\ntime to reach the same error (log-log interpolation; n/a: outside a curve's measured range):")
    for metric, label, target, threads, ours_variant, t_ours, variant, sampler, t_mi in summary:
        if not (math.isfinite(t_ours) and math.isfinite(t_mi)):
            continue
        print(f"  {metric:9s} {label:14s} {target:9.4g} {threads} thr: ours {ours_variant:10s} {t_ours:8.4f} s | "
              f"mitsuba {variant:11s} {sampler:11s} {t_mi:8.4f} s | mitsuba / ours {t_mi / t_ours:6.2f}")

    # 5. the CSV
    ref_note = (f"reference for rmse and mean_de00: Mitsuba {ref_variant} {ref_mi_spp} spp (stratified, passes of "
                f"{REFERENCE_PASS_SPP} spp, {ref_mi_seconds:.0f} s; its noise RMSE ~{ref_mi_noise:.2e} from its two "
                f"halves); *_vs_ours: against ours at {OURS_REFERENCE_SPP} spp (exhaustive); *_vs_mean: against the "
                f"mean of the two; between the two references RMSE {floor_rmse:.4e}, mean dE00 {floor_de:.4f}")
    checks = "; ".join(f"{o}/{k} RMSE {v[0]:.3e} dE00 {v[1]:.3f}" for (o, k), v in check.items())
    columns = ["renderer", "variant", "sampler", "threshold", "spp", "threads", "role", "width", "height", "depth", "seconds",
               "seconds_min", "clean_runs", "seconds_runs", "other_cpu_share", "rays", "rmse", "mean_de00"]
    columns += [f"{k}_vs_{n}" for n in references for k in ("rmse", "de00")]
    ttl = "; ".join(f"{m} {lab} {target:.4g} {n} thr: ours {ov} {a:.4g} s, {v} {smp} {b:.4g} s, ratio {b / a:.3g}"
                    for m, lab, target, n, ov, a, v, smp, b in summary if math.isfinite(a) and math.isfinite(b))
    comments = [
        provenance(f"benchmarks/peer_mitsuba.py{' --quick' if quick else ''}", *([note] if note else []),
                   f"mitsuba {mi.__version__}"),
        f"scene: clear glass sphere n = {IOR}, radius 1, at the origin; pinhole camera at (0, 0, 4) "
        f"looking at it, vertical fov {FOV_DEG} deg, {size}x{size}, box filter, depth {DEPTH}; environment "
        f"{image.shape[1]}x{image.shape[0]} procedural (nearest texel in ours, bilinear in Mitsuba); ours: "
        f"Whitted, RGB, threshold 0 (exhaustive) or 1e-3 (pruned); Mitsuba: path, max_depth {DEPTH}, "
        f"rr_depth 1000; seconds: median of the clean runs (compilation excluded; renderers interleaved; "
        f"a run of a configuration shorter than {MIN_WINDOW_SECONDS} s is the median of a batch lasting that "
        f"long); {load_note}",
        ref_note,
        f"orientation check, ours vs Mitsuba (matched; then three wrong orientations): {checks}",
        f"time to equal error (log-log interpolation, Mitsuba / ours): {ttl}",
    ]
    write_csv(out, rows, comments, fieldnames=columns, float_format="{:.6g}", extrasaction="ignore")
    shutil.rmtree(folder, ignore_errors=True)  # the EXR files
    print(f"\nwrote {out}")
    return 0


def time_to_error_table(sweep):
    """Rows (metric, target label, target, threads, ours variant, ours seconds, Mitsuba variant,
    sampler, Mitsuba seconds) for the error ours reaches at 4 spp and at common targets; each
    pair of curves at the same thread count."""
    curves = {}
    for r in sweep:
        curves.setdefault((r["renderer"], r["variant"], r["sampler"], r["threads"]), []).append(r)
    out = []
    for metric, common in (("rmse", (0.003, 0.002, 0.001)), ("mean_de00", (0.1, 0.05))):
        for threads in sorted({key[3] for key in curves}):
            exhaustive = curves[("ours", "exhaustive", "stratified", threads)]
            ours_4 = next(r[metric] for r in exhaustive if r["spp"] == 4)
            for label, target in [("ours 4 spp", ours_4)] + [("common", v) for v in common]:
                for (renderer, ours_variant, _, n), ours_curve in curves.items():
                    if renderer != "ours" or n != threads:
                        continue
                    t_ours = time_at_error([r["seconds"] for r in ours_curve], [r[metric] for r in ours_curve],
                                           target)
                    for (renderer2, variant, sampler, n2), curve in curves.items():
                        if renderer2 == "ours" or n2 != threads:
                            continue
                        t_mi = time_at_error([r["seconds"] for r in curve], [r[metric] for r in curve], target)
                        out.append((metric, label, target, threads, ours_variant, t_ours, variant, sampler, t_mi))
    return out


if __name__ == "__main__":
    sys.exit(main())
