"""The plumbing every gd-analyze dataset shares: variables, CF attributes, writing, reading.

One :func:`var` (``units`` and ``long_name`` on every variable), one block of CF-style global
attributes with the provenance (:func:`global_attributes`), one writer (:func:`write_dataset`,
atomic, h5netcdf) and one reader (:func:`open_results`, :func:`open_sweep`). The schemas that use
it: :mod:`gd_analyze.store.datasets` (``results.h5``), :mod:`gd_analyze.store.sweep_view`,
:mod:`gd_analyze.store.control_dataset`.
"""

from __future__ import annotations

import datetime
import os
from collections import namedtuple
from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from typing import TYPE_CHECKING, Any, ClassVar, TypeVar

import numpy as np
from numpy.typing import ArrayLike

from .._version import VERSION as __version__
from ..errors import InputError, regular_file
from ..files import atomic_path
from ..ranking.labels import element_index, element_units
from ..ranking.ranking import element_labels
from .names import Attr, Var

if TYPE_CHECKING:
    from collections.abc import Callable, Sequence

    import xarray as xr

    from ..model.robot import Robot

__all__ = ["CONVENTIONS", "MIXED_UNITS", "var", "flag", "attribute_value", "global_attributes",
           "element_coords", "text_coordinate", "joint_type_var", "strings", "utc_now",
           "stored_prismatic", "stored_has_drives", "require",
           "Record", "stored_name", "texts", "stored", "derived", "View", "RunRecord", "EvaluatorCosts", "write_dataset", "append_dataset", "open_results", "open_sweep"]

#: The CF conventions the datasets follow.
CONVENTIONS = "CF-1.10"
#: Units of a variable over the element dim (D elements in kg m2, h elements in N m).
MIXED_UNITS = "per element: element_units (kg m2, kg m or kg for D; N m or N for h)"


def append_dataset(ds: xr.Dataset, path: str | os.PathLike[str]) -> None:
    """Add a dataset's variables and attributes to a netCDF4/HDF5 file, through h5netcdf.

    Parameters
    ----------
    ds : xarray.Dataset
        In memory (numpy-backed).
    path : str or os.PathLike
        An existing file, opened in append mode.

    Raises
    ------
    OSError
        If the file cannot be written.

    Notes
    -----
    The same encoding as ``ds.to_netcdf(path, mode="a", engine="h5netcdf")``, through xarray's
    public h5netcdf store with an explicit lock: ``to_netcdf`` asks dask for its scheduler
    (importing dask where it is installed), which the main job has no use for.
    """
    _dump(ds, path, "a")


def var(dims: tuple[str, ...], data: ArrayLike, units: str, long_name: str,
        **attrs: Any) -> tuple[Any, ...]:
    """One variable as xarray takes it: ``(dims, data, attrs)`` with ``units`` and ``long_name``.

    Parameters
    ----------
    dims : tuple of str
        Dimension names.
    data : array_like
        Values.
    units : str
        UDUNITS string, e.g. ``"N m"``, ``"kg m2"``, ``"1"``.
    long_name : str
        What the variable is.
    **attrs
        More attributes (e.g. CF ``flag_values``).

    Returns
    -------
    tuple
    """
    return (dims, data, {"units": units, "long_name": long_name, **attrs})


def attribute_value(value: object) -> Any:
    """A value as an HDF5 attribute can hold it: numbers, strings or numeric arrays.

    Parameters
    ----------
    value : object
        bool, None, a sequence, a dict or a scalar.

    Returns
    -------
    int, float, str or ndarray
        bools as 0/1, None as "", numeric sequences as arrays, other sequences and dicts as
        "; "-joined text.
    """
    if isinstance(value, (bool, np.bool_)):
        return int(value)
    if value is None:
        return ""
    if isinstance(value, (list, tuple)):
        arr = np.asarray(value)
        return arr if arr.dtype.kind in "iuf" else "; ".join(map(str, value))
    if isinstance(value, dict):
        return "; ".join(f"{k}={v}" for k, v in value.items())
    return value


def utc_now() -> datetime.datetime:
    """The current UTC time, to the second: the time stamp of every dataset and report.

    Returns
    -------
    datetime.datetime
        Time-zone aware, microseconds zero.
    """
    return datetime.datetime.now(datetime.timezone.utc).replace(microsecond=0)


