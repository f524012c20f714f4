"""The identification's typed result and its store, ``identification.h5``.

:class:`StoredIdentification` holds what the identify report reads from the root group (the
parameters with their standard deviations and identifiability, the links' consistency, the
noise per joint, the run's statements and provenance) and, per recording group, a
:class:`StoredRecording` (its file, role, series and errors). Read once, by
:meth:`StoredIdentification.from_dataset`, which checks what a report needs. Names, roles and
statements are kept as stored (the report cleans them of its markup characters); a number that
is missing or not a number is NaN.

``gd-analyze identify`` (:func:`gd_analyze.jobs.identify.identify`) returns an
:class:`IdentificationResult`; :func:`identification_tree` turns it into xarray datasets and
:func:`write_identification` writes them with h5netcdf; :func:`read_identification` reads them
back. The layout, stable for the report and for other readers:

Root group ``/``
    Attributes: ``gd_analyze_version``; ``robot`` (the prior robot's name), ``robot_source``,
    ``robot_sha256``; ``settings`` (JSON: every option of the run); ``inputs`` (JSON: file ->
    SHA-256 of its bytes); ``preprocessing`` (JSON list of sentences: what was done to the
    recordings); ``condition_number`` (of the column-scaled, weighted regressor); ``rank``
    (identifiable columns); ``unidentifiable`` (JSON list of parameter names not identifiable on
    the data: kept at the prior's value, never silently dropped); ``noise_std`` as a variable;
    ``standard_method`` (how the standard parameters were chosen); ``coulomb_model``
    (``"sign(qd)"``).

    Coordinates: ``parameter`` (names of the identified parameters: the base parameters
    ``ZZ1``, ``XX2``, ... (Gautier 1990) then the drive columns ``armature_j``, ``viscous_j``,
    ``coulomb_j``, ``offset_j`` with j the joint from 1); ``joint`` (the joint names); ``link``
    (1..n); ``standard_parameter`` (XX, XY, XZ, YY, YZ, ZZ, MX, MY, MZ, M).

    Variables:

    - ``value``, ``std`` (parameter): the weighted least-squares estimate and its standard
      deviation [SI units of each parameter: kg m^2, kg m, kg, N m s/rad, N m]; ``prior``
      (parameter): the robot file's value (0 for a drive column the file does not give);
      ``identifiable`` (parameter, bool); ``kind`` (parameter, str): ``base``, ``armature``,
      ``viscous``, ``coulomb`` or ``offset``; ``ols_value`` (parameter): ordinary least squares.
    - ``noise_std`` (joint): the per-joint residual standard deviation of the ordinary fit,
      the weights of the weighted fit [N m or N].
    - ``standard``, ``standard_prior`` (link, standard_parameter): the standard parameters
      written to ``identified_robot.toml`` and the prior's, body frame, about the joint's origin.
    - ``pseudo_inertia_min_eigenvalue`` (link) [kg m^2] and ``link_consistent`` (link, bool):
      whether each link's pseudo-inertia (Wensing, Kim & Slotine 2017) is positive
      semidefinite.

Group ``/<name>`` per recording, ``<name>`` the file's stem made safe (letters, digits, ``_``,
``-``, ``.``; others ``_``) and unique (``_2``, ``_3``, ... on repeats and on the names of the
root group's variables and dimensions, e.g. ``offset``):
    Coordinates ``t`` [s] (the file's own time base, not shifted, after the stated resampling
    and trimming) and ``joint``.
    Variables (t, joint): ``q`` [rad or m], ``qd``, ``qdd``, ``tau_measured`` (after the stated
    filter) and ``tau_predicted`` (identified model), ``tau_prior`` (the robot file as shipped),
    ``used`` (bool: the row entered the fit; only for training recordings, else all False);
    optionally ``tau_simplified`` (the simplified model of the identified robot).
    Variables (joint): ``rms_error`` [N m], ``relative_error`` ||tau_meas,i - tau_pred,i|| /
    ||tau_meas,i||, ``prior_rms_error``, ``prior_relative_error`` and, with a simplified model,
    ``simplified_relative_error``.
    Attributes: ``role`` (``train`` or ``validate``), ``file``, ``sha256``,
    ``total_relative_error`` ||E||_F / ||T||_F, ``prior_total_relative_error`` and, with a
    simplified model, ``simplified_total_relative_error``; ``notes`` (JSON list of what was done
    to this file: rows dropped, resampled, filtered).
"""

