"""The first render after an install (numba's cache empty) and a fresh process with the cache warm.

Run:  python benchmarks/first_render.py [--repeats N] [--quick]
Writes ``data/derived/first_render.csv``.

Every measurement is one child process running the command line a user types,
``python -m tracer image [SCENE] OUT.png --quiet`` (from this checkout: ``PYTHONPATH`` starts with
it), so that this script does not depend on where the tracer's modules live.  The cases:

* ``first_render_builtin``: the built-in scene at 960x960 (the render defaults: depth 10, 1 spp,
  16 bands), numba's cache directory new and empty (``NUMBA_CACHE_DIR``, a new temporary folder
  per run): what a first ``tracer image`` after installing costs, compilation included;
* ``first_render_sphere_only``: the same for a coursework-format scene of Phong spheres only
  (``data/scenes/coursework_two_sphere_three_bubbles.txt``: six clear spheres, one point light,
  black background; RGB transport), its own empty cache;
* ``first_render_builtin_no_helper``, ``first_render_sphere_only_no_helper``: the same two with
  ``TRACER_COMPILE_HELPER=0``, so that the second process that compiles part of a first render
  (:mod:`tracer.rendering.compile_helper`, on in the cases above) is measured against its absence
  in the same repeats;
* ``warm_fresh_process_builtin``: the built-in scene at 960x960 again, in a fresh process whose
  cache is the one the ``first_render_builtin`` run of the same repeat filled: start-up, import,
  loading the kernels from the cache, the render and the PNG;
* ``make_demo_fresh_clone``: ``make demo`` in a fresh ``git clone`` of this checkout's committed
  state, as on a fresh machine: the virtual environment created and the package installed from
  nothing (``PIP_NO_CACHE_DIR=1``; the wheels come from the configured index), the thin-film
  plots, and the first render with numba's cache empty (the clone has none; ``NUMBA_CACHE_DIR``
  is unset).  Not with ``--quick``.

Per run: wall time from starting the child to its exit (:func:`time.perf_counter`), its CPU time
(user + system) and peak resident memory (``ru_maxrss`` of :func:`os.wait4` for that child alone,
not ``RUSAGE_CHILDREN``, which is the maximum over every child so far), and for the first renders
the size of the cache directory afterwards.  The repeats interleave the cases, so that a burst of
other work on the shared machine disturbs one run of each case rather than every run of one.
Reported: median, min and max; the targets (first render of the built-in scene <= 20 s and
<= 600 MB, of a sphere-only scene <= 8 s, a warm fresh process <= 1.5 s, ``make demo`` on a
fresh machine <= 90 s) beside them.  A repeat
of the three cases takes minutes (two of its runs compile the kernels).
"""

import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from study.results import image_benchmark_arguments, provenance, write_csv

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "derived" / "first_render.csv"
SPHERE_SCENE = Path("data") / "scenes" / "coursework_two_sphere_three_bubbles.txt"
#: case -> (scene file relative to the checkout or None for the built-in scene, empty cache?,
#: target seconds, target peak RSS MB or None, the compile helper on?)
CASES = {
    "first_render_builtin": (None, True, 20.0, 600.0, True),
    "first_render_sphere_only": (SPHERE_SCENE, True, 8.0, None, True),
    "first_render_builtin_no_helper": (None, True, 20.0, 600.0, False),
    "first_render_sphere_only_no_helper": (SPHERE_SCENE, True, 8.0, None, False),
    "warm_fresh_process_builtin": (None, False, 1.5, None, True),
}
DEMO_CASE = "make_demo_fresh_clone"
DEMO_TARGET_SECONDS = 90.0


def spread(values):
    return statistics.median(values), min(values), max(values)


def folder_mb(path):
    return sum(f.stat().st_size for f in Path(path).rglob("*") if f.is_file()) / 2**20


