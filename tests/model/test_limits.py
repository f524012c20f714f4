"""The sane magnitudes (model/limits.py): the search for the first value beyond a limit,
the finiteness check, and the claim that inputs at the limits keep the G-D terms finite and
correct (against Pinocchio)."""

import numpy as np
import pytest
from chapter_two_link import spec as two_link_spec
from numpy_engines import gd_terms_numpy

from gd_analyze.dynamics.pinocchio import reference_terms, relative_error
from gd_analyze.errors import InputError
from gd_analyze.model.limits import LIMITS, check_finite, first_beyond
from gd_analyze.model.robot_spec import robot_from_dict


@pytest.mark.parametrize("shape", [(7,), (5, 4), (3, 2, 6)])
def test_first_beyond_is_the_first_offender_in_c_order(shape):
    rng = np.random.default_rng(len(shape))
    values = rng.uniform(-1.0, 1.0, shape)
    assert first_beyond(values, 1.0) is None
    flat = values.reshape(-1)
    picks = sorted(rng.choice(flat.size, 3, replace=False))
    for pick, bad in zip(picks, (-1.5, np.nan, np.inf)):
        flat[pick] = bad
    want = tuple(int(i) for i in np.unravel_index(picks[0], shape))
    assert first_beyond(values, 1.0) == want
    flat[picks[0]] = 0.0
    assert first_beyond(values, 1.0) == tuple(int(i) for i in np.unravel_index(picks[1], shape))


def test_first_beyond_accepts_the_limit_itself_and_catches_every_non_finite():
    assert first_beyond([2.5, -2.5], 2.5) is None
    assert first_beyond([2.5, -2.5000001], 2.5) == (1,)
    for bad in (np.nan, np.inf, -np.inf):
        assert first_beyond([0.0, bad], 1e300) == (1,)
    assert first_beyond([0.0, np.nan], np.inf) == (1,)
    for bad in (np.inf, -np.inf):           # not finite, so beyond even an infinite limit
        assert first_beyond([0.0, bad], np.inf) == (1,)
        assert first_beyond([[0.0, 1.0], [bad, 0.0]], np.inf) == (1, 0)
    assert first_beyond(np.zeros((0, 3)), 1.0) is None


def test_check_finite_passes_finite_arrays_unchanged():
    arr = np.arange(6.0).reshape(2, 3)
    assert check_finite("D", arr) is arr
    ints = np.arange(4)
    assert check_finite("n", ints) is ints


def test_check_finite_names_the_array_and_the_set_point():
    arr = np.ones((5, 2))
    arr[3, 1] = np.nan
    with pytest.raises(InputError) as err:
        check_finite("h_tran", arr, what="computed")
    text = str(err.value)
    assert "computed h_tran" in text and "set point 3" in text and "\n" not in text


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_check_finite_rejects_every_non_finite_value(bad):
    for arr in (np.array([1.0, bad]), np.array([[1.0, 2.0], [bad, 0.0]])):
        with pytest.raises(InputError, match="the computed D is not finite"):
            check_finite("D", arr)


def test_inputs_at_the_limits_keep_the_terms_finite_and_right():
    """The module's claim: every input at its limit gives torques far from overflow. Two rods
    of the largest mass and length, at the largest speed, against Pinocchio."""
    m, l, inertia = LIMITS["mass"], LIMITS["length"], LIMITS["inertia"]
    spec = two_link_spec(m1=m, m2=m, l=l, g=LIMITS["gravity"])
    for link in spec["link"]:
        link["inertia"] = [inertia] * 3
    robot = robot_from_dict(spec)
    q = np.array([[0.3, -1.2], [LIMITS["q"], -LIMITS["q"]]])
    qd = np.full((2, 2), LIMITS["qd"])
    terms = gd_terms_numpy(robot, q, qd)
    for name in ("D_tran", "D_rot", "h_tran", "h_rot", "c"):
        check_finite(name, getattr(terms, name))
    tau = terms.tau(np.full((2, 2), LIMITS["qdd"]))
    assert np.isfinite(tau).all() and np.abs(tau).max() < 1e30
    ref = reference_terms(robot, q, qd)
    assert relative_error(terms.D, ref.D) < 1e-10
    assert relative_error(terms.h, ref.h) < 1e-10


def test_the_default_acceleration_limits_name_their_joints_in_number():
    """Oracle: the joints left without an acceleration limit (NaN) in the arm given; one joint
    is "joint 2", more are "joints 1, 3" (a one-joint arm's plan read "for joints 1")."""
    import dataclasses

    from gd_analyze import load_robot
    from gd_analyze.model.limits import acceleration_limits

    puma = load_robot("puma560")
    for missing, said in (([1], "for joint 2 ("), ([0, 2], "for joints 1, 3 (")):
        qdd = np.ones(puma.n)
        qdd[missing] = np.nan
        limits, source = acceleration_limits(dataclasses.replace(puma, qdd_max=qdd))
        assert said in source and np.isfinite(limits).all(), source
