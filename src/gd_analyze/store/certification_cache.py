"""On-disk caches of the region certification and of the region model's searches, checked before
they are used.

The certification of a joint-limit region (:func:`gd_analyze.certify.certify.certify`:
the proved bound of every (base parameter, part) pair, the scale s_i and where it is reached)
is a pure function of the robot's parameters, the region, the settings and the package's
code, so it is kept in the derivation cache (:mod:`gd_analyze.cache`) as ``region-<sha>.npz``
under the one key (:func:`gd_analyze.cache.cache_key`), as :mod:`.explicit_cache` keeps the
explicit model.

The cache is not trusted, and a bound is never read from it. An entry stores what lets the
certification be derived again without its searches: the scale s_i and the states where it was
found (the local maximisation over the region), the branch and bound's tree as its cuts
(per box evaluated, level by level: the joint it was halved along, or -1, and where), its
witnesses (per box and link, whether some final box's bound comes from that box's enclosure of
the link's columns: :attr:`gd_analyze.certify.certify.PairBounds.witness`) and the SHA-256 of
the final boxes' bounds (:func:`leaves_sha256`), with the number of boxes and the time it took.
It is used only if it is a regular file whose stored key equals the key and whose checksum
matches its arrays (:func:`gd_analyze.cache.read_entry`), and if:

- every scale state lies in the region, |tau_i| there equals s_i (or s_i is the torque floor),
  and s_i is at least the largest |tau_i| over the certification's own sampled positions
  (:func:`gd_analyze.certify.region.sample_positions`, deterministic; the velocity vertices
  are searched only at the positions where a cheap bound of |tau_i| exceeds s_i,
  :func:`gd_analyze.certify.region.worst_above`);
- the cuts tile the region (:func:`gd_analyze.certify.certify.tiling`: every cut point
  strictly inside its box, every box accounted for, in exact float comparisons: no box of zero
  volume, no overlap, the whole region covered);

then the enclosures the witnesses name are evaluated again, link by link over all boxes of the
tree at once (:func:`gd_analyze.certify.certify.certify_tree`), and each final box's bound is
the least of those evaluated on it and its ancestors: the bounds are derived, not read; no box
is searched for. The witnesses are not trusted either: whatever they name, a bound is the
enclosure of a box that contains the final box, so wrong witnesses only make bounds larger
(+inf where none is named), never smaller; the digest then differs and the entry is refused,
so a used entry gives a fresh certification's bounds bit for bit. Bounds or boxes written
into an entry (zero-volume boxes at the samples, bounds lowered to the sampled peaks,
overlapping boxes) are never read: such an entry does not match its checksum over the stored
fields, or its tree does not tile the region, and is certified again. A failed entry gives one
:class:`gd_analyze.cache.CacheWarning` line; the region is certified again and the entry rewritten.

The model pruned over a joint-limit region (:func:`gd_analyze.simplify.deploy.region_model`)
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
(above), and is not trusted either. A search entry is used only if it is a regular file whose stored
key equals the key and whose checksum matches its arrays (:func:`gd_analyze.cache.read_entry`), its
arrays have the robot's shapes and types, its forms are names of FORMS, and its dropped pairs
pass the same budget check as a search's (each joint's bound at most EPS s_i on the proved
bounds, :func:`~gd_analyze.symbolic.pruning.prune_bounds` with ``chosen``). The programs
are then built from those choices, so they compute the same torques whatever the entry says:
a forged entry can make the model cost more, never err more than its stated bound. An entry
that fails gives one :class:`gd_analyze.cache.CacheWarning` line; the searches run again and the
entry is rewritten.

Where the sampled pre-screen chooses the exact model instead
(:func:`gd_analyze.simplify.deploy.screened_exact`: the pairs proved identically zero left
out, no search), its two programs' forms are still searched; they are kept in an entry of the
same layout under a key of their own (``screened`` in :func:`search_key`), used only where its
dropped pairs are those very pairs and none is dropped whole, so that the model stays the
pre-screen's.
"""

from __future__ import annotations

import hashlib
from typing import TYPE_CHECKING, Any

import numpy as np

