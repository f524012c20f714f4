"""Trajectories and recordings: reading and writing their CSV files (planning is in :mod:`gd_analyze.trajectory.planning`).

A trajectory CSV has a header ``t,q1..qn,qd1..qdn,qdd1..qddn`` in [s], [rad], [rad/s] and
[rad/s^2], one set point per row. A file with only ``t,q1..qn`` is accepted too: its velocities
and accelerations then come from a not-a-knot cubic spline through the positions, and the
trajectory records that (``derivatives = "cubic-spline"``). Given the robot, :func:`unwrapped`
undoes a continuous joint's wraps at +-pi first.

Rows are counted as a spreadsheet counts them: the header is row 1, the first set point row 2.

Recordings for identification (:class:`Recording`, :func:`read_recording`) hold joint positions
and measured torques against time. A recording CSV has a header ``t,q1..qn,tau1..taun`` with
optional ``qd1..qdn`` and ``qdd1..qddn`` (the columns in any order), in [s], [rad or m],
[N m or N], [rad/s or m/s], [rad/s^2 or m/s^2]. With motor currents (``--current``) the torque columns hold currents [A]
(named ``tau1..taun`` or ``i1..in``) and the drive gains K turn them into torque, tau = K i.
``time`` names the time column too, ``dq``, ``ddq`` velocities and accelerations, and a kind
numbered from 0 (``q0..``) counts from joint 1, with a note. Given the chain's joint names, the columns may name the
joints instead, as a ROS ``joint_states`` export does (``<joint>_position``, ``_velocity``,
``_acceleration``, ``_effort``, a leading ``"- "`` ignored; other joints' columns ignored with
a note), or be ROS 1's ``rostopic echo -p`` of a JointState topic (``%time``,
``field.header.stamp`` in ns, ``field.name<k>``, ``field.position<k>``...) or PlotJuggler's CSV
export of one (``__time`` [s], ``/<topic>/<joint>/position``...), or a UR RTDE log
(``timestamp``, ``actual_q_0``.., ``actual_qd_0``.., ``actual_current_as_torque_0``.. or with
``--current`` ``actual_current_0``..), and ``A.csv+B.csv`` joins files on one clock into one
recording (files of one kind each, ``q.csv+dq.csv+current_mA.csv``, may name the joints bare:
the kind from the file's name).

Real logs have irregular clocks, out-of-order and repeated time stamps: :func:`read_recording`
sorts the rows by time (stable) and keeps the first of rows with the same time stamp, and says
so in :attr:`Recording.notes`. Everything else that cannot be used (a cell that is not a plain
finite number, a missing or unknown column, a ragged row, fewer than 10 distinct time stamps,
a time going back by more than :data:`BACK_STEPS` median steps: a recording appended to
another, which sorting would interleave) is refused with the file, the row (header = row 1)
and the column.
"""

from __future__ import annotations

import collections
import csv
import hashlib
import io
import math
import os
import re
import warnings
from collections.abc import Callable, Iterable, Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, BinaryIO

import numpy as np

from .. import errors
from ..errors import InputError, InputNote, InputWarning, check_flags, expect, one_line, path_text
from ..files import atomic_path
from ..model.limits import LIMITS, exact_text, first_beyond, real_values

if TYPE_CHECKING:                       # for the type hints only
    from numpy.typing import ArrayLike

    from ..model.robot import Robot

__all__ = ["Trajectory", "read_trajectory", "write_trajectory", "write_trajectory_chunks",
           "trajectory_columns", "trajectory_from_arrays", "as_trajectory", "parse_number",
           "JointLimitWarning", "check_joint_limits", "unwrapped", "check_magnitudes", "checked_arrays",
           "FAST_PARSE_BYTES", "MAX_CELL", "streamed_values", "Recording", "read_recording",
           "recording_from_arrays", "MIN_SAMPLES", "BACK_STEPS"]

#: Files larger than this [bytes] are parsed by pandas first when they are regular; the
#: cell-by-cell parser runs on smaller ones, on irregular ones, and to locate an error.
FAST_PARSE_BYTES = 1 << 18


