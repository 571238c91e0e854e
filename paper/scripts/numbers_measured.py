"""The numbers of the measurement comparison, a plug-in of make_numbers.py.

* ``measured``: ``data/measured/optifik_comparison.csv`` (``python -m study.measured``): the TTAB
  film of Ziapkoff et al. (2026) against the exact optics: how many spectra, the agreement with
  the authors' thickness from 200 to 800 nm (largest and median relative difference), the RMS
  residual in absolute reflectance, and the two ranges where it fails (order 0, the thick spectra);
* ``measuredthinning``: ``data/measured/optifik_thinning.csv``: the fitted thinning-rate exponent
  β (its profile interval in the CSV is resolved only to a 0.05 grid starting at 1.05, so not quoted), and the log-RMS of the laws with β = 3 and 5/2 against the free fit.

* ``measuredbubble``: ``data/measured/oospectro_bubble_thinning.csv``: a bubble's apex thinning
  (the thicknesses stated in the oospectro repository, ``oospectro_bubble_stated_thickness.csv``)
  fitted by the apex equation of this project's rigid-drainage model with evaporation,
  dh/dt = -c h^3 - q_e (c = ρg/(6μR)), and by its parts; written by this module run as a script
  (``python paper/scripts/numbers_measured.py``, :func:`write_bubble_fits`, seconds), read back by
  the plug-in and by ``fig_measured.py``;
* ``measuredbubbleoptics``: ``data/measured/oospectro_bubble_comparison.csv`` (``--spectra DIR``,
  :func:`write_bubble_comparison`, half a minute; the spectra are not in this repository): the
  bubble's spectra against the exact optics as the optifik film's, the agreement with the stated
  thickness from 200 nm up and how many of all the spectra before index 75000 fit a film thinner
  than 150 nm (failures: every stated thickness there is above 390 nm).

Bounds are rounded outward (``MeasAgreeMaxPct`` and ``MeasRmsMax`` up, ``MeasThinMinPct``/``MeasThinMaxPct``
away from zero; :func:`macros.up_to`, :func:`macros.at_least`), so that "within X %", "at most X" and
"X–Y % thinner" stay true.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

from macros import at_least, date_of, machine_of, read_commented_csv, significant, up_to


def _up(x, digits=1):
    return up_to(float(x), decimals=digits)


def _down(x, digits=1):
    return at_least(float(x), decimals=digits)


#: The stated thicknesses split into the first order (below), the agreement range and thick films (from).
THIN_BELOW_NM = 200
THICK_FROM_NM = 800


def comparison(dirs):
    notes, rows = read_commented_csv(dirs["data"] / "measured" / "optifik_comparison.csv")
    st = [r for r in rows if r["stated_nm"]]
    h = np.array([float(r["stated_nm"]) for r in st])
    rel = np.array([float(r["fit_nm"]) / float(r["stated_nm"]) - 1 for r in st])
    rms = np.array([float(r["rms_fit"]) for r in st])
    good = (h >= THIN_BELOW_NM) & (h < THICK_FROM_NM)
    thin = h < THIN_BELOW_NM
    thick = h >= THICK_FROM_NM
    from study.measured import FIT_BAND_NM

    return {
        "MeasThinBelowNm": str(THIN_BELOW_NM),
        "MeasThickFromNm": str(THICK_FROM_NM),
        "MeasBandLowNm": f"{FIT_BAND_NM[0]:g}",
        "MeasBandHighNm": f"{FIT_BAND_NM[1]:g}",
        "MeasDate": date_of(notes),
        "MeasMachine": machine_of(notes),
        "MeasSpectra": str(len(rows)),
        "MeasStated": str(len(st)),
        "MeasAgreeN": str(int(good.sum())),
        "MeasAgreeMaxPct": _up(100 * np.max(np.abs(rel[good]))),
        "MeasAgreeMedianPct": significant(100 * np.median(rel[good]), 1, 2),
        "MeasRmsMedian": significant(float(np.median(rms[good])), 2),
        "MeasRmsMax": _up(float(np.max(rms[good])), 3),
        "MeasThinN": str(int(thin.sum())),
        "MeasThinMinPct": _down(100 * np.min(-rel[thin]), 0),
        "MeasThinMaxPct": _up(100 * np.max(-rel[thin]), 0),
        "MeasThickN": str(int(thick.sum())),
        "MeasThickFailN": str(int(np.sum(np.abs(rel[thick]) > 0.1))),
    }


COMPARISON_MACROS = ["MeasThinBelowNm", "MeasThickFromNm", "MeasBandLowNm", "MeasBandHighNm", "MeasDate", "MeasMachine", "MeasSpectra", "MeasStated", "MeasAgreeN", "MeasAgreeMaxPct",
                     "MeasAgreeMedianPct", "MeasRmsMedian", "MeasRmsMax", "MeasThinN", "MeasThinMinPct",
                     "MeasThinMaxPct", "MeasThickN", "MeasThickFailN"]


def thinning(dirs):
    _, rows = read_commented_csv(dirs["data"] / "measured" / "optifik_thinning.csv")
    out = {}
    for source, key in (("stated", "Stated"), ("fitted", "Fitted")):
        mine = {r["law"]: r for r in rows if r["source"] == source}
        free = mine["free"]
        out[f"MeasBeta{key}"] = significant(float(free["beta"]), 2)
        out[f"MeasRmsLog{key}"] = significant(float(free["rms_log"]), 2)
        for law, r in mine.items():
            if law.startswith("rigid"):
                out[f"MeasRmsLogRigid{key}"] = significant(float(r["rms_log"]), 2)
            elif law.startswith("marginal"):
                out[f"MeasRmsLogMarginal{key}"] = significant(float(r["rms_log"]), 2)
        out[f"MeasThinPoints{key}"] = str(int(free["n_points"]))
    return out


THINNING_MACROS = [f"{m}{k}" for k in ("Stated", "Fitted")
                   for m in ("MeasBeta", "MeasRmsLog", "MeasRmsLogRigid", "MeasRmsLogMarginal", "MeasThinPoints")]

# ---------------------------------------------------------------- a bubble's apex (oospectro)
#: The stated thicknesses of the bubble series (transcribed; provenance in its header and README).
BUBBLE_STATED = "oospectro_bubble_stated_thickness.csv"
#: The fits written by :func:`write_bubble_fits` and the curves drawn from them.
BUBBLE_FITS = "oospectro_bubble_thinning.csv"
BUBBLE_CURVES = "oospectro_bubble_curves.csv"
#: The numbers in the names of all the series' files (a listing, for the spacing of the index).
BUBBLE_FILE_INDEX = "oospectro_bubble_file_index.csv"
#: The TTAB concentration in multiples of the critical micelle concentration: the source's folder
#: name, ``20150611_Bulle6_TTAB10cmc``.
BUBBLE_CMC_MULTIPLE = 10
#: The confidence level of the q_e interval (F test on the profile of the residual).
BUBBLE_LEVEL = 0.95
#: The power of ten in which the fitted evaporation rate q_e is printed (MeasBubQe x 10^QE_EXPONENT m/s).
QE_EXPONENT = -8
#: Seconds per unit of the file-name index: not stated by the source; consecutive files differ by
#: 36-51 units (median 40), as a millisecond clock read at about 25 spectra a second would.
BUBBLE_TIME_UNIT_S = 1e-3
#: The laws fitted: name -> (rate exponent of the drainage term or None for no drainage,
#: evaporation fitted).  dh/dt = -c h^beta - q_e, h1 = h(t1) fitted too.
BUBBLE_LAWS = {
    "rigid drainage + evaporation": (3.0, True),
    "t^-2/3 drainage + evaporation": (2.5, True),
    "rigid drainage only": (3.0, False),
    "evaporation only": (None, True),
}
#: The profile grid of q_e for its interval (rigid drainage + evaporation), relative to the best q_e.
_Q_GRID = np.linspace(0.8, 1.2, 81)


def load_bubble(path):
    """``(t_s, h_m)`` of the bubble series: times from the file-name index (:data:`BUBBLE_TIME_UNIT_S`),
    thicknesses in metres, in the order of time."""
    _, rows = read_commented_csv(path)
    t = np.array([float(r["time_index"]) for r in rows]) * BUBBLE_TIME_UNIT_S
    h = np.array([float(r["stated_nm"]) for r in rows]) * 1e-9
    order = np.argsort(t)
    return t[order], h[order]


def apex_thinning(t, h1, c, beta, q):
    """h(t) of dh/dt = -c h^beta - q from h(t[0]) = h1 (SI units; *beta* None: no drainage term).
    Closed forms for the parts, :func:`scipy.integrate.solve_ivp` (LSODA) for the sum; a film that
    reaches zero stays at 1e-12 m."""
    t = np.asarray(t, dtype=float)
    s = t - t[0]
    if beta is None:
        return np.maximum(h1 - q * s, 1e-12)
    if q == 0:
        return h1 * (1 + (beta - 1) * c * h1 ** (beta - 1) * s) ** (-1 / (beta - 1))
    from scipy.integrate import solve_ivp

    sol = solve_ivp(lambda _, y: -c * np.maximum(y, 1e-12) ** beta - q, (t[0], t[-1]), [h1], t_eval=t,
                    method="LSODA", rtol=1e-10, atol=1e-15)
    y = sol.y[0]
    return np.maximum(np.concatenate([y, np.full(t.size - y.size, 1e-12)]), 1e-12)


def fit_apex_law(t, h, beta, evaporation, q=None, start=None):
    """Least squares in ln h of :func:`apex_thinning`: ``{"h1", "c", "q", "rms_log"}`` (SI);
    *q* given holds the evaporation rate at that value.  Several starts of c (and q), or the one
    fit *start* (a previous result) if given."""
    from scipy.optimize import least_squares

    def ex(x):
        return math.exp(min(max(float(x), -300.0), 300.0))

    def unpack(p):
        h1 = ex(p[0])
        c = ex(p[1]) if beta is not None else 0.0
        qq = q if q is not None else (ex(p[-1]) if evaporation else 0.0)
        return h1, c, qq

    def resid(p):
        h1, c, qq = unpack(p)
        return np.log(apex_thinning(t, h1, c, beta, qq)) - np.log(h)

    starts_c = [[]] if beta is None else [[lc] for lc in np.linspace(-5.0, 30.0, 8)]
    starts_q = [[]] if (not evaporation or q is not None) else [[math.log(v)] for v in (1e-8, 3e-8, 1e-7)]
    if start is not None:
        starts_c = [[]] if beta is None else [[math.log(start["c"])]]
        starts_q = [[]] if not starts_q[0] else [[math.log(start["q"])]]
    best = None
    for sc in starts_c:
        for sq in starts_q:
            h0 = math.log(h[0]) if start is None else math.log(start["h1"])
            r = least_squares(resid, [h0] + sc + sq, method="lm")
            if best is None or r.cost < best.cost:
                best = r
    h1, c, qq = unpack(best.x)
    return {"h1": h1, "c": c, "q": qq, "rms_log": math.sqrt(2 * best.cost / t.size)}


def bubble_fits(path):
    """The rows of :data:`BUBBLE_FITS` and the curves (t_s, {law: h_m}) for the figure."""
    from scipy.stats import f as f_dist

    from bubbleoptics.filmflow import FilmParameters

    p = FilmParameters()
    t, h = load_bubble(path)
    rows, curves = [], {}
    tt = np.linspace(t[0], t[-1], 241)
    for law, (beta, evap) in BUBBLE_LAWS.items():
        fit = fit_apex_law(t, h, beta, evap)
        row = {"law": law, "beta": beta if beta is not None else math.nan, "h1_nm": fit["h1"] * 1e9,
               "c_per_m2_s": fit["c"], "q_e_m_per_s": fit["q"], "q_e_low": math.nan, "q_e_high": math.nan,
               "radius_equiv_mm": math.nan, "rms_log": fit["rms_log"], "n_points": t.size,
               "t_first_s": t[0], "t_last_s": t[-1], "h_first_nm": h[0] * 1e9, "h_last_nm": h[-1] * 1e9}
        if beta == 3.0 and fit["c"] > 0:  # c = rho g / (6 mu R): the radius whose rigid drainage this is
            row["radius_equiv_mm"] = 1e3 * p.density * p.gravity / (6 * p.viscosity * fit["c"])
        if law == "rigid drainage + evaporation":  # profile interval of q_e (F test, 95 %)
            n, k = t.size, 3
            bound = (fit["rms_log"] ** 2 * n) * (1 + f_dist.ppf(BUBBLE_LEVEL, 1, n - k) / (n - k))
            grid = fit["q"] * _Q_GRID
            prof = np.array([fit_apex_law(t, h, beta, evap, q=qv, start=fit)["rms_log"] ** 2 * n for qv in grid])
            ok = grid[prof <= bound]
            if ok.size and ok.min() > grid[0] and ok.max() < grid[-1]:
                row["q_e_low"], row["q_e_high"] = float(ok.min()), float(ok.max())
        rows.append(row)
        curves[law] = apex_thinning(tt, fit["h1"], fit["c"], beta, fit["q"])
    return rows, (tt, curves)


def write_bubble_fits(data_dir):
    """Write :data:`BUBBLE_FITS` and :data:`BUBBLE_CURVES` into *data_dir* from :data:`BUBBLE_STATED`."""
    from study import provenance, write_csv

    data_dir = Path(data_dir)
    rows, (tt, curves) = bubble_fits(data_dir / BUBBLE_STATED)
    head = [provenance("paper/scripts/numbers_measured.py",
                       "regenerate with: python paper/scripts/numbers_measured.py"),
            f"input: {BUBBLE_STATED} (thicknesses stated in github.com/sciunto-org/oospectro v0.4.0; see README.md)",
            "dh/dt = -c h^beta - q_e fitted in ln h (h1 = h(t1) free); t in s read from the file index as ms "
            "(an inference); radius_equiv_mm: R with c = rho g/(6 mu R), this project's rigid-drainage apex "
            "(water, FilmParameters); q_e_low/high: 95 % profile interval (F test) on a grid of 0.8-1.2 times "
            "the best q_e in steps of 0.005"]
    write_csv(data_dir / BUBBLE_FITS, rows, head, float_format="{:.6g}", na_rep="")
    crow = [{"t_s": float(x), **{law: float(curves[law][i] * 1e9) for law in curves}} for i, x in enumerate(tt)]
    write_csv(data_dir / BUBBLE_CURVES, crow, head[:2] + ["the fitted laws of " + BUBBLE_FITS + ", h in nm"],
              float_format="{:.6g}")
    return rows


#: The spectra of the series: the film is there from index 12000 to 85000 (the mean intensity over
#: 450-800 nm jumps at both ends); from 88000 on the spectra are flat and constant (mean within 1 %),
#: the film gone: their mean is the "no film" background.
BUBBLE_FILM_FROM, BUBBLE_FILM_TO, BUBBLE_VOID_FROM = 12000, 85000, 88000
#: The index the source states for the film (``refractive_index`` of ``known_values.py``).
BUBBLE_INDEX = 1.33
#: The spectra compared with the optics, written by ``numbers_measured.py --spectra DIR``.
BUBBLE_COMPARISON = "oospectro_bubble_comparison.csv"


def bubble_spectra(source_dir):
    """``(wavelength_nm, void, times, intensities)`` of the series in *source_dir* (the folder
    ``spectra/20150611_Bulle6_TTAB10cmc`` of oospectro), cut to :data:`study.measured.FIT_BAND_NM`:
    the spectra of the film (:data:`BUBBLE_FILM_FROM` to :data:`BUBBLE_FILM_TO`) and the mean of
    those after :data:`BUBBLE_VOID_FROM` as the background."""
    from study.measured import load_spectrum

    paths_ = sorted(Path(source_dir).glob("*.xy"))
    if not paths_:
        raise FileNotFoundError(f"no .xy spectra in {source_dir}")
    times = np.array([int(p_.stem) for p_ in paths_])
    wl = load_spectrum(paths_[0])[0]
    stack = []
    for p_ in paths_:
        w, y = load_spectrum(p_)
        if w.shape != wl.shape or not np.allclose(w, wl):
            raise ValueError(f"{p_}: not on the grid of {paths_[0].name}")
        stack.append(y)
    stack = np.array(stack)
    void = stack[times >= BUBBLE_VOID_FROM].mean(axis=0)
    film = (times >= BUBBLE_FILM_FROM) & (times < BUBBLE_FILM_TO)
    return wl, void, times[film], stack[film]


def compare_bubble_spectra(source_dir, stated_csv):
    """Every spectrum of the film against the exact optics, as the optifik series
    (:func:`study.measured.compare_optifik`): in absolute reflectance through the series' envelope,
    the thickness fitted with the gain held at 1, for the source's index (1.33) and for water."""
    from study.measured import calibrated_reflectance, fit_thickness, lamp_envelope, rms_at_thickness, smooth

    wl, void, times, stack = bubble_spectra(source_dir)
    env = lamp_envelope(stack, void)
    _, st = read_commented_csv(stated_csv)
    stated = {int(r["time_index"]): float(r["stated_nm"]) for r in st}
    rows = []
    for t, y in zip(times, stack):
        r = smooth(calibrated_reflectance(wl, y, void, env))
        fit = fit_thickness(wl, r, gain=1.0, n_film=BUBBLE_INDEX)
        water = fit_thickness(wl, r, gain=1.0)
        h = stated.get(int(t), math.nan)
        at = rms_at_thickness(wl, r, h, gain=1.0, n_film=BUBBLE_INDEX)[0] if math.isfinite(h) else math.nan
        rows.append({"time_index": int(t), "stated_nm": h, "fit_nm": fit.thickness_nm, "fit_water_nm": water.thickness_nm,
                     "rms_fit": fit.rms, "rms_at_stated": at, "peak_reflectance": float(np.max(r))})
    return rows