from ..cache import cache_key, entry_path, lookup, read_entry, store
from ..certify.certify import certify_tree
from ..certify.region import channel_values, sample_positions, worst_above
from ..dynamics.regressor_kernels import part_regressor
from ..simplify.region_memo import fresh_certification
from ..simplify.simplified import parameters_sha256
from ..symbolic.newton_euler import FORMS

if TYPE_CHECKING:
    from collections.abc import Mapping, Sequence

    from ..certify.region import Region
    from ..model.robot import Robot

__all__ = ["certification", "certification_key", "robot_inputs", "SELF_CHECK_TOLERANCE",
           "leaves_sha256", "search_key", "read_search", "write_search", "SEARCH_FIELDS"]

_FIELDS = ("scale", "scale_state", "boxes", "seconds", "split_joint", "split_at", "witness",
           "leaves_sha256")
#: Layout of an entry (3: the tree of boxes, no bounds; 4: with the witnesses and the
#: digest of the final boxes' bounds).
_FORMAT = 4
#: Slack of the self-check's comparisons, relative to s_i [1].
SELF_CHECK_TOLERANCE = 1e-9
#: Largest entry read [bytes] (the PUMA 560's is about 0.7 MB).
_MAX_BYTES = 256 * 2**20


def robot_inputs(robot: Robot) -> dict[str, Any]:
    """The robot's part of a cache key: its file's SHA-256, the SHA-256 of the parameters
    used (:func:`gd_analyze.simplify.simplified.parameters_sha256`), its joints.

    Parameters
    ----------
    robot : Robot
        The arm, as loaded (with its payload, if any).

    Returns
    -------
    dict
        ``robot_sha256``, ``parameters_sha256``, ``n``, ``prismatic``.
    """
    return {"robot_sha256": str(robot.sha256),
            "parameters_sha256": parameters_sha256(robot.to_dict()),
            "n": int(robot.n), "prismatic": [bool(p) for p in robot.prismatic]}


def certification_key(robot: Robot, region: Region, settings: dict[str, Any],
                      kind: str = "region") -> dict[str, Any]:
    """What an entry must store to be used.

    Parameters
    ----------
    robot : Robot
    region : Region
    settings : dict
        The certification's settings (torque floor [N m or N], samples, seed, ...), JSON
        numbers.
    kind : str, optional
        The entry's kind (``"search"`` for :func:`search_key`).

    Returns
    -------
    dict
        :func:`gd_analyze.cache.cache_key` of this format, the robot
        (:func:`robot_inputs`), the region (exact hex floats) and the settings.
    """
    return cache_key(kind, {
        "format": _FORMAT, **robot_inputs(robot),
        "region": {name: [float(x).hex()                 # exact text of the floats
                          for x in np.asarray(getattr(region, name), float).ravel()]
                   for name in ("q_min", "q_max", "qd_max", "qdd_max")},
        "settings": {k: (float(v).hex() if isinstance(v, float) else v)
                     for k, v in settings.items()}})


