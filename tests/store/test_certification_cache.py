"""The region certification in the derivation cache: used only when it passes its checks.

The oracle is a fresh certification (certify.certify.certify): an entry that is used
must give exactly its bounds and scale; an entry forged with a matching key and checksum but a
wrong scale or scale state must be refused with one warning line and certified again. No bound
is read from an entry: the forged boxes and bounds (zero-volume boxes at
the samples, honest boxes with their bounds lowered to the sampled peaks, overlapping boxes
whose volumes add up to the region's) are refused or re-derived, never used.
"""

import os
import warnings

import numpy as np
import pytest
from cache_checks import forge

from gd_analyze import load_robot
from gd_analyze.cache import CacheWarning
from gd_analyze.certify import certify as certify_module
from gd_analyze.certify.certify import pair_peaks_at
from gd_analyze.certify.region import channel_values, joint_region, sample_positions
from gd_analyze.dynamics.base_parameters import base_parameters
from gd_analyze.simplify import region_memo
from gd_analyze.store import certification_cache as cache_module
from gd_analyze.store.certification_cache import certification

SAMPLES = 200
FIELDS = ("scale", "scale_state", "boxes", "seconds", "split_joint", "split_at", "witness",
          "leaves_sha256")
#: The layout of format 1, which stored the boxes and their bounds.
OLD_FIELDS = ("scale", "scale_state", "leaves", "leaf_boxes", "boxes", "seconds")


@pytest.fixture(scope="module")
def arm():
    robot = load_robot("stanford")              # six joints, one prismatic
    return robot, base_parameters(robot), joint_region(robot, robot.qdd_max)


@pytest.fixture(scope="module")
def fresh(arm):
    robot, base, region = arm
    return certify_module.certify(robot, base, region, samples=SAMPLES)


@pytest.fixture(scope="module")
def stored(arm, tmp_path_factory):
    """The entry a certification writes, as (file name, bytes): the tests that damage an
    entry start from a copy of it instead of certifying once more each."""
    folder = tmp_path_factory.mktemp("cache")
    with pytest.MonkeyPatch.context() as mp:
        mp.delenv("GD_ANALYZE_NO_CACHE", raising=False)
        mp.setenv("GD_ANALYZE_CACHE_DIR", str(folder))
        _, seen = _call(arm)
    assert not seen
    path = _entry(folder)
    return path.name, path.read_bytes()


def _store(cache, stored):
    """The written entry, copied into this test's own cache folder; its path."""
    cache.mkdir(parents=True, exist_ok=True)
    path = cache / stored[0]
    path.write_bytes(stored[1])
    return path


def _call(arm):
    robot, base, region = arm
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        pb = certification(robot, base, region, samples=SAMPLES)
    return pb, [str(w.message) for w in seen if issubclass(w.category, CacheWarning)]


def _same(a, b):
    for f in ("bound", "sampled", "scale", "scale_state", "leaves", "leaf_boxes", "positions",
              "split_joint", "split_at"):
        np.testing.assert_array_equal(getattr(a, f), getattr(b, f), err_msg=f)


def _entry(folder):
    (path,) = folder.glob("region-*.npz")
    return path


def _forge(path, **change):
    forge(path, FIELDS, **change)


def test_a_stored_certification_is_used_and_equals_a_fresh_one(arm, fresh, cache, monkeypatch):
    first, w1 = _call(arm)
    _same(first, fresh)
    assert not w1 and _entry(cache).is_file()

    def refuse(*args, **kwargs):
        raise AssertionError("sampled and searched again although the entry is sound")
    monkeypatch.setattr(certify_module, "region_samples", refuse)     # the scale's search
    second, w2 = _call(arm)
    assert not w2
    _same(second, fresh)
    assert second.seconds == first.seconds


