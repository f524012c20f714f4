"""The report's "Simplified model" section, from the stored dataset only.

Kept self-contained (one context function, one figure function) so that it carries over to any
report engine: :func:`simplified_context` gives the tables and text, :func:`error_figure` the
per-joint plots of tau_s - tau with the guaranteed bound. Everything is read from the variables
and attributes that :func:`gd_analyze.jobs.simplified_dataset.simplified_dataset` stored at analysis
time; nothing is recomputed.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..ranking.ranking import (
    ROUND_OFF,
    ROUND_OFF_CLAUSE,
    arm_scales,
    is_round_off,
    joint_units_text,
)
from ..store.stored_simplified import InertiaCheck, StoredSimplified
from .common import count, fmt, pct, pct_column, table
from .markup import element as _el
from .markup import powers
from .markup import scope as scope_markup
from .markup import sub as _sub
from .plot_data import PlotData
from .ticks import label_axes, set_ticks

if TYPE_CHECKING:
    from collections.abc import Mapping

    import xarray as xr
    from matplotlib.figure import Figure

__all__ = ["simplified_context", "error_figure", "SIMPLIFIED_CAPTION", "ROUND_OFF",
           "simplified_caption", "region_pruning", "guarantee_kind", "BOUND_WHERE", "has_drives", "REGION_SCALE"]

#: Caption of the torque-error figure; ``{units}`` as :func:`simplified_caption` fills it.
SIMPLIFIED_CAPTION = ("Torque error of the simplified model, \u0394\u03c4 = \u03c4" + _sub("s")
                      + " \u2212 \u03c4 [{units}], "
                      "per joint against time, with the bound \u00b1 (dotted), {where}, "
                      + ROUND_OFF_CLAUSE + ". The joints whose model "
                      "drops nothing (bound 0) get no panel: the note below names them; their "
                      "difference is floating-point round-off.")

def simplified_caption(ds: StoredSimplified | xr.Dataset) -> str:
    """The caption of :func:`error_figure`, with the units of each joint's torque.

    Parameters
    ----------
    ds : StoredSimplified or xarray.Dataset
        The simplified model's record (:class:`gd_analyze.store.stored_simplified.StoredSimplified`),
        or a results dataset holding it.

    Returns
    -------
    str
        :data:`SIMPLIFIED_CAPTION` in N m, or N m and N for an arm with a prismatic joint,
        saying where the bound holds from the stored guarantee's kind (:data:`BOUND_WHERE`).
    """
    s = StoredSimplified.of(ds)
    where = BOUND_WHERE["region" if s.guarantee_kind == "region" else "trajectory"]
    return SIMPLIFIED_CAPTION.format(units=joint_units_text(s.tau_units), where=where)


#: Where the figure's bound holds, by the kind of the model's guarantee.
BOUND_WHERE = {"region": "proved at every state of the region (positions, velocities and "
                         "accelerations within the model's limits), so on this trajectory "
                         "wherever it lies in the region",
               "trajectory": "guaranteed on this trajectory only"}


_S_I = "s" + _sub("i")
#: The simplified model's torque, its subscript set as such (8 pt at least in the PDF).
_TAU_S = "\u03c4" + _sub("s")
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


def inertia_check_text(check: InertiaCheck | Mapping[str, Any] | None) -> str:
    """The sentence on the proof that D_s is positive definite, from the stored figures.

    Parameters
    ----------
    check : InertiaCheck, Mapping or None
        The stored check (:class:`gd_analyze.store.stored_simplified.InertiaCheck`), or a results
        dataset's attributes holding it (``simplified_inertia_check_*``, written by
        :func:`gd_analyze.jobs.simplified_dataset.inertia_check_attrs`).

    Returns
    -------
    str
        " " and the sentences, or "" when no check is stored.

    Examples
    --------
    >>> inertia_check_text({})
    ''
    """
    if check is not None and not isinstance(check, InertiaCheck):
        check = InertiaCheck.from_attrs(check)
    if check is None:
        return ""
    d_s = "D" + _sub("s")
    where = ("over the joint-limit region" if check.where == "region" else
             "over the trajectory's bounding box of joint positions")
    if check.proved:
        text = (f" The inertia matrix of the model, {d_s}, is proved positive definite {where} "
                f"(interval arithmetic rounded outward): its smallest eigenvalue is at least "
                f"{fmt(check.lower_bound, 3)}, "
                f"{fmt(check.ratio, 3)} of the least smallest eigenvalue of D "
                "over the same positions.")
        if check.restored:
            text += (f" To prove it, these base parameters were kept with all parts: "
                     f"{check.restored}.")
        return text
    sampled = check.sampled_min_eigenvalue
    return (f" The inertia matrix of the model, {d_s}, is not proved positive definite: "
            f"{check.statement}. Its smallest eigenvalue at the "
            f"{count(check.samples)} sampled positions is {fmt(sampled, 3)}"
            + (" (sampled, not proved between the samples)." if sampled > 0 else
               ": forward dynamics with it is not safe there."))


def simplified_context(ds: StoredSimplified | xr.Dataset) -> dict[str, Any]:
    """Tables and text of the "Simplified model" section.

    Parameters
    ----------
    ds : StoredSimplified or xarray.Dataset
        The simplified model's record (:class:`gd_analyze.store.stored_simplified.StoredSimplified`),
        or a results dataset with the ``simplified_*``, ``cost_*`` and ``ladder_*`` variables.

    Returns
    -------
    dict
        ``text`` (str), ``bound`` (table: per joint scale, bound, its split by D/h/c, measured
        error), ``costs`` (table), ``ladder`` (table), ``files`` (list of str), ``prefix``
        (the emitted C symbols' prefix, setting ``c_prefix``; "" if not stored), ``rule``,
        ``tolerance``.
    """
    s = StoredSimplified.of(ds)
    n = s.n
    rule, eps = s.rule, s.tolerance
    floor = s.torque_floor
    files = list(s.files)
    choice = s.choice
    dropped = sum({"both": 0, "tran": 1, "rot": 1, "none": 2}.get(c, 0) for c in choice)
    form = s.form
    if form == "recursive":
        text = _recursive_text(s, eps, floor)
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
                + _scope(s))
    else:
        text = ("Rule: the chapter's share-based classes (Sec. 3.4.1): each element keeps its "
                "dominant part, no term is pruned; there is no error bound.")
    if form != "recursive":
        text += (f" Kept: {count(s.terms_kept)} terms of the explicit "
                 f"model; {dropped} of {2 * len(choice)} element parts dropped as whole parts.")
    text += (f" The emitted code costs {count(s.multiplications)} "
             f"multiplications and {count(s.additions)} additions per set "
             f"point ({count(s.sin)} sin, {count(s.cos)} "
             "cos).")
    text += inertia_check_text(s.inertia_check)
    other = s.other_rule
    if other and s.other_rule_error_relative_peak is not None:
        rel = np.asarray(s.other_rule_error_relative_peak, float)
        rel = rel[np.isfinite(rel)]     # a joint without torque has no relative error
        worst = (f"worst error {pct(rel.max())} of peak |\u03c4|" if rel.size else
                 "no relative error (no joint has torque on this trajectory)")
        text += (f" Side by side, the {other} rule's model costs "
                 f"{count(s.other_rule_multiplications)} multiplications and "
                 f"{count(s.other_rule_additions)} additions, {worst}."
                 + _dearer_than_full(s, other))
    measured = np.asarray(s.tau_error_peak, float)
    parts = ("from D", "from h", "from c") if form != "recursive" else (
        "inertial (D)", "velocity (h)", "gravity (c)", "whole parameters")
    whole = s.bound_whole
    units = s.tau_units
    scale = np.asarray(s.scale, float)

    arm = arm_scales(scale, units)

    def off(v, i):                   # round-off of joint i's or the arm's scale
        return bool(is_round_off(v, scale[i], arm_scale=arm[i]))

    def num(v, i):                   # a bound that is round-off bounds nothing: 0, as an
        return "0" if off(v, i) else _num(v)      # exact 0 (one mark per column)

    measured_off = np.array([off(measured[i], i) for i in range(n)], bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = pct_column(np.where(scale > 0, measured / scale, np.nan), measured_off)
    parts_bound = [np.asarray(v, float) for v in (s.bound_inertia, s.bound_coriolis,
                                                  s.bound_gravity)]
    bound = table(
        ["joint", "units", f"scale {_S_I}", "bound", *parts,
         f"measured peak |{_TAU_S}\u00a0\u2212\u00a0\u03c4|", f"measured / {_S_I}"],
        [[str(i + 1), units[i], _num(scale[i]),
          num(s.bound[i], i), *(num(part[i], i) for part in parts_bound),
          *([] if whole is None else [num(whole[i], i)]),
          "\u2261 0" if measured_off[i] or measured[i] == 0 else _num(measured[i]),
          ratio[i] if scale[i] > 0 else "\u2014"] for i in range(n)],
        align=["left", "left"] + ["right"] * (7 + (whole is not None)))
    costs = ladder = None
    if s.costs is not None:
        c = s.costs
        costs = table(["model", "multiplications", "additions", "total"],
                      [[str(lab).replace("EPS=", "\u03b5 = "), _int(m), _int(ad),
                        _int(tot)] for lab, m, ad, tot in
                       zip(c.models, c.multiplications, c.additions, c.total)],
                      align=["left", "right", "right", "right"], widths=[3, 1, 1, 1])
    lad = s.ladder
    if lad is not None:
        region = s.guarantee_kind == "region"
        has_bound = lad.worst_bound is not None
        ladder = table(["\u03b5", "operations", "sin + cos",
                        f"worst measured peak |{_TAU_S}\u00a0\u2212\u00a0\u03c4| / {_S_I} on "
                        "this trajectory" + ("" if has_bound else " (guaranteed \u2264 \u03b5)")]
                       + ([f"largest bound / {_S_I}, "
                           + ("proved over the joint-limit region" if region else
                              "on this trajectory") + " (\u2264 \u03b5)"] if has_bound else []),
                       [[f"{e:g}", _int(o), _int(tr), w, *b] for e, o, tr, w, *b in
                        zip(lad.tolerance, lad.operations, lad.trig,
                            pct_column(lad.worst_error,   # relative: own scale 1
                                       is_round_off(lad.worst_error, 1.0)),
                            *([pct_column(lad.worst_bound, is_round_off(lad.worst_bound, 1.0))]
                              if lad.worst_bound is not None else []))],
                       align=["right"] * (4 + has_bound))
    skipped = s.ladder_skipped if ladder is None else ""
    region_rows, region_text = region_table(s)
    ladder_form = s.ladder_form
    return {"text": text, "bound": bound, "costs": costs, "ladder": ladder, "files": files,
            "prefix": s.c_prefix,
            "region": region_rows, "region_text": region_text,
            "rule": rule, "tolerance": eps,
            "form_note": s.form_note,
            "screen_note": _screen_note(s.region_screen),
            "ladder_heading": "5.5 Tolerance ladder" + (
                f" of the {ladder_form} form" if ladder is not None else ""),
            "ladder_note": f"Tolerance ladder {skipped}." if skipped else ""}


def _screen_note(said):
    """The sampled pre-screen that skipped the region's certification, as a sentence, or ""."""
    return f"Region certification skipped: {said}." if said else ""


def region_table(ds: StoredSimplified | xr.Dataset) -> tuple[dict[str, Any] | None, str]:
    """The region of the model's guarantee as a table, and whether it covers this trajectory.

    Parameters
    ----------
    ds : StoredSimplified or xarray.Dataset
        The simplified model's record, or a results dataset with it and the ``region_*``
        variables (:func:`gd_analyze.store.datasets.region_fields`).

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

    s = StoredSimplified.of(ds)
    r = s.region
    if r is None:
        return None, ""
    pris = list(s.prismatic)
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
    text = (f"The region: {s.region_source}"
            + (f"; acceleration limits {note}, not given by the robot" if note else "")
            + (f"; clipped to the robot's limits: {s.region_notes}"
               if s.region_notes else "") + ".")
    if r["covered"] is True:
        text += " Every set point of this trajectory lies in the region."
    elif r["covered"] is False:
        text += (f" This trajectory leaves the region: {r['coverage']}. "
                 + ("The region's guarantee holds in the region, not on this trajectory: "
                    "it does not cover it." if s.guarantee_kind == "region" else ""))
    return tab, powers(text)               # s^-1, deg/s^2 as superscripts


def _recursive_text(s, eps, floor):
    """The rule of a model of the recursive form, what it keeps and its guarantee."""
    b = s.base_parameters
    dropped = s.pairs_dropped
    pairs = s.pairs
    text = (f"Form: the customized recursive Newton-Euler model (Algorithm 3.1) on the arm's "
            f"{b} base inertial parameters (Khalil & Kleinfinger 1987; Gautier 1990), with the "
            "numeric parameters as constants, 0 and \u00b11 folded and common subexpressions "
            "shared. The torque is linear in the base parameters, \u03c4 = Y" + _sub("b")
            + " \u03b2; each parameter's contribution splits into an inertial part (in "
            "D q\u0308), a velocity part (in h) and a gravity part (in c). ")
    if dropped == 0:
        return text + (f"Rule: error budget, \u03b5\u00a0=\u00a0{eps:g}: no part is dropped, "
                       "the model is exact (its difference from the full torque is round-off)."
                       + _scope(s, exact=True))
    rule = (f"Rule: error budget, \u03b5\u00a0=\u00a0{eps:g}"
            + (f", torque floor {floor:g} N m" if floor else ""))
    if s.guarantee_kind == "region":
        return text + rule + ". " + region_pruning(pairs, dropped, drives=s.has_drives) \
            + _scope(s, exact=True)
    return text + (rule + f". Of the {pairs} (parameter, part) pairs that contribute on this "
                   f"trajectory, {dropped} are dropped (alone or with their whole parameter), "
                   "in order of "
                   "increasing peak contribution, while for every joint the dropped peaks sum "
                   f"to at most {_EPS_S} ({_S_I} = peak |{_TAU_I}|, raised to the "
                   "floor); by the triangle inequality the error on this trajectory is within "
                   "that sum: " + _scope(s))


def has_drives(ds: StoredSimplified | xr.Dataset) -> bool:
    """Whether the dataset's robot has drives (armature or friction), which the region's
    scale s_i leaves out.

    Parameters
    ----------
    ds : StoredSimplified or xarray.Dataset
        The simplified model's record, or a results dataset holding it; its drives are the
        variables ``D_arm``, ``viscous``, ``coulomb`` and ``torque_offset``.

    Returns
    -------
    bool
        True where any of them is nonzero.
    """
    return StoredSimplified.of(ds).has_drives


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


def guarantee_kind(ds: StoredSimplified | xr.Dataset) -> str:
    """The stored guarantee's kind.

    Parameters
    ----------
    ds : StoredSimplified or xarray.Dataset
        The simplified model's record, or a results dataset holding it.

    Returns
    -------
    str
        ``"region"``, ``"trajectory"``, or ``"none"`` where the dataset stores none.
    """
    return StoredSimplified.of(ds).guarantee_kind


def _scope(s, exact=False):
    """Where the bound holds: on this trajectory (the table's bound), and the model's
    guarantee as stored from the model built (:func:`gd_analyze.store.datasets.stored_guarantee`);
    an older dataset's sentence where none is stored."""
    g = s.guarantee
    if g is None:
        return "" if exact else (f"the bound below is guaranteed {ROUND_OFF_CLAUSE}, on this "
                                 "trajectory only.")
    said = f"The model's guarantee: {scope_markup(g['statement'])}."
    return " " + said if exact else (f"the bound below is guaranteed on this trajectory, "
                                     f"{ROUND_OFF_CLAUSE}. {said}")


def _dearer_than_full(s, other):
    """Why the other rule's explicit model costs more than the full one, from the stored
    counts (:func:`gd_analyze.jobs.simplified_dataset.coefficient_structure`), or ""."""
    if s.costs is None or s.structure is None:
        return ""
    full = s.costs.totals().get("explicit, full")
    mine = sum(int(-1 if v is None else v)
               for v in (s.other_rule_multiplications, s.other_rule_additions))
    if full is None or mine <= full:
        return ""
    fh, fc, oh, oc = s.structure
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
    (:func:`gd_analyze.ranking.ranking.is_round_off`), with ``arm_scale`` the largest
    scale among the joints of the same units
    (:func:`gd_analyze.ranking.ranking.arm_scales`)."""
    if diff.size == 0 or not np.isfinite(diff).all() or not np.isfinite(bound):
        return False
    return bool(is_round_off(bound, scale, arm_scale=arm_scale)
                and is_round_off(float(np.max(np.abs(diff))), scale, arm_scale=arm_scale))


def error_figure(ds: StoredSimplified | xr.Dataset, width: float = 7.2,
                 data: PlotData | None = None) -> Figure:
    """Per-joint plots of tau_s - tau against time, with the guaranteed band +- bound.

    Parameters
    ----------
    ds : StoredSimplified or xarray.Dataset
        The simplified model's record, or a results dataset with ``t``, ``tau``,
        ``tau_simplified`` (N, n) [N m] and ``simplified_bound`` (n,).
    width : float, optional
        Figure width [in]; narrower than 5 in (a 3.5-in column) gives one panel a row, else
        two.
    data : gd_analyze.report.main_figures.PlotData, optional
        The series as the report reads them, with ``tau_error`` (tau_s - tau per set point,
        or its min/max envelope for a long trajectory: the stored series are then never read
        whole); without it, the whole series are read from ``ds``.

    Returns
    -------
    matplotlib.figure.Figure
        One panel per joint whose difference is not round-off, on a fixed grid (no layout
        engine: the margins are set for the 7-pt tick labels, the 8-pt axis labels and the
        panel titles; no figure title, which the numbered caption gives); ticks placed once,
        in one notation for the figure (:func:`gd_analyze.report.ticks.label_axes`), every y
        range padded so that neither the error nor the bound touches the frame; the legend
        above the panels, clear of every curve. The joints whose difference and bound are
        round-off (:func:`_round_off`, :data:`gd_analyze.ranking.ranking.ROUND_OFF`)
        get no panel: a note below names them ("nothing dropped: Δτ = 0 up to round-off")
        with their peak difference.
    """
    from matplotlib.figure import Figure


    s = StoredSimplified.of(ds)
    n = s.n
    units = s.tau_units
    if data is not None and "tau_error" in data.series:
        t, diff = data.x, data.series["tau_error"]
    else:
        t = s.t
        diff = s.torque_difference()
    bound = s.bound
    scale = np.asarray(s.scale if s.scale is not None else s.tau_peak, float)
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
            + f"{float(np.max(np.abs(diff[:, i]))):.1e}".replace("-", "\u2212") + f" {units[i]}"
            for i in quiet)
        what = ("joint " if len(quiet) == 1 else "joints ") + ", ".join(
            str(i + 1) for i in quiet)
        note = textwrap.fill(
            f"Nothing dropped for {what} (bound 0): \u0394\u03c4 = 0 up to round-off, "
            f"not drawn (peak |\u0394\u03c4|, joint {peaks}).",
            int((W - 0.3) / 0.075))
    note_h = 0.12 + 0.16 * (note.count("\n") + 1) if quiet else 0.0
    H = (top + rows * h + (rows - 1) * hgap + bottom if shown else 0.1) + note_h
    w = (W - left - right - (cols - 1) * gap) / cols
    fig = Figure(figsize=(W, H))
    if data is not None and data.enveloped:     # the set points' range, not the columns'
        t = np.asarray(t, float)
        t0, t1 = s.time_span()
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
        ax.set_ylabel(f"\u0394\u03c4{which} [{units[i]}]", fontsize=8,
                      labelpad=1.0)
        line, = ax.plot(t, diff[:, i], color="#D55E00", linewidth=1.1,
                        label="\u0394\u03c4")
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
