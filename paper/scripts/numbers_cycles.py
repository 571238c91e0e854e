"""The numbers of the section "An independent renderer" (``paper/sections/peer_cycles.tex``).

Read from ``data/derived/peer_cycles.csv`` (``benchmarks/peer_cycles.py``, Blender's Cycles in
its own venv) and, for the attribution's sensitivity to the RGB-to-spectrum lifting, from
``data/derived/peer_cycles_lifting.csv`` (``benchmarks/peer_cycles_lifting.py``).  A plug-in of
:mod:`make_numbers` (its ``SECTIONS`` format); a missing file makes every number of its section
n/a.
"""

import re

from macros import at_least, date_of, read_commented_csv, significant, up_to

THICKNESS_WORDS = {10.0: "Ten", 200.0: "TwoHundred", 400.0: "FourHundred", 800.0: "EightHundred"}

#: (macro stem, section, setting prefix, renderer or None)
COMPARISONS = (
    ("CyclesDe", "comparison", "mean of two seeds", "cycles"),
    ("CyclesNoise", "comparison", "own noise", "cycles"),
    ("CyclesRefNoise", "comparison", "reference noise", "ours"),
    ("CyclesOursDefaults", "comparison", "defaults", "ours"),
    ("CyclesDispersion", "comparison", "dispersion", "ours"),
    ("CyclesDecompCheck", "decomposition", "model check", None),
    ("CyclesDecompCut", "decomposition", "series cut", None),
    ("CyclesDecompColour", "decomposition", "colour model", None),
    ("CyclesDecompModel", "decomposition", "total model", None),
    ("CyclesDecompRest", "decomposition", "table and the rest", None),
)
#: the statistics quoted: (suffix, column)
STATS = (("", "bubble_mean"), ("Pninetyfive", "bubble_p95"), ("Edge", "edge_mean"), ("All", "all_mean"))
ORIENT = {"CyclesOrientEmptyMatched": "empty/matched", "CyclesOrientMirrorMatched": "mirror/matched",
          "CyclesOrientMirrorFlipped": "mirror/flipped", "CyclesOrientMirrorTilted": "mirror/tilted",
          "CyclesOrientEmptyFlipped": "empty/flipped", "CyclesOrientEmptyTilted": "empty/tilted"}
TIMING = ("CyclesTimingThickness", "CyclesBestSpp", "CyclesBestSeconds", "CyclesBestSecondsMin", "CyclesBestSecondsMax",
          "CyclesBestError", "CyclesOursSeconds", "CyclesOursSecondsMin", "CyclesOursSecondsMax", "CyclesOursError",
          "CyclesOursBestSpp", "CyclesOursBestError", "CyclesTimeRatio", "CyclesSecondsPerSample",
          "CyclesOursSecondsPerSample", "CyclesRounds", "CyclesBestOwnError", "CyclesOwnTimeRatio",
          "CyclesOwnRatioQualifier", "CyclesRatioQualifier")
#: the largest over the films of the statistics the text quotes after "up to" / "at most" / "within",
#: rounded up (macros.up_to): (macro, stem, column)
MAXIMA = (("CyclesDeMax", "CyclesDe", "bubble_mean"), ("CyclesDePninetyfiveMax", "CyclesDe", "bubble_p95"),
          ("CyclesOursDefaultsMax", "CyclesOursDefaults", "bubble_mean"))
HEAD = ("CyclesDate", "CyclesVersion", "CyclesSize", "CyclesRefSpp", "CyclesRefBands", "CyclesSpp", "CyclesTriangles",
        "CyclesBounces", "CyclesDepth", "CyclesEdgePx", "CyclesLoad", "CyclesFilmIndex", "CyclesWaterBlue",
        "CyclesWaterRed")

#: the same with one thread (sections timing_1_thread, ...), where the CSV has them
TIMING_ONE_THREAD = tuple(f"{name}OneThread" for name in (
    "CyclesBestSeconds", "CyclesBestSecondsMin", "CyclesBestSecondsMax", "CyclesOursSeconds", "CyclesOursSecondsMin",
    "CyclesOursSecondsMax", "CyclesTimeRatio", "CyclesRatioQualifier", "CyclesOwnTimeRatio",
    "CyclesOwnRatioQualifier", "CyclesSecondsPerSample", "CyclesOursSecondsPerSample"))

