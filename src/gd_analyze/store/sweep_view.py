"""Sweep datasets: the dominance ranking over many trajectories, and over payloads, written and
read back.

Schemas of ``sweep.h5`` (dim ``trajectory``) and of a payload sweep (dim ``payload``), built from
the per-trajectory results of :mod:`gd_analyze.jobs.sweep` and
:mod:`gd_analyze.jobs.payload`. Write them with :func:`gd_analyze.store.schema.write_dataset`
and read them back with :func:`gd_analyze.store.schema.open_sweep`. Source: Sec. 3.4.1 of Fu,
Gonzalez & Lee (1987).

The typed views, for the command line's summary and the report: :class:`StoredSweep` is the whole sweep as its report reads it and the command line prints it
after a run (where and how the trajectories were spread over the dask workers, and per element
the fraction of the trajectories in each dominance class, the spread of its translational share
and the part the merged model keeps: :func:`sweep_dataset`,
:func:`gd_analyze.jobs.sweep.run_sweep`). :class:`MergedModel` is the merged model's
record as the sweep report says it: its rule, form, what it keeps, its bound and guarantee,
its costs and its error on the held-out trajectories
(:func:`gd_analyze.jobs.sweep_merged.with_budget_model`,
:func:`gd_analyze.jobs.sweep_merged.with_model_cost`). :class:`PayloadSweep` is a payload
sweep (the ranking against the load on the last link). :func:`with_more_tasks` counts
tasks the run added after the sweep itself (the workers' error measurement).

:func:`merged_guarantee` reads back the merged model's guarantee that
:func:`gd_analyze.jobs.sweep_merged.with_budget_model` stores (``merged_guarantee_kind``,
``merged_guarantee_statement``: the one sentence of
:meth:`gd_analyze.simplify.guarantee.Guarantee.statement`) and, for a model proved over the
joint-limit region, whether each swept trajectory lies in that region (``merged_covered``,
``merged_coverage``), so that the command line and the sweep report say the same.
"""

from __future__ import annotations

import hashlib
import re
from collections import namedtuple
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..ranking.ranking import (
    CLASSES,
    arm_scales,
    element_labels,
    is_round_off,
)
from ..simplify.guarantee import within_bound
from .datasets import TORQUE_ERRORS, error_variables, units_by_type
from .names import SWEEP_ATTRIBUTES, Attr, Var
from .names import SweepAttr as SA
from .names import SweepVar as SV
from .schema import (
    MIXED_UNITS,
    EvaluatorCosts,
    Record,
    RunRecord,
    View,
    derived,
    element_coords,
    flag,
    global_attributes,
    joint_type_var,
    require,
    stored,
    stored_prismatic,
    strings,
    text_coordinate,
    texts,
    var,
)

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr
    from numpy.typing import ArrayLike

    from ..model.robot import Robot
    from ..trajectory.trajectory import Trajectory

__all__ = ["MergedModel", "SweepSettings", "StoredSweep", "PayloadSweep",
           "REQUIRED", "PAYLOAD_REQUIRED", "with_more_tasks", "inputs_attributes", "sweep_dataset",
           "payload_dataset", "sweep_payloads_dataset", "embed_payload", "payload_part",
           "beyond_the_floor", "merged_guarantee", "embed_pair_peaks", "merged_error_variables",
           "sweep_size", "MERGED_ERRORS"]

#: At most this many input files are listed by name in the global attributes (all are in the
#: per-trajectory variables ``source`` and ``input_sha256``); HDF5 attributes stay small.
_MAX_LISTED_FILES = 20
_RANDOM_SOURCE = re.compile(r"^random-(\d+)-(\d+)$")
_REFERENCES = "Fu, Gonzalez & Lee (1987), Robotics, Sec. 3.4.1; Lee, Lee & Nigam (1983)"

#: How the envelope of the shares treats round-off (:func:`is_round_off`).
_AS_DATA = ("; 0 or 1 on a trajectory where a part is round-off (at most 1e-12 of the element's "
            "scale or 64 eps of the arm's), a trajectory where the element is round-off left out (NaN: on every one)")


#: Bytes counted per stored text (a variable-length HDF5 string: its heap entry and its
#: reference), as 8 values; a file name or a sentence counts as 32 values.
_TEXT_VALUES, _LONG_TEXT_VALUES = 8, 32


def sweep_size(trajectories: int, n: int, masses: int = 0) -> int:
    """Bytes of the per-trajectory variables of sweep.h5 and of the per-mass ones of
    payload_sweep.h5 (uncompressed), plus 1 MiB a file: an over-estimate of the files,
    checked before the sweep (:func:`gd_analyze.store.staging.check_free_space`).

    Parameters
    ----------
    trajectories : int
        K, the trajectories swept.
    n : int
        Joints; the elements are M = n (n + 1) / 2 + n.
    masses : int, optional
        P, the load masses of a payload sweep (:func:`sweep_payloads_dataset`); 0: none.

    Returns
    -------
    int
        8 bytes per value. Per trajectory: per element two numbers, the flag ``round_off``
        and two texts (``dominance``, ``choice``); per joint 16 numbers (the start and the
        goal, the peak torque, the own and merged models' errors and bounds); the texts
        ``source``, ``input_sha256`` and ``merged_coverage`` and five numbers. The peaks the
        budget rule prunes on are not stored
        (:func:`gd_analyze.jobs.sweep_merged.with_budget_model`). Per mass: per element the
        four class fractions, the share, ``round_off`` and two texts; n peak torques and the
        mass [bytes].

    Examples
    --------
    >>> sweep_size(2, 2) - (1 << 20) == 8 * 2 * (5 * (3 + 2 * 8) + 16 * 2 + 3 * 32 + 5)
    True
    >>> sweep_size(2, 2, 3) - sweep_size(2, 2) - (1 << 20) == 8 * 3 * (5 * (6 + 2 * 8) + 3)
    True
    """
    elements = n * (n + 1) // 2 + n
    per_trajectory = elements * (3 + 2 * _TEXT_VALUES) + 16 * n + 3 * _LONG_TEXT_VALUES + 5
    per_mass = elements * (6 + 2 * _TEXT_VALUES) + n + 1
    return (8 * trajectories * per_trajectory + (1 << 20)
            + (8 * masses * per_mass + (1 << 20) if masses else 0))


