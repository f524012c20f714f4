"""Printers of straight-line programs: one per language (C99, numpy, CasADi), one pipeline.

A program (:class:`~gd_analyze.symbolic.codegen.Program`: temporaries, then outputs) has
its common subexpressions already eliminated (:mod:`.subexpressions`); a :class:`Printer` writes
each temporary as one statement and each output into its slot of the result, in the style of
SymPyBotics (Sousa & Cortesao 2014: a model's expressions, then cse, then a code printer per
language). The three printers differ only in how they name an input, call a function and write
a statement:

- :data:`C`: ``const double x0 = cos(q[1]);`` and ``D[7] = x0;``, only math.h;
- :data:`NUMPY`: ``x0 = np.cos(q[:, 1])`` over a batch of N set points, ``out[:, 1, 1] = x0``;
- :data:`CASADI`: ``x0 = ca.cos(q[1])`` on ``casadi.SX`` symbols, outputs returned as a list.

All print the very expressions that
:func:`gd_analyze.symbolic.operation_count.count_operations` counts: sums of more than a
few terms flat (in runs, as Python's compiler nests binary operators), negative coefficients as
subtractions, powers as products, ``sign`` as numpy's (``sign(0) = 0``). :func:`emit_c` and
:func:`emit_python` print one program computing tau (a test bench, and
:func:`python_function`); the deployed model's files are :mod:`.emit_model`'s. Headers pass
through :func:`gd_analyze.symbolic.safe_text.header_lines`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import symengine as se

from .operation_count import is_number
from .safe_text import header_lines

if TYPE_CHECKING:
    from .codegen import Program

__all__ = ["Printer", "C", "NUMPY", "CASADI", "STATE", "emit_c", "emit_python",
           "emit_state_python", "python_function", "state_function"]


@dataclass(frozen=True)
class Printer:
    """How one language writes the expressions of a program.

    Attributes
    ----------
    name : str
        ``"c"``, ``"numpy"``, ``"casadi"`` or ``"state"`` (Python floats, one state).
    index : str
        How an input is indexed, a format of ``name`` and ``i``: ``"{name}[{i}]"`` (one set
        point) or ``"{name}[:, {i}]"`` (a batch, one row per set point).
    module : str
        Prefix of sin, cos and sign (``""``, ``"np."``, ``"ca."``, ``"math."``).
    temporary : str
        A temporary's statement, a format of ``name`` and ``expr``.
    """

    name: str
    index: str
    module: str
    temporary: str

    def symbol(self, name: str) -> str:
        """A symbol's text.

        Parameters
        ----------
        name : str
            An input (``q3``, ``qd0``, ``qdd1``) or a temporary's name.

        Returns
        -------
        str
            The input as an indexed array (:attr:`index`), or the name.
        """
        for prefix in ("qdd", "qd", "q"):
            if name.startswith(prefix) and name[len(prefix):].isdigit():
                return self.index.format(name=prefix, i=int(name[len(prefix):]))
        return name

    def sign(self, x: str) -> str:
        """sign(x) with sign(0) = 0.

        Parameters
        ----------
        x : str
            The argument's text.

        Returns
        -------
        str
        """
        if self.name == "c":
            return f"({x} > 0 ? 1.0 : {x} < 0 ? -1.0 : 0.0)"
        if self.name == "state":
            return f"(({x} > 0) - ({x} < 0))"
        return f"{self.module}sign({x})"

    def expression(self, e: se.Basic, prec: int = 0) -> str:
        """An expression's text.

        Parameters
        ----------
        e : symengine.Basic
        prec : int, optional
            Where it stands: 0 at the top or in a sum, 1 a product's operand, 2 an atom
            (parentheses as needed).

        Returns
        -------
        str

        Raises
        ------
        ValueError
            For an expression outside the straight-line programs' kinds (sums, products,
            integer powers, cos, sin, sign).
        """
        if e.is_Symbol:
            return self.symbol(e.name)
        if is_number(e):
            s = _number(e)
            return f"({s})" if s.startswith("-") and prec > 0 else s
        if e.is_Add:
            terms = sorted(e.args, key=is_number)            # constants last
            return self._sum(terms, prec)
        if e.is_Mul:
            neg, body = _split_sign(e)
            factors = list(body.args) if body.is_Mul else [body]
            factors.sort(key=lambda t: not is_number(t))     # constant first
            s = "*".join(self.expression(f, 2) for f in factors)
            if neg:
                s = f"-{s}"
                return f"({s})" if prec > 0 else s
            return s
        if e.is_Pow:
            base, ex = e.args
            b = self.expression(base, 2)
            return "(" + "*".join([b] * int(float(ex))) + ")"
        if isinstance(e, se.sign):
            return self.sign(self.expression(e.args[0], 2))
        if isinstance(e, (se.sin, se.cos)):
            fn = "sin" if isinstance(e, se.sin) else "cos"
            return f"{self.module}{fn}({self.expression(e.args[0], 0)})"
        raise ValueError(f"cannot print {e}")

    def _sum(self, terms, prec):
        if len(terms) > _SUM_CHUNK:
            chunks = [terms[a:a + _SUM_CHUNK] for a in range(0, len(terms), _SUM_CHUNK)]
            out = " + ".join(self._sum(c, 1) for c in chunks)
            return f"({out})" if prec > 0 else out
        out = ""
        for t in terms:
            neg, body = _split_sign(t)
            s = self.expression(body, 1)
            out += (" - " if neg else " + ") + s if out else ("-" + s if neg else s)
        return f"({out})" if prec > 0 else out

    def body(self, program: Program, target: Callable[..., Any] | None,
             indent: str = "    ") -> list[str]:
        """The statements of a program: its temporaries, then each output into its slot.

        Parameters
        ----------
        program : Program
        target : callable
            Output index -> the text it is assigned to (``"tau[2]"``, ``"out[:, 0, 1]"``);
            None for a printer that collects the outputs itself (:data:`CASADI`).
        indent : str, optional

        Returns
        -------
        list of str
        """
        lines = [indent + self.temporary.format(name=s.name, expr=self.expression(e))
                 for s, e in program.assignments]
        end = ";" if self.name == "c" else ""
        if target is None:
            return lines
        return lines + [f"{indent}{target(k)} = {self.expression(e)}{end}"
                        for k, e in enumerate(program.outputs)]


#: Longest run of terms printed as one flat sum (Python's compiler nests binary operators).
_SUM_CHUNK = 32

#: The three printers.
C = Printer("c", "{name}[{i}]", "", "const double {name} = {expr};")
NUMPY = Printer("numpy", "{name}[:, {i}]", "np.", "{name} = {expr}")
CASADI = Printer("casadi", "{name}[{i}]", "ca.", "{name} = {expr}")
STATE = Printer("state", "{name}[{i}]", "math.", "{name} = {expr}")


def _number(x):
    v = float(x)
    return repr(v) if v == v else "NAN"


def _split_sign(t):
    """(negative?, |t|) for a product with a negative numeric coefficient."""
    if t.is_Mul:
        coeff = [a for a in t.args if is_number(a)]
        if coeff and float(coeff[0]) < 0:
            c = -float(coeff[0])
            rest = [a for a in t.args if not is_number(a)]
            body = se.Mul(*rest) if c == 1.0 else se.Mul(se.RealDouble(c), *rest)
            if c == 1.0 and len(rest) == 1:
                body = rest[0]
            return True, body
    if is_number(t) and float(t) < 0:
        return True, se.RealDouble(-float(t))
    return False, t


def emit_c(program: Program, header: dict[str, Any], prefix: str = "gd_") -> str:
    """C99 source of one program: ``void <prefix>tau(q, qd, qdd, tau)`` (a test bench).

    Parameters
    ----------
    program : Program
    header : dict
        Lines of the header comment, keys and values through
        :func:`~gd_analyze.symbolic.safe_text.header_lines`.
    prefix : str, optional
        Prefix of the function's name (a C identifier; not checked here).

    Returns
    -------
    str
        Standalone C99 that includes only math.h; arrays of n doubles in SI units. The
        deployed model's files are :func:`.emit_model.c_source` and
        :func:`.emit_model.c_header`.
    """
    lines = ["/*"] + [f" * {ln}" for ln in header_lines(header)] + [" */",
             "#include <math.h>", "",
             f"void {prefix}tau(const double *q, const double *qd, const double *qdd, "
             "double *tau)", "{"]
    lines += C.body(program, lambda k: f"tau[{k}]")
    return "\n".join(lines + ["}", ""])


def python_function(program: Program) -> Callable[..., Any]:
    """The program's ``tau(q, qd, qdd)`` as a Python function, compiled once per program.

    Parameters
    ----------
    program : Program

    Returns
    -------
    callable
        ``tau`` of :func:`emit_python` (the header does not change what it computes):
        arrays of shape (N, n) [rad, rad/s, rad/s^2; m, m/s, m/s^2 for a prismatic joint]
        to shape (N, n) [N m; N].
    """
    return program._tau_function


def state_function(program: Program) -> Callable[..., Any]:
    """The program's torques at one state, in Python floats, compiled once per program.

    Parameters
    ----------
    program : Program

    Returns
    -------
    callable
        ``tau(q, qd, qdd)``: three sequences of n floats [rad, rad/s, rad/s^2; m, m/s, m/s^2
        for a prismatic joint] to a list of n floats [N m; N]; the same operations as
        :func:`python_function` in the same order (:func:`emit_state_python`), without numpy's
        per-call cost on one set point (the closed loop's right-hand side,
        :mod:`gd_analyze.jobs.control`). A sine or cosine of an infinite angle raises
        ``ValueError`` (Python's ``math``).
    """
    return program._state_function


def emit_state_python(program: Program) -> str:
    """Python source of one program at one state: ``tau(q, qd, qdd)`` in floats.

    Parameters
    ----------
    program : Program

    Returns
    -------
    str
        A module that imports only math; no header (nothing of the input's text).
    """
    lines = ["import math", "", "", "def tau(q, qd, qdd):",
             f"    out = [0.0] * {int(program.n)}"]
    lines += STATE.body(program, lambda k: f"out[{k}]")
    return "\n".join(lines + ["    return out", ""])


#: The docstring of :func:`emit_python`'s module: fixed text, the header follows as comments.
_PY_DOC = '"""Simplified G-D model emitted by gd-analyze: tau(q, qd, qdd); header below."""'


def emit_python(program: Program, header: dict[str, Any]) -> str:
    """numpy source of one program: ``tau(q, qd, qdd)`` vectorised over set points.

    Parameters
    ----------
    program : Program
    header : dict
        Lines of the header, written as ``#`` comments from the third line on (after a fixed
        docstring, so that no input text can be a PEP 263 coding line), keys and values
        through :func:`~gd_analyze.symbolic.safe_text.header_lines`.

    Returns
    -------
    str
        A module that imports only numpy; ``tau(q, qd, qdd)`` takes arrays of shape (N, n)
        (or (n,)) [rad, rad/s, rad/s^2] and returns shape (N, n) [N m].
    """
    lines = [_PY_DOC, ""] + [f"# {ln}" for ln in header_lines(header)] + [
             "", "import numpy as np", "",
             f"N_JOINTS = {program.n}", "", "",
             "def tau(q, qd, qdd):",
             '    """Joint torques [N m], shape (N, n), of q, qd, qdd of shape (N, n)."""',
             "    q, qd, qdd = (np.atleast_2d(np.asarray(x, dtype=float)) for x in "
             "(q, qd, qdd))",
             "    out = np.zeros(np.broadcast_shapes(q.shape, qd.shape, qdd.shape))",
             "    if out.shape[-1] != N_JOINTS:",
             "        raise ValueError(f'expected {N_JOINTS} joints, got shape {out.shape}')"]
    lines += NUMPY.body(program, lambda k: f"out[:, {k}]")
    return "\n".join(lines + ["    return out", ""])
