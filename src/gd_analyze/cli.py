"""The command line: ``gd-analyze ROBOT TRAJECTORY.csv`` and its sub-commands.

Exit status: 0 on success; 1 if the verification against Pinocchio fails; 2 on bad input or an
unusable output location (one line on stderr naming the file, row and column, no traceback, no
partial output); 3 when ``evaluate --max-error`` is exceeded; 4 on an internal error (a bug: one
line, the traceback only with ``--debug``).

Nothing in the package imports this module.
"""

from __future__ import annotations

import argparse
import decimal
import math
import os
import sys
import warnings
from pathlib import Path

from .errors import InputError, InputNote, InputWarning

__all__ = ["main"]

PROG = "gd-analyze"
COMMANDS = ("analyze", "plan", "evaluate", "compare", "control", "sweep")
EXIT_OK, EXIT_VERIFY, EXIT_INPUT, EXIT_TOLERANCE, EXIT_INTERNAL = 0, 1, 2, 3, 4
EXIT_STATUS_HELP = ("Exit status: 0 ok, 1 verification failed, 2 bad input or unusable output "
                    "location, 3 error above --max-error, 4 internal error (--debug shows the "
                    "traceback).")


class _Parser(argparse.ArgumentParser):
    """argparse that reports usage errors as one line with exit status 2."""

    def error(self, message):
        sub = self.prog[len(PROG):].strip()
        raise InputError(f"{sub}: {message}" if sub else message)



