"""Ordinary and weighted least squares with identifiability and standard deviations.

On the stacked rows (sample, joint) that enter the fit, kept per joint i as the triangular
factor R_i of [A_i | y_i] (the QR decomposition, so that no step needs the whole regressor in
memory and the per-joint weights of step 3 apply to the factors: ||w_i (A_i x - y_i)||^2 =
w_i^2 ||R_i [x; -1]||^2):

1. The columns are scaled to unit norm; a QR decomposition with column pivoting
   (``scipy.linalg.qr(pivoting=True)``; Golub & Van Loan, *Matrix Computations*, Sec. 5.4.2)
   finds the columns the data identify: the pivoted diagonal |R_kk| above
   :data:`RANK_TOL` x |R_00|. The others are *not identifiable on these data*: they are
   reported by name and kept at the prior's value (moved to the right-hand side), never
   silently dropped.
2. Ordinary least squares on the identifiable columns; the per-joint noise variance
   sigma_i^2 = ||r_i||^2 / (N_i (1 - p / M)) (M rows, p parameters).
3. Weighted least squares with the rows of joint i divided by sigma_i (Gautier & Poignet 2001),
   the covariance c s^2 (A_w^T A_w)^-1 with s^2 = ||r_w||^2 / (M - p) and c the rows per
   independent noise sample (a filtered noise's samples are correlated), and the standard
   deviations its diagonal's square roots.
4. The condition number of the column-scaled, weighted regressor: the ratio of its extreme
   singular values.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from scipy import linalg

from ..dynamics.base_parameters import one_blas_thread

__all__ = ["Estimate", "least_squares", "joint_factors", "combine_factors", "RANK_TOL",
           "QR_BLOCK"]

#: A pivoted column is identifiable when |R_kk| > RANK_TOL |R_00| (scaled columns).
RANK_TOL = 1e-6


@dataclass(frozen=True, eq=False)
class Estimate:
    """The least-squares estimate.

    Attributes
    ----------
    value : ndarray, shape (p,)
        Weighted least squares; prior values where not identifiable.
    std : ndarray, shape (p,)
        Standard deviations (0 where not identifiable).
    ols_value : ndarray, shape (p,)
        Ordinary least squares.
    identifiable : ndarray of bool, shape (p,)
    noise_std : ndarray, shape (n,)
        sigma_i, the residual standard deviation of joint i in the ordinary fit.
    condition_number : float
        Of the column-scaled, weighted regressor on the identifiable columns.
    rank : int
    R : ndarray, shape (r, r)
        The triangular factor of the weighted regressor on the identifiable columns (unscaled):
        ||A_w (theta - value)||^2 = ||R (theta_id - value_id)||^2 for the identifiable part.
    """

    value: np.ndarray
    std: np.ndarray
    ols_value: np.ndarray
    identifiable: np.ndarray
    noise_std: np.ndarray
    condition_number: float
    rank: int
    R: np.ndarray


#: Rows per block of the blocked QR of :func:`joint_factors` (at least 4 (p + 1)).
QR_BLOCK = 2048


def joint_factors(Y: npt.NDArray[np.float64], tau: npt.NDArray[np.float64],
                  used: npt.NDArray[np.bool_]) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]:
    """Per joint the triangular factor of [A_i | y_i] over the rows that enter the fit.

    Parameters
    ----------
    Y : ndarray, shape (N, n, p)
        The regressor [N m per unit parameter].
    tau : ndarray, shape (N, n)
        Measured torques [N m or N].
    used : ndarray of bool, shape (N, n)
        The rows that enter the fit.

    Returns
    -------
    R : ndarray, shape (n, p + 1, p + 1)
        R_i with Q_i R_i = [A_i | y_i] (zero-padded when joint i has fewer than p + 1 rows).
    counts : ndarray of int, shape (n,)
        Rows per joint.

    Notes
    -----
    A blocked (tall-skinny) QR: R of the first block of :data:`QR_BLOCK` rows, then R of
    [R; next block], and so on (Demmel, Grigori, Hoemmen & Langou, "Communication-optimal
    parallel and sequential QR and LU factorizations", SIAM J. Sci. Comput. 34(1), 2012):
    the same R up to the rows' signs, each block in cache, on one BLAS thread (a busy machine's
    threads make one large QR several times slower).
    """
    N, n, p = Y.shape
    R = np.zeros((n, p + 1, p + 1))
    counts = np.zeros(n, int)
    tau = np.asarray(tau, float)
    step = max(QR_BLOCK, 4 * (p + 1))
    with one_blas_thread():
        for i in range(n):
            rows = np.flatnonzero(np.asarray(used[:, i], bool))
            counts[i] = rows.size
            r = None
            for a in range(0, rows.size, step):
                blk = rows[a:a + step]
                M = np.empty((blk.size + (0 if r is None else r.shape[0]), p + 1), order="F")
                k = 0 if r is None else r.shape[0]
                if r is not None:
                    M[:k] = r
                M[k:, :p] = Y[blk, i, :]
                M[k:, p] = tau[blk, i]
                r = linalg.qr(M, mode="r", overwrite_a=True, check_finite=False)[0][:p + 1]
            if r is not None:
                R[i, :r.shape[0]] = r
    return R, counts


def combine_factors(a: tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]],
                    b: tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]:
    """The factors of two sets of rows stacked: per joint R of [R_a; R_b].

    Parameters
    ----------
    a, b : tuple (R, counts)
        From :func:`joint_factors`.

    Returns
    -------
    tuple (R, counts)
    """
    Ra, ca = a
    Rb, cb = b
    out = np.empty_like(Ra)
    with one_blas_thread():
        for i in range(Ra.shape[0]):
            out[i] = linalg.qr(np.vstack([Ra[i], Rb[i]]), mode="r", check_finite=False)[0][
                :Ra.shape[1]]
    return out, ca + cb


def least_squares(factors: tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]],
                  prior: npt.NDArray[np.float64], correlation: float = 1.0) -> Estimate:
    """Ordinary then weighted least squares (steps in the module docstring).

    Parameters
    ----------
    factors : tuple (R, counts)
        Per joint the factor of [A_i | y_i] and its row count (:func:`joint_factors`,
        :func:`combine_factors`).
    prior : ndarray, shape (p,)
        The prior values, kept for the columns the data do not identify.
    correlation : float, optional
        Rows per independent noise sample, c >= 1 (the filter's,
        :attr:`.preprocess.Preprocessed.correlation`): the covariance is c times that of
        independent rows.

    Returns
    -------
    Estimate

    Raises
    ------
    ValueError
        If no more rows than identifiable parameters enter the fit.
    """
    with one_blas_thread():     # small factors: threads only cost
        return _least_squares(factors, prior, correlation)


def _least_squares(factors, prior, correlation):
    """:func:`least_squares`' work, on the calling thread's BLAS."""
    Rj, counts = factors
    n, p1, _ = Rj.shape
    p = p1 - 1
    M = int(counts.sum())
    prior = np.asarray(prior, float)
    R = linalg.qr(Rj.reshape(n * p1, p1), mode="r", check_finite=False)[0][:p1]
    norms = np.linalg.norm(R[:, :p], axis=0)
    live = norms > 0
    scale = np.where(live, norms, 1.0)
    R0, piv = linalg.qr(R[:p, :p] / scale, mode="r", pivoting=True, check_finite=False)
    diag = np.abs(np.diag(R0))
    ok = np.zeros(p, bool)
    if diag.size and diag[0] > 0:
        ok[piv[diag > RANK_TOL * diag[0]]] = True
    ok &= live
    r = int(ok.sum())
    if M <= r:
        raise ValueError(f"{M} rows enter the fit, not more than the {r} identifiable "
                         f"parameters")

    def reduced(Rm):
        """[A_ok | y - A_fixed prior] in the factor's coordinates."""
        return np.hstack([Rm[:, :p][:, ok], (Rm[:, p] - Rm[:, :p][:, ~ok] @ prior[~ok])[:, None]])

    Rr = reduced(R)
    x_ols = linalg.lstsq(Rr[:, :r] / scale[ok], Rr[:, r], check_finite=False)[0] / scale[ok]
    xe = np.concatenate([x_ols, [-1.0]])
    ss = np.array([float(np.sum((reduced(Rj[i]) @ xe) ** 2)) for i in range(n)])
    yy = np.array([float(np.sum(reduced(Rj[i])[:, r] ** 2)) for i in range(n)])
    dof = np.maximum(counts * (1.0 - r / M), 1.0)
    sigma = np.sqrt(ss / dof)
    y_scale = np.sqrt(yy / np.maximum(counts, 1))
    floor = 1e-13 * np.maximum(y_scale, y_scale.max(initial=0.0)) + 1e-300
    w = 1.0 / np.maximum(sigma, floor)
    Rw = linalg.qr(np.vstack([w[i] * reduced(Rj[i]) for i in range(n)]), mode="r",
                   check_finite=False)[0][:r + 1]
    wscale = np.linalg.norm(Rw[:, :r], axis=0)
    wscale = np.where(wscale > 0, wscale, 1.0)
    Ru = Rw[:r, :r] / wscale
    x_scaled = linalg.solve_triangular(Ru, Rw[:r, r], check_finite=False)
    x_wls = x_scaled / wscale
    s2 = correlation * float(Rw[r, r] ** 2) / (M - r)
    Rinv = linalg.solve_triangular(Ru, np.eye(r), check_finite=False)
    std = np.sqrt(s2 * np.sum(Rinv ** 2, axis=1)) / wscale
    sv = np.linalg.svd(Ru, compute_uv=False)
    cond = float(sv[0] / sv[-1]) if sv[-1] > 0 else float("inf")
    value, std_all, ols = prior.copy(), np.zeros(p), prior.copy()
    value[ok], std_all[ok], ols[ok] = x_wls, std, x_ols
    return Estimate(value=value, std=std_all, ols_value=ols, identifiable=ok, noise_std=sigma,
                    condition_number=cond, rank=r, R=Rw[:r, :r])
