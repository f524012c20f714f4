"""The sweep report says what each model is and which carries a guarantee, explains its
figures' marks and states each setting once (review 23, defects 7, 8 and 17).

Sweeps under both merge rules; the text is checked against the stored rules (changing the
stored rule changes the words: they are generated, not fixed) and the stored errors.
"""

import re

import numpy as np
import pytest
import xarray as xr
from conftest import SHIPPED
from html_checks import html_table as _table
from html_checks import html_text as _text

from gd_analyze import __version__
from gd_analyze.cli import main
from gd_analyze.dynamics.pinocchio import reference_terms
from gd_analyze.report.sweep import write_sweep_report
from gd_analyze.store.model_file import load_model
from gd_analyze.store.names import SweepAttr
from gd_analyze.store.schema import write_dataset
from gd_analyze.symbolic.recursive_model import PART_NAMES
from gd_analyze.trajectory.trajectory import read_trajectory

#: Over 5 s on an idle machine (the module's fixtures): run on one interpreter in CI.
pytestmark = pytest.mark.slow


def _rows(html, anchor):
    return _table(html, f'id="{anchor}"')[1:]


@pytest.fixture(scope="module", params=["budget", "chapter"])
def swept(request, shared_main):
    """The sweep of the PUMA 560 by a rule, with its report: run once a session, shared by the
    xdist workers (tests/conftest.py's ``shared_main``, keyed by the arguments); read only."""
    out = shared_main("sweep", "puma560", "--random", "3", "--seed", "1",
                      "--held-out", "0", "--rule", request.param)
    return request.param, out


def test_each_model_is_named_with_its_rule_and_guarantee(swept, tmp_path):
    rule, out = swept
    text = _text((out / "sweep_report.html").read_text())
    with xr.open_dataset(out / "sweep.h5") as ds:
        own = str(ds.attrs["own_model_rule"])
        worst = float(np.nanmax(ds["tau_error_relative_peak"].values))
        stored = ds.load()
    assert own == "chapter"                       # the per-trajectory models: share-based
    error_sec = text[text.index("5.1 Open-loop torque error"):]
    assert f"own models, {own} rule (worst)" in error_sec
    assert "own simplified model (chapter rule: share-based classes of Sec. 3.4.1, no error " \
           "bound)" in error_sec
    summary = text[text.index("puma560: translational share"):text.index("The generalized")]
    said = float(re.search(r"errs by up to ([0-9.]+) %", summary).group(1))
    assert abs(said - 100 * worst) <= 0.01 * 100 * worst           # the stored worst case
    assert "no error bound" in summary
    assert ("guaranteed within" in summary) == (rule == "budget")
    caption = error_sec[error_sec.index("Relative peak open-loop torque error per joint, per"):]
    assert "(chapter rule: share-based" in caption
    assert ("merged model (budget rule" in caption) == (rule == "budget")
    # the words follow the stored rule: a dataset saying otherwise reads otherwise
    stored.attrs["own_model_rule"] = "budget"
    write_dataset(stored, tmp_path / "sweep.h5")
    html = write_sweep_report(tmp_path / "sweep.h5", tmp_path / "r", formats=["html"])[0]
    other = _text(html.read_text())
    assert "own models, budget rule (worst)" in other and "own models, chapter rule" not in other


def test_figure_marks_and_merged_none_are_explained(swept):
    rule, out = swept
    text = _text((out / "sweep_report.html").read_text())
    for fig in ("Figure 1.", "Figure 2."):
        caption = text[text.index(fig):][:900]
        assert "Grey dots" in caption and "one dot per trajectory" in caption
    classes = text[text.index("Figure 3."):][:600]
    assert "\u201cnone\u201d: it keeps neither part" in classes
    assert ("within the budget" in classes) == (rule == "budget")


def test_settings_state_each_setting_once_in_words(swept):
    _, out = swept
    html = (out / "sweep_report.html").read_text()
    rows = _rows(html, "settings")
    items = [r[0] for r in rows]
    values = " | ".join(r[1] for r in rows if len(r) > 1 and r[0] != "command")
    assert len(items) == len(set(items))
    assert not any("_" in item or item.startswith(("mounting", "merged ")) for item in items)
    assert values.count("seed 1") == 1 and "seed" not in items
    assert values.count(f"gd-analyze {__version__}") == 1                  # one version
    assert values.count("9.8") == 1                                         # gravity once
    assert "conventions" not in items and "CF-1" not in values
    assert "trajectories per task" not in values


