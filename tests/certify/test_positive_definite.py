"""D_s proved positive definite where the model's bound holds (certify/positive_definite.py).

Oracles: Pinocchio's crba (D at 100,000 positions never below the floor the proof uses, the
Rayleigh bound above its least smallest eigenvalue), numpy's eigenvalues of the deployed D_s
at 100,000 positions (never below the proved bound), matrices whose discs are known by hand,
the planes where the issue found D_s singular (the Panda's q2 = 0, the Kinova's q5 = pi), a
hand-made model that drops the wrist's inertia (D_s singular: not proved, restored), and the
region certification's own leaves for the bound of the model finally deployed."""

import dataclasses
from importlib import resources
from unittest import mock

import numpy as np
import pinocchio as pin
import pytest
from robot_files import crba, inertia_arm

from gd_analyze import SimplifiedModel, load_robot
from gd_analyze.certify import regressor_bounds
from gd_analyze.certify.positive_definite import (
    check_inertia,
    inertia_floor,
    prove_inertia,
    sample_positions,
    with_inertia_check,
)
from gd_analyze.certify.region import worst_states
from gd_analyze.dynamics.base_parameters import base_parameters, random_states
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.ranking.labels import element_labels
from gd_analyze.simplify import deploy
from gd_analyze.simplify.deploy import (
    build_recursive,
    certified,
    guarantee_region,
    restored_rebuild,
)
from gd_analyze.simplify.guarantee import Guarantee
from gd_analyze.store.json_schema import MODEL_SCHEMA
from gd_analyze.symbolic.recursive_model import recursive_model

SAMPLED = 100_000


def _model(robot, rec):
    return SimplifiedModel(robot=robot, choices={k: "both" for k in element_labels(robot.n)},
                           dominance_threshold=0.9, negligible_threshold=0.01, rule="budget",
                           tolerance=0.01, recursive=rec)


def _without_the_wrist(robot):
    """60 random positions, the exact recursive model of ``robot`` (a PUMA 560 layout), the
    indices of its base parameters of links 5 and 6, and the model dropping those whole."""
    q, qd, qdd = random_states(robot, 60, 2)
    rec = recursive_model(robot, q, qd, qdd, 0.0)
    dropped = np.zeros_like(rec.dropped)
    last = [k for k, name in enumerate(rec.names) if name[-1] in "56"]
    dropped[last] = True
    return q, rec, last, _model(robot, dataclasses.replace(rec, dropped=dropped))


_DEFAULT = {}


@pytest.fixture(scope="module")
def puma():
    robot = load_robot("puma560")
    q, qd, qdd = random_states(robot, 60, 2)
    return robot, q, qd, qdd, recursive_model(robot, q, qd, qdd, 0.0)


def test_check_inertia_on_known_matrices():
    mats = np.array([[[4.0, 1.0, 0.5], [1.0, 3.0, 0.2], [0.5, 0.2, 2.0]],    # dominant
                     [[1.0, 0.9, 0.9], [0.9, 1.0, 0.9], [0.9, 0.9, 1.0]],    # PD, not dominant
                     [[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]]])   # indefinite
    got = check_inertia(lambda q: mats[q[:, 0].astype(int)], np.array([[0], [1]]))
    assert got["positive_definite"] and got["gershgorin_proved"] == 1 and got["samples"] == 2
    assert got["min_eigenvalue"] == pytest.approx(0.1)                   # 1 - 0.9 of the second
    bad = check_inertia(lambda q: mats[q[:, 0].astype(int)], np.array([[0], [2]]))
    assert not bad["positive_definite"] and bad["min_eigenvalue"] == pytest.approx(-1.0)


def _default(key):
    """The robot's default region model (EPS = 1 %), before and after the proof, searched
    without the decomposed bound (``deploy.DECOMPOSE`` False) and with the joint sums in balls
    alone (``regressor_bounds.BOX_MAX_JOINTS`` 0): the models of the issue's planes (with
    either, the Kinova's default model drops other pairs and needs no restore)."""
    if key not in _DEFAULT:
        robot = inertia_arm(key)
        region, _, _ = guarantee_region(robot)
        q, qd, qdd = random_states(robot, 40, 1)
        with mock.patch.object(deploy, "DECOMPOSE", False), \
                mock.patch.object(regressor_bounds, "BOX_MAX_JOINTS", 0):
            model, _ = build_recursive(robot, q, qd, qdd, 0.01, region=region,
                                       sample_region=region)
            proved = with_inertia_check(model, q, rebuild=restored_rebuild(
                q, qd, qdd, region=region, sample_region=region))
        _DEFAULT[key] = (robot, region, model, proved)
    return _DEFAULT[key]


