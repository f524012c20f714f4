"""The report's statements agree with the model it describes.

Models are built under both rules (``--rule budget``, ``--rule chapter``), both forms
(``--form recursive``, ``--form explicit``) and with terms of gravity dropped (``--form explicit
--tolerance 0.05`` drops terms of c at joints 2 and 3 of the PUMA 560). Oracles: Pinocchio's
generalized gravity for what the emitted model does with c at rest (q̇ = q̈ = 0); the stored
ranking, cost table and verification attributes for the counts the text states.
"""

import importlib.util
import re

import numpy as np
import pytest
import xarray as xr
from conftest import ROOT, SHIPPED, built_once
from html_checks import context_texts, html_table
from html_checks import html_text as _text

from gd_analyze import load_robot
from gd_analyze.dynamics.pinocchio import reference_terms
from gd_analyze.jobs.analyze import analyze
from gd_analyze.jobs.options import AnalysisOptions
from gd_analyze.report import main as report
from gd_analyze.store.model_file import load_model
from gd_analyze.store.schema import write_dataset
from gd_analyze.trajectory.planning import plan_quintic

#: Over 5 s on an idle machine (the module's fixtures): run on one interpreter in CI.
pytestmark = pytest.mark.slow

STANFORD = ROOT / "data" / "stanford_trajectory.csv"
CONFIGS = {"budget-recursive": ["--rule", "budget", "--form", "recursive"],
           "chapter": ["--rule", "chapter"],
           "budget-explicit": ["--rule", "budget", "--form", "explicit"],
           "gravity-dropped": ["--form", "explicit", "--tolerance", "0.05"]}


def _provenance(html):
    return html_table(html, 'id="provenance"', cell="td")[1:]


def _summary(text):
    return text[text.index("Dominance: "):text.index(" set points over ")]


@pytest.fixture(scope="module")
def stanford(shared_main):
    return shared_main("stanford", STANFORD)           # shared with test_units, test_report_review


@pytest.fixture(scope="module", params=list(CONFIGS))
def puma(request, shared_main):
    # shared with tests/report/test_control_text.py where the options are the same
    return request.param, shared_main("puma560", SHIPPED, *CONFIGS[request.param])


def _check_summary_against_dataset(folder):
    text = _text((folder / "report.html").read_text())
    summary = _summary(text)
    with xr.open_dataset(folder / "results.h5") as ds:
        labels = [str(v) for v in ds["element"].values]
        dominance = [str(v) for v in ds["dominance"].values]
        costs = dict(zip([str(v) for v in ds["cost_model"].values], ds["cost_total"].values))
        form = str(ds.attrs["simplified_form"])
        noise = ds["tau_error_round_off"].values.astype(bool)
    for lab, cls in zip(labels, dominance):              # every negligible element named
        if cls == "negligible":
            # lettered D<sub>12</sub>: "D 12" once the tags are stripped
            assert re.search(rf"\b{lab[0]} ?{lab[1:]}\b", summary), (lab, summary)
    negligible = re.findall(r"(\d+) are negligible", summary)
    assert sum(map(int, negligible)) == dominance.count("negligible")
    for key in ("recursive N-E, exact", "explicit, full", "project N-E as implemented"):
        if key == "explicit, full" and key not in costs:    # not derived (--form recursive)
            assert "the full explicit model was not derived" in summary, summary
            continue
        assert f"{int(costs[key]):,}" in summary, (key, summary)
    assert "open-loop torque error" in summary
    # a largest error is named unless the stored marks make every joint's round-off
    assert ("largest open-loop torque error" in summary) == (not noise.all()), summary
    assert ("at every joint (round-off only)" in summary) == bool(noise.all()), summary
    assert ("recursive Newton-Euler model on" in summary) == (form == "recursive")
    return summary


def test_summary_names_every_negligible_element_and_every_reference_cost(stanford):
    _check_summary_against_dataset(stanford)


