"""Fixtures of the io tests."""

import pytest


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """An empty derivation cache folder of the test's own, caching enabled."""
    monkeypatch.delenv("GD_ANALYZE_NO_CACHE", raising=False)
    folder = tmp_path / "cache"
    monkeypatch.setenv("GD_ANALYZE_CACHE_DIR", str(folder))
    return folder