def _torque_units(robot, which="tau"):
    """The ``units`` of a per-joint torque (``which="tau"``) or position (``"q"``) variable:
    N m, N (rad, m), or both with where to read them."""
    return units_by_type(robot.prismatic, which, "joint_type")


def inputs_attributes(trajectories: Sequence[Trajectory]) -> dict[str, Any]:
    """Global attributes that identify a sweep's inputs: seed or files, and one digest of all.

    Parameters
    ----------
    trajectories : sequence of Trajectory
        The sweep's trajectories; random ones have ``source`` ``"random-<seed>-<i>"``.

    Returns
    -------
    dict
        ``inputs_sha256`` (SHA-256 over every source and its SHA-256), ``trajectories`` (K),
        ``input_kind`` (random, files or mixed), ``seed`` when all random ones share one, and
        ``input_files`` (at most 20 listed by name with their SHA-256).
    """
    sources = [str(tr.source) for tr in trajectories]
    shas = [str(tr.sha256) for tr in trajectories]
    digest = hashlib.sha256()
    for src, sha in zip(sources, shas):
        digest.update(f"{src}\t{sha}\n".encode())
    attrs = {SA.INPUTS_SHA256: digest.hexdigest(), SA.TRAJECTORIES: len(trajectories)}
    seeds = {m.group(1) for m in map(_RANDOM_SOURCE.match, sources) if m}
    n_random = sum(bool(_RANDOM_SOURCE.match(s)) for s in sources)
    files = [(s, h) for s, h in zip(sources, shas) if h]
    attrs[SA.INPUT_KIND] = ("random" if n_random == len(sources) else
                            "files" if len(files) == len(sources) else "mixed")
    if n_random and len(seeds) == 1:
        attrs[SA.SEED] = int(next(iter(seeds)))
    if files:
        listed = [f"{Path(s).name} sha256 {h}" for s, h in files[:_MAX_LISTED_FILES]]
        if len(files) > _MAX_LISTED_FILES:
            listed.append(f"... and {len(files) - _MAX_LISTED_FILES} more (see the variables "
                          "source and input_sha256)")
        attrs[SA.INPUT_FILES] = "; ".join(listed)
    return attrs


#: The merged model's error over all the swept trajectories: its key in a torque error
#: (:func:`gd_analyze.simplify.simplified.torque_error`), its variable, whether in torque units
#: (else 1) and its long_name; read back by :func:`gd_analyze.jobs.sweep_merged.merged_model`.
MERGED_ERRORS = (
    ("peak_abs_error", SV.MERGED_ERROR_PEAK, True,
     "merged model: peak |tau_merged - tau| over all trajectories"),
    ("rms_error", SV.MERGED_ERROR_RMS, True,
     "merged model: RMS of |tau_merged - tau| over all set points of all trajectories"),
    ("peak_tau", SV.MERGED_ERROR_TAU_PEAK, True, "peak |tau| over all trajectories"),
    ("relative_peak_error", SV.MERGED_ERROR_RELATIVE_PEAK, False,
     "merged model: peak error / peak |tau|, over all trajectories"),
    ("relative_rms_error", SV.MERGED_ERROR_RELATIVE_RMS, False,
     "merged model: RMS error / peak |tau|, over all trajectories"))


def merged_error_variables(error: Mapping[str, Any], torque: str) -> dict[str, Any]:
    """The merged model's error over all the swept trajectories as ``sweep.h5`` stores it.

    Parameters
    ----------
    error : Mapping
        Per joint ``peak_abs_error``, ``rms_error``, ``peak_tau`` [N m or N],
        ``relative_peak_error`` and ``relative_rms_error`` [1], as
        :func:`gd_analyze.simplify.simplified.torque_error` gives them (None: NaN).
    torque : str
        The ``units`` attribute of a joint torque.

    Returns
    -------
    dict
        ``merged_error_peak``, ``merged_error_rms``, ``merged_error_tau_peak``,
        ``merged_error_relative_peak``, ``merged_error_relative_rms`` (dim joint), as
        :func:`gd_analyze.store.schema.var`.
    """
    return error_variables(error, (SV.JOINT,), torque, MERGED_ERRORS)


