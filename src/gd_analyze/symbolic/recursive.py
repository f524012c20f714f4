"""The customized recursive Newton-Euler model as straight-line code.

The recursion of :mod:`.newton_euler` (Fu, Gonzalez & Lee 1987, Algorithm 3.1 and Table 3.3;
Khalil & Kleinfinger 1987) with numeric parameters as constants: the base parameters (0 in the
dependent slots, :mod:`gd_analyze.dynamics.base_parameters`), so whatever multiplies a zero folds away. Only what
tau needs is kept; sums used once are merged into their user, common factors are taken out
(:func:`gd_analyze.symbolic.factoring.factor_sum`) and common subexpressions eliminated. Per link,
the form of the inertial moment (:data:`.newton_euler.FORMS`) is chosen by the count. The
result is a :class:`gd_analyze.symbolic.codegen.Program` for the emitters of
:mod:`gd_analyze.symbolic.emit`. Programs with per-part parameter values serve the pruned
models of :mod:`.pruning`.
"""

from __future__ import annotations

import dataclasses
import hashlib
import threading
from collections import OrderedDict
from collections.abc import Callable, Hashable, Iterable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
import symengine as se
from numpy.typing import ArrayLike

from ..dynamics.base_parameters import base_parameters
from .codegen import Program
from .factoring import prune_dead
from .newton_euler import ALL, FORMS, PARTS, Recursion, link_constants, link_torques
from .transform import finish_program, jacobian, substitute

if TYPE_CHECKING:
    from ..dynamics.base_parameters import BaseParameters
    from ..model.robot import Robot


__all__ = ["recursive_program", "exact_program", "parts_program", "regressor_program",
           "finish_program", "PARTS", "ProgramMemo", "PROGRAMS", "COUNTS", "program_key",
           "parts_count"]


class ProgramMemo:
    """Values of a pure function kept by key in this process, least recently used out.

    Parameters
    ----------
    size : int
        Entries kept (at least 1).

    Raises
    ------
    ValueError
        If size is below 1.

    Notes
    -----
    A program of this module is a pure function of the arm's kinematics, the parameter values
    and the settings (:func:`program_key`), and is never changed once built (a frozen
    :class:`~gd_analyze.symbolic.codegen.Program`), so one build serves every caller: the
    main job's tolerance ladder, the control command's model cost, a model file's check and a
    sweep each ask for programs built before. Thread-safe; nothing is read from or written to
    disk.

    Examples
    --------
    >>> memo = ProgramMemo(size=1)
    >>> memo.get("a", lambda: 1), memo.get("a", lambda: 2), memo.get("b", lambda: 3)
    (1, 1, 3)
    >>> memo.get("a", lambda: 4)            # "a" went out when "b" came in
    4
    """

    def __init__(self, size: int) -> None:
        if int(size) < 1:
            raise ValueError(f"size must be at least 1, got {size!r}")
        self.size = int(size)
        self._kept: OrderedDict = OrderedDict()
        self._lock = threading.Lock()

    def get(self, key: Hashable, make: Callable[[], Any],
            aliases: Callable[[Any], Iterable[Hashable]] = lambda value: ()) -> Any:
        """The value kept under a key, or made and kept.

        Parameters
        ----------
        key : hashable
            What the value is a pure function of (e.g. :func:`program_key`).
        make : callable
            ``make()`` makes the value when none is kept under ``key``.
        aliases : callable, optional
            ``aliases(value)``: other keys that give the same value; it is kept under them too.

        Returns
        -------
        object
            The kept or the new value (one object for every caller: never change it).
        """
        with self._lock:
            if key in self._kept:
                self._kept.move_to_end(key)
                return self._kept[key]
        value = make()
        with self._lock:
            for k in (key, *aliases(value)):
                self._kept[k] = value
                self._kept.move_to_end(k)
            while len(self._kept) > self.size:
                self._kept.popitem(last=False)
        return value

    def clear(self) -> None:
        """Forget every entry."""
        with self._lock:
            self._kept.clear()


#: The programs of :func:`recursive_program` and :func:`parts_program` built in this process.
PROGRAMS = ProgramMemo(size=24)
#: The operation counts of :func:`parts_count` (integers: the pruning's search compares
#: hundreds of candidate programs and keeps none of them).
COUNTS = ProgramMemo(size=4096)


def program_key(kind: str, robot: Robot, values: ArrayLike, *settings: object) -> str:
    """SHA-256 of what a program of this module depends on.

    Parameters
    ----------
    kind : str
        Which builder.
    robot : Robot
        The arm: its joint types, the joint placements' rotations and translations and gravity
        (all :class:`.newton_euler.Recursion` reads of it).
    values : array_like
        The parameter values [kg m^2, kg m, kg].
    *settings
        The builder's other arguments (their ``repr``).

    Returns
    -------
    str
        64 hexadecimal digits.
    """
    digest = hashlib.sha256(repr((kind, int(robot.n), [bool(p) for p in robot.prismatic],
                                  np.shape(values), settings)).encode())
    for array in (robot.rotation, robot.translation, robot.gravity, values):
        digest.update(np.ascontiguousarray(array, float).tobytes())
    return digest.hexdigest()


