"""The package's import structure, and what it costs at the command line's start.

Prints, for the package in ``src/`` (or ``--src``):

- the import circles among its modules, counting every import that runs (module level and
  inside functions, not those under ``if TYPE_CHECKING:``), as tests/test_layers.py does;
- the function-local imports of the package's own modules, per module;
- the imports that run against the flow of the packages (tests/test_layers.py's ``LAYERS``);

and, with ``--baseline SRC`` (another checkout's ``src``), the time of ``import gd_analyze.cli``
in a fresh interpreter for both, interleaved (a, b, b, a, ...), median and [min, max] of the
per-pair ratios, with the load averages.

Usage::

    python analysis/import_structure.py [--src SRC] [--baseline OTHER_SRC] [--rounds 12]
"""

from __future__ import annotations

import argparse
import collections
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _structure(src):
    """Circles, function-local imports and upward imports of the package at ``src``."""
    sys.path.insert(0, str(ROOT / "tests"))
    import test_layers as layers

    layers.SRC = Path(src) / "gd_analyze"
    modules = sorted(layers.SRC.rglob("*.py"))
    layers.MODULES = modules
    graph = {layers._module_name(p): layers._runtime_edges(p) - {layers._module_name(p)}
             for p in modules}
    local = [x for p in modules for x in layers.local_imports(p)]
    upward = [u for p in modules for u in layers.upward(p)]
    return layers.circles(graph), local, upward


def _import_time(src):
    env = {**os.environ, "PYTHONPATH": str(src)}
    t = time.perf_counter()
    subprocess.run([sys.executable, "-c", "import gd_analyze.cli"], env=env, check=True)
    return time.perf_counter() - t


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--src", default=str(ROOT / "src"))
    parser.add_argument("--baseline", default=None, help="another checkout's src folder")
    parser.add_argument("--rounds", type=int, default=12)
    args = parser.parse_args(argv)
    circles, local, upward = _structure(args.src)
    print(f"import circles (runtime imports, functions included): {len(circles)}")
    for c in circles:
        print("  " + " -> ".join(c))
    per = collections.Counter(x.split(":")[0] for x in local)
    print(f"function-local imports of the package: {len(local)}")
    for mod, k in sorted(per.items(), key=lambda kv: -kv[1]):
        print(f"  {k:3d}  {mod}")
    print(f"imports against the flow: {len(upward)}")
    for u in upward:
        print("  " + u)
    if args.baseline:
        print(f"load averages before: {os.getloadavg()}")
        times = {"src": [], "baseline": []}
        for k in range(args.rounds):
            order = [("src", args.src), ("baseline", args.baseline)]
            for name, path in order if k % 2 == 0 else order[::-1]:
                times[name].append(_import_time(path))
        ratios = [a / b for a, b in zip(times["src"], times["baseline"])]
        print(f"import gd_analyze.cli: src {statistics.median(times['src']):.3f} s, baseline "
              f"{statistics.median(times['baseline']):.3f} s (medians); src / baseline "
              f"{statistics.median(ratios):.2f} [{min(ratios):.2f}, {max(ratios):.2f}] over "
              f"{args.rounds} interleaved pairs")
        print(f"load averages after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
