"""The part contributions and their peaks, the compiled kernel and its oracle (array code),
against Pinocchio (rnea per part, computeJointTorqueRegressor), against the numpy regressor of
base_parameters, and against each other (the same values to round-off, NaN kept out of the
peaks alike)."""

import numpy as np
import pinocchio as pin
import pytest
from numpy_engines import contribution_peaks_numpy, part_contributions_numpy, part_regressor_numpy
from symbolic_helpers import ROBOTS, mixed_chain, rnea, robot, states

from gd_analyze.dynamics import regressor_kernels
from gd_analyze.dynamics.base_parameters import base_parameters, regressor
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.dynamics.regressor_kernels import (
    contribution_peaks,
    link_channels,
    part_contributions,
    part_regressor,
    regressor_columns,
    regressor_columns_pullback,
    stacked_contribution_peaks,
)

#: Pinocchio's per-joint order (m, mc_x, mc_y, mc_z, Ixx, Ixy, Iyy, Ixz, Iyz, Izz) -> ours.
PIN_ORDER = [4, 5, 7, 6, 8, 9, 1, 2, 3, 0]
#: The kernels and their oracles (array code), by engine.
ENGINES = ("numpy", "compiled")
PARTS = {"numpy": part_contributions_numpy, "compiled": part_contributions}
PEAKS = {"numpy": contribution_peaks_numpy, "compiled": contribution_peaks}
REGRESSOR = {"numpy": part_regressor_numpy, "compiled": part_regressor}


def _pin_base_columns(arm, base, q, qd, qdd, gravity):
    """Pinocchio's joint-torque regressor on the independent columns, times beta."""
    model = pinocchio_model(arm)
    if not gravity:
        model.gravity = pin.Motion.Zero()
    data = model.createData()
    W = np.array([pin.computeJointTorqueRegressor(model, data, a, b, c)
                  for a, b, c in zip(q, qd, qdd)])
    W = np.concatenate([W[..., 10 * j:10 * j + 10][..., PIN_ORDER] for j in range(arm.n)], -1)
    return W[:, :, base.independent.reshape(-1)] * base.beta


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("name", ROBOTS)
def test_each_part_is_pinocchios_regressor_of_that_part(name, engine):
    """Part p of every base parameter is Pinocchio's regressor column at the part's state
    (qd = 0 and g = 0 for the inertial part, qdd = 0 and g = 0 for the velocity part, qd = qdd
    = 0 for gravity), times beta; a wrong column, sign, frame or part fails."""
    arm = robot(name)
    base = base_parameters(arm)
    q, qd, qdd = states(arm, 25, 7)
    zero = np.zeros_like(q)
    C = PARTS[engine](arm, base, q, qd, qdd)
    assert C.shape == (3, 25, arm.n, base.rank)
    for p, (a, b, c, g) in enumerate(((q, zero, qdd, False), (q, qd, zero, False),
                                      (q, zero, zero, True))):
        ref = _pin_base_columns(arm, base, a, b, c, g)
        scale = max(np.abs(ref).max(), 1e-300)
        assert np.abs(C[p] - ref).max() <= 1e-12 * scale, (name, p)


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("name", ROBOTS)
def test_contributions_add_up_to_rnea_and_equal_the_numpy_regressor(name, engine):
    arm = robot(name)
    base = base_parameters(arm)
    q, qd, qdd = states(arm, 30, 3)
    C = PARTS[engine](arm, base, q, qd, qdd)
    tau = rnea(arm, q, qd, qdd)
    scale = np.abs(tau).max()
    assert np.abs(C.sum(axis=(0, 3)) - tau).max() <= 1e-10 * scale
    cols = base.independent.reshape(-1)
    zero = np.zeros_like(q)
    for p, (a, b, c, g) in enumerate(((q, zero, qdd, np.zeros(3)), (q, qd, zero, np.zeros(3)),
                                      (q, zero, zero, None))):
        ref = regressor(arm, a, b, c, gravity=g)[:, :, cols] * base.beta
        assert np.abs(C[p] - ref).max() <= 1e-13 * max(np.abs(ref).max(), 1e-300)


