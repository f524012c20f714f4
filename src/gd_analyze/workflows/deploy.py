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
from ..core.selection.positive_definite import with_inertia_check
from ..core.selection.ranking import DEFAULT_DOMINANCE, DEFAULT_NEGLIGIBLE
from ..core.selection.simplified import SimplifiedModel
from .region_memo import REGION_SAMPLES, certified, region_values

__all__ = ["build_recursive", "recursive_simplified", "replace_cost", "region_model",
           "trajectory_guarantee", "certified", "robot_region", "guarantee_region",
           "exact_explicit_wins", "exact_explicit_model", "deploy_models", "REGION_SAMPLES"]

def robot_region(robot):
    """The robot's joint-limit region for a model's guarantee, or None and why not.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    region : Region or None
        Its own position and velocity limits, the acceleration limits of
        :func:`gd_analyze.io.planning.acceleration_limits` (the robot's, or the planner's
        default where it has none); None when a limit is missing.
    missing : str
        The missing limit (:func:`gd_analyze.core.selection.region.missing_limits`), or "".
    """
    from ..core.selection.region import joint_region, missing_limits
    from ..io.planning import acceleration_limits

    why = missing_limits(robot)
    if why:
        return None, why
    try:
        qdd_max, _ = acceleration_limits(robot)
    except ValueError as exc:
        return None, str(exc)
    return joint_region(robot, qdd_max), ""


def guarantee_region(robot, guarantee="auto"):
    """The robot's region, and whether a budget model's bound is proved over it (issue 29).

    Parameters
    ----------
    robot : Robot
    guarantee : {"auto", "region", "trajectory"}, optional
        The ``--guarantee`` choice: ``"trajectory"`` never proves over the region; ``"auto"``
        and ``"region"`` do where the robot gives position and velocity limits for every
        joint, and fall back to the trajectory otherwise (the guarantee then names the
        missing limit).

    Returns
    -------
    region : Region or None
        :func:`robot_region`'s (also under ``"trajectory"``: a trajectory model's error is
        sampled on it); None when a limit is missing.
    missing : str
        The missing limit, or "".
    proved : bool
        Prune on bounds proved over ``region`` (a guarantee of kind ``"region"``).
    """
    region, missing = robot_region(robot)
    return region, missing, region is not None and guarantee != "trajectory"


def region_model(robot, base, region, tolerance, torque_floor=0.0):
    """The recursive model pruned on bounds proved over a joint-limit region (issue 29).

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its base parameters.
    region : Region
        R = {q_min <= q <= q_max, |qd| <= qd_max, |qdd| <= qdd_max}.
    tolerance : float
        EPS.
    torque_floor : float, optional
        [N m or N].

    Returns
    -------
    model : RecursiveModel
        Dropped pairs whose proved bounds add up to at most EPS s_i per joint; ``scale`` is
        s_i over R, ``bound`` the sum of the dropped bounds [N m or N].
    guarantee : Guarantee
        Of kind ``"region"``: |tau_s - tau| <= bound_i <= EPS s_i at every state of R (up to
        round-off), with the sampled error, the scale and where it was found.

    Notes
    -----
    The triangle inequality over the dropped pairs of tau = Y_b beta (Khalil & Kleinfinger
    1987; Gautier 1990); bounds by :func:`gd_analyze.core.selection.certify.certify`.
    """
    pb = certified(robot, base, region, torque_floor)
    return _region_model(robot, base, region, tolerance, pb, _region_pruning(base, pb, robot,
                                                                            tolerance))


def _region_pruning(base, pb, robot, tolerance, chosen=None):
    """:func:`~gd_analyze.core.symbolic.pruning.prune_bounds` on a region's certification
    (``chosen``: an earlier search's pairs, checked against the budget; ValueError if over)."""
    from ..core.symbolic.pruning import prune_bounds

    return prune_bounds(robot, base, pb.scale, pb.bound, pb.leaves.sum(axis=1).max(axis=1),
                        tolerance, pieces=pb.leaves, chosen=chosen)


