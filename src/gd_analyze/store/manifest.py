"""Which files of an output folder gd-analyze wrote: one manifest per command.

Every command that writes an output folder (the main job, ``control``, ``sweep``) records the
files of its run in ``.gd-analyze-manifest-<command>.json`` inside the folder: each file's path
relative to the folder, its size [bytes] and SHA-256, with the tool's version and the command.

Before a run touches a folder, :func:`folder_owners` reads every manifest and walks the folder.
A file that no manifest lists, or a file a manifest lists whose bytes changed since (a user's
own ``report.html`` saved over ours), was not written by gd-analyze: the run is refused with one
line and nothing is touched. A command replaces only the files its own previous manifest lists;
the files of the other commands' manifests are kept as they are.
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import stat
import sys
import threading
import time
from collections.abc import Collection, Iterator, Mapping
from concurrent.futures import Future
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import InputError
from ..files import file_sha256, read_regular

__all__ = ["MANIFEST_PREFIX", "RESERVED_PREFIX", "FolderOwners", "manifest_name",
           "folder_owners", "write_manifest", "write_transition", "walk_files", "hash_beside"]

MANIFEST_PREFIX = ".gd-analyze-manifest-"
#: The prefix of gd-analyze's own names: its manifests (inside the folder), its lock and its
#: temporaries (``.gd-lock``, ``.gd-tmp-<random>`` inside a folder that is a mount point;
#: ``.<folder>.gd-lock``, ``.<folder>.gd-tmp-<random>`` beside it). A name with the prefix that
#: gd-analyze did not register is a user's file like any other.
RESERVED_PREFIX = ".gd-"
#: Largest manifest read [bytes].
MANIFEST_LIMIT = 64 << 20
#: Foreign files named in the refusal, at most (the walk stops after one more).
SHOWN = 8
_COMMAND = re.compile(r"[a-z][a-z0-9_-]{0,40}")


def manifest_name(command: str) -> str:
    """The manifest's file name of ``command``.

    Parameters
    ----------
    command : str
        The command's name: lower-case letters, digits, ``_`` and ``-``.

    Returns
    -------
    str
        ``.gd-analyze-manifest-<command>.json``.

    Raises
    ------
    ValueError
        If the name is not a plain command name.

    Examples
    --------
    >>> manifest_name("control")
    '.gd-analyze-manifest-control.json'
    """
    if not _COMMAND.fullmatch(str(command)):
        raise ValueError(f"not a command name: {command!r}")
    return f"{MANIFEST_PREFIX}{command}.json"


@dataclass
class FolderOwners:
    """Who wrote what in an output folder, as its manifests say.

    Attributes
    ----------
    own : dict of str to dict
        The files the command's previous manifest lists and the folder holds unchanged
        (relative POSIX path to its manifest entry): the run may replace them.
    others : dict of str to str
        The files of the other commands' manifests (path to the command): kept as they are.
    manifests : list of str
        The manifests' names, the command's own included.
    empty_dirs : list of str
        Folders that hold nothing (kept).
    """

    own: dict = field(default_factory=dict)
    others: dict = field(default_factory=dict)
    manifests: list = field(default_factory=list)
    empty_dirs: list = field(default_factory=list)


def walk_files(root: str | os.PathLike[str], empty_dirs: list[str] | None = None,
               skip: Collection[str] = ()) -> Iterator[tuple[str, os.stat_result]]:
    """The entries under ``root`` that are not folders (each folder's in sorted order), without following a
    symbolic link; the manifests (top-level names starting ``.gd-analyze-manifest-``) and the
    top-level names in ``skip`` (the run's lock and registered temporaries) are left out.

    Parameters
    ----------
    root : str or os.PathLike
        A folder.
    empty_dirs : list, optional
        Receives the relative paths of the folders that hold nothing.
    skip : collection of str, optional
        Top-level names to leave out.

    Yields
    ------
    path : str
        Relative POSIX path of a regular file, symbolic link or other non-folder entry.
    st : os.stat_result
        Its ``lstat``.

    Raises
    ------
    OSError
        If a folder cannot be listed.
    """
    todo = [(os.fspath(root), "")]         # a stack, not recursion: any depth of folders
    while todo:
        folder, rel = todo.pop()
        with os.scandir(folder) as it:
            entries = sorted(it, key=lambda e: e.name)
        if rel and not entries and empty_dirs is not None:
            empty_dirs.append(rel)
        subfolders = []
        for e in entries:
            if not rel and (e.name.startswith(MANIFEST_PREFIX) or e.name in skip):
                continue
            path = f"{rel}/{e.name}" if rel else e.name
            st = e.stat(follow_symlinks=False)
            if stat.S_ISDIR(st.st_mode):
                subfolders.append((e.path, path))
            else:
                yield path, st
        todo.extend(reversed(subfolders))


def _read_manifest(folder, name):
    """The manifest's ``(command, files)``, or None if it is not a manifest gd-analyze wrote."""
    try:
        data = json.loads(read_regular(os.path.join(folder, name), MANIFEST_LIMIT, follow=False))
    except (OSError, ValueError, RecursionError):     # RecursionError: nested 100,000 deep
        return None
    if not isinstance(data, dict) or data.get("tool") != "gd-analyze" \
            or not isinstance(data.get("files"), dict) \
            or not _COMMAND.fullmatch(str(data.get("command"))) \
            or name != manifest_name(data["command"]):
        return None
    good = {}
    for path, entry in data["files"].items():
        parts = str(path).split("/")
        if (_valid(entry) and path and not path.startswith("/")
                and all(p not in ("", ".", "..") for p in parts)
                and not parts[0].startswith(RESERVED_PREFIX)):
            also = entry.get("also")
            good[path] = {**entry, "also": [e for e in also if _valid(e)]
                          if isinstance(also, list) else []}
    return data["command"], good


def _valid(entry):
    return (isinstance(entry, dict) and isinstance(entry.get("sha256"), str)
            and isinstance(entry.get("size"), int))


#: How long before it is hashed a file's status must have last changed [ns] for its digest to
#: be kept for this process's later checks (:func:`_digest`).
SETTLED_NS = 1_000_000_000
#: Digests kept, at most (then the memo starts again).
_KEPT = 256
_DIGESTS: dict[tuple[int, ...], str] = {}
#: Files at least this large [bytes], settled, are hashed beside the run by the first check.
DEFERRED_BYTES = 16 << 20
#: The digests being made beside the run (:func:`_defer`), by the same key as the memo.
_PENDING: dict[tuple[int, ...], Future] = {}


def _digest(path, st):
    """The file's SHA-256, hashed once per process while its status stays the same.

    A run checks its folder twice, before it computes and again before it moves its files in:
    the second check reuses the first's digest of a file whose device, inode, size,
    modification and change times are all unchanged. Any write to a file sets its change time
    to the clock's current tick, and no user can set it back (``touch -r`` and ``cp -p`` set
    only the modification time). A digest is kept only when the change time was already
    :data:`SETTLED_NS` old when the file was hashed, so that a later write cannot fall in the
    same tick; a file written more recently is hashed every time.
    """
    key = _key(st)
    known = _DIGESTS.get(key)
    if known is not None:
        return known
    pending = _PENDING.get(key)             # being hashed beside the run (_defer): its digest
    if pending is not None and pending.exception() is None:     # of this very status, waited
        return pending.result()
    settled = time.time_ns() - st.st_ctime_ns > SETTLED_NS
    digest = file_sha256(path)
    if settled:
        _remember(key, digest)
    return digest


def _remember(key, digest):
    """Keep a settled file's digest (the memo starts again beyond :data:`_KEPT` entries)."""
    if len(_DIGESTS) >= _KEPT:
        _DIGESTS.clear()
    _DIGESTS[key] = digest


def _key(st):
    """A file's status as the digests' key: device, inode, size, modification and change
    times."""
    return (st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns, st.st_ctime_ns)


def _defer(path, st):
    """Start hashing a large settled file on a thread of its own, for the folder's second
    check; False (nothing started) for a small file, one changed within :data:`SETTLED_NS`
    or one already hashed, which the first check looks at itself.

    The digest is made from the status taken before hashing began and goes into
    :func:`_digest`'s memo, whose rule (an unchanged status) the second check applies. A
    file the thread cannot read is hashed again by the second check, which reports the
    error. The thread only reads; it does not hold the process at exit.
    """
    key = _key(st)
    if (st.st_size < DEFERRED_BYTES or time.time_ns() - st.st_ctime_ns <= SETTLED_NS
            or key in _DIGESTS):
        return False
    if key not in _PENDING:
        _PENDING[key] = future = _hashing(path, "gd-analyze-digest", nice=True)

        def done(future):                   # a file it cannot read: the second check says why
            if future.exception() is None:
                _remember(key, future.result())
            _PENDING.pop(key, None)
        future.add_done_callback(done)
    return True


def _hashing(path, name, nice=False):
    """A Future of the file's SHA-256 (or of the OSError that stopped it), made on a thread
    ``name`` of its own, which only reads and does not hold the process at exit; with
    ``nice``, at the processor time the run leaves (:func:`_yield_cpu`)."""
    future: Future = Future()

    def work():
        if nice:
            _yield_cpu()
        try:
            future.set_result(file_sha256(path))
        except OSError as exc:
            future.set_exception(exc)
    threading.Thread(target=work, name=name, daemon=True).start()
    return future


def _unchanged(folder, path, entry, st, defer=False):
    """Whether the file still holds the bytes the manifest recorded (or, in a transition
    manifest, the bytes of the set being replaced: ``also``). With ``defer``, a large settled
    file of the right size passes now and is hashed beside the run (:func:`_defer`): the
    second check compares its digest."""
    accepted = [e for e in [entry, *entry.get("also", [])] if e["size"] == st.st_size]
    if not stat.S_ISREG(st.st_mode) or not accepted:
        return False
    if defer and _defer(os.path.join(folder, path), st):
        return True
    # Always the SHA-256 (once per process while the status is the same): a same-size edit
    # with its mtime put back (cp -p, touch -r) changed it.
    digest = _digest(os.path.join(folder, path), st)
    return any(e["sha256"] == digest for e in accepted)


def folder_owners(folder: str | os.PathLike[str], command: str,
                  shown_as: str | os.PathLike[str] | None = None,
                  skip: Collection[str] = (), defer: bool = False) -> FolderOwners:
    """Read the manifests of an output folder and check that gd-analyze wrote every file.

    Parameters
    ----------
    folder : str or os.PathLike
        The output folder (it may not exist: then it holds nothing).
    command : str
        The command about to write it.
    shown_as : str, optional
        The folder as the user named it, for the message.
    skip : collection of str, optional
        Top-level names that are the run's own lock and registered temporaries.
    defer : bool, optional
        The check before a run computes: files of at least :data:`DEFERRED_BYTES` whose
        change time is older than :data:`SETTLED_NS` are checked by name and size now, and
        hashed on a thread beside the run; the check before the new set is moved in
        (``defer`` False) compares their SHA-256 and refuses a changed one, before anything
        is touched.

    Returns
    -------
    FolderOwners

    Raises
    ------
    InputError
        ``"<folder> holds files gd-analyze did not write: <paths>; use an empty or new
        folder"`` if a file is listed by no manifest, or a listed file was changed since.
    """
    folder = Path(folder)
    owners = FolderOwners()
    if not folder.is_dir():
        return owners
    foreign, more = [], False
    listed: dict[str, tuple[Any, Any]] = {}
    try:
        for name in sorted(n for n in os.listdir(folder) if n.startswith(MANIFEST_PREFIX)):
            read = _read_manifest(folder, name)
            if read is None:
                foreign.append(name)
                continue
            owners.manifests.append(name)
            for path, entry in read[1].items():
                listed.setdefault(path, (read[0], entry))
        for path, st in walk_files(folder, owners.empty_dirs, skip):
            cmd, entry = listed.get(path, (None, None))
            if cmd is not None and cmd != command:
                owners.others[path] = cmd
            elif cmd is not None and _unchanged(folder, path, entry, st, defer):
                owners.own[path] = entry
            else:
                foreign.append(path)
                if len(foreign) > SHOWN:        # a wrong -o (a home folder): stop looking
                    more = True
                    break
    except OSError as exc:
        raise InputError(f"cannot read the output folder: {exc.strerror or exc}",
                         shown_as or folder) from None
    if foreign:
        names = ", ".join(sorted(foreign)[:SHOWN]) + (" and more" if more else "")
        raise InputError(f"{shown_as or folder} holds files gd-analyze did not write: "
                         f"{names}; use an empty or new folder")
    return owners


def write_manifest(folder: str | os.PathLike[str], command: str, version: str) -> list[str]:
    """Record every file under ``folder`` (a run's new set) in the command's manifest there.

    Parameters
    ----------
    folder : str or os.PathLike
        The staging folder holding only this run's files.
    command : str
        The command that wrote them.
    version : str
        gd-analyze's version.

    Returns
    -------
    list of str
        The relative paths recorded.

    Raises
    ------
    OSError
        If a file cannot be read or the manifest cannot be written (it is created new, never
        through a symbolic link).
    """
    entries = {}
    for path, st in walk_files(folder):
        if not stat.S_ISREG(st.st_mode):
            continue                            # a run writes regular files only
        full = os.path.join(folder, path)
        entries[path] = {"sha256": _staged_digest(full, st), "size": st.st_size}
    _write_new(os.path.join(folder, manifest_name(command)),
               {"tool": "gd-analyze", "format": 1, "version": str(version),
                "command": command, "files": entries})
    return list(entries)


def _yield_cpu():
    """Lower the calling thread's scheduling priority (Linux: the nice value of one thread;
    elsewhere nothing): a digest wanted only at the run's end takes the processor time the
    run's computation leaves."""
    if not sys.platform.startswith("linux"):  # elsewhere the id would name a process
        return
    with contextlib.suppress(AttributeError, OSError):
        os.setpriority(os.PRIO_PROCESS, threading.get_native_id(), 19)


def hash_beside(path: str | os.PathLike[str]) -> None:
    """Start hashing a finished file of a run's staging folder on a thread of its own, for
    :func:`write_manifest` (a large ``results.h5`` is hashed while the run writes the rest).

    The digest is used only if the file's device, inode, size, modification and change times
    are still those taken before hashing began; otherwise the manifest hashes it again. The
    staging folder is the run's own (mode 0700). The thread only reads.

    Parameters
    ----------
    path : str or os.PathLike
        A regular file in the staging folder, closed.
    """
    full = os.path.abspath(path)
    try:
        key = _key(os.stat(full))
    except OSError:
        return                                  # write_manifest reports it
    _STAGED[full] = (key, _hashing(full, "gd-analyze-digest-out"))


def _staged_digest(path, st):
    """A staged file's SHA-256: the one :func:`hash_beside` made if the file's status is
    unchanged since, else hashed now."""
    known = _STAGED.pop(os.path.abspath(path), None)
    if known is not None and known[0] == _key(st):
        with contextlib.suppress(OSError):      # hashed again, which reports the error
            return known[1].result()
    return file_sha256(path)


#: Files being hashed by :func:`hash_beside`: absolute path -> (status key, Future of digest).
_STAGED: dict[str, tuple[tuple, Future]] = {}


def _write_new(path, data):
    """Write JSON to a file created new, never through a symbolic link."""
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o666)
    with os.fdopen(fd, "w", encoding="utf-8") as fh:
        fh.write(json.dumps(data, indent=1))


def write_transition(folder: str | os.PathLike[str], command: str,
                     old: Mapping[str, Mapping[str, Any]], name: str) -> None:
    """A manifest that accepts the old set and the new one, put in place while the sets are
    exchanged entry by entry (a mount point): after a SIGKILL in between, the next run still
    knows every file as the command's own and replaces the lot.

    Parameters
    ----------
    folder : str or os.PathLike
        The staging folder, holding the command's new manifest.
    command : str
        The command.
    old : dict of str to dict
        The entries of the files the run replaces (:attr:`FolderOwners.own`).
    name : str
        The file to write in ``folder``.

    Raises
    ------
    OSError
        If the new manifest cannot be read or the file cannot be written.
    """
    data = json.loads(Path(folder, manifest_name(command)).read_text(encoding="utf-8"))
    files = data["files"]
    for path, entry in old.items():
        base = {k: entry[k] for k in ("sha256", "size")}
        if path not in files:
            files[path] = base
        elif files[path]["sha256"] != base["sha256"]:
            files[path] = {**files[path], "also": [base]}
    _write_new(os.path.join(folder, name), data)
