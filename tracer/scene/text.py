"""A scene file's text: the reading step both scene formats share.

:func:`read_scene_text` reads the file's bytes and decodes them as UTF-8, refusing with a
:class:`~tracer.scene.errors.SceneError` what cannot be read or is not text (a missing file, a
directory, a NUL byte, bytes that are not UTF-8), with the line to blame where there is one.
"""

from __future__ import annotations

from .errors import SceneError
from .file_access import ANYWHERE, FileAccess, FileAccessError

__all__ = ["read_scene_text", "decode_scene_bytes"]


def read_scene_text(path: str, access: FileAccess = ANYWHERE) -> str:
    """The file's text, refusing what cannot be read or is not UTF-8 text (SceneError), and
    what *access* (:class:`tracer.scene.file_access.FileAccess`) does not allow: a path outside its
    root, a file that is not a regular file (a pipe or a device is never opened for reading in
    a way that could block), a file over its size limit."""
    try:
        data = access.read_bytes(access.resolve(path), shown=path, scene=True)
    except FileAccessError as exc:
        raise SceneError(path, None, exc.reason) from None
    return decode_scene_bytes(path, data)


def decode_scene_bytes(path: str, data: bytes) -> str:
    """Decode UTF-8 (an initial byte-order mark is dropped); NUL bytes mean a binary file."""
    nul = data.find(b"\x00")
    if nul >= 0:
        raise SceneError(path, data.count(b"\n", 0, nul) + 1,
                         "binary data (a NUL byte): this is not a text scene file")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise SceneError(
            path, data.count(b"\n", 0, exc.start) + 1,
            f"not UTF-8 text (byte 0x{data[exc.start]:02x} at offset {exc.start} cannot be decoded);"
            " scene files must be UTF-8",
        ) from None
    return text[1:] if text.startswith("\ufeff") else text
