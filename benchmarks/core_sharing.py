"""How much two cores slow each other down: one single-threaded process alone, then two at once.

Run:  python benchmarks/core_sharing.py [--repeats N] [--quick]
Writes ``data/derived/core_sharing.csv``.

Why: the tracer speeds up by less from one thread to two than a minimal kernel does
(``benchmarks/throughput.py``).  If two *independent* single-threaded processes slow each other
down by as much, the limit is the machine (what its two cores share), not the tracer's
threading.  Each workload runs in a child process with ``numba.set_num_threads(1)``: first
alone, then two copies started together (each waits until both are ready), ``--repeats`` timed
runs each, after one untimed run (compilation from the cache, page faults).  Workloads: the
floor kernel of ``throughput.py`` (scalar), its vector-arithmetic probe, and the tracer on the
coursework's three-bubble scene and on the built-in scene, 960x960, defaults.
"""

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from bubbleoptics.study.results import image_benchmark_arguments, provenance, write_csv

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "derived" / "core_sharing.csv"

_CHILD = r'''
import json, os, sys, time
import numba
numba.set_num_threads(1)
import numpy as np
name, size, repeats, gate = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
sys.path.insert(0, os.path.join(os.environ["BUBBLEOPTICS_ROOT"], "benchmarks"))
if name in ("floor", "probe"):
    from throughput import floor_kernel, simd_probe_kernel
    centers = np.array([[0.0, 0.0, -5.0], [1.5, 0.0, -6.0], [-1.5, 0.0, -6.0]])
    radii = np.array([1.0, 0.7, 0.7])
    out = np.zeros((size, size))
    probe_out = np.zeros(64)
    run = ((lambda: floor_kernel(size, size, centers, radii, 0.5, out)) if name == "floor"
           else (lambda: simd_probe_kernel(100000, probe_out)))
else:
    import tracer
    scene = (tracer.default_scene() if name == "builtin" else
             tracer.load_scene(os.path.join(os.environ["BUBBLEOPTICS_ROOT"], "data", "scenes",
                                            "coursework_three_bubbles.txt")))
    run = lambda: tracer.render(scene, width=size, height=size, progress=False)
run()
open(gate + "." + str(os.getpid()), "w").close()
while len([f for f in os.listdir(os.path.dirname(gate)) if f.startswith(os.path.basename(gate))]) < int(sys.argv[5]):
    time.sleep(0.01)
times = []
for _ in range(repeats):
    t0 = time.perf_counter()
    run()
    times.append(time.perf_counter() - t0)
print(json.dumps(times))
'''


def run_together(name, size, repeats, copies):
    """Seconds of each timed run of *copies* child processes started together (a list per copy)."""
    folder = tempfile.mkdtemp()
    gate = os.path.join(folder, "ready")
    env = dict(os.environ, BUBBLEOPTICS_ROOT=str(ROOT))
    procs = [subprocess.Popen([sys.executable, "-c", _CHILD, name, str(size), str(repeats), gate, str(copies)],
                              stdout=subprocess.PIPE, text=True, env=env) for _ in range(copies)]
    return [json.loads(p.communicate()[0]) for p in procs]


def main(argv=None):
    args, size, repeats = image_benchmark_arguments(__doc__.splitlines()[0], OUT, 7, 2, argv)
    rows = []
    for name in ("floor", "probe", "coursework_3_bubbles", "builtin"):
        alone = np.array(run_together(name, size, repeats, 1)[0])
        pair = np.array(run_together(name, size, repeats, 2)).ravel()
        rows.append(dict(workload=name, width=size, height=size, repeats=repeats,
                         alone_seconds_median=float(np.median(alone)), alone_seconds_min=float(alone.min()),
                         alone_seconds_max=float(alone.max()),
                         together_seconds_median=float(np.median(pair)), together_seconds_min=float(pair.min()),
                         together_seconds_max=float(pair.max()),
                         slowdown_median=float(np.median(pair) / np.median(alone)),
                         two_core_speedup_bound=float(2.0 * np.median(alone) / np.median(pair))))
        r = rows[-1]
        print(f"{name:22s} alone {r['alone_seconds_median'] * 1e3:7.1f} ms [{r['alone_seconds_min'] * 1e3:.1f}, "
              f"{r['alone_seconds_max'] * 1e3:.1f}]  two at once {r['together_seconds_median'] * 1e3:7.1f} ms "
              f"[{r['together_seconds_min'] * 1e3:.1f}, {r['together_seconds_max'] * 1e3:.1f}]  "
              f"slowdown {r['slowdown_median']:.2f}x: two cores give at most {r['two_core_speedup_bound']:.2f}x")
    write_csv(args.out, rows, provenance("benchmarks/core_sharing.py",
                                         "regenerate with: python benchmarks/core_sharing.py"),
              float_format="{:.6g}")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    started = time.perf_counter()
    status = main()
    print(f"total {time.perf_counter() - started:.0f} s")
    sys.exit(status)
