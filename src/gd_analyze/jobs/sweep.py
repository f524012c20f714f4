"""Sweeps: the dominance analysis of Sec. 3.4.1 over many trajectories, on dask.distributed.

The chapter ranks the translational and rotational parts of D and h along one preplanned
trajectory and notes that "the above simplification depends on the specific trajectory being
considered" (Fu, Gonzalez & Lee 1987, Sec. 3.4.1). A sweep repeats the ranking over K
trajectories and reports, per ranked element (``"D11"`` .. ``"Dnn"``, ``"h1"`` .. ``"hn"``):

- the distribution of share_tran = sum|tran| / (sum|tran| + sum|rot|) over the trajectories
  (min, median, max);
- the fraction of trajectories in which each class (translational, rotational, both,
  negligible) holds;
- one merged simplified model for the whole sweep. By default (budget rule) it is the model
  of :func:`gd_analyze.jobs.sweep_merged.budget_sweep_model`: where the robot gives its
  limits, the main job's model proved within EPS x s_i over its joint-limit region, checked on
  every swept trajectory; else (or with ``guarantee="trajectory"``) the cheaper of the pruned
  recursive and explicit models, pruned on the peaks the workers compute per trajectory
  (``recursive_peaks=True``) and guaranteed within EPS x scale_i on every swept trajectory
  (:func:`gd_analyze.jobs.sweep_merged.with_budget_model` puts it into the dataset); with
  the chapter rule a part of an element is dropped only where every
  trajectory's own share-based model drops it
  (:func:`gd_analyze.simplify.simplified.merge_choices`), which bounds nothing.

The per-trajectory work (:func:`analyze_one`) is a pure function of small arguments, done for
a group of trajectories in one pass (:func:`gd_analyze.jobs.analyze.analysis_passes`, each
trajectory's result that of :func:`analyze_one`, bit for bit) in batches on a dask.distributed cluster (:mod:`gd_analyze.jobs.dask_cluster`) by
:func:`run_sweep`, or, for a small sweep (``in_process``), in one batch in the caller's process,
where a cluster's start would cost more than the ranking. The dataset's schema is in :mod:`gd_analyze.store.sweep_view`; the merged
models read from it are in :mod:`gd_analyze.jobs.sweep_merged`; random trajectories come
from :func:`gd_analyze.trajectory.planning.random_trajectories`; payload sweeps are in
:mod:`gd_analyze.jobs.payload`.
"""

from __future__ import annotations

import contextlib
import math
import pickle
import time
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from tqdm.auto import tqdm

from ..certify.regressor_bounds import joint_sum_arithmetic
from ..dynamics.base_parameters import base_parameters
from ..dynamics.dalembert import gd_terms
from ..ranking.ranking import DEFAULT_DOMINANCE, DEFAULT_NEGLIGIBLE
from ..simplify.simplified import TorqueErrorAccumulator, merge_choices, simplified_torque
from ..simplify.sweep_model import per_trajectory_errors
from ..store.names import SweepAttr as SA
from ..store.schema import attribute_value, utc_now
from ..store.sweep_view import embed_pair_peaks, sweep_dataset
from ..symbolic.pruning import stacked_peaks
from . import compile_ahead
from .analyze import analysis_pass, analysis_passes, stacked
from .dask_cluster import TASK_RETRIES, ClusterLost, cluster_failures, dask_client
from .options import AnalysisOptions

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr
    from distributed import Client

    from ..model.robot import Robot
    from ..simplify.choices import Motion
    from ..simplify.simplified import SimplifiedModel
    from ..trajectory.trajectory import Trajectory

__all__ = ["DEFAULT_BATCH_MAX", "ERRORS_SETPOINTS_MAX", "IN_PROCESS", "IN_PROCESS_SETPOINTS_MAX",
           "analyze_one", "run_sweep", "check_trajectory", "WorkerErrors"]

