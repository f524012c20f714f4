"""Operation counts per set point of the L-E, N-E and G-D formulations, as implemented.

The counts are measured, not derived: the algorithms run on one set point whose values are
:class:`~gd_analyze.dynamics.counting.Counted` scalars, which count every multiplication and addition they take part in.

- L-E and N-E: the counted run calls the very cores that :func:`~gd_analyze.dynamics.lagrange_euler.le_terms`
  and :func:`~gd_analyze.dynamics.newton_euler.ne_tau` run on float arrays (``le_core``, ``ne_core``),
  on object arrays with a set-point axis of length 1. The counts cannot drift from that code.
- G-D, ``"gd"``: :func:`~gd_analyze.dynamics.dalembert.gd_terms` runs a compiled kernel
  (``gd_analyze.dynamics.kernels``, one pass per set point), counted by running the
  Python source of the very kernel numba compiles (``gd_kernel.py_func``) with ``np.empty``,
  ``np.cos`` and ``np.sin`` bound to counting versions.
- G-D, ``"gd-numpy"``: the Jacobian form as written, as array code (the array engine the
  package had beside the kernel, now the tests' oracle of it): :func:`_gd_mirror` transcribes
  its steps one for one (including the work it does on entries it then masks: the Jacobian
  columns j > s and the products Ic_s z_j for all s, j); the tests check that the
  transcription reproduces that array code.

Counting rule
-------------
- Inputs of a set point are C_i = cos(q_i), S_i = sin(q_i) (revolute joints), q_i (prismatic
  joints), qd_i and qdd_i; sines and cosines are not counted. Every formulation runs on the joint
  model of :mod:`gd_analyze.model.robot` (fixed placement P_i, t_i, then the joint's motion):
  the DH offsets are inside the placements, so theta_i = q_i + offset_i costs nothing.
- Robot parameters (placements P_i, t_i, masses, centres of mass, inertias,
  pseudo-inertias, gravity) are general numbers: an operation on parameters only is done once
  per robot and not counted; an operation with at least one set-point-dependent operand is.
  Parameters that happen to be 0 or 1 are counted like any other value, so the counts depend on
  n and the joint types only, not on the robot's numbers: :func:`operation_counts` counts a
  :func:`random_chain` with the arm's joint types, once per pattern of joint types and process
  (one count per arm, which the main report, the control report and ``compare`` all read).
  The revolute chains of 1 to 10 joints, whose counts every report tabulates beside Table 3.5,
  are counted once and kept in :data:`REVOLUTE_COUNTS`, which the tests count again.

Prismatic joints
----------------
Table 3.5 counts n revolute joints. A prismatic joint i changes the N-E recursion (Table 3.3)
thus: its rotation ^{i-1}R_i is the constant placement (a revolute joint's costs 12
multiplications and 6 additions: two columns of P_i Rz(q_i), each entry c P + s P) while its
origin becomes t_i + q_i P_i z0 (3 multiplications, 3 additions); w_i = ^iR_{i-1} w_{i-1}
loses "+ z0 qd_i" (1 addition) and wd_i loses "+ z0 qdd_i + w x z0 qd_i" (2 multiplications,
3 additions); vd_i gains "+ z0 qdd_i + 2 w_i x z0 qd_i" (3 multiplications, 3 additions);
tau_i = f_i . z0 in place of n_i . z0 costs the same. A prismatic joint with a moving frame
after a turning one (i > 2) so saves 12 + 2 - 3 - 3 = 8 multiplications and 6 + 1 + 3 - 3 - 3
= 4 additions. At i = 2 it saves 2 multiplications more: the component of vd_1 along joint 1's
axis is gravity's, a robot constant, which the constant ^1R_2 multiplies at no counted cost.
A prismatic first joint saves far more (its frame does not turn: w_1 = wd_1 = 0, whose zeros
spread). The tests check these savings against the counted run.
- Structural constants of the algorithm (the 0 and 1 entries of Q, z0, identity matrices, the
  last row of homogeneous matrices, zero initial conditions w_0 = wd_0 = 0, p_0 = 0) are exact
  0 and 1: multiplying by 0 or +-1 and adding 0 cost nothing. A negation costs nothing; a
  subtraction is an addition.
- tau = D qdd + h + c is included for L-E and G-D (Eqs. (3.2-26), (3.4-24)); N-E computes tau
  directly with no load and no damping.

Book formulas
-------------
Table 3.5 of Fu, Gonzalez & Lee (1987), "Comparison of robot arm dynamics computational
complexities" (its footnote: "No effort is spent here to optimize the computation"). The OCR of
the table is garbled; the formulas below are the published ones:

- L-E: 128/3 n^4 + 512/3 n^3 + 739/3 n^2 + 160/3 n multiplications,
  98/3 n^4 + 781/6 n^3 + 559/3 n^2 + 245/6 n additions;
- N-E: 132 n multiplications, 111 n - 4 additions;
- G-D: 13/6 n^3 + 105/2 n^2 + 268/3 n + 69 multiplications,
  4/3 n^3 + 44 n^2 + 146/3 n + 45 additions.

What the OCR confirms: in Table 3.5, N-E "132n" and "111n - 4" and G-D "+ 69", "44n^2" and
"+ 45" are legible; the L-E entries and the other G-D terms are not. Table 3.1 (L-E) totals read
128/3 n^4 + 512/3 n^3 + 844/3 n^2 + 76/3 n multiplications and 98/3 n^4 + 781/6 n^3 + 637/3 n^2 +
107/6 n additions: its n^4 and n^3 terms confirm Table 3.5's, its n^2 and n terms differ from
them. Table 3.4 (N-E in link coordinates, for a PUMA) totals 117 n - 24 multiplications and
103 n - 21 additions, not Table 3.5's 132 n and 111 n - 4; its partly garbled rows read, in a way
consistent with those totals, w 9n/7n, wd 9n/9n, vd 27n/22n, abar 15n/14n, F 3n/0,
f 9(n-1)/9n-6, N 24n/18n, n 21n-15/24n-15.
"""