def run_child(scene, out_png, size, cache_dir, helper=True):
    """Run ``python -m tracer image`` in a child process with numba's cache in *cache_dir*, with
    or without the compile helper (``TRACER_COMPILE_HELPER``): ``(wall seconds, CPU seconds, peak RSS MB)``."""
    env = dict(os.environ)
    env["NUMBA_CACHE_DIR"] = str(cache_dir)
    env["TRACER_COMPILE_HELPER"] = "1" if helper else "0"
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), *filter(None, [env.get("PYTHONPATH")])])
    cmd = [sys.executable, "-m", "tracer", "image", *([str(scene)] if scene else []), str(out_png), "--quiet",
           "--width", str(size), "--height", str(size)]
    t0 = time.perf_counter()
    child = subprocess.Popen(cmd, cwd=ROOT, env=env)
    _, status, usage = os.wait4(child.pid, 0)
    seconds = time.perf_counter() - t0
    child.returncode = os.waitstatus_to_exitcode(status)
    if child.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} exited with {child.returncode}")
    if not Path(out_png).is_file():
        raise RuntimeError(f"{' '.join(cmd)} wrote no {out_png}")
    # ru_maxrss is in KiB on Linux (bytes on macOS)
    rss_mb = usage.ru_maxrss / (2**20 if sys.platform == "darwin" else 2**10)
    return seconds, usage.ru_utime + usage.ru_stime, rss_mb


def run_make_demo(work):
    """``make demo`` in a fresh clone of this checkout (HEAD) under *work*:
    ``(wall seconds, CPU seconds, peak RSS MB)``; the clone's time is not counted."""
    clone = work / "clone"
    shutil.rmtree(clone, ignore_errors=True)
    subprocess.run(["git", "clone", "--quiet", "--no-hardlinks", str(ROOT), str(clone)], check=True)
    env = {k: v for k, v in os.environ.items()
           if k not in ("NUMBA_CACHE_DIR", "PYTHONPATH", "VIRTUAL_ENV", "MAKEFLAGS", "MFLAGS")}
    env["PIP_NO_CACHE_DIR"] = "1"
    t0 = time.perf_counter()
    child = subprocess.Popen(["make", "demo"], cwd=clone, env=env, stdout=subprocess.DEVNULL)
    _, status, usage = os.wait4(child.pid, 0)
    seconds = time.perf_counter() - t0
    if os.waitstatus_to_exitcode(status) != 0:
        raise RuntimeError(f"make demo in {clone} exited with {os.waitstatus_to_exitcode(status)}")
    if not (clone / "demo-output" / "bubbles.png").is_file():
        raise RuntimeError(f"make demo in {clone} wrote no demo-output/bubbles.png")
    shutil.rmtree(clone, ignore_errors=True)
    # ru_maxrss of a reaped child covers the descendants it waited for: the largest process
    return seconds, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 2**10


