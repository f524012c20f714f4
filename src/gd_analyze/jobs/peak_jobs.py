"""The simplification's peak passes, started beside the main job's G-D pass.

The pruned recursive model needs the peaks of every base parameter's part contributions on
the trajectory (unless it is pruned on bounds proved over the joint-limit region:
:func:`proves_over_region`), the explicit model the peaks of its atoms: both depend on q, qd,
qdd only, and both run compiled kernels that release the GIL. :func:`start_peaks` submits
them to a thread pool before the pass over the G-D terms, which runs meanwhile; the simplification
(:func:`gd_analyze.jobs.analyze.analysis_pass`) then takes their results. A model proved over
the region needs no peaks but the region's certification and searches, which depend on the
robot and the options only: on a long trajectory :func:`region_job` makes them on a thread of
its own beside the pass too. Nothing here prints; only the derivation cache is written (by the region's searches,
as they do after the pass).
"""

from __future__ import annotations

import threading
from concurrent.futures import Future
from typing import TYPE_CHECKING

import numpy as np

from ..certify.regressor_bounds import joint_sum_arithmetic
from ..dynamics.base_parameters import base_parameters
from ..errors import InputError
from ..simplify.deploy import guarantee_region, region_searches, robot_region
from ..simplify.explicit_model import LADDER
from ..simplify.region_memo import UNKEPT, Derivations
from ..store import explicit_cache
from ..symbolic.explicit import term_peaks
from ..symbolic.explicit_estimate import EXPENSIVE_TERMS, MAX_TERMS, estimate_terms
from ..symbolic.pruning import contribution_peaks
from . import compile_ahead

if TYPE_CHECKING:
    from ..model.robot import Robot
    from ..simplify.deploy import RegionSearches
    from ..symbolic.explicit import Term
    from .options import SimplifyOptions


__all__ = ["derives_explicit", "proves_over_region", "contribution_job", "explicit_job",
           "region_job", "start_peaks", "REGION_BESIDE_SETPOINTS"]

#: Set points from which the region's searches run beside the pass over the G-D terms: below
#: it the pass is too short to hide them (a few milliseconds against about a second), and the
#: deployment makes them after it, without a thread's switching.
REGION_BESIDE_SETPOINTS = 65_536


def derives_explicit(robot: Robot, options: SimplifyOptions) -> bool:
    """Whether the main job derives the explicit G-D model.

    Parameters
    ----------
    robot : Robot
        The arm.
    options : SimplifyOptions
        ``rule``, ``explicit`` and ``form`` of the command line.

    Returns
    -------
    bool
        True when the chapter rule or ``form="explicit"`` asks for it, when ``explicit`` is
        ``"always"``, or (``"auto"``) when it may be deployed (``form`` is not
        ``"recursive"``) and its estimated size is cheap (at most
        :data:`~gd_analyze.symbolic.explicit_estimate.EXPENSIVE_TERMS` terms by
        :func:`~gd_analyze.symbolic.explicit_estimate.estimate_terms`).

    Raises
    ------
    InputError
        Where it is asked for and estimated above
        :data:`~gd_analyze.symbolic.explicit_estimate.MAX_TERMS` terms (its expansion would
        run for hours), naming the option that asks for it and the recursive form instead.
    """

    rule, explicit, form = options.rule, options.explicit, options.form
    asked, fix = (("--rule chapter", "--rule budget --explicit never") if rule == "chapter" else
                  ("--form explicit", "--form recursive") if form == "explicit" else
                  ("--explicit always", "--explicit never") if explicit == "always" else ("", ""))
    terms = estimate_terms(robot)
    if asked and terms > MAX_TERMS:
        raise InputError(f"the explicit model of {robot.name} is estimated at {terms:,} terms, "
                         f"above the limit of {MAX_TERMS:,}: use the recursive form ({fix})", column=asked)
    return bool(asked) or explicit == "auto" and form != "recursive" and terms <= EXPENSIVE_TERMS


def proves_over_region(robot: Robot, options: SimplifyOptions) -> bool:
    """Whether the main job prunes the recursive model on bounds proved over the robot's
    joint-limit region, as :func:`gd_analyze.simplify.form_choice.deploy` decides it.

    Parameters
    ----------
    robot : Robot
        The arm.
    options : SimplifyOptions
        ``rule``, ``guarantee`` and ``region`` of the command line.

    Returns
    -------
    bool
        True under the budget rule, unless ``guarantee`` is ``"trajectory"``, when the robot
        has a region (:func:`gd_analyze.simplify.deploy.robot_region`). The model then needs
        no contribution peaks on the trajectory.
    """

    return (options.rule == "budget" and options.guarantee != "trajectory"
            and robot_region(robot, getattr(options, "region", None))[0] is not None)


