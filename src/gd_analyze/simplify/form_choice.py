"""Which form of the simplified model is deployed: the one decision, and the check that can
overturn it.

The pruned recursive model, the explicit model of the rule, or the exact explicit model under
a region guarantee (:func:`choose_form`); an explicit model whose D_s is not proved positive
definite gives way to the recursive one (:func:`inertia_checked`). :func:`deploy` builds the
candidates for the main job, makes that decision and starts the tolerance ladder of the form
deployed, returning a :class:`Deployment`. Nothing here prints or writes files.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from concurrent.futures import Future
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..certify.positive_definite import with_inertia_check
from ..dynamics.opcount import operation_counts
from ..symbolic.explicit_estimate import EXPENSIVE_TERMS, estimate_terms
from .choices import full_choices
from .deploy import build_recursive, guarantee_region, recursive_selection, restored_rebuild
from .explicit_model import (
    LADDER,
    build_model,
    collect_peaks,
    full_program,
    full_torque,
    ladder,
    ladder_skipped,
)
from .guarantee import Guarantee
from .recursive_ladder import LadderMeter, recursive_ladder
from .region_memo import UNKEPT, Derivations
from .simplified import total_operations

if TYPE_CHECKING:
    from ..certify.region import Region
    from ..model.robot import Robot
    from ..ranking.ranking import Ranking
    from ..symbolic.explicit import Term
    from .budget import PartPeaks, Selection
    from .choices import Motion
    from .options import SimplifyOptions
    from .simplified import SimplifiedModel

__all__ = ["FormChoice", "choose_form", "recursive_note", "inertia_checked", "recursive_costs",
           "exact_explicit_model", "Deployment", "deploy"]


@dataclass(frozen=True)
class FormChoice:
    """Which form of the simplified model is deployed, and why.

    Attributes
    ----------
    form : {"recursive", "explicit", "exact explicit"}
        The pruned recursive model; the explicit model of the rule (pruned within the budget,
        or the chapter's choices); or the exact explicit model (nothing dropped), under a
        region guarantee.
    why : str
        For ``"exact explicit"``: why it is deployed (the clause its guarantee's ``method``
        gives); for ``"recursive"`` where a pruned explicit model was a candidate: the
        sentence saying why that one is not deployed; else "".
    """

    form: str
    why: str = ""


def choose_form(rule: str, form: str, proved: bool, recursive: Mapping[str, Any],
                explicit: Mapping[str, Any] | None = None,
                full: Mapping[str, Any] | None = None,
                exact: tuple[bool, bool] = (False, False)) -> FormChoice:
    """The one decision of which model is deployed: recursive, explicit or exact explicit.

    Parameters
    ----------
    rule : {"budget", "chapter"}
        The selection rule.
    form : {"cheapest", "recursive", "explicit"}
        The ``--form`` choice.
    proved : bool
        The recursive model's bound is proved over the joint-limit region.
    recursive : mapping
        The pruned recursive model's ``multiplications`` and ``additions``.
    explicit : mapping, optional
        The explicit model's of the rule, where one is a candidate (None: not derived, or,
        as in a sweep over the region, not built).
    full : mapping, optional
        The full explicit model's, where it is derived.
    exact : tuple of (bool, bool), optional
        The recursive and the explicit model of the rule drop nothing but terms whose bound is
        0 at every joint (said "exact", not "pruned", in :func:`recursive_note`).

    Returns
    -------
    FormChoice
        The chapter rule's model is explicit. ``form="explicit"`` deploys the pruned explicit
        model where it is a candidate, else the exact one under a region guarantee.
        ``form="cheapest"`` deploys the model that counts fewest operations
        (multiplications + additions, the recursive one on a tie) among the recursive one
        and, on the trajectory, the pruned explicit one or, over the region, the exact
        explicit one (a pruned explicit model's bound holds on the trajectory only).
    """
    rec = total_operations(recursive)
    if rule == "chapter" or explicit is not None and (form == "explicit" or (
            form == "cheapest" and not proved and total_operations(explicit) < rec)):
        return FormChoice("explicit")
    if proved and full is not None and form == "explicit":
        return FormChoice("exact explicit", "asked for (--form explicit): the explicit model "
                                            "proved over the region")
    if proved and full is not None and form == "cheapest" and total_operations(full) < rec:
        return FormChoice("exact explicit",
                          "cheaper than the recursive model pruned over the region")
    if explicit is None:
        return FormChoice("recursive")
    return FormChoice("recursive", recursive_note(rec, total_operations(explicit), form, proved,
                                                  exact=exact))


def recursive_note(recursive: int, explicit: int, form: str, proved: bool,
                   restored: bool = False, exact: tuple[bool, bool] = (False, False)) -> str:
    """The sentence saying why the pruned recursive model is deployed, not the explicit one.

    Parameters
    ----------
    recursive, explicit : int
        Operations per set point (multiplications + additions) of the deployed recursive model
        and of the pruned explicit model of the rule.
    form : {"cheapest", "recursive", "explicit"}
        The ``--form`` choice.
    proved : bool
        The recursive model's bound is proved over the joint-limit region.
    restored : bool, optional
        Parameters were restored after the choice, for the proof that D_s is positive definite
        (:func:`gd_analyze.certify.positive_definite.with_inertia_check`): ``recursive`` is the
        cost after it.
    exact : tuple of (bool, bool), optional
        The recursive and the explicit model drop nothing but terms whose bound is 0 at every
        joint: each is called exact, not pruned.

    Returns
    -------
    str
        One sentence with both counts, and why where the recursive model does not count fewer
        operations (``--form recursive``, a bound proved over the region, a tie).

    Examples
    --------
    >>> recursive_note(290, 498, "cheapest", True).split(" (")[1]
    "290 operations against the pruned explicit one's 498)."
    """
    why = (", --form recursive" if form != "cheapest" else
           ", whose bound holds on this trajectory only, while the recursive one's is proved "
           "over the joint-limit region" if proved and explicit < recursive else
           ": a tie, which the recursive one wins" if explicit == recursive else "")
    after = (", with the parameters restored for the proof that its inertia matrix is "
             "positive definite," if restored else "")
    word = ["exact" if e else "pruned" for e in exact]
    return (f"The deployed model is the {word[0]} recursive one ({recursive:,} operations{after} "
            f"against the {word[1]} explicit one's {explicit:,}{why}).")


def inertia_checked(model: SimplifiedModel, recursive: SimplifiedModel,
                    rebuild: Callable[..., SimplifiedModel], q: np.ndarray | None = None
                    ) -> tuple[SimplifiedModel, SimplifiedModel | None]:
    """The deployed model with D_s proved positive definite, or the recursive one in place of
    an explicit model whose D_s is not.

    Parameters
    ----------
    model : SimplifiedModel
        The model chosen (:func:`choose_form`).
    recursive : SimplifiedModel
        The pruned recursive model built beside it.
    rebuild : callable
        :func:`gd_analyze.certify.positive_definite.with_inertia_check`'s ``rebuild``.
    q : ndarray, shape (N, n), optional
        The positions of a trajectory guarantee [rad; m].

    Returns
    -------
    model : SimplifiedModel
        :func:`gd_analyze.certify.positive_definite.with_inertia_check` of ``model``; an
        explicit model whose D_s is not proved, where its bound is claimed over the region or
        where D_s is not positive definite at a sampled position (NaN is not positive), is
        replaced by the recursive model where that one's D_s is proved.
    replaced : SimplifiedModel or None
        The explicit model replaced, with its check.
    """
    model = with_inertia_check(model, q, rebuild=rebuild)
    check: Any = model.inertia_check
    claim = model.guarantee is not None and model.guarantee.proved
    if model.recursive is None and not check["proved"] and (
            claim or not check["sampled_min_eigenvalue"] > 0):
        fallback = with_inertia_check(recursive, q, rebuild=rebuild)
        if (fallback.inertia_check or {}).get("proved"):
            return fallback, model
    return model, None


def recursive_costs(model: SimplifiedModel, counts: Mapping[str, Any] | None = None
                    ) -> dict[str, dict[str, int]]:
    """The ``costs`` compared with a deployed model: the exact recursive model's, the pruned
    recursive model's and Newton-Euler's as implemented.

    Parameters
    ----------
    model : SimplifiedModel
        The pruned recursive model (:func:`gd_analyze.simplify.deploy.build_recursive`).
    counts : dict, optional
        :func:`gd_analyze.dynamics.opcount.operation_counts` of the robot; counted if not
        given.

    Returns
    -------
    dict
        ``"exact recursive"``, ``"recursive, budget"`` and ``"newton-euler"``, each with
        ``multiplications`` and ``additions``.
    """
    ne = (operation_counts(model.robot) if counts is None else counts)["newton-euler"]
    return {"exact recursive": model.costs["exact recursive"],
            "recursive, budget": dict(model.cost),
            "newton-euler": {"multiplications": int(ne["multiplications"]),
                             "additions": int(ne["additions"])}}


def exact_explicit_model(full: SimplifiedModel, terms: Term, guarantee: Guarantee,
                         tolerance: float,
                         why: str = "cheaper than the recursive model pruned over the region"
                         ) -> SimplifiedModel:
    """The exact explicit model deployed under a region guarantee (bound 0).

    Parameters
    ----------
    full : SimplifiedModel
        The explicit model at EPS = 0 (nothing dropped that contributes).
    terms : Term
        All the robot's explicit terms (:func:`gd_analyze.symbolic.explicit.derive`).
    guarantee : Guarantee
        The region guarantee of the recursive model pruned over the same region
        (:func:`gd_analyze.simplify.deploy.region_model`): its region and scale s_i are kept.
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
    program = full_program(full.robot, terms)
    return dataclasses.replace(
        full, tolerance=float(tolerance), bound=[0.0] * n, terms=terms,
        choices=full_choices(n), cost=program.cost(), program_cache=program,
        guarantee=dataclasses.replace(
            guarantee, bound=np.zeros(n), sampled_error=np.zeros(n), tilings=(),
            decomposed=(), bound_method=(), joint_sum_arithmetic="",
            method=f"the exact explicit G-D model (nothing dropped), {why}; scale: "
                   + guarantee.method))


@dataclass(frozen=True, eq=False)
class Deployment:
    """The main job's simplified model and what its choice leaves for the record.

    Attributes
    ----------
    model : SimplifiedModel
        The deployed model, its D_s checked (:func:`inertia_checked`).
    other : SimplifiedModel or None
        The explicit model of the other rule, compared with it (None: not derived).
    selection : Selection
        The deployed model's selection (its dropped terms or pairs, bound and scale).
    ladder : list of dict or LadderMeter
        The tolerance ladder's rows of the form deployed, or the recursive form's rungs
        waiting to be measured on the trajectory (:meth:`meter`); empty where it is not
        built.
    ladder_skipped : str
        Why the ladder is not built, or "".
    form_note : str
        Why the deployed form is not the one first chosen, or why the recursive one was (also
        where ``--explicit auto`` left the explicit model underived, estimated too large), or
        "".
    region : Region or None
        The joint-limit region (None under the chapter rule or without limits).
    screen : dict or None
        The screen that chose the exact recursive model
        (:meth:`gd_analyze.certify.screen.RegionScreen.to_dict`), under a region guarantee.
    terms : Term or None
        The robot's explicit terms, where derived.
    counts : dict
        The formulations' operation counts (:func:`gd_analyze.dynamics.opcount.operation_counts`).
    """

    model: SimplifiedModel
    other: SimplifiedModel | None
    selection: Selection
    ladder: Any
    ladder_skipped: str
    form_note: str
    region: Region | None
    screen: Mapping[str, Any] | None
    terms: Term | None
    counts: Mapping[str, Any]

    def ladder_rows(self) -> list[dict[str, Any]]:
        """The ladder's rows (the meter's as measured so far: after the caller's pass).

        Returns
        -------
        list of dict
            As :func:`gd_analyze.simplify.recursive_ladder.recursive_ladder` or
            :func:`gd_analyze.simplify.explicit_model.ladder` give them.
        """
        return self.ladder.rows() if isinstance(self.ladder, LadderMeter) else list(self.ladder)

    def meter(self) -> LadderMeter | None:
        """The recursive ladder's rungs, built and waiting for the trajectory's blocks
        (:meth:`~gd_analyze.simplify.recursive_ladder.LadderMeter.update`), or None where the
        ladder is measured already or not built."""
        return self.ladder if isinstance(self.ladder, LadderMeter) else None


def deploy(robot: Robot, trajectory: Motion, ranking: Ranking, part_peaks: PartPeaks,
           options: SimplifyOptions, provenance: Mapping[str, Any],
           recursive_peaks: Future[Any], explicit_peaks: Future[Any] | None = None,
           derive: Derivations = UNKEPT, searches: Future[Any] | None = None) -> Deployment:
    """The main job's one decision: which simplified model is deployed, the model of the other
    rule compared with it, and the tolerance ladder of the form deployed.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    trajectory : Motion
        q, qd, qdd of shape (N, n), and its file's ``sha256``.
    ranking : Ranking
        The trajectory's dominance ranking (its chapter choices, thresholds and scales).
    part_peaks : PartPeaks
        Accumulated in the pass over the G-D terms.
    options : SimplifyOptions
        Tolerance, rule, torque floor, form, guarantee and region.
    provenance : dict
        Recorded with the models.
    recursive_peaks : Future
        The base parameters and their contribution peaks on the trajectory
        (:func:`gd_analyze.symbolic.pruning.contribution_peaks`), computed beside the caller.
    explicit_peaks : Future, optional
        The robot's explicit terms and their atom peaks on the trajectory; None: the explicit
        model is not derived.
    derive : Derivations, optional
        Where certifications and searches are kept between runs (default nowhere).
    searches : Future, optional
        :func:`gd_analyze.simplify.deploy.region_searches` of the robot's region at the
        model's EPS and the ladder's (:data:`gd_analyze.simplify.explicit_model.LADDER`),
        made beside the caller, for a model proved over the region; None: made here.

    Returns
    -------
    Deployment

    Notes
    -----
    The pruned recursive model is always built; the explicit model where ``explicit_peaks``
    is given. Which one is deployed is :func:`choose_form`'s decision, its D_s checked by
    :func:`inertia_checked`. The tolerance ladder is of the form deployed
    (:func:`gd_analyze.simplify.recursive_ladder.recursive_ladder` for the recursive one,
    pruned as it is). Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987) and the error budget
    (:mod:`gd_analyze.simplify.budget`).
    """
    tolerance, rule, torque_floor, form = (options.tolerance, options.rule,
                                           options.torque_floor, options.form)
    q, qd, qdd = trajectory.q, trajectory.qd, trajectory.qdd
    common: dict[str, Any] = dict(ranking=ranking, trajectory_sha256=trajectory.sha256,
                                  provenance=provenance)
    counts = operation_counts(robot)
    region, missing, proved = guarantee_region(robot, options.guarantee, options.region) \
        if rule == "budget" else (None, "", False)
    contributions = recursive_peaks.result()
    searched = searches.result() if searches is not None and proved else None
    rec, _ = build_recursive(robot, q, qd, qdd, tolerance=tolerance, torque_floor=torque_floor,
                             contributions=contributions, region=region if proved else None,
                             sample_region=region, region_missing=missing, derive=derive,
                             searches=searched, **common)
    costs = recursive_costs(rec, counts)
    ex: Any = None                 # the explicit model of the rule, its terms and peaks
    terms: Any = None
    other: SimplifiedModel | None = None
    if explicit_peaks is not None:
        terms, term = explicit_peaks.result()
        peaks = collect_peaks(robot, terms, q, qd, qdd, gd=part_peaks, term=term)
        ex, ex_sel = build_model(robot, terms, peaks, tolerance=tolerance, rule=rule,
                                 torque_floor=torque_floor,
                                 chapter_choices=ranking.choices(), **common)
        other, _ = build_model(robot, terms, peaks, tolerance=tolerance,
                               rule="chapter" if rule == "budget" else "budget",
                               torque_floor=torque_floor, chapter_choices=ranking.choices(),
                               **common)
        costs.update({f"explicit, {rule}": dict(ex.cost), "explicit, full": dict(ex.full_cost)})
    # a model whose dropped terms' bound is 0 everywhere is the exact one (pairs proved zero)
    rec_exact, ex_exact = (m is not None and not np.any(np.asarray(m.bound, float)) for m in (rec, ex))
    exact = (rec_exact, ex_exact)
    choice = choose_form(rule, form, proved, rec.cost, None if ex is None else ex.cost,
                         None if ex is None else ex.full_cost, exact)
    # a screen chose the exact recursive model; the sampled pre-screen skipped the region's
    # certification too (not the screen of the pairs searched under the proved bounds), so
    # no ladder is certified either
    screen = rec.provenance.get("region_screen") if proved else None
    screened = screen if screen and not screen.get("proved") else None
    rows: Any = []              # the ladder's rows, or its meter (recursive_ladder)
    sel: Any = None             # the deployed model's selection, set for each form below
    model, skipped = rec, _screened_ladder(screened)
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
    if model.guarantee is None and model.rule == "budget":     # the explicit budget model's
        model = dataclasses.replace(model, guarantee=Guarantee(   # on its trajectory
            "trajectory", float(model.tolerance), bound=np.asarray(model.bound, float),
            scale=np.asarray(sel.scale, float), trajectory_sha256=trajectory.sha256,
            region_missing=missing, region=region,
            method="sum of the dropped terms' peak contributions on the trajectory "
                   "(triangle inequality)"))
    # D_s proved positive definite where the bound holds; parameters restored where it is
    # not, the bound and sampled error derived again for the model finally deployed
    rebuild = restored_rebuild(q, qd, qdd, region=region if proved else None,
                               sample_region=region, region_missing=missing,
                               contributions=contributions, derive=derive)
    model, replaced = inertia_checked(model, with_costs(rec), rebuild, q)
    if form_note and replaced is None and model.cost != rec.cost:   # the restored model's count
        form_note = recursive_note(total_operations(model.cost), total_operations(ex.cost),
                                   form, proved, restored=True, exact=exact)
    if replaced is not None:
        check: Any = replaced.inertia_check
        form_note = ("The deployed model is the " + ("exact" if screen else "pruned")
                     + " recursive one: the explicit model's inertia matrix "
                     + ("was not proved positive definite over the region."
                        if replaced.guarantee is not None and replaced.guarantee.proved else
                        "is not positive definite at the sampled positions of the trajectory "
                        f"(smallest eigenvalue {check['sampled_min_eigenvalue']:.3g})."))
    if explicit_peaks is None and options.explicit == "auto" and form != "recursive":
        # not derived: estimated too large (gd_analyze.jobs.peak_jobs.derives_explicit)
        form_note = (f"The deployed model is the recursive one: the explicit model was not "
                     f"derived, its {estimate_terms(robot):,} estimated terms above the "
                     f"{EXPENSIVE_TERMS:,} of --explicit auto.")
    if model.recursive is not None:             # its own bound, restored pairs included
        sel, skipped, rows = recursive_selection(model), _screened_ladder(screened), []
    if model.recursive is not None and not screened:        # the recursive form's ladder
        # built here, measured by the caller's pass over the trajectory (Deployment.meter)
        rows = recursive_ladder(robot, contributions[0], (q, qd, qdd), LADDER, torque_floor,
                                region=region if proved else None,
                                contributions=contributions[1], deployed=model, beside=True,
                                derive=derive, searched=None if searched is None
                                else searched.rungs)
    return Deployment(model, other, sel, rows, skipped, form_note, region, screen, terms, counts)


def _screened_ladder(screen):
    """Why the ladder is not built when the pre-screen skipped the region's certification
    (or "" without a screen)."""
    return "" if not screen else (
        "not built: the region was not certified (" + str(screen["statement"])
        + "), and each rung would need its certification")
