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

from ..io.names import Attr
from .common import attr as _attr
from .common import fmt as _fmt
from .common import prismatic_joints
from .markup import scope as scope_markup
from .markup import sub as _sub
from .simplified_section import REGION_SCALE, guarantee_kind, has_drives

if TYPE_CHECKING:
    import xarray as xr


def _no_floor(ds):
    """The torque floor 0, said with what each joint's scale s_i then is: its peak on the
    trajectory, or over the region (the rigid links' alone where the robot has drives)."""
    if guarantee_kind(ds) != "region":
        return "none: each joint's scale s" + _sub("i") + " is its own peak |\u03c4" + \
            _sub("i") + "| on this trajectory"
    return ("none: each joint's scale " + REGION_SCALE[has_drives(ds)].replace(" = ", " is ", 1)
            + " (positions, velocities and accelerations within the model's limits), not its "
            "peak on this trajectory")

__all__ = ["provenance_rows", "software_row", "run_row", "gravity_row"]

#: Attributes shown in other sections or rows, or results printed in Secs. 5 and 7.
_ELSEWHERE = {
    "robot", "robot_description", "robot_reference", "gravity", "gravity_units", "input_file",
    "derivatives", "setpoints", "title", "source", "gd_analyze_version", "history",
    "input_path", "input_sha256", "robot_source", "robot_sha256", "dominance_threshold",
    "negligible_threshold", "command", "Conventions", "references", "robot_placeholder_inertia",
    "simplified_terms_kept", "simplified_pairs_dropped", "simplified_pairs",
    "simplified_dropped_pairs", "simplified_multiplications", "simplified_additions",
    "simplified_sin", "simplified_cos", "other_rule_multiplications", "other_rule_additions",
    "simplified_ladder_skipped", "simplified_ladder_form", "simplified_form_note",
    "simplified_region_screen", "simplified_region_possible_saving",
    "simplified_region_saving_threshold",
    "formulations_n", "formulations_setpoints",
    "payload_mass", "payload_com", "payload_inertia", "simplified_files", "c_prefix",
    "simplified_inertia_check_where", "simplified_inertia_check_samples",
    "simplified_inertia_check_proved", "simplified_inertia_check_lower_bound",
    "simplified_inertia_check_ratio", "simplified_inertia_check_sampled_min_eigenvalue",
    "simplified_inertia_check_restored", "simplified_inertia_check_statement",
    "simplified_inertia_check_method",
    "mounting_base_rpy_deg", "mounting_gravity_base", "mounting_gravity_world",
    "full_harmonics", "full_coefficients", "other_rule_harmonics", "other_rule_coefficients",
    "formulations_joint_types", "simplified_guarantee_kind", "simplified_guarantee_statement",
    "simplified_guarantee_tolerance", "region_summary", "region_source", "region_notes",
    "region_covers_trajectory", "region_coverage",
    # the chapter's conclusions, counted: Sec. 6
    "chapter_elements_compared", "chapter_arm_ranked", "chapter_arm_translation_leads",
    "chapter_wrist_ranked", "chapter_wrist_rotation_leads",
}
#: The ``explicit`` setting in words.
_EXPLICIT = {"auto": "derived when its estimated size is cheap and it may be deployed (auto)",
             "always": "always derived", "never": "never derived"}
#: (row, setting asked for, what the model records it was built with), in the order shown.
_SETTINGS = (
    ("simplification rule", "rule", "simplified_rule"),
    ("error budget \u03b5 (relative to each joint's scale)", "tolerance",
     "simplified_tolerance"),
    ("torque floor of each joint's scale", "torque_floor", "simplified_torque_floor"),
    ("model form", "form", "simplified_form"),
    ("explicit model", "explicit", None),
    ("rule compared side by side", "other_rule", None),
)


def _setting(ds, asked, built):
    a = _attr(ds, asked) if asked in ds.attrs else None
    b = _attr(ds, built) if built and built in ds.attrs else None
    if a is None or b is None or a == b:
        return a if a is not None else b
    return f"asked {a}, built {b}"


