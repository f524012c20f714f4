"""Labels of the G-D elements: the one rule from which every index, mask, table and file key derives.

The elements are the upper triangle of D (i <= j) and the n elements of h (Fu, Gonzalez & Lee
1987, Eqs. (3.4-24) to (3.4-27)). Their labels are one-based: ``"D11"`` .. ``"D66"`` and
``"h1"`` .. ``"h6"`` for the PUMA 560. Two indices of D are run together while both have one
digit and separated by a comma once one has two (``"D19"``, ``"D1,10"``, ``"D10,10"``), so a
robot with fewer than 10 joints keeps the labels of the files written before, and every label
of any robot is unambiguous (``"D110"`` is no label: it is ``"D1,10"``).

Their units follow the joint types (:func:`element_units`, :func:`joint_torque_units`): a
prismatic joint's coordinate is a length and its generalized force a force, so D_ij is
kg m^2, kg m or kg as none, one or both of joints i and j are prismatic, and h_i, c_i and
tau_i are N m or N. Every table, axis, caption and stored attribute takes its units from here.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np

__all__ = ["element_index", "element_label", "element_labels", "parse_element_label",
           "element_units", "joint_torque_units", "joint_motion_units", "joint_gain_units",
           "joint_drive_units",
           "joint_units_text"]

_PATTERN = re.compile(r"D([1-9])([1-9])|D([1-9][0-9]*),([1-9][0-9]*)|h([1-9][0-9]*)")


def element_index(n: int) -> list[tuple]:
    """Index triples of the elements, in label order.

    Parameters
    ----------
    n : int
        Number of joints.

    Returns
    -------
    list of tuple
        ``("D", i, j)`` for 0 <= i <= j < n (row by row), then ``("h", i, None)`` for
        0 <= i < n; zero-based.

    Examples
    --------
    >>> element_index(2)
    [('D', 0, 0), ('D', 0, 1), ('D', 1, 1), ('h', 0, None), ('h', 1, None)]
    """
    return ([("D", i, j) for i in range(n) for j in range(i, n)]
            + [("h", i, None) for i in range(n)])


def element_label(kind: str, i: int, j: int | None = None) -> str:
    """The label of one element.

    Parameters
    ----------
    kind : str
        ``"D"`` or ``"h"``.
    i : int
        Zero-based row (D) or index (h).
    j : int, optional
        Zero-based column of D (ignored for h).

    Returns
    -------
    str
        ``"D12"``, ``"h3"``, or ``"D1,10"`` once an index of D has two digits.

    Raises
    ------
    ValueError
        If kind is not ``"D"`` or ``"h"``, or an index is negative.

    Examples
    --------
    >>> element_label("D", 0, 1), element_label("D", 0, 9), element_label("h", 6)
    ('D12', 'D1,10', 'h7')
    """
    if kind == "h" and i >= 0:
        return f"h{i + 1}"
    if kind == "D" and i >= 0 and j is not None and j >= 0:
        return f"D{i + 1}{j + 1}" if i < 9 and j < 9 else f"D{i + 1},{j + 1}"
    raise ValueError(f"no element {kind!r} with indices {i!r}, {j!r}")


def element_labels(n: int) -> list[str]:
    """Labels of the elements of an n-joint robot, in the order of :func:`element_index`.

    Parameters
    ----------
    n : int
        Number of joints.

    Returns
    -------
    list of str
        ``["D11", "D12", ..., "Dnn", "h1", ..., "hn"]``; n (n + 1) / 2 + n labels.

    Examples
    --------
    >>> element_labels(10)[8:10]
    ['D19', 'D1,10']
    """
    return list(_labels(int(n)))


@functools.lru_cache(maxsize=64)
def _labels(n):
    """:func:`element_labels` as a tuple, kept: a sweep asks for them twice per trajectory."""
    return tuple(element_label(kind, i, j) for kind, i, j in element_index(n))


def parse_element_label(text: str, n: int) -> tuple:
    """The element a label names: the inverse of :func:`element_label`.

    Parameters
    ----------
    text : str
        A label as :func:`element_label` writes it.
    n : int
        Number of joints of the robot.

    Returns
    -------
    tuple
        ``("D", i, j)`` with 0 <= i <= j < n, or ``("h", i, None)`` with 0 <= i < n; zero-based.

    Raises
    ------
    ValueError
        If the text is not the label of an element of an n-joint robot (``"D110"``, ``"D1,2"``
        (written ``"D12"``), ``"D21"`` (lower triangle), ``"h0"``, an index beyond n).

    Examples
    --------
    >>> parse_element_label("D1,10", 12), parse_element_label("h3", 6)
    (('D', 0, 9), ('h', 2, None))
    """
    m = _PATTERN.fullmatch(text) if isinstance(text, str) else None
    if m is not None:
        one, two = (m.group(1), m.group(2)) if m.group(1) else (m.group(3), m.group(4))
        kind, i, j = ("h", int(m.group(5)) - 1, None) if m.group(5) else (
            "D", int(one) - 1, int(two) - 1)
        if (max(i, -1 if j is None else j) < n and (j is None or i <= j)
                and element_label(kind, i, j) == text):
            return kind, i, j
    raise ValueError(f"{str(text)[:40]!r} is not an element of a {n}-joint robot "
                     f"({element_labels(n)[0]}..{element_labels(n)[-1]})" if n > 0 else
                     f"{str(text)[:40]!r} is not an element label")


def element_units(kind: str, i: int, j: int | None = None,
                  prismatic: Sequence[bool] | np.ndarray | None = None) -> str:
    """The units of an element of D or h (and of c_i, tau_i), from the joint types.

    D_ij = dtau_i / dqdd_j: a revolute joint contributes m (torque over force, or angle over
    length) to neither, so D_ij is kg m^2 when joints i and j are both revolute, kg m when
    one is prismatic and kg when both are; h_i is a generalized force of joint i: N m for a
    revolute joint, N for a prismatic one (Fu, Gonzalez & Lee 1987, Eq. (3.4-24)).

    Parameters
    ----------
    kind : str
        ``"D"`` or ``"h"`` (``"c"`` and ``"tau"`` are read as ``"h"``).
    i : int
        Zero-based row (D) or joint (h).
    j : int, optional
        Zero-based column of D.
    prismatic : sequence of bool, shape (n,), optional
        True for a prismatic joint; all revolute if not given.

    Returns
    -------
    str
        ``"kg m2"``, ``"kg m"``, ``"kg"``, ``"N m"`` or ``"N"`` (UDUNITS spelling, as stored).

    Raises
    ------
    ValueError
        If kind is not one of ``"D"``, ``"h"``, ``"c"``, ``"tau"``, or j is missing for D.

    Examples
    --------
    >>> p = [False, False, True]
    >>> element_units("D", 0, 2, p), element_units("D", 2, 2, p), element_units("h", 2, None, p)
    ('kg m', 'kg', 'N')
    """
    def lin(k):
        return bool(prismatic[k]) if prismatic is not None else False

    if kind in ("h", "c", "tau"):
        return joint_torque_units(lin(i))
    if kind == "D" and j is not None:
        return {0: "kg m2", 1: "kg m", 2: "kg"}[int(lin(i)) + int(lin(j))]
    raise ValueError(f"no element {kind!r} with indices {i!r}, {j!r}")


def joint_torque_units(prismatic: bool) -> str:
    """The units of a joint's generalized force (tau_i, h_i, c_i).

    Parameters
    ----------
    prismatic : bool
        True for a prismatic joint.

    Returns
    -------
    str
        ``"N"`` for a prismatic joint, ``"N m"`` for a revolute one.

    Examples
    --------
    >>> joint_torque_units(True), joint_torque_units(False)
    ('N', 'N m')
    """
    return "N" if prismatic else "N m"


def joint_gain_units(prismatic: bool) -> tuple[str, ...]:
    """The units of a joint's position and velocity gains in generalized force (a PD law
    tau_i = Kp_i e_i + Kv_i de_i/dt): generalized force over q and over qd of the joint.

    Parameters
    ----------
    prismatic : bool
        True for a prismatic joint.

    Returns
    -------
    tuple of str
        (Kp, Kv) units, UDUNITS spelling as stored: ``("N m rad-1", "N m s rad-1")`` for a
        revolute joint, ``("N m-1", "N s m-1")`` for a prismatic one.

    Examples
    --------
    >>> joint_gain_units(False), joint_gain_units(True)
    (('N m rad-1', 'N m s rad-1'), ('N m-1', 'N s m-1'))
    """
    return ("N m-1", "N s m-1") if prismatic else ("N m rad-1", "N m s rad-1")


def joint_motion_units(prismatic: bool, shown: bool = False) -> tuple[str, ...]:
    """The units of a joint's q, qd and qdd.

    Parameters
    ----------
    prismatic : bool
        True for a prismatic joint.
    shown : bool, optional
        False: as stored (rad or m, SI); True: as the report shows them (deg or mm).

    Returns
    -------
    tuple of str
        (q, qd, qdd) units, e.g. ``("deg", "deg/s", "deg/s\u00b2")``.

    Examples
    --------
    >>> joint_motion_units(True), joint_motion_units(False, shown=True)[2]
    (('m', 'm s-1', 'm s-2'), 'deg/s²')
    """
    if shown:
        base = "mm" if prismatic else "deg"
        return base, f"{base}/s", f"{base}/s\u00b2"
    base = "m" if prismatic else "rad"
    return base, f"{base} s-1", f"{base} s-2"


def joint_units_text(units: Sequence[str], what: str = "joint") -> str:
    """Units that differ between joints, said once: ``"N m"`` or ``"N m (joints 1, 2), N (joint 3)"``.

    Parameters
    ----------
    units : sequence of str, shape (n,)
        The units of each joint (or element).
    what : str, optional
        What is counted (``"joint"``).

    Returns
    -------
    str
        The one unit if all agree, else each unit with the one-based joints that have it.

    Examples
    --------
    >>> joint_units_text(["N m", "N m", "N"])
    'N m (joints 1, 2), N (joint 3)'
    """
    order = list(dict.fromkeys(units))
    if len(order) == 1:
        return order[0]
    parts = []
    for u in order:
        ks = [str(k + 1) for k, v in enumerate(units) if v == u]
        parts.append(f"{u} ({what}{'s' if len(ks) > 1 else ''} {', '.join(ks)})")
    return ", ".join(parts)


def joint_drive_units(prismatic: bool) -> tuple[str, ...]:
    """The units of a joint's drive parameters: armature (D_ii's part) and viscous friction.

    The armature adds to D_ii, so it has D_ii's units (kg m^2 for a revolute joint, kg for a
    prismatic one, as :func:`element_units`); viscous friction is a generalized force per joint
    rate: N m / (rad/s) for a revolute joint, N / (m/s) for a prismatic one. Coulomb friction
    is a generalized force (:func:`joint_torque_units`).

    Parameters
    ----------
    prismatic : bool
        True for a prismatic joint.

    Returns
    -------
    tuple of str
        (armature, viscous) in UDUNITS spelling, as stored.

    Examples
    --------
    >>> joint_drive_units(False), joint_drive_units(True)
    (('kg m2', 'N m s rad-1'), ('kg', 'N s m-1'))
    """
    return ("kg", "N s m-1") if prismatic else ("kg m2", "N m s rad-1")
