"""The commands of the command line: each runs a workflow, writes its files and prints a summary.

``cmd_<command>(args)`` (``cmd_analyze`` for the main job) takes the parsed arguments of
:mod:`gd_analyze.cli.parsing` (``<command>_parser``) and returns the exit status: ``analyze``,
``plan``, ``evaluate``, ``compare``, ``control``, ``sweep`` (many trajectories on dask, the
merged model) and ``identify`` (recordings -> identification.h5 and identified_robot.toml);
bad input raises :class:`gd_analyze.errors.InputError`, which
:func:`gd_analyze.cli.main` prints as one line with exit status 2.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import json
import math
import os
import re
import shlex
import sys
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import cast

import numpy as np

from .._version import VERSION as __version__
from ..certify.region import RegionLimits, joint_region
from ..dynamics.compare import compare_report, format_compare
from ..errors import InputError, InputWarning
from ..estimation.estimate import RANK_TOL
from ..estimation.preprocess import most_samples
from ..files import file_sha256
from ..jobs.analyze import progress_bar
from ..jobs.control import CONTROL_FILE, DEFAULT_GRID_POINTS, run_control
from ..jobs.evaluate import coverage, evaluate, gate
from ..jobs.identify import IdentifyOptions, identify, recording_name
from ..jobs.options import AnalysisOptions, SimplifyOptions
from ..jobs.payload import sweep_payloads
from ..jobs.peak_jobs import derives_explicit
from ..jobs.run import Payload, run_analysis
from ..jobs.sweep_merged import (
    budget_region_model,
    budget_sweep_model,
    merged_model,
    with_budget_model,
    with_model_cost,
)
from ..model.limits import LIMITS, acceleration_limits, exact_text, first_beyond
from ..model.mounting import mounting_of, with_mounting
from ..model.robot import Robot, with_payload
from ..model.robot_file import robot_toml
from ..model.robots import is_urdf, load_robot
from ..model.urdf_writer import robot_urdf
from ..ranking.labels import joint_units_text
from ..report.control import dataset_verdict, write_control_report
from ..report.identify import write_identify_report
from ..report.main import write_report
from ..report.main_context import effort_rows
from ..report.numbers import count
from ..report.sweep import write_sweep_report
from ..simplify.deploy import guarantee_region, robot_region
from ..simplify.deploy import release as release_searches
from ..simplify.simplified import json_safe
from ..store import control_dataset as control_file
from ..store import model_trust
from ..store.datasets import joint_units
from ..store.model_file import load_model, save_model
from ..store.results_view import ZERO_MARK, Results, torque_table_header
from ..store.schema import write_dataset
from ..store.staging import check_free_space, check_output_file, safe_name, staged_output, writing
from ..store.stored_identification import (
    identification_size,
    identification_tree,
    recordings_json,
    write_identification,
)
from ..store.sweep_view import (
    StoredSweep,
    beyond_the_floor,
    merged_guarantee,
    sweep_size,
    with_more_tasks,
)
from ..symbolic.safe_text import c_prefix
from ..trajectory.excitation import DEFAULT_HARMONICS, OBJECTIVE_SAMPLES, plan_excitation
from ..trajectory.planning import (
    DEFAULT_SETPOINTS,
    check_velocity_limits,
    default_motion,
    provenance_mismatch,
    provenance_path,
    quintic_min_durations,
    quintic_plan,
    random_trajectories,
    user_positions,
    write_provenance,
)
from ..trajectory.trajectory import (
    JointLimitWarning,
    check_joint_limits,
    read_recording,
    read_trajectory,
    recording_files,
    unwrapped,
    write_trajectory_chunks,
)
from .parsing import EXIT_OK, EXIT_TOLERANCE, EXIT_VERIFY, PROG, parse_range

__all__ = []

def command_line(args: argparse.Namespace) -> str:
    """The command as :func:`gd_analyze.cli.main` was given it, for the provenance (a shell
    could run it: each argument quoted as needed)."""
    return shlex.join([PROG] + [str(a) for a in getattr(args, "given_argv", ())])


def load_robot_arg(args: argparse.Namespace) -> Robot:
    """The robot named by ``args.robot`` (with ``--base``, ``--tip``), mounted by ``--gravity``
    and ``--base-rpy``.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed arguments of :mod:`gd_analyze.cli.parsing`.

    Returns
    -------
    Robot

    Raises
    ------
    gd_analyze.errors.InputError
        If the robot cannot be read (:func:`gd_analyze.model.robots.load_robot`).
    """

    return with_mounting(load_robot(args.robot, args.base, args.tip),
                         getattr(args, "gravity", None), getattr(args, "base_rpy", None))


def model_mounting(model_robot: Robot, args: argparse.Namespace,
                   path: str | os.PathLike[str]) -> Robot:
    """The reference arm of ``evaluate`` and ``control``: the model's robot mounted by
    ``--gravity`` and ``--base-rpy`` in the world, in place of the mounting it was built with
    (never on top of it); an option equal to that mounting changes nothing, with one note."""
    rpy, g_world = mounting_of(model_robot)
    for opt, given, own in (("--gravity", args.gravity, g_world),
                            ("--base-rpy", args.base_rpy, rpy)):
        if given is not None and np.array_equal(np.asarray(given, float), own):
            warnings.warn(f"{opt} {','.join(f'{float(v):g}' for v in own)} is the mounting "
                          f"{path} was built with (recorded in it): applied once, not again",
                          InputWarning)
    return with_mounting(model_robot, args.gravity, args.base_rpy)


def mounting_settings(args: argparse.Namespace, robot: Robot) -> dict[str, list[float]]:
    """The mounting, for the provenance: the options as given and the gravity they give in the
    base frame [m/s^2]."""
    out = {"mounting_base_rpy_deg": [float(v) for v in (args.base_rpy or (0.0, 0.0, 0.0))],
           "mounting_gravity_base": [float(v) for v in robot.gravity]}
    if args.gravity is not None:
        out["mounting_gravity_world"] = [float(v) for v in args.gravity]
    return out


def run_settings(args: argparse.Namespace, robot: Robot, /, **extra: object
                 ) -> dict[str, object]:
    """The provenance of a run's outputs: the command (:func:`command_line`), ``extra``, the
    URDF chain options given and the mounting (:func:`mounting_settings`)."""
    chain = {k: v for k, v in (("robot_base", args.base), ("robot_tip", args.tip)) if v}
    return {"command": command_line(args), **extra, **chain, **mounting_settings(args, robot)}


def apply_payload(robot: Robot, args: argparse.Namespace) -> Robot:
    """The robot with the --payload options' load, if any (Sec. 3.4.1's loaded arm)."""

    payload = _payload(args)
    return robot if payload is None or not payload.mass else with_payload(
        robot, payload.mass, payload.com, payload.inertia)


def output_folder(args_outdir: str | os.PathLike[str] | None, *parts: str) -> Path:
    """The output folder: -o as given, or reports/<sanitised parts joined by '-'>; InputError
    if it is there and is not a folder, or a name in it is too long for the file system."""
    if args_outdir == "":   # -o "$DIR" with DIR unset: no folder the user named
        raise InputError("an empty name is no folder", column="--outdir")
    folder = Path(args_outdir) if args_outdir is not None else \
        Path("reports") / "-".join(safe_name(p) for p in parts)
    base = folder.absolute()
    while not os.path.exists(base) and base != base.parent:
        base = base.parent
    try:
        limit = os.pathconf(base, "PC_NAME_MAX")
    except (OSError, ValueError):
        limit = 255
    for part in folder.parts:
        if len(os.fsencode(part)) > limit:
            raise InputError(f"a name of {len(os.fsencode(part))} bytes in the path is longer "
                             f"than the file system allows ({limit})", folder)
    # after the names' lengths: asking for a name the file system cannot hold raises
    if folder.exists() and not folder.is_dir():
        raise InputError("exists and is not a folder", folder)
    return folder


def wrote_line(files: Sequence[Path], folder: Path, verbose: bool) -> str:
    """The last line a command prints: ``wrote 26 files to DIR``, or with ``-v`` every file.

    Parameters
    ----------
    files : sequence of pathlib.Path
        The files written, in ``folder`` or below it.
    folder : pathlib.Path
        The output folder.
    verbose : bool
        List each file (comma-separated) instead of their count.

    Returns
    -------
    str

    Examples
    --------
    >>> wrote_line([Path("o/a.h5"), Path("o/figures/b.pdf")], Path("o"), False)
    'wrote 2 files to o'
    >>> wrote_line([Path("o/a.h5"), Path("o/figures/b.pdf")], Path("o"), True)
    'wrote o/a.h5, o/figures/b.pdf'
    """
    if verbose:
        return "wrote " + ", ".join(str(p) for p in files)
    return f"wrote {len(files)} file{'s' if len(files) != 1 else ''} to {folder}"


def _load(args):
    robot = load_robot_arg(args)
    return robot, unwrapped(robot, read_trajectory(args.trajectory, robot.n, robot.joint_names()))






def _cost_lines(costs):
    """The simplified model's counted operations beside Newton-Euler's, from the stored table
    (:class:`gd_analyze.store.stored_simplified.CostTable`, or None)."""
    names = [] if costs is None else list(costs.models)
    mine = [k for k, name in enumerate(names) if name.endswith("(this model)")]
    ne = [k for k, name in enumerate(names) if name == "project N-E as implemented"]
    if not mine or not ne:
        return []
    m, a = int(costs.multiplications[mine[0]]), int(costs.additions[mine[0]])
    total, ne_total = m + a, int(costs.total[ne[0]])
    others = "".join(f"; {label}: {int(costs.total[names.index(key)]):,}"
                     for key, label in (("recursive N-E, exact", "exact recursive model"),
                                        ("explicit, full", "full explicit model"))
                     if key in names)
    lines = ["", f"simplified model ({names[mine[0]].replace(' (this model)', '')}): {total:,} "
                 f"operations per set point ({m:,} multiplications, {a:,} additions){others}; "
                 f"Newton-Euler as implemented: {ne_total:,}"]
    if total >= ne_total:
        lines.append("  it does not beat Newton-Euler for this arm: for speed, use N-E (the "
                     "model still gives the error bound and the dominance)")
    return lines


def _format_summary(results):
    """The main job's summary as printed, from the typed results view
    (:class:`gd_analyze.store.results_view.Results`)."""

    lines = [f"{results.robot} along {results.input_file}: "
             f"{count(results.setpoints)} set points, s = {results.dominance_threshold:g}, "
             f"e = {results.negligible_threshold:g}", "", *results.ranking.text()]
    lines += ["", "simplified model torque error per joint:", *results.torque_error.text()]
    rows = effort_rows(results)     # each joint's peak |tau| against its effort limit
    if rows:
        lines += ["", "effort limits (peak |tau| of the full model against the robot's limit):",
                  f"{'joint':<6}{'peak |tau|':>12}{'limit':>12}  {'units':<6}{'ratio':>7}  flag"]
        for j, peak, limit, ratio, flag, unit in rows:
            lines.append(f"{j:<6}{peak:>12.4g}{limit:>12.4g}  {unit:<6}{ratio:>7.3f}  {flag}")
        over = [str(r[0]) for r in rows if r.exceeded]
        if over:
            lines.append(f"  joint{'s' if len(over) > 1 else ''} {', '.join(over)} exceed"
                         f"{'' if len(over) > 1 else 's'} {'their' if len(over) > 1 else 'its'} "
                         "effort limit along this trajectory")
    lines += _cost_lines(results.costs)
    region, scope = results.region, results.guarantee
    if scope is not None:           # the model built, as results.h5 stores it: the region (one
        # line per limit kind), the guarantee line (saying when the analysed trajectory leaves
        # the region, which the guarantee then does not cover) and s_i per joint in N m with
        # how it was found (a region kind's as the analysis stored it)
        lines += ([] if lines[-1].startswith(("simplified model", "  it does")) else [""])
        lines += [] if region is None else list(region["lines"])
        statement = scope["statement"]
        if region is not None and region["covered"] is False and scope["kind"] == "region":
            statement += ("; this trajectory is not covered: it leaves the region (the "
                          "guarantee holds in the region, not on this trajectory)")
        lines.append(f"guarantee: {statement}")
        screen = results.region_screen
        if screen:
            lines.append(("pruned region model not built: " if results.region_screen_proved
                          else "region certification skipped: ") + screen)
        if scope.get("scale") is not None and scope["kind"] != "none":
            pris = results.prismatic
            mixed = any(pris) and not all(pris)
            unit = "" if mixed else f" [{'N' if all(pris) else 'N m'}]"
            where = ((scope.get("scale_source") or "the largest |tau_i| found over the region, "
                      "a lower bound of the region's largest")
                     + (", or the torque floor where larger" if results.simplified is not None
                        and results.simplified.torque_floor > 0 else "")
                     if scope["kind"] == "region" else
                     "max(peak |tau_i| on the trajectory, torque floor)")
            eps = scope["tolerance"]
            lines.append(f"s_i{unit} ({where}): " + ", ".join(
                f"{j + 1} {v:.4g}" + ((" N" if pris[j] else " N m") if mixed else "")
                for j, v in enumerate(scope["scale"]))
                + (f"; {100 * eps:.4g} % of s_i: " + ", ".join(
                    f"{j + 1} {eps * v:.3g}" for j, v in enumerate(scope["scale"]))
                   if eps == eps else ""))
    if results.inertia_check:                   # the proof of the model built
        lines += ([] if lines[-1].startswith(("guarantee:", "s_i")) else [""]) + [
            f"D_s: {results.inertia_check}"]
    check = results.verification
    if check is not None:
        checked, total = check.setpoints, results.setpoints
        where = ("verified against Pinocchio on "
                 + (f"{count(checked)} of {count(total)}" if checked < total else count(checked))
                 + " set points")
        lines += ["", f"{where}: every difference within round-off (64 eps of its scale)"
                  if check.worst_excess == 0 else
                  f"{where}: largest difference beyond round-off {check.worst_excess:.2e} of its "
                  "natural scale"]
    return "\n".join(lines)


def payload_mass_list(args: argparse.Namespace) -> list[float] | None:
    """The payload masses of ``--payload-sweep`` [kg], or None without it.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed arguments of :mod:`gd_analyze.cli.parsing`.

    Returns
    -------
    list of float or None
        Increasing masses [kg].

    Raises
    ------
    gd_analyze.errors.InputError
        If the range is malformed or a mass exceeds the supported limit.
    """
    if args.payload_sweep is None:
        return None

    masses = parse_range(args.payload_sweep)
    if masses[0] < 0 or masses[-1] > LIMITS["mass"]:
        raise InputError(f"load masses in [0, {LIMITS['mass']:g}] kg, got {masses[0]:g} to "
                         f"{masses[-1]:g}", column="--payload-sweep")
    return masses


def region_limits(args: argparse.Namespace, robot: Robot) -> RegionLimits | None:
    """The user's region from ``--q-limits``, ``--qd-max`` and ``--qdd-max``, in SI units, or
    None when none is given; its clipped limits printed as warnings.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed arguments (degrees for a revolute joint, metres for a prismatic one).
    robot : Robot
        The arm the region is for.

    Returns
    -------
    RegionLimits or None

    Raises
    ------
    gd_analyze.errors.InputError
        If an option has neither one nor n values, or a range lies wholly outside the robot's
        limits: one line naming the option.
    """
    given = {k: v for k in ("q_limits", "qd_max", "qdd_max")
             if (v := getattr(args, k, None)) is not None}
    if not given:
        return None
    pris = np.asarray(robot.prismatic, bool)
    out = {}
    for key, vals in given.items():
        option = f"--{key.replace('_', '-')}"
        if len(vals) not in (1, robot.n):
            raise InputError(f"{len(vals)} values for {robot.n} joints (give one for all or one "
                             "per joint)", column=option)
        v = np.asarray(vals * robot.n if len(vals) == 1 else vals, float)
        v = np.where(pris[:, None] if v.ndim == 2 else pris, v, np.radians(v))
        out[key] = tuple(map(tuple, v)) if v.ndim == 2 else tuple(v)
    try:
        limits = RegionLimits(**out)
        region, _ = robot_region(robot, limits)
    except ValueError as exc:
        option, _, why = str(exc).partition(": ")
        raise InputError(why or option, column=option if why else None) from None
    for note in () if region is None else region.notes:
        print(f"{PROG}: warning: the region: {note}", file=sys.stderr)
    return limits


def check_rule_options(args: argparse.Namespace) -> None:
    """Refuse ``--form recursive`` or ``--explicit never`` beside ``--rule chapter``, whose
    model is the explicit model's elements (the rule of
    :class:`gd_analyze.simplify.options.SimplifyOptions`).

    Raises
    ------
    gd_analyze.errors.InputError
        Naming the option refused.
    """
    try:
        SimplifyOptions(rule=args.rule, form=args.form, explicit=args.explicit)
    except ValueError as exc:
        raise InputError(str(exc), column="--form" if args.form == "recursive"
                         else "--explicit") from None


def _payload(args):
    """The --payload options as a Payload (mass 0 with --payload-sweep alone: the swept loads'
    shape, the arm analysed unloaded), or None; InputError for a shape without a mass."""

    if args.payload is None and getattr(args, "payload_sweep", None) is None:   # evaluate: none
        if any(args.payload_com) or any(args.payload_inertia):
            raise InputError("--payload-com and --payload-inertia need --payload or --payload-sweep")
        return None
    return Payload(float(args.payload or 0.0), tuple(float(v) for v in args.payload_com),
                   tuple(float(v) for v in args.payload_inertia))


def cmd_analyze(args: argparse.Namespace) -> int:
    """The main job: G-D terms, verification, ranking, simplified model, files and report.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed arguments of :mod:`gd_analyze.cli.parsing`.

    Returns
    -------
    int
        The exit status: 0 ok, 1 verification failed, 2 bad input, 3 evaluate gate, 4 internal
        error (:mod:`gd_analyze.cli.parsing`).

    Raises
    ------
    gd_analyze.errors.InputError
        On bad input; the command line prints it as one line and exits 2.
    """

    check_rule_options(args)
    bar = progress_bar(not args.quiet and sys.stderr.isatty())
    robot, trajectory = _load(args)
    bar.reset(total=trajectory.n_setpoints)
    bar.update(trajectory.n_setpoints)
    warnings.simplefilter("always", JointLimitWarning)    # beyond the joint limits: a line each
    check_joint_limits(robot, trajectory)
    report = None
    if not args.no_report:
        def report(results, folder, progress):
            # the command's one model is built: what the process kept for a later model of
            # the arm (a 12-joint arm's certification, about 300 MB) goes before the report
            release_searches()
            model_trust.release()
            bar.reset(total=trajectory.n_setpoints)
            bar.set_description("report")
            return write_report(results, folder, paper=args.paper, progress=bar.update,
                                column_figures=args.column_figures, latex=args.latex)
    options = AnalysisOptions(
        dominance=args.dominance, negligible=args.negligible, verify=not args.no_verify,
        compress=args.compress,
        simplify=SimplifyOptions(tolerance=args.tolerance, rule=args.rule,
                                 torque_floor=args.torque_floor, explicit=args.explicit,
                                 form=args.form, guarantee=args.guarantee,
                                 region=region_limits(args, robot)))
    outputs = run_analysis(
        robot, trajectory, options, output_folder(args.outdir, robot.name,
                                                  Path(args.trajectory).stem),
        report=report, settings=run_settings(args, robot),
        payload=_payload(args), payload_masses=payload_mass_list(args), progress=bar,
        prefix=args.prefix)
    bar.close()
    analysis = outputs.analysis
    results = Results.from_dataset(analysis.dataset)    # the summary in memory, typed
    region = results.region
    if region is not None and region["covered"] is False:
        print(f"{PROG}: warning: the trajectory leaves the region: {region['coverage']}",
              file=sys.stderr)
    if not args.quiet:
        print(_format_summary(results))
        print()
        print(wrote_line(outputs.files, outputs.outdir, args.verbose))
    if analysis.verification and not analysis.verification["passed"]:
        print(f"{PROG}: error: the G-D terms disagree with Pinocchio beyond "
              f"{analysis.verification['tolerance']:g} (see results.h5 attributes)",
              file=sys.stderr)
        return EXIT_VERIFY
    return EXIT_OK


def _check_plan(robot, start, goal, duration):
    """Refuse a plan that breaks the robot's limits: InputError naming the joint and limit.

    start, goal in SI (rad, m for a prismatic joint); robot with the limits the plan uses."""

    def show(j, v, unit=""):
        return f"{v:g} m{unit}" if robot.prismatic[j] else f"{math.degrees(v):g} deg{unit}"

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


def cmd_plan(args: argparse.Namespace) -> int:
    """``plan``: a quintic rest-to-rest trajectory within the robot's limits, written as CSV.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed arguments of :mod:`gd_analyze.cli.parsing`.

    Returns
    -------
    int
        The exit status: 0 ok, 1 verification failed, 2 bad input, 3 evaluate gate, 4 internal
        error (:mod:`gd_analyze.cli.parsing`).

    Raises
    ------
    gd_analyze.errors.InputError
        On bad input; the command line prints it as one line and exits 2.
    """
    robot = load_robot_arg(args)
    # the arm with the user's region (--q-limits, --qd-max, clipped to the robot's) as its
    # limits, the region asked for (or None) and the user's acceleration limits [rad/s^2;
    # m/s^2] (or None)
    limits = region_limits(args, robot)
    qdd_arg = None
    if limits is not None:
        try:        # the user's position and velocity limits, within the robot's
            own = joint_region(robot, np.ones(robot.n), limits)
        except ValueError as exc:
            option, _, why = str(exc).partition(": ")
            raise InputError(why or option, column=option if why else None) from None
        robot = dataclasses.replace(robot, q_min=np.where(own.full_turn, robot.q_min, own.q_min),
                                    q_max=np.where(own.full_turn, robot.q_max, own.q_max),
                                    qd_max=own.qd_max)
        qdd_arg = None if limits.qdd_max is None else own.qdd_max
    if args.excitation:
        return _plan_excitation(args, robot, qdd_arg)
    for name in ("harmonics", "base_frequency", "seed"):
        if getattr(args, name) is not None:
            raise InputError("only with --excitation", column=f"--{name.replace('_', '-')}")
    if args.duration is None or not args.ignore_limits:     # the plan needs the limits
        warn_if(check_velocity_limits(robot, "give --duration with --ignore-limits"))
    start, goal = default_motion(robot)
    for name, vals in (("--start", args.start), ("--goal", args.goal)):
        if vals is not None and len(vals) != robot.n:
            raise InputError(f"{name}: {len(vals)} values for {robot.n} joints")
        far = None if vals is None else first_beyond(user_positions(robot, vals), LIMITS["q"])
        if far is not None:     # no trajectory may hold it, whatever its duration
            raise InputError(f"joint {far[0] + 1} at {vals[far[0]]:g} is beyond the largest "
                             f"position accepted, {math.degrees(LIMITS['q']):.6g} deg (a "
                             f"prismatic joint: {LIMITS['q']:g} m)", column=name)
    start = start if args.start is None else user_positions(robot, args.start)
    goal = goal if args.goal is None else user_positions(robot, args.goal)

    _check_plan_options(args)
    try:
        qdd_max, qdd_source = acceleration_limits(robot, qdd_arg)
    except ValueError as exc:
        if qdd_arg is not None or args.duration is None or not args.ignore_limits:
            raise InputError(str(exc), column="--qdd-max" if qdd_arg is not None else None) \
                from None
        qdd_max, qdd_source = robot.qdd_max, "none (the robot gives none; --ignore-limits)"
    if limits is not None and limits.qd_max is not None and limits.qdd_max is None:
        qdd_source = qdd_source.replace("qd_max", "the --qd-max given")
    planning = dataclasses.replace(robot, qdd_max=qdd_max)      # for planning only
    if not args.ignore_limits:
        _check_plan(planning, start, goal, args.duration)
    try:
        plan = quintic_plan(planning, start, goal, args.setpoints or DEFAULT_SETPOINTS,
                            args.duration)
    except ValueError as exc:       # start = goal, with no duration
        raise InputError(str(exc), column="--goal" if "coincide" in str(exc) else None) from None
    T = plan.duration                                       # t runs from 0 to T
    if first_beyond([T], LIMITS["t"]) is not None:          # the CSV reader's rule
        t_vel, t_acc = quintic_min_durations(planning, start, goal)     # T is the larger
        own = "--qd-max" if getattr(limits, "qd_max", None) is not None else "robot"
        kind, source = (("velocity", own) if t_vel.max() >= t_acc.max()
                        else ("acceleration", qdd_source))
        raise InputError(f"the planned duration, {exact_text(T)} s, is beyond the supported "
                         f"magnitude {LIMITS['t']:g} s: the {kind} limits ({source}) are too small",
                         column=next((o for o in ("--qdd-max", "--qd-max") if o in source), None))
    return _write_plan(args, robot, plan, {
        "q_min": robot.q_min, "q_max": robot.q_max, "qd_max": robot.qd_max, "qdd_max": qdd_max,
        "qdd_source": qdd_source}, ": choose a longer --duration", {
        "start": [float(v) for v in start], "goal": [float(v) for v in goal],
        "start_goal_units": "rad (m for a prismatic joint)",
        "duration_from": "--duration" if args.duration is not None else "limits",
        **({} if limits is None else {"region": limits.settings()})})


def _write_plan(args, robot, motion, limits, advice, record, detail=""):
    """Write a planned motion (:class:`~gd_analyze.trajectory.planning.SampledMotion`) piece by
    piece to ``args.output``, every piece's values checked against the CSV reader's limits
    before it is written, then its provenance beside it: the tool, the command, the robot and
    its chain and mounting, ``record``, then the set points, the duration, the ``limits`` the
    plan kept to (``q_min``, ``q_max``, ``qd_max``, ``qdd_max``, per joint, and
    ``qdd_source``) and how the motion was made.

    A file is written under a temporary name (:func:`write_trajectory_chunks`), each piece
    checked just before it is written: a piece beyond the limits stops the write and removes
    the temporary file, so nothing is left, and the pieces are computed once (``advice`` ends
    the refusal). Standard output cannot take back what it was given: every piece is checked
    first, then written (the pieces computed twice).

    Then, for a file, one line on stderr: ``wrote FILE: N set points over T s (how);
    <detail>acceleration limits: <qdd_source>; provenance in <its provenance file>`` (standard
    output: no provenance, no line). Returns 0."""

    def checked(pieces):
        for piece in pieces:
            for name in ("q", "qd", "qdd"):
                if first_beyond(getattr(piece, name), LIMITS[name]) is not None:
                    raise InputError(f"the planned {name} exceeds the supported magnitude "
                                     f"{LIMITS[name]:g}{advice}", column="--duration")
            yield piece

    output = args.output
    if output == "-":
        for _ in checked(motion.chunks()):
            pass
        written = motion.chunks()
    else:
        written = checked(motion.chunks())
    try:
        write_trajectory_chunks(written, robot.n, output)
    except OSError as exc:      # a reader of stdout gone away (`| head`) is not bad input
        raise (exc if isinstance(exc, BrokenPipeError) else
               InputError(f"cannot write: {exc.strerror or exc}", output)) from None
    if output == "-":
        return EXIT_OK
    try:
        # JSON holds no NaN or inf: a limit the robot does not give (NaN or inf) is null
        side = write_provenance(output, json_safe({
            "tool": "gd-analyze", "version": __version__, **run_settings(
                args, robot, robot=robot.name, robot_source=robot.source,
                robot_sha256=robot.sha256), **record, "setpoints": motion.n_setpoints,
            "duration_s": float(motion.duration),
            **{k: list(limits[k]) for k in ("q_min", "q_max", "qd_max", "qdd_max")},
            "limits_units": "rad, rad/s, rad/s^2 (m, m/s, m/s^2 for a prismatic joint); null: "
                            "no limit",
            "qdd_max_source": limits["qdd_source"], "trajectory": motion.source}))
    except OSError as exc:
        raise InputError(f"cannot write its provenance: {exc.strerror or exc}",
                         output) from None
    print(f"wrote {output}: {motion.n_setpoints} set points over {motion.duration:.4f} s "
          f"({motion.source}); {detail}acceleration limits: {limits['qdd_source']}; provenance "
          f"in {side}", file=sys.stderr)
    return EXIT_OK


def _check_plan_options(args, positive=False):
    """Refuse ``plan``'s --duration and --base-frequency out of range (with
    ``positive``: a --duration or --base-frequency <= 0 as not positive, first), then an
    output CSV or provenance that this run may not write (store/staging.py)."""
    for name, value in (("--duration", args.duration), ("--base-frequency", args.base_frequency)):
        if positive and value is not None and not value > 0:
            raise InputError(f"must be positive, got {value:g}", column=name)
    if args.duration is not None and not (LIMITS["min_duration"] <= args.duration
                                          <= LIMITS["duration"]):
        raise InputError(f"must be a number of seconds in [{LIMITS['min_duration']:g}, "
                         f"{LIMITS['duration']:g}], got {args.duration:g}", column="--duration")
    if args.base_frequency is not None and not (1e-6 <= args.base_frequency <= 1e4):
        raise InputError(f"must be in [1e-6, 1e4] rad/s, got {args.base_frequency:g}",
                         column="--base-frequency")
    if args.output != "-":
        check_output_file(args.output)
        check_output_file(provenance_path(args.output))


def _plan_excitation(args, robot, qdd_arg):
    """``plan --excitation``: a Fourier series excitation within the limits, written as CSV.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed arguments of ``plan``.
    robot : Robot
        The arm, loaded and mounted, with the user's region as its limits.
    qdd_arg : ndarray, shape (n,), or None
        The user's acceleration limits [rad/s^2; m/s^2 for a prismatic joint], or None for the
        robot's (or the assumed ones).

    Returns
    -------
    int
        0; bad input raises :class:`~gd_analyze.errors.InputError`.
    """
    no_ends = "a Fourier series has no start or goal"
    for name, why in (("start", no_ends), ("goal", no_ends),
                      ("ignore-limits", "an excitation always stays within the limits")):
        if getattr(args, name.replace("-", "_")) not in (None, False):
            raise InputError(f"not with --excitation ({why})", column=f"--{name}")
    warn_if(check_velocity_limits(robot))
    _check_plan_options(args, positive=True)
    seed = 0 if args.seed is None else args.seed
    try:                # --harmonics is a whole number from 2
        ex = plan_excitation(robot, duration=args.duration, seed=seed, qdd_max=qdd_arg,
                             harmonics=args.harmonics or DEFAULT_HARMONICS,
                             base_frequency=args.base_frequency, n_setpoints=args.setpoints)
    except ValueError as exc:
        column = ("--setpoints" if "set points" in str(exc) and args.setpoints is not None
                  else "--duration" if "duration" in str(exc) or "period" in str(exc)
                  else "--qdd-max" if qdd_arg is not None and "acceleration" in str(exc)
                  else None)
        raise InputError(str(exc), column=column) from None
    # its duration is within the CSV reader's LIMITS["t"]: --duration at most
    # LIMITS["duration"], else one period 2 pi / w_f (w_f at least 1e-6 rad/s) or 10 s
    if ex.condition > 1 / RANK_TOL:     # beyond it the estimator's rank test may drop columns
        warn_if(f"scaled condition number {ex.condition:.4g} above {1 / RANK_TOL:g} (1 / the "
                "estimator's rank tolerance): identify may find parameters not identifiable")
    series = ex.series
    return _write_plan(args, robot, ex, ex.limits, "", {
        "excitation": {
            "method": "finite Fourier series (Swevers et al. 1997), coefficients constrained to "
                      "start and end at rest, optimised by SLSQP for the scaled condition "
                      "number",
            "harmonics": series.harmonics, "base_frequency_rad_s": series.wf,
            "periods": ex.periods, "seed": seed,
            "q0": series.q0.tolist(), "a": series.a.tolist(), "b": series.b.tolist(),
            "coefficients_units": "q0 rad, a and b rad/s (m, m/s for a prismatic joint)",
            "regressor_columns": ex.columns.names(),
            "drive_columns_regrouped": ex.columns.dropped(),
            "scaled_condition_number": ex.condition,
            "random_starts_scaled_condition_numbers": ex.start_conditions,
            "shrink": ex.shrink.tolist(),
            "optimiser": list(ex.messages),
            "seconds": ex.seconds,
            "bounds": {**{k: getattr(ex.bounds, k).tolist()
                          for k in ("q_low", "q_high", "qd_peak", "qdd_peak")},
                       "grid_points_per_period": ex.bounds.points},
        },
    }, f"scaled condition number {ex.condition:.4g} of {ex.columns.count} columns on "
       f"{OBJECTIVE_SAMPLES} samples of a period (random starts: "
       f"{float(np.min(ex.start_conditions)):.4g} at best), {ex.seconds:.1f} s; ")


def _load_model(args):
    """``evaluate``'s and ``control``'s inputs: the model of ``args.model``, its robot and the
    trajectory of ``args.trajectory``, with one warning line when the trajectory's provenance
    names another robot."""
    model = load_model(args.model)
    model_robot = cast(Robot, model.robot)      # the model file's arm
    traj = unwrapped(model_robot, read_trajectory(args.trajectory, model_robot.n,
                                           model_robot.joint_names()))
    warn_if(provenance_mismatch(args.trajectory, model_robot))
    return model, model_robot, traj


def warn_if(message: str | None) -> None:
    """One warning line (:class:`gd_analyze.errors.InputWarning`) with ``message``, if any.

    Parameters
    ----------
    message : str or None
        The warning; None or "" warns nothing.
    """
    if message:
        warnings.warn(message, InputWarning)


def _print_coverage(scope):
    """The model's guarantee and whether it covers the trajectory
    (:func:`gd_analyze.jobs.evaluate.coverage`), as ``evaluate`` and ``control`` print them."""
    print(f"model's guarantee: {scope['statement']}")
    print(f"covers this trajectory: {'yes' if scope['covered'] else 'no'}: {scope['reason']}")


def cmd_evaluate(args: argparse.Namespace) -> int:
    """``evaluate``: a simplified model's torque error on a trajectory, gated by its guarantee.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed arguments of :mod:`gd_analyze.cli.parsing`.

    Returns
    -------
    int
        The exit status: 0 ok, 1 verification failed, 2 bad input, 3 evaluate gate, 4 internal
        error (:mod:`gd_analyze.cli.parsing`).

    Raises
    ------
    gd_analyze.errors.InputError
        On bad input; the command line prints it as one line and exits 2.
    """
    model, model_robot, traj = _load_model(args)
    plant = apply_payload(model_mounting(model_robot, args, args.model), args)
    err = evaluate(model, traj, plant=plant)
    worst = err.pop("max_relative_peak_error")
    scope = coverage(model, traj, plant=plant, path=args.model)
    verdict = gate(err, model, args.max_error)
    if args.json:
        out = {"model": args.model, "trajectory": args.trajectory,
               "trajectory_sha256": traj.sha256, "robot": model_robot.name,
               "setpoints": traj.n_setpoints, "payload_mass": float(args.payload or 0.0),
               **mounting_settings(args, plant),
               "max_relative_peak_error": worst, "guarantee": scope,
               "max_error": args.max_error, "gate": verdict["by"],
               "gate_limit": verdict["limit"], "worst_joint": verdict["worst_joint"],
               "exceeded": verdict["exceeded"], **err}
        print(json.dumps(json_safe(out), allow_nan=False, default=str))
    else:
        print(f"{model_robot.name} simplified model on {args.trajectory} "
              f"({traj.n_setpoints} set points)")
        header, ends = torque_table_header(joint_units(model_robot.prismatic, "tau"))
        print(header)
        for j in range(model_robot.n):
            print(f"{j + 1:<6}{err['peak_abs_error'][j]:>12.4g}{err['rms_error'][j]:>12.4g}"
                  f"{err['peak_tau'][j]:>12.4g}{err['relative_peak_error'][j]:>10.2e}"
                  f"{err['relative_rms_error'][j]:>10.2e}{ends[j]}"
                  + ("  (relative to s_i: no torque here)" if err["relative_to"][j] == "s_i"
                     else "  (no torque, no s_i)" if err["relative_to"][j] == "none" else ""))
        print(f"largest relative peak error: {worst:.3e}")
        _print_coverage(scope)
        print("gate: " + (f"--max-error {args.max_error:g}" if args.max_error is not None
                          else "the model's tolerance x scale (EPS s_i) per joint"
                          if verdict["by"] else
                          "none (the model carries no guarantee; --max-error sets one)"))
    if verdict["exceeded"]:
        print(f"{PROG}: {verdict['message']}", file=sys.stderr)
        return EXIT_TOLERANCE
    return EXIT_OK


def cmd_compare(args: argparse.Namespace) -> int:
    """``compare``: L-E, N-E, G-D and Pinocchio on every set point, and their costs (Table 3.5).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed arguments of :mod:`gd_analyze.cli.parsing`.

    Returns
    -------
    int
        The exit status: 0 ok, 1 verification failed, 2 bad input, 3 evaluate gate, 4 internal
        error (:mod:`gd_analyze.cli.parsing`).

    Raises
    ------
    gd_analyze.errors.InputError
        On bad input; the command line prints it as one line and exits 2.
    """
    robot, traj = _load(args)
    report = compare_report(robot, traj.q, traj.qd, traj.qdd)
    if args.json:
        print(json.dumps({**report, **mounting_settings(args, robot)}))
    else:
        print(format_compare(report))
    return EXIT_OK


def _peak_row(name, peaks, floors, what):
    """A line of ``control``'s table: the name, each joint's peak (\u2261 0 at or below its
    floor, the report's rule: noise is not data), then what the peaks are."""
    return (f"{name:<12}" + "".join(f"{ZERO_MARK if v <= f else format(v, '.3e'):>11}"
                                    for v, f in zip(peaks, floors)) + f"   {what}")


def cmd_control(args: argparse.Namespace) -> int:
    """``control``: computed-torque tracking with the exact and the simplified model.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed arguments of :mod:`gd_analyze.cli.parsing`.

    Returns
    -------
    int
        The exit status: 0 ok, 1 verification failed, 2 bad input, 3 evaluate gate, 4 internal
        error (:mod:`gd_analyze.cli.parsing`).

    Raises
    ------
    gd_analyze.errors.InputError
        On bad input; the command line prints it as one line and exits 2.
    """
    model, model_robot, traj = _load_model(args)
    outdir = output_folder(args.outdir, model_robot.name, Path(args.trajectory).stem, "control")
    size = control_file.control_size(traj.n_setpoints + DEFAULT_GRID_POINTS, model_robot.n)
    check_free_space(outdir, size, CONTROL_FILE)        # before the closed-loop runs
    try:
        result = run_control(model, traj, wn=args.wn, zeta=args.zeta, q0_offset=args.offset,
                             model_path=args.model, model_sha256=file_sha256(args.model),
                             plant=model_mounting(model_robot, args, args.model),
                             verdict_tolerance=args.verdict_tolerance)
    except ValueError as exc:
        raise InputError(str(exc)) from None
    with staged_output(outdir, command="control") as stage, writing(outdir, stage):
        # and again before writing: the disk may have filled since
        check_free_space(outdir, size, CONTROL_FILE)
        path = stage / CONTROL_FILE
        control_file.write_control_dataset(result, path, {"command": command_line(args)})
        written = [path]
        if not args.no_report:
            written += list(write_control_report(path, stage, paper=args.paper,
                                                 latex=args.latex,
                                                 column_figures=args.column_figures))
    written = [outdir / Path(p).relative_to(stage) for p in written]
    summary = result.summary()
    if args.json:
        print(json.dumps(summary, default=float))
    elif not args.quiet:
        print(f"computed-torque control of {model_robot.name} along {args.trajectory}: "
              f"wn = {args.wn:g} rad/s, zeta = {args.zeta:g}")
        judged = dataset_verdict(control_file.control_dataset(result))
        q_floor = judged["floors"][0]           # the report's rule: noise is not data
        print(f"{'controller':<12}" + "".join(f"{'joint ' + str(j + 1):>11}"
                                               for j in range(model_robot.n)))
        units = {w: joint_units_text(joint_units(model_robot.prismatic, w)) for w in ("q", "tau")}
        # the PD controller's row, as the report names it: plain "pd" on an arm without gravity
        rows = {"pd_gravity": control_file.pd_name(result.robot.gravity).lower().replace(
            " + ", "_")}
        for name, fig in summary["tracking"].items():
            print(_peak_row(rows.get(name, name), fig["peak_grid"], q_floor,
                            f"peak |e| [{units['q']}]"))
        if summary["tau_difference"]:
            floor = result.tau_noise_floor
            assert floor is not None      # None without a measured integrator noise
            print(_peak_row("tau diff", summary["tau_difference"]["peak"], floor,
                            f"peak |tau_simplified - tau_full| [{units['tau']}]"))
            how = "measured" if result.tau_noise is not None else "not measured: rtol x peak |tau|"
            print(f"{'noise floor':<12}" + "".join(f"{v:>11.3e}" for v in floor)
                  + f"   integrator noise of tau diff ({how}), \u2261 0 at or below")
        print(judged["verdict"])
        _print_coverage(summary["guarantee"])
        print(wrote_line(written, outdir, args.verbose))
    return EXIT_OK


def _comments(result, args):
    lines = [f"identified by gd-analyze {result.version}: {command_line(args)}",
             f"prior: {result.prior.source} (SHA-256 {result.prior.sha256})"]
    lines += [f"recording: {f} (SHA-256 {h})" for f, h in result.inputs.items()
              if f != str(result.prior.source)]
    lines.append(f"standard parameters: {result.standard_method}")
    if result.settings.get("robot_file_note"):
        lines.append(str(result.settings["robot_file_note"]))
    return lines


def _summary(result, outdir, written, args):
    p = result.parameters
    lines = [f"identified {result.prior.name} from {sum(f.role == 'train' for f in result.recordings)}"
             f" recording(s): {len(p.names)} parameters, rank {result.rank}, condition number "
             f"{result.condition_number:.4g} (column-scaled, weighted regressor)"]
    unident = p.unidentifiable
    if unident:
        lines.append(f"not identifiable on these data (kept at the robot file's value): "
                     f"{', '.join(unident)}")
    bad = [str(k + 1) for k, ok in enumerate(result.consistent) if not ok]
    lines.append("standard parameters: every link physically consistent" if not bad else
                 f"standard parameters: link(s) {', '.join(bad)} not physically consistent "
                 f"(pseudo-inertia not >= 0)")
    if result.settings.get("robot_file_note"):      # the robot file holds others
        lines.append(str(result.settings["robot_file_note"]))
    width = max([len("recording")] + [len(f.name) for f in result.recordings])
    simplified = any(f.tau_simplified is not None for f in result.recordings)
    lines.append(f"{'recording':<{width}}  {'role':<8}  {'identified':>10}  {'robot file':>10}"
                 + (f"  {'simplified':>10}" if simplified else "")
                 + "   total relative torque error ||E||_F / ||T||_F")
    lines += [f"{f.name:<{width}}  {f.role:<8}  {f.errors()[2]:>10.2%}  "
              f"{f.errors('prior')[2]:>10.2%}"
              + ("" if f.tau_simplified is None else f"  {f.errors('simplified')[2]:>10.2%}")
              for f in result.recordings]
    if simplified and result.settings.get("simplified_guarantee"):
        lines.append(f"simplified model: {result.settings['simplified_guarantee']}")
    lines.append(wrote_line(written, outdir, args.verbose))
    return lines


def cmd_identify(args: argparse.Namespace) -> int:
    """``identify``: identify the robot from recordings, write the store and the robot file.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed arguments of :func:`gd_analyze.cli.parsing.identify_parser`.

    Returns
    -------
    int
        The exit status: 0 ok.

    Raises
    ------
    gd_analyze.errors.InputError
        On bad input; the command line prints it as one line and exits 2.
    """
    robot = load_robot_arg(args)
    if args.current and args.drive_gains is None:
        raise InputError("--current needs --drive-gains K1,.. (tau = K i)", column="--current")
    if args.drive_gains is not None and not args.current:
        raise InputError("--drive-gains applies to currents: give --current",
                         column="--drive-gains")
    options = IdentifyOptions(**{f.name: getattr(args, f.name) for f in dataclasses.fields(IdentifyOptions)})
    outdir = output_folder(args.outdir, robot.name, recording_name(recording_files(
        args.recordings[0])), "identify")
    train, valid = ([read_recording(path, robot.n, options.current, robot.joint_names())
                     for path in paths] for paths in (args.recordings, args.validate))
    size = identification_size([most_samples(r.t, resampled=options.cutoff is not None)
                                for r in train + valid], robot.n)
    check_free_space(outdir, size, "identification.h5")    # before the identification
    result = identify(robot, train, validate=valid, options=options)
    with staged_output(outdir, command="identify") as stage, writing(outdir, stage):
        # and again before writing: the disk may have filled since
        check_free_space(outdir, size, "identification.h5")
        written = [write_identification(result, stage / "identification.h5")]
        toml = stage / "identified_robot.toml"
        toml.write_text(robot_toml(result.identified, _comments(result, args)),
                        encoding="utf-8")
        written.append(toml)
        if isinstance(args.robot, str) and is_urdf(args.robot):
            urdf = stage / "identified_robot.urdf"
            urdf.write_text(robot_urdf(result.identified, _comments(result, args) + [
                "the drives (armature, viscous and Coulomb friction, torque offsets) are in "
                "identified_robot.toml only: a URDF holds none that gd-analyze reads"]),
                encoding="utf-8")
            written.append(urdf)
        if not args.no_report:
            tree = identification_tree(result)
            root = tree.pop("/")
            written += write_identify_report(root, tree, stage, paper=args.paper,
                                             latex=args.latex)
    written = [outdir / Path(p).relative_to(stage) for p in written]
    if args.json:
        print(json.dumps(recordings_json(result)))
    elif not args.quiet:
        print("\n".join(_summary(result, outdir, written, args)))
    return EXIT_OK


def _model_lines(model, ds, args):
    """What the command prints of the merged model: its cost, its worst error where its
    guarantee covers the swept trajectories, the ones it does not cover, and the guarantee
    as the model states it (:meth:`gd_analyze.simplify.guarantee.Guarantee.statement`)."""
    v = model.validation
    eps = args.tolerance
    said = merged_guarantee(ds)
    region = said["kind"] == "region"
    worst = said["worst"]
    floor = f"max(peak |tau_i|, {args.torque_floor:g} N m)" if args.torque_floor else \
        "peak |tau_i|"
    scale = "s_i over the joint-limit region" if region else f"each trajectory's {floor}"
    claim = f"guaranteed <= {eps:g}" if said["within"] else \
        f"ABOVE the guarantee {eps:g}: please report this bug"
    beyond = beyond_the_floor(ds)
    caveat = ""
    if beyond is not None:
        rel, j, over = beyond
        caveat = (f"; relative to peak |tau_i| itself, where it is below "
                  f"{args.torque_floor:g} N m, not guaranteed: up to {rel:.2e} (joint {j}; "
                  f"above {eps:g} on joint{'s' if len(over) > 1 else ''} "
                  f"{', '.join(map(str, over))})")
    outside = said["outside"]
    inside = v["trajectories"] - len(outside)
    where = (f"on the {v['trajectories']} swept trajectories" if not outside else
             f"on the {inside} of {v['trajectories']} swept trajectories inside the region")
    error = (f"worst error {where} {worst:.2e} of {scale} ({claim}){caveat}" if inside else
             f"none of the {v['trajectories']} swept trajectories lies inside the region")
    if outside:
        error += (f"; on the {len(outside)} outside it (not covered by the proof) "
                  f"{max(w for _, _, w in outside):.2e}")
    if v["held_out"]:   # relative to max(peak |tau_i|, TAU) over them all, or to s_i over R
        h = v["held_out"]
        with np.errstate(divide="ignore", invalid="ignore"):
            held_err = np.asarray(h["peak_abs_error"], float) / (
                np.asarray(model.guarantee.scale, float) if region else
                np.maximum(np.asarray(h["peak_tau"], float), args.torque_floor))
        covered = ("not guaranteed" if not region else
                   f"measured; {said['held_out_inside']} of them inside the region, where "
                   "the bound is proved")
        error += (f", on {v['held_out_trajectories']} held-out {np.nanmax(held_err):.2e} of "
                  f"{'s_i' if region else 'their ' + floor} ({covered})")
    others = "; ".join(f"{name}: {c['multiplications'] + c['additions']:,}" for name, c in
                       model.costs.items() if name in ("exact recursive", "explicit, full"))
    lines = [f"merged model (budget rule, EPS = {eps:g}, {model.form} form): "
             f"{model.cost['multiplications'] + model.cost['additions']:,} operations "
             f"({model.cost['multiplications']} mult + {model.cost['additions']} add; "
             f"{others}); {error}"]
    if outside:
        lines.append(f"not covered by the region guarantee ({len(outside)} swept "
                     f"trajector{'y' if len(outside) == 1 else 'ies'} outside the region): "
                     + "; ".join(f"{src}: {why}" for src, why, _ in outside[:5])
                     + ("" if len(outside) <= 5 else f"; and {len(outside) - 5} more "
                        "(merged_covered in sweep.h5)"))
    region = getattr(model.guarantee, "region", None)
    lines += [] if region is None else region.lines()
    lines.append(f"guarantee: {said['statement']}")
    return lines


def cmd_sweep(args: argparse.Namespace) -> int:
    """``sweep``: the ranking over many trajectories on dask, and the merged model.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed arguments of :mod:`gd_analyze.cli.parsing`.

    Returns
    -------
    int
        The exit status: 0 ok, 1 verification failed, 2 bad input, 3 evaluate gate, 4 internal
        error (:mod:`gd_analyze.cli.parsing`).

    Raises
    ------
    gd_analyze.errors.InputError
        On bad input; the command line prints it as one line and exits 2.
    """
    from ..jobs.dask_cluster import dask_client
    from ..jobs.sweep import IN_PROCESS_SETPOINTS_MAX, WorkerErrors, run_sweep

    robot = load_robot_arg(args)
    if (args.random is None) == (not args.csv):
        raise InputError("give either --random K or trajectory CSV files")
    if args.scheduler is not None:
        if not re.fullmatch(r"((tcp|tls|ws|wss|ucx)://)?[^\s/:]+:[0-9]{1,5}/?", args.scheduler):
            raise InputError("not a dask scheduler address (e.g. tcp://10.0.0.5:8786)",
                             column="--scheduler")
    check_rule_options(args)
    if args.csv:
        trajectories = [unwrapped(robot, read_trajectory(path, robot.n, robot.joint_names()))
                        for path in args.csv]
    else:
        warn_if(check_velocity_limits(robot))               # random plans need them
        trajectories = random_trajectories(robot, args.random, seed=args.seed)
    masses = payload_mass_list(args)
    loaded = apply_payload(robot, args)
    outdir = output_folder(args.outdir, robot.name, "sweep")
    settings = run_settings(args, robot, payload_mass=float(args.payload or 0.0))
    if args.random is not None:
        settings["seed"] = args.seed
        # never raises: check_velocity_limits gave every joint a velocity limit
        settings["random_qdd_max_source"] = acceleration_limits(robot)[1]

    limits = region_limits(args, loaded)
    settings.update({} if limits is None else limits.settings())
    # the budget rule's merged model (budget_region_model, budget_sweep_model) is made with these
    model_settings = {"tolerance": args.tolerance, "torque_floor": args.torque_floor,
                      "provenance": {"gd_analyze_version": __version__, **settings},
                      "explicit": args.explicit, "form": args.form, "guarantee": args.guarantee,
                      "region": limits}
    # over the region the merge needs no per-trajectory peaks of the recursive model
    proved = guarantee_region(loaded, args.guarantee, limits)[2]
    budget = args.rule == "budget"
    if budget:          # an explicit model asked for beyond its size limit: before the sweep
        derives_explicit(loaded, SimplifyOptions(explicit=args.explicit, form=args.form))
    size = sweep_size(len(trajectories), robot.n, 0 if masses is None else len(masses))
    check_free_space(outdir, size, "sweep.h5")      # before the sweep, which may take hours
    # the held-out trajectories of the budget rule's merged model (--held-out, at least 0):
    # random plans, none on an arm without the limits to plan them (said in one line)
    held = []
    if budget and args.held_out:
        try:
            acceleration_limits(loaded)
        except ValueError as exc:
            warn_if(f"{robot.source}: no held-out trajectories (--held-out): {exc}")
        else:
            held = random_trajectories(loaded, args.held_out, seed=args.seed + 1_000_003)
    prepared = {}

    def region_model():
        # over the region the merged model does not depend on the ranking: it is built here
        # while the workers rank
        prepared["model"] = budget_region_model(loaded, trajectories, **model_settings)

    model = None
    # a small sweep with no cluster asked for is ranked here: a LocalCluster's start and its
    # workers' warm-up would cost more than the ranking
    local = args.scheduler is None and args.workers is None and \
        sum(len(t.q) for t in trajectories) <= IN_PROCESS_SETPOINTS_MAX
    with contextlib.ExitStack() as stack:
        client = cluster = None
        try:                            # only the connection: the sweep's errors are its own
            if not local:
                client, cluster = stack.enter_context(dask_client(args.scheduler,
                                                                  args.workers))
        except (OSError, ValueError, TypeError) as exc:
            if args.scheduler is None:
                raise InputError(f"cannot start a local dask cluster: {exc}") from None
            raise InputError(f"cannot reach the dask scheduler: {exc}",
                             args.scheduler) from None
        ds = run_sweep(loaded, trajectories, args.dominance, args.negligible, client=client,
                       settings=settings, progress=not args.quiet and sys.stderr.isatty(),
                       recursive_peaks=budget and not proved, cluster=cluster,
                       chapter_errors=not budget,
                       meanwhile=region_model if budget and proved else None,
                       in_process=local)
        payload = None if masses is None else sweep_payloads(
            robot, trajectories, masses, args.payload_com, args.payload_inertia,
            args.dominance, args.negligible, client=client, in_process=local)
        if budget:                      # measured on every trajectory (by the workers)
            errors = None if client is None else WorkerErrors(client)  # one task per worker
            model = budget_sweep_model(loaded, trajectories, ds, held_out=held,
                                       prepared=prepared.get("model"), errors=errors,
                                       **model_settings)
            if errors is not None:
                ds = with_more_tasks(ds, errors.tasks)

    with staged_output(outdir, command="sweep") as stage, writing(outdir, stage):
        # and again before writing: the disk may have filled since
        check_free_space(outdir, size, "sweep.h5")
        written = [stage / "sweep.h5", stage / "merged_model.json"]
        if model is None:               # the chapter rule's
            model = merged_model(loaded, ds)
            ds = with_model_cost(ds, model)
            said = ["merged model (chapter rule): a part is dropped only where every "
                    "trajectory's share-based model drops it; no error bound"]
        else:       # the budget rule's, within EPS x s_i over the region or on every trajectory
            ds = with_budget_model(ds, model)
            model.validation.pop("per_trajectory")          # in sweep.h5; K x n lists
            said = [] if args.quiet else _model_lines(model, ds, args)
            # its emitted sources: merged_model.h, .c, .py, _casadi.py (prefix ROBOT_merged_)
            for name, text in model.sources("merged_model",
                                            c_prefix(loaded.name) + "merged_").items():
                (stage / name).write_text(text, encoding="utf-8")
                written.append(stage / name)
        save_model(model, written[1])
        if not args.quiet:
            print("\n".join(said))
        write_dataset(ds, written[0])
        if payload is not None:
            written.append(stage / "payload_sweep.h5")
            write_dataset(payload, written[-1])
        if not args.no_report:
            written += list(write_sweep_report(written[0], stage, payload=payload,
                                               paper=args.paper, latex=args.latex,
                                               column_figures=args.column_figures))
    written = [outdir / Path(p).relative_to(stage) for p in written]
    if not args.quiet:
        run = StoredSweep.of(ds)
        s = run.settings
        w, k = int(s.n_workers), run.trajectories
        where = (f"on {w} dask worker{'s' * (w > 1)} ({s.scheduler_address})"
                 if w else "in this process (no dask cluster)")
        print(f"{robot.name}: {k} trajector{'ies' if k > 1 else 'y'} in "
              f"{float(s.elapsed_s):.1f} s {where}")
        print(f"{'element':<8}" + "".join(f"{c[:5]:>7}" for c in run.classes)
              + f"{'min':>8}{'median':>8}{'max':>8}  merged")
        for k, lab in enumerate(run.elements):      # no share (NaN): round-off everywhere
            shares = (run.share_min[k], run.share_median[k], run.share_max[k])
            print(f"{lab:<8}" + "".join(f"{v:>7.3f}" for v in run.class_fraction[k])
                  + "".join(f"{v:>8.3f}" if math.isfinite(v) else f"{'≡ 0':>8}" for v in shares)
                  + f"  {run.merged.choice[k]}")
        print(wrote_line(written, outdir, args.verbose))
    return EXIT_OK
