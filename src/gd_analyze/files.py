"""File utilities shared by every layer: atomic writes, content hashes and the code's hash.

A leaf module like :mod:`gd_analyze.errors`: it imports nothing from the package, so the core
(a simplified model's JSON), the derivation cache (:mod:`gd_analyze.cache`), io, workflows and
reports can all write files atomically and record their SHA-256 for provenance;
:func:`package_sha256` is the code part of every cache key.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path

__all__ = ["atomic_path", "current_umask", "file_sha256", "read_regular", "TooLarge",
           "sources_sha256", "package_sha256"]


def file_sha256(path: str | os.PathLike[str]) -> str:
    """SHA-256 of a file's bytes, read in blocks.

    Parameters
    ----------
    path : str or os.PathLike
        The file.

    Returns
    -------
    str
        64 hexadecimal digits.

    Raises
    ------
    OSError
        If the file cannot be read.
    """
    digest = hashlib.sha256()
    block = bytearray(1 << 20)              # one buffer, read into: no new bytes per block
    view = memoryview(block)
    with open(path, "rb", buffering=0) as fh:
        while size := fh.readinto(block):
            digest.update(view[:size])
    return digest.hexdigest()


def sources_sha256(root: str | os.PathLike) -> str:
    """SHA-256 of every Python source below a folder: each file's path and bytes, by path.

    Parameters
    ----------
    root : str or os.PathLike
        The folder (a package's).

    Returns
    -------
    str
        64 hexadecimal digits; any edited, added, removed or renamed ``.py`` file changes it.

    Raises
    ------
    OSError
        If a file cannot be read.
    """
    root = Path(root)
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py"), key=lambda p: p.relative_to(root).as_posix()):
        data = path.read_bytes()
        digest.update(f"{path.relative_to(root).as_posix()}\0{len(data)}\0".encode())
        digest.update(data)
    return digest.hexdigest()


@functools.cache
def package_sha256() -> str:
    """SHA-256 of the installed package's sources (:func:`sources_sha256` of ``gd_analyze``),
    computed once per process: the code part of every cache key, so no list of "the modules
    a result depends on" can go stale.

    Returns
    -------
    str
        64 hexadecimal digits.
    """
    return sources_sha256(Path(__file__).resolve().parent)


class TooLarge(ValueError):
    """A file read with :func:`read_regular` is larger than its limit."""


def read_regular(path: str | os.PathLike[str], limit: int, follow: bool = True) -> bytes:
    """The bytes of a regular file of at most ``limit`` bytes, read without blocking.

    A FIFO, socket or device (or a symbolic link to one: ``/dev/zero``) is never read, so a
    reader neither hangs on a FIFO nor fills the memory from a device.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    limit : int
        Largest size accepted [bytes].
    follow : bool, optional
        False: a symbolic link is refused too (``O_NOFOLLOW``).

    Returns
    -------
    bytes

    Raises
    ------
    OSError
        If the file cannot be opened or read, or is not a regular file (``EINVAL``).
    TooLarge
        If it holds more than ``limit`` bytes (a ``ValueError``).

    Examples
    --------
    >>> read_regular("/dev/zero", 10)
    Traceback (most recent call last):
    ...
    OSError: [Errno 22] not a regular file: '/dev/zero'
    """
    import errno
    import stat

    flags = os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC | (0 if follow else os.O_NOFOLLOW)
    fd = os.open(path, flags)
    with os.fdopen(fd, "rb", buffering=0) as fh:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise OSError(errno.EINVAL, "not a regular file", os.fspath(path))
        if st.st_size > limit:
            raise TooLarge(f"{os.fspath(path)}: larger than {limit} bytes")
        data = fh.read(limit + 1)
    if len(data) > limit:
        raise TooLarge(f"{os.fspath(path)}: larger than {limit} bytes")
    return data


def current_umask() -> int:
    """The process's file mode creation mask, left as it is.

    Returns
    -------
    int
        The umask (read by setting it and setting it back: POSIX has no call that only reads
        it), e.g. ``0o022``.
    """
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str], create: bool = True) -> Iterator[str]:
    """Yield a temporary file name beside ``path``; rename it to ``path`` on success.

    The temporary name is unpredictable and created new with the final mode (never through a
    symbolic link), and the rename replaces whatever ``path`` is without following it.

    Parameters
    ----------
    path : str or os.PathLike
        The final destination. Its folder must exist.
    create : bool, optional
        False: the name is left free for a writer that creates the file itself, new
        (``O_CREAT | O_EXCL``, which never follows a symbolic link, with mode 0666 less the
        umask). Opening the empty file again with ``O_TRUNC`` instead makes ext4 write all
        of it back on close (its ``auto_da_alloc``): half a second for a 1.3 GB results.h5.

    Yields
    ------
    str
        The temporary name to write to. On an exception it is removed and ``path`` is left as
        it was.

    Raises
    ------
    OSError
        If the temporary file cannot be created or renamed.
    """
    path = Path(path)
    # mkstemp: an unpredictable name, created new (O_EXCL), never through a symbolic link
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.gd-tmp-", suffix=".tmp",
                               dir=path.parent or ".")
    try:
        os.fchmod(fd, 0o666 & ~current_umask())     # mkstemp makes 0600; the usual mode,
    finally:            # set on the file itself: a name swapped meanwhile is never followed
        os.close(fd)
    if not create:
        os.remove(tmp)                  # the writer creates it new (O_EXCL) or fails
    try:
        yield tmp
        os.replace(tmp, path)           # a rename replaces a symbolic link, never follows it
    except BaseException:
        with contextlib.suppress(OSError):
            os.remove(tmp)
        raise
