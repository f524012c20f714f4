"""The control report's statements about the simplified model and its verdict agree with the
model and the run (review 23, defects 1 and 2).

Models are built by the main job under both rules and with gravity parts dropped (a small EPS
keeps c whole, EPS = 0.05 drops gravity parts of the PUMA 560 in both forms). Oracles: the
main report's sentence on the same model (one wording, one count), and Pinocchio's
generalized gravity against the emitted model at rest (q̇ = q̈ = 0) for what it does with c.
"""

import importlib.util
import re
import shlex

import numpy as np
import pytest
import xarray as xr
from conftest import SHIPPED, built_once
from html_checks import context_texts, html_text

from gd_analyze import load_robot
from gd_analyze.cli import main
from gd_analyze.dynamics.pinocchio import reference_terms
from gd_analyze.jobs.control import run_control
from gd_analyze.model.mounting import with_mounting
from gd_analyze.report.control import write_control_report
from gd_analyze.store.control_dataset import write_control_dataset
from gd_analyze.store.model_file import load_model
from gd_analyze.symbolic.recursive_model import PART_NAMES
from gd_analyze.trajectory.trajectory import read_trajectory

#: Over 5 s on an idle machine (the module's fixtures): run on one interpreter in CI.
pytestmark = pytest.mark.slow

CONFIGS = {"budget-recursive": ["--rule", "budget", "--form", "recursive"],
           "chapter": ["--rule", "chapter"],
           "gravity-dropped-recursive": ["--form", "recursive", "--tolerance", "0.1",
                                         "--guarantee", "trajectory"],
           # tests/report/test_text_truth.py's run of the same name: one main job for both
           "gravity-dropped-explicit": ["--form", "explicit", "--tolerance", "0.05"]}


def _text(html):
    return html_text(html, nbsp=True)


@pytest.fixture(scope="module", params=list(CONFIGS))
def built(request, shared_main):
    """The main job of a configuration and the control report of its model, built once a
    session (conftest's built_once: a folder shared by the xdist workers, read only)."""
    # the main job (shared, read only: tests/report/test_text_truth.py runs the same ones)
    run = shared_main("puma560", SHIPPED, *CONFIGS[request.param])

    def build(folder):
        (folder / "main").symlink_to(run, target_is_directory=True)
        # the control dataset and report of the model as read from its file; the full-model
        # controller alone (the model's statements do not depend on the closed loop, and a
        # model with EPS = 0.05 makes the simplified loop too stiff to integrate)
        path = folder / "main" / "simplified_model.json"
        result = run_control(load_model(path), read_trajectory(SHIPPED, n_joints=6),
                             controllers=("full",), grid_points=31, model_path=path)
        write_control_dataset(result, folder / "control.h5")
        write_control_report(folder / "control.h5", folder / "control")
    return request.param, built_once(f"control-text-{request.param}", build)


def _c_whole(name, folder):
    """Pinocchio's oracle: the emitted model's torque at rest equals the gravity loading c."""
    robot = load_robot("puma560")
    with xr.open_dataset(folder / "main" / "results.h5") as ds:
        q, scale = ds["q"].values, ds["tau_peak"].values
    spec = importlib.util.spec_from_file_location(f"ctl_{name.replace('-', '_')}",
                                                  folder / "main" / "simplified_model.py")
    model = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(model)
    rest = np.zeros_like(q)
    error = np.max(np.abs(model.tau(q, rest, rest) - reference_terms(robot, q, rest).c),
                   axis=0) / scale
    assert np.all(np.isfinite(error))
    return bool(np.all(error <= 1e-9))


