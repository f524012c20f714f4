"""Excitation: a finite Fourier series trajectory optimised for identification.

:func:`plan_excitation` makes the ``gd-analyze plan --excitation`` trajectory of Swevers,
Ganseman, Tukel, De Schutter & Van Brussel, "Optimal robot excitation and identification",
IEEE Trans. Robot. Autom. 13(5), 1997, Eq. (9): per joint i, K harmonics of the base
frequency w_f::

    q_i(t) = q_i0 + sum_{l=1..K} a_il / (w_f l) sin(w_f l t) - b_il / (w_f l) cos(w_f l t)
    qd_i(t) = sum_l a_il cos(w_f l t) + b_il sin(w_f l t)
    qdd_i(t) = sum_l w_f l (b_il cos(w_f l t) - a_il sin(w_f l t))

The trajectory lasts a whole number of periods 2 pi / w_f, so it ends where and as it starts.
It starts and ends at rest because the coefficients are constrained: qd_i(0) = sum_l a_il = 0
and qdd_i(0) = w_f sum_l l b_il = 0, i.e. a_i1 = -sum_{l>=2} a_il and b_i1 = -sum_{l>=2} l b_il;
the optimiser varies q_i0 and the other 2 (K - 1) coefficients (:class:`FourierSeries`).

The coefficients minimise the condition number of the column-scaled identification regressor
(the base regressor with the drive columns, :mod:`gd_analyze.symbolic.drive_regressor`)
stacked over one period, with SciPy's SLSQP from several starts, under the position, velocity
and acceleration limits on a dense grid (they are linear in the coefficients; SLSQP is given
those near their bound, every iterate checked against all of them), in stages
(:data:`STAGES`): the Coulomb columns first replaced by smooth surrogates, then as they are,
and the objective first the A-optimality criterion, then ever closer to the log condition
number. The result is
then bounded on a fine grid (:func:`limit_bounds`: the grid's extremes widened by half a step
times a bound of the derivative), and its oscillation about q_0 shrunk if a bound exceeds a
limit.
"""

from __future__ import annotations

import contextlib
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..dynamics.base_parameters import one_blas_thread
from ..dynamics.regressor_kernels import regressor_columns_pullback
from ..model.limits import acceleration_limits
from ..symbolic.drive_regressor import (
    DRIVE_COLUMNS,
    IdentificationColumns,
    drive_regressor,
    identification_columns,
    identification_regressor,
)
from .planning import SampledMotion, check_velocity_limits, default_motion_range
from .trajectory import Trajectory

if TYPE_CHECKING:
    from ..model.robot import Robot

__all__ = ["DEFAULT_HARMONICS", "DEFAULT_DURATION", "DEFAULT_SAMPLE_PERIOD", "LIMIT_MARGIN",
           "FourierSeries", "LimitBounds", "Excitation", "limit_bounds", "scaled_condition",
           "excitation_condition", "random_excitation", "plan_excitation", "excitation_timing"]

#: Harmonics K of the default excitation (Swevers et al. 1997 use 5).
DEFAULT_HARMONICS = 5
#: Duration of the default excitation [s]: one period of w_f = 2 pi / 10 rad/s (0.1 Hz, as in
#: Swevers et al. 1997).
DEFAULT_DURATION = 10.0
#: Time between the set points of the written trajectory by default [s] (100 Hz).
DEFAULT_SAMPLE_PERIOD = 0.01
#: Fraction of each limit (of the position range) kept free in the optimisation, so that the
#: final bound between the grid's points stays inside the limits.
LIMIT_MARGIN = 0.03
#: Regressor samples per period in the objective, and constraint points per period per
#: harmonic.
OBJECTIVE_SAMPLES = 100
CONSTRAINT_POINTS_PER_HARMONIC = 20
#: Points per period per harmonic of the final bound (:func:`limit_bounds`).
BOUND_POINTS_PER_HARMONIC = 400
#: The optimisation's stages, each (v, P): the Coulomb columns sgn(qd_j) replaced by
#: tanh(qd_j / v_j) with v_j = v x the joint's velocity limit (None: sgn itself), and the
#: exponent P of the smooth objective (:func:`_log_condition`). The sampled
#: sgn(qd) is piecewise constant in the coefficients (its gradient is zero): the surrogates let
#: the optimiser see how the time spent at each speed decorrelates the Coulomb column from the
#: viscous one (mean |qd| / rms qd), the pair that bounds the condition number of an arm whose
#: other columns are well excited (the UR5's). P = 2 first: with unit-norm columns sum
#: sigma_i^2 is the number of columns, so the objective is then the trace of the inverse of
#: the information matrix (A-optimality), smoother than the condition number and with fewer
#: poor local minima; P then grows towards log cond (P -> infinity).
STAGES = ((0.1, 2.0), (0.1, 8.0), (0.03, 16.0), (None, 16.0), (None, 64.0))


