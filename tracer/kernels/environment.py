"""What rays that leave the scene see: a constant colour, a procedural sky, or an image (numba).

All three return linear sRGB radiance; the integrator turns it into its channels (spectral
bands through the Mallett-Yuksel basis, or RGB as is).
"""

import math

from numba import njit
from bubbleoptics.jit import JIT

from .records import ENV_CONSTANT, ENV_IMAGE, ENV_SKY

__all__ = ["environment_rgb", "ENV_CONSTANT", "ENV_SKY", "ENV_IMAGE"]


# Procedural sky colours (linear sRGB), chosen by eye to resemble a clear daytime sky: a
# saturated zenith, a pale horizon and a dark ground (like grass), so bubbles seen against the
# ground show the bright sky they reflect, as in photographs of bubbles outdoors.
_ZENITH = (0.16, 0.33, 0.80)
_HORIZON = (0.85, 0.92, 1.00)
_GROUND_NEAR = (0.045, 0.05, 0.035)
_GROUND_FAR = (0.012, 0.015, 0.01)
_SUN = (30.0, 28.0, 24.0)
_DISC_MIN = 0.97  # 0.97**2000 = 3.5e-27


@njit(**JIT)
def environment_rgb(env, image, d):
    """Radiance (r, g, b), linear sRGB, seen along unit direction *d*.

    *env* is a :data:`tracer.kernels.records.ENVIRONMENT` record, *image* the equirectangular image
    (H, W, 3) of an image environment.
    Constant: ``color * intensity``.
    Sky: elevation e = d.up; above the horizon the colour blends from horizon to zenith as
    1 - (1 - e)^3, plus a sun disc (cos^2000) and glow (cos^8); below, a ground darkening with
    depth; a narrow smooth blend (|e| < 0.01) avoids a seam.
    Image: equirectangular (latitude-longitude) lookup, nearest texel, in Mitsuba 3's
    ``envmap`` convention (W. Jakob et al., Mitsuba 3 renderer, plugin ``envmap``; checked
    against Mitsuba itself in tests/tracer/test_environment.py): in the frame (X, up, Z) of the
    record's ``xaxis``, ``up`` and ``zaxis`` (world x, y, z for up = +y), the direction d falls on
    column u = atan2(d.X, -d.Z) / 2π (mod 1) and row v = acos(d.up) / π of the image (row 0 at
    the zenith).  Looking along -Z with up up, the image's column 0 is straight ahead and the
    columns increase to the right (u = 1/4 at +X, 1/2 behind, 3/4 at -X): the image is seen as
    it is drawn, not mirrored (docs/images/environment_convention.png).
    """
    s = env.intensity
    if env.kind == ENV_CONSTANT:
        return env.color[0] * s, env.color[1] * s, env.color[2] * s
    up = env.up
    e = d[0] * up[0] + d[1] * up[1] + d[2] * up[2]
    if env.kind == ENV_IMAGE:
        h = image.shape[0]
        w = image.shape[1]
        xa = env.xaxis
        za = env.zaxis
        x = d[0] * xa[0] + d[1] * xa[1] + d[2] * xa[2]
        z = d[0] * za[0] + d[1] * za[1] + d[2] * za[2]
        theta = math.acos(min(1.0, max(-1.0, e)))
        u = math.atan2(x, -z) / (2.0 * math.pi)  # in [-1/2, 1/2]
        if u < 0.0:
            u += 1.0
        i = min(h - 1, int(theta / math.pi * h))
        j = min(w - 1, int(u * w))
        return image[i, j, 0] * s, image[i, j, 1] * s, image[i, j, 2] * s
    # sky
    up_t = 1.0 - (1.0 - max(e, 0.0)) ** 3
    sky0 = _HORIZON[0] + (_ZENITH[0] - _HORIZON[0]) * up_t
    sky1 = _HORIZON[1] + (_ZENITH[1] - _HORIZON[1]) * up_t
    sky2 = _HORIZON[2] + (_ZENITH[2] - _HORIZON[2]) * up_t
    sun = env.sun
    cs = d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2]
    if cs > 0.0:
        c2 = cs * cs
        c4 = c2 * c2
        glow = 0.35 * (c4 * c4)
        # cos^2000 only near the sun: below _DISC_MIN it is under 4e-27 (times _SUN, 1e-25), far
        # below half an ulp of the sky it is added to (>= 0.012), and its chain of squarings would
        # pass through subnormal numbers, which cost many times a normal multiply
        disc = cs**2000 if cs > _DISC_MIN else 0.0
        sky0 += glow + disc * _SUN[0]
        sky1 += glow + disc * _SUN[1]
        sky2 += glow + disc * _SUN[2]
    down_t = min(1.0, max(-e, 0.0) * 3.0)
    g0 = _GROUND_NEAR[0] + (_GROUND_FAR[0] - _GROUND_NEAR[0]) * down_t
    g1 = _GROUND_NEAR[1] + (_GROUND_FAR[1] - _GROUND_NEAR[1]) * down_t
    g2 = _GROUND_NEAR[2] + (_GROUND_FAR[2] - _GROUND_NEAR[2]) * down_t
    a = min(1.0, max(0.0, (e + 0.01) / 0.02))  # 0 below, 1 above the horizon
    return (s * (a * sky0 + (1 - a) * g0), s * (a * sky1 + (1 - a) * g1), s * (a * sky2 + (1 - a) * g2))
