"""Sweeps: the dominance analysis of Sec. 3.4.1 over many trajectories and over payloads.

The chapter ranks the translational and rotational parts of D and h along one preplanned
trajectory and notes that "the above simplification depends on the specific trajectory being
considered" (Fu, Gonzalez & Lee 1987, Sec. 3.4.1). A sweep repeats the ranking over K
trajectories and reports, per ranked element (``"D11"`` .. ``"Dnn"``, ``"h1"`` .. ``"hn"``):

- the distribution of share_tran = sum|tran| / (sum|tran| + sum|rot|) over the trajectories
  (min, median, max);
- the fraction of trajectories in which each class (translational, rotational, both,
  negligible) holds;
- the choice of a *conservative merged* simplified model, valid for every trajectory of the
  sweep: a part of an element is dropped only where every trajectory's own simplified model
  drops it (:func:`merge_choices`).

The per-trajectory work (:func:`analyze_one`) is a pure function of small arguments, run in
batches on a dask.distributed cluster by :func:`run_sweep`. :func:`payload_sweep` repeats the
ranking of one trajectory for a range of loads fixed to the last link
(:func:`gd_analyze.core.robot.with_payload`).

dask is an optional dependency (the ``sweep`` extra); it is imported only by :func:`run_sweep`.
"""

from __future__ import annotations

import dataclasses
import contextlib
import datetime
import decimal
import hashlib
import math
import os
import re
import time
from pathlib import Path

import numpy as np

from ..core.dalembert import COMPILED_MIN_SETPOINTS, DEFAULT_CHUNK, GDTerms, gd_terms
from ..errors import InputError
from ..core.ranking import CLASSES, DEFAULT_DOMINANCE, DEFAULT_NEGLIGIBLE, element_labels, \
    rank_dominance
from ..core.simplified import TorqueErrorAccumulator, choice_masks, simplified_torque, torque_error

__all__ = [
    "dask_client", "sweep_payloads", "DEFAULT_BATCH_MAX", "random_trajectories", "analyze_one", "merge_choices", "run_sweep",
    "merged_model", "payload_sweep", "parse_range", "write_sweep",
]

#: Largest number of trajectories per dask task chosen automatically by :func:`run_sweep`.
DEFAULT_BATCH_MAX = 50
#: Tasks per worker aimed at by the automatic batch size (load balance vs. task overhead).
_TASKS_PER_WORKER = 4
#: At most this many input files are listed by name in the global attributes (all are in the
#: per-trajectory variables ``source`` and ``input_sha256``); HDF5 attributes stay small.
_MAX_LISTED_FILES = 20
#: Set points of consecutive trajectories whose G-D terms are computed in one call.
_GROUP_SETPOINTS = 4096
_RANDOM_SOURCE = re.compile(r"^random-(\d+)-(\d+)$")
_CHOICES = ("tran", "rot", "both", "none")
_MIXED_UNITS = "kg m2 (D) or N m (h)"
#: Scheduler options of the local cluster: no dashboard, and its small HTTP server (health
#: checks) on a free loopback port rather than the shared default 8787.
_NO_DASHBOARD = {"dashboard": False, "dashboard_address": "127.0.0.1:0"}


def _var(dims, data, units, long_name):
    return (dims, data, {"units": units, "long_name": long_name})


def _check_thresholds(dominance, negligible):
    if not 0.5 < float(dominance) <= 1.0:
        raise ValueError(f"the dominance threshold s must be in (0.5, 1], got {dominance}")
    if not float(negligible) >= 0.0:
        raise ValueError(f"the negligibility threshold e must be >= 0, got {negligible}")


def _check_trajectory(robot, trajectory):
    q = np.asarray(trajectory.q)
    N = np.asarray(trajectory.t).shape[0]
    for name in ("q", "qd", "qdd"):
        shape = np.shape(getattr(trajectory, name))
        if shape != (N, robot.n):
            raise ValueError(f"{trajectory.source or 'trajectory'}: {name} has shape {shape}, "
                             f"expected ({N}, {robot.n}) for {robot.name}")
    if q.shape[0] < 2:
        raise ValueError(f"{trajectory.source or 'trajectory'}: fewer than 2 set points")


# --------------------------------------------------------------------------------------------
# Trajectories
# --------------------------------------------------------------------------------------------

def random_trajectories(robot, k, seed=0, n_setpoints=31):
    """K random rest-to-rest quintic trajectories inside the joint limits.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints, position limits q_min, q_max [rad] and velocity and
        acceleration limits qd_max [rad/s], qdd_max [rad/s^2].
    k : int
        Number of trajectories K, >= 1.
    seed : int, optional
        Seed of the :class:`numpy.random.Generator` (``numpy.random.default_rng(seed)``).
    n_setpoints : int, optional
        Set points N per trajectory, >= 2 (31, as in Sec. 3.4.1).

    Returns
    -------
    list of Trajectory
        Trajectory i goes from a start to a goal drawn uniformly inside [q_min, q_max] (start
        and goal of every trajectory drawn in turn, shape (n,) each) in the shortest time
        within the velocity and acceleration limits
        (:func:`gd_analyze.io.trajectory.plan_quintic`); t (N,) [s], q, qd, qdd (N, n) [rad,
        rad/s, rad/s^2]; its ``source`` is ``"random-<seed>-<i>"`` and its ``sha256`` is "".

    Raises
    ------
    ValueError
        If k < 1, n_setpoints < 2, or the seed is not a non-negative integer.

    Notes
    -----
    The quintic's peak speed and acceleration are reached between set points in general, so
    the sampled |qd| and |qdd| stay within the limits. Source: Sec. 3.4.1 of Fu, Gonzalez &
    Lee (1987) ranks one preplanned PUMA 560 trajectory of 31 set points; a sweep repeats that
    over many.
    """
    from ..io.trajectory import plan_quintic

    k = int(k)
    if k < 1:
        raise ValueError(f"the number of trajectories must be >= 1, got {k}")
    if int(n_setpoints) < 2:
        raise ValueError("a trajectory needs at least 2 set points")
    if isinstance(seed, bool) or int(seed) != seed or int(seed) < 0:
        raise ValueError(f"the seed must be a non-negative integer, got {seed!r}")
    seed = int(seed)
    rng = np.random.default_rng(seed)
    lo, hi = np.asarray(robot.q_min, float), np.asarray(robot.q_max, float)
    out = []
    for i in range(k):
        q_start = rng.uniform(lo, hi)
        q_goal = rng.uniform(lo, hi)
        traj = plan_quintic(robot, q_start, q_goal, n_setpoints=int(n_setpoints))
        out.append(dataclasses.replace(traj, source=f"random-{seed}-{i}", sha256=""))
    return out


