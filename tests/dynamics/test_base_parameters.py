"""Standard parameters, the numeric regressor and the base parameters against Pinocchio's
computeJointTorqueRegressor and rnea."""

import numpy as np
import pinocchio as pin
import pytest
from symbolic_helpers import ROBOTS, rnea, robot, states

from gd_analyze.dynamics.base_parameters import (
    PARAMETER_NAMES,
    base_parameters,
    regressor,
    shortest_decimal,
    standard_parameters,
)
from gd_analyze.dynamics.pinocchio import pinocchio_model

#: Pinocchio's per-joint order (m, mc_x, mc_y, mc_z, Ixx, Ixy, Iyy, Ixz, Iyz, Izz) -> ours.
PIN_ORDER = [4, 5, 7, 6, 8, 9, 1, 2, 3, 0]


def pin_regressor(arm, q, qd, qdd):
    model = pinocchio_model(arm)
    data = model.createData()
    return np.array([pin.computeJointTorqueRegressor(model, data, a, b, c)
                     for a, b, c in zip(q, qd, qdd)])


def _ours_from_pin(W):
    n = W.shape[-1] // 10
    return np.concatenate([W[..., 10 * j:10 * j + 10][..., PIN_ORDER] for j in range(n)], -1)


@pytest.mark.parametrize("name", ROBOTS)
def test_regressor_equals_pinocchio_and_standard_parameters_its_inertias(name):
    arm = robot(name)
    q, qd, qdd = states(arm, 30, 2)
    W = regressor(arm, q, qd, qdd)
    Wp = _ours_from_pin(pin_regressor(arm, q, qd, qdd))
    assert np.abs(W - Wp).max() <= 1e-12 * np.abs(Wp).max()
    model = pinocchio_model(arm)
    pin_phi = np.array([model.inertias[j + 1].toDynamicParameters() for j in range(arm.n)])
    np.testing.assert_allclose(standard_parameters(arm), pin_phi[:, PIN_ORDER],
                               rtol=0, atol=1e-14 * np.abs(pin_phi).max())


@pytest.mark.parametrize("name", ROBOTS)
def test_base_parameters_rank_regrouping_and_torques(name):
    arm = robot(name)
    bp = base_parameters(arm)
    q, qd, qdd = states(arm, 60, 3)
    Wp = pin_regressor(arm, q, qd, qdd).reshape(-1, 10 * arm.n)
    assert bp.rank == np.linalg.matrix_rank(Wp) == bp.beta.size == bp.independent.sum()
    W = regressor(arm, q, qd, qdd).reshape(-1, 10 * arm.n)
    B = bp.independent.reshape(-1)
    WB, WD = W[:, B], W[:, ~B]
    assert np.abs(WD - WB @ bp.K).max() <= 1e-9 * np.abs(W).max()
    tau = rnea(arm, q, qd, qdd).reshape(-1)
    for model_tau in (WB @ bp.beta, W @ bp.values.reshape(-1)):
        assert np.abs(model_tau - tau).max() <= 1e-10 * np.abs(tau).max()
    assert len(bp.names()) == bp.rank


def test_revolute_joints_regroup_yy_mz_m_and_noise_is_exactly_zero():
    """Khalil's regrouping on the PUMA: YY_j, MZ_j, M_j are never base parameters (all
    joints revolute); link 1 keeps ZZ1 only; XX6 - YY6 = 0 of the AKB wrist is exactly 0."""
    arm = robot("puma560")
    bp = base_parameters(arm)
    assert not bp.independent[:, [PARAMETER_NAMES.index(k) for k in ("YY", "MZ", "M")]].any()
    assert bp.names()[0] == "ZZ1" and "XX2" in bp.names()
    values = bp.values
    assert values[5, 0] == 0.0 and values[5, 5] > 0      # XX6 - YY6 regrouped, ZZ6 kept
    assert values[5, 1] == values[5, 2] == values[5, 4] == 0.0
    phi = bp.standard
    assert np.all((phi == 0.0) | (np.abs(phi) > 1e-12))


