"""The film-flow verification (grids, conservation, time step, evaporation), black-film time, frames.

Run:  python benchmarks/film_flow_verification.py [--quick] [--only {checks,dt,evaporation}] [--out PATH]
Writes ``data/derived/film_flow_verification.csv`` (one row a measured quantity) and
``data/derived/film_flow_verification.npz`` (the apex curve, the thickness against time of the
black-film run and the rendered frames, 8-bit sRGB, for ``paper/scripts/fig_film_flow.py``)
(``--only checks``), ``data/derived/film_flow_dt.csv`` (the time-step study, ``--only dt``) and
``data/derived/film_flow_evaporation.csv`` (the evaporation study, ``--only evaporation``);
without ``--only``, all three.  These are verification (the equations solved right, and how the
answer depends on the numerical and assumed parameters), not validation: nothing here is
compared with a measured film.

The checks are those of ``tests/bubbleoptics/test_film_flow.py``, computed by the same helpers (both import
them from :mod:`study.film_flow`: ``plug_equilibrium_error``,
``rigid_characteristics_profile``, ``plug_transient_differences``), on more grids:

* ``apex``: rigid drainage from a uniform film, steps of τ/20 to 10τ; the largest relative error
  of the top cell row against :math:`h_0(1 + t/\\tau)^{-1/2}` for t in [τ, 10τ], on 16-128 rows;
* ``profile``: rigid drainage, the profile (θ < π/2) after one step of τ against the
  characteristics of the PDE (scipy), largest |Δh|/h0, on 32-256 rows;
* ``equilibrium``: plug flow with a = 1 after 600 steps of 5 ms against
  :math:`h_0 (a/\\sinh a) e^{-a\\cos\\theta}`, largest relative error, on 16-128 rows;
* ``transient``: plug flow, 20 steps of 2.5 ms from a smooth perturbation, each grid against the
  next finer one averaged over 2 x 2 cells, largest |Δh|/h0;
* ``order_*``: log2 of the ratio of successive errors (the observed order of convergence);
* ``conservation``: the worst relative change of the volume (rigid: 30 steps of τ/2 on 24 x 12;
  plug: 200 steps of 5 ms on 64 x 128) and of the surfactant (plug) per step without evaporation,
  and the evaporated volume against E t 4πR² (rigid: 10 steps of 2 s; plug: 100 steps of 10 ms);
* ``black``: plug flow with the default (cited) parameters on :data:`BLACK_GRID`, steps of
  :data:`BLACK_DT`, to 1.2 h0/E: when the apex (top row, mean over φ), the first cell anywhere
  and the whole film go below :data:`BLACK_NM` (:func:`study.film_flow.first_crossing`),
  and the estimates h0/E (uniform evaporation), h_eq(0)/E (the equilibrium apex evaporating) and
  the rigid apex law's time to the same thickness (:func:`~study.film_flow.rigid_black_time`);
* ``frames``: :data:`FRAME_TIMES` frames of that series on a bubble under the sky (the notebook
  07 view), rendered at :data:`FRAME_SIZE` pixels, depth 4, the other render settings the
  defaults; the seconds a frame took (median, min, max) are in the CSV.

* ``dt`` (``film_flow_dt.csv``): the black-film run again (cited defaults, seed 0) at the steps
  of :data:`DT_STUDY`, halving each time, on two grids, sampled after every step
  (:func:`study.film_flow.black_film_run`): the apex's and the first cell's black-film times and
  the apex thickness at :data:`PROBE_S` s; for each three consecutive steps the observed order
  :math:`p = \\log_2(|f(\\Delta t)-f(\\Delta t/2)| / |f(\\Delta t/2)-f(\\Delta t/4)|)`
  (:func:`study.film_flow.observed_orders`) and Richardson's estimate from the two finer steps
  with that order (:func:`study.film_flow.richardson`; empty where the order is not positive).
  (The mean thickness is no test of the step: the scheme keeps the volume exactly, so it is
  h0 - E t at every step.)
* ``evaporation`` (``film_flow_evaporation.csv``): the apex's black-film time at the evaporation
  rates :data:`EVAPORATION_MULTIPLES` x the cited E, on the grids and steps of
  :data:`EVAPORATION_RUNS`, against :math:`h_{eq}(0)/E` and :math:`h_0/E`, with the share of the
  apex's thinning that evaporation did (:attr:`study.film_flow.BlackFilm.evaporated_share`)
  and the most the flow had drained from the apex at any step (and when);
  E = 0 (the rest drains only) is run for :data:`NO_EVAPORATION_S` s.

``--quick`` uses fewer and coarser grids, a coarse black-film run and tiny frames, and for the
studies an 8 x 16 grid (smoke test; each CSV says so).
"""