def test_the_exact_puma_model_is_proved_and_recorded():
    robot = load_robot("puma560")
    q, qd, qdd = random_states(robot, 60, 2)
    rec = recursive_model(robot, q, qd, qdd, 0.0)
    model = with_inertia_check(_model(robot, rec), q)
    check = model.inertia_check
    assert check["where"] == "trajectory" and check["proved"] and check["restored"] == []
    assert check["lower_bound"] == pytest.approx(inertia_floor(robot).min())
    D = model.functions().numpy()["inertia"](q)
    assert np.linalg.eigvalsh(D)[:, 0].min() >= check["lower_bound"]
    assert check["statement"].startswith("proved positive definite over the bounding box of "
                                         "the trajectory positions: lambda_min(D_s) >= ")
    # a budget model's file states its guarantee (the exact model's: bound 0 on a trajectory)
    stated = Guarantee("trajectory", 0.01, bound=np.zeros(6), scale=np.ones(6),
                       scale_state=np.zeros((6, 18)))
    spec = dataclasses.replace(model, guarantee=stated).to_dict()
    MODEL_SCHEMA.check(spec, "<test>")
    assert SimplifiedModel.from_dict(spec, robot).inertia_check is None    # never believed
    with pytest.raises(ValueError, match="no region"):
        sample_positions(_model(robot, rec))


def test_the_bound_of_an_arm_of_prismatic_joints_only_is_in_kg():
    """A gantry's D is the masses it moves [kg] (x^T D x = sum m v^2, v in m/s): its bound
    was stated in 'SI units (kg m^2, kg m and kg mixed: q in rad and m)', with no angle in
    it. Oracle: D's unit from the kinetic energy; with one revolute joint the units mix."""
    links = "".join(
        f'<link name="l{k}"><inertial><mass value="{k}"/><inertia ixx="0.1" ixy="0" ixz="0" '
        f'iyy="0.1" iyz="0" izz="0.1"/></inertial></link><joint name="j{k}" type="{kind}">'
        f'<parent link="l{k - 1}"/><child link="l{k}"/><axis xyz="{axis}"/><limit lower="-1" '
        'upper="1" effort="10" velocity="1"/></joint>'
        for k, (kind, axis) in enumerate([("prismatic", "1 0 0"), ("prismatic", "0 1 0"),
                                          ("revolute", "0 0 1")], start=1))
    for n, unit in [(2, "kg"), (3, "SI units (kg m^2, kg m and kg mixed: q in rad and m)")]:
        robot = load_robot(f'<robot name="gantry"><link name="l0"/>{links}</robot>', tip=f"l{n}")
        q, qd, qdd = random_states(robot, 20, 2)
        model = with_inertia_check(_model(robot, recursive_model(robot, q, qd, qdd, 0.0)), q)
        assert model.inertia_check["proved"] and model.inertia_check["unit"] == unit
        assert f"lambda_min(D_s) >= {model.inertia_check['lower_bound']:.3g} {unit} (" in \
            model.inertia_check["statement"]


def test_a_model_that_drops_the_wrists_inertia_is_not_proved_and_is_restored():
    """Dropping every base parameter of links 5 and 6 whole makes D_s singular: the proof
    fails ("not proved"), and the restore keeps those parameters until it holds."""
    robot = load_robot("puma560")
    q, rec, last, broken = _without_the_wrist(robot)
    D = broken.functions().numpy()["inertia"](q)
    assert np.linalg.eigvalsh(D)[:, 0].min() <= 1e-12 * np.abs(D).max()
    proof = prove_inertia(robot, rec.base(robot), broken.left_out(), q.min(0), q.max(0))
    assert not proof.proved and proof.why and np.isnan(proof.ratio)
    fixed = with_inertia_check(broken, q)
    check = fixed.inertia_check
    assert check["proved"] and check["restored"]
    assert set(check["restored"]) <= {rec.names[k] for k in last}
    kept = [rec.names.index(name) for name in check["restored"]]
    # only the inertial part (the one in D_s) is restored: the others stay dropped
    assert not fixed.recursive.dropped[kept, 0].any() and fixed.recursive.dropped[kept, 1:].all()
    D = fixed.functions().numpy()["inertia"](q)
    assert np.linalg.eigvalsh(D)[:, 0].min() >= check["lower_bound"] > 0
    assert fixed.cost == fixed.program().cost()


