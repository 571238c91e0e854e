"""Smooth shading of meshes: interpolated vertex normals (:func:`tracer.kernels.geometry.shading_normal`),
normals from mesh files, and the TOML ``shading`` key.

reference: a finely tessellated sphere shaded smooth renders close to the tracer's analytic
sphere of the same material (an independent primitive: ray-sphere roots, exact normals); flat,
it differs more.  analytic: a quad whose file normals are tilted by a known angle renders the
Phong terms computed here from that normal; a light inside a closed opaque mesh lights nothing
outside it.  property: the shading normal never sends a mirror ray into the surface, never NaN.
api: the TOML keys and their one-line errors.
"""

import math

import numpy as np
import pytest
from numba import njit

import tracer
from tracer.scene.errors import SceneError
from tracer.kernels.geometry import shading_normal
from tracer.prepare.meshes import corner_normals
from tracer.scene import Camera, Environment, Material, Mesh, PointLight, Scene, Sphere
from tracer.scene.toml_read import load_toml_scene, parse_toml_text
from tracer.scene.toml_write import scene_to_toml_text

CLAY = Material(name="clay", color=(0.8, 0.3, 0.2), ambient=0.1, diffuse=0.8, specular=0.3, shininess=20.0)
BLACK = Environment(kind="constant", color=(0.0, 0.0, 0.0))


def camera_rays(camera, width, height):
    """Origin and unit directions (H, W, 3) through the pixel centres (docs/scene-format.md)."""
    pos = np.asarray(camera.position, float)
    fwd = np.asarray(camera.look_at, float) - pos
    fwd /= np.linalg.norm(fwd)
    right = np.cross(fwd, np.asarray(camera.up, float))
    right /= np.linalg.norm(right)
    up = np.cross(right, fwd)
    half = np.tan(np.radians(camera.fov_deg) / 2)
    u = ((np.arange(width) + 0.5) / width * 2 - 1) * half * width / height
    v = (1 - (np.arange(height) + 0.5) / height * 2) * half
    d = fwd + u[None, :, None] * right + v[:, None, None] * up
    return pos, d / np.linalg.norm(d, axis=2, keepdims=True)


def icosphere(subdivisions):
    import trimesh

    m = trimesh.creation.icosphere(subdivisions=subdivisions)
    return np.asarray(m.vertices), np.asarray(m.faces)


# ------------------------------------------------------------------------------------------
# Against the analytic sphere
# ------------------------------------------------------------------------------------------
@pytest.mark.reference
def test_smooth_sphere_mesh_renders_like_the_analytic_sphere():
    size = 64
    camera = Camera(position=(0.0, 0.0, 4.0), look_at=(0.0, 0.0, 0.0), fov_deg=40.0)
    lights = [PointLight(position=(3.0, 4.0, 5.0))]
    common = dict(lights=lights, camera=camera, environment=BLACK)
    settings = dict(width=size, height=size, depth=2, progress=False)
    analytic = tracer.render(Scene(spheres=[Sphere(center=(0.0, 0.0, 0.0), radius=1.0, material=CLAY)], **common),
                             **settings)
    v, f = icosphere(4)  # 5120 faces, vertices on the unit sphere
    images = {s: tracer.render(Scene(meshes=[Mesh(vertices=v, faces=f, material=CLAY, shading=s)], **common),
                               **settings) for s in ("smooth", "flat")}
    # pixels well inside the disc (the mesh is inscribed: its silhouette is a little smaller)
    origin, d = camera_rays(camera, size, size)
    along = -d @ origin
    miss = np.sqrt(np.maximum(origin @ origin - along**2, 0.0))
    inside = miss < 0.95
    assert inside.sum() > 400
    err = {s: np.abs(img - analytic)[inside] for s, img in images.items()}
    for img in images.values():
        assert np.isfinite(img).all()
    assert err["smooth"].mean() < 1e-3 and err["smooth"].max() < 0.03
    assert err["flat"].mean() > 5 * err["smooth"].mean()  # facets
    # the highlight: flat shading breaks it into facets, smooth keeps its peak where the analytic one is
    peak = np.unravel_index(np.argmax(analytic.sum(-1)), analytic.shape[:2])
    assert np.abs(np.array(np.unravel_index(np.argmax(images["smooth"].sum(-1)), (size, size))) - peak).max() <= 1


