"""The closed-loop check's dataset (``control.h5``): schema and writer.

Built from a :class:`gd_analyze.jobs.control.ControlResult`; every variable has ``units``
and ``long_name``, the global attributes carry the provenance (see
:func:`gd_analyze.store.schema.global_attributes`). Sources: Fu, Gonzalez & Lee (1987),
Eq. (3.4-24) and Sec. 3.4.1; Ch. 5 (computed-torque control).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ..model.drives import COULOMB_BAND
from ..ranking.labels import element_units, joint_gain_units
from ..ranking.ranking import element_labels
from .datasets import JOINT_UNIT_COORDS, joint_units, units_attribute, units_by_type
from .names import ControlVar as V
from .schema import flag, global_attributes, joint_type_var, text_coordinate, var, write_dataset

if TYPE_CHECKING:                       # for the type hints only
    import os

    import xarray as xr

__all__ = ["control_dataset", "write_control_dataset", "control_size", "peak_rms", "pd_name"]


def pd_name(gravity: ArrayLike | None) -> str:
    """The name of the PD controller (``pd_gravity``) of a run, true of its controlled arm.

    Parameters
    ----------
    gravity : array_like, shape (3,), or None
        Gravity in the controlled arm's base frame [m/s^2] (the control dataset's ``gravity``);
        None where not stored.

    Returns
    -------
    str
        ``"PD + gravity"``: PD control plus the arm's gravity loading c(q); ``"PD"`` where
        every component of gravity is 0, since c is linear in g (Fu, Gonzalez & Lee 1987,
        Eq. (3.4-24)) and so identically 0: the law is plain PD. The controller's key,
        ``pd_gravity``, and the gains' names stay the same.

    Examples
    --------
    >>> pd_name([0.0, 0.0, -9.81]), pd_name([0.0, 0.0, 0.0]), pd_name(None)
    ('PD + gravity', 'PD', 'PD + gravity')
    """
    return "PD" if gravity is not None and not np.any(np.asarray(gravity, float)) else \
        "PD + gravity"


def control_size(samples: int, n: int, controllers: int = 3) -> int:
    """Bytes of the per-sample variables of control.h5 (uncompressed), plus 1 MiB: an
    over-estimate of the file, checked before the run
    (:func:`gd_analyze.store.staging.check_free_space`).

    Parameters
    ----------
    samples : int
        Samples of the run, at most the set points plus the fine grid's points
        (:func:`gd_analyze.jobs.control.run_control`).
    n : int
        Joints.
    controllers : int, optional
        Controllers run (three by default).

    Returns
    -------
    int
        8 bytes per value: time and ``is_setpoint``, four vectors of n (``q_d``, ``qd_d``,
        ``qdd_d``, ``tau_difference``) and, per controller, four more (``q``, ``qd``,
        ``tau``, ``error``) per sample; the per-joint figures, gains and attributes are in the
        1 MiB [bytes].

    Examples
    --------
    >>> control_size(2021, 6) - (1 << 20) == 8 * 2021 * (2 + 4 * 6 + 3 * 4 * 6)
    True
    """
    return 8 * samples * (2 + 4 * n + controllers * 4 * n) + (1 << 20)


def peak_rms(x: ArrayLike, axis: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Peak |x| and the RMS of x along an axis.

    Parameters
    ----------
    x : array_like
        Samples, e.g. shape (T, n) [N m or rad].
    axis : int, optional
        The axis of the samples.

    Returns
    -------
    peak, rms : ndarray
        ``x``'s shape without ``axis``, in ``x``'s units.
    """
    x = np.asarray(x, dtype=float)
    return np.abs(x).max(axis=axis), np.sqrt((x**2).mean(axis=axis))


def gain_units(prismatic: Sequence[bool] | np.ndarray) -> dict[str, list[str]]:
    """Per joint, the units of the PD gains and of D_ii (which scales them), from the joint
    types (:func:`gd_analyze.ranking.labels.joint_gain_units`, ``element_units``)."""

    gains = [joint_gain_units(bool(p)) for p in prismatic]
    return {"inertia_scale": [element_units("D", j, j, prismatic) for j in range(len(prismatic))],
            "Kp_pd": [kp for kp, _ in gains], "Kv_pd": [kv for _, kv in gains]}


