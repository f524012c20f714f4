"""Storage: the analysis as one xarray Dataset in an HDF5/netCDF4 file (engine h5netcdf).

This module also holds the plumbing every gd-analyze dataset shares (:func:`var`,
:func:`global_attributes`, :func:`element_coords`, :func:`write_dataset`,
:func:`open_results`); the sweep and closed-loop schemas are in
:mod:`gd_analyze.io.sweep_datasets` and :mod:`gd_analyze.io.control_dataset`.

Dimensions: ``setpoint``, ``joint`` and ``joint_k`` (the column index of D), ``element`` (the
ranked elements ``"D11"`` .. ``"hn"``, string labels) and ``xyz``/``xyz_k`` for the link
parameters. Every variable carries ``units`` and ``long_name``; the global attributes follow
the CF conventions and carry the provenance: tool version, robot and its SHA-256, gravity,
thresholds, and the input file's name and SHA-256.

Files are written to a temporary name in the destination folder and renamed
(:func:`gd_analyze.files.atomic_path`), so a reader never sees a half-written file.
"""

from __future__ import annotations

import datetime
import os
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..files import atomic_path

__all__ = ["CONVENTIONS", "MIXED_UNITS", "var", "attribute_value", "global_attributes",
           "element_coords", "strings", "write_dataset", "open_results", "open_sweep",
           "build_dataset", "summary_dataset", "setpoint_arrays", "SetpointWriter",
           "SETPOINT_VARIABLES", "skip_dask", "append_dataset"]

#: The CF conventions the datasets follow.
CONVENTIONS = "CF-1.10"
#: Units of a variable over the element dim (D elements in kg m2, h elements in N m).
MIXED_UNITS = "kg m2 (D) or N m (h)"


def skip_dask():
    """Keep xarray from importing dask in a process that has not imported it.

    xarray imports dask (about 0.3 s, and 1-2 s with ``dask.array``) the first time it builds
    a variable, only to check whether the data is a dask array. No object can be a dask array
    or collection before dask is imported, so this installs two checks that answer "no" while
    ``dask`` is not in ``sys.modules`` and defer to xarray's own once it is: always correct, so
    a later dask user (the sweep) is unaffected.

    Returns
    -------
    bool
        True if the checks are installed; False if xarray's internals differ from those
        expected (then nothing is changed and xarray imports dask as usual).

    Notes
    -----
    Writing with :meth:`xarray.Dataset.to_netcdf` still imports dask (it asks for the dask
    scheduler): :func:`append_dataset` writes without it.
    """
    import sys

    try:
        from xarray.namedarray import pycompat, utils
    except ImportError:          # pragma: no cover - another xarray layout
        return False
    cache = getattr(pycompat, "_cached_duck_array_modules", None)
    module_type = getattr(pycompat, "DuckArrayModule", None)
    collection = getattr(utils, "is_dask_collection", None)
    if not isinstance(cache, dict) or module_type is None or collection is None:
        return False
    if getattr(collection, "_gd_lazy", False):
        return True

    class _LazyDask(module_type):
        """xarray's record of dask: absent until dask is imported, then the real one."""

        def __init__(self):                  # noqa: D107 - no import here
            self._real = None

        def _get(self):
            if "dask" not in sys.modules:
                return None
            if self._real is None:
                self._real = module_type("dask")
            return self._real

        module = property(lambda self: self._get().module if self._get() else None)
        version = property(lambda self: self._get().version if self._get() else
                           __import__("packaging.version").version.Version("0"))
        type = property(lambda self: self._get().type if self._get() else ())
        available = property(lambda self: bool(self._get() and self._get().available))

    def is_dask_collection(x):
        return "dask" in sys.modules and collection(x)

    is_dask_collection._gd_lazy = True
    if "dask" not in cache:
        cache["dask"] = _LazyDask()
    utils.is_dask_collection = is_dask_collection
    return True


