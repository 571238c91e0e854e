"""A movie's commands file: its verbs and fields, read line by line into a
:class:`tracer.movie.timeline.Timeline`.

The coursework's ``-film`` mode changed the scene between frames by the commands of a text
file. The file, one command a line (``docs/movies.md`` has the full format and an example)::

    # the coursework's scene: a bubble drifts right while the camera turns
    render 12                      # 12 frames of the scene as loaded
    move "пузырь 1" 200 0 0        # objects by name (quoted when they contain spaces)
    camera orbit 15
    render 24                      # both changes spread linearly over 24 frames

``render K`` renders K frames; every change written since the previous ``render`` is spread
linearly over them (frame k of K shows k/K of it; ``render 1`` jumps). The verbs:
``move NAME dx dy dz``, ``scale NAME k``, ``rotate NAME ax ay az degrees``,
``set NAME FIELD VALUE...``, ``light N x y z intensity``, ``light add x y z intensity``,
``light delete N``, ``camera position|look_at x y z``, ``camera orbit degrees``,
``camera fov degrees``, ``time SECONDS``.

:class:`Timeline` is the same vocabulary as Python methods (a notebook builds one without a
file); :meth:`Timeline.from_file` and :meth:`Timeline.from_text` call those methods line by line
and report every problem as :class:`CommandsError`, ``COMMANDS:LINE: what is wrong``.
:meth:`Timeline.frames` resolves the timeline into one self-contained :class:`Frame` per
image (the scene as it is then, and the render settings), which any process can render alone.
"""

from __future__ import annotations

import difflib
import shlex

from ..scene.block_format import LineReader
from ..scene.errors import SceneError
from ..scene.limits import MAX_INDEX, MAX_MAGNITUDE

__all__ = ["COMMANDS", "PHONG_FIELDS", "BUBBLE_FIELDS", "SWITCH_FIELDS", "FILM_KIND_FIELDS", "FIELD_ALIASES",
           "CommandsError", "tokens", "dispatch"]


#: The verbs of the commands file, with what follows them.
COMMANDS = {
    "render": "K",
    "move": "NAME dx dy dz",
    "scale": "NAME k",
    "rotate": "NAME axis_x axis_y axis_z degrees",
    "set": "NAME FIELD VALUE...",
    "light": "N x y z intensity | add x y z intensity | delete N",
    "camera": "position x y z | look_at x y z | orbit degrees | fov degrees",
    "time": "SECONDS",
}

# field: (number of values, lowest, highest, lowest excluded); names as the TOML format's
#: Fields ``set`` changes on a sphere or a mesh (its Phong material).
PHONG_FIELDS = {
    "color": (3, 0.0, 1.0, False),
    "ambient": (1, 0.0, 1.0, False),
    "diffuse": (1, 0.0, 1.0, False),
    "specular": (1, 0.0, 1.0, False),
    "transmission": (1, 0.0, 1.0, False),
    "shininess": (1, 0.0, MAX_MAGNITUDE, False),
    "ior": (1, 0.0, MAX_INDEX, True),
}
#: Fields ``set`` changes on a bubble: its highlight exponent and its film's profile parameters.
BUBBLE_FIELDS = {
    "shininess": (1, 0.0, MAX_MAGNITUDE, False),
    "thickness_nm": (1, 0.0, MAX_MAGNITUDE, False),
    "top_nm": (1, 0.0, MAX_MAGNITUDE, False),
    "bottom_nm": (1, 0.0, MAX_MAGNITUDE, False),
    "exponent": (1, 0.0, MAX_MAGNITUDE, True),
    "swirl": (1, 0.0, 1.0, False),
    "swirl_scale": (1, 0.0, MAX_MAGNITUDE, True),
}
#: The film fields of ``set`` that each film kind uses (the scene editor shows these).
FILM_KIND_FIELDS = {
    "uniform": ("thickness_nm", "swirl", "swirl_scale"),
    "draining": ("top_nm", "bottom_nm", "exponent", "swirl", "swirl_scale"),
    "map": ("swirl", "swirl_scale"),
}
#: Fields ``set`` switches on a bubble (not numbers that can move in a straight line): they take
#: their new value at the last frame of the next ``render``.  ``profile``: ``uniform`` or
#: ``draining`` (a ``map`` needs its table, from a scene file); ``n_film``: ``water`` or a
#: constant real index in (0, MAX_INDEX].
SWITCH_FIELDS = {"profile": ("uniform", "draining"), "n_film": ("water", "a number > 0 and <= 100")}
#: Other names ``set`` accepts for a field.
FIELD_ALIASES = {"colour": "color", "thickness": "thickness_nm", "top": "top_nm", "bottom": "bottom_nm"}


