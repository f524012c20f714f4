"""G-D terms against Pinocchio (split by half-models), the chapter's two-link closed forms, and
physical identities."""

import numpy as np
import pytest
from conftest import SHIPPED, random_states
from numpy_engines import gd_terms_numpy

from gd_analyze import gd_terms, load_robot
from gd_analyze.dynamics.dalembert import GDTerms, assemble_tau, forward_dynamics
from gd_analyze.dynamics.pinocchio import reference_terms, relative_error
from gd_analyze.trajectory.trajectory import read_trajectory

TOL = 1e-10
PARTS = ("D_tran", "D_rot", "h_tran", "h_rot", "c")


#: The G-D kernel (gd_terms) and its oracle, the Jacobian form as array code.
ENGINES = {"numpy": gd_terms_numpy, "compiled": gd_terms}


def _check_against_pinocchio(robot, q, qd, engine):
    terms = ENGINES[engine](robot, q, qd)
    ref = reference_terms(robot, q, qd)
    for name in PARTS:
        assert relative_error(getattr(terms, name), getattr(ref, name)) < TOL, name
    # The sums against the full model's crba and nonLinearEffects
    assert relative_error(terms.D_tran + terms.D_rot, ref.D) < TOL
    assert relative_error(terms.h_tran + terms.h_rot, ref.h) < TOL
    # and Pinocchio's own split adds up too (the half-model split is a valid oracle)
    assert relative_error(ref.D_tran + ref.D_rot, ref.D) < TOL
    assert relative_error(ref.h_tran + ref.h_rot, ref.h) < TOL
    return terms


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("name, seed", [("puma560", 11), ("two-link", 12)])
def test_split_matches_pinocchio_half_models_on_random_states(name, seed, engine):
    robot = load_robot(name)
    q, qd, _ = random_states(robot, 250, seed)
    _check_against_pinocchio(robot, q, qd, engine)


@pytest.mark.parametrize("engine", ENGINES)
def test_split_matches_pinocchio_on_shipped_trajectory(puma, engine):
    traj = read_trajectory(SHIPPED, puma.n)
    _check_against_pinocchio(puma, traj.q, traj.qd, engine)


def test_engines_agree_on_a_robot_with_products_of_inertia_and_offsets(puma):
    """A chain unlike the built-ins: full inertia tensors, joint offsets, odd twists."""
    from gd_analyze.model.robot_spec import robot_from_dict

    spec = puma.to_dict()
    rng = np.random.default_rng(31)
    for i, link in enumerate(spec["link"]):
        A = rng.normal(size=(3, 3))
        I = A @ A.T * 0.05
        link["inertia"] = [I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]]
        link["offset_deg"] = float(rng.uniform(-90, 90))
        link["alpha_deg"] = float(rng.uniform(-180, 180))
        link["mass"] = float(rng.uniform(0.1, 5))
        link["com"] = rng.uniform(-0.2, 0.2, 3).tolist()
    spec["gravity"] = [1.0, -2.0, -9.0]
    robot = robot_from_dict(spec)
    q, qd, _ = random_states(robot, 200, 32)
    for engine in ENGINES:
        _check_against_pinocchio(robot, q, qd, engine)


def test_the_kernel_gives_the_array_oracle_s_terms(puma):
    q, qd, _ = random_states(puma, 2000, 33)
    kernel, oracle = gd_terms(puma, q, qd), gd_terms_numpy(puma, q, qd)
    for name in PARTS:
        np.testing.assert_allclose(getattr(kernel, name), getattr(oracle, name), rtol=0,
                                   atol=1e-12)


def test_each_set_point_is_independent_of_the_batch(puma):
    q, qd, _ = random_states(puma, 40, 3)
    whole = gd_terms(puma, q, qd)
    chunked = GDTerms.concatenate([gd_terms(puma, q[k:k + 7], qd[k:k + 7])
                                   for k in range(0, 40, 7)])
    one = gd_terms(puma, q[17], qd[17])
    for name in PARTS:
        np.testing.assert_array_equal(getattr(whole, name), getattr(chunked, name))
        np.testing.assert_allclose(getattr(one, name)[0], getattr(whole, name)[17], rtol=0,
                                   atol=1e-14)


