"""Which files a scene may read, and how much of them: :class:`FileAccess`.

A scene file names other files (environment images, thickness maps, simulated films, meshes).
From the command line a scene may name any file its user can read, and :data:`ANYWHERE` says
so.  A server that reads scene files for other people (the scene editor, ``tracer edit``) must
not: it gives a :class:`FileAccess` with a *root* folder, and then every path, the scene file's
own and each one it names, is resolved (``Path.resolve()``: ``..`` and every symbolic link
followed) and refused unless the result lies inside the root.  A refused path gets the same
message whether or not it exists outside the root, so that the messages cannot be used to probe
the disk.

Only regular files are read (a FIFO, a device such as ``/dev/zero`` or a directory is refused
before it is opened, and the file is opened non-blocking so that a FIFO swapped in at the last
moment cannot hang the reader), and at most *max_bytes* of each; an image asset may have at most
*max_pixels* pixels, read from its header before it is decoded.

>>> import tempfile, pathlib
>>> root = pathlib.Path(tempfile.mkdtemp())
>>> access = FileAccess(root)
>>> access.resolve("../etc/passwd")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
tracer.scene.file_access.FileAccessError: ../etc/passwd: outside the folder ... (every path must resolve inside it)
"""

from __future__ import annotations

import errno
import os
import stat
import tempfile
import unicodedata
from dataclasses import dataclass
from pathlib import Path
from bubbleoptics.messages import shorten

__all__ = ["FileAccess", "FileAccessError", "ANYWHERE", "check_name", "MAX_NAME_LENGTH"]

#: The longest object name a scene may give (characters).
MAX_NAME_LENGTH = 200


class FileAccessError(ValueError):
    """A path that may not be read or written: ``str(err)`` is ``"PATH: why"``, with the path as
    it was given (``err.path``) and the reason alone (``err.reason``)."""

    def __init__(self, path, reason):
        self.path, self.reason = _show(path), reason
        super().__init__(f"{self.path}: {reason}" if self.path else reason)


def _show(text) -> str:
    text = str(text)
    text = "".join(c if unicodedata.category(c)[0] != "C" else "?" for c in text)
    return shorten(text, 120)


def check_name(name, what="name") -> str:
    """*name* (an object's name, a file name) if it is text of at most :data:`MAX_NAME_LENGTH`
    characters with no control or format character and no line or paragraph separator (a
    newline in a name would start a new line of a commands file, U+2028 would in an editor that
    shows it; a bidirectional override would make it read as something else), else
    :class:`ValueError` saying so."""
    if not isinstance(name, str):
        raise ValueError(f"{what} must be a string, got {type(name).__name__}")
    if len(name) > MAX_NAME_LENGTH:
        raise ValueError(f"{what} has {len(name)} characters, at most {MAX_NAME_LENGTH} are allowed")
    bad = next((c for c in name if unicodedata.category(c) in ("Cc", "Cf", "Cs", "Zl", "Zp")), None)
    if bad is not None:
        raise ValueError(f"{what} {_show(name)!r} has a control character (U+{ord(bad):04X}): names are"
                         " printable text")
    return name


