"""A film-thickness time series h(θ, φ, t): what a simulation gives the renderer.

Stored as one ``.npz`` (NumPy's zip of arrays, loaded without pickle): ``h_nm`` (n_times,
n_theta, n_phi) float32 thickness in nm, ``times`` (n_times,) in s, ``theta`` and ``phi``
(the cell centres, radians), ``radius`` (m), ``model`` (its name) and ``parameters`` (a JSON
string: the physical parameters in SI units and the run's dt, seed and grid).

:meth:`ThicknessSeries.load` reads such a file defensively: the archive's members and every
array's ``.npy`` header (NumPy's own reader, :mod:`numpy.lib.format`) are checked first (the
keys, shapes, dtypes, the decompressed size against :data:`MAX_SERIES_BYTES` and the memory
available), then the thickness is decompressed one frame at a time, each frame checked (finite,
>= 0) as it arrives.  Any problem, a damaged archive included, is one ``ValueError`` line
``FILE:KEY: what is wrong``.
"""

import json
import math
import os
import struct
import zipfile
import zlib

import numpy as np

from ..atomic import write_atomically
from ..resources import available_memory_bytes, gib
from .grid import MAX_THETA, MIN_THETA, FilmGrid

__all__ = ["ThicknessSeries", "SeriesFileError", "MAX_SERIES_BYTES", "MAX_TIMES"]

FORMAT = "bubbleoptics.filmflow.ThicknessSeries/1"

#: The largest thickness array a series file may hold, decompressed to float32: 2 GiB, sixteen
#: frames of the largest grid (4096 x 8192).  A scene keeps its series in memory, and a file is
#: refused before it is decompressed when it would need more than this or than the memory
#: available.
MAX_SERIES_BYTES = 2**31
#: The most stored times a series file may hold.
MAX_TIMES = 1_000_000
#: The longest text each text member may hold, in characters.
_TEXT_LIMITS = {"format": 200, "model": 200, "parameters": 1_000_000}
#: Bytes decompressed at a time while a frame is read.
_READ_CHUNK = 1 << 22
#: The members a series file holds (each NAME.npy in the zip archive).
_MEMBERS = ("format", "h_nm", "times", "theta", "phi", "radius", "model", "parameters")
#: What can go wrong reading a damaged archive or .npy member (zipfile, zlib, numpy's header reader).
_READ_ERRORS = (zipfile.BadZipFile, zipfile.LargeZipFile, zlib.error, EOFError, OSError, ValueError, KeyError,
                NotImplementedError, RuntimeError, struct.error, SyntaxError, OverflowError)


class SeriesFileError(ValueError):
    """A file that is not a readable ThicknessSeries: one line, ``FILE:KEY: what is wrong``."""


def _short(exc):
    text = " ".join(str(exc).split()) or type(exc).__name__
    return f"{type(exc).__name__}: {text[:120]}{'...' if len(text) > 120 else ''}"


def _check_values(h, where):
    """ValueError unless every value of *h* is finite and >= 0 (frame by frame: no temporary
    of the whole array)."""
    for i in range(h.shape[0]):
        frame = h[i]
        if not np.isfinite(frame).all() or frame.min() < 0:
            raise ValueError(f"{where} must be finite and >= 0 (frame {i} is not)")


