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


def test_the_errors_are_gathered_block_by_block_in_bounded_memory(puma, monkeypatch):
    """In blocks of a few set points, the error of a bare arm's full model on a loaded arm is
    still the load's torque (Pinocchio), peak and RMS; the largest allocation of evaluate
    does not grow with the set points (tracemalloc, 10^4 against 10^5)."""
    import tracemalloc

    from gd_analyze.jobs import evaluate as job
    from gd_analyze.trajectory.planning import plan_quintic

    plant = with_payload(puma, 2.0, (0.0, 0.0, 0.05))
    model = SimplifiedModel(puma, full_choices(6), 0.9, 0.01)
    start, goal = np.radians([-60, 20, -150, -80, -60, -120]), np.radians([60, 110, -60, 80,
                                                                          60, 120])
    traj = plan_quintic(puma, start, goal, n_setpoints=101)
    monkeypatch.setattr(job, "EVALUATE_BLOCK", 7)
    err = evaluate(model, traj, plant=plant)
    diff = np.abs(_pin_tau(plant, traj) - _pin_tau(puma, traj))
    scale = np.abs(_pin_tau(plant, traj)).max()
    np.testing.assert_allclose(err["peak_abs_error"], diff.max(axis=0), rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(err["rms_error"], np.sqrt((diff**2).mean(axis=0)), rtol=0,
                               atol=1e-9 * scale)
    monkeypatch.setattr(job, "EVALUATE_BLOCK", 4096)
    peaks = []
    for N in (10_000, 100_000):
        traj = plan_quintic(puma, start, goal, n_setpoints=N)
        tracemalloc.start()
        evaluate(model, traj, plant=plant)
        peaks.append(tracemalloc.get_traced_memory()[1])
        tracemalloc.stop()
    assert peaks[1] < 1.5 * peaks[0], peaks
