"""Which simplified model the main job deploys: the pruned recursive model, the
pruned explicit one or the exact explicit one, and the tolerance ladder of the form deployed.

Nothing here prints or writes files.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from concurrent.futures import Future, ThreadPoolExecutor
from typing import TYPE_CHECKING, Any

import numpy as np

from ..dynamics.opcount import operation_counts
from ..simplify.deploy import (
    build_recursive,
    guarantee_region,
    recursive_selection,
    restored_rebuild,
)
from ..simplify.explicit_model import (
    LADDER,
    build_model,
    collect_peaks,
    full_torque,
    ladder,
    ladder_skipped,
)
from ..simplify.form_choice import (
    choose_form,
    exact_explicit_model,
    inertia_checked,
    recursive_costs,
)
from ..simplify.guarantee import Guarantee
from ..simplify.recursive_ladder import recursive_ladder
from ..store.derivations import DERIVATIONS
from ..store.names import Attr
from .simplified_dataset import cost_rows, simplified_dataset

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr

    from ..certify.region import Region
    from ..model.robot import Robot
    from ..ranking.ranking import Ranking
    from ..simplify.budget import PartPeaks
    from ..simplify.simplified import SimplifiedModel
    from ..trajectory.trajectory import Trajectory
    from .options import SimplifyOptions

__all__ = ["deploy_models", "region_coverage", "region_screen_attrs"]


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
        :func:`gd_analyze.jobs.simplified_dataset.simplified_dataset`.

    Notes
    -----

    The pruned recursive model is always built; the explicit G-D model is derived when the
    chapter rule or ``form="explicit"`` asks for it, when ``explicit`` is ``"always"``, or
    (``"auto"``) when it may be deployed (``form`` is not ``"recursive"``) and its estimated
    size is cheap (:func:`.peak_jobs.derives_explicit`). Which one is deployed is
    :func:`choose_form`'s decision, its D_s checked by :func:`inertia_checked`. The tolerance
    ladder is of the form deployed (:func:`gd_analyze.simplify.recursive_ladder.recursive_ladder` for the
    recursive one, pruned as it is).
    """
    tolerance, rule, torque_floor, form = (options.tolerance, options.rule,
                                           options.torque_floor, options.form)
    q, qd, qdd = trajectory.q, trajectory.qd, trajectory.qdd
    common: dict[str, Any] = dict(ranking=ranking, trajectory_sha256=trajectory.sha256,
                                  provenance=provenance)
    counts = operation_counts(robot)
    region, missing, proved = guarantee_region(robot, options.guarantee, options.region) \
        if rule == "budget" else (None, "", False)
    contributions = background["recursive"].result()
    rec, _ = build_recursive(robot, q, qd, qdd, tolerance=tolerance, torque_floor=torque_floor,
                          contributions=contributions, region=region if proved else None,
                          sample_region=region, region_missing=missing, derive=DERIVATIONS,
                          **common)
    costs = recursive_costs(rec, counts)
    ex: Any = None                 # the explicit model of the rule, its terms and peaks
    terms: Any = None
    other: SimplifiedModel | None = None
    if "explicit" in background:
        terms, term = background["explicit"].result()
        peaks = collect_peaks(robot, terms, q, qd, qdd, gd=part_peaks, term=term)
        ex, ex_sel = build_model(robot, terms, peaks, tolerance=tolerance, rule=rule,
                                 torque_floor=torque_floor,
                                 chapter_choices=ranking.choices(), **common)
        other, _ = build_model(robot, terms, peaks, tolerance=tolerance,
                               rule="chapter" if rule == "budget" else "budget",
                               torque_floor=torque_floor, chapter_choices=ranking.choices(),
                               **common)
        costs.update({f"explicit, {rule}": dict(ex.cost), "explicit, full": dict(ex.full_cost)})
    choice = choose_form(rule, form, proved, rec.cost, None if ex is None else ex.cost,
                         None if ex is None else ex.full_cost)
    # a screen chose the exact recursive model; the sampled pre-screen skipped the region's
    # certification too (not the screen of the pairs searched under the proved bounds), so
    # no ladder is certified either
    screen = rec.provenance.get("region_screen") if proved else None
    screened = screen if screen and not screen.get("proved") else None
    rows: Any = []              # the ladder's rows, or their Future (recursive_ladder)
    model, sel, skipped = rec, None, _screened_ladder(screened)
    if choice.form == "explicit":               # the ladder of the form deployed
        model, sel = ex, ex_sel
        skipped = ladder_skipped(ex.full_cost, counts)
        rows = [] if skipped else ladder(robot, terms, peaks, (q, qd, qdd),
                                         torque_floor=torque_floor,
                                         reference=full_torque(robot, terms))
    elif choice.form == "exact explicit":
        full, sel = build_model(robot, terms, peaks, tolerance=0.0, rule="budget",
                                torque_floor=torque_floor, chapter_choices=ranking.choices(),
                                **common)
        model = exact_explicit_model(full, terms, rec.guarantee, tolerance, choice.why)  # type: ignore[arg-type]  # proved: a region guarantee
        skipped = ("not built: the deployed model is the exact explicit one, which holds "
                   "over the whole region, and the ladder prunes on the trajectory")
    form_note = choice.why if choice.form == "recursive" else ""

    def with_costs(m):
        return dataclasses.replace(m, costs=costs, program_cache=m.program(),
                                   full_cost=dict(costs.get("explicit, full", m.full_cost)))
    model = with_costs(model)
    if model.guarantee is None:
        model = dataclasses.replace(model, guarantee=_trajectory_guarantee(
            model, sel, trajectory, missing, region))
    # D_s proved positive definite where the bound holds; parameters restored where it is
    # not, the bound and sampled error derived again for the model finally deployed
    rebuild = restored_rebuild(q, qd, qdd, region=region if proved else None,
                               sample_region=region, region_missing=missing,
                               contributions=contributions, derive=DERIVATIONS)
    model, replaced = inertia_checked(model, with_costs(rec), rebuild, q)
    if replaced is not None:
        check: Any = replaced.inertia_check
        form_note = ("The deployed model is the " + ("exact" if screen else "pruned")
                     + " recursive one: the explicit model's D_s "
                     + ("was not proved positive definite over the region."
                        if replaced.guarantee is not None and replaced.guarantee.proved else
                        "is not positive definite at the sampled positions of the trajectory "
                        f"(smallest eigenvalue {check['sampled_min_eigenvalue']:.3g})."))
    if model.recursive is not None:             # its own bound, restored pairs included
        sel, skipped, rows = recursive_selection(model), _screened_ladder(screened), []
    pool = None
    if model.recursive is not None and not screened:        # the recursive form's ladder
        # measured over the trajectory in a thread, beside the error pass
        pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="gd-ladder")
        rows = recursive_ladder(robot, contributions[0], (q, qd, qdd), LADDER, torque_floor,
                                region=region if proved else None,
                                contributions=contributions[1], deployed=model, pool=pool,
                                derive=DERIVATIONS)
        pool.shutdown(wait=False)               # the thread ends when its one job has

    def finish(other_error):
        rungs = rows.result() if pool is not None else rows
        table = cost_rows(robot.n, model, other=other, ladder_rows=rungs,
                          formulation_counts=counts)
        extra = simplified_dataset(model, sel, other=other, ladder_rows=rungs, cost_table=table,
                                   other_error=other_error,
                                   full_terms=terms)
        if skipped:
            extra.attrs["simplified_ladder_skipped"] = skipped
        if rungs:
            extra.attrs["simplified_ladder_form"] = model.form
        if form_note:
            extra.attrs["simplified_form_note"] = form_note
        extra.attrs.update(region_coverage(region, trajectory))
        if screen:
            extra.attrs.update(region_screen_attrs(screen))
        return extra

    return model, other, finish


