"""Region coverage up to round-off: the desired motion between set points is judged against
its own round-off (jobs.control.motion_round_off), never a fixed share of the limit, and the
main job judges set points as evaluate and control do.

Oracle: the limits and the exact quintic Hermite interpolant of the set points, solved from
its six end conditions in rational arithmetic (fractions), never the code's own output.
"""

import math
from fractions import Fraction

import numpy as np
import pytest

from gd_analyze.certify.region import Region
from gd_analyze.cli import main
from gd_analyze.jobs.control import (
    DEFAULT_GRID_POINTS,
    desired_motion,
    motion_round_off,
    run_control,
)
from gd_analyze.jobs.evaluate import coverage
from gd_analyze.trajectory.trajectory import Trajectory, read_trajectory

#: Over 5 s on an idle machine (the PUMA 560's shared analysis and a closed-loop run).
pytestmark = pytest.mark.slow

#: A PUMA 560 move [deg] whose joint 6 sets the plan's duration: its |qd| peaks exactly at
#: qd_max (the 16th of 31 set points) and the desired motion, evaluated in floating point,
#: passes qd_max by about 20 eps of it there (4 eps was allowed).
START, GOAL = "120,60,10,90,50,-210", "0,190,-90,90,10,90"


def _exact(traj, i, j):
    """The exact interpolant's coefficients a_m of (t - t_i)^m on interval i, joint j:
    q, qd and qdd matched at both ends, the 6 x 6 system solved by Gauss-Jordan."""
    h = Fraction(traj.t[i + 1]) - Fraction(traj.t[i])
    rows = []
    for end, x in ((i, Fraction(0)), (i + 1, h)):
        for d, y in enumerate((traj.q, traj.qd, traj.qdd)):
            rows.append([Fraction(math.perm(m, d)) * x ** (m - d) if m >= d else Fraction(0)
                         for m in range(6)] + [Fraction(y[end, j])])
    for col in range(6):
        pivot = next(r for r in range(col, 6) if rows[r][col] != 0)
        rows[col], rows[pivot] = rows[pivot], rows[col]
        for r in range(6):
            if r != col and rows[r][col] != 0:
                f = rows[r][col] / rows[col][col]
                rows[r] = [a - f * b for a, b in zip(rows[r], rows[col])]
    return [rows[m][6] / rows[m][m] for m in range(6)]


def _exact_at(traj, t, j, k):
    """The exact interpolant's k-th derivative at the float times t, joint j (as Fractions);
    a time on a set point is taken in the interval it starts, as scipy does."""
    i = np.clip(np.searchsorted(traj.t, t, side="right") - 1, 0, len(traj.t) - 2)
    cache, out = {}, []
    for ti, ii in zip(t, i):
        if ii not in cache:                 # each interval's system solved once
            cache[ii] = _exact(traj, ii, j)
        a = cache[ii]
        s = Fraction(ti) - Fraction(traj.t[ii])
        out.append(sum(a[m] * math.perm(m, k) * s ** (m - k) for m in range(k, 6)))
    return out


@pytest.fixture(scope="module")
def planned(tmp_path_factory):
    """The plan job's trajectory of START -> GOAL (31 and 30 set points), read back."""
    folder = tmp_path_factory.mktemp("plan")
    out = {}
    for n in (31, 30):
        path = folder / f"plan{n}.csv"
        assert main(["plan", "puma560", "--start", START, "--goal", GOAL, "--setpoints",
                     str(n), "-o", str(path)]) == 0
        out[n] = read_trajectory(path, n_joints=6)
    return out


def _sample_times(traj):
    """Times at which a control run checks the desired motion: set points and its grid."""
    return np.union1d(traj.t, np.linspace(traj.t[0], traj.t[-1], DEFAULT_GRID_POINTS))