def test_two_link_closed_forms_sec_3_4_2(two_link):
    """Sec. 3.4.2: D, h (with h_rot = 0) and c of the two-link arm."""
    q, qd, _ = random_states(two_link, 200, 5)
    m1 = m2 = 1.0
    l, g = 1.0, 9.8062
    C1, C2, C12 = np.cos(q[:, 0]), np.cos(q[:, 1]), np.cos(q.sum(axis=1))
    S2 = np.sin(q[:, 1])
    t = gd_terms(two_link, q, qd)
    D = t.D
    np.testing.assert_allclose(D[:, 0, 0], m1 * l**2 / 3 + 4 * m2 * l**2 / 3 + m2 * C2 * l**2,
                               rtol=TOL, atol=TOL)
    np.testing.assert_allclose(D[:, 0, 1], m2 * l**2 / 3 + m2 * C2 * l**2 / 2, rtol=TOL,
                               atol=TOL)
    np.testing.assert_allclose(D[:, 1, 0], D[:, 0, 1], rtol=0, atol=1e-15)
    np.testing.assert_allclose(D[:, 1, 1], m2 * l**2 / 3, rtol=TOL)
    h1 = -m2 * S2 * l**2 * qd[:, 1] ** 2 / 2 - m2 * S2 * l**2 * qd[:, 0] * qd[:, 1]
    h2 = m2 * S2 * l**2 * qd[:, 0] ** 2 / 2
    np.testing.assert_allclose(t.h[:, 0], h1, rtol=TOL, atol=TOL)
    np.testing.assert_allclose(t.h[:, 1], h2, rtol=TOL, atol=TOL)
    np.testing.assert_allclose(t.h_rot, 0.0, atol=1e-14)   # "h_rot = 0", Sec. 3.4.2
    np.testing.assert_allclose(t.c[:, 0], (m1 / 2 + m2) * g * l * C1 + m2 * g * l * C12 / 2,
                               rtol=TOL, atol=TOL)
    np.testing.assert_allclose(t.c[:, 1], m2 * g * l * C12 / 2, rtol=TOL, atol=TOL)
    # The chapter's split: D_rot holds the rod inertias m l^2/12 about z, D_tran the rest
    np.testing.assert_allclose(t.D_rot[:, 0, 0], (m1 + m2) * l**2 / 12, rtol=TOL)
    np.testing.assert_allclose(t.D_rot[:, 0, 1], m2 * l**2 / 12, rtol=TOL)
    np.testing.assert_allclose(t.D_rot[:, 1, 1], m2 * l**2 / 12, rtol=TOL)


@pytest.mark.parametrize("name", ["puma560", "two-link", "stanford"])
def test_D_parts_symmetric_and_D_positive_definite(name):
    robot = load_robot(name)
    q, qd, _ = random_states(robot, 300, 8)
    t = gd_terms(robot, q, qd)
    for M in (t.D_tran, t.D_rot, t.D):
        np.testing.assert_allclose(M, np.swapaxes(M, 1, 2), rtol=0, atol=1e-14)
    assert np.linalg.eigvalsh(t.D).min() > 0
    # each part is a sum of Gram matrices: positive semi-definite
    for M in (t.D_tran, t.D_rot):
        assert np.linalg.eigvalsh(M).min() > -1e-12


