"""``python -m gd_analyze.cli``: the command line."""

import sys

from . import main

sys.exit(main())
