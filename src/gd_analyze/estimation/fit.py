"""The identification's fit: recordings (preprocessed) -> the robot's base parameters and
drive terms -> the standard parameters a robot file holds.

The weighted least-squares fit of the identification regressor (:mod:`.estimate`) on the
rows where the joint moves (:func:`.regressor.moving_rows`), once more without the outlier
rows; then the standard parameters: physically consistent ones
(:func:`.consistent.consistent_standard`), or those closest to the robot file's that reproduce the identified
base parameters, replaced by consistent ones where a robot file cannot hold them. Pure: the
job reads the recordings and writes the results.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..dynamics.base_parameters import base_parameters
from ..symbolic.drive_regressor import IdentificationColumns, identification_regressor
from . import preprocess
from .consistent import (
    base_map,
    closest_standard,
    consistent_standard,
    loadable,
    min_eigenvalues,
    robot_with_standard,
    rounding_cleaned,
)
from .estimate import Estimate, combine_factors, joint_factors, least_squares
from .regressor import DRIVE_KINDS, column_names, moving_rows, prior_values

if TYPE_CHECKING:
    from ..dynamics.base_parameters import BaseParameters
    from ..model.robot import Robot
    from .preprocess import Preprocessed

__all__ = ["OUTLIER_SIGMAS", "Fit", "FitFailure", "fit_robot", "fit_columns"]

#: A training row whose residual exceeds this many noise standard deviations is an outlier.
OUTLIER_SIGMAS = 5.0


class FitFailure(ValueError):
    """The least-squares fit cannot be made on these recordings (its message says why)."""


@dataclass(frozen=True, eq=False)
class Fit:
    """An identified robot: the fitted columns and the standard parameters behind them.

    Attributes
    ----------
    base : BaseParameters
        The prior robot's b base parameters.
    columns : IdentificationColumns
        The regressor's columns: base parameters, then the drive columns.
    names, kinds : tuple of str, length p
        Each column's name and kind (:func:`.regressor.column_names`).
    prior : ndarray, shape (p,)
        The robot file's values of the columns.
    threshold : ndarray, shape (n,)
        |qd_i| below which a row is at rest [rad/s or m/s] (:func:`.regressor.moving_rows`).
    estimate : Estimate
        The least-squares fit (after the outlier rows were left out, if any were).
    theta : ndarray, shape (p,)
        The identified columns as predicted: with ``consistent``, those of the consistent
        standard parameters.
    used : tuple of ndarray of bool, each shape (N_k, n)
        The rows (sample, joint) of each training recording's kept samples that the fit used.
    standard : ndarray, shape (n, 10)
        The standard parameters behind ``theta`` (per link: m, m c, inertia about the frame).
    identified : Robot
        The prior robot with the parameters a robot file can hold (armature, viscous and
        Coulomb friction, torque offsets among them).
    offsets : ndarray, shape (n,)
        The torque offsets [N m or N].
    min_eigenvalue : ndarray, shape (n,)
        The smallest eigenvalue of each link's pseudo-inertia [kg m^2].
    consistent : ndarray of bool, shape (n,)
        Each link's pseudo-inertia is positive semidefinite (to 1e-10 of its scale).
    method : str
        How the standard parameters were chosen, in words.
    robot_file_note : str or None
        Why the robot file holds other parameters than ``standard``, or None.
    file_theta : ndarray, shape (p,)
        The columns of ``identified``'s parameters, the robot file's (``theta`` but for the
        rounding where ``robot_file_note`` is None).
    notes : tuple of str
        What the fit left out, and why, in words.
    """

    base: BaseParameters
    columns: IdentificationColumns
    names: tuple[str, ...]
    kinds: tuple[str, ...]
    prior: np.ndarray
    threshold: np.ndarray
    estimate: Estimate
    theta: np.ndarray
    used: tuple[np.ndarray, ...]
    standard: np.ndarray
    identified: Robot
    offsets: np.ndarray
    min_eigenvalue: np.ndarray
    consistent: np.ndarray
    method: str
    robot_file_note: str | None
    file_theta: np.ndarray
    notes: tuple[str, ...]


#: Most bytes of a recording's filtered regressor kept in memory between the passes over it
#: (:class:`RegressorRows`); a larger one is made again, block by block, for each pass.
KEEP_BYTES = 512 << 20


class RegressorRows:
    """A recording's filtered identification regressor at its kept samples, block by block.

    Iterating gives ``(a, b, Y)``: Y, shape (b - a, n, p), the rows a to b - 1 of
    ``p.filtered(identification_regressor(robot, p.q, p.qd, p.qdd, columns))[p.keep]``
    (:meth:`.preprocess.Preprocessed.filtered_blocks`; parallel filtering, Gautier 1997).
    The first pass keeps the blocks when they hold at most :data:`KEEP_BYTES` together, so
    that later passes read them; otherwise each pass makes them again, and memory stays a
    few blocks whatever the recording's length.

    Parameters
    ----------
    robot : Robot
        The arm.
    pre : Preprocessed
        The recording, preprocessed.
    columns : IdentificationColumns
        The regressor's columns.

    Attributes
    ----------
    keep : ndarray of bool, shape (N,)
        The recording's kept samples (all of them if it keeps no list).
    rows : int
        The kept samples: the rows of each joint.
    """

    def __init__(self, robot: Robot, pre: Preprocessed, columns: IdentificationColumns) -> None:
        self.robot, self.pre, self.columns = robot, pre, columns
        self.keep = np.ones(pre.t.size, bool) if pre.keep is None else pre.keep
        self.rows = int(np.count_nonzero(self.keep))
        self._size = self.rows * robot.n * columns.count * 8
        self._kept: list[tuple[int, int, np.ndarray]] | None = None

    def _made(self) -> Iterator[tuple[int, int, np.ndarray]]:
        pre, robot, columns = self.pre, self.robot, self.columns
        before = np.cumsum(self.keep) - self.keep       # kept samples before each sample

        def make(a, b):
            return identification_regressor(robot, pre.q[a:b], pre.qd[a:b], pre.qdd[a:b],
                                            columns)
        for a, b, Y in pre.filtered_blocks(make):
            keep = self.keep[a:b]
            if keep.any():
                start = int(before[a])
                yield start, start + int(keep.sum()), Y[keep]

    def times(self, V: np.ndarray) -> np.ndarray:
        """The filtered regressor's rows times a matrix: ``Y @ V`` at every kept sample.

        Parameters
        ----------
        V : ndarray, shape (p, k)
            Column values, k of them (e.g. the identified parameters).

        Returns
        -------
        ndarray, shape (rows, n, k)
            [N m or N]. From the kept blocks where they are kept; otherwise the regressor is
            made once, multiplied by V block by block and the (N, n, k) products filtered: the
            filter is linear, so filtered(Y) V = filtered(Y V), to round-off.
        """
        V = np.asarray(V, float)
        pre, n = self.pre, self.robot.n
        if self._kept is not None:
            out = np.empty((self.rows, n) + V.shape[1:])
            for a, b, Y in self._kept:
                out[a:b] = Y @ V
            return out
        raw = np.empty((pre.t.size, n) + V.shape[1:])
        step = preprocess.FILTER_BLOCK          # read when called (tests change it)
        for a in range(0, pre.t.size, step):
            b = min(a + step, pre.t.size)
            raw[a:b] = identification_regressor(self.robot, pre.q[a:b], pre.qd[a:b],
                                                pre.qdd[a:b], self.columns) @ V
        return pre.filtered(raw)[self.keep]

    def __iter__(self) -> Iterator[tuple[int, int, np.ndarray]]:
        if self._kept is not None:
            yield from self._kept
            return
        keep = self._size <= KEEP_BYTES
        kept = []
        for block in self._made():
            if keep:
                kept.append(block)
            yield block
        if keep:
            self._kept = kept


def fit_columns(prior: Robot, train: Sequence[Preprocessed], drive_columns: Sequence[str]
                ) -> tuple[Estimate, list[RegressorRows]]:
    """The least-squares fit of :func:`fit_robot` alone, without the standard parameters.

    For a fit that only predicts the recordings' torque (the clip check against a fitted
    model): the same estimate as :func:`fit_robot`'s ``estimate``, without the standard
    parameters' least-norm or consistent solution, which such a fit needs not and which may
    fail (``SolverFailure``) where the least squares do not.

    Parameters
    ----------
    prior : Robot
        The robot file's arm, with n joints.
    train : sequence of Preprocessed
        The training recordings (:func:`.preprocess.preprocess`).
    drive_columns : sequence of str
        The drive columns, among ``armature``, ``viscous``, ``coulomb``, ``offset``.

    Returns
    -------
    estimate : Estimate
        The weighted least-squares fit, the outlier rows left out (values of the p columns,
        the residual standard deviation per joint [N m or N]).
    regressors : list of RegressorRows
        Each training recording's filtered regressor at its kept samples.

    Raises
    ------
    FitFailure
        If the least-squares fit cannot be made (e.g. no rows).
    """
    *_, rows, est, _ = _least_squares(prior, train, drive_columns)
    return est, rows


def _least_squares(prior, train, drive_columns):
    """The least squares of :func:`fit_robot`: (base, kinds, column names, column kinds,
    columns, prior values, rest thresholds, notes, regressor rows, estimate, rows used)."""
    n = prior.n
    base = base_parameters(prior)
    kinds = tuple(k for k in DRIVE_KINDS if k in drive_columns)     # the columns' order
    col_names, col_kinds = column_names(base, n, kinds)
    columns = IdentificationColumns.keeping_all(base, n, kinds)
    theta0 = prior_values(base, prior, kinds)
    # rows at rest: thresholds from all training data
    threshold = moving_rows(np.concatenate([p.qd[p.keep] for p in train]))[1]
    notes = ["rows (sample, joint) with |qd_i| below 2% of the joint's 99th-percentile "
             "speed are left out of the fit: at rest the torque holds an unknown static "
             "friction (they count in the errors), except where the joint is held still "
             "all along a recording (its offset takes that friction); Coulomb friction is "
             "F_c sign(qd), not smoothed, as in the robot file"]
    rows = [RegressorRows(prior, p, columns) for p in train]

    def solved(used_rows):      # least squares on these rows, the factors block by block
        factors: Any = None
        for p, src, used in zip(train, rows, used_rows):
            tau = p.tau[p.keep]
            for a, b, Y in src:
                f = joint_factors(Y, tau[a:b], used[a:b])
                factors = f if factors is None else combine_factors(factors, f)
        counts = [int(used.sum()) for used in used_rows]   # over the rows' independent ones
        correlation = sum(counts) / max(sum(c / p.correlation for c, p in zip(counts, train)),
                                        1e-300)
        return least_squares(factors, theta0, correlation)
    moving = [(moving_rows(p.qd[p.keep], threshold)[0] | np.asarray(p.held, bool))  # fitted
              & (True if p.clipped is None else ~p.clipped[p.keep]) for p in train]
    try:
        est = solved(moving)
        # outliers: rows whose residual exceeds OUTLIER_SIGMAS x the joint's noise are left out
        # and the fit repeated once (a Gaussian residual exceeds 5 sigma once in 1.7 million)
        limit = OUTLIER_SIGMAS * np.maximum(est.noise_std, 1e-300)
        fit_rows = [used & ~(np.abs(p.tau[p.keep] - src.times(est.value[:, None])[..., 0])
                             > limit) for p, src, used in zip(train, rows, moving)]
        dropped = sum(int(m.sum() - used.sum()) for m, used in zip(moving, fit_rows))
        if dropped:
            est = solved(fit_rows)
            notes.append(f"{dropped} outlier rows (residual above {OUTLIER_SIGMAS:g} x the "
                         f"joint's noise standard deviation) left out and the fit repeated")
    except ValueError as exc:
        raise FitFailure(str(exc)) from None
    return (base, kinds, col_names, col_kinds, columns, theta0, threshold, notes, rows, est,
            fit_rows)


def fit_robot(prior: Robot, train: Sequence[Preprocessed], drive_columns: Sequence[str],
              consistent: bool = False) -> tuple[Fit, list[RegressorRows]]:
    """Identify a robot's base parameters and drive terms from its training recordings.

    Parameters
    ----------
    prior : Robot
        The robot file's arm, with n joints.
    train : sequence of Preprocessed
        The training recordings, filtered and differentiated (:func:`.preprocess.preprocess`).
    drive_columns : sequence of str
        The drive columns, among ``armature``, ``viscous``, ``coulomb``, ``offset``.
    consistent : bool, optional
        Physically consistent standard parameters (every pseudo-inertia positive
        semidefinite, armature and friction >= 0).

    Returns
    -------
    fit : Fit
    regressors : list of RegressorRows
        Each training recording's filtered regressor at its kept samples, block by block,
        for its prediction.

    Raises
    ------
    FitFailure
        If the least-squares fit cannot be made (e.g. no rows).
    gd_analyze.estimation.consistent.SolverFailure
        If the consistent parameters are needed and neither solver finds them.

    Notes
    -----
    Source: weighted least squares on the base-parameter regressor (Gautier & Khalil 1990;
    Swevers, Verdonck & De Schutter 2007), physical consistency by the pseudo-inertia
    (Wensing, Kim & Slotine 2018).
    """
    n = prior.n
    base, kinds, col_names, col_kinds, columns, theta0, threshold, notes, rows, est, fit_rows = \
        _least_squares(prior, train, drive_columns)
    phi0, b, theta = base.standard, base.rank, est.value
    drive_kind = col_kinds[b:]
    nonneg = np.array([k != "offset" for k in drive_kind], bool)
    if consistent:
        sol = consistent_standard(base, theta, est.identifiable, est.R, phi0, drive_kind,
                                  theta0[b:])
        phi, drives = sol.phi, sol.drives
        theta = np.concatenate([base_map(base) @ phi.reshape(-1), drives])
        closest = ("the closest to the robot file's" if sol.closest else "any: the solvers "
                   "did not find which are the closest to the robot file's")
        method = (f"physically consistent (every pseudo-inertia >= 0, armature and friction "
                  f">= 0; cvxpy with {sol.solver}): "
                  + (f"they reproduce the identified base parameters; among those, {closest}"
                     if sol.reproduces else
                     f"no consistent parameters reproduce the identified ones: the closest fit "
                     f"(weighted residual {sol.residual:.3g} of the fit's scale), and among "
                     f"those {closest}"))
        file_phi, file_drives, file_note = phi, drives, None
    else:
        phi = closest_standard(base, theta[:b], phi0)
        drives = theta[b:]
        method = ("the standard parameters closest to the robot file's that reproduce the "
                  "identified base parameters (least-norm deviation)")
        (file_phi, file_drives), file_note = rounding_cleaned(phi, drives, nonneg), None
        if not loadable(file_phi, bool((file_drives[nonneg] >= 0).all())):
            sol = consistent_standard(base, theta, est.identifiable, est.R, phi0, drive_kind,
                                      theta0[b:])
            file_phi, file_drives = sol.phi, sol.drives
            file_note = ("the least-squares parameters are not physically realisable (a "
                         "link's inertia or mass, or a friction < 0), which a robot file cannot "
                         "hold: identified_robot.toml holds the physically consistent "
                         "parameters (as --consistent)"
                         + ("" if sol.reproduces else ", which do not reproduce the identified "
                            "ones exactly") + ("" if sol.closest else " (the best consistent fit "
                                               "found, not the closest to the robot file's)"))
            notes.append(file_note)
    per_kind = {k: np.array(getattr(prior, "torque_offset" if k == "offset" else k), float)
                for k in DRIVE_KINDS}           # the file's, where not a column
    for k, kind in enumerate(drive_kind):
        per_kind[kind][k % n] = file_drives[k]
    identified = robot_with_standard(prior, file_phi, armature=per_kind["armature"],
                                     viscous=per_kind["viscous"], coulomb=per_kind["coulomb"],
                                     torque_offset=per_kind["offset"])
    eig = min_eigenvalues(phi)
    fit = Fit(base=base, columns=columns, names=col_names, kinds=col_kinds, prior=theta0,
              threshold=threshold, estimate=est, theta=theta, used=tuple(fit_rows),
              standard=np.asarray(phi), identified=identified, offsets=per_kind["offset"],
              min_eigenvalue=eig, method=method, robot_file_note=file_note, notes=tuple(notes),
              file_theta=np.concatenate([base_map(base) @ np.ravel(file_phi), file_drives]),
              consistent=eig >= -1e-10 * np.maximum(1e-300, np.abs(phi[:, :6]).max(axis=1)))
    return fit, rows
