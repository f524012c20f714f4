"""The torque-error figure of the simplified model (gd_analyze.report.simplified_section)."""

import numpy as np
import pytest
import xarray as xr
from conftest import ROOT

from gd_analyze import load_robot
from gd_analyze.jobs.analyze import analyze
from gd_analyze.jobs.options import AnalysisOptions, SimplifyOptions
from gd_analyze.report.simplified_section import ROUND_OFF, error_figure, simplified_caption
from gd_analyze.trajectory.trajectory import read_trajectory


def _ds(diff, bound, scale):
    N, n = diff.shape
    t = np.linspace(0.0, 2.0, N)
    tau = np.sin(t)[:, None] * scale[None, :]
    return xr.Dataset({"t": ("t", t), "tau": (("t", "joint"), tau),
                       "tau_simplified": (("t", "joint"), tau + diff),
                       "simplified_bound": ("joint", bound),
                       "simplified_scale": ("joint", scale)})


def _texts(ax):
    return " ".join(t.get_text() for t in ax.texts)


def _note(fig):
    return " ".join(t.get_text().replace("\n", " ") for t in fig.texts)


def test_round_off_reads_equal_and_a_real_error_is_drawn():
    N = 31
    rng = np.random.default_rng(1)
    scale = np.array([10.0, 2.0, 1.2e-4, 1.0])
    noise = rng.standard_normal(N) * 1e-17
    diff = np.column_stack([
        0.01 * np.sin(np.linspace(0, 3, N)),        # a kept error within its bound
        noise,                                      # nothing dropped, round-off
        noise,                                      # round-off of a tiny joint: still noise
        1e-6 * np.ones(N),                          # bound 0 but a real difference: drawn
    ])
    fig = error_figure(_ds(diff, np.array([0.02, 0.0, 0.0, 0.0]), scale))
    axes = fig.axes
    # joints 2 and 3 (round-off) get no panel: no empty "nothing dropped" panels
    assert [ax.get_title() for ax in axes] == ["joint 1", "joint 4"]
    assert len(axes[0].lines) >= 3
    note = _note(fig)
    assert "Nothing dropped for joints 2, 3" in note and "round-off" in note
    assert any(np.allclose(line.get_ydata(), 1e-6) for line in axes[1].lines)


def test_the_threshold_is_relative_to_the_joint_scale():
    N = 5
    scale = np.array([1.0, 1.0])
    at = ROUND_OFF * np.ones(N)
    above = 2 * ROUND_OFF * np.ones(N)
    fig = error_figure(_ds(np.column_stack([at, above]), np.zeros(2), scale))
    assert [ax.get_title() for ax in fig.axes] == ["joint 2"]
    assert "Nothing dropped for joint 1 " in _note(fig)


def test_nan_is_never_round_off():
    N = 5
    diff = np.full((N, 1), np.nan)
    fig = error_figure(_ds(diff, np.zeros(1), np.ones(1)))
    assert len(fig.axes) == 1 and not _note(fig)


def test_no_empty_panel_for_a_joint_with_nothing_dropped(shipped_dataset):
    """A joint whose model drops nothing (bound 0, tau_s - tau round-off) gets no panel in
    Fig. 4, a note names it (three of the PUMA's six panels were empty, reading
    "nothing dropped"); every panel drawn draws tau_s - tau."""
    ds = shipped_dataset("puma560")
    fig = error_figure(ds)
    diff = ds["tau_simplified"].values - ds["tau"].values
    scale = ds["simplified_scale"].values
    quiet = [i + 1 for i in range(ds.sizes["joint"])
             if float(ds["simplified_bound"][i]) == 0.0
             and np.abs(diff[:, i]).max() <= ROUND_OFF * scale[i]]
    assert quiet                                    # the case exists on the shipped run
    shown = [i + 1 for i in range(ds.sizes["joint"]) if i + 1 not in quiet]
    assert [ax.get_title() for ax in fig.axes] == [f"joint {i}" for i in shown]
    for ax in fig.axes:
        assert any(len(line.get_xdata()) == ds.sizes["t"] for line in ax.lines)
        assert not _texts(ax)
    which = ("joint " if len(quiet) == 1 else "joints ") + ", ".join(map(str, quiet))
    assert f"Nothing dropped for {which} " in _note(fig)


