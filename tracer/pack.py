"""Turn a :class:`tracer.scene.Scene` into the flat arrays the numba integrator reads.

This is also where the renderer decides what a scene needs: spectral transport only when
something depends on wavelength (a bubble), otherwise three linear-sRGB channels.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from bubbleoptics import band_spectral_weights, point_sampling_limit_nm, rgb_reflectance_basis, water_refractive_index
from bubbleoptics.colorimetry import XYZ_TO_LINEAR_SRGB

from .bvh import build_bvh
from .environment import ENV_CONSTANT, ENV_IMAGE, ENV_SKY
from .films import FILM_DRAINING, FILM_MAP, FILM_UNIFORM, N_FILM_PARAMS
from .geometry import origin_epsilon
from .scene import Scene

__all__ = ["Packed", "pack_scene", "channel_setup", "film_thickness_bound_nm", "resolve_spectral_method"]

_ENV_KINDS = {"constant": ENV_CONSTANT, "sky": ENV_SKY, "image": ENV_IMAGE}
_FILM_KINDS = {"uniform": FILM_UNIFORM, "draining": FILM_DRAINING, "map": FILM_MAP}


@dataclass
class Packed:
    """Arrays for the integrator (see :mod:`tracer.integrator` for their layout)."""

    spectral: bool
    wavelengths: np.ndarray  # (C,) band centres in nm (empty in RGB mode)
    to_rgb: np.ndarray  # (3, C) channels -> linear sRGB
    rgb_basis: np.ndarray  # (C, 3) linear sRGB -> channels (reflectances and radiances)
    spheres: np.ndarray  # (S, 5): centre, radius, material index
    bubbles: np.ndarray  # (B, 5): centre, radius, shininess
    bubble_n: np.ndarray  # (B, C) film index per channel
    bubble_n_edges: np.ndarray  # (B, C + 1) film index at the band edges (band-averaged films)
    band_edges: np.ndarray  # (C + 1,) band edges in nm
    band_mode: int  # 1: bubbles use the band-averaged film (bubbleoptics.kernels.film_band_average)
    bubble_film: np.ndarray  # (B, N_FILM_PARAMS)
    film_maps: np.ndarray  # flat thickness tables
    tris: np.ndarray  # (T, 3, 3) in BVH order
    tri_info: np.ndarray  # (T, 4): outward unit normal, material index
    bvh_bounds: np.ndarray
    bvh_child: np.ndarray
    bvh_first: np.ndarray
    bvh_count: np.ndarray
    mat_color: np.ndarray  # (M, C) reflectance per channel
    mat_coef: np.ndarray  # (M, 6): ambient, diffuse, specular, transmission, shininess, ior
    lights: np.ndarray  # (L, 3) positions
    light_rad: np.ndarray  # (L, C) radiance factor per channel
    env_kind: int
    env_params: np.ndarray  # (16,)
    env_image: np.ndarray  # (H, W, 3)
    ambient: np.ndarray  # (C,)
    camera: np.ndarray  # (13,)
    eps: float


#: Normalise the RGB -> bands basis (so that a colour entering the scene leaves as the same
#: colour) only where that is well conditioned: cond(to_rgb @ basis) is 1.06 at 16 bands, 1.4
#: at 8, 2.6 at 4 and 26 at 3 bands, where the inverse would amplify noise.
BASIS_NORMALISE_MAX_COND = 3.0


def _srgb_dominant_wavelengths():
    """Dominant wavelengths (nm) of the sRGB red, green and blue primaries (colour-science)."""
    import colour

    cs = colour.RGB_COLOURSPACES["sRGB"]
    return np.array([float(colour.dominant_wavelength(p, cs.whitepoint)[0]) for p in cs.primaries])


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
    that the run-time-against-error study quantifies.
    """
    if not spectral:
        return _srgb_dominant_wavelengths(), np.eye(3), np.eye(3)
    wl, w = band_spectral_weights(n_bands)
    to_rgb = XYZ_TO_LINEAR_SRGB @ w
    basis = rgb_reflectance_basis(n_bands)
    round_trip = to_rgb @ basis
    if np.linalg.cond(round_trip) <= BASIS_NORMALISE_MAX_COND:
        basis = basis @ np.linalg.inv(round_trip)
    return wl, to_rgb, basis


def _unit(v):
    v = np.asarray(v, float)
    n = np.linalg.norm(v)
    if not n > 0:
        raise ValueError(f"zero-length direction vector {v.tolist()}")
    return v / n


def _perpendicular(up):
    ref = np.cross(up, [1.0, 0.0, 0.0])
    if np.linalg.norm(ref) < 1e-6:
        ref = np.cross(up, [0.0, 0.0, 1.0])
    return ref / np.linalg.norm(ref)


