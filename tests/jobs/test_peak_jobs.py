"""The simplification's peak passes started in threads: the same peaks as computed in line,
the explicit model derived only where it may be deployed."""

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest
from conftest import SHIPPED

from gd_analyze.dynamics.base_parameters import base_parameters, regressor
from gd_analyze.jobs.options import SimplifyOptions
from gd_analyze.jobs.peak_jobs import derives_explicit, proves_over_region, start_peaks
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
