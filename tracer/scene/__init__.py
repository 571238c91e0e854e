"""The scene layer: what a scene is and how it is read, written and checked.

* :mod:`.model` -- the scene's objects (:class:`Scene`, :class:`Sphere`, :class:`Bubble`, ...);
* :mod:`.load` -- :func:`load_scene`, either format; :mod:`.toml_read` and :mod:`.toml_write` the
  native TOML format, :mod:`.block_format` the coursework's text format (blocks of lines),
  :mod:`.convert` the one into the other;
* :mod:`.text` reads a scene file's text; :mod:`.assets` the files a scene names (environment
  images, meshes, film maps and series); :mod:`.file_access` confines both to a folder;
* :mod:`.simulated` turns simulated films into film maps; :mod:`.builtin` the built-in scene;
* :mod:`.errors` (``FILE:LINE: what is wrong``) and :mod:`.limits` (the allowed ranges).

Nothing here renders: the layers above pack a scene (:mod:`tracer.prepare`) and trace it
(:mod:`tracer.kernels`, :mod:`tracer.rendering`).
"""

from .builtin import default_scene
from .errors import SceneError, SceneWarning
from .load import load_scene
from .model import (COURSEWORK_NM_PER_UNIT, LIGHT_FALLOFFS, MAX_LIGHT_SAMPLES, Bubble, Camera, Environment,
                    FilmProfile, Material, Mesh, PointLight, Scene, Sphere)

__all__ = ["Scene", "Sphere", "Bubble", "FilmProfile", "Mesh", "Material", "PointLight", "Camera", "Environment",
           "LIGHT_FALLOFFS", "MAX_LIGHT_SAMPLES", "COURSEWORK_NM_PER_UNIT", "load_scene", "default_scene",
           "SceneError", "SceneWarning"]
