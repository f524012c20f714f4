"""The sentences of the main report: its three-sentence conclusion, the cause of each
disagreement with the chapter, and the figure captions (the same in the HTML and the PDF).

Every sentence is built from the stored ranking and torque errors; nothing is recomputed.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .common import say
from .figure_style import element_markevery
from .main_figures import ENVELOPE_COLUMNS
from .markup import marked
from .numbers import share as _share

if TYPE_CHECKING:
    import numpy.typing as npt

__all__ = ["conclusion", "model_sentence", "StoredModel", "gravity_clause", "weightless", "disagreement_cause", "shared_causes", "captions",
           "prismatic_count_note"]

_CLASSES = ("translational", "rotational", "both", "negligible")


def _names(labels):
    if not labels:
        return "none"
    if len(labels) <= 6:
        return ", ".join(map(marked, labels))
    return ", ".join(map(marked, labels[:5])) + f" and {len(labels) - 5} more"


def _qty(value, unit):
    """A number and its unit joined by no-break spaces ("4.9\u00a0N\u00a0m"): a line never
    ends between them (the Stanford summary broke "4.9 N" / "m")."""
    return f"{value:.3g}\u00a0" + str(unit).replace(" ", "\u00a0")


def conclusion(labels: Sequence[str], dominance: Sequence[str], zero: npt.NDArray[np.bool_],
               choice: Sequence[str], rel_peak: npt.NDArray[np.float64],
               abs_peak: npt.NDArray[np.float64], tau_peak: npt.NDArray[np.float64],
               cost: tuple[int, int, int | None] | tuple[int, int, int | None, int | None, int | None] | None = None,
               model: StoredModel | None = None, units: Sequence[str] | None = None,
               scope: str | None = None, shown: Mapping[str, Sequence[str]] | None = None,
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
        rotational effects lead, the sentence says so (the placeholder note of ``templates/wording.j2``).
    shown : dict of str to list of str, optional
        Those numbers as the error table prints them (``rel``, ``abs``, ``tau``), quoted so
        that the text and the table agree digit for digit; else 3 digits.
    cost : tuple of (int, int, int or None[, int or None, int or None]), optional
        The emitted model's multiplications and additions per set point, Newton-Euler's
        operations as implemented (None if not counted), and optionally the operations of the
        exact (nothing dropped) model and of the full explicit model, which the sentence then
        names beside Newton-Euler's.
    model : StoredModel, optional
        What the simplified model keeps (its form's counts or ``choice``, what it does with
        the gravity loading c, where its pairs were judged, whether it was built without
        gravity), said by :meth:`StoredModel.sentence`; if not given, the explicit model of
        ``choice``, nothing said of c.
    units : list of str, optional
        Units of each joint's torque (N m, or N for a prismatic joint); N m if not given.
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
    groups = []
    for name in ("D", "h"):
        ks = [k for k, lab in enumerate(labels) if lab.startswith(name)]
        by = {c: [labels[k] for k in ks if dominance[k] == c and not zero[k]] for c in _CLASSES}
        z = [labels[k] for k in ks if zero[k]]
        most = max(len(by[c]) for c in ("translational", "rotational", "both"))
        # "≡ 0" is kept with its last element on one line (no-break spaces)
        negl = [", ".join(map(marked, by["negligible"])),
                ", ".join(map(marked, z)) + "\u00a0\u2261\u00a00" if z else ""]
        groups.append({"name": name, "m": len(ks), "k_tran": len(by["translational"]),
                       "tran": _names(by["translational"]), "k_rot": len(by["rotational"]),
                       "rot": _names(by["rotational"]), "k_both": len(by["both"]),
                       "k_negl": len(by["negligible"]) + len(z),
                       "negl": "; ".join(filter(None, negl)),
                       # the classes of most ranked elements: one if it leads, all that tie,
                       # none if no element is ranked (every one negligible or \u2261 0)
                       "lead": [c for c in ("translational", "rotational", "both")
                                if len(by[c]) == most] if most else [],
                       "k_most": most})
    first = say("dominance", groups=groups, placeholder_inertia=placeholder_inertia)
    second = (model or StoredModel(None, tuple(choice), None, "this trajectory", False)
              ).sentence()
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
        return text.replace(" ", "\u00a0") if kind == "rel" else f"{text}\u00a0" + str(u).replace(" ", "\u00a0")

    noise = (np.zeros(rel.size, bool) if round_off is None
             else np.asarray(round_off, bool).reshape(rel.size))
    alike = [k for k in range(rel.size) if unit[k] == unit[worst]]     # N m with N m, N with N
    big_at = alike[int(np.nanargmax(np.asarray(tau_peak, float)[alike]))]
    big = float(tau_peak[big_at])
    within = None
    if others.size and np.any(np.isfinite(others)):
        second_worst = int(np.nanargmax(np.where(np.arange(rel.size) == worst, -np.inf,
                                                 np.nan_to_num(rel, nan=-np.inf))))
        within = cell('rel', second_worst, 100 * rel[second_worst], '%')
    third = say("torque_error", round_off=noise.all(), joint=worst + 1,
                rel=cell('rel', worst, 100 * rel[worst], '%'),
                abs=cell('abs', worst, abs_peak[worst], unit[worst]),
                peak=cell('tau', worst, tau_peak[worst], unit[worst]),
                small=_qty(big, unit[big_at]) if tau_peak[worst] < 0.01 * big else None,
                others_zero=within is not None and np.delete(noise, worst).all(),
                within=within)
    if cost is not None:
        mult, add, ne = cost[:3]
        exact, full = (tuple(cost[3:5]) + (None, None))[:2]
        third += say("code_cost", mult=mult, add=add, ne=ne,
                     models=[(name, v) for name, v in (("exact", exact), ("full explicit", full))
                             if v], underived=len(cost) > 4 and not full)
    return first + " " + second + " " + third + "." + said


def model_sentence(recursive: tuple[int, int, int] | None = None,
                   choice: Sequence[str] | None = None, gravity: str | None = None,
                   trajectory: str = "this trajectory", weightless: bool = False) -> str:
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
    weightless : bool, optional
        The model was built without gravity (:func:`weightless`): c is identically 0, so the
        sentence names no gravity part and says once that there is no gravity.

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
    >>> text = model_sentence(recursive=(36, 4, 30), gravity="keeps c whole", weightless=True)
    >>> text[80:117]
    'of the 30 inertial and velocity parts'
    >>> text[-66:]
    'it drops 4. The model was built without gravity (g = 0), so c \u2261 0.'
    """
    if recursive is not None:
        b, dropped, pairs = recursive
        return say("recursive_model", b=b, dropped=dropped, pairs=pairs, gravity=gravity,
                   trajectory=trajectory, weightless=weightless)
    choice = list(choice or [])
    kept = {c: sum(1 for v in choice if v == c) for c in ("tran", "rot", "both", "none")}
    return say("explicit_model", kept=kept, parts=2 * len(choice), gravity=gravity,
               weightless=weightless)


