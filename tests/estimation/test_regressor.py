"""The identification regressor against Pinocchio: the rigid links and the drives."""

import numpy as np
import pinocchio as pin

from gd_analyze import load_robot
from gd_analyze.dynamics.base_parameters import base_parameters, random_states
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.estimation.regressor import DRIVE_KINDS, column_names, moving_rows, prior_values
from gd_analyze.symbolic.drive_regressor import IdentificationColumns, identification_regressor


def test_the_prior_values_give_pinocchios_torque_with_the_drives():
    robot = load_robot("puma560-drives")
    base = base_parameters(robot)
    q, qd, qdd = random_states(robot, 50, seed=3)
    kinds = DRIVE_KINDS
    Y = identification_regressor(robot, q, qd, qdd,
                                 IdentificationColumns.keeping_all(base, robot.n, kinds))
    theta = prior_values(base, robot, kinds)
    model = pinocchio_model(robot)
    model.armature = np.zeros(robot.n)
    data = model.createData()
    ref = np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])
    ref = ref + robot.armature * qdd + robot.viscous * qd + robot.coulomb * np.sign(qd)
    assert np.abs(Y @ theta - ref).max() <= 1e-10 * np.abs(ref).max()
    names, col_kinds = column_names(base, robot.n, kinds)
    assert len(names) == Y.shape[2] and names[-1] == "offset_6" and col_kinds[-1] == "offset"
    assert list(names) == IdentificationColumns.keeping_all(base, robot.n, kinds).names()


def test_the_prior_values_hold_the_robot_files_torque_offsets():
    """An identified robot file used as the prior: its offsets are the offset columns' values,
    and Y theta is Pinocchio's torque plus the drives and offsets."""
    import dataclasses

    robot = load_robot("puma560-drives")
    robot = dataclasses.replace(robot, torque_offset=np.linspace(-1.0, 1.5, robot.n))
    base = base_parameters(robot)
    q, qd, qdd = random_states(robot, 30, seed=4)
    Y = identification_regressor(robot, q, qd, qdd,
                                 IdentificationColumns.keeping_all(base, robot.n, DRIVE_KINDS))
    theta = prior_values(base, robot, DRIVE_KINDS)
    assert np.array_equal(theta[-robot.n:], robot.torque_offset)
    model = pinocchio_model(robot)
    model.armature = np.zeros(robot.n)
    data = model.createData()
    ref = np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])
    ref = ref + robot.armature * qdd + robot.viscous * qd + robot.coulomb * np.sign(qd) \
        + robot.torque_offset
    assert np.abs(Y @ theta - ref).max() <= 1e-10 * np.abs(ref).max()


def test_rows_at_rest_are_left_out():
    qd = np.array([[1.0, 0.0], [0.001, 2.0], [-1.0, 2.0]])
    used, threshold = moving_rows(qd)
    assert used.tolist() == [[True, False], [False, True], [True, True]]
    assert threshold.shape == (2,)
