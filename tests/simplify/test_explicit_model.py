"""The simplified explicit model along a trajectory, against Pinocchio's rnea.

Oracles: Pinocchio's ``rnea`` (the full model and the exact rung equal it); the budget's
promise, checked against rnea, that the model built at EPS errs by at most EPS times the
scale on the trajectory it was built on.
"""

import numpy as np
import pinocchio as pin
import pytest

from gd_analyze import load_robot
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.simplify.explicit_model import (
    LADDER,
    build_model,
    collect_peaks,
    full_torque,
    ladder,
)
from gd_analyze.symbolic.explicit import derive, model_terms


@pytest.fixture(scope="module")
def built():
    robot = load_robot("puma560")
    rng = np.random.default_rng(3)
    t = np.linspace(0.0, 2.0, 41)[:, None]
    w = rng.uniform(0.5, 2.0, robot.n)
    q, qd, qdd = np.sin(w * t), w * np.cos(w * t), -w**2 * np.sin(w * t)
    terms = model_terms(derive(robot))
    model = pinocchio_model(robot)
    data = model.createData()
    ref = np.array([pin.rnea(model, data, *x).copy() for x in zip(q, qd, qdd)])
    return robot, terms, (q, qd, qdd), ref


def test_the_full_model_is_rnea(built):
    robot, terms, states, ref = built
    np.testing.assert_allclose(full_torque(robot, terms)(*states), ref, rtol=0,
                               atol=1e-9 * np.abs(ref).max())


@pytest.mark.parametrize("eps", [0.0, 0.01, 0.05])
def test_the_model_built_at_eps_keeps_its_budget_on_its_trajectory(built, eps):
    robot, terms, states, ref = built
    peaks = collect_peaks(robot, terms, *states)
    model, _ = build_model(robot, terms, peaks, tolerance=eps)
    scale = np.abs(ref).max(axis=0)
    err = np.abs(model.torque(*states) - ref).max(axis=0)
    assert np.all(np.isfinite(err))
    assert np.all(err <= eps * scale + 1e-9 * scale.max())
    if eps > 0:
        full, _ = build_model(robot, terms, peaks, tolerance=0.0)
        assert sum(model.cost.values()) < sum(full.cost.values())


def test_the_ladder_s_errors_are_rnea_s(built):
    robot, terms, states, ref = built
    peaks = collect_peaks(robot, terms, *states)
    rows = ladder(robot, terms, peaks, states)
    assert [r["tolerance"] for r in rows] == list(LADDER)
    scale = np.abs(ref).max(axis=0)
    for row in rows:
        model, _ = build_model(robot, terms, peaks, tolerance=row["tolerance"])
        worst = (np.abs(model.torque(*states) - ref).max(axis=0) / scale).max()
        assert row["worst_relative_error"] == pytest.approx(worst, rel=1e-6, abs=1e-12)
        assert row["worst_relative_error"] <= row["tolerance"] + 1e-9
