"""A model file's region guarantee, checked against its robot before any output states it.

A ``simplified_model.json`` states a guarantee: |tau_s - tau| <= bound_i <= EPS s_i at every
state of a region. Its numbers are the file's, and a file can be edited (or another model's
guarantee pasted in, its ``scale`` and ``bound`` multiplied by 100). :func:`check_guarantee`
recomputes what the claim rests on, from the model's robot, and refuses the file where the
claim fails, with one line naming the key:

- ``tolerance``, ``torque_floor`` (of a model with a guarantee): equal to the provenance's,
  the EPS and torque floor the model was built with, where it states them (evaluate's gate is
  EPS s_i: an EPS edited from 0.01 to 0.5 would loosen it 50 times, a torque floor raised to
  1e4 N m with every s_i set to it, far more);
- ``guarantee.q_min``, ``q_max``, ``qd_max``, ``qdd_max``: the region lies within the robot's
  own limits (a revolute joint without limits, or with more than a turn, has [-pi, pi]; a
  limit the robot does not give is any finite positive number);
- ``guarantee.scale_state``, ``guarantee.scale``: every state where s_i was found lies in the
  region, and |tau_i| there, recomputed with the robot's rigid links (drives' armature and
  friction left out, as s_i is defined)
  (:func:`gd_analyze.dynamics.dalembert.gd_terms`), equals s_i to
  :data:`SCALE_RTOL` of s_i, plus the round-off of the arm's largest s_i
  (:data:`~gd_analyze.simplify.guarantee.ROUND_OFF_EPS` machine epsilons), or s_i is
  the torque floor and |tau_i| is not above it;
- of a trajectory-kind guarantee, ``guarantee.scale_state`` and ``guarantee.scale``: the same
  but for the region (a trajectory has none) and with the robot as it is (its s_i is
  max(peak |tau_i| on the trajectories, torque floor), drives included): an s_i multiplied by
  100 loosens no gate. That the states are set points of the model's trajectory is checked
  where the trajectory is at hand (:func:`gd_analyze.jobs.evaluate.check_trajectory_claim`);
- ``bound``, ``recursive.bound`` (beside a region guarantee): equal to ``guarantee.bound``,
  so that the model's ``bound`` is the bound proved;
- ``guarantee.bound``: the bound is proved again for the model's dropped (base parameter,
  part) pairs: first on the trees of boxes stored with it (``guarantee.tilings``, and the
  pairs of trees of the decomposition, ``guarantee.decomposed_tilings``: the first links'
  pairs bounded on the first, the rest on the second, the two bounds added), each
  checked to tile the region (a bisection tree cut at the middles: the final boxes cover it
  without overlap) and every box's enclosures evaluated afresh, without search
  (:func:`gd_analyze.certify.certify.tilings_bound`; a tree that is not such a
  tiling proves nothing); then by a branch and bound on those pairs alone
  (:func:`gd_analyze.certify.certify.prove_dropped`, a fraction of a certification's
  cost when few parameters are dropped), and where that does not reach the stored bound, as the
  main job derived it (:func:`gd_analyze.certify.certify.region_bound`: the pairs'
  bounds and their joint sum on the region's certification, :func:`.certification_cache.certification`,
  through the derivation cache, whose entries are themselves re-derived, and the branch and
  bound on the joint sum with the budget EPS s_i), and the stored bound is not below it by
  more than :data:`BOUND_RTOL` of s_i;
- ``guarantee.bound_method`` (where stored): each joint's way of bounding
  (:data:`gd_analyze.certify.certify.BOUND_METHODS`) gives its stored bound, within
  :data:`BOUND_RTOL` of s_i, when derived again: on the stored trees
  (:func:`gd_analyze.certify.certify.tree_method_bounds`), else as the main job derived it
  (:func:`gd_analyze.certify.certify.method_bounds` of
  :func:`gd_analyze.certify.certify.region_trees`); "none" only where the bound is 0; and
  ``guarantee.joint_sum_arithmetic`` is the one the arm's joint sums are enclosed in
  (:func:`gd_analyze.certify.regressor_bounds.joint_sum_arithmetic`). A file without them
  (written before) is read, its bound checked as above. A model of the explicit form keeps
  every term (bound 0) only if its terms are the robot's full explicit model's
  (:func:`.explicit_cache.explicit_terms`);
- ``explicit_terms`` of a model of the chapter's rule, which states no bound: every term of the
  parts its choices keep (:func:`gd_analyze.simplify.budget.chapter_terms`), so that a pruned
  model whose guarantee was removed is not read as the chapter's.
"""

