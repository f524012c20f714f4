"""Is a model file's program the one its stored pairs, parameters and bound describe?

A simplified model file stores what its program is built from (the recursive form's dropped
(base parameter, part) pairs, the explicit form's kept terms), its operation count and its
bound. A hand-edited file can list pairs the program keeps, or drop parts its bound does not
cover; its outputs would then state a guarantee for another model. :func:`check_program`
rebuilds the program and refuses such a file, so that every statement of a
guarantee is about the program that runs.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..certify.region import Region, sample_positions
from ..dynamics import dalembert
from ..errors import InputError
from .guarantee import ROUND_OFF_EPS

if TYPE_CHECKING:
    from .simplified import SimplifiedModel

__all__ = ["check_program", "BOUND_SAMPLES"]

#: Uniformly sampled states of the region at which a region model's proved bound is checked
#: when its file is read (besides every joint's scale state and each joint at its limits).
BOUND_SAMPLES = 64


def check_program(model: SimplifiedModel, cost: dict | None, path: str = "<model>") -> None:
    """Refuse a model whose program is not what its stored pairs, parameters and bound give.

    Parameters
    ----------
    model : SimplifiedModel
        As read from the file.
    cost : dict or None
        The file's ``cost`` (multiplications, additions, sin, cos), None if it has none.
    path : str, optional
        The file, for messages.

    Raises
    ------
    InputError
        One line naming the key: a pair listed as dropped that the program built from the
        list keeps (dropping it would not lower the count, so the exact program runs); a
        stored ``cost`` that is not the rebuilt program's; or, for a bound proved over the
        region, an error of the program above that bound at a state of the region (sampled:
        :data:`BOUND_SAMPLES` uniform states, every joint at its limits and the states where
        s_i was found), beyond :data:`~gd_analyze.simplify.guarantee.ROUND_OFF_EPS`
        machine epsilons of the largest s_i.

    Notes
    -----
    The bound is the triangle inequality over the dropped pairs of tau = Y_b beta (Khalil &
    Kleinfinger 1987); the reference torque is the G-D model's, Eq. (3.4-24) of Fu, Gonzalez &
    Lee (1987), with the drives.
    """
    rec = model.recursive
    if rec is not None:
        left_out = rec.choice(model.robot)[1]
        if not np.array_equal(left_out, rec.dropped):
            kept = int((rec.dropped & ~left_out).sum())
            raise InputError(f"{kept} of the dropped pairs are kept by the program built from "
                             "them (dropping them does not lower the operation count): not a "
                             "file gd-analyze writes (edited?)", path, column="recursive.dropped")
    if cost:
        counted = model.program().cost()
        if any(counted.get(k) != v for k, v in cost.items()):
            said = ", ".join(f"{v} {k}" for k, v in counted.items())
            raise InputError(f"the program built from the stored pairs and parameters has "
                             f"{said}, not the cost the file states: the file was edited after "
                             "the model was written, and its bound and guarantee are another "
                             "model's", path, column="cost")
    g = model.guarantee
    if g is not None and g.proved:
        _check_region_bound(model, g, path)


def _check_region_bound(model, g, path):
    n = model.robot.n
    region = Region(np.asarray(g.q_min, float), np.asarray(g.q_max, float),
                    np.asarray(g.qd_max, float), np.asarray(g.qdd_max, float))
    rng = np.random.default_rng(0)
    q = sample_positions(region, BOUND_SAMPLES, seed=0)
    qd = rng.choice([-1.0, 1.0], q.shape) * region.qd_max
    qdd = rng.uniform(-1.0, 1.0, q.shape) * region.qdd_max
    state = np.asarray(g.scale_state, float).reshape(n, 3 * n)
    q, qd, qdd = (np.vstack([x, state[:, k * n:(k + 1) * n]]) for k, x in enumerate((q, qd, qdd)))
    with np.errstate(all="ignore"):
        err = np.abs(model.torque(q, qd, qdd) - dalembert.gd_terms(model.robot, q, qd).tau(qdd))
    if not np.isfinite(err).all():
        raise InputError("the model's torque is not finite at a sampled state of its region: "
                         "its coefficients are beyond the range of a float", path,
                         column="explicit_terms.coef" if model.recursive is None else "recursive")
    scale = np.asarray(g.scale, float)
    slack = ROUND_OFF_EPS * np.finfo(float).eps * float(np.nanmax(scale, initial=0.0))
    worst = err.max(axis=0)
    bad = ~(worst <= np.asarray(g.bound, float) * (1 + 1e-9) + slack)
    if bad.any():
        j = int(np.argmax(np.where(bad, worst - np.asarray(g.bound, float), -np.inf)))
        raise InputError(f"the program's error at a sampled state of its region, {worst[j]:.4g} "
                         f"at joint {j + 1}, exceeds its proved bound {g.bound[j]:.4g}: the "
                         "program is not the model the bound was proved for (edited?)", path,
                         column="guarantee.bound")
