"""The sentences of the main report: its three-sentence conclusion, the cause of each
disagreement with the chapter, and the figure captions (the same in the HTML and the PDF).

Every sentence is built from the stored ranking and torque errors; nothing is recomputed.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..ranking.ranking import element_label, parse_element_label
from .figure_style import element_markevery
from .markup import element, sub
from .numbers import share as _share
from .plot_data import ENVELOPE_COLUMNS

if TYPE_CHECKING:
    import numpy.typing as npt

__all__ = ["conclusion", "PLACEHOLDER_INERTIA", "model_sentence", "gravity_clause", "simplified_intro", "disagreement_cause", "shared_causes", "captions",
           "element_scale", "prismatic_count_note", "alike_sentence"]

_CLASSES = ("translational", "rotational", "both", "negligible")


def element_scale(labels: Sequence[str], peak_total: npt.NDArray[np.float64],
                  tau_peak: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Each element's own scale: peak sqrt(D_ii D_jj) bound for D_ij, peak |tau_i| for h_i.

    Parameters
    ----------
    labels : sequence of str
        ``D11``, ``D12``, ..., ``h1``, ... (``D1,10`` for two-digit indices).
    peak_total : ndarray, shape (M,)
        Peak |D_ij| or |h_i| over the set points.
    tau_peak : ndarray, shape (n,)
        Peak |tau_i| [N m].

    Returns
    -------
    ndarray, shape (M,)
        sqrt(peak D_ii * peak D_jj) [kg m^2] (>= the peak of sqrt(D_ii D_jj)) or peak |tau_i|.
    """
    n = np.asarray(tau_peak).size
    index = {lab: k for k, lab in enumerate(labels)}
    out = np.zeros(len(labels))
    for k, lab in enumerate(labels):
        kind, i, j = parse_element_label(lab, n)
        if kind == "D":
            dii = peak_total[index[element_label("D", i, i)]]
            djj = peak_total[index[element_label("D", j, j)]]
            out[k] = np.sqrt(abs(dii * djj))
        else:
            out[k] = tau_peak[i]
    return out


#: The simplified model's torque tau_s and the subscript s of its D, h and c, set as
#: subscripts (8 pt at least in the PDF), not as Unicode's small letters.
_S = sub("s")
_TAU_S = "\u03c4" + _S


def _math(label):
    """An element's label as mathematics, its index a subscript: "D12" -> D with 12 marked."""

    return element(label[0], label[1:])


def _names(labels):
    if not labels:
        return "none"
    if len(labels) <= 6:
        return ", ".join(map(_math, labels))
    return ", ".join(map(_math, labels[:5])) + f" and {len(labels) - 5} more"


def _are(k):
    """The verb after "k of m elements": "1 of 6 elements is", "4 of 21 elements are"."""
    return "is" if k == 1 else "are"


def _qty(value, unit):
    """A number and its unit joined by no-break spaces ("4.9\u00a0N\u00a0m"): a line never
    ends between them (the Stanford summary broke "4.9 N" / "m")."""
    return f"{value:.3g}\u00a0" + str(unit).replace(" ", "\u00a0")


def _qty_text(text, unit):
    """A number already formatted and its unit, joined as :func:`_qty` joins them."""
    return f"{text}\u00a0" + str(unit).replace(" ", "\u00a0")


#: Said after "rotational effects lead" (or "both") for a robot whose inertia tensors are
#: placeholders: the rotational parts are made of them.
PLACEHOLDER_INERTIA = (" (on this robot's placeholder inertia tensors, stand-ins in its URDF, "
                       "not measured values: the rotational parts are made of them, so this "
                       "is not a finding about the real arm)")


