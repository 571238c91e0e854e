"""Macros of the coursework chapter: timing spread, thread scaling, the interval of b,
rays per level of the two bubble models.  A plug-in of ``make_numbers.py`` (``SECTIONS``, ``FLAGS``).

* ``courseworkspread``, ``courseworkthreads``: ``data/derived/coursework_table.csv``
  (``benchmarks/coursework_table.py``): the load average, the interquartile spread of the cells,
  the depth-1 cells that do identical work (pruned and exhaustive), the speed-up from 1 to 2 threads.
* ``courseworkbranch``: ``data/coursework_table_4_1.csv``: 95 % intervals of the growth base b of
  a + c·b^d fitted to the coursework's columns (:func:`study.fits.branching_interval`:
  covariance, profile likelihood, residual bootstrap).
* ``courseworkrays``: ``data/derived/coursework_rays.csv`` (``benchmarks/coursework_rays.py``):
  rays per tree level and times of the thin-film and the two-sphere bubbles.
"""

from __future__ import annotations

import math

import numpy as np

from macros import WORDS, at_least, date_of, group_digits, machine_of, plain, read_commented_csv, significant, up_to

GOLDEN = (1 + 5**0.5) / 2
LEVEL = 0.95
N_BOOT = 2000


def _timing(dirs):
    from study import load_timing

    return load_timing(dirs["derived"] / "coursework_table.csv")


def _load(notes, which):
    import re

    m = re.search(r"load average ([0-9.]+) before, ([0-9.]+) after", " ".join(notes))
    return m.group(1 if which == "before" else 2) if m else None


def spread(dirs):
    from study.coursework import identical_work_check, timing_spread

    timing = _timing(dirs)
    out = {}
    for which in ("before", "after"):
        value = _load(timing["notes"], which)
        if value is not None:
            out[f"OursLoad{which.capitalize()}"] = value
    half_iqr, full = [], []
    for nb in WORDS:
        for mode in ("pruned", "exhaustive"):
            _, med, lo, hi = timing_spread(timing, nb, mode)
            half_iqr += list(50 * (hi - lo) / med)
    runs = timing["seconds_runs"]
    med = np.nanmedian(runs, axis=1)
    full = 100 * (np.nanmax(runs, axis=1) - np.nanmin(runs, axis=1)) / med
    out["OursSpreadMedian"] = significant(float(np.median(half_iqr)), 2)
    out["OursSpreadMax"] = up_to(float(np.max(half_iqr)), 2)  # "at most"
    out["OursRangeMax"] = up_to(float(np.max(full)), 2)  # "up to"
    checks = identical_work_check(timing)
    ratios = [c["ratio"] for c in checks]
    out["IdenticalRatioMin"] = f"{min(ratios):.2f}"
    out["IdenticalRatioMax"] = f"{max(ratios):.2f}"
    out["IdenticalAgree"] = "1" if all(c["overlap"] for c in checks) else "0"
    out["IdenticalDisagreeCount"] = str(sum(not c["overlap"] for c in checks))
    # the depth-1 trees share their camera rays; the threshold drops low-throughput shadow rays
    diffs = [abs(c["rays_exhaustive"] - c["rays_pruned"]) / c["rays_exhaustive"] for c in checks]
    out["IdenticalRaysDiffMax"] = up_to(100 * max(diffs), 2)  # "by at most"
    for mode, name in (("pruned", "IdenticalShadowPrunedOne"), ("exhaustive", "IdenticalShadowExhaustiveOne")):
        out[name] = _shadow_rays(dirs, 1, 1, mode)
    return out


def _shadow_rays(dirs, bubbles, depth, mode):
    """The shadow rays of one cell of coursework_table.csv (grouped digits)."""
    _, rows = read_commented_csv(dirs["derived"] / "coursework_table.csv")
    for r in rows:
        if int(r["bubbles"]) == bubbles and int(r["depth"]) == depth and r["mode"] == mode:
            return group_digits(str(int(float(r["rays_shadow"]))))
    raise ValueError(f"no row for {bubbles} bubbles, depth {depth}, {mode}")


