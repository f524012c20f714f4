"""The tolerance ladder of the pruned recursive model: its cost and error per EPS.

For each EPS of the ladder the recursive model is pruned as the deployed one is (on bounds
proved over the joint-limit region, or on the trajectory's peaks), its program built and
counted, and its torque error measured on the trajectory. Nothing here prints or writes files
(the region searches go through the derivation cache, :mod:`gd_analyze.store.certification_cache`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
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
    from .deploy import RegionSearch

__all__ = ["recursive_ladder", "LadderMeter", "LADDER_BLOCK"]

#: Set points whose torques each rung evaluates at once where :func:`recursive_ladder`
#: measures the ladder itself (the main job's pass feeds its own blocks).
LADDER_BLOCK = 8192


def recursive_ladder(robot: Robot, base: BaseParameters,
                     trajectory: tuple[np.ndarray, np.ndarray, np.ndarray],
                     tolerances: Sequence[float], torque_floor: float = 0.0,
                     region: Region | None = None,
                     contributions: tuple[np.ndarray, ...] | None = None,
                     deployed: SimplifiedModel | None = None, beside: bool = False,
                     derive: Derivations = UNKEPT,
                     searched: Mapping[float, RegionSearch] | None = None
                     ) -> list[dict] | LadderMeter:
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
    beside : bool, optional
        Build the rungs (models, programs, counts) and return them unmeasured, as a
        :class:`LadderMeter` the caller feeds with the trajectory's blocks and its own
        reference torques (the main job's pass, on a thread beside it); default: measured here
        against the exact recursive program, block by block.
    derive : Derivations, optional
        Where certifications and searches are kept between runs
        (:class:`~gd_analyze.simplify.region_memo.Derivations`; default nowhere).
    searched : dict of float to RegionSearch, optional
        With ``region``: the rungs' searches the caller made already, by EPS
        (:attr:`gd_analyze.simplify.deploy.RegionSearches.rungs`); a rung missing there is
        searched here.

    Returns
    -------
    list of dict, or LadderMeter (with ``beside``)
        Per EPS: ``tolerance``; ``multiplications``, ``additions``, ``sin``, ``cos`` of the
        rung's program with the drives (:func:`gd_analyze.symbolic.drive_regressor.with_drives`);
        ``worst_relative_error``: max over joints of peak |tau_s - tau| / s_i on the
        trajectory, tau from the exact recursive program with the drives (or the caller's
        reference) and s_i the rung's scale (over the region, or the trajectory's peak
        |tau_i| with the floor); ``worst_relative_bound``: max over joints of its bound / s_i
        (<= EPS).

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
                found = (searched or {}).get(eps) or region_search(
                    robot, base, region, eps, torque_floor, sampled=False, derive=derive)
                rec, forms, store = found.rec, found.forms, found.store
            else:
                rec = recursive_model(robot, q, qd, qdd, eps, torque_floor, base=base,
                                      peaks=contributions)
                forms, store = None, None
            program = rec.choice(robot, exact=exact, forms=forms[1] if forms and
                                 rec.dropped.any() else None)[0]
            if store is not None:
                store(exact.forms, None if program is exact else program.forms)
        rungs.append((eps, rec, with_drives(program, robot)))
    at = [k for k, (eps, _, _) in enumerate(rungs)
          if deployed is not None and eps == float(deployed.tolerance)]
    meter = LadderMeter(robot.n, rungs, at[0] if at else None)
    if beside:
        return meter
    reference = python_function(with_drives(exact, robot))
    for a in range(0, q.shape[0], LADDER_BLOCK):
        rows = slice(a, a + LADDER_BLOCK)
        meter.update(q[rows], qd[rows], qdd[rows], reference(q[rows], qd[rows], qdd[rows]))
    return meter.rows()


class LadderMeter:
    """The rungs of a tolerance ladder, built, and each one's peak |tau_s - tau| per joint,
    measured block by block against a reference torque (:meth:`update`).

    Rungs whose programs are the same straight-line code share one evaluation. The deployed
    model's rung takes the deployed model's torques when the caller has them (the main job's
    pass computes them anyway).

    Parameters
    ----------
    n : int
        Joints.
    rungs : list of (float, RecursiveModel, Program)
        Per EPS: the pruned model and its program with the drives
        (:func:`gd_analyze.symbolic.drive_regressor.with_drives`).
    deployed : int, optional
        The index of the deployed model's rung.

    Notes
    -----
    tau is Eq. (3.4-24) of Fu, Gonzalez & Lee (1987); each rung's program is that of
    :func:`recursive_ladder` (Algorithm 3.1 on the base parameters, pruned).
    """

    def __init__(self, n: int, rungs: list, deployed: int | None = None) -> None:
        self.n, self._rungs, self._deployed = n, rungs, deployed
        self._distinct: list = []           # the programs evaluated
        self._which: list[int] = []         # each rung's index in them; -1 the deployed one's
        for k, (_, _, program) in enumerate(rungs):
            same = [i for i, p in enumerate(self._distinct) if _same_code(p, program)]
            if k == deployed:
                self._which.append(-1)
            elif same:
                self._which.append(same[0])
            else:
                self._which.append(len(self._distinct))
                self._distinct.append(program)
        for program in self._distinct:      # compiled here, in the caller's thread
            python_function(program)
        self._peak = np.zeros((len(self._distinct), n))
        self._deployed_peak = np.zeros(n)

    def update(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, tau: np.ndarray,
               tau_deployed: np.ndarray | None = None) -> None:
        """Fold one block of set points into the peaks.

        Parameters
        ----------
        q, qd, qdd : ndarray, shape (B, n)
            The block's states [rad, rad/s, rad/s^2; m, m/s, m/s^2].
        tau : ndarray, shape (B, n)
            The reference torques there: the exact model's, drives included [N m; N].
        tau_deployed : ndarray, shape (B, n), optional
            The deployed model's torques there; evaluated here when not given.
        """
        if len(q) == 0:
            return
        for k, program in enumerate(self._distinct):
            got = np.asarray(python_function(program)(q, qd, qdd))
            np.maximum(self._peak[k], np.abs(got - tau).max(axis=0), out=self._peak[k])
        if self._deployed is not None:
            got = tau_deployed if tau_deployed is not None else np.asarray(
                python_function(self._rungs[self._deployed][2])(q, qd, qdd))
            np.maximum(self._deployed_peak, np.abs(got - tau).max(axis=0),
                       out=self._deployed_peak)

    def peaks(self) -> np.ndarray:
        """ndarray, shape (rungs, n): each rung's peak |tau_s - tau| per joint so far [N m; N];
        NaN where a torque was NaN."""
        return np.array([self._deployed_peak if k < 0 else self._peak[k]
                         for k in self._which]).reshape(-1, self.n)

    def rows(self) -> list[dict]:
        """The ladder's rows, as :func:`recursive_ladder` returns them.

        Returns
        -------
        list of dict
        """
        rows = []
        for (eps, rec, program), worst in zip(self._rungs, self.peaks()):
            scale = np.asarray(rec.scale, float)
            safe = np.where(scale > 0, scale, np.inf)
            rows.append({"tolerance": eps, **program.cost(),
                         "worst_relative_error": float(np.max(worst / safe)),
                         "worst_relative_bound": float(np.max(np.asarray(rec.bound, float)
                                                              / safe))})
        return rows


def _same_code(a, b):
    """Whether two programs are the same straight-line code: equal assignments and outputs,
    so their torques are the same floats."""
    return a is b or (a.n == b.n and a.assignments == b.assignments and a.outputs == b.outputs)
