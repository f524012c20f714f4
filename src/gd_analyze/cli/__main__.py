"""``python -m gd_analyze.cli``: the command line."""

from . import run

run()