MACROS = list(HEAD) + list(ORIENT) + list(TIMING) + list(TIMING_ONE_THREAD) + [name for name, *_ in MAXIMA]
MACROS += [f"CyclesThick{word}" for word in THICKNESS_WORDS.values()]
MACROS += [f"{stem}{suffix}{word}" for stem, *_ in COMPARISONS for suffix, _ in STATS
           for word in THICKNESS_WORDS.values()]


def _f(row, column):
    return float(row[column])


def cycles(dirs):
    notes, rows = read_commented_csv(dirs["derived"] / "peer_cycles.csv")
    text = " ".join(notes)
    out = {"CyclesDate": date_of(notes)}
    for name, pattern in (("CyclesVersion", r"Blender (\d+(?:\.\d+)+)"), ("CyclesSize", r"(\d+)x\1, box"),
                          ("CyclesRefBands", r"ours spectral (\d+) bands"), ("CyclesRefSpp", r"\), (\d+) spp, mean"),
                          ("CyclesSpp", r"mean of two seeds at (\d+) spp"),
                          ("CyclesTriangles", r"icosphere of (\d+) triangles"), ("CyclesBounces", r"(\d+) bounces"),
                          ("CyclesDepth", r"depth (\d+);"), ("CyclesEdgePx", r"silhouette by > ([0-9.]+) px"),
                          ("CyclesRounds", r"(\d+) interleaved rounds"),
                          ("CyclesFilmIndex", r"uniform film n = ([0-9.]+)")):
        m = re.search(pattern, text)
        if m:
            value = m.group(1)
            out[name] = f"{int(value):,}".replace(",", "\\,") if name == "CyclesTriangles" else value
    from bubbleoptics import water_refractive_index

    out["CyclesWaterBlue"] = f"{float(water_refractive_index(400.0)):.3f}"
    out["CyclesWaterRed"] = f"{float(water_refractive_index(700.0)):.3f}"
    # the load average before and after each timing round
    loads = [float(v) for pair in re.findall(r"timing round \d+(?:, \d+ threads?)?: load ([0-9.]+) -> ([0-9.]+)", text) for v in pair]
    if loads:
        out["CyclesLoad"] = f"{min(loads):.1f}--{max(loads):.1f}"
    for name, setting in ORIENT.items():
        row = next(r for r in rows if r["section"] == "orientation" and r["setting"] == setting)
        out[name] = significant(_f(row, "all_mean"), 2)
    maxima = {name: [] for name, *_ in MAXIMA}
    for stem, section, prefix, renderer in COMPARISONS:
        for row in rows:
            if row["section"] != section or not row["setting"].startswith(prefix):
                continue
            if renderer and row["renderer"] != renderer:
                continue
            word = THICKNESS_WORDS.get(float(row["thickness_nm"]))
            if word is None:
                continue
            out[f"CyclesThick{word}"] = f"{float(row['thickness_nm']):g}"
            for suffix, column in STATS:
                out[f"{stem}{suffix}{word}"] = significant(_f(row, column), 2)
            for name, max_stem, column in MAXIMA:
                if max_stem == stem:
                    maxima[name].append(_f(row, column))
    for name, values in maxima.items():
        out[name] = up_to(max(values), 2)
    out.update(cycles_timing(rows, "", ""))
    if any(r["section"] == "timing_1_thread" for r in rows):
        out.update(cycles_timing(rows, "_1_thread", "OneThread"))
    return out


