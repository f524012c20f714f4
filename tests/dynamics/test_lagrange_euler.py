"""Lagrange-Euler equations (Sec. 3.2): two-link closed forms, derivatives, pseudo-inertia."""

import numpy as np
import pytest

from gd_analyze import load_robot
from gd_analyze.dynamics.lagrange_euler import le_terms, pseudo_inertia, u_matrices
from gd_analyze.dynamics.opcount import random_chain
from gd_analyze.model.kinematics import joint_transforms
from gd_analyze.model.robot_spec import robot_from_dict

G = 9.8062


def _states(n, N=40, seed=0):
    rng = np.random.default_rng(seed)
    return (rng.uniform(-np.pi, np.pi, (N, n)), rng.uniform(-3, 3, (N, n)),
            rng.uniform(-5, 5, (N, n)))


def _T(robot, q):
    """^0T_i of the body frames, shape (N, n, 4, 4), by plain matrix products (Eq. 3.2-6)."""
    A = joint_transforms(robot, q)
    T = [A[:, 0]]
    for i in range(1, robot.n):
        T.append(T[-1] @ A[:, i])
    return np.stack(T, axis=1)


def test_two_link_closed_forms_sec_3_2_6():
    robot = load_robot("two-link")
    q, qd, _ = _states(2, N=50)
    t = le_terms(robot, q, qd)
    m1 = m2 = 1.0
    l = 1.0
    C1, C2, S2 = np.cos(q[:, 0]), np.cos(q[:, 1]), np.sin(q[:, 1])
    C12 = np.cos(q[:, 0] + q[:, 1])
    qd1, qd2 = qd[:, 0], qd[:, 1]
    np.testing.assert_allclose(t.D[:, 0, 0], m1 * l**2 / 3 + 4 * m2 * l**2 / 3 + m2 * C2 * l**2,
                               rtol=0, atol=1e-13)
    np.testing.assert_allclose(t.D[:, 0, 1], m2 * l**2 / 3 + m2 * C2 * l**2 / 2, atol=1e-13)
    np.testing.assert_allclose(t.D[:, 1, 0], m2 * l**2 / 3 + m2 * C2 * l**2 / 2, atol=1e-13)
    np.testing.assert_allclose(t.D[:, 1, 1], m2 * l**2 / 3, atol=1e-13)
    np.testing.assert_allclose(t.h[:, 0], -m2 * S2 * l**2 * qd2**2 / 2 - m2 * S2 * l**2 * qd1 * qd2,
                               atol=1e-12)
    np.testing.assert_allclose(t.h[:, 1], m2 * S2 * l**2 * qd1**2 / 2, atol=1e-12)
    np.testing.assert_allclose(t.c[:, 0], (m1 / 2 + m2) * G * l * C1 + m2 * G * l * C12 / 2,
                               atol=1e-12)
    np.testing.assert_allclose(t.c[:, 1], m2 * G * l * C12 / 2, atol=1e-12)
    # the individual h_ikm of the worked example: h_112 = h_121 = h_122 = -m2 S2 l^2 / 2,
    # h_211 = m2 S2 l^2 / 2, all others 0
    half = m2 * S2 * l**2 / 2
    expected = np.zeros((50, 2, 2, 2))
    expected[:, 0, 0, 1] = expected[:, 0, 1, 0] = expected[:, 0, 1, 1] = -half
    expected[:, 1, 0, 0] = half
    np.testing.assert_allclose(t.h_ikm, expected, atol=1e-13)


def test_two_link_pseudo_inertia_matches_book():
    # Sec. 3.2.6: J_i = [[m l^2/3, 0, 0, -m l/2], 0, 0, [-m l/2, 0, 0, m]] for a uniform rod
    J = pseudo_inertia(load_robot("two-link"))
    book = np.zeros((4, 4))
    book[0, 0], book[0, 3], book[3, 0], book[3, 3] = 1 / 3, -1 / 2, -1 / 2, 1.0
    np.testing.assert_allclose(J, np.stack([book, book]), atol=1e-15)