@pytest.mark.parametrize("name", ["puma560", "two-link", "stanford"])
def test_power_balance_of_each_part(name):
    """qd^T h_x = 1/2 qd^T (dD_x/dt) qd for x in {tran, rot}: the Coriolis and centrifugal
    torques do no work beyond changing the kinetic energy 1/2 qd^T D_x qd at fixed qdd = 0."""
    robot = load_robot(name)
    q, qd, _ = random_states(robot, 50, 9)
    eps = 1e-6
    plus, minus = gd_terms(robot, q + eps * qd, qd), gd_terms(robot, q - eps * qd, qd)
    t = gd_terms(robot, q, qd)
    for part in ("tran", "rot"):
        Ddot = (getattr(plus, f"D_{part}") - getattr(minus, f"D_{part}")) / (2 * eps)
        lhs = np.einsum("ki,ki->k", qd, getattr(t, f"h_{part}"))
        rhs = 0.5 * np.einsum("ki,kij,kj->k", qd, Ddot, qd)
        np.testing.assert_allclose(lhs, rhs, rtol=1e-6, atol=1e-7)


def test_energy_balance_along_a_simulated_motion(two_link):
    """Free fall (tau = 0) conserves kinetic + potential energy when integrated with the G-D
    forward dynamics qdd = D^-1 (-h - c)."""
    from scipy.integrate import solve_ivp

    from gd_analyze.model.kinematics import centres_of_mass, frames

    robot = two_link

    def rhs(_, x):
        q, qd = x[:2], x[2:]
        t = gd_terms(robot, q, qd)
        return np.concatenate([qd, np.linalg.solve(t.D[0], -t.h[0] - t.c[0])])

    def energy(x):
        q, qd = x[:2], x[2:]
        t = gd_terms(robot, q, qd)
        R, p = frames(robot, q[None])
        rbar = centres_of_mass(robot, R, p)[0]
        potential = -np.sum(robot.mass * (rbar @ robot.gravity))
        return 0.5 * qd @ t.D[0] @ qd + potential

    x0 = np.array([0.4, -0.7, 0.5, -1.0])
    sol = solve_ivp(rhs, (0, 2.0), x0, rtol=1e-10, atol=1e-12)
    e = np.array([energy(x) for x in sol.y.T])
    assert np.ptp(e) < 1e-6 * (abs(e[0]) + 1)
    assert np.ptp(sol.y[0]) > 0.5   # it really moved


def test_rejects_wrong_shapes(puma):
    with pytest.raises(ValueError):
        gd_terms(puma, np.zeros((2, 6)), np.zeros((2, 5)))


def test_a_qdd_given_as_fourth_argument_is_one_line_naming_out(puma):
    """gd_terms(robot, q, qd, qdd), written as regressor(robot, q, qd, qdd) is, passed qdd as
    the buffers ``out`` and raised AttributeError ("'numpy.ndarray' object has no attribute
    'D_tran'") from inside."""
    from gd_analyze.errors import InputError

    q = np.zeros((2, 6))
    with pytest.raises(InputError) as e:
        gd_terms(puma, q, q, q)
    assert str(e.value) == ("out: a GDTerms from allocate_terms (the terms take no qdd), not a "
                            "ndarray")


@pytest.mark.parametrize("name", ["puma560", "two-link"])
def test_forward_dynamics_matches_pinocchio_aba(name):
    pin = pytest.importorskip("pinocchio")
    from gd_analyze.dynamics.pinocchio import pinocchio_model

    robot = load_robot(name)
    q, qd, qdd = random_states(robot, 40, seed=11)
    tau = gd_terms(robot, q, qd).tau(qdd) + np.random.default_rng(2).normal(size=q.shape)
    ours = forward_dynamics(robot, q, qd, tau)
    model = pinocchio_model(robot)
    data = model.createData()
    for k in range(q.shape[0]):
        ref = pin.aba(model, data, q[k], qd[k], tau[k])
        assert np.abs(ours[k] - ref).max() <= 1e-10 * np.abs(ref).max()
    # inverse of inverse dynamics, and a single state
    back = forward_dynamics(robot, q, qd, gd_terms(robot, q, qd).tau(qdd))
    np.testing.assert_allclose(back, qdd, rtol=1e-9, atol=1e-9)
    assert forward_dynamics(robot, q[0], qd[0], tau[0]).shape == (1, robot.n)


