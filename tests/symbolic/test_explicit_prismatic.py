"""The explicit G-D model with prismatic joints: the joint variable d_i enters polynomially.

Oracles: Pinocchio rnea (EPS = 0 on random states; the budget bound on the shipped stanford
trajectory), finite differences and direct evaluation for the polynomial algebra, and the
operator count of the emitted C read off its text.
"""

import ctypes
import shutil
import subprocess

import numpy as np
import pytest
from conftest import ROOT, random_states
from model.test_chain import random_chain_spec
from symbolic.test_explicit import _c_operator_count, natural_error, python_tau, rnea

from gd_analyze import load_robot
from gd_analyze.dynamics.dalembert import gd_terms
from gd_analyze.model.robot_spec import robot_from_chain
from gd_analyze.simplify.budget import PartPeaks, select_terms
from gd_analyze.symbolic.codegen import build_program
from gd_analyze.symbolic.emit import emit_c
from gd_analyze.symbolic.explicit import derive, model_terms, term_peaks
from gd_analyze.symbolic.trigpoly import TrigPoly
from gd_analyze.trajectory.trajectory import read_trajectory

TOL = 1e-10
STANFORD_TRAJECTORY = ROOT / "data" / "stanford_trajectory.csv"


@pytest.fixture(scope="module")
def stanford():
    robot = load_robot("stanford")
    assert robot.joint_types[2] == "prismatic"
    return robot, model_terms(derive(robot))


def test_mixed_polynomials_are_exact():
    """Products, sums and derivatives of trig x powers agree with evaluating the factors."""
    lin = [False, True, False]
    rng = np.random.default_rng(5)
    x = rng.uniform(-2, 2, (60, 3))
    d = TrigPoly.var(3, 1, lin)
    a = TrigPoly.cos(3, 0, lin) * d + 0.3 * TrigPoly.sin(3, 2, lin) * d * d - 1.5
    b = TrigPoly.sin(3, 0, lin) * TrigPoly.cos(3, 2, lin) - 2.0 * d + 0.25
    ab = a * b
    want = ((np.cos(x[:, 0]) * x[:, 1] + 0.3 * np.sin(x[:, 2]) * x[:, 1] ** 2 - 1.5)
            * (np.sin(x[:, 0]) * np.cos(x[:, 2]) - 2.0 * x[:, 1] + 0.25))
    np.testing.assert_allclose(ab(x), want, rtol=0, atol=1e-13)
    h = 1e-6
    for m in range(3):
        e = np.zeros(3)
        e[m] = h
        fd = (ab(x + e) - ab(x - e)) / (2 * h)
        np.testing.assert_allclose(ab.diff(m)(x), fd, atol=1e-7)
    # powers never change sign in the canonical form; d^3 differentiated three times is 6
    assert (ab.K[:, 1] >= 0).all()
    assert (d * d * d).diff(1).diff(1).diff(1).constant() == pytest.approx(6.0)
    with pytest.raises(ValueError):
        TrigPoly.var(3, 0, lin)


def test_stanford_prismatic_joint_has_no_rotational_part(stanford):
    """Jw column of a prismatic joint is 0: D_rot row 3 vanishes identically (the parts
    themselves are checked against the G-D engine in test_explicit.py)."""
    robot, _ = stanford
    model = derive(robot)
    assert all(not len(model.D_rot[(min(2, j), max(2, j))]) for j in range(6))
    assert not any(len(p) for (i, j, k), p in model.h_rot.items() if 2 in (i, j, k))
    assert len(model.D_tran[(2, 2)]) == 1                 # D33 = m3 + ... + m6, a constant
    assert model.D_tran[(2, 2)].constant() == pytest.approx(float(robot.mass[2:].sum()))