from __future__ import annotations

import json
import math
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._version import VERSION
from ..dynamics.base_parameters import PARAMETER_NAMES
from ..errors import InputError
from .names import Attr
from .schema import View, derived, stored

if TYPE_CHECKING:
    import xarray as xr

    from ..model.robot import Robot

__all__ = ["ParameterTable", "RecordingFit", "IdentificationResult", "group_names",
           "identification_tree", "identification_size", "write_identification", "read_identification",
           "recordings_json", "REQUIRED_ROOT", "REQUIRED_RECORDING", "StoredRecording",
           "StoredIdentification"]


@dataclass(frozen=True, eq=False)
class ParameterTable:
    """The identified parameters.

    Attributes
    ----------
    names : tuple of str, length p
        Base parameter names then drive column names (``viscous_1``, ...).
    kinds : tuple of str, length p
        ``base``, ``armature``, ``viscous``, ``coulomb`` or ``offset``.
    value : ndarray, shape (p,)
        The weighted least-squares estimate [SI].
    std : ndarray, shape (p,)
        Its standard deviations [SI] (0 where not identifiable).
    ols_value : ndarray, shape (p,)
        The ordinary least-squares estimate [SI].
    prior : ndarray, shape (p,)
        The robot file's values [SI].
    identifiable : ndarray of bool, shape (p,)
        False for the columns the data do not identify (kept at the prior).
    """

    names: tuple
    kinds: tuple
    value: np.ndarray
    std: np.ndarray
    ols_value: np.ndarray
    prior: np.ndarray
    identifiable: np.ndarray

    @property
    def unidentifiable(self) -> list[str]:
        """list of str: the names of the parameters the data do not identify, in order."""
        return [nm for nm, ok in zip(self.names, self.identifiable) if not ok]


@dataclass(frozen=True, eq=False)
class RecordingFit:
    """One recording after preprocessing, with the measured and predicted torques.

    Attributes
    ----------
    name : str
        The group name (the file's stem, made safe and unique).
    file : str
        The file as given.
    sha256 : str
        SHA-256 of its bytes.
    role : {"train", "validate"}
    t : ndarray, shape (N,)
        Time [s], the file's own time base.
    q, qd, qdd : ndarray, shape (N, n)
        [rad, rad/s, rad/s^2; m, m/s, m/s^2].
    tau_measured : ndarray, shape (N, n)
        After the stated filter [N m or N].
    tau_predicted, tau_prior : ndarray, shape (N, n)
        The identified model's and the robot file's torques [N m or N].
    used : ndarray of bool, shape (N, n)
        The rows that entered the fit.
    notes : tuple of str
        What was done to the file.
    tau_simplified : ndarray, shape (N, n), optional
        The simplified model of the identified robot.
    """

    name: str
    file: str
    sha256: str
    role: str
    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    tau_measured: np.ndarray
    tau_predicted: np.ndarray
    tau_prior: np.ndarray
    used: np.ndarray
    notes: tuple = ()
    tau_simplified: np.ndarray | None = None

    def errors(self, which: str = "predicted") -> tuple[np.ndarray, np.ndarray, float]:
        """Per-joint RMS and relative errors and the total relative error.

        Parameters
        ----------
        which : {"predicted", "prior", "simplified"}
            The model compared with the measured torque.

        Returns
        -------
        rms : ndarray, shape (n,)
            sqrt(mean_k e_ki^2) [N m or N].
        relative : ndarray, shape (n,)
            ||tau_meas,i - tau_i|| / ||tau_meas,i|| (inf where the measured torque is 0).
        total : float
            ||E||_F / ||T||_F.
        """
        E = self.tau_measured - getattr(self, f"tau_{which}")
        norm = np.linalg.norm(self.tau_measured, axis=0)     # ||T||_F is the norm of these
        rel = np.divide(np.linalg.norm(E, axis=0), norm, out=np.full(norm.shape, np.inf),
                        where=norm > 0)
        total = float(np.linalg.norm(E) / np.linalg.norm(norm)) if norm.any() else float("inf")
        return np.sqrt(np.mean(E ** 2, axis=0)), rel, total


