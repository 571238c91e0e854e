"""Rebuild every figure of the paper: run each ``fig_*.py`` beside this file, in name order.

Run:  python paper/scripts/make_figures.py [--quick]

Each script runs in its own process (``sys.executable``), so one figure's matplotlib state
cannot leak into the next.  ``--quick`` sets ``BUBBLEOPTICS_QUICK=1`` in the scripts'
environment (coarser grids, the same figures).  The output folder is ``paper/figures/`` or
``BUBBLEOPTICS_FIGURES_DIR`` (see ``paths.py``).  The first script that fails stops the run:
its name and exit status are printed and this script exits with status 1.
"""

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="quick mode (BUBBLEOPTICS_QUICK=1)")
    args = parser.parse_args(argv)
    env = dict(os.environ)
    if args.quick:
        env["BUBBLEOPTICS_QUICK"] = "1"
    env.setdefault("MPLBACKEND", "Agg")
    scripts = sorted(HERE.glob("fig_*.py"))
    if not scripts:
        print(f"make_figures: no fig_*.py in {HERE}", file=sys.stderr)
        return 1
    for script in scripts:
        print(f"== {script.name}", flush=True)
        t0 = time.perf_counter()
        status = subprocess.run([sys.executable, str(script)], env=env, cwd=HERE).returncode
        if status != 0:
            print(f"make_figures: {script.name} failed (exit status {status}); stopped", file=sys.stderr, flush=True)
            return 1
        print(f"   {script.name}: {time.perf_counter() - t0:.1f} s", flush=True)
    print(f"make_figures: {len(scripts)} figure script(s) done")
    return 0


if __name__ == "__main__":
    sys.exit(main())