def test_with_no_floor_under_d_a_d_s_singular_at_samples_is_restored_until_positive_there(
        tmp_path):
    """A point-mass wrist link (no rotational inertia) leaves D without a floor, so D_s
    cannot be proved (example-robot-data's iCub arm). Dropping links 5 and 6 whole then made
    D_s singular at the sampled positions, and that model was deployed as it was. Now the
    inertial parts are restored until D_s is positive definite at every sampled position, and
    the check says it is not a proof. Oracle: numpy's eigenvalues of D_s at those positions,
    and Pinocchio's crba, which D_s then equals where nothing inertial is dropped."""
    text = resources.files("gd_analyze").joinpath("data/puma560.toml").read_text()
    wrist = "com = [0.0, 0.0, 0.032]\ninertia = [0.15e-3, 0.15e-3, 0.04e-3]"
    assert wrist in text              # a point mass off joint 6's axis: D stays regular
    path = tmp_path / "point_wrist.toml"
    path.write_text(text.replace(wrist, "com = [0.02, 0.0, 0.032]\ninertia = [0.0, 0.0, 0.0]"))
    robot = load_robot(path)
    assert not (inertia_floor(robot) > 0).all()
    assert np.linalg.eigvalsh(crba(robot, random_states(robot, 200, 3)[0]))[:, 0].min() > 0
    q, rec, last, broken = _without_the_wrist(robot)
    fixed = with_inertia_check(broken, q)
    check = fixed.inertia_check
    assert not check["proved"] and "no floor under D" in check["why"]
    assert check["restored"] and set(check["restored"]) <= {rec.names[k] for k in last}
    assert check["sampled_min_eigenvalue"] > 0
    assert "not proved" in check["statement"] and "NOT" not in check["statement"]
    _, positions = sample_positions(fixed, q, 2000, 0)
    D = fixed.functions().numpy()["inertia"](positions)
    assert np.linalg.eigvalsh(D)[:, 0].min() > 0
    kept = [rec.names.index(name) for name in check["restored"]]
    assert not fixed.recursive.dropped[kept, 0].any() and fixed.recursive.dropped[kept, 1:].all()


@pytest.mark.slow
@pytest.mark.parametrize("key", ["panda", "erd-panda", "kinova"])
def test_the_default_model_is_proved_and_100000_positions_agree(key):
    robot, region, _, model = _default(key)
    check = model.inertia_check
    assert check["where"] == "region" and check["proved"] and check["lower_bound"] > 0
    assert 0 < check["ratio"] <= 1
    q = np.random.default_rng(7).uniform(region.q_min, region.q_max, (SAMPLED, robot.n))
    D_s = model.functions().numpy()["inertia"](q)
    assert np.linalg.eigvalsh(D_s)[:, 0].min() >= check["lower_bound"]
    D = crba(robot, q)
    assert np.linalg.eigvalsh(D)[:, 0].min() >= min(check["floor"])
    at = crba(robot, np.array([check["witness"]]))
    assert np.linalg.eigvalsh(at)[0, 0] <= check["d_upper"]          # the ratio's denominator


@pytest.mark.slow
@pytest.mark.parametrize("key, joint, value", [("panda", 1, 0.0), ("kinova", 4, np.pi)])
def test_the_sampled_check_passed_a_singular_d_s_the_proof_does_not(key, joint, value):
    """The issue's planes: the default model with the inertial part of ZZ1 dropped too (Panda:
    the default model of the certification before its cuts followed the open columns) and the
    one the sampled check kept after restoring ZZ1 (Kinova) are positive definite at 2,000
    uniform samples of the region, as the old check found, yet singular on the plane; neither
    is proved, and the model deployed is positive definite there by the proved margin."""
    robot, region, model, proved = _default(key)
    rec = model.recursive
    left = model.left_out().copy()
    if key == "kinova":
        left[rec.names.index("ZZ1")] = False
    else:
        left[rec.names.index("ZZ1"), 0] = True
    candidate = _model(robot, dataclasses.replace(rec, dropped=left))
    candidate = dataclasses.replace(candidate, guarantee=model.guarantee)
    _, qs = sample_positions(candidate)
    assert check_inertia(candidate.functions().numpy()["inertia"], qs)["positive_definite"]
    q = np.random.default_rng(1).uniform(region.q_min, region.q_max, (4000, robot.n))
    q[:, joint] = value
    D = candidate.functions().numpy()["inertia"](q)
    assert np.linalg.eigvalsh(D)[:, 0].min() <= 1e-12 * np.abs(D).max()
    proof = prove_inertia(robot, rec.base(robot), left, region.q_min, region.q_max)
    assert not proof.proved
    D = proved.functions().numpy()["inertia"](q)
    assert np.linalg.eigvalsh(D)[:, 0].min() >= proved.inertia_check["lower_bound"] > 0
    assert proved.inertia_check["restored"]


