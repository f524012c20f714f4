"""The Robotics Toolbox's Panda (modified DH) against gd-analyze on the same parameters.

``data/robots/panda_mdh.toml`` holds the Robotics Toolbox for Python's modified-DH Panda
(``roboticstoolbox.models.DH.Panda``) in gd-analyze's robot-file layout. This script draws
random states within the joint limits and compares, with motor inertia and friction set to zero
in the toolbox,

- D: gd-analyze's D_tran + D_rot against the toolbox's ``inertia(q)``,
- h: h_tran + h_rot against ``coriolis(q, qd) @ qd``,
- c: the gravity loading against ``gravload(q)``,
- tau = D qdd + h + c against ``rne(q, qd, qdd)``,

each on its natural scale: sqrt(D_ii D_jj) for D_ij, and per joint the peak |tau_i| of the
toolbox's torques over the states for h, c and tau. It prints the largest relative difference of
each and exits with status 1 if any exceeds the tolerance (default 1e-10).

The toolbox is not a dependency of gd-analyze: this is the only file that imports it
(``pip install roboticstoolbox-python``).

Usage::

    python analysis/rtb_panda.py [--states N] [--seed S] [--tol TOL]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
TOML = ROOT / "data" / "robots" / "panda_mdh.toml"


def toolbox_panda():
    """The toolbox's DH Panda with motor inertia, viscous and Coulomb friction all zero."""
    import roboticstoolbox as rtb

    panda = rtb.models.DH.Panda().nofriction(coulomb=True, viscous=True)
    for link in panda.links:
        link.Jm = 0.0
        link.B = 0.0
        link.Tc = [0.0, 0.0]
    return panda


def natural_errors(robot, panda, q, qd, qdd):
    """Largest relative differences of D, h, c and tau on their natural scales."""
    from gd_analyze import gd_terms

    terms = gd_terms(robot, q, qd)
    D_ref = np.array([panda.inertia(qk) for qk in q])
    h_ref = np.array([panda.coriolis(qk, qdk) @ qdk for qk, qdk in zip(q, qd)])
    c_ref = np.array([panda.gravload(qk) for qk in q])
    tau_ref = np.array([panda.rne(qk, qdk, qddk) for qk, qdk, qddk in zip(q, qd, qdd)])
    ours = {"D": terms.D, "h": terms.h, "c": terms.c, "tau": terms.tau(qdd)}
    refs = {"D": D_ref, "h": h_ref, "c": c_ref, "tau": tau_ref}
    for name, arr in {**ours, **{f"{k} (toolbox)": v for k, v in refs.items()}}.items():
        if not np.isfinite(arr).all():
            raise SystemExit(f"rtb_panda: {name} is not finite")
    diag = np.einsum("kii->ki", D_ref)
    d_scale = np.sqrt(np.abs(diag[:, :, None] * diag[:, None, :])).max(axis=0)
    t_scale = np.abs(tau_ref).max(axis=0)
    if not ((d_scale > 0).all() and (t_scale > 0).all()):
        raise SystemExit("rtb_panda: a zero scale (the states do not excite every element)")
    return {name: float((np.abs(ours[name] - refs[name])
                         / (d_scale if name == "D" else t_scale)).max()) for name in ours}


def main(argv=None):
    """Compare and print; return 0 if every difference is within the tolerance, else 1."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--states", type=int, default=200, help="random states (default 200)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--tol", type=float, default=1e-10)
    args = ap.parse_args(argv)
    import roboticstoolbox

    from gd_analyze import load_robot

    robot = load_robot(TOML)
    panda = toolbox_panda()
    rng = np.random.default_rng(args.seed)
    lo, hi = np.asarray(robot.q_min), np.asarray(robot.q_max)
    q = rng.uniform(lo, hi, (args.states, robot.n))
    qd = rng.uniform(-1, 1, (args.states, robot.n)) * np.asarray(robot.qd_max)
    qdd = rng.uniform(-1, 1, (args.states, robot.n)) * np.asarray(robot.qdd_max)
    t0 = time.perf_counter()
    errors = natural_errors(robot, panda, q, qd, qdd)
    elapsed = time.perf_counter() - t0
    print(f"{robot.name} ({TOML.relative_to(ROOT)}) against roboticstoolbox-python "
          f"{roboticstoolbox.__version__} models.DH.Panda (Jm = B = Tc = 0), {args.states} random "
          f"states within the limits, seed {args.seed} ({elapsed:.1f} s)")
    print(f"{'quantity':<10}{'toolbox':<26}{'max relative difference':>24}")
    calls = {"D": "inertia(q)", "h": "coriolis(q, qd) @ qd", "c": "gravload(q)",
             "tau": "rne(q, qd, qdd)"}
    for name, err in errors.items():
        print(f"{name:<10}{calls[name]:<26}{err:>24.2e}")
    worst = max(errors.values())
    ok = worst <= args.tol
    print(f"{'PASS' if ok else 'FAIL'}: largest {worst:.2e} "
          f"{'<=' if ok else '>'} {args.tol:g} (D on sqrt(D_ii D_jj), the others on peak |tau_i|)")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