def write_bubble_comparison(source_dir, data_dir):
    from study import provenance, write_csv

    data_dir = Path(data_dir)
    rows = compare_bubble_spectra(source_dir, data_dir / BUBBLE_STATED)
    head = [provenance("paper/scripts/numbers_measured.py",
                       "regenerate with: python paper/scripts/numbers_measured.py --spectra DIR (DIR: the folder "
                       "spectra/20150611_Bulle6_TTAB10cmc of github.com/sciunto-org/oospectro at tag v0.4.0)"),
            f"the spectra of index {BUBBLE_FILM_FROM} to {BUBBLE_FILM_TO}; background: the mean of those from "
            f"{BUBBLE_VOID_FROM} on; absolute reflectance through the series' envelope; 450-800 nm, smoothed",
            f"fit_nm: exact free-film reflectance at normal incidence, gain 1, n = {BUBBLE_INDEX} (the source's); "
            "fit_water_nm: water after Daimon & Masumura; rms in reflectance; stated_nm: the source's, where stated"]
    write_csv(data_dir / BUBBLE_COMPARISON, rows, head, float_format="{:.6g}", na_rep="")
    return rows


def bubble(dirs):
    _, rows = read_commented_csv(dirs["data"] / "measured" / BUBBLE_FITS)
    _, files = read_commented_csv(dirs["data"] / "measured" / BUBBLE_FILE_INDEX)
    step = np.diff(np.sort([int(r["time_index"]) for r in files]))
    law = {r["law"]: r for r in rows}
    both, mr = law["rigid drainage + evaporation"], law["t^-2/3 drainage + evaporation"]
    dry, evap = law["rigid drainage only"], law["evaporation only"]
    qe_scale = 10.0 ** -QE_EXPONENT  # q_e is printed as MeasBubQe x MeasBubQeScale m/s
    return {
        "MeasBubN": both["n_points"],
        "MeasBubFirstNm": f"{float(both['h_first_nm']):.0f}",
        "MeasBubLastNm": f"{float(both['h_last_nm']):.0f}",
        "MeasBubSpanS": significant(float(both["t_last_s"]) - float(both["t_first_s"]), 2),
        "MeasBubRmsBoth": significant(float(both["rms_log"]), 2),
        "MeasBubRmsMr": significant(float(mr["rms_log"]), 2),
        "MeasBubRmsDry": significant(float(dry["rms_log"]), 2),
        "MeasBubRmsEvap": significant(float(evap["rms_log"]), 2),
        "MeasBubQe": significant(qe_scale * float(both["q_e_m_per_s"]), 2),
        "MeasBubQeLow": _down(qe_scale * float(both["q_e_low"])),
        "MeasBubQeHigh": _up(qe_scale * float(both["q_e_high"])),
        "MeasBubQeScale": rf"\ensuremath{{10^{{{QE_EXPONENT}}}}}",
        "MeasBubQeMr": significant(qe_scale * float(mr["q_e_m_per_s"]), 2),
        "MeasBubRadiusMm": significant(float(both["radius_equiv_mm"]), 2),
        "MeasBubCmc": str(BUBBLE_CMC_MULTIPLE),
        "MeasBubLevel": f"{100 * BUBBLE_LEVEL:g}",
        "MeasBubFiles": str(len(files)),
        "MeasBubStepMin": str(int(step.min())),
        "MeasBubStepMax": str(int(step.max())),
        "MeasBubStepMedian": f"{float(np.median(step)):g}",
    }


