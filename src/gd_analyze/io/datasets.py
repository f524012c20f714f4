"""Storage: the analysis as one xarray Dataset in an HDF5/netCDF4 file (engine h5netcdf).

The plumbing every gd-analyze dataset shares (one ``var``, one block of CF global attributes,
one writer and one reader) is in :mod:`gd_analyze.io.schema`; the sweep and closed-loop schemas
are in :mod:`gd_analyze.io.sweep_datasets` and :mod:`gd_analyze.io.control_dataset`.

Dimensions: ``t``, the set points, whose coordinate is the time [s] (so that
``ds.D_tran.sel(joint=..., joint_k=...).plot()`` draws against time), ``joint`` and ``joint_k``
(the rows and columns of D), whose coordinates are the joints' names
(:meth:`gd_analyze.core.model.robot.Robot.joint_names`), ``element`` (the ranked elements
``"D11"`` .. ``"hn"``, string labels) and ``xyz``/``xyz_k`` for the link parameters. Every variable carries ``units`` and ``long_name``; the global attributes follow
the CF conventions and carry the provenance: tool version, robot and its SHA-256, gravity,
thresholds, and the input file's name and SHA-256.

Files are written to a temporary name in the destination folder and renamed
(:func:`gd_analyze.files.atomic_path`), so a reader never sees a half-written file.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .schema import MIXED_UNITS, element_coords, global_attributes, joint_coordinate, var

__all__ = ["build_dataset", "summary_dataset", "setpoint_arrays", "SetpointWriter", "SETPOINT_DIM",
           "SETPOINT_VARIABLES", "FRICTION_VARIABLE", "setpoint_variables", "setpoint_units", "joint_units", "units_attribute",
           "guarantee_fields", "stored_guarantee", "region_fields", "stored_region"]


#: The set points' dimension; its coordinate variable is the time t [s].
SETPOINT_DIM = "t"
#: Per-set-point variables: name -> (dims, units, long_name). Used by both writers; ``t`` is
#: the coordinate of :data:`SETPOINT_DIM`.
SETPOINT_VARIABLES = {
    "t": (("t",), "s", "time"),
    "q": (("t", "joint"), "rad", "joint position"),
    "qd": (("t", "joint"), "rad s-1", "joint velocity"),
    "qdd": (("t", "joint"), "rad s-2", "joint acceleration"),
    "D_tran": (("t", "joint", "joint_k"), "kg m2",
               "inertia matrix, translational part (Eq. 3.4-25)"),
    "D_rot": (("t", "joint", "joint_k"), "kg m2",
              "inertia matrix, rotational part (Eq. 3.4-25)"),
    "D": (("t", "joint", "joint_k"), "kg m2",
          "inertia matrix D = D_tran + D_rot + diag(armature)"),
    "h_tran": (("t", "joint"), "N m",
               "Coriolis and centrifugal torque, translational part (Eq. 3.4-26)"),
    "h_rot": (("t", "joint"), "N m",
              "Coriolis and centrifugal torque, rotational part (Eq. 3.4-27)"),
    "h": (("t", "joint"), "N m", "Coriolis and centrifugal torque h = h_tran + h_rot"),
    "c": (("t", "joint"), "N m", "gravity loading (Eq. 3.4-28)"),
    "tau": (("t", "joint"), "N m",
            "joint torque of the full model, D qdd + h + c + tau_f (Eq. 3.4-24)"),
    "tau_simplified": (("t", "joint"), "N m",
                       "joint torque of the simplified model, D_s qdd + h_s + c + tau_f"),
}
#: The per-set-point variable of a robot with friction only (core/model/drives.py).
FRICTION_VARIABLE = {"tau_f": (("t", "joint"), "N m",
                               "joint friction torque viscous qd + coulomb sign(qd) + "
                               "torque_offset")}


def setpoint_variables(friction=False):
    """The per-set-point variables of a dataset: name -> (dims, units, long_name).

    Parameters
    ----------
    friction : bool, optional
        Whether the robot has friction: then ``tau_f`` is stored too.

    Returns
    -------
    dict
        :data:`SETPOINT_VARIABLES`, and :data:`FRICTION_VARIABLE` with friction.
    """
    return {**SETPOINT_VARIABLES, **(FRICTION_VARIABLE if friction else {})}


#: Per-joint unit coordinates: name -> (quantity of :func:`joint_units`, long_name).
JOINT_UNIT_COORDS = {"q_units": ("q", "units of q of the joint (rad or m)"),
                      "qd_units": ("qd", "units of qd of the joint (rad s-1 or m s-1)"),
                      "qdd_units": ("qdd", "units of qdd of the joint (rad s-2 or m s-2)"),
                      "tau_units": ("tau", "units of tau, h and c of the joint (N m or N)")}


def guarantee_fields(model, torque_units="N m"):
    """The simplified model's guarantee as the results dataset stores it (issue 29 item 4).

    Parameters
    ----------
    model : SimplifiedModel
        The model built; its ``guarantee``
        (:class:`~gd_analyze.core.selection.guarantee.Guarantee`) may be None (chapter rule).
    torque_units : str, optional
        The ``units`` attribute of a joint torque (``"N m"``, or the mixed-units marker).

    Returns
    -------
    variables : dict
        ``simplified_guarantee_bound`` and ``simplified_guarantee_scale`` (dim joint) [N m or
        N]: the guarantee's bound and s_i; empty without a guarantee.
    attrs : dict
        ``simplified_guarantee_kind`` (``"region"``, ``"trajectory"`` or ``"none"``),
        ``simplified_guarantee_statement`` (:meth:`gd_analyze.core.selection.simplified.SimplifiedModel.scope`, the one sentence
        every output prints) and, with a guarantee, ``simplified_guarantee_tolerance`` (EPS);
        with a region, :func:`region_fields`' ``region_*``.
    """
    g = model.guarantee
    attrs = {"simplified_guarantee_kind": "none" if g is None else g.kind,
             "simplified_guarantee_statement": model.scope()}
    if g is None:
        return {}, attrs
    attrs["simplified_guarantee_tolerance"] = float(g.tolerance)
    where = "over the region" if g.kind == "region" else "on the trajectory"
    region_vars, region_attrs = region_fields(g.region)
    attrs.update(region_attrs)
    return {**region_vars, "simplified_guarantee_bound": var(("joint",), np.asarray(g.bound, float),
                                              torque_units, f"the guarantee's bound on "
                                              f"|tau_s - tau| {where}"),
            "simplified_guarantee_scale": var(("joint",), np.asarray(g.scale, float),
                                              torque_units, f"the guarantee's scale s_i {where}")
            }, attrs


def region_fields(region):
    """The region of a model's guarantee as the results dataset stores it.

    Parameters
    ----------
    region : Region or None
        :class:`gd_analyze.core.selection.region.Region` (None: nothing stored).

    Returns
    -------
    variables : dict
        Dim joint: ``region_q_min``, ``region_q_max`` [rad or m] (NaN for a revolute joint
        that turns freely: ``region_q_full_turn`` 1, "any angle (full turn)"),
        ``region_qd_max`` [rad/s or m/s], ``region_qdd_max`` [rad/s^2 or m/s^2],
        ``region_qdd_max_assumed`` (1: assumed, the robot gives none and the user set none).
    attrs : dict
        ``region_summary``: the three lines every output prints
        (:meth:`~gd_analyze.core.selection.region.Region.lines`); ``region_source``;
        ``region_notes`` (the user's limits clipped to the robot's), where any.
    """
    if region is None:
        return {}, {}
    pris = region.is_prismatic
    full = region.full_turn

    def units(which):
        return units_attribute(joint_units(pris, which), f"{which}_units")

    flag = {"flag_values": np.array([0, 1], dtype=np.int8)}
    out = {
        "region_q_min": (("joint",), np.where(full, np.nan, region.q_min),
                         {"units": units("q"), "long_name": "lower position limit of the "
                          "guarantee's region (NaN: any angle, full turn)"}),
        "region_q_max": (("joint",), np.where(full, np.nan, region.q_max),
                         {"units": units("q"), "long_name": "upper position limit of the "
                          "guarantee's region (NaN: any angle, full turn)"}),
        "region_q_full_turn": (("joint",), full.astype(np.int8),
                               {"units": "1", "long_name": "1: a revolute joint at any angle "
                                "(its region spans a full turn)", **flag,
                                "flag_meanings": "range full_turn"}),
        "region_qd_max": (("joint",), np.asarray(region.qd_max, float),
                          {"units": units("qd"), "long_name": "velocity limit of the "
                           "guarantee's region"}),
        "region_qdd_max": (("joint",), np.asarray(region.qdd_max, float),
                           {"units": units("qdd"), "long_name": "acceleration limit of the "
                            "guarantee's region"}),
        "region_qdd_max_assumed": (("joint",), region.assumed.astype(np.int8),
                                   {"units": "1", "long_name": "1: the acceleration limit is "
                                    f"assumed ({region.qdd_rule or 'not given'}): the robot "
                                    "gives none and none was set", **flag,
                                    "flag_meanings": "given assumed"}),
    }
    attrs = {"region_summary": "\n".join(region.lines()), "region_source": region.source}
    if region.notes:
        attrs["region_notes"] = "; ".join(region.notes)
    return out, attrs


def stored_region(ds):
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
    if "region_summary" not in a or "region_qd_max" not in ds.variables:
        return None
    out = {"lines": str(a["region_summary"]).split("\n"),
           **{k: np.asarray(ds[f"region_{k}"].values) for k in (
               "q_min", "q_max", "q_full_turn", "qd_max", "qdd_max", "qdd_max_assumed")}}
    out["covered"] = (bool(int(a["region_covers_trajectory"]))
                      if "region_covers_trajectory" in a else None)
    out["coverage"] = str(a.get("region_coverage", ""))
    return out


def stored_guarantee(ds):
    """The guarantee of the model built, read back from a results dataset.

    Parameters
    ----------
    ds : xarray.Dataset
        As the main job stores it (:func:`guarantee_fields`).

    Returns
    -------
    dict or None
        ``kind``, ``statement``, ``tolerance`` (NaN without a guarantee), ``bound`` and
        ``scale`` (ndarray (n,), or None); None for a dataset written before issue 29.
    """
    a = ds.attrs
    if "simplified_guarantee_statement" not in a:
        return None
    return {"kind": str(a.get("simplified_guarantee_kind", "none")),
            "statement": str(a["simplified_guarantee_statement"]),
            "tolerance": float(a.get("simplified_guarantee_tolerance", np.nan)),
            **{k: (np.asarray(ds[f"simplified_guarantee_{k}"].values, float)
                   if f"simplified_guarantee_{k}" in ds.variables else None)
               for k in ("bound", "scale")}}


def joint_units(prismatic, which):
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
        From :func:`gd_analyze.core.selection.labels.joint_motion_units`,
        :func:`gd_analyze.core.selection.labels.joint_torque_units` and
        :func:`gd_analyze.core.selection.labels.joint_drive_units`.
    """
    from ..core.selection.labels import joint_drive_units, joint_motion_units, joint_torque_units

    if which == "tau":
        return [joint_torque_units(bool(p)) for p in prismatic]
    if which in ("armature", "viscous"):
        return [joint_drive_units(bool(p))[which == "viscous"] for p in prismatic]
    k = ("q", "qd", "qdd").index(which)
    return [joint_motion_units(bool(p))[k] for p in prismatic]


