"""The numbers of the film-flow chapter (paper/sections/film_flow.tex), a plug-in of make_numbers.py.

* ``filmflowverif``: ``data/derived/film_flow_verification.csv`` (``benchmarks/film_flow_verification.py``):
  the checks of ``tests/bubbleoptics/test_film_flow.py`` on more grids, the black-film time and the frames;
* ``filmflowspeed``: ``data/derived/film_flow.csv`` (``benchmarks/film_flow.py``): ms a step, steps
  per second, the target, and the cost of a 10-s movie;
* ``filmflowparams``: :class:`bubbleoptics.filmflow.FilmParameters` (the cited defaults) and the
  black-film threshold of the benchmark (computed, no data file);
* ``filmflowdt``: ``data/derived/film_flow_dt.csv`` (``benchmarks/film_flow_verification.py --only dt``):
  the black-film time and the apex at a fixed time against the step, the observed orders and
  Richardson's estimates, on the study's grid and on the black-film run's;
* ``filmflowevap``: ``data/derived/film_flow_evaporation.csv`` (``--only evaporation``): the
  black-film time at each multiple of the cited evaporation rate, its ratio to h_eq(0)/E and the
  share of the apex's thinning that evaporation does.
"""

from __future__ import annotations

import math
import re

from macros import NA, date_of, machine_of, read_commented_csv, scientific, significant, up_to


def _grid_tex(grid):
    n_theta, n_phi = grid.split("x")
    return rf"\ensuremath{{{n_theta}\times{n_phi}}}"


def _value(rows, check, quantity, grid=None):
    found = [r for r in rows if r["check"] == check and r["quantity"] == quantity and (grid is None or r["grid"] == grid)]
    if len(found) != 1:
        raise ValueError(f"expected one row {check}/{quantity}/{grid}, found {len(found)}")
    return float(found[0]["value"])


def _series(rows, check, quantity):
    """{n_theta: value} of the rows of one check (grids 'NxM')."""
    return {int(r["grid"].split("x")[0]): float(r["value"]) for r in rows
            if r["check"] == check and r["quantity"] == quantity}