def global_attributes(robot: Robot, title: str,
                      references: str = "Fu, Gonzalez & Lee (1987), Robotics, Sec. 3.4; " "Lee, Lee & Nigam (1983)",
                      **extra: Any) -> dict[str, Any]:
    """The CF-style global attributes every gd-analyze dataset carries: its provenance.

    Parameters
    ----------
    robot : Robot
        The arm: its name, description, reference, source file and SHA-256, and gravity
        [m/s^2] are recorded.
    title : str
        The dataset's title.
    references : str, optional
        The sources of the method.
    **extra
        More attributes (passed through :func:`attribute_value`), e.g. thresholds, input files
        and their SHA-256, settings.

    Returns
    -------
    dict
        ``Conventions``, ``title``, ``source``, ``references``, ``history``,
        ``gd_analyze_version``, ``robot``, ``robot_description``, ``robot_reference``,
        ``robot_source``, ``robot_sha256``, ``gravity``, ``gravity_units``,
        ``robot_placeholder_inertia`` (1, only for a robot whose inertia tensors are
        placeholders, ``Robot.metadata["placeholder_inertia"]``), then ``extra``.
    """

    now = utc_now().isoformat()
    attrs: dict[str, Any] = {
        Attr.CONVENTIONS: CONVENTIONS,
        Attr.TITLE: title,
        Attr.SOURCE: f"gd-analyze {__version__}",
        Attr.REFERENCES: references,
        Attr.HISTORY: f"{now} created by gd-analyze {__version__}",
        Attr.GD_ANALYZE_VERSION: __version__,
        Attr.ROBOT: robot.name,
        Attr.ROBOT_DESCRIPTION: robot.description,
        Attr.ROBOT_REFERENCE: robot.reference,
        Attr.ROBOT_SOURCE: robot.source,
        Attr.ROBOT_SHA256: robot.sha256,
        Attr.GRAVITY: np.asarray(robot.gravity, dtype=float),
        Attr.GRAVITY_UNITS: "m s-2",
    }
    if robot.metadata.get("placeholder_inertia"):     # a read-only mapping, maybe empty
        attrs[Attr.ROBOT_PLACEHOLDER_INERTIA] = 1     # its inertia tensors are not measured
    attrs.update({k: attribute_value(v) for k, v in extra.items()})
    return attrs


def text_coordinate(dim: str, values: Sequence[object], long_name: str) -> tuple[Any, ...]:
    """A coordinate of names (the joints', the elements', the controllers', the classes').

    Parameters
    ----------
    dim : str
        Its dimension.
    values : sequence
        Its values, each written as str (stored as netCDF4 strings).
    long_name : str
        Its ``long_name``.

    Returns
    -------
    tuple
        ``(dim, values, attrs)`` as xarray takes it, with ``units`` ``"1"``.

    Examples
    --------
    >>> text_coordinate("class", ["both", "none"], "dominance class")[1].tolist()
    ['both', 'none']
    """
    return (dim, np.array([str(v) for v in values], dtype=str),
            {"long_name": long_name, "units": "1"})


def element_coords(n: int, prismatic: Sequence[bool] | np.ndarray | None = None,
                   joints: Sequence[str] | None = None) -> dict[str, Any]:
    """Coordinates ``element`` (with ``element_units``) and ``joint`` for an n-joint robot.

    Parameters
    ----------
    n : int
        Number of joints.
    prismatic : sequence of bool, shape (n,), optional
        The prismatic joints, for the units (all revolute if not given).
    joints : sequence of str, length n, optional
        The joints' names (default ``"joint1"`` .. ``"jointn"``, as
        :meth:`gd_analyze.model.robot.Robot.joint_names` names a robot without its own).

    Returns
    -------
    dict
        name -> (dims, values, attrs): the M = n (n + 1) / 2 + n ranked element labels
        ``"D11"`` .. ``"hn"``, their units from the joint types
        (:func:`gd_analyze.ranking.labels.element_units`: kg m2, kg m or kg for D; N m or N for
        h) and the joints' names (``joints``, else ``"joint1"`` .. ``"jointn"``: a
        :func:`text_coordinate`).
    """

    labels = element_labels(n)
    units = [element_units(kind, i, j, prismatic) for kind, i, j in element_index(n)]
    return {
        Var.ELEMENT: text_coordinate("element", labels, "ranked element of D (i <= j) or h"),
        Var.ELEMENT_UNITS: text_coordinate("element", units, "units of the element"),
        Var.JOINT: text_coordinate("joint", joints if joints is not None else
                                   [f"joint{i}" for i in range(1, n + 1)], "joint"),
    }


