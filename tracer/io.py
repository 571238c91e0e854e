"""Load a scene file of either format: ``load_scene(path)``.

``.toml`` files are the native format (:mod:`tracer.tomlformat`); anything else is read as the
seed coursework's text format (:mod:`tracer.seedformat`).  Both raise :class:`SceneError`,
whose text is ``FILE:LINE: what is wrong``.
"""

from __future__ import annotations

import os

from .errors import SceneError, SceneWarning
from .scene import Scene
from .seedformat import load_seed_scene
from .tomlformat import load_toml_scene, save_toml_scene, scene_to_toml_text, seed_to_toml

__all__ = [
    "load_scene",
    "load_seed_scene",
    "load_toml_scene",
    "save_toml_scene",
    "scene_to_toml_text",
    "seed_to_toml",
    "SceneError",
    "SceneWarning",
]


def load_scene(path) -> Scene:
    """Read a scene: ``.toml`` (any case) as TOML, any other name as the seed's text format."""
    path = os.fspath(path)
    if os.path.splitext(path)[1].lower() == ".toml":
        return load_toml_scene(path)
    return load_seed_scene(path)
