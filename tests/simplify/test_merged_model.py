"""The merged model of a sweep, built without the sweep's dataset or any cache, against
Pinocchio's rnea: within EPS of each trajectory's own scale on every swept trajectory, or
within its proved bound over the region."""

import numpy as np
import pytest
from symbolic_helpers import rnea

from gd_analyze.dynamics.base_parameters import base_parameters
from gd_analyze.simplify.deploy import guarantee_region
from gd_analyze.simplify.merged_model import region_merged_model, trajectory_merged_model
from gd_analyze.symbolic.explicit import derive, model_terms
from gd_analyze.symbolic.pruning import stacked_peaks


def _peaks(robot, trajectories):
    stack = [np.concatenate([getattr(t, k) for t in trajectories]) for k in ("q", "qd", "qdd")]
    return stacked_peaks(robot, base_parameters(robot), *stack, [len(t.q) for t in trajectories])


@pytest.mark.parametrize("explicit", [False, True])
def test_within_eps_of_each_trajectorys_own_scale(puma, mixed, explicit):
    eps, floor = 0.01, 0.5
    terms = model_terms(derive(puma)) if explicit else None
    model = trajectory_merged_model(puma, mixed, *_peaks(puma, mixed), tolerance=eps,
                                    torque_floor=floor, terms=terms)
    assert model.guarantee.kind == "trajectory"
    worst = 0.0
    for t in mixed:
        ref = rnea(puma, t.q, t.qd, t.qdd)
        scale = np.maximum(np.abs(ref).max(axis=0), floor)
        err = np.abs(model.torque(t.q, t.qd, t.qdd) - ref).max(axis=0)
        assert np.all(err <= eps * scale * (1 + 1e-9)), (err / scale).max()
        worst = max(worst, float((err / scale).max()))
    assert model.validation["worst_scaled_error"] == pytest.approx(worst, rel=1e-6, abs=1e-9)
    assert ("explicit, full" in model.costs) == explicit


def test_region_model_holds_its_proved_bound_at_sampled_states_and_tells_the_store(puma, mixed):
    from gd_analyze.simplify.region_memo import Derivations

    told = []
    region, _, proved = guarantee_region(puma, "region")
    assert proved
    model, reference = region_merged_model(puma, mixed, region, tolerance=0.01,
                                           derive=Derivations(claimed=told.append))
    assert reference is None and model.guarantee.kind == "region" and len(told) == 1
    rng = np.random.default_rng(0)
    q = rng.uniform(region.q_min, region.q_max, (400, puma.n))
    qd = rng.uniform(-1, 1, (400, puma.n)) * region.qd_max
    qdd = rng.uniform(-1, 1, (400, puma.n)) * region.qdd_max
    err = np.abs(model.torque(q, qd, qdd) - rnea(puma, q, qd, qdd)).max(axis=0)
    bound = np.asarray(model.guarantee.bound, float)
    assert np.all(np.isfinite(bound)) and np.all(err <= bound * (1 + 1e-9) + 1e-12)
    assert np.all(bound <= 0.01 * np.asarray(model.guarantee.scale) * (1 + 1e-9))
