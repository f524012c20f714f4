"""The compiled interval-box recursion encloses what the array code's boxes enclose, holds the
regressor at points, and intersected with the balls is tighter than either alone."""
import interval_oracle
import numpy as np
import pytest
from conftest import random_boxes as _boxes

from gd_analyze import load_robot
from gd_analyze.certify import regressor_bounds as rb
from gd_analyze.dynamics.base_parameters import base_parameters
from gd_analyze.dynamics.opcount import random_chain

ARMS = {"puma560": lambda: load_robot("puma560"), "stanford": lambda: load_robot("stanford"),
        "panda": lambda: load_robot("panda"), "ur5": lambda: load_robot("ur5"),
        "chain-RPRRPR": lambda: random_chain(6, seed=3, types="RPRRPR")}


def _array_code(robot, lo, hi, cols):
    """The oracle: the array code's box recursion (``_column_groups`` with the oracle's
    ``Box``, each operation rounded outward by one ulp), in :func:`channel_enclosures`'
    layout."""
    shape = (lo.shape[0], rb.channel_count(robot.n), robot.n, cols.size)
    a, b = np.zeros(shape), np.zeros(shape)
    for ms, i, (x, y) in interval_oracle.column_groups(robot, lo, hi, cols):
        a[:, :, i, ms], b[:, :, i, ms] = x, y
    return a, b


def _columns(robot):
    return np.flatnonzero(base_parameters(robot).independent.reshape(-1))


@pytest.mark.parametrize("name", sorted(ARMS))
def test_the_box_kernels_enclose_the_array_codes_boxes(name):
    """The same operations in the same order, each rounded outward in one step by a margin
    above the array code's ulps: each enclosure equals the array code's to round-off of the
    channels' size, and where it is narrower, by no more than the array code's own ulps (the
    array code also rounds the sums with exact zeros, which the kernel leaves out), on
    revolute and prismatic joints and boxes narrow, wide and past a half turn."""
    robot = ARMS[name]()
    cols = _columns(robot)
    for width, seed in ((0.0, 3), (0.02, 0), (0.3, 1), (0.9, 2)):
        lo, hi = _boxes(robot, 9, width, seed)
        got = rb.channel_enclosures(robot, lo, hi, cols, arithmetic="box")
        want = _array_code(robot, lo, hi, cols)
        scale = max(np.abs(want[0]).max(), np.abs(want[1]).max())
        assert np.all(np.isfinite(got[0])) and np.all(np.isfinite(got[1]))
        assert np.all(got[0] <= got[1])
        for g, w in zip(got, want):
            assert np.abs(g - w).max() <= 1e-12 * scale, (name, width)
        assert np.all(got[0] <= want[0] + 1e-15 * scale), (name, width)
        assert np.all(got[1] >= want[1] - 1e-15 * scale), (name, width)


@pytest.mark.parametrize("name", sorted(ARMS))
@pytest.mark.parametrize("arithmetic", ["box", "both"])
def test_the_enclosures_hold_the_regressor_at_points_of_each_box(name, arithmetic):
    """Every channel of the regressor at a point of a box (:func:`channel_values`, checked
    against the regressor in ``test_regressor_bounds.py``) lies within its enclosure over
    the box, in boxes alone and intersected with the balls, on boxes up to a half turn
    wide."""
    robot = ARMS[name]()
    cols = _columns(robot)
    rng = np.random.default_rng(6)
    for width, seed in ((0.05, 5), (0.4, 8)):
        lo, hi = _boxes(robot, 6, width, seed)
        e_lo, e_hi = rb.channel_enclosures(robot, lo, hi, cols, arithmetic=arithmetic)
        for _ in range(20):
            q = rng.uniform(lo, hi)
            q[0] = lo[0]                            # the boxes' corners too
            q[1] = hi[1]
            V = rb.channel_values(robot, q, cols)
            tol = 1e-12 * np.abs(V).max()
            assert np.all(V >= e_lo - tol) and np.all(V <= e_hi + tol), (name, width)


@pytest.mark.parametrize("name", ["panda", "ur5", "puma560"])
def test_the_intersection_is_within_each_and_tighter_than_either(name):
    """Intersected, each enclosure lies within the balls' and the boxes' (up to the
    boxes' round-off); the default on these arms is the intersection, narrower than the
    balls alone on many channels (the inertial and velocity channels near the column's own
    joint) and than the boxes alone on others (down the chain)."""
    robot = ARMS[name]()
    cols = _columns(robot)
    lo, hi = _boxes(robot, 16, 0.1, 11)
    ball = rb.channel_enclosures(robot, lo, hi, cols, arithmetic="ball")
    box = rb.channel_enclosures(robot, lo, hi, cols, arithmetic="box")
    both = rb.channel_enclosures(robot, lo, hi, cols)
    scale = np.abs(ball[0]).max()
    for e in (ball, box):
        assert np.all(both[0] >= e[0] - 1e-12 * scale)
        assert np.all(both[1] <= e[1] + 1e-12 * scale)
    w_both, w_ball, w_box = (e[1] - e[0] for e in (both, ball, box))
    assert np.sum(w_both < 0.9 * w_ball) > 0.2 * np.sum(w_ball > 0)
    assert np.sum(w_both < 0.9 * w_box) > 0.05 * np.sum(w_box > 0)
    assert w_both.sum() < 0.95 * min(w_ball.sum(), w_box.sum())


def test_long_chains_are_enclosed_in_balls_alone():
    """Beyond :data:`BOX_MAX_JOINTS` joints the default is the balls' enclosure itself."""
    robot = random_chain(rb.BOX_MAX_JOINTS + 1, seed=4)
    cols = _columns(robot)[:12]
    lo, hi = _boxes(robot, 4, 0.1, 2)
    got = rb.channel_enclosures(robot, lo, hi, cols)
    want = rb.channel_enclosures(robot, lo, hi, cols, arithmetic="ball")
    assert all(np.array_equal(g, w) for g, w in zip(got, want))
    with pytest.raises(ValueError):
        rb.channel_enclosures(robot, lo, hi, cols, arithmetic="interval")
