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
