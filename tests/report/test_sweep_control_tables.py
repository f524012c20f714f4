"""The sweep and the control report's tables, one format per column, and what the control
report's provenance and Fig. 3 show.

The sweep report printed peak errors as "0.001225" beside "3.64e-05", the control report D_ii
as "0.3603" beside "4.000e-05" and torques as "0.0258" beside "1.25e-04"; the control report's
provenance had no command line (control.h5 did not store one); Fig. 3 drew the markers of
the three controllers' coinciding torque curves at the same set points, one hiding the others.
Oracles: the stored sweep.h5 and control.h5 (every printed value reads back within its
significant digits), the argv given to :func:`gd_analyze.cli.main`, and the drawn figure's
marker positions.
"""

import re
import shlex

import numpy as np
import pytest
from conftest import built_once
from table_checks import csv_matches_html, number, reads_back
from table_checks import tables as _tables

from gd_analyze.cli import main
from gd_analyze.report.control import control_context, control_figures
from gd_analyze.report.markup import plain
from gd_analyze.report.sweep import sweep_context, write_sweep_report
from gd_analyze.store.schema import open_results, open_sweep

#: Over 5 s on an idle machine (the module's fixtures): run on one interpreter in CI.
pytestmark = pytest.mark.slow


@pytest.fixture(scope="module", params=("puma560", "stanford"))
def runs(request, shared_control):
    """The main job (shared, read only, linked as ``main``) and the control run on its model
    (conftest's shared_control), and a 3-trajectory sweep, by the command line; the control
    run's argv as given. Built once a session per robot (:func:`conftest.built_once`), shared
    by the xdist workers: read only."""
    name = request.param
    folder, argv = shared_control(name)

    def build(tmp):
        assert main(["sweep", name, "--random", "3", "--seed", "2",
                     "--held-out", "0", "-o", str(tmp / "sweep"), "-q", "--no-report"]) == 0

    tmp = built_once(f"sweep-control-tables-{name}", build)
    sweep = open_sweep(tmp / "sweep" / "sweep.h5", "sweep")
    control = open_results(str(folder / "control" / "control.h5"))
    return {"name": name, "argv": argv, "folder": folder, "sweep_folder": tmp, "sweep": sweep,
            "control": control,
            "sweep_ctx": sweep_context(sweep), "control_ctx": control_context(control)}


def _number(cell):
    """The number a cell prints (its units after a no-break space cut off), or None."""
    return number(plain(str(cell)).split("\u00a0")[0])


@pytest.mark.parametrize("report", ["sweep_ctx", "control_ctx"])
def test_no_column_mixes_exponent_and_fixed(runs, report):
    tables = list(_tables(runs[report]))
    assert len(tables) >= (4 if report == "sweep_ctx" else 7)
    for where, table in tables:
        for c, head in enumerate(table["header"]):
            cells = [plain(str(row[c])) for row in table["rows"] if c < len(row)]
            nums = [t for t in cells if _number(t) is not None and _number(t) != 0]
            assert len({"e" in t for t in nums}) <= 1, (runs["name"], where, head, nums)


def _reads_back(text, value, digits):
    reads_back(plain(str(text)).split("\u00a0")[0], value, digits)


def _pct_reads_back(text, value):
    """A percentage cell against its fraction: within half a unit of its last decimal, or a
    true bound ("< 0.01 %")."""
    figure = text.split()[-2]
    decimals = len(figure.split(".")[1]) if "." in figure else 0
    if text.startswith("<"):
        assert 100 * value < float(figure), (text, value)
    else:
        assert abs(float(figure) - 100 * value) <= 0.5 * 10.0 ** -decimals * (1 + 1e-9)


def test_sweep_error_table_reads_back(runs):
    """Table of Sec. 5.1 against sweep.h5: peak |tau|, peak and RMS error (four digits), the
    percentages within their last decimal."""
    ds, table = runs["sweep"], runs["sweep_ctx"]["error"]
    checked = 0
    for j, row in enumerate(table["rows"]):
        _reads_back(row[1], ds["merged_error_tau_peak"].values[j], 4)
        if "\u2261" in row[2]:
            continue
        _reads_back(row[2], ds["merged_error_peak"].values[j], 4)
        _reads_back(row[3], ds["merged_error_rms"].values[j], 4)
        _pct_reads_back(row[4], ds["merged_error_relative_peak"].values[j])
        _pct_reads_back(row[5], ds["merged_error_relative_rms"].values[j])
        checked += 1
    assert checked >= 1            # the recursive merged model errs on some joints only