def verification(dirs):
    notes, rows = read_commented_csv(dirs["derived"] / "film_flow_verification.csv")
    if any("QUICK MODE" in n for n in notes):
        raise ValueError("film_flow_verification.csv was written in quick mode")
    out = {"FfVerifDate": date_of(notes), "FfVerifMachine": machine_of(notes)}
    apex = _series(rows, "apex", "max_relative_error")
    prof = _series(rows, "profile", "max_abs_error_h_over_h0")
    eq = _series(rows, "equilibrium", "max_relative_error")
    tr = _series(rows, "transient", "max_abs_difference_h_over_h0")
    for prefix, errors in (("Apex", apex), ("Profile", prof), ("Eq", eq), ("Transient", tr)):
        ns = sorted(errors)
        out[f"Ff{prefix}RowsMin"] = str(ns[0])
        out[f"Ff{prefix}RowsMax"] = str(ns[-1])
        out[f"Ff{prefix}ErrCoarse"] = scientific(errors[ns[0]], 2)
        out[f"Ff{prefix}ErrFine"] = scientific(errors[ns[-1]], 2)
        orders = [math.log2(errors[a] / errors[b]) for a, b in zip(ns, ns[1:])]
        out[f"Ff{prefix}OrderMin"] = significant(min(orders), 2, 2) if min(orders) < 10 else significant(min(orders))
        out[f"Ff{prefix}OrderMax"] = significant(max(orders), 2, 2) if max(orders) < 10 else significant(max(orders))
        out[f"Ff{prefix}OrderLast"] = significant(orders[-1], 2, 2)
        lo, hi = out[f"Ff{prefix}OrderMin"], out[f"Ff{prefix}OrderMax"]
        out[f"Ff{prefix}Orders"] = lo if lo == hi else f"{lo}--{hi}"  # one value when they round alike
    out["FfTransientCoarseGrid"] = _grid_tex(f"{min(tr)}x{2 * min(tr)}")
    out["FfTransientFineGrid"] = _grid_tex(f"{max(tr) * 2}x{max(tr) * 4}")
    out["FfApexErrSixtyFour"] = scientific(apex[64], 2)
    out["FfTauS"] = significant(_value(rows, "apex", "drainage_time"), 4)
    for name, key in (("FfConsRigidVolume", "rigid_volume_per_step"), ("FfConsPlugVolume", "plug_volume_per_step"),
                      ("FfConsPlugSurfactant", "plug_surfactant_per_step"), ("FfEvapRigid", "rigid_evaporated"),
                      ("FfEvapPlug", "plug_evaporated")):
        out[name] = scientific(_value(rows, "conservation", key), 2)
    cons_grid = [r["grid"] for r in rows if r["quantity"] == "plug_volume_per_step"]
    out["FfConsPlugGrid"] = _grid_tex(cons_grid[0])
    # the black film
    black = {r["quantity"]: r for r in rows if r["check"] == "black"}
    grid = black["t_apex"]["grid"]
    out["FfBlackGrid"] = _grid_tex(grid)
    out["FfBlackDtMs"] = significant(1e3 * float(black["dt"]["value"]), 2)
    out["FfBlackNm"] = significant(float(black["threshold"]["value"]), 2)
    t_apex = float(black["t_apex"]["value"])
    for name, key in (("FfBlackApexS", "t_apex"), ("FfBlackFirstS", "t_first"), ("FfBlackAllS", "t_all"),
                      ("FfUniformS", "t_uniform"), ("FfEqApexS", "t_equilibrium_apex"), ("FfBlackEndS", "t_end")):
        out[name] = significant(float(black[key]["value"]), 3)
    out["FfBlackOverUniform"] = significant(t_apex / float(black["t_uniform"]["value"]), 2, 2)
    out["FfBlackOverEqApex"] = significant(t_apex / float(black["t_equilibrium_apex"]["value"]), 3)
    rigid = float(black["t_rigid"]["value"])
    out["FfRigidBlackDays"] = significant(rigid / 86400.0, 2)
    out["FfRigidBlackTau"] = significant(rigid / _value(rows, "apex", "drainage_time"), 2)
    out["FfBlackRunS"] = significant(float(black["run_wall_seconds"]["value"]), 2)
    out["FfBlackSteps"] = significant(float(black["steps"]["value"]), 4)
    # the frames
    frames = {r["quantity"]: r for r in rows if r["check"] == "frames" and r["quantity"] != "time"}
    out["FfFrameSize"] = str(int(float(frames["size"]["value"])))
    out["FfFrameCount"] = str(int(float(frames["count"]["value"])))
    out["FfFrameDepth"] = str(int(float(frames["depth"]["value"])))
    for name, key in (("FfFrameSecMedian", "render_seconds_median"), ("FfFrameSecMin", "render_seconds_min"),
                      ("FfFrameSecMax", "render_seconds_max")):
        out[name] = significant(float(frames[key]["value"]), 2)
    load = re.search(r"load average ([0-9.]+) at the start, ([0-9.]+) at the end", notes[0])
    if load:
        out["FfVerifLoadStart"], out["FfVerifLoadEnd"] = load.group(1), load.group(2)
    return out


VERIFICATION_MACROS = ["FfVerifDate", "FfVerifMachine", "FfVerifLoadStart", "FfVerifLoadEnd"] + [
    f"Ff{p}{s}" for p in ("Apex", "Profile", "Eq", "Transient")
    for s in ("RowsMin", "RowsMax", "ErrCoarse", "ErrFine", "OrderMin", "OrderMax", "OrderLast", "Orders")] + [
    "FfTransientCoarseGrid", "FfTransientFineGrid", "FfApexErrSixtyFour", "FfTauS", "FfConsRigidVolume",
    "FfConsPlugVolume", "FfConsPlugSurfactant", "FfEvapRigid", "FfEvapPlug", "FfConsPlugGrid", "FfBlackGrid",
    "FfBlackDtMs", "FfBlackNm", "FfBlackApexS", "FfBlackFirstS", "FfBlackAllS", "FfUniformS", "FfEqApexS",
    "FfBlackEndS", "FfBlackOverUniform", "FfBlackOverEqApex", "FfRigidBlackDays", "FfRigidBlackTau", "FfBlackRunS",
    "FfBlackSteps", "FfFrameSize", "FfFrameCount", "FfFrameDepth", "FfFrameSecMedian", "FfFrameSecMin",
    "FfFrameSecMax"]


