"""A region's certification and samples, once per process, kept where the caller says.

Oracles: :func:`gd_analyze.certify.certify.certify` called directly on the same samples (the
memo's certification has its bounds), and counts of the calls a :class:`Derivations` receives.
"""

import numpy as np

from gd_analyze import load_robot
from gd_analyze.certify.certify import certify
from gd_analyze.certify.region import joint_region
from gd_analyze.dynamics.base_parameters import base_parameters
from gd_analyze.simplify import region_memo
from gd_analyze.simplify.region_memo import (
    REGION_SAMPLES,
    Derivations,
    certified,
    fresh_certification,
    region_values,
)


def test_a_certification_is_made_once_per_process_and_told_to_the_store(monkeypatch):
    for memo in ("_CERTIFIED", "_SAMPLED", "_MAGNITUDES"):
        monkeypatch.setattr(region_memo, memo, {})
    robot = load_robot("two-link")
    base = base_parameters(robot)
    region = joint_region(robot, robot.qdd_max)
    made, asked = [], []

    def certification(*args, **kwargs):
        asked.append(kwargs)
        return fresh_certification(*args, **kwargs)
    derive = Derivations(certification=certification, made=lambda *a: made.append(a))
    pb = certified(robot, base, region, 0.0, derive)
    again = certified(robot, base, region, 0.0, derive)
    assert again is pb and len(asked) == 1 and len(made) == 1
    assert asked[0]["samples"] == REGION_SAMPLES and made[0][-1] is pb

    direct = certify(robot, base, region, samples=REGION_SAMPLES,
                     values=region_values(robot, base, region))
    np.testing.assert_array_equal(pb.bound, direct.bound)
    np.testing.assert_array_equal(region_values(robot, base, region)[0], pb.positions)