# ------------------------------------------------------------------------------------------
# Normals from the file
# ------------------------------------------------------------------------------------------
ALPHA = 0.4  # the normals' tilt from +z towards +x, radians


def _quad_files(tmp_path):
    """The square [-1, 1]^2 at z = 0 as two triangles, every vertex normal tilted by ALPHA, as an
    OBJ written here and as a PLY written by trimesh."""
    import trimesh

    n = (math.sin(ALPHA), 0.0, math.cos(ALPHA))
    obj = tmp_path / "quad.obj"
    obj.write_text("v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
                   f"vn {n[0]!r} {n[1]!r} {n[2]!r}\nf 1//1 2//1 3//1\nf 1//1 3//1 4//1\n")
    verts = np.array([[-1.0, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]])
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    mesh = trimesh.Trimesh(verts, faces, vertex_normals=np.tile(n, (4, 1)), process=False)
    ply = tmp_path / "quad.ply"
    ply.write_bytes(trimesh.exchange.ply.export_ply(mesh, encoding="binary", vertex_normal=True))
    return obj, ply


def _quad_scene(tmp_path, mesh_file, shading=None):
    key = f'shading = "{shading}"\n' if shading else ""
    text = f"""[camera]
position = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
fov_deg = 30

[environment]
kind = "constant"
color = [0.0, 0.0, 0.0]

[[meshes]]
path = "{mesh_file.name}"
material = {{ color = [0.8, 0.6, 0.4], ambient = 0.1, diffuse = 0.7, specular = 0.0 }}
{key}
[[lights]]
position = [-2.0, 1.0, 4.0]
intensity = 1.5
"""
    path = tmp_path / f"quad_{mesh_file.suffix[1:]}_{shading}.toml"
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.analytic
@pytest.mark.parametrize("fmt", ["obj", "ply"])
def test_tilted_file_normals_change_the_image_as_predicted(tmp_path, fmt):
    """Diffuse Phong, one light, RGB transport: on the quad every pixel is
    ka C + kd (N.L) C I with N the file's (tilted) normal by default, the plane's with
    shading = "flat"; computed here from the camera and the light, to rounding."""
    obj, ply = _quad_files(tmp_path)
    mesh_file = obj if fmt == "obj" else ply
    size = 40
    color = np.array([0.8, 0.6, 0.4])
    light = np.array([-2.0, 1.0, 4.0])
    tilted = np.array([math.sin(ALPHA), 0.0, math.cos(ALPHA)])
    if fmt == "ply":  # trimesh writes a PLY's normals as float32
        tilted = tilted.astype(np.float32).astype(float)
        tilted /= np.linalg.norm(tilted)
    for shading, normal in ((None, tilted), ("smooth", tilted), ("flat", np.array([0.0, 0.0, 1.0]))):
        scene = load_toml_scene(_quad_scene(tmp_path, mesh_file, shading))
        (mesh,) = scene.meshes
        assert mesh.shading == ("flat" if shading == "flat" else "smooth")
        assert mesh.normals is not None
        image = tracer.render(scene, width=size, height=size, depth=1, progress=False)
        origin, d = camera_rays(scene.camera, size, size)
        t = -origin[2] / d[..., 2]
        p = origin + t[..., None] * d
        on = (np.abs(p[..., :2]) < 0.98).all(axis=-1)
        assert on.sum() > 300
        to_light = light - p
        to_light /= np.linalg.norm(to_light, axis=-1, keepdims=True)
        ndl = np.maximum(to_light @ normal, 0.0)
        expected = (0.1 + 0.7 * 1.5 * ndl)[..., None] * color
        np.testing.assert_allclose(image[on], expected[on], rtol=1e-9, atol=1e-12)


