"""Standard parameters from identified base parameters, and physical consistency.

The base parameters are linear in the standard ones, beta = A phi with A = [I K] in the
columns (B, D) of :class:`~gd_analyze.dynamics.base_parameters.BaseParameters` (Gautier
1990). Many phi give the same beta; two choices:

- :func:`closest_standard`: the phi closest to the prior phi_0 (the robot file's) that
  reproduces beta exactly, min ||S^-1 (phi - phi_0)|| subject to A phi = beta, by the
  minimum-norm solution of the underdetermined system (S: per kind, the largest prior
  |value| of the inertias, first moments and masses);
- :func:`consistent_standard`: physically consistent parameters, every link's pseudo-inertia
  positive semidefinite (Wensing, Kim & Slotine, "Linear matrix inequalities for physically
  consistent inertial parameter identification: a statistical perspective on the mass
  distribution", IEEE RA-L 3(1), 2018, arXiv 2017), and armature, viscous and Coulomb
  friction >= 0. Two convex problems with cvxpy (Clarabel, else SCS): first the smallest
  weighted torque residual ||R (theta(phi, d) - theta_hat)|| any consistent parameters reach
  (0 when the identified base parameters are consistent), then among the consistent
  parameters within that residual the ones closest to the prior. The unknowns are the
  deviations from the prior in units of S times the largest of the closest deviation
  (:func:`closest_standard`'s), so that they are of order 1 however far off the prior is.

The pseudo-inertia of a link with inertia J about the joint's origin, first moment h = m c and
mass m is P = [[tr(J)/2 1 - J, h], [h^T, m]] (Wensing et al., Eq. (7)).
"""

from __future__ import annotations

import dataclasses
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from ..dynamics.base_parameters import _kind_scales

if TYPE_CHECKING:
    from ..dynamics.base_parameters import BaseParameters
    from ..model.robot import Robot

__all__ = ["base_map", "closest_standard", "pseudo_inertia", "min_eigenvalues",
           "consistent_standard", "Consistent", "robot_with_standard", "SolverFailure",
           "ROUNDING", "rounding_cleaned", "loadable"]


def base_map(base: BaseParameters) -> npt.NDArray[np.float64]:
    """A with beta = A phi (phi flat, link-major).

    Parameters
    ----------
    base : BaseParameters

    Returns
    -------
    ndarray, shape (b, 10 n)
    """
    ind = base.independent.reshape(-1)
    A = np.zeros((base.rank, ind.size))
    A[:, np.flatnonzero(ind)] = np.eye(base.rank)
    A[:, np.flatnonzero(~ind)] = base.K
    return A


def _scales(phi0):
    """S: per standard parameter its kind's prior scale (:func:`_kind_scales`), flat."""
    phi0 = np.asarray(phi0, float)
    return np.tile(_kind_scales(phi0), phi0.shape[0])


