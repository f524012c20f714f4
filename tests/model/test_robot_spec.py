"""The robot-file layout (model/robot_spec.py): the three conventions build the arm they
describe, and every mistake is one error naming the key.

Oracles: the chapter's two-link closed forms (Sec. 3.2.6) for an arm written by hand in the
standard DH, modified DH and chain conventions; a prismatic joint's closed form (D = m,
c = m g); Pinocchio's crba for a random chain; hashlib for the specification's digest."""

import copy
import hashlib
import json
import math
import warnings

import chapter_two_link
import numpy as np
import pytest
from numpy_engines import gd_terms_numpy

from gd_analyze.errors import InputError, InputWarning
from gd_analyze.model.robot_spec import robot_from_chain, robot_from_dict

M1, M2, L, G = 1.7, 0.6, 0.8, 9.81
TOL = 1e-12


def _states(n=25, seed=1):
    rng = np.random.default_rng(seed)
    return rng.uniform(-np.pi, np.pi, (n, 2)), rng.uniform(-3, 3, (n, 2))


def _check_chapter(robot):
    q, qd = _states()
    terms = gd_terms_numpy(robot, q, qd)
    want = chapter_two_link.terms(q, qd, M1, M2, L, G)
    for name, w in zip(("D_tran", "D_rot", "h_tran", "h_rot", "c"), want):
        got = getattr(terms, name)
        scale = max(np.abs(w).max(), 1.0)
        assert np.abs(got - w).max() <= TOL * scale, name


def _modified_spec():
    """Craig's modified DH: link i's row has alpha_{i-1}, a_{i-1}, d_i, theta_i; frame i sits at
    joint i, so the rod's centre of mass is at (+l/2, 0, 0)."""
    spec = chapter_two_link.spec(M1, M2, L, G)
    spec["convention"] = "modified"
    for i, link in enumerate(spec["link"]):
        link["a"] = 0.0 if i == 0 else L
        link["com"] = [L / 2, 0.0, 0.0]
    return spec


def _chain_spec():
    """General placements: joint 1 at the base origin, joint 2 at (l, 0, 0) of body frame 1."""
    spec = chapter_two_link.spec(M1, M2, L, G)
    spec["convention"] = "chain"
    for i, link in enumerate(spec["link"]):
        for key in ("d", "a", "alpha_deg", "q_limits_deg", "qd_max_deg", "qdd_max_deg"):
            del link[key]
        link.update(rotation=np.eye(3).tolist(), translation=[0.0 if i == 0 else L, 0.0, 0.0],
                    com=[L / 2, 0.0, 0.0], q_limits=[-math.inf, math.inf], qd_max=3.0)
    return spec


@pytest.mark.parametrize("make", [lambda: chapter_two_link.spec(M1, M2, L, G), _modified_spec,
                                  _chain_spec], ids=["standard", "modified", "chain"])
def test_each_convention_builds_the_chapters_two_link_arm(make):
    robot = robot_from_dict(make(), source="arm.toml")
    assert robot.n == 2 and robot.source == "arm.toml"
    _check_chapter(robot)


def test_chain_route_builds_the_same_arm():
    spec = _chain_spec()
    joints = [{"type": "revolute", "rotation": link["rotation"],
               "translation": link["translation"], "mass": link["mass"], "com": link["com"],
               "inertia": np.diag(link["inertia"]), "q_min": -np.inf, "q_max": np.inf,
               "qd_max": 3.0, "qdd_max": None} for link in spec["link"]]
    robot = robot_from_chain("rods", joints, [0.0, -G, 0.0], source="rods.urdf", tip_link="t")
    assert robot.convention == "chain" and dict(robot.metadata) == {"tip_link": "t"}
    _check_chapter(robot)


@pytest.mark.parametrize("source, name", [("arm.urdf", "<robot name>"),
                                          ("pinocchio.Model", "key model.name")])
def test_a_urdfs_robot_name_with_a_line_break_is_named_as_its_attribute(source, name):
    """A URDF's robot name with a newline was refused as "key name", the wording of a TOML
    key: the URDF has a <robot name> attribute, a Pinocchio model a ``name``."""
    spec = _chain_spec()
    joints = [{"type": "revolute", "rotation": link["rotation"],
               "translation": link["translation"], "mass": link["mass"], "com": link["com"],
               "inertia": np.diag(link["inertia"])} for link in spec["link"]]
    with pytest.raises(InputError) as err:
        robot_from_chain("ur\n5", joints, [0.0, -G, 0.0], source=source,
                         urdf_joints=["j1", "j2"])
    assert str(err.value) == (f"{source}: {name}: expected at most 200 printable characters "
                              "(no control characters such as NUL or newline)")


def test_prismatic_joint_closed_form():
    """A vertical slider (alpha = 0, z up, gravity -z) on a turntable: the slide's D entry
    is its mass, its gravity force m g, and the units are SI (limits in m, m/s)."""
    spec = {"name": "lift", "gravity": [0.0, 0.0, -G], "link": [
        {"joint": "prismatic", "a": 0.0, "alpha_deg": 0.0, "mass": 2.5, "com": [0, 0, 0.1],
         "inertia": [0.01, 0.01, 0.02], "q_limits": [0.0, 0.5], "qd_max": 0.3,
         "qdd_max": 1.0}]}
    robot = robot_from_dict(spec)
    assert robot.joint_types == ("prismatic",)
    assert (robot.q_min[0], robot.q_max[0], robot.qd_max[0]) == (0.0, 0.5, 0.3)
    terms = gd_terms_numpy(robot, np.array([[0.2]]), np.array([[0.7]]))
    assert terms.D[0, 0, 0] == pytest.approx(2.5, rel=1e-14)
    assert terms.c[0, 0] == pytest.approx(2.5 * G, rel=1e-14)
    assert terms.h[0, 0] == pytest.approx(0.0, abs=1e-14)


