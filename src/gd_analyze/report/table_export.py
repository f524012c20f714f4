"""Every table of a report as a CSV file, and as a LaTeX table on request.

The tables are those of the report's one section list (:class:`gd_analyze.report.sections.Outline`),
numbered as the report numbers them: Table 4.1 becomes ``tables/table_4_1.csv`` (and
``table_4_1.tex``). The CSV holds the table's header row (its units in brackets, or a units
column, as in the report) and its rows, the cells as plain text with the report's minus sign
(U+2212) written "-" in numbers. Text read from files (robot and joint names) is hostile: a CSV
cell that a spreadsheet would run as a formula (starting with ``=``, ``+``, ``-``, ``@``, a tab
or a carriage return, and not a number) is written with a leading apostrophe (OWASP, "CSV
Injection"); LaTeX's special characters are escaped, sub- and superscripts set with
``\\textsubscript`` and ``\\textsuperscript``, code with ``\\texttt``.
"""

from __future__ import annotations

import csv
import io
import re
from pathlib import Path
from typing import TYPE_CHECKING

from ..files import atomic_path
from . import markup

if TYPE_CHECKING:
    import contextlib
    import os

    from .sections import Outline

__all__ = ["csv_cell", "latex_text", "table_csv", "table_latex", "table_files", "write_tables"]

#: What a spreadsheet reads as the start of a formula.
_FORMULA_START = ("=", "+", "-", "@", "\t", "\r")
_NUMBER = re.compile(r"^[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?( ?%)?$")
#: LaTeX's special characters and what prints them.
_LATEX = {"\\": r"\textbackslash{}", "&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#",
          "_": r"\_", "{": r"\{", "}": r"\}", "~": r"\textasciitilde{}",
          "^": r"\textasciicircum{}", "<": r"\textless{}", ">": r"\textgreater{}",
          "|": r"\textbar{}", "\n": " ", "\r": " "}
_ALIGN = {"left": "l", "right": "r", "center": "c"}
#: The LaTeX command of each kind of marked span (:func:`gd_analyze.report.markup.spans`).
_COMMAND = {"sub": r"\textsubscript", "sup": r"\textsuperscript", "code": r"\texttt"}


def csv_cell(text: str) -> str:
    """A table cell as CSV text: plain, a number's minus sign "-", a formula neutralised.

    Parameters
    ----------
    text : str
        The cell as the report marks it (:mod:`gd_analyze.report.markup`).

    Returns
    -------
    str
        The cell's text; one that starts as a formula would and is not a number gets a leading
        apostrophe, so that a spreadsheet shows it as text.
    """
    t = markup.unicode(str(text)).replace("\u00a0", " ")
    t = markup.plain(t)
    as_number = t.replace("\u2212", "-")
    if _NUMBER.match(as_number):
        return as_number
    if t.startswith(_FORMULA_START):
        return "'" + t
    return t


def latex_text(text: str) -> str:
    """A marked string as LaTeX: specials escaped, scripts and code as commands.

    Parameters
    ----------
    text : str
        Marked as :mod:`gd_analyze.report.markup` marks it.

    Returns
    -------
    str
        Balanced braces; no character a LaTeX engine would read as a command.
    """
    pieces = [("".join(_LATEX.get(c, c) for c in piece), kind)
              for piece, kind in markup.spans(str(text))]
    return "".join(_COMMAND[kind] + "{" + t + "}" if kind else t for t, kind in pieces)


def table_csv(table: dict) -> str:
    """A report table as CSV text: the header row, then the rows.

    Parameters
    ----------
    table : dict
        ``header`` (list of str) and ``rows`` (list of list of str), as
        :func:`gd_analyze.report.common.table` makes it.

    Returns
    -------
    str
        RFC 4180 CSV (every cell quoted where it needs to be), lines ended by CRLF.
    """
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow([csv_cell(h) for h in table["header"]])
    w.writerows([csv_cell(c) for c in row] for row in table["rows"])
    return buf.getvalue()


