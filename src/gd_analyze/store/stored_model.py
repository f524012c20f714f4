"""The simplified model's record as ``results.h5`` stores it: typed views.

:class:`CostTable` is the table of operations per set point of the model built and of the
models it is compared with (Newton-Euler as implemented, the exact recursive model, the full
explicit model ...), as :mod:`gd_analyze.jobs.simplified_dataset` stored it over the
``cost_model`` coordinate; :class:`BaseParameters` the base parameters of a recursive model
and the parts of tau each is kept or dropped in. Read once by
:class:`gd_analyze.store.results_view.Results`. :class:`EvaluatorCosts` is the operations of each
evaluator of tau that a control or sweep dataset counted.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .names import Var
from .schema import optional, strings

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr

__all__ = ["CostTable", "BaseParameters", "EvaluatorCosts"]


@dataclass(frozen=True, eq=False)
class CostTable:
    """The operations per set point of each model compared.

    Attributes
    ----------
    models : tuple of str, length K
        Each model's label (``"explicit, budget EPS=0.01 (this model)"``, ``"project N-E as
        implemented"`` ...).
    multiplications, additions, total : ndarray of int, shape (K,)
        Its multiplications, additions and their sum per set point.
    """

    models: tuple[str, ...]
    multiplications: np.ndarray
    additions: np.ndarray
    total: np.ndarray

    @classmethod
    def from_dataset(cls, ds: xr.Dataset) -> CostTable | None:
        """The stored table of a results dataset.

        Parameters
        ----------
        ds : xarray.Dataset

        Returns
        -------
        CostTable or None
            None where no simplified model's costs are stored.
        """
        if Var.COST_MODEL not in ds.coords or Var.COST_TOTAL not in ds.variables:
            return None
        return cls(models=tuple(strings(ds[Var.COST_MODEL].values)),
                   multiplications=ds[Var.COST_MULTIPLICATIONS].values,
                   additions=ds[Var.COST_ADDITIONS].values, total=ds[Var.COST_TOTAL].values)

    def totals(self) -> dict[str, int]:
        """Each model's total operations per set point, by its label.

        Returns
        -------
        dict of str to int
        """
        return dict(zip(self.models, self.total))


@dataclass(frozen=True, eq=False)
class BaseParameters:
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

    names: tuple[str, ...]
    parts: tuple[str, ...]
    dropped: np.ndarray
    units: tuple[str, ...]
    relative_peak: np.ndarray | None
    value: np.ndarray | None

    @classmethod
    def from_dataset(cls, ds: xr.Dataset) -> BaseParameters | None:
        """The base parameters of a results dataset: names, parts, what is dropped, values.

        Parameters
        ----------
        ds : xarray.Dataset
            A results dataset; a recursive model's holds ``base_parameter*`` and
            ``torque_part``.

        Returns
        -------
        BaseParameters or None
            None for an explicit model (no base parameters stored).
        """
        if Var.BASE_PARAMETER_DROPPED not in ds.variables:
            return None

        return cls(names=tuple(strings(ds[Var.BASE_PARAMETER].values)),
                   parts=tuple(strings(ds[Var.TORQUE_PART].values)),
                   dropped=ds[Var.BASE_PARAMETER_DROPPED].values,
                   units=tuple(strings(ds[Var.BASE_PARAMETER_UNITS].values)),
                   relative_peak=optional(ds, Var.BASE_PARAMETER_RELATIVE_PEAK),
                   value=optional(ds, Var.BASE_PARAMETER_VALUE))


@dataclass(frozen=True, eq=False)
class EvaluatorCosts:
    """The operations per set point of each evaluator of tau a control or sweep dataset
    counted, Newton-Euler last.

    Attributes
    ----------
    evaluators : tuple of str, length E
        Each evaluator's name.
    multiplications, additions : ndarray of int, shape (E,)
        Its multiplications and additions per set point.
    """

    evaluators: tuple[str, ...]
    multiplications: np.ndarray
    additions: np.ndarray

    @classmethod
    def from_dataset(cls, ds: xr.Dataset) -> EvaluatorCosts | None:
        """The counts of a dataset (``multiplications`` and ``additions`` over dim
        ``evaluator``).

        Parameters
        ----------
        ds : xarray.Dataset
            The control dataset (:func:`gd_analyze.jobs.control.model_cost`) or the
            sweep's (:func:`gd_analyze.jobs.sweep_merged.with_model_cost`).

        Returns
        -------
        EvaluatorCosts or None
            None where no counts are stored.
        """
        if "evaluator" not in ds.dims:
            return None
        return cls(evaluators=tuple(strings(ds["evaluator"].values)),
                   multiplications=ds["multiplications"].values,
                   additions=ds["additions"].values)
