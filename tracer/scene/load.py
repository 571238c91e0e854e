"""Load a scene file of either format: ``load_scene(path)``.

``.toml`` files are the native format (:mod:`tracer.scene.toml_read`); anything else is read as the
coursework's text format (:mod:`tracer.scene.block_format`).  Both raise :class:`SceneError`,
whose text is ``FILE:LINE: what is wrong``.  Writing and converting: :mod:`tracer.scene.toml_write`,
:mod:`tracer.scene.convert`.
"""

from __future__ import annotations

import os

from .convert import coursework_to_toml
from .block_format import load_coursework_scene
from .errors import SceneError, SceneWarning
from .file_access import ANYWHERE, FileAccess
from .model import Scene
from .toml_read import load_toml_scene
from .toml_write import save_toml_scene, scene_to_toml_text

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

    *access* (:class:`tracer.scene.file_access.FileAccess`) says which files the scene and the files
    it names may be: anywhere by default; the scene editor confines them to its root folder."""
    path = os.fspath(path)
    if os.path.splitext(path)[1].lower() == ".toml":
        return load_toml_scene(path, access)
    return load_coursework_scene(path, access)
