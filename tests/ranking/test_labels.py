"""The one label rule of the G-D elements: every module derives from it."""

import pytest

from gd_analyze.ranking.labels import (
    element_index,
    element_label,
    element_labels,
    parse_element_label,
)
from gd_analyze.simplify.budget import part_index


@pytest.mark.parametrize("n", range(1, 13))
def test_round_trip_and_distinct(n):
    labels = element_labels(n)
    assert len(labels) == len(set(labels)) == n * (n + 1) // 2 + n
    assert [parse_element_label(lab, n) for lab in labels] == element_index(n)


def test_labels_below_ten_joints_are_those_of_the_shipped_files():
    assert element_labels(6) == [f"D{i}{j}" for i in range(1, 7) for j in range(i, 7)] + \
        [f"h{i}" for i in range(1, 7)]


def test_two_digit_indices_are_separated_by_a_comma():
    labels = element_labels(12)
    assert element_label("D", 0, 9) == "D1,10" and element_label("D", 9, 11) == "D10,12"
    assert "D19" in labels and "D110" not in labels and "D1,10" in labels
    assert labels[-1] == "h12"


@pytest.mark.parametrize("text", ["D110", "D1,2", "D21", "h0", "D01", "h13", "D1,13", "x",
                                  "D", "h", "D1,", " D11", "D11 ", "h1.0", 11])
def test_parse_refuses_what_is_no_label_of_a_12_joint_robot(text):
    with pytest.raises(ValueError):
        parse_element_label(text, 12)


@pytest.mark.parametrize("n", [6, 10, 12])
def test_the_budget_parts_use_the_same_labels(n):
    """budget.part_index wrote "D110" for n >= 10 while the ranking wrote "D1,10"."""
    parts = part_index(n)
    assert [lab for lab, p, *_ in parts if p == "tran"] == element_labels(n)
    assert all(parse_element_label(lab, n) == (kd, i, None if kd == "h" else j)
               for lab, _, kd, i, j in parts)


def test_gain_units_are_generalized_force_over_the_joint_motion():
    """A PD law tau_i = Kp e_i + Kv de_i/dt: Kp is [tau_i]/[q_i], Kv is [tau_i] s/[q_i];
    a revolute joint's q is rad and tau N m, a prismatic one's m and N."""
    from gd_analyze.ranking.labels import joint_gain_units

    for prismatic, (force, motion) in ((False, ("N m", "rad")), (True, ("N", "m"))):
        kp, kv = joint_gain_units(prismatic)
        assert kp == f"{force} {motion}-1" and kv == f"{force} s {motion}-1"
