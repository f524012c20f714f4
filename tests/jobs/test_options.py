"""The main job's settings as values: the user's region through the Python API."""

import numpy as np
import pytest

import gd_analyze as gd


def test_region_limits_pass_through_the_api_into_the_dataset():
    robot = gd.load_robot("two-link")
    t = np.linspace(0.0, 1.0, 21)
    q = np.column_stack([0.2 * np.sin(t), 0.1 * t])
    region = gd.RegionLimits(q_limits=((-0.5, 0.5), (-1.0, 1.0)), qd_max=(1.0,),
                             qdd_max=(2.0, 3.0))
    options = gd.AnalysisOptions(formulations=False, verify=False,
                                 simplify=gd.SimplifyOptions(region=region))
    ds = gd.analyze(robot, (t, q), options)
    np.testing.assert_array_equal(ds["region_q_min"].values, [-0.5, -1.0])
    np.testing.assert_array_equal(ds["region_q_max"].values, [0.5, 1.0])
    np.testing.assert_array_equal(ds["region_qd_max"].values, [1.0, 1.0])
    np.testing.assert_array_equal(ds["region_qdd_max"].values, [2.0, 3.0])
    assert ds["region_q_full_turn"].values.tolist() == [0, 0]
    assert ds["region_qdd_max_assumed"].values.tolist() == [0, 0]
    assert int(ds.attrs["region_covers_trajectory"]) == 1
    assert ds.attrs["region_summary"].splitlines()[0] == \
        "region: q [deg] 1 [-28.65, 28.65], 2 [-57.3, 57.3]"
    assert ds.attrs["simplified_guarantee_kind"] == "region"


@pytest.mark.parametrize("field, value, said", [
    ("dominance", "0.9", "dominance must be a number in (0.5, 1], got '0.9'"),
    ("dominance", None, "dominance must be a number in (0.5, 1], got None"),
    ("negligible", "x", "negligible must be a number in [0, 1), got 'x'"),
    ("negligible", float("nan"), "negligible must be a number in [0, 1), got nan"),
    ("dominance", True, "dominance must be a number in (0.5, 1], got True"),
])
def test_a_threshold_that_is_not_a_number_is_one_value_error(field, value, said):
    """AnalysisOptions(dominance="0.9") raised TypeError ("'<' not supported between
    instances of 'float' and 'str'"); a number's range check is as before."""
    with pytest.raises(ValueError) as e:
        gd.AnalysisOptions(**{field: value})
    assert str(e.value) == said
    assert gd.AnalysisOptions(dominance=np.float64(0.75), negligible=0).dominance == 0.75


@pytest.mark.parametrize("field, value, said", [
    ("verify", "no", "verify: True or False, not a str"),
    ("formulations", 1, "formulations: True or False, not a int"),
    ("simplify", 3, "simplify: a SimplifyOptions or None, not a int"),
    ("simplify", {"tolerance": 0.1}, "simplify: a SimplifyOptions or None, not a dict"),
])
def test_a_flag_or_nested_options_of_another_type_is_one_value_error(field, value, said):
    """AnalysisOptions(verify="no") was accepted and read as True (a non-empty str), and
    simplify=3 was kept, to fail deep in the job; numpy's bool is a bool."""
    with pytest.raises(ValueError) as e:
        gd.AnalysisOptions(**{field: value})
    assert str(e.value) == said
    assert gd.AnalysisOptions(verify=np.False_, formulations=np.bool_(True)).verify is np.False_


@pytest.mark.parametrize("value", [True, np.True_, False, 3.5, "3", None, 10, -1])
def test_a_gzip_level_that_is_a_bool_or_not_a_whole_number_0_to_9_is_refused(value):
    """AnalysisOptions(compress=True) was accepted and read as gzip level 1 (True in
    range(10)); a bool is refused as the thresholds refuse one, naming the option."""
    with pytest.raises(ValueError, match=r"^compress must be a whole number 0-9, got "):
        gd.AnalysisOptions(compress=value)
    assert [gd.AnalysisOptions(compress=k).compress for k in (0, np.int64(9))] == [0, 9]
