"""The identification regressor against Pinocchio: the rigid links and the drives."""

import numpy as np
import pinocchio as pin

from gd_analyze import load_robot
from gd_analyze.core.identify.regressor import (
    DRIVE_KINDS,
    column_names,
    drive_columns,
    identification_regressor,
    moving_rows,
    prior_values,
)
from gd_analyze.core.symbolic.base_parameters import base_parameters, random_states
from gd_analyze.formulations.pinocchio import pinocchio_model


def test_the_prior_values_give_pinocchios_torque_with_the_drives():
    robot = load_robot("puma560-drives")
    base = base_parameters(robot)
    q, qd, qdd = random_states(robot, 50, seed=3)
    kinds = DRIVE_KINDS
    Y = identification_regressor(robot, q, qd, qdd, base, kinds)
    theta = prior_values(base, robot, kinds)
    model = pinocchio_model(robot)
    model.armature = np.zeros(robot.n)
    data = model.createData()
    ref = np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])
    ref = ref + robot.armature * qdd + robot.viscous * qd + robot.coulomb * np.sign(qd)
    assert np.abs(Y @ theta - ref).max() <= 1e-10 * np.abs(ref).max()
    names, col_kinds = column_names(base, robot.n, kinds)
    assert len(names) == Y.shape[2] and names[-1] == "offset_6" and col_kinds[-1] == "offset"


def test_drive_columns_touch_their_joint_only():
    qd = np.array([[0.5, -1.0, 0.0]])
    cols = drive_columns(qd, np.array([[2.0, 3.0, 4.0]]), ("armature", "coulomb"))
    assert cols.shape == (1, 3, 6)
    assert np.array_equal(cols[0, :, :3], np.diag([2.0, 3.0, 4.0]))
    assert np.array_equal(cols[0, :, 3:], np.diag([1.0, -1.0, 0.0]))


def test_rows_at_rest_are_left_out():
    qd = np.array([[1.0, 0.0], [0.001, 2.0], [-1.0, 2.0]])
    used, threshold = moving_rows(qd)
    assert used.tolist() == [[True, False], [False, True], [True, True]]
    assert threshold.shape == (2,)