import argparse
import math
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

from bubbleoptics.filmflow import FilmGrid, FilmParameters, PlugFlow, RigidDrainage
from study import film_flow as ff
from study import provenance, write_csv
from study.film_flow import STILL, plug_equilibrium_error, plug_transient_differences, rigid_characteristics_profile

OUT = ROOT / "data" / "derived" / "film_flow_verification.csv"
BLACK_NM = 30.0  # "black film": thinner than this (as notebook 07)
BLACK_GRID, BLACK_DT = (128, 256), 0.01
FRAME_SIZE = 200
FRAME_OFFSETS = (-16.0, -8.0, 0.0, 4.0)  # s, around the apex's black-film time
DT_OUT = ROOT / "data" / "derived" / "film_flow_dt.csv"
EVAPORATION_OUT = ROOT / "data" / "derived" / "film_flow_evaporation.csv"
#: the time-step study: grid -> steps (s), halving each time from 40 ms
DT_STUDY = {(64, 128): tuple(0.04 / 2**k for k in range(8)), BLACK_GRID: tuple(0.04 / 2**k for k in range(6))}
DT_STUDY_QUICK = {(8, 16): tuple(0.1 / 2**k for k in range(4))}
PROBE_S = 30.0  # s: the apex thickness at this time is the study's second output
#: the evaporation study: multiples of the cited E, and (grid, step) of its runs
EVAPORATION_MULTIPLES = (0.25, 0.5, 1.0, 2.0, 4.0)
EVAPORATION_RUNS = (((32, 64), 0.000625), (BLACK_GRID, BLACK_DT))
EVAPORATION_RUNS_QUICK = (((8, 16), 0.05),)
NO_EVAPORATION_S = 120.0  # s: how long the run without evaporation goes on


def _orders(errors):
    return [math.log2(errors[i] / errors[i + 1]) for i in range(len(errors) - 1)]


def apex_errors(rows_list):
    p = FilmParameters(**STILL)
    tau = p.drainage_time
    out, curve = {}, None
    for n in rows_list:
        g = FilmGrid(n, 4, p.radius)
        series = RigidDrainage(p, g).run(t_end=10 * tau, dt=tau / 20, seed=0)
        t = series.times
        apex = series.h_nm[:, 0, :].astype(float).mean(axis=1) * 1e-9
        law = p.h0 * (1 + t / tau) ** -0.5
        late = t >= tau * (1 - 1e-12)
        out[n] = float(np.abs(apex[late] / law[late] - 1).max())
        if n == 64 or curve is None:
            curve = dict(apex_t_over_tau=t / tau, apex_nm=apex * 1e9, apex_law_nm=law * 1e9, apex_rows=n)
    return out, curve, tau


def profile_errors(rows_list):
    p = FilmParameters(**STILL)
    theta_end, h_end = rigid_characteristics_profile(1.0)
    out = {}
    for n in rows_list:
        g = FilmGrid(n, 4, p.radius)
        m = RigidDrainage(p, g)
        s = m.step(m.initial_state(0), p.drainage_time)
        top = g.theta < math.pi / 2
        out[n] = float(np.abs(s.h[top, 0] / p.h0 - np.interp(g.theta[top], theta_end, h_end)).max())
    return out


def equilibrium_errors(rows_list):
    return {n: float(plug_equilibrium_error(n)[0]) for n in rows_list}


def transient_differences(rows_list):
    return plug_transient_differences(rows_list)