def closest_standard(base: BaseParameters, beta: npt.NDArray[np.float64],
                     phi0: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """The standard parameters closest to the prior that reproduce beta.

    Parameters
    ----------
    base : BaseParameters
    beta : ndarray, shape (b,)
        Base parameter values [kg m^2, kg m, kg].
    phi0 : ndarray, shape (n, 10)
        The prior's standard parameters.

    Returns
    -------
    ndarray, shape (n, 10)
        phi = phi_0 + S (A S)^+ (beta - A phi_0), the minimum of ||S^-1 (phi - phi_0)|| with
        A phi = beta.
    """
    phi0 = np.asarray(phi0, float)
    A = base_map(base)
    S = _scales(phi0)
    u = np.linalg.lstsq(A * S, np.asarray(beta, float) - A @ phi0.reshape(-1), rcond=None)[0]
    return (phi0.reshape(-1) + S * u).reshape(phi0.shape)


def pseudo_inertia(phi: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Each link's pseudo-inertia matrix.

    Parameters
    ----------
    phi : ndarray, shape (n, 10)
        Standard parameters (XX, XY, XZ, YY, YZ, ZZ, MX, MY, MZ, M).

    Returns
    -------
    ndarray, shape (n, 4, 4)
        P = [[tr(J)/2 1 - J, h], [h^T, m]] [kg m^2].

    Examples
    --------
    >>> P = pseudo_inertia(np.array([[1.0, 0, 0, 1.0, 0, 1.0, 0, 0, 0, 1.0]]))
    >>> np.linalg.eigvalsh(P[0]).round(3).tolist()
    [0.5, 0.5, 0.5, 1.0]
    """
    phi = np.asarray(phi, float)
    n = phi.shape[0]
    J = np.empty((n, 3, 3))
    for k, (a, b) in enumerate(((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))):
        J[:, a, b] = J[:, b, a] = phi[:, k]
    P = np.zeros((n, 4, 4))
    P[:, :3, :3] = 0.5 * np.trace(J, axis1=1, axis2=2)[:, None, None] * np.eye(3) - J
    P[:, :3, 3] = P[:, 3, :3] = phi[:, 6:9]
    P[:, 3, 3] = phi[:, 9]
    return P


def min_eigenvalues(phi: npt.NDArray[np.float64]) -> npt.NDArray[np.floating[Any]]:
    """The smallest eigenvalue of each link's pseudo-inertia.

    Parameters
    ----------
    phi : ndarray, shape (n, 10)

    Returns
    -------
    ndarray, shape (n,)
        [kg m^2]; >= 0 for a physically consistent link.
    """
    return np.linalg.eigvalsh(pseudo_inertia(phi))[:, 0]


@dataclass(frozen=True, eq=False)
class Consistent:
    """Physically consistent parameters.

    Attributes
    ----------
    phi : ndarray, shape (n, 10)
        Standard parameters, each link's pseudo-inertia PSD.
    drives : ndarray, shape (n_d,)
        The drive parameters, armature and friction >= 0.
    residual : float
        ||R (theta - theta_hat)|| / ||R theta_hat|| of the solution.
    reproduces : bool
        True if the identified base and drive parameters were reached (residual below
        :data:`REPRODUCED`).
    solver : str
    closest : bool
        True if, among the consistent parameters of the smallest residual, these are the
        closest to the prior (the second problem solved); False if only the first was: the
        consistent parameters of the smallest residual the solver found.
    """

    phi: np.ndarray
    drives: np.ndarray
    residual: float
    reproduces: bool
    solver: str
    closest: bool = True


#: A relative weighted residual below this counts as reproducing the identified parameters.
REPRODUCED = 1e-7


def _psd_blocks(cp, phi, n):
    out = []
    for j in range(n):
        x = phi[10 * j:10 * j + 10]
        XX, XY, XZ, YY, YZ, ZZ, MX, MY, MZ, M = (x[k] for k in range(10))
        tr = 0.5 * (XX + YY + ZZ)
        out.append(cp.bmat([[tr - XX, -XY, -XZ, MX], [-XY, tr - YY, -YZ, MY],
                            [-XZ, -YZ, tr - ZZ, MZ], [MX, MY, MZ, M]]))
    return out


def consistent_standard(base: BaseParameters, theta_hat: npt.NDArray[np.float64],
                        identifiable: npt.NDArray[np.bool_], R: npt.NDArray[np.float64],
                        phi0: npt.NDArray[np.float64], drive_kinds: Sequence[str],
                        drive_prior: npt.NDArray[np.float64], margin: float = 1e-9) -> Consistent:
    """Physically consistent standard parameters and drives closest to the prior among those
    that fit the data best (two convex problems, module docstring).

    Parameters
    ----------
    base : BaseParameters
    theta_hat : ndarray, shape (p,)
        Identified (beta, drives), p = b + n_d.
    identifiable : ndarray of bool, shape (p,)
    R : ndarray, shape (r, r)
        The weighted regressor's triangular factor on the identifiable columns
        (:class:`~gd_analyze.estimation.estimate.Estimate`).
    phi0 : ndarray, shape (n, 10)
        The prior's standard parameters.
    drive_kinds : sequence of str
        Per drive column its kind (``armature``, ``viscous``, ``coulomb``, ``offset``).
    drive_prior : ndarray, shape (n_d,)
        The prior's drive values.
    margin : float, optional
        Each pseudo-inertia >= margin x the prior's inertia scale x identity, so that rounding
        in the files keeps it >= 0; 100 x margin where both solvers' solutions end below 0
        within their tolerance.

    Returns
    -------
    Consistent

    Raises
    ------
    SolverFailure
        If neither Clarabel nor SCS solves the first problem (a RuntimeError), or each solution
        it calls (inaccurately) optimal has a pseudo-inertia not >= 0 (to 1e-10 of its scale).
        Where no solver solves the second problem (its feasible set a sliver around the first's
        optimum: a small arm whose prior is far off, in units of its largest link's), the
        first's consistent solution of the smallest residual is returned, ``closest`` False.
    """
    import cvxpy as cp

    phi0 = np.asarray(phi0, float)
    n = phi0.shape[0]
    A = base_map(base)
    theta_hat = np.asarray(theta_hat, float)
    b = base.rank
    nd = theta_hat.size - b
    # u of order 1: S times k, the prior's largest deviation to the closest beta in units of
    # S (1 for a prior tens of percent off, 10^6 for one in grams), and the drives' term of
    # the second cost divided by k^2: the same minimiser, which the solvers now find
    S = _scales(phi0)
    k = max(1.0, float(np.abs(np.linalg.lstsq(A * S, theta_hat[:b] - A @ phi0.reshape(-1),
                                              rcond=None)[0]).max(initial=0.0)))
    S = k * S
    drive_prior = np.asarray(drive_prior, float)
    d_scale = np.maximum(np.maximum(np.abs(theta_hat[b:]), np.abs(drive_prior)),
                         1e-6 * max(1.0, float(np.abs(theta_hat[b:]).max(initial=0.0))))
    u = cp.Variable(10 * n)                 # phi = phi0 + S u
    v = cp.Variable(nd)                     # d = theta_hat_d + d_scale v
    phi = phi0.reshape(-1) + cp.multiply(S, u)
    d = theta_hat[b:] + cp.multiply(d_scale, v)
    theta = cp.hstack([A @ phi, d]) if nd else A @ phi
    ok = np.flatnonzero(identifiable)
    target = R @ theta_hat[ok]
    norm = max(float(np.linalg.norm(target)), 1e-300)
    resid = cp.norm(R @ theta[ok] - target) / norm
    nonneg = [k for k, kind in enumerate(drive_kinds) if kind != "offset"]
    second_cost = cp.sum_squares(u) + cp.sum_squares(
        cp.multiply(d_scale, v) + theta_hat[b:] - drive_prior) / k ** 2 if nd else cp.sum_squares(u)
    solver, why, firsts = None, [], []

    def consistent(u_v):        # phi of u, if each pseudo-inertia >= 0 to 1e-10 of its scale
        phi_v = (phi0.reshape(-1) + S * u_v).reshape(n, 10)
        return None if (min_eigenvalues(phi_v) < -1e-10 * np.abs(phi_v[:, :6]).max(
            axis=1)).any() else phi_v

    # Clarabel, else SCS, for both stages together; where both end a hair below 0 (within
    # their tolerance), both again with a margin 100 times larger
    for name, times in (("CLARABEL", 1), ("SCS", 1), ("CLARABEL", 100), ("SCS", 100)):
        eps = times * margin * float(_kind_scales(phi0)[0])
        cons = [P >> eps * np.eye(4) for P in _psd_blocks(cp, phi, n)]
        cons += [d[nonneg] >= 0] if nonneg else []
        label = name if times == 1 else f"{name} with {times}x the margin"
        try:
            first = cp.Problem(cp.Minimize(resid), cons)
            with warnings.catch_warnings():         # the status is checked instead
                warnings.simplefilter("ignore")
                first.solve(solver=name)
            if first.status not in ("optimal", "optimal_inaccurate"):
                why.append(f"{label}: {first.status}")
                continue
            if (phi_v := consistent(u.value)) is not None:    # kept, should the second fail
                firsts.append((float(first.value), name, phi_v, v.value if nd else None))
            bound = float(first.value) * (1 + 1e-6) + REPRODUCED * 0.1
            second = cp.Problem(cp.Minimize(second_cost), cons + [resid <= bound])
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                second.solve(solver=name)
            if second.status not in ("optimal", "optimal_inaccurate"):
                why.append(f"{label}: second stage {second.status}")
                continue
            if (phi_v := consistent(u.value)) is None:
                why.append(f"{label}: {second.status}, but a pseudo-inertia not >= 0")
                continue        # an inaccurate solution that is not consistent: not one
        except cp.error.SolverError as exc:
            why.append(f"{label}: {str(exc).splitlines()[0] if str(exc) else 'failed'}")
            continue
        solver = name
        break
    if solver is None and not firsts:
        raise SolverFailure("the consistency problem was solved by neither Clarabel nor SCS ("
                            + "; ".join(why) + ")")
    closest = solver is not None
    if closest:
        v_v = v.value if nd else None
    else:                       # the first problem's consistent solution of least residual
        _, solver, phi_v, v_v = min(firsts, key=lambda f: f[0])
    d_v = theta_hat[b:] + d_scale * v_v if nd else np.zeros(0)
    if nonneg:
        d_v[nonneg] = np.maximum(d_v[nonneg], 0.0)
    th = np.concatenate([A @ phi_v.reshape(-1), d_v])
    residual = float(np.linalg.norm(R @ th[ok] - target) / norm)
    return Consistent(phi=phi_v, drives=d_v, residual=residual,
                      reproduces=residual <= REPRODUCED, solver=str(solver), closest=closest)


class SolverFailure(RuntimeError):
    """Neither Clarabel nor SCS solved the consistency problem (a numerical failure of the
    solvers, not of the input's form)."""


def robot_with_standard(robot: Robot, phi: npt.NDArray[np.float64],
                        armature: npt.NDArray[np.float64] | None = None,
                        viscous: npt.NDArray[np.float64] | None = None,
                        coulomb: npt.NDArray[np.float64] | None = None,
                        torque_offset: npt.NDArray[np.float64] | None = None) -> Robot:
    """A copy of the robot with the given standard parameters and drives.

    Parameters
    ----------
    robot : Robot
        The arm (geometry, limits, names kept).
    phi : ndarray, shape (n, 10)
        Standard parameters, body frame, about the joint's origin; a link with mass 0 gets
        its centre of mass at the link frame's origin (its first moment must then be 0).
    armature, viscous, coulomb, torque_offset : ndarray, shape (n,), optional
        The drives; default the robot's.

    Returns
    -------
    Robot
        Mass m, centre of mass c = h / m and inertia about it I_c = J - m (c^T c 1 - c c^T)
        (parallel-axis theorem), both turned into link frame i (L_R^T (c - L_t), L_R^T I_c L_R).

    Raises
    ------
    ValueError
        If a mass is negative, or the robot rejects a drive (< 0).
    """
    phi = np.asarray(phi, float)
    m = phi[:, 9].copy()
    if (m < 0).any():
        raise ValueError(f"negative mass of link {int(np.flatnonzero(m < 0)[0]) + 1}")
    h = phi[:, 6:9]
    c = np.divide(h, m[:, None], out=np.zeros_like(h), where=m[:, None] > 0)
    Sigma = pseudo_inertia(phi)[:, :3, :3]       # tr(J)/2 1 - J, so J = tr(Sigma) 1 - Sigma
    Jo = np.trace(Sigma, axis1=1, axis2=2)[:, None, None] * np.eye(3) - Sigma
    Ic = Jo - m[:, None, None] * (np.einsum("ia,ia->i", c, c)[:, None, None] * np.eye(3)
                                  - c[:, :, None] * c[:, None, :])
    Ic = 0.5 * (Ic + np.swapaxes(Ic, 1, 2))
    LR, Lt = robot.link_rotation, robot.link_translation
    com = np.einsum("iba,ib->ia", LR, c - Lt)
    inertia = np.swapaxes(LR, 1, 2) @ Ic @ LR
    changes = {"mass": m, "com": com, "inertia": inertia}
    for key, value in (("armature", armature), ("viscous", viscous), ("coulomb", coulomb),
                       ("torque_offset", torque_offset)):
        if value is not None:
            changes[key] = np.asarray(value, float).copy()
    return dataclasses.replace(robot, **changes)


#: Relative size of a negative mass, first moment or friction taken for a rounding error of
#: a true 0 (:func:`rounding_cleaned`).
ROUNDING = 1e-12


def rounding_cleaned(phi: np.ndarray, drives: np.ndarray, nonneg: np.ndarray
                     ) -> tuple[np.ndarray, np.ndarray]:
    """The standard parameters and drives with rounding-level negatives set to 0.

    Parameters
    ----------
    phi : ndarray, shape (n, 10)
        Standard parameters per link: XX, XY, XZ, YY, YZ, ZZ about the link frame's origin
        [kg m^2], m X, m Y, m Z [kg m], m [kg].
    drives : ndarray, shape (d,)
        The drive values (armature, friction, offset) [SI].
    nonneg : ndarray of bool, shape (d,)
        The drive values that cannot be negative (frictions, armatures).

    Returns
    -------
    phi, drives : ndarray
        Copies, cleaned as below.

    Notes
    -----
    A link of mass 0 (or a friction of 0) in the true arm comes out of a noise-free fit as
    +-1e-18: a mass below ``ROUNDING`` x the largest mass becomes 0, with its first moments
    when they are as small, a negative principal moment about the centre of mass above
    -``ROUNDING`` x the largest inertia parameter becomes 0 (an unidentifiable link's moments
    come out as +-1e-17, which Pinocchio refuses), and a friction below ``ROUNDING`` x the
    largest drive value becomes 0, so the robot file holds them (the torque changes by a
    rounding error).
    """
    phi, drives = np.array(phi, float), np.array(drives, float)
    m = phi[:, 9]
    tiny_m = np.abs(m) <= ROUNDING * max(1.0, float(np.abs(m).max(initial=0.0)))
    m[tiny_m] = 0.0
    h_scale = ROUNDING * max(1.0, float(np.abs(phi[:, 6:9]).max(initial=0.0)))
    zero_h = (m == 0) & (np.abs(phi[:, 6:9]).max(axis=1) <= h_scale)
    phi[zero_h, 6:9] = 0.0
    phi[:, :6] = _rounding_moments(phi, ROUNDING * max(1.0, float(np.abs(phi[:, :6]).max(
        initial=0.0))))
    d_scale = ROUNDING * max(1.0, float(np.abs(drives).max(initial=0.0)))
    drives[nonneg & (drives < 0) & (drives >= -d_scale)] = 0.0
    return phi, drives


def _rounding_moments(phi, tol):
    """XX..ZZ (n, 6) with each link's principal moments about its centre of mass in
    [-tol, tol / 2) raised to tol / 2 (Huygens-Steiner, Fu, Gonzalez & Lee 1987, Sec. 3.2), where
    none is below -tol: not to 0, since a tensor with a zero moment, or rebuilt from its
    eigenvectors, carries their round-off (about 1e-16 of its largest moment), which left a
    zero moment at -1e-18 on one CPU and Pinocchio refused it."""
    m = phi[:, 9]
    c = np.divide(phi[:, 6:9], m[:, None], out=np.zeros((phi.shape[0], 3)),
                  where=m[:, None] > 0)
    shift = m[:, None, None] * (np.einsum("ia,ia->i", c, c)[:, None, None] * np.eye(3)
                                - c[:, :, None] * c[:, None, :])
    out = np.array(phi[:, :6], float)
    for k, (w, V) in enumerate(zip(*np.linalg.eigh(_moments(phi) - shift))):
        if (w < 0.5 * tol).any() and not (w < -tol).any():
            Ic = (V * np.maximum(w, 0.5 * tol)) @ V.T + shift[k]
            out[k] = [Ic[a, b] for a, b in ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))]
    return out


def _moments(phi):
    """(n, 3, 3): each link's inertia tensor about its frame's origin from XX..ZZ."""
    J = np.empty((phi.shape[0], 3, 3))
    for k, (a, b) in enumerate(((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))):
        J[:, a, b] = J[:, b, a] = phi[:, k]
    return J


def loadable(robot_phi: np.ndarray, drives_ok: bool) -> bool:
    """Whether the standard parameters make a robot file the loader accepts.

    Parameters
    ----------
    robot_phi : ndarray, shape (n, 10)
        Standard parameters per link, as :func:`rounding_cleaned` takes them.
    drives_ok : bool
        Whether the drive values are acceptable (no negative friction or armature).

    Returns
    -------
    bool
        Every mass >= 0, no first moment without mass, and every inertia tensor about the
        centre of mass positive semi-definite up to 1e-10 of its largest entry
        (Huygens-Steiner, Fu, Gonzalez & Lee 1987, Sec. 3.2).
    """
    phi = robot_phi
    m = phi[:, 9]
    if (m < 0).any() or not drives_ok:
        return False
    c = np.divide(phi[:, 6:9], m[:, None], out=np.zeros((phi.shape[0], 3)),
                  where=m[:, None] > 0)
    if ((m == 0) & (np.abs(phi[:, 6:9]).max(axis=1) > 0)).any():
        return False
    Ic = _moments(phi) - m[:, None, None] * (np.einsum("ia,ia->i", c, c)[:, None, None] * np.eye(3)
                                 - c[:, :, None] * c[:, None, :])
    tol = 1e-10 * np.maximum(1.0, np.abs(Ic).max(axis=(1, 2)))
    return bool((np.linalg.eigvalsh(Ic)[:, 0] >= -tol).all())