class ThicknessSeries:
    """Film thickness on a :class:`FilmGrid` at a sequence of times.

    Attributes: ``h_nm`` (n_times, n_theta, n_phi) float32, nm; ``times`` (n_times,) float64, s,
    strictly increasing; ``grid``; ``parameters`` (dict); ``model`` (str).

    >>> import numpy as np
    >>> from bubbleoptics.filmflow import FilmGrid, ThicknessSeries
    >>> g = FilmGrid(4, 8, 0.04)
    >>> s = ThicknessSeries(np.stack([np.full((4, 8), 900.0), np.full((4, 8), 700.0)]), [0.0, 2.0], g, {}, "demo")
    >>> float(s.thickness_at(0.5)[0, 0]), float(s.thickness_at(99.0)[0, 0])  # linear, then clamped
    (850.0, 700.0)
    """

    def __init__(self, h_nm, times, grid, parameters, model):
        with np.errstate(over="ignore"):  # a float64 beyond float32 becomes inf: refused below
            h = np.ascontiguousarray(h_nm, dtype=np.float32)
        t = np.asarray(times, dtype=float)
        if not isinstance(grid, FilmGrid):
            raise ValueError(f"grid must be a FilmGrid (got {type(grid).__name__})")
        if h.ndim != 3 or h.shape[1:] != (grid.n_theta, grid.n_phi) or h.shape[0] < 1:
            raise ValueError(f"h_nm must have shape (n_times >= 1, {grid.n_theta}, {grid.n_phi}) (got {h.shape})")
        if t.shape != (h.shape[0],):
            raise ValueError(f"times must have shape ({h.shape[0]},) to match h_nm (got {t.shape})")
        if not (np.all(np.isfinite(t)) and np.all(np.diff(t) > 0)):
            raise ValueError("times must be finite and strictly increasing")
        _check_values(h, "h_nm")
        self.h_nm = h
        self.times = t
        self.grid = grid
        self.parameters = dict(parameters)
        self.model = str(model)

    def __len__(self):
        return len(self.times)

    def __repr__(self):
        return (f"ThicknessSeries(model={self.model!r}, {len(self)} times {self.times[0]:g}..{self.times[-1]:g} s, "
                f"grid {self.grid.n_theta}x{self.grid.n_phi})")

    def thickness_at(self, t):
        """Thickness (n_theta, n_phi) in nm at time *t* (s): linear in time between the stored
        times, clamped to the first and last.  float64."""
        if isinstance(t, bool) or not isinstance(t, (int, float, np.floating, np.integer)) or not math.isfinite(t):
            raise ValueError(f"t must be a finite number of seconds (got {t!r})")
        times = self.times
        if t <= times[0]:
            return self.h_nm[0].astype(float)
        if t >= times[-1]:
            return self.h_nm[-1].astype(float)
        i = int(np.searchsorted(times, t, side="right")) - 1
        w = (t - times[i]) / (times[i + 1] - times[i])
        out = self.h_nm[i].astype(float)  # (1 - w) h_i + w h_{i+1} in place: two frames of float64
        later = self.h_nm[i + 1].astype(float)
        out *= 1.0 - w
        later *= w
        out += later
        return out

    def node_map_at(self, t):
        """The thickness at time *t* on the n_theta + 1 face latitudes θ_i = iπ/n_theta (poles
        included) and the n_phi cell azimuths φ_k = 2πk/n_phi: the layout of the tracer's film
        maps (rows evenly spaced from the top, θ = 0, to the bottom).  Interior rows are the mean
        of the two neighbouring cell rows, a pole row the mean of its ring.  nm, float64."""
        h = self.thickness_at(t)
        out = np.empty((h.shape[0] + 1, h.shape[1]))
        out[1:-1] = 0.5 * (h[:-1] + h[1:])
        out[0] = h[0].mean()
        out[-1] = h[-1].mean()
        return out

    def save(self, path):
        """Write the series to *path* (``.npz``) atomically; returns *path*."""
        def write(tmp):
            with open(tmp, "wb") as f:
                np.savez_compressed(
                    f, format=np.array(FORMAT), h_nm=self.h_nm, times=self.times, theta=self.grid.theta,
                    phi=self.grid.phi, radius=np.array(self.grid.radius), model=np.array(self.model),
                    parameters=np.array(json.dumps(self.parameters, sort_keys=True)))

        return write_atomically(path, write)

    @classmethod
    def load(cls, path):
        """Read a series written by :meth:`save`.  Everything is checked before the thickness is
        decompressed (see the module docstring); a file that is not a series, or a damaged one,
        raises :class:`SeriesFileError` (a ValueError), one line naming the file and the key."""
        shown = os.fspath(path)
        try:
            archive = zipfile.ZipFile(shown)
        except (zipfile.BadZipFile, zipfile.LargeZipFile, EOFError, ValueError, NotImplementedError) as exc:
            raise SeriesFileError(f"{shown}: is not a ThicknessSeries file (format {FORMAT}): not a readable "
                                  f".npz archive ({_short(exc)})") from None
        with archive:
            return _load(cls, archive, shown)


