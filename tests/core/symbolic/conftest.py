"""Makes the shared helpers of this folder (symbolic_helpers.py) importable by its tests."""

import sys
from pathlib import Path

HERE = str(Path(__file__).resolve().parent)
if HERE not in sys.path:
    sys.path.append(HERE)          # after tests/ (whose conftest the other tests import)
