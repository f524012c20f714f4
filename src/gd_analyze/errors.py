"""Errors raised on bad input.

Every error that a user can cause with a file or an argument is an :class:`InputError`. Its
message is one line that names the file, and the row and column where they apply, so that the
command line can print it as it is and exit with status 2.
"""

from __future__ import annotations

import numbers
import os
from typing import Any

import numpy as np

__all__ = ["InputError", "InputWarning", "InputNote", "expect", "check_flags", "is_number",
           "path_text", "regular_file"]


class InputError(ValueError):
    """Bad input: a file, a row, a column or an argument the tool cannot use.

    Parameters
    ----------
    message : str
        What is wrong, in one line.
    path : str or os.PathLike, optional
        The file the error is in (an empty name is written ``''``).
    row : int, optional
        The row of the file, counted from 1 with the header as row 1 (as a spreadsheet shows it).
    column : str, optional
        The column's name (with a row: a CSV file), the key (without a row: a TOML or JSON
        file, e.g. ``link[2].mass``), the option (e.g. ``"--payload"``) or a URDF's element or
        attribute (e.g. ``"<robot name>"``).

    Notes
    -----
    ``str(err)`` gives ``"<path>: row <row>, column <column>: <message>"`` with the parts that
    are known; without a row, ``"<path>: key <column>: <message>"``, or
    ``"<path>: <column>: <message>"`` for an option or anything naming an XML element (``<``).
    """

    def __init__(self, message: object, path: str | os.PathLike[str] | None = None,
                 row: int | None = None, column: str | None = None) -> None:
        self.message = one_line(str(message).replace("\n", " "))
        self.path = None if path is None else one_line(path) or "''"
        self.row = row
        self.column = None if column is None else one_line(column)
        super().__init__(self.__str__())

    def __str__(self):
        loc, kind = ([], "key") if self.row is None else ([f"row {self.row}"], "column")
        if self.column is not None:
            # a command-line option and a URDF's element or attribute name themselves; a cell
            # of a CSV file (with a row) is in a column; anything else is a key of a TOML or
            # JSON file
            bare = self.column.startswith("--") or "<" in self.column and self.row is None
            loc.append(self.column if bare else f"{kind} {self.column}")
        # the path is never empty (an empty name is written '')
        return ": ".join([p for p in (self.path, ", ".join(loc)) if p] + [self.message])


def one_line(text: object) -> str:
    """``text`` with every unprintable character (line breaks, controls, unassigned code
    points) written as its escape, so that a file name or key cannot break the line."""
    return "".join(c if c.isprintable() else c.encode("unicode_escape").decode("ascii")
                   for c in str(text))


def expect(value: Any, types: type | tuple[type, ...], name: str, what: str) -> Any:
    """An argument of the Python API, checked to be of its type.

    Parameters
    ----------
    value : object
        The argument.
    types : type or tuple of type
        What it may be (:func:`isinstance`).
    name : str
        The argument's name, for the message.
    what : str
        What it should be, for the message (e.g. ``"a Robot"``).

    Returns
    -------
    object
        ``value``.

    Raises
    ------
    InputError
        If ``value`` is not of ``types``: ``"NAME: WHAT, not a TYPE"``, one line naming the
        argument.

    Examples
    --------
    >>> expect(3, str, "name", "a str")
    Traceback (most recent call last):
    ...
    gd_analyze.errors.InputError: name: a str, not a int
    """
    if not isinstance(value, types):
        raise InputError(f"{name}: {what}, not a {type(value).__name__}")
    return value


def check_flags(**flags: Any) -> None:
    """Check that every flag of the Python API is a bool (Python's or numpy's).

    Parameters
    ----------
    **flags : bool
        Each flag by its argument's name.

    Raises
    ------
    InputError
        At the first flag that is not a bool (``"no"`` would read as True, 3 as a count):
        one line naming it (:func:`expect`).

    Examples
    --------
    >>> check_flags(verify=True, current=np.False_)
    >>> check_flags(current="no")
    Traceback (most recent call last):
    ...
    gd_analyze.errors.InputError: current: True or False, not a str
    """
    for name, value in flags.items():
        expect(value, (bool, np.bool_), name, "True or False")


def is_number(value: Any) -> bool:
    """Whether an argument of the Python API is a real number.

    Parameters
    ----------
    value : object
        The argument.

    Returns
    -------
    bool
        True for an int or float (numpy's too), False for anything else, a bool among them
        (True would read as 1).

    Examples
    --------
    >>> is_number(np.float32(0.5)), is_number(True), is_number("1")
    (True, False, False)
    """
    return isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))


def path_text(path: object, what: str) -> str:
    """A file argument of the Python API as text.

    Parameters
    ----------
    path : object
        The argument, a str or os.PathLike.
    what : str
        What the file is, for the message (e.g. ``"CSV file"``).

    Returns
    -------
    str
        ``str(path)``.

    Raises
    ------
    InputError
        If ``path`` is not a str or os.PathLike (``None``, a number): one line naming the
        argument, not the "None: no such file" or TypeError that opening it would give.

    Examples
    --------
    >>> path_text(None, "CSV file")
    Traceback (most recent call last):
    ...
    gd_analyze.errors.InputError: path: a CSV file (str or os.PathLike), not a NoneType
    """
    return str(expect(path, (str, os.PathLike), "path", f"a {what} (str or os.PathLike)"))


class InputWarning(UserWarning):
    """Input the tool accepts but the user should hear about, in one line (e.g. an unknown
    key that is ignored, a byte-order mark that is stripped, a value that looks like radians
    in a field in degrees). The command line prints it as ``gd-analyze: warning: ...``."""


class InputNote(InputWarning):
    """Input the tool corrected on its own (e.g. a byte-order mark stripped); printed as
    ``gd-analyze: note: ...``."""


def regular_file(path: str | os.PathLike[str], what: str) -> None:
    """Refuse, in one line, a file to read that is not a regular file: every reader says alike
    what stands there instead.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    what : str
        What it should be, for the message: "a CSV file", "a robot file", ...

    Raises
    ------
    InputError
        "no such file", "is a folder, not WHAT" or "not a regular file (a device, FIFO or
        socket?): give WHAT".
    """
    if not os.path.exists(path):
        raise InputError("no such file", path)
    if os.path.isdir(path):
        raise InputError(f"is a folder, not {what}", path)
    if not os.path.isfile(path):
        raise InputError(f"not a regular file (a device, FIFO or socket?): give {what}", path)
