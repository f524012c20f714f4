"""The on-disk cache of the measured operation counts: ``opcounts-<code>.json``.

The counts (:mod:`gd_analyze.formulations.opcount`) are a pure function of the counted code, so
the file lives in the cache folder of :func:`gd_analyze.config.cache_dir` (the derivation
cache's: ``$GD_ANALYZE_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/gd-analyze`` or
``~/.cache/gd-analyze``; none when ``GD_ANALYZE_NO_CACHE=1``) under a name that carries the SHA-256 of that code. The file
records its own format, the code's SHA-256 and, for each pattern of joint types (the key), the
counts and a SHA-256 of (format, code, key, counts). It is read only if it is a regular file of
at most :data:`LIMIT` bytes (never through a symbolic link, never blocking on a FIFO). A file
or an entry that fails (not JSON, of another type, format or code, a count that is not a
non-negative integer, a checksum that does not match: a hand-edited "Newton-Euler: 1") is
never used: one warning line says so, and the counts are measured again and stored.

A checksum is no proof: anyone who edits an entry can compute it again (a keyed MAC would need
a secret the user's machine does not keep). So the counts are always measured again when they
are used (:func:`gd_analyze.formulations.opcount.operation_counts`; milliseconds for a six-joint
arm), and an entry that differs from the recount gets one warning line
(:func:`mismatch_warning`) and is replaced: an edited entry is never printed.
"""

from __future__ import annotations

import hashlib
import json
import os
import warnings
from collections.abc import Sequence
from pathlib import Path

from ..config import cache_dir
from ..errors import InputWarning, one_line
from ..files import atomic_path, read_regular

__all__ = ["FORMAT", "LIMIT", "cache_file", "read_counts", "store_counts", "mismatch_warning"]

#: Layout of the file.
FORMAT = 2
#: Largest file read [bytes] (a few hundred bytes a pattern of joint types).
LIMIT = 1 << 20


def cache_file(code_sha256: str) -> Path | None:
    """The cache file of the counted code, or None when caching is disabled.

    Parameters
    ----------
    code_sha256 : str
        SHA-256 of the counted code (64 hexadecimal digits: the package's sources).

    Returns
    -------
    pathlib.Path or None
        ``<cache folder>/opcounts-<first 32 digits>.json``.
    """
    folder = cache_dir()
    return None if folder is None else folder / f"opcounts-{code_sha256[:32]}.json"


def _checksum(code, key, counts):
    text = json.dumps({"format": FORMAT, "code": code, "key": key, "counts": counts},
                      sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def _entries(path, code):
    """The file's entries, or the reason it is not used (a str); {} when there is none."""
    try:
        data = json.loads(read_regular(path, LIMIT, follow=False))
    except FileNotFoundError:
        return {}
    except (OSError, ValueError, RecursionError) as exc:
        return f"cannot be read ({' '.join(str(exc).split())[:120]})"
    if not (isinstance(data, dict) and data.get("format") == FORMAT
            and data.get("code") == code and isinstance(data.get("entries"), dict)):
        return "is not a gd-analyze operation-count file of this format and code"
    return data["entries"]


def _valid_counts(counts, methods):
    return (isinstance(counts, dict) and set(counts) == set(methods)
            and all(isinstance(v, list) and len(v) == 2
                    and all(type(x) is int and x >= 0 for x in v) for v in counts.values()))


def read_counts(path: Path, code: str, key: str,
                methods: Sequence[str]) -> dict[str, tuple[int, ...]] | None:
    """The stored counts of ``key``, or None (with one warning line if an entry failed).

    Parameters
    ----------
    path : pathlib.Path
        :func:`cache_file`.
    code : str
        The counted code's SHA-256, which the file must record.
    key : str
        The pattern of joint types.
    methods : sequence of str
        The methods every entry must count.

    Returns
    -------
    dict of str to tuple of int or None
        ``{method: (multiplications, additions)}``.

    Warns
    -----
    InputWarning
        When the file or the entry exists but fails: it is counted again.
    """
    entries = _entries(path, code)
    entry = entries.get(key) if isinstance(entries, dict) else None
    if isinstance(entries, str):
        reason = entries
    elif entry is None:
        return None
    elif not (isinstance(entry, dict) and _valid_counts(entry.get("counts"), methods)
              and entry.get("checksum") == _checksum(code, key, entry["counts"])):
        reason = f"entry {key[:40]!r} fails its checksum"
    else:
        return {m: tuple(v) for m, v in entry["counts"].items()}
    warnings.warn(one_line(f"{path}: operation-count cache {reason}: ignored, the operations "
                           "are counted again"), InputWarning, stacklevel=2)
    return None


def mismatch_warning(path: Path, key: str, stored: dict[str, tuple[int, ...]],
                     counted: dict[str, tuple[int, ...]]) -> None:
    """One warning line: a cache entry that passed its checksum differs from the recount.

    Parameters
    ----------
    path : pathlib.Path
        :func:`cache_file`.
    key : str
        The pattern of joint types.
    stored, counted : dict of str to tuple of int
        ``{method: (multiplications, additions)}`` of the entry and of the recount.

    Warns
    -----
    InputWarning
        Naming the file, the entry and the first method that differs.
    """
    method = next(m for m in counted if tuple(stored.get(m, ())) != tuple(counted[m]))
    said, got = stored.get(method), counted[method]
    warnings.warn(one_line(
        f"{path}: operation-count cache entry {key[:40]!r} differs from the recount ({method}: "
        f"{list(said) if said is not None else None} stored, {list(got)} counted): ignored, "
        "the recount is used and stored"), InputWarning, stacklevel=3)


def store_counts(path: Path, code: str, key: str, counts: dict[str, tuple[int, ...]]) -> None:
    """Add ``key``'s counts to the file atomically; silent when it cannot be written.

    Parameters
    ----------
    path : pathlib.Path
    code : str
    key : str
    counts : dict of str to tuple of int
    """
    import stat

    try:
        if not stat.S_ISREG(os.lstat(path).st_mode):
            return                  # a link, a FIFO, a device: never replaced
    except FileNotFoundError:
        pass
    except OSError:
        return
    entries = _entries(path, code)
    entries = entries if isinstance(entries, dict) else {}
    plain = {m: [int(x) for x in v] for m, v in counts.items()}
    entries[key] = {"counts": plain, "checksum": _checksum(code, key, plain)}
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with atomic_path(path) as tmp:
            with open(tmp, "w", encoding="utf-8") as fh:
                json.dump({"tool": "gd-analyze", "format": FORMAT, "code": code,
                           "entries": entries}, fh)
    except OSError:
        pass        # a read-only home: count again next time
