"""Film colour from few spectral samples: aliasing of point sampling against band-limited methods.

Run:  python benchmarks/bandlimited_colour.py [--thicknesses N] [--repeats N] [--quick]
Writes ``data/derived/bandlimited_colour.csv``.

Setting: a free-standing water film (Daimon & Masumura 2007 dispersion) in air, unpolarized,
thickness 0-20 µm (4001 values), angles of incidence 0° and 60°, CIE 1931 2° observer, D65.
Reference: the 1 nm spectrum, 360-780 nm (``bubbleoptics.film_color(..., wavelengths_nm=None)``
before display encoding).  Error: CIE ΔE00 (:func:`study.delta_e00_XYZ`: colour-science's
CIEDE2000 of ``colour.XYZ_to_Lab`` with the illuminant's white), per thickness; the table gives its median,
95th percentile, maximum, and the thickness of the maximum over 0-20 µm, and the median and
maximum over 0-2 µm alone (the saturated low orders; over 0-20 µm the grey thick films, where
every method but point sampling converges, pull the median down).  These compare the colours
as reflected: a water film reflects at most ~8 %, so they are dark (L* below ~35) and their
differences small.  ``dE00_max_exposed`` and ``dE00_median_0_2um_exposed`` compare them after
the exposure ``exposure`` = 1 / (the reference's largest Y over 0-1 µm), which makes the
brightest film white, as ``benchmarks/stability.py``, notebook 01 and a camera exposed for the
bubble show them: every difference grows (2-3x).

Methods (N bands of equal width over 360-780 nm):

* ``point``: R sampled at the N band centres, weights ``band_spectral_weights(N)`` (what the
  tracer does today);
* ``band_mean``: one value per band, R averaged uniformly in wavelength over the band
  (``film_reflectance_band``), same weights: what a renderer carrying one value per band can use;
* ``band_mean_phase``: the same averaged uniformly in phase (the atan2 closed form alone,
  ``kernels.film_band_average_nb``);
* ``bandlimited``: ``film_XYZ_bandlimited`` -- CMFs x D65 as continuous piecewise polynomials of
  degree ``order`` in wavenumber, integrated exactly against the film's band moments.

Second block: the published approaches of :mod:`study.film_colour` (that module's
docstring gives their sources, construction and check), each on its own setting, illuminant E
and a film of constant index n = 1.33 (the setting of the Gaussian fit of L. Belcour and P.
Barla, ACM TOG 36(4), 65, 2017, also used by Blender 4.2's thin film), with each term of the
film's exact Fourier series in OPD weighted by the approach's sensitivity S(OPD):

* ``gaussian_fit_BB2017``: the Gaussian fit of the CMFs
  (:func:`~study.film_colour.bb_film_XYZ`)
  against the 1 nm spectrum under E with the same n; ``gaussian_fit_vs_dispersive`` compares it
  with the water (dispersive) reference under E instead, adding the error of ignoring dispersion.
* ``lut_nondispersive``: the lookup table of the exact 1 nm sensitivity
  (:func:`~study.film_colour.lut_table`, every 1 nm of OPD to 64.8 µm).

``lut_nondispersive`` against the constant-index reference measures the table's own error
(interpolation and the dropped terms; tiny).  ``lut_nondispersive_vs_dispersive`` against the
water reference measures the cost of ignoring dispersion with n = 1.33 (below water's index at
every wavelength in 360-780 nm: 1.348-1.329, 1.33 near 725 nm), and
``lut_nondispersive_n555_vs_dispersive`` the same with the constant index set to water's at
555 nm (the peak of y-bar, 1.3345): the choice of the single index is part of the cost.  Ours is
the exact 1 nm integral on a 1 nm grid, so its error against the dispersive reference is that
of ignoring dispersion alone, essentially a lower bound for any table of this kind with the same
constant index, whatever its resolution; another table adds its own error, which can partly
offset the dispersion error at some thicknesses (the Gaussian fit's maximum at 60° is lower).

``lut_blender_like`` (against the n = 1.33 reference: the table's own error) and
``lut_blender_like_vs_dispersive`` (against the water reference): the same series with the table
rebuilt like Blender's (:func:`~study.film_colour.blender_like_table`: 512 complex
entries every 18.7 nm of OPD to 9.55 µm, last entry held, m <= 3, RGB per-channel DC
normalization).  The rows follow the later of the two revisions of Blender's kernel (real and
imaginary parts interpolated); the run prints the earlier's errors (magnitude and phase,
``polar=True``, not a row).

Checked at every run (:func:`~study.film_colour.check_lut`): at thicknesses whose OPD
falls on table nodes, the table's series equals the direct 1 nm integration of
``film_reflectance(..., n_film=1.33)`` to 1e-11 in XYZ up to 2 µm and to 1e-5 up to 20 µm.

``bandlimited_water``: ``film_XYZ_bandlimited`` (16 bands, order 3, illuminant E) of the water film
against the water reference under E, the like-for-like companion of the two ``_vs_dispersive``
rows.

Times: wall time per colour (XYZ only, after a warm-up call), median, minimum and maximum of the repeats,
numba kernels on all of this machine's cores; the Gaussian fit and the lookup table are plain
NumPy (vectorized; the tables' construction, about a second, is not included) and are timed for
completeness only.
"""

