"""Our tracer on the coursework's table, a plug-in of ``make_numbers.py``.

* ``ours``: ``data/derived/coursework_table.csv`` (``benchmarks/coursework_table.py``).
"""

from __future__ import annotations

from macros import NA, WORDS, date_of, group_digits, machine_of, read_commented_csv, significant

#: where these macros stand in numbers.tex (make_numbers.py)
ORDER = 3


def ours(dirs):
    notes, rows = read_commented_csv(dirs["derived"] / "coursework_table.csv")
    main = [r for r in rows if r["mode"] in ("pruned", "exhaustive")]
    extra = [r for r in rows if r["mode"] not in ("pruned", "exhaustive")]
    if not main:
        raise ValueError("no pruned or exhaustive rows")

    def get(nb, mode, depth, column="seconds_median"):
        for r in main:
            if int(r["bubbles"]) == nb and r["mode"] == mode and int(r["depth"]) == depth:
                return float(r[column])
        raise ValueError(f"no row for {nb} bubbles, {mode}, depth {depth}")

    out = {"OursMachine": machine_of(notes), "OursDate": date_of(notes)}
    out["OursWidth"] = str(int(float(main[0]["width"])))
    out["OursHeight"] = str(int(float(main[0]["height"])))
    out["OursCameraRays"] = group_digits(str(int(float(main[0]["rays_camera"]))))
    modes = ("pruned", "exhaustive")
    d1 = [get(nb, m, 1) for nb in WORDS for m in modes]
    d10 = [get(nb, m, 10) for nb in WORDS for m in modes]
    s1 = [get(nb, m, 1, "speedup_vs_seed") for nb in WORDS for m in modes]
    s10 = [get(nb, m, 10, "speedup_vs_seed") for nb in WORDS for m in modes]
    out["OursDepthOneMin"], out["OursDepthOneMax"] = significant(min(d1), 2), significant(max(d1), 2)
    out["OursDepthTenMin"], out["OursDepthTenMax"] = significant(min(d10), 2), significant(max(d10), 2)
    out["SpeedupDepthOneMin"], out["SpeedupDepthOneMax"] = significant(min(s1), 2), significant(max(s1), 2)
    out["SpeedupDepthTenMin"], out["SpeedupDepthTenMax"] = significant(min(s10), 2), significant(max(s10), 2)
    growth = [get(nb, m, 10) / get(nb, m, 1) for nb in WORDS for m in modes]
    out["OursGrowthMin"], out["OursGrowthMax"] = significant(min(growth), 2), significant(max(growth), 2)
    for nb, word in WORDS.items():
        for mode in modes:
            m = mode.capitalize()
            rays = get(nb, mode, 10, "rays_total") / get(nb, mode, 1, "rays_total")
            out[f"RaysGrowth{m}{word}"] = significant(rays, 3)
        saved = 1 - get(nb, "pruned", 10, "rays_total") / get(nb, "exhaustive", 10, "rays_total")
        out[f"PrunedSaved{word}"] = significant(100 * saved, 2)
    out["OursThreeTenPruned"] = significant(get(3, "pruned", 10), 2)
    out["OursThreeTenExhaustive"] = significant(get(3, "exhaustive", 10), 2)
    repeats = max(len(r["seconds_runs"].split()) for r in main)
    out["OursRepeats"] = str(repeats)
    fresh = [r for r in extra if "fresh" in r["mode"]]
    out["FreshProcessSeconds"] = significant(float(fresh[0]["seconds_median"]), 2) if fresh else NA
    return out


OURS_MACROS = (
    ["OursMachine", "OursDate", "OursWidth", "OursHeight", "OursCameraRays", "OursDepthOneMin", "OursDepthOneMax",
     "OursDepthTenMin", "OursDepthTenMax", "SpeedupDepthOneMin", "SpeedupDepthOneMax", "SpeedupDepthTenMin",
     "SpeedupDepthTenMax", "OursGrowthMin", "OursGrowthMax", "OursThreeTenPruned", "OursThreeTenExhaustive",
     "OursRepeats", "FreshProcessSeconds"]
    + [f"RaysGrowth{m}{w}" for m in ("Pruned", "Exhaustive") for w in WORDS.values()]
    + [f"PrunedSaved{w}" for w in WORDS.values()]
)

SECTIONS = {
    "ours": (["derived/coursework_table.csv"], ours, OURS_MACROS),
}
