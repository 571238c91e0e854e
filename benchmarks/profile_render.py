"""Where a warm render's time goes, per compiled kernel: ``perf`` samples with numba's symbols.

numba's JIT code has no symbols that ``perf`` can see, and llvmlite's JIT-event hook supports
only Intel's and OProfile's listeners (and turns on debug information, which changes the
code).  So this script writes perf's JIT map itself (``/tmp/perf-PID.map``: start, size and name
of each function): each compiled library gives its object code
(``library.serialize_using_object_code()``, which works only for code compiled in this process,
hence a fresh ``NUMBA_CACHE_DIR``), ``nm -S`` of it gives every function's offset and size, and
the address numba reports for one of them places the rest.  Weak (``W``) symbols are left to the
library that defines them as its own.  No library does this; it is a few lines.

The child process compiles and renders once, writes the map, then asks ``perf`` (started with
its events disabled, ``--control`` fifo) to sample only the ``--renders`` warm renders that
follow.  The parent aggregates the samples by function (numba's mangled names shortened to
their dotted path) and writes ``data/derived/profile_render.csv``: samples and share of all
samples, and share of the samples in compiled code and libm (the render's own work).

Needs Linux ``perf`` (Debian: ``linux-perf``) and ``binutils``; the events are ``cpu-clock``,
which virtual machines without hardware counters also have.  Example::

    python benchmarks/profile_render.py --renders 15            # the built-in scene, 960², 1 thread
    python benchmarks/profile_render.py --scene data/scenes/coursework_three_bubbles.txt

``--callgrind`` instead counts the instructions (deterministic, unlike times on a shared machine)
of one warm render under ``valgrind --tool=callgrind``, the instrumentation switched on only
around it, and prints the total: how two worktrees are compared to a fraction of a per cent
(docs/performance.md).  It uses numba's usual cache (run a render first: compiling under
valgrind takes many minutes) and is about fifty times slower than a render, so give it a small
image::

    python benchmarks/profile_render.py --callgrind --width 256
"""
from __future__ import annotations

import argparse
import collections
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from study.results import provenance, write_csv

ROOT = Path(__file__).resolve().parent.parent

OUT = ROOT / "data" / "derived" / "profile_render.csv"
_MANGLED = re.compile(r"_ZN((?:\d+[A-Za-z_][A-Za-z0-9_]*)+)")


def short_name(symbol: str) -> str:
    """``_ZN6tracer7kernels9thickness14film_thicknessB3v48...`` -> ``tracer.kernels.thickness.film_thickness``."""
    m = _MANGLED.match(symbol)
    if not m:
        return symbol
    parts, s = [], m.group(1)
    while s and s[0].isdigit():
        n = re.match(r"\d+", s).group(0)
        parts.append(s[len(n): len(n) + int(n)])
        s = s[len(n) + int(n):]
    return ".".join(parts)


def write_perf_map() -> int:
    """Write /tmp/perf-<pid>.map for every numba function compiled in this process; return its line count."""
    import gc

    import numba

    lines, seen = [], set()
    with tempfile.TemporaryDirectory() as tmp:
        for obj in gc.get_objects():
            if not isinstance(obj, numba.core.dispatcher.Dispatcher):
                continue
            for cres in list(obj.overloads.values()):
                lib = cres.library
                if id(lib) in seen:
                    continue
                seen.add(id(lib))
                try:
                    _, _, data = lib.serialize_using_object_code()
                except Exception:  # loaded from a cache: no object code to read
                    continue
                path = os.path.join(tmp, f"{len(seen)}.o")
                with open(path, "wb") as f:
                    f.write(data[0])
                out = subprocess.run(["nm", "-S", "--defined-only", path], capture_output=True, text=True, check=True).stdout
                syms = [(int(p[0], 16), int(p[1], 16), p[3]) for p in (l.split() for l in out.splitlines())
                        if len(p) == 4 and p[2] in "tT"]
                base = None
                for off, _, name in syms:
                    try:
                        addr = lib.get_pointer_to_function(name)
                    except Exception:
                        addr = 0
                    if addr:
                        base = addr - off
                        break
                if base is not None:
                    lines += [f"{base + off:x} {size:x} {name}" for off, size, name in syms]
    with open(f"/tmp/perf-{os.getpid()}.map", "w") as f:
        f.write("\n".join(lines) + "\n")
    return len(lines)


def _scene(name):
    import tracer

    return tracer.default_scene() if name == "built-in" else tracer.load_scene(name)


def _prepare(args):
    import numba

    import tracer
    from bubbleoptics.resources import prefer_workqueue_threads

    prefer_workqueue_threads()
    numba.set_num_threads(args.threads)
    scene = _scene(args.scene)
    tracer.render_with_stats(scene, width=args.width, height=args.width, depth=args.depth, progress=False)
    return tracer, scene


def child(args) -> None:
    tracer, scene = _prepare(args)
    write_perf_map()
    with open(args.ctl, "w") as ctl, open(args.ack) as ack:
        ctl.write("enable\n")
        ctl.flush()
        ack.readline()
        for _ in range(args.renders):
            tracer.render_with_stats(scene, width=args.width, height=args.width, depth=args.depth, progress=False)
        ctl.write("disable\n")
        ctl.flush()
        ack.readline()


