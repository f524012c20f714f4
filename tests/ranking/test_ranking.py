import numpy as np
import pytest
from conftest import SHIPPED
from numpy_engines import element_series

from gd_analyze import gd_terms
from gd_analyze.ranking.ranking import (
    CHAPTER_DOMINANCE,
    arm_scales,
    element_labels,
    rank_dominance,
)
from gd_analyze.trajectory.trajectory import read_trajectory


def test_labels():
    labels = element_labels(6)
    assert len(labels) == 27 and labels[:3] == ["D11", "D12", "D13"] and labels[-1] == "h6"
    assert set(CHAPTER_DOMINANCE) == set(labels)


def _synthetic(tran_D, rot_D, tran_h, rot_h, tau):
    """Constant-in-time 2-joint terms from per-element values."""
    N = 4
    Dt = np.broadcast_to(np.array(tran_D, float), (N, 2, 2)).copy()
    Dr = np.broadcast_to(np.array(rot_D, float), (N, 2, 2)).copy()
    return (Dt, Dr, np.tile(tran_h, (N, 1)).astype(float), np.tile(rot_h, (N, 1)).astype(float),
            np.tile(tau, (N, 1)).astype(float))


def test_classes_follow_the_definitions():
    # D11: 95 % tran -> translational; D12: 50/50 -> both; D22: 5 % tran -> rotational
    # h1: tiny against |tau1| = 100 -> negligible; h2: 0.92 share -> translational
    args = _synthetic([[9.5, 0.5], [0.5, 0.1]], [[0.5, 0.5], [0.5, 1.9]],
                      [0.5, 9.2], [0.4, -0.8], [100.0, 50.0])
    r = rank_dominance(*args, dominance=0.9, negligible=0.01)
    got = dict(zip(r.labels, r.dominance))
    assert got == {"D11": "translational", "D12": "both", "D22": "rotational",
                   "h1": "negligible", "h2": "translational"}
    np.testing.assert_allclose(r.share_tran, [0.95, 0.5, 0.05, 0.5 / 0.9, 9.2 / 10.0])
    # scale of D12 is sqrt(D11 D22) = sqrt(10 * 2)
    np.testing.assert_allclose(r.scale[1], np.sqrt(20.0))
    assert r.choices() == {"D11": "tran", "D12": "both", "D22": "rot", "h1": "none",
                           "h2": "tran"}


def test_thresholds_move_the_boundaries():
    args = _synthetic([[9.5, 0.5], [0.5, 0.1]], [[0.5, 0.5], [0.5, 1.9]],
                      [0.5, 9.2], [0.4, -0.8], [100.0, 50.0])
    strict = dict(zip(*(lambda r: (r.labels, r.dominance))(rank_dominance(*args, dominance=0.96))))
    assert strict["D11"] == "both" and strict["h2"] == "both"
    loose = dict(zip(*(lambda r: (r.labels, r.dominance))(rank_dominance(*args, negligible=0.0))))
    assert loose["h1"] == "both"


def test_share_is_summed_over_set_points():
    N = 3
    Dt = np.zeros((N, 1, 1)); Dr = np.zeros((N, 1, 1))
    Dt[:, 0, 0] = [1.0, -2.0, 0.0]
    Dr[:, 0, 0] = [0.0, 1.0, 3.0]
    r = rank_dominance(Dt, Dr, np.zeros((N, 1)), np.zeros((N, 1)), np.ones((N, 1)))
    assert r.share_tran[0] == pytest.approx(3.0 / 7.0)
    assert r.peak_total[0] == pytest.approx(3.0) and r.peak_tran[0] == 2.0


@pytest.mark.parametrize("s, e", [(0.5, 0.01), (1.2, 0.01), (0.9, -0.1)])
def test_bad_thresholds(s, e):
    args = _synthetic(np.eye(2), np.eye(2), [1, 1], [1, 1], [1, 1])
    with pytest.raises(ValueError):
        rank_dominance(*args, dominance=s, negligible=e)


