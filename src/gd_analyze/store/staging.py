"""Output folders a run can trust: one run at a time, one run's set, never a user's file.

:func:`staged_output` is the one way a command writes its output folder:

- the folder is taken by its real path (a symbolic link to it names the same folder) and locked
  with ``flock`` on a lock file beside it (``.<name>.gd-lock``; inside it, ``.gd-lock``, when
  the folder is a mount point), opened without following a symbolic link, so a second run into
  the same folder is refused and the kernel releases the lock even when a run is killed;
- the folder's manifests (:mod:`gd_analyze.store.manifest`) must list every file it holds: a
  file gd-analyze did not write is never replaced or deleted; the run is refused, with one line
  and exit status 2, before it computes anything, and nothing is touched (a large listed file
  edited in place to the same size is found by its SHA-256, made beside the run, and refused
  before anything is moved in);
- every file of the run is written into a fresh staging folder (``.<name>.gd-tmp-<random>``:
  an unpredictable name, mode 0700, registered in the lock file before it is created) beside
  the target; it also receives, as hard links, the files
  of the other commands' manifests, so that ``control`` and the main job can share a folder
  and neither replaces the other's files; the command's manifest (paths, sizes, SHA-256, tool
  version) is written there too;
- the staging folder then takes the target's place in one ``renameat2(RENAME_EXCHANGE)``
  (Linux): an interruption leaves the old set or the new set, whole. SIGINT, SIGTERM and SIGHUP
  are held back during the exchange and delivered after it. Where the target cannot be
  exchanged (a mount point, such as a Docker volume at ``/out``, or the current folder of the
  run, which a shell would keep open), the run stages inside the target and exchanges its
  top-level entries one by one, the new manifest last (only SIGKILL can split that set; a
  manifest that knows both sets is in place meanwhile, so the next run replaces it whole). Without
  ``renameat2`` (other systems, old C libraries) the target is renamed aside and the new
  folder renamed in; a run killed between the two renames is undone by the next run;
- on an error, SIGINT or SIGTERM the staging folder is removed; the temporaries of a killed
  run (SIGKILL) are removed by the next run into the same folder, only those its lock file
  registered and only once the folder passed its check: a refused run removes nothing, and a
  name that merely looks like gd-analyze's (``.gd-notes.txt``) is a user's file;
- an output location that cannot be created or written gives an
  :class:`~gd_analyze.errors.InputError` (exit status 2) and leaves nothing behind. Inside a
  run, :func:`writing` turns the write errors (and only those: a full disk, an HDF5 error) of
  the calls it wraps into one line: an :class:`OSError` of a write, an error that a full disk
  caused anywhere in an exception's chain (h5py reports ENOSPC when the file is closed, as
  another error), and an error the HDF5 library raised inside h5py or h5netcdf; before that,
  the h5netcdf files a failed close left half-open are marked closed, so that their
  finalizers do not flush again into a file HDF5 has torn down (a SIGSEGV on a full disk);
  an error of h5py's finalizers inside it is the write's error, not a traceback each;
- a single output file (``plan -o``) is written only over a regular file or a new name
  (:func:`check_output_file`).
"""

from __future__ import annotations

import contextlib
import ctypes
import errno
import functools
import os
import re
import secrets
import shutil
import signal
import stat
import sys
from collections.abc import Iterator
from pathlib import Path

from .._version import VERSION as __version__
from ..errors import InputError
from ..files import current_umask
from .manifest import folder_owners, manifest_name, write_manifest, write_transition
from .signals import SIGNALS, Terminated, without_teardown

__all__ = ["safe_name", "staged_output", "writing", "write_error", "full_disk_error", "is_inside", "check_free_space", "check_output_file",
           "Terminated", "LOCK_SUFFIX", "TMP_MARK"]

LOCK_SUFFIX = ".gd-lock"
TMP_MARK = ".gd-tmp-"
#: Largest lock record read [bytes]: a pid and a few temporary names.
RECORD_LIMIT = 1 << 16
#: Free space kept besides the estimate [bytes].
SPACE_MARGIN = 16 << 20


