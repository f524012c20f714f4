"""The cost of the tests' figure checks (``tests/figure_checks.py``) here and in a reference
checkout, on the same figures, in interleaved rounds.

    python analysis/figure_checks_cost.py --baseline /tmp/old/ [--rounds 5] [--joints 10]

The figures: the main report's Fig. 2 (``main_figures.fig_D``) of an arm of ``--joints``
joints in its planned parts and its Fig. 1 (``fig_joints``), on synthetic series (seeded),
made once per round for each side. Each side's ``collisions`` and ``smallest_type`` run on
them (the reference's module imported from ``<baseline>/tests``); timed in CPU seconds of
this process. The two sides must find the same collisions and type sizes: the script stops
if they differ.

Prints one JSON line: per side the median [min, max] CPU seconds a round, the ratio this /
reference of the medians, and the load.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import statistics
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402  after the backend is chosen

from gd_analyze.ranking.ranking import element_label  # noqa: E402
from gd_analyze.report.main_figures import (  # noqa: E402
    PAGE_WIDTH,
    RC,
    PlotData,
    element_parts,
    fig_D,
    fig_joints,
)

ROOT = Path(__file__).resolve().parents[1]


def _module(tests: Path, name: str):
    spec = importlib.util.spec_from_file_location(name, tests / "figure_checks.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def figures(n: int) -> list:
    """Fig. 2's planned parts and Fig. 1 of an n-joint arm on seeded synthetic series."""
    rng = np.random.default_rng(n)
    D = rng.standard_normal((21, n, n))
    t = np.linspace(0.0, 2.0, 21)
    data = PlotData(x=t, enveloped=False, N=21,
                    series={"D_tran": D, "D_rot": 0.5 * D, "D": 1.5 * D,
                            "q": np.sin(t[:, None] + np.arange(n)),
                            "qd": np.cos(t[:, None] + np.arange(n)),
                            "qdd": -np.sin(t[:, None] + np.arange(n))})
    labels = [element_label("D", i, j) for i in range(n) for j in range(i, n)]
    classes = {lab: "both" for lab in labels}
    with matplotlib.rc_context(RC):
        out = [fig_D(data, classes, {}, 0.9, 0.01, part=k)
               for k in range(len(element_parts(labels)))]
        out.append(fig_joints(data, np.zeros(n, bool), PAGE_WIDTH))
    return out


def one_round(checks, n: int) -> tuple[float, list]:
    """CPU seconds of the checks on fresh figures, and what they found."""
    figs = figures(n)
    start = time.process_time()
    found = [(checks.collisions(f, RC), checks.smallest_type(f, RC)) for f in figs]
    return time.process_time() - start, found


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", required=True, type=Path,
                        help="the reference checkout (its tests/figure_checks.py)")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--joints", type=int, default=10)
    args = parser.parse_args(argv)
    sides = {"this": _module(ROOT / "tests", "checks_this"),
             "baseline": _module(args.baseline.resolve() / "tests", "checks_baseline")}
    times: dict[str, list[float]] = {"this": [], "baseline": []}
    for k in range(args.rounds):
        found = {}
        for side in (("this", "baseline") if k % 2 == 0 else ("baseline", "this")):
            seconds, found[side] = one_round(sides[side], args.joints)
            times[side].append(seconds)
        if found["this"] != found["baseline"]:
            raise SystemExit("the two sides' checks found different things")
    out = {side: [round(statistics.median(v), 3), round(min(v), 3), round(max(v), 3)]
           for side, v in times.items()}
    out["ratio"] = round(out["this"][0] / out["baseline"][0], 3)
    out["load"] = [round(x, 2) for x in os.getloadavg()]
    print(json.dumps(out))


if __name__ == "__main__":
    main()