def conclusion(labels: Sequence[str], dominance: Sequence[str], zero: npt.NDArray[np.bool_],
               choice: Sequence[str], rel_peak: npt.NDArray[np.float64],
               abs_peak: npt.NDArray[np.float64], tau_peak: npt.NDArray[np.float64],
               cost: tuple[int, int, int | None] | tuple[int, int, int | None, int | None, int | None] | None = None,
               recursive: tuple[int, int, int] | None = None, gravity: str | None = None,
               units: Sequence[str] | None = None, scope: str | None = None,
               where: str = "this trajectory", shown: Mapping[str, Sequence[str]] | None = None,
               placeholder_inertia: bool = False,
               round_off: npt.ArrayLike | None = None) -> str:
    """The report's conclusion in three sentences.

    Parameters
    ----------
    labels, dominance, choice : list of str
        Element labels, their classes and the simplified model's kept part per element.
    zero : ndarray of bool
        Elements zero in every part (:func:`gd_analyze.report.main_figures.identically_zero`).
    rel_peak, abs_peak, tau_peak : ndarray, shape (n,)
        Per joint: peak |tau_s - tau| / peak |tau| [1], peak |tau_s - tau| [N m], peak |tau|.
    round_off : ndarray of bool, shape (n,), optional
        Per joint, the torque error is round-off (``round_off`` of the stored torque error,
        marked \u2261 0 in the error table): where every joint's is, the sentence says so
        instead of naming a largest error.
    placeholder_inertia : bool, optional
        The robot's inertia tensors are placeholders (``robot_placeholder_inertia``): where
        rotational effects lead, the sentence says so (:data:`PLACEHOLDER_INERTIA`).
    shown : dict of str to list of str, optional
        Those numbers as the error table prints them (``rel``, ``abs``, ``tau``), quoted so
        that the text and the table agree digit for digit; else 3 digits.
    cost : tuple of (int, int, int or None[, int or None, int or None]), optional
        The emitted model's multiplications and additions per set point, Newton-Euler's
        operations as implemented (None if not counted), and optionally the operations of the
        exact (nothing dropped) model and of the full explicit model, which the sentence then
        names beside Newton-Euler's.
    recursive : tuple of (int, int, int), optional
        For a model of the recursive form: its number of base parameters, of dropped
        (parameter, part) pairs and of pairs; ``choice`` is then not used.
    gravity : str, optional
        What the model does with the gravity loading c, as a clause (``"keeps c whole"``,
        ``"drops terms of c ..."``); the sentence on the model ends with it.
    units : list of str, optional
        Units of each joint's torque (N m, or N for a prismatic joint); N m if not given.
    where : str, optional
        Where the recursive model's pairs were judged: ``"this trajectory"``, or ``"the
        joint-limit region"`` for a model pruned over the region.
    scope : str, optional
        The model's guarantee in one sentence
        (:meth:`~gd_analyze.simplify.guarantee.Guarantee.statement`, as stored), said
        after the error and cost.

    Returns
    -------
    str
        What dominates D and h, every negligible element named; what the simplified model
        keeps, c included; at what open-loop torque error (tau_s - tau along the given
        trajectory), with the reason when the worst relative error sits on a joint whose own
        torque is small, and at what counted cost against the exact model, the full explicit
        model and Newton-Euler; then the scope of its guarantee, if given.

    Examples
    --------
    >>> import numpy as np
    >>> text = conclusion(["D11", "h1"], ["translational", "rotational"], np.zeros(2, bool),
    ...                   ["tran", "rot"], np.array([0.004]), np.array([0.02]),
    ...                   np.array([5.0]), cost=(348, 260, 1212))
    >>> text[text.index("; its code"):]
    "; its code costs 608 operations per set point (348 multiplications, 260 additions) against Newton-Euler's 1,212."
    """
    parts = []
    for name in ("D", "h"):
        ks = [k for k, lab in enumerate(labels) if lab.startswith(name)]
        by = {c: [labels[k] for k in ks if dominance[k] == c and not zero[k]] for c in _CLASSES}
        z = [labels[k] for k in ks if zero[k]]
        lead = max(("translational", "rotational", "both"), key=lambda c: len(by[c]))
        k_tran, k_both, k_negl = (len(by["translational"]), len(by["both"]),
                                  len(by["negligible"]) + len(z))
        text = (f"in {name}, {k_tran} of {len(ks)} elements {_are(k_tran)} dominated by "
                f"the translational part ({_names(by['translational'])}), "
                f"{len(by['rotational'])} by the rotational part ({_names(by['rotational'])}) "
                f"and {k_both} need{'s' if k_both == 1 else ''} both")
        if k_negl:
            # "≡ 0" is kept with its last element on one line (no-break spaces)
            text += (f"; {k_negl} {_are(k_negl)} negligible ("
                     + "; ".join(filter(None, [", ".join(map(_math, by["negligible"])),
                                               ", ".join(map(_math, z)) + "\u00a0\u2261\u00a00"
                                               if z else ""]))
                     + ")")
        parts.append(text + f" \u2014 {lead} effects lead" + (
            PLACEHOLDER_INERTIA if placeholder_inertia and lead != "translational" else ""))
    first = "Dominance: " + "; ".join(parts) + "."
    second = model_sentence(recursive=recursive, choice=choice, gravity=gravity,
                            trajectory=where)
    rel = np.asarray(rel_peak, float)
    said = f" Its guarantee: {scope}." if scope else ""
    if not np.any(np.isfinite(rel)):
        return first + " " + second + " Its torque error is not defined (no torque)." + said
    worst = int(np.nanargmax(rel))
    others = np.delete(rel, worst)
    unit = list(units) if units is not None else ["N m"] * rel.size
    def cell(kind, k, value, u):                   # as Table 5.1 prints it, if given
        if shown is None:
            return _qty(value, u)
        text = str(shown[kind][k])
        return text.replace(" ", "\u00a0") if kind == "rel" else _qty_text(text, u)

    noise = (np.zeros(rel.size, bool) if round_off is None
             else np.asarray(round_off, bool).reshape(rel.size))
    if noise.all():
        third = (f"Its open-loop torque error ({_TAU_S} \u2212 \u03c4 along the trajectory) "
                 f"is \u2261\u00a00 at every joint (round-off only)")
    else:
        third = (f"Its largest open-loop torque error ({_TAU_S} \u2212 \u03c4 along the "
                 f"trajectory) is {cell('rel', worst, 100 * rel[worst], '%')} of peak |\u03c4| "
                 f"at joint {worst + 1} ({cell('abs', worst, abs_peak[worst], unit[worst])} of "
                 f"{cell('tau', worst, tau_peak[worst], unit[worst])})")
    big = float(np.nanmax(tau_peak))
    if tau_peak[worst] < 0.01 * big and not noise.all():
        at = int(np.nanargmax(tau_peak))
        third += (f": that joint's own torque is under 1\u00a0% of the largest joint's "
                  f"({_qty(big, unit[at])}), so a tiny absolute error is a large share of it")
    if others.size and np.any(np.isfinite(others)) and not noise.all():
        second_worst = int(np.nanargmax(np.where(np.arange(rel.size) == worst, -np.inf,
                                                 np.nan_to_num(rel, nan=-np.inf))))
        third += ("; every other joint's is \u2261\u00a00"
                  if np.delete(noise, worst).all() else
                  f"; every other joint is within "
                  f"{cell('rel', second_worst, 100 * rel[second_worst], '%')}")
    if cost is not None:
        mult, add, ne = cost[:3]
        exact, full = (tuple(cost[3:5]) + (None, None))[:2]
        third += (f"; its code costs {mult + add:,} operations per set point ({mult:,} "
                  f"multiplications, {add:,} additions)")
        counts = [f"the {name} model's {v:,}" for name, v in (("exact", exact),
                                                               ("full explicit", full)) if v]
        if counts and ne:
            third += (f" against {', '.join(counts)} and Newton-Euler's {ne:,}" if mult + add < ne
                      else f" against {' and '.join(counts)}, more than Newton-Euler's "
                      f"{ne:,}: for speed, use Newton-Euler")
        elif ne:
            third += (f" against Newton-Euler's {ne:,}" if mult + add < ne else
                      f", more than Newton-Euler's {ne:,}: for speed, use Newton-Euler")
        elif counts:
            third += f" against {' and '.join(counts)}"
        if len(cost) > 4 and not full:
            third += " (the full explicit model was not derived, so it has no count)"
    return first + " " + second + " " + third + "." + said