def safe_name(name: str, fallback: str = "robot") -> str:
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


def check_output_file(path: str | os.PathLike[str]) -> None:
    """Check that a single output file can be written at ``path``: only a regular file is ever
    replaced.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write.

    Raises
    ------
    InputError
        If path is a folder; a device, FIFO or socket (``/dev/null``: the atomic rename would
        replace it); a symbolic link (to anything: a link is neither written through nor
        replaced); or its folder does not exist, is not a folder, or is not writable.
    """
    p = Path(path)
    try:
        mode = os.lstat(p).st_mode
    except OSError:
        mode = None
    if mode is not None and stat.S_ISLNK(mode):
        raise InputError("is a symbolic link: give the file itself or a new name (a link is "
                         "never written through or replaced)", path)
    if mode is not None and stat.S_ISDIR(mode):
        raise InputError("is a folder: give a file name" if str(path) else "no file name", path)
    if mode is not None and not stat.S_ISREG(mode):
        raise InputError("is not a regular file (a device, FIFO or socket): give a file name",
                         path)
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise InputError("its folder does not exist" if not parent.exists() else
                         "its folder is not a folder", path)
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError("cannot write in its folder (permission denied)", path)


def check_free_space(folder: str | os.PathLike[str], need_bytes: int,
                     what: str = "the results") -> None:
    """Refuse to start a write that cannot fit.

    Parameters
    ----------
    folder : str or os.PathLike
        Where the file goes; a folder not yet created is checked on the nearest existing
        folder above it (where it will be created), so a command can refuse before it
        computes. A folder that cannot be written, or on a file system without blocks
        (``/proc``), is not checked: the write refuses it ("cannot write").
    need_bytes : int
        Estimated size of the file [bytes].
    what : str, optional
        Named in the message.

    Raises
    ------
    InputError
        If the free space, or the process's file size limit (``ulimit -f``, RLIMIT_FSIZE),
        is below ``need_bytes`` plus a margin of 16 MiB: HDF5 may crash the process on a
        write the limit cuts short, before any message.
    """
    where = Path(folder).absolute()
    while not os.path.exists(where) and where != where.parent:
        where = where.parent
    usage = shutil.disk_usage(where)
    if usage.total == 0 or not os.access(where, os.W_OK | os.X_OK):
        return      # /proc and the like (no blocks), or not writable: the write refuses it
    free = usage.free
    if free < need_bytes + SPACE_MARGIN:
        raise InputError(f"not enough free space for {what}: about {need_bytes / 1e6:.0f} MB "
                         f"needed and a margin of {SPACE_MARGIN / 2**20:.0f} MiB, "
                         f"{free / 1e6:.0f} MB free", folder)
    try:
        import resource
    except ImportError:                 # not a Unix system: no such limit
        return
    most = resource.getrlimit(resource.RLIMIT_FSIZE)[0]
    if most != resource.RLIM_INFINITY and most < need_bytes + SPACE_MARGIN:
        raise InputError(f"the file size limit (ulimit -f) is {most / 1e6:.3g} MB, below "
                         f"{what}'s about {need_bytes / 1e6:.0f} MB and a margin of "
                         f"{SPACE_MARGIN / 2**20:.0f} MiB: raise it", folder)


