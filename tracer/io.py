"""Load a scene file of either format: ``load_scene(path)``.

``.toml`` files are the native format (:mod:`tracer.toml_scene`); anything else is read as the
coursework's text format (:mod:`tracer.coursework_format`).  Both raise :class:`SceneError`,
whose text is ``FILE:LINE: what is wrong``.  Writing and converting: :mod:`tracer.toml_writer`,
:mod:`tracer.coursework_convert`.
"""

from __future__ import annotations

import os

from .coursework_convert import coursework_to_toml
from .coursework_format import load_coursework_scene
from .errors import SceneError, SceneWarning
from .file_access import ANYWHERE, FileAccess
from .scene import Scene
from .toml_scene import load_toml_scene
from .toml_writer import save_toml_scene, scene_to_toml_text

__all__ = [
    "load_scene",
    "load_coursework_scene",
    "load_toml_scene",
    "save_toml_scene",
    "scene_to_toml_text",
    "coursework_to_toml",
    "SceneError",
    "SceneWarning",
]


def load_scene(path, access: FileAccess = ANYWHERE) -> Scene:
    """Read a scene: ``.toml`` (any case) as TOML, any other name as the coursework's text format.

    *access* (:class:`tracer.file_access.FileAccess`) says which files the scene and the files
    it names may be: anywhere by default; the scene editor confines them to its root folder."""
    path = os.fspath(path)
    if os.path.splitext(path)[1].lower() == ".toml":
        return load_toml_scene(path, access)
    return load_coursework_scene(path, access)