from __future__ import annotations

import numbers
from collections import namedtuple
from fractions import Fraction as Fr
from functools import cache
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from ..model.kinematics import as_states, transforms_core
from ..model.robot import Robot
from ..model.robot_spec import robot_from_dict
from .counting import (
    OpLedger,
    count_consts,
    count_value,
    count_vars,
    counting_clone,
    python_kernels,
)
from .lagrange_euler import joint_q_matrices, le_core
from .lagrange_euler import le_constants as _le_constants
from .newton_euler import link_constants, ne_core, ne_cross

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["OpCount", "METHODS", "TABLE_3_5", "joint_types", "random_chain", "count_operations",
           "operation_counts", "book_counts", "table", "count_chain", "REVOLUTE_COUNTS"]

#: The implementations counted, in table order ("gd" is the compiled G-D engine).
METHODS = ("lagrange-euler", "newton-euler", "gd", "gd-numpy")

#: Table 3.5 of Fu, Gonzalez & Lee (1987): polynomial coefficients in n, highest power first.
TABLE_3_5: dict[str, dict[str, tuple[Fr, ...]]] = {
    "lagrange-euler": {
        "multiplications": (Fr(128, 3), Fr(512, 3), Fr(739, 3), Fr(160, 3), Fr(0)),
        "additions": (Fr(98, 3), Fr(781, 6), Fr(559, 3), Fr(245, 6), Fr(0)),
    },
    "newton-euler": {"multiplications": (Fr(132), Fr(0)), "additions": (Fr(111), Fr(-4))},
    "gd": {
        "multiplications": (Fr(13, 6), Fr(105, 2), Fr(268, 3), Fr(69)),
        "additions": (Fr(4, 3), Fr(44), Fr(146, 3), Fr(45)),
    },
}


