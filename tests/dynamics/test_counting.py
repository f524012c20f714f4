"""The operation ledger (gd_analyze.dynamics.counting): what counts as an operation."""

import numpy as np
import pytest

from gd_analyze.dynamics.counting import OpLedger, counting_clone


def test_operations_on_set_point_values_count_and_parameters_do_not():
    led = OpLedger()
    x, y, a, b = led.var(2.0), led.var(3.0), led.const(5.0), led.const(7.0)
    ab = a * b + a                      # parameters only: folded, not counted
    assert (led.multiplications, led.additions) == (0, 0)
    z = ab * x - y                      # one multiplication, one subtraction
    assert (led.multiplications, led.additions, z.value) == (1, 1, 40 * 2.0 - 3.0)
    w = x * 0 + y * 1 + x * -1          # structural constants: no count but the one addition
    assert (led.multiplications, led.additions) == (1, 2)
    assert w.value == pytest.approx(3.0 - 2.0)


def test_a_counted_value_never_slips_into_a_float():
    led = OpLedger()
    with pytest.raises(TypeError):
        float(led.var(1.0))


def test_a_cloned_kernel_counts_its_loop():
    def dot(u, v):
        s = u[0] * v[0]
        for k in range(1, u.shape[0]):
            s = s + u[k] * v[k]
        return s

    led = OpLedger()
    u = np.array([led.var(float(k)) for k in range(4)], dtype=object)
    v = np.array([led.var(1.0) for _ in range(4)], dtype=object)
    s = counting_clone(dot)(u, v)
    assert (led.multiplications, led.additions, s.value) == (4, 3, 6.0)