@dataclass(frozen=True)
class StoredModel:
    """What a simplified model keeps, as the facts stored with it state it
    (:func:`gd_analyze.jobs.control.model_facts`: a control run's ``model_<fact>`` attributes,
    a sweep's ``merged_<fact>``; the main report's from its results), and where it was built:
    the one value from which every report says it (:meth:`sentence`).

    Attributes
    ----------
    recursive : tuple of (int, int, int) or None
        A model of the recursive form: its base parameters, dropped (parameter, part) pairs and
        pairs that act; None for the explicit form.
    choice : tuple of str
        The explicit form: the part kept of each element of D and h.
    gravity : str or None
        :func:`gravity_clause` of the model: for the recursive form from the base parameters
        whose gravity part it drops, for the explicit form from its terms of c kept and the
        full model's (None where the budget rule's are not counted).
    where : str
        Where the recursive form's pairs were judged, as the sentence names it.
    weightless : bool
        The model was built without gravity (:func:`weightless`).
    """

    recursive: tuple[int, int, int] | None
    choice: tuple[str, ...]
    gravity: str | None
    where: str
    weightless: bool

    @classmethod
    def of(cls, facts: Any, choice: Sequence[str], where: str, weightless: bool
           ) -> StoredModel:
        """The value of a model's stored facts.

        Parameters
        ----------
        facts : ModelFacts or MergedModel
            The facts as stored (:class:`gd_analyze.store.stored_control.ModelFacts`,
            :class:`gd_analyze.store.sweep_view.MergedModel`): ``rule``, ``form``,
            ``base_parameters``, ``pairs_dropped``, ``pairs``, ``gravity_dropped``
            (comma-separated), ``c_terms_kept`` and ``c_terms`` (-1 where not counted).
        choice : sequence of str
            The part kept of each element of D and h.
        where, weightless : str, bool
            As the attributes.

        Returns
        -------
        StoredModel
        """
        if str(facts.form) == "recursive":
            return cls((int(facts.base_parameters), int(facts.pairs_dropped), int(facts.pairs)),
                       tuple(choice), gravity_clause(str(facts.rule), gravity_dropped=[
                           x.strip() for x in str(facts.gravity_dropped).split(",") if x.strip()]),
                       where, weightless)
        c_terms = (int(facts.c_terms_kept), int(facts.c_terms))
        return cls(None, tuple(choice), gravity_clause(
            str(facts.rule), c_terms=c_terms if min(c_terms) >= 0 else None), where, weightless)

    def sentence(self, subject: str = "The simplified model") -> str:
        """:func:`model_sentence` of the model, its subject ``subject``.

        Parameters
        ----------
        subject : str, optional
            How the sentence names the model (``"The merged model"``).

        Returns
        -------
        str
        """
        return model_sentence(recursive=self.recursive, choice=self.choice, gravity=self.gravity,
                              trajectory=self.where, weightless=self.weightless
                              ).replace("The simplified model", subject, 1)


