"""The identification regressor: the base regressor with per-joint drive columns.

The joint torques of an arm with geared drives (:mod:`gd_analyze.model.drives`) are linear
in the base inertial parameters beta (:mod:`gd_analyze.dynamics.base_parameters`) and in four parameters per
joint i: the armature Ia_i [kg m^2], the viscous friction F_v,i [N m s/rad], the Coulomb
friction F_c,i [N m] and a torque offset tau_0,i [N m] (a sensor's or a current's bias;
prismatic joints: kg, N s/m, N, N)::

    tau_i = Y_b,i(q, qd, qdd) beta + Ia_i qdd_i + F_v,i qd_i + F_c,i sgn(qd_i) + tau_0,i

(Swevers, Ganseman, Tukel, De Schutter & Van Brussel, "Optimal robot excitation and
identification", IEEE Trans. Robot. Autom. 13(5), 1997; the friction model of
Armstrong-Helouvry, Dupont & Canudas de Wit, Automatica 30(7), 1994). Drive column k of joint
i is zero on every other joint's row. Some drive columns are combinations of base columns: the
armature of a first joint about the vertical is ``qdd_1`` on row 1, the column of ZZ_1 too (and
a second joint across it has ZZ_2's column ``qdd_2`` on row 2).
:func:`identification_columns` finds them as :func:`gd_analyze.dynamics.base_parameters.base_parameters` finds
the base parameters (QR of the scaled regressor stacked at random states, base columns first):
a dependent drive column is left out and its parameter is regrouped into the base parameters
it depends on. sgn may be smoothed to tanh(qd / v_s) (``coulomb_velocity`` v_s > 0).
:func:`with_drives` adds the same drive terms to a deployed model's program.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import symengine as se

from ..dynamics.base_parameters import BaseParameters, base_parameters, random_states
from ..dynamics.regressor_kernels import regressor_columns
from ..model.drives import DRIVE_FIELDS
from ..model.kinematics import as_states
from .codegen import Program

if TYPE_CHECKING:
    from ..model.robot import Robot

__all__ = ["DRIVE_COLUMNS", "drive_regressor", "IdentificationColumns",
           "identification_columns", "identification_regressor", "with_drives"]

#: The drive column kinds, in the order of the columns (kind-major: every joint's armature,
#: then every joint's viscous friction, ...).
DRIVE_COLUMNS = ("armature", "viscous", "coulomb", "offset")


def _checked_kinds(drives):
    kinds = tuple(drives)
    for k in kinds:
        if k not in DRIVE_COLUMNS:
            raise ValueError(f"unknown drive column {k!r} (expected some of "
                             f"{', '.join(DRIVE_COLUMNS)})")
    if len(set(kinds)) != len(kinds):
        raise ValueError(f"drive columns repeated: {kinds}")
    return tuple(k for k in DRIVE_COLUMNS if k in kinds)


def drive_regressor(qd: np.ndarray, qdd: np.ndarray, drives: Sequence[str] = DRIVE_COLUMNS,
                    coulomb_velocity: float = 0.0) -> np.ndarray:
    """The drive columns of every joint: qdd_i, qd_i, sgn(qd_i) and 1 on joint i's row.

    Parameters
    ----------
    qd, qdd : array_like, shape (N, n)
        Joint velocities [rad/s or m/s] and accelerations [rad/s^2 or m/s^2].
    drives : sequence of str, optional
        Some of :data:`DRIVE_COLUMNS`; they are taken in that order whatever the order given.
    coulomb_velocity : float, optional
        v_s [rad/s or m/s]: 0 (default) for sgn(qd) (sgn(0) = 0), else tanh(qd / v_s).

    Returns
    -------
    ndarray, shape (N, n, n k)
        ``D[s, i, c n + j]``: torque of joint i [N m or N] per unit drive parameter c of
        joint j, zero unless i = j; kind-major.

    Raises
    ------
    ValueError
        If a drive column is unknown or repeated, the arrays' shapes differ or are not
        (N, n), or coulomb_velocity is negative or not finite.

    Notes
    -----
    The drive torque Ia qdd + F_v qd + F_c sgn(qd) + tau_0 of Swevers et al. (1997), per joint.

    Examples
    --------
    >>> D = drive_regressor(np.array([[1.0, -2.0]]), np.array([[3.0, 4.0]]))
    >>> D[0, 1].tolist()        # joint 2's row: Ia, Fv, Fc, offset of joints 1 and 2
    [0.0, 4.0, 0.0, -2.0, 0.0, -1.0, 0.0, 1.0]
    """
    kinds = _checked_kinds(drives)
    qd = np.asarray(qd, float)
    qdd = np.asarray(qdd, float)
    if qd.ndim != 2 or qd.shape != qdd.shape:
        raise ValueError(f"qd and qdd need the same shape (N, n), got {qd.shape}, {qdd.shape}")
    v = float(coulomb_velocity)
    if not (np.isfinite(v) and v >= 0):
        raise ValueError(f"coulomb_velocity must be finite and >= 0, got {coulomb_velocity!r}")
    N, n = qd.shape
    values = {"armature": qdd, "viscous": qd,
              "coulomb": np.sign(qd) if v == 0 else np.tanh(qd / v),
              "offset": np.ones_like(qd)}
    out = np.zeros((N, n, n * len(kinds)))
    rows = np.arange(n)
    for c, kind in enumerate(kinds):
        out[:, rows, c * n + rows] = values[kind]
    return out


@dataclass(frozen=True, eq=False)
class IdentificationColumns:
    """The columns of an arm's identification regressor: base parameters and drive columns.

    Attributes
    ----------
    base : BaseParameters
        The base inertial parameters (:func:`gd_analyze.dynamics.base_parameters.base_parameters`).
    drives : tuple of str
        The drive columns per joint, in the order of :data:`DRIVE_COLUMNS`.
    drive_kept : ndarray of bool, shape (n, len(drives))
        Whether joint i's drive column c is independent of the base columns and of the kept
        drive columns before it; False: a combination of them (its parameter regroups into
        theirs, e.g. the armature of a first joint about the vertical into ZZ_1).
    coulomb_velocity : float
        v_s [rad/s or m/s] of tanh(qd / v_s); 0 for sgn(qd).
    """

    base: BaseParameters
    drives: tuple
    drive_kept: np.ndarray
    coulomb_velocity: float = 0.0

    @property
    def count(self) -> int:
        """int: the number of columns p = b + the kept drive columns."""
        return int(self.base.rank + self.drive_kept.sum())

    def names(self) -> list[str]:
        """Labels of the columns: the base parameters', then e.g. ``"viscous_3"``.

        Returns
        -------
        list of str, length p
        """
        return self.base.names() + self._drive_names(True)

    def _drive_names(self, kept):
        n = self.drive_kept.shape[0]
        return [f"{kind}_{j + 1}" for c, kind in enumerate(self.drives) for j in range(n)
                if self.drive_kept[j, c] == kept]

    @property
    def drive_mask(self) -> np.ndarray:
        """ndarray of bool, shape (n len(drives),): the kept drive columns, kind-major."""
        return self.drive_kept.T.reshape(-1)

    @classmethod
    def keeping_all(cls, base: BaseParameters, n: int, drives: Sequence[str] = DRIVE_COLUMNS,
                    coulomb_velocity: float = 0.0) -> IdentificationColumns:
        """The base columns with every drive column of the given kinds, none left out.

        For a fit that finds the columns not identifiable on its data itself (rank and
        condition of the data's regressor) rather than those dependent on every state
        (:func:`identification_columns`).

        Parameters
        ----------
        base : BaseParameters
            The arm's base parameters.
        n : int
            Joints.
        drives : sequence of str, optional
            Some of :data:`DRIVE_COLUMNS` (taken in that order).
        coulomb_velocity : float, optional
            v_s of :func:`drive_regressor` [rad/s or m/s]; 0 for sgn(qd).

        Returns
        -------
        IdentificationColumns

        Raises
        ------
        ValueError
            If a drive column is unknown or repeated.
        """
        kinds = _checked_kinds(drives)
        return cls(base=base, drives=kinds, drive_kept=np.ones((int(n), len(kinds)), bool),
                   coulomb_velocity=float(coulomb_velocity))

    def dropped(self) -> list[str]:
        """Labels of the drive columns left out as combinations of the others.

        Returns
        -------
        list of str
        """
        return self._drive_names(False)


def identification_columns(robot: Robot, drives: Sequence[str] = DRIVE_COLUMNS,
                           base: BaseParameters | None = None,
                           coulomb_velocity: float = 0.0, count: int | None = None,
                           seed: int = 0, tol: float = 1e-8) -> IdentificationColumns:
    """The structurally independent columns of the base regressor with drive columns.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    drives : sequence of str, optional
        Some of :data:`DRIVE_COLUMNS` (default all four).
    base : BaseParameters, optional
        The arm's base parameters, if already computed.
    coulomb_velocity : float, optional
        v_s of :func:`drive_regressor` [rad/s or m/s]; 0 for sgn(qd).
    count : int, optional
        Random set points of the stacked regressor; default max(20, 4 n).
    seed : int, optional
        Seed of the random set points (:func:`gd_analyze.dynamics.base_parameters.random_states`).
    tol : float, optional
        A drive column is kept when |R_jj| > tol max|R| in the QR of the stacked, column-scaled
        regressor [Y_b, D] (base columns first).

    Returns
    -------
    IdentificationColumns

    Raises
    ------
    ValueError
        If a drive column is unknown or repeated.

    Notes
    -----
    Gautier's numerical base parameters (ICRA 1990) applied to the drive columns: the base
    columns are independent by construction; a drive column whose QR diagonal entry is
    negligible is in the span of the columns before it on every state.

    Examples
    --------
    >>> from gd_analyze import load_robot
    >>> cols = identification_columns(load_robot("puma560"))
    >>> cols.dropped()      # joint 1 about the vertical, joint 2 across it: in ZZ1's and ZZ2's
    ['armature_1', 'armature_2']
    """
    kinds = _checked_kinds(drives)
    base = base_parameters(robot) if base is None else base
    n = robot.n
    count = max(20, 4 * n) if count is None else int(count)
    q, qd, qdd = random_states(robot, count, seed)
    Yb = regressor_columns(robot, np.flatnonzero(base.independent.reshape(-1)), q, qd, qdd)
    D = drive_regressor(qd, qdd, kinds, coulomb_velocity)
    W = np.concatenate([Yb, D], axis=2).reshape(count * n, -1)
    norms = np.linalg.norm(W, axis=0)
    zero = norms <= tol * norms.max(initial=0.0)
    R = np.linalg.qr(np.where(zero, 0.0, W / np.where(zero, 1.0, norms)), mode="r")
    diag = np.abs(np.diag(R))
    keep = diag > tol * max(diag.max(initial=0.0), 1e-300)
    return IdentificationColumns(base=base, drives=kinds,
                                 drive_kept=keep[base.rank:].reshape(len(kinds), n).T,
                                 coulomb_velocity=float(coulomb_velocity))


def identification_regressor(robot: Robot, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
                             columns: IdentificationColumns) -> np.ndarray:
    """The base regressor with the kept drive columns, tau = Y theta.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints (its inertial parameters are not read).
    q, qd, qdd : array_like, shape (N, n) or (n,)
        Joint positions, velocities and accelerations [rad, rad/s, rad/s^2; m, m/s, m/s^2].
    columns : IdentificationColumns
        The columns: :func:`identification_columns` (the drive columns independent of the
        others on every state) or :meth:`IdentificationColumns.keeping_all`.

    Returns
    -------
    ndarray, shape (N, n, p)
        ``Y[s, i, m]``: torque of joint i [N m or N] per unit parameter m at set point s, in
        the order of ``columns.names()``: the base parameters (with the robot's gravity), then
        the kept drive columns, kind-major.

    Raises
    ------
    ValueError
        If the arrays are not of shape (N, n) or (n,).

    Examples
    --------
    >>> from gd_analyze import load_robot
    >>> robot = load_robot("puma560")
    >>> cols = identification_columns(robot)
    >>> identification_regressor(robot, *np.zeros((3, 2, 6)), cols).shape
    (2, 6, 58)
    """
    q, qd, qdd = as_states(robot, q, qd, qdd)
    Yb = regressor_columns(robot, np.flatnonzero(columns.base.independent.reshape(-1)),
                           q, qd, qdd)
    D = drive_regressor(qd, qdd, columns.drives, columns.coulomb_velocity)
    return np.concatenate([Yb, D[:, :, columns.drive_mask]], axis=2)


def with_drives(program: Program, robot: Robot) -> Program:
    """The program with the robot's drive terms added to every tau_i, never dropped.

    Parameters
    ----------
    program : Program
        The rigid-link model, tau_i of q, qd, qdd.
    robot : Robot
        Its ``armature`` Ia [kg m^2], ``viscous`` F_v [N m s/rad], ``coulomb`` F_c [N m] and
        ``torque_offset`` tau_0 [N m].

    Returns
    -------
    Program
        The same program when the robot has no drives; else one whose tau_i adds
        Ia_i qdd_i + F_v,i qd_i + F_c,i sign(qd_i) + tau_0,i
        (:mod:`gd_analyze.model.drives`): one multiplication and one addition per
        nonzero coefficient, and one addition for the offset, at most 3 + 4 per joint
        (sign(qd) costs two comparisons, not counted).
    """
    arm, fv, fc, t0 = (np.asarray(getattr(robot, k), float) for k in DRIVE_FIELDS)
    if not (arm.any() or fv.any() or fc.any() or t0.any()):
        return program
    outputs = list(program.outputs)
    for i in range(program.n):
        qd, qdd = se.Symbol(f"qd{i}"), se.Symbol(f"qdd{i}")
        extra = [se.RealDouble(float(c)) * x for c, x in ((arm[i], qdd), (fv[i], qd),
                                                          (fc[i], se.sign(qd))) if c != 0.0]
        if t0[i] != 0.0:
            extra.append(se.RealDouble(float(t0[i])))
        outputs[i] = se.Add(outputs[i], *extra)
    return Program(program.n, program.assignments, outputs)