#: Largest number of trajectories per dask task chosen automatically by :func:`run_sweep`.
DEFAULT_BATCH_MAX = 50
#: Tasks per worker aimed at by the automatic batch size (load balance vs. task overhead).
_TASKS_PER_WORKER = 4
#: Set points of consecutive trajectories whose G-D terms are computed in one call.
_GROUP_SETPOINTS = 4096
#: Most set points of a sweep that the command line ranks in its own process when it is given
#: no dask scheduler and no number of workers (:func:`run_sweep`'s ``in_process``): up to
#: about 8,000 trajectories of 31 set points, ranked at roughly 1 ms each, the ranking costs
#: less than a LocalCluster's start and the numba warm-up of each of its workers.
IN_PROCESS_SETPOINTS_MAX = 2**18
#: What a sweep ranked in its own process ran on (its ``cluster`` attribute).
IN_PROCESS = "this process, without a dask cluster"
#: Most set points in one task of :class:`WorkerErrors` cutting the trajectories by itself
#: (about 38 MB of q, qd, qdd for 6 joints).
ERRORS_SETPOINTS_MAX = 2**18


def check_trajectory(robot: Robot, trajectory: Trajectory) -> None:
    """Check that a trajectory fits a robot.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    trajectory : Trajectory
        t (N,) [s]; q, qd, qdd must have shape (N, n).

    Raises
    ------
    ValueError
        If a shape does not match, or there are fewer than 2 set points.
    """
    N = np.asarray(trajectory.t).shape[0]
    for name in ("q", "qd", "qdd"):
        shape = np.shape(getattr(trajectory, name))
        if shape != (N, robot.n):
            raise ValueError(f"{trajectory.source or 'trajectory'}: {name} has shape {shape}, "
                             f"expected ({N}, {robot.n}) for {robot.name}")
    if N < 2:                            # q has shape (N, n) here
        raise ValueError(f"{trajectory.source or 'trajectory'}: fewer than 2 set points")


# --------------------------------------------------------------------------------------------
# One trajectory
# --------------------------------------------------------------------------------------------

def analyze_one(robot: Robot, trajectory: Trajectory, dominance: float = DEFAULT_DOMINANCE,
                negligible: float = DEFAULT_NEGLIGIBLE) -> dict[str, Any]:
    """Rank one trajectory and validate its own simplified model: the unit of work of a sweep.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    trajectory : Trajectory
        t (N,) [s]; q, qd, qdd (N, n) [rad, rad/s, rad/s^2].
    dominance : float, optional
        s, in (0.5, 1]: the dominance threshold.
    negligible : float, optional
        e, >= 0: the negligibility threshold.

    Returns
    -------
    dict
        Small and picklable (numpy arrays, strings, dicts), M = n (n + 1) / 2 + n elements:

        - ``share_tran`` : ndarray, shape (M,), the translational share in [0, 1] (NaN where
          both parts vanish);
        - ``classes`` : tuple of str, length M, each one of :data:`gd_analyze.ranking.ranking.CLASSES`;
        - ``choices`` : dict, element label -> ``"tran"``, ``"rot"``, ``"both"`` or ``"none"``;
        - ``peaks`` : dict of ndarray, shape (M,): ``peak_tran``, ``peak_rot``, ``peak_total``
          and ``scale`` [kg m^2] for D, [N m] for h;
        - ``summary`` : dict: ``source`` (str), ``sha256`` (str), ``duration`` [s],
          ``setpoints`` N, ``q_start`` and ``q_goal`` (n,) [rad], ``tau_peak`` (n,) = peak
          |tau| [N m], and ``error``: the torque error of the trajectory's own simplified
          model as :func:`gd_analyze.simplify.simplified.torque_error` gives it.

    Raises
    ------
    ValueError
        If the trajectory does not fit the robot or the thresholds are out of range.

    Notes
    -----
    The per-trajectory analysis of the main job, :func:`gd_analyze.jobs.analyze.analysis_pass`,
    without the verification and the per-set-point dataset. Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987); terms from
    Eqs. (3.4-24) to (3.4-28).
    """
    options = _ranking_only(dominance, negligible)
    check_trajectory(robot, trajectory)
    return _summary(trajectory, analysis_pass(robot, trajectory, options,
                                              chunk=trajectory.q.shape[0]))


