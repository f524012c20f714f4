"""The sweep report's words about the merged model: its rule, what it keeps, its guarantee
(as the model states it, :meth:`gd_analyze.simplify.guarantee.Guarantee.statement`) and
which swept trajectories that covers, generated from the stored sweep
(:func:`gd_analyze.jobs.sweep_merged.with_budget_model`); :mod:`gd_analyze.report.sweep_text`
puts them in the report's context."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..ranking.ranking import ROUND_OFF_CLAUSE, joint_units_text
from ..store.sweep_view import MergedModel
from .common import count, torque_units
from .common import pct as _pct
from .main_text import gravity_clause, model_sentence
from .markup import scope as scope_markup
from .markup import sub as _sub
from .simplified_section import region_pruning
from .sweep_figures import torque_error_round_off

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr

__all__ = ["merged_claim", "coverage"]


def merged_claim(ds: MergedModel | xr.Dataset) -> str:
    """The summary's clause on the budget rule's merged model: what its error is guaranteed
    within and where, its bound and its largest measured error.

    Parameters
    ----------
    ds : MergedModel or xarray.Dataset
        The budget rule's merged model (:class:`gd_analyze.store.sweep_view.MergedModel`), or a
        sweep dataset with it.

    Returns
    -------
    str
        Without a leading subject ("is guaranteed within ..."); for a region model the
        guarantee's own statement and which swept trajectories lie in the region
        (:func:`coverage`).
    """
    m = MergedModel.of(ds)
    eps = f"{float(m.tolerance):g}"
    if m.region:
        said = m.guarantee
        return (f"is guaranteed {scope_markup(said['statement'])} ({_SI} = the largest "  # type: ignore[index]  # a merged model's
                f"|{_TAU_I}| found over the region, at least {_floor(m)}); "
                f"{_bound_clause(m)}{coverage(m)}")
    claim = (f"is guaranteed within \u03b5\u00b7{_SI} (\u03b5 = {eps}), {ROUND_OFF_CLAUSE}, "
             "on every swept "
             f"trajectory ({_SI} = max(that trajectory's peak |{_TAU_I}|, "
             f"{_floor(m)})); {_bound_clause(m)}its largest "
             f"measured peak error is "
             f"{_pct(m.worst_scaled_error)} of {_SI}")
    beyond = m.beyond_floor
    if beyond is not None:
        rel, j, over = beyond
        claim += (f". Relative to peak |\u03c4{_sub('i')}| itself, below the torque floor, "
                  f"nothing is guaranteed: the error reaches {_pct(rel)} (joint {j}; above "
                  f"\u03b5 on joint{'s' if len(over) > 1 else ''} "
                  f"{', '.join(map(str, over))})")
    return claim


def coverage(ds: MergedModel | xr.Dataset) -> str:
    """Which swept trajectories a region model's proof covers, and its largest measured error
    there, as a clause (:func:`gd_analyze.store.sweep_guarantee.merged_guarantee`); the ones
    outside the region are named, at most five, with why.

    Parameters
    ----------
    ds : MergedModel or xarray.Dataset
        A merged model proved over the joint-limit region, or a sweep dataset with it.

    Returns
    -------
    str
        E.g. "every one of the 20 swept trajectories lies in the region, where its largest
        measured peak error is 0.02 % of s_i".
    """
    said = MergedModel.of(ds).guarantee
    K, outside = len(said["covered"]), said["outside"]  # type: ignore[index]  # a merged model's
    inside = K - len(outside)
    worst = f"its largest measured peak error is {_pct(said['worst'])} of {_SI}"  # type: ignore[index]  # a merged model's
    if not outside:
        return (f"every one of the {count(K)} swept trajector{'y' if K == 1 else 'ies'} lies "
                f"in the region, where {worst}")
    named = "; ".join(f"{src}: {why}" for src, why, _ in outside[:5]) + (
        "" if len(outside) <= 5 else f"; and {count(len(outside) - 5)} more (merged_covered in "
                                     "sweep.h5)")
    there = (f"{count(inside)} of the {count(K)} swept trajectories lie in the region, where "
             f"{worst}" if inside else f"none of the {count(K)} swept trajectories lies in the "
                                       "region")
    return (f"{there}; {count(len(outside))} lie{'s' if len(outside) == 1 else ''} outside it "
            f"and {'is' if len(outside) == 1 else 'are'} not covered by the proof ({named}), "
            f"where its error reaches {_pct(max(w for _, _, w in outside))} of {_SI}")


def _acts_on(m):
    """Where the recursive merged model's pairs were judged, in words."""
    return "the joint-limit region" if m.region else "the swept trajectories"


