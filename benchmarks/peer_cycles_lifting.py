"""The Cycles attribution's sensitivity to how the environment's RGB is lifted to a spectrum.

Run:  python benchmarks/peer_cycles_lifting.py [--quick] [--out PATH] [--methods M ...] [--lifted NPZ]
Writes ``data/derived/peer_cycles_lifting.csv`` (read by ``paper/scripts/numbers_cycles.py`` and
``paper/scripts/fig_peer_cycles.py``); ``--quick`` (the thickest film, a 256-row environment, 8 spp) writes
into a temporary folder unless ``--out`` is given.  Needs no Blender: Cycles' images are the
ones ``benchmarks/peer_cycles.py`` stored (``data/derived/peer_cycles_images.npz``, float16,
the mean of two seeds at 1024 spp), and the scene, masks and closed form are that benchmark's
(imported as the module ``peer_cycles`` beside this file).

Our reference lifts the environment's linear-sRGB colours to spectra with the Mallett-Yuksel
basis (the tracer's ``channel_setup``); Cycles never lifts them (each RGB channel's light times
that channel's film reflectance).  The "colour model" share of the difference between them is
therefore measured against one lifting.  Here the environment's rows (its only colours: it
varies with elevation alone) are lifted by each of :data:`study.lifting.METHODS` (colour-science's
Jakob & Hanika 2019, Smits 1999, Otsu et al. 2018), and for each lifting and film:

1. **Round trip.**  CIEDE2000 between each row's colour and its lifted spectrum brought back
   through our 64-band D65 pipeline (mean and largest over the rows).  The main results use the
   spectra *corrected* (:func:`study.lifting.corrected`: plus the Mallett-Yuksel spectrum of the
   residual, so the round trip is exact, as the tracer's normalisation makes it for its own
   basis); ``variant = raw`` repeats them without the correction.
2. **Closed form** (the decomposition's: ``peer_cycles.sphere_paths``, the exact Airy
   reflectance at the band centres, 64 bands, depth 12), the environment looked up by nearest
   row as the tracer does, its spectra the lifting's.  Rows: the reference's move (this lifting
   against Mallett-Yuksel), the colour model (Cycles' RGB model, ``peer_cycles.model_image("rgb")``,
   against this lifting's closed form), all of Cycles' model (``"cycles"``: cut and clamp too),
   and Cycles' render against this lifting's closed form; the RGB models are evaluated with the
   same nearest-row lookup.  With Mallett-Yuksel these are the rows of ``peer_cycles.csv`` up to
   the nearest-row lookup and the float16 images (the ``check`` rows: each nearest-row closed
   form against ``peer_cycles.model_image``'s continuous one).
3. **Rendered.**  The tracer's environment lookup is linear in RGB (a basis (C, 3) times the
   texel), so a non-linear lifting enters it as its best linear fit over the environment's
   rows (:func:`study.lifting.linear_fit`; ``channel_setup`` replaced for the render).  Ours
   spectral (64 bands, band method, 64 spp, one seed) with that basis; rows: the render against
   the closed form with the same linear fit (the closed form's check), the linear fit's own
   effect (closed form, fit against full lifting), the render against our Mallett-Yuksel
   reference (stored), and Cycles against the render.

CIEDE2000 statistics as in ``peer_cycles.py`` (``de_stats``: bubble, edge, all); only the bubble
region is free of the closed form's missing anti-aliasing.
"""

from __future__ import annotations

import argparse
import contextlib
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import peer_cycles as pc  # the sibling benchmark: its scene, masks and closed form

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "derived" / "peer_cycles_lifting.csv"
IMAGES = ROOT / "data" / "derived" / pc.IMAGES_NAME
BANDS = pc.REF_BANDS
SPP, SEED = pc.REF_SPP, pc.REF_SEEDS[0]


def row_index(dirs, height):
    """The environment row the tracer reads along unit directions *dirs* (..., 3), y up:
    ``min(h - 1, int(acos(d.y) / pi * h))`` (``tracer.kernels.environment``)."""
    theta = np.arccos(np.clip(np.asarray(dirs, float)[..., 1], -1.0, 1.0))
    return np.minimum(height - 1, (theta / math.pi * height).astype(int))


