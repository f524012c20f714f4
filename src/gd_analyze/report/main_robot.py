"""The main report's robot section: the robot's geometry (DH rows, or a URDF arm's joint
placements and axes), its links, its drives, the trajectory, each joint's range of motion and
its effort limits, read from the typed results (:class:`gd_analyze.store.results_view.Results`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..ranking.ranking import joint_motion_units
from ..store.results_view import Results
from .common import attr_text as _text
from .common import count, given
from .common import fmt as _fmt
from .common import fmt_column as _column
from .common import share as share_text
from .common import table as _table
from .effort import effort_rows
from .markup import element, tau

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["robot_section", "alike_joints", "ALIKE"]

_DERIVATIVES = {
    "file": "read from the file (its velocity and acceleration columns)",
    "cubic-spline": "derived from q by a not-a-knot cubic spline",
    "quintic": "analytic derivatives of a planned quintic motion",
    "arrays": "given as arrays (the Python API)",
}


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
    traj = results.trajectory
    series = [np.asarray(v, float) for v in traj.motion]
    n = prismatic.size

    def alike(i, j):
        if prismatic[i] != prismatic[j]:
            return False
        for x in series:
            scale = max(np.max(np.abs(x[:, i])), np.max(np.abs(x[:, j])))
            if np.max(np.abs(x[:, i] - x[:, j])) > ALIKE * scale:
                return False
        return True

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
    return _table(["item", "value"], rows, widths=[1.2, 3.4])


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
    N = t.size
    labels = [r.label for r in results.ranking.rows]
    robot_kv = _kv([
        ("name", robot_name), ("description", _text(robot.description)),
        ("reference", _text(robot.reference)), ("robot file", _text(robot.source)),
        ("robot file SHA-256", _text(robot.sha256)), ("joints n", str(n)),
        ("gravity g [m/s\u00b2]", _text(robot.gravity)),
    ])
    com = robot.link_com
    inertia = robot.link_inertia
    dh, placements = _robot_geometry(results)
    link = _table(
        ["joint", "mass [kg]", "com x [m]", "com y [m]", "com z [m]", "Ixx [kg m\u00b2]",
         "Iyy [kg m\u00b2]", "Izz [kg m\u00b2]"],
        _rows(range(1, n + 1), robot.link_mass, *com.T,
              *(inertia[:, i, i] for i in range(3))),
        align=["left"] + ["right"] * 7, widths=[0.7] + [1] * 7)
    drives = _drives_context(results, labels)
    derivatives = traj.derivatives
    sha_in = _text(traj.input_sha256, "")
    traj_kv = _kv([
        ("source file", _text(traj.input_file)), ("path", _text(traj.input_path)),
        ("SHA-256", sha_in or "\u2014 (not read from a file)"),
        ("set points N", count(N)),
        ("duration [s]",
         f"{_fmt(t[-1] - t[0], 6)}  (t = {_fmt(t[0], 6)} \u2026 {_fmt(t[-1], 6)})"),
        ("derivatives", f"{derivatives}: {_DERIVATIVES.get(derivatives, 'as recorded')}"
         if derivatives else "\u2014"),
    ])
    prismatic = np.array(results.prismatic)
    # the units of Fig. 1 (joint_motion_units shown): deg, or mm for a prismatic joint
    scale = np.where(prismatic, 1000.0, np.degrees(1.0))
    q, qd, qdd = (v * scale for v in traj.motion)
    joints = _table(
        ["joint", "type", "q min", "q max", "peak |q\u0307|", "peak |q\u0308|", "units"],
        [[row[0], "prismatic" if prismatic[k] else "revolute", *row[1:],
          ", ".join(joint_motion_units(bool(prismatic[k]), shown=True))]
         for k, row in enumerate(_rows(range(1, n + 1), q.min(axis=0), q.max(axis=0),
                                       np.abs(qd).max(axis=0), np.abs(qdd).max(axis=0)))],
        align=["left", "left"] + ["right"] * 4 + ["left"], widths=[0.6, 0.9, 1, 1, 1, 1, 1.5])

    efforts = effort_rows(results)
    effort = _table(
        ["joint", "peak |\u03c4|", "effort limit", "peak / limit", "flag", "units"],
        [[*row, flag, unit] for row, (*_, flag, unit) in zip(
            _rows([e[0] for e in efforts], [e[1] for e in efforts], [e[2] for e in efforts],
                  ([e[3] for e in efforts], 3)), efforts)],
        align=["left", "right", "right", "right", "left", "left"],
        widths=[0.6, 1, 1, 1, 1, 0.6]) if efforts else None
    return {"robot_kv": robot_kv, "dh": dh, "placements": placements, "link": link,
            "traj_kv": traj_kv, "joints": joints, "effort": effort,
            "effort_text": _effort_text(efforts), "drives": drives}


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
        [[*row, share_text(float(share[diag[k]])) if diag[k] is not None else "—",
          ("kg, N s/m, N" + ", N" * has_offset + ", N") if pris[k] else
          ("kg m², N m s/rad, N m" + ", N m" * has_offset + ", N m")]
         for k, row in enumerate(_rows(range(1, n + 1), arm, fv, fc, *extra, peak_f))],
        align=["left"] + ["right"] * (5 + has_offset) + ["left"],
        widths=[0.5, 0.9, 0.9, 0.9, *([0.9] if has_offset else []), 0.9, 1, 2])
    note = ("Drives: the armature (rotor inertia × gear ratio²) adds diag(armature) "
            f"to D, a third part {element('D', '', 'arm')} beside {element('D', '', 'tran')} "
            f"and {element('D', '', 'rot')}, counted on the rotational side of the "
            f"translational share (Sec. 4); friction {tau('f')} = viscous "
            "· q̇ + Coulomb · sign(q̇)" + (" + offset" if has_offset else "")
            + " adds to τ. The simplified model keeps both whole.")
    return {"table": table, "note": note}


def _effort_text(rows):
    """The sentence over the effort-limit table: which joints exceed their limit, if any."""
    if not rows:
        return ""
    over = [str(r[0]) for r in rows if r.exceeded]
    verdict = (f"joint{'s' if len(over) > 1 else ''} {', '.join(over)} exceed"
               f"{'' if len(over) > 1 else 's'} {'their' if len(over) > 1 else 'its'} limit "
               "along this trajectory" if over else "every joint stays within its limit")
    return ("Peak |\u03c4| of the full model against the effort limits the robot gives "
            "(the effort attribute of a URDF joint's limit, or the maximum joint torques and "
            f"forces of a robot file): {verdict}.")
