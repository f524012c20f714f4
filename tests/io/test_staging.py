"""Issue 9, cases 3, 6 and 8 (output locations): staged output folders with a lock."""

import os
import re
import shutil
import signal
import stat
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from gd_analyze.errors import InputError
from gd_analyze.io.manifest import manifest_name
from gd_analyze.io.staging import (
    LOCK_SUFFIX,
    TMP_MARK,
    check_free_space,
    check_output_file,
    safe_name,
    staged_output,
)


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


def _tree(folder):
    """Every file under folder (hidden ones too) with its bytes."""
    return {p.relative_to(folder).as_posix(): p.read_bytes()
            for p in sorted(Path(folder).rglob("*")) if p.is_file() or p.is_symlink()}


def _visible(folder):
    return {k: v for k, v in _tree(folder).items() if not k.startswith(".gd-")}


def test_the_set_is_moved_in_together_and_old_files_go(tmp_path):
    target = tmp_path / "out"
    with staged_output(target, ("a.txt", "b.txt")) as stage:
        (stage / "a.txt").write_text("1")
        (stage / "b.txt").write_text("1")
        assert not target.exists()                 # nothing visible before the run succeeds
    assert sorted(os.listdir(target)) == [manifest_name("output"), "a.txt", "b.txt"]
    with staged_output(target, ("a.txt", "b.txt")) as stage:
        (stage / "a.txt").write_text("2")          # this run writes no b.txt: ours, it goes
    assert _visible(target) == {"a.txt": b"2"}
    assert _leftovers(tmp_path) == []


def _foreign_message(target, names):
    return (f"{target} holds files gd-analyze did not write: {', '.join(names)}; use an empty "
            "or new folder")


@pytest.mark.parametrize("ours", [False, True])
def test_case2_a_users_files_are_never_touched(tmp_path, ours):
    """Issue 16 item 2: a folder holding files no manifest lists is refused, untouched."""
    target = tmp_path / "out"
    if ours:                                       # a folder a run wrote, then the user's files
        with staged_output(target, ("report.html", "figures"), command="analyze") as stage:
            (stage / "figures").mkdir()
            (stage / "figures" / "fig.svg").write_text("ours")
            (stage / "report.html").write_text("ours")
    (target / "figures").mkdir(parents=True, exist_ok=True)
    (target / "figures" / "thesis_fig1.png").write_bytes(b"the user's")
    (target / "report.html").write_text("the user's own")
    before = _tree(target)
    entered = []
    with pytest.raises(InputError) as err:
        with staged_output(target, ("report.html", "figures"), command="analyze") as stage:
            entered.append(stage)                  # refused before the run computes
    assert str(err.value) == _foreign_message(target, ["figures/thesis_fig1.png",
                                                       "report.html"])
    assert not entered
    assert _tree(target) == before
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
    assert _visible(target) == {k: v.encode() for k, v in {**main, **control}.items()}
    _run_as(target, "control", {"control.h5": "c2"})            # control --no-report
    assert _visible(target) == {k: v.encode() for k, v in {**main, "control.h5": "c2"}.items()}
    _run_as(target, "analyze", {"results.h5": "m2"})            # main job --no-report
    assert _visible(target) == {"results.h5": b"m2", "control.h5": b"c2"}
    assert {manifest_name("analyze"), manifest_name("control")} <= set(os.listdir(target))


@pytest.mark.parametrize("path", ["results.h5", "figures/fig_3_10_D.svg", "figures"])
def test_case2_a_command_never_replaces_another_commands_file(tmp_path, path):
    target = tmp_path / "out"
    _run_as(target, "analyze", {"results.h5": "m", "figures/fig_3_10_D.svg": "m"})
    before = _tree(target)
    with pytest.raises(InputError, match="a command never replaces another command's files"):
        _run_as(target, "sweep", {path: "s"})
    assert _tree(target) == before
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
    assert _visible(target) == {"a.txt": b"1"}
    assert _leftovers(tmp_path) == []


#: How long a child holds its state once it has said so [s]: far longer than any wait here, so
#: that only the signal ends it (the tests wait for the child's line, not for seconds).
HOLD = 900
#: A safety net only: how long a signalled child may take to exit, even at load 10 [s].
EXIT_WAIT = 300


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
    proc = _start(_writer_script(target, HOLD))
    assert _leftovers(tmp_path)                      # lock and staging folder exist
    proc.send_signal(sig)
    proc.wait(timeout=EXIT_WAIT)
    assert _leftovers(tmp_path) == [] and not target.exists()


def test_case8_a_killed_run_is_cleaned_by_the_next(tmp_path):
    target = tmp_path / "out"
    proc = _start(_writer_script(target, HOLD))
    with pytest.raises(InputError, match="another run is writing here"):
        with staged_output(target):
            pass
    proc.kill()                                      # SIGKILL: no clean-up possible
    proc.wait(timeout=EXIT_WAIT)
    assert any(TMP_MARK in n for n in _leftovers(tmp_path))
    with staged_output(target, ("big.bin",)) as stage:        # the lock is free again
        (stage / "big.bin").write_text("ok")
    assert _leftovers(tmp_path) == []
    assert sorted(os.listdir(target)) == [manifest_name("output"), "big.bin"]


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

    from gd_analyze.io.staging import writing

    with pytest.raises(InputError, match="no space left on the device"):
        with staged_output(tmp_path / "out") as stage, writing(tmp_path / "out", stage):
            raise OSError(errno.ENOSPC, "No space left on device", str(stage / "x.h5"))
    with pytest.raises(InputError, match="cannot write the output folder"):
        with staged_output(tmp_path / "out") as stage, writing(tmp_path / "out", stage):
            raise OSError("Can't write data (file write failed)")    # as h5py raises it
    assert os.listdir(tmp_path) == []


def test_case10_a_read_error_is_what_it_is(tmp_path):
    """Issue 16 item 10: an OSError reading a file is not "cannot write the output folder"."""
    missing = tmp_path / "fonts" / "missing.ttf"
    with pytest.raises(FileNotFoundError) as err:
        with staged_output(tmp_path / "out"):
            missing.read_bytes()
    assert err.value.filename == str(missing)
    from gd_analyze.io.staging import writing

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


# --- issue 16 item 7: no write follows a symbolic link ----------------------------------------

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
    assert (tmp_path / "alias").is_symlink() and _visible(real) == {"a.txt": b"2"}
    assert _leftovers(tmp_path) == []


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


# --- issue 16 item 8: the set is exchanged whole ----------------------------------------------

OLD = {"a.txt": "old-a", "b.txt": "old-b", "figures/f.svg": "old-f"}
NEW = {"a.txt": "new-a", "b.txt": "new-b", "figures/f.svg": "new-f"}


def _mover_script(target, hold, mount=False):
    """A run that pauses just after its first rename into target (old code: per file)."""
    return textwrap.dedent(f"""
        import os, time
        from gd_analyze.io import staging
        from gd_analyze.io.staging import install_signal_handlers, staged_output
        install_signal_handlers()
        target = os.path.realpath({str(target)!r})
        if {mount!r}:
            ismount = os.path.ismount
            os.path.ismount = lambda p: os.path.realpath(p) == target or ismount(p)
        moved = []
        def pause(fn):
            def wrapper(*args, **kw):
                out = fn(*args, **kw)
                dst = os.path.realpath(os.fspath(args[1]))
                if not moved and (dst == target or dst.startswith(target + os.sep)) \
                        and not os.path.basename(dst).startswith(".gd-"):
                    moved.append(1)
                    print("moved", flush=True)
                    time.sleep({hold})
                return out
            return wrapper
        os.replace, os.rename = pause(os.replace), pause(os.rename)
        if hasattr(staging, "_renameat2"):
            staging._renameat2 = pause(staging._renameat2)
        with staged_output(target, ("a.txt", "b.txt", "figures")) as stage:
            for path, text in {NEW!r}.items():
                (stage / path).parent.mkdir(parents=True, exist_ok=True)
                (stage / path).write_text(text)
            print("staged", flush=True)
        """)


