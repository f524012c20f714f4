"""How large the explicit G-D model of an arm would be, estimated before expanding it.

The explicit model (:func:`gd_analyze.symbolic.explicit.derive`) writes D, h and c as sums of
coefficients times cos or sin of integer combinations of the joint angles. Its size grows
roughly geometrically with the joints whose angles the elements depend on: D_ij and the
Christoffel terms of h, taken in body frame i, depend on the angles of the joints after i
(Eq. (3.4-25) and the module docstring of :mod:`gd_analyze.symbolic.explicit`). How many harmonics
each such angle brings depends on the geometry: an axis parallel to the one before (DH twist 0)
lets the angles combine (cos(q2 + q3)) instead of multiplying, a perpendicular one does not,
and every nonzero offset of the joint placement, of the centre of mass or product of inertia
adds couplings that do not cancel. :func:`estimate_terms` turns this into a number in
microseconds, without any symbolic work, so that a caller can decide whether the expansion is
worth starting (:data:`EXPENSIVE_TERMS`).

Calibration (``len(model_terms(derive(robot)))``, measured on this machine; estimate / real):
two-link 14 (0.86), PUMA 560 1,630 (1.75), Stanford 1,049 (2.67), UR5 1,297 (0.69), UR3 1,173
(0.76), UR10 1,080 (0.83), SO-100 6,131 (0.79), finger_edu 62 (1.44), TwoDofs 11 (1.09), Kinova
16,893 (0.38), Z1 36,444 (1.64), Panda 418,774 (0.74): every estimate within a factor
:data:`ESTIMATE_FACTOR` of the real count. The factors below are a least-squares fit of log
counts on these twelve arms. Arms not used in the fit (estimate / real): SO-101 10,349 (1.85),
borinot flying arm 15 (0.93), hextilt flying arm 905 (2.09), TALOS left arm 412,034 (0.59;
53 s of derivation), xArm7 573,168 (0.45; 129 s). Derivation times: under 1 s for the 6-joint
arms above except SO-101 (3.6 s) and Kinova (1.2 s); Z1 3.8 s, Panda 19 s (two shared cores).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ..model.robot import Robot

__all__ = ["estimate_terms", "is_expensive", "EXPENSIVE_TERMS", "ESTIMATE_FACTOR", "MAX_TERMS"]

#: Above this many estimated terms the explicit expansion is not started by default: the arms
#: whose explicit model pays (PUMA 560, Stanford, UR3/5/10, SO-100: 1,000 to 6,100 terms,
#: derived in under a second) lie far below it, the Panda (418,774 terms; 19 s of derivation,
#: minutes for the main job) far above. It leaves a margin of :data:`ESTIMATE_FACTOR` over the
#: largest cheap arm measured.
EXPENSIVE_TERMS = 20_000
#: The calibrated arms' estimates are within this factor of their real counts (both ways).
ESTIMATE_FACTOR = 3.0
#: Above this many estimated terms the explicit model is not derived even when asked for
#: (``--explicit always``, ``--form explicit``, ``--rule chapter``): five times the Panda's
#: 418,774 terms (minutes for the main job); a random 12-joint chain is estimated at 3.3e9, and
#: its expansion ran 19 minutes without an end before it was stopped.
MAX_TERMS = 2_000_000

# Fitted factors (module docstring): per later joint whose axis is parallel to the one before,
# per other later joint, per nonzero offset of its link, and the overall scale.
_PARALLEL = 0.67
_CROSSED = 1.63
_PER_OFFSET = 0.18
_SCALE = 1.38


def estimate_terms(robot: Robot) -> int:
    """Estimate the number of terms of an arm's explicit G-D model without deriving it.

    Parameters
    ----------
    robot : Robot
        The arm: joint placements (``rotation`` P_i (n, 3, 3), ``translation`` t_i (n, 3)
        [m]), ``body_com`` (n, 3) [m] and ``body_inertia`` (n, 3, 3) [kg m^2].

    Returns
    -------
    int
        Estimated ``len(model_terms(derive(robot)))``: within a factor
        :data:`ESTIMATE_FACTOR` of it on the calibrated arms (module docstring) and on random
        chains of revolute joints (0.85 to 0.91 of it for 2 to 5 joints); above it with
        prismatic joints, each counted as a revolute one (2.7 to 4.7 times it on random
        chains of 3 to 5 joints, every third one prismatic). Measured by
        ``tests/symbolic/test_explicit_estimate.py``.

    Notes
    -----
    Each joint k > 1 brings a factor f_k = (0.67 if its axis is parallel to joint k-1's, else
    1.63) x (1 + 0.18 x its link's nonzero offsets); the elements D_ij (i <= j) and the
    Christoffel terms C_ijk (j <= k) of h depend on the angles after min(i, j, k), so the
    estimate is 1.38 x (sum over D_ij of M_i + sum over C_ijk of M_min(i,j,k)) with
    M_i = prod_{k > i} f_k. Source: the structure of Eqs. (3.4-25) to (3.4-27) of Fu,
    Gonzalez & Lee (1987) as derived in :mod:`gd_analyze.symbolic.explicit`; the factors are fitted.

    Examples
    --------
    >>> from gd_analyze import load_robot
    >>> estimate_terms(load_robot("two-link"))
    12
    >>> 500 < estimate_terms(load_robot("puma560")) < 5000
    True
    """
    n = robot.n
    axis_z = np.abs(np.asarray(robot.rotation, float)[:, 2, 2])
    # per link: nonzero placement offsets, centre-of-mass offsets and products of inertia
    inertia = np.asarray(robot.body_inertia, float)
    products = np.abs(inertia - np.einsum("kii->ki", inertia)[:, :, None] * np.eye(3)) > 1e-12
    offsets = (np.abs(np.asarray(robot.translation, float)) > 1e-12).sum(axis=1) + (np.abs(
        np.asarray(robot.body_com, float)) > 1e-12).sum(axis=1) + products.sum(axis=(1, 2)) // 2
    f = np.where(np.isclose(axis_z, 1.0), _PARALLEL, _CROSSED) * (1 + _PER_OFFSET * offsets)
    M = np.array([np.prod(f[i + 1:]) for i in range(n)])
    d = sum((n - i) * M[i] for i in range(n))
    # C_ijk, j <= k: min(i, j, k) = m for the (i, j, k) whose smallest index is m
    pairs = np.array([[sum(1 for j in range(n) for k in range(j, n) if min(i, j, k) == m)
                       for m in range(n)] for i in range(n)]).sum(axis=0)
    return int(round(_SCALE * (d + float(pairs @ M))))


def is_expensive(robot: Robot) -> bool:
    """Whether an arm's explicit expansion is estimated too large to start by default.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    bool
        :func:`estimate_terms` > :data:`EXPENSIVE_TERMS`.

    Examples
    --------
    >>> from gd_analyze import load_robot
    >>> is_expensive(load_robot("puma560"))
    False
    """
    return estimate_terms(robot) > EXPENSIVE_TERMS
