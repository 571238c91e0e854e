"""Meshes at scale: face orientation without dense matrices (:mod:`tracer.prepare.meshes`), vertex
welding and normals, and packing a mesh of a few hundred thousand triangles.

reference: :func:`literal_rule` below is the coursework's orientation rule written out
literally (every vertex against every face plane, a V x F matrix), used on small
meshes only; trimesh's ``weighted_vertex_normals`` for the computed vertex normals.
property: many random convex and non-convex meshes.  api: packing 200k+ triangles works in
bounded memory (no V x F matrix).  No test here measures time.
"""

import tracemalloc

import numpy as np
import pytest

from tracer.prepare import meshes
from tracer.prepare.meshes import computed_vertex_normals, corner_normals, face_normals, orient_faces, weld_vertices


def literal_rule(vertices, faces, normals):
    """The coursework's rule, literally: the faces whose normal is to be negated (empty unless
    convex).  Convex: every vertex on the inner side of every face plane, each face's normal
    turned away from the centroid of the vertices, within 1e-9 (max|x| + 1)."""
    used = np.unique(faces)
    v = vertices[used]
    centroid = v.mean(axis=0)
    side = np.einsum("ij,ij->i", normals, vertices[faces].mean(axis=1) - centroid)
    offsets = np.einsum("ij,ij->i", normals, vertices[faces[:, 0]])
    signed = v @ normals.T - offsets[None, :]
    flip = np.where(side < 0, -1.0, 1.0)
    convex = np.all(signed * flip[None, :] <= 1e-9 * (np.abs(v).max() + 1.0))
    return (flip < 0) if convex else np.zeros(len(faces), bool)


def hull_mesh(points, rng, soup=False):
    """The convex hull of *points* (scipy's Qhull) with every face's winding drawn at random;
    as a soup (three vertices of its own per face, like STL) if *soup*."""
    from scipy.spatial import ConvexHull

    faces = ConvexHull(points).simplices.copy()
    turn = rng.random(len(faces)) < 0.5
    faces[turn] = faces[turn][:, ::-1]
    if soup:
        return points[faces].reshape(-1, 3), np.arange(3 * len(faces)).reshape(-1, 3)
    return points, faces


def sphere_points(rng, n):
    v = rng.normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def decide(vertices, faces):
    normals, zero = face_normals(vertices, faces)
    assert not zero.any()
    flip, verdict = orient_faces(vertices, faces, normals)
    return flip, verdict, normals


# ------------------------------------------------------------------------------------------
# The rule, against its literal form
# ------------------------------------------------------------------------------------------
@pytest.mark.property
@pytest.mark.parametrize("seed", range(12))
def test_convex_meshes_are_turned_outward_as_the_literal_rule_says(seed):
    rng = np.random.default_rng(seed)
    kind = seed % 3
    if kind == 0:
        pts = sphere_points(rng, 60)
    elif kind == 1:
        pts = rng.uniform(-1, 1, (80, 3)) * [3.0, 1.0, 0.2]  # a flat-ish box of points
    else:
        pts = sphere_points(rng, 40) * [1.0, 2.0, 5.0] + 1e4  # an ellipsoid far from the origin
    for soup in (False, True):
        v, f = hull_mesh(pts, rng, soup=soup)
        flip, verdict, normals = decide(v, f)
        assert verdict == "convex"
        np.testing.assert_array_equal(flip, literal_rule(v, f, normals))
        turned = np.where(flip[:, None], -normals, normals)
        centre = v[f].mean(axis=1)
        assert (np.einsum("ij,ij->i", turned, centre - v[np.unique(f)].mean(0)) > 0).all()


@pytest.mark.property
@pytest.mark.parametrize("seed", range(8))
def test_non_convex_meshes_keep_their_winding(seed):
    """A dent, two nested shells (a hollow ball), two separate bodies, a torus: each is not
    convex by the literal rule, and keeps the file's winding."""
    rng = np.random.default_rng(100 + seed)
    pts = sphere_points(rng, 50)
    v, f = hull_mesh(pts, rng)
    cases = {}
    dent = v.copy()
    dent[f[0, 0]] *= 0.7  # pull one hull vertex inwards: a concave corner
    cases["dent"] = (dent, f)
    cases["hollow ball"] = (np.concatenate([v, 0.5 * v]), np.concatenate([f, f[:, ::-1] + len(v)]))
    cases["two bodies"] = (np.concatenate([v, v + [3.0, 0.0, 0.0]]), np.concatenate([f, f + len(v)]))
    import trimesh

    torus = trimesh.creation.torus(1.0, 0.3, major_sections=12 + seed, minor_sections=8)
    cases["torus"] = (np.asarray(torus.vertices), np.asarray(torus.faces))
    for name, (vv, ff) in cases.items():
        flip, verdict, normals = decide(vv, ff)
        assert not literal_rule(vv, ff, normals).any(), name
        assert verdict == "not convex" and not flip.any(), name


