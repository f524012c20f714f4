"""The main report's content: every number, table and paragraph, read from the stored dataset.

:func:`report_context` builds the context that both the HTML template and the PDF typesetter
render (the same sections and numbers in both): robot and trajectory, the ranking, the
simplified model, the comparison with the chapter (Sec. 3.4.1 of Fu, Gonzalez & Lee 1987), the
payload sweep, the formulations (Table 3.5) and the provenance. Nothing is recomputed. The
robot section (:func:`robot_section`), the tables and notes of the model's parts and the
chapter's conclusions as this run measured them (:func:`chapter_conclusions`, Sec. 6) are
built here too, with each joint's peak |tau| against the effort limit its robot gives
(:func:`effort_rows`).

The provenance (:func:`provenance_rows`) says each setting of the analysis once, in words. The
dataset's global attributes hold the settings asked for (``rule``, ``tolerance``, ``form``
...), the model's record of what it was built with (``simplified_rule`` ...), and results that
Sec. 5 and Sec. 7 already print: a setting asked for and recorded twice with one value is
shown once; one asked for and built otherwise ("form: cheapest") reads "asked cheapest, built
recursive"; results and the attributes the report shows elsewhere (the robot and trajectory in
Sec. 1, the title) are left out.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from .._version import VERSION as __version__
from ..ranking.labels import element_label, joint_torque_units
from ..ranking.ranking import is_chapter_puma, joint_motion_units
from ..store.datasets import stored_guarantee, stored_region
from ..store.names import RANKING_COLUMNS
from ..store.results_view import Results
from ..store.schema import RunRecord, require
from .common import CLASS_COLOURS as _CLASS_COLOURS
from .common import (
    FORMULATION_ABBR,
    FORMULATION_NAMES,
    count,
    given,
    joints_text,
    other_rows,
    prismatic_joints,
    say,
    settings_table,
    torque_units,
    units_said_once,
    units_text,
    utc_now,
)
from .common import attr_text as _text
from .common import fmt as _fmt
from .common import fmt_column as _column
from .common import fmt_columns as _columns
from .common import pct_columns as _pct_columns
from .common import share as _share
from .common import table as _table
from .main_figures import ENVELOPE_COLUMNS, ENVELOPE_THRESHOLD
from .main_text import (
    StoredModel,
    captions,
    conclusion,
    disagreement_cause,
    gravity_clause,
    prismatic_count_note,
    shared_causes,
    weightless,
)
from .markup import code, element, marked, powers, tau
from .markup import scope as _scope
from .numbers import pct, time_origin
from .simplified_section import ROUND_OFF, budget_caption, simplified_caption, simplified_context

if TYPE_CHECKING:
    import numpy.typing as npt
    import xarray as xr

    from ..store.results_view import Provenance

__all__ = ["EffortRow", "effort_rows", "EXCEEDED", "WITHIN", "chapter_conclusions",
           "choice_table", "base_parameter_table", "base_note", "zero_parameters",
           "armature_columns", "has_armature", "robot_section", "alike_joints",
           "ALIKE", "prismatic_joints", "zero_mask", "report_context", "DERIVATIVES",
           "provenance_rows", "software_row", "command_row", "run_row", "gravity_row",
           "guarantee_row"]

#: The flag of a joint whose peak |tau| exceeds its effort limit, and of one within it.
EXCEEDED, WITHIN = "EXCEEDED", "within"


class EffortRow(tuple):
    """(joint, peak, limit, ratio, flag, units) of one joint with an effort limit."""

    __slots__ = ()

    @property
    def exceeded(self) -> bool:
        """bool: the peak |tau| is above the limit."""
        return self[4] == EXCEEDED


def effort_rows(results: Results) -> list[EffortRow]:
    """Each joint with an effort limit: its peak |tau| against the limit.

    Parameters
    ----------
    results : Results
        The main job's results: peak |tau| (its torque error table) and the effort limits
        (its robot), shape (n,) [N m; N for a prismatic joint] (a limit NaN where the robot
        gives none).

    Returns
    -------
    list of EffortRow
        One per joint whose limit is given: (joint number from 1, peak |tau|, limit,
        peak / limit, :data:`EXCEEDED` or :data:`WITHIN`, units); empty when the robot gives
        no limit (or the dataset predates them).

    Notes
    -----
    The limits are the URDF's ``<limit effort>`` or a robot file's ``tau_max``; peak |tau| is
    that of the full model, D qdd + h + c (Fu, Gonzalez & Lee 1987, Eq. (3.4-24)).
    """
    if results.robot_record.effort_limit is None:
        return []
    peak = results.torque_error.column("peak_tau").astype(float)
    limit = np.asarray(results.robot_record.effort_limit, float)
    units = [joint_torque_units(p) for p in results.prismatic]
    kept = [j for j in range(peak.size) if math.isfinite(limit[j]) and limit[j] > 0]
    return [EffortRow((j + 1, float(peak[j]), float(limit[j]), float(peak[j] / limit[j]),
                       EXCEEDED if peak[j] / limit[j] > 1.0 else WITHIN, units[j]))
            for j in kept]


def chapter_conclusions(blocks: dict[str, list[str]], grid: ArrayLike, agree: ArrayLike,
                        compared: int, n: int, s: float, chapter_error: ArrayLike,
                        chapter_off: ArrayLike, built_error: ArrayLike, built_off: ArrayLike,
                        where: str = "this trajectory", weightless: bool = False) -> list[str]:
    """The chapter's conclusions on its PUMA 560, each as this run measured it.

    Parameters
    ----------
    blocks : dict
        ``arm``, ``arm_translation``, ``wrist`` and ``wrist_rotation``: element labels, as
        :func:`gd_analyze.ranking.chapter_comparison.block_leads` counts them.
    grid : array_like, shape (S,)
        Dominance thresholds s.
    agree : array_like of int, shape (S,)
        Elements whose class at each s equals the chapter's
        (:func:`gd_analyze.ranking.chapter_comparison.agreement_against_s`).
    compared : int
        The elements the chapter classes.
    n : int
        Number of joints (6).
    s : float
        The dominance threshold of the report's ranking.
    chapter_error, chapter_off : array_like, shape (n,)
        The chapter's own simplified model's peak |tau_s - tau| / peak |tau| per joint, and
        where that is round-off.
    built_error, built_off : array_like, shape (n,)
        The same for the model the run built.
    where : str, optional
        The motion the errors were measured on.
    weightless : bool, optional
        The arm has no gravity (:func:`gd_analyze.report.main_text.weightless`): the chapter's
        model is not said to keep c, which is identically 0.

    Returns
    -------
    list of str
        Three sentences: which part leads the arm block and the wrist, agreement against s,
        and the chapter's own model measured.

    Notes
    -----
    Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987), Figs. 3.10-3.11.
    """
    arm, arm_t, wrist, wrist_r = (blocks[k] for k in ("arm", "arm_translation", "wrist",
                                                      "wrist_rotation"))
    missed = [k for k in arm if k not in arm_t] + [k for k in wrist if k not in wrist_r]
    grid, agree = np.asarray(grid, dtype=float), np.asarray(agree, dtype=int)
    best = int(agree.max(initial=0))
    err, off = np.asarray(chapter_error, dtype=float), np.asarray(chapter_off, dtype=bool)
    shown = np.where(off | ~np.isfinite(err), 0.0, err)
    worst = int(np.argmax(shown))
    per_joint = ", ".join(f"{k + 1}: " + ("\u2261 0" if off[k] else pct(err[k]))
                          for k in range(err.size))
    mine = np.where(np.asarray(built_off, dtype=bool), 0.0, np.asarray(built_error, dtype=float))
    return [say("chapter_leads", arm=len(arm), arm_t=len(arm_t), wrist=len(wrist),
                wrist_r=len(wrist_r), n=n, missed=", ".join(map(marked, missed))),
            say("chapter_agreement", compared=compared, best=best,
                at=[f"{v:g}" for v, a in zip(grid, agree) if a == best],
                parts=[(a, f"{v:g}", v == float(s)) for v, a in zip(grid, agree)]),
            say("chapter_model", where=where, worst=pct(shown[worst]), joint=worst + 1,
                per_joint=per_joint, mine=pct(float(mine.max(initial=0.0))),
                weightless=weightless)]


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

    def cell(k, p):                     # "\u2261 0": contributes nothing on this trajectory
        return "\u2261 0" if rel[k, p] < ROUND_OFF else "dropped" if dropped[k, p] else "kept"

    value = bp.value
    listed = [k for k in range(len(names)) if value[k] != 0]
    return _table(["base parameter", "value", "units", *parts],
                  [[names[k], text, units_text(units[k]),
                    *(cell(k, p) for p in range(len(parts)))]
                   for k, text in zip(listed, _column(value[listed]))],
                  align=["left", "right", "left", "left", "left", "left"],
                  widths=[1.0, 1.0, 0.7, 0.8, 0.8, 0.8])


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
        return say("base_note")
    for j in range(com.shape[0]):
        for axis, c in (("X", 0), ("Y", 1)):
            if values.get(f"M{axis}{j + 1}") == 0 and com[j, c] != 0:
                return say("base_note", moment=f"M{axis}{j + 1}", axis=axis.lower(),
                           com=_fmt(com[j, c]), link=j + 1)
    return say("base_note")


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
    return say("zero_parameters", all=len(bp.names),
               zero=[n for n, v in zip(bp.names, bp.value) if v == 0])


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
    return {"header": ["armature share", f"peak |{element('X', '', 'arm')}|"], "rows": rows,
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


#: Two joints move alike when q, q\u0307 and q\u0308 differ by at most this fraction of their
#: scale (the larger peak of the two): round-off, their curves drawn one over the other.
ALIKE = 1e-12


def alike_joints(results: Results) -> list[list[int]]:
    """The groups of joints whose stored motions are equal to round-off: their curves in
    Fig. 1 coincide, the one drawn last hiding the others.

    Parameters
    ----------
    results : Results
        With the trajectory's q, q\u0307 and q\u0308 of shape (N, n) and the joint types.

    Returns
    -------
    list of list of int
        Each group's joints, 1-based and ascending, of one joint type (a revolute and a
        prismatic joint are drawn on different panels); groups of two or more only, in the
        order of their first joint.

    Notes
    -----
    Joints i and j move alike when, for each of q, q\u0307 and q\u0308, the largest
    difference of their columns is at most :data:`ALIKE` times the larger peak of the two
    columns (both columns 0: alike).
    """
    prismatic = np.array(results.prismatic)
    n = prismatic.size
    peak, apart = np.zeros((3, n)), np.zeros((3, n, n))     # per q, q̇, q̈: max |x_i|, |x_i - x_j|
    for block in results.trajectory.motion_blocks(max(1, 2 ** 20 // n ** 2)):
        for k, x in enumerate(block):
            peak[k] = np.maximum(peak[k], np.abs(x).max(axis=0))
            apart[k] = np.maximum(apart[k], np.abs(x[:, :, None] - x[:, None, :]).max(axis=0))

    def alike(i, j):
        return prismatic[i] == prismatic[j] and bool(np.all(
            apart[:, i, j] <= ALIKE * np.maximum(peak[:, i], peak[:, j])))

    groups, placed = [], set()
    for i in range(n):
        if i in placed:
            continue
        group = [i] + [j for j in range(i + 1, n) if j not in placed and alike(i, j)]
        if len(group) > 1:
            placed.update(group)
            groups.append([k + 1 for k in group])
    return groups


def _kv(rows):
    return settings_table(rows, widths=[1.2, 3.4])


def robot_section(results: Results, robot_name: str) -> dict[str, Any]:
    """The tables and sentences of the robot and trajectory section.

    Parameters
    ----------
    results : Results
        The main job's results.
    robot_name : str
        The robot's name as printed.

    Returns
    -------
    dict
        ``robot_kv``, ``dh`` and ``placements`` (one of them None), ``link``, ``drives``
        (None without drives), ``traj_kv``, ``joints``, ``effort`` (None without limits) and
        ``effort_text``: the entries of the report's context.
    """
    robot, traj = results.robot_record, results.trajectory
    n = len(results.prismatic)
    t = traj.t
    labels = [r.label for r in results.ranking.rows]
    robot_kv = _kv([
        ("name", robot_name), ("description", _text(robot.description)),
        ("reference", _text(robot.reference)), ("robot file", _text(robot.source)),
        ("robot file SHA-256", _text(robot.sha256)), ("joints n", str(n)),
        ("gravity g [m/s\u00b2]", _text(robot.gravity)),
    ])
    dh, placements = _robot_geometry(results)
    link = _table(
        ["joint", "mass [kg]", "com x [m]", "com y [m]", "com z [m]", "Ixx [kg m\u00b2]",
         "Iyy [kg m\u00b2]", "Izz [kg m\u00b2]"],
        _rows(range(1, n + 1), robot.link_mass, *robot.link_com.T,
              *(robot.link_inertia[:, i, i] for i in range(3))),
        align=["left"] + ["right"] * 7, widths=[0.7] + [1] * 7)
    drives = _drives_context(results, labels)
    derivatives = traj.derivatives
    sha_in = _text(traj.input_sha256, "")
    traj_kv = _kv([
        ("source file", _text(traj.input_file)), ("path", _text(traj.input_path)),
        ("SHA-256", sha_in or "\u2014 (not read from a file)"),
        ("set points N", count(t.size)),
        ("duration [s]",
         f"{_fmt(t[-1] - t[0], 6)}  (t = {_stamp(t[0], t)} \u2026 {_stamp(t[-1], t)})"),
        ("derivatives", f"{derivatives}: {DERIVATIVES.get(derivatives, 'as recorded')}"
         if derivatives else "\u2014"),
    ])
    prismatic = np.array(results.prismatic)
    # the units of Fig. 1 (joint_motion_units shown): deg, or mm for a prismatic joint
    scale = np.where(prismatic, 1000.0, np.degrees(1.0))
    extremes = []       # per block: q min, q max, peak |q̇|, peak |q̈|
    for block in traj.motion_blocks():
        q, qd, qdd = (v * scale for v in block)
        extremes.append((q.min(axis=0), q.max(axis=0), np.abs(qd).max(axis=0),
                         np.abs(qdd).max(axis=0)))
    q_min, q_max, qd_peak, qdd_peak = (f(np.array(e), axis=0) for f, e in zip(
        (np.min, np.max, np.max, np.max), zip(*extremes)))
    joints = _table(
        ["joint", "type", "q min", "q max", "peak |q\u0307|", "peak |q\u0308|", "units"],
        [[row[0], "prismatic" if prismatic[k] else "revolute", *row[1:],
          ", ".join(joint_motion_units(bool(prismatic[k]), shown=True))]
         for k, row in enumerate(_rows(range(1, n + 1), q_min, q_max, qd_peak, qdd_peak))],
        align=["left", "left"] + ["right"] * 4 + ["left"], widths=[0.6, 0.9, 1, 1, 1, 1, 1.5])

    efforts = effort_rows(results)
    over = [str(r[0]) for r in efforts if r.exceeded]     # the joints beyond their limit
    effort = _table(
        ["joint", "peak |\u03c4|", "effort limit", "peak / limit", "flag", "units"],
        [[*row, flag, unit] for row, (*_, flag, unit) in zip(
            _rows([e[0] for e in efforts], [e[1] for e in efforts], [e[2] for e in efforts],
                  ([e[3] for e in efforts], 3)), efforts)],
        align=["left", "right", "right", "right", "left", "left"],
        widths=[0.6, 1, 1, 1, 1, 0.6]) if efforts else None
    return {"robot_kv": robot_kv, "dh": dh, "placements": placements, "link": link,
            "traj_kv": traj_kv, "joints": joints, "effort": effort,
            "drives": drives,
            "effort_text": say("effort_text", over=over, joints=joints_text(over)) if efforts else ""}


def _rows(first, *columns):
    """Table rows: ``first`` as text, then each column of numbers in one notation
    (:func:`gd_analyze.report.numbers.fmt_column`); a column given as ``(values, digits)``
    keeps that many significant digits."""
    cols = [_column(*c) if isinstance(c, tuple) else _column(c) for c in columns]
    return [[str(f), *cells] for f, *cells in zip(first, *cols)]


def _robot_geometry(results):
    """(DH table, None) for a robot given by DH rows; (None, placements table) for a URDF or
    chain robot, whose DH parameters are not defined: each joint's fixed placement in body frame
    i-1 (translation xyz [m], rotation as roll-pitch-yaw [deg], R = Rz(yaw) Ry(pitch)
    Rx(roll) as in URDF) and its axis, the z column of the rotation."""
    robot = results.robot_record
    n = len(results.prismatic)
    dh_rows = robot.dh
    if (np.all(np.isfinite(dh_rows)) or robot.joint_rotation is None
            or robot.joint_translation is None):
        pris = np.array(results.prismatic)

        def cell(value, variable):            # the joint variable q where it moves: q + offset
            if not variable:
                return given(value)
            sign = "+" if value > 0 else "\u2212"
            return "q" if value == 0 else f"q {sign} {given(abs(value))}"

        dh = _table(                        # as the robot file gives them
            ["joint", "d [m]", "a [m]", "\u03b1 [deg]", "\u03b8 [deg]"],
            [[str(k + 1), cell(dh_rows[0, k], pris[k]), given(dh_rows[1, k]),
              given(np.degrees(dh_rows[2, k])), cell(np.degrees(dh_rows[3, k]), not pris[k])]
             for k in range(n)],
            align=["left"] + ["right"] * 4, widths=[0.8, 1, 1, 1, 1])
        return dh, None
    import warnings

    from scipy.spatial.transform import Rotation

    R = np.asarray(robot.joint_rotation, float)
    t = np.asarray(robot.joint_translation, float)
    with warnings.catch_warnings():             # pitch of +-90 deg: yaw 0, roll takes it all
        warnings.simplefilter("ignore", UserWarning)
        rpy = Rotation.from_matrix(R).as_euler("xyz", degrees=True)  # extrinsic: URDF's rpy

    def num(v):
        return _fmt(0.0 if abs(v) < 1e-12 else v)                    # no -0, no 1e-17

    xyz = np.where(np.abs(t) < 1e-12, 0.0, t)
    angles = np.where(np.abs(rpy) < 1e-12, 0.0, rpy)
    placements = _table(
        ["joint", "type", "x [m]", "y [m]", "z [m]", "roll [deg]", "pitch [deg]", "yaw [deg]",
         "axis in frame i\u22121"],
        [[str(k + 1), robot.joint_type[k] if robot.joint_type is not None else "",
          *row[1:], "(" + ", ".join(num(v) for v in R[k, :, 2]) + ")"]
         for k, row in enumerate(_rows(range(n), *xyz.T, *angles.T))],
        align=["left", "left"] + ["right"] * 6 + ["left"],
        widths=[0.6, 0.9, 0.9, 0.9, 0.9, 0.9, 0.9, 0.9, 1.6])
    return None, placements


def _drives_context(results: Results | xr.Dataset, labels):
    """The drives' table and its note, or None when the robot has no drives."""
    results = Results.of(results)
    robot = results.robot_record
    offset = robot.torque_offset
    has_offset = offset is not None and bool(np.any(offset))
    drives = robot.drives
    if drives is None or not (any(np.any(v) for v in drives) or has_offset):
        return None
    arm, fv, fc = drives
    n = arm.shape[0]
    pris = np.array(results.prismatic)
    tau_f = results.trajectory.tau_f
    peak_f = np.abs(tau_f).max(axis=0) if tau_f is not None else np.zeros(n)
    share = results.share_arm if results.share_arm is not None else np.zeros(len(labels))
    diag = [list(labels).index(f"D{k + 1}{k + 1}") if n < 10 else None for k in range(n)]
    extra = (offset,) if has_offset else ()
    table = _table(
        ["joint", "armature", "viscous", "Coulomb", *(["offset"] if has_offset else []),
         f"peak |{tau('f')}|", f"armature share of {element('D', 'ii')}", "units"],
        [[*row, _share(float(share[diag[k]])) if diag[k] is not None else "—",
          ("kg, N s/m, N" + ", N" * has_offset + ", N") if pris[k] else
          ("kg m², N m s/rad, N m" + ", N m" * has_offset + ", N m")]
         for k, row in enumerate(_rows(range(1, n + 1), arm, fv, fc, *extra, peak_f))],
        align=["left"] + ["right"] * (5 + has_offset) + ["left"],
        widths=[0.5, 0.9, 0.9, 0.9, *([0.9] if has_offset else []), 0.9, 1, 2])
    note = say("drives_note", offset=has_offset)
    return {"table": table, "note": note}