# --------------------------------------------------------------------------------------------
# One trajectory
# --------------------------------------------------------------------------------------------

def analyze_one(robot, trajectory, dominance=DEFAULT_DOMINANCE, negligible=DEFAULT_NEGLIGIBLE):
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
        - ``classes`` : tuple of str, length M, each one of :data:`gd_analyze.core.ranking.CLASSES`;
        - ``choices`` : dict, element label -> ``"tran"``, ``"rot"``, ``"both"`` or ``"none"``;
        - ``peaks`` : dict of ndarray, shape (M,): ``peak_tran``, ``peak_rot``, ``peak_total``
          and ``scale`` [kg m^2] for D, [N m] for h;
        - ``summary`` : dict: ``source`` (str), ``sha256`` (str), ``duration`` [s],
          ``setpoints`` N, ``q_start`` and ``q_goal`` (n,) [rad], ``tau_peak`` (n,) = peak
          |tau| [N m], and ``error``: the torque error of the trajectory's own simplified
          model as :func:`gd_analyze.core.simplified.torque_error` gives it.

    Raises
    ------
    ValueError
        If the trajectory does not fit the robot or the thresholds are out of range.

    Notes
    -----
    The same computation as :func:`gd_analyze.workflows.analyze.analyze` without the verification and
    the per-set-point dataset. Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987); terms from
    Eqs. (3.4-24) to (3.4-28).
    """
    _check_thresholds(dominance, negligible)
    _check_trajectory(robot, trajectory)
    return _rank_with_terms(trajectory, gd_terms(robot, trajectory.q, trajectory.qd),
                            dominance, negligible)


def _rank_with_terms(trajectory, terms, dominance, negligible):
    """The body of :func:`analyze_one`, given the trajectory's G-D terms."""
    tau = terms.tau(trajectory.qdd)
    ranking = rank_dominance(terms.D_tran, terms.D_rot, terms.h_tran, terms.h_rot, tau,
                             dominance=dominance, negligible=negligible)
    choices = ranking.choices()
    tau_s = simplified_torque(terms, choices, trajectory.qdd)
    t = np.asarray(trajectory.t, float)
    q = np.asarray(trajectory.q, float)
    return {
        "share_tran": np.asarray(ranking.share_tran, float),
        "classes": tuple(ranking.dominance),
        "choices": choices,
        "peaks": {"peak_tran": ranking.peak_tran, "peak_rot": ranking.peak_rot,
                  "peak_total": ranking.peak_total, "scale": ranking.scale},
        "summary": {
            "source": str(trajectory.source), "sha256": str(trajectory.sha256),
            "duration": float(t[-1] - t[0]), "setpoints": int(t.shape[0]),
            "q_start": q[0].copy(), "q_goal": q[-1].copy(),
            "tau_peak": np.abs(tau).max(axis=0), "error": torque_error(tau_s, tau),
        },
    }


def _error_stats(trajectory, terms, choices):
    """Accumulated torque error of a simplified model along one trajectory."""
    acc = TorqueErrorAccumulator(terms.c.shape[1])
    acc.update(simplified_torque(terms, choices, trajectory.qdd), terms.tau(trajectory.qdd))
    return {"peak": acc.peak.copy(), "sum_sq": acc.sum_sq.copy(), "count": acc.count,
            "peak_tau": acc.peak_tau.copy()}


def _batch_terms(robot, trajectories, max_setpoints=_GROUP_SETPOINTS):
    """Yield (trajectory, GDTerms) for each trajectory, in order.

    The terms of consecutive short trajectories are computed in one call of the numpy engine
    (at most max_setpoints set points at a time): for 31-set-point trajectories the per-call
    overhead of the array code dominates. Short means below COMPILED_MIN_SETPOINTS, i.e. the
    trajectories that gd_terms(engine="auto") alone would also give to the numpy engine, so
    the terms, to the last bit, and the shares of round-off-level elements are those of
    :func:`analyze_one`. Longer trajectories are computed one by one as analyze_one does."""
    group, size = [], 0

    def flush():
        if not group:
            return []
        q = np.concatenate([np.asarray(tr.q, float) for tr in group])
        qd = np.concatenate([np.asarray(tr.qd, float) for tr in group])
        terms = gd_terms(robot, q, qd, chunk=max(DEFAULT_CHUNK, q.shape[0]), engine="numpy")
        out, a = [], 0
        for tr in group:
            b = a + tr.q.shape[0]
            out.append((tr, GDTerms(terms.D_tran[a:b], terms.D_rot[a:b], terms.h_tran[a:b],
                                    terms.h_rot[a:b], terms.c[a:b])))
            a = b
        return out

    for tr in trajectories:
        N = np.shape(tr.q)[0]
        if N >= COMPILED_MIN_SETPOINTS:
            yield from flush()
            group, size = [], 0
            yield tr, gd_terms(robot, tr.q, tr.qd)
            continue
        if group and size + N > max_setpoints:
            yield from flush()
            group, size = [], 0
        group.append(tr)
        size += N
    yield from flush()