@dataclass(frozen=True, eq=False)
class FourierSeries:
    """A finite Fourier series trajectory (Swevers et al. 1997, Eq. (9)).

    Attributes
    ----------
    q0 : ndarray, shape (n,)
        Offsets, the mean positions [rad or m].
    a, b : ndarray, shape (n, K)
        Coefficients of harmonic l = 1..K [rad/s or m/s].
    wf : float
        Base frequency w_f [rad/s].
    """

    q0: np.ndarray
    a: np.ndarray
    b: np.ndarray
    wf: float

    @property
    def harmonics(self) -> int:
        """int: the number of harmonics K."""
        return int(self.a.shape[1])

    @property
    def period(self) -> float:
        """float: 2 pi / w_f [s]."""
        return 2 * math.pi / self.wf

    def evaluate(self, t: np.ndarray) -> tuple:
        """Positions, velocities and accelerations at given times.

        Parameters
        ----------
        t : array_like, shape (N,)
            Times [s].

        Returns
        -------
        q, qd, qdd : ndarray, shape (N, n)
            [rad, rad/s, rad/s^2; m... for a prismatic joint].
        """
        t = np.asarray(t, float).reshape(-1)
        w = self.wf * np.arange(1, self.harmonics + 1)          # (K,)
        s, c = np.sin(np.outer(t, w)), np.cos(np.outer(t, w))    # (N, K)
        a, b = self.a.T, self.b.T                                  # (K, n)
        return (self.q0 + s @ (a / w[:, None]) - c @ (b / w[:, None]),
                c @ a + s @ b,
                c @ (w[:, None] * b) - s @ (w[:, None] * a))

    def derivative_bounds(self) -> np.ndarray:
        """Bounds of |qd|, |qdd| and |qddd| over all times, from the amplitudes.

        Returns
        -------
        ndarray, shape (3, n)
            sum_l (w_f l)^d sqrt(a_il^2 + b_il^2) for d = 0, 1, 2 [rad/s, rad/s^2, rad/s^3]:
            a cos + b sin never exceeds sqrt(a^2 + b^2).
        """
        w = self.wf * np.arange(1, self.harmonics + 1)
        amp = np.hypot(self.a, self.b)                              # (n, K)
        return np.stack([amp.sum(1), (amp * w).sum(1), (amp * w**2).sum(1)])


@dataclass(frozen=True, eq=False)
class LimitBounds:
    """Bounds of a trajectory over all times (:func:`limit_bounds`).

    Attributes
    ----------
    q_low, q_high : ndarray, shape (n,)
        q_i(t) >= q_low_i and <= q_high_i for all t [rad or m].
    qd_peak, qdd_peak : ndarray, shape (n,)
        |qd_i(t)| <= qd_peak_i, |qdd_i(t)| <= qdd_peak_i for all t [rad/s, rad/s^2].
    points : int
        Grid points per period the bounds were taken on.
    """

    q_low: np.ndarray
    q_high: np.ndarray
    qd_peak: np.ndarray
    qdd_peak: np.ndarray
    points: int


def limit_bounds(series: FourierSeries, points: int | None = None) -> LimitBounds:
    """Bounds of q, |qd| and |qdd| over all times.

    Parameters
    ----------
    series : FourierSeries
    points : int, optional
        Grid points per period; default ``BOUND_POINTS_PER_HARMONIC * K``.

    Returns
    -------
    LimitBounds

    Notes
    -----
    The series is periodic, so one period's grid t_k = k h, h = 2 pi / (w_f points), covers
    every time. Any t is within h/2 of a grid point, so |f(t) - f(t_k)| <= h/2 sup|f'|, and
    sup|f'| is bounded by :meth:`FourierSeries.derivative_bounds`: f(t) <= max_k f(t_k) +
    h/2 sup|f'|. (A bound in floating point, not an outward-rounded proof.)
    """
    points = BOUND_POINTS_PER_HARMONIC * series.harmonics if points is None else int(points)
    h = series.period / points
    t = np.arange(points) * h
    q, qd, qdd = series.evaluate(t)
    d1, d2, d3 = series.derivative_bounds()
    return LimitBounds(q_low=q.min(0) - h / 2 * d1, q_high=q.max(0) + h / 2 * d1,
                       qd_peak=np.abs(qd).max(0) + h / 2 * d2,
                       qdd_peak=np.abs(qdd).max(0) + h / 2 * d3, points=points)


def scaled_condition(Y: np.ndarray) -> float:
    """The condition number of a regressor with its columns scaled to unit norm.

    Parameters
    ----------
    Y : ndarray, shape (N, n, p) or (rows, p)
        The regressor; set points and joints are stacked as rows.

    Returns
    -------
    float
        sigma_max / sigma_min of Y diag(1 / ||Y_c||); inf if a column is zero or the matrix is
        rank deficient.

    Notes
    -----
    The SVD runs on one BLAS thread: the matrix is tall and thin (p columns, a few dozen), and
    a threaded LAPACK call on a busy machine takes several times longer than a serial one
    (8 Panda regressors of 2,800 rows: 1.9 to 11 s threaded, 0.4 to 0.5 s serial, the same
    singular values).
    """
    W = Y.reshape(-1, Y.shape[-1])
    norms = np.linalg.norm(W, axis=0)
    if not np.all(norms > 0):
        return math.inf
    with one_blas_thread():
        s = np.linalg.svd(W / norms, compute_uv=False)
    return float(s[0] / s[-1]) if s[-1] > 0 else math.inf


