"""Helpers shared by the three reports (:mod:`gd_analyze.report.main`, :mod:`gd_analyze.report.sweep`
and :mod:`gd_analyze.report.control`).

Reading a dataset's strings and attributes, the table dictionaries the Jinja2 templates and the
PDF writers read, the rendering of a report's template, and the units by joint type: a
revolute joint's torque in N m and its D elements in kg m², a prismatic joint's force in N and
its elements in kg m or kg; units in headings kept on one line. The number formats
(:mod:`gd_analyze.report.numbers`) are re-exported here; the figure style is
:mod:`gd_analyze.report.figure_style`. Private: the reports' output is
the interface, not these functions.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Callable, Iterable, Mapping, Sequence
from importlib import resources
from typing import TYPE_CHECKING, Any

import numpy as np

from ..ranking.ranking import ROUND_OFF, ROUND_OFF_CLAUSE, joint_torque_units, joint_units_text
from ..store.results_view import Results
from ..store.schema import EvaluatorCosts, stored_prismatic, strings, utc_now
from ..store.sweep_view import MergedModel
from . import markup
from .markup import clean, marked, powers
from .numbers import count, fmt, fmt_column, fmt_columns, given, pct, pct_column, pct_columns, share
from .numbers import decade_label as _decade_label

if TYPE_CHECKING:
    import numpy.typing as npt
    import xarray as xr

__all__ = ["CLASS_COLOURS", "utc_now", "keep_units", "strings", "fmt", "fmt_column",
           "fmt_columns", "given", "count", "share", "pct", "pct_column", "pct_columns",
           "attr_text", "table", "render_template", "say", "check_formats",
           "prismatic_joints", "torque_units", "FORMULATION_NAMES", "FORMULATION_ABBR",
           "units_text", "units_said_once", "cost_table", "settings_table", "other_rows",
           "or_default", "joints_text"]

#: Colour-blind-safe colours (Okabe & Ito) of the dominance classes, the same in every report.
CLASS_COLOURS = {"translational": "#0072B2", "rotational": "#D55E00", "both": "#6A3D9A",
                 "negligible": "#777777"}


def attr_text(value: object, default: str = "\u2014", *, parens: bool = True,
              bools: bool = False, sci_outside: tuple[float, float] | None = None) -> str:
    """An attribute's stored value as text.

    Parameters
    ----------
    value : object
        The value as stored (a string, bytes, a number, an array), or None where missing.
    default : str, optional
        Returned if the value is missing or empty.
    parens : bool, optional
        Put an array's values, joined by ", ", in parentheses.
    bools : bool, optional
        Format booleans as numbers (``1``) rather than as ``True``.
    sci_outside : (float, float), optional
        Passed to :func:`fmt` (numbers are written with 6 digits).

    Returns
    -------
    str
        An integer as a count with thousands separators (:func:`count`).
    """
    if value is None:
        return default
    if isinstance(value, bytes):
        value = value.decode()
    if isinstance(value, np.ndarray):
        text = ", ".join(fmt(v, 6, sci_outside) for v in value.ravel())
        return f"({text})" if parens else text
    if isinstance(value, (np.integer, int)) and not isinstance(value, (bool, np.bool_)):
        return count(value)             # a count, as every count: 1,212
    if isinstance(value, (np.generic, float, int)) and (
            bools or not isinstance(value, (bool, np.bool_))):
        return fmt(value, 6, sci_outside)

    text = clean(str(value))            # no sub/superscript marks from a file's text
    return powers(text) if text else default      # unit powers (s^-1) as superscripts


def or_default(value: Any, default: Any) -> Any:
    """A stored attribute's value, or ``default`` where it is missing.

    Parameters
    ----------
    value : object or None
        The value as stored; None where missing.
    default : object
        What stands for a missing value.

    Returns
    -------
    object
        ``value`` unless it is None (a stored 0 or "" is kept), else ``default``.
    """
    return default if value is None else value


def joints_text(joints: Sequence[object]) -> str:
    """Joints named by number, the noun agreeing with their count.

    Parameters
    ----------
    joints : sequence of int or str, length >= 1
        The joints' numbers (one-based), in the order said.

    Returns
    -------
    str
        "joint 3" for one, "joints 1, 2, 4" for several.
    """
    return f"joint{'s' if len(joints) > 1 else ''} {', '.join(map(str, joints))}"


#: How the report names each formulation and implementation of the stored comparison (the
#: key is the name in the dataset), in full and abbreviated.
FORMULATION_NAMES = {"lagrange-euler": "Lagrange-Euler", "newton-euler": "Newton-Euler",
                     "gd": "G-D, compiled engine", "gd-numpy": "G-D, array engine",
                     "pinocchio": "Pinocchio"}
FORMULATION_ABBR = {"lagrange-euler": "L-E", "newton-euler": "N-E", "gd": "G-D",
                    "gd-numpy": "G-D np", "pinocchio": "Pinocchio"}


def table(header: Sequence[str], rows: Sequence[Sequence[Any]],
          align: Sequence[str] | str | None = None, widths: Sequence[float] | None = None,
          colour_cols: Sequence[int] = (),
          cells: Callable[[str], str] = marked) -> dict[str, Any]:
    """A table as the templates and the PDF writers read it.

    Parameters
    ----------
    header : sequence of str
        Column headings.
    rows : sequence of sequence
        The cells, converted with ``str``; a cell that is an element's label (``D12``,
        ``D1,10``, ``h3``) is lettered as mathematics, its index a subscript
        (:func:`gd_analyze.report.markup.marked`).
    align : sequence of str or {"right"}, optional
        ``"left"`` or ``"right"`` per column; ``"right"``: the first column left, the others
        right. Default: all left.
    widths : sequence of float, optional
        Relative column widths (PDF of the analysis report); default all 1.
    colour_cols : sequence of int, optional
        Columns whose cells are dominance classes, drawn in their colour.
    cells : callable, optional
        Each cell's text as shown: by default element labels lettered as mathematics
        (:func:`gd_analyze.report.markup.marked`); :func:`gd_analyze.report.markup.clean`
        leaves a cell as text (names from a file).

    Returns
    -------
    dict
        Keys ``header``, ``rows``, ``align``, ``widths`` and ``colour_cols``.
    """
    if isinstance(align, str):
        align = ["left"] + [align] * (len(header) - 1)

    header = [keep_units(h) for h in header]
    return {"header": header, "rows": [[cells(str(c)) for c in row] for row in rows],
            "align": list(align or ["left"] * len(header)),
            "widths": list(widths or [1] * len(header)), "colour_cols": list(colour_cols)}


def settings_table(rows: Iterable[Sequence[Any]], *, widths: Sequence[float] | None = None,
                   cells: Callable[[str], str] = marked) -> dict[str, Any]:
    """A report's table of settings or provenance: one row (item, value) a setting, the rows
    a file does not record left out (the main, control, identification and sweep reports).

    Parameters
    ----------
    rows : iterable of (str, object)
        Each setting's item and its value as shown; a value None leaves its row out.
    widths : sequence of float, optional
        Relative column widths (:func:`table`); default both 1.
    cells : callable, optional
        Each cell's text as shown (:func:`table`).

    Returns
    -------
    dict
        :func:`table` of the columns "item" and "value", both left-aligned.
    """
    return table(["item", "value"], [row for row in rows if row[1] is not None],
                 widths=widths, cells=cells)


def other_rows(others: Iterable[Sequence[Any]]) -> list[tuple[str, str]]:
    """The rows of the attributes a file stores that a report names nowhere else, each once.

    Parameters
    ----------
    others : iterable of (str, object) or (str, object, object)
        Each attribute's name and stored value, and optionally the setting asked for that
        it records (None where none is).

    Returns
    -------
    list of (str, str)
        (name with spaces for underscores, value as text: :func:`attr_text`); an attribute
        that records a setting asked for with the same value is left out (the setting's row
        says it).
    """
    return [(key.replace("_", " "), attr_text(value)) for key, value, *asked in others
            if not asked or asked[0] is None or attr_text(asked[0]) != attr_text(value)]


def cost_table(ds: EvaluatorCosts | xr.Dataset | None) -> dict[str, Any] | None:
    """The operations per set point of each evaluator a dataset stores, as a table.

    Parameters
    ----------
    ds : EvaluatorCosts, xarray.Dataset or None
        The counts (:class:`gd_analyze.store.schema.EvaluatorCosts`), or a dataset with
        ``multiplications`` and ``additions`` over dim ``evaluator``, Newton-Euler last
        (the control dataset, :func:`gd_analyze.jobs.control.model_cost`; the sweep,
        :func:`gd_analyze.jobs.sweep_merged.with_model_cost`).

    Returns
    -------
    dict or None
        :func:`table` of evaluator, multiplications, additions, operations and operations
        relative to Newton-Euler; None if no counts are stored.
    """
    costs = ds if ds is None or isinstance(ds, EvaluatorCosts) else \
        EvaluatorCosts.from_dataset(ds)
    if costs is None:
        return None
    names = costs.evaluators
    mul, add = costs.multiplications, costs.additions
    ref = len(names) - 1                 # the last: Newton-Euler, the recursive reference
    return table(["evaluator", "multiplications", "additions", "operations",
                  "operations vs Newton-Euler"],
                 [[e, count(mul[k]), count(add[k]), count(mul[k] + add[k]),
                   f"{(mul[k] + add[k]) / (mul[ref] + add[ref]):.3f}"]
                  for k, e in enumerate(names)], align=["left"] + ["right"] * 4,
                 widths=[2.2, 1, 1, 1, 1.2])          # the evaluators' names on one line


#: A number's space before its percent sign, in the text and tables (not in the drawings,
#: given as markup): a line may not break there in the HTML (the PDF template's rule likewise).
_PERCENT = re.compile(r"(?<=\d) (?=%)")


def render_template(name: str, context: Mapping[str, Any],
                    env_globals: Mapping[str, Any] | None = None) -> str:
    """Render one of the package's Jinja2 templates (autoescape on, strict undefined).

    Parameters
    ----------
    name : str
        File name under ``gd_analyze/report/templates``.
    context : dict
        The template's variables.
    env_globals : dict, optional
        Globals of the environment (e.g. ``class_colours``).

    Returns
    -------
    str
        The rendered document.

    Notes
    -----
    The environment is made once a process per set of globals (:data:`_ENVIRONMENTS`), so
    that each template (and the macros it imports) is compiled once a process, not once a
    report: Jinja2 keeps the templates it loaded, and loads one again if its file changed.
    """
    import jinja2

    key = tuple((k, id(v)) for k, v in (env_globals or {}).items())
    if key not in _ENVIRONMENTS:
        env = jinja2.Environment(loader=jinja2.PackageLoader("gd_analyze.report"),
                                 autoescape=True, undefined=jinja2.StrictUndefined,
                                 finalize=_finalize, trim_blocks=True, lstrip_blocks=True,
                                 keep_trailing_newline=True)
        env.globals.update(env_globals or {})
        _ENVIRONMENTS[key] = env
    return _ENVIRONMENTS[key].get_template(name).render(**context)


#: The environments of :func:`render_template` by their globals' names and their values'
#: identities (an environment holds its values, so no other object takes their identity).
_ENVIRONMENTS: dict[tuple[tuple[str, int], ...], Any] = {}


def _finalize(value):
    """How the report templates print a value: sub-, superscripts and code as tags, the rest
    escaped (by the autoescape), a number's space before its percent sign kept."""
    from markupsafe import Markup

    if not isinstance(value, str):
        return value
    if not isinstance(value, Markup):
        value = _PERCENT.sub("\u00a0", value)          # "1.23 %" kept on one line
    if any(m in value for m in (markup.SUB, markup.SUP, markup.CODE)):
        return markup.html(value)
    shown = markup.visible(value)   # format characters (bidi controls) made visible
    return value if shown == value else (
        Markup(shown) if isinstance(value, Markup) else shown)


