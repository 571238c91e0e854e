"""Geometry the renderer tests compute themselves, independently of the tracer's kernels."""

import math

import numpy as np

import tracer


def luminance(img):
    """CIE Y of linear sRGB (IEC 61966-2-1: the second row of its RGB -> XYZ matrix)."""
    return np.asarray(img) @ np.array([0.2126, 0.7152, 0.0722])


def incidence_cosines(scene, w, h):
    """cos(angle of incidence) of each pixel-centre camera ray on the unit sphere at the origin
    (0 where it misses), from the ray-sphere quadratic solved here (the camera ray itself from
    tracer.kernels.sampling.camera_ray, the documented pinhole model)."""
    cam = tracer.prepare.pack.pack_scene(scene).camera[0]
    o = np.asarray(cam["origin"], float)
    out = np.zeros((h, w))
    for y in range(h):
        for x in range(w):
            d = np.array(tracer.kernels.sampling.camera_ray(cam, x + 0.5, y + 0.5, w, h))
            b = o @ d
            disc = b * b - (o @ o - 1.0)
            if disc > 0:
                t = -b - math.sqrt(disc) if o @ o > 1 else -b + math.sqrt(disc)
                n = o + t * d
                out[y, x] = abs(d @ n)
    return out