def excitation_condition(robot: Robot, columns: IdentificationColumns, series: FourierSeries,
                         samples: int = OBJECTIVE_SAMPLES) -> float:
    """The scaled condition number of the identification regressor over one period.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    columns : IdentificationColumns
        The regressor's columns (base parameters and drive columns).
    series : FourierSeries
        The trajectory.
    samples : int, optional
        Set points over one period, at the middles of its equal parts (t = (k + 1/2) T_f /
        samples: never at rest, where sgn(qd) would be decided by rounding).

    Returns
    -------
    float
        :func:`scaled_condition` of the regressor stacked at the samples.
    """
    q, qd, qdd = series.evaluate(_middles(series.period, samples))
    return scaled_condition(identification_regressor(robot, q, qd, qdd, columns))


def _middles(period, samples):
    """Times (k + 1/2) period / samples, k = 0..samples - 1 [s]."""
    return (np.arange(int(samples)) + 0.5) * (period / int(samples))


class _Basis:
    """The linear map from the free variables x to q, qd, qdd at given times.

    x holds per joint (q0, a_2..a_K, b_2..b_K), joint-major; a_1 and b_1 make the series start
    at rest. ``P[d]`` (N, 2K - 1) gives derivative d of every joint: ``P[d] @ X``, X of shape
    (2K - 1, n).
    """

    def __init__(self, K, wf, t):
        self.K, self.wf = K, wf
        w = wf * np.arange(1, K + 1)
        s, c = np.sin(np.outer(t, w)), np.cos(np.outer(t, w))
        Za = np.vstack([-np.ones((1, K - 1)), np.eye(K - 1)])
        Zb = np.vstack([-np.arange(2, K + 1)[None, :].astype(float), np.eye(K - 1)])
        one, zero = np.ones((t.size, 1)), np.zeros((t.size, 1))
        self.P = (np.hstack([one, (s / w) @ Za, (-c / w) @ Zb]),
                  np.hstack([zero, c @ Za, s @ Zb]),
                  np.hstack([zero, (-w * s) @ Za, (w * c) @ Zb]))

    @property
    def size(self):
        return 2 * self.K - 1

    def series(self, x, n):
        X = x.reshape(n, self.size)
        a_rest, b_rest = X[:, 1:self.K], X[:, self.K:]
        a = np.hstack([-a_rest.sum(1, keepdims=True), a_rest])
        b = np.hstack([-(np.arange(2, self.K + 1) * b_rest).sum(1, keepdims=True), b_rest])
        return FourierSeries(q0=X[:, 0].copy(), a=a, b=b, wf=self.wf)

    def states(self, x, n):
        X = x.reshape(n, self.size).T
        return tuple(P @ X for P in self.P)


def _kept_drives(columns, qd, qdd, coulomb_scale=None):
    """The kept drive columns alone, shape (N, n, kept), and d(Coulomb column)/d qd.

    With ``coulomb_scale`` v (n,) [rad/s or m/s], the Coulomb column of joint j is the
    surrogate tanh(qd_j / v_j) and its derivative (1 - tanh^2(qd_j / v_j)) / v_j; without, the
    columns' own (sgn(qd), or tanh(qd / v_s) of ``columns.coulomb_velocity``).
    """
    if coulomb_scale is None:
        D = drive_regressor(qd, qdd, columns.drives, columns.coulomb_velocity)
        vs = columns.coulomb_velocity
        slope = np.zeros_like(qd) if vs == 0 else (1.0 - np.tanh(qd / vs) ** 2) / vs
    else:
        v = np.asarray(coulomb_scale, float)
        D = drive_regressor(qd, qdd, columns.drives)
        surrogate = np.tanh(qd / v)
        slope = (1.0 - surrogate ** 2) / v
        if "coulomb" in columns.drives:     # joint j's Coulomb column is c n + j
            n, c = qd.shape[1], columns.drives.index("coulomb")
            D[:, np.arange(n), c * n + np.arange(n)] = surrogate
    return D[:, :, columns.drive_mask], slope


def _singular(Ws):
    """All singular values of Ws, descending, and the right singular vectors V (p, p).

    From the eigenvalues of the p x p Gram matrix Ws^T Ws (a product on one BLAS thread in
    :func:`plan_excitation`: a threaded SVD of the tall matrix is hundreds of times slower on a
    loaded machine), by the SVD itself when the Gram matrix is too ill-conditioned for that
    (cond(Ws) > 1e6). The left ones, Ws V / s, are not formed: only the gradient needs them.
    """
    lam, V = np.linalg.eigh(Ws.T @ Ws)
    if lam[0] > 1e-12 * lam[-1]:
        return np.sqrt(lam[::-1]), V[:, ::-1]
    s, Vt = np.linalg.svd(Ws, full_matrices=False)[1:]
    return s, Vt.T


