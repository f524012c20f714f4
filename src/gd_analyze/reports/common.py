"""Helpers shared by the three reports (:mod:`gd_analyze.reports.main`, :mod:`gd_analyze.reports.sweep`
and :mod:`gd_analyze.reports.control`).

Number and attribute formatting (from :mod:`gd_analyze.reports.numbers`), the table
dictionaries the Jinja2 templates and the PDF writers read, matplotlib style contexts,
fixed-layout grids, inline SVG figures and the rendering of a report's template. Private: the reports' output is the interface, not these functions.
"""

from __future__ import annotations

import contextlib
import datetime
import io
import math
import re
from importlib import resources

import numpy as np

from .numbers import attr, fmt, pct, pct_column

#: A4 portrait and landscape [in].
A4 = (8.27, 11.69)
A4_LANDSCAPE = (11.69, 8.27)

#: Colour-blind-safe colours (Okabe & Ito) of the dominance classes, the same in every report.
__all__ = ["CLASS_COLOURS", "BASE_RC", "SUPTITLE_RC", "A4", "A4_LANDSCAPE", "style", "utc_now",
           "keep_units",
           "strings", "fmt", "pct", "pct_column", "attr", "thresholds", "check", "table",
           "grid_shape", "joint_colours", "joint_style", "JOINT_STYLES", "MAX_MARKERS",
           "MIN_MARKERS", "markevery", "panel_markevery",
           "gridspec", "svg", "inline_svgs", "render_template", "check_formats",
           "prismatic_joints", "torque_units", "FORMULATION_NAMES", "FORMULATION_ABBR",
           "element_units_of", "units_text", "units_said_once"]

CLASS_COLOURS = {"translational": "#0072B2", "rotational": "#D55E00", "both": "#6A3D9A",
                 "negligible": "#777777"}

#: matplotlib settings every report uses; each adds its own to them (see :func:`style`).
BASE_RC = {
    "font.size": 8.0,
    "axes.titlesize": 8.5,
    "axes.labelsize": 8.0,
    "xtick.labelsize": 7.0,
    "ytick.labelsize": 7.0,
    "axes.grid": True,
    "grid.color": "0.88",
    "grid.linewidth": 0.5,
    "lines.linewidth": 1.0,
    "svg.fonttype": "none",      # text stays text in the SVG: searchable and small
    "pdf.fonttype": 42,          # embed TrueType fonts in the PDF
    "path.simplify": True,
}
#: :data:`BASE_RC` with bold 11 pt figure titles, 8 pt legends and thin axes lines (the
#: analysis and the sweep report).
SUPTITLE_RC = {**BASE_RC, "legend.fontsize": 8.0, "figure.titlesize": 11.0,
               "figure.titleweight": "bold", "axes.linewidth": 0.6}


def style(rc):
    """A context in which matplotlib draws with the settings ``rc``.

    Parameters
    ----------
    rc : dict
        rcParams to set, e.g. :data:`SUPTITLE_RC`; the others keep their current values.

    Returns
    -------
    contextlib.AbstractContextManager
        :func:`matplotlib.rc_context` of ``rc``.
    """
    import matplotlib

    return matplotlib.rc_context(rc)


def utc_now():
    """The current UTC time, to the second.

    Returns
    -------
    datetime.datetime
        Time-zone aware, microseconds zero.
    """
    return datetime.datetime.now(datetime.timezone.utc).replace(microsecond=0)


def strings(values):
    """Values of a dataset variable as a flat list of str (bytes decoded).

    Parameters
    ----------
    values : array_like
        Strings or bytes, any shape.

    Returns
    -------
    list of str
    """
    return [v.decode() if isinstance(v, bytes) else str(v) for v in np.asarray(values).ravel()]


def thresholds(ds):
    """The dominance threshold s and the negligibility threshold e stored in a dataset.

    Parameters
    ----------
    ds : xarray.Dataset
        With attributes ``dominance_threshold`` and ``negligible_threshold``.

    Returns
    -------
    s, e : float
        NaN where an attribute is missing.
    """
    return (float(ds.attrs.get("dominance_threshold", np.nan)),
            float(ds.attrs.get("negligible_threshold", np.nan)))


