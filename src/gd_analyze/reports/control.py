"""Control report: the stored closed-loop comparison as one self-contained HTML file and a PDF.

:func:`write_control_report` reads a control dataset written by
:func:`gd_analyze.io.control_dataset.write_control_dataset` (``control.h5``) and never recomputes anything:
every number and curve comes from the dataset's variables and global attributes. The report
holds the set-up and gains, the tracking error per joint of the three controllers (figure and
peak/RMS table), the torque difference between the simplified-model and the full-model
computed-torque controllers, the applied torques, the evaluation cost of the simplified model
against the full one, the model's choices and the provenance.

``control_report.html`` has no external resources (inline CSS, inline SVG figures, Jinja2
template ``templates/control_report.html.j2``); ``control_report.pdf`` is written with
matplotlib's PdfPages from :class:`matplotlib.figure.Figure` objects (no pyplot). Both are
written atomically (:func:`gd_analyze.files.atomic_path`).
"""

from __future__ import annotations

import contextlib
import functools
from pathlib import Path

import numpy as np

from ..config import defaults
from ..core.selection.ranking import (
    element_label,
    is_round_off,
    joint_motion_units,
    joint_torque_units,
)
from .common import attr, count, fmt, prismatic_joints, render_template, utc_now
from .common import strings as _strings
from .common import table as _table
from .control_figures import (
    _LABELS,
    _RC,
    COLUMN_WIDTH,
    PAGE_WIDTH,
    _joint_units,
    control_figures,
    noise_scales,
)
from .drawing import draw_figures, figure_svg, write_figure_files
from .main_provenance import gravity_row, run_row, software_row
from .main_text import gravity_clause, model_sentence
from .markup import sub as _sub
from .pages import PAPER, Document
from .sections import Outline, to_document

__all__ = ["CONTROL_REPORT_FILES", "REQUIRED_VARIABLES", "VERDICT_TOLERANCE", "control_verdict", "make_control_figures",
           "render_control_html", "render_control_pdf", "write_control_report"]

#: Names of the files written into the output folder.
CONTROL_REPORT_FILES = ("control_report.html", "control_report.pdf")
#: Variables a control dataset must have.
REQUIRED_VARIABLES = ("is_setpoint", "q_d", "error", "tau", "error_peak_setpoints",
                      "error_rms_setpoints", "error_peak_grid", "error_rms_grid", "Kp", "Kv",
                      "Kp_pd", "Kv_pd", "wn", "zeta", "inertia_scale", "choice", "nfev")

# Numbers in e-notation outside [1e-3, 1e5), 3 significant digits unless told; attributes
# with 6 digits, arrays without parentheses, booleans as 0/1.
_SCI = (1e-3, 1e5)
_fmt = functools.partial(fmt, digits=3, sci_outside=_SCI)
_attr = functools.partial(attr, parens=False, bools=True, sci_outside=_SCI)


def _check(ds, path):
    from ..errors import InputError

    missing = [v for v in REQUIRED_VARIABLES if v not in ds.variables]
    if missing or "controller" not in ds.dims or "time" not in ds.dims:
        raise InputError(f"not a gd-analyze control dataset (missing {missing[:3] or 'dims'})",
                         str(path))


# --------------------------------------------------------------------------------------------
# Figures (reports/control_figures.py)
# --------------------------------------------------------------------------------------------

def make_control_figures(ds, width=PAGE_WIDTH):
    """The report's figures, drawn from a stored control dataset.

    Parameters
    ----------
    ds : xarray.Dataset
        A control dataset (:func:`gd_analyze.io.control_dataset.control_dataset`).
    width : float, optional
        7.2 in (a page, default) or 3.5 in (a column, one panel a row).

    Returns
    -------
    dict of str to matplotlib.figure.Figure
        As :func:`gd_analyze.reports.control_figures.control_figures`: ``"error"``,
        ``"tau_difference"`` (if stored) and ``"tau"``.

    Raises
    ------
    InputError
        If the dataset lacks a variable of a control dataset.
    """
    _check(ds, "<dataset>")
    return control_figures(ds, width)


# --------------------------------------------------------------------------------------------
# Content shared by the HTML and the PDF
# --------------------------------------------------------------------------------------------

