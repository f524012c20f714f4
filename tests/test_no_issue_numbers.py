"""No issue numbers in the package's code or in the documentation.

The developers' guide: issue numbers go in commit messages, not in the code. Every ``.py`` file
under src/ (comments, docstrings and strings alike), README.md and every Markdown page of docs/
is searched for "issue 29", "Issues 8 and 17", "issue-8", "issue #31" (case-insensitive).
"""

import pathlib
import re

import gd_analyze

ROOT = pathlib.Path(__file__).resolve().parent.parent
PACKAGE = pathlib.Path(gd_analyze.__file__).resolve().parent

#: An issue number: "issue", "issues", then a number after a space, a hyphen or a "#".
ISSUE = re.compile(r"\bissues?(?:[ -]#?|#)\d+", re.IGNORECASE)

#: Files another branch is still editing, with the number of occurrences they may keep. Remove
#: an entry once that branch is merged: the test fails while an entry allows more than is left.
ALLOWED: dict[str, int] = {}


def files(root, package):
    """The files searched: every .py under the package, README.md and docs/**/*.md.

    Parameters
    ----------
    root : pathlib.Path
        The repository's root.
    package : pathlib.Path
        The package's folder (src/gd_analyze).

    Returns
    -------
    list of pathlib.Path
    """
    found = sorted(package.rglob("*.py")) + sorted((root / "docs").rglob("*.md"))
    readme = root / "README.md"
    return found + ([readme] if readme.is_file() else [])


def occurrences(paths, root):
    """Where an issue number occurs.

    Parameters
    ----------
    paths : iterable of pathlib.Path
        The files to search.
    root : pathlib.Path
        The folder the reported paths are relative to.

    Returns
    -------
    dict of str to list of str
        Per file (POSIX path relative to ``root``) with at least one, its ``"line: text"``,
        once per occurrence.
    """
    out = {}
    for path in paths:
        for k, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            for _ in ISSUE.finditer(line):
                out.setdefault(path.relative_to(root).as_posix(), []).append(f"{k}: {line}")
    return out


def test_no_issue_numbers_in_the_code_or_the_documentation():
    paths = files(ROOT, PACKAGE)
    assert len(paths) > 100 and ROOT / "README.md" in paths      # the scan sees everything
    found = occurrences(paths, ROOT)
    offences = [f"{f}:{hit}" for f, hits in found.items() if f not in ALLOWED for hit in hits]
    assert not offences, "issue numbers (they go in commit messages):\n" + "\n".join(offences)
    for f, allowed in ALLOWED.items():
        n = len(found.get(f, []))
        assert n <= allowed, f"{f}: {n} issue numbers, {allowed} allowed:\n" + "\n".join(found[f])
        assert n == allowed, (f"{f} has {n} issue numbers left: set its entry in ALLOWED "
                              f"to {n} (remove it at 0)")


def test_the_check_finds_every_form(tmp_path):
    package, docs = tmp_path / "src" / "pkg", tmp_path / "docs"
    package.mkdir(parents=True)
    docs.mkdir()
    (package / "a.py").write_text('"""Clean."""\n# fixed in Issue 29\nx = "see issues 8 and 17"\n')
    (package / "b.py").write_text("# the issue-8 rule; issue #31\n# an issue, not a number\n")
    (docs / "c.md").write_text("Said once (issue 31 item 2).\n")
    (tmp_path / "README.md").write_text("No tissue 5 here, and reissued 3 times.\n")
    found = occurrences(files(tmp_path, package), tmp_path)
    assert found == {"src/pkg/a.py": ["2: # fixed in Issue 29", '3: x = "see issues 8 and 17"'],
                     "src/pkg/b.py": ["1: # the issue-8 rule; issue #31"] * 2,
                     "docs/c.md": ["1: Said once (issue 31 item 2)."]}
