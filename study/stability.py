"""Numerical stress tests of bubbleoptics, as data: grazing incidence and thick-film aliasing.

The analysis of ``benchmarks/stability.py`` (which writes ``data/derived/stability_grazing.csv``
and ``stability_aliasing.csv``), of notebook 05 (which shows it, and computes it live in quick
mode) and of ``paper/scripts/fig_stability.py``.

1. **Grazing incidence** (:func:`grazing_table`).  theta = pi/2 - 10**-u for u in [0, 8], five
   films at 550 nm (:data:`GRAZING_FILMS`), s, p and unpolarized light.  (R, T) from

   * ``bubbleoptics.film_rt`` (cancellation-free formulation, see ``bubbleoptics/kernels.py``),
   * ``tmm.coh_tmm`` (Byrnes; angles through ``arcsin`` and ``cos``),
   * :func:`naive_film_rt`, the textbook float64 Airy sum with ``cos = sqrt(1 - sin^2)``,

   against ``film_rt_mp`` of :mod:`study.reference` (the textbook formulas at 40
   digits on the exact float64 inputs).  Errors are formed in mpmath, so they are exact to the
   digits shown.

2. **Thick-film aliasing** (:func:`aliasing_table`).  The colour of a free-standing water film,
   0-20 um, at normal incidence, from N = 4, 8, 16, 32, 81 band centres (point samples of R
   weighted by ``band_spectral_weights(N)``), against the 1 nm reference (the computation inside
   ``bubbleoptics.film_color``), as CIE XYZ and CIEDE2000 after a fixed exposure
   (:func:`study.delta_e00_XYZ`).  Aliasing sets in when a wavelength with visual
   weight sees fringes spaced by less than a band, lambda^2 / (2 n d cos theta_t) < 420 nm / N;
   since the spacing grows as lambda^2, the blue end of the spectrum (~400 nm) aliases first.
   If ``bubbleoptics.film_color_bandlimited`` exists it is included as one more method (its XYZ,
   default settings: polynomial order 3).
"""

from __future__ import annotations

import inspect
import math
import time
import warnings

import numpy as np

from .metrics import delta_e00_XYZ

__all__ = [
    "WAVELENGTH_NM", "POLARIZATIONS", "METHODS", "GRAZING_FILMS", "GRAZING_COLUMNS", "BAND_COUNTS",
    "ONSET_DE00", "ONSET_WINDOW_NM", "ALIASING_COLUMNS",
    "grazing_films", "naive_film_rt", "grazing_angles", "grazing_table", "grazing_summary",
    "reference_XYZ", "point_sampled_XYZ", "bandlimited_XYZ", "exposure_factor", "predicted_onset_nm",
    "running_median", "measured_onset_nm", "aliasing_table",
]

WAVELENGTH_NM = 550.0
POLARIZATIONS = ("s", "p", "unpolarized")
METHODS = ("bubbleoptics", "tmm", "naive")

#: The films of the grazing-incidence test (wavelength 550 nm).  ``n_film`` of water is set at
#: import from bubbleoptics' Daimon & Masumura (2007) index at 550 nm.
GRAZING_FILMS = {
    "water": dict(label="water 500 nm, free-standing", n_film=None, n_outside=1.0, n_inside=None,
                  thickness_nm=500.0),
    "matched": dict(label="n = 1.5, 500 nm, on n = 1.5", n_film=1.5, n_outside=1.0, n_inside=1.5,
                    thickness_nm=500.0),
    "absorbing": dict(label="n = 1.5 + 0.05i, 500 nm, free-standing", n_film=1.5 + 0.05j, n_outside=1.0,
                      n_inside=None, thickness_nm=500.0),
    "tir_back": dict(label="glass | n = 1.6, 500 nm | air (TIR at back)", n_film=1.6, n_outside=1.52,
                     n_inside=1.0, thickness_nm=500.0),
    "ftir": dict(label="glass | 200 nm air gap | glass (frustrated TIR)", n_film=1.0, n_outside=1.52,
                 n_inside=1.52, thickness_nm=200.0),
}

