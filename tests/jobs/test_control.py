"""Closed-loop use of the simplified model: forward dynamics, computed torque, evaluation cost,
the control dataset and the control report.

Run time: one closed-loop run of the three controllers along the shipped 31-set-point PUMA 560
trajectory (4.16 s of motion, DOP853, rtol 1e-8, atol 1e-10, 2001-point grid) is shared by the
tests; the crude-model and offset runs reuse the same settings (the offset run stops at
0.5 s). The cost is timed on 2000 set points only. The file runs in about 20-30 s.
"""


from dataclasses import replace

import numpy as np
import pinocchio as pin
import pytest
import xarray as xr
from conftest import SHIPPED
from figure_checks import check_print_ready, column_twins

from gd_analyze import gd_terms, load_robot
from gd_analyze.dynamics.opcount import count_operations
from gd_analyze.dynamics.pinocchio import pinocchio_model, reference_terms
from gd_analyze.errors import InputError
from gd_analyze.files import file_sha256
from gd_analyze.jobs.control import CONTROLLERS, run_control, singular_inertia
from gd_analyze.model.robot_spec import robot_from_chain
from gd_analyze.ranking.ranking import element_labels
from gd_analyze.report.control import write_control_report
from gd_analyze.simplify.simplified import SimplifiedModel, full_choices
from gd_analyze.store.control_dataset import control_dataset, write_control_dataset
from gd_analyze.store.model_file import load_model, save_model
from gd_analyze.trajectory.trajectory import Trajectory, read_trajectory

#: Over 5 s on an idle machine (the module's fixtures): run on one interpreter in CI.
pytestmark = pytest.mark.slow

#: Bound on the tracking error of the full-model computed-torque controller started on the
#: trajectory [rad]. With the exact model the closed loop is e'' + Kv e' + Kp e = 0 with
#: e(0) = e'(0) = 0, so e = 0 exactly; what remains is the integrator's error. DOP853 keeps the
#: local error per step below atol + rtol |y| = 1e-10 + 1e-8 * 2.62 ~ 3e-8 rad (|q| <= 2.62 rad,
#: |qd| <= 1.9 rad/s on the shipped motion), and the critically damped error dynamics forget an
#: injected error within a few 1/wn = 0.05 s, i.e. within ~10 steps of the ~290 taken, so
#: the global error stays below ~10 * 3e-8 = 3e-7 rad. The desired motion is the piecewise
#: quintic Hermite through (q, qd, qdd), which reproduces the shipped quintic exactly, so
#: interpolation adds nothing at the set points. Bound: 1e-6 rad.
FULL_MODEL_BOUND = 1e-6


@pytest.fixture(scope="module")
def model(puma_analysis):
    """The PUMA 560's simplified model of its shipped trajectory (conftest's shared
    analysis, without verification and formulations)."""
    return puma_analysis.model


@pytest.fixture(scope="module")
def model_file(model, tmp_path_factory):
    path = tmp_path_factory.mktemp("model") / "simplified_model.json"
    save_model(model, path)
    return path


@pytest.fixture(scope="module")
def result(model_file):
    model = load_model(model_file)
    return run_control(model, read_trajectory(SHIPPED, n_joints=6), cost=True,
                       model_path=model_file,
                       model_sha256=file_sha256(model_file))


def _crude(robot):
    """All D elements kept whole, all of h dropped."""
    return {lab: ("both" if lab.startswith("D") else "none") for lab in element_labels(robot.n)}


# --------------------------------------------------------------------------------------------
# Forward dynamics
# --------------------------------------------------------------------------------------------


# --------------------------------------------------------------------------------------------
# Desired motion and gains
# --------------------------------------------------------------------------------------------


# --------------------------------------------------------------------------------------------
# Closed loop
# --------------------------------------------------------------------------------------------

def test_full_model_tracks_within_solver_tolerance(result):
    assert list(result.runs) == list(CONTROLLERS)
    assert all(r.success for r in result.runs.values())
    assert int(result.is_setpoint.sum()) == 31
    f = result.error_figures("full")
    assert max(f["peak_grid"]) < FULL_MODEL_BOUND
    assert max(f["peak_setpoints"]) < FULL_MODEL_BOUND
    # torque of the full-model controller on the trajectory = inverse dynamics of q_d
    tau_ff = gd_terms(result.robot, result.q_d, result.qd_d).tau(result.qdd_d)
    assert np.abs(result.runs["full"].tau - tau_ff).max() < 1e-3