def test_counts_are_the_merged_choices_in_the_tables_words(swept):
    # the counts under Sec. 5 called the budget rule's dropped elements
    # "negligible" (the Stanford sweep's D23, translational on every trajectory, among them)
    _, out = swept
    html = (out / "sweep_report.html").read_text()
    line = re.search(r'<p class="counts">(.*?)</p>', html, flags=re.S).group(1)
    said = {k: int(v) for k, v in re.findall(r">\s*(\w+): (\d+)\s*<", line)}
    rows = _table(html, "Table 4.1: ")
    choice = [r[-1] for r in rows[1:]]
    words = ("tran", "rot", "both", "none") + (("pruned",) if "pruned" in choice else ())
    assert said == {c: choice.count(c) for c in words}, said
    assert sum(said.values()) == len(choice)          # every element counted once


def test_a_merged_model_built_without_gravity_is_said_once_to_have_none(shared_main):
    """A sweep with ``--gravity 0,0,0``: Pinocchio's generalized gravity is 0 on the swept
    trajectory, so no gravity part of a base parameter acts: the report counts the inertial and
    velocity parts, says once that there is no gravity, and never that terms or parts of c are
    kept or dropped (the summary included)."""
    out = shared_main("sweep", "puma560", SHIPPED, SHIPPED, "--held-out", "0",
                      "--gravity", "0,0,0")
    model = load_model(out / "merged_model.json")
    q = read_trajectory(SHIPPED, n_joints=6).q
    assert not np.any(reference_terms(model.robot, q, np.zeros_like(q)).c)      # c = 0
    contributing = model.recursive.contributing()
    assert not contributing[:, PART_NAMES.index("gravity")].any() and contributing.any()
    text = _text((out / "sweep_report.html").read_text(), nbsp=True)
    sec5 = text[text.index("5. Merged model"):text.index("5.1 Open-loop torque error")]
    assert (f"of the {int(contributing.sum())} inertial and velocity parts of their "
            "contributions that act on") in sec5, sec5
    assert text.count("The model was built without gravity (g = 0), so c \u2261 0.") == 1
    assert not re.search(r"keeps c whole|gravity parts? (of|is)|drops the gravity|terms of c",
                         text), text


def test_a_chapter_rule_merged_model_without_gravity_is_said_once_to_have_none(tmp_path):
    """``sweep ... --rule chapter --gravity 0,0,0`` (the two-link arm, one 11-set-point
    trajectory twice): Pinocchio's generalized gravity of the merged model's arm is 0 along
    it, so c has no term: the rule is said to drop parts of D and h only, without an equation
    that adds c, the model's parts of D and h are counted and the absence of gravity said
    once, and nothing says that c is kept."""
    from gd_analyze.report.sweep import sweep_context

    csv = tmp_path / "two.csv"
    assert main(["plan", "two-link", "-o", str(csv), "--setpoints", "11"]) == 0
    assert main(["sweep", "two-link", str(csv), str(csv), "--held-out", "0", "--rule", "chapter",
                 "--gravity", "0,0,0", "--no-report", "-q", "-o", str(tmp_path / "s")]) == 0
    model = load_model(tmp_path / "s" / "merged_model.json")
    q = read_trajectory(csv, n_joints=2).q
    assert not np.any(reference_terms(model.robot, q, np.zeros_like(q)).c)      # c = 0
    with xr.open_dataset(tmp_path / "s" / "sweep.h5") as ds:
        ctx = sweep_context(ds.load())
    said = [ctx["summary"], ctx["merged_heading"], ctx["merged_text"]]
    text = "\n".join(said)
    no_gravity = "The model was built without gravity (g = 0), so c \u2261 0."
    assert text.count(no_gravity) == 1
    assert "The chapter rule drops parts of D and h only. This rule has no error bound" in text
    assert re.search(r"of the \d+ parts of D and h\. " + re.escape(no_gravity), text), text
    assert not re.search(r"keeps c whole|never a term of gravity|\+ c\b|terms of c", text), text


