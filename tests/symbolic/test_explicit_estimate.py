"""The term-count estimate of the explicit model, against the real expansion."""

import pytest

from gd_analyze.model.robots import load_robot
from gd_analyze.symbolic.explicit import derive, model_terms
from gd_analyze.symbolic.explicit_estimate import (
    ESTIMATE_FACTOR,
    EXPENSIVE_TERMS,
    estimate_terms,
    is_expensive,
)


@pytest.mark.parametrize("name", ["two-link", "puma560", "stanford", "ur5"])
def test_estimate_within_the_stated_factor_of_the_real_count(name):
    robot = load_robot(name)
    real = len(model_terms(derive(robot)).kind)          # the expansion itself is the oracle
    estimate = estimate_terms(robot)
    assert isinstance(estimate, int)
    assert real / ESTIMATE_FACTOR <= estimate <= real * ESTIMATE_FACTOR, (real, estimate)
    assert not is_expensive(robot)


def test_the_panda_is_flagged_expensive_without_expanding():
    # its expansion has 418,774 terms (module docstring); the estimate must say so at once
    panda = load_robot("panda")
    assert estimate_terms(panda) > EXPENSIVE_TERMS * ESTIMATE_FACTOR
    assert is_expensive(panda)


def test_more_offsets_and_crossed_axes_never_shrink_the_estimate(puma):
    import dataclasses

    import numpy as np

    com = np.asarray(puma.com, float) + 0.01          # every centre of mass off its axes
    assert estimate_terms(dataclasses.replace(puma, com=com)) > estimate_terms(puma)
