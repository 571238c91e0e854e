"""tracer: a numba spectral Whitted ray tracer for soap-bubble scenes, built on bubbleoptics.

Units: scene lengths in scene units, film thickness in nm, colours linear sRGB in [0, 1].
``render`` returns linear sRGB radiance as an (H, W, 3) float array.
"""

from .builtin import default_scene
from .errors import SceneError
from .io import load_scene
from .movie import render_movie
from .movie_commands import Frame, Timeline
from .render import DEFAULTS, render, render_with_stats, save_image
from .scene import Bubble, Camera, Environment, FilmProfile, Material, Mesh, PointLight, Scene, Sphere

__all__ = [
    "load_scene",
    "render",
    "render_with_stats",
    "save_image",
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
]
