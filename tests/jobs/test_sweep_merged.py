"""The chapter rule's merged model of a sweep (gd_analyze.jobs.sweep_merged.merged_model),
read from a sweep dataset written by hand: its choices and validation as stored, and a
dataset without one of them refused in one line naming it."""

import pytest
import xarray as xr

from gd_analyze.errors import InputError
from gd_analyze.jobs.sweep_merged import merged_model
from gd_analyze.ranking.labels import element_labels


def _sweep(robot):
    labels = element_labels(robot.n)
    joint = ("joint",)
    return xr.Dataset({
        "merged_choice": ("element", ["both"] * len(labels)),
        "merged_error_peak": (joint, [0.1, 0.2]),
        "merged_error_rms": (joint, [0.01, 0.02]),
        "merged_error_tau_peak": (joint, [10.0, 20.0]),
        "merged_error_relative_peak": (joint, [0.01, 0.01]),
        "merged_error_relative_rms": (joint, [0.001, 0.001]),
    }, coords={"element": labels, "trajectory": [0, 1, 2]}, attrs={"setpoints_total": 93})


def test_the_validation_is_the_stored_error_over_all_trajectories(two_link):
    model = merged_model(two_link, _sweep(two_link))
    assert model.validation == {
        "peak_abs_error": [0.1, 0.2], "rms_error": [0.01, 0.02], "peak_tau": [10.0, 20.0],
        "relative_peak_error": [0.01, 0.01], "relative_rms_error": [0.001, 0.001],
        "trajectories": 3, "setpoints": 93}
    assert set(model.choices.values()) == {"both"}


@pytest.mark.parametrize("name", ["merged_choice", "merged_error_rms",
                                  "merged_error_relative_rms"])
def test_a_dataset_without_a_merged_variable_is_refused_naming_it(two_link, name):
    with pytest.raises(InputError) as err:
        merged_model(two_link, _sweep(two_link).drop_vars(name))
    assert str(err.value) == f"not a gd-analyze sweep dataset: missing {name}"
