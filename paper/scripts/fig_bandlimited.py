"""Figure: film colour from few spectral samples, against thickness, by method.

Run:  python paper/scripts/fig_bandlimited.py [--quick]
Computes with the bubbleoptics package and the approaches of :mod:`study.film_colour`
(the Gaussian CMF fit ``bb_film_XYZ`` and the lookup table ``lut_table`` / ``lut_film_XYZ``, as
``benchmarks/bandlimited_colour.py`` uses them); reads ``data/derived/bandlimited_colour.csv``
(written by that benchmark) only to check the curves against it; writes
``fig_bandlimited.pdf``/``.png``.

Every curve is the CIEDE2000 (:func:`study.delta_e00_XYZ` with the illuminant's
white, as the benchmark computes it) between a method's colour and the 1 nm reference, both
exposed so that the reference's brightest film of 0-1 µm is white (:func:`exposure`, the
benchmark's ``exposure``; the paper's one convention for film-colour differences, also that of
``benchmarks/stability.py`` and Fig. stability), against the thickness of a free-standing film in air, 0-20 µm,
unpolarized, CIE 1931 2° observer.  The per-thickness values of point sampling alias and are
very jagged, so every curve is drawn as its running maximum over a window of 0.2 µm: the
envelope of the worst case, whose peak is the maximum ΔE00 of the table (``dE00_max_exposed``).  Values
are floored at 1e-3 for display; dashed grey line: ΔE00 = 1, the target (with at most 16
spectral samples, within ΔE00 ≤ 1 of the 1 nm reference at every thickness up to 20 µm).

(a) θ = 0° and (b) θ = 60°, D65, water film (Daimon & Masumura 2007 dispersion): point sampling
at the centres of 16 bands of equal width over 360-780 nm; the band mean (R averaged over each
of the 16 bands, ``film_reflectance_band``); ours, ``film_XYZ_bandlimited`` with 8 and 16 bands
(order 3, the default).
(c) Illuminant E, the setting of the Gaussian fit, at 0° (solid) and 60° (dotted): the Gaussian
CMF fit of Belcour & Barla (2017) on a film of constant n = 1.33 against the n = 1.33
reference (the fit's own error); the lookup table of the exact 1 nm sensitivity with n = 1.33
(the approach attributed to Blender, rebuilt; its own error is < 0.002) against the dispersive
water reference (the cost of ignoring dispersion); ours (16 bands, water) against the water
reference.

Prints each curve's maximum and, in full mode (the benchmark's 4001 thicknesses), stops with an
error unless it agrees with the CSV's ``dE00_max_exposed`` for the same method within 5 %.  Quick mode:
401 thicknesses, no check (the grid differs).
"""

import sys

import numpy as np

import paths
import style
from study import delta_e00_XYZ, read_commented_csv
from study.film_colour import bb_film_XYZ, lut_film_XYZ, lut_table

CSV = paths.DERIVED / "bandlimited_colour.csv"
WINDOW_NM = 200.0  # running maximum over this window of thickness
EXPOSURE_MAX_NM = 1000.0  # the exposure whitens the brightest film up to this thickness (as the benchmark)
FLOOR = 1e-3
TOLERANCE = 0.05  # relative, curve maximum against the CSV's dE00_max (full mode)
N_CONST = 1.33
ANGLES = (0.0, 60.0)
# style cycle (Okabe-Ito): 0 blue, 1 vermillion, 2 green, 3 reddish purple, 4 orange, 5 sky blue
COLOURS = {"point": 1, "band_mean": 4, "ours8": 5, "ours16": 0, "gaussian": 3, "lut": 2}


def read_csv(path):
    """Rows of a benchmark CSV as dicts, its '#' comment lines dropped."""
    if not path.exists():
        raise SystemExit(f"{path} is missing: run python benchmarks/bandlimited_colour.py first")
    return read_commented_csv(path)[1]


def csv_max(rows, method, theta_deg, illuminant, n_bands="", order=""):
    """The CSV's dE00_max_exposed of one method, or None when it has no such row."""
    for r in rows:
        if (r["method"], r["illuminant"], float(r["theta_deg"]), r["n_bands"], r["order"]) == (
                method, illuminant, theta_deg, str(n_bands), str(order)):
            return float(r["dE00_max_exposed"])
    return None


def envelope(d, e, window=WINDOW_NM):
    """Running maximum of *e* (on the uniform grid *d*) over a centred window of *window* in d."""
    half = max(int(round(window / 2 / (d[1] - d[0]))), 0)
    padded = np.pad(e, half, constant_values=-np.inf)
    return np.lib.stride_tricks.sliding_window_view(padded, 2 * half + 1).max(axis=1)


def exposure(d, XYZ):
    """The exposure that makes the brightest reference film up to EXPOSURE_MAX_NM white: 1 / its largest Y."""
    return 1.0 / XYZ[d <= EXPOSURE_MAX_NM, 1].max()


def delta_e(XYZ, ref, d, illuminant):
    """CIEDE2000 per thickness between *XYZ* and the reference *ref*, both exposed by :func:`exposure`."""
    return delta_e00_XYZ(XYZ, ref, illuminant, exposure=exposure(d, ref))


