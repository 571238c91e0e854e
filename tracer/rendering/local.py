"""Rendering here, on this machine's numba threads: the integrator called on sets of rows, in
short calls that can be cancelled, interleaved so that every call refines the whole image.
The Python API (:mod:`tracer.rendering.api`) and the Dask tasks (:mod:`tracer.rendering.dask`)
both render through :func:`render_in_parts` and :func:`render_tile`."""

from __future__ import annotations

import sys
import threading
import time

import numpy as np

from ..kernels.integrator import N_COUNTS, new_workspace, render_rows, scene_features
from ..kernels.records import PackedScene

__all__ = ["render_in_parts", "render_here", "render_tile", "warm_up", "is_compiled", "feature_names", "COMPILE_NOTICE", "RenderCancelled", "PARALLEL_LOCK",
           "spread_rows", "render_threads", "ROWS_PER_TASK", "PROGRESS_AFTER", "CALL_SECONDS"]


class RenderCancelled(Exception):
    """A render stopped because its *cancel* argument said so (:func:`render_with_stats`)."""


def _cancelled(cancel) -> bool:
    """Whether *cancel* (None, a ``threading.Event`` or a callable returning a truth value) asks
    the render to stop."""
    if cancel is None:
        return False
    is_set = getattr(cancel, "is_set", None)
    return bool(is_set() if is_set is not None else cancel())


#: Rows per task (one kernel call each, handed to the render threads one at a time): small
#: enough to balance an image whose objects sit in one part of it (the rows are spread over the
#: tasks, :func:`spread_rows`), large enough that a call's set-up costs nothing.
ROWS_PER_TASK = 8
#: A render predicted to take longer than this (s) shows a progress bar and is split into
#: calls of about :data:`CALL_SECONDS` each (which also lets Ctrl-C stop it between calls).
PROGRESS_AFTER = 0.5
CALL_SECONDS = 0.25
#: Hold this around any other parallel numba kernel (e.g. :func:`tracer.rendering.output.display_codes`,
#: the film index tables :func:`tracer.prepare.pack.pack_scene` computes) called from a thread while
#: renders may run in others: numba's default (workqueue) thread pool is not thread-safe and
#: runs one parallel kernel at a time.  Renders take it themselves around each kernel call; it
#: is re-entrant, so a caller may hold it around a whole :func:`tracer.render_with_stats`.
PARALLEL_LOCK = threading.RLock()


def spread_rows(rows):
    """*rows* reordered so that every stretch of the list samples the whole set: sorted by the
    bit-reversed position of each row (van der Corput order).  The threads take tasks in list
    order, so every task, and the last ones that finish a call, sample the whole image rather than
    one band of it (where a bubble may be all or none of the work)."""
    n = rows.size
    bits = max(1, int(n - 1).bit_length())
    pos = np.arange(n, dtype=np.int64)
    rev = np.zeros(n, dtype=np.int64)
    for b in range(bits):
        rev |= ((pos >> b) & 1) << (bits - 1 - b)
    return rows[np.argsort(rev, kind="stable")]


def render_threads() -> int:
    """How many threads a render uses: numba's thread count (``NUMBA_NUM_THREADS``, or
    ``numba.set_num_threads`` in this thread), the machine's cores by default."""
    import numba

    return max(1, int(numba.get_num_threads()))


