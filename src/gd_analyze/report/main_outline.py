"""The main report's sections, once, for the HTML template and the PDF typesetter alike.

:func:`main_outline` turns the context of :func:`gd_analyze.report.main_context.report_context`
into an :class:`gd_analyze.report.sections.Outline`: numbered sections, paragraphs, tables
with numbered captions, figures with numbered captions.
"""

from __future__ import annotations

from collections.abc import Collection, Mapping
from typing import Any

from ..ranking.ranking import ROUND_OFF
from .budget_figures import BUDGET_CAPTIONS
from .markup import code, element, sub
from .numbers import decade_label
from .sections import Outline

__all__ = ["main_outline", "RANKING_TEXT"]

_X = "X"
#: The ranking's rule in words (Sec. 3.4.1 of Fu, Gonzalez & Lee 1987, with the negligible
#: class of this tool); ``{s}`` and ``{e}`` are the thresholds.
RANKING_TEXT = (
    "For each element X (" + element("D", "ij") + " or " + element("h", "i") + "), the "
    "translational share is \u03a3|" + element(_X, "", "tran") + "| / (\u03a3|"
    + element(_X, "", "tran") + "| + \u03a3|" + element(_X, "", "rot") + "{arm}|) over the set "
    "points{arm_said}. An element is negligible if its peak |" + element(_X, "", "tran") + " + "
    + element(_X, "", "rot") + "{arm}| is below e = {e} times its scale (peak \u221a("
    + element("D", "ii") + " " + element("D", "jj") + ") for " + element("D", "ij")
    + ", peak |\u03c4" + sub("i") + "| for " + element("h", "i") + "); otherwise "
    "translational if its share is at least s = {s}, rotational if at most 1 \u2212 s, and "
    "both in between. \u2261 0: zero in every part (below " + decade_label(ROUND_OFF)
    + " of its scale); its share is "
    "rounding noise and is not shown.")
#: The armature's term in :data:`RANKING_TEXT`, for an arm with drives (Table 1.4).
_ARMATURE_TERMS = {"arm": " + " + element(_X, "", "arm"),
                   "arm_said": ", the drives' armature " + element(_X, "", "arm") + " (on "
                   + element("D", "ii") + " only) counted on the rotational side; the armature "
                   "share \u03a3|" + element(_X, "", "arm") + "| over the same sum is its own "
                   "column"}
_DH_CAPTION = "Denavit-Hartenberg parameters (standard form); q is joint i's variable, {what}."
_DH_VARIABLE = {False: "the angle \u03b8 (revolute joints)",
                True: "the angle \u03b8 of a revolute joint, the offset d of a prismatic one, "
                      "whose \u03b8 is fixed"}
_PLACEMENT_CAPTION = (
    "Joint placements, as the model holds them: frame i in body frame i \u2212 1, translation "
    "x, y, z [m] and rotation as roll, pitch, yaw [deg] (R = Rz(yaw) Ry(pitch) Rx(roll), as in "
    "URDF); joint i turns about, or slides along, the z axis of frame i, whose direction in "
    "frame i \u2212 1 is the last column. The robot has no Denavit-Hartenberg parameters.")
_LINK_CAPTION = ("Link inertial parameters: mass, centre of mass (com) in link frame i, and "
                 "the diagonal of the inertia tensor about the centre of mass.")
def _files_text(prefix):
    """What the emitted source files hold, with the C prefix the run used (stored setting
    ``c_prefix``; an older file without it: the placeholder PREFIX), code set as code."""
    p = prefix or "PREFIX"
    return (" (a C header and C99 source with " + code(f"{p}tau") + ", "
            + code(f"{p}inertia") + ", " + code(f"{p}velocity_terms") + ", "
            + code(f"{p}gravity") + " and " + code(f"{p}regressor") + "; numpy "
            + code("tau") + ", " + code("inertia") + ", " + code("velocity_terms") + ", "
            + code("gravity") + " and " + code("regressor") + " over arrays of shape (N, n); "
            "CasADi " + code("functions()") + " of the same).")


def _split(heading):
    """("5.2", "Choice per element") from "5.2 Choice per element"."""
    number, title = heading.split(" ", 1)
    return number, title


