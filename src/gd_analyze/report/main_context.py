"""The main report's content: every number, table and paragraph, read from the stored dataset.

:func:`report_context` builds the context that both the HTML template and the PDF typesetter
render (the same sections and numbers in both): robot and trajectory, the ranking, the
simplified model, the comparison with the chapter (Sec. 3.4.1 of Fu, Gonzalez & Lee 1987), the
payload sweep, the formulations (Table 3.5) and the provenance. Nothing is recomputed.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .._version import VERSION as __version__
from ..ranking.ranking import is_chapter_puma, joint_motion_units
from ..store.datasets import stored_guarantee, stored_region
from ..store.names import RANKING_COLUMNS
from ..store.results_view import Results
from .budget_figures import budget_caption
from .common import CLASS_COLOURS as _CLASS_COLOURS
from .common import (
    FORMULATION_ABBR,
    FORMULATION_NAMES,
    count,
    prismatic_joints,
    torque_units,
    units_said_once,
    units_text,
    utc_now,
)
from .common import attr as _attr
from .common import attr_text as _text
from .common import check as _check
from .common import fmt as _fmt
from .common import fmt_column as _fmt_column
from .common import fmt_columns as _columns
from .common import pct_columns as _pct_columns
from .common import share as _share
from .common import table as _table
from .main_chapter import chapter_conclusions
from .main_parts import (
    armature_columns,
    base_note,
    base_parameter_table,
    choice_table,
    d_text,
    has_armature,
    zero_parameters,
)
from .main_provenance import provenance_rows
from .main_robot import alike_joints, robot_section
from .main_text import (
    captions,
    conclusion,
    disagreement_cause,
    gravity_clause,
    prismatic_count_note,
    shared_causes,
    simplified_intro,
)
from .markup import element as _el
from .markup import scope as _scope
from .markup import tau
from .plot_data import ENVELOPE_COLUMNS, ENVELOPE_THRESHOLD
from .simplified_section import ROUND_OFF, simplified_caption, simplified_context

if TYPE_CHECKING:
    import numpy.typing as npt
    import xarray as xr

    from ..store.results_view import Results

__all__ = ["prismatic_joints", "zero_mask", "report_context"]

_REQUIRED = ("t", "q", "qd", "qdd", "D_tran", "D_rot", "D", "h_tran", "h_rot", "h", "tau",
             "tau_simplified", "share_tran", "dominance", "chapter_dominance", "choice",
             "peak_tran", "peak_rot", "peak_total", "tau_error_peak", "tau_error_rms",
             "tau_peak", "tau_error_relative_peak", "tau_error_relative_rms", "dh_d", "dh_a",
             "dh_alpha", "dh_offset", "link_mass", "link_com", "link_inertia")

_CHOICES_HEADING = {"explicit": "5.2 Choice per element",
                    "recursive": "5.2 Base parameters and the parts kept"}
_MODEL_HEADING = {"explicit": "5.3 Explicit model: rule, bound, cost",
                  "recursive": "5.3 Recursive model: rule, bound, cost"}



def _statement(ds):
    """The model's guarantee as stored, and where this trajectory leaves its region (which
    the region guarantee then does not cover); "" without a guarantee."""
    g = stored_guarantee(ds) or {}
    text = g.get("statement") or ""
    region = stored_region(ds)
    if text and g.get("kind") == "region" and region is not None and region["covered"] is False:
        text += (f"; this trajectory is not covered: it leaves the region "
                 f"({region['coverage']})")
    return text

def _recursive_facts(results):
    """(base parameters, dropped pairs, all pairs) of a recursive model, for the summary."""
    bp = results.base_parameters
    return (0 if bp is None else len(bp.names), *results.pairs)


def zero_mask(ds: Results | xr.Dataset) -> tuple[list[str], npt.NDArray[np.bool_]]:
    """The element labels and which elements are identically zero for the arm.

    Parameters
    ----------
    ds : Results or xarray.Dataset
        The results view (:class:`gd_analyze.store.results_view.Results`) or a results dataset.

    Returns
    -------
    (list of str, ndarray of bool, shape (M,))
        The labels, and True where the translational, rotational and total peaks are all
        round-off of the element's scale (drawn as "\u2261 0", no share printed): the marks
        stored at analysis.
    """
    table = Results.of(ds).ranking
    return [str(v) for v in table.column("label")], table.column("round_off")


def _share_text(share, tran_off, rot_off):
    """The translational share as printed: 0 or 1 where the other part is round-off of the
    element's scale (a share of 4e-14 is round-off, not data), else four decimals, never rounded
    to 0 or 1 (:func:`gd_analyze.report.numbers.share`)."""
    if tran_off and not rot_off:
        return "0"
    if rot_off and not tran_off:
        return "1"
    return _share(share)                # never "1" or "0" unless it is


def _share_cells(table):
    """The translational share of each element as printed: "\u2261 0" for an element zero in
    every part, else :func:`_share_text` with the stored round-off marks of its parts."""
    zero, tran, rot = table.column("round_off"), table.off("peak_tran"), table.off("peak_rot")
    return ["\u2261 0" if zero[k] else _share_text(v, tran[k], rot[k])
            for k, v in enumerate(table.column("share_tran"))]


def _caption_units(ds):
    """The units the captions state, from the joint types (:func:`captions`)."""

    prismatic = prismatic_joints(ds)
    motion = []
    for kind in (False, True):
        joints = [str(k + 1) for k in range(len(prismatic)) if prismatic[k] == kind]
        if joints:
            what = "prismatic" if kind else "revolute"
            motion.append(", ".join(joint_motion_units(kind, shown=True))
                          + (f" for {what} joint{'s' if len(joints) > 1 else ''} "
                             f"{', '.join(joints)}" if prismatic.any() else ""))
    return {"joints": "; ".join(motion), "D": units_said_once(ds, "D"),
            "tau": units_said_once(ds, "tau")}


def _is_puma560(name):
    return is_chapter_puma(name)


def _kv(rows):
    return _table(["item", "value"], rows, widths=[1.2, 3.4])


#: The models every cost is shown against, by their label in the stored cost table.
_COST_REFERENCES = ("project N-E as implemented", "recursive N-E, exact", "explicit, full")


def _model_cost(results):
    """(multiplications, additions, then the operations of Newton-Euler, of the exact model and
    of the full explicit model, each None if not counted) of the emitted model, from the stored
    attributes and cost table; None without a simplified model."""
    if results.simplified_operations is None:
        return None
    totals = {} if results.costs is None else results.costs.totals()
    return (*results.simplified_operations,
            *(int(totals[key]) if key in totals else None for key in _COST_REFERENCES))


def _gravity_fact(results, form):
    """What the deployed model does with the gravity loading c, read from what it dropped: a
    clause for the summary, or None when the dataset does not say."""
    bp = results.base_parameters
    if form == "recursive" and bp is not None:
        if "gravity" not in bp.parts:
            return None
        g = bp.parts.index("gravity")
        rel = (bp.relative_peak[:, g] if bp.relative_peak is not None
               else np.ones(len(bp.names)))
        names = [nm for nm, d, r in zip(bp.names, bp.dropped[:, g], rel)
                 if d and r >= ROUND_OFF]
        return gravity_clause("budget", gravity_dropped=names)
    simplified = results.simplified
    if simplified is None or simplified.bound_gravity is None:
        return None
    bound, rule = simplified.bound_gravity, simplified.rule
    if not np.all(np.isfinite(bound)) and rule != "chapter":    # no budget, rule unknown
        return None
    return gravity_clause(rule, c_bound=bound, units=torque_units(results))


def report_context(results: Results | xr.Dataset) -> dict[str, Any]:
    """Every number, table and paragraph of the main report, for the HTML and the PDF alike.

    Parameters
    ----------
    results : Results or xarray.Dataset
        The main job's results, typed (:class:`gd_analyze.store.results_view.Results`), or a
        results dataset as it stores them (viewed here).

    Returns
    -------
    dict
        The context the template and the PDF typesetter render.

    Raises
    ------
    InputError
        If a variable the report needs is missing.
    """
    results = Results.of(results)
    ctx = _report_context_base(results)
    simplified = results.simplified
    ctx["simplified_model"] = None if simplified is None else simplified_context(simplified)
    if simplified is not None and ctx["simplified_model"]:
        ctx["captions"] = {**ctx["captions"], "torque": simplified_caption(simplified),
                           "budget": budget_caption(simplified)}
    return ctx


#: The kinds of Sec. 4's columns shown only for an arm with drives.
_ARMATURE_KINDS = ("armature_share", "armature_peak")


def ranking_table(results: Results) -> dict[str, Any]:
    """Sec. 4's table: the columns of :data:`gd_analyze.store.names.RANKING_COLUMNS` with a
    ``report``, in their order, as the one view the command line prints too.

    Parameters
    ----------
    results : Results
        The results (their ranking table; the armature for an arm with drives).

    Returns
    -------
    dict
        A table (:func:`gd_analyze.report.common.table`). The peaks of the parts (and the
        armature) are one quantity: one number format for them all, "\u2261 0" where a
        peak is round-off (stored at analysis); a column of kind ``"number"`` has a format of
        its own.
    """
    table = results.ranking
    labels = [str(v) for v in table.column("label")]
    zero = table.column("round_off")
    arm = armature_columns(results, labels, zero)
    shown = [(c, c.report) for c in RANKING_COLUMNS if c.report is not None
             and (bool(arm["header"]) if c.report.kind in _ARMATURE_KINDS
                  else c.field in table.columns)]
    peaks = [c.field for c, r in shown if r.kind == "peak"]
    texts = _columns([table.column(f) for f in peaks] + [arm["peak"]],    # round-off: not data
                     off=[table.offs.get(f) for f in peaks] + [None])
    cells: dict[str, list[str]] = dict(zip(peaks, texts))
    arm_peak = iter(texts[-1])
    for c, r in shown:
        if r.kind == "share":
            cells[c.field] = _share_cells(table)
        elif r.kind == "armature_share":
            cells[c.field] = [row[0] for row in arm["rows"]]
        elif r.kind == "armature_peak":
            cells[c.field] = [next(arm_peak) if row[1] == "." else row[1]
                              for row in arm["rows"]]
        elif r.kind == "number":
            cells[c.field] = _fmt_column(table.column(c.field), off=zero)
        elif r.kind == "units":
            cells[c.field] = [units_text(str(v)) for v in table.column(c.field)]
        elif r.kind != "peak":                  # the label, a class: as stored
            cells[c.field] = [str(v) for v in table.column(c.field)]
    reports = [r for _, r in shown]
    return _table([r.header.format(X=_el("X", "", r.part) if r.part else "X")
                   for r in reports],
                  [[cells[c.field][k] for c, _ in shown] for k in range(len(labels))],
                  align=["left" if r.kind in ("label", "class", "units") else "right"
                         for r in reports],
                  widths=[r.width for r in reports],
                  colour_cols=[k for k, r in enumerate(reports) if r.kind == "class"])


def _report_context_base(results):
    """Everything both reports print, as strings and tables (no figures)."""

    ds = results.dataset
    _check(ds, _REQUIRED, "results")
    n = len(results.prismatic)
    t = results.trajectory.t
    N = t.size
    table = results.ranking                     # the view the command line prints too
    labels = [str(v) for v in table.column("label")]
    dominance = [str(v) for v in table.column("dominance")]
    chapter = [str(v) for v in table.column("chapter_dominance")]
    choice = [str(v) for v in table.column("choice")]
    share, zero = table.column("share_tran"), table.column("round_off")
    share_cells = _share_cells(table)
    tau_units = list(results.joint_units["tau"])
    s, e = results.dominance_threshold, results.negligible_threshold
    robot_name = _text(results.robot, "robot")
    now = utc_now()

    # 1. robot and trajectory
    robot = robot_section(results, robot_name)
    sha_in = _text(results.trajectory.input_sha256, "")

    # 4. ranking: the round-off marks as stored at analysis
    ranking = ranking_table(results)
    counts = {c: dominance.count(c) for c in _CLASS_COLOURS}

    # 5. simplified model and torque error
    built = results.provenance.simplified_form
    form = "explicit" if built is None else str(built)
    if form == "recursive":
        choices = base_parameter_table(results)
    else:
        choices = choice_table(results, labels, dominance, choice)
    errors = results.torque_error               # the view the command line prints too
    err_off = errors.column("round_off")        # as stored at analysis
    rel_peak, rel_rms = _pct_columns([errors.column("relative_peak"),  # one format
                                      errors.column("relative_rms")],   # for both
                                     off=[err_off, err_off])
    # the errors and peak |tau| are one quantity [N m or N]: one format
    err_peak, err_rms, tau_peak = _columns(
        [errors.column(v) for v in ("peak", "rms", "peak_tau")],
        off=[err_off, err_off, None])
    said = {"rel": rel_peak, "abs": err_peak, "tau": tau_peak}   # the summary quotes them
    err = _table(
        ["joint", f"peak |{tau(simplified=True)}\u00a0\u2212\u00a0\u03c4|",
         f"RMS |{tau(simplified=True)}\u00a0\u2212\u00a0\u03c4|",
         "peak |\u03c4|", "peak error / peak |\u03c4|", "RMS error / peak |\u03c4|", "units"],
        [[str(k + 1)] + (["\u2261 0 (round-off)"] * 2 if err_off[k] else
                         [err_peak[k], err_rms[k]])
         + [tau_peak[k], rel_peak[k], rel_rms[k], tau_units[k]]
         for k in range(n)],
        align=["left"] + ["right"] * 5 + ["left"], widths=[0.6, 1.2, 1.2, 1, 1.2, 1.2, 0.6])
    rel_peak = errors.column("relative_peak")

    # 6. comparison with the chapter
    applicable = n == 6 and _is_puma560(robot_name)
    compare_rows, n_agree, n_compared = [], 0, 0
    for k, (lab, ours, theirs) in enumerate(zip(labels, dominance, chapter)):
        shown = share_cells[k]
        if theirs:
            n_compared += 1
            agree = ours == theirs
            n_agree += agree
            compare_rows.append([lab, ours, theirs, "yes" if agree else "no", shown,
                                 disagreement_cause(lab, ours, theirs, share[k], zero[k], s,
                                                    robot_name)])
        else:
            compare_rows.append([lab, ours, "\u2014", "\u2014", shown, ""])
    if applicable:
        note = ("The chapter reads these classes by eye off Figs. 3.10 and 3.11 for its own "
                "PUMA 560 trajectory of 31 set points; it notes that the simplification depends "
                "on the trajectory, so disagreements are expected for another trajectory. The "
                "chapter has no 'negligible' class: an element classed negligible here counts "
                "as a disagreement.")
    elif n == 6:
        note = (f"The chapter reports dominance only for its PUMA 560 (Sec. 3.4.1); this robot "
                f"({robot_name}) is another arm, so its classes are not compared with the "
                "chapter's.")
    else:
        note = (f"The chapter reports dominance only for the 6-joint PUMA 560 (Sec. 3.4.1); "
                f"this robot has {n} joint{'s' if n != 1 else ''}, so a comparison is not "
                "meaningful and none is made.")
    if applicable and results.rigid_dominance is not None:
        rigid = results.rigid_dominance
        n_rigid = sum(r == c for r, c in zip(rigid, chapter) if c)
        note += (f" With its drives (armature counted on the rotational side, friction in "
                 f"τ) {n_agree} of {n_compared} classes agree with the chapter's; its "
                 f"rigid links alone (drives left out, the chapter's model) {n_rigid} of "
                 f"{n_compared}.")
    conclusions = []
    ch = results.chapter
    if applicable and ch is not None:
        conclusions = chapter_conclusions(
            ch.blocks, ch.threshold, ch.agreement, ch.elements_compared, n, s,
            ch.model_error_relative_peak, ch.model_error_round_off,
            errors.column("relative_peak"), err_off,
            where=f"this trajectory ({count(N)} set points)")
    causes, said_once = shared_causes([row[-1] for row in compare_rows])
    compare_rows = [row[:-1] + [cause] for row, cause in zip(compare_rows, causes)]
    if said_once:
        note += f" Causes shared by several rows of Table 6.1, said once: {said_once}"
    compare = _table(["element", "our class", "chapter's class", "agree", "translational share",
                      "cause"],
                     compare_rows, align=["left"] * 4 + ["right", "left"],
                     widths=[0.6, 1.05, 1.05, 0.45, 0.85, 4.0], colour_cols=[1, 2, 3])

    # 7. provenance
    verified, verification = _verification(results.verification, N)
    prov = provenance_rows(results, now.isoformat(), __version__, verification)

    formulations = _formulations_context(results.formulations)
    payload = _payload_context(results)
    title = f"G-D dominance analysis: {robot_name} along {_text(results.trajectory.input_file)}"
    summary = conclusion(labels, dominance, zero, choice, rel_peak,
                         errors.column("peak"), errors.column("peak_tau"), _model_cost(results),
                         recursive=_recursive_facts(results) if form == "recursive" else None,
                         gravity=_gravity_fact(results, form), units=tau_units,
                         scope=_scope(_statement(ds)),
                         where="the joint-limit region" if (stored_guarantee(ds) or {}).get(
                             "kind") == "region" else "this trajectory", shown=said,
                         placeholder_inertia=results.robot_record.placeholder_inertia)
    facts = (f"{robot_name}, {n} joints, {count(N)} set points over {_fmt(t[-1] - t[0], 4)} s; "
             f"{len(labels)} elements ranked with s = {s:g}, e = {e:g}: "
             + ", ".join(f"{counts[c]} {c}" for c in _CLASS_COLOURS)
             + f". Verification against Pinocchio: {verified}.")
    enveloped = N > ENVELOPE_THRESHOLD
    return {
        "version": __version__, "title": title, "summary": summary, "robot_name": robot_name,
        "facts": facts, "intro": _INTRO.format(created=now.isoformat(), version=__version__),
        "captions": captions(enveloped, N, f"{s:g}", f"{e:g}", units=_caption_units(ds),
                             alike=alike_joints(results)),
        "D_text": d_text(results, s, e, enveloped), "armature": has_armature(results),
        "n": n, "N": N, "s": f"{s:g}", "e": f"{e:g}", "created": now.isoformat(),
        **robot,
        "ranking": ranking, "counts": counts, "choices": choices, "error": err,
        "simplified_intro": (simplified_intro(form, _gravity_fact(results, form))
                             + zero_parameters(results)),
        "choices_heading": _CHOICES_HEADING[form],
        "choices_note": base_note(results) if form == "recursive" else "",
        "model_heading": _MODEL_HEADING[form],
        "compare": {"applicable": applicable, "note": note, "table": compare,
                    "conclusions": conclusions,
                    "n_agree": n_agree, "n_compared": n_compared},
        "provenance": _kv(prov), "enveloped": enveloped,
        "formulations": formulations, "payload": payload,
        "envelope_note": (f"The trajectory has {count(N)} set points: curves are drawn as their "
                          f"min/max envelope over {count(ENVELOPE_COLUMNS)} equal time columns per panel, "
                          "without markers (the report reads the stored series in chunks)."
                          if enveloped else ""),
        "keywords": (f"generalized d'Alembert; G-D dynamics; dominance; {robot_name}; "
                     f"input {_text(results.trajectory.input_file)} sha256 {sha_in or '-'}; "
                     f"robot sha256 {_attr(ds, 'robot_sha256')}; s={s:g}; e={e:g}; "
                     f"verification {verified}"),
    }


_INTRO = ("Generalized d'Alembert (G-D) equations of motion split the inertia matrix D and the "
          "Coriolis and centrifugal vector h of \u03c4 = D(q) q\u0308 + h(q, q\u0307) + c(q) into "
          "a translational and a rotational part (Fu, Gonzalez & Lee 1987, Robotics, Sec. 3.4, "
          "Eqs. 3.4-24 to 3.4-28). This report ranks which part dominates each element along "
          "the trajectory (Sec. 3.4.1, Figs. 3.10 and 3.11). Report created {created} by "
          "gd-analyze {version} from the stored results; nothing was recomputed.")


#: The verification's absolute floor (gd_analyze.dynamics.pinocchio.FLOOR_EPS machine
#: epsilons of the overall scale), as the text names it; a report imports no formulation.
_ROUND_OFF_FLOOR = "64 eps"


def _quantity(name):
    """A verified quantity's name as mathematics: "D_tran" -> D^tran, "h" -> h."""
    symbol, _, part = name.partition("_")
    return _el(symbol, "", part) if part in ("tran", "rot") else name


