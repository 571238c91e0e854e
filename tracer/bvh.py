"""Bounding-volume hierarchy over triangles: a NumPy builder and a numba traversal kernel.

Build (:func:`build_bvh`): binned surface-area heuristic, 12 bins per axis over the
triangles' bounding-box centroids (Wald, "On fast Construction of SAH-based Bounding Volume
Hierarchies", IEEE Symposium on Interactive Ray Tracing 2007), leaves of at most 4 triangles.
The tree is built breadth first, one whole level per step, with every node of the level binned
by the same few NumPy calls (bin counts by ``bincount``, bin bounds by ``minimum.at``, split
costs by prefix scans over the bins), so the Python overhead is per level, not per node:
100k triangles take about 1.5 s.  When a node's centroids all coincide (duplicate
triangles) no bin split exists and the node is split at the middle of its list.  From depth 32
on every node is split at the object median of its longest centroid axis, so the depth stays
below 32 + log2(T) even for adversarial inputs (SAH may peel off one triangle per level),
and :data:`STACK_SIZE` = 64 entries always suffice for the traversal.

Traversal (:func:`intersect_bvh`, a numba kernel kept in :mod:`tracer.geometry` with the other
per-ray kernels and re-exported here): depth first, near child first, with an explicit stack
the caller preallocates (``np.empty(STACK_SIZE, np.int64)``, one per thread), so the kernel
allocates nothing.  The ray/box test is the slab test with the robustness fixes of Ize,
"Robust BVH Ray Traversal", *JCGT* 2(2), 2013: the near and far planes are chosen by the sign
of the reciprocal direction, ``1/±0 = ±inf`` handles axis-parallel rays, the ``0 * inf = NaN``
of an origin lying exactly in a slab plane is ignored (comparisons with NaN are false, so the
running max/min keep their previous value: the ray counts as inside that slab, conservatively),
and each far distance is widened by :math:`2\\gamma_3` so rounding never culls a box the ray
touches.  Triangles are tested with the watertight kernel of :mod:`tracer.geometry`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .geometry import STACK_SIZE, intersect_bvh

__all__ = [
    "BVH",
    "LEAF_SIZE",
    "N_BINS",
    "STACK_SIZE",
    "build_bvh",
    "degenerate_triangles",
    "intersect_bvh",
]

#: Most triangles in a leaf.
LEAF_SIZE = 4
#: SAH bins per axis.
N_BINS = 12
#: Below this depth nodes are split at the object median (bounds the depth, see module doc).
_SAH_MAX_DEPTH = 32

_EPS = 2.0**-52


class BVH(NamedTuple):
    """A flattened BVH.  Node 0 is the root; *N* nodes, *T* triangles.

    bounds: (N, 2, 3) float64, ``[min, max]`` corners of each node's box (an empty tree has
        one leaf with inverted bounds, ``min = +inf``, ``max = -inf``, which no ray enters).
    child: (N, 2) int64, the two children of an interior node, ``-1`` for a leaf.
    first, count: (N,) int64, a leaf's triangles are ``tris[first : first + count]``
        (``count = 0`` for interior nodes).
    order: (T,) int64, ``tris[i]`` is input triangle ``order[i]``.
    tris: (T, 3, 3) float64, the triangles reordered (a copy); degenerate triangles (zero
        area, see :func:`degenerate_triangles`) are collapsed to their first vertex, so that
        no ray ever hits them.
    """

    bounds: np.ndarray
    child: np.ndarray
    first: np.ndarray
    count: np.ndarray
    order: np.ndarray
    tris: np.ndarray


def degenerate_triangles(tris):
    """Boolean mask of zero-area triangles: height :math:`\\le 16\\varepsilon\\max|x|`.

    The height over the longest edge, :math:`h = |e_1\\times e_2|/\\max_k|e_k|`
    (:math:`e_1 = v_1 - v_0`, :math:`e_2 = v_2 - v_0`), is compared with 16 ulps of the
    triangle's largest coordinate :math:`\\max|x|`: a triangle thinner than the rounding of its
    own vertices cannot be told from a segment (e.g. a vertex computed as
    :math:`a + s(b - a)` is off the line by up to ~2 ulps).  This flags repeated and collinear
    vertices, and nothing any image could show.  Why it is needed: the watertight test rejects a
    zero-area triangle only when its edge functions cancel exactly; for collinear vertices whose
    sheared coordinates are rounded it may report a "hit" on the segment, with no defined normal.
    The one test of a zero-area face: the scene loaders skip the faces it flags, with a
    warning (:mod:`tracer.coursework_format`, :mod:`tracer.toml_scene`), and :func:`build_bvh`
    collapses any left in a mesh built in code.
    """
    tris = np.asarray(tris, dtype=np.float64).reshape(-1, 3, 3)
    e1 = tris[:, 1] - tris[:, 0]
    e2 = tris[:, 2] - tris[:, 0]
    e3 = tris[:, 2] - tris[:, 1]
    area2 = np.linalg.norm(np.cross(e1, e2), axis=1)
    longest = np.sqrt(np.max([(e * e).sum(axis=1) for e in (e1, e2, e3)], axis=0))
    size = np.abs(tris).max(axis=(1, 2))
    return ~(area2 > 16.0 * _EPS * size * longest)


def _empty_bvh():
    bounds = np.empty((1, 2, 3))
    bounds[0, 0] = np.inf
    bounds[0, 1] = -np.inf
    return BVH(
        bounds=bounds,
        child=np.full((1, 2), -1, dtype=np.int64),
        first=np.zeros(1, dtype=np.int64),
        count=np.zeros(1, dtype=np.int64),
        order=np.zeros(0, dtype=np.int64),
        tris=np.zeros((0, 3, 3)),
    )


def _half_area(lo, hi):
    """Half the surface area of boxes [lo, hi] (last axis xyz); 0 for empty (inverted) boxes."""
    e = np.maximum(hi - lo, 0.0)
    return e[..., 0] * e[..., 1] + e[..., 1] * e[..., 2] + e[..., 2] * e[..., 0]


def build_bvh(triangles, leaf_size=LEAF_SIZE, n_bins=N_BINS):
    """Build a BVH over ``triangles`` (T, 3, 3) float64 (vertex, xyz); see :class:`BVH`.

    Binned SAH (module doc).  Each level: the node boxes are the union of their triangles'
    boxes; a node with at most ``leaf_size`` triangles becomes a leaf; otherwise its triangle
    centroids are binned along each axis into ``n_bins`` equal bins over the centroid extent,
    and of the ``3 (n_bins - 1)`` planes between bins the one minimising
    :math:`N_L A_L + N_R A_R` (triangle counts times box half-areas of the two sides; the
    constant traversal cost and the parent's area do not change the choice) splits the node.
    T = 0 gives a single empty leaf; non-finite vertices raise ``ValueError``.
    """
    tris = np.array(triangles, dtype=np.float64)  # a copy
    if tris.size == 0:
        return _empty_bvh()
    if tris.ndim != 3 or tris.shape[1:] != (3, 3):
        raise ValueError(f"build_bvh: triangles must have shape (T, 3, 3), got {tris.shape}")
    if not np.all(np.isfinite(tris)):
        raise ValueError("build_bvh: triangle vertices must be finite")
    if leaf_size < 1 or n_bins < 2:
        raise ValueError("build_bvh: need leaf_size >= 1 and n_bins >= 2")
    T = tris.shape[0]
    deg = degenerate_triangles(tris)
    tris[deg] = tris[deg, 0:1, :]

    lo = tris.min(axis=1)
    hi = tris.max(axis=1)
    cent = 0.5 * (lo + hi)

    max_nodes = 2 * T - 1  # every split makes two non-empty children
    bounds = np.empty((max_nodes, 2, 3))
    child = np.full((max_nodes, 2), -1, dtype=np.int64)
    first = np.zeros(max_nodes, dtype=np.int64)
    count = np.zeros(max_nodes, dtype=np.int64)
    order = np.arange(T, dtype=np.int64)

    seg_node = np.zeros(1, dtype=np.int64)  # the nodes of the current level ...
    seg_start = np.zeros(1, dtype=np.int64)  # ... own order[start : start + cnt]
    seg_cnt = np.full(1, T, dtype=np.int64)
    n_nodes = 1
    level = 0
    nb = int(n_bins)
    while seg_node.size:
        # -- boxes of all nodes of this level; small nodes become leaves
        offs, seg_of, pos = _segments(seg_start, seg_cnt)
        prim = order[pos]
        bounds[seg_node, 0] = np.minimum.reduceat(lo[prim], offs, axis=0)
        bounds[seg_node, 1] = np.maximum.reduceat(hi[prim], offs, axis=0)
        leaf = seg_cnt <= leaf_size
        first[seg_node[leaf]] = seg_start[leaf]
        count[seg_node[leaf]] = seg_cnt[leaf]
        inner = ~leaf
        if not inner.any():
            break
        seg_node, seg_start, seg_cnt = seg_node[inner], seg_start[inner], seg_cnt[inner]
        S = seg_node.size
        offs, seg_of, pos = _segments(seg_start, seg_cnt)
        prim = order[pos]
        M = prim.size
        c = cent[prim]
        cmin = np.minimum.reduceat(c, offs, axis=0)
        cmax = np.maximum.reduceat(c, offs, axis=0)
        ext = cmax - cmin
        rank = np.arange(M, dtype=np.int64) - offs[seg_of]

        if level < _SAH_MAX_DEPTH:
            # -- binned SAH, all nodes of the level at once
            ext_p = ext[seg_of]
            rel = np.divide(c - cmin[seg_of], ext_p, out=np.zeros_like(c), where=ext_p > 0)
            b = np.clip(np.floor(rel * nb).astype(np.int64), 0, nb - 1)  # (M, 3)
            key = (seg_of[:, None] * 3 + np.arange(3)) * nb + b  # (M, 3) flat (node, axis, bin)
            n_keys = S * 3 * nb
            cnt = np.bincount(key.ravel(), minlength=n_keys).reshape(S, 3, nb)
            blo = np.full((n_keys, 3), np.inf)
            bhi = np.full((n_keys, 3), -np.inf)
            plo, phi = lo[prim], hi[prim]
            for a in range(3):
                np.minimum.at(blo, key[:, a], plo)
                np.maximum.at(bhi, key[:, a], phi)
            blo = blo.reshape(S, 3, nb, 3)
            bhi = bhi.reshape(S, 3, nb, 3)
            # left side = bins 0..i, right side = bins i+1..nb-1, for i = 0..nb-2
            l_cnt = np.cumsum(cnt, axis=2)[:, :, :-1]
            r_cnt = np.cumsum(cnt[:, :, ::-1], axis=2)[:, :, ::-1][:, :, 1:]
            l_area = _half_area(
                np.minimum.accumulate(blo, axis=2),
                np.maximum.accumulate(bhi, axis=2),
            )[:, :, :-1]
            r_area = _half_area(
                np.minimum.accumulate(blo[:, :, ::-1], axis=2)[:, :, ::-1],
                np.maximum.accumulate(bhi[:, :, ::-1], axis=2)[:, :, ::-1],
            )[:, :, 1:]
            cost = np.where((l_cnt > 0) & (r_cnt > 0), l_cnt * l_area + r_cnt * r_area, np.inf)
            cost = cost.reshape(S, 3 * (nb - 1))
            best = np.argmin(cost, axis=1)
            valid = np.isfinite(cost[np.arange(S), best])
            best_axis = best // (nb - 1)
            best_bin = best % (nb - 1)
            right = b[np.arange(M), best_axis[seg_of]] > best_bin[seg_of]
            # no bin split (all centroids equal): split the list in the middle
            fallback = ~valid[seg_of]
            right[fallback] = rank[fallback] >= (seg_cnt[seg_of[fallback]] // 2)
        else:
            # -- object median on the longest centroid axis (bounds the depth)
            axis = np.argmax(ext, axis=1)
            perm = np.lexsort((c[np.arange(M), axis[seg_of]], seg_of))
            prim = prim[perm]
            right = rank >= (seg_cnt[seg_of] // 2)

        # -- partition each node's list (stable), create the children
        perm = np.argsort(seg_of * 2 + right, kind="stable")
        order[pos] = prim[perm]
        n_left = np.bincount(seg_of, weights=~right, minlength=S).astype(np.int64)
        left_id = n_nodes + 2 * np.arange(S, dtype=np.int64)
        child[seg_node, 0] = left_id
        child[seg_node, 1] = left_id + 1
        n_nodes += 2 * S
        seg_node = np.stack([left_id, left_id + 1], axis=1).ravel()
        seg_start = np.stack([seg_start, seg_start + n_left], axis=1).ravel()
        seg_cnt = np.stack([n_left, seg_cnt - n_left], axis=1).ravel()
        level += 1

    if level + 1 >= STACK_SIZE:  # cannot happen for T < 2**31 (module doc)
        raise RuntimeError(f"build_bvh: tree depth {level} exceeds the traversal stack")
    return BVH(
        bounds=np.ascontiguousarray(bounds[:n_nodes]),
        child=np.ascontiguousarray(child[:n_nodes]),
        first=np.ascontiguousarray(first[:n_nodes]),
        count=np.ascontiguousarray(count[:n_nodes]),
        order=order,
        tris=np.ascontiguousarray(tris[order]),
    )


def _segments(start, cnt):
    """For contiguous ranges ``order[start_s : start_s + cnt_s]`` laid end to end: the offset
    of each range in the concatenation, the range index of each element, and its position."""
    offs = np.zeros(cnt.size, dtype=np.int64)
    np.cumsum(cnt[:-1], out=offs[1:])
    seg_of = np.repeat(np.arange(cnt.size, dtype=np.int64), cnt)
    pos = np.repeat(start - offs, cnt) + np.arange(int(cnt.sum()), dtype=np.int64)
    return offs, seg_of, pos
