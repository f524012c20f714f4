"""Compiled parsing of a regular CSV body of plain decimal numbers, correctly rounded.

:func:`parse_body` reads the lines after the header of a trajectory CSV file (bytes) into a
float array in one pass, checking as it goes that every line has the same number of fields and
every field is a plain decimal number with nothing else but spaces and tabs around it::

    [ \\t]* [+-]? (digits [. digits*] | . digits) [(e|E) [+-]? digits] [ \\t]*

each line ending in ``\\n``, ``\\r\\n`` or the end of the file. Anything else (quotes, a blank
line, a stray ``\\r``, a field longer than :data:`MAX_FIELD` bytes) makes it give up: the caller
then parses the file cell by cell, which accepts or locates the fault exactly.

Every value is the double nearest to the decimal number, ties to even, as Python's ``float()``
gives it: the first 19 significant digits w and the decimal exponent q, then

- Clinger's fast path where w <= 2^53 and |q| <= 22: one correctly rounded IEEE product or
  quotient of two exact doubles;
- otherwise the Eisel-Lemire algorithm (D. Lemire, "Number parsing at a gigabyte per second",
  Software: Practice and Experience 51(8), 2021, Sec. 5-6): w times a 128-bit truncation of
  5^q, rounded where the product's bits decide the rounding; for more than 19 significant
  digits, where w and w + 1 round to the same double.

A field where neither applies for certain (the product cannot decide, a subnormal or
overflowing result, more digits where w and w + 1 disagree) is handed back to the caller, who
converts it with ``float()``.
"""

from __future__ import annotations

import functools

import numpy as np
from numba import njit

__all__ = ["parse_body", "count_lines", "MAX_FIELD", "HARD_CELLS"]

#: Longest field accepted [bytes, spaces included]; a longer one is left to the cell-by-cell
#: parser (which refuses a number of more than 1000 characters).
MAX_FIELD = 1000
#: Fields handed back for ``float()`` per call of the kernel, at most.
HARD_CELLS = 1 << 14

_DONE, _FULL, _BAD = 0, 1, 2
_U = np.uint64
_M32 = np.uint64(0xFFFFFFFF)
_ONES = np.uint64(0xFFFFFFFFFFFFFFFF)
_S32 = np.uint64(32)
_S63 = np.uint64(63)
_S52 = np.uint64(52)
_S9 = np.uint64(9)              # 64 - (52 explicit mantissa bits + 3)
_MASK55 = np.uint64(0x1FF)      # the product's bits below the 55 that matter
_HIDDEN = np.uint64(1 << 52)
_TWO53 = np.uint64(1 << 53)
_SIGN = np.uint64(1 << 63)
_TEN = np.uint64(10)
_ONE = np.uint64(1)
_THREE = np.uint64(3)


@functools.lru_cache(maxsize=1)
def _tables():
    """The 128-bit truncated powers 5^q, q = -342..308, as high and low 64-bit words (Lemire
    2021, Appendix B), and the exact doubles 10^0..10^22."""
    hi, lo = np.empty(651, np.uint64), np.empty(651, np.uint64)
    for k, q in enumerate(range(-342, 309)):
        if q < 0:
            p5 = 5 ** -q
            z = p5.bit_length()                 # the least z with 2^z >= 5^-q
            if q >= -27:
                c = (1 << (z + 127)) // p5 + 1
            else:
                c = (1 << (2 * z + 128)) // p5 + 1
                while c >= 1 << 128:
                    c >>= 1
        else:
            c = 5 ** q
            while c < 1 << 127:
                c <<= 1
            while c >= 1 << 128:
                c >>= 1
        hi[k], lo[k] = c >> 64, c & ((1 << 64) - 1)
    return hi, lo, np.array([float(10 ** k) for k in range(23)])


@njit(cache=True, nogil=True, inline="always")
def _mul128(a, b):  # pragma: no cover - compiled
    """The 128-bit product of two uint64 as (high, low) words."""
    a0, a1, b0, b1 = a & _M32, a >> _S32, b & _M32, b >> _S32
    p00, p01, p10, p11 = a0 * b0, a0 * b1, a1 * b0, a1 * b1
    mid = (p00 >> _S32) + (p01 & _M32) + (p10 & _M32)
    return p11 + (p01 >> _S32) + (p10 >> _S32) + (mid >> _S32), (mid << _S32) | (p00 & _M32)


@njit(cache=True, nogil=True, inline="always")
def _eisel_lemire(w, q, hi5, lo5):  # pragma: no cover - compiled
    """The bits of the double nearest to w 10^q (w > 0, -342 <= q <= 308) and whether they are
    certain; not certain also where the result is subnormal or infinite."""
    lz = 0
    for s in (32, 16, 8, 4, 2, 1):          # normalise: the top bit of w set
        if (w >> _U(64 - s)) == _U(0):
            w = w << _U(s)
            lz += s
    k = q + 342
    hi, lo = _mul128(w, hi5[k])
    if (hi & _MASK55) == _MASK55:           # the low word may carry: refine it
        hi2, _ = _mul128(w, lo5[k])
        lo = lo + hi2
        if hi2 > lo:
            hi = hi + _ONE
    if lo == _ONES and (q < -27 or q > 55):
        return _U(0), False
    upper = hi >> _S63
    shift = upper + _S9
    mantissa = hi >> shift
    power2 = ((q * 217706) >> 16) + 63 + np.int64(upper) - lz + 1023
    if power2 <= 0:
        return _U(0), False
    if (lo <= _ONE and -4 <= q <= 23 and (mantissa & _THREE) == _ONE
            and (mantissa << shift) == hi):
        mantissa = mantissa & ~_ONE         # exactly halfway: round to even, down
    mantissa = (mantissa + (mantissa & _ONE)) >> _ONE
    if mantissa >= _U(2 << 52):
        mantissa = _HIDDEN
        power2 += 1
    if power2 >= 2047:
        return _U(0), False
    return (_U(power2) << _S52) | (mantissa & ~_HIDDEN), True


