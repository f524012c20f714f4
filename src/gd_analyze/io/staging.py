"""Output folders a run can trust: one run at a time, all files of one run, nothing half-written.

:func:`staged_output` is the one way a command writes its output folder:

- a lock file beside the folder (``.<name>.gd-lock``, held with ``flock``, so the kernel
  releases it even when a run is killed) refuses a second run into the same folder;
- every file of the run is written into a temporary folder beside the target
  (``.<name>.gd-tmp-<random>``) and moved in together once the run has succeeded; files a
  command writes that this run did not (e.g. an old report after ``--no-report``) are removed,
  so the set in the folder is from one run;
- on an error, SIGINT or SIGTERM the temporary folder is removed; the temporary folders and
  files of a killed run (SIGKILL) are removed by the next run into the same folder;
- an output location that cannot be created or written gives an
  :class:`~gd_analyze.errors.InputError` (exit status 2) and leaves nothing behind.
"""

from __future__ import annotations

import contextlib
import errno
import os
import re
import shutil
import signal
import tempfile
from pathlib import Path

from ..errors import InputError

__all__ = ["safe_name", "staged_output", "check_free_space", "check_output_file",
           "install_signal_handlers", "Terminated", "LOCK_SUFFIX", "TMP_MARK"]

LOCK_SUFFIX = ".gd-lock"
TMP_MARK = ".gd-tmp-"
#: Free space kept besides the estimate [bytes].
SPACE_MARGIN = 16 << 20


class Terminated(BaseException):
    """Raised in the main thread on SIGTERM (or SIGHUP), so that clean-up code runs."""


def _raise_terminated(signum, frame):
    raise Terminated(signum)


def install_signal_handlers():
    """Turn SIGTERM and SIGHUP into :class:`Terminated` so that ``finally`` blocks run.

    SIGINT already raises KeyboardInterrupt. Call from the main thread only.
    """
    for sig in (signal.SIGTERM, getattr(signal, "SIGHUP", None)):
        if sig is not None:
            signal.signal(sig, _raise_terminated)


def safe_name(name, fallback="robot"):
    """A robot or file name made safe as one path component.

    Parameters
    ----------
    name : str
        Any text, e.g. a robot's name from a file.
    fallback : str, optional
        Used when nothing safe remains.

    Returns
    -------
    str
        Only ASCII letters, digits, ``.``, ``_``, ``+`` and ``-`` (others become ``_``), no
        leading dot or dash, at most 80 characters: never a separator, ``..`` or an absolute
        path.

    Examples
    --------
    >>> safe_name("../../etc/x")
    'etc_x'
    >>> safe_name("/abs/path")
    'abs_path'
    >>> safe_name("puma560+payload")
    'puma560+payload'
    """
    text = re.sub(r"\.{2,}", "", str(name))
    text = re.sub(r"[^A-Za-z0-9._+-]+", "_", text).lstrip("._-")[:80].rstrip(".")
    return text or fallback


def check_output_file(path):
    """Check that a single output file can be written at ``path``.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write.

    Raises
    ------
    InputError
        If path is a folder, its folder does not exist or is not a folder, or is not writable.
    """
    p = Path(path)
    if p.is_dir():
        raise InputError("is a folder: give a file name", path)
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise InputError("its folder does not exist" if not parent.exists() else
                         "its folder is not a folder", path)
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError("cannot write in its folder (permission denied)", path)


def check_free_space(folder, need_bytes, what="the results"):
    """Refuse to start a write that cannot fit.

    Parameters
    ----------
    folder : str or os.PathLike
        Where the file goes.
    need_bytes : int
        Estimated size of the file [bytes].
    what : str, optional
        Named in the message.

    Raises
    ------
    InputError
        If the free space is below ``need_bytes`` plus a margin of 16 MiB.
    """
    free = shutil.disk_usage(folder).free
    if free < need_bytes + SPACE_MARGIN:
        raise InputError(f"not enough free space for {what}: about {need_bytes / 1e6:.0f} MB "
                         f"needed, {free / 1e6:.0f} MB free", folder)


def _oserror(exc, path):
    reason = exc.strerror or str(exc)
    if exc.errno == errno.ENOSPC:
        reason = "no space left on the device"
    return InputError(f"cannot write the output folder: {reason}", path)


