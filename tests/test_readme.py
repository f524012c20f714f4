"""The README cannot drift from the tool (issue 20 item 6).

It lists every option of every command exactly as ``analysis/cli_options.py`` prints them, the
exit codes, ships its picture, quotes the sample output the main job prints, lists every module
of the package (``analysis/layout.py``) and the operation counts ``opcount.operation_counts``
gives.
"""

import re
from pathlib import Path

import pytest

from gd_analyze import cli

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")


def test_every_option_of_every_command_is_in_its_table():
    parsers = {"analyze": cli.analyze_parser()}
    parsers.update({name: getattr(cli, f"{name}_parser")() for name in cli.COMMANDS
                    if name != "analyze"})
    start = README.index("### Options of every command")
    section = README[start:README.index("\n#", start + 10)]
    tables = re.split(r"^`gd-analyze ", section, flags=re.MULTILINE)[1:]
    by_command = {}
    for t in tables:
        head = t.split("`", 1)[0]
        name = "analyze" if head.startswith("ROBOT") else head.split()[0]
        by_command[name] = t.split("\n\n", 2)[1]
    for name, parser in parsers.items():
        table = by_command[name]
        for action in parser._actions:
            for opt in action.option_strings:
                assert f"`{opt}`" in table, (name, opt)


def test_exit_codes_and_picture():
    for code, word in ((0, "ok"), (1, "verification failed"), (2, "bad input"),
                       (3, "max-error"), (4, "internal error")):
        assert re.search(rf"^\| {code} \| .*{re.escape(word)}", README, re.MULTILINE), code
    picture = re.search(r"!\[[^]]*\]\(([^)]+)\)", README[:3000]).group(1)
    assert (ROOT / picture).is_file()
    assert (ROOT / "LICENSE").read_text().startswith("MIT License")
    assert "license: MIT" in (ROOT / "CITATION.cff").read_text()


# --- issue 20 item 6: a README that cannot drift -------------------------------------------
import importlib.util
import subprocess
import sys