def test_the_round_off_bound_holds_against_the_exact_interpolant(planned):
    """|motion(t, k) - Q^(k)(t)| <= motion_round_off at every sample of joint 6 (the one at
    its limit) and of joint 1, for q, qd and qdd; and the bound stays far below a real
    excess of 1e-9 of the limit."""
    traj = planned[31]
    pp, t = desired_motion(traj), _sample_times(traj)
    bound = motion_round_off(pp, traj, t)
    for j in (0, 5):
        for k in range(3):
            exact = _exact_at(traj, t, j, k)
            err = np.array([float(abs(Fraction(v) - e)) for v, e in zip(pp(t, k)[:, j], exact)])
            assert np.all(err <= bound[k, :, j]), (j, k, np.max(err / bound[k, :, j]))
    qd_max = 1.91986217719376                       # the PUMA 560's joint 6, 110 deg/s
    assert bound[1, :, 5].max() < 1e-12 * qd_max


def test_a_planned_motion_at_its_velocity_limit_is_covered(planned, puma_analysis):
    """The plan peaks exactly at joint 6's velocity limit; the exact interpolant between the
    set points never passes it by more than the set points' own 4 eps, every other joint
    and quantity stays well inside: covered. (Said "not covered" from round-off alone.)"""
    model, traj = puma_analysis.model, planned[31]
    g = model.guarantee
    assert g.kind == "region"
    pp, t = desired_motion(traj), _sample_times(traj)
    limit = Fraction(g.qd_max[5])
    peak = max(abs(v) for v in _exact_at(traj, t, 5, 1))
    assert limit * (1 - Fraction(1, 10 ** 12)) < peak <= limit * (1 + 4 * Fraction(
        np.finfo(float).eps))                                   # at its limit, exactly
    assert np.abs(pp(t, 1)[:, 5]).max() > g.qd_max[5] * (1 + 4 * np.finfo(float).eps)
    others = np.abs(pp(t, 1)).max(0) / g.qd_max
    assert np.all(np.delete(others, 5) < 0.999)
    assert np.all(np.abs(pp(t, 2)).max(0) < 0.999 * g.qdd_max)
    q = pp(t)[:, :5]                                 # joint 6 turns freely (its region)
    assert np.all((q > g.q_min[:5] + 1e-3) & (q < g.q_max[:5] - 1e-3))
    said = run_control(model, traj, controllers=("full",), cost=False).summary()["guarantee"]
    assert said["covered"], said["reason"]


def test_a_motion_a_little_above_its_velocity_limit_is_not_covered(planned, puma_analysis):
    """The 30-set-point plan, 1e-11 faster: its peak (at T/2, between set points, on the
    output grid) passes joint 6's limit by 1e-11 of it in the exact interpolant, while
    every set point stays inside: not covered, the desired motion, joint and excess said."""
    model, base = puma_analysis.model, planned[30]
    c = 1 - 1e-11
    fast = Trajectory(base.t * c, base.q, base.qd / c, base.qdd / c ** 2)
    limit = model.guarantee.qd_max[5]
    t = _sample_times(fast)
    mid = np.argmin(np.abs(t - fast.t[-1] / 2))
    excess = float(abs(_exact_at(fast, t[mid:mid + 1], 5, 1)[0]) - Fraction(limit))
    assert 0.9e-11 * limit < excess < 1.1e-11 * limit
    assert coverage(model, fast)["covered"]                     # the set points are inside
    said = run_control(model, fast, controllers=("full",), cost=False).summary()["guarantee"]
    head = ("the desired motion between the set points is outside the model's region: "
            "joint 6's |qd| reaches ")
    assert not said["covered"] and said["reason"].startswith(head), said["reason"]


def test_the_main_job_judges_set_points_as_evaluate_does():
    """A set point 1e-10 of its limit beyond it is outside the region (the main job once
    allowed 1e-9 of each limit); one within 4 eps of it is inside."""
    region = Region(np.array([-1.0]), np.array([1.0]), np.array([2.0]), np.array([5.0]))
    zero = np.zeros((2, 1))
    for qd, inside in ((2.0 * (1 + 1e-10), False), (2.0 * (1 + 2 * np.finfo(float).eps), True)):
        out = region.excursion(zero, np.array([[0.0], [qd]]), zero)
        assert (out is None) == inside, out
    out = region.excursion(np.array([[0.0], [1 + 1e-10]]), zero, zero)
    assert out is not None and out.quantity == "q"
