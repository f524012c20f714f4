"""An output folder's manifests are read with bounded cost and compared by SHA-256."""

import os
import time

import pytest

from gd_analyze.errors import InputError
from gd_analyze.store.manifest import folder_owners, manifest_name, walk_files
from gd_analyze.store.staging import staged_output


def test_a_manifest_nested_100000_deep_is_refused_in_one_line(tmp_path):
    """json's RecursionError (exit 4) becomes the folder's refusal (exit 2)."""
    name = manifest_name("analyze")
    (tmp_path / name).write_text('{"tool": "gd-analyze", "files": ' + "[" * 100_000
                                 + "]" * 100_000 + "}")
    with pytest.raises(InputError) as err:
        folder_owners(tmp_path, "analyze", "out")
    assert str(err.value) == (f"out holds files gd-analyze did not write: {name}; use an empty "
                              "or new folder")


def test_a_deep_folder_is_walked_without_recursion(tmp_path):
    """A folder deeper than the recursion limit is walked (RecursionError was exit 4)."""
    import inspect
    import sys

    deep = tmp_path.joinpath(*["d"] * 200)
    deep.mkdir(parents=True)
    (deep / "f.txt").write_text("x")
    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(len(inspect.stack()) + 100)     # 100 frames for a 200-deep folder
    try:
        found = [p for p, _ in walk_files(tmp_path)]
    finally:
        sys.setrecursionlimit(limit)
    assert found == ["/".join(["d"] * 200 + ["f.txt"])]


def test_a_manifest_that_is_a_fifo_is_not_read(tmp_path):
    name = manifest_name("analyze")
    os.mkfifo(tmp_path / name)
    with pytest.raises(InputError, match=f"did not write: {name};"):
        folder_owners(tmp_path, "analyze")


def test_a_same_size_edit_with_its_mtime_put_back_is_the_users(tmp_path):
    """cp -p, rsync -t, touch -r: the size and mtime are as recorded, the SHA-256 is not."""
    target = tmp_path / "out"
    with staged_output(target, command="analyze") as stage:
        (stage / "a.txt").write_text("old")
    st = os.stat(target / "a.txt")
    (target / "a.txt").write_text("own")
    os.utime(target / "a.txt", ns=(st.st_atime_ns, st.st_mtime_ns))
    with pytest.raises(InputError, match="did not write: a.txt; use an empty or new folder"):
        with staged_output(target, command="analyze"):
            pass
    assert (target / "a.txt").read_text() == "own"


def _settled_folder(tmp_path, monkeypatch):
    """A folder written by a run whose files' change times are already settled, with a count
    of the SHA-256s taken."""
    from gd_analyze.store import manifest

    target = tmp_path / "out"
    with staged_output(target, command="analyze") as stage:
        (stage / "a.txt").write_text("old")
    monkeypatch.setattr(manifest, "SETTLED_NS", 0)      # not to wait a second for the clock
    monkeypatch.setattr(manifest, "_DIGESTS", {})
    calls = []
    hashed = manifest.file_sha256
    monkeypatch.setattr(manifest, "file_sha256", lambda p: calls.append(p) or hashed(p))
    return target, calls


def test_an_unchanged_file_is_hashed_once_per_process(tmp_path, monkeypatch):
    target, calls = _settled_folder(tmp_path, monkeypatch)
    time.sleep(0.05)                                     # past the change time's tick
    first = folder_owners(target, "analyze")
    second = folder_owners(target, "analyze")
    assert first.own == second.own and list(first.own) == ["a.txt"]
    assert len(calls) == 1


def test_a_same_size_edit_with_its_mtime_put_back_is_seen_by_the_second_check(tmp_path,
                                                                              monkeypatch):
    """The change time moves on any write, and no user can set it back."""
    target, calls = _settled_folder(tmp_path, monkeypatch)
    time.sleep(0.05)
    folder_owners(target, "analyze")
    st = os.stat(target / "a.txt")
    time.sleep(0.05)
    (target / "a.txt").write_text("own")
    os.utime(target / "a.txt", ns=(st.st_atime_ns, st.st_mtime_ns))
    with pytest.raises(InputError, match="did not write: a.txt; use an empty or new folder"):
        folder_owners(target, "analyze")
    assert len(calls) == 2


def test_a_file_changed_just_before_its_check_is_hashed_every_time(tmp_path, monkeypatch):
    from gd_analyze.store import manifest

    target, calls = _settled_folder(tmp_path, monkeypatch)
    monkeypatch.setattr(manifest, "SETTLED_NS", 10**12)  # every change time is recent
    for _ in range(3):
        folder_owners(target, "analyze")
    assert len(calls) == 3