def _analyze_batch(robot, trajectories, dominance, negligible):
    return [_rank_with_terms(tr, terms, dominance, negligible)
            for tr, terms in _batch_terms(robot, trajectories)]


def _error_batch(robot, trajectories, choices):
    return [_error_stats(tr, terms, choices) for tr, terms in _batch_terms(robot, trajectories)]


# --------------------------------------------------------------------------------------------
# Merging
# --------------------------------------------------------------------------------------------

def merge_choices(choices_list):
    """Merge simplified models conservatively: drop a part only where every model drops it.

    Parameters
    ----------
    choices_list : sequence of dict
        One dict per trajectory: element label -> ``"tran"``, ``"rot"``, ``"both"`` or
        ``"none"``; all with the same labels.

    Returns
    -------
    dict
        Element label -> merged choice, in the label order of the first dict. With
        keep_tran = any choice in {tran, both} and keep_rot = any choice in {rot, both}:
        ``"both"`` if both are kept, ``"tran"`` or ``"rot"`` if only one, ``"none"`` if
        neither (the element is negligible in every trajectory).

    Raises
    ------
    ValueError
        If the sequence is empty, the dicts have different labels, or a choice is not one of
        the four.

    Notes
    -----
    The merged model keeps every part that any trajectory's own model keeps, so it is the
    smallest model of this form that is, element by element, at least as complete as each of
    them. Source: the simplified model of Sec. 3.4.1 of Fu, Gonzalez & Lee (1987), which
    "depends on the specific trajectory being considered".

    Examples
    --------
    >>> merge_choices([{"D11": "tran", "h1": "none"}, {"D11": "rot", "h1": "none"}])
    {'D11': 'both', 'h1': 'none'}
    """
    choices_list = list(choices_list)
    if not choices_list:
        raise ValueError("no simplified models to merge")
    labels = list(choices_list[0])
    keep_t = dict.fromkeys(labels, False)
    keep_r = dict.fromkeys(labels, False)
    for k, choices in enumerate(choices_list):
        if set(choices) != set(labels):
            diff = sorted(set(choices) ^ set(labels))
            raise ValueError(f"model {k} has other elements than model 0 (e.g. {diff[0]!r})")
        for label, ch in choices.items():
            if ch not in _CHOICES:
                raise ValueError(f"model {k}, element {label}: choice must be one of "
                                 f"{_CHOICES}, got {ch!r}")
            keep_t[label] |= ch in ("tran", "both")
            keep_r[label] |= ch in ("rot", "both")
    table = {(True, True): "both", (True, False): "tran", (False, True): "rot",
             (False, False): "none"}
    return {label: table[(keep_t[label], keep_r[label])] for label in labels}


# --------------------------------------------------------------------------------------------
# The sweep on dask.distributed
# --------------------------------------------------------------------------------------------

def _auto_batch(k, n_workers):
    per_task = math.ceil(k / (_TASKS_PER_WORKER * max(1, n_workers)))
    return int(min(DEFAULT_BATCH_MAX, max(1, per_task)))


def _inputs_attrs(trajectories):
    """Global attributes that identify the inputs: seed or files, and one digest of all."""
    sources = [str(tr.source) for tr in trajectories]
    shas = [str(tr.sha256) for tr in trajectories]
    digest = hashlib.sha256()
    for src, sha in zip(sources, shas):
        digest.update(f"{src}\t{sha}\n".encode())
    attrs = {"inputs_sha256": digest.hexdigest(), "trajectories": len(trajectories)}
    seeds = {m.group(1) for m in map(_RANDOM_SOURCE.match, sources) if m}
    n_random = sum(bool(_RANDOM_SOURCE.match(s)) for s in sources)
    files = [(s, h) for s, h in zip(sources, shas) if h]
    if n_random == len(sources):
        attrs["input_kind"] = "random"
    elif len(files) == len(sources):
        attrs["input_kind"] = "files"
    else:
        attrs["input_kind"] = "mixed"
    if n_random and len(seeds) == 1:
        attrs["seed"] = int(next(iter(seeds)))
    if files:
        listed = [f"{Path(s).name} sha256 {h}" for s, h in files[:_MAX_LISTED_FILES]]
        if len(files) > _MAX_LISTED_FILES:
            listed.append(f"... and {len(files) - _MAX_LISTED_FILES} more (see the variables "
                          "source and input_sha256)")
        attrs["input_files"] = "; ".join(listed)
    return attrs