from __future__ import annotations

import hashlib
import json
from typing import TYPE_CHECKING

import numpy as np

from ..certify.certify import (
    method_bounds,
    prove_dropped,
    region_trees,
    tree_method_bounds,
    unproved_way,
)
from ..certify.region import Region
from ..certify.regressor_bounds import joint_sum_arithmetic
from ..dynamics.base_parameters import base_parameters
from ..dynamics.dalembert import gd_terms
from ..errors import InputError
from ..model.drives import rigid_links
from ..simplify.budget import chapter_terms
from ..simplify.guarantee import ROUND_OFF_EPS
from .certification_cache import certification, certification_key
from .explicit_cache import explicit_terms

if TYPE_CHECKING:                       # for the type hints only
    from ..certify.certify import PairBounds
    from ..model.robot import Robot
    from ..simplify.guarantee import Guarantee
    from ..simplify.simplified import SimplifiedModel

__all__ = ["check_guarantee", "check_region", "reproved_bound", "remember", "remember_claim", "SCALE_RTOL", "BOUND_RTOL", "REGION_RTOL",
           "CERTIFICATION_SAMPLES", "release"]

#: |tau_i| at the stored scale state must equal s_i to this share of s_i [1].
SCALE_RTOL = 1e-9
#: The stored bound may lie below the re-proved one by this share of s_i at most [1].
BOUND_RTOL = 1e-9
#: A region's limit may exceed the robot's by this share of the limit (or of the span) [1].
REGION_RTOL = 1e-9
#: Boxes of the quick proof on the dropped pairs alone
#: (:func:`gd_analyze.certify.certify.prove_dropped`) before the region's full
#: certification decides.
QUICK_BOXES = 1024
#: Positions the certification samples (the main job's, ``simplify.region_memo``).
CERTIFICATION_SAMPLES = 1000

#: Certifications kept in this process: certification key -> PairBounds.
_PROVED: dict = {}
_PROVED_MAX = 4


def check_region(robot: Robot, guarantee: Guarantee | None, torque_floor: float = 0.0,
                 path: str = "<model>") -> Region | None:
    """Refuse a region guarantee whose region or scale does not hold for the robot.

    Parameters
    ----------
    robot : Robot
        The model's robot, rebuilt from the file.
    guarantee : Guarantee or None
        The file's ``guarantee`` (:meth:`~gd_analyze.simplify.guarantee.Guarantee.from_dict`);
        nothing is checked for None. Of the trajectory kind, only its scale: |tau_i| of the
        robot (drives included, as that kind's s_i is measured) at each ``scale_state``.
    torque_floor : float, optional
        The model's least scale [N m or N].
    path : str, optional
        The file, for messages.

    Returns
    -------
    Region or None
        The guarantee's region, within the robot's limits; None for a trajectory kind.

    Raises
    ------
    InputError
        One line naming the key: the region outside the robot's limits (``guarantee.q_min``,
        ``q_max``, ``qd_max``, ``qdd_max``), a scale state outside the region
        (``guarantee.scale_state``) or an s_i that |tau_i| there does not reach
        (``guarantee.scale``).
    """
    if guarantee is None:
        return None
    region = _region_within_limits(robot, guarantee, path) if guarantee.proved else None
    _scale_reached(robot, guarantee, region, float(torque_floor), path)
    return region


