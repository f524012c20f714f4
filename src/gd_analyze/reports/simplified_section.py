"""The report's "Simplified model" section, from the stored dataset only.

Kept self-contained (one context function, one figure function) so that it carries over to any
report engine: :func:`simplified_context` gives the tables and text, :func:`error_figure` the
per-joint plots of tau_s - tau with the guaranteed bound. Everything is read from the variables
and attributes that :func:`gd_analyze.workflows.simplify.simplified_dataset` stored at analysis
time; nothing is recomputed.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..core.selection.ranking import ROUND_OFF, ROUND_OFF_CLAUSE, arm_scales, is_round_off
from ..io.datasets import stored_guarantee, stored_region
from ..io.names import Attr, Var
from .common import (
    count,
    fmt,
    pct,
    pct_column,
    prismatic_joints,
    strings,
    table,
    torque_units,
    units_said_once,
)
from .markup import element as _el
from .markup import powers
from .markup import scope as scope_markup
from .markup import sub as _sub
from .plot_data import PlotData
from .ticks import MINUS, label_axes, set_ticks

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

__all__ = ["has_simplified", "simplified_context", "error_figure", "SIMPLIFIED_CAPTION", "ROUND_OFF",
           "simplified_caption", "region_pruning", "guarantee_kind", "BOUND_WHERE", "has_drives", "REGION_SCALE"]

#: Caption of the torque-error figure; ``{units}`` as :func:`simplified_caption` fills it.
SIMPLIFIED_CAPTION = ("Torque error of the simplified model, \u03c4\u209b \u2212 \u03c4 [{units}], "
                      "per joint against time, with the bound \u00b1 (dotted), {where}, "
                      + ROUND_OFF_CLAUSE + ". The joints whose model "
                      "drops nothing (bound 0) get no panel: the note below names them; their "
                      "difference is floating-point round-off.")

def simplified_caption(ds: xr.Dataset) -> str:
    """The caption of :func:`error_figure`, with the units of each joint's torque.

    Parameters
    ----------
    ds : xarray.Dataset

    Returns
    -------
    str
        :data:`SIMPLIFIED_CAPTION` in N m, or N m and N for an arm with a prismatic joint,
        saying where the bound holds from the stored guarantee's kind (:data:`BOUND_WHERE`).
    """
    where = BOUND_WHERE["region" if guarantee_kind(ds) == "region" else "trajectory"]
    return SIMPLIFIED_CAPTION.format(units=units_said_once(ds, "tau"), where=where)


#: Where the figure's bound holds, by the kind of the model's guarantee.
BOUND_WHERE = {"region": "proved at every state of the region (positions, velocities and "
                         "accelerations within the model's limits), so on this trajectory "
                         "wherever it lies in the region",
               "trajectory": "guaranteed on this trajectory only"}


def has_simplified(ds: xr.Dataset) -> bool:
    """Whether the dataset holds the simplified model's variables (error budget rule).

    Parameters
    ----------
    ds : xarray.Dataset

    Returns
    -------
    bool
    """
    return Var.SIMPLIFIED_BOUND in ds.variables


_S_I = "s" + _sub("i")
_EPS_S = "\u03b5\u00b7" + _S_I
_TAU_I, _TAU_J = "\u03c4" + _sub("i"), "\u03c4" + _sub("j")
_D_IJ = _el("D", "ij")
_QDD_I, _QDD_J = "q\u0308" + _sub("i"), "q\u0308" + _sub("j")


def _int(v):
    """A count as every table prints it (1,212), "\u2014" where it was not counted."""
    return count(v) if np.isfinite(float(v)) else "\u2014"


def _num(v, digits=4):
    v = float(v)
    return "\u2014" if not np.isfinite(v) else fmt(v, digits)


def inertia_check_text(attrs: dict[str, Any]) -> str:
    """The sentence on the proof that D_s is positive definite, from the stored figures.

    Parameters
    ----------
    attrs : dict
        A results dataset's attributes (``simplified_inertia_check_*``, written by
        :func:`gd_analyze.workflows.simplified_dataset.inertia_check_attrs`).

    Returns
    -------
    str
        " " and the sentences, or "" when no check is stored.

    Examples
    --------
    >>> inertia_check_text({})
    ''
    """
    key = "simplified_inertia_check_"
    if key + "proved" not in attrs:
        return ""
    d_s = "D" + _sub("s")
    where = ("over the joint-limit region" if str(attrs[key + "where"]) == "region" else
             "over the trajectory's bounding box of joint positions")
    restored = str(attrs.get(key + "restored", ""))
    if int(attrs[key + "proved"]):
        text = (f" The inertia matrix of the model, {d_s}, is proved positive definite {where} "
                f"(interval arithmetic rounded outward): its smallest eigenvalue is at least "
                f"{fmt(float(attrs[key + 'lower_bound']), 3)}, "
                f"{fmt(float(attrs[key + 'ratio']), 3)} of the least smallest eigenvalue of D "
                "over the same positions.")
        if restored:
            text += (f" To prove it, these base parameters were kept with all parts: "
                     f"{restored}.")
        return text
    sampled = float(attrs.get(key + "sampled_min_eigenvalue", float("nan")))
    return (f" The inertia matrix of the model, {d_s}, is not proved positive definite: "
            f"{attrs.get(key + 'statement', '')}. Its smallest eigenvalue at the "
            f"{count(int(attrs[key + 'samples']))} sampled positions is {fmt(sampled, 3)}"
            + (" (sampled, not proved between the samples)." if sampled > 0 else
               ": forward dynamics with it is not safe there."))


def simplified_context(ds: xr.Dataset) -> dict[str, Any]:
    """Tables and text of the "Simplified model" section.

    Parameters
    ----------
    ds : xarray.Dataset
        A results dataset with the ``simplified_*``, ``cost_*`` and ``ladder_*`` variables.

    Returns
    -------
    dict
        ``text`` (str), ``bound`` (table: per joint scale, bound, its split by D/h/c, measured
        error), ``costs`` (table), ``ladder`` (table), ``files`` (list of str), ``prefix``
        (the emitted C symbols' prefix, setting ``c_prefix``; "" if not stored), ``rule``,
        ``tolerance``.
    """
    a = ds.attrs
    n = ds.sizes["joint"]
    rule, eps = str(a.get(Attr.SIMPLIFIED_RULE, "")), float(a.get(Attr.SIMPLIFIED_TOLERANCE, np.nan))
    floor = float(a.get(Attr.SIMPLIFIED_TORQUE_FLOOR, 0.0))
    files = [f.strip() for f in str(a.get(Attr.SIMPLIFIED_FILES, "")).split(",") if f.strip()]
    choice = strings(ds[Var.CHOICE].values) if Var.CHOICE in ds.variables else []
    dropped = sum({"both": 0, "tran": 1, "rot": 1, "none": 2}.get(c, 0) for c in choice)
    form = str(a.get(Attr.SIMPLIFIED_FORM, "explicit"))
    if form == "recursive":
        text = _recursive_text(ds, eps, floor)
    elif rule == "budget":
        text = (f"Rule: error budget, \u03b5\u00a0=\u00a0{eps:g}"
                + (f", torque floor {floor:g} N m" if floor else "")
                + ". Every part of an element and every term of the explicit model contributes "
                f"to the joint torques ({_D_IJ} {_QDD_J} to {_TAU_I} and {_D_IJ} "
                f"{_QDD_I} to {_TAU_J}, {_el('h', 'i')} to {_TAU_I}, {_el('c', 'i')} to "
                f"{_TAU_I}); terms are dropped in order of increasing peak contribution while, "
                f"for every joint, the dropped peaks sum to at most {_EPS_S} ({_S_I} = peak "
                f"|{_TAU_I}|, raised to the floor). By the triangle "
                "inequality the error on this trajectory is within that sum: "
                + _scope(ds))
    else:
        text = ("Rule: the chapter's share-based classes (Sec. 3.4.1): each element keeps its "
                "dominant part, no term is pruned; there is no error bound.")
    if form != "recursive":
        text += (f" Kept: {count(a.get('simplified_terms_kept', 0))} terms of the explicit "
                 f"model; {dropped} of {2 * len(choice)} element parts dropped as whole parts.")
    text += (f" The emitted code costs {count(a.get('simplified_multiplications'))} "
             f"multiplications and {count(a.get('simplified_additions'))} additions per set "
             f"point ({count(a.get('simplified_sin'))} sin, {count(a.get('simplified_cos'))} "
             "cos).")
    text += inertia_check_text(a)
    other = str(a.get(Attr.OTHER_RULE, ""))
    if other and Var.OTHER_RULE_ERROR_RELATIVE_PEAK in ds.variables:
        rel = np.asarray(ds[Var.OTHER_RULE_ERROR_RELATIVE_PEAK].values, float)
        rel = rel[np.isfinite(rel)]     # a joint without torque has no relative error
        worst = (f"worst error {pct(rel.max())} of peak |\u03c4|" if rel.size else
                 "no relative error (no joint has torque on this trajectory)")
        text += (f" Side by side, the {other} rule's model costs "
                 f"{count(a.get('other_rule_multiplications'))} multiplications and "
                 f"{count(a.get('other_rule_additions'))} additions, {worst}."
                 + _dearer_than_full(ds, other))
    measured = ds[Var.TAU_ERROR_PEAK].values
    parts = ("from D", "from h", "from c") if form != "recursive" else (
        "inertial (D)", "velocity (h)", "gravity (c)", "whole parameters")
    whole = ds[Var.SIMPLIFIED_BOUND_WHOLE].values if Var.SIMPLIFIED_BOUND_WHOLE in ds else None
    units = torque_units(ds)
    scale = ds[Var.SIMPLIFIED_SCALE].values

    arm = arm_scales(scale, units)

    def off(v, i):                   # round-off of joint i's or the arm's scale
        return bool(is_round_off(v, scale[i], arm_scale=arm[i]))

    def num(v, i):                   # a bound that is round-off bounds nothing: 0, as an
        return "0" if off(v, i) else _num(v)      # exact 0 (one mark per column)

    measured_off = np.array([off(measured[i], i) for i in range(n)], bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = pct_column(np.where(scale > 0, measured / scale, np.nan), measured_off)
    bound = table(
        ["joint", "units", f"scale {_S_I}", "bound", *parts,
         "measured peak |\u03c4\u209b\u00a0\u2212\u00a0\u03c4|", f"measured / {_S_I}"],
        [[str(i + 1), units[i], _num(scale[i]),
          num(ds[Var.SIMPLIFIED_BOUND].values[i], i),
          num(ds[Var.SIMPLIFIED_BOUND_INERTIA].values[i], i),
          num(ds[Var.SIMPLIFIED_BOUND_CORIOLIS].values[i], i),
          num(ds[Var.SIMPLIFIED_BOUND_GRAVITY].values[i], i),
          *([] if whole is None else [num(whole[i], i)]),
          "\u2261 0" if measured_off[i] or measured[i] == 0 else _num(measured[i]),
          ratio[i] if scale[i] > 0 else "\u2014"] for i in range(n)],
        align=["left", "left"] + ["right"] * (7 + (whole is not None)))
    costs = ladder = None
    if Var.COST_TOTAL in ds.variables:
        costs = table(["model", "multiplications", "additions", "total"],
                      [[str(lab).replace("EPS=", "\u03b5 = "), _int(m), _int(ad),
                        _int(tot)] for lab, m, ad, tot in
                       zip(strings(ds[Var.COST_MODEL].values), ds[Var.COST_MULTIPLICATIONS].values,
                           ds[Var.COST_ADDITIONS].values, ds[Var.COST_TOTAL].values)],
                      align=["left", "right", "right", "right"], widths=[3, 1, 1, 1])
    if Var.LADDER_OPERATIONS in ds.variables:
        region = str(a.get(Attr.SIMPLIFIED_GUARANTEE_KIND, "")) == "region"
        has_bound = Var.LADDER_WORST_BOUND in ds.variables
        ladder = table(["\u03b5", "operations", "sin + cos",
                        f"worst measured peak |\u03c4\u209b\u00a0\u2212\u00a0\u03c4| / {_S_I} on "
                        "this trajectory" + ("" if has_bound else " (guaranteed \u2264 \u03b5)")]
                       + ([f"largest bound / {_S_I}, "
                           + ("proved over the joint-limit region" if region else
                              "on this trajectory") + " (\u2264 \u03b5)"] if has_bound else []),
                       [[f"{e:g}", _int(o), _int(tr), w, *b] for e, o, tr, w, *b in
                        zip(ds[Var.LADDER_TOLERANCE].values, ds[Var.LADDER_OPERATIONS].values,
                            ds[Var.LADDER_TRIG].values, pct_column(   # relative: own scale 1
                                ds[Var.LADDER_WORST_ERROR].values,
                                is_round_off(ds[Var.LADDER_WORST_ERROR].values, 1.0)),
                            *([pct_column(ds[Var.LADDER_WORST_BOUND].values,
                                          is_round_off(ds[Var.LADDER_WORST_BOUND].values, 1.0))]
                              if has_bound else []))],
                       align=["right"] * (4 + has_bound))
    skipped = str(ds.attrs.get(Attr.SIMPLIFIED_LADDER_SKIPPED, "")) if ladder is None else ""
    region_rows, region_text = region_table(ds)
    ladder_form = str(a.get(Attr.SIMPLIFIED_LADDER_FORM, "explicit"))
    return {"text": text, "bound": bound, "costs": costs, "ladder": ladder, "files": files,
            "prefix": str(a.get(Attr.C_PREFIX, "")),
            "region": region_rows, "region_text": region_text,
            "rule": rule, "tolerance": eps,
            "form_note": str(a.get(Attr.SIMPLIFIED_FORM_NOTE, "")),
            "screen_note": _screen_note(a),
            "ladder_heading": "5.5 Tolerance ladder" + (
                f" of the {ladder_form} form" if ladder is not None else ""),
            "ladder_note": f"Tolerance ladder {skipped}." if skipped else ""}


def _screen_note(attrs):
    """The sampled pre-screen that skipped the region's certification, as a sentence, or ""."""
    said = str(attrs.get(Attr.SIMPLIFIED_REGION_SCREEN, ""))
    return f"Region certification skipped: {said}." if said else ""


def region_table(ds: xr.Dataset) -> tuple[dict[str, Any] | None, str]:
    """The region of the model's guarantee as a table, and whether it covers this trajectory.

    Parameters
    ----------
    ds : xarray.Dataset
        A results dataset with the ``region_*`` variables
        (:func:`gd_analyze.io.datasets.region_fields`).

    Returns
    -------
    table : dict or None
        Per joint the position range (degrees for a revolute joint, metres for a prismatic
        one; "any angle (full turn)"), qd max, qdd max and whether qdd max is assumed; None
        without a region.
    text : str
        Where the limits come from, which acceleration limits are assumed, and whether this
        trajectory lies in the region (where not: the joint, the quantity and the amount, and
        that the guarantee does not cover it); "" without a region.
    """
    import math

    r = stored_region(ds)
    if r is None:
        return None, ""
    pris = [bool(p) for p in prismatic_joints(ds)]
    rows = []
    for j in range(len(r["qd_max"])):
        conv = (lambda v: v) if pris[j] else math.degrees
        unit = "m" if pris[j] else "deg"
        q = ("any angle (full turn)" if r["q_full_turn"][j] else
             f"[{_num(conv(r['q_min'][j]))}, {_num(conv(r['q_max'][j]))}]")
        rows.append([str(j + 1), unit, q, _num(conv(r["qd_max"][j])),
                     _num(conv(r["qdd_max"][j])),
                     "assumed" if r["qdd_max_assumed"][j] else "given"])
    tab = table(["joint", "units of q", "q range", "qd max [/s]", "qdd max [/s²]",
                 "qdd max"], rows, align=["left", "left", "left", "right", "right", "left"])
    lines = r["lines"]
    note = lines[-1].partition(" (")[2].partition(")")[0] if "(assumed" in lines[-1] else ""
    text = (f"The region: {ds.attrs.get('region_source', 'the robot limits')}"
            + (f"; acceleration limits {note}, not given by the robot" if note else "")
            + (f"; clipped to the robot's limits: {ds.attrs['region_notes']}"
               if ds.attrs.get(Attr.REGION_NOTES) else "") + ".")
    if r["covered"] is True:
        text += " Every set point of this trajectory lies in the region."
    elif r["covered"] is False:
        text += (f" This trajectory leaves the region: {r['coverage']}. "
                 + ("The region's guarantee holds in the region, not on this trajectory: "
                    "it does not cover it." if guarantee_kind(ds) == "region" else ""))
    return tab, powers(text)               # s^-1, deg/s^2 as superscripts


def _recursive_text(ds, eps, floor):
    """The rule of a model of the recursive form, what it keeps and its guarantee."""
    a = ds.attrs
    b = ds.sizes.get("base_parameter", 0)
    dropped = int(a.get(Attr.SIMPLIFIED_PAIRS_DROPPED, 0))
    pairs = int(a.get(Attr.SIMPLIFIED_PAIRS, 3 * b))
    text = (f"Form: the customized recursive Newton-Euler model (Algorithm 3.1) on the arm's "
            f"{b} base inertial parameters (Khalil & Kleinfinger 1987; Gautier 1990), with the "
            "numeric parameters as constants, 0 and \u00b11 folded and common subexpressions "
            "shared. The torque is linear in the base parameters, \u03c4 = Y" + _sub("b")
            + " \u03b2; each parameter's contribution splits into an inertial part (in "
            "D q\u0308), a velocity part (in h) and a gravity part (in c). ")
    if dropped == 0:
        return text + (f"Rule: error budget, \u03b5\u00a0=\u00a0{eps:g}: no part is dropped, "
                       "the model is exact (its difference from the full torque is round-off)."
                       + _scope(ds, exact=True))
    rule = (f"Rule: error budget, \u03b5\u00a0=\u00a0{eps:g}"
            + (f", torque floor {floor:g} N m" if floor else ""))
    if guarantee_kind(ds) == "region":
        return text + rule + ". " + region_pruning(pairs, dropped, drives=has_drives(ds)) \
            + _scope(ds, exact=True)
    return text + (rule + f". Of the {pairs} (parameter, part) pairs that contribute on this "
                   f"trajectory, {dropped} are dropped (alone or with their whole parameter), "
                   "in order of "
                   "increasing peak contribution, while for every joint the dropped peaks sum "
                   f"to at most {_EPS_S} ({_S_I} = peak |{_TAU_I}|, raised to the "
                   "floor); by the triangle inequality the error on this trajectory is within "
                   "that sum: " + _scope(ds))


def has_drives(ds: xr.Dataset) -> bool:
    """Whether the dataset's robot has drives (armature or friction), which the region's
    scale s_i leaves out.

    Parameters
    ----------
    ds : xarray.Dataset
        A results dataset; its drives are the variables ``D_arm``, ``viscous``, ``coulomb``
        and ``torque_offset``.

    Returns
    -------
    bool
        True where any of them is nonzero.
    """
    return any(k in ds.variables and np.any(np.asarray(ds[k].values, float) != 0)
               for k in ("D_arm", "viscous", "coulomb", "torque_offset"))


#: What s_i is over the region, by whether the robot has drives: the region's scale is the
#: rigid links' torque (the base regressor's; armature and friction are not in it).
REGION_SCALE = {False: f"{_S_I} = the largest |{_TAU_I}| found over the region",
                True: f"{_S_I} = the largest |{_TAU_I}| of the rigid links alone found over "
                      "the region, the drives' armature and friction left out (the model keeps "
                      f"them whole; {_TAU_I} in the tables and figures includes them)"}


def region_pruning(pairs: int, dropped: int, bound: str = "the bound below", drives: bool = False) -> str:
    """How a recursive model was pruned over the joint-limit region, in the words of every
    report (the main report's Sec. 5.3, the sweep report's Sec. 5).

    Parameters
    ----------
    pairs, dropped : int
        The (parameter, part) pairs that contribute over the region, and those dropped.
    bound : str, optional
        The bound, named where the sentence ends.
    drives : bool, optional
        The robot has drives (:func:`has_drives`): s_i is said to leave them out.

    Returns
    -------
    str
        One sentence.
    """
    return (f"Of the {pairs} (parameter, part) pairs that contribute over the joint-limit "
            f"region, {dropped} are dropped (alone or with their whole parameter), in order of "
            "increasing proved bound, while for every joint a bound of the change they make "
            f"together, proved over the region, stays within {_EPS_S} ({REGION_SCALE[drives]}, "
            "raised to the floor): the sum of their own bounds (triangle inequality) or, where "
            "lower, that of their sum at the same state (enclosures added on boxes, branch and "
            f"bound). The error at every state of the region is within that bound, {bound}.")


def guarantee_kind(ds: xr.Dataset) -> str:
    """The stored guarantee's kind.

    Parameters
    ----------
    ds : xarray.Dataset

    Returns
    -------
    str
        ``"region"``, ``"trajectory"``, or ``"none"`` where the dataset stores none.
    """
    g = stored_guarantee(ds)
    return "none" if g is None else g["kind"]


def _scope(ds, exact=False):
    """Where the bound holds: on this trajectory (the table's bound), and the model's
    guarantee as stored from the model built (:func:`gd_analyze.io.datasets.stored_guarantee`);
    an older dataset's sentence where none is stored."""
    g = stored_guarantee(ds)
    if g is None:
        return "" if exact else (f"the bound below is guaranteed {ROUND_OFF_CLAUSE}, on this "
                                 "trajectory only.")
    said = f"The model's guarantee: {scope_markup(g['statement'])}."
    return " " + said if exact else (f"the bound below is guaranteed on this trajectory, "
                                     f"{ROUND_OFF_CLAUSE}. {said}")


def _dearer_than_full(ds, other):
    """Why the other rule's explicit model costs more than the full one, from the stored
    counts (:func:`gd_analyze.workflows.simplified_dataset.coefficient_structure`), or ""."""
    a = ds.attrs
    keys = ("full_harmonics", "full_coefficients", "other_rule_harmonics",
            "other_rule_coefficients")
    if Var.COST_TOTAL not in ds.variables or not all(k in a for k in keys):
        return ""
    costs = dict(zip(strings(ds[Var.COST_MODEL].values), ds[Var.COST_TOTAL].values))
    full = costs.get("explicit, full")
    mine = int(a.get(Attr.OTHER_RULE_MULTIPLICATIONS, -1)) + int(a.get(Attr.OTHER_RULE_ADDITIONS, -1))
    if full is None or mine <= full:
        return ""
    fh, fc, oh, oc = (int(a[k]) for k in keys)
    return (f" It costs more than the full explicit model ({mine:,} against {int(full):,} "
            f"operations) although it keeps {oh:,} of the full model's {fh:,} harmonic terms: "
            "where an element keeps one part, its coefficients are that part's, not the sum "
            f"of both; the full model's {fc:,} distinct coefficient magnitudes become {oc:,}, so "
            "the code generator's factoring (a x + a y = a (x + y), and a cos(A + B) + b "
            "cos(A \u2212 B) in one product where a = \u00b1b) finds less to share."
            + (" The budget rule falls back to the full model in that case; the chapter rule "
               "has no such fallback." if other == "chapter" else ""))


def _round_off(diff, bound, scale, arm_scale=None):
    """Whether a joint's tau_s - tau is floating-point round-off only: its bound (what was
    dropped for the joint) and its peak both by the one rule
    (:func:`gd_analyze.core.selection.ranking.is_round_off`), with ``arm_scale`` the largest
    scale among the joints of the same units
    (:func:`gd_analyze.core.selection.ranking.arm_scales`)."""
    if diff.size == 0 or not np.isfinite(diff).all() or not np.isfinite(bound):
        return False
    return bool(is_round_off(bound, scale, arm_scale=arm_scale)
                and is_round_off(float(np.max(np.abs(diff))), scale, arm_scale=arm_scale))


def error_figure(ds: xr.Dataset, width: float = 7.2, data: PlotData | None = None) -> Figure:
    """Per-joint plots of tau_s - tau against time, with the guaranteed band +- bound.

    Parameters
    ----------
    ds : xarray.Dataset
        With ``t``, ``tau``, ``tau_simplified`` (N, n) [N m] and ``simplified_bound`` (n,).
    width : float, optional
        Figure width [in]; narrower than 5 in (a 3.5-in column) gives one panel a row, else
        two.
    data : gd_analyze.reports.main_figures.PlotData, optional
        The series as the report reads them, with ``tau_error`` (tau_s - tau per set point,
        or its min/max envelope for a long trajectory: the stored series are then never read
        whole); without it, the whole series are read from ``ds``.

    Returns
    -------
    matplotlib.figure.Figure
        One panel per joint whose difference is not round-off, on a fixed grid (no layout
        engine: the margins are set for the 7-pt tick labels, the 8-pt axis labels and the
        panel titles; no figure title, which the numbered caption gives); ticks placed once,
        in one notation for the figure (:func:`gd_analyze.reports.ticks.label_axes`), every y
        range padded so that neither the error nor the bound touches the frame; the legend
        above the panels, clear of every curve. The joints whose difference and bound are
        round-off (:func:`_round_off`, :data:`gd_analyze.core.selection.ranking.ROUND_OFF`)
        get no panel: a note below names them ("nothing dropped: τₛ = τ up to round-off")
        with their peak difference.
    """
    from matplotlib.figure import Figure


    n = ds.sizes["joint"]
    units = torque_units(ds)
    if data is not None and "tau_error" in data.series:
        t, diff = data.x, data.series["tau_error"]
    else:
        t = ds[Var.T].values
        diff = ds[Var.TAU_SIMPLIFIED].values - ds[Var.TAU].values
    bound = ds[Var.SIMPLIFIED_BOUND].values
    scale = ds[Var.SIMPLIFIED_SCALE].values if Var.SIMPLIFIED_SCALE in ds else ds[Var.TAU_PEAK].values
    arm = arm_scales(scale, units)
    quiet = [i for i in range(n) if _round_off(diff[:, i], bound[i], scale[i], arm[i])]
    shown = [i for i in range(n) if i not in quiet]
    W = width
    column = W < 5.0
    cols = 2 if len(shown) > 1 and not column else 1
    rows = -(-len(shown) // cols)
    left, right, gap, top, bottom, hgap = 0.62, 0.1, 0.75, 0.5, 0.42, 0.62
    if column:
        top, hgap = 0.45, 0.5
    h = 1.0 if column else 1.6
    note = ""
    if quiet:                       # wrapped for 8.5 pt (the least printed size's text)
        import textwrap

        peaks = "; ".join(
            f"{i + 1}: "
            + f"{float(np.max(np.abs(diff[:, i]))):.1e}".replace("-", MINUS) + f" {units[i]}"
            for i in quiet)
        what = ("joint " if len(quiet) == 1 else "joints ") + ", ".join(
            str(i + 1) for i in quiet)
        note = textwrap.fill(
            f"Nothing dropped for {what} (bound 0): \u03c4\u209b = \u03c4 up to round-off, "
            f"not drawn (peak |\u03c4\u209b \u2212 \u03c4|, joint {peaks}).",
            int((W - 0.3) / 0.075))
    note_h = 0.12 + 0.16 * (note.count("\n") + 1) if quiet else 0.0
    H = (top + rows * h + (rows - 1) * hgap + bottom if shown else 0.1) + note_h
    w = (W - left - right - (cols - 1) * gap) / cols
    fig = Figure(figsize=(W, H))
    if data is not None and data.enveloped:     # the set points' range, not the columns'
        t = np.asarray(t, float)
        t0, t1 = float(ds[Var.T][0]), float(ds[Var.T][-1])
    else:
        t0, t1 = (float(t[0]), float(t[-1])) if t.size else (0.0, 1.0)
    handles = None
    ys = []
    for k, i in enumerate(shown):
        r, c = divmod(k, cols)
        x0, y0 = left + c * (w + gap), top + r * (h + hgap)
        ax = fig.add_axes((x0 / W, 1 - (y0 + h) / H, w / W, h / H))
        ax.set_xlim(t0, t1 if t1 > t0 else t0 + 1.0)
        set_ticks(ax.xaxis, t0, t1 if t1 > t0 else t0 + 1.0, 4)
        ax.set_title(f"joint {i + 1}", fontsize=8)
        ax.set_xlabel("t [s]", fontsize=8, labelpad=1.0)
        ax.tick_params(labelsize=7)
        which = "" if column else f" (joint {i + 1})"   # a column's panels are short
        ax.set_ylabel(f"\u03c4\u209b \u2212 \u03c4{which} [{units[i]}]", fontsize=8,
                      labelpad=1.0)
        line, = ax.plot(t, diff[:, i], color="#D55E00", linewidth=1.1,
                        label="\u03c4\u209b \u2212 \u03c4")
        span = [0.0]
        if diff.size and np.isfinite(diff[:, i]).any():
            span += [float(np.nanmin(diff[:, i])), float(np.nanmax(diff[:, i]))]
        if np.isfinite(bound[i]):
            b, = ax.plot([t0, t1], [bound[i]] * 2, color="0.4", linestyle=":", linewidth=1,
                         label="guaranteed bound \u00b1")
            ax.axhline(-bound[i], color="0.4", linestyle=":", linewidth=1)
            span += [float(bound[i]), -float(bound[i])]
            handles = handles or [line, b]
        ax.axhline(0.0, color="0.8", linewidth=0.6)
        lo, hi = min(span), max(span)
        if hi - lo <= 1e-300:
            lo, hi = -1.0, 1.0
        pad = 0.08 * (hi - lo)
        ax.set_ylim(lo - pad, hi + pad)
        set_ticks(ax.yaxis, lo, hi, 4 if h > 1.2 else 3, labels=False)
        ys.append(ax.yaxis)
    label_axes(ys)
    if handles:                     # above the panels: no curve or bound runs through it
        fig.legend(handles, [str(hd.get_label()) for hd in handles], loc="upper center",
                   ncol=2, frameon=False, fontsize=7, handlelength=2.6,
                   bbox_to_anchor=(0.5, 1 - 0.08 / H))
    if quiet:
        fig.text(0.1 / W, (note_h - 0.06) / H, note, fontsize=7, va="top", ha="left",
                 color="0.25")
    return fig                      # no title inside: the numbered caption says it
