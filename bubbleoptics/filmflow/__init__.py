"""Living films: the thickness of a soap film on a bubble evolving from physics.

Two models behind one interface, SI units inside, the thickness series in nm:

* :class:`RigidDrainage`: lubrication drainage between immobile interfaces, with evaporation;
* :class:`PlugFlow`: Huang et al. (2020)-style plug flow with surfactant (Marangoni force,
  gravity, air drag, evaporation).

``model.run(t_end, dt, save_every, seed, progress)`` gives a :class:`ThicknessSeries`
(``h_nm`` (n_times, n_theta, n_phi), ``times``, ``grid``, ``parameters``, ``model``) with
``save`` / ``load`` (``.npz``) and ``thickness_at(t)``.  θ is the polar angle from the top.

>>> from bubbleoptics.filmflow import FilmParameters, FilmGrid, PlugFlow
>>> p = FilmParameters()
>>> series = PlugFlow(p, FilmGrid(8, 16, p.radius)).run(t_end=0.05, dt=0.005, save_every=5, seed=3)
>>> series.h_nm.shape, series.times.tolist()
((3, 8, 16), [0.0, 0.025, 0.05])
"""

from .grid import FilmGrid
from .models import FilmState, PlugFlow, RigidDrainage, smooth_perturbation
from .parameters import FilmParameters
from .series import ThicknessSeries

__all__ = [
    "FilmGrid",
    "FilmParameters",
    "FilmState",
    "RigidDrainage",
    "PlugFlow",
    "ThicknessSeries",
    "smooth_perturbation",
]
