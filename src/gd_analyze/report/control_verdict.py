"""The control report's verdict: does the simplified-model controller track as well as the
full-model one, said per joint type in its own units; and the report's number formats."""

from __future__ import annotations

import functools
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..config import defaults
from ..ranking.ranking import joint_motion_units, joint_torque_units
from .common import attr_text, fmt

if TYPE_CHECKING:                       # for the type hints only
    from numpy.typing import ArrayLike

__all__ = ["VERDICT_TOLERANCE", "control_verdict"]


# Numbers in e-notation outside [1e-3, 1e5), 3 significant digits unless told; attributes
# with 6 digits, arrays without parentheses, booleans as 0/1.
_SCI = (1e-3, 1e5)
fmt_number = functools.partial(fmt, digits=3, sci_outside=_SCI)
stored_text = functools.partial(attr_text, parens=False, bools=True, sci_outside=_SCI)


#: Default tolerance of the verdict on the simplified-model controller's peak tracking error:
#: (revolute joints [rad], prismatic joints [m]) (:data:`gd_analyze.config.defaults`); the
#: verdict takes the larger of it and twice the full-model controller's error (its integrator
#: floor); ``control --verdict-tolerance`` sets it.
VERDICT_TOLERANCE = tuple(defaults["verdict_tolerance"])
#: A tracking error that is integrator noise on every joint, as the text says it.
NOISE = "\u2261 0 (integrator noise)"


def _value(value, unit):
    """A number and its unit, never split over two lines."""
    return f"{fmt_number(value)}\u00a0{unit}".replace(" ", "\u00a0")


def _by_type(values, prismatic, which):
    """Each joint type present, as (unit, largest value, one-based joints), revolute first."""
    values, prismatic = np.asarray(values, float), np.asarray(prismatic, bool)
    out = []
    for kind in (False, True):
        ks = np.nonzero(prismatic == kind)[0]
        if ks.size:
            unit = (joint_torque_units(kind) if which == "tau" else
                    joint_motion_units(kind)[0])
            out.append((unit, float(np.nanmax(values[ks])), [int(k) + 1 for k in ks]))
    return out


def by_type_text(values: ArrayLike, prismatic: ArrayLike, which: str,
                 limits: Sequence[float] | None = None) -> str:
    """``"2.63e-04 rad"``, or per joint type ``"2.63e-04 rad, 6.20e-05 m"`` (revolute, then
    prismatic joints): a maximum is never taken across units."""
    groups = _by_type(values, prismatic, which)
    if limits is not None:
        groups = [(u, lim, js) for (u, _, js), lim in zip(groups, limits)]
    return ", ".join(_value(v, u) for u, v, _ in groups)


def _joint_types(prismatic):
    """For a mixed arm, which joints are revolute and which prismatic, said once; else ""."""
    groups = _by_type(np.zeros(len(prismatic)), prismatic, "q")
    if len(groups) < 2:
        return ""
    return ("; ".join(f"joint{'s' if len(js) > 1 else ''} {', '.join(map(str, js))} "
                      f"{'prismatic' if kind else 'revolute'} ({u}, "
                      f"{joint_torque_units(kind)})"
                      for (u, _, js), kind in zip(groups, (False, True))) + ": ")


