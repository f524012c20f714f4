"""On-disk cache of the explicit model's derivation, keyed by SHA-256.

The explicit model (:func:`gd_analyze.core.explicit.derive`) is a pure function of the robot's
parameters and of the deriving code, so the cache file is named by the SHA-256 of both: the
robot's canonical parameters (its file's SHA-256 and the parameters actually used, so a robot
carrying a payload gets its own entry) and the source of the deriving modules. The folder is
``$GD_ANALYZE_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/gd-analyze`` or
``~/.cache/gd-analyze``; ``GD_ANALYZE_NO_CACHE=1`` disables it. An unwritable or corrupt cache
is ignored: the model is derived again.
"""

from __future__ import annotations

import hashlib
import json
import os
from importlib import resources
from pathlib import Path

import numpy as np

__all__ = ["cache_dir", "explicit_terms"]

_DERIVING = ("core/explicit.py", "core/trigpoly.py")
_FIELDS = ("kind", "part", "i", "j", "k", "K", "S", "C")


def cache_dir():
    """The cache folder, or None when caching is disabled.

    Returns
    -------
    pathlib.Path or None
    """
    if os.environ.get("GD_ANALYZE_NO_CACHE"):
        return None
    if os.environ.get("GD_ANALYZE_CACHE_DIR"):
        return Path(os.environ["GD_ANALYZE_CACHE_DIR"])
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "gd-analyze"


def _key(robot):
    digest = hashlib.sha256()
    digest.update(robot.sha256.encode())
    digest.update(json.dumps(robot.to_dict(), sort_keys=True).encode())
    for name in _DERIVING:
        digest.update(resources.files("gd_analyze").joinpath(name).read_bytes())
    return digest.hexdigest()


def explicit_terms(robot):
    """All terms of the robot's explicit G-D model, from the cache or derived afresh.

    Parameters
    ----------
    robot : Robot
        The arm.

    Returns
    -------
    terms : gd_analyze.core.explicit.Term
        The terms (:func:`gd_analyze.core.explicit.model_terms`).
    seconds : float
        Time the derivation took now (0.0 when read from the cache).
    """
    import time

    from ..core.explicit import Term, derive, model_terms

    folder = cache_dir()
    path = None if folder is None else folder / f"explicit-{_key(robot)[:40]}.npz"
    if path is not None and path.is_file():
        try:
            with np.load(path, allow_pickle=False) as z:
                return Term(*(z[f] for f in _FIELDS)), 0.0
        except (OSError, ValueError, KeyError):
            pass
    t0 = time.perf_counter()
    terms = model_terms(derive(robot))
    seconds = time.perf_counter() - t0
    if path is not None:
        try:
            folder.mkdir(parents=True, exist_ok=True)
            tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp.npz")
            np.savez(tmp, **{f: getattr(terms, f) for f in _FIELDS})
            os.replace(tmp, path)
        except OSError:
            pass        # read-only cache: derive again next time
    return terms, seconds
