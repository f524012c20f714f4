"""The command line's parsers: one argparse parser per command, and the argument types.

Usage errors are one line with exit status 2 (:class:`_Parser`). The commands themselves are in
:mod:`gd_analyze.cli.commands`; :func:`gd_analyze.cli.main` ties the two together.
"""

from __future__ import annotations

import argparse
import decimal
import math
import re

from .._version import VERSION as __version__
from ..config import MAXIMA, defaults
from ..errors import InputError
from ..estimation.regressor import DRIVE_KINDS
from ..jobs.control import DEFAULT_WN, DEFAULT_ZETA, GAIN_RANGES
from ..jobs.identify import DEFAULT_DRIVES
from ..jobs.sweep import IN_PROCESS_SETPOINTS_MAX
from ..model.limits import DEFAULT_QDD_PER_QD, LIMITS
from ..model.robots import robots_text
from ..model.urdf import URDF_BUILTIN
from ..symbolic.safe_text import check_prefix
from ..trajectory.excitation import DEFAULT_DURATION, DEFAULT_HARMONICS, DEFAULT_SAMPLE_PERIOD
from ..trajectory.planning import DEFAULT_GOAL_DEG, DEFAULT_SETPOINTS, DEFAULT_START_DEG
from ..trajectory.trajectory import parse_number

__all__ = ["parse_range", "PROG", "COMMANDS", "EXIT_STATUS_HELP", "identify_parser"]

PROG = "gd-analyze"
#: A value that starts like a negative number (``-9.81,0,0``, ``-.5``, ``-1e3``).
_NEGATIVE = re.compile(r"-[0-9.]")


COMMANDS = ("analyze", "plan", "evaluate", "compare", "control", "sweep", "identify")


EXIT_OK, EXIT_VERIFY, EXIT_INPUT, EXIT_TOLERANCE, EXIT_INTERNAL = 0, 1, 2, 3, 4


EXIT_STATUS_HELP = ("Exit status: 0 ok, 1 verification failed, 2 bad input, an unusable output "
                    "location or a lost dask cluster, 3 evaluate's gate: an error above the model's tolerance x s_i or "
                    "--max-error, 4 internal error (--debug shows the "
                    "traceback).")


class _Parser(argparse.ArgumentParser):
    """argparse that reports usage errors as one line with exit status 2, and takes a value
    that starts with a minus sign (``--gravity -9.81,0,0``) as the option's value."""

    def error(self, message):
        sub = self.prog[len(PROG):].strip()
        raise InputError(f"{sub}: {message}" if sub else message)

    def parse_intermixed_args(self, args=None, namespace=None):
        return super().parse_intermixed_args(self._joined(args), namespace)

    def _joined(self, args):
        """``--opt -1.5,2`` as ``--opt=-1.5,2`` for an option taking one value: argparse
        reads only ``-1`` or ``-.5`` alone as a negative number, not a list of them."""
        takes = {o for a in self._actions if a.option_strings and a.nargs is None
                 and a.type is not None for o in a.option_strings}
        out, args = [], list(args or [])
        for k, a in enumerate(args):
            if out and out[-1] in takes and _NEGATIVE.match(a) and \
                    (k < 2 or "=" not in args[k - 1]):
                out[-1] = f"{out[-1]}={a}"
            else:
                out.append(a)
        return out


