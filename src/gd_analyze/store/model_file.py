"""Reading and writing ``simplified_model.json``: the simplified model as a file.

:func:`save_model` writes :meth:`SimplifiedModel.to_dict
<gd_analyze.simplify.simplified.SimplifiedModel.to_dict>` atomically; :func:`load_model`
reads it back with strict JSON (:func:`gd_analyze.store.json_schema.load_json`), checks it against
:data:`gd_analyze.store.json_schema.MODEL_SCHEMA`, rebuilds its robot from the stored parameters
(:func:`gd_analyze.model.robot_spec.robot_from_dict`), with a URDF's joint names
(``robot.joint_names``) where the file gives them, and hands the rest to
:meth:`SimplifiedModel.from_dict <gd_analyze.simplify.simplified.SimplifiedModel.from_dict>`.
"""

from __future__ import annotations

import dataclasses
import json
import types
from typing import TYPE_CHECKING

from ..errors import InputError, expect, path_text
from ..files import atomic_path
from ..model.mounting import as_mounted
from ..model.robot_spec import robot_from_dict
from ..simplify.guarantee import Guarantee
from ..simplify.simplified import (
    READABLE_SCHEMAS,
    SCHEMA_VERSION,
    SimplifiedModel,
    json_safe,
    parameters_sha256,
)
from .json_schema import MODEL_SCHEMA, load_json
from .model_trust import check_guarantee, check_region
from .staging import check_output_file

if TYPE_CHECKING:                       # for the type hints only
    import os

__all__ = ["save_model", "load_model"]


def save_model(model: SimplifiedModel, path: str | os.PathLike[str]) -> None:
    """Write a simplified model as JSON, atomically.

    Parameters
    ----------
    model : SimplifiedModel
        The model (:class:`~gd_analyze.simplify.simplified.SimplifiedModel`).
    path : str or os.PathLike
        Destination file (``simplified_model.json``).

    Raises
    ------
    InputError
        If ``model`` is not a SimplifiedModel or ``path`` not a str or os.PathLike (one line
        naming the argument), or ``path`` is a folder, a device or a symbolic link, or its
        folder does not exist (:func:`~gd_analyze.store.staging.check_output_file`).
    OSError
        If the file cannot be written.

    Notes
    -----
    NaN and inf, which JSON cannot hold, are written as null.
    """
    expect(model, SimplifiedModel, "model", "a SimplifiedModel")
    check_output_file(path := path_text(path, "JSON file"))
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8") as fh:
        json.dump(json_safe(model.to_dict()), fh, indent=2)
        fh.write("\n")


def load_model(path: str | os.PathLike[str]) -> SimplifiedModel:
    """Read a simplified_model.json written by :func:`save_model` or ``gd-analyze``.

    Parameters
    ----------
    path : str or os.PathLike
        The file.

    Returns
    -------
    SimplifiedModel
        Ready for ``.torque(q, qd, qdd)`` (q [rad] or [m], tau [N m] or [N]).

    Raises
    ------
    InputError
        If ``path`` is not a str or os.PathLike, the file is missing or not strict JSON
        (duplicate keys, NaN, numbers beyond a float, deep nesting), of another schema
        version, does not follow
        :data:`~gd_analyze.store.json_schema.MODEL_SCHEMA` (types, unknown keys, finite
        thresholds in range), its robot's parameters do not match
        ``robot.parameters_sha256`` or fail validation, its ``robot.joint_names`` (a URDF's,
        optional) are not one per joint, or its choices do not name exactly
        the elements of an n-joint robot, or its region guarantee does not hold for its
        robot (:func:`gd_analyze.store.model_trust.check_guarantee`: the region within the
        robot's limits, s_i reached at its stored state, the bound proved again for the
        dropped pairs). One line naming the key.

    Notes
    -----
    The file's ``cost`` and ``full_cost`` are not read: a claim is not a count (Sec. 3.4.1's
    simplified model is counted from its own terms).
    """
    path = path_text(path, "simplified-model JSON file")
    spec = load_json(path, "simplified-model JSON")
    if isinstance(spec, dict) and spec.get("schema_version") not in READABLE_SCHEMAS:
        raise InputError(f"expected schema_version {SCHEMA_VERSION}, got "
                         f"{spec.get('schema_version')!r}"[:120], path, column="schema_version")
    MODEL_SCHEMA.check(spec, path)
    rob = spec["robot"]
    if parameters_sha256(rob["parameters"]) != rob["parameters_sha256"]:
        raise InputError("the robot's parameters do not match their SHA-256 (edited after "
                         "the model was written?)", path, column="robot.parameters_sha256")
    robot = robot_from_dict(rob["parameters"], source=f"{path}#robot",
                            sha256=rob["sha256"] or None)
    if "joint_names" in rob:            # a URDF's names, as results.h5 and the emitted files
        if len(rob["joint_names"]) != robot.n:
            raise InputError(f"{len(rob['joint_names'])} names for {robot.n} joints", path,
                             column="robot.joint_names")
        robot = dataclasses.replace(robot, metadata=types.MappingProxyType(
            {**robot.metadata, "urdf_joints": list(rob["joint_names"])}))
    # the mounting the model was built with (key mounting; in files written before it, the
    # provenance's mounting_base_rpy_deg), recorded so that a --base-rpy or --gravity is not
    # applied on top of it (gd_analyze.model.mounting.with_mounting)
    said, key = spec.get("mounting"), "mounting"
    if said is None:
        rpy = (spec.get("provenance") or {}).get("mounting_base_rpy_deg", (0.0, 0.0, 0.0))
        said, key = {"base_rpy_deg": rpy, "gravity_world": None}, "provenance"
    try:
        robot = as_mounted(robot, said["base_rpy_deg"], said["gravity_world"])
    except (TypeError, ValueError) as exc:
        raise InputError(f"the mounting the model was built with is not usable: {exc}"[:200],
                         path, column=key) from None
    # a guarantee's region and scale, checked against the robot (model_trust.check_region)
    # before the model's program is built and sampled
    if isinstance(guarantee := spec.get("guarantee"), dict):
        g = Guarantee.from_dict(guarantee, robot.n, float(spec.get("tolerance", "nan")), path)
        check_region(robot, g, float(spec.get("torque_floor", 0.0)), path)
    model = SimplifiedModel.from_dict(spec, robot, path)
    check_guarantee(model, path)
    return model