def units_attribute(units, coord):
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
    if len(set(units)) == 1:
        return units[0]
    return " or ".join(dict.fromkeys(units)) + f" by joint type (per joint: {coord})"


def setpoint_units(name, prismatic=None):
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
    from ..core.selection.labels import element_units

    base = setpoint_variables(True)[name][1]
    if prismatic is None or not np.any(prismatic):
        return base
    if name in ("q", "qd", "qdd"):
        return units_attribute(joint_units(prismatic, name), f"{name}_units")
    if name.startswith("D"):
        n = len(prismatic)
        units = [element_units("D", i, j, prismatic) for i in range(n) for j in range(i, n)]
        return units_attribute(units, "element_units")
    if name == "t":
        return base
    return units_attribute(joint_units(prismatic, "tau"), "tau_units")


def setpoint_arrays(trajectory, terms, tau, tau_simplified):
    """The per-set-point arrays, keyed as :data:`SETPOINT_VARIABLES`.

    Parameters
    ----------
    trajectory : Trajectory
        t (N,) [s]; q, qd, qdd (N, n).
    terms : GDTerms
        The G-D terms at the same set points.
    tau, tau_simplified : ndarray, shape (N, n)
        Torques of the full and the simplified model [N m].

    Returns
    -------
    dict
        name -> ndarray; ``tau_f`` too where the terms have friction.
    """
    out = {"t": trajectory.t, "q": trajectory.q, "qd": trajectory.qd, "qdd": trajectory.qdd,
           "D_tran": terms.D_tran, "D_rot": terms.D_rot, "D": terms.D, "h_tran": terms.h_tran,
           "h_rot": terms.h_rot, "h": terms.h, "c": terms.c, "tau": tau,
           "tau_simplified": tau_simplified}
    if terms.tau_f is not None:
        out["tau_f"] = terms.tau_f
    return out


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
        Torque error per joint, as :func:`gd_analyze.core.selection.simplified.torque_error` gives it.
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

    from ..core.selection.ranking import CHAPTER_DOMINANCE, identically_zero, is_chapter_puma

    n = robot.n
    labels = list(ranking.labels)
    mixed = MIXED_UNITS
    puma = is_chapter_puma(robot.name, n)
    prismatic = np.asarray(robot.prismatic, bool)
    torque = units_attribute(joint_units(prismatic, "tau"), "tau_units")

    def by_type(which, coord):
        return units_attribute(joint_units(prismatic, which), coord)

    # an element zero in every part has no share: its ratio of round-off is not data (NaN)
    zero = identically_zero(ranking.peak_tran, ranking.peak_rot, ranking.peak_total,
                            ranking.scale)
    data_vars = {
        "share_tran": var(("element",), np.where(zero, np.nan, ranking.share_tran), "1",
                           "translational share sum|tran| / (sum|tran| + sum|rot|); NaN "
                           "where the element is zero in every part (round-off)"),
        "dominance": var(("element",), np.array(ranking.dominance, dtype=str), "1",
                          "dominance class (translational, rotational, both, negligible)"),
        "chapter_dominance": var(("element",),
                                  np.array([CHAPTER_DOMINANCE.get(lab, "") if puma else ""
                                            for lab in labels], dtype=str), "1",
                                  "dominance reported in Sec. 3.4.1 for the chapter's PUMA 560 "
                                  "(empty unless the robot is a PUMA 560)"),
        "choice": var(("element",), np.array([choices[lab] for lab in labels], dtype=str), "1",
                       "part kept by the simplified model (tran, rot, both, none; for the "
                       "recursive form both, or pruned where its dropped base-parameter "
                       "terms change the element)"),
        "peak_tran": var(("element",), ranking.peak_tran, mixed,
                          "peak |translational part| along the trajectory"),
        "peak_rot": var(("element",), ranking.peak_rot, mixed,
                         "peak |rotational part| along the trajectory"),
        "peak_total": var(("element",), ranking.peak_total, mixed,
                           "peak |translational + rotational| along the trajectory"),
        "element_scale": var(("element",), ranking.scale, mixed,
                              "scale of the negligibility test: peak sqrt(D_ii D_jj) or |tau_i|"),
        "tau_error_peak": var(("joint",), np.array(error["peak_abs_error"]), torque,
                               "peak |tau_simplified - tau|"),
        "tau_error_rms": var(("joint",), np.array(error["rms_error"]), torque,
                              "RMS of |tau_simplified - tau|"),
        "tau_peak": var(("joint",), np.array(error["peak_tau"]), torque, "peak |tau|"),
        "tau_max": var(("joint",), np.asarray(robot.tau_max, float), torque,
                        "joint effort limit |tau| <= tau_max (NaN: not given)"),
        "tau_error_relative_peak": var(("joint",), np.array(error["relative_peak_error"]), "1",
                                        "peak |tau_simplified - tau| / peak |tau|"),
        "tau_error_relative_rms": var(("joint",), np.array(error["relative_rms_error"]), "1",
                                       "RMS |tau_simplified - tau| / peak |tau|"),
        **({} if "round_off" not in error else {"tau_error_round_off": var(
            ("joint",), np.array(error["round_off"], dtype=np.int8), "1",
            "1 where the torque error is floating-point round-off (shown as \u2261 0), not data",
            flag_values=np.array([0, 1], dtype=np.int8), flag_meanings="data round_off")}),
        "joint_type": var(("joint",), np.array(robot.joint_types, dtype=str), "1",
                          "joint type: revolute (q in rad) or prismatic (q in m)"),
        "dh_d": var(("joint",), robot.d, "m",
                    "DH link offset d (prismatic joint: its constant part, d = q + dh_d)"),
        "dh_a": var(("joint",), robot.a, "m", "DH link length a"),
        "dh_alpha": var(("joint",), robot.alpha, "rad", "DH twist angle alpha"),
        "dh_offset": var(("joint",), robot.offset, "rad",
                         "DH joint angle: revolute joint theta = q + dh_offset; prismatic joint "
                         "theta = dh_offset, fixed"),
        "joint_translation": var(("joint", "xyz"), robot.translation, "m",
                                 "translation of joint i's placement in body frame i-1"),
        "joint_rotation": var(("joint", "xyz", "xyz_k"), robot.rotation, "1",
                              "rotation of joint i's placement in body frame i-1; its z column "
                              "is joint i's axis"),
        "link_mass": var(("joint",), robot.mass, "kg", "link mass"),
        "link_com": var(("joint", "xyz"), robot.com, "m", "centre of mass in link frame"),
        "link_inertia": var(("joint", "xyz", "xyz_k"), robot.inertia, "kg m2",
                             "inertia tensor about the centre of mass, link-frame axes"),
        "q_min": var(("joint",), robot.q_min, by_type("q", "q_units"),
                     "lower joint position limit"),
        "q_max": var(("joint",), robot.q_max, by_type("q", "q_units"),
                     "upper joint position limit"),
        "qd_max": var(("joint",), robot.qd_max, by_type("qd", "qd_units"),
                      "joint velocity limit"),
        "qdd_max": var(("joint",), robot.qdd_max, by_type("qdd", "qdd_units"),
                       "joint acceleration limit"),
        "D_arm": var(("joint",), robot.armature, by_type("armature", "joint_type"),
                     "armature part of D: its diagonal, the drive's reflected rotor inertia "
                     "rotor_inertia * gear_ratio^2 (D_arm = diag of this)"),
        "viscous": var(("joint",), robot.viscous, by_type("viscous", "joint_type"),
                       "viscous friction coefficient (N m s rad-1 revolute, N s m-1 "
                       "prismatic)"),
        "coulomb": var(("joint",), robot.coulomb, torque, "Coulomb friction torque"),
        "torque_offset": var(("joint",), robot.torque_offset, torque,
                             "constant joint torque offset"),
    }
    if getattr(ranking, "rigid_dominance", None) is not None:
        data_vars["dominance_rigid_links"] = var(
            ("element",), np.array(ranking.rigid_dominance, dtype=str), "1",
            "dominance class of the rigid links alone: drives (armature, friction) left out")
    if getattr(ranking, "share_arm", None) is not None:
        data_vars["share_arm"] = var(
            ("element",), ranking.share_arm, "1",
            "armature share sum|arm| / (sum|tran| + sum|rot + arm|), diagonal of D only")
    coords = element_coords(n, prismatic)
    coords["joint"] = joint_coordinate(robot.joint_names(), long_name="joint (row of D)")
    for name, (which, long_name) in JOINT_UNIT_COORDS.items():
        units = joint_units(prismatic, which)
        coords[name] = ("joint", np.array(units, dtype=str), {"long_name": long_name,
                                                              "units": "1"})
    coords["xyz"] = ("xyz", np.array(["x", "y", "z"]), {"long_name": "axis", "units": "1"})
    coords["xyz_k"] = ("xyz_k", np.array(["x", "y", "z"]), {"long_name": "axis", "units": "1"})
    attrs = global_attributes(
        robot, f"G-D dominance analysis of {robot.name} along {Path(trajectory.source).name}",
        dominance_threshold=ranking.dominance_threshold,
        negligible_threshold=ranking.negligible_threshold,
        input_file=Path(trajectory.source).name, input_path=str(trajectory.source),
        input_sha256=trajectory.sha256, derivatives=trajectory.derivatives,
        setpoints=int(trajectory.t.shape[0]))
    for key, value in (verification or {}).items():
        attrs[f"verification_{key}"] = value
    attrs.update(settings or {})
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def build_dataset(robot, trajectory, terms, ranking, tau, tau_simplified, choices, error,
                  verification=None, settings=None):
    """Assemble the analysis into one xarray Dataset, in memory.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    trajectory : Trajectory
        t (N,) [s]; q, qd, qdd (N, n) [rad, rad/s, rad/s^2].
    terms : GDTerms
        D_tran, D_rot (N, n, n) [kg m^2]; h_tran, h_rot, c (N, n) [N m].
    ranking : Ranking
        The dominance of each of the M elements.
    tau, tau_simplified : ndarray, shape (N, n)
        Torques of the full and the simplified model [N m].
    choices : dict
        Element label -> kept part.
    error : dict
        Torque error per joint.
    verification : dict, optional
        Result of the check against Pinocchio.
    settings : dict, optional
        Extra global attributes.

    Returns
    -------
    xarray.Dataset
        The per-set-point variables of :data:`SETPOINT_VARIABLES` over dim ``t`` (its
        coordinate: the time [s]) and the :func:`summary_dataset`.
    """
    ds = summary_dataset(robot, trajectory, ranking, choices, error, verification, settings)
    arrays = setpoint_arrays(trajectory, terms, tau, tau_simplified)
    prismatic = np.asarray(robot.prismatic, bool)
    for name, (dims, _, long_name) in setpoint_variables("tau_f" in arrays).items():
        ds[name] = var(dims, arrays[name], setpoint_units(name, prismatic), long_name)
    return ds.assign_coords(joint_k=joint_coordinate(robot.joint_names(), "joint_k",
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

    def __init__(self, path, N, n, chunk=8192, compress=0, prismatic=None, friction=False,
                 joints=None):
        import h5netcdf
        import h5py

        self._file = h5netcdf.File(path, "x")     # O_EXCL: no write-back on close
        f = self._file
        f.dimensions = {SETPOINT_DIM: N, "joint": n, "joint_k": n}
        rows = max(1, min(int(chunk), N))
        names = [f"joint{i}" for i in range(1, n + 1)] if joints is None else joints
        for dim, long_name in (("joint", "joint (row of D)"), ("joint_k", "joint (column of D)")):
            _, values, attrs = joint_coordinate(names, dim, long_name)
            v = f.create_variable(dim, (dim,), dtype=h5py.string_dtype())
            v[:] = values.astype(object)
            v.attrs.update(attrs)
        self.variables = {}
        for name, (dims, _, long_name) in setpoint_variables(friction).items():
            units = setpoint_units(name, prismatic)
            shape = tuple({SETPOINT_DIM: rows, "joint": n, "joint_k": n}[d] for d in dims)
            opts = {"compression": "gzip", "compression_opts": int(compress)} if compress else {}
            v = f.create_variable(name, dims, "f8", chunks=shape, **opts)
            v.attrs.update(units=units, long_name=long_name)
            self.variables[name] = v

    def write(self, start, arrays):
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

    def read(self, name, start, stop):
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

    def close(self):
        """Close the file (``with contextlib.closing(SetpointWriter(...)) as w:``)."""
        self._file.close()


