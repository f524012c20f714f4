"""Payload sweeps: how the dominance ranking moves with a load fixed to the last link.

:func:`payload_sweep` ranks one trajectory for each load mass (the main job's
``--payload-sweep``); :func:`sweep_payloads` repeats a whole sweep over many trajectories for each
load mass (``gd-analyze sweep --payload-sweep``). The load is merged into link n by
:func:`gd_analyze.model.robot.with_payload`. Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..model.robot import with_payload
from ..ranking.ranking import CLASSES, DEFAULT_DOMINANCE, DEFAULT_NEGLIGIBLE
from ..store.sweep_view import payload_dataset, sweep_payloads_dataset
from .sweep import analyze_one, run_sweep

if TYPE_CHECKING:
    import xarray as xr

    from ..model.robot import Robot
    from ..trajectory.trajectory import Trajectory

__all__ = ["payload_sweep", "sweep_payloads"]


def payload_sweep(robot: Robot, trajectory: Trajectory, masses: ArrayLike,
                  com: ArrayLike = (0.0, 0.0, 0.0), inertia: ArrayLike = (0.0, 0.0, 0.0),
                  dominance: float = DEFAULT_DOMINANCE,
                  negligible: float = DEFAULT_NEGLIGIBLE) -> xr.Dataset:
    """Rank one trajectory for a range of payloads fixed to the last link.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    trajectory : Trajectory
        t (N,) [s]; q, qd, qdd (N, n) [rad, rad/s, rad/s^2].
    masses : array_like, shape (P,)
        Payload masses [kg], >= 0, distinct (e.g. ``parse_range("0:2.5:0.5")``).
    com : array_like, shape (3,), optional
        Payload centre of mass in link frame n [m].
    inertia : array_like, shape (3,) or (3, 3), optional
        Payload inertia about its centre of mass, axes of link frame n [kg m^2].
    dominance : float, optional
        s, in (0.5, 1].
    negligible : float, optional
        e, >= 0.

    Returns
    -------
    xarray.Dataset
        Dims ``payload`` (P; coordinate = masses [kg]), ``element`` (M), ``joint`` (n):
        ``share_tran``, ``dominance``, ``choice``, ``peak_total`` and ``round_off`` (1 where
        every part of the element is round-off of its scale: its share is noise) (payload,
        element);
        ``tau_peak`` = peak |tau| [N m] and ``tau_error_relative_peak`` of each payload's own
        simplified model (payload, joint). Units and long names on every variable; global
        attributes as for :func:`run_sweep`, plus the payload's com and inertia and the
        trajectory's source and SHA-256.

    Raises
    ------
    InputError
        If masses is empty, not 1-D, has duplicates, or a mass is negative or not finite, or
        the inertia is not symmetric positive semi-definite.
    ValueError
        If the trajectory does not fit the robot or a threshold is out of range.

    Notes
    -----
    Each payload is merged into link n by :func:`gd_analyze.model.robot.with_payload`; the load
    changes link n's mass, centre of mass and inertia and so the G-D terms. Source: Sec. 3.4.1
    of Fu, Gonzalez & Lee (1987) (the simplification "depends on the specific trajectory");
    the load enters the dynamics as in Sec. 3.1.
    """

    masses = np.asarray(masses, dtype=float)
    if masses.ndim != 1 or masses.size == 0:
        raise InputError("the payload masses must be a non-empty list", column="--payload-sweep")
    if np.unique(masses).size != masses.size:
        raise InputError("the payload masses must be distinct", column="--payload-sweep")
    results = [analyze_one(with_payload(robot, m, com, inertia), trajectory, dominance,
                           negligible) for m in masses]
    return payload_dataset(robot, trajectory, masses, com, inertia, results, dominance,
                           negligible)


def sweep_payloads(robot: Robot, trajectories: Sequence[Trajectory], masses: Sequence[float],
                   com: ArrayLike = (0.0, 0.0, 0.0), inertia: ArrayLike = (0.0, 0.0, 0.0),
                   dominance: float = DEFAULT_DOMINANCE, negligible: float = DEFAULT_NEGLIGIBLE,
                   client: Any = None, in_process: bool = False) -> xr.Dataset:
    """Repeat a sweep for each load mass: how the classes over many trajectories move with it.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints, without the load.
    trajectories : sequence of Trajectory
        The sweep's trajectories.
    masses : sequence of float
        Load masses [kg], >= 0.
    com : array_like, shape (3,), optional
        Load centre of mass in link frame n [m].
    inertia : array_like, shape (3,), optional
        Load principal moments about its centre of mass [kg m^2].
    dominance, negligible : float, optional
        s and e of the ranking.
    client : distributed.Client
        The cluster to run on (see :func:`~gd_analyze.jobs.dask_cluster.dask_client`).
    in_process : bool, optional
        Rank in this process, without a cluster (``client`` None), as :func:`run_sweep`.

    Returns
    -------
    xarray.Dataset
        Dims ``payload`` (P), ``element`` (M), ``class``, ``joint``: ``class_fraction``
        (payload, element, class), ``share_tran`` (payload, element) = the median over the
        trajectories, ``dominance`` (payload, element) = the most frequent class, ``choice``
        (payload, element) = the merged choice of the chapter rule, ``round_off`` (payload,
        element) = round-off on every trajectory, ``tau_peak`` (payload, joint) =
        peak |tau| over all trajectories [N m].

    Raises
    ------
    InputError
        If a mass or the load's inertia is invalid.
    ValueError
        As :func:`run_sweep`.

    Notes
    -----
    Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987), repeated for each load.
    """

    trajectories = list(trajectories)
    parts = []
    for mass in masses:
        ds = run_sweep(with_payload(robot, mass, com, inertia), trajectories, dominance,
                       negligible, client=client, in_process=in_process)
        frac = ds["class_fraction"].values
        parts.append((frac, ds["share_tran_median"].values,
                      np.array(CLASSES)[np.argmax(frac, axis=1)],
                      np.asarray(ds["merged_choice"].values, dtype=str),
                      ds["merged_error_tau_peak"].values,
                      ds["round_off"].values.astype(bool).all(axis=0)))
    return sweep_payloads_dataset(robot, len(trajectories), masses, com, inertia, parts,
                                  dominance, negligible)
