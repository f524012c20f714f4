"""Issue 9, cases 3, 6 and 8 (output locations): staged output folders with a lock."""

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from gd_analyze.errors import InputError
from gd_analyze.io.staging import (LOCK_SUFFIX, TMP_MARK, check_free_space, check_output_file,
                                   safe_name, staged_output)


def _leftovers(parent):
    return sorted(p.name for p in Path(parent).iterdir() if LOCK_SUFFIX in p.name
                  or TMP_MARK in p.name or p.name.endswith(".tmp"))


@pytest.mark.parametrize("name, expect", [("../../x", "x"), ("/etc/passwd", "etc_passwd"),
                                          ("a\x00b", "a_b"), ("..", "robot"), ("", "robot"),
                                          ("puma560+payload", "puma560+payload"),
                                          ("C:\\evil", "C_evil"), ("-rf", "rf")])
def test_case6_safe_name(name, expect):
    out = safe_name(name)
    assert out == expect
    assert "/" not in out and ".." not in out and not out.startswith((".", "-"))


def test_the_set_is_moved_in_together_and_old_files_go(tmp_path):
    target = tmp_path / "out"
    with staged_output(target, ("a.txt", "b.txt")) as stage:
        (stage / "a.txt").write_text("1")
        (stage / "b.txt").write_text("1")
        assert not target.exists()                 # nothing visible before the run succeeds
    assert sorted(os.listdir(target)) == ["a.txt", "b.txt"]
    (target / "user.txt").write_text("mine")
    with staged_output(target, ("a.txt", "b.txt")) as stage:
        (stage / "a.txt").write_text("2")          # this run writes no b.txt
    assert sorted(os.listdir(target)) == ["a.txt", "user.txt"]
    assert (target / "a.txt").read_text() == "2"
    assert _leftovers(tmp_path) == []


def test_case3_a_failed_run_leaves_the_old_set_and_nothing_else(tmp_path):
    target = tmp_path / "out"
    with staged_output(target, ("a.txt",)) as stage:
        (stage / "a.txt").write_text("old")
    with pytest.raises(RuntimeError):
        with staged_output(target, ("a.txt",)) as stage:
            (stage / "a.txt").write_text("new")
            raise RuntimeError("interrupted")
    assert (target / "a.txt").read_text() == "old"
    assert _leftovers(tmp_path) == []


def test_case3_a_second_run_into_the_same_folder_is_refused(tmp_path):
    target = tmp_path / "out"
    with staged_output(target) as stage:
        with pytest.raises(InputError, match="another run is writing here"):
            with staged_output(target):
                pass
        (stage / "a.txt").write_text("1")
    assert os.listdir(target) == ["a.txt"]
    assert _leftovers(tmp_path) == []


def _writer_script(target, hold):
    return textwrap.dedent(f"""
        import sys, time
        from gd_analyze.io.staging import install_signal_handlers, staged_output
        install_signal_handlers()
        with staged_output({str(target)!r}, ("big.bin",)) as stage:
            (stage / "big.bin").write_bytes(b"x" * 100000)
            print("staged", flush=True)
            time.sleep({hold})
        """)


def _start(script):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, env=env,
                            text=True)
    assert proc.stdout.readline().strip() == "staged"
    return proc


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_case8_signals_remove_the_temporary_files(tmp_path, sig):
    target = tmp_path / "out"
    proc = _start(_writer_script(target, 30))
    assert _leftovers(tmp_path)                      # lock and staging folder exist
    proc.send_signal(sig)
    proc.wait(timeout=20)
    assert _leftovers(tmp_path) == [] and not target.exists()


def test_case8_a_killed_run_is_cleaned_by_the_next(tmp_path):
    target = tmp_path / "out"
    proc = _start(_writer_script(target, 30))
    with pytest.raises(InputError, match="another run is writing here"):
        with staged_output(target):
            pass
    proc.kill()                                      # SIGKILL: no clean-up possible
    proc.wait(timeout=20)
    assert any(TMP_MARK in n for n in _leftovers(tmp_path))
    (target).mkdir()
    (target / ".big.bin.abc.tmp").write_bytes(b"half")        # an atomic_path leftover
    (target / ".user.tmp").write_bytes(b"not ours")
    with staged_output(target, ("big.bin",)) as stage:        # the lock is free again
        (stage / "big.bin").write_text("ok")
    assert _leftovers(tmp_path) == []
    assert sorted(os.listdir(target)) == [".user.tmp", "big.bin"]


@pytest.mark.parametrize("where", ["proc", "under_file", "file"])
def test_case8_unusable_targets(tmp_path, where):
    f = tmp_path / "afile"
    f.write_text("x")
    target = {"proc": Path("/proc/gd-analyze-test/out"), "under_file": f / "sub",
              "file": f}[where]
    with pytest.raises(InputError) as err:
        with staged_output(target):
            pass
    assert "\n" not in str(err.value)
    assert sorted(os.listdir(tmp_path)) == ["afile"]


def test_created_parents_are_removed_on_failure(tmp_path):
    with pytest.raises(RuntimeError):
        with staged_output(tmp_path / "a" / "b" / "out"):
            raise RuntimeError
    assert os.listdir(tmp_path) == []


def test_case8_full_disk_is_refused_before_writing(tmp_path, monkeypatch):
    import shutil
    from collections import namedtuple

    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(shutil, "disk_usage", lambda p: usage(10**9, 10**9 - 10**6, 10**6))
    with pytest.raises(InputError, match="not enough free space"):
        with staged_output(tmp_path / "out") as stage:
            check_free_space(stage, 50 * 10**6, "results.h5")
    assert os.listdir(tmp_path) == []


def test_case8_write_errors_become_one_line(tmp_path):
    import errno

    with pytest.raises(InputError, match="no space left on the device"):
        with staged_output(tmp_path / "out"):
            raise OSError(errno.ENOSPC, "No space left on device")
    with pytest.raises(InputError, match="cannot write the output folder"):
        with staged_output(tmp_path / "out"):
            raise OSError("Can't write data (file write failed)")    # as h5py raises it
    assert os.listdir(tmp_path) == []


def test_check_output_file(tmp_path):
    with pytest.raises(InputError, match="is a folder"):
        check_output_file(tmp_path)
    with pytest.raises(InputError, match="does not exist"):
        check_output_file(tmp_path / "no" / "x.csv")
    check_output_file(tmp_path / "x.csv")