def flag(dims: tuple[str, ...], mask: ArrayLike, long_name: str,
         meanings: str = "data round_off") -> tuple[Any, ...]:
    """A 0/1 flag variable (int8, CF ``flag_values`` and ``flag_meanings``), as :func:`var`.

    Parameters
    ----------
    dims : tuple of str
        Dimension names.
    mask : array_like of bool
        Where the flag is 1.
    long_name : str
        What 1 means.
    meanings : str, optional
        The CF ``flag_meanings`` of 0 and 1.

    Returns
    -------
    tuple
    """
    return var(dims, np.asarray(mask, bool).astype(np.int8), "1", long_name,
               flag_values=np.array([0, 1], dtype=np.int8), flag_meanings=meanings)


def joint_type_var(robot: Robot) -> tuple[Any, ...]:
    """The variable ``joint_type``, as :func:`var`: each joint's type, from which the units of
    its q and tau follow.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    tuple
    """
    return var(("joint",), np.array(robot.joint_types, dtype=str), "1",
               "joint type: revolute (q in rad) or prismatic (q in m)")


def strings(values: ArrayLike) -> list[str]:
    """Decode an array of bytes or str read from a file into a list of str.

    Parameters
    ----------
    values : array_like
        Strings as stored.

    Returns
    -------
    list of str
    """
    return [v.decode() if isinstance(v, bytes) else str(v) for v in np.asarray(values).ravel()]


def stored_prismatic(ds: xr.Dataset) -> tuple[bool, ...]:
    """The prismatic joints, as the variable ``joint_type`` stores them.

    Parameters
    ----------
    ds : xarray.Dataset
        With dim ``joint``.

    Returns
    -------
    tuple of bool, length n
        All False (revolute) where ``joint_type`` is not stored.
    """
    if Var.JOINT_TYPE not in ds.variables:
        return (False,) * int(ds.sizes[Var.JOINT])
    return tuple(t == "prismatic" for t in strings(ds[Var.JOINT_TYPE].values))


def stored_has_drives(ds: xr.Dataset) -> bool:
    """Whether the stored robot has drives: armature, friction or a torque offset.

    Parameters
    ----------
    ds : xarray.Dataset
        A results dataset, with or without the variables ``D_arm``, ``viscous``,
        ``coulomb`` and ``torque_offset`` (each shape (n,)).

    Returns
    -------
    bool
        True where one of them is stored and nonzero.
    """
    return any(k in ds.variables and bool(np.any(np.asarray(ds[k].values, float) != 0))
               for k in (Var.D_ARM, Var.VISCOUS, Var.COULOMB, Var.TORQUE_OFFSET))

_R = TypeVar("_R", bound="Record")


class Record:
    """Global attributes of a dataset as stored, read by name: the base of every record of a
    file's settings and provenance (:class:`RunRecord`, the control and sweep settings, the
    results' provenance), each a named tuple that names its attributes once.

    Each field is the global attribute ``prefix + field`` (spelt as its constant of
    :class:`gd_analyze.store.names.Attr` where that differs in case, ``conventions`` is
    ``Conventions``), None where the dataset has none; a field given is as given.
    """

    __slots__ = ()

    @classmethod
    def from_attrs(cls: type[_R], attrs: Mapping[str, Any], prefix: str = "", /,
                   **given: Any) -> _R:
        """The record of a dataset's global attributes.

        Parameters
        ----------
        attrs : Mapping
            The global attributes.
        prefix : str, optional
            The attributes' common prefix (``"model_"``).
        **given
            Fields given, not read (e.g. ``others``).

        Returns
        -------
        The record.
        """
        return cls(**{f: given[f] if f in given else attrs.get(stored_name(prefix + f))
                      for f in cls._fields})  # type: ignore[attr-defined]


def stored_name(name: str) -> str:
    """A global attribute's name as stored: its constant of
    :class:`gd_analyze.store.names.Attr`, else the name itself.

    Parameters
    ----------
    name : str
        Lower case (``"conventions"``).

    Returns
    -------
    str

    Examples
    --------
    >>> stored_name("conventions"), stored_name("model_rule")
    ('Conventions', 'model_rule')
    """
    return getattr(Attr, name.upper(), name)


_V = TypeVar("_V", bound="View")
#: The default of a :func:`stored` field that the dataset must hold.
_REQUIRED: Any = object()


def texts(values: ArrayLike) -> tuple[str, ...]:
    """Strings read from a file, as a tuple (:func:`strings`).

    Parameters
    ----------
    values : array_like
        Strings as stored.

    Returns
    -------
    tuple of str
    """
    return tuple(strings(values))


