"""A typed view of the main job's results: what the report and the command line read.

:class:`Results` is read once, from ``results.h5`` (:meth:`Results.open`) or from the dataset in
memory (:meth:`Results.from_dataset`, e.g. the main job's own summary), and checked as it is
read: a missing or renamed variable is one :class:`~gd_analyze.errors.InputError` naming the
file and the variable, not a ``KeyError`` when a report renders. The names are the constants of
:mod:`gd_analyze.store.names`. The round-off marks and the joints' units are those stored at
analysis (:func:`gd_analyze.store.datasets.summary_dataset`), never decided again here.

The ranking and the torque error are one view object each (:class:`RankingTable`,
:class:`TorqueErrorTable`), which the command line's text and the report's tables both render.
"""

from __future__ import annotations

import types
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError
from ..ranking.ranking import arm_scales, identically_zero, is_round_off
from .datasets import joint_units as _units_of
from .datasets import stored_guarantee, stored_region
from .names import RANKING_COLUMNS, VERIFICATION_PREFIX, Attr, Var, verification_attribute
from .schema import View, open_results, optional, stored_prismatic, strings
from .stored_comparisons import ChapterComparison, FormulationComparison
from .stored_model import BaseParameters, CostTable
from .stored_provenance import Provenance
from .stored_robot import ROBOT_VARIABLES, StoredRobot, StoredTrajectory
from .stored_simplified import StoredSimplified
from .sweep_datasets import payload_part
from .sweep_view import PayloadSweep

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr

__all__ = ["ZERO_MARK", "RankingRow", "RankingTable", "TorqueErrorRow", "TorqueErrorTable",
           "torque_table_header",
           "Verification", "Results"]

#: Printed instead of a number that is round-off (zero to rounding).
ZERO_MARK = "\u2261 0"

#: The variables a results file must hold for the view.
REQUIRED = (*(c.name for c in RANKING_COLUMNS if c.required), Var.TAU_ERROR_PEAK,
            Var.TAU_ERROR_RMS, Var.TAU_PEAK, Var.TAU_ERROR_RELATIVE_PEAK, Var.TAU_ERROR_RELATIVE_RMS, Var.JOINT, *ROBOT_VARIABLES)
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


class _Rows:
    """A table of frozen rows: one field of every row as an array."""

    rows: tuple

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
        ``choice``, ``peak_tran``, ``peak_rot``, ``peak_total``, ``scale`` (NaN for an older
        file), ``units``, ``round_off``, and ``share_arm``, ``rigid_dominance`` where stored.
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
        lines = ["".join(f"{cli.lead}{cli.header:{cli.align}}" for cli, _ in shown)]
        zero = self.columns["round_off"]
        for k in range(zero.size):
            lines.append("".join(
                cli.lead + (f"{values[k]:{cli.align}}" if not cli.number else
                            f"{ZERO_MARK:{cli.align}}" if zero[k] else
                            f"{values[k]:{cli.align}{cli.number}}")
                for cli, values in shown))
        return lines


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
    if len(set(units)) == 1:
        u = f" [{units[0]}]"
        return (f"{'joint':<6}{'peak' + u:>12}{'rms' + u:>12}{'peak |tau|':>12}"
                f"{'rel peak':>10}{'rel rms':>10}"), [""] * len(units)
    return (f"{'joint':<6}{'peak':>12}{'rms':>12}{'peak |tau|':>12}{'rel peak':>10}"
            f"{'rel rms':>10}  units"), [f"  {u}" for u in units]


