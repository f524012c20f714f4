"""The simplified model's results as ``results.h5`` stores them: a typed view.

:class:`StoredSimplified` holds what the report's "Simplified model" section and the figures of
the error budget read: the rule and its settings, what the model keeps and costs, the bound on
|tau_s - tau| per joint and its parts, the measured error, the cost table and the tolerance
ladder, the check of D_s (:class:`InertiaCheck`), the region and the guarantee, as
:func:`gd_analyze.jobs.simplified_dataset.simplified_dataset` stored them. Read once, by
:class:`gd_analyze.store.results_view.Results` or :meth:`StoredSimplified.of`; the series (t, tau,
tau_s) stay in the dataset and are read on demand. :class:`CostTable` is the operations of the
model beside the models it is compared with, :class:`BaseParameters` a recursive model's base
parameters. The names are those of :mod:`gd_analyze.store.names`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .datasets import joint_units, stored_guarantee, stored_region
from .names import Attr, Var
from .schema import View, derived, stored, stored_has_drives, stored_prismatic, texts

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr

__all__ = ["InertiaCheck", "Ladder", "StoredSimplified"]

#: The stored counts that say why a pruned explicit model can cost more than the full one.
_STRUCTURE = (Attr.FULL_HARMONICS, Attr.FULL_COEFFICIENTS, Attr.OTHER_RULE_HARMONICS,
              Attr.OTHER_RULE_COEFFICIENTS)


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
class Ladder(View):
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

    presence = (Var.LADDER_OPERATIONS,)

    tolerance: np.ndarray = stored(Var.LADDER_TOLERANCE)
    operations: np.ndarray = stored(Var.LADDER_OPERATIONS)
    trig: np.ndarray = stored(Var.LADDER_TRIG)
    worst_error: np.ndarray = stored(Var.LADDER_WORST_ERROR)
    worst_bound: np.ndarray | None = stored(Var.LADDER_WORST_BOUND, default=None)


@dataclass(frozen=True, eq=False)
class CostTable(View):
    """The operations per set point of each model compared.

    Attributes
    ----------
    models : tuple of str, length K
        Each model's label (``"explicit, budget EPS=0.01 (this model)"``, ``"project N-E as
        implemented"`` ...).
    multiplications, additions, total : ndarray of int, shape (K,)
        Its multiplications, additions and their sum per set point.
    """

    presence = (Var.COST_MODEL, Var.COST_TOTAL)

    models: tuple[str, ...] = stored(Var.COST_MODEL, texts)
    multiplications: np.ndarray = stored(Var.COST_MULTIPLICATIONS)
    additions: np.ndarray = stored(Var.COST_ADDITIONS)
    total: np.ndarray = stored(Var.COST_TOTAL)

    def totals(self) -> dict[str, int]:
        """Each model's total operations per set point, by its label.

        Returns
        -------
        dict of str to int
        """
        return dict(zip(self.models, self.total))


@dataclass(frozen=True, eq=False)
class BaseParameters(View):
    """The base parameters of a recursive model (Khalil & Kleinfinger 1987; Gautier 1990).

    Attributes
    ----------
    names : tuple of str, length K
        ``"XX1"``, ``"MX2"`` ...
    parts : tuple of str, length P
        The parts of tau (``"inertia"``, ``"coriolis"``, ``"gravity"``).
    dropped : ndarray of bool, shape (K, P)
        The parameter is dropped from that part.
    units : tuple of str, length K
        Each parameter's units as stored (``"kg m2"``, ``"kg m"``, ``"kg"``).
    relative_peak : ndarray, shape (K, P), or None
        Its peak contribution to that part relative to the joint's scale [1]; None in a file
        written before it was stored.
    value : ndarray, shape (K,), or None
        Its value [units]; None where not stored.
    """

    presence = (Var.BASE_PARAMETER_DROPPED,)

    names: tuple[str, ...] = stored(Var.BASE_PARAMETER, texts)
    parts: tuple[str, ...] = stored(Var.TORQUE_PART, texts)
    dropped: np.ndarray = stored(Var.BASE_PARAMETER_DROPPED)
    units: tuple[str, ...] = stored(Var.BASE_PARAMETER_UNITS, texts)
    relative_peak: np.ndarray | None = stored(Var.BASE_PARAMETER_RELATIVE_PEAK, default=None)
    value: np.ndarray | None = stored(Var.BASE_PARAMETER_VALUE, default=None)


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
        The emitted C symbols' prefix, why this form, why a screen chose the exact recursive
        model ("" where not stored).
    region_screen_proved : bool
        That screen is the one of the pairs searched under the proved bounds (the region
        certified, the pruned model not built), not the sampled pre-screen that skipped the
        certification (False where not stored).
    region : dict or None
        :func:`gd_analyze.store.datasets.stored_region`.
    region_source, region_notes : str
        Where the region's limits come from, and what was clipped to the robot's.
    guarantee : dict or None
        :func:`gd_analyze.store.datasets.stored_guarantee`.
    guarantee_kind : str
        Its kind, ``"region"``, ``"trajectory"`` or ``"none"`` (also where none is stored).
    prismatic : tuple of bool, length n
        The prismatic joints.
    n : int
        The joints.
    tau_units : list of str, length n
        Each joint's torque units, ``"N m"`` or ``"N"``.
    has_drives : bool
        The robot has armature, friction or a torque offset.
    dataset : xarray.Dataset
        The dataset the series are read from.
    """

    presence = (Var.SIMPLIFIED_BOUND,)

    rule: str = stored(Attr.SIMPLIFIED_RULE, str, "", attr=True)
    form: str = stored(Attr.SIMPLIFIED_FORM, str, "explicit", attr=True)
    files: tuple[str, ...] = stored(Attr.SIMPLIFIED_FILES, lambda v: tuple(
        f.strip() for f in str(v).split(",") if f.strip()), (), attr=True)
    choice: tuple[str, ...] = stored(Var.CHOICE, texts, ())
    tolerance: float = stored(Attr.SIMPLIFIED_TOLERANCE, float, np.nan, attr=True)
    torque_floor: float = stored(Attr.SIMPLIFIED_TORQUE_FLOOR, float, 0.0, attr=True)
    terms_kept: Any = stored(Attr.SIMPLIFIED_TERMS_KEPT, default=0, attr=True)
    multiplications: Any = stored(Attr.SIMPLIFIED_MULTIPLICATIONS, default=None, attr=True)
    additions: Any = stored(Attr.SIMPLIFIED_ADDITIONS, default=None, attr=True)
    sin: Any = stored(Attr.SIMPLIFIED_SIN, default=None, attr=True)
    cos: Any = stored(Attr.SIMPLIFIED_COS, default=None, attr=True)
    pairs: int = derived(lambda ds: int(ds.attrs.get(
        Attr.SIMPLIFIED_PAIRS, 3 * int(ds.sizes.get(Var.BASE_PARAMETER, 0)))))
    pairs_dropped: int = stored(Attr.SIMPLIFIED_PAIRS_DROPPED, int, 0, attr=True)
    base_parameters: int = derived(lambda ds: int(ds.sizes.get(Var.BASE_PARAMETER, 0)))
    inertia_check: InertiaCheck | None = derived(lambda ds: InertiaCheck.from_attrs(ds.attrs))
    other_rule: str = stored(Attr.OTHER_RULE, str, "", attr=True)
    other_rule_multiplications: Any = stored(Attr.OTHER_RULE_MULTIPLICATIONS, default=None, attr=True)
    other_rule_additions: Any = stored(Attr.OTHER_RULE_ADDITIONS, default=None, attr=True)
    other_rule_error_relative_peak: np.ndarray | None = stored(
        Var.OTHER_RULE_ERROR_RELATIVE_PEAK, default=None)
    structure: tuple[int, int, int, int] | None = derived(lambda ds: (
        tuple(int(ds.attrs[k]) for k in _STRUCTURE) if all(k in ds.attrs for k in _STRUCTURE)
        else None))
    scale: np.ndarray | None = stored(Var.SIMPLIFIED_SCALE, default=None)
    bound: np.ndarray = stored(Var.SIMPLIFIED_BOUND)
    bound_inertia: np.ndarray | None = stored(Var.SIMPLIFIED_BOUND_INERTIA, default=None)
    bound_coriolis: np.ndarray | None = stored(Var.SIMPLIFIED_BOUND_CORIOLIS, default=None)
    bound_gravity: np.ndarray | None = stored(Var.SIMPLIFIED_BOUND_GRAVITY, default=None)
    bound_whole: np.ndarray | None = stored(Var.SIMPLIFIED_BOUND_WHOLE, default=None)
    tau_error_peak: np.ndarray | None = stored(Var.TAU_ERROR_PEAK, default=None)
    tau_peak: np.ndarray | None = stored(Var.TAU_PEAK, default=None)
    costs: CostTable | None = derived(CostTable.from_dataset)
    ladder: Ladder | None = derived(Ladder.from_dataset)
    ladder_skipped: str = stored(Attr.SIMPLIFIED_LADDER_SKIPPED, str, "", attr=True)
    ladder_form: str = stored(Attr.SIMPLIFIED_LADDER_FORM, str, "explicit", attr=True)
    c_prefix: str = stored(Attr.C_PREFIX, str, "", attr=True)
    form_note: str = stored(Attr.SIMPLIFIED_FORM_NOTE, str, "", attr=True)
    region_screen: str = stored(Attr.SIMPLIFIED_REGION_SCREEN, str, "", attr=True)
    region_screen_proved: bool = stored(Attr.SIMPLIFIED_REGION_SCREEN_PROVED,
                                        lambda v: bool(int(v)), False, attr=True)
    region: dict | None = derived(stored_region)
    region_source: str = stored(Attr.REGION_SOURCE, str, "the robot limits", attr=True)
    region_notes: str = stored(Attr.REGION_NOTES, lambda v: str(v or ""), "", attr=True)
    guarantee: dict | None = derived(stored_guarantee)
    guarantee_kind: str = derived(lambda ds: (stored_guarantee(ds) or {}).get("kind", "none"))
    prismatic: tuple[bool, ...] = derived(stored_prismatic)
    n: int = derived(lambda ds: len(stored_prismatic(ds)))
    tau_units: list[str] = derived(lambda ds: joint_units(stored_prismatic(ds), "tau"))
    has_drives: bool = derived(stored_has_drives)
    dataset: xr.Dataset = derived(lambda ds: ds)

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
