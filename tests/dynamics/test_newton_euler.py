"""Recursive Newton-Euler equations (Sec. 3.3): two-link example, Pinocchio, damping, load."""

import numpy as np
import pinocchio as pin
import pytest

from gd_analyze import load_robot
from gd_analyze.dynamics.newton_euler import joint_frames, link_constants, ne_tau, ne_terms
from gd_analyze.dynamics.pinocchio import pinocchio_model

G = 9.8062
ROBOTS = [load_robot("puma560"), load_robot("two-link"), load_robot("stanford")]


def _states(n, N, seed=0):
    rng = np.random.default_rng(seed)
    return (rng.uniform(-np.pi, np.pi, (N, n)), rng.uniform(-3, 3, (N, n)),
            rng.uniform(-5, 5, (N, n)))


def test_two_link_torques_sec_3_3_7():
    robot = load_robot("two-link")
    q, qd, qdd = _states(2, 50)
    tau = ne_tau(robot, q, qd, qdd)
    m1 = m2 = l = 1.0
    C1, C2, S2 = np.cos(q[:, 0]), np.cos(q[:, 1]), np.sin(q[:, 1])
    C12 = np.cos(q[:, 0] + q[:, 1])
    (qd1, qd2), (a1, a2) = qd.T, qdd.T
    tau1 = ((m1 / 3 + 4 * m2 / 3 + m2 * C2) * l**2 * a1 + (m2 / 3 + m2 * C2 / 2) * l**2 * a2
            - m2 * S2 * l**2 * qd1 * qd2 - m2 * S2 * l**2 * qd2**2 / 2
            + (m1 / 2 + m2) * G * l * C1 + m2 * G * l * C12 / 2)
    tau2 = ((m2 / 3 + m2 * C2 / 2) * l**2 * a1 + m2 * l**2 * a2 / 3
            + m2 * S2 * l**2 * qd1**2 / 2 + m2 * G * l * C12 / 2)
    np.testing.assert_allclose(tau, np.stack([tau1, tau2], axis=1), rtol=0, atol=1e-12)


def _dh(theta, d, a, alpha):
    """Eq. (3.2-5), written out."""
    ct, st, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha), np.sin(alpha)
    return np.array([[ct, -ca * st, sa * st, a * ct], [st, ca * ct, -sa * ct, a * st],
                     [0, sa, ca, d], [0, 0, 0, 1]])


def test_joint_frames_compose_to_the_dh_frames_of_the_stanford_arm():
    robot = load_robot("stanford")
    q = np.array([0.3, -0.7, 0.9, 1.1, -0.4, 0.25])
    R, p = joint_frames(robot, q[None])
    T, T_dh = np.eye(4), np.eye(4)
    for i in range(6):
        Ti = np.eye(4)
        Ti[:3, :3], Ti[:3, 3] = R[0, i], p[0, i]
        T = T @ Ti
        pris = robot.joint_types[i] == "prismatic"
        theta = robot.offset[i] + (0 if pris else q[i])
        d = robot.d[i] + (q[i] if pris else 0)
        T_dh = T_dh @ _dh(theta, d, robot.a[i], robot.alpha[i])
        # body frame i and DH frame i differ by the fixed link pose L_i
        L = np.eye(4)
        L[:3, :3], L[:3, 3] = robot.link_rotation[i], robot.link_translation[i]
        np.testing.assert_allclose(T @ L, T_dh, atol=1e-14)
    np.testing.assert_allclose(link_constants(robot)["vd0"], -np.asarray(robot.gravity))


@pytest.mark.parametrize("robot", ROBOTS, ids=lambda r: r.name)
def test_torques_and_probed_terms_match_pinocchio(robot):
    q, qd, qdd = _states(robot.n, 200, seed=1)
    model = pinocchio_model(robot)
    data = model.createData()
    tau_ref = np.array([pin.rnea(model, data, *x) for x in zip(q, qd, qdd)])
    c_ref = np.array([pin.computeGeneralizedGravity(model, data, x) for x in q])
    D_ref = np.array([pin.crba(model, data, x) for x in q])
    D_ref = np.triu(D_ref) + np.swapaxes(np.triu(D_ref, 1), 1, 2)
    zero = np.zeros(robot.n)
    h_ref = np.array([pin.rnea(model, data, a, b, zero) for a, b in zip(q, qd)]) - c_ref
    D, h, c = ne_terms(robot, q, qd)
    for value, ref in ((ne_tau(robot, q, qd, qdd), tau_ref), (D, D_ref), (h, h_ref), (c, c_ref)):
        assert np.abs(value - ref).max() <= 1e-10 * np.abs(ref).max()


