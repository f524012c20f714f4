"""The region model's searches in the derivation cache: used only when they pass their checks.

The oracle is the model searched afresh (no entry): a used entry must give the same dropped
pairs and the same programs; an entry forged with a matching key and checksum but dropped
pairs over the budget, or forms that are no forms, must be refused with one warning line and
the model searched again; valid forms other than the searched ones give the same torques
(the programs are built from the entry's choices, so an entry cannot make the model err).
"""

import warnings

import numpy as np
import pytest
from cache_checks import forge

from gd_analyze import load_robot
from gd_analyze.cache import CacheWarning, entry_path
from gd_analyze.certify.region import joint_region
from gd_analyze.dynamics.base_parameters import random_states
from gd_analyze.files import package_sha256
from gd_analyze.simplify import deploy as deploy_module
from gd_analyze.simplify.deploy import REGION_SAMPLES, build_recursive, guarantee_region
from gd_analyze.store.certification_cache import SEARCH_FIELDS, search_key
from gd_analyze.store.derivations import DERIVATIONS
from gd_analyze.symbolic import recursive as recursive_module
from gd_analyze.symbolic.newton_euler import FORMS

EPS = 0.02


@pytest.fixture(scope="module")
def arm():
    robot = load_robot("stanford")              # six joints, one prismatic
    return robot, joint_region(robot, robot.qdd_max)


def _build(arm):
    robot, region = arm
    z = np.zeros((2, robot.n))
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        model, _ = build_recursive(robot, z, z, z, tolerance=EPS, region=region,
                                   derive=DERIVATIONS)
    return model, [str(w.message) for w in seen if issubclass(w.category, CacheWarning)]


@pytest.fixture(scope="module")
def fresh(arm, tmp_path_factory):
    """The model searched with no entry (its own empty cache folder)."""
    with pytest.MonkeyPatch.context() as mp:
        mp.delenv("GD_ANALYZE_NO_CACHE", raising=False)
        mp.setenv("GD_ANALYZE_CACHE_DIR", str(tmp_path_factory.mktemp("search-fresh")))
        model, seen = _build(arm)
    assert not seen
    return model


def _entry(folder):
    (path,) = folder.glob("search-*.npz")
    return path


def _forge(path, **change):
    forge(path, SEARCH_FIELDS, **change)


def _torques(model, robot):
    q, qd, qdd = random_states(robot, 50, seed=3)
    return model.functions().numpy()["tau"](q, qd, qdd)


def _count_builds(monkeypatch):
    """Count the programs built from here on; the programs this process built before are
    forgotten (:data:`gd_analyze.symbolic.recursive.PROGRAMS`), so each is built again."""
    recursive_module.PROGRAMS.clear()
    recursive_module.COUNTS.clear()
    built = []
    finish = recursive_module._finish

    def counted(*args, **kwargs):
        built.append(1)
        return finish(*args, **kwargs)
    monkeypatch.setattr(recursive_module, "_finish", counted)
    return built


def test_a_stored_search_is_used_and_gives_the_searched_model(arm, fresh, cache, monkeypatch):
    first, w1 = _build(arm)
    assert not w1 and _entry(cache).is_file()
    built = _count_builds(monkeypatch)
    second, w2 = _build(arm)
    assert not w2
    # the exact and the pruned program, and the proved screen's quick counts of the exact
    # model and of the stored set (certify.screen.proved_screen): no search, which counts
    # every candidate it compares
    assert len(built) <= 4
    for model in (first, second):
        np.testing.assert_array_equal(model.recursive.dropped, fresh.recursive.dropped)
        np.testing.assert_array_equal(model.bound, fresh.bound)
        assert model.cost == fresh.cost
        assert model.costs["exact recursive"] == fresh.costs["exact recursive"]
        assert model.choice_cache[0].forms == fresh.choice_cache[0].forms
        assert [str(e) for e in model.program().outputs] == \
            [str(e) for e in fresh.program().outputs]


def test_dropped_pairs_over_the_budget_are_refused(arm, fresh, cache):
    _build(arm)
    path = _entry(cache)
    with np.load(path) as z:
        dropped = np.ones_like(z["dropped"])
    _forge(path, dropped=dropped, whole=np.ones(dropped.shape[0], bool))
    model, seen = _build(arm)
    assert len(seen) == 1 and "over the budget" in seen[0] and str(path) in seen[0]
    np.testing.assert_array_equal(model.recursive.dropped, fresh.recursive.dropped)
    assert model.cost == fresh.cost
    assert not _build(arm)[1]                   # rewritten: sound again


@pytest.mark.parametrize("change", ["index", "shape", "type"])
def test_forms_that_are_no_forms_are_refused(arm, fresh, cache, change):
    robot, _ = arm
    _build(arm)
    path = _entry(cache)
    bad = {"index": np.full(robot.n, len(FORMS), np.int64),
           "shape": np.zeros(robot.n + 1, np.int64),
           "type": np.zeros(robot.n, float)}[change]
    _forge(path, exact_forms=bad)
    model, seen = _build(arm)
    assert len(seen) == 1 and str(path) in seen[0], seen
    assert model.cost == fresh.cost


