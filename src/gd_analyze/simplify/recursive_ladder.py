"""The tolerance ladder of the pruned recursive model: its cost and error per EPS.

For each EPS of the ladder the recursive model is pruned as the deployed one is (on bounds
proved over the joint-limit region, or on the trajectory's peaks), its program built and
counted, and its torque error measured on the trajectory. Nothing here prints or writes files
(the region searches go through the derivation cache, :mod:`gd_analyze.store.certification_cache`).
"""

from __future__ import annotations

import concurrent.futures
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..symbolic.drive_regressor import with_drives
from ..symbolic.emit import python_function
from ..symbolic.recursive import recursive_program
from ..symbolic.recursive_model import recursive_model
from .deploy import region_search
from .region_memo import UNKEPT, Derivations

if TYPE_CHECKING:
    from ..certify.region import Region
    from ..dynamics.base_parameters import BaseParameters
    from ..model.robot import Robot
    from ..simplify.simplified import SimplifiedModel

__all__ = ["recursive_ladder", "LADDER_BLOCK"]

#: Set points whose torques each rung evaluates at once (the blocks of
#: :meth:`gd_analyze.simplify.simplified.SimplifiedModel.torque`).
LADDER_BLOCK = 8192


def recursive_ladder(robot: Robot, base: BaseParameters,
                     trajectory: tuple[np.ndarray, np.ndarray, np.ndarray],
                     tolerances: Sequence[float], torque_floor: float = 0.0,
                     region: Region | None = None,
                     contributions: tuple[np.ndarray, ...] | None = None,
                     deployed: SimplifiedModel | None = None,
                     pool: concurrent.futures.Executor | None = None,
                     derive: Derivations = UNKEPT) -> list[dict] | concurrent.futures.Future:
    """The pruned recursive model's cost and measured worst error at each tolerance EPS.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its b base parameters.
    trajectory : (ndarray, ndarray, ndarray)
        q, qd, qdd, each of shape (N, n) [rad, rad/s, rad/s^2; m, m/s, m/s^2].
    tolerances : sequence of float
        EPS of each rung, each >= 0.
    torque_floor : float, optional
        TAU [N m or N].
    region : Region, optional
        Prune on bounds proved over this joint-limit region, as
        :func:`gd_analyze.simplify.deploy.build_recursive` does
        (:func:`gd_analyze.simplify.deploy.region_search`: the exact model where the sampled
        pre-screen finds that no region model could save enough at that EPS, and the searches
        kept by ``derive``); None: prune on the trajectory's peaks.
    contributions : tuple of ndarray, optional
        The pairs' peaks on the trajectory
        (:func:`gd_analyze.symbolic.pruning.contribution_peaks`), when the caller has them.
    deployed : SimplifiedModel, optional
        The recursive model built at one of the tolerances
        (:func:`gd_analyze.simplify.deploy.recursive_simplified`): its rung takes its program
        instead of building it again, and every rung its exact program.
    pool : concurrent.futures.Executor, optional
        Where the rungs' errors are measured over the trajectory (numpy array code, which
        releases the GIL), beside the caller's next work; the rungs' models, programs and
        counts are built before, in the caller's thread. Then a Future of the list is returned.
    derive : Derivations, optional
        Where certifications and searches are kept between runs
        (:class:`~gd_analyze.simplify.region_memo.Derivations`; default nowhere).

    Returns
    -------
    list of dict, or concurrent.futures.Future of it (with ``pool``)
        Per EPS: ``tolerance``; ``multiplications``, ``additions``, ``sin``, ``cos`` of the
        rung's program with the drives (:func:`gd_analyze.symbolic.drive_regressor.with_drives`);
        ``worst_relative_error``: max over joints of peak |tau_s - tau| / s_i on the
        trajectory, tau from the exact recursive program and s_i the rung's scale (over the
        region, or the trajectory's peak |tau_i| with the floor); ``worst_relative_bound``: max over joints of
        its bound / s_i (<= EPS).

    Raises
    ------
    ValueError
        If a tolerance is negative or not finite (:func:`gd_analyze.symbolic.pruning.prune_bounds`).

    Notes
    -----
    Fu, Gonzalez & Lee (1987), Algorithm 3.1 on the base parameters (Khalil & Kleinfinger
    1987; Gautier 1990), pruned as :func:`gd_analyze.simplify.deploy.build_recursive`; the
    error bound is the triangle inequality over the dropped pairs.
    """

    q, qd, qdd = trajectory
    built: tuple = getattr(deployed, "choice_cache", None) or ()
    exact = built[2] if len(built) > 2 else recursive_program(robot, base.values)
    rungs = []
    for eps in tolerances:
        eps = float(eps)
        if deployed is not None and eps == float(deployed.tolerance):
            rec, program = deployed.recursive, deployed.choice_cache[0]  # type: ignore[index]  # a deployed model has its choice
        else:
            if region is not None:      # as the main job would deploy it at this EPS
                found = region_search(robot, base, region, eps, torque_floor, sampled=False,
                                      derive=derive)
                rec, forms, store = found.rec, found.forms, found.store
            else:
                rec = recursive_model(robot, q, qd, qdd, eps, torque_floor, base=base,
                                      peaks=contributions)
                forms, store = None, None
            program = rec.choice(robot, exact=exact, forms=forms[1] if forms and
                                 rec.dropped.any() else None)[0]
            if store is not None:
                store(exact.forms, None if program is exact else program.forms)
        rungs.append((eps, rec, program, with_drives(program, robot).cost()))
    programs = [program for _, _, program, _ in rungs]
    for program in (exact, *programs):       # compiled here, in the caller's thread
        python_function(program)

    def measured():
        err = _worst_errors(exact, programs, q, qd, qdd, robot.n)
        rows = []
        for (eps, rec, _, cost), worst in zip(rungs, err):
            scale = np.asarray(rec.scale, float)
            safe = np.where(scale > 0, scale, np.inf)
            rows.append({"tolerance": eps, **cost,
                         "worst_relative_error": float(np.max(worst / safe)),
                         "worst_relative_bound": float(np.max(np.asarray(rec.bound, float)
                                                              / safe))})
        return rows

    return measured() if pool is None else pool.submit(measured)


