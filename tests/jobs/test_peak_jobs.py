"""The simplification's peak passes started in threads: the same peaks as computed in line,
the explicit model derived only where it may be deployed."""

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest
from conftest import SHIPPED

from gd_analyze.dynamics.base_parameters import base_parameters, regressor
from gd_analyze.jobs.options import SimplifyOptions
from gd_analyze.jobs.peak_jobs import derives_explicit, proves_over_region, start_peaks
from gd_analyze.simplify.region_memo import UNKEPT
from gd_analyze.trajectory.trajectory import read_trajectory


@pytest.mark.parametrize("form, explicit, derived", [
    ("cheapest", "auto", True), ("recursive", "auto", False), ("recursive", "always", True),
    ("explicit", "never", True), ("cheapest", "never", False)])
def test_explicit_derived_only_where_it_may_be_deployed(puma, form, explicit, derived):
    assert derives_explicit(puma, SimplifyOptions(form=form, explicit=explicit)) is derived


@pytest.mark.parametrize("rule, guarantee, proved", [
    ("budget", "auto", True), ("budget", "region", True), ("budget", "trajectory", False),
    ("chapter", "auto", False)])
def test_a_model_proved_over_the_region_needs_no_trajectory_peaks(puma, rule, guarantee,
                                                                   proved):
    options = SimplifyOptions(rule=rule, guarantee=guarantee)
    assert proves_over_region(puma, options) is proved
    traj = read_trajectory(SHIPPED, puma.n)
    with ThreadPoolExecutor(max_workers=2) as pool:
        base, peaks = start_peaks(pool, puma, traj, options)["recursive"].result()
    assert base.names() == base_parameters(puma).names()
    assert (peaks is None) is proved


def test_no_region_without_limits(puma):
    import dataclasses

    bare = dataclasses.replace(puma, qd_max=np.full(puma.n, np.nan))
    assert not proves_over_region(bare, SimplifyOptions())


def test_threaded_peaks_are_the_peaks_of_the_numpy_regressor(puma):
    """The recursive job's peaks against the numpy regressor (independent code) on the
    shipped trajectory; the explicit job's atom peaks make up at least the joint torques'."""
    traj = read_trajectory(SHIPPED, puma.n)
    with ThreadPoolExecutor(max_workers=2) as pool:
        jobs = start_peaks(pool, puma, traj, SimplifyOptions(guarantee="trajectory"))
        base, (tau_peak, peak, whole) = jobs["recursive"].result()
        terms, term = jobs["explicit"].result()
    assert base.names() == base_parameters(puma).names()
    cols = base.independent.reshape(-1)
    zero = np.zeros_like(traj.q)
    C = np.stack([regressor(puma, traj.q, b, c, gravity=g)[:, :, cols] * base.beta
                  for b, c, g in ((zero, traj.qdd, np.zeros(3)), (traj.qd, zero, np.zeros(3)),
                                  (zero, zero, None))])
    np.testing.assert_allclose(peak, np.abs(C).max(axis=1).transpose(2, 0, 1), rtol=1e-12,
                               atol=1e-14 * tau_peak.max())
    np.testing.assert_allclose(whole, np.abs(C.sum(axis=0)).max(axis=0).T, rtol=1e-12,
                               atol=1e-14 * tau_peak.max())
    np.testing.assert_allclose(tau_peak, np.abs(C.sum(axis=(0, 3))).max(axis=0), rtol=1e-12)
    # triangle inequality: each joint's peak |tau| is at most the sum of its atoms' peaks
    assert np.all(tau_peak <= term.sum(axis=0) * (1 + 1e-12))


@pytest.mark.parametrize("floor", [0.0, 1.0])
def test_the_region_searches_made_beside_the_pass_are_those_made_after_it(puma, floor,
                                                                          monkeypatch):
    """Under the budget rule with a region, the region's searches start beside the pass (no
    trajectory needed) and find what the deployment's own calls find, at the model's EPS and
    at every other rung of the ladder; the torque floor's second choice is made too. Below
    REGION_BESIDE_SETPOINTS set points the deployment makes them itself."""
    from gd_analyze.jobs import peak_jobs
    from gd_analyze.simplify.deploy import _floor_zero_choice, guarantee_region, region_search
    from gd_analyze.simplify.explicit_model import LADDER

    options = SimplifyOptions(torque_floor=floor)
    traj = read_trajectory(SHIPPED, puma.n)
    with ThreadPoolExecutor(max_workers=2) as pool:
        assert "region" not in start_peaks(pool, puma, traj, options)
        monkeypatch.setattr(peak_jobs, "REGION_BESIDE_SETPOINTS", traj.q.shape[0])
        jobs = start_peaks(pool, puma, traj, options)
        searches = jobs["region"].result()
    base = base_parameters(puma)
    region = guarantee_region(puma, options.guarantee, options.region)[0]
    own = region_search(puma, base, region, options.tolerance, floor)
    assert searches.found.screen is None and own.screen is None
    np.testing.assert_array_equal(searches.found.rec.dropped, own.rec.dropped)
    assert sorted(searches.rungs) == sorted(e for e in LADDER if e != options.tolerance)
    for eps, rung in searches.rungs.items():
        np.testing.assert_array_equal(
            rung.rec.dropped,
            region_search(puma, base, region, eps, floor, sampled=False).rec.dropped)
    if floor == 0:
        assert searches.floor_zero is None
    else:
        zero = _floor_zero_choice(puma, base, region, options.tolerance, floor, UNKEPT)
        np.testing.assert_array_equal(searches.floor_zero.rec.dropped, zero.rec.dropped)


def test_no_region_searches_for_a_trajectory_guarantee_and_errors_reach_the_caller(
        puma, monkeypatch):
    import threading

    from gd_analyze.jobs import peak_jobs

    traj = read_trajectory(SHIPPED, puma.n)
    seen = []

    def fails(*args):
        seen.append(threading.current_thread())
        raise ValueError("made to fail")

    monkeypatch.setattr(peak_jobs, "region_searches", fails)
    monkeypatch.setattr(peak_jobs, "REGION_BESIDE_SETPOINTS", 1)
    with ThreadPoolExecutor(max_workers=2) as pool:
        assert "region" not in start_peaks(pool, puma, traj,
                                           SimplifyOptions(guarantee="trajectory"))
        job = start_peaks(pool, puma, traj, SimplifyOptions())["region"]
        with pytest.raises(ValueError, match="made to fail"):
            job.result()
    # its own daemon thread: an interrupted run does not wait for the certification
    assert seen[0].daemon and seen[0] is not threading.main_thread()
