"""Effort limits: each joint's peak |tau| against the limit its robot gives.

One place for the CLI summary and the report (Sec. 1.2): :func:`effort_rows` reads the stored
peak |tau| and effort limits (:class:`gd_analyze.store.results_view.Results`) and computes nothing
else.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..ranking.labels import joint_torque_units

if TYPE_CHECKING:
    from ..store.results_view import Results

__all__ = ["EffortRow", "effort_rows", "EXCEEDED", "WITHIN"]

#: The flag of a joint whose peak |tau| exceeds its effort limit, and of one within it.
EXCEEDED, WITHIN = "EXCEEDED", "within"


class EffortRow(tuple):
    """(joint, peak, limit, ratio, flag, units) of one joint with an effort limit."""

    __slots__ = ()

    @property
    def exceeded(self) -> bool:
        """bool: the peak |tau| is above the limit."""
        return self[4] == EXCEEDED


def effort_rows(results: Results) -> list[EffortRow]:
    """Each joint with an effort limit: its peak |tau| against the limit.

    Parameters
    ----------
    results : Results
        The main job's results: peak |tau| (its torque error table) and the effort limits
        (its robot), shape (n,) [N m; N for a prismatic joint] (a limit NaN where the robot
        gives none).

    Returns
    -------
    list of EffortRow
        One per joint whose limit is given: (joint number from 1, peak |tau|, limit,
        peak / limit, :data:`EXCEEDED` or :data:`WITHIN`, units); empty when the robot gives
        no limit (or the dataset predates them).

    Notes
    -----
    The limits are the URDF's ``<limit effort>`` or a robot file's ``tau_max``; peak |tau| is
    that of the full model, D qdd + h + c (Fu, Gonzalez & Lee 1987, Eq. (3.4-24)).
    """
    if results.robot_record.effort_limit is None:
        return []
    peak = results.torque_error.column("peak_tau").astype(float)
    limit = np.asarray(results.robot_record.effort_limit, float)
    units = [joint_torque_units(p) for p in results.prismatic]
    rows = []
    for j in range(peak.size):
        if not (math.isfinite(limit[j]) and limit[j] > 0):
            continue
        ratio = peak[j] / limit[j]
        rows.append(EffortRow((j + 1, float(peak[j]), float(limit[j]), float(ratio),
                               EXCEEDED if ratio > 1.0 else WITHIN,
                               units[j])))
    return rows
