"""Where the test suite's time goes: the JUnit XML of a pytest run, summed per test module.

    python analysis/test_time.py RUN.xml [--top 30]

``RUN.xml`` is what ``pytest --junitxml RUN.xml`` writes; CI writes one per interpreter
(``.ci-junit-<version>.xml`` in its checkout, see ``.ci/run``). Each test case's time there is
its setup, call and teardown together, on the xdist worker that ran it, so the sum over the
cases is worker time: with ``-n 2`` the wall time is about half of it. A fixture built once a
session (``tests/conftest.py``'s ``built_once``) is charged to the first test that asks for it.

Prints one JSON line: the cases, their summed time [s], the share of the ``top`` modules, and
those modules (path, cases, summed time [s], the slowest case and its time [s]), slowest first.
"""

from __future__ import annotations

import argparse
import json
import xml.etree.ElementTree as ET  # noqa: N817  the standard library's parser of pytest's file
from collections import defaultdict


def module_times(xml_path: str) -> dict[str, dict]:
    """Summed time per test module of a pytest JUnit XML file.

    Parameters
    ----------
    xml_path : str
        The file ``pytest --junitxml`` wrote.

    Returns
    -------
    dict of str to dict
        By module path (``tests/report/test_main.py``): ``cases``, ``seconds`` (summed) and
        ``slowest`` ``(name, seconds)``.
    """
    out: dict[str, dict] = defaultdict(lambda: {"cases": 0, "seconds": 0.0,
                                                "slowest": ("", 0.0)})
    for case in ET.parse(xml_path).getroot().iter("testcase"):
        path = case.get("classname", "").replace(".", "/") + ".py"
        seconds = float(case.get("time", 0.0))
        row = out[path]
        row["cases"] += 1
        row["seconds"] += seconds
        if seconds > row["slowest"][1]:
            row["slowest"] = (case.get("name", ""), seconds)
    return dict(out)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("xml", help="pytest's JUnit XML file")
    parser.add_argument("--top", type=int, default=30, help="modules to list")
    args = parser.parse_args(argv)
    rows = sorted(module_times(args.xml).items(), key=lambda kv: -kv[1]["seconds"])
    total = sum(r["seconds"] for _, r in rows)
    top = rows[:args.top]
    print(json.dumps({
        "cases": sum(r["cases"] for _, r in rows), "seconds": round(total, 1),
        "top_share": round(sum(r["seconds"] for _, r in top) / total, 3) if total else None,
        "modules": [{"module": m, "cases": r["cases"], "seconds": round(r["seconds"], 1),
                     "slowest": [r["slowest"][0], round(r["slowest"][1], 1)]}
                    for m, r in top]}))


if __name__ == "__main__":
    main()
