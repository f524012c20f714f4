"""Storage: the analysis as one xarray Dataset in an HDF5/netCDF4 file (engine h5netcdf).

Dimensions: ``setpoint``, ``joint`` and ``joint_k`` (the column index of D), ``element`` (the
ranked elements ``"D11"`` .. ``"hn"``, string labels) and ``xyz``/``xyz_k`` for the link
parameters. Every variable carries ``units`` and ``long_name``; the global attributes follow
the CF conventions and carry the provenance: tool version, robot and its SHA-256, gravity,
thresholds, and the input file's name and SHA-256.

Files are written to a temporary name in the destination folder and renamed, so a reader never
sees a half-written file.
"""

from __future__ import annotations

import contextlib
import datetime
import os
import tempfile
from pathlib import Path

import numpy as np

__all__ = ["atomic_path", "build_dataset", "write_dataset", "open_results", "CONVENTIONS"]

CONVENTIONS = "CF-1.10"


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary file name beside ``path``; rename it to ``path`` on success.

    Parameters
    ----------
    path : str or os.PathLike
        The final destination. Its folder must exist.

    Yields
    ------
    str
        The temporary name to write to. On an exception it is removed and ``path`` is left as
        it was.

    Raises
    ------
    OSError
        If the temporary file cannot be created or renamed.
    """
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent or ".")
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    try:
        yield tmp
        os.chmod(tmp, 0o666 & ~umask)   # mkstemp makes 0600; give the file the usual mode
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.remove(tmp)
        raise


def _var(dims, data, units, long_name, **attrs):
    return (dims, data, {"units": units, "long_name": long_name, **attrs})


def build_dataset(robot, trajectory, terms, ranking, tau, tau_simplified, choices, error,
                  verification=None, settings=None):
    """Assemble the analysis into one xarray Dataset.

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
        Element label -> kept part (``"tran"``, ``"rot"``, ``"both"``, ``"none"``).
    error : dict
        Torque error per joint, as :func:`gd_analyze.simplified.torque_error` gives it.
    verification : dict, optional
        Largest relative disagreement with Pinocchio per term, and the set points checked.
    settings : dict, optional
        Extra global attributes (scalars or strings), e.g. the command line.

    Returns
    -------
    xarray.Dataset
    """
    import xarray as xr

    from . import __version__
    from .ranking import CHAPTER_DOMINANCE

    n = robot.n
    N = trajectory.t.shape[0]
    sj, sjk = ("setpoint", "joint"), ("setpoint", "joint", "joint_k")
    labels = list(ranking.labels)
    el_units = ["kg m2" if lab.startswith("D") else "N m" for lab in labels]
    data_vars = {
        "t": _var(("setpoint",), trajectory.t, "s", "time"),
        "q": _var(sj, trajectory.q, "rad", "joint position"),
        "qd": _var(sj, trajectory.qd, "rad s-1", "joint velocity"),
        "qdd": _var(sj, trajectory.qdd, "rad s-2", "joint acceleration"),
        "D_tran": _var(sjk, terms.D_tran, "kg m2",
                       "inertia matrix, translational part (Eq. 3.4-25)"),
        "D_rot": _var(sjk, terms.D_rot, "kg m2", "inertia matrix, rotational part (Eq. 3.4-25)"),
        "D": _var(sjk, terms.D, "kg m2", "inertia matrix D = D_tran + D_rot"),
        "h_tran": _var(sj, terms.h_tran, "N m",
                       "Coriolis and centrifugal torque, translational part (Eq. 3.4-26)"),
        "h_rot": _var(sj, terms.h_rot, "N m",
                      "Coriolis and centrifugal torque, rotational part (Eq. 3.4-27)"),
        "h": _var(sj, terms.h, "N m", "Coriolis and centrifugal torque h = h_tran + h_rot"),
        "c": _var(sj, terms.c, "N m", "gravity loading (Eq. 3.4-28)"),
        "tau": _var(sj, tau, "N m", "joint torque of the full model, D qdd + h + c (Eq. 3.4-24)"),
        "tau_simplified": _var(sj, tau_simplified, "N m",
                               "joint torque of the simplified model, D_s qdd + h_s + c"),
        "share_tran": _var(("element",), ranking.share_tran, "1",
                           "translational share sum|tran| / (sum|tran| + sum|rot|)"),
        "dominance": _var(("element",), np.array(ranking.dominance, dtype=str), "1",
                          "dominance class (translational, rotational, both, negligible)"),
        "chapter_dominance": _var(("element",),
                                  np.array([CHAPTER_DOMINANCE.get(lab, "") for lab in labels],
                                           dtype=str), "1",
                                  "dominance reported in Sec. 3.4.1 for the chapter's PUMA 560"),
        "choice": _var(("element",), np.array([choices[lab] for lab in labels], dtype=str), "1",
                       "part kept by the simplified model (tran, rot, both, none)"),
        "peak_tran": _var(("element",), ranking.peak_tran, "kg m2 (D) or N m (h)",
                          "peak |translational part| along the trajectory"),
        "peak_rot": _var(("element",), ranking.peak_rot, "kg m2 (D) or N m (h)",
                         "peak |rotational part| along the trajectory"),
        "peak_total": _var(("element",), ranking.peak_total, "kg m2 (D) or N m (h)",
                           "peak |translational + rotational| along the trajectory"),
        "element_scale": _var(("element",), ranking.scale, "kg m2 (D) or N m (h)",
                              "scale of the negligibility test: peak sqrt(D_ii D_jj) or |tau_i|"),
        "tau_error_peak": _var(("joint",), np.array(error["peak_abs_error"]), "N m",
                               "peak |tau_simplified - tau|"),
        "tau_error_rms": _var(("joint",), np.array(error["rms_error"]), "N m",
                              "RMS of |tau_simplified - tau|"),
        "tau_peak": _var(("joint",), np.array(error["peak_tau"]), "N m", "peak |tau|"),
        "tau_error_relative_peak": _var(("joint",), np.array(error["relative_peak_error"]), "1",
                                        "peak |tau_simplified - tau| / peak |tau|"),
        "tau_error_relative_rms": _var(("joint",), np.array(error["relative_rms_error"]), "1",
                                       "RMS |tau_simplified - tau| / peak |tau|"),
        "dh_d": _var(("joint",), robot.d, "m", "DH link offset d"),
        "dh_a": _var(("joint",), robot.a, "m", "DH link length a"),
        "dh_alpha": _var(("joint",), robot.alpha, "rad", "DH twist angle alpha"),
        "dh_offset": _var(("joint",), robot.offset, "rad", "joint angle offset, theta = q + offset"),
        "link_mass": _var(("joint",), robot.mass, "kg", "link mass"),
        "link_com": _var(("joint", "xyz"), robot.com, "m", "centre of mass in link frame"),
        "link_inertia": _var(("joint", "xyz", "xyz_k"), robot.inertia, "kg m2",
                             "inertia tensor about the centre of mass, link-frame axes"),
        "q_min": _var(("joint",), robot.q_min, "rad", "lower joint position limit"),
        "q_max": _var(("joint",), robot.q_max, "rad", "upper joint position limit"),
        "qd_max": _var(("joint",), robot.qd_max, "rad s-1", "joint velocity limit"),
        "qdd_max": _var(("joint",), robot.qdd_max, "rad s-2", "joint acceleration limit"),
    }
    coords = {
        "setpoint": ("setpoint", np.arange(N), {"long_name": "set point index", "units": "1"}),
        "joint": ("joint", np.arange(1, n + 1), {"long_name": "joint (row of D)", "units": "1"}),
        "joint_k": ("joint_k", np.arange(1, n + 1),
                    {"long_name": "joint (column of D)", "units": "1"}),
        "element": ("element", np.array(labels, dtype=str),
                    {"long_name": "ranked element of D (i <= j) or h", "units": "1"}),
        "element_units": ("element", np.array(el_units, dtype=str),
                          {"long_name": "units of the element", "units": "1"}),
        "xyz": ("xyz", np.array(["x", "y", "z"]), {"long_name": "axis", "units": "1"}),
        "xyz_k": ("xyz_k", np.array(["x", "y", "z"]), {"long_name": "axis", "units": "1"}),
    }
    now = datetime.datetime.now(datetime.timezone.utc).replace(microsecond=0).isoformat()
    attrs = {
        "Conventions": CONVENTIONS,
        "title": f"G-D dominance analysis of {robot.name} along {Path(trajectory.source).name}",
        "source": f"gd-analyze {__version__}",
        "references": "Fu, Gonzalez & Lee (1987), Robotics, Sec. 3.4; Lee, Lee & Nigam (1983)",
        "history": f"{now} created by gd-analyze {__version__}",
        "gd_analyze_version": __version__,
        "robot": robot.name,
        "robot_description": robot.description,
        "robot_reference": robot.reference,
        "robot_source": robot.source,
        "robot_sha256": robot.sha256,
        "gravity": np.asarray(robot.gravity, dtype=float),
        "gravity_units": "m s-2",
        "dominance_threshold": ranking.dominance_threshold,
        "negligible_threshold": ranking.negligible_threshold,
        "input_file": Path(trajectory.source).name,
        "input_path": str(trajectory.source),
        "input_sha256": trajectory.sha256,
        "derivatives": trajectory.derivatives,
    }
    for key, value in (verification or {}).items():
        attrs[f"verification_{key}"] = value
    attrs.update(settings or {})
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


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


def open_results(path):
    """Open a results file written by :func:`write_dataset`.

    Parameters
    ----------
    path : str or os.PathLike
        The ``results.h5`` file.

    Returns
    -------
    xarray.Dataset
        Loaded into memory; the file is closed.

    Raises
    ------
    InputError
        If the file is missing or not a readable netCDF4/HDF5 file.
    """
    import xarray as xr

    from .errors import InputError

    if not os.path.isfile(path):
        raise InputError("no such file", path)
    try:
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            return ds.load()
    except (OSError, ValueError) as exc:
        raise InputError(f"not a gd-analyze results file: {exc}", path) from None
