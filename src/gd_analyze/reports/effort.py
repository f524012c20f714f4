"""Effort limits: each joint's peak |tau| against the limit its robot gives.

One place for the CLI summary and the report (Sec. 1.2): :func:`effort_rows` reads the stored
dataset's ``tau_peak`` and ``tau_max`` and computes nothing else.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .common import torque_units

if TYPE_CHECKING:
    import xarray as xr

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


def effort_rows(ds: xr.Dataset) -> list[EffortRow]:
    """Each joint with an effort limit: its peak |tau| against the limit.

    Parameters
    ----------
    ds : xarray.Dataset
        A main-job dataset with ``tau_peak`` and ``tau_max``, shape (n,) [N m; N for a
        prismatic joint] (``tau_max`` NaN where the robot gives none).

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
    if "tau_max" not in ds.variables:
        return []
    peak = np.asarray(ds["tau_peak"].values, float)
    limit = np.asarray(ds["tau_max"].values, float)
    units = torque_units(ds)
    rows = []
    for j in range(peak.size):
        if not (math.isfinite(limit[j]) and limit[j] > 0):
            continue
        ratio = peak[j] / limit[j]
        rows.append(EffortRow((j + 1, float(peak[j]), float(limit[j]), float(ratio),
                               EXCEEDED if ratio > 1.0 else WITHIN,
                               units[j])))
    return rows
