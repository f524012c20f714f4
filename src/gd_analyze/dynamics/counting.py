"""The counting scalar: numbers that count the multiplications and additions they take part in.

:class:`Counted` values share an :class:`OpLedger`; running an algorithm's own code on them (on
object arrays, or through :func:`counting_clone` for code that calls ``np.empty``, ``np.cos`` and
``np.sin``) counts its operations per set point. The counting rule is set out in
:mod:`gd_analyze.dynamics.opcount`, which uses this module for L-E, N-E and G-D.
"""

from __future__ import annotations

import ast
import importlib.util
import math
import numbers
import types
from collections.abc import Callable
from typing import Any

import numpy as np
import numpy.typing as npt

__all__ = ["OpLedger", "Counted", "counting_clone", "python_kernels"]


class OpLedger:
    """Tally of the operations done by the :class:`Counted` scalars that share it.

    Attributes
    ----------
    multiplications : int
        Multiplications counted so far.
    additions : int
        Additions and subtractions counted so far.
    """

    def __init__(self):
        self.multiplications = 0
        self.additions = 0

    def var(self, value: float) -> Counted:
        """A set-point-dependent scalar (its operations are counted).

        Parameters
        ----------
        value : float
            Its numerical value.

        Returns
        -------
        Counted

        Raises
        ------
        TypeError
            If value is not a real number.
        """
        return Counted(float(value), self, True)

    def const(self, value: float) -> Counted:
        """A robot parameter (operations between parameters only are not counted).

        Parameters
        ----------
        value : float
            Its numerical value.

        Returns
        -------
        Counted

        Raises
        ------
        TypeError
            If value is not a real number.
        """
        return Counted(float(value), self, False)


class Counted:
    """A real scalar that counts the multiplications and additions it takes part in.

    Parameters
    ----------
    value : float
        The numerical value carried along.
    ledger : OpLedger
        Where the operations are tallied.
    var : bool
        True if the value depends on the set point; False for a robot parameter.

    Raises
    ------
    TypeError
        From an arithmetic operation with an operand that is neither a Counted nor a real
        number, or on conversion to float.

    Notes
    -----
    An operation is counted when at least one operand is set-point dependent. Plain Python or
    NumPy numbers are structural constants: x * 0 gives the plain 0, x * 1 gives x, x * -1 gives
    -x and x + 0 gives x, all without a count. Negation is free; subtraction counts as an
    addition. There is no ``__float__``, so a Counted cannot slip silently into a float array.

    Examples
    --------
    >>> led = OpLedger()
    >>> x, y, a = led.var(2.0), led.var(3.0), led.const(5.0)
    >>> z = a * x + y * y - 0 * x
    >>> (led.multiplications, led.additions, z.value)
    (2, 1, 19.0)
    """

    __slots__ = ("value", "ledger", "var")

    def __init__(self, value: Any, ledger: OpLedger, var: bool = True) -> None:
        self.value = value
        self.ledger = ledger
        self.var = var

    def __repr__(self):
        return f"Counted({self.value!r}, var={self.var})"

    def __neg__(self):
        return Counted(-self.value, self.ledger, self.var)

    def __pos__(self):
        return self

    def __mul__(self, other):
        if isinstance(other, Counted):
            var = self.var or other.var
            self.ledger.multiplications += var
            return Counted(self.value * other.value, self.ledger, var)
        if not isinstance(other, numbers.Real):
            return NotImplemented
        if other == 0:
            return 0
        if other == 1:
            return self
        if other == -1:
            return -self
        self.ledger.multiplications += self.var
        return Counted(self.value * float(other), self.ledger, self.var)

    __rmul__ = __mul__

    def __add__(self, other):
        if isinstance(other, Counted):
            var = self.var or other.var
            self.ledger.additions += var
            return Counted(self.value + other.value, self.ledger, var)
        if not isinstance(other, numbers.Real):
            return NotImplemented
        if other == 0:
            return self
        self.ledger.additions += self.var
        return Counted(self.value + float(other), self.ledger, self.var)

    __radd__ = __add__

    def __sub__(self, other):
        return self + (-other)

    def __rsub__(self, other):
        return (-self) + other


def count_consts(led: OpLedger, x: npt.ArrayLike) -> npt.NDArray[np.object_]:
    """Object array of parameter scalars with the shape of x."""
    x = np.asarray(x, dtype=float)
    return np.array([led.const(v) for v in x.ravel()], dtype=object).reshape(x.shape)


