"""The sweep over trajectories (on a real dask LocalCluster), the merge rule, the payload sweep
and the sweep report."""

import dataclasses
import itertools
import re

import numpy as np
import pytest
from conftest import SHIPPED
from figure_checks import check_print_ready, column_twins
from pdf_checks import text as pdf_text

from gd_analyze import InputError, gd_terms
from gd_analyze.cli import parse_range
from gd_analyze.jobs.analyze import analyze
from gd_analyze.jobs.options import AnalysisOptions, SimplifyOptions
from gd_analyze.jobs.payload import payload_sweep
from gd_analyze.jobs.sweep import IN_PROCESS, analyze_one, run_sweep
from gd_analyze.jobs.sweep_merged import merged_model
from gd_analyze.ranking.ranking import CLASSES, element_labels
from gd_analyze.simplify.simplified import choice_masks
from gd_analyze.store.model_file import load_model
from gd_analyze.store.schema import open_sweep
from gd_analyze.store.schema import write_dataset as write_sweep
from gd_analyze.trajectory.planning import plan_quintic, random_trajectories
from gd_analyze.trajectory.trajectory import read_trajectory

#: Over 5 s on an idle machine (the module's fixtures): run on one interpreter in CI.
pytestmark = pytest.mark.slow

K = 6


# --------------------------------------------------------------------------------------------
# Merge rule
# --------------------------------------------------------------------------------------------


# --------------------------------------------------------------------------------------------
# The sweep on a dask LocalCluster
# --------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def trajectories(puma):
    return random_trajectories(puma, K, seed=5)


@pytest.fixture(scope="module")
def sweep(puma, trajectories, cluster):
    _, client = cluster
    return run_sweep(puma, trajectories, client=client, batch=2,
                     settings={"command": "test"})


@pytest.fixture(scope="module")
def serial(puma, trajectories):
    return [analyze(puma, tr, AnalysisOptions(verify=False, formulations=False, simplify=SimplifyOptions(rule="chapter"))).dataset for tr in trajectories]


def test_sweep_equals_serial_analysis(sweep, serial, puma, trajectories):
    labels = element_labels(puma.n)
    assert sweep.sizes == {"trajectory": K, "element": len(labels), "joint": 6, "class": 4}
    assert list(sweep["element"].values) == labels
    for k, ref in enumerate(serial):
        stored = np.isfinite(ref["share_tran"].values)     # results.h5: NaN where ≡ 0
        np.testing.assert_allclose(sweep["share_tran"].values[k][stored],
                                   ref["share_tran"].values[stored], rtol=0, atol=1e-12)
        assert list(sweep["dominance"].values[k]) == list(ref["dominance"].values)
        assert list(sweep["choice"].values[k]) == list(ref["choice"].values)
        np.testing.assert_allclose(sweep["tau_peak"].values[k], ref["tau_peak"].values,
                                   rtol=1e-12)
        np.testing.assert_allclose(sweep["tau_error_peak"].values[k],
                                   ref["tau_error_peak"].values, rtol=1e-9, atol=1e-14)
        np.testing.assert_allclose(sweep["peak_total"].values[k], ref["peak_total"].values,
                                   rtol=1e-12)
        tr = trajectories[k]
        assert sweep["source"].values[k] == tr.source
        assert sweep["duration"].values[k] == pytest.approx(tr.t[-1] - tr.t[0], rel=1e-14)
        np.testing.assert_array_equal(sweep["q_start"].values[k], tr.q[0])
        np.testing.assert_array_equal(sweep["q_goal"].values[k], tr.q[-1])
    # analyze_one in a loop gives the same
    for k, tr in enumerate(trajectories):
        one = analyze_one(puma, tr, 0.9, 0.01)
        np.testing.assert_allclose(sweep["share_tran"].values[k], one["share_tran"], rtol=0,
                                   atol=1e-12)