def _finish(rec, tau, cse):
    return finish_program(rec.b.assignments, tau, rec.n, cse)


def _last_joint_free(robot, values):
    """Whether tau does not depend on the last joint's angle: its link's base parameters are
    symmetric about the joint axis (XX - YY, XY, XZ, YZ, MX, MY all 0)."""
    if robot.prismatic[-1]:
        return False
    XX, XY, XZ, YY, YZ, _, MX, MY, _, _ = np.asarray(values, float)[-1]
    return bool(XX == YY and XY == XZ == YZ == MX == MY == 0.0)


def recursive_program(robot: Robot, values: ArrayLike | None = None, cse: bool = True,
                      forms: Sequence[str] | None = None) -> Program:
    """The exact customized recursive Newton-Euler model of an arm as a straight-line program.

    Parameters
    ----------
    robot : Robot
        The arm, with n revolute or prismatic joints.
    values : array_like, shape (n, 10), optional
        Inertial parameters per link (:data:`gd_analyze.dynamics.base_parameters.PARAMETER_NAMES`, body frame,
        about its origin); default the base parameters with zeros in the dependent slots
        (:attr:`gd_analyze.dynamics.base_parameters.BaseParameters.values`), which give the same torques.
    cse : bool, optional
        Run symengine's common-subexpression elimination on the result (default True).
    forms : sequence of str, optional
        The form of each link's inertial moment (:data:`.newton_euler.FORMS`, length n), as
        a program's ``forms`` records them: the program is built with these, without the
        search (the same program when they are the ones the search chose).

    Returns
    -------
    gd_analyze.symbolic.codegen.Program
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
    forms = None if forms is None else tuple(forms)

    def build():
        consts = link_constants(values)
        return _choose(robot, [[(ALL, consts[j])] for j in range(robot.n)],
                       _last_joint_free(robot, values), cse, forms=forms)
    return PROGRAMS.get(program_key("exact", robot, values, cse, forms), build,
                        lambda p: [program_key("exact", robot, values, cse, p.forms)])


#: The exact program: :func:`recursive_program` (the name the pruning module uses).
exact_program = recursive_program


def parts_program(robot: Robot, values: ArrayLike, cse: bool = True, search: bool = True,
                  forms: Sequence[str] | None = None) -> Program:
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
    gd_analyze.symbolic.codegen.Program
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
    forms = None if forms is None else tuple(forms)
    searched = search and forms is None
    return PROGRAMS.get(program_key("parts", robot, values, cse, searched, forms),
                        lambda: _parts_program(robot, values, cse, search, forms),
                        lambda p: [program_key("parts", robot, values, cse, False, p.forms)]
                        if searched else [])


def parts_count(robot: Robot, values: ArrayLike) -> int:
    """Multiplications + additions of the quick program of per-part values.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    values : array_like, shape (3, n, 10)
        As :func:`parts_program` [kg m^2, kg m, kg].

    Returns
    -------
    int
        The count of ``parts_program(robot, values, cse=False, search=False)``: no common-
        subexpression elimination, the product form on every link (the pruning's quick
        comparison of candidates, :mod:`.pruning`).

    Raises
    ------
    ValueError
        If values is not of shape (3, n, 10).
    """
    values = np.asarray(values, float)
    if values.shape != (len(PARTS), robot.n, 10):
        raise ValueError(f"values must have shape (3, {robot.n}, 10), got {values.shape}")
    return COUNTS.get(program_key("count", robot, values),
                      lambda: _total(_parts_program(robot, values, False, False, None)))


def _parts_program(robot, values, cse, search, forms):
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


def regressor_program(robot: Robot, base: BaseParameters, kept: ArrayLike) -> Program:
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
    gd_analyze.symbolic.codegen.Program
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
    groups: list[dict] = [{} for _ in range(n)]
    for k, (j, c) in enumerate(np.argwhere(base.independent)):
        parts = frozenset(p for p, keep in zip(PARTS, kept[k]) if keep)
        if parts:
            groups[j].setdefault(parts, [se.Integer(0)] * 10)[c] = beta[k]
    rec = Recursion(robot)
    tau = link_torques(rec, [sorted(g.items(), key=lambda t: sorted(t[0])) for g in groups])
    raw = Program(n, prune_dead(rec.b.assignments, tau), tau)
    assignments, outputs = jacobian(raw, beta, [(i, k) for i in range(n) for k in range(b)])
    return substitute(Program(n, assignments, outputs), dict.fromkeys(beta, 0))
