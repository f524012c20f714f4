"""Sweep datasets: the dominance ranking over many trajectories, and over payloads.

Schemas of ``sweep.h5`` (dim ``trajectory``) and of a payload sweep (dim ``payload``), built from
the per-trajectory results of :mod:`gd_analyze.jobs.sweep` and
:mod:`gd_analyze.jobs.payload`. Write them with :func:`gd_analyze.store.schema.write_dataset`
and read them back with :func:`gd_analyze.store.schema.open_sweep`. Source: Sec. 3.4.1 of Fu,
Gonzalez & Lee (1987).
"""

from __future__ import annotations

import hashlib
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..ranking.ranking import (
    CLASSES,
    arm_scales,
    element_labels,
    element_units,
    is_round_off,
    parse_element_label,
)
from .datasets import joint_units, units_attribute
from .schema import (
    MIXED_UNITS,
    element_coords,
    flag,
    global_attributes,
    joint_coordinate,
    joint_type_var,
    var,
)

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr
    from numpy.typing import ArrayLike

    from ..model.robot import Robot
    from ..trajectory.trajectory import Trajectory

__all__ = ["inputs_attributes", "sweep_dataset", "payload_dataset", "sweep_payloads_dataset",
           "embed_payload", "payload_part", "beyond_the_floor", "embed_pair_peaks"]

#: At most this many input files are listed by name in the global attributes (all are in the
#: per-trajectory variables ``source`` and ``input_sha256``); HDF5 attributes stay small.
_MAX_LISTED_FILES = 20
_RANDOM_SOURCE = re.compile(r"^random-(\d+)-(\d+)$")
_REFERENCES = "Fu, Gonzalez & Lee (1987), Robotics, Sec. 3.4.1; Lee, Lee & Nigam (1983)"


#: How the envelope of the shares treats round-off (:func:`is_round_off`).
_AS_DATA = ("; 0 or 1 on a trajectory where a part is round-off (at most 1e-12 of the element's "
            "scale or 64 eps of the arm's), a trajectory where the element is round-off left out (NaN: on every one)")


def _torque_units(robot, which="tau"):
    """The ``units`` of a per-joint torque (``which="tau"``) or position (``"q"``) variable:
    N m, N (rad, m), or both with where to read them."""

    return units_attribute(joint_units(robot.prismatic, which), "joint_type")


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


