import numpy as np
import pytest

from gd_analyze.model.kinematics import as_states, frames, link_matrices


def test_two_link_positions_are_planar_closed_form(two_link):
    q = np.array([[0.3, -1.1], [2.0, 0.5]])
    R, p = frames(two_link, q)
    l = 1.0
    for k in range(2):
        q1, q2 = q[k]
        np.testing.assert_allclose(p[k, 1], [l * np.cos(q1), l * np.sin(q1), 0], atol=1e-15)
        np.testing.assert_allclose(
            p[k, 2], [l * (np.cos(q1) + np.cos(q1 + q2)), l * (np.sin(q1) + np.sin(q1 + q2)), 0],
            atol=1e-15)


def test_rotations_are_orthonormal(puma):
    q = np.random.default_rng(1).uniform(-3, 3, (20, 6))
    R, _ = frames(puma, q)
    np.testing.assert_allclose(R @ np.swapaxes(R, -1, -2), np.broadcast_to(np.eye(3), R.shape),
                               atol=1e-14)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=1e-14)


def test_puma_zero_pose_wrist_position(puma):
    # At q = 0, alpha1 = +90 deg turns z1 into -y0, so d3 (along z2 = z1) points along -y;
    # alpha3 = -90 deg turns z3 into y2 = +z0, so d4 points up: the forearm stands vertical
    # (Corke's "qz" pose). Wrist centre (frame 4 origin): (a2 + a3, -d3, d4).
    _, p = frames(puma, np.zeros((1, 6)))
    np.testing.assert_allclose(p[0, 4], [0.4318 + 0.0203, -0.15005, 0.4318], atol=1e-15)


def test_link_matrix_matches_the_product_of_elementary_transforms(puma):
    q = np.random.default_rng(2).uniform(-3, 3, (1, 6))
    A = link_matrices(puma, q)[0]
    for i in range(6):
        th, d, a, al = q[0, i], puma.d[i], puma.a[i], puma.alpha[i]
        Rz = np.array([[np.cos(th), -np.sin(th), 0, 0], [np.sin(th), np.cos(th), 0, 0],
                       [0, 0, 1, 0], [0, 0, 0, 1]])
        Tz = np.eye(4); Tz[2, 3] = d
        Tx = np.eye(4); Tx[0, 3] = a
        Rx = np.array([[1, 0, 0, 0], [0, np.cos(al), -np.sin(al), 0],
                       [0, np.sin(al), np.cos(al), 0], [0, 0, 0, 1]])
        np.testing.assert_allclose(A[i], Rz @ Tz @ Tx @ Rx, atol=1e-15)


def test_as_states_rejects_wrong_shapes_naming_the_array(puma):
    """One line naming the argument (the message named only the robot: which of q, qd, qdd
    had the wrong shape was left to guess)."""
    from gd_analyze.errors import InputError

    with pytest.raises(InputError, match=r"^qd: expected shape \(N, 6\) for puma560, got \(3, 5\)$"):
        as_states(puma, np.zeros((3, 6)), np.zeros((3, 5)))
    with pytest.raises(InputError, match=r"^arrays disagree on the number of set points: "
                                         r"q \(3, 6\), qd \(4, 6\)$"):
        as_states(puma, np.zeros((3, 6)), np.zeros((4, 6)))
    (q,) = as_states(puma, np.zeros(6))
    assert q.shape == (1, 6)


@pytest.mark.parametrize("robot", [None, "two-link", {"n": 2}])
def test_a_robot_of_another_type_is_one_input_error(robot):
    """gd.gd_terms(None, q, qd) and gd.regressor("two-link", ...) raised AttributeError
    ("'NoneType' object has no attribute 'n'") from inside; every entry that checks its states
    (as_states) now names the argument, as gd.analyze does."""
    import gd_analyze as gd
    from gd_analyze.errors import InputError

    q = np.zeros((3, 2))
    said = f"robot: a Robot (from load_robot), not a {type(robot).__name__}"
    for call in (lambda: gd.gd_terms(robot, q, q), lambda: gd.regressor(robot, q, q, q)):
        with pytest.raises(InputError) as e:
            call()
        assert str(e.value) == said
