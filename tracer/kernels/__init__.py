"""The kernels: numba code that traces rays through packed scenes (nothing here reads a file or
knows a :class:`tracer.scene.Scene`).

* :mod:`.records` -- the packed scene's arrays and record layouts (what every kernel reads);
* :mod:`.integrator` -- transport only: camera rays, the ray tree, shadows, counts;
* :mod:`.surfaces` -- one module per surface model (:mod:`.surfaces.soap_film`, :mod:`.surfaces.phong`);
* :mod:`.geometry` (intersections), :mod:`.sampling` (camera rays, random numbers),
  :mod:`.environment` (the background), :mod:`.thickness` (a film's thickness at a point);
* the numba options every kernel is compiled with are :mod:`bubbleoptics.jit`'s.
"""