SPREAD_MACROS = ["OursLoadBefore", "OursLoadAfter", "OursSpreadMedian", "OursSpreadMax", "OursRangeMax",
                 "IdenticalRatioMin", "IdenticalRatioMax", "IdenticalAgree", "IdenticalDisagreeCount",
                 "IdenticalRaysDiffMax", "IdenticalShadowPrunedOne", "IdenticalShadowExhaustiveOne"]


def threads(dirs):
    timing = _timing(dirs)
    rows = {(r["bubbles"], r["depth"], r["mode"]): r for r in timing["extra"] if str(r["mode"]).startswith("threads")}
    ratios, low, high, depths = [], [], [], set()
    for (nb, depth, mode), one in rows.items():
        if mode != "threads 1" or (nb, depth, "threads 2") not in rows:
            continue
        two = rows[nb, depth, "threads 2"]
        ratios.append(one["seconds_median"] / two["seconds_median"])
        low.append(one["seconds_q1"] / two["seconds_q3"])
        high.append(one["seconds_q3"] / two["seconds_q1"])
        depths.add(int(depth))
    if not ratios:
        raise ValueError("no thread-scaling rows (threads 1 and threads 2)")
    return {"ThreadSpeedupMin": significant(min(ratios), 2, 2), "ThreadSpeedupMax": significant(max(ratios), 2, 2),
            "ThreadSpeedupLow": significant(min(low), 2, 2), "ThreadSpeedupHigh": significant(max(high), 2, 2),
            "ThreadDepths": " and ".join(str(d) for d in sorted(depths))}


THREAD_MACROS = ["ThreadSpeedupMin", "ThreadSpeedupMax", "ThreadSpeedupLow", "ThreadSpeedupHigh", "ThreadDepths"]


def _coursework_intervals(dirs, n_boot=N_BOOT):
    from study import load_coursework_table
    from study.fits import branching_interval

    table = load_coursework_table(dirs["data"] / "coursework_table_4_1.csv")
    return {nb: branching_interval(table["depth"], table["seconds"][nb], level=LEVEL, n_boot=n_boot)
            for nb in WORDS}


def branch(dirs):
    intervals = _coursework_intervals(dirs)
    out = {"GoldenRatio": f"{GOLDEN:.3f}", "BranchLevel": significant(100 * LEVEL, 2),
           "BranchBoot": group_digits(str(N_BOOT))}
    diffs = []
    for nb, word in WORDS.items():
        ci = intervals[nb]
        for key, (lo, hi) in (("", ci.profile), ("Wald", ci.wald), ("Boot", ci.bootstrap)):
            out[f"CourseworkBranch{key}Low{word}"] = f"{lo:.3f}"
            out[f"CourseworkBranch{key}High{word}"] = f"{hi:.3f}"
        ends = np.array([ci.profile, ci.wald, ci.bootstrap])
        diffs.append(float(np.max(ends.max(axis=0) - ends.min(axis=0))))
    # "agree to within", "intervals within LowMin--HighMax": rounded outwards
    out["CourseworkBranchMethodsDiff"] = up_to(max(diffs), 1)
    out["CourseworkBranchLowMin"] = at_least(min(i.profile[0] for i in intervals.values()), 4)
    out["CourseworkBranchHighMax"] = up_to(max(i.profile[1] for i in intervals.values()), 4)
    return out


BRANCH_MACROS = (["GoldenRatio", "BranchLevel", "BranchBoot", "CourseworkBranchMethodsDiff", "CourseworkBranchLowMin",
                  "CourseworkBranchHighMax"]
                 + [f"CourseworkBranch{k}{end}{w}" for k in ("", "Wald", "Boot") for end in ("Low", "High")
                    for w in WORDS.values()])


