"""Command line: ``tracer image``, ``tracer research`` (the coursework's -image and -research modes).

Bad input (a malformed scene, an unwritable output, a bad option) prints one line on stderr,
``FILE:LINE: what is wrong`` for scene errors, and exits with status 2; no traceback, and no
output file is written (images are written atomically).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import warnings
from pathlib import Path

__all__ = ["main"]

EXIT_BAD_INPUT = 2


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, status 2 (argparse's own convention too)
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {message}\n")


def _rgb(text):
    parts = text.split(",")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected R,G,B numbers, got {text!r}") from None
    if len(values) != 3 or not all(v >= 0 and v < float("inf") for v in values):
        raise argparse.ArgumentTypeError(f"expected three finite non-negative numbers R,G,B, got {text!r}")
    return tuple(values)


def _setting_type(key):
    """An argparse type for the limited render setting *key* (:mod:`tracer.scene.limits`): ASCII
    decimal text (``1e3`` is accepted for an integer setting when integral), within the limits."""
    from .scene.limits import LimitError, check_setting, describe

    def parse(text):
        value = None
        if text.isascii():
            for convert in ((float,) if key == "threshold" else (int, float)):
                try:
                    value = convert(text)
                    break
                except (ValueError, OverflowError):
                    continue
        try:
            return check_setting(key, text if value is None else value)
        except LimitError:
            from bubbleoptics.messages import shorten

            shown = shorten(text)
            raise argparse.ArgumentTypeError(f"must be {describe(key)}, got {shown!r}") from None

    return parse


def _exposure(text):
    """An argparse type: a number of stops within :data:`tracer.scene.limits.MAX_EXPOSURE`."""
    from .scene.limits import MAX_EXPOSURE

    try:
        value = float(text) if text.isascii() else None
    except ValueError:
        value = None
    if value is None or not -MAX_EXPOSURE <= value <= MAX_EXPOSURE:
        from bubbleoptics.messages import shorten

        shown = shorten(text)
        raise argparse.ArgumentTypeError(f"expected a number of stops in [{-MAX_EXPOSURE:g}, {MAX_EXPOSURE:g}], "
                                         f"got {shown!r}")
    return value


#: Options whose default comes from a TOML scene's [render] table when it has one, else DEFAULTS.
_SCENE_DEFAULTED = ("width", "height", "spp", "threshold", "spectral_samples", "seed", "spectral_method", "depth")
#: What the command line calls each render setting, in error messages.
_OPTION_NAMES = {k: "--" + k.replace("_", "-") for k in _SCENE_DEFAULTED}


def _add_render_options(p, movie=False):
    # default None means "not given": resolved after the scene is read (_resolve_settings)
    from .scene.limits import LIMITS, MAX_EXHAUSTIVE_DEPTH, SPECTRAL_METHODS

    def span(key):
        return f"{LIMITS[key][0]}-{LIMITS[key][1]}"

    p.add_argument("--width", type=_setting_type("width"), help=f"image width in pixels ({span('width')})")
    p.add_argument("--height", type=_setting_type("height"), help=f"image height in pixels ({span('height')})")
    p.add_argument("--spp", type=_setting_type("spp"), help=f"samples per pixel, stratified ({span('spp')})")
    p.add_argument("--threshold", type=_setting_type("threshold"),
                   help="prune child rays whose throughput is at most this (0: the coursework's exhaustive tree, "
                        f"depth at most {MAX_EXHAUSTIVE_DEPTH})")
    p.add_argument("--spectral-samples", type=_setting_type("spectral_samples"),
                   help=f"wavelength bands for spectral transport, scenes with bubbles ({span('spectral_samples')})")
    p.add_argument("--spectral-method", choices=SPECTRAL_METHODS,
                   help="bubble films at the band centres (point), averaged over each band (band), or "
                        "band only where a film is thick enough to alias (auto, the default)")
    p.add_argument("--seed", type=_setting_type("seed"), help="random seed for sample positions (0 to 2^63-1)")
    p.add_argument("--background", type=_rgb, default=None, metavar="R,G,B",
                   help="replace the environment by this constant linear-RGB colour")
    p.add_argument("--bits", type=int, choices=(8, 16, 32), default=None,
                   help="bits per channel: .png 8 (default) or 16; .exr 32 (float, default) or 16 (half)")
    p.add_argument("--exposure", type=_exposure, metavar="STOPS",
                   help="display exposure of a .png: the image times 2**STOPS (default 0)")
    p.add_argument("--view", choices=("clip", "aces"),
                   help="display view of a .png: clip each channel to [0, 1] (clip, the default) or "
                        "the ACES 2.0 filmic view (aces; needs opencolorio)")
    if movie:
        p.add_argument("--spectral-out", metavar="FOLDER",
                       help="also save each frame's per-band spectral image, FOLDER/0000.npz, ... (forces "
                            "spectral transport)")
    else:
        p.add_argument("--spectral-out", metavar="FILE.npz",
                       help="also save the per-band spectral image with its wavelengths (forces spectral "
                            "transport)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")


def _version():
    """The installed distribution's version (pyproject.toml's, the one source; bubbleoptics.__version__
    reads the same), without importing the package: the parser is built before anything heavy."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("bubbleoptics")
    except PackageNotFoundError:  # a source tree that is not installed
        return "0+unknown"


