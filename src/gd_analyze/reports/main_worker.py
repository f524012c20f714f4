"""Part of the main report's figures drawn by a second interpreter, on a second core.

The figures of a report depend only on the stored results file, so they can be drawn in any
process that can read it. :class:`FigureWorker` starts a fresh, isolated interpreter
(:func:`worker_command`: ``python -I``, not a fork) when the main job begins. While the job
computes the dynamics and writes ``results.h5``, the worker imports matplotlib, xarray and the
report's modules. When the file is written, :meth:`FigureWorker.draw` asks it for some figures
(:data:`WORKER_FIGURES`: D, h and the torque error, the ones with one panel per element or
joint); it reads the file, makes and draws them, each once for both the SVG and the PDF
(:func:`gd_analyze.reports.drawing.draw_figures`), while the job's own process makes and draws
the others. The worker sends the sizes of its figures first (:meth:`FigureWorker.sizes`), so
that the job can lay out the PDF and draw its text pages meanwhile; then the drawings
(:meth:`FigureWorker.collect`). Each figure is still drawn exactly once, from the same file, with the same code.

The worker is started only if a second core is free (:func:`spare_core`), and by the main job
only for a trajectory file of at most :data:`WORKER_MAX_INPUT` bytes. Should it fail at any
point, :func:`gd_analyze.reports.main.write_report` draws the missing figures itself, with the
same result. Messages are pickles over the worker's stdin and stdout, between two processes of
the same user and program.
"""

from __future__ import annotations

import os
import pickle
import subprocess
import sys
from pathlib import Path

__all__ = ["FigureWorker", "WORKER_FIGURES", "WORKER_MAX_INPUT", "spare_core", "worker_command"]

#: The figures the worker draws (when they are in the report), by key.
#: The column-width D (the costliest of the column versions) goes with them, so that the
#: job's own process, which draws the other column versions and lays out the text, and the
#: worker finish at about the same time.
WORKER_FIGURES = ("joints", "D", "h", "torque", "D_column")
#: The largest trajectory file [bytes] for which the main job starts the worker: it saves
#: about half a second, which matters for a short trajectory; a long one is bound by its
#: computing, and the worker's own memory is better left to it.
WORKER_MAX_INPUT = 8 * 2**20


class FigureWorker:
    """A child interpreter that draws some of a report's figures from its results file.

    Parameters
    ----------
    enabled : bool, optional
        Start the child (if :func:`spare_core` allows it). With False the worker does nothing
        and the report draws every figure in its own process.

    Notes
    -----
    Use: ``with FigureWorker() as w:`` before the results are computed (the child imports while
    the caller works); ``w.draw(results_path, keys)`` once the file is written;
    ``w.collect()`` for the drawn figures. Leaving the block stops the child if it still runs.
    """

    def __init__(self, enabled=True):
        self.proc = None
        self.keys = ()
        if not enabled or not spare_core():
            return
        try:
            self.proc = subprocess.Popen(worker_command(), stdin=subprocess.PIPE,
                                         stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                                         env={**os.environ, "MPLBACKEND": "Agg"})
        except OSError:
            self.proc = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def draw(self, results_path, keys=WORKER_FIGURES, fonts="type3"):
        """Ask the worker to draw these figures of a stored analysis.

        Parameters
        ----------
        results_path : str or os.PathLike
            The results file (written and closed).
        keys : sequence of str, optional
            Figure keys of :func:`gd_analyze.reports.main.make_figures` that every results
            dataset has (default :data:`WORKER_FIGURES`).
        fonts : {"type3", "truetype"}, optional
            How the figures' PDFs embed their font.

        Returns
        -------
        tuple of str
            The keys the worker took: to be collected, not drawn by the caller. Empty if no
            worker runs.
        """
        if self.proc is None:
            return ()
        try:
            pickle.dump((str(results_path), tuple(keys), str(fonts)), self.proc.stdin,
                        protocol=pickle.HIGHEST_PROTOCOL)
            self.proc.stdin.close()
        except (OSError, pickle.PicklingError):
            self.close()
            return ()
        self.keys = tuple(keys)
        return self.keys

    def sizes(self):
        """The sizes of the figures the worker made (sent before it draws them).

        Returns
        -------
        dict of str to (float, float)
            Width and height [in] by key; empty if the worker failed (the caller then makes
            and draws them).
        """
        answer = self._receive()
        if not isinstance(answer, dict):
            return {}
        return {k: v for k, v in answer.items()
                if k in self.keys and isinstance(v, tuple) and len(v) == 2}

    def collect(self):
        """The figures the worker drew; stops the worker.

        Returns
        -------
        dict of str to (str, bytes, (float, float))
            SVG text, PDF bytes and size [in] by key, as
            :func:`gd_analyze.reports.drawing.draw_figures` gives them; only well-formed
            entries. Empty if the worker failed (the caller then draws them).
        """
        answer = self._receive()
        self.close()
        if not isinstance(answer, dict):
            return {}
        return {k: v for k, v in answer.items() if k in self.keys and _well_formed(v)}

    def _receive(self):
        if self.proc is None:
            return None
        try:
            return pickle.load(self.proc.stdout)
        except (OSError, EOFError, pickle.UnpicklingError, AttributeError, ImportError):
            self.close()
            return None

    def close(self):
        """Stop the worker if it still runs (idempotent)."""
        proc, self.proc = self.proc, None
        if proc is None:
            return
        for stream in (proc.stdin, proc.stdout):
            try:
                stream.close()
            except OSError:
                pass
        if proc.poll() is None:
            proc.kill()
        proc.wait()