def _convex_outward(vertices, faces, normals):
    """Orient face normals away from the centroid when the mesh is convex (the seed's rule);
    otherwise keep the file's winding."""
    centroid = vertices.mean(axis=0)
    centres = vertices[faces].mean(axis=1)
    side = np.einsum("ij,ij->i", normals, centres - centroid)
    # convex: every vertex lies on the inner side of every face plane
    offsets = np.einsum("ij,ij->i", normals, vertices[faces[:, 0]])
    signed = vertices @ normals.T - offsets[None, :]
    flip = np.where(side < 0, -1.0, 1.0)
    convex = np.all(signed * flip[None, :] <= 1e-9 * (np.abs(vertices).max() + 1.0))
    return normals * flip[:, None] if convex else normals


SPECTRAL_METHODS = ("auto", "point", "band")


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
    With 16 bands the switch is at 1.51 µm, inside the window the measurements leave
    (water, normal incidence): from the Nyquist thickness, 1.13 µm, band means beat point
    samples thickness by thickness, and from 1.72 µm point samples are grossly wrong (1 µm
    running median of ΔE00 above 5, ``benchmarks/stability.py``); but on whole scenes with films
    up to 1.43 µm point sampling measured more accurate and faster, because band means carry
    their own error (the colour matching functions vary within a band) on the thin parts that
    make up most of a bubble (``benchmarks/time_vs_error.py``: interior mean ΔE00 0.042 against
    0.072 on six bubbles).
    """
    if spectral_method not in SPECTRAL_METHODS:
        raise ValueError(f"spectral_method must be one of {SPECTRAL_METHODS} (got {spectral_method!r})")
    if spectral_method != "auto":
        return spectral_method
    for b in scene.bubbles:
        n400 = float(water_refractive_index(400.0)) if isinstance(b.n_film, str) else float(b.n_film)
        limit = float(point_sampling_limit_nm(int(spectral_samples), 400.0, 0.0, n400)) / AUTO_FRINGE_BANDS
        if film_thickness_bound_nm(b.film) > limit:
            return "band"
    return "point"


def pack_scene(scene: Scene, spectral_samples=16, force_spectral=None, spectral_method="auto"):
    """Pack *scene*; spectral transport if it has bubbles (or *force_spectral* is True).

    *spectral_method*: ``"point"`` evaluates each bubble film at the band centres; ``"band"``
    uses each band's film averaged in closed form over the band
    (:func:`bubbleoptics.kernels.film_band_average`), which does not alias on thick films;
    ``"auto"`` chooses between them (:func:`resolve_spectral_method`).  ``Packed.band_mode``
    records the choice.
    """
    spectral_method = resolve_spectral_method(scene, spectral_samples, spectral_method)
    spectral = bool(scene.bubbles) if force_spectral is None else bool(force_spectral)
    wl, to_rgb, basis = channel_setup(spectral, spectral_samples)
    nc = basis.shape[0]
    edges = np.linspace(360.0, 780.0, nc + 1) if spectral else np.zeros(nc + 1)

    materials = []
    mat_index = {}

    def material_id(m):
        key = id(m)
        if key not in mat_index:
            mat_index[key] = len(materials)
            materials.append(m)
        return mat_index[key]

    spheres = np.array(
        [[*s.center, s.radius, material_id(s.material)] for s in scene.spheres], dtype=float
    ).reshape(-1, 5)

    # triangles of all meshes, one BVH
    tri_list, info_list = [], []
    for m in scene.meshes:
        v = np.asarray(m.vertices, float)
        f = np.asarray(m.faces, np.int64)
        tri = v[f]
        nrm = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        length = np.linalg.norm(nrm, axis=1)
        keep = length > 0
        tri, nrm = tri[keep], nrm[keep] / length[keep, None]
        nrm = _convex_outward(v, f[keep], nrm)
        mid = material_id(m.material)
        tri_list.append(tri)
        info_list.append(np.column_stack([nrm, np.full(len(tri), mid, float)]))
    tris = np.concatenate(tri_list) if tri_list else np.zeros((0, 3, 3))
    info = np.concatenate(info_list) if info_list else np.zeros((0, 4))
    bvh = build_bvh(tris)
    info = info[bvh.order] if len(info) else info

    mat_color = np.array([basis @ np.asarray(m.color, float) for m in materials]).reshape(-1, nc)
    mat_coef = np.array(
        [[m.ambient, m.diffuse, m.specular, m.transmission, m.shininess, m.ior] for m in materials], float
    ).reshape(-1, 6)

    # bubbles
    nb = len(scene.bubbles)
    bubbles = np.array([[*b.center, b.radius, b.shininess] for b in scene.bubbles], float).reshape(-1, 5)
    bubble_n = np.empty((nb, nc))
    bubble_n_edges = np.empty((nb, nc + 1))
    bubble_film = np.zeros((nb, N_FILM_PARAMS))
    maps = []
    map_size = 0
    rng_waves = np.random.default_rng
    for i, b in enumerate(scene.bubbles):
        if isinstance(b.n_film, str):
            if b.n_film != "water":
                raise ValueError(f"bubble {b.name!r}: n_film must be a number or 'water' (got {b.n_film!r})")
            bubble_n[i] = water_refractive_index(wl)
            bubble_n_edges[i] = water_refractive_index(edges) if spectral else 1.333
        else:
            bubble_n[i] = float(b.n_film)
            bubble_n_edges[i] = float(b.n_film)
        fp = b.film
        if fp.kind not in _FILM_KINDS:
            raise ValueError(f"bubble {b.name!r}: unknown film kind {fp.kind!r}")
        up = _unit(fp.up)
        ref = _perpendicular(up)
        row = bubble_film[i]
        row[0] = _FILM_KINDS[fp.kind]
        row[1] = fp.thickness_nm
        row[2], row[3], row[4] = fp.top_nm, fp.bottom_nm, fp.exponent
        row[5], row[6] = fp.swirl, fp.swirl_scale
        row[7:10] = up
        row[10:13] = ref
        if fp.kind == "map":
            table = np.asarray(fp.table, float)
            row[13], row[14], row[15] = map_size, table.shape[0], table.shape[1]
            maps.append(table.ravel())
            map_size += table.size
        waves = rng_waves(fp.seed).normal(size=(4, 3))
        waves /= np.linalg.norm(waves, axis=1, keepdims=True)
        phases = rng_waves(fp.seed + 1).uniform(0, 2 * math.pi, 4)
        row[16:32] = np.column_stack([waves, phases]).ravel()
    film_maps = np.concatenate(maps) if maps else np.zeros(1)

    lights = np.array([lt.position for lt in scene.lights], float).reshape(-1, 3)
    light_rad = np.array([lt.intensity * (basis @ np.asarray(lt.color, float)) for lt in scene.lights]).reshape(-1, nc)

    env = scene.environment
    if env.kind not in _ENV_KINDS:
        raise ValueError(f"unknown environment kind {env.kind!r}")
    up = _unit(env.up)
    xaxis = _perpendicular(up)
    zaxis = np.cross(xaxis, up)
    env_params = np.zeros(16)
    env_params[0:3] = env.color
    env_params[3:6] = up
    env_params[6:9] = _unit(env.sun_direction)
    env_params[9] = env.intensity
    env_params[10:13] = xaxis
    env_params[13:16] = zaxis
    env_image = np.zeros((1, 1, 3)) if env.image is None else np.ascontiguousarray(env.image, dtype=float)

    origin, fwd, right, cup = scene.camera.basis()
    camera = np.concatenate([origin, fwd, right, cup, [math.tan(math.radians(scene.camera.fov_deg) / 2)]])

    coords = [np.abs(np.asarray(scene.camera.position, float)).max()]
    for s in list(scene.spheres) + list(scene.bubbles):
        coords.append(np.abs(np.asarray(s.center, float)).max() + s.radius)
    if len(tris):
        coords.append(np.abs(tris).max())
    eps = origin_epsilon(scene.scale(), max(coords))

    return Packed(
        spectral=spectral,
        wavelengths=wl,
        to_rgb=np.ascontiguousarray(to_rgb),
        rgb_basis=np.ascontiguousarray(basis),
        spheres=spheres,
        bubbles=bubbles,
        bubble_n=bubble_n,
        bubble_n_edges=bubble_n_edges,
        band_edges=edges,
        band_mode=int(spectral and spectral_method == "band"),
        bubble_film=bubble_film,
        film_maps=film_maps,
        tris=np.ascontiguousarray(bvh.tris),
        tri_info=np.ascontiguousarray(info),
        bvh_bounds=bvh.bounds,
        bvh_child=bvh.child,
        bvh_first=bvh.first,
        bvh_count=bvh.count,
        mat_color=np.ascontiguousarray(mat_color),
        mat_coef=mat_coef,
        lights=lights,
        light_rad=np.ascontiguousarray(light_rad),
        env_kind=_ENV_KINDS[env.kind],
        env_params=env_params,
        env_image=env_image,
        ambient=basis @ np.asarray(scene.ambient, float),
        camera=camera,
        eps=float(eps),
    )
