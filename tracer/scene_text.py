"""A scene file's text: the reading step both scene formats share.

:func:`read_scene_text` reads the file's bytes and decodes them as UTF-8, refusing with a
:class:`~tracer.errors.SceneError` what cannot be read or is not text (a missing file, a
directory, a NUL byte, bytes that are not UTF-8), with the line to blame where there is one.
"""

from __future__ import annotations

from .errors import SceneError

__all__ = ["read_scene_text", "decode_scene_bytes"]


def read_scene_text(path: str) -> str:
    """The file's text, refusing what cannot be read or is not UTF-8 text (SceneError)."""
    try:
        with open(path, "rb") as fh:
            data = fh.read()
    except FileNotFoundError:
        raise SceneError(path, None, "no such file") from None
    except IsADirectoryError:
        raise SceneError(path, None, "is a directory, not a scene file") from None
    except OSError as exc:
        raise SceneError(path, None, f"cannot read the file: {exc.strerror or exc}") from None
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
