"""On-disk cache of the explicit model's derivation, which cannot lie.

The explicit model (:func:`gd_analyze.core.symbolic.explicit.derive`) is a pure function of the robot's
parameters and of the package's code, so an entry is named by the SHA-256 of its key: the
robot's parameters (its file's SHA-256 and the parameters actually used, so a robot carrying
a payload gets its own entry), the version and the package's sources (:func:`gd_analyze.files.package_sha256`) and the
derivation's settings. The folder is ``$GD_ANALYZE_CACHE_DIR`` if set, else
``$XDG_CACHE_HOME/gd-analyze`` or ``~/.cache/gd-analyze``; ``GD_ANALYZE_NO_CACHE=1`` disables
it.

The cache is not trusted (:mod:`.cache_files`). An entry (``explicit-<sha>.npz``, plain
arrays: nothing is ever unpickled) stores its key and a SHA-256 of its arrays, and is used only
if

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

import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._version import VERSION as __version__
from ..core.selection.simplified import parameters_sha256
from ..core.symbolic.explicit import Term, derive, model_terms
from ..core.symbolic.explicit_check import terms_disagreement
from ..errors import one_line
from ..files import package_sha256
from .cache_files import CacheWarning, cache_dir, entry_path, read_entry, write_entry

if TYPE_CHECKING:
    from ..core.model.robot import Robot
    from ..core.symbolic.explicit import Term

__all__ = ["cache_dir", "cache_path", "cache_key", "explicit_terms", "CacheWarning",
           "SELF_CHECK_TOLERANCE"]

_FIELDS = ("kind", "part", "i", "j", "k", "K", "S", "C")
#: Layout of an entry (its arrays and the stored key).
_FORMAT = 2
#: Largest relative difference of a cached entry's terms from the G-D engine.
SELF_CHECK_TOLERANCE = 1e-10
#: Largest entry read [bytes] (the PUMA 560's is about 100 kB).
_MAX_BYTES = 256 * 2**20


def cache_key(robot: Robot) -> dict[str, Any]:
    """What an entry of the robot must store to be used.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    dict
        ``format``; ``robot_sha256`` (its file's SHA-256), ``parameters_sha256`` (of the
        parameters used, :func:`gd_analyze.core.selection.simplified.parameters_sha256`); ``code`` (the
        package version and the SHA-256 of the package's sources); ``settings`` (what
        the derivation depends on besides the parameters: the joint types, the fields).
    """

    return {"format": _FORMAT, "robot_sha256": str(robot.sha256),
            "parameters_sha256": parameters_sha256(robot.to_dict()),
            "code": {"version": str(__version__), "sha256": package_sha256()},
            "settings": {"n": int(robot.n),
                         "prismatic": [bool(p) for p in robot.prismatic],
                         "offsets_in": "placements", "fields": list(_FIELDS)}}


def cache_path(robot: Robot) -> Path | None:
    """The robot's entry in the cache folder, or None when caching is disabled.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    pathlib.Path or None
        ``<folder>/explicit-<first 40 hex digits of the key's SHA-256>.npz``.
    """
    if cache_dir() is None:
        return None
    return entry_path("explicit", cache_key(robot))


#: The dtype of each stored array.
_DTYPES = {"kind": np.dtype("<U1"), "part": np.dtype("<U4"), "i": np.dtype("<i8"),
           "j": np.dtype("<i8"), "k": np.dtype("<i8"), "K": np.dtype("<i8"),
           "S": np.dtype(bool), "C": np.dtype("<f8")}


def _arrays(terms):
    """The Term's fields as the plain arrays an entry stores (fixed dtypes)."""
    return {f: np.asarray(getattr(terms, f), _DTYPES[f]) for f in _FIELDS}


def _read(path, key, robot):
    """The entry's terms, or the reason it is not used (a str)."""

    arrays = read_entry(path, key, _FIELDS, _MAX_BYTES)
    if arrays is None or isinstance(arrays, str):
        return arrays
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


    path = cache_path(robot)
    key = None if path is None else cache_key(robot)
    if path is not None:
        found = _read(path, key, robot)
        if found is not None and not isinstance(found, str):
            return found, 0.0
        if isinstance(found, str):
            warnings.warn(one_line(f"{path}: derivation cache entry {found}: ignored, the "
                                    "model is derived again"), CacheWarning, stacklevel=2)
    t0 = time.perf_counter()
    terms = model_terms(derive(robot))
    seconds = time.perf_counter() - t0
    if path is not None:
        write_entry(path, key, _arrays(terms))
    return terms, seconds