def test_control_report_states_the_model_as_the_main_report_does(built):
    name, folder = built
    main_text = _text((folder / "main" / "report.html").read_text())
    sentence = main_text[main_text.index("The simplified model "):
                         main_text.index(" Its largest open-loop")]
    control = _text((folder / "control" / "control_report.html").read_text())
    model_sec = control[control.index("5. Simplified model"):control.index("6. Provenance")]
    with xr.open_dataset(folder / "main" / "results.h5") as ds:
        form, rule = str(ds.attrs["simplified_form"]), str(ds.attrs["simplified_rule"])
    if form == "recursive":
        assert sentence in model_sec, (sentence, model_sec)     # same counts, same words
        assert "every element of D and h" not in model_sec
    else:                    # explicit: the parts of D and h in the same words; c below
        assert sentence[:sentence.index(" and keeps") if "keeps c" in sentence
                        else sentence.index(" and drops terms")] in model_sec
    whole = _c_whole(name, folder)
    assert ("keeps c whole" in model_sec) == whole, model_sec
    assert bool(re.search(r"drops[^.;]* of c\b|from c\b", model_sec)) == (not whole)
    assert ("no error bound" in model_sec) == (rule == "chapter")
    assert ("guaranteed" in model_sec) == (rule == "budget")
    assert not name.startswith("gravity-dropped") or not whole      # the case is exercised
    assert not name == "budget-recursive" or whole


def test_sec5_of_a_model_built_without_gravity_says_so_once_and_counts_no_gravity_part(
        shared_main):
    """A model built with ``--gravity 0,0,0``: Pinocchio's generalized gravity of its arm is 0,
    so no gravity part of a base parameter acts (none is among the contributing pairs): Sec. 5
    counts the inertial and velocity parts, says once that there is no gravity, and never
    that a gravity part is kept or dropped."""
    run = shared_main("puma560", SHIPPED, "--gravity", "0,0,0")    # shared: test_text_truth

    def build(folder):
        path = run / "simplified_model.json"
        result = run_control(load_model(path), read_trajectory(SHIPPED, n_joints=6),
                             controllers=("full",), grid_points=31, model_path=path)
        write_control_dataset(result, folder / "control.h5")
        write_control_report(folder / "control.h5", folder / "control")
    folder = built_once("control-text-no-gravity", build)
    model = load_model(run / "simplified_model.json")
    with xr.open_dataset(run / "results.h5") as ds:
        q = ds["q"].values
    assert not np.any(reference_terms(model.robot, q, np.zeros_like(q)).c)    # c = 0
    contributing = model.recursive.contributing()
    assert not contributing[:, PART_NAMES.index("gravity")].any() and contributing.any()
    control = _text((folder / "control" / "control_report.html").read_text())
    sec5 = control[control.index("5. Simplified model"):control.index("6. Provenance")]
    said = (f"of the {int(contributing.sum())} inertial and velocity parts of their "
            "contributions that act on")
    assert said in sec5, sec5
    assert control.count("The model was built without gravity (g = 0), so c \u2261 0.") == 1
    assert not re.search(r"keeps c whole|gravity parts? (of|is)|drops the gravity|terms of c",
                         control), sec5


def test_control_verdict_keeps_revolute_and_prismatic_joints_apart():
    """A prismatic joint's error in m is never reported, or compared, in rad."""
    from gd_analyze.report.control import control_verdict

    prismatic = np.array([False, False, True])
    peaks = {"full": np.array([1e-10, 1e-10, 1e-11]),
             "simplified": np.array([2e-4, 1e-4, 5e-3]),        # 5 mm: beyond 1 mm
             "pd_gravity": np.array([1e-2, 1e-2, 2e-2])}
    text = control_verdict(peaks, prismatic, np.array([0.1, 0.2, 3.0]),
                           (1e-3, 1e-3)).replace("\u00a0", " ")
    assert "NOT good enough" in text or "degrades" in text
    assert "joints 1, 2 revolute (rad, N m); joint 3 prismatic (m, N)" in text
    assert "2.00e-04 rad, 0.005 m" in text and "0.2 N m, 3 N" in text
    assert "0.02 rad" not in text and "0.005 rad" not in text       # no max across units
    looser = control_verdict(peaks, prismatic, None, (1e-3, 1e-2)).replace("\u00a0", " ")
    assert "good enough" in looser and "NOT" not in looser
    revolute = control_verdict({k: v[:2] for k, v in peaks.items()},
                               prismatic[:2]).replace("\u00a0", " ")
    assert " m " not in revolute and "joint" not in revolute


