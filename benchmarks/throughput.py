"""Tracer throughput against a minimal kernel of its own, in one process, interleaved.

Run:  python benchmarks/throughput.py [--repeats N] [--quick]
Writes ``data/derived/throughput.csv``.

The floor (:func:`study.floor.floor_kernel`) is the least a ray tracer can do per pixel: one camera ray
against three spheres (textbook quadratic), the nearest hit, one mirror bounce against the
same spheres, a constant environment; parallel over rows like the tracer.  Each case is a
full ``tracer.render_with_stats`` call (packing the scene, the first call's measurement,
everything a user waits for; compilation excluded, the kernels come from numba's cache),
timed right after a floor run with the same thread count, so that both see the same load on
this shared machine; the ratio of each pair is what is reported (median and range over the
repeats), beside the seconds and rays per second.  Cases, all 960x960 at one sample per pixel:

* ``empty``: no objects, a constant environment (RGB transport);
* ``coursework_{1,2,3}_bubbles`` at depth 1 and 10: the scenes of the coursework's table 4.1
  (``data/scenes/coursework_{one,two,three}_bubble*.txt``), defaults otherwise;
* ``coursework_two_sphere_3_bubbles`` at depth 1 and 10: the three bubbles modelled literally,
  each two concentric clear spheres (``data/scenes/coursework_two_sphere_three_bubbles.txt``);
* ``builtin``: ``tracer.default_scene()`` at the defaults (what ``make demo`` renders).

Every case runs with 1 and with 2 threads (``numba.set_num_threads``), and so do the floor
and a probe of the machine (:func:`simd_probe_kernel`: vectorized arithmetic only), whose
speed-ups from 1 to 2 threads say what this machine allows; and a check of the machine's cores:
each of the floor, the probe, the three-bubble and the built-in scene in one single-threaded
process alone, then in two such processes at once (``--child`` runs one of them).  Finally
fresh processes are
timed: ``import numba``, numba with one kernel loaded from its cache (numba's own start-up:
its first call initialises its CPU target), ``import tracer``,
and ``python -m tracer image OUT.png`` of the built-in scene at 960x960 (start to saved file).
"""

import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numba
import numpy as np
from numba import njit, prange

from study.floor import paired_render, run_floor
from study.results import image_benchmark_arguments, provenance, write_csv

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "derived" / "throughput.csv"
COURSEWORK_SCENES = {1: "coursework_one_bubble.txt", 2: "coursework_two_bubbles.txt", 3: "coursework_three_bubbles.txt"}
#: the coursework's bubbles modelled literally, each two concentric clear spheres (every hit a
#: Fresnel-reflected and a refracted ray): the scene the issue's three-bubble targets name
TWO_SPHERE_SCENE = "coursework_two_sphere_three_bubbles.txt"


@njit(parallel=True, cache=True)
def simd_probe_kernel(n, out):
    """A machine probe: 32 independent multiply-add chains per task (vectorized arithmetic, no
    memory traffic), to show how this machine's two cores share vector throughput."""
    for i in prange(out.shape[0]):
        acc = np.zeros(32)
        for _ in range(n):
            for j in range(32):
                acc[j] = acc[j] * 0.999999 + 1.0
        out[i] = acc.sum()


def cases(tracer):
    from tracer.scene import Environment, Scene

    empty = Scene(environment=Environment(kind="constant", color=(0.5, 0.5, 0.5)))
    out = [("empty", empty, tracer.DEFAULTS["depth"])]
    for nb, name in COURSEWORK_SCENES.items():
        scene = tracer.load_scene(ROOT / "data" / "scenes" / name)
        for depth in (1, 10):
            out.append((f"coursework_{nb}_bubble{'s' if nb > 1 else ''}", scene, depth))
    two_sphere = tracer.load_scene(ROOT / "data" / "scenes" / TWO_SPHERE_SCENE)
    for depth in (1, 10):
        out.append(("coursework_two_sphere_3_bubbles", two_sphere, depth))
    out.append(("builtin", tracer.default_scene(), tracer.DEFAULTS["depth"]))
    return out


