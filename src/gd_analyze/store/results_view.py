"""A typed view of the main job's results: what the report and the command line read.

:class:`Results` is read once, from ``results.h5`` (:meth:`Results.open`) or from the dataset in
memory (:meth:`Results.from_dataset`, e.g. the main job's own summary), and checked as it is
read: a missing or renamed variable is one :class:`~gd_analyze.errors.InputError` naming the
file and the variable, not a ``KeyError`` when a report renders. The names are the constants of
:mod:`gd_analyze.store.names`. The round-off marks and the joints' units are those stored at
analysis (:func:`gd_analyze.store.datasets.summary_dataset`), never decided again here.

The ranking and the torque error are one view object each (:class:`RankingTable`,
:class:`TorqueErrorTable`), which the command line's text and the report's tables both render.
The robot and trajectory (:class:`StoredRobot`, :class:`StoredTrajectory`), the provenance
(:class:`Provenance`) and the comparisons (:class:`FormulationComparison`,
:class:`ChapterComparison`) are views of their own.
"""

from __future__ import annotations

import types
from collections import namedtuple
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError
from .datasets import JOINT_UNIT_COORDS, stored_guarantee, stored_region
from .names import (
    ATTRIBUTES,
    RANKING_COLUMNS,
    VERIFICATION_PREFIX,
    Attr,
    Var,
    verification_attribute,
)
from .schema import (
    Record,
    View,
    derived,
    open_results,
    stored,
    stored_has_drives,
    stored_name,
    stored_prismatic,
    strings,
    texts,
)
from .stored_simplified import BaseParameters, CostTable, StoredSimplified
from .sweep_view import PayloadSweep, payload_part

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr

__all__ = ["SHOWN_ELSEWHERE", "Provenance", "ROBOT_VARIABLES", "StoredRobot", "StoredTrajectory",
           "FormulationComparison", "ChapterComparison", "ZERO_MARK", "RankingRow", "RankingTable", "TorqueErrorRow", "TorqueErrorTable",
           "torque_table_header",
           "Verification", "Results"]

#: The attributes a typed view shows elsewhere (the robot and trajectory, the thresholds, the
#: simplified model's results, the region, the chapter's conclusions): not among the others.
SHOWN_ELSEWHERE = frozenset({
    # the robot, the trajectory, the thresholds and the file (Sec. 1, Sec. 7's first rows)
    Attr.ROBOT, Attr.ROBOT_DESCRIPTION, Attr.ROBOT_REFERENCE, Attr.ROBOT_SOURCE,
    Attr.ROBOT_SHA256, Attr.ROBOT_PLACEHOLDER_INERTIA, Attr.GRAVITY, Attr.GRAVITY_UNITS,
    Attr.INPUT_FILE, Attr.INPUT_PATH, Attr.INPUT_SHA256, Attr.DERIVATIVES, Attr.SETPOINTS,
    Attr.DOMINANCE_THRESHOLD, Attr.NEGLIGIBLE_THRESHOLD, Attr.TITLE, Attr.SOURCE,
    Attr.GD_ANALYZE_VERSION, Attr.HISTORY, Attr.COMMAND, Attr.CONVENTIONS, Attr.REFERENCES,
    Attr.C_PREFIX,
}) | {name for name in ATTRIBUTES      # the simplified model's results (Sec. 5) and D_s's
      # check, the formulations compared, the payload, the mounting, the region, the chapter's
      # conclusions: every such attribute the package writes
      if name.startswith(("simplified_", "other_rule_", "full_", "formulations_", "payload_",
                          "mounting_", "region_", "chapter_"))}

#: The prefix of what the model records it was built with, beside the setting asked for.
_BUILT = "simplified_"


