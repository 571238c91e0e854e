"""The film-flow simulation's validation figures, the black-film time and a few rendered frames.

Run:  python benchmarks/film_flow_validation.py [--quick] [--out PATH]
Writes ``data/derived/film_flow_validation.csv`` (one row a measured quantity) and
``data/derived/film_flow_validation.npz`` (the apex curve, the thickness against time of the
black-film run and the rendered frames, 8-bit sRGB, for ``paper/scripts/fig_film_flow.py``).

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

``--quick`` uses fewer and coarser grids, a coarse black-film run and tiny frames (smoke test;
its CSV says so).
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

OUT = ROOT / "data" / "derived" / "film_flow_validation.csv"
BLACK_NM = 30.0  # "black film": thinner than this (as notebook 07)
BLACK_GRID, BLACK_DT = (128, 256), 0.01
FRAME_SIZE = 200
FRAME_OFFSETS = (-16.0, -8.0, 0.0, 4.0)  # s, around the apex's black-film time


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


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="coarse grids and tiny frames (smoke test)")
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
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
        provenance("benchmarks/film_flow_validation.py",
                   f"load average {load_start:.2f} at the start, {load:.2f} at the end (other processes share the cores)",
                   ("QUICK MODE (smoke test), " if q else "")
                   + "the checks of tests/bubbleoptics/test_film_flow.py on more grids; frames in film_flow_validation.npz",
                   "regenerate with: python benchmarks/film_flow_validation.py" + (" --quick" if q else "")),
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