def say(name: str, /, **values: Any) -> str:
    """A passage of the reports' fixed wording, its values filled in.

    The passages are the Jinja2 macros of ``templates/wording.j2``: the prose lives there, the
    code computes the values. The text is returned as it is, not escaped: it is escaped where
    a report writes it (the HTML template's autoescape, the PDF's typesetter), as any other
    text of a report, so a value read from a file (a robot's name) stays inert.

    Parameters
    ----------
    name : str
        The macro's name.
    **values
        Its arguments, by name.

    Returns
    -------
    str
        The passage, which may hold the marks of :mod:`gd_analyze.report.markup`.

    Examples
    --------
    >>> say("plural", k=1, one="trajectory", many="trajectories")
    'trajectory'
    """
    return str(_passage(name)(**values))


@functools.cache
def _passages() -> dict[str, str]:
    """The macros of ``templates/wording.j2`` by name, in the file's order, each one's source
    as Jinja2 reads the file: a line break reads as one space, and as nothing after a
    ``{% tag %}`` or a ``{# comment #}`` or before a line starting with one; ``~`` is a
    no-break space (as in TeX). Outside its macros the file holds comments only, and no macro
    holds another."""
    text = resources.files("gd_analyze.report").joinpath("templates/wording.j2") \
        .read_text(encoding="utf-8")
    text = re.sub(r"(?<=%}|#})\n|[ \t]*\n(?={[%#])", "", text)
    text = re.sub(r"[ \t]*\n", " ", text).replace("~", "\u00a0")
    return {m.group(1): m.group(0)
            for m in re.finditer(r"{% macro (\w+)\(.*?{% endmacro %}", text, re.DOTALL)}