def stored(name: str, convert: Callable[[Any], Any] | None = None, default: Any = _REQUIRED,
           *, attr: bool = False) -> Any:
    """A field of a :class:`View`: where :meth:`View.read` reads it from a dataset.

    Parameters
    ----------
    name : str
        The variable (a constant of :class:`gd_analyze.store.names.Var`) or, with ``attr``,
        the global attribute it is read from.
    convert : callable, optional
        Applied to the stored value (the variable's values, the attribute's value), not to
        the default.
    default : object, optional
        The field where the dataset does not hold it; without one the dataset must hold it.
    attr : bool, optional
        A global attribute, not a variable.

    Returns
    -------
    dataclasses.Field
        A field without a default, whose metadata says where it is stored.
    """
    return field(metadata={"stored": (name, convert, default, attr)})


def derived(read: Callable[[xr.Dataset], Any]) -> Any:
    """A field of a :class:`View` that :meth:`View.read` computes from the dataset.

    Parameters
    ----------
    read : callable
        The dataset -> the field.

    Returns
    -------
    dataclasses.Field
    """
    return field(metadata={"derived": read})


def require(ds: xr.Dataset, names: Sequence[str], what: str) -> None:
    """Raise if a dataset lacks a variable that a reader of it needs.

    Parameters
    ----------
    ds : xarray.Dataset
        The dataset.
    names : sequence of str
        The variables (coordinates included) needed.
    what : str
        The kind of dataset, for the message ("results", "sweep", ...).

    Raises
    ------
    InputError
        One line naming every missing variable: "not a gd-analyze sweep dataset: missing
        variable(s) merged_bound".
    """
    missing = [name for name in names if name not in ds.variables]
    if missing:
        raise InputError(f"not a gd-analyze {what} dataset: missing variable(s) "
                         + ", ".join(missing))


class View:
    """A typed view read from a dataset by one path, :meth:`read`: each field that is
    :func:`stored` where it says, each :func:`derived` one computed from the dataset, any other
    given by the class's own ``from_dataset`` (a view's file and its one-line checks)."""

    #: The variables (coordinates included) that a dataset holding the view holds: where one is
    #: missing, :meth:`View.from_dataset` gives None.
    presence: ClassVar[tuple[str, ...]] = ()
    #: The variables a dataset of the view must hold: where one is missing,
    #: :meth:`View.from_dataset` raises an error of one line naming what the dataset is not.
    required: ClassVar[tuple[str, ...]] = ()
    #: What a dataset of the view is, as that error names it (``"sweep"``).
    what: ClassVar[str] = ""

    @classmethod
    def read(cls: type[_V], ds: xr.Dataset, /, **given: Any) -> _V:
        """The view of a dataset: each :func:`stored` field as stored, each :func:`derived`
        one computed, the others as given.

        Parameters
        ----------
        ds : xarray.Dataset
        **given
            Fields given, not read.

        Returns
        -------
        The view.

        Raises
        ------
        KeyError
            If the dataset lacks a variable or attribute of a field without a default.
        """
        values = {}
        for f in fields(cls):  # type: ignore[arg-type]
            if f.name in given or not f.metadata:
                continue
            if "derived" in f.metadata:
                values[f.name] = f.metadata["derived"](ds)
                continue
            name, convert, default, attr = f.metadata["stored"]
            if name not in (ds.attrs if attr else ds.variables) and default is not _REQUIRED:
                values[f.name] = default
                continue
            value = ds.attrs[name] if attr else ds[name].values
            values[f.name] = value if convert is None else convert(value)
        return cls(**values, **given)

    @classmethod
    def from_dataset(cls: type[_V], ds: xr.Dataset) -> _V | None:
        """The view of a dataset, or None where it lacks a variable of ``presence``.

        Parameters
        ----------
        ds : xarray.Dataset

        Returns
        -------
        The view (:meth:`read`), or None.

        Raises
        ------
        InputError
            If a variable of ``required`` is missing (one line naming them).
        """
        require(ds, cls.required, cls.what)
        return cls.read(ds) if all(name in ds.variables for name in cls.presence) else None

    @classmethod
    def of(cls: type[_V], ds: _V | xr.Dataset, *args: Any) -> _V:
        """The view itself, or ``from_dataset`` of a dataset (its errors as there).

        Parameters
        ----------
        ds : the view, or xarray.Dataset
        *args
            More arguments of ``from_dataset``.

        Returns
        -------
        The view.
        """
        return ds if isinstance(ds, cls) else cls.from_dataset(ds, *args)  # type: ignore[return-value, call-arg, arg-type]


class RunRecord(Record, namedtuple("RunRecord", """
        gd_analyze_version history gravity mounting_gravity_base mounting_gravity_world
        mounting_base_rpy_deg""")):
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