def _evaporation_error(model, seed, steps, dt):
    """|lost volume / (E t 4 pi R^2) - 1| after *steps* steps of *dt* s of *model* from seed *seed*."""
    s0 = s = model.initial_state(seed)
    for _ in range(steps):
        s = model.step(s, dt)
    expected = model.params.evaporation * steps * dt * model.grid.total_area
    return abs((model.volume(s0) - model.volume(s)) / expected - 1)


def conservation(quick):
    out = {}
    p = FilmParameters(evaporation=0.0, perturbation=0.3)
    m = RigidDrainage(p, FilmGrid(24, 12, p.radius))
    s, worst = m.initial_state(5), 0.0
    for _ in range(30):
        v = m.volume(s)
        s = m.step(s, 0.5 * p.drainage_time)
        worst = max(worst, abs(m.volume(s) - v) / v)
    out["rigid_volume_per_step"] = worst
    grid = (16, 32) if quick else (64, 128)
    m = PlugFlow(p, FilmGrid(*grid, p.radius))
    s, wv, ws = m.initial_state(4), 0.0, 0.0
    for _ in range(200):
        v, g0 = m.volume(s), m.surfactant(s)
        s = m.step(s, 0.005)
        wv = max(wv, abs(m.volume(s) - v) / v)
        ws = max(ws, abs(m.surfactant(s) - g0) / g0)
    out["plug_volume_per_step"], out["plug_surfactant_per_step"] = wv, ws
    p = FilmParameters(evaporation=3e-8, perturbation=0.1)
    out["rigid_evaporated"] = _evaporation_error(RigidDrainage(p, FilmGrid(16, 8, p.radius)), 2, 10, 2.0)
    p = FilmParameters(evaporation=5e-8)
    out["plug_evaporated"] = _evaporation_error(PlugFlow(p, FilmGrid(8, 16, p.radius)), 1, 100, 0.01)
    return out, grid


def black_film(grid, dt):
    p = FilmParameters()
    t_end = dt * math.ceil(1.2 * p.h0 / p.evaporation / dt)
    save_every = max(1, int(round(0.5 / dt)))
    model = PlugFlow(p, FilmGrid(*grid, p.radius))
    t0, c0 = time.perf_counter(), time.process_time()
    series = model.run(t_end=t_end, dt=dt, save_every=save_every, seed=0)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    h = series.h_nm.reshape(len(series.h_nm), -1)
    apex = series.h_nm[:, 0, :].astype(float).mean(axis=1)
    a = p.equilibrium_exponent
    out = dict(apex=ff.first_crossing(series.times, apex, BLACK_NM),
               first=ff.first_crossing(series.times, h.min(axis=1), BLACK_NM),
               all=ff.first_crossing(series.times, h.max(axis=1), BLACK_NM),
               uniform=p.h0 / p.evaporation,
               equilibrium_apex=p.h0 * a / math.sinh(a) * math.exp(-a) / p.evaporation,
               rigid=ff.rigid_black_time(p.h0 * 1e9, p.drainage_time, BLACK_NM),
               steps=series.parameters["n_steps"], wall=wall, cpu=cpu, t_end=t_end, exponent=a)
    curves = dict(black_times=series.times, black_apex_nm=apex,
                  black_bottom_nm=series.h_nm[:, -1, :].astype(float).mean(axis=1),
                  black_min_nm=h.min(axis=1).astype(float), black_max_nm=h.max(axis=1).astype(float))
    return out, curves, series


def render_frames(series, t_black, size):
    import tracer
    from tracer.rendering.output import display_codes
    from tracer.scene import Bubble, Camera, Environment, FilmProfile, Scene

    times = [min(max(0.0, t_black + dt), float(series.times[-1])) for dt in FRAME_OFFSETS]
    film = FilmProfile(kind="simulated", series=series, time_s=times[0])
    scene = Scene(bubbles=[Bubble(center=(0.0, 0.0, 0.0), radius=1.0, film=film, name="bubble")],
                  camera=Camera(position=(0.0, 1.6, 3.6), look_at=(0.0, 0.0, 0.0), fov_deg=40.0),
                  environment=Environment(kind="sky"))
    tracer.render(scene, width=8, height=8, depth=4, progress=False)  # the kernels from numba's cache
    images, seconds = [], []
    for t in times:
        scene.bubbles[0].film.time_s = float(t)
        t0 = time.perf_counter()
        image = tracer.render(scene, width=size, height=size, depth=4, progress=False)
        seconds.append(time.perf_counter() - t0)
        images.append(display_codes(image, bits=8))
    return np.array(times), np.stack(images).astype(np.uint8), seconds


