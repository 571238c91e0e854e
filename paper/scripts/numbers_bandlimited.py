"""Film colour from few bands, a plug-in of ``make_numbers.py``.

* ``bandlimited``: ``data/derived/bandlimited_colour.csv`` (``benchmarks/bandlimited_colour.py``).
"""

from __future__ import annotations

import re

from macros import NA, group_digits, read_commented_csv, scientific, significant, to_float, up_to

#: where these macros stand in numbers.tex (make_numbers.py)
ORDER = 7


ANGLE_WORDS = {0: "Normal", 60: "Sixty"}


def bandlimited(dirs):
    """Film colour from few bands (``benchmarks/bandlimited_colour.py``): our band-limited method,
    point sampling, band means, and the two published approaches it is compared with."""
    notes, rows = read_commented_csv(dirs["derived"] / "bandlimited_colour.csv")

    def row(method, theta, n_bands="", order="", illuminant="D65"):
        found = [r for r in rows if r["method"] == method and int(float(r["theta_deg"])) == theta
                 and r["n_bands"] == str(n_bands) and r["order"] == str(order) and r["illuminant"] == illuminant]
        if len(found) != 1:
            raise ValueError(f"expected one row {method}/{theta}/{n_bands}/{order}/{illuminant}, found {len(found)}")
        return {k: to_float(v) if k not in ("method", "illuminant", "note") else v for k, v in found[0].items()}

    out = {}
    m = re.search(r"(\d+) thicknesses 0-(\d+) nm", " ".join(notes))
    out["BlThicknesses"] = group_digits(m.group(1)) if m else NA
    out["BlMaxThicknessUm"] = significant(float(m.group(2)) / 1000, 2) if m else NA
    defaults = {r["order"] for r in rows if r["method"] == "bandlimited" and r["note"] == "default"}
    if len(defaults) != 1:
        raise ValueError(f"expected one default weight degree, found {sorted(defaults)}")
    order = defaults.pop()
    out["BlOrder"] = order
    m = re.search(r"_0_(\d+)um", " ".join(rows[0]))
    out["BlThinMaxUm"] = m.group(1) if m else NA
    m = re.search(r"n=([0-9.]+)", " ".join(r["note"] for r in rows if r["illuminant"] == "E"))
    out["ConstIndex"] = m.group(1) if m else NA
    m = re.search(r"_n(\d+)_", " ".join(r["method"] for r in rows))
    out["NearIndexNm"] = m.group(1) if m else NA
    # One convention for every film-colour difference the paper quotes (and fig_bandlimited.py and
    # fig_stability.py draw): the colours exposed so that the brightest film of the reference is
    # white, as a camera exposed for the bubble shows them (the CSV's *_exposed columns, the
    # exposure in its "exposure" column; benchmarks/stability.py uses the same exposure).
    exposed_gain = []
    worst = {"BlSixteenMax": [], "BlPointSixteenMax": []}  # unrounded, for the abstract's worst case
    for theta, word in ANGLE_WORDS.items():
        r16 = row("bandlimited", theta, 16, order)
        out[f"BlExposure{word}"] = significant(r16["exposure"], 2)
        for n_bands, bands in ((4, "Four"), (8, "Eight"), (16, "Sixteen")):
            out[f"Bl{bands}Max{word}"] = significant(row("bandlimited", theta, n_bands, order)["dE00_max_exposed"], 2)
        worst["BlSixteenMax"].append(r16["dE00_max_exposed"])
        out[f"BlSixteenThinMedian{word}"] = significant(r16["dE00_median_0_2um_exposed"], 2)
        point = row("point", theta, 16)
        # the maxima the text quotes after "up to" / "within" are rounded up (macros.up_to)
        out[f"BlPointSixteenMax{word}"] = up_to(point["dE00_max_exposed"], 2)
        worst["BlPointSixteenMax"].append(point["dE00_max_exposed"])
        out[f"BlPointSixteenThinMedian{word}"] = significant(point["dE00_median_0_2um_exposed"], 2)
        band_mean = row("band_mean", theta, 16, 6)
        out[f"BlBandMeanSixteenMax{word}"] = up_to(band_mean["dE00_max_exposed"], 2)
        out[f"BlFourEightMax{word}"] = significant(row("bandlimited", theta, 4, 8)["dE00_max_exposed"], 2)
        gauss = row("gaussian_fit_BB2017", theta, illuminant="E")
        out[f"GaussThinMedian{word}"] = significant(gauss["dE00_median_0_2um_exposed"], 2)
        out[f"GaussMax{word}"] = significant(gauss["dE00_max_exposed"], 2)
        out[f"GaussDispMax{word}"] = significant(
            row("gaussian_fit_vs_dispersive", theta, illuminant="E")["dE00_max_exposed"], 2)
        out[f"LutMax{word}"] = scientific(row("lut_nondispersive", theta, illuminant="E")["dE00_max_exposed"], 1)
        lut = row("lut_nondispersive_vs_dispersive", theta, illuminant="E")
        out[f"LutDispThinMedian{word}"] = significant(lut["dE00_median_0_2um_exposed"], 2)
        out[f"LutDispMax{word}"] = up_to(lut["dE00_max_exposed"], 2)
        out[f"LutNearDispMax{word}"] = significant(
            row("lut_nondispersive_n555_vs_dispersive", theta, illuminant="E")["dE00_max_exposed"], 2)
        out[f"BlWaterMax{word}"] = up_to(row("bandlimited_water", theta, 16, order, "E")["dE00_max_exposed"], 2)
        out[f"LutBlenderMax{word}"] = up_to(row("lut_blender_like", theta, illuminant="E")["dE00_max_exposed"], 2)
        out[f"LutBlenderDispMax{word}"] = significant(
            row("lut_blender_like_vs_dispersive", theta, illuminant="E")["dE00_max_exposed"], 2)
        # the same colours as reflected (dark) differ less: by how much, for the methods of panels (a), (b)
        for r in (point, band_mean, r16, row("bandlimited", theta, 8, order)):
            exposed_gain.append(r["dE00_max_exposed"] / r["dE00_max"])
    # the worst over both angles (the abstract's numbers)
    for key, values in worst.items():
        out[f"{key}Worst"] = up_to(max(values), 2)
    out["BlExposedGainMin"] = significant(min(exposed_gain), 2)
    out["BlExposedGainMax"] = significant(max(exposed_gain), 2)
    ns = lambda r: 0.5 * sum(row(*r[:1], t, *r[1:])["ns_per_colour"] for t in ANGLE_WORDS)  # noqa: E731
    out["BlNsSixteen"] = significant(ns(("bandlimited", 16, order)), 2)
    out["BlNsPointSixteen"] = significant(ns(("point", 16)), 2)
    out["BlNsReference"] = significant(ns(("reference_1nm", 421)), 2)
    # the spread of the timed runs: fastest and slowest run over both angles
    for key, r in (("Sixteen", ("bandlimited", 16, order)), ("PointSixteen", ("point", 16)),
                   ("Reference", ("reference_1nm", 421))):
        runs = [row(*r[:1], t, *r[1:]) for t in ANGLE_WORDS]
        out[f"BlNs{key}Min"] = significant(min(x["ns_per_colour_min"] for x in runs), 2)
        out[f"BlNs{key}Max"] = significant(max(x["ns_per_colour_max"] for x in runs), 2)
    m = re.search(r"(\d+) timed runs a method", " ".join(notes))
    out["BlTimedRuns"] = m.group(1) if m else NA
    return out


