"""The settings and provenance of an analysis as ``results.h5`` stores them: a typed view.

:class:`Provenance` holds the global attributes that say how the results were made: the
software and command, each setting asked for and what the model records it was built with,
the payload, the mounting, the formulations compared, the files emitted, and every other
attribute that no typed field shows (a setting of a newer version, say). Values are kept as
stored (None where the file has none): the reader decides how to write them. Read once by
:class:`gd_analyze.store.results_view.Results`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, fields
from typing import Any

from .names import ATTRIBUTES, VERIFICATION_PREFIX, Attr

__all__ = ["SHOWN_ELSEWHERE", "Provenance", "RunRecord"]

#: The attributes a typed view shows elsewhere (the robot and trajectory, the thresholds, the
#: simplified model's results, the region, the chapter's conclusions): not among the others.
SHOWN_ELSEWHERE = frozenset({
    # the robot, the trajectory, the thresholds and the file (Sec. 1, Sec. 7's first rows)
    Attr.ROBOT, Attr.ROBOT_DESCRIPTION, Attr.ROBOT_REFERENCE, Attr.ROBOT_SOURCE,
    Attr.ROBOT_SHA256, Attr.ROBOT_PLACEHOLDER_INERTIA, Attr.GRAVITY, Attr.GRAVITY_UNITS,
    Attr.INPUT_FILE, Attr.INPUT_PATH, Attr.INPUT_SHA256, Attr.DERIVATIVES, Attr.SETPOINTS,
    Attr.DOMINANCE_THRESHOLD, Attr.NEGLIGIBLE_THRESHOLD, Attr.TITLE, Attr.SOURCE,
    Attr.GD_ANALYZE_VERSION, Attr.HISTORY, Attr.COMMAND, Attr.CONVENTIONS, Attr.REFERENCES,
    # the simplified model's results (Sec. 5)
    Attr.SIMPLIFIED_TERMS_KEPT, Attr.SIMPLIFIED_PAIRS_DROPPED, Attr.SIMPLIFIED_PAIRS,
    Attr.SIMPLIFIED_DROPPED_PAIRS, Attr.SIMPLIFIED_MULTIPLICATIONS, Attr.SIMPLIFIED_ADDITIONS,
    Attr.SIMPLIFIED_SIN, Attr.SIMPLIFIED_COS, Attr.OTHER_RULE_MULTIPLICATIONS,
    Attr.OTHER_RULE_ADDITIONS, Attr.SIMPLIFIED_LADDER_SKIPPED, Attr.SIMPLIFIED_LADDER_FORM,
    Attr.SIMPLIFIED_FORM_NOTE, Attr.SIMPLIFIED_REGION_SCREEN, Attr.SIMPLIFIED_FILES,
    Attr.SIMPLIFIED_REGION_POSSIBLE_SAVING, Attr.SIMPLIFIED_REGION_SAVING_THRESHOLD,
    Attr.FULL_HARMONICS, Attr.FULL_COEFFICIENTS, Attr.OTHER_RULE_HARMONICS,
    Attr.OTHER_RULE_COEFFICIENTS, Attr.SIMPLIFIED_GUARANTEE_KIND, Attr.C_PREFIX,
    Attr.SIMPLIFIED_GUARANTEE_STATEMENT, Attr.SIMPLIFIED_GUARANTEE_TOLERANCE,
    # the formulations compared, the payload and the mounting
    Attr.FORMULATIONS_N, Attr.FORMULATIONS_SETPOINTS, Attr.FORMULATIONS_JOINT_TYPES,
    Attr.PAYLOAD_MASS, Attr.PAYLOAD_COM, Attr.PAYLOAD_INERTIA, Attr.MOUNTING_BASE_RPY_DEG,
    Attr.MOUNTING_GRAVITY_BASE, Attr.MOUNTING_GRAVITY_WORLD,
}) | {name for name in ATTRIBUTES      # D_s's check, the region, the chapter's conclusions
      if name.startswith(("simplified_inertia_check_", "region_", "chapter_"))}
#: The prefix of what the model records it was built with, beside the setting asked for.
_BUILT = "simplified_"


@dataclass(frozen=True)
class Provenance:
    """How the results were made: the provenance and settings attributes, as stored.

    Each field but ``others`` is the attribute of :class:`gd_analyze.store.names.Attr` of the
    same name, upper-cased (``conventions`` is ``Attr.CONVENTIONS``), None where not stored.

    Attributes
    ----------
    gd_analyze_version, command, history, conventions, references : object
        The software, the command line, the CF history ("<time> created by ..."), the CF
        conventions and the method's references.
    rule, tolerance, torque_floor, form, explicit, other_rule : object
        The settings asked for.
    simplified_rule, simplified_tolerance, simplified_torque_floor, simplified_form : object
        What the simplified model records it was built with.
    payload_mass, payload_com, payload_inertia : object
        The payload on the last link [kg, m, kg m^2].
    mounting_base_rpy_deg, mounting_gravity_world : object
        How the base is turned [deg] and gravity in the world [m/s^2].
    formulations_setpoints, formulations_n, formulations_joint_types : object
        What the formulations were compared on (``"RRP..."``).
    simplified_files : object
        The emitted source files.
    simplified_guarantee_kind, simplified_guarantee_statement : object
        The model's guarantee.
    verification_engine : object
        What the G-D terms were checked against.
    others : tuple of (str, object, object)
        Every other attribute (neither a field here nor :data:`SHOWN_ELSEWHERE` nor of the
        verification), sorted by name: (name, value, the value of the setting it records,
        ``simplified_<x>``'s ``<x>``, or None).
    """

    gd_analyze_version: Any
    command: Any
    history: Any
    conventions: Any
    references: Any
    rule: Any
    tolerance: Any
    torque_floor: Any
    form: Any
    explicit: Any
    other_rule: Any
    simplified_rule: Any
    simplified_tolerance: Any
    simplified_torque_floor: Any
    simplified_form: Any
    payload_mass: Any
    payload_com: Any
    payload_inertia: Any
    mounting_base_rpy_deg: Any
    mounting_gravity_world: Any
    formulations_setpoints: Any
    formulations_n: Any
    formulations_joint_types: Any
    simplified_files: Any
    simplified_guarantee_kind: Any
    simplified_guarantee_statement: Any
    verification_engine: Any
    others: tuple[tuple[str, Any, Any], ...]

    @classmethod
    def from_attrs(cls, attrs: Mapping[str, Any]) -> Provenance:
        """The provenance of a results dataset's global attributes.

        Parameters
        ----------
        attrs : Mapping
            The dataset's global attributes.

        Returns
        -------
        Provenance
        """
        names = {f.name: getattr(Attr, f.name.upper()) for f in fields(cls)
                 if f.name != "others"}
        typed = SHOWN_ELSEWHERE | set(names.values())
        others = tuple(
            (k, attrs[k], attrs.get(k[len(_BUILT):]) if k.startswith(_BUILT) else None)
            for k in sorted(attrs) if k not in typed and not k.startswith(VERIFICATION_PREFIX))
        return cls(**{f: attrs.get(name) for f, name in names.items()}, others=others)


@dataclass(frozen=True)
class RunRecord:
    """When and by what a stored run was computed, and the arm's gravity and mounting: the
    attributes every dataset (results, sweep, control) stores alike, as stored (None where
    missing).

    Attributes
    ----------
    gd_analyze_version, history : object
        The software, and the CF history ("<time> created by ...").
    gravity, mounting_gravity_base, mounting_gravity_world : object
        Gravity [m/s^2]: as the robot file gives it, in the base frame, in the world.
    mounting_base_rpy_deg : object
        How the base is turned: roll, pitch, yaw [deg].
    """

    gd_analyze_version: Any
    history: Any
    gravity: Any
    mounting_gravity_base: Any
    mounting_gravity_world: Any
    mounting_base_rpy_deg: Any

    @classmethod
    def from_attrs(cls, attrs: Mapping[str, Any]) -> RunRecord:
        """The record of a dataset's global attributes.

        Parameters
        ----------
        attrs : Mapping

        Returns
        -------
        RunRecord
        """
        return cls(**{f.name: attrs.get(getattr(Attr, f.name.upper())) for f in fields(cls)})