def model_sentence(recursive: tuple[int, int, int] | None = None,
                   choice: Sequence[str] | None = None, gravity: str | None = None,
                   trajectory: str = "this trajectory") -> str:
    """The sentence on what the simplified model keeps, the same in every report.

    Parameters
    ----------
    recursive : tuple of (int, int, int), optional
        For a model of the recursive form: its number of base parameters, of dropped
        (parameter, part) pairs and of pairs that contribute on the trajectories it was built
        on (:meth:`gd_analyze.symbolic.recursive_model.RecursiveModel.stated_facts`).
    choice : list of str, optional
        For a model of the explicit form: the part kept of each element of D and h
        (``tran``, ``rot``, ``both``, ``none``).
    gravity : str, optional
        :func:`gravity_clause` of the model; the sentence ends with it.
    trajectory : str, optional
        The trajectories the model was built on, as the sentence names them.

    Returns
    -------
    str
        One sentence (Fu, Gonzalez & Lee 1987, Sec. 3.4.1: the parts of D and h kept).

    Examples
    --------
    >>> model_sentence(recursive=(36, 4, 40), gravity="keeps c whole (no gravity part is "
    ...                "dropped)")[-80:]
    ' on this trajectory, it drops 4, and keeps c whole (no gravity part is dropped).'
    >>> model_sentence(recursive=(36, 0, 40))[-51:]     # parts that are identically 0 do not act
    'act on this trajectory, it drops none: it is exact.'
    """
    if recursive is not None:
        b, dropped, pairs = recursive
        return (f"The simplified model is the recursive Newton-Euler model on {b} base "
                f"parameters; of the {pairs} inertial, velocity and gravity parts of their "
                f"contributions that act on {trajectory}, it drops "
                + ("none: it is exact." if dropped == 0 else f"{dropped}"
                   + (f", and {gravity}" if gravity else "") + "."))
    choice = list(choice or [])
    kept = {c: sum(1 for v in choice if v == c) for c in ("tran", "rot", "both", "none")}
    terms = kept["tran"] + kept["rot"] + 2 * kept["both"]
    return (f"The simplified model keeps only the translational part of {kept['tran']} "
            f"element{'' if kept['tran'] == 1 else 's'}, only the rotational part of "
            f"{kept['rot']}, both parts of "
            f"{kept['both']} and drops {kept['none']}: it evaluates {terms} of the "
            f"{2 * len(choice)} parts of D and h, and "
            + (f"{gravity}." if gravity else "its rule's terms of c."))


