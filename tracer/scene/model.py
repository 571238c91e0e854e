"""The scene model: plain dataclasses that loaders build and the renderer packs into arrays.

Units: lengths in scene units (any unit, used consistently; the coursework's files use
screen-like units where a 960x960 image spans about 0-960), film thickness in nanometres, angles
in radians (the camera's field of view in degrees, as people say it), colours as linear RGB in
[0, 1] (the coursework's 0-255 integers are converted by the loader), light intensities as
non-negative multipliers of the light's spectrum (CIE D65 unless given), and in W/sr for
lights with inverse-square falloff (:class:`PointLight`).
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
    "LIGHT_FALLOFFS",
    "MAX_LIGHT_SAMPLES",
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
    kind ``"simulated"``: a film-flow simulation's thickness series (``series``, a
    :class:`bubbleoptics.filmflow.ThicknessSeries`) shown at film time ``time_s`` (s), drawn as
    the map of that moment; ``rupture_nm`` > 0 pops the bubble once the film is thinner than
    that anywhere (:mod:`tracer.scene.simulated`).
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
    series: object | None = None  # kind "simulated": a bubbleoptics.filmflow.ThicknessSeries
    time_s: float = 0.0
    rupture_nm: float = 0.0


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
    # "airy" (the exact sum of all reflected beams) or "two-beam" (the coursework's two-beam
    # formula, R = 4 R01 sin^2(beta), T = 1 - R: to show that model's error in a render)
    film_model: str = "airy"


@dataclass
class Mesh:
    """A triangle mesh: vertices (V, 3) and faces (F, 3) of 0-based vertex indices.

    ``shading``: ``"flat"`` (each triangle shaded with its own plane's normal, the coursework's
    model) or ``"smooth"`` (the normal interpolated from the vertex normals ``normals`` (V, 3),
    or, when they are ``None``, from normals computed from the faces,
    :func:`tracer.prepare.meshes.computed_vertex_normals`).  Face orientation follows the coursework's
    rule (:mod:`tracer.prepare.meshes`).
    """

    vertices: np.ndarray
    faces: np.ndarray
    material: Material = field(default_factory=Material)
    name: str = "mesh"
    normals: np.ndarray | None = None
    shading: str = "flat"


#: How a light's strength depends on the distance r to its centre (:class:`PointLight`).
LIGHT_FALLOFFS = ("none", "inverse_square")
#: A spherical light's sample count (:attr:`PointLight.samples`) lies in 1..MAX_LIGHT_SAMPLES:
#: every sample is a shadow ray at every shaded point, so 1024 already makes a light cost as
#: much as a thousand point lights.
MAX_LIGHT_SAMPLES = 1024


@dataclass
class PointLight:
    """A light: a point (``radius`` 0) or a uniformly emitting sphere, with a D65 spectrum
    tinted by ``color`` (linear RGB) and scaled by ``intensity``.

    **The renderer's radiance scale.**  Pixel values are radiance L (linear sRGB, channel
    values as factors on D65, :func:`tracer.prepare.pack.channel_setup`): an environment of intensity 1
    seen directly is 1.  Read 1 as 1 W m⁻² sr⁻¹ and every quantity below is in SI units
    (lengths in metres).  A Phong surface (:mod:`tracer.kernels.surfaces.phong`) sends the viewer
    ``S · (kd (N·L) C + ks (R·V)^s)`` from a light, a soap film ``S · R (R·V)^s``, times the
    shadow ray's transmittance, where S, the light's *strength* at the shaded point, is set
    by ``falloff``:

    * ``"none"`` (the default; the coursework's lights, which do not dim with distance):
      ``S = intensity``, a pure number: the radiance of a white (kd C = 1) Lambertian surface
      facing the light, at any distance.
    * ``"inverse_square"``: ``intensity`` is the radiant intensity I in W/sr (the same in
      every direction; a power Φ in W is I = Φ / 4π) and ``S = I / (π r²)``, r the distance
      to the light's centre: the irradiance E = I cos θ / r² of a point source, turned into
      radiance by the Lambertian BRDF kd C / π (PBRT 4th ed. :cite:`PBRT4`, point lights and
      the Lambertian BRDF).  The Phong specular term and the film highlight, which are not
      normalised BRDFs, are scaled by the same S.

    **Spherical lights** (``radius`` a > 0): a sphere of uniform radiance L_e whose radiant
    intensity seen from outside is π a² L_e, equal to ``intensity`` (so L_e = I / (π a²) for
    ``"inverse_square"``; for ``"none"`` L_e = S / sin²α, which keeps the coursework's
    distance-free strength).  From a point at distance d > a it fills the cone of half-angle
    α, sin α = a / d, of solid angle Ω = 2π (1 − cos α).  The irradiance it gives a Lambertian
    surface whose horizon it lies entirely above is E = π L_e sin²α cos θ (θ between the normal
    and the direction to the centre; the view factor of a sphere, Howell et al.
    :cite:`Howell2021`), exactly what a point light of the same intensity at its centre gives:
    a sphere light differs from a point light only where it is partly hidden, by an occluder
    (soft shadows) or by the horizon.  The renderer estimates, for each of ``samples``
    directions ω_k stratified over the cone (uniform in solid angle, which for a sphere is
    exact: every direction of the cone meets it; Shirley, Wang & Zimmerman :cite:`Shirley1996`,
    PBRT's sphere sampling :cite:`PBRT4`),

        L ≈ S · Ω / (π sin²α) · (1/N) Σ_k f(ω_k) V(ω_k),   Ω / (π sin²α) = 2 / (1 + cos α),

    with f the surface's response above (diffuse, Phong and film highlights alike evaluated at
    the sample direction ω_k) and V(ω_k) the transmittance of a shadow ray to the sphere's near
    surface along ω_k.  A point inside the sphere (d < a) is surrounded by it: the cone is the
    whole sphere of directions (Ω = 4π, sin α = 1), S is taken at d = a, and the point is lit
    from its whole upper hemisphere (E = π L_e).  ``radius`` 0 is exactly the point light (one
    shadow ray to the centre).  The sample directions are a hash of the camera sample (seed,
    pixel, sample: :func:`tracer.kernels.sampling.sample_key`), the shaded point's place in its ray
    tree, the light and the sample (:func:`tracer.kernels.sampling.cone_sample`), so an image does not
    depend on the thread count or the run, and another seed gives other light samples.

    ``samples`` (1 to :data:`MAX_LIGHT_SAMPLES`) is used only when ``radius`` > 0.
    """

    position: tuple[float, float, float]
    intensity: float = 1.0
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    radius: float = 0.0
    falloff: str = "none"
    samples: int = 16


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
