"""The numbers of the scene-editor chapter (paper/sections/editor.tex), a plug-in of make_numbers.py.

* ``editor``: ``data/derived/editor.csv`` (``benchmarks/editor_latency.py``): from a click on
  Change to the first preview and to the full image on screen in headless Chromium, medians with
  min-max, the targets and whether the medians meet them (the CSV's ``meets_target`` column), the
  server's and the render's shares, the round trip without a render, and two tabs editing at once
  (each tab's first preview, and its ratio to one tab's).

Flags for ``\\ifnum`` (0 when the section fails): ``EdPreviewMeets``, ``EdFullMeets``,
``EdTwoTabsMeets``.
"""

from __future__ import annotations

import re

from macros import date_of, machine_of, read_commented_csv, significant


def _ms(x):
    """Milliseconds as the reader compares them with a target: whole from 100 ms on (1004, not 1000)."""
    x = float(x)
    return str(int(round(x))) if x >= 100 else significant(x, 2)


def editor(dirs):
    notes, rows = read_commented_csv(dirs["derived"] / "editor.csv")
    by = {r["case"]: r for r in rows}
    out = {"EdDate": date_of(notes), "EdMachine": machine_of(notes)}
    for key, case in (("Preview", "first_preview"), ("Full", "full_resolution"), ("Clear", "clear_no_render")):
        r = by[case]
        out[f"Ed{key}Ms"] = _ms(r["ms_median"])
        out[f"Ed{key}MinMs"] = _ms(r["ms_min"])
        out[f"Ed{key}MaxMs"] = _ms(r["ms_max"])
        if case != "clear_no_render":
            out[f"Ed{key}Width"] = str(int(float(r["width"])))
            out[f"Ed{key}TargetMs"] = _ms(r["target_ms"])
            out[f"Ed{key}ServerMs"] = _ms(r["server_ms_median"])
            out[f"Ed{key}RenderMs"] = _ms(r["render_ms_median"])
            meets = r["meets_target"].strip().lower()
            if meets not in ("true", "false"):
                raise ValueError(f"editor.csv: meets_target {r['meets_target']!r} for {case}")
            out[f"Ed{key}Meets"] = "1" if meets == "true" else "0"
            over = float(r["ms_median"]) / float(r["target_ms"]) - 1
            out[f"Ed{key}OverPercent"] = significant(100 * abs(over), 1)
    out["EdRepeats"] = str(int(float(by["first_preview"]["repeats"])))
    two = by["two_tabs_first_preview"]
    out["EdTwoTabsMs"], out["EdTwoTabsMinMs"], out["EdTwoTabsMaxMs"] = (_ms(two[k]) for k in ("ms_median", "ms_min",
                                                                                              "ms_max"))
    out["EdTwoTabsRatio"] = significant(float(two["ratio_to_one_tab"]), 2)
    out["EdTwoTabsMeets"] = "1" if two["meets_target"].strip().lower() == "true" else "0"
    load = re.search(r"load average ([0-9.]+) before, ([0-9.]+) after", notes[0])
    if load:
        out["EdLoadBefore"], out["EdLoadAfter"] = load.group(1), load.group(2)
    m = re.search(r"depth (\d+), (\d+) spp, (\d+) bands", notes[0])
    if m:
        out["EdDepth"], out["EdSpp"], out["EdBands"] = m.groups()
    return out


EDITOR_MACROS = (["EdDate", "EdMachine", "EdRepeats", "EdLoadBefore", "EdLoadAfter", "EdDepth", "EdSpp", "EdBands",
                  "EdTwoTabsMs", "EdTwoTabsMinMs", "EdTwoTabsMaxMs", "EdTwoTabsRatio", "EdTwoTabsMeets"]
                 + [f"Ed{k}{s}" for k in ("Preview", "Full", "Clear") for s in ("Ms", "MinMs", "MaxMs")]
                 + [f"Ed{k}{s}" for k in ("Preview", "Full")
                    for s in ("Width", "TargetMs", "ServerMs", "RenderMs", "Meets", "OverPercent")])

SECTIONS = {"editor": (["derived/editor.csv"], editor, EDITOR_MACROS)}

FLAGS = {"EdPreviewMeets": "0", "EdFullMeets": "0", "EdTwoTabsMeets": "0"}
