"""The main job as a function: robot and trajectory in, verified analysis out.

robot model -> kinematics -> G-D terms -> verification -> ranking -> simplified model -> dataset.
The command line calls :func:`analyze_to_file` (or :func:`analyze`, in memory) and then writes
the remaining files; nothing here prints or exits.

There is one per-trajectory path (:func:`analysis_pass`): it computes the G-D terms once per
set point, chunk by chunk, and hands each chunk to the ranking, to the file, and to the samples
that the verification against Pinocchio and the comparison of the formulations read. The
simplified model's torque error needs the ranking of the whole trajectory first, so it is a
second pass over the same terms: held in memory when there is one chunk (or no file), read
back from the file otherwise. Nothing is computed twice. A sweep's many short trajectories go
through the same path in one pass (:func:`analysis_passes`): laid one after another, each
chunk's segments added to their own trajectories' ranking and error.
"""

from __future__ import annotations

import contextlib
import dataclasses
from collections.abc import Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from types import SimpleNamespace
from typing import TYPE_CHECKING, Any

import numpy as np

from .._version import VERSION as __version__
from ..dynamics import pinocchio as reference
from ..dynamics.compare import FORMULATIONS_MAX_SETPOINTS, formulations_dataset
from ..dynamics.dalembert import GDTerms, allocate_terms, gd_terms
from ..errors import InputError
from ..files import atomic_path
from ..model.limits import check_finite
from ..ranking.chapter_comparison import CHAPTER_CHOICES, S_VALUES, agreement_against_s, block_leads
from ..ranking.ranking import TermsRanking, is_chapter_puma
from ..simplify.budget import PartPeaks
from ..simplify.choices import recursive_choices
from ..simplify.form_choice import deploy
from ..simplify.simplified import SimplifiedModel, TorqueErrorAccumulator, simplified_torque
from ..store.datasets import SetpointWriter, summary_dataset, with_setpoints
from ..store.derivations import DERIVATIONS
from ..store.schema import append_dataset, var
from ..trajectory.trajectory import unwrapped
from .evaluate import round_off
from .options import AnalysisOptions
from .peak_jobs import start_peaks
from .simplified_dataset import deployment_dataset

if TYPE_CHECKING:                       # for the type hints only
    import os

    import xarray as xr
    from numpy.typing import NDArray
    from tqdm import tqdm

    from ..model.robot import Robot
    from ..trajectory.trajectory import Trajectory

__all__ = ["Analysis", "AnalysisPass", "analysis_pass", "analysis_passes", "analyze", "analyze_to_file", "verify",
           "VERIFY_TOLERANCE",
           "VERIFY_MAX_SETPOINTS", "STREAM_CHUNK", "CHUNK_JOINTS", "stream_chunk",
           "progress_bar", "stacked"]

#: Largest relative disagreement with Pinocchio accepted by :func:`verify`.
VERIFY_TOLERANCE = 1e-9
#: Set points checked against Pinocchio at most (evenly spread over the trajectory).
VERIFY_MAX_SETPOINTS = 2000
#: Set points per chunk when streaming to a file, for an arm of up to :data:`CHUNK_JOINTS`
#: joints (:func:`stream_chunk`).
STREAM_CHUNK = 65536
#: Joints up to which a chunk holds :data:`STREAM_CHUNK` set points.
CHUNK_JOINTS = 7
#: Seconds a run must last before its progress bar appears.
PROGRESS_DELAY = 1.0


@dataclass(frozen=True, eq=False)
class Analysis:
    """The result of :func:`analyze`.

    Attributes
    ----------
    dataset : xarray.Dataset
        Everything to store (see :mod:`gd_analyze.store.datasets`).
    model : SimplifiedModel
        The simplified model with its validation along the trajectory.
    verification : dict
        Largest relative disagreement with Pinocchio per term, the set points checked, and
        ``passed`` (bool).
    """

    dataset: xr.Dataset
    model: SimplifiedModel
    verification: dict


def progress_bar(enabled: bool = True, desc: str = "reading") -> tqdm:
    """A tqdm progress bar on stderr that counts set points.

    Parameters
    ----------
    enabled : bool, optional
        False: a bar that shows nothing.
    desc : str, optional
        The first phase's name.

    Returns
    -------
    tqdm.tqdm
        Appears after :data:`PROGRESS_DELAY` seconds; each phase calls ``reset(total=N)`` and
        ``set_description``.
    """
    from tqdm import tqdm

    return tqdm(total=None, unit=" set points", disable=not enabled,
                desc=desc, delay=PROGRESS_DELAY, leave=False)