def test_the_inertia_check_sentence_is_the_stored_check():
    """The report says what the stored proof found, for each outcome."""
    from gd_analyze.jobs.simplified_dataset import inertia_check_attrs
    from gd_analyze.report.markup import plain
    from gd_analyze.report.simplified_section import inertia_check_text

    base = {"where": "region", "samples": 200, "restored": [], "method": "m",
            "sampled_min_eigenvalue": 0.02}
    ok = plain(inertia_check_text(inertia_check_attrs(
        {**base, "proved": True, "lower_bound": 0.0123, "ratio": 0.25, "statement": "s"})))
    assert "is proved positive definite over the joint-limit region" in ok
    assert "0.0123" in ok and "0.25 of the least" in ok and "sampled" not in ok
    bad = plain(inertia_check_text(inertia_check_attrs(
        {**base, "where": "trajectory", "samples": 31, "proved": False,
         "sampled_min_eigenvalue": -0.5, "statement": "not proved (why)"})))
    assert "is not proved positive definite: not proved (why)." in bad
    assert "the 31 sampled positions is -0.5: forward dynamics with it is not safe" in bad
    kept = plain(inertia_check_text(inertia_check_attrs(
        {**base, "proved": True, "lower_bound": 0.1, "ratio": 0.5, "statement": "s",
         "restored": ["XX2", "ZZ3"]})))
    assert kept.endswith("kept with all parts: XX2, ZZ3.")
    assert inertia_check_text({}) == ""


def test_region_table_and_whether_this_trajectory_lies_in_it():
    """The report's region table: per joint the range in degrees or "any angle
    (full turn)", qd max, qdd max and whether qdd max is assumed; a trajectory leaving the
    region is said not covered, naming the joint and quantity."""
    import gd_analyze as gd
    from gd_analyze.report.simplified_section import region_table

    robot = gd.load_robot("two-link")
    t = np.linspace(0.0, 1.0, 21)
    q = np.column_stack([np.radians(50) * t, 0.1 * t])       # joint 1 at 50 deg/s
    region = gd.RegionLimits(q_limits=((np.radians(-30), np.radians(60)),
                                       (-np.pi, np.pi)), qd_max=(np.radians(40),))
    options = gd.AnalysisOptions(formulations=False, verify=False,
                                 simplify=gd.SimplifyOptions(region=region))
    tab, text = region_table(gd.analyze(robot, (t, q), options))
    assert [r[2] for r in tab["rows"]] == ["[-30, 60]", "any angle (full turn)"]
    assert [r[3] for r in tab["rows"]] == ["40", "40"]
    assert [r[4] for r in tab["rows"]] == ["360", "360"]           # the robot's, given
    assert [r[5] for r in tab["rows"]] == ["given", "given"]
    # qd, qdd set as q with a dot, as the coverage clause sets them (they printed "qd")
    assert "This trajectory leaves the region: joint 1 q\u0307 reaches" in text
    assert [h.split(" [")[0] for h in tab["header"][3:]] == ["q\u0307 max", "q\u0308 max",
                                                            "q\u0308 max"]
    assert "it does not cover it" in text
    inside = gd.analyze(robot, (t, 0.1 * q), options)
    assert "Every set point of this trajectory lies in the region." in region_table(inside)[1]


def test_the_core_s_statements_reach_the_report_as_mathematics():
    """The screen's sentence (the proof of D_s restored some parameters) and a failed D_s
    proof's statement, as the core writes them, are set with D and a subscript s, never
    "D_s" (a 15-joint chain's report printed "the proof that D_s is positive definite")."""
    from gd_analyze.certify.screen import RegionScreen
    from gd_analyze.jobs.simplified_dataset import inertia_check_attrs
    from gd_analyze.report.markup import html, plain, sub
    from gd_analyze.report.simplified_section import _screen_note, inertia_check_text

    screen = RegionScreen(tolerance=0.01, threshold=0.015, exact_operations=2701,
                          best_operations=2690, dropped=np.zeros(3, bool), scale=np.ones(2),
                          scale_state=np.zeros((2, 6)), relative_peak=np.zeros((3, 3)),
                          seconds=0.0, proved=True, restored=12)
    said = screen.text()
    assert "D_s" in said                                 # the core's plain text
    note = _screen_note(said, proved=True)
    assert "the proof that D" + sub("s") + " is positive definite" in note
    assert "D_s" not in note and "D_s" not in str(html(note)) and "D_s" not in plain(note)
    assert "D<sub>s</sub>" in str(html(note))
    bad = inertia_check_text(inertia_check_attrs(
        {"where": "region", "samples": 200, "restored": [], "method": "m", "proved": False,
         "sampled_min_eigenvalue": -0.5, "statement": "D_s has eigenvalue -0.5 at a sampled "
                                                       "position"}))
    assert "D_s" not in bad and "D" + sub("s") + " has eigenvalue -0.5" in bad


def test_s_i_is_said_raised_to_a_floor_only_where_there_is_one():
    """With no torque floor (0, the default) the rules said "s_i = ..., raised to the floor",
    of a floor that does not exist: said now only with one."""
    from gd_analyze.report.common import say
    from gd_analyze.report.simplified_section import region_pruning

    raised = "raised to the floor"
    assert raised not in region_pruning(40, 6)
    assert raised in region_pruning(40, 6, floor="2 N m")
    for floor in ("", "2"):
        explicit = say("explicit_rule", rule="budget", eps="0.01", floor=floor, scope="")
        recursive = say("recursive_rule", b=36, eps="0.01", floor=floor, pairs=40, dropped=6,
                        region=False, drives=False, scope="")
        region = say("recursive_rule", b=36, eps="0.01", floor=floor, pairs=40, dropped=6,
                     region=True, drives=False, scope="")
        for text in (explicit, recursive, region):
            assert (raised in text) == bool(floor), (floor, text)
            assert (f"torque floor {floor} N m" in text) == bool(floor), text