def control_verdict(peaks: Mapping[str, np.ndarray], prismatic: ArrayLike,
                    tau_difference: np.ndarray | None = None,
                    tolerance: tuple[float, float] = VERDICT_TOLERANCE,
                    quiet: Mapping[str, bool] | None = None, noise_rule: str | None = None) -> str:
    """One sentence: does the simplified model control the arm as well as the full one?

    Parameters
    ----------
    peaks : dict of str to ndarray, shape (n,)
        Per controller (``"full"``, ``"simplified"``, ``"pd_gravity"``), each joint's peak
        tracking error |q_d - q| [rad, or m for a prismatic joint].
    prismatic : ndarray of bool, shape (n,)
        Which joints are prismatic.
    tau_difference : ndarray, shape (n,), optional
        Each joint's peak closed-loop torque difference, simplified-model controller minus
        full-model controller [N m, or N for a prismatic joint].
    tolerance : tuple of (float, float), optional
        Revolute [rad] and prismatic [m] tolerance
        (:data:`VERDICT_TOLERANCE`).
    quiet : dict of str to bool, optional
        Per controller, whether its error is integrator noise on every joint, and under
        ``"tau_difference"`` whether the torque difference is: said as
        "\u2261 0 (integrator noise)" instead of its digits.
    noise_rule : str, optional
        The rule by which a joint's torque difference is integrator noise, in words
        (:func:`gd_analyze.report.control_figures.noise_words`), said after the torque
        difference.

    Returns
    -------
    str
        The verdict: the simplified model holds if, for every joint type, its largest peak
        error is within the larger of the tolerance and twice the full model's. Errors of
        revolute and prismatic joints are stated apart, each in its unit.

    Examples
    --------
    >>> v = control_verdict({"full": np.array([1e-9, 1e-9]),
    ...                      "simplified": np.array([2e-4, 5e-4])}, np.array([False, True]))
    >>> print(v[:v.index(" (tolerance")])
    Verdict: the simplified model is good enough for computed-torque control along this trajectory: joint 1 revolute (rad, N m); joint 2 prismatic (m, N): peak tracking error 2.00e-04\xa0rad, 5.00e-04\xa0m against 1.00e-09\xa0rad, 1.00e-09\xa0m with the full model
    """
    full, simp = peaks.get("full"), peaks.get("simplified")
    if full is None or simp is None:
        return "Verdict: not available (the run lacks the full or the simplified controller)."
    pd = peaks.get("pd_gravity")
    quiet = quiet or {}

    def said(c, values):
        return NOISE if quiet.get(c) else by_type_text(values, prismatic, "q")

    groups = {k: _by_type(v, prismatic, "q") for k, v in peaks.items()}
    tol = {False: tolerance[0], True: tolerance[1]}
    kinds = [u != joint_motion_units(False)[0] for u, _, _ in groups["full"]]
    bounds = [max(2.0 * f, tol[kind]) for (_, f, _), kind in zip(groups["full"], kinds)]
    holds = all(s <= b for (_, s, _), b in zip(groups["simplified"], bounds))
    beats_pd = pd is not None and all(s < p for (_, s, _), (_, p, _) in
                                      zip(groups["simplified"], groups["pd_gravity"]))
    tail = ""
    if tau_difference is not None:
        tail = ("; its closed-loop torque differs from the full-model controller's (two "
                "closed-loop runs) by at most "
                + (NOISE if quiet.get("tau_difference") else
                   by_type_text(tau_difference, prismatic, 'tau')))
        if noise_rule:
            tail += (f" (a joint's value counts as integrator noise, \u2261 0, where it is "
                     f"{noise_rule})")
    pd_text = f", PD + gravity {said('pd_gravity', pd)}" if pd is not None else ""
    if holds:
        head = ("Verdict: the simplified model is good enough for computed-torque control "
                "along this trajectory")
    elif beats_pd:
        head = ("Verdict: the simplified model degrades tracking beyond the tolerance, though "
                "it still beats PD + gravity")
    else:
        head = "Verdict: the simplified model is NOT good enough for computed-torque control"
    if len(kinds) == 1:
        (u, _, _), kind = groups["full"][0], kinds[0]
        tolerance_text = (f"{fmt_number(bounds[0])} {u}, the larger of {tol[kind]:g} {u} and twice "
                          "the full model's")
    else:
        tolerance_text = (" and ".join(
            f"{fmt_number(b)} {u} ({'prismatic' if kind else 'revolute'})"
            for b, (u, _, _), kind in zip(bounds, groups["full"], kinds))
            + ", each the larger of " + " or ".join(
                f"{tol[kind]:g} {u}" for (u, _, _), kind in zip(groups["full"], kinds))
            + " and twice the full model's")
    return (f"{head}: {_joint_types(prismatic)}"
            f"peak tracking error {said('simplified', simp)} against "
            f"{said('full', full)} with the full model{pd_text} (tolerance: "
            f"{tolerance_text}){tail}.")