def _summary(trajectory, result):
    """The small, picklable result of :func:`analyze_one` from the trajectory's analysis."""
    ranking = result.ranking
    t = np.asarray(trajectory.t, float)
    q = np.asarray(trajectory.q, float)
    return {
        "share_tran": np.asarray(ranking.share_tran, float),
        "classes": tuple(ranking.dominance),
        "choices": result.choices,
        "peaks": {"peak_tran": ranking.peak_tran, "peak_rot": ranking.peak_rot,
                  "peak_total": ranking.peak_total, "scale": ranking.scale},
        "summary": {
            "source": str(trajectory.source), "sha256": str(trajectory.sha256),
            "duration": float(t[-1] - t[0]), "setpoints": int(t.shape[0]),
            "q_start": q[0].copy(), "q_goal": q[-1].copy(),
            "tau_peak": np.abs(result.tau).max(axis=0), "error": result.error,
        },
    }


def _groups(trajectories, max_setpoints=_GROUP_SETPOINTS):
    """Yield consecutive groups of the trajectories, in order, each of at most max_setpoints
    set points (a longer trajectory alone).

    The G-D terms of a group are computed in one call of :func:`gd_terms`: for 31-set-point
    trajectories the per-call overhead dominates. The kernel computes every set point on its
    own, so the terms, to the last bit, and the shares of round-off-level elements are those
    of :func:`analyze_one`."""
    group, size = [], 0
    for tr in trajectories:
        N = np.shape(tr.q)[0]
        if group and size + N > max_setpoints:
            yield group
            group, size = [], 0
        group.append(tr)
        size += N
    if group:
        yield group


def _ranking_only(dominance, negligible):
    """The analysis of one swept trajectory: its ranking and masked model, nothing checked
    (the thresholds are, by :class:`~gd_analyze.jobs.options.AnalysisOptions`: a ValueError
    if either is out of range)."""
    return AnalysisOptions(dominance=dominance, negligible=negligible, verify=False,
                           formulations=False, simplify=None)


def _analyze_batch(robot, trajectories, dominance, negligible, base=None):
    options = _ranking_only(dominance, negligible)
    silent = tqdm(disable=True)     # one per task: a disabled bar per group costs more than
    #                                 ranking a short trajectory's set points
    # each group in one pass (analysis_passes): every trajectory's analysis_pass at once
    out = [_summary(tr, result) for group in _groups(trajectories)
           for tr, result in zip(group, analysis_passes(robot, group, options, silent))]
    if base is not None:        # the recursive model's peaks, per trajectory
        motion, ends = stacked(trajectories)
        peaks = stacked_peaks(robot, base, motion.q, motion.qd, motion.qdd,
                              np.diff(ends, prepend=0))
        for k, r in enumerate(out):
            r["recursive_peaks"] = tuple(p[k] for p in peaks)
    return out


def _error_batch(robot, trajectories, choices):
    """The accumulated torque error of one simplified model (``choices``) along each
    trajectory, a group of them at a time: ``peak``, ``sum_sq``, ``count``, ``peak_tau``."""
    out = []
    for group in _groups(trajectories):
        motion, ends = stacked(group)
        terms = gd_terms(robot, motion.q, motion.qd)
        acc = TorqueErrorAccumulator(terms.c.shape[1], trajectories=len(group))
        acc.update(simplified_torque(terms, choices, motion.qdd), terms.tau(motion.qdd),
                   ends=ends)
        out += [{"peak": p, "sum_sq": s, "count": c, "peak_tau": t} for p, s, c, t in zip(
            acc.peak, acc.sum_sq, acc.count.tolist(), acc.peak_tau)]
    return out


def _errors_task(packed, trajectories):
    """A task of :class:`WorkerErrors`: ``packed`` = the (model, reference) it serialized."""
    import cloudpickle

    model, reference = cloudpickle.loads(packed)
    return per_trajectory_errors(model, trajectories, reference)


