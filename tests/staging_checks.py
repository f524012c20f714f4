"""What a staged output folder leaves behind, for the staging tests (tests/io/test_staging*.py)."""

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
