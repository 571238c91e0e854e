"""The grazing-incidence accuracy of the film formulas, a plug-in of ``make_numbers.py``.

* ``grazing``: ``data/derived/stability_grazing.csv`` (``benchmarks/stability.py``); unpolarized
  light, as in ``fig_stability.py``.
"""

from __future__ import annotations

import math

from macros import read_commented_csv, sci_or_plain, scientific, significant, to_float, up_to

#: where these macros stand in numbers.tex (make_numbers.py)
ORDER = 4


def grazing(dirs):
    _, rows = read_commented_csv(dirs["derived"] / "stability_grazing.csv")

    def worst(method, column, u_max=math.inf, positive_ref=None):
        values = []
        for r in rows:
            if r["method"] != method or r["polarization"] != "unpolarized" or to_float(r["u"]) > u_max + 1e-9:
                continue
            if positive_ref and not to_float(r[positive_ref]) > 0:
                continue
            v = to_float(r[column])
            if math.isfinite(v):
                values.append(v)
        if not values:
            raise ValueError(f"no finite {column} for {method}")
        return max(values)

    u_max = max(to_float(r["u"]) for r in rows)
    out = {"GrazingUMax": significant(u_max, 1)}
    out["GrazingFilms"] = str(len({r["film"] for r in rows}))
    out["GrazingOursRelT"] = up_to(worst("bubbleoptics", "rel_err_T", positive_ref="T_ref"), 2, form="scientific")  # "at most"
    out["GrazingOursAbsR"] = scientific(worst("bubbleoptics", "abs_err_R"), 2)
    for method, key in (("naive", "Naive"), ("tmm", "Tmm")):
        out[f"Grazing{key}RelTFour"] = scientific(worst(method, "rel_err_T", 4.0, "T_ref"), 1)
        out[f"Grazing{key}RelTSix"] = scientific(worst(method, "rel_err_T", 6.0, "T_ref"), 1)
        out[f"Grazing{key}RelTAll"] = sci_or_plain(worst(method, "rel_err_T", positive_ref="T_ref"), 2)
    return out


GRAZING_MACROS = ["GrazingUMax", "GrazingFilms", "GrazingOursRelT", "GrazingOursAbsR"] + [
    f"Grazing{k}RelT{u}" for k in ("Naive", "Tmm") for u in ("Four", "Six", "All")
]

SECTIONS = {
    "grazing": (["derived/stability_grazing.csv"], grazing, GRAZING_MACROS),
}
