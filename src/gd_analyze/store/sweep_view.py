"""Typed views of a sweep's dataset, for the command line's summary and the report.

:class:`StoredSweep` is the whole sweep as its report reads it and the command line prints it
after a run (where and how the trajectories were spread over the dask workers, and per element
the fraction of the trajectories in each dominance class, the spread of its translational share
and the part the merged model keeps: :func:`gd_analyze.store.sweep_datasets.sweep_dataset`,
:func:`gd_analyze.jobs.sweep.run_sweep`). :class:`MergedModel` is the merged model's
record as the sweep report says it: its rule, form, what it keeps, its bound and guarantee,
its costs and its error on the held-out trajectories
(:func:`gd_analyze.jobs.sweep_merged.with_budget_model`,
:func:`gd_analyze.jobs.sweep_merged.with_model_cost`). :class:`PayloadSweep` is a payload
sweep (the ranking against the load on the last link). :func:`with_more_tasks` counts
tasks the run added after the sweep itself (the workers' error measurement).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError
from .schema import View, from_attrs, optional, stored_prismatic, strings
from .stored_model import EvaluatorCosts
from .stored_provenance import RunRecord
from .sweep_datasets import beyond_the_floor
from .sweep_guarantee import merged_guarantee

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr

__all__ = ["MergedModel", "SweepSettings", "StoredSweep", "PayloadSweep",
           "REQUIRED", "PAYLOAD_REQUIRED", "with_more_tasks"]

#: The variables of a payload sweep the report reads.
PAYLOAD_REQUIRED = ("share_tran", "dominance", "choice", "tau_peak")

#: The variables of a sweep dataset the report reads.
REQUIRED = ("share_tran", "dominance", "choice", "source", "duration", "tau_peak",
            "tau_error_relative_peak", "class_fraction", "share_tran_min", "share_tran_median",
            "share_tran_max", "merged_choice", "merged_tau_error_relative_peak",
            "merged_error_peak", "merged_error_rms", "merged_error_tau_peak",
            "merged_error_relative_peak", "merged_error_relative_rms")
#: Attributes the report says in rows of their own (or elsewhere), or that are results: any
#: other attribute is a setting added later, in :attr:`SweepSettings.others`.
SAID = frozenset({
    "robot", "robot_description", "robot_source", "robot_sha256", "gravity", "gravity_units",
    "dominance_threshold", "negligible_threshold", "seed", "input_files", "inputs_sha256",
    "setpoints_total", "merge_rule", "cluster", "n_workers", "scheduler_address", "n_tasks",
    "batch_size", "elapsed_s", "compute_s", "history", "gd_analyze_version", "Conventions",
    "title", "source", "references", "input_kind", "trajectories", "started",
    "robot_reference", "merged_rule", "merged_tolerance", "merged_torque_floor",
    "merged_worst_scaled_error", "payload_mass", "random_qdd_max_source", "command",
    "mounting_base_rpy_deg", "mounting_gravity_base", "mounting_gravity_world",
    "own_model_rule", "merged_form", "merged_c_terms", "merged_c_terms_kept",
    "held_out_trajectories", "merged_base_parameters", "merged_pairs", "merged_pairs_dropped",
    "merged_dropped_pairs", "merged_gravity_dropped", "merged_guarantee_kind",
    "merged_guarantee_statement", "held_out_inside_region"})

#: The fields of :class:`StoredSweep` that are the variable of the same name, as stored.
_AS_STORED = ("class_fraction", "share_tran", "duration", "tau_peak", "tau_error_peak",
              "tau_error_relative_peak", "merged_tau_error_peak",
              "merged_tau_error_relative_peak", "merged_error_peak", "merged_error_rms",
              "merged_error_tau_peak", "merged_error_relative_peak",
              "merged_error_relative_rms")
def _require(ds: xr.Dataset, names: tuple[str, ...], what: str) -> None:
    """Raise InputError naming the variables of ``names`` that ``ds`` lacks."""
    missing = [v for v in names if v not in ds.variables]
    if missing:
        raise InputError(f"not a gd-analyze {what} dataset: missing variable(s) "
                         + ", ".join(missing))


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
    guarantee_statement : object
        The guarantee as the model states it (None where not stored).
    guarantee : dict or None
        :func:`gd_analyze.store.sweep_guarantee.merged_guarantee`: the guarantee and the swept
        trajectories it covers.
    beyond_floor : tuple or None
        :func:`gd_analyze.store.sweep_datasets.beyond_the_floor`.
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

    rule: str
    form: str
    tolerance: Any
    torque_floor: float
    own_rule: str
    guarantee_kind: str
    guarantee_statement: Any
    guarantee: dict | None
    beyond_floor: tuple[float, int, list[int]] | None
    worst_scaled_error: float
    base_parameters: Any
    pairs: Any
    pairs_dropped: Any
    gravity_dropped: str
    c_terms_kept: int
    c_terms: int
    elements: tuple[str, ...]
    choice: tuple[str, ...]
    bound: np.ndarray | None
    scale: np.ndarray | None
    held_out_error_peak: np.ndarray | None
    held_out_tau_peak: np.ndarray | None
    held_out_trajectories: int
    held_out_inside_region: int
    costs: EvaluatorCosts | None
    prismatic: tuple[bool, ...]

    @property
    def region(self) -> bool:
        """bool: its guarantee is proved over the joint-limit region."""
        return self.guarantee_kind == "region"

    @classmethod
    def from_dataset(cls, ds: xr.Dataset) -> MergedModel:
        """The merged model's record of a sweep dataset.

        Parameters
        ----------
        ds : xarray.Dataset
            A sweep with its merged model, its costs and its held-out error
            (:func:`gd_analyze.jobs.sweep_merged.with_budget_model`,
            :func:`gd_analyze.jobs.sweep_merged.with_model_cost`).

        Returns
        -------
        MergedModel
            Attributes missing in an older file take the defaults said above.
        """
        a = ds.attrs
        return cls(
            rule=str(a.get("merged_rule", "chapter")),
            form=str(a.get("merged_form", "explicit")),
            tolerance=a.get("merged_tolerance"),
            torque_floor=float(a.get("merged_torque_floor", 0.0) or 0.0),
            own_rule=str(a.get("own_model_rule", "chapter")),
            guarantee_kind=str(a.get("merged_guarantee_kind", "")),
            guarantee_statement=a.get("merged_guarantee_statement"),
            guarantee=merged_guarantee(ds), beyond_floor=beyond_the_floor(ds),
            worst_scaled_error=float(a.get("merged_worst_scaled_error", np.nan)),
            base_parameters=a.get("merged_base_parameters"), pairs=a.get("merged_pairs"),
            pairs_dropped=a.get("merged_pairs_dropped"),
            gravity_dropped=str(a.get("merged_gravity_dropped", "")),
            c_terms_kept=int(a.get("merged_c_terms_kept", -1)),
            c_terms=int(a.get("merged_c_terms", -1)),
            elements=tuple(strings(ds["element"].values)),
            choice=tuple(strings(ds["merged_choice"].values)),
            bound=optional(ds, "merged_bound"), scale=optional(ds, "merged_scale"),
            held_out_error_peak=optional(ds, "held_out_error_peak"),
            held_out_tau_peak=optional(ds, "held_out_tau_peak"),
            held_out_trajectories=int(a.get("held_out_trajectories", 0)),
            held_out_inside_region=int(a.get("held_out_inside_region", 0)),
            costs=EvaluatorCosts.from_dataset(ds), prismatic=stored_prismatic(ds))


@dataclass(frozen=True)
class SweepSettings:
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
        Every other attribute (not in :data:`SAID`), sorted by name.
    """

    robot: Any
    robot_description: Any
    robot_reference: Any
    robot_source: Any
    robot_sha256: Any
    input_kind: Any
    seed: Any
    input_files: Any
    inputs_sha256: Any
    setpoints_total: Any
    dominance_threshold: Any
    negligible_threshold: Any
    merged_rule: Any
    payload_mass: Any
    random_qdd_max_source: Any
    command: Any
    cluster: Any
    n_workers: Any
    scheduler_address: Any
    batch_size: Any
    n_tasks: Any
    elapsed_s: Any
    compute_s: Any
    others: tuple[tuple[str, Any], ...]


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
        The elements that are round-off on each trajectory (all False in an older file).
    round_off_stored : bool
        ``round_off`` is stored.
    duration : ndarray, shape (K,)
        Each trajectory's duration [s].
    setpoints : ndarray, shape (K,)
        Each trajectory's set points (empty where not stored).
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

    trajectories: int
    joints: int
    elements: tuple[str, ...]
    classes: tuple[str, ...]
    class_fraction: np.ndarray
    share_tran: np.ndarray
    share_min: np.ndarray
    share_median: np.ndarray
    share_max: np.ndarray
    round_off: np.ndarray
    round_off_stored: bool
    duration: np.ndarray
    setpoints: np.ndarray
    sources: tuple[str, ...]
    tau_peak: np.ndarray
    tau_error_peak: np.ndarray
    tau_error_relative_peak: np.ndarray
    merged_tau_error_peak: np.ndarray
    merged_tau_error_relative_peak: np.ndarray
    merged_error_peak: np.ndarray
    merged_error_rms: np.ndarray
    merged_error_tau_peak: np.ndarray
    merged_error_relative_peak: np.ndarray
    merged_error_relative_rms: np.ndarray
    merged: MergedModel
    settings: SweepSettings
    run: RunRecord

    @classmethod
    def from_dataset(cls, ds: xr.Dataset) -> StoredSweep:
        """The view of a sweep dataset.

        Parameters
        ----------
        ds : xarray.Dataset
            As :func:`gd_analyze.jobs.sweep.run_sweep` returns it.

        Returns
        -------
        StoredSweep

        Raises
        ------
        InputError
            If a variable of :data:`REQUIRED` is missing (one line naming them).
        """
        _require(ds, REQUIRED, "sweep")
        a = ds.attrs
        settings = from_attrs(SweepSettings, a,
                              others=tuple((k, a[k]) for k in sorted(set(a) - SAID)))
        return cls(
            trajectories=int(ds.sizes["trajectory"]), joints=int(ds.sizes["joint"]),
            elements=tuple(strings(ds["element"].values)),
            classes=tuple(strings(ds["class"].values)),
            share_min=ds["share_tran_min"].values, share_median=ds["share_tran_median"].values,
            share_max=ds["share_tran_max"].values,
            round_off=(ds["round_off"].values.astype(bool) if "round_off" in ds.variables
                       else np.zeros(ds["share_tran"].shape, bool)),
            round_off_stored="round_off" in ds.variables,
            setpoints=(ds["setpoints"].values if "setpoints" in ds.variables
                       else np.array([])),
            sources=tuple(strings(ds["source"].values)),
            **{k: ds[k].values for k in _AS_STORED},
            merged=MergedModel.from_dataset(ds), settings=settings,
            run=RunRecord.from_attrs(a))