#: Band counts of the aliasing test, and the wavelength range the bands cover (nm).
BAND_COUNTS = (4, 8, 16, 32, 81)
BAND_LO_NM, BAND_HI_NM = 360.0, 780.0
#: ΔE00 above which (as a 1 µm running median) a point-sampled colour counts as aliased.
ONSET_DE00 = 5.0
ONSET_WINDOW_NM = 1000.0

#: Columns of the two tables (the CSV files' column order).
GRAZING_COLUMNS = ("film", "polarization", "u", "theta", "cos_theta", "method", "R", "T", "R_ref", "T_ref",
                   "abs_err_R", "rel_err_R", "abs_err_T", "rel_err_T")
ALIASING_COLUMNS = ("thickness_nm", "method", "n_bands", "theta", "X", "Y", "Z", "dE00", "exposure",
                    "onset_pred_400_nm", "onset_pred_550_nm", "onset_measured_nm")


def _water_index():
    import bubbleoptics as bo

    return float(bo.water_refractive_index(WAVELENGTH_NM))


def grazing_films():
    """GRAZING_FILMS with water's index filled in."""
    films = {k: dict(v) for k, v in GRAZING_FILMS.items()}
    films["water"]["n_film"] = _water_index()
    return films


# ------------------------------------------------------------------------------------------
# 1. Grazing incidence
# ------------------------------------------------------------------------------------------
def naive_film_rt(wavelength_nm, thickness_nm, theta, n_film, n_outside=1.0, n_inside=None,
                  polarization="unpolarized"):
    """(R, T) of one film by the textbook formulas in float64, as most codes write them.

    ``cos(theta_j) = sqrt(1 - sin(theta_j)**2)`` with ``sin(theta_j) = n0 sin(theta0) / n_j``
    (complex square root, principal branch: decaying for absorbing media and beyond the critical
    angle), Fresnel coefficients r_ij, t_ij in the convention of Byrnes (arXiv:1603.02720),
    the Airy sums r = (r01 + r12 e) / (1 + r01 r12 e), t = t01 t12 e^{i beta} / (1 + r01 r12 e)
    with e = exp(2 i beta), beta = 2 pi d n1 cos(theta_1) / lambda, and
    T_s = Re(n2 cos2) / (n0 cos0) |t|^2, T_p = Re(n2 conj(cos2)) / (n0 cos0) |t|^2.
    Broadcasts over *theta* (and the other real arguments).
    """
    n0 = float(n_outside)
    n1 = np.asarray(n_film, dtype=complex)
    n2 = np.asarray(n0 if n_inside is None else n_inside, dtype=complex)
    theta = np.asarray(theta, dtype=float)
    cos0 = np.cos(theta)
    sin0 = np.sin(theta)

    def cosine(n):
        sin_j = n0 * sin0 / n
        return np.sqrt(1.0 - sin_j * sin_j + 0j)

    cos1, cos2 = cosine(n1), cosine(n2)
    beta = 2.0 * np.pi * thickness_nm * n1 * cos1 / wavelength_nm
    e = np.exp(2j * beta)

    def one(pol):
        if pol == "s":
            d01 = n0 * cos0 + n1 * cos1
            r01, t01 = (n0 * cos0 - n1 * cos1) / d01, 2 * n0 * cos0 / d01
            d12 = n1 * cos1 + n2 * cos2
            r12, t12 = (n1 * cos1 - n2 * cos2) / d12, 2 * n1 * cos1 / d12
        else:
            d01 = n1 * cos0 + n0 * cos1
            r01, t01 = (n1 * cos0 - n0 * cos1) / d01, 2 * n0 * cos0 / d01
            d12 = n2 * cos1 + n1 * cos2
            r12, t12 = (n2 * cos1 - n1 * cos2) / d12, 2 * n1 * cos1 / d12
        den = 1.0 + r01 * r12 * e
        r = (r01 + r12 * e) / den
        t = t01 * t12 * np.exp(1j * beta) / den
        exit_factor = (n2 * cos2).real if pol == "s" else (n2 * np.conj(cos2)).real
        return np.abs(r) ** 2, exit_factor / (n0 * cos0) * np.abs(t) ** 2

    if polarization == "unpolarized":
        (rs, ts), (rp, tp) = one("s"), one("p")
        return 0.5 * (rs + rp), 0.5 * (ts + tp)
    return one(polarization)


