"""An identification as ``identification.h5`` stores it: a typed view.

:class:`StoredIdentification` holds what the identify report reads from the root group (the
parameters with their standard deviations and identifiability, the links' consistency, the
noise per joint, the run's statements and provenance) and, per recording group, a
:class:`StoredRecording` (its file, role, series and errors), as the identify command's
``gd_analyze.store.identification_dataset`` wrote them. Read once, by
:meth:`StoredIdentification.from_dataset`, which checks what a report needs. Names, roles and
statements are kept as stored (the report cleans them of its markup characters); a number that
is missing or not a number is NaN.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError
from .schema import View, from_attrs, optional

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr

__all__ = ["REQUIRED_ROOT", "REQUIRED_RECORDING", "StoredRecording", "StoredIdentification"]

#: Variables the root group must have.
REQUIRED_ROOT = ("value", "std")
#: Variables every recording group must have.
REQUIRED_RECORDING = ("tau_measured", "tau_predicted")
#: The torque series a recording may store, measured and by model.
TORQUES = ("tau_measured", "tau_predicted", "tau_prior", "tau_simplified")
_FILE = "identification.h5"


def _number(ds: xr.Dataset, key: str) -> float:
    """An attribute, or else a variable, as a float; NaN where neither is a number."""
    try:
        return float(ds.attrs[key]) if key in ds.attrs else float(ds[key].values)
    except (KeyError, TypeError, ValueError):
        return math.nan


def _joint(ds: xr.Dataset) -> np.ndarray | None:
    return ds["joint"].values if "joint" in ds.coords else None


@dataclass(frozen=True, eq=False)
class StoredRecording:
    """One recording's group of ``identification.h5``: its file, role, torques and errors.

    Attributes
    ----------
    name, file : str, object
        The group's name, and the recording's file name as stored (None where none is;
        :attr:`file_name`).
    sha256 : object
        Its SHA-256 (None where not stored).
    role : object
        ``"train"`` or ``"validate"`` as stored, an attribute or the first value of a
        variable (None where neither).
    t : ndarray, shape (N,)
        The time [s].
    torques : Mapping of str to ndarray, shape (N, n)
        The stored series of :data:`TORQUES`, by name [N m or N].
    joint : ndarray, shape (n,), or None
        The joints' names, as stored.
    rms_error, relative_error, prior_relative_error, simplified_relative_error :
            ndarray, shape (n,), or None
        Per joint, RMS of tau_measured - tau_predicted [N m or N] and the relative errors of
        the identified model, the robot file's and the simplified model's [1].
    total_relative_error, prior_total_relative_error, simplified_total_relative_error : float
        ||E||_F / ||T||_F of each model [1] (NaN where not stored).
    has_prior_total, has_simplified_total : bool
        The robot file's, the simplified model's total is stored as an attribute.
    notes : object
        The run's notes on the recording (a JSON list), None where none.
    """

    name: str
    file: Any
    sha256: Any
    role: Any
    t: np.ndarray
    torques: Mapping[str, np.ndarray]
    joint: np.ndarray | None
    rms_error: np.ndarray | None
    relative_error: np.ndarray | None
    prior_relative_error: np.ndarray | None
    simplified_relative_error: np.ndarray | None
    total_relative_error: float
    prior_total_relative_error: float
    simplified_total_relative_error: float
    has_prior_total: bool
    has_simplified_total: bool
    notes: Any

    @property
    def file_name(self) -> Any:
        """object: the recording's file name as stored, or else the group's name."""
        return self.name if self.file is None else self.file

    @property
    def n(self) -> int:
        """int: the joints."""
        return int(self.torques["tau_measured"].shape[1])

    @classmethod
    def from_dataset(cls, name: str, ds: xr.Dataset) -> StoredRecording:
        """The view of a recording's group.

        Parameters
        ----------
        name : str
            The group's name.
        ds : xarray.Dataset
            The group.

        Returns
        -------
        StoredRecording

        Raises
        ------
        InputError
            If ``t`` or a variable of :data:`REQUIRED_RECORDING` is missing.
        """
        lacks = [v for v in REQUIRED_RECORDING + ("t",) if v not in ds.variables]
        if lacks:
            raise InputError(f"recording group {name[:80]!r} lacks {', '.join(lacks)}", _FILE)
        a = ds.attrs
        role = (a["role"] if "role" in a else
                np.asarray(ds["role"].values).reshape(-1)[0] if "role" in ds.variables
                else None)
        return cls(name=name, file=a.get("file"), sha256=a.get("sha256"), role=role,
                   t=np.asarray(ds["t"].values, float),
                   torques={v: ds[v].values for v in TORQUES if v in ds.variables},
                   joint=_joint(ds), **{k: optional(ds, k) for k in (
                       "rms_error", "relative_error", "prior_relative_error",
                       "simplified_relative_error")},
                   total_relative_error=_number(ds, "total_relative_error"),
                   prior_total_relative_error=_number(ds, "prior_total_relative_error"),
                   simplified_total_relative_error=_number(ds,
                                                           "simplified_total_relative_error"),
                   has_prior_total="prior_total_relative_error" in a,
                   has_simplified_total="simplified_total_relative_error" in a,
                   notes=a.get("notes"))


@dataclass(frozen=True, eq=False)
class StoredIdentification(View):
    """An identification: its root group and its recordings.

    Attributes
    ----------
    robot, robot_source, robot_sha256 : object
        The robot and its file (None where not stored).
    gd_analyze_version, standard_method, coulomb_model : object
        The software, how the standard parameters were found, the Coulomb friction model.
    inputs, settings, unidentifiable, preprocessing : object
        JSON texts as stored: the input files, the settings, the columns the data do not
        identify, the preprocessing steps (None where not stored).
    condition_number : float
        Of the column-scaled regressor (NaN where not stored).
    parameter : ndarray, shape (P,), or None
        The parameters' names.
    value, std : ndarray, shape (P,)
        Their values and standard deviations [their units].
    kind : ndarray, shape (P,), or None
        ``base`` or the drive kind.
    prior : ndarray, shape (P,), or None
        The robot file's values.
    identifiable : ndarray of bool, shape (P,), or None
    link : ndarray, shape (L,), or None
        The links' names.
    link_consistent : ndarray of bool, shape (L,), or None
        Each link's pseudo-inertia is positive semidefinite.
    pseudo_inertia_min_eigenvalue : ndarray, shape (L,), or None
        [kg m^2].
    noise_std : ndarray, shape (n,), or None
        The residual standard deviation per joint of the ordinary fit [N m or N].
    joint : ndarray, shape (n,), or None
        The joints' names.
    prismatic : ndarray of bool, shape (n,), or None
    recordings : Mapping of str to StoredRecording
        By group name, in order.
    """

    robot: Any
    robot_source: Any
    robot_sha256: Any
    gd_analyze_version: Any
    standard_method: Any
    coulomb_model: Any
    inputs: Any
    settings: Any
    unidentifiable: Any
    preprocessing: Any
    condition_number: float
    parameter: np.ndarray | None
    value: np.ndarray
    std: np.ndarray
    kind: np.ndarray | None
    prior: np.ndarray | None
    identifiable: np.ndarray | None
    link: np.ndarray | None
    link_consistent: np.ndarray | None
    pseudo_inertia_min_eigenvalue: np.ndarray | None
    noise_std: np.ndarray | None
    joint: np.ndarray | None
    prismatic: np.ndarray | None
    recordings: Mapping[str, StoredRecording]

    @classmethod
    def from_dataset(cls, root: xr.Dataset, groups: Mapping[str, xr.Dataset]
                     ) -> StoredIdentification:
        """The view of ``identification.h5``'s root group and recording groups.

        Parameters
        ----------
        root : xarray.Dataset
            The root group: ``value`` and ``std`` over ``parameter`` (required).
        groups : Mapping of str to xarray.Dataset
            One per recording, by group name, in order: ``t`` [s], ``tau_measured`` and
            ``tau_predicted`` (t, joint) [N m or N] (required).

        Returns
        -------
        StoredIdentification

        Raises
        ------
        InputError
            If a required variable is missing, or there is no recording (one line).
        """
        missing = [v for v in REQUIRED_ROOT if v not in root.variables]
        if missing:
            raise InputError(f"not an identification (the root lacks {', '.join(missing)})",
                             _FILE)
        if not groups:
            raise InputError("not an identification (no recording group)", _FILE)
        recordings = {name: StoredRecording.from_dataset(name, ds)
                      for name, ds in groups.items()}
        return from_attrs(
            cls, root.attrs, condition_number=_number(root, "condition_number"),
            parameter=root["parameter"].values if "parameter" in root.coords else None,
            value=np.asarray(root["value"].values, float),
            std=np.asarray(root["std"].values, float),
            link=root["link"].values if "link" in root.coords else None, joint=_joint(root),
            recordings=recordings, **{k: optional(root, k) for k in (
                "kind", "prior", "identifiable", "link_consistent",
                "pseudo_inertia_min_eigenvalue", "noise_std", "prismatic")})