def test_samples_drawn_by_the_caller_give_a_fresh_certification_s_bounds(arm, fresh, cache,
                                                                          monkeypatch):
    """Positions, channel values and peaks drawn by the caller (``drawn``): a certification
    computed afresh and one read back from its entry both equal certify's, and the read-back
    draws nothing again."""
    robot, base, region = arm
    q = sample_positions(region, SAMPLES)
    V = channel_values(robot, q, np.flatnonzero(base.independent.reshape(-1)))
    drawn = (q, V, pair_peaks_at(V, np.asarray(base.beta, float), region.qd_max,
                                 region.qdd_max))
    first = certification(robot, base, region, samples=SAMPLES, drawn=drawn)
    _same(first, fresh)
    np.testing.assert_array_equal(first.bound, fresh.bound)

    def refuse(*args, **kwargs):
        raise AssertionError("drawn again although the caller drew them")
    for name in ("sample_positions", "channel_values"):
        monkeypatch.setattr(cache_module, name, refuse)
    monkeypatch.setattr(region_memo, "region_scale", refuse)
    monkeypatch.setattr(certify_module, "region_samples", refuse)
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        second = certification(robot, base, region, samples=SAMPLES, drawn=drawn)
    assert not [w for w in seen if issubclass(w.category, CacheWarning)]
    _same(second, fresh)
    assert second.seconds == first.seconds


@pytest.mark.slow
@pytest.mark.parametrize("damage", ["scale doubled", "scale state moved", "scale halved",
                                    "boxes zero"])
def test_a_forged_entry_is_refused_and_certified_again(arm, fresh, cache, stored, damage):
    path = _store(cache, stored)
    with np.load(path, allow_pickle=False) as z:
        scale, state = z["scale"], z["scale_state"]
    if damage == "scale doubled":
        change = {"scale": scale * 2}
    elif damage == "scale halved":
        change = {"scale": scale * 0.5}
    elif damage == "scale state moved":
        moved = state.copy()
        moved[:, 1] = 0.5 * (moved[:, 1] + arm[2].q_min[1])
        change = {"scale_state": moved}
    else:
        change = {"boxes": np.array(0, np.int64)}
    _forge(path, **change)
    again, seen = _call(arm)
    assert len(seen) == 1 and "ignored, the region is certified again" in seen[0], seen
    _same(again, fresh)
    third, seen3 = _call(arm)                        # rewritten: used without a warning
    assert not seen3
    _same(third, fresh)


def _issue_forgeries(fresh, region):
    """The module docstring's forged boxes and bounds, as (leaves (b, 3, L, n), boxes (L, 2, n))."""
    from gd_analyze.certify.certify import pair_magnitudes_at

    beta = np.asarray(base_parameters(load_robot("stanford")).beta, float)
    at = pair_magnitudes_at(fresh.values, beta, region.qd_max, region.qdd_max)   # (B, b, 3, n)
    q = fresh.positions
    points = (at.transpose(1, 2, 0, 3), np.stack([q, q], axis=1))   # zero volume at samples
    lowered = (np.minimum(fresh.leaves, fresh.sampled[:, :, None, :]), fresh.leaf_boxes)
    half = np.stack([region.q_min, region.q_max])
    half[1, 1] = 0.5 * (region.q_min[1] + region.q_max[1])           # joint 2's lower half
    peaks = np.repeat(fresh.sampled[:, :, None, :], 2, axis=2)
    overlapping = (peaks, np.stack([half, half]))                    # twice: volume 1
    return {"zero-volume boxes at the samples": points,
            "bounds lowered to the sampled peaks": lowered,
            "overlapping boxes of the region's volume": overlapping}


@pytest.mark.slow
@pytest.mark.parametrize("forgery", ["zero-volume boxes at the samples",
                                     "bounds lowered to the sampled peaks",
                                     "overlapping boxes of the region's volume"])