def _payload(ds):
    mass = float(ds.attrs.get(Attr.PAYLOAD_MASS, 0.0) or 0.0)
    if mass == 0.0:
        return "none"
    return (f"{mass:g} kg, centre of mass {_attr(ds, 'payload_com')} m in link frame n, "
            f"inertia diagonal {_attr(ds, 'payload_inertia')} kg m\u00b2")


def _vector(ds, key):
    """A stored 3-vector attribute as numbers, or None."""
    if key not in ds.attrs:
        return None
    v = np.asarray(ds.attrs[key], dtype=float).ravel()
    return v if v.size == 3 else None


def _mounting(ds):
    """The mounting in words: how the base is turned, and where gravity comes from."""
    rpy, world = _vector(ds, "mounting_base_rpy_deg"), _vector(ds, "mounting_gravity_world")
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


def _prismatic_joints(ds):
    """", joint 3 prismatic" when the operation counts are for an arm with prismatic joints."""
    types = str(ds.attrs.get(Attr.FORMULATIONS_JOINT_TYPES, ""))
    pris = [str(k + 1) for k, t in enumerate(types) if t == "P"]
    if not pris:
        return ""
    return f", joint{'s' if len(pris) > 1 else ''} {', '.join(pris)} prismatic"


def _analysis_time(ds):
    """When the analysis ran, from the CF ``history`` ("<time> created by gd-analyze X")."""
    return _attr(ds, Attr.HISTORY).split(" created by ")[0]


def _conventions(ds):
    """The results file's format in words."""
    cf = _attr(ds, Attr.CONVENTIONS).replace("CF-", "")
    return f"results.h5: HDF5 (netCDF-4) with metadata after the CF conventions, version {cf}"


def provenance_rows(ds: xr.Dataset, created: str, version: str,
                    verification: str) -> list[tuple[str, str]]:
    """The rows (item, value) of the main report's provenance table, each setting once.

    Parameters
    ----------
    ds : xarray.Dataset
        A results dataset; only its global attributes are read.
    created : str
        When the report was made (ISO 8601).
    version : str
        The version of gd-analyze that makes the report.
    verification : str
        The verification's one row (:func:`gd_analyze.reports.main_context._verification`).

    Returns
    -------
    list of (str, str)
    """
    analysis = _attr(ds, Attr.GD_ANALYZE_VERSION)
    sha_in = _attr(ds, Attr.INPUT_SHA256, "") or "\u2014, not read from a file"
    rows = [
        ("software", f"gd-analyze {version}" if analysis == version else
         f"analysis by gd-analyze {analysis}, report by gd-analyze {version}"),
        ("command", _attr(ds, Attr.COMMAND)),
        ("analysis run, report created", created if _analysis_time(ds) == created
         else f"{_analysis_time(ds)}, {created}"),
        ("trajectory file", f"{_attr(ds, 'input_path')} (SHA-256 {sha_in})"),
        ("robot file", f"{_attr(ds, 'robot_source')} (SHA-256 {_attr(ds, 'robot_sha256')})"),
        ("dominance threshold s, negligibility threshold e",
         f"{_fmt(float(ds.attrs.get('dominance_threshold', np.nan)), 6)}, "
         f"{_fmt(float(ds.attrs.get('negligible_threshold', np.nan)), 6)}"),
    ]
    used: set[str | None] = set(_ELSEWHERE)
    for label, asked, built in _SETTINGS:
        value = _setting(ds, asked, built)
        used.update((asked, built))
        if value is not None and asked == "torque_floor":
            value = (_no_floor(ds) if value == "0" else
                     value + " N m" + (", or N for a prismatic joint"
                                       if prismatic_joints(ds).any() else ""))
        if value is not None and asked == "explicit":
            value = _EXPLICIT.get(value, value)
        if value is not None:
            rows.append((label, value))
    mounting = _mounting(ds)
    if mounting is not None:
        rows.append(("mounting", mounting))
    rows.append(("payload on the last link", _payload(ds)))
    if "formulations_setpoints" in ds.attrs:
        rows.append(("formulations compared on",
                     f"{_attr(ds, 'formulations_setpoints')} set points, for "
                     f"n = {_attr(ds, 'formulations_n')}" + _prismatic_joints(ds)))
    if "simplified_files" in ds.attrs:
        rows.append(("emitted source files", _attr(ds, Attr.SIMPLIFIED_FILES)))
    if "simplified_guarantee_statement" in ds.attrs:        # the model's scope
        rows.append(("guarantee of the model built",
                     f"{_attr(ds, 'simplified_guarantee_kind')} kind: "
                     + scope_markup(_attr(ds, 'simplified_guarantee_statement'))))
    engine = _attr(ds, Attr.VERIFICATION_ENGINE, "Pinocchio")
    rows.append(("verification against " + engine.replace("pinocchio", "Pinocchio"),
                 verification))
    for key in sorted(k for k in ds.attrs if k not in used
                      and not k.startswith("verification_")):
        value = _attr(ds, key)
        twin = key[len("simplified_"):] if key.startswith("simplified_") else None
        if twin is not None and twin in ds.attrs and _attr(ds, twin) == value:
            continue                                        # each setting once
        rows.append((key.replace("_", " "), value))
    rows += [("file format", _conventions(ds)), ("method", _attr(ds, Attr.REFERENCES))]
    return rows