def check_guarantee(model: SimplifiedModel, path: str = "<model>") -> None:
    """Refuse a model whose region guarantee does not hold for its own robot.

    Parameters
    ----------
    model : SimplifiedModel
        As read from the file (:meth:`~gd_analyze.simplify.simplified.SimplifiedModel.from_dict`).
    path : str, optional
        The file, for messages.

    Raises
    ------
    InputError
        One line naming the key (module docstring): a region outside the robot's limits, a
        scale not reached at its stored state (:func:`check_region`), a bound below the
        one re-proved for the model's dropped pairs (``guarantee.bound``), or ways of proving
        it that are not the arm's arithmetic, do not give it when derived again, or are stated
        for a model without a recursive form to derive them on (``guarantee.bound_method``);
        a model of the chapter's rule whose terms are not every term of the parts its choices
        keep (``explicit_terms``); a ``tolerance`` or ``torque_floor`` that is not the
        provenance's; beside a region guarantee, a ``bound`` or ``recursive.bound`` that is
        not ``guarantee.bound``.

    Notes
    -----
    A guarantee of kind ``"trajectory"`` is checked where its trajectory is at hand
    (:func:`gd_analyze.jobs.evaluate.coverage`, on the very file by SHA-256).
    """
    g = model.guarantee
    for name in ("tolerance", "torque_floor") if g is not None else ():  # the gate's EPS s_i
        if name in model.provenance and (built := model.provenance[name]) != getattr(model, name):
            raise InputError(f"is {getattr(model, name):g}, not the {built!r} the model was built "
                             f"with (provenance.{name})", path, column=name)
    if model.rule == "chapter" and model.terms is not None and not _same_terms(
            chapter_terms(explicit_terms(model.robot)[0], model.choices), model.terms):
        raise InputError("are not the chapter's model of the file's choices (the terms of the "
                         "parts its classes keep, nothing pruned)", path, column="explicit_terms")
    if g is not None and g.kind == "region":      # the bounds the file states beside it
        for column, stated in (("bound", model.bound),
                               ("recursive.bound", getattr(model.recursive, "bound", None))):
            if stated is not None and len(stated) and not np.array_equal(
                    np.asarray(stated, float), np.asarray(g.bound, float), equal_nan=True):
                raise InputError("is not guarantee.bound, the bound proved over the region",
                                 path, column=column)
    key = _claim_key(model) if g is not None and g.proved and model.recursive is not None else None
    if key in _PROVED_CLAIMS:
        return                              # the same claim, checked before in this process
    region = check_region(model.robot, g, model.torque_floor, path)
    if region is None:
        return
    bound, scale = (np.asarray(v, float) for v in (g.bound, g.scale))  # type: ignore[union-attr]  # the guarantee is not None here
    limit = bound + BOUND_RTOL * np.abs(scale)
    how = tuple(g.bound_method)  # type: ignore[union-attr]  # the guarantee is not None here
    if how and model.recursive is None:
        raise InputError("states how a recursive model's dropped pairs were bounded, but the "
                         "file holds no recursive model", path, column="guarantee.bound_method")
    if how and g.joint_sum_arithmetic != joint_sum_arithmetic(model.robot.n):  # type: ignore[union-attr]
        raise InputError(f"is not the joint sums' arithmetic on {model.robot.n} joints "
                         f"({joint_sum_arithmetic(model.robot.n)!r})", path,
                         column="guarantee.joint_sum_arithmetic")
    if model.recursive is not None and np.isfinite(bound).all() and (
            _tiled(model, region, limit) or not how and prove_dropped(
                model.robot, base_parameters(model.robot), region, model.recursive.dropped,
                limit, max_boxes=QUICK_BOXES)):
        _PROVED_CLAIMS.add(key)
        return                              # proved on the stored trees or the pairs' own boxes
    reproved = reproved_bound(model, region, path)
    short = ~(bound >= reproved - BOUND_RTOL * np.abs(scale))      # NaN never passes
    if short.any():
        j = int(np.argmax(np.where(short, reproved - bound, -np.inf)))
        raise InputError(f"is below the bound re-proved for its dropped terms (joint {j + 1}: "
                         f"{bound[j]:.4g} < {reproved[j]:.4g})", path, column="guarantee.bound")
    unmet = unproved_way(how, bound, _reproved(model, region)[1], limit) if how else None
    if unmet is not None:
        raise InputError(f"joint {unmet + 1}'s {how[unmet]!r} does not give its bound "
                         f"{bound[unmet]:.4g} when derived again", path,
                         column="guarantee.bound_method")
    if key is not None:
        _PROVED_CLAIMS.add(key)


