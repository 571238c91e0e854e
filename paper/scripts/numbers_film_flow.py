"""The numbers of the film-flow chapter (paper/sections/film_flow.tex), a plug-in of make_numbers.py.

* ``filmflowvalid``: ``data/derived/film_flow_validation.csv`` (``benchmarks/film_flow_validation.py``):
  the checks of ``tests/bubbleoptics/test_film_flow.py`` on more grids, the black-film time and the frames;
* ``filmflowspeed``: ``data/derived/film_flow.csv`` (``benchmarks/film_flow.py``): ms a step, steps
  per second, the target, and the cost of a 10-s movie;
* ``filmflowparams``: :class:`bubbleoptics.filmflow.FilmParameters` (the cited defaults) and the
  black-film threshold of the benchmark (computed, no data file).
"""

from __future__ import annotations

import math
import re

from macros import date_of, machine_of, read_commented_csv, scientific, significant


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


def validation(dirs):
    notes, rows = read_commented_csv(dirs["derived"] / "film_flow_validation.csv")
    if any("QUICK MODE" in n for n in notes):
        raise ValueError("film_flow_validation.csv was written in quick mode")
    out = {"FfValidDate": date_of(notes), "FfValidMachine": machine_of(notes)}
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
        out["FfValidLoadStart"], out["FfValidLoadEnd"] = load.group(1), load.group(2)
    return out


VALIDATION_MACROS = ["FfValidDate", "FfValidMachine", "FfValidLoadStart", "FfValidLoadEnd"] + [
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

SECTIONS = {
    "filmflowvalid": (["derived/film_flow_validation.csv"], validation, VALIDATION_MACROS),
    "filmflowspeed": (["derived/film_flow.csv"], speed, SPEED_MACROS),
    "filmflowparams": (["bubbleoptics.filmflow.FilmParameters"], parameters, PARAMETER_MACROS),
}

#: \ifnum flags: 0 when their section fails
FLAGS = {"FfTargetMet": "0"}