def test_merged_model_cost_and_gravity_said_against_the_models(swept):
    # what the model keeps of c, and its cost against the exact recursive
    # model, the full explicit model and Newton-Euler, from the model written beside the report
    import json

    from gd_analyze.dynamics.opcount import operation_counts
    from gd_analyze.store.explicit_cache import explicit_terms
    from gd_analyze.store.model_file import load_model

    rule, out = swept
    html = (out / "sweep_report.html").read_text()
    text = _text(html)
    model = load_model(out / "merged_model.json")
    sec5 = text[text.index("5. Merged model"):text.index("5.1 Open-loop torque error")]
    summary = text[text.index("puma560: translational share"):text.index("The generalized")]
    full_terms, _ = explicit_terms(model.robot)
    full_c = int(np.sum(np.asarray(full_terms.kind) == "c"))
    if rule == "budget" and model.form == "recursive":          # the names it drops
        gone = model.recursive.stated_facts()["gravity_dropped"]
        said = ("keeps c whole (no gravity part is dropped)" if not gone else
                f"drops the gravity part of {len(gone)} base parameter")
    elif rule == "budget":
        kept_c = int(np.sum(np.asarray(model.terms.kind) == "c"))
        said = ("keeps c whole" if kept_c == full_c else
                f"drops {full_c - kept_c} of the {full_c} terms of c")
    else:
        said = "keeps c whole (the chapter rule drops parts of D and h only)"
    assert said in sec5 and said in summary
    rows = {r[0]: r for r in _table(html, "Table 5.2: ")[1:]}
    ne = operation_counts(model.robot)["newton-euler"]
    assert rows["Newton-Euler (as implemented)"][1:3] == [f"{int(ne['multiplications']):,}",
                                                          f"{int(ne['additions']):,}"]
    merged = f"merged model ({model.form} form)"
    assert {merged, "exact recursive model", "full explicit model"} <= set(rows)
    stored = json.loads((out / "merged_model.json").read_text())
    assert stored["form"] == model.form == ("recursive" if rule == "budget" else "explicit")
    if rule == "budget":
        for name, key in ((merged, "cost"), ("full explicit model", "full_cost")):
            assert rows[name][1:3] == [f"{stored[key]['multiplications']:,}",
                                       f"{stored[key]['additions']:,}"]
    for words in ("exact recursive model:", "full explicit model:", "Newton-Euler"):
        assert words in summary and words in sec5
    ops = {k: int(r[3].replace(",", "")) for k, r in rows.items()}
    mine = ops[merged]
    if rule == "budget":                 # never dearer than the exact recursive model
        assert mine <= ops["exact recursive model"]
    assert ("more than the full explicit model" in sec5) == (mine > ops["full explicit model"])
    assert ("more than the exact recursive model" in sec5) == (
        mine > ops["exact recursive model"])


@pytest.mark.parametrize("guarantee", ["trajectory", "region"])
def test_held_out_error_is_reported_as_measured(tmp_path, guarantee):
    # the sweep measured its merged model on held-out trajectories (merged_model.json) but the
    # report never said so: "guaranteed ... (not on others)" and nothing on the others; a
    # region model's proof covers those inside the region (random plans within the limits)
    import json

    out = tmp_path / "sweep"
    assert main(["sweep", "puma560", "--random", "2", "--seed", "1",
                 "--held-out", "2", "-o", str(out), "-q", "--guarantee", guarantee]) == 0
    spec = json.loads((out / "merged_model.json").read_text())
    held = spec["validation"]["held_out"]
    rel = np.asarray(held["peak_abs_error"]) / np.asarray(
        held["peak_tau"] if guarantee == "trajectory" else spec["guarantee"]["scale"])
    rel[5] = 0.0                               # joint 6: round-off (the arm's 2e-16)
    text = _text((out / "sweep_report.html").read_text())
    summary = text[text.index("puma560: translational share"):text.index("The generalized")]
    sec = text[text.index("5.1 Open-loop torque error"):]
    j = int(np.argmax(rel))
    said = (f"On 2 held-out random trajectories (another seed, not swept) the merged model's "
            f"error is measured, not guaranteed: at most {100 * rel[j]:.2f} % of peak |\u03c4 i "
            f"| over them (joint {j + 1}).")
    if guarantee == "region":                  # relative to s_i, as the guarantee is
        said = (f"On 2 held-out random trajectories (another seed, not swept) the merged "
                f"model's error is measured: at most {100 * rel[j]:.2f} % of s i (joint "
                f"{j + 1}); 2 of them lie in the region, where its bound is proved.")
    assert said in summary and said in sec, (said, summary)


