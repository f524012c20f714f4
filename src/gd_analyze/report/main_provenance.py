"""The main report's provenance: each setting of the analysis once, in words.

The dataset's global attributes hold the settings asked for (``rule``, ``tolerance``, ``form``
...), the model's record of what it was built with (``simplified_rule`` ...), and results that
Sec. 5 and Sec. 7 already print. :func:`provenance_rows` gives one row per setting: a setting
asked for and recorded twice with one value is shown once; one asked for and built otherwise
("form: cheapest") reads "asked cheapest, built recursive"; results and the attributes the
report shows elsewhere (the robot and trajectory in Sec. 1, the title) are left out.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..store.schema import RunRecord
from .common import attr_text as _text
from .common import fmt as _fmt
from .common import joints_text, other_rows, say
from .markup import code
from .markup import scope as scope_markup

if TYPE_CHECKING:
    import xarray as xr

    from ..store.results_view import Provenance, Results


def _no_floor(results):
    """The torque floor 0, said with what each joint's scale s_i then is: its peak on the
    trajectory, or over the region (the rigid links' alone where the robot has drives)."""
    return say("no_floor", region=results.guarantee_kind == "region",
               drives=results.robot_record.has_drives)

__all__ = ["DERIVATIVES", "provenance_rows", "software_row", "command_row", "run_row",
           "gravity_row", "guarantee_row"]

#: How a trajectory's velocities and accelerations were obtained, in words (the stored
#: ``derivatives`` setting).
DERIVATIVES = {
    "file": "read from the file (its velocity and acceleration columns)",
    "cubic-spline": "derived from q by a not-a-knot cubic spline",
    "quintic": "analytic derivatives of a planned quintic motion",
    "arrays": "given as arrays (the Python API)",
}


#: The ``explicit`` setting in words.
_EXPLICIT = {"auto": "derived when its estimated size is cheap and it may be deployed (auto)",
             "always": "always derived", "never": "never derived"}
#: The ``guarantee`` asked for, in words (what was built is the row "guarantee of the model
#: built").
_GUARANTEE = {k: "over the joint-limit region where the robot file or the command line gives "
                 f"every joint's position and velocity limits, else on the trajectory ({k})"
              for k in ("auto", "region")} | {
    "trajectory": "on the analysed trajectory only (trajectory)"}


def _settings(p: Provenance):
    """(row, setting asked for, what the model records it was built with), in the order
    shown."""
    return (("simplification rule", p.rule, p.simplified_rule),
            ("error budget \u03b5 (relative to each joint's scale)", p.tolerance,
             p.simplified_tolerance),
            ("torque floor of each joint's scale", p.torque_floor, p.simplified_torque_floor),
            ("model form", p.form, p.simplified_form),
            ("explicit model", p.explicit, None),
            ("guarantee asked for", p.guarantee, None),
            ("rule compared side by side", p.other_rule, None))


def _setting(asked, built):
    a = None if asked is None else _text(asked)
    b = None if built is None else _text(built)
    if a is None or b is None or a == b:
        return a if a is not None else b
    return f"asked {a}, built {b}"


def _payload(p):
    mass = float(p.payload_mass or 0.0)
    if mass == 0.0:
        return "none"
    return (f"{mass:g} kg, centre of mass {_text(p.payload_com)} m in link frame n, "
            f"inertia diagonal {_text(p.payload_inertia)} kg m\u00b2")


def _vector(value):
    """A stored 3-vector attribute as numbers, or None."""
    if value is None:
        return None
    v = np.asarray(value, dtype=float).ravel()
    return v if v.size == 3 else None


def _mounting(p):
    """The mounting in words: how the base is turned, and where gravity comes from."""
    rpy, world = _vector(p.mounting_base_rpy_deg), _vector(p.mounting_gravity_world)
    if rpy is None and world is None:
        return None
    if rpy is None or not np.any(rpy):
        base = "base not turned"
    else:
        base = ("base turned by roll, pitch, yaw " + ", ".join(_fmt(v, 6) for v in rpy)
                + " deg")
    if world is None:
        return base + "; gravity as the robot file gives it (Sec. 1.1)"
    return (base + "; gravity (" + ", ".join(_fmt(v, 6) for v in world) + ") m/s\u00b2 in "
            "the world, in the base frame as Sec. 1.1 gives it")


def _prismatic_joints(p):
    """", joint 3 prismatic" when the operation counts are for an arm with prismatic joints."""
    types = "" if p.formulations_joint_types is None else str(p.formulations_joint_types)
    pris = [str(k + 1) for k, t in enumerate(types) if t == "P"]
    if not pris:
        return ""
    return f", {joints_text(pris)} prismatic"


def provenance_rows(results: Results, created: str, version: str,
                    verification: str) -> list[tuple[str, str | None]]:
    """The rows (item, value) of the main report's provenance table, each setting once
    (:func:`gd_analyze.report.common.settings_table`).

    Parameters
    ----------
    results : Results
        The main job's results; its provenance, robot and trajectory files and thresholds
        are read.
    created : str
        When the report was made (ISO 8601).
    version : str
        The version of gd-analyze that makes the report.
    verification : str
        The verification's one row (:func:`gd_analyze.report.main_context._verification`).

    Returns
    -------
    list of (str, str or None)
        A value None where the results do not record the setting: no row.
    """
    p, robot, traj = results.provenance, results.robot_record, results.trajectory
    analysis = _text(p.gd_analyze_version)
    sha_in = _text(traj.input_sha256, "") or "\u2014, not read from a file"
    ran = _text(p.history).split(" created by ")[0]   # the CF history: "<time> created by"
    rows = [
        ("software", f"gd-analyze {version}" if analysis == version else
         f"analysis by gd-analyze {analysis}, report by gd-analyze {version}"),
        command_row(p.command),
        ("analysis run, report created", created if ran == created else f"{ran}, {created}"),
        ("trajectory file", f"{_text(traj.input_path)} (SHA-256 {sha_in})"),
        ("robot file", f"{_text(robot.source)} (SHA-256 {_text(robot.sha256)})"),
        ("dominance threshold s, negligibility threshold e",
         f"{_fmt(results.dominance_threshold, 6)}, {_fmt(results.negligible_threshold, 6)}"),
    ]
    for k, (label, asked, built) in enumerate(_settings(p)):
        value = _setting(asked, built)
        if value is not None and k == 2:                    # the torque floor
            value = (_no_floor(results) if value == "0" else
                     value + " N m" + (", or N for a prismatic joint"
                                       if any(results.prismatic) else ""))
        # the explicit model, the guarantee asked for: in words
        rows.append((label, {4: _EXPLICIT, 5: _GUARANTEE}.get(k, {}).get(value, value)))
    engine = _text(p.verification_engine, "Pinocchio")
    return rows + [
        ("mounting", _mounting(p)), ("payload on the last link", _payload(p)),
        ("formulations compared on", None if p.formulations_setpoints is None else
         f"{_text(p.formulations_setpoints)} set points, for n = {_text(p.formulations_n)}"
         + _prismatic_joints(p)),
        ("emitted source files", None if p.simplified_files is None else
         _text(p.simplified_files)),
        guarantee_row("guarantee of the model built", p.simplified_guarantee_kind,
                      p.simplified_guarantee_statement),
        ("verification against " + engine.replace("pinocchio", "Pinocchio"), verification),
        *other_rows(p.others),                              # each setting once
        ("file format", "results.h5: HDF5 (netCDF-4) with metadata after the CF "
         f"conventions, version {_text(p.conventions).replace('CF-', '')}"),
        ("method", _text(p.references))]


# Rows shared with the sweep and control reports' provenance (each setting once, in words).

def software_row(ds: RunRecord | xr.Dataset, version: str) -> tuple[str, str]:
    """("software", ...): the version that computed the stored results and the one that
    writes the report, once when they agree (as the main report's provenance says it).

    Parameters
    ----------
    ds : RunRecord or xarray.Dataset
        The run's record (:class:`gd_analyze.store.schema.RunRecord`) of a stored
        results, sweep or control dataset, or the dataset (attribute ``gd_analyze_version``).
    version : str
        The version of gd-analyze that writes the report.

    Returns
    -------
    tuple of (str, str)
    """
    computed = _text(_record(ds).gd_analyze_version)
    return ("software", f"gd-analyze {version}" if computed == version else
            f"computed by gd-analyze {computed}, report by gd-analyze {version}")


def command_row(command: object) -> tuple[str, str | None]:
    """("command", ...): the command line as the command line stored it, set as code (in the
    PDF an option such as ``-o`` is not broken across lines).

    Parameters
    ----------
    command : object
        The stored ``command`` attribute, or None where the file has none (an older file).

    Returns
    -------
    tuple of (str, str or None)
        None as the value where there is no command: no row.
    """
    return ("command", None if command is None else code(_text(command)))


def run_row(ds: RunRecord | xr.Dataset, label: str = "computed") -> tuple[str, str]:
    """(label, when): the time the stored results were computed, from the CF ``history``
    attribute without its repeated software version.

    Parameters
    ----------
    ds : RunRecord or xarray.Dataset
        The run's record, or the dataset.
    label : str, optional
        The row's item.

    Returns
    -------
    tuple of (str, str)
    """
    return (label, _text(_record(ds).history).split(" created by ")[0])


def gravity_row(ds: RunRecord | xr.Dataset) -> tuple[str, str]:
    """("gravity and mounting", ...): gravity in the base frame and how the arm is mounted,
    said once from ``gravity`` and the ``mounting_*`` attributes (the sweep stored both, the
    same gravity twice).

    Parameters
    ----------
    ds : RunRecord or xarray.Dataset
        The run's record, or the dataset.

    Returns
    -------
    tuple of (str, str)
    """
    r = _record(ds)

    def vector(value):
        return ", ".join(f"{float(v):g}" for v in np.atleast_1d(value))

    base = r.mounting_gravity_base if r.mounting_gravity_base is not None else r.gravity
    text = f"{vector(base)} m/s\u00b2 in the base frame" if base is not None else "not recorded"
    if r.mounting_gravity_world is not None:
        text += f" (given as {vector(r.mounting_gravity_world)} m/s\u00b2 in the world)"
    rpy = np.atleast_1d([0.0] if r.mounting_base_rpy_deg is None else r.mounting_base_rpy_deg)
    if np.any(np.asarray(rpy, float) != 0):
        text += f"; base turned by roll, pitch, yaw {vector(r.mounting_base_rpy_deg)} deg"
    elif r.mounting_base_rpy_deg is not None:
        text += "; base as in the robot file"
    return ("gravity and mounting", text)


def guarantee_row(label: str, kind: object, statement: object) -> tuple[str, str | None]:
    """(label, "<kind> kind: <statement>"): a model's guarantee as it states it.

    Parameters
    ----------
    label : str
        The row's item.
    kind, statement : object
        The guarantee's kind and statement as stored; None where missing.

    Returns
    -------
    tuple of (str, str or None)
        The value None where no statement is stored.
    """
    return (label, None if statement is None else
            f"{_text(kind)} kind: " + scope_markup(_text(statement)))


def _record(ds):
    """The run's record, or that of a dataset."""
    return ds if isinstance(ds, RunRecord) else RunRecord.from_attrs(ds.attrs)
