"""The deployed model's files: a C header and source, a numpy module, a CasADi module.

Every file holds the five functions of :data:`FUNCTIONS` (tau, inertia,
velocity_terms, gravity, regressor) of one :class:`.model_functions.ModelFunctions`, printed by
the printers of :mod:`.emit` from the same programs:

- :func:`c_header` (``STEM.h``): include guard, ``extern "C"`` for C++, the constants
  ``PREFIX_N_JOINTS``, ``PREFIX_N_BASE_PARAMETERS``, ``PREFIX_JOINT_NAMES`` and the prototypes
  ``void PREFIX<function>(const double *q, ..., double *out)``, arrays row-major, and
  ``void PREFIX<function>_batch(long n, const double *q, ..., double *out)``, the same at n
  states (row-major, state after state), plus ``extern const double PREFIX_base_parameters[]``;
- :func:`c_source` (``STEM.c``): their definitions, including only math.h and the header; the
  batch functions run the single-state program on blocks of :data:`BATCH_BLOCK` states in a
  loop of unit stride that GCC vectorises at ``-O3`` (:data:`BATCH_COMPILE`), sin and cos
  through glibc's libmvec (SIMD across states; Fu, Gonzalez & Lee's equations unchanged);
- :func:`numpy_source` (``STEM.py``): the functions batched over N set points, importing only
  numpy;
- :func:`casadi_source` (``STEM_casadi.py``): ``functions()`` returning a dict of
  ``casadi.Function`` built from ``casadi.SX`` by the same programs, and
  ``batch_functions(n_states)`` those mapped over states, importing only casadi.

:data:`ARTEFACTS` is the one table of these files: what the main job and ``sweep`` write and
what the reports list. Input text (robot name, file names) reaches them only as comment text
through :func:`gd_analyze.symbolic.safe_text.header_lines`; joint names only as string
literals that escape every character but letters, digits, space and ``_ . -``
(:func:`.safe_text.c_string`, :func:`.safe_text.python_string`); the prefix only when it is a
C identifier (:func:`.safe_text.check_prefix`), and in the include guard with a hash of it
(:func:`.safe_text.include_guard`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .emit import CASADI, NUMPY, C, Printer
from .safe_text import (
    c_string,
    check_prefix,
    comment_safe,
    header_lines,
    include_guard,
    python_string,
)

if TYPE_CHECKING:
    from .model_functions import ModelFunctions


__all__ = ["FunctionSpec", "FUNCTIONS", "Artefact", "ARTEFACTS", "artefact_names", "render",
           "c_header", "c_source", "numpy_source", "casadi_source"]


@dataclass(frozen=True)
class FunctionSpec:
    """One function of the deployed model.

    Attributes
    ----------
    key : str
        Its name, e.g. ``"inertia"`` (the C function is ``PREFIX<key>``).
    inputs : tuple of str
        The argument arrays, of n values each (``"q"``, ``"qd"``, ``"qdd"``).
    output : str
        The result's name (``"tau"``, ``"D"``, ``"h"``, ``"c"``, ``"Y"``).
    columns : str
        ``"1"`` (a vector of n), ``"n"`` (n x n) or ``"b"`` (n x b, b parameters).
    text : str
        What it returns, with units.
    """

    key: str
    inputs: tuple
    output: str
    columns: str
    text: str


#: The five functions, in the order every emitted file lists them.
FUNCTIONS = (
    FunctionSpec("tau", ("q", "qd", "qdd"), "tau", "1",
                 "joint torques tau_s = D_s qdd + h_s + c_s [N m; N for a prismatic joint]"),
    FunctionSpec("inertia", ("q",), "D", "n",
                 "inertia matrix D_s, n x n row-major, symmetric, armature on the diagonal "
                 "[kg m^2; kg]"),
    FunctionSpec("velocity_terms", ("q", "qd"), "h", "1",
                 "Coriolis and centrifugal terms h_s plus joint friction F_v qd + F_c sign(qd) "
                 "[N m; N]"),
    FunctionSpec("gravity", ("q",), "c", "1", "gravity terms c_s [N m; N]"),
    FunctionSpec("regressor", ("q", "qd", "qdd"), "Y", "b",
                 "regressor Y_s, n x b row-major, tau_s = Y_s beta_s [N m per unit of beta]"),
)



@dataclass(frozen=True)
class Artefact:
    """One emitted file.

    Attributes
    ----------
    suffix : str
        Appended to the stem (``simplified_model``, ``merged_model``): ``".h"``, ``".c"``...
    language : str
        What it is, for the reports.
    printer : callable
        ``printer(functions, header, prefix, stem)`` -> the file's text.
    """

    suffix: str
    language: str
    printer: Callable[..., str]

    def name(self, stem: str) -> str:
        """The file's name for a stem.

        Parameters
        ----------
        stem : str
            E.g. ``simplified_model``.

        Returns
        -------
        str
            E.g. ``simplified_model_casadi.py``.
        """
        return f"{stem}{self.suffix}"


def _dims(functions, prefix):
    return f"{prefix}N_JOINTS", f"{prefix}N_BASE_PARAMETERS"


def _signature(spec, prefix):
    args = ", ".join(f"const double *{a}" for a in spec.inputs)
    return f"void {prefix}{spec.key}({args}, double *{spec.output})"


def _batch_signature(spec, prefix):
    args = ", ".join(f"const double *{a}" for a in spec.inputs)
    return f"void {prefix}{spec.key}_batch(long n, {args}, double *{spec.output})"


#: How to compile the batch functions so that GCC evaluates sin and cos on 2, 4 or 8 states
#: at once (glibc's libmvec, declared in the source; no -ffast-math); the header's comment.
BATCH_COMPILE = "cc -std=c99 -O3 -march=native -c STEM.c (link with -lm)"

#: The C source's sin and cos of the batch loops: on GCC, x86-64 and glibc, sin and cos
#: themselves (assembler names) declared with GCC's ``simd`` attribute, so that the vectoriser
#: calls glibc's libmvec (_ZGV*_sin, _ZGV*_cos; at most 4 ulp) at -O3 without -ffast-math
#: (which <bits/math-vector.h> requires); under their own names, which GCC does not fuse into
#: sincos (a call it cannot vectorise) as it fuses sin and cos of one angle.
_LIBMVEC = [
    "#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) \\",
    "    && defined(__GLIBC__) && !defined(__FAST_MATH__)",
    '__attribute__((simd("notinbranch"))) double gd_vsin(double) __asm__("sin");',
    '__attribute__((simd("notinbranch"))) double gd_vcos(double) __asm__("cos");',
    "#else",
    "#define gd_vsin sin",
    "#define gd_vcos cos",
    "#endif",
    "#if defined(__GNUC__) && !defined(__clang__)",
    '#define GD_BATCH_IVDEP _Pragma("GCC ivdep")',
    "#else",
    "#define GD_BATCH_IVDEP",
    "#endif"]


def _batch_body(spec, program, n, size, inputs):
    """The C lines of one batch loop: the single-state program on blocks of BATCH_BLOCK states.

    ``inputs`` are the arguments the program uses (the others are cast to void).

    Each block's inputs are copied into arrays of one row per joint and one column per state,
    the program runs over the block's columns in a loop of
    unit stride that GCC vectorises, and the block's results are copied back row-major.
    """
    w = BATCH_BLOCK
    printer = Printer("c", "{name}_b[{i}][l]", "gd_v", "const double {name} = {expr};")
    lines = ["    long k, l, m, j;"]
    lines += [f"    double {a}_b[{n}][{w}];" for a in inputs]
    lines += [f"    double {spec.output}_b[{max(size, 1)}][{w}];",
              f"    for (k = 0; k < n; k += {w}) {{",
              f"        m = n - k < {w} ? n - k : {w};",
              f"        for (j = 0; j < {n}; ++j)",
              "            for (l = 0; l < m; ++l) {"]
    lines += [f"                {a}_b[j][l] = {a}[{n} * (k + l) + j];" for a in inputs]
    lines += ["            }", "        GD_BATCH_IVDEP", "        for (l = 0; l < m; ++l) {"]
    lines += printer.body(program, lambda j, o=spec.output: f"{o}_b[{j}][l]",
                          indent="            ")
    lines += ["        }", f"        for (j = 0; j < {size}; ++j)",
              "            for (l = 0; l < m; ++l)",
              f"                {spec.output}[{size} * (k + l) + j] = {spec.output}_b[j][l];",
              "    }"]
    return lines


#: States per block of the batch functions (4 AVX2 lanes twice, or 8 AVX-512 lanes).
BATCH_BLOCK = 8


def _comment(lines):
    return ["/*"] + [f" * {ln}" if ln else " *" for ln in lines] + [" */"]


def _parameter_lines(functions):
    return [f"  {k:3d}  {comment_safe(name)} = {value!r}" for k, (name, value) in
            enumerate(zip(functions.parameter_names, map(float, functions.parameters)))]


def _batch_note(stem):
    """The header comment's note on the batch functions."""
    return [
        "Each function f has f_batch(n, ...): f at n states, arrays row-major, state after state,",
        "the same operations as f in the same order. Compiled with",
        "    " + BATCH_COMPILE.replace("STEM", stem),
        "GCC evaluates n states 2, 4 or 8 at once (SSE2, AVX2, AVX-512), sin and cos through",
        f"glibc's libmvec (declared in {stem}.c; no -ffast-math, which would change the results);",
        "otherwise the loop is a plain loop over f's statements. Vector sin and cos are within",
        "4 ulp of the scalar ones, so f_batch equals f to rounding, not bit for bit."]