def test_round_off_threshold_in_mathematics(swept):
    """The sweep's captions and figures wrote the round-off rule as the code-like "1e-12";
    every place writes it as the main report does, 10⁻¹² (the ranking's ROUND_OFF)."""
    from gd_analyze.ranking.ranking import ROUND_OFF
    from gd_analyze.report.numbers import decade_label

    _, out = swept
    html = (out / "sweep_report.html").read_text()
    text = _text(html)
    assert decade_label(ROUND_OFF) == "10\u207b\u00b9\u00b2"
    assert "1e-12" not in html and "1e\u221212" not in html
    assert text.count("at most 10\u207b\u00b9\u00b2 of") >= 2, text


def test_a_region_scale_names_its_torque_floor_only_where_there_is_one(shared_main, tmp_path):
    """s_i of a region model is max(largest |tau_i| over the region, floor): with the default
    floor 0 the summary says no "at least 0 N m"; a stored floor of 2 is said, after how s_i
    was found as sweep.h5 stores it."""
    out = shared_main("sweep", "puma560", "--random", "3", "--seed", "1",
                      "--held-out", "0", "--rule", "budget")      # the budget case of ``swept``

    def summary(html):
        text = _text(html)
        return text[text.index("puma560: translational share"):text.index("The generalized")]

    said = summary((out / "sweep_report.html").read_text())
    with xr.open_dataset(out / "sweep.h5") as ds:
        stored = ds.load()
    assert float(stored.attrs[SweepAttr.MERGED_TORQUE_FLOOR]) == 0.0
    found = stored.attrs[SweepAttr.MERGED_GUARANTEE_SCALE_SOURCE].split("|tau_i| ")[1]
    assert f"{found})" in said and "at least" not in said
    stored.attrs[SweepAttr.MERGED_TORQUE_FLOOR] = 2.0
    write_dataset(stored, tmp_path / "sweep.h5")
    html = write_sweep_report(tmp_path / "sweep.h5", tmp_path / "r", formats=["html"])[0]
    assert f"{found}, at least 2 N m)" in summary(html.read_text())


def test_the_merged_cost_agrees_in_number_with_its_counts():
    """Oracle: the counts given; a count of one is singular."""
    from gd_analyze.report.common import say

    assert say("merged_cost", mine=1, mul=1, add=0, others=[], table=False, chapter=False,
               recursive_cheaper=False, dearer=False).startswith(
        "It costs 1 operation per set point (1 multiplication, 0 additions);")
    assert say("merged_cost", mine=5, mul=2, add=3, others=[], table=False, chapter=False,
               recursive_cheaper=False, dearer=False).startswith(
        "It costs 5 operations per set point (2 multiplications, 3 additions);")


def test_worst_cases_rank_only_errors_above_round_off():
    """Oracle: the errors given against the round-off rule (1e-12 of the joint's peak |tau|).
    An exact merged model's round-off (a one-joint arm's 2.5e-14 %) is not ranked as its
    "largest torque errors"; where one trajectory's error is real, only it is named."""
    from types import SimpleNamespace

    from gd_analyze.report.markup import plain
    from gd_analyze.report.sweep import _worst_cases

    def said(peak):
        peak = np.array(peak, float)                                  # (K, n) [N m]
        tau = np.full(peak.shape, 10.0)
        merged = SimpleNamespace(region=True, scale=tau, variables={},
                                 sizes={"joint": peak.shape[1]})
        w = SimpleNamespace(merged=merged, merged_tau_error_peak=peak, tau_peak=tau,
                            merged_tau_error_relative_peak=peak / tau, sources=["a", "b"],
                            share_min=np.array([0.5]), share_max=np.array([0.5]))
        return plain(_worst_cases(w, ["D11"]))

    assert said([[2.5e-15, 0.0], [1e-15, 3e-16]]).startswith(
        "Worst cases: the merged model's torque error is round-off on every trajectory and "
        "joint.")
    real = said([[2.5e-15, 0.0], [0.1, 3e-16]])
    assert "largest torque errors are on b (1.00 % of" in real and "a (" not in real


