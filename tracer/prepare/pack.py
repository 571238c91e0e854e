"""Turn a :class:`tracer.scene.Scene` into the :class:`tracer.kernels.records.PackedScene` the numba
integrator reads.

This is also where the renderer decides what a scene needs: spectral transport only when
something depends on wavelength (a bubble), otherwise three linear-sRGB channels; films
averaged over each band only when one is thick enough for point samples to alias.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from bubbleoptics import band_spectral_weights, point_sampling_limit_nm, rgb_reflectance_basis, water_refractive_index
from bubbleoptics.colorimetry import XYZ_TO_LINEAR_SRGB, srgb_dominant_wavelengths

from ..kernels import records as lay
from .bvh import build_bvh
from ..kernels.geometry import origin_epsilon
from ..kernels.records import PackedScene
from ..scene.limits import MAX_MAGNITUDE, SPECTRAL_METHODS
from .meshes import (computed_vertex_normals, corner_normals, face_normals, orient_faces, triangle_records,
                     weld_vertices)
from ..scene.model import MAX_LIGHT_SAMPLES, Scene, unit_vector

__all__ = ["pack_scene", "channel_setup", "film_thickness_bound_nm", "resolve_spectral_method",
           "AUTO_FRINGE_BANDS", "film_model_code", "camera_record", "film_index"]

_ENV_KINDS = {"constant": lay.ENV_CONSTANT, "sky": lay.ENV_SKY, "image": lay.ENV_IMAGE}
_PROFILES = {"uniform": lay.PROFILE_UNIFORM, "draining": lay.PROFILE_DRAINING, "map": lay.PROFILE_MAP}


#: Normalise the RGB -> bands basis (so that a colour entering the scene leaves as the same
#: colour) only where that is well conditioned: cond(to_rgb @ basis) is 1.06 at 16 bands, 1.4
#: at 8, 2.6 at 4 and 26 at 3 bands, where the inverse would amplify noise.
BASIS_NORMALISE_MAX_COND = 3.0


def channel_setup(spectral, n_bands):
    """(wavelengths, to_rgb (3, C), rgb_basis (C, 3)) for spectral or RGB transport.

    Spectral: *n_bands* equal bands over 360-780 nm, XYZ weights under D65
    (:func:`bubbleoptics.band_spectral_weights`), so a channel value is a factor on D65 and a
    perfect white reflector lit by a white light renders as sRGB (1, 1, 1).  RGB colours enter
    through the Mallett-Yuksel basis (:func:`bubbleoptics.rgb_reflectance_basis`), normalised
    by ``inv(to_rgb @ basis)`` where that is well conditioned, so that an RGB colour seen
    directly comes back unchanged (without it, 16 bands shift colours by up to 3.5 %).
    RGB: three linear-sRGB channels; a bubble's film is then evaluated at the dominant
    wavelengths of the sRGB primaries (611, 549, 464 nm), a crude stand-in for its spectrum
    that the run-time-against-error study quantifies.  New arrays on every call (computed once
    per setting and kept: many frames of a movie, or an editor's previews, pack the same).
    """
    return tuple(a.copy() for a in _channel_setup(bool(spectral), int(n_bands)))


@functools.lru_cache(maxsize=16)
def _channel_setup(spectral, n_bands):
    if not spectral:
        return srgb_dominant_wavelengths(), np.eye(3), np.eye(3)
    wl, w = band_spectral_weights(n_bands)
    to_rgb = XYZ_TO_LINEAR_SRGB @ w
    basis = rgb_reflectance_basis(n_bands)
    round_trip = to_rgb @ basis
    if np.linalg.cond(round_trip) <= BASIS_NORMALISE_MAX_COND:
        basis = basis @ np.linalg.inv(round_trip)
    return wl, to_rgb, basis


def _concatenate(parts, empty):
    """``np.concatenate(parts)`` without a copy for one part."""
    if not parts:
        return empty
    return parts[0] if len(parts) == 1 else np.concatenate(parts)


def _perpendicular(up):
    ref = np.cross(up, [1.0, 0.0, 0.0])
    if np.linalg.norm(ref) < 1e-6:
        ref = np.cross(up, [0.0, 0.0, 1.0])
    return ref / np.linalg.norm(ref)


def _mesh_triangles(mesh):
    """A mesh's triangles (T, 3, 3), their unit normals (T, 3) oriented by the coursework's rule
    (:func:`tracer.prepare.meshes.orient_faces`) and, for smooth shading, their corner normals
    (T, 3, 3) (``None`` for flat shading); faces of zero area left out."""
    v = np.ascontiguousarray(mesh.vertices, dtype=np.float64)
    f = np.ascontiguousarray(mesh.faces, dtype=np.int64)
    if mesh.shading not in ("flat", "smooth"):
        raise ValueError(f"mesh {mesh.name!r}: shading must be 'flat' or 'smooth' (got {mesh.shading!r})")
    nrm, zero = face_normals(v, f)
    if zero.any():
        f, nrm = f[~zero], nrm[~zero]
    weld = weld_vertices(v)
    flip, _ = orient_faces(v, f, nrm, weld)
    nrm[flip] *= -1.0
    corners = None
    if mesh.shading == "smooth":
        vn = mesh.normals
        if vn is None:
            vn = computed_vertex_normals(v, f, nrm, weld)
        elif np.shape(vn) != v.shape:
            raise ValueError(f"mesh {mesh.name!r}: normals must have the shape of vertices {v.shape}"
                             f" (got {np.shape(vn)})")
        corners = corner_normals(vn, f, nrm)
    return v[f], nrm, corners


def _triangle_records(parts, order):
    """The TRIANGLE records in BVH order (*order*) of the meshes' parts ``(normals, corner
    normals or None, material index)``."""
    n = [len(p[0]) for p in parts]
    if not sum(n):
        return np.zeros(0, lay.TRIANGLE)
    normals = _concatenate([p[0] for p in parts], None)
    smooth = np.repeat([p[1] is not None for p in parts], n)
    corners = (_concatenate([p[1] if p[1] is not None else np.zeros((len(p[0]), 3, 3)) for p in parts], None)
               if smooth.any() else None)
    material = np.repeat(np.array([p[2] for p in parts], dtype=np.int64), n)
    return triangle_records(order, normals, corners, material, smooth, lay.SURFACE_PHONG)




def film_thickness_bound_nm(film) -> float:
    """An upper bound of a :class:`~tracer.scene.FilmProfile`'s thickness over the bubble, in nm.

    Uniform: its thickness; draining: the larger of top and bottom (the profile runs between
    them); map: the table's maximum (bilinear interpolation stays within it).  Swirl multiplies
    the thickness by 1 + a·s/4 with s a sum of four sines, so by at most 1 + |a|.
    """
    if film.kind == "uniform":
        base = float(film.thickness_nm)
    elif film.kind == "draining":
        base = max(float(film.top_nm), float(film.bottom_nm))
    elif film.kind == "map":
        base = float(np.max(film.table)) if film.table is not None and np.size(film.table) else 0.0
    elif film.kind == "simulated":
        from ..scene.simulated import sampled_film

        return film_thickness_bound_nm(sampled_film(film))
    else:
        raise ValueError(f"unknown film kind {film.kind!r}")
    return max(base, 0.0) * (1.0 + abs(float(film.swirl)))


#: ``spectral_method="auto"`` switches to band-averaged films when a film's fringe period at
#: 400 nm can be shorter than this many bands (see :func:`resolve_spectral_method`).
AUTO_FRINGE_BANDS = 1.5


def resolve_spectral_method(scene: Scene, spectral_samples, spectral_method="auto"):
    """The film method a render uses: ``"point"`` or ``"band"``; *spectral_method* ``"auto"`` decides.

    ``"auto"`` chooses ``"band"`` (films averaged over each band) when some bubble's film can be
    thicker than :func:`bubbleoptics.point_sampling_limit_nm` / :data:`AUTO_FRINGE_BANDS` for
    *spectral_samples* bands (its index at 400 nm, normal incidence: the thinnest limit), i.e.
    when its fringes at 400 nm can span fewer than 1.5 bands, and keeps ``"point"`` otherwise.
    With 16 bands the switch is at 1.51 µm (water), between the Nyquist thickness (1.13 µm),
    from which band means beat point samples thickness by thickness, and the thickness from
    which point samples are grossly wrong (1 µm running median of ΔE00 above 5; water at
    normal incidence: ``benchmarks/stability.py``, ``data/derived/stability_aliasing.csv``).
    Not lower, because on whole scenes of thinner films point sampling is the more accurate and
    the faster: band means carry their own error (the colour matching functions vary within a
    band) on the thin parts that make up most of a bubble.  On a scene of 1.6-3 µm films
    (``data/scenes/thick_films.toml``) the switch is right against 16 point samples, though 32
    point samples can do better than both (``benchmarks/time_vs_error.py``,
    ``data/derived/time_vs_error.csv``).
    """
    if spectral_method not in SPECTRAL_METHODS:
        raise ValueError(f"spectral_method must be one of {SPECTRAL_METHODS} (got {spectral_method!r})")
    if spectral_method != "auto":
        return spectral_method
    for b in scene.bubbles:
        n400 = float(water_refractive_index(400.0)) if isinstance(b.n_film, str) else complex(b.n_film).real
        limit = float(point_sampling_limit_nm(int(spectral_samples), 400.0, 0.0, n400)) / AUTO_FRINGE_BANDS
        if film_thickness_bound_nm(b.film) > limit:
            return "band"
    return "point"


def film_index(b, wavelengths):
    """A bubble's film index n + ik at *wavelengths* (nm): water (Daimon & Masumura 2007) or a
    constant (a real or complex number)."""
    if isinstance(b.n_film, str):
        if b.n_film != "water":
            raise ValueError(f"bubble {b.name!r}: n_film must be a number or 'water' (got {b.n_film!r})")
        return water_refractive_index(np.asarray(wavelengths, float)) + 0j
    n = complex(b.n_film)
    if not (math.isfinite(n.real) and math.isfinite(n.imag) and n.real > 0 and n.imag >= 0):
        raise ValueError(f"bubble {b.name!r}: n_film must be finite with n > 0 and k >= 0 (got {b.n_film!r})")
    return np.full(np.shape(wavelengths), n, dtype=complex)


def film_model_code(b) -> int:
    """The :data:`tracer.kernels.records.FILM_MODELS` code of bubble *b*'s ``film_model``; a
    :class:`ValueError` naming the bubble for any other value."""
    model = b.film_model
    if not isinstance(model, str) or model not in lay.FILM_MODELS:
        choices = ", ".join(map(repr, lay.FILM_MODELS))
        raise ValueError(f"bubble {b.name!r}: film_model must be one of {choices} (got {model!r})")
    return lay.FILM_MODELS[model]


def _film_record(rec, fp, shininess, lossless, maps, map_size, model=lay.FILM_MODEL_AIRY):
    """Fill a FILM record from a FilmProfile; returns the new size of the flat map table."""
    if fp.kind not in _PROFILES:
        raise ValueError(f"unknown film kind {fp.kind!r}")
    up = unit_vector(fp.up, "film up")
    rec["profile"] = _PROFILES[fp.kind]
    rec["thickness_nm"] = fp.thickness_nm
    rec["top_nm"], rec["bottom_nm"], rec["exponent"] = fp.top_nm, fp.bottom_nm, fp.exponent
    rec["swirl"], rec["swirl_scale"] = fp.swirl, fp.swirl_scale
    rec["up"] = up
    rec["ref"] = _perpendicular(up)
    if fp.kind == "map":
        table = np.asarray(fp.table, float)
        rec["map_offset"], rec["map_rows"], rec["map_cols"] = map_size, table.shape[0], table.shape[1]
        maps.append(table.ravel())
        map_size += table.size
    waves = np.random.default_rng(fp.seed).normal(size=(lay.N_SWIRL_WAVES, 3))
    waves /= np.linalg.norm(waves, axis=1, keepdims=True)
    phases = np.random.default_rng(fp.seed + 1).uniform(0, 2 * math.pi, lay.N_SWIRL_WAVES)
    rec["waves"] = np.column_stack([waves, phases])
    rec["shininess"] = shininess
    rec["uniform"] = fp.kind == "uniform" and fp.swirl == 0.0
    rec["lossless"] = lossless
    rec["model"] = model
    return map_size


def _environment_xaxis(up):
    """The image environment's longitude axis X: world +x made perpendicular to *up* (world +z
    when up is within 0.1 degrees of the x axis).  With Z = X x up, the frame (X, up, Z) is
    world (x, y, z) for the default up = +y: Mitsuba 3's ``envmap`` frame (see
    :func:`tracer.kernels.environment.environment_rgb`)."""
    ref = np.array([1.0, 0.0, 0.0]) if abs(up[0]) < math.cos(math.radians(0.1)) else np.array([0.0, 0.0, 1.0])
    x = ref - np.dot(ref, up) * up
    return x / np.linalg.norm(x)


def _environment_record(env):
    if env.kind not in _ENV_KINDS:
        raise ValueError(f"unknown environment kind {env.kind!r}")
    rec = np.zeros(1, lay.ENVIRONMENT)
    up = unit_vector(env.up, "environment up")
    xaxis = _environment_xaxis(up)
    rec["kind"] = _ENV_KINDS[env.kind]
    rec["color"] = env.color
    rec["intensity"] = env.intensity
    rec["up"] = up
    rec["sun"] = unit_vector(env.sun_direction, "environment sun_direction")
    rec["xaxis"] = xaxis
    rec["zaxis"] = np.cross(xaxis, up)
    image = np.zeros((1, 1, 3)) if env.image is None else np.ascontiguousarray(env.image, dtype=float)
    return rec, image


_FALLOFFS = {"none": lay.FALLOFF_NONE, "inverse_square": lay.FALLOFF_INVERSE_SQUARE}


def _light_records(lights, basis):
    """(LIGHT records, strengths (L, C)) of :class:`~tracer.scene.PointLight` s; a light the
    renderer cannot use is a ValueError naming it."""
    nc = basis.shape[0]
    recs = np.zeros(len(lights), lay.LIGHT)
    radiance = np.zeros((len(lights), nc))
    for i, lt in enumerate(lights):
        what = f"light {i + 1}"  # 1-based, as the editor and the movie commands number lights
        if lt.falloff not in _FALLOFFS:
            raise ValueError(f"{what}: falloff must be one of {', '.join(map(repr, _FALLOFFS))} (got {lt.falloff!r})")
        position = np.asarray(lt.position, float)
        if position.shape != (3,) or not np.all(np.isfinite(position)):
            raise ValueError(f"{what}: position must be three finite numbers (got {lt.position!r})")
        radius = lt.radius
        if isinstance(radius, bool) or not (isinstance(radius, (int, float, np.integer, np.floating))
                                            and math.isfinite(radius) and radius >= 0):
            raise ValueError(f"{what}: radius must be a finite number >= 0 (got {radius!r})")
        samples = lt.samples
        if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or \
                not 1 <= samples <= MAX_LIGHT_SAMPLES:
            raise ValueError(f"{what}: samples must be an integer in 1..{MAX_LIGHT_SAMPLES} (got {samples!r})")
        if not (math.isfinite(lt.intensity) and lt.intensity >= 0):
            raise ValueError(f"{what}: intensity must be a finite number >= 0 (got {lt.intensity!r})")
        recs[i]["position"] = position
        recs[i]["radius"] = float(radius)
        recs[i]["falloff"] = _FALLOFFS[lt.falloff]
        recs[i]["samples"] = int(samples)
        # inverse-square: S = I / (pi r^2), the 1/pi here and the 1/r^2 per shaded point
        scale = lt.intensity / math.pi if lt.falloff == "inverse_square" else lt.intensity
        radiance[i] = scale * (basis @ np.asarray(lt.color, float))
    return recs, radiance


def camera_record(camera):
    rec = np.zeros(1, lay.CAMERA)
    origin, fwd, right, cup = camera.basis()
    rec["origin"], rec["forward"], rec["right"], rec["up"] = origin, fwd, right, cup
    rec["tan_half_fov"] = math.tan(math.radians(camera.fov_deg) / 2)
    return rec


def check_magnitudes(scene: Scene):
    """ValueError naming the first number of *scene* that is not finite or is beyond
    :data:`tracer.scene.limits.MAX_MAGNITUDE` (the loaders refuse such numbers with FILE:LINE; this
    is the same check for scenes built in Python)."""

    def check(what, value):
        a = np.asarray(value, dtype=float)
        if a.size and not (np.all(np.isfinite(a)) and np.abs(a).max() <= MAX_MAGNITUDE):
            shown = a.ravel()[np.flatnonzero(~(np.abs(a.ravel()) <= MAX_MAGNITUDE))[0]]
            raise ValueError(f"{what}: {shown:g} is not a finite number within -{MAX_MAGNITUDE:g} to "
                             f"{MAX_MAGNITUDE:g} (tracer.scene.limits)")

    cam = scene.camera
    if not 0.0 < float(cam.fov_deg) < 180.0:
        raise ValueError(f"camera fov_deg must be > 0 and < 180, got {cam.fov_deg!r}")
    check("camera position", cam.position)
    check("camera look_at", cam.look_at)
    check("camera up", cam.up)
    check("ambient", scene.ambient)
    for s in scene.spheres:
        check(f"sphere {s.name!r} center", s.center)
        check(f"sphere {s.name!r} radius", s.radius)
    for b in scene.bubbles:
        check(f"bubble {b.name!r} center", b.center)
        check(f"bubble {b.name!r} radius", b.radius)
        f = b.film
        check(f"bubble {b.name!r} film thickness", [f.thickness_nm, f.top_nm, f.bottom_nm, f.exponent, f.swirl,
                                                     f.swirl_scale])
        if f.table is not None:
            check(f"bubble {b.name!r} film map", f.table)
    for m in scene.meshes:
        check(f"mesh {m.name!r} vertices", m.vertices)
    for i, lt in enumerate(scene.lights, start=1):
        check(f"light {i} position", lt.position)
        check(f"light {i} radius", lt.radius)
        check(f"light {i} intensity", [lt.intensity, *lt.color])
    env = scene.environment
    check("environment colour", [*env.color, env.intensity])
    if env.image is not None:
        check("environment image", env.image)


def pack_scene(scene: Scene, spectral_samples=16, force_spectral=None, spectral_method="auto") -> PackedScene:
    """Pack *scene*; spectral transport if it has bubbles (or *force_spectral* is True).

    *spectral_method*: ``"point"`` evaluates each bubble film at the band centres; ``"band"``
    uses each band's film averaged in closed form over the band
    (:func:`bubbleoptics.kernels.film_band_average_nb`), which does not alias on thick films;
    ``"auto"`` chooses between them (:func:`resolve_spectral_method`).
    ``PackedScene.band_mode`` records the choice.

    A bubble with ``film_model="two-beam"`` is evaluated at the band centres whatever the
    method (the two-beam formula has no band average here), so ``"band"`` is refused for a
    scene with one; it is lossless whatever its index (the formula uses only Re n, T = 1 - R).
    """
    from ..scene.simulated import resolve_simulated_films

    scene = resolve_simulated_films(scene)  # simulated films as the maps they show (popped bubbles gone)
    check_magnitudes(scene)
    models = [film_model_code(b) for b in scene.bubbles]
    if spectral_method == "band" and lay.FILM_MODEL_TWO_BEAM in models:
        raise ValueError("spectral_method 'band' cannot render a bubble with film_model 'two-beam' "
                         "(the two-beam formula has no band average): use 'point' or 'auto'")
    spectral_method = resolve_spectral_method(scene, spectral_samples, spectral_method)
    spectral = bool(scene.bubbles) if force_spectral is None else bool(force_spectral)
    wl, to_rgb, basis = channel_setup(spectral, spectral_samples)
    nc = basis.shape[0]
    edges = np.linspace(360.0, 780.0, nc + 1) if spectral else np.zeros(nc + 1)

    # Phong materials, shared by identity
    materials = []
    mat_index = {}

    def material_id(m):
        if id(m) not in mat_index:
            mat_index[id(m)] = len(materials)
            materials.append(m)
        return mat_index[id(m)]

    # spheres: the Phong spheres, then the bubbles (a sphere whose surface is a film)
    nb = len(scene.bubbles)
    spheres = np.zeros(len(scene.spheres) + nb, lay.SPHERE)
    for i, s in enumerate(scene.spheres):
        spheres[i] = (s.center, s.radius, lay.SURFACE_PHONG, material_id(s.material))
    for b, bub in enumerate(scene.bubbles):
        spheres[len(scene.spheres) + b] = (bub.center, bub.radius, lay.SURFACE_FILM, b)

    # triangles of all meshes, one BVH
    tri_list, parts = [], []
    for m in scene.meshes:
        tri, nrm, corners = _mesh_triangles(m)
        tri_list.append(tri)
        parts.append((nrm, corners, material_id(m.material)))
    tris = _concatenate(tri_list, np.zeros((0, 3, 3)))
    del tri_list
    max_tri_coordinate = max(float(tris.max()), -float(tris.min())) if len(tris) else 0.0
    bvh = build_bvh(tris, overwrite=True)
    del tris
    triangles = _triangle_records(parts, bvh.order)
    del parts

    phong = np.zeros(len(materials), lay.PHONG)
    for i, m in enumerate(materials):
        phong[i] = (m.ambient, m.diffuse, m.specular, m.transmission, m.shininess, m.ior)
    phong_color = np.array([basis @ np.asarray(m.color, float) for m in materials]).reshape(-1, nc)

    # films
    films = np.zeros(nb, lay.FILM)
    film_n = np.empty((nb, nc), complex)
    film_n_edges = np.empty((nb, nc + 1), complex)
    maps = []
    map_size = 0
    for i, b in enumerate(scene.bubbles):
        film_n[i] = film_index(b, wl)
        film_n_edges[i] = film_index(b, edges) if spectral else film_n[i, 0]
        two_beam = models[i] == lay.FILM_MODEL_TWO_BEAM
        lossless = two_beam or (not np.any(film_n[i].imag) and not np.any(film_n_edges[i].imag))
        map_size = _film_record(films[i:i + 1], b.film, b.shininess, lossless, maps, map_size, models[i])
    film_maps = np.concatenate(maps) if maps else np.zeros(1)

    lights, light_radiance = _light_records(scene.lights, basis)

    environment, env_image = _environment_record(scene.environment)

    coords = [np.abs(np.asarray(scene.camera.position, float)).max()]
    for s in list(scene.spheres) + list(scene.bubbles):
        coords.append(np.abs(np.asarray(s.center, float)).max() + s.radius)
    if len(triangles):
        coords.append(max_tri_coordinate)
    eps = origin_epsilon(scene.scale(), max(coords))

    c = np.ascontiguousarray
    return PackedScene(
        spheres=spheres,
        tris=c(bvh.tris),
        triangles=c(triangles),
        bvh_bounds=bvh.bounds,
        bvh_child=bvh.child,
        bvh_first=bvh.first,
        bvh_count=bvh.count,
        eps=float(eps),
        phong=phong,
        phong_color=c(phong_color),
        films=films,
        film_n=c(film_n.real),
        film_k=c(film_n.imag),
        film_n_edges=c(film_n_edges.real),
        film_k_edges=c(film_n_edges.imag),
        film_maps=film_maps,
        lights=lights,
        light_radiance=c(light_radiance),
        ambient=c(basis @ np.asarray(scene.ambient, float)),
        environment=environment,
        env_image=env_image,
        camera=camera_record(scene.camera),
        wavelengths=c(np.asarray(wl, float)),
        band_edges=c(edges),
        band_mode=int(spectral and spectral_method == "band"),
        to_rgb=c(to_rgb),
        rgb_basis=c(basis),
        rgb_basis_t=c(basis.T),
        rgb_round_trip=c(to_rgb @ basis),
        spectral=spectral,
    )