@contextlib.contextmanager
def _lock(lock_path, target):
    import fcntl

    while True:
        try:
            fd = os.open(lock_path, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW | os.O_NONBLOCK
                         | os.O_CLOEXEC, 0o644)
        except OSError as exc:
            if exc.errno == errno.ELOOP:
                raise InputError(f"cannot write the output folder: its lock file {lock_path} "
                                 "is a symbolic link", target) from None
            raise write_error(exc, target) from None
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode) or st.st_nlink != 1:     # a FIFO, a hard link
            os.close(fd)
            raise InputError(f"cannot write the output folder: its lock file {lock_path} is "
                             "not a file of its own", target)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            raise InputError("another run is writing here; wait for it to finish or choose "
                             "another output folder (-o)", target) from None
        # The previous holder may have unlinked the file between our open and our flock.
        try:
            same = os.path.samestat(os.fstat(fd), os.lstat(lock_path))
        except FileNotFoundError:
            same = False
        if same:
            break
        os.close(fd)
    owner, record = os.getpid(), None
    try:
        with writing(target):           # a full disk: one line, as any write of the run
            before = os.pread(fd, RECORD_LIMIT, 0).decode("utf-8", "replace")
            os.ftruncate(fd, 0)
            os.write(fd, f"{owner}\n".encode())
            record = _Record(fd, before)
        yield record
    finally:
        if os.getpid() == owner and not (record is not None and record.pending):
            with contextlib.suppress(OSError):
                os.unlink(lock_path)
        os.close(fd)


class _Record:
    """The lock file's record of the temporary names a run creates, written before each is
    created: the next run removes only the names a killed run registered, never a user's file
    that merely looks like one."""

    def __init__(self, fd, before):
        self.fd = fd
        self.before = [line.split(" ", 1) for line in before.splitlines()[1:]
                       if line.count(" ") == 1]
        self.pending = bool(self.before)    # kept until removed: a refused run keeps them
        for where, name in self.before:
            self.register(where, name)

    def register(self, where, name):
        """Record ``name`` (``beside`` the target, or ``inside`` it) before it is created."""
        os.write(self.fd, f"{where} {name}\n".encode())

    def stale(self, where, pattern):
        """The names the previous holder registered ``where`` that match ``pattern``."""
        return [n for w, n in self.before if w == where and re.fullmatch(pattern, n)]


RENAME_NOREPLACE, RENAME_EXCHANGE = 1, 2


@functools.cache
def _libc_renameat2():
    if not sys.platform.startswith("linux"):
        return None
    try:
        fn = ctypes.CDLL(None, use_errno=True).renameat2
    except (OSError, AttributeError):
        return None
    fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    fn.restype = ctypes.c_int
    return fn


def _renameat2(src, dst, flags):
    """``renameat2(src, dst, flags)``; False where the system or file system lacks it."""
    fn = _libc_renameat2()
    if fn is None:
        return False
    if fn(-100, os.fsencode(src), -100, os.fsencode(dst), flags) == 0:     # AT_FDCWD
        return True
    err = ctypes.get_errno()
    if err in (errno.EINVAL, errno.ENOSYS, errno.EOPNOTSUPP):
        return False
    raise OSError(err, os.strerror(err), os.fspath(src), None, os.fspath(dst))


@contextlib.contextmanager
def _signals_held():
    """Hold SIGINT, SIGTERM and SIGHUP back while the sets are exchanged; deliver them after."""
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return
    got, old = [], {}
    for sig in SIGNALS:
        if signal.getsignal(sig) is not None:
            old[sig] = signal.signal(sig, lambda signum, frame: got.append(signum))
    try:
        yield
    finally:
        for sig, handler in old.items():
            signal.signal(sig, handler)
        for sig in got[:1]:
            signal.raise_signal(sig)


def _conflict(new, owners):
    """The first new path that would replace a file of another command's manifest (the file,
    a folder above it, or a file where the path has a folder), with that command; or None."""
    taken = owners.others               # reversed: the first file under a folder names it
    dirs = {folder: cmd for path, cmd in reversed(taken.items()) for folder in _folders(path)}
    for path in new:
        cmd = taken.get(path) or dirs.get(path) or next(
            (taken[folder] for folder in _folders(path) if folder in taken), None)
        if cmd is not None:
            return path, cmd
    return None


def _folders(path):
    """The folders above a relative path: ``a`` and ``a/b`` for ``a/b/c``."""
    parts = path.split("/")
    return ["/".join(parts[:k]) for k in range(1, len(parts))]


