"""The README cannot drift from the tool.

It gives the exit codes, ships its picture, quotes the sample output the main job prints and
runs its Python example. The option tables, the module list and the operation counts moved to
the reference pages in docs/, checked by ``tests/test_docs.py``.
"""

import re
from pathlib import Path

import pytest
from conftest import golden_run

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")


def test_exit_codes_and_picture():
    for code, word in ((0, "ok"), (1, "verification failed"), (2, "bad input"),
                       (3, "max-error"), (4, "internal error")):
        assert re.search(rf"^\| {code} \| .*{re.escape(word)}", README, re.MULTILINE), code
    picture = re.search(r"!\[[^]]*\]\(([^)]+)\)", README[:3000]).group(1)
    assert (ROOT / picture).is_file()
    assert (ROOT / "LICENSE").read_text().startswith("MIT License")
    assert "license: MIT" in (ROOT / "CITATION.cff").read_text()


def test_the_first_screen_keeps_the_two_commands_for_a_fresh_machine():
    first_screen = "\n".join(README.split("\n")[:24])
    for command in ("python3 -m venv .venv && . .venv/bin/activate && pip install -e . && "
                    "gd-analyze puma560 data/puma560_trajectory.csv",
                    'bash .ci/system-packages && python3 -m venv .venv && . .venv/bin/activate && '
                    'pip install -e ".[test]" '
                    "&& python -m pytest -q -n auto"):
        assert f"\n    {command}\n" in first_screen, command


# --- the sample output, run ---------------------------------------------------------------


def _code_block_after(heading):
    """The first fenced or indented code block after a heading, as lines."""
    start = README.index(heading)
    rest = README[start:].split("\n")
    for i, line in enumerate(rest):
        if line.startswith("```"):
            end = rest.index("```", i + 1)
            return rest[i + 1:end]
        if line.startswith("    ") and i > 0 and not rest[i - 1].strip():
            block = []
            for later in rest[i:]:
                if later.startswith("    ") or not later.strip():
                    block.append(later)
                else:
                    break
            while block and not block[-1].strip():
                block.pop()
            return block
    raise AssertionError(f"no code block after {heading!r}")


@pytest.mark.slow
def test_sample_output_is_what_the_main_job_prints():
    """The README's sample block, line by line, against a run of the main job.

    Allowed to differ: only the ``wrote`` line (the README abbreviates the files of the default
    folder; the run here writes to a temporary folder without the report). Round-off (a
    joint's error or an element below 1e-12 of its scale) prints as "≡ 0", the same on every
    platform. The run is golden case puma560's (``gd-analyze puma560
    data/puma560_trajectory.csv --no-report``, conftest's golden_run, in the test's process:
    the console script itself is run by test_one_code_path).
    """
    block = _code_block_after("## Reading the summary")
    command = block[0]
    assert command == "$ gd-analyze puma560 data/puma560_trajectory.csv"
    (root, *_), text = golden_run("puma560")       # shared, read only
    out = root / "puma560"
    printed = text.rstrip("\n").split("\n")
    expected = block[1:]
    assert len(printed) == len(expected), "\n".join(printed)
    for want, got in zip(expected, printed):
        if want.startswith("wrote "):
            # the count and folder, not the ~2,000 characters of every path
            shape = r"wrote \d+ files to \S+"
            assert re.fullmatch(shape, want) and re.fullmatch(shape, got), (want, got)
            assert got.endswith(str(out))
            continue
        if want.startswith("simplified model (") and got.startswith("simplified model ("):
            # the recursive models' counts come from symengine's CSE, which finds one
            # operation more or less between interpreters (the exact model 320 on Python
            # 3.10-3.12, 319 on 3.13; the region model 312 (169 + 143), 311 (169 + 142) on
            # 3.13); every other number of the line must agree
            for pattern in (r"exact recursive model: (\d+)", r": (\d+) operations per set point",
                            r"(\d+) multiplications", r"(\d+) additions"):
                count = re.compile(pattern)
                w, g = int(count.search(want).group(1)), int(count.search(got).group(1))
                assert abs(w - g) <= 1, (want, got)
                want, got = count.sub("", want), count.sub("", got)
        assert want == got


@pytest.mark.slow
def test_python_api_example_runs_as_a_doctest(monkeypatch):
    """The README's notebook example, every line of it, as a doctest from the repository's
    folder; the first screen keeps the command that installs and runs the main job."""
    import doctest

    assert README.index("## Python API") < README.index("## Exit codes")
    assert README.index("pip install -e . && gd-analyze puma560") < 1500
    monkeypatch.chdir(ROOT)
    result = doctest.testfile(str(ROOT / "README.md"), module_relative=False,
                              optionflags=doctest.ELLIPSIS, verbose=False, report=True)
    assert result.attempted >= 10 and result.failed == 0