def c_header(functions: ModelFunctions, header: dict[str, Any], prefix: str, stem: str) -> str:
    """The C header ``STEM.h``.

    Parameters
    ----------
    functions : ModelFunctions
    header : dict
        The header comment's entries (:func:`.safe_text.header_lines`).
    prefix : str
        Prefix of every symbol, a C identifier (e.g. ``puma560_``).
    stem : str
        The files' stem (names the include guard's tail).

    Returns
    -------
    str
        C99 and C++ (``extern "C"``): constants, joint names, prototypes of the five functions
        and of their batch calls ``PREFIX<function>_batch(n, ...)`` (arrays row-major, SI
        units; the comment gives the compile line of :data:`BATCH_COMPILE`) and ``extern const double PREFIXbase_parameters[]``.

    Raises
    ------
    ValueError
        If the prefix is not a C identifier (:func:`.safe_text.check_prefix`).
    """
    prefix = check_prefix(prefix)
    nj, nb = _dims(functions, prefix)
    guard = include_guard(prefix, stem)
    names = ", ".join(c_string(v) for v in functions.joint_names)
    lines = _comment(header_lines(header) + ["", *_batch_note(stem)]) + [
        f"#ifndef {guard}", f"#define {guard}", "",
        "#ifdef __cplusplus", 'extern "C" {', "#endif", "",
        f"#define {nj} {functions.n}",
        f"#define {nb} {len(functions.parameter_names)}", "",
        "/* The joints' names, their exact UTF-8 bytes (other than letters, digits, space,"
        " _ . - as octal escapes). */",
        f"static const char *const {prefix}JOINT_NAMES[{nj}] = {{{names}}};", ""]
    for spec in FUNCTIONS:
        rows, cols = functions.shape(spec) + (1,) * (2 - len(functions.shape(spec)))
        size = f"{rows}" if len(functions.shape(spec)) == 1 else f"{rows} x {cols}"
        lines += _comment([f"{spec.key}({', '.join(spec.inputs)}): {spec.text}; "
                           f"{spec.output} has {size} doubles."]) + [
            _signature(spec, prefix) + ";", ""]
        lines += _comment([f"{spec.key}_batch(n, {', '.join(spec.inputs)}): the same at n "
                           f"states, row-major: each input has n x {functions.n} doubles, "
                           f"{spec.output} n x {size}; arrays must not overlap."]) + [
            _batch_signature(spec, prefix) + ";", ""]
    lines += _comment(["beta_s, the parameters of the regressor's columns (tau = Y beta):"]
                      + _parameter_lines(functions))
    lines += [f"extern const double {prefix}base_parameters[{nb}];", "",
              "#ifdef __cplusplus", "}", "#endif", "", f"#endif /* {guard} */", ""]
    return "\n".join(lines)


