"""Drives and friction: armature as a third part of D, friction as a
separate torque term, against Pinocchio with ``model.armature`` set and against hand-computed
identities."""

import math

import numpy as np
import pytest
from numpy_engines import gd_terms_numpy

from gd_analyze import InputError, gd_terms, load_robot
from gd_analyze.cli import main
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.model.drives import friction_torque, rigid_links
from gd_analyze.model.robot_spec import robot_from_chain, robot_from_dict
from gd_analyze.ranking.ranking import rank_dominance

TOL = 1e-10
#: The G-D kernel (gd_terms) and its oracle, the Jacobian form as array code.
ENGINES = {"numpy": gd_terms_numpy, "compiled": gd_terms}


def _pinocchio(robot, q, qd, qdd):
    """Pinocchio's crba (upper triangle mirrored) and rnea, model.armature set."""
    import pinocchio as pin

    model = pinocchio_model(robot)
    assert np.array_equal(model.armature, robot.armature)
    data = model.createData()
    D = np.array([pin.crba(model, data, qk) for qk in q])
    D = np.triu(D) + np.swapaxes(np.triu(D, 1), 1, 2)
    tau = np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])
    return D, tau


def _friction(robot, qd):
    """viscous qd + coulomb sign(qd) + torque_offset, written out joint by joint."""
    out = np.zeros_like(qd)
    for k in range(qd.shape[0]):
        for i in range(qd.shape[1]):
            v = qd[k, i]
            out[k, i] = robot.viscous[i] * v + robot.coulomb[i] * (1 if v > 0 else -1 if v < 0
                                                                    else 0) \
                + robot.torque_offset[i]
    return out


def _natural_errors(robot, q, qd, qdd, engine):
    terms = ENGINES[engine](robot, q, qd)
    D_ref, rnea = _pinocchio(robot, q, qd, qdd)
    tau_ref = rnea + _friction(robot, qd)
    diag = np.einsum("kii->ki", D_ref)
    assert diag.min() > 0
    scale_D = np.sqrt(diag[:, :, None] * diag[:, None, :])
    scale_tau = np.abs(tau_ref).max(axis=0)
    D_parts = terms.D_tran + terms.D_rot + terms.D_arm
    errs = {"D": float((np.abs(terms.D - D_ref) / scale_D).max()),
            "D parts": float((np.abs(D_parts - D_ref) / scale_D).max()),
            "tau": float((np.abs(terms.tau(qdd) - tau_ref) / scale_tau).max())}
    assert all(math.isfinite(v) for v in errs.values()), errs
    return terms, errs


def _random_states(robot, count, seed):
    rng = np.random.default_rng(seed)
    n = robot.n
    qd = rng.uniform(-2, 2, (count, n))
    qd[0, :] = 0.0                       # sign(0) = 0: no Coulomb torque at rest
    return rng.uniform(-np.pi, np.pi, (count, n)), qd, rng.uniform(-2, 2, (count, n))


def test_puma_drives_carry_the_toolbox_values_reflected_to_the_links():
    robot = load_robot("puma560-drives")
    # Robotics Toolbox Puma560: Jm, G, B, Tc+; armature Jm G^2, viscous B G^2, coulomb Tc+ |G|
    Jm = [200e-6, 200e-6, 200e-6, 33e-6, 33e-6, 33e-6]
    G = [-62.6111, 107.815, -53.7063, 76.0364, 71.923, 76.686]
    B = [1.48e-3, .817e-3, 1.38e-3, 71.2e-6, 82.6e-6, 36.7e-6]
    Tc = [0.395, 0.126, 0.132, 11.2e-3, 9.26e-3, 3.96e-3]
    np.testing.assert_allclose(robot.armature, [j * g * g for j, g in zip(Jm, G)], rtol=1e-12)
    np.testing.assert_allclose(robot.viscous, [b * g * g for b, g in zip(B, G)], rtol=1e-5)
    np.testing.assert_allclose(robot.coulomb, [t * abs(g) for t, g in zip(Tc, G)], rtol=1e-5)
    plain = load_robot("puma560")
    for name in ("mass", "com", "inertia", "d", "a", "alpha", "offset"):
        np.testing.assert_array_equal(getattr(robot, name), getattr(plain, name))
    assert not plain.armature.any() and not plain.viscous.any() and not plain.coulomb.any()


@pytest.mark.parametrize("engine", ENGINES)
def test_puma_with_drives_matches_pinocchio_armature_and_hand_friction(engine):
    robot = load_robot("puma560-drives")
    q, qd, qdd = _random_states(robot, 200, 5)
    terms, errs = _natural_errors(robot, q, qd, qdd, engine)
    assert max(errs.values()) < TOL, errs
    # the armature is a separate part: D_tran and D_rot are the rigid links' alone
    rigid = ENGINES[engine](load_robot("puma560"), q, qd)
    np.testing.assert_array_equal(terms.D_tran, rigid.D_tran)
    np.testing.assert_array_equal(terms.D_rot, rigid.D_rot)
    np.testing.assert_array_equal(np.einsum("kii->ki", terms.D_arm),
                                  np.broadcast_to(robot.armature, (200, 6)))