def check(ds, required, what):
    """Raise if a dataset lacks a variable a report needs.

    Parameters
    ----------
    ds : xarray.Dataset
        The dataset.
    required : sequence of str
        Names of the variables needed.
    what : str
        The kind of dataset, for the message ("results", "sweep", ...).

    Raises
    ------
    InputError
        Naming the missing variables.
    """
    missing = [v for v in required if v not in ds.variables]
    if missing:
        from ..errors import InputError

        raise InputError(f"not a gd-analyze {what} dataset: missing variable(s) "
                         + ", ".join(missing))


#: Units in brackets in a column heading: kept on one line (no-break spaces).
_UNITS = re.compile(r"\[[^\]\n]{1,16}\]")


def keep_units(text):
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


#: How the report names each formulation and implementation of the stored comparison (the
#: key is the name in the dataset), in full and abbreviated.
FORMULATION_NAMES = {"lagrange-euler": "Lagrange-Euler", "newton-euler": "Newton-Euler",
                     "gd": "G-D, compiled engine", "gd-numpy": "G-D, array engine",
                     "pinocchio": "Pinocchio"}
FORMULATION_ABBR = {"lagrange-euler": "L-E", "newton-euler": "N-E", "gd": "G-D",
                    "gd-numpy": "G-D np", "pinocchio": "Pinocchio"}


def table(header, rows, align=None, widths=None, colour_cols=()):
    """A table as the templates and the PDF writers read it.

    Parameters
    ----------
    header : sequence of str
        Column headings.
    rows : sequence of sequence
        The cells, converted with ``str``; a cell that is an element's label (``D12``,
        ``D1,10``, ``h3``) is lettered as the figures letter it, ``D₁₂``
        (:func:`gd_analyze.reports.markup.label`).
    align : sequence of str or {"right"}, optional
        ``"left"`` or ``"right"`` per column; ``"right"``: the first column left, the others
        right. Default: all left.
    widths : sequence of float, optional
        Relative column widths (PDF of the analysis report); default all 1.
    colour_cols : sequence of int, optional
        Columns whose cells are dominance classes, drawn in their colour.

    Returns
    -------
    dict
        Keys ``header``, ``rows``, ``align``, ``widths`` and ``colour_cols``.
    """
    if isinstance(align, str):
        align = ["left"] + [align] * (len(header) - 1)
    from .markup import label

    header = [keep_units(h) for h in header]
    return {"header": header, "rows": [[label(str(c)) for c in row] for row in rows],
            "align": list(align or ["left"] * len(header)),
            "widths": list(widths or [1] * len(header)), "colour_cols": list(colour_cols)}


def grid_shape(n, max_cols):
    """Rows and columns of a grid of n panels, at most ``max_cols`` a row.

    Parameters
    ----------
    n : int
        Number of panels.
    max_cols : int
        Most columns.

    Returns
    -------
    rows, cols : int
    """
    cols = max(1, min(max_cols, n))
    return math.ceil(n / cols), cols


def joint_colours(n):
    """One colour per joint from the tab10 colour map.

    Parameters
    ----------
    n : int
        How many colours.

    Returns
    -------
    list of tuple
        RGBA, the ten of tab10 in turn.
    """
    from matplotlib import colormaps

    cmap = colormaps["tab10"]
    return [cmap(k % 10) for k in range(n)]


#: Line style and marker of joints 1..7: no two joints share either, so that seven lines are
#: told apart in greyscale (dash patterns as (offset, (on, off, ...)) in points).
JOINT_STYLES = (("-", "o"), ((0, (4.0, 1.6)), "s"), ((0, (1.0, 1.3)), "^"),
                ((0, (5.0, 1.5, 1.0, 1.5)), "D"), ((0, (2.2, 1.4)), "v"),
                ((0, (6.0, 1.5, 1.0, 1.5, 1.0, 1.5)), "x"), ((0, (8.0, 2.0)), "+"))


