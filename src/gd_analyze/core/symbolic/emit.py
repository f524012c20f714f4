"""C99 and numpy Python source of a straight-line program, and its Python function.

:func:`emit_c` writes ``void gd_simplified_tau(q, qd, qdd, tau)`` (only math.h included, one
external symbol), :func:`emit_python` a module whose ``tau(q, qd, qdd)`` is vectorised over set
points (only numpy imported); :func:`python_function` is that function compiled once per
program. Both print the very expressions of the program that
:func:`gd_analyze.core.symbolic.operation_count.count_operations` counts: sums of more than a
few terms are printed flat (in chunks, as Python's compiler nests binary operators), negative
coefficients as subtractions, powers as products, ``sign`` as numpy's (``sign(0) = 0``). The
header's text passes through :func:`gd_analyze.core.symbolic.safe_text.header_lines`.
"""

from __future__ import annotations

import symengine as se

from .operation_count import is_number
from .safe_text import header_lines

__all__ = ["C_FUNCTION", "emit_c", "emit_python", "python_function"]

#: The exported C function.
C_FUNCTION = "gd_simplified_tau"


def _fmtis_number(x):
    v = float(x)
    return repr(v) if v == v else "NAN"


def _print(e, lang, prec=0):
    """Print an expression; prec: 0 top/sum, 1 product operand, 2 atom."""
    if e.is_Symbol:
        return _ref(e.name, lang)
    if is_number(e):
        s = _fmtis_number(e)
        return f"({s})" if s.startswith("-") and prec > 0 else s
    if e.is_Add:
        terms = list(e.args)
        terms.sort(key=lambda t: is_number(t))             # constants last
        return _print_sum(terms, lang, prec)
    if e.is_Mul:
        neg, body = _split_sign(e)
        factors = list(body.args) if body.is_Mul else [body]
        factors.sort(key=lambda t: not is_number(t))       # constant first
        s = "*".join(_print(f, lang, 2) for f in factors)
        if neg:
            s = f"-{s}"
            return f"({s})" if prec > 0 else s
        return s
    if e.is_Pow:
        base, ex = e.args
        b = _print(base, lang, 2)
        return "(" + "*".join([b] * int(float(ex))) + ")"
    if isinstance(e, se.sign):          # sign(0) = 0, as numpy's
        x = _print(e.args[0], lang, 2)
        return f"np.sign({x})" if lang == "py" else f"({x} > 0 ? 1.0 : {x} < 0 ? -1.0 : 0.0)"
    if isinstance(e, (se.sin, se.cos)):
        fn = "sin" if isinstance(e, se.sin) else "cos"
        fn = f"np.{fn}" if lang == "py" else fn
        return f"{fn}({_print(e.args[0], lang, 0)})"
    raise ValueError(f"cannot print {e}")


#: Longest run of terms printed as one flat sum (Python's compiler nests binary operators).
_SUM_CHUNK = 32


def _print_sum(terms, lang, prec):
    if len(terms) > _SUM_CHUNK:
        chunks = [terms[a:a + _SUM_CHUNK] for a in range(0, len(terms), _SUM_CHUNK)]
        out = " + ".join(_print_sum(c, lang, 1) for c in chunks)
        return f"({out})" if prec > 0 else out
    out = ""
    for t in terms:
        neg, body = _split_sign(t)
        s = _print(body, lang, 1)
        out += (" - " if neg else " + ") + s if out else ("-" + s if neg else s)
    return f"({out})" if prec > 0 or len(terms) > 1 and prec > 0 else out


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


def _ref(name, lang):
    for prefix, arr in (("qdd", "qdd"), ("qd", "qd"), ("q", "q")):
        if name.startswith(prefix) and name[len(prefix):].isdigit():
            idx = int(name[len(prefix):])
            return f"{arr}[{idx}]" if lang == "c" else f"{arr}[:, {idx}]"
    return name


def emit_c(program, header):
    """C99 source of the program: ``void gd_simplified_tau(q, qd, qdd, tau)``.

    Parameters
    ----------
    program : Program
    header : dict
        Lines of the header comment (robot, SHA-256s, tolerance, counts, version); keys and
        values are written through :func:`~gd_analyze.core.symbolic.safe_text.header_lines`.

    Returns
    -------
    str
        Standalone C99 that includes only math.h; arrays of n doubles in SI units. Its only
        external symbol is ``gd_simplified_tau``.
    """
    lines = ["/*"] + [f" * {ln}" for ln in header_lines(header)] + [" */",
             "#include <math.h>", "",
             f"void {C_FUNCTION}(const double *q, const double *qd, const double *qdd, "
             "double *tau)", "{"]
    for s, e in program.assignments:
        lines.append(f"    const double {s.name} = {_print(e, 'c')};")
    for i, e in enumerate(program.outputs):
        lines.append(f"    tau[{i}] = {_print(e, 'c')};")
    lines += ["}", ""]
    return "\n".join(lines)


def python_function(program):
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


#: The emitted Python module's docstring: fixed text, the header follows as comments.
_PY_DOC = '"""Simplified G-D model emitted by gd-analyze: tau(q, qd, qdd); header below."""'


def emit_python(program, header):
    """numpy source of the program: ``tau(q, qd, qdd)`` vectorised over set points.

    Parameters
    ----------
    program : Program
    header : dict
        Lines of the header, written as ``#`` comments from the third line on (after a fixed
        docstring, so that no input text can be a PEP 263 coding line), keys and values
        through :func:`~gd_analyze.core.symbolic.safe_text.header_lines`.

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
    for s, e in program.assignments:
        lines.append(f"    {s.name} = {_print(e, 'py')}")
    for i, e in enumerate(program.outputs):
        lines.append(f"    out[:, {i}] = {_print(e, 'py')}")
    lines += ["    return out", ""]
    return "\n".join(lines)
