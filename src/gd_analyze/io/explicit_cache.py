"""On-disk cache of the explicit model's derivation, which cannot lie.

The explicit model (:func:`gd_analyze.core.symbolic.explicit.derive`) is a pure function of the robot's
parameters and of the deriving code, so an entry is named by the SHA-256 of its key: the
robot's parameters (its file's SHA-256 and the parameters actually used, so a robot carrying
a payload gets its own entry), the version and source of the deriving modules and the
derivation's settings. The folder is ``$GD_ANALYZE_CACHE_DIR`` if set, else
``$XDG_CACHE_HOME/gd-analyze`` or ``~/.cache/gd-analyze``; ``GD_ANALYZE_NO_CACHE=1`` disables
it.

The cache is not trusted. An entry (``explicit-<sha>.npz``, plain arrays: nothing is ever
unpickled) stores its key and a SHA-256 of its arrays, and is used only if

- it is a regular file (a symbolic link is not followed) that numpy reads without pickles,
- its stored key equals the robot's key and its checksum its arrays, and
- its terms, evaluated at a few fixed pseudo-random states, equal the G-D engine's D_tran,
  D_rot, h_tran, h_rot and c to 1e-10 of their scales
  (:func:`gd_analyze.core.symbolic.explicit_check.terms_disagreement`): the terms of another robot, or
  coefficients scaled, are caught even with a forged key and checksum.

Otherwise one warning line (:class:`CacheWarning`) says why, the model is derived again, and
the entry is rewritten atomically: an unpredictable temporary name in the cache folder
(:func:`tempfile.mkstemp`, created exclusively, so a planted symbolic link is never followed),
then renamed over the entry (the rename replaces a link at the entry's name, not its target).
An unwritable cache folder is silent: the model is derived each time.
"""

from __future__ import annotations

import hashlib
import json
import os
import stat
import tempfile
import warnings
from importlib import resources
from pathlib import Path

import numpy as np

from ..errors import InputWarning, _one_line

__all__ = ["cache_dir", "cache_path", "cache_key", "explicit_terms", "CacheWarning",
           "SELF_CHECK_TOLERANCE"]

_DERIVING = ("core/symbolic/explicit.py", "core/symbolic/trigpoly.py")
_FIELDS = ("kind", "part", "i", "j", "k", "K", "S", "C")
#: Layout of an entry (its arrays and the stored key).
_FORMAT = 2
#: Largest relative difference of a cached entry's terms from the G-D engine.
SELF_CHECK_TOLERANCE = 1e-10
#: Largest entry read [bytes] (the PUMA 560's is about 100 kB).
_MAX_BYTES = 256 * 2**20


class CacheWarning(InputWarning):
    """A cache entry that was ignored (unreadable, of another key, or failing its checks);
    the command line prints it as one ``gd-analyze: warning: ...`` line."""


def cache_dir():
    """The cache folder, or None when caching is disabled.

    Returns
    -------
    pathlib.Path or None
    """
    if os.environ.get("GD_ANALYZE_NO_CACHE"):
        return None
    if os.environ.get("GD_ANALYZE_CACHE_DIR"):
        return Path(os.environ["GD_ANALYZE_CACHE_DIR"])
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "gd-analyze"


def cache_key(robot):
    """What an entry of the robot must store to be used.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    dict
        ``format``; ``robot_sha256`` (its file's SHA-256), ``parameters_sha256`` (of the
        parameters used, :func:`gd_analyze.core.selection.simplified.parameters_sha256`); ``code`` (the
        package version and the SHA-256 of the deriving modules' source); ``settings`` (what
        the derivation depends on besides the parameters: the joint types, the fields).
    """
    from .._version import __version__
    from ..core.selection.simplified import parameters_sha256

    code = hashlib.sha256()
    for name in _DERIVING:
        code.update(resources.files("gd_analyze").joinpath(name).read_bytes())
    return {"format": _FORMAT, "robot_sha256": str(robot.sha256),
            "parameters_sha256": parameters_sha256(robot.to_dict()),
            "code": {"version": str(__version__), "sha256": code.hexdigest()},
            "settings": {"n": int(robot.n),
                         "prismatic": [bool(p) for p in robot.prismatic],
                         "offsets_in": "placements", "fields": list(_FIELDS)}}


def _canonical(key):
    return json.dumps(key, sort_keys=True, separators=(",", ":"))


def cache_path(robot):
    """The robot's entry in the cache folder, or None when caching is disabled.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    pathlib.Path or None
        ``<folder>/explicit-<first 40 hex digits of the key's SHA-256>.npz``.
    """
    folder = cache_dir()
    if folder is None:
        return None
    digest = hashlib.sha256(_canonical(cache_key(robot)).encode()).hexdigest()
    return folder / f"explicit-{digest[:40]}.npz"