def _compile(tmp_path, program, n):
    cc = shutil.which("cc")
    assert cc, "the machine's C compiler (cc) is required"
    (tmp_path / "m.c").write_text(emit_c(program, {"robot": "test"}))
    lib = tmp_path / "libm_prismatic.so"
    subprocess.run([cc, "-O2", "-shared", "-fPIC", "-std=c99", "-Wall", "-Werror",
                    "-o", str(lib), str(tmp_path / "m.c"), "-lm"], check=True)
    fn = ctypes.CDLL(str(lib)).gd_tau
    dp = ctypes.POINTER(ctypes.c_double)
    fn.argtypes, fn.restype = [dp, dp, dp, dp], None

    def tau(q, qd, qdd):
        out, res = np.empty(n), np.empty_like(q)
        for k in range(q.shape[0]):
            args = [np.ascontiguousarray(x[k]) for x in (q, qd, qdd)]
            fn(*(a.ctypes.data_as(dp) for a in args), out.ctypes.data_as(dp))
            res[k] = out
        return res
    return tau


def test_stanford_full_model_python_and_c_equal_rnea(tmp_path, stanford):
    """EPS = 0: the emitted Python and the compiled C equal rnea to 1e-10 on 200 states."""
    robot, terms = stanford
    program = build_program(terms, robot.n, np.zeros(robot.n), prismatic=robot.prismatic)
    q, qd, qdd = random_states(robot, 200, 21)
    ref = rnea(robot, q, qd, qdd)
    assert natural_error(python_tau(program)(q, qd, qdd), ref).max() < TOL
    assert natural_error(_compile(tmp_path, program, robot.n)(q, qd, qdd), ref).max() < TOL
    cost = program.cost()
    assert _c_operator_count(emit_c(program, {})) == (
        cost["multiplications"], cost["additions"], cost["sin"] + cost["cos"])
    # the prismatic q_3 is never an angle
    assert "sin(q[2])" not in emit_c(program, {}) and "cos(q[2])" not in emit_c(program, {})


@pytest.mark.parametrize("seed", [2, 3])
def test_random_mixed_chain_full_model_equals_rnea(seed):
    joints = random_chain_spec(5 if seed == 2 else 6, seed)
    robot = robot_from_chain(f"chain{seed}", joints, [0.5, -1.0, -9.5], source="<test>")
    assert "prismatic" in robot.joint_types and "revolute" in robot.joint_types
    program = build_program(model_terms(derive(robot)), robot.n, np.zeros(robot.n),
                            prismatic=robot.prismatic)
    q, qd, qdd = random_states(robot, 200, seed)
    assert natural_error(python_tau(program)(q, qd, qdd), rnea(robot, q, qd, qdd)).max() < TOL


@pytest.mark.parametrize("eps", [0.001, 0.01, 0.05])
def test_stanford_budget_bound_on_the_shipped_trajectory(eps, stanford):
    robot, terms = stanford
    traj = read_trajectory(STANFORD_TRAJECTORY, robot.n)
    q, qd, qdd = traj.q, traj.qd, traj.qdd
    t = gd_terms(robot, q, qd)
    parts = PartPeaks(robot.n)
    parts.update(t.D_tran, t.D_rot, t.h_tran, t.h_rot, qdd, t.tau(qdd))
    peaks = term_peaks(terms, np.zeros(robot.n), q, qd, qdd, prismatic=robot.prismatic)
    sel = select_terms(terms, peaks, parts.peaks, parts.tau_peak, tolerance=eps)
    assert (sel.bound <= eps * sel.scale * (1 + 1e-12)).all()
    program = build_program(sel.kept, robot.n, np.zeros(robot.n), prismatic=robot.prismatic)
    ref = rnea(robot, q, qd, qdd)
    err = np.abs(python_tau(program)(q, qd, qdd) - ref).max(axis=0)
    scale = np.abs(ref).max(axis=0)
    assert np.isfinite(err).all()
    assert (err <= eps * scale + 1e-9 * scale).all(), (err / scale, eps)
    assert (err <= sel.bound + 1e-9 * scale).all()
    assert len(sel.kept) < len(terms)                  # the budget did drop something