def grazing_angles(n_u):
    """u values (n_u of them, 0 to 8) and theta = pi/2 - 10**-u (float64)."""
    u = np.linspace(0.0, 8.0, n_u)
    return u, np.pi / 2 - 10.0**-u


def grazing_table(n_u=81, films=None, polarizations=POLARIZATIONS, reference=None):
    """Rows (dicts) of the grazing-incidence test: one per film, polarization, angle and method.

    *reference*: the module of references (default :mod:`study.reference`, which
    needs ``mpmath`` and ``tmm``: the ``test`` extra); ``film_rt_mp`` is the truth, ``tmm_rt``
    one of the methods compared.

    Errors are evaluated in mpmath from the exact float64 results: ``abs_err_X = |X - X_ref|``,
    ``rel_err_X = abs_err_X / X_ref`` (NaN where X_ref = 0, e.g. T beyond total internal
    reflection).  Also returns the wall time spent per method (seconds).
    """
    import mpmath

    import bubbleoptics as bo

    if reference is None:
        from . import reference as ref  # needs the test extra (mpmath, tmm)
    else:
        ref = reference
    films = films or grazing_films()
    u_values, thetas = grazing_angles(n_u)
    rows = []
    timings = dict.fromkeys(METHODS + ("mpmath",), 0.0)
    for key, film in films.items():
        args = (film["n_film"], film["n_outside"], film["n_inside"])
        for pol in polarizations:
            t0 = time.perf_counter()
            R_b, T_b = bo.film_rt(WAVELENGTH_NM, film["thickness_nm"], thetas, *args, polarization=pol)
            t1 = time.perf_counter()
            R_n, T_n = naive_film_rt(WAVELENGTH_NM, film["thickness_nm"], thetas, *args, polarization=pol)
            t2 = time.perf_counter()
            timings["bubbleoptics"] += t1 - t0
            timings["naive"] += t2 - t1
            for i, (u, theta) in enumerate(zip(u_values, thetas)):
                t0 = time.perf_counter()
                R_ref, T_ref = ref.film_rt_mp(WAVELENGTH_NM, film["thickness_nm"], float(theta), *args,
                                              polarization=pol)
                t1 = time.perf_counter()
                try:
                    R_t, T_t = ref.tmm_rt(WAVELENGTH_NM, film["thickness_nm"], float(theta), *args,
                                          polarization=pol)
                except Exception:  # tmm refuses some inputs; record as missing
                    R_t, T_t = math.nan, math.nan
                t2 = time.perf_counter()
                timings["mpmath"] += t1 - t0
                timings["tmm"] += t2 - t1
                with mpmath.workdps(40):
                    cos_theta = float(mpmath.cos(mpmath.mpf(float(theta))))
                results = {"bubbleoptics": (R_b[i], T_b[i]), "tmm": (R_t, T_t), "naive": (R_n[i], T_n[i])}
                for method, (R, T) in results.items():
                    row = dict(film=key, polarization=pol, u=float(u), theta=float(theta),
                               cos_theta=cos_theta, method=method, R=float(R), T=float(T),
                               R_ref=float(R_ref), T_ref=float(T_ref))
                    for name, x, x_ref in (("R", R, R_ref), ("T", T, T_ref)):
                        if not math.isfinite(float(x)):
                            row[f"abs_err_{name}"] = row[f"rel_err_{name}"] = math.nan
                            continue
                        with mpmath.workdps(40):
                            err = abs(mpmath.mpf(float(x)) - x_ref)
                            row[f"abs_err_{name}"] = float(err)
                            row[f"rel_err_{name}"] = float(err / abs(x_ref)) if x_ref != 0 else math.nan
                    rows.append(row)
    return rows, timings