def count_vars(led: OpLedger, x: npt.ArrayLike) -> npt.NDArray[np.object_]:
    """Set-point-dependent values as :class:`Counted` scalars of one ledger.

    Parameters
    ----------
    led : Ledger
        The operation ledger (its ``var``).
    x : array_like, any shape
        The values (q, qd, qdd [rad, rad/s, rad/s^2; m, m/s, m/s^2]).

    Returns
    -------
    ndarray of object, the shape of ``x``
        One :class:`Counted` per value; the operations they take part in are counted as in
        Table 3.5.
    """
    x = np.asarray(x, dtype=float)
    return np.array([led.var(v) for v in x.ravel()], dtype=object).reshape(x.shape)


def _elementwise(fn, x):
    """fn of a Counted (uncounted, keeps its kind), a plain number or an object array."""
    if isinstance(x, np.ndarray):
        return np.array([_elementwise(fn, e) for e in x.ravel()], dtype=object).reshape(x.shape)
    if isinstance(x, Counted):
        return Counted(fn(x.value), x.ledger, x.var)
    return fn(float(x))


class _CountingNumPy:
    """The NumPy functions that ``_gd_kernel.gd_kernel`` calls, for counting scalars."""

    @staticmethod
    def empty(shape):
        return np.zeros(shape, dtype=object)

    @staticmethod
    def cos(x):
        return _elementwise(math.cos, x)

    @staticmethod
    def sin(x):
        return _elementwise(math.sin, x)


def counting_clone(fn: Any) -> Callable[..., Any]:
    """The Python source of a numba kernel, bound to counting NumPy functions.

    Parameters
    ----------
    fn : numba dispatcher or function
        The kernel; the compiled helpers it calls (any global with a ``py_func``) are cloned
        the same way.

    Returns
    -------
    function
        Runs on object arrays of :class:`Counted` scalars; ``np.empty``, ``np.cos`` and
        ``np.sin`` are :class:`_CountingNumPy`'s.
    """
    py = getattr(fn, "py_func", fn)
    env = {**py.__globals__, "np": _CountingNumPy}
    for name in py.__code__.co_names:
        obj = env.get(name)
        if hasattr(obj, "py_func"):
            env[name] = counting_clone(obj)
    return types.FunctionType(py.__code__, env, py.__name__, py.__defaults__, py.__closure__)


def _python_njit(*args, **options):
    """numba's ``njit`` as a no-op: the function itself, its own ``py_func``."""
    def mark(fn):
        fn.py_func = fn
        return fn
    return mark(args[0]) if args and callable(args[0]) else mark


def python_kernels(module: str) -> dict[str, Any]:
    """A module of numba kernels, run as plain Python without importing numba.

    Parameters
    ----------
    module : str
        The module's dotted name (e.g. ``"gd_analyze.dynamics.kernels"``); it imports
        ``njit`` from numba at its top level.

    Returns
    -------
    dict
        The module's namespace, executed from its own source with every ``from numba import
        ...`` left out and ``njit`` a decorator that returns the function itself (with a
        ``py_func``, as :func:`counting_clone` expects): the kernels' Python source, as numba
        compiles it (``fn.py_func``), without numba's import and start-up (about 0.45 s).

    Raises
    ------
    ModuleNotFoundError
        If the module cannot be found.
    NameError
        If the module uses from numba anything but ``njit``.

    Examples
    --------
    >>> ns = python_kernels("gd_analyze.dynamics.kernels")
    >>> ns["gd_kernel"].py_func is ns["gd_kernel"]
    True
    """
    spec = importlib.util.find_spec(module)
    if spec is None:
        raise ModuleNotFoundError(module)
    assert spec.origin is not None                  # a module with a source file
    loader: Any = spec.loader                       # its InspectLoader (get_source)
    tree = ast.parse(loader.get_source(module), spec.origin)
    tree.body = [node for node in tree.body
                 if not (isinstance(node, ast.ImportFrom) and node.module == "numba")]
    namespace = {"__name__": f"{module}.python", "__package__": spec.parent,
                 "__file__": spec.origin, "njit": _python_njit}
    exec(compile(tree, spec.origin, "exec"), namespace)
    return namespace


def count_value(x: Counted | float) -> float:
    """The float value of a :class:`Counted` scalar, or of a plain number.

    Parameters
    ----------
    x : Counted or float

    Returns
    -------
    float

    Examples
    --------
    >>> count_value(2.5)
    2.5
    """
    return x.value if isinstance(x, Counted) else float(x)