def _load_script(name):
    spec = importlib.util.spec_from_file_location(f"analysis_{name}", ROOT / "analysis" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


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
def test_sample_output_is_what_the_main_job_prints(tmp_path):
    """The README's sample block, line by line, against a run of the main job.

    Allowed to differ: only the ``wrote`` line (the README abbreviates the files of the default
    folder; the run here writes to a temporary folder without the report). Round-off (a
    joint's error or an element below 1e-12 of its scale) prints as "≡ 0", the same on every
    platform.
    """
    block = _code_block_after("## Sample output")
    command = block[0]
    assert command == "$ gd-analyze puma560 data/puma560_trajectory.csv"
    run = subprocess.run([sys.executable, "-m", "gd_analyze.cli", "puma560",
                          str(ROOT / "data" / "puma560_trajectory.csv"), "-o",
                          str(tmp_path / "out"), "--no-report"],
                         capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert run.returncode == 0, run.stderr
    printed = run.stdout.rstrip("\n").split("\n")
    expected = block[1:]
    assert len(printed) == len(expected), "\n".join(printed)
    for want, got in zip(expected, printed):
        if want.startswith("wrote "):
            # the count and folder, not the ~2,000 characters of every path (issue 31 item 5)
            shape = r"wrote \d+ files to \S+"
            assert re.fullmatch(shape, want) and re.fullmatch(shape, got), (want, got)
            assert got.endswith(str(tmp_path / "out"))
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


def _section(start, end_marker="\n## "):
    i = README.index(start)
    return README[i:README.index(end_marker, i + len(start))]


def test_option_tables_equal_the_script_output(capsys):
    _load_script("cli_options").main()
    printed = capsys.readouterr().out.strip()
    section = _section("### Options of every command", "\n### ")
    body = section[section.index("`gd-analyze ROBOT TRAJECTORY.csv`"):].strip()
    assert body == printed, "regenerate with python analysis/cli_options.py"


def test_layout_lists_every_module_of_the_package():
    lines = _load_script("layout").lines()
    block = _code_block_after("## Layout")
    listed = {line.split()[0] for line in block if line.strip().startswith("gd_analyze/")}
    modules = {line.split()[0] for line in lines}
    assert not modules - listed, f"modules missing from the README: {sorted(modules - listed)}"
    assert not listed - modules, f"README lists modules not in the tree: {sorted(listed - modules)}"


def test_formulation_counts_are_the_counted_ones():
    from gd_analyze.formulations.opcount import book_counts, operation_counts

    counted, book = operation_counts(6), book_counts(6)
    section = _section("## Formulations")
    columns = ("lagrange-euler", "newton-euler", "gd")
    for kind in ("multiplications", "additions"):
        for label, source in (("as implemented", counted), ("Table 3.5", book)):
            row = re.search(rf"^\| {kind}, {label} \|(.*)\|$", section, re.MULTILINE)
            assert row, (kind, label)
            cells = [int(c.strip().replace(",", "")) for c in row.group(1).split("|")]
            assert cells == [source[m][kind] for m in columns], (kind, label)
    ne = counted["newton-euler"]
    total = ne["multiplications"] + ne["additions"]
    assert f"Newton-Euler {total:,} ({ne['multiplications']} + {ne['additions']})" in README


def test_how_to_read_quotes_the_sample_errors():
    """The summary's worst and other errors quoted in "How to read the report" are the sample's."""
    rows = [line.split() for line in _code_block_after("## Sample output")
            if re.match(r"^\d+ ", line)]
    rel = [float(r[4]) for r in rows]
    worst = max(range(len(rel)), key=rel.__getitem__)
    others = max(r for k, r in enumerate(rel) if k != worst)
    text = " ".join(_section("## How to read the report").split())
    assert (f"worst error is {100 * rel[worst]:.3g} % of peak |tau| at joint {worst + 1}, every "
            f"other joint within {100 * others:.3g} %") in text
    assert "32 %" not in text and "EPS = 0.01" in text


def test_quoted_costs_agree_with_the_sample_and_the_counts():
    """Costs quoted outside the sample block are the sample's and opcount's (no second copy drifts)."""
    from gd_analyze.formulations.opcount import operation_counts

    cost_line = next(line for line in _code_block_after("## Sample output")
                     if line.startswith("simplified model (recursive N-E"))
    deployed, exact, explicit, ne = (re.search(pattern, cost_line).group(1) for pattern in (
        r": ([\d,]+) operations per set point", r"exact recursive model: ([\d,]+)",
        r"full explicit model: ([\d,]+)", r"Newton-Euler as implemented: ([\d,]+)"))
    row = re.search(r"^\| PUMA 560 \(\d+ base parameters\) \| (.*)$", README, re.MULTILINE)
    cells = [c.strip() for c in row.group(1).split("|")]
    assert cells[0].split()[0] == exact and cells[4] == ne
    # the table's EPS = 0.01 column is the trajectory model; the sample deploys the region model
    assert f"the region model at EPS = 0.01 costs **{deployed}** operations" in " ".join(
        README.split())
    assert f"full explicit PUMA 560 model ({explicit} operations)" in " ".join(README.split())
    counted = operation_counts(6)
    for label, method in (("G-D", "gd"), ("L-E", "lagrange-euler")):
        total = sum(counted[method].values())
        assert f"{label} {total:,}" in README, (label, total)


@pytest.mark.slow
def test_python_api_example_runs_as_a_doctest(monkeypatch):
    """The README's notebook example (issue 30 item 6), every line of it, as a doctest from the
    repository's folder; it is where the usage starts, after the first screen's commands."""
    import doctest

    assert README.index("## Python API") < README.index("## Commands")
    assert README.index("pip install -e . && gd-analyze puma560") < 1500
    monkeypatch.chdir(ROOT)
    result = doctest.testfile(str(ROOT / "README.md"), module_relative=False,
                              optionflags=doctest.ELLIPSIS, verbose=False, report=True)
    assert result.attempted >= 10 and result.failed == 0
