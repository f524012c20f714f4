"""The deployed model's functions: tau, D, h, c and the regressor, all of one model.

A simplified model is deployed as five functions of the same kept terms, each a
straight-line program (:class:`~gd_analyze.symbolic.codegen.Program`) that the printers
of :mod:`gd_analyze.symbolic.emit` write in C, numpy and CasADi:

========================  ==========================  =====================================
function                  of                          value
========================  ==========================  =====================================
``tau``                   q, qd, qdd                  tau_s (n,) [N m]
``inertia``               q                           D_s (n, n) [kg m^2], symmetric
``velocity_terms``        q, qd                       h_s (n,) [N m], with the friction
``gravity``               q                           c_s (n,) [N m]
``regressor``             q, qd, qdd                  Y_s (n, b) with tau_s = Y_s beta_s
========================  ==========================  =====================================

so that tau_s = D_s qdd + h_s + c_s (Eq. (3.4-24) of Fu, Gonzalez & Lee 1987) and
tau_s = Y_s beta_s. For the recursive form each function keeps exactly the (base parameter,
part) pairs of the pruned model (the inertial parts make D_s, the velocity parts h_s, the
gravity parts c_s; :mod:`.pruning`), and Y_s is the regressor of those pairs on the base
parameters (Khalil & Kleinfinger 1987; Gautier 1990); for the explicit form D_s, h_s and c_s
are its D, h and c groups, and Y_s has one column per kept coefficient
(:meth:`.codegen.ExplicitProgram.regressor`). The drives (:mod:`gd_analyze.model.drives`)
appear as in tau: the armature Ia_i on the diagonal of D_s, the friction F_v qd + F_c sign(qd)
in h_s (velocity_terms), and in Y_s as columns ``Ia<i>``, ``Fv<i>``, ``Fc<i>`` (qdd_i, qd_i,
sign(qd_i)) whose parameters are those coefficients (Gautier 1990 identifies them the same
way). Pure: no files.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
import symengine as se
from numpy.typing import ArrayLike

from ..model.drives import DRIVE_FIELDS
from .codegen import ExplicitProgram, Program
from .emit_model import FUNCTIONS, FunctionSpec, numpy_source
from .pruning import part_values
from .recursive import parts_program, regressor_program
from .transform import jacobian, substitute

if TYPE_CHECKING:
    from ..dynamics.base_parameters import BaseParameters
    from ..model.robot import Robot
    from .explicit import Term


__all__ = ["FunctionSpec", "FUNCTIONS", "ModelFunctions", "recursive_functions",
           "recursive_inertia", "explicit_functions", "joint_labels"]


@dataclass(frozen=True, eq=False)
class ModelFunctions:
    """The five programs of a deployed model and what they need to be printed.

    Attributes
    ----------
    n : int
        Number of joints.
    joint_names : tuple of str
        Per joint, its name (:func:`joint_labels`).
    parameter_names : tuple of str
        The b parameters beta_s, e.g. ``("ZZ1", "XXR2", ..., "Fv1")``.
    parameters : ndarray, shape (b,)
        Their values [kg m^2, kg m, kg; N m s/rad, N m].
    programs : dict
        :data:`FUNCTIONS` key -> :class:`~gd_analyze.symbolic.codegen.Program`, outputs
        row-major.
    """

    n: int
    joint_names: tuple
    parameter_names: tuple
    parameters: np.ndarray
    programs: dict

    def shape(self, spec: FunctionSpec) -> tuple[int, ...]:
        """The shape of a function's result.

        Parameters
        ----------
        spec : FunctionSpec

        Returns
        -------
        tuple of int
            (n,), (n, n) or (n, b).
        """
        return {"1": (self.n,), "n": (self.n, self.n),
                "b": (self.n, len(self.parameter_names))}[spec.columns]

    def numpy(self) -> dict[str, Any]:
        """The five functions as numpy callables: the emitted module, compiled once.

        Returns
        -------
        dict
            The module's namespace (:func:`.emit_model.numpy_source`): ``tau``, ``inertia``,
            ``velocity_terms``, ``gravity``, ``regressor`` over arrays of shape (N, n).
        """
        return self._numpy

    @cached_property
    def _numpy(self):
        ns: dict[str, Any] = {}
        exec(compile(numpy_source(self, {}), "<simplified_model.py>", "exec"), ns)
        return ns

    def costs(self) -> dict:
        """Counted operations per function (:meth:`Program.cost`), keyed as :data:`FUNCTIONS`."""
        return {spec.key: self.programs[spec.key].cost() for spec in FUNCTIONS}


def joint_labels(robot: Robot) -> tuple[str, ...]:
    """The joints' names, as the emitted files list them.

    Parameters
    ----------
    robot : Robot

    Returns
    -------
    tuple of str, length n
        :meth:`~gd_analyze.model.robot.Robot.joint_names` (the URDF's or Pinocchio
        model's names, else ``joint1`` .. ``jointn``), exactly: the emitted files write them
        as escaped string literals (:func:`~gd_analyze.symbolic.safe_text.c_string`,
        :func:`~gd_analyze.symbolic.safe_text.python_string`), so distinct names stay
        distinct and none can end its literal.
    """
    return tuple(str(v) for v in robot.joint_names())


def _symbols(n, name):
    return [se.Symbol(f"{name}{i}") for i in range(n)]


def _zero(n, *names):
    return {s: 0 for name in names for s in _symbols(n, name)}


def _inertia_from_linear(program, n):
    """D of a program linear in qdd: d tau_i / d qdd_j (i <= j), mirrored, at qd = qdd = 0."""
    entries = [(i, j) for i in range(n) for j in range(i, n)]
    assignments, upper = jacobian(program, _symbols(n, "qdd"), entries)
    out = [se.Integer(0)] * (n * n)
    for (i, j), e in zip(entries, upper):
        out[i * n + j] = out[j * n + i] = e
    return substitute(Program(n, assignments, out), _zero(n, "qd", "qdd"))


def _drives(robot, programs, names, values):
    """Armature on D's diagonal, friction and torque offset in h, and their regressor
    columns (the offset's a column of ones)."""
    n = robot.n
    arm, fv, fc, t0 = (np.asarray(getattr(robot, k), float) for k in DRIVE_FIELDS)
    if not (arm.any() or fv.any() or fc.any() or t0.any()):
        return programs, names, values
    qd, qdd = _symbols(n, "qd"), _symbols(n, "qdd")
    D, h, Y = (programs[k] for k in ("inertia", "velocity_terms", "regressor"))
    d_out, h_out = list(D.outputs), list(h.outputs)
    columns = []                                    # (name, value, joint, function)
    for i in range(n):
        if arm[i]:
            d_out[i * n + i] = d_out[i * n + i] + se.RealDouble(float(arm[i]))
            columns.append((f"Ia{i + 1}", arm[i], i, qdd[i]))
        extra = []
        for label, c, x in (("Fv", fv[i], qd[i]), ("Fc", fc[i], se.sign(qd[i])),
                            ("tau0_", t0[i], se.Integer(1))):
            if c:
                extra.append(se.RealDouble(float(c)) * x)
                columns.append((f"{label}{i + 1}", c, i, x))
        h_out[i] = se.Add(h_out[i], *extra)
    b0, b = len(names), len(names) + len(columns)
    y_out = [se.Integer(0)] * (n * b)
    for i in range(n):
        y_out[i * b:i * b + b0] = Y.outputs[i * b0:(i + 1) * b0]
    for m, (_, _, i, x) in enumerate(columns):
        y_out[i * b + b0 + m] = x
    return ({**programs, "inertia": Program(n, D.assignments, d_out),
             "velocity_terms": Program(n, h.assignments, h_out),
             "regressor": Program(n, Y.assignments, y_out)},
            list(names) + [c[0] for c in columns],
            np.concatenate([values, [float(c[1]) for c in columns]]))


def _functions(robot, tau, programs, names, values):
    programs, names, values = _drives(robot, {"tau": tau, **programs}, names, values)
    return ModelFunctions(n=robot.n, joint_names=joint_labels(robot),
                          parameter_names=tuple(names),
                          parameters=np.asarray(values, float), programs=programs)


def recursive_functions(robot: Robot, base: BaseParameters, left_out: ArrayLike,
                        tau: Program) -> ModelFunctions:
    """The functions of a model of the recursive form.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints (drives included).
    base : BaseParameters
        Its base parameters (b of them).
    left_out : array_like of bool, shape (b, 3)
        The (base parameter, part) pairs the model's program leaves out
        (:func:`.pruning.pruned_choice`).
    tau : Program
        The model's program, drives included (:func:`gd_analyze.symbolic.drive_regressor.with_drives`).

    Returns
    -------
    ModelFunctions
        Parameters: the base parameters (:meth:`gd_analyze.dynamics.base_parameters.BaseParameters.names`), then
        the drives'.

    Notes
    -----
    Each part is the recursion of the values it keeps (:func:`.pruning.part_values`) in every
    part: D_s is the derivative by qdd of that of the inertial values with gravity 0, h_s that
    of the velocity values at qdd = 0 with gravity 0, c_s that of the gravity values at
    qd = qdd = 0 (:func:`.transform.substitute`, :func:`.transform.jacobian`); by the
    decomposition of :mod:`.pruning` they add up to tau_s.
    """

    n = robot.n
    left_out = np.asarray(left_out, bool)
    values = part_values(base, left_out)
    still = dataclasses.replace(robot, gravity=np.zeros(3))

    def part(p, arm):                               # the form search barely pays here
        return parts_program(arm, np.stack([values[p]] * 3), search=False)
    programs = {
        "inertia": recursive_inertia(robot, base, left_out, search=False),
        "velocity_terms": substitute(part(1, still), _zero(n, "qdd")),
        "gravity": substitute(part(2, robot), _zero(n, "qd", "qdd")),
        "regressor": regressor_program(robot, base, ~left_out),
    }
    return _functions(robot, tau, programs, base.names(), np.asarray(base.beta, float))


def recursive_inertia(robot: Robot, base: BaseParameters, left_out: ArrayLike,
                      search: bool = True) -> Program:
    """D_s of a recursive model without the drives' armature: the inertial parts it keeps.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.
    base : BaseParameters
    left_out : array_like of bool, shape (b, 3)
        The pairs the model leaves out.
    search : bool, optional
        Choose each link's form by the count (:func:`.recursive.parts_program`); False is
        quicker.

    Returns
    -------
    Program
        D_s row-major (n x n) [kg m^2; kg]: the derivative by qdd of the recursion of the kept
        inertial values with gravity 0 (:func:`.transform.jacobian`), mirrored.
    """

    values = part_values(base, np.asarray(left_out, bool))[0]
    still = dataclasses.replace(robot, gravity=np.zeros(3))
    return _inertia_from_linear(parts_program(still, np.stack([values] * 3), search=search),
                                robot.n)


def explicit_functions(robot: Robot, terms: Term, tau: Program) -> ModelFunctions:
    """The functions of a model of the explicit form.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints (drives included).
    terms : gd_analyze.symbolic.explicit.Term
        The kept terms.
    tau : Program
        The model's program, drives included.

    Returns
    -------
    ModelFunctions
        Parameters: the kept coefficients (:meth:`.codegen.ExplicitProgram.regressor`), then
        the drives'.

    Notes
    -----
    D_s from the D groups, h_s = the program of the h terms alone, c_s that of the c terms
    alone (Eqs. (3.4-25) to (3.4-28) in the explicit form).
    """
    n, offset, lin = robot.n, np.zeros(robot.n), robot.prismatic

    def build(kind=None):
        sub = terms if kind is None else terms.subset(np.asarray(terms.kind) == kind)
        return ExplicitProgram(sub, n, offset, prismatic=lin)
    Y, names, values = build().regressor()
    programs = {"inertia": build("D").inertia(), "velocity_terms": build("h").tau(),
                "gravity": build("c").tau(), "regressor": Y}
    return _functions(robot, tau, programs, names, values)
