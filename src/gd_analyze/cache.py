"""The derivation cache: one folder, one key, entries checked and never trusted.

The cache holds results that are pure functions of their inputs and of the code that computes
them: the explicit G-D model (:mod:`gd_analyze.store.explicit_cache`), the region certification
and the region model's searches (:mod:`gd_analyze.store.certification_cache`) and the operation counts
(:mod:`gd_analyze.dynamics.opcount`). Every entry has one key (:func:`cache_key`): the
SHA-256 of the installed package's sources (:func:`gd_analyze.files.package_sha256`; no list
of "the modules a result depends on" to go stale) plus the inputs. Its folder is
:func:`gd_analyze.config.cache_dir`: ``$GD_ANALYZE_CACHE_DIR`` if set, else
``$XDG_CACHE_HOME/gd-analyze`` or ``~/.cache/gd-analyze``; ``GD_ANALYZE_NO_CACHE=1`` disables
it.

An entry is a ``.npz`` of plain arrays (nothing is ever unpickled) named by the SHA-256 of its
key, and stores the key and a SHA-256 of its arrays. :func:`read_entry` opens it without
following a symbolic link and without blocking on a FIFO, refuses anything but a regular file
of bounded size, and checks the key and the checksum; :func:`lookup` then hands the content to
the cache's own check, an independent computation, before it is used, and says in one warning
line why an entry is not. :func:`write_entry` writes atomically
(:func:`gd_analyze.files.atomic_path`: an unpredictable temporary name created exclusively, so
a planted symbolic link is never followed, then a rename over the entry, which replaces a link
at the entry's name, not its target; a FIFO or device there is never replaced). An unwritable
cache folder is silent.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import math
import os
import stat
import warnings
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from ._version import VERSION
from .config import cache_dir
from .errors import InputWarning, one_line
from .files import atomic_path, package_sha256

__all__ = ["CacheWarning", "cache_dir", "cache_key", "entry_path", "canonical", "checksum",
           "read_entry", "write_entry", "lookup", "store"]


class CacheWarning(InputWarning):
    """A cache entry that was ignored (unreadable, of another key, or failing its checks);
    the command line prints it as one ``gd-analyze: warning: ...`` line."""


def canonical(key: Mapping[str, Any]) -> str:
    """The key as canonical JSON text (sorted keys, no spaces).

    Parameters
    ----------
    key : dict
        JSON-serialisable.

    Returns
    -------
    str
    """
    return json.dumps(key, sort_keys=True, separators=(",", ":"))


def cache_key(kind: str, inputs: Mapping[str, Any]) -> dict[str, Any]:
    """The one key of an entry: its kind, the code (the package's version and the SHA-256 of
    its sources) and the inputs.

    Parameters
    ----------
    kind : str
        The kind of entry (``"explicit"``, ``"region"``, ``"search"``): the
        first part of its file name.
    inputs : dict
        Everything else the content depends on (JSON values).

    Returns
    -------
    dict
        ``{"kind", "code": {"version", "sha256"}, **inputs}``.
    """
    return {"kind": kind, "code": {"version": str(VERSION), "sha256": package_sha256()},
            **inputs}


def entry_path(key: Mapping[str, Any]) -> Path | None:
    """Where the entry of a key lives, or None when caching is disabled.

    Parameters
    ----------
    key : dict
        From :func:`cache_key`.

    Returns
    -------
    pathlib.Path or None
        ``<folder>/<kind>-<first 40 hex digits of the key's SHA-256>.npz``.
    """
    folder = cache_dir()
    if folder is None:
        return None
    digest = hashlib.sha256(canonical(key).encode()).hexdigest()
    return folder / f"{key['kind']}-{digest[:40]}.npz"


def checksum(arrays: Mapping[str, npt.NDArray[Any]], fields: Sequence[str]) -> str:
    """SHA-256 of arrays: each field's name, dtype, shape and bytes, in the given order.

    Parameters
    ----------
    arrays : mapping of str to ndarray
    fields : sequence of str

    Returns
    -------
    str
    """
    digest = hashlib.sha256()
    for f in fields:
        a = np.ascontiguousarray(arrays[f])
        digest.update(f"{f}:{a.dtype.str}:{a.shape};".encode())
        digest.update(a.tobytes())
    return digest.hexdigest()


class _Refused(ValueError):
    """An entry that is not read at all (its reason is the message)."""


def _load_stored(fh, names, max_bytes):
    """The arrays ``names`` of an ``.npz`` as :func:`write_entry` writes it, with bounded cost.

    Every member must be stored uncompressed (as :func:`numpy.savez` writes it) and its array
    header must describe no more bytes than the member holds, so that no entry ever makes more
    than ``max_bytes`` of memory: a 1 MB file of deflated zeros once inflated to 2 GiB.
    """
    import zipfile

    from numpy.lib import format as npy

    out, total = {}, 0
    with zipfile.ZipFile(fh) as z:
        for name in names:
            info = z.getinfo(f"{name}.npy")
            total += info.file_size
            if info.compress_type != zipfile.ZIP_STORED:
                raise _Refused("holds a compressed array (gd-analyze stores its entries "
                               "uncompressed)")
            if total > max_bytes:
                raise _Refused(f"holds more than {max_bytes} bytes of arrays")
            with z.open(info) as member:
                version = npy.read_magic(member)
                if version not in ((1, 0), (2, 0)):
                    raise _Refused(f"holds an array of format {version}")
                header = (npy.read_array_header_1_0 if version == (1, 0)
                          else npy.read_array_header_2_0)
                shape, fortran, dtype = header(member, max_header_size=4096)
                count = math.prod(int(d) for d in shape)
                if dtype.hasobject or count * dtype.itemsize > info.file_size:
                    raise _Refused(f"holds an array {name} larger than its file")
                data = member.read(count * dtype.itemsize)
                if len(data) != count * dtype.itemsize:
                    raise _Refused(f"holds a truncated array {name}")
            out[name] = np.frombuffer(bytearray(data), dtype).reshape(
                shape, order="F" if fortran else "C")
    return out


def read_entry(path: Path, key: Mapping[str, Any], fields: Sequence[str],
               max_bytes: int) -> dict[str, npt.NDArray[Any]] | str | None:
    """The stored arrays of an entry whose key and checksum match, or why it is not used.

    Parameters
    ----------
    path : pathlib.Path
    key : dict
        The key the entry must store.
    fields : sequence of str
        The arrays it must hold.
    max_bytes : int
        Largest file read [bytes].

    Returns
    -------
    dict of str to ndarray, str or None
        The arrays; a reason (one phrase, e.g. ``"is not a regular file"``) when the entry
        exists but is not used; None when there is no entry.
    """
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | os.O_NONBLOCK)
    except OSError as exc:          # no entry (or no folder) is no warning
        return f"cannot be read ({exc.strerror or exc})" if os.path.lexists(path) else None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            return "is not a regular file"
        if info.st_size > max_bytes:
            return f"is larger than {max_bytes} bytes"
        with os.fdopen(fd, "rb") as fh:
            fd = None  # type: ignore[assignment]  # fh closes it now
            stored = _load_stored(fh, (*fields, "key", "checksum"), max_bytes)
    except _Refused as exc:
        return str(exc)
    except Exception as exc:  # noqa: BLE001 - any damage of the file: not used, computed again
        return f"cannot be read ({type(exc).__name__}: {' '.join(str(exc).split())[:120]})"
    finally:
        if fd is not None:
            os.close(fd)
    if str(stored["key"]) != canonical(key):
        return "was stored for another robot, code version or setting"
    arrays = {f: stored[f] for f in fields}
    if str(stored["checksum"]) != checksum(arrays, fields):
        return "does not match its checksum"
    return arrays


def write_entry(path: Path, key: Mapping[str, Any], arrays: Mapping[str, Any]) -> None:
    """Write an entry atomically (:func:`gd_analyze.files.atomic_path`); silent when the
    folder is not writable.

    Parameters
    ----------
    path : pathlib.Path
    key : dict
    arrays : dict of str to ndarray
        Plain (not object) arrays, stored in this order with their checksum.
    """
    with contextlib.suppress(OSError):        # read-only cache: computed again next time
        if os.path.lexists(path) and not (path.is_symlink() or path.is_file()):
            return      # a FIFO, a device, a folder: never replaced
        path.parent.mkdir(mode=0o700, parents=True, exist_ok=True)
        with atomic_path(path) as tmp, open(tmp, "wb") as fh:
            np.savez(fh, key=np.array(canonical(key)),
                     checksum=np.array(checksum(arrays, list(arrays))), **arrays)
            fh.flush()
            os.fsync(fh.fileno())


def lookup(key: Mapping[str, Any], fields: Sequence[str], max_bytes: int,
           check: Callable[[dict[str, npt.NDArray[Any]]], Any], again: str) -> Any:
    """The content of the key's entry once the cache's own check accepts it, or None.

    Parameters
    ----------
    key : dict
        From :func:`cache_key`.
    fields : sequence of str
        The arrays the entry must hold.
    max_bytes : int
        Largest file read [bytes].
    check : callable
        ``check(arrays)``: the content, checked against an independent computation, or the
        reason (a str, one phrase) it is not used.
    again : str
        What is done instead, for the warning (``"the model is derived again"``).

    Returns
    -------
    object or None
        What ``check`` returned; None when caching is off, there is no entry, or it failed.

    Warns
    -----
    CacheWarning
        Once, naming the entry and the reason, when the entry exists but is not used.
    """
    path = entry_path(key)
    found = None if path is None else read_entry(path, key, fields, max_bytes)
    if isinstance(found, dict):
        found = check(found)
    if isinstance(found, str):
        warnings.warn(one_line(f"{path}: derivation cache entry {found}: ignored, {again}"),
                      CacheWarning, stacklevel=3)
        return None
    return found


def store(key: Mapping[str, Any], arrays: Mapping[str, Any]) -> None:
    """:func:`write_entry` at the key's entry; nothing when caching is off.

    Parameters
    ----------
    key : dict
        From :func:`cache_key`.
    arrays : dict of str to ndarray
    """
    path = entry_path(key)
    if path is not None:
        write_entry(path, key, arrays)
