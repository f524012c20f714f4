"""The compiled ball recursion encloses what the array code encloses, and holds at points."""
import interval_oracle
import numpy as np
import pinocchio as pin
import pytest
from conftest import random_boxes as _boxes

from gd_analyze import load_robot
from gd_analyze.certify import regressor_bounds as rb
from gd_analyze.dynamics.base_parameters import base_parameters, standard_parameters
from gd_analyze.dynamics.opcount import random_chain
from gd_analyze.dynamics.pinocchio import pinocchio_model


def _crba(robot, q):
    """Pinocchio's D(q) at each row of q, both triangles filled."""
    pm = pinocchio_model(robot)
    data = pm.createData()
    D = np.array([pin.crba(pm, data, x) for x in q])
    return np.triu(D) + np.swapaxes(np.triu(D, 1), 1, 2)


def _array_code(robot, lo, hi, cols):
    """The oracle: the array code's ball recursion (``_column_groups`` with ``_Ball``), in
    :func:`channel_enclosures`' layout."""
    shape = (lo.shape[0], rb.channel_count(robot.n), robot.n, cols.size)
    a, b = np.zeros(shape), np.zeros(shape)
    for ms, i, (x, y) in rb._column_groups(robot, lo, hi, cols, None, rb._Ball):
        a[:, :, i, ms], b[:, :, i, ms] = x, y
    return a, b


ARMS = {"puma560": lambda: load_robot("puma560"), "stanford": lambda: load_robot("stanford"),
        "panda": lambda: load_robot("panda"),
        "chain-RPRRPR": lambda: random_chain(6, seed=3, types="RPRRPR"),
        "chain-9": lambda: random_chain(9, seed=4)}


@pytest.mark.parametrize("name", sorted(ARMS))
def test_the_kernels_give_the_array_codes_enclosures(name):
    """The same operations in the same order: equal to the array code to its round-off (bit
    for bit where the libraries round alike), on revolute and prismatic joints and the wide
    boxes where a rotation's arc is enclosed about its axis."""
    robot = ARMS[name]()
    cols = np.flatnonzero(base_parameters(robot).independent.reshape(-1))
    for width, seed in ((0.02, 0), (0.3, 1), (0.9, 2)):
        lo, hi = _boxes(robot, 9, width, seed)
        got = rb.channel_enclosures(robot, lo, hi, cols, arithmetic="ball")
        want = _array_code(robot, lo, hi, cols)
        scale = max(np.abs(want[0]).max(), np.abs(want[1]).max())
        for g, w in zip(got, want):
            assert np.all(np.isfinite(g))
            assert np.abs(g - w).max() <= 1e-14 * scale, (name, width)
        assert np.all(got[0] <= got[1])


@pytest.mark.parametrize("name", ["puma560", "chain-RPRRPR"])
def test_the_enclosures_hold_the_regressor_at_points_of_each_box(name):
    """Every channel of the regressor at a point (Khalil & Kleinfinger's coefficients of qdd,
    qd qd and gravity: :func:`gd_analyze.certify.regressor_bounds.channel_values`, which
    ``test_regressor_bounds.py`` checks against the regressor) lies within its enclosure over
    a box that holds the point."""
    robot = ARMS[name]()
    cols = np.flatnonzero(base_parameters(robot).independent.reshape(-1))
    lo, hi = _boxes(robot, 6, 0.1, 5)
    e_lo, e_hi = rb.channel_enclosures(robot, lo, hi, cols, arithmetic="ball")
    rng = np.random.default_rng(6)
    for _ in range(20):
        q = rng.uniform(lo, hi)
        V = rb.channel_values(robot, q, cols)
        tol = 1e-12 * np.abs(V).max()
        assert np.all(V >= e_lo - tol) and np.all(V <= e_hi + tol)


def test_pair_magnitudes_by_the_kernels_equal_the_array_codes():
    """The magnitudes taken link by link in the link's own channels equal those taken in the
    whole layout from the array code's enclosures."""
    robot = load_robot("panda")
    n = robot.n
    cols = np.flatnonzero(base_parameters(robot).independent.reshape(-1))
    lo, hi = _boxes(robot, 7, 0.2, 8)
    qd_max, qdd_max = np.linspace(1.0, 2.5, n), np.linspace(3.0, 6.0, n)
    got = rb.pair_magnitudes(robot, lo, hi, cols, qd_max, qdd_max)
    want = rb.channel_magnitudes(*_array_code(robot, lo, hi, cols), qd_max, qdd_max)
    assert np.abs(got - want).max() <= 1e-14 * np.abs(want).max()
    assert got.shape == (7, 3, n, cols.size) and np.all(got >= 0)


@pytest.mark.parametrize("name", ["puma560", "panda", "stanford", "two-link"])
def test_compiled_inertia_enclosure_is_the_array_codes(name):
    """The compiled kernel (ball arithmetic, box by box) gives the array code's enclosures in
    the same arithmetic (its oracle) to round-off of D's size, on boxes narrow, wide and past
    the arc limit of a rotation (half-width > pi/2), on points, and with a prismatic joint
    (stanford); and it holds Pinocchio's D at points inside each box."""
    robot = load_robot(name)
    n = robot.n
    phi = standard_parameters(robot)
    rng = np.random.default_rng(7)
    centre = rng.uniform(-2, 2, (40, n))
    half = rng.uniform(0.0, 2.0, (40, n)) * rng.uniform(0, 1, (40, 1))
    half[:5] = 0.0
    half[5:10] = rng.uniform(1.6, 3.0, (5, n))
    lo_q, hi_q = rb._boxes(robot, centre - half, centre + half)
    lo, hi = rb.inertia_enclosure(robot, lo_q, hi_q, phi)
    a_lo, a_hi = interval_oracle.inertia_arrays(robot, lo_q, hi_q, phi, rb._Ball)
    arm = np.asarray(robot.armature, float)
    idx = np.arange(n)
    a_lo[:, idx, idx] += arm
    a_hi[:, idx, idx] += arm
    a_lo = np.maximum(a_lo, np.swapaxes(a_lo, 1, 2))
    a_hi = np.minimum(a_hi, np.swapaxes(a_hi, 1, 2))
    size = np.abs(a_lo).max() + np.abs(a_hi).max()
    assert np.all(np.isfinite(lo)) and np.all(np.isfinite(hi))
    assert np.abs(lo - a_lo).max() <= 1e-14 * size
    assert np.abs(hi - a_hi).max() <= 1e-14 * size
    assert np.all(lo <= hi)
    for b in range(0, 40, 4):
        q = rng.uniform(lo_q[b], hi_q[b], (50, n))
        D = _crba(robot, q)
        assert ((lo[b] <= D) & (D <= hi[b])).all()
