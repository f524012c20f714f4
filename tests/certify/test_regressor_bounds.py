"""The interval regressor recursion: at points it is the regressor, over boxes it encloses it."""
import interval_oracle
import numpy as np
import pinocchio as pin
import pytest

from gd_analyze import load_robot
from gd_analyze.certify.region import channel_values as point_channels
from gd_analyze.certify.region import full_channels
from gd_analyze.certify.regressor_bounds import (
    channel_enclosures,
    channel_magnitudes,
    channel_values,
    combined_bound,
    inertia_enclosure,
    inertia_form_enclosure,
    pair_magnitudes,
)
from gd_analyze.dynamics.base_parameters import base_parameters, regressor, standard_parameters
from gd_analyze.dynamics.pinocchio import pinocchio_model


@pytest.mark.parametrize("name", ["puma560", "stanford"])
def test_channels_at_points_are_the_regressor(name):
    robot = load_robot(name)
    n = robot.n
    rng = np.random.default_rng(0)
    q, qd, qdd = rng.uniform(-2, 2, (3, 20, n))
    cols = np.arange(10 * n)
    for V in (channel_values(robot, q, cols), full_channels(point_channels(robot, q, cols))):
        W = (np.einsum("bjim,bj->bim", V[:, 1:1 + n], qdd) + V[:, 0]
             + np.einsum("bcim,bc->bim", V[:, 1 + n:],
                         (qd[:, :, None] * qd[:, None, :]).reshape(20, -1)))
        ref = regressor(robot, q, qd, qdd)
        assert np.abs(W - ref).max() <= 1e-12 * np.abs(ref).max()


def test_box_bounds_enclose_every_sampled_contribution():
    robot = load_robot("stanford")          # a prismatic joint: its position is an interval too
    n = robot.n
    rng = np.random.default_rng(1)
    lo = rng.uniform(robot.q_min, robot.q_max, (3, n))
    hi = np.minimum(lo + 0.4 * (robot.q_max - robot.q_min), robot.q_max)
    cols = np.arange(10 * n)
    U = pair_magnitudes(robot, lo, hi, cols, robot.qd_max, robot.qdd_max)
    for b in range(3):
        q = rng.uniform(lo[b], hi[b], (200, n))
        qd = rng.choice([-1.0, 1.0], (200, n)) * robot.qd_max * rng.uniform(0, 1, (200, 1))
        qdd = rng.uniform(-1, 1, (200, n)) * robot.qdd_max
        z = np.zeros_like(q)
        parts = (regressor(robot, q, z, qdd, gravity=np.zeros(3)),
                 regressor(robot, q, qd, z, gravity=np.zeros(3)), regressor(robot, q, z, z))
        for p, W in enumerate(parts):
            assert np.all(np.abs(W).max(axis=0) <= U[b, p] + 1e-12), p
    with pytest.raises(ValueError):
        pair_magnitudes(robot, hi, lo, cols, robot.qd_max, robot.qdd_max)