def _carry(real, stage, owners, command, tops=None):
    """Hard-link the other commands' files (and manifests, and empty folders) into stage."""
    own = manifest_name(command)
    keep = [*owners.others, *(m for m in owners.manifests if m != own)]
    for path in [*keep, *owners.empty_dirs]:
        if tops is not None and path.split("/")[0] not in tops:
            continue
        dst = stage / path
        if path in owners.empty_dirs:
            dst.mkdir(parents=True, exist_ok=True)
            continue
        dst.parent.mkdir(parents=True, exist_ok=True)
        try:
            os.link(real / path, dst, follow_symlinks=False)
        except OSError:                          # another file system, or links forbidden
            shutil.copy2(real / path, dst, follow_symlinks=False)


#: The longest suffix a sibling name adds to the folder's: ``.`` + ``.gd-tmp-`` + the 16 hex
#: digits of a temporary's token.
_SIBLING_EXTRA = 1 + len(TMP_MARK) + 16


def sibling_stem(parent: Path, name: str) -> str:
    """The folder's name as it appears in the names of its siblings (lock, staging, previous
    set): the name itself, or where that would make a sibling's name longer than the file
    system allows, its first characters and the SHA-256 of the whole name.

    Parameters
    ----------
    parent : pathlib.Path
        The folder that holds the output folder.
    name : str
        The output folder's name.

    Returns
    -------
    str

    Examples
    --------
    >>> len(sibling_stem(Path("/tmp"), "f" * 245)) <= 255 - _SIBLING_EXTRA
    True
    >>> sibling_stem(Path("/tmp"), "out")
    'out'
    """
    try:
        limit = os.pathconf(parent, "PC_NAME_MAX")
    except (OSError, ValueError):
        limit = 255
    room = limit - _SIBLING_EXTRA
    if len(os.fsencode(name)) <= room:
        return name
    import hashlib

    digest = hashlib.sha256(os.fsencode(name)).hexdigest()[:16]
    head = os.fsencode(name)[:max(room - 17, 1)].decode(errors="ignore")
    return f"{head}-{digest}"


@contextlib.contextmanager
def staged_output(target: str | os.PathLike[str], command: str = "output") -> Iterator[Path]:
    """Write a run's files aside and put them into ``target`` as one set.

    Parameters
    ----------
    target : str or os.PathLike
        The output folder; created (with its parents) if missing. A symbolic link to a folder
        names that folder.
    command : str, optional
        The command writing the folder (``analyze``, ``control``, ``sweep``): its manifest
        ``.gd-analyze-manifest-<command>.json`` lists the run's files; the run replaces the
        files of its own previous manifest and keeps the other commands'.

    Yields
    ------
    pathlib.Path
        The staging folder (empty, mode 0700): write every file of the run there.

    Raises
    ------
    InputError
        If ``target`` exists and is not a folder, holds files gd-analyze did not write (before
        the run computes anything; a large file edited to the same size, before the set is
        moved in), cannot be created or written, another run holds its lock,
        a new file would replace another command's file, or the set cannot be moved in. Then
        the folder is as it was, and the lock file and the staging folder are removed.
    """
    manifest_name(command)                  # a plain command name, or ValueError
    target = Path(target)
    for a in [target, *target.parents]:     # never create folders through a dangling link
        if a.is_symlink() and not a.exists():
            raise InputError(f"{a} is a symbolic link to nothing", target)
    real = Path(os.path.realpath(target))
    if real.exists() and not real.is_dir():
        raise InputError("exists and is not a folder", target)
    parent, name = real.parent, real.name
    missing = [a for a in [parent, *parent.parents] if not a.exists()]
    first = next((a for a in [parent, *parent.parents] if a.exists()), None)
    if first is not None and not first.is_dir():
        raise InputError(f"{first} is a file, not a folder", target)
    try:
        parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise write_error(exc, target) from None
    mount = real.is_dir() and os.path.ismount(real)
    try:
        if not all(os.access(a, os.W_OK | os.X_OK) for a in {real if mount else parent,
                                                             *([real] if real.is_dir() else [])}):
            raise InputError("cannot write the output folder: permission denied", target)
        stem = sibling_stem(parent, name)
        lock = real / LOCK_SUFFIX if mount else parent / f".{stem}{LOCK_SUFFIX}"
        with _lock(lock, target) as record:
            # the temporaries a killed run registered: beside the target, and inside it
            temporary = re.escape(f".{stem}{TMP_MARK}") + r"[0-9a-f]{16}"
            beside, prev = record.stale("beside", temporary), record.stale("prev", temporary)
            inside = record.stale("inside", re.escape(TMP_MARK) + r"[0-9a-f]{16}")
            with writing(target):   # a run killed between its two renames: the old set back
                for p in (parent / n for n in prev):
                    if p.is_dir() and not p.is_symlink() and not os.path.lexists(real):
                        os.rename(p, real)
            skip = {*inside, *([LOCK_SUFFIX] if mount else [])}
            folder_owners(real, command, target, skip, defer=True)   # refuse before the run computes
            # they go after the folder's check (no live run owns them, and a refused run
            # removes nothing), with the lock held
            with writing(target):
                for p in [*(parent / n for n in [*beside, *prev]), *(real / n for n in inside)]:
                    if p.is_dir() and not p.is_symlink():
                        shutil.rmtree(p, ignore_errors=True)
                record.pending = False
            with _staged(real, target, command, mount, record) as stage:
                yield stage
    except BaseException:
        for a in missing:                   # the folders this run created, deepest first
            with contextlib.suppress(OSError):
                a.rmdir()
        raise


