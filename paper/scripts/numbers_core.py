"""Numbers of the tracer-core chapter (``paper/sections/core_speed.tex``).

* ``core``: ``data/derived/throughput.csv`` (``benchmarks/throughput.py``): each scene's time
  as a ratio to the floor kernel timed beside it, median [fastest, slowest] over the repeats,
  rays per second, the speed-up from one thread to two, two single-threaded processes at once,
  and the start-up of fresh processes.
* ``energy``: ``data/derived/energy.csv`` (``benchmarks/energy.py``): the white furnace (largest
  deviation of a lossless object in uniform light from the light itself), the absorbing film
  against its closed form, and what the default pruning changes on the built-in scene.
"""

from __future__ import annotations

from macros import date_of, machine_of, read_commented_csv, scientific, significant, up_to

#: (case, depth) of the throughput table, and its macro word
CASES = {("empty", "10"): "Empty", ("coursework_1_bubble", "1"): "OneShallow", ("coursework_1_bubble", "10"): "OneDeep",
         ("coursework_2_bubbles", "1"): "TwoShallow", ("coursework_2_bubbles", "10"): "TwoDeep",
         ("coursework_3_bubbles", "1"): "ThreeShallow", ("coursework_3_bubbles", "10"): "ThreeDeep",
         ("builtin", "10"): "Builtin"}
THREADS = {"1": "OneThread", "2": "TwoThreads"}
TOGETHER = {"floor": "Floor", "probe": "Probe", "coursework_3_bubbles": "Three", "builtin": "Builtin"}
FRESH = {"import numba": "Numba", "numba and one cached kernel": "Kernel", "import tracer": "Tracer",
         "built-in scene to PNG": "Png"}


def spread(median, lo, hi, n=2):
    """'4.2 [3.9, 4.6]': a median and its range, each to *n* significant digits."""
    return f"{significant(median, n)} [{significant(lo, n)}, {significant(hi, n)}]"


def core(dirs):
    notes, rows = read_commented_csv(dirs["derived"] / "throughput.csv")
    out = {"CoreMachine": machine_of(notes), "CoreDate": date_of(notes)}
    by = {(r["case"], r["depth"], r["threads"]): r for r in rows}
    for (case, depth), word in CASES.items():
        for t, tw in THREADS.items():
            r = by[(case, depth, t)]
            out[f"CoreRatio{word}{tw}"] = spread(float(r["ratio_to_floor_median"]), float(r["ratio_to_floor_min"]),
                                                 float(r["ratio_to_floor_max"]))
        r2 = by[(case, depth, "2")]
        out[f"CoreMrays{word}"] = significant(float(r2["rays_per_second"]) / 1e6, 2)
        out[f"CoreSpeedup{word}"] = significant(float(r2["speedup_1_to_2_threads"]), 2)
        out[f"CoreMs{word}"] = spread(1e3 * float(r2["seconds_median"]), 1e3 * float(r2["seconds_min"]),
                                      1e3 * float(r2["seconds_max"]), 3)
    first = by[("builtin", "10", "2")]
    out["CoreSize"] = f"{int(first['width'])}"
    out["CoreRepeats"] = f"{int(first['repeats'])}"
    for name, word in (("floor kernel", "Floor"), ("probe: vector arithmetic", "Probe")):
        r = by[(name, "", "1")]
        out[f"CoreSpeedup{word}"] = significant(float(r["speedup_1_to_2_threads"]), 2)
        r2 = by[(name, "", "2")]
        out[f"CoreMs{word}"] = spread(1e3 * float(r2["seconds_median"]), 1e3 * float(r2["seconds_min"]),
                                      1e3 * float(r2["seconds_max"]), 3)
    together = {}
    for key, word in TOGETHER.items():
        r = by[(f"two processes at once: {key}", "", "1")]
        together[word] = float(r["slowdown_together"])
        out[f"CoreTogether{word}"] = significant(together[word], 2)
    out["CoreTogetherMin"] = significant(min(together.values()), 2)
    out["CoreTogetherMax"] = significant(max(together.values()), 2)
    for key, word in FRESH.items():
        r = by[(f"fresh process: {key}", "10", "2")]
        out[f"CoreStart{word}"] = spread(float(r["seconds_median"]), float(r["seconds_min"]), float(r["seconds_max"]))
    speedups = [float(by[(c, d, "2")]["speedup_1_to_2_threads"]) for c, d in CASES]
    out["CoreSpeedupMin"], out["CoreSpeedupMax"] = significant(min(speedups), 2), significant(max(speedups), 2)
    return out