def speed(dirs):
    notes, rows = read_commented_csv(dirs["derived"] / "film_flow.csv")
    target = re.search(r"target: (\d+)x(\d+) plug flow at >= ([0-9.]+) steps/s", " ".join(notes))
    if not target:
        raise ValueError("no target in film_flow.csv's header")
    grid, goal = f"{target.group(1)}x{target.group(2)}", float(target.group(3))

    def row(model, grid_, threads):
        found = [r for r in rows if r["model"] == model and r["grid"] == grid_ and int(r["threads"]) == threads]
        if len(found) != 1:
            raise ValueError(f"expected one row {model} {grid_} {threads} threads, found {len(found)}")
        return found[0]

    threads = sorted({int(r["threads"]) for r in rows})
    one, most = row("plug_flow", grid, 1), row("plug_flow", grid, max(threads))
    rigid = row("rigid_drainage", grid, 1)
    load = re.search(r"load average ([0-9.]+) at the start, ([0-9.]+) at the end", notes[0])
    out = {
        "FfSpeedDate": date_of(notes), "FfSpeedMachine": machine_of(notes),
        "FfTargetGrid": _grid_tex(grid), "FfTargetSteps": significant(goal, 3),
        "FfStepMs": significant(1e3 * float(one["step_seconds_median"]), 2),
        "FfStepMsMin": significant(1e3 * float(one["step_seconds_min"]), 2),
        "FfStepMsMax": significant(1e3 * float(one["step_seconds_max"]), 2),
        "FfCpuMs": significant(1e3 * float(one["step_cpu_seconds_median"]), 2),
        "FfStepsPerS": significant(float(one["steps_per_second"]), 3),
        "FfStepsPerSMin": significant(1 / float(one["step_seconds_max"]), 3),
        "FfStepsPerSMax": significant(1 / float(one["step_seconds_min"]), 3),
        "FfStepsPerSMost": significant(float(most["steps_per_second"]), 3),
        "FfMostThreads": str(max(threads)),
        "FfRigidStepsPerS": significant(float(rigid["steps_per_second"]), 3),
        "FfSimPerWall": significant(float(one["simulated_seconds_per_wall_second"]), 2),
        "FfMovieSimS": significant(float(most["movie_sim_seconds"]), 2),
        "FfMovieRenderS": significant(float(most["movie_render_seconds"]), 3),
        "FfMovieFrames": str(int(float(most["movie_frames"]))),
        "FfRenderFrameMin": significant(float(most["movie_render_frame_seconds_min"]), 2),
        "FfRenderFrameMax": significant(float(most["movie_render_frame_seconds_max"]), 2),
        "FfSpeedLoadStart": load.group(1) if load else None,
        "FfSpeedLoadEnd": load.group(2) if load else None,
    }
    m = re.search(r"at (\d+)x(\d+) \(", " ".join(notes))
    if m:
        out["FfMovieSize"] = rf"\ensuremath{{{m.group(1)}\times{m.group(2)}}}"
    out["FfTargetMet"] = "1" if float(one["steps_per_second"]) >= goal else "0"
    return {k: v for k, v in out.items() if v is not None}


SPEED_MACROS = ["FfSpeedDate", "FfSpeedMachine", "FfTargetGrid", "FfTargetSteps", "FfStepMs", "FfStepMsMin",
                "FfStepMsMax", "FfCpuMs", "FfStepsPerS", "FfStepsPerSMin", "FfStepsPerSMax", "FfStepsPerSMost",
                "FfMostThreads", "FfRigidStepsPerS", "FfSimPerWall", "FfMovieSimS", "FfMovieRenderS", "FfMovieFrames",
                "FfRenderFrameMin", "FfRenderFrameMax", "FfSpeedLoadStart", "FfSpeedLoadEnd", "FfMovieSize",
                "FfTargetMet"]


def parameters(dirs):
    from bubbleoptics.filmflow import FilmParameters

    p = FilmParameters()
    return {
        "FfRadiusCm": significant(100 * p.radius, 2),
        "FfHzeroUm": significant(1e6 * p.h0, 2),
        "FfEvaporation": scientific(p.evaporation, 1),
        "FfSurfactant": scientific(p.surfactant, 1),
        "FfExponent": significant(p.equilibrium_exponent, 2),
        "FfPerturbation": significant(p.perturbation, 1),
    }


PARAMETER_MACROS = ["FfRadiusCm", "FfHzeroUm", "FfEvaporation", "FfSurfactant", "FfExponent", "FfPerturbation"]

def _float(text):
    return float(text) if text not in ("", None) else math.nan


def _ms(seconds):
    """A step of the studies in ms, as the benchmark sets it (0.3125, 1.25, 40): a setting, not rounded."""
    return f"{1e3 * seconds:.6g}"


