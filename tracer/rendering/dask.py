"""Rendering on a Dask cluster: the frames of a movie (:mod:`tracer.movie`) and the rows of one
large image (:func:`render_tiles`), on a :class:`distributed.LocalCluster` of one-thread
processes (``workers=N``) or a running cluster (``scheduler=ADDRESS``)::

    dask scheduler                          # on one machine: prints tcp://HOST:8786
    dask worker tcp://HOST:8786 --nthreads 1 --nworkers 4   # on each machine (NUMBA_NUM_THREADS=1)
    tracer movie scene.toml out.mp4 moves.txt --scheduler tcp://HOST:8786

Why Dask's distributed scheduler and not a hand-written pool: it retries the tasks of a lost
worker (``retries``), balances uneven tasks dynamically, and the same code runs on one machine
or on many (``docs/movies.md``).

Every task is a module-level function (:func:`tracer.rendering.local.render_tile`,
:func:`tracer.movie.render_frame_png`), so that a worker imports ``tracer`` and loads the numba
kernels from the on-disk cache instead of compiling them (:func:`worker_numba_cache_stats`).
A pixel depends only on the scene, the settings and its own position, never on which process
or thread renders it, so a distributed image is bit for bit the local one.
"""

from __future__ import annotations

import contextlib
import sys

import numpy as np

from bubbleoptics.resources import usable_cores
from bubbleoptics.messages import shorten

from ..kernels.integrator import N_COUNTS

__all__ = ["local_cluster", "connect", "cluster_client", "render_tiles", "tile_bounds", "worker_numba_cache_stats",
           "check_cluster_options", "check_scheduler_address", "max_workers", "SCHEMES", "CONNECT_DEADLINE",
           "DEFAULT_PORT", "TILES_PER_WORKER"]

#: Seconds a scheduler has to accept the connection *and* answer Dask's handshake (one deadline
#: for both): a closed port, a silent one and one that answers something else all fail within it.
CONNECT_DEADLINE = 3.0
#: The port of an address given without one (``dask scheduler``'s default).
DEFAULT_PORT = 8786
#: The schemes of a Dask address: ``tcp`` is used (also for an address without a scheme, as Dask
#: does); every other is refused by name, with the reason.
SCHEMES = {
    "tcp": None,
    "tls": "needs TLS certificates, which the command line does not take: from Python, pass "
           "client=distributed.Client(ADDRESS, security=...)",
    "inproc": "names a place inside one Python process, not a cluster to connect to",
    "ucx": "needs UCX (ucx-py), which the dask extra does not install",
    "ws": "needs the websocket comm (tornado websockets), which the command line does not use: give its tcp:// address",
    "wss": "needs the websocket comm and TLS certificates: give the scheduler's tcp:// address",
}

#: Tiles of rows per worker in :func:`render_tiles`: enough that a worker that finishes early
#: (its rows miss the bubbles) takes another tile, few enough that a tile's fixed cost (a task,
#: its transfer) stays small beside its rows.
TILES_PER_WORKER = 8