def test_the_verdict_never_vouches_for_a_model_its_guarantee_does_not_cover():
    """A run within the tolerance is "good enough" only where the model's guarantee covers it;
    else the sentence says the guarantee does not cover the motion."""
    from gd_analyze.report.control import control_verdict

    peaks = {"full": np.array([1e-9]), "simplified": np.array([1e-5])}
    said = {c: control_verdict(peaks, np.array([False]), covered=c) for c in (True, False)}
    assert "good enough" in said[True] and "does not cover" not in said[True]
    assert "good enough" not in said[False] and "guarantee does not cover" in said[False]



def test_from_an_offset_the_verdict_judges_the_loops_departure_not_the_offset(puma, shipped):
    """From q(0) - q_d(0) = 0.02 rad every controller's peak tracking error is the offset's,
    so comparing peaks vouches for any model. The verdict judges instead how far the
    simplified-model loop departs from the full-model loop, max |q_s - q_f| (the oracle: the
    two runs' own q), against the tolerance: a model without h (Eq. (3.4-24)'s h dropped)
    is refused at half its departure and passes at twice it (within the tolerance "in this
    run": the model states no guarantee)."""
    from gd_analyze.ranking.ranking import element_labels
    from gd_analyze.report.control import dataset_verdict
    from gd_analyze.simplify.simplified import SimplifiedModel
    from gd_analyze.store.control_dataset import control_dataset

    crude = SimplifiedModel(robot=puma, choices={lab: "both" if lab.startswith("D") else "none"
                                                 for lab in element_labels(puma.n)},
                            dominance_threshold=0.9, negligible_threshold=0.01)
    res = run_control(crude, shipped, q0_offset=0.02, controllers=("full", "simplified"),
                      cost=False, t_end=1.0)
    departure = np.abs(res.runs["simplified"].q - res.runs["full"].q).max()
    peaks = {c: np.abs(res.runs[c].error).max() for c in ("full", "simplified")}
    assert peaks["full"] == pytest.approx(0.02) and peaks["simplified"] == pytest.approx(0.02)
    assert 1e-5 < departure < 0.01                   # the model's own error, not the offset
    for tol, good in ((departure / 2, False), (2 * departure, True)):
        ds = control_dataset(res)
        ds.attrs.update(verdict_tolerance_revolute=tol, verdict_tolerance_prismatic=tol)
        said = " ".join(dataset_verdict(ds)["verdict"].replace("\u00a0", " ").split())
        passes = "is good enough" in said or "tracks within the tolerance" in said
        assert passes == good and ("NOT good enough" in said) != good, said
        assert f"departs from the full-model controller's by at most {departure:.3g} rad" in said


def test_sec5_keeps_the_desired_motions_guarantee_where_only_the_closed_loop_leaves():
    """Region guarantee, desired motion inside, the closed loop's states outside: the open-loop
    error along the desired motion is still guaranteed, the closed loop's is not; a desired
    motion outside the region: nothing is guaranteed."""
    from gd_analyze.report.control import scope_sentences

    facts = {"model_rule": "budget", "model_guarantee_kind": "region",
             "model_scope": "within 1 % of s_i at every state of the region (proved)",
             "model_guarantee_covered": 0}
    loop = scope_sentences({**facts, "model_guarantee_coverage": "the closed loop of the "
                            "simplified-model controller is outside the model's region"}, 0.01)
    assert "along the desired motion is guaranteed" in loop and "not guaranteed" not in loop
    assert "where the controller evaluates it is not" in loop
    desired = scope_sentences({**facts, "model_guarantee_coverage": "outside the model's "
                               "region: joint 1's q reaches 3 rad"}, 0.01)
    assert "is guaranteed" not in desired and "not guaranteed" in desired
    # a trajectory-kind guarantee, measured at its trajectory's set points: guaranteed there
    own = scope_sentences({**facts, "model_guarantee_kind": "trajectory",
                           "model_guarantee_covered": 1, "model_guarantee_coverage": "it is a "
                           "trajectory the model was built on (same SHA-256)"}, 0.01)
    assert "at its set points is guaranteed" in own and "along the desired motion" not in own
    assert "where the controller evaluates the model, it is not" in own