def build_parser():
    from .scene.limits import LIMITS
    from .rendering.api import DEFAULTS

    epilog = ("Render options not given take their value from a TOML scene's [render] table, else the "
              f"defaults: {', '.join(f'{k}={v}' for k, v in DEFAULTS.items())}.")
    parser = _Parser(prog="tracer", description="A spectral Whitted ray tracer for soap-bubble scenes.",
                     epilog=epilog)
    parser.add_argument("--version", action="version", version=f"%(prog)s (bubbleoptics) {_version()}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    img = sub.add_parser("image", help="render a scene to an image (.png; linear float .npy, .exr, .hdr; "
                                       "the spectral image .npz)",
                         description="Render SCENE (or the built-in bubble scene) to OUT.", epilog=epilog)
    img.add_argument("paths", nargs="+", metavar="[SCENE] OUT",
                     help="scene file (TOML or the coursework's text format; the built-in scene when left out) "
                          "and output image (.png, or .npy linear float)")
    img.add_argument("--depth", type=_setting_type("depth"),
                     help=f"maximum ray generation, 1 = camera rays only ({LIMITS['depth'][0]}-{LIMITS['depth'][1]})")
    _add_render_options(img)
    _add_cluster_options(img, "the image as tiles of rows")
    res = sub.add_parser("research", help="render at a trace depth and report the time and ray counts",
                         description="Render SCENE to OUT at trace depth DEPTH; print the render time "
                                     "(compilation excluded) and the rays traced by kind.", epilog=epilog)
    res.add_argument("scene", metavar="SCENE", help="scene file: TOML (.toml) or the coursework's text format")
    res.add_argument("out", metavar="OUT", help="output image (.png, or .npy linear float)")
    res.add_argument("depth", type=_setting_type("depth"), metavar="DEPTH",
                     help=f"trace depth, the coursework's: maximum ray generation ({LIMITS['depth'][0]}-"
                          f"{LIMITS['depth'][1]})")
    res.add_argument("--json", action="store_true", help="print one JSON object")
    _add_render_options(res)
    _add_movie_commands(sub, epilog)
    wu = sub.add_parser("warmup", help="compile the renderer ahead, for these scenes' features (clusters, CI images)",
                        description="Compile, into numba's on-disk cache, the renderer each SCENE needs (its "
                                    "features: meshes, spherical lights, films, Phong materials, films beyond the "
                                    "lossless Airy film), so that the first render of such a scene starts at once.",
                        epilog=epilog)
    wu.add_argument("scenes", nargs="*", metavar="SCENE",
                    help="scene files (TOML or the coursework's text format; default: the built-in scene)")
    wu.add_argument("--all", action="store_true",
                    help="also the renderer with every feature (what TRACER_FEATURES=all renders every scene with)")
    wu.add_argument("--spectral", action="store_true",
                    help="also the variants that keep a per-band image (--spectral-out, .npz outputs)")
    ed = sub.add_parser("edit", help="the scene editor in the browser (needs the editor extra: panel)",
                        description="Serve the scene editor for SCENE (or the built-in bubble scene) at "
                                    "http://ADDRESS:PORT/ until Ctrl-C or SIGTERM (docs/editor.md).")
    ed.add_argument("scene", nargs="?", metavar="SCENE", help="scene file (TOML or the coursework's text format)")
    ed.add_argument("--port", type=_port, default=5006, help="TCP port (0: a free one; default 5006)")
    ed.add_argument("--address", default="127.0.0.1", help="address to bind (default 127.0.0.1: this machine only)")
    ed.add_argument("--no-browser", action="store_true", help="do not open a browser tab")
    ed.add_argument("--width", type=_setting_type("width"), help="image width (default: the scene's, else 960)")
    ed.add_argument("--height", type=_setting_type("height"), help="image height (default: the scene's, else 960)")
    ed.add_argument("--root", metavar="DIR", help="the folder every file the page loads or saves resolves inside"
                                                  " (default: the working folder)")
    tok = ed.add_mutually_exclusive_group()
    tok.add_argument("--token", help="the token the page asks for (default: a new random one, printed in the URL)")
    tok.add_argument("--no-token", action="store_true", help="no token: only with a loopback --address (every user of"
                                                             " this machine can then use the editor as you)")
    ed.add_argument("--max-sessions", type=_max_sessions, default=None, metavar="N",
                    help="the most editor tabs open at once (1 to 64; default 8)")
    ed.add_argument("--allow-host", action="append", default=[], metavar="NAME",
                    help="a host name besides this machine's that requests may be addressed to (a proxy's)")
    return parser


def _max_sessions(text):
    if not (text.isascii() and text.isdigit()) or not 1 <= int(text) <= 64:
        raise argparse.ArgumentTypeError(f"must be an integer from 1 to 64, got {text[:40]!r}")
    return int(text)


def _port(text):
    if not (text.isascii() and text.isdigit()) or not 0 <= int(text) <= 65535:
        raise argparse.ArgumentTypeError(f"must be an integer from 0 to 65535, got {text[:40]!r}")
    return int(text)


def _edit(args):
    """``tracer edit [SCENE]``: a bad scene file or a missing Panel is one line and status 2."""
    from .scene.errors import SceneError

    import importlib.util

    if importlib.util.find_spec("panel") is None:
        return _fail("tracer edit: error: the scene editor needs Panel: pip install 'bubbleoptics[editor]'")
    from .editor.app import serve

    from .editor.app import check_serve_options
    from .scene.file_access import FileAccess, FileAccessError

    token = False if args.no_token else args.token
    try:
        check_serve_options(args.address, token, args.width, args.height)
        root = FileAccess(args.root).root if args.root is not None else None
    except FileAccessError as err:
        return _fail(f"tracer edit: error: --root {err}")
    except ValueError as err:
        return _fail(f"tracer edit: error: {err}")
    try:
        scene = _load_scene(args.scene) if args.scene else None
        status = serve(scene, port=args.port, address=args.address, show=not args.no_browser, width=args.width,
                       height=args.height, root=root, token=token, allow_hosts=args.allow_host,
                       **({} if args.max_sessions is None else {"max_sessions": args.max_sessions}))
    except SceneError as err:
        return _fail(str(err))
    except ValueError as err:  # a name the editor refuses, an option out of range
        return _fail(f"tracer edit: error: {err}")
    except OSError as err:  # e.g. the port is taken
        return _fail(f"tracer edit: error: {err}")
    # The server has stopped: its renders are cancelled and its saves done.  End the process
    # now: the interpreter's own teardown (collecting Panel's, Bokeh's and numba's objects)
    # takes seconds on a busy machine, and a kernel that numba is still compiling (a first
    # run) cannot be stopped at all.
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(status)


def _fail(message):
    print(message, file=sys.stderr)
    return EXIT_BAD_INPUT


def _check_output(out, bits=None, exposure=None, view=None, suffixes=None):
    """*out* as a Path, if its suffix is one of *suffixes* (default: every output,
    :data:`tracer.rendering.output.OUTPUT_SUFFIXES`), and the options given on the command line (None:
    not given) suit it, and it can be written (:func:`tracer.rendering.output.check_output_path`: the
    writer installed, the folder exists and is writable, not a folder); else ValueError (one
    line).  Called before the scene is read and rendered."""
    from .rendering.output import DISPLAY_DEFAULTS, OUTPUT_SUFFIXES, check_output_path

    out = Path(out)
    suffixes = tuple(suffixes or OUTPUT_SUFFIXES)
    if out.suffix.lower() not in suffixes:
        raise ValueError(f"{out}: output must end in {', '.join(suffixes[:-1])} or {suffixes[-1]}"
                         if len(suffixes) > 1 else f"{out}: output must end in {suffixes[0]}")
    check_output_path(out, bits=bits, exposure=DISPLAY_DEFAULTS["exposure"] if exposure is None else exposure,
                      view=DISPLAY_DEFAULTS["view"] if view is None else view)
    return out


def _display_settings(args, table, out):
    """``exposure`` and ``view`` for :func:`tracer.save_image` of *out*: for a display image
    (.png) the option, else the scene's [render] *table*, else the defaults; for a float output
    only those given on the command line (which :func:`_check_output` has refused), so that a
    scene's display defaults do not stop it from being saved as .npy, .exr or .hdr."""
    from .rendering.output import DISPLAY_DEFAULTS, is_display_output

    given = {k: getattr(args, k) for k in DISPLAY_DEFAULTS if getattr(args, k) is not None}
    if is_display_output(out):
        return {k: given.get(k, table.get(k, v)) for k, v in DISPLAY_DEFAULTS.items()}
    return given


def _load_scene(path):
    """load_scene, with each SceneWarning printed as its own one line ``FILE:LINE: ...`` on stderr
    (not Python's two-line warning format naming the loader's source line)."""
    from .scene.errors import SceneWarning
    from .scene.load import load_scene

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", SceneWarning)
        scene = load_scene(path)
    for w in caught:
        if issubclass(w.category, SceneWarning):
            print(str(w.message), file=sys.stderr)
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    return scene


def _scene_from_args(args, scene_path):
    """The scene file *scene_path* (the built-in scene when None), its environment replaced by
    ``--background`` when given."""
    if scene_path is None:
        from .scene.builtin import default_scene

        scene = default_scene()
    else:
        scene = _load_scene(scene_path)
    if args.background is not None:
        from .scene.model import Environment

        scene.environment = Environment(kind="constant", color=args.background)
    return scene


def _resolve_settings(args, scene, spectral_image=False):
    """An option given on the command line, else the scene's [render] table (TOML), else
    DEFAULTS; checked against tracer.scene.limits (errors name the option) and for memory."""
    from .rendering.api import resolve_settings

    given = {key: getattr(args, key, None) for key in _SCENE_DEFAULTED}
    names = dict(_OPTION_NAMES)
    if args.command == "research":
        names["depth"] = "DEPTH"
    return resolve_settings(scene, names=names, spectral_image=spectral_image, **given)


def _warmup(args):
    """``tracer warmup``: compile the renderer of each scene's feature set (once each)."""
    import time

    from .kernels.integrator import FEATURES, scene_features
    from .prepare.pack import pack_scene
    from .rendering.api import render_with_stats, resolve_settings
    from .rendering.local import is_compiled, warm_up
    from .rendering.output import display_codes
    from .scene.builtin import default_scene
    from .scene.errors import SceneError

    try:
        scenes = [_load_scene(path) for path in args.scenes] or [default_scene()]
    except SceneError as err:
        return _fail(str(err))
    jobs = {}  # (features, per-band image) -> a packed scene to compile it with
    for scene in scenes:
        s = resolve_settings(scene)
        packed = pack_scene(scene, spectral_samples=s["spectral_samples"], spectral_method=s["spectral_method"])
        for features in [scene_features(packed)] + ([(True,) * len(FEATURES)] if args.all else []):
            for spectral_image in (False, True) if args.spectral else (False,):
                jobs.setdefault((features, spectral_image), packed)
    for (features, spectral_image), packed in jobs.items():
        what = ", ".join(n for n, f in zip(FEATURES, features) if f is not None) or "none"
        what += " + per-band image" if spectral_image else ""
        if is_compiled(packed, spectral_image, features):
            print(f"tracer warmup: {what}: already compiled")
            continue
        print(f"tracer warmup: {what}: compiling ...", flush=True)
        t0 = time.perf_counter()
        warm_up(packed, spectral_image=spectral_image, features=features, helper=True)
        print(f"tracer warmup: {what}: compiled in {time.perf_counter() - t0:.0f} s", flush=True)
    # the rest of a render (packing's spectra, the PNG encoding): a tiny render of each scene
    for scene in scenes:
        display_codes(render_with_stats(scene, width=4, height=4, progress=False)[0])
    return 0


EXIT_INTERRUPTED = 130  # 128 + SIGINT, the shells' convention


def main(argv=None):
    """Run the command line; returns the exit status (0; 2 for bad input; 130 on Ctrl-C)."""
    from bubbleoptics.resources import prefer_workqueue_threads

    prefer_workqueue_threads()
    try:
        return _main(argv)
    except KeyboardInterrupt:
        # Ctrl-C: the render stops at its next ray; no output file was written (images are
        # written atomically, and a temporary file is removed when its write is interrupted)
        print("tracer: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError:
        # stdout closed early (e.g. piped into `head`): no traceback; Python's documented idiom
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 1


def _main(argv=None):
    args = build_parser().parse_args(argv)
    if args.command in ("movie", "film"):
        return _movie(args)
    if args.command == "edit":
        return _edit(args)
    if args.command == "warmup":
        return _warmup(args)
    from .rendering.dask import check_cluster_options, cluster_client
    from .scene.errors import SceneError
    from .rendering.output import save_spectral
    from .rendering.api import render_with_stats, save_image

    try:
        if args.command == "image":
            if len(args.paths) > 2:
                return _fail("tracer image: error: expected [SCENE] OUT")
            scene_path, out = (None, args.paths[0]) if len(args.paths) == 1 else args.paths
        else:
            scene_path, out = args.scene, args.out
        out = _check_output(out, bits=args.bits, exposure=args.exposure, view=args.view)
        spectral_out = _check_output(args.spectral_out, suffixes=(".npz",)) if args.spectral_out else None
        spectral_image = spectral_out is not None or out.suffix.lower() == ".npz"
        workers, scheduler = getattr(args, "workers", None), getattr(args, "scheduler", None)
        check_cluster_options(workers=workers, scheduler=scheduler, names=_CLUSTER_NAMES)
        scene = _scene_from_args(args, scene_path)
        s = _resolve_settings(args, scene, spectral_image)  # every limit and the memory estimate, first
        with cluster_client(workers=workers, scheduler=scheduler, names=_CLUSTER_NAMES) as client:
            image, stats = render_with_stats(scene, **s, progress=False if args.quiet else None,
                                             spectral_image=spectral_image, client=client)
        if out.suffix.lower() == ".npz":
            save_spectral(stats.spectral_image, out)
        else:
            save_image(image, out, bits=args.bits, **_display_settings(args, scene.render_defaults, out))
        if spectral_out is not None:
            save_spectral(stats.spectral_image, spectral_out)
    except SceneError as err:
        return _fail(str(err))
    except (ValueError, OSError) as err:
        return _fail(f"tracer: error: {err}")
    if args.command == "research":
        report = dict(scene=str(scene_path), depth=s["depth"], width=s["width"], height=s["height"], spp=s["spp"],
                      threshold=s["threshold"], spectral=stats.spectral, channels=stats.channels,
                      spectral_method=stats.spectral_method, render_seconds=stats.render_seconds, rays=stats.rays)
        if args.json:
            print(json.dumps(report))
        else:
            print(f"{scene_path}: depth {s['depth']}, {s['width']}x{s['height']}, {s['spp']} spp: "
                  f"{stats.render_seconds:.3f} s (compilation excluded)")
            print("rays: " + ", ".join(f"{k} {v:,}" for k, v in stats.rays.items()))
    return 0


def _add_movie_commands(sub, epilog):
    """``tracer movie`` and ``tracer film`` (the coursework's name for it, same arguments)."""
    from .scene.limits import LIMITS

    for name in ("movie", "film"):
        help_ = ("render a movie: the scene changed between frames by a commands file (.mp4, .gif or a "
                 "folder of PNG frames)") if name == "movie" else "the same as 'movie' (the coursework's -film mode)"
        p = sub.add_parser(name, help=help_, epilog=epilog,
                           description="Render the movie of COMMANDS (docs/movies.md) applied to SCENE (or the "
                                       "built-in bubble scene) into OUT: OUT.mp4 (H.264), OUT.gif, or a folder "
                                       "of frames 0000.png, ... Frames are cached in OUT.cache: a rerun renders "
                                       "only the missing ones.")
        p.add_argument("paths", nargs="+", metavar="[SCENE] OUT COMMANDS",
                       help="scene file (TOML or the coursework's text format; the built-in scene when left out), "
                            "the movie (.mp4, .gif, or a folder name) and the commands file")
        p.add_argument("--depth", type=_setting_type("depth"),
                       help=f"maximum ray generation, 1 = camera rays only ({LIMITS['depth'][0]}-{LIMITS['depth'][1]})")
        _add_render_options(p, movie=True)
        p.add_argument("--fps", type=_fps, default=None, help="frames per second of an .mp4 or .gif (1-1000; 24)")
        _add_cluster_options(p, "the frames")


def _add_cluster_options(p, what):
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=_workers, metavar="N",
                       help=f"render {what} on a local Dask cluster of N processes, one thread each")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help=f"render {what} on a running Dask cluster (e.g. tcp://host:8786)")


