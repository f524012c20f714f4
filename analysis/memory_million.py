"""Peak memory for 1,000,000 set points: gd_terms alone, the CLI with --no-report, and the
main job with its report (HTML, PDF and the figure files).

    python analysis/memory_million.py [--setpoints N] [--no-terms] [--joints n] [--src DIR]
                                      [--read-only] [--blank-end] [--space-end]

Each measurement runs in a fresh Python process that prints its own peak resident set size
(ru_maxrss), so the figures do not mix. The main job runs as a user runs it, in one process.
The trajectory is the default PUMA 560 motion planned with N set points, written to a
temporary CSV. With ``--joints n``, the arm is instead the random chain of n joints of
``analysis/main_job_scaling.py`` (``write_inputs``: position, velocity and acceleration
limits) and its trajectory the motion ``gd-analyze plan`` makes for it with N set points; the
jobs then share one derivation cache, filled by an untimed ``--no-report`` run on the chain's
31-point trajectory first (the certification of a long arm is not what this measures), no
gd_terms-only process is run (its (N, n, n) arrays are what the job avoids), and the limit is 2 GiB (issue 42: 15 joints under 2 GiB) instead of 1 GiB. ``--src DIR`` runs
every process on another checkout's ``src`` (first on PYTHONPATH), to measure the code before
a change. A process that only reads the CSV (``read_trajectory``) gives the reading's own peak;
``--read-only`` runs that one alone (no job). ``--blank-end`` ends the CSV with an empty line
(as many recorded files do), ``--space-end`` with lines of spaces and tabs (LF and CRLF). Prints one JSON line.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

PEAK = "import resource; print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)"


ENV = dict(os.environ)


def run(code):
    """Run Python code in a fresh process; its last stdout line is the peak RSS [MiB]."""
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True,
                         text=True, env=ENV).stdout
    return float(out.strip().splitlines()[-1]), time.perf_counter() - t0


def main(argv=None):
    """Measure and print one JSON line.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.
    """
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--setpoints", type=int, default=1_000_000)
    p.add_argument("--no-terms", action="store_true", help="skip the gd_terms-only process")
    p.add_argument("--joints", type=int, default=0, help="a random chain of this many joints")
    p.add_argument("--src", default="", help="another checkout's src folder")
    p.add_argument("--read-only", action="store_true", help="measure the CSV's reading alone")
    p.add_argument("--blank-end", action="store_true", help="end the CSV with an empty line")
    p.add_argument("--space-end", action="store_true",
                   help="end the CSV with lines of spaces and tabs")
    args = p.parse_args(argv)
    N = args.setpoints
    if args.src:
        ENV["PYTHONPATH"] = os.pathsep.join([args.src, ENV.get("PYTHONPATH", "")]).rstrip(
            os.pathsep)
    limit = 2048 if args.joints else 1024
    with tempfile.TemporaryDirectory() as tmp:
        csv = Path(tmp) / "million.csv"
        arm = "puma560"
        if args.joints:
            sys.path.insert(0, str(Path(__file__).resolve().parent))
            from main_job_scaling import write_inputs

            toml, short = write_inputs(args.joints, Path(tmp))
            arm = str(toml)
            ENV["GD_ANALYZE_CACHE_DIR"] = str(Path(tmp) / "cache")
            run(f"from gd_analyze.cli import main; rc = main([{arm!r}, {str(short)!r}, '-o', "
                f"{str(Path(tmp) / 'warm')!r}, '--no-report', '-q']); assert rc == 0; " + PEAK)
            plan = (f"import numpy as np; from gd_analyze import load_robot; "
                    f"from gd_analyze.trajectory.planning import *; r = load_robot({arm!r}); ")
            run(f"from gd_analyze.cli import main; rc = main(['plan', {arm!r}, '-o', "
                f"{str(csv)!r}, '--setpoints', '{N}']); assert rc == 0; " + PEAK)
            plan += f"from gd_analyze.trajectory.trajectory import *; tr = read_trajectory({str(csv)!r}); "
        else:
            plan = (f"import numpy as np; from gd_analyze import load_robot; "
                    f"from gd_analyze.trajectory.trajectory import *; from gd_analyze.trajectory.planning import *; r = load_robot('puma560'); "
                    f"tr = plan_quintic(r, np.radians(DEFAULT_START_DEG), "
                    f"np.radians(DEFAULT_GOAL_DEG), {N});")
            run(plan + f"write_trajectory(tr, {str(csv)!r}); " + PEAK)
        if args.blank_end or args.space_end:
            with open(csv, "ab") as fh:
                fh.write(b" \t\r\n\t\n  \n" if args.space_end else b"\n")
        rss_read, t_read = run("from gd_analyze.trajectory.trajectory import read_trajectory; "
                               f"tr = read_trajectory({str(csv)!r}); " + PEAK)
        csv_size = csv.stat().st_size
        if args.read_only:
            print(json.dumps({"setpoints": N, "joints": args.joints or 6,
                              "src": args.src or None, "load_average": os.getloadavg(),
                              "blank_end": args.blank_end, "space_end": args.space_end,
                              "read_csv_peak_rss_mib": rss_read, "read_csv_s": t_read,
                              "csv_mib": csv_size / 2**20}))
            return 0
        rss_terms, t_terms = (None, None) if args.no_terms or args.joints else run(
            plan + "from gd_analyze import gd_terms; t = gd_terms(r, tr.q, tr.qd); " + PEAK)
        rss_cli, t_cli = run(
            f"from gd_analyze.cli import main; "
            f"rc = main([{arm!r}, {str(csv)!r}, '-o', {str(Path(tmp) / 'out')!r}, "
            f"'--no-report', '-q']); assert rc == 0; " + PEAK)
        size = (Path(tmp) / "out" / "results.h5").stat().st_size
        rss_report, t_report = run(
            f"from gd_analyze.cli import main; "
            f"rc = main([{arm!r}, {str(csv)!r}, '-o', {str(Path(tmp) / 'rep')!r}, "
            f"'-q']); assert rc == 0; " + PEAK)
    print(json.dumps({"setpoints": N, "joints": args.joints or 6, "src": args.src or None,
                      "load_average": os.getloadavg(), "read_csv_peak_rss_mib": rss_read,
                      "read_csv_s": t_read, "gd_terms_peak_rss_mib": rss_terms,
                      "gd_terms_process_s": t_terms, "cli_no_report_peak_rss_mib": rss_cli,
                      "cli_no_report_s": t_cli, "cli_with_report_peak_rss_mib": rss_report,
                      "cli_with_report_s": t_report, "csv_mib": csv_size / 2**20,
                      "results_h5_mib": size / 2**20, "limit_mib": limit,
                      "within_limit": max(v for v in (rss_terms, rss_cli, rss_report)
                                          if v is not None) <= limit}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
