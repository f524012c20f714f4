"""The chapter's closed forms of the planar two-link arm of uniform rods (Fu, Gonzalez & Lee
1987, Sec. 3.2.6, Eqs. (3.2-37) to (3.2-40), and the G-D split of Sec. 3.4.2), for any link
masses m1, m2, a common length l and gravity g along -y of the base frame; and the robot-file
dictionary of that arm, written out by hand (not taken from the tool)."""

import numpy as np


def spec(m1=1.0, m2=1.0, l=1.0, g=9.8062, name="two-link-test"):
    """The standard-DH robot file of the arm: rods along x of link frame i, centre of mass at
    (-l/2, 0, 0), I = diag(0, m l^2/12, m l^2/12) about it."""
    links = [{"d": 0.0, "a": l, "alpha_deg": 0.0, "mass": m, "com": [-l / 2, 0.0, 0.0],
              "inertia": [0.0, m * l * l / 12, m * l * l / 12], "q_limits_deg": [-180, 180],
              "qd_max_deg": 180.0, "qdd_max_deg": 360.0} for m in (m1, m2)]
    return {"name": name, "gravity": [0.0, -g, 0.0], "link": links}


def terms(q, qd, m1=1.0, m2=1.0, l=1.0, g=9.8062):
    """D_tran, D_rot (N, 2, 2) [kg m^2], h_tran, h_rot, c (N, 2) [N m] in closed form.

    D, h, c: Eqs. (3.2-37) to (3.2-40). D_rot is the rods' own rotational inertias about
    their centres (I_1 + I_2, I_2, I_2 with I_i = m_i l^2/12); D_tran = D - D_rot. The arm
    turns about z only, so w x (I w) = 0 and h_rot = 0.
    """
    q, qd = np.atleast_2d(q), np.atleast_2d(qd)
    C1, C2, S2 = np.cos(q[:, 0]), np.cos(q[:, 1]), np.sin(q[:, 1])
    C12 = np.cos(q[:, 0] + q[:, 1])
    L2 = l * l
    N = q.shape[0]
    D = np.empty((N, 2, 2))
    D[:, 0, 0] = m1 * L2 / 3 + 4 * m2 * L2 / 3 + m2 * C2 * L2
    D[:, 0, 1] = D[:, 1, 0] = m2 * L2 / 3 + m2 * L2 * C2 / 2
    D[:, 1, 1] = m2 * L2 / 3
    D_rot = np.empty((N, 2, 2))
    D_rot[:] = np.array([[(m1 + m2) * L2 / 12, m2 * L2 / 12], [m2 * L2 / 12, m2 * L2 / 12]])
    h = np.stack([-m2 * S2 * L2 * qd[:, 0] * qd[:, 1] - m2 * S2 * L2 * qd[:, 1] ** 2 / 2,
                  m2 * S2 * L2 * qd[:, 0] ** 2 / 2], axis=1)
    c = np.stack([m1 * g * l * C1 / 2 + m2 * g * l * C12 / 2 + m2 * g * l * C1,
                  m2 * g * l * C12 / 2], axis=1)
    return D - D_rot, D_rot, h, np.zeros_like(h), c