def test_sweep_envelope(sweep, serial):
    dom = np.array([list(ref["dominance"].values) for ref in serial])
    for c, cls in enumerate(CLASSES):
        np.testing.assert_allclose(sweep["class_fraction"].values[:, c],
                                   np.mean(dom == cls, axis=0), rtol=0, atol=1e-15)
    np.testing.assert_allclose(sweep["class_fraction"].sum("class").values, 1.0, atol=1e-12)
    # the envelope of the shares as data: a part that is round-off of the element's scale
    # (is_round_off on each analysis's own peaks) makes the share exactly 0 or 1; an element
    # that is round-off in every part on a trajectory has no share there
    import warnings

    from gd_analyze.ranking.ranking import is_round_off

    share = np.array([ref["share_tran"].values for ref in serial])
    off = {p: np.array([is_round_off(ref[f"peak_{p}"].values, ref["element_scale"].values)
                        for ref in serial]) for p in ("tran", "rot", "total")}
    share = np.where(off["tran"] & ~off["rot"], 0.0,
                     np.where(off["rot"] & ~off["tran"], 1.0, share))
    share = np.where(off["tran"] & off["rot"] & off["total"], np.nan, share)
    assert np.isnan(share).all(axis=0).any() and (share == 0.0).any()   # both rules at work
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)                  # all-NaN columns
        for name, fn in (("min", np.nanmin), ("median", np.nanmedian), ("max", np.nanmax)):
            np.testing.assert_allclose(sweep[f"share_tran_{name}"].values, fn(share, axis=0),
                                       rtol=0, atol=1e-12)
    # the merged choice by set logic, element by element
    choices = np.array([list(ref["choice"].values) for ref in serial])
    for m, label in enumerate(sweep["element"].values):
        kept = set(choices[:, m])
        tran = bool(kept & {"tran", "both"})
        rot = bool(kept & {"rot", "both"})
        want = "both" if tran and rot else "tran" if tran else "rot" if rot else "none"
        assert sweep["merged_choice"].values[m] == want, label


def test_merged_model_keeps_every_part_any_trajectory_keeps(sweep, puma):
    model = merged_model(puma, sweep)
    merged = choice_masks(model.choices, puma.n)
    for k in range(K):
        own = dict(zip(sweep["element"].values, sweep["choice"].values[k]))
        for m_merged, m_own in zip(merged, choice_masks(own, puma.n)):
            assert np.all(m_merged >= m_own)
    # and it drops what every trajectory drops
    labels = list(sweep["element"].values)
    for m, label in enumerate(labels):
        if all(sweep["choice"].values[k, m] == "none" for k in range(K)):
            assert model.choices[label] == "none"


def test_merged_model_validation_is_its_error_over_all_trajectories(sweep, puma,
                                                                    trajectories):
    model = merged_model(puma, sweep)
    errs, taus = [], []
    for k, tr in enumerate(trajectories):
        terms = gd_terms(puma, tr.q, tr.qd)
        tau = terms.tau(tr.qdd)
        err = np.abs(model.torque(tr.q, tr.qd, tr.qdd) - tau)
        errs.append(err)
        taus.append(tau)
        np.testing.assert_allclose(sweep["merged_tau_error_peak"].values[k], err.max(axis=0),
                                   rtol=1e-9, atol=1e-13)
    err, tau = np.concatenate(errs), np.concatenate(taus)
    peak, rms, tau_peak = err.max(axis=0), np.sqrt((err**2).mean(axis=0)), np.abs(tau).max(axis=0)
    v = model.validation
    np.testing.assert_allclose(v["peak_abs_error"], peak, rtol=1e-9, atol=1e-13)
    np.testing.assert_allclose(v["rms_error"], rms, rtol=1e-9, atol=1e-13)
    np.testing.assert_allclose(v["peak_tau"], tau_peak, rtol=1e-12)
    np.testing.assert_allclose(v["relative_peak_error"], peak / tau_peak, rtol=1e-9,
                               atol=1e-13)
    assert v["trajectories"] == K and v["setpoints"] == 31 * K
    assert model.dominance_threshold == 0.9 and model.negligible_threshold == 0.01


def test_merged_model_checks_the_robot(sweep, two_link):
    with pytest.raises(InputError, match="robot"):
        merged_model(two_link, sweep)