def append_dataset(ds, path):
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
    The same encoding as ``ds.to_netcdf(path, mode="a", engine="h5netcdf")``, without the
    dask scheduler query of ``to_netcdf`` (which imports dask): see :func:`skip_dask`.
    """
    from xarray.backends import H5NetCDFStore
    from xarray.backends.locks import HDF5_LOCK

    # an explicit lock: the default one asks dask for its scheduler
    store = H5NetCDFStore.open(str(path), mode="a", lock=HDF5_LOCK)
    try:
        ds.dump_to_store(store)
    finally:
        store.close()


#: Per-set-point variables: name -> (dims, units, long_name). Used by both writers.
SETPOINT_VARIABLES = {
    "t": (("setpoint",), "s", "time"),
    "q": (("setpoint", "joint"), "rad", "joint position"),
    "qd": (("setpoint", "joint"), "rad s-1", "joint velocity"),
    "qdd": (("setpoint", "joint"), "rad s-2", "joint acceleration"),
    "D_tran": (("setpoint", "joint", "joint_k"), "kg m2",
               "inertia matrix, translational part (Eq. 3.4-25)"),
    "D_rot": (("setpoint", "joint", "joint_k"), "kg m2",
              "inertia matrix, rotational part (Eq. 3.4-25)"),
    "D": (("setpoint", "joint", "joint_k"), "kg m2", "inertia matrix D = D_tran + D_rot"),
    "h_tran": (("setpoint", "joint"), "N m",
               "Coriolis and centrifugal torque, translational part (Eq. 3.4-26)"),
    "h_rot": (("setpoint", "joint"), "N m",
              "Coriolis and centrifugal torque, rotational part (Eq. 3.4-27)"),
    "h": (("setpoint", "joint"), "N m", "Coriolis and centrifugal torque h = h_tran + h_rot"),
    "c": (("setpoint", "joint"), "N m", "gravity loading (Eq. 3.4-28)"),
    "tau": (("setpoint", "joint"), "N m",
            "joint torque of the full model, D qdd + h + c (Eq. 3.4-24)"),
    "tau_simplified": (("setpoint", "joint"), "N m",
                       "joint torque of the simplified model, D_s qdd + h_s + c"),
}


def var(dims, data, units, long_name, **attrs):
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


def attribute_value(value):
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


def global_attributes(robot, title, references="Fu, Gonzalez & Lee (1987), Robotics, Sec. 3.4; "
                      "Lee, Lee & Nigam (1983)", **extra):
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
        ``robot_source``, ``robot_sha256``, ``gravity``, ``gravity_units``, then ``extra``.
    """
    from .._version import __version__

    now = datetime.datetime.now(datetime.timezone.utc).replace(microsecond=0).isoformat()
    attrs = {
        "Conventions": CONVENTIONS,
        "title": title,
        "source": f"gd-analyze {__version__}",
        "references": references,
        "history": f"{now} created by gd-analyze {__version__}",
        "gd_analyze_version": __version__,
        "robot": robot.name,
        "robot_description": robot.description,
        "robot_reference": robot.reference,
        "robot_source": robot.source,
        "robot_sha256": robot.sha256,
        "gravity": np.asarray(robot.gravity, dtype=float),
        "gravity_units": "m s-2",
    }
    attrs.update({k: attribute_value(v) for k, v in extra.items()})
    return attrs


def element_coords(n):
    """Coordinates ``element`` (with ``element_units``) and ``joint`` for an n-joint robot.

    Parameters
    ----------
    n : int
        Number of joints.

    Returns
    -------
    dict
        name -> (dims, values, attrs): the M = n (n + 1) / 2 + n ranked element labels
        ``"D11"`` .. ``"hn"``, their units (kg m2 for D, N m for h) and joints 1 .. n.
    """
    from ..core.ranking import element_labels

    labels = element_labels(n)
    return {
        "element": ("element", np.array(labels, dtype=str),
                    {"long_name": "ranked element of D (i <= j) or h", "units": "1"}),
        "element_units": ("element",
                          np.array(["kg m2" if lab.startswith("D") else "N m" for lab in labels],
                                   dtype=str),
                          {"long_name": "units of the element", "units": "1"}),
        "joint": ("joint", np.arange(1, n + 1), {"long_name": "joint", "units": "1"}),
    }