# ------------------------------------------------------------------------------------------
# No NaN, no light leak
# ------------------------------------------------------------------------------------------
@pytest.mark.analytic
def test_a_light_inside_a_closed_smooth_mesh_lights_nothing_outside():
    """A coarse icosphere (80 faces: shading normals up to ~20 degrees off the facets) with a
    light at its centre, seen from outside: only the ambient term, exactly, wherever it is
    seen; and mirror and glass versions render finite images."""
    v, f = icosphere(1)
    size = 48
    camera = Camera(position=(0.0, 0.5, 3.5), look_at=(0.0, 0.0, 0.0), fov_deg=45.0)
    matte = Material(color=(0.5, 0.7, 0.9), ambient=0.2, diffuse=0.8, specular=0.0)
    scene = Scene(meshes=[Mesh(vertices=v, faces=f, material=matte, shading="smooth")],
                  lights=[PointLight(position=(0.0, 0.0, 0.0), intensity=5.0)], camera=camera, environment=BLACK)
    image = tracer.render(scene, width=size, height=size, depth=1, progress=False)
    seen = image.sum(-1) > 0
    assert seen.sum() > 300
    np.testing.assert_array_equal(image[seen], np.tile(0.2 * np.array([0.5, 0.7, 0.9]), (seen.sum(), 1)))
    # vertex normals given pointing inwards are turned to the faces' side: the same image
    inward = -v / np.linalg.norm(v, axis=1, keepdims=True)
    flipped = Scene(meshes=[Mesh(vertices=v, faces=f, material=matte, shading="smooth", normals=inward)],
                    lights=[PointLight(position=(2.0, 3.0, 4.0))], camera=camera, environment=BLACK)
    outward = Scene(meshes=[Mesh(vertices=v, faces=f, material=matte, shading="smooth", normals=-inward)],
                    lights=[PointLight(position=(2.0, 3.0, 4.0))], camera=camera, environment=BLACK)
    np.testing.assert_array_equal(tracer.render(flipped, width=size, height=size, depth=1, progress=False),
                                  tracer.render(outward, width=size, height=size, depth=1, progress=False))
    for mat in (Material(color=(0.9, 0.9, 0.9), ambient=0.0, diffuse=0.1, specular=1.0),
                Material(color=(1.0, 1.0, 1.0), ambient=0.0, diffuse=0.0, specular=0.0, transmission=1.0, ior=1.5)):
        glass = Scene(meshes=[Mesh(vertices=v, faces=f, material=mat, shading="smooth")],
                      lights=[PointLight(position=(2.0, 3.0, 4.0))], camera=camera,
                      environment=Environment(kind="sky"))
        img = tracer.render(glass, width=size, height=size, depth=8, progress=False)
        assert np.isfinite(img).all() and (img >= 0).all()


@njit(cache=True)
def _shading_batch(tris, vn, ng, bary, D, out, fell_back):
    for i in range(tris.shape[0]):
        v0 = (tris[i, 0, 0], tris[i, 0, 1], tris[i, 0, 2])
        v1 = (tris[i, 1, 0], tris[i, 1, 1], tris[i, 1, 2])
        v2 = (tris[i, 2, 0], tris[i, 2, 1], tris[i, 2, 2])
        p = (bary[i, 0] * v0[0] + bary[i, 1] * v1[0] + bary[i, 2] * v2[0],
             bary[i, 0] * v0[1] + bary[i, 1] * v1[1] + bary[i, 2] * v2[1],
             bary[i, 0] * v0[2] + bary[i, 1] * v1[2] + bary[i, 2] * v2[2])
        g = (ng[i, 0], ng[i, 1], ng[i, 2])
        n = shading_normal(v0, v1, v2, (vn[i, 0, 0], vn[i, 0, 1], vn[i, 0, 2]),
                           (vn[i, 1, 0], vn[i, 1, 1], vn[i, 1, 2]), (vn[i, 2, 0], vn[i, 2, 1], vn[i, 2, 2]), g, p,
                           (D[i, 0], D[i, 1], D[i, 2]))
        out[i, 0] = n[0]
        out[i, 1] = n[1]
        out[i, 2] = n[2]
        fell_back[i] = n[0] == g[0] and n[1] == g[1] and n[2] == g[2]