@dataclass(frozen=True, eq=False)
class IdentificationResult:
    """What ``identify`` found: parameters, the identified robot and every recording's fit.

    Attributes
    ----------
    prior : Robot
        The robot file as given.
    identified : Robot
        The identified robot (standard parameters and drives); its ``armature``, ``viscous``
        and ``coulomb`` are the identified ones (clipped at 0 where the fit gave less, which
        ``notes`` states).
    offsets : ndarray, shape (n,)
        The identified constant torque offsets [N m or N], the identified robot's
        ``torque_offset`` (written to the robot file as each link's ``torque_offset``).
    parameters : ParameterTable
    condition_number : float
        Of the column-scaled, weighted regressor.
    rank : int
    standard : ndarray, shape (n, 10)
        The standard parameters written (body frame, about the joint's origin).
    standard_prior : ndarray, shape (n, 10)
    min_eigenvalue : ndarray, shape (n,)
        Smallest eigenvalue of each link's pseudo-inertia [kg m^2].
    consistent : ndarray of bool, shape (n,)
    standard_method : str
        How the standard parameters were chosen, one sentence.
    recordings : tuple of RecordingFit
    settings : dict
        Every option of the run.
    inputs : dict
        File -> SHA-256.
    preprocessing : tuple of str
        What was done to the recordings, sentence by sentence.
    version : str
        gd-analyze's version.
    noise_std : ndarray, shape (n,)
        Per joint the residual standard deviation of the ordinary fit, the weighted fit's
        weights [N m or N].
    """

    prior: Robot
    identified: Robot
    offsets: np.ndarray
    parameters: ParameterTable
    condition_number: float
    rank: int
    standard: np.ndarray
    standard_prior: np.ndarray
    min_eigenvalue: np.ndarray
    consistent: np.ndarray
    standard_method: str
    recordings: tuple
    settings: dict = field(default_factory=dict)
    inputs: dict = field(default_factory=dict)
    preprocessing: tuple = ()
    version: str = ""
    noise_std: np.ndarray | None = None

    @property
    def dataset(self) -> dict[str, xr.Dataset]:
        """dict of str -> xarray.Dataset: the store's groups (:func:`identification_tree`)."""
        return identification_tree(self)


_UNSAFE = re.compile(r"[^A-Za-z0-9_.-]")
#: The root group's variables and dimensions, which no recording's group may be named.
_ROOT_NAMES = {"value", "std", "ols_value", "prior", "identifiable", "kind", "noise_std",
               "prismatic", "offset", "standard", "standard_prior", "link_consistent",
               "pseudo_inertia_min_eigenvalue", "parameter", "joint", "link", "standard_parameter"}


def group_names(stems: Sequence[str]) -> list[str]:
    """Safe, unique netCDF group names from file stems.

    Parameters
    ----------
    stems : sequence of str

    Returns
    -------
    list of str
        Each stem with every character but letters, digits, ``_``, ``-`` and ``.`` written as
        ``_`` (an empty or dot-led name prefixed ``r``), repeats and the names of the root
        group's variables and dimensions (``offset``, ``std``, ...) suffixed ``_2``, ``_3``, ...

    Examples
    --------
    >>> group_names(["run 1", "run 1", "../x"])
    ['run_1', 'run_1_2', 'r.._x']
    """
    out, seen = [], set(_ROOT_NAMES)
    for stem in stems:
        name = _UNSAFE.sub("_", str(stem))[:100]
        if not name or name[0] in ".-":
            name = "r" + name
        base, k = name, 2
        while name in seen:
            name = f"{base}_{k}"
            k += 1
        seen.add(name)
        out.append(name)
    return out