def _verification(check, N):
    """(verdict for the summary, the one provenance row) of the check against Pinocchio: how
    many of the N set points it checked, its tolerance once, and its largest errors, which are
    as measured, and whether they are past the round-off floor."""
    if check is None:
        return "not run", "not run (analysis without check)"
    checked = check.setpoints
    verdict = (f"{'passed' if check.passed else 'FAILED'} on {count(checked)} of {count(N)} "
               "set points" + ("" if checked == N else " (evenly spread)"))
    measured = {_quantity(term): error for term, error, _ in check.terms}
    past = {_quantity(term): excess for term, _, excess in check.terms}
    floor = _ROUND_OFF_FLOOR
    largest = ("largest relative difference: "
               + ", ".join(f"{k} {_fmt(v, 2, (1e-3, 1e3))}" for k, v in measured.items()))
    if past and all(v == 0 for v in past.values()):
        errors = f"{largest}; each within the round-off floor ({floor} of its scale)"
    elif past and all(np.isnan(v) for v in past.values()):       # a file of before the excess
        errors = largest
    else:
        errors = (f"{largest}; past the round-off floor ({floor} of its scale): "
                  + ", ".join(f"{k} {_fmt(v, 2, (1e-3, 1e3))}" for k, v in past.items()))
    row = (f"{verdict}; tolerance {_text(check.tolerance)} of each element's "
           f"scale on {', '.join(measured) or 'D, h and c'}; {errors}")
    return verdict, row