@dataclass(frozen=True)
class TorqueErrorTable(_Rows):
    """The torque error per joint: the one object both renderers read.

    Attributes
    ----------
    rows : tuple of TorqueErrorRow, length n
    """

    rows: tuple[TorqueErrorRow, ...]

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
        largest relative difference and that beyond round-off (NaN in a file written before
        it was stored).
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
        Why the region's certification was skipped, "" where it was not.
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

    robot: str
    input_file: str
    setpoints: int
    dominance_threshold: float
    negligible_threshold: float
    prismatic: tuple[bool, ...]
    joint_units: Mapping[str, tuple[str, ...]]
    ranking: RankingTable
    torque_error: TorqueErrorTable
    region: dict | None
    guarantee: dict | None
    inertia_check: str
    verification: Verification | None
    robot_record: StoredRobot
    trajectory: StoredTrajectory
    share_arm: np.ndarray | None
    costs: CostTable | None
    region_screen: str
    base_parameters: BaseParameters | None
    simplified_operations: tuple[int, int] | None
    pairs: tuple[int, int]
    formulations: FormulationComparison | None
    chapter: ChapterComparison | None
    rigid_dominance: tuple[str, ...] | None
    provenance: Provenance
    simplified: StoredSimplified | None
    payload: PayloadSweep | None
    attrs: Mapping
    dataset: xr.Dataset
    source: str = "<memory>"

    @property
    def guarantee_kind(self) -> str:
        """str: the stored guarantee's kind, ``"region"``, ``"trajectory"`` or ``"none"``
        (also where the file stores none)."""
        return "none" if self.guarantee is None else str(self.guarantee["kind"])

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
        for name in REQUIRED:
            if name not in ds.variables:
                raise InputError(f"missing variable {name!r}: not a gd-analyze results file",
                                 source)
        for name in REQUIRED_ATTRS:
            if name not in ds.attrs:
                raise InputError(f"missing attribute {name!r}: not a gd-analyze results file",
                                 source)
        prismatic = stored_prismatic(ds)
        joint_units = types.MappingProxyType(
            {q: tuple(strings(ds[name].values)) if name in ds.variables
             else _default_units(q, prismatic)
             for q, name in (("q", Var.Q_UNITS), ("qd", Var.QD_UNITS), ("qdd", Var.QDD_UNITS),
                             ("tau", Var.TAU_UNITS))})
        attrs = types.MappingProxyType(dict(ds.attrs))
        return cls(robot=str(attrs[Attr.ROBOT]), input_file=str(attrs[Attr.INPUT_FILE]),
                   setpoints=int(attrs[Attr.SETPOINTS]),
                   dominance_threshold=float(attrs[Attr.DOMINANCE_THRESHOLD]),
                   negligible_threshold=float(attrs[Attr.NEGLIGIBLE_THRESHOLD]),
                   prismatic=prismatic, joint_units=joint_units, ranking=_ranking(ds),
                   torque_error=_torque_error(ds, joint_units["tau"]),
                   region=stored_region(ds), guarantee=stored_guarantee(ds),
                   inertia_check=str(attrs.get(Attr.SIMPLIFIED_INERTIA_CHECK_STATEMENT, "")),
                   verification=_verification(attrs),
                   robot_record=StoredRobot.from_dataset(ds),
                   trajectory=StoredTrajectory.from_dataset(ds),
                   share_arm=optional(ds, Var.SHARE_ARM),
                   costs=CostTable.from_dataset(ds),
                   region_screen=str(attrs.get(Attr.SIMPLIFIED_REGION_SCREEN, "")),
                   base_parameters=BaseParameters.from_dataset(ds),
                   simplified_operations=_operations(attrs),
                   pairs=(int(attrs.get(Attr.SIMPLIFIED_PAIRS_DROPPED, 0)),
                          int(attrs.get(Attr.SIMPLIFIED_PAIRS, 0))),
                   formulations=FormulationComparison.from_dataset(ds),
                   chapter=ChapterComparison.from_dataset(ds),
                   rigid_dominance=(tuple(str(v) for v in ds[Var.DOMINANCE_RIGID_LINKS].values)
                                    if Var.DOMINANCE_RIGID_LINKS in ds.variables else None),
                   provenance=Provenance.from_attrs(attrs),
                   simplified=StoredSimplified.from_dataset(ds),
                   payload=(PayloadSweep.from_dataset(payload_part(ds))
                            if Var.PAYLOAD_SHARE_TRAN in ds.variables else None),
                   attrs=attrs, dataset=ds, source=source)


def _default_units(which, prismatic):
    """The units of a file written before the per-joint units were stored."""
    return tuple(_units_of(prismatic, which))


