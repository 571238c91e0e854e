"""The latitude-longitude finite-volume grid of a film on a sphere.

θ is the polar angle from the bubble's top (θ = 0 is "up", θ = π the bottom), φ the azimuth,
periodic.  Cell centres: :math:`\\theta_j = (j + 1/2)\\Delta\\theta`, :math:`\\phi_k = k\\Delta\\phi`
(so the columns are the tracer map's columns), :math:`\\Delta\\theta = \\pi/N_\\theta`,
:math:`\\Delta\\phi = 2\\pi/N_\\phi`.  Velocities are staggered (a C grid, as in Huang et al. 2020):
the θ component on the θ faces :math:`\\theta_{j-1/2} = j\\Delta\\theta` (``n_theta + 1`` rows, the
first and last on the poles, where the face has length 0), the φ component on the φ faces
:math:`\\phi_{k-1/2}` between columns k - 1 and k.

The cell areas are exact, :math:`A_j = R^2\\Delta\\phi(\\cos\\theta_{j-1/2} - \\cos\\theta_{j+1/2})`,
so they add up to :math:`4\\pi R^2` to rounding; a θ face has length
:math:`R\\sin\\theta_{j-1/2}\\Delta\\phi` (exactly 0 on the poles: no flux crosses a pole, which
is what makes the poles stable and the schemes conservative), a φ face :math:`R\\Delta\\theta`.
"""

import math
from dataclasses import dataclass, field

import numpy as np

from .limits import PARAMETER_LIMITS, check_number

__all__ = ["FilmGrid"]

#: grid sizes accepted: 4 <= n_theta <= 4096, 4 <= n_phi <= 8192
MIN_THETA, MAX_THETA = 4, 4096


@dataclass(frozen=True)
class FilmGrid:
    """A lat-long grid of ``n_theta`` x ``n_phi`` cells on a sphere of radius *radius* (m, within
    the limits of ``FilmParameters.radius``, :mod:`bubbleoptics.filmflow.limits`).

    Attributes (NumPy arrays, SI units): ``theta`` (n_theta,) cell-centre polar angles,
    ``phi`` (n_phi,) cell-centre azimuths, ``theta_faces`` (n_theta + 1,), ``area`` (n_theta,)
    cell areas in m² (one cell of each row), ``theta_face_length`` (n_theta + 1,) in m (0 at
    the poles), ``phi_face_length`` (a float, m), ``theta_spacing`` (a float, m, between centres
    along a meridian), ``phi_spacing`` (n_theta,) in m, between centres along a parallel.

    >>> g = FilmGrid(8, 16, 0.04)
    >>> bool(abs(g.area.sum() * g.n_phi / (4 * np.pi * 0.04**2) - 1) < 1e-14)
    True
    >>> float(g.theta_face_length[0]), float(g.theta_face_length[-1])
    (0.0, 0.0)
    """

    n_theta: int
    n_phi: int
    radius: float
    theta: np.ndarray = field(init=False, repr=False, compare=False)
    phi: np.ndarray = field(init=False, repr=False, compare=False)
    theta_faces: np.ndarray = field(init=False, repr=False, compare=False)
    area: np.ndarray = field(init=False, repr=False, compare=False)
    theta_face_length: np.ndarray = field(init=False, repr=False, compare=False)
    phi_spacing: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        for name, hi in (("n_theta", MAX_THETA), ("n_phi", 2 * MAX_THETA)):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not MIN_THETA <= v <= hi:
                raise ValueError(f"{name} must be an integer in [{MIN_THETA}, {hi}] (got {v!r})")
        r = check_number("radius", self.radius, PARAMETER_LIMITS)
        nt, nph = int(self.n_theta), int(self.n_phi)
        object.__setattr__(self, "n_theta", nt)
        object.__setattr__(self, "n_phi", nph)
        object.__setattr__(self, "radius", r)
        dth, dph = math.pi / nt, 2 * math.pi / nph
        faces = np.arange(nt + 1) * dth
        faces[-1] = math.pi
        cos_f = np.cos(faces)
        sin_f = np.sin(faces)
        sin_f[0] = sin_f[-1] = 0.0
        theta = (np.arange(nt) + 0.5) * dth
        for name, value in (
            ("theta", theta),
            ("phi", np.arange(nph) * dph),
            ("theta_faces", faces),
            ("area", r * r * dph * (cos_f[:-1] - cos_f[1:])),
            ("theta_face_length", r * sin_f * dph),
            ("phi_spacing", r * np.sin(theta) * dph),
        ):
            value.setflags(write=False)
            object.__setattr__(self, name, value)

    @property
    def d_theta(self):
        """Δθ = π / n_theta (radians)."""
        return math.pi / self.n_theta

    @property
    def d_phi(self):
        """Δφ = 2π / n_phi (radians)."""
        return 2 * math.pi / self.n_phi

    @property
    def theta_spacing(self):
        """Distance between neighbouring cell centres along a meridian, R Δθ (m)."""
        return self.radius * self.d_theta

    @property
    def phi_face_length(self):
        """Length of a φ face (a piece of meridian), R Δθ (m)."""
        return self.radius * self.d_theta

    @property
    def total_area(self):
        """Sum of the cell areas, 4πR² to rounding (m²)."""
        return float(self.area.sum() * self.n_phi)

    def volume(self, h):
        """Film volume :math:`\\sum_{jk} A_j h_{jk}` of a thickness field *h* (m → m³), summed exactly
        (:func:`math.fsum`, so the conservation tests see the scheme's error, not the sum's)."""
        h = np.asarray(h, dtype=float)
        return math.fsum((self.area[:, None] * h).ravel())

    def area_mean(self, f):
        """Area-weighted mean of a cell field *f* (n_theta, n_phi)."""
        return self.volume(f) / self.total_area

    def to_dict(self):
        return {"n_theta": self.n_theta, "n_phi": self.n_phi, "radius": self.radius}