@pytest.mark.property
def test_shading_normal_never_points_a_mirror_ray_into_the_surface():
    """Random triangles, wild corner normals (any direction, as corner_normals orients them),
    rays from both sides down to grazing: the normal is unit, on the ray's side of the geometric
    one, and the mirror direction about it leaves on the incoming side of the plane; where the
    corner normals agree with the plane it is the plane's normal; it interpolates at vertices."""
    rng = np.random.default_rng(11)
    n = 20000
    tris = rng.normal(size=(n, 3, 3))
    ng = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    ng /= np.linalg.norm(ng, axis=1, keepdims=True)
    raw = rng.normal(size=(n * 3, 3))
    vn = corner_normals(raw, np.arange(3 * n).reshape(n, 3), ng)
    bary = rng.dirichlet(np.ones(3), n)
    D = rng.normal(size=(n, 3)) * rng.uniform(0.1, 10, (n, 1))
    graze = rng.random(n) < 0.3  # nearly in the plane
    D[graze] -= np.einsum("ij,ij->i", D[graze], ng[graze])[:, None] * ng[graze] * (1 - 1e-3)
    out = np.empty((n, 3))
    fell = np.empty(n, dtype=np.bool_)
    _shading_batch(tris, vn, ng, bary, D, out, fell)
    assert np.isfinite(out).all()
    np.testing.assert_allclose(np.linalg.norm(out, axis=1), 1.0, rtol=0, atol=1e-12)
    dg = np.einsum("ij,ij->i", D, ng)
    ds = np.einsum("ij,ij->i", D, out)
    assert (np.sign(ds) == np.sign(dg)).all()
    refl = D - 2 * ds[:, None] * out
    assert (np.einsum("ij,ij->i", refl, ng) * np.sign(dg) < 0).all()  # back to the side it came from
    assert 0.05 < fell.mean() < 0.9
    # corner normals equal to the plane's: the plane's normal, to rounding
    _shading_batch(tris, np.repeat(ng[:, None], 3, axis=1), ng, bary, D, out, fell)
    np.testing.assert_allclose(out, ng, rtol=0, atol=1e-15)
    # at a vertex: that vertex's normal, wherever it is valid
    corner = np.zeros((n, 3))
    corner[:, 1] = 1.0
    _shading_batch(tris, vn, ng, corner, D, out, fell)
    np.testing.assert_allclose(out[~fell], vn[~fell, 1], rtol=0, atol=1e-12)


# ------------------------------------------------------------------------------------------
# The TOML keys
# ------------------------------------------------------------------------------------------
HEAD = '[camera]\nposition = [0, 0, 5]\n\n[[meshes]]\nvertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\nfaces = [[0, 1, 2]]\n'


@pytest.mark.api
def test_toml_shading_defaults_and_round_trip():
    (m,) = parse_toml_text(HEAD).meshes
    assert m.shading == "flat" and m.normals is None  # inline mesh without normals: flat
    text = HEAD + "normals = [[0, 0, 1], [0, 0.1, 1], [0.1, 0, 1]]\n"
    (m,) = parse_toml_text(text).meshes
    assert m.shading == "smooth"
    np.testing.assert_array_equal(m.normals, [[0, 0, 1], [0, 0.1, 1], [0.1, 0, 1]])
    (m,) = parse_toml_text(text + 'shading = "flat"\n').meshes
    assert m.shading == "flat" and m.normals is not None
    (m,) = parse_toml_text(HEAD + 'shading = "smooth"\n').meshes
    assert m.shading == "smooth" and m.normals is None  # computed when packed
    for src in (text, HEAD + 'shading = "smooth"\n', HEAD):
        scene = parse_toml_text(src)
        back = parse_toml_text(scene_to_toml_text(scene)).meshes[0]
        assert back.shading == scene.meshes[0].shading
        assert (back.normals is None) == (scene.meshes[0].normals is None)
        if back.normals is not None:
            np.testing.assert_array_equal(back.normals, scene.meshes[0].normals)