def _context(ds):
    from .._version import __version__

    names = _strings(ds["controller"].values)
    n = int(ds.sizes["joint"])
    joints = [f"J{j + 1}" for j in range(n)]
    desc = (_strings(ds["controller_description"].values) if "controller_description" in ds
            else names)
    peak_grid = ds["error_peak_grid"]
    prismatic = prismatic_joints(ds)
    peaks = {c: peak_grid.sel(controller=c).values for c in names}
    q_units = _joint_units(ds, "q")
    tol, q_scale, tau_scale = noise_scales(ds)
    quiet = {c: bool(is_round_off(peaks[c], q_scale, tol).all())
             for c in names}           # every joint's error is integrator noise: not data
    summary = "; ".join(f"{_LABELS.get(c, c)}: peak |e| "
                        + (_NOISE if quiet[c] else _by_type_text(peaks[c], prismatic, "q"))
                        for c in names)
    summary = summary[:1].upper() + summary[1:]
    summary = (f"{_attr(ds, 'robot')} along {_attr(ds, 'trajectory_file')}, "
               f"\u03c9{_sub('n')} = {_attr(ds, 'wn')} rad/s, \u03b6 = {_attr(ds, 'zeta')}. "
               f"{summary}.")
    diff = ds["tau_difference_peak"].values if "tau_difference_peak" in ds else None
    if diff is not None:
        summary += (" Largest closed-loop torque difference, simplified-model controller "
                    "minus full-model controller (two closed-loop runs, each along its own "
                    f"motion): {_by_type_text(diff, prismatic, 'tau')}; not the "
                    "open-loop error \u03c4" + _sub("s") + " \u2212 \u03c4 of the main "
                    "report (one model against the other along the desired trajectory).")
    tolerance = tuple(float(ds.attrs.get(f"verdict_tolerance_{k}", d)) for k, d in
                      zip(("revolute", "prismatic"), VERDICT_TOLERANCE))
    verdict = control_verdict(peaks, prismatic, diff, tolerance, quiet)
    setup = _table(["item", "value"], [
        ["robot", f"{_attr(ds, 'robot')} (SHA-256 {_attr(ds, 'robot_sha256')})"],
        ["trajectory", f"{_attr(ds, 'trajectory_file')} (SHA-256 "
                       f"{_attr(ds, 'trajectory_sha256')})"],
        ["simplified model", f"{_attr(ds, 'model_file')} (SHA-256 {_attr(ds, 'model_sha256')})"],
        ["plant", _plant(ds)],
        ["controllers", "; ".join(_LABELS.get(c, d) for c, d in zip(names, desc))
         + " (control laws below)"],
        ["desired motion", _attr(ds, "interpolation")],
        ["integrator", f"{_attr(ds, 'integrator')}, rtol = {_attr(ds, 'rtol')}, "
                       f"atol = {_attr(ds, 'atol')}"],
        ["samples", f"{_attr(ds, 'samples')} ({_attr(ds, 'setpoints')} set points + fine grid "
                    f"of {_attr(ds, 'grid_points')})"],
        ["initial offset q(0) \u2212 q" + _sub("d") + "(0)",
         ", ".join(f"{_fmt(v)}\u00a0{u}" for v, u in zip(ds["q0_offset"].values, q_units))
         if "q0_offset" in ds else "0"],
    ], align=["left", "left"])
    gains = _gains_table(ds, joints)
    def noise(values, peaks, scale):     # integrator noise of the joint's scale: not data
        off = is_round_off(peaks, scale, tol)
        return ["\u2261 0" if o else _fmt(v) for v, o in zip(values, off)]

    err_rows = []
    for c in names:
        for key, where in (("setpoints", "set points"), ("grid", "fine grid")):
            pk = ds[f"error_peak_{key}"].sel(controller=c).values
            rm = ds[f"error_rms_{key}"].sel(controller=c).values
            err_rows.append([_SHORT.get(c, c), where, "peak"] + noise(pk, pk, q_scale))
            err_rows.append([_SHORT.get(c, c), where, "RMS"] + noise(rm, pk, q_scale))
    q_u, tau_u = _joint_units(ds, "q"), _joint_units(ds, "tau")
    errors = _table(["controller", "sampled at", "figure"]
                    + [f"{j} [{u}]" for j, u in zip(joints, q_u)],
                    err_rows, align=["left", "left", "left"] + ["right"] * n)
    tau_diff = _table(["figure"] + [f"{j} [{u}]" for j, u in zip(joints, tau_u)], [],
                      align="right")

    def fmt_all(name, **sel):
        return [_fmt(v) for v in ds[name].sel(**sel).values]

    def diff(name, peak):
        return noise(ds[name].values, ds[peak].values, tau_scale)

    if "tau_difference_peak" in ds:
        tau_diff["rows"] = [["peak, fine grid"] + diff("tau_difference_peak",
                                                       "tau_difference_peak"),
                            ["RMS, fine grid"] + diff("tau_difference_rms",
                                                      "tau_difference_peak")]
        if "tau_difference_peak_setpoints" in ds:
            at = "tau_difference_peak_setpoints"
            tau_diff["rows"] += [["peak, set points"] + diff(at, at),
                                 ["RMS, set points"] + diff("tau_difference_rms_setpoints", at)]
    tau_rows = []
    for c in names:
        if "tau_peak" in ds:
            tau_rows.append([_SHORT.get(c, c), "peak |\u03c4|"] + fmt_all("tau_peak", controller=c))
            tau_rows.append([_SHORT.get(c, c), "RMS \u03c4"] + fmt_all("tau_rms", controller=c))
    tau_table = _table(["controller", "figure"] + [f"{j} [{u}]" for j, u in zip(joints, tau_u)],
                       tau_rows,
                       align=["left", "left"] + ["right"] * n)
    cost = None
    if "evaluator" in ds.dims:
        ev = _strings(ds["evaluator"].values)
        mul, add = ds["multiplications"].values, ds["additions"].values
        ref = len(ev) - 1            # the last: Newton-Euler, the recursive reference
        cost = _table(["evaluator", "multiplications", "additions", "operations",
                       "operations vs Newton-Euler"],
                      [[e, count(mul[k]), count(add[k]), count(mul[k] + add[k]),
                        f"{(mul[k] + add[k]) / (mul[ref] + add[ref]):.3f}"]
                       for k, e in enumerate(ev)], align="right")
    cost_note = ("Operations per set point, counted (not timed): the emitted models on their "
                 "expressions (constants and structural 0/\u00b11 free, a square one "
                 "multiplication), the project's Newton-Euler on its counting scalar "
                 "(gd_analyze.formulations.opcount).")
    model_note, recursive = _model_note(ds)
    labels = _strings(ds["element"].values)
    choice = dict(zip(labels, _strings(ds["choice"].values)))
    rows = [[f"D, row {i + 1}"] + [choice.get(element_label("D", i, j), "") if j >= i else ""
                                   for j in range(n)] for i in range(n)]
    rows.append(["h"] + [choice.get(element_label("h", j), "") for j in range(n)])
    choices = None if recursive else _table(["element"] + [f"column {j + 1}"
                                                          for j in range(n)], rows,
                                           align=["left"] * (n + 1))
    prov = _table(["item", "value"], _provenance(ds, __version__), align=["left", "left"])
    floor = ("Integrator noise (at most the integrator's rtol times the joint's scale) is not "
             "drawn: a log axis starts at that floor.")
    return {
        "version": __version__,
        "created": utc_now().isoformat(),
        "title": f"Computed-torque control with the simplified G-D model: {_attr(ds, 'robot')}",
        "summary": summary, "verdict": verdict,
        "intro": ("The arm, simulated with its full generalized d'Alembert dynamics (Fu, Gonzalez "
                  "& Lee 1987, Eq. 3.4-24), tracks the trajectory under computed-torque control "
                  "(Ch. 5) with the full model, with the simplified model of Sec. 3.4.1, and "
                  "under PD control with gravity compensation."),
        "setup": setup, "gains": gains,
        "gains_note": (f"Computed torque: v = q\u0308{_D} + {_KV} (q\u0307{_D} \u2212 q\u0307) + "
                       f"{_KP} (q{_D} \u2212 q), {_KP} = {_WN}\u00b2, {_KV} = 2\u03b6{_WN}, so "
                       f"the full-model closed loop is \u00eb + {_KV} \u0117 + {_KP} e = 0 "
                       f"(e = q{_D} \u2212 q, q{_D} the desired motion). PD + gravity: \u03c4 = "
                       f"{_KP} e + {_KV} \u0117 + c with the PD gains, scaled by the diagonal "
                       f"of D at the start of the motion (D{_sub('ii')} at the start)."),
        "errors": errors,
        "error_note": (f"Tracking error e = q{_D} \u2212 q per joint, peak |e| and RMS, at the "
                       "set points of the trajectory and on the fine grid (set points "
                       "included)."),
        "floor_note": floor, "noise_tol": f"{tol:g}",
        "tau_diff": tau_diff,
        "diff_note": ("Closed-loop torque difference: torque of the simplified-model "
                      "computed-torque controller minus that of the full-model one, each along "
                      "its own closed-loop run, at the same times. It is not the open-loop "
                      "error of the main report (\u03c4\u209b \u2212 \u03c4 of the two models "
                      "along the desired trajectory)."),
        "tau_table": tau_table,
        "cost": cost, "cost_note": cost_note,
        "choices": choices, "model_note": model_note, "provenance": prov,
        "keywords": (f"robot {_attr(ds, 'robot')} sha256 {_attr(ds, 'robot_sha256')}; "
                     f"trajectory {_attr(ds, 'trajectory_file')} sha256 "
                     f"{_attr(ds, 'trajectory_sha256')}; model {_attr(ds, 'model_file')} sha256 "
                     f"{_attr(ds, 'model_sha256')}"),
    }


