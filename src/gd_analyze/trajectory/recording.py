"""Recordings for identification: joint positions and measured torques against time.

A recording CSV has a header ``t,q1..qn,tau1..taun`` with optional ``qd1..qdn`` and
``qdd1..qddn`` (the columns in any order), in [s], [rad or m], [N m or N], [rad/s or m/s],
[rad/s^2 or m/s^2]. With motor currents (``--current``) the torque columns hold currents [A]
(named ``tau1..taun`` or ``i1..in``) and the drive gains K turn them into torque, tau = K i.

Real logs have irregular clocks, out-of-order and repeated time stamps: :func:`read_recording`
sorts the rows by time (stable) and keeps the first of rows with the same time stamp, and says
so in :attr:`Recording.notes`. Everything else that cannot be used (a cell that is not a plain
finite number, a missing or unknown column, a ragged row, fewer than 10 distinct time stamps)
is refused with the file, the row (header = row 1) and the column.
"""

from __future__ import annotations

import hashlib
import os
import re
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError, check_flags, expect
from ..model.limits import LIMITS
from . import trajectory as tr

__all__ = ["Recording", "read_recording", "recording_from_arrays", "MIN_SAMPLES"]

#: The fewest distinct time stamps a recording may have.
MIN_SAMPLES = 10
#: Largest accepted |torque| [N m or N] or |current| [A] in a recording.
TAU_LIMIT = 1e7
_LIMITS = {**LIMITS, "tau": TAU_LIMIT}
_COLUMN = re.compile(r"^(t|q|qd|qdd|tau|i)(\d*)$")


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
        SHA-256 of its bytes.
    notes : tuple of str
        What was done on reading (rows sorted, repeated stamps dropped).
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

    @property
    def n(self) -> int:
        """int: the number of joints."""
        return int(self.q.shape[1])


def _columns(header, path, n_joints, current):
    """{kind: [column index per joint]} from the header, or an InputError naming the column."""
    names = [c.strip() for c in header]
    found: dict = {}
    for k, name in enumerate(names):
        m = _COLUMN.match(name)
        if not m or (m.group(1) == "t") == bool(m.group(2)) or int(m.group(2) or 1) < 1:
            raise InputError(f"unknown column {name!r} (expected t,q1..qn,tau1..taun and "
                             f"optionally qd1..qdn, qdd1..qddn)", path, row=1, column=name)
        kind = "tau" if m.group(1) == "i" else m.group(1)
        if m.group(1) == "i" and not current:
            raise InputError(f"column {name!r} holds a current: give --current and "
                             f"--drive-gains", path, row=1, column=name)
        slot, j = found.setdefault(kind, {}), int(m.group(2) or 1)
        if j in slot:
            raise InputError(f"column {name!r} appears twice", path, row=1, column=name)
        slot[j] = k
    n = len(found.get("q", {}))
    if "t" not in found or n == 0:
        raise InputError(f"no {'time column t' if n else 'joint position columns q1..qn'} in "
                         f"the header", path, row=1, column="t" if n else "q1")
    if n_joints is not None and n != n_joints:
        raise InputError(f"the file has {n} joint position columns, the robot has {n_joints} "
                         f"joints", path, row=1, column="q")
    out = {"t": [found["t"][1]]}
    for kind in ("q", "tau", "qd", "qdd"):
        slot = found.get(kind, {})
        missing = [j for j in range(1, n + 1) if j not in slot]
        if missing and (slot or kind == "tau"):     # qd and qdd may be absent, not in part
            raise InputError(f"missing column '{kind}{missing[0]}'" + (
                "" if slot else f" (expected t,q1..q{n},tau1..tau{n})"), path, row=1,
                column=f"{kind}{missing[0]}")
        extra = sorted(set(slot) - set(range(1, n + 1)))
        if extra:
            raise InputError(f"column '{kind}{extra[0]}' beyond the {n} joints", path, row=1,
                             column=f"{kind}{extra[0]}")
        if slot:
            out[kind] = [slot[j] for j in range(1, n + 1)]
    return names, out, n


def _ordered(t, arrays, rows, path):
    """Sort by time (stable), drop repeated stamps (keep the first), and say what was done."""
    notes = []
    order = np.argsort(t, kind="stable")
    back = np.flatnonzero(np.diff(t) < 0)          # a stamp earlier than the one before
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
                         path, row=int(repeated[0]), column="t")
    return t, arrays, rows, notes


def read_recording(path: str | os.PathLike[str], n_joints: int | None = None,
                   current: bool = False) -> Recording:
    """Read and check a recording CSV file.

    Parameters
    ----------
    path : str or os.PathLike
        The CSV file (layout in the module docstring).
    n_joints : int, optional
        The robot's number of joints n; the file must have as many.
    current : bool, optional
        The torque columns hold motor currents [A] (``--current``); ``i1..in`` is accepted as
        their name.

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
        joint count other than ``n_joints``. One line with the file, row and column. Before
        the file is opened: if ``path`` is not a str or os.PathLike, ``n_joints`` not a
        whole number >= 1, or ``current`` not a bool (the message names the argument).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "r.csv"
    >>> _ = f.write_text("t,q1,tau1\\n" + "".join(f"{k * 0.01},{k},{k}\\n" for k in range(12)))
    >>> read_recording(f).q.shape
    (12, 1)
    """
    path = tr._csv_path(path, n_joints)
    check_flags(current=current)
    found = {}

    def header(fields):
        try:
            names, found["cols"], _ = _columns(fields, path, n_joints, current)
        except InputError:
            return None
        return names

    def cells(raw):
        """Cell by cell, naming the row and column of the first fault."""
        (_, header_cells), *data = tr._numbered_rows(raw, path)
        names, found["cols"], _ = _columns(header_cells, path, n_joints, current)
        return tr._cell_values(data, names, path), names, np.array([r for r, _ in data], int)

    values, names, rows, sha256 = tr._read_csv(path, header, cells)
    cols = found["cols"]
    tr.check_magnitudes(values, names, cols, path, rows, _LIMITS)
    if values.shape[0] < MIN_SAMPLES:
        raise InputError(f"{values.shape[0]} rows: at least {MIN_SAMPLES} are needed", path)
    get = {k: values[:, idx] for k, idx in cols.items()}
    t, (q, tau, qd, qdd), rows, notes = _ordered(
        get["t"][:, 0], [get.get(k) for k in ("q", "tau", "qd", "qdd")], rows, path)
    return Recording(t=t, q=q, tau=tau, qd=qd, qdd=qdd, rows=rows, current=bool(current),
                     source=path, sha256=sha256, notes=tuple(notes))


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
    t, got = tr.checked_arrays({"t": t, "q": q, "tau": tau, "qd": qd, "qdd": qdd}, source,
                               _LIMITS, MIN_SAMPLES, "sample")
    arrays = [got.get(k) for k in ("q", "tau", "qd", "qdd")]
    ts, (qs, taus, qds, qdds), rows, notes = _ordered(t, arrays, np.arange(2, t.size + 2), source)
    digest = hashlib.sha256(b"".join(np.ascontiguousarray(a).tobytes() for a in
                                     (ts, qs, taus) if a is not None)).hexdigest()
    return Recording(t=ts, q=qs, tau=taus, qd=qds, qdd=qdds, rows=rows, current=bool(current),
                     source=source, sha256=digest, notes=tuple(notes))
