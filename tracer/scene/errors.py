"""Errors and warnings raised while reading scene files.

Every problem found in a scene file is reported as ``FILE:LINE: what is wrong`` (or
``FILE: what is wrong`` when no single line is to blame, e.g. an unreadable file), so that a
person can jump straight to it and a program can parse it like a compiler message.
"""

from __future__ import annotations

import os

__all__ = ["SceneError", "SceneWarning"]


class SceneError(ValueError):
    """A scene file that cannot be read, or that describes an impossible scene.

    Attributes:
        path: the file, as given to the loader (a string).
        line: the 1-based line the problem was found on, or ``None``.
        message: what is wrong, without the location prefix.
    """

    def __init__(self, path: str | os.PathLike, line: int | None, message: str):
        self.path = os.fspath(path)
        self.line = None if line is None else int(line)
        self.message = str(message)
        super().__init__(str(self))

    def __str__(self) -> str:
        if self.line is None:
            return f"{self.path}: {self.message}"
        return f"{self.path}:{self.line}: {self.message}"

    def __reduce__(self):  # keep pickling (multiprocessing) working with three arguments
        return (type(self), (self.path, self.line, self.message))


class SceneWarning(UserWarning):
    """Something in a scene file that was skipped rather than refused (a zero-area face)."""