def _checksum(arrays):
    """SHA-256 of the arrays: each field's name, dtype, shape and bytes."""
    digest = hashlib.sha256()
    for f in _FIELDS:
        a = np.ascontiguousarray(arrays[f])
        digest.update(f"{f}:{a.dtype.str}:{a.shape};".encode())
        digest.update(a.tobytes())
    return digest.hexdigest()


#: The dtype of each stored array.
_DTYPES = {"kind": np.dtype("<U1"), "part": np.dtype("<U4"), "i": np.dtype("<i8"),
           "j": np.dtype("<i8"), "k": np.dtype("<i8"), "K": np.dtype("<i8"),
           "S": np.dtype(bool), "C": np.dtype("<f8")}


def _arrays(terms):
    """The Term's fields as the plain arrays an entry stores (fixed dtypes)."""
    return {f: np.asarray(getattr(terms, f), _DTYPES[f]) for f in _FIELDS}


def _read(path, key, robot):
    """The entry's terms, or the reason it is not used (a str)."""
    from ..core.symbolic.explicit import Term
    from ..core.symbolic.explicit_check import terms_disagreement

    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | os.O_NONBLOCK)
    except OSError as exc:          # no entry (or no folder) is no warning
        return f"cannot be read ({exc.strerror or exc})" if os.path.lexists(path) else None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            return "is not a regular file"
        if info.st_size > _MAX_BYTES:
            return f"is larger than {_MAX_BYTES} bytes"
        with os.fdopen(fd, "rb") as fh:
            fd = None
            with np.load(fh, allow_pickle=False) as z:
                stored = {name: z[name] for name in (*_FIELDS, "key", "checksum")}
    except Exception as exc:  # noqa: BLE001 - any damage of the file: not used, derived again
        return f"cannot be read ({type(exc).__name__}: {' '.join(str(exc).split())[:120]})"
    finally:
        if fd is not None:
            os.close(fd)
    if str(stored["key"]) != _canonical(key):
        return "was stored for another robot, code version or setting"
    arrays = {f: stored[f] for f in _FIELDS}
    if str(stored["checksum"]) != _checksum(arrays):
        return "does not match its checksum"
    U = arrays["C"].shape[:1]
    if any(arrays[f].dtype != _DTYPES[f] or arrays[f].shape[:1] != U
           or arrays[f].ndim != (2 if f == "K" else 1) for f in _FIELDS):
        return "does not hold explicit terms (arrays of other types or shapes)"
    terms = Term(**arrays)
    worst = terms_disagreement(robot, terms)
    if not worst <= SELF_CHECK_TOLERANCE:
        return (f"fails its self-check (its terms differ from the G-D engine by {worst:.2g} "
                f"of their scale at the check states)")
    return terms


def _write(path, key, terms):
    """Write the entry atomically (an unpredictable temporary name, then a rename); silent
    when the folder is not writable."""
    arrays = _arrays(terms)
    tmp = None
    try:
        path.parent.mkdir(mode=0o700, parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp",
                                   dir=path.parent)
        with os.fdopen(fd, "wb") as fh:
            np.savez(fh, key=np.array(_canonical(key)), checksum=np.array(_checksum(arrays)),
                     **arrays)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
        tmp = None
    except OSError:
        pass        # read-only cache: derive again next time
    finally:
        if tmp is not None:
            try:
                os.unlink(tmp)
            except OSError:
                pass


def explicit_terms(robot):
    """All terms of the robot's explicit G-D model, from the cache or derived afresh.

    Parameters
    ----------
    robot : Robot
        The arm.

    Returns
    -------
    terms : gd_analyze.core.symbolic.explicit.Term
        The terms (:func:`gd_analyze.core.symbolic.explicit.model_terms`).
    seconds : float
        Time the derivation took now (0.0 when read from the cache).

    Warns
    -----
    CacheWarning
        Once, when the robot's entry exists but is not used (module docstring); it is then
        derived again and rewritten.

    Notes
    -----
    Source: the derivation is :func:`gd_analyze.core.symbolic.explicit.derive` (Fu, Gonzalez & Lee,
    1987, Eqs. (3.4-24) to (3.4-28)); the self-check compares with
    :func:`gd_analyze.core.dynamics.dalembert.gd_terms`.
    """
    import time

    from ..core.symbolic.explicit import derive, model_terms

    path = cache_path(robot)
    key = None if path is None else cache_key(robot)
    if path is not None:
        found = _read(path, key, robot)
        if found is not None and not isinstance(found, str):
            return found, 0.0
        if isinstance(found, str):
            warnings.warn(_one_line(f"{path}: derivation cache entry {found}: ignored, the "
                                    "model is derived again"), CacheWarning, stacklevel=2)
    t0 = time.perf_counter()
    terms = model_terms(derive(robot))
    seconds = time.perf_counter() - t0
    if path is not None:
        _write(path, key, terms)
    return terms, seconds
