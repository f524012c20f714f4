"""The reference pages in docs/ and the README cannot drift from the tool.

Every ``gd-analyze ...`` command in a code block of README.md or docs/*.md parses with the
command line's own parsers, and the cheap ones (``plan`` without ``--excitation``,
``compare``) run. Every page linked from the README, from a page or from ``mkdocs.yml``
exists; the README stays at most 300 lines. The option tables are those
``analysis/cli_options.py`` prints from the parsers; the layout lists every module
(``analysis/layout.py``); the operation counts quoted are those ``opcount`` counts; the README's
C program compiles with the README's compile line against the emitted model, and it and the
CasADi example agree with Pinocchio's ``rnea`` within the model's guarantee.
"""

import importlib.util
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import golden_run

from gd_analyze import cli
from gd_analyze.errors import InputError
from gd_analyze.model.robots import builtin_robots

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")
DOCS = ROOT / "docs"
PAGES = {p.name: p.read_text(encoding="utf-8") for p in sorted(DOCS.glob("*.md"))}
COMMAND_WORD = "gd-analyze"


# --- code blocks and the commands in them ---------------------------------------------------

def code_blocks(text):
    """The code blocks of a Markdown text, fenced or indented by four spaces, as lists of lines.

    Parameters
    ----------
    text : str
        Markdown.

    Returns
    -------
    list of (str, list of str)
        Each block's info string ("" for an indented block) and its lines.
    """
    blocks, lines, i = [], text.split("\n"), 0
    while i < len(lines):
        line = lines[i]
        fence = re.match(r"^(\s*)(```+)(.*)$", line)
        if fence:
            indent, marks, info = fence.groups()
            end = next(k for k in range(i + 1, len(lines))
                       if lines[k].strip().startswith(marks) and not lines[k].strip(marks).strip())
            blocks.append((info.strip(), [b[len(indent):] for b in lines[i + 1:end]]))
            i = end + 1
            continue
        if line.startswith("    ") and line.strip() and (i == 0 or not lines[i - 1].strip()):
            block = []
            while i < len(lines) and (lines[i].startswith("    ") or not lines[i].strip()):
                block.append(lines[i][4:])
                i += 1
            while block and not block[-1].strip():
                block.pop()
            blocks.append(("", block))
            continue
        i += 1
    return blocks


def commands(text):
    """Every ``gd-analyze`` command in the code blocks of a Markdown text, as argument lists.

    A command starts a line (after an optional ``$ `` prompt) or follows ``&&``; it ends at the
    next ``&&`` or at the end of the line; a ``#`` comment is dropped.
    """
    found = []
    for info, block in code_blocks(text):
        if info not in ("", "console", "sh", "bash", "shell"):
            continue
        for line in block:
            for part in re.split(r"\s&&\s", line):
                part = part.strip().removeprefix("$ ")
                if part.startswith(COMMAND_WORD + " "):
                    found.append(shlex.split(part, comments=True)[1:])
    return found


def all_commands():
    """(where, arguments) of every command in the README and the reference pages."""
    pairs = [("README.md", c) for c in commands(README)]
    for name, text in PAGES.items():
        pairs += [(f"docs/{name}", c) for c in commands(text)]
    return pairs


def parse(arguments):
    """Parse a command line with the parser of its command, as :func:`cli.main` picks it.

    Raises
    ------
    InputError
        Where the parser refuses the command line (argparse's own SystemExit, for ``--help``
        and ``--version``, passes through).
    """
    command = arguments[0] if arguments and arguments[0] in cli.COMMANDS else "analyze"
    rest = arguments[1:] if arguments and arguments[0] == command else arguments
    parser = cli.parsing.analyze_parser() if command == "analyze" else getattr(cli.parsing, f"{command}_parser")()
    return command, parser.parse_intermixed_args(rest)


def test_the_extractor_finds_the_readme_commands_and_a_bad_one_fails():
    found = commands(README)
    assert ["puma560", "data/puma560_trajectory.csv"] in found            # the first screen
    assert ["sweep", "puma560", "--random", "1000", "--seed", "0", "-o", "reports/sweep"] in found
    assert not any(c and c[0] in ("-m", "install") for c in found)
    bad = "text\n\n    gd-analyze puma560 data/puma560_trajectory.csv --no-such-option\n"
    with pytest.raises(InputError):
        parse(commands(bad)[0])
    with pytest.raises(InputError):
        parse(commands("```\n$ gd-analyze plan puma560 -o x.csv [--start DEG,..]\n```\n")[0])