def parse_range(text: str, name: str = "--payload-sweep") -> list[float]:
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
        count: float = int((stop - start) // step) + 1
    except decimal.DecimalException:                  # e.g. 0:1:1e-30: beyond the precision
        count = math.inf
    if count > 10_000:
        raise InputError(f"the range {text!r} has {count:.3g} values (at most 10000)",
                         column=name)
    return [float(start + k * step) for k in range(int(count))]


def _number(text, integer=False):
    """A number of the command line by the trajectory CSV's rules
    (:func:`gd_analyze.trajectory.trajectory.parse_number`): plain decimal, finite."""

    try:
        return parse_number(text.strip(" "), integer=integer)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def _checked(parse, ok, message):
    """An argument type: ``parse`` the text, then refuse a value ``v`` for which ``ok(v)``
    fails, with ``message`` formatted with ``v`` and ``text``."""
    def checked(text):
        v = parse(text)
        if not ok(v):
            raise argparse.ArgumentTypeError(message.format(v=v, text=text))
        return v
    return checked


def _integer(text):
    return _number(text, integer=True)


def _whole(name, lo=0, hi=None):
    """A whole number of at least lo (and at most hi, if given), by the CSV's rules (no ``1_0``,
    no other digits)."""
    return _checked(_integer, lambda v: lo <= v <= (v if hi is None else hi), f"{name} must be "
                    + (f"at least {lo}" if hi is None else f"in [{lo}, {hi}]") + ", got {v}")


def _fraction(lo, hi, name, ends="(]"):
    """A finite number from lo to hi, an end included where ``ends`` has a square bracket
    (``"[)"``: lo but not hi)."""
    return _checked(_number, lambda v: math.isfinite(v) and (lo <= v if ends[0] == "[" else lo < v)
                    and (v <= hi if ends[1] == "]" else v < hi),
                    f"{name} must be in {ends[0]}{lo}, {hi}{ends[1]}, got {{v}}")


def _angles(text):
    try:
        return [_number(v) for v in text.split(",")]
    except argparse.ArgumentTypeError as exc:
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers, got {text!r}: "
                                         f"{exc}") from None


def _numbers(check, message):
    """Comma-separated numbers (:func:`_angles`) for which ``check`` holds; else the error
    ``message`` followed by ``got TEXT``."""
    return _checked(_angles, check, message + ", got {text!r}")


def _verdict_tolerance(text):
    """RAD or RAD,M: the control verdict's tolerance for revolute [rad] and prismatic [m]
    joints (one number: both)."""
    vals = _numbers(lambda v: len(v) in (1, 2) and all(0 < x <= 1e3 for x in v),
                    "--verdict-tolerance needs 1 or 2 numbers in (0, 1e3]")(text)
    return (vals[0], vals[-1])


def _vector3(name):
    return _numbers(lambda v: len(v) == 3, f"{name} needs 3 comma-separated numbers")


def _add_payload_arguments(p, sweep=False):
    """--payload, --payload-com, --payload-inertia (with ``sweep``: --payload-sweep after them)."""
    g = p.add_argument_group("payload (a rigid load fixed to the last link)")
    g.add_argument("--payload", metavar="MASS", type=_fraction(0.0, math.inf, "--payload", "[)"),
                   help="load mass [kg] (the PUMA 560's rated load is 2.5 kg)")
    g.add_argument("--payload-com", metavar="X,Y,Z", type=_vector3("--payload-com"),
                   default=[0.0, 0.0, 0.0], help="load centre of mass in the last link frame [m]")
    g.add_argument("--payload-inertia", metavar="IXX,IYY,IZZ",
                   type=_vector3("--payload-inertia"), default=[0.0, 0.0, 0.0],
                   help="load principal moments about its centre of mass [kg m^2]")
    if sweep:
        g.add_argument("--payload-sweep", metavar="START:STOP:STEP",
                       help="also rank the elements for each load mass in this range [kg], "
                            "stop included, e.g. 0:2.5:0.5; uses --payload-com and "
                            "--payload-inertia for the load's shape (stored with dim 'payload')")


def _add_mounting_arguments(p, what="the arm"):
    g = p.add_argument_group("mounting (recorded in the provenance)")
    g.add_argument("--gravity", metavar="GX,GY,GZ", type=_vector3("--gravity"),
                   help="gravity in the world frame [m/s^2] (default: the robot file's, e.g. "
                        "0,0,-9.81; 0,0,0 for none)")
    g.add_argument("--base-rpy", metavar="R,P,Y", type=_vector3("--base-rpy"),
                   help=f"roll, pitch, yaw of {what}'s base in the world [deg] (URDF "
                        "convention R = Rz(Y) Ry(P) Rx(R); gravity in the base frame is R^T g): "
                        "e.g. 0,90,0 on a wall, 0,180,0 on a ceiling (default 0,0,0)")