def test_text_matches_the_model_under_each_rule_and_form(puma):
    """The summary's claim about c against the emitted model at rest and Pinocchio's gravity."""
    name, folder = puma
    summary = _check_summary_against_dataset(folder)
    robot = load_robot("puma560")
    with xr.open_dataset(folder / "results.h5") as ds:
        q = ds["q"].values
        scale = ds["tau_peak"].values
    spec = importlib.util.spec_from_file_location(f"model_{name.replace('-', '_')}",
                                                  folder / "simplified_model.py")
    model = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(model)
    rest = np.zeros_like(q)
    c = reference_terms(robot, q, rest).c
    error = np.max(np.abs(model.tau(q, rest, rest) - c), axis=0) / scale
    assert np.all(np.isfinite(error))
    whole = bool(np.all(error <= 1e-9))
    assert ("keeps c whole" in summary) == whole, (name, error, summary)
    assert bool(re.search(r"drops[^.;]* of c\b|from c\b", summary)) == (not whole), summary
    assert name != "gravity-dropped" or not whole        # the case is really exercised
    text = _text((folder / "report.html").read_text())   # Sec. 5's opening sentence
    intro = text[text.index("5. Simplified model"):text.index("5.1 Torque error")]
    if "explicit G-D model" in intro:
        assert ("keeps c whole" in intro) == whole, (name, intro)
        assert bool(re.search(r"\bc left out|terms of c left out", intro)) == (not whole), intro


def test_chapter_comparison_only_for_the_puma_560(stanford, puma):
    _, folder = puma
    assert "Agreement:" in _text((folder / "report.html").read_text())
    text = _text((stanford / "report.html").read_text())
    assert "Agreement:" not in text and "chapter's class" not in text
    with xr.open_dataset(stanford / "results.h5") as ds:
        assert not any(str(v) for v in ds["chapter_dominance"].values)


def test_provenance_states_each_setting_once_and_no_contradicting_error(stanford):
    html = (stanford / "report.html").read_text()
    rows = _provenance(html)
    values = dict((r[0], r[1]) for r in rows if len(r) == 2)
    joined = " ".join(" ".join(r) for r in rows)
    # the model's guarantee row states its own round-off allowance; the other settings once
    settings = " ".join(" ".join(r) for r in rows if not r[0].startswith("guarantee"))
    assert joined.count("1e-09") == 1 and settings.count("64 eps") <= 1
    assert not [k for k in values if k.startswith("max relative error")]
    for key, value in values.items():                   # simplified_rule = rule: shown once
        if key.startswith("simplified_") and key[len("simplified_"):] in values:
            assert values[key[len("simplified_"):]] != value, key
    text = _text(html)
    assert re.search(r"Verification against Pinocchio: passed on 31 of 31 set points", text)
    # every setting in words: the guarantee asked for was a raw row "guarantee | auto"
    assert "guarantee" not in values and "auto" not in values.values()
    assert values["guarantee asked for"].startswith("over the joint-limit region where")


@pytest.fixture(scope="module")
def two_link_runs():
    """The two-link arm's analysis (no formulations, verified) of a quintic move of
    ``setpoints`` set points and its HTML report, made once a session per count (conftest's
    built_once) for the tests of the verification's count and of Sec. 2's marks:
    ``get(setpoints)`` -> ``(dataset, folder)``, the dataset read back from
    ``folder / "results.h5"``, the report in ``folder / "out"``. Shared: read only."""
    from gd_analyze.store.schema import open_results

    def build(folder, setpoints):
        robot = load_robot("two-link")
        trajectory = plan_quintic(robot, [0.0, 0.0], [np.pi / 2, np.pi / 3],
                                  n_setpoints=setpoints)
        ds = analyze(robot, trajectory, AnalysisOptions(formulations=False)).dataset
        write_dataset(ds, folder / "results.h5")
        report.write_report(folder / "results.h5", folder / "out", formats=("html",))

    def get(setpoints):
        folder = built_once(f"text-truth-two-link-{setpoints}",
                            lambda f: build(f, setpoints))
        with open_results(folder / "results.h5", lazy=True) as ds:
            return ds.load(), folder
    return get


def test_verification_says_how_many_set_points_it_checked(two_link_runs):
    ds, folder = two_link_runs(2101)        # shared with test_section_2_names_the_marks...
    checked = int(ds.attrs["verification_setpoints"])
    assert checked < 2101
    text = _text((folder / "out" / "report.html").read_text())
    assert f"passed on {checked:,} of 2,101 set points" in text


#: What a report may not say of a model built without gravity, whose c is identically 0:
#: that gravity parts or terms of c are kept, dropped or counted among those that act.
GRAVITY_CLAIMS = ("keeps c whole", "gravity part is dropped", "drops the gravity part",
                  "terms of c", "gravity parts of their", "gravity c unchanged")
NO_GRAVITY = "The model was built without gravity (g = 0), so c \u2261 0."


