"""Verification on the natural scale; NaN never passes.

The oracle is Pinocchio (via :func:`verify`); the check must pass where the G-D terms are right
(one-link arm, a PUMA row with qd1 = 4.4e-16, positions-only files whose spline leaves round-off
in qd) and must fail on a real disagreement and on NaN.
"""

import dataclasses

import numpy as np
import pytest

from gd_analyze.dynamics.dalembert import gd_terms
from gd_analyze.errors import InputError
from gd_analyze.jobs.analyze import VERIFY_TOLERANCE, analyze, verify
from gd_analyze.jobs.options import AnalysisOptions
from gd_analyze.model.robot_spec import robot_from_dict
from gd_analyze.trajectory.trajectory import read_trajectory


def one_link(gravity=(0.0, -9.8062, 0.0)):
    link = {"d": 0.0, "a": 1.0, "alpha_deg": 0.0, "mass": 1.0, "com": [-0.5, 0.0, 0.0],
            "inertia": [0.0, 1 / 12, 1 / 12], "q_limits_deg": [-180, 180], "qd_max_deg": 180,
            "qdd_max_deg": 360}
    return robot_from_dict({"name": "one-link", "gravity": list(gravity), "link": [link]})


@pytest.mark.parametrize("gravity", [(0.0, -9.8062, 0.0), (0.0, 0.0, -9.8062), (0.0, 0.0, 0.0)])
def test_one_link_arm_passes(gravity):
    """A single joint has h = 0 exactly in Pinocchio; our round-off must not fail it."""
    robot = one_link(gravity)
    rng = np.random.default_rng(1)
    q, qd = rng.uniform(-3, 3, (50, 1)), rng.uniform(-3, 3, (50, 1))
    out = verify(robot, q, qd, qdd=rng.uniform(-3, 3, (50, 1)))
    assert out["passed"] == 1, out


def test_zero_velocity_puma_row_passes(puma):
    """The PUMA row with qd1 = 4.4e-16 (case 5): h is round-off on both sides."""
    q = np.radians([[10.0, -20.0, 30.0, 40.0, -50.0, 60.0]])
    qd = np.array([[4.4e-16, 0, 0, 0, 0, 0]])
    out = verify(puma, q, qd, qdd=np.zeros((1, 6)))
    assert out["passed"] == 1, out
    # Pinocchio's h is ~1e-31 here: a difference of 1e-38 N m is round-off on the torque's
    # scale (tens of N m), not a relative difference of 1e-7 as on h's own tiny scale.
    terms = gd_terms(puma, q, qd)
    noisy = dataclasses.replace(terms, h_rot=terms.h_rot + 1e-38, h_tran=terms.h_tran - 1e-38)
    out = verify(puma, q, qd, noisy, qdd=np.zeros((1, 6)))
    assert out["passed"] == 1, out


def test_positions_only_file_passes(tmp_path, puma):
    """Case 5 on Python 3.10: the spline's round-off in qd of a resting joint."""
    t = np.linspace(0, 1, 21)
    q = np.column_stack([np.sin(t)] + [np.full_like(t, 0.3 * k) for k in range(1, 6)])
    path = tmp_path / "pos.csv"
    path.write_text("t," + ",".join(f"q{i}" for i in range(1, 7)) + "\n"
                    + "\n".join(",".join(repr(float(v)) for v in row)
                                for row in np.column_stack([t, q])) + "\n")
    traj = read_trajectory(path, n_joints=6)
    assert traj.derivatives == "cubic-spline"
    out = verify(puma, traj.q, traj.qd, qdd=traj.qdd)
    assert out["passed"] == 1, out


def test_a_real_disagreement_fails(puma):
    rng = np.random.default_rng(2)
    q, qd = rng.uniform(-3, 3, (20, 6)), rng.uniform(-3, 3, (20, 6))
    terms = gd_terms(puma, q, qd)
    h_rot = terms.h_rot.copy()
    h_rot[:, 5] *= 1 + 1e-6
    bad = dataclasses.replace(terms, h_rot=h_rot)
    out = verify(puma, q, qd, bad)
    assert out["passed"] == 0 and out["max_rel_error_h_rot"] > VERIFY_TOLERANCE


@pytest.mark.parametrize("where", [0, 7, 19])
def test_nan_anywhere_fails_verification(puma, where):
    """Case 2: Python's max skipped a NaN unless it came first."""
    rng = np.random.default_rng(3)
    q, qd = rng.uniform(-3, 3, (20, 6)), rng.uniform(-3, 3, (20, 6))
    terms = gd_terms(puma, q, qd)
    D_tran = terms.D_tran.copy()
    D_tran[where, 2, 3] = np.nan
    out = verify(puma, q, qd, dataclasses.replace(terms, D_tran=D_tran))
    assert out["passed"] == 0 and np.isnan(out["max_rel_error_D_tran"])


def test_huge_inputs_are_refused_before_any_nan(puma, tmp_path):
    """Case 2: qd of 1e160 gave NaN torques and "Verification: passed"."""
    path = tmp_path / "fast.csv"
    cols = ["t"] + [f"{k}{i}" for k in ("q", "qd", "qdd") for i in range(1, 7)]
    rows = [[0.0] + [0.0] * 6 + [1e160] * 6 + [0.0] * 6, [1.0] + [0.0] * 18]
    path.write_text(",".join(cols) + "\n" + "\n".join(",".join(map(repr, r)) for r in rows))
    with pytest.raises(InputError, match="row 2, column qd1: .*beyond the supported"):
        read_trajectory(path)


def test_non_finite_terms_are_refused(puma):
    """Every computed array is checked: a robot beyond the limits (built without validation)
    yields an InputError, never NaN in the results."""
    heavy = puma.with_inertial(mass=np.full(6, 1e308))
    traj = dataclasses.make_dataclass("T", ["t", "q", "qd", "qdd", "derivatives", "source",
                                            "sha256"])
    q = np.ones((3, 6))
    tr = traj(np.arange(3.0), q, q * 1e10, q, "file", "x", "")
    with pytest.raises(InputError, match="not finite"):
        analyze(heavy, tr, AnalysisOptions(verify=False, formulations=False))
