"""The report's sentences (gd_analyze.reports.main_text): the conclusion's cost clause."""

import numpy as np

from gd_analyze.reports.main_text import conclusion

ARGS = (["D11", "h1"], ["translational", "rotational"], np.zeros(2, bool), ["tran", "rot"],
        np.array([0.004]), np.array([0.02]), np.array([5.0]))


def test_cost_against_newton_euler_both_ways_and_without():
    cheaper = conclusion(*ARGS, cost=(348, 260, 1212))
    assert "costs 608 operations per set point" in cheaper
    assert "against Newton-Euler's 1,212" in cheaper and "use Newton-Euler" not in cheaper
    dearer = conclusion(*ARGS, cost=(61149, 93750, 1452))
    assert "costs 154,899 operations" in dearer
    assert "more than Newton-Euler's 1,452: for speed, use Newton-Euler" in dearer
    unknown = conclusion(*ARGS, cost=(10, 5, None))
    assert "costs 15 operations" in unknown and "Newton-Euler" not in unknown
    assert "costs" not in conclusion(*ARGS)
    for text in (cheaper, dearer, unknown):
        assert text.count(". ") == 2 and text.endswith(".")      # still three sentences