@dataclass(frozen=True, eq=False)
class PayloadSweep(View):
    """The ranking repeated for each load mass on the last link
    (:func:`gd_analyze.jobs.payload.payload_sweep`, or the part a results file stores,
    :func:`gd_analyze.store.sweep_datasets.payload_part`).

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

    masses: np.ndarray
    elements: tuple[str, ...]
    share_tran: np.ndarray
    round_off: np.ndarray | None
    dominance: np.ndarray
    tau_peak: np.ndarray
    prismatic: tuple[bool, ...]
    input_file: Any
    input_sha256: Any
    payload_com: Any
    payload_inertia: Any
    dominance_threshold: Any
    negligible_threshold: Any

    @classmethod
    def from_dataset(cls, ds: xr.Dataset) -> PayloadSweep:
        """The view of a payload sweep.

        Parameters
        ----------
        ds : xarray.Dataset
            With dims ``payload``, ``element`` and ``joint``.

        Returns
        -------
        PayloadSweep

        Raises
        ------
        InputError
            If a variable of :data:`PAYLOAD_REQUIRED` is missing (one line naming them).
        """
        _require(ds, PAYLOAD_REQUIRED, "payload sweep")
        return from_attrs(
            cls, ds.attrs,
            masses=ds["payload"].values, elements=tuple(strings(ds["element"].values)),
            share_tran=ds["share_tran"].values,
            round_off=(ds["round_off"].values.astype(bool) if "round_off" in ds.variables
                       else None),
            dominance=np.array(strings(ds["dominance"].values)).reshape(
                ds["dominance"].shape),
            tau_peak=ds["tau_peak"].values, prismatic=stored_prismatic(ds))


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
    return ds.assign_attrs(n_tasks=int(ds.attrs["n_tasks"]) + int(tasks))
