"""Pinocchio's terms split as the G-D terms are (gd_analyze.dynamics.pinocchio), against the
chapter's two-link closed forms (Fu, Gonzalez & Lee 1987, Eqs. (3.2-37) to (3.2-40)) and the
identities D = D_tran + D_rot, h = h_tran + h_rot."""

import numpy as np
import pinocchio as pin
import pytest
from chapter_two_link import spec, terms
from robot_files import erd_path

from gd_analyze import load_robot
from gd_analyze.dynamics.pinocchio import reference_terms, relative_error
from gd_analyze.model.robot_spec import robot_from_dict


def test_the_split_equals_the_chapters_closed_forms():
    rng = np.random.default_rng(3)
    q, qd = rng.uniform(-np.pi, np.pi, (20, 2)), rng.uniform(-2, 2, (20, 2))
    robot = robot_from_dict(spec(m1=1.3, m2=0.7, l=0.9))
    ref = reference_terms(robot, q, qd)
    D_tran, D_rot, h_tran, h_rot, c = terms(q, qd, m1=1.3, m2=0.7, l=0.9)
    for got, want in ((ref.D_tran, D_tran), (ref.D_rot, D_rot), (ref.h_tran, h_tran),
                      (ref.c, c), (ref.D, D_tran + D_rot), (ref.h, h_tran + h_rot)):
        assert np.allclose(got, want, rtol=0, atol=1e-12 * max(1.0, np.abs(want).max()))
    assert np.abs(ref.h_rot).max() <= 1e-12


def test_the_parts_add_up_on_a_real_arm(puma):
    rng = np.random.default_rng(4)
    q, qd = rng.uniform(-np.pi, np.pi, (10, 6)), rng.uniform(-1, 1, (10, 6))
    ref = reference_terms(puma, q, qd)
    assert relative_error(ref.D_tran + ref.D_rot, ref.D) < 1e-12
    assert relative_error(ref.h_tran + ref.h_rot, ref.h) < 1e-12


def test_relative_error():
    assert relative_error([1.0, 2.0], [1.0, 2.0]) == 0.0
    assert relative_error([1.0, 2.5], [1.0, 2.0]) == pytest.approx(0.25)
    assert relative_error([], []) == 0.0
    assert not relative_error([np.nan], [1.0]) <= 1.0           # NaN never passes a check


def test_a_tensor_with_round_off_below_zero_on_its_diagonal_is_taken_as_read():
    """The iCub's right leg (example-robot-data): its URDF writes links' inertia tensors of
    about 1e-20 with diagonal entries such as -5.4e-20, CAD round-off. The robot file's check
    takes them, but pinocchio.Inertia(mass, com, I) refused them ("The 3d inertia should be
    positive"): the main job's verification exited 4. Oracle: the URDF's own Pinocchio model
    (the chain driven, every other joint at its neutral position): its crba and rnea."""
    robot = load_robot(erd_path("icub_description/robots/icub_reduced.urdf"), tip="r_ankle_2")
    assert min(np.diag(I).min() for I in robot.body_inertia) < 0       # the case itself
    urdf = pin.buildModelFromUrdf(erd_path("icub_description/robots/icub_reduced.urdf"))
    ids = [urdf.getJointId(name) for name in robot.joint_names()]
    iq, iv = [urdf.idx_qs[j] for j in ids], [urdf.idx_vs[j] for j in ids]
    rng = np.random.default_rng(6)
    q, qd, qdd = (rng.uniform(-1, 1, (8, robot.n)) for _ in range(3))
    ref = reference_terms(robot, q, qd)
    data = urdf.createData()
    for k in range(len(q)):
        x, v, a = pin.neutral(urdf), np.zeros(urdf.nv), np.zeros(urdf.nv)
        x[iq], v[iv], a[iv] = q[k], qd[k], qdd[k]
        D = pin.crba(urdf, data, x)
        D = np.triu(D) + np.triu(D, 1).T
        tau = pin.rnea(urdf, data, x, v, a)[iv]
        scale = np.abs(tau).max() + np.abs(D).max()
        assert np.abs(ref.D[k] - D[np.ix_(iv, iv)]).max() <= 1e-12 * scale
        assert np.abs(ref.D[k] @ qdd[k] + ref.h[k] + ref.c[k] - tau).max() <= 1e-12 * scale
