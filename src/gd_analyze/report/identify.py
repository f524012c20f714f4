"""Identify report: the stored identification as one self-contained HTML file and a PDF.

:func:`write_identify_report` reads the datasets of ``identification.h5`` (the root group and
one group per recording, as ``read_identification`` of the identify command's
``gd_analyze.store.stored_identification`` returns them) and never recomputes a model: the measured against the
predicted torque per joint on each validation recording and the residuals (figures), the
errors per recording and joint beside the robot file's as shipped, the parameter table with
standard deviations in % and identifiability, the links' physical consistency, the
preprocessing steps as stated by the run, and the provenance. One module for the report's
figures (:func:`identify_figures`), its words and tables (:func:`identify_context`) and its
outline.

``report.html`` has no external resources (inline CSS and SVG figures; the Jinja2 template of
the control report, ``templates/control_report.html.j2``, autoescape on); ``report.pdf`` is
typeset by Typst from the same section list (:mod:`gd_analyze.report.typeset`). Both, and
each figure as ``figures/fig_identify_*.pdf`` and ``.svg``, are written atomically
(:func:`gd_analyze.files.atomic_path`).
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Collection, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..store.schema import strings
from ..store.stored_identification import StoredIdentification, StoredRecording
from .common import say, settings_table, table, utc_now
from .drawing import draw_figures, write_report_files
from .figure_style import BASE_RC, joint_lines, markevery
from .markup import clean, scope
from .numbers import fmt, pct
from .sections import Outline
from .typeset import check_paper

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

__all__ = ["identify_figures", "shown_recordings", "role_of", "PAGE_WIDTH",
           "MAX_POINTS", "MODEL_STYLES", "FIGURE_RC", "short", "TITLE_CHARS",
           "identify_context", "parameter_units",
           "plain_table", "write_identify_report", "identify_outline"]

#: Figure width [in]: the text of a page.
PAGE_WIDTH = 7.2
#: The most points drawn of one line: longer recordings are drawn every k-th sample (the
#: caption says which k).
MAX_POINTS = 1500
#: Colour, line style and width [pt] of each torque (Okabe & Ito colours, told apart in black
#: and white by the line style too), with its key label.
MODEL_STYLES = {"tau_measured": ("#000000", "-", 1.3, "measured (filtered)"),
                "tau_predicted": ("#0072B2", (0, (4.0, 1.6)), 1.0, "identified model"),
                "tau_prior": ("#D55E00", (0, (1.0, 1.3)), 1.0, "robot file as shipped"),
                "tau_simplified": ("#009E73", (0, (5.0, 1.5, 1.0, 1.5)), 0.9,
                                   "simplified model")}
#: The residual's style: measured minus identified.
RESIDUAL_STYLE = ("#0072B2", "-", 0.9, "measured \u2212 identified model")
FIGURE_RC = {**BASE_RC, "legend.fontsize": 7.5}


def shown_recordings(groups: Mapping[str, StoredRecording]) -> list[str]:
    """The recordings the figures show: the validation recordings, or, without any, all.

    Parameters
    ----------
    groups : Mapping of str to StoredRecording
        The recordings by group name, in order.

    Returns
    -------
    list of str
        Group names.
    """
    validate = [k for k, ds in groups.items() if role_of(ds) == "validate"]
    return validate or list(groups)


def role_of(rec: StoredRecording) -> str:
    """A recording's role: its ``role`` attribute, or its ``role`` variable.

    Parameters
    ----------
    rec : StoredRecording
        A recording (:class:`gd_analyze.store.stored_identification.StoredRecording`).

    Returns
    -------
    str
        ``train`` or ``validate`` as stored (cleaned of the report's markup characters);
        ``train`` when not stored.
    """
    return "train" if rec.role is None else clean(str(rec.role))


#: The most characters of a joint's name in a panel title (a longer one is cut, with "...";
#: the tables give it whole).
TITLE_CHARS = 36


def short(name: str) -> str:
    """A joint's name cut to :data:`TITLE_CHARS` characters for a panel title.

    Parameters
    ----------
    name : str

    Returns
    -------
    str
        The name, or its first characters and an ellipsis.

    Examples
    --------
    >>> short("arm_1_joint")
    'arm_1_joint'
    """
    name = str(name)
    return name if len(name) <= TITLE_CHARS else name[:TITLE_CHARS - 1] + "\u2026"


def _panels(t, curves, joints, ylabel, width, prismatic=None):
    """One panel per joint, three a row at page width from five joints on (two a row
    otherwise, and in a column), the curves (name -> (N, n)) over t, a key below; each
    panel's unit N m (revolute) or N (prismatic), scaled with its ticks, said on each panel
    (:func:`gd_analyze.report.figure_style.joint_lines`)."""
    units = ["N" if prismatic is not None and prismatic[j] else "N m" for j in range(len(joints))]
    return joint_lines(t, [(MODEL_STYLES.get(name, RESIDUAL_STYLE), y) for name, y in curves.items()],
                       [f"joint {j + 1}: {short(name)}" for j, name in enumerate(joints)],
                       [f"{ylabel} [{u}]" for u in units], width,
                       cols=3 if len(joints) >= 5 and width >= PAGE_WIDTH else 2,
                       step=markevery(len(t), MAX_POINTS))


def identify_figures(root: StoredIdentification | xr.Dataset,
                     groups: dict[str, xr.Dataset] | None = None,
                     width: float = PAGE_WIDTH) -> dict[str, Figure]:
    """The report's figures from a stored identification.

    Parameters
    ----------
    root : StoredIdentification or xarray.Dataset
        The stored identification
        (:class:`gd_analyze.store.stored_identification.StoredIdentification`), or its root group
        (its ``joint`` coordinate names the joints, if present).
    groups : dict of str to xarray.Dataset, optional
        With a root group: one dataset per recording, ``t`` [s], ``tau_measured`` and
        ``tau_predicted`` (t, joint) [N m or N], optionally ``tau_prior`` and
        ``tau_simplified``.
    width : float, optional
        Figure width [in].

    Returns
    -------
    dict of str to matplotlib.figure.Figure
        ``"torque_k"`` and ``"residual_k"`` for the k-th recording of
        :func:`shown_recordings`.
    """

    ident = StoredIdentification.of(root, groups)
    out = {}
    import matplotlib

    with matplotlib.rc_context(FIGURE_RC):  # type: ignore[arg-type]  # keys typed as literals
        for k, name in enumerate(shown_recordings(ident.recordings)):
            rec = ident.recordings[name]
            t = rec.t
            joints = _joints(rec.n, rec.joint, ident.joint)
            curves = {v: rec.torques[v] for v in MODEL_STYLES if v in rec.torques}
            out[f"torque_{k}"] = _panels(t, curves, joints, "\u03c4", width, ident.prismatic)
            residual = rec.torques["tau_measured"] - rec.torques["tau_predicted"]
            out[f"residual_{k}"] = _panels(
                t, {"residual": residual}, joints, "\u03c4 residual", width, ident.prismatic)
    return out


def _joints(n, *stored):
    """The joints' names: the first of the ``stored`` coordinates (None where missing) that
    names n joints, else their numbers."""
    for joint in stored:
        if joint is not None and joint.size == n:
            return _strings(joint)
    return [str(j + 1) for j in range(n)]


#: Units of a base parameter by its name's letters, and of each drive kind (revolute joints;
#: prismatic: kg, kg, N s/m, N, N).
_M2 = "kg m\u00b2"
_BASE_UNITS = {"XX": _M2, "XY": _M2, "XZ": _M2, "YY": _M2, "YZ": _M2, "ZZ": _M2,
               "MX": "kg m", "MY": "kg m", "MZ": "kg m", "M": "kg"}
_DRIVE_UNITS = {"armature": _M2, "viscous": "N m s/rad", "coulomb": "N m", "offset": "N m"}


def plain_table(header: Sequence[str], rows: Sequence[Sequence[Any]],
                align: Sequence[str] | None = None,
                colour_cols: Sequence[int] = ()) -> dict[str, Any]:
    """A table as :func:`gd_analyze.report.common.table` makes it, its cells left as text.

    (``common.table`` letters cells that look like a G-D element's label, ``D12``, as
    mathematics, its index a subscript: a joint or file named so is shown as named here.)

    Parameters
    ----------
    header : sequence of str
    rows : sequence of sequence
    align : sequence of str, optional
        ``"left"`` or ``"right"`` per column; default the first left, the others right.
    colour_cols : sequence of int, optional
        Columns of yes/no cells, drawn in their colour.

    Returns
    -------
    dict
    """
    return table(header, rows, align or "right", colour_cols=colour_cols, cells=clean)


def parameter_units(name: str, kind: str) -> str:
    """The SI units of an identified parameter (a revolute joint's).

    Parameters
    ----------
    name : str
        ``ZZ1``, ``MX2``, ``M3``, ``viscous_1``...
    kind : str
        ``base`` or a drive kind.

    Returns
    -------
    str
        E.g. ``"kg m²"``; ``""`` if unknown.
    """
    if kind in _DRIVE_UNITS:
        return _DRIVE_UNITS[kind]
    letters = name.rstrip("0123456789")
    return _BASE_UNITS.get(letters, "")


def _json(text, default):
    """A JSON attribute as stored, or ``default`` when absent (None) or not JSON."""
    if text is None:
        return default
    try:
        return json.loads(str(text))
    except ValueError:
        return str(text)


def _strings(values):
    return [clean(v) for v in strings(values)]


def _file_of(rec):
    return clean(str(rec.file_name))


def _recordings_table(groups):
    has_prior = any(rec.has_prior_total for rec in groups.values())
    has_simple = any(rec.has_simplified_total for rec in groups.values())
    header = ["recording", "role", "samples", "duration [s]", "identified model",
              *(["robot file as shipped"] if has_prior else []),
              *(["simplified model"] if has_simple else [])]
    rows = [[_file_of(rec), role_of(rec), f"{rec.t.size:,}",
             fmt(rec.t[-1] - rec.t[0], 4) if rec.t.size else "n/a", pct(rec.total_relative_error),
             *([pct(rec.prior_total_relative_error)] if has_prior else []),
             *([pct(rec.simplified_total_relative_error)] if has_simple else [])]
            for rec in groups.values()]
    return plain_table(header, rows, align=["left", "left"] + ["right"] * (len(header) - 2))


def _joint_table(ident, rec):
    n = rec.n
    joints = _joints(n, rec.joint, ident.joint)
    cols = [(rec.rms_error, "RMS error [N m]", fmt),
            (rec.relative_error, "relative error", pct),
            (rec.prior_relative_error, "robot file: relative error", pct),
            (rec.simplified_relative_error, "simplified: relative error", pct)]
    cols = [c for c in cols if c[0] is not None]
    rows = [[str(j + 1), joints[j]] + [f(float(v[j])) for v, _, f in cols]
            for j in range(n)]
    return plain_table(["joint", "name"] + [h for _, h, _ in cols], rows,
                       align=["right", "left"] + ["right"] * len(cols))


def _parameter_table(stored):
    names = _strings(stored.parameter) if stored.parameter is not None \
        else [str(k + 1) for k in range(stored.value.size)]
    value, std = stored.value, stored.std
    kinds = _strings(stored.kind) if stored.kind is not None else ["base"] * len(names)
    prior = np.asarray(stored.prior, float) if stored.prior is not None else None
    ident = np.asarray(stored.identifiable, bool) if stored.identifiable is not None \
        else np.ones(len(names), bool)
    with np.errstate(divide="ignore", invalid="ignore"):    # NaN: not identifiable, or 0
        rel = np.where((value != 0) & ident, np.abs(std / value), math.nan)
    rows = [[name, parameter_units(name, kinds[k]), fmt(value[k], 4, (1e-3, 1e4)),
             fmt(std[k], 3, (1e-3, 1e4)) if ident[k] else "\u2014",
             pct(rel[k]) if math.isfinite(rel[k]) else "\u2014",
             *([] if prior is None else [fmt(prior[k], 4, (1e-3, 1e4))]),
             "yes" if ident[k] else "no"] for k, name in enumerate(names)]
    header = ["parameter", "units", "value", "std", "std [%]"] + \
        ["robot file"] * (prior is not None) + ["identifiable"]
    return plain_table(header, rows, align=["left", "left"] + ["right"] * (len(header) - 3)
                       + ["left"], colour_cols=[len(header) - 1]), int((~ident).sum()), names


def _links_table(stored):
    if stored.link_consistent is None:
        return None
    links = np.asarray(stored.link).reshape(-1) if stored.link is not None \
        else np.arange(1, stored.link_consistent.size + 1)
    ok = np.asarray(stored.link_consistent, bool)
    eig = np.asarray(stored.pseudo_inertia_min_eigenvalue, float) \
        if stored.pseudo_inertia_min_eigenvalue is not None else np.full(ok.size, math.nan)
    return plain_table(["link", f"smallest pseudo-inertia eigenvalue [{_M2}]", "consistent"],
                       [[str(links[k]), fmt(eig[k], 4, (1e-3, 1e4)), "yes" if ok[k] else "no"]
                        for k in range(ok.size)], colour_cols=[2])


def _noise_table(stored):
    if stored.noise_std is None:
        return None
    noise = np.asarray(stored.noise_std, float)
    joints = _joints(noise.size, stored.joint)
    return plain_table(["joint", "name", "residual standard deviation [N m]"],
                       [[str(j + 1), joints[j], fmt(noise[j], 4)] for j in range(noise.size)],
                       align=["right", "left", "right"])


def _provenance(stored, created):
    inputs, settings = _json(stored.inputs, {}), _json(stored.settings, {})
    rows = [("report created", created),
            ("gd-analyze version", stored.gd_analyze_version or "\u2014"),
            ("robot", stored.robot), ("robot file", stored.robot_source),
            ("robot file SHA-256", stored.robot_sha256),
            ("standard parameters", stored.standard_method),
            ("Coulomb friction model", stored.coulomb_model)]
    rows += [(f"input {k}", str(v)) for k, v in inputs.items()    # the robot file stands above
             if k != stored.robot_source] if isinstance(inputs, dict) else [
        (f"input {_file_of(rec)}", rec.sha256) for rec in stored.recordings.values()]
    if isinstance(settings, dict):
        rows += [(f"setting {k}", _setting(v)) for k, v in sorted(settings.items())]
    elif settings:
        rows.append(("settings", settings))
    return settings_table(rows, cells=clean)   # names from the files left as text


def _setting(value):
    """A stored setting as the provenance table shows it: a float, or a list of floats
    (``cutoff_hz_used``, ``idle_threshold``), to 6 significant digits (the file keeps every
    digit); text as it is; anything else as JSON."""
    floats = value if isinstance(value, list) else [value]
    if floats and all(isinstance(x, float) for x in floats):
        return ", ".join(fmt(x, 6) for x in floats)
    return value if isinstance(value, str) else json.dumps(value, default=str)


def _sentences(values):
    """Stored statements as sentences: cleaned, each ending with a full stop."""
    values = values if isinstance(values, list) else [values] if values else []
    texts = [clean(str(v)).strip() for v in values]
    return [text + ("" if text.endswith((".", "!", "?")) else ".") for text in texts if text]


def identify_context(root: StoredIdentification | xr.Dataset,
                     groups: dict[str, xr.Dataset] | None = None) -> dict[str, Any]:
    """The report's words and tables.

    Parameters
    ----------
    root : StoredIdentification or xarray.Dataset
        The stored identification
        (:class:`gd_analyze.store.stored_identification.StoredIdentification`), or its root group: ``value``, ``std`` (parameter) and optionally ``prior``,
        ``identifiable``, ``kind``, ``noise_std``, ``link_consistent``,
        ``pseudo_inertia_min_eigenvalue``; attributes ``condition_number``, ``rank``,
        ``unidentifiable``, ``preprocessing``, ``settings``, ``inputs`` (JSON), ``robot``...
    groups : dict of str to xarray.Dataset, optional
        With a root group, one per recording: ``t``, ``tau_measured``, ``tau_predicted`` (t, joint), per joint
        ``rms_error``, ``relative_error`` (and the robot file's and simplified model's), the
        role and ``total_relative_error``.

    Returns
    -------
    dict
        ``title``, ``lead``, ``summary``, ``notes`` and the tables, each a dict of
        :func:`plain_table`.
    """
    stored = StoredIdentification.of(root, groups)
    recordings = stored.recordings
    robot = clean(str("the robot" if stored.robot is None else stored.robot))
    cond = stored.condition_number
    validated = [rec for rec in recordings.values() if role_of(rec) == "validate"]
    shown = shown_recordings(recordings)
    parameters, n_unident, names = _parameter_table(stored)

    def said(error):                    # an error as a percentage; "" where there is none
        return pct(error) if math.isfinite(error) else ""

    settings = _json(stored.settings, {})
    lead = say("identify_lead", validated=[
        (_file_of(rec), pct(rec.total_relative_error), said(rec.prior_total_relative_error),
         said(rec.simplified_total_relative_error)) for rec in validated],
        inconsistent=isinstance(settings, dict) and bool(settings.get("robot_file_note")))
    unident = _json(stored.unidentifiable, [])
    which = [clean(str(u)) for u in unident] if isinstance(unident, list) else []
    summary = say("identify_summary", parameters=len(names), unidentifiable=n_unident,
                  which=which, condition=fmt(cond, 4),
                  recordings=sum(role_of(rec) == 'train' for rec in recordings.values()))
    strides = {name: markevery(int(recordings[name].t.size), MAX_POINTS) for name in shown}
    drawn = "; ".join(f"{_file_of(recordings[name])}: one sample in {k}"
                      for name, k in strides.items() if k > 1)
    return {
        "title": f"Identification of {robot}",
        "lead": lead,
        "summary": summary,
        "recordings": _recordings_table(recordings),
        "joint_tables": {name: _joint_table(stored, rec) for name, rec in recordings.items()},
        "files": {name: _file_of(rec) for name, rec in recordings.items()},
        "roles": {name: role_of(rec) for name, rec in recordings.items()},
        "shown": shown,
        "shown_note": say("identify_outline", key="shown", validated=bool(validated),
                          most=MAX_POINTS, drawn=drawn),
        "parameters": parameters,
        "parameter_note": say("identify_outline", key="parameters"),
        "links": _links_table(stored),
        "noise": _noise_table(stored),
        # the tool's own notes: each a sentence, s_i and tau_s typeset
        "preprocessing": [scope(text[:1].upper() + text[1:])
                          for text in _sentences(_json(stored.preprocessing, []))],
        "notes": {name: _sentences([str(n).removeprefix(f"{rec.file_name}: ") for n in notes])
                  if isinstance(notes := _json(rec.notes, None), list) else []
                  for name, rec in recordings.items()},     # the file is named before them
        "provenance": _provenance(stored, utc_now().strftime("%Y-%m-%d %H:%M:%S UTC")),
        "version": clean(str("" if stored.gd_analyze_version is None
                             else stored.gd_analyze_version)),
        "keywords": f"identification; robot {robot}; condition number {fmt(cond, 4)}",
    }



def identify_outline(ctx: dict, figures: Collection[str]) -> Outline:
    """The report's sections, once, for the HTML and the PDF.

    Parameters
    ----------
    ctx : dict
        :func:`gd_analyze.report.identify.identify_context`.
    figures : collection of str
        The keys of the figures drawn.

    Returns
    -------
    Outline
    """
    o = Outline(ctx["title"], figures, [
        (ctx["lead"], "lead"), (ctx["summary"], "summary"),
        (say("identify_outline", key="created", version=ctx["version"]), "note")])
    o.section("1", "Torque errors", "errors")
    o.table(ctx["recordings"], say("identify_outline", key="recordings"))
    for name, joint_table in ctx["joint_tables"].items():
        o.table(joint_table, say("identify_outline", key="joints", file=ctx["files"][name],
                                 role=ctx["roles"][name]), size=7)
    o.section("2", "Measured and predicted torque", "torque")
    o.paragraph(ctx["shown_note"], "note")
    for k, name in enumerate(ctx["shown"]):
        for kind in ("torque", "residual"):
            o.figure(f"{kind}_{k}", say("identify_outline", key=kind,
                                              file=ctx["files"][name], role=ctx["roles"][name]))
    o.section("3", "Parameters", "parameters")
    o.paragraph(ctx["parameter_note"], "note")
    o.table(ctx["parameters"], say("identify_outline", key="parameter_table"), size=7)
    for key in ("links", "noise"):
        if ctx[key] is not None:
            o.table(ctx[key], say("identify_outline", key=key))
    o.section("4", "Preprocessing", "preprocessing")
    for sentence in ctx["preprocessing"] or ["The run states no preprocessing."]:
        o.paragraph(sentence, "body")
    for name, notes in ctx["notes"].items():
        if notes:
            o.paragraph(f"{ctx['files'][name]}: " + " ".join(notes), "note")
    o.section("5", "Provenance", "provenance")
    o.table(ctx["provenance"], "Provenance: the files and settings of the run.", kv=True,
            size=7)
    return o


def write_identify_report(root: xr.Dataset, groups: dict[str, xr.Dataset],
                          folder: str | os.PathLike[str], paper: str = "a4",
                          latex: bool = False) -> list[Path]:
    """Write report.html, report.pdf and the figures of a stored identification.

    Parameters
    ----------
    root : xarray.Dataset
        The root group of ``identification.h5``: ``value`` and ``std`` over ``parameter``
        (required), and what :func:`gd_analyze.report.identify.identify_context` reads.
    groups : dict of str to xarray.Dataset
        One dataset per recording, by group name, in order: ``t`` [s], ``tau_measured`` and
        ``tau_predicted`` (t, joint) [N m or N] (required), the errors and the role.
    folder : str or os.PathLike
        The output folder (made if missing; the identify command's staged folder).
    paper : {"a4", "letter"}, optional
        Page size of the PDF.
    latex : bool, optional
        Also write every table as LaTeX, ``folder/tables/table_<section>_<k>.tex``.

    Returns
    -------
    list of pathlib.Path
        ``folder/report.html``, ``folder/report.pdf``, then each figure's
        ``folder/figures/fig_identify_<kind>_<k>.pdf`` and ``.svg`` (k: the recording's place
        among those shown, never its name), then every table of the report as
        ``folder/tables/table_<section>_<k>.csv`` (and ``.tex`` with ``latex``).

    Raises
    ------
    InputError
        If a required variable is missing.
    ValueError
        If ``paper`` is unknown.
    OSError
        If a file cannot be written.
    """

    check_paper(paper)
    stored = StoredIdentification.from_dataset(root, groups)
    ctx = identify_context(stored)
    drawn = draw_figures(identify_figures(stored), FIGURE_RC)
    return write_report_files(
        folder, ctx, drawn, {k: f"fig_identify_{k}" for k in drawn}, identify_outline,
        "control_report.html.j2", "Identification of a robot's base parameters and drives from "
        "recorded torques", "identify report", paper=paper, latex=latex)
