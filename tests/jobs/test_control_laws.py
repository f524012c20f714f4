"""The control laws' pieces (gd_analyze.jobs.control): the desired motion through the set points
and the gains."""

import numpy as np
import pytest

from gd_analyze import gd_terms
from gd_analyze.jobs.control import (
    GAIN_RANGES,
    Gains,
    closed_loop_rates,
    control_gains,
    desired_motion,
)
from gd_analyze.trajectory.trajectory import Trajectory


def test_desired_motion_interpolates_q_qd_qdd(shipped):
    rng = np.random.default_rng(4)
    t = np.cumsum(rng.uniform(0.1, 0.3, 12))
    q, qd, qdd = (rng.normal(size=(12, 3)) for _ in range(3))
    for traj in (shipped, Trajectory(t=t, q=q, qd=qd, qdd=qdd)):
        pp = desired_motion(traj)
        for nu, want in ((0, traj.q), (1, traj.qd), (2, traj.qdd)):
            np.testing.assert_allclose(pp(traj.t, nu), want, rtol=1e-9, atol=1e-9)
    # the shipped motion is one quintic: the piecewise quintic reproduces it between set points
    pp = desired_motion(shipped)
    T, q0, q1 = shipped.t[-1], shipped.q[0], shipped.q[-1]
    u = np.linspace(0, 1, 101)[:, None]
    exact = q0 + (q1 - q0) * u**3 * (10 - 15 * u + 6 * u**2)
    np.testing.assert_allclose(pp(u[:, 0] * T), exact, rtol=0, atol=1e-12)


def test_gains(puma, shipped):
    g = control_gains(puma, shipped.q[0], wn=10.0, zeta=0.7)
    np.testing.assert_allclose(g.Kp, 100.0)
    np.testing.assert_allclose(g.Kv, 14.0)
    D0 = np.diagonal(gd_terms(puma, shipped.q[:1], 0 * shipped.q[:1]).D[0])
    np.testing.assert_allclose(g.Kp_pd, D0 * 100.0)
    np.testing.assert_allclose(g.Kv_pd, D0 * 14.0)
    g6 = control_gains(puma, shipped.q[0], wn=np.arange(1.0, 7.0))
    np.testing.assert_allclose(g6.Kp, np.arange(1.0, 7.0) ** 2)
    for bad in ({"wn": 0.0}, {"zeta": -1.0}, {"wn": [1.0, 2.0]}, {"wn": np.nan}):
        with pytest.raises(ValueError):
            control_gains(puma, shipped.q[0], **bad)
    # the command line's ranges, from one constant (any positive wn and zeta were taken)
    for name, (lo, hi) in GAIN_RANGES.items():
        for beyond in (lo * (1 - 1e-12), hi * (1 + 1e-12), [20.0] * 5 + [hi * 2]):
            with pytest.raises(ValueError, match=rf"^{name} must be in \[{lo:g}, {hi:g}\], got "):
                control_gains(puma, shipped.q[0], **{name: beyond})
        assert getattr(control_gains(puma, shipped.q[0], **{name: [lo, hi] * 3}), name).tolist() \
            == [lo, hi] * 3


def test_the_stacked_motion_is_exactly_the_desired_motion_and_its_derivatives():
    """The closed loop evaluates q_d, qd_d and qdd_d as one piecewise polynomial: its values
    are bit for bit those of the desired motion and its two derivatives (the padded leading
    zeros add exactly), which interpolate the set points (the oracle)."""
    from gd_analyze.jobs.control import _stacked

    t = np.array([0.0, 0.4, 1.0, 1.7])
    q = np.array([[0.0, 1.0], [0.3, 0.8], [0.2, 0.1], [-0.4, 0.0]])
    qd = np.array([[0.0, 0.0], [0.5, -1.0], [-0.2, -0.6], [0.0, 0.0]])
    qdd = np.array([[1.0, 0.0], [0.0, -2.0], [-1.0, 1.0], [0.0, 0.0]])
    pp = desired_motion(Trajectory(t=t, q=q, qd=qd, qdd=qdd, source="test"))
    d1, d2 = pp.derivative(1), pp.derivative(2)
    motion = _stacked(pp, d1, d2)
    ts = np.linspace(0.0, 1.7, 97)
    np.testing.assert_array_equal(motion(ts), np.hstack([pp(ts), d1(ts), d2(ts)]))
    np.testing.assert_allclose(motion(t), np.hstack([q, qd, qdd]), atol=1e-12)


