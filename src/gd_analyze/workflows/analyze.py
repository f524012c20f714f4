"""The main job as a function: robot and trajectory in, verified analysis out.

robot model -> kinematics -> G-D terms -> verification -> ranking -> simplified model -> dataset.
The command line calls :func:`analyze` and then writes the files; nothing here prints or exits.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.dalembert import gd_terms
from ..core.ranking import DEFAULT_DOMINANCE, DEFAULT_NEGLIGIBLE, rank_dominance
from ..core.simplified import SimplifiedModel, simplified_torque, torque_error

__all__ = ["Analysis", "analyze", "analyze_to_file", "verify", "VERIFY_TOLERANCE",
           "VERIFY_MAX_SETPOINTS", "STREAM_CHUNK"]

#: Largest relative disagreement with Pinocchio accepted by :func:`verify`.
VERIFY_TOLERANCE = 1e-9
#: Set points checked against Pinocchio at most (evenly spread over the trajectory).
VERIFY_MAX_SETPOINTS = 2000
#: Set points per chunk when streaming to a file.
STREAM_CHUNK = 65536
#: Seconds a run must last before its progress bar appears.
PROGRESS_DELAY = 1.0


@dataclass(frozen=True, eq=False)
class Analysis:
    """The result of :func:`analyze`.

    Attributes
    ----------
    dataset : xarray.Dataset
        Everything to store (see :mod:`gd_analyze.io.datasets`).
    model : SimplifiedModel
        The simplified model with its validation along the trajectory.
    verification : dict
        Largest relative disagreement with Pinocchio per term, the set points checked, and
        ``passed`` (bool).
    """

    dataset: object
    model: SimplifiedModel
    verification: dict


def _subsample(N, max_setpoints):
    return np.unique(np.linspace(0, N - 1, min(N, max_setpoints)).round().astype(int))


def verify(robot, q, qd, terms=None, max_setpoints=VERIFY_MAX_SETPOINTS):
    """Check G-D terms against Pinocchio's crba, nonLinearEffects and generalized gravity.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q, qd : ndarray, shape (N, n)
        Joint positions [rad] and velocities [rad/s].
    terms : GDTerms, optional
        The G-D terms at those states; computed at the checked set points if not given.
    max_setpoints : int, optional
        At most this many set points, evenly spread, are checked.

    Returns
    -------
    dict
        ``max_rel_error_<term>`` for D_tran, D_rot, h_tran, h_rot, D, h and c (each the largest
        absolute difference over the largest magnitude of Pinocchio's value), ``setpoints``
        checked, ``tolerance`` and ``passed`` (1 if all are within tolerance, else 0).

    Notes
    -----
    The split parts are checked against the half-models with zero rotational inertia and with
    zero mass (see :mod:`gd_analyze.formulations.pinocchio`).
    """
    from ..formulations.pinocchio import reference_terms, relative_error

    idx = _subsample(q.shape[0], max_setpoints)
    ref = reference_terms(robot, q[idx], qd[idx])
    ours = gd_terms(robot, q[idx], qd[idx]) if terms is None else None
    out = {}
    for name in ("D_tran", "D_rot", "h_tran", "h_rot", "D", "h", "c"):
        value = getattr(ours, name) if terms is None else getattr(terms, name)[idx]
        out[f"max_rel_error_{name}"] = relative_error(value, getattr(ref, name))
    worst = max(out.values())
    out.update(setpoints=int(idx.size), tolerance=VERIFY_TOLERANCE,
               engine="pinocchio", passed=int(worst <= VERIFY_TOLERANCE))
    return out


def _simplify(robot, trajectory, ranking, part_peaks, tolerance, rule, torque_floor,
               provenance):
    """The explicit simplified model by the rule, the other rule's model, ladder, costs."""
    from .simplify import (build_model, collect_peaks, cost_rows, ladder,
                                     simplified_dataset, validate)
    from ..io.explicit_cache import explicit_terms

    terms, _ = explicit_terms(robot)
    q, qd, qdd = trajectory.q, trajectory.qd, trajectory.qdd
    peaks = collect_peaks(robot, terms, q, qd, qdd, gd=part_peaks)
    common = dict(torque_floor=torque_floor, chapter_choices=ranking.choices(),
                  ranking=ranking, trajectory_sha256=trajectory.sha256, provenance=provenance)
    model, sel = build_model(robot, terms, peaks, tolerance=tolerance, rule=rule, **common)
    other_rule = "chapter" if rule == "budget" else "budget"
    other, _ = build_model(robot, terms, peaks, tolerance=tolerance, rule=other_rule, **common)
    other_error = validate(other, [(q, qd, qdd)])
    rows = ladder(robot, terms, peaks, [(q, qd, qdd)], torque_floor=torque_floor)
    table = cost_rows(robot.n, model, other=other, ladder_rows=rows)
    extra = simplified_dataset(model, sel, other=other, ladder_rows=rows, cost_table=table,
                               other_error=other_error)
    return model, extra


def analyze(robot, trajectory, dominance=DEFAULT_DOMINANCE, negligible=DEFAULT_NEGLIGIBLE,
            check=True, settings=None, tolerance=0.01, rule="budget", torque_floor=0.0):
    """Compute, verify, rank and simplify the G-D terms along a trajectory.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    trajectory : Trajectory
        q, qd, qdd of shape (N, n) [rad, rad/s, rad/s^2].
    dominance : float, optional
        s, the dominance threshold of the ranking.
    negligible : float, optional
        e, the negligibility threshold.
    check : bool, optional
        Verify against Pinocchio (:func:`verify`).
    settings : dict, optional
        Extra provenance for the dataset's global attributes and the model.
    tolerance : float, optional
        EPS of the error budget (rule ``"budget"``).
    rule : {"budget", "chapter"}, optional
        How the simplified model is chosen (:mod:`gd_analyze.core.budget`).
    torque_floor : float, optional
        TAU [N m], the least scale of a joint torque.

    Returns
    -------
    Analysis

    Raises
    ------
    ValueError
        If the trajectory does not fit the robot or the thresholds are out of range.

    Notes
    -----
    Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987); terms from Eqs. (3.4-24) to (3.4-28).
    """
    from .. import __version__
    from ..io.datasets import build_dataset

    from ..core.budget import PartPeaks

    terms = gd_terms(robot, trajectory.q, trajectory.qd)
    tau = terms.tau(trajectory.qdd)
    ranking = rank_dominance(terms.D_tran, terms.D_rot, terms.h_tran, terms.h_rot, tau,
                             dominance=dominance, negligible=negligible)
    parts = PartPeaks(robot.n)
    parts.update(terms.D_tran, terms.D_rot, terms.h_tran, terms.h_rot, trajectory.qdd, tau)
    provenance = {"gd_analyze_version": __version__, "trajectory_file": trajectory.source,
                  "derivatives": trajectory.derivatives, **(settings or {})}
    model, extra = _simplify(robot, trajectory, ranking, parts, tolerance, rule, torque_floor,
                             provenance)
    choices = model.choices
    tau_s = model.torque(trajectory.q, trajectory.qd, trajectory.qdd)
    error = torque_error(tau_s, tau)
    object.__setattr__(model, "validation", error)
    verification = verify(robot, trajectory.q, trajectory.qd, terms) if check else {}
    ds = build_dataset(robot, trajectory, terms, ranking, tau, tau_s, choices, error,
                       verification=verification, settings=settings)
    ds = ds.assign(extra.data_vars)
    ds.attrs.update(extra.attrs)
    return Analysis(dataset=ds, model=model, verification=verification)


def analyze_to_file(robot, trajectory, path, dominance=DEFAULT_DOMINANCE,
                    negligible=DEFAULT_NEGLIGIBLE, check=True, settings=None,
                    chunk=STREAM_CHUNK, progress=False, compress=0, formulations=True,
                    extra=None, tolerance=0.01, rule="budget", torque_floor=0.0):
    """:func:`analyze`, streamed into a results file in chunks of bounded memory.

    Two passes over the trajectory: the first computes the G-D terms chunk by chunk, writes
    them and accumulates the ranking; the second, once the simplified model is known,
    recomputes the terms and writes tau_simplified. Memory stays a few chunks whatever N is.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    trajectory : Trajectory
        q, qd, qdd of shape (N, n) [rad, rad/s, rad/s^2].
    path : str or os.PathLike
        The results file (netCDF4/HDF5), written under a temporary name and renamed.
    dominance, negligible : float, optional
        s and e of the ranking.
    check : bool, optional
        Verify against Pinocchio on at most :data:`VERIFY_MAX_SETPOINTS` set points.
    settings : dict, optional
        Extra provenance.
    chunk : int, optional
        Set points per chunk.
    progress : bool, optional
        Show a tqdm progress bar on stderr (set points done and rate).
    compress : int, optional
        gzip level (0-9) of the per-set-point variables; 0 stores them uncompressed.
    formulations : bool, optional
        Also store the agreement of L-E, N-E, G-D and Pinocchio on (a sample of) the
        trajectory and their operation counts
        (:func:`gd_analyze.formulations.compare.formulations_dataset`).
    extra : xarray.Dataset, optional
        More variables to store with the summary (e.g. a payload sweep, dim ``payload``).
    tolerance, rule, torque_floor : optional
        As :func:`analyze`.

    Returns
    -------
    Analysis
        Its dataset is the summary (:func:`gd_analyze.io.datasets.summary_dataset`); the file holds
        the per-set-point variables as well.

    Raises
    ------
    ValueError
        If the trajectory does not fit the robot or the thresholds are out of range.
    OSError
        If the file cannot be written.
    """
    from tqdm.auto import tqdm

    from .. import __version__
    from ..core.ranking import RankingAccumulator
    from ..core.simplified import TorqueErrorAccumulator
    from ..files import atomic_path
    from ..io.datasets import SetpointWriter, summary_dataset

    N, n = trajectory.q.shape
    chunk = max(1, int(chunk))
    ranges = [(a, min(a + chunk, N)) for a in range(0, N, chunk)]
    from ..core.budget import PartPeaks

    ranker = RankingAccumulator(n)
    parts = PartPeaks(n)
    errors = TorqueErrorAccumulator(n)
    bar = tqdm(total=2 * N, unit="setpoint", unit_scale=True, disable=not progress,
               desc="G-D terms", delay=PROGRESS_DELAY, leave=False)
    with atomic_path(path) as tmp:
        with SetpointWriter(tmp, N, n, chunk=min(chunk, 8192), compress=compress) as out:
            out.write(0, {"t": trajectory.t, "q": trajectory.q, "qd": trajectory.qd,
                          "qdd": trajectory.qdd})
            for a, b in ranges:
                terms = gd_terms(robot, trajectory.q[a:b], trajectory.qd[a:b])
                tau = terms.tau(trajectory.qdd[a:b])
                ranker.update(terms.D_tran, terms.D_rot, terms.h_tran, terms.h_rot, tau)
                parts.update(terms.D_tran, terms.D_rot, terms.h_tran, terms.h_rot,
                             trajectory.qdd[a:b], tau)
                out.write(a, {"D_tran": terms.D_tran, "D_rot": terms.D_rot, "D": terms.D,
                              "h_tran": terms.h_tran, "h_rot": terms.h_rot, "h": terms.h,
                              "c": terms.c, "tau": tau})
                bar.update(b - a)
            ranking = ranker.result(dominance=dominance, negligible=negligible)
            provenance = {"gd_analyze_version": __version__,
                          "trajectory_file": trajectory.source,
                          "derivatives": trajectory.derivatives, **(settings or {})}
            model, simp = _simplify(robot, trajectory, ranking, parts, tolerance, rule,
                                    torque_floor, provenance)
            choices = model.choices
            bar.set_description("simplified model")
            for a, b in ranges:
                terms = gd_terms(robot, trajectory.q[a:b], trajectory.qd[a:b])
                tau_s = model.torque(trajectory.q[a:b], trajectory.qd[a:b],
                                     trajectory.qdd[a:b])
                errors.update(tau_s, terms.tau(trajectory.qdd[a:b]))
                out.write(a, {"tau_simplified": tau_s})
                bar.update(b - a)
        bar.close()
        error = errors.result()
        verification = verify(robot, trajectory.q, trajectory.qd) if check else {}
        ds = summary_dataset(robot, trajectory, ranking, choices, error, verification, settings)
        if formulations:
            from ..formulations.compare import formulations_dataset

            costs = formulations_dataset(robot, trajectory.q, trajectory.qd, trajectory.qdd)
            ds = ds.assign(costs.data_vars)
            ds.attrs.update(costs.attrs)
        if extra is not None:
            ds = ds.assign(extra.data_vars)
        ds = ds.assign(simp.data_vars)
        ds.attrs.update(simp.attrs)
        ds.to_netcdf(tmp, mode="a", engine="h5netcdf")
    object.__setattr__(model, "validation", error)
    return Analysis(dataset=ds, model=model, verification=verification)