#: Exponent P of the smooth objective: log of the ratio of the P-norm of the singular values
#: to the P-norm of their inverses' inverse, log cond as P -> infinity.
SMOOTH_POWER = 16.0


def _log_condition(x, robot, columns, basis, coulomb_scale=None, power=None):
    """A smooth log of the scaled condition number at x, and a function giving its gradient
    with respect to x (called only where the optimiser needs it, not in its line searches).

    The value is (1/P) log sum sigma_i^P + (1/P) log sum sigma_i^-P (P = ``power``, default
    SMOOTH_POWER), within (2/P) log p above log(sigma_max / sigma_min) and smooth where the
    smallest singular values cluster, as they do near the optimum. For P = 2 it is
    (1/2) log p + (1/2) log trace((Ws^T Ws)^-1), Ws the regressor with unit-norm columns
    (sum sigma_i^2 = p): the A-optimality criterion. With d value / d sigma_i = c_i and sigma_i =
    u_i^T W S v_i (S = diag(1 / ||W_c||)), the gradient with respect to column c of W is
    s_c (m_c - (m_c . w_c) w_c) with m = U diag(c) V^T = Ws V diag(c / sigma) V^T and w_c =
    s_c W_c; that gradient is
    carried to the states by the regressor recursion's reverse-mode derivative
    (:func:`~gd_analyze.dynamics.regressor_kernels.regressor_columns_pullback`, about three
    evaluations of the regressor whatever n is) and by the drive columns' exact derivatives,
    then to x by the basis (linear).
    """
    n = robot.n
    q, qd, qdd = basis.states(x, n)
    M = q.shape[0]
    base_idx = np.flatnonzero(columns.base.independent.reshape(-1))
    Yb, pullback = regressor_columns_pullback(robot, base_idx, q, qd, qdd)
    Dk, slope = _kept_drives(columns, qd, qdd, coulomb_scale)
    Y = np.concatenate([Yb, Dk], axis=2)
    p = Y.shape[2]
    W = Y.reshape(M * n, p)
    norms = np.linalg.norm(W, axis=0)
    if not np.all(norms > 0):
        return math.inf, lambda: np.zeros_like(x)
    Ws = W / norms
    s, V = _singular(Ws)
    if not s[-1] > 0:
        return math.inf, lambda: np.zeros_like(x)
    P = SMOOTH_POWER if power is None else float(power)
    up, down = (s / s[0]) ** P, (s[-1] / s) ** P
    value = math.log(s[0] / s[-1]) + (math.log(up.sum()) + math.log(down.sum())) / P
    return value, lambda: _gradient(x, columns, basis, s, V, up, down, Ws, norms, Yb.shape[2],
                                    pullback, slope)


def _gradient(x, columns, basis, s, V, up, down, Ws, norms, b, pullback, slope):
    """:func:`_log_condition`'s gradient with respect to x, from its evaluation's parts."""
    M, n = slope.shape
    p = Ws.shape[1]
    c = up / (s * up.sum()) - down / (s * down.sum())        # d value / d sigma_i
    Mg = Ws @ ((V * (c / s)) @ V.T)                      # d value / d Ws = U diag(c) V^T
    G = (Mg - np.einsum("kc,kc->c", Mg, Ws) * Ws) / norms
    G = G.reshape(M, n, p)
    grads = list(pullback(G[:, :, :b]))
    # the drive columns: d(qdd_j)/d(qdd_j) = 1, d(qd_j)/d(qd_j) = 1, tanh' or 0 for Coulomb
    col = b
    for c, kind in enumerate(columns.drives):
        for j in np.flatnonzero(columns.drive_kept[:, c]):
            if kind == "armature":
                grads[2][:, j] += G[:, j, col]
            elif kind in ("viscous", "coulomb"):
                grads[1][:, j] += G[:, j, col] * (slope[:, j] if kind == "coulomb" else 1.0)
            col += 1
    gX = sum(P.T @ gd for P, gd in zip(basis.P, grads))        # (2K - 1, n)
    return gX.T.reshape(-1)


def _limits(robot, qdd_max=None):
    """lo, hi, qd_max, qdd_max (n,) each, and where qdd_max comes from; an InputError (a
    ValueError) naming the first joint without a velocity limit
    (:func:`~gd_analyze.trajectory.planning.check_velocity_limits`)."""
    check_velocity_limits(robot)
    qd = np.asarray(robot.qd_max, float)
    qdd, source = acceleration_limits(robot, qdd_max)
    lo, hi = default_motion_range(robot)
    return lo, hi, qd, qdd, source


def _margined(lo, hi, qd, qdd, margin):
    span = hi - lo
    return lo + margin * span, hi - margin * span, (1 - margin) * qd, (1 - margin) * qdd