def test_ranking_on_the_shipped_trajectory_is_self_consistent(puma):
    traj = read_trajectory(SHIPPED, 6)
    t = gd_terms(puma, traj.q, traj.qd)
    tau = t.tau(traj.qdd)
    r = rank_dominance(t.D_tran, t.D_rot, t.h_tran, t.h_rot, tau)
    tran, rot = element_series(t.D_tran, t.D_rot, t.h_tran, t.h_rot)
    for k, cls in enumerate(r.dominance):
        if cls == "translational":
            assert np.abs(tran[:, k]).sum() >= 9 * np.abs(rot[:, k]).sum()
        elif cls == "rotational":
            assert np.abs(rot[:, k]).sum() >= 9 * np.abs(tran[:, k]).sum()
    # D22 of the PUMA is dominated by the masses of links 2 and 3 moving: never rotational
    assert dict(zip(r.labels, r.dominance))["D22"] in ("translational", "both")
    # D66 of the PUMA has no translational part at all: the wrist's last link spins on its axis
    # with its centre of mass on that axis.
    assert dict(zip(r.labels, r.dominance))["D66"] == "rotational"


@pytest.mark.parametrize("name, setpoints", [("stanford", 31), ("puma560", 5000)])
def test_round_off_rule_judges_a_small_joint_against_the_arm(name, setpoints):
    """Oracle: the G-D torque and Pinocchio's rnea are two exact algorithms, so their
    difference is round-off at every joint. Joint 6 of both arms (peak |tau_6| 5.8e-4 and
    1.2e-4 N m) differs by about 1.8e-12 of its own scale, which the own-scale rule alone
    calls data (the tables and the CLI printed it); judged also against the arm's scale
    (64 eps of the largest peak |tau| in the same units) it is round-off. A real difference,
    1e-6 of the inertial torque (qdd scaled by 1 + 1e-6), stays data."""
    import pinocchio as pin

    from gd_analyze import load_robot
    from gd_analyze.dynamics.pinocchio import pinocchio_model
    from gd_analyze.ranking.ranking import arm_scales, is_round_off
    from gd_analyze.trajectory.planning import default_motion, plan_quintic

    robot = load_robot(name)
    traj = plan_quintic(robot, *default_motion(robot), setpoints)
    tau = gd_terms(robot, traj.q, traj.qd).tau(traj.qdd)
    model = pinocchio_model(robot)
    data = model.createData()
    ref = np.array([pin.rnea(model, data, q, qd, qdd)
                    for q, qd, qdd in zip(traj.q, traj.qd, traj.qdd)])
    diff, peak = np.abs(tau - ref).max(axis=0), np.abs(tau).max(axis=0)
    arm = arm_scales(peak, ["N" if p else "N m" for p in robot.prismatic])
    assert np.all(peak > 0) and np.all(np.isfinite(diff))
    assert not is_round_off(diff, peak).all()                 # the own scale alone: data
    assert is_round_off(diff, peak, arm_scale=arm).all()       # the one rule: round-off
    real = np.abs(gd_terms(robot, traj.q, traj.qd).tau(traj.qdd * (1 + 1e-6)) - tau).max(axis=0)
    moving = np.abs(traj.qdd).max(axis=0) > 0
    assert not is_round_off(real, peak, arm_scale=arm)[moving].any()


def test_arm_scales_group_by_units():
    got = arm_scales([2.0, 5e-4, 90.0, np.nan], ["N m", "N m", "N", "kg"])
    assert got[:3].tolist() == [2.0, 2.0, 90.0] and np.isnan(got[3])


def test_an_element_beside_a_rounding_diagonal_is_zero_by_the_arms_floor():
    """D_ij of a diagonal D_jj that is rounding but not tiny (a point-mass last link on its
    axis, computed by sums over the chain: D_66 = 1.4e-17 kg m^2) has the scale
    sqrt(D_ii D_jj), 7e-9, far above D_jj; its own rounding (6.9e-18, below 64 eps of the
    largest D) is still zero, as is_round_off's arm floor says. A real element is not."""
    import numpy as np

    from gd_analyze.ranking.ranking import identically_zero, is_round_off

    n = 2                                         # D11, D12, D22, h1, h2
    peak = np.array([3.7, 6.9e-18, 1.4e-17, 10.0, 1e-3])
    scale = np.array([3.7, np.sqrt(3.7 * 1.4e-17), 1.4e-17, 10.0, 10.0])
    zero = identically_zero(peak, np.zeros(5), peak, scale)
    assert zero.tolist() == [False, True, True, False, False]
    # the same verdict as the reports' one rule with the arm's scale of each kind
    arm = np.array([3.7, 3.7, 3.7, 10.0, 10.0])
    assert is_round_off(peak[:3], scale[:3], arm_scale=arm[:3]).tolist() == [False, True, True]
    assert n * (n + 3) // 2 == peak.size
