"""The compiled regressor kernel (regressor_compiled._contributions_kernel), called directly:
its contributions summed over parts and base parameters are Pinocchio's rnea, and the array
code of the tests' oracle (numpy_engines) gives its values."""

import numpy as np
import pytest
from numpy_engines import part_contributions_numpy
from symbolic_helpers import rnea, robot, states

from gd_analyze.dynamics.base_parameters import base_parameters
from gd_analyze.dynamics.regressor_compiled import _contributions_kernel
from gd_analyze.dynamics.regressor_kernels import _arguments


@pytest.mark.parametrize("name", ("puma560", "stanford"))
def test_the_kernel_sums_to_rnea_and_the_array_code_gives_its_values(name):
    arm = robot(name)
    base = base_parameters(arm)
    q, qd, qdd = states(arm, 20, 9)
    args = _arguments(arm, np.flatnonzero(base.independent.reshape(-1)), base.beta, q, qd, qdd)
    n, b = arm.n, base.rank
    out = np.empty((20, 3, n, b))
    tau_peak = np.zeros(n)
    _contributions_kernel(*args, True, out, tau_peak, np.zeros((b, 3, n)), np.zeros((b, n)))
    tau = rnea(arm, q, qd, qdd)
    scale = np.abs(tau).max()
    assert np.abs(out.sum(axis=(1, 3)) - tau).max() <= 1e-10 * scale
    np.testing.assert_allclose(tau_peak, np.abs(tau).max(axis=0), rtol=1e-10, atol=0)
    numpy = part_contributions_numpy(arm, base, q, qd, qdd).transpose(1, 0, 2, 3)
    assert np.abs(numpy - out).max() <= 1e-12 * np.abs(out).max()
