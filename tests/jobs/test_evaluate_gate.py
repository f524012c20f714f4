"""The evaluate gate and the guarantee's coverage: region membership checked
against the region's limits as given, NaN and inf never pass, a joint without torque is
measured against the model's s_i."""

import dataclasses

import numpy as np
import pytest
from conftest import SHIPPED

from gd_analyze.errors import InputError
from gd_analyze.jobs.evaluate import coverage, evaluate, gate
from gd_analyze.simplify.guarantee import Guarantee
from gd_analyze.simplify.simplified import SimplifiedModel, full_choices
from gd_analyze.trajectory.trajectory import read_trajectory


def _region(n, scale=1.0):
    return Guarantee("region", 0.01, np.zeros(n), np.full(n, scale), q_min=np.full(n, -1.0),
                     q_max=np.full(n, 1.0), qd_max=np.full(n, 2.0), qdd_max=np.full(n, 3.0),
                     scale_state=np.zeros((n, 3 * n)))


def test_region_membership_names_the_first_state_outside():
    g = _region(2)
    q, qd, qdd = np.zeros((3, 2)), np.zeros((3, 2)), np.zeros((3, 2))
    assert g.covers(q, qd, qdd)[0]
    for name, arr, value in (("q", q, 1.5), ("|qd|", qd, -2.5), ("|qdd|", qdd, 3.5)):
        bad = arr.copy()
        arr[1, 1] = value
        covered, reason = g.covers(q, qd, qdd)
        arr[:] = bad
        assert not covered and f"joint 2's {name}" in reason and f"{abs(value):g}" in reason
    q[2, 0] = np.nan                                 # NaN is never inside
    assert not g.covers(q, qd, qdd)[0]
    # a continuous joint ([-pi, pi] in the region) is taken modulo 2 pi
    wide = dataclasses.replace(g, q_min=np.full(2, -np.pi), q_max=np.full(2, np.pi))
    q = np.array([[3 * np.pi / 2, 0.0]])
    assert not wide.covers(q, np.zeros((1, 2)), np.zeros((1, 2)))[0]
    assert wide.covers(q, np.zeros((1, 2)), np.zeros((1, 2)), continuous=[True, False])[0]


def test_trajectory_kind_covers_its_own_file_only(puma):
    """On its own file (same SHA-256) the claim is measured again: s_i is the
    trajectory's peak |tau_i| (the full model keeps every term, so its bound 0 holds)."""
    traj = read_trajectory(SHIPPED, n_joints=6)
    peak = np.abs(evaluate(SimplifiedModel(puma, full_choices(6), 0.9, 0.01), traj)["peak_tau"])
    g = Guarantee("trajectory", 0.01, np.zeros(6), np.asarray(peak, float),
                  trajectory_sha256=traj.sha256)
    model = SimplifiedModel(puma, full_choices(6), 0.9, 0.01, rule="budget", tolerance=0.01,
                            guarantee=g)
    assert coverage(model, traj)["covered"]
    invented = dataclasses.replace(model, guarantee=dataclasses.replace(g, scale=np.ones(6)))
    with pytest.raises(InputError, match="guarantee.scale"):
        coverage(invented, traj)
    other = dataclasses.replace(traj, sha256="0" * 64)
    said = coverage(model, other)
    assert not said["covered"] and said["statement"] == g.statement()


def test_nan_never_passes_a_gate(puma):
    g = Guarantee("trajectory", 0.01, np.zeros(6), np.ones(6))
    model = SimplifiedModel(puma, full_choices(6), 0.9, 0.01, rule="budget", tolerance=0.01,
                            guarantee=g)
    err = {"peak_abs_error": [0.0] * 5 + [np.nan], "peak_tau": [1.0] * 6,
           "relative_peak_error": [0.0] * 5 + [np.nan], "relative_to": ["peak |tau|"] * 6,
           "scale": [1.0] * 6}
    for max_error in (None, 0.5):
        verdict = gate(err, model, max_error)
        assert verdict["exceeded"] and verdict["worst_joint"] == 6


def test_zero_torque_joint_is_relative_to_the_models_scale(two_link):
    """A two-link arm at rest without gravity has no torque; a model that knows gravity errs
    by its gravity torque, relative to s_i; with s_i = 0 too the error is inf, never NaN."""
    from gd_analyze.model.mounting import with_mounting
    from gd_analyze.trajectory.trajectory import Trajectory

    n = two_link.n
    q = np.tile([0.3, -0.4], (4, 1))
    traj = Trajectory(t=np.arange(4.0), q=q, qd=np.zeros_like(q), qdd=np.zeros_like(q))
    plant = with_mounting(two_link, (0.0, 0.0, 0.0), None)
    scale = np.array([5.0, 0.0])
    g = Guarantee("trajectory", 0.01, np.zeros(n), scale)
    model = SimplifiedModel(two_link, full_choices(n), 0.9, 0.01, rule="budget",
                            tolerance=0.01, guarantee=g)
    err = evaluate(model, traj, plant=plant)
    gravity = np.abs(model.torque(q[:1], np.zeros((1, n)), np.zeros((1, n))))[0]
    assert np.all(np.asarray(err["peak_tau"]) == 0) and np.all(gravity > 1e-3)
    assert err["relative_to"] == ["s_i", "none"]
    assert err["relative_peak_error"][0] == gravity[0] / 5.0
    assert err["relative_peak_error"][1] == np.inf
    assert gate(err, model)["exceeded"] and gate(err, model, 1e6)["exceeded"]


def test_the_gate_allows_the_round_off_the_guarantee_states(puma):
    """A joint's stored error exceeded its bound by 6e-15 N m (0.002400359948032
    against 0.002400359948026) and joints dropping nothing showed 1e-16 N m against a bound
    of 0: round-off, which the guarantee allows ("up to floating-point round-off (64 eps of
    the scale)"); a real excess still fails."""
    from gd_analyze.simplify.guarantee import ROUND_OFF_CLAUSE, within_bound

    assert ROUND_OFF_CLAUSE == "up to floating-point round-off (64 eps of the scale)"
    scale = np.array([15.6, 50.5, 0.24, 0.055, 0.063, 0.00088])
    bound = np.array([0.068, 0.066, 0.002400359948026, 0.0, 0.0, 0.0])
    error = np.array([0.0086, 0.0052, 0.002400359948032, 1.1e-16, 6.7e-16, 1.1e-16])
    assert within_bound(error, bound, scale).all()
    error[2] = bound[2] * (1 + 1e-9)                     # 2.4e-12 N m over: not round-off
    assert within_bound(error, bound, scale).tolist() == [True, True, False, True, True, True]
    assert not within_bound([np.nan], [1.0], [1.0]).any()
    # the evaluate gate judges by the same rule: tolerance x s_i, up to that round-off
    g = Guarantee("trajectory", 0.01, np.zeros(6), scale)
    model = SimplifiedModel(puma, full_choices(6), 0.9, 0.01, rule="budget", tolerance=0.01,
                            guarantee=g)
    limit = 0.01 * scale
    err = {"peak_abs_error": list(limit + [0, 0, 6e-15, 0, 0, 0]), "peak_tau": list(scale),
           "relative_peak_error": [0.01] * 6, "relative_to": ["peak |tau|"] * 6}
    assert not gate(err, model)["exceeded"]
    err["peak_abs_error"][2] = limit[2] * (1 + 1e-9)
    assert gate(err, model)["worst_joint"] == 3