#: The series the report draws: the rest it reads, the results view requires
#: (:data:`gd_analyze.store.results_view.REQUIRED`).
_REQUIRED = ("t", "q", "qd", "qdd", "D_tran", "D_rot", "D", "h_tran", "h_rot", "h", "tau",
             "tau_simplified")

_CHOICES_HEADING = {"explicit": "5.2 Choice per element",
                    "recursive": "5.2 Base parameters and the parts kept"}
_MODEL_HEADING = {"explicit": "5.3 Explicit model: rule, bound, cost",
                  "recursive": "5.3 Recursive model: rule, bound, cost"}




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
    joints = {kind: [str(k + 1) for k in range(len(prismatic)) if prismatic[k] == kind]
              for kind in (False, True)}
    return {"joints": say("motion_units", mixed=bool(prismatic.any()), kinds=[
        (", ".join(joint_motion_units(kind, shown=True)), kind, joints_text(js))
        for kind, js in joints.items() if js]),
        "D": units_said_once(ds, "D"), "tau": units_said_once(ds, "tau")}


#: The models every cost is shown against, by their label in the stored cost table.
_COST_REFERENCES = ("project N-E as implemented", "recursive N-E, exact", "explicit, full")


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
    ds = results.dataset
    require(ds, _REQUIRED, "results")
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
    no_gravity = weightless(results.robot_record.gravity)    # c is then 0: said once
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
    choices = (base_parameter_table(results) if form == "recursive"
               else choice_table(results, labels, dominance, choice))
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

    # 6. comparison with the chapter
    applicable = n == 6 and is_chapter_puma(robot_name)
    n_compared = sum(bool(c) for c in chapter)          # the elements the chapter classes
    n_agree = sum(ours == c for ours, c in zip(dominance, chapter) if c)
    compare_rows = [[lab, ours, theirs, "yes" if ours == theirs else "no", share_cells[k],
                     disagreement_cause(lab, ours, theirs, share[k], zero[k], s, robot_name)]
                    if theirs else [lab, ours, "\u2014", "\u2014", share_cells[k], ""]
                    for k, (lab, ours, theirs) in enumerate(zip(labels, dominance, chapter))]
    n_rigid = (sum(r == c for r, c in zip(results.rigid_dominance, chapter) if c)
               if applicable and results.rigid_dominance is not None else None)
    ch = results.chapter
    conclusions = [] if not applicable or ch is None else chapter_conclusions(
        ch.blocks, ch.threshold, ch.agreement, ch.elements_compared, n, s,
        ch.model_error_relative_peak, ch.model_error_round_off,
        errors.column("relative_peak"), err_off,
        where=f"this trajectory ({count(N)} set points)", weightless=no_gravity)
    causes, said_once = shared_causes([row[-1] for row in compare_rows])
    compare_rows = [row[:-1] + [cause] for row, cause in zip(compare_rows, causes)]
    note = say("chapter_note", applicable=applicable, n=n, robot=robot_name, n_agree=n_agree,
               n_compared=n_compared, n_rigid=n_rigid, shared=said_once)
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
    # the emitted model's (multiplications, additions, then the operations of Newton-Euler, of
    # the exact model and of the full explicit model, each None if not counted), from the stored
    # attributes and cost table; None without a simplified model
    totals = {} if results.costs is None else results.costs.totals()
    cost: Any = None if results.simplified_operations is None else (
        *results.simplified_operations,
        *(int(totals[key]) if key in totals else None for key in _COST_REFERENCES))
    bp = results.base_parameters    # a recursive model's base parameters and dropped pairs
    # the model's guarantee as stored, and where this trajectory leaves its region (which the
    # region guarantee then does not cover); "" without a guarantee
    g, region = stored_guarantee(ds) or {}, stored_region(ds)
    statement = g.get("statement") or ""
    if (statement and g.get("kind") == "region" and region is not None
            and region["covered"] is False):
        statement += f"; this trajectory is not covered: it leaves the region ({region['coverage']})"
    kept = StoredModel((0 if bp is None else len(bp.names), *results.pairs)
                       if form == "recursive" else None, tuple(choice),
                       _gravity_fact(results, form), "the joint-limit region"
                       if g.get("kind") == "region" else "this trajectory", no_gravity)
    summary = conclusion(labels, dominance, zero, choice, errors.column("relative_peak"),
                         errors.column("peak"), errors.column("peak_tau"), cost, kept,
                         units=tau_units, scope=powers(_scope(statement)), shown=said,
                         placeholder_inertia=results.robot_record.placeholder_inertia,
                         round_off=err_off)
    facts = say("main_facts", robot=robot_name, n=n, N=count(N), span=_fmt(t[-1] - t[0], 4),
                M=len(labels), s=f"{s:g}", e=f"{e:g}", counts=counts, verified=verified)
    enveloped = N > ENVELOPE_THRESHOLD
    simplified = results.simplified
    model = None if simplified is None else simplified_context(simplified)
    caps = captions(enveloped, N, f"{s:g}", f"{e:g}", units=_caption_units(ds),
                    alike=alike_joints(results))
    if model and simplified is not None:
        caps.update(torque=simplified_caption(simplified), budget=budget_caption(simplified))
    return {
        "version": __version__, "title": title, "summary": summary, "robot_name": robot_name,
        "facts": facts, "intro": say("main_intro", created=now.isoformat(), version=__version__),
        "captions": caps, "simplified_model": model,
        "D_text": say("d_text", enveloped=enveloped, armature=has_armature(results), s=f"{s:g}",
                      e=f"{e:g}", units=units_said_once(results, "D")),   # Fig. 2's lead-in
        "armature": has_armature(results),
        "n": n, "N": N, "s": f"{s:g}", "e": f"{e:g}", "created": now.isoformat(),
        **robot,
        "ranking": ranking, "counts": counts, "choices": choices, "error": err,
        "simplified_intro": (say("simplified_intro", form=form, weightless=no_gravity,
                                 gravity=kept.gravity) + zero_parameters(results)),
        "choices_heading": _CHOICES_HEADING[form],
        "choices_note": base_note(results) if form == "recursive" else "",
        "model_heading": _MODEL_HEADING[form],
        "compare": {"applicable": applicable, "note": note, "table": compare,
                    "conclusions": conclusions,
                    "n_agree": n_agree, "n_compared": n_compared},
        "provenance": _kv(prov),
        "formulations": formulations, "payload": payload,
        "envelope_note": (say("envelope_note", N=N, columns=ENVELOPE_COLUMNS)
                          if enveloped else ""),
        "keywords": (f"generalized d'Alembert; G-D dynamics; dominance; {robot_name}; "
                     f"input {_text(results.trajectory.input_file)} sha256 {sha_in or '-'}; "
                     f"robot sha256 {_text(results.robot_record.sha256)}; s={s:g}; e={e:g}; "
                     f"verification {verified}"),
    }


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
            cells[c.field] = _column(table.column(c.field), off=zero)
        elif r.kind == "units":
            cells[c.field] = [units_text(str(v)) for v in table.column(c.field)]
        elif r.kind != "peak":                  # the label, a class: as stored
            cells[c.field] = [str(v) for v in table.column(c.field)]
    reports = [r for _, r in shown]
    return _table([r.header.format(X=element("X", "", r.part) if r.part else "X")
                   for r in reports],
                  [[cells[c.field][k] for c, _ in shown] for k in range(len(labels))],
                  align=["left" if r.kind in ("label", "class", "units") else "right"
                         for r in reports],
                  widths=[r.width for r in reports],
                  colour_cols=[k for k, r in enumerate(reports) if r.kind == "class"])


