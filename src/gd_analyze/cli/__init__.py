"""The command line: ``gd-analyze ROBOT TRAJECTORY.csv`` and its sub-commands.

Exit status: 0 on success; 1 if the verification against Pinocchio fails; 2 on bad input or an
unusable output location (one line on stderr naming the file, row and column, no traceback, no
partial output); 3 when ``evaluate --max-error`` is exceeded; 4 on an internal error (a bug: one
line, the traceback only with ``--debug``).

The parsers are in :mod:`gd_analyze.cli.parsing`, the commands in :mod:`gd_analyze.cli.commands`.
Nothing in the package imports this package.
"""

from __future__ import annotations

import contextlib
import os
import re
import sys
import warnings
from collections.abc import Sequence
from typing import NoReturn

from ..errors import InputError, InputNote, InputWarning
from ..model.robots import builtin_robots, unknown_robot
from ..model.urdf import is_urdf_text
from ..store.signals import after_run, exit_with, install
from ..store.staging import Terminated, full_disk_error
from . import commands, parsing
from .parsing import COMMANDS, EXIT_INPUT, EXIT_INTERNAL, EXIT_OK, PROG, parse_range

__all__ = ["main", "run", "parse_range", "escape_control", "MAIN_JOB_IMPORTS", "REPORT_IMPORTS"]

#: The libraries the main job always uses, imported by :func:`run` before the job starts, so
#: that ``gc.freeze()`` then moves their objects out of the collector's reach (the job's
#: garbage collections no longer walk the modules' objects: about 0.3 s of the PUMA 560 job).
MAIN_JOB_IMPORTS = ("numpy", "xarray", "h5netcdf", "h5py", "pinocchio", "symengine")
#: The libraries the main job's report uses (Jinja2's templates, matplotlib's figures and SVG
#: writer, Typst), imported likewise unless ``--no-report`` is given.
REPORT_IMPORTS = ("jinja2", "matplotlib.figure", "matplotlib.backends.backend_svg", "typst")


#: Control characters never written to the terminal as they are (C0 but newline, tab and
#: carriage return, which a progress bar needs; DEL; C1): an ESC from a robot file, a URDF or
#: a file name would start a terminal escape sequence.
_CONTROL = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\x7f-\x9f]")


def escape_control(text: str) -> str:
    r"""Text with its control characters written as ``\xNN`` escapes (:data:`_CONTROL`).

    Parameters
    ----------
    text : str

    Returns
    -------
    str

    Examples
    --------
    >>> print(escape_control("evil \x1b[31mred\x1b[0m"))
    evil \x1b[31mred\x1b[0m
    """
    return _CONTROL.sub(lambda m: f"\\x{ord(m.group()):02x}", text)


class _Escaping:
    """A text stream that writes through another with :func:`escape_control`."""

    def __init__(self, stream):
        self._stream = stream

    def write(self, text):
        return self._stream.write(escape_control(text))

    def __getattr__(self, name):
        return getattr(self._stream, name)


def _show_warning(message, category, filename, lineno, file=None, line=None):
    kind = "note" if issubclass(category, InputNote) else "warning"
    print(f"{PROG}: {kind}: {message}", file=sys.stderr)


def _check_command(argv):
    """Raise a 'did you mean' error for a first word that is neither a built-in robot nor a
    file: an unknown robot when the second argument looks like a trajectory file (a file, or a
    name ending in .csv: ``gd-analyze pand traj.csv``), else a mistyped command when one is
    close; nothing otherwise."""
    import difflib

    word = argv[0]
    if (word.startswith("-") or word in builtin_robots() or os.path.exists(word)
            or is_urdf_text(word)):
        return
    if len(argv) > 1 and (argv[1].lower().endswith(".csv") or os.path.isfile(argv[1])):
        raise unknown_robot(word)
    close = difflib.get_close_matches(word, COMMANDS, n=1, cutoff=0.6)
    if close:
        raise InputError(f"unknown command {word!r}: did you mean '{close[0]}'? (commands: "
                         f"{', '.join(COMMANDS)}; or a robot for the main job)")


def _command(name):
    """A command's parser maker (``parsing.<name>_parser``) and its runner
    (``commands.cmd_<name>``); ``"analyze"`` is the main job."""
    return getattr(parsing, f"{name}_parser"), getattr(commands, f"cmd_{name}")


def run() -> NoReturn:
    """The ``gd-analyze`` program: :func:`main` on ``sys.argv``, then exit with its status.

    The main job runs as on an installation without dask (:func:`_without`): it makes no
    dask arrays, and xarray would otherwise import dask (about 0.3 s) to check that its numpy
    arrays are not dask arrays (the sweep, which runs on dask.distributed, only without
    dask.array). Its libraries (:data:`MAIN_JOB_IMPORTS`, and
    :data:`REPORT_IMPORTS` unless ``--no-report``) are imported first, then ``gc.freeze()``
    (Python's documented way to keep objects made at start-up out of the garbage collector's
    passes; every run of every command does the same, whatever the load). The interpreter then
    exits normally (atexit handlers and teardown run). :func:`main` itself returns, for use
    from Python, and neither imports ahead nor freezes.

    Raises
    ------
    SystemExit
        With the exit status.
    """
    import gc
    import importlib


    argv = sys.argv[1:]
    first = [a for a in argv if a != "--debug"][:1]
    if not first or first[0] not in COMMANDS:      # the main job: no sub-command word first
        _without("dask")
        for name in MAIN_JOB_IMPORTS + (() if "--no-report" in argv else REPORT_IMPORTS):
            importlib.import_module(name)
    elif first == ["sweep"]:
        _without("dask.array")
    gc.freeze()                 # after the imports: start-up objects leave the collector's passes
    code = main(argv)
    after_run(PROG)             # a signal during the interpreter's shutdown: no traceback
    exit_with(code)


