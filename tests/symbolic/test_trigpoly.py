"""Trigonometric polynomials (symbolic/trigpoly.py) against numpy's sin and cos at random
angles, trigonometric identities (the canonical form is unique, so equal functions have equal
rows), and derivatives against the analytic ones."""

import numpy as np
import pytest

from gd_analyze.symbolic.trigpoly import TrigPoly, _unique_rows, evaluate_rows

RNG = np.random.default_rng(2024)
THETA = RNG.uniform(-np.pi, np.pi, (50, 3))


def rows(p):
    """The rows as a sorted list, for comparing representations."""
    return sorted((tuple(int(v) for v in k), bool(s), round(float(c), 12)) for k, s, c in p.rows())


def c(i, lin=None):
    return TrigPoly.cos(3, i, lin)


def s(i, lin=None):
    return TrigPoly.sin(3, i, lin)


def test_pythagoras_and_double_angles_collapse_to_their_canonical_rows():
    assert rows(s(1) * s(1) + c(1) * c(1)) == [((0, 0, 0), False, 1.0)]
    assert rows(2.0 * s(0) * c(0)) == [((2, 0, 0), True, 1.0)]            # sin 2x
    assert rows(c(0) * c(0) - s(0) * s(0)) == [((2, 0, 0), False, 1.0)]   # cos 2x
    # angle addition: cos(t1 + t2) and sin(t2 - t3), with the first nonzero harmonic > 0
    assert rows(c(0) * c(1) - s(0) * s(1)) == [((1, 1, 0), False, 1.0)]
    assert rows(s(1) * c(2) - c(1) * s(2)) == [((0, 1, -1), True, 1.0)]
    assert rows(s(2) * c(1) - c(2) * s(1)) == [((0, 1, -1), True, -1.0)]  # sin(-x) = -sin x
    assert len(s(0) - s(0)) == 0 and (s(0) - s(0)).constant() == 0.0


def test_products_sums_and_scalars_agree_with_numpy():
    S, C = np.sin(THETA), np.cos(THETA)
    p = (c(0) * s(1) + 0.3 * s(2)) * (s(0) - 2.0 * c(1) * c(2) + 1.5) - 0.7
    want = (C[:, 0] * S[:, 1] + 0.3 * S[:, 2]) * (S[:, 0] - 2.0 * C[:, 1] * C[:, 2] + 1.5) - 0.7
    np.testing.assert_allclose(p(THETA), want, rtol=0, atol=1e-12)
    q = 2.0 - s(1) * s(1) * s(1) * c(2)                                 # __rsub__, powers
    np.testing.assert_allclose(q(THETA), 2.0 - S[:, 1] ** 3 * C[:, 2], rtol=0, atol=1e-12)
    # the product is commutative and associative as a representation
    a, b, d = c(0) + s(2), s(1) * c(0) - 0.5, c(2) * c(2) + s(0)
    assert rows(a * b) == rows(b * a)
    assert rows((a * b) * d) == rows(a * (b * d))
    assert rows(a * 0) == [] and rows(0.0 + a) == rows(a)


def test_derivatives_are_the_analytic_ones():
    S, C = np.sin(THETA), np.cos(THETA)
    p = c(0) * s(1) * s(1) + 0.5 * c(2) * s(0)
    # d/dt0 and d/dt1 by hand
    np.testing.assert_allclose(p.diff(0)(THETA), -S[:, 0] * S[:, 1] ** 2 + 0.5 * C[:, 2] * C[:, 0],
                               rtol=0, atol=1e-12)
    np.testing.assert_allclose(p.diff(1)(THETA), 2 * C[:, 0] * S[:, 1] * C[:, 1],
                               rtol=0, atol=1e-12)
    np.testing.assert_allclose(p.diff(2)(THETA), -0.5 * S[:, 2] * S[:, 0], rtol=0, atol=1e-12)
    assert len(TrigPoly.const(3, 4.0).diff(1)) == 0


def test_polynomial_columns_hold_powers_of_a_length():
    lin = [False, True, False]
    d = TrigPoly.var(3, 1, lin)
    x = THETA.copy()
    x[:, 1] = RNG.uniform(-0.5, 0.8, 50)           # a length [m]
    p = (d * c(0, lin) + 0.3 * s(2, lin) * d * d - 1.5) * (s(0, lin) * d + 2.0)
    D, S0, C0, S2 = x[:, 1], np.sin(x[:, 0]), np.cos(x[:, 0]), np.sin(x[:, 2])
    np.testing.assert_allclose(p(x), (D * C0 + 0.3 * S2 * D ** 2 - 1.5) * (S0 * D + 2.0),
                               rtol=0, atol=1e-12)
    dp = p.diff(1)                                   # d/dd by the product rule
    want = (C0 + 0.6 * S2 * D) * (S0 * D + 2.0) + (D * C0 + 0.3 * S2 * D ** 2 - 1.5) * S0
    np.testing.assert_allclose(dp(x), want, rtol=0, atol=1e-12)
    # the power of d keeps its sign: d * cos(-t0) is d cos t0, not 1/d
    assert rows(d * TrigPoly(np.array([[-1, 0, 0]]), [False], [1.0], lin=lin)) == \
        [((1, 1, 0), False, 1.0)]
    assert (d * d).constant() == 0.0 and (d * d + 3.0).constant() == 3.0
    with pytest.raises(ValueError, match="not polynomial"):
        TrigPoly.var(3, 0, lin)


def test_evaluate_rows_is_cos_or_sin_of_the_harmonic_times_the_powers():
    K = np.array([[1, 0, 2], [0, 3, -1], [2, 1, 0]])
    S = np.array([False, True, True])
    ang = THETA @ K.T
    np.testing.assert_allclose(evaluate_rows(K, S, THETA),
                               np.column_stack([np.cos(ang[:, 0]), np.sin(ang[:, 1]),
                                                np.sin(ang[:, 2])]), rtol=0, atol=1e-12)
    lin = np.array([False, True, False])
    got = evaluate_rows(K, S, THETA, lin)
    a = THETA[:, [0, 2]] @ K[:, [0, 2]].T
    want = np.column_stack([np.cos(a[:, 0]), np.sin(a[:, 1]) * THETA[:, 1] ** 3,
                            np.sin(a[:, 2]) * THETA[:, 1]])
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)


def test_rounding_residue_is_dropped_relative_to_the_largest_coefficient():
    p = TrigPoly(np.array([[1, 0, 0], [0, 1, 0]]), [False, False], [1.0, 1e-16])
    assert rows(p) == [((1, 0, 0), False, 1.0)]
    q = TrigPoly(np.array([[1, 0, 0], [0, 1, 0]]), [False, False], [1.0, 1e-10])
    assert len(q) == 2


def test_unique_rows_are_numpys_unique_rows():
    """The canonical form's distinct rows and inverse equal np.unique(axis=0)'s (the oracle),
    on random small integer arrays with repeated rows, one column, and none."""
    rng = np.random.default_rng(3)
    keys = [rng.integers(-3, 4, (int(rng.integers(1, 60)), int(rng.integers(1, 9))))
            for _ in range(300)] + [np.zeros((0, 4), np.int64), np.zeros((5, 1), np.int64)]
    for key in keys:
        uniq, inv = np.unique(key, axis=0, return_inverse=True)
        got, got_inv = _unique_rows(key)
        assert got.dtype == uniq.dtype and got.shape == uniq.shape
        np.testing.assert_array_equal(got, uniq)
        np.testing.assert_array_equal(got_inv, inv.reshape(-1))
