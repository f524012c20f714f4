"""The model building keeps nothing itself: the derivation cache is what the jobs give it.

The oracle is the files: built with :data:`gd_analyze.simplify.region_memo.UNKEPT` (the
default), a region model leaves the cache folder empty; built with
:data:`gd_analyze.store.derivations.DERIVATIONS`, the folder holds the region's certification
and the search, and a second build reads the same dropped pairs back.
"""

import numpy as np

from gd_analyze import load_robot
from gd_analyze.certify.region import joint_region
from gd_analyze.simplify import deploy, region_memo
from gd_analyze.simplify.deploy import build_recursive
from gd_analyze.store.derivations import DERIVATIONS

EPS = 0.02


def _build(robot, region, **kw):
    z = np.zeros((2, robot.n))
    return build_recursive(robot, z, z, z, tolerance=EPS, region=region, **kw)[0]


def test_only_the_derivations_given_keep_anything(tmp_path, monkeypatch):
    robot = load_robot("stanford")
    region = joint_region(robot, robot.qdd_max)
    folder = tmp_path / "cache"
    monkeypatch.delenv("GD_ANALYZE_NO_CACHE", raising=False)
    monkeypatch.setenv("GD_ANALYZE_CACHE_DIR", str(folder))
    for memo in ("_CERTIFIED", "_SAMPLED", "_MAGNITUDES"):       # nothing from other tests
        monkeypatch.setattr(region_memo, memo, {})
    monkeypatch.setattr(deploy, "_SEARCHED", {})     # (a search of the arm an earlier test made)
    unkept = _build(robot, region)
    assert not folder.exists() or not any(folder.iterdir())

    monkeypatch.setattr(region_memo, "_CERTIFIED", {})          # certified again, and kept
    kept = _build(robot, region, derive=DERIVATIONS)
    names = sorted(p.name.split("-")[0] for p in folder.glob("*.npz"))
    assert "search" in names and len(names) >= 2, names
    np.testing.assert_array_equal(kept.recursive.dropped, unkept.recursive.dropped)

    def refuse(*args, **kwargs):
        raise AssertionError("searched again although the search was kept")
    monkeypatch.setattr(region_memo, "_CERTIFIED", {})
    monkeypatch.setattr(deploy, "_region_pruning", _only_chosen(deploy._region_pruning, refuse))
    again = _build(robot, region, derive=DERIVATIONS)
    np.testing.assert_array_equal(again.recursive.dropped, unkept.recursive.dropped)


def _only_chosen(original, refuse):
    """``_region_pruning`` that refuses a search from scratch (no ``chosen`` pairs)."""
    def pruning(base, pb, robot, region, tolerance, chosen=None):
        if chosen is None:
            refuse()
        return original(base, pb, robot, region, tolerance, chosen)
    return pruning
