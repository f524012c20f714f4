"""The budget rule's merged model of a sweep: the cheapest form within EPS on every swept trajectory.

Issue 29: the sweep used to merge in the explicit G-D form only, which costs more than the
exact customized recursive Newton-Euler model on every arm measured (the Panda's 97,074
operations against 610). Here the recursive model is pruned over all swept trajectories
together (:func:`recursive_sweep_model`), from the peaks of its (base parameter, part)
contributions that the dask workers computed per trajectory
(:func:`gd_analyze.workflows.sweep.run_sweep` with ``recursive_peaks=True``), each taken
relative to its own trajectory's scale, so that the budget holds on every one of them. The
explicit model (:func:`gd_analyze.workflows.simplify.explicit_sweep_model`) is derived only where
its expansion is estimated cheap (:func:`gd_analyze.core.symbolic.explicit_estimate.is_expensive`),
as the main job does, and deployed only where it counts fewer operations
(:func:`budget_sweep_model`). The deployed model never costs more than the exact recursive
model: at worst it is that model (:func:`gd_analyze.core.symbolic.pruning.pruned_program`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..core.selection.budget import DEFAULT_TOLERANCE
from ..errors import InputError
from .options import EXPLICIT, FORMS

__all__ = ["pair_peaks", "recursive_sweep_model", "budget_sweep_model"]


def pair_peaks(sweep_ds):
    """The per-trajectory peaks of the recursive model's contributions stored in a sweep.

    Parameters
    ----------
    sweep_ds : xarray.Dataset
        From :func:`gd_analyze.workflows.sweep.run_sweep` with ``recursive_peaks=True``.

    Returns
    -------
    tau_peak : ndarray, shape (K, n)
        Peak |tau_i| on each trajectory [N m or N].
    peak : ndarray, shape (K, b, 3, n)
        Peak |contribution| of each (base parameter, part) on each trajectory [N m or N].
    whole_peak : ndarray, shape (K, b, n)
        The same per base parameter [N m or N].

    Raises
    ------
    InputError
        If the dataset does not hold them.
    """
    names = ("pair_tau_peak", "pair_peak", "parameter_peak")
    missing = [v for v in names if v not in sweep_ds.variables]
    if missing:
        raise InputError("the sweep holds no peaks of the recursive model's contributions "
                         "(run_sweep(..., recursive_peaks=True)): missing " + ", ".join(missing))
    return tuple(np.asarray(sweep_ds[v].values, float) for v in names)


def recursive_sweep_model(robot, scale, peak, whole_peak, tolerance=DEFAULT_TOLERANCE,
                          torque_floor=0.0, trajectory_sha256="", provenance=None, base=None):
    """The pruned recursive model within EPS x scale_{t,i} on each of K trajectories.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    scale : array_like, shape (K, n)
        scale_{t,i} = max(peak |tau_i| on t, TAU) [N m or N].
    peak : array_like, shape (K, b, 3, n)
        Per trajectory, a bound on |contribution| of each (base parameter, part): its peak
        there (:func:`gd_analyze.core.symbolic.pruning.stacked_peaks`), or a bound proved on a
        region of states, which the guarantee then carries over [N m or N].
    whole_peak : array_like, shape (K, b, n)
        The same per base parameter, all parts together [N m or N].
    tolerance : float, optional
        EPS >= 0.
    torque_floor : float, optional
        TAU [N m], recorded with the model (``scale`` already holds it).
    trajectory_sha256 : str, optional
        Digest of the trajectories (:func:`gd_analyze.workflows.simplify.trajectories_sha256`).
    provenance : dict, optional
    base : BaseParameters, optional
        The robot's base parameters (those the peaks are of); derived if not given.

    Returns
    -------
    model : SimplifiedModel
        Of the recursive form (:func:`gd_analyze.workflows.deploy.recursive_simplified`),
        ``validation`` empty.
    bound : ndarray, shape (K, n)
        The guaranteed bound on |tau_s - tau| on each trajectory: the dropped units' peaks
        there [N m or N], at most EPS x scale.

    Raises
    ------
    ValueError
        As :func:`gd_analyze.core.symbolic.pruning.prune_on_peaks`.

    Notes
    -----
    :func:`gd_analyze.core.symbolic.recursive_model.sweep_recursive_model`; Fu, Gonzalez & Lee
    (1987), Algorithm 3.1 on the base parameters (Khalil & Kleinfinger 1987; Gautier 1990).
    """
    from ..core.symbolic.base_parameters import base_parameters
    from ..core.symbolic.recursive_model import sweep_recursive_model
    from .deploy import recursive_simplified

    base = base_parameters(robot) if base is None else base
    rec, each = sweep_recursive_model(robot, scale, peak, whole_peak, tolerance, base=base)
    model = recursive_simplified(robot, rec, base, tolerance=tolerance,
                                 torque_floor=torque_floor, trajectory_sha256=trajectory_sha256,
                                 provenance=provenance)
    return model, each.sum(axis=1)


def budget_sweep_model(robot, trajectories, sweep_ds, tolerance=DEFAULT_TOLERANCE,
                       torque_floor=0.0, held_out=(), provenance=None, explicit="auto",
                       form="cheapest"):
    """The sweep's merged model of the budget rule: the cheapest form within EPS on each
    swept trajectory.

    Parameters
    ----------
    robot : Robot
        The arm the sweep ran on (with its payload, if any).
    trajectories : sequence of Trajectory
        The K swept trajectories, in the dataset's order.
    sweep_ds : xarray.Dataset
        The sweep (:func:`gd_analyze.workflows.sweep.run_sweep` with ``recursive_peaks=True``).
    tolerance : float, optional
        EPS >= 0.
    torque_floor : float, optional
        TAU [N m]: scale_{t,i} = max(peak |tau_i| on t, TAU).
    held_out : sequence of Trajectory, optional
        Trajectories not swept: the error there is measured, not guaranteed.
    provenance : dict, optional
    explicit : {"auto", "always", "never"}, optional
        Derive the explicit model too: where its expansion is estimated cheap (default),
        always, or never.
    form : {"cheapest", "recursive", "explicit"}, optional
        The model returned: the cheaper of the two (default), or that form (explicit: derived
        whatever ``explicit`` says), as the main job's ``--form``.

    Returns
    -------
    SimplifiedModel
        With ``form="cheapest"`` the recursive model, or the explicit one where it counts
        fewer operations (multiplications + additions; the recursive one on a tie), so never
        more than the exact recursive model; ``costs`` holds the
        counts of both candidates, the exact recursive model and Newton-Euler; ``validation``
        as :func:`gd_analyze.workflows.simplify.sweep_validation`, ``per_trajectory["bound"]``
        the bound on each trajectory [N m].

    Raises
    ------
    InputError
        If the dataset holds no recursive peaks.
    ValueError
        If ``explicit`` or ``form`` is unknown, or the trajectories do not match the dataset.

    Notes
    -----
    Source: the budget of :mod:`gd_analyze.core.selection.budget` over several trajectories;
    Sec. 3.4.1 of Fu, Gonzalez & Lee (1987) (a simplified model "at a reduced computation
    time").
    """
    from ..core.selection.positive_definite import with_inertia_check
    from ..core.symbolic.explicit_estimate import is_expensive
    from ..formulations.opcount import operation_counts
    from .simplify import (
        explicit_sweep_model,
        full_torque,
        sweep_validation,
        total_operations,
        trajectories_sha256,
    )

    if explicit not in EXPLICIT:
        raise ValueError(f"explicit must be one of {EXPLICIT}, got {explicit!r}")
    if form not in FORMS:
        raise ValueError(f"form must be one of {FORMS}, got {form!r}")
    trajectories = list(trajectories)
    tau_peak, peak, whole_peak = pair_peaks(sweep_ds)
    if tau_peak.shape[0] != len(trajectories):
        raise ValueError(f"{len(trajectories)} trajectories for a sweep of {tau_peak.shape[0]}")
    provenance = {**(provenance or {}), "kind": "sweep model", "trajectories": len(trajectories)}
    digest = trajectories_sha256(trajectories)
    scales = np.maximum(tau_peak, float(torque_floor))
    model, bound = recursive_sweep_model(robot, scales, peak, whole_peak, tolerance,
                                         torque_floor, digest, provenance)
    with np.errstate(divide="ignore", invalid="ignore"):
        relative = np.where(bound > 0, bound / scales, 0.0).max(axis=0)
    ne = operation_counts(robot)["newton-euler"]
    costs = {"exact recursive": model.costs["exact recursive"],
             "recursive, budget": dict(model.cost),
             "newton-euler": {"multiplications": int(ne["multiplications"]),
                              "additions": int(ne["additions"])}}
    reference = None                           # the G-D terms, D qdd + h + c
    if form == "explicit" or explicit == "always" or (
            explicit == "auto" and not is_expensive(robot)):
        ex, _, ex_scales, ex_relative, terms = explicit_sweep_model(
            robot, trajectories, tolerance, torque_floor, provenance)
        costs.update({"explicit, budget": dict(ex.cost), "explicit, full": dict(ex.full_cost)})
        if form == "explicit" or (form == "cheapest" and total_operations(ex.cost) < total_operations(model.cost)):
            model, scales, relative, bound = ex, ex_scales, ex_relative, None
            reference = full_torque(robot, terms)
    model = dataclasses.replace(model, costs=costs,
                                full_cost=dict(costs.get("explicit, full", model.full_cost)))
    # D_s positive definite on the swept positions (issue 30), before the model is measured
    model = with_inertia_check(model, np.concatenate([t.q for t in trajectories]))
    validation = sweep_validation(model, trajectories, scales, relative, held_out=held_out,
                                  reference=reference, bound=bound)
    return dataclasses.replace(model, validation=validation,
                               guarantee=sweep_guarantee(robot, model, trajectories, scales,
                                                         relative, tolerance))


def sweep_guarantee(robot, model, trajectories, scales, relative, tolerance):
    """The merged model's guarantee: on the swept trajectories only (issue 29).

    Parameters
    ----------
    robot : Robot
    model : SimplifiedModel
        The merged model.
    trajectories : sequence of Trajectory
        The K swept trajectories.
    scales : ndarray, shape (K, n)
        scale_{t,i} [N m or N].
    relative : ndarray, shape (n,)
        max over t of bound_{t,i} / scale_{t,i} [1].
    tolerance : float
        EPS.

    Returns
    -------
    Guarantee
        Of kind ``"trajectory"``: ``scale`` the largest scale_{t,i} over the trajectories,
        ``bound`` ``relative`` times it (on trajectory t the error is at most relative_i
        scale_{t,i}); for the recursive form the error sampled over the robot's region
        relative to s_i there, where the robot gives the limits.
    """
    from ..core.selection.guarantee import Guarantee
    from ..core.symbolic.base_parameters import base_parameters
    from .deploy import robot_region, trajectory_guarantee

    scale = np.asarray(scales, float).max(axis=0)
    bound = np.asarray(relative, float) * scale
    shas = tuple(getattr(t, "sha256", "") or "" for t in trajectories)
    method = ("the dropped pairs' (or terms') largest peaks relative to each swept "
              "trajectory's scale_i, summed (triangle inequality)")
    region, missing = robot_region(robot)
    sampled = None
    if model.recursive is not None and region is not None:
        sampled = trajectory_guarantee(robot, base_parameters(robot), model.recursive,
                                       tolerance, region=region).region_sampled_error
    return Guarantee("trajectory", float(tolerance), bound=bound, scale=scale,
                     trajectories_sha256=shas, region_sampled_error=sampled,
                     region_missing=missing, method=method)
