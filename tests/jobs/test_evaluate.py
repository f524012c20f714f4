"""evaluate(): a simplified model's torque error, against Pinocchio as the oracle."""

import numpy as np
from conftest import SHIPPED

from gd_analyze.dynamics.pinocchio import reference_terms
from gd_analyze.jobs.evaluate import evaluate
from gd_analyze.model.robot import with_payload
from gd_analyze.simplify.simplified import SimplifiedModel, full_choices
from gd_analyze.trajectory.trajectory import read_trajectory


def _pin_tau(robot, traj):
    ref = reference_terms(robot, traj.q, traj.qd)
    return np.einsum("nij,nj->ni", ref.D, traj.qdd) + ref.h + ref.c


def test_full_model_has_no_error(puma):
    traj = read_trajectory(SHIPPED, n_joints=6)
    model = SimplifiedModel(puma, full_choices(6), 0.9, 0.01)
    err = evaluate(model, traj)
    assert np.isfinite(err["max_relative_peak_error"])
    assert err["max_relative_peak_error"] < 1e-12


def test_unknown_payload_error_is_the_payload_torque(puma):
    """A full model of the bare arm on a loaded arm errs by exactly the load's torque."""
    traj = read_trajectory(SHIPPED, n_joints=6)
    plant = with_payload(puma, 2.0, (0.0, 0.0, 0.05))
    err = evaluate(SimplifiedModel(puma, full_choices(6), 0.9, 0.01), traj, plant=plant)
    tau_plant, tau_bare = _pin_tau(plant, traj), _pin_tau(puma, traj)
    expected = np.abs(tau_plant - tau_bare).max(axis=0)
    scale = np.abs(tau_plant).max(axis=0)
    np.testing.assert_allclose(err["peak_abs_error"], expected, rtol=0, atol=1e-9 * scale.max())
    np.testing.assert_allclose(err["peak_tau"], scale, rtol=1e-10)
    assert err["max_relative_peak_error"] > 1e-3