def _region_rule(m):
    """How a region model was built and what it guarantees, for Sec. 5: the main report's
    words on pruning over the region (:func:`gd_analyze.report.simplified_section.region_pruning`),
    the guarantee's statement and the swept trajectories it covers."""
    eps = f"{float(m.tolerance):g}"
    statement = scope_markup(str(m.guarantee_statement))
    head = (f"One model for the whole sweep, by the budget rule (\u03b5 = {eps}) over the "
            "robot's joint-limit region (its position, velocity and acceleration limits), as "
            "the main job builds it: the region does not depend on the trajectories. ")
    if m.form != "recursive":
        how = ("It is the exact explicit G-D model (nothing dropped, bound 0), which holds at "
               "every state of the region. ")
    elif int(0 if m.pairs_dropped is None else m.pairs_dropped):
        how = ("It is the customized recursive Newton-Euler model on the base inertial "
               "parameters. " + region_pruning(int(m.pairs), int(m.pairs_dropped),
                                               bound=f"at most {_worst_bound(m)}") + " ")
    else:
        how = ("It is the exact customized recursive Newton-Euler model on the base inertial "
               "parameters: no pair fits the budget by its proved bound, nothing is dropped. ")
    return (head + how + f"The model's guarantee: {statement}. On the sweep, "
            + coverage(m) + ".")


def _merged_rule(m):
    """The merged model's rule, the heading of its section and its description, in words that
    follow the rule: a bound only for the budget rule."""
    rule = m.rule
    if rule == "budget" and m.region:
        eps = f"{float(m.tolerance):g}"
        return rule, (f"5. Merged model (budget rule over the joint-limit region, \u03b5 = "
                      f"{eps}) and its torque error"), (
            _region_rule(m) + " " + _keeps(m) + " " + _cost_sentence(m, table=True))
    if rule == "budget":
        eps = f"{float(m.tolerance):g}"
        recursive = m.form == "recursive"
        what = ("One customized recursive Newton-Euler model on the base inertial parameters "
                "for the whole sweep, by the budget rule: the peak contribution of every (base "
                "parameter, part) pair (inertial, velocity, gravity), computed per trajectory "
                "by the dask workers," if recursive else
                "One explicit model for the whole sweep, by the budget rule: every term's peak "
                "contribution")
        return rule, f"5. Merged model (budget rule, \u03b5 = {eps}) and its torque error", (
            f"{what} on each trajectory is divided by that trajectory's {_SI} = "
            f"max(peak |{_TAU_I}|, torque floor), and {'pairs' if recursive else 'terms'} are "
            f"dropped while these ratios sum to at most \u03b5 = {eps} for every joint. By the "
            f"triangle inequality its torque error is guaranteed within \u03b5\u00b7{_SI}, "
            f"{ROUND_OFF_CLAUSE}, on every swept trajectory (not on others)"
            + ("; the bound on each trajectory, "
               + ("the sum of the dropped pairs' peaks there" if recursive else
                  f"the sum of the dropped terms' largest ratios times its {_SI}")
               + f", is stored per trajectory and joint in sweep.h5 and is at most "
               f"{_worst_bound(m)}. "
               if m.bound is not None else ". ")
            + _keeps(m) + ("" if recursive else " The budget weighs single terms too, so a "
                            "part it keeps may lose some of its terms.") + " "
            + _cost_sentence(m, table=True))
    return rule, "5. Merged model (chapter rule, no error bound) and its torque error", (
        _MERGED_TEXT + " This rule has no error bound: the errors below are measured, not "
                       "guaranteed. " + _keeps(m) + " " + _cost_sentence(m, table=True))