OpCount = namedtuple("OpCount", ["multiplications", "additions", "tau"])
OpCount.__doc__ = """Result of :func:`count_operations`.

Attributes
----------
multiplications : int
    Multiplications per set point.
additions : int
    Additions and subtractions per set point.
tau : ndarray, shape (n,)
    The joint torques the counted run computed [N m].
"""


def joint_types(robot: Robot) -> str:
    """The joint types of an arm as one string, "R" revolute and "P" prismatic, base first.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints.

    Returns
    -------
    str
        Length n, e.g. ``"RRPRRR"`` for the Stanford arm.
    """
    return "".join("P" if p else "R" for p in robot.prismatic)


def random_chain(n: int, seed: int = 0, types: str | None = None) -> Robot:
    """A random n-joint chain with general parameters (none 0 or 1).

    Parameters
    ----------
    n : int
        Number of joints, >= 1.
    seed : int, optional
        Seed of :func:`numpy.random.default_rng`.
    types : str, optional
        Joint types, "R" revolute and "P" prismatic, length n (:func:`joint_types`); all
        revolute by default.

    Returns
    -------
    Robot
        Link lengths and offsets in [0.1, 0.5] m, twists +-[10, 170] deg, masses in [0.5, 5] kg,
        centres of mass within 0.2 m of the frame origin, physically valid inertia tensors with
        products of inertia, gravity (0, 0, -9.8062) m/s^2.

    Raises
    ------
    ValueError
        If n < 1 or types is not n letters R or P.
    """
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    types = "R" * n if types is None else types
    if len(types) != n or set(types) - {"R", "P"}:
        raise ValueError(f"types must be {n} letters R or P, got {types!r}")
    rng = np.random.default_rng(seed)
    links = []
    for kind in types:
        B = rng.normal(size=(3, 3)) * 0.1
        S = B @ B.T                                # second moment about the centre of mass
        I = np.trace(S) * np.eye(3) - S            # always satisfies the triangle inequality
        links.append({
            "d": float(rng.uniform(0.1, 0.5)), "a": float(rng.uniform(0.1, 0.5)),
            "alpha_deg": float(rng.choice([-1, 1]) * rng.uniform(10, 170)),
            "offset_deg": float(rng.uniform(-30, 30)), "mass": float(rng.uniform(0.5, 5.0)),
            "com": [float(v) for v in rng.uniform(-0.2, 0.2, 3)],
            "inertia": [float(I[0, 0]), float(I[1, 1]), float(I[2, 2]),
                        float(I[0, 1]), float(I[0, 2]), float(I[1, 2])],
            "q_limits_deg": [-170.0, 170.0], "qd_max_deg": 180.0, "qdd_max_deg": 360.0,
        })
        if kind == "P":                        # d is the joint variable, theta fixed
            link = links[-1]
            link["joint"], link["theta_deg"] = "prismatic", link.pop("offset_deg")
            del link["d"], link["q_limits_deg"], link["qd_max_deg"], link["qdd_max_deg"]
            link.update({"q_limits": [0.1, 1.0], "qd_max": 0.5, "qdd_max": 1.0})
    name = f"random-{n}" if "P" not in types else f"random-{types}"
    return robot_from_dict({"name": name, "gravity": [0.0, 0.0, -9.8062],
                            "link": links}, source=f"<random_chain({n}, {seed}, {types!r})>")


def _tau(D, h, c, qdd):
    """tau = D qdd + h + c, Eq. (3.2-26), on counting scalars; D (N, n, n), h, c, qdd (N, n).

    The counted mirror of :func:`gd_analyze.dynamics.dalembert.assemble_tau` (whose
    ``float`` conversion counting scalars refuse).
    """
    return (D @ qdd[..., None])[..., 0] + h + c