def test_a_share_the_same_to_its_printed_digits_is_not_said_to_vary():
    """Oracle: the shares given. A one-joint arm's D11 is the same on every trajectory but
    for rounding (0.6667 and 0.6667 + 1e-16): it read "The widest box is that of D11, from
    0.6667 to 0.6667" and "The classes vary most for D11 (0.6667–0.6667)"."""
    from types import SimpleNamespace

    from gd_analyze.report.markup import plain
    from gd_analyze.report.sweep import _share_sentence, _worst_cases

    def sweep(low, high):
        merged = SimpleNamespace(region=True, scale=None, variables={}, sizes={"joint": 1})
        return SimpleNamespace(
            elements=["D11", "h1"], trajectories=3, class_fraction=[[0, 0, 1, 0]] * 2,
            share_min=np.array([low, 1.0]), share_max=np.array([high, 1.0]), merged=merged,
            merged_tau_error_peak=np.zeros((3, 1)), tau_peak=np.ones((3, 1)),
            merged_tau_error_relative_peak=np.zeros((3, 1)), sources=["a", "b", "c"])

    same = sweep(2 / 3, 2 / 3 + 1e-16)
    assert plain(_share_sentence(same, "D", [False, False])).endswith(
        " Every element has the same share on every trajectory.")
    assert "vary most" not in plain(_worst_cases(same, ["D11", "h1"]))
    apart = sweep(0.5, 0.6)
    assert plain(_share_sentence(apart, "D", [False, False])).endswith(
        " The widest box is that of D11, from 0.5000 to 0.6000.")
    assert "vary most for D11 (0.5000–0.6000)" in plain(_worst_cases(apart, ["D11", "h1"]))


def test_one_element_of_a_matrix_is_said_in_the_singular():
    """Oracle: the elements given, one of D (a one-joint arm read "each of the 1 elements")."""
    from types import SimpleNamespace

    from gd_analyze.report.markup import plain
    from gd_analyze.report.sweep import _share_sentence

    w = SimpleNamespace(elements=["D11", "h1"], trajectories=3, class_fraction=[[0, 0, 1, 0]] * 2,
                        share_min=np.array([0.5, 1.0]), share_max=np.array([0.6, 1.0]))
    assert plain(_share_sentence(w, "D", [False, False])).startswith(
        "shows the translational share of the 1 element of D over the 3 trajectories:")
    w.elements = ["D11", "D12", "D22", "h1"]
    w.class_fraction = [[0, 0, 1, 0]] * 4
    w.share_min, w.share_max = np.full(4, 0.5), np.full(4, 0.6)
    assert plain(_share_sentence(w, "D", [False] * 4)).startswith(
        "shows the translational share of each of the 3 elements of D over the 3 trajectories:")


def test_a_sweep_of_one_trajectory_says_it_in_the_singular(tmp_path):
    """Oracle: the one trajectory given. A sweep of one CSV read "scara, 1 trajectories",
    "over 1 trajectories (files)", "repeats the ranking over 1 trajectories"."""
    from gd_analyze.report.markup import plain
    from gd_analyze.report.sweep import sweep_context
    from gd_analyze.store.schema import open_sweep

    csv, out = tmp_path / "one.csv", tmp_path / "out"
    assert main(["plan", "two-link", "-o", str(csv)]) == 0
    assert main(["sweep", "two-link", str(csv), "-o", str(out), "--no-report", "-q",
                 "--held-out", "0"]) == 0
    with open_sweep(out / "sweep.h5") as ds:
        context = sweep_context(ds.load())
    assert context["title"] == "G-D dominance sweep: two-link, 1 trajectory"
    assert "over 1 trajectory (files), s = " in plain(context["summary"])
    assert plain(context["intro"]).count("repeats the ranking over 1 trajectory. ") == 1


def test_the_sweep_passages_agree_in_number_with_their_counts():
    """Oracle: the counts given (one trajectory; one bar of one colour)."""
    from gd_analyze.report.common import say
    from gd_analyze.report.markup import plain

    key = plain(say("sweep_key", K=1, s="0.9", e="0.01", pruned=False, round_off="r"))
    assert "of the element X over the 1 trajectory (box: quartiles;" in key
    said = plain(say("computed_on", cluster="here", K=1, batches=1, workers=0, many=False,
                     scheduler="", tasks=1, batch=1))
    assert said.startswith("here (the 1 trajectory in 1 batch: ranked")
    bars = plain(say("classes_shows", K=3, M=5, choices="both 5", one=1))
    assert "; 1 of the 5 bars is of one colour" in bars
    assert "; 2 of the 5 bars are of one colour" in plain(
        say("classes_shows", K=3, M=5, choices="both 5", one=2))