def _add_chain_arguments(p):
    g = p.add_argument_group(f"URDF chain (a ROBOT given as a .urdf file, or "
                             f"{', '.join(sorted(URDF_BUILTIN))})")
    g.add_argument("--base", metavar="LINK",
                   help="the chain's base link (default: the URDF's root link)")
    g.add_argument("--tip", metavar="LINK",
                   help="the chain's tip link (default: the end of the only chain); moving "
                        "joints off the chain are locked at q = 0 and carried by their link")


def _robot_help():
    return (f"built-in robot ({robots_text()}), a TOML robot file or a URDF file (*.urdf, see "
            "--base and --tip)")


def _q_ranges(text):
    """``LO:HI`` (one for all joints) or ``LO:HI,LO:HI,...`` (one per joint), as pairs."""
    pairs = []
    for part in text.split(","):
        ends = part.split(":")
        if len(ends) != 2:
            raise argparse.ArgumentTypeError(f"expected LO:HI per joint (e.g. -90:90 or "
                                             f"-90:90,0:45), got {text!r}")
        lo, hi = (_number(e) for e in ends)
        if not lo < hi:
            raise argparse.ArgumentTypeError(f"each range LO:HI needs LO < HI, got {part!r}")
        pairs.append((lo, hi))
    return pairs


def _positive_list(name):
    """Comma-separated finite numbers of at least LIMITS["least_rate"], 1e-9 (one for all
    joints or one per joint): a smaller velocity or acceleration limit overflows a duration
    (15 |dq| / (8 qd_max)) or underflows the squares of the motions it allows."""
    least = LIMITS["least_rate"]
    return _numbers(lambda v: min(v) >= least, f"{name} limits must be at least {least:g}")


def _add_region_arguments(p, what="the region over which the bound is proved (--guarantee "
                                  "region) and the analysed trajectory is checked"):
    """--q-limits, --qd-max, --qdd-max: the user's region (in degrees as the other options)."""

    g = p.add_argument_group(f"region ({what})")
    g.add_argument("--q-limits", metavar="LO:HI[,...]", type=_q_ranges,
                   help="position range of the region [deg; m for a prismatic joint], LO:HI for "
                        "all joints or LO:HI,LO:HI,... one per joint (default: the robot's "
                        "limits; a revolute joint spanning 360 deg or more is any angle, a full "
                        "turn). Beyond the robot's own limits a range is clipped to them, with a "
                        "warning")
    g.add_argument("--qd-max", metavar="V[,...]", type=_positive_list("--qd-max"),
                   help="velocity limits of the region [deg/s; m/s for a prismatic joint], one "
                        "for all joints or one per joint (default: the robot's; above the "
                        "robot's clipped to it, with a warning)")
    g.add_argument("--qdd-max", metavar="A[,...]", type=_positive_list("--qdd-max"),
                   help="acceleration limits of the region [deg/s^2; m/s^2 for a prismatic "
                        "joint], one for all joints or one per joint (default: the robot's; "
                        f"where it has none, as in a URDF, assumed {DEFAULT_QDD_PER_QD:g} s^-1 "
                        "times the velocity limit, i.e. full speed in "
                        f"1/{DEFAULT_QDD_PER_QD:g} s, which the printed region says)")