def test_a_model_built_without_gravity_is_said_once_to_have_none(shared_main):
    """``--gravity 0,0,0``: Pinocchio's generalized gravity is 0 along the trajectory, so no
    gravity part acts; the report says once that there is no gravity, counts the inertial and
    velocity parts only, and says nothing of gravity parts kept, dropped or compared."""
    run = shared_main("puma560", SHIPPED, "--gravity", "0,0,0")  # shared: test_control_text
    model = load_model(run / "simplified_model.json")
    with xr.open_dataset(run / "results.h5") as ds:
        q = ds["q"].values
    assert not np.any(reference_terms(model.robot, q, np.zeros_like(q)).c)    # c = 0
    text = _text((run / "report.html").read_text())
    assert text.count(NO_GRAVITY) == 1
    pairs = model.recursive.stated_facts()["pairs"]
    assert f"of the {pairs} inertial and velocity parts of their contributions" in _summary(text)
    assert [c for c in GRAVITY_CLAIMS if c in text] == []


def test_an_explicit_model_built_without_gravity_is_said_once_to_have_none():
    """``--form explicit`` on an arm without gravity (the two-link arm, 11 set points):
    Pinocchio's generalized gravity is 0 along the trajectory, so the explicit model has no
    term of c. The summary counts the parts of D and h and says once that there is no
    gravity, Sec. 3's equation has no c, and nothing says that terms of c are kept or
    dropped."""
    from gd_analyze.jobs.options import SimplifyOptions
    from gd_analyze.model.mounting import with_mounting
    from gd_analyze.report.main_context import report_context

    robot = with_mounting(load_robot("two-link"), gravity=(0.0, 0.0, 0.0))
    trajectory = plan_quintic(robot, [0.0, 0.0], [np.pi / 2, np.pi / 3], n_setpoints=11)
    options = AnalysisOptions(formulations=False, verify=False, simplify=SimplifyOptions(
        form="explicit", guarantee="trajectory"))
    ds = analyze(robot, trajectory, options).dataset
    q = ds["q"].values
    assert not np.any(reference_terms(robot, q, np.zeros_like(q)).c)       # c = 0
    assert str(ds.attrs["simplified_form"]) == "explicit"
    ctx = report_context(ds)
    said = "\n".join(context_texts(ctx))
    assert said.count(NO_GRAVITY) == 1
    parts = 2 * ds.sizes["element"]
    assert f"of the {parts} parts of D and h. {NO_GRAVITY}" in ctx["summary"], ctx["summary"]
    intro = ctx["simplified_intro"]
    assert "(c \u2261 0)" in intro and "+ c" not in intro, intro
    assert [c for c in GRAVITY_CLAIMS if c in said] == []


def test_no_statement_of_gravity_kept_whole_without_a_check():
    """The sweep report said "Gravity c is kept whole" of a budget model that drops terms."""
    src = ROOT / "src" / "gd_analyze"
    assert not [p.name for p in src.rglob("*.py") if "kept whole" in p.read_text()]


def test_control_verdict_names_its_torque_difference_closed_loop():
    """The control verdict's torque is a difference of two closed-loop runs, not the main
    report's open-loop error: the sentence says so."""
    from gd_analyze.report.control import control_verdict

    text = control_verdict({"full": np.array([1e-4, 1e-5]), "simplified": np.array([2e-4, 0.0])},
                           np.zeros(2, bool), np.array([0.152, 0.01])).replace("\u00a0", " ")
    assert "closed-loop torque differs" in text and "0.152 N m" in text


@pytest.mark.parametrize("setpoints", [31, 2101])
def test_section_2_names_the_marks_fig_2_draws(two_link_runs, setpoints):
    """Oracle: the drawn Fig. 2. A 2,101-set-point run draws its curves as envelopes without
    markers, so Sec. 2 must not point the reader to ○, × and △ (the 5,000-set-point PUMA
    report did); a 31-set-point run draws them, and Sec. 2 names them."""
    from gd_analyze.report.main_figures import plot_data

    ds, folder = two_link_runs(setpoints)
    text = _text((folder / "out" / "report.html").read_text())
    section = text[text.index("One panel per element"):text.index("Figure 2.")]
    fig = report.make_figures(ds, plot_data(ds), keys=("D",))["D"]
    marked = {ln.get_label(): ln.get_marker() not in (None, "None", "", " ")
              for ax in fig.axes for ln in ax.lines}
    assert set(marked) >= {"translational", "rotational", "combined"}
    for part, mark in (("translational", "\u25cb"), ("rotational", "\u00d7"),
                       ("combined", "\u25b3")):
        assert (mark in section) == marked[part], (setpoints, part, section)