def test_other_valid_forms_change_the_cost_never_the_torques(arm, fresh, cache):
    """A forged entry with every link in another form: the programs are built with those
    forms (so the count may differ), and compute the same torques as the searched model."""
    robot, _ = arm
    _build(arm)
    path = _entry(cache)
    with np.load(path) as z:
        pruned = z["pruned_forms"]
    other = np.full(robot.n, FORMS.index("direct"), np.int64)
    _forge(path, exact_forms=other, pruned_forms=other if (pruned >= 0).all() else pruned)
    model, seen = _build(arm)
    assert not seen
    np.testing.assert_array_equal(model.recursive.dropped, fresh.recursive.dropped)
    if (pruned >= 0).all():
        assert model.choice_cache[0].forms == ("direct",) * robot.n
    tau, ref = _torques(model, robot), _torques(fresh, robot)
    scale = np.abs(ref).max(axis=0)
    assert np.all(np.abs(tau - ref) <= 1e-9 * scale)


def test_the_key_names_the_tolerance_and_the_searching_code(arm):
    robot, region = arm
    a = search_key(robot, region, EPS, 0.0, REGION_SAMPLES)
    assert a != search_key(robot, region, 2 * EPS, 0.0, REGION_SAMPLES)
    assert a != search_key(robot, region, EPS, 1.0, REGION_SAMPLES)
    assert a["kind"] == "search"
    assert a["code"]["sha256"] == package_sha256()


@pytest.fixture(scope="module")
def puma():
    """The PUMA 560 over its joint-limit region: at EPS 0 the sampled pre-screen chooses the
    exact model (the pairs proved identically zero left out), with no certification."""
    robot = load_robot("puma560")
    return robot, guarantee_region(robot)[0]


def _screened(puma, monkeypatch):
    """The model at EPS 0, this process's searches forgotten (so the entry is read) and the
    programs built with common subexpressions counted (the forms' search builds them)."""
    monkeypatch.setattr(deploy_module, "_SEARCHED", {})
    recursive_module.PROGRAMS.clear()
    built = []
    finish = recursive_module._finish

    def counted(rec, tau, cse):
        built.append(cse)
        return finish(rec, tau, cse)
    monkeypatch.setattr(recursive_module, "_finish", counted)
    robot, region = puma
    z = np.zeros((2, robot.n))
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        model, _ = build_recursive(robot, z, z, z, tolerance=0.0, region=region,
                                   derive=DERIVATIONS)
    return model, [str(w.message) for w in seen if issubclass(w.category, CacheWarning)], \
        sum(built)


def _same_model(model, other):
    np.testing.assert_array_equal(model.recursive.dropped, other.recursive.dropped)
    assert model.cost == other.cost and model.costs == other.costs
    assert model.choice_cache[0].forms == other.choice_cache[0].forms
    assert model.choice_cache[2].forms == other.choice_cache[2].forms
    assert [str(e) for e in model.program().outputs] == \
        [str(e) for e in other.program().outputs]
    assert model.provenance["region_screen"] == other.provenance["region_screen"]


def test_the_pre_screen_s_exact_model_keeps_its_programs_forms(puma, cache, monkeypatch):
    """The exact model the sampled pre-screen chose is no search, but its two programs' forms
    are searched (1 + 2n programs each): they are kept in an entry of its own, from which the
    next run builds the same two programs without searching; the model stays the
    pre-screen's (the entry is not a search's)."""
    robot, region = puma
    first, seen, searched = _screened(puma, monkeypatch)
    assert not seen and not first.provenance["region_screen"]["proved"]
    assert searched >= 2 * (1 + 2 * robot.n) - 1       # the pruned and the exact program's
    path = _entry(cache)
    key = search_key(robot, region, 0.0, 0.0, REGION_SAMPLES, screened=True)
    assert key != search_key(robot, region, 0.0, 0.0, REGION_SAMPLES)
    assert str(path) == str(entry_path(key))
    second, seen, searched = _screened(puma, monkeypatch)
    assert not seen and searched == 2
    _same_model(second, first)


def test_a_screened_entry_of_other_pairs_is_refused(puma, cache, monkeypatch):
    first, _, _ = _screened(puma, monkeypatch)
    path = _entry(cache)
    with np.load(path) as z:
        dropped = ~z["dropped"]
    _forge(path, dropped=dropped)
    model, seen, searched = _screened(puma, monkeypatch)
    assert len(seen) == 1 and "proved identically zero" in seen[0] and str(path) in seen[0]
    assert searched > 2
    _same_model(model, first)
    assert _screened(puma, monkeypatch)[1:] == ([], 2)      # rewritten: used again
