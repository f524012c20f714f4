"""The joint model for every source: revolute and prismatic joints, standard and modified DH,
general chains; the G-D kernel and its array oracle against Pinocchio, closed forms and energy balance."""

import math

import numpy as np
import pytest
from numpy_engines import gd_terms_numpy

from gd_analyze import InputError, gd_terms, load_robot
from gd_analyze.dynamics.dalembert import allocate_terms
from gd_analyze.dynamics.pinocchio import reference_terms
from gd_analyze.model.kinematics import centres_of_mass, frames
from gd_analyze.model.robot_spec import robot_from_chain, robot_from_dict
from gd_analyze.model.robots import builtin_robots

TOL = 1e-10
#: The G-D kernel (gd_terms) and its oracle, the Jacobian form as array code.
ENGINES = {"numpy": gd_terms_numpy, "compiled": gd_terms}


def _states(robot, count, seed):
    """Random (q, qd, qdd) within the position limits where they are finite (else +-pi)."""
    rng = np.random.default_rng(seed)
    lo = np.where(np.isfinite(robot.q_min), robot.q_min, -np.pi)
    hi = np.where(np.isfinite(robot.q_max), robot.q_max, np.pi)
    n = robot.n
    return (rng.uniform(lo, hi, (count, n)), rng.uniform(-2, 2, (count, n)),
            rng.uniform(-2, 2, (count, n)))


def natural_errors(terms, ref, qdd):
    """Largest error of each part on its natural scale: D_ij against sqrt(D_ii D_jj) of the
    reference's full D at the same set point, h_i and c_i against the peak |tau_i| of the
    reference over the set points."""
    D = ref.D
    diag = np.einsum("kii->ki", D)
    assert diag.min() > 0
    scale_D = np.sqrt(diag[:, :, None] * diag[:, None, :])
    tau = np.einsum("kij,kj->ki", D, qdd) + ref.h + ref.c
    scale_t = np.abs(tau).max(axis=0)
    assert scale_t.min() > 0
    out = {}
    for name in ("D_tran", "D_rot"):
        err = np.abs(getattr(terms, name) - getattr(ref, name)) / scale_D
        out[name] = float(err.max())
    for name in ("h_tran", "h_rot", "c"):
        err = np.abs(getattr(terms, name) - getattr(ref, name)) / scale_t
        out[name] = float(err.max())
    for name, value in out.items():
        assert math.isfinite(value), name
    return out


def _check(robot, q, qd, qdd, engine):
    terms = ENGINES[engine](robot, q, qd)
    ref = reference_terms(robot, q, qd)
    errs = natural_errors(terms, ref, qdd)
    assert max(errs.values()) < TOL, errs
    # Pinocchio's half-model split adds up (the split is a valid oracle); the full model
    # carries the drives' armature (model.armature), the half models do not
    assert np.abs(ref.D_tran + ref.D_rot + np.diag(robot.armature) - ref.D).max() \
        <= TOL * np.abs(ref.D).max()
    return terms


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("name", builtin_robots())
def test_every_builtin_robot_matches_pinocchio_half_models(name, engine):
    robot = load_robot(name)
    q, qd, qdd = _states(robot, 250, 101)
    _check(robot, q, qd, qdd, engine)


def random_chain_spec(n, seed, p_prismatic=0.4):
    """A random general chain: random rotations and translations, mixed joint types, full
    inertia tensors, limits left open."""
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(seed)
    joints = []
    for i in range(n):
        B = rng.normal(size=(3, 3)) * 0.1
        S = B @ B.T
        joints.append({
            "type": "prismatic" if rng.random() < p_prismatic else "revolute",
            "rotation": Rotation.random(random_state=seed * 100 + i).as_matrix(),
            "translation": rng.uniform(-0.3, 0.3, 3), "mass": rng.uniform(0.3, 4.0),
            "com": rng.uniform(-0.2, 0.2, 3), "inertia": np.trace(S) * np.eye(3) - S,
            "q_min": -np.inf, "q_max": np.inf, "qd_max": 2.0, "qdd_max": None})
    return joints


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_random_mixed_chains_match_pinocchio_in_both_engines(seed):
    joints = random_chain_spec(7, seed)
    robot = robot_from_chain(f"chain{seed}", joints, [0.5, -1.0, -9.5], source="<test>")
    assert "prismatic" in robot.joint_types and "revolute" in robot.joint_types
    q, qd, qdd = _states(robot, 200, seed)
    for engine in ENGINES:
        _check(robot, q, qd, qdd, engine)


