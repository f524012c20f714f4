"""The robot and its trajectory as ``results.h5`` stores them: typed views for the readers.

:class:`StoredRobot` holds the robot's record (its links, its geometry, its drives and effort
limits, and where it came from); :class:`StoredTrajectory` the trajectory's (where it came
from, and its per-set-point series, read when asked so that a long file stays on disk). Both
are read once by :class:`gd_analyze.store.results_view.Results`; the names are those of
:mod:`gd_analyze.store.names`. An attribute's value is kept as stored (a string, a number or an
array; None where the file has none): the reader decides how to write it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .names import Attr, Var
from .schema import optional, strings

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr

__all__ = ["ROBOT_VARIABLES", "StoredRobot", "StoredTrajectory"]

#: The robot's variables every results file holds.
ROBOT_VARIABLES = (Var.LINK_MASS, Var.LINK_COM, Var.LINK_INERTIA, Var.DH_D, Var.DH_A,
                   Var.DH_ALPHA, Var.DH_OFFSET)


@dataclass(frozen=True, eq=False)
class StoredRobot:
    """The robot of a results file, as the main job stored it.

    Attributes
    ----------
    description, reference, source, sha256, gravity : object
        The attributes ``robot_description``, ``robot_reference``, ``robot_source`` (the robot
        file), ``robot_sha256`` and ``gravity`` [m/s^2] as stored; None where missing.
    joint_type : tuple of str or None, length n
        ``"revolute"`` or ``"prismatic"`` per joint; None in a file without it.
    link_mass : ndarray, shape (n,)
        [kg].
    link_com : ndarray, shape (n, 3)
        Each link's centre of mass in its frame [m].
    link_inertia : ndarray, shape (n, 3, 3)
        Each link's inertia about its centre of mass [kg m^2].
    dh : ndarray, shape (4, n)
        The DH rows d [m or -], a [m], alpha [rad] and the joint offset [rad or m], in that
        order; NaN for a robot given by joint placements (URDF, chain).
    joint_rotation : ndarray, shape (n, 3, 3), or None
        Each joint's fixed rotation in body frame i-1 (URDF, chain); None where not stored.
    joint_translation : ndarray, shape (n, 3), or None
        Its fixed translation [m]; None where not stored.
    armature, viscous, coulomb : ndarray, shape (n,), or None
        The drives: armature [kg m^2 or kg], viscous [N m s/rad or N s/m] and Coulomb
        friction [N m or N]; None in a file without drives.
    torque_offset : ndarray, shape (n,), or None
        A constant torque of each drive [N m or N]; None where not stored.
    effort_limit : ndarray, shape (n,), or None
        The effort limits |tau| <= tau_max [N m or N] (NaN: not given); None in a file written
        before they were stored.
    placeholder_inertia : bool
        The robot file gave no inertia: placeholders were used.
    """

    description: Any
    reference: Any
    source: Any
    sha256: Any
    gravity: Any
    joint_type: tuple[str, ...] | None
    link_mass: np.ndarray
    link_com: np.ndarray
    link_inertia: np.ndarray
    dh: np.ndarray
    joint_rotation: np.ndarray | None
    joint_translation: np.ndarray | None
    armature: np.ndarray | None
    viscous: np.ndarray | None
    coulomb: np.ndarray | None
    torque_offset: np.ndarray | None
    effort_limit: np.ndarray | None
    placeholder_inertia: bool

    @classmethod
    def from_dataset(cls, ds: xr.Dataset) -> StoredRobot:
        """The robot's record of a results dataset.

        Parameters
        ----------
        ds : xarray.Dataset
            Holding :data:`ROBOT_VARIABLES` (the caller checks them).

        Returns
        -------
        StoredRobot
        """
        a = ds.attrs
        return cls(
            description=a.get(Attr.ROBOT_DESCRIPTION), reference=a.get(Attr.ROBOT_REFERENCE),
            source=a.get(Attr.ROBOT_SOURCE), sha256=a.get(Attr.ROBOT_SHA256),
            gravity=a.get(Attr.GRAVITY),
            joint_type=(tuple(strings(ds[Var.JOINT_TYPE].values))
                        if Var.JOINT_TYPE in ds.variables else None),
            link_mass=ds[Var.LINK_MASS].values, link_com=ds[Var.LINK_COM].values,
            link_inertia=ds[Var.LINK_INERTIA].values,
            dh=np.stack([ds[v].values for v in (Var.DH_D, Var.DH_A, Var.DH_ALPHA,
                                                Var.DH_OFFSET)]),
            joint_rotation=optional(ds, Var.JOINT_ROTATION),
            joint_translation=optional(ds, Var.JOINT_TRANSLATION),
            armature=optional(ds, Var.D_ARM), viscous=optional(ds, Var.VISCOUS),
            coulomb=optional(ds, Var.COULOMB), torque_offset=optional(ds, Var.TORQUE_OFFSET),
            effort_limit=optional(ds, Var.TAU_MAX),
            placeholder_inertia=bool(a.get(Attr.ROBOT_PLACEHOLDER_INERTIA)))

    @property
    def drives(self) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """(armature, viscous, coulomb), each shape (n,); None where one is not stored."""
        if self.armature is None or self.viscous is None or self.coulomb is None:
            return None
        return self.armature, self.viscous, self.coulomb

    @property
    def has_drives(self) -> bool:
        """bool: any armature, friction or torque offset is stored nonzero."""
        return any(v is not None and bool(np.any(np.asarray(v, float) != 0))
                   for v in (self.armature, self.viscous, self.coulomb, self.torque_offset))


@dataclass(frozen=True, eq=False)
class StoredTrajectory:
    """The analysed trajectory of a results file: its source, and its series read on demand.

    Attributes
    ----------
    input_file, input_path, input_sha256 : object
        The attributes of the trajectory file (name, path, SHA-256) as stored; None where
        missing.
    derivatives : str
        How q̇ and q̈ were obtained (``"file"``, ``"cubic-spline"``, ``"quintic"``,
        ``"arrays"``); "" where not stored.
    dataset : xarray.Dataset
        The dataset the series are read from.
    """

    input_file: Any
    input_path: Any
    input_sha256: Any
    derivatives: str
    dataset: xr.Dataset

    @classmethod
    def from_dataset(cls, ds: xr.Dataset) -> StoredTrajectory:
        """The trajectory's record of a results dataset (its series left in ``ds``).

        Parameters
        ----------
        ds : xarray.Dataset

        Returns
        -------
        StoredTrajectory
        """
        a = ds.attrs
        return cls(input_file=a.get(Attr.INPUT_FILE), input_path=a.get(Attr.INPUT_PATH),
                   input_sha256=a.get(Attr.INPUT_SHA256),
                   derivatives=str(a.get(Attr.DERIVATIVES, "")), dataset=ds)

    @property
    def t(self) -> np.ndarray:
        """ndarray, shape (N,): the time of each set point [s]."""
        return self.dataset[Var.T].values

    @property
    def motion(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(q, q̇, q̈), each ndarray of shape (N, n): joint positions [rad or m], velocities
        [rad/s or m/s] and accelerations [rad/s^2 or m/s^2]."""
        return (self.dataset[Var.Q].values, self.dataset[Var.QD].values,
                self.dataset[Var.QDD].values)

    @property
    def tau_f(self) -> np.ndarray | None:
        """ndarray, shape (N, n), or None: the drives' friction torque [N m or N]; None for a
        robot without drives."""
        return optional(self.dataset, Var.TAU_F)
