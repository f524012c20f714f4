"""The excitation trajectory (plan --excitation): within the limits on a fine grid of its own
formula, at rest at both ends, far better conditioned than random Fourier trajectories with
the same harmonics and limits, and its objective's regressor spans Pinocchio's."""

import json
import math
import pickle
import re
import subprocess
import sys

import numpy as np
import pinocchio as pin
import pytest
import scipy.optimize
from conftest import built_once
from scipy.optimize import check_grad, minimize
from threadpoolctl import threadpool_limits

from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.model.limits import acceleration_limits
from gd_analyze.model.robots import load_robot
from gd_analyze.symbolic.drive_regressor import identification_columns, identification_regressor
from gd_analyze.trajectory import excitation as ex_module
from gd_analyze.trajectory.excitation import (
    FourierSeries,
    excitation_condition,
    excitation_timing,
    limit_bounds,
    plan_excitation,
    random_excitation,
    scaled_condition,
)
from gd_analyze.trajectory.planning import default_motion_range
from gd_analyze.trajectory.trajectory import read_trajectory


def _log_condition_and_gradient(x, robot, columns, basis, coulomb_scale=None, power=None):
    """The excitation's smooth log condition number at x and its gradient with respect to x
    (``_log_condition`` returns the gradient as a function, called where the optimiser needs
    it)."""
    value, gradient = ex_module._log_condition(x, robot, columns, basis, coulomb_scale, power)
    return value, gradient()


def _formula(series, t):
    """q, qd, qdd of Swevers et al. (1997), Eq. (9), written out term by term (not the
    module's matrix form)."""
    t = np.asarray(t, float)
    n, K = series.a.shape
    q = np.tile(series.q0, (t.size, 1)).astype(float)
    qd = np.zeros((t.size, n))
    qdd = np.zeros((t.size, n))
    for ell in range(1, K + 1):         # each joint's terms summed in the order of ell
        w = series.wf * ell
        sin, cos = np.sin(w * t), np.cos(w * t)
        for i in range(n):
            a, b = series.a[i, ell - 1], series.b[i, ell - 1]
            q[:, i] += a / w * sin - b / w * cos
            qd[:, i] += a * cos + b * sin
            qdd[:, i] += -a * w * sin + b * w * cos
    return q, qd, qdd


def _limits(robot):
    lo, hi = default_motion_range(robot)
    return lo, hi, np.asarray(robot.qd_max, float), acceleration_limits(robot)[0]


def _assert_within(robot, series, duration, points=200_001):
    """The formula on a fine grid and at random times stays inside every limit."""
    lo, hi, qd_max, qdd_max = _limits(robot)
    t = np.concatenate([np.linspace(0, duration, points),
                        np.random.default_rng(0).uniform(0, duration, 20_000)])
    q, qd, qdd = _formula(series, t)
    for arr in (q, qd, qdd):
        assert np.isfinite(arr).all()
    assert (q >= lo).all() and (q <= hi).all()
    assert (np.abs(qd) <= qd_max).all()
    assert (np.abs(qdd) <= qdd_max).all()
    return q, qd, qdd


@pytest.fixture(scope="module")
def planned():
    """The default excitation of a built-in robot (the PUMA 560, the Panda and the UR5: URDFs,
    default acceleration limits), by name: ``planned(name)`` is ``(robot, excitation)``.

    Each robot's is planned once a session, by whichever xdist worker asks first, and read
    back (pickled) by the others (:func:`conftest.built_once`: a folder of its own per robot,
    the plan's settings the defaults). Shared: tests must not modify it.
    """
    stored = {}

    def build(name, folder):
        (folder / "excitation.pickle").write_bytes(pickle.dumps(plan_excitation(
            load_robot(name))))

    def get(name):
        if name not in stored:
            folder = built_once(f"excitation-{name}-defaults", lambda f: build(name, f))
            stored[name] = (load_robot(name),
                            pickle.loads((folder / "excitation.pickle").read_bytes()))
        return stored[name]
    return get