def test_pd_gravity_tracks_worse_than_computed_torque(result):
    full, pd = result.error_figures("full"), result.error_figures("pd_gravity")
    assert all(p > f for p, f in zip(pd["peak_grid"], full["peak_grid"]))
    assert max(pd["peak_grid"]) > 100 * max(full["peak_grid"]) and max(pd["peak_grid"]) > 1e-4


def test_simplified_model_tracks_between(result):
    full, simp = result.error_figures("full"), result.error_figures("simplified")
    pd = result.error_figures("pd_gravity")
    assert all(s >= f for s, f in zip(simp["peak_grid"], full["peak_grid"]))
    assert max(simp["peak_grid"]) < max(pd["peak_grid"])
    diff = result.summary()["tau_difference"]
    assert len(diff["peak"]) == 6 and max(diff["peak"]) > 0
    assert all(r <= p for r, p in zip(diff["rms"], diff["peak"]))


def test_crude_model_without_h_tracks_worse(puma, shipped, result):
    crude = SimplifiedModel(robot=puma, choices=_crude(puma), dominance_threshold=0.9,
                            negligible_threshold=0.01)
    res = run_control(crude, shipped, controllers=("simplified",), cost=False)
    full, bad = result.error_figures("full"), res.error_figures("simplified")
    assert all(b >= f for b, f in zip(bad["peak_grid"], full["peak_grid"]))
    assert max(bad["peak_grid"]) > 100 * max(full["peak_grid"])
    assert max(bad["peak_grid"]) > 10 * FULL_MODEL_BOUND


def test_initial_offset_decays_as_critically_damped(model, shipped):
    wn, e0 = 20.0, 0.01
    res = run_control(model, shipped, wn=wn, zeta=1.0, q0_offset=e0, controllers=("full",),
                      t_end=0.5, grid_points=201, cost=False)
    t = res.t - res.t[0]
    exact = -e0 * (1 + wn * t) * np.exp(-wn * t)        # e = q_d - q, q(0) = q_d(0) + e0
    np.testing.assert_allclose(res.runs["full"].error, exact[:, None] * np.ones(6),
                               rtol=0, atol=1e-7)


def test_region_coverage_follows_the_closed_loop_not_only_the_desired_motion(model, puma,
                                                                             shipped):
    """An initial offset that starts joint 5 0.2 rad below its limit takes the simplified-model
    controller's closed loop out of the region (q(0) = q_d(0) + offset, the oracle): not
    covered, the joint, its unit and how far said; no offset stays inside: covered."""
    assert model.guarantee.kind == "region"
    offset = np.zeros(6)
    offset[4] = puma.q_min[4] - shipped.q[0, 4] - 0.2
    for e0, inside in ((0.0, True), (offset, False)):
        res = run_control(model, shipped, q0_offset=e0, controllers=("simplified",), t_end=0.5,
                          grid_points=201, cost=False)
        said = res.summary()["guarantee"]
        assert said["covered"] == int(inside), said["reason"]
        assert control_dataset(res).attrs["model_guarantee_covered"] == int(inside)
        if inside:      # a "yes" names every state checked: set points, desired motion, loop
            assert said["reason"] == (
                f"every set point, and at the {res.t.size} output times the desired motion "
                "between the set points (q, |qd|, |qdd|) and the closed loop of the "
                "simplified-model controller (q, |qd|, commanded |qdd|), lie in the model's region")
    assert said["reason"].startswith("the closed loop of the simplified-model controller is "
                                     "outside the model's region: joint 5's q reaches ")
    beyond = float(said["reason"].split(", ")[1].split(" rad below")[0])
    assert 0.2 - 1e-9 <= beyond < 0.21 and said["reason"].endswith(
        f"below its limit {puma.q_min[4]:.6g} rad")


def test_region_coverage_checks_the_commanded_acceleration(model, puma, shipped):
    """The simplified-model controller evaluates its model at v = qdd_d + Kv ed + Kp e: an
    offset of 0.01 rad starts it at v(0) = qdd_d(0) - wn^2 0.01 = -4 rad/s^2 (the shipped
    motion starts at rest), beyond joint 1's 45 deg/s^2: not covered, said with the value,
    the distance past the limit and the unit."""
    qdd_max = model.guarantee.qdd_max[0]
    res = run_control(model, shipped, q0_offset=0.01, controllers=("simplified",), t_end=0.5,
                      grid_points=201, cost=False)
    said = res.summary()["guarantee"]
    assert not said["covered"]
    head = ("the closed loop of the simplified-model controller is outside the model's "
            "region: joint 1's commanded |qdd| reaches ")
    assert said["reason"].startswith(head), said["reason"]
    reached, beyond = (float(v.split(" ")[0]) for v in said["reason"][len(head):].split(", "))
    assert reached == pytest.approx(20.0 ** 2 * 0.01, rel=1e-6)
    assert beyond == pytest.approx(reached - qdd_max, rel=2e-3)
    assert said["reason"].endswith(f"rad/s^2 above its limit {qdd_max:.6g} rad/s^2")