# --------------------------------------------------------------------------------------------
# The sweep on dask.distributed
# --------------------------------------------------------------------------------------------

class WorkerErrors:
    """A merged model's errors along many trajectories, measured by the workers of a dask
    cluster: :func:`gd_analyze.simplify.sweep_model.per_trajectory_errors` in tasks over
    batches of trajectories, each returning four small arrays.

    Parameters
    ----------
    client : distributed.Client
        The sweep's client (left open).
    batch : int, optional
        Trajectories per task (>= 1). By default as many tasks as the cluster has workers,
        each with at most :data:`ERRORS_SETPOINTS_MAX` set points: the model is evaluated on
        all of a task's set points at once, in a few calls, so that more tasks than workers
        cost their round trips and the model's transfer and buy nothing.

    Attributes
    ----------
    tasks : int
        The tasks submitted so far.

    Notes
    -----
    Pass it as ``errors`` to :func:`gd_analyze.jobs.sweep_merged.budget_sweep_model`
    (:func:`gd_analyze.simplify.sweep_model.sweep_validation`). Each task carries the model,
    its reference and its batch, so that a task whose worker is lost runs again on another;
    a failure of the cluster raises :class:`~.dask_cluster.ClusterLost`.
    """

    def __init__(self, client: Client, batch: int | None = None) -> None:
        if batch is not None and int(batch) < 1:
            raise ValueError(f"batch must be >= 1, got {batch}")
        self.client, self.tasks = client, 0
        self.batch = None if batch is None else int(batch)

    def __call__(self, model: SimplifiedModel, trajectories: Sequence[Motion],
                 reference: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray] | None
                 = None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """:func:`~gd_analyze.simplify.sweep_model.per_trajectory_errors` of all
        ``trajectories`` (K of them), in the same order: peak |tau_s - tau|, the sum of its
        squares, peak |tau| (K, n) [N m, N^2 m^2, N m] and the set points (K,)."""
        trajectories = list(trajectories)
        n = model.robot.n
        if not trajectories:
            return np.zeros((0, n)), np.zeros((0, n)), np.zeros((0, n)), np.zeros(0, int)
        import cloudpickle  # dask's own serializer, a dependency of it

        batches = self._batches(trajectories)
        # the model (some thousand small objects) serialized once, not once per task; each
        # task still carries it, so that a task whose worker is lost runs again on another
        try:
            packed = cloudpickle.dumps((model, reference))
        except (TypeError, pickle.PicklingError):
            # a model or reference holding an object that cannot travel (a compiled function
            # of this process): measured here, one trajectory after another, as before
            return tuple(np.asarray(x) for x in  # type: ignore[return-value]
                         per_trajectory_errors(model, trajectories, reference))
        with cluster_failures(str(self.client.scheduler.address)):
            futures = [self.client.submit(_errors_task, packed, b, pure=False,
                                          retries=TASK_RETRIES) for b in batches]
            self.tasks += len(futures)
            parts = self.client.gather(futures)
        return tuple(np.concatenate([part[k] for part in parts])  # type: ignore[return-value]
                     for k in range(4))

    def _batches(self, trajectories):
        """The trajectories cut into consecutive batches, one per task."""
        if self.batch is not None:
            return [trajectories[a:a + self.batch]
                    for a in range(0, len(trajectories), self.batch)]
        counts = np.array([np.shape(t.q)[0] for t in trajectories])
        workers = max(1, len(self.client.scheduler_info().get("workers", {})))
        tasks = min(len(trajectories),
                    max(workers, math.ceil(int(counts.sum()) / ERRORS_SETPOINTS_MAX)))
        # cut where the running set point count crosses each task's equal share
        cuts = np.searchsorted(np.cumsum(counts), np.arange(1, tasks) * counts.sum() / tasks,
                               side="right")
        edges = np.unique(np.concatenate([[0], cuts, [len(trajectories)]]))
        return [trajectories[a:b] for a, b in zip(edges[:-1], edges[1:]) if b > a]