def _counted_transforms(robot, led, q, homogeneous=False):
    """^{i-1}R_i (1, n, 3, 3) and ^{i-1}p_i (1, n, 3) of counting scalars, by the very
    function the float code runs (:func:`~gd_analyze.model.kinematics.transforms_core`); or the
    homogeneous ^{i-1}T_i (1, n, 4, 4) with exact 0 and 1 in the last row."""
    n = robot.n
    q = np.asarray(q, dtype=float)[None]
    R, p = transforms_core(count_consts(led, robot.rotation), count_consts(led, robot.translation),
                           robot.prismatic, count_vars(led, np.cos(q)), count_vars(led, np.sin(q)),
                           count_vars(led, q))
    if not homogeneous:
        return R, p
    T = np.zeros((1, n, 4, 4), dtype=object)
    T[..., :3, :3] = R
    T[..., :3, 3] = p
    T[..., 3, 3] = 1
    return T


def _gd_mirror(R, o, pris, m, com, inertia, gravity, qd, qdd):
    """dalembert._gd_chunk and GDTerms.tau, step for step, for one set point.

    R (n, 3, 3), o (n, 3): body frames in the base frame; pris (n,) bools; m (n,); com (n, 3)
    and inertia (n, 3, 3) in the body frames; gravity (3,); qd, qdd (n,). Float or object
    arrays. Returns (tau, D_tran, D_rot, h_tran, h_rot, c).
    """
    n = len(m)
    dt = R.dtype
    zero3 = np.zeros(3, dtype=dt)
    z = [R[j][:, 2] for j in range(n)]
    zr = [zero3 if pris[j] else z[j] for j in range(n)]                 # z * (~pris)
    rbar = [o[s] + R[s] @ com[s] for s in range(n)]
    Ib = [(R[s] @ inertia[s]) @ R[s].T for s in range(n)]

    def suffix(x):                                            # _suffix_sum
        out = list(x)
        for s in range(n - 2, -1, -1):
            out[s] = out[s + 1] + x[s]
        return out

    def cumsum(x):
        out = list(x)
        for s in range(1, n):
            out[s] = out[s - 1] + x[s]
        return out

    def shift(x):
        return [zero3] + list(x[:-1])

    # D_tran: all n^2 Jacobian columns, then the mask j <= s, then einsum with m first
    Jv = np.zeros((n, n, 3), dtype=dt)
    for s in range(n):
        for j in range(n):
            col = ne_cross(z[j], rbar[s] - o[j])
            col = z[j] if pris[j] else col
            if j <= s:
                Jv[s, j] = col
    mJv = np.stack([m[s] * Jv[s] for s in range(n)])
    D_tran = np.einsum("sia,sja->ij", mJv, Jv)
    # D_rot: Ic_s zr_j for all s, j, then zr_i . Iz[max(i, j)][j]
    Ic = suffix(Ib)
    Iz = [[Ic[s] @ zr[j] for j in range(n)] for s in range(n)]
    D_rot = np.array([[zr[i] @ Iz[max(i, j)][j] for j in range(n)] for i in range(n)])
    # velocities and velocity-product accelerations
    wz = [qd[j] * zr[j] for j in range(n)]
    w = cumsum(wz)
    w_prev = shift(w)
    wd = cumsum([ne_cross(w_prev[s], wz[s]) for s in range(n)])
    wd_prev = shift(wd)
    o_prev = shift(o)
    dp = [o[s] - o_prev[s] for s in range(n)]
    slide = [(2.0 * ne_cross(w_prev[s], qd[s] * z[s])) * pris[s] for s in range(n)]
    ap = cumsum([ne_cross(wd_prev[s], dp[s]) + ne_cross(w_prev[s], ne_cross(w_prev[s], dp[s]))
                 + slide[s] for s in range(n)])
    rc = [rbar[s] - o[s] for s in range(n)]
    abar = [ap[s] + ne_cross(wd[s], rc[s]) + ne_cross(w[s], ne_cross(w[s], rc[s])) for s in range(n)]

    def along_axes(F):
        S = suffix(F)
        M = suffix([ne_cross(rbar[s], F[s]) for s in range(n)])
        M = [M[j] - ne_cross(o[j], S[j]) for j in range(n)]
        return np.array([z[j] @ (S[j] if pris[j] else M[j]) for j in range(n)])

    h_tran = along_axes([m[s] * abar[s] for s in range(n)])
    c = -along_axes([m[s] * gravity for s in range(n)])
    Iw = [Ib[s] @ w[s] for s in range(n)]
    f = [Ib[s] @ wd[s] + ne_cross(w[s], Iw[s]) for s in range(n)]
    fs = suffix(f)
    h_rot = np.array([zr[j] @ fs[j] for j in range(n)])
    D = D_tran + D_rot                                        # GDTerms.D, .h, .tau
    h = h_tran + h_rot
    tau = np.einsum("ij,j->i", D, qdd) + h + c
    return tau, D_tran, D_rot, h_tran, h_rot, c


