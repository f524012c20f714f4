"""Checks of a drawn figure at print size, shared by the figure tests of every report: label
collisions from the text extents the renderer gives, text left outside the figure, the
smallest type, and code names lettered where mathematics belongs.

Collisions are measured on the drawn figure: every text's extent from the renderer
(``Text.get_window_extent``) against every other text's, and against the plotting area of every
other panel; a text that runs past the figure's edge is cut off in print and counts too.
"""

import re

#: Overlap below this many points is antialiasing, not a collision.
SLACK = 0.5


def drawn_tick_labels(ax):
    """The tick labels the axes draws: of ticks within its view, shown (as Axis.draw picks
    them; a located tick outside the limits is not drawn)."""
    out = []
    for axis in (ax.xaxis, ax.yaxis):
        for tick in axis._update_ticks():
            out += [lab for lab in (tick.label1, tick.label2) if lab.get_visible()]
    return out


def tick_texts(ax, axis="y"):
    """(tick position, label Text) of the labelled ticks one axis of an Axes draws (as
    Axis.draw picks them); labels formatted as when the figure is drawn."""
    which = ax.xaxis if axis == "x" else ax.yaxis
    return [(tick.get_loc(), tick.label1) for tick in which._update_ticks()
            if tick.label1.get_visible() and tick.label1.get_text()]


def texts(fig):
    """(owner, text) of every visible non-empty text: tick labels, axis labels, titles,
    panel texts, legends, figure texts; the owner is the axes (or the figure)."""
    out = []
    for ax in fig.axes:
        if not ax.get_visible():
            continue
        items = ([ax.title, ax._left_title, ax._right_title, ax.xaxis.label, ax.yaxis.label]
                 + list(ax.texts) + drawn_tick_labels(ax))
        legend = ax.get_legend()
        if legend is not None:
            items += legend.get_texts()
        out += [(ax, t) for t in items]
    items = list(fig.texts) + [t for lg in fig.legends for t in lg.get_texts()]
    for extra in (fig._suptitle, getattr(fig, "_supylabel", None),
                  getattr(fig, "_supxlabel", None)):
        if extra is not None and extra not in items:
            items.append(extra)
    out += [(fig, t) for t in items]
    return [(o, t) for o, t in out if t.get_visible() and t.get_text().strip()]


def draw(fig, rc=None):
    """Draw the figure as the reports do (fixed layout, ``rc`` settings) and give its
    renderer.

    Drawn without rendering (``Figure.draw_without_rendering``): every artist is drawn on
    the Agg canvas's renderer, which lays out the ticks, their labels and every text as a
    full draw does, but paints no pixel. The extents the checks read are a full draw's; the
    painting, which they do not read, was most of a check's time."""
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(fig)
    with matplotlib.rc_context(rc or {}):
        fig.draw_without_rendering()
    return canvas.get_renderer()


def _overlap(a, b):
    w = min(a.x1, b.x1) - max(a.x0, b.x0)
    h = min(a.y1, b.y1) - max(a.y0, b.y0)
    return min(w, h)


def collisions(fig, rc=None):
    """Pairs of labels of a drawn figure whose extents overlap, labels that run into the
    plotting area of a panel they do not belong to, and labels cut by the figure's edge; as
    readable strings."""
    renderer = draw(fig, rc)
    px = fig.dpi / 72.0 * SLACK
    page = fig.bbox
    boxes = [(o, t, t.get_window_extent(renderer)) for o, t in texts(fig)]
    found = []
    for k, (oa, ta, a) in enumerate(boxes):
        if (a.x0 < page.x0 - px or a.x1 > page.x1 + px or a.y0 < page.y0 - px
                or a.y1 > page.y1 + px):
            found.append(f"{ta.get_text()!r} runs past the figure's edge")
        for ob, tb, b in boxes[k + 1:]:
            if _overlap(a, b) > px:
                found.append(f"{ta.get_text()!r} / {tb.get_text()!r}")
        for ax in fig.axes:
            if ax is oa or not ax.get_visible() or not ax.axison:
                continue
            if _overlap(a, ax.get_window_extent(renderer)) > px:
                found.append(f"{ta.get_text()!r} runs into panel {ax.get_title()!r}")
    return found