# Rows shared with the sweep and control reports' provenance (each setting once, in words).

def software_row(ds: xr.Dataset, version: str) -> tuple[str, str]:
    """("software", ...): the version that computed the stored results and the one that
    writes the report, once when they agree (as the main report's provenance says it).

    Parameters
    ----------
    ds : xarray.Dataset
        A stored results, sweep or control dataset (attribute ``gd_analyze_version``).
    version : str
        The version of gd-analyze that writes the report.

    Returns
    -------
    tuple of (str, str)
    """
    computed = _attr(ds, Attr.GD_ANALYZE_VERSION)
    return ("software", f"gd-analyze {version}" if computed == version else
            f"computed by gd-analyze {computed}, report by gd-analyze {version}")


def run_row(ds: xr.Dataset, label: str = "computed") -> tuple[str, str]:
    """(label, when): the time the stored results were computed, from the CF ``history``
    attribute without its repeated software version.

    Parameters
    ----------
    ds : xarray.Dataset
    label : str, optional
        The row's item.

    Returns
    -------
    tuple of (str, str)
    """
    return (label, _attr(ds, Attr.HISTORY).split(" created by ")[0])


def gravity_row(ds: xr.Dataset) -> tuple[str, str]:
    """("gravity and mounting", ...): gravity in the base frame and how the arm is mounted,
    said once from ``gravity`` and the ``mounting_*`` attributes (the sweep stored both, the
    same gravity twice).

    Parameters
    ----------
    ds : xarray.Dataset

    Returns
    -------
    tuple of (str, str)
    """
    def vector(key):
        return ", ".join(f"{float(v):g}" for v in np.atleast_1d(ds.attrs[key]))

    key = "mounting_gravity_base" if "mounting_gravity_base" in ds.attrs else "gravity"
    text = f"{vector(key)} m/s\u00b2 in the base frame" if key in ds.attrs else "not recorded"
    if "mounting_gravity_world" in ds.attrs:
        text += f" (given as {vector('mounting_gravity_world')} m/s\u00b2 in the world)"
    rpy = np.atleast_1d(ds.attrs.get(Attr.MOUNTING_BASE_RPY_DEG, [0.0]))
    if np.any(np.asarray(rpy, float) != 0):
        text += f"; base turned by roll, pitch, yaw {vector('mounting_base_rpy_deg')} deg"
    elif "mounting_base_rpy_deg" in ds.attrs:
        text += "; base as in the robot file"
    return ("gravity and mounting", text)
