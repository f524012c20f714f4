"""The region proof's compiled kernels, compiled in a second process on a first run.

On a machine whose numba cache does not hold the enclosure kernels yet (a first run after an
install or an upgrade), compiling them is most of the job: about 17 s of the PUMA 560's first
main job of 41 s go to :mod:`gd_analyze.certify.ball_kernels` and
:mod:`gd_analyze.certify.box_kernels` alone. :func:`start` then runs
``python -m gd_analyze.jobs.compile_ahead ARITHMETIC`` beside the job, which compiles those
kernels by calling them on a small arm, so that numba writes them to its cache, while the job
compiles and runs its own analysis kernels on the other core. Before a kernel is first called,
:func:`ready` waits until the second process has written it, and the job's own numba loads it
from the cache instead of compiling it. Nothing is shared but numba's cache, whose files numba
writes atomically and checks against the kernel's source and the machine before loading, so
the results are those of a run that compiled everything itself.

Where the cache already holds the kernels, or the process cannot be started, nothing happens:
the job compiles what it needs, as it always did.
"""

from __future__ import annotations

import atexit
import os
import subprocess
import sys
import threading
from pathlib import Path
from typing import IO, Any

import numpy as np
from numba.core import event

from ..certify import regressor_bounds
from ..certify.ball_kernels import backward_kernel, forward_kernel, inertia_kernel
from ..certify.box_kernels import both_backward_kernel, box_forward_kernel
from ..certify.regressor_bounds import channel_enclosures, inertia_enclosure
from ..model.robots import load_robot

__all__ = ["KERNELS", "WAIT_S", "compile_kernels", "is_cached", "kernel_name", "ready", "start",
           "stop"]

#: Per arithmetic of :func:`gd_analyze.certify.regressor_bounds.channel_enclosures`, the
#: kernels the second process compiles, in the order the job first calls them; the job
#: compiles the rest itself meanwhile (in the mixed arithmetic, the ball backward kernel).
KERNELS = {
    "both": (forward_kernel, box_forward_kernel, both_backward_kernel, inertia_kernel),
    "ball": (forward_kernel, backward_kernel, inertia_kernel),
}

#: Longest wait for the second process [s]; after it the job compiles what is left itself.
WAIT_S = 300.0

_lock = threading.Lock()
_child: subprocess.Popen[str] | None = None
_planned: set[str] = set()
_written: set[str] = set()


def kernel_name(kernel: Any) -> str:
    """A numba kernel's name as the second process writes it.

    Parameters
    ----------
    kernel : numba dispatcher

    Returns
    -------
    str
        The kernel's ``__qualname__``.
    """
    return str(kernel.py_func.__qualname__)


def is_cached(kernel: Any) -> bool | None:
    """Whether numba's cache holds any compiled version of a kernel for this source.

    Parameters
    ----------
    kernel : numba dispatcher
        A kernel compiled with ``cache=True``.

    Returns
    -------
    bool or None
        True if its cache index lists a compiled version for the kernel's current source,
        False if it lists none, None if numba's cache cannot be read this way (a numba
        whose cache is laid out otherwise).

    Notes
    -----
    The index is read with numba's own reader (``Cache._cache_file._load_index``, not a public
    API), which returns no entries for an index of another numba version or another source.
    """
    try:
        return bool(kernel._cache._cache_file._load_index())
    except Exception:                     # noqa: BLE001 - another numba: no compiling ahead
        return None