def simplified_intro(form: str, gravity: str | None = None) -> str:
    """Section 5's opening sentence: the deployed model's form and what its rule leaves out.

    Parameters
    ----------
    form : str
        ``"explicit"`` or ``"recursive"``.
    gravity : str, optional
        :func:`gravity_clause` of the model: an explicit model's sentence names c among what is
        left out only when the model drops terms of c (the chapter rule never does).

    Returns
    -------
    str

    Examples
    --------
    >>> from gd_analyze.report.markup import plain
    >>> plain(simplified_intro("explicit", gravity_clause("chapter")).split("; ")[-1])
    'it keeps c whole: τs = Ds q̈ + hs + c.'
    """
    if form == "recursive":
        return ("The simplified model is the customized recursive Newton-Euler model on the "
                "base inertial parameters, with parts of the parameters' contributions left "
                "out by the error budget (Sec. 5.3); it keeps the elements of D and h as sums "
                "over the parameters, not element by element.")
    head = ("The simplified model is the explicit G-D model (Eq. (3.4-24)) with parts of the "
            "elements of D (mirrored to the lower triangle)")
    if gravity and gravity.startswith("keeps c whole"):
        return (head + " and h left out by its rule (Sec. 5.3); it keeps c whole: "
                f"{_TAU_S} = D{_S} q\u0308 + h{_S} + c.")
    what = ", h and terms of c" if gravity else ", h and c"
    return (head + what + " left out by its rule (Sec. 5.3): "
            f"{_TAU_S} = D{_S} q\u0308 + h{_S} + c{_S}.")