def _region_model(robot, base, region, tolerance, pb, pr):
    """:func:`region_model`'s model and guarantee from the certification and the pruning."""
    from ..core.selection.certify import METHOD
    from ..core.selection.guarantee import Guarantee
    from ..core.selection.region import worst_states
    from ..core.symbolic.recursive_model import RecursiveModel

    single = pr.dropped & ~pr.whole[:, None]
    by_part = np.stack([np.einsum("bln,b->ln", pb.leaves[:, p], single[:, p]).max(axis=0)
                        for p in range(3)]
                       + [np.einsum("bpln,b->ln", pb.leaves, pr.whole).max(axis=0)])
    safe = np.where(pb.scale > 0, pb.scale, 1.0)
    rel = np.where(pb.scale > 0, pb.bound / safe, np.where(pb.bound > 0, np.inf, 0.0)).max(2)
    rec = RecursiveModel(names=tuple(base.names()), beta=np.array(base.beta, float),
                         dropped=np.array(pr.dropped, bool), scale=np.array(pb.scale, float),
                         bound=np.array(pr.bound, float), bound_by_part=by_part,
                         relative_peak=rel)
    weights = np.asarray(base.beta, float)[None, :] * pr.dropped.T          # (3, b)
    err = worst_states(pb.values, weights, region.qd_max, region.qdd_max)[0].max(axis=0)
    guarantee = Guarantee(
        "region", float(tolerance), bound=rec.bound, scale=rec.scale, q_min=region.q_min,
        q_max=region.q_max, qd_max=region.qd_max, qdd_max=region.qdd_max,
        scale_state=pb.scale_state, sampled_error=err,
        method=f"{METHOD}; {pb.boxes} boxes, {pb.positions.shape[0]} sampled positions")
    return rec, guarantee


def trajectory_guarantee(robot, base, rec, tolerance, trajectory_sha256="", region=None,
                         region_missing=""):
    """The guarantee of a model pruned on a trajectory, its error sampled over the region.

    Parameters
    ----------
    robot : Robot
    base : BaseParameters
    rec : RecursiveModel
        The pruned model (its ``dropped`` pairs, ``bound`` and trajectory ``scale``).
    tolerance : float
        EPS.
    trajectory_sha256 : str, optional
    region : Region, optional
        The robot's region, on which the model's error is sampled (None: not sampled).
    region_missing : str, optional
        Why there is no region.

    Returns
    -------
    Guarantee
        Of kind ``"trajectory"``; ``region_sampled_error``: the largest error found over the
        region relative to s_i there (the largest |tau_i| found), or None
        (:func:`gd_analyze.core.selection.region.sampled_error` at the positions of
        :func:`.region_memo.region_values`: sampling only, no certification).
    """
    from ..core.selection.guarantee import Guarantee
    from ..core.selection.region import sampled_error

    sampled = None
    if region is not None:
        sampled = sampled_error(base, region, rec.dropped, region_values(robot, base, region))[0]
    return Guarantee("trajectory", float(tolerance), bound=np.asarray(rec.bound, float),
                     scale=np.asarray(rec.scale, float), trajectory_sha256=trajectory_sha256,
                     region_sampled_error=sampled, region_missing=region_missing,
                     method="sum of the dropped pairs' peak contributions on the trajectory "
                            "(triangle inequality)")


def build_recursive(robot, q, qd, qdd, tolerance=DEFAULT_TOLERANCE, torque_floor=0.0,
                    ranking=None, trajectory_sha256="", provenance=None, region=None,
                    sample_region=None, region_missing="", contributions=None):
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
    region : Region, optional
        Prune on bounds proved over this joint-limit region
        (:func:`gd_analyze.core.selection.certify.certify`) instead of the trajectory's peaks:
        the model's guarantee is then of kind ``"region"``.
    sample_region : Region, optional
        For a trajectory model: the region on which its error is sampled
        (``region_sampled_error`` of its guarantee).
    region_missing : str, optional
        Why a trajectory model has no region (a missing limit), for its guarantee.
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
    from ..core.selection.budget import Selection
    from ..core.symbolic.base_parameters import base_parameters
    from ..core.symbolic.recursive_model import recursive_model

    base, peaks = (base_parameters(robot), None) if contributions is None else contributions
    forms, store = None, None
    if region is not None:
        rec, guarantee, forms, store = _searched(robot, base, region, tolerance, torque_floor)
    else:
        rec = recursive_model(robot, q, qd, qdd, tolerance, torque_floor, base=base,
                              peaks=peaks)
        guarantee = trajectory_guarantee(robot, base, rec, tolerance, trajectory_sha256,
                                         sample_region, region_missing)
    model = recursive_simplified(robot, rec, base, tolerance=tolerance,
                                 torque_floor=torque_floor, ranking=ranking,
                                 trajectory_sha256=trajectory_sha256, provenance=provenance,
                                 guarantee=guarantee, forms=forms, searched=store)
    sel = Selection(rule="budget", tolerance=float(tolerance), choices=model.choices,
                    kept=None, scale=rec.scale, bound=rec.bound,
                    bound_by_kind={"D": rec.bound_by_part[0], "h": rec.bound_by_part[1],
                                   "c": rec.bound_by_part[2], "whole": rec.bound_by_part[3]},
                    element_bound=np.full(robot.n, np.nan))
    return model, sel