def _recording_dataset(fit, joints):
    import xarray as xr

    tj = ("t", "joint")
    data = {k: (tj, np.asarray(getattr(fit, k), float)) for k in
            ("q", "qd", "qdd", "tau_measured", "tau_predicted", "tau_prior")}
    data["used"] = (tj, np.asarray(fit.used, bool))
    rms, rel, total = fit.errors("predicted")
    prms, prel, ptotal = fit.errors("prior")
    data.update(rms_error=(("joint",), rms), relative_error=(("joint",), rel),
                prior_rms_error=(("joint",), prms), prior_relative_error=(("joint",), prel))
    attrs = {"role": fit.role, "file": fit.file, "sha256": fit.sha256,
             "total_relative_error": total, "prior_total_relative_error": ptotal,
             "notes": json.dumps(list(fit.notes))}
    if fit.tau_simplified is not None:
        data["tau_simplified"] = (tj, np.asarray(fit.tau_simplified, float))
        _, srel, stotal = fit.errors("simplified")
        data["simplified_relative_error"] = (("joint",), srel)
        attrs["simplified_total_relative_error"] = stotal
    ds = xr.Dataset(data, coords={"t": ("t", np.asarray(fit.t, float)), "joint": joints},
                    attrs=attrs)
    ds["t"].attrs["units"] = "s"
    return ds


def identification_tree(result: IdentificationResult) -> dict[str, xr.Dataset]:
    """The store's datasets: ``"/"`` for the root and one per recording.

    Parameters
    ----------
    result : IdentificationResult

    Returns
    -------
    dict of str -> xarray.Dataset
        Keys ``"/"`` and the recordings' group names, in order (layout in the module
        docstring).
    """
    import xarray as xr

    p = result.parameters
    joints = list(result.prior.joint_names())
    links = np.arange(1, result.prior.n + 1)

    par = ("parameter",)
    root = xr.Dataset(
        {"value": (par, p.value), "std": (par, p.std), "ols_value": (par, p.ols_value),
         "prior": (par, p.prior), "identifiable": (par, np.asarray(p.identifiable, bool)),
         "kind": (par, np.array(p.kinds, dtype=object).astype(str)),
         "noise_std": (("joint",), np.asarray(result.noise_std, float)),
         "prismatic": (("joint",), np.asarray(result.prior.prismatic, bool)),
         "offset": (("joint",), np.asarray(result.offsets, float)),
         "standard": (("link", "standard_parameter"), result.standard),
         "standard_prior": (("link", "standard_parameter"), result.standard_prior),
         "pseudo_inertia_min_eigenvalue": (("link",), result.min_eigenvalue),
         "link_consistent": (("link",), np.asarray(result.consistent, bool))},
        coords={"parameter": list(p.names), "joint": joints, "link": links,
                "standard_parameter": list(PARAMETER_NAMES)},
        attrs={Attr.GD_ANALYZE_VERSION: result.version or VERSION,
               Attr.ROBOT: result.prior.name, Attr.ROBOT_SOURCE: str(result.prior.source),
               Attr.ROBOT_SHA256: result.prior.sha256,
               "settings": json.dumps(result.settings, sort_keys=True, default=str),
               "inputs": json.dumps(result.inputs, sort_keys=True),
               "preprocessing": json.dumps(list(result.preprocessing)),
               "condition_number": float(result.condition_number), "rank": int(result.rank),
               "unidentifiable": json.dumps(p.unidentifiable),
               "standard_method": result.standard_method, "coulomb_model": "sign(qd)"})
    return {"/": root, **{fit.name: _recording_dataset(fit, joints) for fit in result.recordings}}


