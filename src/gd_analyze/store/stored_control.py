"""The closed-loop comparison as ``control.h5`` stores it: a typed view.

:class:`StoredControl` holds what the control report and the command line's verdict read: the
controllers and their runs (tracking error and applied torque per controller), the error and
torque figures per joint, the closed-loop torque difference and its measured noise floor, the
gains, the elements the simplified model keeps, the evaluators' costs, and the run's settings
and provenance (:class:`ControlSettings`, :class:`ModelFacts`), as
:func:`gd_analyze.store.control_dataset.control_dataset` stored them. Read once, by
:meth:`StoredControl.of`; values of attributes are kept as stored (None where the file has
none), the reader decides how to write them.
"""

from __future__ import annotations

import types
from collections import namedtuple
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError
from .names import ControlVar as V
from .schema import (
    EvaluatorCosts,
    Record,
    RunRecord,
    View,
    derived,
    stored,
    stored_prismatic,
    strings,
    texts,
)

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr

__all__ = ["REQUIRED_VARIABLES", "ControlSettings", "ModelFacts", "StoredControl"]

#: The gains whose units depend on the joint's type, each stored with ``<name>_units``.
_TYPED_GAINS = (V.INERTIA_SCALE, V.KP_PD, V.KV_PD)
#: Variables a control dataset must have.
REQUIRED_VARIABLES = (V.IS_SETPOINT, V.Q_D, V.ERROR, V.TAU, V.ERROR_PEAK_SETPOINTS,
                      V.ERROR_RMS_SETPOINTS, V.ERROR_PEAK_GRID, V.ERROR_RMS_GRID, V.KP, V.KV,
                      V.KP_PD, V.KV_PD, V.WN, V.ZETA, V.INERTIA_SCALE, V.CHOICE, V.ELEMENT,
                      V.NFEV, V.TAU_PEAK, V.TAU_RMS, V.Q0_OFFSET, V.CONTROLLER_DESCRIPTION,
                      *(f"{k}_units" for k in _TYPED_GAINS))


class ControlSettings(Record, namedtuple("ControlSettings", """
        robot robot_sha256 trajectory_file trajectory_sha256 trajectory_path
        trajectory_derivatives model_file model_sha256 model_path model_trajectory_sha256
        trajectory_is_models plant interpolation integrator rtol atol noise_rtol noise_atol
        noise_nfev noise_factor noise_unmeasured samples setpoints grid_points wn zeta
        verdict_tolerance_revolute verdict_tolerance_prismatic command references""")):
    """The run's files, settings and provenance, as stored (None where missing).

    Each field is the global attribute of the same name.

    Attributes
    ----------
    robot, robot_sha256, trajectory_file, trajectory_sha256, trajectory_path : object
        The robot and the tracked trajectory's file.
    trajectory_derivatives : object
        How the trajectory's derivatives were obtained.
    model_file, model_sha256, model_path, model_trajectory_sha256 : object
        The simplified model's file, and the trajectory it was built on.
    trajectory_is_models : object
        1 where the model was built on this trajectory.
    plant, interpolation, integrator : object
        The simulated arm, the desired motion between set points, the integrator.
    rtol, atol : object
        The integrator's tolerances.
    noise_rtol, noise_atol, noise_nfev, noise_factor, noise_unmeasured : object
        The runs again with tighter tolerances that measure the noise floor of the torque
        difference, or why it was not measured.
    samples, setpoints, grid_points : object
        The times of the runs: set points plus a fine grid.
    wn, zeta : object
        The natural frequency [rad/s] and damping ratio per joint.
    verdict_tolerance_revolute, verdict_tolerance_prismatic : object
        The verdict's tolerance [rad, m].
    command, references : object
        The command line, the method's references.
    """



