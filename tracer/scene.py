"""The scene model: plain dataclasses that loaders build and the renderer packs into arrays.

Units: lengths in scene units (any unit, used consistently; the coursework's files use
screen-like units where a 960x960 image spans about 0-960), film thickness in nanometres, angles
in radians (the camera's field of view in degrees, as people say it), colours as linear RGB in
[0, 1] (the coursework's 0-255 integers are converted by the loader), light intensities as
non-negative multipliers of the light's spectrum (CIE D65 unless given).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = [
    "Material",
    "Sphere",
    "FilmProfile",
    "Bubble",
    "Mesh",
    "PointLight",
    "Camera",
    "Environment",
    "Scene",
    "COURSEWORK_NM_PER_UNIT",
]

#: A coursework-format bubble's film is (r_out - r_in) * COURSEWORK_NM_PER_UNIT nanometres thick
#: (see docs/scene-format.md: the coursework's screen-unit spheres are centimetres-sized, its
#: films are not).
COURSEWORK_NM_PER_UNIT = 1000.0


def unit_vector(v, what="direction"):
    """*v* scaled to unit length: first by its largest component, so that neither tiny
    (``[0, 1e-300, 0]``) nor huge components under- or overflow the length; ValueError naming
    *what* when it has no direction (zero, or not finite)."""
    v = np.asarray(v, float)
    m = np.abs(v).max() if v.size else 0.0
    if not (m > 0 and np.isfinite(m)):
        raise ValueError(f"{what} {v.tolist()} has no direction (zero or not finite)")
    v = v / m
    return v / np.linalg.norm(v)


@dataclass
class Material:
    """Whitted/Phong material (the coursework's five material lines, in physical clothing).

    Local terms (the coursework's eq. 1.4):
    ``color * (ambient * Ia + diffuse * sum_j I_j max(0, N.L_j)) + specular * sum_j I_j max(0, V.R_j)^shininess``.
    Secondary rays: a mirror ray weighted by ``specular * color + transmission * F``, a
    refracted ray weighted by ``transmission * (1 - F) * color``, where F is the unpolarized
    Fresnel reflectance for index ``ior`` (0 when ior == 1; total internal reflection sends
    everything to the mirror ray).
    """

    name: str = "default"
    color: tuple[float, float, float] = (0.8, 0.8, 0.8)
    ambient: float = 0.1
    diffuse: float = 0.9
    specular: float = 0.0
    transmission: float = 0.0
    shininess: float = 50.0
    ior: float = 1.0


@dataclass
class Sphere:
    """An opaque or transparent sphere with a material."""

    center: tuple[float, float, float]
    radius: float
    material: Material = field(default_factory=Material)
    name: str = "sphere"


@dataclass
class FilmProfile:
    """Film thickness over a bubble's surface, in nm.

    kind ``"uniform"``: ``thickness_nm`` everywhere.
    kind ``"draining"``: gravitational drainage, thinnest at the top: a film draining under
    gravity thins at the top and thickens at the bottom; we use the profile
    d(θ) = d_top + (d_bottom - d_top) * ((1 - cos θ)/2)^exponent, θ the polar angle from the
    top (``up`` direction), exponent default 1/2: the immobile-interface drainage law
    h(z, t) = 2 sqrt(eta z / (rho g t)) for height z below the top (see docs/scene-format.md for its source and
    parameters), with optional swirl noise of relative amplitude ``swirl``.
    kind ``"map"``: a (Nθ, Nφ) array in nm over polar angle θ in [0, π] (from ``up``) and azimuth
    φ in [0, 2π), bilinearly interpolated.
    """

    kind: str = "uniform"
    thickness_nm: float = 500.0
    top_nm: float = 100.0
    bottom_nm: float = 1000.0
    exponent: float = 0.5
    swirl: float = 0.0
    swirl_scale: float = 6.0
    seed: int = 0
    up: tuple[float, float, float] = (0.0, 1.0, 0.0)
    table: np.ndarray | None = None


@dataclass
class Bubble:
    """A spherical soap film: reflects with R(λ, θ, d) and transmits straight on with T."""

    center: tuple[float, float, float]
    radius: float
    film: FilmProfile = field(default_factory=FilmProfile)
    # a constant index, real or complex n + ik (k > 0: a dyed, absorbing film), or "water"
    # (Daimon & Masumura 2007); the TOML and coursework formats give real indices
    n_film: float | complex | str = "water"
    shininess: float = 200.0  # exponent of point-light highlights (weighted by R)
    name: str = "bubble"


@dataclass
class Mesh:
    """A triangle mesh: vertices (V, 3) and faces (F, 3) of 0-based vertex indices.

    ``shading``: ``"flat"`` (each triangle shaded with its own plane's normal, the coursework's
    model) or ``"smooth"`` (the normal interpolated from the vertex normals ``normals`` (V, 3),
    or, when they are ``None``, from normals computed from the faces,
    :func:`tracer.meshes.computed_vertex_normals`).  Face orientation follows the coursework's
    rule (:mod:`tracer.meshes`).
    """

    vertices: np.ndarray
    faces: np.ndarray
    material: Material = field(default_factory=Material)
    name: str = "mesh"
    normals: np.ndarray | None = None
    shading: str = "flat"


@dataclass
class PointLight:
    """A point light: ``intensity`` times a spectrum (``color`` linear RGB tint of D65)."""

    position: tuple[float, float, float]
    intensity: float = 1.0
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)


@dataclass
class Camera:
    """A pinhole camera: position, look-at point, up vector, vertical field of view in degrees."""

    position: tuple[float, float, float] = (0.0, 0.0, 5.0)
    look_at: tuple[float, float, float] = (0.0, 0.0, 0.0)
    up: tuple[float, float, float] = (0.0, 1.0, 0.0)
    fov_deg: float = 40.0
    mirror: bool = False  # flip the image left-right (a left-handed screen, as the coursework's)

    def basis(self):
        """(origin, forward, right, up) unit vectors; raises ValueError when degenerate."""
        pos = np.asarray(self.position, float)
        look = np.asarray(self.look_at, float)
        with np.errstate(over="ignore", invalid="ignore"):
            fwd = look - pos  # may overflow for coordinates near the float limit: checked below
        if not np.any(fwd) or not np.all(np.isfinite(fwd)):
            what = "coincides with" if not np.any(fwd) else "is too far (overflow) from"
            raise ValueError(f"camera look_at {what} its position")
        fwd = unit_vector(fwd, "camera look_at - position")
        right = np.cross(fwd, unit_vector(self.up, "camera up"))
        rn = np.linalg.norm(right)
        if not rn > 1e-12:
            raise ValueError("camera up vector is parallel to the viewing direction")
        right /= rn
        up = np.cross(right, fwd)
        if self.mirror:
            right = -right
        return pos, fwd, right, up

    @staticmethod
    def coursework_default():
        """Frames the coursework's screen-like coordinates: the plane z = 0, x and y in 0-960.

        The coursework's Qt program drew y downwards and x to the right, with the viewer (and its
        lights, e.g. at z = +1000) on the +z side: a left-handed screen frame, which no rotation
        of a camera reproduces.  So the camera sits at z = 2000 looking at (480, 480, 0) with up
        = -y and ``mirror=True`` (pixel column follows +x), with the field of view that spans
        exactly 0-960 at z = 0.
        """
        return Camera(
            position=(480.0, 480.0, 2000.0),
            look_at=(480.0, 480.0, 0.0),
            up=(0.0, -1.0, 0.0),
            fov_deg=math.degrees(2 * math.atan(480.0 / 2000.0)),
            mirror=True,
        )


@dataclass
class Environment:
    """What a ray that leaves the scene sees.

    kind ``"constant"``: ``color`` (linear RGB) in every direction.
    kind ``"sky"``: a procedural daylight sky (zenith blue to a bright horizon, a soft sun, a
    darker ground) around ``up``; the default, because bubbles show what surrounds them.
    kind ``"image"``: an equirectangular (latitude-longitude) image, linear RGB (H, W, 3),
    ``up`` towards the image's top row, scaled by ``intensity``.
    """

    kind: str = "sky"
    color: tuple[float, float, float] = (0.0, 0.0, 0.0)
    intensity: float = 1.0
    up: tuple[float, float, float] = (0.0, 1.0, 0.0)
    sun_direction: tuple[float, float, float] = (0.4, 0.6, 0.5)
    image: np.ndarray | None = None


@dataclass
class Scene:
    """Everything a render needs besides its settings."""

    spheres: list[Sphere] = field(default_factory=list)
    bubbles: list[Bubble] = field(default_factory=list)
    meshes: list[Mesh] = field(default_factory=list)
    lights: list[PointLight] = field(default_factory=list)
    camera: Camera = field(default_factory=Camera)
    environment: Environment = field(default_factory=Environment)
    ambient: tuple[float, float, float] = (1.0, 1.0, 1.0)
    source: str = "<code>"
    render_defaults: dict = field(default_factory=dict)  # a TOML file's [render] table

    def scale(self):
        """A length typical of the scene (bounding-box diagonal), for ray-origin offsets."""
        pts = [np.asarray(s.center, float) for s in self.spheres + self.bubbles]
        pts += [np.asarray(self.camera.position, float)]
        for m in self.meshes:
            pts.extend([m.vertices.min(axis=0), m.vertices.max(axis=0)])
        pts = np.array(pts)
        radii = [s.radius for s in self.spheres + self.bubbles] or [0.0]
        return float(np.linalg.norm(pts.max(axis=0) - pts.min(axis=0)) + 2 * max(radii)) or 1.0
