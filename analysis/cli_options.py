"""Print the option tables of docs/options.md: every option of every command, from the argparse parsers.

    python analysis/cli_options.py

One Markdown table per command (``gd-analyze``, then each sub-command): option, argument and
what it does (with its default). tests/test_docs.py checks that docs/options.md lists them all.
"""

from __future__ import annotations

import argparse
import sys


def parsers():
    """The parser of each command, by the command line that starts it.

    Returns
    -------
    dict of str to argparse.ArgumentParser
    """
    from gd_analyze import cli

    out = {"gd-analyze ROBOT TRAJECTORY.csv": cli.parsing.analyze_parser()}
    for name in cli.COMMANDS:
        if name != "analyze":
            out[f"gd-analyze {name}"] = getattr(cli.parsing, f"{name}_parser")()
    return out


def options(parser):
    """(option strings, metavar, help) of each optional argument of a parser."""
    rows = []
    for action in parser._actions:
        if not action.option_strings:
            continue
        metavar = action.metavar or ("" if action.nargs == 0 else action.dest.upper())
        if action.choices is not None and not action.metavar and action.nargs != 0:
            metavar = "{" + ",".join(str(c) for c in action.choices) + "}"
        text = (action.help or "").replace("%(prog)s", "gd-analyze").replace("|", "\\|")
        if isinstance(action, argparse._VersionAction):
            text = "print the version and exit"
        rows.append((", ".join(f"`{o}`" for o in action.option_strings), metavar, text))
    return rows


def main():
    """Print the tables."""
    for command, parser in parsers().items():
        print(f"`{command}`\n")
        print("| option | argument | what it does |")
        print("|---|---|---|")
        for opts, metavar, text in options(parser):
            print(f"| {opts} | {f'`{metavar}`' if metavar else ''} | {text} |")
        print()
    return 0


if __name__ == "__main__":
    sys.exit(main())
