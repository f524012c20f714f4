"""A simplified model's torque error (simplify/torque_error.py): figures by hand, and the
accumulator chunk by chunk equal to one pass."""

import numpy as np

from gd_analyze.simplify.torque_error import TorqueErrorAccumulator, torque_error


def test_torque_error():
    tau = np.array([[1.0, -4.0], [-2.0, 0.0]])
    err = torque_error(tau + np.array([[0.1, 0.0], [-0.3, 0.0]]), tau)
    np.testing.assert_allclose(err["peak_abs_error"], [0.3, 0.0])
    np.testing.assert_allclose(err["rms_error"], [np.sqrt((0.01 + 0.09) / 2), 0.0])
    np.testing.assert_allclose(err["relative_peak_error"], [0.15, 0.0])


def test_chunks_add_up_to_one_pass():
    rng = np.random.default_rng(3)
    tau, noise = rng.normal(size=(2, 50, 3))
    acc = TorqueErrorAccumulator(3)
    for sl in (slice(0, 7), slice(7, 7), slice(7, 50)):
        acc.update(tau[sl] + 0.01 * noise[sl], tau[sl])
    one = torque_error(tau + 0.01 * noise, tau)
    for key, value in acc.result().items():
        np.testing.assert_allclose(value, one[key], rtol=1e-12)