def test_chain_round_trips_through_its_dictionary():
    joints = random_chain_spec(4, 7)
    robot = robot_from_chain("chain", joints, [0, 0, -9.81], base_link="base", tip_link="tip")
    assert robot.convention == "chain" and np.isnan(robot.d).all()
    assert dict(robot.metadata) == {"base_link": "base", "tip_link": "tip"}
    assert np.isnan(robot.qdd_max).all() and np.isinf(robot.q_max).all()
    again = robot_from_dict(robot.to_dict())
    for name in ("rotation", "translation", "prismatic", "mass", "com", "inertia", "q_min",
                 "qd_max"):
        np.testing.assert_array_equal(getattr(again, name), getattr(robot, name))
    q, qd, _ = _states(robot, 5, 0)
    np.testing.assert_array_equal(gd_terms(again, q, qd).D, gd_terms(robot, q, qd).D)


@pytest.mark.parametrize("key, value, column", [
    ("type", "helical", "joint[2].type"),
    ("rotation", np.diag([1.0, 1.0, -1.0]), "joint[2].rotation"),
    ("mass", -1.0, "joint[2].mass"),
    ("inertia", np.diag([1.0, -1.0, 1.0]), "joint[2].inertia"),
    ("q_max", -np.inf, "joint[2].q_min/q_max"),
])
def test_chain_errors_name_the_joint_and_key(key, value, column):
    joints = random_chain_spec(3, 4)
    joints[1][key] = value
    with pytest.raises(InputError) as err:
        robot_from_chain("bad", joints, [0, 0, -9.81], source="arm.urdf")
    assert err.value.column == column and str(err.value).startswith("arm.urdf: ")
    joints = random_chain_spec(3, 4)
    del joints[2]["com"]
    with pytest.raises(InputError) as err:
        robot_from_chain("bad", joints, [0, 0, -9.81])
    assert err.value.column == "joint[3].com"


def test_out_buffers_are_filled_in_place_and_reused():
    robot = load_robot("stanford")
    q, qd, _ = _states(robot, 300, 5)
    buf = allocate_terms(128, robot.n)
    whole = gd_terms(robot, q, qd)
    for start in range(0, 300, 128):
        part = gd_terms(robot, q[start:start + 128], qd[start:start + 128], out=buf)
        assert np.shares_memory(part.D_tran, buf.D_tran)
        for name in ("D_tran", "D_rot", "h_tran", "h_rot", "c"):
            np.testing.assert_array_equal(getattr(part, name),
                                          getattr(whole, name)[start:start + 128])
    with pytest.raises(ValueError, match="out.D_tran"):
        gd_terms(robot, q, qd, out=buf)                 # 300 rows do not fit in 128


# --- the Stanford arm: a prismatic joint ----------------------------------------------------

def test_stanford_prismatic_joint_closed_forms():
    """Joint 3 slides along z_2 and carries links 3..6: D_33 = m3 + m4 + m5 + m6, no
    rotational part in its row, c_3 = -(m3 + ... + m6) g . z_2, with z_2 from the DH matrices
    of Eq. (3.2-5) multiplied out here."""
    robot = load_robot("stanford")
    q, qd, _ = _states(robot, 200, 9)
    t = gd_terms(robot, q, qd)
    m = robot.mass[2:].sum()
    np.testing.assert_allclose(t.D_tran[:, 2, 2], m, rtol=1e-13)
    np.testing.assert_allclose(t.D_rot[:, 2, :], 0.0, atol=1e-15)
    np.testing.assert_allclose(t.h_rot[:, 2], 0.0, atol=1e-15)

    def A(theta, d, a, alpha):
        ct, st, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha), np.sin(alpha)
        return np.array([[ct, -ca * st, sa * st], [st, ca * ct, -sa * ct], [0, sa, ca]])

    for k in range(len(q)):
        R = A(q[k, 0], 0.412, 0.0, -np.pi / 2) @ A(q[k, 1], 0.154, 0.0, np.pi / 2)
        np.testing.assert_allclose(t.c[k, 2], -m * (np.array([0, 0, -9.81]) @ R[:, 2]),
                                   rtol=1e-12, atol=1e-12)


