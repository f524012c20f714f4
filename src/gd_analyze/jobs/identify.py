"""The identification job: recordings -> identified robot (``gd-analyze identify``).

:func:`identify` reads and preprocesses the recordings (:mod:`gd_analyze.trajectory.trajectory`,
:mod:`gd_analyze.estimation.preprocess`), stacks the identification regressor of the
training recordings (:mod:`gd_analyze.estimation.regressor`), estimates by ordinary then
weighted least squares (:mod:`gd_analyze.estimation.estimate`), chooses the standard
parameters (:mod:`gd_analyze.estimation.consistent`), and predicts every recording with the
identified model and with the robot file as shipped. It returns a frozen
:class:`~gd_analyze.store.stored_identification.IdentificationResult`; it neither prints nor
writes.
"""

from __future__ import annotations

import math
import os
import tempfile
import warnings
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from .._version import VERSION
from ..errors import InputError, InputWarning, check_flags, expect, is_number
from ..estimation import preprocess as prep
from ..estimation.consistent import SolverFailure
from ..estimation.fit import FitFailure, RegressorRows, fit_columns, fit_robot
from ..estimation.regressor import DRIVE_KINDS
from ..model.robot import Robot
from ..model.robots import load_robot
from ..store.stored_identification import (
    IdentificationResult,
    ParameterTable,
    RecordingFit,
    group_names,
)
from ..trajectory.trajectory import (
    Recording,
    check_joint_limits,
    read_recording,
    trajectory_from_arrays,
)
from .analyze import analyze, analyze_to_file, stream_chunk
from .evaluate import model_torque as simplified_torque
from .options import AnalysisOptions

__all__ = ["IdentifyOptions", "identify", "recording_name", "DEFAULT_DRIVES"]

#: The drive columns identified by default.
DEFAULT_DRIVES = ("viscous", "coulomb", "offset")


@dataclass(frozen=True)
class IdentifyOptions:
    """The settings of an identification.

    Attributes
    ----------
    cutoff : float, "auto" or None
        Low-pass cutoff [Hz]; ``"auto"``: chosen from the training recordings
        (:func:`~gd_analyze.estimation.preprocess.default_cutoff`, the largest over them,
        used for every recording); None: no filter.
    decimate : int
        Keep every decimate-th sample after filtering.
    drives : tuple of str
        The drive columns, a subset of ``armature``, ``viscous``, ``coulomb``, ``offset`` (a
        str is refused: it is not read letter by letter).
    current : bool
        The recordings hold motor currents [A]; ``drive_gains`` turn them into torque.
    drive_gains : tuple of float or None
        K_i [N m/A]: tau_i = K_i i_i.
    consistent : bool
        Physically consistent standard parameters (pseudo-inertias PSD).
    simplify : bool
        Build the simplified model of the identified robot (the main job's analysis) and
        predict every recording with it too.

    Raises
    ------
    ValueError
        On an unknown drive kind (or drives not a tuple or list: one str), a cutoff <= 0 or
        not a number, decimate not a whole number >= 1 (a bool neither),
        currents without gains, or current, consistent or simplify not a bool (numpy's too;
        an InputError naming the field).
    """

    cutoff: object = "auto"
    decimate: int = 1
    drives: tuple = DEFAULT_DRIVES
    current: bool = False
    drive_gains: tuple | None = None
    consistent: bool = False
    simplify: bool = False

    def __post_init__(self):
        if not isinstance(self.drives, (tuple, list)):  # one word is not a sequence of letters
            raise ValueError(f"drives is a tuple of drive columns, e.g. ('viscous', "
                             f"'coulomb'), not the {type(self.drives).__name__} {self.drives!r}")
        unknown = [k for k in self.drives if k not in DRIVE_KINDS]
        if unknown:
            raise ValueError(f"unknown drive column {unknown[0]!r} (known: "
                             f"{', '.join(DRIVE_KINDS)})")
        if len(set(self.drives)) != len(self.drives):
            raise ValueError("a drive column is given twice")
        if not (self.cutoff is None or self.cutoff == "auto" or
                (is_number(self.cutoff) and 0 < self.cutoff < math.inf)):     # NaN neither
            raise ValueError(f"cutoff must be a frequency > 0 [Hz], 'auto' or None, got "
                             f"{self.cutoff!r}")
        if not (is_number(self.decimate) and self.decimate % 1 == 0 and self.decimate >= 1):
            raise ValueError(f"decimate must be a whole number >= 1, got {self.decimate!r}")
        check_flags(current=self.current, consistent=self.consistent, simplify=self.simplify)
        if self.current and self.drive_gains is None:
            raise ValueError("currents need the drive gains K (tau = K i)")
        if self.drive_gains is not None and not all(
                is_number(k) and 0 < abs(k) < math.inf for k in self.drive_gains):
            raise ValueError("drive gains must be finite and nonzero numbers")

    def settings(self) -> dict:
        """dict: the options as plain values, for provenance."""
        return {"cutoff_hz": self.cutoff, "decimate": int(self.decimate),
                "drives": [k for k in DRIVE_KINDS if k in self.drives], "current": bool(self.current),
                "drive_gains": None if self.drive_gains is None else
                [float(k) for k in self.drive_gains],
                "consistent": bool(self.consistent), "simplify": bool(self.simplify),
                "coulomb_model": "sign(qd)"}


