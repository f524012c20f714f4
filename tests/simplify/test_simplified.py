import itertools
import json

import numpy as np
import pytest
from conftest import random_states

from gd_analyze import InputError, SimplifiedModel, gd_terms
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.ranking.ranking import element_labels
from gd_analyze.simplify.simplified import choice_masks, merge_choices, simplified_torque
from gd_analyze.store.model_file import load_model, save_model


def _model(robot, choice):
    return SimplifiedModel(robot=robot, choices={lab: choice for lab in element_labels(robot.n)},
                           dominance_threshold=0.9, negligible_threshold=0.01)


def test_keeping_both_everywhere_is_the_full_model_rnea(puma):
    import pinocchio as pin

    q, qd, qdd = random_states(puma, 30, 21)
    tau = _model(puma, "both").torque(q, qd, qdd)
    model = pinocchio_model(puma)
    data = model.createData()
    ref = np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])
    np.testing.assert_allclose(tau, ref, rtol=0, atol=1e-10 * np.abs(ref).max())


def test_keeping_only_one_part_is_the_half_model(puma):
    """'tran' everywhere: tau = D_tran qdd + h_tran + c, which is Pinocchio's rnea on the
    zero-rotational-inertia model (gravity acts on the masses only)."""
    import pinocchio as pin

    q, qd, qdd = random_states(puma, 20, 22)
    tau = _model(puma, "tran").torque(q, qd, qdd)
    model = pinocchio_model(puma, "tran")
    data = model.createData()
    ref = np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])
    np.testing.assert_allclose(tau, ref, rtol=0, atol=1e-10 * np.abs(ref).max())
    # 'none' everywhere leaves gravity alone
    c = gd_terms(puma, q, qd).c
    np.testing.assert_allclose(_model(puma, "none").torque(q, qd, qdd), c, rtol=0, atol=1e-13)


def test_torque_is_the_program_on_the_whole_arrays(puma):
    """torque is the emitted program's tau bit for bit (its blocks: test_codegen.py), for
    many states, one state and none."""
    model = _model(puma, "tran")
    q, qd, qdd = random_states(puma, 23, 31)
    whole = model.program()._tau_function(q, qd, qdd)
    got = model.torque(q, qd, qdd)
    assert got.shape == whole.shape == (23, puma.n)
    assert np.array_equal(got, whole)
    assert model.torque(q[:0], qd[:0], qdd[:0]).shape == (0, puma.n)
    assert np.array_equal(model.torque(q[3], qd[3], qdd[3]), whole[3:4])


@pytest.mark.parametrize("choice", ["both", "tran"])
def test_torque_at_one_state_is_the_half_model_rnea(puma, choice):
    """torque_at, one state at a time: Pinocchio's rnea of the whole (both) and of the
    zero-rotational-inertia (tran) model, as torque is; not finite in, NaN out; n entries."""
    import pinocchio as pin

    q, qd, qdd = random_states(puma, 20, 23)
    qd[:3] = 0.0
    simp = _model(puma, choice)
    got = np.array([simp.torque_at(a, b, c) for a, b, c in zip(q, qd, qdd)])
    model = pinocchio_model(puma, "tran" if choice == "tran" else "full")
    data = model.createData()
    ref = np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-10 * np.abs(ref).max())
    bad = q[0].copy()
    bad[2] = np.inf
    assert np.isnan(simp.torque_at(bad, qd[0], qdd[0])).all()
    with pytest.raises(ValueError, match="6 entries"):
        simp.torque_at(q[0][:5], qd[0], qdd[0])


def test_masks_are_symmetric_and_complete():
    choices = {lab: "none" for lab in element_labels(3)}
    choices.update(D13="tran", D23="rot", h2="both")
    Mt, Mr, mt, mr = choice_masks(choices, 3)
    assert Mt[0, 2] == Mt[2, 0] == 1 and Mr[0, 2] == 0
    assert Mr[1, 2] == Mr[2, 1] == 1 and Mt.sum() == 2 and Mr.sum() == 2
    assert list(mt) == [0, 1, 0] and list(mr) == [0, 1, 0]
    del choices["h3"]
    with pytest.raises(ValueError, match="h3"):
        choice_masks(choices, 3)