def test_region_coverage_checks_the_desired_motion_between_set_points(model, shipped):
    """The shipped motion is one quintic q_0 + dq (10 s^3 - 15 s^4 + 6 s^5), s = t / T, whose
    |qdd| peaks at 10 sqrt(3) / 3 |dq| / T^2 (s = 1/2 - sqrt(3)/6), on joint 6 at its limit.
    Kept at s = 0, 1/2, 1 only (qdd = 0 there) and run 1 % faster, the set points lie in the
    region but the desired motion between them does not: not covered, its peak said."""
    c = 0.99
    pick = [0, 15, 30]
    t = (shipped.t[pick] - shipped.t[0]) * c
    fast = Trajectory(t, shipped.q[pick], shipped.qd[pick] / c, shipped.qdd[pick] / c ** 2)
    dq, T = shipped.q[-1] - shipped.q[0], t[-1]
    peak = 10 * np.sqrt(3) / 3 * np.abs(dq) / T ** 2
    qdd_max = model.guarantee.qdd_max
    assert np.flatnonzero(peak > qdd_max).tolist() == [5]      # the case: joint 6 only
    res = run_control(model, fast, controllers=("full",), cost=False)
    said = res.summary()["guarantee"]
    head = ("the desired motion between the set points is outside the model's region: "
            "joint 6's |qdd| reaches ")
    assert not said["covered"] and said["reason"].startswith(head), said["reason"]
    reached = float(said["reason"][len(head):].split(" ")[0])
    assert reached == pytest.approx(peak[5], rel=1e-5)


def test_the_simplified_control_law_names_the_gravity_the_model_applies(result, model_file):
    """The simplified-model controller applies the model's own gravity c_s = tau_s(q, 0, 0):
    its law reads "+ c" only where that is c. The PUMA 560's model keeps c whole (Pinocchio's
    c, the oracle, equals c_s at set points); a model that drops a gravity part, or terms of
    c, reads "+ c_s" in the law stored in control.h5."""
    model = load_model(model_file)
    q = result.q_d[::400]
    c_s = model.torque(q, np.zeros_like(q), np.zeros_like(q))
    c = reference_terms(model.robot, q, np.zeros_like(q)).c
    np.testing.assert_allclose(c_s, c, rtol=0, atol=1e-9 * np.abs(c).max())
    assert result.descriptions["simplified"].endswith("D_s v + h_s + c")
    facts = result.provenance["model"]
    for dropped in ({"gravity_dropped": "MX2"}, {"c_terms_kept": 3, "c_terms": 5}):
        res = replace(result, provenance={**result.provenance, "model": {**facts, **dropped}})
        assert res.descriptions["simplified"].endswith("D_s v + h_s + c_s")
        assert "simplified model: D_s v + h_s + c_s;" in control_dataset(res).attrs["control_laws"]


def test_the_laws_and_the_plant_name_the_drives_friction(shipped):
    """An arm with drives: the full-model controller applies D v + h + c + tau_f (Pinocchio's
    D, h, c, the armature Ia added to D, the oracle: what is left is the friction, not 0), and
    the plant is qdd = D^-1 (tau - h - c - tau_f): the stored law and plant say tau_f."""
    robot = load_robot("puma560-drives")
    model = SimplifiedModel(robot, full_choices(6), 0.9, 0.01)
    res = run_control(model, shipped, controllers=("full",), t_end=0.5, grid_points=21,
                      cost=False)
    run, g = res.runs["full"], res.gains
    v = res.qdd_d + g.Kv * (res.qd_d - run.qd) + g.Kp * (res.q_d - run.q)
    ref = reference_terms(robot, run.q, run.qd)
    rest = run.tau - np.einsum("nij,nj->ni", ref.D, v) - ref.h - ref.c - robot.armature * v
    assert np.abs(rest).max() > 1e-3 * np.abs(run.tau).max()        # friction, applied
    attrs = control_dataset(res).attrs
    assert "full: computed torque, full G-D model: D v + h + c + tau_f;" in attrs["control_laws"]
    assert attrs["plant"].startswith("full G-D model, qdd = D^-1 (tau - h - c - tau_f)")


