"""The recursive simplified model as the main job builds it (issue 17).

robot -> base parameters -> pruned recursive model within the budget on the trajectory ->
SimplifiedModel of the recursive form, with the exact recursive model's count beside it.
Nothing here prints or writes files.
"""

from __future__ import annotations

import numpy as np

from ..core.selection.budget import DEFAULT_TOLERANCE
from ..core.selection.ranking import DEFAULT_DOMINANCE, DEFAULT_NEGLIGIBLE
from ..core.selection.simplified import SimplifiedModel

__all__ = ["build_recursive", "replace_cost", "region_model", "trajectory_guarantee",
           "certified", "REGION_SAMPLES"]

#: Positions sampled over the region for a model's sampled error (its velocity and
#: acceleration at the worst vertices).
REGION_SAMPLES = 1000


#: Certifications kept in this process (keyed by the robot's parameters, the region and the
#: torque floor): a certification is a pure function of them, so a second analysis of the same
#: arm in one session (a payload sweep, a test run) does not repeat it.
_CERTIFIED = {}
_CERTIFIED_MAX = 2


def certified(robot, base, region, torque_floor=0.0):
    """:func:`gd_analyze.core.selection.certify.certify` of an arm, once per process.

    Parameters
    ----------
    robot : Robot
    base : BaseParameters
    region : Region
    torque_floor : float, optional
        [N m or N].

    Returns
    -------
    PairBounds
    """
    import hashlib
    import json

    from ..core.selection.certify import certify
    from ..core.selection.simplified import json_safe

    text = json.dumps(json_safe(robot.to_dict()), sort_keys=True)
    key = hashlib.sha256(text.encode() + b"".join(
        np.ascontiguousarray(a, float).tobytes() for a in (
            region.q_min, region.q_max, region.qd_max, region.qdd_max,
            np.array([torque_floor, REGION_SAMPLES], float)))).hexdigest()
    if key not in _CERTIFIED:
        while len(_CERTIFIED) >= _CERTIFIED_MAX:
            _CERTIFIED.pop(next(iter(_CERTIFIED)))
        _CERTIFIED[key] = certify(robot, base, region, torque_floor=torque_floor,
                                  samples=REGION_SAMPLES)
    return _CERTIFIED[key]


def region_model(robot, base, region, tolerance, torque_floor=0.0):
    """The recursive model pruned on bounds proved over a joint-limit region (issue 29).

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its base parameters.
    region : Region
        R = {q_min <= q <= q_max, |qd| <= qd_max, |qdd| <= qdd_max}.
    tolerance : float
        EPS.
    torque_floor : float, optional
        [N m or N].

    Returns
    -------
    model : RecursiveModel
        Dropped pairs whose proved bounds add up to at most EPS s_i per joint; ``scale`` is
        s_i over R, ``bound`` the sum of the dropped bounds [N m or N].
    guarantee : Guarantee
        Of kind ``"region"``: |tau_s - tau| <= bound_i <= EPS s_i at every state of R (up to
        round-off), with the sampled error, the scale and where it was found.

    Notes
    -----
    The triangle inequality over the dropped pairs of tau = Y_b beta (Khalil & Kleinfinger
    1987; Gautier 1990); bounds by :func:`gd_analyze.core.selection.certify.certify`.
    """
    from ..core.selection.certify import METHOD
    from ..core.selection.guarantee import Guarantee
    from ..core.selection.region import worst_states
    from ..core.symbolic.pruning import prune_bounds
    from ..core.symbolic.recursive_model import RecursiveModel

    pb = certified(robot, base, region, torque_floor)
    pr = prune_bounds(robot, base, pb.scale, pb.bound, pb.leaves.sum(axis=1).max(axis=1),
                      tolerance, pieces=pb.leaves)
    single = pr.dropped & ~pr.whole[:, None]
    by_part = np.stack([np.einsum("bln,b->ln", pb.leaves[:, p], single[:, p]).max(axis=0)
                        for p in range(3)]
                       + [np.einsum("bpln,b->ln", pb.leaves, pr.whole).max(axis=0)])
    safe = np.where(pb.scale > 0, pb.scale, 1.0)
    rel = np.where(pb.scale > 0, pb.bound / safe, np.where(pb.bound > 0, np.inf, 0.0)).max(2)
    rec = RecursiveModel(names=tuple(base.names()), beta=np.array(base.beta, float),
                         dropped=np.array(pr.dropped, bool), scale=np.array(pb.scale, float),
                         bound=np.array(pr.bound, float), bound_by_part=by_part,
                         relative_peak=rel)
    weights = np.asarray(base.beta, float)[None, :] * pr.dropped.T          # (3, b)
    err = worst_states(pb.values, weights, region.qd_max, region.qdd_max)[0].max(axis=0)
    guarantee = Guarantee(
        "region", float(tolerance), bound=rec.bound, scale=rec.scale, q_min=region.q_min,
        q_max=region.q_max, qd_max=region.qd_max, qdd_max=region.qdd_max,
        scale_state=pb.scale_state, sampled_error=err,
        method=f"{METHOD}; {pb.boxes} boxes, {pb.positions.shape[0]} sampled positions")
    return rec, guarantee


