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


def random_states(robot, count, seed):
    """Random (q, qd, qdd), shape (count, n): q within [-pi, pi], qd, qdd within +-3."""
    rng = np.random.default_rng(seed)
    n = robot.n
    return (rng.uniform(-np.pi, np.pi, (count, n)), rng.uniform(-3, 3, (count, n)),
            rng.uniform(-3, 3, (count, n)))


def pytest_configure(config):
    """Tests always count operations afresh (no on-disk cache of the counts)."""
    import os

    os.environ["GD_ANALYZE_NO_CACHE"] = "1"