@pytest.mark.parametrize("name", ["puma560", "stanford"])
def test_the_bound_of_a_signed_sum_of_columns_holds_at_sampled_states(name):
    """Columns added as signed intervals on a box (each part its own weights, as a dropped set
    of (parameter, part) pairs), then bounded over the velocity and acceleration limits: never
    below |sum| of the regressor's columns at states inside the box, and below the sum of the
    columns' own bounds (the cancellation it is for)."""
    robot = load_robot(name)
    n = robot.n
    rng = np.random.default_rng(3)
    lo = rng.uniform(robot.q_min, robot.q_max, (3, n))
    hi = np.minimum(lo + rng.uniform(0.05, 0.6, (3, n)), robot.q_max)
    cols = np.arange(10 * n)
    w = rng.normal(size=(3, cols.size)) * (rng.uniform(size=(3, cols.size)) < 0.5)
    c_lo, c_hi = channel_enclosures(robot, lo, hi, cols)
    part = np.r_[2, np.zeros(n, int), np.ones(n * n, int)]
    W = w[part][:, None, :]                                        # (C, 1, m)
    mid = (0.5 * (c_lo + c_hi) * W).sum(-1)
    rad = (0.5 * (c_hi - c_lo) * np.abs(W)).sum(-1) * (1 + 1e-12)
    bound = combined_bound(mid, rad, robot.qd_max, robot.qdd_max)       # (3, n)
    own = np.einsum("bpim,pm->bi", pair_magnitudes(robot, lo, hi, cols, robot.qd_max,
                                                   robot.qdd_max), np.abs(w))
    assert np.all(bound <= own * (1 + 1e-9)) and np.any(bound < 0.95 * own)
    for b in range(3):
        q = rng.uniform(lo[b], hi[b], (400, n))
        qd = rng.choice([-1.0, 1.0], (400, n)) * robot.qd_max
        qd[200:] *= rng.uniform(0, 1, (200, n))
        qdd = rng.choice([-1.0, 1.0], (400, n)) * robot.qdd_max
        z = np.zeros_like(q)
        tau = (regressor(robot, q, z, qdd, gravity=np.zeros(3)) @ w[0]
               + regressor(robot, q, qd, z, gravity=np.zeros(3)) @ w[1]
               + regressor(robot, q, z, z) @ w[2])                       # (400, n)
        assert np.all(np.abs(tau).max(axis=0) <= bound[b] * (1 + 1e-12) + 1e-12), b
    # at a point (a box of zero width) the bound is never below the largest over the velocity
    # box's vertices with the best accelerations, computed from the regressor, and within 15 %
    # above it (the diagonal of the quadratic form is bounded apart from its vertices)
    q = lo[:1]
    c_lo, c_hi = channel_enclosures(robot, q, q, cols)
    mid = (0.5 * (c_lo + c_hi) * W).sum(-1)
    rad = (0.5 * (c_hi - c_lo) * np.abs(W)).sum(-1) * (1 + 1e-12)
    at = combined_bound(mid, rad, robot.qd_max, robot.qdd_max)[0]
    z = np.zeros((1, n))
    g = (regressor(robot, q, z, z) @ w[2])[0]
    a = sum(np.abs(regressor(robot, q, z, np.eye(n)[j:j + 1], gravity=np.zeros(3)) @ w[0])[0]
            * robot.qdd_max[j] for j in range(n))
    signs = np.array(np.meshgrid(*[[-1.0, 1.0]] * n)).reshape(n, -1).T
    v = signs * robot.qd_max
    quad = regressor(robot, np.repeat(q, len(v), 0), v, np.zeros_like(v),
                     gravity=np.zeros(3)) @ w[1]                          # (2^n, n)
    exact = np.maximum(g + a + quad.max(axis=0), -(g - a + quad.min(axis=0)))
    assert np.all(exact <= at * (1 + 1e-12) + 1e-12)
    assert np.all(at <= 1.15 * exact + 1e-9)


@pytest.mark.parametrize("arithmetic", ["ball", "box"])
def test_both_arithmetics_enclose_the_sampled_peaks_on_boxes(arithmetic):
    """Every pair's bound over a box is at least its largest value sampled inside the box
    (velocity at the vertices of the limits, where the quadratic form can peak)."""
    from gd_analyze.certify.certify import pair_peaks_at

    robot = load_robot("puma560")
    n = robot.n
    rng = np.random.default_rng(2)
    lo = rng.uniform(robot.q_min, robot.q_max, (4, n))
    hi = np.minimum(lo + rng.uniform(0.05, 1.0, (4, n)), robot.q_max)
    cols = np.arange(10 * n)
    if arithmetic == "ball":
        U = pair_magnitudes(robot, lo, hi, cols, robot.qd_max, robot.qdd_max)
    else:                 # the box kernels' channels, as the certification's joint sums take them
        U = channel_magnitudes(*channel_enclosures(robot, lo, hi, cols, arithmetic="box"),
                               robot.qd_max, robot.qdd_max)
    for b in range(4):
        q = rng.uniform(lo[b], hi[b], (300, n))
        peaks = pair_peaks_at(point_channels(robot, q, cols), np.ones(cols.size),
                              robot.qd_max, robot.qdd_max)          # (m, 3, n)
        assert np.all(peaks.transpose(1, 2, 0) <= U[b] * (1 + 1e-12) + 1e-12)
    with pytest.raises(ValueError):
        channel_enclosures(robot, lo, hi, cols, arithmetic="x")


