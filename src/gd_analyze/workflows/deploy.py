"""The simplified model the main job deploys (issue 17), and the recursive one it builds.

robot -> base parameters -> pruned recursive model within the budget on the trajectory ->
SimplifiedModel of the recursive form, with the exact recursive model's count beside it
(:func:`build_recursive`); beside it the explicit models where derived, the cheaper deployed
(:func:`deploy_models`). Nothing here prints or writes files.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..core.selection.budget import DEFAULT_TOLERANCE
from ..core.selection.ranking import DEFAULT_DOMINANCE, DEFAULT_NEGLIGIBLE
from ..core.selection.simplified import SimplifiedModel

__all__ = ["build_recursive", "replace_cost", "deploy_models"]


def build_recursive(robot, q, qd, qdd, tolerance=DEFAULT_TOLERANCE, torque_floor=0.0,
                    ranking=None, trajectory_sha256="", provenance=None, contributions=None):
    """The pruned customized recursive Newton-Euler model within the budget (issue 17).

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q, qd, qdd : ndarray, shape (N, n)
        The trajectory [rad, rad/s, rad/s^2; m, m/s, m/s^2]: the bound holds on it.
    tolerance : float, optional
        EPS.
    torque_floor : float, optional
        TAU [N m].
    ranking : Ranking, optional
        For the thresholds s and e recorded with the model.
    trajectory_sha256 : str, optional
    provenance : dict, optional
    contributions : (BaseParameters, tuple of ndarray), optional
        The robot's base parameters and their
        :func:`gd_analyze.core.symbolic.pruning.contribution_peaks` on this trajectory, if the
        caller computed them already (:func:`.peak_jobs.contribution_job`); computed here otherwise.

    Returns
    -------
    model : SimplifiedModel
        Of the recursive form, ``validation`` empty; ``costs["exact recursive"]`` holds the
        exact recursive model's count.
    selection : Selection
        Its scale and bound, the bound split by part (``"D"``: inertial, ``"h"``: velocity,
        ``"c"``: gravity, ``"whole"``: parameters dropped whole) [N m].

    Notes
    -----
    Fu, Gonzalez & Lee (1987), Algorithm 3.1 on the base parameters (Khalil & Kleinfinger
    1987; Gautier 1990), pruned as :func:`gd_analyze.core.symbolic.recursive_model.recursive_model`.
    """
    from ..core.model.drives import with_drives
    from ..core.selection.budget import Selection
    from ..core.selection.ranking import element_labels
    from ..core.symbolic.base_parameters import base_parameters
    from ..core.symbolic.recursive import recursive_program
    from ..core.symbolic.recursive_model import recursive_model

    base, peaks = (base_parameters(robot), None) if contributions is None else contributions
    rec = recursive_model(robot, q, qd, qdd, tolerance, torque_floor, base=base, peaks=peaks)
    exact_program = recursive_program(robot, base.values)
    exact = with_drives(exact_program, robot).cost()
    program = with_drives(rec.program(robot, exact=exact_program), robot)
    choices = {lab: "both" for lab in element_labels(robot.n)}
    model = SimplifiedModel(
        robot=robot, choices=choices,
        dominance_threshold=float(getattr(ranking, "dominance_threshold", DEFAULT_DOMINANCE)),
        negligible_threshold=float(getattr(ranking, "negligible_threshold", DEFAULT_NEGLIGIBLE)),
        trajectory_sha256=trajectory_sha256, provenance=dict(provenance or {}), rule="budget",
        tolerance=float(tolerance), torque_floor=float(torque_floor), terms=None,
        recursive=rec, bound=[float(v) for v in rec.bound],
        costs={"exact recursive": exact}, program_cache=program)
    model = replace_cost(model, program.cost())
    sel = Selection(rule="budget", tolerance=float(tolerance), choices=choices, kept=None,
                    scale=rec.scale, bound=rec.bound,
                    bound_by_kind={"D": rec.bound_by_part[0], "h": rec.bound_by_part[1],
                                   "c": rec.bound_by_part[2], "whole": rec.bound_by_part[3]},
                    element_bound=np.full(robot.n, np.nan))
    return model, sel


def replace_cost(model, cost):
    """The model with its ``cost`` set (a new frozen value; its ``program_cache`` field, and
    so a program built before, is carried over by :func:`dataclasses.replace`).

    Parameters
    ----------
    model : SimplifiedModel
    cost : dict
        ``multiplications``, ``additions``, ``sin``, ``cos``.

    Returns
    -------
    SimplifiedModel
    """
    import dataclasses

    return dataclasses.replace(model, cost=dict(cost))


def deploy_models(robot, trajectory, ranking, part_peaks, options, provenance, background):
    """The simplified model deployed (issue 17), the models compared with it, ladder, costs.

    Parameters
    ----------
    robot : Robot
    trajectory : Trajectory
        q, qd, qdd of shape (N, n).
    ranking : Ranking
    part_peaks : PartPeaks
        Accumulated in the pass over the G-D terms.
    options : SimplifyOptions
    provenance : dict
    background : dict of str to Future
        The peak passes of :func:`.peak_jobs.start_peaks`.

    Returns
    -------
    model : SimplifiedModel
        The deployed model.
    other : SimplifiedModel or None
        The other rule's explicit model, whose error the caller measures in its pass over
        the trajectory.
    finish : callable
        ``finish(other_error)``: the dataset of
        :func:`gd_analyze.workflows.simplify.simplified_dataset`.

    Notes
    -----

    The pruned recursive model is always built; the explicit G-D model is derived when the
    chapter rule or ``form="explicit"`` asks for it, when ``explicit`` is ``"always"``, or
    (``"auto"``) when it may be deployed (``form`` is not ``"recursive"``) and its estimated
    size is cheap
    (:func:`gd_analyze.core.symbolic.explicit_estimate.is_expensive`). Under the budget rule and
    ``form="cheapest"`` the cheaper of the pruned recursive and pruned explicit models is
    deployed (multiplications + additions; the recursive one on a tie).
    """
    from ..formulations.opcount import operation_counts
    from .simplify import (
        build_model,
        build_recursive,
        collect_peaks,
        cost_rows,
        full_torque,
        ladder,
        ladder_skipped,
        simplified_dataset,
    )

    tolerance, rule, torque_floor = options.tolerance, options.rule, options.torque_floor
    explicit, form = options.explicit, options.form
    q, qd, qdd = trajectory.q, trajectory.qd, trajectory.qdd
    common = dict(ranking=ranking, trajectory_sha256=trajectory.sha256, provenance=provenance)
    counts = operation_counts(robot)
    rec, rec_sel = build_recursive(robot, q, qd, qdd, tolerance=tolerance,
                                   torque_floor=torque_floor,
                                   contributions=background["recursive"].result(), **common)
    exact = rec.costs["exact recursive"]
    ne = counts["newton-euler"]
    ne = {"multiplications": int(ne["multiplications"]), "additions": int(ne["additions"])}
    derive = "explicit" in background
    model, sel, other, rows, skipped = rec, rec_sel, None, [], ""
    costs = {"exact recursive": exact, "recursive, budget": dict(rec.cost),
             "newton-euler": ne}
    if derive:
        terms, term = background["explicit"].result()
        peaks = collect_peaks(robot, terms, q, qd, qdd, gd=part_peaks, term=term)
        ex, ex_sel = build_model(robot, terms, peaks, tolerance=tolerance, rule=rule,
                                 torque_floor=torque_floor,
                                 chapter_choices=ranking.choices(), **common)
        other_rule = "chapter" if rule == "budget" else "budget"
        other, _ = build_model(robot, terms, peaks, tolerance=tolerance, rule=other_rule,
                               torque_floor=torque_floor, chapter_choices=ranking.choices(),
                               **common)
        costs.update({f"explicit, {rule}": dict(ex.cost), "explicit, full": dict(ex.full_cost)})
        deployed = rule == "chapter" or form == "explicit" or (
            form == "cheapest" and _ops(ex.cost) < _ops(rec.cost))
        # the ladder is of the explicit form: built only where that form is deployed
        skipped = ladder_skipped(ex.full_cost, counts) if deployed else (
            f"not built: the deployed model is the pruned recursive one ({_ops(rec.cost):,} "
            f"operations against the pruned explicit one's {_ops(ex.cost):,}"
            f"{'' if form == 'cheapest' else ', --form recursive'}), and the ladder is of the "
            "explicit form")
        rows = [] if skipped else ladder(robot, terms, peaks, [(q, qd, qdd)],
                                         torque_floor=torque_floor,
                                         reference=full_torque(robot, terms))
        if deployed:
            model, sel = ex, ex_sel
    else:
        skipped = ("not built: the explicit G-D model of this arm is estimated too large to "
                   "pay (give --explicit always to derive it)") if form != "recursive" or \
            explicit == "never" else ("not built: the explicit G-D model is not derived under "
                                      "--form recursive, where it cannot be deployed (give "
                                      "--explicit always to derive it)")
    model = dataclasses.replace(model, costs=costs,
                                full_cost=dict(costs.get("explicit, full", model.full_cost)),
                                program_cache=model.program())
    table = cost_rows(robot.n, model, other=other, ladder_rows=rows, formulation_counts=counts)

    def finish(other_error):
        extra = simplified_dataset(model, sel, other=other, ladder_rows=rows, cost_table=table,
                                   other_error=other_error,
                                   full_terms=terms if derive else None)
        if skipped:
            extra.attrs["simplified_ladder_skipped"] = skipped
        return extra

    return model, other, finish


def _ops(cost):
    return int(cost["multiplications"]) + int(cost["additions"])