def c_source(functions: ModelFunctions, header: dict, prefix: str, stem: str) -> str:
    """The C source ``STEM.c``: the definitions of :func:`c_header`'s declarations.

    Parameters
    ----------
    functions, header, prefix, stem
        As :func:`c_header`.

    Returns
    -------
    str
        C99 that includes only math.h and ``STEM.h``; compiles under ``-Wall -Wextra
        -Werror``.

    Raises
    ------
    ValueError
        If the prefix is not a C identifier.
    """
    prefix = check_prefix(prefix)
    _, nb = _dims(functions, prefix)
    values = [f"    {float(v)!r}," for v in functions.parameters] or ["    0.0,"]
    lines = _comment(header_lines(header)) + [
        "#include <math.h>", f'#include "{stem}.h"', ""] + _LIBMVEC + [
        "", f"const double {prefix}base_parameters[{nb}] = {{"] + values + ["};"]
    for spec in FUNCTIONS:
        program = functions.programs[spec.key]
        used = {s.name for e in [e for _, e in program.assignments] + list(program.outputs)
                for s in e.free_symbols}
        inputs = [a for a in spec.inputs
                  if any(u.startswith(a) and u[len(a):].isdigit() for u in used)]
        unused = [f"    (void){a};" for a in spec.inputs if a not in inputs]
        lines += ["", _signature(spec, prefix), "{"] + unused
        lines += C.body(program, lambda k, o=spec.output: f"{o}[{k}]")
        lines.append("}")
        lines += ["", _batch_signature(spec, prefix), "{"] + unused
        lines += _batch_body(spec, program, functions.n, int(np.prod(functions.shape(spec))),
                             inputs)
        lines.append("}")
    return "\n".join(lines + [""])


