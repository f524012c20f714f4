"""Build the simplified explicit model of a robot along trajectories.

robot -> explicit terms (cached derivation) -> peaks of every part and term along the
trajectories -> selection by the rule (budget or chapter) -> straight-line program -> model,
its cost, its error, and the tolerance ladder. Nothing here prints or writes files.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..dynamics.dalembert import gd_terms
from ..model.drives import DRIVE_FIELDS
from ..ranking.ranking import DEFAULT_DOMINANCE, DEFAULT_NEGLIGIBLE
from ..simplify.budget import DEFAULT_TOLERANCE, PartPeaks, relative_peaks, select_terms
from ..simplify.simplified import SimplifiedModel, TorqueErrorAccumulator, total_operations
from ..store.explicit_cache import explicit_terms
from ..symbolic.codegen import build_program
from ..symbolic.drive_regressor import with_drives
from ..symbolic.emit import python_function
from ..symbolic.explicit import term_peaks

if TYPE_CHECKING:                       # for the type hints only
    from numpy.typing import NDArray

    from ..model.robot import Robot
    from ..ranking.ranking import Ranking
    from ..simplify.budget import Selection
    from ..symbolic.codegen import Program
    from ..symbolic.explicit import Term
    from ..trajectory.trajectory import Trajectory

    #: tau(q, qd, qdd), each of shape (N, n), -> tau, shape (N, n) [N m]
    TorqueFunction = Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]
    #: The (q, qd, qdd) arrays of one trajectory, each of shape (N, n)
    States = tuple[np.ndarray, np.ndarray, np.ndarray]
    #: errors(model, trajectories, reference) -> (peak, sum_sq, peak_tau, counts), as
    #: per_trajectory_errors returns them
    TrajectoryErrors = Callable[[SimplifiedModel, Sequence[Trajectory], TorqueFunction | None],
                                tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]

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
    import dataclasses

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


def sweep_model(robot: Robot, trajectories: Sequence[Trajectory],
                tolerance: float = DEFAULT_TOLERANCE, torque_floor: float = 0.0,
                held_out: Sequence[Trajectory] = (), provenance: Mapping[str, Any] | None = None
                ) -> tuple[SimplifiedModel, Selection]:
    """One simplified explicit model guaranteed on every trajectory of a sweep (budget rule).

    Each joint's scale is per trajectory, scale_{t,i} = max(peak_t |tau_i|, TAU); every part's
    and term's (atom's) peak on trajectory t is divided by scale_{t,i} and the largest ratio
    over the trajectories is budgeted within EPS (:func:`gd_analyze.simplify.budget.relative_peaks`),
    so the model's error on each swept trajectory t is at most EPS x scale_{t,i} for every
    joint i.

    Parameters
    ----------
    robot : Robot
    trajectories : sequence of Trajectory
        The swept trajectories, q, qd, qdd of shape (N_t, n).
    tolerance : float, optional
        EPS.
    torque_floor : float, optional
        TAU [N m].
    held_out : sequence of Trajectory, optional
        Trajectories not swept: the error there is measured, not guaranteed.
    provenance : dict, optional

    Returns
    -------
    model : SimplifiedModel
        ``bound`` is the relative bound times the largest scale_i [N m]; ``validation`` as
        :func:`sweep_validation` gives it.
    selection : Selection
        ``scale`` is the largest scale_i over the trajectories.

    Raises
    ------
    ValueError
        If there are no trajectories.
    """
    trajectories = list(trajectories)
    model, sel, scales, relative, terms = explicit_sweep_model(robot, trajectories, tolerance,
                                                               torque_floor, provenance)
    validation = sweep_validation(model, trajectories, scales, relative, held_out=held_out,
                                  reference=full_torque(robot, terms))
    return dataclasses.replace(model, validation=validation), sel


def trajectories_sha256(trajectories: Sequence[Trajectory]) -> str:
    """One SHA-256 of a sweep's trajectories: their files' digests, or the arrays of planned
    trajectories.

    Parameters
    ----------
    trajectories : sequence of Trajectory
        Each with ``sha256`` (of its file; empty for a planned one) and q, qd, qdd (N, n).

    Returns
    -------
    str
        64 hex digits.
    """
    import hashlib

    h = hashlib.sha256()
    for tr in trajectories:
        h.update(tr.sha256.encode() if tr.sha256 else
                 b"".join(np.ascontiguousarray(x, float).tobytes() for x in (tr.q, tr.qd, tr.qdd)))
    return h.hexdigest()


def explicit_sweep_model(robot: Robot, trajectories: Sequence[Trajectory],
                         tolerance: float = DEFAULT_TOLERANCE, torque_floor: float = 0.0,
                         provenance: Mapping[str, Any] | None = None
                         ) -> tuple[SimplifiedModel, Selection, np.ndarray, np.ndarray, Term]:
    """The explicit model of :func:`sweep_model`, not yet validated.

    Parameters
    ----------
    robot : Robot
    trajectories : sequence of Trajectory
        K >= 1 swept trajectories.
    tolerance : float, optional
        EPS.
    torque_floor : float, optional
        TAU [N m].
    provenance : dict, optional

    Returns
    -------
    model : SimplifiedModel
        ``validation`` empty.
    selection : Selection
    scales : ndarray, shape (K, n)
        scale_{t,i} = max(peak |tau_i| on t, TAU) [N m].
    relative_bound : ndarray, shape (n,)
        The guaranteed bound on peak |tau_s - tau| / scale_{t,i} on every swept trajectory
        (<= EPS).
    terms : Term
        All the robot's explicit terms (for :func:`full_torque`).

    Raises
    ------
    ValueError
        If there are no trajectories.
    """
    trajectories = list(trajectories)
    if not trajectories:
        raise ValueError("no trajectories")
    terms, _ = explicit_terms(robot)
    peaks: Peaks | None = None
    scales: Any = []                   # a list, then its array (K, n)
    for tr in trajectories:
        p = collect_peaks(robot, terms, tr.q, tr.qd, tr.qdd)
        scales.append(np.maximum(p.parts.tau_peak, float(torque_floor)))
        p = p.relative(scales[-1])
        peaks = p if peaks is None else peaks.merge(p)
    scales = np.array(scales)
    top = scales.max(axis=0)
    model, sel = build_model(robot, terms,
                             peaks,  # type: ignore[arg-type]  # not None: K >= 1
                             tolerance=tolerance, torque_floor=torque_floor,
                             trajectory_sha256=trajectories_sha256(trajectories),
                             provenance={**(provenance or {}), "kind": "sweep model",
                                         "trajectories": len(trajectories)},
                             relative_to=top)
    relative = np.where(top > 0, sel.bound / np.where(top > 0, top, 1.0), 0.0)
    return model, sel, scales, relative, terms


def sweep_validation(model: SimplifiedModel, trajectories: Sequence[Trajectory],
                     scales: NDArray[np.float64], relative_bound: NDArray[np.float64],
                     held_out: Sequence[Trajectory] = (), reference: TorqueFunction | None = None,
                     bound: NDArray[np.float64] | None = None,
                     errors: TrajectoryErrors | None = None) -> dict[str, Any]:
    """A sweep model's errors on each swept trajectory, over all of them and on held-out ones.

    Parameters
    ----------
    model : SimplifiedModel
    trajectories : sequence of Trajectory
        The K swept trajectories.
    scales : ndarray, shape (K, n)
        scale_{t,i} [N m].
    relative_bound : ndarray, shape (n,)
        The guaranteed bound on peak |tau_s - tau| / scale_{t,i} (<= EPS).
    held_out : sequence of Trajectory, optional
        Trajectories not swept (measured, not guaranteed).
    reference : callable, optional
        tau_full(q, qd, qdd), as :func:`validate` takes it (default: the G-D terms).
    bound : ndarray, shape (K, n), optional
        The guaranteed bound on each trajectory [N m]; default ``relative_bound`` x scales.
    errors : callable, optional
        ``errors(model, trajectories, reference)`` -> (peak, sum_sq, peak_tau, counts) as
        :func:`per_trajectory_errors` (the default) returns them, e.g. measured by the
        workers of a dask cluster (:class:`gd_analyze.jobs.sweep.WorkerErrors`); called
        once, on the swept trajectories followed by the held-out ones.

    Returns
    -------
    dict
        The error over the swept trajectories together (as :func:`validate`), plus
        ``relative_bound`` (n,); ``worst_scaled_error``: the largest measured
        peak |tau_s - tau| / scale_{t,i} over trajectories and joints (<= relative_bound);
        ``per_trajectory``: ``peak_abs_error``, ``rms_error``, ``peak_tau``, ``scale`` and
        ``bound``, (K, n) lists [N m] (large: remove it before saving a big sweep's model);
        ``trajectories`` (K); ``held_out`` (the error on the held-out ones, or an empty dict)
        and ``held_out_trajectories``.
    """
    scales = np.asarray(scales, float)
    relative_bound = np.asarray(relative_bound, float)
    bound = relative_bound * scales if bound is None else np.asarray(bound, float)
    K = len(trajectories)
    every = (per_trajectory_errors if errors is None else errors)(
        model, [*trajectories, *held_out], reference)
    peak, sum_sq, peak_tau, counts = (np.asarray(a)[:K] for a in every)
    held = [np.asarray(a)[K:] for a in every]
    with np.errstate(divide="ignore", invalid="ignore"):
        scaled = np.where(peak > 0, peak / np.where(scales > 0, scales, 0.0), 0.0)
    validation = _accumulated(peak.max(axis=0, initial=0.0), sum_sq.sum(axis=0),
                              peak_tau.max(axis=0, initial=0.0), int(counts.sum()))
    validation.update({
        "relative_bound": [float(v) for v in relative_bound],
        "worst_scaled_error": float(np.nan_to_num(scaled, nan=np.inf).max(initial=0.0)),
        "per_trajectory": {"peak_abs_error": peak.tolist(),
                           "rms_error": np.sqrt(sum_sq / np.maximum(counts, 1)[:, None]).tolist(),
                           "peak_tau": peak_tau.tolist(),
                           "scale": scales.tolist(), "bound": bound.tolist()},
        "trajectories": len(trajectories),
        "held_out": _accumulated(held[0].max(axis=0), held[1].sum(axis=0),
                                 held[2].max(axis=0), int(held[3].sum())) if held_out else {},
        "held_out_trajectories": len(held_out),
    })
    return validation


def per_trajectory_errors(model: SimplifiedModel, trajectories: Sequence[Trajectory],
                          reference: TorqueFunction | None = None, chunk: int = 65536
                          ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A model's torque error along each of K trajectories, all evaluated together.

    Parameters
    ----------
    model : SimplifiedModel
        With n joints.
    trajectories : sequence of Trajectory
        Each q, qd, qdd (N_k, n) [rad, rad/s, rad/s^2].
    reference : callable, optional
        tau_full(q, qd, qdd), as :func:`validate` takes it (default: the G-D terms).
    chunk : int, optional
        Set points evaluated at once (a chunk may cut through trajectories).

    Returns
    -------
    peak : ndarray, shape (K, n)
        Peak |tau_s - tau| on each trajectory [N m].
    sum_sq : ndarray, shape (K, n)
        The sum of its squares [N^2 m^2].
    peak_tau : ndarray, shape (K, n)
        Peak |tau| [N m].
    counts : ndarray of int, shape (K,)
        The set points N_k.

    Notes
    -----
    The error of Sec. 3.4.1 of Fu, Gonzalez & Lee (1987), tau from Eqs. (3.4-24) to (3.4-28)
    by default; the states of consecutive trajectories are concatenated, so the model and the
    reference are evaluated on many set points per call.
    """
    n = model.robot.n
    K = len(trajectories)
    peak, sum_sq, peak_tau = np.zeros((K, n)), np.zeros((K, n)), np.zeros((K, n))
    counts = np.array([t.q.shape[0] for t in trajectories], int)
    owner = np.repeat(np.arange(K), counts)
    starts = np.concatenate([[0], np.cumsum(counts)])
    total = int(starts[-1])
    for a in range(0, total, chunk):
        b = min(a + chunk, total)
        first, last = int(owner[a]), int(owner[b - 1])
        q, qd, qdd = (np.concatenate([getattr(t, name)[max(a - starts[k], 0):b - starts[k]]
                                      for k, t in enumerate(trajectories[first:last + 1],
                                                            start=first)])
                      for name in ("q", "qd", "qdd"))
        tau = gd_terms(model.robot, q, qd).tau(qdd) if reference is None \
            else reference(q, qd, qdd)
        tau = np.asarray(tau, float)
        err = np.abs(np.asarray(model.torque(q, qd, qdd), float) - tau)
        who = owner[a:b]
        np.maximum.at(peak, who, err)
        np.add.at(sum_sq, who, err ** 2)
        np.maximum.at(peak_tau, who, np.abs(tau))
    return peak, sum_sq, peak_tau, counts


def _accumulated(peak, sum_sq, peak_tau, count):
    """:meth:`TorqueErrorAccumulator.result` of figures gathered elsewhere."""
    acc = TorqueErrorAccumulator(len(peak))
    acc.peak, acc.sum_sq, acc.peak_tau, acc.count = (np.asarray(peak, float),
                                                     np.asarray(sum_sq, float),
                                                     np.asarray(peak_tau, float), count)
    return acc.result()


__all__ += ["sweep_model", "explicit_sweep_model", "sweep_validation", "trajectories_sha256",
            "per_trajectory_errors"]
