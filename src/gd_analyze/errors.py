"""Errors raised on bad input.

Every error that a user can cause with a file or an argument is an :class:`InputError`. Its
message is one line that names the file, and the row and column where they apply, so that the
command line can print it as it is and exit with status 2.
"""

from __future__ import annotations

__all__ = ["InputError"]


class InputError(ValueError):
    """Bad input: a file, a row, a column or an argument the tool cannot use.

    Parameters
    ----------
    message : str
        What is wrong, in one line.
    path : str or os.PathLike, optional
        The file the error is in.
    row : int, optional
        The row of the file, counted from 1 with the header as row 1 (as a spreadsheet shows it).
    column : str, optional
        The column's name (or the key, for a robot file; or the option, e.g. "--payload").

    Notes
    -----
    ``str(err)`` gives ``"<path>: row <row>, column <column>: <message>"`` with the parts that
    are known.
    """

    def __init__(self, message, path=None, row=None, column=None):
        self.message = str(message).replace("\n", " ")
        self.path = None if path is None else str(path)
        self.row = row
        self.column = column
        super().__init__(self.__str__())

    def __str__(self):
        where = []
        if self.path is not None:
            where.append(self.path)
        loc = []
        if self.row is not None:
            loc.append(f"row {self.row}")
        if self.column is not None:
            # a command-line option names itself; anything else is a column (or key) of a file
            opt = str(self.column).startswith("--")
            loc.append(str(self.column) if opt else f"column {self.column}")
        if loc:
            where.append(", ".join(loc))
        return ": ".join(where + [self.message])