def test_run_control_rejects_bad_input(model, shipped):
    two = load_robot("two-link")
    with pytest.raises(ValueError):
        run_control(model, shipped, controllers=("nonsense",), cost=False)
    with pytest.raises(ValueError):
        run_control(SimplifiedModel(two, full_choices(2), 0.9, 0.01), shipped, cost=False)
    with pytest.raises(ValueError):
        run_control(model, shipped, wn=-1, cost=False)
    with pytest.raises(InputError):
        load_model("/nonexistent/simplified_model.json")



@pytest.mark.parametrize("gravity, loop", [((0.0, 0.0, -9.81), "PD + gravity"),
                                           ((0.0, 0.0, 0.0), "PD")])
def test_a_stiff_pd_loop_is_named_for_the_gravity_of_its_arm(model, shipped, gravity, loop):
    """wn = 5000 makes the PD loop too stiff (its fastest mode runs through D^-1 diag(D)); the
    refusal names the loop as the controller is named for its plant: plain PD where the
    plant has g = 0, since c is linear in g (Eq. (3.4-24)) and so identically 0."""
    plant = replace(model.robot, gravity=np.asarray(gravity))
    with pytest.raises(ValueError, match="too stiff") as err:
        run_control(model, shipped, wn=5000.0, controllers=("pd_gravity",), cost=False,
                    plant=plant)
    said = str(err.value)
    assert f"make the {loop} loop (pd_gravity) too stiff" in said, said
    assert "gravity term" not in said and "compensation" not in said


# --------------------------------------------------------------------------------------------
# The model's counted cost
# --------------------------------------------------------------------------------------------

def test_model_cost_counts_the_emitted_model_and_newton_euler(model, puma):
    """The control dataset's cost: the model's own counts (of its emitted program), the full
    explicit model's, and N-E's from the counting scalar; no timing."""
    from gd_analyze.jobs.control import model_cost

    cost = model_cost(model)
    names = cost["evaluators"]
    assert names[0] == f"simplified model ({model.form} form)"
    assert names[-1].startswith("Newton-Euler") and "exact recursive model" in names
    program = model.program().cost()
    assert (cost["multiplications"][0], cost["additions"][0]) == \
        (program["multiplications"], program["additions"])
    ne = count_operations(puma, "newton-euler")
    assert (cost["multiplications"][-1], cost["additions"][-1]) == (ne[0], ne[1])
    if "full explicit model" in names:
        k = names.index("full explicit model")
        assert cost["multiplications"][0] + cost["additions"][0] <= \
            cost["multiplications"][k] + cost["additions"][k]
    if model.recursive is None:
        dropped = sum({"both": 0, "tran": 1, "rot": 1, "none": 2}[c]
                      for c in model.choices.values())
        assert cost["dropped"] == dropped and cost["parts"] == 54
    else:                   # the pairs that contribute on the model's trajectory, as stored
        live = model.recursive.contributing()
        assert cost["dropped"] == int((model.recursive.dropped & live).sum())
        assert cost["parts"] == int(live.sum()) < 3 * len(model.recursive.names)


# --------------------------------------------------------------------------------------------
# Dataset and report
# --------------------------------------------------------------------------------------------

def test_control_dataset_round_trips_through_hdf5(result, model_file, tmp_path):
    path = tmp_path / "control.h5"
    ds = write_control_dataset(result, path)
    with xr.open_dataset(path, engine="h5netcdf") as back:
        back = back.load()
    assert set(back.dims) >= {"controller", "time", "joint"}
    assert back.sizes["controller"] == 3 and back.sizes["time"] == result.t.size
    for name in list(back.data_vars) + list(back.coords):
        assert back[name].attrs.get("units"), name
        assert back[name].attrs.get("long_name"), name
    for name in ("error", "tau", "q", "tau_difference", "Kp_pd", "error_peak_grid",
                 "multiplications", "additions"):
        np.testing.assert_array_equal(back[name].values, ds[name].values)
    assert list(back["controller"].values) == list(CONTROLLERS)
    np.testing.assert_allclose(back["error_peak_grid"].sel(controller="full").values,
                               result.error_figures("full")["peak_grid"])
    attrs = back.attrs
    assert attrs["robot"] == "puma560" and len(attrs["robot_sha256"]) == 64
    assert attrs["trajectory_file"] == "puma560_trajectory.csv"
    assert attrs["trajectory_sha256"] == read_trajectory(SHIPPED).sha256
    import hashlib

    assert attrs["model_file"] == "simplified_model.json"
    assert attrs["model_sha256"] == hashlib.sha256(model_file.read_bytes()).hexdigest()
    assert attrs["gd_analyze_version"] and "Kp" in attrs["gains"]
    assert attrs["trajectory_is_models"] == 1
    np.testing.assert_allclose(attrs["wn"], 20.0)
    assert control_dataset(result).equals(ds)