def _stamp(v, t):
    """A time stamp of the series t [s] in 6 significant digits, or, where the series' first
    stamp is far from 0 against its span (:func:`gd_analyze.report.numbers.time_origin`: Unix
    time stamps), in as many decimals as give its span 6 significant digits."""
    origin, _ = time_origin(t)
    if not origin:
        return _fmt(v, 6)
    span = float(t[-1] - t[0])
    return f"{float(v):.{max(0, 5 - math.floor(math.log10(span)))}f}"


def _quantity(name):
    """A verified quantity's name as mathematics: "D_tran" -> D^tran, "h" -> h."""
    symbol, _, part = name.partition("_")
    return element(symbol, "", part) if part in ("tran", "rot") else name


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
    def said(values):
        return [f"{k} {_fmt(v, 2, (1e-3, 1e3))}" for k, v in values.items()]

    state = ("within" if past and all(v == 0 for v in past.values()) else
             "" if past and all(np.isnan(v) for v in past.values()) else "past")
    row = say("verification", verdict=verdict, tolerance=_text(check.tolerance),
              quantities=list(measured), largest=said(measured), past=said(past), state=state)
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
    note = say("payload_note", lightest=f"{masses[0]:g}", heaviest=f"{masses[-1]:g}",
               com=_text(results.provenance.payload_com), changed=len(rows),
               elements=len(labels))
    return {"applicable": True, "table": table, "note": note}