def test_sweep_attributes_and_units(sweep, puma, cluster):
    cl, _ = cluster
    for name, var in itertools.chain(sweep.data_vars.items(), sweep.coords.items()):
        assert "units" in var.attrs and "long_name" in var.attrs, name
    a = sweep.attrs
    assert a["Conventions"] == "CF-1.10"
    from gd_analyze import __version__

    assert a["gd_analyze_version"] == __version__
    assert a["robot"] == "puma560" and a["robot_sha256"] == puma.sha256
    np.testing.assert_array_equal(a["gravity"], puma.gravity)
    assert a["seed"] == 5 and a["input_kind"] == "random" and a["trajectories"] == K
    assert a["dominance_threshold"] == 0.9 and a["negligible_threshold"] == 0.01
    assert a["n_workers"] == 2 and a["scheduler_address"] == cl.scheduler_address
    assert a["batch_size"] == 2 and a["n_tasks"] == 2 * 3
    assert a["elapsed_s"] > 0 and a["command"] == "test"
    assert len(a["inputs_sha256"]) == 64


def test_sweep_by_scheduler_address_and_file_inputs(sweep, puma, trajectories, cluster,
                                                    tmp_path):
    cl, _ = cluster
    shipped = read_trajectory(SHIPPED, puma.n)
    ds = run_sweep(puma, [trajectories[1], shipped], scheduler=cl.scheduler_address)
    np.testing.assert_allclose(ds["share_tran"].values[0], sweep["share_tran"].values[1],
                               rtol=0, atol=1e-12)
    # its shares are the pass's ranking, before any model: ranked only
    ref = analyze(puma, shipped, AnalysisOptions(verify=False, formulations=False,
                                                 simplify=None)).dataset
    stored = np.isfinite(ref["share_tran"].values)         # results.h5: NaN where ≡ 0
    np.testing.assert_allclose(ds["share_tran"].values[1][stored],
                               ref["share_tran"].values[stored], rtol=0, atol=1e-12)
    assert ds.attrs["scheduler_address"] == cl.scheduler_address
    assert ds.attrs["input_kind"] == "mixed" and "seed" in ds.attrs
    assert shipped.sha256 in ds.attrs["input_files"]
    assert list(ds["input_sha256"].values) == ["", shipped.sha256]


def test_big_batches_and_long_trajectories_equal_one_by_one(puma, cluster):
    """A task groups short trajectories into one G-D call; a long one (compiled engine in
    gd_terms) is computed alone: either way every share, also of round-off-level elements,
    is that of analyze_one."""
    _, client = cluster
    trajs = random_trajectories(puma, 140, seed=9)      # 100 x 31 set points in one call
    long = plan_quintic(puma, trajs[0].q[0], trajs[0].q[-1], n_setpoints=2500)
    trajs.insert(100, dataclasses.replace(long, source="long"))
    ds = run_sweep(puma, trajs, client=client, batch=len(trajs))
    assert ds.attrs["n_tasks"] == 2
    for k, tr in enumerate(trajs):
        one = analyze_one(puma, tr)
        np.testing.assert_allclose(ds["share_tran"].values[k], one["share_tran"], rtol=0,
                                   atol=1e-12)
        assert tuple(ds["dominance"].values[k]) == one["classes"]
    assert ds["setpoints"].values[100] == 2500


def test_sweep_starts_and_closes_its_own_cluster(puma, trajectories):
    ds = run_sweep(puma, trajectories[:2], n_workers=1)
    assert ds.attrs["n_workers"] == 1
    assert ds.attrs["cluster"].startswith("a LocalCluster of 1 worker process")
    np.testing.assert_allclose(ds["share_tran"].values[1],
                               analyze_one(puma, trajectories[1])["share_tran"], rtol=0,
                               atol=1e-12)