def main(argv=None):
    args, size, repeats = image_benchmark_arguments(__doc__.splitlines()[0], OUT, 3, 1, argv)
    import numba

    load_before = os.getloadavg()[0]
    cases = dict(CASES)
    if not args.quick:
        cases[DEMO_CASE] = (None, True, DEMO_TARGET_SECONDS, None, True)
    runs = {case: [] for case in cases}
    work = Path(tempfile.mkdtemp(prefix="first_render_"))
    try:
        for rep in range(repeats):
            caches = {}
            for case, (scene, empty, _, _, helper) in CASES.items():
                if case == DEMO_CASE:
                    continue
                key = scene or "builtin"
                if empty:
                    cache = work / f"cache_{rep}_{case}"
                    cache.mkdir()
                    caches.setdefault(key, cache)
                else:
                    cache = caches[key]  # filled by this repeat's first render of the same scene
                out_png = work / f"{case}.png"
                out_png.unlink(missing_ok=True)
                seconds, cpu, rss = run_child(ROOT / scene if scene else None, out_png, size, cache, helper)
                run = dict(seconds=seconds, cpu=cpu, rss=rss, cache_mb=folder_mb(cache) if empty else None)
                runs[case].append(run)
                print(f"repeat {rep}: {case}: {seconds:.2f} s (CPU {cpu:.1f} s), peak RSS {rss:.0f} MB"
                      + (f", cache {run['cache_mb']:.1f} MB" if empty else ""), file=sys.stderr)
            if DEMO_CASE in cases:
                seconds, cpu, rss = run_make_demo(work)
                runs[DEMO_CASE].append(dict(seconds=seconds, cpu=cpu, rss=rss, cache_mb=None))
                print(f"repeat {rep}: {DEMO_CASE}: {seconds:.2f} s (CPU {cpu:.1f} s), peak RSS {rss:.0f} MB",
                      file=sys.stderr)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    load_after = os.getloadavg()[0]

    rows = []
    for case, (scene, empty, target_s, target_mb, helper) in cases.items():
        r = runs[case]
        med, lo, hi = spread([x["seconds"] for x in r])
        rss_med, rss_lo, rss_hi = spread([x["rss"] for x in r])
        meets = med <= target_s and (target_mb is None or rss_med <= target_mb)
        rows.append(dict(case=case, scene=str(scene) if scene else "built-in", cache="empty" if empty else "warm",
                         compile_helper=helper,
                         width=size, height=size, repeats=len(r), seconds_median=med, seconds_min=lo,
                         seconds_max=hi, cpu_seconds_median=statistics.median(x["cpu"] for x in r),
                         peak_rss_mb_median=rss_med, peak_rss_mb_min=rss_lo, peak_rss_mb_max=rss_hi,
                         cache_mb_median=(statistics.median(x["cache_mb"] for x in r)
                                          if empty and case != DEMO_CASE else None),
                         target_seconds=target_s, target_rss_mb=target_mb, meets_target=meets,
                         seconds_runs=" ".join(f"{x['seconds']:.2f}" for x in r)))
        print(f"{case}: median {med:.2f} s [{lo:.2f}, {hi:.2f}], peak RSS {rss_med:.0f} MB "
              f"[{rss_lo:.0f}, {rss_hi:.0f}] (target {target_s:g} s"
              + (f", {target_mb:g} MB" if target_mb else "") + f"): {'met' if meets else 'not met'}", file=sys.stderr)
    comment = provenance(
        "benchmarks/first_render.py",
        f"machine load average {load_before:.1f} before, {load_after:.1f} after (shared machine)",
        f"numba {numba.__version__}, {os.cpu_count()} cores visible",
        f"{repeats} repeat(s), cases interleaved, median (min-max); each run a fresh `python -m tracer image` "
        f"process at {size}x{size} (render defaults otherwise); first_render_*: a new empty NUMBA_CACHE_DIR per run; "
        f"warm_fresh_process_builtin: the cache that repeat's first_render_builtin filled; peak RSS: the child's "
        f"ru_maxrss (os.wait4: the larger of it and the compile helper it waits for); *_no_helper: "
        f"TRACER_COMPILE_HELPER=0 (the others 1: tracer.rendering.compile_helper where 2 CPUs are usable)"
        + (f"; {DEMO_CASE}: `make demo` in a fresh git clone of HEAD (venv and install from nothing, "
           f"PIP_NO_CACHE_DIR=1, numba's cache empty), the clone itself not timed" if DEMO_CASE in cases else ""),
        "regenerate with: python benchmarks/first_render.py")
    fields = ["case", "scene", "cache", "compile_helper", "width", "height", "repeats", "seconds_median", "seconds_min", "seconds_max",
              "cpu_seconds_median", "peak_rss_mb_median", "peak_rss_mb_min", "peak_rss_mb_max", "cache_mb_median",
              "target_seconds", "target_rss_mb", "meets_target", "seconds_runs"]
    write_csv(args.out, rows, comment, fieldnames=fields, float_format="{:.4g}")
    print(f"wrote {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
