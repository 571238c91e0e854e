"""Mitsuba 3 against our tracer, a plug-in of ``make_numbers.py``.

* ``peer``: ``data/derived/peer_mitsuba.csv`` (``benchmarks/peer_mitsuba.py``, optional Mitsuba),
  times to equal error by :func:`study.time_at_error` (as that benchmark).
"""

from __future__ import annotations

import re

import numpy as np

from macros import NA, date_of, group_digits, read_commented_csv, scientific, significant

#: where these macros stand in numbers.tex (make_numbers.py)
ORDER = 9


PEER_CURVES = {
    "OursExhaustive": ("ours", "exhaustive", "stratified"),
    "OursPruned": ("ours", "pruned", "stratified"),
    "MitsubaStratified": ("mitsuba", "llvm_ad_rgb", "stratified"),
    "MitsubaIndependent": ("mitsuba", "llvm_ad_rgb", "independent"),
    "MitsubaScalar": ("mitsuba", "scalar_rgb", "stratified"),
}


PEER_TARGET_SPP = 4  # the error ours reaches at this many samples per pixel is the target (as the benchmark)

#: thread counts of the sweeps -> macro suffix (every renderer ran at each; the CSV's column threads)
PEER_THREADS = {1: "OneThread", 2: "TwoThreads"}


def peer_curves(sweep, threads):
    """{PEER_CURVES key: rows sorted by spp} of the sweep at *threads* threads."""
    curves = {}
    for key, ident in PEER_CURVES.items():
        curve = sorted((r for r in sweep if (r["renderer"], r["variant"], r["sampler"]) == ident
                        and int(r["threads"]) == threads), key=lambda r: int(r["spp"]))
        if not curve:
            raise ValueError(f"no rows for {ident} at {threads} threads")
        curves[key] = curve
    return curves


def ratio_range(slow, fast, metric):
    """(smallest, largest) time ratio slow / fast at equal *metric* over every error both reach
    (:func:`study.fronts.time_ratio_curve`)."""
    from study.fronts import time_ratio_curve

    _, ratios = time_ratio_curve(([float(r["seconds"]) for r in slow], [float(r[metric]) for r in slow]),
                                 ([float(r["seconds"]) for r in fast], [float(r[metric]) for r in fast]))
    ratios = ratios[np.isfinite(ratios)]
    if ratios.size == 0:
        raise ValueError(f"the curves share no {metric} range")
    return float(ratios.min()), float(ratios.max())