@contextlib.contextmanager
def dask_client(scheduler=None, n_workers=None):
    """A dask.distributed client: connected to ``scheduler``, or on a new LocalCluster.

    Parameters
    ----------
    scheduler : str, optional
        Address of a running scheduler, e.g. ``"tcp://10.0.0.5:8786"``.
    n_workers : int, optional
        Workers of the LocalCluster started when no scheduler is given (one process and one
        thread each); default ``os.cpu_count() or 2``.

    Yields
    ------
    (distributed.Client, str)
        The client and a description of the cluster; both are closed on exit.

    Raises
    ------
    ImportError
        If dask.distributed is not installed (``pip install 'gd-analyze[sweep]'``).
    OSError
        If the scheduler cannot be reached.
    """
    try:
        from distributed import Client, LocalCluster
    except ImportError as exc:  # pragma: no cover - the extra is installed for the tests
        raise ImportError("sweeps need dask.distributed: pip install 'gd-analyze[sweep]'") \
            from exc
    cluster = None
    if scheduler is not None:
        client, how = Client(scheduler), "connected by address"
    else:
        import dask

        workers = int(n_workers) if n_workers else (os.cpu_count() or 2)
        # The workers' statistical profiler samples every thread's stack every 10 ms while
        # holding the GIL; for these many short numpy calls it costs about 40 % of the time,
        # so the cluster started here runs without it.
        with dask.config.set({"distributed.worker.profile.enabled": False}):
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                   dashboard_address=None, scheduler_kwargs=_NO_DASHBOARD)
        client, how = Client(cluster), "LocalCluster started by gd-analyze"
    try:
        yield client, how
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def sweep_payloads(robot, trajectories, masses, com=(0.0, 0.0, 0.0), inertia=(0.0, 0.0, 0.0),
                   dominance=DEFAULT_DOMINANCE, negligible=DEFAULT_NEGLIGIBLE, client=None):
    """Repeat a sweep for each load mass: how the classes over many trajectories move with it.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints, without the load.
    trajectories : sequence of Trajectory
        The sweep's trajectories.
    masses : sequence of float
        Load masses [kg], >= 0.
    com : array_like, shape (3,), optional
        Load centre of mass in link frame n [m].
    inertia : array_like, shape (3,), optional
        Load principal moments about its centre of mass [kg m^2].
    dominance, negligible : float, optional
        s and e of the ranking.
    client : distributed.Client
        The cluster to run on (see :func:`dask_client`).

    Returns
    -------
    xarray.Dataset
        Dims ``payload`` (P), ``element`` (M), ``class``, ``joint``: ``class_fraction``
        (payload, element, class), ``share_tran`` (payload, element) = the median over the
        trajectories, ``dominance`` (payload, element) = the most frequent class, ``choice``
        (payload, element) = the merged (conservative) choice, ``tau_peak`` (payload, joint) =
        peak |tau| over all trajectories [N m].

    Raises
    ------
    InputError
        If a mass or the load's inertia is invalid.
    ValueError
        As :func:`run_sweep`.

    Notes
    -----
    Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987), repeated for each load.
    """
    import xarray as xr

    from ..core.ranking import CLASSES, element_labels
    from ..core.robot import with_payload

    parts = []
    for mass in masses:
        ds = run_sweep(with_payload(robot, mass, com, inertia), trajectories, dominance,
                       negligible, client=client)
        frac = ds["class_fraction"].values
        parts.append((frac, ds["share_tran_median"].values,
                      np.array(CLASSES)[np.argmax(frac, axis=1)],
                      np.asarray(ds["merged_choice"].values, dtype=str),
                      ds["merged_error_tau_peak"].values))
    frac, share, dom, choice, tau = (np.array(x) for x in zip(*parts))
    n = robot.n

    def var(dims, data, units, long_name):
        return (dims, data, {"units": units, "long_name": long_name})

    return xr.Dataset(
        {"class_fraction": var(("payload", "element", "class"), frac, "1",
                               "fraction of the trajectories in each class"),
         "share_tran": var(("payload", "element"), share, "1",
                           "median translational share over the trajectories"),
         "dominance": var(("payload", "element"), dom.astype(str), "1",
                          "most frequent dominance class over the trajectories"),
         "choice": var(("payload", "element"), choice.astype(str), "1",
                       "merged (conservative) simplified-model choice"),
         "tau_peak": var(("payload", "joint"), tau, "N m",
                         "peak |tau| over all trajectories")},
        coords={"payload": ("payload", np.asarray(masses, float),
                            {"units": "kg", "long_name": "load mass on the last link"}),
                "element": ("element", np.array(element_labels(n), dtype=str),
                            {"units": "1", "long_name": "ranked element of D (i <= j) or h"}),
                "class": ("class", np.array(CLASSES, dtype=str),
                          {"units": "1", "long_name": "dominance class"}),
                "joint": ("joint", np.arange(1, n + 1), {"units": "1", "long_name": "joint"})},
        attrs={**_common_attrs(robot, dominance, negligible,
                               f"G-D dominance of {robot.name} vs payload over "
                               f"{len(list(trajectories))} trajectories"),
               "kind": "payload",
               "payload_com": np.asarray(com, dtype=float).reshape(3),
               "payload_com_units": "m",
               "payload_inertia": np.asarray(inertia, dtype=float).reshape(-1),
               "payload_inertia_units": "kg m2 (principal moments)"})