def test_the_closed_loop_on_one_state_floats_is_the_closed_loop_on_the_batch_model(
        puma, shipped, puma_analysis):
    """The simplified controller's run, its model evaluated at each right-hand-side call in
    floats (torque_at), equals the run with the batch numpy model (an object without
    torque_at) bit for bit: the same operations in the same order. The model is the PUMA 560's
    pruned recursive one, with sines, cosines and products of every kind."""
    from gd_analyze.jobs.control import track

    model = puma_analysis.model         # the session's analysis (default options), read only

    class BatchOnly:                       # the model without its one-state function
        robot = model.robot

        def torque(self, q, qd, qdd):
            return model.torque(q, qd, qdd)

    desired = desired_motion(shipped)
    gains = control_gains(puma, shipped.q[0])
    t = np.linspace(shipped.t[0], shipped.t[0] + 0.5, 21)
    one, batch = (track(puma, "simplified", gains, desired, t, q0_offset=0.01, choices=c)
                  for c in (model, BatchOnly()))
    assert one.success and batch.success and one.nfev == batch.nfev > 50
    assert np.array_equal(one.q, batch.q) and np.array_equal(one.tau, batch.tau)


def test_a_run_stopped_on_a_dense_trajectory_says_how_many_set_points(puma, monkeypatch):
    """The integrator's evaluations grow with the set points the desired motion passes
    through (C2 joins): a run stopped by the bound on a dense trajectory says their number
    and spacing; on a sparse one it does not."""
    from gd_analyze.jobs import control
    from gd_analyze.trajectory.planning import plan_quintic

    monkeypatch.setattr(control, "MAX_RHS_EVALS", 200)
    start, goal = np.radians([-60, 20, -150, -80, -60, -120]), np.radians([60, 110, -60, 80,
                                                                          60, 120])
    for n_setpoints, dense in ((31, False), (control.DENSE_SETPOINTS + 1, True)):
        traj = plan_quintic(puma, start, goal, n_setpoints=n_setpoints)
        with pytest.raises(ValueError, match="within 200 evaluations") as err:
            control.track(puma, "full", control_gains(puma, traj.q[0]), desired_motion(traj),
                           traj.t)
        said = str(err.value)
        assert "too stiff" in said
        assert (f"passes through {n_setpoints} set points" in said) == dense, said
        if dense:
            spacing = (traj.t[-1] - traj.t[0]) / (n_setpoints - 1)
            assert f"({spacing:.3g} s apart)" in said


def test_a_run_on_unix_time_stamps_is_the_run_from_zero(puma, shipped):
    """The closed loop is time-invariant: the same trajectory stamped 1.7e9 s later (Unix time,
    as a ROS log writes it) gives the same run. The stamps are 2.4e-7 s apart there, so a run
    integrated on them took steps at that resolution and stopped at the evaluation bound."""
    from gd_analyze.jobs.control import track

    late = Trajectory(t=shipped.t + 1.7e9, q=shipped.q, qd=shipped.qd, qdd=shipped.qdd,
                      source="late")
    gains = control_gains(puma, shipped.q[0])
    for controller in ("full", "pd_gravity"):
        runs = [track(puma, controller, gains, desired_motion(traj), traj.t, q0_offset=0.01)
                for traj in (shipped, late)]
        assert all(r.success for r in runs)
        np.testing.assert_array_equal(runs[1].t, late.t)
        # the stamps' own rounding at 1.7e9 s (up to 1.2e-7 s) moves the set points' times
        np.testing.assert_allclose(runs[1].q, runs[0].q, rtol=0, atol=1e-6)
        np.testing.assert_allclose(runs[1].tau, runs[0].tau, rtol=0,
                                   atol=1e-5 * np.abs(runs[0].tau).max())
        # the stamps, rounded, join the pieces a little less smoothly: a few more steps
        assert runs[1].nfev <= 1.5 * runs[0].nfev, (controller, runs[0].nfev, runs[1].nfev)