def _worst_errors(exact, programs, q, qd, qdd, n, block=LADDER_BLOCK):
    """Peak |tau_s - tau| per joint of each program against the exact one, block by block.

    Parameters
    ----------
    exact : Program
        The exact recursive program (the reference tau).
    programs : list of Program
        The rungs' programs; one that is ``exact`` has error 0.
    q, qd, qdd : ndarray, shape (N, n)
        The trajectory [rad, rad/s, rad/s^2; m, m/s, m/s^2].
    n : int
        Joints.
    block : int, optional
        Set points evaluated at once: memory stays a few (block, n) temporaries of each
        program whatever N is, and the peaks do not depend on it (every row is computed alone).

    Returns
    -------
    ndarray, shape (len(programs), n)
        [N m; N]; NaN where a torque is NaN.
    """

    # rungs whose programs are the same straight-line code (the same assignments and
    # outputs) share one evaluation; the exact program's rung has none
    measured: list = []                     # the distinct programs measured
    which = []                              # each rung's index in it, or -1 for the exact
    for program in programs:
        same = [i for i, p in enumerate(measured) if _same_code(p, program)]
        if program is exact or _same_code(program, exact):
            which.append(-1)
        elif same:
            which.append(same[0])
        else:
            which.append(len(measured))
            measured.append(program)
    peak = np.zeros((len(measured), n))
    reference = python_function(exact)
    for a in range(0, q.shape[0], max(1, int(block))):
        rows = slice(a, a + block)
        tau = reference(q[rows], qd[rows], qdd[rows])
        for k, program in enumerate(measured):
            got = python_function(program)(q[rows], qd[rows], qdd[rows])
            np.maximum(peak[k], np.abs(np.asarray(got) - tau).max(axis=0), out=peak[k])
    return np.array([np.zeros(n) if k < 0 else peak[k] for k in which]).reshape(-1, n)


def _same_code(a, b):
    """Whether two programs are the same straight-line code: equal assignments and outputs,
    so their torques are the same floats."""
    return a is b or (a.n == b.n and a.assignments == b.assignments and a.outputs == b.outputs)