def _gd_kernel_counted(robot, led, q, qd):
    """Run the compiled G-D engine's Python source on one set point of counting scalars.

    Returns (D_tran, D_rot, h_tran, h_rot, c) as object arrays of shapes (n, n) and (n,).
    The kernel's module runs as Python (:func:`.counting.python_kernels`): counting never
    imports numba.
    """
    kernel = counting_clone(python_kernels("gd_analyze.dynamics.kernels")["gd_kernel"])
    n = robot.n
    out = [np.zeros((1, n, n), dtype=object), np.zeros((1, n, n), dtype=object)]
    out += [np.zeros((1, n), dtype=object) for _ in range(3)]
    # q is the input: cos q and sin q are not counted (the rule)
    kernel(count_vars(led, q)[None], qd, count_consts(led, robot.rotation),
           count_consts(led, robot.translation), np.asarray(robot.prismatic, dtype=np.int64),
           count_consts(led, robot.mass), count_consts(led, robot.body_com),
           count_consts(led, robot.body_inertia), count_consts(led, robot.gravity), *out)
    return tuple(x[0] for x in out)


def count_operations(robot: Robot, method: str, q: ArrayLike | None = None,
                     qd: ArrayLike | None = None, qdd: ArrayLike | None = None) -> OpCount:
    """Run one formulation on one set point of counting scalars.

    Parameters
    ----------
    robot : Robot
        The arm, with n revolute joints.
    method : {"lagrange-euler", "newton-euler", "gd", "gd-numpy"}
        The implementation: ``"gd"`` is the compiled G-D engine, ``"gd-numpy"`` the array one.
    q, qd, qdd : array_like, shape (n,), optional
        The set point [rad], [rad/s], [rad/s^2]; random if omitted (the counts do not depend on
        it).

    Returns
    -------
    OpCount
        ``multiplications`` and ``additions`` (int) for one set point, and ``tau`` (ndarray,
        shape (n,)) [N m], the torques the counted run computed.

    Raises
    ------
    ValueError
        If method is unknown or a state does not have shape (n,).

    Notes
    -----
    The counting rule is in the module docstring. L-E computes tau by Eqs. (3.2-26) to
    (3.2-34), N-E by Table 3.3 (Eqs. (3.3-50) to (3.3-58)), G-D by Eqs. (3.4-24) to (3.4-28) as
    :func:`~gd_analyze.dynamics.dalembert.gd_terms` evaluates them.
    """
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    n = robot.n
    rng = np.random.default_rng(1)
    q, qd, qdd = (rng.uniform(-1, 1, n) if x is None else x for x in (q, qd, qdd))
    q, qd, qdd = (x[0] for x in as_states(robot, q, qd, qdd))
    led = OpLedger()
    qd_c, qdd_c = count_vars(led, qd)[None], count_vars(led, qdd)[None]
    if method == "lagrange-euler":
        J, gm, rbar = _le_constants(robot)
        gm = np.concatenate([count_consts(led, gm[:, :3]), np.zeros((n, 1), dtype=object)], axis=1)
        rbar = np.concatenate([count_consts(led, rbar[:, :3]), np.ones((n, 1), dtype=object)], axis=1)
        A = _counted_transforms(robot, led, q, homogeneous=True)
        D, _, h, c = le_core(A, joint_q_matrices(robot), count_consts(led, J), gm, rbar, qd_c)
        tau = _tau(D, h, c, qdd_c)[0]
    elif method == "newton-euler":
        k = {key: count_consts(led, val) for key, val in link_constants(robot).items()}
        R, p = _counted_transforms(robot, led, q)
        tau = ne_core(R, p, robot.prismatic, qd_c, qdd_c, k)[0]
    elif method == "gd":
        D_tran, D_rot, h_tran, h_rot, c = _gd_kernel_counted(robot, led, q, qd_c)
        tau = _tau(D_tran + D_rot, h_tran + h_rot, c, qdd_c[0])   # GDTerms.D, .h and .tau
    else:
        Rr, pr = _counted_transforms(robot, led, q)
        R, o = [Rr[0, 0]], [pr[0, 0]]                         # kinematics.body_frames
        for i in range(1, n):
            o.append(o[-1] + R[-1] @ pr[0, i])
            R.append(R[-1] @ Rr[0, i])
        tau = _gd_mirror(np.array(R), np.array(o), robot.prismatic, count_consts(led, robot.mass),
                         count_consts(led, robot.body_com), count_consts(led, robot.body_inertia),
                         count_consts(led, robot.gravity), qd_c[0], qdd_c[0])[0]
    return OpCount(int(led.multiplications), int(led.additions),
                   np.array([count_value(t) for t in tau]))


