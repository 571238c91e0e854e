"""Render the soft-shadow example of docs/scene-format.md into docs/images/soft_shadow.png.

Run:  python docs/images/make_soft_shadow.py [--quick]

The scene is the TOML block under the heading "Example: a soft shadow" of
docs/scene-format.md, read from that page, so the picture always shows the documented scene.
Two panels: the same scene with the light's radius set to 0 (a point light: hard shadows) on
the left, the scene as written (a spherical light: soft shadows) on the right, at the settings
of its [render] table.  ``--quick`` renders a quarter of the size at one sample per pixel
(for tests).
"""

import argparse
import dataclasses
from pathlib import Path

import numpy as np

import tracer
from tracer.scene.toml_read import parse_toml_text

HERE = Path(__file__).resolve().parent
DOC = HERE.parent / "scene-format.md"
HEADING = "### Example: a soft shadow"


def example_toml(doc_path=DOC) -> str:
    """The TOML block of the soft-shadow example in docs/scene-format.md."""
    text = Path(doc_path).read_text(encoding="utf-8")
    section = text.split(HEADING, 1)[1]
    return section.split("```toml\n", 1)[1].split("```", 1)[0]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a quarter of the size, 1 sample per pixel")
    parser.add_argument("--out", type=Path, default=HERE / "soft_shadow.png")
    args = parser.parse_args(argv)

    scene = parse_toml_text(example_toml(), DOC)
    settings = dict(scene.render_defaults)
    if args.quick:
        settings.update(width=settings["width"] // 4, height=settings["height"] // 4, spp=1)
    point = dataclasses.replace(scene, lights=[dataclasses.replace(lt, radius=0.0) for lt in scene.lights])
    panels = [tracer.render(s, progress=False, **settings) for s in (point, scene)]
    gap = np.ones((settings["height"], max(1, settings["width"] // 90), 3))
    tracer.save_image(np.concatenate([panels[0], gap, panels[1]], axis=1), args.out)

    from PIL import Image, ImageDraw

    img = Image.open(args.out).convert("RGB")
    draw = ImageDraw.Draw(img)
    radius = scene.lights[0].radius
    for x, label in ((0, "radius = 0 (a point)"), (settings["width"] + gap.shape[1], f"radius = {radius:g} m")):
        draw.text((x + 6, 4), label, fill=(255, 255, 255))
    img.save(args.out, format="PNG", compress_level=9)
    print(args.out)


if __name__ == "__main__":
    main()