def _tiled(model, region, limit):
    """Whether the guarantee's stored trees of boxes (``guarantee.tilings`` and the pairs
    ``guarantee.decomposed_tilings``), each checked to tile the region and evaluated afresh,
    give the bound within ``limit`` (n,) on every joint: where the guarantee states each
    joint's way (``guarantee.bound_method``), that way's bound on them from the first joint
    stating it (:func:`gd_analyze.certify.certify.tree_method_bounds`,
    :func:`gd_analyze.certify.certify.unproved_way`), else the least of the trees'
    (:func:`gd_analyze.certify.certify.tilings_bound`; NaN never passes); False without
    trees."""
    g = model.guarantee
    if not g.tilings and not g.decomposed:
        return False
    robot, how = model.robot, tuple(g.bound_method)
    ways = {m: j for j, m in reversed(list(enumerate(how)))}      # each way's first joint
    found = tree_method_bounds(robot, base_parameters(robot), region,
                               np.asarray(model.recursive.dropped, bool), g.tilings,
                               g.decomposed, ways or None)
    if how:
        return unproved_way(how, np.asarray(g.bound, float), found, limit) is None
    return bool(np.all(np.minimum(found["joint sum"], found["decomposition"]) <= limit))


def remember_claim(model: SimplifiedModel) -> None:
    """Keep the region claim of a model built in this process, its bound proved as it was
    built, so that :func:`check_guarantee` does not prove it again.

    Parameters
    ----------
    model : SimplifiedModel
        Of the recursive form, its guarantee of kind ``"region"`` and its bound the one
        proved for its dropped pairs over that region
        (:func:`gd_analyze.certify.certify.region_bound`, as
        :func:`gd_analyze.simplify.deploy.region_model` derives it); other models are
        ignored.

    Notes
    -----
    The key is a digest of the whole claim (:func:`_claim_key`): a model whose robot, region,
    bound, scale, torque floor, dropped pairs or parameter values differ is checked afresh.
    """
    g = model.guarantee
    if g is not None and g.kind == "region" and model.recursive is not None:
        _PROVED_CLAIMS.add(_claim_key(model))


#: Digests of the claims (robot, region, dropped pairs, bound, scale) checked in this process
#: by :func:`check_guarantee`: the same claim, checked again for each trajectory of a sweep,
#: is not proved again. A digest of the whole claim: any other claim is proved afresh.
_PROVED_CLAIMS: set = set()


def _claim_key(model):
    """SHA-256 of everything a recursive model's region claim depends on: its robot, its
    guarantee (region, bound, scale and the states where s_i is reached), torque floor,
    dropped pairs and base parameter values."""
    text = json.dumps([model.robot.to_dict(), model.guarantee.to_dict(),
                       float(model.torque_floor),
                       np.asarray(model.recursive.dropped, bool).tolist(),
                       np.asarray(model.recursive.beta, float).tolist()],
                      sort_keys=True, default=repr)
    return hashlib.sha256(text.encode()).hexdigest()


def reproved_bound(model: SimplifiedModel, region: Region, path: str = "<model>") -> np.ndarray:
    """The bound of a model's dropped terms proved afresh over a region.

    Parameters
    ----------
    model : SimplifiedModel
        Of the recursive form (its ``recursive.dropped`` pairs), or of the explicit form with
        every term of the full explicit model.
    region : Region
    path : str, optional
        The file, for messages.

    Returns
    -------
    ndarray, shape (n,)
        Recursive form: :func:`gd_analyze.certify.certify.region_bound` of the dropped
        pairs with the budget EPS s_i, on the region's certification derived again: the
        least of the largest over the certification's boxes of the sum of the dropped pairs'
        bounds there or of their joint sum, and of the branch and bound on their joint sum
        [N m or N] (tau = Y_b beta is linear in the base parameters, Khalil & Kleinfinger
        1987); explicit form with nothing dropped: zeros.

    Raises
    ------
    InputError
        For an explicit model whose terms are not the full explicit model's (its bound cannot
        be proved over the region), key ``guarantee.bound``.
    """
    robot = model.robot
    if model.recursive is None:
        full, _ = explicit_terms(robot)
        mine = model.explicit_terms()
        if not _same_terms(full, mine):
            raise InputError("a region guarantee is proved for dropped (base parameter, part) "
                             "pairs or for the full explicit model, and this explicit model "
                             "keeps other terms: its bound cannot be proved", path,
                             column="guarantee.bound")
        return np.zeros(robot.n)
    return _reproved(model, region)[0]