class ModelFacts(Record, namedtuple("ModelFacts", """
        rule tolerance form base_parameters pairs pairs_dropped pairs_known dropped_pairs
        gravity_dropped c_terms c_terms_kept scope guarantee_kind guarantee_covered
        guarantee_coverage gravity""")):
    """What the simplified model keeps, its rule and its guarantee, as the control run stored
    them from the model file (:func:`gd_analyze.jobs.control.model_facts`).

    Each field is the global attribute ``model_<field>``, which a control dataset must have
    (:meth:`StoredControl.from_dataset`); a dict of attributes lacking one reads it as None.

    Attributes
    ----------
    rule, tolerance, form : object
        The rule (``"budget"``, ``"chapter"``), EPS [1], the form (``"explicit"``,
        ``"recursive"``).
    base_parameters, pairs, pairs_dropped, pairs_known, dropped_pairs, gravity_dropped : object
        A recursive model's base parameters and (parameter, part) pairs: all, dropped, whether
        known, which, and those of gravity.
    c_terms, c_terms_kept : object
        An explicit model's terms of c: all and kept.
    scope, guarantee_kind, guarantee_covered, guarantee_coverage : object
        The model's scope, its guarantee's kind, whether it covers the tracked motion and why.
    gravity : object
        Gravity in the base frame of the arm the model was built for [m/s^2], shape (3,): the
        model's own, which the controlled arm's (``--gravity``) need not equal.
    """



def _by_controller(name):
    """A :func:`derived` field: the variable ``name`` over (controller, ...) by controller."""
    return derived(lambda ds: types.MappingProxyType(
        {c: ds[name].sel(controller=c).values for c in strings(ds[V.CONTROLLER].values)}))