@contextlib.contextmanager
def _staged(real, target, command, mount, record):
    owner = os.getpid()
    try:                                    # the run's current folder, which a shell keeps open
        holds_cwd = is_inside(os.path.realpath(os.getcwd()), real)
    except OSError:                         # removed
        holds_cwd = False
    inside = real.is_dir() and (mount or holds_cwd)      # not exchanged whole: staged inside
    stage = _new_temporary(real if inside else real.parent,
                           TMP_MARK if inside else
                           f".{sibling_stem(real.parent, real.name)}{TMP_MARK}",
                           record, "inside" if inside else "beside", target)
    try:
        yield stage
        skip = {stage.name, *([LOCK_SUFFIX] if mount else [])}
        owners = folder_owners(real, command, target, skip)   # files added meanwhile
        with writing(target):
            new = write_manifest(stage, command, __version__)
        clash = _conflict(new, owners)
        if clash:
            path, other = clash
            raise InputError(f"{target} holds {path} of gd-analyze {other}; a command never "
                             "replaces another command's files: use an empty or new folder")
        with writing(target):
            if inside:
                _swap_entries(real, stage, owners, command, new)
            else:
                _swap_folder(real, stage, owners, command, record)
    finally:
        if os.getpid() == owner:
            shutil.rmtree(stage, ignore_errors=True)


def _new_temporary(where, prefix, record, kind, target):
    """Create the folder ``<prefix><random>`` (mode 0700) in ``where``, registered first."""
    for _ in range(16):
        path = Path(where) / f"{prefix}{secrets.token_hex(8)}"
        try:
            record.register(kind, path.name)
            path.mkdir(mode=0o700)
            return path
        except FileExistsError:
            continue
        except OSError as exc:
            raise write_error(exc, target) from None
    raise InputError("cannot write the output folder: no free temporary name", target)