def test_random_chain_with_prismatic_joints_and_drives_matches_pinocchio():
    from model.test_chain import random_chain_spec

    joints = random_chain_spec(6, 11, p_prismatic=0.5)
    rng = np.random.default_rng(3)
    for j in joints:
        j.update(armature=rng.uniform(0.0, 2.0), viscous=rng.uniform(0.0, 5.0),
                 coulomb=rng.uniform(0.0, 3.0), torque_offset=rng.uniform(-4.0, 4.0))
    robot = robot_from_chain("drives", joints, [0.3, -0.2, -9.81], source="<test>")
    assert "prismatic" in robot.joint_types and robot.armature.all()
    assert (robot.torque_offset < 0).any() and robot.torque_offset.all()
    q, qd, qdd = _random_states(robot, 150, 9)
    for engine in ENGINES:
        _, errs = _natural_errors(robot, q, qd, qdd, engine)
        assert max(errs.values()) < TOL, (engine, errs)


def test_friction_is_viscous_times_qd_plus_coulomb_times_sign():
    robot = robot_from_dict({"name": "f", "gravity": [0, 0, -9.81], "link": [
        {"d": 0, "a": 1, "alpha_deg": 0, "mass": 1, "com": [0, 0, 0], "inertia": [0, 0, 0],
         "q_limits_deg": [-90, 90], "qd_max_deg": 90, "qdd_max_deg": 90,
         "viscous": 0.5, "coulomb": 3.0},
        {"d": 0, "a": 1, "alpha_deg": 0, "mass": 1, "com": [0, 0, 0], "inertia": [0, 0, 0],
         "q_limits_deg": [-90, 90], "qd_max_deg": 90, "qdd_max_deg": 90}]})
    qd = np.array([[1.0, 1.0], [-2.0, -2.0], [0.0, 0.0]])
    # 0.5 * 1 + 3 = 3.5; 0.5 * (-2) - 3 = -4; at rest 0; joint 2 has no friction
    assert friction_torque(robot, qd).tolist() == [[3.5, 0.0], [-4.0, 0.0], [0.0, 0.0]]
    terms = gd_terms(robot, np.zeros((3, 2)), qd)
    no_f = gd_terms(rigid_links(robot), np.zeros((3, 2)), qd)
    np.testing.assert_array_equal(terms.tau(np.zeros((3, 2))) - no_f.tau(np.zeros((3, 2))),
                                  [[3.5, 0.0], [-4.0, 0.0], [0.0, 0.0]])
    # a band of 0.5 (a simulated plant's): sign(qd) beyond it, qd / 0.5 within it
    qd = np.array([[1.0, 0.0], [-0.25, 0.0], [0.1, 0.0]])
    # 0.5 + 3 = 3.5; 0.5 * (-0.25) + 3 * (-0.5) = -1.625; 0.05 + 3 * 0.2 = 0.65
    np.testing.assert_allclose(friction_torque(robot, qd, band=0.5),
                               [[3.5, 0.0], [-1.625, 0.0], [0.65, 0.0]], rtol=1e-15)


def test_armature_dominated_diagonal_counts_as_rotational():
    # joint 1 of the two-link arm with a rotor of 100 times its link's D_11: the share of the
    # translational part drops below 1 - s, D11 becomes rotational with share_arm near 1
    robot = load_robot("two-link")
    q = np.linspace(0, 1, 30)[:, None] * np.array([1.0, -0.5])
    qd = np.ones_like(q)
    terms = gd_terms(robot, q, qd)
    tau = terms.tau(np.zeros_like(q))
    plain = rank_dominance(terms.D_tran, terms.D_rot, terms.h_tran, terms.h_rot, tau)
    arm = np.array([100.0 * terms.D_tran[:, 0, 0].max(), 0.0])
    ranked = rank_dominance(terms.D_tran, terms.D_rot, terms.h_tran, terms.h_rot, tau,
                            armature=arm)
    k = list(ranked.labels).index("D11")
    assert plain.dominance[k] == "translational"
    assert ranked.dominance[k] == "rotational" and ranked.share_arm[k] > 0.98
    expect = terms.D_tran[:, 0, 0].sum() / (terms.D_tran[:, 0, 0].sum()
                                           + np.abs(terms.D_rot[:, 0, 0] + arm[0]).sum())
    assert ranked.share_tran[k] == pytest.approx(expect, rel=1e-12)
    assert ranked.dominance[1:] == plain.dominance[1:]      # off the diagonal: unchanged


