"""The sweep report's words about the merged model: its rule, what it keeps, its guarantee
(as the model states it, :meth:`gd_analyze.core.selection.guarantee.Guarantee.statement`) and
which swept trajectories that covers, generated from the stored sweep
(:func:`gd_analyze.workflows.sweep_merged.with_budget_model`); :mod:`gd_analyze.reports.sweep_text`
puts them in the report's context."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..core.selection.ranking import ROUND_OFF_CLAUSE, joint_units_text
from ..io.sweep_datasets import beyond_the_floor
from ..io.sweep_guarantee import merged_guarantee
from .common import count, torque_units
from .common import pct as _pct
from .common import strings as _strings
from .main_text import gravity_clause, model_sentence
from .markup import scope as scope_markup
from .markup import sub as _sub
from .simplified_section import region_pruning
from .sweep_figures import torque_error_round_off

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr

__all__ = ["merged_claim", "coverage"]


def merged_claim(ds: xr.Dataset) -> str:
    """The summary's clause on the budget rule's merged model: what its error is guaranteed
    within and where, its bound and its largest measured error.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep dataset with the budget rule's merged model.

    Returns
    -------
    str
        Without a leading subject ("is guaranteed within ..."); for a region model the
        guarantee's own statement and which swept trajectories lie in the region
        (:func:`coverage`).
    """

    eps = f"{float(ds.attrs['merged_tolerance']):g}"
    if _region(ds):
        said = merged_guarantee(ds)
        return (f"is guaranteed {scope_markup(said['statement'])} ({_SI} = the largest "  # type: ignore[index]  # a merged model's
                f"|{_TAU_I}| found over the region, at least {_floor(ds)}); "
                f"{_bound_clause(ds)}{coverage(ds)}")
    claim = (f"is guaranteed within \u03b5\u00b7{_SI} (\u03b5 = {eps}), {ROUND_OFF_CLAUSE}, "
             "on every swept "
             f"trajectory ({_SI} = max(that trajectory's peak |{_TAU_I}|, "
             f"{_floor(ds)})); {_bound_clause(ds)}its largest "
             f"measured peak error is "
             f"{_pct(float(ds.attrs.get('merged_worst_scaled_error', np.nan)))} of {_SI}")
    beyond = beyond_the_floor(ds)
    if beyond is not None:
        rel, j, over = beyond
        claim += (f". Relative to peak |\u03c4{_sub('i')}| itself, below the torque floor, "
                  f"nothing is guaranteed: the error reaches {_pct(rel)} (joint {j}; above "
                  f"\u03b5 on joint{'s' if len(over) > 1 else ''} "
                  f"{', '.join(map(str, over))})")
    return claim


def coverage(ds: xr.Dataset) -> str:
    """Which swept trajectories a region model's proof covers, and its largest measured error
    there, as a clause (:func:`gd_analyze.io.sweep_guarantee.merged_guarantee`); the ones
    outside the region are named, at most five, with why.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep dataset with a merged model proved over the joint-limit region.

    Returns
    -------
    str
        E.g. "every one of the 20 swept trajectories lies in the region, where its largest
        measured peak error is 0.02 % of s_i".
    """
    said = merged_guarantee(ds)
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


def _region(ds):
    """Whether the merged model's guarantee is proved over the joint-limit region."""
    return str(ds.attrs.get("merged_guarantee_kind", "")) == "region"


def _acts_on(ds):
    """Where the recursive merged model's pairs were judged, in words."""
    return "the joint-limit region" if _region(ds) else "the swept trajectories"


