"""The operation-count cache is never trusted blindly."""

import json
import os
import stat
import warnings

import numpy as np
import pytest
from cache_checks import forge

from gd_analyze.dynamics import opcount
from gd_analyze.errors import InputWarning


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """A fresh count of "RRR" (measured without a cache) and the cache file's path."""
    monkeypatch.setenv("GD_ANALYZE_NO_CACHE", "1")
    opcount._counts_for.cache_clear()
    fresh = opcount._counts_for("RRR")
    monkeypatch.delenv("GD_ANALYZE_NO_CACHE")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    opcount._counts_for.cache_clear()
    path = opcount._cache_file("RRR")
    path.parent.mkdir(parents=True)
    yield fresh, path
    opcount._counts_for.cache_clear()


def _counts_with_warnings():
    opcount._counts_for.cache_clear()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        counts = opcount._counts_for("RRR")
    return counts, [str(w.message) for w in caught if issubclass(w.category, InputWarning)]


@pytest.mark.parametrize("planted", [
    {"3": {"lagrange-euler": [1, 1], "newton-euler": [1, 1], "gd": [1, 1],
           "gd-numpy": [1, 1]}},                               # "Newton-Euler: 1", as measured
    {"3": 5}, [], "x", {"format": 2, "entries": {"3": 7}}])   # JSON, not an entry
def test_an_edited_or_wrong_file_is_counted_again_with_one_warning(cache, planted):
    fresh, path = cache
    path.write_text(json.dumps(planted))
    counts, warned = _counts_with_warnings()
    assert counts == fresh
    assert len(warned) == 1 and "\n" not in warned[0] and "counted again" in warned[0]
    assert str(path) in warned[0]
    counts, warned = _counts_with_warnings()                 # stored again, whole: no warning
    assert counts == fresh and warned == []


def _stored(path):
    with np.load(path, allow_pickle=False) as z:
        return {name: z[name] for name in z.files}


def test_an_entry_edited_without_its_checksum_is_counted_again(cache):
    fresh, path = cache
    assert _counts_with_warnings() == (fresh, [])            # written
    entry = _stored(path)
    entry["counts"][opcount.METHODS.index("newton-euler")] = [1, 1]
    with open(path, "wb") as fh:
        np.savez(fh, **entry)
    counts, warned = _counts_with_warnings()
    assert counts == fresh and len(warned) == 1 and "does not match its checksum" in warned[0]


def test_a_cache_file_that_is_a_fifo_is_not_read(cache):
    fresh, path = cache
    os.mkfifo(path)
    counts, warned = _counts_with_warnings()
    assert counts == fresh and len(warned) == 1
    assert stat.S_ISFIFO(os.lstat(path).st_mode)              # never replaced


@pytest.mark.parametrize("setting", ["cache-dir", "xdg", "none"])
def test_the_counts_live_in_the_derivation_cache_folder(tmp_path, monkeypatch, setting):
    """One folder rule for both caches: ``GD_ANALYZE_CACHE_DIR`` moves the operation counts as
    it moves the derivation cache (it was ignored: the counts went to ``$XDG_CACHE_HOME``)."""
    from gd_analyze.cache import entry_path

    chosen, xdg = tmp_path / "chosen", tmp_path / "xdg"
    monkeypatch.setenv("XDG_CACHE_HOME", str(xdg))
    monkeypatch.delenv("GD_ANALYZE_NO_CACHE", raising=False)
    monkeypatch.delenv("GD_ANALYZE_CACHE_DIR", raising=False)
    if setting == "cache-dir":
        monkeypatch.setenv("GD_ANALYZE_CACHE_DIR", str(chosen))
    elif setting == "none":
        monkeypatch.setenv("GD_ANALYZE_CACHE_DIR", str(chosen))
        monkeypatch.setenv("GD_ANALYZE_NO_CACHE", "1")
    opcount._counts_for.cache_clear()
    try:
        opcount._counts_for("RRR")
    finally:
        opcount._counts_for.cache_clear()
    written = sorted(p.relative_to(tmp_path).as_posix() for p in tmp_path.rglob("opcounts-*"))
    expected = {"cache-dir": ["chosen/opcounts-"], "xdg": ["xdg/gd-analyze/opcounts-"],
                "none": []}[setting]
    assert [w[:len(e)] for w, e in zip(written, expected)] == expected
    assert len(written) == len(expected)
    derivation = entry_path({"kind": "explicit", "k": 1})
    assert (derivation is None) == (setting == "none")
    if written:                                              # the same folder as the derivations
        assert (tmp_path / written[0]).parent == derivation.parent


def test_an_entry_edited_with_its_checksum_recomputed_is_recounted(cache):
    """"Newton-Euler as implemented: 1" from an entry whose SHA-256 was computed
    again. The oracle is the count of the code itself, measured without a cache (the chapter's
    Table 3.5 formula for N-E, 150 n - 48 multiplications, is far above 1 for three joints)."""
    fresh, path = cache
    assert fresh["newton-euler"][0] > 100
    assert _counts_with_warnings() == (fresh, [])            # written
    planted = _stored(path)["counts"].copy()
    planted[opcount.METHODS.index("newton-euler")] = [1, 1]
    forge(path, ("counts",), counts=planted)
    counts, warned = _counts_with_warnings()
    assert counts == fresh
    assert len(warned) == 1 and "\n" not in warned[0] and str(path) in warned[0]
    assert "differs from the recount" in warned[0] and "newton-euler" in warned[0]
    assert opcount.operation_counts(3)["newton-euler"]["multiplications"] == fresh[
        "newton-euler"][0]
    counts, warned = _counts_with_warnings()                 # replaced by the recount
    assert counts == fresh and warned == []
    assert list(_stored(path)["counts"][opcount.METHODS.index("newton-euler")]) == list(
        fresh["newton-euler"])
