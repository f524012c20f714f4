"""The main job as one call: analyse a trajectory and write its output folder.

:func:`run_analysis` is what ``gd-analyze ROBOT TRAJECTORY.csv`` runs: the G-D terms, their
verification against Pinocchio, the ranking and the simplified model
(:func:`gd_analyze.jobs.analyze.analyze_to_file`), an optional payload sweep, then
``results.h5``, ``simplified_model.json`` with its emitted C header and source, numpy and CasADi
modules, and the report,
all written aside and moved into the output folder together
(:func:`gd_analyze.store.staging.staged_output`). The command line only parses, calls this and
prints. :func:`results_dataset` is the same analysis with the same settings, in memory: the
Python API's ``gd_analyze.analyze``.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import InputError, expect
from ..model.robot import Robot, with_payload
from ..simplify import deploy
from ..simplify.simplified import SOURCE_STEM
from ..store import model_trust
from ..store.manifest import hash_beside
from ..store.model_file import save_model
from ..store.names import Var
from ..store.results_view import Results
from ..store.staging import check_free_space, staged_output, writing
from ..store.sweep_view import embed_payload
from ..symbolic.safe_text import c_prefix, check_prefix
from ..trajectory.trajectory import as_trajectory
from .analyze import Analysis, analyze, analyze_to_file
from .options import AnalysisOptions
from .payload import payload_sweep
from .peak_jobs import derives_explicit

if TYPE_CHECKING:
    import xarray as xr

    from ..trajectory.trajectory import Trajectory

__all__ = ["AnalysisOutputs", "Payload", "run_analysis",
           "results_size", "results_dataset"]



@dataclass(frozen=True)
class Payload:
    """A load fixed to the last link (Sec. 3.4.1's simplified model, loaded).

    Attributes
    ----------
    mass : float
        Load mass [kg].
    com : tuple of float, length 3
        The load's centre of mass in the last link frame [m].
    inertia : tuple of float, length 3
        The load's principal moments of inertia about its centre of mass [kg m^2].
    """

    mass: float = 0.0
    com: tuple = (0.0, 0.0, 0.0)
    inertia: tuple = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class AnalysisOutputs:
    """What the main job wrote.

    Attributes
    ----------
    outdir : pathlib.Path
        The output folder.
    files : tuple of pathlib.Path
        The files written, in the output folder.
    analysis : Analysis
        The summary dataset, the simplified model and the verification
        (:class:`gd_analyze.jobs.analyze.Analysis`).
    """

    outdir: Path
    files: tuple
    analysis: Analysis


def results_size(N: int, n: int) -> int:
    """Bytes of the per-set-point variables of results.h5 (uncompressed), plus 1 MiB.

    Parameters
    ----------
    N, n : int
        Set points and joints.

    Returns
    -------
    int
        8 bytes per value: t, nine vectors of n (q, qd, qdd, h and its two parts, c, tau,
        tau_simplified) and three matrices of n^2 (D and its two parts) per set point
        [bytes].

    Examples
    --------
    >>> results_size(31, 6) - (1 << 20) == 8 * 31 * (1 + 9 * 6 + 3 * 6 * 6)
    True
    """
    return 8 * N * (1 + 9 * n + 3 * n * n) + (1 << 20)


def _settings(options, base_settings, payload, robot, prefix=None):
    """The provenance of a run: each setting once, with the C prefix of the emitted sources
    (the robot's name made one unless given)."""

    s = options.simplify                    # None: no model
    simplify = {} if s is None else {k: v for k, v in dataclasses.asdict(s).items() if k != "region"}
    region = {} if s is None or s.region is None else s.region.settings()
    return {**(base_settings or {}), "payload_mass": float(payload.mass),
            "payload_com": [float(v) for v in payload.com],
            "payload_inertia": [float(v) for v in payload.inertia],
            **simplify, **region,
            "c_prefix": c_prefix(robot.name) if prefix is None else check_prefix(prefix)}


def run_analysis(robot: Robot, trajectory: Trajectory, options: AnalysisOptions,
                 outdir: str | os.PathLike, report: Callable[..., Any] | None = None,
                 settings: dict | None = None, payload: Payload | None = None,
                 payload_masses: Sequence[float] | None = None, progress: Any = False,
                 prefix: str | None = None) -> AnalysisOutputs:
    """Analyse a trajectory and write the main job's output folder.

    Parameters
    ----------
    robot : Robot
        The arm, n joints, without the payload.
    trajectory : Trajectory
        t [s], q, qd, qdd of shape (N, n) [rad, rad/s, rad/s^2; m, m/s, m/s^2 for a
        prismatic joint].
    options : AnalysisOptions
        Ranking, verification, storage and simplified-model settings.
    outdir : str or os.PathLike
        The output folder: created if missing; only the files this command wrote before are
        replaced (:func:`gd_analyze.store.staging.staged_output`).
    report : callable, optional
        ``report(results, folder, progress) -> list of paths``: writes the report into
        ``folder`` from ``results``, the analysis in memory
        (:class:`gd_analyze.store.results_view.Results`, with its per-set-point series), or the
        path of results.h5 when the series were streamed in chunks (the command line passes
        :func:`gd_analyze.report.main.write_report` with its page and font settings); None
        writes no report. Before the report of series streamed in chunks, the region
        searches, derivations and certifications kept in this process are released
        (:func:`gd_analyze.simplify.deploy.release`,
        :func:`gd_analyze.store.model_trust.release`).
    settings : dict, optional
        Extra provenance (the command line, the payload, the URDF chain), stored with the
        simplified-model settings in results.h5 and the model.
    payload : Payload, optional
        A load fixed to the last link for the analysis
        (:func:`gd_analyze.model.robot.with_payload`); one of mass 0 is no load, only the
        shape (centre of mass, inertia) of ``payload_masses``' loads.
    payload_masses : sequence of float, optional
        Also rank the trajectory for each of these load masses [kg] of the payload's shape,
        on the arm without the payload (variables ``payload_*`` of results.h5); computed
        before anything is written.
    progress : bool or tqdm.tqdm, optional
        As for :func:`gd_analyze.jobs.analyze.analysis_pass`.
    prefix : str, optional
        Prefix of the emitted C symbols and CasADi functions, a C identifier; default the
        robot's name made one (:meth:`~gd_analyze.simplify.simplified.SimplifiedModel.sources`).

    Returns
    -------
    AnalysisOutputs

    Raises
    ------
    InputError
        If the output folder is not a folder, holds files gd-analyze did not write, or has no
        room; or the payload range is invalid; or an explicit model is asked for above its
        size limit (:func:`gd_analyze.jobs.peak_jobs.derives_explicit`). Nothing is written then.
    OSError
        If the output folder cannot be written ("cannot write the output folder").

    Notes
    -----
    Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987) for the analysis; the terms from
    Eqs. (3.4-24) to (3.4-28).
    """

    outdir = Path(outdir)
    if outdir.exists() and not outdir.is_dir():
        raise InputError("exists and is not a folder", outdir)
    extra, unloaded = None, robot
    shape = Payload() if payload is None else payload
    if payload is not None and payload.mass:            # mass 0: the swept loads' shape
        robot = with_payload(robot, payload.mass, payload.com, payload.inertia)
    if options.simplify is not None:        # an explicit model too large: refused before any work
        derives_explicit(robot, options.simplify)
    need = results_size(trajectory.n_setpoints, robot.n)
    check_free_space(outdir, need, "results.h5")        # before the payload sweep
    if payload_masses is not None:                      # computed before any output
        extra = embed_payload(payload_sweep(
            unloaded, trajectory, payload_masses, com=shape.com, inertia=shape.inertia,
            dominance=options.dominance, negligible=options.negligible))
    settings = _settings(options, settings, shape, robot, prefix)
    prefix = settings["c_prefix"]
    with staged_output(outdir, command="analyze") as stage, writing(outdir, stage):
        # on the output folder's file system, the staging folder's; the message names it
        check_free_space(outdir, need, "results.h5")
        results = stage / "results.h5"
        analysis = analyze_to_file(robot, trajectory, results, options, settings=settings,
                                   progress=progress, extra=extra)
        hash_beside(results)                    # for the manifest, while the rest is written
        model = analysis.model
        save_model(model, stage / "simplified_model.json")
        written = [results, stage / "simplified_model.json"]
        for name, text in model.sources(SOURCE_STEM, prefix).items():
            (stage / name).write_text(text, encoding="utf-8")
            written.append(stage / name)
        if report is not None:          # from the result in memory when it holds the series
            whole = Var.T in analysis.dataset.variables
            if not whole:               # a long trajectory: the report's memory, not the memos'
                deploy.release()
                model_trust.release()
            written += report(Results.from_dataset(analysis.dataset) if whole else results,
                              stage, progress)
    files = tuple(outdir / Path(p).relative_to(stage) for p in written)
    return AnalysisOutputs(outdir=outdir, files=files, analysis=analysis)


def results_dataset(robot: Robot, trajectory: Trajectory | str | os.PathLike | Mapping | Sequence,
                    options: AnalysisOptions | None = None) -> xr.Dataset:
    """The main job's results dataset, in memory: what ``results.h5`` holds, no file written.

    The same analysis as :func:`run_analysis` (:func:`gd_analyze.jobs.analyze.analysis_pass`
    with the same provenance settings); ``gd_analyze.analyze`` is this function.

    Parameters
    ----------
    robot : Robot
        The arm, n joints (:func:`gd_analyze.load_robot`).
    trajectory : Trajectory, str, os.PathLike, mapping or sequence
        A :class:`~gd_analyze.trajectory.trajectory.Trajectory` (:func:`gd_analyze.read_trajectory`), a
        trajectory CSV file, or arrays: ``(t, q)`` or ``(t, q, qd, qdd)``, or a mapping of
        them, t of shape (N,) [s], the others (N, n) [rad, rad/s, rad/s^2; m, m/s, m/s^2]
        (:func:`gd_analyze.trajectory.trajectory.as_trajectory`).
    options : AnalysisOptions, optional
        As the main job's (default: its defaults, :data:`gd_analyze.config.defaults`).

    Returns
    -------
    xarray.Dataset
        Dims ``t`` (the set points; coordinate: time [s]), ``joint`` and ``joint_k`` (rows and
        columns of D; coordinates: the joints' names), ``element`` (``"D11"`` .. ``"hn"``) and
        the model's own: D_tran, D_rot, D (N, n, n) [kg m2], h_tran, h_rot, h, c, tau,
        tau_simplified (N, n) [N m], the ranking (share_tran, dominance, ...), the simplified
        model's error and guarantee, the robot, and the provenance and the verification
        against Pinocchio (``verification_passed``) in the attributes
        (:mod:`gd_analyze.store.datasets`). The same variables, coordinates and values as the
        ``results.h5`` of :func:`run_analysis`.

    Raises
    ------
    InputError
        If the trajectory cannot be read or does not fit the robot, or the robot is not a
        :class:`~gd_analyze.model.robot.Robot` (a name or a file: :func:`gd_analyze.load_robot`
        first) or the options not an :class:`AnalysisOptions`.
    ValueError
        If an option is out of range.

    Notes
    -----
    Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987); terms from Eqs. (3.4-24) to (3.4-28).
    The simplified model itself (to evaluate or save) is
    :func:`gd_analyze.jobs.analyze.analyze`'s ``model``.

    Examples
    --------
    >>> import numpy as np
    >>> import gd_analyze as gd
    >>> robot = gd.load_robot("two-link")
    >>> t = np.linspace(0.0, 1.0, 5)
    >>> ds = gd.analyze(robot, (t, np.outer(t, [1.0, -0.5])), gd.AnalysisOptions(
    ...     formulations=False))
    >>> dict(ds.D.sizes), ds.t.attrs["units"], ds.joint.values.tolist()
    ({'t': 5, 'joint': 2, 'joint_k': 2}, 's', ['joint1', 'joint2'])
    """

    expect(robot, Robot, "robot", "a Robot (gd.load_robot(...) reads a name or a file)")
    expect(options, (AnalysisOptions, type(None)), "options", "an AnalysisOptions")
    options = AnalysisOptions() if options is None else options
    trajectory = as_trajectory(trajectory, robot.n, robot.joint_names())
    return analyze(robot, trajectory, options,
                   settings=_settings(options, None, Payload(), robot)).dataset