def child(name, size, repeats, gate, copies):
    """``--child``: one single-threaded process of the core-sharing check (:func:`core_sharing`):
    run *name* once, wait until *copies* processes are ready, then print the seconds of
    *repeats* runs as JSON."""
    numba.set_num_threads(1)
    if name == "floor":
        out = np.zeros((size, size))

        def run():
            run_floor(size, out)
    elif name == "probe":
        out = np.zeros(64)

        def run():
            simd_probe_kernel(100000, out)
    else:
        import tracer

        scene = {case: sc for case, sc, _ in cases(tracer)}[name]

        def run():
            tracer.render(scene, width=size, height=size, progress=False)
    run()
    Path(f"{gate}.{os.getpid()}").touch()
    while len(list(Path(gate).parent.glob(Path(gate).name + ".*"))) < copies:
        time.sleep(0.01)
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        run()
        times.append(time.perf_counter() - t0)
    print(json.dumps(times))


def core_sharing(size, repeats):
    """Rows: each workload in one single-threaded process alone, then in two at once.

    If two *independent* processes slow each other down, the limit to what two threads can
    gain is the machine (what its cores share), not the tracer's threading."""
    rows = []
    for name in ("floor", "probe", "coursework_3_bubbles", "builtin"):
        runs = {}
        for copies in (1, 2):
            gate = Path(tempfile.mkdtemp()) / "ready"
            procs = [subprocess.Popen([sys.executable, __file__, "--child", name, str(size), str(repeats), str(gate),
                                       str(copies)], stdout=subprocess.PIPE, text=True) for _ in range(copies)]
            runs[copies] = np.array([json.loads(p.communicate()[0]) for p in procs]).ravel()
        alone, together = runs[1], runs[2]
        rows.append(dict(case=f"two processes at once: {name}", depth="", threads=1, width=size, height=size,
                         repeats=repeats, seconds_median=float(np.median(together)),
                         seconds_min=float(together.min()), seconds_max=float(together.max()),
                         alone_seconds_median=float(np.median(alone)),
                         slowdown_together=float(np.median(together) / np.median(alone))))
    return rows


def fresh_process_seconds(args_list, repeats):
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        subprocess.run([sys.executable, *args_list], check=True, stdout=subprocess.DEVNULL)
        times.append(time.perf_counter() - t0)
    return times