def rays(dirs):
    from study.coursework import load_rays, rays_series
    from study.fits import branching_interval

    data = load_rays(dirs["derived"] / "coursework_rays.csv")
    notes = data["notes"]
    out = {"RaysMachine": machine_of(notes), "RaysDate": date_of(notes),
           "RaysWidth": str(int(data["width"][0])), "RaysRepeats": str(data["seconds_runs"].shape[1])}
    for which in ("before", "after"):
        value = _load(notes, which)
        if value is not None:
            out[f"RaysLoad{which.capitalize()}"] = value
    thin, two_late = [], []
    cw = _coursework_intervals(dirs, n_boot=0)
    cw_low = min(i.profile[0] for i in cw.values())
    below, overlap_count = True, 0
    from study import load_coursework_table

    table = load_coursework_table(dirs["data"] / "coursework_table_4_1.csv")
    ten_times, ten_ratios = [], []
    for nb, word in WORDS.items():
        depth, br = rays_series(data, "thin film", nb, "branching")
        thin += list(br[np.isfinite(br)])
        depth, br = rays_series(data, "two spheres", nb, "branching")
        two_late += list(br[depth >= 7])
        out[f"RaysTwoBranchTen{word}"] = f"{br[depth == 10][0]:.3f}"
        _, level = rays_series(data, "two spheres", nb)
        out[f"RaysTwoLevelTen{word}"] = group_digits(str(int(level[-1])))
        _, total = rays_series(data, "two spheres", nb, "rays_total")
        out[f"RaysTwoTotalGrowth{word}"] = significant(total[-1] / total[0], 2)
        _, thin_total = rays_series(data, "thin film", nb, "rays_total")
        out[f"RaysThinTotalGrowth{word}"] = significant(thin_total[-1] / thin_total[0], 3)
        d, t = rays_series(data, "two spheres", nb, "seconds_median")
        out[f"TwoSphereTimeTen{word}"] = significant(t[-1], 2)
        out[f"TwoSphereTimeGrowth{word}"] = significant(t[-1] / t[0], 2)
        cw_ten = float(np.asarray(table["seconds"][nb])[np.asarray(table["depth"]) == d[-1]][0])
        ten_times.append(float(t[-1]))
        ten_ratios.append(cw_ten / float(t[-1]))
        ci = branching_interval(d, t, level=LEVEL, n_boot=0)
        out[f"TwoSphereTimeBranch{word}"] = f"{ci.b:.3f}"
        out[f"TwoSphereTimeBranchLow{word}"] = f"{ci.profile[0]:.3f}"
        out[f"TwoSphereTimeBranchHigh{word}"] = f"{ci.profile[1]:.3f}"
        own = cw[nb].profile
        overlap_count += bool(ci.profile[0] < own[1] and own[0] < ci.profile[1])
        ci_rays = branching_interval(d, total, level=LEVEL, n_boot=0)
        out[f"RaysTwoTotalBranch{word}"] = f"{ci_rays.b:.3f}"
        out[f"RaysTwoTotalBranchLow{word}"] = f"{ci_rays.profile[0]:.3f}"
        out[f"RaysTwoTotalBranchHigh{word}"] = f"{ci_rays.profile[1]:.3f}"
        below = below and ci_rays.profile[1] < cw_low
    # the like-for-like comparison: the coursework's depth-10 times over our two-sphere trees'
    out["TwoSphereTimeTenMin"] = significant(min(ten_times), 2)
    out["TwoSphereTimeTenMax"] = significant(max(ten_times), 2)
    out["TwoSphereSpeedupTenMin"] = significant(min(ten_ratios), 2)
    out["TwoSphereSpeedupTenMax"] = significant(max(ten_ratios), 2)
    out["RaysThinBranchMin"] = f"{min(thin):.3f}"
    out["RaysThinBranchMax"] = f"{max(thin):.3f}"
    out["RaysTwoBranchLateMin"] = f"{min(two_late):.3f}"
    out["RaysTwoBranchLateMax"] = f"{max(two_late):.3f}"
    out["TwoSphereRaysBelowCoursework"] = "1" if below else "0"
    out["TwoSphereTimeOverlapCount"] = str(overlap_count)
    out["GoldenBelowCoursework"] = "1" if GOLDEN < cw_low else "0"
    return out


