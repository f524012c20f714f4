"""The vertex search of a quadratic form against exact enumeration in rational arithmetic."""

from __future__ import annotations

import itertools
from fractions import Fraction

import numpy as np
import pytest

from gd_analyze.certify.regressor_bounds import _QuadraticBound
from gd_analyze.certify.vertex_kernel import BLOCK, vertex_extremes


def _exact(mid, j, l, w, s):
    """max and min over v in {-1, 1}^s, v_0 = 1, of sum_p m_p w_p v_j v_l, exactly."""
    terms = [[Fraction(float(m)) * Fraction(float(wp)) for m, wp in zip(row, w)] for row in mid]
    tops, bottoms = [], []
    for row in terms:
        values = []
        for rest in itertools.product((1, -1), repeat=s - 1):
            v = (1,) + rest
            values.append(sum(t * v[a] * v[b] for t, a, b in zip(row, j, l)))
        tops.append(max(values))
        bottoms.append(min(values))
    return tops, bottoms


def _case(rng, s, rows, spread=1.0):
    j, l = np.triu_indices(s, 1)
    mid = rng.standard_normal((rows, j.size)) * 10.0 ** rng.uniform(-spread, spread, (rows, j.size))
    w = rng.uniform(0.1, 4.0, j.size)
    return mid, j, l, w


@pytest.mark.parametrize("s", [1, 2, 3, 5, 8])
def test_the_extremes_enclose_the_exact_ones_and_are_tight(s):
    rng = np.random.default_rng(s)
    mid, j, l, w = _case(rng, s, 7)
    top, bottom = vertex_extremes(mid, j, l, w, s)
    tops, bottoms = _exact(mid, j, l, w, s) if s > 1 else ([0] * 7, [0] * 7)
    scale = np.abs(mid) @ w + 1e-300
    for r in range(7):
        assert Fraction(float(top[r])) >= tops[r]
        assert Fraction(float(bottom[r])) <= bottoms[r]
        assert float(top[r] - tops[r]) <= 1e-10 * scale[r]
        assert float(bottoms[r] - bottom[r]) <= 1e-10 * scale[r]


def test_more_vertices_than_a_block_and_more_rows_than_a_pass():
    """2^10 vertices (16 blocks) and 300 rows (two passes), against float enumeration."""
    s, rows = 11, 300
    rng = np.random.default_rng(11)
    mid, j, l, w = _case(rng, s, rows)
    assert 2 ** (s - 1) > BLOCK
    top, bottom = vertex_extremes(mid, j, l, w, s)
    signs = np.array([(1,) + v for v in itertools.product((1.0, -1.0), repeat=s - 1)])
    values = mid @ ((signs[:, j] * signs[:, l]) * w).T
    scale = np.abs(mid) @ w
    assert np.all(top >= values.max(axis=1) - 1e-14 * scale)
    assert np.all(bottom <= values.min(axis=1) + 1e-14 * scale)
    assert np.all(top - values.max(axis=1) <= 1e-10 * scale)
    assert np.all(values.min(axis=1) - bottom <= 1e-10 * scale)


def test_cancellation_is_covered_by_the_round_off_bound():
    """Terms of 1e16 that cancel beside terms of 1: the float sums lose the small ones."""
    s = 9
    j, l = np.triu_indices(s, 1)
    rng = np.random.default_rng(3)
    mid = np.where(rng.random((4, j.size)) < 0.3, 1e16, 1.0) * rng.choice([-1.0, 1.0],
                                                                          (4, j.size))
    mid += rng.standard_normal((4, j.size))
    w = np.ones(j.size)
    top, bottom = vertex_extremes(mid, j, l, w, s)
    tops, bottoms = _exact(mid, j, l, w, s)
    for r in range(4):
        assert Fraction(float(top[r])) >= tops[r]
        assert Fraction(float(bottom[r])) <= bottoms[r]


def test_shapes_that_do_not_agree_are_refused():
    j, l = np.triu_indices(4, 1)
    with pytest.raises(ValueError, match="pairs"):
        vertex_extremes(np.zeros((2, j.size)), j, l, np.ones(j.size), 5)
    with pytest.raises(ValueError, match="pairs"):
        vertex_extremes(np.zeros((2, j.size)), j[:-1], l, np.ones(j.size), 4)


def test_the_quadratic_bound_encloses_the_form_over_the_velocity_box():
    """max |qd^T C qd| over the box, with C anywhere in its intervals, against dense samples
    and the box's vertices with C at the interval ends."""
    rng = np.random.default_rng(5)
    n, rows = 6, 5
    a = rng.uniform(0.5, 3.0, n)
    mid = rng.standard_normal((rows, n * n))
    rad = 0.1 * rng.random((rows, n * n))
    bound = _QuadraticBound(n, a)(mid - rad, mid + rad)
    bottom, top = _QuadraticBound(n, a).range(mid - rad, mid + rad)
    qd = rng.uniform(-1, 1, (20000, n)) * a
    qd[:64] = np.array(list(itertools.product((-1.0, 1.0), repeat=n)))[:64] * a
    for r in range(rows):
        for C in (mid[r] - rad[r], mid[r] + rad[r], mid[r] + rad[r] * rng.uniform(-1, 1, n * n)):
            form = np.einsum("bj,jl,bl->b", qd, C.reshape(n, n), qd)
            assert np.abs(form).max() <= bound[r]
            assert bottom[r] <= form.min() and form.max() <= top[r]