def _signed(x, n=2, min_decimals=2):
    """:func:`significant`, with a negative number's minus in math mode (a minus sign, not a hyphen)."""
    text = significant(x, n, min_decimals)
    return rf"\ensuremath{{-{text[1:]}}}" if text.startswith("-") else text


#: the grids of the time-step study, by their role: STUDY reaches the asymptotic range, BLACK is
#: the black-film run's grid of film_flow_verification.csv
DT_GRIDS = {"": "64x128", "Black": "128x256"}


def dt_study(dirs):
    """The time-step study (``film_flow_dt.csv``)."""
    from bubbleoptics.filmflow import FilmParameters

    notes, rows = read_commented_csv(dirs["derived"] / "film_flow_dt.csv")
    if any("QUICK MODE" in n for n in notes):
        raise ValueError("film_flow_dt.csv was written in quick mode")
    out = {"FfDtDate": date_of(notes), "FfDtMachine": machine_of(notes)}
    p = FilmParameters()
    # the Gibbs (Marangoni) waves of the plug flow: c^2 = 2 R_g T Gamma_0 / (rho h0) = E_G / (rho h0)
    wave = math.sqrt(p.gibbs_elasticity / (p.density * p.h0))
    out["FfGibbsWaveSpeed"] = significant(wave, 2)
    richardson = {}
    for role, grid in DT_GRIDS.items():
        runs = sorted((r for r in rows if r["grid"] == grid), key=lambda r: -float(r["dt_s"]))
        if len(runs) < 3:
            raise ValueError(f"film_flow_dt.csv: fewer than three steps on {grid}")
        n_theta = int(grid.split("x")[0])
        dts = [float(r["dt_s"]) for r in runs]
        t_apex = [float(r["t_apex_s"]) for r in runs]
        probe = [float(r["apex_probe_nm"]) for r in runs]
        pre = f"FfDt{role}"
        out[f"{pre}Grid"] = _grid_tex(grid)
        out[f"{pre}Count"] = str(len(runs))
        out[f"{pre}StepMaxMs"] = _ms(dts[0])
        out[f"{pre}StepMinMs"] = _ms(dts[-1])
        out[f"{pre}CellMs"] = significant(1e3 * p.radius * math.pi / n_theta / wave, 2)
        out[f"{pre}ApexCoarseS"] = significant(t_apex[0], 4)
        out[f"{pre}ApexFineS"] = significant(t_apex[-1], 4)
        default = [t for dt, t in zip(dts, t_apex) if abs(dt - 0.01) < 1e-12]
        if default:
            out[f"{pre}ApexDefaultS"] = significant(default[0], 4)
            out[f"{pre}DefaultMinusFineS"] = significant(default[0] - t_apex[-1], 2)
        out[f"{pre}ApexSpreadS"] = significant(max(t_apex) - min(t_apex), 2)
        out[f"{pre}ApexSpreadPercent"] = significant(100 * (max(t_apex) - min(t_apex)) / min(t_apex), 2)
        out[f"{pre}ApexLastDiffS"] = significant(abs(t_apex[-2] - t_apex[-1]), 2)
        orders = [_float(r["order_t_apex"]) for r in runs[2:]]
        probe_orders = [_float(r["order_apex_probe"]) for r in runs[2:]]
        out[f"{pre}OrderApexLast"] = _signed(orders[-1])
        # the orders of the longer steps: every triple but the finest
        out[f"{pre}OrderApexMin"] = _signed(min(orders[:-1]))
        out[f"{pre}OrderApexMax"] = _signed(max(orders[:-1]))
        out[f"{pre}OrderProbeLast"] = _signed(probe_orders[-1])
        out[f"{pre}ProbeFineNm"] = significant(probe[-1], 4)
        out[f"{pre}ProbeCoarseNm"] = significant(probe[0], 4)
        out[f"{pre}OrderLastPositive"] = "1" if orders[-1] > 0 else "0"
        rich = _float(runs[-1]["richardson_t_apex_s"])
        richardson[role] = rich
        if role == "" and math.isfinite(rich):
            out[f"{pre}RichardsonApexS"] = significant(rich, 4)
            out[f"{pre}FineMinusRichardsonS"] = significant(t_apex[-1] - rich, 2)
            if default:
                out[f"{pre}DefaultMinusRichardsonS"] = significant(default[0] - rich, 2)
                out[f"{pre}DefaultOverRichardsonPercent"] = significant(100 * (default[0] / rich - 1), 2)
        rich_probe = _float(runs[-1]["richardson_apex_probe_nm"])
        if role == "" and math.isfinite(rich_probe):
            out[f"{pre}RichardsonProbeNm"] = significant(rich_probe, 4)
    out["FfDtProbeS"] = significant(float(rows[0]["probe_s"]), 2)
    out["FfDtRichardsonOverEqApex"] = NA
    if math.isfinite(richardson.get("", math.nan)):
        heq_time = _equilibrium_apex_nm(p) * 1e-9 / p.evaporation
        out["FfDtRichardsonOverEqApex"] = significant(richardson[""] / heq_time, 4)
    return {k: v for k, v in out.items() if v != NA}


