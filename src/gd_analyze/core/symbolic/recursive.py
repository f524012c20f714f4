"""The customized recursive Newton-Euler model as straight-line code.

The recursion of :mod:`.newton_euler` (Fu, Gonzalez & Lee 1987, Algorithm 3.1 and Table 3.3;
Khalil & Kleinfinger 1987) with numeric parameters as constants: the base parameters (0 in the
dependent slots, :mod:`.base_parameters`), so whatever multiplies a zero folds away. Only what
tau needs is kept; sums used once are merged into their user, common factors are taken out
(:func:`gd_analyze.core.symbolic.factoring.factor_sum`) and common subexpressions eliminated. Per link,
the form of the inertial moment (:data:`.newton_euler.FORMS`) is chosen by the count. The
result is a :class:`gd_analyze.core.symbolic.codegen.Program` for the emitters of
:mod:`gd_analyze.core.symbolic.emit`. Programs with per-part parameter values serve the pruned
models of :mod:`.pruning`.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import symengine as se

from .base_parameters import base_parameters
from .codegen import Program
from .factoring import prune_dead
from .newton_euler import ALL, FORMS, PARTS, Recursion, link_constants, link_torques
from .transform import finish_program, jacobian, substitute

__all__ = ["recursive_program", "exact_program", "parts_program", "regressor_program",
           "finish_program", "PARTS"]

def _finish(rec, tau, cse):
    return finish_program(rec.b.assignments, tau, rec.n, cse)


def _last_joint_free(robot, values):
    """Whether tau does not depend on the last joint's angle: its link's base parameters are
    symmetric about the joint axis (XX - YY, XY, XZ, YZ, MX, MY all 0)."""
    if robot.prismatic[-1]:
        return False
    XX, XY, XZ, YY, YZ, _, MX, MY, _, _ = np.asarray(values, float)[-1]
    return bool(XX == YY and XY == XZ == YZ == MX == MY == 0.0)


def recursive_program(robot, values=None, cse=True, forms=None):
    """The exact customized recursive Newton-Euler model of an arm as a straight-line program.

    Parameters
    ----------
    robot : Robot
        The arm, with n revolute or prismatic joints.
    values : array_like, shape (n, 10), optional
        Inertial parameters per link (:data:`.base_parameters.PARAMETER_NAMES`, body frame,
        about its origin); default the base parameters with zeros in the dependent slots
        (:attr:`.base_parameters.BaseParameters.values`), which give the same torques.
    cse : bool, optional
        Run symengine's common-subexpression elimination on the result (default True).
    forms : sequence of str, optional
        The form of each link's inertial moment (:data:`.newton_euler.FORMS`, length n), as
        a program's ``forms`` records them: the program is built with these, without the
        search (the same program when they are the ones the search chose).

    Returns
    -------
    gd_analyze.core.symbolic.codegen.Program
        tau [N m or N] from the symbols ``q0, qd0, qdd0, ...``; ``Program.cost()`` counts it;
        ``forms`` the forms chosen.

    Raises
    ------
    ValueError
        If values is not a finite array of shape (n, 10), or forms are not n names of FORMS.

    Notes
    -----
    Fu, Gonzalez & Lee (1987), Algorithm 3.1 and Table 3.3, with gravity as the base
    acceleration (Eq. (3.3-46)); customized form of Khalil & Kleinfinger (1987). When the last
    link's base parameters are symmetric about its (revolute) axis, the torques do not depend
    on the last angle and it is taken as 0 (no cos/sin of it). Per link, w x (J w) is formed
    either from the six products w_a w_b (shared with U) or as it stands, whichever gives the
    smaller count (a greedy pass over the links).

    Examples
    --------
    >>> from gd_analyze import load_robot
    >>> prog = recursive_program(load_robot("two-link"))
    >>> sorted(prog.cost())
    ['additions', 'cos', 'multiplications', 'sin']
    """
    if values is None:
        values = base_parameters(robot).values
    values = np.asarray(values, float)
    if values.shape != (robot.n, 10) or not np.isfinite(values).all():
        raise ValueError(f"values must be finite, of shape ({robot.n}, 10), got "
                         f"{values.shape}")
    consts = link_constants(values)
    return _choose(robot, [[(ALL, consts[j])] for j in range(robot.n)],
                   _last_joint_free(robot, values), cse, forms=forms)


#: The exact program: :func:`recursive_program` (the name the pruning module uses).
exact_program = recursive_program


def parts_program(robot, values, cse=True, search=True, forms=None):
    """The recursive program with different parameter values per part of the torque.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    values : array_like, shape (3, n, 10)
        Per part of :data:`PARTS` (inertial, velocity, gravity) the parameter values per
        link; a parameter is either 0 or one common value in every part.
    cse : bool, optional
        Run symengine's common-subexpression elimination on the result (default True).
    search : bool, optional
        Choose each link's form of the inertial moment (:data:`.newton_euler.FORMS`) by
        the count (default True); False: the product form everywhere (quicker).
    forms : sequence of str, optional
        As :func:`recursive_program`: these forms, no search (``search`` is then ignored).

    Returns
    -------
    gd_analyze.core.symbolic.codegen.Program
        tau = sum over the parts p of the part p of the torque of values[p] [N m or N];
        ``forms`` the forms chosen.

    Raises
    ------
    ValueError
        If values is not of shape (3, n, 10), or forms are not n names of FORMS.

    Notes
    -----
    Per link the parameters are grouped by the set of parts they are kept in; a group's
    wrench is formed from the kinematic quantities of those parts: the whole recursion,
    the inertial and gravity parts by their own recursions, the others by differences.
    """
    values = np.asarray(values, float)
    if values.shape != (len(PARTS), robot.n, 10):
        raise ValueError(f"values must have shape (3, {robot.n}, 10), got {values.shape}")
    groups = []
    for j in range(robot.n):
        by_set = {}
        for c in range(10):
            col = values[:, j, c]
            kept = [p for p, v in zip(PARTS, col) if v != 0.0]
            if not kept:
                continue
            if len({float(col[PARTS.index(p)]) for p in kept}) == 1:
                by_set.setdefault(frozenset(kept), np.zeros(10))[c] = col[PARTS.index(kept[0])]
            else:
                for p in kept:
                    by_set.setdefault(frozenset(p), np.zeros(10))[c] = col[PARTS.index(p)]
        groups.append([(S, link_constants(phi[None, :])[0])
                       for S, phi in sorted(by_set.items(), key=lambda t: sorted(t[0]))])
    lock = all(_last_joint_free(robot, values[p]) for p in range(len(PARTS)))
    return _choose(robot, groups, lock, cse, search, forms)


def _total(program):
    c = program.cost()
    return c["multiplications"] + c["additions"]


def _choose(robot, groups, lock, cse, search=True, forms=None):
    """The cheapest program over the links' forms of :data:`FORMS`, by a greedy pass from
    the product form: each link switched to another form where that lowers the count; or
    the program of the given forms. The program records the forms (``Program.forms``)."""
    def build(chosen):
        rec = Recursion(robot, lock_last=lock, direct=chosen)
        program = _finish(rec, link_torques(rec, groups), cse)
        return dataclasses.replace(program, forms=tuple(chosen.get(j, FORMS[0])
                                                        for j in range(robot.n)))
    if forms is not None:
        forms = tuple(forms)
        if len(forms) != robot.n or not set(forms) <= set(FORMS):
            raise ValueError(f"forms must be {robot.n} names of {FORMS}, got {forms!r}")
        return build({j: f for j, f in enumerate(forms) if f != FORMS[0]})
    chosen = {}
    best = build(chosen)
    for j in range(robot.n if search else 0):
        for form in FORMS[1:]:
            trial = build({**chosen, j: form})
            if _total(trial) < _total(best):
                best, chosen = trial, {**chosen, j: form}
    return best


def regressor_program(robot, base, kept):
    """The regressor of the kept (base parameter, part) pairs as a straight-line program.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
        Its b base parameters.
    kept : array_like of bool, shape (b, 3)
        ``kept[k, p]``: part p (:data:`PARTS`: inertial, velocity, gravity) of parameter k is
        in the model (a pruned model's pairs not dropped; all True for the exact model).

    Returns
    -------
    gd_analyze.core.symbolic.codegen.Program
        Outputs Y[i, k], row-major (n x b): d tau_i / d beta_k of the model that keeps those
        pairs [N m per unit of beta_k: kg m^2, kg m or kg], so tau = Y beta; Y[:, k] is the sum
        of the kept parts of the k-th column of Y_b = Y_b(q, 0, qdd; g = 0) + Y_b(q, qd, 0; g = 0)
        + Y_b(q, 0, 0; g).

    Notes
    -----
    The recursion of :mod:`.newton_euler` (Fu, Gonzalez & Lee 1987, Algorithm 3.1) with the
    base parameters as symbols beta_k, each in the parts it is kept in (per link, grouped by
    that set of parts as :func:`parts_program` groups them), differentiated by them in forward
    mode (:func:`.transform.jacobian`): tau is linear in beta (Khalil & Kleinfinger 1987;
    Gautier 1990), so the derivatives are the regressor's columns. No joint angle is locked: a
    column may depend on the last angle even where beta's values do not.
    """
    kept = np.asarray(kept, bool)
    n, b = robot.n, base.rank
    if kept.shape != (b, len(PARTS)):
        raise ValueError(f"kept must have shape ({b}, 3), got {kept.shape}")
    beta = [se.Symbol(f"beta{k}") for k in range(b)]
    groups = [{} for _ in range(n)]
    for k, (j, c) in enumerate(np.argwhere(base.independent)):
        parts = frozenset(p for p, keep in zip(PARTS, kept[k]) if keep)
        if parts:
            groups[j].setdefault(parts, [se.Integer(0)] * 10)[c] = beta[k]
    rec = Recursion(robot)
    tau = link_torques(rec, [sorted(g.items(), key=lambda t: sorted(t[0])) for g in groups])
    raw = Program(n, prune_dead(rec.b.assignments, tau), tau)
    assignments, outputs = jacobian(raw, beta, [(i, k) for i in range(n) for k in range(b)])
    return substitute(Program(n, assignments, outputs), dict.fromkeys(beta, 0))
