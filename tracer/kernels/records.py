"""The packed scene: the typed structure the numba integrator reads, and its record layouts.

:func:`tracer.prepare.pack.pack_scene` turns a :class:`tracer.scene.Scene` into a :class:`PackedScene`,
a ``NamedTuple`` of arrays that numba passes as one typed value.  Rows of parameters are
NumPy structured arrays (numba records), so kernels read ``spheres[i].radius`` or
``films[b].top_nm`` instead of ``row[3]``.  Every array has a fixed dtype, number of
dimensions and C layout whatever the scene (empty tables have length 0), so one compiled
kernel serves every scene and numba's on-disk cache is hit on every run.

Geometry and surfaces are separate: a sphere (``SPHERE``) or a triangle (``TRIANGLE``) names
its surface by kind and index, ``SURFACE_FILM`` (a soap film, :mod:`tracer.kernels.surfaces.soap_film`,
whose parameters are ``films[index]``) or ``SURFACE_PHONG`` (the coursework's Phong/Whitted
material, :mod:`tracer.kernels.surfaces.phong`, ``phong[index]``).  A bubble is a sphere whose surface
is a film.

Per-channel quantities (colours, radiances, film indices) are separate ``(N, C)`` float arrays
next to their records: *C*, the number of transport channels (spectral bands, or 3 for RGB),
is a run-time size, not part of any type.

Units: scene lengths in scene units, film thickness in nm, angles through their cosines,
radiance as a factor on the channel basis (:func:`tracer.prepare.pack.channel_setup`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = [
    "SURFACE_FILM",
    "SURFACE_PHONG",
    "PROFILE_UNIFORM",
    "PROFILE_DRAINING",
    "PROFILE_MAP",
    "FALLOFF_NONE",
    "FALLOFF_INVERSE_SQUARE",
    "ENV_CONSTANT",
    "ENV_SKY",
    "ENV_IMAGE",
    "N_SWIRL_WAVES",
    "FILM_MODEL_AIRY",
    "FILM_MODEL_TWO_BEAM",
    "FILM_MODELS",
    "SPHERE",
    "TRIANGLE",
    "PHONG",
    "FILM",
    "LIGHT",
    "ENVIRONMENT",
    "CAMERA",
    "PackedScene",
    "RAY_COUNT_KINDS",
]

# Surface kinds (one module each in tracer.kernels.surfaces).
SURFACE_FILM = 0
SURFACE_PHONG = 1

# Film thickness profiles (tracer.kernels.thickness).
PROFILE_UNIFORM = 0
PROFILE_DRAINING = 1
PROFILE_MAP = 2

# Light falloffs (tracer.scene.PointLight).
FALLOFF_NONE = 0
FALLOFF_INVERSE_SQUARE = 1

# Environments (tracer.kernels.environment).
ENV_CONSTANT = 0
ENV_SKY = 1
ENV_IMAGE = 2

# How a film's R and T are computed (tracer.kernels.surfaces.soap_film.film_optics): the exact Airy
# sum, or the coursework's two-beam formula (bubbleoptics.kernels.two_beam_r_nb, T = 1 - R).
FILM_MODEL_AIRY = 0
FILM_MODEL_TWO_BEAM = 1
#: ``Bubble.film_model`` values and their codes.
FILM_MODELS = {"airy": FILM_MODEL_AIRY, "two-beam": FILM_MODEL_TWO_BEAM}

#: Plane waves summed by a film's swirl (tracer.kernels.thickness.film_thickness).
N_SWIRL_WAVES = 4

_V3 = (np.float64, (3,))

#: A sphere: centre, radius, and the surface it carries.
SPHERE = np.dtype([("center", *_V3), ("radius", np.float64), ("surface", np.int64), ("index", np.int64)],
                  align=True)

#: A triangle's surface (its vertices are ``PackedScene.tris``, in BVH order): the outward unit
#: normal (the geometric one: it decides which side a ray is on and where spawned rays start),
#: the surface it carries, and for smooth shading (``smooth``) the unit normals at its three
#: vertices, in the order of its vertices in ``tris``, each on the side of ``normal``
#: (:func:`tracer.prepare.meshes.corner_normals`), interpolated by :func:`tracer.kernels.geometry.shading_normal`.
TRIANGLE = np.dtype([("normal", *_V3), ("surface", np.int64), ("index", np.int64),
                     ("vertex_normals", np.float64, (3, 3)), ("smooth", np.bool_)], align=True)

#: The coursework's material (eq. 1.4 of its report); its colour is ``PackedScene.phong_color``.
PHONG = np.dtype([("ambient", np.float64), ("diffuse", np.float64), ("specular", np.float64),
                  ("transmission", np.float64), ("shininess", np.float64), ("ior", np.float64)], align=True)

#: A soap film on a sphere: its thickness profile (tracer.kernels.thickness), highlight exponent, film
#: model (Airy sum or two-beam formula) and whether it is lossless (every channel's index
#: real); its index per channel is ``PackedScene.film_n + 1j * film_k`` (band centres) and
#: ``film_n_edges``, ``film_k_edges`` (band edges).
FILM = np.dtype([
    ("profile", np.int64),
    ("thickness_nm", np.float64),  # uniform
    ("top_nm", np.float64),  # draining: at the top ...
    ("bottom_nm", np.float64),  # ... and at the bottom
    ("exponent", np.float64),  # draining: d = top + (bottom - top) z^exponent
    ("swirl", np.float64),  # relative amplitude of the swirl (0: none)
    ("swirl_scale", np.float64),  # spatial frequency of the swirl waves
    ("up", *_V3),  # the film's "up": polar angle measured from it
    ("ref", *_V3),  # azimuth 0 of a map, perpendicular to up
    ("map_offset", np.int64),  # map: first entry of its table in PackedScene.film_maps
    ("map_rows", np.int64),  # map: N_theta
    ("map_cols", np.int64),  # map: N_phi
    ("waves", np.float64, (N_SWIRL_WAVES, 4)),  # swirl: unit wave vector and phase per wave
    ("shininess", np.float64),  # exponent of point-light highlights
    ("uniform", np.bool_),  # thickness the same everywhere (profile uniform, no swirl)
    ("lossless", np.bool_),  # every channel's index real: R + T = 1
    ("model", np.int64),  # FILM_MODEL_AIRY or FILM_MODEL_TWO_BEAM
], align=True)

#: A light (:class:`tracer.scene.PointLight`): its centre, radius (0: a point), falloff
#: (:data:`FALLOFF_NONE` or :data:`FALLOFF_INVERSE_SQUARE`) and number of samples (spheres);
#: its strength per channel is ``PackedScene.light_radiance`` (``intensity`` times the colour,
#: divided by π for inverse-square falloff, whose strength is then divided by r²).
LIGHT = np.dtype([("position", *_V3), ("radius", np.float64), ("falloff", np.int64), ("samples", np.int64)],
                 align=True)

#: What rays leaving the scene see (one record): constant colour, procedural sky or an image.
ENVIRONMENT = np.dtype([
    ("kind", np.int64),
    ("color", *_V3),  # constant: linear sRGB
    ("intensity", np.float64),
    ("up", *_V3),
    ("sun", *_V3),  # sky: unit direction to the sun
    ("xaxis", *_V3),  # image: the frame around up that fixes longitude
    ("zaxis", *_V3),
], align=True)

#: The pinhole camera (one record): origin and orthonormal forward, right, up; tan(fov_y / 2).
CAMERA = np.dtype([("origin", *_V3), ("forward", *_V3), ("right", *_V3), ("up", *_V3),
                   ("tan_half_fov", np.float64)], align=True)

#: The order of ``render``'s ray counters.
RAY_COUNT_KINDS = ("camera", "reflected", "transmitted", "shadow")


class PackedScene(NamedTuple):
    """Everything the integrator reads, as one typed value (see the module docstring)."""

    # -- geometry
    spheres: np.ndarray  # (S,) SPHERE
    tris: np.ndarray  # (T, 3, 3) float64 vertices, BVH order
    triangles: np.ndarray  # (T,) TRIANGLE
    bvh_bounds: np.ndarray  # (N, 2, 3) float64 (tracer.prepare.bvh.BVH)
    bvh_child: np.ndarray  # (N, 2) int64
    bvh_first: np.ndarray  # (N,) int64
    bvh_count: np.ndarray  # (N,) int64
    eps: float  # ray-origin offset (tracer.kernels.geometry.origin_epsilon)
    # -- surfaces
    phong: np.ndarray  # (M,) PHONG
    phong_color: np.ndarray  # (M, C) reflectance per channel
    films: np.ndarray  # (B,) FILM
    film_n: np.ndarray  # (B, C) film index n at the band centres (or RGB wavelengths) ...
    film_k: np.ndarray  # (B, C) ... and its extinction coefficient k (the index is n + ik)
    film_n_edges: np.ndarray  # (B, C + 1) n and k at the band edges (band-averaged films)
    film_k_edges: np.ndarray
    film_maps: np.ndarray  # (K,) float64: every map film's (N_theta, N_phi) table, flattened
    # -- lights, environment, camera
    lights: np.ndarray  # (L,) LIGHT
    light_radiance: np.ndarray  # (L, C) strength per channel (see LIGHT)
    ambient: np.ndarray  # (C,) the coursework's ambient light
    environment: np.ndarray  # (1,) ENVIRONMENT
    env_image: np.ndarray  # (H, W, 3) float64 linear sRGB (1x1 when unused)
    camera: np.ndarray  # (1,) CAMERA
    # -- channels
    wavelengths: np.ndarray  # (C,) nm: band centres (spectral) or the RGB primaries' dominant wavelengths
    band_edges: np.ndarray  # (C + 1,) nm (spectral; zeros in RGB)
    band_mode: int  # 1: films averaged over each band (bubbleoptics.kernels.film_band_average_nb)
    to_rgb: np.ndarray  # (3, C): channels -> linear sRGB
    rgb_basis: np.ndarray  # (C, 3): linear sRGB -> channels
    rgb_basis_t: np.ndarray  # (3, C): rgb_basis transposed, contiguous (so the loops over channels vectorize)
    rgb_round_trip: np.ndarray  # (3, 3) = to_rgb @ rgb_basis (an environment seen directly)
    spectral: bool  # transport in spectral bands (True) or linear-sRGB channels (False)

    @property
    def n_channels(self) -> int:
        return self.rgb_basis.shape[0]