def cycles_timing(rows, suffix, word):
    """The timing macros of one thread count: sections ``timing{suffix}``, ``equal_error{suffix}``
    and ``equal_own_error{suffix}`` of peer_cycles.csv, each macro name ending in *word* (``""``:
    two threads, ``"OneThread"``)."""
    out = {}
    timing = [r for r in rows if r["section"] == "timing" + suffix]
    cyc = sorted((r for r in timing if r["renderer"] == "cycles"), key=lambda r: int(r["spp"]))
    ours = sorted((r for r in timing if r["renderer"] == "ours"), key=lambda r: int(r["spp"]))
    best, first = cyc[-1], ours[0]
    if not word:
        out["CyclesTimingThickness"] = f"{float(best['thickness_nm']):g}"
        out["CyclesBestSpp"] = best["spp"]
        out["CyclesBestError"] = significant(_f(best, "bubble_mean"), 2)
        out["CyclesOursError"] = significant(_f(first, "bubble_mean"), 2)
        out["CyclesOursBestSpp"] = ours[-1]["spp"]
        out["CyclesOursBestError"] = significant(_f(ours[-1], "bubble_mean"), 2)
        if best.get("own_bubble_mean"):
            out["CyclesBestOwnError"] = significant(_f(best, "own_bubble_mean"), 2)
    for name, row in (("CyclesBest", best), ("CyclesOurs", first)):
        out[f"{name}Seconds{word}"] = significant(_f(row, "seconds"), 2)
        out[f"{name}SecondsMin{word}"] = significant(_f(row, "seconds_min"), 2)
        out[f"{name}SecondsMax{word}"] = significant(_f(row, "seconds_max"), 2)
    for section, ratio_name, word_name in (("equal_error", "CyclesTimeRatio", "CyclesRatioQualifier"),
                                           ("equal_own_error", "CyclesOwnTimeRatio", "CyclesOwnRatioQualifier")):
        equal = [r for r in rows if r["section"] == section + suffix]
        if not equal:
            continue
        last = max(equal, key=lambda r: _f(r, "seconds_cycles"))  # Cycles' slowest, most converged point
        lower = "lower bound" in last["setting"]
        out[ratio_name + word] = at_least(_f(last, "ratio"), 2) if lower else significant(_f(last, "ratio"), 2)
        out[word_name + word] = "at least" if lower else "about"
    out[f"CyclesSecondsPerSample{word}"] = significant(_f(best, "seconds") / int(best["spp"]) * 1000.0, 2)
    out[f"CyclesOursSecondsPerSample{word}"] = significant(_f(ours[-1], "seconds") / int(ours[-1]["spp"]) * 1000.0,
                                                           2)
    return out


#: per film, over the liftings other than the tracer's (corrected round trip, closed form): (macro
#: stem, setting prefix, statistic) with the statistic "range" (CyclesLift<stem>Min/Max<film>) or
#: "max" (rounded up)
LIFT_PER_FILM = (("De", "Cycles render vs", "range"), ("Colour", "colour model", "range"),
                 ("Move", "reference moves", "max"))
LIFT_MACROS = ["CyclesLiftColourChange", "CyclesLiftColourShareDev", "CyclesLiftCheckMax", "CyclesLiftFitMax", "CyclesLiftOthersRoundTrip", "CyclesLiftMoveMax"]
LIFT_MACROS += [f"CyclesLift{stem}{end}{word}" for stem, _, kind in LIFT_PER_FILM
                for end in (("Min", "Max") if kind == "range" else ("Max",)) for word in THICKNESS_WORDS.values()]
#: the supplement's table, one row per lifting: CyclesLift<method><stem><film> (corrected, closed form;
#: "Rendered": Cycles against our render with the lifting's linear fit), CyclesLift<method>RoundTrip
#: (raw, largest over the environment's rows), ...Check and ...Fit (rendered, largest over the films)
LIFT_METHOD_WORDS = {"Mallett2019": "Mallett", "Jakob2019": "Jakob", "Smits1999": "Smits", "Otsu2018": "Otsu"}
LIFT_METHOD_STEMS = (("De", "closed_form", "Cycles render vs"), ("Colour", "closed_form", "colour model"),
                     ("Move", "closed_form", "reference moves"), ("Rendered", "rendered", "Cycles render vs render"))
LIFT_MACROS += [f"CyclesLift{m}{stem}{word}" for m in LIFT_METHOD_WORDS.values() for stem, *_ in LIFT_METHOD_STEMS
                for word in THICKNESS_WORDS.values() if not (m == "Mallett" and stem == "Rendered")]
LIFT_MACROS += [f"CyclesLift{m}{what}" for m in LIFT_METHOD_WORDS.values() for what in ("RoundTrip", "Check", "Fit")
                if not (m == "Mallett" and what != "RoundTrip")]
LIFT_MACROS += ["CyclesLiftRows", "CyclesLiftBaseCheckMax", "CyclesLiftSmitsRawColourEightHundred",
                "CyclesLiftJakobSeconds"]


