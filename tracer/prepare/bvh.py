"""Bounding-volume hierarchy over triangles: a numba builder and a numba traversal kernel.

Build (:func:`build_bvh`): binned surface-area heuristic (SAH), 12 bins per axis over the
triangles' bounding-box centroids, leaves of at most 4 triangles (Wald, "On fast Construction of
SAH-based Bounding Volume Hierarchies", IEEE Symposium on Interactive Ray Tracing 2007, §3:
binning the centroids into equal bins over the node's centroid extent, and evaluating the
:math:`3(K-1)` planes between the K bins with one sweep from each side).  The builder is one
numba kernel (:func:`_build_nb`, ``cache=True``) working top down with an explicit stack, depth
first: per node one pass over its triangles for the bins, one sweep over the bins, and an
in-place partition of its slice of the triangle order, so a node costs O(its triangles) and the
whole build O(T log T) time and O(T) memory, with no Python per node or per level.

* When a node's centroids all coincide (duplicate triangles) no bin split exists and the node is
  split at the middle of its list.
* Below the 32 top levels every node is split at the object median of its longest centroid
  axis, so the depth (root = 1) stays at most 33 + log2(T / 4) even for adversarial inputs
  (SAH may peel off one triangle per level), and :data:`STACK_SIZE` = 64 entries always
  suffice for the traversal (T < 2**30).
* Every node with more than :data:`LEAF_SIZE` triangles is split (no SAH leaf test): the leaf
  size is a bound the traversal may rely on.
* Above 2 x :data:`PARALLEL_MIN` triangles the top of the tree is built first, down to nodes
  of at most max(T / 8, PARALLEL_MIN) triangles, and those subtrees are then built in numba's
  threads (:func:`_build_tasks_nb`), each into its own range of node ids, which are compacted
  afterwards: the same splits as one thread would make (every split depends on its node's
  triangles and depth only), so the tree does not depend on the number of threads.
* Centroids are computed as ``0.5 lo + 0.5 hi`` (no overflow for coordinates near the largest
  double); a bin split whose cost overflows to infinity is never chosen (the middle split is
  used instead), so huge coordinates give a valid, if not SAH-optimal, tree.

Traversal (:func:`intersect_bvh`, a numba kernel kept in :mod:`tracer.kernels.geometry` with the other
per-ray kernels and re-exported here): depth first, near child first, with an explicit stack
the caller preallocates (``np.empty(STACK_SIZE, np.int64)``, one per thread), so the kernel
allocates nothing.  The ray/box test is the slab test with the robustness fixes of Ize,
"Robust BVH Ray Traversal", *JCGT* 2(2), 2013: the near and far planes are chosen by the sign
of the reciprocal direction, ``1/±0 = ±inf`` handles axis-parallel rays, the ``0 * inf = NaN``
of an origin lying exactly in a slab plane is ignored (comparisons with NaN are false, so the
running max/min keep their previous value: the ray counts as inside that slab, conservatively),
and each far distance is widened by :math:`2\\gamma_3` so rounding never culls a box the ray
touches.  Triangles are tested with the watertight kernel of :mod:`tracer.kernels.geometry`.

The tests check the tree against a brute-force nearest hit over all triangles
(``tests/tracer/test_geometry.py``).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit, prange
from bubbleoptics.jit import JIT

from ..kernels.geometry import STACK_SIZE, degenerate_triangles

__all__ = [
    "BVH",
    "LEAF_SIZE",
    "N_BINS",
    "build_bvh",
]

#: Most triangles in a leaf.
LEAF_SIZE = 4
#: SAH bins per axis.
N_BINS = 12
#: Nodes at depths 1 .. this (root = 1) are split by SAH, deeper ones at the object median.
_SAH_MAX_DEPTH = 32

#: Meshes of more than twice this many triangles have their subtrees of at most
#: max(T / 8, this) triangles built in parallel (numba threads).
PARALLEL_MIN = 16384



class BVH(NamedTuple):
    """A flattened BVH.  Node 0 is the root; *N* nodes, *T* triangles.

    bounds: (N, 2, 3) float64, ``[min, max]`` corners of each node's box (an empty tree has
        one leaf with inverted bounds, ``min = +inf``, ``max = -inf``, which no ray enters).
    child: (N, 2) int64, the two children of an interior node, ``-1`` for a leaf.
    first, count: (N,) int64, a leaf's triangles are ``tris[first : first + count]``
        (``count = 0`` for interior nodes).
    order: (T,) int64, ``tris[i]`` is input triangle ``order[i]``.
    tris: (T, 3, 3) float64, the triangles reordered (a copy); degenerate triangles (zero
        area, see :func:`tracer.kernels.geometry.degenerate_triangles`) are collapsed to their first vertex, so that
        no ray ever hits them.
    """

    bounds: np.ndarray
    child: np.ndarray
    first: np.ndarray
    count: np.ndarray
    order: np.ndarray
    tris: np.ndarray


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


@njit(**JIT)
def _half_area(x0, y0, z0, x1, y1, z1):
    """Half the surface area of the box [x0, x1] x [y0, y1] x [z0, z1]; 0 for an empty one."""
    ex = x1 - x0
    ey = y1 - y0
    ez = z1 - z0
    if not ex > 0.0:  # (explicit tests: numba's min and max of floats cost more)
        ex = 0.0
    if not ey > 0.0:
        ey = 0.0
    if not ez > 0.0:
        ez = 0.0
    return ex * ey + ey * ez + ez * ex


@njit(**JIT)
def _bin_of(c, cmin, scale, n_bins):
    """Bin of centroid coordinate *c* among *n_bins* equal bins from *cmin* (``scale`` =
    n_bins / extent)."""
    b = int((c - cmin) * scale)
    if b < 0:
        return 0
    if b >= n_bins:
        return n_bins - 1
    return b


@njit(**JIT)
def _swap_rows(x, i, j):
    for q in range(x.shape[1]):
        t = x[i, q]
        x[i, q] = x[j, q]
        x[j, q] = t


@njit(**JIT)
def _range_bounds(box, start, end, out):
    """``out[0:6]`` = the box (lo xyz, hi xyz) of ``box[start:end]``'s triangle boxes,
    ``out[6:12]`` = the box of their centres."""
    for q in range(3):
        out[q] = np.inf
        out[3 + q] = -np.inf
        out[6 + q] = np.inf
        out[9 + q] = -np.inf
    for k in range(start, end):
        for q in range(3):
            x = box[k, q]
            if x < out[q]:
                out[q] = x
            x = box[k, 3 + q]
            if x > out[3 + q]:
                out[3 + q] = x
            x = box[k, 6 + q]
            if x < out[6 + q]:
                out[6 + q] = x
            if x > out[9 + q]:
                out[9 + q] = x


@njit(**JIT)
def _build_range_nb(box, leaf_size, n_bins, sah_max_depth, order, bounds, child, first, count, root, start0, end0,
                    depth0, cbox0, next_node, cutoff, tasks, task_cbox):
    """Build the subtree of node *root* over the triangles ``start0 .. end0 - 1``.

    *box*: (T, 9) per triangle its box ``lo``, ``hi`` and the box centre (columns 0-2, 3-5,
    6-8), permuted in place together with *order* (the triangle order), so that every pass over
    a node reads memory in sequence.  *root*'s box is in *bounds* already (written by its
    parent, or by the caller for the root), *cbox0* is its centres' box (lo xyz, hi xyz),
    *depth0* its depth (the tree's root has depth 1).  New nodes are numbered from
    *next_node* up; *bounds*, *child* (-1 where unset), *first*, *count* are the tree's arrays.

    With *cutoff* > 0 a node of more than ``leaf_size`` but at most *cutoff* triangles is not
    split but listed in ``tasks`` (rows node, start, end, depth; centres' boxes in
    ``task_cbox``), to be built by a later call.  Returns ``(next free node, deepest depth
    reached, number of tasks)``.

    A node is visited once, after its parent wrote its box and its centres' box: the SAH split
    gets both children's boxes from its bins (unions of the same triangle boxes) and their
    centres' boxes while it partitions, so a node costs two passes over its triangles.
    """
    T = end0 - start0
    # pending nodes: (node, start, end, depth) and the centres' box; depth first, so at most
    # one node per level waits
    n_stack = min(sah_max_depth, T) + STACK_SIZE + 8  # > the depth bound (module doc)
    stack_node = np.empty(n_stack, dtype=np.int64)
    stack_start = np.empty(n_stack, dtype=np.int64)
    stack_end = np.empty(n_stack, dtype=np.int64)
    stack_depth = np.empty(n_stack, dtype=np.int64)
    stack_cbox = np.empty((n_stack, 6))
    bin_cnt = np.zeros((3, n_bins), dtype=np.int64)
    bin_box = np.empty((3, n_bins, 6))  # per axis and bin: lo xyz, hi xyz
    right_cnt = np.zeros(n_bins, dtype=np.int64)
    right_area = np.zeros(n_bins)
    left_box = np.empty(6)
    right_box = np.empty(6)
    lc_box = np.empty(6)
    rc_box = np.empty(6)
    half = np.empty(12)

    for q in range(6):
        stack_cbox[0, q] = cbox0[q]
    stack_node[0] = root
    stack_start[0] = start0
    stack_end[0] = end0
    stack_depth[0] = depth0
    sp = 1
    n_nodes = next_node
    max_depth = depth0
    n_tasks = 0
    while sp > 0:
        sp -= 1
        node = stack_node[sp]
        start = stack_start[sp]
        end = stack_end[sp]
        depth = stack_depth[sp]
        if depth > max_depth:
            max_depth = depth
        n = end - start
        if n <= leaf_size:
            first[node] = start
            count[node] = n
            continue
        if n <= cutoff:
            tasks[n_tasks, 0] = node
            tasks[n_tasks, 1] = start
            tasks[n_tasks, 2] = end
            tasks[n_tasks, 3] = depth
            for q in range(6):
                task_cbox[n_tasks, q] = stack_cbox[sp, q]
            n_tasks += 1
            continue
        cmin = (stack_cbox[sp, 0], stack_cbox[sp, 1], stack_cbox[sp, 2])
        ext = (stack_cbox[sp, 3] - cmin[0], stack_cbox[sp, 4] - cmin[1], stack_cbox[sp, 5] - cmin[2])
        mid = -1  # no split found yet
        if depth <= sah_max_depth:
            # -- binned SAH
            s0 = n_bins / ext[0] if ext[0] > 0.0 else 0.0
            s1 = n_bins / ext[1] if ext[1] > 0.0 else 0.0
            s2 = n_bins / ext[2] if ext[2] > 0.0 else 0.0
            scale = (s0, s1, s2)
            for a in range(3):
                for b in range(n_bins):
                    bin_cnt[a, b] = 0
                    for q in range(3):
                        bin_box[a, b, q] = np.inf
                        bin_box[a, b, 3 + q] = -np.inf
            for k in range(start, end):
                x0 = box[k, 0]
                x1 = box[k, 1]
                x2 = box[k, 2]
                x3 = box[k, 3]
                x4 = box[k, 4]
                x5 = box[k, 5]
                for a in range(3):
                    if scale[a] > 0.0:
                        b = _bin_of(box[k, 6 + a], cmin[a], scale[a], n_bins)
                        bin_cnt[a, b] += 1
                        # (selects, not branches: neighbouring triangles update the same bin)
                        y = bin_box[a, b, 0]
                        bin_box[a, b, 0] = x0 if x0 < y else y
                        y = bin_box[a, b, 1]
                        bin_box[a, b, 1] = x1 if x1 < y else y
                        y = bin_box[a, b, 2]
                        bin_box[a, b, 2] = x2 if x2 < y else y
                        y = bin_box[a, b, 3]
                        bin_box[a, b, 3] = x3 if x3 > y else y
                        y = bin_box[a, b, 4]
                        bin_box[a, b, 4] = x4 if x4 > y else y
                        y = bin_box[a, b, 5]
                        bin_box[a, b, 5] = x5 if x5 > y else y
            best_cost = np.inf
            best_axis = -1
            best_bin = -1
            for a in range(3):
                if not scale[a] > 0.0:
                    continue
                # sweep from the right: right_cnt[b], right_area[b] of bins b .. n_bins - 1
                rc = 0
                for q in range(3):
                    right_box[q] = np.inf
                    right_box[3 + q] = -np.inf
                for b in range(n_bins - 1, 0, -1):
                    rc += bin_cnt[a, b]
                    for q in range(3):
                        if bin_box[a, b, q] < right_box[q]:
                            right_box[q] = bin_box[a, b, q]
                        if bin_box[a, b, 3 + q] > right_box[3 + q]:
                            right_box[3 + q] = bin_box[a, b, 3 + q]
                    right_cnt[b] = rc
                    right_area[b] = _half_area(right_box[0], right_box[1], right_box[2], right_box[3], right_box[4],
                                               right_box[5])
                # sweep from the left; the plane after bin b: left = bins 0..b, right = b+1..
                lc = 0
                for q in range(3):
                    left_box[q] = np.inf
                    left_box[3 + q] = -np.inf
                for b in range(n_bins - 1):
                    lc += bin_cnt[a, b]
                    for q in range(3):
                        if bin_box[a, b, q] < left_box[q]:
                            left_box[q] = bin_box[a, b, q]
                        if bin_box[a, b, 3 + q] > left_box[3 + q]:
                            left_box[3 + q] = bin_box[a, b, 3 + q]
                    r = right_cnt[b + 1]
                    if lc == 0 or r == 0:
                        continue
                    cost = lc * _half_area(left_box[0], left_box[1], left_box[2], left_box[3], left_box[4],
                                           left_box[5]) + r * right_area[b + 1]
                    if cost < best_cost:  # never an overflowed (inf) or NaN cost
                        best_cost = cost
                        best_axis = a
                        best_bin = b
            if best_axis >= 0:
                a = best_axis
                # the children's boxes: unions of their bins
                for q in range(3):
                    left_box[q] = np.inf
                    left_box[3 + q] = -np.inf
                    right_box[q] = np.inf
                    right_box[3 + q] = -np.inf
                for b in range(n_bins):
                    for q in range(3):
                        x0 = bin_box[a, b, q]
                        x1 = bin_box[a, b, 3 + q]
                        if b <= best_bin:
                            if x0 < left_box[q]:
                                left_box[q] = x0
                            if x1 > left_box[3 + q]:
                                left_box[3 + q] = x1
                        else:
                            if x0 < right_box[q]:
                                right_box[q] = x0
                            if x1 > right_box[3 + q]:
                                right_box[3 + q] = x1
                # partition (bins <= best_bin to the left, by the same bin formula), and the
                # children's centres' boxes on the way
                lx0 = np.inf
                ly0 = np.inf
                lz0 = np.inf
                lx1 = -np.inf
                ly1 = -np.inf
                lz1 = -np.inf
                rx0 = np.inf
                ry0 = np.inf
                rz0 = np.inf
                rx1 = -np.inf
                ry1 = -np.inf
                rz1 = -np.inf
                ca = cmin[a]
                sa = scale[a]
                i0 = start
                j0 = end - 1
                while i0 <= j0:
                    cx = box[i0, 6]
                    cy = box[i0, 7]
                    cz = box[i0, 8]
                    if _bin_of(box[i0, 6 + a], ca, sa, n_bins) <= best_bin:
                        if cx < lx0:
                            lx0 = cx
                        if cy < ly0:
                            ly0 = cy
                        if cz < lz0:
                            lz0 = cz
                        if cx > lx1:
                            lx1 = cx
                        if cy > ly1:
                            ly1 = cy
                        if cz > lz1:
                            lz1 = cz
                        i0 += 1
                    else:
                        if cx < rx0:
                            rx0 = cx
                        if cy < ry0:
                            ry0 = cy
                        if cz < rz0:
                            rz0 = cz
                        if cx > rx1:
                            rx1 = cx
                        if cy > ry1:
                            ry1 = cy
                        if cz > rz1:
                            rz1 = cz
                        _swap_rows(box, i0, j0)
                        t = order[i0]
                        order[i0] = order[j0]
                        order[j0] = t
                        j0 -= 1
                lc_box[0] = lx0
                lc_box[1] = ly0
                lc_box[2] = lz0
                lc_box[3] = lx1
                lc_box[4] = ly1
                lc_box[5] = lz1
                rc_box[0] = rx0
                rc_box[1] = ry0
                rc_box[2] = rz0
                rc_box[3] = rx1
                rc_box[4] = ry1
                rc_box[5] = rz1
                mid = i0
        else:
            # -- object median on the longest centroid axis (bounds the depth)
            a = 0
            if ext[1] > ext[a]:
                a = 1
            if ext[2] > ext[a]:
                a = 2
            keys = np.empty(n)
            for k in range(n):
                keys[k] = box[start + k, 6 + a]
            perm = np.argsort(keys, kind="mergesort")
            tmp_order = order[start:end].copy()
            tmp_box = box[start:end].copy()
            for k in range(n):
                order[start + k] = tmp_order[perm[k]]
                for q in range(9):
                    box[start + k, q] = tmp_box[perm[k], q]
        if mid < 0:
            # the middle of the list (the object median above, or no bin split: all centres
            # equal); the children's boxes by one pass over each half
            mid = start + n // 2
            _range_bounds(box, start, mid, half)
            for q in range(6):
                left_box[q] = half[q]
                lc_box[q] = half[6 + q]
            _range_bounds(box, mid, end, half)
            for q in range(6):
                right_box[q] = half[q]
                rc_box[q] = half[6 + q]
        left = n_nodes
        n_nodes += 2
        child[node, 0] = left
        child[node, 1] = left + 1
        for q in range(3):
            bounds[left, 0, q] = left_box[q]
            bounds[left, 1, q] = left_box[3 + q]
            bounds[left + 1, 0, q] = right_box[q]
            bounds[left + 1, 1, q] = right_box[3 + q]
        # the right child waits, the left one is built next
        stack_node[sp] = left + 1
        stack_start[sp] = mid
        stack_end[sp] = end
        stack_depth[sp] = depth + 1
        for q in range(6):
            stack_cbox[sp, q] = rc_box[q]
        sp += 1
        stack_node[sp] = left
        stack_start[sp] = start
        stack_end[sp] = mid
        stack_depth[sp] = depth + 1
        for q in range(6):
            stack_cbox[sp, q] = lc_box[q]
        sp += 1
    return n_nodes, max_depth, n_tasks


@njit(parallel=True, **JIT)
def _build_tasks_nb(box, leaf_size, n_bins, sah_max_depth, order, bounds, child, first, count, tasks, task_cbox,
                    base, used, depth):
    """Build the subtrees listed in *tasks* in parallel, task *k*'s new nodes from ``base[k]``
    up (its range of ``2 n`` ids cannot overlap another's); ``used[k]``, ``depth[k]``: its next
    free node and deepest depth."""
    for k in prange(tasks.shape[0]):
        cb = task_cbox[k].copy()
        nn, dd, _ = _build_range_nb(box, leaf_size, n_bins, sah_max_depth, order, bounds, child, first, count,
                                    tasks[k, 0], tasks[k, 1], tasks[k, 2], tasks[k, 3], cb, base[k], 0,
                                    tasks[:0], task_cbox[:0])
        used[k] = nn
        depth[k] = dd


@njit(**JIT)
def _compact_nb(n_top, tasks, base, used, bounds, child, first, count, out_bounds, out_child, out_first, out_count):
    """Copy the tree into arrays without the unused ids between the tasks' ranges: the top
    nodes keep their ids, task *k*'s nodes move down to follow the earlier tasks'."""
    for i in range(n_top):
        for a in range(2):
            for q in range(3):
                out_bounds[i, a, q] = bounds[i, a, q]
            out_child[i, a] = child[i, a]
        out_first[i] = first[i]
        out_count[i] = count[i]
    new_base = n_top
    for k in range(tasks.shape[0]):
        shift = base[k] - new_base
        r = tasks[k, 0]  # the task's root (a top node): its children are in the task's range
        if out_child[r, 0] >= 0:
            out_child[r, 0] -= shift
            out_child[r, 1] -= shift
        for i in range(base[k], used[k]):
            j = i - shift
            for a in range(2):
                for q in range(3):
                    out_bounds[j, a, q] = bounds[i, a, q]
                c = child[i, a]
                out_child[j, a] = c - shift if c >= 0 else -1
            out_first[j] = first[i]
            out_count[j] = count[i]
        new_base += used[k] - base[k]
    return new_base


@njit(**JIT)
def _prepare_nb(tris, degenerate, box):
    """Collapse the degenerate triangles (in place) and fill their boxes and box centres."""
    for i in range(tris.shape[0]):
        if degenerate[i]:
            for k in range(1, 3):
                for a in range(3):
                    tris[i, k, a] = tris[i, 0, a]
        for a in range(3):
            x0 = min(tris[i, 0, a], tris[i, 1, a], tris[i, 2, a])
            x1 = max(tris[i, 0, a], tris[i, 1, a], tris[i, 2, a])
            box[i, a] = x0
            box[i, 3 + a] = x1
            box[i, 6 + a] = 0.5 * x0 + 0.5 * x1


@njit(**JIT)
def _gather_nb(tris, order, out):
    for k in range(order.shape[0]):
        i = order[k]
        for v in range(3):
            for a in range(3):
                out[k, v, a] = tris[i, v, a]


def build_bvh(triangles, leaf_size=LEAF_SIZE, n_bins=N_BINS, *, overwrite=False):
    """Build a BVH over ``triangles`` (T, 3, 3) float64 (vertex, xyz); see :class:`BVH`.

    Binned SAH (module doc).  Per node: its box is the union of its triangles' boxes; a node
    with at most ``leaf_size`` triangles becomes a leaf; otherwise its triangle centroids are
    binned along each axis into ``n_bins`` equal bins over the centroid extent, and of the
    ``3 (n_bins - 1)`` planes between bins the one minimising :math:`N_L A_L + N_R A_R`
    (triangle counts times box half-areas of the two sides; the constant traversal cost and the
    parent's area do not change the choice) splits the node.
    T = 0 gives a single empty leaf; non-finite vertices raise ``ValueError``.
    ``overwrite=True`` lets the build collapse degenerate triangles in *triangles* itself (a
    C-contiguous float64 array) instead of in a copy (a mesh of a million triangles is 72 MB).
    """
    tris = np.asarray(triangles, dtype=np.float64)
    if not (overwrite and tris.flags.c_contiguous and tris.flags.writeable):
        tris = np.array(tris, dtype=np.float64, order="C")  # a copy (degenerate ones collapse)
    if tris.size == 0:
        return _empty_bvh()
    if tris.ndim != 3 or tris.shape[1:] != (3, 3):
        raise ValueError(f"build_bvh: triangles must have shape (T, 3, 3), got {tris.shape}")
    if not np.isfinite(tris).all():
        raise ValueError("build_bvh: triangle vertices must be finite")
    if leaf_size < 1 or n_bins < 2:
        raise ValueError("build_bvh: need leaf_size >= 1 and n_bins >= 2")
    T = tris.shape[0]
    if T >= 2**30:
        raise ValueError(f"build_bvh: at most 2**30 triangles, got {T}")
    box = np.empty((T, 9))
    _prepare_nb(tris, degenerate_triangles(tris), box)

    order = np.arange(T, dtype=np.int64)
    # the root's box and its centres' box
    root = np.empty(12)
    _range_bounds(box, 0, T, root)
    # the top of the tree in this thread, down to nodes of at most `cutoff` triangles (a
    # function of T alone, so the tree is the same for every thread count) ...
    cutoff = max(T // 8, PARALLEL_MIN) if T > 2 * PARALLEL_MIN else 0
    # room for the top nodes and the tasks: at each depth (< STACK_SIZE) at most T / cutoff
    # disjoint nodes have more than `cutoff` triangles, and each split makes two nodes
    n_room = 2 * STACK_SIZE * (T // cutoff + 1) + 2 if cutoff else 0
    size = 2 * T + n_room  # the tasks' ranges start at n_top + 2 start, n_top <= n_room
    bounds = np.empty((size, 2, 3))
    child = np.full((size, 2), -1, dtype=np.int64)
    first = np.zeros(size, dtype=np.int64)
    count = np.zeros(size, dtype=np.int64)
    bounds[0, 0] = root[0:3]
    bounds[0, 1] = root[3:6]
    tasks = np.empty((n_room, 4), dtype=np.int64)
    task_cbox = np.empty((n_room, 6))
    n_top, depth, n_tasks = _build_range_nb(box, int(leaf_size), int(n_bins), _SAH_MAX_DEPTH, order, bounds, child,
                                            first, count, 0, 0, T, 1, root[6:12].copy(), 1, cutoff, tasks,
                                            task_cbox)
    if n_tasks:
        # ... then the subtrees below, in parallel (largest first; ids from n_top + 2 start)
        pick = np.argsort(-(tasks[:n_tasks, 2] - tasks[:n_tasks, 1]), kind="stable")
        tasks = np.ascontiguousarray(tasks[:n_tasks][pick])
        task_cbox = np.ascontiguousarray(task_cbox[:n_tasks][pick])
        base = n_top + 2 * tasks[:, 1]
        used = np.empty(n_tasks, dtype=np.int64)
        depths = np.empty(n_tasks, dtype=np.int64)
        import numba

        with numba.parallel_chunksize(1):
            _build_tasks_nb(box, int(leaf_size), int(n_bins), _SAH_MAX_DEPTH, order, bounds, child, first, count,
                            tasks, task_cbox, base, used, depths)
        depth = max(depth, int(depths.max()))
        by_start = np.argsort(tasks[:, 1], kind="stable")  # compact in the order of the ranges
        tasks, base, used = tasks[by_start], base[by_start], used[by_start]
        n_nodes = n_top + int((used - base).sum())
        out_bounds = np.empty((n_nodes, 2, 3))
        out_child = np.empty((n_nodes, 2), dtype=np.int64)
        out_first = np.empty(n_nodes, dtype=np.int64)
        out_count = np.empty(n_nodes, dtype=np.int64)
        _compact_nb(n_top, tasks, base, used, bounds, child, first, count, out_bounds, out_child, out_first,
                    out_count)
        bounds, child, first, count = out_bounds, out_child, out_first, out_count
    else:
        n_nodes = n_top
        bounds, child, first, count = (bounds[:n_nodes].copy(), child[:n_nodes].copy(), first[:n_nodes].copy(),
                                       count[:n_nodes].copy())
    del box
    if depth >= STACK_SIZE:  # cannot happen for T < 2**30 (module doc)
        raise RuntimeError(f"build_bvh: tree depth {depth} exceeds the traversal stack")
    out = np.empty_like(tris)
    _gather_nb(tris, order, out)
    return BVH(bounds=bounds, child=child, first=first, count=count, order=order, tris=out)
