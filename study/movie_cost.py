"""The cost model of a long movie on a Dask cluster (``benchmarks/movie.py``, the paper's
section on movies): what a 4K, 64-spp, one-minute movie would take on many workers, from the
costs the benchmark measures on this machine.  A model, not a measurement.
"""

from __future__ import annotations

import math

__all__ = ["MODEL_MOVIE", "model_movie_seconds"]

#: The movie of the scaling model (``benchmarks/movie.py``, the paper's section on movies): a
#: 3840x2160, 64-spp, one-minute movie at 24 frames a second.
MODEL_MOVIE = dict(width=3840, height=2160, spp=64, frames=24 * 60)


def model_movie_seconds(workers, frame_cpu_seconds, overhead_seconds, startup_seconds, encode_seconds_per_frame,
                        measured_pixels, model=MODEL_MOVIE):
    """``(wall seconds, seconds a frame, rounds, encoder seconds)`` of *model* on *workers* one-core workers.

    A cost model, not a measurement: a frame costs the measured one-thread CPU time of a
    *measured_pixels*-pixel, one-sample frame scaled by pixels x samples (camera rays dominate),
    plus the measured Dask overhead a frame; workers render whole frames in
    ``ceil(frames / workers)`` rounds; the cluster starts once; one encoder runs at the end at
    the measured speed (*encode_seconds_per_frame*) scaled by pixels.

    >>> seconds, frame, rounds, encode = model_movie_seconds(512, 0.27, 0.008, 1.5, 0.016, 480 * 480)
    >>> rounds
    3
    """
    scale = model["width"] * model["height"] * model["spp"] / measured_pixels
    frame = frame_cpu_seconds * scale
    encode = encode_seconds_per_frame * model["width"] * model["height"] / measured_pixels * model["frames"]
    rounds = math.ceil(model["frames"] / workers)
    return rounds * (frame + overhead_seconds) + startup_seconds + encode, frame, rounds, encode
