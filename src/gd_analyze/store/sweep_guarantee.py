"""The guarantee of a sweep's merged model, read back from ``sweep.h5``.

:func:`gd_analyze.jobs.sweep_merged.with_budget_model` stores the merged model's guarantee
(``merged_guarantee_kind``, ``merged_guarantee_statement``: the one sentence of
:meth:`gd_analyze.simplify.guarantee.Guarantee.statement`) and, for a model proved over the
joint-limit region, whether each swept trajectory lies in that region (``merged_covered``,
``merged_coverage``). :func:`merged_guarantee` reads them back for the command line and the
sweep report, so that both say the same.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .names import SweepVar as SV
from .schema import strings

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr

__all__ = ["merged_guarantee"]


def merged_guarantee(ds: xr.Dataset) -> dict[str, Any] | None:
    """The merged model's guarantee and the swept trajectories it covers.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep dataset (K trajectories, n joints) with the budget rule's merged model.

    Returns
    -------
    dict or None
        None without a stored guarantee (chapter rule, older files); else ``kind``
        (``"region"`` or ``"trajectory"``), ``statement`` (str), ``covered`` (ndarray of bool,
        shape (K,): a trajectory-kind guarantee covers every swept trajectory, a region one
        those lying in its region), ``outside`` (list of (source, reason, worst peak
        |tau_merged - tau| / s_i [1]) of the trajectories not covered), ``worst`` (the
        largest peak |tau_merged - tau| / scale_i over the covered trajectories [1], NaN if
        none; ``merged_tau_error_relative_peak``), ``held_out`` and ``held_out_inside`` (the
        held-out trajectories, and how many lie in the region; None when not stored).
    """
    a = ds.attrs
    if "merged_guarantee_statement" not in a:
        return None
    kind = str(a.get("merged_guarantee_kind", "none"))
    rel = np.asarray(ds[SV.MERGED_TAU_ERROR_RELATIVE_PEAK].values, float)
    K = rel.shape[0]
    if kind == "region" and SV.MERGED_COVERED in ds.variables:
        covered = np.asarray(ds[SV.MERGED_COVERED].values).astype(bool)
        reasons = strings(ds[SV.MERGED_COVERAGE].values)
    else:
        covered, reasons = np.ones(K, bool), [""] * K
    worst = np.where(np.isfinite(rel), rel, np.inf).max(axis=1) if rel.size else np.zeros(K)
    sources = strings(ds[SV.SOURCE].values) if SV.SOURCE in ds.variables else \
        [str(k) for k in range(K)]
    held = a.get("held_out_trajectories")
    inside = a.get("held_out_inside_region")
    return {"kind": kind, "statement": str(a["merged_guarantee_statement"]),
            "covered": covered,
            "outside": [(sources[k], reasons[k], float(worst[k])) for k in range(K)
                        if not covered[k]],
            "worst": float(worst[covered].max()) if covered.any() else float("nan"),
            "held_out": None if held is None else int(held),
            "held_out_inside": None if inside is None else int(inside)}
