"""Deterministic per-sample random numbers and the pinhole camera (numba).

Random numbers are a hash of (seed, pixel, sample, dimension), not a stream, so an image is
the same for a given seed whatever the number of threads or the order of work.
"""

import math

import numpy as np
from numba import njit

__all__ = ["uniform", "stratified_offset", "camera_ray"]

_JIT = dict(cache=True, error_model="numpy")

_M1 = np.uint64(0x9E3779B97F4A7C15)
_M2 = np.uint64(0xBF58476D1CE4E5B9)
_M3 = np.uint64(0x94D049BB133111EB)
_S30 = np.uint64(30)
_S27 = np.uint64(27)
_S31 = np.uint64(31)
_S11 = np.uint64(11)


@njit(**_JIT)
def _mix(x):
    """The splitmix64 finaliser (Steele, Lea & Flood, OOPSLA 2014): a bijective 64-bit mix."""
    x = (x ^ (x >> _S30)) * _M2
    x = (x ^ (x >> _S27)) * _M3
    return x ^ (x >> _S31)


@njit(**_JIT)
def uniform(seed, pixel, sample, dim):
    """A uniform number in [0, 1) from the four integers (53 random bits)."""
    x = _mix(np.uint64(seed) * _M1 + np.uint64(pixel))
    x = _mix(x ^ (np.uint64(sample) * _M2 + np.uint64(dim) * _M1))
    return float(x >> _S11) * (1.0 / 9007199254740992.0)


@njit(**_JIT)
def stratified_offset(seed, pixel, sample, spp):
    """Sub-pixel position of sample *sample* of *spp*: one jittered point per stratum of a
    ceil(sqrt(spp))^2 grid (strata beyond spp unused); the pixel centre when spp == 1."""
    if spp == 1:
        return 0.5, 0.5
    n = int(math.ceil(math.sqrt(spp)))
    sx = sample % n
    sy = sample // n
    return (sx + uniform(seed, pixel, sample, 0)) / n, (sy + uniform(seed, pixel, sample, 1)) / n


@njit(**_JIT)
def camera_ray(cam, px, py, width, height):
    """Unit direction of the ray through image point (px, py) (pixels, origin top-left).

    *cam* is a :data:`tracer.layout.CAMERA` record: origin, forward, right and up unit
    vectors, tan(fov_y / 2).  Image rows go down the camera's up vector.
    """
    th = cam.tan_half_fov
    aspect = width / height
    sx = (2.0 * px / width - 1.0) * th * aspect
    sy = (1.0 - 2.0 * py / height) * th
    f = cam.forward
    r = cam.right
    u = cam.up
    dx = f[0] + sx * r[0] + sy * u[0]
    dy = f[1] + sx * r[1] + sy * u[1]
    dz = f[2] + sx * r[2] + sy * u[2]
    inv = 1.0 / math.sqrt(dx * dx + dy * dy + dz * dz)
    return (dx * inv, dy * inv, dz * inv)