def _set(target):
    return {k: v.decode() for k, v in _visible(target).items()}


def _old_set(target, monkeypatch, mount):
    """A folder holding the OLD set, written by a run; optionally seen as a mount point."""
    target.mkdir()
    if mount:
        ismount = os.path.ismount
        monkeypatch.setattr(os.path, "ismount",
                            lambda p: Path(p).resolve() == target.resolve() or ismount(p))
    with staged_output(target, ("a.txt", "b.txt", "figures")) as stage:
        for path, text in OLD.items():
            (stage / path).parent.mkdir(parents=True, exist_ok=True)
            (stage / path).write_text(text)
    return target


@pytest.mark.parametrize("sig, mount", [(signal.SIGKILL, False), (signal.SIGTERM, False),
                                        (signal.SIGINT, False), (signal.SIGTERM, True)])
def test_case8_an_interrupted_move_leaves_one_whole_set(tmp_path, sig, mount, monkeypatch):
    target = _old_set(tmp_path / "out", monkeypatch, mount)
    proc = _start(_mover_script(target, HOLD if sig == signal.SIGKILL else 2, mount))
    assert proc.stdout.readline().strip() == "moved"
    proc.send_signal(sig)
    proc.wait(timeout=EXIT_WAIT)
    assert _set(target) in (OLD, NEW)
    with staged_output(target, ("a.txt",)) as stage:          # the next run cleans up
        (stage / "a.txt").write_text("next")
    assert _set(target) == {"a.txt": "next"}
    assert _leftovers(tmp_path) == [] and not any(TMP_MARK in n for n in os.listdir(target))


def _refuse_renaming(monkeypatch, folder):
    """The kernel's answers for a mount point (a Docker volume at /out): no rename of it, or
    across it."""
    import errno

    from gd_analyze.io import staging

    real = os.path.realpath(folder)

    def on_volume(path):
        path = os.path.realpath(path)
        return path == real or path.startswith(real + os.sep)

    def guard(fn):
        def wrapper(src, dst, *args, **kw):
            if real in (os.path.realpath(src), os.path.realpath(dst)) or \
                    on_volume(src) != on_volume(dst):
                raise OSError(errno.EXDEV, "Invalid cross-device link", str(src))
            return fn(src, dst, *args, **kw)
        return wrapper

    monkeypatch.setattr(os, "replace", guard(os.replace))
    monkeypatch.setattr(os, "rename", guard(os.rename))
    if hasattr(staging, "_renameat2"):
        monkeypatch.setattr(staging, "_renameat2", guard(staging._renameat2))
    ismount = os.path.ismount
    monkeypatch.setattr(os.path, "ismount", lambda p: os.path.realpath(p) == real or ismount(p))


def test_case8_a_mount_point_is_written_inside(tmp_path, monkeypatch):
    target = tmp_path / "vol"
    target.mkdir()
    _refuse_renaming(monkeypatch, target)
    for text in ("1", "2"):
        with staged_output(target, ("a.txt", "figures")) as stage:
            (stage / "a.txt").write_text(text)
            (stage / "figures").mkdir()
            (stage / "figures" / f"f{text}.svg").write_text(text)
    assert _set(target) == {"a.txt": "2", "figures/f2.svg": "2"}
    assert os.listdir(tmp_path) == ["vol"]                  # nothing beside the mount point
    assert not any(TMP_MARK in n for n in os.listdir(target))


def test_case8_the_current_folder_is_kept(tmp_path, monkeypatch):
    """-o . : the folder is not replaced under the user's shell; its entries are."""
    monkeypatch.chdir(tmp_path)
    inode = os.stat(tmp_path).st_ino
    for text in ("1", "2"):
        with staged_output(".", ("a.txt",)) as stage:
            (stage / "a.txt").write_text(text)
    assert os.stat(tmp_path).st_ino == inode and _set(tmp_path) == {"a.txt": "2"}


