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
from .dynamics.dalembert import GDTerms, gd_terms
from .errors import InputError
from .model.robot import Robot
from .model.robots import load_robot

__all__ = ["__version__", "GDTerms", "gd_terms", "InputError", "Robot", "load_robot",
           "SimplifiedModel", "load_model", "save_model", "regressor", "analyze",
           "read_trajectory", "AnalysisOptions", "SimplifyOptions", "RegionLimits", "identify",
           "read_recording", "IdentifyOptions"]

#: Public names imported on first use: name -> (module, attribute).
_LAZY = {
    # SimplifiedModel pulls in JSON/IO code that the core does not need
    "SimplifiedModel": ("simplify.simplified", "SimplifiedModel"),
    "load_model": ("store.model_file", "load_model"),
    "save_model": ("store.model_file", "save_model"),
    "regressor": ("dynamics.base_parameters", "base_regressor"),
    "analyze": ("jobs.run", "results_dataset"),
    "read_trajectory": ("trajectory.trajectory", "read_trajectory"),
    "AnalysisOptions": ("jobs.options", "AnalysisOptions"),
    "SimplifyOptions": ("jobs.options", "SimplifyOptions"),
    "RegionLimits": ("certify.region", "RegionLimits"),
    "identify": ("jobs.identify", "identify"),
    "read_recording": ("trajectory.trajectory", "read_recording"),
    "IdentifyOptions": ("jobs.identify", "IdentifyOptions"),
}


def __getattr__(name):
    if name in _LAZY:
        import importlib

        module, attribute = _LAZY[name]
        return getattr(importlib.import_module(f".{module}", __name__), attribute)
    raise AttributeError(f"module 'gd_analyze' has no attribute {name!r}")
