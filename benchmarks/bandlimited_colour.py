"""Film colour from few spectral samples: aliasing of point sampling against band-limited methods.

Run:  python benchmarks/bandlimited_colour.py [--thicknesses N] [--repeats N] [--quick]
Writes ``data/derived/bandlimited_colour.csv``.

Setting: a free-standing water film (Daimon & Masumura 2007 dispersion) in air, unpolarized,
thickness 0-20 µm (4001 values), angles of incidence 0° and 60°, CIE 1931 2° observer, D65.
Reference: the 1 nm spectrum, 360-780 nm (``bubbleoptics.film_color(..., wavelengths_nm=None)``
before display encoding).  Error: CIE ΔE00 (``colour.delta_E(..., method="CIE 2000")``) of
``colour.XYZ_to_Lab`` with the illuminant's white, per thickness; the table gives its median,
95th percentile, maximum, and the thickness of the maximum over 0-20 µm, and the median and
maximum over 0-2 µm alone (the saturated low orders; over 0-20 µm the grey thick films, where
every method but point sampling converges, pull the median down).

Methods (N bands of equal width over 360-780 nm):

* ``point``: R sampled at the N band centres, weights ``band_spectral_weights(N)`` (what the
  tracer does today);
* ``band_mean``: one value per band, R averaged uniformly in wavelength over the band
  (``film_reflectance_band``), same weights: what a renderer carrying one value per band can use;
* ``band_mean_phase``: the same averaged uniformly in phase (the atan2 closed form alone,
  ``kernels.film_band_average``);
* ``bandlimited``: ``film_XYZ_bandlimited`` -- CMFs x D65 as continuous piecewise polynomials of
  degree ``order`` in wavenumber, integrated exactly against the film's band moments.

Second block, illuminant E and a non-dispersive film (n = 1.33), the setting of the Gaussian
fit of the CMFs in Fourier space by L. Belcour and P. Barla, "A Practical Extension to Microfacet
Theory for the Modeling of Varying Iridescence", ACM TOG 36(4), 65 (SIGGRAPH 2017), also used by
Blender 4.2's thin film: the film's exact Fourier series in optical path difference,
:math:`R = (1 - T_{inc}) - 2T_{inc}\\sum_m \\rho^m\\cos(2\\pi m\\,{\\rm OPD}/\\lambda)` (summed
to convergence, so only the CMF fit is tested), with each term's XYZ from their published
Gaussian-fit sensitivity (constants as in the paper's supplemental code).  Its reference is the 1 nm
spectrum under E with the same n; ``gaussian_fit_vs_dispersive`` compares it with the water
(dispersive) reference under E instead, adding the error of ignoring dispersion.

Times: wall time per colour (XYZ only, after a warm-up call), median and minimum of the repeats,
numba kernels on all of this machine's cores; the Gaussian fit is plain NumPy (vectorized) and
is timed for completeness only.
"""

import argparse
import csv
import datetime
import os
import platform
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "derived" / "bandlimited_colour.csv"
OBSERVER = "CIE 1931 2 Degree Standard Observer"

# Belcour & Barla (2017), supplemental code, evalSensitivity: XYZ CMFs fitted in wavenumber by
# Gaussians (one per channel, two for x), Fourier-transformed in closed form; OPD in m.
_BB_VAL = np.array([5.4856e-13, 4.4201e-13, 5.2481e-13])
_BB_POS = np.array([1.6810e06, 1.7953e06, 2.2084e06])
_BB_VAR = np.array([4.3278e09, 9.3046e09, 6.6121e09])
_BB_X2 = (9.7470e-14, 2.2399e06, 4.5282e09)  # value, position, variance of x's second lobe
_BB_NORM = 1.0685e-7


