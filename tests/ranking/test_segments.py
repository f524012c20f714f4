"""A chunk's segments (ranking/segments.py) against the trajectory of each set point counted
one by one, and the checks of the chunk and the ends."""

import numpy as np
import pytest

from gd_analyze.ranking.segments import chunk_segments


def test_each_row_of_the_chunk_is_in_its_own_trajectory_s_segment():
    rng = np.random.default_rng(2)
    for _ in range(200):
        lengths = rng.integers(1, 6, size=rng.integers(1, 8))
        ends = np.cumsum(lengths)
        owner = np.repeat(np.arange(lengths.size), lengths)     # the trajectory of each point
        at = int(rng.integers(0, ends[-1]))
        N = int(rng.integers(1, ends[-1] - at + 1))
        bounds, each = chunk_segments(N, ends, at, trajectories=lengths.size)
        rows = np.repeat(np.arange(each.start, each.stop), np.diff(bounds))
        assert rows.tolist() == owner[at:at + N].tolist()
        assert bounds[0] == 0 and bounds[-1] == N


def test_one_trajectory_by_default():
    bounds, each = chunk_segments(7, at=40)
    assert bounds.tolist() == [0, 7] and (each.start, each.stop) == (0, 1)


def test_the_chunk_and_the_ends_are_checked():
    with pytest.raises(ValueError, match="rise strictly"):
        chunk_segments(5, [3, 3, 5], trajectories=3)
    with pytest.raises(ValueError, match="rise strictly"):
        chunk_segments(2, [3, 2, 5], trajectories=3)
    with pytest.raises(ValueError, match="are not in"):
        chunk_segments(5, [2, 4], trajectories=2)
    with pytest.raises(ValueError, match="are not in"):
        chunk_segments(0)
    with pytest.raises(ValueError, match="for 2 trajectories"):
        chunk_segments(3, [1, 2, 3], trajectories=2)
