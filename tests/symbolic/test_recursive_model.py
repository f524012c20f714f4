"""The pruned recursive model as a value (symbolic/recursive_model.py).

Oracles: Pinocchio's rnea (the model's error never exceeds its bound, the bound never exceeds
EPS x scale_i, scale_i from rnea's peaks; EPS = 0 gives rnea itself) and its joint torque
regressor (the base parameters beta reproduce rnea through Y_b = Y K); the model file's
round trip, and every edit to it refused with the key named."""

import copy
from functools import cache

import numpy as np
import pinocchio as pin
import pytest
from symbolic_helpers import rnea, robot, states

from gd_analyze.dynamics.base_parameters import PARAMETER_NAMES, base_parameters
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.errors import InputError
from gd_analyze.model.mounting import with_mounting
from gd_analyze.symbolic.emit import python_function
from gd_analyze.symbolic.recursive_model import (
    BOUND_PARTS,
    PART_NAMES,
    RecursiveModel,
    recursive_model,
)

ROUND = 1e-11


@cache
def case(eps, floor=0.0):
    arm = robot("stanford")
    q, qd, qdd = states(arm, 150, 71)
    q[:, arm.prismatic] *= 0.2
    model = recursive_model(arm, q, qd, qdd, eps, torque_floor=floor)
    return arm, (q, qd, qdd), rnea(arm, q, qd, qdd), model


@pytest.mark.parametrize("eps, floor", [(0.01, 0.0), (0.05, 20.0)])
def test_error_within_bound_within_eps_of_the_scale(eps, floor):
    arm, (q, qd, qdd), tau, model = case(eps, floor)
    np.testing.assert_allclose(model.scale, np.maximum(np.abs(tau).max(axis=0), floor),
                               rtol=1e-10)
    error = np.abs(python_function(model.program(arm))(q, qd, qdd) - tau).max(axis=0)
    assert np.all(error <= model.bound + ROUND * model.scale.max())
    assert np.all(model.bound <= eps * model.scale * (1 + 1e-12))
    assert model.dropped.any()
    np.testing.assert_allclose(model.bound_by_part.sum(axis=0), model.bound, rtol=1e-10,
                               atol=1e-15 * model.scale.max())
    # every dropped pair names a parameter and a part; pairs of no contribution cost nothing
    assert len(model.dropped_pairs()) == int(model.dropped.sum())
    assert {p for _, p in model.dropped_pairs()} <= set(PART_NAMES)
    assert model.relative_peak.shape == model.dropped.shape
    assert np.all(model.relative_peak[model.dropped] <= eps * (1 + 1e-12))


def test_chosen_pairs_keep_their_bound_against_rnea():
    """A model of given pairs (some of the search's restored) holds its bound against rnea;
    pairs over the budget are refused."""
    arm, (q, qd, qdd), tau, model = case(0.05, 20.0)
    dropped = model.dropped.copy()
    dropped[np.argwhere(dropped)[0][0]] = False              # one parameter restored
    chosen = recursive_model(arm, q, qd, qdd, 0.05, torque_floor=20.0,
                             chosen=(dropped, np.zeros(dropped.shape[0], bool)))
    np.testing.assert_array_equal(chosen.dropped, dropped)
    error = np.abs(python_function(chosen.program(arm))(q, qd, qdd) - tau).max(axis=0)
    assert np.all(error <= chosen.bound + ROUND * chosen.scale.max())
    assert np.all(chosen.bound <= 0.05 * chosen.scale * (1 + 1e-12))
    everything = np.ones_like(dropped)
    with pytest.raises(ValueError):
        recursive_model(arm, q, qd, qdd, 0.05, torque_floor=20.0,
                        chosen=(everything, everything.all(axis=1)))


def test_exact_model_is_rnea():
    arm, (q, qd, qdd), tau, model = case(0.0)
    assert not model.dropped.any() and np.all(model.bound == 0)
    error = np.abs(python_function(model.program(arm))(q, qd, qdd) - tau).max()
    assert error <= 1e-10 * np.abs(tau).max()


