"""The budget rule's merged model of a sweep, as the sweep command builds it: the cheapest form
within EPS, proved over the joint-limit region or on every swept trajectory.

The model itself is built by :mod:`gd_analyze.simplify.merged_model` (pure): on the
trajectories from the peaks of the recursive model's (base parameter, part) contributions that
the dask workers computed per trajectory (:func:`gd_analyze.jobs.sweep.run_sweep` with
``recursive_peaks=True``; :func:`pair_peaks` reads them from the sweep's dataset), or over the
region, where it does not depend on the trajectories (:func:`budget_region_model`). Here the
options are checked, the explicit terms are read from the derivation cache where the
explicit model is derived (where its expansion is estimated cheap,
:func:`gd_analyze.symbolic.explicit_estimate.is_expensive`, as the main job does), and a
region model is measured on every swept trajectory, each said to lie inside the region or not.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..config import defaults
from ..errors import InputError
from ..simplify.budget import DEFAULT_TOLERANCE
from ..simplify.choices import sweep_choices
from ..simplify.deploy import guarantee_region
from ..simplify.merged_model import region_merged_model, trajectory_merged_model
from ..simplify.options import EXPLICIT, FORMS, GUARANTEES
from ..simplify.sweep_model import sweep_validation, trajectories_sha256
from ..store import explicit_cache
from ..store.derivations import DERIVATIONS
from ..store.names import SweepVar as SV
from ..symbolic.explicit_estimate import is_expensive
from .evaluate import coverages

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr
    from numpy.typing import NDArray

    from ..certify.region import RegionLimits
    from ..model.robot import Robot
    from ..simplify.explicit_model import TorqueFunction
    from ..simplify.simplified import SimplifiedModel
    from ..simplify.sweep_model import TrajectoryErrors
    from ..trajectory.trajectory import Trajectory

__all__ = ["pair_peaks", "budget_sweep_model", "budget_region_model"]


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
    for name, value, allowed in (("explicit", explicit, EXPLICIT), ("form", form, FORMS),
                                 ("guarantee", guarantee, GUARANTEES)):
        if value not in allowed:
            raise ValueError(f"{name} must be one of {allowed}, got {value!r}")
    provenance = {**(provenance or {}), "kind": "sweep model", "trajectories": len(trajectories)}
    derive = form == "explicit" or explicit == "always" or (
        explicit == "auto" and not is_expensive(robot))
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
