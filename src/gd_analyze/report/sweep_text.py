"""The sweep report's words: its context (tables, summary, captions) and every sentence
about the own and the merged models, generated from the stored sweep and its rules
(:mod:`gd_analyze.report.sweep` renders them as HTML and PDF)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .._version import VERSION as __version__
from ..ranking.ranking import CLASSES
from ..store.sweep_view import PayloadSweep, StoredSweep
from .common import attr_text as _text
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
from .common import table as _table
from .main_provenance import gravity_row, run_row, software_row
from .main_text import gravity_clause
from .markup import element as _el
from .markup import scope as scope_markup
from .markup import sub as _sub
from .sweep_figures import (
    ERROR_FLOOR,
    TORQUE_ROUND_OFF_WORDS,
    error_marks,
    torque_error_round_off,
)
from .sweep_merged_text import (
    _SI,
    _TAU_I,
    _cost_sentence,
    _floor,
    _held_out,
    _merged_rule,
    _models,
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

def sweep_context(ds: StoredSweep | xr.Dataset,
                  payload: PayloadSweep | xr.Dataset | None = None) -> dict[str, Any]:
    """Everything the sweep report says, from the stored sweep (and payload sweep): the
    tables, the summary, the captions and the sentences about the models.

    Parameters
    ----------
    ds : StoredSweep or xarray.Dataset
        The stored sweep (:class:`gd_analyze.store.sweep_view.StoredSweep`), or a sweep dataset
        (:func:`gd_analyze.jobs.sweep.run_sweep`).
    payload : PayloadSweep or xarray.Dataset, optional
        A payload sweep (:func:`gd_analyze.jobs.payload.payload_sweep`), typed
        (:class:`gd_analyze.store.sweep_view.PayloadSweep`) or not.

    Returns
    -------
    dict
        The report's context, the same for the HTML and the PDF.

    Raises
    ------
    InputError
        If a dataset lacks a variable the report needs.
    """
    w = StoredSweep.of(ds)
    m, st = w.merged, w.settings
    K = w.trajectories
    n = w.joints
    labels = list(w.elements)
    frac = w.class_fraction
    merged = list(m.choice)
    s, e = _thresholds(st)
    robot = _text(st.robot)
    kind = str("" if st.input_kind is None else st.input_kind)
    if kind == "random" and st.seed is not None:
        inputs = f"{K} random quintic trajectories (seed {_text(st.seed)})"
    else:
        inputs = f"{K} trajectories ({kind or 'given'})"
    durations = w.duration
    setpoints = w.setpoints
    settings = _settings(w, inputs, setpoints, durations, __version__)
    zero = np.asarray(w.round_off.all(axis=0) if w.round_off_stored
                      else np.zeros(len(labels), bool), bool)
    envelope = _table(
        ["element", "translational", "rotational", "both", "negligible", "min share",
         "median share", "max share", "merged choice"],
        [[lab, *(f"{f:.3f}" for f in frac[k]),
          *(_share(spread[k], zero[k]) for spread in (w.share_min, w.share_median,
                                                      w.share_max)),
          merged[k]] for k, lab in enumerate(labels)],
        align=["left"] + ["right"] * 7 + ["left"], colour_cols=[8])
    units = torque_units(m)
    merged_off = torque_error_round_off(m, w.merged_error_peak, w.merged_error_tau_peak)
    rel_peak = pct_column(w.merged_error_relative_peak, merged_off)   # one format
    rel_rms = pct_column(w.merged_error_relative_rms, merged_off)     # per column
    own_worst = _own_worst(w)
    tau_peak = fmt_column(w.merged_error_tau_peak)     # one notation per column
    peak, rms = (fmt_column(v, off=merged_off)
                 for v in (w.merged_error_peak, w.merged_error_rms))
    err = _table(
        ["joint", "peak |\u03c4|", "peak error", "RMS error",
         "peak error / peak |\u03c4|", "RMS error / peak |\u03c4|",
         f"own models, {m.own_rule} rule (worst)", "units"],
        [[str(j + 1), tau_peak[j]]
         + (["\u2261 0 (round-off)"] * 2 + ["\u2261 0"] * 2 if merged_off[j] else
            [peak[j], rms[j], rel_peak[j], rel_rms[j]])
         + [own_worst[j], units[j]] for j in range(n)],
        align=["left"] + ["right"] * 6 + ["left"])
    counts = {c: sum(m == c for m in merged) for c in _CHOICES    # the table's words
              + (("pruned",) if "pruned" in merged else ())}
    kept = sum(m != "none" for m in merged)
    single = sum(m in ("tran", "rot") for m in merged)
    worst = _worst_cases(w, labels)
    rule, heading, merged_text = _merged_rule(m)
    if rule == "budget":
        eps = f"{float(m.tolerance):g}"
        claim = merged_claim(m)
        name = f"The merged model (budget rule, \u03b5 = {eps})"
    else:
        claim = ("has no error bound: its largest peak torque error over all trajectories is "
                 f"{_pct(np.nanmax(w.merged_error_relative_peak))} of that joint's "
                 f"peak |\u03c4| over all of them (joint "
                 f"{int(np.nanargmax(w.merged_error_relative_peak)) + 1})")
        name = "The merged model of the chapter rule"
    summary = (f"{robot}: translational share of the {len(labels)} ranked elements of D and h over "
               f"{inputs}, s = {s:g}, e = {e:g}. {name} "
               + (_recursive_clause(m) if m.form == "recursive" else
                  f"keeps both parts of {counts['both']} elements, one part of {single}, and "
                  f"drops {len(labels) - kept}")
               + f"; it {claim}. {_held_out(m)}{_gravity(m)}"
               f"{_cost_sentence(m)}{_own_sentence(w)}").strip()
    ctx = {"version": __version__, "title": f"G-D dominance sweep: {robot}, {K} trajectories",
           "summary": summary, "settings": _table(["item", "value"], settings),
           "merged_heading": heading, "merged_text": merged_text,
           "worst": worst,
           "intro": _INTRO.format(K=K, created=utc_now().isoformat(), version=__version__),
           "envelope": envelope, "error": err, "cost": cost_table(m.costs),
           "error_text": _error_text(m),
           "captions": _captions(m),
           "figure_text": _figure_text(w, zero, counts),
           "counts": counts, "s": f"{s:g}", "e": f"{e:g}",
           "K": K,
           "created": utc_now().isoformat(),
           "payload": None}
    if payload is not None:
        part = PayloadSweep.of(payload)
        masses = part.masses
        plabels = list(part.elements)
        dom = part.dominance.reshape(part.share_tran.shape)
        rows = [[lab, *(dom[p, k] for p in range(len(masses)))] for k, lab in enumerate(plabels)]
        changed = [lab for k, lab in enumerate(plabels) if len(set(dom[:, k])) > 1]
        ctx["figure_text"]["payload"] = _payload_text(masses)
        ctx["payload"] = {
            "table": _table(["element", *(f"{m:g} kg" for m in masses)], rows,
                            colour_cols=list(range(1, len(masses) + 1))),
            "settings": _table(["item", "value"], [
                ("trajectory", _text(part.input_file)),
                ("trajectory SHA-256", _text(part.input_sha256)),
                ("payload masses [kg]", ", ".join(f"{m:g}" for m in masses)),
                ("payload centre of mass [m]", _text(part.payload_com)),
                ("payload inertia [kg m\u00b2]", _text(part.payload_inertia)),
                ("s, e", f"{_text(part.dominance_threshold)}, "
                         f"{_text(part.negligible_threshold)}")]),
            "changed": ", ".join(changed) if changed else "none",
        }
    return ctx


def _or(value, default):
    """A stored attribute's value, or ``default`` where it is missing (None)."""
    return default if value is None else value


