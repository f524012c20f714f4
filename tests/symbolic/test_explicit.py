"""The explicit G-D model: derivation against Pinocchio and the chapter's two-link closed forms,
the error budget's bound, the emitted C (compiled with the machine's cc) and Python, the count."""

import ctypes
import re
import shutil
import subprocess

import numpy as np
import pinocchio as pin
import pytest
from conftest import SHIPPED, random_states

from gd_analyze import load_robot
from gd_analyze.dynamics.dalembert import gd_terms
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.simplify.budget import PartPeaks, budget_choices, part_index, select_terms
from gd_analyze.symbolic.codegen import build_program
from gd_analyze.symbolic.emit import emit_c, emit_python
from gd_analyze.symbolic.explicit import budget_drop, derive, model_terms, term_peaks
from gd_analyze.symbolic.operation_count import count_operations
from gd_analyze.symbolic.trigpoly import TrigPoly
from gd_analyze.trajectory.planning import plan_quintic
from gd_analyze.trajectory.trajectory import read_trajectory

TOL = 1e-10


def rnea(robot, q, qd, qdd):
    model = pinocchio_model(robot)
    data = model.createData()
    return np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])


def python_tau(program):
    ns = {}
    exec(emit_python(program, {"test": "explicit"}), ns)
    return ns["tau"]


def natural_error(tau, ref):
    """Per joint: peak |tau - ref| / peak |ref| (the joint's natural scale)."""
    scale = np.abs(ref).max(axis=0)
    assert (scale > 0).all()
    err = np.abs(tau - ref).max(axis=0) / scale
    assert np.isfinite(err).all()
    return err


def _robot_with_products_and_offsets():
    """The PUMA's twists with full inertia tensors, joint offsets, other masses and centres."""
    from gd_analyze.model.robot_spec import robot_from_dict

    spec = load_robot("puma560").to_dict()
    rng = np.random.default_rng(31)
    for link in spec["link"]:
        A = rng.normal(size=(3, 3))
        I = A @ A.T * 0.05
        link["inertia"] = [I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]]
        link["offset_deg"] = float(rng.uniform(-90, 90))
        link["mass"] = float(rng.uniform(0.1, 5))
        link["com"] = rng.uniform(-0.2, 0.2, 3).tolist()
    return robot_from_dict(spec)


# --------------------------------------------------------------------------------------------
# Derivation
# --------------------------------------------------------------------------------------------

def test_trigpoly_products_and_derivatives_are_exact():
    rng = np.random.default_rng(0)
    th = rng.uniform(-3, 3, (50, 3))
    a = TrigPoly.cos(3, 0) * TrigPoly.sin(3, 1) + 0.3 * TrigPoly.sin(3, 2)
    b = TrigPoly.sin(3, 0) - 2.0 * TrigPoly.cos(3, 1) * TrigPoly.cos(3, 2) + 1.5
    np.testing.assert_allclose((a * b)(th), a(th) * b(th), rtol=0, atol=1e-14)
    eps = 1e-6
    for m in range(3):
        d = np.zeros(3)
        d[m] = eps
        fd = ((a * b)(th + d) - (a * b)(th - d)) / (2 * eps)
        np.testing.assert_allclose((a * b).diff(m)(th), fd, atol=1e-8)
    # canonical form: sin^2 + cos^2 is the constant 1
    one = TrigPoly.sin(3, 1) * TrigPoly.sin(3, 1) + TrigPoly.cos(3, 1) * TrigPoly.cos(3, 1)
    assert len(one) == 1 and one.constant() == pytest.approx(1.0, abs=1e-15)


@pytest.mark.parametrize("name", ["puma560", "two-link", "general", "ur5"])
def test_full_explicit_model_equals_pinocchio_rnea(name):
    """EPS = 0: the emitted model equals rnea to 1e-10 on 200 random states (DH robots, a
    PUMA with products of inertia and offsets, and a URDF chain)."""
    from gd_analyze.model.robots import load_robot as load_any

    robot = _robot_with_products_and_offsets() if name == "general" else load_any(name)
    terms = model_terms(derive(robot))
    program = build_program(terms, robot.n, np.zeros(robot.n))
    q, qd, qdd = random_states(robot, 200, 21)
    err = natural_error(python_tau(program)(q, qd, qdd), rnea(robot, q, qd, qdd))
    assert err.max() < TOL, err