def test_degrees_are_read_as_degrees_and_radians_look_alikes_warn():
    spec = chapter_two_link.spec(M1, M2, L, G)
    spec["link"][1]["alpha_deg"] = 90.0
    spec["link"][0]["offset_deg"] = 30.0
    spec["link"][0]["q_limits_deg"] = [-90.0, 45.0]
    robot = robot_from_dict(spec)
    assert robot.alpha[1] == pytest.approx(math.pi / 2, abs=1e-15)
    assert robot.offset[0] == pytest.approx(math.pi / 6, abs=1e-15)
    assert (robot.q_min[0], robot.q_max[0]) == pytest.approx((-math.pi / 2, math.pi / 4))
    spec["link"][1]["alpha_deg"] = 1.5708
    with pytest.warns(InputWarning, match=r"link\[2\].alpha_deg: 1.5708 looks like radians"):
        robot_from_dict(spec)


def test_six_inertia_numbers_are_the_full_tensor():
    spec = chapter_two_link.spec(M1, M2, L, G)
    spec["link"][0]["inertia"] = [0.2, 0.3, 0.4, 0.01, -0.02, 0.03]
    I = robot_from_dict(spec).inertia[0]
    np.testing.assert_array_equal(I, [[0.2, 0.01, -0.02], [0.01, 0.3, 0.03],
                                      [-0.02, 0.03, 0.4]])
    spec["link"][0]["inertia"] = I.tolist()                 # the 3x3 form, same tensor
    np.testing.assert_array_equal(robot_from_dict(spec).inertia[0], I)


def test_digest_is_that_of_the_canonical_json():
    spec = chapter_two_link.spec(M1, M2, L, G)
    want = hashlib.sha256(json.dumps(spec, sort_keys=True).encode()).hexdigest()
    assert robot_from_dict(spec).sha256 == want
    reordered = dict(reversed(list(spec.items())))
    assert robot_from_dict(reordered).sha256 == want
    other = copy.deepcopy(spec)
    other["link"][0]["mass"] += 1e-9
    assert robot_from_dict(other).sha256 != want
    assert robot_from_dict(spec, sha256="f" * 64).sha256 == "f" * 64


def _set(path, value):
    def mutate(spec):
        *keys, last = path
        target = spec
        for key in keys:
            target = target[key]
        if value is KeyError:
            del target[last]
        else:
            target[last] = value
    return mutate


@pytest.mark.parametrize("mutate, column, words", [
    (_set(("name",), "two\nlines"), "name", "printable"),
    (_set(("name",), KeyError), "name", "missing robot name"),
    (_set(("gravity",), [0.0, 9.81]), "gravity", "list of 3 numbers"),
    (_set(("gravity",), [0.0, 2e3, 0.0]), "gravity", "beyond the supported magnitude"),
    (_set(("convention",), "craig"), "convention", "convention must be"),
    (_set(("link",), []), "link", "no [[link]] tables"),
    (_set(("link", 0, "joint"), "helical"), "link[1].joint", "revolute' or 'prismatic"),
    (_set(("link", 1, "mass"), True), "link[2].mass", "expected a number"),
    (_set(("link", 1, "mass"), float("nan")), "link[2].mass", "finite number"),
    (_set(("link", 1, "mass"), -0.5), "link[2].mass", "negative mass"),
    (_set(("link", 0, "a"), 5e3), "link[1].a", "beyond the supported magnitude"),
    (_set(("link", 0, "inertia"), [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]), "link[1].inertia",
     "not symmetric"),
    (_set(("link", 0, "inertia"), [1.0, 1.0, -0.1]), "link[1].inertia",
     "not positive semi-definite"),
    (_set(("link", 1, "qd_max_deg"), 0.0), "link[2].qd_max_deg", "must be positive"),
    (_set(("link", 1, "qdd_max_deg"), float("inf")), "link[2].qdd_max_deg", "finite"),
    (_set(("link", 1, "q_limits_deg"), [1.0]), "link[2].q_limits_deg", "list of 2 numbers"),
    (_set(("link", 1, "offset"), 0.1), "link[2].offset", "offset_deg"),
    (_set(("link", 1, "d"), KeyError), "link[2].d", "missing key"),
])
def test_every_mistake_is_one_line_naming_the_key(mutate, column, words):
    spec = chapter_two_link.spec(M1, M2, L, G)
    mutate(spec)
    with pytest.raises(InputError) as err:
        robot_from_dict(spec, source="arm.toml")
    assert err.value.column == column
    text = str(err.value)
    assert text.startswith(f"arm.toml: key {column}: ") and words in text and "\n" not in text


def test_chain_placements_must_be_proper_rotations():
    spec = _chain_spec()
    spec["link"][1]["rotation"] = np.diag([1.0, 1.0, -1.0]).tolist()     # a reflection
    with pytest.raises(InputError, match="not a rotation matrix") as err:
        robot_from_dict(spec)
    assert err.value.column == "link[2].rotation"
    spec["link"][1]["rotation"] = (2 * np.eye(3)).tolist()
    with pytest.raises(InputError, match="not a rotation matrix"):
        robot_from_dict(spec)


def test_unknown_top_level_keys_warn_and_are_ignored():
    spec = chapter_two_link.spec(M1, M2, L, G)
    spec["colour"] = "red"
    with pytest.warns(InputWarning, match="unknown key 'colour' ignored"):
        robot = robot_from_dict(spec)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _check_chapter(robot)