def _payload_context(results):
    part = results.payload
    if part is None:
        return {"applicable": False, "table": None, "note": ""}
    masses = [float(m) for m in part.masses]
    labels = list(part.elements)
    dom = part.dominance
    rows = [[lab] + [dom[k, j] for k in range(len(masses))]
            for j, lab in enumerate(labels) if len(set(dom[:, j])) > 1]
    table = _table(["element"] + [f"{m:g} kg" for m in masses], rows,
                   colour_cols=list(range(1, len(masses) + 1)))
    note = (f"The ranking was repeated with a rigid load of {masses[0]:g} to {masses[-1]:g} kg "
            f"fixed to the last link (centre of mass {_text(results.provenance.payload_com)} m in link "
            f"frame n). {len(rows)} of {len(labels)} elements change class with the load; "
            "they are listed below. The load is merged into link n, so its parallel-axis "
            "terms about the combined centre of mass count as rotational.")
    return {"applicable": True, "table": table, "note": note}


def _formulations_context(f):
    """Agreement and cost tables of L-E, N-E, G-D and Pinocchio, if the dataset has them."""
    if f is None:
        return {"applicable": False, "note": "The dataset holds no comparison of the "
                "formulations (made by `gd-analyze ROBOT TRAJECTORY.csv`).",
                "agreement": None, "costs": None}
    quantities, pairs, dis = f.quantities, f.pairs, f.disagreement

    def pair(p):                            # "lagrange-euler vs gd" -> "L-E vs G-D"
        return " vs ".join(FORMULATION_ABBR.get(f, f) for f in p.split(" vs "))

    agreement = _table(["pair"] + [tau() if q == "tau" else q for q in quantities],
                       [[pair(p)] + [f"{v:.2e}" for v in dis[i]] for i, p in enumerate(pairs)],
                       align=["left"] + ["right"] * len(quantities))
    n, names, dof = f.n, f.names, list(f.dof)
    rows = []
    if n in dof:
        k = dof.index(n)
        for j, name in enumerate(names):
            if f.arm is not None:             # the arm's own joint types (prismatic joints)
                mul, add = f.arm[0][j], f.arm[1][j]
            else:
                mul, add = f.multiplications[k, j], f.additions[k, j]
            bm = f.multiplications_table_3_5[k, j]
            ba = f.additions_table_3_5[k, j]
            rows.append([FORMULATION_NAMES.get(name, name), count(mul), count(add),
                         count(bm), count(ba)])
    costs = _table(["formulation", "multiplications", "additions", "mult. Table 3.5",
                    "add. Table 3.5"], rows, align=["left"] + ["right"] * 4)
    worst = float(np.max(dis)) if dis.size else float("nan")
    note = (f"Lagrange-Euler (Sec. 3.2), recursive Newton-Euler (Sec. 3.3; D, h and c by "
            f"probing), the G-D equations (Sec. 3.4) and Pinocchio (crba, rnea) were run on "
            f"{'?' if f.setpoints is None else f.setpoints} set points of the trajectory; the "
            f"largest relative disagreement of any pair is {worst:.1e}. Operation counts are "
            f"per set point, counted on the code as implemented (the G-D equations by the "
            f"compiled and by the array engine), beside the formulas of Table 3.5, for "
            f"n = {n}; pairs: L-E Lagrange-Euler, N-E Newton-Euler, G-D the G-D equations."
            + prismatic_count_note(f.joint_types))
    return {"applicable": True, "note": note, "agreement": agreement, "costs": costs}
