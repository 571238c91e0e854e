"""The settings of Fig. gallery, a plug-in of ``make_numbers.py``.

* ``gallery``: ``fig_gallery.py`` and the scenes it renders (``data/scenes/``).
"""

from __future__ import annotations

from macros import plain

#: where these macros stand in numbers.tex (make_numbers.py)
ORDER = 14


def gallery(dirs):
    """The settings of Fig. gallery, from ``fig_gallery.py`` and the scene it renders in panel (c)."""
    import fig_gallery
    import tracer

    size, spp = fig_gallery.FULL
    out = {"GallerySize": str(size), "GallerySpp": str(spp)}
    for age, film in (("Young", fig_gallery.YOUNG), ("Old", fig_gallery.OLD)):
        out[f"Gallery{age}TopNm"] = plain(film["top_nm"])
        out[f"Gallery{age}BottomNm"] = plain(film["bottom_nm"])
    out["GalleryYoungTopUm"] = plain(fig_gallery.YOUNG["top_nm"] / 1000)
    out["GalleryYoungBottomUm"] = plain(fig_gallery.YOUNG["bottom_nm"] / 1000)
    (bubble,) = tracer.load_scene(fig_gallery.SCENES / fig_gallery.MATERIALS_SCENE).bubbles
    out["GalleryMaterialsFilmNm"] = plain(bubble.film.thickness_nm)
    (bubble, *_) = tracer.load_scene(fig_gallery.SCENES / "coursework_one_bubble.txt").bubbles
    out["CourseworkFilmNm"] = plain(bubble.film.thickness_nm)  # its listing 3.2's radii, read as micrometres
    return out


GALLERY_MACROS = ["GallerySize", "GallerySpp", "GalleryYoungTopNm", "GalleryYoungBottomNm", "GalleryOldTopNm",
                  "GalleryOldBottomNm", "GalleryYoungTopUm", "GalleryYoungBottomUm", "GalleryMaterialsFilmNm",
                  "CourseworkFilmNm"]

SECTIONS = {
    "gallery": (["paper/scripts/fig_gallery.py", "data/scenes/"], gallery, GALLERY_MACROS),
}