@pytest.mark.parametrize("name", ["general", "stanford"])
def test_explicit_parts_equal_the_gd_terms(name):
    """D_tran, D_rot, h_tran, h_rot, c against the G-D engine (stanford: a prismatic joint)."""
    robot = _robot_with_products_and_offsets() if name == "general" else load_robot(name)
    q, qd, _ = random_states(robot, 100, 3)
    ours = derive(robot).terms(q, qd)
    ref = gd_terms(robot, q, qd)
    for got, name in zip(ours, ("D_tran", "D_rot", "h_tran", "h_rot", "c")):
        want = getattr(ref, name)
        assert np.abs(got - want).max() <= 1e-11 * np.abs(want).max(), name


def test_two_link_reproduces_the_closed_forms_of_sec_3_4_2(two_link):
    """D11 = m1 l^2/3 + 4 m2 l^2/3 + m2 C2 l^2, D12 = m2 l^2/3 + m2 C2 l^2/2, D22 = m2 l^2/3,
    h1 = -m2 S2 l^2 qd2^2/2 - m2 S2 l^2 qd1 qd2, h2 = m2 S2 l^2 qd1^2/2, h_rot = 0,
    c1 = (m1/2 + m2) g l C1 + m2 g l C12/2, c2 = m2 g l C12/2 (m1 = m2 = l = 1)."""
    g = 9.8062
    m = derive(two_link)

    def coeffs(p):
        return {(tuple(int(v) for v in k), bool(s)): float(c) for k, s, c in p.rows()}

    D = {ij: coeffs(m.D_tran[ij] + m.D_rot[ij]) for ij in m.D_tran}
    assert D[(0, 0)] == pytest.approx({((0, 0), False): 5 / 3, ((0, 1), False): 1.0})
    assert D[(0, 1)] == pytest.approx({((0, 0), False): 1 / 3, ((0, 1), False): 0.5})
    assert D[(1, 1)] == pytest.approx({((0, 0), False): 1 / 3})
    h = {key: coeffs(p) for key, p in m.h_tran.items()}
    # h1: qd1 qd2 -> -S2, qd2^2 -> -S2/2 ; h2: qd1^2 -> S2/2
    assert h[(0, 0, 1)] == pytest.approx({((0, 1), True): -1.0})
    assert h[(0, 1, 1)] == pytest.approx({((0, 1), True): -0.5})
    assert h[(1, 0, 0)] == pytest.approx({((0, 1), True): 0.5})
    assert set(h) == {(0, 0, 1), (0, 1, 1), (1, 0, 0)}
    assert not m.h_rot
    assert coeffs(m.c[0]) == pytest.approx({((1, 0), False): 1.5 * g, ((1, 1), False): g / 2})
    assert coeffs(m.c[1]) == pytest.approx({((1, 1), False): g / 2})
    # and the chapter's split: D_rot holds the rod inertias m l^2/12
    assert coeffs(m.D_rot[(0, 0)]) == pytest.approx({((0, 0), False): 2 / 12})


# --------------------------------------------------------------------------------------------
# The error budget
# --------------------------------------------------------------------------------------------

def test_budget_drop_stays_within_the_budget():
    rng = np.random.default_rng(4)
    peaks = rng.exponential(size=(300, 4)) * (rng.random((300, 4)) < 0.5)
    budget = np.array([1.0, 0.5, 0.0, 3.0])
    drop, used = budget_drop(peaks, budget)
    np.testing.assert_allclose(used, peaks[drop].sum(axis=0))
    assert (used <= budget).all() and drop.any()
    assert not drop[peaks[:, 2] > 0].any()           # no budget on joint 3


def _two_link_trajectory(robot):
    return plan_quintic(robot, np.radians([-30.0, 60.0]), np.radians([90.0, -45.0]), 101)


