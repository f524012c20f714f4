"""A simplified model's per-joint torque error along trajectories, accumulated chunk by chunk.

Peak and rms of |tau_s - tau| per joint, and relative to the peak |tau_i| of the full model
(Sec. 3.4.1 of Fu, Gonzalez & Lee 1987: the error of the simplified equations of motion).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..ranking.segments import chunk_segments

__all__ = ["TorqueErrorAccumulator", "torque_error"]


class TorqueErrorAccumulator:
    """Accumulate a simplified model's per-joint torque error chunk by chunk.

    Parameters
    ----------
    n : int
        Number of joints.
    trajectories : int, optional
        K >= 1: accumulate K trajectories at once, each chunk cut into segments of
        consecutive set points of one trajectory (as
        :meth:`gd_analyze.ranking.ranking.RankingAccumulator.update` takes them); each
        trajectory's figures are those it has alone, bit for bit. Without it one
        trajectory (or all set points together), and the arrays below have no leading axis.

    Attributes
    ----------
    peak, sum_sq, peak_tau : ndarray, shape (n,) or (K, n)
        Peak |tau_s - tau| [N m], its sum of squares [N^2 m^2] and peak |tau| [N m].
    count : int or ndarray of int, shape (K,)
        How many set points were added (per trajectory).

    Raises
    ------
    ValueError
        If ``trajectories`` is below 1.
    """

    def __init__(self, n: int, trajectories: int | None = None) -> None:
        if trajectories is not None and int(trajectories) < 1:
            raise ValueError(f"trajectories must be >= 1, got {trajectories}")
        self.trajectories = None if trajectories is None else int(trajectories)
        lead = () if trajectories is None else (int(trajectories),)
        self.peak = np.zeros(lead + (n,))
        self.sum_sq = np.zeros(lead + (n,))
        self.peak_tau = np.zeros(lead + (n,))
        self.count: int | np.ndarray = 0 if trajectories is None else np.zeros(lead, int)

    def _each(self, name: str) -> np.ndarray:
        """An array with its leading trajectory axis (a view, also for one trajectory)."""
        value = np.asarray(getattr(self, name), float)
        return value if self.trajectories is not None else value[None]

    def update(self, tau_simplified: np.ndarray, tau_full: np.ndarray,
               ends: ArrayLike | None = None, at: int = 0) -> None:
        """Add a chunk of set points.

        Parameters
        ----------
        tau_simplified, tau_full : ndarray, shape (N, n)
            Torques of the simplified and the full model [N m].
        ends : array_like of int, shape (K,), optional
            Where each of the K trajectories' set points end, laid one after another
            (:mod:`gd_analyze.ranking.segments`); default one trajectory.
        at : int, optional
            The chunk's first set point among them.

        Raises
        ------
        ValueError
            If the chunk does not fit the trajectories' ends
            (:func:`gd_analyze.ranking.segments.chunk_segments`).
        """
        err = np.abs(np.asarray(tau_simplified, float) - np.asarray(tau_full, float))
        if err.shape[0] == 0:
            return
        bounds, each = chunk_segments(err.shape[0], ends, at, self.trajectories)
        starts = bounds[:-1]
        # the peaks of all segments at once (a maximum is exact in any order); each sum of
        # squares over its own rows, in row order, as one trajectory's chunk is summed
        peak, peak_tau, sum_sq = self._each("peak"), self._each("peak_tau"), \
            self._each("sum_sq")
        np.maximum(peak[each], np.maximum.reduceat(err, starts, axis=0), out=peak[each])
        square = err**2
        sum_sq[each] += np.array([square[a:b].sum(axis=0)
                                  for a, b in zip(starts.tolist(), bounds[1:].tolist())])
        np.maximum(peak_tau[each], np.maximum.reduceat(np.abs(tau_full), starts, axis=0),
                   out=peak_tau[each])
        if self.trajectories is None:
            self.count += err.shape[0]
        else:
            self.count[each] += np.diff(bounds)    # type: ignore[index]

    def result(self) -> dict:
        """The error figures of the one trajectory (or of all set points together).

        Returns
        -------
        dict
            Lists of n floats: ``peak_abs_error`` and ``rms_error`` of |tau_s - tau| [N m],
            ``peak_tau`` = peak |tau| [N m], and ``relative_peak_error`` and
            ``relative_rms_error`` (the errors divided by peak |tau|; NaN for a joint whose
            torque is zero throughout).

        Raises
        ------
        ValueError
            If the accumulator holds K > 1 trajectories (:meth:`results`).
        """
        if (self.trajectories or 1) != 1:
            raise ValueError(f"{self.trajectories} trajectories are accumulated: use results()")
        return self.results()[0]

    def results(self) -> list[dict]:
        """The error figures of every trajectory.

        Returns
        -------
        list of dict
            K of them (one without ``trajectories``), each as :meth:`result`.
        """
        pt = self._each("peak_tau")
        count = np.maximum(np.asarray(self.count, int).reshape(-1), 1)[:, None]
        rms = np.sqrt(self._each("sum_sq") / count)
        peak = self._each("peak")
        with np.errstate(invalid="ignore", divide="ignore"):
            rel_peak = np.where(pt > 0, peak / np.where(pt > 0, pt, 1), np.nan)
            rel_rms = np.where(pt > 0, rms / np.where(pt > 0, pt, 1), np.nan)
        return [{"peak_abs_error": p, "rms_error": r, "peak_tau": t,
                 "relative_peak_error": rp, "relative_rms_error": rr}
                for p, r, t, rp, rr in zip(peak.tolist(), rms.tolist(), pt.tolist(),
                                           rel_peak.tolist(), rel_rms.tolist())]


def torque_error(tau_simplified: np.ndarray, tau_full: np.ndarray) -> dict:
    """Per-joint torque error of a simplified model along a trajectory.

    Parameters
    ----------
    tau_simplified, tau_full : ndarray, shape (N, n)
        Torques [N m].

    Returns
    -------
    dict
        As :meth:`TorqueErrorAccumulator.result`.
    """
    tau_full = np.asarray(tau_full, float)
    acc = TorqueErrorAccumulator(tau_full.shape[1])
    acc.update(tau_simplified, tau_full)
    return acc.result()
