"""How the simplified model is built, as one checked value."""

import math
import re

import numpy as np
import pytest

from gd_analyze.certify.region import RegionLimits
from gd_analyze.cli.parsing import analyze_parser
from gd_analyze.config import defaults
from gd_analyze.errors import InputError
from gd_analyze.simplify.options import EXPLICIT, FORMS, GUARANTEES, RULES, SimplifyOptions


def test_simplify_options_take_only_a_region_value():
    with pytest.raises(ValueError, match="RegionLimits"):
        SimplifyOptions(region={"qd_max": 1.0})
    with pytest.raises(ValueError, match="--qd-max"):
        RegionLimits(qd_max=(float("nan"),))


def test_defaults_are_the_configured_ones_and_each_choice_is_checked():
    o = SimplifyOptions()
    assert (o.tolerance, o.rule, o.torque_floor, o.explicit, o.form, o.guarantee) == (
        defaults["tolerance"], defaults["rule"], defaults["torque_floor"], defaults["explicit"],
        defaults["form"], defaults["guarantee"])
    for name, allowed in (("rule", RULES), ("explicit", EXPLICIT), ("form", FORMS),
                          ("guarantee", GUARANTEES)):
        for value in allowed:
            assert getattr(SimplifyOptions(**{name: value}), name) == value
        with pytest.raises(ValueError, match=f"{name} must be one of"):
            SimplifyOptions(**{name: "nonsense"})
    for bad in (-0.01, math.nan):
        with pytest.raises(ValueError, match=r"tolerance must be a number in \[0, 1000\]"):
            SimplifyOptions(tolerance=bad)
        with pytest.raises(ValueError, match=r"torque_floor must be a number in \[0, 1e\+30\]"):
            SimplifyOptions(torque_floor=bad)


@pytest.mark.parametrize("other", [{"form": "recursive"}, {"explicit": "never"}])
def test_the_chapter_rule_refuses_a_form_it_cannot_write(other):
    """The chapter rule's model is the explicit model's elements in their classes, so it can
    neither be written in recursive form nor built without the explicit model."""
    with pytest.raises(ValueError, match="rule 'chapter' takes no form"):
        SimplifyOptions(rule="chapter", **other)
    assert SimplifyOptions(rule="budget", **other).rule == "budget"
    assert SimplifyOptions(rule="chapter", form="explicit", explicit="always").form == "explicit"


@pytest.mark.parametrize("field, value", [("tolerance", "0.01"), ("torque_floor", None),
                                          ("tolerance", True), ("torque_floor", np.True_)])
def test_a_tolerance_or_floor_that_is_not_a_number_is_one_value_error(field, value):
    """SimplifyOptions(tolerance="0.01") raised TypeError ("'>=' not supported between
    instances of 'str' and 'float'")."""
    with pytest.raises(ValueError, match=rf"^{field} must be a number in \[0, "):
        SimplifyOptions(**{field: value})


@pytest.mark.parametrize("field, value, most", [("tolerance", 1e308, "1000"),
                                                ("torque_floor", 1e31, "1e+30")])
def test_a_tolerance_or_floor_beyond_the_command_lines_range_is_refused(field, value, most):
    """SimplifyOptions(tolerance=1e308) was accepted through the API while the command line
    refuses --tolerance above 1e3 (EPS x s_i overflowed to inf in the region search); the
    bound is the parser's own (gd_analyze.config.MAXIMA)."""
    with pytest.raises(ValueError, match=re.escape(f"{field} must be a number in [0, {most}], got")):
        SimplifyOptions(**{field: value})
    assert getattr(SimplifyOptions(**{field: float(most)}), field) == float(most)  # the bound
    option = "--" + field.replace("_", "-")
    with pytest.raises(InputError, match=f"argument {option}: {option} must be in"):
        analyze_parser().parse_intermixed_args(["puma560", "t.csv", option, str(value)])