def sweep_dataset(robot: Robot, trajectories: Sequence[Trajectory],
                  results: Sequence[Mapping[str, Any]], merged: Mapping[str, Any],
                  merged_stats: Sequence[Mapping[str, Any]] | None, dominance: float,
                  negligible: float) -> xr.Dataset:
    """The sweep dataset (``sweep.h5``) from the per-trajectory results.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    trajectories : sequence of Trajectory
        The K trajectories, in the order of ``results``.
    results : list of dict
        Per trajectory, as :func:`gd_analyze.jobs.sweep.analyze_one` returns it.
    merged : dict
        Element label -> the merged choice of the chapter rule (no error bound).
    merged_stats : list of dict or None
        Per trajectory, the merged model's accumulated torque error: ``peak``, ``sum_sq``,
        ``count``, ``peak_tau`` [N m]. None: not measured (the budget rule's model is put in
        later, :func:`gd_analyze.jobs.sweep_merged.with_budget_model`), the merged
        model's error variables are NaN.
    dominance, negligible : float
        s and e of the ranking.

    Returns
    -------
    xarray.Dataset
        See :func:`gd_analyze.jobs.sweep.run_sweep` for the variables.
    """
    import xarray as xr

    n = robot.n
    labels = element_labels(n)
    K = len(results)
    T, TE, TJ = (SV.TRAJECTORY,), (SV.TRAJECTORY, SV.ELEMENT), (SV.TRAJECTORY, SV.JOINT)
    ranking, peaks, arm, round_off = _ranking_vars(
        TE, results, labels, robot, "part kept by the trajectory's own simplified "
        "model (tran, rot, both, none)", "on the trajectory")
    # the share as data: 0 or 1 where one part is round-off of the element's scale or of the
    # arm's (a share of 4e-14 or of 2e-12 is round-off, not data), left out where the element
    # is round-off on a trajectory
    tran_off, rot_off = (is_round_off(peaks[k], peaks["scale"], arm_scale=arm)
                         for k in ("peak_tran", "peak_rot"))
    share_data = np.where(tran_off & ~rot_off, 0.0,
                          np.where(rot_off & ~tran_off, 1.0, ranking[SV.SHARE_TRAN][1]))
    share_data = np.where(round_off, np.nan, share_data)
    summ = [r["summary"] for r in results]

    def each(key, dtype=None):
        """Per trajectory, the summary's ``key``."""
        return np.array([s[key] for s in summ], dtype=dtype)

    if merged_stats is None:
        nan = np.full(robot.n, np.nan)
        merged_stats = [{"peak": nan, "peak_tau": nan, "sum_sq": nan, "count": 0}] * K
    m_peak, m_tau = (np.array([s[k] for s in merged_stats]) for k in ("peak", "peak_tau"))
    all_peak = m_peak.max(axis=0)
    all_tau = m_tau.max(axis=0)
    all_rms = np.sqrt(np.sum([s["sum_sq"] for s in merged_stats], axis=0)
                      / max(1, sum(s["count"] for s in merged_stats)))
    classes = ranking[SV.DOMINANCE][1]
    fraction = np.stack([(classes == c).mean(axis=0) for c in CLASSES], axis=1)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)     # all-NaN columns
        s_min, s_med, s_max = (np.nanmin(share_data, axis=0),
                               np.nanmedian(share_data, axis=0), np.nanmax(share_data, axis=0))
    torque, position = _torque_units(robot), _torque_units(robot, "q")
    tau_peak = ranking.pop(SV.TAU_PEAK)
    data_vars = {
        **ranking,
        SV.SOURCE: var(T, each("source", str), "1",
                       "trajectory source (file name or random-<seed>-<index>)"),
        SV.INPUT_SHA256: var(T, each("sha256", str), "1",
                             "SHA-256 of the trajectory file (empty if generated)"),
        SV.DURATION: var(T, each("duration"), "s", "trajectory duration"),
        SV.SETPOINTS: var(T, each("setpoints"), "1", "number of set points"),
        SV.Q_START: var(TJ, each("q_start"), position, "joint position at the first set point"),
        SV.Q_GOAL: var(TJ, each("q_goal"), position, "joint position at the last set point"),
        SV.TAU_PEAK: tau_peak,
        **error_variables({key: [s["error"][key] for s in summ] for key, *_ in TORQUE_ERRORS},
                          TJ, torque, prefix="own simplified model: "),
        SV.MERGED_TAU_ERROR_PEAK: var(TJ, m_peak, torque,
                                      "merged model: peak |tau_merged - tau| along the "
                                      "trajectory"),
        SV.MERGED_TAU_ERROR_RELATIVE_PEAK: var(TJ, _relative(m_peak, m_tau), "1",
                                               "merged model: peak |tau_merged - tau| / peak "
                                               "|tau| along the trajectory"),
        SV.CLASS_FRACTION: var((SV.ELEMENT, SV.CLASS), fraction, "1",
                               "fraction of the trajectories in which the class holds"),
        SV.SHARE_TRAN_MIN: var((SV.ELEMENT,), s_min, "1",
                               "smallest translational share over the trajectories" + _AS_DATA),
        SV.SHARE_TRAN_MEDIAN: var((SV.ELEMENT,), s_med, "1",
                                  "median translational share over the trajectories"
                                  + _AS_DATA),
        SV.SHARE_TRAN_MAX: var((SV.ELEMENT,), s_max, "1",
                               "largest translational share over the trajectories" + _AS_DATA),
        SV.MERGED_CHOICE: var((SV.ELEMENT,), np.array([merged[lab] for lab in labels], dtype=str),
                              "1", "part kept by the merged model of the chapter rule: a "
                                   "part is dropped only where every trajectory drops it"),
        **merged_error_variables({"peak_abs_error": all_peak, "rms_error": all_rms,
                                  "peak_tau": all_tau,
                                  "relative_peak_error": _relative(all_peak, all_tau),
                                  "relative_rms_error": _relative(all_rms, all_tau)}, torque),
    }
    data_vars["joint_type"] = joint_type_var(robot)
    coords = element_coords(n, robot.prismatic, robot.joint_names())
    coords[SV.TRAJECTORY] = (SV.TRAJECTORY, np.arange(K),
                            {"long_name": "trajectory index", "units": "1"})
    coords[SV.CLASS] = text_coordinate(SV.CLASS, CLASSES, "dominance class")
    attrs = global_attributes(robot, f"G-D dominance sweep of {robot.name} over {K} trajectories",
                              references=_REFERENCES, dominance_threshold=float(dominance),
                              negligible_threshold=float(negligible))
    attrs.update(inputs_attributes(trajectories))
    attrs[SA.SETPOINTS_TOTAL] = int(sum(s["setpoints"] for s in summ))
    attrs[SA.MERGE_RULE] = ("keep_tran = any trajectory keeps tran (tran or both); keep_rot = "
                           "any keeps rot (rot or both); merged = both/tran/rot/none "
                           "(chapter rule: no error bound)")
    attrs[SA.MERGED_RULE] = "chapter"
    # each trajectory's own simplified model (tau_error_*): the chapter's share-based classes
    attrs[SA.OWN_MODEL_RULE] = "chapter"
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def _relative(error, tau):
    """``error / tau`` where ``tau`` > 0, else NaN (a joint at rest has no relative error)."""
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(tau > 0, error / np.where(tau > 0, tau, 1.0), np.nan)


def payload_dataset(robot: Robot, trajectory: Trajectory, masses: np.ndarray, com: ArrayLike,
                    inertia: ArrayLike, results: Sequence[Mapping[str, Any]], dominance: float,
                    negligible: float) -> xr.Dataset:
    """The dataset of one trajectory ranked for a range of loads (``--payload-sweep``).

    Parameters
    ----------
    robot : Robot
        The arm, with n joints, without the load.
    trajectory : Trajectory
        The trajectory ranked.
    masses : ndarray, shape (P,)
        Load masses [kg].
    com : array_like, shape (3,)
        Load centre of mass in link frame n [m].
    inertia : array_like, shape (3,) or (3, 3)
        Load inertia about its centre of mass [kg m^2].
    results : list of dict
        Per mass, as :func:`gd_analyze.jobs.sweep.analyze_one` returns it.
    dominance, negligible : float
        s and e of the ranking.

    Returns
    -------
    xarray.Dataset
        See :func:`gd_analyze.jobs.payload.payload_sweep`.
    """
    n = robot.n
    labels = element_labels(n)
    I_p = np.asarray(inertia, dtype=float)
    I_p = np.diag(I_p) if I_p.shape == (3,) else I_p.reshape(3, 3)
    data_vars = _ranking_vars((Var.PAYLOAD, Var.ELEMENT), results, labels, robot,
                              "part kept by the simplified model (tran, rot, both, none)",
                              "along the trajectory")[0]
    data_vars[Var.TAU_ERROR_RELATIVE_PEAK] = var(
        (Var.PAYLOAD, Var.JOINT),
        np.array([r["summary"]["error"]["relative_peak_error"] for r in results]), "1",
        "own simplified model: peak |tau_simplified - tau| / peak |tau|")
    source = Path(str(trajectory.source))
    return _by_payload(
        robot, masses, {"long_name": "payload mass on the last link", "units": "kg"},
        data_vars, element_coords(n, robot.prismatic, robot.joint_names()),
        f"G-D dominance of {robot.name} vs payload along {source.name}", dominance, negligible,
        {**_payload_attrs(com, I_p, "kg m2 (3 x 3 tensor, row by row)"),
         Attr.INPUT_FILE: source.name,
         Attr.INPUT_PATH: str(trajectory.source),
         Attr.INPUT_SHA256: str(trajectory.sha256),
         Attr.DERIVATIVES: str(trajectory.derivatives),
         Attr.SETPOINTS: int(np.asarray(trajectory.t).shape[0])})