def _fit(series, lo, hi, qd_max, qdd_max):
    """The series with each joint's oscillation about q0 shrunk until its bounds fit."""
    bounds = limit_bounds(series)
    q0 = series.q0
    with np.errstate(divide="ignore", invalid="ignore"):
        ratios = np.stack([(hi - q0) / (bounds.q_high - q0), (q0 - lo) / (q0 - bounds.q_low),
                           qd_max / bounds.qd_peak, qdd_max / bounds.qdd_peak])
    ratios = np.where(np.isnan(ratios), np.inf, ratios)
    scale = np.minimum(1.0, ratios.min(0) * (1 - 1e-9))[:, None]
    return FourierSeries(q0=q0, a=series.a * scale, b=series.b * scale, wf=series.wf)


def random_excitation(robot: Robot, harmonics: int = DEFAULT_HARMONICS,
                      wf: float = 2 * math.pi / 10, seed: int | Sequence[int] = 0,
                      qdd_max: ArrayLike | None = None) -> FourierSeries:
    """A random Fourier series from rest to rest, each joint scaled to fit its limits.

    Parameters
    ----------
    robot : Robot
        The arm, with position, velocity and (or the default of
        :func:`~gd_analyze.model.limits.acceleration_limits`) acceleration limits.
    harmonics : int, optional
        K >= 2.
    wf : float, optional
        Base frequency [rad/s].
    seed : int or sequence of int, optional
        Seed of :func:`numpy.random.default_rng`.
    qdd_max : array_like, shape (n,), optional
        Acceleration limits [rad/s^2] replacing the robot's.

    Returns
    -------
    FourierSeries
        q0 the middle of each joint's range; a_il, b_il (l >= 2) drawn from N(0, 1/l^2), a_i1
        and b_i1 set for rest at t = 0; each joint's oscillation then scaled so that its
        :func:`limit_bounds` touch the limits less :data:`LIMIT_MARGIN`.

    Raises
    ------
    ValueError
        If K < 2 or a joint has no velocity limit (an :class:`~gd_analyze.errors.InputError`,
        :func:`~gd_analyze.trajectory.planning.check_velocity_limits`).
    """
    K = int(harmonics)
    if K < 2:
        raise ValueError("an excitation from rest to rest needs at least 2 harmonics")
    lo, hi, qd, qdd, _ = _limits(robot, qdd_max)
    lo_m, hi_m, qd_m, qdd_m = _margined(lo, hi, qd, qdd, LIMIT_MARGIN)
    rng = np.random.default_rng(seed)
    basis = _Basis(K, float(wf), np.zeros(1))
    n = robot.n
    X = rng.normal(size=(n, basis.size)) / np.concatenate(
        [[1.0], np.arange(2, K + 1), np.arange(2, K + 1)])
    X[:, 0] = (lo + hi) / 2
    series = basis.series(X.reshape(-1), n)
    big = FourierSeries(q0=series.q0, a=series.a * 1e3, b=series.b * 1e3, wf=series.wf)
    return _fit(big, lo_m, hi_m, qd_m, qdd_m)


def _variables(series):
    """x of a series that starts at rest (the inverse of _Basis.series)."""
    K = series.harmonics
    return np.hstack([series.q0[:, None], series.a[:, 1:K], series.b[:, 1:K]]).reshape(-1)


def excitation_timing(duration: float | None = None,
                      base_frequency: float | None = None) -> tuple[float, float, int]:
    """The duration, base frequency and number of periods of an excitation.

    Parameters
    ----------
    duration : float, optional
        T [s]; default one period, or :data:`DEFAULT_DURATION` without a base frequency.
    base_frequency : float, optional
        w_f [rad/s]; default 2 pi / T.

    Returns
    -------
    T : float
        [s].
    wf : float
        [rad/s].
    periods : int
        T w_f / (2 pi), a whole number >= 1.

    Raises
    ------
    ValueError
        If a value is not finite and positive, or T is not a whole number of periods (to
        1e-9).
    """
    for name, v in (("duration", duration), ("base frequency", base_frequency)):
        if v is not None and not (math.isfinite(v) and v > 0):
            raise ValueError(f"the {name} must be finite and positive, got {v!r}")
    if base_frequency is None:
        T = DEFAULT_DURATION if duration is None else float(duration)
        return T, 2 * math.pi / T, 1
    wf = float(base_frequency)
    if duration is None:
        return 2 * math.pi / wf, wf, 1
    cycles = float(duration) * wf / (2 * math.pi)
    m = round(cycles)
    if m < 1 or abs(cycles - m) > 1e-9 * max(1.0, cycles):
        raise ValueError(f"a duration of {duration:g} s is {cycles:.6g} periods of 2 pi / w_f "
                         f"= {2 * math.pi / wf:.6g} s: it must be a whole number of them, so "
                         "that the trajectory ends at rest")
    return float(duration), wf, int(m)