def test_in_process_sweep_equals_the_cluster_sweep(sweep, puma, trajectories):
    """Ranked in this process (one batch, no cluster), every variable of the dataset is the
    cluster's: the ranking to the last bit, the chapter merge's errors up to round-off (the
    set points are grouped otherwise); the provenance says where it ran."""
    ds = run_sweep(puma, trajectories, in_process=True, settings={"command": "test"})
    assert set(ds.variables) == set(sweep.variables)
    for name in ds.variables:
        a, b = ds[name].values, sweep[name].values
        if a.dtype.kind == "f":
            np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12, err_msg=name)
        else:
            np.testing.assert_array_equal(a, b, err_msg=name)
    for name in ("share_tran", "peak_total", "tau_peak"):
        np.testing.assert_array_equal(ds[name].values, sweep[name].values, err_msg=name)
    a = ds.attrs
    assert a["cluster"] == IN_PROCESS and a["scheduler_address"] == "none"
    assert (a["n_workers"], a["n_tasks"], a["batch_size"]) == (0, 0, K)
    assert run_sweep(puma, trajectories[:3], in_process=True, batch=2).attrs["batch_size"] == 2


def test_in_process_takes_no_cluster(puma, trajectories, cluster):
    _, client = cluster
    for where in ({"client": client}, {"scheduler": "tcp://127.0.0.1:1"}, {"n_workers": 1}):
        with pytest.raises(ValueError, match="without a dask cluster"):
            run_sweep(puma, trajectories[:1], in_process=True, **where)


def test_sweep_rejects_bad_input_before_starting(puma, two_link, trajectories):
    with pytest.raises(ValueError, match="at least one"):
        run_sweep(puma, [])
    with pytest.raises(ValueError, match="shape"):
        run_sweep(two_link, trajectories[:1])
    with pytest.raises(ValueError, match="dominance"):
        run_sweep(puma, trajectories[:1], dominance=0.4)
    with pytest.raises(ValueError, match="batch"):
        run_sweep(puma, trajectories[:1], batch=0)


def test_sweep_file_round_trip(sweep, tmp_path):
    path = tmp_path / "sweep.h5"
    write_sweep(sweep, path)
    back = open_sweep(path)
    for name in sweep.data_vars:
        a, b = sweep[name].values, back[name].values
        if a.dtype.kind in "fi":
            np.testing.assert_array_equal(a, b)
        else:
            assert [str(x) for x in a.ravel()] == [str(x) for x in b.ravel()], name
        assert back[name].attrs["units"] == sweep[name].attrs["units"]
        assert back[name].attrs["long_name"] == sweep[name].attrs["long_name"]
    assert back.attrs["robot_sha256"] == sweep.attrs["robot_sha256"]
    assert not list(tmp_path.glob(".*.tmp"))
    with pytest.raises(InputError):
        open_sweep(path, "payload")


# --------------------------------------------------------------------------------------------
# Report
# --------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def chapter_html(sweep, tmp_path_factory):
    """The sweep's report as HTML alone, without a payload sweep (the per-trajectory models
    of the chapter rule), written once for the tests that read it: its text."""
    from gd_analyze.report.sweep import write_sweep_report

    folder = tmp_path_factory.mktemp("chapter")
    write_sweep(sweep, folder / "chapter.h5")
    return write_sweep_report(folder / "chapter.h5", folder / "rc",
                              formats=["html"])[0].read_text(encoding="utf-8")