def _payload_attrs(com, inertia, inertia_units):
    """The load's centre of mass [m] and inertia (``inertia_units``), with their units."""
    return {Attr.PAYLOAD_COM: np.asarray(com, dtype=float).reshape(3), "payload_com_units": "m",
            Attr.PAYLOAD_INERTIA: np.asarray(inertia, dtype=float).reshape(-1),
            "payload_inertia_units": inertia_units}


def _by_payload(robot, masses, mass_attrs, data_vars, coords, title, dominance, negligible,
                attrs):
    """A dataset over the load masses (dim ``payload`` [kg], its attributes ``mass_attrs``),
    with the joint types and :func:`global_attributes` (s, e) before ``attrs``."""
    import xarray as xr

    data_vars[Var.JOINT_TYPE] = joint_type_var(robot)
    coords[Var.PAYLOAD] = (Var.PAYLOAD, np.asarray(masses, float), mass_attrs)
    return xr.Dataset(data_vars, coords=coords, attrs={
        **global_attributes(robot, title, references=_REFERENCES,
                            dominance_threshold=float(dominance),
                            negligible_threshold=float(negligible)), **attrs})


def sweep_payloads_dataset(robot: Robot, n_trajectories: int, masses: Sequence[float],
                           com: ArrayLike, inertia: ArrayLike,
                           parts: Sequence[tuple[Any, ...]], dominance: float,
                           negligible: float) -> xr.Dataset:
    """The dataset of a sweep repeated per load mass (``payload_sweep.h5`` of ``sweep``).

    Parameters
    ----------
    robot : Robot
        The arm, with n joints, without the load.
    n_trajectories : int
        K, the trajectories of each sweep.
    masses : sequence of float
        Load masses [kg], P of them.
    com : array_like, shape (3,)
        Load centre of mass in link frame n [m].
    inertia : array_like, shape (3,)
        Load principal moments [kg m^2].
    parts : list of tuple
        Per mass: class fractions (M, 4), median share_tran (M,), most frequent class (M,),
        merged choice (M,), peak |tau| over all trajectories (n,) [N m], and optionally
        round-off on every trajectory (M,) bool (stored as ``round_off``).
    dominance, negligible : float
        s and e of the ranking.

    Returns
    -------
    xarray.Dataset
        See :func:`gd_analyze.jobs.payload.sweep_payloads`.
    """
    frac, share, dom, choice, tau = (np.array(x) for x in list(zip(*parts))[:5])
    PE = (Var.PAYLOAD, Var.ELEMENT)
    extra = ({Var.ROUND_OFF: _round_off_var(PE, np.array([p[5] for p in parts]),
                                            "on every trajectory")}
             if all(len(p) > 5 for p in parts) else {})
    coords = element_coords(robot.n, joints=robot.joint_names())
    del coords[Var.ELEMENT_UNITS]
    coords[SV.CLASS] = text_coordinate(SV.CLASS, CLASSES, "dominance class")
    return _by_payload(
        robot, masses, {"units": "kg", "long_name": "load mass on the last link"},
        {**extra,
         SV.CLASS_FRACTION: var((*PE, "class"), frac, "1",
                               "fraction of the trajectories in each class"),
         Var.SHARE_TRAN: var(PE, share, "1", "median translational share over the trajectories"),
         Var.DOMINANCE: var(PE, dom.astype(str), "1",
                            "most frequent dominance class over the trajectories"),
         Var.CHOICE: var(PE, choice.astype(str), "1",
                         "merged share-based choice (chapter rule, no error bound)"),
         Var.TAU_PEAK: var((Var.PAYLOAD, Var.JOINT), tau, _torque_units(robot),
                           "peak |tau| over all trajectories")},
        coords, f"G-D dominance of {robot.name} vs payload over {n_trajectories} trajectories",
        dominance, negligible,
        {"kind": "payload", **_payload_attrs(com, inertia, "kg m2 (principal moments)")})


def _ranking_vars(dims, results, labels, robot, kept, where):
    """The ranking's variables over ``dims`` (trajectory or payload, then element) from the
    per-run results of :func:`gd_analyze.jobs.sweep.analyze_one`: share, class, the part kept
    (``kept``: its long name), peak, round-off (``where``: on which run) and each joint's peak
    |tau|; with the peaks (each of shape (K, M)), the arm's scales and the round-off flags."""
    peaks = {k: np.array([r["peaks"][k] for r in results])
             for k in ("peak_tran", "peak_rot", "peak_total", "scale")}
    # each element's arm scale on each run: the largest scale of its units there, so that the
    # sweep tells round-off from data by the main report's rule
    units = element_coords(robot.n, robot.prismatic)[Var.ELEMENT_UNITS][1]
    arm = np.array([arm_scales(row, units) for row in np.atleast_2d(peaks["scale"])])
    round_off = is_round_off(np.max([peaks[k] for k in ("peak_tran", "peak_rot", "peak_total")],
                                    axis=0), peaks["scale"], arm_scale=arm)
    return {
        Var.SHARE_TRAN: var(dims, np.array([r["share_tran"] for r in results]), "1",
                            "translational share sum|tran| / (sum|tran| + sum|rot|)"),
        Var.DOMINANCE: var(dims, np.array([r["classes"] for r in results], dtype=str), "1",
                           "dominance class (translational, rotational, both, negligible)"),
        Var.CHOICE: var(dims, np.array([[r["choices"][lab] for lab in labels] for r in results],
                                       dtype=str), "1", kept),
        Var.PEAK_TOTAL: var(dims, peaks["peak_total"], MIXED_UNITS,
                            "peak |translational + rotational| along the trajectory"),
        Var.TAU_PEAK: var((dims[0], Var.JOINT),
                          np.array([r["summary"]["tau_peak"] for r in results]),
                          _torque_units(robot), "peak |tau| of the full model along the trajectory"),
        Var.ROUND_OFF: _round_off_var(dims, round_off, where),
    }, peaks, arm, round_off