@pytest.mark.parametrize("name", ("stanford", "mixed-chain"))
def test_running_peaks_over_chunks_are_the_peaks_of_the_contributions(name):
    """Peaks updated chunk by chunk (out=) are the abs max of the stored contributions: per
    pair, per parameter (parts summed) and of tau = the sum of everything."""
    arm = robot(name)
    base = base_parameters(arm)
    q, qd, qdd = states(arm, 41, 11)
    C = part_contributions(arm, base, q, qd, qdd)
    out = None
    for a in range(0, 41, 9):
        out = contribution_peaks(arm, base, q[a:a + 9], qd[a:a + 9], qdd[a:a + 9], out=out)
    tau_peak, peak, whole = out
    np.testing.assert_array_equal(peak, np.abs(C).max(axis=1).transpose(2, 0, 1))
    np.testing.assert_array_equal(whole, np.abs(C.sum(axis=0)).max(axis=0).T)
    tau = rnea(arm, q, qd, qdd)
    np.testing.assert_allclose(tau_peak, np.abs(tau).max(axis=0), rtol=1e-10,
                               atol=1e-12 * np.abs(tau).max())


def test_bad_shapes_are_refused():
    arm = robot("puma560")
    base = base_parameters(arm)
    q = np.zeros((3, arm.n))
    with pytest.raises(ValueError):
        part_contributions(arm, base, q[:, :4], q[:, :4], q[:, :4])
    with pytest.raises(ValueError):
        contribution_peaks(arm, base, q, q, q, out=(np.zeros(2), np.zeros(2), np.zeros(2)))


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("name", ROBOTS)
def test_part_regressor_sums_to_pinocchios_regressor(name, engine):
    """part_regressor at unit beta: its parts sum to Pinocchio's computeJointTorqueRegressor
    on every standard column; its gravity part is the regressor at rest."""
    arm = robot(name)
    q, qd, qdd = states(arm, 4, 11)
    cols = np.arange(10 * arm.n)
    W = REGRESSOR[engine](arm, cols, q, qd, qdd)
    model = pinocchio_model(arm)
    data = model.createData()
    ref = np.array([pin.computeJointTorqueRegressor(model, data, a, b, c)
                    for a, b, c in zip(q, qd, qdd)])
    ref = np.concatenate([ref[..., 10 * j:10 * j + 10][..., PIN_ORDER] for j in range(arm.n)],
                         -1)
    scale = np.abs(ref).max()
    assert np.abs(W.sum(axis=1) - ref).max() <= 1e-10 * scale
    z = np.zeros_like(q)
    assert np.abs(W[:, 2] - regressor(arm, q, z, z)).max() <= 1e-10 * scale


def test_part_regressor_refuses_columns_beyond_the_links():
    arm = robot("two-link")
    z = np.zeros((1, 2))
    with pytest.raises(ValueError, match="columns"):
        part_regressor(arm, [20], z, z, z)
    with pytest.raises(ValueError, match="columns"):
        regressor_columns(arm, [-1], z, z, z)


@pytest.mark.parametrize("name", ("puma560", "stanford"))
def test_the_kernel_gives_the_oracle_s_values_on_every_output(name, monkeypatch):
    """Compiled kernel and array code (the oracle): the part regressor (columns in any order, repeated),
    the contributions and their running peaks within 1e-12 of their scale, over several
    blocks of the array code (BLOCK made small) and a prismatic joint (Stanford)."""
    monkeypatch.setattr(regressor_kernels, "BLOCK", 16)
    arm = robot(name)
    base = base_parameters(arm)
    q, qd, qdd = states(arm, 70, 21)
    cols = np.r_[np.arange(10 * arm.n)[::-1], 3, 3]
    a, b = (REGRESSOR[e](arm, cols, q, qd, qdd) for e in ENGINES)
    assert np.abs(a - b).max() <= 1e-12 * np.abs(b).max()
    a, b = (PARTS[e](arm, base, q, qd, qdd) for e in ENGINES)
    assert np.abs(a - b).max() <= 1e-12 * np.abs(b).max()
    a, b = (PEAKS[e](arm, base, q, qd, qdd) for e in ENGINES)
    for x, y in zip(a, b):
        assert np.abs(x - y).max() <= 1e-12 * np.abs(y).max()
    # one part of the oracle is the numpy regressor of base_parameters, column by column
    z = np.zeros_like(q)
    ref = regressor(arm, q, z, qdd, gravity=np.zeros(3))[:, :, cols]
    W = regressor_columns(arm, cols, q, z, qdd, gravity=np.zeros(3))
    assert np.abs(W - ref).max() <= 1e-12 * np.abs(ref).max()