def recursive_simplified(robot, rec, base, tolerance=DEFAULT_TOLERANCE, torque_floor=0.0,
                         ranking=None, trajectory_sha256="", provenance=None, guarantee=None,
                         forms=None, searched=None):
    """A pruned recursive model as a :class:`SimplifiedModel`, its program and counts built.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    rec : RecursiveModel
        The pruned model (:func:`gd_analyze.core.symbolic.recursive_model.recursive_model`, or
        :func:`~gd_analyze.core.symbolic.recursive_model.sweep_recursive_model` for a sweep).
    base : BaseParameters
        The robot's base parameters, those of ``rec``.
    tolerance : float, optional
        EPS.
    torque_floor : float, optional
        TAU [N m].
    ranking : Ranking, optional
        For the thresholds s and e recorded with the model.
    trajectory_sha256 : str, optional
    provenance : dict, optional
    guarantee : Guarantee, optional
        Where its bound holds (:class:`gd_analyze.core.selection.guarantee.Guarantee`).
    forms : (sequence of str, sequence of str or None), optional
        The forms of the links' inertial moments of the exact and of the pruned program
        (:attr:`gd_analyze.core.symbolic.codegen.Program.forms`) from an earlier search with
        the same inputs: the programs are built with them, without the searches.
    searched : callable, optional
        Called with those forms of the programs built (the pruned program's None when the
        exact one is deployed).

    Returns
    -------
    SimplifiedModel
        Of the recursive form, ``validation`` empty, ``bound`` = ``rec.bound`` [N m];
        ``cost`` counted on its program (the exact recursive program when pruning would
        cost more, :func:`gd_analyze.core.symbolic.pruning.pruned_program`), and
        ``costs["exact recursive"]`` the exact recursive model's count.

    Notes
    -----
    Fu, Gonzalez & Lee (1987), Algorithm 3.1 on the base parameters (Khalil & Kleinfinger
    1987; Gautier 1990).
    """
    from ..core.model.drives import with_drives
    from ..core.selection.ranking import element_labels
    from ..core.symbolic.recursive import recursive_program

    exact_forms, pruned_forms = forms if forms is not None else (None, None)
    exact_program = recursive_program(robot, base.values, forms=exact_forms)
    exact = with_drives(exact_program, robot).cost()
    choice = rec.choice(robot, exact=exact_program,          # built once, kept with the model
                        forms=pruned_forms if rec.dropped.any() else None)
    if searched is not None:
        searched(exact_program.forms, None if choice[0] is exact_program else choice[0].forms)
    program = with_drives(choice[0], robot)
    choices = {lab: "both" for lab in element_labels(robot.n)}
    model = SimplifiedModel(
        robot=robot, choices=choices,
        dominance_threshold=float(getattr(ranking, "dominance_threshold", DEFAULT_DOMINANCE)),
        negligible_threshold=float(getattr(ranking, "negligible_threshold", DEFAULT_NEGLIGIBLE)),
        trajectory_sha256=trajectory_sha256, provenance=dict(provenance or {}), rule="budget",
        tolerance=float(tolerance), torque_floor=float(torque_floor), terms=None,
        recursive=rec, bound=[float(v) for v in rec.bound],
        costs={"exact recursive": exact}, program_cache=program, choice_cache=choice,
        guarantee=guarantee)
    return replace_cost(model, program.cost())