@dataclass(frozen=True, eq=False)
class EvaluatorCosts(View):
    """The operations per set point of each evaluator of tau a control or sweep dataset
    counted, Newton-Euler last.

    Attributes
    ----------
    evaluators : tuple of str, length E
        Each evaluator's name.
    multiplications, additions : ndarray of int, shape (E,)
        Its multiplications and additions per set point.
    """

    presence = ("evaluator",)

    evaluators: tuple[str, ...] = stored("evaluator", texts)
    multiplications: np.ndarray = stored("multiplications")
    additions: np.ndarray = stored("additions")


def write_dataset(ds: xr.Dataset, path: str | os.PathLike[str]) -> None:
    """Write a dataset to HDF5/netCDF4 with h5netcdf, atomically.

    Parameters
    ----------
    ds : xarray.Dataset
        The dataset.
    path : str or os.PathLike
        Destination, e.g. ``results.h5``.

    Raises
    ------
    OSError
        If the file cannot be written.
    """
    encoding = {name: {"zlib": True, "complevel": 4}
                for name, var in ds.data_vars.items() if var.dtype.kind == "f" and var.ndim >= 2}
    with atomic_path(path) as tmp:
        # what ds.to_netcdf(tmp, engine="h5netcdf", encoding=encoding, invalid_netcdf=False)
        # writes (dask arrays computed first: the store writes numpy arrays)
        _dump(ds.compute() if ds.chunks else ds, tmp, "w", encoding=encoding,
              invalid_netcdf=False)


def _dump(ds, path, mode, encoding=None, **options):
    """Write ``ds`` (numpy-backed) into the file at ``path`` opened in ``mode`` through
    xarray's public h5netcdf store, with an explicit lock: ``to_netcdf`` and the default lock
    ask dask for its scheduler, importing dask.distributed (about 0.5 s of CPU time) where dask
    is installed, which these writes have no use for."""
    from xarray.backends import H5NetCDFStore
    from xarray.backends.locks import HDF5_LOCK

    with H5NetCDFStore.open(str(path), mode=mode, lock=HDF5_LOCK, **options) as store:
        ds.dump_to_store(store, encoding=encoding or {})


def open_results(path: str | os.PathLike[str], lazy: bool = False) -> xr.Dataset:
    """Open a results file written by :func:`write_dataset`.

    Parameters
    ----------
    path : str or os.PathLike
        The ``results.h5`` file.
    lazy : bool, optional
        Leave the variables on disk, to be read in slices (the report of a long trajectory);
        the caller closes the dataset.

    Returns
    -------
    xarray.Dataset
        Loaded into memory and the file closed; or, if ``lazy``, open and read on access.
        Read by xarray's h5netcdf backend, as ``engine="h5netcdf"`` reads it.

    Raises
    ------
    InputError
        If the file is missing or not a readable netCDF4/HDF5 file.
    """
    import xarray as xr
    from xarray.backends import H5netcdfBackendEntrypoint

    regular_file(path, "a results file")
    # the backend given as its entry-point class (xarray's documented alternative to the name):
    # the name would have xarray list every installed package's backends first
    engine = H5netcdfBackendEntrypoint
    try:
        if lazy:
            return xr.open_dataset(path, engine=engine)
        with xr.open_dataset(path, engine=engine) as ds:
            return ds.load()
    except (OSError, ValueError) as exc:
        raise InputError(f"not a gd-analyze results file: {exc}", path) from None


def open_sweep(path: str | os.PathLike[str], kind: str = "sweep") -> xr.Dataset:
    """Read a sweep file written by :func:`gd_analyze.store.schema.write_dataset`.

    Parameters
    ----------
    path : str or os.PathLike
        The ``sweep.h5`` (or payload-sweep) file.
    kind : {"sweep", "payload"}, optional
        What the file must hold: a trajectory sweep (dim ``trajectory``) or a payload sweep
        (dim ``payload``).

    Returns
    -------
    xarray.Dataset
        Loaded into memory; the file is closed.

    Raises
    ------
    InputError
        If the file is missing, unreadable, or not a sweep dataset of that kind.
    """
    ds = open_results(path)
    dim = {"sweep": "trajectory", "payload": "payload"}.get(kind)
    if dim is None:
        raise ValueError(f"kind must be 'sweep' or 'payload', got {kind!r}")
    if "share_tran" not in ds.variables or dim not in ds["share_tran"].dims:
        raise InputError(f"not a gd-analyze {kind} sweep file (no share_tran over {dim})",
                         str(path))
    return ds
