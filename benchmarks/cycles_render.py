"""Render a peer scene with Blender's Cycles (runs under the Cycles venv's Python only).

Run:  .venv-cycles/bin/python benchmarks/cycles_render.py JOB.json
(``make peers`` creates ``.venv-cycles``; ``benchmarks/peer_cycles.py`` writes the job and calls
this script.)  It imports ``bpy`` and NumPy only, never ``bubbleoptics``: Blender's wheel
(bpy 5.0.1) needs numpy < 2, the project numpy >= 2, so they cannot share an environment.

The job (JSON) is the scene in *our* frame (y up, as ``tracer``) and a list of renders::

    {"width": 128, "height": 128, "threads": 2, "bounces": 32, "subdivisions": 6,
     "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov_deg": 40},
     "environment": "env.npy",            # (H, W, 3) float32, equirectangular, row 0 at +y
     "orientation": "matched",            # or "flipped", "tilted" (controls that must fail)
     "object": {"kind": "bubble", "center": [0, 0, 0], "radius": 1.0,
                "thickness_nm": 400.0, "film_ior": 1.33},   # kind "mirror" or "empty"
     "renders": [{"spp": 16, "seed": 1, "out": "a.npy"}, ...],
     "report": "timing.json"}

Each render writes float32 linear Rec.709 RGB, (height, width, 3), row 0 at the top, to its
``out`` and its wall time to the report.  Our frame maps to Blender's z-up one by
(x, y, z) -> (x, -z, y).  Cycles: CPU, ``threads`` threads, path tracing, fixed seed, no
adaptive sampling, no denoiser, no clamping, no glossy filter, caustics on, ``bounces`` for
every kind of bounce, box pixel filter 1 px wide, Standard view transform (look None,
exposure 0, gamma 1), output read back from a 32-bit float EXR (scene-linear).

The environment is the image in an Environment Texture (equirectangular, linear interpolation)
driven by the world direction: Blender puts the image's last row (bottom-up storage) at
elevation +90 degrees, so our top-down image is stored flipped.  The controls: ``"flipped"``
stores it unflipped (the sky below), ``"tilted"`` rotates the lookup 90 degrees about x
(what forgetting the y-up to z-up conversion does).

The bubble: a Principled BSDF (base colour white, metallic 0, roughness 0, IOR 1.0,
transmission 1, thin film ``thickness_nm`` of index ``film_ior``) on an icosphere of
``subdivisions`` (20 * 4^s triangles) with custom normals set to the exact radial
directions.  The mirror: a Glossy BSDF, white, roughness 0.
"""

import json
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

bpy = None  # imported by main(): the helpers above it are usable (and tested) without Blender


def to_blender(v):
    """Our frame (y up) to Blender's (z up): (x, y, z) -> (x, -z, y)."""
    x, y, z = (float(c) for c in v)
    return (x, -z, y)


def setup_scene(job):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    cyc = scene.cycles
    cyc.device = "CPU"
    cyc.use_adaptive_sampling = False
    cyc.use_denoising = False
    cyc.sample_clamp_direct = 0.0
    cyc.sample_clamp_indirect = 0.0
    cyc.blur_glossy = 0.0
    cyc.caustics_reflective = True
    cyc.caustics_refractive = True
    b = int(job.get("bounces", 32))
    cyc.max_bounces = b
    cyc.glossy_bounces = b
    cyc.transmission_bounces = b
    cyc.transparent_max_bounces = b
    cyc.diffuse_bounces = 0
    cyc.volume_bounces = 0
    cyc.pixel_filter_type = "BOX"
    cyc.filter_width = 1.0
    cyc.use_animated_seed = False
    scene.render.threads_mode = "FIXED"
    scene.render.threads = int(job.get("threads", 2))
    scene.render.resolution_x = int(job["width"])
    scene.render.resolution_y = int(job["height"])
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    scene.render.use_persistent_data = True
    vs = scene.view_settings
    vs.view_transform = "Standard"
    vs.look = "None"
    vs.exposure = 0.0
    vs.gamma = 1.0
    settings = scene.render.image_settings
    settings.file_format = "OPEN_EXR"
    settings.color_depth = "32"
    settings.exr_codec = "NONE"
    settings.color_mode = "RGBA"

    # camera
    cam = job["camera"]
    data = bpy.data.cameras.new("camera")
    data.type = "PERSP"
    data.sensor_fit = "VERTICAL"
    data.angle_y = math.radians(float(cam["fov_deg"]))
    data.clip_start = 1e-3
    obj = bpy.data.objects.new("camera", data)
    scene.collection.objects.link(obj)
    scene.camera = obj
    from mathutils import Matrix, Vector  # Blender's, available once bpy is imported

    pos = Vector(to_blender(cam["position"]))
    fwd = (Vector(to_blender(cam["look_at"])) - pos).normalized()
    up = Vector(to_blender(cam["up"]))
    right = fwd.cross(up).normalized()
    true_up = right.cross(fwd)
    # a Blender camera looks along its local -z with local +y up
    rot = Matrix((right, true_up, -fwd)).transposed()
    obj.matrix_world = Matrix.Translation(pos) @ rot.to_4x4()

    setup_world(scene, job)
    setup_object(scene, job)
    return scene