@pytest.mark.reference
def test_open_meshes_small_enough_are_checked_literally():
    rng = np.random.default_rng(7)
    v, f = hull_mesh(sphere_points(rng, 200), rng)
    cap = f[v[f].mean(axis=1)[:, 2] > 0.3]  # an open cap of the sphere: convex by the rule
    flip, verdict, normals = decide(v, cap)
    assert verdict == "convex" and flip.any()
    np.testing.assert_array_equal(flip, literal_rule(v, cap, normals))
    # a spiral strip: convex at every edge, open, but not convex
    t = np.linspace(0, 1.9 * np.pi, 60)
    r = np.exp(0.25 * t)
    ring = np.stack([r * np.cos(t), r * np.sin(t), np.zeros_like(t)], axis=1)
    sv = np.concatenate([ring, ring + [0.0, 0.0, 1.0]])
    n = len(t)
    sf = np.array([[i, i + 1, n + i] for i in range(n - 1)] + [[i + 1, n + i + 1, n + i] for i in range(n - 1)])
    flip, verdict, normals = decide(sv, sf)
    assert not literal_rule(sv, sf, normals).any()
    assert verdict == "not convex" and not flip.any()


@pytest.mark.api
def test_flat_meshes_keep_their_winding_and_large_open_ones_are_not_checked(monkeypatch):
    rng = np.random.default_rng(3)
    xy = rng.uniform(-1, 1, (40, 2))
    from scipy.spatial import Delaunay

    f = Delaunay(xy).simplices
    v = np.column_stack([xy, np.full(len(xy), 2.0)]) @ np.linalg.qr(rng.normal(size=(3, 3)))[0]
    flip, verdict, _ = decide(v, f)
    assert verdict == "flat" and not flip.any()
    # an open cap above the literal check's size keeps its winding (documented)
    pv, pf = hull_mesh(sphere_points(rng, 100), rng)
    cap = pf[pv[pf].mean(axis=1)[:, 2] > 0.2]
    monkeypatch.setattr(meshes, "EXACT_CHECK_PAIRS", 10)
    flip, verdict, _ = decide(pv, cap)
    assert verdict == "open mesh too large to check" and not flip.any()


@pytest.mark.analytic
def test_the_coursework_tetrahedron_points_outward():
    import tracer

    scene = tracer.load_scene("data/coursework_scenes/listing_3_1.txt")
    (mesh,) = scene.meshes
    flip, verdict, normals = decide(mesh.vertices, mesh.faces)
    assert verdict == "convex"
    turned = np.where(flip[:, None], -normals, normals)
    opposite = [np.setdiff1d(np.arange(4), face)[0] for face in mesh.faces]
    for k, face in enumerate(mesh.faces):  # the fourth vertex is behind every face
        assert turned[k] @ (mesh.vertices[opposite[k]] - mesh.vertices[face[0]]) < 0


# ------------------------------------------------------------------------------------------
# Welding and normals
# ------------------------------------------------------------------------------------------
@pytest.mark.reference
def test_weld_vertices_matches_numpy_unique():
    rng = np.random.default_rng(0)
    base = rng.normal(size=(500, 3))
    base[:10] = 0.0
    base[5:10] = -0.0  # equal to 0.0
    v = base[rng.integers(0, 500, 3000)]
    ids, n = weld_vertices(v)
    _, inverse = np.unique(v + 0.0, axis=0, return_inverse=True)
    inverse = inverse.ravel()
    assert n == len(np.unique(inverse))
    # the same partition of the vertices (numbered differently)
    pairs = np.unique(np.stack([ids, inverse], axis=1), axis=0)
    assert len(pairs) == n
    assert ids[0] == 0 and (np.diff(np.maximum.accumulate(ids)) <= 1).all()  # first-appearance order


