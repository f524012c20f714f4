"""The README lists every option of every command, the exit codes, and ships its picture."""

import re
from pathlib import Path

from gd_analyze import cli

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")


def test_every_option_of_every_command_is_in_its_table():
    parsers = {"analyze": cli._analyze_parser()}
    parsers.update({name: getattr(cli, f"_{name}_parser")() for name in cli.COMMANDS
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