def _model_note(ds):
    """Sec. 5's text: what the simplified model keeps, its rule and guarantee, generated from
    the model's facts stored by the control run (:func:`gd_analyze.workflows.control.model_facts`)
    in the words of the main report (:func:`gd_analyze.reports.main_text.model_sentence`).
    Returns (text, whether the model has the recursive form)."""
    a = ds.attrs
    form, rule = str(a.get("model_form", "")), str(a.get("model_rule", ""))
    if form not in ("recursive", "explicit"):
        return ("The control dataset does not record what the simplified model keeps.",
                False)
    recursive = form == "recursive"
    if recursive:
        dropped_g = [v for v in str(a.get("model_gravity_dropped", "")).split(", ") if v]
        gravity = gravity_clause(rule, gravity_dropped=dropped_g)
        facts = (int(a.get("model_base_parameters", 0)), int(a.get("model_pairs_dropped", 0)),
                 int(a.get("model_pairs", 0)))
        own = str(a.get("trajectory_is_models")) == "1"
        where = "this trajectory" if own else "the trajectory the model was built on"
        if str(a.get("model_pairs_known", "1")) == "0":
            where += (" (or are structurally 0: the model file does not record which pairs "
                      "act)")
        text = model_sentence(recursive=facts, gravity=gravity, trajectory=where)
        if facts[1]:
            text += f" The dropped pairs: {a.get('model_dropped_pairs', '')}."
    else:
        kept, full = int(a.get("model_c_terms_kept", -1)), int(a.get("model_c_terms", -1))
        gravity = gravity_clause(rule, c_terms=(kept, full) if min(kept, full) >= 0 else None)
        text = model_sentence(choice=_strings(ds["choice"].values), gravity=gravity)
    eps = float(a.get("model_tolerance", np.nan))
    if rule == "budget":
        text += (f" Rule: error budget, \u03b5\u00a0=\u00a0{eps:g}: the open-loop error "
                 "\u03c4\u209b \u2212 \u03c4 is guaranteed within \u03b5\u00b7s\u1d62 on the "
                 "trajectory the model was built on" + (" (this one)." if
                                                         str(a.get("trajectory_is_models"))
                                                         == "1" else
                                                         ", not on this one."))
    elif rule == "chapter":
        text += (" Rule: the chapter's share-based classes (Sec. 3.4.1): each element keeps "
                 "its dominant part; there is no error bound.")
    return text, recursive


