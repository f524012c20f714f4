"""The explicit terms' self-check (symbolic/explicit_check.py).

Oracles: Pinocchio's half-models (D_tran, D_rot, h_tran, h_rot) and generalized gravity, the
chapter's two-link closed forms; a tampered model (another arm's terms, one coefficient
scaled by a known factor) must be found, and by the factor it was scaled by."""

import dataclasses
from functools import cache

import chapter_two_link
import numpy as np
import pytest
from conftest import random_states

from gd_analyze.dynamics.pinocchio import reference_terms, relative_error
from gd_analyze.model.robot_spec import robot_from_dict
from gd_analyze.model.robots import load_robot
from gd_analyze.symbolic.explicit import derive, model_terms
from gd_analyze.symbolic.explicit_check import _check_states, term_values, terms_disagreement

TOL = 1e-10
M1, M2, L, G = 1.2, 0.8, 0.6, 9.81


@cache
def arm(name):
    if name in ("chapter", "offsets"):
        spec = chapter_two_link.spec(M1, M2, L, G)
        if name == "offsets":
            spec["link"][0]["offset_deg"], spec["link"][1]["offset_deg"] = 25.0, -70.0
        robot = robot_from_dict(spec)
    else:
        robot = load_robot(name)
    return robot, model_terms(derive(robot))


def _values(robot, terms, q, qd):
    # the explicit model's terms are in q (the offsets are inside them)
    return term_values(terms, q, qd, robot.prismatic)


@pytest.mark.parametrize("name", ["puma560", "stanford", "offsets"])
def test_term_values_match_pinocchios_split(name):
    robot, terms = arm(name)
    q, qd, _ = random_states(robot, 30, 41)
    q[:, robot.prismatic] *= 0.2                                 # lengths [m]
    got = _values(robot, terms, q, qd)
    ref = reference_terms(robot, q, qd)
    for g, want in zip(got, (ref.D_tran, ref.D_rot, ref.h_tran, ref.h_rot, ref.c)):
        assert relative_error(g, want) < TOL
    np.testing.assert_array_equal(got[0], np.swapaxes(got[0], 1, 2))     # mirrored


def test_term_values_give_the_chapters_closed_forms():
    robot, terms = arm("chapter")
    rng = np.random.default_rng(42)
    q, qd = rng.uniform(-np.pi, np.pi, (40, 2)), rng.uniform(-3, 3, (40, 2))
    for got, want in zip(term_values(terms, q, qd), chapter_two_link.terms(q, qd, M1, M2, L, G)):
        assert np.abs(got - want).max() <= 1e-12 * max(np.abs(want).max(), 1.0)


def test_own_terms_agree_and_tampered_terms_do_not():
    robot, terms = arm("puma560")
    assert terms_disagreement(robot, terms) < 1e-12
    # the constant term of D_11 scaled by 1 + f: D_11 grows by f C at every state, so the
    # disagreement is f C / min D_11 over the check's states (D_11 from Pinocchio's crba)
    big = int(np.flatnonzero((terms.kind == "D") & (terms.i == 0) & (terms.j == 0)
                             & (terms.part == "tran") & ~terms.K.any(axis=1))[0])
    q_check, qd_check = _check_states(robot)
    D11 = reference_terms(robot, q_check, qd_check).D[:, 0, 0]
    for f in (1e-3, 0.2):
        C = terms.C.copy()
        C[big] *= 1 + f
        bad = terms_disagreement(robot, dataclasses.replace(terms, C=C))
        assert bad == pytest.approx(f * terms.C[big] / D11.min(), rel=1e-8)
    # a heavier arm: the same terms no longer describe it
    heavier = dataclasses.replace(robot, mass=robot.mass * 1.1)
    assert terms_disagreement(heavier, terms) > 1e-3