def _py_head(functions, header, what):
    doc = (f'"""Simplified G-D model emitted by gd-analyze ({what}): tau, inertia, '
           'velocity_terms, gravity, regressor; header below."""')
    names = ", ".join(python_string(v) for v in functions.joint_names)
    pnames = ", ".join(repr(comment_safe(v)) for v in functions.parameter_names)
    return [doc, ""] + [f"# {ln}" for ln in header_lines(header)] + [""], [
        f"N_JOINTS = {functions.n}",
        f"N_BASE_PARAMETERS = {len(functions.parameter_names)}",
        f"JOINT_NAMES = ({names}{',' if functions.n == 1 else ''})",
        f"BASE_PARAMETER_NAMES = ({pnames}{',' if len(functions.parameter_names) == 1 else ''})"]


_NUMPY_STATES = '''

def _states(*arrays):
    """The arrays as float arrays of shape (N, n), broadcast together."""
    arrays = [np.atleast_2d(np.asarray(x, dtype=float)) for x in arrays]
    shape = np.broadcast_shapes(*(x.shape for x in arrays))
    if len(shape) != 2 or shape[-1] != N_JOINTS:
        raise ValueError(f'expected {N_JOINTS} joints, got shape {shape}')
    return [np.broadcast_to(x, shape) for x in arrays]
'''


def numpy_source(functions: ModelFunctions, header: dict, prefix: str | None = None,
                 stem: str | None = None) -> str:
    """The numpy module ``STEM.py``: the five functions batched over set points.

    Parameters
    ----------
    functions, header
        As :func:`c_header`.
    prefix, stem : str, optional
        Not used (Python modules are their own namespace).

    Returns
    -------
    str
        A module that imports only numpy: ``tau(q, qd, qdd)`` -> (N, n), ``inertia(q)`` ->
        (N, n, n), ``velocity_terms(q, qd)`` and ``gravity(q)`` -> (N, n), ``regressor(q, qd,
        qdd)`` -> (N, n, b), inputs of shape (N, n) or (n,) [rad, rad/s, rad/s^2]; constants
        ``N_JOINTS``, ``JOINT_NAMES``, ``BASE_PARAMETER_NAMES``, ``BASE_PARAMETERS``. A wrong
        number of joints raises ValueError.
    """
    head, consts = _py_head(functions, header, "numpy")
    values = ", ".join(repr(float(v)) for v in functions.parameters)
    lines = head + ["import numpy as np", ""] + consts + [
        f"BASE_PARAMETERS = np.array([{values}])"] + _NUMPY_STATES.split("\n")
    for spec in FUNCTIONS:
        lines += _numpy_function(spec, functions.programs[spec.key], functions.shape(spec))
    return "\n".join(lines + [""])


def _numpy_function(spec, program, shape):
    """The lines of one batched numpy function (it needs ``np`` and ``_states``)."""
    args = ", ".join(spec.inputs)
    idx = (lambda k: f"out[:, {k}]") if len(shape) == 1 else \
        (lambda k, c=shape[1]: f"out[:, {k // c}, {k % c}]")
    lines = ["", "", f"def {spec.key}({args}):",
             f'    """{spec.text}; shape (N, {", ".join(map(str, shape))})."""',
             f"    {args}{',' if len(spec.inputs) == 1 else ''} = _states({args})",
             f"    out = np.zeros(({spec.inputs[0]}.shape[0], {', '.join(map(str, shape))}))"]
    return lines + NUMPY.body(program, idx) + ["    return out"]