#: Stored units of the gains (:func:`gd_analyze.core.selection.labels.joint_gain_units`) and
#: of D_ii, as printed.
_GAIN_UNITS = {"N m rad-1": "N m/rad", "N m s rad-1": "N m s/rad", "N m-1": "N/m",
               "N s m-1": "N s/m", "kg m2": "kg m\u00b2", "kg": "kg"}


def _gains_table(ds, joints):
    """The gains per joint. D_ii and the PD gains carry the units of their joint's type
    (the stored ``<name>_units`` per joint): in the header where every joint agrees, else in
    each cell."""
    from .common import prismatic_joints

    prismatic = prismatic_joints(ds)
    header = ["joint", "\u03c9" + _sub("n") + " [rad/s]", "\u03b6",
              "K" + _sub("p") + " [1/s\u00b2]", "K" + _sub("v") + " [1/s]"]
    per_joint = {}
    for name, title in (("inertia_scale", "D" + _sub("ii") + " at the start"),
                        ("Kp_pd", "PD K" + _sub("p")), ("Kv_pd", "PD K" + _sub("v"))):
        if f"{name}_units" in ds.coords:
            units = [_GAIN_UNITS.get(u, u) for u in _strings(ds[f"{name}_units"].values)]
        else:                               # an older file: units from the joint types
            from ..io.control_dataset import _gain_units

            units = [_GAIN_UNITS.get(u, u) for u in _gain_units(prismatic)[name]]
        same = len(set(units)) == 1
        header.append(f"{title} [{units[0]}]" if same else title)
        per_joint[name] = ([""] * len(units) if same else
                           ["\u00a0" + u.replace(" ", "\u00a0") for u in units])
    rows = [[joints[j]] + [_fmt(ds[v].values[j], digits=4) for v in ("wn", "zeta", "Kp", "Kv")]
            + [_fmt(ds[v].values[j], digits=4) + per_joint[v][j]
               for v in ("inertia_scale", "Kp_pd", "Kv_pd")] for j in range(len(joints))]
    return _table(header, rows, align="right")


