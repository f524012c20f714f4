"""The PDF of a report written on a second core while the first draws its figures.

A report's text pages (:class:`gd_analyze.reports.pages.Document`: thousands of strings) depend
only on its sentences, tables and the sizes of its figures, not on the figures' drawings. So
:class:`PdfWorker` starts a fresh interpreter (``python -m gd_analyze.reports.pdf_worker``; not a
fork) when a report begins; while the report's process makes and draws the figures, the worker
imports matplotlib and pypdf, lays out the document it is sent and draws its text pages; when the
figures' PDFs arrive, it places them and writes the file. It is started only if a second core
is free (:func:`spare_core`); otherwise the document is written in the report's own process. Messages are pickles over the worker's
stdin and stdout, between processes of the same user and program. Should the worker fail at any
point, the document is written in the report's own process, with the same result.
"""

from __future__ import annotations

import os
import pickle
import subprocess
import sys
from pathlib import Path

__all__ = ["PdfWorker", "spare_core"]


class PdfWorker:
    """A child interpreter that writes one :class:`~gd_analyze.reports.pages.Document`.

    Use: ``w = PdfWorker()`` early (the child imports while the caller works),
    ``w.send(document)`` once its figure blocks hold keys and sizes, then
    ``w.finish(path, figures)`` with the figures' PDF bytes by key.
    """

    def __init__(self):
        self.proc = None
        self.document = None
        if not spare_core():
            return
        try:
            root = str(Path(__file__).resolve().parents[2])
            env = {**os.environ, "MPLBACKEND": "Agg",
                   "PYTHONPATH": os.pathsep.join(
                       [root] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep)
                                 if p])}
            self.proc = subprocess.Popen([sys.executable, "-m", "gd_analyze.reports.pdf_worker"],
                                         stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                         stderr=subprocess.DEVNULL, env=env)
        except OSError:
            self.proc = None

    def send(self, document):
        """Give the worker the document to lay out and draw (figure blocks: keys, sizes).

        Parameters
        ----------
        document : gd_analyze.reports.pages.Document
        """
        self.document = document
        if self.proc is None:
            return
        try:
            pickle.dump(document, self.proc.stdin, protocol=pickle.HIGHEST_PROTOCOL)
            self.proc.stdin.flush()
        except (OSError, pickle.PicklingError):
            self.close()

    def finish(self, path, figures):
        """Write the document with its figures to ``path``; in this process if the worker failed.

        Parameters
        ----------
        path : str or os.PathLike
            The PDF file.
        figures : dict of str to bytes
            Each figure's one-page PDF, by the key its block holds.

        Returns
        -------
        int
            The number of pages.

        Raises
        ------
        OSError
            If the file cannot be written.
        """
        if self.proc is not None:
            try:
                pickle.dump((str(path), figures), self.proc.stdin,
                            protocol=pickle.HIGHEST_PROTOCOL)
                self.proc.stdin.close()
                answer = pickle.load(self.proc.stdout)
                if self.proc.wait() == 0 and isinstance(answer, int):
                    return answer
            except (OSError, EOFError, pickle.UnpicklingError):
                pass
            finally:
                self.close()
        return self.document.write(path, figures)

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


def spare_core():
    """Whether a second core is free for the worker: at least two cores usable by this process
    and a one-minute load average below their number less a half (this job counts as one).
    On a busy machine a second interpreter would only compete with the first.
    ``GD_ANALYZE_PDF_WORKER=0`` (never) or ``=1`` (always) overrides the test, e.g. to time
    both ways with ``analysis/benchmark.py --latency-only``.

    Returns
    -------
    bool
    """
    forced = os.environ.get("GD_ANALYZE_PDF_WORKER", "").strip()
    if forced in ("0", "1"):
        return forced == "1"
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:                  # not on Linux
        cores = os.cpu_count() or 1
    try:
        load = os.getloadavg()[0]
    except OSError:
        return False
    return cores >= 2 and load < cores - 0.5


def _serve(stdin, stdout):
    import gc

    gc.disable()
    import matplotlib.figure  # noqa: F401 - imported while the caller makes its figures
    import pypdf  # noqa: F401
    from matplotlib.backends import backend_pdf  # noqa: F401

    document = pickle.load(stdin)
    pages, bookmarks = document._layout()
    text = document._text_pages(pages)
    path, figures = pickle.load(stdin)
    count = document._finish(text, pages, bookmarks, path, figures)
    pickle.dump(count, stdout)
    stdout.flush()


if __name__ == "__main__":
    _serve(sys.stdin.buffer, sys.stdout.buffer)