def run_sweep(robot, trajectories, dominance=DEFAULT_DOMINANCE, negligible=DEFAULT_NEGLIGIBLE,
              client=None, scheduler=None, batch=None, n_workers=None, settings=None,
              progress=False):
    """Rank K trajectories on a dask.distributed cluster and merge their simplified models.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints (may carry a payload, see
        :func:`gd_analyze.core.robot.with_payload`).
    trajectories : sequence of Trajectory
        K >= 1 trajectories, each t (N_k,) [s] and q, qd, qdd (N_k, n) [rad, rad/s, rad/s^2].
    dominance : float, optional
        s, in (0.5, 1]: the dominance threshold.
    negligible : float, optional
        e, >= 0: the negligibility threshold.
    client : distributed.Client, optional
        Run on this client's cluster (left open).
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
        or batch < 1.
    RuntimeError
        If no worker joins the cluster within 60 s.
    ImportError
        If dask.distributed is not installed (``pip install gd-analyze[sweep]``).

    Notes
    -----
    Two passes of tasks over the same scattered batches (the robot is scattered once to every
    worker): the first runs :func:`analyze_one` per trajectory; once all choices are known and
    merged (:func:`merge_choices`), the second computes the merged model's torque error along
    every trajectory. Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987).
    """
    t0 = time.perf_counter()
    trajectories = list(trajectories)
    if not trajectories:
        raise ValueError("a sweep needs at least one trajectory")
    _check_thresholds(dominance, negligible)
    for tr in trajectories:
        _check_trajectory(robot, tr)
    if batch is not None and int(batch) < 1:
        raise ValueError(f"batch must be >= 1, got {batch}")
    from distributed import as_completed
    from tqdm.auto import tqdm

    started = datetime.datetime.now(datetime.timezone.utc).replace(microsecond=0)
    own = contextlib.ExitStack()
    if client is None:
        client, how = own.enter_context(dask_client(scheduler, n_workers))
    else:
        how = "client given by the caller"
    try:
        try:
            client.wait_for_workers(1, timeout=60)
        except Exception as exc:  # distributed raises TimeoutError (type varies by version)
            raise RuntimeError(f"no dask worker joined the scheduler at "
                               f"{client.scheduler.address} within 60 s") from exc
        address = str(client.scheduler.address)
        n_w = len(client.scheduler_info().get("workers", {}))
        size = int(batch) if batch is not None else _auto_batch(len(trajectories), n_w)
        batches = [trajectories[a:a + size] for a in range(0, len(trajectories), size)]
        t_compute = time.perf_counter()
        robot_f = client.scatter(robot, broadcast=True, hash=False)
        batch_f = client.scatter(batches, hash=False)
        bar = tqdm(total=2 * len(batches), unit="task", disable=not progress,
                   desc="sweep: ranking", leave=False)

        def run(fn, *args):
            futures = {client.submit(fn, robot_f, b, *args, pure=False): k
                       for k, b in enumerate(batch_f)}
            out = [None] * len(futures)
            for fut in as_completed(list(futures)):
                out[futures[fut]] = fut.result()
                bar.update(1)
            return [item for part in out for item in part]

        results = run(_analyze_batch, float(dominance), float(negligible))
        merged = merge_choices([r["choices"] for r in results])
        bar.set_description("sweep: merged model")
        merged_stats = run(_error_batch, merged)
        bar.close()
        compute_s = time.perf_counter() - t_compute
        del robot_f, batch_f
    finally:
        own.close()
    ds = _sweep_dataset(robot, trajectories, results, merged, merged_stats, dominance,
                        negligible)
    ds.attrs.update({
        "scheduler_address": address, "n_workers": n_w, "batch_size": size,
        "n_tasks": 2 * len(batches),
        "cluster": how,
        "compute_s": round(compute_s, 4), "started": started.isoformat(),
    })
    for key, value in (settings or {}).items():
        ds.attrs[key] = _attr_value(value)
    ds.attrs["elapsed_s"] = round(time.perf_counter() - t0, 4)
    return ds


def _attr_value(value):
    if isinstance(value, (bool, np.bool_)):
        return int(value)
    if value is None:
        return ""
    if isinstance(value, (list, tuple)):
        arr = np.asarray(value)
        return arr if arr.dtype.kind in "iuf" else "; ".join(map(str, value))
    if isinstance(value, dict):
        return "; ".join(f"{k}={v}" for k, v in value.items())
    return value


def _common_attrs(robot, dominance, negligible, title):
    from .. import __version__
    from ..io.datasets import CONVENTIONS

    now = datetime.datetime.now(datetime.timezone.utc).replace(microsecond=0).isoformat()
    return {
        "Conventions": CONVENTIONS,
        "title": title,
        "source": f"gd-analyze {__version__}",
        "references": "Fu, Gonzalez & Lee (1987), Robotics, Sec. 3.4.1; Lee, Lee & Nigam (1983)",
        "history": f"{now} created by gd-analyze {__version__}",
        "gd_analyze_version": __version__,
        "robot": robot.name,
        "robot_description": robot.description,
        "robot_source": robot.source,
        "robot_sha256": robot.sha256,
        "gravity": np.asarray(robot.gravity, dtype=float),
        "gravity_units": "m s-2",
        "dominance_threshold": float(dominance),
        "negligible_threshold": float(negligible),
    }


def _element_coords(n):
    labels = element_labels(n)
    return {
        "element": ("element", np.array(labels, dtype=str),
                    {"long_name": "ranked element of D (i <= j) or h", "units": "1"}),
        "element_units": ("element",
                          np.array(["kg m2" if lab.startswith("D") else "N m" for lab in labels],
                                   dtype=str),
                          {"long_name": "units of the element", "units": "1"}),
        "joint": ("joint", np.arange(1, n + 1), {"long_name": "joint", "units": "1"}),
    }