def test_the_costs_said_agree_in_number_with_their_counts():
    """Oracle: the counts given; a count of one is singular ("1 additions" read before)."""
    from gd_analyze.report.common import say

    assert say("emitted_cost", mult=1, add=1, sin=0, cos=0).startswith(
        " The emitted code costs 1 multiplication and 1 addition per set point")
    assert say("emitted_cost", mult=2, add=0, sin=0, cos=0).startswith(
        " The emitted code costs 2 multiplications and 0 additions per set point")
    assert "model costs 1 multiplication and 3 additions," in say(
        "other_rule", rule="chapter", mult=1, add=3, worst="1 %")


def test_the_other_rules_round_off_is_said_as_round_off(shipped_dataset):
    """Oracle: the relative errors given against the round-off rule (1e-12 of peak |tau|):
    the other rule's model, exact on this trajectory, read "worst error 2.4e-13 % of peak
    |τ|" beside Table 5.1's ≡ 0; an error above the rule is still given as a percentage."""
    from gd_analyze.report.markup import plain
    from gd_analyze.report.simplified_section import simplified_context

    ds = shipped_dataset("puma560").copy(deep=True)
    assert ds.attrs["other_rule"]
    rel = ds["other_rule_error_relative_peak"]
    ds["other_rule_error_relative_peak"] = rel.copy(data=np.full(rel.shape, 2.4e-15))
    text = plain(simplified_context(ds)["text"])
    assert "additions, error ≡\u00a00 at every joint (round-off only)." in text
    ds["other_rule_error_relative_peak"] = rel.copy(data=np.full(rel.shape, 0.02))
    assert "additions, worst error 2.00 % of peak |τ|." in plain(simplified_context(ds)["text"])


def test_a_dearer_model_is_explained_by_its_coefficients_only_where_they_grew():
    """Oracle: the counts given. "the full model's 18 distinct coefficient magnitudes become
    18, so the code generator's factoring finds less to share" gave a cause the counts deny
    (an arm whose chapter model costs one addition more with the same terms)."""
    from gd_analyze.report.common import say
    from gd_analyze.report.markup import plain

    def said(oc):
        return plain(say("dearer_than_full", mine=100, full=99, fh=52, fc=18, oh=52, oc=oc,
                         chapter=False))

    assert said(18) == (" It costs more than the full explicit model (100 against 99 operations)"
                        " although it keeps 52 of the full model's 52 harmonic terms, with 18"
                        " distinct coefficient magnitudes against its 18.")
    assert "magnitudes become 25, so the code generator's factoring" in said(25)


def test_a_recursive_rule_with_no_contribution_is_not_said_to_drop_none_of_zero():
    """Oracle: the count given, 0 pairs (an arm without inertia read "of the 0 (parameter,
    part) pairs that contribute, none is dropped")."""
    from gd_analyze.report.common import say
    from gd_analyze.report.markup import plain

    def rule(pairs):
        return plain(say("recursive_rule", b=8, eps="0.01", floor="", pairs=pairs, dropped=0,
                         region=False, drives=False, scope=""))

    assert "0.01: no (parameter, part) pair contributes, so none is dropped; the model" in rule(0)
    assert "0.01: of the 4 (parameter, part) pairs that contribute, none is dropped; the" in rule(4)


@pytest.mark.parametrize("case", ["puma560", "ur5", "puma560 exact"])
def test_the_torque_error_caption_says_what_the_figure_draws(shipped_dataset, case):
    """The caption of the torque-error figure is true of the figure drawn: "per joint against
    time" only where a panel is drawn, the note of the joints without one only where some
    have none, and a figure of no panel said so (a model that drops nothing: EPS = 0, the
    exact model). Oracle: the figure's own panels."""
    name, _, exact = case.partition(" ")
    if exact:
        robot = load_robot(name)
        trajectory = read_trajectory(ROOT / "data" / f"{name}_trajectory.csv", robot.n)
        options = AnalysisOptions(verify=False, formulations=False, simplify=SimplifyOptions(
            tolerance=0.0, guarantee="trajectory"))
        ds = analyze(robot, trajectory, options).dataset
    else:
        ds = shipped_dataset(name)
    panels, n = len(error_figure(ds).axes), int(ds.sizes["joint"])
    caption = " ".join(simplified_caption(ds).split())
    assert ("per joint against time" in caption) == (panels > 0), caption
    assert ("get no panel" in caption) == (0 < panels < n), caption
    assert ("no joint is drawn" in caption) == (panels == 0), caption
    if exact:
        assert panels == 0