@pytest.mark.parametrize("layout", [OLD_FIELDS, FIELDS + ("leaves", "leaf_boxes")])
def test_forged_boxes_and_bounds_are_never_used(arm, fresh, cache, stored, forgery,
                                                        layout):
    """Written into an entry with a checksum over the former layout (boxes and bounds
    included) or over this one with the arrays added: the bound stated is a fresh
    certification's, never the forged one (which is below it)."""
    robot, base, region = arm
    leaves, boxes = _issue_forgeries(fresh, region)[forgery]
    assert (leaves.max(axis=2) < fresh.bound * (1 - 1e-6)).any()   # the forgery claims less
    path = _store(cache, stored)
    forge(path, layout, leaves=leaves, leaf_boxes=boxes)
    again, seen = _call(arm)
    assert len(seen) <= 1 and all("ignored, the region is certified again" in w for w in seen)
    _same(again, fresh)
    assert np.all(again.bound >= fresh.bound)


@pytest.mark.parametrize("kind", ["symlink", "fifo", "garbage", "checksum"])
def test_an_unusable_file_is_one_warning_and_never_followed(arm, fresh, cache, stored, tmp_path,
                                                           kind):
    path = _store(cache, stored)
    target = tmp_path / "elsewhere.npz"
    if kind == "symlink":
        os.replace(path, target)
        os.symlink(target, path)
    elif kind == "fifo":
        path.unlink()
        os.mkfifo(path)                              # opening it must not block
    elif kind == "garbage":
        path.write_bytes(b"\x93NUMPY" + b"\x00" * 100)
    else:
        with np.load(path, allow_pickle=False) as z:
            entry = {name: z[name] for name in z.files}
        entry["scale"] = entry["scale"] * 0.5        # the checksum no longer matches
        with open(path, "wb") as fh:
            np.savez(fh, **entry)
    again, seen = _call(arm)
    assert len(seen) == 1, seen
    _same(again, fresh)
    if kind == "symlink":
        assert not path.is_symlink() and target.is_file()     # replaced, target untouched


def test_no_cache_writes_nothing(arm, fresh, tmp_path, monkeypatch):
    monkeypatch.setenv("GD_ANALYZE_NO_CACHE", "1")
    monkeypatch.setenv("GD_ANALYZE_CACHE_DIR", str(tmp_path / "cache"))
    pb, seen = _call(arm)
    _same(pb, fresh)
    assert not seen and not (tmp_path / "cache").exists()


def _tree_forgeries(fresh, region):
    """Trees of boxes that do not tile the region, each as (split_joint, split_at)."""
    joint, at = fresh.split_joint.copy(), fresh.split_at.copy()
    first = int(np.flatnonzero(joint >= 0)[0])                     # the root's cut
    d = int(joint[first])
    edge = at.copy()
    edge[first] = region.q_min[d]                                  # a box of zero volume
    outside = at.copy()
    outside[first] = region.q_max[d] + 1.0                         # overlapping halves
    cut = joint.copy()
    cut[first] = -1                                                # the root's cut removed
    leaf = int(np.flatnonzero(joint < 0)[0])
    deeper, deeper_at = joint.copy(), at.copy()
    deeper[leaf] = d                                               # a final box cut, no
    deeper_at[leaf] = 0.5 * (fresh.leaf_boxes[0, 0, d] + fresh.leaf_boxes[0, 1, d])  # children
    return {"cut at the region's edge (zero volume)": (joint, edge),
            "cut outside the box (overlap)": (joint, outside),
            "tree ends early (region not covered)": (joint[:-1], at[:-1]),
            "entries of boxes it does not have": (cut, at),
            "a final box cut without its children": (deeper, deeper_at),
            "a joint the arm does not have": (np.where(joint >= 0, 99, joint), at)}


@pytest.mark.slow
@pytest.mark.parametrize("forgery", ["cut at the region's edge (zero volume)",
                                     "cut outside the box (overlap)",
                                     "tree ends early (region not covered)",
                                     "entries of boxes it does not have",
                                     "a final box cut without its children",
                                     "a joint the arm does not have"])
