"""The simplified model's results as ``results.h5`` stores them: a typed view.

:class:`StoredSimplified` holds what the report's "Simplified model" section and the figures of
the error budget read: the rule and its settings, what the model keeps and costs, the bound on
|tau_s - tau| per joint and its parts, the measured error, the cost table and the tolerance
ladder, the check of D_s (:class:`InertiaCheck`), the region and the guarantee, as
:func:`gd_analyze.jobs.simplified_dataset.simplified_dataset` stored them. Read once, by
:class:`gd_analyze.store.results_view.Results` or :meth:`StoredSimplified.of`; the series (t, tau,
tau_s) stay in the dataset and are read on demand. The names are those of
:mod:`gd_analyze.store.names`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .datasets import joint_units, stored_guarantee, stored_region
from .names import Attr, Var
from .schema import View, optional, stored_prismatic, strings
from .stored_model import CostTable

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr

__all__ = ["InertiaCheck", "Ladder", "StoredSimplified"]

#: The stored counts that say why a pruned explicit model can cost more than the full one.
_STRUCTURE = (Attr.FULL_HARMONICS, Attr.FULL_COEFFICIENTS, Attr.OTHER_RULE_HARMONICS,
              Attr.OTHER_RULE_COEFFICIENTS)


def _structure(attrs: Mapping[str, Any]) -> tuple[int, int, int, int] | None:
    if not all(k in attrs for k in _STRUCTURE):
        return None
    fh, fc, oh, oc = (int(attrs[k]) for k in _STRUCTURE)
    return fh, fc, oh, oc


@dataclass(frozen=True)
class InertiaCheck:
    """The check that D_s, the simplified model's inertia matrix, is positive definite.

    Attributes
    ----------
    proved : bool
        Proved by interval arithmetic rounded outward.
    where : str
        ``"region"`` (the joint-limit region) or the trajectory's bounding box of positions.
    lower_bound, ratio : float
        The proved least eigenvalue [kg m^2 or kg], and its ratio to D's over the same
        positions [1] (NaN where not proved).
    restored : str
        The base parameters kept with all their parts for the proof, comma-separated.
    statement : str
        The sentence every output states.
    samples : int
        The positions sampled.
    sampled_min_eigenvalue : float
        The least eigenvalue at those samples (NaN where not stored).
    """

    proved: bool
    where: str
    lower_bound: float
    ratio: float
    restored: str
    statement: str
    samples: int
    sampled_min_eigenvalue: float

    @classmethod
    def from_attrs(cls, attrs: Mapping[str, Any]) -> InertiaCheck | None:
        """The check of a results dataset's attributes.

        Parameters
        ----------
        attrs : Mapping
            The ``simplified_inertia_check_*`` attributes
            (:func:`gd_analyze.jobs.simplified_dataset.inertia_check_attrs`).

        Returns
        -------
        InertiaCheck or None
            None where no check is stored.
        """
        if Attr.SIMPLIFIED_INERTIA_CHECK_PROVED not in attrs:
            return None
        proved = bool(int(attrs[Attr.SIMPLIFIED_INERTIA_CHECK_PROVED]))
        nan = float("nan")
        return cls(proved=proved, where=str(attrs[Attr.SIMPLIFIED_INERTIA_CHECK_WHERE]),
                   lower_bound=(float(attrs[Attr.SIMPLIFIED_INERTIA_CHECK_LOWER_BOUND])
                                if proved else nan),
                   ratio=float(attrs[Attr.SIMPLIFIED_INERTIA_CHECK_RATIO]) if proved else nan,
                   restored=str(attrs.get(Attr.SIMPLIFIED_INERTIA_CHECK_RESTORED, "")),
                   statement=str(attrs.get(Attr.SIMPLIFIED_INERTIA_CHECK_STATEMENT, "")),
                   samples=(0 if proved else
                            int(attrs[Attr.SIMPLIFIED_INERTIA_CHECK_SAMPLES])),
                   sampled_min_eigenvalue=float(attrs.get(
                       Attr.SIMPLIFIED_INERTIA_CHECK_SAMPLED_MIN_EIGENVALUE, nan)))


@dataclass(frozen=True, eq=False)
class Ladder:
    """The tolerance ladder: the model rebuilt at several EPS.

    Attributes
    ----------
    tolerance : ndarray, shape (L,)
        Each rung's EPS [1].
    operations, trig : ndarray, shape (L,)
        Its multiplications + additions, and its sin and cos calls, per set point.
    worst_error : ndarray, shape (L,)
        Its worst measured peak |tau_s - tau| / s_i on the trajectory [1].
    worst_bound : ndarray, shape (L,), or None
        Its largest bound / s_i [1]; None where not stored.
    """

    tolerance: np.ndarray
    operations: np.ndarray
    trig: np.ndarray
    worst_error: np.ndarray
    worst_bound: np.ndarray | None


@dataclass(frozen=True, eq=False)
class StoredSimplified(View):
    """The simplified model's record of a results dataset.

    Attributes
    ----------
    rule : str
        ``"budget"`` or ``"chapter"`` ("" where not stored).
    tolerance, torque_floor : float
        EPS [1] (NaN where not stored) and the least scale of a joint torque [N m].
    form : str
        ``"explicit"`` or ``"recursive"``.
    files : tuple of str
        The emitted files.
    choice : tuple of str, length M
        The part each element keeps (empty where not stored).
    terms_kept, multiplications, additions, sin, cos : object
        The explicit model's terms kept (-1 for a recursive one), the emitted code's
        operations and trigonometric calls per set point, as stored (None where not).
    pairs, pairs_dropped : int
        A recursive model's (parameter, part) pairs that contribute, and those dropped.
    base_parameters : int
        The base parameters stored (0 for an explicit model).
    inertia_check : InertiaCheck or None
    other_rule : str
        The other rule, whose model is built beside ("" where none).
    other_rule_multiplications, other_rule_additions : object
        Its operations as stored (None where not).
    other_rule_error_relative_peak : ndarray, shape (n,), or None
        Its peak error / peak |tau_i| per joint [1].
    structure : tuple of int or None
        The full explicit model's harmonics and distinct coefficients, and the other rule's
        (:func:`gd_analyze.jobs.simplified_dataset.coefficient_structure`); None where not
        stored.
    scale : ndarray, shape (n,), or None
        s_i, each joint's scale [N m or N].
    bound : ndarray, shape (n,)
        The bound on |tau_s - tau| [N m or N].
    bound_inertia, bound_coriolis, bound_gravity, bound_whole : ndarray, shape (n,), or None
        Its parts from D qdd, h, c and base parameters dropped whole.
    tau_error_peak, tau_peak : ndarray, shape (n,), or None
        The measured peak |tau_s - tau| and peak |tau| [N m or N].
    costs : CostTable or None
    ladder : Ladder or None
    ladder_skipped : str
        Why the ladder was not built ("" where it was).
    ladder_form : str
        The form of the ladder's models.
    c_prefix, form_note, region_screen : str
        The emitted C symbols' prefix, why this form, why the region's certification was
        skipped ("" where not stored).
    region : dict or None
        :func:`gd_analyze.store.datasets.stored_region`.
    region_source, region_notes : str
        Where the region's limits come from, and what was clipped to the robot's.
    guarantee : dict or None
        :func:`gd_analyze.store.datasets.stored_guarantee`.
    prismatic : tuple of bool, length n
        The prismatic joints.
    has_drives : bool
        The robot has armature, friction or a torque offset.
    dataset : xarray.Dataset
        The dataset the series are read from.
    """

    rule: str
    form: str
    files: tuple[str, ...]
    choice: tuple[str, ...]
    tolerance: float
    torque_floor: float
    terms_kept: Any
    multiplications: Any
    additions: Any
    sin: Any
    cos: Any
    pairs: int
    pairs_dropped: int
    base_parameters: int
    inertia_check: InertiaCheck | None
    other_rule: str
    other_rule_multiplications: Any
    other_rule_additions: Any
    other_rule_error_relative_peak: np.ndarray | None
    structure: tuple[int, int, int, int] | None
    scale: np.ndarray | None
    bound: np.ndarray
    bound_inertia: np.ndarray | None
    bound_coriolis: np.ndarray | None
    bound_gravity: np.ndarray | None
    bound_whole: np.ndarray | None
    tau_error_peak: np.ndarray | None
    tau_peak: np.ndarray | None
    costs: CostTable | None
    ladder: Ladder | None
    ladder_skipped: str
    ladder_form: str
    c_prefix: str
    form_note: str
    region_screen: str
    region: dict | None
    region_source: str
    region_notes: str
    guarantee: dict | None
    prismatic: tuple[bool, ...]
    has_drives: bool
    dataset: xr.Dataset

    @classmethod
    def of(cls, results: StoredSimplified | xr.Dataset, *args: Any) -> StoredSimplified:
        """The view itself, or the view of a results dataset.

        Parameters
        ----------
        results : StoredSimplified or xarray.Dataset
            With the simplified model (``simplified_bound``).
        *args
            None.

        Returns
        -------
        StoredSimplified

        Raises
        ------
        ValueError
            If the dataset holds no simplified model.
        """
        view = super().of(results)
        if view is None:
            raise ValueError(f"no simplified model stored (no {Var.SIMPLIFIED_BOUND!r})")
        return view

    @classmethod
    def from_dataset(cls, ds: xr.Dataset) -> StoredSimplified | None:
        """The simplified model's record of a results dataset.

        Parameters
        ----------
        ds : xarray.Dataset
            As :func:`gd_analyze.store.datasets.summary_dataset` builds it.

        Returns
        -------
        StoredSimplified or None
            None where no simplified model is stored (no ``simplified_bound``).
        """
        if Var.SIMPLIFIED_BOUND not in ds.variables:
            return None
        a = ds.attrs
        b = int(ds.sizes.get(Var.BASE_PARAMETER, 0))
        ladder = None
        if Var.LADDER_OPERATIONS in ds.variables:
            ladder = Ladder(tolerance=ds[Var.LADDER_TOLERANCE].values,
                            operations=ds[Var.LADDER_OPERATIONS].values,
                            trig=ds[Var.LADDER_TRIG].values,
                            worst_error=ds[Var.LADDER_WORST_ERROR].values,
                            worst_bound=optional(ds, Var.LADDER_WORST_BOUND))
        drives = any(k in ds.variables and np.any(np.asarray(ds[k].values, float) != 0)
                     for k in (Var.D_ARM, Var.VISCOUS, Var.COULOMB, Var.TORQUE_OFFSET))
        return cls(
            rule=str(a.get(Attr.SIMPLIFIED_RULE, "")),
            tolerance=float(a.get(Attr.SIMPLIFIED_TOLERANCE, np.nan)),
            torque_floor=float(a.get(Attr.SIMPLIFIED_TORQUE_FLOOR, 0.0)),
            form=str(a.get(Attr.SIMPLIFIED_FORM, "explicit")),
            files=tuple(f.strip() for f in str(a.get(Attr.SIMPLIFIED_FILES, "")).split(",")
                        if f.strip()),
            choice=(tuple(strings(ds[Var.CHOICE].values)) if Var.CHOICE in ds.variables
                    else ()),
            terms_kept=a.get(Attr.SIMPLIFIED_TERMS_KEPT, 0),
            multiplications=a.get(Attr.SIMPLIFIED_MULTIPLICATIONS),
            additions=a.get(Attr.SIMPLIFIED_ADDITIONS),
            sin=a.get(Attr.SIMPLIFIED_SIN), cos=a.get(Attr.SIMPLIFIED_COS),
            pairs=int(a.get(Attr.SIMPLIFIED_PAIRS, 3 * b)),
            pairs_dropped=int(a.get(Attr.SIMPLIFIED_PAIRS_DROPPED, 0)),
            base_parameters=b, inertia_check=InertiaCheck.from_attrs(a),
            other_rule=str(a.get(Attr.OTHER_RULE, "")),
            other_rule_multiplications=a.get(Attr.OTHER_RULE_MULTIPLICATIONS),
            other_rule_additions=a.get(Attr.OTHER_RULE_ADDITIONS),
            other_rule_error_relative_peak=optional(ds, Var.OTHER_RULE_ERROR_RELATIVE_PEAK),
            structure=_structure(a),
            scale=optional(ds, Var.SIMPLIFIED_SCALE), bound=ds[Var.SIMPLIFIED_BOUND].values,
            bound_inertia=optional(ds, Var.SIMPLIFIED_BOUND_INERTIA),
            bound_coriolis=optional(ds, Var.SIMPLIFIED_BOUND_CORIOLIS),
            bound_gravity=optional(ds, Var.SIMPLIFIED_BOUND_GRAVITY),
            bound_whole=optional(ds, Var.SIMPLIFIED_BOUND_WHOLE),
            tau_error_peak=optional(ds, Var.TAU_ERROR_PEAK),
            tau_peak=optional(ds, Var.TAU_PEAK),
            costs=CostTable.from_dataset(ds), ladder=ladder,
            ladder_skipped=str(a.get(Attr.SIMPLIFIED_LADDER_SKIPPED, "")),
            ladder_form=str(a.get(Attr.SIMPLIFIED_LADDER_FORM, "explicit")),
            c_prefix=str(a.get(Attr.C_PREFIX, "")),
            form_note=str(a.get(Attr.SIMPLIFIED_FORM_NOTE, "")),
            region_screen=str(a.get(Attr.SIMPLIFIED_REGION_SCREEN, "")),
            region=stored_region(ds),
            region_source=str(a.get(Attr.REGION_SOURCE, "the robot limits")),
            region_notes=str(a.get(Attr.REGION_NOTES) or ""),
            guarantee=stored_guarantee(ds), prismatic=stored_prismatic(ds),
            has_drives=bool(drives),
            dataset=ds)

    @property
    def n(self) -> int:
        """int: the joints."""
        return len(self.prismatic)

    @property
    def tau_units(self) -> list[str]:
        """list of str, length n: each joint's torque units, ``"N m"`` or ``"N"``."""
        return joint_units(self.prismatic, "tau")

    @property
    def guarantee_kind(self) -> str:
        """str: the stored guarantee's kind, ``"region"``, ``"trajectory"`` or ``"none"``
        (also where none is stored)."""
        return "none" if self.guarantee is None else str(self.guarantee["kind"])

    @property
    def t(self) -> np.ndarray:
        """ndarray, shape (N,): the time of each set point [s], read from the dataset."""
        return self.dataset[Var.T].values

    def time_span(self) -> tuple[float, float]:
        """The first and last set points' times [s], two values read from the dataset.

        Returns
        -------
        tuple of float
        """
        t = self.dataset[Var.T]
        return float(t[0]), float(t[-1])

    def torque_difference(self) -> np.ndarray:
        """tau_s - tau at every set point, the whole series read from the dataset.

        Returns
        -------
        ndarray, shape (N, n)
            [N m or N].
        """
        return self.dataset[Var.TAU_SIMPLIFIED].values - self.dataset[Var.TAU].values