def _kept_torque(prior, drives, p):
    """The robot file's drive torque Ia qdd + F_v qd + F_c sign(qd) + tau_0
    (:func:`gd_analyze.model.drives.friction_torque`, sign(0) = 0) of the kinds not among
    ``drives`` (not fitted, kept at the file's values; every kind for ``()``) at a
    preprocessed recording's samples, filtered as its torque, shape (N, n) [N m or N]; None
    where the file has none of them."""
    kept = [k for k in DRIVE_KINDS if k not in drives
            and np.any(getattr(prior, "torque_offset" if k == "offset" else k))]
    terms = {"armature": prior.armature * p.qdd, "viscous": prior.viscous * p.qd,
             "coulomb": prior.coulomb * np.sign(p.qd), "offset": prior.torque_offset + 0 * p.qd}
    return p.filtered(sum(terms[k] for k in kept)) if kept else None


def _less_kept(pres, kept):
    """The preprocessed recordings with the robot file's kept drive torque
    (:func:`_kept_torque`, None where the file has none) taken off their torque, as a fit of
    the other columns needs."""
    return [p if d is None else replace(p, tau=p.tau - d) for p, d in zip(pres, kept)]


def _listed(items):
    """The recordings as a list: one file or Recording given alone is one recording, not a
    sequence of its name's characters."""
    one = isinstance(items, (str, os.PathLike, Recording)) or not isinstance(items or (), Iterable)
    return [items] if one else list(items or ())     # not iterable: refused as a recording


def _recording(item, prior, options):
    expect(item, (str, os.PathLike, Recording), "recording", "a CSV file or a Recording")
    n, rec = prior.n, (item if isinstance(item, Recording)
                       else read_recording(item, prior.n, options.current, prior.joint_names()))
    if rec.n != n:
        raise InputError(f"the recording has {rec.n} joints, the robot has {n}", rec.source)
    if (step := float(np.median(np.diff(rec.t)))) >= prep.SLOW_STEP:   # a clock in ms read in s
        warnings.warn(f"{rec.source}: column t: steps of {step:.3g} s: in ms?", InputWarning)
    # a step beyond pi is no arm's motion but a wrap at +-pi, as a continuous joint's log holds it
    rec = replace(rec, q=np.where(prior.prismatic, rec.q, np.unwrap(rec.q, axis=0)))
    if options.current and len(options.drive_gains) != n:
        raise InputError(f"{len(options.drive_gains)} drive gains for {n} joints",
                         column="--drive-gains")
    return rec