def dt_study(study):
    """Rows of ``film_flow_dt.csv``: :func:`study.film_flow.black_film_run` for each grid and
    step of *study*, with the observed orders and Richardson's estimates."""
    p = FilmParameters()
    rows = []
    for grid, steps in study.items():
        runs = []
        for dt in steps:
            r = ff.black_film_run(p, grid, dt, BLACK_NM, PROBE_S)
            runs.append(r)
            print(f"dt study {grid[0]}x{grid[1]} dt {dt * 1e3:9.4f} ms: apex black {r.t_apex:.6f} s, first "
                  f"{r.t_first:.6f} s, apex at {PROBE_S:g} s {r.apex_probe_nm:.4f} nm ({r.steps} steps, "
                  f"{r.wall:.1f} s)", flush=True)
        columns = {"t_apex_s": [r.t_apex for r in runs], "t_first_s": [r.t_first for r in runs],
                   "apex_probe_nm": [r.apex_probe_nm for r in runs]}
        orders = {k: [math.nan, math.nan] + ff.observed_orders(v) for k, v in columns.items()}
        for i, r in enumerate(runs):
            row = dict(grid=f"{grid[0]}x{grid[1]}", dt_s=r.dt, t_apex_s=r.t_apex, t_first_s=r.t_first,
                       probe_s=r.probe_s, apex_probe_nm=r.apex_probe_nm)
            for k, v in columns.items():
                name = k[:-3] if k.endswith("_nm") else k[:-2]
                row[f"order_{name}"] = orders[k][i]
                row[f"richardson_{k}"] = ff.richardson(v[i - 1], v[i], orders[k][i]) if i >= 2 else math.nan
            row.update(steps=r.steps, wall_s=r.wall, cpu_s=r.cpu)
            rows.append(row)
    return rows


def evaporation_study(runs, multiples):
    """Rows of ``film_flow_evaporation.csv``: the apex's black-film time at each multiple of the
    cited evaporation rate (and at E = 0) on each (grid, step) of *runs*."""
    base = FilmParameters()
    rows = []
    for grid, dt in runs:
        for m in (0.0,) + tuple(multiples):
            p = base.replace(evaporation=base.evaporation * m)
            r = ff.black_film_run(p, grid, dt, BLACK_NM, probe_s=0.0, t_max=NO_EVAPORATION_S if m == 0 else None)
            heq = ff.equilibrium_apex_nm(p)
            t_eq = heq * 1e-9 / p.evaporation if m > 0 else math.inf
            t_uniform = p.h0 / p.evaporation if m > 0 else math.inf
            rows.append(dict(grid=f"{grid[0]}x{grid[1]}", dt_s=dt, evaporation_multiple=m,
                             evaporation_m_per_s=p.evaporation, t_apex_s=r.t_apex, t_first_s=r.t_first,
                             t_eq_apex_s=t_eq, t_apex_over_t_eq_apex=r.t_apex / t_eq if m > 0 else math.nan,
                             t_uniform_s=t_uniform, evaporated_share=r.evaporated_share if m > 0 else 0.0,
                             h_eq_apex_nm=heq, apex_start_nm=r.apex_start_nm, apex_end_nm=r.apex_end_nm,
                             drained_peak_nm=r.drained_peak_nm, t_drained_peak_s=r.t_drained_peak,
                             t_end_s=r.t_end, steps=r.steps, wall_s=r.wall))
            print(f"evaporation {grid[0]}x{grid[1]} dt {dt * 1e3:g} ms E x {m:g}: apex black {r.t_apex:.4f} s, "
                  f"h_eq(0)/E {t_eq:.4f} s, ratio {rows[-1]['t_apex_over_t_eq_apex']:.4f}, evaporated share "
                  f"{rows[-1]['evaporated_share']:.4f}, apex at the end {r.apex_end_nm:.1f} nm, drained at most "
                  f"{r.drained_peak_nm:.1f} nm at {r.t_drained_peak:.3g} s "
                  f"({r.steps} steps, {r.wall:.1f} s)", flush=True)
    return rows