def _equilibrium_apex_nm(p):
    a = p.equilibrium_exponent
    return p.h0 * 1e9 * a / math.sinh(a) * math.exp(-a)


DT_SUFFIXES = ("Grid", "Count", "StepMaxMs", "StepMinMs", "CellMs", "ApexCoarseS", "ApexFineS", "ApexDefaultS",
               "DefaultMinusFineS", "ApexSpreadS", "ApexSpreadPercent", "ApexLastDiffS", "OrderApexLast",
               "OrderApexMin", "OrderApexMax", "OrderProbeLast", "ProbeFineNm", "ProbeCoarseNm", "OrderLastPositive")
#: Richardson's estimates: on the study's grid only (on the black-film grid the steps run do not
#: reach the asymptotic range, and the text says so)
RICHARDSON_SUFFIXES = ("RichardsonApexS", "FineMinusRichardsonS", "DefaultMinusRichardsonS",
                       "DefaultOverRichardsonPercent", "RichardsonProbeNm")
DT_MACROS = ["FfDtDate", "FfDtMachine", "FfGibbsWaveSpeed", "FfDtProbeS", "FfDtRichardsonOverEqApex"] + [
    f"FfDt{role}{suffix}" for role in DT_GRIDS for suffix in DT_SUFFIXES] + [f"FfDt{s}" for s in RICHARDSON_SUFFIXES]

#: the evaporation multiples, by macro word
MULTIPLES = {"Quarter": 0.25, "Half": 0.5, "One": 1.0, "Two": 2.0, "Four": 4.0}
#: the evaporation study's runs, by role: "" the small-step run (time-converged), "Black" the
#: black-film run's grid and step
EVAP_RUNS = {"": ("32x64", 0.000625), "Black": ("128x256", 0.01)}


