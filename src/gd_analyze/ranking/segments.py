"""Trajectories laid one after another and taken in chunks: the segments of each chunk.

A sweep ranks many short trajectories in one pass over their set points laid one after
another (:func:`gd_analyze.jobs.analyze.analysis_passes`): K trajectories whose set points end
at ``ends`` (strictly increasing; trajectory k holds set points ends[k - 1] .. ends[k] - 1,
ends[-1] = 0). A chunk of that pass, set points ``at`` .. ``at + N - 1``, holds a segment of
consecutive set points of each trajectory it meets. The accumulators
(:class:`gd_analyze.ranking.ranking.RankingAccumulator`,
:class:`gd_analyze.simplify.torque_error.TorqueErrorAccumulator`) and the simplified torque
(:func:`gd_analyze.simplify.choices.simplified_torque`) take a chunk with ``ends`` and
``at``, and add each segment to its own trajectory's figures; without ``ends`` the chunk is
one segment of trajectory 0 (the main job: one trajectory, chunk by chunk).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["chunk_segments"]


def chunk_segments(N: int, ends: ArrayLike | None = None, at: int = 0,
                   trajectories: int | None = None) -> tuple[np.ndarray, slice]:
    """The segments of a chunk of set points, and the trajectories they belong to.

    Parameters
    ----------
    N : int
        The chunk's set points, >= 1.
    ends : array_like of int, shape (K,), optional
        Where each trajectory's set points end (module docstring); default one trajectory
        that holds the whole chunk.
    at : int, optional
        The chunk's first set point, >= 0.
    trajectories : int, optional
        The trajectories an accumulator holds (default 1): ``ends`` must have that many.

    Returns
    -------
    bounds : ndarray of int64, shape (S + 1,)
        Segment s is the chunk's rows bounds[s] .. bounds[s + 1] - 1 (bounds[0] = 0,
        bounds[S] = N).
    each : slice
        The segments' trajectories, first .. first + S - 1.

    Raises
    ------
    ValueError
        If the chunk is empty or runs past the last trajectory, the ends do not rise
        strictly, or their number is not ``trajectories``.

    Examples
    --------
    Trajectories of 5, 12, 1 and 22 set points; the chunk of set points 9 .. 19:

    >>> bounds, each = chunk_segments(11, [5, 17, 18, 40], at=9, trajectories=4)
    >>> bounds.tolist(), (each.start, each.stop)
    ([0, 8, 9, 11], (1, 4))
    """
    K = trajectories or 1
    ends = np.array([at + N] if ends is None else ends, np.int64).reshape(-1)
    if ends.size != K:
        raise ValueError(f"{ends.size} trajectory ends for {K} trajectories")
    first = int(np.searchsorted(ends, at, side="right"))
    last = int(np.searchsorted(ends, at + N - 1, side="right"))
    if N < 1 or at < 0 or last >= K:
        raise ValueError(f"set points {at} .. {at + N - 1} are not in the trajectories' "
                         f"{int(ends[-1])}")
    bounds = np.concatenate([[0], np.minimum(ends[first:last + 1], at + N) - at])
    if np.any(np.diff(bounds) <= 0) or np.any(np.diff(ends) <= 0):
        raise ValueError(f"trajectory ends must rise strictly, got {[int(e) for e in ends[:8]]}")
    return bounds.astype(np.int64), slice(first, last + 1)