@pytest.mark.slow
def test_the_stored_bound_and_sampled_error_are_the_restored_models():
    """After a restore, the bound and the sampled error are those of the pairs still dropped:
    the bound at least each leaf's sum of their certified bounds, and the sampled error the
    worst at the certification's samples for them (before, they described the model before the
    restore: larger)."""
    robot, region, before, model = _default("kinova")
    assert model.inertia_check["restored"]
    base = base_parameters(robot)
    pb = certified(robot, base, region, 0.0)
    dropped = np.asarray(model.recursive.dropped, bool)
    weights = np.asarray(base.beta, float)[None, :] * dropped.T
    err = worst_states(pb.values, weights, region.qd_max, region.qdd_max)[0].max(axis=0)
    assert np.array_equal(model.guarantee.sampled_error, err)
    leaves = np.einsum("bpln,bp->ln", pb.leaves, dropped).max(axis=0)
    bound = np.asarray(model.bound, float)
    assert (bound >= leaves * (1 - 1e-12)).all()
    assert np.array_equal(np.asarray(model.guarantee.bound, float), bound)
    assert np.array_equal(model.recursive.bound, bound)
    assert (bound <= np.asarray(before.bound)).all() and (bound < np.asarray(before.bound)).any()


def test_an_explicit_model_that_drops_terms_is_not_said_to_be_proved():
    """Its dropped terms are not parameters: checked at the trajectory's positions only, and
    every statement says "not proved" with numpy's smallest eigenvalue there."""
    robot = load_robot("two-link")
    choices = {k: "both" for k in element_labels(robot.n)}
    choices["D12"] = "tran"
    model = SimplifiedModel(robot=robot, choices=choices, dominance_threshold=0.9,
                            negligible_threshold=0.01)
    q = np.random.default_rng(0).uniform(-2, 2, (30, 2))
    check = with_inertia_check(model, q).inertia_check
    assert not check["proved"] and check["lower_bound"] is None and check["samples"] == 30
    D = model.functions().numpy()["inertia"](q)
    assert check["sampled_min_eigenvalue"] == np.linalg.eigvalsh(D)[:, 0].min()
    assert check["statement"].startswith("not proved (an explicit model that drops terms")
    assert "proved positive definite" not in check["statement"]


def test_forward_dynamics_through_d_s_is_pinocchios_aba(puma):
    """EPS = 0: qdd = D_s^-1 (tau - h_s - c_s) equals aba(q, qd, tau) for tau = rnea."""
    robot, q, qd, qdd, rec = puma
    ns = _model(robot, rec).functions().numpy()
    pm = pinocchio_model(robot)
    data = pm.createData()
    tau = np.array([pin.rnea(pm, data, *x) for x in zip(q, qd, qdd)])
    got = np.linalg.solve(ns["inertia"](q), (tau - ns["velocity_terms"](q, qd)
                                             - ns["gravity"](q))[:, :, None])[:, :, 0]
    want = np.array([pin.aba(pm, data, a, b, c) for a, b, c in zip(q, qd, tau)])
    assert np.abs(got - want).max() <= 1e-8 * np.abs(want).max()
    assert np.abs(got - qdd).max() <= 1e-8 * np.abs(qdd).max()


def _smooth_path(N, shift=0.0, seed=3):
    """Symmetric 5 x 5 matrices along a smooth path (a random walk smoothed), shifted by
    ``shift`` I: positive definite or not, with neighbours that differ little (the case the
    screening rules out) and a few jumps (the case it must not)."""
    rng = np.random.default_rng(seed)
    base = rng.normal(size=(5, 5))
    base = base @ base.T + 0.5 * np.eye(5)
    walk = np.cumsum(rng.normal(scale=2e-3, size=(N, 5, 5)), axis=0)
    walk[rng.integers(0, N, 5)] += rng.normal(scale=0.5, size=(5, 5))
    mats = base + walk + shift * np.eye(5)
    return 0.5 * (mats + np.swapaxes(mats, 1, 2))           # symmetric to the last bit