def _round_off_var(dims, flags, where):
    """The (trajectory or payload, element) flag: every part of the element is round-off (its
    share is noise, :func:`gd_analyze.ranking.ranking.is_round_off`)."""
    return flag(dims, flags, f"every part of the element is round-off {where} "
                "(1: at most 1e-12 of its scale; its share_tran is noise), else 0")


def embed_pair_peaks(ds: xr.Dataset, names: Sequence[str], tau_peak: np.ndarray,
                     peak: np.ndarray, whole_peak: np.ndarray) -> xr.Dataset:
    """A sweep dataset with each trajectory's peaks of the recursive model's contributions.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep dataset (:func:`sweep_dataset`), K trajectories, n joints.
    names : sequence of str, length b
        The base parameters (:meth:`gd_analyze.dynamics.base_parameters.BaseParameters.names`).
    tau_peak : ndarray, shape (K, n)
        Peak |tau_i| of each trajectory, from the contributions [N m or N].
    peak : ndarray, shape (K, b, 3, n)
        Peak |contribution| of each (base parameter, part) on each trajectory [N m or N].
    whole_peak : ndarray, shape (K, b, n)
        The same per base parameter, all parts together [N m or N].

    Returns
    -------
    xarray.Dataset
        A copy with ``pair_tau_peak``, ``pair_peak`` and ``parameter_peak``, coordinates
        ``base_parameter`` and ``part`` (inertial, velocity, gravity): what the budget rule's
        merge prunes on (:mod:`gd_analyze.jobs.sweep_merged`, which removes them again).

    Raises
    ------
    ValueError
        If a shape does not match the dataset.
    """
    K, n = ds.sizes[SV.TRAJECTORY], ds.sizes[SV.JOINT]
    tau_peak, peak, whole_peak = (np.asarray(x, float) for x in (tau_peak, peak, whole_peak))
    b = len(names)
    if tau_peak.shape != (K, n) or peak.shape != (K, b, 3, n) or whole_peak.shape != (K, b, n):
        raise ValueError(f"peaks of shapes {tau_peak.shape}, {peak.shape}, {whole_peak.shape} "
                         f"do not fit {K} trajectories, {b} base parameters, {n} joints")
    torque = ds[SV.TAU_PEAK].attrs.get("units", "N m")
    out = ds.assign_coords(base_parameter=(SV.BASE_PARAMETER, np.array(list(names), dtype=str)),
                           part=(SV.PART, np.array(["inertial", "velocity", "gravity"])))
    out[SV.PAIR_TAU_PEAK] = var((SV.TRAJECTORY, SV.JOINT), tau_peak, torque,
                               "peak |tau_i|, the sum of the base-parameter contributions")
    out[SV.PAIR_PEAK] = var((SV.TRAJECTORY, SV.BASE_PARAMETER, SV.PART, SV.JOINT), peak, torque,
                           "peak |contribution| of a (base parameter, part) to tau_i")
    out[SV.PARAMETER_PEAK] = var((SV.TRAJECTORY, SV.BASE_PARAMETER, SV.JOINT), whole_peak, torque,
                                "peak |contribution| of a base parameter (all parts) to tau_i")
    return out


def embed_payload(payload: xr.Dataset) -> xr.Dataset:
    """A payload sweep as variables ``payload_<name>`` to store beside the main analysis.

    ``results.h5`` holds the main job's ranking over dim ``element``; a ``--payload-sweep``
    adds its own ranking over (``payload``, ``element``) under prefixed names so the two do not
    collide. :func:`payload_part` undoes it.

    Parameters
    ----------
    payload : xarray.Dataset
        From :func:`payload_dataset`.

    Returns
    -------
    xarray.Dataset
        The same variables, each prefixed ``payload_``; the ``element_units`` coordinate and
        ``joint_type`` (already in the main analysis) dropped.
    """
    renamed = payload.drop_vars(["joint_type", "element_units"], errors="ignore")
    return renamed.rename({v: f"payload_{v}" for v in renamed.data_vars})


def payload_part(results: xr.Dataset) -> xr.Dataset:
    """The payload sweep stored in a results dataset by :func:`embed_payload`, under its own names.

    Parameters
    ----------
    results : xarray.Dataset
        A ``results.h5`` read back (:func:`gd_analyze.store.schema.open_results`).

    Returns
    -------
    xarray.Dataset
        The ``payload_*`` variables over dim ``payload``, without the prefix, and the
        analysis' ``joint_type`` (empty if the run had no payload sweep).
    """
    names = [v for v in results.data_vars
             if v.startswith("payload_")  # type: ignore[attr-defined]  # names are str here
             and "payload" in results[v].dims]
    part = results[names].rename({v: v[len("payload_"):]  # type: ignore[index]  # str
                                  for v in names})
    if names and "joint_type" in results.variables:     # the main analysis' joint types
        part["joint_type"] = results["joint_type"]
    return part