def _keeps(m):
    """What the merged model keeps of D, h and c, in the words of the main and the control
    reports (:func:`gd_analyze.report.main_text.model_sentence`), from the stored choices and
    counts of its terms of c (:func:`gd_analyze.jobs.sweep_merged.with_model_cost`)."""
    rule = m.rule
    if m.form == "recursive":
        text = model_sentence(recursive=_pairs(m), gravity=_recursive_gravity(m),
                              trajectory=_acts_on(m))
        pruned = [lab for lab, c in zip(m.elements, m.choice) if c == "pruned"]
        return text.replace("The simplified model", "The merged model", 1) + (
            " It computes every element of D and h as a sum over the base parameters; "
            + (f"the dropped parts change {len(pruned)} of them on the swept trajectories "
               f"({', '.join(pruned)}: choice \u201cpruned\u201d in the tables), the others "
               "are exact (\u201cboth\u201d)." if pruned else
               "the dropped parts change none of them on the swept trajectories beyond "
               "round-off (choice \u201cboth\u201d in the tables)."))
    kept, full = m.c_terms_kept, m.c_terms
    gravity = gravity_clause(rule, c_terms=(kept, full) if min(kept, full) >= 0 else None)
    text = model_sentence(choice=list(m.choice), gravity=gravity)
    return text.replace("The simplified model", "The merged model", 1)


def _pairs(m):
    """A recursive merged model's (base parameters, pairs dropped, pairs), as stored."""
    return int(m.base_parameters), int(m.pairs_dropped), int(m.pairs)


def _recursive_gravity(m):
    """gravity_clause of a recursive merged model, from the names stored with it."""
    names = [x.strip() for x in m.gravity_dropped.split(",")]
    return gravity_clause("budget", gravity_dropped=[x for x in names if x])


def _recursive_clause(m):
    """What a recursive merged model is and drops, for the summary: "is the ... model on 36
    base parameters and drops 5 of the 80 (parameter, part) pairs that act on the swept
    trajectories" (on the joint-limit region, for a region model)."""
    b, dropped, pairs = _pairs(m)
    head = f"is the customized recursive Newton-Euler model on {b} base parameters"
    if dropped == 0:
        return head + ", exact: it drops nothing"
    return (f"{head} and drops {dropped} of the {pairs} (parameter, part) pairs that act on "
            f"{_acts_on(m)}")