def trajectory_guarantee(robot, base, rec, tolerance, trajectory_sha256="", region=None,
                         region_missing=""):
    """The guarantee of a model pruned on a trajectory, its error sampled over the region.

    Parameters
    ----------
    robot : Robot
    base : BaseParameters
    rec : RecursiveModel
        The pruned model (its ``dropped`` pairs, ``bound`` and trajectory ``scale``).
    tolerance : float
        EPS.
    trajectory_sha256 : str, optional
    region : Region, optional
        The robot's region, on which the model's error is sampled (None: not sampled).
    region_missing : str, optional
        Why there is no region.

    Returns
    -------
    Guarantee
        Of kind ``"trajectory"``; ``region_sampled_error``: the largest error found over the
        region relative to s_i there (the largest |tau_i| found), or None.
    """
    from ..core.selection.guarantee import Guarantee
    from ..core.selection.region import worst_states

    sampled = None
    if region is not None:
        pb = certified(robot, base, region)
        weights = np.asarray(base.beta, float)[None, :] * np.asarray(rec.dropped).T
        err = worst_states(pb.values, weights, region.qd_max, region.qdd_max)[0].max(axis=0)
        sampled = err / np.where(pb.scale > 0, pb.scale, np.inf)
    return Guarantee("trajectory", float(tolerance), bound=np.asarray(rec.bound, float),
                     scale=np.asarray(rec.scale, float), trajectory_sha256=trajectory_sha256,
                     region_sampled_error=sampled, region_missing=region_missing,
                     method="sum of the dropped pairs' peak contributions on the trajectory "
                            "(triangle inequality)")


def build_recursive(robot, q, qd, qdd, tolerance=DEFAULT_TOLERANCE, torque_floor=0.0,
                    ranking=None, trajectory_sha256="", provenance=None, region=None,
                    sample_region=None, region_missing=""):
    """The pruned customized recursive Newton-Euler model within the budget (issue 17).

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q, qd, qdd : ndarray, shape (N, n)
        The trajectory [rad, rad/s, rad/s^2; m, m/s, m/s^2]: the bound holds on it.
    tolerance : float, optional
        EPS.
    torque_floor : float, optional
        TAU [N m].
    ranking : Ranking, optional
        For the thresholds s and e recorded with the model.
    trajectory_sha256 : str, optional
    provenance : dict, optional
    region : Region, optional
        Prune on bounds proved over this joint-limit region
        (:func:`gd_analyze.core.selection.certify.certify`) instead of the trajectory's peaks:
        the model's guarantee is then of kind ``"region"``.
    sample_region : Region, optional
        For a trajectory model: the region on which its error is sampled
        (``region_sampled_error`` of its guarantee).
    region_missing : str, optional
        Why a trajectory model has no region (a missing limit), for its guarantee.

    Returns
    -------
    model : SimplifiedModel
        Of the recursive form, ``validation`` empty; ``costs["exact recursive"]`` holds the
        exact recursive model's count.
    selection : Selection
        Its scale and bound, the bound split by part (``"D"``: inertial, ``"h"``: velocity,
        ``"c"``: gravity, ``"whole"``: parameters dropped whole) [N m].

    Notes
    -----
    Fu, Gonzalez & Lee (1987), Algorithm 3.1 on the base parameters (Khalil & Kleinfinger
    1987; Gautier 1990), pruned as :func:`gd_analyze.core.symbolic.recursive_model.recursive_model`.
    """
    from ..core.model.drives import with_drives
    from ..core.selection.budget import Selection
    from ..core.selection.ranking import element_labels
    from ..core.symbolic.base_parameters import base_parameters
    from ..core.symbolic.recursive import recursive_program
    from ..core.symbolic.recursive_model import recursive_model

    base = base_parameters(robot)
    if region is not None:
        rec, guarantee = region_model(robot, base, region, tolerance, torque_floor)
    else:
        rec = recursive_model(robot, q, qd, qdd, tolerance, torque_floor, base=base)
        guarantee = trajectory_guarantee(robot, base, rec, tolerance, trajectory_sha256,
                                         sample_region, region_missing)
    exact_program = recursive_program(robot, base.values)
    exact = with_drives(exact_program, robot).cost()
    program = with_drives(rec.program(robot, exact=exact_program), robot)
    choices = {lab: "both" for lab in element_labels(robot.n)}
    model = SimplifiedModel(
        robot=robot, choices=choices,
        dominance_threshold=float(getattr(ranking, "dominance_threshold", DEFAULT_DOMINANCE)),
        negligible_threshold=float(getattr(ranking, "negligible_threshold", DEFAULT_NEGLIGIBLE)),
        trajectory_sha256=trajectory_sha256, provenance=dict(provenance or {}), rule="budget",
        tolerance=float(tolerance), torque_floor=float(torque_floor), terms=None,
        recursive=rec, bound=[float(v) for v in rec.bound],
        costs={"exact recursive": exact}, program_cache=program, guarantee=guarantee)
    model = replace_cost(model, program.cost())
    sel = Selection(rule="budget", tolerance=float(tolerance), choices=choices, kept=None,
                    scale=rec.scale, bound=rec.bound,
                    bound_by_kind={"D": rec.bound_by_part[0], "h": rec.bound_by_part[1],
                                   "c": rec.bound_by_part[2], "whole": rec.bound_by_part[3]},
                    element_bound=np.full(robot.n, np.nan))
    return model, sel


def replace_cost(model, cost):
    """The model with its ``cost`` set (a new frozen value; its ``program_cache`` field, and
    so a program built before, is carried over by :func:`dataclasses.replace`).

    Parameters
    ----------
    model : SimplifiedModel
    cost : dict
        ``multiplications``, ``additions``, ``sin``, ``cos``.

    Returns
    -------
    SimplifiedModel
    """
    import dataclasses

    return dataclasses.replace(model, cost=dict(cost))
