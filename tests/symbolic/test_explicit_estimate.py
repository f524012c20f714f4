"""The term-count estimate of the explicit model, against the real expansion, and the limit
above which an explicit model asked for is refused."""

import pytest
import xarray as xr
from robot_files import random_chain

from gd_analyze.cli import main
from gd_analyze.model.robot_file import robot_toml
from gd_analyze.model.robots import load_robot
from gd_analyze.symbolic.explicit import derive, model_terms
from gd_analyze.symbolic.explicit_estimate import (
    ESTIMATE_FACTOR,
    EXPENSIVE_TERMS,
    MAX_TERMS,
    estimate_terms,
    is_expensive,
)


@pytest.mark.parametrize("name", ["two-link", "puma560", "stanford", "ur5"])
def test_estimate_within_the_stated_factor_of_the_real_count(name):
    robot = load_robot(name)
    real = len(model_terms(derive(robot)).kind)          # the expansion itself is the oracle
    estimate = estimate_terms(robot)
    assert isinstance(estimate, int)
    assert real / ESTIMATE_FACTOR <= estimate <= real * ESTIMATE_FACTOR, (real, estimate)
    assert not is_expensive(robot)


@pytest.mark.parametrize("n", [3, 4])
def test_estimate_of_small_random_chains_against_the_real_count(n):
    """Random chains (general placements, full inertia tensors): with revolute joints only the
    estimate is within :data:`ESTIMATE_FACTOR` of the real count both ways; with every third
    joint prismatic it is an upper bound (a prismatic joint is counted as a revolute one,
    though it brings powers 0..2 of q_i, not five harmonics), never below real /
    ESTIMATE_FACTOR either. The expansion itself is the oracle."""
    revolute = random_chain(n, seed=n, prismatic=False)
    real = len(model_terms(derive(revolute)).kind)
    assert real / ESTIMATE_FACTOR <= estimate_terms(revolute) <= real * ESTIMATE_FACTOR
    mixed = random_chain(n, seed=n)
    assert estimate_terms(mixed) >= len(model_terms(derive(mixed)).kind)


def test_the_panda_is_flagged_expensive_without_expanding():
    # its expansion has 418,774 terms (module docstring); the estimate must say so at once
    panda = load_robot("panda")
    assert estimate_terms(panda) > EXPENSIVE_TERMS * ESTIMATE_FACTOR
    assert is_expensive(panda)
    assert estimate_terms(panda) * ESTIMATE_FACTOR < MAX_TERMS       # always: still derived


def test_more_offsets_and_crossed_axes_never_shrink_the_estimate(puma):
    import dataclasses

    import numpy as np

    com = np.asarray(puma.com, float) + 0.01          # every centre of mass off its axes
    assert estimate_terms(dataclasses.replace(puma, com=com)) > estimate_terms(puma)


def _chain_files(folder, n, capsys):
    robot = random_chain(n, seed=1, prismatic=False)
    path = folder / f"random-{n}.toml"
    path.write_text(robot_toml(robot))
    code = main(["plan", str(path), "-o", str(folder / "plan.csv"), "--setpoints", "5"])
    assert code == 0, capsys.readouterr().err
    capsys.readouterr()
    return robot, path, folder / "plan.csv"


def _no_derivation(robot):
    raise AssertionError("the explicit model was derived")


@pytest.mark.parametrize("option", [["--explicit", "always"], ["--form", "explicit"]])
def test_a_random_12_joint_chain_asked_for_its_explicit_model_is_refused_in_one_line(
        tmp_path, capsys, monkeypatch, option):
    """Estimated at about 3e9 terms (its 5-joint start alone has 25,392): the main job exits
    2 before any work, with one line naming the estimate, the limit and the recursive form,
    writes nothing, and never starts the expansion (which ran 19 minutes on such an arm)."""
    import gd_analyze.store.explicit_cache as explicit_cache

    monkeypatch.setattr(explicit_cache, "derive", _no_derivation)
    robot, path, plan = _chain_files(tmp_path, 12, capsys)
    estimate = estimate_terms(robot)
    assert estimate > MAX_TERMS
    code = main([str(path), str(plan), "-o", str(tmp_path / "out"), "--no-report",
                 "--guarantee", "trajectory", *option])
    out, err = capsys.readouterr()
    assert code == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert f"{' '.join(option)}: the explicit model of random-12 is estimated at " \
           f"{estimate:,} terms, above the limit of {MAX_TERMS:,}: use the recursive form" in err
    assert ("--explicit never" if option[0] == "--explicit" else "--form recursive") in err
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
def test_auto_leaves_an_expensive_explicit_model_underived_and_says_so(tmp_path, capsys,
                                                                        monkeypatch):
    """A random 5-joint revolute chain, estimated above EXPENSIVE_TERMS: under --explicit auto
    the recursive model is deployed, the explicit model is not derived, and results.h5's
    form note names the estimate and the threshold."""
    import gd_analyze.store.explicit_cache as explicit_cache

    monkeypatch.setattr(explicit_cache, "derive", _no_derivation)
    robot, path, plan = _chain_files(tmp_path, 5, capsys)
    estimate = estimate_terms(robot)
    assert EXPENSIVE_TERMS < estimate < MAX_TERMS
    code = main([str(path), str(plan), "-o", str(tmp_path / "out"), "--no-report", "-q",
                 "--guarantee", "trajectory"])
    assert code == 0, capsys.readouterr().err
    with xr.open_dataset(tmp_path / "out" / "results.h5", engine="h5netcdf") as ds:
        assert ds.attrs["simplified_form"] == "recursive"
        note = ds.attrs["simplified_form_note"]
    assert "the explicit model was not derived" in note
    assert f"{estimate:,} estimated terms above the {EXPENSIVE_TERMS:,} of --explicit auto" in note
