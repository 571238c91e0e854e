"""The movie layer: a scene and its changes over time into frames and a movie file.

* :mod:`.commands` -- the movie commands file (the coursework's ``-film`` mode) into a :class:`Timeline`;
* :mod:`.timeline` -- :class:`Timeline`: the scene at each frame;
* :mod:`.frames` -- :class:`Frame` and its cache key;
* :mod:`.run` -- :func:`render_movie`: frames here or on a Dask cluster, cached, encoded.
"""

from .run import (DEFAULT_FPS, MovieResult, check_movie_output, check_spectral_output, movie_cache_folder,
                  render_frame_files, render_frame_png, render_movie)
from .frames import Frame
from .timeline import Timeline

__all__ = ["render_movie", "render_frame_files", "render_frame_png", "check_movie_output", "check_spectral_output",
           "movie_cache_folder", "MovieResult", "DEFAULT_FPS", "Timeline", "Frame"]