@pytest.mark.api
@pytest.mark.parametrize("extra, line, message", [
    ('shading = "phong"\n', 7, "meshes[0].shading: must be one of 'auto', 'smooth', 'flat', got 'phong'"),
    ("shading = 1\n", 7, "meshes[0].shading: must be a string, got an integer"),
    ("normals = [[0, 0, 1]]\n", 7, "meshes[0].normals: must be an array of one [x, y, z] normal per vertex (3),"
                                   " got 1 entries"),
    ("normals = [[0, 0, 1], [0, 0, 0], [0, 0, 1]]\n", 7, "meshes[0].normals: must not be the zero vector"),
    ("normals = [[0, 0, 1], [0, 0, 1], [0, 0, nan]]\n", 7, "meshes[0].normals: must be a finite number, got nan"),
])
def test_toml_mesh_shading_errors_are_one_line(extra, line, message):
    with pytest.raises(SceneError) as info:
        parse_toml_text(HEAD + extra, "s.toml")
    text = str(info.value)
    assert "\n" not in text and text == f"s.toml:{line}: {message}"


@pytest.mark.api
def test_toml_normals_with_a_mesh_file_is_an_error(tmp_path):
    obj, _ = _quad_files(tmp_path)
    path = tmp_path / "bad.toml"
    path.write_text(f'[[meshes]]\npath = "{obj.name}"\nnormals = [[0, 0, 1]]\n', encoding="utf-8")
    with pytest.raises(SceneError, match=r"bad\.toml:3: meshes\[0\]\.normals: give either 'path' or 'vertices'"
                                         r" and 'faces', not both \(a mesh file carries its own normals\)$"):
        load_toml_scene(path)


@pytest.mark.api
def test_a_mesh_file_with_a_face_out_of_range_is_a_one_line_error(tmp_path):
    import trimesh

    m = trimesh.Trimesh(np.eye(3), [[0, 1, 2]], process=False)
    text = trimesh.exchange.ply.export_ply(m, encoding="ascii").decode()
    assert "3 0 1 2" in text
    (tmp_path / "bad.ply").write_text(text.replace("3 0 1 2", "3 0 1 7"))
    path = tmp_path / "s.toml"
    path.write_text('[[meshes]]\npath = "bad.ply"\n', encoding="utf-8")
    with pytest.raises(SceneError) as info:
        load_toml_scene(path)
    assert str(info.value) == (f"{path}:2: meshes[0].path: mesh 'bad.ply' has a face naming vertex 7 (0-based),"
                               " but there are 3 vertices")


@pytest.mark.api
def test_mesh_coordinates_beyond_the_limit_are_one_line_errors(tmp_path):
    (tmp_path / "far.obj").write_text("v 0 0 0\nv 2e15 0 0\nv 0 1 0\nf 1 2 3\n")
    (tmp_path / "near.obj").write_text("v 0 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\n")
    far = tmp_path / "far.toml"
    far.write_text('[[meshes]]\npath = "far.obj"\n', encoding="utf-8")
    with pytest.raises(SceneError) as info:
        load_toml_scene(far)
    assert str(info.value) == (f"{far}:2: meshes[0].path: mesh 'far.obj' has a vertex coordinate of magnitude"
                               " 2e+15, beyond 1e+15 (tracer.scene.limits)")
    scaled = tmp_path / "scaled.toml"
    scaled.write_text('[[meshes]]\npath = "near.obj"\nscale = 1e15\n', encoding="utf-8")
    with pytest.raises(SceneError) as info:
        load_toml_scene(scaled)
    assert str(info.value) == (f"{scaled}:3: meshes[0].scale: the mesh's vertices reach 2e+15, beyond 1e+15"
                               " (tracer.scene.limits)")


@pytest.mark.api
def test_a_mesh_built_in_code_with_bad_shading_fields_is_refused_when_packed():
    from tracer.prepare.pack import pack_scene

    v = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    f = np.array([[0, 1, 2]])
    with pytest.raises(ValueError, match=r"^mesh 'm': shading must be 'flat' or 'smooth' \(got 'phong'\)$"):
        pack_scene(Scene(meshes=[Mesh(vertices=v, faces=f, shading="phong", name="m")]))
    with pytest.raises(ValueError, match=r"^mesh 'm': normals must have the shape of vertices \(3, 3\)"):
        pack_scene(Scene(meshes=[Mesh(vertices=v, faces=f, shading="smooth", normals=np.ones((2, 3)), name="m")]))
    packed = pack_scene(Scene(meshes=[Mesh(vertices=v, faces=f, shading="flat", normals=np.ones((3, 3)))]))
    assert not packed.triangles["smooth"].any()  # flat: the normals are kept in the Mesh, not used