#: The last re-derivation (:func:`_reproved`): claim key -> (bound, each way's bound).
_REPROVED: dict = {}


def _reproved(model, region):
    """:func:`reproved_bound` of a recursive model and each way's bound
    (:func:`gd_analyze.certify.certify.method_bounds`), the last kept."""
    key = _claim_key(model)
    if key not in _REPROVED:
        # the region's certification (certify.PairBounds), once per process
        proved = _proved_key(model.robot, region, float(model.torque_floor))
        if proved not in _PROVED:
            _keep(proved, certification(model.robot, base_parameters(model.robot), region,
                                        torque_floor=float(model.torque_floor),
                                        samples=CERTIFICATION_SAMPLES))
        pb = _PROVED[proved]
        dropped = np.asarray(model.recursive.dropped, bool)
        bound, trees = region_trees(model.robot, base_parameters(model.robot), region, pb, dropped,
                                    float(model.tolerance) * np.asarray(pb.scale, float))
        _REPROVED.clear()
        _REPROVED[key] = bound, method_bounds(pb, dropped, trees)
    return _REPROVED[key]


def _proved_key(robot, region, torque_floor, samples=CERTIFICATION_SAMPLES):
    return repr(certification_key(robot, region, {"torque_floor": float(torque_floor),
                                                  "samples": int(samples), "seed": 0}))


def remember(robot: Robot, region: Region, torque_floor: float, samples: int,
             pb: PairBounds) -> None:
    """Keep a certification made (or recomputed) in this process for the checks of
    :func:`check_guarantee`, so that a model built here is not certified again.

    Parameters
    ----------
    robot : Robot
    region : Region
    torque_floor : float
        [N m or N].
    samples : int
        The certification's uniform position samples (seed 0); kept only when they are
        :data:`CERTIFICATION_SAMPLES`.
    pb : PairBounds
        :func:`.certification_cache.certification`'s result for these inputs.
    """
    if int(samples) == CERTIFICATION_SAMPLES:
        _keep(_proved_key(robot, region, torque_floor), pb)


def release() -> None:
    """Forget the certifications kept in this process (:func:`remember`).

    A later check of a model derives its region's certification again, or reads it from the
    derivation cache. The main job releases them before the report of a long trajectory (the
    command line's before every report): a 15-joint arm's certification holds about 530 MB
    (its samples' channel values and the joint sums).

    Examples
    --------
    >>> release()
    >>> _PROVED
    {}
    """
    _PROVED.clear()


def _keep(key, pb):
    while len(_PROVED) >= _PROVED_MAX:
        _PROVED.pop(next(iter(_PROVED)))
    _PROVED[key] = pb


def _same_terms(a, b):
    """Whether two explicit models have the same terms (coefficients to 1e-12 relative)."""
    if a.C.shape != b.C.shape:
        return False
    same = all(np.array_equal(getattr(a, f), getattr(b, f))
               for f in ("kind", "part", "i", "j", "k", "K", "S"))
    scale = np.maximum(np.abs(a.C), 1e-300)
    return same and bool(np.all(np.abs(a.C - b.C) <= 1e-12 * scale))


