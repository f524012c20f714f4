"""The defaults of gd-analyze's settings, in one place.

Every default a command-line option, a workflow or a core function uses is read from
:data:`defaults` (in the style of python-control's ``control.config.defaults``): the ranking's
thresholds s and e (Sec. 3.4.1 of Fu, Gonzalez & Lee 1987), the simplified model's error budget
EPS and torque floor TAU, the rule and form of the model, the report's paper, and
the control report's verdict tolerance; and the one rule of where the on-disk cache lives
(:func:`cache_dir`), which the derivation cache (:mod:`gd_analyze.cache`) reads.
A leaf module: it imports nothing of the package, so every layer may read it.

Examples
--------
>>> defaults["tolerance"], defaults["dominance"], defaults["rule"]
(0.01, 0.9, 'budget')
"""

from __future__ import annotations

import os
import types
from pathlib import Path
from typing import Any

__all__ = ["defaults", "MAXIMA", "cache_dir", "ROUND_OFF", "ROUND_OFF_EPS"]

#: A quantity whose peak is at most this fraction of its own scale is floating-point round-off
#: (about 4500 machine epsilons: a sum of a few thousand rounded terms), never data: the one
#: threshold of the ranking, the simplified model and the reports.
ROUND_OFF = 1e-12
#: ... or at most this many machine epsilons of the arm's scale of the same quantity (the
#: largest scale in the same units): the absolute floor of the verification against Pinocchio
#: (:data:`gd_analyze.dynamics.pinocchio.FLOOR_EPS`).
ROUND_OFF_EPS = 64.0

#: The largest error budget EPS [1] and torque floor TAU [N m] accepted, by the command line's
#: --tolerance and --torque-floor and by :class:`gd_analyze.simplify.options.SimplifyOptions`
#: alike: EPS x s_i and EPS x TAU then stay far from a float's range.
MAXIMA: dict[str, float] = {"tolerance": 1e3, "torque_floor": 1e30}

#: The defaults, read-only. Units: ``torque_floor`` [N m]; the others are fractions or names.
defaults: types.MappingProxyType[str, Any] = types.MappingProxyType({
    # ranking (Sec. 3.4.1): an element's part dominates at a share of at least s; an element
    # below e times its scale is negligible
    "dominance": 0.9,
    "negligible": 0.01,
    # the simplified model: error budget EPS (fraction of each joint's torque scale), least
    # torque scale TAU [N m], the rule that chooses its terms, whether the explicit G-D model
    # is derived and which form is written
    "tolerance": 0.01,
    "torque_floor": 0.0,
    "rule": "budget",
    "explicit": "auto",
    "form": "cheapest",
    # where the budget model's bound must hold: "auto" is "region" when the robot
    # gives position and velocity limits for every joint, else "trajectory"
    "guarantee": "auto",
    # results.h5 and the report
    "verify": True,
    "formulations": True,
    "compress": 0,
    "paper": "a4",
    # the control report's verdict: the simplified-model controller's peak tracking error
    # within this (or twice the full-model controller's) on every revolute joint [rad] and
    # prismatic joint [m]: 1 mrad, and 1 mm, the same 1 mrad seen at a 1 m lever arm
    "verdict_tolerance": (1e-3, 1e-3),
})


def cache_dir() -> Path | None:
    """The folder of every on-disk cache, or None when caching is disabled.

    ``GD_ANALYZE_NO_CACHE`` (any non-empty value) disables the caches; else
    ``GD_ANALYZE_CACHE_DIR`` names the folder; else it is ``$XDG_CACHE_HOME/gd-analyze``, or
    ``~/.cache/gd-analyze`` when ``XDG_CACHE_HOME`` is unset or empty (the XDG Base Directory
    Specification). The derivation cache's entries (:mod:`gd_analyze.cache`) live there.

    Returns
    -------
    pathlib.Path or None
        Read from the environment at each call (not created).
    """
    if os.environ.get("GD_ANALYZE_NO_CACHE"):
        return None
    if os.environ.get("GD_ANALYZE_CACHE_DIR"):
        return Path(os.environ["GD_ANALYZE_CACHE_DIR"])
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "gd-analyze"
