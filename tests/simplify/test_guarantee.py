"""The guarantee of a simplified model: its statement and its file form."""
import numpy as np
import pytest

from gd_analyze.errors import InputError
from gd_analyze.simplify.guarantee import Guarantee


def _region(bound=(0.01, 0.0)):
    return Guarantee("region", 0.01, bound=np.array(bound), scale=np.array([2.0, 1.0]),
                     q_min=-np.ones(2), q_max=np.ones(2), qd_max=np.ones(2),
                     qdd_max=np.ones(2), scale_state=np.zeros((2, 6)),
                     sampled_error=np.array([0.004, 0.0]), method="interval")


def test_region_statement_says_proved_and_round_trips():
    g = _region()
    assert "every state of the region (proved" in g.statement()
    back = Guarantee.from_dict(g.to_dict(), 2, 0.01)
    assert back.kind == "region" and np.array_equal(back.bound, g.bound)
    assert np.array_equal(back.scale_state, g.scale_state)
    assert back.sampled_percent() == pytest.approx(0.2)


def test_trajectory_statement_gives_the_sampled_region_error():
    g = Guarantee("trajectory", 0.01, bound=np.zeros(2), scale=np.ones(2),
                  region_sampled_error=np.array([0.135, 0.02]))
    text = g.statement()
    assert text.startswith("within 1 % of s_i on this trajectory only")
    assert "13.5 %" in text
    missing = Guarantee("trajectory", 0.01, bound=np.zeros(2), scale=np.ones(2),
                        region_missing="joint 2 has no velocity limit",
                        scale_state=np.zeros((2, 6)))
    assert "joint 2 has no velocity limit" in missing.statement()
    assert Guarantee.from_dict(missing.to_dict(), 2, 0.01).region_sampled_error is None


def test_a_trajectory_bound_without_its_trajectorys_sha256_does_not_say_it_differs():
    """A model file whose guarantee.trajectory_sha256 was removed said of its own trajectory
    "it is not the trajectory the model was built on (SHA-256 differs)". Oracle: the file
    stores no SHA-256, so nothing was compared."""
    spec = Guarantee("trajectory", 0.01, bound=np.zeros(2), scale=np.ones(2),
                     trajectory_sha256="ab" * 32, scale_state=np.zeros((2, 6))).to_dict()
    spec.pop("trajectory_sha256")
    g = Guarantee.from_dict(spec, 2, 0.01)
    covered, why = g.covers(np.zeros((1, 2)), np.zeros((1, 2)), np.zeros((1, 2)), "cd" * 32)
    assert not covered and "differs" not in why and "stores no SHA-256" in why, why
    kept = Guarantee.from_dict({**spec, "trajectory_sha256": "ab" * 32}, 2, 0.01)
    assert kept.covers(np.zeros((1, 2)), np.zeros((1, 2)), np.zeros((1, 2)), "cd" * 32)[1]\
        .startswith("it is not the trajectory the model was built on (SHA-256 differs)")


def test_a_file_whose_bound_exceeds_its_promise_is_refused():
    spec = _region(bound=(0.03, 0.0)).to_dict()         # 0.03 > 0.01 x 2.0
    with pytest.raises(InputError, match="guarantee.bound"):
        Guarantee.from_dict(spec, 2, 0.01)
    spec = _region().to_dict()
    spec["scale_state"] = [[0.0] * 6]
    with pytest.raises(InputError, match="guarantee.scale_state"):
        Guarantee.from_dict(spec, 2, 0.01)
    with pytest.raises(ValueError):
        Guarantee("anywhere", 0.01, np.zeros(1), np.ones(1))


def test_covers_reports_the_true_extreme_not_the_first_set_point_outside():
    """A trajectory that first leaves the region at 3.217 and goes on to 6.283: the reason
    names 6.283."""
    import numpy as np

    from gd_analyze.simplify.guarantee import Guarantee

    g = Guarantee("region", 0.01, np.zeros(1), np.ones(1), q_min=np.array([-3.0]),
                  q_max=np.array([3.0]), qd_max=np.array([10.0]), qdd_max=np.array([10.0]),
                  scale_state=np.zeros((1, 3)))
    q = np.array([[0.0], [3.217], [6.283], [4.0]])
    covered, reason = g.covers(q, 0 * q, 0 * q)
    assert not covered and "reaches 6.283" in reason and "3.217" not in reason
    qd = np.array([[0.0], [-10.5], [-20.0], [11.0]])
    covered, reason = g.covers(0 * qd, qd, 0 * qd)
    assert not covered and "|qd| reaches 20 rad/s, 10 rad/s above its limit 10 rad/s" in reason
    # a prismatic joint in m: 6.283 m is 3.283 m beyond the 3 m limit
    assert g.covers(q, 0 * q, 0 * q, prismatic=[True])[1].endswith(
        "q reaches 6.283 m, 3.28 m above its limit 3 m")


def test_region_round_trips_and_a_region_that_disagrees_is_refused():
    """The region stored beside a region guarantee's limits must be those limits: a file
    whose region says otherwise (e.g. a wider velocity) is refused, naming the key."""
    import numpy as np
    import pytest

    from gd_analyze.certify.region import Region
    from gd_analyze.errors import InputError
    from gd_analyze.simplify.guarantee import Guarantee

    region = Region(np.array([-1.0, -np.pi]), np.array([1.0, np.pi]), np.array([2.0, 3.0]),
                    np.array([4.0, 6.0]), prismatic=np.array([False, False]),
                    qdd_assumed=np.array([True, True]), qdd_rule="2 s^-1 x qd max")
    g = Guarantee("region", 0.01, np.zeros(2), np.ones(2), q_min=region.q_min,
                  q_max=region.q_max, qd_max=region.qd_max, qdd_max=region.qdd_max,
                  scale_state=np.zeros((2, 6)), region=region)
    spec = g.to_dict()
    assert spec["region"]["q"] == [[-1.0, 1.0], "any angle (full turn)"]
    back = Guarantee.from_dict(spec, 2, 0.01)
    assert back.region.lines() == region.lines()
    # joint 2 turns freely: any angle is covered; joint 1 is not
    assert back.covers([[0.0, 7.0]], [[0.0, 0.0]], [[0.0, 0.0]])[0]
    assert not back.covers([[1.5, 0.0]], [[0.0, 0.0]], [[0.0, 0.0]])[0]
    spec["region"]["qd_max"] = [20.0, 3.0]
    with pytest.raises(InputError, match="guarantee.region"):
        Guarantee.from_dict(spec, 2, 0.01)