# ------------------------------------------------------------------------------------------
# 2. Thick-film aliasing
# ------------------------------------------------------------------------------------------
def reference_XYZ(thickness_nm, theta=0.0):
    """XYZ (Y = 1 white) of a free-standing water film from 1 nm spectra, 360-780 nm: the
    computation inside ``bubbleoptics.film_color``, stopped before the display encoding."""
    import bubbleoptics as bo
    from bubbleoptics.colorimetry import DEFAULT_WAVELENGTHS_NM

    d = np.asarray(thickness_nm, dtype=float)
    R = bo.film_reflectance(DEFAULT_WAVELENGTHS_NM, d[:, None], theta)
    return bo.spectrum_to_XYZ(R, DEFAULT_WAVELENGTHS_NM)


def point_sampled_XYZ(thickness_nm, n_bands, theta=0.0):
    """XYZ from R at the N band centres only, weighted by ``band_spectral_weights(N)``: what a
    spectral renderer with N point-sampled bands computes (the tracer's transport)."""
    import bubbleoptics as bo

    centres, W = bo.band_spectral_weights(n_bands, lo_nm=BAND_LO_NM, hi_nm=BAND_HI_NM)
    d = np.asarray(thickness_nm, dtype=float)
    return bo.film_reflectance(centres, d[:, None], theta) @ W.T


def bandlimited_XYZ(thickness_nm, n_bands, theta=0.0):
    """XYZ of the band-limited method (``bubbleoptics.film_color_bandlimited``), None if the
    package does not have it.

    Uses ``bubbleoptics.bandlimited.film_XYZ_bandlimited`` (the XYZ behind that function, with
    its default settings) when present; otherwise calls ``film_color_bandlimited`` with the
    thickness, angle and band count, unclipped, and decodes its display sRGB back to XYZ.
    """
    import colour

    import bubbleoptics as bo

    func = getattr(bo, "film_color_bandlimited", None)
    if func is None:
        return None
    d = np.asarray(thickness_nm, dtype=float)
    xyz_func = getattr(getattr(bo, "bandlimited", None), "film_XYZ_bandlimited", None)
    if xyz_func is not None:
        return np.asarray(xyz_func(d, theta=theta, n_bands=n_bands), dtype=float)
    params = inspect.signature(func).parameters
    if "n_bands" not in params:
        raise TypeError("film_color_bandlimited has no n_bands parameter")
    kwargs = dict(n_bands=n_bands, theta=theta)
    if "gamut" in params:
        kwargs["gamut"] = "none"
    rgb = np.asarray(func(d, **kwargs), dtype=float)
    return colour.sRGB_to_XYZ(rgb, apply_cctf_decoding=True)


def exposure_factor(theta=0.0):
    """Exposure k = 1 / max Y over 0-1000 nm at 1 nm steps (the brightest, first-order film),
    as in notebook 01: colours are compared as a camera exposed for the brightest film sees them."""
    Y = reference_XYZ(np.arange(0.0, 1000.5, 1.0), theta)[:, 1]
    return 1.0 / Y.max()


def predicted_onset_nm(n_bands, wavelength_nm, theta=0.0):
    """Thickness at which the fringe spacing in wavelength, lambda^2 / (2 n d cos theta_t),
    equals the band width (hi - lo) / N, at *wavelength_nm* (water film, outside n = 1):
    :func:`bubbleoptics.point_sampling_limit_nm`, the limit the tracer's ``spectral_method="auto"``
    uses."""
    import bubbleoptics as bo

    assert (BAND_LO_NM, BAND_HI_NM) == bo.bandlimited.BAND_RANGE_NM
    return float(bo.point_sampling_limit_nm(n_bands, wavelength_nm, theta))