@pytest.mark.parametrize("wn, zeta", [(20.0, 1e300), (3.0, 1e160), (20.0, 0.5), (2.0, 3.0)])
def test_the_computed_torque_rate_is_the_fast_root_without_overflow(puma, wn, zeta):
    """The fastest root of s^2 + 2 zeta wn s + wn^2, |s| = wn (zeta + sqrt(zeta^2 - 1)) for
    zeta >= 1 and wn below: zeta = 1e300 gave inf ("its fastest mode, inf rad/s") because
    zeta^2 overflowed, and zeta = 0.5 gave zeta wn, half the roots' |s|. Oracle: numpy's roots where they are representable, else the closed
    form's limit 2 zeta wn (the slow root wn / (2 zeta) is negligible beside it)."""
    one = np.ones(6)        # the gains built as control_gains would, which refuses zeta > 100
    with np.errstate(over="ignore", invalid="ignore"):
        gains = Gains(wn=wn * one, zeta=zeta * one, Kp=wn**2 * one, Kv=2 * zeta * wn * one,
                      inertia_scale=one, Kp_pd=wn**2 * one, Kv_pd=2 * zeta * wn * one)
        rate = closed_loop_rates(puma, gains, np.eye(6)[None])["full"]
    exact = (2 * zeta * wn if zeta > 1e100 else
             float(np.abs(np.roots([1.0, 2 * zeta * wn, wn**2])).max()))
    assert rate == pytest.approx(exact, rel=1e-12)


def test_a_run_on_an_arm_with_coulomb_friction_finishes_and_its_plant_is_regularised(shipped):
    """With sign(qd) itself in the plant, the PD + gravity loop on the PUMA 560 with drives
    switched its friction torque at every step where qd crossed 0 and stopped at the evaluation
    bound. With the band, it finishes; its q, qd obey the plant qdd = D^-1 (tau - h - c -
    tau_f) with tau_f's sign(qd) linear within the band (physical identity: the run's
    acceleration, by finite differences of qd, against the forward dynamics at its states)."""
    from gd_analyze import load_robot
    from gd_analyze.jobs.control import track
    from gd_analyze.model.drives import COULOMB_BAND, friction_torque

    robot = load_robot("puma560-drives")
    assert np.any(robot.coulomb)
    fine = np.linspace(shipped.t[0], shipped.t[-1], 3001)
    run = track(robot, "pd_gravity", control_gains(robot, shipped.q[0]),
                desired_motion(shipped), fine, q0_offset=0.01)
    assert run.success and np.isfinite(run.q).all()
    # the plant's acceleration at the run's states, from its torques, against qd's slope
    terms = gd_terms(robot, run.q, run.qd)
    plant_f = friction_torque(robot, run.qd, COULOMB_BAND)
    qdd = np.linalg.solve(terms.D, (run.tau - terms.h - terms.c - plant_f)[..., None])[..., 0]
    slope = np.gradient(run.qd, run.t, axis=0)
    inner = slice(2, -2)
    scale = np.abs(qdd).max(axis=0)
    assert np.all(np.abs(slope[inner] - qdd[inner]).max(axis=0) <= 0.05 * scale)
    # with sign(qd) in the plant instead, the slopes disagree where qd is within the band
    sign_f = friction_torque(robot, run.qd)
    qdd_sign = np.linalg.solve(terms.D, (run.tau - terms.h - terms.c - sign_f)[..., None])[..., 0]
    assert np.abs(slope[inner] - qdd_sign[inner]).max() > 0.5 * scale.max()
