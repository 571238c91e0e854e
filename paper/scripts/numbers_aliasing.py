"""Spectral aliasing of thick films, a plug-in of ``make_numbers.py``.

* ``aliasing``: ``data/derived/stability_aliasing.csv`` (``benchmarks/stability.py``), as in
  ``fig_stability.py``.
"""

from __future__ import annotations

from macros import NA, plain, read_commented_csv, significant, to_float, up_to

#: where these macros stand in numbers.tex (make_numbers.py)
ORDER = 5


BANDS = {4: "Four", 8: "Eight", 16: "Sixteen", 32: "ThirtyTwo", 81: "EightyOne"}


ALIAS_THIN_NM = 2000.0  # "thin films": below this thickness (the saturated low orders)


def aliasing(dirs):
    _, rows = read_commented_csv(dirs["derived"] / "stability_aliasing.csv")
    out = {}
    thick = [to_float(r["thickness_nm"]) for r in rows]
    out["AliasMaxThicknessUm"] = significant(max(thick) / 1000, 2)
    out["AliasThinMaxUm"] = plain(ALIAS_THIN_NM / 1000)
    for n, word in BANDS.items():
        sel = [r for r in rows if r["method"] == "point" and int(float(r["n_bands"])) == n]
        if not sel:
            out[f"AliasOnset{word}"] = out[f"AliasPredicted{word}"] = out[f"AliasMaxTwoUm{word}"] = NA
            continue
        out[f"AliasOnset{word}"] = significant(to_float(sel[0]["onset_measured_nm"]) / 1000, 2)
        out[f"AliasPredicted{word}"] = significant(to_float(sel[0]["onset_pred_400_nm"]) / 1000, 2)
        below = [to_float(r["dE00"]) for r in sel if to_float(r["thickness_nm"]) < ALIAS_THIN_NM]
        # maxima quoted after "up to" / "within": rounded up
        out[f"AliasMaxTwoUm{word}"] = up_to(max(below), 2) if below else NA
        out[f"AliasMaxAll{word}"] = up_to(max(to_float(r["dE00"]) for r in sel), 2)
    any_band = False
    for n, word in BANDS.items():
        band = [r for r in rows if r["method"] == "bandlimited" and int(float(r["n_bands"])) == n]
        any_band = any_band or bool(band)
        out[f"BandlimitedMax{word}"] = up_to(max(to_float(r["dE00"]) for r in band), 2) if band else NA
    out["BandlimitedAvailable"] = "1" if any_band else "0"
    return out


ALIASING_MACROS = (
    ["AliasMaxThicknessUm", "AliasThinMaxUm", "BandlimitedAvailable"]
    + [f"Alias{what}{w}" for what in ("Onset", "Predicted", "MaxTwoUm", "MaxAll") for w in BANDS.values()]
    + [f"BandlimitedMax{w}" for w in BANDS.values()]
)

SECTIONS = {
    "aliasing": (["derived/stability_aliasing.csv"], aliasing, ALIASING_MACROS),
}

#: \ifnum flags: 0 when their section fails
FLAGS = {"BandlimitedAvailable": "0"}