@dataclass(frozen=True, eq=False)
class Excitation(SampledMotion):
    """An optimised excitation trajectory (:func:`plan_excitation`), sampled on demand
    (:meth:`rows`, :meth:`~gd_analyze.trajectory.planning.SampledMotion.chunks`, the whole
    :attr:`~gd_analyze.trajectory.planning.SampledMotion.trajectory`).

    Attributes
    ----------
    duration : float
        T [s], a whole number of periods.
    n_setpoints : int
        N >= 2 set points, evenly spaced in time, both ends included.
    source : str
        How the motion was made (harmonics, w_f, periods, seed).
    series : FourierSeries
        The series it samples.
    columns : IdentificationColumns
        The regressor's columns the condition number is of.
    condition : float
        The scaled condition number (:func:`excitation_condition`) of the trajectory.
    start_conditions : tuple of float
        That of each random start (:func:`random_excitation`, scaled to the same limits).
    bounds : LimitBounds
        The trajectory's bounds over all times (:func:`limit_bounds`), inside the limits.
    limits : dict
        ``q_min``, ``q_max``, ``qd_max``, ``qdd_max`` used, shape (n,) each, and
        ``qdd_source`` (:func:`~gd_analyze.model.limits.acceleration_limits`).
    periods : int
        Periods of 2 pi / w_f in the duration.
    shrink : ndarray, shape (n,)
        Factor the optimised oscillation of each joint was scaled by to fit its bounds (1 when
        it fitted as found).
    seconds : float
        Wall time of the optimisation [s].
    messages : tuple of str
        SLSQP's messages of each start, its stages joined by "; ".
    """

    series: FourierSeries
    columns: IdentificationColumns
    condition: float
    start_conditions: tuple
    bounds: LimitBounds
    limits: dict
    periods: int
    shrink: np.ndarray
    seconds: float
    messages: tuple

    def rows(self, start: int, stop: int) -> Trajectory:
        """Set points start to stop - 1 of the whole motion (the same times; the values to
        rounding, the matrix products of :meth:`FourierSeries.evaluate` being over the piece).

        Parameters
        ----------
        start, stop : int
            0 <= start < stop <= N.

        Returns
        -------
        Trajectory
            t (stop - start,) [s] (:meth:`~gd_analyze.trajectory.planning.SampledMotion.times`),
            q, qd, qdd (stop - start, n) from :meth:`FourierSeries.evaluate`;
            ``derivatives = "fourier"``.
        """
        t = self.times(start, stop)
        q, qd, qdd = self.series.evaluate(t)
        return Trajectory(t=t, q=q, qd=qd, qdd=qdd, derivatives="fourier", source=self.source)


def _variable_scales(K, wf, lo, hi, qd, qdd):
    """Typical magnitudes of x's entries, shape (n (2K - 1),): per joint (hi - lo) / 2 for
    q0, then min(qd_max, qdd_max / (w_f l)) for a_il and b_il, l = 2..K."""
    w = wf * np.arange(2, K + 1)
    amp = np.minimum(qd[:, None], qdd[:, None] / w)                 # (n, K - 1)
    D = np.hstack([((hi - lo) / 2)[:, None], amp, amp]).reshape(-1)
    return np.where(np.isfinite(D) & (D > 0), D, 1.0)


class _ScaledObjective:
    """:func:`_log_condition` at x = D z (``value``) and its gradient with respect to z
    (``gradient``), the gradient computed from the last value's evaluation when z is the same
    (SLSQP's line searches ask for values alone). Values and gradients are kept by z: a run
    started again from the same point (:func:`_constrained_minimum`) retraces its iterates."""

    def __init__(self, D, robot, columns, basis, coulomb_scale, power=None):
        self.D, self.args = D, (robot, columns, basis, coulomb_scale, power)
        self.known, self.last, self.gradient_at = {}, None, None

    def _entry(self, z):
        key = np.asarray(z, float).tobytes()
        if key not in self.known:
            value, self.gradient_at = _log_condition(z * self.D, *self.args)
            self.known[key], self.last = [value, None], key
        return key, self.known[key]

    def value(self, z):
        return self._entry(z)[1][0]

    def gradient(self, z):
        key, entry = self._entry(z)
        if entry[1] is None:
            if key != self.last:        # the value is kept, not its evaluation's parts
                self.gradient_at, self.last = _log_condition(z * self.D, *self.args)[1], key
            entry[1] = self.gradient_at() * self.D
        return entry[1]


def _constraints(basis, n, lo, hi, qd, qdd):
    """A x <= c: the limits on the grid of basis, joint by joint (linear in x)."""
    m = basis.size
    P0, P1, P2 = basis.P
    G = P0.shape[0]
    block = np.vstack([P0, -P0, P1, -P1, P2, -P2])
    A = np.zeros((6 * G * n, m * n))
    c = np.empty(6 * G * n)
    for j in range(n):
        rows = slice(6 * G * j, 6 * G * (j + 1))
        A[rows, m * j:m * (j + 1)] = block
        c[rows] = np.repeat([hi[j], -lo[j], qd[j], qd[j], qdd[j], qdd[j]], G)
    return A, c


#: Rows of the limits given to SLSQP: those whose slack is at most this fraction of their
#: room (:func:`_constrained_minimum`).
WORKING_SLACK = 0.3