def _trajectories():
    puma = load_robot("puma560")
    two = load_robot("two-link")
    return [(puma, read_trajectory(SHIPPED, 6)), (two, _two_link_trajectory(two))]


@pytest.mark.parametrize("eps", [0.001, 0.01, 0.05])
@pytest.mark.parametrize("which", [0, 1])
def test_budget_bound_holds_on_the_trajectory(eps, which):
    """Triangle inequality: every joint within EPS x peak |tau_i| against Pinocchio rnea."""
    robot, traj = _trajectories()[which]
    q, qd, qdd = traj.q, traj.qd, traj.qdd
    terms = model_terms(derive(robot))
    t = gd_terms(robot, q, qd)
    parts = PartPeaks(robot.n)
    parts.update(t.D_tran, t.D_rot, t.h_tran, t.h_rot, qdd, t.tau(qdd))
    sel = select_terms(terms, term_peaks(terms, np.zeros(robot.n), q, qd, qdd), parts.peaks,
                       parts.tau_peak, tolerance=eps)
    assert (sel.bound <= eps * sel.scale * (1 + 1e-12)).all()
    program = build_program(sel.kept, robot.n, np.zeros(robot.n))
    ref = rnea(robot, q, qd, qdd)
    err = np.abs(python_tau(program)(q, qd, qdd) - ref).max(axis=0)
    scale = np.abs(ref).max(axis=0)
    assert (err <= eps * scale + 1e-9 * scale).all(), (err / scale, eps)
    assert (err <= sel.bound + 1e-9 * scale).all()
    if eps >= 0.01 and robot.n == 6:
        assert len(sel.kept) < len(terms)        # the budget did drop something


def test_budget_choices_describe_the_dropped_parts():
    robot, traj = _trajectories()[0]
    t = gd_terms(robot, traj.q, traj.qd)
    parts = PartPeaks(robot.n)
    parts.update(t.D_tran, t.D_rot, t.h_tran, t.h_rot, traj.qdd, t.tau(traj.qdd))
    choices, used = budget_choices(parts.peaks, parts.tau_peak, 0.01)
    assert (used <= 0.01 * parts.tau_peak).all()
    dropped = {(lab, p) for lab, p, *_ in part_index(6)
               if choices[lab] not in (p, "both")}
    assert dropped and len(dropped) < len(part_index(6))
    with pytest.raises(ValueError):
        budget_choices(parts.peaks, parts.tau_peak, -0.1)


# --------------------------------------------------------------------------------------------
# Emitted code and counting
# --------------------------------------------------------------------------------------------

def _c_operator_count(source):
    """Count * and binary +/- in the body of emitted C, independently of the counter."""
    body = source.split("{", 1)[1]
    body = "\n".join(ln.split("=", 1)[1] for ln in body.splitlines() if "=" in ln)
    body = re.sub(r"\d+\.\d*(e[+-]?\d+)?|\d+e[+-]?\d+|\d+", "N", body)
    mults = body.count("*")
    adds = len(re.findall(r"[\w\)\]]\s*[+-]", body))
    trig = len(re.findall(r"\b(sin|cos)\(", body))
    return mults, adds, trig


@pytest.fixture(scope="module")
def puma_model_1pct():
    robot, traj = _trajectories()[0]
    terms = model_terms(derive(robot))
    t = gd_terms(robot, traj.q, traj.qd)
    parts = PartPeaks(robot.n)
    parts.update(t.D_tran, t.D_rot, t.h_tran, t.h_rot, traj.qdd, t.tau(traj.qdd))
    sel = select_terms(terms, term_peaks(terms, np.zeros(robot.n), traj.q, traj.qd, traj.qdd),
                       parts.peaks, parts.tau_peak, tolerance=0.01)
    return robot, traj, terms, build_program(sel.kept, 6, np.zeros(6))


