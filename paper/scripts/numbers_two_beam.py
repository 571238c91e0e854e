"""Numbers of the two-beam renders paragraph (``paper/sections/two_beam_renders.tex``).

Reads ``data/derived/two_beam_render.csv`` (``benchmarks/two_beam_render.py``): per scene the
ΔE00 of the two-beam render against the exact one over the bubble pixels, and the settings.
"""

from __future__ import annotations

import re

from macros import read_commented_csv, significant, up_to
from numbers_time_vs_error import film_range_um

SCENE_WORDS = {"builtin": "Builtin", "bubbles": "Bubbles", "thick": "Thick"}
STATS = {"bubble_mean_de00": "Mean", "bubble_median_de00": "Median", "bubble_p95_de00": "Pninetyfive",
         "bubble_max_de00": "Max"}


def two_beam_renders(dirs):
    notes, rows = read_commented_csv(dirs["derived"] / "two_beam_render.csv")
    by = {r["scene"]: r for r in rows if not r.get("variant")}
    checks = [r for r in rows if r.get("variant")]
    out = {}
    if checks:  # how far the statistics move with twice the bands or 9 samples per pixel
        for col, word in (("bubble_mean_de00", "Mean"), ("bubble_p95_de00", "Pninetyfive")):
            moved = max(abs(float(c[col]) - float(by[c["scene"]][col])) for c in checks)
            out[f"TbRCheck{word}"] = up_to(moved, 2)  # "move by at most"
    for scene, word in SCENE_WORDS.items():
        r = by[scene]
        for col, stat in STATS.items():
            out[f"TbR{word}{stat}"] = significant(float(r[col]), 2)
        out[f"TbR{word}AboveTwo"] = significant(100 * float(r["bubble_share_above_2"]), 2)
        out[f"TbR{word}AboveOne"] = significant(100 * float(r["bubble_share_above_1"]), 2)
    first = by["builtin"]
    out["TbRSize"] = str(int(first["width"]))
    out["TbRBands"] = str(int(first["spectral_samples"]))
    out["TbRSpp"] = str(int(first["spp"]))
    out["TbRDepth"] = str(int(first["depth"]))
    if any(int(r["spectral_samples"]) != int(first["spectral_samples"]) or int(r["width"]) != int(first["width"])
           for r in by.values()):
        raise ValueError("the scenes were rendered with different settings")
    # the films' thickness as the tracer computes it, swirl included (not the scene's top and bottom values)
    lo, hi = film_range_um(dirs["data"] / "scenes" / "thick_films.toml")
    out["TbRThickFromUm"], out["TbRThickToUm"] = significant(lo, 2), significant(hi, 2)
    m = re.search(r"on (\d{4}-\d{2}-\d{2})", notes[0])
    out["TbRDate"] = m.group(1) if m else r"\NumberNA{}"
    return out


TWO_BEAM_MACROS = (
    [f"TbR{w}{s}" for w in SCENE_WORDS.values() for s in list(STATS.values()) + ["AboveTwo", "AboveOne"]]
    + ["TbRCheckMean", "TbRCheckPninetyfive"]
    + ["TbRSize", "TbRBands", "TbRSpp", "TbRDepth", "TbRDate", "TbRThickFromUm", "TbRThickToUm"]
)

SECTIONS = {"tworenders": (["derived/two_beam_render.csv", "data/scenes/thick_films.toml"], two_beam_renders,
                           TWO_BEAM_MACROS)}