def _prepared(rec, cutoff, options, label, prismatic, train, notes, extra=None, predicted=None):
    """A recording preprocessed, its clipped samples (and ``extra``'s) left out of the fit; one
    warning line per joint clipped, model-free and where ``extra`` (found against the fitted
    model) adds to it (none where ``notes`` is None: the fit that judges the extreme levels,
    which leaves out every sample marked). With ``predicted`` (the fitted model's torque on the
    recording's clock), a coarsely quantised torque keeps the model-free rule's samples only at
    an extreme the model goes beyond
    (:func:`gd_analyze.estimation.preprocess.confirmed_clips`). A torque of fewer than
    :data:`~gd_analyze.estimation.preprocess.CLIP_FEW` values keeps the samples either finds,
    its warning line saying that so few levels cannot tell a clip from a rounded peak."""
    tau = rec.tau * np.asarray(options.drive_gains) if options.current else rec.tau
    clipped = prep.clipped_samples(rec.q, rec.tau)
    if predicted is not None:
        clipped = prep.confirmed_clips(rec.q, tau, clipped, predicted)
    few = prep.coarse_columns(tau, prep.CLIP_FEW) & (notes is not None)
    found = [(clipped, "")] + ([] if extra is None else
                               [(extra & ~clipped, " where the fitted model goes beyond")])
    for new, where in found if notes is not None else ():
        for j in np.flatnonzero(new.any(axis=0)):
            x, mid = rec.tau[new[:, j], j], rec.tau[:, j].mean()     # the level of each extreme
            at = " and ".join(f"{np.median(v):.6g}" for v in (x[x < mid], x[x > mid]) if v.size)
            notes.append(f"{rec.source}: column {rec.column('tau', j)}: joint {j + 1}'s "
                         f"{'current' if options.current else 'torque'} "
                         f"{'looks' if few[j] else 'is'} clipped at {at} "
                         f"{'A' if options.current else 'N' if prismatic[j] else 'N m'} (flat at "
                         f"its extreme{where}, a drive's limit or a sensor's range?) on "
                         f"{new[:, j].mean():.1%} of the samples: " + (
                             f"it takes fewer than {prep.CLIP_FEW} values, too few to tell a "
                             f"clip from an honest peak rounded to its level, so they are kept"
                             if few[j] else "left out of the fit" if train
                             else "they count in its errors"))
            warnings.warn(notes[-1], InputWarning, stacklevel=3)
    clipped = (clipped if extra is None else clipped | extra) & ~few
    try:
        return prep.preprocess(rec.t, rec.q, tau, rec.qd, rec.qdd, cutoff=cutoff,
                               decimate=int(options.decimate), label=label, prismatic=prismatic,
                               clipped=clipped)
    except ValueError as exc:
        said = str(exc).removeprefix(f"{label}: ")      # the file is named by the error
        if options.cutoff == "auto" and cutoff is not None and not train:   # chosen elsewhere
            own = prep.default_cutoff(rec.t, rec.q, prismatic)    # 1000x apart: ms against s
            raise InputError(f"{said} (the cutoff {cutoff:.4g} Hz was chosen from the training "
                             f"recordings; this one's median step is "
                             f"{float(np.median(np.diff(rec.t))):.4g} s" + (
                                 f" and its own data give {own:.4g} Hz: are all time stamps "
                                 f"in seconds? Else give --cutoff)" if own > 30 * cutoff else
                                 ": a longer recording, or a higher --cutoff, is needed)"),
                             rec.source) from None
        raise InputError(said, rec.source,
                         column="--cutoff" if "cutoff" in said else None) from None


def recording_name(files: Sequence[str | os.PathLike[str]]) -> str:
    """What a recording is called in the results, the reports and the output folder's name:
    its (first) file's name, or the folder's where files of one folder whose names have
    nothing in common are joined (``log/q.csv+log/dq.csv+log/current_mA.csv``: ``log``).

    Parameters
    ----------
    files : sequence of str or os.PathLike, length >= 1
        The recording's files, in the order given.

    Returns
    -------
    str

    Examples
    --------
    >>> recording_name(["log/q.csv", "log/dq.csv"]), recording_name(["a/arm_q.csv", "a/arm_dq.csv"])
    ('log', 'arm_q')
    """
    paths = [Path(f) for f in files]
    folder = paths[0].parent.name if len({p.parent for p in paths}) == 1 else ""
    common = os.path.commonprefix([p.stem for p in paths])
    return folder if len(paths) > 1 and folder and not common else paths[0].stem