def strings(values):
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


def setpoint_arrays(trajectory, terms, tau, tau_simplified):
    """The per-set-point arrays, keyed as :data:`SETPOINT_VARIABLES`.

    Parameters
    ----------
    trajectory : Trajectory
        t (N,) [s]; q, qd, qdd (N, n).
    terms : GDTerms
        The G-D terms at the same set points.
    tau, tau_simplified : ndarray, shape (N, n)
        Torques of the full and the simplified model [N m].

    Returns
    -------
    dict
        name -> ndarray.
    """
    return {"t": trajectory.t, "q": trajectory.q, "qd": trajectory.qd, "qdd": trajectory.qdd,
            "D_tran": terms.D_tran, "D_rot": terms.D_rot, "D": terms.D, "h_tran": terms.h_tran,
            "h_rot": terms.h_rot, "h": terms.h, "c": terms.c, "tau": tau,
            "tau_simplified": tau_simplified}


def summary_dataset(robot, trajectory, ranking, choices, error, verification=None,
                    settings=None):
    """Everything but the per-set-point variables: ranking, model, robot, provenance.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    trajectory : Trajectory
        Its source, SHA-256 and how derivatives were obtained go into the attributes.
    ranking : Ranking
        The dominance of each of the M elements.
    choices : dict
        Element label -> kept part (``"tran"``, ``"rot"``, ``"both"``, ``"none"``).
    error : dict
        Torque error per joint, as :func:`gd_analyze.core.simplified.torque_error` gives it.
    verification : dict, optional
        Largest relative disagreement with Pinocchio per term, and the set points checked.
    settings : dict, optional
        Extra global attributes (scalars or strings), e.g. the command line.

    Returns
    -------
    xarray.Dataset
        Dims ``element``, ``joint``, ``xyz``, ``xyz_k``; CF-style global attributes.
    """
    import xarray as xr

    from ..core.ranking import CHAPTER_DOMINANCE

    n = robot.n
    labels = list(ranking.labels)
    mixed = MIXED_UNITS
    data_vars = {
        "share_tran": var(("element",), ranking.share_tran, "1",
                           "translational share sum|tran| / (sum|tran| + sum|rot|)"),
        "dominance": var(("element",), np.array(ranking.dominance, dtype=str), "1",
                          "dominance class (translational, rotational, both, negligible)"),
        "chapter_dominance": var(("element",),
                                  np.array([CHAPTER_DOMINANCE.get(lab, "") if n == 6 else ""
                                            for lab in labels], dtype=str), "1",
                                  "dominance reported in Sec. 3.4.1 for the chapter's PUMA 560 "
                                  "(empty unless the robot has 6 joints)"),
        "choice": var(("element",), np.array([choices[lab] for lab in labels], dtype=str), "1",
                       "part kept by the simplified model (tran, rot, both, none)"),
        "peak_tran": var(("element",), ranking.peak_tran, mixed,
                          "peak |translational part| along the trajectory"),
        "peak_rot": var(("element",), ranking.peak_rot, mixed,
                         "peak |rotational part| along the trajectory"),
        "peak_total": var(("element",), ranking.peak_total, mixed,
                           "peak |translational + rotational| along the trajectory"),
        "element_scale": var(("element",), ranking.scale, mixed,
                              "scale of the negligibility test: peak sqrt(D_ii D_jj) or |tau_i|"),
        "tau_error_peak": var(("joint",), np.array(error["peak_abs_error"]), "N m",
                               "peak |tau_simplified - tau|"),
        "tau_error_rms": var(("joint",), np.array(error["rms_error"]), "N m",
                              "RMS of |tau_simplified - tau|"),
        "tau_peak": var(("joint",), np.array(error["peak_tau"]), "N m", "peak |tau|"),
        "tau_error_relative_peak": var(("joint",), np.array(error["relative_peak_error"]), "1",
                                        "peak |tau_simplified - tau| / peak |tau|"),
        "tau_error_relative_rms": var(("joint",), np.array(error["relative_rms_error"]), "1",
                                       "RMS |tau_simplified - tau| / peak |tau|"),
        "joint_type": var(("joint",), np.array(robot.joint_types, dtype=str), "1",
                          "joint type: revolute (q in rad) or prismatic (q in m)"),
        "dh_d": var(("joint",), robot.d, "m", "DH link offset d"),
        "dh_a": var(("joint",), robot.a, "m", "DH link length a"),
        "dh_alpha": var(("joint",), robot.alpha, "rad", "DH twist angle alpha"),
        "dh_offset": var(("joint",), robot.offset, "rad", "joint angle offset, theta = q + offset"),
        "link_mass": var(("joint",), robot.mass, "kg", "link mass"),
        "link_com": var(("joint", "xyz"), robot.com, "m", "centre of mass in link frame"),
        "link_inertia": var(("joint", "xyz", "xyz_k"), robot.inertia, "kg m2",
                             "inertia tensor about the centre of mass, link-frame axes"),
        "q_min": var(("joint",), robot.q_min, "rad", "lower joint position limit"),
        "q_max": var(("joint",), robot.q_max, "rad", "upper joint position limit"),
        "qd_max": var(("joint",), robot.qd_max, "rad s-1", "joint velocity limit"),
        "qdd_max": var(("joint",), robot.qdd_max, "rad s-2", "joint acceleration limit"),
    }
    coords = element_coords(n)
    coords["joint"] = ("joint", np.arange(1, n + 1), {"long_name": "joint (row of D)",
                                                      "units": "1"})
    coords["xyz"] = ("xyz", np.array(["x", "y", "z"]), {"long_name": "axis", "units": "1"})
    coords["xyz_k"] = ("xyz_k", np.array(["x", "y", "z"]), {"long_name": "axis", "units": "1"})
    attrs = global_attributes(
        robot, f"G-D dominance analysis of {robot.name} along {Path(trajectory.source).name}",
        dominance_threshold=ranking.dominance_threshold,
        negligible_threshold=ranking.negligible_threshold,
        input_file=Path(trajectory.source).name, input_path=str(trajectory.source),
        input_sha256=trajectory.sha256, derivatives=trajectory.derivatives,
        setpoints=int(trajectory.t.shape[0]))
    for key, value in (verification or {}).items():
        attrs[f"verification_{key}"] = value
    attrs.update(settings or {})
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def build_dataset(robot, trajectory, terms, ranking, tau, tau_simplified, choices, error,
                  verification=None, settings=None):
    """Assemble the analysis into one xarray Dataset, in memory.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    trajectory : Trajectory
        t (N,) [s]; q, qd, qdd (N, n) [rad, rad/s, rad/s^2].
    terms : GDTerms
        D_tran, D_rot (N, n, n) [kg m^2]; h_tran, h_rot, c (N, n) [N m].
    ranking : Ranking
        The dominance of each of the M elements.
    tau, tau_simplified : ndarray, shape (N, n)
        Torques of the full and the simplified model [N m].
    choices : dict
        Element label -> kept part.
    error : dict
        Torque error per joint.
    verification : dict, optional
        Result of the check against Pinocchio.
    settings : dict, optional
        Extra global attributes.

    Returns
    -------
    xarray.Dataset
        The per-set-point variables of :data:`SETPOINT_VARIABLES` and the
        :func:`summary_dataset`.
    """
    ds = summary_dataset(robot, trajectory, ranking, choices, error, verification, settings)
    arrays = setpoint_arrays(trajectory, terms, tau, tau_simplified)
    for name, (dims, units, long_name) in SETPOINT_VARIABLES.items():
        ds[name] = var(dims, arrays[name], units, long_name)
    N, n = trajectory.q.shape
    ds = ds.assign_coords(
        setpoint=("setpoint", np.arange(N), {"long_name": "set point index", "units": "1"}),
        joint_k=("joint_k", np.arange(1, n + 1), {"long_name": "joint (column of D)",
                                                  "units": "1"}))
    return ds