@dataclass(frozen=True)
class FileAccess:
    """Where files may be read and written, and how much of a file may be read.

    *root*: None (anywhere the user can read) or a folder (resolved when this is made): every
    path must resolve inside it.  *max_bytes*: the largest file read (None: no limit).
    *max_pixels*: the most pixels an image asset may have (None: no limit).  *max_scene_bytes*:
    the largest scene file (its text is parsed whole; None: *max_bytes*).
    """

    root: Path | None = None
    max_bytes: int | None = None
    max_pixels: int | None = None
    max_scene_bytes: int | None = None

    def __post_init__(self):
        if self.root is not None:
            root = Path(self.root).expanduser().resolve()
            if not root.is_dir():
                raise FileAccessError(self.root, "not a folder")
            object.__setattr__(self, "root", root)

    @property
    def confined(self) -> bool:
        return self.root is not None

    def resolve(self, text, base=None) -> Path:
        """The path *text* (relative to *base*, else to the root, else to the working folder)
        resolved, and, when confined, refused unless inside the root.  The file need not exist."""
        raw = os.fspath(text)
        if "\x00" in raw:
            raise FileAccessError(raw, "a path has no NUL character")
        if not raw.strip():
            raise FileAccessError("", "give a file name")
        path = Path(raw)
        if self.root is not None and raw.startswith("~"):
            raise FileAccessError(raw, f"a path under a home folder (~) is not allowed here: give one inside"
                                       f" {self.root}")
        if not path.is_absolute():
            path = Path(base if base is not None else (self.root or Path.cwd())) / path
        try:
            full = path.resolve()
        except (OSError, RuntimeError) as exc:  # a symbolic link loop
            raise FileAccessError(raw, f"cannot resolve the path ({exc})") from None
        if self.root is not None and not full.is_relative_to(self.root):
            raise FileAccessError(raw, f"outside the folder {self.root} (every path must resolve inside it)")
        return full

    def relative(self, path: Path) -> str:
        """*path* as the person should see it: relative to the root when confined."""
        if self.root is not None:
            try:
                return str(Path(path).relative_to(self.root))
            except ValueError:
                pass
        return str(path)

    def check_file(self, full: Path, shown=None) -> int:
        """The size of the regular file *full* (resolved), or :class:`FileAccessError` if it is
        missing, not a regular file, or larger than *max_bytes*."""
        shown = shown if shown is not None else full
        try:
            st = os.stat(full)
        except FileNotFoundError:
            raise FileAccessError(shown, "no such file") from None
        except OSError as exc:
            raise FileAccessError(shown, f"cannot read the file ({exc.strerror or exc})") from None
        return self._check_stat(st, shown)

    def _check_stat(self, st, shown, limit=None) -> int:
        limit = self.max_bytes if limit is None else limit
        if stat.S_ISDIR(st.st_mode):
            raise FileAccessError(shown, "is a directory, not a file")
        if not stat.S_ISREG(st.st_mode):
            raise FileAccessError(shown, "not a regular file (a device, pipe or socket is never read)")
        if limit is not None and st.st_size > limit:
            raise FileAccessError(shown, f"{st.st_size:,} bytes, more than the {limit:,} allowed here")
        return st.st_size

    def read_bytes(self, full: Path, shown=None, scene=False) -> bytes:
        """The bytes of the regular file *full* (resolved), at most *max_bytes* (a *scene*
        file: *max_scene_bytes*): opened non-blocking and checked on the open file (not only by
        name) before it is read."""
        limit = self.max_scene_bytes if scene and self.max_scene_bytes is not None else self.max_bytes
        shown = shown if shown is not None else full
        flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0)
        try:
            fd = os.open(full, flags)
        except FileNotFoundError:
            raise FileAccessError(shown, "no such file") from None
        except IsADirectoryError:
            raise FileAccessError(shown, "is a directory, not a file") from None
        except OSError as exc:
            raise FileAccessError(shown, f"cannot read the file ({exc.strerror or exc})") from None
        try:
            size = self._check_stat(os.fstat(fd), shown, limit)
            chunks, left = [], (size if limit is None else min(size, limit)) + 1  # a file that grew is refused
            while left > 0:
                try:
                    chunk = os.read(fd, min(left, 1 << 20))
                except OSError as exc:
                    if exc.errno in (errno.EAGAIN, errno.EWOULDBLOCK):
                        raise FileAccessError(shown, "not a regular file") from None
                    raise FileAccessError(shown, f"cannot read the file ({exc.strerror or exc})") from None
                if not chunk:
                    break
                chunks.append(chunk)
                left -= len(chunk)
            data = b"".join(chunks)
            if limit is not None and len(data) > limit:
                raise FileAccessError(shown, f"more than the {limit:,} bytes allowed here")
            return data
        finally:
            os.close(fd)

    def save_new(self, text, suffixes, make_files, *, attempts=1000):
        """Write new files, never over an existing one: ``(path, renamed)``.

        *text* is the file name asked for (resolved as :meth:`resolve` does; its folder must
        exist; its suffix one of *suffixes*).  ``make_files(stem)`` returns ``{name: bytes}``,
        the files to write into that folder for the stem ``stem`` (the main one is
        ``stem + suffix``; a scene's arrays go beside it).  If any of them exists, the stem
        becomes ``stem-2``, ``stem-3``, ... (*renamed* is then True).  Each file is written to
        a temporary file and linked to its name (``os.link`` fails if the name exists, so a
        name taken meanwhile is never overwritten); a failure removes what it wrote.
        """
        raw = Path(os.fspath(text))
        if raw.name in ("", ".", ".."):
            raise FileAccessError(text, "give a file name")
        # the folder resolved (and confined); the name itself taken as it is, never followed:
        # a symbolic link of that name counts as a file that exists
        full = self.resolve(raw.parent if str(raw.parent) else ".") / raw.name
        suffix = full.suffix.lower()
        if suffix not in suffixes:
            want = " or ".join(suffixes)
            raise FileAccessError(text, f"give a name ending in {want}")
        try:
            check_name(full.name, "the file name")
        except ValueError as exc:
            raise FileAccessError(text, str(exc)) from None
        folder = full.parent
        if not folder.is_dir():
            raise FileAccessError(text, f"no folder {self.relative(folder)!r} to write into")
        stem = full.name[: -len(full.suffix)]
        for k in range(1, attempts + 1):
            candidate = stem if k == 1 else f"{stem}-{k}"
            files = make_files(candidate)
            if any(os.path.lexists(folder / name) for name in files):
                continue
            written = []
            try:
                for name, data in files.items():
                    fd, tmp = tempfile.mkstemp(prefix=f".{name}.", suffix=".tmp", dir=folder)
                    try:
                        with os.fdopen(fd, "wb") as fh:
                            fh.write(data)
                        os.chmod(tmp, 0o666 & ~_umask())
                        os.link(tmp, folder / name)  # FileExistsError if the name was taken meanwhile
                        written.append(folder / name)
                    finally:
                        os.unlink(tmp)
            except FileExistsError:
                for p in written:
                    os.unlink(p)
                continue
            except OSError as exc:
                for p in written:
                    os.unlink(p)
                raise FileAccessError(text, f"cannot write the file ({exc.strerror or exc})") from None
            return folder / f"{candidate}{full.suffix}", k > 1
        raise FileAccessError(text, f"{attempts} names like it are taken: give another name")

    def check_pixels(self, width, height, shown) -> None:
        """Refuse an image of *width* x *height* pixels beyond *max_pixels*."""
        if self.max_pixels is not None and int(width) * int(height) > self.max_pixels:
            raise FileAccessError(shown, f"an image of {int(width)} x {int(height)} pixels, more than the"
                                  f" {self.max_pixels:,} pixels allowed here")


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


#: No root, no size limits: what a scene file read from the command line may do.
ANYWHERE = FileAccess()