def _plant(ds):
    """The simulated plant: the full G-D model's forward dynamics, written as mathematics."""
    plant = _attr(ds, "plant")
    if plant.startswith("full G-D model"):
        return "full G-D model, q\u0308 = D\u207b\u00b9 (\u03c4 \u2212 h \u2212 c) (Eq. 3.4-24)"
    return plant


#: The controllers as a table's rows name them (the figures' keys: ``CONTROLLER_LABELS``).
_SHORT = {"full": "full model", "simplified": "simplified model", "pd_gravity": "PD + gravity"}

_D, _KP, _KV, _WN = _sub("d"), "K" + _sub("p"), "K" + _sub("v"), "\u03c9" + _sub("n")

#: The provenance rows of the control report: (item, attribute), each setting once (the gains
#: and the control laws are in Sec. 1, the robot, trajectory and model files in Table 1.1).
_PROVENANCE = (("trajectory path", "trajectory_path"),
               ("trajectory derivatives", "trajectory_derivatives"),
               ("model path", "model_path"),
               ("trajectory the model was built on (SHA-256)", "model_trajectory_sha256"),
               ("model built on this trajectory", "trajectory_is_models"),
               ("method", "references"))


def _provenance(ds, version):
    """The provenance rows, each setting once and in words: the software and the run as the
    main report says them (:mod:`gd_analyze.reports.main_provenance`), gravity, the files,
    the verdict's tolerance."""
    rows = [list(software_row(ds, version)), list(run_row(ds, "run")),
            list(gravity_row(ds))]
    for label, k in _PROVENANCE:
        if k in ds.attrs:
            value = _attr(ds, k)
            if k == "trajectory_is_models":
                value = {"1": "yes", "0": "no"}.get(value, value)
            rows.append([label, value])
    if "verdict_tolerance_revolute" in ds.attrs:
        kinds = set(prismatic_joints(ds).tolist())
        said = [f"{_attr(ds, 'verdict_tolerance_revolute')} rad"
                + (" (revolute joints)" if len(kinds) > 1 else "")] * (False in kinds) + \
            [f"{_attr(ds, 'verdict_tolerance_prismatic')} m"
             + (" (prismatic joints)" if len(kinds) > 1 else "")] * (True in kinds)
        rows.append(["verdict tolerance", ", ".join(said)])
    return rows

#: Default tolerance of the verdict on the simplified-model controller's peak tracking error:
#: (revolute joints [rad], prismatic joints [m]) (:data:`gd_analyze.config.defaults`); the
#: verdict takes the larger of it and twice the full-model controller's error (its integrator
#: floor); ``control --verdict-tolerance`` sets it.
VERDICT_TOLERANCE = tuple(defaults["verdict_tolerance"])
#: A tracking error that is integrator noise on every joint, as the text says it.
_NOISE = "\u2261 0 (integrator noise)"


def _value(value, unit):
    """A number and its unit, never split over two lines."""
    return f"{_fmt(value)}\u00a0{unit}".replace(" ", "\u00a0")


def _by_type(values, prismatic, which):
    """Each joint type present, as (unit, largest value, one-based joints), revolute first."""
    values, prismatic = np.asarray(values, float), np.asarray(prismatic, bool)
    out = []
    for kind in (False, True):
        ks = np.nonzero(prismatic == kind)[0]
        if ks.size:
            unit = (joint_torque_units(kind) if which == "tau" else
                    joint_motion_units(kind)[0])
            out.append((unit, float(np.nanmax(values[ks])), [int(k) + 1 for k in ks]))
    return out


def _by_type_text(values, prismatic, which, limits=None):
    """``"2.63e-04 rad"``, or per joint type ``"2.63e-04 rad, 6.20e-05 m"`` (revolute, then
    prismatic joints): a maximum is never taken across units."""
    groups = _by_type(values, prismatic, which)
    if limits is not None:
        groups = [(u, lim, js) for (u, _, js), lim in zip(groups, limits)]
    return ", ".join(_value(v, u) for u, v, _ in groups)


