"""Interval arithmetic: every operation encloses the exact values at points of its operands
(the package's sums and products by a number, and the array oracle's box arithmetic that the
compiled box kernels are tested against)."""
import interval_oracle as ivo
import numpy as np
import pytest

from gd_analyze.certify import intervals as iv


def _box(rng, shape):
    a, b = rng.normal(size=(2,) + shape) * 3
    return np.minimum(a, b), np.maximum(a, b)


def _inside(rng, box):
    t = rng.uniform(size=box[0].shape)
    return box[0] + t * (box[1] - box[0])


@pytest.mark.parametrize("op", ["add", "sub", "mul", "cross", "matvec"])
def test_operations_enclose_point_values(op):
    rng = np.random.default_rng(3)
    a, b = _box(rng, (200, 3)), _box(rng, (200, 3))
    M = rng.normal(size=(3, 3))
    f = {"add": (iv.add, np.add), "sub": (ivo.sub, np.subtract), "mul": (ivo.mul, np.multiply),
         "cross": (ivo.cross, np.cross),
         "matvec": (lambda x, y: ivo.matvec(M, x), lambda x, y: x @ M.T)}[op]
    lo, hi = f[0](a, b)
    for _ in range(50):
        x, y = _inside(rng, a), _inside(rng, b)
        v = f[1](x, y)
        assert np.all(lo <= v) and np.all(v <= hi)


def test_cos_sin_enclose_and_reach_the_extremes():
    rng = np.random.default_rng(4)
    lo = rng.uniform(-7, 7, 500)
    hi = lo + rng.uniform(0, 7, 500)
    (clo, chi), (slo, shi) = ivo.cos_sin(lo, hi)
    x = np.linspace(0, 1, 101)[:, None] * (hi - lo) + lo
    assert np.all(np.cos(x) >= clo) and np.all(np.cos(x) <= chi)
    assert np.all(np.sin(x) >= slo) and np.all(np.sin(x) <= shi)
    (c0, c1), _ = ivo.cos_sin(np.array([-0.1]), np.array([0.1]))
    assert c1[0] == 1.0 and c0[0] < np.cos(0.1) < c0[0] + 1e-12      # tight, rounded outward
    (c0, c1), _ = ivo.cos_sin(np.array([3.0]), np.array([3.3]))
    assert c0[0] == -1.0