def run_sweep(robot: Robot, trajectories: Sequence[Trajectory],
              dominance: float = DEFAULT_DOMINANCE, negligible: float = DEFAULT_NEGLIGIBLE,
              client: Client | None = None, scheduler: str | None = None,
              batch: int | None = None, n_workers: int | None = None,
              settings: Mapping[str, Any] | None = None, progress: bool = False,
              recursive_peaks: bool = False, cluster: str | None = None,
              chapter_errors: bool = True,
              meanwhile: Callable[[], object] | None = None,
              in_process: bool = False) -> xr.Dataset:
    """Rank K trajectories on a dask.distributed cluster and merge their simplified models.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints (may carry a payload, see
        :func:`gd_analyze.model.robot.with_payload`).
    trajectories : sequence of Trajectory
        K >= 1 trajectories, each t (N_k,) [s] and q, qd, qdd (N_k, n) [rad, rad/s, rad/s^2].
    dominance : float, optional
        s, in (0.5, 1]: the dominance threshold.
    negligible : float, optional
        e, >= 0: the negligibility threshold.
    client : distributed.Client, optional
        Run on this client's cluster (left open).
    cluster : str, optional
        What ``client`` runs on, for the provenance (the description
        :func:`gd_analyze.jobs.dask_cluster.dask_client` yields); default "a client
        given by the caller".
    scheduler : str, optional
        Address of a running scheduler, e.g. ``"tcp://10.0.0.5:8786"``; a client is connected
        to it and closed at the end. Ignored if ``client`` is given.
    batch : int, optional
        Trajectories per task. By default about K / (4 workers), at most
        :data:`DEFAULT_BATCH_MAX`, so that 1,000 trajectories make tens of tasks, not 1,000.
    n_workers : int, optional
        Workers of the local cluster started when neither ``client`` nor ``scheduler`` is
        given (one process and one thread each); default ``os.cpu_count() or 2``.
    settings : dict, optional
        Extra global attributes (strings or numbers), e.g. the command line.
    progress : bool, optional
        Show a tqdm progress bar of the tasks on stderr.
    recursive_peaks : bool, optional
        Also compute, in the workers, each trajectory's peaks of the recursive model's
        (base parameter, part) contributions (:func:`gd_analyze.symbolic.pruning.stacked_peaks`),
        for the budget rule's merge (:mod:`gd_analyze.jobs.sweep_merged`): variables
        ``pair_tau_peak`` (trajectory, joint), ``pair_peak`` (trajectory, base_parameter, part,
        joint) and ``parameter_peak`` (trajectory, base_parameter, joint) [N m or N]
        (:func:`gd_analyze.store.sweep_view.embed_pair_peaks`). The chapter merge's error is
        then not measured (its variables are NaN; one pass of tasks, not two): the budget
        rule's model replaces it (:func:`gd_analyze.jobs.sweep_merged.with_budget_model`).
    chapter_errors : bool, optional
        Measure the chapter merge's error along every trajectory (a second pass of tasks);
        False where another merged model replaces it (its variables are then NaN, as with
        ``recursive_peaks``).
    meanwhile : callable, optional
        Called without arguments in this process once the ranking's tasks are submitted,
        while the workers run them (work that does not depend on the ranking, e.g. the
        merged model over a region, :func:`gd_analyze.jobs.sweep_merged.budget_region_model`);
        its errors pass unchanged, the tasks then dropped.
    in_process : bool, optional
        Rank in this process, without a dask cluster (``client``, ``scheduler`` and
        ``n_workers`` must then be None): the trajectories in one batch (``batch`` unless
        given), their G-D terms computed :data:`_GROUP_SETPOINTS` set points at a time,
        ``meanwhile`` called first. The provenance then says so: ``cluster`` =
        :data:`IN_PROCESS`, ``scheduler_address`` "none", ``n_workers`` and ``n_tasks`` 0.
        For a small sweep this is faster than a LocalCluster, whose start and per-worker
        warm-up cost more than the ranking itself (:data:`IN_PROCESS_SETPOINTS_MAX`).

    Returns
    -------
    xarray.Dataset
        The sweep dataset. Dims ``trajectory`` (K), ``element`` (M = n (n + 1) / 2 + n),
        ``joint`` (n), ``class`` (4). Per trajectory: ``share_tran``, ``dominance``,
        ``choice`` and ``peak_total`` (trajectory, element); ``source``, ``input_sha256``,
        ``duration`` [s], ``setpoints`` (trajectory); ``q_start``, ``q_goal`` [rad],
        ``tau_peak`` [N m], the own simplified model's ``tau_error_peak``, ``tau_error_rms``
        [N m], ``tau_error_relative_peak``, ``tau_error_relative_rms`` and the merged model's
        ``merged_tau_error_peak`` [N m] and ``merged_tau_error_relative_peak``
        (trajectory, joint). Envelope: ``class_fraction`` (element, class),
        ``share_tran_min``, ``share_tran_median``, ``share_tran_max`` (element). Merged model:
        ``merged_choice`` (element); its error over all trajectories ``merged_error_peak``,
        ``merged_error_rms``, ``merged_error_tau_peak`` [N m], ``merged_error_relative_peak``,
        ``merged_error_relative_rms`` (joint). Every variable has ``units`` and ``long_name``;
        the global attributes carry the provenance (CF-1.10, tool version, robot and its
        SHA-256, gravity, s, e, seed or input files and a SHA-256 of all inputs, elapsed time,
        workers, scheduler address, batch size).

    Raises
    ------
    ValueError
        If there are no trajectories, one does not fit the robot, a threshold is out of range,
        batch < 1, or ``in_process`` is asked for with a client, scheduler or workers.
    ClusterLost
        (An :class:`~gd_analyze.errors.InputError`: exit 2 on the command line.) If no worker
        joins the cluster within 60 s, the scheduler goes away, or a task's workers are lost
        more often than the scheduler allows (:func:`~.dask_cluster.cluster_failures`); a
        task whose worker is lost runs again on the workers that remain.
    ImportError
        If dask.distributed is missing from the environment (it is a dependency).

    Notes
    -----
    Two passes of tasks over the same batches (each task carries the robot and its batch, so
    that a task whose worker is lost runs again on another): the first gives :func:`analyze_one` of every trajectory (a group at a time in one pass); once all choices are known and
    merged (:func:`merge_choices`), the second computes the merged model's torque error along
    every trajectory (or, for another merged model, :class:`WorkerErrors` does, on the same
    cluster). Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987).
    """
    t0 = time.perf_counter()
    trajectories = list(trajectories)
    if not trajectories:
        raise ValueError("a sweep needs at least one trajectory")
    _ranking_only(float(dominance), float(negligible))      # the thresholds checked
    for tr in trajectories:
        check_trajectory(robot, tr)
    if batch is not None and int(batch) < 1:
        raise ValueError(f"batch must be >= 1, got {batch}")
    if in_process and (client is not None or scheduler is not None or n_workers is not None):
        raise ValueError("in_process runs without a dask cluster: give no client, scheduler "
                         "or n_workers")
    started = utc_now()
    compile_ahead.start(joint_sum_arithmetic(robot.n))    # a first run: on the other core
    base = base_parameters(robot) if recursive_peaks else None
    passes = 2 if base is None and chapter_errors else 1
    if in_process:
        t_compute = time.perf_counter()
        size = int(batch) if batch is not None else len(trajectories)
        batches = [trajectories[a:a + size] for a in range(0, len(trajectories), size)]
        if meanwhile is not None:
            meanwhile()
        results = [r for b in batches
                   for r in _analyze_batch(robot, b, float(dominance), float(negligible), base)]
        merged = merge_choices([r["choices"] for r in results])
        merged_stats = None if passes == 1 else [
            r for b in batches for r in _error_batch(robot, b, merged)]
        address, n_w, how, tasks = "none", 0, IN_PROCESS, 0
        compute_s = time.perf_counter() - t_compute
    else:
        results, merged, merged_stats, address, n_w, size, how, tasks, compute_s = _on_dask(
            robot, trajectories, float(dominance), float(negligible), client, cluster,
            scheduler, batch, n_workers, progress, base, passes, meanwhile)
    ds = sweep_dataset(robot, trajectories, results, merged, merged_stats, dominance,
                       negligible)
    if base is not None:
        ds = embed_pair_peaks(ds, base.names(), *(np.array([r["recursive_peaks"][k]
                                                            for r in results])
                                                  for k in range(3)))
    ds.attrs.update({
        SA.SCHEDULER_ADDRESS: address, SA.N_WORKERS: n_w, SA.BATCH_SIZE: size,
        SA.N_TASKS: tasks, SA.CLUSTER: how,
        SA.COMPUTE_S: round(compute_s, 4), SA.STARTED: started.isoformat(),
    })
    ds.attrs.update({key: attribute_value(v) for key, v in (settings or {}).items()})
    ds.attrs[SA.ELAPSED_S] = round(time.perf_counter() - t0, 4)
    return ds