def _region_rule(ds):
    """How a region model was built and what it guarantees, for Sec. 5: the main report's
    words on pruning over the region (:func:`gd_analyze.reports.simplified_section.region_pruning`),
    the guarantee's statement and the swept trajectories it covers."""
    eps = f"{float(ds.attrs['merged_tolerance']):g}"
    statement = scope_markup(str(ds.attrs["merged_guarantee_statement"]))
    head = (f"One model for the whole sweep, by the budget rule (\u03b5 = {eps}) over the "
            "robot's joint-limit region (its position, velocity and acceleration limits), as "
            "the main job builds it: the region does not depend on the trajectories. ")
    if _form(ds) != "recursive":
        how = ("It is the exact explicit G-D model (nothing dropped, bound 0), which holds at "
               "every state of the region. ")
    elif int(ds.attrs.get("merged_pairs_dropped", 0)):
        how = ("It is the customized recursive Newton-Euler model on the base inertial "
               "parameters. " + region_pruning(int(ds.attrs["merged_pairs"]),
                                               int(ds.attrs["merged_pairs_dropped"]),
                                               bound=f"at most {_worst_bound(ds)}") + " ")
    else:
        how = ("It is the exact customized recursive Newton-Euler model on the base inertial "
               "parameters: no pair fits the budget by its proved bound, nothing is dropped. ")
    return (head + how + f"The model's guarantee: {statement}. On the sweep, "
            + coverage(ds) + ".")


def _merged_rule(ds):
    """The merged model's rule, the heading of its section and its description, in words that
    follow the rule: a bound only for the budget rule."""
    rule = str(ds.attrs.get("merged_rule", "chapter"))
    if rule == "budget" and _region(ds):
        eps = f"{float(ds.attrs['merged_tolerance']):g}"
        return rule, (f"5. Merged model (budget rule over the joint-limit region, \u03b5 = "
                      f"{eps}) and its torque error"), (
            _region_rule(ds) + " " + _keeps(ds) + " " + _cost_sentence(ds, table=True))
    if rule == "budget":
        eps = f"{float(ds.attrs['merged_tolerance']):g}"
        recursive = _form(ds) == "recursive"
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
               f"{_worst_bound(ds)}. "
               if "merged_bound" in ds.variables else ". ")
            + _keeps(ds) + ("" if recursive else " The budget weighs single terms too, so a "
                            "part it keeps may lose some of its terms.") + " "
            + _cost_sentence(ds, table=True))
    return rule, "5. Merged model (chapter rule, no error bound) and its torque error", (
        _MERGED_TEXT + " This rule has no error bound: the errors below are measured, not "
                       "guaranteed. " + _keeps(ds) + " " + _cost_sentence(ds, table=True))


def _keeps(ds):
    """What the merged model keeps of D, h and c, in the words of the main and the control
    reports (:func:`gd_analyze.reports.main_text.model_sentence`), from the stored choices and
    counts of its terms of c (:func:`gd_analyze.workflows.sweep_merged.with_model_cost`)."""
    rule = str(ds.attrs.get("merged_rule", "chapter"))
    if _form(ds) == "recursive":
        text = model_sentence(recursive=tuple(int(ds.attrs[f"merged_{k}"]) for k in
                                              ("base_parameters", "pairs_dropped", "pairs")),
                              gravity=_recursive_gravity(ds),
                              trajectory=_acts_on(ds))
        choice = _strings(ds["merged_choice"].values)
        pruned = [lab for lab, c in zip(_strings(ds["element"].values), choice)
                  if c == "pruned"]
        return text.replace("The simplified model", "The merged model", 1) + (
            " It computes every element of D and h as a sum over the base parameters; "
            + (f"the dropped parts change {len(pruned)} of them on the swept trajectories "
               f"({', '.join(pruned)}: choice \u201cpruned\u201d in the tables), the others "
               "are exact (\u201cboth\u201d)." if pruned else
               "the dropped parts change none of them on the swept trajectories beyond "
               "round-off (choice \u201cboth\u201d in the tables)."))
    kept, full = (int(ds.attrs.get(k, -1)) for k in ("merged_c_terms_kept", "merged_c_terms"))
    gravity = gravity_clause(rule, c_terms=(kept, full) if min(kept, full) >= 0 else None)
    text = model_sentence(choice=_strings(ds["merged_choice"].values), gravity=gravity)
    return text.replace("The simplified model", "The merged model", 1)