def test_count_matches_the_emitted_c_and_beats_newton_euler(puma_model_1pct):
    from gd_analyze.dynamics.opcount import operation_counts

    robot, _, terms, program = puma_model_1pct
    ne = operation_counts(robot)["newton-euler"]
    ne_total = ne["multiplications"] + ne["additions"]
    for prog in (program, build_program(terms, 6, np.zeros(robot.n))):
        cost = prog.cost()
        m, a, trig = _c_operator_count(emit_c(prog, {}))
        assert (m, a, trig) == (cost["multiplications"], cost["additions"],
                                cost["sin"] + cost["cos"])
    simp = program.cost()
    assert simp["multiplications"] + simp["additions"] < ne_total


def test_counting_rule_on_small_expressions():
    import symengine as se

    x, y, z = se.symbols("x y z")
    assert count_operations([], [x * y * z]) == {"multiplications": 2, "additions": 0,
                                                  "sin": 0, "cos": 0}
    assert count_operations([], [-x * y + 3.0]) == {"multiplications": 1, "additions": 1,
                                                     "sin": 0, "cos": 0}
    assert count_operations([(z, se.cos(x + y))], [2.5 * z**2]) == {
        "multiplications": 2, "additions": 1, "sin": 0, "cos": 1}


def test_emitted_c_compiles_and_agrees_with_python_and_rnea(tmp_path, puma_model_1pct):
    """cc -O2 -shared -fPIC, called through ctypes: C == Python, both within 1 % of rnea."""
    cc = shutil.which("cc")
    assert cc, "the machine's C compiler (cc) is required"
    robot, traj, _, program = puma_model_1pct
    src = emit_c(program, {"robot": robot.name})
    assert re.findall(r"#include\s*<(\w+\.h)>", src) == ["math.h"]
    (tmp_path / "m.c").write_text(src)
    lib = tmp_path / "libm_test.so"
    subprocess.run([cc, "-O2", "-shared", "-fPIC", "-std=c99", "-Wall", "-Werror",
                    "-o", str(lib), str(tmp_path / "m.c"), "-lm"], check=True)
    dll = ctypes.CDLL(str(lib))
    fn = dll.gd_tau
    dp = ctypes.POINTER(ctypes.c_double)
    fn.argtypes, fn.restype = [dp, dp, dp, dp], None
    q, qd, qdd = traj.q, traj.qd, traj.qdd
    out = np.empty(6)
    tau_c = np.empty_like(q)
    for k in range(q.shape[0]):
        args = [np.ascontiguousarray(x[k]) for x in (q, qd, qdd)]
        fn(*(a.ctypes.data_as(dp) for a in args), out.ctypes.data_as(dp))
        tau_c[k] = out
    tau_py = python_tau(program)(q, qd, qdd)
    ref = rnea(robot, q, qd, qdd)
    scale = np.abs(ref).max(axis=0)
    assert (np.abs(tau_c - tau_py).max(axis=0) <= 1e-12 * scale).all()
    assert (np.abs(tau_c - ref).max(axis=0) <= 0.01 * scale).all()


def test_derivation_cache(tmp_path, monkeypatch, puma):
    from gd_analyze.store.explicit_cache import explicit_terms

    monkeypatch.delenv("GD_ANALYZE_NO_CACHE", raising=False)
    monkeypatch.setenv("GD_ANALYZE_CACHE_DIR", str(tmp_path / "cache"))
    first, t1 = explicit_terms(puma)
    second, t2 = explicit_terms(puma)
    assert t1 > 0 and t2 == 0.0
    np.testing.assert_array_equal(first.C, second.C)
    np.testing.assert_array_equal(first.K, second.K)
    # a payload changes the parameters, not the file: another entry
    from gd_analyze.model.robot import with_payload

    _, t3 = explicit_terms(with_payload(puma, 1.0))
    assert t3 > 0
    # an unwritable cache folder: derived again, no error
    blocked = tmp_path / "file"
    blocked.write_text("not a folder")
    monkeypatch.setenv("GD_ANALYZE_CACHE_DIR", str(blocked / "sub"))
    third, t4 = explicit_terms(puma)
    assert t4 > 0 and len(third) == len(first)
