"""Standard parameters from base parameters, and physical consistency."""

import numpy as np
import pinocchio as pin

from gd_analyze import load_robot
from gd_analyze.dynamics.base_parameters import base_parameters, standard_parameters
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.estimation.consistent import (
    base_map,
    closest_standard,
    consistent_standard,
    min_eigenvalues,
    pseudo_inertia,
    robot_with_standard,
)


def test_pseudo_inertia_of_a_point_mass_is_m_cc():
    m, c = 2.0, np.array([0.1, -0.2, 0.3])
    J = m * (c @ c * np.eye(3) - np.outer(c, c))
    phi = np.array([[J[0, 0], J[0, 1], J[0, 2], J[1, 1], J[1, 2], J[2, 2], *(m * c), m]])
    v = np.append(c, 1.0)
    assert np.allclose(pseudo_inertia(phi)[0], m * np.outer(v, v), atol=1e-15)
    assert abs(min_eigenvalues(phi)[0]) < 1e-12


def test_closest_standard_reproduces_beta_and_is_the_least_norm_change():
    robot = load_robot("panda")
    base = base_parameters(robot)
    phi0 = standard_parameters(robot)
    beta = base.beta * 1.05
    phi = closest_standard(base, beta, phi0)
    A = base_map(base)
    assert np.allclose(A @ phi.reshape(-1), beta, rtol=0, atol=1e-12)
    # optimality: the scaled change lies in the row space of A S (orthogonal to its null space)
    from gd_analyze.estimation.consistent import _scales

    S = _scales(phi0)
    u = (phi - phi0).reshape(-1) / S
    null = np.linalg.svd(A * S)[2][base.rank:]
    assert np.abs(null @ u).max() < 1e-10 * np.abs(u).max()


def test_robot_with_standard_keeps_pinocchios_torque():
    robot = load_robot("puma560")
    rebuilt = robot_with_standard(robot, standard_parameters(robot))
    q = np.random.default_rng(0).uniform(-2, 2, (5, 6))
    a, b = pinocchio_model(robot), pinocchio_model(rebuilt)
    da, db = a.createData(), b.createData()
    for x in q:
        ta, tb = pin.rnea(a, da, x, x, x), pin.rnea(b, db, x, x, x)
        assert np.abs(ta - tb).max() <= 1e-12 * np.abs(ta).max()


def test_consistent_parameters_of_inconsistent_base_parameters():
    """From a prior with negative masses, the consistent parameters have PSD pseudo-inertias
    and reproduce base parameters that consistent links can give (the Panda's own)."""
    robot = load_robot("panda")
    base = base_parameters(robot)
    phi0 = standard_parameters(robot)
    theta = np.concatenate([base.beta, [0.1, 0.2]])
    R = np.eye(theta.size)
    bad = phi0.copy()
    bad[:, 9] *= -1                     # a negative-mass prior: far from consistent
    sol = consistent_standard(base, theta, np.ones(theta.size, bool), R, bad,
                              ("viscous", "viscous"), np.zeros(2))
    assert (min_eigenvalues(sol.phi) >= 0).all()
    assert sol.reproduces
    assert np.allclose(base_map(base) @ sol.phi.reshape(-1), base.beta, rtol=0,
                       atol=1e-6 * np.abs(base.beta).max())
    assert np.allclose(sol.drives, [0.1, 0.2], atol=1e-6)


def test_a_failing_solver_falls_back_and_two_failures_are_one_error(monkeypatch):
    """Clarabel raising SolverError in either stage: SCS solves both; both failing: the
    dedicated SolverFailure, not cvxpy's own error."""
    import cvxpy as cp
    import pytest

    from gd_analyze.estimation.consistent import SolverFailure

    robot = load_robot("two-link")
    base = base_parameters(robot)
    phi0 = standard_parameters(robot)
    theta = np.concatenate([base.beta, [0.1]])
    args = (base, theta, np.ones(theta.size, bool), np.eye(theta.size), phi0, ("viscous",),
            np.zeros(1))
    real = cp.Problem.solve
    failing = {"CLARABEL"}

    def solve(self, *a, solver=None, **k):
        if solver in failing:
            raise cp.error.SolverError(f"{solver} made to fail")
        return real(self, *a, solver=solver, **k)

    monkeypatch.setattr(cp.Problem, "solve", solve)
    sol = consistent_standard(*args)
    assert sol.solver == "SCS" and sol.residual < 1e-4       # SCS: first order, less exact
    failing.add("SCS")
    with pytest.raises(SolverFailure, match="CLARABEL made to fail.*SCS made to fail"):
        consistent_standard(*args)
