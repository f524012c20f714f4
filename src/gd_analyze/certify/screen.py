"""Whether a region model can save operations at all, judged from the region's samples.

Decided before any bound is proved; once more after, on the set the search finds under the
proved bounds (:func:`proved_screen`).

The region model (:func:`gd_analyze.simplify.deploy.region_model`) drops a set S of (base
parameter, part) pairs only if, on every final box L of the certification's branch and bound,
sum over S of the pairs' enclosures on L <= EPS s_i (:func:`.certify.certify`,
:func:`gd_analyze.symbolic.pruning.prune_bounds`). Each enclosure on L is at least the
pair's largest |contribution| at any position of L over the velocity and acceleration limits
(:func:`.certify.pair_magnitudes_at`), and the boxes cover every sampled position, so every
set the proof can drop also satisfies

    sum over S of m_p(x) <= EPS s_i    at every sampled position x and joint i,

with s_i the scale the certification itself uses (the same samples and local maximisation,
:func:`.region.region_samples`). The pruning's own cost search run under this weaker
constraint (the sampled magnitudes in place of the enclosures, as its pieces) may drop more
pairs than any proof can; the operations it saves against the exact recursive model, on the
pruning's quick count, estimate from above what a region model could save. Where that is
below :data:`MIN_SAVING` of the exact count, the region's certification and search buy
nothing worth their time: the exact recursive model (error 0 at every state), less the pairs
proved identically zero symbolically, is deployed instead. The estimate is a sampled one (the search is greedy and the counts are the quick
ones, :func:`gd_analyze.symbolic.recursive.parts_count`); it decides only whether to
search, never a bound.

Where the region is certified and searched, the search's own set, found under the proved
bounds, is screened again before any of its programs is built (:func:`proved_screen`): where
its quick count saves less than :data:`MIN_SAVING` of the exact count, the pruned model's
programs (each a search over the links' forms) are not built and the same exact model is
deployed. Where that set drops inertial parts, it is screened as the model would be built:
with the inertial parts restored that the model's proof of D_s positive definite needs
(:func:`gd_analyze.certify.positive_definite.inertia_restored`, the trials
:func:`~gd_analyze.certify.positive_definite.with_inertia_check` makes; on a random 15-joint
arm the quick counts of the searched set saved 3.3 %, the model built after its restore of
10 parameters 0.85 %). Both screens choose only between two sound models.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..symbolic.pruning import part_values, prune_bounds
from ..symbolic.recursive import parts_count
from .certify import pair_magnitudes_at

if TYPE_CHECKING:
    from ..dynamics.base_parameters import BaseParameters
    from ..model.robot import Robot
    from .region import Region

__all__ = ["MIN_SAVING", "ROUND_OFF", "RegionScreen", "screen_region", "proved_screen"]

#: Least share of the exact recursive model's operations (quick count) that the sampled
#: pre-screen must find a region model could save for the region to be certified and
#: searched: below it the exact recursive model is deployed (a region model of the PUMA 560
#: saves 4 %, 308 of 320 operations; random chains of 10 to 12 joints 1 to 1.5 %).
MIN_SAVING = 0.02
#: Sampled magnitudes at most this share of s_i count as zero in the pre-screen (a pair that
#: is identically zero samples as round-off; counting it free only loosens the screen).
ROUND_OFF = 1e-12


@dataclass(frozen=True, eq=False)
class RegionScreen:
    """The sampled pre-screen of a region model.

    Attributes
    ----------
    tolerance : float
        EPS [1].
    threshold : float
        The least share of the exact count a region model must be able to save
        (:data:`MIN_SAVING`) [1].
    exact_operations : int
        Multiplications + additions of the exact recursive model (quick count).
    best_operations : int
        The same with the pairs of ``dropped`` left out.
    dropped : ndarray of bool, shape (b, 3)
        The pairs the search under the sampled constraint drops. The search ends at the first
        set that saves the threshold (``stop_at`` of
        :func:`gd_analyze.symbolic.pruning.prune_bounds`): where it searched on, the
        saving is the largest it found; where it stopped, only at least the threshold.
    scale : ndarray, shape (n,)
        s_i, as the certification would use it (largest |tau_i| found over the region, at
        least the torque floor) [N m or N].
    scale_state : ndarray, shape (n, 3 n)
        Where |tau_i| = s_i was found: (q, qd, qdd).
    relative_peak : ndarray, shape (b, 3)
        Per pair, its largest sampled |contribution| relative to s_i, max over the joints
        (a lower bound of the true one) [1].
    seconds : float
        Wall time of the screen, the samples not included (of a proved screen: its counts,
        the certification and the search not included) [s].
    proved : bool
        The pairs were found by the pruning's search under the bounds proved over the region
        (:func:`proved_screen`: the region was certified and searched, ``best_operations``
        is that set's quick count, and ``skip`` means its programs were not built), not
        under the sampled constraint (:func:`screen_region`).
    restored : int
        Of a proved screen: the parameters whose inertial part the search dropped and
        ``dropped`` keeps, restored for the proof of D_s (0: none).
    """

    tolerance: float
    threshold: float
    exact_operations: int
    best_operations: int
    dropped: np.ndarray
    scale: np.ndarray
    scale_state: np.ndarray
    relative_peak: np.ndarray
    seconds: float
    proved: bool = False
    restored: int = 0

    @property
    def saving(self) -> float:
        """float: the estimated largest saving, a share of the exact count [1] (where the
        screen chose to search, a saving found of at least the threshold)."""
        return (self.exact_operations - self.best_operations) / max(self.exact_operations, 1)

    @property
    def skip(self) -> bool:
        """bool: a region model cannot save :data:`threshold` of the operations: no search
        (of a proved screen: the searched model's programs are not built)."""
        return bool(self.saving < self.threshold)

    def text(self) -> str:
        """One sentence with the numbers, as the outputs print it.

        Returns
        -------
        str
        """
        if self.proved:
            head = (f"the pairs the pruning's search drops under the bounds proved over the "
                    f"region save {100 * self.saving:.3g} % of the exact recursive model's "
                    f"operations ({self.exact_operations:,} - {self.best_operations:,}, quick "
                    f"counts; at EPS = {self.tolerance:g}"
                    + (f"; with the inertial parts of {self.restored} parameters restored, "
                       "as the proof that D_s is positive definite needs"
                       if self.restored else "") + ")")
            if self.skip:
                return (head + f", below the threshold of {100 * self.threshold:g} %: the "
                        "pruned model's programs were not built and the exact recursive model "
                        "(error 0 at every state; only pairs proved identically zero are left "
                        "out) is deployed")
            return head + f", at least the threshold of {100 * self.threshold:g} %: built"
        head = (f"a region model could save {'at most' if self.skip else 'at least'} about "
                f"{100 * self.saving:.3g} % of the "
                f"exact recursive model's operations ({self.exact_operations:,} - "
                f"{self.best_operations:,}, quick counts; estimated from the region's sampled "
                f"torques at EPS = {self.tolerance:g})")
        if self.skip:
            return (head + f", below the threshold of {100 * self.threshold:g} %: the region's "
                    "certification and search were skipped and the exact recursive model "
                    "(error 0 at every state; only pairs proved identically zero are left out) "
                    "is deployed")
        return head + f", at least the threshold of {100 * self.threshold:g} %: searched"

    def to_dict(self) -> dict:
        """The model file's ``provenance.region_screen``.

        Returns
        -------
        dict
            ``possible_saving`` and ``threshold`` [1], ``exact_operations``,
            ``best_operations``, ``skipped``, ``proved`` (:attr:`proved`),
            ``statement`` and, where some were, ``restored`` (:attr:`restored`).
        """
        out = {"possible_saving": float(self.saving), "threshold": float(self.threshold),
               "exact_operations": int(self.exact_operations),
               "best_operations": int(self.best_operations), "skipped": self.skip,
               "proved": bool(self.proved), "statement": self.text()}
        if self.restored:
            out["restored"] = int(self.restored)
        return out


def screen_region(robot: Robot, base: BaseParameters, region: Region, values: tuple,
                  tolerance: float, torque_floor: float = 0.0, threshold: float = MIN_SAVING,
                  magnitudes: np.ndarray | None = None) -> RegionScreen:
    """The sampled pre-screen of a region model (module docstring).

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its b base parameters.
    region : Region
    values : tuple
        :func:`.region.region_samples` with the certification's samples and seed:
        positions (B, n), channel values (B, P, n, b) (packed), scale (n,), scale state (n, 3 n).
    tolerance : float
        EPS >= 0.
    torque_floor : float, optional
        Least scale [N m or N].
    threshold : float, optional
        :data:`MIN_SAVING`.
    magnitudes : ndarray, shape (B, b, 3, n), optional
        :func:`.certify.pair_magnitudes_at` of ``values``, if already computed.

    Returns
    -------
    RegionScreen

    Raises
    ------
    ValueError
        If the tolerance is negative or not finite.

    Notes
    -----
    Moore, Kearfott & Cloud (2009), Ch. 6: an enclosure over a box bounds every point value
    in it, so the sampled constraint is implied by the proved one; Khalil & Kleinfinger (1987)
    for tau = Y_b beta.
    """
    t0 = time.perf_counter()
    _, V, scale, state = values
    scale = np.maximum(np.asarray(scale, float), torque_floor)
    beta = np.asarray(base.beta, float)
    if magnitudes is None:
        magnitudes = pair_magnitudes_at(V, beta, region.qd_max, region.qdd_max)
    pieces = np.array(np.asarray(magnitudes, float).transpose(1, 2, 0, 3),
                      order="C")                                         # (b, 3, B, n), a copy
    pieces[pieces <= ROUND_OFF * scale] = 0.0
    peak = pieces.max(axis=2)
    free = ~(peak > 0).any(axis=2)
    exact = int(parts_count(robot, part_values(base, np.zeros(peak.shape[:2], bool))))
    pr = prune_bounds(robot, base, scale, peak, pieces.sum(axis=1).max(axis=1), tolerance,
                      pieces=pieces, zero=free,
                      stop_at=math.floor((1.0 - threshold) * max(exact, 1)))
    safe = np.where(scale > 0, scale, 1.0)
    rel = np.where(scale > 0, peak / safe, np.where(peak > 0, np.inf, 0.0)).max(axis=2)
    return RegionScreen(
        tolerance=float(tolerance), threshold=float(threshold), exact_operations=exact,
        best_operations=int(parts_count(robot, part_values(base, pr.dropped))),
        dropped=pr.dropped, scale=scale, scale_state=np.asarray(state, float),
        relative_peak=rel, seconds=time.perf_counter() - t0)


def proved_screen(robot: Robot, base: BaseParameters, dropped: np.ndarray, tolerance: float,
                  scale: np.ndarray, scale_state: np.ndarray, relative_peak: np.ndarray,
                  threshold: float = MIN_SAVING, restored: int = 0) -> RegionScreen:
    """The saving of a region model's pairs found under the proved bounds, as a screen.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its b base parameters.
    dropped : ndarray of bool, shape (b, 3)
        The pairs the pruning's search drops under the bounds proved over the region
        (:attr:`gd_analyze.symbolic.pruning.Pruning.dropped`).
    tolerance : float
        EPS >= 0.
    scale : ndarray, shape (n,)
        s_i of the certification [N m or N].
    scale_state : ndarray, shape (n, 3 n)
        Where it was found: (q, qd, qdd).
    relative_peak : ndarray, shape (b, 3)
        Per pair, its proved bound relative to s_i, max over the joints [1].
    threshold : float, optional
        :data:`MIN_SAVING`.
    restored : int, optional
        The parameters whose inertial part the search dropped and ``dropped`` keeps, for the
        proof of D_s (:func:`gd_analyze.certify.positive_definite.inertia_restored`).

    Returns
    -------
    RegionScreen
        ``proved`` True; ``best_operations`` the quick count of ``dropped``
        (:func:`gd_analyze.symbolic.recursive.parts_count`, as the search compared its
        candidates), ``exact_operations`` that of nothing dropped. ``skip``: the set saves
        less than ``threshold`` of it, so the pruned model's programs (each a search over the
        links' forms) are not worth building.

    Notes
    -----
    It decides only which of two sound models is built: the pruned one (its bound proved) or
    the exact one (error 0), never a bound.
    """
    t0 = time.perf_counter()
    dropped = np.asarray(dropped, bool)
    exact = int(parts_count(robot, part_values(base, np.zeros(dropped.shape, bool))))
    best = int(parts_count(robot, part_values(base, dropped)))
    return RegionScreen(
        tolerance=float(tolerance), threshold=float(threshold), exact_operations=exact,
        best_operations=best, dropped=dropped.copy(), scale=np.array(scale, float),
        scale_state=np.asarray(scale_state, float),
        relative_peak=np.asarray(relative_peak, float), seconds=time.perf_counter() - t0,
        proved=True, restored=int(restored))
