"""The merged simplified model of a sweep: the chapter rule's read from the dataset, the budget rule's built and put into it.

A sweep (:func:`gd_analyze.jobs.sweep.run_sweep`) stores one merged model for all its
trajectories. :func:`merged_model` reads the chapter rule's merge (a part of an element dropped
only where every trajectory's own model drops it, no error bound) and its validation back from
the dataset as a :class:`~gd_analyze.simplify.simplified.SimplifiedModel`.

The budget rule's model, :func:`budget_sweep_model`, is the cheapest form within EPS: within
EPS x s_i at every state of the robot's joint-limit region, or (the cheaper of a pruned
recursive and a pruned explicit model) within EPS x scale_i on every swept trajectory. It is
built by :mod:`gd_analyze.simplify.merged_model` (pure): on the
trajectories from the peaks of the recursive model's (base parameter, part) contributions that
the dask workers computed per trajectory (:func:`gd_analyze.jobs.sweep.run_sweep` with
``recursive_peaks=True``; :func:`pair_peaks` reads them from the sweep's dataset), or over the
region, where it does not depend on the trajectories (:func:`budget_region_model`). Here the
options are checked, the explicit terms are read from the derivation cache where the
explicit model is derived (where its expansion is estimated cheap,
:func:`gd_analyze.symbolic.explicit_estimate.is_expensive`, as the main job does), and a
region model is measured on every swept trajectory, each said to lie inside the region or not.

:func:`with_budget_model` puts the budget rule's model, its errors and bounds, its guarantee
and which swept trajectories that covers into the dataset in place of the chapter merge;
:func:`with_model_cost` puts what the merged model costs and keeps of c beside it. Source:
Sec. 3.4.1 of Fu, Gonzalez & Lee (1987).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from .._version import VERSION as __version__
from ..config import defaults
from ..errors import InputError
from ..ranking.ranking import DEFAULT_DOMINANCE, DEFAULT_NEGLIGIBLE, element_labels
from ..simplify.budget import DEFAULT_TOLERANCE
from ..simplify.choices import sweep_choices
from ..simplify.deploy import guarantee_region
from ..simplify.merged_model import region_merged_model, trajectory_merged_model
from ..simplify.options import SimplifyOptions
from ..simplify.simplified import SimplifiedModel, choice_masks
from ..simplify.sweep_model import sweep_validation, trajectories_sha256
from ..store import explicit_cache
from ..store.datasets import region_fields
from ..store.derivations import DERIVATIONS
from ..store.names import SweepAttr as SA
from ..store.names import SweepVar as SV
from ..store.schema import require, strings, text_coordinate, var
from ..store.sweep_view import MERGED_ERRORS, merged_error_variables
from ..symbolic.explicit_estimate import is_expensive
from .control import model_cost, model_facts
from .evaluate import coverages
from .peak_jobs import derives_explicit

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr
    from numpy.typing import NDArray

    from ..certify.region import RegionLimits
    from ..model.robot import Robot
    from ..simplify.explicit_model import TorqueFunction
    from ..simplify.sweep_model import TrajectoryErrors
    from ..trajectory.trajectory import Trajectory

__all__ = ["merged_model", "pair_peaks", "budget_sweep_model", "budget_region_model",
           "with_budget_model", "with_model_cost"]


#: The merged model's validation (its torque error over all trajectories) from the sweep's
#: variables: key -> variable, as :func:`gd_analyze.store.sweep_view.merged_error_variables`
#: stores them.
_VALIDATION = {key: name for key, name, *_ in MERGED_ERRORS}


def merged_model(robot: Robot, sweep_ds: xr.Dataset) -> SimplifiedModel:
    """The sweep's merged simplified model of the chapter rule (no error bound).

    Parameters
    ----------
    robot : Robot
        The arm the sweep was run on (checked against the dataset's ``robot_sha256`` and
        number of elements).
    sweep_ds : xarray.Dataset
        A sweep dataset from :func:`~gd_analyze.jobs.sweep.run_sweep` (or read back with
        :func:`~gd_analyze.store.schema.open_sweep`).

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
    The validation is computed by :func:`~gd_analyze.jobs.sweep.run_sweep` along every
    trajectory and stored in the dataset; nothing is recomputed here. Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987).
    """
    require(sweep_ds, (SV.MERGED_CHOICE, *_VALIDATION.values()), "sweep")
    sha = sweep_ds.attrs.get(SA.ROBOT_SHA256, "")
    if sha and robot.sha256 and sha != robot.sha256:
        raise InputError(f"the sweep was computed for robot {sweep_ds.attrs.get('robot')!r} "
                         f"(sha256 {sha[:12]}...), not for {robot.name!r} "
                         f"(sha256 {robot.sha256[:12]}...)")
    labels = strings(sweep_ds[SV.ELEMENT].values)
    if labels != element_labels(robot.n):
        raise InputError(f"the sweep's elements do not match a {robot.n}-joint robot")
    choices = dict(zip(labels, strings(sweep_ds[SV.MERGED_CHOICE].values)))
    choice_masks(choices, robot.n)
    validation = {
        **{key: sweep_ds[name].values.tolist() for key, name in _VALIDATION.items()},
        "trajectories": int(sweep_ds.sizes.get("trajectory", 0)),
        "setpoints": int(sweep_ds.attrs.get(SA.SETPOINTS_TOTAL, 0)),
    }
    provenance: dict[str, Any] = {"gd_analyze_version": __version__,
                                  "kind": "merged model of a sweep",
                  "sweep_version": str(sweep_ds.attrs.get(SA.GD_ANALYZE_VERSION, "")),
                  "merge_rule": str(sweep_ds.attrs.get(SA.MERGE_RULE, "")),
                  "input_kind": str(sweep_ds.attrs.get(SA.INPUT_KIND, ""))}
    if SA.SEED in sweep_ds.attrs:
        provenance["seed"] = int(sweep_ds.attrs[SA.SEED])
    return SimplifiedModel(
        robot=robot, choices=choices,
        dominance_threshold=float(sweep_ds.attrs.get(SA.DOMINANCE_THRESHOLD, DEFAULT_DOMINANCE)),
        negligible_threshold=float(sweep_ds.attrs.get(SA.NEGLIGIBLE_THRESHOLD,
                                                      DEFAULT_NEGLIGIBLE)),
        trajectory_sha256=str(sweep_ds.attrs.get(SA.INPUTS_SHA256, "")),
        validation=validation, provenance=provenance)


def pair_peaks(sweep_ds: xr.Dataset) -> tuple[NDArray[np.float64], ...]:
    """The per-trajectory peaks of the recursive model's contributions stored in a sweep.

    Parameters
    ----------
    sweep_ds : xarray.Dataset
        From :func:`gd_analyze.jobs.sweep.run_sweep` with ``recursive_peaks=True``.

    Returns
    -------
    tau_peak : ndarray, shape (K, n)
        Peak |tau_i| on each trajectory [N m or N].
    peak : ndarray, shape (K, b, 3, n)
        Peak |contribution| of each (base parameter, part) on each trajectory [N m or N].
    whole_peak : ndarray, shape (K, b, n)
        The same per base parameter [N m or N].

    Raises
    ------
    InputError
        If the dataset does not hold them.
    """
    names = ("pair_tau_peak", "pair_peak", "parameter_peak")
    missing = [v for v in names if v not in sweep_ds.variables]
    if missing:
        raise InputError("the sweep holds no peaks of the recursive model's contributions "
                         "(run_sweep(..., recursive_peaks=True)): missing " + ", ".join(missing))
    return tuple(np.asarray(sweep_ds[v].values, float) for v in names)


def budget_sweep_model(robot: Robot, trajectories: Sequence[Trajectory], sweep_ds: xr.Dataset,
                       tolerance: float = DEFAULT_TOLERANCE, torque_floor: float = 0.0,
                       held_out: Sequence[Trajectory] = (),
                       provenance: Mapping[str, Any] | None = None, explicit: str = "auto",
                       form: str = "cheapest", guarantee: str = defaults["guarantee"],
                       region: RegionLimits | None = None,
                       prepared: tuple[SimplifiedModel, TorqueFunction | None] | None = None,
                       errors: TrajectoryErrors | None = None) -> SimplifiedModel:
    """The sweep's merged model of the budget rule: the cheapest form within EPS, proved over
    the joint-limit region or on each swept trajectory.

    Parameters
    ----------
    robot : Robot
        The arm the sweep ran on (with its payload, if any), with n joints.
    trajectories : sequence of Trajectory
        The K swept trajectories, in the dataset's order.
    sweep_ds : xarray.Dataset
        The sweep (:func:`gd_analyze.jobs.sweep.run_sweep`; with ``recursive_peaks=True``
        for a trajectory guarantee).
    tolerance : float, optional
        EPS >= 0.
    torque_floor : float, optional
        TAU [N m]: scale_{t,i} = max(peak |tau_i| on t, TAU); over the region, s_i =
        max(largest |tau_i| found there, TAU).
    held_out : sequence of Trajectory, optional
        Trajectories not swept: the error there is measured, not guaranteed by the sweep
        (a region model's proof covers those inside its region).
    provenance : dict, optional
    explicit : {"auto", "always", "never"}, optional
        Derive the explicit model too: where its expansion is estimated cheap (default),
        always, or never.
    form : {"cheapest", "recursive", "explicit"}, optional
        The model returned: the cheaper of the two (default), or that form (explicit: derived
        whatever ``explicit`` says), as the main job's ``--form``.
    guarantee : {"auto", "region", "trajectory"}, optional
        Where the bound must hold, as the main job's ``--guarantee``
        (:func:`gd_analyze.simplify.deploy.guarantee_region`): over the robot's joint-limit
        region (``"auto"``, the default, where the robot gives position and velocity limits
        for every joint) or on the swept trajectories.
    region : RegionLimits, optional
        The user's region in place of the robot's limits
        (:func:`gd_analyze.simplify.deploy.robot_region`).
    prepared : (SimplifiedModel, callable or None), optional
        Under a region guarantee, :func:`budget_region_model` of the same arguments, built
        earlier (e.g. while the workers ranked the trajectories); it is then only measured.
    errors : callable, optional
        How the model's errors along the trajectories are measured
        (:func:`gd_analyze.simplify.sweep_model.sweep_validation`; e.g. by the workers of a
        dask cluster, :class:`gd_analyze.jobs.sweep.WorkerErrors`).

    Returns
    -------
    SimplifiedModel
        Over the region (:func:`budget_region_model`): the recursive model pruned on bounds
        proved there (never dearer than the exact recursive model), or the exact explicit
        model where that counts fewer operations (``form="cheapest"``) or is asked for
        (``form="explicit"``); its guarantee of kind ``"region"``. On the trajectories: with
        ``form="cheapest"`` the recursive model, or the explicit one where it counts fewer
        operations (multiplications + additions; the recursive one on a tie), so never more
        than the exact recursive model; its guarantee of kind ``"trajectory"``
        (scale: the largest scale_{t,i} over the trajectories). ``costs`` holds the counts
        of the candidates, the exact recursive model and Newton-Euler; ``validation`` as
        :func:`gd_analyze.simplify.sweep_model.sweep_validation`, ``per_trajectory["bound"]``
        the bound on each trajectory [N m] and ``per_trajectory["scale"]`` the scale it is
        relative to (s_i over the region for a region model) [N m]; a region model's
        ``per_trajectory["covered"]`` and ``["coverage"]`` say whether each swept trajectory
        lies inside the region, and why (:func:`gd_analyze.jobs.evaluate.coverage`),
        ``held_out_inside_region`` how many held-out ones do. A recursive model's ``choices``
        are "pruned" where its dropped pairs change the element on the swept trajectories
        (:func:`gd_analyze.simplify.choices.sweep_choices`), else "both".

    Raises
    ------
    InputError
        If a trajectory guarantee is asked for and the dataset holds no recursive peaks.
    ValueError
        If ``explicit``, ``form`` or ``guarantee`` is unknown, or the trajectories do not
        match the dataset.

    Notes
    -----
    Source: the budget of :mod:`gd_analyze.simplify.budget` over several trajectories;
    Sec. 3.4.1 of Fu, Gonzalez & Lee (1987) (a simplified model "at a reduced computation
    time"); the region's bounds as :func:`gd_analyze.simplify.deploy.region_model`.
    """

    trajectories = list(trajectories)
    if sweep_ds.sizes[SV.TRAJECTORY] != len(trajectories):
        raise ValueError(f"{len(trajectories)} trajectories for a sweep of "
                         f"{sweep_ds.sizes['trajectory']}")
    provenance, digest, derive, (box, missing, proved) = _settings(
        robot, trajectories, provenance, explicit, form, guarantee, region)
    K, n = len(trajectories), robot.n
    if proved:              # the bound holds at every state of the region: checked on each
        merged, reference = prepared if prepared is not None else region_merged_model(
            robot, trajectories, box,  # type: ignore[arg-type]  # proved: a region
            tolerance, torque_floor, provenance, digest,
            _terms(robot, derive), form, DERIVATIONS)
        g: Any = merged.guarantee                # a region model's guarantee: never None
        s_i, proved_bound = np.asarray(g.scale, float), np.asarray(g.bound, float)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(proved_bound > 0, proved_bound / s_i, 0.0)
        validation = sweep_validation(merged, trajectories, np.broadcast_to(s_i, (K, n)),
                                      ratio, held_out=held_out, reference=reference,
                                      bound=np.broadcast_to(proved_bound, (K, n)), errors=errors)
        said = coverages(merged, [*trajectories, *held_out])    # one outside: not covered
        validation["per_trajectory"].update(covered=[c["covered"] for c in said[:K]],
                                            coverage=[c["reason"] for c in said[:K]])
        validation["held_out_inside_region"] = sum(c["covered"] for c in said[K:])
        return sweep_choices(dataclasses.replace(merged, validation=validation), trajectories)
    tau_peak, peak, whole_peak = pair_peaks(sweep_ds)
    return trajectory_merged_model(robot, trajectories, tau_peak, peak, whole_peak, tolerance,
                                   torque_floor, held_out, provenance, digest,
                                   _terms(robot, derive), form, box, missing, errors)


def _settings(robot, trajectories, provenance, explicit, form, guarantee, region):
    """The checked settings of :func:`budget_sweep_model`: (provenance, digest of the
    trajectories, whether the explicit model is derived, :func:`guarantee_region`'s triple)."""
    options = SimplifyOptions(explicit=explicit, form=form, guarantee=guarantee)  # each checked
    # asked for beyond its estimated size's limit: refused, as by the main job
    derive = derives_explicit(robot, options) or explicit == "auto" and not is_expensive(robot)
    provenance = {**(provenance or {}), "kind": "sweep model", "trajectories": len(trajectories)}
    return (provenance, trajectories_sha256(trajectories), derive,
            guarantee_region(robot, guarantee, region))


def budget_region_model(robot: Robot, trajectories: Sequence[Trajectory],
                        tolerance: float = DEFAULT_TOLERANCE, torque_floor: float = 0.0,
                        provenance: Mapping[str, Any] | None = None, explicit: str = "auto",
                        form: str = "cheapest", guarantee: str = defaults["guarantee"],
                        region: RegionLimits | None = None
                        ) -> tuple[SimplifiedModel, TorqueFunction | None] | None:
    """The merged model of :func:`budget_sweep_model` under a region guarantee, before it is
    measured on the trajectories: it does not depend on the sweep's ranking.

    Parameters
    ----------
    robot, trajectories, tolerance, torque_floor, provenance, explicit, form, guarantee, region
        As :func:`budget_sweep_model` takes them.

    Returns
    -------
    (SimplifiedModel, callable or None) or None
        The model: the main job's region model (:func:`gd_analyze.simplify.deploy.region_search`
        without the pre-screen, its claim kept as proved in this process,
        :func:`gd_analyze.store.model_trust.remember_claim`; its cost never above the exact
        recursive model's) or the exact explicit model
        (:func:`gd_analyze.simplify.form_choice.exact_explicit_model`) as
        :func:`gd_analyze.simplify.form_choice.choose_form` decides it over the region, its
        inertia check done (:func:`gd_analyze.simplify.form_choice.inertia_checked`),
        ``validation`` empty; and the reference tau_full(q, qd, qdd) its errors are measured
        against (the full explicit model for an explicit model, else None: the G-D terms).
        None where the guarantee is on the trajectories (that model is pruned on the
        ranking's peaks).

    Raises
    ------
    ValueError
        If ``explicit``, ``form`` or ``guarantee`` is unknown.
    """
    trajectories = list(trajectories)
    provenance, digest, derive, (box, _, proved) = _settings(
        robot, trajectories, provenance, explicit, form, guarantee, region)
    if box is None or not proved:
        return None
    return region_merged_model(robot, trajectories, box, tolerance, torque_floor,
                               provenance, digest, _terms(robot, derive), form, DERIVATIONS)


def _terms(robot, derive):
    """The robot's explicit terms from the derivation cache where ``derive``, else None."""
    return explicit_cache.explicit_terms(robot)[0] if derive else None


def with_budget_model(sweep_ds: xr.Dataset, model: SimplifiedModel) -> xr.Dataset:
    """The sweep dataset with the budget rule's merged model in place of the chapter merge.

    Parameters
    ----------
    sweep_ds : xarray.Dataset
        From :func:`~gd_analyze.jobs.sweep.run_sweep` (K trajectories, n joints).
    model : SimplifiedModel
        From :func:`budget_sweep_model` (recursive or
        explicit form) or :func:`gd_analyze.simplify.sweep_model.sweep_model` on the same
        trajectories, in the same order (its ``validation["per_trajectory"]``).

    Returns
    -------
    xarray.Dataset
        A copy without the recursive peaks the merge pruned on (``pair_peak`` ...); with
        ``merged_choice`` = the model's whole-part choices (for the recursive form, which
        drops parameter parts, not element parts: ``pruned`` where those change the element
        on the swept trajectories, else ``both``);
        ``merged_bound`` (trajectory, joint) [N m], the guaranteed bound on each trajectory
        (``per_trajectory["bound"]``); ``merged_tau_error_peak``
        (trajectory, joint) [N m] and ``merged_tau_error_relative_peak`` (divided by that
        trajectory's scale_{t,i} = max(peak |tau_i|, TAU), guaranteed <= EPS; for a model
        proved over the joint-limit region, by its s_i over the region, the same on every
        trajectory, and proved <= EPS where the trajectory lies in the region);
        ``merged_scale`` (trajectory, joint) [N m]; for a region model ``merged_covered``
        (trajectory) [1] (1 where every set point lies in the region) and
        ``merged_coverage`` (trajectory), why (:func:`gd_analyze.jobs.evaluate.coverage`);
        ``merged_error_*`` over all trajectories
        (relative to the peak |tau| over all of them); attributes ``merged_rule`` = "budget",
        ``merged_tolerance`` (EPS), ``merged_torque_floor`` (TAU) [N m],
        ``merged_worst_scaled_error``, ``merge_rule`` (the rule in words) and, where the model
        carries a guarantee, ``merged_guarantee_kind`` (region or trajectory),
        ``merged_guarantee_statement`` (its
        :meth:`~gd_analyze.simplify.guarantee.Guarantee.statement`) and
        ``merged_guarantee_scale_source`` (how a region model's s_i was found, its
        :meth:`~gd_analyze.simplify.guarantee.Guarantee.scale_source`, as the main job's
        ``simplified_guarantee_scale_source``; "" for a trajectory guarantee); where the model
        was measured on held-out trajectories, ``held_out_error_peak`` and
        ``held_out_tau_peak`` (joint) [N m or N] and ``held_out_trajectories`` (their number),
        for a region model ``held_out_inside_region`` (how many lie in the region).

    Raises
    ------
    ValueError
        If the model's per-trajectory errors do not match the dataset's trajectories.

    Notes
    -----
    The guarantee is that of :mod:`gd_analyze.simplify.budget` over several trajectories,
    or that of the joint-limit region (:func:`gd_analyze.simplify.deploy.region_model`).
    """
    torque = sweep_ds[SV.TAU_PEAK].attrs.get("units", "N m") if SV.TAU_PEAK in sweep_ds else "N m"

    v = model.validation
    per = v["per_trajectory"]
    peak = np.asarray(per["peak_abs_error"], float)
    scale = np.asarray(per["scale"], float)
    if peak.shape != (sweep_ds.sizes[SV.TRAJECTORY], sweep_ds.sizes[SV.JOINT]):
        raise ValueError(f"the model's errors have shape {peak.shape}, the sweep has "
                         f"{sweep_ds.sizes['trajectory']} trajectories and "
                         f"{sweep_ds.sizes['joint']} joints")
    with np.errstate(invalid="ignore", divide="ignore"):
        rel = np.where(peak > 0, peak / np.where(scale > 0, scale, 0.0), 0.0)
    ds = sweep_ds.drop_vars([v for v in (SV.PAIR_TAU_PEAK, SV.PAIR_PEAK, SV.PARAMETER_PEAK,
                                         SV.BASE_PARAMETER, SV.PART) if v in sweep_ds.variables])
    eps, g = f"{model.tolerance:g}", model.guarantee
    region = g is not None and g.kind == "region"
    words = _REGION_WORDS if region else _TRAJECTORY_WORDS

    def put(name, dims, data, units, desc):
        ds[name] = var(dims, np.asarray(data), units, desc)

    labels = element_labels(sweep_ds.sizes[SV.JOINT])
    put(SV.MERGED_CHOICE, (SV.ELEMENT,), np.array([model.choices[k] for k in labels], dtype=str),
        "1", f"whole parts kept by the budget rule (EPS = {eps}) {words['where']}"
        if model.recursive is None else "pruned where the recursive model's dropped parts "
        "change the element on the swept trajectories, else both")
    put(SV.MERGED_TAU_ERROR_PEAK, (SV.TRAJECTORY, SV.JOINT), peak, torque,
        "merged model: peak |tau_merged - tau| along the trajectory")
    put(SV.MERGED_SCALE, (SV.TRAJECTORY, SV.JOINT), scale, torque, words["scale"])
    put(SV.MERGED_BOUND, (SV.TRAJECTORY, SV.JOINT), np.asarray(per["bound"], float), torque,
        words["bound"])                 # the guarantee on each trajectory
    put(SV.MERGED_TAU_ERROR_RELATIVE_PEAK, (SV.TRAJECTORY, SV.JOINT), np.nan_to_num(rel, nan=np.inf),
        "1", words["relative"].format(eps=eps))
    if region:                          # the proof holds where the trajectory lies in R
        put(SV.MERGED_COVERED, (SV.TRAJECTORY,), np.asarray(per["covered"], np.int8), "1",
            "1 if every set point of the trajectory lies in the merged model's region, where "
            "its bound is proved; 0 if not (not covered)")
        put(SV.MERGED_COVERAGE, (SV.TRAJECTORY,), np.array(per["coverage"], dtype=str), "1",
            "why the trajectory lies in the merged model's region or not")
    ds.update(merged_error_variables(v, torque))
    held = v.get("held_out") or {}
    if held:                            # measured off the sweep, not guaranteed
        put(SV.HELD_OUT_ERROR_PEAK, (SV.JOINT,), np.array(held["peak_abs_error"], float), torque,
            "merged model: peak |tau_merged - tau| over the held-out trajectories (not "
            "guaranteed)" if not region else "merged model: peak |tau_merged - tau| over the "
            "held-out trajectories (measured; proved only on those inside the region)")
        put(SV.HELD_OUT_TAU_PEAK, (SV.JOINT,), np.array(held["peak_tau"], float), torque,
            "peak |tau| over the held-out trajectories")
        ds.attrs[SA.HELD_OUT_TRAJECTORIES] = int(v.get("held_out_trajectories", 0))
        if region:
            ds.attrs[SA.HELD_OUT_INSIDE_REGION] = int(v.get("held_out_inside_region", 0))
    ds.attrs.update({
        SA.MERGED_RULE: "budget", SA.MERGED_TOLERANCE: float(model.tolerance),
        SA.MERGED_TORQUE_FLOOR: float(model.torque_floor),
        SA.MERGED_WORST_SCALED_ERROR: float(v["worst_scaled_error"]),
        SA.MERGE_RULE: _merge_rule(model)})
    if g is not None:       # its scope, in the model's one sentence, and how s_i was found
        ds.attrs.update({SA.MERGED_GUARANTEE_KIND: g.kind, SA.MERGED_GUARANTEE_STATEMENT:
                         g.statement(), SA.MERGED_GUARANTEE_SCALE_SOURCE: g.scale_source()})
        if g.bound_method:  # how each joint's bound was proved
            put(SV.MERGED_BOUND_METHOD, (SV.JOINT,), np.array(g.bound_method, dtype=str), "1",
                "how the merged model's bound of each joint was proved over the region "
                "(certify.BOUND_METHODS)")
            ds.attrs[SA.MERGED_JOINT_SUM_ARITHMETIC] = g.joint_sum_arithmetic
        region_vars, region_attrs = region_fields(g.region)
        ds.update(region_vars)
        ds.attrs.update(region_attrs)
    return with_model_cost(ds, model)


def _merge_rule(model):
    """The budget rule of a merged model in words (the ``merge_rule`` attribute): how it was
    pruned, and its guarantee as the model states it
    (:meth:`gd_analyze.simplify.guarantee.Guarantee.statement`) for a region model."""
    eps, floor = f"{model.tolerance:g}", f"{model.torque_floor:g}"
    g = model.guarantee
    if g is not None and g.kind == "region":
        how = (f"one {_WHAT[model.form]}, exact (nothing dropped)" if model.form == "explicit"
               else f"one {_WHAT[model.form]} whose dropped {_UNITS[model.form]}' bounds "
                    f"proved over the joint-limit region sum to at most EPS = {eps} x s_i "
                    f"(s_i = max(largest |tau_i| found over the region, {floor} N m))")
        return f"budget rule over the joint-limit region: {how}; {model.scope()}"
    return (f"budget rule: one {_WHAT[model.form]} whose dropped "
            f"{_UNITS[model.form]}' peaks, each divided by its trajectory's scale_i "
            f"= max(peak |tau_i|, {floor} N m), sum to at most EPS = "
            f"{eps}: guaranteed within {eps} x scale_i on every swept trajectory")


#: The descriptions of the per-trajectory variables of a merged model, by its guarantee.
_TRAJECTORY_WORDS = {
    "where": "on every swept trajectory",
    "scale": "scale_i = max(peak |tau_i|, torque floor) along the trajectory",
    "bound": "merged model: guaranteed bound on |tau_merged - tau| along the trajectory "
             "(<= EPS x scale_i)",
    "relative": "merged model: peak |tau_merged - tau| / scale_i along the trajectory "
                "(guaranteed <= {eps})"}
_REGION_WORDS = {
    "where": "over the joint-limit region",
    "scale": "s_i = max(largest |tau_i| found over the joint-limit region, torque floor), the "
             "guarantee's scale (the same on every trajectory)",
    "bound": "merged model: bound on |tau_merged - tau| proved at every state of the "
             "joint-limit region (<= EPS x s_i), on the trajectory where it lies in the region",
    "relative": "merged model: peak |tau_merged - tau| / s_i along the trajectory (proved "
                "<= {eps} where the trajectory lies in the region, merged_covered)"}


#: The merged model of each form, and what its budget drops, in the words of ``merge_rule``.
_WHAT = {"recursive": "customized recursive Newton-Euler model on the base parameters",
         "explicit": "explicit G-D model"}
_UNITS = {"recursive": "(base parameter, part) pairs", "explicit": "terms"}


def with_model_cost(sweep_ds: xr.Dataset, model: SimplifiedModel) -> xr.Dataset:
    """The sweep dataset with its merged model's cost and gravity terms, counted on the model.

    Parameters
    ----------
    sweep_ds : xarray.Dataset
        A sweep dataset (:func:`~gd_analyze.jobs.sweep.run_sweep`).
    model : SimplifiedModel
        The merged model written beside it (budget rule: :func:`with_budget_model`'s; chapter
        rule: :func:`merged_model`'s).

    Returns
    -------
    xarray.Dataset
        A copy with ``multiplications`` and ``additions`` (evaluator) [1]: operations per set
        point of the merged model, the exact recursive model, the full explicit model (where
        derived) and the project's Newton-Euler, last
        (:func:`gd_analyze.jobs.control.model_cost`, counted, never timed); attributes
        ``merged_form`` (recursive or explicit), ``merged_c_terms_kept`` and
        ``merged_c_terms`` (its terms of c and the full explicit model's; -1 when not
        counted: the chapter rule keeps c whole, :func:`gd_analyze.jobs.control.model_facts`);
        for the recursive form ``merged_base_parameters``, ``merged_pairs`` and
        ``merged_pairs_dropped`` (the (parameter, part) pairs that contribute on the swept
        trajectories, and those dropped), ``merged_dropped_pairs`` and
        ``merged_gravity_dropped`` (names, comma-separated).

    Notes
    -----
    Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987) (a simplified model "at a reduced
    computation time"); Table 3.5 for Newton-Euler.
    """

    cost = model_cost(model)
    facts = model_facts(model)
    names = [("merged model" + name[len("simplified model"):])
             if name.startswith("simplified model") else name for name in cost["evaluators"]]
    ds = sweep_ds.assign_coords(evaluator=text_coordinate(SV.EVALUATOR, names,
                                                          "evaluator of tau at one set point"))
    for name, what in ((SV.MULTIPLICATIONS, "multiplications"),
                       (SV.ADDITIONS, "additions and subtractions")):
        ds[name] = var((SV.EVALUATOR,), np.array(cost[name], np.int64), "1",
                       f"{what} per set point (counted)")
    # the model's facts as control.h5 states them (model_<fact>), here merged_<fact>
    recursive = ("base_parameters", "pairs", "pairs_dropped", "dropped_pairs", "gravity_dropped")
    ds.attrs.update({f"merged_{k}": facts[k] for k in ("form", "c_terms_kept", "c_terms",
                     *(recursive if facts["form"] == "recursive" else ()))})
    return ds
