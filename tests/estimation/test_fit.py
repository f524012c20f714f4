"""The identification's fit on its own: preprocessed recordings that the test makes with a true
arm (the robot file with other inertial parameters, friction and offsets), against Pinocchio."""

import numpy as np
import pinocchio as pin
from identify_recordings import builtin_urdf, fourier, irregular_clock, truth_for

from gd_analyze import load_robot
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.estimation.fit import fit_robot
from gd_analyze.estimation.preprocess import preprocess
from gd_analyze.estimation.regressor import DRIVE_KINDS, moving_rows


def _prepared(truth, robot, seconds, seed, noise=0.0, outliers=0):
    n = robot.n
    t = irregular_clock(seconds, seed)
    q, qd, qdd = fourier(n, t, seed=seed)
    true = truth.torque(q, qd, qdd)         # returned as it is: noise and outliers on a copy
    tau = true.copy()
    rng = np.random.default_rng(seed + 7)
    if noise:
        tau = tau + noise * tau.std(axis=0) * rng.normal(size=tau.shape)
    if outliers:        # bursts of two samples: preprocessing replaces single spikes
        rows = rng.choice(len(t) - 1, outliers, replace=False)
        tau[np.concatenate([rows, rows + 1]), 0] += 50 * tau[:, 0].std()
    return preprocess(t, q, tau, qd, qdd, cutoff=None, label=f"rec{seed}",
                      prismatic=robot.prismatic), (q, qd, qdd), true


def _stacked(rows):
    """A recording's filtered regressor rows (RegressorRows) as one array, shape (N, n, p)."""
    blocks = sorted(rows, key=lambda block: block[0])
    assert [a for a, _, _ in blocks[1:]] == [b for _, b, _ in blocks[:-1]]   # a tiling
    assert blocks[0][0] == 0 and blocks[-1][1] == rows.rows
    return np.concatenate([Y for _, _, Y in blocks])


def test_noise_free_training_gives_the_true_torques_and_drives():
    robot = load_robot("puma560")
    truth = truth_for(robot)
    pre, (q, qd, qdd), true = _prepared(truth, robot, 20, seed=3)
    fit, regressors = fit_robot(robot, [pre], ("viscous", "coulomb", "offset"))
    tau_true = true[pre.keep]
    scale = np.abs(tau_true).max()
    assert np.abs(_stacked(regressors[0]) @ fit.theta - tau_true).max() < 1e-8 * scale
    values = dict(zip(fit.names, fit.theta))
    for kind, true in (("viscous", truth.viscous), ("coulomb", truth.coulomb),
                       ("offset", truth.offset)):
        got = np.array([values[f"{kind}_{j + 1}"] for j in range(robot.n)])
        np.testing.assert_allclose(got, true, rtol=0, atol=1e-8 * scale)
    np.testing.assert_allclose(fit.offsets, truth.offset, rtol=0, atol=1e-8 * scale)
    # the robot file as shipped is far off: the test can fail
    assert np.abs(_stacked(regressors[0]) @ fit.prior - tau_true).max() > 1e-2 * scale
    assert fit.kinds[fit.base.rank:] == tuple(k for k in DRIVE_KINDS
                                             if k in ("viscous", "coulomb", "offset")
                                             for _ in range(robot.n))


def test_outlier_rows_are_left_out_and_the_fit_repeated():
    robot = load_robot("puma560")
    truth = truth_for(robot)
    pre, (q, qd, qdd), true = _prepared(truth, robot, 20, seed=4, noise=1e-3, outliers=5)
    fit, regressors = fit_robot(robot, [pre], ("viscous", "coulomb", "offset"))
    assert any("outlier rows" in note for note in fit.notes)
    moving = moving_rows(pre.qd[pre.keep], fit.threshold)[0] | pre.held[None, :]
    assert (moving[:, 0] & ~fit.used[0][:, 0]).sum() >= 5     # the five, at least
    tau_true = true[pre.keep]
    assert np.abs(_stacked(regressors[0]) @ fit.theta - tau_true).max() < 1e-2 * np.abs(tau_true).max()