def closed_form(table, thickness_nm, size, model="spectral", n_film=pc.FILM_N, depth=pc.DEPTH):
    """The bubble's closed-form image (size, size, 3), the environment's row *i* being ``table[i]``
    and looked up by the nearest row as the tracer does (:func:`row_index`); first reflection
    plus the internal ones, as ``peer_cycles.model_image``.  *model* ``"spectral"``: *table* (H, C)
    band spectra, the exact Airy reflectance at the band centres, to linear sRGB through the
    tracer's ``to_rgb`` (``model_image("exact")`` with another light); ``"rgb"`` and ``"cycles"``:
    *table* (H, 3) linear sRGB, the reflectance per channel through ``peer_cycles.rgb_cmfs``
    (``"cycles"``: cut after m = 3 and clamped), as ``model_image`` does.  Outside the bubble: the
    RGB environment."""
    from tracer.prepare.pack import channel_setup

    table = np.asarray(table, float)
    hit, cos, refl, outs = pc.sphere_paths(size, depth=depth)
    cam, _ = pc.camera_rays(size)
    image = pc.environment_radiance(cam)
    c = cos[hit][:, None]
    with np.errstate(invalid="ignore", divide="ignore"):
        if model == "spectral":
            wl, to_rgb, _ = channel_setup(True, table.shape[1])
            R = pc.free_film_reflectance(wl[None, :], thickness_nm, c, n_film)
        elif model in ("rgb", "cycles"):
            wl = np.arange(360.0, 781.0, 1.0)
            m_max = None if model == "rgb" else pc.AIRY_CUT
            R = pc.free_film_reflectance(wl[None, :], thickness_nm, c, n_film, m_max) @ pc.rgb_cmfs(wl).T
            if model == "cycles":
                R = np.clip(R, 0.0, 1.0)
            to_rgb = np.eye(3)
        else:
            raise ValueError(f"unknown model {model!r}")

    def light(dirs):
        return table[row_index(dirs, table.shape[0])]

    return pc.fill_bubble(image, hit, refl, outs, R, light, to_rgb)


@contextlib.contextmanager
def tracer_basis(basis):
    """Render with *basis* (C, 3) in place of the tracer's Mallett-Yuksel one (``channel_setup``
    as ``tracer.prepare.pack`` calls it, for spectral packing with C bands)."""
    import tracer.prepare.pack as pack

    original = pack.channel_setup

    def patched(spectral, n_bands):
        wl, to_rgb, own = original(spectral, n_bands)
        if spectral and n_bands == basis.shape[0]:
            return wl, to_rgb, np.array(basis, float)
        return wl, to_rgb, own

    pack.channel_setup = patched
    try:
        yield
    finally:
        pack.channel_setup = original


