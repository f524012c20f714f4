"""The sampled pre-screen of the region model (:mod:`gd_analyze.certify.screen`).

Oracles: the sampled magnitudes of the pairs (each a lower bound of its enclosure on any box
holding the position), the certified region model's dropped pairs, and the quick operation
counts of the programs.
"""

import numpy as np
import pytest

from gd_analyze import load_robot
from gd_analyze.certify.screen import MIN_SAVING, screen_region
from gd_analyze.dynamics.base_parameters import base_parameters
from gd_analyze.simplify.deploy import robot_region
from gd_analyze.simplify.region_memo import region_values


def _inputs(name):
    robot = load_robot(name)
    base = base_parameters(robot)
    region, _ = robot_region(robot)
    return robot, base, region, region_values(robot, base, region)


def test_the_two_link_arm_has_nothing_to_save():
    """Nothing can be dropped that changes the two-link arm's count: the screen skips, and
    says so with its numbers."""
    robot, base, region, values = _inputs("two-link")
    found = screen_region(robot, base, region, values, 0.01)
    assert found.skip and found.saving == 0.0
    assert found.best_operations == found.exact_operations > 0
    said = found.to_dict()
    assert said["skipped"] and said["possible_saving"] == 0.0 and said["threshold"] == MIN_SAVING
    assert "below the threshold of 2 %" in said["statement"]


def test_the_puma_region_model_saves_and_is_searched():
    """The PUMA 560 (its region model counts 308 operations against the exact 320): the
    pre-screen finds more than the threshold to save; its s_i is the region samples' own."""
    robot, base, region, values = _inputs("puma560")
    found = screen_region(robot, base, region, values, 0.01)
    assert not found.skip and found.saving >= MIN_SAVING
    np.testing.assert_array_equal(found.scale, values[2])
    assert "searched" in found.text()
    with pytest.raises(ValueError):
        screen_region(robot, base, region, values, float("nan"))


@pytest.mark.slow
def test_every_set_the_proof_drops_passes_the_sampled_constraint():
    """The screen is optimistic: the pairs the certified region model drops satisfy the
    sampled constraint (at each sampled position, the sum of their magnitudes is within
    EPS s_i), so the screen's search may drop them too; its s_i is the certification's."""
    from gd_analyze.certify.certify import pair_magnitudes_at
    from gd_analyze.simplify.deploy import region_model

    robot, base, region, values = _inputs("puma560")
    for eps in (0.01, 0.05):
        rec, _ = region_model(robot, base, region, eps)
        found = screen_region(robot, base, region, values, eps)
        np.testing.assert_array_equal(found.scale, rec.scale)
        M = pair_magnitudes_at(values[1], np.asarray(base.beta, float), region.qd_max,
                               region.qdd_max)                            # (B, b, 3, n)
        total = np.einsum("xbpn,bp->xn", M, np.asarray(rec.dropped, float))
        assert rec.dropped.any()
        assert np.all(total <= eps * rec.scale * (1 + 1e-9))
        assert found.best_operations <= found.exact_operations


def test_the_proved_screen_counts_the_searched_pairs_programs():
    """The screen of pairs found under the proved bounds: its counts are those of the
    programs without common-subexpression elimination; the PUMA 560's region model (308 of
    320) saves more than the threshold and is built, dropping nothing saves nothing and is
    skipped; both say which screen they are."""
    from gd_analyze.certify.screen import proved_screen
    from gd_analyze.simplify.deploy import region_model
    from gd_analyze.symbolic.pruning import part_values
    from gd_analyze.symbolic.recursive import parts_program

    robot, base, region, values = _inputs("puma560")
    rec, _ = region_model(robot, base, region, 0.01)

    def quick(dropped):
        c = parts_program(robot, part_values(base, dropped), cse=False, search=False).cost()
        return c["multiplications"] + c["additions"]
    rel = np.zeros(rec.dropped.shape)
    found = proved_screen(robot, base, rec.dropped, 0.01, rec.scale, values[3], rel)
    assert found.proved and not found.skip and found.saving >= MIN_SAVING
    assert found.exact_operations == quick(np.zeros(rec.dropped.shape, bool))
    assert found.best_operations == quick(rec.dropped) < found.exact_operations
    assert "proved over the region" in found.text() and found.text().endswith(": built")
    none = proved_screen(robot, base, np.zeros(rec.dropped.shape, bool), 0.01, rec.scale,
                         values[3], rel)
    said = none.to_dict()
    assert none.skip and none.saving == 0.0 and said["proved"] and said["skipped"]
    assert "not built" in said["statement"] and "threshold of 2 %" in said["statement"]
    assert not screen_region(robot, base, region, values, 0.01).to_dict()["proved"]