def _fps(text):
    try:
        value = float(text) if text.isascii() else None
    except ValueError:
        value = None
    if value is None or not 1 <= value <= 1000:
        raise argparse.ArgumentTypeError(f"must be a number from 1 to 1000, got {text[:40]!r}")
    return int(value) if value == int(value) else value


def _workers(text):
    """An argparse type: an integer >= 1 (its upper limit, the cores, is checked with the other
    cluster options by tracer.rendering.dask.check_cluster_options, which names the count)."""
    if not (text.isascii() and text.isdigit()) or len(text) > 100 or not int(text) >= 1:
        raise argparse.ArgumentTypeError(f"must be an integer >= 1 (at most one per core), got {text[:40]!r}")
    return int(text)


#: What the command line calls the cluster options, in errors.
_CLUSTER_NAMES = {"workers": "--workers", "scheduler": "--scheduler"}


def _movie(args):
    """``tracer movie|film [SCENE] OUT COMMANDS``: everything checked before any work; exit 2
    with one line on a bad input, nothing written."""
    from .rendering.dask import check_cluster_options
    from .scene.errors import SceneError
    from .movie.run import DEFAULT_FPS, check_movie_output, check_spectral_output, render_movie
    from .movie.timeline import Timeline

    try:
        if len(args.paths) not in (2, 3):
            return _fail(f"tracer {args.command}: error: expected [SCENE] OUT COMMANDS")
        scene_path, out, commands = (None, *args.paths) if len(args.paths) == 2 else args.paths
        check_movie_output(out)
        check_cluster_options(workers=args.workers, scheduler=args.scheduler, names=_CLUSTER_NAMES)
        if args.spectral_out is not None:
            check_spectral_output(args.spectral_out, out)
        scene = _scene_from_args(args, scene_path)
        timeline = Timeline.from_file(scene, commands)
        s = _resolve_settings(args, scene)
        render_movie(scene, timeline, out, fps=DEFAULT_FPS if args.fps is None else args.fps, bits=8 if args.bits is None else args.bits,
                     progress=False if args.quiet else None, workers=args.workers, scheduler=args.scheduler,
                     exposure=args.exposure, view=args.view, spectral_out=args.spectral_out,
                     names={**_OPTION_NAMES, "fps": "--fps", "exposure": "--exposure", "view": "--view",
                            **_CLUSTER_NAMES}, **s)
    except SceneError as err:
        return _fail(str(err))
    except (ValueError, OSError) as err:
        return _fail(f"tracer: error: {err}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