def gravity_clause(rule: str, gravity_dropped: Sequence[str] | None = None,
                   c_bound: npt.NDArray[np.float64] | None = None,
                   units: Sequence[str] | None = None,
                   c_terms: tuple[int, int] | None = None) -> str | None:
    """What a simplified model does with the gravity loading c, as a clause.

    Parameters
    ----------
    rule : str
        ``"budget"`` or ``"chapter"``.
    gravity_dropped : list of str, optional
        A recursive model: the base parameters whose contributing gravity part it drops.
    c_bound : ndarray, shape (n,), optional
        An explicit model: the bound on what its dropped terms of c add to each joint's
        torque [N m or N] (not finite: no budget).
    units : list of str, optional
        Each joint's torque unit, for ``c_bound``.
    c_terms : tuple of (int, int), optional
        An explicit model without ``c_bound``: its terms of c kept and the full model's.

    Returns
    -------
    str or None
        E.g. ``"keeps c whole (no gravity part is dropped)"``; None when nothing says.

    Examples
    --------
    >>> gravity_clause("budget", gravity_dropped=["MX2", "MY3"])
    'drops the gravity part of 2 base parameters from c (MX2, MY3)'
    >>> gravity_clause("chapter", c_bound=np.full(2, np.nan))
    'keeps c whole (the chapter rule drops parts of D and h only)'
    """
    if gravity_dropped is not None:
        names = list(gravity_dropped)
        if not names:
            return "keeps c whole (no gravity part is dropped)"
        return (f"drops the gravity part of {len(names)} base parameter"
                f"{'s' if len(names) > 1 else ''} from c ({', '.join(names)})")
    if rule == "chapter":
        return "keeps c whole (the chapter rule drops parts of D and h only)"
    if c_bound is not None:
        bound = np.asarray(c_bound, float)
        if not np.all(np.isfinite(bound)):
            return None
        if not np.any(bound > 0):
            return "keeps c whole (no term of c is dropped)"
        units = list(units) if units is not None else ["N m"] * bound.size
        return ("drops terms of c, worth at most "
                + ", ".join(f"{b:.3g} {units[i]} at joint {i + 1}" for i, b in enumerate(bound)
                            if b > 0))
    if c_terms is not None:
        kept, full = c_terms
        if kept >= full:
            return "keeps c whole (no term of c is dropped)"
        return f"drops {full - kept} of the {full} terms of c"
    return None


def disagreement_cause(label: str, ours: str, theirs: str, share: float, zero: bool, s: float,
                       robot_name: str) -> str:
    """Why our class of an element differs from the chapter's.

    Parameters
    ----------
    label, ours, theirs : str
        The element, our class and the chapter's class.
    share : float
        share_tran of the element.
    zero : bool
        The element is zero in every part.
    s : float
        The dominance threshold.
    robot_name : str
        The robot: for ``puma560`` a class the chapter does not share is put down to what
        differs (its parameters and trajectory are not the chapter's, which it does not give),
        not to a cause the measurements do not support (README, "How the ranking compares
        with the chapter": the drives do not bring the classes closer).

    Returns
    -------
    str
        One line; empty if the classes agree.
    """
    if ours == theirs:
        return ""
    if zero:
        return ("\u2261 0 for this arm in every part; the chapter reads a class off its plot "
                "by eye")
    if ours == "negligible":
        return ("peak below e times its scale, so no part is ranked; the chapter has no "
                "negligible class")
    rot = 1.0 - share
    if ours == "both":
        if theirs == "translational":          # shares as fractions, as in Sec. 4
            cause = f"rotational share {_share(rot)} > 1 \u2212 s = {1 - s:g}"
        else:
            cause = f"translational share {_share(share)} > 1 \u2212 s = {1 - s:g}"
    elif ours == "translational":
        cause = f"translational share {_share(share)} \u2265 s = {s:g}"
    else:
        cause = f"translational share {_share(share)} \u2264 1 \u2212 s = {1 - s:g}"
    if label.startswith("h"):
        cause += ("; h depends on q\u0307 and the chapter's trajectory is not given, so it is "
                  "compared on another motion")
    elif robot_name.lower().replace(" ", "").replace("-", "") == "puma560":
        cause += ("; these PUMA 560 parameters (Armstrong, Khatib & Burdick) and this "
                  "trajectory are not the chapter's, which it does not give")
    elif robot_name == "puma560-drives" and label[1] == label[2] and \
            ours in ("rotational", "both") and theirs == "translational":
        cause += "; the drive's armature counts on the rotational side"
    return cause


