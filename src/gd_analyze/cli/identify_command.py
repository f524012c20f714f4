"""The ``identify`` command: recordings -> identification.h5 and identified_robot.toml.

``cmd_identify(args)`` takes the parsed arguments of :mod:`gd_analyze.cli.parsing` and returns
the exit status; bad input raises :class:`gd_analyze.errors.InputError` (exit status 2). The
job is :func:`gd_analyze.jobs.identify.identify`; the files are written into a staged
output folder (:func:`gd_analyze.store.staging.staged_output`), with the report
(:func:`gd_analyze.report.identify.write_identify_report`) unless ``--no-report``.
"""

from __future__ import annotations

import argparse
import json
from dataclasses import fields
from pathlib import Path

from ..errors import InputError
from ..estimation.preprocess import most_samples
from ..jobs.identify import IdentifyOptions, identify
from ..model.robot_file import robot_toml
from ..model.robots import is_urdf
from ..model.urdf_writer import robot_urdf
from ..report.identify import write_identify_report
from ..store.staging import check_free_space, staged_output, writing
from ..store.stored_identification import (
    identification_size,
    identification_tree,
    recordings_json,
    write_identification,
)
from ..trajectory.recording import read_recording
from .commands import command_line, load_robot_arg, output_folder, wrote_line
from .parsing import EXIT_OK

__all__ = ["cmd_identify"]



def _options(args):
    if args.current and args.drive_gains is None:
        raise InputError("--current needs --drive-gains K1,.. (tau = K i)", column="--current")
    if args.drive_gains is not None and not args.current:
        raise InputError("--drive-gains applies to currents: give --current",
                         column="--drive-gains")
    return IdentifyOptions(**{f.name: getattr(args, f.name) for f in fields(IdentifyOptions)})


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
    width = max([len("recording")] + [len(f.name) for f in result.recordings])
    simplified = any(f.tau_simplified is not None for f in result.recordings)
    head = f"{'recording':<{width}}  {'role':<8}  {'identified':>10}  {'robot file':>10}"
    if simplified:
        head += f"  {'simplified':>10}"
    lines += [head + "   total relative torque error ||E||_F / ||T||_F"]
    for f in result.recordings:
        row = (f"{f.name:<{width}}  {f.role:<8}  {f.errors()[2]:>10.2%}  "
               f"{f.errors('prior')[2]:>10.2%}")
        if f.tau_simplified is not None:
            row += f"  {f.errors('simplified')[2]:>10.2%}"
        lines.append(row)
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
    options = _options(args)
    outdir = output_folder(args.outdir, robot.name, Path(args.recordings[0]).stem, "identify")
    train, valid = ([read_recording(path, n_joints=robot.n, current=options.current)
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