def test_the_kernel_and_the_oracle_keep_nan_out_of_the_peaks_alike():
    """A set point with NaN velocities: its contributions are NaN, never a peak; both give the peaks of the other set points (the kernel's ``if v > peak``)."""
    arm = robot("stanford")
    base = base_parameters(arm)
    q, qd, qdd = states(arm, 12, 4)
    qd[5, 1] = np.nan
    a, b = (PEAKS[e](arm, base, q, qd, qdd) for e in ENGINES)
    clean = contribution_peaks(arm, base, np.delete(q, 5, 0), np.delete(qd, 5, 0),
                               np.delete(qdd, 5, 0))
    for x, y, c in zip(a, b, clean):
        assert not np.isnan(x).any() and not np.isnan(y).any()
        assert np.abs(x - y).max() <= 1e-12 * np.abs(y).max()
        assert np.all(x >= c - 1e-12 * np.abs(c).max())         # the others' peaks are kept


def test_stacked_peaks_are_pinocchios_per_trajectory():
    """Trajectories of 1 to 700 set points stacked (short ones evaluated together, a group
    closed at BLOCK set points, the long one alone): each trajectory's peaks are those of
    Pinocchio's regressor columns on its own states, and a NaN state is never a peak."""
    arm = robot("mixed-chain")
    base = base_parameters(arm)
    lengths = [31, 1, 700, 5, 40, 2047, 3, 31]
    q, qd, qdd = states(arm, sum(lengths), 12)
    q[33, 0] = np.nan                                   # in the third trajectory
    tau_peak, peak, whole = stacked_contribution_peaks(arm, base, q, qd, qdd, lengths)
    zero = np.zeros_like(q)
    parts = [_pin_base_columns(arm, base, a, b, c, g) for a, b, c, g in
             ((q, zero, qdd, False), (q, qd, zero, False), (q, zero, zero, True))]
    C = np.stack(parts)                                 # (3, N, n, b)
    starts = np.cumsum([0] + lengths)
    for k, (a, e) in enumerate(zip(starts[:-1], starts[1:])):
        Ck = C[:, a:e]
        scale = np.nanmax(np.abs(Ck.sum(axis=(0, 3))))
        want = (np.nanmax(np.abs(Ck.sum(axis=(0, 3))), axis=0),
                np.nanmax(np.abs(Ck), axis=1).transpose(2, 0, 1),
                np.nanmax(np.abs(Ck.sum(axis=0)), axis=0).T)
        for got, ref in zip((tau_peak[k], peak[k], whole[k]), want):
            assert np.all(np.isfinite(got))
            assert np.abs(got - ref).max() <= 1e-12 * scale, k


@pytest.mark.parametrize("name", ROBOTS)
def test_the_pullback_is_the_gradient_of_the_weighted_regressor(name):
    """regressor_columns_pullback's W is regressor_columns', and its pullback of random weights
    G is the gradient of sum G * W in q, qd and qdd: central differences of regressor_columns
    (step 1e-5, truncation error ~1e-10 of the scale), every column in a shuffled order."""
    arm = robot(name)
    n = arm.n
    q, qd, qdd = states(arm, 40, 11)
    rng = np.random.default_rng(3)
    columns = rng.permutation(10 * n)
    W, pullback = regressor_columns_pullback(arm, columns, q, qd, qdd)
    np.testing.assert_allclose(W, regressor_columns(arm, columns, q, qd, qdd), rtol=0,
                               atol=1e-12 * np.abs(W).max())
    G = rng.normal(size=W.shape)
    got = pullback(G)
    h = 1e-5
    for d in range(3):
        want = np.empty((q.shape[0], n))
        for j in range(n):
            up = [a.copy() for a in (q, qd, qdd)]
            down = [a.copy() for a in (q, qd, qdd)]
            up[d][:, j] += h
            down[d][:, j] -= h
            want[:, j] = ((regressor_columns(arm, columns, *up)
                           - regressor_columns(arm, columns, *down)) * G).sum((1, 2)) / (2 * h)
        np.testing.assert_allclose(got[d], want, rtol=0, atol=1e-7 * np.abs(want).max())