def test_a_chapter_merged_model_exact_but_for_round_off_is_said_so(tmp_path, one_joint_urdf):
    """Oracle: a physical identity. One revolute joint has h1 = 0 and the chapter rule keeps
    D11 whole (both parts: neither dominates), so the merged model is exact: its error is
    round-off, which the summary gave as "its largest peak torque error ... is 4.3e-14 %"."""
    from gd_analyze.report.markup import plain
    from gd_analyze.report.sweep import sweep_context
    from gd_analyze.store.schema import open_sweep

    out = tmp_path / "out"
    assert main(["sweep", str(one_joint_urdf), "--random", "2", "--rule", "chapter", "-o", str(out),
                 "--no-report", "-q", "--held-out", "0"]) == 0
    with open_sweep(out / "sweep.h5") as ds:
        assert list(ds["merged_choice"].values) == ["both", "none"]
        summary = plain(sweep_context(ds.load())["summary"])
    assert ("it has no error bound: its torque error is round-off on every trajectory and "
            "joint.") in summary


@pytest.mark.parametrize("guarantee", ["region", "trajectory"])
def test_an_exact_merged_models_measured_error_is_said_round_off(tmp_path, one_joint_urdf,
                                                                guarantee):
    """Oracle: a physical identity. One revolute joint: h1 = 0 and D11 whole, so the budget
    rule's merged model drops nothing that acts and is exact; its measured error, read
    "its largest measured peak error is 2.5e-14 % of s_i", is round-off."""
    from gd_analyze.report.markup import plain
    from gd_analyze.report.sweep import merged_claim
    from gd_analyze.store.schema import open_sweep

    out = tmp_path / "out"
    assert main(["sweep", str(one_joint_urdf), "--random", "2", "--guarantee", guarantee,
                 "-o", str(out), "--no-report", "-q", "--held-out", "0"]) == 0
    with open_sweep(out / "sweep.h5") as ds:
        claim = plain(merged_claim(ds.load()))
    assert "its measured error is round-off" in claim and "measured peak error" not in claim


def test_held_out_round_off_is_not_named_at_a_joint():
    """Oracle: the errors given against the round-off rule. Held-out errors all round-off
    read "at most 0.00 % of s_i (joint 1)", naming joint 1 as the worst of equal zeros."""
    from types import SimpleNamespace

    from gd_analyze.report.markup import plain
    from gd_analyze.report.sweep import _held_out

    def said(peak):
        m = SimpleNamespace(held_out_error_peak=np.array(peak), region=True,
                            held_out_tau_peak=np.array([10.0, 10.0]), torque_floor=0.0,
                            scale=np.array([[10.0, 10.0]]), held_out_trajectories=2,
                            held_out_inside_region=2, variables={}, sizes={"joint": 2})
        return plain(_held_out(m))

    assert said([2e-15, 1e-16]).endswith(
        "the merged model's error is measured: it is round-off on every one and every joint; "
        "2 of them lie in the region, where its bound is proved. ")
    assert "at most 1.00 % of s" in said([2e-15, 0.1])


def test_the_cost_caption_names_only_the_evaluators_of_its_table(tmp_path):
    """Oracle: the rows of Table 5.2. Its caption named "the full explicit model" on arms of
    8 and 10 joints (the PR2, the iCub) whose sweep derives none, so the table has no such row;
    here the two-link sweep's stored counts without that evaluator."""
    csv, out = tmp_path / "one.csv", tmp_path / "out"
    assert main(["plan", "two-link", "-o", str(csv)]) == 0
    assert main(["sweep", "two-link", str(csv), "-o", str(out), "--no-report", "-q",
                 "--held-out", "0"]) == 0
    with xr.open_dataset(out / "sweep.h5") as ds:
        ds = ds.load()
    ds = ds.sel(evaluator=[e for e in ds["evaluator"].values if e != "full explicit model"])
    write_dataset(ds, out / "fewer.h5")
    write_sweep_report(out / "fewer.h5", out / "report", formats=("html",))
    html = (out / "report" / "sweep_report.html").read_text()
    rows = [r[0] for r in _table(html, "Table 5.2: ")[1:]]
    assert rows[0].startswith("merged model") and rows[-1].startswith("Newton-Euler")
    caption = _text(html[html.index("Table 5.2: "):])[:300]
    for name in ("exact recursive model", "full explicit model"):
        assert (name in caption) <= (name in rows), (caption, rows)