def compute(d):
    """{(panel, theta_deg, key): (ΔE00 per thickness, (CSV method, illuminant, n_bands, order))}."""
    import bubbleoptics as bo
    from bubbleoptics.bandlimited import film_XYZ_bandlimited
    from bubbleoptics.colorimetry import DEFAULT_WAVELENGTHS_NM as WL

    out = {}
    W1, WE = bo.spectral_weights(WL), bo.spectral_weights(WL, illuminant=None)
    wl16, W16 = bo.band_spectral_weights(16)
    table = lut_table()
    for theta_deg in ANGLES:
        th = np.deg2rad(theta_deg)
        # (a), (b): D65, water
        ref = bo.film_reflectance(WL, d[:, None], th) @ W1.T
        panel = "a" if theta_deg == 0.0 else "b"
        point = bo.film_reflectance(wl16, d[:, None], th) @ W16.T
        out[panel, theta_deg, "point"] = (delta_e(point, ref, d, "D65"), ("point", "D65", 16, ""))
        band_mean = bo.film_reflectance_band(16, d, th) @ W16.T
        out[panel, theta_deg, "band_mean"] = (delta_e(band_mean, ref, d, "D65"), ("band_mean", "D65", 16, 6))
        for N in (8, 16):
            ours = film_XYZ_bandlimited(d, th, N, order=3)
            out[panel, theta_deg, f"ours{N}"] = (delta_e(ours, ref, d, "D65"), ("bandlimited", "D65", N, 3))
        # (c): illuminant E
        ref_const = bo.film_reflectance(WL, d[:, None], th, N_CONST) @ WE.T
        ref_water = bo.film_reflectance(WL, d[:, None], th) @ WE.T
        out["c", theta_deg, "gaussian"] = (delta_e(bb_film_XYZ(d, th, N_CONST), ref_const, d, "E"),
                                           ("gaussian_fit_BB2017", "E", "", ""))
        out["c", theta_deg, "lut"] = (delta_e(lut_film_XYZ(d, th, N_CONST, table), ref_water, d, "E"),
                                      ("lut_nondispersive_vs_dispersive", "E", "", ""))
        ours_water = film_XYZ_bandlimited(d, th, 16, illuminant=None, order=3)
        out["c", theta_deg, "ours16"] = (delta_e(ours_water, ref_water, d, "E"), ("bandlimited_water", "E", 16, 3))
    return out


LABELS = {
    "point": "point sampling, $N = 16$",
    "band_mean": "band mean, $N = 16$",
    "ours8": "ours, $N = 8$",
    "ours16": "ours, $N = 16$",
    "gaussian": "Gaussian CMF fit (Belcour-Barla), $n = 1.33$",
    "lut": "1 nm table, $n = 1.33$, against water",
}


def main(argv=None):
    args = paths.parse_args(__doc__.splitlines()[0], argv)
    rows = read_csv(CSV)
    d = np.linspace(0.0, 20000.0, 401 if args.quick else 4001)
    curves = compute(d)

    fig = style.figure(width=style.PAGE_WIDTH, height=2.6)
    axes = dict(zip("abc", fig.subplots(1, 3, sharey=True)))
    colors = [c["color"] for c in style.matplotlib.rcParams["axes.prop_cycle"]]
    mismatches = []
    # panel by panel, 0 deg first; within one panel and angle the order of compute() (stable sort)
    for (panel, theta_deg, key), (e, (method, ill, n_bands, order)) in sorted(curves.items(), key=lambda kv: kv[0][:2]):
        ax = axes[panel]
        dotted = panel == "c" and theta_deg != 0.0
        ax.semilogy(d / 1000, np.maximum(envelope(d, e), FLOOR), color=colors[COLOURS[key]],
                    ls=":" if dotted else "-", lw=0.9 if dotted else 1.0,
                    label=None if dotted else LABELS[key] + (", water" if key == "ours16" and panel == "c" else ""))
        peak = float(e.max())
        ref_max = csv_max(rows, method, theta_deg, ill, n_bands, order)
        agree = ref_max is not None and abs(peak - ref_max) <= TOLERANCE * ref_max
        print(f"({panel}) {theta_deg:2.0f} deg {ill:3s} {LABELS[key].replace('$', ''):45s} max dE00 {peak:7.4g} "
              f"at {d[int(np.argmax(e))] / 1000:6.3f} um  (CSV {method} {ref_max if ref_max is not None else 'n/a'})")
        if not args.quick and not agree:
            mismatches.append(f"({panel}) {theta_deg:g} deg {method} N={n_bands}: {peak:.4g} vs CSV {ref_max}")
    if mismatches:
        raise SystemExit("fig_bandlimited: curve maxima disagree with " + str(CSV) + " by more than "
                         f"{TOLERANCE:.0%} (stale CSV? rerun benchmarks/bandlimited_colour.py):\n  "
                         + "\n  ".join(mismatches))

    titles = {"a": r"(a) $\theta = 0^\circ$, D65, water", "b": r"(b) $\theta = 60^\circ$, D65, water",
              "c": r"(c) illuminant E; $0^\circ$ solid, $60^\circ$ dotted"}
    for panel, ax in axes.items():
        ax.axhline(1.0, color="0.45", ls="--", lw=0.6, zorder=1)
        ax.set_xlim(0.0, 20.0)
        ax.set_xlabel(r"film thickness $d$ ($\mu$m)")
        ax.set_title(titles[panel], loc="left")
        ax.grid(True, which="major")
    axes["a"].set_ylim(FLOOR * 0.8, 600.0)  # head room for the legends
    axes["a"].set_yticks(10.0 ** np.arange(-3, 3))
    axes["a"].set_ylabel(r"$\Delta E_{00}$ against 1 nm, exposed" + "\n" + r"(0.2 $\mu$m running max.)")
    legend = dict(loc="upper right", fontsize=7, handlelength=1.5, columnspacing=0.8, handletextpad=0.4,
                  borderaxespad=0.2)
    axes["a"].legend(ncol=2, **legend)
    axes["c"].legend(ncol=1, **legend)
    axes["a"].text(19.6, 0.85, r"$\Delta E_{00} = 1$", fontsize=7, color="0.35", ha="right", va="top")
    for path in style.savefig(fig, "fig_bandlimited"):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