def main_outline(ctx: Mapping[str, Any], figures: Collection[str]) -> Outline:
    """The main report's sections.

    Parameters
    ----------
    ctx : dict
        :func:`gd_analyze.report.main_context.report_context` of the dataset.
    figures : collection of str
        The keys of the drawn figures (:data:`gd_analyze.report.main.FIGURE_FILES`).

    Returns
    -------
    Outline
        Title block, then Secs. 1 to 8: Sec. 6, the comparison with the chapter, only for
        the chapter's PUMA 560 (the payload sweep is 6.1 there, else Sec. 6; the later
        sections move up when neither is there).

    Notes
    -----
    Source of the sections: Sec. 3.4.1, Figs. 3.10-3.11 and Table 3.5 of Fu, Gonzalez & Lee
    (1987).
    """
    caps = ctx["captions"]
    o = Outline(ctx["title"], figures)
    o.paragraph(ctx["summary"], "summary")
    o.paragraph(ctx["facts"], "body")
    o.paragraph(ctx["intro"], "note")

    o.section("1", "Robot and trajectory", "robot")
    o.section("1.1", "Robot")
    o.table(ctx["robot_kv"], "The robot.", kv=True)
    if ctx["dh"] is not None:
        prismatic = any(row[1].startswith("q") for row in ctx["dh"]["rows"])
        o.table(ctx["dh"], _DH_CAPTION.format(what=_DH_VARIABLE[prismatic]))
    if ctx.get("placements") is not None:
        o.table(ctx["placements"], _PLACEMENT_CAPTION)
    o.table(ctx["link"], _LINK_CAPTION)
    if ctx.get("drives"):
        o.paragraph(ctx["drives"]["note"], "note")
        o.table(ctx["drives"]["table"], "The drives: armature and friction per joint.")
    o.section("1.2", "Trajectory")
    o.table(ctx["traj_kv"], "The trajectory.", kv=True)
    o.table(ctx["joints"], "Range of motion per joint.")
    if ctx.get("effort"):
        o.paragraph(ctx["effort_text"], "note")
        o.table(ctx["effort"], "Peak |\u03c4| of the full model against each joint's effort "
                               "limit.")
    o.paragraph(ctx["envelope_note"], "note")
    o.figure("joints", caps["joints"])

    o.section("2", "Acceleration-related elements of D (analogue of Fig. 3.10)", "D")
    o.paragraph(ctx["D_text"], "note")
    o.figure("D", caps["D"])
    for part in range(2, 6):            # the panels that did not fit on one page
        o.figure(f"D_{part}", f"{caps['D']} (Part {part}.)")
    o.section("3", "Coriolis and centrifugal elements of h (analogue of Fig. 3.11)", "h")
    o.figure("h", caps["h"])

    o.section("4", "Dominance ranking", "ranking")
    o.paragraph(RANKING_TEXT.format(s=ctx["s"], e=ctx["e"], **(
        _ARMATURE_TERMS if ctx.get("armature") else dict.fromkeys(_ARMATURE_TERMS, ""))), "note")
    o.counts(ctx["counts"])
    o.table(ctx["ranking"], "Dominance of each element: translational share, class and the "
                            "peaks of its parts along the trajectory.")

    o.section("5", "Simplified model and torque error", "simplified")
    o.paragraph(ctx["simplified_intro"], "note")
    o.figure("contributions", BUDGET_CAPTIONS["contributions"])
    o.section("5.1", "Torque error along the trajectory")
    o.table(ctx["error"], "Open-loop torque error of the simplified model per joint, "
                          "\u03c4" + sub("s") + " \u2212 \u03c4 along the trajectory.")
    o.figure("torque", caps["torque"])
    o.section(*_split(ctx["choices_heading"]))
    o.paragraph(ctx.get("choices_note", ""), "note")
    o.table(ctx["choices"], "Base parameters and the parts of their contributions the model "
                            "keeps." if ctx["choices"]["header"][0] == "base parameter" else
            "The part of each element the simplified model keeps.")
    sm = ctx.get("simplified_model")
    if sm:
        o.section(*_split(ctx["model_heading"]))
        o.paragraph(sm["text"], "note")
        if sm.get("screen_note"):
            o.paragraph(sm["screen_note"], "note")
        o.table(sm["bound"], "Bound on the torque error per joint, split by where the dropped "
                             "terms sit, beside the measured peak error.")
        if sm.get("region"):
            o.paragraph(sm["region_text"], "note")
            o.table(sm["region"], "The region of the model's guarantee per joint: position "
                                  "range, velocity and acceleration limits, and whether the "
                                  "acceleration limit is assumed.")
        o.figure("budget", caps.get("budget", BUDGET_CAPTIONS["budget"]))
        if sm["costs"]:
            o.section("5.4", "Cost per set point (counted)")
            o.table(sm["costs"], "Operations per set point, counted on each model's code.")
            if sm["form_note"]:
                o.paragraph(sm["form_note"], "note")
            o.figure("cost_ladder", BUDGET_CAPTIONS["cost_ladder"])
        if sm["ladder"] or sm["ladder_note"]:
            o.section(*_split(sm["ladder_heading"]))
            if sm["ladder"]:
                o.table(sm["ladder"], "Cost and worst error of the model built at each "
                                      "tolerance \u03b5.")
            else:
                o.paragraph(sm["ladder_note"], "note")
        o.paragraph("Emitted source files: " + ", ".join(code(f) for f in sm["files"])
                    + _files_text(sm["prefix"]), "note")

    compare = ctx["compare"]
    top = 6                                  # the chapter comparison only for its PUMA 560
    if compare["applicable"]:
        o.section("6", "Comparison with the chapter's PUMA 560", "chapter")
        for sentence in compare["conclusions"]:
            o.paragraph(sentence)
        o.paragraph(compare["note"], "note")
        o.paragraph(f"Agreement: {compare['n_agree']} of {compare['n_compared']} elements.",
                    "strong")
        o.table(compare["table"], "Our class of each element against the class the chapter "
                                  "reads off Figs. 3.10 and 3.11.")
    payload = ctx["payload"]
    if payload["applicable"]:
        o.section(f"{top}.1" if compare["applicable"] else str(top),
                  "Dominance against the payload", "payload", level=1)
        o.paragraph(payload["note"], "note")
        if payload["table"]["rows"]:
            o.table(payload["table"], "Elements whose class changes with the payload.")
        o.figure("payload", caps["payload"])
    top += compare["applicable"] or payload["applicable"]

    forms = ctx["formulations"]
    o.section(str(top), "Formulations: Lagrange-Euler, Newton-Euler, G-D", "formulations")
    o.paragraph(forms["note"], "note")
    if forms["applicable"]:
        o.section(f"{top}.1", "Largest relative disagreement per pair")
        o.table(forms["agreement"], "Largest relative disagreement of each pair of "
                                    "formulations over the checked set points.")
        o.section(f"{top}.2", "Operations per set point")
        o.table(forms["costs"], "Operations per set point: as implemented, and by the "
                                "formulas of Table 3.5.")
        o.figure("formulations", caps["formulations"])

    o.section(str(top + 1), "Provenance", "provenance")
    o.table(ctx["provenance"], "Provenance: each setting of the analysis and the report once.",
            kv=True, size=7)
    return o