def beyond_the_floor(ds: xr.Dataset) -> tuple[float, int, list[int]] | None:
    """Where the budget's guarantee does not reach: errors above EPS of peak |tau_i| itself.

    The budget rule guarantees |tau_merged - tau| <= EPS scale_i with scale_i = max(peak
    |tau_i|, TAU) on each swept trajectory; where a joint's peak |tau_i| is below the torque
    floor TAU, its error relative to its own peak |tau_i| is not bounded by EPS.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep dataset with the budget rule's merged model (``merged_tau_error_peak`` and
        ``tau_peak``, dims (trajectory, joint) [N m]; attribute ``merged_tolerance``).

    Returns
    -------
    tuple or None
        (worst relative error, its joint from 1, the joints above EPS) when some joint's peak
        error exceeds EPS times its own peak |tau_i| on some trajectory; None otherwise (or
        without a budget-rule model, or for a model proved over the joint-limit region, whose
        guarantee is relative to s_i over the region, never to a trajectory's peak).
    """
    if SV.MERGED_TAU_ERROR_PEAK not in ds.variables or SA.MERGED_TOLERANCE not in ds.attrs \
            or ds.attrs.get(SA.MERGED_GUARANTEE_KIND) == "region":
        return None
    err = np.asarray(ds[SV.MERGED_TAU_ERROR_PEAK].values, float)
    peak = np.asarray(ds[SV.TAU_PEAK].values, float)
    with np.errstate(invalid="ignore", divide="ignore"):
        rel = np.where(err > 0, err / np.where(peak > 0, peak, 0.0), 0.0)
    rel = np.nan_to_num(rel, nan=np.inf).max(axis=0)
    eps = float(ds.attrs[SA.MERGED_TOLERANCE])
    over = np.flatnonzero(rel > eps * (1 + 1e-9))
    if not over.size:
        return None
    j = int(np.argmax(rel))
    return float(rel[j]), j + 1, [int(k) + 1 for k in over]


def merged_guarantee(ds: xr.Dataset) -> dict[str, Any] | None:
    """The merged model's guarantee and the swept trajectories it covers.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep dataset (K trajectories, n joints) with the budget rule's merged model.

    Returns
    -------
    dict or None
        None without a stored guarantee (chapter rule, older files); else ``kind``
        (``"region"`` or ``"trajectory"``), ``statement`` (str), ``covered`` (ndarray of bool,
        shape (K,): a trajectory-kind guarantee covers every swept trajectory, a region one
        those lying in its region), ``outside`` (list of (source, reason, worst peak
        |tau_merged - tau| / s_i [1]) of the trajectories not covered), ``worst`` (the
        largest peak |tau_merged - tau| / scale_i over the covered trajectories [1], NaN if
        none; ``merged_tau_error_relative_peak``), ``within`` (whether every covered
        trajectory's peak |tau_merged - tau| is within its bound up to round-off, judged by
        :func:`~gd_analyze.simplify.guarantee.within_bound`; True if none is covered) and
        ``held_out_inside`` (how many held-out trajectories lie in the region; None when not
        stored).

    Raises
    ------
    InputError
        If the file stores a guarantee but not the variables it is checked on (one line).
    """
    a = ds.attrs
    if "merged_guarantee_statement" not in a:
        return None
    kind = str(a.get("merged_guarantee_kind", "none"))
    require(ds, (SV.MERGED_TAU_ERROR_PEAK, SV.MERGED_SCALE, SV.MERGED_BOUND)
            + ((SV.MERGED_COVERED, SV.MERGED_COVERAGE) if kind == "region" else ()), "sweep")
    rel = np.asarray(ds[SV.MERGED_TAU_ERROR_RELATIVE_PEAK].values, float)
    K = rel.shape[0]
    if kind == "region":
        covered = np.asarray(ds[SV.MERGED_COVERED].values).astype(bool)
        reasons = strings(ds[SV.MERGED_COVERAGE].values)
    else:
        covered, reasons = np.ones(K, bool), [""] * K
    worst = np.where(np.isfinite(rel), rel, np.inf).max(axis=1) if rel.size else np.zeros(K)
    sources = strings(ds[SV.SOURCE].values)
    peak = np.asarray(ds[SV.MERGED_TAU_ERROR_PEAK].values, float)
    scale = np.asarray(ds[SV.MERGED_SCALE].values, float)
    bound = np.asarray(ds[SV.MERGED_BOUND].values, float)
    within = all(within_bound(peak[k], bound[k], scale[k]).all() for k in np.flatnonzero(covered))
    inside = a.get(SA.HELD_OUT_INSIDE_REGION)
    return {"kind": kind, "statement": str(a["merged_guarantee_statement"]),
            "covered": covered,
            "outside": [(sources[k], reasons[k], float(worst[k])) for k in range(K)
                        if not covered[k]],
            "worst": float(worst[covered].max()) if covered.any() else float("nan"),
            "within": within,
            "held_out_inside": None if inside is None else int(inside)}

#: The variables of a payload sweep the report reads.
PAYLOAD_REQUIRED = (Var.SHARE_TRAN, Var.DOMINANCE, Var.CHOICE, Var.TAU_PEAK)

#: The variables of a sweep dataset the report reads.
REQUIRED = (SV.SHARE_TRAN, SV.ROUND_OFF, SV.DOMINANCE, SV.CHOICE, SV.SOURCE, SV.DURATION,
            SV.SETPOINTS, SV.TAU_PEAK, SV.TAU_ERROR_RELATIVE_PEAK, SV.CLASS_FRACTION,
            SV.SHARE_TRAN_MIN, SV.SHARE_TRAN_MEDIAN, SV.SHARE_TRAN_MAX, SV.MERGED_CHOICE,
            SV.MERGED_TAU_ERROR_RELATIVE_PEAK, *(name for _, name, *_ in MERGED_ERRORS))


