"""Drawing the reports' figures once, as SVG, and writing a report's files from them: the
figure files, the HTML and the PDF documents and the tables.

:func:`draw_figures` renders each matplotlib figure a single time, as SVG (text kept as text,
``svg.fonttype`` "none"); Typst turns that SVG into each figure's PDF file
(:func:`gd_analyze.report.typeset.figure_pdfs`), as it embeds it in the PDF reports, so every
PDF sets the figures' text in a TrueType subset of DejaVu Sans and none holds a Type 3 font.
:func:`write_figure_files` writes them to ``OUTDIR/figures/``; :func:`write_documents` writes
every file of a report, staged together.

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

import contextlib
import csv
import functools
import io
import os
import re
import warnings
from collections.abc import Callable, Collection, Iterator, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..files import atomic_path
from . import markup
from .common import render_template
from .figure_style import raise_small_text, text_extent
from .typeset import MIN_PRINTED_PT, figure_pdfs, fonts_loaded, printed_scale, write_pdf

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from .sections import Outline


__all__ = ["figure_svg", "kept_in_the_draw", "svg_size", "draw_figures", "draw_each",
           "write_figure_files", "prefix_ids", "html_document", "write_documents",
           "write_report_files", "csv_cell", "latex_text", "table_csv", "table_latex",
           "table_files"]

#: A drawn figure: its SVG text, its PDF (None if not typeset) and its size [in].
Drawn = tuple[str, bytes | None, tuple[float, float]]


def figure_svg(fig: Figure, rc: Mapping[str, Any] | None = None) -> str:
    """A figure as SVG text, without XML declaration, DOCTYPE or date metadata.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    rc : dict, optional
        rcParams to draw with.

    Returns
    -------
    str
        Starts with ``<svg``: fit to be a file of its own and to be inlined in HTML.
    """
    import matplotlib

    meta = {"Date": None, "Creator": None, "Format": None, "Type": None}
    extent = []         # measured on the drawing itself: its text laid out once
    buf = io.BytesIO()
    with matplotlib.rc_context(rc or {}), warnings.catch_warnings():  # type: ignore[arg-type]  # keys typed as literals
        # a name in a script DejaVu Sans lacks (a joint named in Japanese): the SVG keeps the
        # text as text, which the reader's fonts show; matplotlib warned once a glyph a drawing
        warnings.filterwarnings("ignore", r"Glyph \d+ .* missing from font", UserWarning)
        # every text at least MIN_PRINTED_PT where the PDF report prints the figure smallest
        raise_small_text(fig, MIN_PRINTED_PT / printed_scale(tuple(fig.get_size_inches())))
        with kept_in_the_draw(fig):     # ticks and text layouts worked out once a drawing
            def measure(event: Any) -> None:    # a DrawEvent (a bare Event to some versions)
                extent.append(text_extent(fig, event.renderer))

            cid = fig.canvas.mpl_connect("draw_event", measure)
            try:
                fig.savefig(buf, format="svg", metadata=meta)
            finally:
                fig.canvas.mpl_disconnect(cid)
            if extent[0].height > fig.bbox_inches.height:   # text sticks out: drawn again,
                buf = io.BytesIO()                           # taller, with the same ticks
                fig.savefig(buf, format="svg", bbox_inches=extent[0], metadata=meta)
    text = buf.getvalue().decode("utf-8")
    start = text.find("<svg")
    return text[start:] if start >= 0 else text


@contextlib.contextmanager
def kept_in_the_draw(fig: Figure) -> Iterator[tuple[dict[int, Any], dict[tuple[Any, ...], Any]]]:
    """Within a ``with`` block, what drawing a figure works out again and again worked out
    once: each axis's ticks, and each text's layout per renderer and setting.

    A drawing asks an axis for its ticks several times: to draw them, and to place its own
    and each shared axis's label clear of their tick labels; measuring the figure just drawn
    (:meth:`matplotlib.figure.Figure.get_tightbbox`, as
    :func:`gd_analyze.report.figure_style.text_extent` does in :func:`figure_svg`), and
    drawing it again taller where its text sticks out, asks again. Each time matplotlib works
    out locator, formatter and a position and label per tick: the same ticks, as nothing
    changes them once the drawing has started (the axes' aspect is applied before, and the
    taller drawing moves the axes, it does not resize them). Within the block each axis
    works them out once, the first time asked; on leaving it, as before.

    Each tick label is laid out four to five times a drawing (the labels placed, the tick
    drawn, the figure measured), and many tick labels read the same ("0", "0.5").
    Matplotlib's layout of a text (its lines' sizes, its box rotated and aligned, relative
    to its anchor) depends on the renderer, the figure's resolution, the string and these
    properties of the text: font, line spacing, multi-line alignment, rotation, alignments
    and rotation mode. Within the block a layout is kept under all of them (the font by the
    values of all its properties) and handed back (its box a copy); a text that wraps (its
    lines depend on where it stands) or is set by TeX is laid out as before.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure; its axes' x, y (and z) axes keep their ticks.

    Yields
    ------
    ticks : dict
        The ticks worked out, by the axis's ``id`` (their number: how many times an axis
        worked its ticks out).
    layouts : dict
        The layouts worked out, by renderer and setting.

    Notes
    -----
    Replaces matplotlib's private ``Axis._update_ticks`` (the ticks to draw, after setting
    their positions and labels) on each axis and ``Text._get_layout`` on the class (3.10 to
    3.11) for the block: the drawing thread is the only one drawing. An axis without
    ``_update_ticks`` works its ticks out as before.
    """
    from matplotlib.text import Text

    axes = [axis for ax in fig.axes for axis in (getattr(ax, f"{a}axis", None) for a in "xyz")
            if axis is not None and hasattr(type(axis), "_update_ticks")]
    ticks: dict[int, Any] = {}
    layouts: dict[tuple[Any, ...], Any] = {}
    work_out = Text._get_layout  # type: ignore[attr-defined]  # private (see Notes)

    def kept_ticks(axis: Any) -> Callable[[], Any]:
        ticks_of = type(axis)._update_ticks
        return lambda: ticks[id(axis)] if id(axis) in ticks else ticks.setdefault(
            id(axis), ticks_of(axis))

    def layout(text: Any, renderer: Any) -> Any:
        if text.get_wrap() or text.get_usetex():
            return work_out(text, renderer)
        key = (renderer, text.figure.dpi, text.get_text(), text.get_parse_math(),
               _font_key(text.get_fontproperties()), text._linespacing,
               text._get_multialignment(), text.get_rotation(), text.get_horizontalalignment(),
               text.get_verticalalignment(), text.get_rotation_mode())
        if key not in layouts:
            layouts[key] = work_out(text, renderer)
        box, lines, corner = layouts[key]
        return box.frozen(), list(lines), corner

    for axis in axes:
        axis._update_ticks = kept_ticks(axis)
    Text._get_layout = layout  # type: ignore[attr-defined]  # for the block
    try:
        yield ticks, layouts
    finally:
        Text._get_layout = work_out  # type: ignore[attr-defined]  # the class's own
        for axis in axes:
            del axis._update_ticks


def _font_key(font: Any) -> tuple[Any, ...]:
    """A font's properties as a key: all of them, a list (matplotlib 3.10 keeps the families
    as one) as a tuple."""
    return tuple((k, tuple(v) if isinstance(v, list) else v) for k, v in vars(font).items())


def svg_size(svg: str) -> tuple[float, float]:
    """The width and height [in] of an SVG written by matplotlib (sizes in pt).

    Parameters
    ----------
    svg : str
        Starts with the ``<svg`` element.

    Returns
    -------
    (float, float)
    """
    head = svg[:svg.index(">")]
    w, h = (float(re.search(rf'\b{a}="([0-9.]+)pt"', head).group(1)) / 72.0  # type: ignore[union-attr]
            for a in ("width", "height"))
    return w, h


def draw_figures(figures: Mapping[str, Figure], rc: Mapping[str, Any], pdf: bool = True,
                 created: str | None = None) -> dict[str, tuple[str, bytes | None, tuple[float, float]]]:
    """Draw each figure once, as SVG, and (if asked) typeset its PDF from that SVG.

    Parameters
    ----------
    figures : dict of str to matplotlib.figure.Figure
        The figures by key.
    rc : dict
        rcParams to draw with.
    pdf : bool, optional
        Also make each figure's PDF (:func:`gd_analyze.report.typeset.figure_pdfs`).
    created : str, optional
        The PDFs' creation time, ISO 8601 UTC (the report's); the time of the run if not given.

    Returns
    -------
    dict of str to (str, bytes or None, (float, float))
        SVG text, PDF bytes (None without ``pdf``) and size [in] of each figure.

    Raises
    ------
    RuntimeError
        If Typst cannot typeset a figure's SVG.

    Notes
    -----
    One drawing per figure (layout, ticks, text): the PDF is the SVG typeset, so the figure
    files, the HTML and the PDF report show the same drawing.
    """
    out = {k: (svg, svg_size(svg)) for k, svg in ((k, figure_svg(f, rc))
                                                   for k, f in figures.items())}
    pdfs = figure_pdfs(out, created) if pdf else {}
    return {k: (svg, pdfs.get(k), size) for k, (svg, size) in out.items()}


def draw_each(makers: Mapping[str, Callable[[], Figure]], rc: Mapping[str, Any],
              created: str | None = None) -> dict[str, Drawn]:
    """Make and draw each figure in turn, as :func:`draw_figures` with ``pdf=True``, each
    figure's PDF typeset on a worker thread while the next figure is made and drawn.

    Parameters
    ----------
    makers : dict of str to callable
        By key, a function of no arguments making the figure: one figure alive at a time.
    rc : dict
        rcParams to draw with.
    created : str, optional
        As for :func:`draw_figures`.

    Returns
    -------
    dict of str to (str, bytes, (float, float))
        As :func:`draw_figures` (and its RuntimeError if Typst cannot typeset a figure's
        SVG), in the order of ``makers``.

    Notes
    -----
    Typst runs without Python's global lock, so its work (the fonts loaded once, then one
    compile per figure) overlaps matplotlib's drawing of the next figure on another core; on
    a single free core it takes its turn as before. The SVG and the PDF of each figure are
    the same as :func:`draw_figures` makes.
    """
    from concurrent.futures import ThreadPoolExecutor

    drawn: dict[str, tuple[str, tuple[float, float]]] = {}
    with ThreadPoolExecutor(1, thread_name_prefix="typst") as pool:
        pool.submit(fonts_loaded)                       # while the first figure is drawn
        pending = {}
        for key, make in makers.items():
            svg = figure_svg(make(), rc)
            drawn[key] = (svg, svg_size(svg))
            pending[key] = pool.submit(figure_pdfs, {key: drawn[key]}, created)
        pdfs = {k: f.result()[k] for k, f in pending.items()}
    return {k: (svg, pdfs[k], size) for k, (svg, size) in drawn.items()}


def write_figure_files(stack: contextlib.ExitStack, drawn: Mapping[str, Drawn], folder: Path,
                       names: Mapping[str, str]) -> list[Path]:
    """Write every drawn figure as ``folder/<name>.pdf`` and ``.svg``, staged.

    Parameters
    ----------
    stack : contextlib.ExitStack
        The files are renamed into place when it closes without an exception
        (:func:`gd_analyze.files.atomic_path`).
    drawn : dict
        From :func:`draw_figures`.
    folder : pathlib.Path
        The figures' folder (made if missing).
    names : dict of str to str
        File name without extension, by figure key.

    Returns
    -------
    list of pathlib.Path
        The files, PDF then SVG of each figure in turn.
    """
    files = {}
    for key, (svg_text, pdf_bytes, _) in drawn.items():
        assert pdf_bytes is not None            # drawn with pdf=True
        files.update({f"{names[key]}.pdf": pdf_bytes,
                      f"{names[key]}.svg": svg_text.encode("utf-8")})
    return _write_staged(stack, folder, files)


def _write_staged(stack, folder, files):
    """Write ``files`` ({name: bytes}) into ``folder`` (made if missing), each under a
    temporary name renamed when ``stack`` closes without an exception
    (:func:`gd_analyze.files.atomic_path`); their paths, in order."""
    folder.mkdir(parents=True, exist_ok=True)
    for name, data in files.items():
        Path(stack.enter_context(atomic_path(folder / name))).write_bytes(data)
    return [folder / name for name in files]


def prefix_ids(svg: str, prefix: str) -> str:
    """An SVG with ``prefix-`` put before every id and every reference to one, so that several
    figures share one HTML document without clashing ids.

    Parameters
    ----------
    svg : str
        The SVG text (:func:`figure_svg`).
    prefix : str
        E.g. ``"fig-D"``.

    Returns
    -------
    str
    """
    text = re.sub(r'\bid="', f'id="{prefix}-', svg)
    text = re.sub(r'\bhref="#', f'href="#{prefix}-', text)
    return re.sub(r"url\(#", f"url(#{prefix}-", text)


def html_document(template: str, context: Mapping[str, Any], outline: Outline,
                  drawn: Mapping[str, Drawn], env_globals: Mapping[str, Any] | None = None
                  ) -> str:
    """A report as one HTML document, its figures inline SVG.

    Parameters
    ----------
    template : str
        The Jinja2 template (:func:`gd_analyze.report.common.render_template`).
    context : dict
        The template's variables; ``figures`` and ``outline`` are added.
    outline : gd_analyze.report.sections.Outline
        The report's sections.
    drawn : dict
        The figures the report shows (:func:`draw_figures`).
    env_globals : dict, optional
        Globals of the template's environment.

    Returns
    -------
    str
        The document; the ids of figure ``k`` start with ``fig-k-`` so that no two figures'
        ids clash.
    """
    from markupsafe import Markup

    figures = {k: Markup(prefix_ids(svg, f"fig-{k}")) for k, (svg, _, _) in drawn.items()}
    return render_template(template, {**context, "figures": figures, "outline": outline},
                           env_globals)


def write_documents(folder: Path, drawn: Mapping[str, Drawn], names: Mapping[str, str],
                    outline: Callable[[Collection[str]], Outline], html: Callable[..., str],
                    pdf: Mapping[str, Any], formats: Sequence[str] = ("html", "pdf"),
                    stem: str = "report", paper: str = "a4", latex: bool = False,
                    prefix: str = "", shown: Sequence[str] | None = None) -> list[Path]:
    """Write a report's files, staged together: every figure, the documents, every table.

    Parameters
    ----------
    folder : pathlib.Path
        The output folder: ``figures/`` and ``tables/`` are made in it.
    drawn : dict
        Every figure drawn (:func:`draw_figures`), the column-width files' too.
    names : dict of str to str
        File name of each figure (:func:`write_figure_files`).
    outline : callable
        The report's sections from the keys of the figures it shows.
    html : callable
        ``html(outline, drawn)``: the HTML document (:func:`html_document`).
    pdf : dict
        ``metadata``, ``footer`` and ``created`` of :func:`gd_analyze.report.typeset.write_pdf`.
    formats : sequence of {"html", "pdf"}, optional
        The documents, ``folder/<stem>.<format>``, in this order.
    stem : str, optional
        The documents' file name.
    paper : {"a4", "letter"}, optional
        The PDF's page size.
    latex, prefix
        As for :func:`gd_analyze.report.drawing.table_files`: every table is also written
        as ``folder/tables/[<prefix>_]table_<section>_<k>.csv`` (and ``.tex``).
    shown : sequence of str, optional
        The figures the report shows, in order; those of ``drawn`` not ending in ``_column``
        if not given.

    Returns
    -------
    list of pathlib.Path
        The documents, then the figures' files, then the tables' files.

    Raises
    ------
    OSError
        If a file cannot be written: then none is (:func:`gd_analyze.files.atomic_path`).
    """
    from concurrent.futures import ThreadPoolExecutor

    if shown is None:
        shown = [k for k in drawn if not k.endswith("_column")]
    Path(folder).mkdir(parents=True, exist_ok=True)     # a report into a new folder
    with contextlib.ExitStack() as stack:
        every = drawn
        drawn = {k: drawn[k] for k in shown if k in drawn}
        sections = outline(drawn)           # read only from here on, by both threads
        docs = [folder / f"{stem}.{fmt}" for fmt in formats]
        staged = {path: stack.enter_context(atomic_path(path)) for path in docs}
        # the PDF typeset on a worker thread (Typst runs without Python's global lock) while
        # the HTML, the figures' files and the tables are written; it is waited for before
        # the files are renamed into place (or, on an error, removed)
        with ThreadPoolExecutor(1, thread_name_prefix="typst") as pool:
            typeset = [pool.submit(write_pdf, sections,
                                   {k: (d[0], d[2]) for k, d in drawn.items()}, staged[path],
                                   paper, **pdf)
                       for path in docs if path.suffix == ".pdf"]
            for path in docs:
                if path.suffix == ".html":
                    Path(staged[path]).write_text(html(sections, drawn), encoding="utf-8")
            files = write_figure_files(stack, every, folder / "figures", names)
            tables = _write_staged(stack, folder / "tables", {
                name: text.encode("utf-8")
                for name, text in table_files(sections, latex, prefix).items()})
            for done in typeset:
                done.result()
    return docs + files + tables


def write_report_files(folder: str | os.PathLike[str], ctx: Mapping[str, Any],
                       drawn: Mapping[str, Drawn], names: Mapping[str, str],
                       outline: Callable[[Any, Collection[str]], Outline], template: str,
                       subject: str, footer: str, keywords: str | None = None,
                       env_globals: Mapping[str, Any] | None = None, created: str | None = None,
                       **options: Any) -> list[Path]:
    """Write a report's files from its context, its outline and its drawn figures: the HTML
    from ``template``, the PDF with its document information, every figure and table
    (:func:`write_documents`).

    Parameters
    ----------
    folder : str or os.PathLike
        The output folder.
    ctx : dict
        The report's context: the HTML template's variables; its ``version`` (and, unless
        ``keywords`` is given, its ``keywords``) go to the PDF's document information.
    drawn, names
        As for :func:`write_documents`.
    outline : callable
        ``outline(ctx, figures)``: the report's sections from its context and the keys of
        the figures it shows.
    template : str
        The HTML's Jinja2 template (:func:`html_document`).
    subject, footer : str
        What the report is about (the PDF's subject), and what its footer says after
        "gd-analyze VERSION: ".
    keywords : str, optional
        The PDF's keywords, if not ``ctx["keywords"]``.
    env_globals : dict, optional
        Globals of the template's environment.
    created : str, optional
        The PDF's creation time, ISO 8601 UTC; none recorded if not given.
    **options
        ``formats``, ``stem``, ``paper``, ``latex``, ``prefix`` and ``shown`` of
        :func:`write_documents`.

    Returns
    -------
    list of pathlib.Path
        As :func:`write_documents`: the documents, the figures' files, the tables' files.

    Raises
    ------
    OSError
        If a file cannot be written: then none is.
    """
    version = ctx["version"]
    pdf = {"metadata": {"Author": f"gd-analyze {version}", "Subject": subject,
                        "Keywords": ctx["keywords"] if keywords is None else keywords},
           "footer": f"gd-analyze {version}: {footer}", "created": created}
    return write_documents(Path(folder), drawn, names, functools.partial(outline, ctx),
                           lambda o, d: html_document(template, ctx, o, d, env_globals), pdf,
                           **options)


# --------------------------------------------------------------------------------------------
# Every table of a report as a CSV file, and as a LaTeX table on request
# --------------------------------------------------------------------------------------------
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
            number, caption = b.number, b.text
            name = (prefix + "_" if prefix else "") + "table_" + number.replace(".", "_")
            out[name + ".csv"] = table_csv(b.content)
            if latex:
                out[name + ".tex"] = table_latex(b.content, number, caption, prefix)
    return out