def _without(module: str) -> None:
    """Make ``import <module>`` fail in this process, as where it is not installed.

    ``sys.modules[module] = None`` is Python's documented way to make an import raise
    ImportError (the import system reference, "The module cache"); xarray then treats dask as
    absent, a configuration it supports. ``"dask"`` only for the main job of the console
    script: one command per process, and the job never makes a dask array. ``"dask.array"``
    only for the ``sweep`` command of the console script: it runs on dask.distributed but
    makes no dask array, and xarray imports dask.array (about 1 s of CPU time) only to check
    that the sweep dataset's numpy arrays are not dask arrays; its local cluster's forked
    workers inherit the same. Nothing is done if the module is imported already.
    """
    sys.modules.setdefault(module, None)  # type: ignore[arg-type]


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line.

    Parameters
    ----------
    argv : list of str, optional
        Arguments without the program name (default ``sys.argv[1:]``). ``--debug`` anywhere
        shows the traceback of an internal error.

    Returns
    -------
    int
        The exit status: 0 ok, 1 verification failed, 2 bad input, unusable output location or
        a lost dask cluster,
        3 evaluate's gate (an error above the model's tolerance x s_i, or above --max-error),
        4 internal error. Control characters of the output (an ESC from an input file) are
        written as escapes (:func:`escape_control`).
    """
    # no control character shown; a stream closed (>&-, 2>&-: None) writes to nowhere, as
    # print() does, and never makes the run an internal error
    with contextlib.redirect_stdout(_Escaping(sys.stdout or open(os.devnull, "w"))), \
            contextlib.redirect_stderr(_Escaping(sys.stderr or open(os.devnull, "w"))):
        return _main(argv)


def _main(argv):
    given = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in given
    argv = [a for a in given if a != "--debug"]
    command = argv[0] if argv and argv[0] in COMMANDS else "analyze"
    if argv and argv[0] == command:
        argv = argv[1:]
    make_parser, run = _command(command)
    try:
        import threading

        if threading.current_thread() is threading.main_thread():
            install()                   # SIGINT, SIGTERM, SIGHUP: one handler

        with warnings.catch_warnings():
            warnings.simplefilter("always", InputWarning)
            warnings.showwarning = _show_warning
            # an argument holding bytes that are not UTF-8 (a file name in another encoding,
            # kept by Python as lone surrogates): the provenance records the command line in
            # UTF-8 files, which cannot hold it
            bad = next((arg for arg in argv if re.search("[\ud800-\udfff]", arg)), None)
            if bad is not None:
                raise InputError(f"argument {os.fsencode(bad)!r} is not UTF-8 text (a file name "
                                 "in another encoding?): the provenance is written in UTF-8; "
                                 "rename the file")
            if command == "analyze" and argv and argv[0] in ("help", "-help"):
                # gd-analyze help [COMMAND]: the help of the main job or of a command
                name = argv[1] if len(argv) > 1 else "analyze"
                if name not in COMMANDS:
                    raise InputError(f"help: unknown command {name!r} (commands: "
                                     f"{', '.join(COMMANDS)})")
                _command(name)[0]().print_help()
                return EXIT_OK
            if command == "analyze" and argv:
                _check_command(argv)
            args = make_parser().parse_intermixed_args(argv)
            args.given_argv = given      # the provenance records what main() was given
            return run(args)
    except InputError as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return EXIT_INPUT
    except BrokenPipeError:
        # The reader of stdout went away (e.g. `| head`): not an error of ours.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return EXIT_OK
    except (KeyboardInterrupt, Terminated) as exc:      # one path for every signal
        interrupted = isinstance(exc, KeyboardInterrupt)
        print(f"{PROG}: {'interrupted' if interrupted else 'terminated'}", file=sys.stderr)
        return 130 if interrupted else 128 + int(exc.args[0]) if exc.args else 143
    except Exception as exc:  # noqa: BLE001 - the last line of defence: exit 4, one line
        full = full_disk_error(exc)     # a full disk elsewhere (numba's cache): not a bug
        if full is not None:
            print(f"{PROG}: error: {full}", file=sys.stderr)
            return EXIT_INPUT
        if debug:
            import traceback

            traceback.print_exc()
        text = " ".join(str(exc).split())[:300]
        print(f"{PROG}: internal error: {type(exc).__name__}: {text} (a bug in gd-analyze; "
              f"{'see the traceback above' if debug else 'rerun with --debug for the traceback'})",
              file=sys.stderr)
        return EXIT_INTERNAL