def test_noise_floor_row_in_the_notation_of_the_torque_difference_table():
    """Table 3.1: a joint whose differences are all integrator noise shows its floor in the
    notation of the other joints' numbers, not "0.000012" beside "5.06e-04"."""
    from gd_analyze.report.control import _with_columns

    rows = _with_columns([(["peak"], [5.06e-4, 3e-6], [False, True]),
                          (["floor"], [4.2e-8, 1.2e-5], [False, False])], one=True)
    cells = [c for r in rows for c in r[1:] if c != "\u2261 0"]
    assert len(cells) == 3 and all("e-" in c for c in cells), rows


def test_verdict_tolerance_option_reaches_the_report(tmp_path, shared_two_link_control):
    """``control --verdict-tolerance RAD,M``: checked (exit 2 on a bad value), stored in
    control.h5 and stated in the verdict and the provenance. The model and trajectory are
    the shared two-link run's (11 set points: the option's path does not depend on the
    count), read only; the control run is this test's own."""
    assert main(["control", "x.json", "y.csv", "--verdict-tolerance", "-1"]) == 2
    assert main(["control", "x.json", "y.csv", "--verdict-tolerance", "1,2,3"]) == 2
    shared, _ = shared_two_link_control(11)
    csv = shared / "two.csv"
    argv = ["control", str(shared / "main" / "simplified_model.json"), str(csv),
            "-o", str(tmp_path / "control"), "-q", "--verdict-tolerance", "0.002,0.004"]
    assert main(list(argv)) == 0
    with xr.open_dataset(tmp_path / "control" / "control.h5") as ds:
        assert (float(ds.attrs["verdict_tolerance_revolute"]),
                float(ds.attrs["verdict_tolerance_prismatic"])) == (0.002, 0.004)
    text = _text((tmp_path / "control" / "control_report.html").read_text())
    assert "the larger of 0.002 rad and twice the full model's" in text     # all revolute
    command = shlex.join(["gd-analyze", *argv])        # the provenance's command line, as given
    assert text.count(command) == 1
    text = text.replace(command, "")
    assert "verdict tolerance 0.002 rad" in text and "0.004" not in text


def test_intro_names_the_models_rule_and_provenance_says_each_file_once(built):
    # the intro said "the simplified model of Sec. 3.4.1" for a budget-rule model
    name, folder = built
    control = _text((folder / "control" / "control_report.html").read_text())
    intro = control[control.index("The arm, simulated"):control.index("1. Set-up")]
    with xr.open_dataset(folder / "main" / "results.h5") as ds:
        rule = str(ds.attrs["simplified_rule"])
        eps = float(ds.attrs["simplified_tolerance"]) if rule == "budget" else None
        sha = str(ds.attrs["input_sha256"])
    if rule == "budget":
        assert f"simplified model (error-budget rule, \u03b5 = {eps:g})" in intro, intro
        assert "3.4.1" not in intro
    else:
        assert "simplified model (the chapter's share-based classes, Sec. 3.4.1)" in intro
    # the model was built on this trajectory: its SHA-256 once (Table 1.1), not again
    assert control.count(sha) == 1, control.count(sha)
    # each setting in words: the derivatives row read "file" alone
    prov = control[control.index("6. Provenance"):]
    assert "file: read from the file (its velocity and acceleration columns)" in prov \
        or "cubic-spline: derived from q" in prov, prov


def test_no_code_names_in_the_control_text(built):
    # code names stand in for words ("gd_analyze.dynamics.opcount", tau_s, D_ij)
    _, folder = built
    control = _text((folder / "control" / "control_report.html").read_text())
    body = control[:control.index("6. Provenance")]
    code = r"gd_analyze\.\w+|\b(?:tau|share|scale|D|h|c|q|qd|qdd|Kp|Kv|wn)_\w+|\bEPS\b"
    assert not re.search(code, body), re.findall(code, body)   # file names may have "_"
    assert not re.search(r"\bqd{1,2}\b", body), re.findall(r".{30}\bqd{1,2}\b.{10}", body)
    # joints named as the main report names them ("joint 1"), never "J1"
    assert not re.search(r"\bJ\d\b", control), re.findall(r".{20}\bJ\d\b", control)
    assert "joint 1 [rad]" in control


