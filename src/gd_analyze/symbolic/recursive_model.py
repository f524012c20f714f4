"""The pruned recursive model as a value: what it keeps, its bound, and how to rebuild it.

A :class:`RecursiveModel` holds the base parameters of an arm (names and values, Gautier 1990)
and which (base parameter, part) pairs the error budget dropped (:mod:`.pruning`). It is
enough to rebuild the straight-line program (:func:`.pruning.pruned_program`), and it is what
``simplified_model.json`` stores for a model of the recursive form. On reading, the base
parameters are derived again from the robot's parameters and must agree with the stored ones,
so a hand-edited value cannot change the torques that the model file claims.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ..config import ROUND_OFF
from ..dynamics.base_parameters import (
    PARAMETER_NAMES,
    BaseParameters,
    base_parameters,
    standard_parameters,
)
from ..errors import InputError
from .pruning import dropped_peaks, prune, prune_bounds, prune_on_peaks, pruned_choice
from .recursive import PARTS

if TYPE_CHECKING:
    from ..model.robot import Robot
    from .codegen import Program

__all__ = ["RecursiveModel", "recursive_model", "sweep_recursive_model", "PART_NAMES", "BOUND_PARTS",
           "AGREEMENT", "structural_zeros"]

#: What each part of a base parameter's contribution is, in the order of :data:`.recursive.PARTS`.
PART_NAMES = ("inertial", "velocity", "gravity")
#: How the bound splits: single parts, then parameters dropped whole.
BOUND_PARTS = PART_NAMES + ("whole",)
#: Largest relative difference accepted between stored and re-derived base parameters.
AGREEMENT = 1e-8


@dataclass(frozen=True, eq=False)
class RecursiveModel:
    """A customized recursive Newton-Euler model with some parameter parts dropped.

    Attributes
    ----------
    names : tuple of str, length b
        The base parameters, e.g. ``("ZZ1", "XXR2", ...)`` as
        :meth:`gd_analyze.dynamics.base_parameters.BaseParameters.names` gives them.
    beta : ndarray, shape (b,)
        Their values [kg m^2, kg m, kg].
    dropped : ndarray of bool, shape (b, 3)
        ``dropped[k, p]``: part p (inertial, velocity, gravity) of parameter k is left out.
    scale : ndarray, shape (n,)
        scale_i = max(peak |tau_i|, torque floor) on the trajectories [N m or N].
    bound : ndarray, shape (n,)
        Guaranteed bound on |tau_s - tau| per joint on those trajectories [N m or N]: the sum
        of the dropped pairs' peaks (triangle inequality).
    bound_by_part : ndarray, shape (4, n)
        The bound split: dropped single parts (inertial, velocity, gravity) and parameters
        dropped whole [N m or N].
    relative_peak : ndarray, shape (b, 3), optional
        Per pair, its largest peak contribution on the trajectory relative to the joint's
        scale, max_i peak_i / scale_i [1] (0: the part contributes nothing); None for a model
        read from a file.
    round_off : ndarray of bool, shape (b, 3), optional
        For a model read from a file: the pairs whose contribution was round-off on the
        trajectories the model was built on (stored as ``round_off``); None if not stored.
    structural_zero : ndarray of bool, shape (b, 3), optional
        For a model read from a file that does not store ``round_off``: the pairs that are
        identically 0 for its robot (:func:`structural_zeros`); None otherwise.

    Notes
    -----
    tau = Y_b(q, qd, qdd) beta (Khalil & Kleinfinger 1987; Gautier 1990), each column split
    into its inertial, Coriolis/centrifugal and gravity parts, i.e. into the D qdd, h and c of
    Fu, Gonzalez & Lee (1987), Eq. (3.4-24).
    """

    names: tuple
    beta: np.ndarray
    dropped: np.ndarray
    scale: np.ndarray
    bound: np.ndarray
    bound_by_part: np.ndarray
    relative_peak: np.ndarray | None = None
    round_off: np.ndarray | None = None
    structural_zero: np.ndarray | None = None

    def contributing(self) -> np.ndarray:
        """Which (parameter, part) pairs contribute on the trajectories the model was built on.

        Returns
        -------
        ndarray of bool, shape (b, 3)
            True where the pair's peak contribution is at least
            :data:`gd_analyze.config.ROUND_OFF` of the joint's scale (a pair
            below it, e.g. the gravity part of a product of inertia, is structurally 0 and
            neither kept nor dropped); where the model does not know, every pair but those
            identically 0 for its robot (:attr:`structural_zero`).
        """
        if self.relative_peak is not None:
            return np.asarray(self.relative_peak) >= ROUND_OFF
        if self.round_off is not None:
            return ~np.asarray(self.round_off, bool)
        if self.structural_zero is not None:
            return ~np.asarray(self.structural_zero, bool)
        return np.ones(np.shape(self.dropped), bool)

    def stated_facts(self) -> dict[str, Any]:
        """What the reports state about the model, counted once for all of them.

        Returns
        -------
        dict
            ``pairs``: contributing (parameter, part) pairs; ``dropped``: those dropped;
            ``dropped_pairs``: list of (parameter name, part name) dropped and contributing;
            ``gravity_dropped``: names of the parameters whose contributing gravity part
            (a term of c, Eq. (3.4-24)) is dropped; ``known``: False for a model read from a
            file that does not record which pairs contribute (every pair then counts but
            those identically 0 for its robot, :func:`structural_zeros`).
        """
        live = self.contributing()
        gone = np.asarray(self.dropped, bool) & live
        g = PART_NAMES.index("gravity")
        return {"pairs": int(live.sum()), "dropped": int(gone.sum()),
                "dropped_pairs": [(self.names[k], PART_NAMES[p])
                                  for k, p in zip(*np.nonzero(gone))],
                "gravity_dropped": [self.names[k] for k in np.nonzero(gone[:, g])[0]],
                "known": self.relative_peak is not None or self.round_off is not None}

    def base(self, robot: Robot) -> BaseParameters:
        """The :class:`gd_analyze.dynamics.base_parameters.BaseParameters` these names and values stand for.

        Parameters
        ----------
        robot : Robot
            The arm the model was built for.

        Returns
        -------
        BaseParameters
            With the stored beta; ``K`` empty (the program does not need it).
        """

        n = robot.n
        index = {f"{PARAMETER_NAMES[c]}{j + 1}": (j, c) for j in range(n) for c in range(10)}
        independent = np.zeros((n, 10), bool)
        for name in self.names:
            independent[index[name]] = True
        return BaseParameters(standard=standard_parameters(robot), independent=independent,
                              K=np.zeros((len(self.names), 0)), beta=np.array(self.beta, float),
                              rank=len(self.names))

    def program(self, robot: Robot, exact: Program | None = None) -> Program:
        """The straight-line program of the pruned model (:class:`~gd_analyze.symbolic.codegen.Program`).

        Parameters
        ----------
        robot : Robot
        exact : Program, optional
            The exact recursive program of these base parameters
            (:func:`.recursive.recursive_program` of ``self.base(robot).values``), when the
            caller has built it already.

        Returns
        -------
        Program
            tau [N m or N] of q, qd, qdd; the exact recursive program when nothing is dropped.
        """
        return self.choice(robot, exact)[0]

    def choice(self, robot: Robot, exact: Program | None = None,
               forms: Sequence[str] | None = None) -> tuple[Program, np.ndarray]:
        """:meth:`program` and the pairs it leaves out (:func:`.pruning.pruned_choice`).

        Parameters
        ----------
        robot : Robot
        exact : Program, optional
            As :meth:`program`.
        forms : sequence of str, optional
            The pruned program's forms (:func:`.pruning.pruned_choice`).

        Returns
        -------
        program : Program
        left_out : ndarray of bool, shape (b, 3)
            ``dropped``, or none where the exact program is the cheaper one.
        """

        return pruned_choice(robot, self.base(robot), self.dropped, exact=exact, forms=forms)

    def dropped_pairs(self) -> list[tuple[str, str]]:
        """The dropped pairs as (parameter name, part name), in parameter order.

        Returns
        -------
        list of (str, str)
        """
        return [(self.names[k], PART_NAMES[p]) for k, p in zip(*np.nonzero(self.dropped))]

    def to_dict(self) -> dict[str, Any]:
        """The model in the layout of ``simplified_model.json`` (key ``recursive``).

        Returns
        -------
        dict
        """
        live = self.contributing()
        gone = np.asarray(self.dropped, bool)
        pairs = [[self.names[k], PART_NAMES[p]] for k, p in zip(*np.nonzero(gone & live))]
        out = {"base_parameters": list(self.names),
               "beta": [float(v) for v in self.beta],
               "dropped": pairs,          # the pairs the reports name
               "scale": [float(v) for v in self.scale],
               "bound": [float(v) for v in self.bound],
               "bound_by_part": {name: [float(v) for v in self.bound_by_part[p]]
                                 for p, name in enumerate(BOUND_PARTS)}}
        if self.relative_peak is not None or self.round_off is not None:
            out["round_off"] = [[self.names[k], PART_NAMES[p]] for k, p in zip(*np.nonzero(~live))]
            # ≡ 0 pairs left out with their dropped parameter: listed apart, as round-off
            out["dropped_round_off"] = [[self.names[k], PART_NAMES[p]]
                                        for k, p in zip(*np.nonzero(gone & ~live))]
        return out

    @classmethod
    def from_dict(cls, spec: dict[str, Any], robot: Robot, path: str = "<model>") -> RecursiveModel:
        """Read the ``recursive`` key of a model file, checked against the robot.

        Parameters
        ----------
        spec : dict
            As :meth:`to_dict` writes it (shapes are checked here, types by the schema).
        robot : Robot
            The model file's robot.
        path : str, optional
            The file, for messages.

        Returns
        -------
        RecursiveModel

        Raises
        ------
        InputError
            If the base parameters differ from those derived again from the robot (names, or
            values by more than :data:`AGREEMENT` relative), a dropped pair names an unknown
            parameter or part, or a list has the wrong length. One line naming the key.
        """
        where = "recursive"
        base = base_parameters(robot)
        names = tuple(base.names())
        if tuple(spec["base_parameters"]) != names:
            raise InputError(f"the base parameters differ from those of the robot ({len(names)}"
                             f": {', '.join(names[:4])}, ...)", path,
                             column=f"{where}.base_parameters")
        beta = np.array(spec["beta"], float)
        scale = np.maximum(np.abs(base.beta), np.abs(base.beta).max(initial=0.0) * 1e-12)
        if beta.shape != base.beta.shape or not np.all(
                np.abs(beta - base.beta) <= AGREEMENT * np.where(scale > 0, scale, 1.0)):
            raise InputError("the base parameter values differ from those of the robot "
                             "(edited after the model was written?)", path,
                             column=f"{where}.beta")
        masks = {}
        for key in ("dropped", "round_off", "dropped_round_off"):
            if key not in spec:
                continue
            masks[key] = np.zeros((len(names), len(PARTS)), bool)
            for pair in spec[key]:
                if len(pair) != 2 or pair[0] not in names or pair[1] not in PART_NAMES:
                    raise InputError(f"unknown {key.replace('_', '-')} pair {pair!r}"[:120],
                                     path, column=f"{where}.{key}")
                masks[key][names.index(pair[0]), PART_NAMES.index(pair[1])] = True
        dropped = masks["dropped"] | masks.get("dropped_round_off", False)
        n = robot.n
        arrays = {}
        for key in ("scale", "bound"):
            arrays[key] = np.array(spec[key], float)
            if arrays[key].shape != (n,):
                raise InputError(f"expected {n} numbers", path, column=f"{where}.{key}")
        lists = [spec["bound_by_part"][p] for p in BOUND_PARTS]
        if any(len(v) != n for v in lists):         # ragged lists make no array: check first
            raise InputError(f"expected {len(BOUND_PARTS)} lists of {n} numbers", path,
                             column=f"{where}.bound_by_part")
        by_part = np.array(lists, float)
        # an older file, which does not record which pairs act: those its robot makes 0
        zero = None if "round_off" in masks else structural_zeros(names, robot.gravity)
        return cls(names=names, beta=base.beta, dropped=dropped, scale=arrays["scale"],
                   bound=arrays["bound"], bound_by_part=by_part,
                   round_off=masks.get("round_off"), structural_zero=zero)


def structural_zeros(names: Sequence[str], gravity: ArrayLike) -> np.ndarray:
    """The (base parameter, part) pairs whose contribution is identically 0 for any motion of
    an arm, from its base parameters and gravity alone.

    Parameters
    ----------
    names : sequence of str, length b
        The base parameters (:meth:`gd_analyze.dynamics.base_parameters.BaseParameters.names`).
    gravity : array_like, shape (3,)
        Gravity in the arm's base frame [m/s^2].

    Returns
    -------
    ndarray of bool, shape (b, 3)
        True for the gravity part of a second moment (XX .. ZZ: gravity enters the
        Newton-Euler recursion as a linear acceleration of the base, which no inertia tensor
        multiplies), and for every gravity part where gravity is 0 (c is linear in g, Fu,
        Gonzalez & Lee 1987, Eq. (3.4-24)); other pairs are not decided here (False).

    Examples
    --------
    >>> structural_zeros(["ZZ1", "MX2", "M2"], [0.0, 0.0, -9.81])[:, 2].tolist()
    [True, False, False]
    >>> structural_zeros(["ZZ1", "MX2", "M2"], [0.0, 0.0, 0.0])[:, 2].tolist()
    [True, True, True]
    """
    out = np.zeros((len(names), len(PART_NAMES)), bool)
    weightless = not np.any(np.asarray(gravity, float))
    out[:, PART_NAMES.index("gravity")] = [weightless or str(name)[:2] in PARAMETER_NAMES[:6]
                                           for name in names]
    return out


def recursive_model(robot: Robot, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, tolerance: float,
                    torque_floor: float = 0.0, base: BaseParameters | None = None,
                    peaks: tuple[np.ndarray, ...] | None = None,
                    chosen: tuple[np.ndarray, np.ndarray] | None = None) -> RecursiveModel:
    """Prune the recursive model within the error budget on a trajectory.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    q, qd, qdd : ndarray, shape (N, n)
        The trajectory [rad, rad/s, rad/s^2; m, m/s, m/s^2].
    tolerance : float
        EPS >= 0: every joint's dropped peaks add up to at most EPS scale_i,
        scale_i = max(peak |tau_i|, torque_floor); EPS = 0 gives the exact model.
    torque_floor : float, optional
        TAU [N m or N].
    base : BaseParameters, optional
        The robot's base parameters, if already derived.
    peaks : tuple of ndarray, optional
        :func:`.pruning.contribution_peaks` of ``base`` on the trajectory, if already
        computed.
    chosen : (ndarray of bool, ndarray of bool), optional
        The pairs (b, 3) and the parameters counted whole (b,) to drop, instead of searching
        them (:func:`.pruning.prune_bounds`): e.g. a model's pairs with some restored.

    Returns
    -------
    RecursiveModel

    Raises
    ------
    ValueError
        If tolerance or torque_floor is negative or not finite, the arrays are not (N, n), or
        the ``chosen`` pairs do not fit the budget.

    Notes
    -----
    The selection of :func:`.pruning.prune` (criterion "peaks": by the triangle inequality
    the error on the trajectory is within the bound). ``bound_by_part`` gives the dropped
    single parts' peaks per part and, last, the parameters dropped whole (by the peak of their
    whole contribution).
    """

    base = base_parameters(robot) if base is None else base
    pr = prune(robot, base, q, qd, qdd, tolerance, torque_floor=torque_floor, peaks=peaks)
    if chosen is not None:
        pr = prune_bounds(robot, base, pr.scale, pr.peak, pr.whole_peak, tolerance,
                          chosen=chosen)
    by_part = dropped_peaks(pr.peak, pr.whole_peak, pr.dropped, pr.whole)
    safe = np.where(pr.scale > 0, pr.scale, 1.0)
    rel = np.where(pr.scale > 0, pr.peak / safe, np.where(pr.peak > 0, np.inf, 0.0)).max(axis=2)
    return RecursiveModel(names=tuple(base.names()), beta=np.array(base.beta, float),
                          dropped=np.array(pr.dropped, bool), scale=np.array(pr.scale, float),
                          bound=np.array(pr.bound, float), bound_by_part=by_part,
                          relative_peak=rel)


def sweep_recursive_model(robot: Robot, scale: ArrayLike, peak: ArrayLike, whole_peak: ArrayLike,
                          tolerance: float,
                          base: BaseParameters | None = None) -> tuple[RecursiveModel, np.ndarray]:
    """Prune the recursive model within the error budget on each of K trajectories at once.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    scale : array_like, shape (K, n)
        scale_{t,i} = max(peak |tau_i| on trajectory t, torque floor) [N m or N].
    peak : array_like, shape (K, b, 3, n)
        Per trajectory, the peak |contribution| of each (base parameter, part)
        (:func:`.pruning.stacked_peaks`), or any bound on it, e.g. one proved on a region of
        states [N m or N].
    whole_peak : array_like, shape (K, b, n)
        The same per base parameter, all parts together [N m or N].
    tolerance : float
        EPS >= 0: on every trajectory t the dropped peaks of joint i add up to at most
        EPS scale_{t,i}; EPS = 0 gives the exact model.
    base : BaseParameters, optional
        The robot's base parameters, if already derived (the peaks must be of these).

    Returns
    -------
    model : RecursiveModel
        ``scale`` and ``bound`` (n,) are the largest over the trajectories [N m or N] (the
        bound holds on each); ``bound_by_part`` (4, n) is each part's largest over them (each
        row a bound of that part's error on every trajectory; their sum may exceed ``bound``,
        whose parts peak on different trajectories); ``relative_peak`` (b, 3) is each pair's
        largest ratio peak / scale_{t,i} over trajectories and joints.
    bound : ndarray, shape (K, 4, n)
        The bound on each trajectory split by part (:func:`.pruning.dropped_peaks`) [N m or
        N]: summed over the parts, at most EPS scale_{t,i}.

    Raises
    ------
    ValueError
        As :func:`.pruning.prune_on_peaks`.

    Notes
    -----
    :func:`.pruning.prune_on_peaks`; by the triangle inequality the model's error on
    trajectory t is within the bound on t. Source: the customized recursive Newton-Euler
    model (Fu, Gonzalez & Lee 1987, Algorithm 3.1) on the base parameters (Khalil &
    Kleinfinger 1987; Gautier 1990).
    """

    base = base_parameters(robot) if base is None else base
    pr = prune_on_peaks(robot, base, scale, peak, whole_peak, tolerance)
    each = dropped_peaks(peak, whole_peak, pr.dropped, pr.whole)          # (K, 4, n)
    return RecursiveModel(names=tuple(base.names()), beta=np.array(base.beta, float),
                          dropped=np.array(pr.dropped, bool),
                          scale=np.asarray(scale, float).max(axis=0),
                          bound=each.sum(axis=1).max(axis=0), bound_by_part=each.max(axis=0),
                          relative_peak=pr.peak.max(axis=2)), each
