"""The identification regressor's columns: their names, the robot file's values, the rows used.

The regressor itself is :func:`gd_analyze.symbolic.drive_regressor.identification_regressor`
with :meth:`~gd_analyze.symbolic.drive_regressor.IdentificationColumns.keeping_all`:
tau = Y_b(q, qd, qdd) beta + sum over the drive kinds of diag(x_kind) d_kind, with per joint i

- armature Ia_i: x = qdd_i [kg m^2; kg prismatic];
- viscous friction F_v,i: x = qd_i [N m s/rad; N s/m];
- Coulomb friction F_c,i: x = sign(qd_i) [N m; N], not smoothed: the robot file's drive model
  (:func:`gd_analyze.model.drives.friction_torque`, sign(0) = 0), so that the identified
  robot file reproduces the identified model; rows at rest are left out of the fit instead
  (:func:`moving_rows`);
- offset o_i: x = 1 [N m; N], a constant torque (sensor or current offset).

Y_b and beta are the package's base regressor (Gautier 1990;
:func:`gd_analyze.dynamics.base_parameters.base_regressor`).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from ..symbolic.drive_regressor import DRIVE_COLUMNS

if TYPE_CHECKING:
    from ..dynamics.base_parameters import BaseParameters
    from ..model.robot import Robot

__all__ = ["DRIVE_KINDS", "column_names",
           "prior_values", "moving_rows", "IDLE_FRACTION"]

#: The drive column kinds, in the order of the columns (the one drive regressor's,
#: :func:`gd_analyze.symbolic.drive_regressor.drive_regressor`).
DRIVE_KINDS = DRIVE_COLUMNS
#: The robot's field of each drive kind.
_FIELD = {"armature": "armature", "viscous": "viscous", "coulomb": "coulomb",
          "offset": "torque_offset"}
#: A joint is at rest in a sample when |qd_i| is below this fraction of its 99th percentile.
IDLE_FRACTION = 0.02


def column_names(base: BaseParameters, n: int,
                 kinds: Sequence[str]) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """Names and kinds of the identification regressor's columns.

    Parameters
    ----------
    base : BaseParameters
        The arm's base parameters.
    n : int
        Joints.
    kinds : sequence of str
        The drive kinds.

    Returns
    -------
    names, column_kinds : tuple of str
        ``("ZZ1", ..., "viscous_1", ...)`` and ``("base", ..., "viscous", ...)``.
    """
    names = list(base.names())
    col_kinds = ["base"] * len(names)
    for kind in kinds:
        names += [f"{kind}_{j + 1}" for j in range(n)]
        col_kinds += [kind] * n
    return tuple(names), tuple(col_kinds)


def prior_values(base: BaseParameters, robot: Robot,
                 kinds: Sequence[str]) -> npt.NDArray[np.float64]:
    """The robot file's values of the columns: its beta and its drives (offset: its
    ``torque_offset``).

    Parameters
    ----------
    base : BaseParameters
    robot : Robot
    kinds : sequence of str

    Returns
    -------
    ndarray, shape (b + n len(kinds),)
    """
    return np.concatenate([np.asarray(base.beta, float)]
                          + [np.asarray(getattr(robot, _FIELD[kind]), float) for kind in kinds])


def moving_rows(qd: npt.NDArray[np.float64],
                threshold: npt.NDArray[np.float64] | None = None) -> tuple[npt.NDArray[np.bool_], npt.NDArray[np.float64]]:
    """The rows (sample, joint) with the joint moving: |qd_i| >= its idle threshold.

    At rest a joint's torque holds an unknown static friction anywhere in [-F_s, F_s], which
    sign(qd) cannot model: those rows are left out of the fit (they still count in the
    prediction errors).

    Parameters
    ----------
    qd : ndarray, shape (N, n)
        Velocities [rad/s or m/s].
    threshold : ndarray, shape (n,), optional
        The idle thresholds; default :data:`IDLE_FRACTION` x the 99th percentile of |qd_i|.

    Returns
    -------
    used : ndarray of bool, shape (N, n)
    threshold : ndarray, shape (n,)
    """
    qd = np.abs(np.asarray(qd, float))
    if threshold is None:
        threshold = IDLE_FRACTION * np.percentile(qd, 99, axis=0)
    return qd >= np.maximum(threshold, 1e-300), np.asarray(threshold, float)
