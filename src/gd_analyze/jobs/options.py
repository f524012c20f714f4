"""The settings of the main job, as frozen values.

:class:`AnalysisOptions` says how a trajectory is analysed (and holds a
:class:`~gd_analyze.simplify.options.SimplifyOptions`: how the simplified model is built);
its defaults come from :data:`gd_analyze.config.defaults`.
The command line builds them from its arguments (:mod:`gd_analyze.cli.commands`) and hands
them to :func:`gd_analyze.jobs.run.run_analysis`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..config import defaults
from ..errors import check_flags, expect, is_number
from ..simplify.options import SimplifyOptions

__all__ = ["SimplifyOptions", "AnalysisOptions"]


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
    simplify : SimplifyOptions or None
        How the simplified model is built; None: no model (the ranking's choices alone).

    Raises
    ------
    ValueError
        If a threshold or compress is not a number (an int or float, not a bool) or is out of
        range, verify or formulations not a bool (numpy's too), or simplify not a
        SimplifyOptions or None (an InputError naming the field).

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
        if not (is_number(self.dominance) and 0.5 < self.dominance <= 1.0):
            raise ValueError(f"dominance must be a number in (0.5, 1], got {self.dominance!r}")
        if not (is_number(self.negligible) and 0.0 <= self.negligible < 1.0):
            raise ValueError(f"negligible must be a number in [0, 1), got {self.negligible!r}")
        check_flags(verify=self.verify, formulations=self.formulations)
        expect(self.simplify, (SimplifyOptions, type(None)), "simplify", "a SimplifyOptions or None")
        if not (is_number(self.compress) and self.compress in range(10)):
            raise ValueError(f"compress must be a whole number 0-9, got {self.compress!r}")