def bb_sensitivity(opd_nm):
    """Belcour-Barla's XYZ sensitivity S(OPD) (shift 0) for OPD in nm; shape (..., 3)."""
    phase = 2.0 * np.pi * np.asarray(opd_nm, float)[..., None] * 1e-9
    xyz = _BB_VAL * np.sqrt(2.0 * np.pi * _BB_VAR) * np.cos(_BB_POS * phase) * np.exp(-_BB_VAR * phase**2)
    v, p, s = _BB_X2
    xyz[..., 0] += v * np.sqrt(2.0 * np.pi * s) * np.cos(p * phase[..., 0]) * np.exp(-s * phase[..., 0] ** 2)
    return xyz / _BB_NORM


def bb_film_XYZ(d, theta, n_film):
    """XYZ (illuminant E) of a free-standing lossless film by the Fourier series x Gaussian fit."""
    import bubbleoptics as bo

    f = bo.fresnel_coefficients(1.0, n_film, theta)
    q1 = np.sqrt(n_film**2 - np.sin(theta) ** 2)
    opd = 2.0 * d * q1  # nm; 2 beta = 2 pi OPD / lambda
    out = 0.0
    for rho in (float(f.Rs), float(f.Rp)):  # free-standing film: rho = R01, T_inc = (1-R01)/(1+R01)
        t_inc = (1.0 - rho) / (1.0 + rho)
        xyz = (1.0 - t_inc) * bb_sensitivity(0.0) * np.ones_like(opd)[..., None]
        m = 1
        while rho**m > 1e-17:
            xyz = xyz - 2.0 * t_inc * rho**m * bb_sensitivity(m * opd)
            m += 1
        out = out + 0.5 * xyz
    return out