def _add_budget_arguments(p, where="s_i: by default the largest |tau_i| found over the region "
                          "(a search: a lower bound of the region's largest; see --guarantee "
                          "and --q-limits), with --guarantee trajectory max(peak |tau_i| on the "
                          "analysed trajectory, TAU)",
                          guarantee="the trajectory only"):
    """The simplified model's options; ``where``: the scale of the budget in these words;
    ``guarantee``: the second choice of --guarantee in these words."""
    g = p.add_argument_group("simplified model (error budget)")
    g.add_argument("--tolerance", metavar="EPS", default=defaults["tolerance"],
                   type=_fraction(0.0, MAXIMA["tolerance"], "--tolerance", "[]"),
                   help="error budget: every joint's simplified torque stays within EPS times "
                        f"its scale {where} (default {defaults['tolerance']:g})")
    g.add_argument("--torque-floor", metavar="TAU", default=defaults["torque_floor"],
                   type=_fraction(0, MAXIMA["torque_floor"], "--torque-floor", "[]"),
                   help=f"least scale of a joint torque [N m] (default "
                        f"{defaults['torque_floor']:g})")
    g.add_argument("--rule", choices=("budget", "chapter"), default=defaults["rule"],
                   help="budget: by torque contribution within EPS (default); chapter: "
                        "the share-based classes of Sec. 3.4.1 (no bound)")
    g.add_argument("--guarantee", choices=("region", "trajectory"),
                   default=defaults["guarantee"],
                   help="where the bound must hold: proved over the robot's joint-limit "
                        "region (default when the robot gives position and velocity limits "
                        f"for every joint) or on {guarantee}")
    g.add_argument("--explicit", choices=("auto", "always", "never"),
                   default=defaults["explicit"],
                   help="derive the explicit G-D model too: auto (default) where its "
                        "estimated size is cheap and it may be deployed (not with --form "
                        "recursive), always, or never (not with --rule chapter)")
    g.add_argument("--form", choices=("cheapest", "recursive", "explicit"),
                   default=defaults["form"],
                   help="the simplified model written: the cheaper of the pruned recursive "
                        "and explicit models (default), or that form (explicit: derived "
                        "whatever --explicit says; --rule chapter writes no recursive)")


def _add_threshold_arguments(p, dominance="default {}", negligible="default {}"):
    """--dominance and --negligible, each help text a template of its default."""
    p.add_argument("--dominance", metavar="S", type=_fraction(0.5, 1.0, "--dominance"),
                   default=defaults["dominance"], help=dominance.format(defaults["dominance"]))
    p.add_argument("--negligible", metavar="E", type=_fraction(0.0, 1.0, "--negligible", "[)"),
                   default=defaults["negligible"], help=negligible.format(defaults["negligible"]))


def _add_outdir_argument(p, default):
    """-o, the output folder (``default``: where it goes without -o)."""
    p.add_argument("-o", "--outdir", metavar="OUTDIR", help=f"output folder (default: {default})")


def _add_verbose_argument(p, quiet="print nothing but errors",
                          default=" (default: how many, and the folder)"):
    """-q (help ``quiet``) and -v (its help ending in ``default``), one or the other."""
    g = p.add_mutually_exclusive_group()
    g.add_argument("-q", "--quiet", action="store_true", help=quiet)
    g.add_argument("-v", "--verbose", action="store_true", help="list every file written" + default)


def _add_print_arguments(p, skip, column=False):
    """--no-report (skipping ``skip``, the report's files), then --paper and --latex (with
    ``column``, --column-figures between them)."""
    p.add_argument("--no-report", action="store_true", help=f"skip {skip}")
    if column:
        p.add_argument("--column-figures", action="store_true",
                       help="also write every report figure 3.5 in wide (one column) as "
                            "figures/<name>_column.pdf and .svg (default: page width only)")
    p.add_argument("--paper", choices=("a4", "letter"), default=defaults["paper"],
                   help="page size of the PDF report (default a4)")
    p.add_argument("--latex", action="store_true",
                   help="also write every report table as LaTeX in tables/, a .tex file beside "
                        "each .csv (the CSV files are always written)")


def analyze_parser() -> argparse.ArgumentParser:
    """The main job's parser (``gd-analyze ROBOT TRAJECTORY``).

    Returns
    -------
    argparse.ArgumentParser
        Its options, defaults from :data:`gd_analyze.config.defaults`.
    """
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
    p.add_argument("robot", metavar="ROBOT", help=_robot_help())
    p.add_argument("trajectory", metavar="TRAJECTORY.csv",
                   help="CSV with header t,q1..qn[,qd1..qdn,qdd1..qddn] [s, rad, rad/s, rad/s^2]")
    _add_outdir_argument(p, "reports/<robot>-<csv stem>/")
    _add_threshold_arguments(p, "share at which one part dominates, in (0.5, 1] (default {})",
                             "an element below E times its scale is negligible (default {})")
    _add_budget_arguments(p)
    _add_region_arguments(p)
    p.add_argument("--prefix", metavar="NAME", type=_prefix, default=None,
                   help="prefix of the emitted model's C symbols and CasADi functions, a C "
                        "identifier (default: the robot's name made one, plus _, e.g. "
                        "puma560_)")
    _add_print_arguments(p, "report.html and report.pdf", column=True)
    p.add_argument("--compress", metavar="LEVEL", type=_whole("--compress"), choices=range(10),
                   default=defaults["compress"],
                   help="gzip level 0-9 for the per-set-point variables of results.h5 "
                        "(default 0: uncompressed, fastest)")
    p.add_argument("--no-verify", action="store_true",
                   help="skip the verification against Pinocchio")
    _add_verbose_argument(p, "print nothing but warnings and errors (no summary, no progress bar)")
    p.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    _add_chain_arguments(p)
    _add_mounting_arguments(p)
    _add_payload_arguments(p, sweep=True)
    return p