def _remove_stale(parent, name, target, outputs):
    """Remove the temporary folders beside ``target``, and the temporary files of its outputs
    inside it (``.<output>.*.tmp``, as :func:`gd_analyze.files.atomic_path` names them).

    Called with the lock held: no live run owns them."""
    for p in parent.glob(f".{glob_escape(name)}{TMP_MARK}*"):
        shutil.rmtree(p, ignore_errors=True)
    if target.is_dir():
        for out in outputs:
            for p in target.glob(f".{glob_escape(out)}.*.tmp"):
                with contextlib.suppress(OSError):
                    p.unlink()


def glob_escape(text):
    """Escape glob's special characters."""
    return re.sub(r"([*?\[])", r"[\1]", text)


@contextlib.contextmanager
def _lock(lock_path, target):
    import fcntl

    while True:
        try:
            fd = os.open(lock_path, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as exc:
            raise _oserror(exc, target) from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            raise InputError("another run is writing here; wait for it to finish or choose "
                             "another output folder (-o)", target) from None
        # The previous holder may have unlinked the file between our open and our flock.
        try:
            same = os.path.samestat(os.fstat(fd), os.stat(lock_path))
        except FileNotFoundError:
            same = False
        if same:
            break
        os.close(fd)
    owner = os.getpid()
    try:
        os.write(fd, f"{owner}\n".encode())
        yield
    finally:
        if os.getpid() == owner:
            with contextlib.suppress(OSError):
                os.unlink(lock_path)
        os.close(fd)


@contextlib.contextmanager
def staged_output(target, outputs=()):
    """Write a run's files aside and move them into ``target`` together.

    Parameters
    ----------
    target : str or os.PathLike
        The output folder; created (with its parents) if missing.
    outputs : iterable of str, optional
        The names of every file (or folder of files, e.g. ``figures``) the command can write;
        those in ``target`` that this run did not write are removed when the new files are
        moved in, so the folder holds one run's set. A folder is replaced whole.

    Yields
    ------
    pathlib.Path
        The staging folder, beside ``target`` on the same filesystem: write every file there.

    Raises
    ------
    InputError
        If ``target`` exists and is not a folder, cannot be created or written, another run
        holds its lock, or a write fails for lack of space or permission. Nothing is left
        behind (the lock file and the staging folder are removed).
    """
    target = Path(target)
    if target.exists() and not target.is_dir():
        raise InputError("exists and is not a folder", target)
    parent = target.parent
    name = target.resolve().name if target.name in ("", ".", "..") else target.name
    if target.name in ("", ".", ".."):
        parent = target.resolve().parent
    missing = [a for a in [parent, *parent.parents] if not a.exists()]
    for a in [parent, *parent.parents]:
        if a.exists():
            if not a.is_dir():
                raise InputError(f"{a} is a file, not a folder", target)
            break
    try:
        parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise _oserror(exc, target) from None
    try:
        if not os.access(parent, os.W_OK | os.X_OK):
            raise InputError("cannot write the output folder: permission denied", target)
        with _staged(parent, name, target, outputs) as stage:
            yield stage
    except BaseException:
        for a in missing:                   # the folders this run created, deepest first
            with contextlib.suppress(OSError):
                a.rmdir()
        raise


@contextlib.contextmanager
def _staged(parent, name, target, outputs):
    owner = os.getpid()
    with _lock(parent / f".{name}{LOCK_SUFFIX}", target):
        _remove_stale(parent, name, target, outputs)
        try:
            stage = Path(tempfile.mkdtemp(prefix=f".{name}{TMP_MARK}", dir=parent))
        except OSError as exc:
            raise _oserror(exc, target) from None
        try:
            try:
                yield stage
            except OSError as exc:          # h5py's and the OS's write errors alike
                raise _oserror(exc, target) from None
            created = not target.exists()
            try:
                target.mkdir(exist_ok=True)
                os.chmod(stage, 0o777 & ~_umask())
                if created and not any(target.iterdir()):
                    os.replace(stage, target)              # one rename: the whole set at once
                else:
                    written = {p.name for p in stage.iterdir()}
                    for p in sorted(stage.iterdir()):
                        dest = target / p.name
                        if p.is_dir() and dest.is_dir() and not dest.is_symlink():
                            shutil.rmtree(dest)      # a folder of outputs (figures/): whole
                        os.replace(p, dest)
                    for old in set(outputs) - written:
                        dest = target / old
                        if dest.is_dir() and not dest.is_symlink():
                            shutil.rmtree(dest, ignore_errors=True)
                        else:
                            with contextlib.suppress(FileNotFoundError, IsADirectoryError):
                                dest.unlink()
            except OSError as exc:
                raise _oserror(exc, target) from None
        finally:
            if os.getpid() == owner:
                shutil.rmtree(stage, ignore_errors=True)


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask
