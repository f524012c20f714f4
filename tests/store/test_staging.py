"""Output locations: staged output folders with a lock; whose
files a folder holds, and no write through a symbolic link. Interrupted runs and mount points
(case 8): test_staging_interrupted.py."""

import os
import re
import shutil
import stat
from pathlib import Path

import pytest
from staging_checks import leftovers, tree, visible

from gd_analyze.errors import InputError
from gd_analyze.store.manifest import manifest_name
from gd_analyze.store.staging import (
    LOCK_SUFFIX,
    check_free_space,
    check_output_file,
    safe_name,
    staged_output,
)


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
    with staged_output(target) as stage:
        (stage / "a.txt").write_text("1")
        (stage / "b.txt").write_text("1")
        assert not target.exists()                 # nothing visible before the run succeeds
    assert sorted(os.listdir(target)) == [manifest_name("output"), "a.txt", "b.txt"]
    with staged_output(target) as stage:
        (stage / "a.txt").write_text("2")          # this run writes no b.txt: ours, it goes
    assert visible(target) == {"a.txt": b"2"}
    assert leftovers(tmp_path) == []


def _foreign_message(target, names):
    return (f"{target} holds files gd-analyze did not write: {', '.join(names)}; use an empty "
            "or new folder")


@pytest.mark.parametrize("ours", [False, True])
def test_case2_a_users_files_are_never_touched(tmp_path, ours):
    """A folder holding files no manifest lists is refused, untouched."""
    target = tmp_path / "out"
    if ours:                                       # a folder a run wrote, then the user's files
        with staged_output(target, command="analyze") as stage:
            (stage / "figures").mkdir()
            (stage / "figures" / "fig.svg").write_text("ours")
            (stage / "report.html").write_text("ours")
    (target / "figures").mkdir(parents=True, exist_ok=True)
    (target / "figures" / "thesis_fig1.png").write_bytes(b"the user's")
    (target / "report.html").write_text("the user's own")
    before = tree(target)
    entered = []
    with pytest.raises(InputError) as err:
        with staged_output(target, command="analyze") as stage:
            entered.append(stage)                  # refused before the run computes
    assert str(err.value) == _foreign_message(target, ["figures/thesis_fig1.png",
                                                       "report.html"])
    assert not entered
    assert tree(target) == before
    assert sorted(os.listdir(tmp_path)) == ["out"]


def test_case2_a_changed_file_is_not_ours(tmp_path):
    """A file the manifest lists but whose bytes changed (same size) is the user's now."""
    target = tmp_path / "out"
    with staged_output(target, command="analyze") as stage:
        (stage / "a.txt").write_text("old")
    (target / "a.txt").write_text("own")
    with pytest.raises(InputError, match="did not write: a.txt; use an empty or new folder"):
        with staged_output(target, command="analyze"):
            pass
    assert (target / "a.txt").read_text() == "own"


def _run_as(target, command, files):
    with staged_output(target, command=command) as stage:
        for path, text in files.items():
            (stage / path).parent.mkdir(parents=True, exist_ok=True)
            (stage / path).write_text(text)


def test_case2_commands_keep_each_others_files(tmp_path):
    """control into a main job's folder: each command replaces its own files only."""
    target = tmp_path / "out"
    main = {"results.h5": "m", "report.html": "m", "figures/fig_3_10_D.svg": "m"}
    control = {"control.h5": "c", "control_report.html": "c", "figures/fig_control.svg": "c"}
    _run_as(target, "analyze", main)
    _run_as(target, "control", control)
    assert visible(target) == {k: v.encode() for k, v in {**main, **control}.items()}
    _run_as(target, "control", {"control.h5": "c2"})            # control --no-report
    assert visible(target) == {k: v.encode() for k, v in {**main, "control.h5": "c2"}.items()}
    _run_as(target, "analyze", {"results.h5": "m2"})            # main job --no-report
    assert visible(target) == {"results.h5": b"m2", "control.h5": b"c2"}
    assert {manifest_name("analyze"), manifest_name("control")} <= set(os.listdir(target))


@pytest.mark.parametrize("path", ["results.h5", "figures/fig_3_10_D.svg", "figures"])
def test_case2_a_command_never_replaces_another_commands_file(tmp_path, path):
    target = tmp_path / "out"
    _run_as(target, "analyze", {"results.h5": "m", "figures/fig_3_10_D.svg": "m"})
    before = tree(target)
    with pytest.raises(InputError, match="a command never replaces another command's files"):
        _run_as(target, "sweep", {path: "s"})
    assert tree(target) == before
    assert leftovers(tmp_path) == []


def test_case3_a_failed_run_leaves_the_old_set_and_nothing_else(tmp_path):
    target = tmp_path / "out"
    with staged_output(target) as stage:
        (stage / "a.txt").write_text("old")
    with pytest.raises(RuntimeError):
        with staged_output(target) as stage:
            (stage / "a.txt").write_text("new")
            raise RuntimeError("interrupted")
    assert (target / "a.txt").read_text() == "old"
    assert leftovers(tmp_path) == []


def test_case3_a_second_run_into_the_same_folder_is_refused(tmp_path):
    target = tmp_path / "out"
    with staged_output(target) as stage:
        with pytest.raises(InputError, match="another run is writing here"):
            with staged_output(target):
                pass
        (stage / "a.txt").write_text("1")
    assert visible(target) == {"a.txt": b"1"}
    assert leftovers(tmp_path) == []


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


def test_a_folder_not_yet_created_is_checked_where_it_will_be(tmp_path, monkeypatch):
    """A command checks before it computes, when its output folder may not exist yet: the
    nearest existing folder above it is asked (shutil.disk_usage of a missing path raised
    FileNotFoundError), and nothing is created."""
    import shutil
    from collections import namedtuple

    usage, asked = namedtuple("usage", "total used free"), []
    monkeypatch.setattr(shutil, "disk_usage",
                        lambda p: asked.append(Path(p)) or usage(10**9, 10**9 - 10**6, 10**6))
    with pytest.raises(InputError, match="not enough free space for sweep.h5"):
        check_free_space(tmp_path / "a" / "out", 50 * 10**6, "sweep.h5")
    assert asked == [tmp_path] and os.listdir(tmp_path) == []


def test_case8_write_errors_become_one_line(tmp_path):
    import errno

    from gd_analyze.store.staging import writing

    with pytest.raises(InputError, match="no space left on the device"):
        with staged_output(tmp_path / "out") as stage, writing(tmp_path / "out", stage):
            raise OSError(errno.ENOSPC, "No space left on device", str(stage / "x.h5"))
    with pytest.raises(InputError, match="cannot write the output folder"):
        with staged_output(tmp_path / "out") as stage, writing(tmp_path / "out", stage):
            raise OSError("Can't write data (file write failed)")    # as h5py raises it
    assert os.listdir(tmp_path) == []


def test_case10_a_read_error_is_what_it_is(tmp_path):
    """An OSError reading a file is not "cannot write the output folder"."""
    missing = tmp_path / "fonts" / "missing.ttf"
    with pytest.raises(FileNotFoundError) as err:
        with staged_output(tmp_path / "out"):
            missing.read_bytes()
    assert err.value.filename == str(missing)
    from gd_analyze.store.staging import writing

    with pytest.raises(FileNotFoundError):
        with staged_output(tmp_path / "out") as stage, writing(tmp_path / "out", stage):
            missing.read_bytes()                 # a read outside the staging folder
    assert os.listdir(tmp_path) == []


def test_check_output_file(tmp_path):
    with pytest.raises(InputError, match="is a folder"):
        check_output_file(tmp_path)
    with pytest.raises(InputError, match="does not exist"):
        check_output_file(tmp_path / "no" / "x.csv")
    check_output_file(tmp_path / "x.csv")


# --- no write follows a symbolic link -------------------------------------------------------------

def test_case7_a_planted_lock_symlink_is_not_followed(tmp_path):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    (tmp_path / f".out{LOCK_SUFFIX}").symlink_to(victim)
    with pytest.raises(InputError, match="lock file .* is a symbolic link"):
        with staged_output(tmp_path / "out") as stage:
            (stage / "a.txt").write_text("1")
    assert victim.read_text() == "precious"
    assert not (tmp_path / "out").exists()


def test_case7_an_alias_of_the_folder_takes_the_same_lock(tmp_path):
    real = tmp_path / "out"
    real.mkdir()
    (tmp_path / "alias").symlink_to(real)
    with staged_output(real) as stage:
        with pytest.raises(InputError, match="another run is writing here"):
            with staged_output(tmp_path / "alias"):
                pass
        (stage / "a.txt").write_text("1")
    with staged_output(tmp_path / "alias") as stage:       # the link names the real folder
        (stage / "a.txt").write_text("2")
    assert (tmp_path / "alias").is_symlink() and visible(real) == {"a.txt": b"2"}
    assert leftovers(tmp_path) == []


def test_case7_staging_names_are_unpredictable_and_private(tmp_path):
    names = []
    for _ in range(2):
        with staged_output(tmp_path / "out") as stage:
            names.append(stage.name)
            assert stat.S_IMODE(stage.stat().st_mode) == 0o700
    assert names[0] != names[1]


def test_case7_atomic_path_never_writes_through_a_link(tmp_path):
    from gd_analyze.files import atomic_path

    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    dest = tmp_path / "out.csv"
    dest.symlink_to(victim)
    with atomic_path(dest) as tmp:
        Path(tmp).write_text("new")
    assert victim.read_text() == "precious" and not dest.is_symlink()
    assert dest.read_text() == "new"


def test_case7_a_lock_file_linked_to_another_file_is_refused(tmp_path):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    os.link(victim, tmp_path / f".out{LOCK_SUFFIX}")
    with pytest.raises(InputError, match="lock file .* is not a file of its own"):
        with staged_output(tmp_path / "out"):
            pass
    assert victim.read_text() == "precious"


def test_case7_a_lock_file_that_is_a_fifo_is_refused_without_blocking(tmp_path):
    os.mkfifo(tmp_path / f".out{LOCK_SUFFIX}")
    with pytest.raises(InputError, match="lock file .* is not a file of its own"):
        with staged_output(tmp_path / "out"):
            pass
    assert stat.S_ISFIFO(os.lstat(tmp_path / f".out{LOCK_SUFFIX}").st_mode)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("kind", ["file", "folder"])
def test_case7_a_symbolic_link_inside_the_folder_is_not_ours(tmp_path, kind):
    victim = tmp_path / "victim"
    if kind == "folder":
        victim.mkdir()
        (victim / "f.svg").write_text("precious")
    else:
        victim.write_text("precious")
    target = tmp_path / "out"
    with staged_output(target) as stage:
        (stage / "figures").mkdir()
        (stage / "figures" / "f.svg").write_text("ours")
    shutil.rmtree(target / "figures")
    (target / "figures").symlink_to(victim)
    with pytest.raises(InputError, match="did not write: figures; use an empty"):
        with staged_output(target) as stage:
            (stage / "figures").mkdir()
            (stage / "figures" / "f.svg").write_text("new")
    assert (target / "figures").is_symlink()
    assert (victim / "f.svg" if kind == "folder" else victim).read_text() == "precious"


def test_case8_a_folder_added_to_during_the_run_is_refused_untouched(tmp_path):
    target = tmp_path / "out"
    with staged_output(target) as stage:
        (stage / "a.txt").write_text("1")
    with pytest.raises(InputError, match="did not write: notes.txt; use an empty"):
        with staged_output(target) as stage:
            (stage / "a.txt").write_text("2")
            (target / "notes.txt").write_text("the user's, written while the run computed")
    assert visible(target) == {"a.txt": b"1",
                                "notes.txt": b"the user's, written while the run computed"}
    assert leftovers(tmp_path) == []


def test_case2_a_wrong_folder_is_refused_without_reading_it_all(tmp_path):
    """-o into a big folder of one's own (a home folder): refused after a few names."""
    target = tmp_path / "home"
    for k in range(30):
        (target / f"d{k:02d}").mkdir(parents=True)
        (target / f"d{k:02d}" / "notes.txt").write_text("mine")
    with pytest.raises(InputError) as err:
        with staged_output(target):
            pass
    assert str(err.value) == _foreign_message(
        target, [f"d{k:02d}/notes.txt" for k in range(8)]).replace("; use", " and more; use")


@pytest.mark.parametrize("where", ["out", "reports/out"])
def test_case7_no_folder_is_created_through_a_dangling_link(tmp_path, where):
    elsewhere = tmp_path / "elsewhere"
    (tmp_path / where.split("/")[0]).symlink_to(elsewhere)
    with pytest.raises(InputError, match="is a symbolic link to nothing"):
        with staged_output(tmp_path / where):
            pass
    assert not elsewhere.exists()