def _random_conditions(robot, ex):
    """The scaled condition numbers, on 400 samples of a period, of 8 random Fourier
    trajectories with the excitation's harmonics and base frequency, each joint scaled to the
    same limits (seeds other than the optimiser's starts), each checked inside the limits."""
    cols = identification_columns(robot)
    randoms = []
    for seed in range(1000, 1008):
        series = random_excitation(robot, ex.series.harmonics, ex.series.wf, seed)
        _assert_within(robot, series, series.period, points=20_001)
        randoms.append(excitation_condition(robot, cols, series, samples=400))
    return np.array(randoms)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["puma560", "panda", "ur5"])
def test_excitation_within_the_limits_and_at_rest_at_both_ends(planned, name):
    robot, ex = planned(name)
    traj = ex.trajectory
    T = traj.t[-1]
    assert T == pytest.approx(10.0) and traj.n_setpoints == 1001
    q, qd, qdd = _assert_within(robot, ex.series, T)
    # at rest at both ends, and where it started
    q_ends, qd_ends, qdd_ends = _formula(ex.series, [0.0, T])
    assert np.abs(qd_ends).max() <= 1e-12 * robot.qd_max.max()
    assert np.abs(qdd_ends).max() <= 1e-12 * np.abs(qdd).max()
    assert np.abs(q_ends[0] - q_ends[1]).max() <= 1e-12
    # the written set points are the formula's
    written = _formula(ex.series, traj.t)
    np.testing.assert_allclose(traj.q, written[0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(traj.qd, written[1], rtol=0, atol=1e-12)
    np.testing.assert_allclose(traj.qdd, written[2], rtol=0, atol=1e-12)
    # it uses its room: some limit is nearly reached on every joint
    lo, hi, qd_max, qdd_max = _limits(robot)
    use = np.maximum.reduce([np.abs(qd).max(0) / qd_max, np.abs(qdd).max(0) / qdd_max,
                             (q.max(0) - q.min(0)) / (hi - lo)])
    assert use.min() > 0.5


@pytest.mark.slow
@pytest.mark.parametrize("name", ["puma560", "panda"])
def test_condition_number_at_least_3x_below_random_fourier_trajectories(planned, name):
    """Against 8 random Fourier trajectories with the same harmonics and base frequency, each
    joint scaled to the same limits (seeds other than the optimiser's starts). Measured
    (analysis/excitation_conditions.py, the defaults): the PUMA's are 2.97 to 22 times worse
    (median 12.3; 12.6 at 10.97, analysis/excitation_cost.py), the Panda's 2.8 to 4.2 times
    (median 3.5); the condition numbers are taken
    on 400 samples of a period, not the objective's 100."""
    robot, ex = planned(name)
    ours = excitation_condition(robot, identification_columns(robot), ex.series, samples=400)
    assert math.isfinite(ours)
    randoms = _random_conditions(robot, ex)
    # 3x below a typical random trajectory (the median), 2x below the best of the eight
    assert ours * 3 <= np.median(randoms) and ours * 2 <= min(randoms), (ours, randoms)


@pytest.mark.slow
def test_ur5_condition_number_below_random_fourier_trajectories(planned):
    """The UR5's random Fourier trajectories are already well conditioned (median 10.2), and
    what bounds its optimum is each joint's viscous and Coulomb pair and the parallel axes'
    ZZ2..ZZ4 columns: measured (analysis/excitation_cost.py) 4.05 with the defaults, 2.5x
    below the median (4.00 with the gradient's former forward differences), where the stages
    at P = 16 alone reached 4.52 (2.3x); 6 starts of at most 80 iterations per stage reach
    4.05."""
    robot, ex = planned("ur5")
    ours = excitation_condition(robot, identification_columns(robot), ex.series, samples=400)
    randoms = _random_conditions(robot, ex)
    assert math.isfinite(ours)
    assert ours * 2.4 <= np.median(randoms) and ours * 1.5 <= min(randoms), (ours, randoms)


@pytest.fixture
def one_blas_thread():
    """numpy's LAPACK calls on one thread for the test: its SVDs are of a few hundred rows, and
    threaded they take seconds on a busy machine."""
    with threadpool_limits(1, "blas"):
        yield


@pytest.mark.slow
@pytest.mark.parametrize("name", ["puma560", "panda", "ur5"])
def test_the_objective_is_the_scaled_condition_of_a_regressor_spanning_pinocchios(
        name, one_blas_thread):
    """The objective's regressor (rigid columns, drive columns) spans what Pinocchio's
    computeJointTorqueRegressor and the drive columns span on the trajectory's samples, the
    objective is log cond of it with unit-norm columns (numpy's SVD), and its gradient is
    right (scipy's check_grad)."""
    robot = load_robot(name)
    cols = identification_columns(robot)
    series = random_excitation(robot, 4, 2 * math.pi / 8, 5)
    basis = ex_module._Basis(4, series.wf, ex_module._middles(series.period, 60))
    x = ex_module._variables(series)
    value, grad = _log_condition_and_gradient(x, robot, cols, basis)
    q, qd, qdd = _formula(series, ex_module._middles(series.period, 60))
    model = pinocchio_model(robot)
    data = model.createData()
    Wp = np.array([pin.computeJointTorqueRegressor(model, data, a, b, c)
                   for a, b, c in zip(q, qd, qdd)])
    n = robot.n
    drives = np.zeros((q.shape[0], n, 4 * n))
    for i in range(n):
        drives[:, i, [i, n + i, 2 * n + i, 3 * n + i]] = np.stack(
            [qdd[:, i], qd[:, i], np.sign(qd[:, i]), np.ones(q.shape[0])], -1)
    ref = np.concatenate([Wp, drives], 2).reshape(-1, 14 * n)
    Y = ex_module.identification_regressor(robot, q, qd, qdd, cols).reshape(-1, cols.count)

    def rank(W):
        """Rank with unit-norm columns, after dropping rounding-noise columns (a zero column
        of Pinocchio's regressor computed as 1e-17 would otherwise be scaled up to noise)."""
        norms = np.linalg.norm(W, axis=0)
        W = W[:, norms > 1e-10 * norms.max()]
        s = np.linalg.svd(W / np.linalg.norm(W, axis=0), compute_uv=False)
        return int((s > 1e-9 * s[0]).sum())

    assert rank(Y) == cols.count == rank(ref) == rank(np.hstack([Y, ref]))
    Ws = Y / np.linalg.norm(Y, axis=0)
    s = np.linalg.svd(Ws, compute_uv=False)
    smooth = (math.log(((s / s[0]) ** ex_module.SMOOTH_POWER).sum()) + math.log(((s[-1] / s) ** ex_module.SMOOTH_POWER).sum())) / ex_module.SMOOTH_POWER
    assert value == pytest.approx(math.log(s[0] / s[-1]) + smooth, rel=1e-9)
    assert s[0] / s[-1] == pytest.approx(scaled_condition(Y), rel=1e-9)

    t = ex_module._middles(series.period, 60)

    def objective(z, power=ex_module.SMOOTH_POWER, v=None):
        """The objective at z from its definition, computed afresh (the value alone, not the
        module's gradient pass over 3 n + 1 shifted copies of the states): the smooth log
        condition with exponent ``power`` of the unit-norm columns of the identification
        regressor on the formula's states, the Coulomb columns tanh(qd_j / v_j) with ``v``."""
        zq, zqd, zqdd = _formula(basis.series(z, n), t)
        Yz = ex_module.identification_regressor(robot, zq, zqd, zqdd, cols)
        if v is not None:
            for j in range(n):
                if f"coulomb_{j + 1}" in cols.names():
                    Yz[:, j, cols.names().index(f"coulomb_{j + 1}")] = np.tanh(zqd[:, j] / v[j])
        Wz = Yz.reshape(-1, cols.count)
        sz = np.linalg.svd(Wz / np.linalg.norm(Wz, axis=0), compute_uv=False)
        return math.log(sz[0] / sz[-1]) + (math.log(((sz / sz[0]) ** power).sum()) + math.log(
            ((sz[-1] / sz) ** power).sum())) / power

    def g(z):
        return _log_condition_and_gradient(z, robot, cols, basis)[1]

    assert objective(x) == pytest.approx(value, rel=1e-9)
    err = check_grad(objective, g, x, epsilon=1e-6)
    assert err <= 1e-3 * np.linalg.norm(grad)

    # the first stages' P = 2: the A-optimality criterion, (1/2) log p + (1/2) log of the
    # trace of the inverse information matrix of the unit-norm columns
    value2, grad2 = _log_condition_and_gradient(x, robot, cols, basis, power=2)
    assert value2 == pytest.approx(0.5 * math.log(cols.count) + 0.5 * math.log(
        np.trace(np.linalg.inv(Ws.T @ Ws))), rel=1e-9)
    assert objective(x, power=2) == pytest.approx(value2, rel=1e-9)
    err = check_grad(lambda z: objective(z, power=2),
                     lambda z: _log_condition_and_gradient(z, robot, cols, basis,
                                                                      power=2)[1],
                     x, epsilon=1e-6)
    assert err <= 1e-3 * np.linalg.norm(grad2)

    # the optimiser's stages: the Coulomb columns replaced by tanh(qd_j / v_j), whose
    # gradient is not zero (sgn's is)
    v = 0.1 * np.asarray(robot.qd_max, float)
    Yt = Y.reshape(q.shape[0], n, cols.count).copy()
    names = cols.names()
    for j in range(n):
        if f"coulomb_{j + 1}" in names:
            Yt[:, j, names.index(f"coulomb_{j + 1}")] = np.tanh(qd[:, j] / v[j])
    st = np.linalg.svd(Yt.reshape(-1, cols.count) / np.linalg.norm(
        Yt.reshape(-1, cols.count), axis=0), compute_uv=False)
    P = ex_module.SMOOTH_POWER
    value_t, grad_t = _log_condition_and_gradient(x, robot, cols, basis, v)
    assert value_t == pytest.approx(math.log(st[0] / st[-1]) + (math.log(
        ((st / st[0]) ** P).sum()) + math.log(((st[-1] / st) ** P).sum())) / P, rel=1e-9)
    assert value_t != pytest.approx(value, rel=1e-6)
    assert objective(x, v=v) == pytest.approx(value_t, rel=1e-9)
    err = check_grad(lambda z: objective(z, v=v),
                     lambda z: _log_condition_and_gradient(z, robot, cols, basis, v)[1],
                     x, epsilon=1e-6)
    assert np.isfinite(grad_t).all() and err <= 1e-3 * np.linalg.norm(grad_t)


def test_limit_bounds_bound_the_formula_and_can_be_exceeded():
    rng = np.random.default_rng(2)
    series = FourierSeries(q0=np.array([0.3, -1.0]), a=rng.normal(size=(2, 4)),
                           b=rng.normal(size=(2, 4)), wf=1.3)
    bounds = limit_bounds(series, points=64)        # coarse: the widening matters
    q, qd, qdd = _formula(series, np.linspace(0, series.period, 100_001))
    assert (q.min(0) >= bounds.q_low).all() and (q.max(0) <= bounds.q_high).all()
    assert (np.abs(qd).max(0) <= bounds.qd_peak).all()
    assert (np.abs(qdd).max(0) <= bounds.qdd_peak).all()
    # a bound is not within the true extremes: the widening makes one strictly wider
    assert ((bounds.q_low < q.min(0)).any() or (bounds.q_high > q.max(0)).any()
            or (bounds.qd_peak > np.abs(qd).max(0)).any()
            or (bounds.qdd_peak > np.abs(qdd).max(0)).any())


class _Quadratic:
    """0.5 ||z - target||^2: strictly convex, one minimiser under linear constraints."""

    def __init__(self, target):
        self.target = target

    def value(self, z):
        return 0.5 * float(np.sum((z - self.target) ** 2))

    def gradient(self, z):
        return z - self.target


def test_the_optimiser_given_the_rows_near_their_bound_finds_slsqps_minimum_under_all(
        monkeypatch):
    """On the dense grid's limits of two joints, the minimum of a convex function outside
    them found with only the rows near their bound given to SLSQP (started again as rows are
    violated) is SLSQP's with every row, and within every row."""
    runs = []

    def counted(*args, constraints=(), **kwargs):     # the rows given to each run, counted
        try:                                            # also where StopIteration passes on
            return minimize(*args, constraints=constraints, **kwargs)
        finally:
            runs.append((sum(len(k["fun"](args[1])) for k in constraints),))

    monkeypatch.setattr(scipy.optimize, "minimize", counted)
    K, wf = 3, 2 * math.pi / 10
    lo, hi = np.array([-1.0, 0.2]), np.array([1.5, 0.9])
    qd, qdd = np.array([0.8, 0.3]), np.array([2.0, 0.5])
    basis = ex_module._Basis(K, wf, np.arange(60) * (2 * math.pi / wf / 60))
    A, c = ex_module._constraints(basis, 2, lo, hi, qd, qdd)
    room = np.concatenate([np.repeat([hi[j] - lo[j]] * 2 + [2 * qd[j]] * 2 + [2 * qdd[j]] * 2,
                                     60) for j in range(2)])
    z0 = np.zeros(2 * basis.size)
    z0[[0, basis.size]] = (lo + hi) / 2                 # at rest in the middle: feasible
    for seed in range(3):
        target = np.random.default_rng(seed).normal(scale=3.0, size=z0.size)
        fun = _Quadratic(target)
        runs.clear()
        ours = ex_module._constrained_minimum(fun, z0, A, c, room, 200)
        full = minimize(fun.value, z0, jac=fun.gradient, method="SLSQP",
                        constraints=[{"type": "ineq", "fun": lambda z: c - A @ z,
                                      "jac": lambda z: -A}],
                        options={"maxiter": 200, "ftol": 1e-12})
        assert full.success and ours.success
        assert runs[-1][0] < c.size and len(runs) >= 2     # rows left out, a run stopped
        assert (c - A @ ours.x >= -1e-9 * room).all()
        assert (c - A @ full.x >= -1e-9 * room).all()
        np.testing.assert_allclose(ours.x, full.x, atol=1e-5)


def test_the_objective_keeps_values_and_gradients_by_point():
    """The optimiser's objective asked again at earlier points (as a run started again asks)
    gives the values and gradients of :func:`_log_condition` evaluated afresh there."""
    robot = load_robot("two-link")
    cols = identification_columns(robot)
    series = random_excitation(robot, 3, 2 * math.pi / 6, 4)
    basis = ex_module._Basis(3, series.wf, ex_module._middles(series.period, 30))
    D = np.linspace(0.5, 2.0, robot.n * basis.size)
    z = [ex_module._variables(random_excitation(robot, 3, series.wf, s)) / D for s in (4, 5)]
    fun = ex_module._ScaledObjective(D, robot, cols, basis, None)
    asked = [fun.value(z[0]), fun.value(z[1]), fun.gradient(z[0]), fun.value(z[0]),
             fun.gradient(z[1]), fun.gradient(z[0]), fun.value(z[1])]
    fresh = [_log_condition_and_gradient(zk * D, robot, cols, basis) for zk in z]
    for got, (k, part) in zip(asked, [(0, 0), (1, 0), (0, 1), (0, 0), (1, 1), (0, 1),
                                      (1, 0)]):
        np.testing.assert_allclose(got, fresh[k][0] if part == 0 else fresh[k][1] * D,
                                   rtol=1e-12, atol=0)


def test_random_excitation_starts_at_rest_and_fits_its_limits():
    robot = load_robot("puma560")
    series = random_excitation(robot, 5, 2 * math.pi / 10, 7)
    _, qd0, qdd0 = _formula(series, [0.0])
    assert np.abs(qd0).max() <= 1e-12 and np.abs(qdd0).max() <= 1e-12
    q, qd, qdd = _assert_within(robot, series, series.period, points=20_001)
    lo, hi, qd_max, qdd_max = _limits(robot)
    # scaled to touch a (margined) limit on every joint
    use = np.maximum.reduce([np.abs(qd).max(0) / qd_max, np.abs(qdd).max(0) / qdd_max,
                             np.maximum(q.max(0) - (lo + hi) / 2, (lo + hi) / 2 - q.min(0))
                             / ((hi - lo) / 2)])
    assert (use > 0.9).all() and (use < 0.98).all()
    with pytest.raises(ValueError, match="at least 2 harmonics"):
        random_excitation(robot, 1)


@pytest.mark.parametrize("duration, wf, expected", [
    (None, None, (10.0, 2 * math.pi / 10, 1)),
    (4.0, None, (4.0, 2 * math.pi / 4, 1)),
    (None, 2.0, (math.pi, 2.0, 1)),
    (3 * math.pi, 2.0, (3 * math.pi, 2.0, 3)),
])
def test_timing(duration, wf, expected):
    T, w, m = excitation_timing(duration, wf)
    assert (T, m) == pytest.approx(expected[::2]) and w == pytest.approx(expected[1])


@pytest.mark.parametrize("duration, wf, message", [
    (5.0, 1.0, "whole number"), (-1.0, None, "positive"), (None, float("inf"), "positive"),
    (1.0, 1.0, "whole number"),
])
def test_timing_refuses(duration, wf, message):
    with pytest.raises(ValueError, match=message):
        excitation_timing(duration, wf)


@pytest.mark.parametrize("name, K, least", [("two-link", 5, 12), ("puma560", 2, 11)])
def test_the_fewest_set_points_resolve_the_highest_harmonic_and_every_column(name, K, least):
    """N = least - 1 is refused. Below 2 K + 2, N - 1 = 2 K set points per period find
    sin(K w_f t) = 0 at every one (the highest harmonic aliases); below ceil(p / n) + 1, the
    regressor stacked over the N - 1 states (the last set point repeats the first's) has rank
    < p, counted by numpy on a random series. At the least, full rank."""
    robot = load_robot(name)
    columns = identification_columns(robot)
    series = random_excitation(robot, K, 2 * math.pi / 10, 3)

    def rank(N):
        q, qd, qdd = series.evaluate(np.linspace(0, 10.0, N)[:-1])[:3]
        Y = identification_regressor(robot, q, qd, qdd, columns)
        return np.linalg.matrix_rank(Y.reshape((N - 1) * robot.n, -1))

    t = np.linspace(0, series.period, 2 * K + 1)
    assert np.abs(np.sin(K * series.wf * t)).max() < 1e-12
    harmonic_binds = least == 2 * K + 2
    assert (rank(least - 1) == columns.count) == harmonic_binds
    assert rank(least) == columns.count
    with pytest.raises(ValueError, match=f"{least - 1} set points .*: {least} to 10"):
        plan_excitation(robot, harmonics=K, n_setpoints=least - 1, starts=1, maxiter=1)
    assert plan_excitation(robot, duration=0.05, harmonics=K, starts=1,
                           maxiter=1).n_setpoints == least     # the default raised to it


#: SLSQP iterations per start and stage of the command's optimiser in
#: :func:`test_cli_writes_the_excitation_and_its_provenance`: what the command writes does not
#: depend on how far the optimiser got (the optimum's quality is tested above, on the defaults).
FEW_ITERATIONS = 2


def test_cli_writes_the_excitation_and_its_provenance(tmp_path, monkeypatch, capsys):
    """The command's options reach the optimiser, and the file and its provenance hold the
    series it found (its formula, the condition numbers of the optimum and of the random
    starts, recomputed here); the optimiser stops after :data:`FEW_ITERATIONS`."""
    from gd_analyze.cli import commands, main

    def few_iterations(*args, **kwargs):
        return plan_excitation(*args, **kwargs, maxiter=FEW_ITERATIONS)

    monkeypatch.setattr(commands, "plan_excitation", few_iterations)
    monkeypatch.chdir(tmp_path)
    code = main(["plan", "puma560", "--excitation", "-o", "ex.csv", "--harmonics", "3",
                 "--duration", "12", "--base-frequency", str(math.pi / 3), "--setpoints", "241"])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert out == ""
    assert err.startswith("wrote ex.csv: 241 set points over 12.0000 s (excitation:")
    traj = read_trajectory(tmp_path / "ex.csv", 6)
    record = json.loads((tmp_path / "ex.provenance.json").read_text())
    ex = record["excitation"]
    assert ex["harmonics"] == 3 and ex["periods"] == 2
    series = FourierSeries(q0=np.array(ex["q0"]), a=np.array(ex["a"]), b=np.array(ex["b"]),
                           wf=ex["base_frequency_rad_s"])
    robot = load_robot("puma560")
    _assert_within(robot, series, 12.0)
    q, qd, qdd = _formula(series, traj.t)
    np.testing.assert_allclose(traj.q, q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(traj.qdd, qdd, rtol=0, atol=1e-12)
    assert np.abs(traj.qd[[0, -1]]).max() <= 1e-12
    cond = excitation_condition(robot, identification_columns(robot), series)
    assert ex["scaled_condition_number"] == pytest.approx(cond, rel=1e-9)
    assert ex["scaled_condition_number"] < min(ex["random_starts_scaled_condition_numbers"])
    assert ex["drive_columns_regrouped"] == ["armature_1", "armature_2"]
    assert record["robot_sha256"] == robot.sha256 and record["setpoints"] == 241


@pytest.mark.parametrize("N, size", [(12, 1), (1001, 300), (1001, 1001)])
def test_pieces_are_the_whole_excitation(N, size):
    """Sampled piece by piece, the excitation gives the set points of the whole trajectory:
    exactly numpy.linspace's times, and the series' formula there (to rounding: a matrix
    product of one row may round otherwise than one of many)."""
    ex = plan_excitation(load_robot("two-link"), starts=1, maxiter=1, n_setpoints=N)
    pieces = list(ex.chunks(size))
    assert max(p.n_setpoints for p in pieces) <= size and sum(p.n_setpoints for p in pieces) == N
    whole = ex.trajectory
    t = np.concatenate([p.t for p in pieces])
    assert np.array_equal(t, np.linspace(0.0, ex.duration, N)) and np.array_equal(t, whole.t)
    for k, name in enumerate(("q", "qd", "qdd")):
        got = np.concatenate([getattr(p, name) for p in pieces])
        np.testing.assert_allclose(got, getattr(whole, name), rtol=0, atol=1e-12)
        np.testing.assert_allclose(got, _formula(ex.series, t)[k], rtol=0, atol=1e-12)
    assert {p.derivatives for p in pieces} == {"fourier"} and pieces[0].source == ex.source


def test_cli_writes_the_excitation_piece_by_piece(tmp_path, monkeypatch, capsys):
    """The command writes the set points a piece of at most CHUNK_SETPOINTS at a time (its
    memory does not grow with N), and the file is the series' formula at every set point."""
    from gd_analyze.cli import commands, main
    from gd_analyze.trajectory import planning

    monkeypatch.setattr(commands, "plan_excitation", lambda *args, **kwargs: plan_excitation(
        *args, **kwargs, starts=1, maxiter=FEW_ITERATIONS))
    monkeypatch.setattr(planning, "CHUNK_SETPOINTS", 100)
    sizes, write = [], commands.write_trajectory_chunks
    monkeypatch.setattr(commands, "write_trajectory_chunks", lambda pieces, n, path: write(
        (sizes.append(p.n_setpoints) or p for p in pieces), n, path))
    monkeypatch.chdir(tmp_path)
    assert main(["plan", "two-link", "--excitation", "-o", "ex.csv", "--setpoints", "1001"]) == 0
    said = capsys.readouterr().err
    assert said.startswith("wrote ex.csv: 1001 set points over 10.0000 s")
    # the condition number is the series' on its samples, not the set points' (2 set points,
    # both at rest, said 2.872 of 13 columns): the line says where it was taken
    assert re.search(r"; scaled condition number \S+ of 13 columns on 100 samples of a period "
                     r"\(random starts: ", said), said
    assert sizes == [100] * 10 + [1]
    ex = json.loads((tmp_path / "ex.provenance.json").read_text())["excitation"]
    series = FourierSeries(q0=np.array(ex["q0"]), a=np.array(ex["a"]), b=np.array(ex["b"]),
                           wf=ex["base_frequency_rad_s"])
    traj = read_trajectory(tmp_path / "ex.csv", 2)
    assert np.array_equal(traj.t, np.linspace(0.0, 10.0, 1001))
    for got, want in zip((traj.q, traj.qd, traj.qdd), _formula(series, traj.t)):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)


@pytest.mark.parametrize("args, column", [
    (["--excitation", "--start", "0,0,0,0,0,0"], "--start"),
    (["--excitation", "--ignore-limits"], "--ignore-limits"),
    (["--excitation", "--duration", "5", "--base-frequency", "1"], "--duration"),
    (["--harmonics", "3"], "--harmonics"),
    (["--seed", "3"], "--seed"),
    (["--excitation", "--harmonics", "1"], "--harmonics"),
    (["--excitation", "--qdd-max", "1,2"], "--qdd-max"),
    (["--excitation", "--setpoints", "2"], "--setpoints"),
])
def test_cli_refuses_bad_options_in_one_line(tmp_path, monkeypatch, capsys, args, column):
    """In the test's process (the console script's own path is tests/test_one_code_path.py's):
    a warning, which a child would print as a line of its own, counts as a line."""
    import warnings

    from gd_analyze.cli import main

    monkeypatch.chdir(tmp_path)
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        code = main(["plan", "puma560", "-o", "x.csv", *args])
    err = capsys.readouterr().err
    assert code == 2
    lines = err.strip().splitlines() + [str(w.message) for w in seen]
    assert len(lines) == 1 and column in lines[0] and "Traceback" not in err
    assert not (tmp_path / "x.csv").exists()


def test_the_planning_runs_every_blas_library_on_one_thread():
    """In a fresh interpreter (SciPy's optimiser not yet loaded), every BLAS library seen
    during the optimisation runs one thread: SciPy's own, which SLSQP calls, included (a limit
    set before a library is loaded does not reach it, and its second thread spun)."""
    code = """
import os
from threadpoolctl import threadpool_info
from gd_analyze.model.robots import load_robot
from gd_analyze.trajectory import excitation

seen = []
optimised = excitation._optimised

def spy(*args, **kwargs):
    import scipy.optimize
    seen.extend((i["filepath"], i["num_threads"]) for i in threadpool_info()
                if i["user_api"] == "blas")
    return optimised(*args, **kwargs)

excitation._optimised = spy
excitation.plan_excitation(load_robot("puma560"), starts=1, maxiter=1)
print(len(seen), max(n for _, n in seen), os.cpu_count())
"""
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=600)
    assert run.returncode == 0, run.stderr
    libraries, threads, cpus = map(int, run.stdout.split())
    assert libraries >= 2 and threads == 1, run.stdout


def test_a_joint_without_a_velocity_limit_is_refused_as_plan_refuses_it():
    """An excitation keeps to the limits a plan keeps to: a joint without a velocity limit is
    refused by planning's own check, an InputError naming the joint and the robot file's key
    that gives one, before any optimisation (the random start and the optimised plan alike)."""
    import dataclasses

    from gd_analyze.errors import InputError

    robot = load_robot("puma560")
    free = dataclasses.replace(robot, qd_max=np.where(np.arange(robot.n) == 1, np.nan,
                                                      robot.qd_max))
    for make in (random_excitation, plan_excitation):
        with pytest.raises(InputError, match=r"^puma560: joint 2 has no velocity limit: planning "
                                             r"needs one \(qd_max_deg\)$"):
            make(free)