def _constrained_minimum(fun, z, A, c, room, maxiter):
    """SLSQP from z for fun under A z <= c, the rows given to it only those near their bound.

    SLSQP's step costs of the order of rows x variables^2 (its quadratic subproblem is
    transformed by the quasi-Newton factor), and most of the dense grid's rows are far from
    their limit. It is given the rows whose slack at z is at most ``WORKING_SLACK`` of their
    room; each iterate is checked against every row, and at the first that violates one the
    run is stopped and started again from z, with the rows violated and those near their
    bound there added. The result is that of a whole run whose every iterate was within
    every row it was not given (at worst every row is given, as without the selection).
    """
    from scipy.optimize import minimize

    given = (c - A @ z) <= WORKING_SLACK * room
    while True:
        Ag, cg = A[given], c[given]

        stopped = []

        def check(x):                           # the run stops at this iterate x
            if np.any(~given & (A @ x > c)):
                stopped.append(x)
                raise StopIteration

        # SciPy 1.17 ends the run there; 1.15's SLSQP passes StopIteration on
        with contextlib.suppress(StopIteration):
            result = minimize(fun.value, z, jac=fun.gradient, method="SLSQP",
                              constraints=[{"type": "ineq", "fun": lambda v: cg - Ag @ v,
                                            "jac": lambda v: -Ag}] if cg.size else [],
                              callback=check, options={"maxiter": maxiter, "ftol": 1e-8})
        slack = c - A @ (stopped[-1] if stopped else result.x)
        violated = ~given & (slack < 0)
        if not violated.any():
            return result
        given |= violated | (slack <= WORKING_SLACK * room)