def _deferred(monkeypatch):
    """Every file counts as large: the first check defers its SHA-256 to a thread."""
    from gd_analyze.store import manifest

    monkeypatch.setattr(manifest, "DEFERRED_BYTES", 0)
    monkeypatch.setattr(manifest, "_PENDING", {})


def test_the_first_check_hashes_a_large_file_beside_the_run_and_the_second_reuses_it(
        tmp_path, monkeypatch):
    import threading

    target, calls = _settled_folder(tmp_path, monkeypatch)
    _deferred(monkeypatch)
    threads = []
    from gd_analyze.store import manifest
    hashed = manifest.file_sha256
    monkeypatch.setattr(manifest, "file_sha256",
                        lambda p: threads.append(threading.current_thread().name) or hashed(p))
    time.sleep(0.05)
    first = folder_owners(target, "analyze", defer=True)
    second = folder_owners(target, "analyze")
    assert list(first.own) == list(second.own) == ["a.txt"]
    assert threads == ["gd-analyze-digest"]             # once, and not on the caller's thread


def test_a_same_size_edit_after_a_deferred_first_check_is_refused_by_the_second(
        tmp_path, monkeypatch):
    target, calls = _settled_folder(tmp_path, monkeypatch)
    _deferred(monkeypatch)
    time.sleep(0.05)
    st = os.stat(target / "a.txt")
    (target / "a.txt").write_text("own")                # before the first check, mtime put back
    os.utime(target / "a.txt", ns=(st.st_atime_ns, st.st_mtime_ns))
    time.sleep(0.05)
    folder_owners(target, "analyze", defer=True)        # size and name only: passes
    with pytest.raises(InputError, match="did not write: a.txt; use an empty or new folder"):
        folder_owners(target, "analyze")


def test_a_run_into_a_folder_edited_during_its_computation_is_refused_untouched(
        tmp_path, monkeypatch):
    """Through staged_output: the edit lands after the deferred first check."""
    target, calls = _settled_folder(tmp_path, monkeypatch)
    _deferred(monkeypatch)
    time.sleep(0.05)
    with pytest.raises(InputError, match="did not write: a.txt"):
        with staged_output(target, command="analyze") as stage:
            (target / "a.txt").write_text("own")
            (stage / "a.txt").write_text("new")
    assert (target / "a.txt").read_text() == "own"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_a_file_hashed_beside_the_run_is_recorded_only_while_unchanged(tmp_path, monkeypatch):
    """hash_beside's digest goes into the manifest when the file is as it was; a file
    rewritten after (even to the same size) is hashed again, and the manifest holds the bytes'
    true SHA-256 either way."""
    import hashlib
    import json

    import gd_analyze.store.manifest as manifest

    kept, edited = tmp_path / "kept.bin", tmp_path / "edited.bin"
    kept.write_bytes(os.urandom(3 << 20))
    edited.write_bytes(b"a" * 1000)
    manifest.hash_beside(kept)
    manifest.hash_beside(edited)
    time.sleep(0.02)
    edited.write_bytes(b"b" * 1000)                 # same size, new bytes
    for _, digest in list(manifest._STAGED.values()):
        digest.result()                             # both threads done before the spy
    hashed = []
    real = manifest.file_sha256

    def spy(path):
        hashed.append(os.path.basename(path))
        return real(path)
    monkeypatch.setattr(manifest, "file_sha256", spy)
    manifest.write_manifest(tmp_path, "analyze", "0")
    files = json.loads((tmp_path / manifest_name("analyze")).read_text())["files"]
    for name in ("kept.bin", "edited.bin"):
        assert files[name]["sha256"] == hashlib.sha256((tmp_path / name).read_bytes()).hexdigest()
    assert hashed == ["edited.bin"]
    assert manifest._STAGED == {}


def test_the_digest_thread_yields_the_processor_and_the_run_does_not():
    """_yield_cpu lowers the calling thread's priority only (Linux: its nice value 19); the
    thread that called it is the only one changed."""
    import sys
    import threading

    import gd_analyze.store.manifest as manifest

    seen = {}

    def work():
        manifest._yield_cpu()
        if sys.platform.startswith("linux"):
            seen["thread"] = os.getpriority(os.PRIO_PROCESS, threading.get_native_id())
    before = os.getpriority(os.PRIO_PROCESS, 0)
    t = threading.Thread(target=work)
    t.start()
    t.join()
    assert os.getpriority(os.PRIO_PROCESS, 0) == before
    if sys.platform.startswith("linux"):
        assert seen["thread"] == 19
