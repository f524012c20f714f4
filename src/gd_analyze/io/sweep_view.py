"""A typed view of a sweep's dataset, for the command line's summary of the run.

:class:`SweepRun` reads, once, what ``gd-analyze sweep`` prints after a run: where and how the
trajectories were spread over the dask workers, and per element the fraction of the
trajectories in each dominance class, the spread of its translational share and the part the
merged model keeps (:func:`gd_analyze.io.sweep_datasets.sweep_dataset`,
:func:`gd_analyze.workflows.sweep.run_sweep`). :func:`with_more_tasks` counts tasks the run
added after the sweep itself (the workers' error measurement).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError
from .schema import strings

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr

__all__ = ["SweepRun", "with_more_tasks"]

#: The per-element variables of the summary, and the run's attributes.
_VARIABLES = ("class_fraction", "share_tran_min", "share_tran_median", "share_tran_max",
              "merged_choice")
_ATTRIBUTES = ("elapsed_s", "n_workers", "scheduler_address", "batch_size", "n_tasks")


@dataclass(frozen=True, eq=False)
class SweepRun:
    """A sweep as the command line summarises it.

    Attributes
    ----------
    trajectories : int
        K, the trajectories swept.
    elapsed_s : float
        The run's wall time [s].
    n_workers : int
        The dask workers.
    scheduler_address : str
        The dask scheduler's address.
    batch_size : int
        The trajectories per task.
    n_tasks : int
        The tasks submitted.
    classes : tuple of str, length C
        The dominance classes.
    elements : tuple of str, length M
        ``"D11"`` .. ``"hn"``.
    class_fraction : ndarray, shape (M, C)
        The fraction of the trajectories in which each class holds [1].
    share_min, share_median, share_max : ndarray, shape (M,)
        The translational share's spread over the trajectories [1].
    merged_choice : tuple of str, length M
        The part the merged model keeps.
    """

    trajectories: int
    elapsed_s: float
    n_workers: int
    scheduler_address: str
    batch_size: int
    n_tasks: int
    classes: tuple[str, ...]
    elements: tuple[str, ...]
    class_fraction: np.ndarray
    share_min: np.ndarray
    share_median: np.ndarray
    share_max: np.ndarray
    merged_choice: tuple[str, ...]

    @classmethod
    def from_dataset(cls, ds: xr.Dataset, source: str = "<memory>") -> SweepRun:
        """The view of a sweep's dataset.

        Parameters
        ----------
        ds : xarray.Dataset
            As :func:`gd_analyze.workflows.sweep.run_sweep` returns it.
        source : str, optional
            The file it was read from, for the message.

        Returns
        -------
        SweepRun

        Raises
        ------
        InputError
            If a variable or attribute of the summary is missing (one line naming it).
        """
        for name in _VARIABLES:
            if name not in ds.variables:
                raise InputError(f"missing variable {name!r}: not a gd-analyze sweep", source)
        for name in _ATTRIBUTES:
            if name not in ds.attrs:
                raise InputError(f"missing attribute {name!r}: not a gd-analyze sweep",
                                 source)
        a = ds.attrs
        return cls(trajectories=int(ds.sizes["trajectory"]), elapsed_s=float(a["elapsed_s"]),
                   n_workers=int(a["n_workers"]), scheduler_address=str(a["scheduler_address"]),
                   batch_size=int(a["batch_size"]), n_tasks=int(a["n_tasks"]),
                   classes=tuple(strings(ds["class"].values)),
                   elements=tuple(strings(ds["element"].values)),
                   class_fraction=ds["class_fraction"].values,
                   share_min=ds["share_tran_min"].values,
                   share_median=ds["share_tran_median"].values,
                   share_max=ds["share_tran_max"].values,
                   merged_choice=tuple(strings(ds["merged_choice"].values)))


def with_more_tasks(ds: xr.Dataset, tasks: int) -> xr.Dataset:
    """The sweep's dataset with ``tasks`` more tasks counted in its ``n_tasks``.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep's dataset (attribute ``n_tasks``).
    tasks : int
        The tasks submitted after the sweep.

    Returns
    -------
    xarray.Dataset
        A new dataset (the data shared); ``ds`` is not changed.
    """
    return ds.assign_attrs(n_tasks=int(ds.attrs["n_tasks"]) + int(tasks))