def table_latex(table: dict, number: str, caption: str, label: str = "") -> str:
    """A report table as a LaTeX ``table`` with a booktabs ``tabular``.

    Parameters
    ----------
    table : dict
        ``header``, ``rows`` and ``align`` (``"left"``, ``"right"`` or ``"center"`` per column).
    number : str
        The report's number of the table ("4.1"): its label is ``tab:gd-4.1``.
    caption : str
        The caption, marked.
    label : str, optional
        The report's name in the label: ``tab:gd-control-2.1`` with ``"control"`` (default:
        none, ``tab:gd-4.1``).

    Returns
    -------
    str
        Needs ``\\usepackage{booktabs}``, and a Unicode engine (XeLaTeX, LuaLaTeX) or
        ``\\usepackage[utf8]{inputenc}`` with the Greek and combining characters declared.
    """
    cols = "".join(_ALIGN.get(a, "l") for a in table["align"])
    lines = [r"\begin{table}[htbp]", r"\centering",
             r"\caption{" + latex_text(caption) + "}", r"\label{tab:gd-" + (label + "-" if label else "") + number + "}",
             r"\begin{tabular}{" + cols + "}", r"\toprule",
             " & ".join(latex_text(h) for h in table["header"]) + r" \\", r"\midrule"]
    lines += [" & ".join(latex_text(c) for c in row) + r" \\" for row in table["rows"]]
    lines += [r"\bottomrule", r"\end{tabular}", r"\end{table}"]
    return "\n".join(lines) + "\n"


_CAPTION = re.compile(r"^Table ([0-9]+(?:\.[0-9]+)?): (.*)$", re.S)


def table_files(outline: Outline, latex: bool = False, prefix: str = "") -> dict[str, str]:
    """Every table of a report's outline as file text, by file name.

    Parameters
    ----------
    outline : gd_analyze.report.sections.Outline
        The report's sections: its tables, numbered as the report numbers them.
    latex : bool, optional
        Also each table as LaTeX.
    prefix : str, optional
        The report's name, which heads each file's name and LaTeX label (``"control"``:
        ``control_table_2_1.csv``, ``tab:gd-control-2.1``), so that the tables of reports
        sharing a folder never collide (default: none, the main report's).

    Returns
    -------
    dict of str to str
        ``table_4_1.csv`` (and ``table_4_1.tex``) to its text, in the report's order.
    """
    out = {}
    for section in outline.sections:
        for b in section.blocks:
            if b.kind != "table":
                continue
            m = _CAPTION.match(b.caption)
            if m is None:
                raise ValueError(f"a table caption without its number: {b.caption[:60]!r}")
            number, caption = m.groups()
            name = (prefix + "_" if prefix else "") + "table_" + number.replace(".", "_")
            out[name + ".csv"] = table_csv(b.content)
            if latex:
                out[name + ".tex"] = table_latex(b.content, number, caption, prefix)
    return out


def write_tables(stack: contextlib.ExitStack, outline: Outline,
                 folder: str | os.PathLike[str], latex: bool = False,
                 prefix: str = "") -> list[Path]:
    """Write every table of a report's outline to ``folder``, staged with the report's files.

    Parameters
    ----------
    stack : contextlib.ExitStack
        The report's stack of staged files: each table is written under a temporary name
        (:func:`gd_analyze.files.atomic_path`) and renamed when the stack closes without error,
        with the report it belongs to.
    outline : gd_analyze.report.sections.Outline
        The report's sections (:func:`table_files`).
    folder : str or os.PathLike
        The tables' folder (``tables/`` beside the report); made if missing.
    latex : bool, optional
        Also each table as LaTeX.
    prefix : str, optional
        The report's name heading the files' names (:func:`table_files`).

    Returns
    -------
    list of pathlib.Path
        ``folder/[<prefix>_]table_<section>_<k>.csv`` (and ``.tex``), in the report's order.

    Raises
    ------
    ValueError
        If a table's caption carries no number.
    OSError
        If a file cannot be written.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    out = []
    for name, text in table_files(outline, latex, prefix).items():
        path = folder / name
        with open(stack.enter_context(atomic_path(path)), "w", encoding="utf-8",
                  newline="") as fh:
            fh.write(text)
        out.append(path)
    return out