def test_every_command_in_the_readme_and_the_docs_parses():
    pairs = all_commands()
    assert len(pairs) >= 20 and {w for w, _ in pairs} >= {"README.md", "docs/commands.md"}
    used = set()
    for where, arguments in pairs:
        try:
            command, _ = parse(arguments)
        except (InputError, SystemExit) as exc:
            pytest.fail(f"{where}: gd-analyze {shlex.join(arguments)}: {exc}")
        used.add(command)
    assert used >= {"analyze", "plan", "sweep", "identify", "evaluate", "compare", "control"}


def _cheap(arguments):
    """A command cheap enough to run in a test: plan (not an excitation) or compare, on files
    that exist in the repository."""
    if not arguments or arguments[0] not in ("plan", "compare") or "--excitation" in arguments:
        return False
    command, args = parse(arguments)
    paths = [args.robot] + ([args.trajectory] if command == "compare" else [])
    return all(p in builtin_robots() or (ROOT / p).is_file() for p in paths)


@pytest.mark.slow
def test_the_cheap_commands_run(tmp_path):
    """plan and compare, as written, in a folder holding the repository's data/."""
    cheap = [(w, c) for w, c in all_commands() if _cheap(c)]
    assert {c[0] for _, c in cheap} == {"plan", "compare"}
    (tmp_path / "data").symlink_to(ROOT / "data")
    runs = {}                  # a command written on two pages runs once: the same process
    for where, arguments in cheap:
        if tuple(arguments) not in runs:
            runs[tuple(arguments)] = subprocess.run(
                [sys.executable, "-m", "gd_analyze.cli", *arguments], capture_output=True,
                text=True, cwd=tmp_path, timeout=600)
        run = runs[tuple(arguments)]
        assert run.returncode == 0, (where, arguments, run.stderr)
        if arguments[0] == "plan":
            out = Path(tmp_path, arguments[arguments.index("-o") + 1])
            header = out.read_text().split("\n", 1)[0]
            assert header.startswith("t,q1,"), (where, header)
        else:                  # compare: the four formulations agree with one another
            pairs = [line.split() for line in run.stdout.split("\n") if " vs " in line]
            assert any(p[:3] == ["gd", "vs", "pinocchio"] for p in pairs), run.stdout
            assert all(0 <= float(x) < 1e-10 for p in pairs for x in p[3:]), run.stdout


# --- pages and links -------------------------------------------------------------------------

def _links(text):
    """Relative link targets of a Markdown text (no URL, no bare anchor), without the anchor."""
    targets = re.findall(r"\]\(([^)\s]+)\)", text)
    return [t.split("#", 1)[0] for t in targets
            if not re.match(r"^[a-z]+:", t) and not t.startswith("#")]


def test_every_linked_page_exists_and_the_readme_is_short():
    assert len(README.split("\n")) <= 300 + 1          # a final newline ends the last line
    linked = _links(README)
    assert {f"docs/{name}" for name in PAGES} - {"docs/index.md"} <= set(linked), \
        "the README links every reference page"
    for target in linked:
        assert (ROOT / target).exists(), f"README.md links {target}"
    for name, text in PAGES.items():
        for target in _links(text):
            assert (DOCS / target).exists(), f"docs/{name} links {target}"


def test_the_mkdocs_nav_lists_every_page_and_only_pages():
    config = (ROOT / "mkdocs.yml").read_text(encoding="utf-8")
    nav = re.findall(r"^\s+- [^:]+: (\S+\.md)$", config, re.MULTILINE)
    assert nav and len(nav) == len(set(nav))
    assert set(nav) == set(PAGES), "every page of docs/ is in the nav, and every nav entry exists"
    assert re.search(r"^docs_dir: docs$", config, re.MULTILINE)
    pyproject = (ROOT / "pyproject.toml").read_text(encoding="utf-8")
    extras = re.search(r"^\[project.optional-dependencies\]\n(.*?)\n\n", pyproject,
                       re.MULTILINE | re.DOTALL).group(1)
    assert re.search(r'^docs = \["mkdocs[^"]*"\]$', extras, re.MULTILINE)
    runtime = re.search(r"^dependencies = \[(.*?)\]", pyproject, re.MULTILINE | re.DOTALL)
    test_extra = re.search(r"^test = \[(.*?)\]", extras, re.MULTILINE | re.DOTALL)
    assert "mkdocs" not in runtime.group(1) and "mkdocs" not in test_extra.group(1)


def test_no_issue_numbers_in_user_facing_text():
    for where, text in [("README.md", README)] + [(f"docs/{n}", t) for n, t in PAGES.items()]:
        assert not re.search(r"\bissue[ -]?\d+", text, re.IGNORECASE), where


