"""Payload sweeps: one trajectory ranked for a range of loads on the last link."""

import itertools

import numpy as np
import pytest
from conftest import random_states

from gd_analyze import InputError, gd_terms
from gd_analyze.jobs.analyze import analyze
from gd_analyze.jobs.options import AnalysisOptions
from gd_analyze.jobs.payload import payload_sweep
from gd_analyze.model.robot import with_payload


@pytest.mark.slow
def test_payload_sweep_equals_plain_analyses(puma, shipped):
    com, inertia = (0.01, -0.02, 0.06), (2e-3, 3e-3, 1e-3)
    ds = payload_sweep(puma, shipped, [0.0, 1.5], com=com, inertia=inertia)
    np.testing.assert_array_equal(ds["payload"].values, [0.0, 1.5])
    assert ds["payload"].attrs["units"] == "kg"
    # zero payload: the plain analysis of the bare arm. Its ranking (shares, classes, choices,
    # peak torques) is the pass's, before and whatever the model built on it: ranked only
    ranked = AnalysisOptions(verify=False, formulations=False, simplify=None)
    plain = analyze(puma, shipped, ranked).dataset
    bare = analyze(with_payload(puma, 0.0, com, inertia), shipped, ranked).dataset
    loaded = analyze(with_payload(puma, 1.5, com, inertia), shipped, ranked).dataset
    for p, ref in ((0, bare), (1, loaded)):
        data = np.isfinite(ref["share_tran"].values)     # no share of an element ≡ 0
        np.testing.assert_allclose(ds["share_tran"].values[p][data],
                                   ref["share_tran"].values[data], rtol=0, atol=1e-12)
        assert ds["round_off"].values[p][~data].all()
        assert list(ds["dominance"].values[p]) == list(ref["dominance"].values)
        assert list(ds["choice"].values[p]) == list(ref["choice"].values)
        np.testing.assert_allclose(ds["tau_peak"].values[p], ref["tau_peak"].values, rtol=1e-12)
    zero = payload_sweep(puma, shipped, [0.0])
    data = np.isfinite(plain["share_tran"].values)
    np.testing.assert_allclose(zero["share_tran"].values[0][data],
                               plain["share_tran"].values[data], rtol=0, atol=1e-12)
    assert list(zero["dominance"].values[0]) == list(plain["dominance"].values)
    # a load changes the torques the arm needs
    assert np.any(np.abs(ds["tau_peak"].values[1] - ds["tau_peak"].values[0]) > 1e-3)
    for name, var in itertools.chain(ds.data_vars.items(), ds.coords.items()):
        assert "units" in var.attrs and "long_name" in var.attrs, name


def test_payload_matches_pinocchio_with_the_load_appended(puma):
    import pinocchio as pin

    from gd_analyze.dynamics.pinocchio import pinocchio_model

    m, com = 2.5, np.array([0.02, -0.03, 0.08])
    inertia = np.array([[4e-3, 2e-4, -1e-4], [2e-4, 5e-3, 3e-4], [-1e-4, 3e-4, 2e-3]])
    loaded = with_payload(puma, m, com, inertia)
    model = pinocchio_model(puma)
    a, d, alpha = puma.a[-1], puma.d[-1], puma.alpha[-1]
    c, s = np.cos(alpha), np.sin(alpha)
    frame_n = pin.SE3(np.array([[1, 0, 0], [0, c, -s], [0, s, c]]), np.array([a, 0.0, d]))
    model.appendBodyToJoint(model.njoints - 1, frame_n.act(pin.Inertia(m, com, inertia)),
                            pin.SE3.Identity())
    data = model.createData()
    q, qd, qdd = random_states(puma, 25, 41)
    ref = np.array([pin.rnea(model, data, a_, b_, c_) for a_, b_, c_ in zip(q, qd, qdd)])
    tau = gd_terms(loaded, q, qd).tau(qdd)
    np.testing.assert_allclose(tau, ref, rtol=0, atol=1e-10 * np.abs(ref).max())
    # and the bare arm differs from it: the test can fail
    bare = gd_terms(puma, q, qd).tau(qdd)
    assert np.abs(bare - ref).max() > 1e-3 * np.abs(ref).max()


def test_payload_sweep_rejects_bad_masses(puma, shipped):
    with pytest.raises(InputError):
        payload_sweep(puma, shipped, [])
    with pytest.raises(InputError, match="distinct"):
        payload_sweep(puma, shipped, [1.0, 1.0])
    with pytest.raises(InputError):
        payload_sweep(puma, shipped, [-1.0])
