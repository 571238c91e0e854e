"""The limits of every film-flow input, in one table, checked before any work starts.

Each physical parameter of :class:`~bubbleoptics.filmflow.FilmParameters` has a range wide
enough for any soap film (and most other liquid films) on Earth or in a centrifuge, narrow
enough that every product the models form stays a finite float: a value outside it is refused
with one line naming the parameter, its unit and the range.  Why each range is where it is:

- ``radius`` 1e-4 to 10 m: from a 0.1 mm foam bubble to a giant bubble; a smaller sphere's
  cells would be smaller than the film is thick.
- ``h0`` 1e-9 to 1e-3 m: from a 1 nm film (below the thinnest black films, about 5 nm) to 1 mm,
  where a film is no longer thin beside any bubble and the lubrication models do not apply.
- ``viscosity`` 1e-4 to 100 Pa s: from below water's 1e-3 (hot solvents) to far above
  glycerol's 1.4.
- ``density`` 100 to 20000 kg m⁻³: every liquid (liquid hydrogen is 71, mercury 13 534).
- ``surface_tension`` 1e-3 to 1 N m⁻¹: every liquid (liquid helium is 4e-4, mercury 0.49).
- ``gravity`` 0 to 1000 m s⁻²: from weightlessness to a hundred g (a centrifuge).
- ``temperature`` 100 to 1000 K: the liquid range of anything that forms films.
- ``surfactant`` 1e-12 to 1e-3 mol m⁻²: a saturated monolayer is a few 1e-6; the upper end is
  further bounded by σ > 0 (``FilmParameters`` checks that too).
- ``air_drag`` 1e-6 to 1000 kg m⁻² s⁻¹: the boundary-layer estimate is about 0.05; the air
  always drags, and without any drag the velocity of a film evaporated to nothing is undefined.
- ``evaporation`` 0 to 1e-4 m s⁻¹: a film 100 µm thick would be gone in a second; soap films
  evaporate at 1e-9 to 1e-7 m s⁻¹.
- ``perturbation`` 0 to 0.5 (excluded): the seeded thickness stays positive, at least half h0.

A run (:meth:`~bubbleoptics.filmflow.RigidDrainage.run` and ``PlugFlow.run``):

- ``dt`` 1e-9 to 1e6 s and ``t_end`` up to 1e9 s (some 30 years, longer than any film lives):
  their ratio, the step count, is then a finite float;
- at most :data:`MAX_STEPS` steps (ten million: hours of a small grid, a finite run);
- the frames it keeps (float32, ``n_kept x n_theta x n_phi x 4`` bytes) and a model's working
  arrays must fit in the memory available (:func:`check_memory`), refused with the estimate.
"""

from __future__ import annotations

import math

import numpy as np

from ..resources import available_memory_bytes, gib
from ..messages import shorten

__all__ = ["PARAMETER_LIMITS", "RUN_LIMITS", "MAX_STEPS", "check_number", "check_memory", "kept_frames"]

#: name: (lowest, highest, unit, highest excluded) of each physical parameter (module docstring).
PARAMETER_LIMITS = {
    "radius": (1e-4, 10.0, "m", False),
    "h0": (1e-9, 1e-3, "m", False),
    "viscosity": (1e-4, 100.0, "Pa s", False),
    "density": (100.0, 2e4, "kg m^-3", False),
    "surface_tension": (1e-3, 1.0, "N m^-1", False),
    "gravity": (0.0, 1e3, "m s^-2", False),
    "temperature": (100.0, 1000.0, "K", False),
    "surfactant": (1e-12, 1e-3, "mol m^-2", False),
    "air_drag": (1e-6, 1e3, "kg m^-2 s^-1", False),
    "evaporation": (0.0, 1e-4, "m s^-1", False),
    "perturbation": (0.0, 0.5, "(relative)", True),
}
#: name: (lowest, highest, unit, highest excluded) of a run's time step and duration.
RUN_LIMITS = {
    "dt": (1e-9, 1e6, "s", False),
    "t_end": (1e-9, 1e9, "s", False),
}
#: The most steps one run may take.
MAX_STEPS = 10_000_000


def _show(value):
    return shorten(repr(value))


def describe(name, table=None):
    """The allowed values of *name* in words: ``'a finite number in [1e-09, 0.001] m'``."""
    lo, hi, unit, open_hi = (table or {**PARAMETER_LIMITS, **RUN_LIMITS})[name]
    return f"a finite number in [{lo:g}, {hi:g}{')' if open_hi else ']'} {unit}"


def check_number(name, value, table=None):
    """*value* of *name* as a float if it is a real number within its limits (``PARAMETER_LIMITS``
    or ``RUN_LIMITS``), else ValueError naming it and the range."""
    table = table or {**PARAMETER_LIMITS, **RUN_LIMITS}
    lo, hi, _, open_hi = table[name]
    ok = not isinstance(value, bool) and isinstance(value, (int, float, np.integer, np.floating))
    if ok:
        try:
            v = float(value)
        except OverflowError:  # an int beyond the float range
            ok = False
    ok = ok and math.isfinite(v) and lo <= v and (v < hi if open_hi else v <= hi)
    if not ok:
        raise ValueError(f"{name} must be {describe(name, table)} (got {_show(value)})")
    return v


def kept_frames(n_steps, save_every):
    """How many thickness frames a run of *n_steps* steps keeps: the start, every
    *save_every*-th step, and the last step."""
    return 1 + n_steps // save_every + (1 if n_steps % save_every else 0)


def check_memory(need, what, available=None):
    """Refuse (ValueError) *need* bytes for *what* when more than the memory available now."""
    have = available_memory_bytes() if available is None else available
    if have is not None and need > have:
        raise ValueError(f"{what} needs about {gib(need)}, more than the {gib(have)} of memory available")
    return need
