"""identification.h5: group names, and a result written (within its estimated size) and read
back."""

import json

import numpy as np
from identify_recordings import fourier, truth_for

from gd_analyze import load_robot
from gd_analyze.jobs.identify import IdentifyOptions, identify
from gd_analyze.store.stored_identification import (
    group_names,
    identification_size,
    identification_tree,
    read_identification,
    recordings_json,
    write_identification,
)
from gd_analyze.trajectory.trajectory import recording_from_arrays


def test_group_names_are_safe_and_unique():
    assert group_names(["a b", "a b", "a_b", "", "-x", "ü"]) == \
        ["a_b", "a_b_2", "a_b_3", "r", "r-x", "_"]


def test_written_and_read_back(tmp_path):
    robot = load_robot("two-link")
    truth = truth_for(robot, seed=3)
    t = np.arange(0, 10, 0.005)
    q, qd, qdd = fourier(2, t, seed=1, harmonics=3, base_hz=0.2)
    rec = recording_from_arrays(t + 100.0, q, truth.torque(q, qd, qdd), qd, qdd,
                                source="weird name/r.csv")
    result = identify(robot, [rec], validate=[rec], options=IdentifyOptions(cutoff=None))
    path = write_identification(result, tmp_path / "identification.h5")
    assert path.stat().st_size <= identification_size([t.size, t.size], robot.n)
    tree = read_identification(path)
    assert list(tree) == ["/", "r", "r_2"]
    root = tree["/"]
    assert root.attrs["condition_number"] == result.condition_number
    assert list(root.parameter.values) == list(result.parameters.names)
    assert np.array_equal(root["std"].values, result.parameters.std)
    assert json.loads(root.attrs["settings"])["cutoff_hz"] is None
    ds = tree["r_2"]
    assert ds.attrs["role"] == "validate"
    assert np.array_equal(ds.t.values, t + 100.0)          # not shifted
    assert np.array_equal(ds.tau_predicted.values, result.recordings[1].tau_predicted)
    doc = recordings_json(result)
    assert doc["recordings"][1]["total_relative_error"] == ds.attrs["total_relative_error"]
    # a recording named like one of the root group's variables or dimensions gets a group of
    # its own (h5netcdf refused to create the group: an internal error)
    root = identification_tree(result)["/"]
    taken = sorted(set(root.variables) | set(root.dims))
    assert not set(group_names(taken)) & set(taken)
    rec = recording_from_arrays(t, q, truth.torque(q, qd, qdd), qd, qdd, source="offset.csv")
    result = identify(robot, [rec], options=IdentifyOptions(cutoff=None))
    tree = read_identification(write_identification(result, tmp_path / "offset.h5"))
    assert list(tree) == ["/", "offset_2"]