@dataclass(frozen=True, eq=False)
class MergedModel(View):
    """The sweep's merged model as the sweep report says it.

    Attributes
    ----------
    rule : str
        ``"budget"`` or ``"chapter"`` (the default of an older file).
    form : str
        ``"explicit"`` or ``"recursive"``.
    tolerance : object
        EPS as stored (None for the chapter rule).
    torque_floor : float
        The least scale of a joint torque [N m] (0 where not stored).
    own_rule : str
        The rule of each trajectory's own simplified model.
    guarantee_kind : str
        ``"region"``, ``"trajectory"`` or "" where none is stored.
    region : bool
        Its guarantee is proved over the joint-limit region.
    guarantee_statement : object
        The guarantee as the model states it (None where not stored).
    guarantee_scale_source : str
        How a region model's s_i was found, as the model states it
        (:meth:`gd_analyze.simplify.guarantee.Guarantee.scale_source`; "" where not stored).
    guarantee : dict or None
        :func:`merged_guarantee`: the guarantee and the swept
        trajectories it covers.
    bound_method : tuple of str, length n
        A region model's way of proving each joint's bound
        (:attr:`gd_analyze.simplify.guarantee.Guarantee.bound_method`); () where not stored.
    joint_sum_arithmetic : str
        The enclosures its joint sums were added on ("" where not stored).
    beyond_floor : tuple or None
        :func:`beyond_the_floor`.
    worst_scaled_error : float
        Its largest measured peak error / s_i over the swept trajectories [1] (NaN where not
        stored).
    base_parameters, pairs, pairs_dropped : object
        A recursive model's base parameters and (parameter, part) pairs: all that act, and
        dropped, as stored (None where not).
    gravity_dropped : str
        The base parameters whose gravity part it drops, comma-separated.
    c_terms_kept, c_terms : int
        An explicit model's terms of c kept and all (-1 where not stored).
    elements, choice : tuple of str, length M
        The ranked elements and the part of each the merged model keeps.
    bound, scale : ndarray, shape (K, n), or None
        Its bound per trajectory and joint, and s_i [N m or N].
    held_out_error_peak, held_out_tau_peak : ndarray, shape (n,), or None
        Its peak error and peak |tau| over the held-out trajectories [N m or N].
    held_out_trajectories, held_out_inside_region : int
        The held-out trajectories, and how many lie in the region.
    costs : EvaluatorCosts or None
        Its operations per set point, first, and the models it is compared with.
    prismatic : tuple of bool, length n
        The prismatic joints.
    """

    rule: str = stored(SA.MERGED_RULE, str, "chapter", attr=True)
    form: str = stored(SA.MERGED_FORM, str, "explicit", attr=True)
    tolerance: Any = stored(SA.MERGED_TOLERANCE, default=None, attr=True)
    torque_floor: float = stored(SA.MERGED_TORQUE_FLOOR, lambda v: float(v or 0.0), 0.0, attr=True)
    own_rule: str = stored(SA.OWN_MODEL_RULE, str, "chapter", attr=True)
    guarantee_kind: str = stored(SA.MERGED_GUARANTEE_KIND, str, "", attr=True)
    region: bool = derived(lambda ds: str(ds.attrs.get(SA.MERGED_GUARANTEE_KIND, "")) == "region")
    guarantee_statement: Any = stored(SA.MERGED_GUARANTEE_STATEMENT, default=None, attr=True)
    guarantee_scale_source: str = stored(SA.MERGED_GUARANTEE_SCALE_SOURCE, str, "", attr=True)
    guarantee: dict | None = derived(merged_guarantee)
    bound_method: tuple[str, ...] = stored(SV.MERGED_BOUND_METHOD, texts, ())
    joint_sum_arithmetic: str = stored(SA.MERGED_JOINT_SUM_ARITHMETIC, str, "", attr=True)
    beyond_floor: tuple[float, int, list[int]] | None = derived(beyond_the_floor)
    worst_scaled_error: float = stored(SA.MERGED_WORST_SCALED_ERROR, float, np.nan, attr=True)
    base_parameters: Any = stored(SA.MERGED_BASE_PARAMETERS, default=None, attr=True)
    pairs: Any = stored(SA.MERGED_PAIRS, default=None, attr=True)
    pairs_dropped: Any = stored(SA.MERGED_PAIRS_DROPPED, default=None, attr=True)
    gravity_dropped: str = stored(SA.MERGED_GRAVITY_DROPPED, str, "", attr=True)
    c_terms_kept: int = stored(SA.MERGED_C_TERMS_KEPT, int, -1, attr=True)
    c_terms: int = stored(SA.MERGED_C_TERMS, int, -1, attr=True)
    elements: tuple[str, ...] = stored(SV.ELEMENT, texts)
    choice: tuple[str, ...] = stored(SV.MERGED_CHOICE, texts)
    bound: np.ndarray | None = stored(SV.MERGED_BOUND, default=None)
    scale: np.ndarray | None = stored(SV.MERGED_SCALE, default=None)
    held_out_error_peak: np.ndarray | None = stored(SV.HELD_OUT_ERROR_PEAK, default=None)
    held_out_tau_peak: np.ndarray | None = stored(SV.HELD_OUT_TAU_PEAK, default=None)
    held_out_trajectories: int = stored(SA.HELD_OUT_TRAJECTORIES, int, 0, attr=True)
    held_out_inside_region: int = stored(SA.HELD_OUT_INSIDE_REGION, int, 0, attr=True)
    costs: EvaluatorCosts | None = derived(EvaluatorCosts.from_dataset)
    prismatic: tuple[bool, ...] = derived(stored_prismatic)


class SweepSettings(Record, namedtuple("SweepSettings", """
        robot robot_description robot_reference robot_source robot_sha256 input_kind seed
        input_files inputs_sha256 setpoints_total dominance_threshold negligible_threshold
        merged_rule payload_mass random_qdd_max_source command cluster n_workers
        scheduler_address batch_size n_tasks elapsed_s compute_s others""")):
    """The sweep's inputs, settings and run, as stored (None where missing).

    Each field but ``others`` is the global attribute of the same name.

    Attributes
    ----------
    robot, robot_description, robot_reference, robot_source, robot_sha256 : object
        The robot and its file.
    input_kind, seed, input_files, inputs_sha256, setpoints_total : object
        The trajectories: random (with the seed) or given (the files), all inputs' SHA-256,
        the set points in all.
    dominance_threshold, negligible_threshold : object
        s and e.
    merged_rule, payload_mass, random_qdd_max_source, command : object
        The merge rule, the payload [kg], what limits the random accelerations, the command.
    cluster, n_workers, scheduler_address, batch_size, n_tasks, elapsed_s, compute_s : object
        Where and how it ran, and how long [s].
    others : tuple of (str, object)
        Every other attribute (not in :data:`gd_analyze.store.names.SWEEP_ATTRIBUTES`, the
        ones the report says in rows of their own or that are results): a setting added
        later. Sorted by name.
    """


