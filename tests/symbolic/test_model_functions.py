"""The deployed model's five functions (symbolic/model_functions.py), both forms, drives.

Oracles: Pinocchio's crba (armature on the diagonal), nonLinearEffects minus
computeGeneralizedGravity plus the drives' friction F_v qd + F_c sign(qd), computeGeneralizedGravity
and rnea plus friction, on the exact models of a random chain with prismatic joints (explicit form)
and of the PUMA 560 with drives (recursive form); the identities D qdd + h + c = tau and
Y beta = tau of a pruned model with drives. The functions are evaluated through the emitted numpy
module (whose agreement with the C is tested in test_emit_model.py).
"""

import numpy as np
import pinocchio as pin
import pytest
from scales import identity_errors
from symbolic_helpers import mixed_chain, states

from gd_analyze import SimplifiedModel, load_robot
from gd_analyze.dynamics.base_parameters import random_states
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.ranking.labels import element_labels
from gd_analyze.symbolic.emit_model import numpy_source
from gd_analyze.symbolic.explicit import derive, model_terms
from gd_analyze.symbolic.model_functions import FUNCTIONS, joint_labels
from gd_analyze.symbolic.recursive_model import recursive_model


def _model(robot, **kw):
    return SimplifiedModel(robot=robot, choices={k: "both" for k in element_labels(robot.n)},
                           dominance_threshold=0.9, negligible_threshold=0.01, **kw)


def _numpy(model):
    ns = {}
    exec(compile(numpy_source(model.functions(), {"robot": "test"}), "<model>", "exec"), ns)
    return ns


def _friction(robot, qd):
    return robot.viscous * qd + robot.coulomb * np.sign(qd) + robot.torque_offset


def _oracle(robot, q, qd, qdd):
    model = pinocchio_model(robot)
    data = model.createData()
    D, h, c, tau = [], [], [], []
    for x, v, a in zip(q, qd, qdd):
        M = pin.crba(model, data, x)
        D.append(np.triu(M) + np.triu(M, 1).T)
        g = pin.computeGeneralizedGravity(model, data, x).copy()
        c.append(g)
        h.append(pin.nonLinearEffects(model, data, x, v) - g)
        tau.append(pin.rnea(model, data, x, v, a).copy())
    f = _friction(robot, qd)
    return np.array(D), np.array(h) + f, np.array(c), np.array(tau) + f


def _check(ns, robot, q, qd, qdd, tol):
    D, h, c, tau = _oracle(robot, q, qd, qdd)
    peak = np.abs(tau).max(axis=0)
    diag = np.abs(np.diagonal(D, axis1=1, axis2=2)).max(axis=0)
    assert (np.abs(ns["tau"](q, qd, qdd) - tau) / peak).max() < tol
    assert (np.abs(ns["velocity_terms"](q, qd) - h) / peak).max() < tol
    assert (np.abs(ns["gravity"](q) - c) / peak).max() < tol
    assert (np.abs(ns["inertia"](q) - D) / np.sqrt(np.outer(diag, diag))).max() < tol
    Ybeta = np.einsum("kib,b->ki", ns["regressor"](q, qd, qdd), ns["BASE_PARAMETERS"])
    assert (np.abs(Ybeta - tau) / peak).max() < tol


def test_explicit_form_equals_pinocchio():
    """A random chain with two prismatic joints, its whole explicit model: every function."""
    robot = mixed_chain(3, seed=2)
    terms = model_terms(derive(robot))
    model = _model(robot, terms=terms)
    assert model.form == "explicit"
    ns = _numpy(model)
    q, qd, qdd = states(robot, 50, 3)
    _check(ns, robot, q, qd, qdd, 1e-10)
    names = model.functions().parameter_names
    assert len(names) == len(ns["BASE_PARAMETERS"]) and names[0].startswith("D11")


def test_recursive_form_with_drives_equals_pinocchio():
    """The PUMA with armature and friction, exact: armature in D, friction in h and tau."""
    robot = load_robot("puma560-drives")
    assert robot.armature.any() and robot.viscous.any() and robot.coulomb.any()
    q, qd, qdd = random_states(robot, 60, 5)
    qd[:3, 0] = 0.0                                    # sign(0) = 0, as numpy's
    model = _model(robot, recursive=recursive_model(robot, q, qd, qdd, 0.0))
    ns = _numpy(model)
    _check(ns, robot, q, qd, qdd, 1e-10)
    names = model.functions().parameter_names
    assert {"Ia1", "Fv1", "Fc1"} <= set(names) and len(names) == ns["N_BASE_PARAMETERS"]


def test_torque_offsets_are_in_h_tau_and_the_regressor():
    """The PUMA with drives and constant torque offsets of both signs, exact: tau_0 in h and
    tau (rnea plus friction plus offsets), and a column of ones per offset in the regressor."""
    import dataclasses

    robot = load_robot("puma560-drives")
    offsets = np.array([1.5, -2.0, 0.0, 0.25, -0.1, 0.05])
    robot = dataclasses.replace(robot, torque_offset=offsets)
    q, qd, qdd = random_states(robot, 40, 7)
    model = _model(robot, recursive=recursive_model(robot, q, qd, qdd, 0.0))
    ns = _numpy(model)
    _check(ns, robot, q, qd, qdd, 1e-10)
    names = list(model.functions().parameter_names)
    assert {"tau0_1", "tau0_2", "tau0_6"} <= set(names) and "tau0_3" not in names
    Y = ns["regressor"](q, qd, qdd)
    col = names.index("tau0_2")
    assert np.array_equal(Y[:, :, col], np.tile([0.0, 1.0, 0, 0, 0, 0], (len(q), 1)))
    assert ns["BASE_PARAMETERS"][col] == -2.0


def test_pruned_model_with_drives_keeps_the_identities():
    robot = load_robot("puma560-drives")
    q, qd, qdd = random_states(robot, 60, 6)
    model = _model(robot, recursive=recursive_model(robot, q, qd, qdd, 0.02))
    assert model.recursive.dropped.any()
    assert max(identity_errors(_numpy(model), q, qd, qdd)) < 1e-12
    costs = model.functions().costs()
    assert list(costs) == [f.key for f in FUNCTIONS]
    assert costs["tau"] == model.program().cost()


@pytest.mark.parametrize("urdf, want", [
    (["j 1", 'x"; puts("y'], ("j 1", 'x"; puts("y')),
    ([], ("joint1", "joint2")),
])
def test_joint_labels_are_the_exact_names(urdf, want):
    """The names themselves: the emitted files escape them (test_emit_model)."""
    import dataclasses
    import types

    robot = load_robot("two-link")
    meta = types.MappingProxyType({"urdf_joints": urdf} if urdf else {})
    assert joint_labels(dataclasses.replace(robot, metadata=meta)) == want