def _header(archive, info, shown, key):
    """``(shape, fortran_order, dtype, offset)`` of the .npy member *info*: NumPy's own header
    reader, on the first bytes of the member only."""
    try:
        with archive.open(info) as f:
            version = np.lib.format.read_magic(f)
            if version == (1, 0):
                shape, fortran, dtype = np.lib.format.read_array_header_1_0(f)
            elif version == (2, 0):
                shape, fortran, dtype = np.lib.format.read_array_header_2_0(f)
            else:
                raise ValueError(f".npy format version {version[0]}.{version[1]} (1.0 or 2.0 expected)")
            return shape, fortran, dtype, f.tell()
    except _READ_ERRORS as exc:
        raise SeriesFileError(f"{shown}:{key}: cannot read its array header ({_short(exc)})") from None


def _load(cls, archive, shown):
    members = {}
    for info in archive.infolist():
        if info.filename.endswith(".npy"):
            members.setdefault(info.filename[:-4], info)
    missing = [k for k in _MEMBERS if k not in members]
    if missing:
        raise SeriesFileError(f"{shown}: is not a ThicknessSeries file (format {FORMAT}): it lacks "
                              f"{', '.join(missing)}")
    heads = {k: _header(archive, members[k], shown, k) for k in _MEMBERS}

    def bad(key, what):
        return SeriesFileError(f"{shown}:{key}: {what}")

    for key, limit in _TEXT_LIMITS.items():
        shape, _, dtype, _ = heads[key]
        if shape != () or dtype.kind != "U" or dtype.itemsize > 4 * limit:
            raise bad(key, f"must be one text of at most {limit:,} characters (got dtype {dtype.str}, shape {shape})")
    for key in ("times", "theta", "phi", "radius"):
        shape, _, dtype, _ = heads[key]
        if dtype.kind not in "fiu" or dtype.itemsize > 8:
            raise bad(key, f"must hold real numbers (got dtype {dtype.str})")
    shape, fortran, dtype, _ = heads["h_nm"]
    if dtype.kind != "f" or dtype.itemsize not in (4, 8):
        raise bad("h_nm", f"must be float32 or float64 nanometres (got dtype {dtype.str})")
    if len(shape) != 3:
        raise bad("h_nm", f"must be a 3-D array (n_times, n_theta, n_phi) (got shape {shape})")
    n_times, nt, nph = shape
    if not 1 <= n_times <= MAX_TIMES:
        raise bad("h_nm", f"must hold 1 to {MAX_TIMES:,} times (got {n_times:,})")
    for name, n, hi in (("n_theta", nt, MAX_THETA), ("n_phi", nph, 2 * MAX_THETA)):
        if not MIN_THETA <= n <= hi:
            raise bad("h_nm", f"{name} must be in [{MIN_THETA}, {hi}] (got shape {shape})")
    need = n_times * nt * nph * 4
    if need > MAX_SERIES_BYTES:
        raise bad("h_nm", f"{n_times} x {nt} x {nph} values are {gib(need)} as float32, more than the "
                          f"{gib(MAX_SERIES_BYTES)} a series file may hold (bubbleoptics.filmflow.series.MAX_SERIES_BYTES)")
    have = available_memory_bytes()
    if have is not None and need > have:
        raise bad("h_nm", f"{n_times} x {nt} x {nph} values need {gib(need)} as float32, more than the "
                          f"{gib(have)} of memory available")
    for key, want in (("times", (n_times,)), ("theta", (nt,)), ("phi", (nph,)), ("radius", ())):
        if heads[key][0] != want:
            raise bad(key, f"must have shape {want} to match h_nm {shape} (got {heads[key][0]})")
    for key in _MEMBERS:  # the declared decompressed size is the header and exactly its data
        shp, _, dt_, offset = heads[key]
        size = offset + math.prod(shp) * dt_.itemsize
        if members[key].file_size != size:
            raise bad(key, f"the archive says {members[key].file_size:,} bytes where its header needs {size:,} "
                           "(a truncated or altered file)")

    def small(key):
        try:
            with archive.open(members[key]) as f:
                return np.lib.format.read_array(f, allow_pickle=False)
        except _READ_ERRORS as exc:
            raise bad(key, f"cannot read it ({_short(exc)})") from None

    if str(small("format")) != FORMAT:
        raise SeriesFileError(f"{shown} is not a ThicknessSeries file (format {FORMAT})")
    text = {k: str(small(k)) for k in ("model", "parameters")}
    try:
        parameters = json.loads(text["parameters"])
    except (ValueError, RecursionError) as exc:
        raise bad("parameters", f"must be a JSON object ({_short(exc)})") from None
    if not isinstance(parameters, dict):
        raise bad("parameters", f"must be a JSON object (got a {type(parameters).__name__})")
    times = small("times").astype(float)
    if not (np.isfinite(times).all() and np.all(np.diff(times) > 0)):
        raise bad("times", "must be finite and strictly increasing (seconds)")
    try:
        grid = FilmGrid(nt, nph, float(small("radius")))
    except ValueError as exc:
        raise bad("radius", str(exc)) from None
    if not (np.allclose(small("theta"), grid.theta, rtol=0, atol=1e-12)
            and np.allclose(small("phi"), grid.phi, rtol=0, atol=1e-12)):
        raise SeriesFileError(f"{shown}: theta/phi are not the cell centres of a {nt}x{nph} grid")
    h = _read_thickness(archive, members["h_nm"], heads["h_nm"], bad)
    series = cls.__new__(cls)  # every check of __init__ is done
    series.h_nm, series.times, series.grid = h, times, grid
    series.parameters, series.model = parameters, text["model"]
    return series