def two_sphere_scene(dirs):
    """The two-sphere bubble's radii and index, from its scene file."""
    import tracer

    scene = tracer.load_scene(dirs["data"] / "scenes" / "coursework_two_sphere_one_bubble.txt")
    outer, inner = sorted(scene.spheres, key=lambda s: -s.radius)
    return {"TwoSphereOuterRadius": plain(outer.radius), "TwoSphereInnerRadius": plain(inner.radius),
            "TwoSphereIndex": plain(outer.material.ior)}


RAYS_MACROS = (["RaysMachine", "RaysDate", "RaysWidth", "RaysRepeats", "RaysLoadBefore", "RaysLoadAfter",
                "RaysThinBranchMin", "RaysThinBranchMax", "RaysTwoBranchLateMin", "RaysTwoBranchLateMax",
                "TwoSphereRaysBelowCoursework", "TwoSphereTimeOverlapCount", "GoldenBelowCoursework",
                "TwoSphereTimeTenMin", "TwoSphereTimeTenMax", "TwoSphereSpeedupTenMin", "TwoSphereSpeedupTenMax"]
               + [f"{k}{w}" for k in ("RaysTwoBranchTen", "RaysTwoLevelTen", "RaysTwoTotalGrowth", "RaysThinTotalGrowth",
                                      "TwoSphereTimeTen", "TwoSphereTimeGrowth", "TwoSphereTimeBranch",
                                      "TwoSphereTimeBranchLow", "TwoSphereTimeBranchHigh", "RaysTwoTotalBranch",
                                      "RaysTwoTotalBranchLow", "RaysTwoTotalBranchHigh") for w in WORDS.values()])

SECTIONS = {
    "courseworktwosphere": (["data/scenes/coursework_two_sphere_one_bubble.txt"], two_sphere_scene,
                            ["TwoSphereOuterRadius", "TwoSphereInnerRadius", "TwoSphereIndex"]),
    "courseworkspread": (["derived/coursework_table.csv"], spread, SPREAD_MACROS),
    "courseworkthreads": (["derived/coursework_table.csv"], threads, THREAD_MACROS),
    "courseworkbranch": (["data/coursework_table_4_1.csv"], branch, BRANCH_MACROS),
    "courseworkrays": (["derived/coursework_rays.csv", "data/coursework_table_4_1.csv"], rays, RAYS_MACROS),
}

FLAGS = {"IdenticalAgree": "0", "TwoSphereRaysBelowCoursework": "0", "GoldenBelowCoursework": "0"}


def throughput(dirs):
    """The speed-up from 1 to 2 threads of the coursework scenes in ``benchmarks/throughput.py``'s run."""
    notes, rows = read_commented_csv(dirs["derived"] / "throughput.csv")
    values = [float(r["speedup_1_to_2_threads"]) for r in rows
              if r["case"].startswith("coursework_") and r["speedup_1_to_2_threads"].strip()]
    if not values:
        raise ValueError("no coursework rows with speedup_1_to_2_threads")
    return {"ThroughputSpeedupMin": significant(min(values), 2, 2), "ThroughputSpeedupMax": significant(max(values), 2, 2),
            "ThroughputDate": date_of(notes)}


SECTIONS["courseworkthroughput"] = (["derived/throughput.csv"], throughput,
                                    ["ThroughputSpeedupMin", "ThroughputSpeedupMax", "ThroughputDate"])