def test_control_report_is_written(result, tmp_path):
    path = tmp_path / "control.h5"
    write_control_dataset(result, path)
    written = write_control_report(path, tmp_path / "out", column_figures=True)
    html_path, pdf_path = written[:2]
    assert [p.name for p in written[2:] if p.parent.name == "figures"] == [
        f"fig_control_{name}{width}.{ext}" for width in ("", "_column")
        for name in ("tracking_error", "torque_difference", "applied_torque")
        for ext in ("pdf", "svg")]
    assert not column_twins(tmp_path / "out" / "figures")        # 3.5-in MediaBox each
    html = html_path.read_text(encoding="utf-8")
    assert "Verdict: the simplified model" in html
    assert html.startswith("<!DOCTYPE html>") and html.count("<svg") >= 3
    assert "<link" not in html and " src=" not in html and "<script" not in html
    assert "puma560_trajectory.csv" in html and "multiplications" in html
    from gd_analyze.report.control import fmt_number

    for c in CONTROLLERS:                             # the stored figures, as read back
        peak = result.error_figures(c)["peak_grid"][5]
        if c == "full":                               # integrator noise: no digits of it
            assert fmt_number(peak) not in html
        else:
            assert fmt_number(peak) in html
    assert pdf_path.read_bytes()[:5] == b"%PDF-"
    from pypdf import PdfReader

    reader = PdfReader(pdf_path)
    assert len({tuple(p.mediabox) for p in reader.pages}) == 1          # one page size
    text = "\n".join(p.extract_text() for p in reader.pages)
    assert "Verdict: the simplified model" in text and "Figure 3." in text
    assert [o["/Title"] for o in reader.outline if not isinstance(o, list)] == [
        "1. Set-up and gains", "2. Tracking error", "3. Torques",
        "4. Evaluation cost of the model", "5. Simplified model", "6. Provenance"]
    assert not list((tmp_path / "out").glob(".*.tmp"))
    with pytest.raises(InputError):
        write_control_report(tmp_path / "missing.h5", tmp_path / "out")


def test_integrator_noise_is_not_drawn_and_units_follow_joint_types(result):
    """The full-model controller tracks its own plant: its error is integrator noise (at most
    rtol of the joint's motion), never drawn as data in the tracking-error figure; the two
    other controllers' errors are drawn, on axes that start at the noise floor, in the units
    of the stored joint types (all revolute: rad, N m)."""
    from gd_analyze.ranking.ranking import is_round_off
    from gd_analyze.report.control import control_figures

    ds = control_dataset(result)
    assert list(ds["joint_type"].values) == ["revolute"] * 6
    assert ds["error"].attrs["units"] == "rad" and ds["tau"].attrs["units"] == "N m"
    rtol = float(ds.attrs["rtol"])
    q_d = ds["q_d"].values
    scale = np.maximum(np.ptp(q_d, axis=0), np.abs(q_d).max(axis=0))
    full = np.abs(ds["error"].sel(controller="full").values).max(axis=0)
    assert is_round_off(full, scale, rtol).all()           # the physics: noise, per joint
    fig = control_figures(ds)["error"]
    labels = {"computed torque, full model", "computed torque, simplified model",
              "PD + gravity"}
    for j, ax in enumerate(a for a in fig.axes if a.get_visible()):
        drawn = {ln.get_label() for ln in ax.lines} & labels
        assert drawn == labels - {"computed torque, full model"}
        assert ax.get_ylim()[0] == pytest.approx(rtol * scale[j])
        assert ax.get_ylabel().endswith("[rad]")
    assert any("\u2261 0 on every joint (integrator noise)" in " ".join(t.get_text().split())
               for t in fig.texts)