def bubble_optics(dirs):
    _, rows = read_commented_csv(dirs["data"] / "measured" / BUBBLE_COMPARISON)
    st = [r for r in rows if r["stated_nm"]]
    h = np.array([float(r["stated_nm"]) for r in st])
    rel = np.array([float(r["fit_nm"]) / float(r["stated_nm"]) - 1 for r in st])
    thick = h >= THIN_BELOW_NM
    good = thick & (np.abs(rel) <= 0.1)
    t = np.array([int(r["time_index"]) for r in rows])
    fit = np.array([float(r["fit_nm"]) for r in rows])
    early = t < BUBBLE_THIN_FROM
    return {
        "MeasBubOptN": str(int(thick.sum())),
        "MeasBubOptGood": str(int(good.sum())),
        "MeasBubOptMaxPct": _up(100 * np.max(np.abs(rel[good]))),
        "MeasBubOptMedianPct": significant(100 * np.median(rel[good]), 1, 1),
        "MeasBubOptAll": str(int(early.sum())),
        "MeasBubOptAllThin": str(int(np.sum(fit[early] < BUBBLE_THIN_FIT_NM))),
        "MeasBubOptThinNm": up_to(float(BUBBLE_THIN_FIT_NM), 2),
        "MeasBubOptAboveNm": at_least(float(np.min(h[np.array([int(r["time_index"]) for r in st]) < BUBBLE_THIN_FROM])), 2),
    }


