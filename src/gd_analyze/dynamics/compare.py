"""One interface to the four ways of computing tau = D(q) qdd + h(q, qd) + c(q).

============== ============================================================ ==================
method         how                                                          source
============== ============================================================ ==================
lagrange-euler traces of U_ij, U_ijk and the pseudo-inertias                Eqs. (3.2-26)-(34)
newton-euler   recursion in link coordinates; D, h, c by probing            Table 3.3, Pr. 3.11
gd             generalized d'Alembert, D = D_tran + D_rot, h = h_tran+h_rot Eqs. (3.4-24)-(28)
pinocchio      ``crba``, ``rnea``, ``computeGeneralizedGravity``            Carpentier 2019
============== ============================================================ ==================

:func:`compare` and :func:`compare_report` measure how far the four agree along a trajectory;
:func:`format_compare` prints the report. The operation counts in the report come from
:mod:`gd_analyze.dynamics.opcount`.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ..model.drives import rigid_links
from ..model.kinematics import as_states
from .dalembert import assemble_tau, gd_terms
from .lagrange_euler import le_terms
from .newton_euler import ne_tau, ne_terms
from .opcount import book_counts, joint_types, operation_counts
from .pinocchio import pinocchio_model

if TYPE_CHECKING:
    import xarray as xr

    from ..model.robot import Robot
    from .dalembert import GDTerms


__all__ = ["METHODS", "DynamicsResult", "dynamics", "inverse_dynamics", "compare",
           "compare_report", "format_compare"]

#: The formulations, in report order.
METHODS = ("lagrange-euler", "newton-euler", "gd", "pinocchio")
_QUANTITIES = ("D", "h", "c", "tau")
#: Set points per block of :func:`compare`: memory stays a few blocks whatever N is.
COMPARE_BLOCK = 8192


@dataclass(frozen=True, eq=False)
class DynamicsResult:
    """The dynamic coefficients of tau = D qdd + h + c at N set points, Eq. (3.2-26).

    Attributes
    ----------
    method : str
        The formulation that computed them, one of :data:`METHODS`.
    D : ndarray, shape (N, n, n)
        Inertia matrix [kg m^2].
    h : ndarray, shape (N, n)
        Coriolis and centrifugal torques [N m].
    c : ndarray, shape (N, n)
        Gravity loading [N m].

    Notes
    -----
    Fu, Gonzalez & Lee (1987): D, h, c are Eqs. (3.2-31), (3.2-32) and (3.2-34) whatever the
    formulation; G-D gives them as D_tran + D_rot, h_tran + h_rot and c, Eq. (3.4-24).
    """

    method: str
    D: np.ndarray
    h: np.ndarray
    c: np.ndarray

    def tau(self, qdd: ArrayLike) -> np.ndarray:
        """Joint torques tau = D qdd + h + c, Eq. (3.2-26).

        Parameters
        ----------
        qdd : array_like, shape (N, n)
            Joint accelerations [rad/s^2].

        Returns
        -------
        ndarray, shape (N, n)
            Joint torques [N m].

        Raises
        ------
        ValueError
            If qdd cannot be reshaped to (N, n).
        """
        return assemble_tau(self.D, self.h, self.c, qdd)


def _check_method(method):
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}; expected one of {', '.join(METHODS)}")


def _pinocchio(robot, q, qd, qdd=None):
    """D, h, c (and rnea's tau if qdd is given) set point by set point."""
    import pinocchio as pin

    model = pinocchio_model(robot, "full")
    data = model.createData()
    N, n = q.shape
    D, h, c = np.empty((N, n, n)), np.empty((N, n)), np.empty((N, n))
    tau = None if qdd is None else np.empty((N, n))
    zero = np.zeros(n)
    for k in range(N):
        M = pin.crba(model, data, q[k])
        D[k] = np.triu(M) + np.triu(M, 1).T
        c[k] = pin.computeGeneralizedGravity(model, data, q[k])
        h[k] = pin.rnea(model, data, q[k], qd[k], zero) - c[k]
        if qdd is not None:
            tau[k] = pin.rnea(model, data, q[k], qd[k], qdd[k])
    return D, h, c, tau


def dynamics(robot: Robot, q: ArrayLike, qd: ArrayLike, method: str) -> DynamicsResult:
    """D, h and c at N set points by one formulation.

    Parameters
    ----------
    robot : Robot
        The arm, with n revolute joints.
    q : array_like, shape (N, n) or (n,)
        Joint positions [rad].
    qd : array_like, shape (N, n) or (n,)
        Joint velocities [rad/s].
    method : {"lagrange-euler", "newton-euler", "gd", "pinocchio"}
        The formulation (see the module docstring).

    Returns
    -------
    DynamicsResult
        D (N, n, n) [kg m^2], h and c (N, n) [N m].

    Raises
    ------
    ValueError
        If method is unknown, or q or qd does not have shape (N, n).

    Notes
    -----
    L-E: Eqs. (3.2-31) to (3.2-34); N-E: Table 3.3 probed as in Problems 3.11 and 3.12; G-D:
    Eqs. (3.4-25) to (3.4-28); Pinocchio: one Python call per set point (slow for large N).
    """
    _check_method(method)
    q, qd = as_states(robot, q, qd)
    if method == "lagrange-euler":
        t = le_terms(robot, q, qd)
        D, h, c = t.D, t.h, t.c
    elif method == "newton-euler":
        D, h, c = ne_terms(robot, q, qd)
    elif method == "gd":
        t = gd_terms(robot, q, qd)
        D, h, c = t.D, t.h, t.c
    else:
        D, h, c, _ = _pinocchio(robot, q, qd)
    return DynamicsResult(method, D, h, c)


def inverse_dynamics(robot: Robot, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike,
                     method: str) -> np.ndarray:
    """Joint torques at N set points by each formulation's own route.

    Parameters
    ----------
    robot : Robot
        The arm, with n revolute joints.
    q : array_like, shape (N, n) or (n,)
        Joint positions [rad].
    qd : array_like, shape (N, n) or (n,)
        Joint velocities [rad/s].
    qdd : array_like, shape (N, n) or (n,)
        Joint accelerations [rad/s^2].
    method : {"lagrange-euler", "newton-euler", "gd", "pinocchio"}
        The formulation.

    Returns
    -------
    tau : ndarray, shape (N, n)
        Joint torques [N m].

    Raises
    ------
    ValueError
        If method is unknown or an array does not have shape (N, n).

    Notes
    -----
    L-E and G-D assemble D qdd + h + c (Eqs. (3.2-26), (3.4-24)); N-E runs one recursion with
    qdd (Algorithm 3.1); Pinocchio runs ``rnea``.
    """
    _check_method(method)
    q, qd, qdd = as_states(robot, q, qd, qdd)
    if method == "newton-euler":
        return ne_tau(robot, q, qd, qdd)
    if method == "pinocchio":
        return _pinocchio(robot, q, qd, qdd)[3]
    return dynamics(robot, q, qd, method).tau(qdd)


def compare(robot: Robot, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike,
            gd: GDTerms | None = None) -> dict[str, Any]:
    """Largest relative disagreement between each pair of formulations.

    Parameters
    ----------
    robot : Robot
        The arm, with n revolute joints.
    q : array_like, shape (N, n) or (n,)
        Joint positions [rad].
    qd : array_like, shape (N, n) or (n,)
        Joint velocities [rad/s].
    qdd : array_like, shape (N, n) or (n,)
        Joint accelerations [rad/s^2].
    gd : GDTerms, optional
        The G-D terms at these set points if the caller has them already (the main job does):
        they are used as they are instead of being computed again.

    Returns
    -------
    dict
        ``{quantity: {"<method a> vs <method b>": float}}`` for quantity in D, h, c, tau and the
        six pairs of :data:`METHODS`. Each figure is max|a - b| over all set points and
        elements divided by the larger of max|a| and max|b| (0 if both are 0, or for h and c
        both within 64 machine epsilons of the largest |tau|: round-off), gathered in
        blocks of :data:`COMPARE_BLOCK` set points. tau is each method's own route
        (:func:`inverse_dynamics`). Plain floats and strings: JSON-ready.

    Raises
    ------
    ValueError
        If an array does not have shape (N, n).

    Notes
    -----
    All four solve the same equations, Eq. (3.2-26); the figures are rounding-level (about
    1e-15) unless one formulation or the robot model is wrong. They compare the rigid links,
    the chapter's model: the drives' armature and friction are left out
    (:func:`gd_analyze.model.drives.rigid_links`).
    """
    robot = rigid_links(robot)
    q, qd, qdd = as_states(robot, q, qd, qdd)
    N = q.shape[0]
    pairs = list(combinations(METHODS, 2))
    # running maxima over the blocks: max|a - b| per pair, max|a| per method
    diff = {x: dict.fromkeys(pairs, 0.0) for x in _QUANTITIES}
    peak = {x: dict.fromkeys(METHODS, 0.0) for x in _QUANTITIES}
    step = max(1, N if gd is not None else COMPARE_BLOCK)   # given terms: the caller's, whole
    given = {} if gd is None else {"gd": DynamicsResult("gd", gd.D_tran + gd.D_rot, gd.h, gd.c)}
    for start in range(0, N, step):
        b = slice(start, start + step)
        results = {m: given[m] if m in given else dynamics(robot, q[b], qd[b], m)
                   for m in METHODS}
        taus = {m: results[m].tau(qdd[b]) if m in given else
                inverse_dynamics(robot, q[b], qd[b], qdd[b], m) for m in METHODS}
        for quantity in _QUANTITIES:
            values = taus if quantity == "tau" else {m: getattr(r, quantity)
                                                     for m, r in results.items()}
            for m in METHODS:
                peak[quantity][m] = float(np.maximum(peak[quantity][m],
                                                     np.max(np.abs(values[m]))))
            for a, c in pairs:
                diff[quantity][a, c] = float(np.maximum(diff[quantity][a, c], np.max(
                    np.abs(np.asarray(values[a], float) - np.asarray(values[c], float)))))
    tiny = np.finfo(float).tiny
    # h and c in both within 64 eps of the largest |tau| are round-off, equal (a one-joint
    # arm's h: 1e-17 against 0 is no relative disagreement of 1)
    noise = 64 * np.finfo(float).eps * max(peak["tau"].values())
    return {quantity: {f"{a} vs {c}": 0.0 if quantity in ("h", "c") and max(
        peak[quantity][a], peak[quantity][c]) <= noise else float(diff[quantity][a, c] / np.maximum(
            np.maximum(peak[quantity][a], peak[quantity][c]), tiny)) for a, c in pairs}
        for quantity in _QUANTITIES}


def compare_report(robot: Robot, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike) -> dict[str, Any]:
    """Agreement of the four formulations and their operation counts, for the CLI.

    Parameters
    ----------
    robot : Robot
        The arm, with n revolute joints.
    q : array_like, shape (N, n) or (n,)
        Joint positions [rad].
    qd : array_like, shape (N, n) or (n,)
        Joint velocities [rad/s].
    qdd : array_like, shape (N, n) or (n,)
        Joint accelerations [rad/s^2].

    Returns
    -------
    dict
        ``robot`` (str), ``n`` (int), ``set_points`` (int), ``methods`` (list of str),
        ``agreement`` (the dict of :func:`compare`), ``max_disagreement`` (float, over all
        quantities and pairs) and ``operation_counts``: ``{method: {"multiplications",
        "additions", "multiplications_table_3_5", "additions_table_3_5"}}`` per set point for
        lagrange-euler, newton-euler, gd (compiled G-D engine) and gd-numpy (array G-D
        engine), see :func:`gd_analyze.dynamics.opcount.operation_counts`. JSON-ready.

    Raises
    ------
    ValueError
        If an array does not have shape (N, n).
    """
    q, qd, qdd = as_states(robot, q, qd, qdd)
    agreement = compare(robot, q, qd, qdd)
    counts, book = operation_counts(robot), book_counts(robot.n)
    ops = {m: {**counts[m], **{f"{k}_table_3_5": v for k, v in book[m].items()}}
           for m in counts}
    return {
        "robot": robot.name, "n": robot.n, "set_points": int(q.shape[0]),
        "methods": list(METHODS), "agreement": agreement,
        "max_disagreement": max(v for d in agreement.values() for v in d.values()),
        "operation_counts": ops,
    }


def format_compare(report: dict[str, Any]) -> str:
    """A human-readable table of a :func:`compare_report` dictionary.

    Parameters
    ----------
    report : dict
        As returned by :func:`compare_report` (or read back from its JSON).

    Returns
    -------
    str
        Several lines: the largest relative disagreement per pair for D, h, c and tau, then the
        operation counts per set point beside Table 3.5.

    Raises
    ------
    KeyError
        If the report lacks one of the keys of :func:`compare_report`.
    """
    agreement = report["agreement"]
    pairs = list(agreement["D"])
    width = max(len(p) for p in pairs)
    lines = [f"{report['robot']} (n = {report['n']}), {report['set_points']} set points",
             "", "Largest relative disagreement, max|a - b| / max(max|a|, max|b|):",
             f"{'pair':<{width}}  " + "  ".join(f"{q:>9}" for q in _QUANTITIES)]
    lines.extend(f"{p:<{width}}  " + "  ".join(f"{agreement[q][p]:9.2e}" for q in _QUANTITIES)
                 for p in pairs)
    lines += ["", "Operations per set point (measured as implemented / Fu, Gonzalez & Lee "
              "Table 3.5):",
              f"{'method':<15} {'mult':>8} {'add':>8} {'mult T3.5':>10} {'add T3.5':>10}"]
    for m, c in report["operation_counts"].items():
        lines.append(f"{m:<15} {c['multiplications']:>8} {c['additions']:>8} "
                     f"{c['multiplications_table_3_5']:>10.0f} {c['additions_table_3_5']:>10.0f}")
    return "\n".join(lines)


#: Set points at most used by :func:`formulations_dataset` (evenly spread).
FORMULATIONS_MAX_SETPOINTS = 200


def formulations_dataset(robot: Robot, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike,
                         n_max: int = 10, max_setpoints: int = FORMULATIONS_MAX_SETPOINTS,
                         gd: GDTerms | None = None) -> xr.Dataset:
    """The formulations' agreement along a trajectory and their costs, as a Dataset to store.

    Parameters
    ----------
    robot : Robot
        The arm, with n revolute joints.
    q, qd, qdd : array_like, shape (N, n)
        Joint positions [rad], velocities [rad/s] and accelerations [rad/s^2]; at most
        ``max_setpoints`` of them, evenly spread, are compared.
    n_max : int, optional
        Operation counts are tabulated for generated chains of n = 1..n_max joints.
    max_setpoints : int, optional
        Bound on the set points compared (L-E and N-E probing are slow per set point).
    gd : GDTerms, optional
        The G-D terms at the same N set points, if the caller has them (see :func:`compare`).

    Returns
    -------
    xarray.Dataset
        ``formulation_disagreement`` (pair, quantity): largest relative disagreement of each
        pair of L-E, N-E, G-D and Pinocchio for D, h, c and tau; ``op_multiplications`` and
        ``op_additions`` (dof, formulation): counts per set point as implemented;
        ``op_multiplications_table_3_5`` and ``op_additions_table_3_5`` (dof, formulation):
        the formulas of Table 3.5 (n revolute joints); ``op_multiplications_arm`` and
        ``op_additions_arm`` (formulation): the counts for this arm's joint types. Attributes
        ``formulations_setpoints``, ``formulations_n`` and ``formulations_joint_types`` (e.g.
        "RRPRRR").

    Raises
    ------
    ValueError
        If an array does not have shape (N, n).

    Notes
    -----
    Source: Table 3.5 of Fu, Gonzalez & Lee (1987); counting rule in :mod:`gd_analyze.dynamics.opcount`.
    """
    import xarray as xr

    q, qd, qdd = as_states(robot, q, qd, qdd)
    N = q.shape[0]
    idx = np.unique(np.linspace(0, N - 1, min(N, max_setpoints)).round().astype(int))
    sample = None if gd is None else gd.rows(idx)
    agreement = compare(robot, q[idx], qd[idx], qdd[idx], gd=sample)
    pairs = list(next(iter(agreement.values())))
    disagreement = np.array([[agreement[k][p] for k in _QUANTITIES] for p in pairs])
    methods = list(operation_counts(1))
    dofs = np.arange(1, n_max + 1)
    got = [operation_counts(int(n)) for n in dofs]
    arm = operation_counts(robot)
    book = [book_counts(int(n)) for n in dofs]

    def grid(source, op):
        return np.array([[float(s[m][op]) for m in methods] for s in source])

    def var(dims, data, long_name):
        return (dims, data, {"units": "1", "long_name": long_name})

    return xr.Dataset(
        {
            "formulation_disagreement": var(
                ("formulation_pair", "quantity"), disagreement,
                "largest |a - b| over the larger of max|a|, max|b|, per pair of formulations"),
            "op_multiplications": var(("dof", "formulation"), grid(got, "multiplications"),
                                      "multiplications per set point, as implemented"),
            "op_additions": var(("dof", "formulation"), grid(got, "additions"),
                                "additions per set point, as implemented"),
            "op_multiplications_arm": var(("formulation",), np.array(
                [float(arm[m]["multiplications"]) for m in methods]),
                "multiplications per set point for this arm's joint types, as implemented"),
            "op_additions_arm": var(("formulation",), np.array(
                [float(arm[m]["additions"]) for m in methods]),
                "additions per set point for this arm's joint types, as implemented"),
            "op_multiplications_table_3_5": var(("dof", "formulation"),
                                                grid(book, "multiplications"),
                                                "multiplications per set point, Table 3.5"),
            "op_additions_table_3_5": var(("dof", "formulation"), grid(book, "additions"),
                                          "additions per set point, Table 3.5"),
        },
        coords={
            "formulation_pair": ("formulation_pair", np.array(pairs, dtype=str),
                                 {"units": "1", "long_name": "pair of formulations"}),
            "quantity": ("quantity", np.array(_QUANTITIES, dtype=str),
                         {"units": "1", "long_name": "compared quantity"}),
            "dof": ("dof", dofs, {"units": "1", "long_name": "number of joints n"}),
            "formulation": ("formulation", np.array(methods, dtype=str),
                            {"units": "1", "long_name": "formulation (gd: compiled G-D engine, "
                                                        "gd-numpy: array G-D engine)"}),
        },
        attrs={"formulations_setpoints": int(idx.size), "formulations_n": robot.n,
               "formulations_joint_types": joint_types(robot)},
    )


__all__.append("formulations_dataset")