def crowded_axis_labels(fig, rc=None, gap=1.0):
    """Axis labels of a drawn figure closer than ``gap`` [pt] to a tick label of their own
    axes on the side they face: not overlapping, yet read as one word in print ("[kg]5.0").
    As readable strings (none: all well)."""
    renderer = draw(fig, rc)
    pt = fig.dpi / 72.0
    found = []
    for ax in fig.axes:
        if not ax.get_visible():
            continue
        ticks = [(t, t.get_window_extent(renderer)) for t in drawn_tick_labels(ax)]
        ticks += [(t, t.get_window_extent(renderer)) for t in ax.texts
                  if getattr(t, "axis_name", None) in ("x", "y")]
        labels = [t for t in ax.texts if not hasattr(t, "axis_name")
                  and t.get_rotation() in (90.0, 270.0) and t.get_text().strip()]
        labels += [ax.yaxis.label] if ax.yaxis.label.get_visible() else []
        for label in labels:
            if not label.get_text().strip():
                continue
            b = label.get_window_extent(renderer)
            for tick, c in ticks:
                if c.y1 <= b.y0 or c.y0 >= b.y1 or c.x1 < b.x0:
                    continue                    # not beside the label, or on its far side
                if (c.x0 - b.x1) / pt < gap - 0.01:     # float slack on a 1-pt pad
                    found.append(f"{label.get_text()!r} / {tick.get_text()!r}: "
                                 f"{(c.x0 - b.x1) / pt:.2f} pt")
    return found


def smallest_type(fig, rc=None):
    """The smallest font size [pt] of the drawn figure's texts (the figure is drawn at the
    size it is printed at)."""
    draw(fig, rc)
    return min(t.get_fontsize() for _, t in texts(fig))


#: Code names where mathematics belongs: an identifier with an underscore (D_ij, share_tran,
#: tau_s, q_d), an element label with plain digits (D12, h3, D1,10), a spelled-out Greek
#: letter (tau), an ASCII "EPS x".
_CODE = re.compile(r"[A-Za-z]_[A-Za-z0-9{]|\b[Dh][0-9]|\b(?:tau|EPS|eps)\b")
_MATHTEXT = re.compile(r"(?<!\\)\$.*?(?<!\\)\$")


def code_names(fig):
    """Texts of the figure (drawn or not yet) that letter mathematics as code: as readable
    strings. Mathtext spans (``$...$``) are mathematics and not checked."""
    draw(fig)
    found = []
    for _, t in texts(fig):
        plain = _MATHTEXT.sub("", t.get_text())
        m = _CODE.search(plain)
        if m:
            found.append(f"{m.group(0)!r} in {t.get_text()[:60]!r}")
    return found


def column_twins(folder, width=3.5):
    """Problems of a figures/ folder: a figure without its ``<name>_column`` twin (PDF and
    SVG), and a column PDF whose page (MediaBox, read with pypdf) is not ``width`` [in] wide;
    as readable strings (none: all well)."""
    from pypdf import PdfReader

    names = {p.name for p in folder.iterdir()}
    found = []
    for name in sorted(names):
        stem, ext = name.rsplit(".", 1)
        if stem.endswith("_column"):
            if ext == "pdf":
                box = PdfReader(folder / name).pages[0].mediabox
                w = (float(box[2]) - float(box[0])) / 72.0
                if abs(w - width) > 0.005:
                    found.append(f"{name} is {w:.3f} in wide")
        elif f"{stem}_column.{ext}" not in names:
            found.append(f"{name} has no {stem}_column.{ext}")
    return found


def check_print_ready(figs, rc=None):
    """Assert what every figure a command writes must hold at print size: no code names, no
    label collisions, and each ``<key>_column`` twin 3.5 in wide with type of at least 7 pt.

    Parameters
    ----------
    figs : dict of str to matplotlib.figure.Figure
        The figures by file key.
    rc : dict, optional
        rcParams to draw with.
    """
    import pytest

    for key, fig in figs.items():
        assert not code_names(fig), (key, code_names(fig)[:4])
        assert not collisions(fig, rc), (key, collisions(fig, rc)[:4])
        if key.endswith("_column"):
            assert fig.get_size_inches()[0] == pytest.approx(3.5)
            assert smallest_type(fig, rc) >= 7.0, key


def sweep_figure(ds, key):
    """The sweep report's figure ``key`` ("error", or the one-part share figure "D" or "h")
    of a sweep dataset at the page's width, as ``make_sweep_figures(ds)[key]`` makes it (the
    same maker, settings and parts), made alone: without the other figures, which a test
    that reads one does not need (the share figures' box plots take most of the making)."""
    import matplotlib

    from gd_analyze.report import sweep
    from gd_analyze.report.figure_style import SUPTITLE_RC

    w = sweep.StoredSweep.of(ds)
    with matplotlib.rc_context(SUPTITLE_RC):
        if key == "error":
            return sweep._fig_error(w)
        width = sweep.PAGE_WIDTH
        return sweep._share_figures(w, key, width, sweep._share_parts(w, key, (width,)))[key]