def plan_excitation(robot: Robot, duration: float | None = None, harmonics: int = DEFAULT_HARMONICS,
                    base_frequency: float | None = None, n_setpoints: int | None = None,
                    seed: int = 0, qdd_max: ArrayLike | None = None, starts: int = 2,
                    maxiter: int = 40, drives: Sequence[str] = DRIVE_COLUMNS) -> Excitation:
    """An excitation trajectory: a Fourier series minimising the scaled condition number.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints, position limits (where infinite, -+pi or 0..0.2 m as in
        :func:`~gd_analyze.trajectory.planning.default_motion_range`), velocity limits and acceleration
        limits (default :func:`~gd_analyze.model.limits.acceleration_limits`).
    duration : float, optional
        T [s] (:func:`excitation_timing`).
    harmonics : int, optional
        K >= 2 (default 5).
    base_frequency : float, optional
        w_f [rad/s] (:func:`excitation_timing`).
    n_setpoints : int, optional
        Set points N written, both ends included; default one per
        :data:`DEFAULT_SAMPLE_PERIOD`, at least the least N allowed (Raises).
    seed : int, optional
        Seed of the random starts (start s uses ``default_rng([seed, s])``).
    qdd_max : array_like, shape (n,), optional
        Acceleration limits [rad/s^2 or m/s^2] replacing the robot's.
    starts : int, optional
        Random starts of the optimiser; the best result is kept.
    maxiter : int, optional
        SLSQP iterations per start and stage (:data:`STAGES`).
    drives : sequence of str, optional
        The drive columns of the regressor (:data:`DRIVE_COLUMNS`).

    Returns
    -------
    Excitation

    Raises
    ------
    ValueError
        If K < 2, starts < 1, N > 10^8 or N below the least that resolves the highest
        harmonic and can identify the regressor's p columns (max(2 K periods + 2, ceil(p / n) +
        1): the last set point repeats the first's state), the timing is inconsistent
        (:func:`excitation_timing`), or a joint has no velocity limit (an
        :class:`~gd_analyze.errors.InputError`).

    Notes
    -----
    Swevers et al. (1997): the Fourier series of Eq. (9), the condition number of the
    (column-scaled) regressor as criterion. The objective is log cond(Y S) over
    ``OBJECTIVE_SAMPLES`` samples of one period, smoothed as the P-norms of the singular values
    and their inverses, its gradient exact (the singular vectors, then the regressor
    recursion differentiated in reverse mode). The variables are scaled to their ranges, and each start is
    optimised in the stages of :data:`STAGES`: the Coulomb columns sgn(qd_j) first replaced by
    tanh(qd_j / v_j), v_j a fraction of the velocity limit (the sampled sgn has no gradient),
    then as they are; P first 2 (the A-optimality criterion, the trace of the inverse
    information matrix), then growing to 64 (log cond within (2/64) log p), a continuation
    that leaves fewer starts in poor local minima than P = 16 throughout. The limits hold on a grid of
    ``CONSTRAINT_POINTS_PER_HARMONIC * K`` points per period with the margin (SLSQP, whose
    step costs about rows x variables^2, is given the rows near their bound, and run again
    with more whenever an iterate violates one it was not given), then the bounds
    of :func:`limit_bounds` are checked against the limits themselves and the oscillation
    shrunk joint by joint where one is exceeded.
    """
    K = int(harmonics)
    if K < 2:
        raise ValueError("an excitation from rest to rest needs at least 2 harmonics")
    if int(starts) < 1:
        raise ValueError("at least one start")
    T, wf, periods = excitation_timing(duration, base_frequency)
    columns = identification_columns(robot, drives)
    # the set points must resolve the highest harmonic (more than 2 of them per its period: N -
    # 1 > 2 K periods, the last set point being the first's state) and give the regressor
    # columns as many rows (n per state: (N - 1) n >= columns)
    least = max(2 * K * periods + 2, -(-columns.count // robot.n) + 1)
    N = max(round(T / DEFAULT_SAMPLE_PERIOD) + 1, least) if n_setpoints is None else int(
        n_setpoints)
    if not least <= N <= 10**8:
        raise ValueError(f"{N:,} set points over the duration {T:g} s: {least:,} to 10^8 "
                         f"allowed (more than 2 K = {2 * K} per period of w_f, {periods} here; "
                         f"(N - 1) x {robot.n} rows for the {columns.count} regressor columns)")
    import scipy.optimize  # noqa: F401  (loads SciPy's own BLAS before the limit below)
    clock = time.perf_counter()
    # one BLAS thread: the SVDs and eigenproblems here are small, and a threaded LAPACK call
    # on a busy machine takes a hundred times longer than a serial one. The limit reaches only
    # the BLAS libraries loaded when it is set: SciPy's (SLSQP's), loaded by the import above,
    # otherwise ran two threads, the second spinning (the PUMA's plan: 17.8 s CPU in 9.2 s
    # wall, 9.0 s CPU in 9.0 s with one thread)
    with one_blas_thread():
        return _optimised(robot, K, T, wf, periods, N, int(seed), qdd_max, int(starts),
                          int(maxiter), columns, clock)


def _optimised(robot, K, T, wf, periods, N, seed, qdd_max, starts, maxiter, columns, clock):
    """plan_excitation's work, with its arguments checked."""
    n = robot.n
    lo, hi, qd, qdd, qdd_source = _limits(robot, qdd_max)
    inner = _margined(lo, hi, qd, qdd, LIMIT_MARGIN)
    period = 2 * math.pi / wf
    objective = _Basis(K, wf, _middles(period, OBJECTIVE_SAMPLES))
    G = CONSTRAINT_POINTS_PER_HARMONIC * K
    A, c = _constraints(_Basis(K, wf, np.arange(G) * (period / G)), n, *inner)
    # each row's room: its limit's interval (hi - lo, 2 qd_max, 2 qdd_max), the sum of the
    # bounds of its pair (the rows of each joint and derivative, + then -, G each)
    room = np.repeat(c.reshape(n, 3, 2, G).sum(2), 2, axis=1).reshape(-1)
    # the variables scaled to their ranges (SLSQP's quasi-Newton starts from the identity):
    # q0 by half its range, a_il and b_il by the largest amplitude the limits allow
    D = _variable_scales(K, wf, *inner)
    AD = A * D
    coulomb = "coulomb" in columns.drives and bool(
        columns.drive_kept[:, columns.drives.index("coulomb")].any())
    stages = [(None if v is None or not coulomb else v * inner[2], power)
              for v, power in STAGES]
    best, start_conditions, messages = None, [], []
    for s in range(int(starts)):
        start = random_excitation(robot, K, wf, [int(seed), s], qdd_max)
        start_conditions.append(excitation_condition(robot, columns, start))
        z, said = _variables(start) / D, []
        for scale, power in stages:
            fun = _ScaledObjective(D, robot, columns, objective, scale, power)
            result = _constrained_minimum(fun, z, AD, c, room, int(maxiter))
            z = result.x
            said.append(f"{result.message} ({result.nit} iterations)")
        messages.append("; ".join(said))
        found = objective.series(z * D, n)
        if not np.all((lo < found.q0) & (found.q0 < hi)):
            continue
        fitted = _fit(found, lo, hi, qd, qdd)
        cond = excitation_condition(robot, columns, fitted)
        if best is None or cond < best[0]:
            best = (cond, fitted, found)
    if best is None:            # every start left the range: keep the best start
        k = int(np.argmin(start_conditions))
        start = random_excitation(robot, K, wf, [int(seed), k], qdd_max)
        best = (start_conditions[k], start, start)
    cond, series, found = best
    found_amp = np.hypot(found.a, found.b).sum(1)      # the oscillation as optimised
    with np.errstate(divide="ignore", invalid="ignore"):
        shrink = np.where(found_amp > 0, np.hypot(series.a, series.b).sum(1) / found_amp, 1.0)
    return Excitation(duration=T, n_setpoints=N,
                      source=f"excitation: Fourier series of {K} harmonics, w_f = {wf:.6g} "
                             f"rad/s, {periods} period{'s' if periods > 1 else ''} of "
                             f"{period:.6g} s, seed {int(seed)}",
                      series=series, columns=columns, condition=cond,
                      start_conditions=tuple(start_conditions), bounds=limit_bounds(series),
                      limits={"q_min": lo, "q_max": hi, "qd_max": qd, "qdd_max": qdd,
                              "qdd_source": qdd_source},
                      periods=periods, shrink=shrink, seconds=time.perf_counter() - clock,
                      messages=tuple(messages))
