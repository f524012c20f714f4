"""Least squares on a linear model with known parameters, noise and a dependent column."""

import numpy as np
import pytest

from gd_analyze.estimation.estimate import combine_factors, joint_factors, least_squares


def _problem(seed=0, N=400, n=2, p=4, noise=(0.0, 0.0)):
    rng = np.random.default_rng(seed)
    Y = rng.normal(size=(N, n, p))
    x = rng.normal(size=p)
    tau = Y @ x + rng.normal(size=(N, n)) * np.asarray(noise)
    return Y, tau, x


def test_noise_free_recovers_the_parameters():
    Y, tau, x = _problem()
    est = least_squares(joint_factors(Y, tau, np.ones(tau.shape, bool)), np.zeros(4))
    assert est.identifiable.all() and est.rank == 4
    assert np.allclose(est.value, x, rtol=0, atol=1e-12)
    assert np.allclose(est.ols_value, x, rtol=0, atol=1e-12)


def test_weighted_fit_and_its_covariance_against_the_normal_equations():
    Y, tau, x = _problem(noise=(0.01, 1.0))
    est = least_squares(joint_factors(Y, tau, np.ones(tau.shape, bool)), np.zeros(4))
    # the oracle: numpy's lstsq per joint for sigma, then the weighted normal equations
    A = Y.reshape(-1, 4)
    y = tau.reshape(-1)
    x_ols = np.linalg.lstsq(A, y, rcond=None)[0]
    r = (tau - Y @ x_ols)
    M, p = A.shape
    sigma = np.sqrt((r ** 2).sum(0) / (Y.shape[0] * (1 - p / M)))
    assert np.allclose(est.noise_std, sigma, rtol=1e-10)
    w = np.tile(1 / sigma, Y.shape[0])
    Aw, yw = A * w[:, None], y * w
    xw = np.linalg.solve(Aw.T @ Aw, Aw.T @ yw)
    s2 = np.sum((yw - Aw @ xw) ** 2) / (M - p)
    std = np.sqrt(np.diag(s2 * np.linalg.inv(Aw.T @ Aw)))
    assert np.allclose(est.value, xw, rtol=1e-9)
    assert np.allclose(est.std, std, rtol=1e-8)
    # the weights matter: the weighted estimate is nearer the truth than plain least squares
    assert np.linalg.norm(est.value - x) < np.linalg.norm(x_ols - x)


def test_a_dependent_column_is_reported_and_kept_at_the_prior():
    Y, tau, x = _problem()
    Y[:, :, 3] = 2 * Y[:, :, 1]
    tau = Y @ x
    prior = np.array([0.0, 0.0, 0.0, 0.5])
    est = least_squares(joint_factors(Y, tau, np.ones(tau.shape, bool)), prior)
    assert est.rank == 3 and est.identifiable.sum() == 3
    held = ~est.identifiable
    assert est.value[held] == pytest.approx(prior[held]) and (est.std[held] == 0).all()
    assert np.allclose(Y @ est.value, tau, atol=1e-10)      # the data are still fitted


def test_factors_of_two_parts_equal_the_factors_of_all_rows():
    Y, tau, _ = _problem(noise=(0.1, 0.1))
    used = np.ones(tau.shape, bool)
    used[::7, 1] = False
    whole = least_squares(joint_factors(Y, tau, used), np.zeros(4))
    parts = combine_factors(joint_factors(Y[:150], tau[:150], used[:150]),
                            joint_factors(Y[150:], tau[150:], used[150:]))
    split = least_squares(parts, np.zeros(4))
    assert np.allclose(split.value, whole.value, rtol=1e-12)
    assert np.allclose(split.std, whole.std, rtol=1e-10)
    assert split.condition_number == pytest.approx(whole.condition_number)


def test_too_few_rows_are_refused():
    Y, tau, _ = _problem(N=2)
    with pytest.raises(ValueError, match="rows"):
        least_squares(joint_factors(Y, tau, np.ones(tau.shape, bool)), np.zeros(4))


def test_blocked_factors_equal_one_qr_of_the_used_rows():
    """Several QR_BLOCK blocks and rows left out: R^T R is A^T A of the used rows (numpy's QR
    of the stacked [A_i | y_i], the oracle), for every joint."""
    from gd_analyze.estimation.estimate import QR_BLOCK

    rng = np.random.default_rng(8)
    N, n, p = 2 * QR_BLOCK + 123, 3, 5
    Y = rng.normal(size=(N, n, p))
    tau = rng.normal(size=(N, n))
    used = rng.random((N, n)) > 0.2
    R, counts = joint_factors(Y, tau, used)
    assert counts.tolist() == used.sum(axis=0).tolist()
    for i in range(n):
        M = np.hstack([Y[used[:, i], i], tau[used[:, i], i, None]])
        ref = np.linalg.qr(M, mode="r")
        np.testing.assert_allclose(np.abs(R[i]), np.abs(ref), rtol=0,
                                   atol=1e-10 * np.abs(ref).max())
        np.testing.assert_allclose(R[i].T @ R[i], M.T @ M, rtol=1e-12, atol=1e-9)