def test_single_prismatic_link_on_a_turntable_closed_form():
    """The Stanford arm's prismatic link (mass, inertia and centre of mass of its link 3) slid
    radially on a turntable (a polar r-theta arm): with r = q2 + z_c the distance of its centre
    of mass from the vertical axis, D11 = I1yy + I2yy + m r^2, D12 = 0, D22 = m,
    h1 = 2 m r rd thd, h2 = -m r thd^2, c = 0 (the motion is horizontal); and the slide alone
    under gravity: D = m, h = 0, c = m g."""
    st = load_robot("stanford").to_dict()["link"][2]
    m2, zc = st["mass"], st["com"][2]
    I2 = st["inertia"]
    base = {"d": 0.0, "a": 0.0, "alpha_deg": -90.0, "mass": 3.0, "com": [0.0, 0.0, 0.0],
            "inertia": [0.2, 0.5, 0.3], "q_limits_deg": [-180, 180], "qd_max_deg": 90,
            "qdd_max_deg": 90}
    slide = {**st, "theta_deg": 0.0, "a": 0.0, "alpha_deg": 0.0}
    arm = robot_from_dict({"name": "polar", "gravity": [0, 0, -9.81],
                           "link": [base, slide]})
    rng = np.random.default_rng(3)
    q = np.column_stack([rng.uniform(-3, 3, 100), rng.uniform(0.3, 1.3, 100)])
    qd = rng.uniform(-2, 2, (100, 2))
    r = q[:, 1] + zc
    for engine in ENGINES:
        t = ENGINES[engine](arm, q, qd)
        np.testing.assert_allclose(t.D_rot[:, 0, 0], 0.5 + I2[1], rtol=1e-13)
        np.testing.assert_allclose(t.D_tran[:, 0, 0], m2 * r**2, rtol=1e-13)
        np.testing.assert_allclose(t.D[:, 0, 1], 0.0, atol=1e-12)
        np.testing.assert_allclose(t.D[:, 1, 1], m2, rtol=1e-13)
        np.testing.assert_allclose(t.h[:, 0], 2 * m2 * r * qd[:, 1] * qd[:, 0], rtol=1e-12)
        np.testing.assert_allclose(t.h[:, 1], -m2 * r * qd[:, 0] ** 2, rtol=1e-12)
        np.testing.assert_allclose(t.c, 0.0, atol=1e-12)
    alone = robot_from_dict({"name": "slide", "gravity": [0, 0, -9.81],
                             "link": [{**slide, "alpha_deg": 0.0}]})
    t = gd_terms(alone, np.array([[0.5]]), np.array([[1.5]]))
    np.testing.assert_allclose([t.D[0, 0, 0], t.h[0, 0], t.c[0, 0]], [m2, 0.0, m2 * 9.81],
                               rtol=1e-14, atol=1e-14)


def test_stanford_free_fall_conserves_energy():
    """tau = 0: qdd = D^-1 (-h - c) integrated for 0.6 s keeps kinetic + potential energy, the
    potential from the centres of mass in the link frames (not from the G-D terms)."""
    from scipy.integrate import solve_ivp

    robot = load_robot("stanford")
    n = robot.n

    def rhs(_, x):
        t = gd_terms(robot, x[:n], x[n:])
        return np.concatenate([x[n:], np.linalg.solve(t.D[0], -t.h[0] - t.c[0])])

    def energy(x):
        t = gd_terms(robot, x[:n], x[n:])
        R, p = frames(robot, x[None, :n])
        rbar = centres_of_mass(robot, R, p)[0]
        return 0.5 * x[n:] @ t.D[0] @ x[n:] - np.sum(robot.mass * (rbar @ robot.gravity))

    x0 = np.array([0.3, -0.5, 0.8, 0.4, -0.6, 0.2, 0.4, -0.3, 0.2, 0.5, -0.4, 0.6])
    sol = solve_ivp(rhs, (0, 0.6), x0, rtol=1e-10, atol=1e-12)
    e = np.array([energy(x) for x in sol.y.T])
    assert np.ptp(e) < 1e-6 * (np.abs(e).max() + 1)
    assert np.ptp(sol.y[2]) > 0.01        # the prismatic joint really moved


# --- modified DH ---------------------------------------------------------------------------