def test_sweep_report(sweep, puma, shipped, tmp_path, chapter_html):
    from matplotlib.figure import Figure

    from gd_analyze.report.main_figures import payload_figure
    from gd_analyze.report.sweep import write_sweep_report

    path = tmp_path / "sweep.h5"
    pay = payload_sweep(puma, shipped, parse_range("0:1:0.5"))
    write_sweep(pay, tmp_path / "payload.h5")
    # the report reads the file: mark a stored value and find it in the report
    marked = sweep.copy()
    marked.attrs["command"] = "marker-7f3a"
    write_sweep(marked, path)
    out = write_sweep_report(path, tmp_path / "report", payload=tmp_path / "payload.h5",
                             column_figures=True)
    html_path, pdf_path = out[:2]
    assert html_path.name == "sweep_report.html" and pdf_path.name == "sweep_report.pdf"
    page = ("sweep_share_D", "sweep_share_h", "payload_dominance", "sweep_class_fractions",
            "sweep_torque_error")
    column = tuple(f"{name}_column" for name in page)
    assert {p.name for p in out[2:] if p.parent.name == "figures"} == {
        f"fig_{name}.{ext}" for ext in ("pdf", "svg")
        for name in page + column}
    assert not column_twins(tmp_path / "report" / "figures")     # 3.5-in MediaBox each
    html = html_path.read_text(encoding="utf-8")
    # the summary leads with the worst cases: the trajectory of the largest merged error
    rel = sweep["merged_tau_error_relative_peak"].values
    worst = str(sweep["source"].values[int(np.nanargmax(np.nanmax(rel, axis=1)))])
    assert html.index("Worst cases:") < html.index("merged model of the chapter rule keeps")
    assert worst in html[html.index("Worst cases:"):html.index("Worst cases:") + 400]
    assert html.count("<svg") >= 5
    assert "<link" not in html and 'src="http' not in html and "<script" not in html
    assert "marker-7f3a" in html and puma.sha256 in html
    from gd_analyze.report.markup import label as lettered

    for label in element_labels(puma.n):
        assert f">{lettered(label)}<" in html          # D(1,2), as the figures letter it
    assert "Payload sweep" in html
    assert pdf_path.read_bytes().startswith(b"%PDF")
    from pypdf import PdfReader

    reader = PdfReader(pdf_path)
    assert len({tuple(p.mediabox) for p in reader.pages}) == 1          # one page size
    text = pdf_text(pdf_path)               # poppler's pdftotext (pypdf's extraction took 2.7 s)
    assert "Worst cases:" in text and "Figure 5." in text
    assert not list((tmp_path / "report").glob(".*.tmp"))
    fig = payload_figure(pay)
    assert isinstance(fig, Figure) and len(fig.axes) >= 2
    # no payload section without a payload sweep; a payload file is not a sweep
    assert "Payload sweep" not in chapter_html
    with pytest.raises(InputError):
        write_sweep_report(tmp_path / "payload.h5", tmp_path / "r3")
    with pytest.raises(InputError):
        write_sweep_report(tmp_path / "missing.h5", tmp_path / "r3")


def test_analyze_one_rejects_a_trajectory_of_another_robot(two_link, puma):
    tr = random_trajectories(puma, 1)[0]
    with pytest.raises(ValueError, match="shape"):
        analyze_one(two_link, tr)
    bad = dataclasses.replace(tr, qd=tr.qd[:, :3])
    with pytest.raises(ValueError, match="qd"):
        analyze_one(puma, bad)


# --------------------------------------------------------------------------------------------
# The merged model of the budget rule: guaranteed on each swept trajectory
# --------------------------------------------------------------------------------------------

def _rnea(robot, q, qd, qdd):
    import pinocchio as pin

    from gd_analyze.dynamics.pinocchio import pinocchio_model

    model = pinocchio_model(robot)
    data = model.createData()
    return np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])


@pytest.mark.parametrize("eps, floor", [(0.002, 0.0), (0.01, 0.0), (0.05, 0.0), (0.01, 1.0)])
def test_budget_merged_model_within_eps_of_each_trajectory_scale(puma, mixed, eps, floor):
    from gd_analyze.simplify.sweep_model import sweep_model

    model, _ = sweep_model(puma, mixed, tolerance=eps, torque_floor=floor)
    assert model.rule == "budget"
    worst = 0.0
    for tr in mixed:
        ref = _rnea(puma, tr.q, tr.qd, tr.qdd)                  # the oracle, per trajectory
        scale = np.maximum(np.abs(ref).max(axis=0), floor)
        err = np.abs(model.torque(tr.q, tr.qd, tr.qdd) - ref).max(axis=0)
        assert np.isfinite(err).all()
        assert (err <= eps * scale * (1 + 1e-9) + 1e-12).all(), (tr.source, err / scale)
        worst = max(worst, float((err / scale).max()))
    # the stored figure is the one the oracle gives, and within the relative bound <= EPS
    assert model.validation["worst_scaled_error"] == pytest.approx(worst, rel=1e-6, abs=1e-12)
    assert max(model.validation["relative_bound"]) <= eps * (1 + 1e-12)
    assert worst <= max(model.validation["relative_bound"]) * (1 + 1e-9) + 1e-12