def test_a_tree_of_boxes_that_does_not_tile_the_region_is_refused(arm, fresh, cache, stored,
                                                                  forgery):
    """The oracle: a fresh certification; a forged tree (key and checksum matching) gives one
    warning and the fresh bounds, never bounds over boxes that miss part of the region."""
    joint, at = _tree_forgeries(fresh, arm[2])[forgery]
    path = _store(cache, stored)
    _forge(path, split_joint=np.asarray(joint, np.int64), split_at=np.asarray(at, float),
           boxes=np.array(len(joint), np.int64))
    again, seen = _call(arm)
    assert len(seen) == 1 and "tree of boxes" in seen[0], seen
    _same(again, fresh)


def test_the_tree_read_back_is_derived_without_search(arm, fresh, cache, stored, monkeypatch):
    """A sound entry is derived on its stored tree: no box is bisected (no search), and the
    bounds are a fresh certification's bit for bit."""
    _store(cache, stored)

    def refuse(*args, **kwargs):
        raise AssertionError("searched again although the entry is sound")
    monkeypatch.setattr(certify_module, "_bisect", refuse)
    again, seen = _call(arm)
    assert not seen
    _same(again, fresh)
    assert again.boxes == fresh.boxes == fresh.split_joint.size


def _witness_forgeries(fresh, stored_witness):
    """Witnesses that do not name every (box, link) enclosure the bounds come from, or are
    not one flag per box and joint."""
    w = stored_witness.copy()
    named = np.flatnonzero(w[:, 3])                  # the boxes link 4's bounds come from
    fewer = w.copy()
    fewer[named[-1], 3] = False                      # one of them left out
    none = np.zeros_like(w)
    return {"a witness left out": fewer,
            "no witness at all": none,
            "witnesses of another shape": w[:-1],
            "witnesses of another type": w.astype(np.int64)}


@pytest.mark.slow
@pytest.mark.parametrize("forgery", ["a witness left out", "no witness at all",
                                     "witnesses of another shape",
                                     "witnesses of another type"])
def test_witnesses_that_do_not_give_the_stored_bounds_are_refused(arm, fresh, cache, stored,
                                                                  forgery):
    """The oracle: a fresh certification. The witnesses only say which enclosures to
    evaluate; with one left out (key and checksum matching) the bounds derived are larger
    than the ones the entry was stored with, so the entry is refused with one warning and
    certified again, never used with other bounds than a fresh certification's."""
    path = _store(cache, stored)
    with np.load(path, allow_pickle=False) as z:
        witness = z["witness"]
    _forge(path, witness=_witness_forgeries(fresh, witness)[forgery])
    again, seen = _call(arm)
    assert len(seen) == 1 and "ignored, the region is certified again" in seen[0], seen
    assert "witness" in seen[0], seen
    _same(again, fresh)


@pytest.mark.slow
def test_a_digest_of_other_bounds_is_refused(arm, fresh, cache, stored):
    """An entry whose digest is of other final-box bounds (a certification with a bound
    lowered) is refused: its bounds, derived again, are not those it claims."""
    path = _store(cache, stored)
    lowered = fresh.leaves.copy()
    lowered[np.unravel_index(np.argmax(lowered), lowered.shape)] *= 0.5
    _forge(path, leaves_sha256=np.array(cache_module.leaves_sha256(lowered)))
    again, seen = _call(arm)
    assert len(seen) == 1 and "witnesses" in seen[0], seen
    _same(again, fresh)


def test_the_read_back_evaluates_only_the_witnessed_enclosures(arm, fresh, cache, stored,
                                                               monkeypatch):
    """A sound entry is read back evaluating the (box, link) enclosures its witnesses name,
    fewer than the tree's boxes times its links, and gives a fresh certification's bounds
    bit for bit."""
    _store(cache, stored)
    calls = []
    real = certify_module.pair_magnitudes

    def counted(robot, lo, *args, **kwargs):
        calls.append(lo.shape[0])
        return real(robot, lo, *args, **kwargs)
    monkeypatch.setattr(certify_module, "pair_magnitudes", counted)
    again, seen = _call(arm)
    assert not seen
    _same(again, fresh)
    links = np.unique(np.flatnonzero(arm[1].independent.reshape(-1)) // 10).size
    assert sum(calls) == fresh.witness.sum() < fresh.boxes * links