def _form(ds):
    """The merged model's form as the dataset records it (recursive or explicit)."""
    return str(ds.attrs.get("merged_form", "explicit"))


def _recursive_gravity(ds):
    """gravity_clause of a recursive merged model, from the names stored with it."""
    names = [x.strip() for x in str(ds.attrs.get("merged_gravity_dropped", "")).split(",")]
    return gravity_clause("budget", gravity_dropped=[x for x in names if x])


def _recursive_clause(ds):
    """What a recursive merged model is and drops, for the summary: "is the ... model on 36
    base parameters and drops 5 of the 80 (parameter, part) pairs that act on the swept
    trajectories" (on the joint-limit region, for a region model)."""
    b, dropped, pairs = (int(ds.attrs[f"merged_{k}"]) for k in
                         ("base_parameters", "pairs_dropped", "pairs"))
    head = f"is the customized recursive Newton-Euler model on {b} base parameters"
    if dropped == 0:
        return head + ", exact: it drops nothing"
    return (f"{head} and drops {dropped} of the {pairs} (parameter, part) pairs that act on "
            f"{_acts_on(ds)}")


def _worst_bound(ds):
    """The largest guaranteed bound over the trajectories relative to their s_i, in words
    ("0.41 % of s_i (joint 2)", "0 (nothing dropped contributes)"); None without
    merged_bound."""
    if "merged_bound" not in ds.variables or "merged_scale" not in ds.variables:
        return None
    bound = np.asarray(ds["merged_bound"].values, float)
    scale = np.asarray(ds["merged_scale"].values, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(bound > 0, bound / scale, 0.0)
    rel = np.where(np.isfinite(rel), rel, np.inf)
    if not rel.size or not rel.max() > 0:
        return "0 (nothing dropped contributes)"
    k, j = np.unravel_index(np.argmax(rel), rel.shape)
    return f"{_pct(rel[k, j])} of {_SI} (joint {j + 1})"


def _bound_clause(ds):
    """The summary's clause on the bound per trajectory ("its bound there is at most 0.41 %
    of s_i (joint 2), "); "" without merged_bound."""
    worst = _worst_bound(ds)
    if worst is None:
        return ""
    return f"its bound is at most {worst}; " if _region(ds) else \
        f"its bound there is at most {worst}, "


def _held_out(ds):
    """The merged model's largest error on the held-out trajectories (measured, not
    guaranteed by the sweep; a region model's proof covers those in its region), relative to
    their max(peak |tau_i|, floor), or to s_i over the region for a region model, as a
    sentence; "" if none."""
    if "held_out_error_peak" not in ds.variables:
        return ""
    peak = np.asarray(ds["held_out_error_peak"].values, float)
    tau = np.asarray(ds["held_out_tau_peak"].values, float)
    floor = float(ds.attrs.get("merged_torque_floor", 0.0) or 0.0)
    region = _region(ds)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = peak / (np.asarray(ds["merged_scale"].values, float)[0] if region else
                      np.maximum(tau, floor))
    rel = np.where(torque_error_round_off(ds, peak, tau) | ~np.isfinite(rel), 0.0, rel)
    j = int(np.argmax(rel))
    k = int(ds.attrs.get("held_out_trajectories", 0))
    scale = (f"peak |{_TAU_I}| over them" if floor == 0 else
             f"max(peak |{_TAU_I}| over them, {_floor(ds)})")
    head = f"On {count(k)} held-out random trajector{'y' if k == 1 else 'ies'} (another seed, " \
        "not swept) the merged model's error is measured"
    if region:
        inside = int(ds.attrs.get("held_out_inside_region", 0))
        return (f"{head}: at most {_pct(rel[j])} of {_SI} (joint {j + 1}); {count(inside)} of "
                f"them lie{'s' if inside == 1 else ''} in the region, where its bound is "
                "proved. ")
    return (f"{head}, not guaranteed: at most "
            f"{_pct(rel[j])} of {scale} (joint {j + 1}). ")


def _cost_sentence(ds, table=False):
    """The merged model's operations per set point against the exact recursive model, the full
    explicit model and Newton-Euler, counted on the models (stored by
    :func:`gd_analyze.workflows.sweep_merged.with_model_cost`), with a word on why where it
    costs more than one of them; "" for a file without the counts."""
    if "evaluator" not in ds.dims:
        return ""
    names = _strings(ds["evaluator"].values)
    ops = dict(zip(names, (ds["multiplications"].values + ds["additions"].values).tolist()))
    mine = ops[names[0]]
    mul, add = int(ds["multiplications"].values[0]), int(ds["additions"].values[0])
    others = [(n, ops[n]) for n in names[1:]]
    text = (f"It costs {count(mine)} operations per set point ({count(mul)} multiplications, "
            f"{count(add)} additions); " + ", ".join(f"{n}: {count(o)}" for n, o in others)
            + (" (Table 5.2, counted, not timed)." if table else "."))
    recursive, full = ops.get("exact recursive model"), ops.get("full explicit model")
    if (recursive is not None and mine > recursive and names[0].endswith("(explicit form)")
            and str(ds.attrs.get("merged_rule", "chapter")) == "chapter"):
        text += (" It costs more than the exact recursive model: the chapter rule's merge "
                 "keeps parts of the explicit model's elements, so it is of the explicit form "
                 "only.")
    if full is not None and mine > full:
        text += (" It costs more than the full explicit model: where an element keeps one "
                 "part, its coefficients are that part's, not the sum of both, so the code "
                 "generator's factoring finds less to share"
                 + ("; the chapter rule has no fallback to the full model."
                    if str(ds.attrs.get("merged_rule", "chapter")) == "chapter" else "."))
    return text + " "


def _floor(ds):
    """The torque floor with the units of every joint type ("0 N m", or "0 N m (joints 1, 2),
    0 N (joint 3)" on a mixed arm)."""
    floor = f"{float(ds.attrs.get('merged_torque_floor', 0.0) or 0.0):g}"
    return joint_units_text([f"{floor} {u}" for u in torque_units(ds)])


def _own_rule(ds):
    """The rule of each trajectory's own simplified model, as the dataset records it."""
    return str(ds.attrs.get("own_model_rule", "chapter"))


def _models(ds):
    """What the own and the merged models are, and which carries a guarantee, in words
    generated from the dataset's rules: (own, merged)."""
    own_rule, rule = _own_rule(ds), str(ds.attrs.get("merged_rule", "chapter"))
    bound = {"chapter": "share-based classes of Sec. 3.4.1, no error bound",
             "budget": "guaranteed within \u03b5\u00b7" + _SI + f", {ROUND_OFF_CLAUSE}, on its "
                       "own trajectory"}
    own = f"each trajectory's own simplified model ({own_rule} rule: {bound[own_rule]})"
    if rule == "budget" and _region(ds):
        merged = (f"the merged model (budget rule, \u03b5 = "
                  f"{float(ds.attrs['merged_tolerance']):g}: "
                  f"{scope_markup(str(ds.attrs['merged_guarantee_statement']))})")
    elif rule == "budget":
        merged = (f"the merged model (budget rule, \u03b5 = "
                  f"{float(ds.attrs['merged_tolerance']):g}: guaranteed within "
                  f"\u03b5\u00b7{_SI}, {ROUND_OFF_CLAUSE}, on every swept trajectory)")
    else:
        merged = "the merged model (chapter rule: no error bound)"
    return own, merged


_MERGED_TEXT = ("Each trajectory has its own simplified model (keep the dominant part of each "
                "element, both if neither dominates, nothing if negligible). The merged model is "
                "one model for the whole sweep: a part of an element is dropped only where every "
                "trajectory's model drops it. The chapter rule drops parts of D and h only, "
                "never a term of gravity: \u03c4\u209b = D\u209b q\u0308 + h\u209b + c.")
_SI = "s" + _sub("i")
_TAU_I = "\u03c4" + _sub("i")

