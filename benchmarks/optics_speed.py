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

Threads: the peers run single-threaded (pure Python and NumPy; OpenBLAS, which ``spectrum_to_XYZ``'s
matrix product and any peer's would use, is held at one thread, :func:`blas_threads`), so ours is
timed with one thread and with two (``numba.set_num_threads``; OpenBLAS likewise for
``spectrum_to_XYZ``), both in every round beside the peers.  Column ``threads`` says which; the
like-for-like ratio is a peer's time over ours with one thread.  numba runs on its default
threading layer, what a caller of the library gets (the header names it; OpenMP here): on this
machine (2026-12-04) the workqueue layer (:func:`bubbleoptics.resources.prefer_workqueue_threads`, the
tracer's choice) lost most of its second thread whenever a peer had run in between (4.1 ms
with two threads against 4.2 with one, where OpenMP's two took 2.2 ms in the same rounds).

Spread: every row has the fastest and the slowest of its runs (``min_seconds``,
``max_seconds``; tmm: of its calls timed in :data:`TMM_BATCHES` batches, extrapolated alike).
``ratio_to_bubbleoptics`` is the row's time over bubbleoptics' with one thread,
``ratio_to_bubbleoptics_2_threads`` over bubbleoptics' with two (so bubbleoptics' one-thread row
has its speed-up from one thread to two there), each the median of the ratios within the rounds
that ran both, with their range (``ratio_min``, ``ratio_max``, ``ratio_2_threads_min``,
``ratio_2_threads_max``); tmm, timed apart, has its range over bubbleoptics' median instead.
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
THREADS = (1, 2)
COLUMNS = ("case", "implementation", "threads", "median_seconds", "min_seconds", "max_seconds", "repeats",
           "ns_per_evaluation", "max_abs_deviation_from_bubbleoptics", "note", "ratio_to_bubbleoptics", "ratio_min",
           "ratio_max", "ratio_to_bubbleoptics_2_threads", "ratio_2_threads_min", "ratio_2_threads_max")


def load_average():
    """The 1-minute load average (``/proc/loadavg``), or "n/a" where there is none."""
    try:
        return Path("/proc/loadavg").read_text().split()[0]
    except OSError:
        return "n/a"


def _openblas():
    """NumPy's bundled OpenBLAS as ``(get_num_threads, set_num_threads)`` (ctypes), or None."""
    import ctypes

    libs = sorted((Path(np.__file__).parent.parent / "numpy.libs").glob("*openblas*"))
    for path in libs:
        try:
            lib = ctypes.CDLL(str(path))
        except OSError:
            continue
        for prefix in ("scipy_openblas", "openblas"):
            for suffix in ("64_", ""):
                get = getattr(lib, f"{prefix}_get_num_threads{suffix}", None)
                put = getattr(lib, f"{prefix}_set_num_threads{suffix}", None)
                if get is not None and put is not None:
                    put.argtypes = [ctypes.c_int]
                    return get, put
    return None


_BLAS = _openblas()


def blas_threads(n=None):
    """Set NumPy's OpenBLAS to *n* threads (if given); return its thread count, or "n/a" where
    this NumPy has no OpenBLAS of its own to ask."""
    if _BLAS is None:
        return "n/a"
    if n is not None:
        _BLAS[1](n)
    return int(_BLAS[0]())


def threads(n):
    """Run bubbleoptics with *n* threads: numba's and OpenBLAS's."""
    import numba

    numba.set_num_threads(n)
    blas_threads(n)


def timed(func):
    """Wall time (s) of one call of *func*."""
    t0 = time.perf_counter()
    func()
    return time.perf_counter() - t0


def median_time(func, repeats, warmup=3):
    """Median wall time of *repeats* calls after *warmup* untimed ones (thread pools, page faults)."""
    times = wall_times(func, repeats, warmup)
    return float(np.median(times)), times


def interleaved(ours, peers, repeats, every=None):
    """Time ``ours`` with each of :data:`THREADS` and every peer in each of *repeats* rounds (the
    peers with one thread; the order of the two ``ours`` alternates from round to round, and each
    is timed after one untimed call with its thread count, which wakes the threads).

    *every*: {peer: k} to run that peer only every k-th round.  Returns ``(times, paired)``:
    {name: [seconds]} with names ``ours1``, ``ours2`` and the peers', and {name: {1: [ratios],
    2: [ratios]}}: each run over ours with 1 and 2 threads in the same round."""
    every = every or {}
    names = [f"ours{n}" for n in THREADS] + list(peers)
    times = {name: [] for name in names}
    paired = {name: {n: [] for n in THREADS} for name in names}
    for k in range(repeats):
        this = {}
        for n in (THREADS if k % 2 == 0 else THREADS[::-1]):
            threads(n)
            ours()  # untimed: wakes the threads after the switch
            this[f"ours{n}"] = timed(ours)
        threads(1)
        for name, func in peers.items():
            if k % every.get(name, 1) == 0:
                this[name] = timed(func)
        for name, t in this.items():
            times[name].append(t)
            for n in THREADS:
                paired[name][n].append(t / this[f"ours{n}"])
    return times, paired


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
    parser.add_argument("--repeats", type=int, default=15, help="timed rounds of the fast peers (median)")
    parser.add_argument("--tmm-calls", type=int, default=3000, help="tmm.coh_tmm calls timed per polarization")
    parser.add_argument("--quick", action="store_true", help="fewer repeats (smoke test)")
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    if args.quick:
        args.repeats, args.tmm_calls = 3, 200

    import colour
    import numba
    import tmm
    from colour.phenomena import thin_film_tmm

    import bubbleoptics as bo

    blas_default = blas_threads()
    wl = np.linspace(380.0, 780.0, 81)
    theta = np.deg2rad(np.arange(90.0))
    d = np.linspace(0.0, 2000.0, 200)
    n_water = bo.water_refractive_index(wl)
    n_evals = wl.size * theta.size * d.size
    rows = []

    def record(case, impl, n_threads, runs, max_dev, note="", ratios=None):
        """*runs*: the seconds of every run; *ratios*: {1: [...], 2: [...]}, the runs' ratios to
        bubbleoptics with 1 and 2 threads in the same round, if any."""
        seconds = float(np.median(runs))
        rows.append(
            dict(case=case, implementation=impl, threads=n_threads, median_seconds=seconds,
                 min_seconds=float(np.min(runs)), max_seconds=float(np.max(runs)), repeats=len(runs),
                 ns_per_evaluation=1e9 * seconds / n_evals if case == "sweep" else "",
                 max_abs_deviation_from_bubbleoptics=max_dev, note=note, paired=ratios)
        )

    def ours():
        return bo.film_reflectance(wl[:, None, None], d, theta[None, :, None], n_water[:, None, None])

    ours()  # compiles, and starts numba's threads
    layer = numba.threading_layer()
    print(f"sweep: {wl.size} wavelengths x {theta.size} angles x {d.size} thicknesses = {n_evals:,} "
          f"unpolarized reflectances; ours with {' and '.join(map(str, THREADS))} threads "
          f"(numba's {layer} layer), the peers with one (OpenBLAS default {blas_default})")

    n_stack = np.array([np.ones_like(wl), n_water, np.ones_like(wl)])

    def colour_sweep():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return thin_film_tmm(n_stack, d, wl, np.rad2deg(theta))[0].mean(axis=-1)

    def numpy_sweep():
        return numpy_airy_unpolarized(wl[:, None, None], d, theta[None, :, None], n_water[:, None, None])

    load_before = load_average()
    # warm up (compilation, each thread count's pool), then interleave ours and the peers in every round
    threads(1)
    R_ours, R_col, R_np = ours(), colour_sweep(), numpy_sweep()
    for n in THREADS:
        threads(n)
        for _ in range(2):
            ours()
    # colour-science is ~100x slower: every third round is enough
    times, paired = interleaved(ours, {"numpy": numpy_sweep, "colour": colour_sweep}, args.repeats, {"colour": 3})
    for n in THREADS:
        record("sweep", "bubbleoptics.film_reflectance", n, times[f"ours{n}"], 0.0, ratios=paired[f"ours{n}"])
        t = float(np.median(times[f"ours{n}"]))
        print(f"  bubbleoptics {n} thr. {t * 1e3:9.1f} ms  (median of {len(times[f'ours{n}'])}, "
              "interleaved with the peers)")
    dev_col = float(np.max(np.abs(R_col - R_ours)))
    record("sweep", f"colour-science {colour.__version__} thin_film_tmm", 1, times["colour"], dev_col,
           "refraction angles taken from the first wavelength only (dispersion ignored in angles)", paired["colour"])
    print(f"  colour-science      {np.median(times['colour']) * 1e3:9.1f} ms   max |dR| vs ours {dev_col:.2e}")
    dev_np = float(np.max(np.abs(R_np - R_ours)))
    record("sweep", "plain NumPy Airy formula", 1, times["numpy"], dev_np, ratios=paired["numpy"])
    print(f"  plain NumPy Airy    {np.median(times['numpy']) * 1e3:9.1f} ms   max |dR| vs ours {dev_np:.2e}")

    threads(1)
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
    record("sweep", f"tmm.coh_tmm (s+p per point; {args.tmm_calls} points, extrapolated)", 1,
           [p * n_evals for p in batch_per_call], dev_tmm, f"{per_call * 1e6:.1f} us per unpolarized point")
    print(f"  tmm (extrapolated)  {t_tmm:9.1f} s    ({per_call * 1e6:.0f} us per point, "
          f"max |dR| vs ours {dev_tmm:.2e})")

    # spectrum -> XYZ, per spectrum: ours (a matrix product, OpenBLAS) with 1 and 2 threads, colour-science's
    # sd_to_XYZ, interleaved like the sweep
    wl_c = np.arange(360.0, 781.0, 1.0)
    spectra = rng.uniform(0, 1, (2000, wl_c.size))
    n_col = 30
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    ill = colour.SDS_ILLUMINANTS["D65"]
    sds = [colour.SpectralDistribution(s, wl_c) for s in spectra[:n_col]]
    ours_xyz = bo.spectrum_to_XYZ(spectra, wl_c)  # builds the cached weights
    dev_xyz = max(float(np.max(np.abs(colour.sd_to_XYZ(sd, cmfs, ill, method="Integration") / 100 - ours_xyz[k])))
                  for k, sd in enumerate(sds))

    def ours_xyz_batch():
        return bo.spectrum_to_XYZ(spectra, wl_c)

    def colour_xyz():
        for sd in sds:
            colour.sd_to_XYZ(sd, cmfs, ill, method="Integration")

    for n in THREADS:
        threads(n)
        wall_times(ours_xyz_batch, 0, warmup=3)
    threads(1)
    colour_xyz()
    # per spectrum: divide each run by its number of spectra (the paired ratios too)
    xtimes, xpaired = interleaved(ours_xyz_batch, {"colour": colour_xyz}, args.repeats)
    per = {"ours1": spectra.shape[0], "ours2": spectra.shape[0], "colour": n_col}
    for name, count in per.items():
        xtimes[name] = [t / count for t in xtimes[name]]
        xpaired[name] = {n: [r * spectra.shape[0] / count for r in v] for n, v in xpaired[name].items()}
    case = f"spectrum_to_XYZ per spectrum ({wl_c.size} samples)"
    for n in THREADS:
        record(case, "bubbleoptics.spectrum_to_XYZ", n, xtimes[f"ours{n}"], 0.0,
               f"batch of {spectra.shape[0]} spectra, time per spectrum", xpaired[f"ours{n}"])
    record(case, f"colour-science {colour.__version__} sd_to_XYZ Integration", 1, xtimes["colour"], dev_xyz,
           f"one call per spectrum, {n_col} per run", xpaired["colour"])
    print(f"spectrum_to_XYZ: bubbleoptics {np.median(xtimes['ours1']) * 1e6:.2f} us/spectrum (1 thread), "
          f"{np.median(xtimes['ours2']) * 1e6:.2f} (2 threads), colour.sd_to_XYZ "
          f"{np.median(xtimes['colour']) * 1e6:.0f} us/spectrum, max |dXYZ| {dev_xyz:.1e}")

    base = {}  # bubbleoptics' median with 1 and 2 threads, per case
    for row in rows:
        if row["implementation"].startswith("bubbleoptics."):
            base[row["case"], row["threads"]] = row["median_seconds"]
    for row in rows:
        ratios = row.pop("paired")
        for n, key, lo, hi in ((1, "ratio_to_bubbleoptics", "ratio_min", "ratio_max"),
                               (2, "ratio_to_bubbleoptics_2_threads", "ratio_2_threads_min", "ratio_2_threads_max")):
            ref = base[row["case"], n]
            if ratios:  # the median of the paired ratios (the ratio of the medians need not lie in their range)
                row[key] = float(np.median(ratios[n]))
                row[lo], row[hi] = float(np.min(ratios[n])), float(np.max(ratios[n]))
            else:
                row[key] = row["median_seconds"] / ref
                row[lo], row[hi] = row["min_seconds"] / ref, row["max_seconds"] / ref
    load_after = load_average()

    print("ratios (peer time / bubbleoptics time with 1 thread [with 2 threads]; medians of paired runs):")
    for row in rows:
        print(f"  {row['implementation'][:48]:48s} {row['threads']} thr. {row['ratio_to_bubbleoptics']:10.3g}x "
              f"[{row['ratio_to_bubbleoptics_2_threads']:.3g}x]")

    write_csv(args.out, rows,
              provenance("benchmarks/optics_speed.py",
                         f"bubbleoptics timed with {' and '.join(map(str, THREADS))} threads (column threads; "
                         f"numba.set_num_threads, numba's default {layer} threading layer, and OpenBLAS), "
                         "interleaved in the same rounds as the peers, which run single-threaded (OpenBLAS "
                         f"at 1 thread, its default here {blas_default})",
                         f"machine load average {load_before} before, {load_after} after (this process at niceness {os.nice(0)})",
                         "min/max: fastest and slowest run; ratio_to_bubbleoptics: this row's time over "
                         "bubbleoptics' with 1 thread (the like-for-like ratio), ratio_to_bubbleoptics_2_threads: "
                         "over bubbleoptics' with 2 threads; medians and ranges of the ratios within a round "
                         "(tmm: its range over bubbleoptics' median)",
                         "regenerate with: python benchmarks/optics_speed.py"),
              fieldnames=COLUMNS, float_format=None)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