def _joint_types(prismatic):
    """For a mixed arm, which joints are revolute and which prismatic, said once; else ""."""
    groups = _by_type(np.zeros(len(prismatic)), prismatic, "q")
    if len(groups) < 2:
        return ""
    return ("; ".join(f"joint{'s' if len(js) > 1 else ''} {', '.join(map(str, js))} "
                      f"{'prismatic' if kind else 'revolute'} ({u}, "
                      f"{joint_torque_units(kind)})"
                      for (u, _, js), kind in zip(groups, (False, True))) + ": ")


def control_verdict(peaks, prismatic, tau_difference=None,
                    tolerance=VERDICT_TOLERANCE, quiet=None):
    """One sentence: does the simplified model control the arm as well as the full one?

    Parameters
    ----------
    peaks : dict of str to ndarray, shape (n,)
        Per controller (``"full"``, ``"simplified"``, ``"pd_gravity"``), each joint's peak
        tracking error |q_d - q| [rad, or m for a prismatic joint].
    prismatic : ndarray of bool, shape (n,)
        Which joints are prismatic.
    tau_difference : ndarray, shape (n,), optional
        Each joint's peak closed-loop torque difference, simplified-model controller minus
        full-model controller [N m, or N for a prismatic joint].
    tolerance : tuple of (float, float), optional
        Revolute [rad] and prismatic [m] tolerance
        (:data:`VERDICT_TOLERANCE`).
    quiet : dict of str to bool, optional
        Per controller, whether its error is integrator noise on every joint: said as
        "\u2261 0 (integrator noise)" instead of its digits.

    Returns
    -------
    str
        The verdict: the simplified model holds if, for every joint type, its largest peak
        error is within the larger of the tolerance and twice the full model's. Errors of
        revolute and prismatic joints are stated apart, each in its unit.

    Examples
    --------
    >>> v = control_verdict({"full": np.array([1e-9, 1e-9]),
    ...                      "simplified": np.array([2e-4, 5e-4])}, np.array([False, True]))
    >>> print(v[:v.index(" (tolerance")])
    Verdict: the simplified model is good enough for computed-torque control along this trajectory: joint 1 revolute (rad, N m); joint 2 prismatic (m, N): peak tracking error 2.00e-04\xa0rad, 5.00e-04\xa0m against 1.00e-09\xa0rad, 1.00e-09\xa0m with the full model
    """
    full, simp = peaks.get("full"), peaks.get("simplified")
    if full is None or simp is None:
        return "Verdict: not available (the run lacks the full or the simplified controller)."
    pd = peaks.get("pd_gravity")
    quiet = quiet or {}

    def said(c, values):
        return _NOISE if quiet.get(c) else _by_type_text(values, prismatic, "q")

    groups = {k: _by_type(v, prismatic, "q") for k, v in peaks.items()}
    tol = {False: tolerance[0], True: tolerance[1]}
    kinds = [u != joint_motion_units(False)[0] for u, _, _ in groups["full"]]
    bounds = [max(2.0 * f, tol[kind]) for (_, f, _), kind in zip(groups["full"], kinds)]
    holds = all(s <= b for (_, s, _), b in zip(groups["simplified"], bounds))
    beats_pd = pd is not None and all(s < p for (_, s, _), (_, p, _) in
                                      zip(groups["simplified"], groups["pd_gravity"]))
    tail = ""
    if tau_difference is not None:
        tail = (f"; its closed-loop torque differs from the full-model controller's (two "
                f"closed-loop runs) by at most {_by_type_text(tau_difference, prismatic, 'tau')}")
    pd_text = f", PD + gravity {said('pd_gravity', pd)}" if pd is not None else ""
    if holds:
        head = ("Verdict: the simplified model is good enough for computed-torque control "
                "along this trajectory")
    elif beats_pd:
        head = ("Verdict: the simplified model degrades tracking beyond the tolerance, though "
                "it still beats PD + gravity")
    else:
        head = "Verdict: the simplified model is NOT good enough for computed-torque control"
    if len(kinds) == 1:
        (u, _, _), kind = groups["full"][0], kinds[0]
        tolerance_text = (f"{_fmt(bounds[0])} {u}, the larger of {tol[kind]:g} {u} and twice "
                          "the full model's")
    else:
        tolerance_text = (" and ".join(
            f"{_fmt(b)} {u} ({'prismatic' if kind else 'revolute'})"
            for b, (u, _, _), kind in zip(bounds, groups["full"], kinds))
            + ", each the larger of " + " or ".join(
                f"{tol[kind]:g} {u}" for (u, _, _), kind in zip(groups["full"], kinds))
            + " and twice the full model's")
    return (f"{head}: {_joint_types(prismatic)}"
            f"peak tracking error {said('simplified', simp)} against "
            f"{said('full', full)} with the full model{pd_text} (tolerance: "
            f"{tolerance_text}){tail}.")


