"""The floor kernel the tracer's benchmarks compare against (benchmarks/throughput.py, builtin_split.py)."""

import math
import time

import numpy as np

from numba import njit, prange

__all__ = ["floor_kernel", "run_floor", "paired_render", "CENTERS", "RADII", "BACKGROUND"]


@njit(parallel=True, cache=True)
def floor_kernel(width, height, centers, radii, background, out):
    """The floor: per pixel one camera ray, three spheres, nearest hit, one mirror bounce."""
    for y in prange(height):
        for x in range(width):
            dx = (2.0 * (x + 0.5) / width - 1.0) * 0.5
            dy = (1.0 - 2.0 * (y + 0.5) / height) * 0.5
            dz = -1.0
            inv = 1.0 / math.sqrt(dx * dx + dy * dy + dz * dz)
            dx *= inv
            dy *= inv
            dz *= inv
            ox = oy = oz = 0.0
            value = 0.0
            weight = 1.0
            for _ in range(2):
                best = np.inf
                hit = -1
                for i in range(centers.shape[0]):
                    fx = ox - centers[i, 0]
                    fy = oy - centers[i, 1]
                    fz = oz - centers[i, 2]
                    b = fx * dx + fy * dy + fz * dz
                    disc = b * b - (fx * fx + fy * fy + fz * fz - radii[i] * radii[i])
                    if disc > 0.0:
                        t = -b - math.sqrt(disc)
                        if t > 1e-9 and t < best:
                            best = t
                            hit = i
                if hit < 0:
                    value += weight * background
                    break
                px = ox + best * dx
                py = oy + best * dy
                pz = oz + best * dz
                nx = (px - centers[hit, 0]) / radii[hit]
                ny = (py - centers[hit, 1]) / radii[hit]
                nz = (pz - centers[hit, 2]) / radii[hit]
                dn = dx * nx + dy * ny + dz * nz
                dx -= 2.0 * dn * nx
                dy -= 2.0 * dn * ny
                dz -= 2.0 * dn * nz
                ox, oy, oz = px, py, pz
                weight *= 0.5
            out[y, x] = value


#: The floor's scene: three spheres (centres, radii) before a constant environment.
CENTERS = np.array([[0.0, 0.0, -5.0], [1.5, 0.0, -6.0], [-1.5, 0.0, -6.0]])
RADII = np.array([1.0, 0.7, 0.7])
BACKGROUND = 0.5


def run_floor(size, out):
    """The floor at *size* x *size* into *out* (float64, (size, size))."""
    floor_kernel(size, size, CENTERS, RADII, BACKGROUND, out)


def paired_render(tracer, scene, size, depth, out):
    """The floor (into *out*), then *scene* rendered at *size* x *size* and trace depth *depth*
    (None: the scene's default): ``(render seconds, floor seconds, total rays)``, so that each
    render is read against the floor run just before it."""
    t0 = time.perf_counter()
    run_floor(size, out)
    t_floor = time.perf_counter() - t0
    t0 = time.perf_counter()
    _, stats = tracer.render_with_stats(scene, width=size, height=size, depth=depth, progress=False)
    return time.perf_counter() - t0, t_floor, stats.rays["total"]