def _swap_folder(real, stage, owners, command, record):
    """Put the staged folder in the target's place in one exchange; the old set ends in stage."""
    _carry(real, stage, owners, command)
    mode = stat.S_IMODE(os.stat(real).st_mode) if real.is_dir() else 0o777 & ~current_umask()
    fd = os.open(stage, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW)    # never a link
    try:
        os.fchmod(fd, mode)
    finally:
        os.close(fd)
    with _signals_held():
        if not real.is_dir():
            if not _renameat2(stage, real, RENAME_NOREPLACE):
                os.rename(stage, real)      # fails on a folder created meanwhile, not empty
        elif not _renameat2(stage, real, RENAME_EXCHANGE):
            prev = (real.parent
                    / f".{sibling_stem(real.parent, real.name)}{TMP_MARK}{secrets.token_hex(8)}")
            record.register("prev", prev.name)
            os.rename(real, prev)           # no exchange here: two renames, undone if killed
            try:
                os.rename(stage, real)
            except OSError:
                os.rename(prev, real)
                raise
            os.rename(prev, stage)


def _swap_entries(real, stage, owners, command, new):
    """Exchange the top-level entries the command owns one by one, under a manifest that
    knows both sets; the new manifest last."""
    own = manifest_name(command)
    tops = {p.split("/")[0] for p in [*owners.own, *new]}
    _carry(real, stage, owners, command, tops)
    old = stage / f"{TMP_MARK}old"
    old.mkdir()
    write_transition(stage, command, owners.own, f"{TMP_MARK}manifest")
    with _signals_held():
        os.replace(stage / f"{TMP_MARK}manifest", real / own)    # knows both sets
        for top in sorted(tops):
            src, dst = stage / top, real / top
            if not os.path.lexists(src):
                os.rename(dst, old / top)   # ours, not in the new set
            elif not os.path.lexists(dst):
                if not _renameat2(src, dst, RENAME_NOREPLACE):
                    os.rename(src, dst)
            elif not _renameat2(src, dst, RENAME_EXCHANGE):
                os.rename(dst, old / top)
                os.rename(src, dst)
        os.replace(stage / own, real / own)          # the new set's own, last


def write_error(exc: OSError, path: str | os.PathLike[str]) -> InputError:
    """The one-line error of a failed write into an output location.

    Parameters
    ----------
    exc : OSError
        The error (ENOSPC reads "no space left on the device").
    path : str or os.PathLike
        The output location, as the message names it.

    Returns
    -------
    InputError
    """
    return InputError(f"cannot write the output folder: {_reason(exc)}", path)


def _reason(exc):
    if exc.errno in _FULL:              # h5py's strerror is HDF5's whole report
        return ("no space left on the device" if exc.errno == errno.ENOSPC
                else os.strerror(exc.errno or 0).lower())
    return exc.strerror or str(exc)


def full_disk_error(exc: BaseException) -> InputError | None:
    """The one-line error of a write outside the output folder that a full disk, a disk quota or
    the file size limit (``ulimit -f``) stopped, such as numba's cache of compiled kernels
    beside the installed package; None if none of those is in the exception's chain.

    Parameters
    ----------
    exc : BaseException
        An exception a command raised; its causes and contexts are searched too.

    Returns
    -------
    InputError or None
        Names the file, where the error gives it: an operational failure (exit status 2),
        not a bug.
    """
    full = _disk_full(exc)
    if full is None:
        return None
    return InputError(f"cannot write: {_reason(full)}",
                      full.filename if isinstance(full.filename, str) else None)


def is_inside(name: str | bytes | os.PathLike[str] | os.PathLike[bytes],
              folder: str | os.PathLike[str]) -> bool:
    """Whether the path ``name`` is ``folder`` or under it (both made absolute, not resolved).

    Parameters
    ----------
    name : str, bytes or os.PathLike
    folder : str or os.PathLike

    Returns
    -------
    bool

    Examples
    --------
    >>> is_inside("/a/b/c", "/a/b"), is_inside("/a/bc", "/a/b")
    (True, False)
    """
    try:                            # both normalised: a comparison of their parts
        return Path(os.path.abspath(os.fsdecode(name))).is_relative_to(os.path.abspath(folder))
    except TypeError:               # not a path (a file descriptor)
        return False