def start(arithmetic: str) -> bool:
    """Compile the region proof's kernels in a second process, if numba's cache does not hold
    them yet.

    Parameters
    ----------
    arithmetic : {"both", "ball"}
        The enclosures' arithmetic on the arm at hand
        (:func:`gd_analyze.certify.regressor_bounds.joint_sum_arithmetic`).

    Returns
    -------
    bool
        Whether a second process was started (not when one is running, the kernels are
        cached, or the process cannot be started).
    """
    global _child
    with _lock:
        if _child is not None or all(is_cached(k) is not False for k in KERNELS[arithmetic]):
            return False
        env = dict(os.environ)      # this gd_analyze first, whichever is installed
        env["PYTHONPATH"] = os.pathsep.join([str(Path(__file__).resolve().parents[2])]
                                            + [p for p in [env.get("PYTHONPATH")] if p])
        try:
            _child = subprocess.Popen([sys.executable, "-m", __name__, arithmetic], env=env,
                                      stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                      stderr=subprocess.DEVNULL, text=True)
        except OSError:
            return False
        timer = threading.Timer(WAIT_S, _child.kill)     # a process that hangs is ended
        timer.daemon = True
        timer.start()
        _planned.clear()
        _planned.update(kernel_name(k) for k in KERNELS[arithmetic])
        _written.clear()
        if ready not in regressor_bounds.BEFORE_KERNEL:
            regressor_bounds.BEFORE_KERNEL.append(ready)
            atexit.register(stop)
        return True


def ready(kernel: Any) -> None:
    """Wait until the second process has written a kernel to numba's cache, if it compiles it.

    Parameters
    ----------
    kernel : numba dispatcher
        The kernel about to be called.

    Notes
    -----
    Returns at once where no second process runs or it does not compile this kernel; when
    the process ends (or after :data:`WAIT_S`), the job compiles what is still missing.
    """
    if _child is None or kernel_name(kernel) not in _planned:
        return
    with _lock:
        while _child is not None and kernel_name(kernel) not in _written:
            line = _child.stdout.readline() if _child.stdout is not None else ""
            if line:
                _written.add(line.strip())
            else:                               # the second process has ended
                _end()


def _end() -> None:
    """Reap the second process once it has ended; called with the lock held."""
    global _child
    child, _child = _child, None
    if child is None:
        return
    child.wait()
    if child.stdout is not None:
        child.stdout.close()


def stop() -> None:
    """End the second process, if it still runs (at exit: no process outlives the job)."""
    child = _child
    if child is not None:
        child.kill()            # first: a thread waiting in ready() then reads the end
    with _lock:
        _end()


class _Written(event.Listener):
    """Writes each kernel's name once numba has cached it: when the next compilation starts,
    or at :meth:`flush` (numba saves a kernel to its cache after its compile event ends)."""

    def __init__(self, out: IO[str]) -> None:
        self.out, self.depth = out, 0
        self.done: list[str] = []

    def on_start(self, ev: event.Event) -> None:
        if self.depth == 0:
            self.flush()
        self.depth += 1

    def on_end(self, ev: event.Event) -> None:
        self.depth -= 1
        if self.depth == 0:
            self.done.append(kernel_name(ev.data["dispatcher"]))

    def flush(self) -> None:
        self.out.write("".join(name + "\n" for name in self.done))
        self.out.flush()
        self.done.clear()


def compile_kernels(arithmetic: str, out: IO[str]) -> None:
    """Compile the kernels of :data:`KERNELS` for an arithmetic by calling them
    on a two-link arm, writing each kernel's name to ``out`` once numba has cached it.

    Parameters
    ----------
    arithmetic : {"both", "ball"}
        As :func:`gd_analyze.certify.regressor_bounds.channel_enclosures`.
    out : text stream
        Receives one name (the kernel's ``__qualname__``) a line.
    """
    robot = load_robot("two-link")
    q_lo = np.zeros((2, robot.n))
    written = _Written(out)
    with event.install_listener("numba:compile", written):
        channel_enclosures(robot, q_lo, q_lo + 0.25, np.arange(10 * robot.n), arithmetic=arithmetic)
        inertia_enclosure(robot, q_lo, q_lo + 0.25, np.ones((robot.n, 10)))
    written.flush()


if __name__ == "__main__":
    compile_kernels(sys.argv[1] if len(sys.argv) > 1 else "both", sys.stdout)
