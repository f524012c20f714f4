"""Significance by torque contribution: the error budget of the simplified model.

Each part p in {tran, rot} of each element contributes to the joint torques along a
trajectory: D_ij^p qdd_j to tau_i and, for i != j, D_ij^p qdd_i to tau_j; h_i^p to tau_i.
Joint i's scale is its peak |tau_i| along the trajectory, raised to a torque floor TAU [N m].
With the budget rule, parts are dropped in order of increasing peak contribution while, for
every joint, the sum of the dropped parts' peak contributions stays within EPS x scale_i: these
are the element choices. The explicit model is pruned the same way at a finer grain, term by
term (:func:`gd_analyze.symbolic.explicit.prune`, atoms of proportional groups), within the same
EPS x scale_i. By the triangle inequality either model's error on the trajectory is within
EPS x scale_i for every joint.

Over several trajectories (a sweep) each joint's scale is that trajectory's: scale_{t,i} =
max(peak_t |tau_i|, TAU). Every peak is divided by its own trajectory's scale
(:func:`relative_peaks`) and the largest ratio over the trajectories is kept; the budget EPS
then applies to these ratios (scale 1). For every trajectory t and joint i the dropped
contributions sum to at most sum_a p_{a,t,i} <= scale_{t,i} sum_a max_u (p_{a,u,i} /
scale_{u,i}) <= EPS x scale_{t,i}: the model is guaranteed on each trajectory, relative to that
trajectory's own scale, with memory independent of the number of trajectories.

The drives' terms of an arm (:mod:`gd_analyze.model.drives`: the armature part D_arm of D and
the friction torque tau_f) are not parts of this index: the simplified model never drops them
(:func:`gd_analyze.symbolic.drive_regressor.with_drives`, at most 3 multiplications and 3 additions per
joint), so they add nothing to the error and the budget applies to the links' parts alone;
each joint's scale, peak |tau_i|, includes them.

The chapter's rule (``"chapter"``) keeps the share-based classes of
:mod:`gd_analyze.ranking.ranking` and prunes no single term: there is no bound.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..config import defaults
from ..ranking.labels import element_label
from ..symbolic.explicit import Term, atoms, budget_drop, prune

__all__ = ["RULES", "DEFAULT_TOLERANCE", "PartPeaks", "part_index", "budget_choices",
           "Selection", "select_terms", "relative_peaks", "chosen_terms", "chapter_terms"]

#: The rules that build a simplified model.
RULES = ("budget", "chapter")
#: Default EPS of --tolerance.
DEFAULT_TOLERANCE = defaults["tolerance"]
#: Rows per block of the array code of :meth:`PartPeaks.update`.
_BLOCK = 8192


def part_index(n):
    """The parts, in order: (label, part, kind, i, j) for every element and part.

    Parameters
    ----------
    n : int
        Number of joints.

    Returns
    -------
    list of tuple
        ``("D12", "tran", "D", 0, 1)`` ...; D elements row by row (i <= j), then h, each with
        ``"tran"`` then ``"rot"``.
    """
    out = []
    for i in range(n):
        for j in range(i, n):
            out += [(element_label("D", i, j), p, "D", i, j) for p in ("tran", "rot")]
    for i in range(n):
        out += [(element_label("h", i), p, "h", i, -1) for p in ("tran", "rot")]
    return out


def chapter_terms(terms: Term, choices: dict) -> Term:
    """The chapter's simplified model in explicit form: the terms of the parts its share-based
    classes keep, merged, nothing pruned.

    Parameters
    ----------
    terms : Term
        The full explicit model's terms (:func:`gd_analyze.symbolic.explicit.model_terms`).
    choices : dict
        Element label -> ``"tran"``, ``"rot"``, ``"both"`` or ``"none"`` (:func:`chosen_terms`).

    Returns
    -------
    Term
        :func:`gd_analyze.symbolic.explicit.prune` of the chosen terms with nothing to drop:
        the kept terms of ``rule="chapter"``, as ``simplified_model.json`` stores them.
    """
    return prune(terms.subset(chosen_terms(terms, choices)), np.zeros((0, terms.K.shape[1])),
                 None)[0]


def chosen_terms(terms, choices):
    """Which terms whole-part choices keep: the parts of D and h they name, and all of c.

    Parameters
    ----------
    terms : Term
        Explicit terms (:func:`gd_analyze.symbolic.explicit.model_terms`), M of them.
    choices : dict
        Element label (:func:`gd_analyze.ranking.labels.element_label`) -> ``"tran"``, ``"rot"``,
        ``"both"`` or ``"none"``.

    Returns
    -------
    ndarray of bool, shape (M,)

    Raises
    ------
    KeyError
        If a term's element has no choice.
    """
    keep = {"tran": ("tran", "both"), "rot": ("rot", "both")}
    return np.array([kd == "c" or choices[element_label(kd, i, j)] in keep[pt]
                     for kd, pt, i, j in zip(terms.kind, terms.part, terms.i, terms.j)], bool)


class PartPeaks:
    """Peak contribution of every part to every joint torque, and the peak |tau|, by chunks.

    Parameters
    ----------
    n : int
        Number of joints.

    Attributes
    ----------
    peaks : ndarray, shape (P, n)
        Peak |contribution| [N m] of the parts of :func:`part_index` to each joint torque.
    tau_peak : ndarray, shape (n,)
        Peak |tau_i| [N m].
    """

    def __init__(self, n):
        self.n = int(n)
        self.index = part_index(n)
        self.peaks = np.zeros((len(self.index), n))
        self.tau_peak = np.zeros(n)
        # the index as the kernel takes it: rotational part, i, and j (-1 for h_i)
        self._rot = np.array([p == "rot" for _, p, _, _, _ in self.index], bool)
        self._i = np.array([i for _, _, _, i, _ in self.index], np.int64)
        self._j = np.array([j if kind == "D" else -1 for _, _, kind, _, j in self.index],
                           np.int64)

    def update(self, D_tran, D_rot, h_tran, h_rot, qdd, tau):
        """Add a chunk of set points.

        Parameters
        ----------
        D_tran, D_rot : ndarray, shape (N, n, n)
            [kg m^2].
        h_tran, h_rot : ndarray, shape (N, n)
            [N m].
        qdd : ndarray, shape (N, n)
            [rad/s^2].
        tau : ndarray, shape (N, n)
            Full-model torques [N m].

        Notes
        -----
        One compiled pass over the chunk
        (:func:`gd_analyze.ranking.kernels.part_peaks_kernel`). A NaN chunk peak is
        never kept; a NaN |tau_i| is.
        """
        from ..ranking.kernels import part_peaks_kernel  # numba: imported by the first chunk only

        qdd = np.asarray(qdd, float)

        if qdd.shape[0] == 0:
            return
        # one compiled pass over the chunk: per part its chunk peak, kept where it exceeds
        # the running one (a NaN chunk peak is not), and the running peak |tau|
        c = np.ascontiguousarray
        part_peaks_kernel(c(D_tran, dtype=float), c(D_rot, dtype=float),
                          c(h_tran, dtype=float), c(h_rot, dtype=float), c(qdd),
                          c(tau, dtype=float), self._rot, self._i, self._j, self.peaks,
                          self.tau_peak)

    def merge(self, other):
        """Combine with the peaks of other set points (another chunk or trajectory).

        Parameters
        ----------
        other : PartPeaks
            Peaks of the same robot elsewhere.

        Returns
        -------
        PartPeaks
            self, updated in place.
        """
        np.maximum(self.peaks, other.peaks, out=self.peaks)
        np.maximum(self.tau_peak, other.tau_peak, out=self.tau_peak)
        return self


def relative_peaks(peaks, scale):
    """Peak contributions relative to the joint scales of the trajectory they were taken on.

    Parameters
    ----------
    peaks : ndarray, shape (U, n)
        Peak |contribution| of each part or atom to each joint torque on one trajectory [N m].
    scale : ndarray, shape (n,)
        That trajectory's scale_i = max(peak |tau_i|, TAU) [N m].

    Returns
    -------
    ndarray, shape (U, n)
        peaks / scale; 0 where the peak is 0, inf where the peak is positive and the scale 0
        (such a unit can never be dropped). The maximum of these over trajectories, under the
        budget EPS with scale 1, keeps every trajectory's error within EPS x its own scale_i
        (module docstring).

    Examples
    --------
    >>> relative_peaks(np.array([[1.0, 0.0], [2.0, 3.0]]), np.array([4.0, 0.0])).tolist()
    [[0.25, 0.0], [0.5, inf]]
    """
    peaks = np.asarray(peaks, float)
    scale = np.asarray(scale, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(peaks > 0, peaks / np.where(scale > 0, scale, 0.0), 0.0)
    return np.where(np.isnan(rel), np.inf, rel)


def budget_choices(peaks, scale, tolerance):
    """Element choices of the budget rule: drop whole parts within EPS x scale_i.

    Parameters
    ----------
    peaks : ndarray, shape (P, n)
        :attr:`PartPeaks.peaks` [N m].
    scale : ndarray, shape (n,)
        scale_i = max(peak |tau_i|, TAU) [N m].
    tolerance : float
        EPS >= 0.

    Returns
    -------
    choices : dict
        Element label -> ``"tran"``, ``"rot"``, ``"both"`` or ``"none"``.
    used : ndarray, shape (n,)
        The budget the dropped parts use [N m].

    Raises
    ------
    ValueError
        If EPS is negative or not finite.
    """
    if not (np.isfinite(tolerance) and tolerance >= 0):
        raise ValueError(f"the tolerance must be a finite number >= 0, got {tolerance}")
    n = len(scale)
    index = part_index(n)
    drop, used = budget_drop(peaks, tolerance * np.asarray(scale, float))
    kept = {}
    for (label, p, *_), d in zip(index, drop):
        kept.setdefault(label, set())
        if not d:
            kept[label].add(p)
    code = {frozenset(): "none", frozenset({"tran"}): "tran", frozenset({"rot"}): "rot",
            frozenset({"tran", "rot"}): "both"}
    return {label: code[frozenset(s)] for label, s in kept.items()}, used


@dataclass(frozen=True, eq=False)
class Selection:
    """The simplified explicit model chosen by a rule.

    Attributes
    ----------
    rule : str
        ``"budget"`` or ``"chapter"``.
    tolerance : float
        EPS.
    choices : dict
        Element label -> kept parts: for the budget rule the whole-part selection of
        :func:`budget_choices` (the element-level model, also within EPS), for the chapter rule
        the share-based classes.
    kept : Term
        The explicit model's kept terms (tran and rot merged).
    scale : ndarray, shape (n,)
        scale_i [N m].
    bound : ndarray, shape (n,)
        Guaranteed bound on |tau_s - tau| of the explicit model per joint on the trajectories
        the peaks came from [N m] (NaN for the chapter rule, which has none).
    bound_by_kind : dict
        ``"D"``, ``"h"``, ``"c"`` -> ndarray (n,): the bound split by what the dropped atoms
        belong to (inertia, Coriolis and centrifugal, gravity) [N m].
    element_bound : ndarray, shape (n,)
        The bound of the element-level model of ``choices`` (sum of the dropped parts' peaks)
        [N m]; NaN for the chapter rule.
    """

    rule: str
    tolerance: float
    choices: dict
    kept: object
    scale: np.ndarray
    bound: np.ndarray
    bound_by_kind: dict
    element_bound: np.ndarray


def select_terms(terms, term_peaks, part_peaks, tau_peak, tolerance=DEFAULT_TOLERANCE,
                 rule="budget", torque_floor=0.0, chapter_choices=None):
    """Choose the parts and terms of the simplified explicit model.

    Parameters
    ----------
    terms : Term
        All terms of the explicit model (:func:`gd_analyze.symbolic.explicit.model_terms`).
    term_peaks : ndarray, shape (A, n)
        Peak contributions of their atoms (:func:`gd_analyze.symbolic.explicit.term_peaks`) [N m].
    part_peaks : ndarray, shape (P, n)
        Peak contributions of the parts (:class:`PartPeaks`) [N m].
    tau_peak : ndarray, shape (n,)
        Peak |tau_i| [N m].
    tolerance : float, optional
        EPS >= 0.
    rule : {"budget", "chapter"}, optional
    torque_floor : float, optional
        TAU >= 0 [N m]: scale_i = max(peak |tau_i|, TAU).
    chapter_choices : dict, optional
        The share-based choices (:meth:`gd_analyze.ranking.ranking.Ranking.choices`); required
        for ``rule="chapter"``.

    Returns
    -------
    Selection

    Raises
    ------
    ValueError
        On an unknown rule, a negative tolerance or floor, or missing chapter choices.

    Notes
    -----
    Budget rule: the atoms of the full explicit model are pruned within EPS x scale_i
    (:func:`gd_analyze.symbolic.explicit.prune`); the whole-part choices are computed beside it.
    Chapter rule: the terms of the parts the share-based classes keep, nothing pruned.
    """
    if rule not in RULES:
        raise ValueError(f"rule must be one of {RULES}, got {rule!r}")
    if not (np.isfinite(torque_floor) and torque_floor >= 0):
        raise ValueError(f"the torque floor must be a finite number >= 0, got {torque_floor}")
    scale = np.maximum(np.asarray(tau_peak, float), float(torque_floor))
    n = scale.size
    nan = np.full(n, np.nan)
    if rule == "chapter":
        if chapter_choices is None:
            raise ValueError("the chapter rule needs the ranking's choices")
        return Selection(rule=rule, tolerance=float(tolerance), choices=dict(chapter_choices),
                         kept=chapter_terms(terms, chapter_choices), scale=scale, bound=nan,
                         bound_by_kind={k: nan for k in "Dhc"}, element_bound=nan)
    choices, element_used = budget_choices(part_peaks, scale, tolerance)
    kept, used, dropped = prune(terms, term_peaks, tolerance * scale)
    merged, atom = atoms(terms)
    by_kind = {}
    for kind in "Dhc":
        ids = np.unique(atom[(merged.kind == kind)])
        ids = ids[dropped[ids]]
        by_kind[kind] = term_peaks[ids].sum(axis=0) if ids.size else np.zeros(n)
    return Selection(rule=rule, tolerance=float(tolerance), choices=choices, kept=kept,
                     scale=scale, bound=used, bound_by_kind=by_kind, element_bound=element_used)
