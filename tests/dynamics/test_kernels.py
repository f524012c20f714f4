"""The compiled G-D kernels (dynamics/kernels.py), called directly.

Oracles: Pinocchio's forward kinematics (body frames), world-frame joint Jacobians (Plücker
axes), crba, nonLinearEffects and computeGeneralizedGravity, and its half-models for the
split; the chapter's two-link closed forms; physical identities (D symmetric positive
definite, h = 0 at qd = 0 and quadratic in qd, the energy identity qd^T h = qd^T Ddot qd / 2,
c = 0 without gravity)."""

import dataclasses

import chapter_two_link
import numpy as np
import pinocchio as pin
import pytest
from conftest import random_states

from gd_analyze.dynamics.dalembert import kernel_arguments
from gd_analyze.dynamics.kernels import body_frames_at, gd_kernel, plucker_axes
from gd_analyze.dynamics.pinocchio import pinocchio_model, reference_terms, relative_error
from gd_analyze.model.robot_spec import robot_from_dict
from gd_analyze.model.robots import load_robot

TOL = 1e-10
ARMS = ("puma560", "stanford", "ur5")


def kernel(robot, q, qd, rows=None):
    """gd_kernel into fresh buffers of ``rows`` rows (default N), pre-filled with NaN."""
    N, n = q.shape
    rows = N if rows is None else rows
    out = (np.full((rows, n, n), np.nan), np.full((rows, n, n), np.nan),
           np.full((rows, n), np.nan), np.full((rows, n), np.nan), np.full((rows, n), np.nan))
    gd_kernel(np.ascontiguousarray(q), np.ascontiguousarray(qd), *kernel_arguments(robot), *out)
    return out


def _frames(robot, qk):
    n = robot.n
    Rp, tp, pris, _, com, _, _ = kernel_arguments(robot)
    R, o, rbar = np.empty((n, 3, 3)), np.empty((n, 3)), np.empty((n, 3))
    body_frames_at(qk[None, :], 0, Rp, tp, pris, com, np.empty((3, 3)), R, o, rbar)
    return R, o, rbar


@pytest.mark.parametrize("name", ARMS)
def test_body_frames_and_plucker_axes_match_pinocchio(name):
    robot = load_robot(name)
    model = pinocchio_model(robot)
    data = model.createData()
    q, _, _ = random_states(robot, 5, 21)
    pris = kernel_arguments(robot)[2]
    for qk in q:
        R, o, rbar = _frames(robot, qk)
        pin.forwardKinematics(model, data, qk)
        pin.computeJointJacobians(model, data, qk)
        for i in range(robot.n):
            M = data.oMi[i + 1]
            np.testing.assert_allclose(R[i], M.rotation, rtol=0, atol=1e-12)
            np.testing.assert_allclose(o[i], M.translation, rtol=0, atol=1e-12)
            np.testing.assert_allclose(rbar[i], M.act(robot.body_com[i]), rtol=0, atol=1e-12)
        A, B = np.empty((robot.n, 3)), np.empty((robot.n, 3))
        plucker_axes(R, o, pris, A, B)
        # world-frame Jacobian column j: the velocity of the point at the base origin and the
        # angular velocity, per unit qd_j: (o_j x z_j, z_j) revolute, (z_j, 0) prismatic
        J = pin.getJointJacobian(model, data, robot.n, pin.ReferenceFrame.WORLD)
        np.testing.assert_allclose(B, J[:3].T, rtol=0, atol=1e-12)
        np.testing.assert_allclose(A, J[3:].T, rtol=0, atol=1e-12)