def setup_world(scene, job):
    env = np.load(job["environment"]).astype(np.float32)
    h, w, _ = env.shape
    orientation = job.get("orientation", "matched")
    if orientation not in ("matched", "flipped", "tilted"):
        raise SystemExit(f"cycles_render.py: unknown orientation {orientation!r}")
    stored = env if orientation == "flipped" else env[::-1]  # Blender stores rows bottom-up
    rgba = np.concatenate([stored, np.ones((h, w, 1), np.float32)], axis=2)
    image = bpy.data.images.new("environment", width=w, height=h, alpha=True, float_buffer=True)
    image.colorspace_settings.name = "Linear Rec.709"
    image.pixels.foreach_set(rgba.ravel())
    image.pack()

    world = bpy.data.worlds.new("world")
    scene.world = world
    world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    nodes.clear()
    coord = nodes.new("ShaderNodeTexCoord")
    mapping = nodes.new("ShaderNodeMapping")
    mapping.vector_type = "VECTOR"
    if orientation == "tilted":
        mapping.inputs["Rotation"].default_value = (math.pi / 2.0, 0.0, 0.0)
    tex = nodes.new("ShaderNodeTexEnvironment")
    tex.image = image
    tex.interpolation = "Linear"
    tex.projection = "EQUIRECTANGULAR"
    background = nodes.new("ShaderNodeBackground")
    background.inputs["Strength"].default_value = 1.0
    out = nodes.new("ShaderNodeOutputWorld")
    links.new(coord.outputs["Generated"], mapping.inputs["Vector"])
    links.new(mapping.outputs["Vector"], tex.inputs["Vector"])
    links.new(tex.outputs["Color"], background.inputs["Color"])
    links.new(background.outputs["Background"], out.inputs["Surface"])


def setup_object(scene, job):
    spec = job["object"]
    kind = spec["kind"]
    if kind == "empty":
        return
    if kind not in ("bubble", "mirror"):
        raise SystemExit(f"cycles_render.py: unknown object kind {kind!r}")
    radius = float(spec.get("radius", 1.0))
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=int(job.get("subdivisions", 6)), radius=radius,
                                          location=to_blender(spec.get("center", (0, 0, 0))))
    obj = bpy.context.active_object
    mesh = obj.data
    co = np.empty(3 * len(mesh.vertices), np.float32)
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3).astype(np.float64)
    normals = co / np.linalg.norm(co, axis=1, keepdims=True)
    mesh.polygons.foreach_set("use_smooth", np.ones(len(mesh.polygons), bool))
    mesh.normals_split_custom_set_from_vertices([tuple(n) for n in normals])

    mat = bpy.data.materials.new(kind)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    if kind == "mirror":
        bsdf = nodes.new("ShaderNodeBsdfGlossy")
        bsdf.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        bsdf.inputs["Roughness"].default_value = 0.0
        links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    else:
        bsdf = nodes.new("ShaderNodeBsdfPrincipled")
        values = {"Base Color": (1.0, 1.0, 1.0, 1.0), "Metallic": 0.0, "Roughness": 0.0, "IOR": 1.0,
                  "Transmission Weight": 1.0, "Alpha": 1.0, "Coat Weight": 0.0, "Sheen Weight": 0.0,
                  "Emission Strength": 0.0, "Subsurface Weight": 0.0,
                  "Thin Film Thickness": float(spec["thickness_nm"]), "Thin Film IOR": float(spec["film_ior"])}
        for name, value in values.items():
            bsdf.inputs[name].default_value = value
        links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    obj.data.materials.append(mat)


def render(scene, spp, seed, folder):
    scene.cycles.samples = int(spp)
    scene.cycles.seed = int(seed)
    path = Path(folder) / "render.exr"
    scene.render.filepath = str(path)
    t0 = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    seconds = time.perf_counter() - t0
    image = bpy.data.images.load(str(path), check_existing=False)
    w, h = image.size
    px = np.empty(w * h * 4, np.float32)
    image.pixels.foreach_get(px)
    bpy.data.images.remove(image)
    return px.reshape(h, w, 4)[::-1, :, :3].copy(), seconds


def main(argv):
    global bpy
    if len(argv) != 1:
        raise SystemExit("usage: cycles_render.py JOB.json")
    import warnings

    warnings.filterwarnings("ignore", category=DeprecationWarning)  # use_nodes (kept for Blender 4.x)
    import bpy
    job = json.loads(Path(argv[0]).read_text())
    scene = setup_scene(job)
    results = []
    with tempfile.TemporaryDirectory(prefix="cycles_") as folder:
        for r in job["renders"]:
            image, seconds = render(scene, r["spp"], r["seed"], folder)
            np.save(r["out"], image)
            results.append({"spp": r["spp"], "seed": r["seed"], "out": r["out"], "seconds": seconds})
    report = {"blender": bpy.app.version_string, "renders": results,
              "faces": sum(len(o.data.polygons) for o in scene.objects if o.type == "MESH")}
    Path(job["report"]).write_text(json.dumps(report))
    return 0


if __name__ == "__main__":
    argv = sys.argv[1:]
    if "--" in argv:  # when run as `blender -b -P cycles_render.py -- JOB.json`
        argv = argv[argv.index("--") + 1 :]
    sys.exit(main(argv))
