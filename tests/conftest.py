"""Shared fixtures: the built-in robots, random states, the shipped trajectory."""

from pathlib import Path

import numpy as np
import pytest

from gd_analyze import load_robot

ROOT = Path(__file__).resolve().parents[1]
SHIPPED = ROOT / "data" / "puma560_trajectory.csv"


@pytest.fixture(scope="session")
def puma():
    return load_robot("puma560")


@pytest.fixture(scope="session")
def two_link():
    return load_robot("two-link")


@pytest.fixture(scope="module")
def cluster():
    """A dask LocalCluster of 2 worker processes and its client, for the sweep tests."""
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None,
                                  scheduler_kwargs={"dashboard_address": "127.0.0.1:0"}) as cl:
        with distributed.Client(cl) as client:
            yield cl, client


@pytest.fixture(scope="session")
def mixed(puma, shipped):
    """PUMA 560 trajectories whose joint scales differ by orders of magnitude: fast random
    moves, the shipped trajectory and a slow small move."""
    from gd_analyze.io.planning import plan_quintic, random_trajectories

    slow = plan_quintic(puma, np.radians([0, 45, -90, 0, 30, 0]),
                        np.radians([2, 46, -89, 1, 31, 1]), duration=4.0)
    return [*random_trajectories(puma, 3, seed=11), shipped, slow]


@pytest.fixture(scope="session")
def shipped():
    """The shipped PUMA 560 trajectory (31 set points), read from its CSV file."""
    from gd_analyze.io.trajectory import read_trajectory

    return read_trajectory(SHIPPED, n_joints=6)


@pytest.fixture(scope="session")
def shipped_dataset(tmp_path_factory):
    """The stored dataset of a built-in robot's shipped trajectory, by robot name.

    A function of the name: the main analysis (without the formulations) written by
    ``analyze_to_file`` and read back from its results.h5, loaded; one analysis per robot a
    session. Shared: tests must not modify it. The model is pruned on the trajectory
    (``guarantee="trajectory"``), so that the figures and tables have errors to draw on every
    arm (the UR5's region model drops nothing).
    """
    from gd_analyze.io.schema import open_results
    from gd_analyze.io.trajectory import read_trajectory
    from gd_analyze.workflows.analyze import analyze_to_file
    from gd_analyze.workflows.options import AnalysisOptions, SimplifyOptions

    stored = {}

    def get(name):
        if name not in stored:
            robot = load_robot(name)
            traj = read_trajectory(ROOT / "data" / f"{name}_trajectory.csv", robot.n)
            path = tmp_path_factory.mktemp(name) / "results.h5"
            options = AnalysisOptions(formulations=False,
                                      simplify=SimplifyOptions(guarantee="trajectory"))
            analyze_to_file(robot, traj, path, options)
            with open_results(path, lazy=True) as ds:
                stored[name] = ds.load()
        return stored[name]
    return get


def random_states(robot, count, seed):
    """Random (q, qd, qdd), shape (count, n): q within [-pi, pi], qd, qdd within +-3."""
    rng = np.random.default_rng(seed)
    n = robot.n
    return (rng.uniform(-np.pi, np.pi, (count, n)), rng.uniform(-3, 3, (count, n)),
            rng.uniform(-3, 3, (count, n)))


def two_link_control(folder, setpoints):
    """Plan a two-link trajectory of ``setpoints`` set points, build its simplified model
    (main job, no report) and run the control command on it, in ``folder``; the control
    dataset, loaded."""
    import xarray as xr

    from gd_analyze.cli import main

    csv = folder / "two.csv"
    assert main(["plan", "two-link", "-o", str(csv), "--setpoints", str(setpoints)]) == 0
    assert main(["two-link", str(csv), "-o", str(folder / "main"), "-q", "--no-report"]) == 0
    assert main(["control", str(folder / "main" / "simplified_model.json"), str(csv),
                 "-o", str(folder / "control"), "-q"]) == 0
    with xr.open_dataset(folder / "control" / "control.h5") as ds:
        return ds.load()


def pytest_configure(config):
    """Tests always count operations afresh (no on-disk cache of the counts)."""
    import os

    os.environ["GD_ANALYZE_NO_CACHE"] = "1"
