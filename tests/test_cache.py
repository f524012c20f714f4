"""A derivation-cache entry is read with bounded memory, whatever its file says."""

import io
import tracemalloc
import zipfile

import numpy as np
import pytest

from gd_analyze.cache import read_entry, write_entry

_KEY = {"robot": "two-link", "version": 1}


def _entry(path, members, compression=zipfile.ZIP_DEFLATED):
    """An .npz of raw .npy members (bytes), as a hostile file would be."""
    with zipfile.ZipFile(path, "w", compression=compression) as z:
        for name, data in members.items():
            z.writestr(f"{name}.npy", data)


def _npy(array):
    buf = io.BytesIO()
    np.save(buf, array)
    return buf.getvalue()


def _header_only(shape):
    """An .npy header claiming a float64 array of ``shape``, without its data."""
    buf = io.BytesIO()
    np.lib.format.write_array_header_1_0(buf, {"descr": "<f8", "fortran_order": False,
                                               "shape": shape})
    return buf.getvalue()


def _peak(fn):
    tracemalloc.start()
    try:
        out = fn()
        return out, tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_a_small_deflated_entry_is_not_inflated(tmp_path):
    """64 MiB of zeros deflated to a 64 KB file: refused before a byte is inflated."""
    path = tmp_path / "explicit-x.npz"
    zeros = _npy(np.zeros(8 << 20))                          # 64 MiB
    _entry(path, {"coef": zeros, "key": _npy(np.array("k")), "checksum": _npy(np.array("c"))})
    assert path.stat().st_size < 1 << 20
    del zeros
    found, peak = _peak(lambda: read_entry(path, _KEY, ["coef"], 256 << 20))
    assert found == "holds a compressed array (gd-analyze stores its entries uncompressed)"
    assert peak < 8 << 20


@pytest.mark.parametrize("shape", [(1 << 28,), (1 << 62,), (-1,)])
def test_an_array_header_larger_than_its_member_is_refused(tmp_path, shape):
    path = tmp_path / "explicit-x.npz"
    _entry(path, {"coef": _header_only(shape), "key": _npy(np.array("k")),
                  "checksum": _npy(np.array("c"))}, zipfile.ZIP_STORED)
    found, peak = _peak(lambda: read_entry(path, _KEY, ["coef"], 256 << 20))
    assert isinstance(found, str) and peak < 8 << 20


def test_an_entry_written_is_read_back(tmp_path):
    path = tmp_path / "explicit-x.npz"
    arrays = {"coef": np.arange(6.0).reshape(2, 3), "K": np.eye(3, dtype=np.int64).T}
    write_entry(path, _KEY, arrays)
    found = read_entry(path, _KEY, ["coef", "K"], 1 << 20)
    assert all(np.array_equal(found[k], v) and found[k].dtype == v.dtype
               for k, v in arrays.items())


def test_write_entry_replaces_a_planted_link_and_reads_back(tmp_path):
    """Atomic write (files.atomic_path): a link at the entry's name is replaced, its target
    untouched, no temporary left; the entry reads back with its key and checksum."""
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    path = tmp_path / "cache" / "explicit-x.npz"
    path.parent.mkdir()
    path.symlink_to(victim)
    arrays = {"coef": np.arange(3.0)}
    write_entry(path, _KEY, arrays)
    assert victim.read_text() == "precious" and not path.is_symlink()
    assert [p.name for p in path.parent.iterdir()] == [path.name]
    np.testing.assert_array_equal(read_entry(path, _KEY, ["coef"], 1 << 20)["coef"],
                                  arrays["coef"])
    assert read_entry(path, {"robot": "other"}, ["coef"], 1 << 20).startswith("was stored")


def test_write_entry_into_a_file_is_silent(tmp_path):
    (tmp_path / "cache").write_text("a file, not a folder")
    write_entry(tmp_path / "cache" / "explicit-x.npz", _KEY, {"coef": np.zeros(2)})
    assert (tmp_path / "cache").read_text() == "a file, not a folder"
