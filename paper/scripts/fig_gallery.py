"""Figure: a gallery of renders, the coursework's three functional scenes and three realistic bubbles.

Run:  python paper/scripts/fig_gallery.py [--quick]
Renders scene files from ``data/scenes/`` with ``tracer``; writes ``fig_gallery.pdf``/``.png``.

Top row, the coursework's functional tests (its figures 3.3-3.5, rebuilt from their captions
in the coursework's text format, seen by its default camera): (a) a purple sphere hidden behind
a pink one, seen in a mirror-like tetrahedron; (b) recursive reflection between a sphere and a
tetrahedron, and a transparent sphere the tetrahedron shows through, both against the
coursework's black background; (c) a soap bubble (a uniform 500 nm film) above glass, metal and
matte spheres, under the procedural sky instead (``under_sky``): a bubble only reflects and
transmits what surrounds it, so against black it would be invisible but for its highlight.
Bottom row, the native TOML scenes under the procedural sky: (d) six bubbles of different sizes
and ages (``gallery_bubbles.toml``); (e) one bubble with a young draining film, 420-1400 nm
with swirls, and (f) the same bubble old, 4-380 nm, a black film at its top
(``gallery_one_bubble.toml`` with its film replaced). Linear sRGB clipped to [0, 1] and
sRGB-encoded, no other tone mapping.  Full mode (``FULL``): 480 x 480 pixels, 4 samples per
pixel; quick mode (``QUICK``): 96 x 96, 1 sample.
"""

import dataclasses
import sys
import time

import colour
import numpy as np

import paths
import style
import tracer

SCENES = paths.DATA / "scenes"
MATERIALS_SCENE = "fig3_5_materials.txt"  # panel (c): the coursework's bubble and three materials
FULL = (480, 4)  # pixels per side, samples per pixel
QUICK = (96, 1)

#: The two ages of the bubble in panels (e) and (f): draining films, thicknesses in nm.
YOUNG = dict(top_nm=420.0, bottom_nm=1400.0, swirl=0.35)
OLD = dict(top_nm=4.0, bottom_nm=380.0, swirl=0.20)


def with_film(scene, **film):
    """The scene with its (only) bubble's draining film replaced by *film*."""
    (bubble,) = scene.bubbles
    new = dataclasses.replace(bubble, film=dataclasses.replace(bubble.film, kind="draining", **film))
    return dataclasses.replace(scene, bubbles=[new])


def under_sky(scene):
    """The scene under the procedural sky, upright for its camera (the coursework's frame has y
    pointing down, so the sky's up is the camera's)."""
    return dataclasses.replace(scene, environment=tracer.Environment(kind="sky", up=scene.camera.up))


def panels():
    """(title, scene) for the six panels, in reading order."""
    def load(name):
        return tracer.load_scene(SCENES / name)

    one = load("gallery_one_bubble.toml")
    return [
        ("(a) coursework fig. 3.3: a hidden sphere in a mirror", load("fig3_3_hidden_sphere_reflected.txt")),
        ("(b) coursework fig. 3.4: recursive reflection", load("fig3_4_recursive_reflection.txt")),
        ("(c) coursework fig. 3.5 under a sky: a bubble", under_sky(load(MATERIALS_SCENE))),
        ("(d) six bubbles of different ages", load("gallery_bubbles.toml")),
        (f"(e) a young film, {YOUNG['top_nm']:g}-{YOUNG['bottom_nm']:g} nm", with_film(one, **YOUNG)),
        ("(f) an old film: black at the top", with_film(one, **OLD)),
    ]


def main(argv=None):
    args = paths.parse_args(__doc__.splitlines()[0], argv)
    size, spp = QUICK if args.quick else FULL

    fig = style.figure(width=style.PAGE_WIDTH, height=5.0)
    axes = fig.subplots(2, 3)
    t0 = time.perf_counter()
    for ax, (title, scene) in zip(axes.ravel(), panels()):
        image = tracer.render(scene, width=size, height=size, spp=spp, progress=False)
        if not np.all(np.isfinite(image)):
            raise RuntimeError(f"{title}: the render has non-finite pixels")
        shown = colour.cctf_encoding(np.clip(image, 0.0, 1.0), function="sRGB")
        ax.imshow(shown, interpolation="nearest" if args.quick else "antialiased")
        ax.set_title(title, fontsize=7, pad=2)
        ax.set_axis_off()
    print(f"six renders, {size} x {size} pixels, {spp} sample(s) per pixel: {time.perf_counter() - t0:.1f} s")
    for path in style.savefig(fig, "fig_gallery"):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
