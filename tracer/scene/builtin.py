"""The built-in scene: soap bubbles of different sizes and ages under a daylight sky."""

from .model import Bubble, Camera, Environment, FilmProfile, PointLight, Scene

__all__ = ["default_scene"]


def default_scene():
    """Three bubbles (radii 0.6, 0.42, 0.25 m) with draining films at different stages.

    The youngest (largest) is still thick at the bottom and swirling; the oldest (smallest) has
    thinned to first-order colours.  Film profiles follow the drainage law of
    :class:`tracer.scene.FilmProfile`; thicknesses in nm, lengths in metres.
    """
    sun = (0.45, 0.55, 0.7)
    return Scene(
        bubbles=[
            Bubble((-0.55, 0.05, 0.0), 0.6, FilmProfile("draining", top_nm=180.0, bottom_nm=950.0, swirl=0.35,
                                                         swirl_scale=9.0, seed=1), name="young"),
            Bubble((0.62, 0.32, -0.4), 0.42, FilmProfile("draining", top_nm=90.0, bottom_nm=650.0, swirl=0.25,
                                                          swirl_scale=7.0, seed=2), name="middle-aged"),
            Bubble((0.3, -0.5, 0.7), 0.25, FilmProfile("draining", top_nm=25.0, bottom_nm=380.0, swirl=0.12,
                                                        seed=3), name="old"),
        ],
        lights=[PointLight(position=(4.5, 5.5, 7.0), intensity=2.0)],
        camera=Camera(position=(0.0, 1.6, 4.0), look_at=(0.05, -0.05, 0.0), up=(0.0, 1.0, 0.0), fov_deg=38.0),
        environment=Environment(kind="sky", sun_direction=sun),
        ambient=(0.0, 0.0, 0.0),
        source="<built-in bubble scene>",
    )