def _read_thickness(archive, info, head, bad):
    """The member h_nm as a C float32 array, decompressed and checked one frame at a time."""
    shape, fortran, dtype, offset = head
    out = np.empty(shape, dtype=np.float32)
    try:
        with archive.open(info) as f:
            f.read(offset)
            if fortran:  # column-major: not frame by frame (the size is bounded above)
                data = np.frombuffer(f.read(math.prod(shape) * dtype.itemsize), dtype=dtype)
                with np.errstate(over="ignore"):
                    out[...] = data.reshape(shape, order="F")
                _check_values(out, "h_nm")
                return out
            buf = bytearray(shape[1] * shape[2] * dtype.itemsize)
            view = memoryview(buf)
            for i in range(shape[0]):
                for a in range(0, len(buf), _READ_CHUNK):  # zipfile's read copies what it returns: small pieces
                    piece = view[a:a + _READ_CHUNK]
                    if f.readinto(piece) != len(piece):
                        raise EOFError(f"the data ends in frame {i}")
                with np.errstate(over="ignore"):  # beyond float32: inf, refused just below
                    out[i] = np.frombuffer(buf, dtype=dtype).reshape(shape[1:])
                if not np.isfinite(out[i]).all() or out[i].min() < 0:
                    raise ValueError(f"must be finite and >= 0 nanometres (frame {i} is not)")
            f.read(1)  # the end of the member: zipfile checks its CRC-32 here
    except _READ_ERRORS as exc:
        if isinstance(exc, ValueError) and str(exc).startswith("must be finite"):
            raise bad("h_nm", str(exc)) from None
        raise bad("h_nm", f"cannot read it ({_short(exc)})") from None
    return out