def element_arm_scales(scale: ArrayLike, labels: Sequence[str],
                       prismatic: Sequence[bool] | np.ndarray) -> np.ndarray:
    """The arm's scale of every ranked element on every trajectory: the largest scale among the
    elements of the same units on that trajectory
    (:func:`gd_analyze.ranking.ranking.arm_scales`), so that the sweep tells round-off
    from data by the same rule as the main report.

    Parameters
    ----------
    scale : array_like, shape (K, M)
        Each element's own scale per trajectory.
    labels : sequence of str, shape (M,)
        The element labels.
    prismatic : sequence of bool, shape (n,)
        The joint types.

    Returns
    -------
    ndarray, shape (K, M)
    """
    n = len(prismatic)
    units = [element_units(*parse_element_label(str(lab), n), prismatic)  # type: ignore[call-arg]  # (kind, i, j), prismatic
             for lab in labels]
    return np.array([arm_scales(row, units) for row in np.atleast_2d(scale)])


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
    share = np.array([r["share_tran"] for r in results])
    classes = np.array([r["classes"] for r in results], dtype=str)
    choice = np.array([[r["choices"][lab] for lab in labels] for r in results], dtype=str)
    peak_total = np.array([r["peaks"]["peak_total"] for r in results])
    peak_part = np.max([[r["peaks"][k] for k in ("peak_tran", "peak_rot", "peak_total")]
                        for r in results], axis=1)
    scale = np.array([r["peaks"]["scale"] for r in results])
    arm = element_arm_scales(scale, labels, robot.prismatic)  # type: ignore[arg-type]  # never None (Robot.__post_init__)
    round_off = is_round_off(peak_part, scale, arm_scale=arm)
    # the share as data: 0 or 1 where one part is round-off of the element's scale or of the
    # arm's (a share of 4e-14 or of 2e-12 is round-off, not data), left out where the element
    # is round-off on a trajectory
    tran_off, rot_off = (is_round_off(np.array([r["peaks"][k] for r in results]), scale,
                                      arm_scale=arm)
                         for k in ("peak_tran", "peak_rot"))
    share_data = np.where(tran_off & ~rot_off, 0.0, np.where(rot_off & ~tran_off, 1.0, share))
    share_data = np.where(round_off, np.nan, share_data)
    summ = [r["summary"] for r in results]
    err = [s["error"] for s in summ]

    def per_joint(key):
        return np.array([e[key] for e in err], dtype=float)

    if merged_stats is None:
        nan = np.full(robot.n, np.nan)
        merged_stats = [{"peak": nan, "peak_tau": nan, "sum_sq": nan, "count": 0}] * K
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
        s_min, s_med, s_max = (np.nanmin(share_data, axis=0),
                               np.nanmedian(share_data, axis=0), np.nanmax(share_data, axis=0))
    torque, position = _torque_units(robot), _torque_units(robot, "q")
    data_vars = {
        "share_tran": var(("trajectory", "element"), share, "1",
                           "translational share sum|tran| / (sum|tran| + sum|rot|)"),
        "dominance": var(("trajectory", "element"), classes, "1",
                          "dominance class (translational, rotational, both, negligible)"),
        "choice": var(("trajectory", "element"), choice, "1",
                       "part kept by the trajectory's own simplified model "
                       "(tran, rot, both, none)"),
        "peak_total": var(("trajectory", "element"), peak_total, MIXED_UNITS,
                           "peak |translational + rotational| along the trajectory"),
        "round_off": flag(("trajectory", "element"), round_off, "every part of the element is "
                          "round-off on the trajectory (1: at most 1e-12 of its scale; its "
                          "share_tran is noise), else 0"),
        "source": var(("trajectory",), np.array([s["source"] for s in summ], dtype=str), "1",
                       "trajectory source (file name or random-<seed>-<index>)"),
        "input_sha256": var(("trajectory",), np.array([s["sha256"] for s in summ], dtype=str),
                             "1", "SHA-256 of the trajectory file (empty if generated)"),
        "duration": var(("trajectory",), np.array([s["duration"] for s in summ]), "s",
                         "trajectory duration"),
        "setpoints": var(("trajectory",), np.array([s["setpoints"] for s in summ]), "1",
                          "number of set points"),
        "q_start": var(("trajectory", "joint"), np.array([s["q_start"] for s in summ]), position,
                        "joint position at the first set point"),
        "q_goal": var(("trajectory", "joint"), np.array([s["q_goal"] for s in summ]), position,
                       "joint position at the last set point"),
        "tau_peak": var(("trajectory", "joint"), np.array([s["tau_peak"] for s in summ]),
                         torque, "peak |tau| of the full model along the trajectory"),
        "tau_error_peak": var(("trajectory", "joint"), per_joint("peak_abs_error"), torque,
                               "own simplified model: peak |tau_simplified - tau|"),
        "tau_error_rms": var(("trajectory", "joint"), per_joint("rms_error"), torque,
                              "own simplified model: RMS of |tau_simplified - tau|"),
        "tau_error_relative_peak": var(("trajectory", "joint"),
                                        per_joint("relative_peak_error"), "1",
                                        "own simplified model: peak |tau_simplified - tau| / "
                                        "peak |tau|"),
        "tau_error_relative_rms": var(("trajectory", "joint"), per_joint("relative_rms_error"),
                                       "1", "own simplified model: RMS |tau_simplified - tau| / "
                                            "peak |tau|"),
        "merged_tau_error_peak": var(("trajectory", "joint"), m_peak, torque,
                                      "merged model: peak |tau_merged - tau| along the "
                                      "trajectory"),
        "merged_tau_error_relative_peak": var(("trajectory", "joint"), m_rel, "1",
                                               "merged model: peak |tau_merged - tau| / peak "
                                               "|tau| along the trajectory"),
        "class_fraction": var(("element", "class"), fraction, "1",
                               "fraction of the trajectories in which the class holds"),
        "share_tran_min": var(("element",), s_min, "1",
                               "smallest translational share over the trajectories" + _AS_DATA),
        "share_tran_median": var(("element",), s_med, "1",
                                  "median translational share over the trajectories"
                                  + _AS_DATA),
        "share_tran_max": var(("element",), s_max, "1",
                               "largest translational share over the trajectories" + _AS_DATA),
        "merged_choice": var(("element",), np.array([merged[lab] for lab in labels], dtype=str),
                              "1", "part kept by the merged model of the chapter rule: a "
                                   "part is dropped only where every trajectory drops it"),
        "merged_error_peak": var(("joint",), all_peak, torque,
                                  "merged model: peak |tau_merged - tau| over all trajectories"),
        "merged_error_rms": var(("joint",), all_rms, torque,
                                 "merged model: RMS of |tau_merged - tau| over all set points "
                                 "of all trajectories"),
        "merged_error_tau_peak": var(("joint",), all_tau, torque,
                                      "peak |tau| over all trajectories"),
        "merged_error_relative_peak": var(("joint",), all_rel_peak, "1",
                                           "merged model: peak error / peak |tau|, over all "
                                           "trajectories"),
        "merged_error_relative_rms": var(("joint",), all_rel_rms, "1",
                                          "merged model: RMS error / peak |tau|, over all "
                                          "trajectories"),
    }
    data_vars["joint_type"] = joint_type_var(robot)
    coords = element_coords(n, robot.prismatic, robot.joint_names())
    coords["trajectory"] = ("trajectory", np.arange(K),
                            {"long_name": "trajectory index", "units": "1"})
    coords["class"] = ("class", np.array(CLASSES, dtype=str),
                       {"long_name": "dominance class", "units": "1"})
    attrs = global_attributes(robot, f"G-D dominance sweep of {robot.name} over {K} trajectories",
                              references=_REFERENCES, dominance_threshold=float(dominance),
                              negligible_threshold=float(negligible))
    attrs.update(inputs_attributes(trajectories))
    attrs["setpoints_total"] = int(sum(s["setpoints"] for s in summ))
    attrs["merge_rule"] = ("keep_tran = any trajectory keeps tran (tran or both); keep_rot = "
                           "any keeps rot (rot or both); merged = both/tran/rot/none "
                           "(chapter rule: no error bound)")
    attrs["merged_rule"] = "chapter"
    # each trajectory's own simplified model (tau_error_*): the chapter's share-based classes
    attrs["own_model_rule"] = "chapter"
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


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
    import xarray as xr

    n = robot.n
    labels = element_labels(n)
    I_p = np.asarray(inertia, dtype=float)
    I_p = np.diag(I_p) if I_p.shape == (3,) else I_p.reshape(3, 3)
    torque = _torque_units(robot)
    data_vars = {
        "share_tran": var(("payload", "element"), np.array([r["share_tran"] for r in results]),
                           "1", "translational share sum|tran| / (sum|tran| + sum|rot|)"),
        "dominance": var(("payload", "element"),
                          np.array([r["classes"] for r in results], dtype=str), "1",
                          "dominance class (translational, rotational, both, negligible)"),
        "choice": var(("payload", "element"),
                       np.array([[r["choices"][lab] for lab in labels] for r in results],
                                dtype=str), "1",
                       "part kept by the simplified model (tran, rot, both, none)"),
        "peak_total": var(("payload", "element"),
                           np.array([r["peaks"]["peak_total"] for r in results]), MIXED_UNITS,
                           "peak |translational + rotational| along the trajectory"),
        "tau_peak": var(("payload", "joint"),
                         np.array([r["summary"]["tau_peak"] for r in results]), torque,
                         "peak |tau| of the full model along the trajectory"),
        "round_off": _round_off_var(np.array([is_round_off(
            np.max([r["peaks"][k] for k in ("peak_tran", "peak_rot", "peak_total")], axis=0),
            r["peaks"]["scale"], arm_scale=element_arm_scales(
                r["peaks"]["scale"], labels,
                robot.prismatic)[0]) for r in results]),  # type: ignore[arg-type]  # never None (Robot.__post_init__)
            "along the trajectory"),
        "tau_error_relative_peak": var(
            ("payload", "joint"),
            np.array([r["summary"]["error"]["relative_peak_error"] for r in results]), "1",
            "own simplified model: peak |tau_simplified - tau| / peak |tau|"),    }
    data_vars["joint_type"] = joint_type_var(robot)
    coords = element_coords(n, robot.prismatic, robot.joint_names())
    coords["payload"] = ("payload", masses, {"long_name": "payload mass on the last link",
                                             "units": "kg"})
    attrs = global_attributes(robot, f"G-D dominance of {robot.name} vs payload along "
                                     f"{Path(str(trajectory.source)).name}",
                              references=_REFERENCES, dominance_threshold=float(dominance),
                              negligible_threshold=float(negligible))
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
    import xarray as xr

    frac, share, dom, choice, tau = (np.array(x) for x in list(zip(*parts))[:5])
    n = robot.n
    torque = _torque_units(robot)
    extra = ({"round_off": _round_off_var(np.array([p[5] for p in parts]),
                                          "on every trajectory")}
             if all(len(p) > 5 for p in parts) else {})

    return xr.Dataset(
        {**extra,
         "class_fraction": var(("payload", "element", "class"), frac, "1",
                               "fraction of the trajectories in each class"),
         "share_tran": var(("payload", "element"), share, "1",
                           "median translational share over the trajectories"),
         "dominance": var(("payload", "element"), dom.astype(str), "1",
                          "most frequent dominance class over the trajectories"),
         "choice": var(("payload", "element"), choice.astype(str), "1",
                       "merged share-based choice (chapter rule, no error bound)"),
         "tau_peak": var(("payload", "joint"), tau, torque,
                         "peak |tau| over all trajectories"),
         "joint_type": joint_type_var(robot)},
        coords={"payload": ("payload", np.asarray(masses, float),
                            {"units": "kg", "long_name": "load mass on the last link"}),
                "element": ("element", np.array(element_labels(n), dtype=str),
                            {"units": "1", "long_name": "ranked element of D (i <= j) or h"}),
                "class": ("class", np.array(CLASSES, dtype=str),
                          {"units": "1", "long_name": "dominance class"}),
                "joint": joint_coordinate(robot.joint_names())},
        attrs={**global_attributes(robot, f"G-D dominance of {robot.name} vs payload over "
                                          f"{n_trajectories} trajectories",
                                   references=_REFERENCES, dominance_threshold=float(dominance),
                                   negligible_threshold=float(negligible)),
               "kind": "payload",
               "payload_com": np.asarray(com, dtype=float).reshape(3),
               "payload_com_units": "m",
               "payload_inertia": np.asarray(inertia, dtype=float).reshape(-1),
               "payload_inertia_units": "kg m2 (principal moments)"})