#: Pinocchio's per-link parameter order (m, mc_x, mc_y, mc_z, Ixx, Ixy, Iyy, Ixz, Iyz, Izz)
#: taken to ours (XX, XY, XZ, YY, YZ, ZZ, MX, MY, MZ, M).
PIN_ORDER = [4, 5, 7, 6, 8, 9, 1, 2, 3, 0]


def test_beta_gives_rnea_through_pinocchios_regressor():
    """tau = W_B beta: Pinocchio's joint torque regressor, its columns of the model's base
    parameters (by name), times the stored beta, is rnea."""
    arm, (q, qd, qdd), tau, model = case(0.05, 20.0)
    base = model.base(arm)
    assert tuple(base.names()) == model.names
    np.testing.assert_array_equal(base.beta, model.beta)
    np.testing.assert_array_equal(model.beta, base_parameters(arm).beta)
    pmodel = pinocchio_model(arm)
    data = pmodel.createData()
    names = [f"{p}{j + 1}" for j in range(arm.n) for p in PARAMETER_NAMES]
    columns = [names.index(name) for name in model.names]
    for k in range(20):
        Y = pin.computeJointTorqueRegressor(pmodel, data, q[k], qd[k], qdd[k])
        W = np.concatenate([Y[:, 10 * j:10 * j + 10][:, PIN_ORDER] for j in range(arm.n)], 1)
        assert np.abs(W[:, columns] @ model.beta - tau[k]).max() <= 1e-10 * np.abs(tau).max()


def test_model_file_round_trip():
    arm, (q, qd, qdd), _, model = case(0.05, 20.0)
    back = RecursiveModel.from_dict(model.to_dict(), arm)
    assert back.names == model.names and back.relative_peak is None
    for key in ("beta", "dropped", "scale", "bound", "bound_by_part"):
        np.testing.assert_array_equal(getattr(back, key), getattr(model, key))
    assert list(model.to_dict()["bound_by_part"]) == list(BOUND_PARTS)
    np.testing.assert_array_equal(python_function(back.program(arm))(q, qd, qdd),
                                  python_function(model.program(arm))(q, qd, qdd))



def test_stated_facts_leave_out_structurally_zero_pairs_and_survive_the_file():
    """Gravity acts on the mass and the first moments only (g enters Y_b through the
    linear accelerations), so the gravity part of every second moment (XX..ZZ) contributes
    nothing: such pairs are neither kept nor dropped in what the reports state, also after
    the model has been written to a file and read back."""
    arm, _, _, model = case(0.05, 20.0)
    live = model.contributing()
    gravity = list(PART_NAMES).index("gravity")
    second = [k for k, name in enumerate(model.names) if name[:2] in
              ("XX", "XY", "XZ", "YY", "YZ", "ZZ")]
    assert second and not live[second, gravity].any()
    facts = model.stated_facts()
    assert facts["known"] and facts["pairs"] == int(live.sum()) < live.size
    assert facts["dropped"] == int((model.dropped & live).sum())
    assert all(model.names.index(n) not in second for n in facts["gravity_dropped"])
    back = RecursiveModel.from_dict(model.to_dict(), arm)
    np.testing.assert_array_equal(back.contributing(), live)
    assert back.stated_facts() == facts
    old = {k: v for k, v in model.to_dict().items() if k != "round_off"}   # an older file
    assert not RecursiveModel.from_dict(old, arm).stated_facts()["known"]