# --------------------------------------------------------------------------------------------
# HTML and PDF
# --------------------------------------------------------------------------------------------

def render_control_html(ds, figures=None):
    """Render the control report as one self-contained HTML document.

    Parameters
    ----------
    ds : xarray.Dataset
        A stored control dataset.
    figures : dict of str to matplotlib.figure.Figure, optional
        :func:`make_control_figures` of it; made here if not given.

    Returns
    -------
    str
        The HTML: inline CSS, figures as inline SVG, no external resources (Jinja2 template
        ``templates/control_report.html.j2``, autoescape on).

    Raises
    ------
    InputError
        If the dataset lacks a variable of a control dataset.
    """
    _check(ds, "<dataset>")
    ctx = _context(ds)
    if figures is None:
        figures = make_control_figures(ds)
    return _html(ctx, {k: (figure_svg(f, _RC), None, None) for k, f in figures.items()})


_CAPTIONS = {
    "error": "Tracking error |q" + _sub("d") + " \u2212 q| per joint along the run, log scale "
             "(markers: set points, at most 12 per line). Integrator noise, at most the "
             "integrator's rtol times the joint's range of motion, is not drawn: the axis "
             "starts there, and a controller whose error is all noise is named above the "
             "panels.",
    "tau_difference": "Closed-loop torque difference: torque of the simplified-model "
                      "controller minus torque of the full-model controller, each along its "
                      "own closed-loop run, per joint (markers: set points); a joint whose "
                      "difference is integrator noise (at most rtol times the full "
                      "controller's peak |\u03c4|) reads so instead of a curve.",
    "tau": "Torques applied by the three controllers, per joint.",
}
_FIGURE_FILES = {"error": "fig_control_tracking_error",
                 "tau_difference": "fig_control_torque_difference",
                 "tau": "fig_control_applied_torque"}
#: Each figure also 3.5 in wide, as ``figures/<name>_column.pdf`` and ``.svg`` (not in the
#: report).
_FIGURE_FILES.update({f"{k}_column": f"{v}_column" for k, v in list(_FIGURE_FILES.items())})


def _outline(ctx, figures):
    """The control report's sections, once, for the HTML and the PDF
    (:class:`gd_analyze.reports.sections.Outline`)."""
    o = Outline(ctx["title"], figures)
    o.paragraph(ctx["verdict"], "lead")
    o.paragraph(ctx["summary"], "summary")
    o.paragraph(ctx["intro"] + f" Report created {ctx['created']} by gd-analyze "
                f"{ctx['version']} from the stored control dataset; nothing was recomputed.",
                "note")
    o.section("1", "Set-up and gains", "setup")
    o.table(ctx["setup"], "The closed-loop run.", kv=True)
    o.paragraph(ctx["gains_note"], "note")
    o.table(ctx["gains"], "Gains per joint.")
    o.section("2", "Tracking error", "tracking")
    o.paragraph(ctx["error_note"], "note")
    o.table(ctx["errors"], "Tracking error per controller and joint; \u2261 0: integrator "
                           f"noise (at most {ctx['noise_tol']} of the joint's range of "
                           "motion), not data.", size=7)
    o.figure("error", _CAPTIONS["error"])
    o.section("3", "Torques", "torque")
    o.paragraph(ctx["diff_note"], "note")
    o.table(ctx["tau_diff"], "Closed-loop torque difference per joint, simplified-model "
                             "controller minus full-model controller; \u2261 0: integrator "
                             f"noise (at most {ctx['noise_tol']} of the full-model controller's "
                             "peak |\u03c4|), not data.")
    if "tau_difference" in o.available:
        o.figure("tau_difference", _CAPTIONS["tau_difference"])
    else:
        o.paragraph("No torque difference stored.", "body")
    o.table(ctx["tau_table"], "Applied torques per controller and joint.", size=7)
    o.figure("tau", _CAPTIONS["tau"])
    o.section("4", "Evaluation cost of the model", "cost")
    o.paragraph(ctx["cost_note"], "note")
    if ctx["cost"]:
        o.table(ctx["cost"], "Operations per set point of each evaluator.")
    else:
        o.paragraph("Not measured.", "body")
    o.section("5", "Simplified model", "model")
    o.paragraph(ctx["model_note"], "note")
    if ctx["choices"]:
        o.table(ctx["choices"], "The part of each element the simplified model keeps.")
    o.section("6", "Provenance", "provenance")
    o.table(ctx["provenance"], "Provenance: the files and settings of the run, each once.",
            kv=True, size=7)
    return o


