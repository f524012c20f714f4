"""The control report's words and tables: set-up, gains, errors, torques, cost, the model's
rule and what it keeps, and the provenance, generated from the stored control dataset
(:mod:`gd_analyze.report.control` renders them as HTML and PDF)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from .._version import VERSION as __version__
from ..ranking.ranking import ROUND_OFF_CLAUSE, element_label, is_round_off
from ..store.control_dataset import gain_units
from ..store.schema import from_attrs
from ..store.stored_control import ModelFacts, StoredControl
from .common import cost_table, fmt_column, utc_now
from .common import table as _table
from .control_figures import (
    CONTROL_LABELS,
    joint_units_of,
    markers_words,
    noise_floors,
    noise_words,
)
from .control_verdict import (
    NOISE,
    VERDICT_TOLERANCE,
    by_type_text,
    control_verdict,
    fmt_number,
    stored_text,
)
from .main_provenance import gravity_row, run_row, software_row
from .main_text import gravity_clause, model_sentence
from .markup import scope as scope_markup
from .markup import sub as _sub

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr

__all__ = ["control_context", "dataset_verdict"]



def dataset_verdict(ds: StoredControl | xr.Dataset) -> dict[str, Any]:
    """The control report's verdict and summary, from the stored control dataset: the same
    words for the report and the command line.

    Parameters
    ----------
    ds : StoredControl or xarray.Dataset
        A stored control run (:class:`gd_analyze.store.stored_control.StoredControl`), or a
        control dataset (:func:`gd_analyze.store.control_dataset.control_dataset`).

    Returns
    -------
    dict
        ``verdict`` and ``summary`` (str), ``rule`` (``"q"``, ``"tau"`` -> the integrator-noise
        rule in words, :func:`~gd_analyze.report.control_figures.noise_words`) and ``floors``
        (:func:`~gd_analyze.report.control_figures.noise_floors`: per joint [rad or m],
        [N m or N]). A tracking error or torque difference at or below its joint's floor is
        integrator noise, said as "\u2261 0 (integrator noise)".
    """
    s = StoredControl.of(ds)
    st = s.settings
    names = s.controllers
    prismatic = np.array(s.prismatic, dtype=bool)
    peaks = {c: s.error_peak_grid[c] for c in names}
    q_floor, tau_floor = noise_floors(s)
    rule = {k: noise_words(s, k) for k in ("q", "tau")}     # the rules, said everywhere
    quiet = {c: bool(is_round_off(peaks[c], q_floor, 1.0).all())
             for c in names}           # every joint's error is integrator noise: not data
    summary = "; ".join(f"{CONTROL_LABELS.get(c, c)}: peak |e| "
                        + (NOISE if quiet[c] else by_type_text(peaks[c], prismatic, "q"))
                        for c in names)
    summary = summary[:1].upper() + summary[1:]
    summary = (f"{stored_text(st.robot)} along {stored_text(st.trajectory_file)}, "
               f"\u03c9{_sub('n')} = {_per_joint(st.wn, ' rad/s')}, "
               f"\u03b6 = {_per_joint(st.zeta)}. {summary}.")
    diff = s.tau_difference_peak
    if diff is not None:                 # a joint's integrator noise is not its largest value
        off = is_round_off(diff, tau_floor, 1.0)
        quiet["tau_difference"] = bool(off.all())
        diff = np.where(off, 0.0, diff)
        summary += (" Largest closed-loop torque difference, simplified-model controller "
                    "minus full-model controller (two closed-loop runs, each along its own "
                    "motion): " + (NOISE if quiet["tau_difference"] else
                                   by_type_text(diff, prismatic, 'tau')) + " (a joint's "
                    "value counts as integrator noise, \u2261 0, where it is "
                    f"{rule['tau']}); not the "
                    "open-loop error \u03c4" + _sub("s") + " \u2212 \u03c4 of the main "
                    "report (one model against the other along the desired trajectory).")
    tolerance = tuple(float(d if v is None else v) for v, d in
                      zip((st.verdict_tolerance_revolute, st.verdict_tolerance_prismatic),
                          VERDICT_TOLERANCE))
    verdict = control_verdict(peaks, prismatic, diff,
                              tolerance,  # type: ignore[arg-type]  # (revolute, prismatic)
                              quiet, rule["tau"])
    return {"verdict": verdict, "summary": summary, "rule": rule,
            "floors": (q_floor, tau_floor)}


def control_context(ds: StoredControl | xr.Dataset) -> dict[str, Any]:
    """Everything the control report says, from the stored control dataset.

    Parameters
    ----------
    ds : StoredControl or xarray.Dataset
        A stored control run (:class:`gd_analyze.store.stored_control.StoredControl`), or a
        control dataset (:func:`gd_analyze.store.control_dataset.write_control_dataset`).

    Returns
    -------
    dict
        The report's context, the same for the HTML and the PDF.
    """
    s = StoredControl.of(ds)
    st = s.settings
    names = s.controllers
    n = s.n
    joints = [f"joint {j + 1}" for j in range(n)]          # as the main report names them
    desc = s.descriptions if s.descriptions is not None else names
    q_units = joint_units_of(s, "q")
    judged = dataset_verdict(s)
    summary, verdict, rule = judged["summary"], judged["verdict"], judged["rule"]
    q_floor, tau_floor = judged["floors"]
    setup = _table(["item", "value"], [
        ["robot", f"{stored_text(st.robot)} (SHA-256 {stored_text(st.robot_sha256)})"],
        ["trajectory", f"{stored_text(st.trajectory_file)} (SHA-256 "
                       f"{stored_text(st.trajectory_sha256)})"],
        ["simplified model", f"{stored_text(st.model_file)} (SHA-256 {stored_text(st.model_sha256)})"],
        ["plant", _plant(st)],
        ["controllers", "; ".join(CONTROL_LABELS.get(c, d) for c, d in zip(names, desc))
         + " (control laws below)"],
        ["desired motion", stored_text(st.interpolation).replace(
            "(q, qd, qdd)", "(q, q\u0307, q\u0308)")],        # the stored words, as mathematics
        ["integrator", f"{stored_text(st.integrator)}, rtol = {float(st.rtol):g}, "
                       f"atol = {float(st.atol):g}"],
        *([["integrator noise of \u03c4" + _sub("s") + " \u2212 \u03c4" + _sub("f"),
            f"measured: both computed-torque runs again with rtol = "
            f"{float(st.noise_rtol):g}, atol = {float(st.noise_atol):g} "
            f"({int(_or(st.noise_nfev, 0)):,} evaluations); noise floor "
            f"{float(_or(st.noise_factor, np.nan)):g} \u00d7 the largest change, at "
            f"least {float(st.rtol):g} \u00d7 the full-model controller's peak "
            "|\u03c4| (Table 3.1)"]] if st.noise_rtol is not None else []),
        *([["integrator noise of \u03c4" + _sub("s") + " \u2212 \u03c4" + _sub("f"),
            "not measured (" + str(st.noise_unmeasured) + "): the floor is rtol "
            "\u00d7 the full-model controller's peak |\u03c4|"]]
          if st.noise_unmeasured is not None else []),
        ["samples", f"{stored_text(st.samples)} ({stored_text(st.setpoints)} set points + fine grid "
                    f"of {stored_text(st.grid_points)})"],
        ["initial offset q(0) \u2212 q" + _sub("d") + "(0)",
         ", ".join(f"{fmt_number(v)}\u00a0{u}" for v, u in zip(s.q0_offset, q_units))
         if s.q0_offset is not None else "0"],
    ], align=["left", "left"])
    gains = _gains_table(s, joints)
    def noisy(peaks, floor):             # at or below the joint's noise floor: not data
        return is_round_off(peaks, floor, 1.0)

    err_rows, err_values, err_off = [], [], []
    for c in names:
        for where, peaks, rmss in (("set points", s.error_peak_setpoints, s.error_rms_setpoints),
                                   ("fine grid", s.error_peak_grid, s.error_rms_grid)):
            pk, rm = peaks[c], rmss[c]
            for fig, v in (("peak", pk), ("RMS", rm)):
                err_rows.append([_SHORT.get(c, c), where, fig])
                err_values.append(v)
                err_off.append(noisy(pk, q_floor))
    q_u, tau_u = joint_units_of(s, "q"), joint_units_of(s, "tau")
    errors = _table(["controller", "sampled at", "figure"]
                    + [f"{j} [{u}]" for j, u in zip(joints, q_u)],
                    _with_columns(err_rows, err_values, err_off),
                    align=["left", "left", "left"] + ["right"] * n)
    diff_rows, diff_values, diff_off = [], [], []
    if s.tau_difference_peak is not None:
        pairs = [("peak, fine grid", s.tau_difference_peak, s.tau_difference_peak),
                 ("RMS, fine grid", s.tau_difference_rms, s.tau_difference_peak)]
        if s.tau_difference_peak_setpoints is not None:
            at = s.tau_difference_peak_setpoints
            pairs += [("peak, set points", at, at),
                      ("RMS, set points", s.tau_difference_rms_setpoints, at)]
        for fig, value, peak in pairs:
            diff_rows.append([fig])
            diff_values.append(value)
            diff_off.append(noisy(peak, tau_floor))
        diff_rows.append(["noise floor (\u2261 0 at or below)"])
        diff_values.append(np.asarray(tau_floor, float))
        diff_off.append(np.zeros(n, bool))
    tau_diff = _table(["figure"] + [f"{j} [{u}]" for j, u in zip(joints, tau_u)],
                      _with_columns(diff_rows, diff_values, diff_off), align="right")
    tau_rows, tau_values = [], []
    for c in names:
        if s.tau_peak is not None and s.tau_rms is not None:
            for fig, figures in (("peak |\u03c4|", s.tau_peak), ("RMS \u03c4", s.tau_rms)):
                tau_rows.append([_SHORT.get(c, c), fig])
                tau_values.append(figures[c])
    tau_table = _table(["controller", "figure"] + [f"{j} [{u}]" for j, u in zip(joints, tau_u)],
                       _with_columns(tau_rows, tau_values),
                       align=["left", "left"] + ["right"] * n)
    cost = cost_table(s.costs)
    cost_note = ("Operations per set point, counted (not timed): the emitted models on their "
                 "expressions (constants and structural 0/\u00b11 free, a square one "
                 "multiplication), the project's Newton-Euler with every multiplication and "
                 "addition of one run counted.")
    model_note, recursive = _model_note(s)
    choice = dict(zip(s.elements, s.choice))
    rows = [[f"D, row {i + 1}"] + [choice.get(element_label("D", i, j), "") if j >= i else ""
                                   for j in range(n)] for i in range(n)]
    rows.append(["h"] + [choice.get(element_label("h", j), "") for j in range(n)])
    choices = None if recursive else _table(["element"] + [f"column {j + 1}"
                                                          for j in range(n)], rows,
                                           align=["left"] * (n + 1))
    prov = _table(["item", "value"], _provenance(s, __version__), align=["left", "left"])
    floor = (f"Integrator noise ({rule['q']}) is not drawn: a log axis starts at that "
             "floor.")
    captions = {
        "error": (f"Tracking error |e| = |q{_D} \u2212 q| per joint along the run, log scale "
                  f"({markers_words(s, names)}). Integrator noise, {rule['q']}, is not "
                  "drawn: the axis starts there, and a controller whose error is all noise is "
                  "named above the panels."),
        "tau_difference": (f"Closed-loop torque difference \u0394\u03c4 = {_TAU_S} \u2212 "
                           f"\u03c4{_sub('f')}: torque of the simplified-model "
                           "controller minus torque of the full-model controller, each along "
                           f"its own closed-loop run, per joint ({markers_words(s, 1)}). "
                           f"Integrator noise, {rule['tau']}, is not drawn: "
                           "the curve breaks off inside the grey band of \u00b1 the noise "
                           "floor (the noise-floor row of the torque-difference table), and a joint whose difference is "
                           "all noise reads so instead of a curve."),
        "tau": (f"Torques applied by the three controllers, per joint "
                f"({markers_words(s, names)})."),
    }
    return {
        "version": __version__,
        "created": utc_now().isoformat(),
        "title": f"Computed-torque control with the simplified G-D model: {stored_text(st.robot)}",
        "summary": summary, "verdict": verdict,
        "intro": ("The arm, simulated with its full generalized d'Alembert dynamics (Fu, Gonzalez "
                  "& Lee 1987, Eq. 3.4-24), tracks the trajectory under computed-torque control "
                  f"(Ch. 5) with the full model, with the simplified model ({_rule_words(s.model)}), "
                  "and under PD control with gravity compensation."),
        "setup": setup, "gains": gains,
        "gains_note": (f"Computed torque: v = q\u0308{_D} + {_KV} (q\u0307{_D} \u2212 q\u0307) + "
                       f"{_KP} (q{_D} \u2212 q), {_KP} = {_WN}\u00b2, {_KV} = 2\u03b6{_WN}, so "
                       f"the full-model closed loop is \u00eb + {_KV} \u0117 + {_KP} e = 0 "
                       f"(e = q{_D} \u2212 q, q{_D} the desired motion). PD + gravity: \u03c4 = "
                       f"{_KP} e + {_KV} \u0117 + c with the PD gains, scaled by the diagonal "
                       f"of D at the start of the motion (D{_sub('ii')} at the start)."),
        "errors": errors,
        "error_note": f"Tracking error e = q{_D} \u2212 q per joint",
        "floor_note": floor, "noise_rule": rule, "captions": captions,
        "tau_diff": tau_diff,
        "diff_note": (f"Closed-loop torque difference \u0394\u03c4 = {_TAU_S} \u2212 "
                      f"\u03c4{_sub('f')}: torque of the simplified-model "
                      "computed-torque controller minus that of the full-model one, each along "
                      "its own closed-loop run, at the same times"),
        "diff_not": ("It is not the open-loop "
                     f"error of the main report ({_TAU_S} \u2212 \u03c4 of the two models "
                     "along the desired trajectory)."),
        "tau_table": tau_table,
        "cost": cost, "cost_note": cost_note,
        "choices": choices, "model_note": model_note, "provenance": prov,
        "keywords": (f"robot {stored_text(st.robot)} sha256 {stored_text(st.robot_sha256)}; "
                     f"trajectory {stored_text(st.trajectory_file)} sha256 "
                     f"{stored_text(st.trajectory_sha256)}; model {stored_text(st.model_file)} sha256 "
                     f"{stored_text(st.model_sha256)}"),
    }


def _with_columns(rows, values, off=None, digits=3):
    """Table rows: each row's leading cells, then its numbers per joint, each joint's column in
    one notation (:func:`gd_analyze.report.numbers.fmt_column`: one format per
    column).

    Parameters
    ----------
    rows : list of list of str, length R
        The leading cells of each row.
    values : list of array_like, shape (R, n)
        The numbers of each row, one per joint [that column's units].
    off : list of array_like of bool, shape (R, n), optional
        Integrator noise by the report's rule: "\u2261 0".
    digits : int, optional
        Significant digits each entry keeps, at least.

    Returns
    -------
    list of list of str
    """
    if not rows:
        return []
    v = np.asarray(values, float)
    hide = np.zeros(v.shape, bool) if off is None else np.asarray(off, bool)
    cols = [fmt_column(v[:, j], digits, hide[:, j]) for j in range(v.shape[1])]
    return [list(r) + list(c) for r, c in zip(rows, zip(*cols))]


def _or(value, default):
    """A stored attribute's value, or ``default`` where it is missing (None)."""
    return default if value is None else value


def _per_joint(stored, unit=""):
    """A per-joint setting as the summary says it: once where every joint has the same value
    ("20 rad/s on every joint"), else the list ("20, 30, 20 rad/s")."""
    values = np.atleast_1d(np.asarray(_or(stored, np.nan), float))
    if values.size > 1 and np.all(values == values[0]):
        return f"{values[0]:g}{unit} on every joint"
    return ", ".join(f"{v:g}" for v in values) + unit


def _rule_words(model):
    """The simplified model's rule as the intro names it, from the stored rule: the error
    budget (with its epsilon) or the chapter's share-based classes of Sec. 3.4.1."""
    rule = str(_or(model.rule, ""))
    if rule == "budget":
        eps = float(_or(model.tolerance, np.nan))
        return f"error-budget rule, \u03b5\u00a0=\u00a0{eps:g}"
    if rule == "chapter":
        return "the chapter's share-based classes, Sec. 3.4.1"
    return "its rule is not recorded"


def _model_note(s):
    """Sec. 5's text: what the simplified model keeps, its rule and guarantee, generated from
    the model's facts stored by the control run (:func:`gd_analyze.jobs.control.model_facts`)
    in the words of the main report (:func:`gd_analyze.report.main_text.model_sentence`).
    Returns (text, whether the model has the recursive form)."""
    m, st = s.model, s.settings
    form, rule = str(_or(m.form, "")), str(_or(m.rule, ""))
    if form not in ("recursive", "explicit"):
        return ("The control dataset does not record what the simplified model keeps.",
                False)
    recursive = form == "recursive"
    if recursive:
        dropped_g = [v for v in str(_or(m.gravity_dropped, "")).split(", ") if v]
        gravity = gravity_clause(rule, gravity_dropped=dropped_g)
        facts = (int(_or(m.base_parameters, 0)), int(_or(m.pairs_dropped, 0)),
                 int(_or(m.pairs, 0)))
        own = str(st.trajectory_is_models) == "1"
        where = "this trajectory" if own else "the trajectory the model was built on"
        if str(_or(m.guarantee_kind, "")) == "region":
            where = "the joint-limit region"           # pruned on bounds over the region
        if str(_or(m.pairs_known, "1")) == "0":
            where += (" (or are structurally 0: the model file does not record which pairs "
                      "act)")
        text = model_sentence(recursive=facts, gravity=gravity, trajectory=where)
        if facts[1]:
            text += f" The dropped pairs: {_or(m.dropped_pairs, '')}."
    else:
        kept, full = int(_or(m.c_terms_kept, -1)), int(_or(m.c_terms, -1))
        gravity = gravity_clause(rule, c_terms=(kept, full) if min(kept, full) >= 0 else None)
        text = model_sentence(choice=list(s.choice), gravity=gravity)
    eps = float(_or(m.tolerance, np.nan))
    if m.scope is not None:             # the scope stored from the model itself
        return text + " " + scope_sentences(m, eps), recursive
    if rule == "budget":                # an older control.h5
        text += (f" Rule: error budget, \u03b5\u00a0=\u00a0{eps:g}: the open-loop error "
                 f"{_TAU_S} \u2212 \u03c4 is guaranteed within \u03b5\u00b7{_S_I}, "
                 f"{ROUND_OFF_CLAUSE}, on the trajectory the model was built on"
                 + (" (this one)." if
                                                         str(st.trajectory_is_models)
                                                         == "1" else
                                                         ", not on this one."))
    elif rule == "chapter":
        text += (" Rule: the chapter's share-based classes (Sec. 3.4.1): each element keeps "
                 "its dominant part; there is no error bound.")
    return text, recursive


def scope_sentences(attrs: ModelFacts | Mapping[str, Any], eps: float) -> str:
    """The model's rule, its guarantee as the model states it, and whether that covers the
    tracked motion, from the attributes the control run stored (``model_scope``,
    ``model_guarantee_kind``, ``model_guarantee_covered``, ``model_guarantee_coverage``).

    Parameters
    ----------
    attrs : ModelFacts or dict
        The model's facts as stored (:class:`gd_analyze.store.stored_control.ModelFacts`), or the
        control dataset's attributes.
    eps : float
        The model's tolerance EPS [1].

    Returns
    -------
    str
        Sentences; "guaranteed" only where the guarantee covers the motion.

    Examples
    --------
    >>> scope_sentences({"model_rule": "budget", "model_guarantee_kind": "trajectory",
    ...                  "model_scope": "within 1 % of s_i on this trajectory only",
    ...                  "model_guarantee_covered": 0,
    ...                  "model_guarantee_coverage": "it is not the trajectory"}, 0.01)[-68:]
    'trajectory. The open-loop error along this motion is not guaranteed.'
    """
    m = attrs if isinstance(attrs, ModelFacts) else from_attrs(ModelFacts, attrs, "model_")
    rule, kind = str(_or(m.rule, "")), str(_or(m.guarantee_kind, ""))
    scope = scope_markup(str(_or(m.scope, "")))
    if kind not in ("region", "trajectory"):
        if rule == "chapter":
            return ("Rule: the chapter's share-based classes (Sec. 3.4.1): each element keeps "
                    f"its dominant part; there is no error bound (the model's scope: {scope}).")
        return f"The model's guarantee: {scope}."
    where = " (stated for the trajectory it was built on)" if kind == "trajectory" else ""
    text = (f"Rule: error budget, \u03b5\u00a0=\u00a0{eps:g}. The model's guarantee{where}: "
            f"{scope}.")
    reason = str(_or(m.guarantee_coverage, ""))
    if str(m.guarantee_covered) == "1":
        return (text + f" It covers this motion: {reason}. The open-loop error "
                f"{_TAU_S} \u2212 \u03c4 along the desired motion is guaranteed within "
                f"\u03b5\u00b7{_S_I}, {ROUND_OFF_CLAUSE}.")
    return (text + f" It does not cover this motion: {reason}. The open-loop error along this "
            "motion is not guaranteed.")


#: Stored units of the gains (:func:`gd_analyze.ranking.labels.joint_gain_units`) and
#: of D_ii, as printed.
_GAIN_UNITS = {"N m rad-1": "N m/rad", "N m s rad-1": "N m s/rad", "N m-1": "N/m",
               "N s m-1": "N s/m", "kg m2": "kg m\u00b2", "kg": "kg"}


def _gains_table(s, joints):
    """The gains per joint. D_ii and the PD gains carry the units of their joint's type
    (the stored ``<name>_units`` per joint): in the header where every joint agrees, else in
    each cell."""

    prismatic = np.array(s.prismatic, dtype=bool)
    header = ["joint", "\u03c9" + _sub("n") + " [rad/s]", "\u03b6",
              "K" + _sub("p") + " [1/s\u00b2]", "K" + _sub("v") + " [1/s]"]
    per_joint = {}
    for name, title in (("inertia_scale", "D" + _sub("ii") + " at the start"),
                        ("Kp_pd", "PD K" + _sub("p")), ("Kv_pd", "PD K" + _sub("v"))):
        stored = s.gain_units[name]
        if stored is not None:
            units = [_GAIN_UNITS.get(u, u) for u in stored]
        else:                               # an older file: units from the joint types

            units = [_GAIN_UNITS.get(u, u) for u in gain_units(prismatic)[name]]
        same = len(set(units)) == 1
        header.append(f"{title} [{units[0]}]" if same else title)
        per_joint[name] = ([""] * len(units) if same else
                           ["\u00a0" + u.replace(" ", "\u00a0") for u in units])
    cols = {v: fmt_column(s.gains[v], 4) for v in ("wn", "zeta", "Kp", "Kv", "inertia_scale",
                                                  "Kp_pd", "Kv_pd")}   # one per column
    rows = [[joints[j]] + [cols[v][j] for v in ("wn", "zeta", "Kp", "Kv")]
            + [cols[v][j] + per_joint[v][j] for v in ("inertia_scale", "Kp_pd", "Kv_pd")]
            for j in range(len(joints))]
    return _table(header, rows, align="right")


def _plant(settings):
    """The simulated plant: the full G-D model's forward dynamics, written as mathematics."""
    plant = stored_text(settings.plant)
    if plant.startswith("full G-D model"):
        return "full G-D model, q\u0308 = D\u207b\u00b9 (\u03c4 \u2212 h \u2212 c) (Eq. 3.4-24)"
    return plant


#: The controllers as a table's rows name them (the figures' keys: ``CONTROLLER_LABELS``).
_SHORT = {"full": "full model", "simplified": "simplified model", "pd_gravity": "PD + gravity"}

_D, _KP, _KV, _WN = _sub("d"), "K" + _sub("p"), "K" + _sub("v"), "\u03c9" + _sub("n")
#: tau_s (the simplified model's torque) and s_i, their subscripts set as such (8 pt in the
#: PDF), not as Unicode's small subscript letters
_TAU_S, _S_I = "\u03c4" + _sub("s"), "s" + _sub("i")

#: The provenance rows of the control report: (item, attribute), each setting once (the gains
#: and the control laws are in Sec. 1, the robot, trajectory and model files in Table 1.1).
_PROVENANCE = (("trajectory path", "trajectory_path"),
               ("trajectory derivatives", "trajectory_derivatives"),
               ("model path", "model_path"),
               ("trajectory the model was built on (SHA-256)", "model_trajectory_sha256"),
               ("model built on this trajectory", "trajectory_is_models"),
               ("model's guarantee covers this motion", "model_guarantee_covered"),
               ("method", "references"))


def _provenance(s, version):
    """The provenance rows, each setting once and in words: the software, the command line as
    :func:`gd_analyze.cli.main` was given it (stored by the command line; an older file has
    none), the run as the main report says them (:mod:`gd_analyze.report.main_provenance`),
    gravity, the files, the verdict's tolerance."""
    st = s.settings
    rows = [list(software_row(s.run, version))]
    if st.command is not None:          # an older control.h5 has none
        rows.append(["command", stored_text(st.command)])
    rows += [list(run_row(s.run, "run")), list(gravity_row(s.run))]
    own = str(st.trajectory_is_models) == "1"
    stored = {"trajectory_path": st.trajectory_path,
              "trajectory_derivatives": st.trajectory_derivatives,
              "model_path": st.model_path,
              "model_trajectory_sha256": st.model_trajectory_sha256,
              "trajectory_is_models": st.trajectory_is_models,
              "model_guarantee_covered": s.model.guarantee_covered,
              "references": st.references}
    for label, k in _PROVENANCE:
        if k == "model_trajectory_sha256" and own:
            continue                    # the trajectory's own SHA-256, said in Table 1.1
        if stored[k] is not None:
            value = stored_text(stored[k])
            if k in ("trajectory_is_models", "model_guarantee_covered"):
                value = {"1": "yes", "0": "no"}.get(value, value)
            rows.append([label, value])
    if st.verdict_tolerance_revolute is not None:
        kinds = set(s.prismatic)
        said = [f"{stored_text(st.verdict_tolerance_revolute)} rad"
                + (" (revolute joints)" if len(kinds) > 1 else "")] * (False in kinds) + \
            [f"{stored_text(st.verdict_tolerance_prismatic)} m"
             + (" (prismatic joints)" if len(kinds) > 1 else "")] * (True in kinds)
        rows.append(["verdict tolerance", ", ".join(said)])
    return rows
