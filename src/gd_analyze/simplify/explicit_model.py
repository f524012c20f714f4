"""The simplified explicit model of a robot along a trajectory.

robot -> explicit terms -> peaks of every part and term along the trajectory -> selection by
the rule (budget or chapter) -> straight-line program -> model, its cost, its error, and the
tolerance ladder. Nothing here prints or writes files.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..dynamics.dalembert import gd_terms
from ..model.drives import DRIVE_FIELDS
from ..ranking.ranking import DEFAULT_DOMINANCE, DEFAULT_NEGLIGIBLE
from ..symbolic.codegen import build_program
from ..symbolic.drive_regressor import with_drives
from ..symbolic.emit import python_function
from ..symbolic.explicit import term_peaks
from .budget import DEFAULT_TOLERANCE, PartPeaks, relative_peaks, select_terms
from .simplified import SimplifiedModel, TorqueErrorAccumulator, total_operations

if TYPE_CHECKING:                       # for the type hints only
    from numpy.typing import NDArray

    from ..model.robot import Robot
    from ..ranking.ranking import Ranking
    from ..symbolic.codegen import Program
    from ..symbolic.explicit import Term
    from .budget import Selection

    #: tau(q, qd, qdd), each of shape (N, n), -> tau, shape (N, n) [N m]
    TorqueFunction = Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]
    #: The (q, qd, qdd) arrays of one trajectory, each of shape (N, n)
    States = tuple[np.ndarray, np.ndarray, np.ndarray]

__all__ = ["Peaks", "collect_peaks", "build_model", "full_program", "LADDER", "ladder"]

#: The tolerance ladder of the report and README.
LADDER = (0.0, 0.001, 0.01, 0.05)


def _program(robot, terms, kept):
    """build_program of ``kept`` (a subset of ``terms``), once per content.

    The programs are kept in ``terms.programs`` by the SHA-256 of the kept terms: the full
    model (its cost and its reference torque) and a model the ladder builds again (the main
    model's EPS) are assembled once.
    """
    import hashlib

    digest = hashlib.sha256()
    for f in ("kind", "part", "i", "j", "k", "K", "S", "C"):
        digest.update(np.ascontiguousarray(getattr(kept, f)).tobytes())
    digest.update(np.asarray(robot.prismatic, bool).tobytes())
    for drive in DRIVE_FIELDS:
        digest.update(np.asarray(getattr(robot, drive), float).tobytes())
    cache = terms.programs
    key = (robot.n, digest.hexdigest())
    if key not in cache:        # the drives' terms are never dropped (drive_regressor.with_drives)
        cache[key] = with_drives(build_program(kept, robot.n, np.zeros(robot.n),
                                               prismatic=robot.prismatic), robot)
    return cache[key]


def full_program(robot: Robot, terms: Term) -> Program:
    """The straight-line program of the full explicit model (:class:`~gd_analyze.symbolic.codegen.Program`).

    Parameters
    ----------
    robot : Robot
        The arm.
    terms : Term
        All its explicit terms (:func:`gd_analyze.store.explicit_cache.explicit_terms`).

    Returns
    -------
    Program
        Built once per terms object; its ``cost()`` is the full model's counted operations.
    """
    return _program(robot, terms, terms)


@dataclass(eq=False)
class Peaks:
    """Peaks along one or more trajectories, combinable by maximum.

    Attributes
    ----------
    parts : PartPeaks
        Peak contribution of every part, and peak |tau| [N m].
    terms : ndarray, shape (U, n)
        Peak contribution of every explicit term [N m].
    """

    parts: PartPeaks
    terms: np.ndarray

    def merge(self, other: Peaks) -> Peaks:
        """Combine with the peaks of other trajectories (maximum).

        Parameters
        ----------
        other : Peaks
            Peaks of the same robot and terms on other trajectories.

        Returns
        -------
        Peaks
            self, updated in place.
        """
        self.parts.merge(other.parts)
        np.maximum(self.terms, other.terms, out=self.terms)
        return self

    def relative(self, scale: NDArray[np.float64]) -> Peaks:
        """These peaks divided by the joint scales of their trajectory (for a sweep).

        Parameters
        ----------
        scale : ndarray, shape (n,)
            The trajectory's scale_i = max(peak |tau_i|, TAU) [N m].

        Returns
        -------
        Peaks
            New peaks: :func:`gd_analyze.simplify.budget.relative_peaks` of the parts and terms,
            and ``parts.tau_peak`` = 1 (every joint's scale is 1 in these units).
        """
        parts = PartPeaks(self.parts.n)
        parts.peaks = relative_peaks(self.parts.peaks, scale)
        parts.tau_peak = np.ones(self.parts.n)
        return Peaks(parts=parts, terms=relative_peaks(self.terms, scale))


def collect_peaks(robot: Robot, terms: Term, q: NDArray[np.float64], qd: NDArray[np.float64],
                  qdd: NDArray[np.float64], chunk: int = 8192, gd: PartPeaks | None = None,
                  term: NDArray[np.float64] | None = None) -> Peaks:
    """Peaks of the parts and of the explicit terms along one trajectory.

    Parameters
    ----------
    robot : Robot
    terms : Term
        All explicit terms (:func:`gd_analyze.store.explicit_cache.explicit_terms`).
    q, qd, qdd : ndarray, shape (N, n)
        [rad, rad/s, rad/s^2].
    chunk : int, optional
        Set points at once.
    gd : PartPeaks, optional
        Part peaks already accumulated (by a pass over the G-D terms); computed if not given.
    term : ndarray, shape (A, n), optional
        :func:`gd_analyze.symbolic.explicit.term_peaks` of these terms on this
        trajectory, if already computed [N m].

    Returns
    -------
    Peaks
    """
    if gd is None:
        gd = PartPeaks(robot.n)
        for a in range(0, q.shape[0], chunk):
            sl = slice(a, a + chunk)
            t = gd_terms(robot, q[sl], qd[sl])
            gd.update(t.D_tran, t.D_rot, t.h_tran, t.h_rot, qdd[sl], t.tau(qdd[sl]))
    if term is None:
        term = term_peaks(terms, np.zeros(robot.n), q, qd, qdd, prismatic=robot.prismatic)
    return Peaks(parts=gd, terms=term)


def build_model(robot: Robot, terms: Term, peaks: Peaks, tolerance: float = DEFAULT_TOLERANCE,
                rule: str = "budget", torque_floor: float = 0.0,
                chapter_choices: Mapping[str, str] | None = None, ranking: Ranking | None = None,
                trajectory_sha256: str = "", provenance: Mapping[str, Any] | None = None,
                relative_to: NDArray[np.float64] | None = None
                ) -> tuple[SimplifiedModel, Selection]:
    """The simplified explicit model chosen by a rule on the peaks.

    Parameters
    ----------
    robot : Robot
    terms : Term
        All explicit terms.
    peaks : Peaks
        From :func:`collect_peaks` (merged over trajectories for a sweep).
    tolerance : float, optional
        EPS.
    rule : {"budget", "chapter"}, optional
    torque_floor : float, optional
        TAU [N m].
    chapter_choices : dict, optional
        The share-based choices (needed for the chapter rule).
    ranking : Ranking, optional
        For the thresholds s and e recorded with the model.
    trajectory_sha256 : str, optional
    provenance : dict, optional
    relative_to : ndarray, shape (n,), optional
        Given when ``peaks`` are relative to each trajectory's own scale
        (:meth:`Peaks.relative`, merged over a sweep): the largest scale_i over the
        trajectories [N m]. The budget is then EPS on the ratios, and the selection's scale and
        bounds are brought back to N m with it (the bound on trajectory t is the relative bound
        times that trajectory's scale_{t,i}, at most this one).

    Returns
    -------
    model : SimplifiedModel
        With ``validation`` empty (fill it with :func:`validate`).
    selection : Selection
    """

    def select(eps):
        sel = select_terms(terms, peaks.terms, peaks.parts.peaks, peaks.parts.tau_peak,
                           tolerance=eps, rule=rule,
                           torque_floor=torque_floor if relative_to is None else 0.0,
                           chapter_choices=chapter_choices)
        if relative_to is not None:
            top = np.asarray(relative_to, float)
            sel = dataclasses.replace(
                sel, scale=top, bound=sel.bound * top, element_bound=sel.element_bound * top,
                bound_by_kind={k: v * top for k, v in sel.bound_by_kind.items()})
        return sel

    sel = select(tolerance)
    program = _program(robot, terms, sel.kept)
    full = full_program(robot, terms).cost()
    if rule == "budget" and total_operations(program.cost()) > total_operations(full):
        # dropping terms can cost more (the factoring and the CSE find less to share): the
        # full model (nothing dropped, bound 0) is then the cheapest one within the budget
        sel = select(0.0)
        program = _program(robot, terms, sel.kept)
    model = SimplifiedModel(
        robot=robot, choices=sel.choices,
        dominance_threshold=float(getattr(ranking, "dominance_threshold", DEFAULT_DOMINANCE)),
        negligible_threshold=float(getattr(ranking, "negligible_threshold", DEFAULT_NEGLIGIBLE)),
        trajectory_sha256=trajectory_sha256, provenance=dict(provenance or {}), rule=rule,
        tolerance=float(tolerance), torque_floor=float(torque_floor), terms=sel.kept,
        cost=program.cost(), full_cost=full, bound=[float(v) for v in sel.bound],
        program_cache=program)
    return model, sel


def full_torque(robot: Robot, terms: Term) -> TorqueFunction:
    """The full explicit model as a function tau(q, qd, qdd), shape (N, n) [N m].

    Parameters
    ----------
    robot : Robot
    terms : Term
        All explicit terms.

    Returns
    -------
    callable
        Equal to the G-D model's tau = D qdd + h + c to rounding (the tests check it against
        Pinocchio rnea to 1e-10), without computing the G-D terms again.
    """

    return python_function(_program(robot, terms, terms))


def validate(model: SimplifiedModel, trajectories: Iterable[States], chunk: int = 65536,
             reference: TorqueFunction | None = None) -> dict[str, Any]:
    """The model's torque error against the full model along trajectories.

    Parameters
    ----------
    model : SimplifiedModel
    trajectories : iterable of (q, qd, qdd)
        Arrays of shape (N, n).
    chunk : int, optional
    reference : callable, optional
        tau_full(q, qd, qdd); by default the G-D terms' D qdd + h + c (:func:`full_torque`
        avoids computing them again).

    Returns
    -------
    dict
        As :func:`gd_analyze.simplify.simplified.torque_error` (over all trajectories
        together).
    """
    acc = TorqueErrorAccumulator(model.robot.n)
    for q, qd, qdd in trajectories:
        for a in range(0, q.shape[0], chunk):
            sl = slice(a, a + chunk)
            tau = gd_terms(model.robot, q[sl], qd[sl]).tau(qdd[sl]) if reference is None \
                else reference(q[sl], qd[sl], qdd[sl])
            acc.update(model.torque(q[sl], qd[sl], qdd[sl]), tau)
    return acc.result()


__all__ += ["validate", "full_torque"]


def ladder(robot: Robot, terms: Term, peaks: Peaks, trajectory: States,
           torque_floor: float = 0.0, reference: TorqueFunction | None = None
           ) -> list[dict[str, Any]]:
    """The explicit model's tolerance ladder: cost and worst per-joint error for each EPS of
    :data:`LADDER`.

    Parameters
    ----------
    robot : Robot
    terms : Term
    peaks : Peaks
        Along the analysed trajectory.
    trajectory : (q, qd, qdd)
        The analysed trajectory, arrays of shape (N, n) (the error there is guaranteed
        within EPS).
    torque_floor : float, optional
    reference : callable, optional
        tau_full(q, qd, qdd) for :func:`validate`.

    Returns
    -------
    list of dict
        Per EPS: ``tolerance``, ``multiplications``, ``additions``, ``sin``, ``cos``,
        ``worst_relative_error`` (max over joints of peak |tau_s - tau| / scale_i on the
        trajectory).
    """
    scale = np.maximum(peaks.parts.tau_peak, torque_floor)
    rows = []
    for eps in LADDER:
        model, _ = build_model(robot, terms, peaks, tolerance=eps, torque_floor=torque_floor)
        err = np.array(validate(model, [trajectory], reference=reference)["peak_abs_error"])
        rows.append({"tolerance": float(eps), **model.cost, "worst_relative_error": float(
            np.max(err / np.where(scale > 0, scale, np.inf)))})
    return rows


#: The ladder is skipped when the full explicit model costs more than this many times
#: Newton-Euler as implemented: its rungs are then not expected to pay (EPS = 0.05 halves the
#: PUMA 560's full model), and each is a long build (seconds for the Panda's full model of
#: 97,231 operations).
LADDER_COST_LIMIT = 4.0


def ladder_skipped(full_cost: Mapping[str, Any],
                   formulation_counts: Mapping[str, Any]) -> str:
    """Why the tolerance ladder is not worth building for an arm, or "" if it is.

    Parameters
    ----------
    full_cost : dict
        The full explicit model's ``multiplications`` and ``additions``.
    formulation_counts : dict
        :func:`gd_analyze.dynamics.opcount.operation_counts`, with ``"newton-euler"``.

    Returns
    -------
    str
        Empty if the full explicit model costs at most :data:`LADDER_COST_LIMIT` times
        Newton-Euler (multiplications + additions); else one sentence for the report.

    Examples
    --------
    >>> ladder_skipped({"multiplications": 638, "additions": 690},
    ...                {"newton-euler": {"multiplications": 683, "additions": 529}})
    ''
    >>> ladder_skipped({"multiplications": 90000, "additions": 80000},
    ...                {"newton-euler": {"multiplications": 800, "additions": 652}})[:50]
    'not built: the full explicit model costs 170,000 o'
    """
    full = int(full_cost["multiplications"]) + int(full_cost["additions"])
    ne = formulation_counts["newton-euler"]
    ne = int(ne["multiplications"]) + int(ne["additions"])
    if full <= LADDER_COST_LIMIT * ne:
        return ""
    return (f"not built: the full explicit model costs {full:,} operations, more than "
            f"{LADDER_COST_LIMIT:g} times Newton-Euler's {ne:,}; none of its rungs (EPS up to "
            f"{max(LADDER):g}) is expected to pay for this arm, and each is a long build")


__all__ += ["ladder_skipped", "LADDER_COST_LIMIT"]