def shared_causes(causes: Sequence[str]) -> tuple[list[str], str]:
    """Causes said once (not one cause repeated in every row of a table): each clause
    (``"; "``-separated) that more than one row gives becomes a note, marked (a), (b), ... in
    those rows.

    Parameters
    ----------
    causes : sequence of str
        One cause per row, as :func:`disagreement_cause` writes it ("" where none).

    Returns
    -------
    rows : list of str
        The causes with each shared clause replaced by its mark.
    note : str
        "(a) ... (b) ..." in order of first use, a row's shared clauses together under one
        mark; "" if no clause is shared.

    Examples
    --------
    >>> shared_causes(["x 1; no class; by eye", "no class; by eye", "y 2; other", ""])
    (['x 1 (a)', '(a)', 'y 2; other', ''], '(a) no class; by eye.')
    """
    split = [[c for c in cause.split("; ") if c] for cause in causes]
    seen: dict[str, int] = {}
    for clauses in split:
        for c in clauses:
            seen[c] = seen.get(c, 0) + 1
    marks: dict[str, str] = {}
    rows: list[str] = []
    for clauses in split:          # a row's shared clauses, together, are one note
        shared = "; ".join(c for c in clauses if seen[c] > 1)
        if shared and shared not in marks:
            marks[shared] = f"({chr(ord('a') + len(marks))})"
        own = "; ".join(c for c in clauses if seen[c] == 1)
        rows.append(" ".join(t for t in (own, marks.get(shared, "")) if t))
    return rows, " ".join(f"{m} {c}." for c, m in marks.items())