def test_prismatic_joint_keeps_its_mass():
    """Stanford joint 3 is prismatic: its link's mass is a base parameter (not regrouped)."""
    bp = base_parameters(robot("stanford"))
    assert bp.independent[2, PARAMETER_NAMES.index("M")]


@pytest.mark.parametrize("name", ["puma560", "panda", "ur5", "stanford", "two-link"])
def test_base_parameters_have_the_same_bits_for_any_random_set_points(name):
    """K and beta come out bit for bit the same from eight different stacks of random set
    points (whose rounding noise differs as another BLAS's or platform's does): the exact
    recursive model's operation count depended on the last bits of beta (PUMA 560 319 or 320,
    Panda 609 or 610 with numpy 2.2 to 2.5). Before, 11 to 23 entries of beta differed."""
    arm = robot(name)
    first = base_parameters(arm, seed=0)
    for seed in range(1, 8):
        other = base_parameters(arm, seed=seed)
        assert np.array_equal(other.K, first.K), seed
        assert np.array_equal(other.beta, first.beta), seed


@pytest.mark.parametrize("name", ROBOTS)
def test_decimal_base_parameters_keep_the_torques_to_round_off(name):
    """The decimal K and beta give Pinocchio's rnea within 1e-13 of the largest torque: the
    decimals move K by at most 64 eps (of max(|K_ij|, 1)) and the standard parameters by 4
    eps of their size, which is below the regression's own noise."""
    arm = robot(name)
    bp = base_parameters(arm)
    q, qd, qdd = states(arm, 40, 7)
    W = regressor(arm, q, qd, qdd).reshape(-1, 10 * arm.n)
    tau = rnea(arm, q, qd, qdd).reshape(-1)
    err = np.abs(W[:, bp.independent.reshape(-1)] @ bp.beta - tau).max()
    assert err <= 1e-13 * np.abs(tau).max(), err / np.abs(tau).max()


def test_shortest_decimal():
    eps = np.finfo(float).eps
    noisy = np.array([0.00288 + 4e-18, 0.1 + 0.2, -1 + 2 * eps, 1 / 3, 0.0, np.nan, 0.7 * 0.1])
    tol = 8 * eps * np.maximum(np.abs(noisy), 1e-3)
    out = shortest_decimal(noisy, tol)
    assert out[:3].tolist() == [0.00288, 0.3, -1.0] and out[6] == 0.07
    assert out[3] == float("0.333333333333333")     # 1/3 has no short decimal: 15 digits
    assert out[4] == 0.0 and np.isnan(out[5])
    assert np.all(np.abs(out - noisy)[:5] <= tol[:5])
    assert np.array_equal(shortest_decimal(noisy[:4], 0.0), noisy[:4])     # nothing may move


@pytest.mark.parametrize("name", ROBOTS)
def test_decimal_coefficients_fit_other_set_points_as_well_as_least_squares(name, monkeypatch):
    """On set points the coefficients were not fitted to, W_D - W_B K is no larger (within
    4 eps of the largest column) with the decimal K than with the least-squares K it was made
    from: the decimals are taken only where they are the exact regrouping (a general
    chain's, "mixed-chain" and "modified-dh", mostly keep their least-squares values)."""
    import gd_analyze.dynamics.base_parameters as module

    arm = robot(name)
    bp = base_parameters(arm)
    monkeypatch.setattr(module, "_decimal_columns", lambda K, WB, WD: K)
    least = base_parameters(arm).K
    q, qd, qdd = states(arm, 4 * arm.n + 20, 11)
    W = regressor(arm, q, qd, qdd).reshape(-1, 10 * arm.n)
    B = bp.independent.reshape(-1)
    WB, WD = W[:, B], W[:, ~B]
    eps_big = np.finfo(float).eps * np.linalg.norm(W, axis=0).max()
    fit = np.linalg.norm(WD - WB @ bp.K, axis=0)
    assert np.all(fit <= np.linalg.norm(WD - WB @ least, axis=0) + 4 * eps_big), fit / eps_big
