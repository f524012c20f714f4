"""The merged model of a sweep under the budget rule: one model within EPS on every swept
trajectory, or proved over the joint-limit region.

On the trajectories (:func:`trajectory_merged_model`), the recursive model is pruned over all
of them together (:func:`gd_analyze.symbolic.recursive_model.sweep_recursive_model`) from the
peaks of its (base parameter, part) contributions on each trajectory, each relative to that
trajectory's scale, so that the budget holds on every one; the explicit model
(:func:`gd_analyze.simplify.sweep_model.explicit_sweep_model`) is built where its terms are
given and deployed where it counts fewer operations. Over the region
(:func:`region_merged_model`), the model is the main job's region model, which does not
depend on the trajectories. The deployed model never costs more than the exact recursive
model. Pure: the shell reads the peaks from the sweep's dataset and gives the explicit terms
and a :class:`~gd_analyze.simplify.region_memo.Derivations` store.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..certify.positive_definite import with_inertia_check
from ..dynamics.base_parameters import base_parameters
from ..symbolic.pruning import dropped_peaks, settle_restored
from ..symbolic.recursive_model import sweep_recursive_model
from .budget import DEFAULT_TOLERANCE
from .choices import sweep_choices
from .deploy import (
    rebuilt,
    recursive_simplified,
    region_search,
    restored_rebuild,
    trajectory_guarantee,
)
from .explicit_model import full_program, full_torque
from .form_choice import choose_form, exact_explicit_model, inertia_checked, recursive_costs
from .guarantee import Guarantee
from .region_memo import UNKEPT, Derivations
from .sweep_model import explicit_sweep_model, sweep_validation

if TYPE_CHECKING:                       # for the type hints only
    from numpy.typing import NDArray

    from ..certify.region import Region
    from ..model.robot import Robot
    from ..symbolic.explicit import Term
    from .choices import Motion
    from .explicit_model import TorqueFunction
    from .simplified import SimplifiedModel
    from .sweep_model import TrajectoryErrors

__all__ = ["trajectory_merged_model", "region_merged_model"]


def trajectory_merged_model(robot: Robot, trajectories: Sequence[Motion],
                            tau_peak: NDArray[np.float64], peak: NDArray[np.float64],
                            whole_peak: NDArray[np.float64],
                            tolerance: float = DEFAULT_TOLERANCE, torque_floor: float = 0.0,
                            held_out: Sequence[Motion] = (),
                            provenance: Mapping[str, Any] | None = None,
                            trajectories_digest: str = "", terms: Term | None = None,
                            form: str = "cheapest", region: Region | None = None,
                            region_missing: str = "", errors: TrajectoryErrors | None = None
                            ) -> SimplifiedModel:
    """The budget rule's merged model guaranteed on each swept trajectory.

    Parameters
    ----------
    robot : Robot
        The arm the sweep ran on, with n joints and b base parameters.
    trajectories : sequence of Motion
        The K swept trajectories, q, qd, qdd of shape (N_t, n).
    tau_peak : ndarray, shape (K, n)
        Peak |tau_i| on each trajectory [N m or N].
    peak : ndarray, shape (K, b, 3, n)
        Peak |contribution| of each (base parameter, part) on each trajectory [N m or N].
    whole_peak : ndarray, shape (K, b, n)
        The same per base parameter [N m or N].
    tolerance : float, optional
        EPS >= 0.
    torque_floor : float, optional
        TAU [N m]: scale_{t,i} = max(peak |tau_i| on t, TAU).
    held_out : sequence of Motion, optional
        Trajectories not swept: the error there is measured, not guaranteed.
    provenance : dict, optional
    trajectories_digest : str, optional
        :func:`gd_analyze.simplify.sweep_model.trajectories_sha256` of the trajectories.
    terms : Term, optional
        The robot's explicit terms: the explicit model is built from them and deployed where
        the form asks for it or it counts fewer operations; None: the recursive model only.
    form : {"cheapest", "recursive", "explicit"}, optional
        As :func:`gd_analyze.simplify.form_choice.choose_form` takes it.
    region : Region, optional
        The robot's joint-limit region: the recursive model's error is sampled there.
    region_missing : str, optional
        Why there is no region (for the guarantee's statement).
    errors : callable, optional
        How the errors along the trajectories are measured
        (:func:`gd_analyze.simplify.sweep_model.sweep_validation`).

    Returns
    -------
    SimplifiedModel
        Its guarantee of kind ``"trajectory"`` (scale: the largest scale_{t,i}); ``costs``
        the candidates' counts; ``validation`` as
        :func:`~gd_analyze.simplify.sweep_model.sweep_validation`; a recursive model's
        ``choices`` as :func:`gd_analyze.simplify.choices.sweep_choices` gives them.

    Notes
    -----
    Source: the budget of :mod:`gd_analyze.simplify.budget` over several trajectories;
    Sec. 3.4.1 of Fu, Gonzalez & Lee (1987).
    """
    scales = np.maximum(tau_peak, float(torque_floor))
    base = base_parameters(robot)
    rec, _ = sweep_recursive_model(robot, scales, peak, whole_peak, tolerance, base=base)
    model: Any = recursive_simplified(robot, rec, base, tolerance=tolerance,
                                      torque_floor=torque_floor, trajectory_sha256=trajectories_digest,
                                      provenance=provenance)
    costs = recursive_costs(model)
    reference, ex = None, None                  # the G-D terms, D qdd + h + c
    if terms is not None:
        ex, _, ex_scales, relative, _ = explicit_sweep_model(
            robot, trajectories, tolerance, torque_floor, provenance, terms)
        costs.update({"explicit, budget": dict(ex.cost), "explicit, full": dict(ex.full_cost)})
    if choose_form("budget", form, False, model.cost,
                   None if ex is None else ex.cost).form == "explicit":
        model, scales, reference = ex, ex_scales, full_torque(
            robot, terms)  # type: ignore[arg-type]  # explicit: its terms were given
    model = dataclasses.replace(model, costs=costs,
                                full_cost=dict(costs.get("explicit, full", model.full_cost)))
    # D_s positive definite on the swept positions, before the model is measured; a restore
    # derives the bound on each trajectory again for the pairs still dropped
    model = with_inertia_check(model, np.concatenate([t.q for t in trajectories]),
                               rebuild=_sweep_rebuild(peak, whole_peak, scales, tolerance))
    bound: Any = None                           # an explicit model's: relative x scales
    if model.recursive is not None:
        bound = _trajectory_bounds(peak, whole_peak, model.recursive.dropped).sum(axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            relative = np.where(bound > 0, bound / scales, 0.0).max(axis=0)
    validation = sweep_validation(model, trajectories, scales, relative, held_out=held_out,
                                  reference=reference, bound=bound, errors=errors)
    return sweep_choices(dataclasses.replace(
        model, validation=validation, guarantee=_sweep_guarantee(
            robot, model, trajectories, scales, relative, tolerance, region,
            region_missing)),
        trajectories)


def region_merged_model(robot: Robot, trajectories: Sequence[Motion], region: Region,
                        tolerance: float = DEFAULT_TOLERANCE, torque_floor: float = 0.0,
                        provenance: Mapping[str, Any] | None = None,
                        trajectories_digest: str = "", terms: Term | None = None,
                        form: str = "cheapest", derive: Derivations = UNKEPT
                        ) -> tuple[SimplifiedModel, TorqueFunction | None]:
    """The budget rule's merged model proved over the joint-limit region, before it is
    measured on the trajectories: it does not depend on them.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    trajectories : sequence of Motion
        The swept trajectories (the exact explicit model's own trajectory record).
    region : Region
        The region the bound is proved over.
    tolerance : float, optional
        EPS >= 0.
    torque_floor : float, optional
        TAU [N m]: s_i = max(largest |tau_i| found over the region, TAU).
    provenance : dict, optional
    trajectories_digest : str, optional
        As :func:`trajectory_merged_model` takes it.
    terms : Term, optional
        The robot's explicit terms: the exact explicit model is a candidate; None: the
        recursive model only.
    form : {"cheapest", "recursive", "explicit"}, optional
        As :func:`gd_analyze.simplify.form_choice.choose_form` takes it.
    derive : Derivations, optional
        Where certifications and searches are kept between runs (default nowhere).

    Returns
    -------
    model : SimplifiedModel
        The main job's region model (:func:`gd_analyze.simplify.deploy.region_search` without
        the pre-screen, told to ``derive.claimed``) or the exact explicit model, as
        :func:`~gd_analyze.simplify.form_choice.choose_form` decides over the region; its
        inertia check done (:func:`~gd_analyze.simplify.form_choice.inertia_checked`);
        ``validation`` empty.
    reference : callable or None
        tau_full(q, qd, qdd) its errors are measured against: the full explicit model for an
        explicit model, else None (the G-D terms).

    Notes
    -----
    Source: the region bound of :func:`gd_analyze.simplify.deploy.region_search` (interval
    branch and bound on the Newton-Euler regressor recursion, rounded outward); the forms
    compared by :func:`~gd_analyze.simplify.form_choice.choose_form`.
    """
    base = base_parameters(robot)
    found = region_search(robot, base, region, tolerance, torque_floor, screen=False,
                          derive=derive)
    first = recursive_simplified(robot, found.rec, base, tolerance=tolerance,
                                 torque_floor=torque_floor, trajectory_sha256=trajectories_digest,
                                 provenance=provenance, guarantee=found.guarantee,
                                 forms=found.forms, searched=found.store)
    derive.claimed(first)           # its bound proved here: not proved again by its checks
    costs = recursive_costs(first)
    if terms is not None:
        costs["explicit, full"] = dict(full_program(robot, terms).cost())
    choice = choose_form("budget", form, True, first.cost, full=costs.get("explicit, full"))
    model, reference = first, None              # the G-D terms, D qdd + h + c
    if choice.form == "exact explicit":
        full = explicit_sweep_model(robot, trajectories, 0.0, torque_floor, provenance,
                                    terms)[0]
        model = exact_explicit_model(full, terms, first.guarantee,  # type: ignore[arg-type]  # a region model's
                                     tolerance, choice.why)
        reference = full_torque(robot, terms)  # type: ignore[arg-type]  # given: a candidate
    model = dataclasses.replace(model, costs=costs,
                                full_cost=dict(costs.get("explicit, full", model.full_cost)))
    # D_s proved positive definite over the region, parameters restored where it is not (bound
    # and sampled error derived again); an explicit model not proved is not deployed under it
    model, replaced = inertia_checked(
        model, dataclasses.replace(first, costs=costs,
                                   full_cost=dict(costs.get("explicit, full", {}))),
        restored_rebuild(None, None, None, region=region, derive=derive))
    return model, None if replaced is not None else reference


def _trajectory_bounds(peak, whole_peak, dropped):
    """The bound on each trajectory, split by part (K, 4, n), of the pairs ``dropped``, a
    parameter with all its parts dropped counted whole."""

    dropped = np.asarray(dropped, bool)
    return dropped_peaks(peak, whole_peak, dropped, dropped.all(axis=1))

def _sweep_rebuild(peak, whole_peak, scales, tolerance):
    """A ``rebuild`` for :func:`gd_analyze.certify.positive_definite.with_inertia_check`
    on a trajectory sweep: the recursive model with the given pairs dropped (the restored
    parameters restored in full where their remaining parts would break the budget on a
    trajectory, or cost more), its bounds on each trajectory derived again."""

    def rebuild(model, dropped):
        robot, rec = model.robot, model.recursive
        base = rec.base(robot)
        dropped = settle_restored(robot, base, rec.dropped, dropped)
        each = _trajectory_bounds(peak, whole_peak, dropped)
        if np.any(each.sum(axis=1) > tolerance * scales * (1 + 1e-12)):
            dropped = dropped.copy()
            dropped[np.asarray(rec.dropped, bool)[:, 0] & ~dropped[:, 0]] = False
            each = _trajectory_bounds(peak, whole_peak, dropped)
        new_rec = dataclasses.replace(rec, dropped=dropped,
                                      bound=each.sum(axis=1).max(axis=0),
                                      bound_by_part=each.max(axis=0))
        return rebuilt(model, new_rec, base)
    return rebuild


def _sweep_guarantee(robot, model, trajectories, scales, relative, tolerance, region, missing):
    """The merged model's guarantee on the swept trajectories (kind ``"trajectory"``):
    ``scale`` the largest scale_{t,i} over them, ``bound`` ``relative`` (n,) times it (on
    trajectory t the error is at most relative_i scale_{t,i}); for the recursive form the
    error sampled over the robot's region relative to s_i there, where it has one."""
    scale = np.asarray(scales, float).max(axis=0)
    bound = np.asarray(relative, float) * scale
    shas = tuple(getattr(t, "sha256", "") or "" for t in trajectories)
    method = ("the dropped pairs' (or terms') largest peaks relative to each swept "
              "trajectory's scale_i, summed (triangle inequality)")
    sampled = None
    if model.recursive is not None and region is not None:
        sampled = trajectory_guarantee(robot, base_parameters(robot), model.recursive,
                                       tolerance, region=region).region_sampled_error
    return Guarantee("trajectory", float(tolerance), bound=bound, scale=scale,
                     trajectories_sha256=shas, region_sampled_error=sampled,
                     region_missing=missing, method=method,
                     region=region).with_scale_states(robot, trajectories)
