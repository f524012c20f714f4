"""The array code of the atom peaks (term_arrays.atom_peaks_arrays) against the compiled
kernel (term_kernels.atom_peaks_kernel): the same peaks on PUMA 560 and on the Stanford arm
(a prismatic joint), over blocks of any size, with NaN kept out of the peaks alike; and the
engine that term_peaks picks by the trajectory's length."""

import numpy as np
import pytest
from symbolic_helpers import robot, states

from gd_analyze.core.dynamics.dalembert import COMPILED_MIN_SETPOINTS
from gd_analyze.core.symbolic import term_arrays
from gd_analyze.core.symbolic.explicit import term_peaks
from gd_analyze.core.symbolic.term_arrays import atom_peaks_arrays, peaks_kernel
from gd_analyze.io.explicit_cache import explicit_terms


def _both(arm, q, qd, qdd, **kw):
    terms, _ = explicit_terms(arm)
    return [term_peaks(terms, np.zeros(arm.n), q, qd, qdd, prismatic=arm.prismatic, engine=e,
                       **kw) for e in ("numpy", "compiled")]


@pytest.mark.parametrize("block", (1 << 20, 3000))
@pytest.mark.parametrize("name", ("puma560", "stanford"))
def test_the_array_code_gives_the_kernels_peaks(name, block, monkeypatch):
    """Within 1e-12 of the largest peak, one block or blocks of a few set points."""
    monkeypatch.setattr(term_arrays, "BLOCK_ELEMENTS", block)
    arm = robot(name)
    q, qd, qdd = states(arm, 90, 8)
    a, b = _both(arm, q, qd, qdd, chunk=37)
    assert a.shape == b.shape and np.abs(b).max() > 0
    assert np.abs(a - b).max() <= 1e-12 * np.abs(b).max()


def test_a_nan_set_point_is_never_a_peak_in_either_engine():
    arm = robot("stanford")
    q, qd, qdd = states(arm, 30, 6)
    qd[11, 2] = np.nan
    qdd[20] = np.nan
    a, b = _both(arm, q, qd, qdd)
    clean = _both(arm, np.delete(q, [11, 20], 0), np.delete(qd, [11, 20], 0),
                  np.delete(qdd, [11, 20], 0))[1]
    assert not np.isnan(a).any() and not np.isnan(b).any()
    assert np.abs(a - b).max() <= 1e-12 * np.abs(b).max()
    assert np.all(a >= clean - 1e-12 * np.abs(clean).max())   # the other set points' peaks


def test_the_engine_follows_the_trajectory_length_only():
    assert peaks_kernel("auto", COMPILED_MIN_SETPOINTS - 1) is atom_peaks_arrays
    assert peaks_kernel("numpy", 10 ** 6) is atom_peaks_arrays
    assert peaks_kernel("auto", COMPILED_MIN_SETPOINTS) is not atom_peaks_arrays
    assert peaks_kernel("compiled", 1) is not atom_peaks_arrays
    with pytest.raises(ValueError, match="engine"):
        peaks_kernel("fortran", 1)
