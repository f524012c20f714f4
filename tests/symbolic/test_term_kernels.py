"""The atom peaks (term_peaks through the compiled term_kernels.atom_peaks_kernel) against the
definition evaluated term by term, and their contributions against Pinocchio's rnea."""

import numpy as np
import pytest
from symbolic_helpers import rnea, robot, states

from gd_analyze.store.explicit_cache import explicit_terms
from gd_analyze.symbolic.explicit import atoms, term_peaks


def _contributions(arm, merged, atom, q, qd, qdd):
    """(N, A, n): each atom's signed contribution to each joint torque, term by term: the
    harmonic C cos/sin(K . q) (times q_m^K_m on a prismatic column); D_ij sends qdd_j to
    tau_i and qdd_i to tau_j (i != j), the coefficient of qd_j qd_k in h_i sends qd_j qd_k to
    tau_i, c_i goes to tau_i (Eq. (3.4-24))."""
    N, n = q.shape
    out = np.zeros((N, int(atom.max()) + 1, n))
    lin = np.asarray(arm.prismatic, bool)
    for r in range(len(merged)):
        K = merged.K[r]
        ang = q[:, ~lin] @ K[~lin]
        v = merged.C[r] * (np.sin(ang) if merged.S[r] else np.cos(ang))
        v = v * np.prod(q[:, lin] ** K[lin], axis=1)
        i, j, k = merged.i[r], merged.j[r], merged.k[r]
        if merged.kind[r] == "D":
            out[:, atom[r], i] += v * qdd[:, j]
            if i != j:
                out[:, atom[r], j] += v * qdd[:, i]
        elif merged.kind[r] == "h":
            out[:, atom[r], i] += v * qd[:, j] * qd[:, k]
        else:
            out[:, atom[r], i] += v
    return out


@pytest.mark.parametrize("name", ("puma560", "stanford"))
def test_atom_peaks_are_the_peaks_of_the_term_by_term_contributions(name):
    arm = robot(name)
    terms, _ = explicit_terms(arm)
    merged, atom = atoms(terms)
    q, qd, qdd = states(arm, 40, 4)
    C = _contributions(arm, merged, atom, q, qd, qdd)
    tau = rnea(arm, q, qd, qdd)
    scale = np.abs(tau).max()
    assert np.abs(C.sum(axis=1) - tau).max() <= 1e-9 * scale      # the atoms make up tau
    peaks = term_peaks(terms, np.zeros(arm.n), q, qd, qdd, chunk=7, prismatic=arm.prismatic)
    np.testing.assert_allclose(peaks, np.abs(C).max(axis=0), rtol=1e-12, atol=1e-13 * scale)


def test_a_nan_set_point_is_never_a_peak():
    """NaN velocities or accelerations at a set point: a NaN contribution is never a peak (the
    kernel's ``if v > peak``); the peaks keep those of the other set points."""
    arm = robot("stanford")
    terms, _ = explicit_terms(arm)
    q, qd, qdd = states(arm, 30, 6)
    qd[11, 2] = np.nan
    qdd[20] = np.nan
    got = term_peaks(terms, np.zeros(arm.n), q, qd, qdd, prismatic=arm.prismatic)
    keep = np.setdiff1d(np.arange(30), [11, 20])
    clean = term_peaks(terms, np.zeros(arm.n), q[keep], qd[keep], qdd[keep],
                       prismatic=arm.prismatic)
    assert not np.isnan(got).any()
    assert np.all(got >= clean - 1e-12 * np.abs(clean).max())