class Provenance(Record, namedtuple("Provenance", """
        gd_analyze_version command history conventions references rule tolerance torque_floor
        form explicit other_rule guarantee simplified_rule simplified_tolerance
        simplified_torque_floor simplified_form payload_mass payload_com payload_inertia
        mounting_base_rpy_deg mounting_gravity_world formulations_setpoints formulations_n
        formulations_joint_types simplified_files simplified_guarantee_kind
        simplified_guarantee_statement verification_engine others""")):
    """How the results were made: the provenance and settings attributes, as stored.

    Each field but ``others`` is the attribute of :class:`gd_analyze.store.names.Attr` of the
    same name, upper-cased (``conventions`` is ``Attr.CONVENTIONS``), None where not stored.

    Attributes
    ----------
    gd_analyze_version, command, history, conventions, references : object
        The software, the command line, the CF history ("<time> created by ..."), the CF
        conventions and the method's references.
    rule, tolerance, torque_floor, form, explicit, other_rule, guarantee : object
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


    @classmethod
    def from_attrs(cls, attrs: Mapping[str, Any], prefix: str = "", /,
                   **given: Any) -> Provenance:
        """The provenance of a results dataset's global attributes.

        Parameters
        ----------
        attrs : Mapping
            The dataset's global attributes.
        prefix : str, optional
            The attributes' common prefix ("" in a results file).
        **given
            Fields given, not read (``others``: by default every other attribute).

        Returns
        -------
        Provenance
        """
        typed = SHOWN_ELSEWHERE | {stored_name(n) for n in cls._fields if n != "others"}
        given.setdefault("others", tuple(
            (k, attrs[k], attrs.get(k[len(_BUILT):]) if k.startswith(_BUILT) else None)
            for k in sorted(attrs) if k not in typed and not k.startswith(VERIFICATION_PREFIX)))
        return super().from_attrs(attrs, prefix, **given)

#: The robot's variables every results file holds.
ROBOT_VARIABLES = (Var.LINK_MASS, Var.LINK_COM, Var.LINK_INERTIA, Var.DH_D, Var.DH_A,
                   Var.DH_ALPHA, Var.DH_OFFSET)


@dataclass(frozen=True, eq=False)
class StoredRobot(View):
    """The robot of a results file, as the main job stored it.

    Attributes
    ----------
    description, reference, source, sha256, gravity : object
        The attributes ``robot_description``, ``robot_reference``, ``robot_source`` (the robot
        file), ``robot_sha256`` and ``gravity`` [m/s^2] as stored; None where missing.
    joint_type : tuple of str or None, length n
        ``"revolute"`` or ``"prismatic"`` per joint; None in a file without it.
    link_mass : ndarray, shape (n,)
        [kg].
    link_com : ndarray, shape (n, 3)
        Each link's centre of mass in its frame [m].
    link_inertia : ndarray, shape (n, 3, 3)
        Each link's inertia about its centre of mass [kg m^2].
    dh : ndarray, shape (4, n)
        The DH rows d [m or -], a [m], alpha [rad] and the joint offset [rad or m], in that
        order; NaN for a robot given by joint placements (URDF, chain).
    joint_rotation : ndarray, shape (n, 3, 3), or None
        Each joint's fixed rotation in body frame i-1 (URDF, chain); None where not stored.
    joint_translation : ndarray, shape (n, 3), or None
        Its fixed translation [m]; None where not stored.
    armature, viscous, coulomb : ndarray, shape (n,), or None
        The drives: armature [kg m^2 or kg], viscous [N m s/rad or N s/m] and Coulomb
        friction [N m or N]; None in a file without drives.
    torque_offset : ndarray, shape (n,), or None
        A constant torque of each drive [N m or N]; None where not stored.
    effort_limit : ndarray, shape (n,), or None
        The effort limits |tau| <= tau_max [N m or N] (NaN: not given); None in a file written
        before they were stored.
    placeholder_inertia : bool
        The robot file gave no inertia: placeholders were used.
    has_drives : bool
        Any armature, friction or torque offset is stored nonzero.
    """

    description: Any = stored(Attr.ROBOT_DESCRIPTION, default=None, attr=True)
    reference: Any = stored(Attr.ROBOT_REFERENCE, default=None, attr=True)
    source: Any = stored(Attr.ROBOT_SOURCE, default=None, attr=True)
    sha256: Any = stored(Attr.ROBOT_SHA256, default=None, attr=True)
    gravity: Any = stored(Attr.GRAVITY, default=None, attr=True)
    joint_type: tuple[str, ...] | None = stored(Var.JOINT_TYPE, texts, None)
    link_mass: np.ndarray = stored(Var.LINK_MASS)
    link_com: np.ndarray = stored(Var.LINK_COM)
    link_inertia: np.ndarray = stored(Var.LINK_INERTIA)
    dh: np.ndarray = derived(lambda ds: np.stack([ds[v].values for v in (
        Var.DH_D, Var.DH_A, Var.DH_ALPHA, Var.DH_OFFSET)]))
    joint_rotation: np.ndarray | None = stored(Var.JOINT_ROTATION, default=None)
    joint_translation: np.ndarray | None = stored(Var.JOINT_TRANSLATION, default=None)
    armature: np.ndarray | None = stored(Var.D_ARM, default=None)
    viscous: np.ndarray | None = stored(Var.VISCOUS, default=None)
    coulomb: np.ndarray | None = stored(Var.COULOMB, default=None)
    torque_offset: np.ndarray | None = stored(Var.TORQUE_OFFSET, default=None)
    effort_limit: np.ndarray | None = stored(Var.TAU_MAX, default=None)
    placeholder_inertia: bool = stored(Attr.ROBOT_PLACEHOLDER_INERTIA, bool, False, attr=True)
    has_drives: bool = derived(stored_has_drives)

    @property
    def drives(self) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """(armature, viscous, coulomb), each shape (n,); None where one is not stored."""
        if self.armature is None or self.viscous is None or self.coulomb is None:
            return None
        return self.armature, self.viscous, self.coulomb


@dataclass(frozen=True, eq=False)
class StoredTrajectory(View):
    """The analysed trajectory of a results file: its source, and its series read on demand.

    Attributes
    ----------
    input_file, input_path, input_sha256 : object
        The attributes of the trajectory file (name, path, SHA-256) as stored; None where
        missing.
    derivatives : str
        How q̇ and q̈ were obtained (``"file"``, ``"cubic-spline"``, ``"quintic"``,
        ``"arrays"``); "" where not stored.
    dataset : xarray.Dataset
        The dataset the series are read from.
    """

    input_file: Any = stored(Attr.INPUT_FILE, default=None, attr=True)
    input_path: Any = stored(Attr.INPUT_PATH, default=None, attr=True)
    input_sha256: Any = stored(Attr.INPUT_SHA256, default=None, attr=True)
    derivatives: str = stored(Attr.DERIVATIVES, str, "", attr=True)
    dataset: xr.Dataset = derived(lambda ds: ds)

    @property
    def t(self) -> np.ndarray:
        """ndarray, shape (N,): the time of each set point [s]."""
        return self.dataset[Var.T].values

    def motion_blocks(self, rows: int = 65536
                      ) -> Iterator[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """The motion (q, q̇, q̈) in consecutive blocks of set points, read one block at a time.

        Parameters
        ----------
        rows : int, optional
            Set points per block (>= 1).

        Yields
        ------
        (ndarray, ndarray, ndarray)
            q, q̇ and q̈ of the next block, each of shape (k, n), k <= ``rows``: joint positions
            [rad or m], velocities [rad/s or m/s] and accelerations [rad/s^2 or m/s^2]; memory
            stays a block whatever N is.
        """
        series = [self.dataset[v] for v in (Var.Q, Var.QD, Var.QDD)]
        step = max(1, int(rows))
        for a in range(0, series[0].shape[0], step):
            q, qd, qdd = (np.asarray(s[a:a + step].values, float) for s in series)
            yield q, qd, qdd

    @property
    def tau_f(self) -> np.ndarray | None:
        """ndarray, shape (N, n), or None: the drives' friction torque [N m or N]; None for a
        robot without drives."""
        return self.dataset[Var.TAU_F].values if Var.TAU_F in self.dataset.variables else None


@dataclass(frozen=True, eq=False)
class FormulationComparison(View):
    """The formulations run on the same set points and their operation counts.

    Attributes
    ----------
    quantities : tuple of str, length Q
        The quantities compared (``"D"``, ``"h"``, ``"c"``, ``"tau"``).
    pairs : tuple of str, length P
        ``"lagrange-euler vs gd"`` ...
    disagreement : ndarray, shape (P, Q)
        Each pair's largest relative disagreement per quantity [1].
    names : tuple of str, length F
        The formulations counted.
    dof : ndarray of int, shape (K,)
        The numbers of joints counted.
    multiplications, additions : ndarray of int, shape (K, F)
        Counted on the code as implemented, per set point.
    multiplications_table_3_5, additions_table_3_5 : ndarray of int, shape (K, F)
        By the formulas of Table 3.5.
    arm : tuple of (ndarray, ndarray) or None
        The multiplications and additions, shape (F,), for the arm's own joint types; None
        where not stored.
    n : int
        The arm's joint count the table is given for.
    setpoints : object
        The set points compared, as stored (None where missing).
    joint_types : str
        The arm's joint types, ``"RRP..."`` ("" where not stored).
    """

    presence = (Var.FORMULATION_DISAGREEMENT,)

    quantities: tuple[str, ...] = stored(Var.QUANTITY, texts)
    pairs: tuple[str, ...] = stored(Var.FORMULATION_PAIR, texts)
    disagreement: np.ndarray = stored(Var.FORMULATION_DISAGREEMENT)
    names: tuple[str, ...] = stored(Var.FORMULATION, texts)
    dof: np.ndarray = stored(Var.DOF)
    multiplications: np.ndarray = stored(Var.OP_MULTIPLICATIONS)
    additions: np.ndarray = stored(Var.OP_ADDITIONS)
    multiplications_table_3_5: np.ndarray = stored(Var.OP_MULTIPLICATIONS_TABLE_3_5)
    additions_table_3_5: np.ndarray = stored(Var.OP_ADDITIONS_TABLE_3_5)
    arm: tuple[np.ndarray, np.ndarray] | None = derived(lambda ds: (
        (ds[Var.OP_MULTIPLICATIONS_ARM].values, ds[Var.OP_ADDITIONS_ARM].values)
        if Var.OP_MULTIPLICATIONS_ARM in ds.variables else None))
    n: int = derived(lambda ds: int(ds.attrs.get(Attr.FORMULATIONS_N, ds.sizes[Var.JOINT])))
    setpoints: Any = stored(Attr.FORMULATIONS_SETPOINTS, default=None, attr=True)
    joint_types: str = stored(Attr.FORMULATIONS_JOINT_TYPES, str, "", attr=True)


@dataclass(frozen=True, eq=False)
class ChapterComparison(View):
    """The ranking against the chapter's conclusions for its PUMA 560 (Sec. 3.4.1).

    Attributes
    ----------
    blocks : dict of str to list of str
        ``"arm"``, ``"arm_translation"``, ``"wrist"``, ``"wrist_rotation"``: the elements the
        chapter ranks in the arm and the wrist, and those its conclusions say translation
        (arm) or rotation (wrist) leads.
    threshold : ndarray, shape (T,)
        The dominance thresholds s the agreement is counted at.
    agreement : ndarray of int, shape (T,)
        The elements whose class agrees with the chapter's at each threshold.
    elements_compared : int
        The elements compared.
    model_error_relative_peak : ndarray, shape (n,)
        The chapter's simplified model's peak torque error relative to peak |tau| [1].
    model_error_round_off : ndarray of bool, shape (n,)
        That error is round-off.
    """

    presence = (Var.CHAPTER_AGREEMENT,)

    blocks: dict[str, list[str]] = derived(lambda ds: {
        key: [k for k in str(ds.attrs.get(name, "")).split(", ") if k]
        for key, name in (("arm", Attr.CHAPTER_ARM_RANKED),
                          ("arm_translation", Attr.CHAPTER_ARM_TRANSLATION_LEADS),
                          ("wrist", Attr.CHAPTER_WRIST_RANKED),
                          ("wrist_rotation", Attr.CHAPTER_WRIST_ROTATION_LEADS))})
    threshold: np.ndarray = stored(Var.CHAPTER_THRESHOLD)
    agreement: np.ndarray = stored(Var.CHAPTER_AGREEMENT)
    elements_compared: int = stored(Attr.CHAPTER_ELEMENTS_COMPARED, int, attr=True)
    model_error_relative_peak: np.ndarray = stored(Var.CHAPTER_MODEL_ERROR_RELATIVE_PEAK)
    model_error_round_off: np.ndarray = stored(Var.CHAPTER_MODEL_ERROR_ROUND_OFF,
                                               lambda v: v.astype(bool))

#: Printed instead of a number that is round-off (zero to rounding).
ZERO_MARK = "\u2261 0"

#: Each number of a :class:`TorqueErrorRow` and the variable (dim joint) it is read from.
_TORQUE_ERROR_FIELDS = (("peak", Var.TAU_ERROR_PEAK), ("rms", Var.TAU_ERROR_RMS),
                        ("peak_tau", Var.TAU_PEAK), ("relative_peak", Var.TAU_ERROR_RELATIVE_PEAK),
                        ("relative_rms", Var.TAU_ERROR_RELATIVE_RMS))
#: The variables a results file must hold for the view (the round-off marks and the joints'
#: units as analysis stores them: they are read, never decided again).
REQUIRED = (*(c.name for c in RANKING_COLUMNS if c.required),
            *(c.round_off for c in RANKING_COLUMNS if c.round_off is not None),
            *(name for _, name in _TORQUE_ERROR_FIELDS), Var.JOINT, *ROBOT_VARIABLES,
            Var.ELEMENT_ROUND_OFF, Var.TAU_ERROR_ROUND_OFF, *JOINT_UNIT_COORDS)
#: The global attributes a results file must hold for the view.
REQUIRED_ATTRS = (Attr.ROBOT, Attr.INPUT_FILE, Attr.SETPOINTS, Attr.DOMINANCE_THRESHOLD,
                  Attr.NEGLIGIBLE_THRESHOLD)


class RankingRow:
    """One ranked element of D (i <= j) or h: its value in every column of the table.

    Its attributes are the fields of :class:`RankingTable` (``row.label``,
    ``row.share_tran``, ``row.peak_total``, ``row.round_off`` ...), as Python scalars.

    Parameters
    ----------
    table : RankingTable
        The table.
    k : int
        The element's index in it.
    """

    __slots__ = ("_table", "_k")

    def __init__(self, table: RankingTable, k: int) -> None:
        self._table, self._k = table, k

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        try:
            value = self._table.columns[name][self._k]
        except KeyError:
            raise AttributeError(name) from None
        return value.item() if isinstance(value, np.generic) else value


@dataclass(frozen=True, eq=False)
class RankingTable:
    """The dominance ranking, column by column: the one object both renderers read.

    Its columns are those of :data:`gd_analyze.store.names.RANKING_COLUMNS` that the file holds,
    by their field, plus ``round_off`` (the element is zero in every part: round-off, no
    share, shown as "\u2261 0"). In the stored order (D's upper triangle row by row, then h).

    Attributes
    ----------
    columns : Mapping of str to ndarray, each shape (M,)
        Field -> values: ``label``, ``share_tran``, ``dominance``, ``chapter_dominance``,
        ``choice``, ``peak_tran``, ``peak_rot``, ``peak_total``, ``scale``, ``units``, ``round_off``, and ``share_arm``, ``rigid_dominance`` where stored.
    offs : Mapping of str to ndarray of bool, each shape (M,)
        Field -> its round-off flag (:func:`gd_analyze.ranking.ranking.is_round_off`),
        for the columns that declare one.
    """

    columns: Mapping[str, np.ndarray]
    offs: Mapping[str, np.ndarray]

    def column(self, name: str) -> np.ndarray:
        """One column.

        Parameters
        ----------
        name : str
            Its field.

        Returns
        -------
        ndarray, shape (M,)

        Raises
        ------
        KeyError
            If the table has no such column (an optional one the file does not hold).
        """
        return self.columns[name]

    def off(self, name: str) -> np.ndarray:
        """A column's round-off flags.

        Parameters
        ----------
        name : str
            The field of a column that declares a round-off flag.

        Returns
        -------
        ndarray of bool, shape (M,)
        """
        return self.offs[name]

    @property
    def rows(self) -> tuple[RankingRow, ...]:
        """tuple of RankingRow, length M: the elements, in the stored order."""
        return tuple(RankingRow(self, k) for k in range(len(self.columns["label"])))

    def text(self) -> list[str]:
        """The ranking as the command line prints it: a header and one line per element.

        Returns
        -------
        list of str
            The columns of :data:`gd_analyze.store.names.RANKING_COLUMNS` with a ``cli``
            (element, share_tran with 4 decimals, class, peak_total with 4 significant
            digits, units); "\u2261 0" for a number of an element zero in every part.
        """
        shown = [(c.cli, self.columns[c.field]) for c in RANKING_COLUMNS
                 if c.cli is not None and c.field in self.columns]
        zero = self.columns["round_off"]
        return ["".join(f"{cli.lead}{cli.header:{cli.align}}" for cli, _ in shown)] + [
            "".join(cli.lead + (f"{values[k]:{cli.align}}" if not cli.number else
                                f"{ZERO_MARK:{cli.align}}" if zero[k] else
                                f"{values[k]:{cli.align}{cli.number}}") for cli, values in shown)
            for k in range(zero.size)]


@dataclass(frozen=True)
class TorqueErrorRow:
    """The simplified model's torque error at one joint, along the trajectory.

    Attributes
    ----------
    joint : int
        1 .. n.
    peak, rms : float
        Peak and RMS of |tau_s - tau| [N m or N].
    peak_tau : float
        Peak |tau| of the full model [N m or N].
    relative_peak, relative_rms : float
        peak and RMS error / peak |tau| [1].
    units : str
        ``"N m"`` (revolute) or ``"N"`` (prismatic).
    round_off : bool
        The error is round-off (stored at analysis), not data.
    """

    joint: int
    peak: float
    rms: float
    peak_tau: float
    relative_peak: float
    relative_rms: float
    units: str
    round_off: bool


def torque_table_header(units: list[str]) -> tuple[str, list[str]]:
    """The header of a per-joint torque-error table as printed, and each row's end.

    Parameters
    ----------
    units : list of str, length n
        Each joint's torque units (``"N m"`` or ``"N"``).

    Returns
    -------
    header : str
        ``[N m]`` in the header when every joint has the same units, else a units column.
    ends : list of str, length n
        What each row ends with: "" or its units.
    """
    same = len(set(units)) == 1
    unit = f" [{units[0]}]" if same else ""
    return (f"{'joint':<6}{'peak' + unit:>12}{'rms' + unit:>12}{'peak |tau|':>12}{'rel peak':>10}"
            f"{'rel rms':>10}{'' if same else '  units'}",
            [""] * len(units) if same else [f"  {u}" for u in units])


@dataclass(frozen=True)
class TorqueErrorTable:
    """The torque error per joint: the one object both renderers read.

    Attributes
    ----------
    rows : tuple of TorqueErrorRow, length n
    """

    rows: tuple[TorqueErrorRow, ...]

    def column(self, name: str) -> np.ndarray:
        """One field of every row as an array.

        Parameters
        ----------
        name : str
            A field of the rows.

        Returns
        -------
        ndarray, shape (len(rows),)
        """
        return np.array([getattr(r, name) for r in self.rows])

    def text(self) -> list[str]:
        """The table as the command line prints it.

        Returns
        -------
        list of str
            A header (``[N m]`` in it when every joint has the same units, else a units
            column) and one line per joint, "\u2261 0" for an error that is round-off.
        """
        header, ends = torque_table_header([r.units for r in self.rows])
        lines = [header]
        for r, end in zip(self.rows, ends):
            if r.round_off:                 # round-off of the joint's torque: not data
                lines.append(f"{r.joint:<6}{ZERO_MARK:>12}{ZERO_MARK:>12}{r.peak_tau:>12.4g}"
                             f"{ZERO_MARK:>10}{ZERO_MARK:>10}{end}")
            else:
                lines.append(f"{r.joint:<6}{r.peak:>12.4g}{r.rms:>12.4g}{r.peak_tau:>12.4g}"
                             f"{r.relative_peak:>10.2e}{r.relative_rms:>10.2e}{end}")
        return lines


@dataclass(frozen=True)
class Verification:
    """The check of the G-D terms against Pinocchio, as stored.

    Attributes
    ----------
    passed : bool
        Every term within the tolerance.
    worst_excess : float
        Largest relative difference beyond round-off over the terms (0: all within
        round-off, 64 eps of its scale; NaN where none is stored).
    setpoints : int
        The set points checked.
    terms : tuple of (str, float, float)
        Each term checked (``"D"``, ``"D_rot"`` ... in the order of its attribute's name), its
        largest relative difference and that beyond round-off.
    tolerance : object
        The relative tolerance as stored (None where missing).
    """

    passed: bool
    worst_excess: float
    setpoints: int
    terms: tuple[tuple[str, float, float], ...] = ()
    tolerance: Any = None


@dataclass(frozen=True, eq=False)
class Results(View):
    """The main job's results as the report and the command line read them.

    Attributes
    ----------
    robot : str
        The robot's name.
    input_file : str
        The trajectory file's name.
    setpoints : int
        N, the set points analysed.
    dominance_threshold, negligible_threshold : float
        s and e of the ranking.
    prismatic : tuple of bool, length n
        The prismatic joints.
    joint_units : Mapping of str to tuple of str
        ``"q"``, ``"qd"``, ``"qdd"``, ``"tau"`` -> the units of each joint, as stored at
        analysis (``q_units`` .. ``tau_units``).
    ranking : RankingTable
        The dominance ranking.
    torque_error : TorqueErrorTable
        The simplified model's torque error per joint.
    region : dict or None
        :func:`gd_analyze.store.datasets.stored_region`.
    guarantee : dict or None
        :func:`gd_analyze.store.datasets.stored_guarantee`.
    guarantee_kind : str
        Its kind, ``"region"``, ``"trajectory"`` or ``"none"`` (also where none is stored).
    inertia_check : str
        The proof (or sample) of D_s's positive definiteness, "" where none is stored.
    verification : Verification or None
        The check against Pinocchio; None where it was not run.
    robot_record : StoredRobot
        The robot as stored: links, geometry, drives, effort limits, its file.
    trajectory : StoredTrajectory
        The trajectory's file, and its series read on demand.
    share_arm : ndarray, shape (M,), or None
        Each ranked element's armature share (None for a robot without drives).
    costs : CostTable or None
        The simplified model's operations beside the models it is compared with.
    region_screen : str
        Why a screen chose the exact recursive model, "" where none did.
    region_screen_proved : bool
        That screen is the one of the pairs searched under the proved bounds (the region
        certified), not the sampled pre-screen that skipped the certification.
    base_parameters : BaseParameters or None
        The base parameters of a recursive model (None for an explicit one).
    simplified_operations : tuple of (int, int) or None
        The emitted model's multiplications and additions per set point; None without a
        simplified model.
    pairs : tuple of (int, int)
        A recursive model's dropped (link, part) pairs and all its pairs (0 where not stored).
    formulations : FormulationComparison or None
        The formulations checked against each other and counted (None where not run).
    chapter : ChapterComparison or None
        The ranking against the chapter's PUMA 560 (None for another robot).
    rigid_dominance : tuple of str or None, length M
        Each element's class for the rigid links alone (drives left out); None for a robot
        without drives.
    provenance : Provenance
        How the results were made: software, command, settings, payload, mounting.
    simplified : StoredSimplified or None
        The simplified model's record: its rule, bound, costs, ladder, check of D_s (None
        where the file holds no simplified model).
    payload : PayloadSweep or None
        The ranking repeated for each load mass on the last link (None without a payload
        sweep).
    attrs : Mapping
        Every global attribute (the provenance), read-only.
    dataset : xarray.Dataset
        The dataset read (the figures' series and the sections not yet typed).
    source : str
        The file read, or ``"<memory>"``.
    """

    robot: str = stored(Attr.ROBOT, str, attr=True)
    input_file: str = stored(Attr.INPUT_FILE, str, attr=True)
    setpoints: int = stored(Attr.SETPOINTS, int, attr=True)
    dominance_threshold: float = stored(Attr.DOMINANCE_THRESHOLD, float, attr=True)
    negligible_threshold: float = stored(Attr.NEGLIGIBLE_THRESHOLD, float, attr=True)
    prismatic: tuple[bool, ...] = derived(stored_prismatic)
    joint_units: Mapping[str, tuple[str, ...]] = derived(lambda ds: _joint_units(ds))
    ranking: RankingTable = derived(lambda ds: _ranking(ds))
    torque_error: TorqueErrorTable = derived(lambda ds: _torque_error(
        ds, _joint_units(ds)["tau"]))
    region: dict | None = derived(stored_region)
    guarantee: dict | None = derived(stored_guarantee)
    guarantee_kind: str = derived(lambda ds: (stored_guarantee(ds) or {}).get("kind", "none"))
    inertia_check: str = stored(Attr.SIMPLIFIED_INERTIA_CHECK_STATEMENT, str, "", attr=True)
    verification: Verification | None = derived(lambda ds: _verification(ds.attrs))
    robot_record: StoredRobot = derived(StoredRobot.read)
    trajectory: StoredTrajectory = derived(StoredTrajectory.read)
    share_arm: np.ndarray | None = stored(Var.SHARE_ARM, default=None)
    costs: CostTable | None = derived(CostTable.from_dataset)
    region_screen: str = stored(Attr.SIMPLIFIED_REGION_SCREEN, str, "", attr=True)
    region_screen_proved: bool = stored(Attr.SIMPLIFIED_REGION_SCREEN_PROVED,
                                        lambda v: bool(int(v)), False, attr=True)
    base_parameters: BaseParameters | None = derived(BaseParameters.from_dataset)
    simplified_operations: tuple[int, int] | None = derived(lambda ds: (
        (int(ds.attrs[Attr.SIMPLIFIED_MULTIPLICATIONS]), int(ds.attrs[Attr.SIMPLIFIED_ADDITIONS]))
        if Attr.SIMPLIFIED_MULTIPLICATIONS in ds.attrs else None))
    pairs: tuple[int, int] = derived(lambda ds: (
        int(ds.attrs.get(Attr.SIMPLIFIED_PAIRS_DROPPED, 0)),
        int(ds.attrs.get(Attr.SIMPLIFIED_PAIRS, 0))))
    formulations: FormulationComparison | None = derived(FormulationComparison.from_dataset)
    chapter: ChapterComparison | None = derived(ChapterComparison.from_dataset)
    rigid_dominance: tuple[str, ...] | None = stored(
        Var.DOMINANCE_RIGID_LINKS, lambda v: tuple(str(x) for x in v), None)
    provenance: Provenance = derived(lambda ds: Provenance.from_attrs(ds.attrs))
    simplified: StoredSimplified | None = derived(StoredSimplified.from_dataset)
    payload: PayloadSweep | None = derived(lambda ds: (
        PayloadSweep.from_dataset(payload_part(ds)) if Var.PAYLOAD_SHARE_TRAN in ds.variables
        else None))
    attrs: Mapping = derived(lambda ds: types.MappingProxyType(dict(ds.attrs)))
    dataset: xr.Dataset = derived(lambda ds: ds)
    source: str = "<memory>"

    @classmethod
    def open(cls, path: str | Path, lazy: bool = False) -> Results:
        """Read a ``results.h5`` written by the main job.

        Parameters
        ----------
        path : str or os.PathLike
            The file.
        lazy : bool, optional
            Leave the per-set-point series on disk, read in slices (the caller closes
            ``results.dataset``).

        Returns
        -------
        Results

        Raises
        ------
        InputError
            If the file is missing, unreadable, or lacks a variable or attribute of a results
            file (the message names the file and the variable).
        """
        return cls.from_dataset(open_results(path, lazy=lazy), source=str(path))

    @classmethod
    def from_dataset(cls, ds: xr.Dataset, source: str = "<memory>") -> Results:
        """The view of a results dataset (in memory, or opened by :meth:`open`).

        Parameters
        ----------
        ds : xarray.Dataset
            As :func:`gd_analyze.store.datasets.summary_dataset` builds it (the main job's summary
            or ``gd_analyze.analyze``'s dataset).
        source : str, optional
            The file it was read from, for the messages.

        Returns
        -------
        Results

        Raises
        ------
        InputError
            If a variable or attribute of a results file is missing.
        """
        for kind, names, held in (("variable", REQUIRED, ds.variables),
                                  ("attribute", REQUIRED_ATTRS, ds.attrs)):
            for name in names:
                if name not in held:
                    raise InputError(f"missing {kind} {name!r}: not a gd-analyze results file",
                                     source)
        return cls.read(ds, source=source)


def _joint_units(ds):
    """The units of each joint's q, qd, qdd and tau, as stored."""
    return types.MappingProxyType({q: texts(ds[name].values)
                                   for name, (q, _) in JOINT_UNIT_COORDS.items()})


def _flags(ds, name):
    return np.asarray(ds[name].values).astype(bool)


def _ranking(ds):
    """The ranking table, as :data:`gd_analyze.store.names.RANKING_COLUMNS` declares it, with
    the round-off marks stored at analysis."""
    columns = {c.field: (np.array(strings(ds[c.name].values)) if c.text
                         else np.asarray(ds[c.name].values, float))
               for c in RANKING_COLUMNS if c.source != "armature" and c.name in ds.variables}
    columns["round_off"] = _flags(ds, Var.ELEMENT_ROUND_OFF)
    offs = {c.field: _flags(ds, c.round_off) for c in RANKING_COLUMNS
            if c.round_off is not None and c.field in columns}
    return RankingTable(columns=types.MappingProxyType(columns),
                        offs=types.MappingProxyType(offs))


def _torque_error(ds, units):
    """The torque-error table, with the round-off marks stored at analysis."""
    v = {field: np.asarray(ds[name].values, float) for field, name in _TORQUE_ERROR_FIELDS}
    off = _flags(ds, Var.TAU_ERROR_ROUND_OFF)
    return TorqueErrorTable(rows=tuple(
        TorqueErrorRow(joint=j + 1, **{field: float(x[j]) for field, x in v.items()},
                       units=units[j], round_off=bool(off[j]))
        for j in range(len(units))))


def _verification(attrs):
    if Attr.VERIFICATION_PASSED not in attrs:
        return None
    excess = [float(v) for k, v in attrs.items()
              if k.startswith(VERIFICATION_PREFIX + "max_rel_excess")]
    error = verification_attribute("")
    terms = tuple((k[len(error):], float(attrs[k]),
                   float(attrs[verification_attribute(k[len(error):], excess=True)]))
                  for k in sorted(attrs) if k.startswith(error))
    return Verification(passed=bool(int(attrs[Attr.VERIFICATION_PASSED])),
                        worst_excess=float(np.max(excess)) if excess else float("nan"),
                        setpoints=int(attrs[Attr.VERIFICATION_SETPOINTS]),
                        terms=terms, tolerance=attrs.get(Attr.VERIFICATION_TOLERANCE))
