"""Redraw the README's picture: the Fig. 3.10 analogue of the shipped PUMA 560 trajectory.

    python analysis/readme_figure.py [--out docs/fig_3_10_D.png]

Runs the main job on data/puma560_trajectory.csv into a temporary folder (no report) and draws
the report's D figure from the stored results, as a PNG at 150 dpi.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def main(argv=None):
    """Write the picture.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.
    """
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", default=str(ROOT / "docs" / "fig_3_10_D.png"))
    args = p.parse_args(argv)
    import matplotlib

    matplotlib.use("Agg")
    from gd_analyze.cli import main as cli
    from gd_analyze.report.main import FIG_RC, make_figures
    from gd_analyze.store.schema import open_results

    with tempfile.TemporaryDirectory() as tmp:
        assert cli(["puma560", str(ROOT / "data" / "puma560_trajectory.csv"), "-o", tmp,
                    "--no-report", "-q"]) == 0
        ds = open_results(Path(tmp) / "results.h5")
        fig = make_figures(ds, keys=("D",))["D"]
        with matplotlib.rc_context(FIG_RC):          # as write_report draws it
            fig.savefig(args.out, dpi=150, facecolor="white")
        ds.close()
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
