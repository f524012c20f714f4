"""Which simplified model the main job deploys: the pruned recursive model, the
pruned explicit one or the exact explicit one, and the tolerance ladder of the form deployed.

Nothing here prints or writes files.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from concurrent.futures import Future
from typing import TYPE_CHECKING, Any

import numpy as np

from ..certify.positive_definite import with_inertia_check
from ..dynamics.opcount import operation_counts
from ..simplify.choices import full_choices
from ..simplify.guarantee import Guarantee
from ..store import explicit_cache
from ..store.names import Attr
from .deploy import build_recursive, guarantee_region, restored_rebuild
from .recursive_ladder import recursive_ladder
from .simplify import (
    LADDER,
    build_model,
    collect_peaks,
    cost_rows,
    full_program,
    full_torque,
    ladder,
    ladder_skipped,
    simplified_dataset,
)

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr

    from ..certify.region import Region
    from ..model.robot import Robot
    from ..ranking.ranking import Ranking
    from ..simplify.budget import PartPeaks
    from ..simplify.simplified import SimplifiedModel
    from ..trajectory.trajectory import Trajectory
    from .options import SimplifyOptions

__all__ = ["deploy_models", "exact_explicit_wins", "exact_explicit_model", "region_coverage",
           "region_screen_attrs"]


def deploy_models(robot: Robot, trajectory: Trajectory, ranking: Ranking, part_peaks: PartPeaks,
                  options: SimplifyOptions, provenance: Mapping[str, Any],
                  background: Mapping[str, Future[Any]]
                  ) -> tuple[SimplifiedModel, SimplifiedModel | None,
                             Callable[[Mapping[str, Any] | None], xr.Dataset]]:
    """The simplified model deployed, the models compared with it, ladder, costs.

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
        :func:`gd_analyze.jobs.simplify.simplified_dataset`.

    Notes
    -----

    The pruned recursive model is always built; the explicit G-D model is derived when the
    chapter rule or ``form="explicit"`` asks for it, when ``explicit`` is ``"always"``, or
    (``"auto"``) when it may be deployed (``form`` is not ``"recursive"``) and its estimated
    size is cheap
    (:func:`gd_analyze.symbolic.explicit_estimate.is_expensive`). Under the budget rule and
    ``form="cheapest"`` the cheaper of the pruned recursive and pruned explicit models is
    deployed (multiplications + additions; the recursive one on a tie). The tolerance ladder
    is of the form deployed (:func:`.recursive_ladder.recursive_ladder` for the recursive one,
    pruned as it is).
    """
    tolerance, rule, torque_floor = options.tolerance, options.rule, options.torque_floor
    form = options.form
    q, qd, qdd = trajectory.q, trajectory.qd, trajectory.qdd
    common: dict[str, Any] = dict(ranking=ranking, trajectory_sha256=trajectory.sha256,
                                  provenance=provenance)
    counts = operation_counts(robot)
    region, missing, proved = guarantee_region(robot, options.guarantee, options.region) \
        if rule == "budget" else (None, "", False)
    rec, rec_sel = build_recursive(robot, q, qd, qdd, tolerance=tolerance,
                                   torque_floor=torque_floor,
                                   contributions=background["recursive"].result(),
                                   region=region if proved else None, sample_region=region,
                                   region_missing=missing, **common)
    exact = rec.costs["exact recursive"]
    ne = counts["newton-euler"]
    ne = {"multiplications": int(ne["multiplications"]), "additions": int(ne["additions"])}
    derive = "explicit" in background
    rows: Any                   # the ladder's rows, or their Future (recursive_ladder)
    model, sel, other, rows, skipped, form_note = rec, rec_sel, None, [], "", ""
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
            form == "cheapest" and not proved and _ops(ex.cost) < _ops(rec.cost))
        # proved over the region: the exact explicit model (bound 0) where it is cheaper
        exact_explicit = (not deployed and proved and form == "cheapest"
                          and exact_explicit_wins(rec.cost, ex.full_cost))
        if deployed:                            # the ladder of the form deployed
            model, sel = ex, ex_sel
            skipped = ladder_skipped(ex.full_cost, counts)
            rows = [] if skipped else ladder(robot, terms, peaks, [(q, qd, qdd)],
                                             torque_floor=torque_floor,
                                             reference=full_torque(robot, terms))
        elif exact_explicit:
            full, sel = build_model(robot, terms, peaks, tolerance=0.0, rule="budget",
                                    torque_floor=torque_floor,
                                    chapter_choices=ranking.choices(), **common)
            model = exact_explicit_model(full, rec.guarantee, tolerance)  # type: ignore[arg-type]  # proved: a region guarantee
            skipped = ("not built: the deployed model is the exact explicit one, which holds "
                       "over the whole region, and the ladder prunes on the trajectory")
        else:
            form_note = _not_deployed(rec, ex, form, proved)
    # the sampled pre-screen skipped the region's certification: no ladder is certified either
    screened = rec.provenance.get("region_screen") if proved else None
    ladder_recursive = model is rec and not screened
    if model is rec and screened:
        skipped = _screened_ladder(screened)
    model = dataclasses.replace(model, costs=costs,
                                full_cost=dict(costs.get("explicit, full", model.full_cost)),
                                program_cache=model.program(),
                                guarantee=model.guarantee if model.guarantee is not None
                                else _trajectory_guarantee(model, sel, trajectory, missing,
                                                           region))
    # D_s proved positive definite where the bound holds; parameters restored where it is
    # not, the bound and sampled error derived again for the model finally deployed
    rebuild = restored_rebuild(q, qd, qdd, region=region if proved else None,
                               sample_region=region, region_missing=missing,
                               contributions=background["recursive"].result())
    model = with_inertia_check(model, q, rebuild=rebuild)
    check = model.inertia_check
    region_claim = model.guarantee is not None and model.guarantee.proved
    # NaN is not positive: a model whose D_s is singular or indefinite at a sampled position
    sampled_indefinite = not check["sampled_min_eigenvalue"] > 0
    if model.recursive is None and not check["proved"] and (region_claim or sampled_indefinite):
        # an explicit model whose D_s is not proved is not deployed under a region guarantee,
        # nor one whose D_s is not positive definite at the sampled positions, where the
        # recursive one's is proved
        fallback = with_inertia_check(dataclasses.replace(
            rec, costs=costs, full_cost=dict(costs.get("explicit, full", rec.full_cost)),
            program_cache=rec.program()), q, rebuild=rebuild)
        if fallback.inertia_check["proved"]:
            model, sel, form_note = fallback, rec_sel, (
                "The deployed model is the " + ("exact" if screened else "pruned")
                + " recursive one: the explicit model's D_s "
                + ("was not proved positive definite over the region." if region_claim else
                   "is not positive definite at the sampled positions of the trajectory "
                   f"(smallest eigenvalue {check['sampled_min_eigenvalue']:.3g})."))
            ladder_recursive = not screened
            skipped = _screened_ladder(screened) if screened else ""
    if model.recursive is not None and model.recursive is not rec.recursive:    # restored
        sel = dataclasses.replace(
            sel, scale=model.recursive.scale, bound=model.recursive.bound,
            bound_by_kind={"D": model.recursive.bound_by_part[0],
                           "h": model.recursive.bound_by_part[1],
                           "c": model.recursive.bound_by_part[2],
                           "whole": model.recursive.bound_by_part[3]})
    pool = None
    if ladder_recursive:                        # the recursive form's ladder
        from concurrent.futures import ThreadPoolExecutor

        base, contributions = background["recursive"].result()
        # measured over the trajectory in a thread, beside the error pass
        pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="gd-ladder")
        rows = recursive_ladder(robot, base, (q, qd, qdd), LADDER, torque_floor,
                                region=region if proved else None, contributions=contributions,
                                deployed=model, pool=pool)
        pool.shutdown(wait=False)               # the thread ends when its one job has

    def finish(other_error):
        rungs = rows.result() if pool is not None else rows
        table = cost_rows(robot.n, model, other=other, ladder_rows=rungs,
                          formulation_counts=counts)
        extra = simplified_dataset(model, sel, other=other, ladder_rows=rungs, cost_table=table,
                                   other_error=other_error,
                                   full_terms=terms if derive else None)
        if skipped:
            extra.attrs["simplified_ladder_skipped"] = skipped
        if rungs:
            extra.attrs["simplified_ladder_form"] = model.form
        if form_note:
            extra.attrs["simplified_form_note"] = form_note
        extra.attrs.update(region_coverage(region, trajectory))
        if screened:
            extra.attrs.update(region_screen_attrs(screened))
        return extra

    return model, other, finish


def region_screen_attrs(screen: Mapping[str, Any]) -> dict[str, Any]:
    """The sampled pre-screen that skipped the region's certification, as results.h5 stores it.

    Parameters
    ----------
    screen : dict
        :meth:`gd_analyze.certify.screen.RegionScreen.to_dict`.

    Returns
    -------
    dict
        ``simplified_region_screen`` (the sentence with the numbers),
        ``simplified_region_possible_saving`` and ``simplified_region_saving_threshold``
        (shares of the exact recursive model's operations [1]).
    """
    return {Attr.SIMPLIFIED_REGION_SCREEN: str(screen["statement"]),
            Attr.SIMPLIFIED_REGION_POSSIBLE_SAVING: float(screen["possible_saving"]),
            Attr.SIMPLIFIED_REGION_SAVING_THRESHOLD: float(screen["threshold"])}


def exact_explicit_wins(recursive_cost: Mapping[str, Any], full_cost: Mapping[str, Any]) -> bool:
    """Under a region guarantee (``form="cheapest"``): whether the exact explicit model is
    deployed rather than the recursive model pruned over the region.

    Parameters
    ----------
    recursive_cost, full_cost : dict
        ``multiplications`` and ``additions`` of the region's recursive model (never dearer
        than the exact recursive one) and of the full explicit model.

    Returns
    -------
    bool
        The full explicit model counts fewer operations (the recursive one wins a tie).
    """
    return _ops(full_cost) < _ops(recursive_cost)


def exact_explicit_model(full: SimplifiedModel, guarantee: Guarantee, tolerance: float,
                         why: str = "cheaper than the recursive model pruned over the region"
                         ) -> SimplifiedModel:
    """The exact explicit model deployed under a region guarantee (bound 0).

    Parameters
    ----------
    full : SimplifiedModel
        The explicit model at EPS = 0 (nothing dropped that contributes).
    guarantee : Guarantee
        The region guarantee of the recursive model pruned over the same region
        (:func:`.deploy.region_model`): its region and scale s_i are kept.
    tolerance : float
        EPS asked for.
    why : str, optional
        Why it is deployed, for the guarantee's ``method``.

    Returns
    -------
    SimplifiedModel
        ``full`` with every explicit term kept (a term whose peak is 0 on the trajectories
        ``full`` was built on need not be 0 elsewhere in the region), ``tolerance`` EPS, bound
        0 on every joint and the region guarantee with bound and sampled error 0.
    """
    n = full.robot.n
    terms, _ = explicit_cache.explicit_terms(full.robot)
    program = full_program(full.robot, terms)
    return dataclasses.replace(
        full, tolerance=float(tolerance), bound=[0.0] * n, terms=terms,
        choices=full_choices(n), cost=program.cost(), program_cache=program,
        guarantee=dataclasses.replace(
            guarantee, bound=np.zeros(n), sampled_error=np.zeros(n), tilings=(),
            method=f"the exact explicit G-D model (nothing dropped), {why}; scale: "
                   + guarantee.method))


def region_coverage(region: Region | None, trajectory: Trajectory) -> dict[str, Any]:
    """Whether the analysed trajectory stays in the region, as results.h5 stores it.

    Parameters
    ----------
    region : Region or None
        The model's region (None: no region, nothing stored).
    trajectory : Trajectory
        q, qd, qdd of shape (N, n).

    Returns
    -------
    dict
        ``region_covers_trajectory`` (1 or 0) and ``region_coverage``: "" inside, else the
        clause of :meth:`gd_analyze.certify.region.Excursion.text` (the joint, the
        quantity and its extreme against the limit); empty without a region.
    """
    if region is None:
        return {}
    out = region.excursion(trajectory.q, trajectory.qd, trajectory.qdd)
    return {"region_covers_trajectory": int(out is None),
            "region_coverage": "" if out is None else out.text()}


def _trajectory_guarantee(model, sel, trajectory, missing="", region=None):
    """The explicit budget model's guarantee on its trajectory (None: chapter rule)."""
    if model.rule != "budget":
        return None
    return Guarantee("trajectory", float(model.tolerance), bound=np.asarray(model.bound, float),
                     scale=np.asarray(sel.scale, float), trajectory_sha256=trajectory.sha256,
                     region_missing=missing, region=region,
                     method="sum of the dropped terms' peak contributions on the trajectory "
                            "(triangle inequality)")


def _not_deployed(rec, ex, form, proved):
    """Why the pruned explicit model is not deployed beside the recursive one."""
    why = (", --form recursive" if form != "cheapest" else
           ", whose bound holds on this trajectory only, while the recursive one's is proved "
           "over the joint-limit region" if proved and _ops(ex.cost) < _ops(rec.cost) else "")
    return (f"The deployed model is the pruned recursive one ({_ops(rec.cost):,} operations "
            f"against the pruned explicit one's {_ops(ex.cost):,}{why}).")


def _screened_ladder(screen):
    """Why the ladder is not built when the pre-screen skipped the region's certification."""
    return ("not built: the region was not certified (" + str(screen["statement"])
            + "), and each rung would need its certification")


def _ops(cost):
    return int(cost["multiplications"]) + int(cost["additions"])
