"""The four formulations behind one interface: closed forms, agreement, the compare report."""

import dataclasses
import json

import numpy as np
import pytest

from gd_analyze import load_robot
from gd_analyze.dynamics import compare as formulations
from gd_analyze.dynamics.compare import (
    METHODS,
    DynamicsResult,
    compare,
    compare_report,
    dynamics,
    format_compare,
    inverse_dynamics,
)

G = 9.8062
ROBOTS = [load_robot("puma560"), load_robot("two-link")]


def _states(n, N, seed=0):
    rng = np.random.default_rng(seed)
    return (rng.uniform(-np.pi, np.pi, (N, n)), rng.uniform(-3, 3, (N, n)),
            rng.uniform(-5, 5, (N, n)))


def _two_link_closed_form(q, qd):
    """Secs. 3.2.6, 3.3.7, 3.4.2 with l = 1 m, m1 = m2 = 1 kg, gravity along -y."""
    m1 = m2 = l = 1.0
    C1, C2, S2 = np.cos(q[:, 0]), np.cos(q[:, 1]), np.sin(q[:, 1])
    C12 = np.cos(q[:, 0] + q[:, 1])
    qd1, qd2 = qd[:, 0], qd[:, 1]
    D12 = m2 * l**2 / 3 + m2 * C2 * l**2 / 2
    D = np.stack([np.stack([m1 * l**2 / 3 + 4 * m2 * l**2 / 3 + m2 * C2 * l**2, D12], -1),
                  np.stack([D12, np.full_like(C2, m2 * l**2 / 3)], -1)], 1)
    h = np.stack([-m2 * S2 * l**2 * qd2**2 / 2 - m2 * S2 * l**2 * qd1 * qd2,
                  m2 * S2 * l**2 * qd1**2 / 2], 1)
    c = np.stack([(m1 / 2 + m2) * G * l * C1 + m2 * G * l * C12 / 2, m2 * G * l * C12 / 2], 1)
    return D, h, c


@pytest.mark.parametrize("method", METHODS)
def test_two_link_closed_forms(method):
    q, qd, qdd = _states(2, 60)
    D, h, c = _two_link_closed_form(q, qd)
    res = dynamics(load_robot("two-link"), q, qd, method)
    assert res.method == method
    for got, want in ((res.D, D), (res.h, h), (res.c, c)):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)
    tau = np.einsum("kij,kj->ki", D, qdd) + h + c
    np.testing.assert_allclose(inverse_dynamics(load_robot("two-link"), q, qd, qdd, method), tau,
                               rtol=0, atol=1e-11)


@pytest.mark.parametrize("robot", ROBOTS, ids=lambda r: r.name)
def test_all_formulations_agree_with_pinocchio(robot):
    q, qd, qdd = _states(robot.n, 250, seed=1)
    ref = dynamics(robot, q, qd, "pinocchio")
    tau_ref = inverse_dynamics(robot, q, qd, qdd, "pinocchio")
    for method in ("lagrange-euler", "newton-euler", "gd"):
        res = dynamics(robot, q, qd, method)
        for name in ("D", "h", "c"):
            got, want = getattr(res, name), getattr(ref, name)
            err = np.abs(got - want).max() / np.abs(want).max()
            assert err < 1e-10, (method, name, err)
        for tau in (res.tau(qdd), inverse_dynamics(robot, q, qd, qdd, method)):
            assert np.abs(tau - tau_ref).max() < 1e-10 * np.abs(tau_ref).max(), method


def test_compare_is_json_ready_and_small_for_consistent_methods():
    robot = load_robot("puma560")
    q, qd, qdd = _states(6, 40, seed=2)
    out = compare(robot, q, qd, qdd)
    assert set(out) == {"D", "h", "c", "tau"}
    for figures in out.values():
        assert len(figures) == 6                                  # pairs of four methods
        assert all(isinstance(v, float) and 0 <= v < 1e-10 for v in figures.values())
    assert json.loads(json.dumps(out)) == out


