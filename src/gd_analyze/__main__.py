"""``python -m gd_analyze``: the command line, as ``gd-analyze`` and ``python -m gd_analyze.cli``."""

from .cli import run

run()