@pytest.mark.parametrize("shift", [0.0, -2.0], ids=["definite", "indefinite"])
@pytest.mark.parametrize("block", [8192, 1000, 7])
def test_check_inertia_s_minima_are_numpys_over_every_position(shift, block):
    """The screened eigenvalues give the minima of numpy's eigvalsh over every position, bit
    for bit, whatever the block; the Gershgorin count is the array code's; NaN never
    passes."""
    mats = _smooth_path(20_000, shift)
    got = check_inertia(lambda q: mats[q[:, 0].astype(int)],
                        np.arange(len(mats), dtype=float)[:, None], block=block)
    diag = np.diagonal(mats, axis1=1, axis2=2)
    s = 1.0 / np.sqrt(np.where(diag > 0, diag, 1.0))
    A = np.abs(mats * s[:, :, None] * s[:, None, :])
    discs = ((diag > 0).all(axis=1)
             & (A.sum(axis=2) - np.diagonal(A, axis1=1, axis2=2) < 1.0).all(axis=1))
    assert got["gershgorin_proved"] == int(discs.sum())
    eig = np.linalg.eigvalsh(mats)
    hi = np.abs(eig).max(axis=1)
    assert got["min_eigenvalue"] == eig[:, 0].min()
    assert got["min_relative_eigenvalue"] == (eig[:, 0] / hi).min()
    assert got["positive_definite"] == bool((eig[:, 0] > 0).all())
    assert got["samples"] == len(mats)
    mats[123] = np.nan
    bad = check_inertia(lambda q: mats[q[:, 0].astype(int)],
                        np.arange(len(mats), dtype=float)[:, None], block=block)
    assert not bad["positive_definite"] and np.isnan(bad["min_eigenvalue"])


def test_the_inertia_check_s_memory_is_flat_in_the_positions(puma):
    """D_s is checked block by block: the largest allocation for 10^5 positions is less than
    twice that for 10^4 (it held (N, n, n) arrays and their eigenvalues at once)."""
    import tracemalloc

    robot, q, _, _, rec = puma
    inertia = _model(robot, rec).functions().numpy()["inertia"]
    rng = np.random.default_rng(0)
    peaks = []
    for N in (10_000, 100_000):
        qs = rng.uniform(robot.q_min, robot.q_max, (N, robot.n))
        tracemalloc.start()
        check_inertia(inertia, qs)
        peaks.append(tracemalloc.get_traced_memory()[1])
        tracemalloc.stop()
    assert peaks[1] < 2 * peaks[0], peaks


def test_the_restore_is_found_from_the_pairs_alone_as_the_check_restores_them():
    """:func:`inertia_restored`, given only the dropped pairs (as the region model's screen
    asks before any program is built), restores the inertial parts that
    :func:`with_inertia_check` restores on the built model: on the model dropping the wrist's
    parameters whole, the same parameters, and its D_s, with only them restored, is positive
    definite at the trajectory's positions where the broken one is singular; a set whose D_s
    is proved comes back as it is."""
    from gd_analyze.certify.positive_definite import inertia_restored

    robot = load_robot("puma560")
    q, qd, qdd = random_states(robot, 60, 2)
    rec = recursive_model(robot, q, qd, qdd, 0.0)
    base = rec.base(robot)
    dropped = np.zeros_like(rec.dropped)
    last = [k for k, name in enumerate(rec.names) if name[-1] in "56"]
    dropped[last] = True
    broken = _model(robot, dataclasses.replace(rec, dropped=dropped))
    check = with_inertia_check(broken, q).inertia_check
    kept = inertia_restored(robot, base, dropped, rec.relative_peak, q.min(0), q.max(0))
    restored = dropped[:, 0] & ~kept[:, 0]
    assert restored.any()
    assert {rec.names[k] for k in np.flatnonzero(restored)} == set(check["restored"])
    np.testing.assert_array_equal(kept[:, 1:], dropped[:, 1:])
    D = _model(robot, dataclasses.replace(rec, dropped=kept)).functions().numpy()["inertia"](q)
    assert np.linalg.eigvalsh(D)[:, 0].min() > 0
    D = broken.functions().numpy()["inertia"](q)
    assert np.linalg.eigvalsh(D)[:, 0].min() <= 1e-12 * np.abs(D).max()
    fine = np.zeros_like(dropped)
    fine[last[0], 1] = True                     # a velocity part: not in D_s
    np.testing.assert_array_equal(
        inertia_restored(robot, base, fine, rec.relative_peak, q.min(0), q.max(0)), fine)
