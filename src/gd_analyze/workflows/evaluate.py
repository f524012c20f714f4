"""Evaluate a simplified model on a trajectory: its torque error against the full model.

``gd-analyze evaluate MODEL.json TRAJECTORY.csv`` checks a model made on one trajectory along
another, optionally with the arm carrying a load the model does not know. Source: Sec. 3.4.1 of
Fu, Gonzalez & Lee (1987), whose simplified model "depends on the specific trajectory being
considered"; terms from Eqs. (3.4-24) to (3.4-28).
"""

from __future__ import annotations

import numpy as np

from ..core.dynamics.dalembert import gd_terms
from ..core.model.limits import check_finite
from ..core.selection.simplified import torque_error
from ..errors import InputError

__all__ = ["evaluate", "model_torque"]


def model_torque(model, q, qd, qdd):
    """A simplified model's torques, refused where they are not finite.

    Parameters
    ----------
    model : SimplifiedModel
        The model (e.g. read from a hand-edited file).
    q, qd, qdd : ndarray, shape (N, n)
        Set points [rad, rad/s, rad/s^2].

    Returns
    -------
    ndarray, shape (N, n)
        tau_s [N m], all finite.

    Raises
    ------
    InputError
        If a torque is NaN or inf: the model's coefficients (``explicit_terms.coef``) are
        beyond the range of a float once multiplied out (a coefficient of 1e308, say).

    Notes
    -----
    Source: the simplified model tau_s = D_s qdd + h_s + c of Fu, Gonzalez & Lee (1987),
    Sec. 3.4.1, Eq. (3.4-24).
    """
    with np.errstate(over="ignore", invalid="ignore"):
        tau = np.asarray(model.torque(q, qd, qdd), float)
    bad = ~np.isfinite(tau)
    if bad.any():
        k, j = (int(v[0]) for v in np.nonzero(bad))
        raise InputError(f"the model's torque is not finite at set point {k + 1}, joint {j + 1}: "
                         "its explicit_terms.coef are beyond the range of a float")
    return tau


def evaluate(model, trajectory, plant=None):
    """The torque error of a simplified model along a trajectory.

    Parameters
    ----------
    model : SimplifiedModel
        The model (its robot and its explicit kept terms, evaluated by
        :meth:`~gd_analyze.core.selection.simplified.SimplifiedModel.torque`).
    trajectory : Trajectory
        q, qd, qdd of shape (N, n) [rad, rad/s, rad/s^2].
    plant : Robot, optional
        The arm that really moves (e.g. the model's robot carrying a payload, see
        :func:`gd_analyze.core.model.robot.with_payload`); default the model's robot.

    Returns
    -------
    dict
        :func:`gd_analyze.core.selection.simplified.torque_error` of the model's torque against the
        plant's full torque (per joint ``peak_abs_error``, ``rms_error``, ``peak_tau`` [N m],
        ``relative_peak_error``, ``relative_rms_error``), plus ``max_relative_peak_error``, the
        largest relative peak error over the joints (0 if no joint has a defined one).

    Raises
    ------
    ValueError
        If the trajectory does not have n columns.
    InputError
        If the torques are not finite (inputs beyond :data:`gd_analyze.core.model.limits.LIMITS`, or
        the model's coefficients beyond a float: :func:`model_torque`).
    """
    robot = model.robot
    plant = robot if plant is None else plant
    full = gd_terms(plant, trajectory.q, trajectory.qd)
    err = torque_error(model_torque(model, trajectory.q, trajectory.qd, trajectory.qdd),
                       check_finite("tau", full.tau(trajectory.qdd)))
    rel = np.array([np.nan if v is None else v for v in err["relative_peak_error"]], float)
    err["max_relative_peak_error"] = float(np.nanmax(rel)) if np.isfinite(rel).any() else 0.0
    return err