def test_viscous_damping_adds_b_qd():
    robot = load_robot("puma560")
    q, qd, qdd = _states(6, 20, seed=2)
    b = np.array([1.5, 2.0, 0.7, 0.1, 0.2, 0.05])
    diff = ne_tau(robot, q, qd, qdd, b=b) - ne_tau(robot, q, qd, qdd)
    np.testing.assert_allclose(diff, b * qd, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("robot", ROBOTS, ids=lambda r: r.name)
def test_end_effector_load_matches_pinocchio_fext(robot):
    n = robot.n
    q, qd, qdd = _states(n, 30, seed=3)
    rng = np.random.default_rng(4)
    f, mom = rng.normal(size=(30, 3)) * 20, rng.normal(size=(30, 3)) * 5
    model = pinocchio_model(robot)
    data = model.createData()
    # link n's frame in Pinocchio's joint-n frame: Trans(a_n, 0, d_n) Rot(x, alpha_n)
    ca, sa = np.cos(robot.alpha[-1]), np.sin(robot.alpha[-1])
    rest = pin.SE3(np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]]),
                   np.array([robot.a[-1], 0.0, robot.d[-1]]))
    expected = np.empty((30, n))
    for k in range(30):
        fext = [pin.Force.Zero() for _ in range(model.njoints)]
        # the load pushes back on the hand with -f_{n+1}, -n_{n+1} at the origin of frame n
        fext[n] = rest.act(pin.Force(-f[k], -mom[k]))
        expected[k] = pin.rnea(model, data, q[k], qd[k], qdd[k], fext)
    got = ne_tau(robot, q, qd, qdd, f_load=f, n_load=mom)
    assert np.abs(got - expected).max() <= 1e-10 * np.abs(expected).max()


def test_static_point_load_equals_heavier_last_link():
    # Holding a point mass mL at the origin of frame n: f_{n+1} = -mL g (frame n), n_{n+1} = 0.
    # That is the same as adding mL to link n (parallel-axis theorem for the new centre of mass).
    robot = load_robot("puma560")
    mL = 2.5
    q, _, _ = _states(6, 10, seed=5)
    from gd_analyze.model.kinematics import frames
    R, _ = frames(robot, q)
    f = -mL * np.einsum("kba,b->ka", R[:, -1], robot.gravity)      # ^nR_0 (-mL g)
    m, r, I = robot.mass[-1], robot.com[-1], robot.inertia[-1]
    M = m + mL
    rc = m * r / M
    d1, d2 = r - rc, -rc
    I_new = (I + m * (d1 @ d1 * np.eye(3) - np.outer(d1, d1))
             + mL * (d2 @ d2 * np.eye(3) - np.outer(d2, d2)))
    heavy = robot.with_inertial(mass=np.r_[robot.mass[:-1], M],
                                com=np.vstack([robot.com[:-1], rc]),
                                inertia=np.concatenate([robot.inertia[:-1], I_new[None]]))
    zero = np.zeros_like(q)
    np.testing.assert_allclose(ne_tau(robot, q, zero, zero, f_load=f),
                               ne_tau(heavy, q, zero, zero), rtol=1e-12, atol=1e-12)


def test_bad_arguments_raise():
    robot = load_robot("two-link")
    z = np.zeros((4, 2))
    with pytest.raises(ValueError):
        ne_tau(robot, z, z, np.zeros((4, 3)))
    with pytest.raises(ValueError):
        ne_tau(robot, z, z, z, b=np.ones(3))
    with pytest.raises(ValueError):
        ne_tau(robot, z, z, z, f_load=np.ones((5, 3)))
