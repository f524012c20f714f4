"""On-disk cache of the explicit model's derivation, which cannot lie.

The explicit model (:func:`gd_analyze.symbolic.explicit.derive`) is a pure function of the
robot's parameters and of the package's code, so it is kept in the derivation cache
(:mod:`gd_analyze.cache`) under the one key (:func:`gd_analyze.cache.cache_key`): the code,
the robot's parameters (its file's SHA-256 and the parameters actually used, so a robot
carrying a payload gets its own entry) and the derivation's settings.

The cache is not trusted. An entry (``explicit-<sha>.npz``, plain
arrays: nothing is ever unpickled) stores its key and a SHA-256 of its arrays, and is used only
if

- it is a regular file (a symbolic link is not followed) that numpy reads without pickles,
- its stored key equals the robot's key and its checksum its arrays, and
- its terms, evaluated at a few fixed pseudo-random states, equal the G-D engine's D_tran,
  D_rot, h_tran, h_rot and c to 1e-10 of their scales
  (:func:`gd_analyze.symbolic.explicit_check.terms_disagreement`): the terms of another robot, or
  coefficients scaled, are caught even with a forged key and checksum.

Otherwise one warning line (:class:`CacheWarning`) says why, the model is derived again, and
the entry is rewritten atomically (:func:`gd_analyze.cache.write_entry`). An unwritable cache
folder is silent: the model is derived each time.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..cache import CacheWarning, lookup, store
from ..cache import cache_key as _key
from ..symbolic.explicit import Term, derive, model_terms
from ..symbolic.explicit_check import terms_disagreement
from .certification_cache import robot_inputs

if TYPE_CHECKING:
    from ..model.robot import Robot

__all__ = ["cache_key", "explicit_terms", "CacheWarning", "SELF_CHECK_TOLERANCE"]

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
        :func:`gd_analyze.cache.cache_key` of the robot's parameters
        (:func:`.certification_cache.robot_inputs`), this format and the derivation's settings
        (the fields).
    """
    return _key("explicit", {"format": _FORMAT, **robot_inputs(robot),
                             "offsets_in": "placements", "fields": list(_FIELDS)})


#: The dtype of each stored array.
_DTYPES = {"kind": np.dtype("<U1"), "part": np.dtype("<U4"), "i": np.dtype("<i8"),
           "j": np.dtype("<i8"), "k": np.dtype("<i8"), "K": np.dtype("<i8"),
           "S": np.dtype(bool), "C": np.dtype("<f8")}


def _checked(robot, arrays):
    """The entry's terms, or the reason they are not used (a str)."""
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


def explicit_terms(robot: Robot) -> tuple[Term, float]:
    """All terms of the robot's explicit G-D model, from the cache or derived afresh.

    Parameters
    ----------
    robot : Robot
        The arm.

    Returns
    -------
    terms : gd_analyze.symbolic.explicit.Term
        The terms (:func:`gd_analyze.symbolic.explicit.model_terms`).
    seconds : float
        Time the derivation took now (0.0 when read from the cache).

    Warns
    -----
    CacheWarning
        Once, when the robot's entry exists but is not used (module docstring); it is then
        derived again and rewritten.

    Notes
    -----
    Source: the derivation is :func:`gd_analyze.symbolic.explicit.derive` (Fu, Gonzalez & Lee,
    1987, Eqs. (3.4-24) to (3.4-28)); the self-check compares with
    :func:`gd_analyze.dynamics.dalembert.gd_terms`.
    """
    import time

    key = cache_key(robot)
    found = lookup(key, _FIELDS, _MAX_BYTES, lambda arrays: _checked(robot, arrays),
                   "the model is derived again")
    if found is not None:
        return found, 0.0
    t0 = time.perf_counter()
    terms = model_terms(derive(robot))
    seconds = time.perf_counter() - t0
    store(key, {f: np.asarray(getattr(terms, f), _DTYPES[f]) for f in _FIELDS})
    return terms, seconds