def test_compare_detects_a_wrong_formulation(monkeypatch):
    robot = load_robot("two-link")
    q, qd, qdd = _states(2, 20, seed=3)
    real = formulations.ne_terms

    def wrong(robot, q, qd):
        D, h, c = real(robot, q, qd)
        return 1.01 * D, h, c

    monkeypatch.setattr(formulations, "ne_terms", wrong)
    out = compare(robot, q, qd, qdd)
    for pair, value in out["D"].items():
        if "newton-euler" in pair:
            assert value == pytest.approx(0.01 / 1.01, rel=1e-6)
        else:
            assert value < 1e-12
    assert max(out["h"].values()) < 1e-12


def test_compare_report_and_format():
    robot = load_robot("puma560")
    q, qd, qdd = _states(6, 10, seed=4)
    report = compare_report(robot, q, qd, qdd)
    assert json.loads(json.dumps(report)) == report
    assert (report["robot"], report["n"], report["set_points"]) == ("puma560", 6, 10)
    assert report["max_disagreement"] < 1e-10
    ops = report["operation_counts"]
    assert set(ops) == {"lagrange-euler", "newton-euler", "gd", "gd-numpy"}
    assert ops["newton-euler"]["multiplications_table_3_5"] == 132 * 6
    assert ops["newton-euler"]["additions_table_3_5"] == 111 * 6 - 4
    text = format_compare(report)
    for method in METHODS:
        assert method in text
    assert str(ops["lagrange-euler"]["multiplications"]) in text
    assert "Table 3.5" in text


def test_result_is_frozen_and_bad_method_raises():
    robot = load_robot("two-link")
    res = dynamics(robot, np.zeros(2), np.zeros(2), "gd")
    assert isinstance(res, DynamicsResult)
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.D = None
    with pytest.raises(ValueError, match="unknown method"):
        dynamics(robot, np.zeros(2), np.zeros(2), "euler-lagrange")
    with pytest.raises(ValueError):
        inverse_dynamics(robot, np.zeros(2), np.zeros(2), np.zeros(3), "newton-euler")


@pytest.mark.parametrize("block", [1, 3, 7])
def test_compare_in_blocks_is_the_whole_arrays_definition(monkeypatch, block):
    """Gathered block by block, each figure is still max|a - b| / max(max|a|, max|b|) over
    every set point (computed here on the whole arrays): a formulation wrong at one set point
    of a late block is found, and the other figures are unchanged."""
    robot = load_robot("two-link")
    q, qd, qdd = _states(2, 20, seed=3)
    real = formulations.ne_terms
    bad = q[17]

    def wrong(robot, q, qd):
        D, h, c = real(robot, q, qd)
        at = np.all(q == bad, axis=-1)
        return np.where(at[:, None, None], 1.5 * D, D), h, c

    monkeypatch.setattr(formulations, "ne_terms", wrong)
    whole = compare(robot, q, qd, qdd)
    monkeypatch.setattr(formulations, "COMPARE_BLOCK", block)
    blocked = compare(robot, q, qd, qdd)
    assert blocked == whole
    D_ne = wrong(robot, q, qd)[0]
    D_gd = formulations.dynamics(robot, q, qd, "gd").D
    expected = np.abs(D_ne - D_gd).max() / max(np.abs(D_ne).max(), np.abs(D_gd).max())
    assert blocked["D"]["newton-euler vs gd"] == pytest.approx(expected, rel=1e-12)
    assert blocked["D"]["newton-euler vs gd"] > 0.1


def test_a_quantity_zero_in_every_formulation_is_no_disagreement(one_joint_urdf):
    """Oracle: a physical identity. One revolute joint has a constant D11, so h1 = 0 for any
    motion: every pair agrees on h, and the round-off one formulation leaves there (1e-17
    against 0) is no relative disagreement of 1, as it read."""
    q, qd, qdd = _states(1, 40, seed=4)
    out = compare(load_robot(str(one_joint_urdf)), q, qd, qdd)
    assert max(out["h"].values()) == 0.0
    assert max(max(v.values()) for v in out.values()) < 1e-10