def peer(dirs):
    """Mitsuba 3 against our tracer (``benchmarks/peer_mitsuba.py``): time to the error ours
    reaches at 4 spp, by the log-log interpolation the benchmark uses
    (:func:`study.time_at_error`)."""
    from study import time_at_error

    notes, rows = read_commented_csv(dirs["derived"] / "peer_mitsuba.csv")
    sweep = [r for r in rows if r["role"] == "sweep"]
    if "threads" not in sweep[0]:
        raise ValueError("peer_mitsuba.csv has no threads column: run benchmarks/peer_mitsuba.py again")
    curves = peer_curves(sweep, max(PEER_THREADS))  # the headline figures: every core, as the figure's (a), (b)
    out = {"PeerDate": date_of(notes)}
    m = re.search(r"mitsuba (\d+(?:\.\d+)+)", " ".join(notes))
    out["PeerVersion"] = m.group(1) if m else NA
    first = sweep[0]
    out["PeerSize"] = str(int(first["width"]))
    out["PeerDepth"] = str(int(first["depth"]))
    mref = next(r for r in rows if r["role"] == "reference" and r["renderer"] == "mitsuba")
    oref = next(r for r in rows if r["role"] == "reference" and r["renderer"] == "ours")
    out["PeerRefSpp"] = group_digits(str(int(mref["spp"])))
    out["PeerOursRefSpp"] = str(int(oref["spp"]))
    out["PeerFloorRmse"] = scientific(float(oref["rmse"]), 2)
    out["PeerFloorDe"] = significant(float(oref["mean_de00"]), 2)
    four = next(r for r in curves["OursExhaustive"] if int(r["spp"]) == PEER_TARGET_SPP)
    out["PeerTargetSpp"] = str(PEER_TARGET_SPP)
    m = re.search(r"glass sphere n = ([0-9.]+)", " ".join(notes))
    out["PeerGlassIndex"] = m.group(1) if m else NA
    m = re.search(r"or ([0-9.e+-]+) \(pruned\)", " ".join(notes))
    out["PeerPrunedThreshold"] = scientific(float(m.group(1)), 1) if m else NA
    m = re.search(r"other processes used <= (\d+)% of the CPUs", " ".join(notes))
    out["PeerCleanSharePercent"] = m.group(1) if m else NA
    # run-to-run spread of the timed configurations: the largest (max - min) / median over them
    spreads = []
    for row in sweep:
        runs = [float(x) for x in row.get("seconds_runs", "").split()]
        if len(runs) >= 2:
            spreads.append((max(runs) - min(runs)) / float(row["seconds"]))
    out["PeerSpreadMedianPercent"] = significant(100 * sorted(spreads)[len(spreads) // 2], 2) if spreads else NA
    for metric, tag in (("rmse", "Rmse"), ("mean_de00", "De")):
        target = float(four[metric])
        out[f"PeerTarget{tag}"] = scientific(target, 2) if metric == "rmse" else significant(target, 2)
        for key, curve in curves.items():
            t = time_at_error([float(r["seconds"]) for r in curve], [float(r[metric]) for r in curve], target)
            out[f"Peer{tag}{key}"] = significant(t, 2)
    # Mitsuba's best (LLVM, stratified) against ours, at the RMSE target: ratios of the times
    for key in ("OursExhaustive", "OursPruned"):
        t_ours = time_at_error([float(r["seconds"]) for r in curves[key]], [float(r["rmse"]) for r in curves[key]],
                               float(four["rmse"]))
        t_mi = time_at_error([float(r["seconds"]) for r in curves["MitsubaStratified"]],
                             [float(r["rmse"]) for r in curves["MitsubaStratified"]], float(four["rmse"]))
        out[f"PeerRatioRmse{key}"] = significant(t_mi / t_ours, 2)
    # like for like: Mitsuba's best against ours over every error both curves reach, per thread count
    for threads, suffix in PEER_THREADS.items():
        at = peer_curves(sweep, threads)
        for metric, tag in (("rmse", "Rmse"), ("mean_de00", "De")):
            for key in ("OursExhaustive", "OursPruned"):
                low, high = ratio_range(at["MitsubaStratified"], at[key], metric)
                out[f"PeerRange{tag}{key}{suffix}Low"] = significant(low, 2)
                out[f"PeerRange{tag}{key}{suffix}High"] = significant(high, 2)
    # 1 -> 2 threads: each renderer's speed-up at the largest sample count both curves have
    one = peer_curves(sweep, min(PEER_THREADS))
    for key in ("OursExhaustive", "MitsubaStratified", "MitsubaScalar"):
        spp = min(int(one[key][-1]["spp"]), int(curves[key][-1]["spp"]))
        one_t = next(float(r["seconds"]) for r in one[key] if int(r["spp"]) == spp)
        two_t = next(float(r["seconds"]) for r in curves[key] if int(r["spp"]) == spp)
        out[f"PeerSpeedup{key}"] = significant(one_t / two_t, 2)
    # what the curves are made of: seconds per sample per pixel, and samples needed for the target
    per_spp = {k: float(c[-1]["seconds"]) / int(c[-1]["spp"]) for k, c in curves.items()}
    out["PeerSampleCostRatio"] = significant(per_spp["OursExhaustive"] / per_spp["MitsubaStratified"], 2)
    mi = curves["MitsubaStratified"]
    spp_needed = time_at_error([int(r["spp"]) for r in mi], [float(r["rmse"]) for r in mi], float(four["rmse"]))
    out["PeerSampleCountRatio"] = significant(spp_needed / 4, 2)
    out["PeerMitsubaSppNeeded"] = significant(spp_needed, 2)
    return out


PEER_MACROS = (
    ["PeerDate", "PeerVersion", "PeerSize", "PeerDepth", "PeerTargetSpp", "PeerGlassIndex", "PeerPrunedThreshold",
     "PeerCleanSharePercent", "PeerSpreadMedianPercent", "PeerRatioRmseOursExhaustive", "PeerRatioRmseOursPruned",
     "PeerRefSpp", "PeerOursRefSpp", "PeerFloorRmse", "PeerFloorDe", "PeerTargetRmse", "PeerTargetDe",
     "PeerSampleCostRatio", "PeerSampleCountRatio",
     "PeerMitsubaSppNeeded"]
    + [f"Peer{tag}{k}" for tag in ("Rmse", "De") for k in PEER_CURVES]
    + [f"PeerRange{tag}{k}{suffix}{end}" for tag in ("Rmse", "De") for k in ("OursExhaustive", "OursPruned")
       for suffix in PEER_THREADS.values() for end in ("Low", "High")]
    + [f"PeerSpeedup{k}" for k in ("OursExhaustive", "MitsubaStratified", "MitsubaScalar")]
)

SECTIONS = {
    "peer": (["derived/peer_mitsuba.csv"], peer, PEER_MACROS),
}