def _subsample(N, max_setpoints):
    return np.unique(np.linspace(0, N - 1, min(N, max_setpoints)).round().astype(int))


def _concat(parts):
    return GDTerms.concatenate(parts) if parts else GDTerms(None, None, None, None, None)


def _verify_sample(robot, q, qd, terms, qdd=None):
    """The verification of :func:`verify` on given set points and their G-D terms."""
    ref = reference.reference_terms(robot, q, qd)
    scales = reference.natural_scales(robot, ref, qd, qdd)
    out, excess = {}, {}
    for name in ("D_tran", "D_rot", "h_tran", "h_rot", "D", "h", "c"):
        kind = "D" if name.startswith("D") else "tau"
        args = (getattr(terms, name), getattr(ref, name), scales[kind], scales[f"floor_{kind}"])
        out[f"max_rel_error_{name}"] = reference.measured_relative_error(*args)
        excess[f"max_rel_excess_{name}"] = reference.natural_relative_error(*args)
    worst = np.max(np.array(list(excess.values())))      # NaN propagates: a NaN fails
    out.update(excess)
    out.update(setpoints=int(q.shape[0]), tolerance=VERIFY_TOLERANCE,
               engine="pinocchio", passed=int(bool(worst <= VERIFY_TOLERANCE)))
    return out


def verify(robot: Robot, q: NDArray[np.float64], qd: NDArray[np.float64],
           terms: GDTerms | None = None, qdd: NDArray[np.float64] | None = None) -> dict[str, Any]:
    """Check G-D terms against Pinocchio's crba, nonLinearEffects and generalized gravity.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q, qd : ndarray, shape (N, n)
        Joint positions [rad] and velocities [rad/s].
    terms : GDTerms, optional
        The G-D terms at those N states; computed at the checked set points if not given
        (at most :data:`VERIFY_MAX_SETPOINTS`, evenly spread).
    qdd : ndarray, shape (N, n), optional
        Joint accelerations [rad/s^2], for the torque scale (zero if not given).

    Returns
    -------
    dict
        ``max_rel_error_<term>`` for D_tran, D_rot, h_tran, h_rot, D, h and c: the largest
        difference from Pinocchio relative to the element's natural scale over the checked set
        points, as measured, round-off included
        (:func:`gd_analyze.dynamics.pinocchio.measured_relative_error`): sqrt(D_ii D_jj)
        for D_ij, peak |tau_i| for h_i and c_i, with an absolute floor of a few machine epsilons
        times the overall scale; ``max_rel_excess_<term>``: the same past that floor
        (:func:`~gd_analyze.dynamics.pinocchio.natural_relative_error`), what the check
        judges; ``setpoints`` checked, ``tolerance`` and ``passed`` (1 if every excess is
        within tolerance, else 0; a NaN anywhere fails).

    Notes
    -----
    The split parts are checked against the half-models with zero rotational inertia and with
    zero mass (see :mod:`gd_analyze.dynamics.pinocchio`).
    """
    idx = _subsample(q.shape[0], VERIFY_MAX_SETPOINTS)
    sample = gd_terms(robot, q[idx], qd[idx]) if terms is None else terms.rows(idx)
    return _verify_sample(robot, q[idx], qd[idx], sample, None if qdd is None else qdd[idx])


