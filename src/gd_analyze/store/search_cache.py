"""On-disk cache of the region model's searches, checked before it is used.

The model pruned over a joint-limit region (:func:`gd_analyze.jobs.deploy.region_model`)
comes out of two searches, each a pure function of the robot's parameters, the region, the
tolerance EPS, the torque floor and the package's code
(the one key of the derivation cache, :func:`gd_analyze.cache.cache_key`):

- which (base parameter, part) pairs to drop: a greedy search over the operation counts of
  candidate programs (:func:`gd_analyze.symbolic.pruning.prune_bounds`);
- per link, the form of the inertial moment (:data:`gd_analyze.symbolic.newton_euler.FORMS`)
  of the exact and of the pruned program: a greedy search over 1 + 2n programs each
  (:func:`gd_analyze.symbolic.recursive.recursive_program`).

Together they build some 45 programs for the PUMA 560 (about a third of the main job's time
without its report), so their outcome is kept in the derivation cache (:mod:`gd_analyze.cache`)
as ``search-<sha>.npz``, named by the SHA-256 of that key, beside the region's certification
(:mod:`.certification_cache`).

The cache is not trusted. An entry is used only if it is a regular file whose stored key
equals the key and whose checksum matches its arrays (:func:`gd_analyze.cache.read_entry`), its
arrays have the robot's shapes and types, its forms are names of FORMS, and its dropped pairs
pass the same budget check as a search's (each joint's bound at most EPS s_i on the proved
bounds, :func:`~gd_analyze.symbolic.pruning.prune_bounds` with ``chosen``). The programs
are then built from those choices, so they compute the same torques whatever the entry says:
a forged entry can make the model cost more, never err more than its stated bound. An entry
that fails gives one :class:`gd_analyze.cache.CacheWarning` line; the searches run again and the
entry is rewritten.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..cache import entry_path, read_entry, store
from ..symbolic.newton_euler import FORMS
from .certification_cache import certification_key

if TYPE_CHECKING:
    from ..certify.region import Region
    from ..model.robot import Robot

__all__ = ["search_key", "read_search", "write_search", "SEARCH_FIELDS"]

#: The arrays of an entry: the dropped pairs (b, 3) and parameters dropped whole (b,), and
#: per link the index in FORMS of the exact and of the pruned program's form (-1: no pruned
#: program, the exact one is deployed).
SEARCH_FIELDS = ("dropped", "whole", "exact_forms", "pruned_forms")
#: Layout of an entry.
_FORMAT = 1
#: Largest entry read [bytes] (the PUMA 560's is under 2 kB).
_MAX_BYTES = 2**20


def search_key(robot: Robot, region: Region, tolerance: float, torque_floor: float,
               samples: int) -> dict[str, Any]:
    """What an entry must store to be used.

    Parameters
    ----------
    robot : Robot
    region : Region
    tolerance : float
        EPS.
    torque_floor : float
        [N m or N].
    samples : int
        The certification's sampled positions.

    Returns
    -------
    dict
        The certification's key (:func:`.certification_cache.certification_key`) of kind
        ``search``, with the tolerance and this format.
    """
    return certification_key(robot, region, {"torque_floor": float(torque_floor),
                                             "samples": int(samples), "seed": 0,
                                             "tolerance": float(tolerance),
                                             "search_format": _FORMAT}, "search")


def read_search(key: Mapping[str, Any], n: int, b: int) -> dict[str, Any] | str | None:
    """The stored searches of a key, or why they are not used.

    Parameters
    ----------
    key : dict
        From :func:`search_key`.
    n, b : int
        Joints and base parameters of the robot.

    Returns
    -------
    dict, str or None
        ``dropped`` (bool, (b, 3)), ``whole`` (bool, (b,)), ``exact_forms`` and
        ``pruned_forms`` (names of FORMS, length n; ``pruned_forms`` None when the exact
        program is deployed); a reason (one phrase) when the entry exists but is not used;
        None when there is none or caching is off. The budget check is the caller's
        (:func:`~gd_analyze.symbolic.pruning.prune_bounds` with ``chosen``).
    """

    path = entry_path(key)
    found = None if path is None else read_entry(path, key, SEARCH_FIELDS, _MAX_BYTES)
    if not isinstance(found, dict):
        return found
    shapes = {"dropped": (b, 3), "whole": (b,), "exact_forms": (n,), "pruned_forms": (n,)}
    kinds = {"dropped": "b", "whole": "b", "exact_forms": "i", "pruned_forms": "i"}
    if any(found[f].shape != shapes[f] or found[f].dtype.kind != kinds[f]
           for f in SEARCH_FIELDS):
        return "does not hold a search of this robot (arrays of other types or shapes)"
    exact, pruned = found["exact_forms"], found["pruned_forms"]
    none = bool((pruned == -1).all())
    if (exact < 0).any() or (exact >= len(FORMS)).any() or not (
            none or ((pruned >= 0).all() and (pruned < len(FORMS)).all())):
        return "holds forms that are not forms of the inertial moment"
    return {"dropped": found["dropped"].astype(bool), "whole": found["whole"].astype(bool),
            "exact_forms": tuple(FORMS[int(k)] for k in exact),
            "pruned_forms": None if none else tuple(FORMS[int(k)] for k in pruned)}


def write_search(key: Mapping[str, Any], dropped: np.ndarray, whole: np.ndarray,
                 exact_forms: Sequence[str], pruned_forms: Sequence[str] | None) -> None:
    """Keep the searches' outcome (silent when the cache is off or not writable).

    Parameters
    ----------
    key : dict
        From :func:`search_key`.
    dropped : ndarray of bool, shape (b, 3)
    whole : ndarray of bool, shape (b,)
    exact_forms : sequence of str, length n
        The exact program's forms (:attr:`~gd_analyze.symbolic.codegen.Program.forms`).
    pruned_forms : sequence of str or None
        The pruned program's, None when the exact program is deployed.
    """

    n = len(exact_forms)
    store(key, {
        "dropped": np.asarray(dropped, bool), "whole": np.asarray(whole, bool),
        "exact_forms": np.array([FORMS.index(f) for f in exact_forms], np.int64),
        "pruned_forms": np.array([FORMS.index(f) for f in pruned_forms] if pruned_forms
                                 else [-1] * n, np.int64)})
