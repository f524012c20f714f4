"""A simplified model's per-joint torque error along trajectories, accumulated chunk by chunk.

Peak and rms of |tau_s - tau| per joint, and relative to the peak |tau_i| of the full model
(Sec. 3.4.1 of Fu, Gonzalez & Lee 1987: the error of the simplified equations of motion).
"""

from __future__ import annotations

import numpy as np

__all__ = ["TorqueErrorAccumulator", "torque_error"]


class TorqueErrorAccumulator:
    """Accumulate a simplified model's per-joint torque error chunk by chunk.

    Parameters
    ----------
    n : int
        Number of joints.
    """

    def __init__(self, n: int) -> None:
        self.peak = np.zeros(n)
        self.sum_sq = np.zeros(n)
        self.peak_tau = np.zeros(n)
        self.count = 0

    def update(self, tau_simplified: np.ndarray, tau_full: np.ndarray) -> None:
        """Add a chunk of set points.

        Parameters
        ----------
        tau_simplified, tau_full : ndarray, shape (N, n)
            Torques of the simplified and the full model [N m].
        """
        err = np.abs(np.asarray(tau_simplified, float) - np.asarray(tau_full, float))
        if err.shape[0] == 0:
            return
        np.maximum(self.peak, err.max(axis=0), out=self.peak)
        self.sum_sq += (err**2).sum(axis=0)
        np.maximum(self.peak_tau, np.abs(tau_full).max(axis=0), out=self.peak_tau)
        self.count += err.shape[0]

    def result(self) -> dict:
        """The error figures.

        Returns
        -------
        dict
            Lists of n floats: ``peak_abs_error`` and ``rms_error`` of |tau_s - tau| [N m],
            ``peak_tau`` = peak |tau| [N m], and ``relative_peak_error`` and
            ``relative_rms_error`` (the errors divided by peak |tau|; NaN for a joint whose
            torque is zero throughout).
        """
        rms = np.sqrt(self.sum_sq / max(self.count, 1))
        pt = self.peak_tau
        with np.errstate(invalid="ignore", divide="ignore"):
            rel_peak = np.where(pt > 0, self.peak / np.where(pt > 0, pt, 1), np.nan)
            rel_rms = np.where(pt > 0, rms / np.where(pt > 0, pt, 1), np.nan)
        return {"peak_abs_error": self.peak.tolist(), "rms_error": rms.tolist(),
                "peak_tau": pt.tolist(), "relative_peak_error": rel_peak.tolist(),
                "relative_rms_error": rel_rms.tolist()}


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