def identification_size(samples: Sequence[int], n: int) -> int:
    """Bytes of the per-sample variables of identification.h5 (uncompressed), plus 1 MiB: an
    over-estimate of the file, checked before the identification
    (:func:`gd_analyze.store.staging.check_free_space`).

    Parameters
    ----------
    samples : sequence of int
        Per recording, at most the samples stored
        (:func:`gd_analyze.estimation.preprocess.most_samples`).
    n : int
        Joints.

    Returns
    -------
    int
        8 bytes per value: ``t`` and eight vectors of n (``q``, ``qd``, ``qdd``,
        ``tau_measured``, ``tau_predicted``, ``tau_prior``, the optional ``tau_simplified``
        and the flags ``used``, counted as 8 bytes) per sample; the parameters, the links'
        tables and the attributes are in the 1 MiB [bytes].

    Examples
    --------
    >>> identification_size([4000, 1500], 2) - (1 << 20) == 8 * 5500 * (1 + 8 * 2)
    True
    """
    return 8 * sum(int(k) for k in samples) * (1 + 8 * n) + (1 << 20)


def write_identification(result: IdentificationResult, path: str | os.PathLike[str]) -> Path:
    """Write ``identification.h5``.

    Parameters
    ----------
    result : IdentificationResult
    path : str or os.PathLike
        The file to write (a staged output folder's file; replaced if it exists).

    Returns
    -------
    pathlib.Path
    """
    path = Path(path)
    tree = identification_tree(result)
    path.unlink(missing_ok=True)
    for name, ds in tree.items():
        ds.to_netcdf(path, mode="w" if name == "/" else "a", engine="h5netcdf",
                     group=None if name == "/" else name, invalid_netcdf=True)
    return path


def read_identification(path: str | os.PathLike[str]) -> dict[str, xr.Dataset]:
    """Read ``identification.h5`` back.

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    dict of str -> xarray.Dataset
        ``"/"`` and one dataset per recording group, loaded into memory.
    """
    import h5netcdf
    import xarray as xr

    with h5netcdf.File(path, "r") as f:
        groups = ["/", *f.groups]
    return {g: xr.load_dataset(path, engine="h5netcdf", group=None if g == "/" else g)
            for g in groups}


def _finite(values):
    """Numbers as JSON allows them: a non-finite one (a joint whose measured torque is all 0
    has no relative error) as None."""
    return [float(v) if np.isfinite(v) else None for v in np.atleast_1d(values)]


def recordings_json(result: IdentificationResult) -> dict[str, Any]:
    """The ``--json`` object: recordings with their errors, and the condition number.

    Parameters
    ----------
    result : IdentificationResult

    Returns
    -------
    dict
        ``{"recordings": [{"file", "role", "relative_error", "total_relative_error",
        "prior_relative_error", "prior_total_relative_error"}, ...], "condition_number",
        "rank", "unidentifiable"}`` (and ``simplified_*`` errors with a simplified model); an
        error that is not finite (a joint whose measured torque is all 0) is None.
    """
    recs = []
    for fit in result.recordings:
        item = {"file": fit.file, "role": fit.role}
        for which, key in (("predicted", ""), ("prior", "prior_"), ("simplified", "simplified_")):
            if which != "simplified" or fit.tau_simplified is not None:
                _, rel, total = fit.errors(which)
                item.update({f"{key}relative_error": _finite(rel),
                             f"{key}total_relative_error": _finite(total)[0]})
        recs.append(item)
    return {"recordings": recs, "condition_number": float(result.condition_number),
            "rank": int(result.rank), "unidentifiable": result.parameters.unidentifiable}


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