@dataclass(frozen=True, eq=False)
class AnalysisPass:
    """What :func:`analysis_pass` produced for one trajectory.

    Attributes
    ----------
    ranking : Ranking
        The dominance of each of the M = n (n + 1) / 2 + n elements.
    choices : dict
        Element label -> the part the simplified model keeps.
    error : dict
        The simplified model's torque error per joint
        (:func:`gd_analyze.simplify.simplified.torque_error`).
    verification : dict
        As :func:`verify` returns it; empty if not checked.
    costs : xarray.Dataset or None
        :func:`gd_analyze.dynamics.compare.formulations_dataset`, if asked for.
    terms : GDTerms or None
        The G-D terms at all N set points, held when there is no file to read them back from
        or when they are one chunk (None when they were streamed in chunks).
    tau, tau_simplified : ndarray, shape (N, n) or None
        Full and simplified torques [N m], held likewise.
    model : SimplifiedModel or None
        The explicit simplified model, when asked for (``simplify``).
    simplified : xarray.Dataset or None
        Its bound, cost table and ladder (:func:`gd_analyze.jobs.simplified_dataset.simplified_dataset`).
    chapter_error : dict or None
        For the chapter's PUMA 560: the torque error of the chapter's own simplified model
        (:data:`gd_analyze.ranking.chapter_comparison.CHAPTER_CHOICES`), as ``error``.
    """

    ranking: object
    choices: dict
    error: dict
    verification: dict
    costs: object
    terms: object = None
    tau: object = None
    tau_simplified: object = None
    model: object = None
    simplified: object = None
    chapter_error: object = None


