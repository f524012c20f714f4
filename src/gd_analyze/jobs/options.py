"""The settings of the main job, as frozen values.

:class:`SimplifyOptions` says how the simplified model is built, :class:`AnalysisOptions` how a
trajectory is analysed (and holds a :class:`SimplifyOptions`), :class:`ReportOptions` whether
and how the report is written. Their defaults come from :data:`gd_analyze.config.defaults`.
The command line builds them from its arguments (:mod:`gd_analyze.cli.commands`) and hands
them to :func:`gd_analyze.jobs.run.run_analysis`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..certify.region import RegionLimits
from ..config import defaults

__all__ = ["SimplifyOptions", "AnalysisOptions", "ReportOptions"]

RULES = ("budget", "chapter")
EXPLICIT = ("auto", "always", "never")
FORMS = ("cheapest", "recursive", "explicit")
GUARANTEES = ("auto", "region", "trajectory")


def _check_choice(name, value, allowed):
    if value not in allowed:
        raise ValueError(f"{name} must be one of {allowed}, got {value!r}")


@dataclass(frozen=True)
class SimplifyOptions:
    """How the simplified model is built (Sec. 3.4.1 and the error budget).

    Attributes
    ----------
    tolerance : float
        EPS: every joint's simplified torque stays within EPS times its scale on the
        trajectory (rule ``"budget"``).
    rule : {"budget", "chapter"}
        ``"budget"``: terms dropped by their torque contribution within EPS;
        ``"chapter"``: the share-based classes of Sec. 3.4.1 (no bound).
    torque_floor : float
        TAU [N m], the least scale of a joint torque.
    explicit : {"auto", "always", "never"}
        Whether the explicit G-D model is derived besides the recursive one.
    form : {"cheapest", "recursive", "explicit"}
        The form written.
    guarantee : {"auto", "region", "trajectory"}
        Where the budget model's bound must hold: proved over the robot's joint-limit region,
        or on the analysed trajectory; ``"auto"``: the region when the robot gives position
        and velocity limits for every joint.
    region : RegionLimits, optional
        The user's region (:class:`gd_analyze.certify.region.RegionLimits`, SI units):
        position ranges, velocity and acceleration limits, each in place of the robot's and
        clipped to the robot's own limits; None: the robot's limits, with the acceleration
        limits it lacks assumed (2 s^-1 x qd_max).

    Raises
    ------
    ValueError
        If a value is out of range or not one of its choices, or ``region`` is not a
        RegionLimits.

    Examples
    --------
    >>> SimplifyOptions().tolerance, SimplifyOptions(rule="chapter").rule
    (0.01, 'chapter')
    """

    tolerance: float = defaults["tolerance"]
    rule: str = defaults["rule"]
    torque_floor: float = defaults["torque_floor"]
    explicit: str = defaults["explicit"]
    form: str = defaults["form"]
    guarantee: str = defaults["guarantee"]
    region: RegionLimits | None = None

    def __post_init__(self):
        if self.region is not None and not isinstance(self.region, RegionLimits):
            raise ValueError("region must be a RegionLimits (or None: the robot's limits)")
        if not self.tolerance >= 0.0 or not self.torque_floor >= 0.0:
            raise ValueError("tolerance and torque_floor must be >= 0 (and not NaN)")
        _check_choice("rule", self.rule, RULES)
        _check_choice("explicit", self.explicit, EXPLICIT)
        _check_choice("form", self.form, FORMS)
        _check_choice("guarantee", self.guarantee, GUARANTEES)


@dataclass(frozen=True)
class AnalysisOptions:
    """How a trajectory is analysed: ranking thresholds, checks, storage, the model.

    Attributes
    ----------
    dominance : float
        s, the share at which one part dominates an element, in (0.5, 1].
    negligible : float
        e: an element below e times its scale is negligible, in [0, 1).
    verify : bool
        Verify the G-D terms against Pinocchio (on at most
        :data:`gd_analyze.jobs.analyze.VERIFY_MAX_SETPOINTS` set points).
    formulations : bool
        Store the agreement and operation counts of L-E, N-E and G-D (Table 3.5).
    compress : int
        gzip level 0-9 of the per-set-point variables of results.h5.
    simplify : SimplifyOptions
        How the simplified model is built.

    Raises
    ------
    ValueError
        If a threshold is out of range.

    Examples
    --------
    >>> AnalysisOptions(verify=False).simplify.tolerance
    0.01
    """

    dominance: float = defaults["dominance"]
    negligible: float = defaults["negligible"]
    verify: bool = defaults["verify"]
    formulations: bool = defaults["formulations"]
    compress: int = defaults["compress"]
    simplify: SimplifyOptions = field(default_factory=SimplifyOptions)

    def __post_init__(self):
        if not 0.5 < self.dominance <= 1.0:
            raise ValueError(f"dominance must be in (0.5, 1], got {self.dominance!r}")
        if not 0.0 <= self.negligible < 1.0:
            raise ValueError(f"negligible must be in [0, 1), got {self.negligible!r}")
        if self.compress not in range(10):
            raise ValueError(f"compress must be 0-9, got {self.compress!r}")


@dataclass(frozen=True)
class ReportOptions:
    """Whether and how the HTML and PDF reports are written.

    Attributes
    ----------
    enabled : bool
        Write report.html, report.pdf and figures/.
    paper : {"a4", "letter"}
        Page size of the PDF.

    Examples
    --------
    >>> ReportOptions().paper
    'a4'
    """

    enabled: bool = True
    paper: str = defaults["paper"]