#: The counts of :func:`count_chain` for revolute chains of 1 to 10 joints, per method of
#: :data:`METHODS`: (multiplications, additions). A fact of the code, counted once and kept
#: here (Table 3.5's rows of every report); ``tests/dynamics/test_opcount.py`` counts them
#: afresh and fails when the code's operations change without this table.
REVOLUTE_COUNTS: dict[int, tuple[tuple[int, int], ...]] = {
    1: ((84, 47), (38, 22), (160, 121), (151, 110)),
    2: ((532, 361), (147, 105), (412, 343), (442, 346)),
    3: ((1632, 1182), (281, 211), (693, 588), (801, 639)),
    4: ((3738, 2822), (415, 317), (985, 844), (1222, 983)),
    5: ((7276, 5665), (549, 423), (1288, 1111), (1711, 1384)),
    6: ((12744, 10167), (683, 529), (1602, 1389), (2274, 1848)),
    7: ((20712, 16856), (817, 635), (1927, 1678), (2917, 2381)),
    8: ((31822, 26332), (951, 741), (2263, 1978), (3646, 2989)),
    9: ((46788, 39267), (1085, 847), (2610, 2289), (4467, 3678)),
    10: ((66396, 56405), (1219, 953), (2968, 2611), (5386, 4454)),
}


@cache
def _counts_for(types):
    """Counts of every method for a chain with joint types ``types``: from
    :data:`REVOLUTE_COUNTS` for a revolute chain it holds, else counted on a
    :func:`random_chain` with those types (a few milliseconds for six joints), once per
    process."""
    if "P" not in types and len(types) in REVOLUTE_COUNTS:
        return dict(zip(METHODS, REVOLUTE_COUNTS[len(types)]))
    return count_chain(types)


def count_chain(types: str) -> dict[str, tuple[int, int]]:
    """Count every method's operations on a random chain, afresh.

    Parameters
    ----------
    types : str
        The joint types, one of "R" or "P" per joint (e.g. "RRPRRR").

    Returns
    -------
    dict
        ``{method: (multiplications, additions)}`` for the methods in :data:`METHODS`, counted
        by :func:`count_operations` on a :func:`random_chain` with those joint types.

    Raises
    ------
    ValueError
        If ``types`` is empty or holds a letter other than R and P.
    """
    if not types or set(types) - {"R", "P"}:
        raise ValueError(f"joint types must be a non-empty string of R and P, got {types!r}")
    robot = random_chain(len(types), types=types)
    counts = {m: count_operations(robot, m) for m in METHODS}
    return {m: (int(c.multiplications), int(c.additions)) for m, c in counts.items()}


