"""Meshes at scale: load, pack (orientation, normals, BVH) and render time and peak memory against
the number of triangles.

Run:  python benchmarks/mesh_scale.py [--repeats N] [--quick]
Writes ``data/derived/mesh_scale.csv``.

Shapes, generated with trimesh and written as binary PLY files (float64 vertices and faces, no
normals: :func:`write_ply`) into a temporary folder, each named by a TOML scene as a user would write it
(``[[meshes]] path = "...", shading = "smooth"``: vertex normals computed at packing):

* ``sphere``: a UV sphere (``trimesh.creation.uv_sphere``), convex and closed: the orientation
  test runs to its end (welding, edges, solid angle) and turns every face outward;
* ``torus``: a torus (``trimesh.creation.torus``), closed but not convex: the edge test stops
  at the first concave edge and the file's winding is kept.

Sizes about 10k, 100k and 1M triangles.  The mesh spans about 60 % of the image's height, lit
by one point light, Phong material with a mirror term (so that reflected rays are traced), a
constant environment.  Every (shape, size, repeat) runs in a fresh child process
(``--child``): it first imports trimesh, reads and renders a small mesh file the same way and
builds a BVH big enough for threads, so that numba's kernels are loaded from its cache (none
of this timed: a process pays it once, whatever the mesh), then times

* ``load``: ``tracer.load_scene`` of the TOML file (trimesh reads the PLY, zero-area check);
* ``pack``: ``tracer.prepare.pack.pack_scene`` inside the render (orientation, vertex normals, BVH),
  of which ``bvh``: ``tracer.prepare.bvh.build_bvh``;
* ``render``: the render itself at 960x960, default settings (depth 10, 1 spp, threshold 1e-3),
  2 threads (``RenderStats.render_seconds``);
* ``total``: load plus the whole ``render_with_stats`` call (packing and the render);
* ``peak_rss``: the child's peak resident memory (``resource.getrusage(RUSAGE_SELF).ru_maxrss``,
  the Python interpreter, numba and its kernels included).

Reported per case: median, min and max over the repeats, and the ratio of the medians to the
~10k case of the same shape.  The machine is shared: the children of one repeat run one after
another, and the repeats interleave the cases so that all see the same load.
"""

import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from study.results import image_benchmark_arguments, provenance, write_csv

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "derived" / "mesh_scale.csv"
#: (shape, nominal size) -> trimesh constructor arguments
SHAPES = {
    ("sphere", "10k"): ("uv_sphere", dict(count=[36, 72])),
    ("sphere", "100k"): ("uv_sphere", dict(count=[112, 224])),
    ("sphere", "1M"): ("uv_sphere", dict(count=[354, 708])),
    ("torus", "10k"): ("torus", dict(major_radius=1.0, minor_radius=0.4, major_sections=100, minor_sections=50)),
    ("torus", "100k"): ("torus", dict(major_radius=1.0, minor_radius=0.4, major_sections=316, minor_sections=158)),
    ("torus", "1M"): ("torus", dict(major_radius=1.0, minor_radius=0.4, major_sections=1000, minor_sections=500)),
}
QUICK = [("sphere", "10k"), ("sphere", "100k"), ("torus", "10k"), ("torus", "100k")]

SCENE = """\
[scene]
description = "benchmarks/mesh_scale.py: {shape}, {faces} triangles"

[camera]
position = [0.0, 0.6, 5.0]
look_at = [0.0, 0.0, 0.0]
fov_deg = 40

[environment]
kind = "constant"
color = [0.2, 0.25, 0.3]

[materials.clay]
color = [0.8, 0.45, 0.3]
ambient = 0.1
diffuse = 0.7
specular = 0.3
shininess = 40

[[meshes]]
name = "{shape}"
path = "{path}"
material = "clay"
shading = "smooth"

[[lights]]
position = [4.0, 5.0, 6.0]
intensity = 1.0
"""