def main(argv=None):
    if argv is None and len(sys.argv) > 1 and sys.argv[1] == "--child":
        name, size, repeats, gate, copies = sys.argv[2:7]
        child(name, int(size), int(repeats), gate, int(copies))
        return 0
    args, size, repeats = image_benchmark_arguments(__doc__.splitlines()[0], OUT, 7, 2, argv)

    import tracer

    floor_out = np.zeros((size, size))
    run_floor(size, floor_out)
    todo = cases(tracer)
    for _, scene, depth in todo:  # compile or load every kernel before timing
        tracer.render(scene, width=8, height=8, depth=depth, progress=False)
    max_threads = numba.config.NUMBA_NUM_THREADS
    thread_counts = [t for t in (1, 2) if t <= max_threads]
    samples = {}  # (case, depth, threads) -> list of (seconds, floor seconds, rays)
    for rep in range(repeats):
        for threads in thread_counts:
            numba.set_num_threads(threads)
            for name, scene, depth in todo:
                samples.setdefault((name, depth, threads), []).append(
                    paired_render(tracer, scene, size, depth, floor_out))
        print(f"repeat {rep + 1}/{repeats} done", file=sys.stderr)
    numba.set_num_threads(max_threads)

    rows = []
    for (name, depth, threads), runs in samples.items():
        sec = np.array([r[0] for r in runs])
        flo = np.array([r[1] for r in runs])
        ratio = sec / flo
        rays = runs[0][2]
        rows.append(dict(
            case=name, depth=depth, threads=threads, width=size, height=size, repeats=len(runs),
            seconds_median=float(np.median(sec)), seconds_min=float(sec.min()), seconds_max=float(sec.max()),
            floor_seconds_median=float(np.median(flo)), ratio_to_floor_median=float(np.median(ratio)),
            ratio_to_floor_min=float(ratio.min()), ratio_to_floor_max=float(ratio.max()),
            rays_total=rays, rays_per_second=float(rays / np.median(sec)),
        ))

    def get(name, depth, threads):
        return next(r for r in rows if (r["case"], r["depth"], r["threads"]) == (name, depth, threads))

    # speed-up from 1 to 2 threads per case (medians)
    if len(thread_counts) == 2:
        for r in rows:
            r["speedup_1_to_2_threads"] = (get(r["case"], r["depth"], 1)["seconds_median"]
                                           / get(r["case"], r["depth"], 2)["seconds_median"])

    # the floor and a vector-arithmetic probe on their own, 1 and 2 threads
    probe_out = np.zeros(64)
    simd_probe_kernel(10, probe_out)
    probes = {"floor kernel": lambda: run_floor(size, floor_out),
              "probe: vector arithmetic": lambda: simd_probe_kernel(20000 if args.quick else 200000, probe_out)}
    probe_times = {}
    for rep in range(repeats):
        for threads in thread_counts:
            numba.set_num_threads(threads)
            for name, run in probes.items():
                t0 = time.perf_counter()
                run()
                probe_times.setdefault((name, threads), []).append(time.perf_counter() - t0)
    numba.set_num_threads(max_threads)
    for (name, threads), times in probe_times.items():
        times = np.array(times)
        row = dict(case=name, depth="", threads=threads, width=size, height=size, repeats=len(times),
                   seconds_median=float(np.median(times)), seconds_min=float(times.min()),
                   seconds_max=float(times.max()))
        if len(thread_counts) == 2:
            row["speedup_1_to_2_threads"] = (float(np.median(probe_times[(name, 1)]))
                                             / float(np.median(probe_times[(name, 2)])))
        rows.append(row)

    rows += core_sharing(size, repeats)

    # fresh processes
    png = Path(tempfile.mkdtemp()) / "builtin.png"
    fresh = {
        "fresh process: import numba": ["-c", "import numba"],
        "fresh process: numba and one cached kernel": ["-c", "from bubbleoptics.kernels import srgb_decode_nb; "
                                                               "srgb_decode_nb(0.5)"],
        "fresh process: import tracer": ["-c", "import tracer"],
        "fresh process: built-in scene to PNG": ["-m", "tracer", "image", str(png), "--quiet", "--width",
                                                 str(size), "--height", str(size)],
    }
    for name, cmd in fresh.items():
        times = np.array(fresh_process_seconds(cmd, repeats))
        rows.append(dict(case=name, depth=tracer.DEFAULTS["depth"], threads=max_threads, width=size, height=size,
                         repeats=repeats, seconds_median=float(np.median(times)), seconds_min=float(times.min()),
                         seconds_max=float(times.max())))

    print(f"\n{size}x{size}, 1 spp; seconds median [min, max] over {repeats}; ratio to the floor kernel "
          "(median [min, max] of the interleaved pairs)")
    for r in rows:
        line = f"{r['case']:44s} depth {r['depth']!s:>2s} threads {r['threads']}: {r['seconds_median']:.4f} s " \
               f"[{r['seconds_min']:.4f}, {r['seconds_max']:.4f}]"
        if "ratio_to_floor_median" in r:
            line += (f"  x floor {r['ratio_to_floor_median']:6.1f} [{r['ratio_to_floor_min']:.1f}, "
                     f"{r['ratio_to_floor_max']:.1f}]  {r['rays_per_second'] / 1e6:7.2f} Mrays/s")
        if "speedup_1_to_2_threads" in r:
            line += f"  1->2 threads {r['speedup_1_to_2_threads']:.2f}x"
        if "slowdown_together" in r:
            line += f"  alone {r['alone_seconds_median']:.4f} s: slowed {r['slowdown_together']:.2f}x by the other"
        print(line)
    if len(thread_counts) == 2:
        for label, case in (("three bubbles", "coursework_3_bubbles"),
                            ("three two-sphere bubbles", "coursework_two_sphere_3_bubbles")):
            depth_ratio = get(case, 10, 2)["seconds_median"] / get(case, 1, 2)["seconds_median"]
            print(f"{label}, 2 threads: depth 10 / depth 1 = {depth_ratio:.2f}")

    fields = ["case", "depth", "threads", "width", "height", "repeats", "seconds_median", "seconds_min",
              "seconds_max", "floor_seconds_median", "ratio_to_floor_median", "ratio_to_floor_min",
              "ratio_to_floor_max", "rays_total", "rays_per_second", "speedup_1_to_2_threads",
              "alone_seconds_median", "slowdown_together"]
    write_csv(args.out, rows, provenance("benchmarks/throughput.py",
                                         f"{os.cpu_count()} cores visible, numba threads {max_threads}; "
                                         "regenerate with: python benchmarks/throughput.py"),
              fieldnames=fields, float_format="{:.6g}")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