def _checked(robot, base, region, torque_floor, samples, seed, arrays, values=None):
    """The certification recomputed from the entry, or why the entry fails (a str)."""
    n = robot.n
    cols = np.flatnonzero(base.independent.reshape(-1))
    scale, state = arrays["scale"], arrays["scale_state"]
    shapes = {"scale": (n,), "scale_state": (n, 3 * n), "boxes": (), "seconds": ()}
    if any(arrays[f].shape != shapes[f] or arrays[f].dtype.kind != "f"
           for f in shapes if f != "boxes") or arrays["boxes"].dtype.kind != "i" \
            or arrays["boxes"].shape != () \
            or arrays["split_joint"].shape != (int(arrays["boxes"]),) \
            or arrays["leaves_sha256"].shape != () or arrays["leaves_sha256"].dtype.kind != "U":
        return "does not hold a certification of this robot (arrays of other types or shapes)"
    if not all(np.isfinite(arrays[f]).all() for f in shapes) or (scale < torque_floor).any() \
            or int(arrays["boxes"]) < 1 or float(arrays["seconds"]) < 0:
        return "holds values no certification gives (not finite, negative or too few boxes)"
    tol = SELF_CHECK_TOLERANCE * np.maximum(scale, 1e-300)          # (n,)
    if values is not None:
        q, V = values[0], values[1]
    else:
        q = sample_positions(region, samples, seed)
        V = channel_values(robot, q, cols)
    beta = np.asarray(base.beta, float)
    # the sampled torques above s_i (+ tol) only: searched where a cheap bound exceeds it
    value = worst_above(V, np.tile(beta, (3, 1)), region.qd_max, region.qdd_max, scale + tol)
    sq, sqd, sqdd = state[:, :n], state[:, n:2 * n], state[:, 2 * n:]
    tau = np.einsum("kpim,m->ki", part_regressor(robot, cols, sq, sqd, sqdd), beta)
    reached = np.abs(tau[np.arange(n), np.arange(n)])
    if not (region.contains(sq, sqd, sqdd).all()
            and np.all((np.abs(reached - scale) <= tol) | (scale == torque_floor))
            and np.all(scale >= value - tol)):
        return ("fails its self-check (its scale is not reached at its state, or is below "
                "the sampled torques)")
    try:
        pb = certify_tree(robot, base, region, arrays["split_joint"], arrays["split_at"],
                          (q, V, scale, state, *(values or ())[4:]),
                          torque_floor=torque_floor, seconds=float(arrays["seconds"]),
                          witness=arrays["witness"])
    except ValueError as exc:
        return f"fails its self-check (its tree of boxes {exc})"
    if leaves_sha256(pb.leaves) != str(arrays["leaves_sha256"]):
        return ("fails its self-check (the bounds derived on the boxes its witnesses name are "
                "not those it was stored with)")
    return pb


def leaves_sha256(leaves: np.ndarray) -> str:
    """SHA-256 of the final boxes' bounds, as stored with an entry.

    Parameters
    ----------
    leaves : ndarray, shape (b, 3, L, n)
        :attr:`gd_analyze.certify.certify.PairBounds.leaves` [N m or N].

    Returns
    -------
    str
        Hex digest of the C-ordered float64 bytes, with the shape.
    """
    a = np.ascontiguousarray(leaves, np.float64)
    return hashlib.sha256(repr(a.shape).encode() + a.tobytes()).hexdigest()


def certification(robot, base, region, torque_floor=0.0, samples=1000, seed=0, values=None,
                  drawn=None):
    """The region's certification, from the derivation cache or computed afresh.

    Parameters
    ----------
    robot, base, region, torque_floor, samples, seed
        As :func:`gd_analyze.certify.certify.certify` takes them: the arm, its base
        parameters, the joint-limit region, the least scale [N m or N], the number of
        uniform position samples and their seed.
    values : tuple, optional
        Those samples already drawn (:func:`gd_analyze.certify.region.region_samples`),
        for a certification computed afresh (their positions and channel values also for one
        recomputed from an entry), optionally followed by their sampled peaks
        (:func:`gd_analyze.certify.certify.pair_peaks_at`).
    drawn : tuple, optional
        Without ``values``: the positions (:func:`gd_analyze.certify.region.sample_positions`
        of ``samples`` and ``seed``), shape (B, n), their channel values
        (:func:`gd_analyze.certify.region.channel_values` of the independent columns) and
        their sampled peaks (b, 3, n) (:func:`gd_analyze.certify.certify.pair_peaks_at`),
        drawn by the caller. An entry is checked on them without drawing them again; a
        certification computed afresh completes them with the scale found over them
        (:func:`gd_analyze.certify.region.region_scale`, as
        :func:`gd_analyze.certify.region.region_samples` finds it), without the scale search
        an entry makes needless.

    Returns
    -------
    PairBounds
        As :func:`gd_analyze.certify.certify.certify` returns it; ``seconds`` is the
        time the certification took when it was computed.

    Warns
    -----
    CacheWarning
        Once, when the entry exists but is not used (module docstring); the region is then
        certified again and the entry rewritten.

    Notes
    -----
    Source: the bounds of :func:`gd_analyze.certify.certify.certify` (interval branch
    and bound on the Newton-Euler regressor recursion, Khalil & Kleinfinger 1987).
    """

    key = certification_key(robot, region, {"torque_floor": float(torque_floor),
                                            "samples": int(samples), "seed": int(seed)})
    # drawn samples: the check reads their positions, channel values and peaks (not a scale)
    checked = values if values is not None or drawn is None else \
        (drawn[0], drawn[1], None, None, drawn[2])
    found = lookup(key, _FIELDS, _MAX_BYTES,
                   lambda arrays: _checked(robot, base, region, float(torque_floor), samples,
                                           seed, arrays, checked),
                   "the region is certified again")
    if found is not None:
        return found
    pb = fresh_certification(robot, base, region, torque_floor, samples, seed, values, drawn)
    store(key, {"scale": np.asarray(pb.scale, float),
                "scale_state": np.asarray(pb.scale_state, float),
                "boxes": np.array(int(pb.boxes), np.int64),
                "seconds": np.array(float(pb.seconds)),
                "split_joint": np.asarray(pb.split_joint, np.int64),
                "split_at": np.asarray(pb.split_at, float),
                "witness": np.asarray(pb.witness, bool),
                "leaves_sha256": np.array(leaves_sha256(pb.leaves))})
    return pb


