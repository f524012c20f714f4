"""The Python API for a notebook (issue 30 item 6): what ``import gd_analyze as gd`` offers, each
checked against an oracle (Pinocchio) or against the command line's own output."""

import numpy as np
import pinocchio as pin
import pytest
from urdf_oracle import UrdfOracle

import gd_analyze as gd
from gd_analyze.core.symbolic.base_parameters import random_states as _random_states
from gd_analyze.formulations.pinocchio import pinocchio_model
from gd_analyze.io.urdf import builtin_urdf_path


def _rnea_oracle(name, robot):
    """Pinocchio's rnea: the shipped URDF's own model for the Panda, else the robot's chain."""
    if name == "panda":
        oracle = UrdfOracle(builtin_urdf_path("panda"), robot.metadata["urdf_joints"])
        return oracle.rnea
    model = pinocchio_model(robot)
    data = model.createData()
    return lambda q, v, a: pin.rnea(model, data, q, v, a)


@pytest.mark.parametrize("name", ["puma560", "panda", "stanford"])
def test_regressor_times_beta_is_rnea(name):
    robot = gd.load_robot(name)
    q, qd, qdd = _random_states(robot, 100, seed=7)
    Y, beta = gd.regressor(robot, q, qd, qdd)
    assert Y.shape == (100, robot.n, beta.size) and beta.ndim == 1
    rnea = _rnea_oracle(name, robot)
    tau_ref = np.array([rnea(*s) for s in zip(q, qd, qdd)])
    scale = np.abs(tau_ref).max(axis=0)
    assert (scale > 0).all()
    assert np.max(np.abs(Y @ beta - tau_ref) / scale) < 1e-10
    # fewer columns than the 10 n standard parameters, and none of them zero
    assert beta.size < 10 * robot.n and np.abs(Y).max(axis=(0, 1)).min() > 0


def test_regressor_of_one_state_and_prismatic_joint_is_used():
    robot = gd.load_robot("stanford")
    assert robot.prismatic.any()
    q, qd, qdd = (x[0] for x in _random_states(robot, 1, seed=3))
    Y, beta = gd.regressor(robot, q, qd, qdd)
    assert Y.shape == (1, robot.n, beta.size)
    with pytest.raises(ValueError, match="expected shape"):
        gd.regressor(robot, q[:-1], qd, qdd)
