"""Speed of bubbleoptics' thin-film optics and colour against its peers, in one process.

Run:  python benchmarks/optics_speed.py [--repeats N] [--tmm-calls N] [--quick]
(or ``make bench``).  Writes ``data/derived/optics_speed.csv``.

Sweep: 81 wavelengths (380-780 nm every 5 nm) x 90 angles (0-89 degrees) x 200 thicknesses
(0-2000 nm), unpolarized, a free-standing water film with Daimon & Masumura (2007) dispersion.
Peers, all timed here, side by side, as medians of repeated runs:

* ``bubbleoptics.film_reflectance`` (numba, exact Airy sum);
* ``colour.phenomena.thin_film_tmm`` (colour-science, NumPy transfer matrices, whole sweep);
* a plain NumPy Airy formula (textbook r = (r01 + r12 e)/(1 + r01 r12 e), complex arithmetic);
* ``tmm.coh_tmm`` (Byrnes), timed per call on a random subset and extrapolated to the sweep.

Each peer's largest deviation from bubbleoptics is reported too, so a fast wrong answer shows.
Then ``spectrum_to_XYZ`` against ``colour.sd_to_XYZ`` per spectrum.

Spread: every row has the fastest and the slowest of its runs (``min_seconds``,
``max_seconds``; tmm: of its calls timed in :data:`TMM_BATCHES` batches, extrapolated alike),
and the range of its ratio to bubbleoptics (``ratio_min``, ``ratio_max``): over the repeats
that ran both in the same round (NumPy and colour-science in the sweep; ``ratio_to_bubbleoptics``
is then the median of those paired ratios), else the peer's range over bubbleoptics' median.
The header records the machine's load average (1 min) before and after.
"""

import argparse
import os
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from study import provenance, wall_times, write_csv

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "derived" / "optics_speed.csv"
TMM_BATCHES = 3
COLUMNS = ("case", "implementation", "median_seconds", "min_seconds", "max_seconds", "repeats", "ns_per_evaluation",
           "max_abs_deviation_from_bubbleoptics", "note", "ratio_to_bubbleoptics", "ratio_min", "ratio_max")


def load_average():
    """The 1-minute load average (``/proc/loadavg``), or "n/a" where there is none."""
    try:
        return Path("/proc/loadavg").read_text().split()[0]
    except OSError:
        return "n/a"


def median_time(func, repeats, warmup=3):
    """Median wall time of *repeats* calls after *warmup* untimed ones (thread pools, page faults)."""
    times = wall_times(func, repeats, warmup)
    return float(np.median(times)), times