def captions(enveloped: bool, N: int, s: str, e: str, units: Mapping[str, str] | None = None,
             alike: Sequence[Sequence[int]] = ()) -> dict[str, str]:
    """Captions of the main report's figures, the same in the HTML and the PDF.

    Parameters
    ----------
    enveloped : bool
        The series are drawn as min/max envelopes (long trajectories).
    N : int
        Set points.
    s, e : str
        Thresholds, as printed.
    units : dict of str to str, optional
        The units as the captions state them, from the joint types: ``joints`` (q, qd, qdd
        per joint type), ``D`` and ``tau``; an all-revolute arm's if not given.
    alike : sequence of sequence of int, optional
        Groups of joints (1-based) that move alike, whose curves in Fig. 1 coincide
        (:func:`gd_analyze.report.main_context.alike_joints`): named in its caption.

    Returns
    -------
    dict of str to str
        By figure key. ``torque`` is the caption of
        :func:`gd_analyze.report.main_figures.fig_torque` (τ and tau_s), the figure of a results
        file without the simplified-model variables; for one with them the report draws
        tau_s − τ and its bound and takes that figure's caption
        (:func:`gd_analyze.report.simplified_section.simplified_caption`), as
        :func:`gd_analyze.report.main_context.report_context` does.
    """

    if enveloped:
        how = (f"The {N:,} set points are drawn as their min/max envelope over "
               f"{ENVELOPE_COLUMNS:,} equal time columns, without markers; lines: translational solid, rotational dashed, "
               "combined dotted")
    else:
        k = element_markevery(N, 3)
        where = (f"Markers at each of the {N:,} set points" if k == 1 else
                 f"Lines through all {N:,} set points, a marker at one set point in {k} "
                 f"(at most {-(-N // k)} per line, staggered)")
        how = (f"{where}: translational \u25cb (solid line), rotational \u00d7 (dashed), "
               "combined \u25b3 (dotted, thin, drawn first)")
    u = {"joints": "deg, deg/s, deg/s\u00b2", "D": "kg m\u00b2", "tau": "N m", **(units or {})}
    # what Fig. 1 draws (main_figures.joints_figure): markers only when not enveloped
    joint_lines = ("each joint in its own colour and line style, without markers: the min/max "
                   f"envelope of its {N:,} set points over {ENVELOPE_COLUMNS:,} equal time columns"
                   if enveloped else "each joint in its own colour, line style and marker")
    return {
        "joints": "Joint positions q, velocities q\u0307 and accelerations q\u0308 against time "
                  f"[{u['joints']}], {joint_lines}; the dataset stores SI units (rad or m)."
                  + alike_sentence(alike),
        "D": f"Elements {element('D', 'ij')} (i \u2264 j) of the inertia matrix against time "
             f"[{u['D']}], "
             f"split into their translational and rotational parts (analogue of Fig. 3.10). "
             f"{how}. Panel title: element, written D(i,j) for {element('D', 'ij')}, and its "
             f"class (s = {s}, e = {e}), in the class's "
             "colour (key below the panels); an element that is zero in every part (\u2261 0), "
             "whose share is not defined, has no panel: the note below names it.",
        "h": f"Coriolis and centrifugal elements {element('h', 'i')} against time "
             f"[{u['tau']}] (analogue of "
             "Fig. 3.11), "
             f"on panels of the size of those of D, titled h(i). {how}.",
        "torque": "Joint torques of the full model \u03c4 (black, solid) and the simplified "
                  f"model {_TAU_S} (green, dashed) against time [{u['tau']}] (joint i's axis: "
                  "\u03c4(i)); the title gives the "
                  "peak error in % of the joint's peak |\u03c4|.",
        "payload": "Translational share and class of each element against the load mass "
                   "(top), and peak joint torques (bottom).",
        "formulations": "Multiplications and additions per set point against the number of "
                        "joints n (logarithmic vertical axis): counted on the code as implemented (solid) and "
                        "the formulas of Table 3.5 (dashed).",
    }


def alike_sentence(groups: Sequence[Sequence[int]]) -> str:
    """The sentence of Fig. 1's caption naming the joints whose curves coincide.

    Parameters
    ----------
    groups : sequence of sequence of int
        Groups of joints (1-based) that move alike.

    Returns
    -------
    str
        Empty without a group; else, with a leading space, one sentence per group.

    Examples
    --------
    >>> alike_sentence([[1, 5]])
    ' Joints 1 and 5 move alike: their curves coincide.'
    >>> alike_sentence([[1, 3, 6]])
    ' Joints 1, 3 and 6 move alike: their curves coincide.'
    """
    out = ""
    for group in groups:
        names = [str(j) for j in group]
        out += (f" Joints {', '.join(names[:-1])} and {names[-1]} move alike: their curves "
                "coincide.")
    return out


def prismatic_count_note(types: str) -> str:
    """The sentence saying that the operation counts are this arm's, not Table 3.5's.

    Parameters
    ----------
    types : str
        Joint types, "R" revolute and "P" prismatic, base first
        (:func:`gd_analyze.dynamics.opcount.joint_types`).

    Returns
    -------
    str
        Empty for an all-revolute arm (Table 3.5's case); else one sentence, with a leading
        space, naming the prismatic joints.

    Examples
    --------
    >>> prismatic_count_note("RRRRRR")
    ''
    >>> prismatic_count_note("RRPRRR")[:40]
    " The counts are this arm's: joint 3 is p"
    """
    pris = [str(i + 1) for i, t in enumerate(types) if t == "P"]
    if not pris:
        return ""
    which = (f"joint {pris[0]} is" if len(pris) == 1
             else f"joints {', '.join(pris[:-1])} and {pris[-1]} are")
    return (f" The counts are this arm's: {which} prismatic, while Table 3.5 assumes n "
            "revolute joints (a prismatic joint has a constant rotation and no joint rate in "
            "its angular velocity, so its N-E step is cheaper).")