@pytest.mark.parametrize("name", ["puma560", "stanford"])
def test_assemble_tau_of_pinocchio_terms_is_pinocchio_rnea(name):
    # oracle: Pinocchio's own D (crba), h + c (nonLinearEffects) and c (generalized gravity)
    # assembled by Eq. (3.2-26) must give its inverse dynamics (rnea); a wrong contraction or a
    # dropped term fails (the Stanford arm's joint 3 is prismatic: tau_3 is a force)
    pin = pytest.importorskip("pinocchio")
    from gd_analyze.dynamics.pinocchio import pinocchio_model

    robot = load_robot(name)
    q, qd, qdd = random_states(robot, 20, seed=5)
    model = pinocchio_model(robot)
    data = model.createData()
    D = np.stack([np.triu(pin.crba(model, data, a)) + np.triu(pin.crba(model, data, a), 1).T
                  for a in q])
    nle = np.stack([pin.nonLinearEffects(model, data, a, b) for a, b in zip(q, qd)])
    c = np.stack([pin.computeGeneralizedGravity(model, data, a) for a in q])
    ref = np.stack([pin.rnea(model, data, a, b, d) for a, b, d in zip(q, qd, qdd)])
    tau = assemble_tau(D, nle - c, c, qdd)
    scale = np.abs(ref).max(axis=0)
    assert np.all(np.abs(tau - ref) <= 1e-12 * scale)
    with pytest.raises(ValueError):
        assemble_tau(D, nle - c, c, qdd[:, :-1])


def test_constants_computed_once_give_the_same_terms_as_pinocchio():
    """A simulation passes the robot's kernel constants once (``constants=``) and reuses its
    buffers (``out=``): the terms are those of Pinocchio's crba and nonLinearEffects, and
    bit for bit those of a plain call."""
    from gd_analyze.dynamics.dalembert import allocate_terms, kernel_arguments

    robot = load_robot("puma560")
    q, qd, _ = random_states(robot, 5, seed=11)
    constants, buffers = kernel_arguments(robot), allocate_terms(1, robot.n)
    ref = reference_terms(robot, q, qd)
    for k in range(5):
        plain = gd_terms(robot, q[k:k + 1], qd[k:k + 1])
        once = gd_terms(robot, q[k:k + 1], qd[k:k + 1], out=buffers,
                        constants=constants)
        np.testing.assert_array_equal(once.D, plain.D)
        np.testing.assert_array_equal(once.h, plain.h)
        np.testing.assert_array_equal(once.c, plain.c)
        assert relative_error(once.D[0], ref.D[k]) < 1e-12
        assert relative_error(once.h[0], ref.h[k]) < 1e-12
        assert relative_error(once.c[0], ref.c[k]) < 1e-12


@pytest.mark.parametrize("name", ["puma560-drives", "stanford", "panda"])
def test_one_state_terms_are_gd_terms_bit_for_bit(name):
    """The simulation's one-state call gives what gd_terms gives at each state, every field
    (friction and armature included), while its buffers are reused from call to call."""
    from gd_analyze.dynamics.dalembert import one_state_terms

    robot = load_robot(name)
    n = robot.n
    terms = one_state_terms(robot)
    rng = np.random.default_rng(11)
    kept = []
    for _ in range(5):
        y = np.concatenate([rng.uniform(-2, 2, n), rng.uniform(-3, 3, n)])
        got = terms(y[None, :n], y[None, n:])
        want = gd_terms(robot, y[None, :n], y[None, n:])
        for field in ("D_tran", "D_rot", "h_tran", "h_rot", "c", "armature", "tau_f"):
            a, b = getattr(got, field), getattr(want, field)
            assert (a is None) == (b is None), field
            if a is not None:
                np.testing.assert_array_equal(a, b, err_msg=field)
        kept.append(got.D.copy())
    assert not np.array_equal(kept[0], kept[-1])
    assert (name == "puma560-drives") == (got.tau_f is not None)
