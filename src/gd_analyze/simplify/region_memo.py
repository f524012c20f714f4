"""The region's certification and samples, each computed once per process.

A certification (:func:`gd_analyze.certify.certify.certify`, kept between runs where the
caller gives a store: :class:`Derivations`) and the region's samples (:func:`gd_analyze.certify.region.region_samples`) are
pure functions of the arm, the region, the torque floor and :data:`REGION_SAMPLES`, so a second
analysis of the same arm in one session (a payload sweep, a sweep after the main job, a test
run) does not repeat them. A trajectory model's sampled error needs only the samples, not the
certification's branch and bound; a certification after them reuses them, and one made first
draws them with their pairs' magnitudes (:func:`region_magnitudes`), which the region's
pre-screen reads afterwards.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..certify.certify import certify, pair_magnitudes_at
from ..certify.region import (
    REFINE_JOINTS,
    channel_values,
    region_samples,
    region_scale,
    sample_positions,
)
from .simplified import json_safe

if TYPE_CHECKING:                       # for the type hints only
    from ..certify.certify import PairBounds
    from ..certify.region import Region
    from ..dynamics.base_parameters import BaseParameters
    from ..model.robot import Robot

__all__ = ["REGION_SAMPLES", "Derivations", "UNKEPT", "fresh_certification", "certified",
           "region_values", "region_magnitudes", "region_key", "release"]

#: Positions sampled over the region for a model's sampled error (its velocity and
#: acceleration at the worst vertices).
REGION_SAMPLES = 1000

#: Certifications kept in this process (keyed by :func:`region_key`).
_CERTIFIED: dict = {}
#: The region samples kept in this process without a certification (the same key, floor 0).
_SAMPLED: dict = {}
#: The pairs' sampled magnitudes of the region samples (:func:`region_magnitudes`).
_MAGNITUDES: dict = {}
#: Entries each keeps (a 10-joint arm's channel values are about 300 MB).
_CERTIFIED_MAX = 2


def _keep(memo, key, make):
    """``memo[key]``, made first if absent; the oldest entry goes beyond :data:`_CERTIFIED_MAX`."""
    if key not in memo:
        while len(memo) >= _CERTIFIED_MAX:
            memo.pop(next(iter(memo)))
        memo[key] = make()
    return memo[key]


def release() -> None:
    """Forget the certifications, region samples and sampled magnitudes kept in this process.

    A later model of the same arm derives them again (or reads them from the derivation
    cache). :func:`gd_analyze.simplify.deploy.release` calls it: the main job releases them
    before the report of a long trajectory (the command line's before every report), as the
    samples' channel values of a 15-joint arm are about 415 MB, which would sit beside the
    report's own memory.

    Examples
    --------
    >>> release()
    >>> _CERTIFIED == _SAMPLED == _MAGNITUDES == {}
    True
    """
    for memo in (_CERTIFIED, _SAMPLED, _MAGNITUDES):
        memo.clear()


def region_key(robot: Robot, region: Region, torque_floor: float) -> str:
    """The in-process key of an arm's region: the SHA-256 of the arm, the region, the floor
    and :data:`REGION_SAMPLES`.

    Parameters
    ----------
    robot : Robot
        The arm (its whole description: geometry, inertial parameters, limits, drives).
    region : Region
        Its joint-limit region.
    torque_floor : float
        TAU [N m or N].

    Returns
    -------
    str
        64 hexadecimal digits.
    """
    import hashlib
    import json

    text = json.dumps(json_safe(robot.to_dict()), sort_keys=True)
    return hashlib.sha256(text.encode() + b"".join(
        np.ascontiguousarray(a, float).tobytes() for a in (
            region.q_min, region.q_max, region.qd_max, region.qdd_max,
            np.array([torque_floor, REGION_SAMPLES], float)))).hexdigest()


def fresh_certification(robot: Robot, base: BaseParameters, region: Region,
                        torque_floor: float = 0.0, samples: int = 1000, seed: int = 0,
                        values: tuple | None = None, drawn: tuple | None = None
                        ) -> PairBounds:
    """:func:`gd_analyze.certify.certify.certify` on samples the caller may have drawn.

    Parameters
    ----------
    robot, base, region, torque_floor, samples, seed
        As :func:`gd_analyze.certify.certify.certify` takes them: the arm, its b base
        parameters, the joint-limit region, the least scale [N m or N], the number of
        uniform position samples and their seed.
    values : tuple, optional
        Those samples already drawn (:func:`gd_analyze.certify.region.region_samples`),
        optionally followed by their sampled peaks.
    drawn : tuple, optional
        Without ``values``: the positions (B, n), their channel values and their sampled
        peaks (b, 3, n), completed here with the scale found over them
        (:func:`gd_analyze.certify.region.region_scale`, as
        :func:`gd_analyze.certify.region.region_samples` finds it).

    Returns
    -------
    PairBounds
        Each (base parameter, part) pair's proved bound over the region and the scale s_i
        [N m or N], as :func:`gd_analyze.certify.certify.certify` returns them.

    Notes
    -----
    Source: the bounds of :func:`gd_analyze.certify.certify.certify` (interval branch and
    bound on the Newton-Euler regressor recursion, Khalil & Kleinfinger 1987).
    """
    if values is None and drawn is not None:
        cols = np.flatnonzero(base.independent.reshape(-1))
        values = (drawn[0], drawn[1],
                  *region_scale(robot, region, cols, np.asarray(base.beta, float),
                                refine=int(robot.n <= REFINE_JOINTS), values=drawn[:2]),
                  drawn[2])
    return certify(robot, base, region, torque_floor=torque_floor, samples=samples, seed=seed,
                   values=values)


def _no_search(*args: Any, **kwargs: Any) -> tuple[None, str]:
    """No search kept.

    Parameters
    ----------
    *args
        As :class:`Derivations`' ``read_search`` takes them; unused.
    **kwargs
        Its ``screened``; unused.

    Returns
    -------
    tuple
        ``(None, "")``: no entry, nowhere.
    """
    return None, ""


def _no_keeping(*args: Any, **kwargs: Any) -> None:
    """Nothing kept.

    Parameters
    ----------
    *args
        As :class:`Derivations`' ``write_search``, ``made`` or ``claimed`` takes them; unused.
    **kwargs
        ``write_search``'s ``screened``; unused.
    """


@dataclass(frozen=True)
class Derivations:
    """Where a region's certification and the searches under it are kept between runs.

    The model building here is pure; the shell gives it a store (the derivation cache,
    :data:`gd_analyze.store.derivations.DERIVATIONS`) or none (:data:`UNKEPT`:
    everything computed afresh, once per process).

    Attributes
    ----------
    certification : callable
        ``certification(robot, base, region, torque_floor, samples, values, drawn)`` ->
        PairBounds: :func:`fresh_certification`'s result, from a store where an entry passes
        its checks.
    read_search : callable
        ``read_search(robot, region, tolerance, torque_floor, samples, n, b,
        screened=False)`` -> ``(found, where)``: a search's stored outcome (a dict of
        ``dropped`` (b, 3), ``whole`` (b,), ``exact_forms`` and ``pruned_forms``), a reason
        (str) where an entry exists but is not used, or None; ``where`` names the entry for a
        warning. With ``screened``: the entry of the exact model the sampled pre-screen
        chose at that EPS (its pairs proved zero and its programs' forms), apart from the
        searches'.
    write_search : callable
        ``write_search(robot, region, tolerance, torque_floor, samples, dropped, whole,
        exact_forms, pruned_forms, screened=False)``: keep a search's outcome (with
        ``screened``, the pre-screen's exact model's).
    made : callable
        ``made(robot, region, torque_floor, samples, pb)``: told of each certification made
        or read in this process.
    claimed : callable
        ``claimed(model)``: told of a model whose region bound was proved in this process, so
        that its checks need not prove it again.
    """

    certification: Callable[..., PairBounds] = fresh_certification
    read_search: Callable[..., tuple[Any, str]] = _no_search
    write_search: Callable[..., None] = _no_keeping
    made: Callable[..., None] = _no_keeping
    claimed: Callable[..., None] = _no_keeping


#: Nothing kept between runs.
UNKEPT = Derivations()


def certified(robot: Robot, base: BaseParameters, region: Region,
              torque_floor: float = 0.0, derive: Derivations = UNKEPT) -> PairBounds:
    """:func:`gd_analyze.certify.certify.certify` of an arm, once per process, and
    kept between runs by ``derive``.

    Parameters
    ----------
    robot : Robot
    base : BaseParameters
    region : Region
    torque_floor : float, optional
        [N m or N].
    derive : Derivations, optional
        Where certifications are kept between runs (default: nowhere).

    Returns
    -------
    PairBounds
        Samples :func:`region_values` drew in this process are not drawn again. Where none
        were, the positions and their channel values are drawn here, without the scale
        search (an entry of the derivation cache brings its scale), and their pairs'
        magnitudes kept for :func:`region_magnitudes`: the certification's sampled peaks
        are their largest over the positions.
    """
    key = region_key(robot, region, 0.0)
    drawn = _SAMPLED.get(key)                                   # the same samples, if drawn
    if drawn is not None and key in _MAGNITUDES:                # and their sampled peaks
        drawn = (*drawn, _MAGNITUDES[key].max(axis=0))

    def make():
        fresh = None
        if drawn is None:
            q = sample_positions(region, REGION_SAMPLES)
            V = channel_values(robot, q, np.flatnonzero(base.independent.reshape(-1)))
            magnitudes = _keep(_MAGNITUDES, key, lambda: pair_magnitudes_at(
                V, np.asarray(base.beta, float), region.qd_max, region.qdd_max))
            fresh = (q, V, magnitudes.max(axis=0))
        pb = derive.certification(robot, base, region, torque_floor=torque_floor,
                                  samples=REGION_SAMPLES, values=drawn, drawn=fresh)
        derive.made(robot, region, torque_floor, REGION_SAMPLES, pb)  # a model built here
        return pb                                       # is checked without it again
    return _keep(_CERTIFIED, region_key(robot, region, torque_floor), make)


def region_values(robot: Robot, base: BaseParameters, region: Region
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The region's samples at :data:`REGION_SAMPLES` positions, torque floor 0.

    Parameters
    ----------
    robot, base, region
        The arm, its base parameters and its joint-limit region.

    Returns
    -------
    tuple
        :func:`gd_analyze.certify.region.region_samples`: positions, channel values,
        scale s_i and where it was found. A certification of the same arm and region with
        floor 0 already made in this process samples the same positions with the same seed
        and gives these values; it is read instead.
    """
    key = region_key(robot, region, 0.0)
    if key in _CERTIFIED:
        pb = _CERTIFIED[key]
        return pb.positions, pb.values, pb.scale, pb.scale_state
    return _keep(_SAMPLED, key, lambda: region_samples(robot, base, region, REGION_SAMPLES))


def region_magnitudes(robot: Robot, base: BaseParameters, region: Region) -> np.ndarray:
    """Each pair's largest |contribution| at each of :func:`region_values`' positions, once
    per process.

    Parameters
    ----------
    robot, base, region
        The arm, its base parameters and its joint-limit region.

    Returns
    -------
    ndarray, shape (B, b, 3, n)
        :func:`gd_analyze.certify.certify.pair_magnitudes_at` of the samples [N m or
        N]; a certification of the region made afterwards in this process takes their
        largest over the positions as its sampled peaks instead of computing them again.
    """
    def make():
        V = region_values(robot, base, region)[1]
        return pair_magnitudes_at(V, np.asarray(base.beta, float), region.qd_max,
                                  region.qdd_max)
    return _keep(_MAGNITUDES, region_key(robot, region, 0.0), make)
