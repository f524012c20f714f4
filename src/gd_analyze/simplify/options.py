"""How the simplified model is built, as one frozen value.

Its defaults come from :data:`gd_analyze.config.defaults`; the command line builds it from its
arguments and the main job (:class:`gd_analyze.jobs.options.AnalysisOptions`) holds it.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..certify.region import RegionLimits
from ..config import MAXIMA, defaults
from ..errors import expect, is_number

__all__ = ["SimplifyOptions", "RULES", "EXPLICIT", "FORMS", "GUARANTEES"]

RULES = ("budget", "chapter")
EXPLICIT = ("auto", "always", "never")
FORMS = ("cheapest", "recursive", "explicit")
GUARANTEES = ("auto", "region", "trajectory")


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
        If a value is out of range (tolerance and torque_floor from 0 to
        :data:`gd_analyze.config.MAXIMA`, as at the command line), not a number where one is
        asked for (tolerance, torque_floor: an int or float, not a bool) or not one of its choices,
        ``region`` is not a RegionLimits, or rule ``"chapter"`` is given form ``"recursive"`` or explicit
        ``"never"`` (its model is the explicit model's elements in their classes).

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
        expect(self.region, (RegionLimits, type(None)), "region", "a RegionLimits or None")
        for name, most in MAXIMA.items():
            v = getattr(self, name)
            if not (is_number(v) and 0.0 <= v <= most):
                raise ValueError(f"{name} must be a number in [0, {most:g}], got {v!r}")
        for name, allowed in (("rule", RULES), ("explicit", EXPLICIT), ("form", FORMS),
                              ("guarantee", GUARANTEES)):
            if getattr(self, name) not in allowed:
                raise ValueError(f"{name} must be one of {allowed}, got {getattr(self, name)!r}")
        if self.rule == "chapter" and (self.form == "recursive" or self.explicit == "never"):
            raise ValueError("rule 'chapter' takes no form 'recursive' or explicit 'never': its "
                             "model is the explicit model's elements in their classes")