def evaporation_study(dirs):
    """The evaporation study (``film_flow_evaporation.csv``)."""
    notes, rows = read_commented_csv(dirs["derived"] / "film_flow_evaporation.csv")
    if any("QUICK MODE" in n for n in notes):
        raise ValueError("film_flow_evaporation.csv was written in quick mode")
    out = {"FfEvDate": date_of(notes), "FfEvMachine": machine_of(notes)}
    zero_s = re.search(r"E = 0 runs ([0-9.]+) s", " ".join(notes))
    threshold = float(re.search(r"threshold ([0-9.]+) nm", " ".join(notes)).group(1))
    for role, (grid, dt) in EVAP_RUNS.items():
        runs = {float(r["evaporation_multiple"]): r for r in rows
                if r["grid"] == grid and abs(float(r["dt_s"]) - dt) < 1e-12}
        pre = f"FfEv{role}"
        out[f"{pre}Grid"] = _grid_tex(grid)
        out[f"{pre}StepMs"] = _ms(dt)
        ratios, shares = [], []
        for word, m in MULTIPLES.items():
            r = runs[m]
            out[f"{pre}T{word}S"] = significant(float(r["t_apex_s"]), 3)
            out[f"{pre}Eq{word}S"] = significant(float(r["t_eq_apex_s"]), 3)
            ratios.append(float(r["t_apex_over_t_eq_apex"]))
            out[f"{pre}Ratio{word}"] = significant(ratios[-1], 4)
            shares.append(float(r["evaporated_share"]))
            out[f"{pre}Share{word}Percent"] = significant(100 * shares[-1], 2)
        out[f"{pre}RatioMin"] = significant(min(ratios), 4)
        out[f"{pre}RatioMax"] = significant(max(ratios), 4)
        out[f"{pre}SharePercentMin"] = significant(100 * min(shares), 2)
        out[f"{pre}SharePercentMax"] = significant(100 * max(shares), 2)
        out[f"{pre}DrainPercentMin"] = significant(100 * (1 - max(shares)), 2)
        out[f"{pre}DrainPercentMax"] = significant(100 * (1 - min(shares)), 2)
        # E t_black is nearly constant: the black time is inversely proportional to E
        et = [m * float(runs[m]["t_apex_s"]) for m in MULTIPLES.values()]
        out[f"{pre}ETSpreadPercent"] = up_to(100 * (max(et) - min(et)) / min(et), 2)  # after "within"
        zero = runs.get(0.0)
        if zero is not None:
            if math.isfinite(_float(zero["t_apex_s"])):
                raise ValueError("film_flow_evaporation.csv: the film without evaporation turned black")
            out[f"{pre}ZeroApexNm"] = significant(float(zero["apex_end_nm"]), 3)
            out[f"{pre}ZeroHeqNm"] = significant(float(zero["h_eq_apex_nm"]), 3)
            out[f"{pre}ZeroMinusHeqPercent"] = significant(
                100 * (float(zero["apex_end_nm"]) / float(zero["h_eq_apex_nm"]) - 1), 2)
            out[f"{pre}ZeroS"] = significant(float(zero["t_end_s"]), 3)
        cited = runs[1.0]
        out[f"{pre}ApexStartNm"] = significant(float(cited["apex_start_nm"]), 4)
        # drainage at the apex with the cited E: its most (early) and its net at the black-film time
        net = float(cited["apex_start_nm"]) - threshold - float(cited["evaporation_m_per_s"]) * 1e9 * float(cited["t_apex_s"])
        if "drained_peak_nm" in cited:
            out[f"{pre}DrainedPeakNm"] = significant(float(cited["drained_peak_nm"]), 3)
            out[f"{pre}DrainedPeakS"] = significant(float(cited["t_drained_peak_s"]), 3)
        out[f"{pre}DrainedNetNm"] = significant(net, 3)
    # the grid at one step: the small-step run against the time-step study's grid at the same step
    grid, dt = EVAP_RUNS[""]
    _, dt_rows = read_commented_csv(dirs["derived"] / "film_flow_dt.csv")
    same = [r for r in dt_rows if r["grid"] == DT_GRIDS[""] and abs(float(r["dt_s"]) - dt) < 1e-12]
    if len(same) == 1:
        mine = next(r for r in rows if r["grid"] == grid and abs(float(r["dt_s"]) - dt) < 1e-12
                    and float(r["evaporation_multiple"]) == 1.0)
        out["FfEvGridDiffS"] = significant(abs(float(mine["t_apex_s"]) - float(same[0]["t_apex_s"])), 1)
    out["FfEvMultipleMin"] = f"{min(MULTIPLES.values()):g}"
    out["FfEvMultipleMax"] = f"{max(MULTIPLES.values()):g}"
    if zero_s:
        out["FfEvZeroRunS"] = significant(float(zero_s.group(1)), 3)
    return out


EVAP_SUFFIXES = (["Grid", "StepMs", "RatioMin", "RatioMax", "SharePercentMin", "SharePercentMax", "DrainPercentMin",
                  "DrainPercentMax", "ETSpreadPercent", "ZeroApexNm", "ZeroHeqNm", "ZeroMinusHeqPercent", "ZeroS",
                  "ApexStartNm", "DrainedPeakNm", "DrainedPeakS", "DrainedNetNm"]
                 + [f"{kind}{word}{unit}" for word in MULTIPLES
                    for kind, unit in (("T", "S"), ("Eq", "S"), ("Ratio", ""), ("Share", "Percent"))])
EVAP_MACROS = ["FfEvDate", "FfEvMachine", "FfEvMultipleMin", "FfEvMultipleMax", "FfEvZeroRunS", "FfEvGridDiffS"] + [
    f"FfEv{role}{suffix}" for role in EVAP_RUNS for suffix in EVAP_SUFFIXES]

SECTIONS = {
    "filmflowverif": (["derived/film_flow_verification.csv"], verification, VERIFICATION_MACROS),
    "filmflowspeed": (["derived/film_flow.csv"], speed, SPEED_MACROS),
    "filmflowparams": (["bubbleoptics.filmflow.FilmParameters"], parameters, PARAMETER_MACROS),
    "filmflowdt": (["derived/film_flow_dt.csv"], dt_study, DT_MACROS),
    "filmflowevap": (["derived/film_flow_evaporation.csv", "derived/film_flow_dt.csv"], evaporation_study,
                     EVAP_MACROS),
}

#: \ifnum flags: 0 when their section fails
FLAGS = {"FfTargetMet": "0", "FfDtOrderLastPositive": "0", "FfDtBlackOrderLastPositive": "0"}