def _crba(robot, q):
    pm = pinocchio_model(robot)
    data = pm.createData()
    D = np.array([pin.crba(pm, data, x) for x in q])
    return np.triu(D) + np.swapaxes(np.triu(D, 1), 1, 2)


@pytest.mark.parametrize("name", ["puma560", "panda", "stanford"])
@pytest.mark.parametrize("arithmetic", ["ball", "box"])
def test_inertia_enclosures_hold_pinocchios_d_on_boxes(name, arithmetic):
    """Pinocchio's crba at points inside random boxes lies within the enclosure of D (both
    arithmetics, the standard parameters), and X D X^T within the form's enclosure; at a
    point the enclosures are round-off wide about crba."""
    robot = load_robot(name)
    phi = standard_parameters(robot)
    rng = np.random.default_rng(4)
    centre = rng.uniform(-2, 2, (6, robot.n))
    half = rng.uniform(0.0, 0.4, (6, robot.n))
    enclosure = inertia_enclosure if arithmetic == "ball" else interval_oracle.inertia_box
    lo, hi = enclosure(robot, centre - half, centre + half, phi)
    X = rng.normal(size=(6, 3, robot.n))
    flo, fhi = inertia_form_enclosure(robot, centre - half, centre + half, phi, X)
    for b in range(6):
        q = rng.uniform(centre[b] - half[b], centre[b] + half[b], (200, robot.n))
        D = _crba(robot, q)
        assert ((lo[b] <= D) & (D <= hi[b])).all()
        P = X[b] @ D @ X[b].T
        assert ((flo[b] <= P) & (P <= fhi[b])).all()
    D = _crba(robot, centre)
    plo, phi_ = enclosure(robot, centre, centre, phi)
    assert ((plo <= D) & (D <= phi_)).all()
    assert (phi_ - plo).max() <= 1e-12 * np.abs(D).max()


def test_a_box_s_bounds_do_not_depend_on_the_batch_it_is_in():
    """The oracle: each box's bounds computed alone. In a batch of 64 boxes (and in batches
    of one link's columns) they are the same bit for bit, so that a read-back that evaluates
    a tree's boxes in other batches than the certification did derives the same bounds."""
    robot = load_robot("panda")
    n = robot.n
    cols = np.flatnonzero(base_parameters(robot).independent.reshape(-1))
    rng = np.random.default_rng(4)
    q_min, q_max = np.asarray(robot.q_min, float), np.asarray(robot.q_max, float)
    c = rng.uniform(q_min, q_max, (64, n))
    w = rng.uniform(0.01, 1.0, (64, n))
    lo, hi = np.maximum(c - w, q_min), np.minimum(c + w, q_max)
    qd_max, qdd_max = np.asarray(robot.qd_max, float), np.full(n, 3.0)
    batch = pair_magnitudes(robot, lo, hi, cols, qd_max, qdd_max)
    alone = np.concatenate([pair_magnitudes(robot, lo[i:i + 1], hi[i:i + 1], cols, qd_max,
                                            qdd_max) for i in range(lo.shape[0])])
    np.testing.assert_array_equal(batch, alone)
    for k in np.unique(cols // 10):
        ms = cols // 10 == k
        np.testing.assert_array_equal(
            pair_magnitudes(robot, lo[5:17], hi[5:17], cols[ms], qd_max, qdd_max),
            batch[5:17][..., ms])