@dataclass(frozen=True, eq=False)
class StoredControl(View):
    """A control dataset as the control report reads it.

    Attributes
    ----------
    controllers : tuple of str, length C
        ``"full"``, ``"simplified"``, ``"pd_gravity"``.
    descriptions : tuple of str
        Each controller's control law.
    prismatic : tuple of bool, length n
        The prismatic joints.
    n : int
        The joints.
    time : ndarray, shape (T,)
        The times of the runs [s].
    is_setpoint : ndarray of bool, shape (T,)
        The times that are set points of the trajectory.
    q_d : ndarray, shape (T, n)
        The desired motion [rad or m].
    error, tau : Mapping of str to ndarray, shape (T, n)
        Per controller, the tracking error q_d - q [rad or m] and the applied torque [N m or N].
    error_peak_setpoints, error_rms_setpoints, error_peak_grid, error_rms_grid :
            Mapping of str to ndarray, shape (n,)
        Per controller, peak and RMS of the tracking error at the set points and on the fine
        grid [rad or m].
    tau_peak, tau_rms : Mapping of str to ndarray, shape (n,)
        Per controller, peak |tau| and RMS of tau on the fine grid [N m or N].
    tau_difference : ndarray, shape (T, n), or None
        The simplified-model controller's torque minus the full-model controller's.
    tau_difference_floor : ndarray, shape (n,), or None
        Its measured integrator-noise floor.
    tau_difference_peak, tau_difference_rms : ndarray, shape (n,), or None
        Its peak and RMS on the fine grid.
    tau_difference_peak_setpoints, tau_difference_rms_setpoints : ndarray, shape (n,), or None
        Its peak and RMS at the set points.
    gains : Mapping of str to ndarray, shape (n,)
        ``wn``, ``zeta``, ``Kp``, ``Kv``, ``inertia_scale``, ``Kp_pd``, ``Kv_pd``.
    gain_units : Mapping of str to tuple of str
        The stored units per joint of ``inertia_scale``, ``Kp_pd`` and ``Kv_pd``.
    q0_offset : ndarray, shape (n,)
        The initial position error [rad or m].
    elements, choice : tuple of str, length M
        The elements of D (i <= j) and h, and the part the simplified model keeps of each.
    costs : EvaluatorCosts or None
        The evaluators' operations per set point.
    settings : ControlSettings
    model : ModelFacts
    run : RunRecord
        The software, the run's time, gravity and mounting.
    """

    controllers: tuple[str, ...] = stored(V.CONTROLLER, texts)
    descriptions: tuple[str, ...] = stored(V.CONTROLLER_DESCRIPTION, texts)
    prismatic: tuple[bool, ...] = derived(stored_prismatic)
    n: int = derived(lambda ds: len(stored_prismatic(ds)))
    time: np.ndarray = stored(V.TIME)
    is_setpoint: np.ndarray = stored(V.IS_SETPOINT, lambda v: np.asarray(v).astype(bool))
    q_d: np.ndarray = stored(V.Q_D)
    error: Mapping[str, np.ndarray] = _by_controller(V.ERROR)
    tau: Mapping[str, np.ndarray] = _by_controller(V.TAU)
    error_peak_setpoints: Mapping[str, np.ndarray] = _by_controller(V.ERROR_PEAK_SETPOINTS)
    error_rms_setpoints: Mapping[str, np.ndarray] = _by_controller(V.ERROR_RMS_SETPOINTS)
    error_peak_grid: Mapping[str, np.ndarray] = _by_controller(V.ERROR_PEAK_GRID)
    error_rms_grid: Mapping[str, np.ndarray] = _by_controller(V.ERROR_RMS_GRID)
    tau_peak: Mapping[str, np.ndarray] = _by_controller(V.TAU_PEAK)
    tau_rms: Mapping[str, np.ndarray] = _by_controller(V.TAU_RMS)
    tau_difference: np.ndarray | None = stored(V.TAU_DIFFERENCE, default=None)
    tau_difference_floor: np.ndarray | None = stored(V.TAU_DIFFERENCE_FLOOR, default=None)
    tau_difference_peak: np.ndarray | None = stored(V.TAU_DIFFERENCE_PEAK, default=None)
    tau_difference_rms: np.ndarray | None = stored(V.TAU_DIFFERENCE_RMS, default=None)
    tau_difference_peak_setpoints: np.ndarray | None = stored(
        V.TAU_DIFFERENCE_PEAK_SETPOINTS, default=None)
    tau_difference_rms_setpoints: np.ndarray | None = stored(
        V.TAU_DIFFERENCE_RMS_SETPOINTS, default=None)
    gains: Mapping[str, np.ndarray] = derived(lambda ds: types.MappingProxyType(
        {k: ds[k].values for k in (V.WN, V.ZETA, V.KP, V.KV, V.INERTIA_SCALE, V.KP_PD, V.KV_PD)}))
    gain_units: Mapping[str, tuple[str, ...]] = derived(lambda ds: types.MappingProxyType({
        k: texts(ds[f"{k}_units"].values) for k in _TYPED_GAINS}))
    q0_offset: np.ndarray = stored(V.Q0_OFFSET)
    elements: tuple[str, ...] = stored(V.ELEMENT, texts)
    choice: tuple[str, ...] = stored(V.CHOICE, texts)
    costs: EvaluatorCosts | None = derived(EvaluatorCosts.from_dataset)
    settings: ControlSettings = derived(lambda ds: ControlSettings.from_attrs(ds.attrs))
    model: ModelFacts = derived(lambda ds: ModelFacts.from_attrs(ds.attrs, "model_"))
    run: RunRecord = derived(lambda ds: RunRecord.from_attrs(ds.attrs))

    @classmethod
    def from_dataset(cls, ds: xr.Dataset, source: str = "<dataset>") -> StoredControl:
        """The view of a control dataset.

        Parameters
        ----------
        ds : xarray.Dataset
            As :func:`gd_analyze.store.control_dataset.control_dataset` builds it.
        source : str, optional
            The file read, for the message.

        Returns
        -------
        StoredControl

        Raises
        ------
        InputError
            If a variable, dim or model's fact (:class:`ModelFacts`) of a control dataset is
            missing (one line naming the first three).
        """
        missing = ([v for v in REQUIRED_VARIABLES if v not in ds.variables]
                   + [a for a in (f"model_{k}" for k in ModelFacts._fields) if a not in ds.attrs])
        if missing or V.CONTROLLER not in ds.dims or V.TIME not in ds.dims:
            raise InputError("not a gd-analyze control dataset "
                             f"(missing {missing[:3] or 'dims'})", source)
        return cls.read(ds)