import argparse
import os
import time
from pathlib import Path

import numpy as np

from study import delta_e00_XYZ, provenance, wall_times, write_csv
from study.film_colour import (
    BLENDER_STEP_NM,
    BLENDER_TERMS,
    LUT_STEP_NM,
    bb_film_XYZ,
    blender_like_table,
    check_lut,
    lut_film_XYZ,
    lut_sensitivity,
    lut_table,
)

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "derived" / "bandlimited_colour.csv"


def timed(func, repeats):
    """(median, minimum, maximum) wall time of *repeats* calls after one untimed warm-up call.

    The minimum is the one to compare on a shared machine (the others' load only adds time); the
    maximum shows how much the others disturbed the runs.
    """
    times = wall_times(func, repeats)
    return float(np.median(times)), float(np.min(times)), float(np.max(times))


def _load():
    """The 1-minute load average (other work on a shared machine)."""
    with open("/proc/loadavg") as f:
        return float(f.read().split()[0])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--thicknesses", type=int, default=4001, help="thickness samples over 0-20 um")
    parser.add_argument("--repeats", type=int, default=9, help="timed runs (median, min, max)")
    parser.add_argument("--quick", action="store_true", help="401 thicknesses, 2 repeats (smoke test)")
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    if args.quick:
        args.thicknesses, args.repeats = 401, 2

    import bubbleoptics as bo
    from bubbleoptics.bandlimited import film_XYZ_bandlimited
    from bubbleoptics.colorimetry import DEFAULT_WAVELENGTHS_NM as WL

    load_before = _load()
    d = np.linspace(0.0, 20000.0, args.thicknesses)
    thin = d <= 2000.0  # the first interference orders, where the colours are saturated
    rows = []

    def reference(XYZ, ill):
        """The reference colours, and the exposure k that makes the brightest film of 0-1 um white
        (as study.stability and notebook 01 show them)."""
        return dict(XYZ=XYZ, exposure=1.0 / XYZ[d <= 1000.0, 1].max())

    def dE00(XYZ, ref, ill):
        """Per-thickness CIEDE2000 against *ref*, as reflected and after the reference's exposure."""
        return (delta_e00_XYZ(XYZ, ref["XYZ"], ill),
                delta_e00_XYZ(XYZ, ref["XYZ"], ill, exposure=ref["exposure"]))

    def record(method, n_bands, order, ill, theta_deg, XYZ, ref, seconds, note=""):
        t_med, t_min, t_max = seconds
        e, e_exp = dE00(XYZ, ref, ill)
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
                ns_per_colour_max=1e9 * t_max / d.size,
                note=note,
                exposure=float(ref["exposure"]),
                dE00_max_exposed=float(e_exp.max()),
                dE00_median_0_2um_exposed=float(np.median(e_exp[thin])),
            )
        )
        r = rows[-1]
        print(
            f"{method:36s} N={str(n_bands):>4s} L={str(order):>2s} {ill:3s} {theta_deg:4.0f}°  "
            f"median {r['dE00_median']:6.3f}  p95 {r['dE00_p95']:6.3f}  max {r['dE00_max']:6.3f} "
            f"(at {r['worst_thickness_nm']:7.0f} nm)  0-2um: {r['dE00_median_0_2um']:6.3f} {r['dE00_max_0_2um']:6.3f}  "
            f"{r['ns_per_colour']:6.0f} ns/colour (min {r['ns_per_colour_min']:.0f})",
            flush=True,
        )

    W1 = bo.spectral_weights(WL)
    for theta_deg in (0.0, 60.0):
        th = np.deg2rad(theta_deg)
        ref_xyz = bo.film_reflectance(WL, d[:, None], th) @ W1.T
        ref = reference(ref_xyz, "D65")
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

    # Illuminant E, non-dispersive film: the Gaussian CMF fit of Belcour & Barla (2017) and the lookup table
    WE = bo.spectral_weights(WL, illuminant=None)
    n_const = 1.33
    t0 = time.perf_counter()
    table = lut_table()
    t_table = time.perf_counter() - t0
    nodes, S = table
    tail = nodes >= 53200.0
    checked = check_lut(table, n_const)
    print(f"lookup table: {nodes.size} nodes every {LUT_STEP_NM:g} nm of OPD to {nodes[-1]:.0f} nm, built in "
          f"{t_table:.2f} s; S(0) = {np.array2string(S[0], precision=6)}; max |S| over OPD 53.2-64.8 um "
          f"{np.abs(S[tail]).max():.1e}; check against the direct 1 nm integration at table nodes, max |dXYZ| "
          + ", ".join(f"{k:g} deg: {a:.1e} (<= 2 um), {b:.1e} (<= 20 um)" for k, (a, b) in checked.items()),
          flush=True)
    bl_table = blender_like_table()
    bl_nodes, bl_S, bl_to_xyz = bl_table
    bl_S0_xyz = bl_S[0].real @ bl_to_xyz.T
    print(f"Blender-like table: {bl_nodes.size} complex entries every {BLENDER_STEP_NM:.3f} nm of OPD to "
          f"{bl_nodes[-1]:.0f} nm (value held beyond), series stopped after m = {BLENDER_TERMS}; S(0) in XYZ "
          f"{np.array2string(bl_S0_xyz, precision=6)}; held value in XYZ "
          f"{np.array2string(bl_S[-1].real @ bl_to_xyz.T, precision=5)}; |Re S - exact S| at its nodes, max "
          f"{np.abs(bl_S.real @ bl_to_xyz.T - lut_sensitivity(table, bl_nodes)).max():.1e}", flush=True)
    n_555 = float(bo.water_refractive_index(555.0))
    lut_note = (f"n=1.33; NumPy; exact 1 nm S(OPD) every {LUT_STEP_NM:g} nm to {nodes[-1] / 1000:g} um; "
                "linear interpolation")
    for theta_deg in (0.0, 60.0):
        th = np.deg2rad(theta_deg)
        ref_const = reference(bo.film_reflectance(WL, d[:, None], th, n_const) @ WE.T, "E")
        ref_water = reference(bo.film_reflectance(WL, d[:, None], th) @ WE.T, "E")
        bb = bb_film_XYZ(d, th, n_const)
        t = timed(lambda: bb_film_XYZ(d, th, n_const), args.repeats)
        record("gaussian_fit_BB2017", "", "", "E", theta_deg, bb, ref_const, t, "n=1.33; NumPy")
        record("gaussian_fit_vs_dispersive", "", "", "E", theta_deg, bb, ref_water, t,
               "n=1.33 against the water reference")
        wl, Wb = bo.band_spectral_weights(16, illuminant=None)
        pt = bo.film_reflectance(wl, d[:, None], th, n_const) @ Wb.T
        record("point", 16, "", "E", theta_deg, pt, ref_const, (float("nan"),) * 3, "n=1.33")
        ours = film_XYZ_bandlimited(d, th, 16, n_film=n_const, illuminant=None, order=3)
        record("bandlimited", 16, 3, "E", theta_deg, ours, ref_const, (float("nan"),) * 3, "n=1.33")
        lut = lut_film_XYZ(d, th, n_const, table)
        t = timed(lambda: lut_film_XYZ(d, th, n_const, table), args.repeats)
        record("lut_nondispersive", "", "", "E", theta_deg, lut, ref_const, t, lut_note)
        record("lut_nondispersive_vs_dispersive", "", "", "E", theta_deg, lut, ref_water, t,
               "n=1.33 against the water reference")
        record("lut_nondispersive_n555_vs_dispersive", "", "", "E", theta_deg, lut_film_XYZ(d, th, n_555, table),
               ref_water, t, f"n={n_555:.4f} (water at 555 nm) against the water reference")

        def blender_like(polar=False):
            return lut_film_XYZ(d, th, n_const, bl_table, n_terms=BLENDER_TERMS, hold_last=True, polar=polar)

        bl = blender_like()
        t = timed(blender_like, args.repeats)
        record("lut_blender_like", "", "", "E", theta_deg, bl, ref_const, t,
               f"n=1.33; NumPy; like Blender's table (rebuilt from its source): {bl_nodes.size} complex entries "
               f"every {BLENDER_STEP_NM:.1f} nm to {bl_nodes[-1] / 1000:.2f} um, last held; "
               f"m <= {BLENDER_TERMS}; RGB per-channel DC normalization")
        record("lut_blender_like_vs_dispersive", "", "", "E", theta_deg, bl, ref_water, t,
               "n=1.33 against the water reference")
        # Not a row: the earlier revision's interpolation in magnitude and unwrapped phase (module docstring)
        e_polar, e_polar_exp = dE00(blender_like(polar=True), ref_const, "E")
        print(f"{'  (magnitude/phase interpolation)':36s} {theta_deg:4.0f}°  median {np.median(e_polar):6.3f}  "
              f"max {e_polar.max():6.3f} (at {d[int(np.argmax(e_polar))]:7.0f} nm)  max exposed "
              f"{e_polar_exp.max():6.3f}", flush=True)

        def ours_water():
            return film_XYZ_bandlimited(d, th, 16, illuminant=None, order=3)

        record("bandlimited_water", 16, 3, "E", theta_deg, ours_water(), ref_water, timed(ours_water, args.repeats),
               "water against the water reference")

    write_csv(args.out, rows,
              provenance("benchmarks/bandlimited_colour.py", f"{d.size} thicknesses 0-20000 nm",
                         f"{args.repeats} timed runs a method (median, min, max); load average {load_before:.2f} "
                         f"before, {_load():.2f} after (shared machine; this process at niceness {os.nice(0)})",
                         "regenerate with: python benchmarks/bandlimited_colour.py"),
              float_format="{:.4g}")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
