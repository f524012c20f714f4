"""Closed-loop use of the simplified model: computed-torque control of the full-model arm.

Sec. 3.4.1 of Fu, Gonzalez & Lee (1987) builds the simplified G-D model "for control purpose".
This module puts it in the loop. The plant is the arm with its full G-D dynamics, Eq. (3.4-24),
integrated forward in time with::

    qdd = D(q)^-1 (tau - h(q, qd) - c(q))                                  (forward_dynamics)

and three controllers track a desired motion q_d(t):

- ``"full"``: computed torque (Fu, Gonzalez & Lee 1987, Ch. 5, computed-torque technique) with
  the full G-D model, tau = D(q) v + h(q, qd) + c(q);
- ``"simplified"``: computed torque with the simplified model of ``simplified_model.json``,
  tau = D_s(q) v + h_s(q, qd) + c_s(q) (c_s = c where the model keeps gravity whole), evaluated
  in its explicit form
  (:meth:`gd_analyze.simplify.simplified.SimplifiedModel.torque`: only the kept terms are computed);
- ``"pd_gravity"``: PD control with gravity compensation, tau = Kp_pd e + Kv_pd ed + c(q);

where e = q_d - q, ed = qd_d - qd and v = qdd_d + Kv ed + Kp e. With the full model the
closed loop is exactly e'' + Kv e' + Kp e = 0, so the error starting on the trajectory stays at
the integrator's tolerance; a model error tau_m - tau_exact enters as a forcing
D^-1 (tau_m - tau_exact) of that linear error equation.

Gains (settable; :func:`~gd_analyze.jobs.tracking.control_gains`)
---------------------------------------
Computed torque: Kp = wn^2 [s^-2] and Kv = 2 zeta wn [s^-1] per joint, default wn = 20 rad/s and
zeta = 1 (critically damped, no overshoot). 20 rad/s (3.2 Hz, time constant 1/wn = 0.05 s)
is fast against the shipped 4.2 s motion (its rest-to-rest quintic has no content above
~1 Hz) and modest for an industrial arm's position loop; the simulation has no structural
flexibility, actuator limit, sampling or friction that would bound it, so it is a stated
choice, not a tuned one. PD + gravity acts on torque, not acceleration, so its gains are
scaled by the diagonal of the inertia matrix at the start of the motion:
Kp_pd = diag(D(q_d(0))) wn^2 [N m/rad; N/m on a prismatic joint], Kv_pd = diag(D(q_d(0)))
2 zeta wn [N m s/rad; N s/m]; each
joint then has the same wn and zeta as long as the inertia stays near its starting value and the
coupling is ignored.

Desired motion (:func:`~gd_analyze.jobs.tracking.desired_motion`)
---------------------------------------
Between set points, q_d is the piecewise quintic Hermite polynomial through (q, qd, qdd) at both
ends of each interval (``scipy.interpolate.BPoly.from_derivatives``, converted to a ``PPoly``):
q_d, qd_d = dq_d/dt and qdd_d = d^2q_d/dt^2 are consistent, match the file's q, qd and qdd at
every set point, and are continuous up to qdd_d (C2). A quintic trajectory such as the shipped
one is reproduced exactly. (A cubic spline through q alone would not honour the file's qd and
qdd; separate Hermite splines on q and on qd would make qd_d differ from dq_d/dt.)

Integration
-----------
``scipy.integrate.solve_ivp`` (default DOP853, rtol = 1e-8, atol = 1e-10) of the state
(q, qd), starting at q(0) = q_d(0) + offset, qd(0) = qd_d(0). The solution is sampled at the set
points and on a fine grid (:data:`DEFAULT_GRID_POINTS` evenly spaced times, set points added);
the applied torques are recomputed at those samples from the sampled states with the same
control law.

Integrator noise of the torque difference (:func:`difference_noise`)
--------------------------------------------------------------------
The closed-loop torque difference tau_s - tau_f is the difference of two runs, each with the
integrator's error in its state; the gains turn a state error into a torque error
(D Kp dq + D Kv dqd, Kp = 400 s^-2), so its noise is far above rtol times the torque. It is
measured, not estimated: both computed-torque runs are integrated again with rtol and atol
divided by :data:`NOISE_TIGHTEN`, and the peak over the run of
|(tau_s - tau_f)(rtol) - (tau_s - tau_f)(rtol / 100)| is the noise of the difference drawn.
Both runs are repeated because their noises neither cancel nor add in a fixed way (the shipped
PUMA 560: the difference's noise is half of each run's; the UR5's joint 5: twice the
full-model run's). The floor below which the difference is noise, not data, is
:data:`NOISE_FACTOR` times that peak (a margin for the tight run's own error: the same
measurement against rtol / 10^4 agrees with it to within 5 % on the shipped PUMA 560,
Stanford and UR5 runs and on a 5,000-set-point PUMA 560 run), and at least
max(rtol, 1e-12) times the full-model controller's peak |tau| (:attr:`ControlResult.tau_noise_floor`).
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..dynamics.dalembert import gd_terms
from ..dynamics.opcount import operation_counts
from ..ranking.ranking import ROUND_OFF
from ..simplify.explicit_model import full_program
from ..simplify.simplified import choice_masks, json_safe
from ..store import explicit_cache
from ..store.control_dataset import peak_rms
from ..symbolic.drive_regressor import with_drives
from ..symbolic.explicit_estimate import is_expensive
from ..symbolic.recursive import recursive_program
from ..trajectory.trajectory import Trajectory
from . import tracking
from .evaluate import coverage, coverages, model_torque

if TYPE_CHECKING:                       # for the type hints only
    import os

    from numpy.typing import ArrayLike, NDArray
    from scipy.interpolate import PPoly

    from ..model.robot import Robot
    from ..simplify.simplified import SimplifiedModel

__all__ = ["DEFAULT_GRID_POINTS", "CONTROL_FILE", "NOISE_TIGHTEN", "NOISE_FACTOR",
           "ControlResult", "run_control", "difference_noise", "model_cost", "model_facts"]

#: Default number of evenly spaced samples of the fine grid (set points are added).
DEFAULT_GRID_POINTS = 2001
#: Default file name of the stored control dataset.
CONTROL_FILE = "control.h5"
#: The tolerances of the runs that measure the integrator noise are rtol and atol over this.
NOISE_TIGHTEN = 100.0
#: The noise floor of the torque difference is this many times its measured noise.
NOISE_FACTOR = 2.0


@dataclass(frozen=True, eq=False)
class ControlResult:
    """The closed-loop comparison of :func:`run_control`.

    Attributes
    ----------
    robot : Robot
        The arm, with n joints.
    choices : dict
        The simplified model's choices.
    gains : Gains
        The gains used.
    t : ndarray, shape (M,)
        Sample times, set points and fine grid [s].
    is_setpoint : ndarray of bool, shape (M,)
        True at the trajectory's set points.
    q_d, qd_d, qdd_d : ndarray, shape (M, n)
        The desired motion at the samples [rad, rad/s, rad/s^2].
    runs : dict
        Controller name -> :class:`~gd_analyze.jobs.tracking.TrackingRun`, in
        :data:`~gd_analyze.jobs.tracking.CONTROLLERS` order.
    cost : dict or None
        :func:`model_cost` of the model, if asked for.
    provenance : dict
        Files and their SHA-256, solver settings, initial offset.
    tau_noise : ndarray, shape (n,), or None
        Measured integrator noise of :attr:`tau_difference` per joint (:func:`difference_noise`)
        [N m; N on a prismatic joint]; None unless both computed-torque controllers ran.
    """

    robot: Robot
    choices: dict
    gains: tracking.Gains
    t: np.ndarray
    is_setpoint: np.ndarray
    q_d: np.ndarray
    qd_d: np.ndarray
    qdd_d: np.ndarray
    runs: dict
    cost: dict | None = None
    provenance: dict = field(default_factory=dict)
    tau_noise: np.ndarray | None = None

    @property
    def tau_noise_floor(self) -> np.ndarray | None:
        """ndarray, shape (n,), or None: per joint, the level at or below which the closed-loop
        torque difference is integrator noise, not data [N m; N on a prismatic joint].

        max(:data:`NOISE_FACTOR` x :attr:`tau_noise`, max(rtol, 1e-12) x the full-model
        controller's peak |tau|); without a measured noise, the second term alone. None
        without a full-model run.
        """
        if "full" not in self.runs:
            return None
        tol = max(float(self.provenance.get("rtol", 0.0)), ROUND_OFF)
        noise = 0.0 if self.tau_noise is None else NOISE_FACTOR * np.asarray(self.tau_noise, float)
        return np.maximum(noise, tol * np.nanmax(np.abs(self.runs["full"].tau), axis=0))

    @property
    def descriptions(self) -> dict[str, str]:
        """dict: controller name -> its control law in one line
        (:data:`~gd_analyze.jobs.tracking.CONTROLLER_DESCRIPTIONS`), the simplified model's
        gravity term c_s where the model drops part of c (its ``gravity_dropped`` parameters,
        or fewer ``c_terms_kept`` than ``c_terms``), else c; the computed-torque laws with the
        drives' friction tau_f where the arm has it."""
        m = self.provenance.get("model", {})
        part = bool(m.get("gravity_dropped")) or -1 < m.get("c_terms_kept", -1) != m.get("c_terms")
        return {c: tracking.CONTROLLER_DESCRIPTIONS[c] + "_s" * (c == "simplified" and part)
                + " + tau_f" * (c != "pd_gravity" and self.robot.has_friction) for c in self.runs}

    @property
    def controllers(self) -> list[str]:
        """list of str: the controllers run, in table order."""
        return list(self.runs)

    def error_figures(self, controller: str) -> dict[str, list[float]]:
        """Tracking error figures of one controller.

        Parameters
        ----------
        controller : str
            A name of :attr:`runs`.

        Returns
        -------
        dict
            Lists of n floats [rad]: ``peak_setpoints``, ``rms_setpoints`` (|e| at the set
            points) and ``peak_grid``, ``rms_grid`` (on all samples).

        Raises
        ------
        KeyError
            If the controller was not run.
        """
        e = self.runs[controller].error
        (ps, rs), (pg, rg) = peak_rms(e[self.is_setpoint]), peak_rms(e)
        return {"peak_setpoints": ps.tolist(), "rms_setpoints": rs.tolist(),
                "peak_grid": pg.tolist(), "rms_grid": rg.tolist()}

    @property
    def tau_difference(self) -> np.ndarray | None:
        """ndarray, shape (M, n), or None: tau of "simplified" minus tau of "full" [N m].

        Each from its own closed-loop run, at the same sample times; None unless both ran.
        """
        if "full" in self.runs and "simplified" in self.runs:
            return self.runs["simplified"].tau - self.runs["full"].tau
        return None

    def summary(self) -> dict[str, Any]:
        """The figures as plain JSON-ready data.

        Returns
        -------
        dict
            ``robot``, ``wn``, ``zeta``, ``tracking`` (controller -> :meth:`error_figures`
            [rad]), ``tau_difference`` (``peak``, ``rms`` per joint [N m], or None),
            ``cost`` (or None) and ``guarantee`` (the model's ``scope`` sentence, its
            ``kind`` and whether it ``covered`` the desired motion and, for a region, its every
            sample and the simplified-model controller's closed loop: q, qd and the commanded
            acceleration v at which it evaluates the model; with the ``reason``).
        """
        td = None if (diff := self.tau_difference) is None else {
            k: v.tolist() for k, v in zip(("peak", "rms"), peak_rms(diff))}
        return {"robot": self.robot.name, "wn": self.gains.wn.tolist(),
                "zeta": self.gains.zeta.tolist(),
                "tracking": {c: self.error_figures(c) for c in self.runs},
                "nfev": {c: r.nfev for c, r in self.runs.items()},
                "tau_difference": td, "cost": self.cost,
                "guarantee": {k: m.get(f) for k, f in (
                    ("statement", "scope"), ("kind", "guarantee_kind"),
                    ("covered", "guarantee_covered"), ("reason", "guarantee_coverage"))
                    if (m := self.provenance.get("model", {})) is not None}}


def model_cost(model: SimplifiedModel) -> dict[str, Any]:
    """The counted operations per set point of a simplified model, beside the full model's.

    Parameters
    ----------
    model : SimplifiedModel
        The model. Both costs are counted here, never read from a file: the simplified
        model's on the straight-line program of its own terms, the full explicit model's on
        the program of all the terms of its robot (:func:`gd_analyze.store.explicit_cache.explicit_terms`).

    Returns
    -------
    dict
        ``evaluators`` (names), ``multiplications`` and ``additions`` (lists of int per set
        point): the simplified model, the exact recursive model
        (:func:`gd_analyze.symbolic.recursive.recursive_program`, or the same program
        its builder kept in ``choice_cache``), the full explicit model
        (unless the model is recursive and the expansion expensive,
        :func:`gd_analyze.symbolic.explicit_estimate.is_expensive`) and the project's Newton-Euler
        as implemented (:func:`gd_analyze.dynamics.opcount.operation_counts`, the arm's one
        count), last;
        ``dropped`` of ``parts``: what the model drops, ``what`` names them (parts of D and h,
        or (base parameter, part) pairs), ``dropped_pairs`` lists the pairs of a recursive model.

    Notes
    -----
    Counts, not times: they do not depend on the machine. Sources: Sec. 3.4.1 of Fu, Gonzalez &
    Lee (1987) (a simplified model "at a reduced computation time"), Table 3.5 (N-E), and
    Armstrong, Khatib & Burdick (1986) for the explicit form.
    """
    robot: Robot = model.robot
    built = model.choice_cache or ()    # the exact program its builder made, where it kept it
    exact = built[2] if len(built) > 2 else recursive_program(robot)
    counted = [(f"simplified model ({model.form} form)", model.program().cost()),
               ("exact recursive model", with_drives(exact, robot).cost())]
    if model.form == "explicit" or not is_expensive(robot):
        terms, _ = explicit_cache.explicit_terms(robot)
        counted.append(("full explicit model", full_program(robot, terms).cost()))
    counted.append(("Newton-Euler (as implemented)", operation_counts(robot)["newton-euler"]))
    counts = {"evaluators": [name for name, _ in counted],
              **{k: [int(c[k]) for _, c in counted] for k in ("multiplications", "additions")}}
    facts = model_facts(model)
    if model.recursive is not None:
        return {**counts, "dropped": facts["pairs_dropped"], "parts": facts["pairs"],
                "what": "(base parameter, part) pairs of the recursive model",
                "dropped_pairs": facts["dropped_pairs"]}
    Mt, Mr, mt, mr = choice_masks(model.choices, robot.n)
    parts = 2 * (robot.n * (robot.n + 1) // 2 + robot.n)
    kept = int(np.triu(Mt).sum() + np.triu(Mr).sum() + mt.sum() + mr.sum())
    return {**counts, "dropped": parts - kept, "parts": parts,
            "what": "translational/rotational parts of D and h", "dropped_pairs": ""}


def model_facts(model: SimplifiedModel) -> dict[str, Any]:
    """What the reports state about a simplified model, read from the model itself.

    Parameters
    ----------
    model : SimplifiedModel
        A model as built, or read from ``simplified_model.json``.

    Returns
    -------
    dict
        ``form`` (recursive or explicit), ``rule`` (budget or chapter), ``tolerance``;
        for the recursive form ``base_parameters`` (count), ``pairs`` and ``pairs_dropped``
        (the (parameter, part) pairs that contribute on the trajectories the model was built
        on, and those dropped), ``dropped_pairs`` (``"XY2 (inertial), ..."``) and
        ``gravity_dropped`` (the parameters whose gravity part is dropped, comma-separated),
        ``pairs_known`` (1 if the model records which pairs contribute, else every pair counts)
        (:meth:`gd_analyze.symbolic.recursive_model.RecursiveModel.stated_facts`, the
        count of the main report); for the explicit form of the budget rule ``c_terms_kept``
        and ``c_terms`` (its terms of c and the full model's; -1 when the full model is not
        derived); ``scope``, the model's guarantee in one sentence
        (:meth:`~gd_analyze.simplify.simplified.SimplifiedModel.scope`), and
        ``guarantee_kind`` (``"region"``, ``"trajectory"`` or ``"none"``). Sources: Fu,
        Gonzalez & Lee (1987), Sec. 3.4.1 and Eq. (3.4-24).
    """
    out = {"form": model.form, "rule": str(model.rule), "tolerance": float(model.tolerance),
           "scope": model.scope(),
           "guarantee_kind": "none" if model.guarantee is None else model.guarantee.kind,
           "base_parameters": -1, "pairs": -1, "pairs_dropped": -1, "dropped_pairs": "",
           "gravity_dropped": "", "pairs_known": 0, "c_terms_kept": -1, "c_terms": -1}
    if model.recursive is not None:
        f = model.recursive.stated_facts()
        out.update(base_parameters=len(model.recursive.names), pairs=f["pairs"],
                   pairs_dropped=f["dropped"],
                   dropped_pairs=", ".join(f"{a} ({b})" for a, b in f["dropped_pairs"]),
                   gravity_dropped=", ".join(f["gravity_dropped"]), pairs_known=int(f["known"]))
    elif model.rule == "budget" and model.terms is not None:
        out["c_terms_kept"] = int(np.sum(np.asarray(model.terms.kind) == "c"))
        if not is_expensive(model.robot):
            full, _ = explicit_cache.explicit_terms(model.robot)
            out["c_terms"] = int(np.sum(np.asarray(full.kind) == "c"))
    return out

def _sample_times(t_set, grid_points):
    """Set-point times and an even grid, merged; grid points within 1e-9 T of a set point go."""
    t_set = np.asarray(t_set, dtype=float)
    grid = np.linspace(t_set[0], t_set[-1], max(2, int(grid_points)))
    tol = 1e-9 * max(t_set[-1] - t_set[0], 1e-300)
    idx = np.clip(np.searchsorted(t_set, grid), 1, t_set.size - 1)
    near = np.minimum(np.abs(grid - t_set[idx - 1]), np.abs(grid - t_set[idx])) <= tol
    t = np.union1d(t_set, grid[~near])
    return t, np.isin(t, t_set)


def run_control(model: SimplifiedModel, trajectory: Trajectory,
                wn: ArrayLike = tracking.DEFAULT_WN, zeta: ArrayLike = tracking.DEFAULT_ZETA,
                q0_offset: ArrayLike = 0.0,
                controllers: Sequence[str] = tracking.CONTROLLERS,
                grid_points: int = DEFAULT_GRID_POINTS, rtol: float = tracking.DEFAULT_RTOL,
                atol: float = tracking.DEFAULT_ATOL, method: str = tracking.DEFAULT_METHOD,
                t_end: float | None = None, cost: bool = True,
                model_path: str | os.PathLike[str] | None = None,
                model_sha256: str | None = None, plant: Robot | None = None,
                verdict_tolerance: tuple[float, float] | None = None) -> ControlResult:
    """Track a trajectory with the full-model, simplified-model and PD + gravity controllers.

    Parameters
    ----------
    model : SimplifiedModel
        The simplified model; its robot is the plant.
    trajectory : Trajectory
        The set points to track.
    wn : float or array_like, shape (n,), optional
        Undamped natural frequency of the error dynamics [rad/s] (default 20), within
        :data:`~gd_analyze.jobs.tracking.GAIN_RANGES` (0.01 to 1e4, as ``--wn``).
    zeta : float or array_like, shape (n,), optional
        Damping ratio (default 1), within :data:`~gd_analyze.jobs.tracking.GAIN_RANGES` (0.01 to
        100, as ``--zeta``).
    q0_offset : float or array_like, shape (n,), optional
        Initial position error q(0) - q_d(0) [rad] (default 0: start on the trajectory).
    controllers : sequence of str, optional
        Which of :data:`~gd_analyze.jobs.tracking.CONTROLLERS` to run.
    grid_points : int, optional
        Evenly spaced samples of the fine grid (the set points are added).
    rtol, atol : float, optional
        Integrator tolerances.
    method : str, optional
        ``solve_ivp`` method.
    t_end : float, optional
        Stop at this time [s] (set points after it are left out); default: the last set point.
    cost : bool, optional
        Also record the counted operations of the model (:func:`model_cost`).
    model_path : str or os.PathLike, optional
        The file the model was read from, recorded in the provenance.
    model_sha256 : str, optional
        That file's SHA-256 (:func:`gd_analyze.files.file_sha256`); without a file, the SHA-256
        of the model's canonical JSON is recorded.
    plant : Robot, optional
        The controlled arm, which the full-model and PD + gravity controllers also use
        (default: the model's robot), e.g. mounted otherwise
        (:func:`gd_analyze.model.mounting.with_mounting`); the simplified model keeps its own.
    verdict_tolerance : tuple of (float, float), optional
        The report's verdict tolerance on the simplified-model controller's peak tracking
        error: revolute joints [rad], prismatic joints [m] (recorded for the report, not used
        here; default: not recorded, the report's
        :data:`gd_analyze.report.control.VERDICT_TOLERANCE`).

    Returns
    -------
    ControlResult

    Raises
    ------
    ValueError
        If the trajectory's joint count differs from the robot's, t_end leaves fewer than 2
        set points, a controller is unknown, wn or zeta is outside
        :data:`~gd_analyze.jobs.tracking.GAIN_RANGES` (as ``--wn``, ``--zeta``;
        :func:`~gd_analyze.jobs.tracking.control_gains`), the gains so stiff that the
        integration would need more than
        :data:`~gd_analyze.jobs.tracking.MAX_STIFFNESS_STEPS` steps
        (:func:`~gd_analyze.jobs.tracking.closed_loop_rates`, every controller), D is singular
        (:func:`~gd_analyze.jobs.tracking.singular_inertia`), or a run exceeds
        :data:`~gd_analyze.jobs.tracking.MAX_RHS_EVALS` evaluations.
    InputError
        If the model's torque is not finite on a set point (:func:`~gd_analyze.jobs.evaluate.model_torque`),
        or its trajectory guarantee does not hold on its own trajectory, measured again
        (:func:`~gd_analyze.jobs.evaluate.check_trajectory_claim`).

    Notes
    -----
    Sources: Fu, Gonzalez & Lee (1987), Eq. (3.4-24) (plant and model), Sec. 3.4.1
    (simplified model), Ch. 5 (computed-torque control).
    """
    model_file = "<in memory>" if model_path is None else str(model_path)
    model_sha = model_sha256 or ("" if model_path is not None else hashlib.sha256(json.dumps(
        json_safe(model.to_dict()), sort_keys=True).encode()).hexdigest())
    robot: Robot = model.robot if plant is None else plant
    if trajectory.q.shape[1] != robot.n:
        raise ValueError(f"the trajectory has {trajectory.q.shape[1]} joints, the robot "
                         f"{robot.n}")
    if not controllers or not set(controllers) <= set(tracking.CONTROLLERS):
        raise ValueError(f"controllers must be among {tracking.CONTROLLERS}, got "
                         f"{list(controllers)}")
    choice_masks(model.choices, robot.n)            # validate
    model_torque(model, trajectory.q, trajectory.qd, trajectory.qdd)    # finite on the set points
    covers = coverage(model, trajectory, plant=robot, path=model_file)  # a claim checked first
    t_set = np.asarray(trajectory.t, dtype=float)
    if t_end is not None:
        t_set = t_set[t_set <= float(t_end) * (1 + 1e-12)]
        if t_set.size < 2:
            raise ValueError(f"t_end = {t_end} s leaves fewer than 2 set points")
    desired = tracking.desired_motion(trajectory)
    t, is_set = _sample_times(t_set, grid_points)
    # D at (up to 64 of) the set points: invertible, and the loops' speed for every controller
    pick = np.unique(np.linspace(0, len(trajectory.t) - 1, 64).round().astype(int))
    D = gd_terms(robot, trajectory.q[pick], np.zeros_like(trajectory.q[pick])).D
    if singular := tracking.singular_inertia(robot, D):
        raise ValueError(singular)
    gains = tracking.control_gains(robot, desired(t[0]), wn, zeta)
    rates = tracking.closed_loop_rates(robot, gains, D)
    for name in (c for c in tracking.CONTROLLERS if c in controllers):
        # computed torque: the gains' own bound; PD + gravity: what a run can evaluate
        most = (tracking.MAX_STIFFNESS_STEPS if name != "pd_gravity"
                else tracking.MAX_RHS_EVALS // tracking.RHS_PER_STEP)
        steps = rates[name] * float(t[-1] - t[0]) / 3.0
        if steps > most:
            raise ValueError(
                f"wn = {np.max(gains.wn):g} rad/s and zeta = {np.max(gains.zeta):g} make the "
                f"{tracking.CONTROLLER_DESCRIPTIONS[name].split(':')[0]} loop ({name}) too "
                f"stiff: its fastest mode, {rates[name]:.3g} rad/s, needs about {steps:.3g} "
                f"integrator steps over {t[-1] - t[0]:g} s (at most {most}); lower wn or zeta")
    offset = np.broadcast_to(np.asarray(q0_offset, dtype=float), (robot.n,)).copy()
    runs = {name: tracking.track(robot, name, gains, desired, t, q0_offset=offset,
                                 choices=model, rtol=rtol, atol=atol, method=method)
            for name in tracking.CONTROLLERS if name in controllers}
    q_d, qd_d, qdd_d = desired(t), desired(t, 1), desired(t, 2)
    states = [("desired motion between the set points", "|qdd|", q_d, qd_d, qdd_d)]
    if (loop := runs.get("simplified")) is not None:     # its model's state: q, qd and v
        states.append(("closed loop of the simplified-model controller", "commanded |qdd|", loop.q,
                       loop.qd, qdd_d + gains.Kv * (qd_d - loop.qd) + gains.Kp * (q_d - loop.q)))
    if covers["covered"] and covers["kind"] == "region":    # a "yes" names what it checked
        covers["reason"] = f"every set point, and at the {t.size} output times " + " and ".join(
            f"the {w} (q, |qd|, {a})" for w, a, *_ in states) + ", lie in the model's region"
        said = coverages(model, [Trajectory(t, *x) for _, _, *x in states], robot, model_file)
        covers = next(({**d, "reason": f"the {who} is " + d["reason"].replace("|qdd|", qdd)}
                       for (who, qdd, *_), d in zip(states, said) if not d["covered"]), covers)
    noise, unmeasured = None, ""
    if "full" in runs and "simplified" in runs:
        try:
            noise, nfev = difference_noise(robot, model, gains, desired, t, runs, offset,
                                           rtol=rtol, atol=atol, method=method)
        except ValueError as err:       # the tighter runs did not finish: the rtol floor
            unmeasured = str(err)
    cost_figures = model_cost(model) if cost else None
    provenance = {
        "trajectory_file": Path(trajectory.source).name if trajectory.source else "",
        "trajectory_path": str(trajectory.source), "trajectory_sha256": trajectory.sha256,
        "trajectory_derivatives": trajectory.derivatives,
        "model_file": Path(model_file).name if model_file != "<in memory>" else model_file,
        "model_path": model_file, "model_sha256": model_sha,
        "model_trajectory_sha256": model.trajectory_sha256,
        "rtol": float(rtol), "atol": float(atol), "method": str(method),
        "grid_points": int(grid_points), "q0_offset": offset.tolist(),
        "t_end": float(t[-1]), "gravity_base": [float(v) for v in robot.gravity],
        "model": {**model_facts(model), "guarantee_covered": int(covers["covered"]),
                  "guarantee_coverage": covers["reason"]},  # desired motion and closed loop
        **({"noise_unmeasured": unmeasured} if unmeasured else {}),
    }
    if noise is not None:
        provenance.update(noise_rtol=float(rtol) / NOISE_TIGHTEN,
                          noise_atol=float(atol) / NOISE_TIGHTEN,
                          noise_factor=NOISE_FACTOR, noise_nfev=nfev)
    if verdict_tolerance is not None:
        provenance["verdict_tolerance"] = [float(v) for v in verdict_tolerance]
    return ControlResult(robot=robot, choices=dict(model.choices), gains=gains, t=t,
                         is_setpoint=is_set, q_d=q_d, qd_d=qd_d, qdd_d=qdd_d, runs=runs,
                         cost=cost_figures, provenance=provenance, tau_noise=noise)


def difference_noise(robot: Robot, model: SimplifiedModel, gains: tracking.Gains, desired: PPoly,
                     t: NDArray[np.float64], runs: dict[str, tracking.TrackingRun],
                     q0_offset: NDArray[np.float64], rtol: float = tracking.DEFAULT_RTOL,
                     atol: float = tracking.DEFAULT_ATOL, method: str = tracking.DEFAULT_METHOD
                     ) -> tuple[np.ndarray, int]:
    """Measured integrator noise of the closed-loop torque difference, simplified-model minus
    full-model computed torque.

    Parameters
    ----------
    robot : Robot
        The plant, n joints.
    model : SimplifiedModel
        The simplified model (the ``"simplified"`` controller).
    gains : Gains
        The gains of the runs.
    desired : scipy.interpolate.PPoly
        The desired motion (:func:`~gd_analyze.jobs.tracking.desired_motion`).
    t : ndarray, shape (M,)
        The sample times of the runs [s].
    runs : dict
        The ``"full"`` and ``"simplified"`` :class:`~gd_analyze.jobs.tracking.TrackingRun`
        at (rtol, atol).
    q0_offset : ndarray, shape (n,)
        Their initial position error [rad; m on a prismatic joint].
    rtol, atol : float, optional
        The runs' tolerances; the measuring runs use them over :data:`NOISE_TIGHTEN`.
    method : str, optional
        The ``solve_ivp`` method.

    Returns
    -------
    noise : ndarray, shape (n,)
        Per joint, the peak over the samples of |(tau_s - tau_f) - (tau_s' - tau_f')| [N m; N],
        primes for the runs at the tight tolerances.
    nfev : int
        Right-hand-side evaluations of the two measuring runs together.

    Raises
    ------
    ValueError
        If a measuring run does not finish (the message names the tolerance).

    Notes
    -----
    See the module docstring ("Integrator noise of the torque difference"). Source: the
    difference of two solutions at tolerances a factor 100 apart as the global error of the
    looser one, the usual check of an adaptive integrator's result (Hairer, Norsett & Wanner,
    *Solving ODEs I*, Ch. II).
    """
    tight = {}
    for name in ("full", "simplified"):
        try:
            tight[name] = tracking.track(robot, name, gains, desired, t, q0_offset=q0_offset,
                                choices=model, rtol=rtol / NOISE_TIGHTEN,
                                atol=atol / NOISE_TIGHTEN, method=method)
        except ValueError as err:
            raise ValueError(f"measuring the integrator noise (rtol = "
                             f"{rtol / NOISE_TIGHTEN:g}): {err}") from None
        if not tight[name].success:
            raise ValueError(f"measuring the integrator noise (rtol = {rtol / NOISE_TIGHTEN:g})"
                             f": the {name} controller's run failed: {tight[name].message}")
    loose, fine = (r["simplified"].tau - r["full"].tau for r in (runs, tight))
    return (np.nanmax(np.abs(loose - fine), axis=0),
            int(tight["full"].nfev + tight["simplified"].nfev))