def test_save_load_and_reuse_on_new_states(tmp_path, puma, shipped, puma_analysis):
    traj, analysis = shipped, puma_analysis          # the session's analysis, read only
    path = tmp_path / "simplified_model.json"
    save_model(analysis.model, path)
    spec = json.loads(path.read_text())
    assert spec["schema_version"] == 2 and spec["robot"]["name"] == "puma560"
    assert spec["rule"] == "budget" and spec["tolerance"] == 0.01
    assert set(spec["cost"]) >= {"multiplications", "additions"}
    assert set(spec["full_cost"]) >= {"multiplications", "additions"}
    assert spec["robot"]["sha256"] == puma.sha256 and spec["trajectory_sha256"] == traj.sha256
    assert spec["dominance_threshold"] == 0.9 and spec["negligible_threshold"] == 0.01
    assert len(spec["validation"]["peak_abs_error"]) == 6
    loaded = load_model(path)
    assert loaded.choices == analysis.model.choices
    q, qd, qdd = random_states(puma, 10, 4)
    terms = gd_terms(puma, q, qd)
    np.testing.assert_allclose(loaded.torque(q, qd, qdd), analysis.model.torque(q, qd, qdd),
                               rtol=1e-12, atol=1e-12)
    # a schema-1 file (no explicit terms) still loads: its kept parts, unpruned
    old = {k: v for k, v in spec.items() if k not in ("rule", "tolerance", "cost", "bound",
                                                      "full_cost", "explicit_terms",
                                                      "torque_floor", "form", "recursive",
                                                      "costs")}
    old["schema_version"] = 1
    # a schema-1 file has no recursive form, so no "pruned" choice: the kept parts are both
    old["choices"] = {k: "both" if v == "pruned" else v for k, v in old["choices"].items()}
    # nor the ways its bound was proved, which name a recursive model's dropped pairs: a file
    # that states them without a recursive form to derive them again on is refused
    assert old["guarantee"]["bound_method"][0] != "none"
    path.write_text(json.dumps(old))
    with pytest.raises(InputError, match="guarantee.bound_method: .*no recursive model"):
        load_model(path)
    old["guarantee"] = {k: v for k, v in old["guarantee"].items()
                        if k not in ("bound_method", "joint_sum_arithmetic")}
    path.write_text(json.dumps(old))
    np.testing.assert_allclose(load_model(path).torque(q, qd, qdd),
                               simplified_torque(terms, analysis.model.choices, qdd),
                               rtol=1e-10, atol=1e-10)


def test_load_errors(tmp_path):
    bad = tmp_path / "m.json"
    bad.write_text("{not json")
    with pytest.raises(InputError, match="not a simplified-model JSON"):
        load_model(bad)
    bad.write_text(json.dumps({"schema_version": 99}))
    with pytest.raises(InputError, match="schema_version"):
        load_model(bad)
    with pytest.raises(InputError, match="no such file"):
        load_model(tmp_path / "none.json")


@pytest.mark.parametrize("a, b, merged", [
    ("tran", "none", "tran"), ("tran", "rot", "both"), ("none", "none", "none"),
    ("rot", "both", "both"), ("rot", "rot", "rot"), ("none", "rot", "rot"),
    ("tran", "tran", "tran"), ("both", "none", "both"),
])
def test_merge_rule_hand_cases(a, b, merged):
    assert merge_choices([{"D11": a, "h1": "none"}, {"D11": b, "h1": "none"}]) == \
        {"D11": merged, "h1": "none"}


def test_merge_rule_many_models_and_order():
    models = [{"D11": "none", "D12": "tran", "h1": "rot"},
              {"D11": "none", "D12": "tran", "h1": "none"},
              {"D11": "none", "D12": "rot", "h1": "none"}]
    for perm in itertools.permutations(models):
        assert merge_choices(perm) == {"D11": "none", "D12": "both", "h1": "rot"}
    assert merge_choices(models[:1]) == models[0]
    assert list(merge_choices(models)) == ["D11", "D12", "h1"]


def test_merge_rule_errors():
    with pytest.raises(ValueError, match="no simplified models"):
        merge_choices([])
    with pytest.raises(ValueError, match="other elements"):
        merge_choices([{"D11": "tran"}, {"D11": "tran", "h1": "rot"}])
    with pytest.raises(ValueError, match="choice must be"):
        merge_choices([{"D11": "tran"}, {"D11": "translational"}])


@pytest.mark.parametrize("row, sin", [([-1, 0], False), ([0, -2], True), ([-1, 1], False)])
def test_explicit_terms_out_of_canonical_form_are_refused(tmp_path, two_link, row, sin):
    """A term cos or sin(k . q) whose first non-zero harmonic is negative (cos(-q1) is cos(q1),
    a form the code generator never meets): one line naming the key, not an internal error."""
    import dataclasses

    model = _model(two_link, "both")
    model = dataclasses.replace(model, terms=model.explicit_terms())
    path = tmp_path / "m.json"
    save_model(model, path)
    spec = json.loads(path.read_text())
    assert len(spec["explicit_terms"]["K"]) > 0
    spec["explicit_terms"]["K"][0], spec["explicit_terms"]["sin"][0] = row, sin
    path.write_text(json.dumps(spec))
    with pytest.raises(InputError, match="explicit_terms: .*canonical form") as err:
        load_model(path)
    assert "\n" not in str(err.value)


def test_a_urdf_models_file_keeps_the_urdfs_joint_names(tmp_path):
    """A model of a URDF arm read back names its joints as the URDF does (Pinocchio's
    ``model.names``), as results.h5 and the emitted files do, not joint1 .. jointn: control.h5
    of a UR10 model named its joints joint1 .. joint6. A count that is not one per joint is
    refused, naming the key."""
    import importlib.resources

    import pinocchio as pin

    from gd_analyze import load_robot

    urdf = importlib.resources.files("gd_analyze") / "data" / "ur5.urdf"
    robot = load_robot(str(urdf))
    path = tmp_path / "m.json"
    save_model(_model(robot, "both"), path)
    names = list(pin.buildModelFromUrdf(str(urdf)).names)[1:]
    assert load_model(path).robot.joint_names() == names
    spec = json.loads(path.read_text())
    spec["robot"]["joint_names"] = names[:-1]
    path.write_text(json.dumps(spec))
    with pytest.raises(InputError, match="robot.joint_names: 5 names for 6 joints"):
        load_model(path)