def region_screen_attrs(screen: Mapping[str, Any]) -> dict[str, Any]:
    """The screen that chose the exact recursive model, as results.h5 stores it.

    Parameters
    ----------
    screen : dict
        :meth:`gd_analyze.certify.screen.RegionScreen.to_dict`: the sampled pre-screen that
        skipped the region's certification, or the screen of the pairs searched under the
        proved bounds (``proved``).

    Returns
    -------
    dict
        ``simplified_region_screen`` (the sentence with the numbers),
        ``simplified_region_possible_saving`` and ``simplified_region_saving_threshold``
        (shares of the exact recursive model's operations [1]), and
        ``simplified_region_screen_proved`` (1: the proved screen, 0: the sampled one).
    """
    return {Attr.SIMPLIFIED_REGION_SCREEN: str(screen["statement"]),
            Attr.SIMPLIFIED_REGION_POSSIBLE_SAVING: float(screen["possible_saving"]),
            Attr.SIMPLIFIED_REGION_SAVING_THRESHOLD: float(screen["threshold"]),
            Attr.SIMPLIFIED_REGION_SCREEN_PROVED: int(bool(screen.get("proved", False)))}


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


def _screened_ladder(screen):
    """Why the ladder is not built when the pre-screen skipped the region's certification
    (or "" without a screen)."""
    return "" if not screen else (
        "not built: the region was not certified (" + str(screen["statement"])
        + "), and each rung would need its certification")