@dataclass(frozen=True, eq=False)
class StoredRecording(View):
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
    n : int
        The joints.
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
    file: Any = stored("file", default=None, attr=True)
    sha256: Any = stored("sha256", default=None, attr=True)
    role: Any = derived(lambda ds: (
        ds.attrs["role"] if "role" in ds.attrs else
        np.asarray(ds["role"].values).reshape(-1)[0] if "role" in ds.variables else None))
    t: np.ndarray = stored("t", lambda v: np.asarray(v, float))
    torques: Mapping[str, np.ndarray] = derived(lambda ds: {
        v: ds[v].values for v in TORQUES if v in ds.variables})
    n: int = derived(lambda ds: int(ds["tau_measured"].shape[1]))
    joint: np.ndarray | None = stored("joint", default=None)
    rms_error: np.ndarray | None = stored("rms_error", default=None)
    relative_error: np.ndarray | None = stored("relative_error", default=None)
    prior_relative_error: np.ndarray | None = stored("prior_relative_error", default=None)
    simplified_relative_error: np.ndarray | None = stored("simplified_relative_error",
                                                          default=None)
    total_relative_error: float = derived(lambda ds: _number(ds, "total_relative_error"))
    prior_total_relative_error: float = derived(
        lambda ds: _number(ds, "prior_total_relative_error"))
    simplified_total_relative_error: float = derived(
        lambda ds: _number(ds, "simplified_total_relative_error"))
    has_prior_total: bool = derived(lambda ds: "prior_total_relative_error" in ds.attrs)
    has_simplified_total: bool = derived(lambda ds: "simplified_total_relative_error" in ds.attrs)
    notes: Any = stored("notes", default=None, attr=True)

    @property
    def file_name(self) -> Any:
        """object: the recording's file name as stored, or else the group's name."""
        return self.name if self.file is None else self.file

    @classmethod
    def from_dataset(cls, name: str,  # type: ignore[override]  # and its group
                     ds: xr.Dataset) -> StoredRecording:
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
        return cls.read(ds, name=name)


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

    recordings: Mapping[str, StoredRecording]
    robot: Any = stored(Attr.ROBOT, default=None, attr=True)
    robot_source: Any = stored(Attr.ROBOT_SOURCE, default=None, attr=True)
    robot_sha256: Any = stored(Attr.ROBOT_SHA256, default=None, attr=True)
    gd_analyze_version: Any = stored(Attr.GD_ANALYZE_VERSION, default=None, attr=True)
    standard_method: Any = stored("standard_method", default=None, attr=True)
    coulomb_model: Any = stored("coulomb_model", default=None, attr=True)
    inputs: Any = stored("inputs", default=None, attr=True)
    settings: Any = stored("settings", default=None, attr=True)
    unidentifiable: Any = stored("unidentifiable", default=None, attr=True)
    preprocessing: Any = stored("preprocessing", default=None, attr=True)
    condition_number: float = derived(lambda ds: _number(ds, "condition_number"))
    parameter: np.ndarray | None = stored("parameter", default=None)
    value: np.ndarray = stored("value", lambda v: np.asarray(v, float))
    std: np.ndarray = stored("std", lambda v: np.asarray(v, float))
    kind: np.ndarray | None = stored("kind", default=None)
    prior: np.ndarray | None = stored("prior", default=None)
    identifiable: np.ndarray | None = stored("identifiable", default=None)
    link: np.ndarray | None = stored("link", default=None)
    link_consistent: np.ndarray | None = stored("link_consistent", default=None)
    pseudo_inertia_min_eigenvalue: np.ndarray | None = stored("pseudo_inertia_min_eigenvalue",
                                                              default=None)
    noise_std: np.ndarray | None = stored("noise_std", default=None)
    joint: np.ndarray | None = stored("joint", default=None)
    prismatic: np.ndarray | None = stored("prismatic", default=None)

    @classmethod
    def from_dataset(cls, root: xr.Dataset,  # type: ignore[override]  # and its groups
                     groups: Mapping[str, xr.Dataset]) -> StoredIdentification:
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
        return cls.read(root, recordings=recordings)