#: The child's program: the folder that holds this gd_analyze package (its argument) goes
#: first on sys.path unless the isolated interpreter has it already (an installed package),
#: so the child runs the parent's code even from a source tree.
_BOOT = ("import sys; root = sys.argv[1]; root in sys.path or sys.path.insert(0, root); "
         "from gd_analyze.reports.main_worker import _serve; "
         "_serve(sys.stdin.buffer, sys.stdout.buffer)")


def worker_command():
    """The command line of the worker: an isolated interpreter.

    ``python -I`` ignores the ``PYTHON*`` environment variables and the user's site folder,
    and puts neither the current folder nor a script's folder on ``sys.path``: no module of the
    folder the job was started in (a ``pickle.py``, say) can run in the child. The package is
    found where the parent found it (the folder that holds it is an argument).

    Returns
    -------
    list of str
    """
    root = str(Path(__file__).resolve().parents[2])
    return [sys.executable, "-I", "-c", _BOOT, root]


def _well_formed(entry):
    return (isinstance(entry, tuple) and len(entry) == 3 and isinstance(entry[0], str)
            and isinstance(entry[1], bytes) and isinstance(entry[2], tuple))


def spare_core():
    """Whether a second core is free for the worker: at least two cores usable by this process
    and a one-minute load average below their number less a half (this job counts as one).
    On a busy machine a second interpreter would only compete with the first.
    ``GD_ANALYZE_WORKER=0`` (never) or ``=1`` (always) overrides the test, e.g. to time both
    ways with ``analysis/benchmark.py --latency-only``.

    Returns
    -------
    bool
    """
    forced = os.environ.get("GD_ANALYZE_WORKER", "").strip()
    if forced in ("0", "1"):
        return forced == "1"
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:                  # not on Linux
        cores = os.cpu_count() or 1
    try:
        load = os.getloadavg()[0]
    except (OSError, AttributeError):        # unknown, or no load average on this system
        return False
    return cores >= 2 and load < cores - 0.5


def _serve(stdin, stdout):
    import gc

    gc.disable()                            # as the report's own drawing (drawing.no_gc)
    from ..io.schema import open_results, skip_dask

    skip_dask()
    import matplotlib.figure  # noqa: F401 - imported while the caller computes
    from matplotlib.backends import backend_pdf, backend_svg  # noqa: F401

    from .drawing import draw_figures
    from .main import FIG_RC, make_figures

    path, keys, fonts = pickle.load(stdin)
    with open_results(path, lazy=True) as ds:
        figures = make_figures(ds, keys=keys)
    pickle.dump({k: tuple(float(v) for v in f.get_size_inches()) for k, f in figures.items()},
                stdout, protocol=pickle.HIGHEST_PROTOCOL)
    stdout.flush()
    pickle.dump(draw_figures(figures, FIG_RC, fonts=fonts), stdout, protocol=pickle.HIGHEST_PROTOCOL)
    stdout.flush()
    os._exit(0)                         # all is sent: skip tearing down thousands of artists


if __name__ == "__main__":
    _serve(sys.stdin.buffer, sys.stdout.buffer)
