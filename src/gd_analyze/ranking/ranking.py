"""Dominance ranking of the G-D terms along a trajectory, Sec. 3.4.1.

The elements ranked are the upper triangle of D (i <= j; 21 for n = 6), labelled ``"D11"`` ..
``"D66"``, and the n elements of h, labelled ``"h1"`` .. ``"hn"`` (:mod:`gd_analyze.ranking.labels`,
re-exported here). For each element, with k
running over the set points::

    share_tran = sum_k |tran_k| / (sum_k |tran_k| + sum_k |rot_k|)

and the element's class is

- ``"negligible"`` if its peak |tran + rot| along the trajectory is below e times its scale:
  the peak of sqrt(D_ii D_jj) for D_ij, the peak |tau_i| for h_i;
- else ``"translational"`` if share_tran >= s, ``"rotational"`` if share_tran <= 1 - s,
  ``"both"`` otherwise.

An element zero to rounding (:func:`identically_zero`: every part below 1e-12 of its scale)
is ``"negligible"`` whatever e, and has no share to speak of: the reports print it as "≡ 0".

The chapter reads the same classes off its Figs. 3.10 and 3.11 by eye; s (default 0.9) and e
(default 0.01) make the reading reproducible.

Drives (:mod:`gd_analyze.model.drives`): the armature Ia_i adds a third part, D_arm = diag(Ia),
to the diagonal elements D_ii only. It is rotational inertia about the joint axis (a rotor's),
which the chapter's PUMA data lump into the links' rotational inertias, so it counts on the
rotational side of the share::

    share_tran = sum_k |tran_k| / (sum_k |tran_k| + sum_k |rot_k + arm_k|)
    share_arm  = sum_k |arm_k|  / (sum_k |tran_k| + sum_k |rot_k + arm_k|)

and the peak and the scale of D_ii include it. An element is thus "rotational" when rotor and
link rotation together dominate; ``share_arm`` tells how much of that is the rotor. The
simplified model always keeps the armature whole (one multiplication and one addition per
joint), whatever the element's class.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..config import ROUND_OFF, ROUND_OFF_EPS, defaults
from ..model.drives import has_drives
from .labels import (
    element_index,
    element_label,
    element_labels,
    element_units,
    joint_motion_units,
    joint_torque_units,
    joint_units_text,
    parse_element_label,
)
from .segments import chunk_segments
from .statistics import ROWS, row

if TYPE_CHECKING:                       # for the type hints only
    from numpy.typing import NDArray

    from ..dynamics.dalembert import GDTerms
    from ..model.robot import Robot

__all__ = [
    "CLASSES", "DEFAULT_DOMINANCE", "DEFAULT_NEGLIGIBLE", "Ranking", "element_labels",
    "element_index", "element_label", "parse_element_label", "rank_dominance",
    "CHAPTER_DOMINANCE", "CHAPTER_PUMA", "is_chapter_puma", "element_units",
    "joint_torque_units", "joint_motion_units",
    "joint_units_text", "ROUND_OFF", "ROUND_OFF_EPS", "ROUND_OFF_CLAUSE", "arm_scales", "is_round_off", "ZERO_TOL",
    "identically_zero",
]

#: An element whose parts all stay below this fraction of its scale is zero to rounding.
ZERO_TOL = 1e-12


def identically_zero(peak_tran, peak_rot, peak_total, scale, tol=ZERO_TOL):
    """Which elements are zero to rounding in every part along the trajectory.

    Parameters
    ----------
    peak_tran, peak_rot, peak_total : ndarray, shape (M,) or (K, M)
        Peak |part| of each element over the set points (of each of K trajectories, each
        judged on its own); M = n (n + 1) / 2 + n (D's upper triangle, then h) or any M
        (each element on its own scale only).
    scale : ndarray, shape (M,) or (K, M)
        Each element's own scale (peak sqrt(D_ii D_jj) [kg m^2] or peak |tau_i| [N m]).
    tol : float, optional
        The fraction of the scale below which a part counts as zero.

    Returns
    -------
    ndarray of bool, shape (M,) or (K, M)
        True where all three peaks are <= tol * scale, or at most :data:`ROUND_OFF_EPS`
        machine epsilons of the largest scale of its kind, D or h (the arm's floor of
        :func:`is_round_off`: the rounding of sums over the whole chain). Where the scale is
        itself rounding (below tol times the largest scale of its kind: a joint that moves no
        inertia, whose D_ii is 1e-34), the largest scale of the kind stands for it. The floor
        matters where D_jj is rounding but not tiny: D_ij's scale sqrt(D_ii D_jj) is then far
        above D_jj, and tol times it far below D_ij's rounding (a point-mass last link on its
        axis: D_66 = 1.4e-17, D_16 = 6.9e-18 against sqrt(3.7 x 1.4e-17) = 7e-9 kg m^2).

    Examples
    --------
    >>> import numpy as np
    >>> identically_zero(np.array([1e-19, 0.2]), np.array([2e-19, 0.1]),
    ...                  np.array([1e-19, 0.3]), np.array([1.0, 1.0])).tolist()
    [True, False]

    A two-joint arm (D11, D12, D22, h1, h2) whose D_22 of 2.5e-34 is measured on a scale of
    its own size is rounding beside D_11 = 3.6:

    >>> peak = np.array([3.6, 0.1, 2.5e-34, 1.0, 0.5])
    >>> identically_zero(peak, np.zeros(5), peak,
    ...                  np.array([3.6, 0.5, 2.5e-34, 5.0, 5.0])).tolist()
    [False, False, True, False, False]
    """
    scale = np.abs(np.asarray(scale, dtype=float))
    ref = scale.copy()
    floor = np.zeros_like(scale)
    m = scale.shape[-1] if scale.ndim else 0
    n = int(round((-3 + np.sqrt(9 + 8 * m)) / 2)) if m else 0
    if n * (n + 3) // 2 == m and m:
        for part in (slice(0, m - n), slice(m - n, m)):
            big = np.max(scale[..., part], axis=-1, initial=0.0, keepdims=True)
            ref[..., part] = np.where(scale[..., part] <= tol * big, big, scale[..., part])
            floor[..., part] = ROUND_OFF_EPS * np.finfo(float).eps * big
    peak = np.fmax(np.fmax(np.abs(peak_tran), np.abs(peak_rot)), np.abs(peak_total))
    return np.asarray(peak <= np.maximum(tol * ref, floor)) & np.isfinite(peak)

#: The dominance classes, in the order used for codes in files.
CLASSES = ("translational", "rotational", "both", "negligible")
#: Default dominance threshold s (:data:`gd_analyze.config.defaults`).
DEFAULT_DOMINANCE = defaults["dominance"]
#: Default negligibility threshold e (:data:`gd_analyze.config.defaults`).
DEFAULT_NEGLIGIBLE = defaults["negligible"]

#: How every text that calls a bound guaranteed says the round-off it allows;
#: :func:`gd_analyze.simplify.guarantee.within_bound` judges by the same allowance.
ROUND_OFF_CLAUSE = f"up to floating-point round-off ({ROUND_OFF_EPS:g} eps of the scale)"


def arm_scales(scale, units):
    """Each quantity's arm scale: the largest finite scale among the quantities in its units.

    Parameters
    ----------
    scale : array_like, shape (M,) or (K, M)
        Each quantity's own scale (peak |tau_i| [N m or N] per joint, or peak sqrt(D_ii D_jj)
        per element of D), of one trajectory or of each of K (each row on its own).
    units : sequence of str, shape (M,)
        Each quantity's units: the quantities of one kind and units share one arm scale (the
        joints of one type, D_ij of the same units).

    Returns
    -------
    ndarray, shape (M,) or (K, M)
        NaN where no quantity of those units has a finite scale.

    Examples
    --------
    >>> arm_scales([2.0, 5e-4, 90.0], ["N m", "N m", "N"]).tolist()
    [2.0, 2.0, 90.0]
    """
    scale = np.abs(np.asarray(scale, dtype=float))
    units = np.asarray([str(u) for u in units])
    out = np.full(scale.shape, np.nan)
    for u in dict.fromkeys(units.tolist()):
        same = units == u
        finite = np.isfinite(scale[..., same])
        top = np.max(np.where(finite, scale[..., same], -np.inf), axis=-1, keepdims=True)
        out[..., same] = np.where(finite.any(axis=-1, keepdims=True), top, np.nan)
    return out


def is_round_off(peak, scale, tol=ROUND_OFF, arm_scale=None):
    """Whether a quantity is floating-point round-off.

    The one rule by which the reports, the command line and the stored model tell round-off
    from data: an element, a joint's torque error or a tracking error whose peak is at most
    ``tol`` times its own scale, or at most :data:`ROUND_OFF_EPS` machine epsilons of the arm's
    scale, is never drawn or tabulated as data.

    Why the second term: round-off is not set by a quantity's own size but by the terms it is
    computed from. The G-D engine sums moments about the base origin and subtracts o_j x S_j
    (Eq. (3.4-25)), and both it and the recursive model run over the whole chain; their
    rounding is a few eps times the arm's largest torques (the verification's absolute floor,
    64 eps of the overall scale), even for a joint whose own torque is small. The Stanford
    arm's joint 6 (peak |tau_6| 5.8e-4 N m) and the PUMA 560's (1.2e-4 N m) differ between two
    exact models by 2e-16 to 9e-16 N m: 1.5e-12 to 1.8e-12 of their own scale, above
    :data:`ROUND_OFF`, but 3e-4 to 4e-4 of 64 eps times the arm's 200 N m or 42 N m. A joint whose
    whole torque is round-off (its own scale itself below the floor) is so judged against the
    arm, never against its own noise.

    Parameters
    ----------
    peak : array_like, shape (M,) or scalar
        Peak |value| of each quantity (any units).
    scale : array_like, shape (M,) or scalar
        Each quantity's own scale, in the same units: peak sqrt(D_ii D_jj) [kg m^2] for D_ij,
        peak |tau_i| [N m] (or [N]) for h_i and for joint i's torque error, the motion's
        range [rad] for a tracking error.
    tol : float, optional
        The fraction of the own scale (default :data:`ROUND_OFF`).
    arm_scale : array_like, shape (M,) or scalar, optional
        The arm's scale of each quantity, in the same units (:func:`arm_scales`); no absolute
        floor if omitted or NaN.

    Returns
    -------
    ndarray of bool, shape (M,) (0-d for scalars)
        True where ``peak <= max(tol * |scale|, ROUND_OFF_EPS * eps * |arm_scale|)`` and the
        peak is finite; NaN or inf never counts as round-off. A zero scale (and no arm scale)
        makes only an exactly zero peak round-off.

    Examples
    --------
    >>> is_round_off([1e-19, 0.2, np.nan, 0.0], [1.0, 1.0, 1.0, 0.0]).tolist()
    [True, False, False, True]

    Stanford joint 6: 8.5e-16 N m on its own 5.8e-4 N m is not round-off by the first term,
    but is beside the arm's 199.6 N m; a real error of 1e-9 N m stays data:

    >>> is_round_off([8.5e-16, 1e-9], [5.8e-4, 5.8e-4]).tolist()
    [False, False]
    >>> is_round_off([8.5e-16, 1e-9], [5.8e-4, 5.8e-4], arm_scale=199.6).tolist()
    [True, False]
    """
    peak = np.abs(np.asarray(peak, dtype=float))
    scale = np.abs(np.asarray(scale, dtype=float))
    limit = tol * np.where(np.isfinite(scale), scale, 0.0)
    if arm_scale is not None:
        arm = np.abs(np.asarray(arm_scale, dtype=float))
        floor = ROUND_OFF_EPS * np.finfo(float).eps * np.where(np.isfinite(arm), arm, 0.0)
        limit = np.maximum(limit, floor)
    with np.errstate(invalid="ignore"):
        return np.asarray((peak <= limit) & np.isfinite(peak))


#: The dominance the chapter reports for its PUMA 560 trajectory (Sec. 3.4.1, Figs. 3.10-3.11).
CHAPTER_DOMINANCE = {
    **{k: "translational" for k in ("D11", "D12", "D13", "D22", "D23", "D33")},
    **{k: "rotational" for k in ("D44", "D46", "D55", "D66")},
    **{k: "both" for k in ("D14", "D15", "D16", "D24", "D25", "D26", "D34", "D35", "D36",
                           "D45", "D56")},
    "h1": "translational", "h2": "translational", "h3": "translational",
    "h4": "rotational", "h5": "both", "h6": "both",
}
#: The built-in robots that are the chapter's PUMA 560 arm: its links alone, and with the
#: Robotics Toolbox's drives (``data/puma560-drives.toml``).
CHAPTER_PUMA = ("puma560", "puma560-drives")


def is_chapter_puma(name, n=6):
    """Whether a robot is the chapter's PUMA 560 (with or without its drives).

    Parameters
    ----------
    name : str
        The robot's name (case, spaces and hyphens ignored).
    n : int, optional
        Its number of joints.

    Returns
    -------
    bool

    Examples
    --------
    >>> is_chapter_puma("PUMA 560"), is_chapter_puma("puma560-drives"), is_chapter_puma("ur5")
    (True, True, False)
    """
    def key(text):
        return str(text).lower().replace(" ", "").replace("-", "")
    return n == 6 and key(name) in {key(k) for k in CHAPTER_PUMA}


@dataclass(frozen=True, eq=False)
class Ranking:
    """Dominance of the translational and rotational parts, per element.

    Attributes
    ----------
    labels : tuple of str, length M
        Element labels, M = n (n + 1) / 2 + n.
    share_tran : ndarray, shape (M,)
        Translational share along the trajectory, in [0, 1]; NaN where both parts are zero.
    dominance : tuple of str, length M
        The class of each element: one of :data:`CLASSES`.
    peak_tran, peak_rot, peak_total : ndarray, shape (M,)
        Peak |tran|, |rot| and |tran + rot| along the trajectory [kg m^2] for D, [N m] for h.
    scale : ndarray, shape (M,)
        The element's scale for the negligibility test: peak sqrt(D_ii D_jj) [kg m^2] or peak
        |tau_i| [N m].
    dominance_threshold : float
        s.
    negligible_threshold : float
        e.
    share_arm : ndarray, shape (M,) or None
        Armature share (module docstring), 0 off the diagonal of D; None for rankings made
        without the drives.
    peak_arm : ndarray, shape (M,) or None
        |armature| of the element [kg m^2] (0 off the diagonal of D and for h).
    rigid_dominance : tuple of str or None
        For an arm with drives, the classes of its rigid links alone (armature and friction
        left out, the chapter's model); None otherwise.
    """

    labels: tuple
    share_tran: np.ndarray
    dominance: tuple
    peak_tran: np.ndarray
    peak_rot: np.ndarray
    peak_total: np.ndarray
    scale: np.ndarray
    dominance_threshold: float
    negligible_threshold: float
    share_arm: np.ndarray | None = None
    peak_arm: np.ndarray | None = None
    rigid_dominance: tuple | None = None

    def choices(self):
        """The simplified model's choice per element.

        Returns
        -------
        dict
            label -> ``"tran"``, ``"rot"``, ``"both"`` or ``"none"`` (negligible).
        """
        code = {"translational": "tran", "rotational": "rot", "both": "both",
                "negligible": "none"}
        return {lab: code[c] for lab, c in zip(self.labels, self.dominance)}


#: Rows per block of the array code of :meth:`RankingAccumulator.update`.
_BLOCK = 8192


class RankingAccumulator:
    """Accumulate the ranking's sums and peaks chunk by chunk, then classify.

    Feeding a trajectory in chunks gives exactly the ranking of the whole: the share uses sums
    of |tran| and |rot|, the classes use peaks, both of which combine across chunks. With
    ``trajectories`` it ranks K trajectories at once, each chunk cut into segments of
    consecutive set points of one trajectory (a sweep's many short trajectories in one pass):
    each trajectory's ranking is the one it has alone, bit for bit.

    Parameters
    ----------
    n : int
        Number of joints.
    trajectories : int, optional
        K >= 1: the trajectories ranked at once. Without it one trajectory, and the arrays
        below have no leading trajectory axis.

    Attributes
    ----------
    stats : ndarray, shape (len(ROWS), M) or (K, len(ROWS), M)
        The running statistics of each element's series (tran, rot + arm, tran + rot + arm:
        sum |x|, sum x^2, peak |x|; and peak |rot|), row r being entry r of
        :data:`gd_analyze.ranking.statistics.ROWS`; read one with :meth:`statistic`.
        [kg m^2] for D and [N m] for h, squared for a sum of squares.
    sum_arm : ndarray, shape (M,) or (K, M)
        The sum over the set points of the armature on each element [kg m^2].
    arm : ndarray, shape (M,)
        The armature itself (Ia_i on D_ii, 0 elsewhere) [kg m^2].
    scale_D : ndarray, shape (n (n + 1) / 2,) or (K, n (n + 1) / 2)
        Peak sqrt(D_ii D_jj) (D_ii with the armature, clipped at 0) [kg m^2].
    peak_tau : ndarray, shape (n,) or (K, n)
        Peak |tau_i| [N m].
    count : int or ndarray of int, shape (K,)
        The set points accumulated.

    Raises
    ------
    ValueError
        If ``trajectories`` < 1.

    Examples
    --------
    Fed in two chunks, it ranks as :func:`rank_dominance` ranks the whole (up to round-off):

    >>> import numpy as np
    >>> from gd_analyze import gd_terms, load_robot
    >>> robot = load_robot("two-link")
    >>> q = np.linspace(0.0, 1.0, 20)[:, None] * np.array([1.0, -0.5])
    >>> terms = gd_terms(robot, q, np.ones_like(q))
    >>> tau = terms.tau(np.zeros_like(q))
    >>> acc = RankingAccumulator(robot.n)
    >>> for s in (slice(0, 7), slice(7, 20)):
    ...     acc.update(terms.D_tran[s], terms.D_rot[s], terms.h_tran[s], terms.h_rot[s], tau[s])
    >>> whole = rank_dominance(terms.D_tran, terms.D_rot, terms.h_tran, terms.h_rot, tau)
    >>> bool(np.allclose(acc.result().share_tran, whole.share_tran, rtol=1e-12, atol=0.0))
    True
    >>> acc.result().dominance == whole.dominance
    True

    The first 7 and the last 13 set points as two trajectories in one chunk:

    >>> two = RankingAccumulator(robot.n, trajectories=2)
    >>> for s in (slice(0, 10), slice(10, 20)):
    ...     two.update(terms.D_tran[s], terms.D_rot[s], terms.h_tran[s], terms.h_rot[s],
    ...                tau[s], ends=[7, 20], at=s.start)
    >>> two.count.tolist()
    [7, 13]
    """

    def __init__(self, n, trajectories=None):
        if trajectories is not None and int(trajectories) < 1:
            raise ValueError(f"trajectories must be >= 1, got {trajectories}")
        m = n * (n + 1) // 2 + n
        self.n = int(n)
        self.trajectories = None if trajectories is None else int(trajectories)
        lead = () if trajectories is None else (int(trajectories),)
        self.stats = np.zeros(lead + (len(ROWS), m))
        self.sum_arm = np.zeros(lead + (m,))
        self.arm = np.zeros(m)
        self.scale_D = np.zeros(lead + (n * (n + 1) // 2,))
        self.peak_tau = np.zeros(lead + (n,))
        self.count = 0 if trajectories is None else np.zeros(lead, int)

    def statistic(self, series, statistic):
        """One running statistic of every element (a view of :attr:`stats`).

        Parameters
        ----------
        series : str
            One of :data:`gd_analyze.ranking.statistics.SERIES`: ``"tran"``, ``"rot_arm"``
            (rot + arm), ``"total"`` (tran + rot + arm) or ``"rot"`` (peak only).
        statistic : str
            ``"sum_abs"``, ``"sum_sq"`` or ``"peak_abs"``.

        Returns
        -------
        ndarray, shape (M,) or (K, M)
            Per element (and trajectory): [kg m^2] for D and [N m] for h, squared for
            ``"sum_sq"``.

        Raises
        ------
        ValueError
            If that statistic of that series is not accumulated.
        """
        return self.stats[..., row(series, statistic), :]

    def _each(self, name):
        """An array with its leading trajectory axis (a view, also for one trajectory)."""
        value = getattr(self, name)
        return value if self.trajectories is not None else value[None]

    def update(self, D_tran, D_rot, h_tran, h_rot, tau, armature=None, ends=None, at=0):
        """Add a chunk of set points.

        Parameters
        ----------
        D_tran, D_rot : ndarray, shape (N, n, n)
            Inertia matrix parts [kg m^2].
        h_tran, h_rot : ndarray, shape (N, n)
            Coriolis and centrifugal parts [N m].
        tau : ndarray, shape (N, n)
            Joint torques of the full model [N m].
        armature : ndarray, shape (n,), optional
            The drives' armature Ia [kg m^2] (the same for every chunk); zero if not given.
        ends : array_like of int, shape (K,), optional
            Where each of the K trajectories' set points end, laid one after another
            (:mod:`gd_analyze.ranking.segments`); default one trajectory.
        at : int, optional
            The chunk's first set point among them: each of its segments (set points of one
            trajectory) is added to its own trajectory's statistics.

        Raises
        ------
        ValueError
            If the shapes disagree with n or with each other, or the chunk does not fit the
            K trajectories' ends (:func:`gd_analyze.ranking.segments.chunk_segments`).

        Notes
        -----
        One compiled pass over the chunk (:func:`gd_analyze.ranking.kernels.ranking_kernel`):
        per segment, the sums of |x| and x^2 (the segment's in row order, then added) and the
        peaks of |x| of x = tran, rot + arm and tran + rot + arm, the peaks of |rot|,
        sqrt(D_ii D_jj) (D_ii + Ia_i clipped at 0) and |tau|, with the elements of
        :func:`element_labels`.
        """
        n = self.n
        D_tran, D_rot = np.asarray(D_tran, float), np.asarray(D_rot, float)
        h_tran, h_rot = np.asarray(h_tran, float), np.asarray(h_rot, float)
        tau = np.asarray(tau, float)
        N = h_tran.shape[0]
        if D_tran.shape != (N, n, n) or D_rot.shape != (N, n, n) or h_rot.shape != (N, n) \
                or h_tran.shape != (N, n) or tau.shape != (N, n):
            raise ValueError(f"D parts must be (N, {n}, {n}) and h parts and tau (N, {n})")
        if N == 0:
            return
        bounds, each = chunk_segments(N, ends, at, self.trajectories)
        lengths = np.diff(bounds)
        arm_d = np.zeros(n) if armature is None else np.asarray(armature, float)
        if arm_d.any():             # Ia_i on the diagonal elements D_ii only
            iu = np.triu_indices(n)
            self.arm[:iu[0].size] = np.where(iu[0] == iu[1], arm_d[iu[0]], 0.0)
            self._each("sum_arm")[each] += lengths[:, None] * self.arm
        from .kernels import ranking_kernel  # numba: imported by the first chunk only

        c = np.ascontiguousarray
        ranking_kernel(c(D_tran), c(D_rot), c(h_tran), c(h_rot), c(tau), self.arm, c(arm_d),
                       bounds, self._each("stats")[each], self._each("scale_D")[each],
                       self._each("peak_tau")[each])
        if self.trajectories is None:
            self.count += N
        else:
            self.count[each] += lengths

    def result(self, dominance=DEFAULT_DOMINANCE, negligible=DEFAULT_NEGLIGIBLE):
        """Classify the elements of the one trajectory: :meth:`results`' only ranking.

        Parameters
        ----------
        dominance, negligible : float, optional
            s and e, as :meth:`results` takes them.

        Returns
        -------
        Ranking
            The trajectory's shares, classes, peaks and scales.

        Raises
        ------
        ValueError
            As :meth:`results`, and if K > 1 trajectories are ranked.
        """
        if (self.trajectories or 1) != 1:
            raise ValueError(f"{self.trajectories} trajectories are ranked: use results()")
        return self.results(dominance, negligible)[0]

    def results(self, dominance=DEFAULT_DOMINANCE, negligible=DEFAULT_NEGLIGIBLE):
        """Classify the elements of every trajectory from what was accumulated.

        Parameters
        ----------
        dominance : float, optional
            s, in (0.5, 1].
        negligible : float, optional
            e, >= 0.

        Returns
        -------
        list of Ranking
            K of them (one without ``trajectories``), in order.

        Raises
        ------
        ValueError
            If s or e is out of range, or nothing was accumulated for some trajectory.
        """
        if not 0.5 < dominance <= 1.0:
            raise ValueError(f"the dominance threshold s must be in (0.5, 1], got {dominance}")
        if not negligible >= 0.0:
            raise ValueError(f"the negligibility threshold e must be >= 0, got {negligible}")
        if np.any(np.asarray(self.count) == 0):
            raise ValueError("no set points were accumulated")
        stats = self._each("stats")

        def stat(series, statistic):
            return stats[:, row(series, statistic)]

        sum_tran = stat("tran", "sum_abs")
        total = sum_tran + stat("rot_arm", "sum_abs")
        peak_tran, peak_rot = stat("tran", "peak_abs"), stat("rot", "peak_abs")
        peak_total = stat("total", "peak_abs")
        with np.errstate(invalid="ignore", divide="ignore"):
            share = np.where(total > 0, sum_tran / np.where(total > 0, total, 1.0), np.nan)
            share_arm = np.where(total > 0, self._each("sum_arm") / np.where(total > 0, total,
                                                                             1.0), 0.0)
        scale = np.concatenate([self._each("scale_D"), self._each("peak_tau")], axis=1)
        zero = identically_zero(peak_tran, peak_rot, peak_total, scale)
        code = np.select([(peak_total < negligible * scale) | ~np.isfinite(share) | zero,
                          share >= dominance, share <= 1.0 - dominance], [3, 0, 1], 2)
        labels = tuple(element_labels(self.n))
        return [Ranking(labels=labels, share_tran=share[k],
                        dominance=tuple(CLASSES[c] for c in code[k].tolist()),
                        peak_tran=peak_tran[k].copy(), peak_rot=peak_rot[k].copy(),
                        peak_total=peak_total[k].copy(), scale=scale[k],
                        dominance_threshold=float(dominance),
                        negligible_threshold=float(negligible), share_arm=share_arm[k],
                        peak_arm=self.arm.copy())
                for k in range(share.shape[0])]




__all__.append("RankingAccumulator")


class TermsRanking:
    """Rank an arm's G-D terms chunk by chunk, of one trajectory or of K laid one after
    another; an arm with drives is also ranked as its rigid links alone (armature and
    friction left out: the chapter's model), in the same pass.

    Parameters
    ----------
    robot : Robot
        The arm, with n joints (its ``armature`` read where it has drives).
    ends : array_like of int, shape (K,)
        Where each trajectory's set points end (:mod:`gd_analyze.ranking.segments`); one
        trajectory of N set points: ``[N]``.

    Attributes
    ----------
    ranker : RankingAccumulator
        Of the arm as it is (K trajectories).
    rigid : RankingAccumulator or None
        Of its rigid links alone, for an arm with drives.
    """

    def __init__(self, robot: Robot, ends: ArrayLike) -> None:
        self.robot, self.ends = robot, np.array(ends, np.int64).reshape(-1)
        self.ranker = RankingAccumulator(robot.n, trajectories=self.ends.size)
        self.rigid = RankingAccumulator(robot.n, trajectories=self.ends.size) \
            if has_drives(robot) else None

    def update(self, terms: GDTerms, tau: NDArray[np.float64], qdd: NDArray[np.float64],
               at: int) -> None:
        """Add a chunk of set points.

        Parameters
        ----------
        terms : GDTerms
            Its G-D terms, N set points: D_tran, D_rot (N, n, n) [kg m^2]; h_tran, h_rot
            (N, n) [N m], with the drives' armature and friction torque where the arm has
            them.
        tau : ndarray, shape (N, n)
            Its joint torques [N m].
        qdd : ndarray, shape (N, n)
            Its joint accelerations [rad/s^2].
        at : int
            Its first set point among the trajectories'.

        Raises
        ------
        ValueError
            As :meth:`RankingAccumulator.update`.
        """
        args = (terms.D_tran, terms.D_rot, terms.h_tran, terms.h_rot)
        self.ranker.update(*args, tau, armature=terms.armature, ends=self.ends, at=at)
        if self.rigid is not None:
            tau_rigid = tau - self.robot.armature * qdd
            if terms.tau_f is not None:
                tau_rigid -= terms.tau_f
            self.rigid.update(*args, tau_rigid, ends=self.ends, at=at)

    def results(self, dominance: float = DEFAULT_DOMINANCE,
                negligible: float = DEFAULT_NEGLIGIBLE) -> list[Ranking]:
        """Each trajectory's ranking, with ``rigid_dominance`` for an arm with drives.

        Parameters
        ----------
        dominance, negligible : float, optional
            s and e, as :meth:`RankingAccumulator.results` takes them.

        Returns
        -------
        list of Ranking
            K of them, in order.

        Raises
        ------
        ValueError
            As :meth:`RankingAccumulator.results`.
        """
        rankings = self.ranker.results(dominance, negligible)
        if self.rigid is None:
            return rankings
        return [replace(ranking, rigid_dominance=alone.dominance) for ranking, alone in
                zip(rankings, self.rigid.results(dominance, negligible))]


__all__.append("TermsRanking")


def rank_dominance(D_tran, D_rot, h_tran, h_rot, tau, dominance=DEFAULT_DOMINANCE,
                   negligible=DEFAULT_NEGLIGIBLE, armature=None):
    """Rank which part, translational or rotational, dominates each element of D and h.

    Parameters
    ----------
    D_tran, D_rot : ndarray, shape (N, n, n)
        Inertia matrix parts along the trajectory [kg m^2].
    h_tran, h_rot : ndarray, shape (N, n)
        Coriolis and centrifugal parts [N m].
    tau : ndarray, shape (N, n)
        Joint torques of the full model [N m]; their peaks scale the h elements.
    dominance : float, optional
        s, in (0.5, 1]: the share above which one part dominates.
    negligible : float, optional
        e, >= 0: an element whose peak is below e times its scale is negligible.
    armature : ndarray, shape (n,), optional
        The drives' armature Ia [kg m^2], counted on the rotational side (module docstring).

    Returns
    -------
    Ranking

    Raises
    ------
    ValueError
        If s is not in (0.5, 1], e is negative, or the shapes disagree.

    Notes
    -----
    Source: the empirical method of Sec. 3.4.1 (Figs. 3.10 and 3.11), with the share and the
    thresholds defined in the module docstring. For long trajectories feed a
    :class:`RankingAccumulator` chunk by chunk instead.
    """
    h_tran = np.asarray(h_tran, float)
    acc = RankingAccumulator(h_tran.shape[-1] if h_tran.ndim == 2 else 0)
    acc.update(D_tran, D_rot, h_tran, h_rot, tau, armature=armature)
    return acc.result(dominance=dominance, negligible=negligible)
