"""The comparisons ``results.h5`` stores: typed views for the readers.

:class:`FormulationComparison` is the check of Lagrange-Euler, Newton-Euler, the G-D equations
and Pinocchio against each other and their counted operations beside Table 3.5 of Fu, Gonzalez
& Lee (1987) (:func:`gd_analyze.dynamics.compare.formulations_dataset`);
:class:`ChapterComparison` the ranking against the chapter's conclusions for its PUMA 560
(Sec. 3.4.1). Read once by :class:`gd_analyze.store.results_view.Results`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .names import Attr, Var
from .schema import strings

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr

__all__ = ["FormulationComparison", "ChapterComparison"]


@dataclass(frozen=True, eq=False)
class FormulationComparison:
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

    quantities: tuple[str, ...]
    pairs: tuple[str, ...]
    disagreement: np.ndarray
    names: tuple[str, ...]
    dof: np.ndarray
    multiplications: np.ndarray
    additions: np.ndarray
    multiplications_table_3_5: np.ndarray
    additions_table_3_5: np.ndarray
    arm: tuple[np.ndarray, np.ndarray] | None
    n: int
    setpoints: Any
    joint_types: str

    @classmethod
    def from_dataset(cls, ds: xr.Dataset) -> FormulationComparison | None:
        """The comparison stored in a results dataset.

        Parameters
        ----------
        ds : xarray.Dataset

        Returns
        -------
        FormulationComparison or None
            None where the formulations were not compared.
        """
        if Var.FORMULATION_DISAGREEMENT not in ds.variables:
            return None
        a = ds.attrs
        arm = ((ds[Var.OP_MULTIPLICATIONS_ARM].values, ds[Var.OP_ADDITIONS_ARM].values)
               if Var.OP_MULTIPLICATIONS_ARM in ds.variables else None)
        return cls(quantities=tuple(strings(ds[Var.QUANTITY].values)),
                   pairs=tuple(strings(ds[Var.FORMULATION_PAIR].values)),
                   disagreement=ds[Var.FORMULATION_DISAGREEMENT].values,
                   names=tuple(strings(ds[Var.FORMULATION].values)), dof=ds[Var.DOF].values,
                   multiplications=ds[Var.OP_MULTIPLICATIONS].values,
                   additions=ds[Var.OP_ADDITIONS].values,
                   multiplications_table_3_5=ds[Var.OP_MULTIPLICATIONS_TABLE_3_5].values,
                   additions_table_3_5=ds[Var.OP_ADDITIONS_TABLE_3_5].values, arm=arm,
                   n=int(a.get(Attr.FORMULATIONS_N, ds.sizes[Var.JOINT])),
                   setpoints=a.get(Attr.FORMULATIONS_SETPOINTS),
                   joint_types=str(a.get(Attr.FORMULATIONS_JOINT_TYPES, "")))


@dataclass(frozen=True, eq=False)
class ChapterComparison:
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

    blocks: dict[str, list[str]]
    threshold: np.ndarray
    agreement: np.ndarray
    elements_compared: int
    model_error_relative_peak: np.ndarray
    model_error_round_off: np.ndarray

    @classmethod
    def from_dataset(cls, ds: xr.Dataset) -> ChapterComparison | None:
        """The comparison with the chapter stored in a results dataset.

        Parameters
        ----------
        ds : xarray.Dataset
            A results dataset; the chapter's PUMA 560's holds ``chapter_*`` variables and
            attributes.

        Returns
        -------
        ChapterComparison or None
            None where the robot is not the chapter's PUMA 560 (nothing stored).
        """
        if Var.CHAPTER_AGREEMENT not in ds.variables:
            return None
        a = ds.attrs
        blocks = {key: [k for k in str(a.get(name, "")).split(", ") if k]
                  for key, name in (("arm", Attr.CHAPTER_ARM_RANKED),
                                    ("arm_translation", Attr.CHAPTER_ARM_TRANSLATION_LEADS),
                                    ("wrist", Attr.CHAPTER_WRIST_RANKED),
                                    ("wrist_rotation", Attr.CHAPTER_WRIST_ROTATION_LEADS))}
        return cls(blocks=blocks, threshold=ds[Var.CHAPTER_THRESHOLD].values,
                   agreement=ds[Var.CHAPTER_AGREEMENT].values,
                   elements_compared=int(a[Attr.CHAPTER_ELEMENTS_COMPARED]),
                   model_error_relative_peak=ds[Var.CHAPTER_MODEL_ERROR_RELATIVE_PEAK].values,
                   model_error_round_off=ds[Var.CHAPTER_MODEL_ERROR_ROUND_OFF].values.astype(
                       bool))
