"""The series the main report's figures draw, read from the stored results file.

:func:`plot_data` reads the stored series whole, or for long trajectories their min/max
envelope per column of the panel, in chunks (memory stays a few chunks whatever N is). The
figures (:mod:`gd_analyze.report.main_figures`) never see the full dataset and never recompute
the dynamics.
"""

from __future__ import annotations

import operator
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..store.names import Var

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["PlotData", "plot_data", "DERIVED", "OPTIONAL", "ENVELOPE_THRESHOLD", "ENVELOPE_COLUMNS",
           "READ_CHUNK"]

#: Series longer than this are read and drawn as a min/max envelope per column.
ENVELOPE_THRESHOLD = 2000
#: Columns of the envelope of a long series (about 300 dpi on a panel).
ENVELOPE_COLUMNS = 400
#: Set points read per chunk when a long series is reduced.
READ_CHUNK = 32768


@dataclass(frozen=True)
class PlotData:
    """The series the figures draw, as stored or reduced to their envelope.

    Attributes
    ----------
    x : ndarray, shape (M,)
        Time [s] of each plotted point (M = N, or two points per envelope column).
    enveloped : bool
        True if the series are min/max envelopes (no markers are drawn).
    series : dict of str to ndarray
        ``q``, ``qd``, ``qdd``, ``h_tran``, ``h_rot``, ``h``, ``c``, ``tau``,
        ``tau_simplified``, ``tau_error``, ``D_tran_qdd``, ``D_rot_qdd`` (M, n) and
        ``D_tran``, ``D_rot``, ``D`` (M, n, n).
    N : int
        Set points stored.
    """

    x: np.ndarray
    enveloped: bool
    series: dict
    N: int


def _read(var, a, b):
    return np.asarray(var[a:b].values, dtype=float)


def _times_qdd(D, qdd):
    return np.einsum("tij,tj->ti", D, qdd)


#: Series computed from stored ones as they are read, per chunk: name -> (stored variables,
#: function of their chunks). ``tau_error`` = tau_s - tau; ``D_tran_qdd`` and ``D_rot_qdd``
#: = D^tran qdd and D^rot qdd (N, n), the inertial contributions to tau (Eq. (3.4-25)).
DERIVED = {"tau_error": (("tau_simplified", "tau"), operator.sub),
           "D_tran_qdd": (("D_tran", "qdd"), _times_qdd),
           "D_rot_qdd": (("D_rot", "qdd"), _times_qdd)}
#: Series read only if the dataset holds what they need (the torque contributions' figure).
OPTIONAL = ("c", "D_tran_qdd", "D_rot_qdd")


def _chunk(ds, v, a, b):
    if v in DERIVED:
        inputs, f = DERIVED[v]
        return f(*(_read(ds[k], a, b) for k in inputs))
    return _read(ds[v], a, b)


def _held(ds, v):
    return all(k in ds.variables for k in (DERIVED[v][0] if v in DERIVED else (v,)))


def plot_data(ds: xr.Dataset,
              names: Sequence[str] = ("q", "qd", "qdd", "D_tran", "D_rot", "D", "h_tran", "h_rot", "h", "tau", "tau_simplified", "tau_error", *OPTIONAL),
              columns: int = ENVELOPE_COLUMNS, threshold: int = ENVELOPE_THRESHOLD,
              chunk: int = READ_CHUNK, progress: Callable[[int], object] | None = None) -> PlotData:
    """Read the series to plot from a stored analysis, reduced if long.

    Parameters
    ----------
    ds : xarray.Dataset
        An opened results file (lazily loaded: only chunks are read) with ``t`` (N,) [s] and
        the variables ``names`` with first dimension ``setpoint``.
    names : sequence of str, optional
        The variables to read; ``tau_error``, ``D_tran_qdd`` and ``D_rot_qdd`` are derived
        from stored ones (:data:`DERIVED`), per chunk before the envelope; those of
        :data:`OPTIONAL` are left out if the dataset lacks what they need.
    columns : int, optional
        Columns of the envelope of a long series.
    threshold : int, optional
        Up to this many set points the series are read whole.
    chunk : int, optional
        Set points read at a time.
    progress : callable, optional
        Called with the number of set points read, per chunk (for a progress bar).

    Returns
    -------
    PlotData
        For N > threshold: per column of equal time, the minimum and the maximum of each series
        at the column's mid-time, in time order (2 * columns points); memory stays a few chunks
        whatever N is.
    """
    names = [v for v in names if v not in OPTIONAL or _held(ds, v)]
    t = np.asarray(ds[Var.T].values, dtype=float)
    N = t.size
    if N <= threshold:
        series = {v: _chunk(ds, v, 0, N) for v in names}
        if progress:
            progress(N)
        return PlotData(x=t, enveloped=False, series=series, N=N)
    t0, t1 = float(t[0]), float(t[-1])
    if t1 > t0:
        col = np.minimum(((t - t0) * (columns / (t1 - t0))).astype(np.intp), columns - 1)
    else:
        col = (np.arange(N) * columns) // N
    lo: dict[str, Any] = {v: None for v in names}
    hi: dict[str, Any] = {v: None for v in names}
    for a in range(0, N, chunk):
        b = min(N, a + chunk)
        c = col[a:b]
        starts = np.flatnonzero(np.r_[True, c[1:] != c[:-1]])
        cols = c[starts]
        for v in names:
            y = _chunk(ds, v, a, b)
            if lo[v] is None:
                lo[v] = np.full((columns,) + y.shape[1:], np.nan)
                hi[v] = np.full((columns,) + y.shape[1:], np.nan)
            with np.errstate(invalid="ignore"):
                lo[v][cols] = np.fmin(lo[v][cols], np.fmin.reduceat(y, starts, axis=0))
                hi[v][cols] = np.fmax(hi[v][cols], np.fmax.reduceat(y, starts, axis=0))
        if progress:
            progress(b - a)
    used = np.unique(col)
    edges = np.linspace(t0, t1, columns + 1) if t1 > t0 else np.arange(columns + 1.0)
    mid = 0.5 * (edges[used] + edges[used + 1])
    x = np.repeat(mid, 2)
    series = {v: np.stack([lo[v][used], hi[v][used]], axis=1)      # (C, 2, ...): lo, hi
              .reshape((2 * used.size,) + lo[v].shape[1:]) for v in names}
    return PlotData(x=x, enveloped=True, series=series, N=N)