@njit(cache=True, nogil=True)
def count_lines(buf, start):  # pragma: no cover - compiled
    """The number of ``\\n`` bytes in buf[start:]."""
    c = 0
    body = buf[start:]
    for k in range(body.shape[0]):
        if body[k] == 10:
            c += 1
    return c


@njit(cache=True, nogil=True)
def _parse(buf, pos, row, out, bits, hi5, lo5, p10, hard):  # pragma: no cover - compiled
    """Parse rows from ``pos`` on into out[:, row:] (out and bits: the same (F, R) memory as
    float64 and uint64); returns (status, row, pos, hard fields) where status is done, full
    (resume at row, pos after the caller converted the hard fields) or bad."""
    F, R = out.shape
    n = buf.shape[0]
    nh = 0
    while row < R:
        if nh + F > hard.shape[0]:
            return _FULL, row, pos, nh
        for f in range(F):
            field = pos
            while pos < n and (buf[pos] == 32 or buf[pos] == 9):
                pos += 1
            start = pos
            neg = False
            if pos < n and (buf[pos] == 45 or buf[pos] == 43):
                neg = buf[pos] == 45
                pos += 1
            w = _U(0)
            taken = 0                       # significant digits in w, at most 19
            q = 0
            digits = 0
            more = False                    # a nonzero digit beyond the 19th
            point = False                   # past the decimal point
            while pos < n:
                c = buf[pos]
                if 48 <= c <= 57:
                    d = _U(c - 48)
                    if taken < 19:
                        if w != _U(0) or d != _U(0):
                            w = w * _TEN + d
                            taken += 1
                        q -= point
                    else:
                        q += not point
                        more = more or d != _U(0)
                    digits += 1
                elif c == 46 and not point:
                    point = True
                else:
                    break
                pos += 1
            if digits == 0:
                return _BAD, row, pos, nh
            if pos < n and (buf[pos] == 101 or buf[pos] == 69):
                pos += 1
                sign = 1
                if pos < n and (buf[pos] == 45 or buf[pos] == 43):
                    sign = -1 if buf[pos] == 45 else 1
                    pos += 1
                if not (pos < n and 48 <= buf[pos] <= 57):
                    return _BAD, row, pos, nh
                e = 0
                while pos < n and 48 <= buf[pos] <= 57:
                    if e < 100000:
                        e = e * 10 + (buf[pos] - 48)
                    pos += 1
                q += sign * e
            stop = pos
            while pos < n and (buf[pos] == 32 or buf[pos] == 9):
                pos += 1
            if pos - field > MAX_FIELD:
                return _BAD, row, pos, nh
            if f < F - 1:
                if not (pos < n and buf[pos] == 44):
                    return _BAD, row, pos, nh
                pos += 1
            else:
                if pos < n and buf[pos] == 13:
                    pos += 1
                    if not (pos < n and buf[pos] == 10):
                        return _BAD, row, pos, nh
                if pos < n:
                    if buf[pos] != 10:
                        return _BAD, row, pos, nh
                    pos += 1
            # the value
            if w == _U(0):
                bits[f, row] = _SIGN if neg else _U(0)
                continue
            if not more and w <= _TWO53 and -22 <= q <= 22:
                v = np.float64(w)
                v = v * p10[q] if q >= 0 else v / p10[-q]
                out[f, row] = -v if neg else v
                continue
            ok = -342 <= q <= 308
            if ok:
                b, ok = _eisel_lemire(w, q, hi5, lo5)
                if ok and more:             # the digits beyond lie between w and w + 1
                    b2, ok2 = _eisel_lemire(w + _ONE, q, hi5, lo5)
                    ok = ok2 and b2 == b
            if ok:
                bits[f, row] = (b | _SIGN) if neg else b
            else:
                hard[nh, 0], hard[nh, 1], hard[nh, 2], hard[nh, 3] = start, stop, f, row
                nh += 1
        row += 1
    if pos != n:
        return _BAD, row, pos, nh
    return _DONE, row, pos, nh


def parse_body(raw, start, fields):
    """The numbers of the lines of ``raw`` from byte ``start`` on, or None if they are not
    regular.

    Parameters
    ----------
    raw : bytes
        The file's bytes.
    start : int
        The first byte after the header line.
    fields : int
        Fields per line (the header's).

    Returns
    -------
    ndarray, shape (N, fields), or None
        A Fortran-ordered view (each column contiguous), every value ``float()`` of its
        field; None if a line is not ``fields`` plain decimal numbers (module docstring), or
        there is no line.
    """
    buf = np.frombuffer(raw, np.uint8)
    body = len(raw) - start
    if body <= 0:
        return None
    rows = int(count_lines(buf, start)) + (raw[-1:] != b"\n")
    out = np.empty((fields, rows))
    hi5, lo5, p10 = _tables()
    hard = np.empty((max(HARD_CELLS, fields), 4), np.int64)
    status, row, pos = _FULL, 0, start
    while status == _FULL:
        status, row, pos, nh = _parse(buf, pos, row, out, out.view(np.uint64), hi5, lo5, p10,
                                      hard)
        for s, e, f, r in hard[:nh].tolist():
            out[f, r] = float(raw[s:e])
    return out.T if status == _DONE and row == rows else None
