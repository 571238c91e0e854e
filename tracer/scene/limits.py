"""The limits of every render setting, in one place, checked before any work starts.

Each setting has a range a user can reason about; :func:`check_settings` refuses a value
outside it with one line naming the setting (as the caller names it: ``--depth`` on the
command line, ``FILE:LINE: render.depth`` in a scene file, ``depth`` in Python) and the
allowed range, and :func:`check_memory` refuses an image that cannot fit in memory, with the
estimate, before anything is allocated.

Why each limit is where it is:

- ``width``, ``height`` <= 65535: the largest side most image tools accept (PNG allows more,
  but a 65535 x 65535 render already needs 100 GB); the memory check below is the real bound.
- ``depth`` <= 1000: a ray's generation.  Rays past a few dozen generations carry nothing
  visible at any threshold a display needs, and the ray stack of a task holds ``depth + 8``
  rays.  The exhaustive tree (``threshold = 0``) branches at every surface, up to
  ``2**depth - 1`` rays a sample, so it is limited to ``depth <= 24`` (the coursework's table
  goes to 10): deeper trees need a pruning threshold.
- ``spp`` <= 65536 samples a pixel (stratified in a 256 x 256 grid at most).
- ``spectral_samples`` <= 421: one band per 1 nm sample of 360-780 nm at most, the step of the
  colour-matching and basis tables they are integrated from
  (:func:`bubbleoptics.band_spectral_weights`); narrower bands would hold no table sample.
- ``seed``: 0 to 2**63 - 1 (a non-negative 64-bit integer; the sample hash takes it as such).
- ``threshold``: a finite number >= 0.

And every number a scene gives (coordinates, lengths, film thicknesses, intensities, colours)
is at most :data:`MAX_MAGNITUDE` = 1e15 in magnitude: squared distances and sums of radiance
must stay finite (1e308 is the float limit), and the tracer is tested on scenes from 1e-12 to
1e12 units (tests/tracer/test_geometry.py); a refractive index at most :data:`MAX_INDEX` = 100.
"""

from __future__ import annotations

import math
import numbers
import operator

from bubbleoptics.colorimetry import MAX_BANDS
from bubbleoptics.resources import available_memory_bytes, gib as _gib
from bubbleoptics.messages import shorten

__all__ = [
    "LIMITS",
    "MAX_EXHAUSTIVE_DEPTH",
    "MAX_MAGNITUDE",
    "MAX_INDEX",
    "LimitError",
    "check_settings",
    "check_setting",
    "describe",
    "check_memory",
    "available_memory_bytes",
    "render_bytes",
    "VIEWS",
    "DISPLAY_DEFAULTS",
    "MAX_EXPOSURE",
    "SPECTRAL_METHODS",
]

#: (lowest, highest) allowed value of each integer setting.
LIMITS = {
    "width": (1, 65535),
    "height": (1, 65535),
    "depth": (1, 1000),
    "spp": (1, 65536),
    "spectral_samples": (1, MAX_BANDS),
    "seed": (0, 2**63 - 1),
}
#: The largest magnitude of any number in a scene (see the module docstring).
MAX_MAGNITUDE = 1e15
#: The largest refractive index a material or a film may have (real materials stay below 5).
MAX_INDEX = 100.0
#: The deepest exhaustive tree (``threshold = 0``): up to 2**24 - 1 rays a sample.
MAX_EXHAUSTIVE_DEPTH = 24
#: Bytes a pixel costs a render and its save: the float64 RGB image (24), the 8- or 16-bit
#: codes and the writer's copy of them (up to 12).
BYTES_PER_PIXEL = 36
#: How films are evaluated over a wavelength band (:func:`tracer.prepare.pack.resolve_spectral_method`).
SPECTRAL_METHODS = ("auto", "point", "band")
#: View transforms of the display outputs (:mod:`tracer.rendering.output`).
VIEWS = ("clip", "aces")
#: The display settings and their defaults (a TOML scene's ``[render]`` table may set them).
DISPLAY_DEFAULTS = dict(exposure=0.0, view="clip")
#: ``exposure`` is limited to +-this many stops (2**64 is 1.8e19: beyond any scene's range).
MAX_EXPOSURE = 64.0


class LimitError(ValueError):
    """A setting outside its allowed range (the message names the setting and the range)."""


def _integer(value):
    """*value* as an int if it is an integer (a Python or NumPy integer, or an integral float),
    else None."""
    if isinstance(value, bool):
        return None
    try:
        return operator.index(value)
    except TypeError:
        pass
    if isinstance(value, float) and math.isfinite(value) and value == int(value):
        return int(value)
    return None


def _show(value) -> str:
    return shorten(repr(value))


def describe(key) -> str:
    """The allowed values of setting *key* in words: ``"an integer from 1 to 1000"``."""
    if key == "threshold":
        return "a finite number >= 0"
    lo, hi = LIMITS[key]
    return f"an integer from {lo} to {hi}"


def check_setting(key, value, name=None):
    """*value* of the setting *key* checked against its limits: the value (an int for integer
    settings, a float for ``threshold``), else :class:`LimitError` naming it as *name*."""
    name = name or key
    if key == "threshold":
        try:
            v = float(value) if isinstance(value, numbers.Real) else math.nan
        except (TypeError, ValueError, OverflowError):
            v = math.nan
        if isinstance(value, bool) or not (math.isfinite(v) and v >= 0.0):
            raise LimitError(f"{name} must be {describe(key)}, got {_show(value)}")
        return v
    lo, hi = LIMITS[key]
    v = _integer(value)
    if v is None or not lo <= v <= hi:
        raise LimitError(f"{name} must be {describe(key)}, got {_show(value)}")
    return v


def check_settings(settings: dict, names=None) -> dict:
    """A copy of *settings* with every limited setting checked (:func:`check_setting`), and the
    exhaustive tree's depth limit; *names* maps a key to what the caller calls it."""
    names = names or {}
    out = dict(settings)
    for key, value in settings.items():
        if key in LIMITS or key == "threshold":
            out[key] = check_setting(key, value, names.get(key))
    if out.get("threshold", 1.0) == 0.0 and out.get("depth", 1) > MAX_EXHAUSTIVE_DEPTH:
        raise LimitError(
            f"{names.get('depth', 'depth')} must be at most {MAX_EXHAUSTIVE_DEPTH} when "
            f"{names.get('threshold', 'threshold')} is 0 (the exhaustive tree has up to 2^depth - 1 rays "
            f"a sample), got {out['depth']}: give a threshold > 0 for deeper trees")
    return out


def render_bytes(width, height, bytes_per_pixel=BYTES_PER_PIXEL):
    """What rendering and saving a *width* x *height* image needs, in bytes (an estimate)."""
    return int(width) * int(height) * int(bytes_per_pixel)


def check_memory(width, height, bytes_per_pixel=BYTES_PER_PIXEL, available=None):
    """Refuse (:class:`LimitError`) an image whose render needs more memory than is available."""
    need = render_bytes(width, height, bytes_per_pixel)
    have = available_memory_bytes() if available is None else available
    if have is not None and need > have:
        raise LimitError(f"a {width} x {height} image needs about {_gib(need)} to render and save, "
                         f"more than the {_gib(have)} of memory available")
    return need