def test_case8_without_renameat2_a_killed_swap_is_undone(tmp_path):
    target = tmp_path / "out"
    script = textwrap.dedent(f"""
        import os, signal
        from gd_analyze.io import staging
        staging._libc_renameat2 = lambda: None
        target = {str(target)!r}
        for text in ("1", "2"):
            with staging.staged_output(target) as stage:
                (stage / "a.txt").write_text(text)
        rename = os.rename
        def killed_after(src, dst):          # killed between the two renames
            rename(src, dst)
            if os.fspath(src) == target:
                os.kill(os.getpid(), signal.SIGKILL)
        os.rename = killed_after
        with staging.staged_output(target) as stage:
            (stage / "a.txt").write_text("3")
        """)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    run = subprocess.run([sys.executable, "-c", script], env=env, timeout=EXIT_WAIT)
    assert run.returncode == -signal.SIGKILL and not target.exists()
    with staged_output(target) as stage:
        (stage / "b.txt").write_text("3")
    assert _set(target) == {"b.txt": "3"} and _leftovers(tmp_path) == []
    assert sorted(os.listdir(tmp_path)) == ["out"]


def test_case7_a_lock_file_linked_to_another_file_is_refused(tmp_path):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    os.link(victim, tmp_path / f".out{LOCK_SUFFIX}")
    with pytest.raises(InputError, match="lock file .* is not a file of its own"):
        with staged_output(tmp_path / "out"):
            pass
    assert victim.read_text() == "precious"


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
    assert _visible(target) == {"a.txt": b"1",
                                "notes.txt": b"the user's, written while the run computed"}
    assert _leftovers(tmp_path) == []


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


def test_case8_a_mount_point_killed_mid_exchange_is_replaced_whole_by_the_next_run(
        tmp_path, monkeypatch):
    """In a mount point the entries are exchanged one by one: SIGKILL between two can split
    the set, but the manifest then knows both sets, so the next run is not refused."""
    target = _old_set(tmp_path / "vol", monkeypatch, mount=True)
    proc = _start(_mover_script(target, HOLD, mount=True))
    assert proc.stdout.readline().strip() == "moved"
    proc.kill()
    proc.wait(timeout=EXIT_WAIT)
    assert set(_set(target)) == set(OLD)                 # every file there, old or new
    with staged_output(target, ("a.txt",)) as stage:
        (stage / "a.txt").write_text("next")
    assert _set(target) == {"a.txt": "next"}
    assert not any(TMP_MARK in n for n in os.listdir(target))


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


def test_issue32_a_refused_run_removes_nothing(tmp_path):
    target = tmp_path / "out"
    _run_as(target, "analyze", {"a.txt": "m"})
    _gd_lookalikes(tmp_path, target)
    (target / "notes.txt").write_text("the user's")
    before, beside = _tree(target), _tree(tmp_path)
    with pytest.raises(InputError, match="did not write: .gd-tmp-abc/keep.txt, notes.txt;"):
        _run_as(target, "analyze", {"a.txt": "m2"})
    assert _tree(target) == before and _tree(tmp_path) == beside


@pytest.mark.parametrize("name", [".gd-notes.txt", ".gd-backup/old.txt", ".gd-lock"])
def test_issue32_a_users_gd_names_are_never_deleted(tmp_path, name):
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


def test_issue32_a_refused_run_keeps_a_killed_runs_temporaries_for_the_next(tmp_path):
    target = tmp_path / "out"
    proc = _start(_writer_script(target, HOLD))
    proc.kill()                                      # SIGKILL: its staging folder stays
    proc.wait(timeout=EXIT_WAIT)
    left = _leftovers(tmp_path)
    assert any(TMP_MARK in n for n in left)
    target.mkdir()
    (target / "notes.txt").write_text("the user's")
    with pytest.raises(InputError, match="did not write: notes.txt"):
        with staged_output(target):
            pass
    assert _leftovers(tmp_path) == left              # refused: nothing removed, still known
    (target / "notes.txt").unlink()
    with staged_output(target) as stage:
        (stage / "a.txt").write_text("1")
    assert _leftovers(tmp_path) == []
