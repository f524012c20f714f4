"""D, h and c of gd-analyze against the Robotics Toolbox for Python on the same robots.

    python analysis/rtb_compare.py [--states N]

The Robotics Toolbox (P. I. Corke) is not a dependency of gd-analyze; run this where it is
installed (``pip install roboticstoolbox-python``). For

- ``analysis/data/panda_mdh.toml``: the toolbox's modified-DH Panda (``models.DH.Panda``)
  written as a gd-analyze robot file in the modified convention, and
- the built-in ``stanford`` robot: the toolbox's standard-DH Stanford arm
  (``models.DH.Stanford``, prismatic joint 3),

it sets the toolbox's motor inertias, viscous and Coulomb friction to zero and compares, on N
random states within the joint limits, gd-analyze's D = D_tran + D_rot, h = h_tran + h_rot and
c with the toolbox's ``inertia(q)``, ``coriolis(q, qd) @ qd`` and ``gravload(q)``. Each error is
on its natural scale: D_ij against sqrt(D_ii D_jj) at the same state, h_i and c_i against the
peak |tau_i| = |D qdd + h + c|_i over the states. Prints one JSON line; exits 1 if an error
passes 1e-10.
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
TOL = 1e-10


def natural_errors(D, h, c, D_ref, h_ref, c_ref, qdd):
    """Largest errors of D, h, c on their natural scales (see the module docstring)."""
    diag = np.einsum("kii->ki", D_ref)
    scale_D = np.sqrt(diag[:, :, None] * diag[:, None, :])
    tau = np.einsum("kij,kj->ki", D_ref, qdd) + h_ref + c_ref
    scale_t = np.abs(tau).max(axis=0)
    return {"D": float((np.abs(D - D_ref) / scale_D).max()),
            "h": float((np.abs(h - h_ref) / scale_t).max()),
            "c": float((np.abs(c - c_ref) / scale_t).max())}


def compare(robot, toolbox_robot, states, seed=0):
    """Errors of gd-analyze against the toolbox on random states within the limits."""
    from gd_analyze import gd_terms

    for link in toolbox_robot.links:                    # rigid links only
        link.Jm, link.B, link.Tc = 0.0, 0.0, np.zeros(2)
    rng = np.random.default_rng(seed)
    n = robot.n
    q = rng.uniform(robot.q_min, robot.q_max, (states, n))
    qd = rng.uniform(-1, 1, (states, n)) * robot.qd_max
    qdd = rng.uniform(-1, 1, (states, n)) * robot.qdd_max
    t = gd_terms(robot, q, qd)
    D_ref = np.array([toolbox_robot.inertia(x) for x in q])
    h_ref = np.array([toolbox_robot.coriolis(x, v) @ v for x, v in zip(q, qd)])
    c_ref = np.array([toolbox_robot.gravload(x, gravity=robot.gravity) for x in q])
    return natural_errors(t.D, t.h, t.c, D_ref, h_ref, c_ref, qdd)


def main(argv=None):
    """Compare and print one JSON line.

    Parameters
    ----------
    argv : list of str, optional
        Command-line arguments.

    Returns
    -------
    int
        0 if every error is within 1e-10, else 1.
    """
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--states", type=int, default=200)
    args = parser.parse_args(argv)
    warnings.filterwarnings("ignore")
    import roboticstoolbox as rtb

    from gd_analyze import load_robot

    result = {"toolbox_version": rtb.__version__, "states": args.states,
              "panda_mdh": compare(load_robot(str(ROOT / "analysis" / "data" / "panda_mdh.toml")),
                                   rtb.models.DH.Panda(), args.states),
              "stanford": compare(load_robot("stanford"), rtb.models.DH.Stanford(), args.states)}
    worst = max(v for key in ("panda_mdh", "stanford") for v in result[key].values())
    result["max_error"] = worst
    print(json.dumps(result))
    return 0 if worst <= TOL else 1


if __name__ == "__main__":
    sys.exit(main())