_CASADI_TAIL = '''

def _matrix(flat, rows, cols):
    """A casadi.SX of shape (rows, cols) from its entries, row-major."""
    out = ca.SX.zeros(rows, cols)
    for k, value in enumerate(flat):
        out[k // cols, k % cols] = value
    return out


def functions():
    """The model's casadi.Function objects, keyed tau, inertia, velocity_terms, gravity and
    regressor, of SX arguments q, qd, qdd (n x 1); results as the C functions', as matrices."""
    x = {name: ca.SX.sym(name, N_JOINTS) for name in ("q", "qd", "qdd")}
    out = {}
    for key, fn, inputs, output, rows, cols in _FUNCTIONS:
        value = _matrix(fn(*(x[a] for a in inputs)), rows, cols)
        out[key] = ca.Function(PREFIX + key, [x[a] for a in inputs], [value], list(inputs),
                               [output])
    return out


def batch_functions(n_states, parallelization="serial"):
    """functions() mapped over n_states states (casadi.Function.map): each argument an
    N_JOINTS x n_states matrix, one column per state; each result its n_states blocks side by
    side (tau: N_JOINTS x n_states)."""
    return {key: fn.map(n_states, parallelization) for key, fn in functions().items()}
'''


def casadi_source(functions: ModelFunctions, header: dict, prefix: str,
                  stem: str | None = None) -> str:
    """The CasADi module ``STEM_casadi.py``.

    Parameters
    ----------
    functions, header, prefix
        As :func:`c_header` (the prefix names the ``casadi.Function`` objects).
    stem : str, optional
        Not used.

    Returns
    -------
    str
        A module that imports only casadi: ``functions()`` returns a dict of
        ``casadi.Function`` keyed ``tau``, ``inertia``, ``velocity_terms``, ``gravity``,
        ``regressor``, each built from ``casadi.SX`` by the same program as the C function;
        ``batch_functions(n_states)`` the same mapped over n_states states (one column each);
        ``BASE_PARAMETERS`` is a tuple of floats. Written whether or not casadi is installed.

    Raises
    ------
    ValueError
        If the prefix is not a C identifier.
    """
    prefix = check_prefix(prefix)
    head, consts = _py_head(functions, header, "CasADi")
    values = ", ".join(repr(float(v)) for v in functions.parameters)
    lines = head + ["import casadi as ca", ""] + consts + [
        f"BASE_PARAMETERS = ({values}{',' if len(functions.parameters) == 1 else ''})",
        f"PREFIX = {prefix!r}"]
    table = []
    for spec in FUNCTIONS:
        program = functions.programs[spec.key]
        shape = functions.shape(spec) + (1,)
        lines += ["", "", f"def _{spec.key}({', '.join(spec.inputs)}):",
                  f'    """{spec.text}: its {len(program.outputs)} entries, row-major."""']
        lines += CASADI.body(program, None)
        outs = ", ".join(CASADI.expression(e) for e in program.outputs)
        lines.append(f"    return [{outs}]")
        table.append(f"    ({spec.key!r}, _{spec.key}, {spec.inputs!r}, {spec.output!r}, "
                     f"{shape[0]}, {shape[1]}),")
    lines += ["", "", "_FUNCTIONS = ("] + table + [")"] + _CASADI_TAIL.split("\n")[1:]
    return "\n".join(lines)


#: The emitted files, in the order they are written and listed.
ARTEFACTS = (
    Artefact(".h", "C header", c_header),
    Artefact(".c", "C99", c_source),
    Artefact(".py", "numpy", numpy_source),
    Artefact("_casadi.py", "CasADi", casadi_source),
)


def artefact_names(stem: str) -> tuple[str, ...]:
    """The emitted files' names for a stem, in :data:`ARTEFACTS` order.

    Parameters
    ----------
    stem : str
        ``"simplified_model"`` or ``"merged_model"``.

    Returns
    -------
    tuple of str

    Examples
    --------
    >>> artefact_names("merged_model")
    ('merged_model.h', 'merged_model.c', 'merged_model.py', 'merged_model_casadi.py')
    """
    return tuple(a.name(stem) for a in ARTEFACTS)


def render(functions: ModelFunctions, header: dict, prefix: str, stem: str) -> dict:
    """Every emitted file's text.

    Parameters
    ----------
    functions : ModelFunctions
    header : dict
    prefix : str
        A C identifier (:func:`.safe_text.check_prefix`).
    stem : str

    Returns
    -------
    dict
        File name -> text, in :data:`ARTEFACTS` order.
    """
    return {a.name(stem): a.printer(functions, header, prefix, stem) for a in ARTEFACTS}