def _round_off_var(flags, where):
    """The (payload, element) flag: every part of the element is round-off (its share is
    noise, :func:`gd_analyze.ranking.ranking.is_round_off`)."""
    return flag(("payload", "element"), flags, f"every part of the element is round-off {where} "
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
        merge prunes on (:mod:`gd_analyze.jobs.sweep_budget`, which removes them again).

    Raises
    ------
    ValueError
        If a shape does not match the dataset.
    """
    K, n = ds.sizes["trajectory"], ds.sizes["joint"]
    tau_peak, peak, whole_peak = (np.asarray(x, float) for x in (tau_peak, peak, whole_peak))
    b = len(names)
    if tau_peak.shape != (K, n) or peak.shape != (K, b, 3, n) or whole_peak.shape != (K, b, n):
        raise ValueError(f"peaks of shapes {tau_peak.shape}, {peak.shape}, {whole_peak.shape} "
                         f"do not fit {K} trajectories, {b} base parameters, {n} joints")
    torque = ds["tau_peak"].attrs.get("units", "N m")
    out = ds.assign_coords(base_parameter=("base_parameter", np.array(list(names), dtype=str)),
                           part=("part", np.array(["inertial", "velocity", "gravity"])))
    out["pair_tau_peak"] = var(("trajectory", "joint"), tau_peak, torque,
                               "peak |tau_i|, the sum of the base-parameter contributions")
    out["pair_peak"] = var(("trajectory", "base_parameter", "part", "joint"), peak, torque,
                           "peak |contribution| of a (base parameter, part) to tau_i")
    out["parameter_peak"] = var(("trajectory", "base_parameter", "joint"), whole_peak, torque,
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
    renamed = payload.drop_vars([v for v in ("joint_type",) if v in payload.variables])
    renamed = renamed.rename({v: f"payload_{v}" for v in renamed.data_vars})
    return renamed.drop_vars([c for c in ("element_units",) if c in renamed.coords])


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
    if "merged_tau_error_peak" not in ds.variables or "merged_tolerance" not in ds.attrs \
            or ds.attrs.get("merged_guarantee_kind") == "region":
        return None
    err = np.asarray(ds["merged_tau_error_peak"].values, float)
    peak = np.asarray(ds["tau_peak"].values, float)
    with np.errstate(invalid="ignore", divide="ignore"):
        rel = np.where(err > 0, err / np.where(peak > 0, peak, 0.0), 0.0)
    rel = np.nan_to_num(rel, nan=np.inf).max(axis=0)
    eps = float(ds.attrs["merged_tolerance"])
    over = np.flatnonzero(rel > eps * (1 + 1e-9))
    if not over.size:
        return None
    j = int(np.argmax(rel))
    return float(rel[j]), j + 1, [int(k) + 1 for k in over]