def _sweep_dataset(robot, trajectories, results, merged, merged_stats, dominance, negligible):
    import xarray as xr

    n = robot.n
    labels = element_labels(n)
    K = len(results)
    share = np.array([r["share_tran"] for r in results])
    classes = np.array([r["classes"] for r in results], dtype=str)
    choice = np.array([[r["choices"][lab] for lab in labels] for r in results], dtype=str)
    peak_total = np.array([r["peaks"]["peak_total"] for r in results])
    summ = [r["summary"] for r in results]
    err = [s["error"] for s in summ]

    def per_joint(key):
        return np.array([e[key] for e in err], dtype=float)

    m_peak = np.array([s["peak"] for s in merged_stats])
    m_tau = np.array([s["peak_tau"] for s in merged_stats])
    with np.errstate(invalid="ignore", divide="ignore"):
        m_rel = np.where(m_tau > 0, m_peak / np.where(m_tau > 0, m_tau, 1.0), np.nan)
    all_peak = m_peak.max(axis=0)
    all_tau = m_tau.max(axis=0)
    all_rms = np.sqrt(np.sum([s["sum_sq"] for s in merged_stats], axis=0)
                      / max(1, sum(s["count"] for s in merged_stats)))
    with np.errstate(invalid="ignore", divide="ignore"):
        safe = np.where(all_tau > 0, all_tau, 1.0)
        all_rel_peak = np.where(all_tau > 0, all_peak / safe, np.nan)
        all_rel_rms = np.where(all_tau > 0, all_rms / safe, np.nan)
    fraction = np.stack([(classes == c).mean(axis=0) for c in CLASSES], axis=1)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)     # all-NaN columns
        s_min, s_med, s_max = (np.nanmin(share, axis=0), np.nanmedian(share, axis=0),
                               np.nanmax(share, axis=0))
    data_vars = {
        "share_tran": _var(("trajectory", "element"), share, "1",
                           "translational share sum|tran| / (sum|tran| + sum|rot|)"),
        "dominance": _var(("trajectory", "element"), classes, "1",
                          "dominance class (translational, rotational, both, negligible)"),
        "choice": _var(("trajectory", "element"), choice, "1",
                       "part kept by the trajectory's own simplified model "
                       "(tran, rot, both, none)"),
        "peak_total": _var(("trajectory", "element"), peak_total, _MIXED_UNITS,
                           "peak |translational + rotational| along the trajectory"),
        "source": _var(("trajectory",), np.array([s["source"] for s in summ], dtype=str), "1",
                       "trajectory source (file name or random-<seed>-<index>)"),
        "input_sha256": _var(("trajectory",), np.array([s["sha256"] for s in summ], dtype=str),
                             "1", "SHA-256 of the trajectory file (empty if generated)"),
        "duration": _var(("trajectory",), np.array([s["duration"] for s in summ]), "s",
                         "trajectory duration"),
        "setpoints": _var(("trajectory",), np.array([s["setpoints"] for s in summ]), "1",
                          "number of set points"),
        "q_start": _var(("trajectory", "joint"), np.array([s["q_start"] for s in summ]), "rad",
                        "joint position at the first set point"),
        "q_goal": _var(("trajectory", "joint"), np.array([s["q_goal"] for s in summ]), "rad",
                       "joint position at the last set point"),
        "tau_peak": _var(("trajectory", "joint"), np.array([s["tau_peak"] for s in summ]),
                         "N m", "peak |tau| of the full model along the trajectory"),
        "tau_error_peak": _var(("trajectory", "joint"), per_joint("peak_abs_error"), "N m",
                               "own simplified model: peak |tau_simplified - tau|"),
        "tau_error_rms": _var(("trajectory", "joint"), per_joint("rms_error"), "N m",
                              "own simplified model: RMS of |tau_simplified - tau|"),
        "tau_error_relative_peak": _var(("trajectory", "joint"),
                                        per_joint("relative_peak_error"), "1",
                                        "own simplified model: peak |tau_simplified - tau| / "
                                        "peak |tau|"),
        "tau_error_relative_rms": _var(("trajectory", "joint"), per_joint("relative_rms_error"),
                                       "1", "own simplified model: RMS |tau_simplified - tau| / "
                                            "peak |tau|"),
        "merged_tau_error_peak": _var(("trajectory", "joint"), m_peak, "N m",
                                      "merged model: peak |tau_merged - tau| along the "
                                      "trajectory"),
        "merged_tau_error_relative_peak": _var(("trajectory", "joint"), m_rel, "1",
                                               "merged model: peak |tau_merged - tau| / peak "
                                               "|tau| along the trajectory"),
        "class_fraction": _var(("element", "class"), fraction, "1",
                               "fraction of the trajectories in which the class holds"),
        "share_tran_min": _var(("element",), s_min, "1",
                               "smallest translational share over the trajectories"),
        "share_tran_median": _var(("element",), s_med, "1",
                                  "median translational share over the trajectories"),
        "share_tran_max": _var(("element",), s_max, "1",
                               "largest translational share over the trajectories"),
        "merged_choice": _var(("element",), np.array([merged[lab] for lab in labels], dtype=str),
                              "1", "part kept by the conservative merged model: a part is "
                                   "dropped only where every trajectory drops it"),
        "merged_error_peak": _var(("joint",), all_peak, "N m",
                                  "merged model: peak |tau_merged - tau| over all trajectories"),
        "merged_error_rms": _var(("joint",), all_rms, "N m",
                                 "merged model: RMS of |tau_merged - tau| over all set points "
                                 "of all trajectories"),
        "merged_error_tau_peak": _var(("joint",), all_tau, "N m",
                                      "peak |tau| over all trajectories"),
        "merged_error_relative_peak": _var(("joint",), all_rel_peak, "1",
                                           "merged model: peak error / peak |tau|, over all "
                                           "trajectories"),
        "merged_error_relative_rms": _var(("joint",), all_rel_rms, "1",
                                          "merged model: RMS error / peak |tau|, over all "
                                          "trajectories"),
    }
    coords = _element_coords(n)
    coords["trajectory"] = ("trajectory", np.arange(K),
                            {"long_name": "trajectory index", "units": "1"})
    coords["class"] = ("class", np.array(CLASSES, dtype=str),
                       {"long_name": "dominance class", "units": "1"})
    attrs = _common_attrs(robot, dominance, negligible,
                          f"G-D dominance sweep of {robot.name} over {K} trajectories")
    attrs.update(_inputs_attrs(trajectories))
    attrs["setpoints_total"] = int(sum(s["setpoints"] for s in summ))
    attrs["merge_rule"] = ("keep_tran = any trajectory keeps tran (tran or both); keep_rot = "
                           "any keeps rot (rot or both); merged = both/tran/rot/none")
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def _strings(values):
    return [v.decode() if isinstance(v, bytes) else str(v) for v in np.asarray(values).ravel()]