def _thresholds(st):
    """s and e as stored (NaN where missing)."""
    return (float(_or(st.dominance_threshold, np.nan)),
            float(_or(st.negligible_threshold, np.nan)))


def _settings(w, inputs, setpoints, durations, version):
    """The settings and provenance of the sweep, each once and in words
    (:mod:`gd_analyze.report.main_provenance` rows for the software, the run and gravity)."""
    st, m = w.settings, w.merged
    K = w.trajectories
    s, e = _thresholds(st)
    batch, tasks = int(_or(st.batch_size, 0)), int(_or(st.n_tasks, 0))
    batches = -(-K // batch) if batch else 0
    rows = [
        software_row(w.run, version),
        ("command", _text(st.command)),
        run_row(w.run),
        ("robot", f"{_text(st.robot)}: {_text(st.robot_description)} "
                  f"({_text(st.robot_reference)})"),
        ("robot file", f"{_text(st.robot_source)} (SHA-256 {_text(st.robot_sha256)})"),
        gravity_row(w.run),
        ("dominance threshold s, negligibility threshold e", f"{s:g}, {e:g}"),
        ("inputs", inputs),
    ]
    if st.input_files is not None:
        rows.append(("input files", _text(st.input_files)))
    rows += [
        ("SHA-256 of all inputs", _text(st.inputs_sha256)),
        ("set points", f"{count(_or(st.setpoints_total, '-'))} in all"
                       + ((f" ({count(setpoints.min())} per trajectory)"
                           if setpoints.min() == setpoints.max() else
                           f" ({count(setpoints.min())}\u2013{count(setpoints.max())} per "
                           "trajectory)") if setpoints.size else "")),
        ("duration [s]", (f"{_fmt(np.min(durations))} (every trajectory)"
                          if _fmt(np.min(durations)) == _fmt(np.max(durations)) else
                          f"{_fmt(np.min(durations))} \u2013 {_fmt(np.max(durations))} "
                          f"(median {_fmt(np.median(durations))})")),
        ("merge rule", f"{_or(st.merged_rule, 'chapter')} rule (Sec. 5)"
                       + (f", \u03b5 = {_text(m.tolerance)}, torque floor "
                          f"{_floor(m)}"
                          if m.tolerance is not None else "")),
        ("payload on the last link", f"{_text(st.payload_mass, '0')} kg"
         if float(_or(st.payload_mass, 0.0) or 0.0) else "none"),
    ]
    if m.guarantee_statement is not None:        # the merged model's scope
        rows.append(("guarantee of the merged model",
                     f"{_text(m.guarantee_kind)} kind: "
                     + scope_markup(_text(m.guarantee_statement))))
    if st.random_qdd_max_source is not None:
        rows.append(("random accelerations limited by",
                     {"robot": "the robot's acceleration limits"}.get(
                         str(st.random_qdd_max_source),
                         _text(st.random_qdd_max_source))))
    rows += [
        ("computed on", f"{_text(st.cluster)} (the {K} trajectories in {batches} "
                        f"batch{'es' if batches != 1 else ''}: ranked, and the merged model "
                        "built and checked on every trajectory, in the process of the command)")
        if not int(_or(st.n_workers, 1)) else
        ("computed on", f"dask, {_text(st.cluster)} ({_text(st.n_workers)} "
                        f"worker{'s' if str(st.n_workers) != '1' else ''} "
                        f"joined; scheduler at {_text(st.scheduler_address)}); {tasks} "
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
        ("time [s]", f"{_text(st.elapsed_s)} in all, {_text(st.compute_s)} computing"),
    ]
    rows += [(key.replace("_", " "), _text(value)) for key, value in st.others]
    return rows


def _gravity(m):
    """The merged model's terms of c as a sentence ("It drops 8 of the 28 terms of c. "), or
    "" where the dataset does not count them."""
    rule = m.rule
    if rule == "budget" and m.form == "recursive":
        return f"It {_recursive_gravity(m)}. "
    kept, full = m.c_terms_kept, m.c_terms
    if rule == "budget" and min(kept, full) < 0:
        return ""
    return f"It {gravity_clause(rule, c_terms=(kept, full))}. "


def _share(value, zero):
    """A share of the envelope as printed: "\u2261 0" for an element that is round-off on
    every trajectory (its share is noise: NaN in the dataset), else four decimals."""
    return "\u2261 0" if zero or not np.isfinite(value) else _share_text(value)


def _own_worst(w):
    """The largest relative peak torque error of the trajectories' own models per joint, as
    one column in one format (:func:`gd_analyze.report.common.pct_column`): round-off of that
    trajectory's peak |\u03c4| counted as 0, "\u2261 0" where it is round-off on every
    trajectory (:func:`gd_analyze.ranking.ranking.is_round_off`)."""
    rel = np.asarray(w.tau_error_relative_peak, float)
    off = torque_error_round_off(w.merged, w.tau_error_peak, w.tau_peak)
    rel = np.where(off, 0.0, rel)
    worst = np.array([np.nanmax(col) if np.isfinite(col).any() else np.nan for col in rel.T])
    return pct_column(worst, off.all(axis=0))


def _worst_cases(w, labels):
    """The sweep's worst cases, first: trajectories with the largest merged-model error, and
    the elements whose share_tran varies most over the trajectories."""
    m = w.merged
    rel = w.merged_tau_error_relative_peak          # (K, n)
    sources = w.sources
    per_traj = np.where(np.isfinite(rel), rel, -np.inf).max(axis=1)
    order = [k for k in np.argsort(per_traj)[::-1][:3] if np.isfinite(per_traj[k])]
    parts = []
    for k in order:
        j = int(np.nanargmax(rel[k]))
        scale = (f"{_SI} over the region" if m.region
                 else f"its own {_SI}" if m.scale is not None else "its own peak |τ|")
        parts.append(f"{sources[k]} ({_pct(rel[k, j])} of {scale} at joint {j + 1})")
    spread = w.share_max - w.share_min
    top = [k for k in np.argsort(np.nan_to_num(spread, nan=-1.0))[::-1][:3]
           if np.isfinite(spread[k])]
    elems = [f"{_element(labels[k])} ({_share_text(w.share_min[k])}\u2013"
             f"{_share_text(w.share_max[k])})" for k in top]
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
         "thresholds s and 1 \u2212 s dashed. Panel title: element (D(i,j) for "
         + _el("D", "ij") + ", in row i and column j) and the merged model's "
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
              + _el("X", "", "rot") + "|) over its set points. A share above s = {s} is "
              "translational, below 1 \u2212 s rotational, in between both, unless the element "
              "is negligible (peak below e = {e} times its scale). The figures draw the share "
              "over the trajectories as a box per element (their captions and keys say how).")


def _own_sentence(w):
    """The own models' worst relative peak error, named with their rule (they carry no
    bound under the chapter rule)."""
    m = w.merged
    rel = np.asarray(w.tau_error_relative_peak, float)
    rel = np.where(torque_error_round_off(m, w.tau_error_peak, w.tau_peak), 0.0, rel)
    if not np.isfinite(rel).any() or not np.nanmax(rel) > 0:
        return ""
    k, j = np.unravel_index(np.nanargmax(np.where(np.isfinite(rel), rel, -np.inf)), rel.shape)
    own, _ = _models(m)
    return (f"For comparison, {own} errs by up to {_pct(rel[k, j])} of peak |{_TAU_I}| "
            f"(joint {j + 1}); it is not the model written.")


def _error_text(m):
    """Sec. 5.1's note: the table's columns, each model named with its rule."""
    own, merged = _models(m)
    return ("Per joint, over all set points of all swept trajectories: peak and RMS of the "
            "open-loop torque error |\u03c4" + _sub("s") + " \u2212 \u03c4| (the simplified "
            "and the full model's torques along the same desired motion, no controller) "
            f"[{units_said_once(m, 'tau')}] of {merged}, and both relative to the peak |\u03c4| "
            f"over all trajectories. Column \u201cown models, {m.own_rule} rule "
            f"(worst)\u201d: the largest relative peak error of {own} along that "
            "trajectory, shown for comparison; it is not the merged model"
            + (" and has no bound." if m.own_rule == "chapter" else ".")
            + (" " + _held_out(m).strip() if _held_out(m) else ""))


def _captions(m):
    """The figure captions, with the models and the merged choice "none" said from the
    dataset's rules."""
    own, merged = _models(m)
    region = m.region
    dots = (" Grey dots beside each box: the share on each trajectory, one dot per "
            "trajectory (spread sideways to stay apart; not drawn beyond 60 trajectories).")
    none = ("The merged model's choice \u201cnone\u201d: it keeps neither part of the "
            "element (" + ("both parts dropped within the budget \u03b5, or \u2261 0"
                           if m.rule == "budget" else
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
                  + f". Round-off ({TORQUE_ROUND_OFF_WORDS} peak |\u03c4|) is not drawn. "
                  f"The figure writes \u0394\u03c4 for \u03c4{_sub('s')} \u2212 \u03c4"
                  + (f" and s for {_SI}" if region else "") + "."),
    }


# --------------------------------------------------------------------------------------------
# The sentences that cite the figures ("Fig. 2 shows ..."): what each figure shows of this sweep
# --------------------------------------------------------------------------------------------

#: At most this many elements are named in a list of a figure's sentence; the rest counted.
_NAMED = 6


def _names(labels):
    """Elements as mathematics, at most :data:`_NAMED` of them named ("D11, D12 and 3
    more")."""
    said = [_element(lab) for lab in labels[:_NAMED]]
    more = len(labels) - len(said)
    if more:
        return ", ".join(said) + f" and {count(more)} more"
    return said[0] if len(said) == 1 else ", ".join(said[:-1]) + " and " + said[-1]


def _steady(fractions):
    """The class an element holds on every trajectory (its class fractions), or None."""
    k = int(np.argmax(fractions))
    return CLASSES[k] if np.isclose(fractions[k], 1.0) else None


def _share_sentence(w, symbol, zero):
    """What the share figure of D or of h shows of this sweep: how many of its elements hold
    one class on every trajectory (by class), which change class, which are round-off on every
    trajectory, and the widest box; a predicate ("shows ...")."""
    labels = list(w.elements)
    mine = [k for k, lab in enumerate(labels) if lab.startswith(symbol)]
    K = w.trajectories
    frac = np.asarray(w.class_fraction, float)
    off = [k for k in mine if zero[k]]
    rest = [k for k in mine if not zero[k]]
    steady = {c: [k for k in rest if _steady(frac[k]) == c] for c in CLASSES}
    varying = [k for k in rest if _steady(frac[k]) is None]
    every = "the trajectory" if K == 1 else "every trajectory"
    text = (f"shows the translational share of each of the {len(mine)} elements of {symbol} "
            + ("along the one trajectory: " if K == 1 else f"over the {K} trajectories: "))
    held = [f"{count(len(ks))} {c}" for c, ks in steady.items() if ks]
    n_held = sum(len(ks) for ks in steady.values())
    parts = []
    if n_held:
        parts.append(f"{count(n_held)} {'is' if n_held == 1 else 'are'} of one class on "
                     f"{every} ({', '.join(held)})")
    if K > 1:
        parts.append((f"{count(len(varying))} change{'s' if len(varying) == 1 else ''} class "
                      f"from one trajectory to another ({_names([labels[k] for k in varying])})")
                     if varying else "none changes class from one trajectory to another")
    if off:
        parts.append(f"{count(len(off))} {'is' if len(off) == 1 else 'are'} round-off on "
                     f"{every} (\u2261 0, no share drawn: {_names([labels[k] for k in off])})")
    text += "; ".join(parts) + "."
    spread = np.asarray(w.share_max, float) - np.asarray(w.share_min, float)
    ranged = [k for k in rest if np.isfinite(spread[k])]
    if K > 1 and ranged:
        k = max(ranged, key=lambda k: spread[k])
        text += (f" The widest box is that of {_element(labels[k])}, from "
                 f"{_share_text(w.share_min[k])} to {_share_text(w.share_max[k])}"
                 if spread[k] > 0 else
                 " Every element has the same share on every trajectory")
        text += "."
    return text


def _classes_sentence(w, zero, counts):
    """What the class-fraction figure shows of this sweep: how many bars are of one colour,
    and the merged model's choices beside them; a predicate."""
    frac = np.asarray(w.class_fraction, float)
    M, K = len(w.elements), w.trajectories
    one = sum(_steady(frac[k]) is not None for k in range(M))
    choices = ", ".join(f"{c} {count(k)}" for c, k in counts.items() if k)
    return (f"shows the fraction of the {K} trajector{'y' if K == 1 else 'ies'} in each class "
            f"for all {M} elements, with the merged model's choice beside each bar ({choices})"
            + (f"; {count(one)} of the {M} bars are of one colour: the element is of one class "
               "on every trajectory" if K > 1 else "") + ".")


def _error_sentence(w):
    """What the torque-error figure shows of this sweep: the largest relative peak error of
    the merged and of the own models, and the joints where the merged model's is round-off on
    every trajectory (not drawn); from the marks the figure draws
    (:func:`gd_analyze.report.sweep_figures.error_marks`); a predicate."""
    own, merged, _, region = error_marks(w)
    scale = f"{_SI} over the region" if region else "that trajectory's peak |\u03c4|"

    def largest(marks):
        drawn = np.where(np.isfinite(marks) & (marks > ERROR_FLOOR), marks, -np.inf)
        if not np.isfinite(drawn).any():
            return "round-off on every joint and trajectory"
        k, j = np.unravel_index(np.argmax(drawn), drawn.shape)
        return f"at most {_pct(drawn[k, j])} of {scale} (joint {j + 1})"

    quiet = [j + 1 for j in range(w.joints)
             if not (np.isfinite(merged[:, j]) & (merged[:, j] > ERROR_FLOOR)).any()]
    text = (f"shows the relative peak errors per trajectory and joint: the merged model's is "
            f"{largest(merged)}, each trajectory's own model's {largest(own)}")
    if quiet and len(quiet) < w.joints:
        text += (f"; on joint{'s' if len(quiet) > 1 else ''} "
                 f"{', '.join(map(str, quiet))} the merged model's error is round-off on every "
                 "trajectory and not drawn")
    return text + "."


def _payload_text(masses):
    """What the payload figure shows: the share and class of every element against the
    payload mass, and the peak torques; a predicate."""
    return (f"shows the translational share and the class of every element at each of the "
            f"{len(masses)} payload masses ({', '.join(f'{m:g}' for m in masses)} kg), and "
            "the peak |\u03c4| per joint below.")


def _figure_text(w, zero, counts):
    """Each figure's sentence, by key, without its subject ("shows ..."): the report writes
    "Fig. 2 " before it, with the number the outline gives the figure."""
    return {"D": _share_sentence(w, "D", zero), "h": _share_sentence(w, "h", zero),
            "classes": _classes_sentence(w, zero, counts), "error": _error_sentence(w)}