def operation_counts(robot_or_n: Robot | int) -> dict[str, Any]:
    """Multiplications and additions per set point of each formulation, as implemented.

    Parameters
    ----------
    robot_or_n : Robot or int
        The arm, or a number of joints n (n revolute joints, as in Table 3.5). A
        :func:`random_chain` with the arm's joint types (:func:`joint_types`) is counted: the
        counts depend on n and the joint types only, so every arm gets one count.

    Returns
    -------
    dict
        ``{method: {"multiplications": int, "additions": int}}`` for the methods in
        :data:`METHODS`.

    Raises
    ------
    ValueError
        If n < 1.
    TypeError
        If robot_or_n is neither a Robot nor an int.

    Notes
    -----
    Counting rule in the module docstring; :func:`book_counts` gives Table 3.5's figures of
    Fu, Gonzalez & Lee (1987) for comparison.
    """
    if isinstance(robot_or_n, Robot):
        counts = _counts_for(joint_types(robot_or_n))
    elif isinstance(robot_or_n, numbers.Integral):
        if robot_or_n < 1:
            raise ValueError(f"n must be >= 1, got {robot_or_n}")
        counts = _counts_for("R" * int(robot_or_n))
    else:
        raise TypeError(f"expected a Robot or an int, got {type(robot_or_n).__name__}")
    return {m: {"multiplications": mu, "additions": ad} for m, (mu, ad) in counts.items()}


def _poly(coeffs, n):
    value = sum(c * Fr(n) ** (len(coeffs) - 1 - p) for p, c in enumerate(coeffs))
    return int(value) if value.denominator == 1 else float(value)


def book_counts(n: int) -> dict[str, Any]:
    """The operation counts of Table 3.5 (Fu, Gonzalez & Lee 1987) for an n-joint arm.

    Parameters
    ----------
    n : int
        Number of joints, >= 1.

    Returns
    -------
    dict
        ``{method: {"multiplications": number, "additions": number}}`` for the methods in
        :data:`METHODS` (int where the formula gives a whole number; both G-D engines get the
        G-D formulas).

    Raises
    ------
    ValueError
        If n < 1.
    """
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    out = {m: {op: _poly(c, n) for op, c in ops.items()} for m, ops in TABLE_3_5.items()}
    out["gd-numpy"] = dict(out["gd"])
    return out


def table(n_max: int = 10) -> pd.DataFrame:
    """Measured operation counts beside Table 3.5, for n = 1..n_max.

    Parameters
    ----------
    n_max : int, optional
        Largest number of joints, >= 1.

    Returns
    -------
    pandas.DataFrame
        Index ``n``; for each of L-E, N-E and G-D (compiled engine) the columns
        ``"<abbr> mul"``, ``"<abbr> mul T3.5"``, ``"<abbr> add"`` and ``"<abbr> add T3.5"``
        (measured counts as implemented, and Table 3.5's formulas), then ``"G-D np mul"`` and
        ``"G-D np add"`` for the numpy G-D engine.

    Raises
    ------
    ValueError
        If n_max < 1.
    """
    import pandas as pd

    if n_max < 1:
        raise ValueError(f"n_max must be >= 1, got {n_max}")
    abbr = {"lagrange-euler": "L-E", "newton-euler": "N-E", "gd": "G-D", "gd-numpy": "G-D np"}
    rows = []
    for n in range(1, n_max + 1):
        got, book = operation_counts(n), book_counts(n)
        row = {"n": n}
        for m in METHODS:
            for op, short in (("multiplications", "mul"), ("additions", "add")):
                row[f"{abbr[m]} {short}"] = got[m][op]
                if m != "gd-numpy":
                    row[f"{abbr[m]} {short} T3.5"] = book[m][op]
        rows.append(row)
    return pd.DataFrame(rows).set_index("n")