#: Layout of a search entry, and of the search that made it: 2 searches the pairs with the
#: decomposed bound too (:func:`gd_analyze.certify.certify.decomposed_bound`), so that an
#: entry of the search before (1) is not read as this one's.
_SEARCH_FORMAT = 2
#: Largest search entry read [bytes] (the PUMA 560's is under 2 kB).
_SEARCH_MAX_BYTES = 2**20


#: The arrays of an entry: the dropped pairs (b, 3) and parameters dropped whole (b,), and
#: per link the index in FORMS of the exact and of the pruned program's form (-1: no pruned
#: program, the exact one is deployed).
SEARCH_FIELDS = ("dropped", "whole", "exact_forms", "pruned_forms")


def search_key(robot: Robot, region: Region, tolerance: float, torque_floor: float,
               samples: int, screened: bool = False) -> dict[str, Any]:
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
    screened : bool, optional
        The entry of the exact model the sampled pre-screen chose at this EPS
        (:func:`gd_analyze.simplify.deploy.screened_exact`: no search, only its programs'
        forms to keep), apart from the searches' entry.

    Returns
    -------
    dict
        The certification's key (:func:`.certification_cache.certification_key`) of kind
        ``search``, with the tolerance and this format (and ``screened`` where True).
    """
    return certification_key(robot, region, {"torque_floor": float(torque_floor),
                                             "samples": int(samples), "seed": 0,
                                             "tolerance": float(tolerance),
                                             "search_format": _SEARCH_FORMAT,
                                             **({"screened": True} if screened else {})},
                             "search")


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
    found = None if path is None else read_entry(path, key, SEARCH_FIELDS, _SEARCH_MAX_BYTES)
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


def write_search(robot: Robot, region: Region, tolerance: float, torque_floor: float,
                 samples: int, dropped: np.ndarray, whole: np.ndarray,
                 exact_forms: Sequence[str], pruned_forms: Sequence[str] | None,
                 screened: bool = False) -> None:
    """Keep the searches' outcome at their :func:`search_key` (silent when the cache is off
    or not writable).

    Parameters
    ----------
    robot, region, tolerance, torque_floor, samples, screened
        As :func:`search_key` takes them.
    dropped : ndarray of bool, shape (b, 3)
    whole : ndarray of bool, shape (b,)
    exact_forms : sequence of str, length n
        The exact program's forms (:attr:`~gd_analyze.symbolic.codegen.Program.forms`).
    pruned_forms : sequence of str or None
        The pruned program's, None when the exact program is deployed.
    """

    n = len(exact_forms)
    store(search_key(robot, region, tolerance, torque_floor, samples, screened), {
        "dropped": np.asarray(dropped, bool), "whole": np.asarray(whole, bool),
        "exact_forms": np.array([FORMS.index(f) for f in exact_forms], np.int64),
        "pruned_forms": np.array([FORMS.index(f) for f in pruned_forms] if pruned_forms
                                 else [-1] * n, np.int64)})