@pytest.mark.parametrize("s", [1, 2, 3, 5, 8])
def test_the_found_extremes_are_the_exact_ones_to_round_off(s):
    """found_extremes against exact rational enumeration: the same extremes to round-off."""
    from gd_analyze.certify.vertex_kernel import found_extremes

    rng = np.random.default_rng(s + 40)
    mid, j, l, w = _case(rng, s, 7)
    top, bottom = found_extremes(mid, j, l, w, s)
    tops, bottoms = _exact(mid, j, l, w, s) if s > 1 else ([0] * 7, [0] * 7)
    scale = np.abs(mid) @ w + 1e-300
    for r in range(7):
        assert abs(float(Fraction(float(top[r])) - tops[r])) <= 1e-13 * scale[r]
        assert abs(float(Fraction(float(bottom[r])) - bottoms[r])) <= 1e-13 * scale[r]


@pytest.mark.parametrize("s", [8, 9, 13])
def test_the_found_extremes_split_the_signs_and_the_rows(s):
    """More signs than the inner half (and exactly as many), more rows than a pass: the
    extremes of every sign pattern with v_0 = 1 (oracle: a matrix of all 2^(s-1) patterns),
    and those of vertex_extremes without widening, to round-off."""
    from gd_analyze.certify.vertex_kernel import INNER, found_extremes

    rows = 300 if s < 13 else 40
    rng = np.random.default_rng(s)
    mid, j, l, w = _case(rng, s, rows, spread=2.0)
    assert s >= INNER
    top, bottom = found_extremes(mid, j, l, w, s)
    signs = np.array([(1,) + v for v in itertools.product((1.0, -1.0), repeat=s - 1)])
    values = mid @ ((signs[:, j] * signs[:, l]) * w).T
    scale = np.abs(mid) @ w
    assert np.all(np.abs(top - values.max(axis=1)) <= 1e-13 * scale)
    assert np.all(np.abs(bottom - values.min(axis=1)) <= 1e-13 * scale)
    gray_top, gray_bottom = vertex_extremes(mid, j, l, w, s, widen=False)
    assert np.all(np.abs(top - gray_top) <= 1e-13 * scale)
    assert np.all(np.abs(bottom - gray_bottom) <= 1e-13 * scale)
    with pytest.raises(ValueError, match="pairs"):
        found_extremes(mid[:, 1:], j[1:], l[1:], w[1:], s)


def test_the_found_extremes_read_in_place_are_those_of_the_gathered_rows():
    """Rows (b, g, i) read in place from an array (B, C, N, b) by channel and column, times a
    factor: bit for bit the extremes of the same coefficients gathered into rows first."""
    from gd_analyze.certify.vertex_kernel import found_extremes

    rng = np.random.default_rng(9)
    s, B, C, N, b = 10, 30, 60, 4, 5
    j, l = np.triu_indices(s, 1)
    V = rng.standard_normal((B, C, N, b))
    chans = rng.choice(C, j.size, replace=False)
    cols = np.array([4, 1, 2])
    w = rng.uniform(0.1, 4.0, j.size)
    mid = (2.0 * V[:, chans][..., cols]).transpose(0, 3, 2, 1).reshape(-1, j.size)
    want = found_extremes(mid, j, l, w, s)
    got = found_extremes(V, j, l, w, s, channels=chans, columns=cols, factor=2.0)
    for x, y in zip(got, want):
        assert x.shape == (B * cols.size * N,)
        np.testing.assert_array_equal(x, y)


@pytest.mark.parametrize("s", [5, 14])
def test_the_found_extremes_over_listed_vertices_are_theirs(s):
    """Over a list of vertices (some repeated, some negated, not all): the extremes of the
    form at those vertices (oracle: one matrix product), to round-off, and not those of all."""
    from gd_analyze.certify.vertex_kernel import found_extremes

    rng = np.random.default_rng(s + 7)
    mid, j, l, w = _case(rng, s, 300)
    signs = rng.choice([-1.0, 1.0], (40 if s > 5 else 5, s))
    signs = np.vstack([signs, -signs[:3], signs[:2]])
    top, bottom = found_extremes(mid, j, l, w, s, vertices=signs)
    top2, bottom2 = found_extremes(mid[:, :, None, None], j, l, w, s,
                                   channels=np.arange(j.size), vertices=signs)
    np.testing.assert_array_equal(top, top2)
    np.testing.assert_array_equal(bottom, bottom2)
    values = mid @ ((signs[:, j] * signs[:, l]) * w).T
    scale = np.abs(mid) @ w
    assert np.all(np.abs(top - values.max(axis=1)) <= 1e-13 * scale)
    assert np.all(np.abs(bottom - values.min(axis=1)) <= 1e-13 * scale)
    everything = found_extremes(mid, j, l, w, s)
    assert np.any(everything[0] > top + 1e-9 * scale)