def _pin_channels(arm, q):
    """Oracle: the channels of every standard column at positions q from Pinocchio's
    computeJointTorqueRegressor at the channels' states, (B, 1 + n + n n, n, 10 n): G = W(q, 0,
    0), A_j = W(q, 0, e_j) - G, and C_jl = (W(q, e_j + e_l, 0) - W(q, e_j - e_l, 0)) / 4
    (C_jj = W(q, e_j, 0) - G), gravity on for G only."""
    n = arm.n
    model = pinocchio_model(arm)
    data = model.createData()
    flat = pinocchio_model(arm)
    flat.gravity = pin.Motion.Zero()
    flat_data = flat.createData()
    eye, zero = np.eye(n), np.zeros(n)
    out = np.empty((q.shape[0], 1 + n + n * n, n, 10 * n))
    for b, x in enumerate(q):
        def Y(qd, qdd, m=flat, d=flat_data, x=x):
            W = pin.computeJointTorqueRegressor(m, d, x, qd, qdd).copy()
            return np.concatenate([W[:, 10 * j:10 * j + 10][:, PIN_ORDER] for j in range(n)], 1)
        out[b, 0] = Y(zero, zero, model, data)
        for j in range(n):
            out[b, 1 + j] = Y(zero, eye[j])
            for l in range(n):
                out[b, 1 + n + n * j + l] = (Y(eye[j], zero) if j == l else
                                             (Y(eye[j] + eye[l], zero)
                                              - Y(eye[j] - eye[l], zero)) / 4)
    return out


@pytest.mark.parametrize("name", ROBOTS + ("mixed-9",))
def test_link_channels_are_pinocchios_regressor_at_the_channels_states(name):
    """Every standard column's gravity, inertial and symmetrized velocity channels (oracle:
    Pinocchio's regressor at (q, 0, 0), (q, 0, e_j) and (q, e_j +- e_l, 0)) within 1e-12 of
    the scale, on the DH, URDF and modified-DH arms and random chains with prismatic joints
    and oblique axes; the channels of a link hold its joints only, the rest being zero."""
    arm = mixed_chain(9, seed=8) if name == "mixed-9" else robot(name)
    n = arm.n
    q = states(arm, 6, 13)[0]
    cols = np.r_[np.arange(10 * n)[::-1], 3]          # every column, out of order, one twice
    ref = _pin_channels(arm, q)[..., cols]
    got = np.zeros_like(ref)
    seen = np.zeros(cols.size, int)
    for M, idx, V in link_channels(arm, cols, q):
        assert np.all(cols[idx] // 10 == M - 1) and V.shape[1:3] == (1 + M + M * (M + 1) // 2, M)
        seen[idx] += 1
        for ci, c in enumerate(idx):
            got[:, :1 + M, :M, c] = V[:, :1 + M, :, ci]
            for k, (a, e) in enumerate(zip(*np.triu_indices(M))):
                got[:, 1 + n + n * a + e, :M, c] = got[:, 1 + n + n * e + a, :M, c] = \
                    V[:, 1 + M + k, :, ci]
    assert np.all(seen == 1)
    scale = np.abs(ref).max(axis=(0, 1, 2))            # per column; the overall one where 0
    assert (scale > 0).sum() > cols.size // 2
    scale[scale == 0] = np.abs(ref).max()
    assert np.all(np.abs(got - ref) <= 1e-12 * scale)


def test_link_channels_do_not_depend_on_the_batch():
    """A position's channels are the same bit for bit alone or among others, and the shapes
    are refused."""
    arm = mixed_chain(7, seed=3)
    q = states(arm, 9, 2)[0]
    cols = np.arange(10 * arm.n)
    whole = link_channels(arm, cols, q)
    alone = link_channels(arm, cols, q[4:5])
    for (M, idx, V), (M1, idx1, V1) in zip(whole, alone):
        assert M == M1 and np.array_equal(idx, idx1)
        assert np.array_equal(V[4:5], V1)
    assert link_channels(arm, [], q) == ()
    with pytest.raises(ValueError, match="shape"):
        link_channels(arm, cols, q[:, :3])
    with pytest.raises(ValueError, match="columns"):
        link_channels(arm, [70], q)