def test_control_figures_label_without_scripts_at_print_size(result):
    """The control figures at page and column width: the axes name |e| and delta tau (no
    mathtext, whose subscripts of q_d, tau_s, tau_f printed at 5.6 pt), no label collisions
    or text past the edge, column type of at least 7 pt; a six-joint arm's panels three a
    row at page width (two rows: half a page)."""
    from matplotlib.text import Text

    from gd_analyze.report.control import (
        COLUMN_WIDTH,
        FIGURE_RC,
        control_figures,
    )

    ds = control_dataset(result)
    figs = {**control_figures(ds),
            **{f"{k}_column": f for k, f in control_figures(ds, COLUMN_WIDTH).items()}}
    check_print_ready(figs, FIGURE_RC)
    labels = [ax.get_ylabel() for ax in figs["error"].axes if ax.get_visible()]
    assert labels == ["|e| [rad]"] * 6
    texts = [t.get_text() for f in figs.values() for t in f.findobj(Text)]
    assert texts and not any("$" in t for t in texts)
    rows = {round(ax.get_position().y0, 6) for ax in figs["error"].axes if ax.get_visible()}
    assert len(rows) == 2


@pytest.mark.parametrize("name, wn, zeta", [
    ("wn", 1e308, 1.0), ("zeta", 20.0, 1e308), ("wn", 1e160, 1e160), ("wn", 1e4 * (1 + 1e-12), 1.0),
    ("zeta", 20.0, 100.5), ("wn", 0.0099, 1.0), ("wn", [20.0, 0.001], 1.0), ("zeta", 20.0, np.nan)])
def test_gains_beyond_the_command_lines_ranges_are_refused_without_overflow(name, wn, zeta):
    """wn or zeta beyond --wn's and --zeta's ranges, even so large that wn^2 or zeta wn
    overflows: refused with the command line's bounds, which its parser reads from the same
    constant (run_control accepted any positive wn and zeta; those beyond a float were refused
    as "too stiff" after overflowing, before that with "Array must not contain infs or NaNs"
    after five overflow warnings)."""
    import warnings

    from gd_analyze.cli.parsing import control_parser
    from gd_analyze.jobs.control import GAIN_RANGES
    from gd_analyze.trajectory.planning import default_motion, plan_quintic

    two = load_robot("two-link")
    trajectory = plan_quintic(two, *default_motion(two))
    lo, hi = GAIN_RANGES[name]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=rf"^{name} must be in \[{lo:g}, {hi:g}\], got "):
            run_control(SimplifiedModel(two, full_choices(2), 0.9, 0.01), trajectory, wn=wn,
                        zeta=zeta, cost=False)
    for bound in (lo, hi):
        args = control_parser().parse_intermixed_args(["m.json", "t.csv", f"--{name}", repr(bound)])
        assert getattr(args, name) == bound


@pytest.mark.parametrize("mass1, said", [
    (0.0, "it moves only what the other joints move"),     # joints 1 and 2 one axis
    (1.0, None)])                                          # link 1's mass: D invertible
def test_a_singular_D_of_two_joints_on_one_axis_is_not_said_to_move_no_inertia(mass1, said):
    """Two revolute joints on the same axis with a massless, inertialess link between them:
    Pinocchio's crba gives D = [[a, a], [a, a]], singular though each D_ii = a > 0. The line
    said "no inertia moves with it" of a joint whose D_ii is the largest element."""
    joints = [{"type": "revolute", "rotation": np.eye(3), "translation": [0.0, 0.0, 0.0],
               "mass": m, "com": [0.3, 0.0, 0.0], "inertia": np.eye(3) * 0.01 * m}
              for m in (mass1, 2.0)]
    robot = robot_from_chain("coaxial", joints, [0.0, 0.0, -9.81])
    model = pinocchio_model(robot)
    q = np.array([[0.3, -0.2], [1.0, 0.5]])
    D = np.array([pin.crba(model, model.createData(), x) for x in q])
    D = np.triu(D) + np.swapaxes(np.triu(D, 1), -1, -2)
    line = singular_inertia(robot, D)
    if said is None:
        assert line is None and np.linalg.eigvalsh(D).min() > 1e-3
        return
    assert np.abs(D - D[:, :1, :1]).max() <= 1e-12 * D.max()     # a = every element
    assert line.startswith("the inertia matrix D is singular at set point 1: ") and said in line
    assert "no inertia moves with it" not in line
    D[:, 0, :] = D[:, :, 0] = 0.0       # joint 1 moving nothing: that is what the line says
    assert "joint 1" in singular_inertia(robot, D) and "no inertia moves with it" in \
        singular_inertia(robot, D)
