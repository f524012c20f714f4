"""Rewrite the golden files of ``tests/golden/`` from a run of this checkout.

    python tests/golden/regenerate.py             # every case
    python tests/golden/regenerate.py puma560 ur5 # some cases

Runs each case of :data:`freeze.CASES` in a temporary folder (its own derivation cache, so no
cached certification is reused) and replaces the case's folder here with its frozen files;
``git diff tests/golden`` then shows the change for review.
"""

import os
import shutil
import sys
import tempfile
from pathlib import Path


def regenerate(names):
    """Run the cases ``names`` (all when empty) and rewrite their golden folders."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from golden.freeze import CASES, GOLDEN, run_all

    unknown = [n for n in names if n not in CASES]
    if unknown:
        sys.exit(f"regenerate.py: unknown case {', '.join(unknown)}; cases: {', '.join(CASES)}")
    with tempfile.TemporaryDirectory(prefix="gd-analyze-golden-") as tmp:
        os.environ["XDG_CACHE_HOME"] = str(Path(tmp) / "cache")
        for name in ("GD_ANALYZE_NO_CACHE", "GD_ANALYZE_CACHE_DIR"):
            os.environ.pop(name, None)
        frozen = run_all(Path(tmp) / "runs", list(names) or None)
    for case, files in frozen.items():
        folder = GOLDEN / case
        shutil.rmtree(folder, ignore_errors=True)
        folder.mkdir()
        for name, text in files.items():
            (folder / name).write_text(text, encoding="utf-8")
        print(f"wrote {len(files)} golden files to {folder.relative_to(GOLDEN.parents[1])}")


if __name__ == "__main__":
    regenerate(sys.argv[1:])