@pytest.mark.parametrize("gravity", [None, (0.0, 0.0, 0.0)])
def test_an_older_file_counts_no_pair_its_arm_makes_zero(gravity):
    """A model file without ``round_off`` (an older one) does not record which pairs act; it
    counted every pair, the gravity parts of an arm without gravity too. Read back, it leaves
    out the pairs its own arm makes identically 0: the gravity part of every second moment,
    and every gravity part where gravity is 0. Oracles: Pinocchio's generalized gravity (rnea
    at rest: 0 on the weightless arm), and the pairs' own peaks on the trajectory (a pair left
    out never acts)."""
    arm = robot("stanford")
    if gravity is not None:
        arm = with_mounting(arm, gravity=gravity)
    q, qd, qdd = states(arm, 40, 5)
    q[:, arm.prismatic] *= 0.2
    rest = np.zeros_like(q)
    weightless = not np.any(rnea(arm, q, rest, rest))
    assert weightless == (gravity is not None)
    model = recursive_model(arm, q, qd, qdd, 0.01)
    old = {k: v for k, v in model.to_dict().items() if k not in ("round_off", "dropped_round_off")}
    back = RecursiveModel.from_dict(old, arm)
    live, acts = back.contributing(), model.contributing()
    assert not (acts & ~live).any()                     # nothing that acts is left out
    g = list(PART_NAMES).index("gravity")
    second = [k for k, name in enumerate(back.names) if name[:2] in PARAMETER_NAMES[:6]]
    assert second and not live[second, g].any()
    assert live[:, g].any() != weightless
    facts = back.stated_facts()
    assert not facts["known"] and facts["pairs"] == int(live.sum())
    b = len(back.names)
    assert facts["pairs"] == 2 * b + (0 if weightless else b - len(second))
    assert not weightless or facts["gravity_dropped"] == []


def test_model_file_names_the_dropped_pairs_the_reports_name():
    """simplified_model.json listed 8 dropped pairs where the report named 4 (the
    round-off pairs of a dropped parameter were listed as dropped). The file's "dropped" is
    the reports' list; the ≡ 0 pairs left out with their parameter are listed apart."""
    arm, (q, qd, qdd), _, model = case(0.05, 20.0)
    live = model.contributing()
    assert (model.dropped & ~live).any() and (model.dropped & live).any()   # the case at hand
    spec = model.to_dict()
    assert [tuple(p) for p in spec["dropped"]] == model.stated_facts()["dropped_pairs"]
    round_off = {tuple(p) for p in spec["round_off"]}
    assert not round_off & {tuple(p) for p in spec["dropped"]}
    assert {tuple(p) for p in spec["dropped_round_off"]} <= round_off
    back = RecursiveModel.from_dict(spec, arm)
    np.testing.assert_array_equal(back.dropped, model.dropped)     # the same model code


def _edit(path, value):
    def mutate(spec):
        *keys, last = path
        target = spec
        for key in keys:
            target = target[key]
        target[last] = value(target[last]) if callable(value) else value
    return mutate


@pytest.mark.parametrize("mutate, column, words", [
    (_edit(("beta", 0), lambda v: v * (1 + 1e-6)), "recursive.beta",
     "differ from those of the robot"),
    (_edit(("base_parameters", 0), "ZZ9"), "recursive.base_parameters", "differ"),
    (_edit(("dropped",), [["ZZ9", "gravity"]]), "recursive.dropped", "unknown dropped pair"),
    (_edit(("dropped",), lambda v: [[v[0][0], "friction"]]), "recursive.dropped",
     "unknown dropped pair"),
    (_edit(("scale",), [1.0]), "recursive.scale", "expected 6 numbers"),
    (_edit(("bound_by_part",), lambda v: {k: [0.0] for k in v}), "recursive.bound_by_part",
     "lists of 6"),
])
def test_edited_model_files_are_refused_naming_the_key(mutate, column, words):
    arm, _, _, model = case(0.05, 20.0)
    spec = copy.deepcopy(model.to_dict())
    mutate(spec)
    with pytest.raises(InputError) as err:
        RecursiveModel.from_dict(spec, arm, path="simplified_model.json")
    assert err.value.column == column and words in str(err.value)
    assert str(err.value).startswith("simplified_model.json: key ")


def test_beta_within_the_agreement_is_accepted():
    """Rounding in a written file (1e-10 relative) is not an edit."""
    arm, _, _, model = case(0.05, 20.0)
    spec = copy.deepcopy(model.to_dict())
    spec["beta"] = [v * (1 + 1e-10) for v in spec["beta"]]
    back = RecursiveModel.from_dict(spec, arm)
    np.testing.assert_array_equal(back.beta, model.beta)          # the derived values are kept


def test_bad_tolerances_are_refused():
    arm = robot("two-link")
    q, qd, qdd = states(arm, 5, 72)
    for eps in (-0.1, float("nan")):
        with pytest.raises(ValueError):
            recursive_model(arm, q, qd, qdd, eps)