def merged_model(robot, sweep_ds):
    """The sweep's conservative merged simplified model.

    Parameters
    ----------
    robot : Robot
        The arm the sweep was run on (checked against the dataset's ``robot_sha256`` and
        number of elements).
    sweep_ds : xarray.Dataset
        A sweep dataset from :func:`run_sweep` (or read back with :func:`open_sweep`).

    Returns
    -------
    SimplifiedModel
        ``choices`` = the dataset's ``merged_choice``; ``validation`` = its torque error over
        all the sweep's trajectories, per joint: ``peak_abs_error``, ``rms_error``,
        ``peak_tau`` [N m] and ``relative_peak_error``, ``relative_rms_error`` (relative to
        the peak |tau| over all trajectories), plus ``trajectories`` (K) and ``setpoints``
        (total); ``trajectory_sha256`` = the digest of all inputs (``inputs_sha256``).

    Raises
    ------
    InputError
        If the dataset is not a sweep dataset, or was computed for another robot.

    Notes
    -----
    The validation is computed by :func:`run_sweep` along every trajectory and stored in the
    dataset; nothing is recomputed here. Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987).
    """
    from .. import __version__
    from ..core.simplified import SimplifiedModel

    needed = ("merged_choice", "merged_error_peak", "merged_error_rms", "merged_error_tau_peak",
              "merged_error_relative_peak", "merged_error_relative_rms")
    missing = [v for v in needed if v not in sweep_ds.variables]
    if missing:
        raise InputError("not a gd-analyze sweep dataset: missing " + ", ".join(missing))
    sha = sweep_ds.attrs.get("robot_sha256", "")
    if sha and robot.sha256 and sha != robot.sha256:
        raise InputError(f"the sweep was computed for robot {sweep_ds.attrs.get('robot')!r} "
                         f"(sha256 {sha[:12]}...), not for {robot.name!r} "
                         f"(sha256 {robot.sha256[:12]}...)")
    labels = _strings(sweep_ds["element"].values)
    if labels != element_labels(robot.n):
        raise InputError(f"the sweep's elements do not match a {robot.n}-joint robot")
    choices = dict(zip(labels, _strings(sweep_ds["merged_choice"].values)))
    choice_masks(choices, robot.n)
    validation = {
        "peak_abs_error": sweep_ds["merged_error_peak"].values.tolist(),
        "rms_error": sweep_ds["merged_error_rms"].values.tolist(),
        "peak_tau": sweep_ds["merged_error_tau_peak"].values.tolist(),
        "relative_peak_error": sweep_ds["merged_error_relative_peak"].values.tolist(),
        "relative_rms_error": sweep_ds["merged_error_relative_rms"].values.tolist(),
        "trajectories": int(sweep_ds.sizes.get("trajectory", 0)),
        "setpoints": int(sweep_ds.attrs.get("setpoints_total", 0)),
    }
    provenance = {"gd_analyze_version": __version__, "kind": "merged model of a sweep",
                  "sweep_version": str(sweep_ds.attrs.get("gd_analyze_version", "")),
                  "merge_rule": str(sweep_ds.attrs.get("merge_rule", "")),
                  "input_kind": str(sweep_ds.attrs.get("input_kind", ""))}
    if "seed" in sweep_ds.attrs:
        provenance["seed"] = int(sweep_ds.attrs["seed"])
    return SimplifiedModel(
        robot=robot, choices=choices,
        dominance_threshold=float(sweep_ds.attrs.get("dominance_threshold", DEFAULT_DOMINANCE)),
        negligible_threshold=float(sweep_ds.attrs.get("negligible_threshold",
                                                      DEFAULT_NEGLIGIBLE)),
        trajectory_sha256=str(sweep_ds.attrs.get("inputs_sha256", "")),
        validation=validation, provenance=provenance)


# --------------------------------------------------------------------------------------------
# Payload sweep
# --------------------------------------------------------------------------------------------

