"""The preparation layer: a :class:`tracer.scene.Scene` into the arrays the kernels read.

* :mod:`.pack` -- :func:`pack_scene`, the scene as a :class:`tracer.kernels.records.PackedScene`
  (the channels, spectra and film tables included);
* :mod:`.meshes` -- triangle meshes: orientation, normals, records;
* :mod:`.bvh` -- the bounding-volume hierarchy over a scene's triangles.
"""