def parse_range(text, name="--payload-sweep"):
    """Parse ``"start:stop:step"`` into the values start, start + step, ..., stop (inclusive).

    Parameters
    ----------
    text : str
        E.g. ``"0:2.5:0.5"``; step > 0, stop >= start. The values are computed in decimal
        arithmetic from the strings, so ``"0:0.3:0.1"`` gives exactly [0.0, 0.1, 0.2, 0.3].
        stop is included when it lies on the grid; otherwise the last value is the largest
        grid value below it.
    name : str, optional
        The option or column named in error messages.

    Returns
    -------
    list of float
        At least one value.

    Raises
    ------
    InputError
        If the text is not three numbers separated by ``:``, a number is not finite, step is
        not positive, stop < start, or the range has more than 10,000 values.

    Examples
    --------
    >>> parse_range("0:2.5:0.5")
    [0.0, 0.5, 1.0, 1.5, 2.0, 2.5]
    """
    parts = str(text).split(":")
    if len(parts) != 3:
        raise InputError(f"expected START:STOP:STEP (e.g. 0:2.5:0.5), got {text!r}",
                         column=name)
    try:
        start, stop, step = (decimal.Decimal(p.strip()) for p in parts)
    except decimal.InvalidOperation:
        raise InputError(f"expected three numbers START:STOP:STEP, got {text!r}",
                         column=name) from None
    if not all(v.is_finite() for v in (start, stop, step)):
        raise InputError(f"START, STOP and STEP must be finite, got {text!r}", column=name)
    if step <= 0:
        raise InputError(f"STEP must be positive, got {text!r}", column=name)
    if stop < start:
        raise InputError(f"STOP must not be below START, got {text!r}", column=name)
    try:
        count = int((stop - start) // step) + 1
    except decimal.DecimalException:                  # e.g. 0:1:1e-30: beyond the precision
        count = math.inf
    if count > 10_000:
        raise InputError(f"the range {text!r} has {count:.3g} values (at most 10000)",
                         column=name)
    return [float(start + k * step) for k in range(count)]

def _fraction(lo, hi, name, lo_open=True):
    def parse(text):
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be a number, got {text!r}") from None
        ok = (lo < v if lo_open else lo <= v) and v <= hi and math.isfinite(v)
        if not ok:
            bracket = "(" if lo_open else "["
            raise argparse.ArgumentTypeError(f"{name} must be in {bracket}{lo}, {hi}], got {v}")
        return v
    return parse


def _angles(text):
    try:
        vals = [float(v) for v in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers, got {text!r}") \
            from None
    if not all(math.isfinite(v) for v in vals):
        raise argparse.ArgumentTypeError(f"expected finite numbers, got {text!r}")
    return vals


def _vector3(name):
    def parse(text):
        vals = _angles(text)
        if len(vals) != 3:
            raise argparse.ArgumentTypeError(f"{name} needs 3 comma-separated numbers, got "
                                             f"{text!r}")
        return vals
    return parse


def _add_payload_arguments(p):
    g = p.add_argument_group("payload (a rigid load fixed to the last link)")
    g.add_argument("--payload", metavar="MASS", type=_fraction(0.0, math.inf, "--payload", False),
                   help="load mass [kg] (the PUMA 560's rated load is 2.5 kg)")
    g.add_argument("--payload-com", metavar="X,Y,Z", type=_vector3("--payload-com"),
                   default=[0.0, 0.0, 0.0], help="load centre of mass in the last link frame [m]")
    g.add_argument("--payload-inertia", metavar="IXX,IYY,IZZ",
                   type=_vector3("--payload-inertia"), default=[0.0, 0.0, 0.0],
                   help="load principal moments about its centre of mass [kg m^2]")
    return g


def _add_chain_arguments(p):
    g = p.add_argument_group("URDF chain (a ROBOT given as a .urdf file, or panda, ur5)")
    g.add_argument("--base", metavar="LINK",
                   help="the chain's base link (default: the URDF's root link)")
    g.add_argument("--tip", metavar="LINK",
                   help="the chain's tip link (default: the end of the only chain); moving "
                        "joints off the chain are locked at q = 0 and carried by their link")
    return g


_ROBOT_HELP = ("built-in robot (puma560, two-link, panda, ur5, ...), a TOML robot file or a URDF "
               "file (*.urdf, see --base and --tip)")


def _load_robot(args):
    from .io.robots import load_robot

    return load_robot(args.robot, args.base, args.tip)


def _chain_settings(args):
    """The URDF chain options, for the provenance of a run's outputs."""
    return {k: v for k, v in (("robot_base", args.base), ("robot_tip", args.tip)) if v}


def _add_payload_sweep_argument(group):
    group.add_argument("--payload-sweep", metavar="START:STOP:STEP",
                       help="also rank the elements for each load mass in this range [kg], "
                            "stop included, e.g. 0:2.5:0.5; uses --payload-com and "
                            "--payload-inertia for the load's shape (stored with dim 'payload')")


def _apply_payload(robot, args):
    from .core.robot import with_payload

    if args.payload is None:
        if any(args.payload_com) or any(args.payload_inertia):
            raise InputError("--payload-com and --payload-inertia need --payload MASS")
        return robot
    return with_payload(robot, args.payload, args.payload_com, args.payload_inertia)


def _add_budget_arguments(p, rule=True):
    g = p.add_argument_group("simplified model (error budget, issue 8)")
    g.add_argument("--tolerance", metavar="EPS", type=_fraction(0.0, math.inf, "--tolerance",
                                                                False), default=0.01,
                   help="error budget: every joint's simplified torque stays within EPS times "
                        "its scale on the analysed trajectory (default 0.01)")
    g.add_argument("--torque-floor", metavar="TAU", type=_fraction(0.0, math.inf,
                                                                   "--torque-floor", False),
                   default=0.0, help="least scale of a joint torque [N m] (default 0)")
    if rule:
        g.add_argument("--rule", choices=("budget", "chapter"), default="budget",
                       help="budget: by torque contribution within EPS (default); chapter: "
                            "the share-based classes of Sec. 3.4.1 (no bound)")


def _write_sources(model, outdir):
    """simplified_model.c and simplified_model.py next to the JSON (in the staging folder)."""
    written = []
    for name, text in (("simplified_model.c", model.c_source()),
                       ("simplified_model.py", model.python_source())):
        path = outdir / name
        path.write_text(text, encoding="utf-8")
        written.append(path)
    return written

def _add_paper_argument(p):
    p.add_argument("--paper", choices=("a4", "letter"), default="a4",
                   help="page size of the PDF report (default a4)")


def _analyze_parser():
    from .core.ranking import DEFAULT_DOMINANCE, DEFAULT_NEGLIGIBLE

    p = _Parser(
        prog=PROG,
        description="Rank the translational and rotational parts of a robot arm's inertia "
                    "matrix D and Coriolis/centrifugal vector h along a trajectory (generalized "
                    "d'Alembert equations, Fu, Gonzalez & Lee 1987, Sec. 3.4), verify them "
                    "against Pinocchio, and write results.h5, simplified_model.json, "
                    "report.html and report.pdf.",
        epilog="other commands: 'gd-analyze plan ROBOT -o FILE' writes a planned trajectory; "
               "'gd-analyze evaluate MODEL.json TRAJECTORY.csv' checks a simplified model on "
               "another trajectory; 'gd-analyze compare ROBOT TRAJECTORY.csv' compares the "
               "L-E, N-E and G-D formulations; 'gd-analyze control MODEL.json TRAJECTORY.csv' "
               "checks a simplified model in closed loop; 'gd-analyze sweep ROBOT ...' analyses "
               "many trajectories on dask. 'gd-analyze COMMAND --help' for details. "
               + EXIT_STATUS_HELP,
    )
    p.add_argument("robot", metavar="ROBOT", help=_ROBOT_HELP)
    p.add_argument("trajectory", metavar="TRAJECTORY.csv",
                   help="CSV with header t,q1..qn[,qd1..qdn,qdd1..qddn] [s, rad, rad/s, rad/s^2]")
    p.add_argument("-o", "--outdir", metavar="OUTDIR",
                   help="output folder (default: reports/<robot>-<csv stem>/)")
    p.add_argument("--dominance", metavar="S", type=_fraction(0.5, 1.0, "--dominance"),
                   default=DEFAULT_DOMINANCE,
                   help=f"share at which one part dominates, in (0.5, 1] (default "
                        f"{DEFAULT_DOMINANCE})")
    p.add_argument("--negligible", metavar="E", type=_fraction(0.0, 1.0, "--negligible", False),
                   default=DEFAULT_NEGLIGIBLE,
                   help=f"an element below E times its scale is negligible (default "
                        f"{DEFAULT_NEGLIGIBLE})")
    _add_budget_arguments(p)
    p.add_argument("--no-report", action="store_true", help="skip report.html and report.pdf")
    _add_paper_argument(p)
    p.add_argument("--compress", metavar="LEVEL", type=int, choices=range(10), default=0,
                   help="gzip level 0-9 for the per-set-point variables of results.h5 "
                        "(default 0: uncompressed, fastest)")
    p.add_argument("--no-verify", action="store_true",
                   help="skip the verification against Pinocchio")
    p.add_argument("-q", "--quiet", action="store_true",
                   help="print nothing but warnings and errors (no summary, no progress bar)")
    p.add_argument("--version", action="version", version=f"%(prog)s {_version()}")
    _add_chain_arguments(p)
    _add_payload_sweep_argument(_add_payload_arguments(p))
    return p


def _version():
    from ._version import __version__

    return __version__


def _plan_parser():
    from .io.planning import DEFAULT_GOAL_DEG, DEFAULT_QDD_PER_QD, DEFAULT_SETPOINTS, DEFAULT_START_DEG

    p = _Parser(prog=f"{PROG} plan",
                description="Write a quintic rest-to-rest joint trajectory at the shortest "
                            "duration within the robot's velocity and acceleration limits, and "
                            "its provenance beside it (FILE's stem + .provenance.json).")
    p.add_argument("robot", metavar="ROBOT", help=_ROBOT_HELP)
    p.add_argument("-o", "--output", metavar="FILE", required=True,
                   help="CSV file to write ('-' for standard output)")
    p.add_argument("--start", metavar="DEG,...", type=_angles,
                   help="start positions [deg; m for a prismatic joint] (default for puma560: "
                        f"{','.join(f'{v:g}' for v in DEFAULT_START_DEG)}; for other robots "
                        "a quarter of each joint's range)")
    p.add_argument("--goal", metavar="DEG,...", type=_angles,
                   help="goal positions [deg; m for a prismatic joint] (default for puma560: "
                        f"{','.join(f'{v:g}' for v in DEFAULT_GOAL_DEG)}; for other robots "
                        "three quarters of each joint's range)")
    p.add_argument("--setpoints", metavar="N", type=int, default=DEFAULT_SETPOINTS,
                   help=f"number of set points, both ends included (default {DEFAULT_SETPOINTS})")
    p.add_argument("--duration", metavar="T", type=float,
                   help="duration [s] (default: the shortest within the limits)")
    p.add_argument("--ignore-limits", action="store_true",
                   help="plan even if the duration, start or goal breaks the robot's joint "
                        "position, velocity or acceleration limits")
    p.add_argument("--qdd-max", metavar="A[,...]", type=_angles,
                   help="acceleration limits [deg/s^2; m/s^2 for a prismatic joint], one for "
                        "all joints or one per joint (default: the robot's; where it has none, "
                        f"as in a URDF, {DEFAULT_QDD_PER_QD:g} s^-1 times the velocity limit, "
                        "i.e. full speed in 1/{0:g} s; the provenance says which)".format(
                            DEFAULT_QDD_PER_QD))
    _add_chain_arguments(p)
    return p


def _evaluate_parser():
    p = _Parser(prog=f"{PROG} evaluate",
                description="Report a simplified model's torque error on another trajectory.")
    p.add_argument("model", metavar="MODEL.json")
    p.add_argument("trajectory", metavar="TRAJECTORY.csv")
    p.add_argument("--max-error", metavar="REL", type=_fraction(0.0, math.inf, "--max-error",
                                                                False),
                   help="exit with status 3 if the peak relative torque error of any joint "
                        "exceeds REL")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    _add_payload_arguments(p)
    p.epilog = ("With --payload, the reference torques are those of the arm carrying the load, "
                "while the simplified model keeps its own robot: the error shows whether the "
                "model holds under that load.")
    return p


def _compare_parser():
    p = _Parser(prog=f"{PROG} compare",
                description="Run Lagrange-Euler, Newton-Euler, G-D and Pinocchio on every set "
                            "point and print their largest relative disagreements and the "
                            "operation counts per set point.")
    p.add_argument("robot", metavar="ROBOT", help=_ROBOT_HELP)
    p.add_argument("trajectory", metavar="TRAJECTORY.csv")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    _add_chain_arguments(p)
    return p


def _control_parser():
    from .workflows.control import DEFAULT_WN, DEFAULT_ZETA

    p = _Parser(prog=f"{PROG} control",
                description="Simulate computed-torque control of the full-model arm along a "
                            "trajectory with three controllers: one built on the full G-D "
                            "model, one on the simplified model, and PD with gravity "
                            "compensation; write control.h5 and control_report.html/.pdf.")
    p.add_argument("model", metavar="MODEL.json")
    p.add_argument("trajectory", metavar="TRAJECTORY.csv")
    p.add_argument("-o", "--outdir", metavar="OUTDIR",
                   help="output folder (default: reports/<robot>-<csv stem>-control/)")
    p.add_argument("--wn", metavar="RAD/S", type=_fraction(0.0, math.inf, "--wn"),
                   default=DEFAULT_WN,
                   help=f"natural frequency of the error dynamics [rad/s] (default {DEFAULT_WN:g}); "
                        "Kp = wn^2, Kv = 2 zeta wn")
    p.add_argument("--zeta", metavar="Z", type=_fraction(0.0, math.inf, "--zeta"),
                   default=DEFAULT_ZETA, help=f"damping ratio (default {DEFAULT_ZETA:g})")
    p.add_argument("--offset", metavar="RAD", type=_fraction(-2 * math.pi, 2 * math.pi,
                                                             "--offset", False),
                   default=0.0, help="initial position error on every joint [rad], within "
                                     "[-2 pi, 2 pi] (default 0)")
    p.add_argument("--no-report", action="store_true", help="skip the HTML and PDF report")
    _add_paper_argument(p)
    p.add_argument("--json", action="store_true", help="print the figures as one JSON object")
    p.add_argument("-q", "--quiet", action="store_true", help="print nothing but errors")
    return p


def _sweep_parser():
    from .core.ranking import DEFAULT_DOMINANCE, DEFAULT_NEGLIGIBLE

    p = _Parser(prog=f"{PROG} sweep",
                description="Rank the G-D elements over many trajectories on dask, give the "
                            "envelope of the ranking per element and one simplified model valid "
                            "over them all (an element is dropped or reduced only where that "
                            "holds in every trajectory); write sweep.h5, merged_model.json and "
                            "sweep_report.html/.pdf.")
    p.add_argument("robot", metavar="ROBOT", help=_ROBOT_HELP)
    p.add_argument("csv", metavar="CSV", nargs="*", help="trajectory files (or use --random)")
    p.add_argument("--random", metavar="K", type=int,
                   help="plan K random quintic trajectories (start and goal uniform in the "
                        "joint limits, shortest duration within the limits, 31 set points)")
    p.add_argument("--seed", metavar="S", type=_seed, default=0,
                   help="seed for --random, an integer in [0, 2^63)")
    p.add_argument("-o", "--outdir", metavar="OUTDIR",
                   help="output folder (default: reports/<robot>-sweep/)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="address of a running dask scheduler (default: start a LocalCluster)")
    p.add_argument("--workers", metavar="N", type=int,
                   help="workers of the LocalCluster (default: one per core)")
    p.add_argument("--dominance", metavar="S", type=_fraction(0.5, 1.0, "--dominance"),
                   default=DEFAULT_DOMINANCE, help=f"default {DEFAULT_DOMINANCE}")
    p.add_argument("--negligible", metavar="E",
                   type=_fraction(0.0, 1.0, "--negligible", False),
                   default=DEFAULT_NEGLIGIBLE, help=f"default {DEFAULT_NEGLIGIBLE}")
    p.add_argument("--tolerance", metavar="EPS", type=_fraction(0.0, math.inf, "--tolerance",
                                                                False),
                   help="also build one simplified explicit model within EPS on every swept "
                        "trajectory (budget rule); writes sweep_model.json/.c/.py")
    p.add_argument("--torque-floor", metavar="TAU", type=_fraction(0.0, math.inf,
                                                                   "--torque-floor", False),
                   default=0.0, help="least scale of a joint torque [N m] (default 0)")
    p.add_argument("--held-out", metavar="K", type=int, default=20,
                   help="random trajectories (another seed) to measure the sweep model on, "
                        "not guaranteed (default 20)")
    p.add_argument("--no-report", action="store_true", help="skip the HTML and PDF report")
    _add_paper_argument(p)
    p.add_argument("-q", "--quiet", action="store_true", help="print nothing but errors")
    _add_chain_arguments(p)
    _add_payload_sweep_argument(_add_payload_arguments(p))
    return p


def _seed(text):
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--seed must be an integer, got {text!r}") from None
    if not 0 <= v < 2**63:
        raise argparse.ArgumentTypeError(f"--seed must be in [0, 2^63), got {text}")
    return v


def _outdir(args_outdir, *parts):
    """The output folder: -o as given, or reports/<sanitised parts joined by '-'>."""
    from .io.staging import safe_name

    if args_outdir:
        return Path(args_outdir)
    return Path("reports") / "-".join(safe_name(p) for p in parts)


def _results_size(N, n):
    """Bytes of the per-set-point variables of results.h5 (uncompressed)."""
    return 8 * N * (1 + 9 * n + 3 * n * n) + (1 << 20)


def _load(args, csv_arg):
    from .io.trajectory import read_trajectory

    robot = _load_robot(args)
    return robot, read_trajectory(csv_arg, n_joints=robot.n)


def _warn_limits(robot, trajectory, quiet):
    from .io.trajectory import JointLimitWarning, check_joint_limits

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", JointLimitWarning)
        messages = check_joint_limits(robot, trajectory)
    for msg in messages:
        print(f"{PROG}: warning: {msg}", file=sys.stderr)


#: Printed instead of share_tran for an element that is zero in every part.
ZERO_MARK = "\u2261 0"


def _format_summary(ds):
    lines = [f"{ds.attrs['robot']} along {ds.attrs['input_file']}: "
             f"{ds.attrs['setpoints']} set points, s = {ds.attrs['dominance_threshold']:g}, "
             f"e = {ds.attrs['negligible_threshold']:g}", "",
             f"{'element':<8}{'share_tran':>11}  {'class':<14}{'peak_total':>12}  units"]
    from .reports.main_figures import identically_zero

    zero = (identically_zero(ds.peak_tran.values, ds.peak_rot.values, ds.peak_total.values,
                             ds.element_scale.values) if "element_scale" in ds.variables
            else [False] * ds.sizes["element"])
    for lab, share, cls, peak, unit, z in zip(ds.element.values, ds.share_tran.values,
                                              ds.dominance.values, ds.peak_total.values,
                                              ds.element_units.values, zero):
        shown = ZERO_MARK.rjust(11) if z else f"{share:>11.4f}"       # rounding noise: no share
        lines.append(f"{lab:<8}{shown}  {cls:<14}{peak:>12.4g}  {unit}")
    lines += ["", "simplified model torque error per joint:",
              f"{'joint':<6}{'peak [N m]':>12}{'rms [N m]':>12}{'peak |tau|':>12}"
              f"{'rel peak':>10}{'rel rms':>10}"]
    for j in range(ds.sizes["joint"]):
        lines.append(f"{j + 1:<6}{ds.tau_error_peak.values[j]:>12.4g}"
                     f"{ds.tau_error_rms.values[j]:>12.4g}{ds.tau_peak.values[j]:>12.4g}"
                     f"{ds.tau_error_relative_peak.values[j]:>10.2e}"
                     f"{ds.tau_error_relative_rms.values[j]:>10.2e}")
    if "verification_passed" in ds.attrs:
        import numpy as np

        worst = float(np.max([v for k, v in ds.attrs.items()
                              if k.startswith("verification_max_rel")]))
        lines += ["", f"verified against Pinocchio on {ds.attrs['verification_setpoints']} set "
                      f"points: largest relative difference {worst:.2e}"]
    return "\n".join(lines)


def _payload_masses(args):
    if args.payload_sweep is None:
        return None
    from .core.limits import LIMITS

    masses = parse_range(args.payload_sweep)
    if masses[-1] > LIMITS["mass"]:
        raise InputError(f"load masses up to {LIMITS['mass']:g} kg, got {masses[-1]:g}",
                         column="--payload-sweep")
    return masses


def _payload_sweep_dataset(robot, trajectory, args):
    """The ranking per load mass, as variables ``payload_*`` with dim ``payload``; or None."""
    masses = _payload_masses(args)
    if masses is None:
        return None
    from .io.sweep_datasets import embed_payload
    from .workflows.payload import payload_sweep

    ds = payload_sweep(robot, trajectory, masses, com=args.payload_com,
                       inertia=args.payload_inertia, dominance=args.dominance,
                       negligible=args.negligible)
    return embed_payload(ds)


ANALYZE_OUTPUTS = ("results.h5", "simplified_model.json", "simplified_model.c",
                   "simplified_model.py", "report.html", "report.pdf", "figures")


def _cmd_analyze(args):
    from .io.schema import skip_dask
    from .io.staging import check_free_space, staged_output
    from .workflows.analyze import analyze_to_file, progress_bar

    skip_dask()                         # the main job makes no dask arrays: skip its import
    bar = progress_bar(not args.quiet and sys.stderr.isatty())
    robot, trajectory = _load(args, args.trajectory)
    bar.reset(total=trajectory.n_setpoints)
    bar.update(trajectory.n_setpoints)
    _warn_limits(robot, trajectory, args.quiet)
    outdir = _outdir(args.outdir, robot.name, Path(args.trajectory).stem)
    base_robot = robot
    robot = _apply_payload(robot, args)
    if outdir.exists() and not outdir.is_dir():
        raise InputError("exists and is not a folder", outdir)
    settings = {"command": " ".join([PROG] + sys.argv[1:]) if sys.argv else PROG,
                "payload_mass": float(args.payload or 0.0),
                "tolerance": float(args.tolerance), "rule": args.rule,
                "torque_floor": float(args.torque_floor),
                "payload_com": [float(v) for v in args.payload_com],
                "payload_inertia": [float(v) for v in args.payload_inertia],
                **_chain_settings(args)}
    extra = _payload_sweep_dataset(base_robot, trajectory, args)   # bad range: before any output
    with staged_output(outdir, ANALYZE_OUTPUTS) as stage:
        check_free_space(stage, _results_size(trajectory.n_setpoints, robot.n), "results.h5")
        results = stage / "results.h5"
        analysis = analyze_to_file(robot, trajectory, results, dominance=args.dominance,
                                   negligible=args.negligible, check=not args.no_verify,
                                   settings=settings, compress=args.compress,
                                   progress=bar, extra=extra,
                                   tolerance=args.tolerance, rule=args.rule,
                                   torque_floor=args.torque_floor)
        analysis.model.save(stage / "simplified_model.json")
        written = [results, stage / "simplified_model.json",
                   *_write_sources(analysis.model, stage)]      # the explicit model
        if not args.no_report:
            from .reports.main import write_report

            bar.reset(total=trajectory.n_setpoints)
            bar.set_description("report")
            written += write_report(results, stage, paper=args.paper, progress=bar.update)
        bar.close()
    written = [outdir / Path(p).relative_to(stage) for p in written]
    if not args.quiet:
        print(_format_summary(analysis.dataset))
        print()
        print("wrote " + ", ".join(str(p) for p in written))
    if analysis.verification and not analysis.verification["passed"]:
        print(f"{PROG}: error: the G-D terms disagree with Pinocchio beyond "
              f"{analysis.verification['tolerance']:g} (see results.h5 attributes)",
              file=sys.stderr)
        return EXIT_VERIFY
    return EXIT_OK


def _check_plan(robot, start, goal, duration):
    """Refuse a plan that breaks the robot's limits: InputError naming the joint and limit.

    start, goal in SI (rad, m for a prismatic joint); robot with the limits the plan uses."""
    import numpy as np

    from .io.planning import quintic_min_durations

    prismatic = np.asarray(getattr(robot, "prismatic", np.zeros(robot.n, bool)), bool)

    def show(j, v, unit=""):
        return f"{v:g} m{unit}" if prismatic[j] else f"{math.degrees(v):g} deg{unit}"

    for name, vals in (("--start", start), ("--goal", goal)):
        for j, v in enumerate(vals):
            if not robot.q_min[j] <= v <= robot.q_max[j]:
                raise InputError(f"joint {j + 1} at {show(j, v)} is outside its position "
                                 f"limits [{show(j, robot.q_min[j])}, {show(j, robot.q_max[j])}]"
                                 f" (--ignore-limits to plan anyway)", column=name)
    if duration is None:
        return
    t_vel, t_acc = quintic_min_durations(robot, start, goal)
    for j in range(robot.n):
        for t_lim, what, lim in ((t_vel[j], "velocity", show(j, robot.qd_max[j], "/s")),
                                 (t_acc[j], "acceleration",
                                  show(j, robot.qdd_max[j], "/s^2"))):
            if duration < t_lim * (1 - 1e-12):
                raise InputError(f"{duration:g} s is too short: joint {j + 1} would exceed its "
                                 f"{what} limit {lim} (at least {t_lim:.6g} s; "
                                 f"--ignore-limits to plan anyway)", column="--duration")


def _cmd_plan(args):
    from ._version import __version__
    from .io.trajectory import write_trajectory
    from .io.planning import acceleration_limits, default_motion, plan_quintic, user_positions, write_provenance

    robot = _load_robot(args)
    start, goal = default_motion(robot)
    for name, vals in (("--start", args.start), ("--goal", args.goal)):
        if vals is not None and len(vals) != robot.n:
            raise InputError(f"{name}: {len(vals)} values for {robot.n} joints")
    start = start if args.start is None else user_positions(robot, args.start)
    goal = goal if args.goal is None else user_positions(robot, args.goal)
    from .core.limits import LIMITS, first_beyond

    if not 2 <= args.setpoints <= 10**8:
        raise InputError("--setpoints: a trajectory needs 2 to 10^8 set points")
    if args.duration is not None and not (LIMITS["min_duration"] <= args.duration
                                          <= LIMITS["duration"]):
        raise InputError(f"must be a number of seconds in [{LIMITS['min_duration']:g}, "
                         f"{LIMITS['duration']:g}], got {args.duration:g}", column="--duration")
    if args.output != "-":
        from .io.staging import check_output_file

        check_output_file(args.output)
    qdd_arg = args.qdd_max
    if qdd_arg is not None and len(qdd_arg) == 1:
        qdd_arg = qdd_arg * robot.n
    if qdd_arg is not None and len(qdd_arg) != robot.n:
        raise InputError(f"{len(qdd_arg)} values for {robot.n} joints", column="--qdd-max")
    try:
        qdd_max, qdd_source = acceleration_limits(
            robot, None if qdd_arg is None else user_positions(robot, qdd_arg))
    except ValueError as exc:
        raise InputError(str(exc), column="--qdd-max" if qdd_arg is not None else None) \
            from None
    planning = _replace_limits(robot, qdd_max)
    if not args.ignore_limits:
        _check_plan(planning, start, goal, args.duration)
    try:
        traj = plan_quintic(planning, start, goal, args.setpoints, args.duration)
    except ValueError as exc:
        raise InputError(str(exc)) from None
    for name in ("q", "qd", "qdd"):
        if first_beyond(getattr(traj, name), LIMITS[name]) is not None:
            raise InputError(f"the planned {name} exceeds the supported magnitude "
                             f"{LIMITS[name]:g}: choose a longer --duration", column="--duration")
    try:
        write_trajectory(traj, args.output)
    except OSError as exc:
        raise InputError(f"cannot write: {exc.strerror or exc}", args.output) from None
    if args.output == "-":
        return EXIT_OK
    record = {
        "tool": "gd-analyze", "version": __version__,
        "command": " ".join([PROG] + sys.argv[1:]) if sys.argv else PROG,
        "robot": robot.name, "robot_source": robot.source, "robot_sha256": robot.sha256,
        **_chain_settings(args),
        "start": [float(v) for v in start], "goal": [float(v) for v in goal],
        "start_goal_units": "rad (m for a prismatic joint)",
        "setpoints": traj.n_setpoints, "duration_s": float(traj.t[-1]),
        "duration_from": "--duration" if args.duration is not None else "limits",
        "qd_max": [float(v) for v in robot.qd_max],
        "qdd_max": [float(v) for v in qdd_max],
        "limits_units": "rad/s, rad/s^2 (m/s, m/s^2 for a prismatic joint)",
        "qdd_max_source": qdd_source,
        "trajectory": traj.source,
    }
    try:
        side = write_provenance(args.output, record)
    except OSError as exc:
        raise InputError(f"cannot write its provenance: {exc.strerror or exc}",
                         args.output) from None
    print(f"wrote {args.output}: {traj.n_setpoints} set points over {traj.t[-1]:.4f} s "
          f"({traj.source}); acceleration limits: {qdd_source}; provenance in {side}",
          file=sys.stderr)
    return EXIT_OK


def _replace_limits(robot, qdd_max):
    """The robot with other acceleration limits, for planning only."""
    import dataclasses

    return dataclasses.replace(robot, qdd_max=qdd_max)


def _cmd_evaluate(args):
    import json

    from .core.simplified import SimplifiedModel
    from .io.trajectory import read_trajectory
    from .workflows.evaluate import evaluate

    model = SimplifiedModel.load(args.model)
    traj = read_trajectory(args.trajectory, n_joints=model.robot.n)
    err = evaluate(model, traj, plant=_apply_payload(model.robot, args))
    worst = err.pop("max_relative_peak_error")
    exceeded = args.max_error is not None and worst > args.max_error
    if args.json:
        out = {"model": args.model, "trajectory": args.trajectory,
               "trajectory_sha256": traj.sha256, "robot": model.robot.name,
               "setpoints": traj.n_setpoints, "payload_mass": float(args.payload or 0.0),
               "max_relative_peak_error": worst,
               "max_error": args.max_error, "exceeded": exceeded, **err}
        print(json.dumps(out, allow_nan=False, default=str).replace("NaN", "null"))
    else:
        print(f"{model.robot.name} simplified model on {args.trajectory} "
              f"({traj.n_setpoints} set points)")
        print(f"{'joint':<6}{'peak [N m]':>12}{'rms [N m]':>12}{'peak |tau|':>12}"
              f"{'rel peak':>10}{'rel rms':>10}")
        for j in range(model.robot.n):
            print(f"{j + 1:<6}{err['peak_abs_error'][j]:>12.4g}{err['rms_error'][j]:>12.4g}"
                  f"{err['peak_tau'][j]:>12.4g}{err['relative_peak_error'][j]:>10.2e}"
                  f"{err['relative_rms_error'][j]:>10.2e}")
        print(f"largest relative peak error: {worst:.3e}")
    if exceeded:
        print(f"{PROG}: relative torque error {worst:.3e} exceeds --max-error "
              f"{args.max_error:g}", file=sys.stderr)
        return EXIT_TOLERANCE
    return EXIT_OK


def _cmd_compare(args):
    import json

    from .formulations.compare import compare_report, format_compare

    robot, traj = _load(args, args.trajectory)
    report = compare_report(robot, traj.q, traj.qd, traj.qdd)
    if args.json:
        print(json.dumps(report))
    else:
        print(format_compare(report))
    return EXIT_OK


def _cmd_control(args):
    import json

    from .core.simplified import SimplifiedModel
    from .files import file_sha256
    from .io.control_dataset import write_control_dataset
    from .workflows.control import CONTROL_FILE, run_control
    from .io.trajectory import read_trajectory

    from .reports.control import CONTROL_REPORT_FILES
    from .io.staging import staged_output

    model = SimplifiedModel.load(args.model)
    traj = read_trajectory(args.trajectory, n_joints=model.robot.n)
    outdir = _outdir(args.outdir, model.robot.name, Path(args.trajectory).stem, "control")
    if outdir.exists() and not outdir.is_dir():
        raise InputError("exists and is not a folder", outdir)
    try:
        result = run_control(model, traj, wn=args.wn, zeta=args.zeta, q0_offset=args.offset,
                             model_path=args.model, model_sha256=file_sha256(args.model))
    except ValueError as exc:
        raise InputError(str(exc)) from None
    with staged_output(outdir, (CONTROL_FILE, *CONTROL_REPORT_FILES, "figures")) as stage:
        path = stage / CONTROL_FILE
        write_control_dataset(result, path)
        written = [path]
        if not args.no_report:
            from .reports.control import write_control_report

            written += list(write_control_report(path, stage, paper=args.paper))
    written = [outdir / Path(p).relative_to(stage) for p in written]
    summary = result.summary()
    if args.json:
        print(json.dumps(summary, default=float))
    elif not args.quiet:
        print(f"computed-torque control of {model.robot.name} along {args.trajectory}: "
              f"wn = {args.wn:g} rad/s, zeta = {args.zeta:g}")
        print(f"{'controller':<12}" + "".join(f"{'joint ' + str(j + 1):>11}"
                                               for j in range(model.robot.n)))
        for name, fig in summary["tracking"].items():
            print(f"{name:<12}" + "".join(f"{v:>11.3e}" for v in fig["peak_grid"])
                  + "   peak |e| [rad]")
        if summary["tau_difference"]:
            print(f"{'tau diff':<12}" + "".join(f"{v:>11.3e}"
                                               for v in summary["tau_difference"]["peak"])
                  + "   peak |tau_simplified - tau_full| [N m]")
        print("wrote " + ", ".join(str(p) for p in written))
    return EXIT_OK


def _sweep_model(robot, trajectories, args, outdir, settings):
    """The sweep's simplified explicit model within EPS on every trajectory (issue 8)."""
    from .io.planning import random_trajectories
    from .workflows.simplify import sweep_model

    if args.held_out < 0:
        raise InputError("--held-out must be >= 0")
    held = random_trajectories(robot, args.held_out, seed=args.seed + 1_000_003) \
        if args.held_out else []
    model, _ = sweep_model(robot, trajectories, tolerance=args.tolerance,
                           torque_floor=args.torque_floor, held_out=held,
                           provenance={"gd_analyze_version": _version(), **settings})
    path = outdir / "sweep_model.json"
    model.save(path)
    written = [path]
    for name, text in (("sweep_model.c", model.c_source()),
                       ("sweep_model.py", model.python_source())):
        (outdir / name).write_text(text, encoding="utf-8")
        written.append(outdir / name)
    if not args.quiet:
        v = model.validation
        held_err = v["held_out"].get("relative_peak_error") if v["held_out"] else None
        print(f"sweep model (budget, EPS = {args.tolerance:g}): {model.cost['multiplications']} "
              f"mult + {model.cost['additions']} add (full explicit: "
              f"{model.full_cost['multiplications']} + {model.full_cost['additions']}); worst "
              f"relative error on the {v['trajectories']} swept trajectories "
              f"{max(x for x in v['relative_peak_error'] if x is not None):.2e} (guaranteed "
              f"<= {args.tolerance:g})" + ("" if held_err is None else
                                         f", on {v['held_out_trajectories']} held-out "
                                         f"{max(x for x in held_err if x is not None):.2e} "
                                         "(not guaranteed)"))
    return written


SWEEP_OUTPUTS = ("sweep.h5", "merged_model.json", "payload_sweep.h5", "sweep_report.html",
                 "sweep_report.pdf", "figures", "sweep_model.json", "sweep_model.c",
                 "sweep_model.py")


def _cmd_sweep(args):
    from .io.schema import write_dataset
    from .io.trajectory import read_trajectory
    from .io.planning import random_trajectories
    from .workflows.payload import sweep_payloads
    from .workflows.sweep import dask_client, merged_model, run_sweep

    robot = _load_robot(args)
    if (args.random is None) == (not args.csv):
        raise InputError("give either --random K or trajectory CSV files")
    if args.random is not None and not 1 <= args.random <= 10**6:
        raise InputError("--random: K must be in [1, 10^6]")
    if args.scheduler is not None:
        import re

        if not re.fullmatch(r"([a-z][a-z0-9+.-]*://)?[^\s/:]+(:[0-9]{1,5})?/?", args.scheduler):
            raise InputError("not a dask scheduler address (e.g. tcp://10.0.0.5:8786)",
                             column="--scheduler")
    if args.workers is not None and args.workers < 1:
        raise InputError("--workers must be >= 1")
    if args.csv:
        trajectories = [read_trajectory(path, n_joints=robot.n) for path in args.csv]
    else:
        trajectories = random_trajectories(robot, args.random, seed=args.seed)
    masses = _payload_masses(args)
    loaded = _apply_payload(robot, args)
    outdir = _outdir(args.outdir, robot.name, "sweep")
    if outdir.exists() and not outdir.is_dir():
        raise InputError("exists and is not a folder", outdir)
    settings = {"command": " ".join([PROG] + sys.argv[1:]) if sys.argv else PROG,
                "payload_mass": float(args.payload or 0.0), **_chain_settings(args)}
    if args.random is not None:
        from .io.planning import acceleration_limits

        settings["seed"] = args.seed
        try:
            settings["random_qdd_max_source"] = acceleration_limits(robot)[1]
        except ValueError as exc:
            raise InputError(str(exc), robot.source) from None
    try:
        with dask_client(args.scheduler, args.workers) as (client, _):
            ds = run_sweep(loaded, trajectories, args.dominance, args.negligible, client=client,
                           settings=settings, progress=not args.quiet and sys.stderr.isatty())
            payload = None if masses is None else sweep_payloads(
                robot, trajectories, masses, args.payload_com, args.payload_inertia,
                args.dominance, args.negligible, client=client)
    except (OSError, ValueError, TypeError) as exc:
        raise InputError(f"cannot reach the dask scheduler: {exc}", args.scheduler) from None
    from .io.staging import staged_output

    with staged_output(outdir, SWEEP_OUTPUTS) as stage:
        written = [stage / "sweep.h5", stage / "merged_model.json"]
        write_dataset(ds, written[0])
        merged_model(loaded, ds).save(written[1])
        if args.tolerance is not None:
            written += _sweep_model(loaded, trajectories, args, stage, settings)
        if payload is not None:
            written.append(stage / "payload_sweep.h5")
            write_dataset(payload, written[-1])
        if not args.no_report:
            from .reports.sweep import write_sweep_report

            written += list(write_sweep_report(written[0], stage, payload=payload,
                                               paper=args.paper))
    written = [outdir / Path(p).relative_to(stage) for p in written]
    if not args.quiet:
        print(f"{robot.name}: {ds.sizes['trajectory']} trajectories in "
              f"{ds.attrs['elapsed_s']:.1f} s on {ds.attrs['n_workers']} dask workers "
              f"({ds.attrs['scheduler_address']})")
        classes = [str(c) for c in ds["class"].values]
        print(f"{'element':<8}" + "".join(f"{c[:5]:>7}" for c in classes)
              + f"{'min':>8}{'median':>8}{'max':>8}  merged")
        for k, lab in enumerate(str(v) for v in ds.element.values):
            frac = ds.class_fraction.values[k]
            print(f"{lab:<8}" + "".join(f"{v:>7.3f}" for v in frac)
                  + f"{ds.share_tran_min.values[k]:>8.3f}{ds.share_tran_median.values[k]:>8.3f}"
                  + f"{ds.share_tran_max.values[k]:>8.3f}  {ds.merged_choice.values[k]}")
        print("wrote " + ", ".join(str(p) for p in written))
    return EXIT_OK


def _show_warning(message, category, filename, lineno, file=None, line=None):
    kind = "note" if issubclass(category, InputNote) else "warning"
    print(f"{PROG}: {kind}: {message}", file=sys.stderr)


def _mistyped_command(word):
    """A 'did you mean' error for a first word that is close to a command and is neither a
    built-in robot nor a file; None otherwise."""
    import difflib

    from .io.robots import builtin_robots          # the TOML and the URDF built-ins

    if word.startswith("-") or word in builtin_robots() or os.path.exists(word):
        return None
    close = difflib.get_close_matches(word, COMMANDS, n=1, cutoff=0.6)
    if not close:
        return None
    return InputError(f"unknown command {word!r}: did you mean '{close[0]}'? (commands: "
                      f"{', '.join(COMMANDS)}; or a robot for the main job)")


def main(argv=None):
    """Run the command line.

    Parameters
    ----------
    argv : list of str, optional
        Arguments without the program name (default ``sys.argv[1:]``). ``--debug`` anywhere
        shows the traceback of an internal error.

    Returns
    -------
    int
        The exit status: 0 ok, 1 verification failed, 2 bad input or unusable output location,
        3 error above --max-error, 4 internal error.
    """
    from .io.staging import Terminated, install_signal_handlers

    argv = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in argv
    argv = [a for a in argv if a != "--debug"]
    command = argv[0] if argv and argv[0] in COMMANDS else "analyze"
    if argv and argv[0] == command:
        argv = argv[1:]
    parsers = {"analyze": (_analyze_parser, _cmd_analyze), "plan": (_plan_parser, _cmd_plan),
               "evaluate": (_evaluate_parser, _cmd_evaluate),
               "compare": (_compare_parser, _cmd_compare),
               "control": (_control_parser, _cmd_control),
               "sweep": (_sweep_parser, _cmd_sweep)}
    make_parser, run = parsers[command]
    try:
        import threading

        if threading.current_thread() is threading.main_thread():
            install_signal_handlers()
        with warnings.catch_warnings():
            warnings.simplefilter("always", InputWarning)
            warnings.showwarning = _show_warning
            if command == "analyze" and argv:
                mistyped = _mistyped_command(argv[0])
                if mistyped is not None:
                    raise mistyped
            args = make_parser().parse_intermixed_args(argv)
            return run(args)
    except InputError as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return EXIT_INPUT
    except BrokenPipeError:
        # The reader of stdout went away (e.g. `| head`): not an error of ours.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return EXIT_OK
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130
    except Terminated as exc:
        print(f"{PROG}: terminated", file=sys.stderr)
        return 128 + int(exc.args[0]) if exc.args else 143
    except Exception as exc:  # noqa: BLE001 - the last line of defence: exit 4, one line
        if debug:
            import traceback

            traceback.print_exc()
        text = " ".join(str(exc).split())[:300]
        print(f"{PROG}: internal error: {type(exc).__name__}: {text} (a bug in gd-analyze; "
              f"{'see the traceback above' if debug else 'rerun with --debug for the traceback'})",
              file=sys.stderr)
        return EXIT_INTERNAL


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