class JointLimitWarning(UserWarning):
    """A position along the trajectory lies outside a joint's limits."""


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A joint trajectory sampled at N set points.

    Attributes
    ----------
    t : ndarray, shape (N,)
        Time of each set point, strictly increasing [s].
    q : ndarray, shape (N, n)
        Joint positions [rad].
    qd : ndarray, shape (N, n)
        Joint velocities [rad/s].
    qdd : ndarray, shape (N, n)
        Joint accelerations [rad/s^2].
    derivatives : str
        ``"file"`` if qd and qdd were read, ``"cubic-spline"`` if they were derived from q,
        ``"quintic"`` if planned, ``"fourier"`` if an excitation
        (:func:`gd_analyze.trajectory.excitation.plan_excitation`), ``"arrays"`` if given as arrays
        (:func:`trajectory_from_arrays`).
    source : str
        The file read, or a description of how the trajectory was made.
    sha256 : str
        SHA-256 of the file's bytes ("" for a trajectory not read from a file).
    rows : ndarray of int, shape (N,), or None
        The file's row of each set point where it is not the set point's index + 2 (a
        recording, sorted by time).
    columns : tuple of str
        The file's name of each joint's position column where it is not ``q<j>`` (a
        recording naming the joints), else empty.
    """

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    derivatives: str = "file"
    source: str = ""
    sha256: str = ""
    rows: np.ndarray | None = None
    columns: tuple = ()

    @property
    def n_setpoints(self) -> int:
        """int: the number of set points N."""
        return int(self.t.shape[0])


def trajectory_columns(n: int, derivatives: bool = True) -> list[str]:
    """Column names of a trajectory CSV for n joints.

    Parameters
    ----------
    n : int
        Number of joints.
    derivatives : bool, optional
        Include ``qd1..qdn`` and ``qdd1..qddn``.

    Returns
    -------
    list of str
        ``["t", "q1", ..., "qn", "qd1", ..., "qddn"]``.
    """
    kinds = ("q", "qd", "qdd") if derivatives else ("q",)
    return ["t"] + [f"{kind}{i}" for kind in kinds for i in range(1, n + 1)]


def _parse_header(header, path):
    names = [c.strip() for c in header]
    if not names or names[0] != "t":
        raise InputError(f"the header must start with 't', got {names[0]!r}" if names else
                         "empty header", path, row=1, column=names[0] if names else None)
    n = sum(c.startswith("q") and c[1:].isdigit() for c in names)
    if n == 0:
        raise InputError("no joint position columns q1..qn in the header", path, row=1)
    expected = trajectory_columns(n, len(names) > n + 1)     # with derivatives, or without
    if names == expected:
        return names, n
    # Name the first column that differs from the expected layout.
    for k, got in enumerate(names):         # an empty name (a trailing comma) by number only
        where = f"{k + 1} ({got})" if got else str(k + 1)
        if k < len(expected) and got != expected[k]:
            raise InputError(f"expected column {expected[k]!r}, got {got!r}", path, row=1,
                             column=where)
        if k == len(expected):
            raise InputError(f"extra column {got!r} (expected t,q1..q{n}[,qd1..qd{n},"
                             f"qdd1..qdd{n}])", path, row=1, column=where)
    missing = expected[len(names)]
    raise InputError(f"missing column {missing!r} (expected t,q1..q{n},qd1..qd{n},qdd1..qdd{n})",
                     path, row=1, column=missing)


def read_trajectory(path: str | os.PathLike[str], n_joints: int | None = None,
                    joint_names: Sequence[str] | None = None) -> Trajectory:
    """Read and validate a trajectory CSV file.

    One reader for every size: a file is parsed by pandas when it is regular (every line has
    the header's number of fields, only the bytes of plain numbers, no quotes; LF or CRLF, blank
    lines (empty, or spaces and tabs) only at its end), and cell by cell otherwise, or whenever pandas' result fails a
    check; the cell-by-cell parse then names the first faulty row and column. Both accept exactly the same files and give the same values.
    pandas reads a large file a piece at a time, so its bytes are never held whole: the memory
    is that of the values (and of the whole file's bytes only when it is irregular).

    Parameters
    ----------
    path : str or os.PathLike
        The CSV file: header ``t,q1..qn,qd1..qdn,qdd1..qddn`` or ``t,q1..qn`` in [s], [rad],
        [rad/s], [rad/s^2]. A UTF-8 byte-order mark (as Excel writes it) is stripped, with an
        :class:`~gd_analyze.errors.InputNote`. A recording (torque columns ``tau1..taun``, or
        columns naming the joints, ``<joint>_position`` and ``<joint>_effort``:
        :func:`read_recording`) is read as one, its torques ignored, with an InputNote.
    n_joints : int, optional
        The robot's number of joints n; the file must have as many.
    joint_names : sequence of str, optional
        The robot's joint names (:meth:`~gd_analyze.model.robot.Robot.joint_names`), by which
        a recording's columns may name the joints.

    Returns
    -------
    Trajectory
        With ``derivatives = "cubic-spline"`` when the file has positions only.

    Raises
    ------
    InputError
        If the file is missing, not a regular file, unreadable or empty; has no header, missing
        or extra columns, or a ragged row; has a cell that is not a plain decimal number
        (``[+-]digits[.digits][e[+-]digits]``, ASCII digits only: no ``1_0``, no full-width
        digits, no ``inf`` or ``nan``); has a value beyond the limits of
        :data:`gd_analyze.model.limits.LIMITS`; if time is not strictly increasing; if there
        are fewer than 2 set points; or if the joint count differs from n_joints. The message
        names the file, the row (header = row 1) and the column. Before the file is opened: if
        ``path`` is not a str or os.PathLike, or ``n_joints`` not a whole number >= 1 (the
        message names the argument).
    """
    path = _csv_path(path, n_joints)
    with open(path, "rb") if os.path.isfile(path) else io.BytesIO() as fh:   # else refused below
        recorded = re.search(rb"^(?:\xef\xbb\xbf)?(%time,|" + _JUGGLED.pattern + rb"|"
                             + _RTDE_HEAD.pattern + rb")|,[ \t]*tau[0-9]|_(position|effort)"
                             rb"[ \t]*(,|\r?\n|$)",
                             fh.readline(HEADER_BYTES)) is not None
    if recorded:        # a recording for identify (read_recording): its torques are no set point's
        with warnings.catch_warnings():     # its notes are said once, from rec.notes below
            warnings.simplefilter("ignore", InputNote)
            rec = read_recording(path, n_joints, joint_names=joint_names)
        qd, qdd = (_spline(rec.t, rec.q, path, lambda k: int(np.asarray(rec.rows)[k]),
                           rec.columns.get("q"))
                   if rec.qd is None or rec.qdd is None else (rec.qd, rec.qdd))
        given = qd is rec.qd
        for note in (*rec.notes, f"{path}: a recording: its torques {rec.column('tau', 0)}.."
                     f"{rec.column('tau', rec.n - 1)} are ignored, its set points are t, q"
                     + (", qd, qdd" if given else
                     " (qd, qdd by a cubic spline through them, which amplifies their noise)")):
            warnings.warn(note, InputNote, stacklevel=2)
        return Trajectory(t=rec.t, q=rec.q, qd=qd, qdd=qdd, source=path, sha256=rec.sha256,
                          derivatives="file" if given else "cubic-spline", rows=rec.rows,
                          columns=rec.columns.get("q", ()))

    def checked(cells, row=1):       # streamed: an InputError falls back to the cells, which say it
        if all(_FLOAT.fullmatch(c.strip(" \t")) for c in cells):
            raise InputError("no header (expected t,q1..qn[,qd1..qdn,qdd1..qddn])", path, row=row)
        names, n = _parse_header(cells, path)
        _same_joints(n, n_joints, "file has", path, row=row)
        return names

    values, names, rows, sha256 = _read_csv(
        path, checked, lambda raw: _validated_values(raw, path, checked, least=2))
    n = _parse_header(names, path)[1]
    t = values[:, 0]
    _increasing(t, path, rows)
    kinds = ("q", "qd", "qdd")[:(len(names) - 1) // n]       # with derivatives, or without
    check_magnitudes(values, names, {"t": [0], **{k: list(range(1 + i * n, 1 + (i + 1) * n))
                                                 for i, k in enumerate(kinds)}}, path, rows)
    q = values[:, 1:n + 1]
    how = "file" if len(names) == 3 * n + 1 else "cubic-spline"
    qd, qdd = ((values[:, n + 1:2 * n + 1], values[:, 2 * n + 1:]) if how == "file"
               else _spline(t, q, path, row_of=lambda k: k + 2))
    return Trajectory(t=t, q=q, qd=qd, qdd=qdd, derivatives=how, source=path, sha256=sha256)


def _csv_path(path: Any, n_joints: Any) -> str:
    """The name of a CSV file to read, as text: the arguments of :func:`read_trajectory` and
    :func:`read_recording` checked, InputError naming the
    argument where ``path`` is not a str or os.PathLike, or ``n_joints`` (when given) not a
    whole number >= 1."""
    path = path_text(path, "CSV file")
    whole = isinstance(n_joints, (int, np.integer)) and not isinstance(n_joints, bool)
    if n_joints is not None and not (whole and n_joints >= 1):
        raise InputError(f"n_joints: a whole number >= 1, not {type(n_joints).__name__} "
                         f"{str(n_joints)[:40]!r}")
    return path


def _spline(t, q, path, row_of, columns=None):
    """qd and qdd of a not-a-knot cubic spline through the positions, within LIMITS (an
    InputError naming the row ``row_of`` gives and the column of ``columns``, else ``q<j>``)."""
    from scipy.interpolate import CubicSpline

    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore")     # SciPy's "ill-conditioned matrix": LIMITS judge
        try:
            spline = CubicSpline(t, q, axis=0, bc_type="not-a-knot")
            qd, qdd = spline(t, 1), spline(t, 2)
        except ValueError:                  # a slope beyond a float: a step of 5e-324 s
            qd = qdd = np.vstack([0 * q[:1], np.diff(q, axis=0) / np.diff(t)[:, None]])
    for name, arr in (("qd", qd), ("qdd", qdd)):
        bad = first_beyond(arr, LIMITS[name])
        if bad is not None:
            raise InputError(f"the {name} derived by the cubic spline exceeds "
                             f"{LIMITS[name]:g} in magnitude (time steps too short for "
                             f"the positions?)", path, row=row_of(bad[0]),
                             column=columns[bad[1]] if columns else f"q{bad[1] + 1}")
    return qd, qdd


#: What errors call a trajectory given as arrays.
ARRAYS = "trajectory arrays"


def checked_arrays(named: Mapping[str, Any], source: str, limits: Mapping[str, float],
                   least: int, what: str) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Arrays of the Python API as floats, checked: real numbers, shapes, magnitudes.

    Parameters
    ----------
    named : mapping of str to array_like or None
        ``t`` first, shape (N,) [s], then ``q`` and the others, each shape (N, n) (None: not
        given, left out).
    source : str
        What the messages call the arrays.
    limits : mapping of str to float
        The largest magnitude of each array (:data:`gd_analyze.model.limits.LIMITS`).
    least : int
        The fewest samples N.
    what : str
        What a sample is called in the messages (e.g. ``"set point"``).

    Returns
    -------
    t : ndarray, shape (N,)
    arrays : dict of str to ndarray, each shape (N, n)

    Raises
    ------
    InputError
        One line naming the array: not real numbers (text, complex, None for ``t`` or
        ``q``), a wrong shape, n = 0, N below ``least``, a value not finite or beyond its
        limit.
    """
    arrays: dict[str, np.ndarray] = {}
    for name, v in named.items():
        if v is None and name not in ("t", "q"):
            continue
        try:
            arrays[name] = np.array(real_values(name, v), dtype=float)
        except InputError as exc:       # complex, text...: one line naming the array
            raise InputError(exc.message, source, column=name) from None
        except (TypeError, ValueError) as exc:
            raise InputError(f"not numeric arrays: {exc}", source, column=name) from None
    t = arrays.pop("t")
    if t.ndim != 1 or t.size < least:
        raise InputError(f"t must have shape (N,) with N >= {least}, got {t.shape}", source,
                         column="t")
    n = arrays["q"].shape[1] if arrays["q"].ndim == 2 else -1
    for name, x in arrays.items():
        if x.ndim != 2 or x.shape != (t.size, n) or n < 1:
            raise InputError(f"{name} must have shape (N, n) = ({t.size}, n), got {x.shape}",
                             source, column=name)
    for name, x in (("t", t), *arrays.items()):
        bad = first_beyond(x, limits[name])
        if bad is not None:
            raise InputError(f"{float(x[bad]):g} at {what} {bad[0]} is not finite or beyond "
                             f"the supported magnitude {limits[name]:g} of {name}", source,
                             column=name)
    return t, arrays


def trajectory_from_arrays(t: ArrayLike, q: ArrayLike, qd: ArrayLike | None = None,
                           qdd: ArrayLike | None = None, n_joints: int | None = None
                           ) -> Trajectory:
    """A trajectory from arrays, checked as a trajectory file is.

    Parameters
    ----------
    t : array_like, shape (N,)
        Time of each set point, strictly increasing [s]; N >= 2.
    q : array_like, shape (N, n)
        Joint positions [rad; m for a prismatic joint].
    qd, qdd : array_like, shape (N, n), optional
        Joint velocities [rad/s] and accelerations [rad/s^2]; both or neither: without them,
        from a not-a-knot cubic spline through q, as for a file with positions only.
    n_joints : int, optional
        The robot's number of joints n.

    Returns
    -------
    Trajectory
        ``derivatives`` ``"arrays"`` (or ``"cubic-spline"``), ``source`` ``"trajectory
        arrays"``, ``sha256`` "" (not read from a file).

    Raises
    ------
    InputError
        If a shape is wrong, only one of qd and qdd is given, there are fewer than 2 set
        points, time is not strictly increasing, a value is not finite or beyond
        :data:`gd_analyze.model.limits.LIMITS`, or the joint count is not n_joints. The
        message names the array and the set point (from 0).

    Examples
    --------
    >>> traj = trajectory_from_arrays([0.0, 0.5, 1.0], np.zeros((3, 2)))
    >>> traj.derivatives, traj.qdd.shape
    ('cubic-spline', (3, 2))
    """
    if (qd is None) != (qdd is None):
        raise InputError("give both qd and qdd, or neither (then a cubic spline through q)",
                         ARRAYS)
    t, arrays = checked_arrays({"t": t, "q": q, "qd": qd, "qdd": qdd}, ARRAYS, LIMITS, 2,
                               "set point")
    _same_joints(arrays["q"].shape[1], n_joints, "arrays have", ARRAYS)
    _increasing(t, ARRAYS)
    how = "cubic-spline" if qd is None else "arrays"
    qd, qdd = (_spline(t, arrays["q"], ARRAYS, row_of=lambda k: None) if qd is None
               else (arrays["qd"], arrays["qdd"]))
    return Trajectory(t=t, q=arrays["q"], qd=qd, qdd=qdd,  # type: ignore[arg-type]  # ndarrays here
                      derivatives=how, source=ARRAYS)


def _increasing(t, path, rows=None):
    """An InputError at the first time not at least ``LIMITS["min_step"]`` after the one
    before, naming its row of ``rows`` (of a file), else its set point."""
    step = LIMITS["min_step"]
    for k in np.flatnonzero(np.diff(t) < step)[:1] + 1:
        raise InputError(f"time not strictly increasing, by {step:g} s or more ({t[k]}" + (
            f" at set point {k}" if rows is None else "") + f" after {t[k - 1]})", path,
            row=None if rows is None else int(rows[k]), column="t")


def as_trajectory(value: Trajectory | str | os.PathLike[str] | Mapping[str, Any] | Sequence[Any],
                  n_joints: int | None = None,
                  joint_names: Sequence[str] | None = None) -> Trajectory:
    """A trajectory from what a notebook holds: a Trajectory, a CSV file, or arrays.

    Parameters
    ----------
    value : Trajectory, str, os.PathLike, mapping or sequence
        A :class:`Trajectory`; a trajectory CSV file (:func:`read_trajectory`); a mapping
        with keys ``t``, ``q`` and optionally ``qd``, ``qdd``; or a sequence ``(t, q)`` or
        ``(t, q, qd, qdd)`` (:func:`trajectory_from_arrays`).
    n_joints : int, optional
        The robot's number of joints n.
    joint_names : sequence of str, optional
        The robot's joint names, by which a recording file's columns may name the joints.

    Returns
    -------
    Trajectory

    Raises
    ------
    InputError
        If the value is none of these, or fails the checks of :func:`read_trajectory` or
        :func:`trajectory_from_arrays`, or has not n_joints joints.

    Examples
    --------
    >>> as_trajectory({"t": [0, 1], "q": [[0], [1]], "qd": [[1], [1]], "qdd": [[0], [0]]}).n_setpoints
    2
    """
    if isinstance(value, Trajectory):
        _same_joints(value.q.shape[1], n_joints, "trajectory has", value.source or ARRAYS)
        return value
    if isinstance(value, (str, os.PathLike)):
        return read_trajectory(value, n_joints=n_joints, joint_names=joint_names)
    if isinstance(value, Mapping):
        unknown = sorted(set(map(str, value)) - {"t", "q", "qd", "qdd"})
        if unknown or "t" not in value or "q" not in value:
            raise InputError("a trajectory mapping has the keys t, q and optionally qd, qdd"
                             + (f" (unknown: {', '.join(unknown)})" if unknown else ""), ARRAYS)
        return trajectory_from_arrays(**value, n_joints=n_joints)  # type: ignore[misc]  # keys checked
    if isinstance(value, (tuple, list)) and len(value) in (2, 4):
        return trajectory_from_arrays(*value, n_joints=n_joints)  # type: ignore[misc]  # length checked
    of = f" of {len(value)}" if isinstance(value, (tuple, list)) else ""    # 2 or 4 are read
    raise InputError("a trajectory is a Trajectory, a CSV file, a mapping of t, q[, qd, qdd] "
                     f"or a sequence (t, q[, qd, qdd]), not a {type(value).__name__}{of}", ARRAYS)


_BOM = b"\xef\xbb\xbf"
#: The plain float grammar of a cell (after stripping spaces and tabs).
_FLOAT = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
#: A whole number of the command line (counts, seeds).
_INTEGER = re.compile(r"[+-]?[0-9]+")
#: Bytes a regular file's body may hold to be parsed by pandas.
_PLAIN_BYTES = b"0123456789.eE+-, \t\r\n"
#: Longest cell accepted [characters].
MAX_CELL = 1000


def _numbered_rows(raw, path, long_cell=False, delimiter=","):
    """The rows of a CSV file's bytes that are not blank, (row number, cells) each; an
    InputError for bytes that are not UTF-8 text without a NUL byte (naming the row and the
    byte that is not UTF-8), not CSV, or no row
    (``long_cell``: a cell beyond the csv module's field limit is named as such)."""
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(f"not a UTF-8 text file (byte 0x{raw[exc.start]:02x})", path,
                         row=raw.count(b"\n", 0, exc.start) + 1) from None
    if "\x00" in text:
        raise InputError("not a text file (holds a NUL byte)", path)
    try:
        rows = list(csv.reader(io.StringIO(text, newline=""), delimiter=delimiter))
    except csv.Error as exc:
        if long_cell and "field larger than field limit" in str(exc):
            raise InputError(f"a cell longer than {csv.field_size_limit()} characters: not a "
                             f"trajectory CSV file", path) from None
        raise InputError(f"not a CSV file: {exc}", path) from None
    # Blank lines (including a trailing one) are not set points.
    numbered = [(k + 1, r) for k, r in enumerate(rows) if any(c.strip() for c in r)]
    if not numbered:
        raise InputError("empty file", path)
    return numbered


def check_magnitudes(values: np.ndarray, names: list[str], columns: Mapping[str, list[int]],
                     path: str, rows: np.ndarray, limits: Mapping[str, float] = LIMITS) -> None:
    """Raise for the first value of a CSV file beyond its kind's supported magnitude.

    Parameters
    ----------
    values : ndarray, shape (N, m)
        The file's numbers.
    names : list of str, length m
        The columns' names.
    columns : mapping of str to list of int
        The columns of each kind (``"t"``, ``"q"``...), indices into ``names``.
    path : str
        The file.
    rows : ndarray of int, shape (N,)
        The file's row of each line of ``values``.
    limits : mapping of str to float, optional
        The largest magnitude of each kind (default :data:`gd_analyze.model.limits.LIMITS`).

    Raises
    ------
    InputError
        Naming the file, the row and the column.
    """
    for kind, idx in columns.items():
        bad = first_beyond(values[:, idx], limits[kind])
        if bad is not None:
            j = idx[bad[1]]
            raise InputError(f"{exact_text(values[bad[0], j])} is beyond the supported magnitude "
                             f"{limits[kind]:g} of {kind} (see docs/limits-and-safety.md)", path,
                             row=int(rows[bad[0]]), column=names[j])


def _read_csv(path, header, cells):
    """(values, names, row numbers, sha256) of a CSV file of numbers: a large, regular one
    streamed by :func:`streamed_values` (``header`` as there), any other read whole and parsed
    by ``cells`` (its bytes, without a byte-order mark, to (values, names, row numbers)); an
    InputNote where a UTF-8 byte-order mark was stripped; an InputError if the file is not a
    readable regular file."""
    errors.regular_file(path, "a CSV file")
    try:
        with open(path, "rb") as fh:
            if fh.read(len(_BOM)) == _BOM:
                warnings.warn(f"{path}: stripped the UTF-8 byte-order mark at the start of the "
                              "file", InputNote, stacklevel=3)
            fh.seek(0)
            if (os.fstat(fh.fileno()).st_size > FAST_PARSE_BYTES
                    and (parsed := streamed_values(fh, path, header)) is not None):
                values, names, sha256 = parsed
                return values, names, np.arange(2, values.shape[0] + 2), sha256
            fh.seek(0)
            raw = fh.read()
    except OSError as exc:
        raise InputError(f"cannot read: {exc.strerror or exc}", path) from None
    return (*cells(raw.removeprefix(_BOM)), hashlib.sha256(raw).hexdigest())  # of the BOM too


def streamed_values(fh: BinaryIO, path: str, header: Callable[[list[str]], list[str] | None]
                    ) -> tuple[np.ndarray, list[str], str] | None:
    """A large CSV file of plain numbers parsed by pandas, streamed a piece at a time.

    Parameters
    ----------
    fh : binary file
        The file, at its start (a UTF-8 byte-order mark is skipped).
    path : str
        Its name, for messages.
    header : callable
        Takes the header's fields (str, split at commas) and gives the column names, or None
        (or raises :class:`~gd_analyze.errors.InputError`) to refuse the file.

    Returns
    -------
    (values, names, sha256) or None
        values, shape (N, len(names)): the N rows after the header, every one finite; sha256:
        that of the file's bytes, BOM and the blank lines that end it (empty, or spaces and
        tabs) included (those are no rows). None if anything is off (a header refused or longer than :data:`HEADER_BYTES`, a
        quote, a byte other than those of plain numbers, a blank line before the last row, a
        line with other fields than the header, a lone carriage return, a value pandas cannot
        parse or that is not finite, fewer than 2 rows): then the caller parses the whole file
        cell by cell, which gives the answer or the exact error.

    Raises
    ------
    OSError
        If the file cannot be read.

    Notes
    -----
    Two passes over the file (after a look at its last 4 KiB for blank lines that end it): the
    first counts its lines (the values' rows), the second hashes, checks and parses each piece
    of about :data:`PARSE_PIECE` bytes (whole lines), on :data:`PARSE_THREADS` threads (pandas'
    parser releases the GIL). At no time are the file's bytes held whole: the memory is the
    values and the pieces in flight, whatever the file's size. A file that changes between the
    passes parses to another number of rows (None). The values are correctly rounded, as
    Python's ``float`` parses each cell.

    Examples
    --------
    >>> import io
    >>> values, names, _ = streamed_values(io.BytesIO(b"t,q1\\n0,1.5\\n0.5,-2e-3\\n"), "f.csv",
    ...                                    lambda fields: fields)
    >>> values.tolist(), names
    ([[0.0, 1.5], [0.5, -0.002]], ['t', 'q1'])
    >>> streamed_values(io.BytesIO(b"t,q1\\n0,1.5\\n0.5,nan\\n"), "f.csv", lambda f: f) is None
    True
    >>> streamed_values(io.BytesIO(b"t,q1\\r\\n0,1\\r\\n1,2\\r\\n\\r\\n"), "f.csv", lambda f: f)[0].shape
    (2, 2)
    """
    import pandas as pd

    # correctly rounded floats, as Python's float() parses them: pandas before 3.0 parses with
    # its own, not always correctly rounded, routine by default
    exact = {} if int(pd.__version__.split(".")[0]) >= 3 else {"float_precision": "round_trip"}
    digest = hashlib.sha256()
    head = fh.read(HEADER_BYTES)
    head = head[:head.find(b"\n") + 1]
    if not head:
        return None
    fh.seek(len(head))
    digest.update(head)
    head = head.removeprefix(_BOM)
    if b'"' in head or head.count(b"\r") != head.count(b"\r\n"):
        return None
    try:
        names = header(head.decode("utf-8").rstrip("\r\n").split(","))
    except (UnicodeDecodeError, InputError):
        return None
    # the blank lines that end the file (within its last 4 KiB: empty, or spaces and tabs)
    # are no rows: not parsed; the last row is parsed to its newline
    start = fh.tell()
    fh.seek(max(start, fh.seek(0, os.SEEK_END) - 4096))
    last = fh.read() + b"\n"
    end = fh.tell() + 2 - len(last) + last.find(b"\n", len(last.rstrip(b" \t\r\n")))
    fh.seek(start)
    if names is None or (lines := _line_count(fh, end)) < 2:
        return None
    fields = len(names)

    def parse(piece):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            frame = pd.read_csv(_PieceReader(memoryview(piece)), header=None,
                                names=list(range(fields)), dtype=float, engine="c",
                                skipinitialspace=True, skip_blank_lines=False, index_col=False,
                                **exact)
        return frame.to_numpy()

    values = np.empty((lines, fields))
    row = 0
    pending: collections.deque = collections.deque()
    pool = ThreadPoolExecutor(max_workers=PARSE_THREADS, thread_name_prefix="gd-csv-parse")
    try:
        for piece in _pieces(fh, end):
            digest.update(piece)
            # only the bytes of plain numbers; every line with the header's fields: pandas
            # then refuses a line with more fields than the first, the shape check a first
            # line with more fields than the header, and the finite check (NaN fill) a line
            # with fewer, which any surplus elsewhere implies
            if (piece.translate(None, _PLAIN_BYTES)
                    or (_byte_count(piece, b"\r") and
                        _byte_count(piece, b"\r") != piece.count(b"\r\n"))
                    or _byte_count(piece, b",") != (fields - 1) * (
                        _byte_count(piece, b"\n") + (not piece.endswith(b"\n")))):
                return None
            pending.append(pool.submit(parse, piece))
            del piece
            while len(pending) > PARSE_THREADS or (pending and pending[0].done()):
                row = _put_piece(values, row, pending.popleft().result())
        while pending:
            row = _put_piece(values, row, pending.popleft().result())
    except (ValueError, pd.errors.ParserError):
        return None
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
    if row != lines or not np.isfinite(values).all():
        return None
    digest.update(fh.read())      # the blank lines at the end
    return values, names, digest.hexdigest()


#: Longest header a file parsed by pandas may have [bytes] (a longer one is read whole).
HEADER_BYTES = 1 << 16


def _put_piece(values, row, piece):
    """Copy a parsed piece into ``values`` at ``row``; the next row. ValueError if it does not
    fit (a field more, or more lines than counted)."""
    if piece.shape[1] != values.shape[1] or row + piece.shape[0] > values.shape[0]:
        raise ValueError("the piece does not fit")
    values[row:row + piece.shape[0]] = piece
    return row + piece.shape[0]


def _line_count(fh, end):
    """The lines from ``fh``'s position to byte ``end`` (the last may lack its newline),
    counted block by block; ``fh`` is put back where it was."""
    at, lines, last = fh.tell(), 0, b"\n"
    while block := fh.read(min(PARSE_PIECE, end - fh.tell())):
        lines += _byte_count(block, b"\n")
        last = block[-1:]
    fh.seek(at)
    return lines + (last != b"\n")


def _pieces(fh, end):
    """The file up to byte ``end`` in pieces of whole lines, each about :data:`PARSE_PIECE`
    bytes (longer where a line is); the last piece may lack its final newline. ValueError if a
    line is longer than :data:`HEADER_BYTES` plus a piece (no regular file has one)."""
    carry = b""
    while block := fh.read(min(PARSE_PIECE, end - fh.tell())):
        data = carry + block
        cut = data.rfind(b"\n") + 1
        if cut == 0:
            if len(data) > HEADER_BYTES + PARSE_PIECE:
                raise ValueError("a line longer than a piece")
            carry = data
            continue
        carry = data[cut:]
        yield data[:cut]
    if carry:
        yield carry


class _PieceReader:
    """A binary file over a piece of the file's bytes, read in the blocks pandas asks for: no
    copy of the whole piece (a fresh allocation per piece, every page of it a fault)."""

    def __init__(self, view: memoryview) -> None:
        self._view, self._at = view, 0

    def read(self, size: int = -1) -> bytes:
        """The next ``size`` bytes (all that remain if ``size`` < 0), b"" at the end."""
        end = len(self._view) if size is None or size < 0 else self._at + size
        block = bytes(self._view[self._at:end])
        self._at += len(block)
        return block

    def __iter__(self):
        """Lines, for a caller that iterates (pandas' C parser reads blocks)."""
        return iter(io.BytesIO(bytes(self._view[self._at:])))


#: Bytes of a large file that pandas parses at once (whole lines; :func:`_pieces`): the
#: pieces in flight (their text and pandas' columns) add to the values, the file's bytes are
#: never held whole.
PARSE_PIECE = 1 << 23
#: Threads that parse a large file's pieces (at most PARSE_THREADS pieces in flight): two
#: parse 1.8x as fast as one; more would add memory at the peak.
PARSE_THREADS = max(1, min(2, os.cpu_count() or 1))


#: Bytes of a file counted at once by :func:`_byte_count` (a 16 MiB temporary).
COUNT_BLOCK = 1 << 24


def _byte_count(raw, byte, block=COUNT_BLOCK):
    r"""How many times one byte occurs in ``raw``: ``raw.count(byte)``, counted by numpy block by
    block (vectorised compares, about three times faster on a 10^6-set-point file).

    Parameters
    ----------
    raw : bytes
    byte : bytes, length 1
    block : int, optional
        Bytes compared at once.

    Returns
    -------
    int

    Examples
    --------
    >>> _byte_count(b"1,2\n3,4\n", b","), _byte_count(b"1,2\n3,4\n", b"\n", block=3)
    (2, 2)
    """
    code = ord(byte)
    total = 0
    for a in range(0, len(raw), block):
        view = np.frombuffer(raw, np.uint8, count=min(block, len(raw) - a), offset=a)
        total += int(np.count_nonzero(view == code))
    return total


def _joints(n, noun="joint"):
    """``n`` and the noun, plural unless ``n`` is 1 ("1 joint", "6 joints")."""
    return f"{n} {noun}{'' if n == 1 else 's'}"


def _same_joints(n, n_joints, what, source, noun="joint", **where):
    """An InputError ``"the <what> <n nouns>, the robot has <n_joints joints>"`` (``what`` with
    its verb, e.g. ``"file has"``; ``where``: the row and column) unless ``n_joints`` is None
    or ``n``."""
    if n_joints is not None and n != n_joints:
        raise InputError(f"the {what} {_joints(n, noun)}, the robot has {_joints(n_joints)}",
                         source, **where)


def _validated_values(raw, path, header, least=0):
    """Parse cell by cell: (values, names, row numbers), ``header`` (the header's cells and its
    row number) giving the names or raising; an InputError naming the row and column of the
    first fault (a ragged row, a cell not a number: :func:`_cell`), or for fewer than
    ``least`` rows (set points)."""
    (header_row, cells), *data = _numbered_rows(raw, path, long_cell=True)
    names = header(cells, header_row)
    if len(data) < least:
        raise InputError(f"fewer than {least} set points ({len(data)})", path)
    values = np.empty((len(data), len(names)))
    for k, (row_no, row) in enumerate(data):
        if len(row) != len(names):
            raise InputError(f"ragged row: {len(row)} cells, the header has {len(names)}", path,
                             row=row_no)
        values[k] = [_cell(row, j, names, path, row_no) for j in range(len(row))]
    return values, names, np.array([r for r, _ in data], int)


def _cell(cells, c, names, path, row):
    """The number in cell ``c`` (None: none) of the row ``cells``, row ``row`` of a file
    whose header is ``names``; an InputError naming the row (and the column) of a row too short
    to hold it (ragged), a cell longer than :data:`MAX_CELL` or not a plain finite number."""
    if c is None or c >= len(cells):
        raise InputError(f"ragged row: {len(cells)} cells, the header has {len(names)}", path,
                         row=row)
    text = cells[c].strip(" \t")
    if len(text) > MAX_CELL:
        raise InputError(f"a cell of {len(text)} characters is not a number", path, row=row,
                         column=names[c])
    try:
        return parse_number(text)
    except ValueError as exc:
        raise InputError(str(exc), path, row=row, column=names[c]) from None


def parse_number(text: str, integer: bool = False) -> float | int:
    """A number by the rules of a trajectory cell: plain decimal, finite.

    Parameters
    ----------
    text : str
        E.g. ``"-1.5e-3"`` (no ``1_0``, no digits other than 0-9, no ``inf`` or ``nan``).
    integer : bool, optional
        Accept only ``[+-]digits``, and return an int.

    Returns
    -------
    float or int

    Raises
    ------
    ValueError
        One clause naming the text and what it holds.

    Examples
    --------
    >>> parse_number("-9.81"), parse_number("12", integer=True)
    (-9.81, 12)
    >>> parse_number("1_0")
    Traceback (most recent call last):
    ...
    ValueError: not a number: '1_0' (it holds an underscore; write plain decimal numbers like -1.5e-3)
    """
    text = str(text)
    if integer and _INTEGER.fullmatch(text):
        return int(text)
    if not integer and _FLOAT.fullmatch(text):
        v = float(text)
        if math.isfinite(v):
            return v
        raise ValueError(f"not a finite number: {text!r} (beyond the range of a float)")
    try:
        v = float(text)
    except ValueError:
        v = None  # type: ignore[assignment]  # not a number
    if v is not None and not math.isfinite(v):
        raise ValueError(f"not a finite number: {text!r}")
    what = ("digits other than 0-9" if any(c.isdigit() and c not in "0123456789" for c in text)
            else "an underscore" if "_" in text else None)
    plain = "whole numbers like 12" if integer else "decimal numbers like -1.5e-3"
    hint = f" (it holds {what}; write plain {plain})" if what else \
        " (write a whole number)" if integer and v is not None else ""
    raise ValueError(f"not {'a whole' if integer else 'a'} number: {text!r}{hint}")


def check_joint_limits(robot: Robot, trajectory: Trajectory | Recording) -> list[str]:
    """Warn for every joint whose position leaves its limits along the trajectory.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints and limits q_min, q_max [rad].
    trajectory : Trajectory or Recording
        Positions q, shape (N, n) [rad] (a recording in degrees by mistake is seen here); a
        recording's messages name its file's row and column of the sample (a trajectory's
        sample k is row k + 2 and joint j's column q{j + 1}).

    Returns
    -------
    list of str
        One message per offending joint (also issued as :class:`JointLimitWarning`).
    """
    messages = []
    rows = trajectory.rows if isinstance(trajectory, Recording) else None
    for j in range(robot.n):
        x, lo, hi = trajectory.q[:, j], robot.q_min[j], robot.q_max[j]
        out = np.nonzero((x < lo) | (x > hi))[0]
        if out.size:
            k = int(out[0])
            s, unit = (1.0, "m") if robot.prismatic[j] else (180 / math.pi, "deg")
            # degrees read as radians: far outside (beyond 3 half-ranges from the middle of
            # the limits), and within them once converted
            deg = (unit == "deg" and np.abs(2 * x - lo - hi).max() > 3 * (hi - lo)
                   and bool(np.all((np.radians(x) >= lo) & (np.radians(x) <= hi))))
            name = trajectory.column("q", j) if isinstance(trajectory, Recording) else f"q{j + 1}"
            msg = (f"{trajectory.source}: row {k + 2 if rows is None else rows[k]}, column "
                   f"{name}: joint {j + 1} at {s * x[k]:.4g} {unit} is outside its limits "
                   f"[{s * lo:.4g}, {s * hi:.4g}] {unit} ({out.size} set point"
                   f"{'s' if out.size > 1 else ''})"
                   + (f"; in degrees? ({name} read in degrees lies within them)" if deg else ""))
            warnings.warn(msg, JointLimitWarning, stacklevel=2)
            messages.append(msg)
    return messages


def unwrapped(robot: Robot, trajectory: Trajectory) -> Trajectory:
    """The trajectory with its continuous joints' wraps at +-pi undone, where the cubic spline
    gave its qd and qdd.

    A continuous revolute joint (no position limits) logged as ROS ``joint_states`` holds it
    wraps at +-pi: its position steps by about 2 pi between two set points, which the spline
    takes for motion (huge qd and qdd). Its positions are unwrapped (``np.unwrap``) and qd,
    qdd derived again by the same spline, with one :class:`~gd_analyze.errors.InputWarning`
    naming the file, the first row and column. Joints with limits, prismatic joints and given
    qd, qdd are left as they are (the G-D terms are periodic in a revolute q).

    Parameters
    ----------
    robot : Robot
        The arm: limits q_min, q_max [rad or m] and ``prismatic`` of its n joints.
    trajectory : Trajectory
        Its set points, n joints.

    Returns
    -------
    Trajectory
        ``trajectory`` itself when no such joint steps by more than pi; else one with q, qd and
        qdd unwrapped and its source, sha256 and derivatives.
    """
    free = np.isinf(robot.q_min) & np.isinf(robot.q_max) & ~robot.prismatic
    steps = (np.abs(np.diff(trajectory.q, axis=0)) > np.pi) & free
    if trajectory.derivatives != "cubic-spline" or not steps.any():
        return trajectory
    k, j = (int(i) for i in np.argwhere(steps)[0])
    step = abs(trajectory.q[k + 1, j] - trajectory.q[k, j])

    def row_of(i):          # read from a file: set point i is row i + 2, unless rows says
        return None if not trajectory.sha256 else (
            i + 2 if trajectory.rows is None else int(trajectory.rows[i]))

    warnings.warn(str(InputError(
        f"joint {j + 1}'s positions step by {step:.2g} rad (wrapped at +-pi, a continuous "
        f"joint's log?): unwrapped before the cubic spline gives qd and qdd", trajectory.source,
        row=row_of(k + 1), column=trajectory.columns[j] if trajectory.columns else f"q{j + 1}")),
        InputWarning, stacklevel=2)
    q = np.where(steps.any(axis=0), np.unwrap(trajectory.q, axis=0), trajectory.q)
    qd, qdd = _spline(trajectory.t, q, trajectory.source, row_of, trajectory.columns)
    return replace(trajectory, q=q, qd=qd, qdd=qdd)


def write_trajectory(trajectory: Trajectory, path: str | os.PathLike[str]) -> None:
    """Write a trajectory CSV file atomically (temporary name, then rename).

    Parameters
    ----------
    trajectory : Trajectory
        The set points; t [s], q [rad], qd [rad/s], qdd [rad/s^2].
    path : str or os.PathLike
        Destination; ``"-"`` writes to standard output.

    Raises
    ------
    OSError
        If the file cannot be written.
    """
    write_trajectory_chunks([trajectory], trajectory.q.shape[1], path)


#: Rows formatted into one string at a time by :func:`write_trajectory_chunks` (a few MB of
#: text for 6 joints).
_ROWS_FORMATTED = 2**14


def _csv_rows(table: np.ndarray) -> str:
    """CSV lines of a table's rows, each value as ``"%.17g"`` (17 significant digits, so that
    it reads back bit for bit) and NaN as an empty field.

    Parameters
    ----------
    table : ndarray, shape (rows, columns)
        Values.

    Returns
    -------
    str
        ``rows`` lines, each ending in a newline: the lines pandas' ``to_csv`` writes with
        ``float_format="%.17g"`` (its empty ``na_rep``), made by one string formatting of the
        whole table instead of one call per value.
    """
    rows, cols = table.shape
    text = (",".join(["%.17g"] * cols) + "\n") * rows % tuple(table.ravel().tolist())
    if np.isnan(table).any():       # "%.17g" writes NaN (of either sign) as "nan"
        text = text.replace("nan", "")
    return text


def write_trajectory_chunks(chunks: Iterable[Trajectory], n: int,
                            path: str | os.PathLike[str]) -> None:
    """Write a trajectory CSV file piece by piece, atomically (temporary name, then rename):
    the same bytes as :func:`write_trajectory` of the pieces joined, in the memory of one piece.

    Parameters
    ----------
    chunks : iterable of Trajectory
        Consecutive pieces of the set points; t [s], q [rad], qd [rad/s], qdd [rad/s^2].
    n : int
        Number of joints.
    path : str or os.PathLike
        Destination; ``"-"`` writes to standard output.

    Raises
    ------
    OSError
        If the file cannot be written; the file is then left as it was.
    """
    columns = trajectory_columns(n, True)

    def write(stream):
        stream.write(",".join(columns) + "\n")
        for piece in chunks:
            # + 0.0: -0.0 (a joint at rest moving down) is written "0"
            table = np.column_stack([piece.t, piece.q, piece.qd, piece.qdd]) + 0.0
            for start in range(0, table.shape[0], _ROWS_FORMATTED):
                stream.write(_csv_rows(table[start:start + _ROWS_FORMATTED]))

    if str(path) == "-":
        import sys

        write(sys.stdout)
        return

    with atomic_path(path) as tmp, open(tmp, "w", newline="", encoding="utf-8") as stream:
        write(stream)


#: The fewest distinct time stamps a recording may have.
MIN_SAMPLES = 10
#: Largest accepted |torque| [N m or N] or |current| [A] in a recording.
TAU_LIMIT = 1e7
_LIMITS = {**LIMITS, "tau": TAU_LIMIT}
#: A numbered column, in any case, its number plain, after ``_`` or in brackets (``tau_1``,
#: ``Q[0]``).
_COLUMN = re.compile(r"^(t|time|__time|timestamp|q|qd|qdd|dq|ddq|tau|effort|torque|i|actual_q_|"
                     r"actual_qd_|actual_current_as_torque_|actual_current_)(?:_?(\d+)|\[(\d+)\])?$",
                     re.IGNORECASE)
#: Other names of a kind: time (PlotJuggler's ``__time``, a UR RTDE log's ``timestamp``),
#: torques (a JointState's ``effort``), currents, velocities and accelerations as FIGAROH's
#: files write them, and a UR RTDE log's measured positions, velocities, torques and currents
#: (numbered from 0).
_KIND = {"time": "t", "__time": "t", "timestamp": "t", "i": "tau", "dq": "qd", "ddq": "qdd",
         "effort": "tau", "torque": "tau", "actual_q_": "q", "actual_qd_": "qd",
         "actual_current_as_torque_": "tau", "actual_current_": "tau"}
#: A column naming a joint of the robot file and a ROS JointState field, and its kind:
#: ``<joint>_position`` or, as PlotJuggler names a JointState topic's series,
#: ``/<topic>/<joint>/position``.
_NAMED = re.compile(r"^(?:/.*/)?(.+?)[_/](position|velocity|acceleration|effort)$")
_FIELD = {"position": "q", "velocity": "qd", "acceleration": "qdd", "effort": "tau"}
#: The kind of a file of one kind whose columns are the joints' bare names (as FIGAROH's SO-101
#: recordings, ``q.csv``, ``dq.csv``, ``current_mA.csv``), by its name up to the first ``_``.
_FILE_KIND = {"q": "q", "qd": "qd", "dq": "qd", "qdd": "qdd", "ddq": "qdd", "tau": "tau",
              "effort": "tau", "torque": "tau", "current": "i", "i": "i"}


@dataclass(frozen=True, eq=False)
class Recording:
    """One recording, sorted by time, with repeated time stamps dropped.

    Attributes
    ----------
    t : ndarray, shape (N,)
        Time [s], strictly increasing, the file's own time base.
    q : ndarray, shape (N, n)
        Joint positions [rad or m].
    tau : ndarray, shape (N, n)
        Measured torques [N m or N] (currents [A] when ``current``).
    qd, qdd : ndarray, shape (N, n), or None
        Velocities and accelerations where the file gives them.
    rows : ndarray of int, shape (N,)
        The file's row of each sample (header = row 1).
    current : bool
        True if ``tau`` holds motor currents.
    source : str
        The file read.
    sha256 : str
        SHA-256 of its bytes (of files joined: of their SHA-256s, space-separated).
    notes : tuple of str
        What was done on reading (rows sorted, repeated stamps dropped).
    files : tuple of (str, str)
        Each file read and the SHA-256 of its bytes (several: files joined on one clock;
        empty for arrays).
    columns : dict of str to tuple of str
        Each kind's ("q", "tau", "qd", "qdd") column name per joint as the file's header writes
        it (blanks around it stripped; empty for arrays).
    """

    t: np.ndarray
    q: np.ndarray
    tau: np.ndarray
    qd: np.ndarray | None = None
    qdd: np.ndarray | None = None
    rows: np.ndarray | None = None
    current: bool = False
    source: str = ""
    sha256: str = ""
    notes: tuple = ()
    files: tuple = ()
    columns: dict = field(default_factory=dict)

    @property
    def n(self) -> int:
        """int: the number of joints."""
        return int(self.q.shape[1])

    def column(self, kind: str, j: int) -> str:
        """The name of joint ``j``'s column of a kind as the file writes it.

        Parameters
        ----------
        kind : str
            ``"q"``, ``"tau"``, ``"qd"`` or ``"qdd"``.
        j : int
            The joint, from 0.

        Returns
        -------
        str
            The header's name (``"- shoulder_position"``, ``"i2"``), else ``f"{kind}{j + 1}"``.
        """
        return self.columns[kind][j] if kind in self.columns else f"{kind}{j + 1}"


def _keys(header, path, joints, current, seen):
    """(names, keys) of a recording file's header: the names stripped of blanks, each column's
    (kind, joint 1..n), ("-", name) for a joint outside the chain (``joints``: the chain's joint
    names, or None); ``seen``, shared by the files of one recording, holds the first (file,
    column) of each naming style ("number", "name") and each key (of ``t`` per file). An
    InputError naming the column of an unknown one, one repeated (in this file or another), or
    of a second style."""
    names, keys = [c.strip() for c in header], []
    for k, name in enumerate(names):
        m, named = _COLUMN.match(bare := name.removeprefix("- ").strip()), _NAMED.match(bare)
        stem, number = (m[1].lower(), m[2] or m[3]) if m else (None, None)
        kind = m and _KIND.get(stem, stem)
        if m and (kind == "t") != bool(number):
            if stem in ("i", "actual_current_") and not current:
                raise InputError(f"column {name!r} holds a current: give --current, --drive-gains",
                                 path, row=1, column=name)
            key = (kind, int(number or 1))
        elif named and joints is not None:      # ("-", name): a joint outside the chain
            key = (_FIELD[named[2]], joints.index(named[1]) + 1) if named[1] in joints else \
                ("-", named[1])
        elif joints is not None and (of_file := _FILE_KIND.get(
                os.path.basename(path).split(".")[0].split("_")[0].lower())):
            if of_file == "i" and not current:
                raise InputError(f"column {name!r} holds a current (by the file's name): give "
                                 f"--current, --drive-gains", path, row=1, column=name)
            key = ("tau" if of_file == "i" else of_file, joints.index(bare) + 1) \
                if bare in joints else ("-", bare)
        else:
            raise InputError(f"unknown column {name!r} (expected t,q1..qn,tau1..taun[,qd1..qdn,"
                             f"qdd1..qddn] or <joint>_position,_effort[,_velocity,_acceleration])",
                             path, row=1, column=name)
        if key[0] != "t":
            seen.setdefault("number" if m else "name", (path, name))
        if {"number", "name"} <= seen.keys():
            file, first = seen["name" if m else "number"]
            raise InputError(f"column {name!r} {'numbers' if m else 'names'} a joint, column "
                             f"{first!r} of {file} {'names' if m else 'numbers'} one", path,
                             row=1, column=name)
        other = seen.setdefault((path, key) if key[0] == "t" else key, (path, k))
        if key[0] != "-" and other != (path, k):
            raise InputError(f"column {name!r} appears twice" + (
                "" if other[0] == path else f", in {other[0]} too"), path, row=1, column=name)
        keys.append(key)
    return names, keys


def _columns(keys, names, path, n_joints, joints):
    """({kind: [column index per joint]}, notes) of a recording's (kind, joint) keys
    (:func:`_keys`, of its files together, whose header ``names`` they are; ``joints``: the
    chain's joint names where the columns name them, else None), or an InputError naming the
    missing or surplus column. A kind numbered from 0 (``q0..q5``) is counted from joint 1, with
    a note."""
    found: dict = {}
    notes, shift = [], collections.Counter()
    for k, key in enumerate(keys):
        found.setdefault(key[0], {})[key[1]] = k
    for kind, slot in found.items():
        if kind != "-" and 0 in slot:
            found[kind], shift[kind] = {j + 1: k for j, k in slot.items()}, 1
            notes.append(f"{names[slot[0]]}..{names[slot[max(slot)]]}")
    notes = [f"{path}: columns {', '.join(notes)} number the joints from 0: read as joints "
             f"from 1"] if notes else []
    n = len(found.get("q", {})) if joints is None else len(joints)
    if "t" not in found or n == 0:
        raise InputError(f"no {'time column t' if n else 'joint position columns q1..qn'} in "
                         f"the header", path, row=1, column="t" if n else "q1")
    _same_joints(n, n_joints, "file has", path, "joint position column", row=1, column="q")
    out = {"t": [found["t"][1]]}
    for kind in ("q", "tau", "qd", "qdd"):
        slot = found.get(kind, {})
        missing = [j for j in range(1, n + 1) if j not in slot]
        if missing and (slot or kind in ("q", "tau")):   # qd and qdd may be absent, not in part
            name = f"{kind}{missing[0] - shift[kind]}" if joints is None else \
                f"{joints[missing[0] - 1]}_" + next(f for f, k in _FIELD.items() if k == kind)
            raise InputError(f"missing column {name!r}" + ("" if slot or joints else (
                f" (expected t,q1..q{n},tau1..tau{n})")), path, row=1, column=name)
        extra = sorted(set(slot) - set(range(1, n + 1)))
        if extra:
            raise InputError(f"column '{kind}{extra[0] - shift[kind]}' beyond the {_joints(n)}",
                             path, row=1, column=f"{kind}{extra[0] - shift[kind]}")
        if slot:
            out[kind] = [slot[j] for j in range(1, n + 1)]
    return out, notes


#: The header of PlotJuggler's CSV export: ``__time`` and a series' path.
_JUGGLED = re.compile(rb"__time,(?:[^\r\n]*,)?/")
#: A UR RTDE log's header: the controller's ``timestamp`` and each joint's measured position.
_RTDE_HEAD = re.compile(rb"timestamp[ ,][^\r\n]*\bactual_q_0\b")
#: Longest joint name a message quotes from a file [characters].
MAX_NAME = 200
#: A column of ``rostopic echo -p`` on a sensor_msgs/JointState topic: an array's field and index.
_ECHO = re.compile(r"field\.(name|position|velocity|effort)(\d+)")


def _echoed_values(raw, path, joints, notes):
    """(values, names, row numbers) of the bytes of a ``rostopic echo -p`` log of a JointState
    topic (header ``%time,field.header.seq,field.header.stamp,..,field.name0..,
    field.position0..``, ``field.velocity0..``, ``field.effort0..``): ``t`` [s] the header's
    stamp [ns] (``%time``, the time received, where a stamp is 0), and each chain joint's
    fields found in each row by its name (``joints``), as columns ``<joint>_position`` etc.
    Rows naming none of the chain's joints (another publisher's) are left out, with a note in
    ``notes``; an InputError names the row and column of a row naming only some of them, or of
    a cell that is not a number. pandas parses a file without quotes, NUL bytes or blank lines
    before its end (:func:`_echoed_frame`); the cells are read one by one where it cannot, or
    to name a fault (:func:`_echoed_rows`): both give the same values."""
    header = [c.strip() for c in next(csv.reader([raw.split(b"\n", 1)[0]
                                                  .decode("utf-8", "replace")]), [])]
    at = {(m[1], int(m[2])): c for c, name in enumerate(header) if (m := _ECHO.fullmatch(name))}
    if joints is None or ("position", 0) not in at:
        raise InputError("a rostopic echo -p log: its rows name the joints by the robot's joint "
                         "names, and need its field.position0..", path, row=1, column="%time")
    slots = sorted(k for kind, k in at if kind == "name")
    fields = [f for f in ("position", "velocity", "effort") if (f, 0) in at]
    # the columns of each row's value: %time, the stamp, then each field of each slot
    columns = [0, *(c for c, name in enumerate(header) if name == "field.header.stamp")]
    plain = not re.search(rb'["\x00]|\n[ \t\r]*\n[ \t\r]*\S', raw)
    table, rows, skipped, others = (plain and _echoed_frame(raw, header, at, slots, fields,
                                                            columns, joints)) or _echoed_rows(
        raw, path, header, at, slots, fields, columns, joints)
    if not rows.size:
        raise InputError(f"no row names a joint of the chain ({', '.join(joints)})", path, row=2,
                         column=header[at["name", slots[0]]] if slots else "%time")
    clock = 1 if len(columns) > 1 and (table[:, 1] > 0).all() else 0
    notes.append(one_line(
        f"{path}: a rostopic echo -p log of joint states: t from "
        f"{'field.header.stamp' if clock else '%time'} [ns]" + (
            f"; {_joints(len(skipped), 'row')} naming none of the chain's joints left out "
            f"(first at row {skipped[0]})" if len(skipped) else "") + (
            f"; joints outside the chain ignored: {', '.join(others)}" if others else "")))
    names = ["t"] + [f"{j}_{f}" for f in fields for j in joints]
    return np.column_stack([table[:, clock] / 1e9, table[:, len(columns):]]), names, rows


def _echoed_rows(raw, path, header, at, slots, fields, columns, joints):
    """(values, row numbers, rows left out, other joints named) of a ``rostopic echo -p`` log
    (:func:`_echoed_values`) read cell by cell: an InputError names the first fault."""
    values, rows, skipped, others = [], [], [], []
    for row, cells in _numbered_rows(raw, path, long_cell=True)[1:]:
        named = {cells[at["name", k]].strip(): k for k in slots if at["name", k] < len(cells)}
        found = [named.get(j) for j in joints]
        if not any(k is not None for k in found):
            skipped.append(row)
            continue
        if None in found:
            raise InputError(f"joint {joints[found.index(None)]!r} of the chain is not named in "
                             f"this row (it names {', '.join(n[:MAX_NAME] for n in named)})",
                             path, row=row, column=header[at["name", slots[0]]])
        others = others or [name[:MAX_NAME] for name in named if name not in joints]
        # a field's array shorter than the names' (no cell): a ragged row
        values.append([_cell(cells, c, header, path, row) for c in columns] + [
            _cell(cells, at.get((f, k)), header, path, row) for f in fields for k in found])
        rows.append(row)
    return np.array(values).reshape(len(rows), -1), np.array(rows, int), skipped, others


def _echoed_frame(raw, header, at, slots, fields, columns, joints):
    """:func:`_echoed_rows` by pandas, at the speed and memory of a numeric file: None where
    the file is not such a log whose every kept row is whole and finite (that function then
    names the fault)."""
    import pandas as pd

    if any((f, k) not in at for f in fields for k in slots):
        return None
    exact = {} if int(pd.__version__.split(".")[0]) >= 3 else {"float_precision": "round_trip"}
    named = [at["name", k] for k in slots]
    numeric = columns + [at[f, k] for f in fields for k in slots]
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            frame = pd.read_csv(io.BytesIO(raw.rstrip()), header=0, names=range(len(header)),
                                usecols=numeric + named, engine="c", skipinitialspace=True,
                                dtype={**dict.fromkeys(numeric, float),
                                       **dict.fromkeys(named, "category")}, **exact)
    except (ValueError, pd.errors.ParserError):
        return None
    # each joint's slot in each row, the last slot naming it (as a dict of the names keeps)
    match = np.stack([np.stack([(frame[c] == j).to_numpy(bool) for c in named], 1)
                      for j in joints], 1)                               # (N, joints, slots)
    found = match.shape[2] - 1 - match[:, :, ::-1].argmax(2)
    some, every = match.any(2), match.any(2).all(1)
    if (some.any(1) & ~every).any() or any(
            (cat != cat.strip()) for c in named for cat in frame[c].cat.categories):
        return None
    keep = np.flatnonzero(every)
    table = np.column_stack([frame[columns].to_numpy(float)[keep]] + [
        np.take_along_axis(frame[[at[f, k] for k in slots]].to_numpy(float)[keep],
                           found[keep], 1) for f in fields])
    if not np.isfinite(table).all():
        return None
    first = [str(frame[c].iloc[keep[0]]) for c in named if not frame[c].isna().iloc[keep[0]]] \
        if keep.size else []
    return table, keep + 2, np.flatnonzero(~some.any(1)) + 2, [
        n[:MAX_NAME] for n in dict.fromkeys(first) if n not in joints]


def _juggled_values(raw, path, joints, notes):
    """(values, names, row numbers) of the bytes of PlotJuggler's CSV export (header ``__time``
    [s], then a column per series, a JointState topic's ``/<topic>/<joint>/position``,
    ``/velocity``, ``/effort``; a row per time stamp of any series exported, a cell blank where
    its series has no sample): ``t`` and each chain joint's series (``joints``) as columns
    ``<joint>_position`` etc., every other series ignored. Rows where the chain's series are all
    blank (another topic's stamps) are left out, with a note in ``notes``; an InputError names
    the row and column of a ragged row, of a blank cell beside the chain's others, or of a cell
    that is not a number, or the column of a series given twice or missing."""
    (_, header), *data = _numbered_rows(raw, path, long_cell=True)
    header = [c.strip() for c in header]
    if joints is None:
        raise InputError("PlotJuggler's CSV export: its columns name the joints by the robot's "
                         "joint names", path, row=1, column="__time")
    at: dict = {}
    for c, name in enumerate(header):
        m = _NAMED.fullmatch(name) if name.startswith("/") else None
        if m and m[1] in joints and at.setdefault((m[2], m[1]), c) != c:
            raise InputError(f"columns {header[at[m[2], m[1]]]!r} and {name!r} both hold joint "
                             f"{m[1]!r}'s {m[2]}", path, row=1, column=name)
    fields = [f for f in ("position", "velocity", "effort") if any((f, j) in at for j in joints)]
    for f, j in ((f, j) for f in fields for j in joints if (f, j) not in at):
        raise InputError(f"no {f} series of joint {j!r} (a column /<topic>/{j}/{f}) beside the "
                         f"other joints'", path, row=1, column=f"/<topic>/{j}/{f}")
    cols = [0] + [at[f, j] for f in fields for j in joints]
    kept, skipped = [], []
    for row, cells in _picked(data, len(header), cols, path):
        blank = [k for k, x in enumerate(cells) if k and not x.strip(" \t")]
        if len(blank) == len(cols) - 1:
            skipped.append(row)
        elif blank:
            raise InputError("a blank cell beside the other joints' values in this row", path,
                             row=row, column=header[cols[blank[0]]])
        else:
            kept.append((row, cells))
    others = dict.fromkeys(m[1][:MAX_NAME] for name in header if name.startswith("/") and (
        m := _NAMED.fullmatch(name)) and m[1] not in joints)
    notes.append(one_line(
        f"{path}: PlotJuggler's CSV export: t from __time [s]" + (
            f"; {len(header) - len(cols)} other columns ignored" if len(header) > len(cols)
            else "") + (f" (joints outside the chain: {', '.join(others)})" if others else "") + (
            f"; {_joints(len(skipped), 'row')} holding none of the chain's series left out "
            f"(first at row {skipped[0]})" if skipped else "")))
    names = [header[c] for c in cols]
    return _numbers(kept, names, path), names, np.array([row for row, _ in kept], int)


def _picked(data, width, cols, path):
    """The cells of the columns ``cols`` of each row ``data`` ((row number, cells) each), or an
    InputError naming the first ragged row (``width``: the header's number of cells)."""
    for row, cells in data:
        if len(cells) != width:
            raise InputError(f"ragged row: {len(cells)} cells, the header has {width}", path,
                             row=row)
    return [(row, [cells[c] for c in cols]) for row, cells in data]


def _numbers(rows, names, path):
    """The numbers of the rows ``rows`` ((row number, cells) each, a cell per name of ``names``)
    as an array, or an InputError naming the row and column of the first cell not a number."""
    return np.array([[_cell(cells, c, names, path, row) for c in range(len(names))]
                     for row, cells in rows], float).reshape(len(rows), len(names))


def _rtde_values(raw, path, current, notes):
    """(values, names, row numbers) of the bytes of a UR RTDE log (header ``timestamp``, then
    the recipe's fields, a vector's as ``actual_q_0..``, separated by spaces as the RTDE
    client's ``record.py`` writes it or by commas as ``ur_rtde``'s file recording does):
    ``timestamp`` [s] and each joint's measured position ``actual_q``, velocity ``actual_qd``
    and torque ``actual_current_as_torque`` (PolyScope 5.23 or later), or with ``current`` its
    motor current ``actual_current`` [A]; every other field ignored, with a note in ``notes``.
    An InputError names the row and column of a fault, or a log without the torques asked."""
    delimiter = "," if b"," in raw.split(b"\n", 1)[0] else " "
    (_, header), *data = _numbered_rows(raw, path, long_cell=True, delimiter=delimiter)
    header = [c.strip() for c in header]
    torque = "actual_current" if current else "actual_current_as_torque"
    cols = [c for c, name in enumerate(header)
            if re.fullmatch(rf"timestamp|actual_qd?_\d+|{torque}_\d+", name)]
    names = [header[c] for c in cols]
    if not any(name.startswith(torque) for name in names):
        raise InputError(f"a UR RTDE log without {torque}_0..: record it" + (
            "" if current else " (PolyScope 5.23 or later), or actual_current with --current "
            "--drive-gains"), path, row=1, column=f"{torque}_0")
    notes.append(f"{path}: a UR RTDE log: t from timestamp [s], " + (
        "motor currents from actual_current" if current else "torques from "
        "actual_current_as_torque") + (f"; {len(header) - len(cols)} other columns ignored"
                                       if len(header) > len(cols) else ""))
    kept = _picked(data, len(header), cols, path)
    return _numbers(kept, names, path), names, np.array([row for row, _ in kept], int)


#: A time stamp earlier than the row before by more than this many median steps starts another
#: recording (a file appended to another), not a stamp out of order: refused.
BACK_STEPS = 20


def _ordered(t, arrays, rows, path, column="t"):
    """Sort by time (stable), drop repeated stamps (keep the first), and say what was done;
    ``column``: the time column's name in the file."""
    notes = []
    order = np.argsort(t, kind="stable")
    back = np.flatnonzero(np.diff(t) < 0)          # a stamp earlier than the one before
    steps = np.diff(t[order])
    step = float(np.median(steps[steps > 0])) if (steps > 0).any() else 0.0
    far = back[t[back] - t[back + 1] > BACK_STEPS * step] if back.size and step else back[:0]
    if far.size:
        k = int(far[0])
        raise InputError(f"the time goes back from {t[k]:.9g} s to {t[k + 1]:.9g} s, "
                         f"{(t[k] - t[k + 1]) / step:.3g} median steps (a recording appended to "
                         f"another? Sorted by time, the two would interleave): give each "
                         f"recording as its own file", path, row=int(rows[k + 1]), column=column)
    if back.size:
        notes.append(f"{path}: {back.size} time stamps earlier than the row before (first at "
                     f"row {rows[back[0] + 1]}): rows sorted by time")
    keep = np.concatenate([[True], np.diff(t[order]) > 0])
    repeated = rows[order][~keep]       # never fewer than MIN_SAMPLES rows: one if too few stamps
    if repeated.size:
        notes.append(f"{path}: {repeated.size} rows repeat an earlier time stamp (first at row "
                     f"{repeated[0]}): the first row of each stamp kept")
    order = order[keep]
    t, rows, arrays = t[order], rows[order], [None if a is None else a[order] for a in arrays]
    if t.size < MIN_SAMPLES:
        raise InputError(f"{t.size} distinct time stamps (this row repeats an earlier one, as "
                         f"{repeated.size - 1} more do): at least {MIN_SAMPLES} are needed",
                         path, row=int(repeated[0]), column=column)
    return t, arrays, rows, notes


def recording_files(source: str) -> list[str]:
    """The files of one recording as the command line names it: ``A.csv+B.csv+C.csv`` (files
    on one clock, see :func:`read_recording`) split at its "+", unless a file has that whole
    name.

    Parameters
    ----------
    source : str
        The recording's argument.

    Returns
    -------
    list of str
        Its files, in the order given.

    Examples
    --------
    >>> recording_files("/no/such/p.csv+/no/such/v.csv")
    ['/no/such/p.csv', '/no/such/v.csv']
    """
    return [source] if os.path.exists(source) or "+" not in source else source.split("+")


def read_recording(path: str | os.PathLike[str], n_joints: int | None = None,
                   current: bool = False, joint_names: Sequence[str] | None = None) -> Recording:
    """Read and check a recording CSV file, or several files on one clock.

    Parameters
    ----------
    path : str or os.PathLike
        The CSV file (layout in the module docstring); ``A.csv+B.csv+..`` (where no file has
        that whole name) joins the columns of files on one clock: each has the column ``t``,
        the same in every row, and no other column of another.
    n_joints : int, optional
        The robot's number of joints n; the file must have as many.
    current : bool, optional
        The torque columns hold motor currents [A] (``--current``); ``i1..in`` is accepted as
        their name.
    joint_names : sequence of str, optional
        The chain's joint names in chain order (:meth:`gd_analyze.model.robot.Robot.joint_names`):
        the columns may name the joints by them instead of numbering them,
        ``<joint>_position``, ``_velocity``, ``_acceleration`` and ``_effort`` (a leading
        ``"- "`` ignored); other joints' columns are ignored, with an InputNote naming them. A
        ``rostopic echo -p`` log of a JointState topic (header ``%time,..``) names them in its
        rows (``field.name<k>``): rows naming none of them are left out, with an InputNote.

    Returns
    -------
    Recording
        Sorted by time, repeated time stamps dropped; ``notes`` says what was done.

    Raises
    ------
    InputError
        If the file is missing or unreadable, not UTF-8 text, has an unknown, missing or
        repeated column, a ragged row, a cell that is not a plain finite number, a value beyond
        the supported magnitude, fewer than :data:`MIN_SAMPLES` distinct time stamps, or a
        joint count other than ``n_joints``; if columns number the joints and others name
        them; if a row of a ``rostopic echo -p`` log names some of the chain's joints only;
        if joined files' clocks differ in a row or their columns overlap. One line with the
        file, row and column. Before the file is opened: if ``path`` is not a str or
        os.PathLike, ``n_joints`` not a whole number >= 1, or ``current`` not a bool (the
        message names the argument).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "r.csv"
    >>> _ = f.write_text("t,q1,tau1\\n" + "".join(f"{k * 0.01},{k},{k}\\n" for k in range(12)))
    >>> read_recording(f).q.shape
    (12, 1)
    """
    source = _csv_path(path, n_joints)
    check_flags(current=current)
    seen: dict = {}             # the first column of each naming style and of each key
    parts: list = []
    notes: list = []
    joined = recording_files(source)
    for file in joined:
        def header(fields, row=1):     # at once, in this round; maybe twice: a copy of seen
            return _keys(fields, file, joint_names, current, dict(seen))[0]

        values, names, rows, sha256 = _read_csv(file, header, lambda raw: (
            _echoed_values(raw, file, joint_names, notes) if raw.startswith(b"%time,")
            else _juggled_values(raw, file, joint_names, notes) if _JUGGLED.match(raw)
            else _rtde_values(raw, file, current, notes) if _RTDE_HEAD.match(raw)
            else _validated_values(raw, file, header)))
        keys = _keys(names, file, joint_names, current, seen)[1]
        kinds = {kind: [k for k, key in enumerate(keys) if key[0] == kind] for kind in _LIMITS}
        check_magnitudes(values, names, kinds, file, rows, _LIMITS)
        if ("t", 1) not in keys:
            raise InputError("no time column t in the header", file, row=1, column="t")
        t = values[:, keys.index(("t", 1))]
        t0 = parts[0][-1] if parts else t
        k = min(t.size, t0.size, *np.flatnonzero(t[:t0.size] != t0[:t.size])[:1])
        if k < max(t.size, t0.size):            # on the first file's clock, row by row
            raise InputError(f"the clock is not {joined[0]}'s: " + (
                f"t = {t[k]:.9g} s, there {t0[k]:.9g} s" if k < min(t.size, t0.size) else
                f"{t.size} rows, it has {t0.size}"), file, row=int(rows[min(k, t.size - 1)]),
                column=names[keys.index(("t", 1))])
        parts.append((file, sha256, values, rows, keys, names, t))
    keys, names = ([x for part in parts for x in part[i]] for i in (4, 5))
    cols, more = _columns(keys, names, source, n_joints, joint_names if "name" in seen else None)
    notes += more
    values = np.hstack([part[2] for part in parts])
    if values.shape[0] < MIN_SAMPLES:
        raise InputError(f"{values.shape[0]} rows: at least {MIN_SAMPLES} are needed", source)
    notes += [one_line(f"{source}: columns of joints outside the chain ignored: {ignored}")
              for ignored in [", ".join(dict.fromkeys(j for kind, j in keys if kind == "-"))] if ignored]
    for note in notes:
        warnings.warn(note, InputNote, stacklevel=2)
    get = {k: values[:, idx] for k, idx in cols.items()}
    t, (q, tau, qd, qdd), rows, more = _ordered(
        get["t"][:, 0], [get.get(k) for k in ("q", "tau", "qd", "qdd")], parts[0][3], source,
        names[cols["t"][0]])
    sha256 = parts[0][1] if len(parts) == 1 else hashlib.sha256(
        " ".join(part[1] for part in parts).encode()).hexdigest()
    return Recording(t=t, q=q, tau=tau, qd=qd, qdd=qdd, rows=rows, current=bool(current),
                     source=source, sha256=sha256, notes=(*notes, *more), files=tuple(
                         part[:2] for part in parts), columns={
                         k: tuple(names[i] for i in idx) for k, idx in cols.items()})


def recording_from_arrays(t: ArrayLike, q: ArrayLike, tau: ArrayLike, qd: ArrayLike | None = None,
                          qdd: ArrayLike | None = None, source: str = "arrays",
                          current: bool = False) -> Recording:
    """A recording from arrays (the API's in-memory input), checked as a file is.

    Parameters
    ----------
    t : array_like, shape (N,)
        Time [s].
    q, tau : array_like, shape (N, n)
        Joint positions [rad or m] and measured torques [N m or N] (or currents [A]).
    qd, qdd : array_like, shape (N, n), optional
        Velocities and accelerations.
    source : str, optional
        A name for messages and the store.
    current : bool, optional
        ``tau`` holds currents.

    Returns
    -------
    Recording

    Raises
    ------
    InputError
        One line naming the argument: an array that is not real numbers, of another shape,
        with a value not finite or beyond the supported magnitude, too few distinct stamps,
        ``source`` not a str or ``current`` not a bool.
    """
    expect(source, str, "source", "a name (str)")
    check_flags(current=current)
    t, got = checked_arrays({"t": t, "q": q, "tau": tau, "qd": qd, "qdd": qdd}, source,
                               _LIMITS, MIN_SAMPLES, "sample")
    arrays = [got.get(k) for k in ("q", "tau", "qd", "qdd")]
    ts, (qs, taus, qds, qdds), rows, notes = _ordered(t, arrays, np.arange(2, t.size + 2), source)
    digest = hashlib.sha256(b"".join(np.ascontiguousarray(a).tobytes() for a in
                                     (ts, qs, taus) if a is not None)).hexdigest()
    return Recording(t=ts, q=qs, tau=taus, qd=qds, qdd=qdds, rows=rows, current=bool(current),
                     source=source, sha256=digest, notes=tuple(notes))