def _flags(ds, name):
    return np.asarray(ds[name].values).astype(bool) if name in ds.variables else None


def _ranking(ds):
    """The ranking table, as :data:`gd_analyze.store.names.RANKING_COLUMNS` declares it: stored
    round-off marks; for a file written before they were stored, the same rule once here."""
    M = int(ds.sizes[Var.ELEMENT])
    columns = {}
    for c in RANKING_COLUMNS:
        if c.source == "armature":
            continue
        if c.name in ds.variables:
            values = ds[c.name].values
            columns[c.field] = (np.array(strings(values)) if c.text
                                else np.asarray(values, float))
    columns.setdefault("scale", np.full(M, np.nan))     # a file written before it was stored
    scale, units = columns["scale"], list(columns["units"])
    zero = _flags(ds, Var.ELEMENT_ROUND_OFF)
    if zero is None:
        zero = (identically_zero(columns["peak_tran"], columns["peak_rot"],
                                 columns["peak_total"], scale)
                if Var.ELEMENT_SCALE in ds.variables else np.zeros(M, bool))
    columns["round_off"] = np.asarray(zero, bool)
    offs = {}
    for c in RANKING_COLUMNS:
        if c.round_off is not None and c.field in columns:
            mark = _flags(ds, c.round_off)
            offs[c.field] = (mark if mark is not None else
                             np.asarray(is_round_off(columns[c.field], scale,
                                                     arm_scale=arm_scales(scale, units)), bool))
    return RankingTable(columns=types.MappingProxyType(columns),
                        offs=types.MappingProxyType(offs))


def _torque_error(ds, units):
    """The torque-error table: the round-off marks stored at analysis; for a file written
    before they were stored, the same rule once here."""
    v = {name: np.asarray(ds[name].values, float)
         for name in (Var.TAU_ERROR_PEAK, Var.TAU_ERROR_RMS, Var.TAU_PEAK,
                      Var.TAU_ERROR_RELATIVE_PEAK, Var.TAU_ERROR_RELATIVE_RMS)}
    off = _flags(ds, Var.TAU_ERROR_ROUND_OFF)
    if off is None:
        tau = v[Var.TAU_PEAK]
        off = np.asarray(is_round_off(v[Var.TAU_ERROR_PEAK], tau,
                                      arm_scale=arm_scales(tau, list(units))), bool)
    return TorqueErrorTable(rows=tuple(
        TorqueErrorRow(joint=j + 1, peak=float(v[Var.TAU_ERROR_PEAK][j]),
                       rms=float(v[Var.TAU_ERROR_RMS][j]), peak_tau=float(v[Var.TAU_PEAK][j]),
                       relative_peak=float(v[Var.TAU_ERROR_RELATIVE_PEAK][j]),
                       relative_rms=float(v[Var.TAU_ERROR_RELATIVE_RMS][j]), units=units[j],
                       round_off=bool(off[j]))
        for j in range(len(units))))


def _operations(attrs):
    """The emitted model's (multiplications, additions), or None where not stored."""
    try:
        return (int(attrs[Attr.SIMPLIFIED_MULTIPLICATIONS]),
                int(attrs[Attr.SIMPLIFIED_ADDITIONS]))
    except (KeyError, TypeError, ValueError):
        return None


def _verification(attrs):
    if Attr.VERIFICATION_PASSED not in attrs:
        return None
    excess = [float(v) for k, v in attrs.items()
              if k.startswith(VERIFICATION_PREFIX + "max_rel_excess")]
    error = verification_attribute("")
    terms = tuple((k[len(error):], float(attrs[k]),
                   float(attrs.get(verification_attribute(k[len(error):], excess=True),
                                   np.nan)))
                  for k in sorted(attrs) if k.startswith(error))
    return Verification(passed=bool(int(attrs[Attr.VERIFICATION_PASSED])),
                        worst_excess=float(np.max(excess)) if excess else float("nan"),
                        setpoints=int(attrs.get(Attr.VERIFICATION_SETPOINTS,
                                                attrs[Attr.SETPOINTS])),
                        terms=terms, tolerance=attrs.get(Attr.VERIFICATION_TOLERANCE))