def _prefix(text):
    """--prefix: a C identifier (:func:`gd_analyze.symbolic.safe_text.check_prefix`)."""

    try:
        return check_prefix(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def plan_parser() -> argparse.ArgumentParser:
    """``plan``'s parser.

    Returns
    -------
    argparse.ArgumentParser
        Its options, defaults from :data:`gd_analyze.config.defaults`.
    """

    p = _Parser(prog=f"{PROG} plan",
                description="Write a quintic rest-to-rest joint trajectory at the shortest "
                            "duration within the robot's velocity and acceleration limits, or "
                            "with --excitation a Fourier series excitation for identification, "
                            "and its provenance beside it (FILE's stem + .provenance.json).")
    p.add_argument("robot", metavar="ROBOT", help=_robot_help())
    p.add_argument("-o", "--output", metavar="FILE", required=True,
                   help="CSV file to write ('-' for standard output)")
    p.add_argument("--start", metavar="DEG,...", type=_angles,
                   help="start positions [deg; m for a prismatic joint] (default for puma560: "
                        f"{','.join(f'{v:g}' for v in DEFAULT_START_DEG)}; for other robots "
                        "between staggered fractions (0.2 to 0.8) of each joint's range, so "
                        "that no two joints move alike)")
    p.add_argument("--goal", metavar="DEG,...", type=_angles,
                   help="goal positions [deg; m for a prismatic joint] (default for puma560: "
                        f"{','.join(f'{v:g}' for v in DEFAULT_GOAL_DEG)}; for other robots "
                        "the other end of the start's span: even joints move up, odd joints "
                        "down)")
    p.add_argument("--setpoints", metavar="N", type=_whole("--setpoints", 2, 10**8),
                   help=f"number of set points, both ends included (default {DEFAULT_SETPOINTS}; "
                        f"with --excitation one per {DEFAULT_SAMPLE_PERIOD * 1e3:g} ms, and at "
                        "least more than 2 per period of the highest harmonic, and (N - 1) n "
                        "rows for the regressor's columns: the last set point repeats the first)")
    p.add_argument("--duration", metavar="T", type=_number,
                   help="duration [s] (default: the shortest within the limits; with "
                        f"--excitation one period of the base frequency, {DEFAULT_DURATION:g} s "
                        "without --base-frequency)")
    p.add_argument("--excitation", action="store_true",
                   help="plan an excitation for identification instead: a finite Fourier series "
                        "(Swevers et al. 1997) from rest to rest, within the position, velocity "
                        "and acceleration limits, minimising the condition number of the "
                        "column-scaled base regressor with armature, viscous, Coulomb and "
                        "offset columns")
    p.add_argument("--harmonics", metavar="K", type=_whole("--harmonics", 2, 100),
                   help=f"with --excitation: harmonics of the series (default "
                        f"{DEFAULT_HARMONICS})")
    p.add_argument("--base-frequency", metavar="WF", type=_number,
                   help="with --excitation: base frequency w_f [rad/s] (default 2 pi / T); "
                        "T must be a whole number of periods 2 pi / w_f")
    p.add_argument("--seed", metavar="S", type=_seed,
                   help="with --excitation: seed of the optimiser's random starts, an integer "
                        "in [0, 2^63) (default 0)")
    p.add_argument("--ignore-limits", action="store_true",
                   help="plan even if the duration, start or goal breaks the robot's joint "
                        "position, velocity or acceleration limits")
    _add_region_arguments(p, "the limits the plan keeps to, in place of the robot's; the "
                             "provenance says which")
    _add_chain_arguments(p)
    _add_mounting_arguments(p)
    return p


def evaluate_parser() -> argparse.ArgumentParser:
    """``evaluate``'s parser.

    Returns
    -------
    argparse.ArgumentParser
        Its options, defaults from :data:`gd_analyze.config.defaults`.
    """
    p = _Parser(prog=f"{PROG} evaluate",
                description="Report a simplified model's torque error on another trajectory, "
                            "the model's guarantee and whether it covers the trajectory.")
    p.add_argument("model", metavar="MODEL.json")
    p.add_argument("trajectory", metavar="TRAJECTORY.csv")
    p.add_argument("--max-error", metavar="REL", type=_fraction(0.0, math.inf, "--max-error", "[)"),
                   help="exit with status 3 if the peak relative torque error of any joint "
                        "(relative to its peak |tau| on the trajectory; to the model's s_i "
                        "where that is 0) exceeds REL (default: exit 3 if any joint's error "
                        "exceeds the model's tolerance x s_i, the scale of its guarantee; no "
                        "gate for a model without one)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    _add_payload_arguments(p)
    _add_mounting_arguments(p, "the reference arm")
    p.epilog = ("With --payload, --gravity or --base-rpy, the reference torques are those of the "
                "arm carrying the load or mounted so, while the simplified model keeps its own "
                "robot: the error shows whether the model holds there.")
    return p


def compare_parser() -> argparse.ArgumentParser:
    """``compare``'s parser.

    Returns
    -------
    argparse.ArgumentParser
        Its options, defaults from :data:`gd_analyze.config.defaults`.
    """
    p = _Parser(prog=f"{PROG} compare",
                description="Run Lagrange-Euler, Newton-Euler, G-D and Pinocchio on every set "
                            "point and print their largest relative disagreements and the "
                            "operation counts per set point.")
    p.add_argument("robot", metavar="ROBOT", help=_robot_help())
    p.add_argument("trajectory", metavar="TRAJECTORY.csv")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    _add_chain_arguments(p)
    _add_mounting_arguments(p)
    return p


def control_parser() -> argparse.ArgumentParser:
    """``control``'s parser.

    Returns
    -------
    argparse.ArgumentParser
        Its options, defaults from :data:`gd_analyze.config.defaults`.
    """

    p = _Parser(prog=f"{PROG} control",
                description="Simulate computed-torque control of the full-model arm along a "
                            "trajectory with three controllers: one built on the full G-D "
                            "model, one on the simplified model, and PD with gravity "
                            "compensation (plain PD on an arm without gravity); write control.h5 and control_report.html/.pdf.")
    p.add_argument("model", metavar="MODEL.json")
    p.add_argument("trajectory", metavar="TRAJECTORY.csv")
    _add_outdir_argument(p, "reports/<robot>-<csv stem>-control/")
    (wn_lo, wn_hi), (z_lo, z_hi) = GAIN_RANGES["wn"], GAIN_RANGES["zeta"]
    p.add_argument("--wn", metavar="RAD/S", type=_fraction(wn_lo, wn_hi, "--wn", "[]"),
                   default=DEFAULT_WN,
                   help=f"natural frequency of the error dynamics [rad/s], {wn_lo:g} to {wn_hi:g} "
                        f"(default {DEFAULT_WN:g}); Kp = wn^2, Kv = 2 zeta wn")
    p.add_argument("--zeta", metavar="Z", type=_fraction(z_lo, z_hi, "--zeta", "[]"),
                   default=DEFAULT_ZETA,
                   help=f"damping ratio, {z_lo:g} to {z_hi:g} (default {DEFAULT_ZETA:g})")
    p.add_argument("--offset", metavar="RAD", type=_fraction(-2 * math.pi, 2 * math.pi,
                                                             "--offset", "[]"),
                   default=0.0, help="initial position error on every joint [rad; m on a "
                                     "prismatic joint], within [-2 pi, 2 pi] (default 0)")
    rad, metre = defaults["verdict_tolerance"]
    p.add_argument("--verdict-tolerance", metavar="RAD[,M]", type=_verdict_tolerance,
                   default=tuple(defaults["verdict_tolerance"]),
                   help="the report's verdict: the simplified-model controller is good enough "
                        "if its peak tracking error is within this, or twice the full-model "
                        "controller's (from an --offset: if its loop departs from the "
                        "full-model controller's by at most this), on every revolute joint "
                        "[rad] and prismatic joint [m], and the model's region guarantee "
                        "covers the run "
                        f"(default {rad:g},{metre:g}; one number for both)")
    _add_print_arguments(p, "the HTML and PDF report", column=True)
    p.add_argument("--json", action="store_true", help="print the figures as one JSON object")
    _add_verbose_argument(p)
    _add_mounting_arguments(p, "the controlled arm (the plant, and the full-model and PD + "
                               "gravity controllers; the simplified model keeps its own)")
    return p


def sweep_parser() -> argparse.ArgumentParser:
    """``sweep``'s parser.

    Returns
    -------
    argparse.ArgumentParser
        Its options, defaults from :data:`gd_analyze.config.defaults`.
    """
    p = _Parser(prog=f"{PROG} sweep",
                description="Rank the G-D elements over many trajectories on dask, give the "
                            "envelope of the ranking per element and one merged simplified model "
                            "(budget rule: within EPS x s_i, proved over the robot's joint-limit "
                            "region by default, or on every swept trajectory with --guarantee "
                            "trajectory; --rule chapter: no error bound); write sweep.h5, "
                            "merged_model.json with its emitted C, numpy and CasADi sources, and "
                            "sweep_report.html/.pdf.")
    p.add_argument("robot", metavar="ROBOT", help=_robot_help())
    p.add_argument("csv", metavar="CSV", nargs="*", help="trajectory files (or use --random)")
    p.add_argument("--random", metavar="K", type=_whole("--random", 1, 10**6),
                   help="plan K random quintic trajectories (start and goal uniform in the "
                        "joint limits, shortest duration within the limits, 31 set points)")
    p.add_argument("--seed", metavar="S", type=_seed, default=0,
                   help="seed for --random, an integer in [0, 2^63)")
    _add_outdir_argument(p, "reports/<robot>-sweep/")
    cluster = p.add_mutually_exclusive_group()      # a running cluster has its own workers
    cluster.add_argument("--scheduler", metavar="ADDRESS",
                         help="address of a running dask scheduler (default: start a LocalCluster; "
                              f"a sweep of at most {IN_PROCESS_SETPOINTS_MAX:,} set points without "
                              "--workers runs in the command's own process)")
    cluster.add_argument("--workers", metavar="N", type=_whole("--workers", 1, 256),
                         help="workers of the LocalCluster, started even for a small sweep "
                              "(default: one per core; at most 256, each a process)")
    _add_threshold_arguments(p)
    _add_budget_arguments(p, where="over the joint-limit region (see --guarantee) or on every "
                                   "swept trajectory (scale_i = max(that trajectory's peak "
                                   "|tau_i|, TAU)); the merged model merged_model.json and its emitted "
                                   "sources",
                          guarantee="the swept trajectories only")
    _add_region_arguments(p, "the region over which the merged model's bound is proved "
                             "(--guarantee region), in place of the robot's limits; random "
                             "trajectories keep to the robot's")
    p.add_argument("--held-out", metavar="K", type=_whole("--held-out", 0, 10**6), default=20,
                   help="random trajectories (another seed) to measure the merged model of the "
                        "budget rule on, not guaranteed (default 20; none, said in one warning "
                        "line, on an arm without the limits to plan them)")
    _add_print_arguments(p, "the HTML and PDF report", column=True)
    _add_verbose_argument(p)
    _add_chain_arguments(p)
    _add_mounting_arguments(p)
    _add_payload_arguments(p, sweep=True)
    return p


_seed = _checked(_integer, lambda v: 0 <= v < 2**63, "--seed must be in [0, 2^63), got {text}")


def _cutoff(text):
    """``--cutoff``: a frequency [Hz] > 0, ``auto`` or ``none``."""
    word = text.strip().lower()
    if word == "auto":
        return "auto"
    if word == "none":
        return None
    return _checked(_number, lambda v: v > 0,
                    "a cutoff must be > 0 Hz (or 'auto', 'none'), got {text!r}")(text)


def _drive_list(text):
    """``--drives``: comma-separated drive columns, or ``none``."""

    word = text.strip().lower()
    if word == "none":
        return ()
    kinds = tuple(k.strip() for k in word.split(","))
    bad = [k for k in kinds if k not in DRIVE_KINDS]
    if bad or len(set(kinds)) < len(kinds):
        raise argparse.ArgumentTypeError(
            (f"unknown drive column {bad[0]!r}" if bad else f"a drive column given twice in "
             f"{text!r}") + f" (known: {', '.join(DRIVE_KINDS)}, or none)")
    return kinds


#: ``--drive-gains``: comma-separated nonzero numbers [N m/A], at most 1e6 in size (a current
#: of the recordings' largest magnitude times it then stays far from a float's range).
_gains = _checked(lambda text: tuple(_number(v) for v in text.split(",")),
                  lambda v: 0 not in v and max(map(abs, v)) <= 1e6,
                  "a drive gain is nonzero and at most 1e6 N m/A in size (0 turns no current "
                  "into torque), got {text!r}")


def identify_parser() -> argparse.ArgumentParser:
    """``identify``'s parser.

    Returns
    -------
    argparse.ArgumentParser
        Its options.
    """

    p = _Parser(prog=f"{PROG} identify",
                description="Identify the robot's base parameters and drives (armature, "
                            "viscous and Coulomb friction, offset) from recorded torques by "
                            "weighted least squares, and write identification.h5 and "
                            "identified_robot.toml.")
    p.add_argument("robot", metavar="ROBOT", help=_robot_help() + "; its parameters are the "
                   "prior and the comparison")
    p.add_argument("recordings", metavar="RECORDING.csv", nargs="+",
                   help="recordings to fit: t,q1..qn,tau1..taun[,qd1..][,qdd1..] or <joint>_position,"
                        "_effort[,_velocity] (s, rad or m, N m or N); A.csv+B.csv: files on one clock")
    p.add_argument("--validate", metavar="FILE.csv", nargs="+", action="extend", default=[],
                   help="recordings not used for fitting, on which the errors are reported")
    _add_outdir_argument(p, "reports/ROBOT-NAME-identify, NAME the first recording's name")
    p.add_argument("--json", action="store_true",
                   help="print one JSON object: the recordings' errors and the condition number")
    p.add_argument("--cutoff", metavar="HZ", type=_cutoff, default="auto",
                   help="low-pass cutoff [Hz] of the zero-phase filter on q and tau; 'auto' "
                        "(default): 5 x the bandwidth holding 99%% of the positions' power; "
                        "'none': no filter")
    p.add_argument("--decimate", metavar="K", type=_whole("--decimate", lo=1), default=1,
                   help="keep every K-th sample after filtering (default 1)")
    p.add_argument("--drives", metavar="LIST", type=_drive_list, default=DEFAULT_DRIVES,
                   help="drive columns identified, from armature, viscous, coulomb, offset, or "
                        f"none (default {','.join(DEFAULT_DRIVES)})")
    p.add_argument("--current", action="store_true",
                   help="the torque columns hold motor currents [A]; give --drive-gains")
    p.add_argument("--drive-gains", metavar="K1,..", type=_gains,
                   help="per joint the gain K [N m/A] of tau = K i (with --current)")
    p.add_argument("--consistent", action="store_true",
                   help="physically consistent standard parameters (each link's pseudo-inertia "
                        ">= 0; cvxpy with Clarabel or SCS)")
    p.add_argument("--simplify", action="store_true",
                   help="also build the simplified model of the identified robot and state its "
                        "error on the validation recordings")
    _add_print_arguments(p, "report.html and report.pdf")
    _add_chain_arguments(p)
    _add_verbose_argument(p, default="")
    return p