def _rx(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def puma_modified_dh_toml(puma):
    """The PUMA 560 written in Craig's modified DH: row i holds alpha_{i-1}, a_{i-1} of the
    standard table, d_i and theta offset_i. Modified frame i sits where standard frame i sits
    before its Trans(a_i) Rot(x, alpha_i), so r and I move by that transform."""
    lines = ['name = "puma560-mdh"', 'convention = "modified"',
             f"gravity = {list(map(float, puma.gravity))}"]
    for i in range(puma.n):
        alpha_prev = puma.alpha[i - 1] if i else 0.0
        a_prev = puma.a[i - 1] if i else 0.0
        Rx = _rx(puma.alpha[i])
        r = Rx @ puma.com[i] + np.array([puma.a[i], 0, 0])
        I = Rx @ puma.inertia[i] @ Rx.T
        lines += ["[[link]]", f"alpha_deg = {math.degrees(alpha_prev)!r}",
                  f"a = {float(a_prev)!r}", f"d = {float(puma.d[i])!r}",
                  f"offset_deg = {math.degrees(puma.offset[i])!r}",
                  f"mass = {float(puma.mass[i])!r}", f"com = {[float(v) for v in r]!r}",
                  "inertia = " + repr([float(I[a, b]) for a, b in ((0, 0), (1, 1), (2, 2), (0, 1),
                                                                   (0, 2), (1, 2))]),
                  "q_limits_deg = [-180.0, 180.0]", "qd_max_deg = 90.0",
                  "qdd_max_deg = 90.0"]
    return "\n".join(lines) + "\n"


def test_modified_dh_puma_equals_standard_dh_puma(tmp_path, puma):
    path = tmp_path / "puma560_mdh.toml"
    path.write_text(puma_modified_dh_toml(puma))
    mdh = load_robot(str(path))
    assert mdh.convention == "modified" and mdh.n == 6
    q, qd, qdd = _states(puma, 200, 21)
    for engine in ENGINES:
        a, b = ENGINES[engine](mdh, q, qd), ENGINES[engine](puma, q, qd)
        errs = natural_errors(a, b, qdd)     # same D, h, c (and the same split)
        assert max(errs.values()) < TOL, errs
    _check(mdh, q, qd, qdd, "compiled")


# --- robot files ------------------------------------------------------------------------------

def _spec():
    return load_robot("stanford").to_dict()


@pytest.mark.parametrize("mutate, column, words", [
    (lambda s: s.update(convention="craig"), "convention", "convention"),
    (lambda s: s["link"][2].update(joint="screw"), "link[3].joint", "revolute"),
    (lambda s: s["link"][2].update(d=0.1), "link[3].d", "q is d"),
    (lambda s: s["link"][2].update(q_limits_deg=[0, 1]), "link[3].q_limits_deg", "'q_limits'"),
    (lambda s: s["link"][2].pop("a"), "link[3].a", "missing"),
    (lambda s: s["link"][2].update(qd_max=-1.0), "link[3].qd_max", "positive"),
    (lambda s: s["link"][2].update(theta_deg="x"), "link[3].theta_deg", "number"),
    (lambda s: s["link"][0].update(theta_deg=10.0), "link[1].theta_deg", "offset_deg"),
    (lambda s: s["link"][0].update(qd_max=1.0), "link[1].qd_max", "qd_max_deg"),
    (lambda s: s["link"][1].update(joint="prismatic"), "link[2].d", "prismatic"),
])
def test_robot_file_errors_name_the_link_and_key(mutate, column, words):
    spec = _spec()
    mutate(spec)
    with pytest.raises(InputError) as err:
        robot_from_dict(spec, source="arm.toml")
    assert err.value.column == column
    assert str(err.value).startswith(f"arm.toml: key {column}: ")
    assert words in str(err.value)


def test_stanford_file_round_trip_and_units():
    robot = load_robot("stanford")
    assert robot.joint_types == ("revolute", "revolute", "prismatic", "revolute", "revolute",
                                 "revolute")
    np.testing.assert_allclose([robot.q_min[2], robot.q_max[2]], [0.3048, 1.27])   # [m]
    np.testing.assert_allclose(robot.qd_max[2], 0.5)                               # [m/s]
    np.testing.assert_allclose(robot.offset[2], -np.pi / 2)                        # theta_3
    again = robot_from_dict(robot.to_dict())
    for name in ("rotation", "translation", "link_rotation", "link_translation", "prismatic",
                 "q_min", "q_max", "qd_max", "qdd_max"):
        np.testing.assert_allclose(getattr(again, name), getattr(robot, name), atol=1e-15)