@dataclass(frozen=True, eq=False)
class StoredSweep(View):
    """A sweep as its report reads it.

    Attributes
    ----------
    trajectories, joints : int
        K and n.
    elements : tuple of str, length M
        ``"D11"`` .. ``"hn"``.
    classes : tuple of str, length C
        The dominance classes.
    class_fraction : ndarray, shape (M, C)
        The fraction of the trajectories in each dominance class [1].
    share_tran : ndarray, shape (K, M)
        The translational share of each element on each trajectory [1].
    share_min, share_median, share_max : ndarray, shape (M,)
        The translational share's spread over the trajectories [1].
    round_off : ndarray of bool, shape (K, M)
        The elements that are round-off on each trajectory.
    duration : ndarray, shape (K,)
        Each trajectory's duration [s].
    setpoints : ndarray, shape (K,)
        Each trajectory's set points.
    sources : tuple of str, length K
        Each trajectory's name.
    tau_peak, tau_error_peak, tau_error_relative_peak : ndarray, shape (K, n)
        Per trajectory and joint: peak |tau| [N m or N], and the peak error of the
        trajectory's own model, absolute and relative [1].
    merged_tau_error_peak, merged_tau_error_relative_peak : ndarray, shape (K, n)
        The merged model's peak error per trajectory [N m or N], and relative [1].
    merged_error_peak, merged_error_rms, merged_error_tau_peak : ndarray, shape (n,)
        The merged model's peak and RMS error and peak |tau| over all trajectories.
    merged_error_relative_peak, merged_error_relative_rms : ndarray, shape (n,)
        Its peak and RMS error relative to that peak |tau| [1].
    merged : MergedModel
    settings : SweepSettings
    run : RunRecord
        The software, the run's time, gravity and mounting.
    """

    required, what = REQUIRED, "sweep"

    trajectories: int = derived(lambda ds: int(ds.sizes[SV.TRAJECTORY]))
    joints: int = derived(lambda ds: int(ds.sizes[SV.JOINT]))
    elements: tuple[str, ...] = stored(SV.ELEMENT, texts)
    classes: tuple[str, ...] = stored(SV.CLASS, texts)
    class_fraction: np.ndarray = stored(SV.CLASS_FRACTION)
    share_tran: np.ndarray = stored(SV.SHARE_TRAN)
    share_min: np.ndarray = stored(SV.SHARE_TRAN_MIN)
    share_median: np.ndarray = stored(SV.SHARE_TRAN_MEDIAN)
    share_max: np.ndarray = stored(SV.SHARE_TRAN_MAX)
    round_off: np.ndarray = stored(SV.ROUND_OFF, lambda v: v.astype(bool))
    duration: np.ndarray = stored(SV.DURATION)
    setpoints: np.ndarray = stored(SV.SETPOINTS)
    sources: tuple[str, ...] = stored(SV.SOURCE, texts)
    tau_peak: np.ndarray = stored(SV.TAU_PEAK)
    tau_error_peak: np.ndarray = stored(SV.TAU_ERROR_PEAK)
    tau_error_relative_peak: np.ndarray = stored(SV.TAU_ERROR_RELATIVE_PEAK)
    merged_tau_error_peak: np.ndarray = stored(SV.MERGED_TAU_ERROR_PEAK)
    merged_tau_error_relative_peak: np.ndarray = stored(SV.MERGED_TAU_ERROR_RELATIVE_PEAK)
    merged_error_peak: np.ndarray = stored(SV.MERGED_ERROR_PEAK)
    merged_error_rms: np.ndarray = stored(SV.MERGED_ERROR_RMS)
    merged_error_tau_peak: np.ndarray = stored(SV.MERGED_ERROR_TAU_PEAK)
    merged_error_relative_peak: np.ndarray = stored(SV.MERGED_ERROR_RELATIVE_PEAK)
    merged_error_relative_rms: np.ndarray = stored(SV.MERGED_ERROR_RELATIVE_RMS)
    merged: MergedModel = derived(MergedModel.read)
    settings: SweepSettings = derived(lambda ds: SweepSettings.from_attrs(ds.attrs, others=tuple(
        (k, ds.attrs[k]) for k in sorted(set(ds.attrs) - SWEEP_ATTRIBUTES))))
    run: RunRecord = derived(lambda ds: RunRecord.from_attrs(ds.attrs))


@dataclass(frozen=True, eq=False)
class PayloadSweep(View):
    """The ranking repeated for each load mass on the last link
    (:func:`gd_analyze.jobs.payload.payload_sweep`, or the part a results file stores,
    :func:`payload_part`).

    Attributes
    ----------
    masses : ndarray, shape (P,)
        The load masses [kg].
    elements : tuple of str, length M
        ``"D11"`` .. ``"hn"``.
    share_tran : ndarray, shape (P, M)
        Each element's translational share at each mass [1].
    round_off : ndarray of bool, shape (P, M), or None
        The elements that are round-off in every part (None where not stored).
    dominance : ndarray of str, shape (P, M)
        Each element's class at each mass.
    tau_peak : ndarray, shape (P, n)
        Peak |tau| per joint at each mass [N m or N].
    prismatic : tuple of bool, length n
        The prismatic joints.
    input_file, input_sha256, payload_com, payload_inertia : object
        The trajectory and the load's shape, as stored (None where not).
    dominance_threshold, negligible_threshold : object
        s and e as stored.
    """

    required, what = PAYLOAD_REQUIRED, "payload sweep"

    masses: np.ndarray = stored(Var.PAYLOAD)
    elements: tuple[str, ...] = stored(Var.ELEMENT, texts)
    share_tran: np.ndarray = stored(Var.SHARE_TRAN)
    round_off: np.ndarray | None = stored(Var.ROUND_OFF, lambda v: v.astype(bool), None)
    dominance: np.ndarray = stored(Var.DOMINANCE,
                                   lambda v: np.array(strings(v)).reshape(v.shape))
    tau_peak: np.ndarray = stored(Var.TAU_PEAK)
    prismatic: tuple[bool, ...] = derived(stored_prismatic)
    input_file: Any = stored(Attr.INPUT_FILE, default=None, attr=True)
    input_sha256: Any = stored(Attr.INPUT_SHA256, default=None, attr=True)
    payload_com: Any = stored(Attr.PAYLOAD_COM, default=None, attr=True)
    payload_inertia: Any = stored(Attr.PAYLOAD_INERTIA, default=None, attr=True)
    dominance_threshold: Any = stored(Attr.DOMINANCE_THRESHOLD, default=None, attr=True)
    negligible_threshold: Any = stored(Attr.NEGLIGIBLE_THRESHOLD, default=None, attr=True)


def with_more_tasks(ds: xr.Dataset, tasks: int) -> xr.Dataset:
    """The sweep's dataset with ``tasks`` more tasks counted in its ``n_tasks``.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep's dataset (attribute ``n_tasks``).
    tasks : int
        The tasks submitted after the sweep.

    Returns
    -------
    xarray.Dataset
        A new dataset (the data shared); ``ds`` is not changed.
    """
    return ds.assign_attrs(n_tasks=int(ds.attrs[SA.N_TASKS]) + int(tasks))