def control_dataset(result: Any, settings: Mapping[str, str | float | int] | None = None
                    ) -> xr.Dataset:
    """The closed-loop comparison as an xarray Dataset.

    Parameters
    ----------
    result : ControlResult
        As :func:`gd_analyze.jobs.control.run_control` returns it.
    settings : dict of str to (str or float or int), optional
        Extra global attributes, e.g. ``{"command": ...}``: the command line as
        :func:`gd_analyze.cli.main` was given it, as the main job and the sweep store it.

    Returns
    -------
    xarray.Dataset
        Dims ``controller``, ``time``, ``joint`` (and ``element`` for the model's choices,
        ``evaluator`` for the cost); every variable and coordinate has ``units`` and
        ``long_name``; CF-style global attributes with the gd-analyze version, the robot and
        its SHA-256, the trajectory and model files and their SHA-256, the gains and the
        solver settings.

    Notes
    -----
    Variables: ``q_d``, ``qd_d``, ``qdd_d`` (time, joint); ``q``, ``qd``, ``tau``, ``error``
    (controller, time, joint); ``error_peak_setpoints``, ``error_rms_setpoints``,
    ``error_peak_grid``, ``error_rms_grid``, ``tau_peak``, ``tau_rms`` (controller, joint);
    ``nfev``, ``success`` (controller); ``tau_difference`` (time, joint) and its
    ``tau_difference_peak``, ``tau_difference_rms``, its measured integrator noise
    ``tau_difference_noise`` and noise floor ``tau_difference_floor`` (joint) when both
    computed-torque controllers ran; the gains (joint); ``is_setpoint`` (time); ``choice`` (element);
    ``multiplications``, ``additions`` (evaluator) when the cost was
    measured. The attribute ``command`` holds the command line when ``settings`` gives it.
    The attribute ``trajectory_is_models`` is 1 if the tracked trajectory is the one
    the simplified model was derived on (same SHA-256), else 0.
    """
    import xarray as xr


    robot, g, prov = result.robot, result.gains, result.provenance
    pd = pd_name(robot.gravity)         # the controlled arm's: "PD" where it has no gravity
    n = robot.n
    names = result.controllers
    runs = [result.runs[c] for c in names]
    stack = lambda key: np.stack([getattr(r, key) for r in runs])   # noqa: E731
    figs = [result.error_figures(c) for c in names]
    fig = lambda key: np.array([f[key] for f in figs])              # noqa: E731
    tau_pk, tau_rm = zip(*(peak_rms(r.tau) for r in runs))
    CTJ, CJ = (V.CONTROLLER, V.TIME, V.JOINT), (V.CONTROLLER, V.JOINT)
    prismatic = np.asarray(robot.prismatic, bool)
    U = {k: units_by_type(prismatic, k) for k in ("q", "qd", "qdd", "tau")}
    per_joint = gain_units(prismatic)
    U.update({k: units_attribute(v, f"{k}_units") for k, v in per_joint.items()})
    data_vars = {
        V.IS_SETPOINT: flag((V.TIME,), result.is_setpoint, "sample is a set point of the "
                            "trajectory (1) or on the fine grid (0)", "fine_grid set_point"),
        V.Q_D: var((V.TIME, V.JOINT), result.q_d, U["q"], "desired joint position"),
        V.QD_D: var((V.TIME, V.JOINT), result.qd_d, U["qd"], "desired joint velocity"),
        V.QDD_D: var((V.TIME, V.JOINT), result.qdd_d, U["qdd"], "desired joint acceleration"),
        V.Q: var(CTJ, stack("q"), U["q"], "joint position of the controlled arm"),
        V.QD: var(CTJ, stack("qd"), U["qd"], "joint velocity of the controlled arm"),
        V.TAU: var(CTJ, stack("tau"), U["tau"], "joint torque applied by the controller"),
        V.ERROR: var(CTJ, stack("error"), U["q"], "tracking error q_d - q"),
        V.ERROR_PEAK_SETPOINTS: var(CJ, fig("peak_setpoints"), U["q"],
                                     "peak |q_d - q| at the set points"),
        V.ERROR_RMS_SETPOINTS: var(CJ, fig("rms_setpoints"), U["q"],
                                    "RMS of q_d - q at the set points"),
        V.ERROR_PEAK_GRID: var(CJ, fig("peak_grid"), U["q"],
                                "peak |q_d - q| on the fine grid"),
        V.ERROR_RMS_GRID: var(CJ, fig("rms_grid"), U["q"], "RMS of q_d - q on the fine grid"),
        V.TAU_PEAK: var(CJ, np.array(tau_pk), U["tau"], "peak |tau| on the fine grid"),
        V.TAU_RMS: var(CJ, np.array(tau_rm), U["tau"], "RMS of tau on the fine grid"),
        V.NFEV: var((V.CONTROLLER,), np.array([r.nfev for r in runs], dtype=np.int64), "1",
                     "right-hand-side evaluations of the integrator"),
        V.SUCCESS: var((V.CONTROLLER,), np.array([r.success for r in runs], dtype=np.int8),
                        "1", "integrator reached the end (1) or failed (0)"),
        V.WN: var((V.JOINT,), g.wn, "rad s-1", "undamped natural frequency of the error dynamics"),
        V.ZETA: var((V.JOINT,), g.zeta, "1", "damping ratio of the error dynamics"),
        V.KP: var((V.JOINT,), g.Kp, "s-2", "computed-torque position gain, wn^2"),
        V.KV: var((V.JOINT,), g.Kv, "s-1", "computed-torque velocity gain, 2 zeta wn"),
        V.INERTIA_SCALE: var((V.JOINT,), g.inertia_scale, U["inertia_scale"],
                              "diagonal of D at the start of the motion, scales the PD gains"),
        V.KP_PD: var((V.JOINT,), g.Kp_pd, U["Kp_pd"],
                      f"{pd} position gain, D_ii(q_d(0)) wn^2"),
        V.KV_PD: var((V.JOINT,), g.Kv_pd, U["Kv_pd"],
                      f"{pd} velocity gain, D_ii(q_d(0)) 2 zeta wn"),
        V.JOINT_TYPE: joint_type_var(robot),
        V.Q0_OFFSET: var((V.JOINT,), np.asarray(prov.get("q0_offset", np.zeros(n)), float),
                          U["q"], "initial position error q(0) - q_d(0)"),
        V.CHOICE: var((V.ELEMENT,), np.array([result.choices[k] for k in element_labels(n)],
                                              dtype=str), "1",
                       "part kept by the simplified model (tran, rot, both, none)"),
    }
    diff = result.tau_difference
    if diff is not None:
        pk, rm = peak_rms(diff)
        ps, rs = peak_rms(diff[result.is_setpoint])
        data_vars.update({
            V.TAU_DIFFERENCE: var((V.TIME, V.JOINT), diff, U["tau"],
                                "tau of the simplified-model controller minus tau of the "
                                "full-model controller, each along its own run"),
            V.TAU_DIFFERENCE_PEAK: var((V.JOINT,), pk, U["tau"],
                                     "peak |tau_simplified - tau_full| on the fine grid"),
            V.TAU_DIFFERENCE_RMS: var((V.JOINT,), rm, U["tau"],
                                    "RMS of tau_simplified - tau_full on the fine grid"),
            V.TAU_DIFFERENCE_PEAK_SETPOINTS: var((V.JOINT,), ps, U["tau"],
                                               "peak |tau_simplified - tau_full| at the set "
                                               "points"),
            V.TAU_DIFFERENCE_RMS_SETPOINTS: var((V.JOINT,), rs, U["tau"],
                                              "RMS of tau_simplified - tau_full at the set "
                                              "points")})
    if diff is not None and result.tau_noise is not None:
        tight = f"rtol/{prov['rtol'] / prov['noise_rtol']:g}, atol/{prov['atol'] / prov['noise_atol']:g}"
        data_vars.update({
            V.TAU_DIFFERENCE_NOISE: var((V.JOINT,), np.asarray(result.tau_noise, float), U["tau"],
                                      "integrator noise of tau_simplified - tau_full, measured: "
                                      "peak over the run of its change when both runs are "
                                      f"integrated again at {tight}"),
            V.TAU_DIFFERENCE_FLOOR: var((V.JOINT,), result.tau_noise_floor, U["tau"],
                                      "noise floor of tau_simplified - tau_full: "
                                      f"{prov['noise_factor']:g} x tau_difference_noise, at "
                                      "least max(rtol, 1e-12) x the full-model controller's "
                                      "peak |tau|; a difference at or below it is integrator "
                                      "noise, not data")})
    coords = {
        V.CONTROLLER: text_coordinate(V.CONTROLLER, names, "controller"),
        V.CONTROLLER_DESCRIPTION: text_coordinate(
            V.CONTROLLER, [result.descriptions[c] for c in names], "control law"),
        V.TIME: (V.TIME, result.t, {"long_name": "time", "units": "s",
                                    "standard_name": "time"}),
        V.JOINT: text_coordinate(V.JOINT, robot.joint_names(), "joint"),
        **{name: text_coordinate(V.JOINT, joint_units(prismatic, which), long_name)
           for name, (which, long_name) in JOINT_UNIT_COORDS.items()},
        **{f"{k}_units": text_coordinate(V.JOINT, v, f"units of {k} of the joint")
           for k, v in per_joint.items()},
        V.ELEMENT: text_coordinate(V.ELEMENT, element_labels(n), "element of D (i <= j) or h"),
    }
    cost = result.cost
    if cost:
        coords[V.EVALUATOR] = text_coordinate(V.EVALUATOR, cost["evaluators"],
                                              "evaluator of tau at one set point")
        data_vars.update({
            V.MULTIPLICATIONS: var((V.EVALUATOR,), np.array(cost["multiplications"], np.int64),
                                 "1", "multiplications per set point (counted, gd_analyze.dynamics.opcount "
                                      "rule)"),
            V.ADDITIONS: var((V.EVALUATOR,), np.array(cost["additions"], np.int64), "1",
                           "additions and subtractions per set point (counted)")})
    attrs = global_attributes(
        robot, f"Computed-torque control of {robot.name} with its simplified G-D model along "
               f"{prov.get('trajectory_file', '')}",
        references="Fu, Gonzalez & Lee (1987), Robotics, Sec. 3.4 (Eq. 3.4-24, Sec. 3.4.1) "
                   "and Ch. 5 (computed-torque technique)")
    attrs.update({
        **{k: prov.get(k, "") for k in ("trajectory_file", "trajectory_path",
                                         "trajectory_sha256", "trajectory_derivatives",
                                         "model_file", "model_path", "model_sha256",
                                         "model_trajectory_sha256")},
        "trajectory_is_models": int(bool(prov.get("model_trajectory_sha256"))
                                    and prov.get("model_trajectory_sha256")
                                    == prov.get("trajectory_sha256")),
        "wn": g.wn, "wn_units": "rad s-1", "zeta": g.zeta,
        "gains": f"computed torque: Kp = wn^2, Kv = 2 zeta wn per joint; {pd}: "
                 "Kp_pd = diag(D(q_d(0))) wn^2, Kv_pd = diag(D(q_d(0))) 2 zeta wn",
        "control_laws": "; ".join(f"{c}: {result.descriptions[c]}" for c in names)
                        + "; v = qdd_d + Kv (qd_d - qd) + Kp (q_d - q), e = q_d - q",
        "plant": "full G-D model, qdd = D^-1 (tau - h - c" + " - tau_f" * result.robot.has_friction
                 + ") (Eq. 3.4-24)" + f"; Coulomb friction regularised: sign(qd) in tau_f is qd / b "
                 f"within |qd| < b = {COULOMB_BAND} rad/s (m/s for a prismatic joint)"
                 * bool(any(result.robot.coulomb)),
        "interpolation": "piecewise quintic Hermite through (q, qd, qdd) at the set points "
                         "(scipy BPoly.from_derivatives), C2",
        "integrator": f"scipy.integrate.solve_ivp {prov.get('method', '')}",
        "rtol": float(prov.get("rtol", np.nan)), "atol": float(prov.get("atol", np.nan)),
        "grid_points": int(prov.get("grid_points", 0)),
        **{k: prov[k] for k in ("noise_rtol", "noise_atol", "noise_factor", "noise_nfev",
                                 "noise_unmeasured") if k in prov},
        "setpoints": int(result.is_setpoint.sum()),
        "samples": int(result.t.size),
        # what the simplified model is (jobs.control.model_facts), for the report's text
        **{f"model_{k}": v for k, v in prov.get("model", {}).items()},
    })
    if "verdict_tolerance" in prov:
        attrs.update(verdict_tolerance_revolute=float(prov["verdict_tolerance"][0]),
                     verdict_tolerance_prismatic=float(prov["verdict_tolerance"][1]))
    if cost:
        attrs.update(cost_dropped_parts=int(cost["dropped"]), cost_parts=int(cost["parts"]),
                     cost_parts_what=str(cost.get("what", "")))
    attrs.update(settings or {})
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def write_control_dataset(result: Any, path: str | os.PathLike[str],
                          settings: Mapping[str, Any] | None = None) -> xr.Dataset:
    """Write :func:`control_dataset` of a result to HDF5/netCDF4 (h5netcdf), atomically.

    Parameters
    ----------
    result : ControlResult
        As :func:`gd_analyze.jobs.control.run_control` returns it.
    path : str or os.PathLike
        Destination, e.g. ``control.h5``.
    settings : dict, optional
        Extra global attributes (:func:`control_dataset`), e.g. the command line.

    Returns
    -------
    xarray.Dataset
        The dataset written.

    Raises
    ------
    OSError
        If the file cannot be written.
    """
    ds = control_dataset(result, settings)
    write_dataset(ds, path)
    return ds
