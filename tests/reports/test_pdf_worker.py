"""The PDF of a report written on a second core (gd_analyze.reports.pdf_worker)."""

from gd_analyze.reports.common import table
from gd_analyze.reports.drawing import figure_pdf
from gd_analyze.reports.pages import Document


def _figure(w, h):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(w, h))
    ax = fig.add_axes((0.1, 0.1, 0.8, 0.8))
    ax.plot([0, 1], [0, 1])
    return figure_pdf(fig)


def test_pdf_worker_writes_what_the_document_writes(tmp_path, monkeypatch):
    """The document laid out and drawn in a second interpreter (figures given later by key)
    reads back as the same pages, text and bookmarks as the same document written here."""
    from pypdf import PdfReader

    from gd_analyze.reports.pdf_worker import PdfWorker

    monkeypatch.setenv("GD_ANALYZE_PDF_WORKER", "1")
    fig = _figure(7.2, 3.0)

    def doc():
        d = Document("Worker", metadata={"Author": "me"})
        d.heading("1. Section \u03c4 \u2261 0")
        d.paragraph("text " * 200)
        d.figure("f", (7.2, 3.0), "A figure.")
        d.table(table(["a", "b"], [[str(i), "\u2212" + str(i)] for i in range(40)]))
        return d

    worker = PdfWorker()
    assert worker.proc is not None
    worker.send(doc())
    proc = worker.proc
    pages = worker.finish(tmp_path / "w.pdf", {"f": fig})
    assert proc.returncode == 0                 # written by the worker, not the fallback
    assert pages == doc().write(tmp_path / "h.pdf", {"f": fig})
    a, b = PdfReader(tmp_path / "w.pdf"), PdfReader(tmp_path / "h.pdf")
    assert [p.extract_text() for p in a.pages] == [p.extract_text() for p in b.pages]
    assert [o.title for o in a.outline] == [o.title for o in b.outline] == ["1. Section \u03c4 \u2261 0"]