def test_terms_that_cannot_be_the_robots_are_infinitely_far():
    robot, terms = arm("puma560")
    two, two_terms = arm("chapter")
    assert terms_disagreement(two, terms) == float("inf")                 # 6 columns, n = 2
    assert terms_disagreement(robot, two_terms) == float("inf")
    i = terms.i.copy()
    i[0] = robot.n                                                          # index out of range
    assert terms_disagreement(robot, dataclasses.replace(terms, i=i)) == float("inf")
    C = terms.C.copy()
    C[3] = np.nan
    assert terms_disagreement(robot, dataclasses.replace(terms, C=C)) == float("inf")
    kind = terms.kind.copy()
    kind[0] = "x"
    assert terms_disagreement(robot, dataclasses.replace(terms, kind=kind)) == float("inf")


def test_term_values_reject_rows_that_do_not_fit():
    _, terms = arm("chapter")
    q = np.zeros((1, 2))
    part = terms.part.copy()
    part[terms.kind == "c"] = "tran"
    with pytest.raises(ValueError, match="kind and part"):
        term_values(dataclasses.replace(terms, part=part), q, q)
    j = terms.j.copy()
    j[terms.kind == "D"] = 2
    with pytest.raises(IndexError, match=r"outside 0 \.\. 1"):
        term_values(dataclasses.replace(terms, j=j), q, q)


def _variant(name):
    """A one-joint arm with gravity along its axis (c is round-off in the engine, exact 0 in
    the terms), or the two-link arm with a massless second link (its h is round-off)."""
    spec = load_robot("two-link").to_dict()
    if name == "one joint":
        spec.update(link=spec["link"][:1], gravity=[0.0, 0.0, -9.81])
    else:
        spec["link"][1].update(mass=0.0)
    return robot_from_dict(spec)


@pytest.mark.parametrize("name", ["one joint", "massless link"])
def test_own_terms_of_arms_without_some_torque_pass_the_self_check(name):
    """Every run of such an arm warned that its own cache entry fails the check;
    the engine's round-off of a zero quantity is measured against the arm's torque."""
    robot = _variant(name)
    terms = model_terms(derive(robot))
    assert terms_disagreement(robot, terms) <= TOL
    # a tampered coefficient is still found, by its factor
    c = np.flatnonzero((terms.kind == "D") & (terms.C != 0))[0]
    tampered = dataclasses.replace(terms, C=np.where(np.arange(terms.C.size) == c,
                                                     1.5 * terms.C, terms.C))
    assert terms_disagreement(robot, tampered) > 1e-3


def test_an_arm_with_a_small_gravity_torque_reads_its_own_cache_entry(cache):
    """The SO-101's first axis is tilted from the vertical by its URDF's rounded angles: its
    gravity torque is 1e-6 of the arm's, and the engine's round-off of the arm's torques
    (1e-15) was measured against it: 1e-9, so every command warned that the entry it had
    just written fails its self-check, and derived the model again. Oracle: Pinocchio's
    generalized gravity gives that first torque; the terms derived for the arm pass, and read
    back from the cache without a warning; one scaled coefficient is still found."""
    import warnings

    from robot_files import erd_path

    from gd_analyze.cache import CacheWarning
    from gd_analyze.store.explicit_cache import SELF_CHECK_TOLERANCE, explicit_terms

    robot = load_robot(erd_path("so_arm_description/urdf/so101.urdf"))
    c = reference_terms(robot, *_check_states(robot)).c
    assert 0 < np.abs(c[:, 0]).max() < 1e-5 * np.abs(c).max()
    terms, _ = explicit_terms(robot)
    assert terms_disagreement(robot, terms) <= SELF_CHECK_TOLERANCE
    with warnings.catch_warnings():
        warnings.simplefilter("error", CacheWarning)
        again, seconds = explicit_terms(robot)
    assert seconds == 0.0 and np.array_equal(again.C, terms.C)
    big = int(np.flatnonzero(terms.kind == "D")[0])
    tampered = dataclasses.replace(terms, C=np.where(np.arange(terms.C.size) == big,
                                                     1.5 * terms.C, terms.C))
    assert terms_disagreement(robot, tampered) > 1e-3