def test_settings_said_once_and_markers_as_drawn(shared_two_link_control):
    # presentation: the summary listed "20, 20, 20, ... rad/s", the integrator row
    # printed "rtol = 1.00000e-08", Fig. 2's caption said "markers: set points" where every
    # k-th is marked, and the noise scale was "the joint's scale" in one place and "the
    # joint's range of motion" in another
    from gd_analyze.report.control import control_figures

    folder, ds = shared_two_link_control(200)       # shared, read only
    assert np.all(ds.attrs["wn"] == 20) and np.all(ds.attrs["zeta"] == 1)   # README defaults
    text = _text((folder / "control" / "control_report.html").read_text())
    summary = text[text.index("two-link along"):text.index("The arm, simulated")]
    assert "\u03c9 n = 20 rad/s on every joint, \u03b6 = 1 on every joint." in summary, summary
    assert f"rtol = {float(ds.attrs['rtol']):g}, atol = {float(ds.attrs['atol']):g}" in text
    assert "range of motion" not in text
    # the torque difference is integrator noise on every joint here (Table 3.1 says so), so
    # neither the summary nor the verdict gives its digits (the table's last row is the
    # noise floor itself)
    table = text[text.index("Table 3.1:"):text.index("Applied torques:")]
    rows = table.split("data.")[1].split("noise floor")
    assert table.count("\u2261 0") >= 2 * len(ds["joint"]) and "e-0" not in rows[0]
    assert len(rows) == 2 and "e-0" in rows[1]
    for said in (summary, text[:text.index("two-link along")]):
        assert re.search(r"torque differ[^;.]*: \u2261 0 \(integrator noise\)|by at most "
                         r"\u2261 0 \(integrator noise\)", said), said
    scale = "the joint's scale, max(range, peak |q d |)"
    tol = f"{max(float(ds.attrs['rtol']), 1e-12):g}"
    for where in ("Table 2.1:", "Figure 1."):
        said = text[text.index(where):][:400]
        assert f"at most {tol} of {scale}" in said, said
    figures = control_figures(ds)
    for key, number in (("error", 1), ("tau_difference", 2), ("tau", 3)):
        caption = text[text.index(f"Figure {number}."):][:300]
        drawn = {line.get_markevery() for ax in figures[key].axes for line in ax.get_lines()
                 if line.get_marker() in ("o", "s", "^")}
        if key == "tau_difference" and not drawn:     # nothing dropped: all integrator noise
            assert "\u2261 0 on every joint (integrator noise)" in " ".join(
                " ".join(t.get_text().split()) for t in figures[key].texts)
            # no markers to describe, and the empty panels span the run's times
            assert "no curve drawn" in caption and "markers: every" not in caption, caption
            t = ds["time"].values.astype(float)
            for ax in figures[key].axes:
                if ax.get_title().startswith("joint"):
                    assert ax.get_xlim() == pytest.approx((0.0, t[-1] - t[0])), ax.get_xlim()
            continue
        k = int(re.search(r"markers: every (\d+)\w\w set point", caption).group(1))
        strides = {m[1] if isinstance(m, tuple) else m for m in drawn}   # (start, k): staggered
        assert strides == {k}, (key, drawn, k)
        assert -(-200 // k) <= 12                     # at most 12 markers a line


def test_the_error_caption_names_only_the_controllers_drawn(shared_two_link_control):
    """Oracle: the curves Fig. 1 draws (their labels). A controller whose tracking error is
    integrator noise on every joint has no curve and no markers, so its caption does not give
    its first marker (the full-model controller without an initial offset was listed)."""
    from gd_analyze.report.control import CONTROLLER_LABELS, control_figures

    folder, ds = shared_two_link_control(200)       # shared, read only
    figure = control_figures(ds)["error"]
    drawn = {line.get_label() for ax in figure.axes for line in ax.get_lines()
             if not line.get_label().startswith("_")}
    assert drawn and drawn < set(CONTROLLER_LABELS.values())   # some controller is not drawn
    text = _text((folder / "control" / "control_report.html").read_text())
    caption = text[text.index("Figure 1."):text.index("Figure 2.")]
    named = set(re.findall(r"set point[s]? (?:\d+, |\d+ and )*?\d+ \(([^)]+)\)", caption)) | set(
        re.findall(r"(?:, |and )\d+ \(([^)]+)\)", caption))
    assert named == drawn, (named, drawn, caption)


def test_a_joint_type_whose_torque_difference_is_noise_reads_as_the_table(
        shared_two_link_control):
    """The PR2 (prismatic torso) said "by at most 3.30e-06 N m, 0 N" where Table 3.1 gives
    joint 1's difference as \u2261 0: a value at or below its joint's noise floor is said
    \u2261 0 in the summary and the verdict too, never as a measured 0. Oracle: the table's
    rule, the stored noise floor."""
    from gd_analyze.report.control import dataset_verdict

    _, ds = shared_two_link_control(11)     # shared; this test changes its own loaded copy
    ds["joint_type"] = ds["joint_type"].copy(data=np.array(["revolute", "prismatic"], object))
    peak = ds["tau_difference_peak"].values
    ds["tau_difference_floor"].values[:] = [peak[0] / 2, 2 * peak[1]]   # joint 2: noise
    assert 0 < peak[1] <= ds["tau_difference_floor"].values[1]
    judged = dataset_verdict(ds)
    for said in (judged["summary"], judged["verdict"]):
        said = said.replace("\u00a0", " ")
        assert ", \u2261 0 N" in said and ", 0 N" not in said, said


#: The sentence of Sec. 5 on a model built without gravity (tests/report/test_text_truth.py).
NO_GRAVITY = "The model was built without gravity (g = 0), so c \u2261 0."
#: The two-link arm's gravity in its robot file, in the world [m/s^2].
TWO_LINK_G = (0.0, -9.8062, 0.0)


def _gravity_runs(folder):
    """Two-link models (11 set points) built with the robot file's gravity and without
    (``--gravity 0,0,0``, the recursive form), each under control of an arm with its gravity
    and of one with the other (the control command's own ``--gravity``), as
    ``<model>-<arm>.h5``; the weightless model's file made an older one (no ``round_off``:
    which pairs act not recorded) and controlled, ``older.h5``; and what the control command
    printed for the weightless model on a weightless arm."""
    import contextlib
    import io
    import json

    csv = folder / "two.csv"
    assert main(["plan", "two-link", "-o", str(csv), "--setpoints", "11"]) == 0
    for model, options in (("with", []), ("none", ["--gravity", "0,0,0", "--form", "recursive"])):
        assert main(["two-link", str(csv), "-o", str(folder / model), "--guarantee", "trajectory",
                     "--no-report", "-q", *options]) == 0
    spec = json.loads((folder / "none" / "simplified_model.json").read_text())
    for key in ("round_off", "dropped_round_off"):
        del spec["recursive"][key]
    (folder / "older.json").write_text(json.dumps(spec))
    trajectory = read_trajectory(csv, n_joints=2)
    for model, arm in (("with", "with"), ("with", "none"), ("none", "with"), ("older", "none")):
        path = folder / ("older.json" if model == "older" else f"{model}/simplified_model.json")
        loaded = load_model(path)
        plant = with_mounting(loaded.robot, gravity=TWO_LINK_G if arm == "with" else (0, 0, 0))
        result = run_control(loaded, trajectory, controllers=("full", "simplified", "pd_gravity"),
                             grid_points=31, cost=False, model_path=path, plant=plant)
        write_control_dataset(result, folder / f"{model}-{arm}.h5")
    printed = io.StringIO()                 # the command itself, on its own model's arm
    with contextlib.redirect_stdout(printed):
        assert main(["control", str(folder / "none" / "simplified_model.json"), str(csv),
                     "-o", str(folder / "control"), "--no-report"]) == 0
    (folder / "printed.txt").write_text(printed.getvalue(), encoding="utf-8")


@pytest.fixture(scope="module")
def gravity_runs():
    return built_once("control-text-gravity-runs", _gravity_runs)


def _weightless(robot, q):
    """Pinocchio's oracle: the arm's generalized gravity is 0 along q."""
    return not np.any(reference_terms(robot, q, np.zeros_like(q)).c)


@pytest.mark.parametrize("model, arm", [("with", "with"), ("with", "none"), ("none", "with"),
                                        ("none", "none")])
def test_pd_controller_and_model_are_said_with_the_gravity_of_their_own_arm(
        gravity_runs, model, arm):
    """The PD controller adds the controlled arm's gravity loading c, the simplified model
    its own (the control command's ``--gravity`` need not be the model's). Oracle: Pinocchio's
    generalized gravity of each arm along the run. Where the controlled arm's is 0 the PD
    controller is plain PD, named so in the report's every text and in control.h5, its law
    without c, said once; where the model's is 0, Sec. 5 says so once, whatever the arm."""
    from gd_analyze.report.control import control_context

    path = gravity_runs / ("control/control.h5" if (model, arm) == ("none", "none")
                           else f"{model}-{arm}.h5")
    with xr.open_dataset(path) as ds:
        ds = ds.load()
    q = ds["q_d"].values
    plant = load_robot("two-link")
    plant_without = _weightless(with_mounting(plant, gravity=(0.0, 0.0, 0.0)), q)
    assert plant_without and not _weightless(plant, q)           # the oracle tells them apart
    pd_free = _weightless(plant if arm == "with" else with_mounting(plant, gravity=(0, 0, 0)), q)
    model_free = _weightless(load_model(gravity_runs / model / "simplified_model.json").robot, q)
    assert (pd_free, model_free) == (arm == "none", model == "none")
    ctx = control_context(ds)
    said = "\n".join(context_texts(ctx)).replace("\u00a0", " ")
    name = "PD" if pd_free else "PD + gravity"
    assert f"{name}: peak |e|" in ctx["summary"] and f", {name} " in ctx["verdict"]
    assert (f"{name}:" in ctx["gains_note"]) and (" \u0117 + c " in ctx["gains_note"]) != pd_free
    assert ("PD + gravity" in said) != pd_free and ("gravity compensation" in said) != pd_free
    assert said.count("the controlled arm has no gravity (g = 0)") == int(pd_free)
    law = str(ds["controller_description"].sel(controller="pd_gravity").values)
    assert law.startswith(name) and law.endswith(" + c") != pd_free, law
    assert ds["Kp_pd"].attrs["long_name"].startswith(f"{name} position gain")
    assert f"; {name}: Kp_pd" in ds.attrs["gains"]
    assert said.count(NO_GRAVITY) == int(model_free) and (NO_GRAVITY in ctx["model_note"]) \
        == model_free, ctx["model_note"]


def test_the_control_command_prints_plain_pd_on_an_arm_without_gravity(gravity_runs):
    """The printed rows and verdict name the controllers as the report does: plain PD where
    the controlled arm's generalized gravity (Pinocchio) is 0; the key ``pd_gravity`` stays in
    control.h5 and ``--json``."""
    printed = (gravity_runs / "printed.txt").read_text(encoding="utf-8")
    with xr.open_dataset(gravity_runs / "control" / "control.h5") as ds:
        q, keys = ds["q_d"].values, [str(c) for c in ds["controller"].values]
    arm = with_mounting(load_robot("two-link"), gravity=(0.0, 0.0, 0.0))
    assert _weightless(arm, q) and "pd_gravity" in keys
    rows = [line.split()[0] for line in printed.splitlines()[2:5]]
    assert rows == ["full", "simplified", "pd"], printed
    assert "PD + gravity" not in printed and "pd_gravity" not in printed
    assert ", PD " in printed.replace("\u00a0", " ")


def test_an_older_model_file_counts_no_gravity_part_of_a_weightless_arm(gravity_runs):
    """A model file that does not record which pairs act (no ``round_off``, an older file)
    counted every (parameter, part) pair, the gravity parts of an arm without gravity too:
    "of the 12 inertial and velocity parts" of 4 base parameters. Oracle: Pinocchio's
    generalized gravity of the model's arm is 0, so no gravity part exists; the count is
    every inertial and velocity pair (the file records no more), with the caveat."""
    from gd_analyze.report.control import control_context

    older = load_model(gravity_runs / "older.json")
    with xr.open_dataset(gravity_runs / "older-none.h5") as ds:
        ds = ds.load()
    assert _weightless(older.robot, ds["q_d"].values)
    assert older.recursive.round_off is None              # the case: an older file
    b = len(older.recursive.names)
    note = control_context(ds)["model_note"].replace("\u00a0", " ")
    assert re.search(f"of the {2 * b} inertial and velocity parts of their contributions that "
                     r"act on [\w ]+ \(or are structurally 0", note), note
    assert NO_GRAVITY in note
