"""One handler for SIGINT, SIGTERM and SIGHUP in every command.

:func:`install` makes each signal raise in the main thread (SIGINT KeyboardInterrupt, SIGTERM
and SIGHUP :class:`Terminated`), so that clean-up code runs and the
command line (:func:`gd_analyze.cli.main`) exits with 128 + the signal's number (130, 143) and one line. Two
places would lose the signal:

- Python code that the interpreter runs on its own (a ``gc.callbacks`` entry such as
  distributed's GC diagnosis, a ``__del__`` method, a weakref's callback such as a
  ``WeakValueDictionary``'s) reports an exception raised in it as "Exception ignored" and
  goes on: the sweep then ran to its end and exited 0. The handler does not raise where it
  sees such code on the stack; where it cannot see it (a weakref's callback is any
  function), the exception it raised reaches ``sys.unraisablehook``, which :func:`install`
  sets. Either way the signal is delivered again to the main thread once that code has
  returned (:func:`_deliver_later`).
- After the command returned, during the interpreter's shutdown (joining threads, atexit
  handlers), a KeyboardInterrupt printed a traceback after "wrote" with exit status 0.
  :func:`after_run` makes a signal then end the process at once with 128 + its number and
  one line: the run's files are complete.
"""

from __future__ import annotations

import contextlib
import gc
import os
import signal
import sys
import threading
from typing import NoReturn

__all__ = ["install", "after_run", "without_teardown", "exit_with", "pending", "SIGNALS",
           "Terminated"]

#: The signals handled: interrupt, terminate, hang-up.
SIGNALS = tuple(s for s in (signal.SIGINT, signal.SIGTERM, getattr(signal, "SIGHUP", None))
                if s is not None)
#: Seconds before a deferred signal is delivered again (it waits for the interpreter's own
#: callback to return; not a test's wait).
_AGAIN = 0.02
_PENDING: list = []
#: The exception the handler raised last, with its signal (for :func:`_unraisable`).
_RAISED: list = []
#: The ``sys.unraisablehook`` before :func:`install`.
_HOOK: list = [sys.unraisablehook]


def pending() -> tuple[int, ...]:
    """The signals received since :func:`install`, in order (one deferred out of a gc
    callback is counted at each delivery).

    Returns
    -------
    tuple of int
    """
    return tuple(_PENDING)


class Terminated(BaseException):
    """Raised in the main thread on SIGTERM (or SIGHUP), so that clean-up code runs."""


def _in_interpreter_callback(frame):
    """Whether the interrupted code runs inside a gc callback or a ``__del__`` method, where
    an exception would be reported as ignored and the signal lost."""
    codes = {getattr(getattr(cb, "__func__", cb), "__code__", None) for cb in gc.callbacks}
    while frame is not None:
        if frame.f_code in codes or frame.f_code.co_name == "__del__":
            return True
        frame = frame.f_back
    return False


def _deliver_later(signum):
    main = threading.main_thread().ident

    def again():
        threading.Event().wait(_AGAIN)
        signal.pthread_kill(main, signum)
    threading.Thread(target=again, name="gd-analyze-signal", daemon=True).start()


def _on_signal(signum, frame):
    _PENDING.append(signum)
    if _in_interpreter_callback(frame):
        _deliver_later(signum)
        return
    exc = KeyboardInterrupt() if signum == signal.SIGINT else Terminated(signum)
    _RAISED[:] = [(exc, signum)]
    raise exc


def _unraisable(unraisable):
    """``sys.unraisablehook``: a signal's exception the interpreter would report as ignored
    (raised in a callback it runs itself: a weakref's, a finalizer's) is delivered again to
    the main thread instead; anything else goes to the hook there was before."""
    for exc, signum in _RAISED:
        if unraisable.exc_value is exc:
            _RAISED.clear()
            _deliver_later(signum)
            return
    _HOOK[0](unraisable)


def install() -> None:
    """Handle SIGINT, SIGTERM and SIGHUP by :func:`_on_signal` (main thread only), and
    set ``sys.unraisablehook`` so that a signal's exception raised in a callback the
    interpreter runs itself is delivered again instead of lost.

    Raises
    ------
    ValueError
        If called from another thread than the main one (``signal.signal``).
    """
    for sig in SIGNALS:
        signal.signal(sig, _on_signal)
    if sys.unraisablehook is not _unraisable:
        _HOOK[0] = sys.unraisablehook
        sys.unraisablehook = _unraisable


#: Set by :func:`without_teardown`: the process ends without the interpreter's teardown.
_TORN = [False]


def _flush_output():
    """Flush stdout and stderr, whatever state they are in (closed, replaced, a full pipe)."""
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(OSError, ValueError, AttributeError):
            stream.flush()


def without_teardown() -> None:
    """After a write the HDF5 library could not finish (a full disk, a file size limit), end
    the process without the interpreter's teardown (:func:`exit_with`): HDF5's own shutdown
    then flushes again into the file it tore down, a SIGSEGV after the run's one error line
    (the run's staging folder and lock are gone by then; nothing else is pending)."""
    _TORN[0] = True


def exit_with(code: int) -> NoReturn:
    """End the process with ``code``: ``sys.exit``, or, after :func:`without_teardown`,
    ``os._exit`` once stdout and stderr are flushed.

    Parameters
    ----------
    code : int
        The exit status.

    Raises
    ------
    SystemExit
        With ``code``, unless the teardown is skipped.
    """
    if _TORN[0]:
        _flush_output()
        os._exit(code)
    sys.exit(code)


def after_run(prog: str) -> None:
    """From now on (the command returned), a signal ends the process at once with status
    128 + its number and one line, without a traceback (main thread only).

    Parameters
    ----------
    prog : str
        The program's name, for the line.
    """
    _flush_output()                             # the run's output, before any os._exit

    def after(signum, frame):
        os.write(sys.stderr.fileno(), f"{prog}: interrupted after the run had finished (its "
                                      "files are complete)\n".encode())
        os._exit(128 + signum)
    for sig in SIGNALS:
        signal.signal(sig, after)