def main(argv=None):
    from study import lifting
    from study import provenance, write_csv
    from study.metrics import delta_e00

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="one film, 256-row environment, 8 spp (smoke test)")
    parser.add_argument("--out", type=Path, default=None, help=f"CSV to write (default {OUT.relative_to(ROOT)})")
    parser.add_argument("--methods", nargs="+", default=list(lifting.METHODS[1:]), choices=lifting.METHODS[1:],
                        help="liftings to compare with Mallett-Yuksel")
    parser.add_argument("--lifted", type=Path, default=None, help="an .npz to reuse the lifted rows from (if it "
                        "holds the same rows) and to write them to: Jakob2019's optimisation takes minutes")
    args = parser.parse_args(argv)
    if not IMAGES.exists():
        print(f"peer_cycles_lifting: {IMAGES} is missing: run benchmarks/peer_cycles.py first", file=sys.stderr)
        return 2
    quick = args.quick
    size = pc.SIZE
    height = 256 if quick else pc.ENV_SHAPE[0]
    spp = 8 if quick else SPP
    out = args.out or (Path(tempfile.mkdtemp(prefix="peer_cycles_lifting_")) / OUT.name if quick else OUT)
    stored = np.load(IMAGES)
    thicknesses = [float(t) for t in stored["thicknesses"]]
    if quick:
        thicknesses = thicknesses[-1:]

    def cycles_image(d):
        return stored[f"cycles_{d:g}"].astype(float)

    env = pc.environment_image(height=height, width=pc.ENV_SHAPE[1])
    rows_rgb = env[:, 0, :].astype(float)
    masks = pc.pixel_masks(size)
    rows, timings = [], []

    def add(**row):
        rows.append(row)
        print("  " + " ".join(f"{k}={row[k]}" for k in ("section", "lifting", "variant", "thickness_nm", "setting")
                              if k in row and row[k] != "")
              + "  " + " ".join(f"{k} {row[k]:.3f}" for k in ("bubble_mean", "bubble_p95", "rows_mean", "rows_max")
                                if k in row), flush=True)

    # 1. the liftings of the environment's rows
    tables = {("Mallett2019", "corrected"): lifting.lift(rows_rgb, "Mallett2019", BANDS)}
    cached = {}
    if args.lifted is not None and args.lifted.exists():
        with np.load(args.lifted) as f:
            if f["rows"].shape == rows_rgb.shape and np.array_equal(f["rows"], rows_rgb):
                cached = {k: f[k] for k in f.files}
    for method in args.methods:
        t0 = time.perf_counter()
        if method in cached:
            raw = cached[method]
            timings.append(f"{method} {float(cached[method + '_seconds']):.0f} s for {height} colours")
        else:
            raw = lifting.lift(rows_rgb, method, BANDS)
            cached[method], cached[method + "_seconds"] = raw, np.array(time.perf_counter() - t0)
            timings.append(f"{method} {time.perf_counter() - t0:.0f} s for {height} colours")
        print(f"lifted {height} rows by {method} in {time.perf_counter() - t0:.1f} s", flush=True)
        tables[(method, "raw")] = raw
        tables[(method, "corrected")] = lifting.corrected(raw, rows_rgb)
    if args.lifted is not None:
        np.savez(args.lifted, rows=rows_rgb, **cached)
    for (method, variant), table in tables.items():
        de = delta_e00(lifting.to_rgb(table), rows_rgb)
        add(section="round_trip", lifting=method, variant=variant, setting="environment rows through 64 bands",
            rows_mean=float(de.mean()), rows_max=float(de.max()), spectrum_min=float(table.min()),
            spectrum_max=float(table.max()))

    # 2. closed form per lifting, against the RGB models and Cycles' render
    stats = pc.de_stats
    for d in thicknesses:
        print(f"\nfilm {d:g} nm:", flush=True)
        cyc = cycles_image(d)
        rgb_model = closed_form(rows_rgb, d, size, "rgb")
        cycles_model = closed_form(rows_rgb, d, size, "cycles")
        base = closed_form(tables[("Mallett2019", "corrected")], d, size)
        for model, mine in (("exact", base), ("rgb", rgb_model), ("cycles", cycles_model)):
            add(section="check", lifting="Mallett2019", variant="corrected", thickness_nm=d,
                setting=f"nearest-row closed form vs peer_cycles.model_image {model}",
                **stats(mine, pc.model_image(model, d, size=size), masks))
        for (method, variant), table in tables.items():
            exact = closed_form(table, d, size)
            common = dict(section="closed_form", lifting=method, variant=variant, thickness_nm=d)
            add(**common, setting="reference moves: this lifting vs Mallett2019", **stats(exact, base, masks))
            add(**common, setting="colour model: rgb vs this lifting", **stats(rgb_model, exact, masks))
            add(**common, setting="total model: cycles model vs this lifting", **stats(cycles_model, exact, masks))
            add(**common, setting="Cycles render vs this lifting", **stats(cyc, exact, masks))

    # 3. rendered with the linear fit of each lifting over the rows
    import tracer

    for method in args.methods:
        basis, residual = lifting.linear_fit(rows_rgb, tables[(method, "corrected")])
        linear_table = rows_rgb @ basis.T
        print(f"\n{method}: linear fit over the rows, largest residual {residual:.4f}", flush=True)
        for d in thicknesses:
            desc = pc.scene_description("bubble", d, size=size)
            with tracer_basis(basis):
                image, seconds = pc.render_ours(pc.our_scene(desc, env), spp, SEED, size=size)
            common = dict(section="rendered", lifting=method, variant="corrected, linear fit", thickness_nm=d,
                          fit_residual=residual, seconds=seconds)
            linear = closed_form(linear_table, d, size)
            add(**common, setting="check: render vs closed form of the linear fit", **stats(image, linear, masks))
            add(**common, setting="linear fit: closed form of the fit vs of the lifting",
                **stats(linear, closed_form(tables[(method, "corrected")], d, size), masks))
            if not quick:
                add(**common, setting="reference moves: render vs Mallett2019 reference",
                    **stats(image, stored[f"ref_{d:g}"].astype(float), masks))
            add(**common, setting="Cycles render vs render", **stats(cycles_image(d), image, masks))

    columns = ["section", "lifting", "variant", "thickness_nm", "setting", "rows_mean", "rows_max", "spectrum_min",
               "spectrum_max", "fit_residual", "seconds"]
    columns += [f"{r}_{s}" for r in ("bubble", "edge", "all") for s in ("mean", "p95")]
    import colour
    import numba

    comments = [
        provenance(f"benchmarks/peer_cycles_lifting.py{' --quick' if quick else ''}",
                   f"colour-science {colour.__version__}, numba {numba.__version__} with {numba.get_num_threads()} "
                   "threads", "regenerate with: python benchmarks/peer_cycles_lifting.py"),
        f"scene: peer_cycles.py's ({size}x{size}, film n = {pc.FILM_N}); environment {pc.ENV_SHAPE[1]}x{height}, its "
        f"rows lifted by {', '.join(['Mallett2019'] + args.methods)} (colour-science, as reflectances under D65) "
        f"onto {BANDS} bands averaged over each band; Cycles: the stored images of peer_cycles.py (float16)",
        "corrected: plus the Mallett-Yuksel spectrum of the round-trip residual (exact round trip); raw: as lifted",
        f"closed form: exact Airy at the band centres, depth {pc.DEPTH}, nearest environment row; rendered: ours "
        f"spectral {BANDS} bands (band), {spp} spp, seed {SEED}, depth {pc.DEPTH}, threshold 0, the lifting's linear fit "
        "over the rows as the tracer's RGB basis; dE00 mean and p95 over bubble, edge and all pixels",
        "lifting times: " + "; ".join(timings),
    ]
    write_csv(out, rows, comments, fieldnames=columns, float_format="{:.6g}", extrasaction="ignore")
    print(f"\nwrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
