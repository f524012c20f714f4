"""Units of the reports by joint type: a revolute joint's torque in N m and its D elements in
kg m², a prismatic joint's force in N and its elements in kg m or kg; units in headings kept on
one line.

Private to the reports (:mod:`gd_analyze.report.common` re-exports these names).
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING

import numpy as np

from ..ranking.ranking import joint_torque_units, joint_units_text
from ..store.results_view import Results
from ..store.schema import strings as _strings
from ..store.sweep_view import MergedModel

if TYPE_CHECKING:
    import numpy.typing as npt
    import xarray as xr

__all__ = ["keep_units", "prismatic_joints", "units_text", "torque_units",
           "units_said_once"]


#: Units in brackets in a column heading: kept on one line (no-break spaces).
_UNITS = re.compile(r"\[[^\]\n]{1,16}\]")


def keep_units(text: object) -> str:
    """Text with the spaces inside its bracketed units made no-break: "[N m]" is never split
    over two lines.

    Parameters
    ----------
    text : object
        Converted with ``str``.

    Returns
    -------
    str

    Examples
    --------
    >>> keep_units("peak error [N m]") == "peak error [N\u00a0m]"
    True
    """
    return _UNITS.sub(lambda m: m.group().replace(" ", "\u00a0"), str(text))


def prismatic_joints(ds: Results | MergedModel | xr.Dataset) -> npt.NDArray[np.bool_]:
    """Which joints are prismatic (q in m), from the stored ``joint_type`` (all revolute in a
    dataset without it).

    Parameters
    ----------
    ds : Results, MergedModel or xarray.Dataset
        A stored analysis or sweep, typed (:class:`gd_analyze.store.results_view.Results`,
        :class:`gd_analyze.store.sweep_view.MergedModel`) or not.

    Returns
    -------
    ndarray of bool, shape (n,)
    """
    if isinstance(ds, (Results, MergedModel)):
        return np.array(ds.prismatic, dtype=bool)
    if "joint_type" not in ds.variables:
        return np.zeros(ds.sizes["joint"], dtype=bool)
    return np.array([t == "prismatic" for t in _strings(ds["joint_type"].values)])


def units_text(u: str) -> str:
    """Stored units as printed: ``"kg m2"`` -> ``"kg m²"``, ``"s-2"`` -> ``"s⁻²"``.

    Parameters
    ----------
    u : str

    Returns
    -------
    str
    """
    return (str(u).replace("m2", "m\u00b2").replace("s-2", "s\u207b\u00b2")
            .replace("s-1", "s\u207b\u00b9"))


def torque_units(ds: Results | MergedModel | xr.Dataset) -> list[str]:
    """The printed units of tau_i, h_i and c_i per joint: N m, or N for a prismatic joint.

    Parameters
    ----------
    ds : Results, MergedModel or xarray.Dataset

    Returns
    -------
    list of str, length n
        From :func:`gd_analyze.ranking.labels.joint_torque_units`.
    """
    return [joint_torque_units(p) for p in prismatic_joints(ds)]


def units_said_once(ds: Results | xr.Dataset, kind: str) -> str:
    """The units of every D_ij or every tau_i in words, for captions and keys.

    Parameters
    ----------
    ds : Results or xarray.Dataset
    kind : str
        ``"D"`` or ``"tau"``.

    Returns
    -------
    str
        ``"kg m²"`` or ``"N m"`` for an all-revolute arm; for a mixed one, each unit with where
        it holds (``"N m (joints 1, 2), N (joint 3)"``; ``"kg m² where joints i and j are both
        revolute, kg m where one is prismatic, kg where both are"``).
    """
    if kind != "D":
        return joint_units_text(torque_units(ds))
    prismatic = prismatic_joints(ds)
    where = {"kg m\u00b2": "kg m\u00b2 where joints i and j are both revolute",
             "kg m": "kg m where one of them is prismatic", "kg": "kg where both are"}
    n = len(prismatic)
    found = {["kg m\u00b2", "kg m", "kg"][int(prismatic[i]) + int(prismatic[j])]
             for i in range(n) for j in range(i, n)}
    if len(found) == 1:
        return found.pop()
    return ", ".join(where[u] for u in where if u in found)