def test_pseudo_inertia_is_second_moment_of_a_point_cloud():
    rng = np.random.default_rng(7)
    pts = rng.normal(size=(50, 3)) * [0.3, 0.1, 0.2] + [0.1, -0.2, 0.3]
    dm = rng.uniform(0.1, 1.0, 50)
    m = dm.sum()
    com = (dm[:, None] * pts).sum(0) / m
    rel = pts - com
    S = np.einsum("p,pa,pb->ab", dm, rel, rel)
    Ic = np.trace(S) * np.eye(3) - S                     # inertia tensor about the com
    spec = {"name": "cloud", "gravity": [0, 0, -G], "link": [{
        "d": 0.1, "a": 0.2, "alpha_deg": 30.0, "mass": float(m), "com": com.tolist(),
        "inertia": [Ic[0, 0], Ic[1, 1], Ic[2, 2], Ic[0, 1], Ic[0, 2], Ic[1, 2]],
        "q_limits_deg": [-90, 90], "qd_max_deg": 90, "qdd_max_deg": 90}]}
    r = np.concatenate([pts, np.ones((50, 1))], axis=1)
    expected = np.einsum("p,pa,pb->ab", dm, r, r)          # Eq. (3.2-17): int r r^T dm
    np.testing.assert_allclose(pseudo_inertia(robot_from_dict(spec))[0], expected, rtol=1e-12)


@pytest.mark.parametrize("robot", [load_robot("puma560"), random_chain(4, seed=3),
                                   load_robot("stanford")],
                         ids=["puma560", "random4", "stanford"])
def test_u_matrices_are_derivatives_of_the_link_transforms(robot):
    n, eps = robot.n, 1e-6
    q, _, _ = _states(n, N=3, seed=1)
    U, U3 = u_matrices(robot, q)
    for j in range(n):
        dq = np.zeros(n)
        dq[j] = eps
        dT = (_T(robot, q + dq) - _T(robot, q - dq)) / (2 * eps)          # (N, i, 4, 4)
        np.testing.assert_allclose(U[:, :, j], dT, atol=1e-8)
        dU = (u_matrices(robot, q + dq)[0] - u_matrices(robot, q - dq)[0]) / (2 * eps)
        np.testing.assert_allclose(U3[:, :, :, j], dU, atol=1e-8)      # dU_ik/dq_j


def test_h_ikm_are_christoffel_symbols_of_D():
    robot = random_chain(4, seed=11)
    n, eps = robot.n, 1e-6
    q, qd, _ = _states(n, N=2, seed=2)
    H = le_terms(robot, q, qd).h_ikm
    dD = np.empty((2, n, n, n))                               # dD[:, i, k, m] = dD_ik/dq_m
    for m in range(n):
        dq = np.zeros(n)
        dq[m] = eps
        dD[..., m] = (le_terms(robot, q + dq, qd).D - le_terms(robot, q - dq, qd).D) / (2 * eps)
    christoffel = 0.5 * (dD + np.swapaxes(dD, 2, 3) - np.transpose(dD, (0, 3, 1, 2)))
    np.testing.assert_allclose(H, christoffel, atol=1e-7)


def test_structure_of_D_and_h_ikm():
    robot = load_robot("puma560")
    q, qd, _ = _states(6, N=30, seed=4)
    t = le_terms(robot, q, qd)
    np.testing.assert_allclose(t.D, np.swapaxes(t.D, 1, 2), atol=1e-14)     # D_ik = D_ki
    assert np.all(np.linalg.eigvalsh(t.D) > 0)
    np.testing.assert_allclose(t.h_ikm, np.swapaxes(t.h_ikm, 2, 3), atol=1e-14)  # h_ikm = h_imk
    diag = t.h_ikm[:, np.arange(6), np.arange(6), np.arange(6)]                # h_iii = 0
    assert np.abs(diag).max() < 1e-13 * np.abs(t.h_ikm).max()
    np.testing.assert_allclose(t.h, np.einsum("nikm,nk,nm->ni", t.h_ikm, qd, qd), atol=1e-12)


def test_batched_equals_one_at_a_time_and_chunking():
    robot = load_robot("puma560")
    q, qd, qdd = _states(6, N=9, seed=5)
    whole = le_terms(robot, q, qd)
    chunked = le_terms(robot, q, qd, chunk=4)
    for k in range(9):
        one = le_terms(robot, q[k], qd[k])
        np.testing.assert_allclose(whole.D[k], one.D[0], rtol=0, atol=1e-15)
        np.testing.assert_allclose(whole.h[k], one.h[0], rtol=0, atol=1e-14)
    np.testing.assert_array_equal(whole.h_ikm, chunked.h_ikm)
    tau = whole.tau(qdd)
    np.testing.assert_allclose(tau, np.einsum("nij,nj->ni", whole.D, qdd) + whole.h + whole.c)


def test_bad_shapes_raise():
    robot = load_robot("two-link")
    with pytest.raises(ValueError):
        le_terms(robot, np.zeros((3, 3)), np.zeros((3, 3)))
    with pytest.raises(ValueError):
        le_terms(robot, np.zeros((3, 2)), np.zeros((4, 2)))