def _searched(robot, base, region, tolerance, torque_floor):
    """:func:`region_model` with its searches taken from the derivation cache when an entry
    passes its checks (:mod:`gd_analyze.io.search_cache`): (model, guarantee, forms or None,
    a callable that keeps the searches' outcome or None)."""
    import warnings

    from ..errors import one_line
    from ..io.cache_files import CacheWarning, entry_path
    from ..io.search_cache import read_search, search_key, write_search

    pb = certified(robot, base, region, torque_floor)
    key = search_key(robot, region, tolerance, torque_floor, REGION_SAMPLES)
    found = read_search(key, robot.n, base.rank)
    if isinstance(found, dict):
        try:
            pr = _region_pruning(base, pb, robot, tolerance, (found["dropped"], found["whole"]))
        except ValueError:
            found = "holds dropped pairs over the budget"
        else:
            return (*_region_model(robot, base, region, tolerance, pb, pr),
                    (found["exact_forms"], found["pruned_forms"]), None)
    if isinstance(found, str):
        warnings.warn(one_line(f"{entry_path('search', key)}: derivation cache entry {found}: "
                               "ignored, the model is searched again"), CacheWarning,
                      stacklevel=2)
    pr = _region_pruning(base, pb, robot, tolerance)
    return (*_region_model(robot, base, region, tolerance, pb, pr), None,
            lambda exact_forms, pruned_forms: write_search(key, pr.dropped, pr.whole,
                                                           exact_forms, pruned_forms))


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
    region, missing, proved = guarantee_region(robot, options.guarantee) \
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
            form == "cheapest" and not proved and _ops(ex.cost) < _ops(rec.cost))
        # proved over the region: the exact explicit model (bound 0) where it is cheaper
        exact_explicit = (not deployed and proved and form == "cheapest"
                          and exact_explicit_wins(rec.cost, ex.full_cost))
        # the ladder is of the explicit form: built only where that form is deployed
        skipped = ladder_skipped(ex.full_cost, counts) if deployed else (
            "not built: the deployed model is the exact explicit one, which holds over the "
            "whole region, and the ladder prunes on the trajectory") if exact_explicit else (
            f"not built: the deployed model is the pruned recursive one ({_ops(rec.cost):,} "
            f"operations against the pruned explicit one's {_ops(ex.cost):,}"
            + (", --form recursive" if form != "cheapest" else
               ", whose bound holds on this trajectory only, while the recursive one's is "
               "proved over the joint-limit region" if proved and _ops(ex.cost) < _ops(rec.cost)
               else "")
            + "), and the ladder is of the explicit form")
        rows = [] if skipped else ladder(robot, terms, peaks, [(q, qd, qdd)],
                                         torque_floor=torque_floor,
                                         reference=full_torque(robot, terms))
        if deployed:
            model, sel = ex, ex_sel
        elif exact_explicit:
            full, sel = build_model(robot, terms, peaks, tolerance=0.0, rule="budget",
                                    torque_floor=torque_floor,
                                    chapter_choices=ranking.choices(), **common)
            model = exact_explicit_model(full, rec.guarantee, tolerance)
    else:
        skipped = ("not built: the explicit G-D model of this arm is estimated too large to "
                   "pay (give --explicit always to derive it)") if form != "recursive" or \
            explicit == "never" else ("not built: the explicit G-D model is not derived under "
                                      "--form recursive, where it cannot be deployed (give "
                                      "--explicit always to derive it)")
    model = dataclasses.replace(model, costs=costs,
                                full_cost=dict(costs.get("explicit, full", model.full_cost)),
                                program_cache=model.program(),
                                guarantee=model.guarantee if model.guarantee is not None
                                else _trajectory_guarantee(model, sel, trajectory, missing))
    model = with_inertia_check(model, q)            # D_s positive definite where it holds
    table = cost_rows(robot.n, model, other=other, ladder_rows=rows, formulation_counts=counts)

    def finish(other_error):
        extra = simplified_dataset(model, sel, other=other, ladder_rows=rows, cost_table=table,
                                   other_error=other_error,
                                   full_terms=terms if derive else None)
        if skipped:
            extra.attrs["simplified_ladder_skipped"] = skipped
        return extra

    return model, other, finish


def exact_explicit_wins(recursive_cost, full_cost):
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


def exact_explicit_model(full, guarantee, tolerance,
                   why="cheaper than the recursive model pruned over the region"):
    """The exact explicit model deployed under a region guarantee (bound 0).

    Parameters
    ----------
    full : SimplifiedModel
        The explicit model at EPS = 0 (nothing dropped that contributes).
    guarantee : Guarantee
        The region guarantee of the recursive model pruned over the same region
        (:func:`region_model`): its region and scale s_i are kept.
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
    from ..core.selection.choices import full_choices
    from ..io.explicit_cache import explicit_terms
    from .simplify import full_program

    n = full.robot.n
    terms, _ = explicit_terms(full.robot)
    program = full_program(full.robot, terms)
    return dataclasses.replace(
        full, tolerance=float(tolerance), bound=[0.0] * n, terms=terms,
        choices=full_choices(n), cost=program.cost(), program_cache=program,
        guarantee=dataclasses.replace(
            guarantee, bound=np.zeros(n), sampled_error=np.zeros(n),
            method=f"the exact explicit G-D model (nothing dropped), {why}; scale: "
                   + guarantee.method))


def _trajectory_guarantee(model, sel, trajectory, missing=""):
    """The explicit budget model's guarantee on its trajectory (None: chapter rule)."""
    from ..core.selection.guarantee import Guarantee

    if model.rule != "budget":
        return None
    return Guarantee("trajectory", float(model.tolerance), bound=np.asarray(model.bound, float),
                     scale=np.asarray(sel.scale, float), trajectory_sha256=trajectory.sha256,
                     region_missing=missing,
                     method="sum of the dropped terms' peak contributions on the trajectory "
                            "(triangle inequality)")


def _ops(cost):
    return int(cost["multiplications"]) + int(cost["additions"])