@functools.cache
def _passage(name: str) -> Callable[..., Any]:
    """One macro of ``templates/wording.j2``, compiled once a process, on its own: each other
    macro whose name it holds as a word (a superset of those it calls) is handed to it
    compiled in the same way. A report compiles the wording it says, not the whole file."""
    import jinja2

    source, passages = _passages()[name], _passages()
    env = jinja2.Environment(undefined=jinja2.StrictUndefined, autoescape=False)
    env.globals.update(sub=markup.sub, sup=markup.sup, code=markup.code,
                       element=markup.element, tau=markup.tau, round_off=ROUND_OFF_CLAUSE,
                       tiny=_decade_label(ROUND_OFF))
    env.globals.update({m: _passage(m) for m in set(re.findall(r"\w+", source)) & passages.keys()
                        if m != name})
    env.filters.update(count=count)
    return getattr(env.from_string(source).module, name)  # type: ignore[no-any-return]


def check_formats(formats: str | Sequence[str], allowed: tuple[str, ...]) -> list[str]:
    """The report formats asked for, checked, lower case and without repeats.

    Parameters
    ----------
    formats : str or sequence of str
        One format or several.
    allowed : tuple of str
        The formats the report can write.

    Returns
    -------
    list of str
        In the order first given.

    Raises
    ------
    ValueError
        If a format is not allowed, or none is given.
    """
    if isinstance(formats, str):
        formats = (formats,)
    formats = [str(f).lower() for f in formats]
    if not formats or any(f not in allowed for f in formats):
        raise ValueError(f"report formats must be among {allowed}, got {formats}")
    return list(dict.fromkeys(formats))