def test_sweep_command_rule_budget_by_default_and_chapter_says_no_bound(tmp_path, capsys):
    import json

    from gd_analyze.cli import main

    slow = tmp_path / "slow.csv"
    assert main(["plan", "puma560", "-o", str(slow), "--start", "0,45,-90,0,30,0", "--goal",
                 "2,46,-89,1,31,1", "--duration", "4"]) == 0
    csvs = [str(SHIPPED), str(slow)]
    trajs = [read_trajectory(p, 6) for p in csvs]
    capsys.readouterr()
    out_b = tmp_path / "budget"
    assert main(["sweep", "puma560", *csvs, "-o", str(out_b),
                 "--tolerance", "0.01", "--torque-floor", "1", "--held-out", "0",
                 "--guarantee", "trajectory"]) == 0              # the merge on each trajectory
    printed = capsys.readouterr().out
    spec = json.loads((out_b / "merged_model.json").read_text())
    assert spec["rule"] == "budget" and spec["tolerance"] == 0.01
    model = load_model(out_b / "merged_model.json")
    ns = {}
    exec((out_b / "merged_model.py").read_text(), ns)                # numpy only
    robot = model.robot
    worst = 0.0
    for tr in trajs:
        ref = _rnea(robot, tr.q, tr.qd, tr.qdd)
        scale = np.maximum(np.abs(ref).max(axis=0), 1.0)
        for tau in (model.torque(tr.q, tr.qd, tr.qdd), ns["tau"](tr.q, tr.qd, tr.qdd)):
            err = np.abs(tau - ref).max(axis=0)
            assert (err <= 0.01 * scale * (1 + 1e-9) + 1e-12).all()
            worst = max(worst, float((err / scale).max()))
    # the printed figure is the guaranteed quantity (relative to max(peak, floor)), and true
    line = next(x for x in printed.splitlines() if x.startswith("merged model (budget"))
    assert f"{worst:.2e}" in line and "(guaranteed <= 0.01)" in line
    figures = {p.name for p in (out_b / "figures").iterdir()}   # no column twin unasked
    assert "fig_sweep_share_D.svg" in figures and not any("_column" in f for f in figures)
    html = (out_b / "sweep_report.html").read_text(encoding="utf-8")
    assert re.search("guaranteed within \u03b5\u00b7s<sub>i</sub>[^.]{0,160}on every swept "
                     "trajectory", html) and "\u03b5 = 0.01" in html
    # "no error bound" only of the per-trajectory models of the chapter rule, never the merged
    assert "onservative" not in html and html.count("no error bound") == html.count(_OWN)
    out_c = tmp_path / "chapter"
    assert main(["sweep", "puma560", *csvs, "-o", str(out_c),
                 "--rule", "chapter", "--no-report"]) == 0
    assert "no error bound" in capsys.readouterr().out
    assert json.loads((out_c / "merged_model.json").read_text())["rule"] == "chapter"
    assert not (out_c / "merged_model.py").exists()


#: How the sweep report names the per-trajectory models (chapter rule: no bound).
_OWN = "chapter rule: share-based classes of Sec. 3.4.1, no error bound"

def test_sweep_report_wording_follows_the_rule(sweep, puma, trajectories, tmp_path,
                                              chapter_html):
    from gd_analyze.jobs.sweep_merged import with_budget_model
    from gd_analyze.report.sweep import write_sweep_report
    from gd_analyze.simplify.sweep_model import sweep_model

    html = chapter_html
    assert "chapter rule, no error bound" in html and "guaranteed within" not in html
    assert "onservative" not in html
    model, _ = sweep_model(puma, trajectories, tolerance=0.02)
    ds = with_budget_model(sweep, model)
    rel = ds["merged_tau_error_relative_peak"].values
    assert np.isfinite(rel).all() and (rel <= 0.02 * (1 + 1e-9)).all()
    write_sweep(ds, tmp_path / "budget.h5")
    html = write_sweep_report(tmp_path / "budget.h5", tmp_path / "rb",
                              formats=["html"])[0].read_text(encoding="utf-8")
    assert re.search("guaranteed within \u03b5\u00b7s<sub>i</sub>[^.]{0,160}on every swept "
                     "trajectory", html) and "\u03b5 = 0.02" in html
    assert html.count("no error bound") == html.count(_OWN) and "onservative" not in html
    with pytest.raises(ValueError, match="trajectories"):
        with_budget_model(sweep.isel(trajectory=slice(0, 2)), model)


