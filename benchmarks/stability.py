"""Numerical stress tests of bubbleoptics, as data: grazing incidence and thick-film aliasing.

Run:  python benchmarks/stability.py [--quick]
Writes ``data/derived/stability_grazing.csv`` and ``data/derived/stability_aliasing.csv``
(read by ``notebooks/05_stability.ipynb`` and ``paper/scripts/fig_stability.py``) and prints a
summary.  The tests and their analysis are :mod:`study.stability` (the notebook
calls the same functions): grazing incidence against the 40-digit references of
:mod:`study.reference` (needs the ``test`` extra: mpmath, tmm), and the colour of
thick films from few point-sampled bands against the 1 nm reference.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

from study import provenance, write_csv
from study.stability import (
    ALIASING_COLUMNS,
    GRAZING_COLUMNS,
    GRAZING_FILMS,
    POLARIZATIONS,
    aliasing_table,
    grazing_summary,
    grazing_table,
)

ROOT = Path(__file__).resolve().parents[1]
DERIVED = ROOT / "data" / "derived"
GRAZING_CSV = DERIVED / "stability_grazing.csv"
ALIASING_CSV = DERIVED / "stability_aliasing.csv"


def write_table(path, rows, columns, what, digits=None):
    """Write *rows* (dicts) to *path* with the provenance comment; floats at full precision
    (shortest round-trip representation, 'nan' for NaN), or rounded to *digits* significant
    digits."""
    return write_csv(path, rows, provenance("benchmarks/stability.py", what,
                                            "regenerate with: python benchmarks/stability.py"),
                     fieldnames=list(columns), float_format=None if digits is None else f"{{:.{digits}g}}",
                     extrasaction="ignore")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="coarser grids (17 angles, 401 thicknesses)")
    parser.add_argument("--angles", type=int, default=None, help="number of u values in [0, 8] (default 81)")
    parser.add_argument("--thicknesses", type=int, default=None, help="thicknesses in 0-20 um (default 2001)")
    parser.add_argument("--grazing-out", type=Path, default=GRAZING_CSV)
    parser.add_argument("--aliasing-out", type=Path, default=ALIASING_CSV)
    args = parser.parse_args(argv)
    n_u = args.angles or (17 if args.quick else 81)
    n_d = args.thicknesses or (401 if args.quick else 2001)

    import bubbleoptics as bo

    bo.film_rt(550.0, 100.0, 0.1)  # compile / load the numba cache outside the timings
    t_start = time.perf_counter()
    rows_g, time_g = grazing_table(n_u)
    write_table(args.grazing_out, rows_g, GRAZING_COLUMNS, "grazing incidence")
    t_grazing = time.perf_counter() - t_start

    t0 = time.perf_counter()
    thickness = np.linspace(0.0, 20000.0, n_d)
    rows_a, time_a = aliasing_table(thickness)
    write_table(args.aliasing_out, rows_a, ALIASING_COLUMNS, "thick-film aliasing", digits=9)  # colours: 9 digits
    t_aliasing = time.perf_counter() - t0

    print(f"grazing incidence: {n_u} angles x {len(GRAZING_FILMS)} films x {len(POLARIZATIONS)} polarizations, "
          f"550 nm, theta = pi/2 - 10^-u, u in [0, 8]  ({t_grazing:.1f} s; "
          + ", ".join(f"{m} {t:.2f} s" for m, t in time_g.items()) + ")")
    worst = grazing_summary(rows_g)
    for method, (rel_T, abs_R) in worst.items():
        print(f"  {method:>12}: worst relative error of T {rel_T:.1e}, worst absolute error of R {abs_R:.1e}"
              " (unpolarized, all films)")
    for u_max in (4.0, 6.0):
        sub = [r for r in rows_g if r["u"] <= u_max + 1e-12]
        print(f"    up to u = {u_max:g}: " + ", ".join(
            f"{m} {v[0]:.1e}" for m, v in grazing_summary(sub).items()))
    print(f"  written {args.grazing_out}")

    print(f"thick-film aliasing: {n_d} thicknesses 0-20 um, water, normal incidence  ({t_aliasing:.1f} s)")
    print(f"  {'method':>12} {'N':>4} {'max dE00 d<2um':>15} {'median dE00':>12} "
          f"{'onset measured':>15} {'predicted 400 nm':>17} {'550 nm':>8}")
    methods = sorted({(r["method"], r["n_bands"]) for r in rows_a if r["method"] != "reference_1nm"})
    for method, N in methods:
        sel = [r for r in rows_a if r["method"] == method and r["n_bands"] == N]
        d = np.array([r["thickness_nm"] for r in sel])
        dE = np.array([r["dE00"] for r in sel])
        onset = sel[0]["onset_measured_nm"]
        onset = "never" if math.isnan(onset) else f"{onset / 1000:.2f}um"
        print(f"  {method:>12} {N:>4} {dE[d < 2000].max():>15.2f} {np.median(dE):>12.2f} {onset:>15} "
              f"{sel[0]['onset_pred_400_nm'] / 1000:>15.2f}um {sel[0]['onset_pred_550_nm'] / 1000:>6.2f}um")
    if not any(m == "bandlimited" for m, _ in methods):
        print("  (bubbleoptics.film_color_bandlimited not available: band-limited method skipped)")
    print(f"  written {args.aliasing_out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
