"""What rays that leave the scene see: a constant colour, a procedural sky, or an image (numba).

All three return linear sRGB radiance; the integrator turns it into its channels (spectral
bands through the Mallett-Yuksel basis, or RGB as is).
"""

import math

from numba import njit

_JIT = dict(cache=True, error_model="numpy")

ENV_CONSTANT = 0
ENV_SKY = 1
ENV_IMAGE = 2

# Procedural sky colours (linear sRGB), chosen by eye to resemble a clear daytime sky: a
# saturated zenith, a pale horizon and a dark ground (like grass), so bubbles seen against the
# ground show the bright sky they reflect, as in photographs of bubbles outdoors.
_ZENITH = (0.16, 0.33, 0.80)
_HORIZON = (0.85, 0.92, 1.00)
_GROUND_NEAR = (0.045, 0.05, 0.035)
_GROUND_FAR = (0.012, 0.015, 0.01)
_SUN = (30.0, 28.0, 24.0)


@njit(**_JIT)
def environment_rgb(kind, params, image, d):
    """Radiance (r, g, b) seen along unit direction *d*.

    *params*: colour (0:3), up (3:6), sun direction (6:9), intensity (9), image x-axis (10:13)
    and z-axis (13:16) completing the frame of ``up`` for the image lookup.
    Sky: elevation e = d.up; above the horizon the colour blends from horizon to zenith as
    1 - (1 - e)^3, plus a sun disc (cos^2000) and glow (cos^8); below, a ground darkening with
    depth; a narrow smooth blend (|e| < 0.01) avoids a seam.
    Image: equirectangular lookup, nearest texel, longitude from the (x, z) axes around up.
    """
    if kind == ENV_CONSTANT:
        return params[0] * params[9], params[1] * params[9], params[2] * params[9]
    e = d[0] * params[3] + d[1] * params[4] + d[2] * params[5]
    if kind == ENV_IMAGE:
        h = image.shape[0]
        w = image.shape[1]
        x = d[0] * params[10] + d[1] * params[11] + d[2] * params[12]
        z = d[0] * params[13] + d[1] * params[14] + d[2] * params[15]
        theta = math.acos(min(1.0, max(-1.0, e)))
        phi = math.atan2(x, z) + math.pi
        i = min(h - 1, int(theta / math.pi * h))
        j = min(w - 1, int(phi / (2.0 * math.pi) * w)) % w
        s = params[9]
        return image[i, j, 0] * s, image[i, j, 1] * s, image[i, j, 2] * s
    # sky
    up_t = 1.0 - (1.0 - max(e, 0.0)) ** 3
    sky0 = _HORIZON[0] + (_ZENITH[0] - _HORIZON[0]) * up_t
    sky1 = _HORIZON[1] + (_ZENITH[1] - _HORIZON[1]) * up_t
    sky2 = _HORIZON[2] + (_ZENITH[2] - _HORIZON[2]) * up_t
    cs = d[0] * params[6] + d[1] * params[7] + d[2] * params[8]
    if cs > 0.0:
        glow = 0.35 * cs**8
        disc = cs**2000
        sky0 += glow + disc * _SUN[0]
        sky1 += glow + disc * _SUN[1]
        sky2 += glow + disc * _SUN[2]
    down_t = min(1.0, max(-e, 0.0) * 3.0)
    g0 = _GROUND_NEAR[0] + (_GROUND_FAR[0] - _GROUND_NEAR[0]) * down_t
    g1 = _GROUND_NEAR[1] + (_GROUND_FAR[1] - _GROUND_NEAR[1]) * down_t
    g2 = _GROUND_NEAR[2] + (_GROUND_FAR[2] - _GROUND_NEAR[2]) * down_t
    a = min(1.0, max(0.0, (e + 0.01) / 0.02))  # 0 below, 1 above the horizon
    s = params[9]
    return (s * (a * sky0 + (1 - a) * g0), s * (a * sky1 + (1 - a) * g1), s * (a * sky2 + (1 - a) * g2))