BANDLIMITED_MACROS = ["BlThicknesses", "BlMaxThicknessUm", "BlOrder", "BlNsSixteen", "BlNsPointSixteen",
                      "BlNsSixteenMin", "BlNsSixteenMax", "BlNsPointSixteenMin", "BlNsPointSixteenMax",
                      "BlNsReferenceMin", "BlNsReferenceMax", "BlTimedRuns",
                      "BlNsReference", "BlThinMaxUm", "ConstIndex", "NearIndexNm", "BlSixteenMaxWorst",
                      "BlPointSixteenMaxWorst", "BlExposedGainMin",
                      "BlExposedGainMax"] + [
    f"{what}{w}" for what in (
        "BlFourMax", "BlEightMax", "BlSixteenMax", "BlSixteenThinMedian", "BlPointSixteenMax",
        "BlPointSixteenThinMedian", "BlBandMeanSixteenMax", "BlFourEightMax", "GaussThinMedian", "GaussMax",
        "GaussDispMax", "LutMax", "LutDispThinMedian", "LutDispMax", "LutNearDispMax", "BlWaterMax", "BlExposure",
        "LutBlenderMax", "LutBlenderDispMax")
    for w in ANGLE_WORDS.values()
]

SECTIONS = {
    "bandlimited": (["derived/bandlimited_colour.csv"], bandlimited, BANDLIMITED_MACROS),
}
