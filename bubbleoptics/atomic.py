"""Write a file all at once: into a temporary file in the same folder, then rename it over the target.

A reader never sees a half-written file, and a failed write leaves the old file (or nothing)
and no temporary file behind.  ``os.replace`` is atomic within one file system, which is why
the temporary file is made in the target's own folder.
"""

import os
import tempfile

__all__ = ["write_atomically"]


def write_atomically(path, write):
    """Call ``write(tmp)`` with the name of a new temporary file beside *path*, then rename it to *path*.

    *write* writes the whole content to the file named ``tmp`` (a string).  The file gets the
    usual mode for a new file (``0o666`` less the umask; ``mkstemp`` would leave it private).
    Returns *path* as given.

    >>> import pathlib, tempfile
    >>> target = pathlib.Path(tempfile.mkdtemp()) / "note.txt"
    >>> _ = write_atomically(target, lambda tmp: pathlib.Path(tmp).write_text("all or nothing"))
    >>> target.read_text(), sorted(p.name for p in target.parent.iterdir())
    ('all or nothing', ['note.txt'])
    """
    folder, name = os.path.split(os.path.abspath(os.fspath(path)))
    fd, tmp = tempfile.mkstemp(prefix=f".{name}.", suffix=".tmp", dir=folder)
    os.close(fd)
    try:
        write(tmp)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, os.path.join(folder, name))
    except BaseException as exc:
        if os.path.exists(tmp):
            os.unlink(tmp)
        if isinstance(exc, OSError) and exc.filename == tmp:
            # name the file the caller asked for, not the temporary one
            raise OSError(exc.errno, f"cannot write {path}: {exc.strerror}") from None
        raise
    return path
