"""The main report's tables and notes of the model's parts: the drives' armature (its share
and peak in Sec. 4, its column in Table 5.2, Fig. 2's lead-in), the choice per element of an
explicit model and the base parameters of a recursive one, with their names defined.

Read from the typed results (:class:`gd_analyze.store.results_view.Results`); nothing is
recomputed.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..ranking.labels import element_label
from .common import fmt as _fmt
from .common import fmt_column as _column
from .common import share as _share
from .common import table as _table
from .common import units_said_once, units_text
from .markup import element as _el
from .simplified_section import ROUND_OFF

if TYPE_CHECKING:
    import numpy.typing as npt

    from ..store.results_view import Results

__all__ = ["choice_table", "base_parameter_table", "base_note", "zero_parameters",
           "armature_columns", "has_armature", "d_text"]

_CHOICE_TEXT = {"tran": "translational part only", "rot": "rotational part only",
                "both": "translational + rotational"}


def choice_table(results: Results, labels: Sequence[str], dominance: Sequence[str],
                 choice: Sequence[str]) -> dict[str, Any]:
    """Sec. 5.2 of an explicit model: the part of each element kept, and for an arm with drives
    the armature, which the model keeps whole (a column of its own: an element whose link
    parts are dropped keeps its armature).

    Parameters
    ----------
    results : Results
        The results of an explicit model (the armature if it has drives).
    labels, dominance, choice : list of str, each length M
        The elements, their classes and the part kept of each.

    Returns
    -------
    dict
        A table (:func:`gd_analyze.report.common.table`).
    """
    arm = has_armature(results)
    diag = _diagonal(len(results.prismatic))

    def meaning(k, lab):
        if choice[k] != "none":
            return _CHOICE_TEXT.get(choice[k], "")
        what = "link parts dropped" if arm and lab in diag else "dropped"
        return what + (" (negligible)" if dominance[k] == "negligible" else " (within the budget)")

    return _table(
        ["element", "class", "kept part", *(["armature"] if arm else []), "meaning"],
        [[lab, dominance[k], choice[k], *(["kept" if lab in diag else "\u2014"] if arm else []),
          meaning(k, lab)] for k, lab in enumerate(labels)],
        widths=[0.8, 1.2, 0.8, *([0.8] if arm else []), 2.2], colour_cols=[1])


def base_parameter_table(results: Results) -> dict[str, Any]:
    """The base parameters of a recursive model, their values and which parts are kept.

    Parameters
    ----------
    results : Results
        The results of a recursive model (its base parameters and their values).

    Returns
    -------
    dict
        A table (:func:`gd_analyze.report.common.table`): the parameters of nonzero value.

    Raises
    ------
    ValueError
        If the results store no base parameters or no values of them.
    """
    bp = results.base_parameters
    if bp is None or bp.value is None:
        raise ValueError("the results store no base parameters' values")
    names, parts, dropped, units = bp.names, bp.parts, bp.dropped, bp.units
    rel = bp.relative_peak if bp.relative_peak is not None else np.ones(dropped.shape)

    def cell(k, p):
        if rel[k, p] < ROUND_OFF:
            return "\u2261 0"            # contributes nothing on this trajectory
        return "dropped" if dropped[k, p] else "kept"

    value = bp.value
    listed = [k for k in range(len(names)) if value[k] != 0]
    return _table(["base parameter", "value", "units", *parts],
                  [[names[k], text, units_text(units[k]),
                    *(cell(k, p) for p in range(len(parts)))]
                   for k, text in zip(listed, _column(value[listed]))],
                  align=["left", "right", "left", "left", "left", "left"],
                  widths=[1.0, 1.0, 0.7, 0.8, 0.8, 0.8])


_BASE_NOTE = (
    "Base parameters (Khalil & Kleinfinger 1987; Gautier 1990), per link j in its joint frame j "
    "(origin on joint j's axis, z along it; the frame joint j moves, not the link frame of "
    "Table 1.3): XXj, XYj, XZj, YZj, ZZj [kg m\u00b2] are entries of the link's inertia "
    "tensor about that origin, MXj, MYj [kg m] its first moment m r, each with the parameters "
    "that do not act on their own regrouped into it (for a revolute joint the link's YY, MZ "
    "and m go to the links before it, XXj stands for XX \u2212 YY).")


def base_note(results: Results) -> str:
    """The note defining the base parameters' names and frame, with an example of a first
    moment that is 0 in the joint frame while Table 1.3's centre of mass has that coordinate.

    Parameters
    ----------
    results : Results
        The results (the base parameters' values, the links' centres of mass, the DH rows).

    Returns
    -------
    str
        "" without base parameters (an explicit model).
    """
    bp = results.base_parameters
    if bp is None or bp.value is None:
        return ""
    values = dict(zip(bp.names, bp.value))
    com = results.robot_record.link_com
    if not np.isfinite(results.robot_record.dh[1]).all():   # a URDF arm: its link frame is the body's
        return _BASE_NOTE
    for j in range(com.shape[0]):
        for axis, c in (("X", 0), ("Y", 1)):
            if values.get(f"M{axis}{j + 1}", None) == 0 and com[j, c] != 0:
                return (_BASE_NOTE + f" So M{axis}{j + 1} = 0 beside a centre of mass "
                        f"{axis.lower()} of {_fmt(com[j, c])} m of link {j + 1} in Table 1.3, for "
                        "the two frames differ.")
    return _BASE_NOTE


def zero_parameters(results: Results) -> str:
    """The sentence naming the base parameters whose value is 0 (not listed in Sec. 5.2).

    Parameters
    ----------
    results : Results
        The results (the base parameters' values).

    Returns
    -------
    str
        With a leading space; "" if none is 0.
    """
    bp = results.base_parameters
    if bp is None or bp.value is None:
        return ""
    zero = [n for n, v in zip(bp.names, bp.value) if v == 0]
    if not zero:
        return ""
    return (f" Of the {len(bp.names)} base parameters, {len(zero)} are 0 for this "
            f"robot and are not listed: {', '.join(zero)}.")




_D_TEXT = ("One panel per element " + _el("D", "ij") + " with i \u2264 j, in reading order "
           "(" + _el("D", "11") + ", " + _el("D", "12") + ", \u2026), but for an element "
           "zero in every part, which the note below the panels names: "
           "translational part " + _el("D", "ij", "tran") + " ({tran}), rotational part "
           + _el("D", "ij", "rot") + " ({rot}){armature} and " + _el("D", "ij")
           + " = " + _el("D", "ij", "tran") + " + " + _el("D", "ij", "rot") + "{plus_arm}"
           + " ({total}) "
           "against time [{units}]. The title gives the element and its dominance class "
           "(s = {s}, e = {e}).")
#: How Fig. 2 draws each part (main_figures): marker and colour, or, for a long trajectory
#: drawn as its envelope without markers, line style and colour.
_D_PARTS = {False: {"tran": "\u25cb, blue", "rot": "\u00d7, orange", "total": "\u25b3, black",
                    "arm": "\u25a1, dash-dot, pink"},
            True: {"tran": "solid, blue", "rot": "dashed, orange", "total": "dotted, black",
                   "arm": "dash-dot, pink"}}
#: What the combined curve of a diagonal panel adds for an arm with drives (Table 1.4).
_D_ARMATURE = {"armature": ", on a diagonal panel the drives' armature " + _el("D", "ii", "arm")
                           + " ({arm}, drawn above the combined curve; a constant; " + _el("D", "ij", "arm")
                           + " = 0 off the diagonal)",
               "plus_arm": " + " + _el("D", "ij", "arm")}


def armature_columns(results: Results, labels: Sequence[str],
                     zero: npt.NDArray[np.bool_]) -> dict[str, Any]:
    """Sec. 4's columns of an arm with drives: the armature share and peak |X^arm| (the
    armature on D_ii, "—" elsewhere); none without drives.

    Parameters
    ----------
    results : Results
        The results (the armature and its share).
    labels : list of str, length M
        The elements.
    zero : ndarray of bool, shape (M,)
        The elements zero in every part.

    Returns
    -------
    dict
        ``header`` (list of str), ``rows`` (M lists of cells; a peak cell is "." until the
        caller formats the peaks with the other parts'), ``peak`` (the armature of each
        diagonal element [kg m^2; kg]).
    """
    if not has_armature(results):
        return {"header": [], "rows": [[] for _ in labels], "peak": []}
    arm = np.asarray(results.robot_record.armature, float)
    share = (results.share_arm if results.share_arm is not None
             else np.full(len(labels), np.nan))
    diag = _diagonal(arm.size)
    rows = [[("\u2261 0" if zero[k] else _share(share[k])) if lab in diag else "\u2014",
             "." if lab in diag else "\u2014"] for k, lab in enumerate(labels)]
    return {"header": ["armature share", f"peak |{_el('X', '', 'arm')}|"], "rows": rows,
            "peak": [arm[diag[lab]] for lab in labels if lab in diag]}


def _diagonal(n):
    """The labels of D's diagonal elements, each with its joint's index (0-based)."""
    return {element_label("D", k, k): k for k in range(n)}


def has_armature(results: Results) -> bool:
    """Whether the arm has drives whose armature adds to the diagonal of D (Table 1.4).

    Parameters
    ----------
    results : Results
        The results (the armature, if the arm has drives).

    Returns
    -------
    bool
    """
    arm = results.robot_record.armature
    return arm is not None and bool(np.any(arm > 0))


def d_text(results: Results, s: float, e: float, enveloped: bool) -> str:
    """Fig. 2's lead-in: the parts drawn and what the combined curve sums.

    Parameters
    ----------
    results : Results
        The results (their joint types, for the units of D, and the armature).
    s, e : float
        The thresholds.
    enveloped : bool
        The series are drawn as envelopes (no markers).

    Returns
    -------
    str
        Marked up (:mod:`gd_analyze.report.markup`).
    """
    parts = _D_PARTS[enveloped]
    arm = ({"armature": _D_ARMATURE["armature"].replace("{arm}", parts["arm"]),
            "plus_arm": _D_ARMATURE["plus_arm"]} if has_armature(results)
           else {"armature": "", "plus_arm": ""})
    return _D_TEXT.format(s=f"{s:g}", e=f"{e:g}", units=units_said_once(results, "D"),
                          **{k: v for k, v in parts.items() if k != "arm"}, **arm)
