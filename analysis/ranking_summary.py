"""One line per main-job result: how many elements of D and h are translational, rotational,
both or negligible, what the simplified model keeps, and the verification against Pinocchio.

Reads the ``results.h5`` that ``gd-analyze ROBOT TRAJECTORY.csv`` writes (nothing is
recomputed). Usage::

    python analysis/ranking_summary.py reports/panda-panda_trajectory/results.h5 [...]
"""

from __future__ import annotations

import argparse
import collections
import sys

CLASSES = ("translational", "rotational", "both", "negligible")
CHOICES = ("tran", "rot", "both", "none")


def summary(path):
    """The counts and verification figures of one results file, as a dict."""
    from gd_analyze.store.schema import open_results

    with open_results(path) as ds:
        labels = [str(v) for v in ds.element.values]
        classes = [str(v) for v in ds.dominance.values]
        choices = [str(v) for v in ds.choice.values]
        out = {"robot": ds.attrs["robot"], "n": int(ds.sizes["joint"]),
               "setpoints": int(ds.attrs["setpoints"]), "elements": len(labels)}
        for part in ("D", "h"):
            count = collections.Counter(c for lab, c in zip(labels, classes)
                                        if lab.startswith(part))
            out[part] = {c: count.get(c, 0) for c in CLASSES}
        kept = collections.Counter(choices)
        out["kept"] = {c: kept.get(c, 0) for c in CHOICES}
        worst = [v for k, v in ds.attrs.items() if k.startswith("verification_max_rel")]
        out["verified"] = bool(ds.attrs.get("verification_passed", False))
        out["verification_worst"] = float(max(worst)) if worst else float("nan")
        out["peak_rel_error"] = float(ds.tau_error_relative_peak.max())
    return out


def main(argv=None):
    """Print a table of :func:`summary` for each results file given."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("results", nargs="+", help="results.h5 files")
    args = ap.parse_args(argv)
    head = (f"{'robot':<10}{'n':>3}  {'D: tran rot both negl':<24}{'h: tran rot both negl':<24}"
            f"{'kept: tran rot both none':<27}{'tau err':>9}  verification")
    print(head)
    for path in args.results:
        s = summary(path)
        d = " ".join(f"{s['D'][c]:>4}" for c in CLASSES)
        h = " ".join(f"{s['h'][c]:>4}" for c in CLASSES)
        k = " ".join(f"{s['kept'][c]:>4}" for c in CHOICES)
        print(f"{s['robot']:<10}{s['n']:>3}  {d:<24}{h:<24}{k:<27}{s['peak_rel_error']:>9.2e}  "
              f"{'passed' if s['verified'] else 'FAILED'} ({s['verification_worst']:.1e})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