def callgrind_child(args) -> None:
    tracer, scene = _prepare(args)
    pid = str(os.getpid())
    subprocess.run(["callgrind_control", "-i", "on", pid], check=True, capture_output=True)
    tracer.render_with_stats(scene, width=args.width, height=args.width, depth=args.depth, progress=False)
    subprocess.run(["callgrind_control", "-i", "off", pid], check=True, capture_output=True)


def _need(tool: str, package: str) -> None:
    if shutil.which(tool) is None:
        sys.exit(f"profile_render.py: `{tool}` not found; install Debian's {package}")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", default="built-in", help="a scene file, or built-in (default)")
    ap.add_argument("--width", type=int, default=960, help="image width and height (default 960)")
    ap.add_argument("--depth", type=int, default=None, help="trace depth (default: the scene's)")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--renders", type=int, default=15, help="warm renders sampled (default 15)")
    ap.add_argument("--callgrind", action="store_true", help="count the instructions of one render instead")
    ap.add_argument("--out", default=str(OUT))
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--ctl", help=argparse.SUPPRESS)
    ap.add_argument("--ack", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    for name, value, low in (("--width", args.width, 8), ("--renders", args.renders, 1), ("--threads", args.threads, 1)):
        if value < low:
            ap.error(f"{name} must be at least {low} (got {value})")
    if args.scene != "built-in" and not Path(args.scene).is_file():
        ap.error(f"--scene: no such scene file {args.scene!r} (a path, or built-in)")
    if args.child:
        return callgrind_child(args) if args.callgrind else child(args)
    common = [sys.executable, __file__, "--child", "--scene", args.scene, "--width", str(args.width),
              "--threads", str(args.threads), "--renders", str(args.renders)]
    if args.depth is not None:
        common += ["--depth", str(args.depth)]
    with tempfile.TemporaryDirectory() as tmp:
        if args.callgrind:  # numba's own cache: compiling under valgrind would take many minutes
            env = dict(os.environ, TRACER_COMPILE_HELPER="0")
            _need("valgrind", "valgrind")
            out = os.path.join(tmp, "callgrind.out")
            subprocess.run(["valgrind", "--tool=callgrind", "--instr-atstart=no", f"--callgrind-out-file={out}",
                            *common, "--callgrind"], env=env, check=True, capture_output=True)
            total = 0
            for line in open(out):
                if line.startswith("totals:") or line.startswith("summary:"):
                    total = int(line.split()[1])
            print(f"{args.scene} at {args.width}²: {total:,} instructions in one warm render")
            return
        env = dict(os.environ, NUMBA_CACHE_DIR=os.path.join(tmp, "cache"), TRACER_COMPILE_HELPER="0")
        _need("perf", "linux-perf")
        _need("nm", "binutils")
        ctl, ack, data = (os.path.join(tmp, n) for n in ("ctl", "ack", "perf.data"))
        os.mkfifo(ctl)
        os.mkfifo(ack)
        subprocess.run(["perf", "record", "-q", "-e", "cpu-clock", "-F", "2000", "-D", "-1",
                        "--control", f"fifo:{ctl},{ack}", "-o", data, "--", *common, "--ctl", ctl, "--ack", ack],
                       env=env, check=True)
        script = subprocess.run(["perf", "script", "-i", data, "-F", "ip,sym,dso"], capture_output=True, text=True,
                                check=True).stdout
    counts = collections.Counter()
    for line in script.splitlines():
        line = line.strip()
        if not line:
            continue
        sym, _, dso = line.partition(" ")[2].rpartition(" (")  # "IP SYMBOL (DSO)"
        dso = dso.rstrip(")")
        if "libpython" in dso:
            key = "Python interpreter"
        elif "kernel" in dso:
            key = "operating system"
        else:
            key = short_name(sym.strip()) or f"[{os.path.basename(dso)}]"
            if "libm" in dso:
                key = f"libm {key}"
        counts[key] += 1
    total = sum(counts.values())
    work = sum(n for k, n in counts.items() if k.startswith(("tracer.", "bubbleoptics.", "libm ")))
    rows = []
    for key, n in counts.most_common():
        own = key.startswith(("tracer.", "bubbleoptics.", "libm "))
        rows.append(dict(function=key, samples=n, share_of_samples=n / total,
                         share_of_compiled_and_libm=n / work if own and work else None))
    write_csv(args.out, rows, provenance(
        "benchmarks/profile_render.py",
        f"perf record -e cpu-clock -F 2000 of {args.renders} warm render(s) of {args.scene} at "
        f"{args.width}x{args.width}, {args.threads} thread(s), after one render that compiles (fresh "
        "NUMBA_CACHE_DIR); numba's functions named through a perf JIT map written from their object code; "
        "share_of_compiled_and_libm: of the samples in numba's code and libm (the render's own work)",
        f"regenerate with: python benchmarks/profile_render.py --scene {args.scene} --width {args.width} "
        f"--renders {args.renders} --threads {args.threads}"), float_format="{:.4f}", na_rep="")
    for r in rows[:12]:
        share = r["share_of_compiled_and_libm"]
        print(f"{r['samples']:7d} {r['share_of_samples']:7.1%} {'' if share is None else f'{share:7.1%}':>8} {r['function']}")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
