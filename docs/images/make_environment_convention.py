"""Draw docs/images/environment_convention.png: how an equirectangular image wraps the scene.

Run:  python docs/images/make_environment_convention.py

Top: a labelled latitude-longitude test image (columns u, rows v) as the file holds it.
Bottom: the tracer looking from the origin along -z (up +y, 100 degrees wide) at that image
as its environment, with a mirror sphere below the horizon: the labels read as they are
written (the image is not mirrored) and the view shows u = 0 straight ahead, +x to the right.
The convention is Mitsuba 3's (tracer.kernels.environment.environment_rgb; checked against Mitsuba in
tests/tracer/test_environment.py).
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from bubbleoptics.colorimetry import srgb_to_linear_srgb  # noqa: E402
from tracer import Camera, Environment, Material, Scene, Sphere, render  # noqa: E402

HERE = Path(__file__).resolve().parent
H, W = 512, 1024
LABELS = [(0.0, "u = 0\n-z (ahead)"), (0.25, "u = 1/4\n+x"), (0.5, "u = 1/2\n+z (behind)"),
          (0.75, "u = 3/4\n-x"), (1.0, "u = 1\n-z")]


def test_image():
    """The labelled panorama, linear RGB (H, W, 3), drawn with matplotlib."""
    fig = plt.figure(figsize=(W / 100, H / 100), dpi=100)
    ax = fig.add_axes([0, 0, 1, 1])
    u, v = np.meshgrid((np.arange(W) + 0.5) / W, (np.arange(H) + 0.5) / H)
    colours = np.stack([0.35 + 0.5 * u, 0.35 + 0.3 * (1 - v), 0.9 - 0.5 * u], axis=-1)
    ax.imshow(colours, extent=(0, 1, 1, 0), aspect="auto")
    for k in range(9):
        ax.axvline(k / 8, color="white", lw=0.8)
    for k in range(5):
        ax.axhline(k / 4, color="white", lw=0.8)
    for x, text in LABELS:
        ax.text(min(max(x, 0.085), 0.915), 0.42, text, ha="center", va="center", fontsize=18, color="black")
    ax.text(0.5, 0.08, "v = 0: zenith (+y)", ha="center", fontsize=16)
    ax.text(0.5, 0.94, "v = 1: nadir (-y)", ha="center", fontsize=16)
    ax.set_xlim(0, 1)
    ax.set_ylim(1, 0)
    ax.axis("off")
    fig.canvas.draw()
    rgba = np.asarray(fig.canvas.buffer_rgba())[..., :3] / 255.0
    plt.close(fig)
    return srgb_to_linear_srgb(rgba)


def main():
    image = test_image()
    scene = Scene(
        spheres=[Sphere(center=(0.0, -0.75, -2.0), radius=0.5,
                        material=Material(color=(1, 1, 1), ambient=0, diffuse=0, specular=1.0))],
        environment=Environment(kind="image", image=image),
        camera=Camera(position=(0, 0, 0), look_at=(0, 0, -1), up=(0, 1, 0), fov_deg=60.0),
        ambient=(0, 0, 0),
    )
    view = render(scene, width=800, height=330, spp=4, progress=False)
    fig, axes = plt.subplots(2, 1, figsize=(7.0, 6.6), gridspec_kw=dict(height_ratios=[1, 0.8]))
    axes[0].imshow(np.clip(image, 0, 1) ** (1 / 2.2), extent=(0, 1, 1, 0), aspect="auto")
    axes[0].set_title("(a) the image file: u across, v down", fontsize=10)
    axes[0].set_xticks([0, 0.25, 0.5, 0.75, 1])
    axes[0].set_yticks([0, 0.5, 1])
    axes[1].imshow(np.clip(view, 0, 1) ** (1 / 2.2))
    axes[1].set_title("(b) the tracer looking along -z, up +y, with a mirror sphere: not mirrored", fontsize=10)
    axes[1].axis("off")
    fig.tight_layout()
    out = HERE / "environment_convention.png"
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    main()