def cycles_lifting(dirs):
    notes, rows = read_commented_csv(dirs["derived"] / "peer_cycles_lifting.csv")
    others = [r for r in rows if r["section"] == "closed_form" and r["variant"] == "corrected"
              and r["lifting"] != "Mallett2019"]
    out = {}
    moves = []
    for stem, prefix, kind in LIFT_PER_FILM:
        for d, word in THICKNESS_WORDS.items():
            values = [_f(r, "bubble_mean") for r in others
                      if r["setting"].startswith(prefix) and float(r["thickness_nm"]) == d]
            if not values:
                continue
            if kind == "range":
                out[f"CyclesLift{stem}Min{word}"] = significant(min(values), 2)
                out[f"CyclesLift{stem}Max{word}"] = significant(max(values), 2)
            else:
                out[f"CyclesLift{stem}Max{word}"] = up_to(max(values), 2)
                moves += values
    if moves:
        out["CyclesLiftMoveMax"] = up_to(max(moves), 2)
    # the coloured films (200 nm and thicker; the black film's differences are noise): how much
    # the colour-model step changes from ours to another lifting, and its share of Cycles' difference
    def step(lifting, prefix, d):
        return next(_f(r, "bubble_mean") for r in rows if r["section"] == "closed_form" and r["variant"] == "corrected"
                    and r["lifting"] == lifting and r["setting"].startswith(prefix) and float(r["thickness_nm"]) == d)

    films = sorted({float(r["thickness_nm"]) for r in others if float(r["thickness_nm"]) >= 200.0})
    lifts = sorted({r["lifting"] for r in others})
    if films and lifts:
        change = max(abs(step(m, "colour model", d) / step("Mallett2019", "colour model", d) - 1.0)
                     for m in lifts for d in films)
        share = max(abs(step(m, "colour model", d) / step(m, "Cycles render vs", d) - 1.0) for m in lifts for d in films)
        out["CyclesLiftColourChange"] = up_to(100.0 * change, 2)
        out["CyclesLiftColourShareDev"] = up_to(100.0 * share, 2)
    rendered = [r for r in rows if r["section"] == "rendered"]
    for name, prefix in (("CyclesLiftCheckMax", "check"), ("CyclesLiftFitMax", "linear fit")):
        values = [_f(r, "bubble_mean") for r in rendered if r["setting"].startswith(prefix)]
        if values:
            out[name] = up_to(max(values), 2)
    for method, m in LIFT_METHOD_WORDS.items():
        for stem, section, prefix in LIFT_METHOD_STEMS:
            for r in rows:
                if (r["section"] == section and r["lifting"] == method and r["variant"].startswith("corrected")
                        and r["setting"].startswith(prefix)):
                    word = THICKNESS_WORDS.get(float(r["thickness_nm"]))
                    if word:
                        out[f"CyclesLift{m}{stem}{word}"] = significant(_f(r, "bubble_mean"), 2)
        for what, prefix in (("Check", "check"), ("Fit", "linear fit")):
            values = [_f(r, "bubble_mean") for r in rendered if r["lifting"] == method and r["setting"].startswith(prefix)]
            if values:
                out[f"CyclesLift{m}{what}"] = up_to(max(values), 2)
        trip = [_f(r, "rows_max") for r in rows if r["section"] == "round_trip" and r["lifting"] == method
                and r["variant"] == ("corrected" if method == "Mallett2019" else "raw")]
        if trip:
            out[f"CyclesLift{m}RoundTrip"] = "0" if trip[0] < 1e-9 else up_to(trip[0], 2)
    base = [_f(r, "bubble_mean") for r in rows if r["section"] == "check"]
    if base:
        out["CyclesLiftBaseCheckMax"] = up_to(max(base), 2)
    raw = [_f(r, "bubble_mean") for r in rows if r["section"] == "closed_form" and r["lifting"] == "Smits1999"
           and r["variant"] == "raw" and r["setting"].startswith("colour model") and float(r["thickness_nm"]) == 800.0]
    if raw:
        out["CyclesLiftSmitsRawColourEightHundred"] = significant(raw[0], 2)
    text = " ".join(notes)
    m = re.search(r"environment \d+x(\d+), its rows", text)
    if m:
        out["CyclesLiftRows"] = m.group(1)
    m = re.search(r"Jakob2019 (\d+) s for (\d+) colours", text)
    if m:
        out["CyclesLiftJakobSeconds"] = significant(float(m.group(1)) / float(m.group(2)), 1)
    trips = {r["lifting"]: _f(r, "rows_max") for r in rows if r["section"] == "round_trip" and r["variant"] == "raw"}
    trips.pop("Smits1999", None)  # Smits' is quoted by itself (CyclesLiftSmitsRoundTrip)
    if trips:
        out["CyclesLiftOthersRoundTrip"] = up_to(max(trips.values()), 1)
    return out


SECTIONS = {"cycles": (["derived/peer_cycles.csv"], cycles, MACROS),
            "cycles_lifting": (["derived/peer_cycles_lifting.csv"], cycles_lifting, LIFT_MACROS)}
