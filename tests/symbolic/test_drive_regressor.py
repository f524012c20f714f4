"""The identification regressor (base regressor with drive columns) against Pinocchio: its
columns span what computeJointTorqueRegressor's and the drive columns span, and it reproduces
rnea with armature plus viscous, Coulomb friction and offsets."""

import numpy as np
import pinocchio as pin
import pytest
from symbolic_helpers import BUILTIN, robot, states

from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.symbolic.drive_regressor import (
    DRIVE_COLUMNS,
    drive_regressor,
    identification_columns,
    identification_regressor,
)


def _pin_regressor(arm, q, qd, qdd):
    model = pinocchio_model(arm)
    data = model.createData()
    return np.array([pin.computeJointTorqueRegressor(model, data, a, b, c)
                     for a, b, c in zip(q, qd, qdd)])


def _reference_drives(qd, qdd):
    """qdd_i, qd_i, sign(qd_i), 1 on joint i's row, kind-major, built entry by entry."""
    N, n = qd.shape
    out = np.zeros((N, n, 4 * n))
    for s in range(N):
        for i in range(n):
            out[s, i, [i, n + i, 2 * n + i, 3 * n + i]] = (qdd[s, i], qd[s, i],
                                                          np.sign(qd[s, i]), 1.0)
    return out


def _rank(W, scale):
    s = np.linalg.svd(W, compute_uv=False)
    return int((s > 1e-9 * scale).sum())


@pytest.mark.parametrize("name", BUILTIN)
def test_columns_span_pinocchios_regressor_and_the_drive_columns(name):
    arm = robot(name)
    cols = identification_columns(arm)
    q, qd, qdd = states(arm, 40, 7)
    Y = identification_regressor(arm, q, qd, qdd, cols).reshape(-1, cols.count)
    ref = np.concatenate([_pin_regressor(arm, q, qd, qdd), _reference_drives(qd, qdd)],
                         axis=2).reshape(Y.shape[0], -1)
    scale = np.linalg.norm(ref, 2)
    # the same span: neither adds a direction to the other, and ours has no redundant column
    assert _rank(Y, scale) == cols.count == _rank(ref, scale) \
        == _rank(np.hstack([Y, ref]), scale)
    assert len(cols.names()) == cols.count


@pytest.mark.parametrize("name", BUILTIN)
def test_reproduces_rnea_with_armature_friction_and_offsets(name):
    """Pinocchio's rnea with model.armature, plus F_v qd + F_c sign(qd) + tau_0, lies in the
    columns' span: least squares on 40 states fits it to rounding, and predicts 20 others."""
    arm = robot(name)
    cols = identification_columns(arm)
    rng = np.random.default_rng(3)
    n = arm.n
    Ia, Fv, Fc, tau0 = (rng.uniform(0.1, 2.0, n) for _ in range(4))
    model = pinocchio_model(arm)
    model.armature = Ia
    data = model.createData()

    def tau(q, qd, qdd):
        rigid = np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])
        return rigid + Fv * qd + Fc * np.sign(qd) + tau0

    q, qd, qdd = states(arm, 40, 8)
    Y = identification_regressor(arm, q, qd, qdd, cols).reshape(-1, cols.count)
    T = tau(q, qd, qdd).reshape(-1)
    theta = np.linalg.lstsq(Y, T, rcond=None)[0]
    q2, qd2, qdd2 = states(arm, 20, 9)
    T2 = tau(q2, qd2, qdd2).reshape(-1)
    pred = identification_regressor(arm, q2, qd2, qdd2, cols).reshape(-1, cols.count) @ theta
    assert np.abs(pred - T2).max() <= 1e-8 * np.abs(T2).max()
    # a kept drive parameter is identified as itself (it regroups nothing)
    names = cols.names()
    for j in range(n):
        for kind, values in (("viscous", Fv), ("coulomb", Fc), ("offset", tau0)):
            label = f"{kind}_{j + 1}"
            assert abs(theta[names.index(label)] - values[j]) <= 1e-8 * np.abs(T2).max()


def test_regrouped_armatures_of_the_puma():
    """Joint 1 turns about the vertical and joint 2 across it: ZZ_1's and ZZ_2's columns are
    qdd_1 and qdd_2 on their own rows (Pinocchio's regressor), so Ia1 and Ia2 regroup."""
    arm = robot("puma560")
    cols = identification_columns(arm)
    assert cols.dropped() == ["armature_1", "armature_2"]
    q, qd, qdd = states(arm, 10, 1)
    W = _pin_regressor(arm, q, qd, qdd)
    zz = 9          # Pinocchio's Izz within a link's 10
    for j in (0, 1):
        col = W[:, :, 10 * j + zz]
        expected = np.zeros_like(col)
        expected[:, j] = qdd[:, j]
        np.testing.assert_allclose(col, expected, atol=1e-12)
    assert all(cols.drive_kept[j].all() for j in range(2, arm.n))


def test_drive_columns_values_order_and_smoothing():
    qd = np.array([[0.5, -2.0, 0.0]])
    qdd = np.array([[3.0, 4.0, -1.0]])
    D = drive_regressor(qd, qdd)
    np.testing.assert_array_equal(D, _reference_drives(qd, qdd))
    only = drive_regressor(qd, qdd, ("offset", "viscous"))          # taken in the fixed order
    np.testing.assert_array_equal(only[0, 1], [0, -2.0, 0, 0, 1.0, 0])
    smooth = drive_regressor(qd, qdd, ("coulomb",), coulomb_velocity=0.1)
    np.testing.assert_allclose(np.diagonal(smooth[0]), np.tanh(qd[0] / 0.1), rtol=1e-15)
    assert DRIVE_COLUMNS == ("armature", "viscous", "coulomb", "offset")


@pytest.mark.parametrize("kwargs, message", [
    ({"drives": ("stiction",)}, "unknown drive column"),
    ({"drives": ("viscous", "viscous")}, "repeated"),
    ({"coulomb_velocity": -1.0}, "coulomb_velocity"),
    ({"coulomb_velocity": float("nan")}, "coulomb_velocity"),
])
def test_bad_arguments_are_refused(kwargs, message):
    with pytest.raises(ValueError, match=message):
        drive_regressor(np.zeros((1, 2)), np.zeros((1, 2)), **kwargs)
    with pytest.raises(ValueError, match="same shape"):
        drive_regressor(np.zeros((1, 2)), np.zeros((2, 2)))
