"""Which form of the simplified model is deployed: the one decision, and the check that can
overturn it.

The pruned recursive model, the explicit model of the rule, or the exact explicit model under
a region guarantee (:func:`choose_form`); an explicit model whose D_s is not proved positive
definite gives way to the recursive one (:func:`inertia_checked`). Nothing here prints or
writes files.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..certify.positive_definite import with_inertia_check
from ..dynamics.opcount import operation_counts
from .choices import full_choices
from .explicit_model import full_program
from .simplified import total_operations

if TYPE_CHECKING:
    from ..symbolic.explicit import Term
    from .guarantee import Guarantee
    from .simplified import SimplifiedModel

__all__ = ["FormChoice", "choose_form", "inertia_checked", "recursive_costs",
           "exact_explicit_model"]


@dataclass(frozen=True)
class FormChoice:
    """Which form of the simplified model is deployed, and why.

    Attributes
    ----------
    form : {"recursive", "explicit", "exact explicit"}
        The pruned recursive model; the explicit model of the rule (pruned within the budget,
        or the chapter's choices); or the exact explicit model (nothing dropped), under a
        region guarantee.
    why : str
        For ``"exact explicit"``: why it is deployed (the clause its guarantee's ``method``
        gives); for ``"recursive"`` where a pruned explicit model was a candidate: the
        sentence saying why that one is not deployed; else "".
    """

    form: str
    why: str = ""


def choose_form(rule: str, form: str, proved: bool, recursive: Mapping[str, Any],
                explicit: Mapping[str, Any] | None = None,
                full: Mapping[str, Any] | None = None) -> FormChoice:
    """The one decision of which model is deployed: recursive, explicit or exact explicit.

    Parameters
    ----------
    rule : {"budget", "chapter"}
        The selection rule.
    form : {"cheapest", "recursive", "explicit"}
        The ``--form`` choice.
    proved : bool
        The recursive model's bound is proved over the joint-limit region.
    recursive : mapping
        The pruned recursive model's ``multiplications`` and ``additions``.
    explicit : mapping, optional
        The explicit model's of the rule, where one is a candidate (None: not derived, or,
        as in a sweep over the region, not built).
    full : mapping, optional
        The full explicit model's, where it is derived.

    Returns
    -------
    FormChoice
        The chapter rule's model is explicit. ``form="explicit"`` deploys the pruned explicit
        model where it is a candidate, else the exact one under a region guarantee.
        ``form="cheapest"`` deploys the model that counts fewest operations
        (multiplications + additions, the recursive one on a tie) among the recursive one
        and, on the trajectory, the pruned explicit one or, over the region, the exact
        explicit one (a pruned explicit model's bound holds on the trajectory only).
    """
    rec = total_operations(recursive)
    if rule == "chapter" or explicit is not None and (form == "explicit" or (
            form == "cheapest" and not proved and total_operations(explicit) < rec)):
        return FormChoice("explicit")
    if proved and full is not None and form == "explicit":
        return FormChoice("exact explicit", "asked for (--form explicit): the explicit model "
                                            "proved over the region")
    if proved and full is not None and form == "cheapest" and total_operations(full) < rec:
        return FormChoice("exact explicit",
                          "cheaper than the recursive model pruned over the region")
    if explicit is None:
        return FormChoice("recursive")
    ex = total_operations(explicit)
    why = (", --form recursive" if form != "cheapest" else
           ", whose bound holds on this trajectory only, while the recursive one's is proved "
           "over the joint-limit region" if proved and ex < rec else "")
    return FormChoice("recursive", f"The deployed model is the pruned recursive one ({rec:,} "
                                   f"operations against the pruned explicit one's {ex:,}{why}).")


def inertia_checked(model: SimplifiedModel, recursive: SimplifiedModel,
                    rebuild: Callable[..., SimplifiedModel], q: np.ndarray | None = None
                    ) -> tuple[SimplifiedModel, SimplifiedModel | None]:
    """The deployed model with D_s proved positive definite, or the recursive one in place of
    an explicit model whose D_s is not.

    Parameters
    ----------
    model : SimplifiedModel
        The model chosen (:func:`choose_form`).
    recursive : SimplifiedModel
        The pruned recursive model built beside it.
    rebuild : callable
        :func:`gd_analyze.certify.positive_definite.with_inertia_check`'s ``rebuild``.
    q : ndarray, shape (N, n), optional
        The positions of a trajectory guarantee [rad; m].

    Returns
    -------
    model : SimplifiedModel
        :func:`gd_analyze.certify.positive_definite.with_inertia_check` of ``model``; an
        explicit model whose D_s is not proved, where its bound is claimed over the region or
        where D_s is not positive definite at a sampled position (NaN is not positive), is
        replaced by the recursive model where that one's D_s is proved.
    replaced : SimplifiedModel or None
        The explicit model replaced, with its check.
    """
    model = with_inertia_check(model, q, rebuild=rebuild)
    check: Any = model.inertia_check
    claim = model.guarantee is not None and model.guarantee.proved
    if model.recursive is None and not check["proved"] and (
            claim or not check["sampled_min_eigenvalue"] > 0):
        fallback = with_inertia_check(recursive, q, rebuild=rebuild)
        if (fallback.inertia_check or {}).get("proved"):
            return fallback, model
    return model, None


def recursive_costs(model: SimplifiedModel, counts: Mapping[str, Any] | None = None
                    ) -> dict[str, dict[str, int]]:
    """The ``costs`` compared with a deployed model: the exact recursive model's, the pruned
    recursive model's and Newton-Euler's as implemented.

    Parameters
    ----------
    model : SimplifiedModel
        The pruned recursive model (:func:`gd_analyze.simplify.deploy.build_recursive`).
    counts : dict, optional
        :func:`gd_analyze.dynamics.opcount.operation_counts` of the robot; counted if not
        given.

    Returns
    -------
    dict
        ``"exact recursive"``, ``"recursive, budget"`` and ``"newton-euler"``, each with
        ``multiplications`` and ``additions``.
    """
    ne = (operation_counts(model.robot) if counts is None else counts)["newton-euler"]
    return {"exact recursive": model.costs["exact recursive"],
            "recursive, budget": dict(model.cost),
            "newton-euler": {"multiplications": int(ne["multiplications"]),
                             "additions": int(ne["additions"])}}


def exact_explicit_model(full: SimplifiedModel, terms: Term, guarantee: Guarantee,
                         tolerance: float,
                         why: str = "cheaper than the recursive model pruned over the region"
                         ) -> SimplifiedModel:
    """The exact explicit model deployed under a region guarantee (bound 0).

    Parameters
    ----------
    full : SimplifiedModel
        The explicit model at EPS = 0 (nothing dropped that contributes).
    terms : Term
        All the robot's explicit terms (:func:`gd_analyze.symbolic.explicit.derive`).
    guarantee : Guarantee
        The region guarantee of the recursive model pruned over the same region
        (:func:`gd_analyze.simplify.deploy.region_model`): its region and scale s_i are kept.
    tolerance : float
        EPS asked for.
    why : str, optional
        Why it is deployed, for the guarantee's ``method``.

    Returns
    -------
    SimplifiedModel
        ``full`` with every explicit term kept (a term whose peak is 0 on the trajectories
        ``full`` was built on need not be 0 elsewhere in the region), ``tolerance`` EPS, bound
        0 on every joint and the region guarantee with bound and sampled error 0.
    """
    n = full.robot.n
    program = full_program(full.robot, terms)
    return dataclasses.replace(
        full, tolerance=float(tolerance), bound=[0.0] * n, terms=terms,
        choices=full_choices(n), cost=program.cost(), program_cache=program,
        guarantee=dataclasses.replace(
            guarantee, bound=np.zeros(n), sampled_error=np.zeros(n), tilings=(),
            method=f"the exact explicit G-D model (nothing dropped), {why}; scale: "
                   + guarantee.method))
