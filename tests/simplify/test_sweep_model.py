"""The explicit model over the trajectories of a sweep, against Pinocchio's rnea: guaranteed
on every swept trajectory, its errors gathered per trajectory, and pure (the terms it is given
or derives itself; nothing kept between runs)."""

import numpy as np
from symbolic_helpers import rnea

from gd_analyze import load_robot
from gd_analyze.simplify.sweep_model import sweep_model
from gd_analyze.trajectory.planning import random_trajectories


def test_sweep_model_is_guaranteed_on_every_swept_trajectory():
    robot = load_robot("puma560")
    trajs = random_trajectories(robot, 6, seed=5)
    held = random_trajectories(robot, 3, seed=99)
    model, sel = sweep_model(robot, trajs, tolerance=0.02, held_out=held)
    scale = np.zeros(6)
    refs = [rnea(robot, t.q, t.qd, t.qdd) for t in trajs]
    for ref in refs:
        scale = np.maximum(scale, np.abs(ref).max(axis=0))
    np.testing.assert_allclose(sel.scale, scale, rtol=1e-9)
    for t, ref in zip(trajs, refs):
        err = np.abs(model.torque(t.q, t.qd, t.qdd) - ref).max(axis=0)
        assert (err <= 0.02 * scale * (1 + 1e-9)).all()
    assert model.validation["trajectories"] == 6
    assert len(model.validation["held_out"]["peak_abs_error"]) == 6


def test_sweep_errors_gathered_in_chunks_are_each_trajectorys(monkeypatch):
    """The per-trajectory errors of a sweep, computed on all states at once in chunks that
    cut through trajectories, equal the errors against Pinocchio's rnea on each alone."""
    import gd_analyze.simplify.sweep_model as simplify

    robot = load_robot("puma560")
    trajs = random_trajectories(robot, 5, seed=11)
    model = sweep_model(robot, trajs, tolerance=0.05)[0]
    real = simplify.per_trajectory_errors
    monkeypatch.setattr(simplify, "per_trajectory_errors",
                        lambda m, t, r=None: real(m, t, r, chunk=7))      # cuts trajectories
    v = simplify.sweep_validation(model, trajs, np.ones((5, robot.n)), np.zeros(robot.n))
    per = v["per_trajectory"]
    for k, t in enumerate(trajs):
        ref = rnea(robot, t.q, t.qd, t.qdd)
        err = model.torque(t.q, t.qd, t.qdd) - ref
        tol = 1e-9 * np.abs(ref).max()
        np.testing.assert_allclose(per["peak_abs_error"][k], np.abs(err).max(axis=0), atol=tol)
        np.testing.assert_allclose(per["rms_error"][k], np.sqrt((err ** 2).mean(axis=0)),
                                   atol=tol)
        np.testing.assert_allclose(per["peak_tau"][k], np.abs(ref).max(axis=0), atol=tol)
    every = np.concatenate([model.torque(t.q, t.qd, t.qdd) - rnea(robot, t.q, t.qd, t.qdd)
                            for t in trajs])
    np.testing.assert_allclose(v["peak_abs_error"], np.abs(every).max(axis=0),
                               atol=1e-9 * np.abs(every).max())


def test_derives_its_terms_without_the_cache_and_uses_those_given(tmp_path, monkeypatch):
    """Without terms, the model derives them itself and leaves the derivation cache folder
    empty; given terms (here the two-link arm's own with every coefficient doubled), it uses
    those and no others: its full torque is then twice rnea's."""
    import dataclasses

    from gd_analyze.simplify import sweep_model as module
    from gd_analyze.symbolic.explicit import derive, model_terms

    monkeypatch.setenv("GD_ANALYZE_CACHE_DIR", str(tmp_path / "cache"))
    robot = load_robot("two-link")
    trajs = random_trajectories(robot, 2, seed=3)
    model = sweep_model(robot, trajs, tolerance=0.0)[0]
    assert not (tmp_path / "cache").exists() or not any((tmp_path / "cache").rglob("*"))
    for t in trajs:
        ref = rnea(robot, t.q, t.qd, t.qdd)
        np.testing.assert_allclose(model.torque(t.q, t.qd, t.qdd), ref,
                                   atol=1e-9 * np.abs(ref).max())
    terms = model_terms(derive(robot))
    doubled = dataclasses.replace(terms, C=2 * np.asarray(terms.C))
    monkeypatch.setattr(module, "derive", lambda r: (_ for _ in ()).throw(AssertionError))
    twice = sweep_model(robot, trajs, tolerance=0.0, terms=doubled)[0]
    for t in trajs:
        ref = rnea(robot, t.q, t.qd, t.qdd)
        np.testing.assert_allclose(twice.torque(t.q, t.qd, t.qdd), 2 * ref,
                                   atol=1e-9 * np.abs(ref).max())