def write_ply(path: Path, vertices, faces):
    """A binary PLY with float64 vertices (trimesh's exporter writes float32, which moves the
    vertices of a fine sphere off it by more than the orientation rule's 1e-9 tolerance: such a
    file is not convex by the rule, and its winding is kept)."""
    head = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(vertices)}\n"
            "property double x\nproperty double y\nproperty double z\n"
            f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
    rows = np.empty(len(faces), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    rows["n"] = 3
    rows["i"] = faces
    with open(path, "wb") as fh:
        fh.write(head.encode("ascii"))
        fh.write(np.ascontiguousarray(vertices, dtype="<f8").tobytes())
        fh.write(rows.tobytes())


def write_shape(folder: Path, shape, size):
    """Write the PLY and its TOML scene; returns (toml path, number of faces)."""
    import trimesh

    maker, kwargs = SHAPES[(shape, size)]
    mesh = getattr(trimesh.creation, maker)(**kwargs)
    if shape == "torus":
        mesh.apply_transform(trimesh.transformations.rotation_matrix(1.1, [1.0, 0.0, 0.0]))
    ply = folder / f"{shape}_{size}.ply"
    write_ply(ply, np.asarray(mesh.vertices), np.asarray(mesh.faces))
    toml = folder / f"{shape}_{size}.toml"
    toml.write_text(SCENE.format(shape=shape, faces=len(mesh.faces), path=ply.name), encoding="utf-8")
    return toml, len(mesh.faces)


def child(toml, size, threads):
    """One measurement in this (fresh) process; prints a JSON line."""
    import numba

    import tracer
    import tracer.prepare.bvh
    import tracer.prepare.pack as pack

    numba.set_num_threads(threads)
    import trimesh  # (imported by the first mesh file a process reads: 0.3-0.5 s, not timed)

    # load numba's kernels from the cache, not timed: a small mesh file read and rendered the
    # same way (closed, convex, smooth), and a BVH big enough to be built in threads
    warm = Path(toml).parent / "warm_up.toml"
    if not warm.exists():
        write_ply(warm.with_suffix(".ply"), np.asarray(trimesh.creation.icosphere(1).vertices),
                  np.asarray(trimesh.creation.icosphere(1).faces))
        warm.write_text(SCENE.format(shape="warm_up", faces=80, path=warm.with_suffix(".ply").name), encoding="utf-8")
    tracer.render(tracer.load_scene(warm), width=8, height=8, progress=False)
    rng = np.random.default_rng(0)
    tracer.prepare.bvh.build_bvh(rng.uniform(-1, 1, (2 * tracer.prepare.bvh.PARALLEL_MIN + 1, 1, 3))
                         + 0.01 * rng.normal(size=(2 * tracer.prepare.bvh.PARALLEL_MIN + 1, 3, 3)))

    timers = {"pack": 0.0, "bvh": 0.0}

    def timed(name, func):
        def wrapper(*args, **kwargs):
            t0 = time.perf_counter()
            try:
                return func(*args, **kwargs)
            finally:
                timers[name] += time.perf_counter() - t0
        return wrapper

    render_module = sys.modules["tracer.render"]  # (tracer.render is also the function)
    render_module.pack_scene = timed("pack", pack.pack_scene)
    pack.build_bvh = timed("bvh", pack.build_bvh)
    t0 = time.perf_counter()
    scene = tracer.load_scene(toml)
    t_load = time.perf_counter() - t0
    t0 = time.perf_counter()
    image, stats = tracer.render_with_stats(scene, width=size, height=size, progress=False)
    t_call = time.perf_counter() - t0
    assert np.isfinite(image).all()
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024  # Linux: kilobytes
    print(json.dumps(dict(load=t_load, pack=timers["pack"], bvh=timers["bvh"], render=stats.render_seconds,
                          total=t_load + t_call, peak_rss=peak, faces=int(sum(len(m.faces) for m in scene.meshes)),
                          rays=stats.rays["total"])))


def main(argv=None):
    if argv is None and len(sys.argv) > 1 and sys.argv[1] == "--child":
        toml, size, threads = sys.argv[2:5]
        child(toml, int(size), int(threads))
        return 0
    args, size, repeats = image_benchmark_arguments(__doc__.splitlines()[0], OUT, 3, 1, argv)
    cases = QUICK if args.quick else list(SHAPES)
    threads = 2
    folder = Path(tempfile.mkdtemp(prefix="mesh_scale_"))
    scenes = {case: write_shape(folder, *case) for case in cases}
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])))
    samples = {case: [] for case in cases}
    for rep in range(repeats):
        for case in cases:
            out = subprocess.run([sys.executable, __file__, "--child", str(scenes[case][0]), str(size), str(threads)],
                                 check=True, capture_output=True, text=True, env=env)
            samples[case].append(json.loads(out.stdout.strip().splitlines()[-1]))
            print(f"repeat {rep + 1}/{repeats} {case[0]} {case[1]}: {samples[case][-1]}", file=sys.stderr)

    keys = ("load", "pack", "bvh", "render", "total", "peak_rss")
    rows = []
    for case in cases:
        shape, nominal = case
        runs = samples[case]
        row = dict(shape=shape, size=nominal, triangles=runs[0]["faces"], width=size, height=size, threads=threads,
                   repeats=len(runs), rays_total=runs[0]["rays"])
        for k in keys:
            vals = np.array([r[k] for r in runs], dtype=float)
            if k == "peak_rss":
                vals = vals / 2**20  # MiB
                k = "peak_rss_mib"
            else:
                k = f"{k}_s"
            row[f"{k}_median"] = float(np.median(vals))
            row[f"{k}_min"] = float(vals.min())
            row[f"{k}_max"] = float(vals.max())
        rows.append(row)
    for row in rows:
        base = next(r for r in rows if r["shape"] == row["shape"] and r["size"] == "10k")
        for k in ("load_s", "pack_s", "bvh_s", "render_s", "total_s", "peak_rss_mib"):
            row[f"{k}_ratio_to_10k"] = row[f"{k}_median"] / base[f"{k}_median"]

    print(f"\n{size}x{size}, default settings, {threads} threads; median [min, max] over {repeats} fresh processes;"
          " ratio of medians to the ~10k case of the same shape")
    for r in rows:
        print(f"{r['shape']:6s} {r['triangles']:>8d} triangles: "
              + "  ".join(f"{k} {r[k + '_s_median']:.3f} s [{r[k + '_s_min']:.3f}, {r[k + '_s_max']:.3f}]"
                          f" x{r[k + '_s_ratio_to_10k']:.2f}"
                          for k in ("load", "pack", "bvh", "render", "total"))
              + f"  peak RSS {r['peak_rss_mib_median']:.0f} MiB [{r['peak_rss_mib_min']:.0f},"
                f" {r['peak_rss_mib_max']:.0f}] x{r['peak_rss_mib_ratio_to_10k']:.2f}")
    fields = ["shape", "size", "triangles", "width", "height", "threads", "repeats", "rays_total"]
    for k in ("load_s", "pack_s", "bvh_s", "render_s", "total_s", "peak_rss_mib"):
        fields += [f"{k}_median", f"{k}_min", f"{k}_max", f"{k}_ratio_to_10k"]
    write_csv(args.out, rows, provenance("benchmarks/mesh_scale.py",
                                         f"{os.cpu_count()} cores visible, numba threads {threads}; each case in a "
                                         "fresh process; regenerate with: python benchmarks/mesh_scale.py"),
              fieldnames=fields, float_format="{:.6g}")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
