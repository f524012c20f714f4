"""The simplified explicit model over the trajectories of a sweep.

robot -> explicit terms (given, or derived here) -> peaks along every trajectory -> one
selection by the budget rule whose bound holds on each -> model, validated on them (and on
held-out ones), and the per-trajectory errors the workers compute. Pure: the jobs pass the
terms read from the derivation cache (:func:`gd_analyze.store.explicit_cache.explicit_terms`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..dynamics.dalembert import gd_terms
from ..symbolic.explicit import derive, model_terms
from .budget import DEFAULT_TOLERANCE
from .explicit_model import Peaks, build_model, collect_peaks, full_torque
from .simplified import SimplifiedModel, TorqueErrorAccumulator

if TYPE_CHECKING:                       # for the type hints only
    from numpy.typing import NDArray

    from ..model.robot import Robot
    from ..symbolic.explicit import Term
    from .budget import Selection
    from .choices import Motion

    #: tau(q, qd, qdd), each of shape (N, n), -> tau, shape (N, n) [N m]
    TorqueFunction = Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]
    #: errors(model, trajectories, reference) -> (peak, sum_sq, peak_tau, counts), as
    #: per_trajectory_errors returns them
    TrajectoryErrors = Callable[[SimplifiedModel, Sequence[Motion], TorqueFunction | None],
                                tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]

__all__ = ["sweep_model", "explicit_sweep_model", "sweep_validation", "trajectories_sha256",
           "per_trajectory_errors"]


def sweep_model(robot: Robot, trajectories: Sequence[Motion],
                tolerance: float = DEFAULT_TOLERANCE, torque_floor: float = 0.0,
                held_out: Sequence[Motion] = (), provenance: Mapping[str, Any] | None = None,
                terms: Term | None = None) -> tuple[SimplifiedModel, Selection]:
    """One simplified explicit model guaranteed on every trajectory of a sweep (budget rule).

    Each joint's scale is per trajectory, scale_{t,i} = max(peak_t |tau_i|, TAU); every part's
    and term's (atom's) peak on trajectory t is divided by scale_{t,i} and the largest ratio
    over the trajectories is budgeted within EPS (:func:`gd_analyze.simplify.budget.relative_peaks`),
    so the model's error on each swept trajectory t is at most EPS x scale_{t,i} for every
    joint i.

    Parameters
    ----------
    robot : Robot
    trajectories : sequence of Motion
        The swept trajectories, q, qd, qdd of shape (N_t, n).
    tolerance : float, optional
        EPS.
    torque_floor : float, optional
        TAU [N m].
    held_out : sequence of Motion, optional
        Trajectories not swept: the error there is measured, not guaranteed.
    provenance : dict, optional
    terms : Term, optional
        All the robot's explicit terms (:func:`gd_analyze.symbolic.explicit.model_terms`);
        derived here (:func:`gd_analyze.symbolic.explicit.derive`) where not given.

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
                                                               torque_floor, provenance, terms)
    validation = sweep_validation(model, trajectories, scales, relative, held_out=held_out,
                                  reference=full_torque(robot, terms))
    return dataclasses.replace(model, validation=validation), sel


def trajectories_sha256(trajectories: Sequence[Motion]) -> str:
    """One SHA-256 of a sweep's trajectories: their files' digests, or the arrays of planned
    trajectories.

    Parameters
    ----------
    trajectories : sequence of Motion
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


def explicit_sweep_model(robot: Robot, trajectories: Sequence[Motion],
                         tolerance: float = DEFAULT_TOLERANCE, torque_floor: float = 0.0,
                         provenance: Mapping[str, Any] | None = None, terms: Term | None = None
                         ) -> tuple[SimplifiedModel, Selection, np.ndarray, np.ndarray, Term]:
    """The explicit model of :func:`sweep_model`, not yet validated.

    Parameters
    ----------
    robot : Robot
    trajectories : sequence of Motion
        K >= 1 swept trajectories.
    tolerance : float, optional
        EPS.
    torque_floor : float, optional
        TAU [N m].
    provenance : dict, optional
    terms : Term, optional
        As :func:`sweep_model` takes them.

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
    if terms is None:
        terms = model_terms(derive(robot))
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


def sweep_validation(model: SimplifiedModel, trajectories: Sequence[Motion],
                     scales: NDArray[np.float64], relative_bound: NDArray[np.float64],
                     held_out: Sequence[Motion] = (), reference: TorqueFunction | None = None,
                     bound: NDArray[np.float64] | None = None,
                     errors: TrajectoryErrors | None = None) -> dict[str, Any]:
    """A sweep model's errors on each swept trajectory, over all of them and on held-out ones.

    Parameters
    ----------
    model : SimplifiedModel
    trajectories : sequence of Motion
        The K swept trajectories.
    scales : ndarray, shape (K, n)
        scale_{t,i} [N m].
    relative_bound : ndarray, shape (n,)
        The guaranteed bound on peak |tau_s - tau| / scale_{t,i} (<= EPS).
    held_out : sequence of Motion, optional
        Trajectories not swept (measured, not guaranteed).
    reference : callable, optional
        tau_full(q, qd, qdd), as :func:`gd_analyze.simplify.explicit_model.validate` takes it (default: the G-D terms).
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
        The error over the swept trajectories together (as :func:`gd_analyze.simplify.explicit_model.validate`), plus
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


def per_trajectory_errors(model: SimplifiedModel, trajectories: Sequence[Motion],
                          reference: TorqueFunction | None = None, chunk: int = 65536
                          ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A model's torque error along each of K trajectories, all evaluated together.

    Parameters
    ----------
    model : SimplifiedModel
        With n joints.
    trajectories : sequence of Motion
        Each q, qd, qdd (N_k, n) [rad, rad/s, rad/s^2].
    reference : callable, optional
        tau_full(q, qd, qdd), as :func:`gd_analyze.simplify.explicit_model.validate` takes it (default: the G-D terms).
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
