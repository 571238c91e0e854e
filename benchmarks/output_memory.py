"""Peak memory of saving (and rendering) a large image, each case in a fresh child process.

Run:  python benchmarks/output_memory.py [--size N] [--render] [--out PATH] [--cases a,b,...]
Writes ``data/derived/output_memory.csv`` (default size 4000: a 4000x4000 image).

Each child makes a float64 linear-RGB image of the size asked (uniform random values in
[-0.1, 1.4], so that clipping, negatives and the encoding's every branch are exercised;
filled in place, no temporary copy), saves a 2x2 image of the same kind first (so that every
module and numba kernel the save needs is loaded), reads its peak resident set size
(``resource.getrusage(RUSAGE_SELF).ru_maxrss``), saves the large image with
``tracer.save_image`` into a temporary folder and reads the peak again.  The difference is
what the save costs above the process and the image it already holds; it is reported beside
the image's own size (H x W x 3 float64).  With ``--render`` the built-in scene is also
rendered at that size (``tracer.render``, then the save to PNG), and the peak of the whole
child is reported beside the peak before the render.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "derived" / "output_memory.csv"

#: case name -> (file name, save_image keyword arguments)
CASES = {
    "png8": ("img.png", {}),
    "png16": ("img.png", {"bits": 16}),
    "png8_aces": ("img.png", {"view": "aces", "exposure": 1.0}),
    "npy": ("img.npy", {}),
    "exr_half": ("img.exr", {"bits": 16}),
    "exr_float": ("img.exr", {"bits": 32}),
    "hdr": ("img.hdr", {}),
}

_CHILD = r"""
import json, resource, sys, tempfile, time
from pathlib import Path
import numpy as np
import tracer

size, name, kwargs, render = int(sys.argv[1]), sys.argv[2], json.loads(sys.argv[3]), sys.argv[4] == "1"
peak = lambda: resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024  # KiB on Linux
folder = Path(tempfile.mkdtemp())
tracer.save_image(np.full((2, 2, 3), 0.5), folder / ("small_" + name), **kwargs)
if render:
    scene = tracer.default_scene()
    tracer.render(scene, width=8, height=8, progress=False)  # numba's kernels loaded
    before_render = peak()
    t = time.perf_counter()
    image = tracer.render(scene, width=size, height=size, progress=False)
    render_seconds = time.perf_counter() - t
else:
    before_render = None
    render_seconds = None
    image = np.random.default_rng(0).random((size, size, 3))
    image *= 1.5
    image -= 0.1
before = peak()
t = time.perf_counter()
tracer.save_image(image, folder / name, **kwargs)
seconds = time.perf_counter() - t
after = peak()
print(json.dumps(dict(before_render=before_render, before=before, after=after, seconds=seconds,
                      render_seconds=render_seconds, file_bytes=(folder / name).stat().st_size,
                      image_bytes=image.nbytes)))
"""


def run_case(size, case, render=False):
    name, kwargs = CASES[case]
    done = subprocess.run([sys.executable, "-c", _CHILD, str(size), name, json.dumps(kwargs), "1" if render else "0"],
                          capture_output=True, text=True, cwd=tempfile.gettempdir())
    if done.returncode != 0:
        return dict(case=case, error=done.stderr.strip().splitlines()[-1] if done.stderr.strip() else "failed")
    r = json.loads(done.stdout.strip().splitlines()[-1])
    mb = 1e6
    row = dict(case=case + ("_render" if render else ""), size=size, image_MB=r["image_bytes"] / mb,
               save_extra_MB=(r["after"] - r["before"]) / mb, peak_MB=r["after"] / mb,
               save_seconds=r["seconds"], file_MB=r["file_bytes"] / mb)
    row["save_extra_per_image"] = row["save_extra_MB"] / row["image_MB"]
    if render:
        row["render_extra_MB"] = (r["before"] - r["before_render"]) / mb
        row["render_seconds"] = r["render_seconds"]
    return row


def main(argv=None):
    from study.results import provenance, write_csv

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--size", type=int, default=4000)
    p.add_argument("--render", action="store_true", help="also render the built-in scene at SIZE and save a PNG")
    p.add_argument("--cases", default=",".join(CASES), help="comma-separated cases: " + ", ".join(CASES))
    p.add_argument("--out", type=Path, default=OUT)
    args = p.parse_args(argv)
    rows = []
    for case in args.cases.split(","):
        row = run_case(args.size, case)
        print(json.dumps(row), flush=True)
        if "error" not in row:
            rows.append(row)
    if args.render:
        row = run_case(args.size, "png8", render=True)
        print(json.dumps(row), flush=True)
        if "error" not in row:
            rows.append(row)
    fields = ["case", "size", "image_MB", "save_extra_MB", "save_extra_per_image", "peak_MB", "save_seconds",
              "file_MB", "render_extra_MB", "render_seconds"]
    write_csv(args.out, rows, provenance("benchmarks/output_memory.py",
                                         f"regenerate with: python benchmarks/output_memory.py --size {args.size}"
                                         + (" --render" if args.render else "")),
              fieldnames=fields)
    return 0


if __name__ == "__main__":
    sys.exit(main())