def identify(robot: Robot | str | Path,
             recordings: Sequence[str | os.PathLike | Recording],
             validate: Sequence[str | os.PathLike | Recording] = (),
             options: IdentifyOptions | dict | None = None) -> IdentificationResult:
    """Identify an arm's base parameters and drives from recorded torques.

    Parameters
    ----------
    robot : Robot, str or pathlib.Path
        The robot file (the prior): a :class:`~gd_analyze.model.robot.Robot`, a built-in
        name or a TOML or URDF file.
    recordings : sequence of str, os.PathLike or Recording
        The training recordings (:func:`~gd_analyze.trajectory.trajectory.read_recording`);
        one given alone is one recording.
    validate : sequence of str, os.PathLike or Recording, optional
        Recordings not used for fitting, on which the errors are reported (one alone, too).
    options : IdentifyOptions or dict, optional
        The settings (a dict: :class:`IdentifyOptions`' fields).

    Returns
    -------
    IdentificationResult
        Its ``dataset`` is the store's content (``identification.h5``).

    Raises
    ------
    InputError
        On a recording that cannot be used (file, row, column), too few moving samples,
        options that do not fit the robot, or a robot, recording or options of another type.

    Notes
    -----
    Model: the base regressor (Gautier 1990) with per-joint drive columns
    (:mod:`gd_analyze.estimation.regressor`); ordinary then weighted least squares
    (Gautier & Poignet 2001); physically consistent parameters after Wensing, Kim & Slotine
    (2017).
    """
    if options is None or isinstance(options, dict):
        try:
            options = IdentifyOptions(**(options or {}))
        except (TypeError, ValueError) as exc:
            raise InputError(f"options: {exc}") from None
    else:
        expect(options, IdentifyOptions, "options", "an IdentifyOptions or a dict of its fields")
    prior = robot if isinstance(robot, Robot) else load_robot(robot)
    recordings, validate = _listed(recordings), _listed(validate)
    if not recordings:
        raise InputError("no recording to identify from")
    train = [_recording(r, prior, options) for r in recordings]
    valid = [_recording(r, prior, options) for r in validate]
    # a recording in degrees by mistake, say: named again on a failure of the fit
    beyond = [m for r in train + valid for m in check_joint_limits(prior, r)]
    degrees = ("; a recording in degrees? (see the joint-limit warnings)" if any(
        "in degrees?" in m for m in beyond) else "") + ("; time stamps in ms? (see the warning on "
        "column t)" if any(np.median(np.diff(r.t)) >= prep.SLOW_STEP for r in train) else "")
    what = "current" if options.current else "torque"
    if not any(np.any(r.tau) for r in train):
        raise InputError(f"every {what} in the training recordings is 0: there is nothing to "
                         f"identify from (is the {what} column recorded?)")
    silent = [j for j in range(prior.n) if not any(np.any(r.tau[:, j]) for r in train)]
    if silent:          # a joint without its torque: its zeros would be fitted as torque
        raise InputError(f"joint {silent[0] + 1}'s {what} is 0 in every row of "
                         f"{'the' if len(train) == 1 else 'every'} training recording: is it "
                         f"recorded? The fit would take the zeros for the joint's {what}",
                         train[0].source if len(train) == 1 else None, row=1,
                         column=train[0].column("tau", silent[0]))
    if all(prep.still_joints(r.q, prior.prismatic).all() for r in train):
        raise InputError("no joint moves in the training recordings (every joint's position "
                         f"spans less than {prep.STILL_SPAN['revolute']:g} rad or "
                         f"{prep.STILL_SPAN['prismatic']:g} m in each): there is nothing to "
                         "identify from")
    names = group_names([recording_name([f for f, _ in r.files] or [r.source])
                         for r in train + valid])
    notes = []
    cutoff = options.cutoff
    if cutoff == "auto":
        cutoff = max(prep.default_cutoff(r.t, r.q, prior.prismatic) for r in train)
        notes.append(f"low-pass cutoff {cutoff:.3g} Hz chosen from the training data (5 x the "
                     f"bandwidth holding 99% of the positions' power), used for every recording")
    judged, kept = _model_clipped(prior, train, names, cutoff, options, notes)   # or none
    pres = [_prepared(r, cutoff, options, name, prior.prismatic, k < len(train), notes,
                      *(judged[k] if k < len(judged) else ()))
            for k, (r, name) in enumerate(zip(train + valid, names))]
    kept += [_kept_torque(prior, options.drives, p) for p in pres[len(kept):]]
    try:
        fit, regressors = fit_robot(prior, _less_kept(pres[:len(train)], kept), options.drives,
                                    options.consistent)
    except FitFailure as exc:
        raise InputError(f"cannot identify: {exc}{degrees}") from None
    except SolverFailure as exc:
        raise InputError(f"cannot find physically consistent parameters: {exc}" + (
            degrees or "; the recordings may not excite the arm enough (try plan --excitation)")
        ) from None
    base, b, theta, est, columns = fit.base, fit.base.rank, fit.theta, fit.estimate, fit.columns
    simplified = _simplified_model(fit.identified, pres, len(train), options) \
        if options.simplify else None
    fits, filed = [], []
    pending = dict(enumerate(regressors))       # each freed once its recording is predicted
    rigid = np.concatenate([base.beta, np.zeros(theta.size - b)])   # the file's, no drives
    for k, (p, name, rec) in enumerate(zip(pres, names, train + valid)):
        is_train = k < len(train)
        keep = p.keep
        rows = pending.pop(k) if is_train else RegressorRows(prior, p, columns)
        products = rows.times(np.column_stack([theta, rigid, fit.file_theta]))
        if kept[k] is not None:
            products[..., [0, 2]] += kept[k][keep][..., None]
        drives = _kept_torque(prior, (), p)         # the file's drives, all of them
        tau_prior = products[..., 1] + (0 if drives is None else drives[keep])
        tau_s = None if simplified is None else p.filtered(
            simplified_torque(simplified[0], p.q, p.qd, p.qdd))[keep]
        fits.append(RecordingFit(
            name=name, file=rec.source, sha256=rec.sha256, tau_simplified=tau_s,
            role="train" if is_train else "validate", t=p.t[keep], q=p.q[keep],
            qd=p.qd[keep], qdd=p.qdd[keep], tau_measured=p.tau[keep],
            tau_predicted=products[..., 0], tau_prior=tau_prior, notes=(*rec.notes, *p.notes),
            used=fit.used[k] if is_train else np.zeros(p.q[keep].shape, bool)))
        filed.append(f"{name} {replace(fits[-1], tau_predicted=products[..., 2]).errors()[2]:.2%}"
                     f" ({fits[-1].errors()[2]:.2%})")
    file_note = fit.robot_file_note and (   # what the robot file's parameters do on the data
        f"{fit.robot_file_note}; their total relative torque error ||E||_F / ||T||_F: "
        f"{', '.join(filed)} (in brackets the least-squares fit's)")
    notes += [file_note or n if n == fit.robot_file_note else n for n in fit.notes]
    table = ParameterTable(names=fit.names, kinds=fit.kinds, value=theta, std=est.std,
                           ols_value=est.ols_value, prior=fit.prior, identifiable=est.identifiable)
    if table.unidentifiable:
        notes.append(f"not identifiable on these data (kept at the robot file's value): "
                     f"{', '.join(table.unidentifiable)}")
    if simplified is not None:
        notes.append(f"simplified model of the identified robot (the main job's analysis along "
                     f"{names[simplified[2]]}): {simplified[1]}")
    settings = {**options.settings(), "cutoff_hz_used": cutoff,
                "idle_threshold": fit.threshold.tolist(), "standard_method": fit.method,
                "robot_file_note": file_note,
                "simplified_guarantee": None if simplified is None else simplified[1]}
    inputs = {**{f: h for r in train + valid for f, h in r.files or [(r.source, r.sha256)]},
              str(prior.source): prior.sha256}
    return IdentificationResult(
        prior=prior, identified=fit.identified, offsets=fit.offsets, parameters=table,
        condition_number=est.condition_number, rank=est.rank, standard=fit.standard,
        standard_prior=base.standard, min_eigenvalue=fit.min_eigenvalue, inputs=inputs,
        consistent=fit.consistent, standard_method=fit.method, recordings=tuple(fits),
        settings=settings, preprocessing=tuple(notes), version=VERSION, noise_std=est.noise_std)