def _spec(**drive):
    link = {"d": 0, "a": 1, "alpha_deg": 0, "mass": 1, "com": [0.5, 0, 0],
            "inertia": [0, 0, 0.1], "q_limits_deg": [-90, 90], "qd_max_deg": 90,
            "qdd_max_deg": 90, **drive}
    return {"name": "one", "gravity": [0, 0, -9.81], "link": [link]}


def test_rotor_inertia_and_gear_ratio_give_the_armature():
    robot = robot_from_dict(_spec(rotor_inertia=2e-4, gear_ratio=-50.0))
    assert robot.armature.tolist() == [2e-4 * 2500.0]
    again = robot_from_dict(robot.to_dict())
    assert again.armature.tolist() == robot.armature.tolist()


@pytest.mark.parametrize("drive, column", [
    ({"armature": 0.5, "rotor_inertia": 1e-4, "gear_ratio": 50.0}, "link[1].rotor_inertia"),
    ({"rotor_inertia": 1e-4}, "link[1].gear_ratio"),
    ({"viscous": -1.0}, "link[1].viscous"),
    ({"coulomb": float("nan")}, "link[1].coulomb"),
    ({"armature": "big"}, "link[1].armature"),
    ({"torque_offset": float("inf")}, "link[1].torque_offset"),
    ({"torque_offset": True}, "link[1].torque_offset"),
])
def test_bad_drives_are_refused_naming_the_key(drive, column):
    with pytest.raises(InputError) as info:
        robot_from_dict(_spec(**drive))
    assert info.value.column == column


def test_torque_offset_of_either_sign_is_read_added_and_written_back():
    """tau_0 adds to tau_f whatever qd (at rest too), survives to_dict, and a robot with only
    offsets has drives (its G-D terms carry tau_f)."""
    robot = robot_from_dict(_spec(torque_offset=-2.5, viscous=0.5))
    assert robot.torque_offset.tolist() == [-2.5] and robot.has_friction
    qd = np.array([[1.0], [0.0], [-2.0]])
    assert friction_torque(robot, qd).tolist() == [[-2.0], [-2.5], [-3.5]]
    again = robot_from_dict(robot.to_dict())
    assert again.torque_offset.tolist() == [-2.5]
    only = robot_from_dict(_spec(torque_offset=1.0))
    assert only.has_friction and not only.has_armature
    terms = gd_terms(only, np.zeros((2, 1)), np.zeros((2, 1)))
    rigid = gd_terms(rigid_links(only), np.zeros((2, 1)), np.zeros((2, 1)))
    np.testing.assert_array_equal(terms.tau(np.zeros((2, 1))) - rigid.tau(np.zeros((2, 1))),
                                  [[1.0], [1.0]])


def test_robot_file_with_both_armature_forms_exits_2_with_one_line(tmp_path, capsys):
    path = tmp_path / "arm.toml"
    path.write_text("""name = "arm"
gravity = [0, 0, -9.81]
[[link]]
d = 0
a = 1
alpha_deg = 0
mass = 1
com = [0.5, 0, 0]
inertia = [0, 0, 0.1]
q_limits_deg = [-90, 90]
qd_max_deg = 90
qdd_max_deg = 90
armature = 0.5
rotor_inertia = 1e-4
gear_ratio = 50
""")
    traj = tmp_path / "t.csv"
    traj.write_text("t,q1\n0,0\n0.1,0.1\n0.2,0.2\n")
    code = main(["analyze", str(path), str(traj), "-o", str(tmp_path / "out"), "--no-report"])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    assert "link[1].rotor_inertia" in err and "armature" in err


@pytest.mark.parametrize("name, armature, friction", [("puma560", False, False),
                                                      ("puma560-drives", True, True)])
def test_a_robot_says_once_whether_it_has_drives(name, armature, friction):
    """has_armature and has_friction, kept once per robot: the PUMA 560's rigid links have
    neither, puma560-drives.toml both; and what the G-D terms carry follows them, also for a
    robot built again with only its friction taken away."""
    import dataclasses

    robot = load_robot(name)
    assert (robot.has_armature, robot.has_friction) == (armature, friction)
    q, qd = np.full((2, 6), 0.3), np.full((2, 6), -0.5)
    terms = gd_terms(robot, q, qd)
    assert (terms.armature is not None, terms.tau_f is not None) == (armature, friction)
    if friction:
        np.testing.assert_array_equal(terms.tau_f, robot.viscous * qd - robot.coulomb)
        still = dataclasses.replace(robot, viscous=np.zeros(6), coulomb=np.zeros(6))
        assert robot.has_friction and not still.has_friction
        assert friction_torque(still, qd) is None
