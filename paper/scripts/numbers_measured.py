"""The numbers of the measurement comparison, a plug-in of make_numbers.py.

* ``measured``: ``data/measured/optifik_comparison.csv`` (``python -m study.measured``): the TTAB
  film of Ziapkoff et al. (2026) against the exact optics: how many spectra, the agreement with
  the authors' thickness from 200 to 800 nm (largest and median relative difference), the RMS
  residual in absolute reflectance, and the two ranges where it fails (order 0, the thick spectra);
* ``measuredthinning``: ``data/measured/optifik_thinning.csv``: the fitted thinning-rate exponent
  β (its profile interval in the CSV is resolved only to a 0.05 grid starting at 1.05, so not quoted), and the log-RMS of the laws with β = 3 and 5/2 against the free fit.

Bounds are rounded outward (``MeasAgreeMaxPct`` and ``MeasRmsMax`` up, ``MeasThinMinPct``/``MeasThinMaxPct``
away from zero; :func:`macros.up_to`, :func:`macros.at_least`), so that "within X %", "at most X" and
"X–Y % thinner" stay true.
"""

from __future__ import annotations

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

SECTIONS = {
    "measured": (["measured/optifik_comparison.csv"], comparison, COMPARISON_MACROS),
    "measuredthinning": (["measured/optifik_thinning.csv"], thinning, THINNING_MACROS),
}