@contextlib.contextmanager
def writing(target: str | os.PathLike[str],
            stage: str | os.PathLike[str] | None = None) -> Iterator[None]:
    """Report the write errors of the enclosed calls as "cannot write the output folder".

    Parameters
    ----------
    target : str or os.PathLike
        The output folder, as the message names it.
    stage : str or os.PathLike, optional
        The staging folder the calls write in: an :class:`OSError` naming a file outside it
        (a file the calls read) is not a write error and propagates unchanged.

    Raises
    ------
    InputError
        On an :class:`OSError` of a write (h5py's write errors name no file); on an error of
        the HDF5 library (an ``OSError`` or ``RuntimeError`` raised inside h5py or h5netcdf,
        such as the one a full disk gives when the file is closed); on any error that a full
        disk (ENOSPC, EDQUOT, EFBIG) caused.
    """
    failed: list[BaseException] = []
    hooks = sys.unraisablehook, sys.excepthook

    def caught(value):              # an error of h5py's finalizers after a failed write
        if value is None or (_disk_full(value) is None and not _from_hdf5(value)):
            return False
        failed.append(value)
        return True
    # Cython prints such an error through both hooks: one line in the end, not a traceback each
    sys.unraisablehook = lambda u: caught(u.exc_value) or hooks[0](u)
    sys.excepthook = lambda kind, value, tb: caught(value) or hooks[1](kind, value, tb)
    try:
        yield
        if failed:                      # a write failed where only a finalizer saw it
            raise failed[0]
    except OSError as exc:
        names = [n for n in (exc.filename, exc.filename2) if n is not None]
        if stage is not None and names and not any(is_inside(n, stage) for n in names):
            raise
        _disarm_hdf5()
        raise write_error(_disk_full(exc) or exc, target) from None
    except Exception as exc:
        _disarm_hdf5()
        full = _disk_full(exc)
        if full is not None:
            raise write_error(full, target) from None
        if isinstance(exc, RuntimeError) and _from_hdf5(exc):
            raise InputError("cannot write the output folder: HDF5 error: "
                             + " ".join(str(exc).split())[:160], target) from None
        raise
    finally:
        sys.unraisablehook, sys.excepthook = hooks


def _disarm_hdf5():
    """After a failed write: mark the h5netcdf files open for writing that a failed close left
    half-open as closed, so that their finalizers (and xarray's) do not flush again into a file
    HDF5 has torn down: on a full disk that second flush was a SIGSEGV. (Every file a command
    writes is in its staging folder, which the failed run removes.)"""
    import gc

    h5netcdf = sys.modules.get("h5netcdf")
    if h5netcdf is None:
        return
    without_teardown()
    for obj in gc.get_objects():
        if (isinstance(obj, h5netcdf.File) and not getattr(obj, "_closed", True)
                and getattr(obj, "_mode", "r") != "r"):
            obj._closed = True      # h5netcdf's own flag: close() and __del__ then do nothing


_FULL = (errno.ENOSPC, getattr(errno, "EDQUOT", errno.ENOSPC), errno.EFBIG)


def _disk_full(exc):
    """The OSError of a full disk in the exception's chain (its causes and contexts), or None."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        seen.add(id(exc))
        said = [e for e in _FULL if f"errno = {e}," in str(exc)]     # in HDF5's words
        if isinstance(exc, OSError) and exc.errno in _FULL:
            return exc
        if isinstance(exc, (OSError, RuntimeError)) and said:
            return OSError(said[0], os.strerror(said[0]))
        exc = exc.__cause__ or exc.__context__
    return None


def _from_hdf5(exc):
    """Whether the exception was raised inside h5py or h5netcdf (an HDF5 library error)."""
    import traceback

    frames = traceback.extract_tb(exc.__traceback__)
    return bool(frames) and any(part in frames[-1].filename.replace("\\", "/")
                                for part in ("h5py/", "h5netcdf/"))