def parse_range(text, name="--payload-sweep"):
    """Parse ``"start:stop:step"`` into the values start, start + step, ..., stop (inclusive).

    Parameters
    ----------
    text : str
        E.g. ``"0:2.5:0.5"``; step > 0, stop >= start. The values are computed in decimal
        arithmetic from the strings, so ``"0:0.3:0.1"`` gives exactly [0.0, 0.1, 0.2, 0.3].
        stop is included when it lies on the grid; otherwise the last value is the largest
        grid value below it.
    name : str, optional
        The option or column named in error messages.

    Returns
    -------
    list of float
        At least one value.

    Raises
    ------
    InputError
        If the text is not three numbers separated by ``:``, a number is not finite, step is
        not positive, stop < start, or the range has more than 10,000 values.

    Examples
    --------
    >>> parse_range("0:2.5:0.5")
    [0.0, 0.5, 1.0, 1.5, 2.0, 2.5]
    """
    parts = str(text).split(":")
    if len(parts) != 3:
        raise InputError(f"expected START:STOP:STEP (e.g. 0:2.5:0.5), got {text!r}",
                         column=name)
    try:
        start, stop, step = (decimal.Decimal(p.strip()) for p in parts)
    except decimal.InvalidOperation:
        raise InputError(f"expected three numbers START:STOP:STEP, got {text!r}",
                         column=name) from None
    if not all(v.is_finite() for v in (start, stop, step)):
        raise InputError(f"START, STOP and STEP must be finite, got {text!r}", column=name)
    if step <= 0:
        raise InputError(f"STEP must be positive, got {text!r}", column=name)
    if stop < start:
        raise InputError(f"STOP must not be below START, got {text!r}", column=name)
    count = int((stop - start) // step) + 1
    if count > 10_000:
        raise InputError(f"the range {text!r} has {count} values (at most 10000)", column=name)
    return [float(start + k * step) for k in range(count)]


def payload_sweep(robot, trajectory, masses, com=(0.0, 0.0, 0.0), inertia=(0.0, 0.0, 0.0),
                  dominance=DEFAULT_DOMINANCE, negligible=DEFAULT_NEGLIGIBLE):
    """Rank one trajectory for a range of payloads fixed to the last link.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    trajectory : Trajectory
        t (N,) [s]; q, qd, qdd (N, n) [rad, rad/s, rad/s^2].
    masses : array_like, shape (P,)
        Payload masses [kg], >= 0, distinct (e.g. ``parse_range("0:2.5:0.5")``).
    com : array_like, shape (3,), optional
        Payload centre of mass in link frame n [m].
    inertia : array_like, shape (3,) or (3, 3), optional
        Payload inertia about its centre of mass, axes of link frame n [kg m^2].
    dominance : float, optional
        s, in (0.5, 1].
    negligible : float, optional
        e, >= 0.

    Returns
    -------
    xarray.Dataset
        Dims ``payload`` (P; coordinate = masses [kg]), ``element`` (M), ``joint`` (n):
        ``share_tran``, ``dominance``, ``choice`` and ``peak_total`` (payload, element);
        ``tau_peak`` = peak |tau| [N m] and ``tau_error_relative_peak`` of each payload's own
        simplified model (payload, joint). Units and long names on every variable; global
        attributes as for :func:`run_sweep`, plus the payload's com and inertia and the
        trajectory's source and SHA-256.

    Raises
    ------
    InputError
        If masses is empty, not 1-D, has duplicates, or a mass is negative or not finite, or
        the inertia is not symmetric positive semi-definite.
    ValueError
        If the trajectory does not fit the robot or a threshold is out of range.

    Notes
    -----
    Each payload is merged into link n by :func:`gd_analyze.core.robot.with_payload`; the load
    changes link n's mass, centre of mass and inertia and so the G-D terms. Source: Sec. 3.4.1
    of Fu, Gonzalez & Lee (1987) (the simplification "depends on the specific trajectory");
    the load enters the dynamics as in Sec. 3.1.
    """
    import xarray as xr

    from ..core.robot import with_payload

    masses = np.asarray(masses, dtype=float)
    if masses.ndim != 1 or masses.size == 0:
        raise InputError("the payload masses must be a non-empty list", column="--payload-sweep")
    if np.unique(masses).size != masses.size:
        raise InputError("the payload masses must be distinct", column="--payload-sweep")
    _check_thresholds(dominance, negligible)
    _check_trajectory(robot, trajectory)
    results = [analyze_one(with_payload(robot, m, com, inertia), trajectory, dominance,
                           negligible) for m in masses]
    n = robot.n
    labels = element_labels(n)
    I_p = np.asarray(inertia, dtype=float)
    I_p = np.diag(I_p) if I_p.shape == (3,) else I_p.reshape(3, 3)
    data_vars = {
        "share_tran": _var(("payload", "element"), np.array([r["share_tran"] for r in results]),
                           "1", "translational share sum|tran| / (sum|tran| + sum|rot|)"),
        "dominance": _var(("payload", "element"),
                          np.array([r["classes"] for r in results], dtype=str), "1",
                          "dominance class (translational, rotational, both, negligible)"),
        "choice": _var(("payload", "element"),
                       np.array([[r["choices"][lab] for lab in labels] for r in results],
                                dtype=str), "1",
                       "part kept by the simplified model (tran, rot, both, none)"),
        "peak_total": _var(("payload", "element"),
                           np.array([r["peaks"]["peak_total"] for r in results]), _MIXED_UNITS,
                           "peak |translational + rotational| along the trajectory"),
        "tau_peak": _var(("payload", "joint"),
                         np.array([r["summary"]["tau_peak"] for r in results]), "N m",
                         "peak |tau| of the full model along the trajectory"),
        "tau_error_relative_peak": _var(
            ("payload", "joint"),
            np.array([r["summary"]["error"]["relative_peak_error"] for r in results]), "1",
            "own simplified model: peak |tau_simplified - tau| / peak |tau|"),
    }
    coords = _element_coords(n)
    coords["payload"] = ("payload", masses, {"long_name": "payload mass on the last link",
                                             "units": "kg"})
    attrs = _common_attrs(robot, dominance, negligible,
                          f"G-D dominance of {robot.name} vs payload along "
                          f"{Path(str(trajectory.source)).name}")
    attrs.update({
        "payload_com": np.asarray(com, dtype=float).reshape(3),
        "payload_com_units": "m",
        "payload_inertia": I_p.ravel(),
        "payload_inertia_units": "kg m2 (3 x 3 tensor, row by row)",
        "input_file": Path(str(trajectory.source)).name,
        "input_path": str(trajectory.source),
        "input_sha256": str(trajectory.sha256),
        "derivatives": str(trajectory.derivatives),
        "setpoints": int(np.asarray(trajectory.t).shape[0]),
    })
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


# --------------------------------------------------------------------------------------------
# Files
# --------------------------------------------------------------------------------------------

def write_sweep(ds, path):
    """Write a sweep or payload-sweep dataset to HDF5/netCDF4 (h5netcdf), atomically.

    Parameters
    ----------
    ds : xarray.Dataset
        From :func:`run_sweep` or :func:`payload_sweep`.
    path : str or os.PathLike
        Destination, e.g. ``sweep.h5``; its folder must exist.

    Raises
    ------
    OSError
        If the file cannot be written.

    Notes
    -----
    The file is written under a temporary name beside ``path`` and renamed
    (:func:`gd_analyze.files.atomic_path`); 2-D float variables are compressed (zlib 4).
    """
    from ..files import atomic_path

    encoding = {name: {"zlib": True, "complevel": 4}
                for name, var in ds.data_vars.items() if var.dtype.kind == "f" and var.ndim >= 2}
    with atomic_path(path) as tmp:
        ds.to_netcdf(tmp, engine="h5netcdf", encoding=encoding, invalid_netcdf=False)
