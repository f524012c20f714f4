"""gd-analyze: translational and rotational dominance in a robot arm's equations of motion.

The generalized d'Alembert equations (Fu, Gonzalez & Lee 1987, Sec. 3.4) split the inertia
matrix D and the Coriolis and centrifugal vector h of tau = D(q) qdd + h(q, qd) + c(q) into a
translational and a rotational part. gd-analyze computes the split along a trajectory, checks it
against Pinocchio, ranks which part dominates each element, and writes a simplified model.
"""

from ._version import VERSION as __version__
from .core.dynamics.dalembert import GDTerms, gd_terms
from .core.model.robot import Robot
from .errors import InputError
from .io.robots import load_robot

__all__ = ["__version__", "GDTerms", "gd_terms", "InputError", "Robot", "load_robot",
           "SimplifiedModel", "load_model", "save_model"]


def __getattr__(name):
    # SimplifiedModel pulls in JSON/IO code that the core does not need: import it on use.
    if name == "SimplifiedModel":
        from .core.selection.simplified import SimplifiedModel

        return SimplifiedModel
    if name in ("load_model", "save_model"):
        from .io import model_file

        return getattr(model_file, name)
    raise AttributeError(f"module 'gd_analyze' has no attribute {name!r}")