def running_median(thickness_nm, values, window_nm=ONSET_WINDOW_NM):
    """Median of *values* over the thickness window [d - w/2, d + w/2] centred on each d
    (truncated at the ends of the range)."""
    d = np.asarray(thickness_nm, dtype=float)
    v = np.asarray(values, dtype=float)
    lo = np.searchsorted(d, d - window_nm / 2, side="left")
    hi = np.searchsorted(d, d + window_nm / 2, side="right")
    return np.array([np.median(v[a:b]) for a, b in zip(lo, hi)])


def measured_onset_nm(thickness_nm, dE, threshold=ONSET_DE00, window_nm=ONSET_WINDOW_NM):
    """First thickness at which the running median of ΔE00 (over *window_nm* centred on it)
    exceeds *threshold*: a clearly visible difference, not an isolated spike.  0 means wrong
    from the thinnest films on; NaN means never within the range."""
    d = np.asarray(thickness_nm, dtype=float)
    hit = np.flatnonzero(running_median(d, dE, window_nm) > threshold)
    return float(d[hit[0]]) if hit.size else math.nan


def aliasing_table(thickness_nm, band_counts=BAND_COUNTS, theta=0.0):
    """Rows (dicts) of the aliasing test: per thickness and method, XYZ and ΔE00 against the
    1 nm reference, with the predicted (400 nm and 550 nm) and measured onsets per method.
    Also returns the wall time spent per method (seconds)."""
    d = np.asarray(thickness_nm, dtype=float)
    timings = {}
    t0 = time.perf_counter()
    XYZ_ref = reference_XYZ(d, theta)
    timings["reference_1nm"] = time.perf_counter() - t0
    k = exposure_factor(theta)
    series = [("reference_1nm", 421, XYZ_ref)]
    for N in band_counts:
        t0 = time.perf_counter()
        series.append(("point", N, point_sampled_XYZ(d, N, theta)))
        timings[f"point_{N}"] = time.perf_counter() - t0
    for N in band_counts:
        t0 = time.perf_counter()
        try:
            XYZ = bandlimited_XYZ(d, N, theta)
        except (TypeError, ValueError) as exc:  # a newer function than this study: do not guess further
            warnings.warn(f"film_color_bandlimited could not be called as expected, skipped: {exc}")
            XYZ = None
        if XYZ is None:
            break
        series.append(("bandlimited", N, XYZ))
        timings[f"bandlimited_{N}"] = time.perf_counter() - t0
    rows = []
    for method, N, XYZ in series:
        dE = delta_e00_XYZ(XYZ_ref, XYZ, exposure=k)
        onset = math.nan if method == "reference_1nm" else measured_onset_nm(d, dE)
        p400, p550 = (predicted_onset_nm(N, lam, theta) for lam in (400.0, 550.0))
        for i in range(d.size):
            rows.append(dict(thickness_nm=float(d[i]), method=method, n_bands=int(N), theta=float(theta),
                             X=float(XYZ[i, 0]), Y=float(XYZ[i, 1]), Z=float(XYZ[i, 2]), dE00=float(dE[i]),
                             exposure=float(k), onset_pred_400_nm=float(p400), onset_pred_550_nm=float(p550),
                             onset_measured_nm=onset))
    return rows, timings


def grazing_summary(rows, polarization="unpolarized"):
    """{method: (worst relative error of T over films with T > 0, worst absolute error of R)}."""
    out = {}
    for method in METHODS:
        sel = [r for r in rows if r["method"] == method and r["polarization"] == polarization]
        rel_T = [r["rel_err_T"] for r in sel if r["T_ref"] > 0]
        abs_R = [r["abs_err_R"] for r in sel]
        out[method] = (float(np.nanmax(rel_T)) if rel_T else math.nan, float(np.nanmax(abs_R)))
    return out