def joint_style(j, n_lines=1, in_panel=1):
    """Colour, line style and marker of joint ``j`` (0-based): distinct for up to 7 joints.

    Parameters
    ----------
    j : int
        The joint, 0-based.
    n_lines : int, optional
        Set points on the line.
    in_panel : int, optional
        Lines on the panel: together they carry at most about :data:`MAX_MARKERS` markers
        (:func:`panel_markevery`).

    Returns
    -------
    dict
        Keyword arguments of :meth:`matplotlib.axes.Axes.plot`: ``color`` (Okabe & Ito
        colour-blind-safe set, then tab10), ``linestyle``, ``marker`` (open), ``markevery``,
        ``markersize``; the markers of joint j start at an offset so that two joints' markers
        do not fall on the same set points.
    """
    colours = ("#000000", "#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9")
    ls, marker = JOINT_STYLES[j % len(JOINT_STYLES)]
    colour = colours[j] if j < len(colours) else joint_colours(j + 1)[j]
    every = panel_markevery(n_lines, in_panel)
    offset = (j * max(1, every // 7)) % every if every > 1 else 0
    return {"color": colour, "linestyle": ls, "marker": marker, "markevery": (offset, every),
            "markersize": 3.0, "markerfacecolor": "none", "markeredgewidth": 0.7}


#: The most markers drawn on one panel, all its lines together: more merge into a band at
#: print size (each line keeps at least :data:`MIN_MARKERS`).
MAX_MARKERS = 12
#: The fewest markers of a line that has any: enough to tell its marker.
MIN_MARKERS = 2


def panel_markevery(m, lines):
    """The stride of the markers of each of ``lines`` lines of ``m`` points on one panel.

    Parameters
    ----------
    m : int
        Points on each line.
    lines : int
        Lines with markers on the panel.

    Returns
    -------
    int
        :func:`markevery` for at most ``max(MIN_MARKERS, MAX_MARKERS // lines)`` markers a
        line: at most about :data:`MAX_MARKERS` on the panel.

    Examples
    --------
    >>> panel_markevery(31, 3), panel_markevery(31, 6), panel_markevery(8, 1)
    (8, 16, 1)
    """
    return markevery(m, max(MIN_MARKERS, MAX_MARKERS // max(1, int(lines))))


def markevery(m, most=MAX_MARKERS):
    """The stride that leaves at most ``most`` markers on a line of ``m`` points.

    Parameters
    ----------
    m : int
        Points on the line.
    most : int, optional
        The most markers (:data:`MAX_MARKERS`).

    Returns
    -------
    int
        k >= 1 with ceil(m / k) <= most (markers at points 0, k, 2k, ...).

    Examples
    --------
    >>> markevery(31), markevery(12), markevery(0)
    (3, 1, 1)
    """
    return max(1, -(-int(m) // max(1, int(most))))


def gridspec(fig, rows, cols, left, right, top, bottom, wgap, hgap):
    """A gridspec with margins and gaps in inches (a fixed layout: no layout engine).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    rows, cols : int
        Grid shape.
    left, right, top, bottom : float
        Margins [in].
    wgap, hgap : float
        Gaps between columns and between rows [in].

    Returns
    -------
    matplotlib.gridspec.GridSpec
    """
    W, H = fig.get_size_inches()
    aw = (W - left - right - (cols - 1) * wgap) / cols
    ah = (H - top - bottom - (rows - 1) * hgap) / max(rows, 1)
    return fig.add_gridspec(rows, cols, left=left / W, right=1 - right / W, bottom=bottom / H,
                            top=1 - top / H, wspace=wgap / aw, hspace=hgap / ah)


def svg(fig, prefix=None, rc=None):
    """A figure as an inline ``<svg>`` element.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    prefix : str, optional
        Put before every id, and the references to it, so that several figures can share one
        HTML document without clashing ids.
    rc : dict, optional
        rcParams to draw with (:func:`style`).

    Returns
    -------
    str
        The SVG without XML declaration and DOCTYPE (whose DTD is an external resource) and
        without date or creator metadata.
    """
    buf = io.StringIO()
    with style(rc) if rc is not None else contextlib.nullcontext():
        fig.savefig(buf, format="svg",
                    metadata={"Date": None, "Creator": None, "Format": None, "Type": None})
    text = buf.getvalue()
    start = text.find("<svg")
    text = text[start:] if start >= 0 else text
    if prefix is None:
        return text
    text = re.sub(r'\bid="', f'id="{prefix}-', text)
    text = re.sub(r'\bhref="#', f'href="#{prefix}-', text)
    return re.sub(r"url\(#", f"url(#{prefix}-", text)


def inline_svgs(figures, rc, prefix_ids=True):
    """Figures as inline SVG markup for a template.

    Parameters
    ----------
    figures : dict of str to matplotlib.figure.Figure
        The figures by name.
    rc : dict
        rcParams to draw with.
    prefix_ids : bool, optional
        Prefix the ids of each figure with ``fig-<name>`` (:func:`svg`).

    Returns
    -------
    dict of str to markupsafe.Markup
    """
    from markupsafe import Markup

    return {name: Markup(svg(fig, f"fig-{name}" if prefix_ids else None, rc))
            for name, fig in figures.items()}


def render_template(name, context, env_globals=None):
    """Render one of the package's Jinja2 templates (autoescape on, strict undefined).

    Parameters
    ----------
    name : str
        File name under ``gd_analyze/reports/templates``.
    context : dict
        The template's variables.
    env_globals : dict, optional
        Globals of the environment (e.g. ``class_colours``).

    Returns
    -------
    str
        The rendered document.
    """
    import jinja2

    from . import markup

    def source(template):
        return resources.files("gd_analyze.reports").joinpath(f"templates/{template}") \
            .read_text(encoding="utf-8")

    def finalize(value):                # sub- and superscripts as tags, the rest escaped
        if isinstance(value, str) and (markup.SUB in value or markup.SUP in value):
            return markup.html(value)
        return value

    env = jinja2.Environment(loader=jinja2.FunctionLoader(source), autoescape=True,
                             undefined=jinja2.StrictUndefined, finalize=finalize,
                             trim_blocks=True, lstrip_blocks=True, keep_trailing_newline=True)
    env.globals.update(env_globals or {})
    return env.get_template(name).render(**context)


def check_formats(formats, allowed):
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


def prismatic_joints(ds):
    """Which joints are prismatic (q in m), from the stored ``joint_type`` (all revolute in a
    dataset without it).

    Parameters
    ----------
    ds : xarray.Dataset
        A stored analysis.

    Returns
    -------
    ndarray of bool, shape (n,)
    """
    if "joint_type" not in ds.variables:
        return np.zeros(ds.sizes["joint"], dtype=bool)
    return np.array([t == "prismatic" for t in strings(ds["joint_type"].values)])


def units_text(u):
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


def torque_units(ds):
    """The printed units of tau_i, h_i and c_i per joint: N m, or N for a prismatic joint.

    Parameters
    ----------
    ds : xarray.Dataset

    Returns
    -------
    list of str, length n
        From :func:`gd_analyze.core.selection.labels.joint_torque_units`.
    """
    from ..core.selection.ranking import joint_torque_units

    return [joint_torque_units(p) for p in prismatic_joints(ds)]


def element_units_of(ds):
    """The printed units of the ranked elements (kg m², kg m, kg, N m, N), from the joint types.

    Parameters
    ----------
    ds : xarray.Dataset
        With the ``element`` coordinate.

    Returns
    -------
    list of str, length M
        From :func:`gd_analyze.core.selection.labels.element_units`.
    """
    from ..core.selection.ranking import element_units, parse_element_label

    n, prismatic = ds.sizes["joint"], prismatic_joints(ds)
    return [units_text(element_units(*parse_element_label(lab, n), prismatic))
            for lab in strings(ds["element"].values)]


def units_said_once(ds, kind):
    """The units of every D_ij or every tau_i in words, for captions and keys.

    Parameters
    ----------
    ds : xarray.Dataset
    kind : str
        ``"D"`` or ``"tau"``.

    Returns
    -------
    str
        ``"kg m²"`` or ``"N m"`` for an all-revolute arm; for a mixed one, each unit with where
        it holds (``"N m (joints 1, 2), N (joint 3)"``; ``"kg m² where joints i and j are both
        revolute, kg m where one is prismatic, kg where both are"``).
    """
    from ..core.selection.ranking import joint_units_text

    if kind != "D":
        return joint_units_text(torque_units(ds))
    prismatic = prismatic_joints(ds)
    where = {"kg m\u00b2": "kg m\u00b2 where joints i and j are both revolute",
             "kg m": "kg m where one of them is prismatic", "kg": "kg where both are"}
    n = len(prismatic)
    found = {["kg m\u00b2", "kg m", "kg"][int(prismatic[i]) + int(prismatic[j])]
             for i in range(n) for j in range(i, n)}
    if len(found) == 1:
        return found.pop()
    return ", ".join(where[u] for u in where if u in found)
