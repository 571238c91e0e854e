"""The growth laws of the coursework's own timings, a plug-in of ``make_numbers.py``.

* ``coursework``: ``data/coursework_table_4_1.csv`` (the coursework's table 4.1) with the
  growth-law fits of :mod:`study` (the same code as ``fig_depth_fits.py``: AICc ranking, relative weights,
  laws fitted to depths 1-7 and tested at depth 10).
"""

from __future__ import annotations

import re

from macros import NA, WORDS, at_least, group_digits, significant, up_to

#: where these macros stand in numbers.tex (make_numbers.py)
ORDER = 2


def coursework(dirs):
    import study

    table = study.load_coursework_table(dirs["data"] / "coursework_table_4_1.csv")
    depth = table["depth"]
    out = {}
    m = re.search(r"on an? (.+?) \(", " ".join(table["notes"]))
    out["CourseworkMachine"] = m.group(1) if m else NA
    branch, delta_quartic, delta_exp, hold = [], [], [], {"Quartic": [], "Affine": [], "Exp": []}
    rms_affine, best = [], set()
    fitters = {
        "Quartic": lambda d, t, relative: study.fit_polynomial(d, t, 4, relative=relative),
        "Affine": study.fit_affine_exponential,
        "Exp": study.fit_exponential,
    }
    for nb, word in WORDS.items():
        t = table["seconds"][nb]
        out[f"CourseworkDepthOne{word}"] = f"{t[0]:.2f}"  # as transcribed (two decimals)
        out[f"CourseworkDepthTen{word}"] = group_digits(f"{t[-1]:.2f}".split(".")[0]) + "." + f"{t[-1]:.2f}".split(".")[1]
        out[f"CourseworkGrowth{word}"] = significant(t[-1] / t[0], 2)
        comparison = study.compare_fits(depth, t)
        best.add(comparison.best)
        rows = {r["model"]: r for r in comparison.rows}
        affine = rows["affine exponential"]["fit"]
        out[f"CourseworkBranch{word}"] = significant(affine.params["b"], 3)
        branch.append(affine.params["b"])
        rms_affine.append(affine.rms_relative)
        delta_quartic.append(rows["polynomial, degree 4"]["delta"])
        delta_exp.append(rows["exponential"]["delta"])
        for key, fitter in fitters.items():
            _, err = study.holdout_errors(fitter, depth, t, 7, relative=True)
            hold[key].append(abs(err[-1]))
    out["CourseworkBestLaw"] = ", ".join(sorted(best)) if best else NA
    out["CourseworkBestIsAffine"] = "1" if best == {"affine exponential"} else "0"
    out["CourseworkBranchMin"] = significant(min(branch), 3)
    out["CourseworkBranchMax"] = significant(max(branch), 3)
    out["CourseworkRmsAffineMax"] = up_to(100 * max(rms_affine), 2)  # "residuals below"
    out["CourseworkDeltaQuarticMin"] = at_least(min(delta_quartic), 2)  # "by at least"
    out["CourseworkDeltaExpMin"] = at_least(min(delta_exp), 2)
    for key, errs in hold.items():
        out[f"CourseworkHoldout{key}Max"] = up_to(100 * max(errs), 2)  # "misses by up to"
    return out


COURSEWORK_MACROS = (
    ["CourseworkMachine", "CourseworkBestLaw", "CourseworkBestIsAffine", "CourseworkBranchMin", "CourseworkBranchMax", "CourseworkRmsAffineMax",
     "CourseworkDeltaQuarticMin", "CourseworkDeltaExpMin", "CourseworkHoldoutQuarticMax", "CourseworkHoldoutAffineMax",
     "CourseworkHoldoutExpMax"]
    + [f"Coursework{what}{w}" for what in ("DepthOne", "DepthTen", "Growth", "Branch") for w in WORDS.values()]
)

SECTIONS = {
    "coursework": (["data/coursework_table_4_1.csv"], coursework, COURSEWORK_MACROS),
}

#: \ifnum flags: 0 when their section fails
FLAGS = {"CourseworkBestIsAffine": "0"}
