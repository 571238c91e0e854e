"""tracer: a numba spectral Whitted ray tracer for soap-bubble scenes, built on bubbleoptics.

Units: scene lengths in scene units, film thickness in nm, colours linear sRGB in [0, 1].
``render`` returns linear sRGB radiance as an (H, W, 3) float array (values may be negative and
above 1: see its docstring); ``save_image`` writes it (:mod:`tracer.rendering.output`).
The layers, bottom to top: :mod:`tracer.kernels`, :mod:`tracer.scene`, :mod:`tracer.prepare`,
:mod:`tracer.rendering`, :mod:`tracer.movie`, then :mod:`tracer.cli` and :mod:`tracer.editor`
(docs/architecture.md).
"""

from .movie import Frame, Timeline, render_movie
from .rendering import (DEFAULTS, SpectralImage, check_output_path, load_spectral, render, render_spectral,
                        render_with_stats, save_image, save_spectral)
from .scene import (Bubble, Camera, Environment, FilmProfile, Material, Mesh, PointLight, Scene, SceneError,
                    Sphere, default_scene, load_scene)

__all__ = [
    "load_scene",
    "render",
    "render_with_stats",
    "render_spectral",
    "save_image",
    "save_spectral",
    "load_spectral",
    "check_output_path",
    "SpectralImage",
    "render_movie",
    "Timeline",
    "Frame",
    "default_scene",
    "DEFAULTS",
    "SceneError",
    "Scene",
    "Sphere",
    "Bubble",
    "FilmProfile",
    "Mesh",
    "Material",
    "PointLight",
    "Camera",
    "Environment",
    "editor",
]


def __getattr__(name):
    # the scene editor, imported when first used (it needs the optional Panel only when called)
    if name == "editor":
        import importlib

        return importlib.import_module(".editor", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
