"""The ``sweep`` command: many trajectories on dask, the merged model, and their files.

``cmd_sweep(args)`` takes the parsed arguments of :mod:`gd_analyze.cli.parsing` and returns the
exit status; bad input raises :class:`gd_analyze.errors.InputError` (exit status 2).
"""

from __future__ import annotations

import argparse
import contextlib
import math
import sys
from pathlib import Path

from .._version import VERSION as __version__
from ..errors import InputError
from ..jobs.payload import sweep_payloads
from ..jobs.sweep_budget import budget_region_model, budget_sweep_model
from ..jobs.sweep_merged import merged_model, with_budget_model, with_model_cost
from ..model.limits import acceleration_limits
from ..report.sweep import write_sweep_report
from ..simplify.deploy import guarantee_region
from ..store.model_file import save_model
from ..store.schema import write_dataset
from ..store.staging import check_free_space, staged_output, writing
from ..store.sweep_guarantee import merged_guarantee
from ..store.sweep_view import StoredSweep, beyond_the_floor, sweep_size, with_more_tasks
from ..symbolic.safe_text import c_prefix
from ..trajectory.planning import check_velocity_limits, random_trajectories
from ..trajectory.trajectory import read_trajectory
from .commands import (
    apply_payload,
    chain_settings,
    check_rule_options,
    command_line,
    load_robot_arg,
    mounting_settings,
    output_folder,
    payload_mass_list,
    region_limits,
    warn_if,
    wrote_line,
)
from .parsing import EXIT_OK

__all__ = []


def _model_settings(args, settings, limits):
    """The keyword arguments of the budget rule's merged model
    (:func:`gd_analyze.jobs.sweep_budget.budget_sweep_model`)."""
    return {"tolerance": args.tolerance, "torque_floor": args.torque_floor,
            "provenance": {"gd_analyze_version": __version__, **settings},
            "explicit": args.explicit, "form": args.form, "guarantee": args.guarantee,
            "region": limits}


def _sweep_model(robot, model, args, outdir, ds):
    """The sweep's merged model of the budget rule, within EPS x s_i over the joint-limit
    region or on every swept trajectory (``--guarantee``), measured
    (:func:`gd_analyze.jobs.sweep_budget.budget_sweep_model`).

    Writes merged_model.json and its emitted files (prefix ROBOT_merged_) into outdir; returns (written paths, the sweep dataset
    with this model's errors)."""

    ds = with_budget_model(ds, model)
    model.validation.pop("per_trajectory")          # in sweep.h5; K x n lists
    written = [outdir / "merged_model.json"]
    save_model(model, written[0])
    for name, text in model.sources(MERGED_STEM, c_prefix(robot.name) + "merged_").items():
        (outdir / name).write_text(text, encoding="utf-8")
        written.append(outdir / name)
    if not args.quiet:
        print("\n".join(_model_lines(model, ds, args)))
    return written, ds


def _model_lines(model, ds, args):
    """What the command prints of the merged model: its cost, its worst error where its
    guarantee covers the swept trajectories, the ones it does not cover, and the guarantee
    as the model states it (:meth:`gd_analyze.simplify.guarantee.Guarantee.statement`)."""
    import numpy as np


    v = model.validation
    eps = args.tolerance
    said = merged_guarantee(ds)
    region = said["kind"] == "region"
    worst = said["worst"]
    floor = f"max(peak |tau_i|, {args.torque_floor:g} N m)" if args.torque_floor else \
        "peak |tau_i|"
    scale = "s_i over the joint-limit region" if region else f"each trajectory's {floor}"
    held_err = None
    if v["held_out"]:   # relative to max(peak |tau_i|, TAU) over them all, or to s_i over R
        h = v["held_out"]
        with np.errstate(divide="ignore", invalid="ignore"):
            held_err = np.asarray(h["peak_abs_error"], float) / (
                np.asarray(model.guarantee.scale, float) if region else
                np.maximum(np.asarray(h["peak_tau"], float), args.torque_floor))
    claim = f"guaranteed <= {eps:g}" if worst <= eps * (1 + 1e-9) or np.isnan(worst) else \
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
    if held_err is not None:
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


#: The stem of the merged model's emitted files (merged_model.h, .c, .py, _casadi.py).
MERGED_STEM = "merged_model"


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
        import re

        if not re.fullmatch(r"((tcp|tls|ws|wss|ucx)://)?[^\s/:]+:[0-9]{1,5}/?", args.scheduler):
            raise InputError("not a dask scheduler address (e.g. tcp://10.0.0.5:8786)",
                             column="--scheduler")
    check_rule_options(args)
    if args.csv:
        trajectories = [read_trajectory(path, n_joints=robot.n) for path in args.csv]
    else:
        warn_if(check_velocity_limits(robot))               # random plans need them
        trajectories = random_trajectories(robot, args.random, seed=args.seed)
    masses = payload_mass_list(args)
    loaded = apply_payload(robot, args)
    outdir = output_folder(args.outdir, robot.name, "sweep")
    settings = {"command": command_line(args),
                "payload_mass": float(args.payload or 0.0), **chain_settings(args),
                **mounting_settings(args, robot)}
    if args.random is not None:
        settings["seed"] = args.seed
        try:
            settings["random_qdd_max_source"] = acceleration_limits(robot)[1]
        except ValueError as exc:
            raise InputError(str(exc), robot.source) from None

    limits = region_limits(args, loaded)
    settings.update({} if limits is None else limits.settings())
    # over the region the merge needs no per-trajectory peaks of the recursive model
    proved = guarantee_region(loaded, args.guarantee, limits)[2]
    budget = args.rule == "budget"
    size = sweep_size(len(trajectories), robot.n, 0 if masses is None else len(masses))
    check_free_space(outdir, size, "sweep.h5")      # before the sweep, which may take hours
    # the held-out trajectories of the budget rule's merged model (--held-out, at least 0)
    held = random_trajectories(loaded, args.held_out, seed=args.seed + 1_000_003) \
        if budget and args.held_out else []
    prepared = {}

    def region_model():
        # over the region the merged model does not depend on the ranking: it is built here
        # while the workers rank
        prepared["model"] = budget_region_model(loaded, trajectories,
                                                **_model_settings(args, settings, limits))

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
                                       **_model_settings(args, settings, limits))
            if errors is not None:
                ds = with_more_tasks(ds, errors.tasks)

    with staged_output(outdir, command="sweep") as stage, writing(outdir, stage):
        # and again before writing: the disk may have filled since
        check_free_space(outdir, size, "sweep.h5")
        written = [stage / "sweep.h5"]
        if model is not None:
            files, ds = _sweep_model(loaded, model, args, stage, ds)
        else:
            files = [stage / "merged_model.json"]
            model = merged_model(loaded, ds)
            ds = with_model_cost(ds, model)
            save_model(model, files[0])
            if not args.quiet:
                print("merged model (chapter rule): a part is dropped only where every "
                      "trajectory's share-based model drops it; no error bound")
        write_dataset(ds, written[0])
        written += files
        if payload is not None:
            written.append(stage / "payload_sweep.h5")
            write_dataset(payload, written[-1])
        if not args.no_report:
            written += list(write_sweep_report(written[0], stage, payload=payload,
                                               paper=args.paper, latex=args.latex))
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
