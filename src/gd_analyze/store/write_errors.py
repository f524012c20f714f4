"""Write errors of an output location, as one line: a full disk, an HDF5 error.

:func:`writing` wraps the calls of a run that write its output: an :class:`OSError` of a write,
an error that a full disk caused anywhere in an exception's chain (h5py reports ENOSPC when
the file is closed, as another error), and an error the HDF5 library raised inside h5py or
h5netcdf become an :class:`~gd_analyze.errors.InputError` (exit status 2) naming the output
location. Before that, the h5netcdf files a failed close left half-open are marked closed, so
that their finalizers do not flush again into a file HDF5 has torn down (a SIGSEGV on a full
disk).
"""

from __future__ import annotations

import contextlib
import errno
import os
import sys
from collections.abc import Iterator

from ..errors import InputError

__all__ = ["write_error", "is_inside", "writing"]


def write_error(exc: OSError, path: str | os.PathLike[str]) -> InputError:
    """The one-line error of a failed write into an output location.

    Parameters
    ----------
    exc : OSError
        The error (ENOSPC reads "no space left on the device").
    path : str or os.PathLike
        The output location, as the message names it.

    Returns
    -------
    InputError
    """
    reason = exc.strerror or str(exc)
    if exc.errno == errno.ENOSPC:
        reason = "no space left on the device"
    return InputError(f"cannot write the output folder: {reason}", path)


def is_inside(name: str | bytes | os.PathLike[str] | os.PathLike[bytes],
              folder: str | os.PathLike[str]) -> bool:
    """Whether the path ``name`` is ``folder`` or under it (both made absolute, not resolved).

    Parameters
    ----------
    name : str, bytes or os.PathLike
    folder : str or os.PathLike

    Returns
    -------
    bool

    Examples
    --------
    >>> is_inside("/a/b/c", "/a/b"), is_inside("/a/bc", "/a/b")
    (True, False)
    """
    try:
        return os.path.commonpath([os.path.abspath(os.fsdecode(name)),
                                   os.path.abspath(folder)]) == os.path.abspath(folder)
    except (TypeError, ValueError):
        return False


@contextlib.contextmanager
def writing(target: str | os.PathLike[str],
            stage: str | os.PathLike[str] | None = None) -> Iterator[None]:
    """Report the write errors of the enclosed calls as "cannot write the output folder".

    Parameters
    ----------
    target : str or os.PathLike
        The output folder, as the message names it.
    stage : str or os.PathLike, optional
        The staging folder the calls write in: an :class:`OSError` naming a file outside it
        (a file the calls read) is not a write error and propagates unchanged.

    Raises
    ------
    InputError
        On an :class:`OSError` of a write (h5py's write errors name no file); on an error of
        the HDF5 library (an ``OSError`` or ``RuntimeError`` raised inside h5py or h5netcdf,
        such as the one a full disk gives when the file is closed); on any error that a full
        disk (ENOSPC, EDQUOT, EFBIG) caused.
    """
    try:
        yield
    except OSError as exc:
        names = [n for n in (exc.filename, exc.filename2) if n is not None]
        if stage is not None and names and not any(is_inside(n, stage) for n in names):
            raise
        _disarm_hdf5()
        raise write_error(_disk_full(exc) or exc, target) from None
    except Exception as exc:
        _disarm_hdf5()
        full = _disk_full(exc)
        if full is not None:
            raise write_error(full, target) from None
        if isinstance(exc, RuntimeError) and _from_hdf5(exc):
            raise InputError("cannot write the output folder: HDF5 error: "
                             + " ".join(str(exc).split())[:160], target) from None
        raise


def _disarm_hdf5():
    """After a failed write: mark the h5netcdf files open for writing that a failed close left
    half-open as closed, so that their finalizers (and xarray's) do not flush again into a file
    HDF5 has torn down: on a full disk that second flush was a SIGSEGV. (Every file a command
    writes is in its staging folder, which the failed run removes.)"""
    import gc

    h5netcdf = sys.modules.get("h5netcdf")
    if h5netcdf is None:
        return
    for obj in gc.get_objects():
        if (isinstance(obj, h5netcdf.File) and not getattr(obj, "_closed", True)
                and getattr(obj, "_mode", "r") != "r"):
            obj._closed = True      # h5netcdf's own flag: close() and __del__ then do nothing


_FULL = (errno.ENOSPC, getattr(errno, "EDQUOT", errno.ENOSPC), errno.EFBIG)


def _disk_full(exc):
    """The OSError of a full disk in the exception's chain (its causes and contexts), or None."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        seen.add(id(exc))
        if isinstance(exc, OSError) and (exc.errno in _FULL or "errno = 28" in str(exc)):
            return exc if exc.errno in _FULL else OSError(errno.ENOSPC, "")
        exc = exc.__cause__ or exc.__context__
    return None


def _from_hdf5(exc):
    """Whether the exception was raised inside h5py or h5netcdf (an HDF5 library error)."""
    import traceback

    frames = traceback.extract_tb(exc.__traceback__)
    return bool(frames) and any(part in frames[-1].filename.replace("\\", "/")
                                for part in ("h5py/", "h5netcdf/"))