def _region_within_limits(robot, g, path):
    """The guarantee's region, refused where it leaves the robot's limits."""
    n = robot.n
    q_min, q_max, qd_max, qdd_max = (np.asarray(v, float) for v in (g.q_min, g.q_max,
                                                                     g.qd_max, g.qdd_max))
    rev = ~np.asarray(robot.prismatic, bool)
    lo, hi = np.asarray(robot.q_min, float), np.asarray(robot.q_max, float)
    with np.errstate(invalid="ignore"):
        turn = rev & (~(np.isfinite(lo) & np.isfinite(hi)) | (hi - lo > 2 * np.pi))
    lo = np.where(np.isfinite(lo), lo, -np.inf)     # a full turn: the robot's own limits, or
    hi = np.where(np.isfinite(hi), hi, np.inf)      # [-pi, pi] (the region of the whole circle)
    lo, hi = np.where(turn, np.minimum(lo, -np.pi), lo), np.where(turn, np.maximum(hi, np.pi), hi)
    span = np.where(np.isfinite(hi - lo), hi - lo, 1.0)
    slack = REGION_RTOL * np.maximum(np.abs(span), 1e-300)
    for key, value, limit, sign in (("q_min", q_min, lo, -1), ("q_max", q_max, hi, 1)):
        bad = ~np.isfinite(value) | ~(sign * (value - limit) <= slack)
        if bad.any():
            j = int(np.argmax(bad))
            raise InputError(f"joint {j + 1}'s {value[j]:.6g} is {'above' if sign > 0 else 'below'}"
                             f" the robot's limit {limit[j]:.6g}: the region must lie within the "
                             "robot's limits", path, column=f"guarantee.{key}")
    if not np.all(q_min <= q_max):
        j = int(np.argmax(~(q_min <= q_max)))
        raise InputError(f"joint {j + 1}'s q_min is above its q_max", path,
                         column="guarantee.q_min")
    for key, value, limit in (("qd_max", qd_max, robot.qd_max),
                              ("qdd_max", qdd_max, robot.qdd_max)):
        limit = np.asarray(limit, float) if np.shape(limit) == (n,) else np.full(n, np.nan)
        cap = np.where(np.isfinite(limit), limit * (1 + REGION_RTOL), np.inf)
        bad = ~(np.isfinite(value) & (value > 0) & (value <= cap))
        if bad.any():
            j = int(np.argmax(bad))
            why = (f"above the robot's limit {limit[j]:.6g}" if np.isfinite(value[j])
                   and value[j] > 0 else "not a finite positive limit")
            raise InputError(f"joint {j + 1}'s {value[j]:.6g} is {why}: the region must lie "
                             "within the robot's limits", path, column=f"guarantee.{key}")
    return Region(q_min=q_min, q_max=q_max, qd_max=qd_max, qdd_max=qdd_max)


def _scale_reached(robot, g, region, torque_floor, path):
    """Refuse a scale s_i that |tau_i| at its stored state does not reach (a state in the
    region, or none for a trajectory kind's)."""
    state = np.asarray(g.scale_state, float).reshape(robot.n, -1)
    q, qd, qdd = np.split(state, 3, axis=1)
    if not (np.isfinite(state).all() and (region is None or region.contains(q, qd, qdd).all())):
        raise InputError("a state where s_i was found is not finite or lies outside the "
                         "guarantee's region", path, column="guarantee.scale_state")
    with np.errstate(all="ignore"):      # over R, the rigid links' (the base regressor's) torque
        tau = gd_terms(robot if region is None else rigid_links(robot), q, qd).tau(qdd)
    reached, scale = np.abs(np.diagonal(tau)), np.asarray(g.scale, float)
    # round-off of the arm's largest scale allowed, as every check of a bound allows it
    slack = ROUND_OFF_EPS * np.finfo(float).eps * float(np.nanmax(np.abs(scale), initial=0.0))
    ok = (np.abs(reached - scale) <= SCALE_RTOL * np.abs(scale) + slack) | (
        (scale == torque_floor) & (reached <= scale * (1 + SCALE_RTOL) + slack))
    if not ok.all():
        j = int(np.argmax(~ok))
        raise InputError(f"is not |tau_i| at its stored scale_state (joint {j + 1}: "
                         f"{scale[j]:.6g} stated, {reached[j]:.6g} recomputed with the robot"
                         + ("'s rigid links)" if region is not None else ", drives included)"),
                         path, column="guarantee.scale")