def _on_dask(robot, trajectories, dominance, negligible, client, cluster, scheduler, batch,
             n_workers, progress, base, passes, meanwhile):
    """:func:`run_sweep`'s ranking (and the chapter merge's errors) in tasks on a dask
    cluster: (results, merged choices, merged errors or None, scheduler address, workers,
    batch size, the cluster in words, tasks, seconds computing once a worker joined)."""
    from distributed import as_completed

    with contextlib.ExitStack() as own:
        if client is None:
            client, how = own.enter_context(dask_client(scheduler, n_workers))
        else:
            how = cluster or "a client given by the caller"
        with cluster_failures(str(client.scheduler.address)):
            try:
                client.wait_for_workers(1, timeout=60)
            except Exception:  # distributed raises TimeoutError (type varies by version)
                raise ClusterLost("no dask worker joined the scheduler within 60 s",
                                  str(client.scheduler.address)) from None
            address = str(client.scheduler.address)
            n_w = len(client.scheduler_info().get("workers", {}))
            size = int(batch) if batch is not None else int(min(DEFAULT_BATCH_MAX, max(
                1, math.ceil(len(trajectories) / (_TASKS_PER_WORKER * max(1, n_w))))))
            batches = [trajectories[a:a + size] for a in range(0, len(trajectories), size)]
            t_compute = time.perf_counter()
            bar = tqdm(total=passes * len(batches), unit="task", disable=not progress,
                       desc="sweep: ranking", leave=False)

            def submit(fn, *args):
                # the robot and each batch go with their task (a few kB each), not scattered
                # ahead: data scattered to a worker is lost with it, a task's own arguments are
                # the scheduler's and go to the workers that remain
                return {client.submit(fn, robot, b, *args, pure=False,
                                      retries=TASK_RETRIES): k
                        for k, b in enumerate(batches)}

            def collect(futures):
                out = [None] * len(futures)
                # the client's own loop: without it, as_completed looks for dask's default
                # client, which a caller's client need not be
                for fut in as_completed(list(futures), loop=client.loop):
                    out[futures[fut]] = fut.result()
                    bar.update(1)
                return [item for part in out for item in part]

            ranking = submit(_analyze_batch, dominance, negligible, base)
        if meanwhile is not None:               # in this process, its errors its own
            meanwhile()
        with cluster_failures(address):
            results = collect(ranking)
            merged = merge_choices([r["choices"] for r in results])
            merged_stats = None             # the budget rule's model replaces the chapter merge
            if passes == 2:
                bar.set_description("sweep: merged model")
                merged_stats = collect(submit(_error_batch, merged))
            bar.close()
            compute_s = time.perf_counter() - t_compute
    return (results, merged, merged_stats, address, n_w, size, how,
            passes * len(batches), compute_s)
