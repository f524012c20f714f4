"""What a staged output folder leaves behind, for the staging tests (tests/io/test_staging*.py),
and the console script run under a file size limit (the commands' tests)."""

import os
import subprocess
import sys
from pathlib import Path

from gd_analyze.store.staging import LOCK_SUFFIX, TMP_MARK


def leftovers(parent):
    """Names in parent that are locks or temporaries of a staged output, sorted."""
    return sorted(p.name for p in Path(parent).iterdir() if LOCK_SUFFIX in p.name
                  or TMP_MARK in p.name or p.name.endswith(".tmp"))


def tree(folder):
    """Every file under folder (hidden ones too) with its bytes."""
    return {p.relative_to(folder).as_posix(): p.read_bytes()
            for p in sorted(Path(folder).rglob("*")) if p.is_file() or p.is_symlink()}


def visible(folder):
    """:func:`tree` without gd-analyze's own hidden ``.gd-`` entries (manifests, locks)."""
    return {k: v for k, v in tree(folder).items() if not k.startswith(".gd-")}


def run_limited(args, cwd, limit):
    """``python -m gd_analyze.cli ARGS`` in a child process, in ``cwd``, under a file size limit
    (RLIMIT_FSIZE, ``ulimit -f``) of ``limit`` bytes set before it starts; the completed
    process, its output as text."""
    import resource

    return subprocess.run([sys.executable, "-m", "gd_analyze.cli", *map(str, args)], cwd=cwd,
                          capture_output=True, text=True, timeout=300,
                          env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)),
                          preexec_fn=lambda: resource.setrlimit(
                              resource.RLIMIT_FSIZE, (limit, resource.RLIM_INFINITY)))


def refused_by_the_limit(run, folder):
    """The run stopped with exit 2 and one line naming the file size limit, no traceback, and
    left nothing in ``folder`` (the parent of its output folder)."""
    assert run.returncode == 2, run.stderr[-2000:]
    lines = run.stderr.splitlines()
    assert len(lines) == 1 and "the file size limit (ulimit -f)" in lines[0], run.stderr
    assert list(Path(folder).iterdir()) == []
