import math
from importlib import resources

import numpy as np
import pytest

from gd_analyze import InputError, load_robot
from gd_analyze.model.robot_spec import robot_from_dict
from gd_analyze.model.robots import builtin_robots


def test_builtin_names():
    assert {"puma560", "stanford", "two-link"} <= set(builtin_robots())


def test_puma560_parameters_match_the_issue_table(puma):
    assert puma.n == 6
    np.testing.assert_allclose(puma.d, [0, 0, 0.15005, 0.4318, 0, 0])
    np.testing.assert_allclose(puma.a, [0, 0.4318, 0.0203, 0, 0, 0])
    np.testing.assert_allclose(puma.alpha, np.pi / 2 * np.array([1, 0, -1, 1, -1, 0]))
    np.testing.assert_allclose(puma.mass, [0, 17.4, 4.8, 0.82, 0.34, 0.09])
    np.testing.assert_allclose(puma.com[1], [-0.3638, 0.006, 0.2275])
    np.testing.assert_allclose(np.diagonal(puma.inertia, axis1=1, axis2=2)[2], [0.066, 0.086, 0.0125])
    np.testing.assert_allclose(np.degrees(puma.q_min), [-160, -45, -225, -110, -100, -266])
    np.testing.assert_allclose(np.degrees(puma.qd_max), [100, 95, 100, 150, 130, 110])
    np.testing.assert_allclose(np.degrees(puma.qdd_max), [45, 40, 75, 70, 90, 80])
    np.testing.assert_allclose(puma.gravity, [0, 0, -9.8062])
    assert len(puma.sha256) == 64


def test_two_link_is_the_chapter_arm(two_link):
    l, m = 1.0, 1.0
    np.testing.assert_allclose(two_link.a, [l, l])
    np.testing.assert_allclose(two_link.com, [[-l / 2, 0, 0]] * 2)
    np.testing.assert_allclose(two_link.inertia[0], np.diag([0, m * l**2 / 12, m * l**2 / 12]))
    np.testing.assert_allclose(two_link.gravity, [0, -9.8062, 0])


def test_arrays_are_read_only(puma):
    with pytest.raises(ValueError):
        puma.mass[0] = 1.0


def test_round_trip_through_dict(puma):
    again = robot_from_dict(puma.to_dict())
    for name in ("d", "a", "alpha", "offset", "mass", "com", "inertia", "q_min", "qd_max"):
        np.testing.assert_allclose(getattr(again, name), getattr(puma, name), atol=1e-15)


def test_load_from_path(tmp_path):
    text = resources.files("gd_analyze").joinpath("data", "two-link.toml").read_text()
    path = tmp_path / "arm.toml"
    path.write_text(text)
    robot = load_robot(str(path))
    assert robot.n == 2 and robot.source == str(path)


@pytest.mark.parametrize("mutate, column", [
    (lambda s: s["link"][0].pop("mass"), "link[1].mass"),
    (lambda s: s["link"][1].update(mass=-1.0), "link[2].mass"),
    (lambda s: s["link"][0].update(inertia=[1.0, -1.0, 0.5]), "link[1].inertia"),
    (lambda s: s["link"][0].update(com=[0.0, 1.0]), "link[1].com"),
    (lambda s: s["link"][0].update(d="x"), "link[1].d"),
    (lambda s: s["link"][0].update(q_limits_deg=[10.0, -10.0]), "link[1].q_limits_deg"),
    (lambda s: s["link"][0].update(colour=1), "link[1].colour"),
    (lambda s: s.pop("gravity"), "gravity"),
])
def test_validation_names_the_key(two_link, mutate, column):
    spec = two_link.to_dict()
    mutate(spec)
    with pytest.raises(InputError) as err:
        robot_from_dict(spec, source="arm.toml")
    assert err.value.column == column
    assert str(err.value).startswith("arm.toml: key " + column)


def test_unknown_robot_and_bad_toml(tmp_path):
    with pytest.raises(InputError, match="unknown robot"):
        load_robot("no-such-robot")
    bad = tmp_path / "bad.toml"
    bad.write_text("name = [")
    with pytest.raises(InputError, match="not a valid TOML"):
        load_robot(str(bad))


def test_full_inertia_tensor_with_products(two_link):
    spec = two_link.to_dict()
    spec["link"][0]["inertia"] = [0.2, 0.3, 0.4, 0.01, -0.02, 0.03]
    robot = robot_from_dict(spec)
    I = robot.inertia[0]
    np.testing.assert_allclose(I, I.T)
    assert math.isclose(I[0, 2], -0.02) and math.isclose(I[1, 2], 0.03)


def test_payload_matches_pinocchio_with_the_load_on_the_last_body(puma):
    """G-D terms of the robot with a merged payload against Pinocchio's model with the load
    appended as a second body on the last joint."""
    import pinocchio as pin
    from conftest import random_states

    from gd_analyze import gd_terms
    from gd_analyze.dynamics.pinocchio import pinocchio_model, relative_error
    from gd_analyze.model.robot import with_payload

    mass, com, inertia = 2.5, np.array([0.01, -0.02, 0.08]), np.array([0.004, 0.005, 0.002])
    loaded = with_payload(puma, mass, com, inertia)
    assert loaded.mass[-1] == pytest.approx(0.09 + 2.5)
    model = pinocchio_model(puma)
    last = model.njoints - 1
    # link n's frame in joint n's frame: Trans(0,0,d) Trans(a,0,0) Rot(x, alpha)
    c, s = np.cos(puma.alpha[-1]), np.sin(puma.alpha[-1])
    frame_n = pin.SE3(np.array([[1, 0, 0], [0, c, -s], [0, s, c]]),
                      np.array([puma.a[-1], 0.0, puma.d[-1]]))
    model.appendBodyToJoint(last, frame_n.act(pin.Inertia(mass, com, np.diag(inertia))),
                            pin.SE3.Identity())
    data = model.createData()
    q, qd, qdd = random_states(puma, 100, 41)
    ref = np.array([pin.rnea(model, data, a, b, cc) for a, b, cc in zip(q, qd, qdd)])
    tau = gd_terms(loaded, q, qd).tau(qdd)
    assert relative_error(tau, ref) < 1e-10
    # and the load matters: without it the torques differ
    assert relative_error(gd_terms(puma, q, qd).tau(qdd), ref) > 1e-3


def test_payload_validation(puma):
    from gd_analyze.model.robot import with_payload

    with pytest.raises(InputError, match="payload mass"):
        with_payload(puma, -1.0)
    with pytest.raises(InputError, match="inertia"):
        with_payload(puma, 1.0, inertia=[1.0, -2.0, 1.0])
    assert with_payload(puma, 0.0) is puma