def contribution_job(robot, q, qd, qdd, peaks=True):
    """The base parameters and their contribution peaks on a trajectory.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q, qd, qdd : ndarray, shape (N, n)
        The trajectory [rad, rad/s, rad/s^2; m, m/s, m/s^2].
    peaks : bool, optional
        False: the base parameters only (a model proved over the region needs no peaks).

    Returns
    -------
    base : BaseParameters
        :func:`gd_analyze.dynamics.base_parameters.base_parameters` of the robot.
    peaks : tuple of ndarray or None
        :func:`gd_analyze.symbolic.pruning.contribution_peaks`: tau_peak (n,), peak
        (b, 3, n), whole_peak (b, n) [N m or N]; None if not asked for.

    Notes
    -----
    What :func:`gd_analyze.simplify.deploy.build_recursive` takes as ``contributions``.
    Compiled or array code by the trajectory's length
    (:mod:`gd_analyze.dynamics.regressor_kernels`), releasing the GIL, so the
    main job runs it in a thread beside its pass over the G-D terms (:func:`start_peaks`).
    """

    base = base_parameters(robot)
    return base, contribution_peaks(robot, base, q, qd, qdd) if peaks else None


def explicit_job(robot: Robot, q: np.ndarray, qd: np.ndarray,
                 qdd: np.ndarray) -> tuple[Term, np.ndarray]:
    """The explicit terms of an arm and their atoms' peaks on a trajectory.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q, qd, qdd : ndarray, shape (N, n)
        The trajectory [rad, rad/s, rad/s^2; m, m/s, m/s^2].

    Returns
    -------
    terms : Term
        :func:`gd_analyze.store.explicit_cache.explicit_terms` of the robot.
    peaks : ndarray, shape (A, n)
        :func:`gd_analyze.symbolic.explicit.term_peaks` [N m or N].
    """
    terms, _ = explicit_cache.explicit_terms(robot)
    return terms, term_peaks(terms, np.zeros(robot.n), q, qd, qdd, prismatic=robot.prismatic)


def region_job(recursive: Future, robot: Robot, options: SimplifyOptions,
               derive: Derivations = UNKEPT) -> RegionSearches:
    """The region searches of the main job's recursive model and its ladder.

    Parameters
    ----------
    recursive : Future
        :func:`contribution_job`'s, for the robot's base parameters (waited for).
    robot : Robot
        The arm, with n joints.
    options : SimplifyOptions
        EPS, TAU, ``guarantee`` and ``region`` of the command line; the model is proved over
        the region (:func:`proves_over_region`).
    derive : Derivations, optional
        Where certifications and searches are kept between runs (default nowhere).

    Returns
    -------
    RegionSearches
        :func:`gd_analyze.simplify.deploy.region_searches` at the model's EPS and the
        ladder's (:data:`gd_analyze.simplify.explicit_model.LADDER`), what
        :func:`gd_analyze.simplify.form_choice.deploy` would otherwise make after the pass.

    Raises
    ------
    ValueError
        If the tolerance is negative or not finite, or the robot has no region under the
        options.
    """
    region, missing, proved = guarantee_region(robot, options.guarantee, options.region)
    if region is None or not proved:
        raise ValueError(f"no region to prove the model over ({missing or options.guarantee})")
    return region_searches(robot, recursive.result()[0], region, options.tolerance,
                           options.torque_floor, LADDER, derive)


def start_peaks(pool, robot, trajectory, options, derive=UNKEPT):
    """Submit the simplification's peak passes to a pool of threads, and start the region
    searches on a thread of their own where the model is proved over the region.

    Parameters
    ----------
    pool : concurrent.futures.Executor
        Runs the jobs (threads: the kernels release the GIL).
    robot : Robot
        The arm.
    trajectory : Trajectory
        q, qd, qdd of shape (N, n).
    options : SimplifyOptions
        The simplification's options (:func:`derives_explicit`).
    derive : Derivations, optional
        Where certifications and searches are kept between runs (default nowhere).

    Returns
    -------
    dict of str to concurrent.futures.Future
        ``"recursive"``: :func:`contribution_job`, without the peaks where the model is
        proved over the region (:func:`proves_over_region`); ``"explicit"``:
        :func:`explicit_job`, only where the explicit model is derived; ``"region"``:
        :func:`region_job`, only where the model is proved over the region and the
        trajectory has at least :data:`REGION_BESIDE_SETPOINTS` set points (the
        certification, read back or made, then does not wait for the pass).
    """
    compile_ahead.start(joint_sum_arithmetic(robot.n))    # a first run: on the other core
    args = (robot, trajectory.q, trajectory.qd, trajectory.qdd)
    proved = proves_over_region(robot, options)
    jobs = {"recursive": pool.submit(contribution_job, *args, peaks=not proved)}
    if derives_explicit(robot, options):
        jobs["explicit"] = pool.submit(explicit_job, *args)
    if proved and trajectory.q.shape[0] >= REGION_BESIDE_SETPOINTS:
        # on a daemon thread of its own, as a Future: an interrupted run exits without waiting
        # for it (a pool's threads are joined at the interpreter's exit)
        jobs["region"] = future = Future()

        def work():
            if not future.set_running_or_notify_cancel():
                return
            try:
                future.set_result(region_job(jobs["recursive"], robot, options, derive))
            except BaseException as exc:    # noqa: BLE001  handed to the caller's result()
                future.set_exception(exc)
        threading.Thread(target=work, name="gd-region", daemon=True).start()
    return jobs