def local_cluster(workers: int):
    """A :class:`distributed.LocalCluster` of *workers* processes with one thread each, and
    ``NUMBA_NUM_THREADS=1`` in every worker (numba reads it when it is first imported), so that
    the workers share the cores rather than each starting one numba thread per core."""
    from distributed import LocalCluster

    env = {"NUMBA_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
    return LocalCluster(n_workers=int(workers), threads_per_worker=1, processes=True, dashboard_address=None,
                        scheduler_kwargs={"dashboard_address": ":0"},  # its HTTP server on a free port
                        env=env, silence_logs=50)  # CRITICAL: no shutdown chatter on stderr


_HOST_CHARACTERS = set("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789.-_")
_IPV6_CHARACTERS = set("0123456789abcdefABCDEF:.%")


def check_scheduler_address(address, name="scheduler") -> str:
    """The Dask address *address* as ``tcp://HOST:PORT`` (the scheme ``tcp`` and the port
    :data:`DEFAULT_PORT` when left out; split by distributed's own
    ``distributed.comm.addressing.parse_host_port``), else ValueError naming it as *name*: a
    scheme other than tcp is refused by name with the reason (:data:`SCHEMES`), and so is a
    malformed host or port."""
    shown = repr(shorten(address, 60)) if isinstance(address, str) else repr(address)
    usage = "a Dask scheduler's address is tcp://HOST:PORT"
    if not isinstance(address, str) or not address or not address.isascii() or not address.isprintable():
        raise ValueError(f"{name}: {usage}, got {shown}")
    scheme, sep, location = address.partition("://")
    if not sep:
        scheme, location = "tcp", address
    scheme = scheme.lower()
    if scheme not in SCHEMES:
        raise ValueError(f"{name}: unknown scheme '{scheme}://' in {shown} ({usage})")
    if SCHEMES[scheme] is not None:
        raise ValueError(f"{name}: the scheme {scheme}:// {SCHEMES[scheme]}; got {shown}")
    from distributed.comm.addressing import parse_host_port, unparse_host_port

    tail = location.rpartition("]")[2]  # after an [IPv6] host: ":PORT" or nothing
    if tail.count(":") == 1 and tail.rpartition(":")[2] and not tail.rpartition(":")[2].isdigit():
        raise ValueError(f"{name}: the port must be an integer from 1 to 65535, got {shown}")
    try:
        host, port = parse_host_port(location, default_port=DEFAULT_PORT)
    except ValueError:
        raise ValueError(f"{name}: {usage} ([IPv6]:PORT for IPv6), got {shown}") from None
    if not host:
        raise ValueError(f"{name}: {usage}, got {shown} (no host)")
    allowed = _IPV6_CHARACTERS if ":" in host else _HOST_CHARACTERS
    if len(host) > 253 or not set(host) <= allowed:
        raise ValueError(f"{name}: {usage}, got {shown} (HOST: a name or an IP address of at most 253 "
                         "characters, letters, digits, '.', '-', '_')")
    if not 1 <= port <= 65535:
        raise ValueError(f"{name}: the port must be an integer from 1 to 65535, got {shown}")
    return "tcp://" + unparse_host_port(host, port)


def _handshake(address, deadline):
    """Connect to *address* (``tcp://HOST:PORT``), do Dask's handshake and ask for its identity,
    all within *deadline* seconds (one ``asyncio.wait_for`` over a plain TCP connection, which
    tells a refused or unreachable port from a silent one, then ``distributed.comm.connect``
    with its own timeout, the handshake and the reply); None if a scheduler answered, else why
    not (one phrase)."""
    import asyncio
    import concurrent.futures

    from distributed.comm import connect as comm_connect

    from distributed.comm.addressing import parse_host_port

    host, port = parse_host_port(address)
    phase = ["connect"]

    async def talk():
        _, writer = await asyncio.open_connection(host, int(port))
        writer.close()
        phase[0] = "handshake"
        comm = await comm_connect(address, timeout=deadline)
        try:
            phase[0] = "identity"
            await comm.write({"op": "identity", "reply": True})
            return await comm.read()
        finally:
            comm.abort()

    def run():
        return asyncio.run(asyncio.wait_for(talk(), deadline))

    seconds = f"{deadline:g} s"
    with concurrent.futures.ThreadPoolExecutor(1) as pool:  # its own event loop, whatever the caller runs
        try:
            reply = pool.submit(run).result()
        except (asyncio.TimeoutError, TimeoutError):
            if phase[0] == "connect":
                return f"no connection within {seconds} (the host does not answer)"
            return (f"it accepted the connection but did not answer Dask's handshake within {seconds} "
                    "(not a Dask scheduler?)")
        except ConnectionRefusedError:
            return "connection refused (nothing listens on that port)"
        except OSError as err:
            if phase[0] == "connect":
                return f"cannot connect ({type(err).__name__}: {' '.join(str(err).split())[:100]})"
            return "it closed the connection during Dask's handshake (not a Dask scheduler?)"
        except MemoryError:  # a length prefix of junk bytes: distributed allocates what it says
            return "it answered, but not in Dask's protocol (a message header claiming more bytes than memory)"
        except Exception as err:  # noqa: BLE001 - junk on the wire: ValueError, msgpack's errors...
            return f"it answered, but not in Dask's protocol ({type(err).__name__}: {' '.join(str(err).split())[:80]})"
    kind = reply.get("type") if isinstance(reply, dict) else None
    if kind != "Scheduler":
        return f"it is a Dask {kind}, not a scheduler" if isinstance(kind, str) else "its answer is not a Dask scheduler's"
    return None


def connect(scheduler: str, timeout: float = CONNECT_DEADLINE, name="scheduler"):
    """A :class:`distributed.Client` of the running scheduler at *scheduler*
    (:func:`check_scheduler_address`); ValueError (one line, with the address and the reason)
    when no Dask scheduler answers the connection and the handshake within *timeout* seconds
    (:data:`CONNECT_DEADLINE`): a closed port, a silent one, one that answers something else."""
    from distributed import Client

    address = check_scheduler_address(scheduler, name)
    timeout = float(timeout.rstrip("s")) if isinstance(timeout, str) else float(timeout)
    why = _handshake(address, timeout)
    if why is not None:
        raise ValueError(f"cannot reach the Dask scheduler at {address}: {why}")
    try:
        return Client(address, timeout=f"{timeout}s")
    except Exception as err:  # noqa: BLE001 - it went away between the check and the client
        raise ValueError(f"cannot reach the Dask scheduler at {address}: {type(err).__name__}: "
                         f"{' '.join(str(err).split())[:120]}") from None


def max_workers() -> int:
    """The most local workers ``workers=N`` starts: one single-threaded process per core this
    process may use (:func:`bubbleoptics.resources.usable_cores`); more would only share them."""
    return usable_cores()


def check_cluster_options(client=None, workers=None, scheduler=None, names=None):
    """Check, before any work, that at most one of *client*, *workers* and *scheduler* is given,
    that *workers* is an integer from 1 to :func:`max_workers`, that *scheduler* is an address
    the tracer connects to (:func:`check_scheduler_address`) and that ``distributed`` is
    installed when needed (ValueError naming the option as *names* calls it, e.g. ``--workers``)."""
    names = names or {}
    if sum(x is not None for x in (client, workers, scheduler)) > 1:
        raise ValueError("give at most one of client, workers and scheduler")
    if workers is not None:
        cores = max_workers()
        if isinstance(workers, bool) or not isinstance(workers, int) or not 1 <= workers <= cores:
            raise ValueError(f"{names.get('workers', 'workers')} must be an integer from 1 to {cores} (one "
                             f"single-threaded worker process per core; this machine gives this process {cores}), "
                             f"got {workers!r}")
    if scheduler is not None:
        check_scheduler_address(scheduler, names.get("scheduler", "scheduler"))
    if workers is not None or scheduler is not None:
        try:
            import distributed  # noqa: F401
        except ImportError:
            raise ValueError("rendering on a Dask cluster needs dask.distributed: pip install "
                             "'bubbleoptics[dask]'") from None


@contextlib.contextmanager
def cluster_client(client=None, workers=None, scheduler=None, names=None):
    """A context giving the :class:`distributed.Client` to render on: *client* itself (left
    open), a :func:`local_cluster` of *workers* processes (started and stopped here), the
    scheduler at *scheduler* (:func:`connect`; closed here), or None (render here) when none is
    given."""
    check_cluster_options(client, workers, scheduler, names)
    if client is not None or (workers is None and scheduler is None):
        yield client
        return
    from distributed import Client

    if workers is not None:
        with local_cluster(workers) as cluster, Client(cluster) as c:
            yield c
    else:
        with connect(scheduler, name=(names or {}).get("scheduler", "scheduler")) as c:
            yield c


def worker_numba_cache_stats() -> dict:
    """numba's cache hits and misses (compilations) of the integrator's row kernel in this
    process, and numba's thread count: ``{"hits": n, "misses": m, "threads": t}``.  Run it on
    workers (``client.run``) to check that they loaded the kernels rather than compiling them."""
    import numba

    from ..kernels.integrator import render_rows

    stats = render_rows.stats
    return {"hits": int(sum(stats.cache_hits.values())), "misses": int(sum(stats.cache_misses.values())),
            "threads": int(numba.config.NUMBA_NUM_THREADS)}


def tile_bounds(height: int, n_tiles: int):
    """*height* rows cut into at most *n_tiles* contiguous tiles ``(row0, row1)`` of sizes that
    differ by at most one row."""
    n = max(1, min(int(n_tiles), int(height)))
    edges = np.linspace(0, height, n + 1).round().astype(int)
    return [(int(a), int(b)) for a, b in zip(edges[:-1], edges[1:]) if b > a]


def render_tiles(client, packed, settings: dict, spectral_image=False, progress=False, n_tiles=None):
    """The image of the packed scene *packed* with the resolved *settings*
    (:func:`tracer.rendering.api.resolve_settings`), rendered as tiles of rows on *client*'s cluster:
    ``(image, counts, spectrum)`` as :func:`tracer.rendering.local.render_tile` gives them for the whole
    image, equal to a local render bit for bit.

    The packed scene is sent to the workers once (``client.scatter(..., broadcast=True)``); each
    of *n_tiles* tiles (default :data:`TILES_PER_WORKER` per worker) is one task, retried up to
    three times if its worker is lost.  A progress bar over tiles when *progress*.
    """
    from distributed import as_completed

    from .local import render_tile

    width, height = settings["width"], settings["height"]
    if n_tiles is None:
        n_tiles = TILES_PER_WORKER * max(1, len(client.scheduler_info().get("workers", {})))
    bounds = tile_bounds(height, n_tiles)
    image = np.zeros((height, width, 3))
    counts = np.zeros((height, N_COUNTS), dtype=np.int64)
    spectrum = np.zeros((height, width, packed.rgb_basis.shape[0])) if spectral_image else None
    remote = client.scatter(packed, broadcast=True, hash=False)
    futures = [client.submit(render_tile, remote, settings, a, b, spectral_image, pure=False, retries=3)
               for a, b in bounds]
    where = {f.key: ab for f, ab in zip(futures, bounds)}
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=height, unit="row", desc="render", leave=False, file=sys.stderr)
    try:
        for future, (tile, tile_counts, tile_spectrum) in as_completed(futures, with_results=True):
            a, b = where[future.key]
            image[a:b] = tile
            counts[a:b] = tile_counts
            if spectral_image:
                spectrum[a:b] = tile_spectrum
            if bar is not None:
                bar.update(b - a)
    finally:
        client.cancel([f for f in futures if not f.done()])
        if bar is not None:
            bar.close()
    return image, counts, spectrum