def test_s_i_is_defined_before_the_readme_uses_it():
    first = README.index("s_i")
    assert README[first - 2:first + 5] == "**s_i**", "s_i is first used where it is defined"
    assert "largest |tau_i|" in README[first:first + 200]
    assert README.index("**s_i**") < README.index("```\n$ gd-analyze puma560")



def test_every_page_says_what_s_i_is_where_it_first_uses_it():
    for name, text in PAGES.items():
        first = text.find("s_i")
        if first < 0:
            continue
        near = text[max(0, first - 300):first + 300].replace("\\|", "|")
        assert "largest |tau_i|" in near or name == "index.md", name


# --- the pages that hold what the README held --------------------------------------------------

def _load_script(name):
    spec = importlib.util.spec_from_file_location(f"analysis_{name}",
                                                  ROOT / "analysis" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_option_of_every_command_is_in_its_table():
    parsers = {"analyze": cli.parsing.analyze_parser()}
    parsers.update({name: getattr(cli.parsing, f"{name}_parser")() for name in cli.COMMANDS
                    if name != "analyze"})
    tables = re.split(r"^`gd-analyze ", PAGES["options.md"], flags=re.MULTILINE)[1:]
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


def test_option_tables_equal_the_script_output(capsys):
    _load_script("cli_options").main()
    printed = capsys.readouterr().out.strip()
    page = PAGES["options.md"]
    body = page[page.index("`gd-analyze ROBOT TRAJECTORY.csv`"):].strip()
    assert body == printed, "regenerate docs/options.md with python analysis/cli_options.py"


def test_layout_lists_every_module_of_the_package():
    lines = _load_script("layout").lines()
    block = next(b for info, b in code_blocks(PAGES["layout.md"])
                 if any(line.startswith("gd_analyze/") for line in b))
    listed = {line.split()[0] for line in block if line.strip().startswith("gd_analyze/")}
    modules = {line.split()[0] for line in lines}
    assert not modules - listed, f"modules missing from docs/layout.md: {sorted(modules - listed)}"
    assert not listed - modules, f"docs/layout.md lists modules not in the tree: {sorted(listed - modules)}"
    assert block == [line[4:] for line in lines], "regenerate with python analysis/layout.py"


def test_formulation_counts_are_the_counted_ones():
    from gd_analyze.dynamics.opcount import book_counts, operation_counts

    counted, book = operation_counts(6), book_counts(6)
    section = PAGES["formulations.md"]
    columns = ("lagrange-euler", "newton-euler", "gd")
    for kind in ("multiplications", "additions"):
        for label, source in (("as implemented", counted), ("Table 3.5", book)):
            row = re.search(rf"^\| {kind}, {label} \|(.*)\|$", section, re.MULTILINE)
            assert row, (kind, label)
            cells = [int(c.strip().replace(",", "")) for c in row.group(1).split("|")]
            assert cells == [source[m][kind] for m in columns], (kind, label)
    ne = counted["newton-euler"]
    total = ne["multiplications"] + ne["additions"]
    assert f"Newton-Euler {total:,} ({ne['multiplications']} + {ne['additions']})" in \
        PAGES["guarantee.md"]


def _sample_block():
    block = next(b for info, b in code_blocks(README) if b and b[0].startswith("$ gd-analyze"))
    return block


def test_how_to_read_quotes_the_sample_errors():
    """The summary's worst and other errors quoted in "How to read the report" are the sample's."""
    rows = [line.split() for line in _sample_block() if re.match(r"^\d+ ", line)]
    rel = [float(r[4]) for r in rows]
    worst = max(range(len(rel)), key=rel.__getitem__)
    others = max(r for k, r in enumerate(rel) if k != worst)
    text = " ".join(PAGES["report.md"].split())
    assert (f"worst error is {100 * rel[worst]:.3g} % of peak |tau| at joint {worst + 1}, every "
            f"other joint within {100 * others:.3g} %") in text
    assert "32 %" not in text and "EPS = 0.01" in text


def test_quoted_costs_agree_with_the_sample_and_the_counts():
    """Costs quoted in the pages are the sample's and opcount's (no second copy drifts)."""
    from gd_analyze.dynamics.opcount import operation_counts

    cost_line = next(line for line in _sample_block()
                     if line.startswith("simplified model (recursive N-E"))
    deployed, exact, explicit, ne = (re.search(pattern, cost_line).group(1) for pattern in (
        r": ([\d,]+) operations per set point", r"exact recursive model: ([\d,]+)",
        r"full explicit model: ([\d,]+)", r"Newton-Euler as implemented: ([\d,]+)"))
    guarantee, performance = PAGES["guarantee.md"], PAGES["performance.md"]
    row = re.search(r"^\| PUMA 560 \(\d+ base parameters\) \| (.*)$", performance, re.MULTILINE)
    cells = [c.strip() for c in row.group(1).split("|")]
    assert cells[0].split()[0] == exact and cells[4] == ne
    # the table's EPS = 0.01 column is the trajectory model; the sample deploys the region model
    assert f"the region model at EPS = 0.01 costs **{deployed}** operations" in " ".join(
        guarantee.split())
    assert f"full explicit PUMA 560 model ({explicit} operations)" in " ".join(guarantee.split())
    counted = operation_counts(6)
    for label, method in (("G-D", "gd"), ("L-E", "lagrange-euler")):
        total = sum(counted[method].values())
        assert f"{label} {total:,}" in guarantee, (label, total)


# --- the emitted model in C, C++ and CasADi, as the README shows it ---------------------------

def _fenced(text, info):
    return next("\n".join(b) + "\n" for i, b in code_blocks(text) if i == info)


@pytest.mark.slow
def test_the_readme_c_program_and_casadi_example_agree_with_pinocchio(tmp_path):
    """Take the main job's output, compile the README's main.c with the README's compile line,
    run it, and run the README's CasADi example: their torques at rest are Pinocchio's gravity
    torque within the model's guarantee (1 % of s_i, plus its round-off), and equal to each
    other. The main job is golden case puma560's run (gd-analyze puma560 <shipped>
    --no-report, conftest's golden_run, once a session), copied into the README's default
    folder: the example writes beside it."""
    import json

    import pinocchio as pin

    import gd_analyze as gd
    from gd_analyze.dynamics.pinocchio import pinocchio_model

    for tool in ("cc", "c++"):               # a missing compiler fails, as in the emitter's tests
        assert shutil.which(tool), f"the machine's {tool} is required"
    default = "reports/puma560-puma560_trajectory"
    out = tmp_path / default
    (root, *_), _ = golden_run("puma560")            # shared: copied, not written in
    shutil.copytree(root / "puma560", out)
    (tmp_path / "main.c").write_text(_fenced(README, "c"))
    compile_line = next(line for info, b in code_blocks(README) if info == ""
                        for line in b if line.startswith("cc "))
    assert f"-I {default} main.c {default}/simplified_model.c" in compile_line
    built = subprocess.run(compile_line, shell=True, cwd=tmp_path, capture_output=True,
                           text=True, timeout=300)
    assert built.returncode == 0, built.stderr
    printed = [line.split() for line in built.stdout.strip().split("\n")]
    names = [p[0] for p in printed]
    tau_c = np.array([float(p[1]) for p in printed])

    q = np.array(re.search(r"q\[puma560_N_JOINTS\] = \{([^}]*)\}", _fenced(README, "c"))
                 .group(1).split(","), dtype=float)
    robot = gd.load_robot("puma560")
    model = pinocchio_model(robot)
    rnea = pin.rnea(model, model.createData(), q, np.zeros(6), np.zeros(6))
    guarantee = json.loads((out / "simplified_model.json").read_text())["guarantee"]
    scale = np.array(guarantee["scale"])
    allowed = 0.01 * scale + 64 * np.finfo(float).eps * scale.max()
    assert names == [f"joint{k}" for k in range(1, 7)]
    assert np.all(np.isfinite(tau_c)) and np.all(np.abs(tau_c - rnea) <= allowed), (tau_c, rnea)
    assert np.abs(rnea).max() > 1.0                   # a real gravity load, not zeros

    (tmp_path / "main.cpp").write_text(_fenced(README, "c"))     # the README's C++ route
    cxx = subprocess.run(f"cc -O2 -c {default}/simplified_model.c -o model.o && c++ -O2 "
                         f"-I {default} main.cpp model.o -o main_cpp && ./main_cpp",
                         shell=True, cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert cxx.returncode == 0 and cxx.stdout == built.stdout, cxx.stderr

    example = _fenced(README, "python")
    assert "import simplified_model_casadi" in example
    exact = f'\nprint("EXACT", *ca.DM(f["gravity"]({q.tolist()})).full().ravel().tolist())\n'
    (out / "example.py").write_text(example + exact)
    casadi_run = subprocess.run([sys.executable, "example.py"], cwd=out, capture_output=True,
                                text=True, timeout=300)
    assert casadi_run.returncode == 0, casadi_run.stderr
    last = casadi_run.stdout.strip().split("\n")[-1].split()
    assert last[0] == "EXACT"
    tau_casadi = np.array(last[1:], dtype=float)
    assert np.all(np.abs(tau_casadi - tau_c) <= 1e-12 * scale.max()), (tau_casadi, tau_c)
