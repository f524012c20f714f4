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

__all__ = ["build_recursive", "recursive_simplified", "replace_cost"]


def build_recursive(robot, q, qd, qdd, tolerance=DEFAULT_TOLERANCE, torque_floor=0.0,
                    ranking=None, trajectory_sha256="", provenance=None):
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
    from ..core.selection.budget import Selection
    from ..core.symbolic.base_parameters import base_parameters
    from ..core.symbolic.recursive_model import recursive_model

    base = base_parameters(robot)
    rec = recursive_model(robot, q, qd, qdd, tolerance, torque_floor, base=base)
    model = recursive_simplified(robot, rec, base, tolerance=tolerance,
                                 torque_floor=torque_floor, ranking=ranking,
                                 trajectory_sha256=trajectory_sha256, provenance=provenance)
    sel = Selection(rule="budget", tolerance=float(tolerance), choices=model.choices,
                    kept=None, scale=rec.scale, bound=rec.bound,
                    bound_by_kind={"D": rec.bound_by_part[0], "h": rec.bound_by_part[1],
                                   "c": rec.bound_by_part[2], "whole": rec.bound_by_part[3]},
                    element_bound=np.full(robot.n, np.nan))
    return model, sel


def recursive_simplified(robot, rec, base, tolerance=DEFAULT_TOLERANCE, torque_floor=0.0,
                         ranking=None, trajectory_sha256="", provenance=None):
    """A pruned recursive model as a :class:`SimplifiedModel`, its program and counts built.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    rec : RecursiveModel
        The pruned model (:func:`gd_analyze.core.symbolic.recursive_model.recursive_model`, or
        :func:`~gd_analyze.core.symbolic.recursive_model.sweep_recursive_model` for a sweep).
    base : BaseParameters
        The robot's base parameters, those of ``rec``.
    tolerance : float, optional
        EPS.
    torque_floor : float, optional
        TAU [N m].
    ranking : Ranking, optional
        For the thresholds s and e recorded with the model.
    trajectory_sha256 : str, optional
    provenance : dict, optional

    Returns
    -------
    SimplifiedModel
        Of the recursive form, ``validation`` empty, ``bound`` = ``rec.bound`` [N m];
        ``cost`` counted on its program (the exact recursive program when pruning would
        cost more, :func:`gd_analyze.core.symbolic.pruning.pruned_program`), and
        ``costs["exact recursive"]`` the exact recursive model's count.

    Notes
    -----
    Fu, Gonzalez & Lee (1987), Algorithm 3.1 on the base parameters (Khalil & Kleinfinger
    1987; Gautier 1990).
    """
    from ..core.model.drives import with_drives
    from ..core.selection.ranking import element_labels
    from ..core.symbolic.recursive import recursive_program

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
        costs={"exact recursive": exact}, program_cache=program)
    return replace_cost(model, program.cost())


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