@pytest.mark.reference
def test_computed_vertex_normals_match_trimesh():
    import trimesh

    mesh = trimesh.creation.icosphere(subdivisions=2)
    rng = np.random.default_rng(1)
    v = np.asarray(mesh.vertices) * [1.0, 2.0, 0.5] + rng.normal(scale=0.01, size=mesh.vertices.shape)
    f = np.asarray(mesh.faces)
    normals, _ = face_normals(v, f)
    ours = computed_vertex_normals(v, f, normals)
    ref = trimesh.geometry.weighted_vertex_normals(len(v), f, normals, trimesh.triangles.angles(v[f]))
    np.testing.assert_allclose(ours, ref, rtol=0, atol=1e-7)
    # the same on a soup (each face its own vertices): welded by position, so smooth too
    sv = v[f].reshape(-1, 3)
    sf = np.arange(len(sv)).reshape(-1, 3)
    np.testing.assert_allclose(computed_vertex_normals(sv, sf, normals), ref[f].reshape(-1, 3), rtol=0, atol=1e-7)


@pytest.mark.analytic
def test_corner_normals_are_unit_and_on_the_side_of_the_face():
    v = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    f = np.array([[0, 1, 2]])
    ng = np.array([[0.0, 0.0, 1.0]])
    vn = np.array([[0.0, 0.0, -2.0], [np.nan, 0.0, 1.0], [1.0, 0.0, 0.0]])  # opposite, NaN, perpendicular
    out = corner_normals(vn, f, ng)
    np.testing.assert_array_equal(out[0], [[0, 0, 1.0], [0, 0, 1.0], [0, 0, 1.0]])
    vn = np.array([[0.0, 3.0, 4.0], [0.0, -3.0, -4.0], [0.0, 0.0, 1e-300]])
    out = corner_normals(vn, f, ng)
    np.testing.assert_allclose(out[0], [[0, 0.6, 0.8], [0, 0.6, 0.8], [0, 0, 1.0]], rtol=0, atol=1e-15)


# ------------------------------------------------------------------------------------------
# Packing at scale
# ------------------------------------------------------------------------------------------
@pytest.mark.api
@pytest.mark.parametrize("shape", ["sphere", "torus"])
def test_packing_a_200k_triangle_mesh_needs_no_dense_matrix(shape):
    """A convex mesh (every face turned outward) and a non-convex one (winding kept) of about
    200k triangles pack; NumPy's peak allocation stays within a few hundred bytes per triangle
    (a V x F matrix of float64 would be 160 GB here)."""
    import trimesh

    import tracer
    from tracer.kernels.records import SURFACE_PHONG
    from tracer.prepare.pack import pack_scene
    from tracer.scene import Mesh, Scene

    if shape == "sphere":
        m = trimesh.creation.uv_sphere(count=[160, 320])
    else:
        m = trimesh.creation.torus(1.0, 0.4, major_sections=450, minor_sections=225)
    v, f = np.asarray(m.vertices), np.asarray(m.faces)
    rng = np.random.default_rng(0)
    f = np.where((rng.random(len(f)) < 0.5)[:, None], f[:, ::-1], f) if shape == "sphere" else f
    assert len(f) >= 190_000
    scene = Scene(meshes=[Mesh(vertices=v, faces=f, shading="smooth")])
    pack_scene(Scene(meshes=[Mesh(vertices=v[:3], faces=np.array([[0, 1, 2]]))]))  # numba's kernels loaded
    tracemalloc.start()
    packed = pack_scene(scene)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 600 * len(f)
    tri = packed.tris
    assert tri.shape == (len(f), 3, 3) and (packed.triangles["surface"] == SURFACE_PHONG).all()
    n = packed.triangles["normal"]
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, rtol=0, atol=1e-12)
    winding = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    along = np.einsum("ij,ij->i", winding, n)
    outward = np.einsum("ij,ij->i", tri.mean(axis=1), n) > 0  # both shapes are centred on the origin
    if shape == "sphere":
        assert outward.all()
        assert (along < 0).any() and (along > 0).any()  # some faces were turned
    else:
        assert (along > 0).all()  # the file's winding kept (trimesh winds its torus outward)
    # smooth shading: every corner normal on the side of its face, unit length
    vn = packed.triangles["vertex_normals"]
    assert packed.triangles["smooth"].all()
    assert (np.einsum("ijk,ik->ij", vn, n) > 0).all()
    np.testing.assert_allclose(np.linalg.norm(vn, axis=2), 1.0, rtol=0, atol=1e-12)
    assert tracer.kernels.geometry.STACK_SIZE == 64