#: Before this index every stated thickness is above 390 nm (``MeasBubOptAboveNm``); a fit below
#: BUBBLE_THIN_FIT_NM there is a failure.
BUBBLE_THIN_FROM, BUBBLE_THIN_FIT_NM = 75000, 150

BUBBLE_OPTICS_MACROS = ["MeasBubOptN", "MeasBubOptGood", "MeasBubOptMaxPct", "MeasBubOptMedianPct", "MeasBubOptAll",
                        "MeasBubOptAllThin", "MeasBubOptThinNm", "MeasBubOptAboveNm"]

BUBBLE_MACROS = ["MeasBubN", "MeasBubFirstNm", "MeasBubLastNm", "MeasBubSpanS", "MeasBubRmsBoth", "MeasBubRmsMr",
                 "MeasBubRmsDry", "MeasBubRmsEvap", "MeasBubQe", "MeasBubQeScale", "MeasBubQeLow", "MeasBubQeHigh", "MeasBubQeMr",
                 "MeasBubRadiusMm", "MeasBubCmc", "MeasBubLevel", "MeasBubFiles", "MeasBubStepMin", "MeasBubStepMax",
                 "MeasBubStepMedian"]

SECTIONS = {
    "measured": (["measured/optifik_comparison.csv"], comparison, COMPARISON_MACROS),
    "measuredthinning": (["measured/optifik_thinning.csv"], thinning, THINNING_MACROS),
    "measuredbubble": ([f"measured/{BUBBLE_FITS}", f"measured/{BUBBLE_FILE_INDEX}"], bubble, BUBBLE_MACROS),
    "measuredbubbleoptics": ([f"measured/{BUBBLE_COMPARISON}"], bubble_optics, BUBBLE_OPTICS_MACROS),
}


if __name__ == "__main__":
    import paths

    if len(sys.argv) == 3 and sys.argv[1] == "--spectra":
        rows = write_bubble_comparison(sys.argv[2], paths.DATA / "measured")
        print(f"wrote {BUBBLE_COMPARISON}: {len(rows)} spectra")

    for r in write_bubble_fits(paths.DATA / "measured"):
        print(f"{r['law']}: rms_log {r['rms_log']:.4f}, q_e {r['q_e_m_per_s']:.3g} m/s, "
              f"R_equiv {r['radius_equiv_mm']:.3g} mm")
