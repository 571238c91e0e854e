"""The rendering layer: a scene to an image.

* :mod:`.api` -- the Python API (:func:`render`, :func:`render_with_stats`, :func:`render_spectral`),
  its settings (:data:`DEFAULTS`, :func:`resolve_settings`);
* :mod:`.local` -- rendering on this machine's threads, in short cancellable calls;
* :mod:`.dask` -- rendering as tiles of rows on a Dask cluster;
* :mod:`.output` -- images and spectral images to files (PNG, EXR, HDR, NPY, NPZ), display views.
"""

from .api import DEFAULTS, RenderStats, render, render_spectral, render_with_stats, resolve_settings
from .local import PARALLEL_LOCK, RenderCancelled, render_in_parts, render_tile
from .output import SpectralImage, check_output_path, load_spectral, save_image, save_spectral

__all__ = ["render", "render_with_stats", "render_spectral", "resolve_settings", "DEFAULTS", "RenderStats",
           "RenderCancelled", "render_in_parts", "render_tile", "PARALLEL_LOCK", "save_image", "save_spectral",
           "load_spectral", "check_output_path", "SpectralImage"]
