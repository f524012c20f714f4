"""Labels of the G-D elements: the one rule from which every index, mask, table and file key derives.

The elements are the upper triangle of D (i <= j) and the n elements of h (Fu, Gonzalez & Lee
1987, Eqs. (3.4-24) to (3.4-27)). Their labels are one-based: ``"D11"`` .. ``"D66"`` and
``"h1"`` .. ``"h6"`` for the PUMA 560. Two indices of D are run together while both have one
digit and separated by a comma once one has two (``"D19"``, ``"D1,10"``, ``"D10,10"``), so a
robot with fewer than 10 joints keeps the labels of the files written before, and every label
of any robot is unambiguous (``"D110"`` is no label: it is ``"D1,10"``).
"""

from __future__ import annotations

import re

__all__ = ["element_index", "element_label", "element_labels", "parse_element_label"]

_PATTERN = re.compile(r"D([1-9])([1-9])|D([1-9][0-9]*),([1-9][0-9]*)|h([1-9][0-9]*)")


def element_index(n):
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


def element_label(kind, i, j=None):
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


def element_labels(n):
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
    return [element_label(kind, i, j) for kind, i, j in element_index(n)]


def parse_element_label(text, n):
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
        if m.group(5):
            kind, i, j = "h", int(m.group(5)) - 1, None
        else:
            kind, i, j = "D", int(one) - 1, int(two) - 1
        if (max(i, -1 if j is None else j) < n and (j is None or i <= j)
                and element_label(kind, i, j) == text):
            return kind, i, j
    raise ValueError(f"{str(text)[:40]!r} is not an element of a {n}-joint robot "
                     f"({element_labels(n)[0]}..{element_labels(n)[-1]})" if n > 0 else
                     f"{str(text)[:40]!r} is not an element label")