def numpy_airy_unpolarized(wl, d, theta, n_film):
    """Plain NumPy Airy sum for a free-standing film (air | film | air): the textbook formula."""
    n0 = 1.0
    cos0 = np.cos(theta)
    sin0 = np.sin(theta)
    cos1 = np.sqrt(1 - (n0 * sin0 / n_film) ** 2 + 0j)
    beta = 2 * np.pi * n_film * d * cos1 / wl
    e = np.exp(2j * beta)
    out = 0.0
    for pol in "sp":
        if pol == "s":
            r01 = (n0 * cos0 - n_film * cos1) / (n0 * cos0 + n_film * cos1)
        else:
            r01 = (n_film * cos0 - n0 * cos1) / (n_film * cos0 + n0 * cos1)
        r12 = -r01
        r = (r01 + r12 * e) / (1 + r01 * r12 * e)
        out = out + 0.5 * np.abs(r) ** 2
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=9, help="timed runs of the fast peers (median)")
    parser.add_argument("--tmm-calls", type=int, default=3000, help="tmm.coh_tmm calls timed per polarization")
    parser.add_argument("--quick", action="store_true", help="fewer repeats (smoke test)")
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    if args.quick:
        args.repeats, args.tmm_calls = 3, 200

    import colour
    import tmm
    from colour.phenomena import thin_film_tmm

    import bubbleoptics as bo

    wl = np.linspace(380.0, 780.0, 81)
    theta = np.deg2rad(np.arange(90.0))
    d = np.linspace(0.0, 2000.0, 200)
    n_water = bo.water_refractive_index(wl)
    n_evals = wl.size * theta.size * d.size
    rows = []

    def record(case, impl, seconds, runs, max_dev, note="", ratios=None):
        """*runs*: the seconds of every run; *ratios*: paired ratios to bubbleoptics, if any."""
        rows.append(
            dict(case=case, implementation=impl, median_seconds=seconds, min_seconds=float(np.min(runs)),
                 max_seconds=float(np.max(runs)), repeats=len(runs),
                 ns_per_evaluation=1e9 * seconds / n_evals if case == "sweep" else "",
                 max_abs_deviation_from_bubbleoptics=max_dev, note=note, paired=ratios)
        )

    print(f"sweep: {wl.size} wavelengths x {theta.size} angles x {d.size} thicknesses = {n_evals:,} "
          "unpolarized reflectances")

    def ours():
        return bo.film_reflectance(wl[:, None, None], d, theta[None, :, None], n_water[:, None, None])

    n_stack = np.array([np.ones_like(wl), n_water, np.ones_like(wl)])

    def colour_sweep():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return thin_film_tmm(n_stack, d, wl, np.rad2deg(theta))[0].mean(axis=-1)

    def numpy_sweep():
        return numpy_airy_unpolarized(wl[:, None, None], d, theta[None, :, None], n_water[:, None, None])

    load_before = load_average()
    # warm up, then interleave the peers in every repeat so that they see the same machine
    R_ours, R_col, R_np = ours(), colour_sweep(), numpy_sweep()
    for _ in range(2):
        ours()
    times = {"ours": [], "colour": [], "numpy": []}
    paired = {"colour": [], "numpy": []}  # peer / ours within one round
    for k in range(args.repeats):
        for name, func in (("ours", ours), ("numpy", numpy_sweep), ("colour", colour_sweep)):
            if name == "colour" and k % 3:
                continue  # colour-science is ~200x slower: every third repeat is enough
            t0 = time.perf_counter()
            func()
            times[name].append(time.perf_counter() - t0)
            if name != "ours":
                paired[name].append(times[name][-1] / times["ours"][-1])
    t_ours = float(np.median(times["ours"]))
    t_col = float(np.median(times["colour"]))
    t_np = float(np.median(times["numpy"]))
    record("sweep", "bubbleoptics.film_reflectance", t_ours, times["ours"], 0.0, ratios=[1.0])
    print(f"  bubbleoptics        {t_ours * 1e3:9.1f} ms  (median of {len(times['ours'])}, interleaved with the peers)")
    dev_col = float(np.max(np.abs(R_col - R_ours)))
    record("sweep", f"colour-science {colour.__version__} thin_film_tmm", t_col, times["colour"], dev_col,
           "refraction angles taken from the first wavelength only (dispersion ignored in angles)", paired["colour"])
    print(f"  colour-science      {t_col * 1e3:9.1f} ms   max |dR| vs ours {dev_col:.2e}")
    dev_np = float(np.max(np.abs(R_np - R_ours)))
    record("sweep", "plain NumPy Airy formula", t_np, times["numpy"], dev_np, ratios=paired["numpy"])
    print(f"  plain NumPy Airy    {t_np * 1e3:9.1f} ms   max |dR| vs ours {dev_np:.2e}")

    rng = np.random.default_rng(0)
    iw = rng.integers(0, wl.size, args.tmm_calls)
    ia = rng.integers(0, theta.size, args.tmm_calls)
    idd = rng.integers(0, d.size, args.tmm_calls)
    dev_tmm = 0.0
    batch_per_call = []
    for batch in np.array_split(np.arange(args.tmm_calls), TMM_BATCHES):
        t0 = time.perf_counter()
        for k in batch:
            i, j, m = iw[k], ia[k], idd[k]
            layers = [1.0, n_water[i], 1.0]
            thick = [np.inf, d[m], np.inf]
            r = 0.5 * (tmm.coh_tmm("s", layers, thick, theta[j], wl[i])["R"]
                       + tmm.coh_tmm("p", layers, thick, theta[j], wl[i])["R"])
            dev_tmm = max(dev_tmm, abs(r - R_ours[i, j, m]))
        batch_per_call.append((time.perf_counter() - t0) / batch.size)
    per_call = float(np.median(batch_per_call))
    t_tmm = per_call * n_evals
    record("sweep", f"tmm.coh_tmm (s+p per point; {args.tmm_calls} points, extrapolated)", t_tmm,
           [p * n_evals for p in batch_per_call], dev_tmm, f"{per_call * 1e6:.1f} us per unpolarized point")
    print(f"  tmm (extrapolated)  {t_tmm:9.1f} s    ({per_call * 1e6:.0f} us per point, "
          f"max |dR| vs ours {dev_tmm:.2e})")

    # spectrum -> XYZ, per spectrum
    wl_c = np.arange(360.0, 781.0, 1.0)
    spectra = rng.uniform(0, 1, (2000, wl_c.size))
    bo.spectrum_to_XYZ(spectra[:1], wl_c)  # build the cached weights
    t_xyz, xyz_runs = median_time(lambda: bo.spectrum_to_XYZ(spectra, wl_c), args.repeats)
    t_xyz /= spectra.shape[0]
    xyz_runs = np.asarray(xyz_runs) / spectra.shape[0]
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    ill = colour.SDS_ILLUMINANTS["D65"]
    sds = [colour.SpectralDistribution(s, wl_c) for s in spectra[:30]]
    dev_xyz = 0.0

    def colour_xyz():
        nonlocal dev_xyz
        for k, sd in enumerate(sds):
            xyz = colour.sd_to_XYZ(sd, cmfs, ill, method="Integration") / 100
            dev_xyz = max(dev_xyz, float(np.max(np.abs(xyz - bo.spectrum_to_XYZ(spectra[k], wl_c)))))

    t_cx, cx_runs = median_time(colour_xyz, 3, warmup=1)
    t_cx /= len(sds)
    cx_runs = np.asarray(cx_runs) / len(sds)
    record("spectrum_to_XYZ per spectrum (421 samples)", "bubbleoptics.spectrum_to_XYZ", t_xyz, xyz_runs, 0.0,
           "batch of 2000 spectra, time per spectrum", ratios=[1.0])
    record("spectrum_to_XYZ per spectrum (421 samples)", f"colour-science {colour.__version__} sd_to_XYZ Integration",
           t_cx, cx_runs, dev_xyz, "one call per spectrum")
    print(f"spectrum_to_XYZ: bubbleoptics {t_xyz * 1e6:.2f} us/spectrum, colour.sd_to_XYZ {t_cx * 1e6:.0f} "
          f"us/spectrum, max |dXYZ| {dev_xyz:.1e}")

    print("ratios (peer time / bubbleoptics time, same process; medians of medians):")
    print(f"  vs tmm            {t_tmm / t_ours:10.0f}x   (target >= 5000x)")
    print(f"  vs colour-science {t_col / t_ours:10.0f}x   (target >= 100x)")
    print(f"  vs plain NumPy    {t_np / t_ours:10.1f}x")
    print(f"  spectrum_to_XYZ vs colour.sd_to_XYZ {t_cx / t_xyz:10.0f}x")
    for row in rows:
        base = t_ours if row["case"] == "sweep" else t_xyz
        paired_ratios = row.pop("paired")
        # the median of the paired ratios where there are pairs (the ratio of the medians need not lie in their range)
        row["ratio_to_bubbleoptics"] = (float(np.median(paired_ratios)) if paired_ratios
                                        else row["median_seconds"] / base)
        ratios = paired_ratios or [row["min_seconds"] / base, row["max_seconds"] / base]
        row["ratio_min"], row["ratio_max"] = float(np.min(ratios)), float(np.max(ratios))
    load_after = load_average()

    write_csv(args.out, rows,
              provenance("benchmarks/optics_speed.py",
                         f"numba threads {os.environ.get('NUMBA_NUM_THREADS', 'default')}",
                         f"machine load average {load_before} before, {load_after} after (this process at niceness {os.nice(0)})",
                         "min/max: fastest and slowest run; ratio_min/max: over paired runs, else the peer's "
                         "range over bubbleoptics' median",
                         "regenerate with: python benchmarks/optics_speed.py"),
              fieldnames=COLUMNS, float_format=None)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