class SetpointWriter:
    """Stream the per-set-point variables into a new netCDF4/HDF5 file, chunk by chunk.

    The file gets dims ``setpoint`` (N), ``joint`` and ``joint_k`` (n), their coordinate
    variables, and every variable of :data:`SETPOINT_VARIABLES` with ``units`` and
    ``long_name``. Add the summary afterwards with
    ``summary.to_netcdf(path, mode="a", engine="h5netcdf")``.

    Parameters
    ----------
    path : str or os.PathLike
        The file to create (write it under a temporary name: see :func:`atomic_path`).
    N : int
        Number of set points.
    n : int
        Number of joints.
    chunk : int, optional
        Set points per HDF5 chunk.
    compress : int, optional
        gzip level 1-9 for the per-set-point variables; 0 (default) stores them uncompressed,
        about ten times faster to write and 1.5 to 2 times larger.
    """

    def __init__(self, path, N, n, chunk=8192, compress=0):
        import h5netcdf

        self._file = h5netcdf.File(path, "w")
        f = self._file
        f.dimensions = {"setpoint": N, "joint": n, "joint_k": n}
        rows = max(1, min(int(chunk), N))
        for name, dims, values, long_name in (
                ("setpoint", ("setpoint",), np.arange(N), "set point index"),
                ("joint", ("joint",), np.arange(1, n + 1), "joint (row of D)"),
                ("joint_k", ("joint_k",), np.arange(1, n + 1), "joint (column of D)")):
            v = f.create_variable(name, dims, "i8")
            v[:] = values
            v.attrs.update(units="1", long_name=long_name)
        self.variables = {}
        for name, (dims, units, long_name) in SETPOINT_VARIABLES.items():
            shape = tuple({"setpoint": rows, "joint": n, "joint_k": n}[d] for d in dims)
            opts = {"compression": "gzip", "compression_opts": int(compress)} if compress else {}
            v = f.create_variable(name, dims, "f8", chunks=shape, **opts)
            v.attrs.update(units=units, long_name=long_name)
            self.variables[name] = v

    def write(self, start, arrays):
        """Write a block of set points.

        Parameters
        ----------
        start : int
            Index of the block's first set point.
        arrays : dict
            name -> ndarray whose first axis is the block's set points.
        """
        for name, values in arrays.items():
            self.variables[name][start:start + len(values)] = values

    def read(self, name, start, stop):
        """Read back set points [start, stop) of a variable.

        Parameters
        ----------
        name : str
            A name of :data:`SETPOINT_VARIABLES`.
        start, stop : int
            Set-point range.

        Returns
        -------
        ndarray
        """
        return self.variables[name][start:stop]

    def close(self):
        """Close the file."""
        self._file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def write_dataset(ds, path):
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
        ds.to_netcdf(tmp, engine="h5netcdf", encoding=encoding, invalid_netcdf=False)


def open_results(path, lazy=False):
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

    Raises
    ------
    InputError
        If the file is missing or not a readable netCDF4/HDF5 file.
    """
    import xarray as xr

    if not os.path.isfile(path):
        raise InputError("no such file", path)
    try:
        if lazy:
            return xr.open_dataset(path, engine="h5netcdf")
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            return ds.load()
    except (OSError, ValueError) as exc:
        raise InputError(f"not a gd-analyze results file: {exc}", path) from None


def open_sweep(path, kind="sweep"):
    """Read a sweep file written by :func:`gd_analyze.io.datasets.write_dataset`.

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
