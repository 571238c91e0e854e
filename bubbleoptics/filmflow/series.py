"""A film-thickness time series h(θ, φ, t): what a simulation gives the renderer.

Stored as one ``.npz`` (NumPy's zip of arrays, loaded without pickle): ``h_nm`` (n_times,
n_theta, n_phi) float32 thickness in nm, ``times`` (n_times,) in s, ``theta`` and ``phi``
(the cell centres, radians), ``radius`` (m), ``model`` (its name) and ``parameters`` (a JSON
string: the physical parameters in SI units and the run's dt, seed and grid).
"""

import json
import math
import os

import numpy as np

from ..atomic import write_atomically
from .grid import FilmGrid

__all__ = ["ThicknessSeries"]

FORMAT = "bubbleoptics.filmflow.ThicknessSeries/1"


class ThicknessSeries:
    """Film thickness on a :class:`FilmGrid` at a sequence of times.

    Attributes: ``h_nm`` (n_times, n_theta, n_phi) float32, nm; ``times`` (n_times,) float64, s,
    strictly increasing; ``grid``; ``parameters`` (dict); ``model`` (str).

    >>> import numpy as np
    >>> from bubbleoptics.filmflow import FilmGrid, ThicknessSeries
    >>> g = FilmGrid(4, 8, 0.04)
    >>> s = ThicknessSeries(np.stack([np.full((4, 8), 900.0), np.full((4, 8), 700.0)]), [0.0, 2.0], g, {}, "demo")
    >>> float(s.thickness_at(0.5)[0, 0]), float(s.thickness_at(99.0)[0, 0])  # linear, then clamped
    (850.0, 700.0)
    """

    def __init__(self, h_nm, times, grid, parameters, model):
        h = np.asarray(h_nm, dtype=np.float32)
        t = np.asarray(times, dtype=float)
        if not isinstance(grid, FilmGrid):
            raise ValueError(f"grid must be a FilmGrid (got {type(grid).__name__})")
        if h.ndim != 3 or h.shape[1:] != (grid.n_theta, grid.n_phi) or h.shape[0] < 1:
            raise ValueError(f"h_nm must have shape (n_times >= 1, {grid.n_theta}, {grid.n_phi}) (got {h.shape})")
        if t.shape != (h.shape[0],):
            raise ValueError(f"times must have shape ({h.shape[0]},) to match h_nm (got {t.shape})")
        if not (np.all(np.isfinite(t)) and np.all(np.diff(t) > 0)):
            raise ValueError("times must be finite and strictly increasing")
        if not np.all(np.isfinite(h)) or np.any(h < 0):
            raise ValueError("h_nm must be finite and >= 0")
        self.h_nm = h
        self.times = t
        self.grid = grid
        self.parameters = dict(parameters)
        self.model = str(model)

    def __len__(self):
        return len(self.times)

    def __repr__(self):
        return (f"ThicknessSeries(model={self.model!r}, {len(self)} times {self.times[0]:g}..{self.times[-1]:g} s, "
                f"grid {self.grid.n_theta}x{self.grid.n_phi})")

    def thickness_at(self, t):
        """Thickness (n_theta, n_phi) in nm at time *t* (s): linear in time between the stored
        times, clamped to the first and last.  float64."""
        if isinstance(t, bool) or not isinstance(t, (int, float, np.floating, np.integer)) or not math.isfinite(t):
            raise ValueError(f"t must be a finite number of seconds (got {t!r})")
        times = self.times
        if t <= times[0]:
            return self.h_nm[0].astype(float)
        if t >= times[-1]:
            return self.h_nm[-1].astype(float)
        i = int(np.searchsorted(times, t, side="right")) - 1
        w = (t - times[i]) / (times[i + 1] - times[i])
        return (1.0 - w) * self.h_nm[i].astype(float) + w * self.h_nm[i + 1].astype(float)

    def node_map_at(self, t):
        """The thickness at time *t* on the n_theta + 1 face latitudes θ_i = iπ/n_theta (poles
        included) and the n_phi cell azimuths φ_k = 2πk/n_phi: the layout of the tracer's film
        maps (rows evenly spaced from the top, θ = 0, to the bottom).  Interior rows are the mean
        of the two neighbouring cell rows, a pole row the mean of its ring.  nm, float64."""
        h = self.thickness_at(t)
        out = np.empty((h.shape[0] + 1, h.shape[1]))
        out[1:-1] = 0.5 * (h[:-1] + h[1:])
        out[0] = h[0].mean()
        out[-1] = h[-1].mean()
        return out

    def save(self, path):
        """Write the series to *path* (``.npz``) atomically; returns *path*."""
        def write(tmp):
            with open(tmp, "wb") as f:
                np.savez_compressed(
                    f, format=np.array(FORMAT), h_nm=self.h_nm, times=self.times, theta=self.grid.theta,
                    phi=self.grid.phi, radius=np.array(self.grid.radius), model=np.array(self.model),
                    parameters=np.array(json.dumps(self.parameters, sort_keys=True)))

        return write_atomically(path, write)

    @classmethod
    def load(cls, path):
        """Read a series written by :meth:`save`; raises ``ValueError`` if *path* is not one."""
        with np.load(os.fspath(path), allow_pickle=False) as z:
            missing = {"format", "h_nm", "times", "theta", "phi", "radius", "model", "parameters"} - set(z.files)
            if missing or str(z["format"]) != FORMAT:
                raise ValueError(f"{path} is not a ThicknessSeries file (format {FORMAT})")
            h = z["h_nm"]
            grid = FilmGrid(int(h.shape[1]), int(h.shape[2]), float(z["radius"]))
            if not (np.allclose(z["theta"], grid.theta, rtol=0, atol=1e-12)
                    and np.allclose(z["phi"], grid.phi, rtol=0, atol=1e-12)):
                raise ValueError(f"{path}: theta/phi are not the cell centres of a {h.shape[1]}x{h.shape[2]} grid")
            return cls(h, z["times"], grid, json.loads(str(z["parameters"])), str(z["model"]))
