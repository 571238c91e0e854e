"""The editor's renders, for every open editor of the process, in one thread, in turns.

Every render the editor starts (the two stages of a preview, a picked pixel's film, the
warm-up) is a *job*: a generator that does one short step of work each time it is resumed (a
preview stage, or a part of the full image's rows of about :data:`STEP_SECONDS`; see
:func:`tracer.rendering.local.render_in_parts`) and yields its priority for the next step,
:data:`INTERACTIVE` (a first preview, a picked pixel: a person is waiting) or
:data:`BACKGROUND` (the full image, refining).  One thread runs the jobs a step at a time:
always an interactive step before a background one, and among equals the owner served least
recently first.  So one editor's long full render never keeps another editor's preview
waiting for more than one step, and two editors rendering at once share the machine.

An owner (an editor) has at most one job of each *kind* ("render", "pick"): a new one cancels
the one it replaces, and :meth:`RenderScheduler.cancel` (a closed tab) cancels all of an
owner's.  A cancelled job's running step stops at its next ray (its ``cancel`` event is the
kernel's ``stop``), so a cancel takes effect within milliseconds.

The parallel kernels are numba's, whose thread pool runs one kernel at a time; running every
editor render in this one thread (and each step under :data:`tracer.rendering.local.PARALLEL_LOCK`)
keeps them from meeting.
"""

from __future__ import annotations

import itertools
import threading
import time
from dataclasses import dataclass

from ..rendering.local import PARALLEL_LOCK, RenderCancelled

__all__ = ["RenderScheduler", "scheduler", "INTERACTIVE", "BACKGROUND", "STEP_SECONDS"]

#: Priorities a job yields: a person waits for the first, the second refines.
INTERACTIVE, BACKGROUND = 0, 1
#: About how long one step of a full image takes (s): the longest another editor's preview
#: waits for its turn.
STEP_SECONDS = 0.08


@dataclass
class _Job:
    owner: object
    kind: str
    steps: object  # the generator
    cancel: threading.Event
    on_error: object = None
    priority: int = INTERACTIVE
    seq: int = 0


class RenderScheduler:
    """Runs jobs (see the module docstring) in one daemon thread, fairly between owners."""

    def __init__(self):
        self._cond = threading.Condition()
        self._jobs: dict[tuple, _Job] = {}
        self._served: dict[int, int] = {}  # id(owner) -> the tick it was last served
        self._tick = itertools.count(1)
        self._running: _Job | None = None
        self._closed = False
        self._thread = threading.Thread(target=self._run, name="tracer-editor-renders", daemon=True)
        self._thread.start()

    def submit(self, owner, kind, make_steps, on_error=None) -> threading.Event:
        """Run ``make_steps(cancel)`` (a generator function taking the job's cancel event) as
        *owner*'s job of *kind*, cancelling the one it replaces; returns the job's cancel event.
        ``on_error(exception)`` receives a failure (not a cancel) from the scheduler's thread."""
        cancel = threading.Event()
        job = _Job(owner, kind, None, cancel, on_error, seq=next(self._tick))
        job.steps = make_steps(cancel)
        with self._cond:
            if self._closed:
                cancel.set()
                return cancel
            old = self._jobs.get((id(owner), kind))
            if old is not None:
                old.cancel.set()
            self._jobs[(id(owner), kind)] = job
            self._cond.notify_all()
        return cancel

    def cancel(self, owner) -> None:
        """Cancel every job of *owner* (its running step stops at its next ray)."""
        with self._cond:
            for key in [k for k in self._jobs if k[0] == id(owner)]:
                self._jobs.pop(key).cancel.set()
            if self._running is not None and self._running.owner is owner:
                self._running.cancel.set()
            self._served.pop(id(owner), None)
            self._cond.notify_all()

    def idle(self, owner=None, timeout=None) -> bool:
        """Wait until *owner* (or anyone, if None) has no job left (True), or *timeout* s (False)."""
        end = None if timeout is None else time.monotonic() + timeout
        with self._cond:
            while any(owner is None or j.owner is owner for j in self._pending()):
                left = None if end is None else end - time.monotonic()
                if left is not None and left <= 0:
                    return False
                self._cond.wait(0.05 if left is None else min(left, 0.05))
        return True

    def busy(self) -> bool:
        with self._cond:
            return bool(self._pending())

    def _pending(self):
        jobs = list(self._jobs.values())
        if self._running is not None and self._running not in jobs:
            jobs.append(self._running)
        return jobs

    def close(self, timeout=1.0) -> bool:
        """Cancel every job and stop the thread; True if its step in progress ended within
        *timeout* s (a kernel stops at its next ray; numba compiling a kernel cannot be
        stopped)."""
        with self._cond:
            self._closed = True
            for job in self._jobs.values():
                job.cancel.set()
            if self._running is not None:
                self._running.cancel.set()
            self._jobs.clear()
            self._cond.notify_all()
        self._thread.join(timeout)
        return not self._thread.is_alive()

    def _next(self):
        """The job to step next (under the lock), or None."""
        live = [j for j in self._jobs.values() if not j.cancel.is_set()]
        for j in [j for j in self._jobs.values() if j.cancel.is_set()]:
            self._drop(j)
        if not live:
            return None
        return min(live, key=lambda j: (j.priority, self._served.get(id(j.owner), 0), j.seq))

    def _drop(self, job):
        if self._jobs.get((id(job.owner), job.kind)) is job:
            del self._jobs[(id(job.owner), job.kind)]
        job.steps.close()

    def _run(self):
        while True:
            with self._cond:
                job = self._next()
                while job is None and not self._closed:
                    self._cond.wait()
                    job = self._next()
                if self._closed:
                    return
                self._running = job
                self._served[id(job.owner)] = next(self._tick)
            finished = False
            try:
                with PARALLEL_LOCK:
                    job.priority = next(job.steps)
            except StopIteration:
                finished = True
            except RenderCancelled:
                job.cancel.set()
            except Exception as exc:  # reported; the thread lives on for the others
                cancelled = job.cancel.is_set()
                job.cancel.set()
                if job.on_error is not None and not cancelled:
                    try:
                        job.on_error(exc)
                    except Exception:
                        pass
            with self._cond:
                self._running = None
                if finished or job.cancel.is_set():
                    self._drop(job)
                self._cond.notify_all()


_SCHEDULER = None
_LOCK = threading.Lock()


def scheduler() -> RenderScheduler:
    """The process's scheduler (made on first use)."""
    global _SCHEDULER
    with _LOCK:
        if _SCHEDULER is None or _SCHEDULER._closed:
            _SCHEDULER = RenderScheduler()
        return _SCHEDULER
