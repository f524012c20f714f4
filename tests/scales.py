"""The project's error scale in tests: an error is relative to the quantity's own scale.

For a joint torque the scale is the joint's peak |tau_i| over the set points (DEVELOPERS'
guide, "Scales"); NaN and inf never pass.
"""

from __future__ import annotations

import numpy as np


def joint_relative_error(tau, ref):
    """Largest |tau - ref| over set points and joints, each joint by its peak |ref_i|.

    Parameters
    ----------
    tau, ref : ndarray, shape (N, n)
        Torques to compare and the reference [N m or N].

    Returns
    -------
    float
        max_i max_k |tau_ki - ref_ki| / max_k |ref_ki|.

    Raises
    ------
    AssertionError
        If a joint's reference is 0 at every set point (no scale) or the error is not finite.
    """
    scale = np.abs(ref).max(axis=0)
    assert (scale > 0).all()
    err = np.abs(tau - ref).max(axis=0) / scale
    assert np.isfinite(err).all()
    return float(err.max())


def identity_errors(ns, q, qd, qdd):
    """How far a deployed model's functions are from its identities.

    Parameters
    ----------
    ns : mapping
        The emitted numpy module's namespace: ``tau``, ``inertia``, ``velocity_terms``,
        ``gravity``, ``regressor`` and ``BASE_PARAMETERS``.
    q, qd, qdd : ndarray, shape (N, n)
        States [rad, rad/s, rad/s^2; m, m/s, m/s^2].

    Returns
    -------
    (float, float)
        max |D qdd + h + c - tau| and max |Y beta - tau|, each joint by its peak |tau_i|.
    """
    tau = ns["tau"](q, qd, qdd)
    parts = np.einsum("kij,kj->ki", ns["inertia"](q), qdd) + ns["velocity_terms"](q, qd) \
        + ns["gravity"](q)
    ybeta = np.einsum("kib,b->ki", ns["regressor"](q, qd, qdd), ns["BASE_PARAMETERS"])
    return joint_relative_error(parts, tau), joint_relative_error(ybeta, tau)