@pytest.mark.parametrize("size", [0, 1, (1 << 20) - 1, 1 << 20, (1 << 20) + 1, 3 << 20])
def test_file_digest_is_hashlib_of_the_bytes(tmp_path, size):
    """The manifest's SHA-256, read in blocks into one buffer, around the block size."""
    import hashlib

    from gd_analyze.files import file_sha256

    data = os.urandom(size)
    (tmp_path / "f.bin").write_bytes(data)
    assert file_sha256(tmp_path / "f.bin") == hashlib.sha256(data).hexdigest()


def _gd_lookalikes(tmp_path, target):
    """Names that look like gd-analyze's own, made by a user: none is the tool's to remove."""
    (target / ".gd-tmp-abc").mkdir()
    (target / ".gd-tmp-abc" / "keep.txt").write_text("user")
    (tmp_path / ".out.gd-prev").mkdir()
    (tmp_path / ".out.gd-prev" / "keep.txt").write_text("user")
    (tmp_path / ".out.gd-tmp-xyz").mkdir()
    (tmp_path / ".out.gd-tmp-xyz" / "keep.txt").write_text("user")


def test_a_refused_run_removes_nothing(tmp_path):
    target = tmp_path / "out"
    _run_as(target, "analyze", {"a.txt": "m"})
    _gd_lookalikes(tmp_path, target)
    (target / "notes.txt").write_text("the user's")
    before, beside = tree(target), tree(tmp_path)
    with pytest.raises(InputError, match="did not write: .gd-tmp-abc/keep.txt, notes.txt;"):
        _run_as(target, "analyze", {"a.txt": "m2"})
    assert tree(target) == before and tree(tmp_path) == beside


@pytest.mark.parametrize("name", [".gd-notes.txt", ".gd-backup/old.txt", ".gd-lock"])
def test_a_users_gd_names_are_never_deleted(tmp_path, name):
    """A top-level name starting .gd- that gd-analyze did not create is a user's file: the run
    is refused and the file kept; temporaries beside the folder that no run registered stay."""
    target = tmp_path / "out"
    _run_as(target, "analyze", {"a.txt": "m"})
    (target / name).parent.mkdir(exist_ok=True)
    (target / name).write_text("the user's")
    with pytest.raises(InputError, match=f"did not write: {re.escape(name)};"):
        _run_as(target, "analyze", {"a.txt": "m2"})
    assert (target / name).read_text() == "the user's"
    (target / name).unlink()
    _gd_lookalikes(tmp_path, target)
    shutil.rmtree(target / ".gd-tmp-abc")
    _run_as(target, "analyze", {"a.txt": "m2"})          # a normal rerun
    assert all((tmp_path / n / "keep.txt").read_text() == "user"
               for n in (".out.gd-prev", ".out.gd-tmp-xyz"))


def test_full_disk_error_finds_the_cause_in_the_chain(tmp_path):
    """Oracle: the errno of each OSError made. A full disk, a quota and the file size limit
    anywhere in an exception's chain give one line naming the file; any other error, None."""
    import errno

    from gd_analyze.store.staging import full_disk_error

    cache = str(tmp_path / "kernel.nbc")
    for code, said in ((errno.ENOSPC, "no space left on the device"),
                       (errno.EFBIG, os.strerror(errno.EFBIG).lower())):
        try:
            try:
                raise OSError(code, os.strerror(code), cache)
            except OSError as inner:
                raise RuntimeError("saving failed") from inner
        except RuntimeError as outer:
            error = full_disk_error(outer)
        assert isinstance(error, InputError) and str(error) == f"{cache}: cannot write: {said}"
    assert full_disk_error(OSError(errno.EACCES, "Permission denied", cache)) is None
    assert full_disk_error(ValueError("no")) is None


def test_an_empty_output_file_name_is_no_folder(tmp_path, monkeypatch):
    """check_output_file("") said ": is a folder: give a file name" (Path("") is the current
    folder); a folder is still called one."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(InputError, match=r"^'': no file name$"):
        check_output_file("")
    with pytest.raises(InputError, match=r"^\.: is a folder: give a file name$"):
        check_output_file(".")