def _model_clipped(prior, train, names, cutoff, options, notes):
    """Per training recording, the samples clipped against a model fitted without the
    samples at each torque's extreme levels (:func:`gd_analyze.estimation.preprocess.model_clipped`),
    and that model's torque (with the robot file's kept drive terms, :func:`_less_kept`, as the
    main fit) interpolated onto the recording's clock; none where no
    torque holds its extreme levels over :data:`~gd_analyze.estimation.preprocess.CLIP_RUN`
    samples, nor where that fit fails (one warning line in ``notes``: the model-free rule then
    judges alone). And the kept drive torque of each recording fitted (:func:`_kept_torque`;
    none where none is fitted), the main fit's too: the marks change which samples are kept,
    not q, qd, qdd nor the filter."""
    if all(prep.extreme_samples(r.tau).sum(axis=0).max() < prep.CLIP_RUN for r in train):
        return [], []   # no torque at its extremes for a run's samples (unquantised): none judged
    firsts = [_prepared(r, cutoff, options, name, prior.prismatic, True, None,
                        extra=prep.extreme_samples(r.tau)) for r, name in zip(train, names)]
    kept = [_kept_torque(prior, options.drives, p) for p in firsts]
    try:
        est, rows = fit_columns(prior, _less_kept(firsts, kept), options.drives)
    except FitFailure as exc:
        coarse = sorted({r.column("tau", j) for r in train
                         for j in np.flatnonzero(prep.coarse_columns(r.tau))})
        notes.append(f"the clip check of the torques of fewer than {prep.CLIP_COARSE} levels "
                     f"({', '.join(coarse)}) against the fitted model is skipped: the fit without "
                     f"the samples at their extreme levels failed ({exc}); their clips are "
                     f"judged by the model-free rule alone")
        warnings.warn(notes[-1], InputWarning, stacklevel=3)
        return [], kept
    judged = []
    for r, p, src, d in zip(train, firsts, rows, kept):
        model = src.times(est.value[:, None])[..., 0] + (0 if d is None else d[p.keep])
        predicted = np.column_stack([np.interp(r.t, p.t[p.keep], c, left=np.nan, right=np.nan)
                                     for c in model.T])
        tau = r.tau * np.asarray(options.drive_gains) if options.current else r.tau
        judged.append((prep.model_clipped(r.q, tau, predicted, est.noise_std), predicted))
    return judged, kept


def _simplified_model(identified, pres, n_train, options):
    """The simplified model of the identified robot: the main job's analysis
    (:func:`gd_analyze.jobs.analyze.analyze`, its default options but the formulations'
    comparison; a recording longer than one chunk streamed through a private temporary file,
    :func:`gd_analyze.jobs.analyze.analyze_to_file`) along the first validation recording's
    kept samples (the first training recording's if there is none). Returns (model, guarantee statement, recording index)."""
    index = n_train if len(pres) > n_train else 0
    p = pres[index]
    traj = trajectory_from_arrays(p.t[p.keep], p.q[p.keep], p.qd[p.keep], p.qdd[p.keep],
                                  n_joints=identified.n)
    options = AnalysisOptions(formulations=False)
    if traj.n_setpoints <= stream_chunk(identified.n):
        model = analyze(identified, traj, options).model
    else:               # streamed through a private file, deleted: memory bounded by chunks
        with tempfile.TemporaryDirectory(prefix="gd-analyze-identify-") as tmp:
            model = analyze_to_file(identified, traj, Path(tmp) / "results.h5", options).model
    statement = model.guarantee.statement() if model.guarantee is not None else \
        "no guarantee beyond the analysed recording"
    return model, statement, index