def weightless(gravity: npt.ArrayLike | None) -> bool:
    """Whether the arm a model was built for has no gravity, so that its gravity loading c is
    identically 0 (Eq. (3.4-24): c is linear in g), read from the gravity vector stored with
    the model's run.

    Parameters
    ----------
    gravity : array_like, shape (3,), or None
        Gravity in the arm's base frame [m/s^2], as stored (the results' and the sweep's
        ``gravity``, the control run's ``model_gravity``); None where not stored.

    Returns
    -------
    bool
        True when every component is 0; False where it is not stored.

    Examples
    --------
    >>> weightless([0.0, 0.0, 0.0]), weightless([9.81, 0.0, 0.0]), weightless(None)
    (True, False, False)
    """
    return gravity is not None and not np.any(np.asarray(gravity, float))


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
    bound = None
    if c_bound is not None and gravity_dropped is None and rule != "chapter":
        b = np.asarray(c_bound, float)
        if not np.all(np.isfinite(b)):
            return None
        units = list(units) if units is not None else ["N m"] * b.size
        bound = [f"{v:.3g} {units[i]} at joint {i + 1}" for i, v in enumerate(b) if v > 0]
    return say("gravity_clause", rule=rule, bound=bound, c_terms=c_terms,
               dropped=None if gravity_dropped is None else list(gravity_dropped)) or None


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
    why = ""
    if label.startswith("h"):
        why = "h"
    elif robot_name.lower().replace(" ", "").replace("-", "") == "puma560":
        why = "puma560"
    elif robot_name == "puma560-drives" and label[1] == label[2] and \
            ours in ("rotational", "both") and theirs == "translational":
        why = "drives"
    return say("disagreement_cause", ours=ours, theirs=theirs, zero=zero, tran=_share(share),
               rot=_share(1.0 - share), s=f"{s:g}", rest=f"{1 - s:g}", why=why)


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
    seen = Counter(c for clauses in split for c in clauses)
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

    k = element_markevery(N, 3)
    u = {"joints": "deg, deg/s, deg/s\u00b2", "D": "kg m\u00b2", "tau": "N m", **(units or {})}
    return {key: say("main_caption", key=key, enveloped=enveloped, N=N, k=k, most=-(-N // k),
                     columns=ENVELOPE_COLUMNS, s=s, e=e, u=u, alike=alike)
            for key in ("joints", "D", "h", "torque", "payload", "formulations")}


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
    return say("prismatic_count_note", joints=[i + 1 for i, t in enumerate(types) if t == "P"])
