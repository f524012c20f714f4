"""simplify/consistency.py: a model file is read only if its program is what its stored
pairs, parameters and bound give. Hand-edited PUMA 560 region models: one that drops
gravity parts its bound does not cover (its error against Pinocchio's rnea is about its whole
gravity torque), one that lists pairs its program keeps, one whose stored cost is another
program's."""

import json

import numpy as np
import pinocchio as pin
import pytest
from conftest import SHIPPED

from gd_analyze import InputError
from gd_analyze.cli import main
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.simplify.simplified import SimplifiedModel
from gd_analyze.store.model_file import load_model
from gd_analyze.trajectory.trajectory import read_trajectory


@pytest.fixture(scope="module")
def region_model(shared_main):
    # the default run (shared, read only: the tests write edited copies in their tmp_path)
    path = shared_main("puma560", SHIPPED) / "simplified_model.json"
    return path, json.loads(path.read_text())


def _write(tmp_path, spec, name="edited.json"):
    path = tmp_path / name
    path.write_text(json.dumps(spec))
    return path


def _gravity_dropped(spec, tmp_path):
    """The file with the gravity parts of the first half of its base parameters added to its
    dropped pairs (the program then leaves them out: 318 operations against the exact 320),
    its cost and guarantee left as they were."""
    spec = json.loads(json.dumps(spec))
    rec = spec["recursive"]
    extra = [[name, "gravity"] for name in rec["base_parameters"][:18]]
    rec["dropped"] = [list(p) for p in rec["dropped"]]
    rec["dropped"] += [p for p in extra if p not in rec["dropped"]]
    return spec


def test_the_tools_own_file_is_read(region_model):
    path, _ = region_model
    assert load_model(path).guarantee.proved


def test_dropped_gravity_beyond_the_bound_is_refused(region_model, tmp_path):
    path, spec = region_model
    edited = _gravity_dropped(spec, tmp_path)
    del edited["cost"], edited["guarantee"]          # the program alone, built unchecked
    program_only = SimplifiedModel.from_dict(edited, load_model(path).robot, "edited")
    # the oracle: the edited program against Pinocchio's rnea on the shipped trajectory
    robot = program_only.robot
    pmodel = pinocchio_model(robot)
    data = pmodel.createData()
    traj = read_trajectory(SHIPPED, n_joints=6)
    tau = np.array([pin.rnea(pmodel, data, q, qd, qdd).copy()
                    for q, qd, qdd in zip(traj.q, traj.qd, traj.qdd)])
    error = np.abs(program_only.torque(traj.q, traj.qd, traj.qdd) - tau).max(axis=0)
    guarantee = spec["guarantee"]
    assert np.any(error > np.asarray(guarantee["bound"]) * 10)     # the claim is false
    edited["guarantee"] = guarantee                  # and no cost: only the bound can tell
    with pytest.raises(InputError, match="guarantee.bound.*exceeds its proved bound"):
        load_model(_write(tmp_path, edited))


def test_a_stored_cost_of_another_program_is_refused(region_model, tmp_path):
    path, spec = region_model
    edited = _gravity_dropped(spec, tmp_path)
    with pytest.raises(InputError, match="key cost: the program built from"):
        load_model(_write(tmp_path, edited))


def test_dropped_pairs_the_program_keeps_are_refused(region_model, tmp_path):
    """Every parameter's inertial part listed as dropped: the pruned program costs more
    than the exact one, which would run while every output listed the drops."""
    path, spec = region_model
    edited = json.loads(json.dumps(spec))
    rec = edited["recursive"]
    rec["dropped"] = [[name, "inertial"] for name in rec["base_parameters"]]
    with pytest.raises(InputError, match="recursive.dropped: .* kept by the program"):
        load_model(_write(tmp_path, edited))


def test_control_states_no_guarantee_for_an_edited_file(region_model, tmp_path, capsys):
    path, spec = region_model
    edited = _gravity_dropped(spec, tmp_path)
    del edited["cost"]                               # only the bound can tell
    code = main(["control", str(_write(tmp_path, edited)), str(SHIPPED), "--no-report",
                 "-o", str(tmp_path / "control")])
    out, err = capsys.readouterr()
    assert code == 2 and "guarantee" not in out and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "control").exists()