def test_the_least_squares_alone_give_the_true_torques_without_the_standard_parameters(
        monkeypatch):
    """fit_columns: the same least squares as fit_robot without the standard parameters (the
    clip check's first fit only predicts), so that a failure there cannot stop it: with the
    standard parameters' solvers made to fail, the noise-free PUMA 560's torque (Pinocchio) and
    its drives are found, as fit_robot's."""
    from gd_analyze.estimation import fit as fit_module

    def failed(*args, **kwargs):
        raise AssertionError("the standard parameters are not needed")
    monkeypatch.setattr(fit_module, "closest_standard", failed)
    monkeypatch.setattr(fit_module, "consistent_standard", failed)
    robot = load_robot("puma560")
    truth = truth_for(robot)
    pre, (q, qd, qdd), true = _prepared(truth, robot, 20, seed=3)
    est, regressors = fit_module.fit_columns(robot, [pre], ("viscous", "coulomb", "offset"))
    tau_true = true[pre.keep]
    scale = np.abs(tau_true).max()
    assert np.abs(_stacked(regressors[0]) @ est.value - tau_true).max() < 1e-8 * scale
    np.testing.assert_allclose(est.value[-robot.n:], truth.offset, rtol=0, atol=1e-8 * scale)


def test_the_standard_deviations_hold_for_filtered_recordings():
    """Oracle: the spread of the estimates over noise realisations. The zero-phase filter
    correlates a white torque noise's samples; standard deviations taken as if the rows were
    independent came out about 7 times too small here."""
    robot = load_robot("two-link")
    truth = truth_for(robot, seed=2)
    clocks = [np.arange(0, 30, 1 / 500), np.arange(0, 30, 1 / 100)]     # two rates
    paths = [fourier(robot.n, t, seed=k) for k, t in enumerate(clocks)]
    clean = [truth.torque(q, qd, qdd) for q, qd, qdd in paths]     # once: each fit adds noise
    rng = np.random.default_rng(0)

    def fitted(noise):
        pres = []
        for t, (q, qd, qdd), tau in zip(clocks, paths, clean):
            tau = tau + noise * tau.std(axis=0) * rng.normal(size=tau.shape)
            pres.append(preprocess(t, q, tau, cutoff=4.0, prismatic=robot.prismatic))
        return fit_robot(robot, pres, ("viscous", "coulomb", "offset"))[0].estimate

    exact = fitted(0.0).value           # the filter's own bias, without noise
    z = np.concatenate([(est.value - exact) / est.std for est in
                        (fitted(0.02) for _ in range(8))])
    assert 0.6 < np.sqrt(np.mean(z ** 2)) < 1.6, np.sqrt(np.mean(z ** 2))



def test_a_position_only_recording_at_100_hz_gives_the_true_arm():
    """qd and qdd from the positions alone, sampled at 100 Hz with harmonics up to 2.5 Hz
    (oracle: the true arm's friction, and Pinocchio's rnea of it at random states). Three-point
    differences, whose gain is sin(w h) / (w h), took 0.8 % off qdd at the top harmonic: the
    viscous friction came out up to 2.0 % off, the Coulomb friction 3.4 %."""
    robot = load_robot("ur5")
    truth = truth_for(robot, urdf=builtin_urdf("ur5"))
    t = np.arange(0, 30, 0.01)
    q, qd, qdd = fourier(robot.n, t, seed=3, base_hz=0.5)
    pre = preprocess(t, q, truth.torque(q, qd, qdd), prismatic=robot.prismatic)
    fit = fit_robot(robot, [pre], ("viscous", "coulomb", "offset"))[0]
    values = dict(zip(fit.names, fit.theta))
    for kind, true in (("viscous", truth.viscous), ("coulomb", truth.coulomb)):
        got = np.array([values[f"{kind}_{j + 1}"] for j in range(robot.n)])
        np.testing.assert_allclose(got, true, rtol=3e-3)
    rng = np.random.default_rng(0)
    states = rng.uniform(-1, 1, (300, robot.n)), *rng.normal(size=(2, 300, robot.n))
    model = pinocchio_model(fit.identified)
    data = model.createData()
    got = np.array([pin.rnea(model, data, *x) for x in zip(*states)])
    rigid = np.array([pin.rnea(truth.model, truth.data, *x) for x in zip(*states)])
    assert np.linalg.norm(got - rigid) < 1e-3 * np.linalg.norm(rigid)
