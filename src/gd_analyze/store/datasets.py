"""Storage: the analysis as one xarray Dataset in an HDF5/netCDF4 file (engine h5netcdf).

The plumbing every gd-analyze dataset shares (one ``var``, one block of CF global attributes,
one writer and one reader) is in :mod:`gd_analyze.store.schema`; the sweep and closed-loop schemas
are in :mod:`gd_analyze.store.sweep_view` and :mod:`gd_analyze.store.control_dataset`.

Dimensions: ``t``, the set points, whose coordinate is the time [s] (so that
``ds.D_tran.sel(joint=..., joint_k=...).plot()`` draws against time), ``joint`` and ``joint_k``
(the rows and columns of D), whose coordinates are the joints' names
(:meth:`gd_analyze.model.robot.Robot.joint_names`), ``element`` (the ranked elements
``"D11"`` .. ``"hn"``, string labels) and ``xyz``/``xyz_k`` for the link parameters. Every variable carries ``units`` and ``long_name``; the global attributes follow
the CF conventions and carry the provenance: tool version, robot and its SHA-256, gravity,
thresholds, and the input file's name and SHA-256.

Files are written to a temporary name in the destination folder and renamed
(:func:`gd_analyze.files.atomic_path`), so a reader never sees a half-written file.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..ranking.labels import (
    element_units,
    joint_drive_units,
    joint_motion_units,
    joint_torque_units,
)
from ..ranking.ranking import (
    CHAPTER_DOMINANCE,
    arm_scales,
    identically_zero,
    is_chapter_puma,
    is_round_off,
)
from .names import ELEMENT_UNITS_RULE, RANKING_COLUMNS, VERIFICATION_PREFIX, Attr, Var
from .schema import (
    MIXED_UNITS,
    element_coords,
    flag,
    global_attributes,
    joint_type_var,
    text_coordinate,
    var,
)

if TYPE_CHECKING:
    import xarray as xr

    from ..certify.region import Region
    from ..simplify.simplified import SimplifiedModel

__all__ = ["summary_dataset", "with_setpoints", "SetpointWriter", "SETPOINT_DIM",
           "SETPOINT_VARIABLES", "setpoint_units", "joint_units", "units_attribute",
           "units_by_type", "TORQUE_ERRORS", "error_variables", "guarantee_fields",
           "stored_guarantee", "region_fields", "stored_region"]


#: The set points' dimension; its coordinate variable is the time t [s].
SETPOINT_DIM = "t"
#: Per-set-point variables: name -> (dims, units, long_name). Used by both writers; ``t`` is
#: the coordinate of :data:`SETPOINT_DIM`; ``tau_f`` is stored for a robot with friction only.
SETPOINT_VARIABLES = {
    Var.T: (("t",), "s", "time"),
    Var.Q: (("t", "joint"), "rad", "joint position"),
    Var.QD: (("t", "joint"), "rad s-1", "joint velocity"),
    Var.QDD: (("t", "joint"), "rad s-2", "joint acceleration"),
    Var.D_TRAN: (("t", "joint", "joint_k"), "kg m2",
               "inertia matrix, translational part (Eq. 3.4-25)"),
    Var.D_ROT: (("t", "joint", "joint_k"), "kg m2",
              "inertia matrix, rotational part (Eq. 3.4-25)"),
    Var.D: (("t", "joint", "joint_k"), "kg m2",
          "inertia matrix D = D_tran + D_rot + diag(armature)"),
    Var.H_TRAN: (("t", "joint"), "N m",
               "Coriolis and centrifugal torque, translational part (Eq. 3.4-26)"),
    Var.H_ROT: (("t", "joint"), "N m",
              "Coriolis and centrifugal torque, rotational part (Eq. 3.4-27)"),
    Var.H: (("t", "joint"), "N m", "Coriolis and centrifugal torque h = h_tran + h_rot"),
    Var.C: (("t", "joint"), "N m", "gravity loading (Eq. 3.4-28)"),
    Var.TAU: (("t", "joint"), "N m",
            "joint torque of the full model, D qdd + h + c + tau_f (Eq. 3.4-24)"),
    Var.TAU_SIMPLIFIED: (("t", "joint"), "N m",
                       "joint torque of the simplified model, D_s qdd + h_s + c + tau_f"),
    Var.TAU_F: (("t", "joint"), "N m",                  # a robot with friction only
                "joint friction torque viscous qd + coulomb sign(qd) + torque_offset"),
}


def _setpoint_variables(friction):
    """:data:`SETPOINT_VARIABLES`, ``tau_f`` only for a robot with friction."""
    return {k: v for k, v in SETPOINT_VARIABLES.items() if friction or k != Var.TAU_F}


#: The simplified model's torque error per joint, as
#: :func:`gd_analyze.simplify.simplified.torque_error` gives it: (its key, the variable, in the
#: torque's units (else [1]), long_name).
TORQUE_ERRORS = (
    ("peak_abs_error", Var.TAU_ERROR_PEAK, True, "peak |tau_simplified - tau|"),
    ("rms_error", Var.TAU_ERROR_RMS, True, "RMS of |tau_simplified - tau|"),
    ("relative_peak_error", Var.TAU_ERROR_RELATIVE_PEAK, False,
     "peak |tau_simplified - tau| / peak |tau|"),
    ("relative_rms_error", Var.TAU_ERROR_RELATIVE_RMS, False,
     "RMS |tau_simplified - tau| / peak |tau|"))


def error_variables(errors: Mapping[str, Any], dims: tuple[str, ...], torque: str,
                    table: Sequence[tuple[str, str, bool, str]] = TORQUE_ERRORS,
                    prefix: str = "") -> dict[str, Any]:
    """The variables of torque errors, as a table of :data:`TORQUE_ERRORS`' form declares them.

    Parameters
    ----------
    errors : mapping of str to array_like
        Each key of the table -> its values over ``dims`` (None: NaN) [N m or N, or 1].
    dims : tuple of str
        The variables' dims, ending in ``joint``.
    torque : str
        The ``units`` attribute of a joint torque (:func:`units_attribute`).
    table : sequence of (str, str, bool, str), optional
        (key, variable, in the torque's units (else [1]), long_name).
    prefix : str, optional
        Put before each long_name (``"own simplified model: "``).

    Returns
    -------
    dict
        Variable name -> (dims, values, attributes).
    """
    return {name: var(dims, np.array(errors[key], float), torque if torqued else "1",
                      prefix + long_name) for key, name, torqued, long_name in table}


#: Per-joint unit coordinates: name -> (quantity of :func:`joint_units`, long_name).
JOINT_UNIT_COORDS = {Var.Q_UNITS: ("q", "units of q of the joint (rad or m)"),
                      Var.QD_UNITS: ("qd", "units of qd of the joint (rad s-1 or m s-1)"),
                      Var.QDD_UNITS: ("qdd", "units of qdd of the joint (rad s-2 or m s-2)"),
                      Var.TAU_UNITS: ("tau", "units of tau, h and c of the joint (N m or N)")}


def guarantee_fields(model: SimplifiedModel,
                     torque_units: str = "N m") -> tuple[dict[str, Any], dict[str, Any]]:
    """The simplified model's guarantee as the results dataset stores it.

    Parameters
    ----------
    model : SimplifiedModel
        The model built; its ``guarantee``
        (:class:`~gd_analyze.simplify.guarantee.Guarantee`) may be None (chapter rule).
    torque_units : str, optional
        The ``units`` attribute of a joint torque (``"N m"``, or the mixed-units marker).

    Returns
    -------
    variables : dict
        ``simplified_guarantee_bound`` and ``simplified_guarantee_scale`` (dim joint) [N m or
        N]: the guarantee's bound and s_i; and, where the guarantee states it,
        ``simplified_guarantee_bound_method`` (dim joint): how each joint's bound was
        proved (:attr:`~gd_analyze.simplify.guarantee.Guarantee.bound_method`); empty
        without a guarantee.
    attrs : dict
        ``simplified_guarantee_kind`` (``"region"``, ``"trajectory"`` or ``"none"``),
        ``simplified_guarantee_statement`` (:meth:`gd_analyze.simplify.simplified.SimplifiedModel.scope`, the one sentence
        every output prints) and, with a guarantee, ``simplified_guarantee_tolerance`` (EPS)
        and, with a way per joint, ``simplified_guarantee_joint_sum_arithmetic``;
        region kind: ``simplified_guarantee_scale_source``, how s_i was found
        (:meth:`~gd_analyze.simplify.guarantee.Guarantee.scale_source`);
        with a region, :func:`region_fields`' ``region_*``.
    """
    g: Any = model.guarantee       # a Guarantee or None
    attrs = {Attr.SIMPLIFIED_GUARANTEE_KIND: "none" if g is None else g.kind,
             Attr.SIMPLIFIED_GUARANTEE_STATEMENT: model.scope()}
    if g is None:
        return {}, attrs
    attrs[Attr.SIMPLIFIED_GUARANTEE_TOLERANCE] = float(g.tolerance)
    if g.kind == "region":
        attrs[Attr.SIMPLIFIED_GUARANTEE_SCALE_SOURCE] = g.scale_source()
    where = "over the region" if g.kind == "region" else "on the trajectory"
    region_vars, region_attrs = region_fields(g.region)
    attrs.update(region_attrs)
    if g.bound_method:
        region_vars[Var.SIMPLIFIED_GUARANTEE_BOUND_METHOD] = var(
            ("joint",), np.array(g.bound_method, dtype=str), "1",
            "how the guarantee's bound of each joint was proved (certify.BOUND_METHODS)")
        attrs[Attr.SIMPLIFIED_GUARANTEE_JOINT_SUM_ARITHMETIC] = g.joint_sum_arithmetic
    return {**region_vars, Var.SIMPLIFIED_GUARANTEE_BOUND: var(("joint",), np.asarray(g.bound, float),
                                              torque_units, f"the guarantee's bound on "
                                              f"|tau_s - tau| {where}"),
            Var.SIMPLIFIED_GUARANTEE_SCALE: var(("joint",), np.asarray(g.scale, float),
                                              torque_units, f"the guarantee's scale s_i {where}")
            }, attrs


def region_fields(region: Region | None) -> tuple[dict[str, Any], dict[str, Any]]:
    """The region of a model's guarantee as the results dataset stores it.

    Parameters
    ----------
    region : Region or None
        :class:`gd_analyze.certify.region.Region` (None: nothing stored).

    Returns
    -------
    variables : dict
        Dim joint: ``region_q_min``, ``region_q_max`` [rad or m] (NaN for a revolute joint
        that turns freely: ``region_q_full_turn`` 1, "any angle (full turn)"),
        ``region_qd_max`` [rad/s or m/s], ``region_qdd_max`` [rad/s^2 or m/s^2],
        ``region_qdd_max_assumed`` (1: assumed, the robot gives none and the user set none).
    attrs : dict
        ``region_summary``: the three lines every output prints
        (:meth:`~gd_analyze.certify.region.Region.lines`); ``region_source``;
        ``region_notes`` (the user's limits clipped to the robot's), where any.
    """
    if region is None:
        return {}, {}
    full = region.full_turn
    q_units, qd_units, qdd_units = (units_by_type(region.is_prismatic, which)
                                    for which in ("q", "qd", "qdd"))

    J = ("joint",)
    out = {
        Var.REGION_Q_MIN: var(J, np.where(full, np.nan, region.q_min), q_units, "lower "
                              "position limit of the guarantee's region (NaN: any angle, full "
                              "turn)"),
        Var.REGION_Q_MAX: var(J, np.where(full, np.nan, region.q_max), q_units, "upper "
                              "position limit of the guarantee's region (NaN: any angle, full "
                              "turn)"),
        Var.REGION_Q_FULL_TURN: flag(J, full, "1: a revolute joint at any angle (its region "
                                     "spans a full turn)", "range full_turn"),
        Var.REGION_QD_MAX: var(J, np.asarray(region.qd_max, float), qd_units,
                               "velocity limit of the guarantee's region"),
        Var.REGION_QDD_MAX: var(J, np.asarray(region.qdd_max, float), qdd_units,
                                "acceleration limit of the guarantee's region"),
        Var.REGION_QDD_MAX_ASSUMED: flag(J, region.assumed, "1: the acceleration limit is "
                                         f"assumed ({region.qdd_rule or 'not given'}): the "
                                         "robot gives none and none was set", "given assumed"),
    }
    attrs = {Attr.REGION_SUMMARY: "\n".join(region.lines()), Attr.REGION_SOURCE: region.source}
    if region.notes:
        attrs[Attr.REGION_NOTES] = "; ".join(region.notes)
    return out, attrs


def stored_region(ds: xr.Dataset) -> dict[str, Any] | None:
    """The region of the model built, read back from a results dataset.

    Parameters
    ----------
    ds : xarray.Dataset
        As the main job stores it (:func:`region_fields`).

    Returns
    -------
    dict or None
        ``lines`` (list of str, as printed), ``q_min``, ``q_max`` (NaN: full turn),
        ``full_turn``, ``qd_max``, ``qdd_max``, ``qdd_assumed`` (ndarray (n,)), ``covered``
        (bool, or None when not checked) and ``coverage`` (the clause where not covered);
        None without a region.
    """
    a = ds.attrs
    if Attr.REGION_SUMMARY not in a or Var.REGION_QD_MAX not in ds.variables:
        return None
    return {"lines": str(a[Attr.REGION_SUMMARY]).split("\n"),
            **{k: np.asarray(ds[name].values) for k, name in (
                ("q_min", Var.REGION_Q_MIN), ("q_max", Var.REGION_Q_MAX),
                ("q_full_turn", Var.REGION_Q_FULL_TURN), ("qd_max", Var.REGION_QD_MAX),
                ("qdd_max", Var.REGION_QDD_MAX), ("qdd_max_assumed", Var.REGION_QDD_MAX_ASSUMED))},
            "covered": (bool(int(a[Attr.REGION_COVERS_TRAJECTORY]))
                        if Attr.REGION_COVERS_TRAJECTORY in a else None),
            "coverage": str(a.get(Attr.REGION_COVERAGE, ""))}


def stored_guarantee(ds: xr.Dataset) -> dict[str, Any] | None:
    """The guarantee of the model built, read back from a results dataset.

    Parameters
    ----------
    ds : xarray.Dataset
        As the main job stores it (:func:`guarantee_fields`).

    Returns
    -------
    dict or None
        ``kind``, ``statement``, ``tolerance`` (NaN without a guarantee), ``bound`` and
        ``scale`` (ndarray (n,), or None), ``bound_method`` (tuple of str, () where not
        stored), ``joint_sum_arithmetic`` and ``scale_source`` (how a region kind's s_i was
        found; "" where not stored); None for a dataset written by an older version
        (without a guarantee).
    """
    a = ds.attrs
    if Attr.SIMPLIFIED_GUARANTEE_STATEMENT not in a:
        return None
    return {"kind": str(a.get(Attr.SIMPLIFIED_GUARANTEE_KIND, "none")),
            "statement": str(a[Attr.SIMPLIFIED_GUARANTEE_STATEMENT]),
            "tolerance": float(a.get(Attr.SIMPLIFIED_GUARANTEE_TOLERANCE, np.nan)),
            **{k: (np.asarray(ds[name].values, float) if name in ds.variables else None)
               for k, name in (("bound", Var.SIMPLIFIED_GUARANTEE_BOUND),
                               ("scale", Var.SIMPLIFIED_GUARANTEE_SCALE))},
            "bound_method": tuple(str(m) for m in ds[Var.SIMPLIFIED_GUARANTEE_BOUND_METHOD].values)
            if Var.SIMPLIFIED_GUARANTEE_BOUND_METHOD in ds.variables else (),
            "joint_sum_arithmetic": str(a.get(Attr.SIMPLIFIED_GUARANTEE_JOINT_SUM_ARITHMETIC, "")),
            "scale_source": str(a.get(Attr.SIMPLIFIED_GUARANTEE_SCALE_SOURCE, ""))}


def joint_units(prismatic: Sequence[bool] | np.ndarray, which: str) -> list[str]:
    """The stored units of one per-joint quantity, joint by joint.

    Parameters
    ----------
    prismatic : sequence of bool, shape (n,)
        The prismatic joints.
    which : str
        ``"q"``, ``"qd"``, ``"qdd"``, ``"tau"`` (also h, c and the torque errors),
        ``"armature"`` or ``"viscous"``.

    Returns
    -------
    list of str, length n
        From :func:`gd_analyze.ranking.labels.joint_motion_units`,
        :func:`gd_analyze.ranking.labels.joint_torque_units` and
        :func:`gd_analyze.ranking.labels.joint_drive_units`.
    """

    if which == "tau":
        return [joint_torque_units(bool(p)) for p in prismatic]
    if which in ("armature", "viscous"):
        return [joint_drive_units(bool(p))[which == "viscous"] for p in prismatic]
    k = ("q", "qd", "qdd").index(which)
    return [joint_motion_units(bool(p))[k] for p in prismatic]


def units_attribute(units: Sequence[str], coord: str) -> str:
    """The ``units`` attribute of a per-joint (or per-element) variable.

    Parameters
    ----------
    units : sequence of str
        The units of each joint or element.
    coord : str
        The variable that gives them one by one (``tau_units``, ``element_units``).

    Returns
    -------
    str
        The unit when all agree, else ``"N m or N by joint type (per joint: tau_units)"``.

    Examples
    --------
    >>> units_attribute(["N m", "N"], "tau_units")
    'N m or N by joint type (per joint: tau_units)'
    """
    return units[0] if len(set(units)) == 1 else (
        " or ".join(dict.fromkeys(units)) + f" by joint type (per joint: {coord})")


def units_by_type(prismatic: Sequence[bool] | np.ndarray, which: str, coord: str = "") -> str:
    """The ``units`` attribute of a per-joint variable of one quantity.

    Parameters
    ----------
    prismatic : sequence of bool, length n
        Which joints are prismatic.
    which : str
        The quantity, as :func:`joint_units` takes it (``"q"``, ``"tau"``, ``"armature"`` ...).
    coord : str, optional
        The variable that gives the units one by one; ``<which>_units`` by default.

    Returns
    -------
    str
        :func:`units_attribute` of the joints' :func:`joint_units`.
    """
    return units_attribute(joint_units(prismatic, which), coord or f"{which}_units")


def setpoint_units(name: str, prismatic: Sequence[bool] | np.ndarray | None = None) -> str:
    """The ``units`` attribute of a variable of :data:`SETPOINT_VARIABLES` for an arm.

    Parameters
    ----------
    name : str
        A key of :data:`SETPOINT_VARIABLES`.
    prismatic : sequence of bool, shape (n,), optional
        The prismatic joints; all revolute if not given.

    Returns
    -------
    str
        The one unit when every joint has it (``"rad"``, ``"m"``, ``"kg m2"``, ``"N"``...),
        else the units and the coordinate that gives them joint by joint (``q_units``,
        ``tau_units``) or element by element (``element_units``).

    Examples
    --------
    >>> setpoint_units("tau", [True]), setpoint_units("D", [False, False])
    ('N', 'kg m2')
    """

    base = SETPOINT_VARIABLES[name][1]
    if prismatic is None or not np.any(prismatic) or name == Var.T:
        return base
    if name in ("q", "qd", "qdd"):
        return units_by_type(prismatic, name)
    if name.startswith("D"):
        n = len(prismatic)
        units = [element_units("D", i, j, prismatic) for i in range(n) for j in range(i, n)]
        return units_attribute(units, "element_units")
    return units_by_type(prismatic, "tau")



def summary_dataset(robot, trajectory, ranking, choices, error, verification=None,
                    settings=None):
    """Everything but the per-set-point variables: ranking, model, robot, provenance.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    trajectory : Trajectory
        Its source, SHA-256 and how derivatives were obtained go into the attributes.
    ranking : Ranking
        The dominance of each of the M elements.
    choices : dict
        Element label -> kept part (``"tran"``, ``"rot"``, ``"both"``, ``"none"``).
    error : dict
        Torque error per joint, as :func:`gd_analyze.simplify.simplified.torque_error` gives it,
        with its round-off marks ``round_off`` (bool, per joint).
    verification : dict, optional
        Largest relative disagreement with Pinocchio per term, and the set points checked.
    settings : dict, optional
        Extra global attributes (scalars or strings), e.g. the command line.

    Returns
    -------
    xarray.Dataset
        Dims ``element``, ``joint`` (coordinate: the joints' names), ``xyz``, ``xyz_k``;
        CF-style global attributes.
    """
    import xarray as xr


    n = robot.n
    labels = list(ranking.labels)
    puma = is_chapter_puma(robot.name, n)
    prismatic = np.asarray(robot.prismatic, bool)
    torque = units_by_type(prismatic, "tau")
    drive = {w: units_by_type(prismatic, w, "joint_type") for w in ("armature", "viscous")}

    # an element zero in every part has no share: its ratio of round-off is not data (NaN)
    zero = identically_zero(ranking.peak_tran, ranking.peak_rot, ranking.peak_total,
                            ranking.scale)
    arm = arm_scales(ranking.scale, element_coords(n, prismatic)[Var.ELEMENT_UNITS][1])
    other = {"choices": [choices[lab] for lab in labels],       # the columns not from ranking
             "chapter": [CHAPTER_DOMINANCE.get(lab, "") if puma else "" for lab in labels]}
    # the ranking's per-element variables and their round-off flags, as RANKING_COLUMNS
    # declares them (an optional Ranking attribute that is None left out)
    data_vars = {}
    for column in RANKING_COLUMNS:
        if not column.stored:
            continue
        values = (getattr(ranking, column.field, None) if column.source == "ranking"
                  else other[column.source])
        if values is None:
            continue
        values = np.array(values, dtype=str) if column.text else np.asarray(values)
        if column.nan_where_zero:
            values = np.where(zero, np.nan, values)
        units = MIXED_UNITS if column.units == ELEMENT_UNITS_RULE else column.units
        data_vars[column.name] = var(("element",), values, units, column.long_name)
        if column.round_off is not None:
            data_vars[column.round_off] = flag(("element",), is_round_off(
                values, ranking.scale, arm_scale=arm), column.round_off_long_name)
    data_vars.update({
        **error_variables(error, ("joint",), torque),
        Var.TAU_PEAK: var(("joint",), np.array(error["peak_tau"]), torque, "peak |tau|"),
        Var.TAU_MAX: var(("joint",), np.asarray(robot.tau_max, float), torque,
                        "joint effort limit |tau| <= tau_max (NaN: not given)"),
        Var.TAU_ERROR_ROUND_OFF: flag(("joint",), error["round_off"], "1 where the torque error "
                                      "is floating-point round-off (shown as \u2261 0), not data"),
        Var.JOINT_TYPE: joint_type_var(robot),
        Var.DH_D: var(("joint",), robot.d, "m",
                    "DH link offset d (prismatic joint: its constant part, d = q + dh_d)"),
        Var.DH_A: var(("joint",), robot.a, "m", "DH link length a"),
        Var.DH_ALPHA: var(("joint",), robot.alpha, "rad", "DH twist angle alpha"),
        Var.DH_OFFSET: var(("joint",), robot.offset, "rad",
                         "DH joint angle: revolute joint theta = q + dh_offset; prismatic joint "
                         "theta = dh_offset, fixed"),
        Var.JOINT_TRANSLATION: var(("joint", "xyz"), robot.translation, "m",
                                 "translation of joint i's placement in body frame i-1"),
        Var.JOINT_ROTATION: var(("joint", "xyz", "xyz_k"), robot.rotation, "1",
                              "rotation of joint i's placement in body frame i-1; its z column "
                              "is joint i's axis"),
        Var.LINK_MASS: var(("joint",), robot.mass, "kg", "link mass"),
        Var.LINK_COM: var(("joint", "xyz"), robot.com, "m", "centre of mass in link frame"),
        Var.LINK_INERTIA: var(("joint", "xyz", "xyz_k"), robot.inertia, "kg m2",
                             "inertia tensor about the centre of mass, link-frame axes"),
        Var.Q_MIN: var(("joint",), robot.q_min, units_by_type(prismatic, "q"),
                     "lower joint position limit"),
        Var.Q_MAX: var(("joint",), robot.q_max, units_by_type(prismatic, "q"),
                     "upper joint position limit"),
        Var.QD_MAX: var(("joint",), robot.qd_max, units_by_type(prismatic, "qd"),
                      "joint velocity limit"),
        Var.QDD_MAX: var(("joint",), robot.qdd_max, units_by_type(prismatic, "qdd"),
                       "joint acceleration limit"),
        Var.D_ARM: var(("joint",), robot.armature, drive["armature"],
                     "armature part of D: its diagonal, the drive's reflected rotor inertia "
                     "rotor_inertia * gear_ratio^2 (D_arm = diag of this)"),
        Var.VISCOUS: var(("joint",), robot.viscous, drive["viscous"],
                       "viscous friction coefficient (N m s rad-1 revolute, N s m-1 "
                       "prismatic)"),
        Var.COULOMB: var(("joint",), robot.coulomb, torque, "Coulomb friction torque"),
        Var.TORQUE_OFFSET: var(("joint",), robot.torque_offset, torque,
                             "constant joint torque offset"),
    })
    # the round-off marks, decided once here (the reports' one rule) and read by every output
    data_vars[Var.ELEMENT_ROUND_OFF] = flag(("element",), zero, "1 where the element is zero "
                                            "in every part: round-off (shown as \u2261 0), no "
                                            "share")
    coords = element_coords(n, prismatic)
    coords[Var.JOINT] = text_coordinate("joint", robot.joint_names(), "joint (row of D)")
    for name, (which, long_name) in JOINT_UNIT_COORDS.items():
        coords[name] = text_coordinate("joint", joint_units(prismatic, which), long_name)
    coords[Var.XYZ] = ("xyz", np.array(["x", "y", "z"]), {"long_name": "axis", "units": "1"})
    coords[Var.XYZ_K] = ("xyz_k", np.array(["x", "y", "z"]), {"long_name": "axis", "units": "1"})
    attrs = global_attributes(
        robot, f"G-D dominance analysis of {robot.name} along {Path(trajectory.source).name}",
        **{Attr.DOMINANCE_THRESHOLD: ranking.dominance_threshold,
           Attr.NEGLIGIBLE_THRESHOLD: ranking.negligible_threshold,
           Attr.INPUT_FILE: Path(trajectory.source).name, Attr.INPUT_PATH: str(trajectory.source),
           Attr.INPUT_SHA256: trajectory.sha256, Attr.DERIVATIVES: trajectory.derivatives,
           Attr.SETPOINTS: int(trajectory.t.shape[0])})
    for key, value in (verification or {}).items():
        attrs[VERIFICATION_PREFIX + key] = value
    attrs.update(settings or {})
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def with_setpoints(ds, robot, trajectory, terms, tau, tau_simplified):
    """A summary dataset with the per-set-point variables added, in memory.

    Parameters
    ----------
    ds : xarray.Dataset
        :func:`summary_dataset`'s.
    robot : Robot
        The arm, with n joints.
    trajectory : Trajectory
        t (N,) [s]; q, qd, qdd (N, n) [rad, rad/s, rad/s^2].
    terms : GDTerms
        D_tran, D_rot, D (N, n, n) [kg m^2]; h_tran, h_rot, h, c and tau_f (or None) (N, n)
        [N m].
    tau, tau_simplified : ndarray, shape (N, n)
        Torques of the full and the simplified model [N m].

    Returns
    -------
    xarray.Dataset
        A new dataset: ``ds`` with the variables of :data:`SETPOINT_VARIABLES` over dim ``t``
        (``tau_f`` where the terms have friction) and the coordinate ``joint_k``, as
        :class:`SetpointWriter` writes them to the file.
    """
    arrays = {Var.TAU: tau, Var.TAU_SIMPLIFIED: tau_simplified,
              **{name: getattr(trajectory, name) for name in (Var.T, Var.Q, Var.QD, Var.QDD)},
              **{name: getattr(terms, name) for name in (Var.D_TRAN, Var.D_ROT, Var.D, Var.H_TRAN,
                                                        Var.H_ROT, Var.H, Var.C, Var.TAU_F)}}
    prismatic = np.asarray(robot.prismatic, bool)
    made = _setpoint_variables(terms.tau_f is not None).items()
    # one merge for all of them (a merge per variable took most of the function's time)
    ds = ds.assign({name: var(dims, arrays[name], setpoint_units(name, prismatic), long_name)
                    for name, (dims, _, long_name) in made})
    return ds.assign_coords(joint_k=text_coordinate("joint_k", robot.joint_names(),
                                                    "joint (column of D)"))


class SetpointWriter:
    """Stream the per-set-point variables into a new netCDF4/HDF5 file, chunk by chunk.

    The file gets dims ``t`` (N), ``joint`` and ``joint_k`` (n), their coordinate variables
    (the time t [s], written with the other per-set-point variables, and the joints' names),
    and every variable of :data:`SETPOINT_VARIABLES` with ``units`` and ``long_name``. Add the summary afterwards with
    ``summary.to_netcdf(path, mode="a", engine="h5netcdf")``.

    Parameters
    ----------
    path : str or os.PathLike
        The file to create, new: it must not exist (write it under a temporary name left free
        by :func:`gd_analyze.files.atomic_path` with ``create=False``).
    N : int
        Number of set points.
    n : int
        Number of joints.
    chunk : int, optional
        Set points per HDF5 chunk.
    compress : int, optional
        gzip level 1-9 for the per-set-point variables; 0 (default) stores them uncompressed,
        about ten times faster to write and 1.5 to 2 times larger.
    prismatic : sequence of bool, shape (n,), optional
        The prismatic joints, for the ``units`` of each variable (:func:`setpoint_units`).
    friction : bool, optional
        Whether the robot has friction: then ``tau_f`` is stored too.
    joints : sequence of str, length n, optional
        The joints' names (default ``"joint1"`` .. ``"jointn"``).
    """

    def __init__(self, path: str | os.PathLike[str], N: int, n: int, chunk: int = 8192,
                 compress: int = 0, prismatic: Sequence[bool] | np.ndarray | None = None,
                 friction: bool = False, joints: Sequence[str] | None = None) -> None:
        import h5netcdf
        import h5py

        self._file = h5netcdf.File(path, "x")     # O_EXCL: no write-back on close
        f = self._file
        f.dimensions = {SETPOINT_DIM: N, Var.JOINT: n, Var.JOINT_K: n}
        rows = max(1, min(int(chunk), N))
        names = [f"joint{i}" for i in range(1, n + 1)] if joints is None else joints
        for dim, long_name in (("joint", "joint (row of D)"), ("joint_k", "joint (column of D)")):
            _, values, attrs = text_coordinate(dim, names, long_name)
            v = f.create_variable(dim, (dim,), dtype=h5py.string_dtype())
            v[:] = values.astype(object)
            v.attrs.update(attrs)
        self.variables = {}
        for name, (dims, _, long_name) in _setpoint_variables(friction).items():
            units = setpoint_units(name, prismatic)
            shape = tuple({SETPOINT_DIM: rows, Var.JOINT: n, Var.JOINT_K: n}[d] for d in dims)
            opts = {"compression": "gzip", "compression_opts": int(compress)} if compress else {}
            v = f.create_variable(name, dims, "f8", chunks=shape, **opts)
            v.attrs.update(units=units, long_name=long_name)
            self.variables[name] = v

    def write(self, start: int, arrays: Mapping[str, np.ndarray]) -> None:
        """Write a block of set points.

        Parameters
        ----------
        start : int
            Index of the block's first set point.
        arrays : dict
            name -> ndarray whose first axis is the block's set points.
        """
        for name, values in arrays.items():
            self.variables[name][start:start + len(values)] = values

    def read(self, name: str, start: int, stop: int) -> np.ndarray:
        """Read back set points [start, stop) of a variable.

        Parameters
        ----------
        name : str
            A name of :data:`SETPOINT_VARIABLES`.
        start, stop : int
            Set-point range.

        Returns
        -------
        ndarray
        """
        return self.variables[name][start:stop]

    def close(self) -> None:
        """Close the file (``with contextlib.closing(SetpointWriter(...)) as w:``)."""
        self._file.close()