def _study_comment(script_note, quick, load_start, extra):
    load = os.getloadavg()[0]
    return [
        provenance("benchmarks/film_flow_verification.py",
                   f"load average {load_start:.2f} at the start, {load:.2f} at the end (other processes share the cores)",
                   f"numba threads {numba_threads()}",
                   ("QUICK MODE (smoke test), " if quick else "") + script_note,
                   "regenerate with: python benchmarks/film_flow_verification.py --only "
                   + extra + (" --quick" if quick else "")),
    ]


def numba_threads():
    import numba

    return numba.get_num_threads()


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="coarse grids and tiny frames (smoke test)")
    parser.add_argument("--only", action="append", choices=("checks", "dt", "evaporation"),
                        help="run only this part (repeatable; default: all three)")
    parser.add_argument("--out", type=Path, default=OUT, help="the checks' CSV (the .npz beside it)")
    parser.add_argument("--dt-out", type=Path, default=DT_OUT)
    parser.add_argument("--evaporation-out", type=Path, default=EVAPORATION_OUT)
    args = parser.parse_args(argv)
    parts = set(args.only or ("checks", "dt", "evaporation"))
    if "checks" in parts:
        checks(args)
    if "dt" in parts:
        load_start = os.getloadavg()[0]
        rows = dt_study(DT_STUDY_QUICK if args.quick else DT_STUDY)
        comment = _study_comment(
            f"time-step study of the black-film run (plug flow, cited defaults, seed 0, threshold {BLACK_NM:g} nm, "
            "sampled every step)", args.quick, load_start, "dt") + [
            "order_X on the row of step dt: log2(|X(4 dt) - X(2 dt)| / |X(2 dt) - X(dt)|); richardson_X: "
            "X(dt) + (X(dt) - X(2 dt)) / (2^order - 1), nan where the order is not positive"]
        write_csv(args.dt_out, rows, comment, float_format="{:.9g}")
        print(f"wrote {args.dt_out}", file=sys.stderr)
    if "evaporation" in parts:
        load_start = os.getloadavg()[0]
        rows = evaporation_study(EVAPORATION_RUNS_QUICK if args.quick else EVAPORATION_RUNS, EVAPORATION_MULTIPLES)
        comment = _study_comment(
            f"evaporation study of the black-film run (plug flow, cited defaults but E, seed 0, threshold "
            f"{BLACK_NM:g} nm); E = 0 runs {NO_EVAPORATION_S:g} s", args.quick, load_start, "evaporation") + [
            "t_eq_apex_s = h_eq(0)/E (the equilibrium's apex evaporating), t_uniform_s = h0/E; evaporated_share = "
            "E t_apex / (apex_start - threshold), the rest of the apex's thinning is drainage; drained_peak_nm: the most "
            "the apex had thinned beyond E t at any step (at t_drained_peak_s)"]
        write_csv(args.evaporation_out, rows, comment, float_format="{:.7g}")
        print(f"wrote {args.evaporation_out}", file=sys.stderr)


