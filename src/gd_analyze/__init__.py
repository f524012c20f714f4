"""gd-analyze: translational and rotational dominance in a robot arm's equations of motion.

The generalized d'Alembert equations (Fu, Gonzalez & Lee 1987, Sec. 3.4) split the inertia
matrix D and the Coriolis and centrifugal vector h of tau = D(q) qdd + h(q, qd) + c(q) into a
translational and a rotational part. gd-analyze computes the split along a trajectory, checks it
against Pinocchio, ranks which part dominates each element, and writes a simplified model.

The Python API, for a notebook: :func:`load_robot` (a built-in name, a TOML or URDF file, URDF
text or a ``pinocchio.Model``), :func:`read_trajectory`, :func:`analyze` (the main job's results
dataset, in memory), :class:`AnalysisOptions` and :class:`SimplifyOptions` (its settings, with
the command line's defaults; :class:`RegionLimits` the user's region), :func:`regressor` (the
base regressor Y_b and beta), :func:`gd_terms`; :func:`identify` (a robot's parameters from
recorded torques: the result, with its ``dataset``), :func:`read_recording` and
:class:`IdentifyOptions`.
"""

from ._version import VERSION as __version__
from .core.dynamics.dalembert import GDTerms, gd_terms
from .core.model.robot import Robot
from .errors import InputError
from .io.robots import load_robot

__all__ = ["__version__", "GDTerms", "gd_terms", "InputError", "Robot", "load_robot",
           "SimplifiedModel", "load_model", "save_model", "regressor", "analyze",
           "read_trajectory", "AnalysisOptions", "SimplifyOptions", "RegionLimits", "identify",
           "read_recording", "IdentifyOptions"]

#: Public names imported on first use: name -> (module, attribute).
_LAZY = {
    # SimplifiedModel pulls in JSON/IO code that the core does not need
    "SimplifiedModel": ("core.selection.simplified", "SimplifiedModel"),
    "load_model": ("io.model_file", "load_model"),
    "save_model": ("io.model_file", "save_model"),
    "regressor": ("core.symbolic.base_parameters", "base_regressor"),
    "analyze": ("workflows.run", "results_dataset"),
    "read_trajectory": ("io.trajectory", "read_trajectory"),
    "AnalysisOptions": ("workflows.options", "AnalysisOptions"),
    "SimplifyOptions": ("workflows.options", "SimplifyOptions"),
    "RegionLimits": ("core.selection.region", "RegionLimits"),
    "identify": ("workflows.identify", "identify"),
    "read_recording": ("io.recording", "read_recording"),
    "IdentifyOptions": ("workflows.identify", "IdentifyOptions"),
}


def __getattr__(name):
    if name in _LAZY:
        import importlib

        module, attribute = _LAZY[name]
        return getattr(importlib.import_module(f".{module}", __name__), attribute)
    raise AttributeError(f"module 'gd_analyze' has no attribute {name!r}")
