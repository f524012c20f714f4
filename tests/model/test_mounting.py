"""model/mounting.py: the base turned in the world and another gravity vector.

Oracles: Pinocchio's rpyToMatrix (the URDF rpy convention) and computeGeneralizedGravity of
the unmounted model with its gravity set to R^T g_world; physical identities (no gravity, no c;
a turn about the gravity axis changes nothing).
"""

import numpy as np
import pinocchio as pin
import pytest

from gd_analyze import InputError, gd_terms, load_robot
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.model.mounting import rpy_matrix, with_mounting


@pytest.mark.parametrize("rpy", [(0, 0, 0), (0, 90, 0), (180, 0, 0), (30, -45, 120),
                                 (-170, 12, 95)])
def test_rpy_matrix_is_urdfs_rpy(rpy):
    expected = pin.rpy.rpyToMatrix(*np.radians(rpy))
    np.testing.assert_allclose(rpy_matrix(*rpy, degrees=True), expected, atol=1e-15)
    np.testing.assert_allclose(rpy_matrix(*np.radians(rpy)), expected, atol=1e-15)


def test_quarter_turns_are_exact():
    R = rpy_matrix(0, 90, 0, degrees=True)
    assert set(np.unique(R).tolist()) <= {-1.0, 0.0, 1.0}


@pytest.mark.parametrize("name", ["puma560", "ur5", "stanford"])
@pytest.mark.parametrize("rpy", [(0, 90, 0), (30, -45, 120)])
def test_gravity_torque_matches_pinocchio_with_the_rotated_gravity(name, rpy):
    robot = load_robot(name)
    mounted = with_mounting(robot, base_rpy=rpy)
    model = pinocchio_model(robot)
    model.gravity.linear = rpy_matrix(*rpy, degrees=True).T @ np.asarray(robot.gravity)
    data = model.createData()
    rng = np.random.default_rng(5)
    q = rng.uniform(-1.0, 1.0, (20, robot.n))
    c = gd_terms(mounted, q, np.zeros_like(q)).c
    ref = np.array([pin.computeGeneralizedGravity(model, data, qi).copy() for qi in q])
    scale = np.abs(ref).max(axis=0) + 1e-300
    assert np.all(np.abs(c - ref) <= 1e-10 * scale.max())


def test_no_gravity_means_no_c_and_a_turn_about_g_changes_nothing():
    robot = load_robot("puma560")
    q = np.random.default_rng(1).uniform(-1, 1, (10, 6))
    assert np.all(gd_terms(with_mounting(robot, gravity=(0, 0, 0)), q, 0 * q).c == 0.0)
    turned = with_mounting(robot, base_rpy=(0, 0, 73))       # yaw about the vertical
    np.testing.assert_allclose(gd_terms(turned, q, 0 * q).c, gd_terms(robot, q, 0 * q).c,
                               atol=1e-12)


@pytest.mark.parametrize("bad", [(0, 0), (0, float("nan"), 0), (0, 0, float("inf"))])
def test_bad_vectors_are_refused(bad):
    with pytest.raises(InputError):
        with_mounting(load_robot("two-link"), gravity=bad)
