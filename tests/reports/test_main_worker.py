"""Part of the main report's figures drawn by a second interpreter (reports.main_worker).

The oracle is the same report written by one process: every file must be the same, byte for
byte (the HTML and PDF up to their creation time), whether the worker drew its figures, failed
before its sizes, or failed after them.
"""

import re
import sys

import numpy as np
import pytest

from gd_analyze.workflows.options import AnalysisOptions
from gd_analyze.io.planning import plan_quintic
from gd_analyze.io.schema import write_dataset
from gd_analyze.reports import main as report
from gd_analyze.reports.main_worker import WORKER_FIGURES, FigureWorker, spare_core
from gd_analyze.workflows.analyze import analyze


@pytest.fixture(scope="module")
def results(tmp_path_factory, two_link):
    folder = tmp_path_factory.mktemp("worker")
    trajectory = plan_quintic(two_link, [0.0, 0.0], [np.pi / 2, np.pi / 3], n_setpoints=21)
    path = folder / "results.h5"
    write_dataset(analyze(two_link, trajectory, AnalysisOptions(formulations=False)).dataset, path)
    return path


@pytest.fixture(scope="module")
def alone(results, tmp_path_factory):
    out = tmp_path_factory.mktemp("alone")
    return out, report.write_report(results, out)


def _pdf_pages(path):
    from pypdf import PdfReader

    reader = PdfReader(path)
    return [(p.extract_text(), sorted(p["/Resources"].get("/XObject", {}).keys()))
            for p in reader.pages]


def _same_report(a_dir, a_files, b_dir, b_files):
    """Figure files equal byte for byte; the HTML up to its creation time; the PDF page by
    page (text up to the creation time, and the placed figures)."""
    assert [p.relative_to(a_dir) for p in a_files] == [p.relative_to(b_dir) for p in b_files]
    created = re.compile(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\S*")
    for a, b in zip(a_files, b_files):
        if a.suffix == ".pdf" and a.name.startswith("report"):
            pa, pb = _pdf_pages(a), _pdf_pages(b)
            assert [(created.sub("T", t), x) for t, x in pa] == \
                [(created.sub("T", t), x) for t, x in pb]
        elif a.name.startswith("report"):
            x, y = a.read_text(encoding="utf-8"), b.read_text(encoding="utf-8")
            assert created.sub("T", x) == created.sub("T", y)
        else:
            assert a.read_bytes() == b.read_bytes(), a.name


def test_worker_draws_what_one_process_draws(results, alone, tmp_path, monkeypatch):
    monkeypatch.setenv("GD_ANALYZE_WORKER", "1")
    taken = {}
    with FigureWorker() as worker:
        assert worker.proc is not None
        real = worker.collect

        def collect():
            got = real()
            taken.update(got)
            return got

        worker.collect = collect
        files = report.write_report(results, tmp_path, worker=worker)
    assert set(taken) == set(WORKER_FIGURES)       # drawn by the worker, not the fallback
    _same_report(*alone, tmp_path, files)


@pytest.mark.parametrize("when", ["before sizes", "after sizes"])
def test_a_failing_worker_leaves_the_same_report(results, alone, tmp_path, monkeypatch, when):
    """The worker killed before it sends anything, or after its sizes: the report draws the
    missing figures itself."""
    monkeypatch.setenv("GD_ANALYZE_WORKER", "1")
    with FigureWorker() as worker:
        if when == "before sizes":
            worker.proc.kill()
        else:
            real = worker.sizes

            def sizes():
                got = real()
                assert set(got) == set(WORKER_FIGURES)
                worker.proc.kill()
                return got

            worker.sizes = sizes
        files = report.write_report(results, tmp_path, worker=worker)
        assert worker.proc is None                 # stopped and reaped
    _same_report(*alone, tmp_path, files)


def test_worker_off_and_forced(monkeypatch):
    monkeypatch.setenv("GD_ANALYZE_WORKER", "0")
    assert not spare_core()
    with FigureWorker() as worker:
        assert worker.proc is None
        assert worker.draw("x.h5") == ()
        assert worker.sizes() == {} and worker.collect() == {}
    monkeypatch.setenv("GD_ANALYZE_WORKER", "1")
    assert spare_core()
    with FigureWorker(enabled=False) as worker:
        assert worker.proc is None


def test_worker_is_a_fresh_isolated_interpreter_of_this_python(monkeypatch):
    monkeypatch.setenv("GD_ANALYZE_WORKER", "1")
    with FigureWorker() as worker:
        args = worker.proc.args
        assert args[:2] == [sys.executable, "-I"]


def test_isolated_worker_draws_and_ignores_the_current_folder(results, tmp_path, monkeypatch):
    """A pickle.py in the current folder (it would write a marker) does not run in the
    worker, and the isolated worker still finds this gd_analyze and draws its figures."""
    monkeypatch.setenv("GD_ANALYZE_WORKER", "1")
    marker = tmp_path / "MARKER"
    (tmp_path / "pickle.py").write_text(f"open({str(marker)!r}, 'w').close()\n"
                                        "raise SystemExit(3)\n")
    monkeypatch.chdir(tmp_path)
    with FigureWorker() as worker:
        assert worker.draw(results) == WORKER_FIGURES
        assert set(worker.sizes()) == set(WORKER_FIGURES)
        assert set(worker.collect()) == set(WORKER_FIGURES)
    assert not marker.exists()


def _embedding(pdf_bytes):
    return ("truetype" if b"/FontFile2" in pdf_bytes else "") + \
        ("type3" if b"/Type3" in pdf_bytes else "")


def test_truetype_figure_fonts_through_the_worker(results, tmp_path, monkeypatch):
    """--figure-fonts truetype reaches the figures the worker draws and those drawn here: every
    figure PDF embeds a TrueType subset and no Type 3 font; the default is Type 3."""
    monkeypatch.setenv("GD_ANALYZE_WORKER", "1")
    with FigureWorker() as worker:
        files = report.write_report(results, tmp_path / "tt", worker=worker, fonts="truetype")
    alone = report.write_report(results, tmp_path / "alone", fonts="truetype")
    figures = [p for p in files if p.parent.name == "figures" and p.suffix == ".pdf"]
    assert len(figures) == len([p for p in alone if p.parent.name == "figures"]) // 2 >= 4
    for path in figures:
        assert _embedding(path.read_bytes()) == "truetype", path.name
        assert path.read_bytes() == (tmp_path / "alone" / "figures" / path.name).read_bytes()
    default = report.write_report(results, tmp_path / "t3", formats=("html",))
    for path in (p for p in default if p.suffix == ".pdf"):
        assert _embedding(path.read_bytes()) == "type3", path.name
    with pytest.raises(ValueError, match="fonts"):
        report.write_report(results, tmp_path / "bad", fonts="type1")