def _formulations_context(f):
    """Agreement and cost tables of L-E, N-E, G-D and Pinocchio, if the dataset has them."""
    if f is None:
        return {"applicable": False, "note": say("formulations_note", applicable=False),
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
        # as implemented: for the arm's own joint types (prismatic joints) where stored
        mul, add = f.arm if f.arm is not None else (f.multiplications[k], f.additions[k])
        rows = [[FORMULATION_NAMES.get(name, name), count(mul[j]), count(add[j]),
                 count(f.multiplications_table_3_5[k, j]), count(f.additions_table_3_5[k, j])]
                for j, name in enumerate(names)]
    costs = _table(["formulation", "multiplications", "additions", "mult. Table 3.5",
                    "add. Table 3.5"], rows, align=["left"] + ["right"] * 4)
    worst = float(np.max(dis)) if dis.size else float("nan")
    note = say("formulations_note", setpoints="?" if f.setpoints is None else f.setpoints,
               worst=f"{worst:.1e}", n=n, prismatic=prismatic_count_note(f.joint_types),
               counted=bool(rows), dof=[int(d) for d in dof])
    return {"applicable": True, "note": note, "agreement": agreement, "costs": costs}


# --------------------------------------------------------------------------------------------
# The provenance: each setting of the analysis once, in words
# --------------------------------------------------------------------------------------------
#: How a trajectory's velocities and accelerations were obtained, in words (the stored
#: ``derivatives`` setting).
DERIVATIVES = {
    "file": "read from the file (its velocity and acceleration columns)",
    "cubic-spline": "derived from q by a not-a-knot cubic spline",
    "quintic": "analytic derivatives of a planned quintic motion",
    "arrays": "given as arrays (the Python API)",
}


#: The ``explicit`` setting in words.
_EXPLICIT = {"auto": "derived when its estimated size is cheap and it may be deployed (auto)",
             "always": "always derived", "never": "never derived"}
#: The ``guarantee`` asked for, in words (what was built is the row "guarantee of the model
#: built").
_GUARANTEE = {k: "over the joint-limit region where the robot file or the command line gives "
                 f"every joint's position and velocity limits, else on the trajectory ({k})"
              for k in ("auto", "region")} | {
    "trajectory": "on the analysed trajectory only (trajectory)"}


def _settings(p: Provenance):
    """(row, setting asked for, what the model records it was built with), in the order
    shown."""
    return (("simplification rule", p.rule, p.simplified_rule),
            ("error budget \u03b5 (relative to each joint's scale)", p.tolerance,
             p.simplified_tolerance),
            ("torque floor of each joint's scale", p.torque_floor, p.simplified_torque_floor),
            ("model form", p.form, p.simplified_form),
            ("explicit model", p.explicit, None),
            ("guarantee asked for", p.guarantee, None),
            ("rule compared side by side", p.other_rule, None))


def _setting(asked, built):
    a = None if asked is None else _text(asked)
    b = None if built is None else _text(built)
    if a is None or b is None or a == b:
        return a if a is not None else b
    return f"asked {a}, built {b}"


def _payload(p):
    mass = float(p.payload_mass or 0.0)
    return say("payload_row", mass=f"{mass:g}" if mass else "", com=_text(p.payload_com),
               inertia=_text(p.payload_inertia))


def _vector(value):
    """A stored 3-vector attribute as numbers, or None."""
    if value is None:
        return None
    v = np.asarray(value, dtype=float).ravel()
    return v if v.size == 3 else None


def _mounting(p):
    """The mounting in words: how the base is turned, and where gravity comes from."""
    rpy, world = _vector(p.mounting_base_rpy_deg), _vector(p.mounting_gravity_world)
    return None if rpy is None and world is None else say(
        "mounting", rpy=[_fmt(v, 6) for v in rpy] if rpy is not None and np.any(rpy) else [],
        world=[] if world is None else [_fmt(v, 6) for v in world])


def provenance_rows(results: Results, created: str, version: str,
                    verification: str) -> list[tuple[str, str | None]]:
    """The rows (item, value) of the main report's provenance table, each setting once
    (:func:`gd_analyze.report.common.settings_table`).

    Parameters
    ----------
    results : Results
        The main job's results; its provenance, robot and trajectory files and thresholds
        are read.
    created : str
        When the report was made (ISO 8601).
    version : str
        The version of gd-analyze that makes the report.
    verification : str
        The verification's one row (:func:`gd_analyze.report.main_context._verification`).

    Returns
    -------
    list of (str, str or None)
        A value None where the results do not record the setting: no row.
    """
    p, robot, traj = results.provenance, results.robot_record, results.trajectory
    analysis = _text(p.gd_analyze_version)
    sha_in = _text(traj.input_sha256, "") or "\u2014, not read from a file"
    ran = _text(p.history).split(" created by ")[0]   # the CF history: "<time> created by"
    rows = [
        ("software", f"gd-analyze {version}" if analysis == version else
         f"analysis by gd-analyze {analysis}, report by gd-analyze {version}"),
        command_row(p.command),
        ("analysis run, report created", created if ran == created else f"{ran}, {created}"),
        ("trajectory file", f"{_text(traj.input_path)} (SHA-256 {sha_in})"),
        ("robot file", f"{_text(robot.source)} (SHA-256 {_text(robot.sha256)})"),
        ("dominance threshold s, negligibility threshold e",
         f"{_fmt(results.dominance_threshold, 6)}, {_fmt(results.negligible_threshold, 6)}"),
    ]
    for k, (label, asked, built) in enumerate(_settings(p)):
        value = _setting(asked, built)
        if value is not None and k == 2:                    # the torque floor
            value = (say("no_floor", region=results.guarantee_kind == "region",
                         drives=results.robot_record.has_drives,
                         source=_scope((results.guarantee or {}).get("scale_source", "")))
                     if value == "0" else
                     value + " N m" + (", or N for a prismatic joint"
                                       if any(results.prismatic) else ""))
        # the explicit model, the guarantee asked for: in words
        rows.append((label, {4: _EXPLICIT, 5: _GUARANTEE}.get(k, {}).get(value, value)))
    engine = _text(p.verification_engine, "Pinocchio")
    # the joints the operation counts take as prismatic, if any (", joint 3 prismatic")
    types = "" if p.formulations_joint_types is None else str(p.formulations_joint_types)
    pris = [str(k + 1) for k, t in enumerate(types) if t == "P"]
    return rows + [
        ("mounting", _mounting(p)), ("payload on the last link", _payload(p)),
        ("formulations compared on", None if p.formulations_setpoints is None else
         f"{_text(p.formulations_setpoints)} set points, for n = {_text(p.formulations_n)}"
         + (f", {joints_text(pris)} prismatic" if pris else "")),
        ("emitted source files", None if p.simplified_files is None else
         _text(p.simplified_files)),
        guarantee_row("guarantee of the model built", p.simplified_guarantee_kind,
                      p.simplified_guarantee_statement),
        ("verification against " + engine.replace("pinocchio", "Pinocchio"), verification),
        *other_rows(p.others),                              # each setting once
        ("file format", "results.h5: HDF5 (netCDF-4) with metadata after the CF "
         f"conventions, version {_text(p.conventions).replace('CF-', '')}"),
        ("method", _text(p.references))]


# Rows shared with the sweep and control reports' provenance (each setting once, in words).

def software_row(ds: RunRecord | xr.Dataset, version: str) -> tuple[str, str]:
    """("software", ...): the version that computed the stored results and the one that
    writes the report, once when they agree (as the main report's provenance says it).

    Parameters
    ----------
    ds : RunRecord or xarray.Dataset
        The run's record (:class:`gd_analyze.store.schema.RunRecord`) of a stored
        results, sweep or control dataset, or the dataset (attribute ``gd_analyze_version``).
    version : str
        The version of gd-analyze that writes the report.

    Returns
    -------
    tuple of (str, str)
    """
    computed = _text(_record(ds).gd_analyze_version)
    return ("software", f"gd-analyze {version}" if computed == version else
            f"computed by gd-analyze {computed}, report by gd-analyze {version}")


def command_row(command: object) -> tuple[str, str | None]:
    """("command", ...): the command line as the command line stored it, set as code (in the
    PDF an option such as ``-o`` is not broken across lines).

    Parameters
    ----------
    command : object
        The stored ``command`` attribute, or None where the file has none (an older file).

    Returns
    -------
    tuple of (str, str or None)
        None as the value where there is no command: no row.
    """
    return ("command", None if command is None else code(_text(command)))


def run_row(ds: RunRecord | xr.Dataset, label: str = "computed") -> tuple[str, str]:
    """(label, when): the time the stored results were computed, from the CF ``history``
    attribute without its repeated software version.

    Parameters
    ----------
    ds : RunRecord or xarray.Dataset
        The run's record, or the dataset.
    label : str, optional
        The row's item.

    Returns
    -------
    tuple of (str, str)
    """
    return (label, _text(_record(ds).history).split(" created by ")[0])


def gravity_row(ds: RunRecord | xr.Dataset) -> tuple[str, str]:
    """("gravity and mounting", ...): gravity in the base frame and how the arm is mounted,
    said once from ``gravity`` and the ``mounting_*`` attributes (the sweep stored both, the
    same gravity twice).

    Parameters
    ----------
    ds : RunRecord or xarray.Dataset
        The run's record, or the dataset.

    Returns
    -------
    tuple of (str, str)
    """
    r = _record(ds)

    def vector(value):
        return None if value is None else ", ".join(f"{float(v):g}" for v in np.atleast_1d(value))

    base = r.mounting_gravity_base if r.mounting_gravity_base is not None else r.gravity
    rpy = r.mounting_base_rpy_deg
    return ("gravity and mounting", say(
        "gravity_row", base=vector(base), world=vector(r.mounting_gravity_world), rpy=vector(rpy),
        turned=rpy is not None and bool(np.any(np.asarray(np.atleast_1d(rpy), float) != 0))))


def guarantee_row(label: str, kind: object, statement: object) -> tuple[str, str | None]:
    """(label, "<kind> kind: <statement>"): a model's guarantee as it states it.

    Parameters
    ----------
    label : str
        The row's item.
    kind, statement : object
        The guarantee's kind and statement as stored; None where missing.

    Returns
    -------
    tuple of (str, str or None)
        The value None where no statement is stored.
    """
    return (label, None if statement is None else
            f"{_text(kind)} kind: " + _scope(_text(statement)))


def _record(ds):
    """The run's record, or that of a dataset."""
    return ds if isinstance(ds, RunRecord) else RunRecord.from_attrs(ds.attrs)
