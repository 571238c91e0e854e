"""The scene editor: the coursework's Qt window, in a notebook and in the browser.

``tracer.editor(scene)`` returns the Panel app for a notebook cell; ``tracer edit [SCENE]``
serves it as a page (``docs/editor.md``).  :mod:`tracer.editor.model` is the scene and its
edits without widgets, :mod:`tracer.editor.preview` the progressive, cancellable preview and
the film spectrum at a picked pixel, :mod:`tracer.editor.app` the Panel app (Panel is an
optional extra: ``pip install bubbleoptics[editor]``).
"""

import sys
import types

from .model import EditorModel, FieldError

__all__ = ["editor", "EditorModel", "FieldError", "serve"]


def editor(scene=None, **kwargs):
    """The scene editor's Panel app for *scene* (a :class:`tracer.Scene`, a scene file's path,
    or None: the built-in scene); display it in a notebook cell, or ``.servable()`` it."""
    from .app import EditorApp

    return EditorApp(scene, **kwargs).layout


def serve(scene=None, **kwargs):
    """Serve the editor (:func:`tracer.editor.app.serve`)."""
    from .app import serve as _serve

    return _serve(scene, **kwargs)


class _EditorModule(types.ModuleType):
    """``tracer.editor`` is this package and, called, :func:`editor`."""

    def __call__(self, scene=None, **kwargs):
        return editor(scene, **kwargs)


sys.modules[__name__].__class__ = _EditorModule