def checks(args):
    q = args.quick
    load_start = os.getloadavg()[0]
    rows = []

    def add(check, quantity, value, unit="", grid="", note=""):
        rows.append(dict(check=check, quantity=quantity, grid=grid, value=value, unit=unit, note=note))
        print(f"{check:13s} {quantity:28s} {grid:9s} {value:.6g} {unit}", flush=True)

    apex, curve, tau = apex_errors((16, 32) if q else (16, 32, 64, 128))
    for n, e in apex.items():
        add("apex", "max_relative_error", e, grid=f"{n}x4", note="t in [tau, 10 tau], steps tau/20")
    for (n, _), o in zip(list(apex.items())[1:], _orders(list(apex.values()))):
        add("apex", "order", o, grid=f"{n}x4")
    add("apex", "drainage_time", tau, "s")
    prof = profile_errors((32, 64) if q else (32, 64, 128, 256))
    for n, e in prof.items():
        add("profile", "max_abs_error_h_over_h0", e, grid=f"{n}x4", note="t = tau, theta < pi/2")
    for (n, _), o in zip(list(prof.items())[1:], _orders(list(prof.values()))):
        add("profile", "order", o, grid=f"{n}x4")
    eq = equilibrium_errors((16, 32) if q else (16, 32, 64, 128))
    for n, e in eq.items():
        add("equilibrium", "max_relative_error", e, grid=f"{n}x4", note="a = 1, 600 steps of 5 ms")
    for (n, _), o in zip(list(eq.items())[1:], _orders(list(eq.values()))):
        add("equilibrium", "order", o, grid=f"{n}x4")
    tr = transient_differences((8, 16, 32) if q else (16, 32, 64, 128))
    for n, e in tr.items():
        add("transient", "max_abs_difference_h_over_h0", e, grid=f"{n}x{2 * n}",
            note="against the next finer grid, 20 steps of 2.5 ms")
    for (n, _), o in zip(list(tr.items())[1:], _orders(list(tr.values()))):
        add("transient", "order", o, grid=f"{n}x{2 * n}")
    cons, plug_grid = conservation(q)
    for name, value in cons.items():
        grid = {"rigid_volume_per_step": "24x12", "plug_volume_per_step": "x".join(map(str, plug_grid)),
                "plug_surfactant_per_step": "x".join(map(str, plug_grid)), "rigid_evaporated": "16x8",
                "plug_evaporated": "8x16"}[name]
        add("conservation", name, value, "relative", grid=grid)

    grid, dt = ((16, 32), 0.1) if q else (BLACK_GRID, BLACK_DT)
    black, curves, series = black_film(grid, dt)
    gname = f"{grid[0]}x{grid[1]}"
    for key in ("apex", "first", "all", "uniform", "equilibrium_apex", "rigid"):
        add("black", f"t_{key}", black[key], "s", grid=gname if key in ("apex", "first", "all") else "",
            note=f"below {BLACK_NM:g} nm" if key != "uniform" else "h0/E")
    add("black", "threshold", BLACK_NM, "nm")
    add("black", "dt", dt, "s", grid=gname)
    add("black", "steps", black["steps"], grid=gname)
    add("black", "t_end", black["t_end"], "s", grid=gname)
    add("black", "equilibrium_exponent", black["exponent"])
    add("black", "run_wall_seconds", black["wall"], "s", grid=gname)

    size = 32 if q else FRAME_SIZE
    times, images, seconds = render_frames(series, black["apex"], size)
    add("frames", "size", size, "px")
    add("frames", "count", len(times))
    add("frames", "depth", 4)
    for t in times:
        add("frames", "time", t, "s")
    med = statistics.median(seconds)
    add("frames", "render_seconds_median", med, "s", note=f"min {min(seconds):.3g}, max {max(seconds):.3g}")
    add("frames", "render_seconds_min", min(seconds), "s")
    add("frames", "render_seconds_max", max(seconds), "s")

    load = os.getloadavg()[0]
    comment = [
        provenance("benchmarks/film_flow_verification.py",
                   f"load average {load_start:.2f} at the start, {load:.2f} at the end (other processes share the cores)",
                   ("QUICK MODE (smoke test), " if q else "")
                   + "the checks of tests/bubbleoptics/test_film_flow.py on more grids; frames in film_flow_verification.npz",
                   "regenerate with: python benchmarks/film_flow_verification.py" + (" --quick" if q else "")),
        "order rows: log2 of the ratio of the error on the grid half as fine to the error on this grid",
    ]
    write_csv(args.out, rows, comment, fieldnames=["check", "quantity", "grid", "value", "unit", "note"])
    npz = args.out.with_suffix(".npz")
    tmp = npz.with_name(f".{npz.stem}.tmp.npz")
    np.savez_compressed(tmp, frame_times=times, frames=images, **curve, **curves)
    os.replace(tmp, npz)
    print(f"wrote {args.out} and {npz}", file=sys.stderr)


if __name__ == "__main__":
    main()
