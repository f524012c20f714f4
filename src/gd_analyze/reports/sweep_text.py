"""The sweep report's words: its context (tables, summary, captions) and every sentence
about the own and the merged models, generated from the stored sweep and its rules
(:mod:`gd_analyze.reports.sweep` renders them as HTML and PDF)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .._version import VERSION as __version__
from .common import attr as _attr
from .common import check as _check
from .common import (
    cost_table,
    count,
    fmt_column,
    pct_column,
    torque_units,
    units_said_once,
    utc_now,
)
from .common import fmt as _fmt
from .common import pct as _pct
from .common import share as _share_text
from .common import strings as _strings
from .common import table as _table
from .common import thresholds as _thresholds
from .figures import PAYLOAD_REQUIRED as _PAYLOAD_REQUIRED
from .main_provenance import gravity_row, run_row, software_row
from .main_text import gravity_clause
from .markup import element as _el
from .markup import scope as scope_markup
from .markup import sub as _sub
from .sweep_figures import REQUIRED as _REQUIRED
from .sweep_figures import TORQUE_ROUND_OFF_WORDS, torque_error_round_off
from .sweep_merged_text import (
    _SI,
    _TAU_I,
    _cost_sentence,
    _floor,
    _form,
    _held_out,
    _merged_rule,
    _models,
    _own_rule,
    _recursive_clause,
    _recursive_gravity,
    merged_claim,
)

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr

__all__ = ["sweep_context"]

#: The merged model's choices per element, in the words of Table 4.1 and the counts line.
_CHOICES = ("tran", "rot", "both", "none")


# --------------------------------------------------------------------------------------------
# Content shared by the HTML and the PDF
# --------------------------------------------------------------------------------------------

def sweep_context(ds: xr.Dataset, payload: xr.Dataset | None = None) -> dict[str, Any]:
    """Everything the sweep report says, from the stored sweep (and payload sweep): the
    tables, the summary, the captions and the sentences about the models.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep dataset (:func:`gd_analyze.workflows.sweep.run_sweep`).
    payload : xarray.Dataset, optional
        A payload sweep (:func:`gd_analyze.workflows.payload.payload_sweep`).

    Returns
    -------
    dict
        The report's context, the same for the HTML and the PDF.

    Raises
    ------
    InputError
        If a dataset lacks a variable the report needs.
    """

    _check(ds, _REQUIRED, "sweep")
    K = ds.sizes["trajectory"]
    n = ds.sizes["joint"]
    labels = _strings(ds["element"].values)
    frac = ds["class_fraction"].values
    merged = _strings(ds["merged_choice"].values)
    s, e = _thresholds(ds)
    robot = _attr(ds, "robot")
    kind = str(ds.attrs.get("input_kind", ""))
    if kind == "random" and "seed" in ds.attrs:
        inputs = f"{K} random quintic trajectories (seed {_attr(ds, 'seed')})"
    else:
        inputs = f"{K} trajectories ({kind or 'given'})"
    durations = ds["duration"].values
    setpoints = ds["setpoints"].values if "setpoints" in ds.variables else np.array([])
    settings = _settings(ds, inputs, setpoints, durations, __version__)
    zero = (ds["round_off"].values.astype(bool).all(axis=0) if "round_off" in ds
            else np.zeros(len(labels), bool))
    envelope = _table(
        ["element", "translational", "rotational", "both", "negligible", "min share",
         "median share", "max share", "merged choice"],
        [[lab, *(f"{f:.3f}" for f in frac[k]),
          *(_share(ds[f"share_tran_{w}"].values[k], zero[k])  # type: ignore[index]  # an array
            for w in ("min", "median", "max")),
          merged[k]] for k, lab in enumerate(labels)],
        align=["left"] + ["right"] * 7 + ["left"], colour_cols=[8])
    units = torque_units(ds)
    merged_off = torque_error_round_off(ds, ds["merged_error_peak"].values, ds["merged_error_tau_peak"].values)
    rel_peak = pct_column(ds["merged_error_relative_peak"].values, merged_off)   # one format
    rel_rms = pct_column(ds["merged_error_relative_rms"].values, merged_off)     # per column
    own_worst = _own_worst(ds)
    tau_peak = fmt_column(ds["merged_error_tau_peak"].values)     # one notation per column
    peak, rms = (fmt_column(ds[v].values, off=merged_off)
                 for v in ("merged_error_peak", "merged_error_rms"))
    err = _table(
        ["joint", "peak |\u03c4|", "peak error", "RMS error",
         "peak error / peak |\u03c4|", "RMS error / peak |\u03c4|",
         f"own models, {_own_rule(ds)} rule (worst)", "units"],
        [[str(j + 1), tau_peak[j]]
         + (["\u2261 0 (round-off)"] * 2 + ["\u2261 0"] * 2 if merged_off[j] else
            [peak[j], rms[j], rel_peak[j], rel_rms[j]])
         + [own_worst[j], units[j]] for j in range(n)],
        align=["left"] + ["right"] * 6 + ["left"])
    counts = {c: sum(m == c for m in merged) for c in _CHOICES    # the table's words
              + (("pruned",) if "pruned" in merged else ())}
    kept = sum(m != "none" for m in merged)
    single = sum(m in ("tran", "rot") for m in merged)
    worst = _worst_cases(ds, labels)
    rule, heading, merged_text = _merged_rule(ds)
    if rule == "budget":
        eps = f"{float(ds.attrs['merged_tolerance']):g}"
        claim = merged_claim(ds)
        name = f"The merged model (budget rule, \u03b5 = {eps})"
    else:
        claim = ("has no error bound: its largest peak torque error over all trajectories is "
                 f"{_pct(np.nanmax(ds['merged_error_relative_peak'].values))} of that joint's "
                 f"peak |\u03c4| over all of them (joint "
                 f"{int(np.nanargmax(ds['merged_error_relative_peak'].values)) + 1})")
        name = "The merged model of the chapter rule"
    summary = (f"{robot}: translational share of the {len(labels)} ranked elements of D and h over "
               f"{inputs}, s = {s:g}, e = {e:g}. {name} "
               + (_recursive_clause(ds) if _form(ds) == "recursive" else
                  f"keeps both parts of {counts['both']} elements, one part of {single}, and "
                  f"drops {len(labels) - kept}")
               + f"; it {claim}. {_held_out(ds)}{_gravity(ds)}"
               f"{_cost_sentence(ds)}{_own_sentence(ds)}").strip()
    ctx = {"version": __version__, "title": f"G-D dominance sweep: {robot}, {K} trajectories",
           "summary": summary, "settings": _table(["item", "value"], settings),
           "merged_heading": heading, "merged_text": merged_text,
           "worst": worst,
           "intro": _INTRO.format(K=K, created=utc_now().isoformat(), version=__version__),
           "envelope": envelope, "error": err, "cost": cost_table(ds),
           "error_text": _error_text(ds),
           "captions": _captions(ds),
           "counts": counts, "s": f"{s:g}", "e": f"{e:g}",
           "K": K,
           "created": utc_now().isoformat(),
           "payload": None}
    if payload is not None:
        _check(payload, _PAYLOAD_REQUIRED, "payload sweep")
        masses = payload["payload"].values
        plabels = _strings(payload["element"].values)
        dom = np.array(_strings(payload["dominance"].values)).reshape(payload["share_tran"].shape)
        rows = [[lab, *(dom[p, k] for p in range(len(masses)))] for k, lab in enumerate(plabels)]
        changed = [lab for k, lab in enumerate(plabels) if len(set(dom[:, k])) > 1]
        ctx["payload"] = {
            "table": _table(["element", *(f"{m:g} kg" for m in masses)], rows,
                            colour_cols=list(range(1, len(masses) + 1))),
            "settings": _table(["item", "value"], [
                ("trajectory", _attr(payload, "input_file")),
                ("trajectory SHA-256", _attr(payload, "input_sha256")),
                ("payload masses [kg]", ", ".join(f"{m:g}" for m in masses)),
                ("payload centre of mass [m]", _attr(payload, "payload_com")),
                ("payload inertia [kg m\u00b2]", _attr(payload, "payload_inertia")),
                ("s, e", f"{_attr(payload, 'dominance_threshold')}, "
                         f"{_attr(payload, 'negligible_threshold')}")]),
            "changed": ", ".join(changed) if changed else "none",
        }
    return ctx


#: Attributes the settings table says in its own rows (or the report elsewhere), or that
#: are results; any other attribute is a setting added later and gets a row of its own.
_SAID = {
    "robot", "robot_description", "robot_source", "robot_sha256", "gravity", "gravity_units",
    "dominance_threshold", "negligible_threshold", "seed", "input_files", "inputs_sha256",
    "setpoints_total", "merge_rule", "cluster", "n_workers", "scheduler_address", "n_tasks",
    "batch_size", "elapsed_s", "compute_s", "history", "gd_analyze_version", "Conventions",
    "title", "source", "references", "input_kind", "trajectories", "started",
    "robot_reference", "merged_rule", "merged_tolerance", "merged_torque_floor",
    "merged_worst_scaled_error", "payload_mass", "random_qdd_max_source", "command",
    "mounting_base_rpy_deg", "mounting_gravity_base", "mounting_gravity_world",
    "own_model_rule", "merged_form", "merged_c_terms", "merged_c_terms_kept",
    "held_out_trajectories", "merged_base_parameters", "merged_pairs", "merged_pairs_dropped",
    "merged_dropped_pairs", "merged_gravity_dropped", "merged_guarantee_kind",
    "merged_guarantee_statement", "held_out_inside_region"}


def _settings(ds, inputs, setpoints, durations, version):
    """The settings and provenance of the sweep, each once and in words
    (:mod:`gd_analyze.reports.main_provenance` rows for the software, the run and gravity)."""
    K = int(ds.sizes["trajectory"])
    s, e = _thresholds(ds)
    batch, tasks = int(ds.attrs.get("batch_size", 0)), int(ds.attrs.get("n_tasks", 0))
    batches = -(-K // batch) if batch else 0
    rows = [
        software_row(ds, version),
        ("command", _attr(ds, "command")),
        run_row(ds),
        ("robot", f"{_attr(ds, 'robot')}: {_attr(ds, 'robot_description')} "
                  f"({_attr(ds, 'robot_reference')})"),
        ("robot file", f"{_attr(ds, 'robot_source')} (SHA-256 {_attr(ds, 'robot_sha256')})"),
        gravity_row(ds),
        ("dominance threshold s, negligibility threshold e", f"{s:g}, {e:g}"),
        ("inputs", inputs),
    ]
    if "input_files" in ds.attrs:
        rows.append(("input files", _attr(ds, "input_files")))
    rows += [
        ("SHA-256 of all inputs", _attr(ds, "inputs_sha256")),
        ("set points", f"{count(ds.attrs.get('setpoints_total', '-'))} in all"
                       + ((f" ({count(setpoints.min())} per trajectory)"
                           if setpoints.min() == setpoints.max() else
                           f" ({count(setpoints.min())}\u2013{count(setpoints.max())} per "
                           "trajectory)") if setpoints.size else "")),
        ("duration [s]", (f"{_fmt(np.min(durations))} (every trajectory)"
                          if _fmt(np.min(durations)) == _fmt(np.max(durations)) else
                          f"{_fmt(np.min(durations))} \u2013 {_fmt(np.max(durations))} "
                          f"(median {_fmt(np.median(durations))})")),
        ("merge rule", f"{ds.attrs.get('merged_rule', 'chapter')} rule (Sec. 5)"
                       + (f", \u03b5 = {_attr(ds, 'merged_tolerance')}, torque floor "
                          f"{_floor(ds)}"
                          if "merged_tolerance" in ds.attrs else "")),
        ("payload on the last link", f"{_attr(ds, 'payload_mass', '0')} kg"
         if float(ds.attrs.get("payload_mass", 0.0) or 0.0) else "none"),
    ]
    if "merged_guarantee_statement" in ds.attrs:        # the merged model's scope
        rows.append(("guarantee of the merged model",
                     f"{_attr(ds, 'merged_guarantee_kind')} kind: "
                     + scope_markup(_attr(ds, 'merged_guarantee_statement'))))
    if "random_qdd_max_source" in ds.attrs:
        rows.append(("random accelerations limited by",
                     {"robot": "the robot's acceleration limits"}.get(
                         str(ds.attrs["random_qdd_max_source"]),
                         _attr(ds, "random_qdd_max_source"))))
    rows += [
        ("computed on", f"dask, {_attr(ds, 'cluster')} ({_attr(ds, 'n_workers')} "
                        f"worker{'s' if str(ds.attrs.get('n_workers')) != '1' else ''} "
                        f"joined; scheduler at {_attr(ds, 'scheduler_address')}); {tasks} "
                        f"tasks (the {K} "
                        f"trajectories in {batches} batch{'es' if batches != 1 else ''} of "
                        f"at most {batch}, "
                        + ("each batch once to rank and once to check the merged model"
                           + (f"; {tasks - 2 * batches} more to check it on the held-out "
                              "trajectories" if tasks > 2 * batches else "") + ")"
                           if tasks > batches else
                           "each batch once to rank and to find the peaks of the recursive "
                           "model's contributions; the merged model was built and checked on "
                           "the client)")),
        ("time [s]", f"{_attr(ds, 'elapsed_s')} in all, {_attr(ds, 'compute_s')} computing"),
    ]
    rows += [(key.replace("_", " "), _attr(ds, key)) for key in sorted(set(ds.attrs) - _SAID)]
    return rows


def _gravity(ds):
    """The merged model's terms of c as a sentence ("It drops 8 of the 28 terms of c. "), or
    "" where the dataset does not count them."""
    rule = str(ds.attrs.get("merged_rule", "chapter"))
    if rule == "budget" and _form(ds) == "recursive":
        return f"It {_recursive_gravity(ds)}. "
    kept, full = (int(ds.attrs.get(k, -1)) for k in ("merged_c_terms_kept", "merged_c_terms"))
    if rule == "budget" and min(kept, full) < 0:
        return ""
    return f"It {gravity_clause(rule, c_terms=(kept, full))}. "


def _share(value, zero):
    """A share of the envelope as printed: "\u2261 0" for an element that is round-off on
    every trajectory (its share is noise: NaN in the dataset), else four decimals."""
    return "\u2261 0" if zero or not np.isfinite(value) else _share_text(value)


def _own_worst(ds):
    """The largest relative peak torque error of the trajectories' own models per joint, as
    one column in one format (:func:`gd_analyze.reports.common.pct_column`): round-off of that
    trajectory's peak |\u03c4| counted as 0, "\u2261 0" where it is round-off on every
    trajectory (:func:`gd_analyze.core.selection.ranking.is_round_off`)."""
    rel = np.asarray(ds["tau_error_relative_peak"].values, float)
    off = torque_error_round_off(ds, ds["tau_error_peak"].values, ds["tau_peak"].values)
    rel = np.where(off, 0.0, rel)
    worst = np.array([np.nanmax(col) if np.isfinite(col).any() else np.nan for col in rel.T])
    return pct_column(worst, off.all(axis=0))


def _worst_cases(ds, labels):
    """The sweep's worst cases, first: trajectories with the largest merged-model error, and
    the elements whose share_tran varies most over the trajectories."""
    rel = ds["merged_tau_error_relative_peak"].values          # (K, n)
    sources = _strings(ds["source"].values)
    per_traj = np.where(np.isfinite(rel), rel, -np.inf).max(axis=1)
    order = [k for k in np.argsort(per_traj)[::-1][:3] if np.isfinite(per_traj[k])]
    parts = []
    for k in order:
        j = int(np.nanargmax(rel[k]))
        scale = (f"{_SI} over the region" if ds.attrs.get("merged_guarantee_kind") == "region"
                 else f"its own {_SI}" if "merged_scale" in ds.variables else "its own peak |τ|")
        parts.append(f"{sources[k]} ({_pct(rel[k, j])} of {scale} at joint {j + 1})")
    spread = ds["share_tran_max"].values - ds["share_tran_min"].values
    top = [k for k in np.argsort(np.nan_to_num(spread, nan=-1.0))[::-1][:3]
           if np.isfinite(spread[k])]
    elems = [f"{_element(labels[k])} ({_share_text(ds['share_tran_min'].values[k])}\u2013"
             f"{_share_text(ds['share_tran_max'].values[k])})" for k in top]
    text = "Worst cases: "
    text += ("the merged model's largest torque errors are on " + "; ".join(parts) + ". "
             if parts else "no torque error is defined. ")
    text += ("The classes vary most for " + ", ".join(elems) + " (range of the translational "
             "share over the trajectories)." if elems else "")
    return text


def _element(label):
    """An element's label ("D14", "h2", "D1,10") as mathematics: D with its index as a
    subscript."""
    return _el(label[0], label[1:])


_INTRO = ("The generalized d'Alembert (G-D) equations of motion split the inertia matrix D and "
          "the Coriolis and centrifugal vector h into a translational and a rotational part (Fu, "
          "Gonzalez & Lee 1987, Robotics, Sec. 3.4). Sec. 3.4.1 ranks which part dominates each "
          "element along one trajectory and notes that the simplification depends on the "
          "trajectory; this report repeats the ranking over {K} trajectories. Report created "
          "{created} by gd-analyze {version} from the stored sweep; nothing was recomputed.")


#: Captions of the sweep report's figures (the same in the HTML and the PDF).
SWEEP_CAPTIONS = {
    "D": "Distribution of the translational share of the elements of D over the sweep (layout of Fig. 3.10): "
         "box of the quartiles, whiskers at the minimum and maximum, coloured bar at the median, "
         "thresholds s and 1 \u2212 s dashed. Panel title: element and the merged model's "
         "choice; bottom line: fraction of trajectories per class.",
    "h": "Distribution of the translational share of the Coriolis and centrifugal elements "
         + _el("h", "i") + " over the "
         "sweep (layout of Fig. 3.11); same conventions as for D.",
    "classes": "Fraction of the trajectories in each class, per element; the merged model's "
               "choice on the right.",
    "error": "Relative peak torque error per joint: of each trajectory's own simplified model "
             "(green) and of the merged model (black), per trajectory; diamond: merged model over "
             "all trajectories.",
    "payload": "Translational share of every element against the payload mass on the last link, with "
               "the class of each cell (T, R, B, N); below, peak |\u03c4| per joint.",
}

SHARE_TEXT = ("For each trajectory and element X, the translational share is \u03a3|"
               + _el("X", "", "tran") + "| / (\u03a3|" + _el("X", "", "tran") + "| + \u03a3|"
               + _el("X", "", "rot") + "|) over its set points. One panel per element "
               + _el("D", "ij") + " with i \u2264 j (row i, column j): a box of the share over "
               "the trajectories (quartiles; whiskers at the minimum and maximum; the coloured "
               "bar is the median), with the thresholds s and 1 \u2212 s dashed. A share above s = {s} is translational, below "
               "1 \u2212 s rotational, in between both, unless the element is negligible (peak "
               "below e = {e} times its scale).")


def _own_sentence(ds):
    """The own models' worst relative peak error, named with their rule (they carry no
    bound under the chapter rule)."""
    rel = np.asarray(ds["tau_error_relative_peak"].values, float)
    rel = np.where(torque_error_round_off(ds, ds["tau_error_peak"].values, ds["tau_peak"].values), 0.0, rel)
    if not np.isfinite(rel).any() or not np.nanmax(rel) > 0:
        return ""
    k, j = np.unravel_index(np.nanargmax(np.where(np.isfinite(rel), rel, -np.inf)), rel.shape)
    own, _ = _models(ds)
    return (f"For comparison, {own} errs by up to {_pct(rel[k, j])} of peak |{_TAU_I}| "
            f"(joint {j + 1}); it is not the model written.")


def _error_text(ds):
    """Sec. 5.1's note: the table's columns, each model named with its rule."""
    own, merged = _models(ds)
    return ("Per joint, over all set points of all swept trajectories: peak and RMS of the "
            "open-loop torque error |\u03c4" + _sub("s") + " \u2212 \u03c4| (the simplified "
            "and the full model's torques along the same desired motion, no controller) "
            f"[{units_said_once(ds, 'tau')}] of {merged}, and both relative to the peak |\u03c4| "
            f"over all trajectories. Column \u201cown models, {_own_rule(ds)} rule "
            f"(worst)\u201d: the largest relative peak error of {own} along that "
            "trajectory, shown for comparison; it is not the merged model"
            + (" and has no bound." if _own_rule(ds) == "chapter" else ".")
            + (" " + _held_out(ds).strip() if _held_out(ds) else ""))


def _captions(ds):
    """The figure captions, with the models and the merged choice "none" said from the
    dataset's rules."""
    own, merged = _models(ds)
    region = ds.attrs.get("merged_guarantee_kind") == "region"
    dots = (" Grey dots beside each box: the share on each trajectory, one dot per "
            "trajectory (spread sideways to stay apart; not drawn beyond 60 trajectories).")
    none = ("The merged model's choice \u201cnone\u201d: it keeps neither part of the "
            "element (" + ("both parts dropped within the budget \u03b5, or \u2261 0"
                           if str(ds.attrs.get("merged_rule", "chapter")) == "budget" else
                           "negligible, or \u2261 0, on every trajectory") + ").")
    return {
        **SWEEP_CAPTIONS,
        "D": f"{SWEEP_CAPTIONS['D']}{dots}",
        "h": f"{SWEEP_CAPTIONS['h']}{dots}",
        "classes": f"{SWEEP_CAPTIONS['classes']} {none}", "none": none,
        "error": (f"Relative peak open-loop torque error per joint, per trajectory: of {own} "
                  "(green) "
                  f"and of {merged} (black); diamond: the merged model over all trajectories"
                  + (f"; every mark relative to one scale, the merged model's {_SI} over the "
                     "region" if region else "; each relative to the peak |\u03c4| of its "
                     "trajectory (the diamond: over all of them)")
                  + f". Round-off ({TORQUE_ROUND_OFF_WORDS} peak |\u03c4|) is not drawn."),
    }