def _worst_bound(m):
    """The largest guaranteed bound over the trajectories relative to their s_i, in words
    ("0.41 % of s_i (joint 2)", "0 (nothing dropped contributes)"); None without
    merged_bound."""
    if m.bound is None or m.scale is None:
        return None
    bound = np.asarray(m.bound, float)
    scale = np.asarray(m.scale, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(bound > 0, bound / scale, 0.0)
    rel = np.where(np.isfinite(rel), rel, np.inf)
    if not rel.size or not rel.max() > 0:
        return "0 (nothing dropped contributes)"
    k, j = np.unravel_index(np.argmax(rel), rel.shape)
    return f"{_pct(rel[k, j])} of {_SI} (joint {j + 1})"


def _bound_clause(m):
    """The summary's clause on the bound per trajectory ("its bound there is at most 0.41 %
    of s_i (joint 2), "); "" without merged_bound."""
    worst = _worst_bound(m)
    if worst is None:
        return ""
    return f"its bound is at most {worst}; " if m.region else \
        f"its bound there is at most {worst}, "


def _held_out(m):
    """The merged model's largest error on the held-out trajectories (measured, not
    guaranteed by the sweep; a region model's proof covers those in its region), relative to
    their max(peak |tau_i|, floor), or to s_i over the region for a region model, as a
    sentence; "" if none."""
    if m.held_out_error_peak is None:
        return ""
    peak = np.asarray(m.held_out_error_peak, float)
    tau = np.asarray(m.held_out_tau_peak, float)
    floor = m.torque_floor
    region = m.region
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = peak / (np.asarray(m.scale, float)[0] if region else
                      np.maximum(tau, floor))
    rel = np.where(torque_error_round_off(m, peak, tau) | ~np.isfinite(rel), 0.0, rel)
    j = int(np.argmax(rel))
    k = m.held_out_trajectories
    scale = (f"peak |{_TAU_I}| over them" if floor == 0 else
             f"max(peak |{_TAU_I}| over them, {_floor(m)})")
    head = f"On {count(k)} held-out random trajector{'y' if k == 1 else 'ies'} (another seed, " \
        "not swept) the merged model's error is measured"
    if region:
        inside = m.held_out_inside_region
        return (f"{head}: at most {_pct(rel[j])} of {_SI} (joint {j + 1}); {count(inside)} of "
                f"them lie{'s' if inside == 1 else ''} in the region, where its bound is "
                "proved. ")
    return (f"{head}, not guaranteed: at most "
            f"{_pct(rel[j])} of {scale} (joint {j + 1}). ")


def _cost_sentence(m, table=False):
    """The merged model's operations per set point against the exact recursive model, the full
    explicit model and Newton-Euler, counted on the models (stored by
    :func:`gd_analyze.jobs.sweep_merged.with_model_cost`), with a word on why where it
    costs more than one of them; "" for a file without the counts."""
    if m.costs is None:
        return ""
    names = list(m.costs.evaluators)
    ops = dict(zip(names, (m.costs.multiplications + m.costs.additions).tolist()))
    mine = ops[names[0]]
    mul, add = int(m.costs.multiplications[0]), int(m.costs.additions[0])
    others = [(n, ops[n]) for n in names[1:]]
    text = (f"It costs {count(mine)} operations per set point ({count(mul)} multiplications, "
            f"{count(add)} additions); " + ", ".join(f"{n}: {count(o)}" for n, o in others)
            + (" (Table 5.2, counted, not timed)." if table else "."))
    recursive, full = ops.get("exact recursive model"), ops.get("full explicit model")
    if (recursive is not None and mine > recursive and names[0].endswith("(explicit form)")
            and m.rule == "chapter"):
        text += (" It costs more than the exact recursive model: the chapter rule's merge "
                 "keeps parts of the explicit model's elements, so it is of the explicit form "
                 "only.")
    if full is not None and mine > full:
        text += (" It costs more than the full explicit model: where an element keeps one "
                 "part, its coefficients are that part's, not the sum of both, so the code "
                 "generator's factoring finds less to share"
                 + ("; the chapter rule has no fallback to the full model."
                    if m.rule == "chapter" else "."))
    return text + " "


def _floor(m):
    """The torque floor with the units of every joint type ("0 N m", or "0 N m (joints 1, 2),
    0 N (joint 3)" on a mixed arm)."""
    floor = f"{m.torque_floor:g}"
    return joint_units_text([f"{floor} {u}" for u in torque_units(m)])


def _models(m):
    """What the own and the merged models are, and which carries a guarantee, in words
    generated from the dataset's rules: (own, merged)."""
    own_rule, rule = m.own_rule, m.rule
    bound = {"chapter": "share-based classes of Sec. 3.4.1, no error bound",
             "budget": "guaranteed within \u03b5\u00b7" + _SI + f", {ROUND_OFF_CLAUSE}, on its "
                       "own trajectory"}
    own = f"each trajectory's own simplified model ({own_rule} rule: {bound[own_rule]})"
    if rule == "budget" and m.region:
        merged = (f"the merged model (budget rule, \u03b5 = "
                  f"{float(m.tolerance):g}: "
                  f"{scope_markup(str(m.guarantee_statement))})")
    elif rule == "budget":
        merged = (f"the merged model (budget rule, \u03b5 = "
                  f"{float(m.tolerance):g}: guaranteed within "
                  f"\u03b5\u00b7{_SI}, {ROUND_OFF_CLAUSE}, on every swept trajectory)")
    else:
        merged = "the merged model (chapter rule: no error bound)"
    return own, merged


_MERGED_TEXT = ("Each trajectory has its own simplified model (keep the dominant part of each "
                "element, both if neither dominates, nothing if negligible). The merged model is "
                "one model for the whole sweep: a part of an element is dropped only where every "
                "trajectory's model drops it. The chapter rule drops parts of D and h only, "
                "never a term of gravity: \u03c4" + _sub("s") + " = D" + _sub("s")
                + " q\u0308 + h" + _sub("s") + " + c.")
_SI = "s" + _sub("i")
_TAU_I = "\u03c4" + _sub("i")

