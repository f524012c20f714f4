"""The simplified model's stored variables: the cost table and what the report's "Simplified
model" section reads.

Built once at analysis time from the model and its selection; the report reads them back and
recomputes nothing.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..dynamics.opcount import book_counts, operation_counts
from ..simplify.simplified import SOURCE_STEM
from ..store.datasets import guarantee_fields, units_by_type
from ..store.names import Attr
from ..store.schema import var
from ..symbolic.emit_model import artefact_names
from ..symbolic.explicit import merge_parts
from ..symbolic.recursive_model import PART_NAMES

if TYPE_CHECKING:                       # for the type hints only
    import xarray as xr

    from ..simplify.budget import Selection
    from ..simplify.form_choice import Deployment
    from ..simplify.simplified import SimplifiedModel
    from ..symbolic.explicit import Term
    from ..trajectory.trajectory import Trajectory

__all__ = ["AKB_COSTS", "coefficient_structure", "cost_rows", "simplified_dataset",
           "deployment_dataset"]

#: Armstrong, Khatib & Burdick (ICRA 1986), PUMA 560: explicit model costs
#: (multiplications, additions, total); the split of the simplified model is not given.
AKB_COSTS = {"AKB 1986 full explicit": (739, 426, 1165),
             "AKB 1986 simplified (1 %)": (np.nan, np.nan, 305)}


def cost_rows(n: int, model: SimplifiedModel, other: SimplifiedModel | None = None,
              ladder_rows: Sequence[Mapping[str, Any]] | None = None,
              formulation_counts: Mapping[str, Any] | None = None
              ) -> dict[str, tuple[float, ...]]:
    """The cost table: label -> (multiplications, additions, total).

    Parameters
    ----------
    n : int
        Number of joints (for Table 3.5).
    model : SimplifiedModel
        The model built (its cost and the full explicit model's).
    other : SimplifiedModel, optional
        The model of the other rule, side by side.
    ladder_rows : list of dict, optional
        From :func:`~gd_analyze.simplify.explicit_model.ladder`, or from
        :func:`~gd_analyze.simplify.recursive_ladder.recursive_ladder` for a model of the
        recursive form.
    formulation_counts : dict, optional
        :func:`gd_analyze.dynamics.opcount.operation_counts` (as implemented); by default
        counted.

    Returns
    -------
    dict
    """

    def row(c):
        return (float(c["multiplications"]), float(c["additions"]),
                float(c["multiplications"] + c["additions"]))

    rows = {}
    rec = model.costs or {}
    eps_m = f" EPS={model.tolerance:g}"
    if "exact recursive" in rec:
        rows["recursive N-E, exact"] = row(rec["exact recursive"])
    if "recursive, budget" in rec:
        rows[f"recursive N-E, budget{eps_m}"
             + (" (this model)" if model.form == "recursive" else "")] = \
            row(rec["recursive, budget"])
    if full := model.full_cost or rec.get("explicit, full"):     # the model's, else its record's
        rows["explicit, full"] = row(full)
    same = {row(model.full_cost)} if model.full_cost else set()     # a rung that is the full
    if model.form == "explicit" and model.rule == "budget":          # model or this one is
        same.add(row(model.cost))                                    # listed once, as such
    if model.form == "recursive" and "exact recursive" in rec:      # its ladder's ends
        same |= {row(rec["exact recursive"]), row(model.cost)}
    for r in ladder_rows or []:
        if not ((r["tolerance"] == 0 or r["tolerance"] == model.tolerance) and row(r) in same):
            rows[("recursive N-E" if model.form == "recursive" else "explicit")
                 + f", budget EPS={r['tolerance']:g}"] = row(r)
    for m in (model, other):
        if m is not None and m.form == "explicit":
            eps = "" if m.rule == "chapter" else f" EPS={m.tolerance:g}"
            rows[f"explicit, {m.rule}{eps} (this model)" if m is model else
                 f"explicit, {m.rule}{eps}"] = row(m.cost)
    for key, c in rec.items():
        if key.startswith("explicit, ") and key != "explicit, full" and model.form != "explicit":
            label = key + ("" if key.endswith("chapter") else eps_m)
            rows.setdefault(label, row(c))

    counts = operation_counts(n) if formulation_counts is None else formulation_counts
    for table, name in ((counts, "project {} as implemented"), (book_counts(n), "Table 3.5 {}")):
        for method, label in (("gd", "G-D"), ("newton-euler", "N-E"), ("lagrange-euler", "L-E")):
            rows[name.format(label)] = row(table[method])
    if getattr(model.robot, "name", "") == "puma560" and n == 6:     # AKB's arm only
        rows.update({k: tuple(float(x) for x in v) for k, v in AKB_COSTS.items()})
    return rows


def coefficient_structure(terms: Term) -> tuple[int, int]:
    """How many harmonic terms an explicit model has, and how many distinct coefficients.

    Parameters
    ----------
    terms : gd_analyze.symbolic.explicit.Term
        Its terms (tran and rot of one element and harmonic are added, as the code generator
        adds them, :func:`gd_analyze.symbolic.explicit.merge_parts`).

    Returns
    -------
    (int, int)
        The harmonic terms, and the distinct coefficient magnitudes among them (to 12
        significant digits): equal magnitudes are what the code generator's factoring writes
        once (:mod:`gd_analyze.symbolic.factoring`).
    """

    merged = merge_parts(terms)
    return len(merged), len({float(f"{abs(c):.12g}") for c in merged.C})


def inertia_check_attrs(check: Mapping[str, Any] | None) -> dict[str, Any]:
    """The stored figures of the proof that D_s is positive definite.

    Parameters
    ----------
    check : dict or None
        :attr:`SimplifiedModel.inertia_check
        <gd_analyze.simplify.simplified.SimplifiedModel.inertia_check>`.

    Returns
    -------
    dict
        ``simplified_inertia_check_where`` ("region" or "trajectory"), ``..._proved`` (1 or
        0), ``..._lower_bound`` (the proved lower bound of lambda_min(D_s) [kg m^2], NaN when
        not proved), ``..._ratio`` (that bound over the upper bound of min lambda_min(D) [1],
        NaN when not proved), ``..._samples`` (positions sampled for a counterexample),
        ``..._sampled_min_eigenvalue`` [kg m^2], ``..._restored`` (base parameters restored
        with all their parts for the proof, comma-separated), ``..._statement`` (the
        sentence every output states) and ``..._method``; empty without a check.

    Examples
    --------
    >>> inertia_check_attrs(None)
    {}
    >>> inertia_check_attrs({"where": "region", "proved": True, "lower_bound": 0.5,
    ...     "ratio": 0.25, "samples": 4, "sampled_min_eigenvalue": 2.0, "restored": [],
    ...     "statement": "proved", "method": "m"})["simplified_inertia_check_proved"]
    1
    """
    if not check:
        return {}
    key = "simplified_inertia_check_"

    def num(v):
        return float("nan") if v is None else float(v)
    return {key + "where": str(check["where"]), key + "proved": int(bool(check["proved"])),
            key + "lower_bound": num(check.get("lower_bound")),
            key + "ratio": num(check.get("ratio")),
            key + "samples": int(check["samples"]),
            key + "sampled_min_eigenvalue": num(check.get("sampled_min_eigenvalue")),
            key + "restored": ", ".join(check.get("restored", ())),
            key + "statement": str(check.get("statement", "")),
            key + "method": str(check.get("method", ""))}


def simplified_dataset(model: SimplifiedModel, selection: Selection,
                       other: SimplifiedModel | None = None,
                       ladder_rows: Sequence[Mapping[str, Any]] | None = None,
                       cost_table: Mapping[str, tuple[float, ...]] | None = None,
                       other_error: Mapping[str, Any] | None = None,
                       full_terms: Term | None = None) -> xr.Dataset:
    """The variables the report's "Simplified model" section reads.

    Parameters
    ----------
    model : SimplifiedModel
    selection : Selection
    other : SimplifiedModel, optional
        The other rule's model.
    ladder_rows : list of dict, optional
    cost_table : dict, optional
        From :func:`cost_rows`.
    other_error : dict, optional
        The other model's error along the trajectory
        (:func:`~gd_analyze.simplify.explicit_model.validate`).
    full_terms : Term, optional
        All terms of the full explicit model: with an explicit ``other``, the attributes
        ``full_harmonics``, ``full_coefficients``, ``other_rule_harmonics`` and
        ``other_rule_coefficients`` (:func:`coefficient_structure`) say why a pruned model can
        cost more than the full one.

    Returns
    -------
    xarray.Dataset
        ``simplified_scale``, ``simplified_bound``, ``simplified_bound_inertia``,
        ``simplified_bound_coriolis``, ``simplified_bound_gravity``,
        ``simplified_element_bound`` (dim joint) [N m]; ``cost_*`` (dim cost_model);
        ``ladder_*`` (dim ladder_tolerance); ``other_rule_*``; attributes ``simplified_rule``,
        ``simplified_tolerance``, ``simplified_torque_floor``, ``simplified_files``,
        ``simplified_terms_kept``; the model's guarantee
        (:func:`gd_analyze.store.datasets.guarantee_fields`: ``simplified_guarantee_*``).
    """
    import xarray as xr


    torque = units_by_type(model.robot.prismatic, "tau")

    by_kind = selection.bound_by_kind
    dv = {name: var(("joint",), data, torque, what) for name, data, what in (
        ("simplified_scale", selection.scale, "scale_i = max(peak |tau_i|, torque floor)"),
        ("simplified_bound", selection.bound,
         "guaranteed bound on |tau_s - tau| on the trajectory"),
        ("simplified_bound_inertia", by_kind["D"],
         "share of the bound from dropped terms of D (D qdd)"),
        ("simplified_bound_coriolis", by_kind["h"], "share of the bound from dropped terms of h"),
        ("simplified_bound_gravity", by_kind["c"], "share of the bound from dropped terms of c"),
        ("simplified_element_bound", selection.element_bound,
         "bound of the whole-part (element) choices"))}
    scope_vars, scope_attrs = guarantee_fields(model, torque)
    dv.update(scope_vars)
    if "whole" in by_kind:
        dv["simplified_bound_whole"] = var(("joint",), by_kind["whole"], torque,
                                           "share of the bound from base parameters dropped "
                                           "whole")
    coords = {}
    if cost_table:
        labels = list(cost_table)
        arr = np.array([cost_table[k] for k in labels], float)
        coords["cost_model"] = var(("cost_model",), np.array(labels, dtype=str), "1",
                                   "formulation or model whose operations are counted")
        dv.update({
            "cost_multiplications": var(("cost_model",), arr[:, 0], "1", "multiplications"),
            "cost_additions": var(("cost_model",), arr[:, 1], "1", "additions"),
            "cost_total": var(("cost_model",), arr[:, 2], "1", "multiplications + additions"),
        })
    if ladder_rows:
        coords["ladder_tolerance"] = var(("ladder_tolerance",),
                                         np.array([r["tolerance"] for r in ladder_rows]), "1",
                                         "EPS of the error budget")
        dv.update({
            "ladder_operations": var(("ladder_tolerance",),
                                     [r["multiplications"] + r["additions"] for r in
                                      ladder_rows], "1", "multiplications + additions"),
            "ladder_trig": var(("ladder_tolerance",), [r["sin"] + r["cos"] for r in
                                                       ladder_rows], "1", "sin and cos calls"),
            "ladder_worst_error": var(("ladder_tolerance",),
                                      [r["worst_relative_error"] for r in ladder_rows], "1",
                                      "worst peak |tau_s - tau| / scale_i on the trajectory "
                                      "(guaranteed <= EPS)"),
        })
        if all("worst_relative_bound" in r for r in ladder_rows):
            dv["ladder_worst_bound"] = var(("ladder_tolerance",),
                                           [r["worst_relative_bound"] for r in ladder_rows],
                                           "1", "largest bound_i / scale_i (<= EPS)")
    if other is not None and other_error is not None:
        dv.update({
            "other_rule_choice": var(("element",), np.array(
                [other.choices[k] for k in other.choices], dtype=str), "1",
                f"choices of the {other.rule} rule"),
            "other_rule_error_relative_peak": var(
                ("joint",), np.array(other_error["relative_peak_error"], float), "1",
                f"peak |tau_s - tau| / peak |tau| of the {other.rule} rule's model"),
        })
    if model.recursive is not None:
        rec = model.recursive
        units = {"M": "kg", "MX": "kg m", "MY": "kg m", "MZ": "kg m"}
        coords["base_parameter"] = var(("base_parameter",), np.array(rec.names, dtype=str),
                                       "1", "base inertial parameter (Gautier 1990)")
        coords["torque_part"] = var(("torque_part",), np.array(PART_NAMES, dtype=str), "1",
                                    "part of the torque: inertial (D qdd), velocity (h), "
                                    "gravity (c)")
        dv.update({
            "base_parameter_value": var(("base_parameter",), rec.beta, "SI", "value"),
            "base_parameter_units": var(("base_parameter",), np.array(
                [units.get(name.rstrip("0123456789"), "kg m2") for name in rec.names],
                dtype=str), "1", "units of the value"),
            "base_parameter_dropped": var(("base_parameter", "torque_part"),
                                          rec.dropped.astype(np.int8), "1",
                                          "1 where the part is dropped from the model"),
        })
        if rec.relative_peak is not None:
            dv["base_parameter_relative_peak"] = var(
                ("base_parameter", "torque_part"), rec.relative_peak, "1",
                "largest peak contribution on the trajectory / scale_i (0: none)")
    ds = xr.Dataset(dv, coords=coords)
    # the (parameter, part) pairs that contribute on the trajectory (round-off excluded)
    facts = None if model.recursive is None else model.recursive.stated_facts()
    cost = model.cost
    ds.attrs.update({
        "simplified_rule": model.rule, "simplified_tolerance": model.tolerance,
        "simplified_torque_floor": model.torque_floor,
        "simplified_files": ", ".join(artefact_names(SOURCE_STEM)),
        "simplified_form": model.form,
        "simplified_terms_kept":
            -1 if model.terms is None else len(model.terms),
        "simplified_pairs_dropped": -1 if facts is None else facts["dropped"],
        "simplified_pairs": -1 if facts is None else facts["pairs"],
        "simplified_dropped_pairs": "" if facts is None else
        ", ".join(f"{a} ({b})" for a, b in facts["dropped_pairs"]),
        "simplified_multiplications": cost["multiplications"],
        "simplified_additions": cost["additions"], "simplified_sin": cost["sin"],
        "simplified_cos": cost["cos"],
        "other_rule": "" if other is None else other.rule,
        "other_rule_multiplications": -1 if other is None else other.cost["multiplications"],
        "other_rule_additions": -1 if other is None else other.cost["additions"],
        **scope_attrs,
        **inertia_check_attrs(model.inertia_check),
    })
    if full_terms is not None and other is not None and other.terms is not None:
        for key, terms in (("full", full_terms), ("other_rule", other.terms)):
            ds.attrs[f"{key}_harmonics"], ds.attrs[f"{key}_coefficients"] = \
                coefficient_structure(terms)
    return ds


def deployment_dataset(deployment: Deployment, trajectory: Trajectory,
                       other_error: Mapping[str, Any] | None = None) -> xr.Dataset:
    """The deployed model's stored variables: :func:`simplified_dataset` of a
    :class:`~gd_analyze.simplify.form_choice.Deployment`, with its ladder, its notes and the
    region's coverage of the trajectory.

    Parameters
    ----------
    deployment : Deployment
        From :func:`gd_analyze.simplify.form_choice.deploy`; its ladder is waited for.
    trajectory : Trajectory
        The analysed trajectory, q, qd, qdd of shape (N, n).
    other_error : dict, optional
        The other rule's model's error on the trajectory (its accumulator's result).

    Returns
    -------
    xarray.Dataset
        As :func:`simplified_dataset`, with the attributes ``simplified_ladder_skipped``,
        ``simplified_ladder_form`` and ``simplified_form_note`` where they apply; with a region,
        ``region_covers_trajectory`` (1 or 0) and ``region_coverage`` ("" inside, else the
        clause of :meth:`gd_analyze.certify.region.Excursion.text`: the joint, the quantity and
        its extreme against the limit); where a screen chose the exact recursive model
        (:meth:`gd_analyze.certify.screen.RegionScreen.to_dict`: the sampled pre-screen that
        skipped the region's certification, or the screen of the pairs searched under the
        proved bounds), ``simplified_region_screen`` (the sentence with the numbers),
        ``simplified_region_possible_saving`` and ``simplified_region_saving_threshold``
        (shares of the exact recursive model's operations [1]) and
        ``simplified_region_screen_proved`` (1: the proved screen, 0: the sampled one).
    """
    d = deployment
    rungs = d.ladder_rows()
    table = cost_rows(d.model.robot.n, d.model, other=d.other, ladder_rows=rungs,
                      formulation_counts=d.counts)
    extra = simplified_dataset(d.model, d.selection, other=d.other, ladder_rows=rungs,
                               cost_table=table, other_error=other_error, full_terms=d.terms)
    if d.ladder_skipped:
        extra.attrs["simplified_ladder_skipped"] = d.ladder_skipped
    if rungs:
        extra.attrs["simplified_ladder_form"] = d.model.form
    if d.form_note:
        extra.attrs["simplified_form_note"] = d.form_note
    if d.region is not None:            # whether the analysed trajectory stays in the region
        out = d.region.excursion(trajectory.q, trajectory.qd, trajectory.qdd)
        extra.attrs.update({"region_covers_trajectory": int(out is None),
                            "region_coverage": "" if out is None else out.text()})
    if d.screen:                        # the screen that chose the exact recursive model
        extra.attrs.update({
            Attr.SIMPLIFIED_REGION_SCREEN: str(d.screen["statement"]),
            Attr.SIMPLIFIED_REGION_POSSIBLE_SAVING: float(d.screen["possible_saving"]),
            Attr.SIMPLIFIED_REGION_SAVING_THRESHOLD: float(d.screen["threshold"]),
            Attr.SIMPLIFIED_REGION_SCREEN_PROVED: int(bool(d.screen.get("proved", False)))})
    return extra
