"""On-disk cache of the region certification, checked before it is used.

The certification of a joint-limit region (:func:`gd_analyze.core.selection.certify.certify`:
the proved bound of every (base parameter, part) pair, the scale s_i and where it is reached)
is a pure function of the robot's parameters, the region, the settings and the certifying
code, so it is kept in the derivation cache (:mod:`.cache_files`) as
``region-<sha>.npz``, named by the SHA-256 of that key, as :mod:`.explicit_cache` keeps the
explicit model.

The cache is not trusted. An entry is used only if it is a regular file whose stored key equals
the key and whose checksum matches its arrays (:func:`.cache_files.read_entry`), and if its
content passes a self-check against quantities computed afresh at the certification's own
sampled positions (:func:`gd_analyze.core.selection.region.sample_positions`, deterministic):

- its final boxes lie in the region, fill its volume and contain every sampled position;
- at every sampled position, each pair's bound on each box that contains it is at least the
  pair's |contribution| there (:func:`gd_analyze.core.selection.certify.pair_magnitudes_at`);
- |tau_i| at the stored ``scale_state`` equals s_i (or s_i is the torque floor), the state lies
  in the region, and s_i is at least the largest |tau_i| over the sampled positions.

The bound itself is not stored: it is the largest box bound and sampled peak, recomputed. The
bounds of another robot or region, or bounds scaled down, fail the check even with a forged key
and checksum; a bound lowered on a box between the sampled positions cannot be told from a
proved one without certifying again (only the user's own cache folder holds entries). A failed
entry gives one :class:`.cache_files.CacheWarning` line; the region is certified again and the
entry rewritten.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import one_line
from .cache_files import (
    CacheWarning,
    entry_path,
    read_entry,
    source_sha256,
    write_entry,
)

__all__ = ["certification", "certification_key", "SELF_CHECK_TOLERANCE"]

#: Modules whose code the certification depends on.
_CERTIFYING = ("core/selection/certify.py", "core/selection/region.py",
               "core/dynamics/regressor_bounds.py", "core/dynamics/balls.py",
               "core/dynamics/intervals.py", "core/symbolic/regressor_kernels.py",
               "core/symbolic/regressor_compiled.py", "core/symbolic/base_parameters.py")
_FIELDS = ("scale", "scale_state", "leaves", "leaf_boxes", "boxes", "seconds")
#: Layout of an entry.
_FORMAT = 1
#: Slack of the self-check's comparisons, relative to s_i [1].
SELF_CHECK_TOLERANCE = 1e-9
#: Largest entry read [bytes] (the PUMA 560's is about 0.7 MB).
_MAX_BYTES = 256 * 2**20


def _floats(a):
    """Exact text of floats (hex), for the key."""
    return [float(x).hex() for x in np.asarray(a, float).reshape(-1)]


def certification_key(robot, region, settings):
    """What an entry must store to be used.

    Parameters
    ----------
    robot : Robot
    region : Region
    settings : dict
        The certification's settings (torque floor [N m or N], samples, seed, ...), JSON
        numbers.

    Returns
    -------
    dict
        ``format``, ``robot_sha256``, ``parameters_sha256``, ``code`` (version and the SHA-256
        of the certifying modules), ``region`` (exact hex floats) and ``settings``.
    """
    from .._version import VERSION as __version__
    from ..core.selection.simplified import parameters_sha256

    return {"format": _FORMAT, "robot_sha256": str(robot.sha256),
            "parameters_sha256": parameters_sha256(robot.to_dict()),
            "code": {"version": str(__version__), "sha256": source_sha256(_CERTIFYING)},
            "region": {name: _floats(getattr(region, name))
                       for name in ("q_min", "q_max", "qd_max", "qdd_max")},
            "settings": {"n": int(robot.n), "prismatic": [bool(p) for p in robot.prismatic],
                         **{k: (float(v).hex() if isinstance(v, float) else v)
                            for k, v in settings.items()}}}


def _checked(robot, base, region, torque_floor, samples, seed, arrays):
    """The entry as PairBounds, or why it fails the self-check (a str)."""
    from ..core.selection.certify import PairBounds, pair_magnitudes_at
    from ..core.selection.region import channel_values, sample_positions, worst_states
    from ..core.symbolic.regressor_kernels import part_regressor

    n = robot.n
    cols = np.flatnonzero(base.independent.reshape(-1))
    b = cols.size
    scale, state = arrays["scale"], arrays["scale_state"]
    leaves, boxes = arrays["leaves"], arrays["leaf_boxes"]
    L = leaves.shape[2] if leaves.ndim == 4 else -1
    shapes = {"scale": (n,), "scale_state": (n, 3 * n), "leaves": (b, 3, L, n),
              "leaf_boxes": (L, 2, n), "boxes": (), "seconds": ()}
    if L < 1 or any(arrays[f].shape != shapes[f] or arrays[f].dtype.kind != "f"
                    for f in _FIELDS if f != "boxes") or arrays["boxes"].dtype.kind != "i" \
            or arrays["boxes"].shape != ():
        return "does not hold a certification of this robot (arrays of other types or shapes)"
    if not all(np.isfinite(arrays[f]).all() for f in _FIELDS) or (leaves < 0).any() \
            or (scale < torque_floor).any() or int(arrays["boxes"]) < L:
        return "holds values no certification gives (not finite, negative or too few boxes)"
    lo, hi = boxes[:, 0], boxes[:, 1]
    if (lo < region.q_min).any() or (hi > region.q_max).any() or (lo > hi).any():
        return "has boxes outside the region"
    span = region.q_max - region.q_min
    wide = span > 0
    volume = np.prod((hi - lo)[:, wide] / span[wide], axis=1).sum()
    if not abs(volume - 1.0) <= 1e-9:
        return f"has boxes that do not fill the region (volume {volume:.6g} of it)"
    tol = SELF_CHECK_TOLERANCE * np.maximum(scale, 1e-300)          # (n,)
    q = sample_positions(region, samples, seed)
    V = channel_values(robot, q, cols)
    beta = np.asarray(base.beta, float)
    mags = pair_magnitudes_at(V, beta, region.qd_max, region.qdd_max)      # (B, b, 3, n)
    inside = np.all((q[:, None, :] >= lo[None]) & (q[:, None, :] <= hi[None]), axis=2)
    if not inside.any(axis=1).all():
        return "has boxes that do not contain every sampled position"
    k, l_ = np.nonzero(inside)
    short = mags[k] - leaves[:, :, l_].transpose(2, 0, 1, 3)         # (P, b, 3, n)
    if (short > tol).any():
        return ("fails its self-check (a box's bound is below a pair's contribution at a "
                "sampled position in it)")
    value = worst_states(V, np.tile(beta, (3, 1)), region.qd_max, region.qdd_max)[0].max(0)
    sq, sqd, sqdd = state[:, :n], state[:, n:2 * n], state[:, 2 * n:]
    tau = np.einsum("kpim,m->ki", part_regressor(robot, cols, sq, sqd, sqdd), beta)
    reached = np.abs(tau[np.arange(n), np.arange(n)])
    if not (region.contains(sq, sqd, sqdd).all()
            and np.all((np.abs(reached - scale) <= tol) | (scale == torque_floor))
            and np.all(scale >= value - tol)):
        return ("fails its self-check (its scale is not reached at its state, or is below "
                "the sampled torques)")
    sampled = mags.max(axis=0)
    bound = np.maximum(leaves.max(axis=2), sampled)
    return PairBounds(bound=bound, sampled=sampled, scale=scale, scale_state=state,
                      positions=q, values=V, boxes=int(arrays["boxes"]), leaves=leaves,
                      leaf_boxes=boxes, seconds=float(arrays["seconds"]))


def certification(robot, base, region, torque_floor=0.0, samples=1000, seed=0, values=None):
    """The region's certification, from the derivation cache or computed afresh.

    Parameters
    ----------
    robot, base, region, torque_floor, samples, seed
        As :func:`gd_analyze.core.selection.certify.certify` takes them: the arm, its base
        parameters, the joint-limit region, the least scale [N m or N], the number of
        uniform position samples and their seed.
    values : tuple, optional
        Those samples already drawn (:func:`gd_analyze.core.selection.region.region_samples`),
        for a certification computed afresh.

    Returns
    -------
    PairBounds
        As :func:`gd_analyze.core.selection.certify.certify` returns it; ``seconds`` is the
        time the certification took when it was computed.

    Warns
    -----
    CacheWarning
        Once, when the entry exists but is not used (module docstring); the region is then
        certified again and the entry rewritten.

    Notes
    -----
    Source: the bounds of :func:`gd_analyze.core.selection.certify.certify` (interval branch
    and bound on the Newton-Euler regressor recursion, Khalil & Kleinfinger 1987).
    """
    from ..core.selection.certify import certify

    key = certification_key(robot, region, {"torque_floor": float(torque_floor),
                                            "samples": int(samples), "seed": int(seed)})
    path = entry_path("region", key)
    if path is not None:
        found = read_entry(path, key, _FIELDS, _MAX_BYTES)
        if isinstance(found, dict):
            found = _checked(robot, base, region, float(torque_floor), samples, seed, found)
            if not isinstance(found, str):
                return found
        if isinstance(found, str):
            warnings.warn(one_line(f"{path}: derivation cache entry {found}: ignored, the "
                                    "region is certified again"), CacheWarning, stacklevel=2)
    pb = certify(robot, base, region, torque_floor=torque_floor, samples=samples, seed=seed,
                 values=values)
    if path is not None:
        write_entry(path, key, {"scale": np.asarray(pb.scale, float),
                                "scale_state": np.asarray(pb.scale_state, float),
                                "leaves": np.asarray(pb.leaves, float),
                                "leaf_boxes": np.asarray(pb.leaf_boxes, float),
                                "boxes": np.array(int(pb.boxes), np.int64),
                                "seconds": np.array(float(pb.seconds))})
    return pb