def _html(ctx, drawn):
    from markupsafe import Markup

    svgs = {k: Markup(svg) for k, (svg, _, _) in drawn.items()}
    return render_template("control_report.html.j2", {**ctx, "figures": svgs,
                                                      "outline": _outline(ctx, drawn)})


def render_control_pdf(ds, path, figures=None, paper="a4"):
    """Write the control report as a PDF document.

    Parameters
    ----------
    ds : xarray.Dataset
        A stored control dataset.
    path : str or os.PathLike
        The PDF to write (not atomically; :func:`write_control_report` passes a temporary
        name).
    figures : dict of str to matplotlib.figure.Figure, optional
        :func:`make_control_figures` of it; made here if not given.
    paper : {"a4", "letter"}, optional
        The size of every page.

    Returns
    -------
    int
        Number of pages written.

    Raises
    ------
    InputError
        If the dataset lacks a variable of a control dataset.
    OSError
        If the file cannot be written.
    """
    _check(ds, "<dataset>")
    ctx = _context(ds)
    if figures is None:
        figures = make_control_figures(ds)
    return _pdf(ctx, draw_figures(figures, _RC), path, paper)


def _pdf(ctx, drawn, path, paper="a4"):
    metadata = {"Author": f"gd-analyze {ctx['version']}",
                "Subject": "Computed-torque control with the simplified G-D model (Fu, Gonzalez "
                           "& Lee 1987, Sec. 3.4.1 and Ch. 5)",
                "Keywords": ctx["keywords"], "Creator": f"gd-analyze {ctx['version']}"}
    doc = Document(ctx["title"], paper=paper, metadata=metadata,
                   footer=f"gd-analyze {ctx['version']}: control report")
    to_document(_outline(ctx, drawn), doc, {k: d[2] for k, d in drawn.items()})
    return doc.write(path, {k: d[1] for k, d in drawn.items()})


def write_control_report(control_path, outdir, paper="a4", fonts="type3"):
    """Write control_report.html and control_report.pdf for a stored control dataset.

    Parameters
    ----------
    control_path : str or os.PathLike
        A control dataset written by :func:`gd_analyze.io.control_dataset.write_control_dataset`
        (``control.h5``). Only read: nothing is recomputed.
    outdir : str or os.PathLike
        Output folder; made if missing.
    paper : {"a4", "letter"}, optional
        Page size of the PDF.
    fonts : {"type3", "truetype"}, optional
        How the figures' PDFs embed their font
        (:data:`gd_analyze.reports.pages.FIGURE_FONTS`).

    Returns
    -------
    list of pathlib.Path
        ``outdir/control_report.html`` and ``outdir/control_report.pdf``, then every figure as
        ``outdir/figures/fig_control_*.pdf`` and ``.svg``.

    Raises
    ------
    InputError
        If the file is missing, unreadable or not a control dataset.
    OSError
        If a file cannot be written.

    Notes
    -----
    Each file is written under a temporary name beside its destination and renamed
    (:func:`gd_analyze.files.atomic_path`). Sources: Fu, Gonzalez & Lee (1987), Sec. 3.4.1
    (simplified model) and Ch. 5 (computed-torque control).
    """
    from ..files import atomic_path
    from ..io.schema import open_results

    if paper not in PAPER:
        raise ValueError(f"paper must be one of {sorted(PAPER)}, got {paper!r}")
    ds = open_results(str(control_path))
    _check(ds, control_path)
    ctx = _context(ds)
    outdir = Path(outdir)
    (outdir / "figures").mkdir(parents=True, exist_ok=True)
    figures = make_control_figures(ds)
    column = control_figures(ds, COLUMN_WIDTH)
    drawn = draw_figures({**figures, **{f"{k}_column": f for k, f in column.items()}}, _RC,
                         fonts=fonts)
    html_path, pdf_path = (outdir / name for name in CONTROL_REPORT_FILES)
    files = []
    with contextlib.ExitStack() as stack:
        files = write_figure_files(stack, drawn, outdir / "figures", _FIGURE_FILES)
        drawn = {k: drawn[k] for k in figures}          # the report shows the page versions
        Path(stack.enter_context(atomic_path(html_path))).write_text(_html(ctx, drawn),
                                                                     encoding="utf-8")
        _pdf(ctx, drawn, stack.enter_context(atomic_path(pdf_path)), paper)
    return [html_path, pdf_path] + files