# --------------------------------------------------------------------------------------------
# Units by joint type
# --------------------------------------------------------------------------------------------
#: Units in brackets in a column heading: kept on one line (no-break spaces).
_UNITS = re.compile(r"\[[^\]\n]{1,16}\]")


def keep_units(text: object) -> str:
    """Text with the spaces inside its bracketed units made no-break: "[N m]" is never split
    over two lines.

    Parameters
    ----------
    text : object
        Converted with ``str``.

    Returns
    -------
    str

    Examples
    --------
    >>> keep_units("peak error [N m]") == "peak error [N\u00a0m]"
    True
    """
    return _UNITS.sub(lambda m: m.group().replace(" ", "\u00a0"), str(text))


def prismatic_joints(ds: Results | MergedModel | xr.Dataset) -> npt.NDArray[np.bool_]:
    """Which joints are prismatic (q in m), from the stored ``joint_type`` (all revolute in a
    dataset without it).

    Parameters
    ----------
    ds : Results, MergedModel or xarray.Dataset
        A stored analysis or sweep, typed (:class:`gd_analyze.store.results_view.Results`,
        :class:`gd_analyze.store.sweep_view.MergedModel`) or not.

    Returns
    -------
    ndarray of bool, shape (n,)
    """
    return np.array(ds.prismatic if isinstance(ds, (Results, MergedModel)) else
                    stored_prismatic(ds), dtype=bool)


def units_text(u: str) -> str:
    """Stored units as printed: ``"kg m2"`` -> ``"kg m²"``, ``"s-2"`` -> ``"s⁻²"``.

    Parameters
    ----------
    u : str

    Returns
    -------
    str
    """
    return (str(u).replace("m2", "m\u00b2").replace("s-2", "s\u207b\u00b2")
            .replace("s-1", "s\u207b\u00b9"))


def torque_units(ds: Results | MergedModel | xr.Dataset) -> list[str]:
    """The printed units of tau_i, h_i and c_i per joint: N m, or N for a prismatic joint.

    Parameters
    ----------
    ds : Results, MergedModel or xarray.Dataset

    Returns
    -------
    list of str, length n
        From :func:`gd_analyze.ranking.labels.joint_torque_units`.
    """
    return [joint_torque_units(p) for p in prismatic_joints(ds)]


def units_said_once(ds: Results | xr.Dataset, kind: str) -> str:
    """The units of every D_ij or every tau_i in words, for captions and keys.

    Parameters
    ----------
    ds : Results or xarray.Dataset
    kind : str
        ``"D"`` or ``"tau"``.

    Returns
    -------
    str
        ``"kg m²"`` or ``"N m"`` for an all-revolute arm; for a mixed one, each unit with where
        it holds (``"N m (joints 1, 2), N (joint 3)"``; ``"kg m² where joints i and j are both
        revolute, kg m where one is prismatic, kg where both are"``).
    """
    if kind != "D":
        return joint_units_text(torque_units(ds))
    prismatic = prismatic_joints(ds)
    n = len(prismatic)
    return say("d_units", found=sorted({int(prismatic[i]) + int(prismatic[j])     # prismatic
                                        for i in range(n) for j in range(i, n)}))  # of i, j