def stream_chunk(n: int) -> int:
    """Set points per chunk for an arm of n joints.

    A chunk's terms hold n^2 entries of D_tran, D_rot and D per set point, so a larger arm's
    chunk holds fewer set points: as many entries as :data:`STREAM_CHUNK` set points of a
    :data:`CHUNK_JOINTS`-joint arm (about 25 MB an array), and at least 4,096 set points.

    Parameters
    ----------
    n : int
        Joints.

    Returns
    -------
    int

    Examples
    --------
    >>> stream_chunk(6), stream_chunk(7), stream_chunk(15)
    (65536, 65536, 14272)
    """
    return max(4096, min(STREAM_CHUNK, STREAM_CHUNK * CHUNK_JOINTS ** 2 // max(int(n), 1) ** 2))


def analysis_pass(robot: Robot, trajectory: Trajectory, options: AnalysisOptions | None = None,
                  provenance: Mapping[str, Any] | None = None, chunk: int | None = None,
                  writer: SetpointWriter | None = None, progress: bool | tqdm = False
                  ) -> AnalysisPass:
    """The one per-trajectory analysis: the G-D terms once per set point, then everything else.

    Pass 1 computes the terms chunk by chunk and feeds the ranking, the writer and the samples
    for the verification and the formulations; pass 2 feeds the simplified model's torque
    error with the same terms (held in memory, or read back from the writer's file).

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    trajectory : Trajectory
        q, qd, qdd of shape (N, n) [rad, rad/s, rad/s^2].
    options : AnalysisOptions, optional
        s and e of the ranking; whether to verify against Pinocchio (on at most
        :data:`VERIFY_MAX_SETPOINTS` set points) and to compare L-E, N-E, G-D and Pinocchio
        (on at most :data:`gd_analyze.dynamics.compare.FORMULATIONS_MAX_SETPOINTS`);
        ``options.simplify``: build the simplified model after pass 1 and take its
        torque in pass 2; with ``simplify=None`` the model is the ranking's choices, masked
        (as in a sweep's per-trajectory models). Default :class:`AnalysisOptions`.
    provenance : dict, optional
        The simplified model's provenance.
    chunk : int, optional
        Set points per chunk; default :func:`stream_chunk` of the arm's joints.
    writer : SetpointWriter, optional
        Receives the per-set-point variables; with more than one chunk, pass 2 reads the terms
        back from it instead of holding them.
    progress : bool or tqdm.tqdm, optional
        Show a tqdm progress bar on stderr, or use the one given (the command line's, which
        also covers reading and the report). It counts set points: it restarts at 0 of N for
        each pass, named "G-D terms" and "simplified model".

    Returns
    -------
    AnalysisPass

    Raises
    ------
    ValueError
        If the trajectory does not fit the robot or the thresholds are out of range; an
        InputError naming the robot's file if every link has zero mass and zero inertia (no
        dynamics: every element would rank as negligible, every torque 0).

    Notes
    -----
    Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987); terms from Eqs. (3.4-24) to (3.4-28).
    """
    _check_masses(robot)
    chunk = stream_chunk(robot.n) if chunk is None else chunk
    options = AnalysisOptions() if options is None else options
    args = (robot, trajectory, options, provenance, chunk, writer, progress, None)
    if options.simplify is None:
        return _analysis_pass(*args, background=None)[0]
    # the simplification's compiled peak passes need only the trajectory: they run in threads
    # (the kernels release the GIL) beside the pass over the G-D terms, always
    with ThreadPoolExecutor(max_workers=2, thread_name_prefix="gd-peaks") as pool:
        background = start_peaks(pool, robot, trajectory, options.simplify, DERIVATIONS)
        try:
            return _analysis_pass(*args, background=background)[0]
        finally:
            for job in background.values():
                job.cancel()


def analysis_passes(robot: Robot, trajectories: Sequence[Trajectory], options: AnalysisOptions,
                    progress: bool | tqdm = False) -> list[AnalysisPass]:
    """:func:`analysis_pass` of K trajectories in one pass: a sweep's many short ones.

    The trajectories' set points are taken one after another as one chunk, their G-D terms
    computed in one call of :func:`gd_analyze.dynamics.dalembert.gd_terms`; the ranking, the
    simplified model's torque and its error are accumulated per trajectory over its own
    segment of the chunk (:class:`gd_analyze.ranking.ranking.RankingAccumulator` with
    ``trajectories``), so each result is, bit for bit, the trajectory's own
    :func:`analysis_pass` in one chunk, at the cost of one pass instead of K.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    trajectories : sequence of Trajectory
        K >= 1 trajectories, each q, qd, qdd of shape (N_k, n), N_k >= 1
        [rad, rad/s, rad/s^2].
    options : AnalysisOptions
        s and e of the ranking; nothing verified, compared or built (``verify`` and
        ``formulations`` False, ``simplify`` None: each trajectory's model is its ranking's
        choices, masked), as a sweep's.
    progress : bool or tqdm.tqdm, optional
        As for :func:`analysis_pass`.

    Returns
    -------
    list of AnalysisPass
        K of them, in order: ``ranking``, ``choices``, ``error``, and ``terms``, ``tau`` and
        ``tau_simplified`` (views of the trajectory's rows); ``verification`` empty.

    Raises
    ------
    ValueError
        If there are no trajectories, one has no set points, the options ask for a check, a
        comparison or a model, or the thresholds are out of range; an InputError as for
        :func:`analysis_pass` for an arm without mass and inertia.

    Notes
    -----
    Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987); terms from Eqs. (3.4-24) to (3.4-28).
    """
    _check_masses(robot)
    if options.verify or options.formulations or options.simplify is not None:
        raise ValueError("analysis_passes ranks only: no verify, formulations or simplify")
    motion, ends = stacked(trajectories)
    return _analysis_pass(robot, motion, options, None, len(motion.q), None, progress, ends,
                          background=None)


def stacked(trajectories: Sequence[Trajectory]) -> tuple[SimpleNamespace, NDArray[np.int64]]:
    """K trajectories laid one after another, as :func:`analysis_passes` reads them.

    Parameters
    ----------
    trajectories : sequence of Trajectory
        K trajectories, each q, qd, qdd of shape (N_k, n) [rad, rad/s, rad/s^2].

    Returns
    -------
    motion : types.SimpleNamespace
        ``q``, ``qd``, ``qdd``: the trajectories' rows one after another, shape (sum N_k, n),
        as floats.
    ends : ndarray of int, shape (K,)
        Where each trajectory's rows end in them.
    """
    motion = SimpleNamespace(**{k: np.concatenate([getattr(tr, k) for tr in trajectories],
                                                  dtype=float) for k in ("q", "qd", "qdd")})
    return motion, np.cumsum([len(tr.q) for tr in trajectories])


def _check_masses(robot):
    """Refuse an arm whose links all have zero mass and inertia (a file's typo, or a URDF
    without any <inertial>): its terms are 0, its ranking meaningless."""
    if not (robot.mass.any() or robot.inertia.any()):
        raise InputError("every link has zero mass and inertia: no dynamics", robot.source)


def _analysis_pass(robot, trajectory, options, provenance, chunk, writer, progress, ends,
                   background):
    """:func:`analysis_pass` with the simplification's peak passes started (``background``):
    a list of one pass, or with ``ends`` (where each of K trajectories laid one after another
    ends, as :func:`analysis_passes` lays them out) of K, one per trajectory."""

    check, formulations, simplify = options.verify, options.formulations, options.simplify
    q, qd, qdd = trajectory.q, trajectory.qd, trajectory.qdd
    N, n = q.shape
    chunk = max(1, int(chunk))
    ranges = [(a, min(a + chunk, N)) for a in range(0, N, chunk)]
    ends = np.array([N] if ends is None else ends, np.int64)
    hold = writer is None or len(ranges) == 1
    idx_verify = _subsample(N, VERIFY_MAX_SETPOINTS) if check else np.zeros(0, int)
    idx_form = _subsample(N, FORMULATIONS_MAX_SETPOINTS) if formulations else np.zeros(0, int)
    # the set points where a recursive model's choice per element is read (kept from the pass:
    # the terms are computed once)
    idx_choice = _subsample(N, _CHOICE_SETPOINTS) if simplify is not None else np.zeros(0, int)
    sample_idx = np.union1d(np.union1d(idx_verify, idx_form), idx_choice).astype(int)
    samples, held, held_tau = [], [], []
    ranker = TermsRanking(robot, ends)
    parts = PartPeaks(n) if simplify is not None else None
    # the chapter's own simplified model (its classes of Figs. 3.10-3.11), measured in the
    # same pass on its PUMA 560 when a model is built (the main job; not a sweep's ranking)
    chapter = (TorqueErrorAccumulator(n)
               if simplify is not None and is_chapter_puma(robot.name, n) else None)
    own = not hasattr(progress, "update")
    bar = progress_bar(bool(progress)) if own else progress
    bar.reset(total=N)
    bar.set_description("G-D terms")
    # streamed chunks (not held) reuse one set of output buffers: no fresh pages per chunk
    buf = None if hold else allocate_terms(min(chunk, N), n)
    for a, b in ranges:
        terms = gd_terms(robot, q[a:b], qd[a:b], out=buf)
        D, h = terms.D, terms.h                 # formed once: for tau and the file
        tau = terms.tau(qdd[a:b], D=D, h=h)
        for name in ("D_tran", "D_rot", "h_tran", "h_rot", "c"):   # finite: inputs within LIMITS
            check_finite(name, getattr(terms, name))
        check_finite("tau", tau)
        ranker.update(terms, tau, qdd[a:b], at=a)
        if parts is not None:
            parts.update(terms.D_tran, terms.D_rot, terms.h_tran, terms.h_rot, qdd[a:b], tau)
        if chapter is not None:
            chapter.update(simplified_torque(terms, CHAPTER_CHOICES, qdd[a:b]), tau)
        rows = sample_idx[(sample_idx >= a) & (sample_idx < b)] - a
        if rows.size:
            samples.append(terms.rows(rows))
        if writer is not None:
            writer.write(a, {"D_tran": terms.D_tran, "D_rot": terms.D_rot, "D": D,
                             "h_tran": terms.h_tran, "h_rot": terms.h_rot, "h": h,
                             "c": terms.c, "tau": tau,
                             **({} if terms.tau_f is None else {"tau_f": terms.tau_f})})
        if hold:
            held.append(terms)
            held_tau.append(tau)
        bar.update(b - a)
    rankings = ranker.results(dominance=options.dominance, negligible=options.negligible)
    ranking = rankings[0]
    each_choices = [r.choices() for r in rankings]
    choices = each_choices[0]
    model = simplified = other = None
    if simplify is not None:
        deployed = deploy(robot, trajectory, ranking, parts, simplify, provenance or {},
                          background["recursive"], background.get("explicit"), DERIVATIONS,
                          background.get("region"))
        model, other = deployed.model, deployed.other
        choices = model.choices
    bar.reset(total=N)
    bar.set_description("simplified model")
    errors = TorqueErrorAccumulator(n, trajectories=len(ends))
    # the model of the other rule, compared side by side: its error in the same pass
    other_errors = None if other is None else TorqueErrorAccumulator(n)
    tau_s_all = []
    # the recursive ladder's rungs, measured against this pass's tau and the deployed model's
    meter = deployed.meter() if simplify is not None else None
    # the other rule's model and the ladder's rungs run chunk by chunk on threads of their own
    # beside the deployed model (numpy releases the GIL in its loops); their chunks keep their
    # order, one in flight each (a pool starts its thread with its first job: none if unused)
    with (ThreadPoolExecutor(max_workers=1, thread_name_prefix="gd-other") as side,
          ThreadPoolExecutor(max_workers=1, thread_name_prefix="gd-ladder") as rungs):
        pending = measuring = None
        for k, (a, b) in enumerate(ranges):
            if hold:
                terms, tau = held[k], held_tau[k]
            else:       # a built model needs only tau; the ranking's masks need the terms
                terms = None if model is not None else GDTerms(
                    *(writer.read(name, a, b) for name in ("D_tran", "D_rot", "h_tran",
                                                           "h_rot", "c")),
                    robot.armature if np.any(robot.armature) else None,
                    writer.read("tau_f", a, b) if "tau_f" in writer.variables else None)
                tau = writer.read("tau", a, b)
            if other is not None:
                if pending is not None:
                    pending.result()
                # the other rule's model's torque error on this chunk, beside the next step
                pending = side.submit(lambda x, tau: other_errors.update(other.torque(*x), tau),
                                      (q[a:b], qd[a:b], qdd[a:b]), tau)
            tau_s = simplified_torque(terms, each_choices, qdd[a:b], ends, at=a) \
                if model is None else model.torque(q[a:b], qd[a:b], qdd[a:b])
            errors.update(tau_s, tau, ends, at=a)
            if meter is not None:
                if measuring is not None:
                    measuring.result()
                measuring = rungs.submit(meter.update, q[a:b], qd[a:b], qdd[a:b], tau, tau_s)
            if writer is not None:
                writer.write(a, {"tau_simplified": tau_s})
            if hold:                        # in memory too: the report reads them from there
                tau_s_all.append(tau_s)
            bar.update(b - a)
        for job in (pending, measuring):
            if job is not None:
                job.result()
    if own:
        bar.close()
    if simplify is not None:
        simplified = deployment_dataset(
            deployed, trajectory, None if other_errors is None else other_errors.result())
    sample = _concat(samples)
    at = {i: k for k, i in enumerate(sample_idx)}

    def sampled(idx):               # the terms kept from pass 1 at these set points
        return sample.rows([at[i] for i in idx])

    verification = {} if not check else _verify_sample(
        robot, q[idx_verify], qd[idx_verify], sampled(idx_verify), qdd[idx_verify])
    costs = None if not formulations else formulations_dataset(
        robot, q[idx_form], qd[idx_form], qdd[idx_form], gd=sampled(idx_form))
    if model is not None and model.recursive is not None:
        choices = recursive_choices(model, q[idx_choice], qd[idx_choice], sampled(idx_choice),
                                    ranking)
    # each trajectory's rows of what was held (views)
    whole = hold and (_concat(held), np.concatenate(held_tau), np.concatenate(tau_s_all))
    return [AnalysisPass(
        ranking=ranking, choices=choices if len(ends) == 1 else own, error=error,
        verification=verification, costs=costs, model=model, simplified=simplified,
        **({} if not whole else {"terms": whole[0].rows(slice(a, b)), "tau": whole[1][a:b],
                                     "tau_simplified": whole[2][a:b]}),
        chapter_error=None if chapter is None else _marked([chapter.result()], robot)[0])
        for ranking, own, error, a, b in zip(rankings, each_choices, _marked(
            errors.results(), robot), [0, *ends[:-1].tolist()], ends.tolist())]


#: Set points (evenly spread) on which a recursive model's D_s and h_s are compared with D
#: and h, element by element, for the stored ``choice``.
_CHOICE_SETPOINTS = 64


def _marked(errors, robot):
    """The torque errors (of one trajectory each) with ``round_off`` per joint: True where its
    peak is floating-point round-off by the reports' one rule
    (:func:`gd_analyze.jobs.evaluate.round_off` of peak |tau_i| and of the arm's), so
    the stored numbers are never read as data."""

    tau = np.array([error["peak_tau"] for error in errors], float).reshape(len(errors), -1)
    peak = np.array([error["peak_abs_error"] for error in errors], float).reshape(tau.shape)
    off = round_off(peak, tau, tau, robot).tolist()
    return [{**error, "round_off": each} for error, each in zip(errors, off)]


def _provenance(trajectory, settings):
    return {"gd_analyze_version": __version__, "trajectory_file": trajectory.source,
            "derivatives": trajectory.derivatives, **(settings or {})}


def _with(ds, extra):
    """The dataset with another's variables and attributes (None: as it is)."""
    if extra is not None:
        ds = ds.assign(extra.data_vars)
        ds.attrs.update(extra.attrs)
    return ds


def _with_chapter(ds, error):
    """The dataset with the chapter's conclusions counted (its PUMA 560 only): its own
    simplified model's error, the agreement with its classes against s, and which part leads
    the arm block and the wrist (:mod:`gd_analyze.ranking.chapter_comparison`)."""
    if error is None:
        return ds
    labels = [str(v) for v in ds["element"].values]
    share = np.asarray(ds["share_tran"].values, float)
    negligible = [str(v) == "negligible" for v in ds["dominance"].values]
    s = float(ds.attrs["dominance_threshold"])
    grid, agree, compared = agreement_against_s(labels, share, negligible,
                                                tuple(sorted(set(S_VALUES) | {s})))
    blocks = block_leads(labels, share, negligible, len(ds["joint"]))

    out = ds.assign_coords(chapter_threshold=var(
        ("chapter_threshold",), grid, "1", "dominance threshold s at which the chapter's "
                                           "classes are compared"))
    out = out.assign({
        "chapter_agreement": var(("chapter_threshold",), agree.astype(np.int32), "1",
                                 "elements whose class at s equals the chapter's"),
        "chapter_model_choice": var(("element",), np.array(
            [CHAPTER_CHOICES.get(k, "") for k in labels], dtype=str), "1",
            "the part the chapter's own simplified model keeps (its classes of Figs. "
            "3.10-3.11)"),
        "chapter_model_error_relative_peak": var(
            ("joint",), np.array(error["relative_peak_error"], float), "1",
            "peak |tau_s - tau| / peak |tau| of the chapter's own simplified model"),
        "chapter_model_error_round_off": var(
            ("joint",), np.array(error["round_off"], np.int8), "1",
            "1 where that error is floating-point round-off"),
    })
    out.attrs.update({
        "chapter_elements_compared": int(compared),
        "chapter_arm_ranked": ", ".join(blocks.arm),
        "chapter_arm_translation_leads": ", ".join(blocks.arm_translation),
        "chapter_wrist_ranked": ", ".join(blocks.wrist),
        "chapter_wrist_rotation_leads": ", ".join(blocks.wrist_rotation),
    })
    return out


def _summary(robot, trajectory, result, settings, extra=None):
    """The summary dataset of a pass (:func:`gd_analyze.store.datasets.summary_dataset`) with
    the formulations' costs, ``extra``'s variables, the simplified model's variables and the
    chapter's conclusions."""
    ds = _with(summary_dataset(robot, trajectory, result.ranking, result.choices, result.error,
                               result.verification, settings), result.costs)
    if extra is not None:
        ds = ds.assign(extra.data_vars)
    return _with_chapter(_with(ds, result.simplified), result.chapter_error)


def _analysis(robot, trajectory, result, options, settings, ds):
    """The :class:`Analysis` of a pass with the summary dataset ``ds``, and the per-set-point
    variables too when the pass held them (one chunk: the result in memory is whole)."""
    if result.terms is not None:
        ds = with_setpoints(ds, robot, trajectory, result.terms, result.tau,
                            result.tau_simplified)
    if result.model is not None:                 # the explicit simplified model
        # a recursive model with its choices as results.h5 stores them
        own = {} if result.model.recursive is None else {"choices": dict(result.choices)}
        g, arm = result.model.guarantee, result.model.robot     # where s_i is reached kept
        model = dataclasses.replace(result.model, validation=result.error, **own,
                                    guarantee=g and g.with_scale_states(arm, [trajectory]))
    else:
        model = SimplifiedModel(robot=robot, choices=result.choices,
                                dominance_threshold=float(options.dominance),
                                negligible_threshold=float(options.negligible),
                                trajectory_sha256=trajectory.sha256, validation=result.error,
                                provenance=_provenance(trajectory, settings))
    return Analysis(dataset=ds, model=model, verification=result.verification)


def analyze(robot: Robot, trajectory: Trajectory, options: AnalysisOptions | None = None,
            settings: Mapping[str, Any] | None = None) -> Analysis:
    """Compute, verify, rank and simplify the G-D terms along a trajectory, in memory.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    trajectory : Trajectory
        q, qd, qdd of shape (N, n) [rad, rad/s, rad/s^2]; a continuous joint's wraps at +-pi
        are undone where the spline gave qd and qdd
        (:func:`gd_analyze.trajectory.trajectory.unwrapped`).
    options : AnalysisOptions, optional
        The ranking's thresholds s and e, whether to verify against Pinocchio
        (:func:`verify`) and store the formulations' agreement and operation counts, and how
        the simplified model is built (``options.simplify``). Default
        :class:`~gd_analyze.jobs.options.AnalysisOptions`, as the main job.
    settings : dict, optional
        Extra provenance for the dataset's global attributes and the model.

    Returns
    -------
    Analysis
        Its dataset holds the per-set-point variables as well as the summary.

    Raises
    ------
    ValueError
        If the trajectory does not fit the robot or the thresholds are out of range.

    Notes
    -----
    Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987); terms from Eqs. (3.4-24) to (3.4-28).
    """

    options = AnalysisOptions() if options is None else options
    trajectory = unwrapped(robot, trajectory)
    result = analysis_pass(robot, trajectory, options, _provenance(trajectory, settings),
                           chunk=max(trajectory.q.shape[0], 1))
    return _analysis(robot, trajectory, result, options, settings,
                     _summary(robot, trajectory, result, settings))


def analyze_to_file(robot: Robot, trajectory: Trajectory, path: str | os.PathLike[str],
                    options: AnalysisOptions | None = None,
                    settings: Mapping[str, Any] | None = None, chunk: int | None = None,
                    progress: bool | tqdm = False, extra: xr.Dataset | None = None) -> Analysis:
    """:func:`analyze`, streamed into a results file in chunks of bounded memory.

    The G-D terms are computed once per set point, chunk by chunk, and written; the simplified
    model's torque (which needs the ranking of the whole trajectory) is computed in a second
    pass from the same terms, held in memory when there is one chunk and read back from the
    file otherwise. Memory stays a few chunks whatever N is.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    trajectory : Trajectory
        q, qd, qdd of shape (N, n) [rad, rad/s, rad/s^2].
    path : str or os.PathLike
        The results file (netCDF4/HDF5), written under a temporary name and renamed.
    options : AnalysisOptions, optional
        As :func:`analyze`; ``options.compress`` is the gzip level (0-9) of the
        per-set-point variables (0 stores them uncompressed).
    settings : dict, optional
        Extra provenance.
    chunk : int, optional
        Set points per chunk; default :func:`stream_chunk` of the arm's joints.
    progress : bool or tqdm.tqdm, optional
        As for :func:`analysis_pass`.
    extra : xarray.Dataset, optional
        More variables to store with the summary (e.g. a payload sweep, dim ``payload``).

    Returns
    -------
    Analysis
        Its dataset is the summary (:func:`gd_analyze.store.datasets.summary_dataset`); the file holds
        the per-set-point variables as well, and so does the dataset when the set points are
        one chunk (N <= ``chunk``: they were held in memory anyway,
        :func:`gd_analyze.store.datasets.with_setpoints`).

    Raises
    ------
    ValueError
        If the trajectory does not fit the robot or the thresholds are out of range.
    OSError
        If the file cannot be written.
    """
    options = AnalysisOptions() if options is None else options
    trajectory = unwrapped(robot, trajectory)
    N, n = trajectory.q.shape
    chunk = stream_chunk(n) if chunk is None else chunk
    with atomic_path(path, create=False) as tmp:
        with contextlib.closing(SetpointWriter(
                tmp, N, n, chunk=min(max(1, int(chunk)), 8192), compress=options.compress,
                prismatic=robot.prismatic,
                friction=robot.has_friction,
                joints=robot.joint_names())) as out:
            step = max(1, int(chunk))
            for a in range(0, N, step):         # block by block: no copy of a whole column
                out.write(a, {name: getattr(trajectory, name)[a:a + step]
                              for name in ("t", "q", "qd", "qdd")})
            result = analysis_pass(robot, trajectory, options,
                                   _provenance(trajectory, settings), chunk, writer=out,
                                   progress=progress)
        ds = _summary(robot, trajectory, result, settings, extra)
        append_dataset(ds, tmp)          # not to_netcdf: it would import dask
    return _analysis(robot, trajectory, result, options, settings, ds)
