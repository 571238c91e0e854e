"""Simulated films: a bubble whose thickness comes from a film-flow simulation.

A :class:`~tracer.scene.FilmProfile` of kind ``"simulated"`` holds a
:class:`bubbleoptics.filmflow.ThicknessSeries` (``series``: h(θ, φ, t) in nm on a lat-long
grid, θ from the top) and the film time ``time_s`` at which the bubble shows it.  The renderer
draws it as a thickness map (kind ``"map"``, :func:`tracer.kernels.thickness.film_thickness`): the series
at ``time_s``, linear in time between its stored steps, on the map's rows θ_i = iπ/N_θ (poles
included) and columns φ_k = 2πk/N_φ (:meth:`~bubbleoptics.filmflow.ThicknessSeries.node_map_at`).
Nothing of the simulation runs in the tracer: it only samples the series (the tracer depends on
``bubbleoptics``, never the reverse).

``rupture_nm`` (> 0) pops the bubble: where the sampled film is thinner than that anywhere, the
bubble is not drawn (a movie's frames after that time show it gone).  Real films rupture
somewhere between a few and a few tens of nanometres, depending on the surfactant and on
disturbances (the common black film is about 5-30 nm thick); the threshold is the user's, 0
(the default) never pops.

A movie's ``time SECONDS`` command advances every simulated film's time
(:meth:`tracer.movie.timeline.Timeline.frames` resolves each frame's films with
:func:`resolve_simulated_films`, so a frame holds only its own thickness map).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .model import FilmProfile, Scene

__all__ = ["sampled_film", "resolve_simulated_films", "film_is_ruptured", "check_series"]


def check_series(series, what="the film's series"):
    """*series* if it is a :class:`bubbleoptics.filmflow.ThicknessSeries`, else ValueError."""
    from bubbleoptics.filmflow import ThicknessSeries

    if not isinstance(series, ThicknessSeries):
        raise ValueError(f"{what} must be a bubbleoptics.filmflow.ThicknessSeries (got {type(series).__name__})")
    return series


def sampled_film(film: FilmProfile, extra_seconds: float = 0.0) -> FilmProfile:
    """The map film (kind ``"map"``) that the simulated *film* shows at its time plus
    *extra_seconds*; its swirl and ``up`` are kept.  Any other kind is returned unchanged."""
    if film.kind != "simulated":
        return film
    series = check_series(film.series)
    table = series.node_map_at(float(film.time_s) + float(extra_seconds))
    return dataclasses.replace(film, kind="map", table=np.ascontiguousarray(table), series=None,
                               time_s=0.0, rupture_nm=0.0)


def film_is_ruptured(film: FilmProfile, extra_seconds: float = 0.0) -> bool:
    """True when the simulated *film* has a ``rupture_nm`` > 0 and is thinner than it somewhere
    at its time plus *extra_seconds* (the series' cells, not the interpolated map)."""
    if film.kind != "simulated" or not film.rupture_nm > 0:
        return False
    h = check_series(film.series).thickness_at(float(film.time_s) + float(extra_seconds))
    return bool(np.min(h) < film.rupture_nm)


def resolve_simulated_films(scene: Scene, extra_seconds: float = 0.0) -> Scene:
    """*scene* with every simulated film replaced by the map it shows *extra_seconds* after its
    own time, and every bubble whose film has ruptured then removed; the scene itself when it
    has no simulated film (no copy)."""
    if not any(b.film.kind == "simulated" for b in scene.bubbles):
        return scene
    bubbles = [dataclasses.replace(b, film=sampled_film(b.film, extra_seconds)) for b in scene.bubbles
               if not film_is_ruptured(b.film, extra_seconds)]
    return dataclasses.replace(scene, bubbles=bubbles)
