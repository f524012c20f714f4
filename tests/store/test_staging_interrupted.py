"""Output locations: a staged output interrupted by a signal or killed, and
output folders that are mount points; the set is exchanged whole."""

import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from staging_checks import leftovers, visible

from gd_analyze.errors import InputError
from gd_analyze.store.manifest import manifest_name
from gd_analyze.store.staging import TMP_MARK, staged_output

#: How long a child holds its state once it has said so [s]: far longer than any wait here, so
#: that only the signal ends it (the tests wait for the child's line, not for seconds).
HOLD = 900
#: A safety net only: how long a signalled child may take to exit, even at load 10 [s].
EXIT_WAIT = 300
#: A child holds in short sleeps [s]: a signal that lands after the interpreter's last check
#: for signals and before the sleep's system call does not interrupt that call, so one long
#: ``time.sleep`` could run out its whole hold after the signal (seen once at load 4).
NAP = 0.05


def _writer_script(target, hold):
    return textwrap.dedent(f"""
        import sys, time
        from gd_analyze.store.signals import install
        from gd_analyze.store.staging import staged_output
        install()
        with staged_output({str(target)!r}) as stage:
            (stage / "big.bin").write_bytes(b"x" * 100000)
            print("staged", flush=True)
            for _ in range(int({hold} / {NAP})):
                time.sleep({NAP})
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
    assert leftovers(tmp_path)                      # lock and staging folder exist
    proc.send_signal(sig)
    proc.wait(timeout=EXIT_WAIT)
    assert leftovers(tmp_path) == [] and not target.exists()


def test_case8_a_killed_run_is_cleaned_by_the_next(tmp_path):
    target = tmp_path / "out"
    proc = _start(_writer_script(target, HOLD))
    with pytest.raises(InputError, match="another run is writing here"):
        with staged_output(target):
            pass
    proc.kill()                                      # SIGKILL: no clean-up possible
    proc.wait(timeout=EXIT_WAIT)
    assert any(TMP_MARK in n for n in leftovers(tmp_path))
    with staged_output(target) as stage:        # the lock is free again
        (stage / "big.bin").write_text("ok")
    assert leftovers(tmp_path) == []
    assert sorted(os.listdir(target)) == [manifest_name("output"), "big.bin"]


# --- the set is exchanged whole -------------------------------------------------------------------

OLD = {"a.txt": "old-a", "b.txt": "old-b", "figures/f.svg": "old-f"}
NEW = {"a.txt": "new-a", "b.txt": "new-b", "figures/f.svg": "new-f"}


def _mover_script(target, hold, mount=False):
    """A run that pauses just after its first rename into target (old code: per file)."""
    return textwrap.dedent(f"""
        import os, time
        from gd_analyze.store import staging
        from gd_analyze.store.signals import install
        from gd_analyze.store.staging import staged_output
        install()
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
        with staged_output(target) as stage:
            for path, text in {NEW!r}.items():
                (stage / path).parent.mkdir(parents=True, exist_ok=True)
                (stage / path).write_text(text)
            print("staged", flush=True)
        """)


def _set(target):
    return {k: v.decode() for k, v in visible(target).items()}


def _old_set(target, monkeypatch, mount):
    """A folder holding the OLD set, written by a run; optionally seen as a mount point."""
    target.mkdir()
    if mount:
        ismount = os.path.ismount
        monkeypatch.setattr(os.path, "ismount",
                            lambda p: Path(p).resolve() == target.resolve() or ismount(p))
    with staged_output(target) as stage:
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
    with staged_output(target) as stage:          # the next run cleans up
        (stage / "a.txt").write_text("next")
    assert _set(target) == {"a.txt": "next"}
    assert leftovers(tmp_path) == [] and not any(TMP_MARK in n for n in os.listdir(target))


def _refuse_renaming(monkeypatch, folder):
    """The kernel's answers for a mount point (a Docker volume at /out): no rename of it, or
    across it."""
    import errno

    from gd_analyze.store import staging

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
        with staged_output(target) as stage:
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
        with staged_output(".") as stage:
            (stage / "a.txt").write_text(text)
    assert os.stat(tmp_path).st_ino == inode and _set(tmp_path) == {"a.txt": "2"}


def test_case8_without_renameat2_a_killed_swap_is_undone(tmp_path):
    target = tmp_path / "out"
    script = textwrap.dedent(f"""
        import os, signal
        from gd_analyze.store import staging
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
    assert _set(target) == {"b.txt": "3"} and leftovers(tmp_path) == []
    assert sorted(os.listdir(tmp_path)) == ["out"]


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
    with staged_output(target) as stage:
        (stage / "a.txt").write_text("next")
    assert _set(target) == {"a.txt": "next"}
    assert not any(TMP_MARK in n for n in os.listdir(target))


def test_a_refused_run_keeps_a_killed_runs_temporaries_for_the_next(tmp_path):
    target = tmp_path / "out"
    proc = _start(_writer_script(target, HOLD))
    proc.kill()                                      # SIGKILL: its staging folder stays
    proc.wait(timeout=EXIT_WAIT)
    left = leftovers(tmp_path)
    assert any(TMP_MARK in n for n in left)
    target.mkdir()
    (target / "notes.txt").write_text("the user's")
    with pytest.raises(InputError, match="did not write: notes.txt"):
        with staged_output(target):
            pass
    assert leftovers(tmp_path) == left              # refused: nothing removed, still known
    (target / "notes.txt").unlink()
    with staged_output(target) as stage:
        (stage / "a.txt").write_text("1")
    assert leftovers(tmp_path) == []