def rows_call(packed: PackedScene, rows, width, height, spp, seed, depth, threshold, image, counts,
               spectrum=None, row0=0, stop=None, features=None):
    """Render the rows *rows* into ``image[rows - row0]`` and ``counts[rows - row0]`` (and
    ``spectrum[rows - row0]``, (rows, width, C), unless it is None: the kernel's per-band code is then pruned when numba compiles it).

    The rows, in :func:`spread_rows` order, are cut into tasks of :data:`ROWS_PER_TASK`; each of
    :func:`render_threads` worker threads takes the next task and runs the serial kernel on it
    (it releases the GIL) until none is left, while this thread waits, so that Ctrl-C reaches Python at once: it then
    sets the kernel's cancel flag, waits for the threads to stop at their next ray, and raises
    ``KeyboardInterrupt`` (the partial image is the caller's to discard).  *stop* (see
    :func:`_cancelled`) is polled the same way: when it asks, the kernel is stopped likewise and
    :class:`RenderCancelled` raised.  *features*: the kernel's feature flags (default: the
    scene's, :func:`tracer.kernels.integrator.scene_features`).
    """
    if _cancelled(stop):  # between calls: stop before starting the next one
        raise RenderCancelled("render cancelled")
    cancel = np.zeros(1, dtype=np.int64)
    n_tasks = -(-rows.size // ROWS_PER_TASK)
    n_threads = max(1, min(render_threads(), n_tasks))
    arguments = _kernel_arguments(packed, spread_rows(rows), width, height, spp, seed, depth, threshold, image,
                                  counts, spectrum, row0, cancel, features)
    tasks = iter(range(n_tasks))  # handed out one at a time (next() on it is atomic under the GIL)
    failure = []
    left = [n_threads]
    done = threading.Event()  # not Thread.is_alive: an interrupted join can leave it False too early
    count_lock = threading.Lock()

    def work(_):
        try:
            ws = new_workspace(packed, depth, cancel)
            for task in tasks:
                if cancel[0]:
                    break
                render_rows(*arguments[:4], task, n_tasks, *arguments[6:15], ws, *arguments[16:])
        except BaseException as exc:  # re-raised in the calling thread
            failure.append(exc)
            cancel[0] = 1  # the other threads stop too
        finally:
            with count_lock:
                left[0] -= 1
                if left[0] == 0:
                    done.set()

    with PARALLEL_LOCK:  # one render at a time (and no other parallel numba kernel meanwhile)
        workers = [threading.Thread(target=work, args=(i,), name=f"tracer-render-{i}", daemon=True)
                   for i in range(n_threads)]
        started = 0
        try:
            for worker in workers:
                worker.start()
                started += 1
            while not done.wait(0.005 if stop is not None else 0.05):
                if _cancelled(stop):
                    raise RenderCancelled("render cancelled")
        except BaseException:
            cancel[0] = 1
            with count_lock:  # threads never started will not count themselves down
                left[0] -= n_threads - started
                if left[0] == 0:
                    done.set()
            # the kernels must have stopped before the next one starts: wait, whatever comes
            while not done.is_set():
                try:
                    done.wait(0.05)
                except BaseException:
                    continue
            raise
    if failure:
        raise failure[0]


def _interleaved(height, n_parts):
    """The rows 0..height-1 split into *n_parts* interleaved sets (row r in part r % n_parts),
    so that every part samples the whole image."""
    return [np.arange(p, height, n_parts, dtype=np.int64) for p in range(n_parts)]


def _kernel_arguments(packed, rows, width, height, spp, seed, depth, threshold, image, counts, spectrum, row0,
                      cancel, features, task0=0, task_step=1):
    """The arguments of :func:`tracer.kernels.integrator.render_rows` for one thread of a
    :func:`rows_call` with these (*features* None: the scene's, :func:`tracer.kernels.integrator.scene_features`)."""
    features = scene_features(packed) if features is None else features
    return (packed, rows, row0, ROWS_PER_TASK, task0, task_step, width, height, spp, seed, depth, threshold, image,
            counts, spectrum, cancel, *features)


def _one_pixel(packed: PackedScene, spectral_image=False):
    """The positional arguments of the 1x1 :func:`rows_call` that compiles the integrator for *packed*."""
    spectrum = np.zeros((1, 1, packed.rgb_basis.shape[0])) if spectral_image else None
    return (packed, np.zeros(1, dtype=np.int64), 1, 1, 1, 0, 1, 0.0, np.zeros((1, 1, 3)),
            np.zeros((1, N_COUNTS), dtype=np.int64), spectrum)


def is_compiled(packed: PackedScene, spectral_image=False, features=None) -> bool:
    """Whether the integrator that *packed* needs (its features, :func:`tracer.kernels.integrator.scene_features`,
    with or without a per-band image; *features* to ask for other flags) is compiled in this process or in numba's on-disk cache,
    so that the next render starts at once.  True when it cannot tell (numba's cache layout is
    its own)."""
    import numba

    try:
        arguments = list(_kernel_arguments(*_one_pixel(packed, spectral_image), 0, np.zeros(1, dtype=np.int64), features))
        arguments[15] = new_workspace(packed, 1, arguments[15])
        sig = tuple(numba.typeof(a) for a in arguments)
        if any(tuple(key) == sig for key in render_rows.overloads):
            return True
        index = render_rows._cache._cache_file._load_index()
        return any(tuple(getattr(key[0], "args", key[0])) == sig for key in index)
    except Exception:  # another numba's internals: say nothing rather than guess
        return True


#: What a render says when it has to compile first (:func:`warm_up`).
COMPILE_NOTICE = ("tracer: compiling the renderer for this scene's features ({features}) on this machine, "
                  "once (10 to 30 s); later runs load it from numba's cache (tracer warmup compiles ahead)")


def feature_names(packed: PackedScene) -> list:
    """The names of the features *packed* uses (:data:`tracer.kernels.integrator.FEATURES`)."""
    from ..kernels.integrator import FEATURES

    return [name for name, flag in zip(FEATURES, scene_features(packed)) if flag is not None]


def warm_up(packed: PackedScene, notice=None, spectral_image=False, features=None, helper=False):
    """Compile (or load from numba's cache) the integrator for this scene on a 1x1 image (with a
    per-band image too if *spectral_image*).  When it is not compiled yet and *notice* is given
    (a callable taking a line of text), say so first; with *helper*, a second process compiles
    part of it meanwhile where a second core is free (:mod:`tracer.rendering.compile_helper`).
    *features*: other flags than the scene's (:func:`tracer.kernels.integrator.scene_features`;
    ``tracer warmup --all``)."""
    from . import compile_helper

    # the kernel's signature is fixed by its flags and by whether it keeps a per-band image: one
    # warmed up in this process needs no look into numba's cache (that costs a render some ms)
    key = (tuple(scene_features(packed) if features is None else features), bool(spectral_image))
    side = None
    if key not in _WARMED and (notice is not None or helper) and not is_compiled(packed, spectral_image, features):
        if notice is not None:
            notice(COMPILE_NOTICE.format(features=", ".join(feature_names(packed)) or "none"))
        if helper:
            side = compile_helper.start(packed, features)
    try:
        rows_call(*_one_pixel(packed, spectral_image), features=features)
    finally:
        compile_helper.finish(side)
    _WARMED.add(key)


#: The (flags, per-band image) of the kernels :func:`warm_up` has compiled or loaded in this process.
_WARMED = set()


def render_in_parts(packed: PackedScene, s, row0=0, row1=None, spectral_image=False, stop=None,
                    call_seconds=CALL_SECONDS):
    """Render rows ``[row0, row1)`` (default: every row) of the image of the packed scene
    *packed* with the resolved settings *s* (:func:`tracer.rendering.api.resolve_settings`) here, on numba's
    threads, in calls of about *call_seconds* each: a generator that yields ``(rows done,
    rows in all, predicted seconds left)`` after each call and returns ``(image, counts,
    spectrum)`` of ``row1 - row0`` rows (spectrum None unless *spectral_image*; take it with
    ``yield from`` or from ``StopIteration.value``).

    A first call on every 16th row measures the scene; the rest go in one call if short, else
    in interleaved parts, so that every part refines the whole image.  Between two calls the
    caller may do other work (the scene editor renders for several people in turns).  *stop*:
    see :func:`rows_call` (:class:`RenderCancelled`).  The pixels do not depend on how the
    rows were split."""
    width, height, spp, seed, depth, threshold = (s[k] for k in ("width", "height", "spp", "seed", "depth",
                                                                  "threshold"))
    row1 = height if row1 is None else row1
    n = row1 - row0
    image = np.zeros((n, width, 3))
    counts = np.zeros((n, N_COUNTS), dtype=np.int64)
    spectrum = np.zeros((n, width, packed.rgb_basis.shape[0])) if spectral_image else None
    t0 = time.perf_counter()
    first = row0 + _interleaved(n, max(1, min(16, n), n // 64))[0]
    rest = np.setdiff1d(np.arange(row0, row1, dtype=np.int64), first)
    rows_call(packed, first, width, height, spp, seed, depth, threshold, image, counts, spectrum, row0, stop)
    predicted = (time.perf_counter() - t0) / first.size * rest.size
    n_calls = max(1, min(rest.size, int(predicted / call_seconds))) if rest.size else 0
    done = first.size
    yield done, n, predicted
    for part in range(n_calls):
        rows = rest[part::n_calls]
        rows_call(packed, rows, width, height, spp, seed, depth, threshold, image, counts, spectrum, row0, stop)
        done += rows.size
        yield done, n, predicted * (n - done) / max(1, rest.size)
    return image, counts, spectrum


def render_here(packed: PackedScene, s, row0, row1, spectral_image, show, stop=None):
    """:func:`render_in_parts` to the end, behind a progress bar when *show* and the render is
    predicted to take over :data:`PROGRESS_AFTER`."""
    parts = render_in_parts(packed, s, row0, row1, spectral_image, stop)
    bar = None
    try:
        while True:
            try:
                done, total, left = next(parts)
            except StopIteration as finished:
                return finished.value
            if bar is None and show and left > PROGRESS_AFTER:
                from tqdm import tqdm

                bar = tqdm(total=total, initial=done, unit="row", desc="render", leave=False, file=sys.stderr)
            elif bar is not None:
                bar.update(done - bar.n)
    finally:
        if bar is not None:
            bar.close()


def render_tile(packed: PackedScene, settings: dict, row0: int, row1: int, spectral_image=False):
    """Rows ``[row0, row1)`` of the image of the packed scene *packed* with the resolved render
    *settings* (:func:`tracer.rendering.api.resolve_settings`): ``(image, counts, spectrum)``, ``row1 - row0`` rows
    of each, equal bit for bit to those rows of the whole image (every pixel depends only on
    the scene, the settings and its own position).  The task a Dask worker runs for
    ``tracer.render(..., client=...)`` (:mod:`tracer.rendering.dask`)."""
    warm_up(packed)
    return render_here(packed, settings, int(row0), int(row1), spectral_image, False)


