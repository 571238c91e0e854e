"""Deterministic per-sample random numbers and the pinhole camera (numba).

Random numbers are a hash of (seed, pixel, sample, dimension), not a stream, so an image is
the same for a given seed whatever the number of threads or the order of work.  Spherical
lights are sampled the same way (:func:`cone_sample`): a hash of the camera sample
(:func:`sample_key`), the shaded point's place in the ray tree, the light and the sample.
"""

import math

import numpy as np
from numba import njit
from bubbleoptics.jit import JIT

__all__ = ["uniform", "stratified_offset", "camera_ray", "sample_key", "stratified_square",
           "orthonormal_basis", "cone_direction", "cone_sample"]


_M1 = np.uint64(0x9E3779B97F4A7C15)
_M2 = np.uint64(0xBF58476D1CE4E5B9)
_M3 = np.uint64(0x94D049BB133111EB)
_S30 = np.uint64(30)
_S27 = np.uint64(27)
_S31 = np.uint64(31)
_S11 = np.uint64(11)


@njit(**JIT)
def _mix(x):
    """The splitmix64 finaliser (Steele, Lea & Flood, OOPSLA 2014): a bijective 64-bit mix."""
    x = (x ^ (x >> _S30)) * _M2
    x = (x ^ (x >> _S27)) * _M3
    return x ^ (x >> _S31)


@njit(**JIT)
def uniform(seed, pixel, sample, dim):
    """A uniform number in [0, 1) from the four integers (53 random bits)."""
    x = _mix(np.uint64(seed) * _M1 + np.uint64(pixel))
    x = _mix(x ^ (np.uint64(sample) * _M2 + np.uint64(dim) * _M1))
    return float(x >> _S11) * (1.0 / 9007199254740992.0)


@njit(**JIT)
def stratified_offset(seed, pixel, sample, spp):
    """Sub-pixel position of sample *sample* of *spp*: one jittered point per stratum of a
    ceil(sqrt(spp))^2 grid (strata beyond spp unused); the pixel centre when spp == 1."""
    if spp == 1:
        return 0.5, 0.5
    n = int(math.ceil(math.sqrt(spp)))
    sx = sample % n
    sy = sample // n
    return (sx + uniform(seed, pixel, sample, 0)) / n, (sy + uniform(seed, pixel, sample, 1)) / n


@njit(**JIT)
def camera_ray(cam, px, py, width, height):
    """Unit direction of the ray through image point (px, py) (pixels, origin top-left).

    *cam* is a :data:`tracer.kernels.records.CAMERA` record: origin, forward, right and up unit
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


@njit(**JIT)
def sample_key(seed, pixel, sample):
    """A 64-bit key of the camera sample (seed, pixel, sample): the seed of that sample's
    light samples, so that they change with the seed, also at one sample per pixel (where the
    camera ray is the pixel centre's whatever the seed)."""
    x = _mix(np.uint64(seed) * _M2 + np.uint64(pixel))
    return _mix(x ^ (np.uint64(sample) * _M1 + _M3))


@njit(**JIT)
def stratified_square(key, stream, k, n):
    """Point *k* of *n* (0 <= k < n) in [0, 1)², one jittered point in each of n strata of
    equal area, for any n.

    The strata are m = floor(sqrt(n)) rows; with n = q m + r, the first r rows hold q + 1
    strata and the others q, and each row's height is its share of the strata (its count / n),
    so every stratum has area exactly 1/n (a perfect square n is the n^½ x n^½ grid).  The
    jitter is :func:`uniform` of (key, stream, k, axis).
    """
    m = int(math.sqrt(n))
    while m * m > n:
        m -= 1
    while (m + 1) * (m + 1) <= n:
        m += 1
    q = n // m
    r = n - q * m
    big = r * (q + 1)  # strata in the rows of q + 1
    if k < big:
        row = k // (q + 1)
        cols = q + 1
        col = k - row * cols
        start = row * cols
    else:
        kk = k - big
        row = kk // q
        cols = q
        col = kk - row * q
        start = big + row * q
    u1 = (start + cols * uniform(key, stream, k, 0)) / n
    u2 = (col + uniform(key, stream, k, 1)) / cols
    return u1, u2


@njit(**JIT)
def orthonormal_basis(a):
    """Two unit vectors that make a right-handed orthonormal frame (b1, b2, a) with the unit
    vector *a*, without a branch on its direction but for the sign of a_z (the construction of
    Duff et al., "Building an orthonormal basis, revisited", JCGT 6(1), 2017 :cite:`Duff2017`)."""
    sign = 1.0 if a[2] >= 0.0 else -1.0
    h = -1.0 / (sign + a[2])
    k = a[0] * a[1] * h
    b1 = (1.0 + sign * a[0] * a[0] * h, sign * k, -sign * a[0])
    b2 = (k, sign + a[1] * a[1] * h, -a[1])
    return b1, b2


@njit(**JIT)
def cone_direction(axis, b1, b2, one_minus_cos, u1, u2):
    """The unit direction at (u1, u2) in [0, 1)² of the cone of directions around *axis*
    (frame b1, b2, axis) whose half-angle α has 1 − cos α = *one_minus_cos*, uniform in solid
    angle: cos θ = 1 − u1 (1 − cos α), φ = 2π u2 (the cone's solid angle 2π (1 − cos α) grows
    linearly in cos θ).  *one_minus_cos* = 2 gives the whole sphere.  sin θ comes from
    u1 (1 − cos α)(2 − u1 (1 − cos α)), without the cancellation of 1 − cos²θ for narrow cones."""
    v = u1 * one_minus_cos
    cos_t = 1.0 - v
    sin_t = math.sqrt(max(0.0, v * (2.0 - v)))
    phi = 2.0 * math.pi * u2
    x = sin_t * math.cos(phi)
    y = sin_t * math.sin(phi)
    return (x * b1[0] + y * b2[0] + cos_t * axis[0],
            x * b1[1] + y * b2[1] + cos_t * axis[1],
            x * b1[2] + y * b2[2] + cos_t * axis[2])


@njit(**JIT)
def cone_sample(key, stream, k, n, axis, b1, b2, one_minus_cos):
    """Direction *k* of *n* stratified over the cone (:func:`stratified_square` mapped by
    :func:`cone_direction`): the samples of a spherical light, uniform in the solid angle the
    sphere subtends (PBRT 4th ed. :cite:`PBRT4`, sampling the cone of a sphere; Shirley, Wang &
    Zimmerman 1996 :cite:`Shirley1996`).  *key* and *stream* choose the random numbers."""
    u1, u2 = stratified_square(key, stream, k, n)
    return cone_direction(axis, b1, b2, one_minus_cos, u1, u2)