def test_round_off_elements_have_no_share_box(sweep, serial):
    """D45 and D56 of the PUMA 560 are zero in every part on every trajectory (parts of about
    1e-19 kg m^2 against scales of 1e-4 kg m^2 and more): the sweep stores the round-off flag
    the per-trajectory analyses give (:func:`is_round_off` on their own peaks and scales),
    and draws no box of their noise shares; every other element gets its box."""
    from gd_analyze.ranking.ranking import is_round_off
    from gd_analyze.report.sweep import make_sweep_figures

    labels = [str(v) for v in sweep["element"].values]
    expected = np.array([[bool(is_round_off(max(ds["peak_tran"].values[k],
                                                ds["peak_rot"].values[k],
                                                ds["peak_total"].values[k]),
                                            ds["element_scale"].values[k]))
                          for k in range(len(labels))] for ds in serial])
    np.testing.assert_array_equal(sweep["round_off"].values.astype(bool), expected)
    assert {lab for lab, z in zip(labels, expected.all(axis=0)) if z} >= {"D45", "D56"}
    from gd_analyze.report.markup import label as shown

    fig = make_sweep_figures(sweep)["D"]
    titled = {shown(lab): lab for lab in labels}        # D(1,2) -> D12
    panels = 0
    for ax in fig.axes:
        element = titled.get((ax.get_title().split() or [""])[0].rstrip(":"))
        if element is None:
            continue
        panels += 1
        if expected[:, labels.index(element)].all():
            assert ax.get_title() == f"{shown(element)}: \u2261 0"
            assert not ax.lines and not ax.patches          # no box, no threshold lines
        else:
            assert len(ax.lines) > 2                        # thresholds, whiskers, median
    assert panels == sum(lab.startswith("D") for lab in labels)


def test_sweep_panel_titles_say_the_part_kept(sweep):
    """A panel's title says which part of the element the merged model keeps ("D(1,6): keeps
    rot"), not "D(1,6) → rot", which read as a class."""
    from gd_analyze.report.markup import label as shown
    from gd_analyze.report.sweep import make_sweep_figures

    labels = [str(v) for v in sweep["element"].values]
    choice = dict(zip(labels, (str(v) for v in sweep["merged_choice"].values)))
    words = {"tran": "keeps tran", "rot": "keeps rot", "both": "keeps both", "none": "dropped",
             "pruned": "pruned"}
    figs = make_sweep_figures(sweep)
    titles = [" ".join(ax.get_title().split())          # a title of two lines read as one
              for key in ("D", "h") for ax in figs[key].axes if ax.get_title()]
    checked = 0
    for lab in labels:
        title = next((t for t in titles if t.startswith(shown(lab) + ":")), None)
        if title is None or title.endswith("\u2261 0"):
            continue
        assert title == f"{shown(lab)}: {words[choice[lab]]}", title
        checked += 1
    assert checked >= len(labels) - 4
    assert not any("\u2192" in t for t in titles)


def test_sweep_figures_letter_mathematics_at_print_size(sweep, puma, shipped):
    """Every sweep figure, at page width and as its 3.5-in column twin (payload included):
    elements lettered D(1,2), h(3) (no D12, share_tran), no label collisions or text past the
    edge, type of at least 7 pt in the column versions."""
    from gd_analyze.report.sweep import _RC, make_sweep_figures

    pay = payload_sweep(puma, shipped, [0.0, 1.0])
    figs = make_sweep_figures(sweep, pay, column=True)
    assert {k for k in figs if not k.endswith("_column")} == {
        k[:-len("_column")] for k in figs if k.endswith("_column")}
    check_print_ready(figs, _RC)