@pytest.mark.parametrize("name", ARMS)
def test_kernel_matches_pinocchio_crba_nle_and_gravity(name):
    robot = load_robot(name)
    q, qd, _ = random_states(robot, 40, 22)
    D_tran, D_rot, h_tran, h_rot, c = kernel(robot, q, qd)
    model = pinocchio_model(robot)
    data = model.createData()
    D_ref, h_ref, c_ref = [], [], []
    for qk, qdk in zip(q, qd):
        M = pin.crba(model, data, qk)
        D_ref.append(np.triu(M) + np.triu(M, 1).T)
        g = pin.computeGeneralizedGravity(model, data, qk)
        h_ref.append(pin.nonLinearEffects(model, data, qk, qdk) - g)
        c_ref.append(g)
    assert relative_error(D_tran + D_rot, np.array(D_ref)) < TOL
    assert relative_error(h_tran + h_rot, np.array(h_ref)) < TOL
    assert relative_error(c, np.array(c_ref)) < TOL
    ref = reference_terms(robot, q, qd)                  # the half-models: the split
    for got, want in ((D_tran, ref.D_tran), (D_rot, ref.D_rot), (h_tran, ref.h_tran),
                      (h_rot, ref.h_rot)):
        assert relative_error(got, want) < TOL


def test_kernel_gives_the_chapters_two_link_closed_forms():
    m1, m2, l, g = 1.4, 0.9, 0.7, 9.81
    robot = robot_from_dict(chapter_two_link.spec(m1, m2, l, g))
    rng = np.random.default_rng(23)
    q, qd = rng.uniform(-np.pi, np.pi, (30, 2)), rng.uniform(-3, 3, (30, 2))
    for got, want in zip(kernel(robot, q, qd), chapter_two_link.terms(q, qd, m1, m2, l, g)):
        assert np.abs(got - want).max() <= 1e-12 * max(np.abs(want).max(), 1.0)


@pytest.mark.parametrize("name", ARMS)
def test_physical_identities(name):
    robot = load_robot(name)
    q, qd, _ = random_states(robot, 20, 24)
    D_tran, D_rot, h_tran, h_rot, c = kernel(robot, q, qd)
    D = D_tran + D_rot
    np.testing.assert_array_equal(D, np.swapaxes(D, 1, 2))            # exactly symmetric
    assert np.linalg.eigvalsh(D).min() > 0                              # positive definite
    assert np.linalg.eigvalsh(D_tran).min() > -1e-12 * np.abs(D).max()  # each part PSD
    assert np.linalg.eigvalsh(D_rot).min() > -1e-12 * np.abs(D).max()
    _, _, h0t, h0r, c0 = kernel(robot, q, np.zeros_like(qd))
    assert np.abs(h0t).max() == 0 and np.abs(h0r).max() == 0           # h = 0 at qd = 0
    np.testing.assert_array_equal(c0, c)                                # c depends on q only
    _, _, h2t, h2r, _ = kernel(robot, q, 2 * qd)                        # h quadratic in qd
    assert relative_error(h2t + h2r, 4 * (h_tran + h_rot)) < TOL
    still = dataclasses.replace(robot, gravity=np.zeros(3))
    assert np.abs(kernel(still, q, qd)[4]).max() == 0                   # c = 0 without g
    # energy: d/dt (qd^T D qd / 2) at qdd = 0 is qd^T Ddot qd / 2 = qd^T h
    eps = 1e-6
    Dp = sum(kernel(robot, q + eps * qd, qd)[:2])
    Dm = sum(kernel(robot, q - eps * qd, qd)[:2])
    Ddot = (Dp - Dm) / (2 * eps)
    lhs = np.einsum("ki,ki->k", qd, h_tran + h_rot)
    rhs = 0.5 * np.einsum("ki,kij,kj->k", qd, Ddot, qd)
    assert np.abs(lhs - rhs).max() < 1e-6 * np.abs(rhs).max()


def test_kernel_writes_only_the_first_n_rows_of_larger_buffers():
    robot = load_robot("puma560")
    q, qd, _ = random_states(robot, 7, 25)
    out = kernel(robot, q, qd, rows=10)
    whole = kernel(robot, q, qd)
    for big, exact in zip(out, whole):
        np.testing.assert_array_equal(big[:7], exact)
        assert np.isnan(big[7:]).all()