class CommandsError(SceneError):
    """A problem in a commands file: ``COMMANDS:LINE: what is wrong`` (a SceneError, so the
    command line reports it the same way)."""


# ------------------------------------------------------------------------------------------
# the text format
# ------------------------------------------------------------------------------------------
def tokens(line):
    """The fields of one line: blank-separated, double or single quotes around a name with
    spaces, ``#`` to the end of the line a comment (outside quotes)."""
    lexer = shlex.shlex(line, posix=True)
    lexer.whitespace_split = True
    lexer.commenters = "#"
    try:
        return list(lexer)
    except ValueError as err:  # shlex: "No closing quotation", "No escaped character"
        raise ValueError(f"{str(err).lower()} in '{line.strip()[:60]}'") from None


def dispatch(tl, r: LineReader, line, tokens):
    """Run the command of *tokens* (line *line*, read by *r*) on the timeline *tl*."""
    verb, args = tokens[0], tokens[1:]

    def numbers(fields, names, what):
        return r.numbers(line, fields, names, f"{verb}: {what}")

    def arity(n, usage):
        if len(args) != n:
            raise ValueError(f"expected '{verb} {usage}', found {len(args)} field{'s' if len(args) != 1 else ''} "
                             f"after '{verb}'")

    if verb == "render":
        arity(1, COMMANDS["render"])
        k = r.integer(line, args[0], "render: the frame count")
        tl.render(k)
    elif verb in ("move", "scale", "rotate"):
        names = {"move": ("dx", "dy", "dz"), "scale": ("k",), "rotate": ("axis_x", "axis_y", "axis_z", "degrees")}
        arity(1 + len(names[verb]), COMMANDS[verb])
        name = args[0]
        tl._ref(name)  # an unknown name before its numbers
        values = numbers(args[1:], names[verb], f"'{name}'")
        getattr(tl, verb)(name, *values)
    elif verb == "set":
        if len(args) < 3:
            raise ValueError(f"expected 'set {COMMANDS['set']}', found {len(args)} field(s) after 'set'")
        name, f = args[0], args[1]
        tl._ref(name)
        if f in SWITCH_FIELDS:  # words, not numbers
            values = args[2:]
        else:
            values = [r.number(line, tok, f"set: '{name}' {f}") for tok in args[2:]]
        tl.set(name, f, *values)
    elif verb == "light":
        if not args:
            raise ValueError(f"expected 'light {COMMANDS['light']}'")
        if args[0] == "add":
            args = args[1:]
            verb = "light add"
            arity(4, "x y z intensity")
            tl.light_add(*numbers(args, ("x", "y", "z", "intensity"), "the new light"))
        elif args[0] == "delete":
            args = args[1:]
            verb = "light delete"
            arity(1, "N")
            tl.light_delete(r.integer(line, args[0], "light delete: the light's number"))
        else:
            n = r.integer(line, args[0], "light: the light's number (or 'add', 'delete')")
            args = args[1:]
            verb = f"light {n}"
            arity(4, "x y z intensity")
            tl.light(n, *numbers(args, ("x", "y", "z", "intensity"), "the light"))
    elif verb == "camera":
        what = args[0] if args else ""
        forms = {"position": ("x", "y", "z"), "look_at": ("x", "y", "z"), "orbit": ("degrees",),
                 "fov": ("degrees",)}
        if what not in forms:
            raise ValueError(f"expected 'camera {COMMANDS['camera']}', found "
                             + (f"'camera {what}'" if what else "nothing after 'camera'"))
        args = args[1:]
        verb = f"camera {what}"
        arity(len(forms[what]), " ".join(forms[what]))
        values = numbers(args, forms[what], what)
        {"position": tl.camera_position, "look_at": tl.camera_look_at, "orbit": tl.camera_orbit,
         "fov": tl.camera_fov}[what](*values)
    elif verb == "time":
        arity(1, COMMANDS["time"])
        tl.time(*numbers(args, ("seconds",), "the seconds"))
    else:
        close = difflib.get_close_matches(verb, list(COMMANDS), n=1)
        hint = f"did you mean '{close[0]}'? " if close else ""
        raise ValueError(f"unknown command; {hint}(commands: {', '.join(COMMANDS)})")