def test_control_tables_read_back(runs):
    """Gains (four digits), tracking errors, torque differences and applied torques (three
    digits) against control.h5."""
    ds, ctx = runs["control"], runs["control_ctx"]
    n = ds.sizes["joint"]
    for j, row in enumerate(ctx["gains"]["rows"]):
        for text, v in zip(row[1:], ("wn", "zeta", "Kp", "Kv", "inertia_scale", "Kp_pd",
                                     "Kv_pd")):
            _reads_back(text, ds[v].values[j], 4)
    names = [str(c) for c in ds["controller"].values]
    short = {"full": "full model", "simplified": "simplified model", "pd_gravity": "PD + gravity"}
    checked = 0
    for row in ctx["errors"]["rows"]:
        c = next(k for k in names if short[k] == row[0])
        key = {"set points": "setpoints", "fine grid": "grid"}[row[1]]
        stored = ds[f"error_{row[2].lower()}_{key}"].sel(controller=c).values
        for text, v in zip(row[3:3 + n], stored):
            if "\u2261" not in text:
                _reads_back(text, v, 3)
                checked += 1
    for row in ctx["tau_diff"]["rows"]:
        if row[0].startswith("noise floor"):         # the measured floor, as stored
            stored = ds["tau_difference_floor"].values
        else:
            fig, where = row[0].split(", ")
            stored = ds["tau_difference_" + fig.lower()
                        + ("_setpoints" if where == "set points" else "")].values
        for text, v in zip(row[1:], stored):
            if "\u2261" not in text:
                _reads_back(text, v, 3)
                checked += 1
    for row in ctx["tau_table"]["rows"]:
        c = next(k for k in names if short[k] == row[0])
        stored = ds["tau_peak" if row[1].startswith("peak") else "tau_rms"].sel(
            controller=c).values
        for text, v in zip(row[2:], stored):
            _reads_back(text, v, 3)
            checked += 1
    assert checked >= 4 * n


def test_control_provenance_shows_the_command_given(runs):
    """control.h5 stores the command line as main() was given it, and the provenance shows
    it, once, in the HTML as in the context."""
    expected = shlex.join(["gd-analyze", *runs["argv"]])
    assert runs["control"].attrs["command"] == expected
    rows = [r for r in runs["control_ctx"]["provenance"]["rows"] if r[0] == "command"]
    assert [plain(r[1]) for r in rows] == [expected]
    html = (runs["folder"] / "control" / "control_report.html").read_text(encoding="utf-8")
    from html import unescape

    text = unescape(re.sub(r"<[^>]+>", " ", re.sub(r"<svg.*?</svg>", "", html, flags=re.S)))
    assert text.count(expected) == 1


def test_fig3_markers_of_the_controllers_never_coincide(runs):
    """Fig. 3 (applied torques): the three controllers' curves coincide; on every panel no two
    controllers put a marker at the same set point, each has markers, and the caption names
    the set points where they start."""
    ds = runs["control"]
    fig = control_figures(ds)["tau"]
    starts = set()
    panels = 0
    for ax in fig.axes:
        marked = []
        for line in ax.get_lines():
            if line.get_marker() in (None, "None", "", " "):
                continue
            x = np.asarray(line.get_xdata(), float)
            every = line.get_markevery()
            idx = (np.arange(x.size) if every in (None, 1) else
                   np.arange(x.size)[every[0]::every[1]] if isinstance(every, tuple) else
                   np.arange(x.size)[::every])
            marked.append(set(x[idx].round(12)))
            starts.add(int(idx[0]))
        if not marked:
            continue
        panels += 1
        assert len(marked) == len(ds["controller"]) and all(marked)
        for a in range(len(marked)):
            for b in range(a + 1, len(marked)):
                assert not marked[a] & marked[b], (ax.get_title(), a, b)
    assert panels == ds.sizes["joint"]
    caption = runs["control_ctx"]["captions"]["tau"]
    said = caption[caption.index("first at set point"):]
    labels = {"full": "computed torque, full model",
              "simplified": "computed torque, simplified model", "pd_gravity": "PD + gravity"}
    numbers = [int(re.search(rf"(\d+) \({re.escape(labels[str(c)])}\)", said).group(1))
               for c in ds["controller"].values]          # each controller by its key label
    assert numbers == sorted(s + 1 for s in starts), caption


def test_control_and_sweep_tables_are_written_as_csv(runs, tmp_path):
    """Every table of the control and the sweep report is also a CSV file, named apart from the
    main report's (a folder may hold all three), with the HTML table's numbers."""
    folder = runs["folder"] / "control"
    html = (folder / "control_report.html").read_text(encoding="utf-8")
    assert csv_matches_html(folder / "tables", "control_table_", html) > 20
    written = write_sweep_report(runs["sweep_folder"] / "sweep" / "sweep.h5", tmp_path,
                                 formats=("html",), latex=True)
    html = (tmp_path / "sweep_report.html").read_text(encoding="utf-8")
    assert csv_matches_html(tmp_path / "tables", "sweep_table_", html) > 20
    tex = sorted(p.name for p in written if p.suffix == ".tex")
    assert tex and tex == sorted(p.name.replace(".csv", ".tex") for p in written
                                 if p.suffix == ".csv")


def test_the_control_command_writes_no_column_twin_unasked(runs):
    """Column-width figures are made only with --column-figures, as for the main job: the
    control run's figures folder holds the page-width figures only (the twins' own test is
    tests/jobs/test_control.py's, with ``column_figures=True``)."""
    from gd_analyze.cli.parsing import control_parser, sweep_parser

    names = {p.name for p in (runs["folder"] / "control" / "figures").iterdir()}
    assert "fig_control_tracking_error.svg" in names
    assert not any("_column" in n for n in names), names
    for parser, argv in ((control_parser, ["m.json", "t.csv"]), (sweep_parser, ["puma560"])):
        assert parser().parse_args(argv).column_figures is False
        assert parser().parse_args([*argv, "--column-figures"]).column_figures is True
