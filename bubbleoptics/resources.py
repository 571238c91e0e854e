"""What this machine lets a computation use: memory available now and the cores of this process.

Both packages check sizes against these before they allocate (``bubbleoptics.filmflow`` for a
run's frames and a series file, ``tracer.scene.limits`` for an image, ``tracer.rendering.dask`` for the
number of Dask workers), so that a request too large is refused with the estimate, up front.
"""

from __future__ import annotations

import os

__all__ = ["available_memory_bytes", "usable_cores", "gib", "prefer_workqueue_threads"]


def _cgroup_room():
    """Bytes left under this process's cgroup v2 memory limit, or None without one."""
    try:
        with open("/proc/self/cgroup") as f:
            line = next((x for x in f if x.startswith("0::")), None)
        if line is None:
            return None
        folder = os.path.join("/sys/fs/cgroup", line.strip()[3:].lstrip("/"))
        with open(os.path.join(folder, "memory.max")) as f:
            limit = f.read().strip()
        if limit == "max":
            return None
        with open(os.path.join(folder, "memory.current")) as f:
            used = int(f.read().strip())
        return max(0, int(limit) - used)
    except (OSError, ValueError, StopIteration):
        return None


def available_memory_bytes():
    """Memory a new allocation can use now, in bytes: Linux's ``MemAvailable`` (and no more than
    the room left under a cgroup v2 memory limit); else the physical memory; None where neither
    is known."""
    have = None
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    have = int(line.split()[1]) * 1024
                    break
    except (OSError, ValueError, IndexError):
        pass
    if have is None:
        try:
            have = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
        except (ValueError, OSError, AttributeError):
            return None
    room = _cgroup_room()
    return have if room is None else min(have, room)


def usable_cores() -> int:
    """The CPU cores this process may run on (its affinity mask where the system has one)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def gib(n) -> str:
    """*n* bytes in GiB, three significant digits: ``'1.5 GiB'``."""
    return f"{n / 2**30:.3g} GiB"


def prefer_workqueue_threads() -> str:
    """Run numba's parallel kernels on its own "workqueue" threads unless the user chose a
    layer (``NUMBA_THREADING_LAYER``); returns the layer in effect.  For applications (the
    ``tracer`` command, the test suite, the benchmarks), not called by any import.

    numba's OpenMP layer busy-waits at barriers, which on a shared or oversubscribed machine
    (CI runners, a busy neighbour) makes short parallel kernels many times slower; the
    workqueue layer does not (docs/performance.md).  It takes effect only before the process's
    first parallel kernel."""
    import os

    import numba

    if "NUMBA_THREADING_LAYER" not in os.environ:
        numba.config.THREADING_LAYER = "workqueue"
    return numba.config.THREADING_LAYER