CORE_MACROS = (
    ["CoreMachine", "CoreDate", "CoreSize", "CoreRepeats"]
    + [f"CoreRatio{w}{t}" for w in CASES.values() for t in THREADS.values()]
    + [f"Core{k}{w}" for w in CASES.values() for k in ("Mrays", "Speedup", "Ms")]
    + ["CoreSpeedupFloor", "CoreSpeedupProbe", "CoreMsFloor", "CoreMsProbe", "CoreSpeedupMin", "CoreSpeedupMax"]
    + [f"CoreTogether{w}" for w in TOGETHER.values()] + ["CoreTogetherMin", "CoreTogetherMax"]
    + [f"CoreStart{w}" for w in FRESH.values()]
)

FURNACE = {"bubble": "Bubble", "thick_bubble": "Thick", "two_beam_bubble": "TwoBeam", "glass": "Glass", "foam": "Foam"}


def energy(dirs):
    notes, rows = read_commented_csv(dirs["derived"] / "energy.csv")
    out = {"EnergyDate": date_of(notes)}
    furnace = [r for r in rows if r["case"] in FURNACE]
    if {r["case"] for r in furnace} != set(FURNACE):
        raise ValueError("a white-furnace case is missing")
    for case, word in FURNACE.items():
        out[f"Furnace{word}"] = scientific(max(float(r["max_abs_deviation"]) for r in furnace if r["case"] == case), 1)
    out["FurnaceMax"] = scientific(max(float(r["max_abs_deviation"]) for r in furnace), 1)
    out["FurnaceExcessMax"] = up_to(max(float(r["max_excess"]) for r in furnace), 1, form="scientific")  # "by at most"
    out["FurnaceSize"] = f"{int(furnace[0]['width'])}"
    out["FurnaceDepth"] = f"{int(furnace[0]['depth'])}"
    thresholds = sorted({float(r["threshold"]) for r in furnace})
    if thresholds[0] != 0.0 or len(thresholds) != 2:
        raise ValueError("expected the exhaustive tree and one pruning threshold")
    out["FurnaceThreshold"] = f"{thresholds[1]:g}"
    foam = {float(r["threshold"]): int(r["rays_total"]) for r in furnace if r["case"] == "foam"}
    out["FoamRaysRatio"] = significant(foam[0.0] / foam[thresholds[1]], 2)
    absorbing = [r for r in rows if r["case"] == "absorbing_bubble"]
    out["AbsorbingRelDev"] = scientific(float(absorbing[0]["max_rel_deviation_closed_form"]), 1)
    pruning = {float(r["threshold"]): r for r in rows if r["case"] == "pruning_builtin"}
    p = pruning[thresholds[1]]
    out["PruneMeanDE"] = scientific(float(p["mean_de00"]), 1)
    out["PruneMaxDE"] = up_to(float(p["max_de00"]), 2)  # "at most"
    out["PruneRaysRatio"] = significant(int(pruning[0.0]["rays_total"]) / int(p["rays_total"]), 2)
    return out


ENERGY_MACROS = (["EnergyDate"] + [f"Furnace{w}" for w in FURNACE.values()]
                 + ["FurnaceMax", "FurnaceExcessMax", "FurnaceSize", "FurnaceDepth", "FurnaceThreshold",
                    "FoamRaysRatio", "AbsorbingRelDev", "PruneMeanDE", "PruneMaxDE", "PruneRaysRatio"])

SECTIONS = {
    "core": (["derived/throughput.csv"], core, CORE_MACROS),
    "energy": (["derived/energy.csv"], energy, ENERGY_MACROS),
}