def timed(func, repeats):
    """(median, minimum) wall time of *repeats* calls after one untimed warm-up call.

    The minimum is the one to compare on a shared machine (the others' load only adds time).
    """
    func()
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        func()
        times.append(time.perf_counter() - t0)
    return float(np.median(times)), float(np.min(times))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--thicknesses", type=int, default=4001, help="thickness samples over 0-20 um")
    parser.add_argument("--repeats", type=int, default=5, help="timed runs (median)")
    parser.add_argument("--quick", action="store_true", help="401 thicknesses, 2 repeats (smoke test)")
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    if args.quick:
        args.thicknesses, args.repeats = 401, 2

    import colour

    import bubbleoptics as bo
    from bubbleoptics.bandlimited import film_XYZ_bandlimited
    from bubbleoptics.colorimetry import DEFAULT_WAVELENGTHS_NM as WL

    d = np.linspace(0.0, 20000.0, args.thicknesses)
    thin = d <= 2000.0  # the first interference orders, where the colours are saturated
    rows = []

    def lab(XYZ, ill):
        wp = colour.CCS_ILLUMINANTS[OBSERVER][ill]
        return colour.XYZ_to_Lab(XYZ, wp)

    def record(method, n_bands, order, ill, theta_deg, XYZ, ref_lab, seconds, note=""):
        t_med, t_min = seconds
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            e = np.asarray(colour.delta_E(lab(XYZ, ill), ref_lab, method="CIE 2000"))
        rows.append(
            dict(
                method=method,
                n_bands=n_bands,
                order=order,
                illuminant=ill,
                theta_deg=theta_deg,
                dE00_median=float(np.median(e)),
                dE00_p95=float(np.percentile(e, 95)),
                dE00_max=float(e.max()),
                worst_thickness_nm=float(d[int(np.argmax(e))]),
                dE00_median_0_2um=float(np.median(e[thin])),
                dE00_max_0_2um=float(e[thin].max()),
                ns_per_colour=1e9 * t_med / d.size,
                ns_per_colour_min=1e9 * t_min / d.size,
                note=note,
            )
        )
        r = rows[-1]
        print(
            f"{method:28s} N={str(n_bands):>4s} L={str(order):>2s} {ill:3s} {theta_deg:4.0f}°  "
            f"median {r['dE00_median']:6.3f}  p95 {r['dE00_p95']:6.3f}  max {r['dE00_max']:6.3f} "
            f"(at {r['worst_thickness_nm']:7.0f} nm)  0-2um: {r['dE00_median_0_2um']:6.3f} {r['dE00_max_0_2um']:6.3f}  "
            f"{r['ns_per_colour']:6.0f} ns/colour (min {r['ns_per_colour_min']:.0f})",
            flush=True,
        )

    W1 = bo.spectral_weights(WL)
    for theta_deg in (0.0, 60.0):
        th = np.deg2rad(theta_deg)
        ref_xyz = bo.film_reflectance(WL, d[:, None], th) @ W1.T
        ref = lab(ref_xyz, "D65")
        t = timed(lambda: bo.film_reflectance(WL, d[:, None], th) @ W1.T, args.repeats)
        record("reference_1nm", 421, "", "D65", theta_deg, ref_xyz, ref, t)
        for N in (4, 8, 16):
            wl, Wb = bo.band_spectral_weights(N)

            def point(wl=wl, Wb=Wb):
                return bo.film_reflectance(wl, d[:, None], th) @ Wb.T

            record("point", N, "", "D65", theta_deg, point(), ref, timed(point, args.repeats))

            def band_mean(Wb=Wb, N=N):
                return bo.film_reflectance_band(N, d, th) @ Wb.T

            record("band_mean", N, 6, "D65", theta_deg, band_mean(), ref, timed(band_mean, args.repeats))

            def band_mean_phase(Wb=Wb, N=N):
                return bo.film_reflectance_band(N, d, th, weighting="phase") @ Wb.T

            record("band_mean_phase", N, 0, "D65", theta_deg, band_mean_phase(), ref,
                   timed(band_mean_phase, args.repeats))
            for L in (2, 3, 4, 8):

                def bandlimited(N=N, L=L):
                    return film_XYZ_bandlimited(d, th, N, order=L)

                record("bandlimited", N, L, "D65", theta_deg, bandlimited(), ref,
                       timed(bandlimited, args.repeats), "default" if L == 3 else "")

    # Illuminant E, non-dispersive film: the Gaussian CMF fit of Belcour & Barla (2017)
    WE = bo.spectral_weights(WL, illuminant=None)
    n_const = 1.33
    for theta_deg in (0.0, 60.0):
        th = np.deg2rad(theta_deg)
        ref_const = lab(bo.film_reflectance(WL, d[:, None], th, n_const) @ WE.T, "E")
        ref_water = lab(bo.film_reflectance(WL, d[:, None], th) @ WE.T, "E")
        bb = bb_film_XYZ(d, th, n_const)
        t = timed(lambda: bb_film_XYZ(d, th, n_const), args.repeats)
        record("gaussian_fit_BB2017", "", "", "E", theta_deg, bb, ref_const, t, "n=1.33; NumPy")
        record("gaussian_fit_vs_dispersive", "", "", "E", theta_deg, bb, ref_water, t,
               "n=1.33 against the water reference")
        wl, Wb = bo.band_spectral_weights(16, illuminant=None)
        pt = bo.film_reflectance(wl, d[:, None], th, n_const) @ Wb.T
        record("point", 16, "", "E", theta_deg, pt, ref_const, (float("nan"), float("nan")), "n=1.33")
        ours = film_XYZ_bandlimited(d, th, 16, n_film=n_const, illuminant=None, order=3)
        record("bandlimited", 16, 3, "E", theta_deg, ours, ref_const, (float("nan"), float("nan")), "n=1.33")

    args.out.parent.mkdir(parents=True, exist_ok=True)
    with open(args.out, "w", newline="") as fh:
        fh.write(f"# written by benchmarks/bandlimited_colour.py on {datetime.date.today()}; "
                 f"{d.size} thicknesses 0-20000 nm; {platform.processor() or platform.machine()}, "
                 f"{os.cpu_count()} CPUs; regenerate with: python benchmarks/bandlimited_colour.py\n")
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        for r in rows:
            writer.writerow({k: (f"{v:.4g}" if isinstance(v, float) else v) for k, v in r.items()})
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
