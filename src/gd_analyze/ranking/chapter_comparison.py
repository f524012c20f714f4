"""The chapter's conclusions on its PUMA 560, measured: Sec. 3.4.1 of Fu, Gonzalez & Lee 1987.

The chapter reads a class off Figs. 3.10 and 3.11 for each element of D and h
(:data:`gd_analyze.ranking.ranking.CHAPTER_DOMINANCE`) and concludes two things: the
translational effect dominates the elements of the first three joints (the arm block), the
rotational effect those of the last three (the wrist); and the simplified model that keeps
each element's dominant part is the one to control with. This module turns each into a
number that can be computed along any trajectory:

- :func:`block_leads`: in how many of the arm block's elements translation leads (share_tran
  > 1/2), and in how many of the wrist's rotation leads;
- :func:`classify` and :func:`agreement_against_s`: the class of every element at any dominance
  threshold s, and how many agree with the chapter's as s varies, since the chapter's own s
  is the reading of a plot by eye;
- :data:`CHAPTER_CHOICES`: the chapter's own simplified model, each element reduced to the
  part the chapter names, in the form :func:`gd_analyze.simplify.choices.simplified_torque`
  evaluates.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .labels import parse_element_label
from .ranking import CHAPTER_DOMINANCE

__all__ = ["CHAPTER_CHOICES", "S_VALUES", "BlockLeads", "classify", "agreement_against_s",
           "block_leads"]

#: The chapter's own simplified model: each element of D and h reduced to the part the
#: chapter reads as dominant off Figs. 3.10-3.11 (both parts where it reads "both"; the
#: chapter has no negligible class, so nothing is dropped whole).
CHAPTER_CHOICES: dict[str, str] = {
    label: {"translational": "tran", "rotational": "rot", "both": "both"}[cls]
    for label, cls in CHAPTER_DOMINANCE.items()}

#: The dominance thresholds s at which agreement with the chapter is counted.
S_VALUES: tuple[float, ...] = (0.6, 0.7, 0.8, 0.9, 0.95, 0.99)


def classify(share_tran: ArrayLike, negligible: ArrayLike, s: float) -> NDArray[np.str_]:
    """The class of each element at dominance threshold s (Sec. 3.4.1's rule, as ranked).

    Parameters
    ----------
    share_tran : array_like, shape (M,)
        Translational share of each element along the trajectory, in [0, 1]; NaN where both
        parts are zero.
    negligible : array_like of bool, shape (M,)
        Where the element is negligible (peak below e times its scale, or zero): that does not
        depend on s.
    s : float
        The dominance threshold, in (0.5, 1].

    Returns
    -------
    ndarray of str, shape (M,)
        ``"translational"`` where share_tran >= s, ``"rotational"`` where share_tran <= 1 - s,
        ``"both"`` otherwise, and ``"negligible"`` where ``negligible`` or the share is not
        finite.

    Raises
    ------
    ValueError
        If s is outside (0.5, 1] or the shapes differ.

    Examples
    --------
    >>> classify([0.95, 0.5, 0.02, np.nan], [False, False, False, False], 0.9).tolist()
    ['translational', 'both', 'rotational', 'negligible']
    >>> classify([0.95, 0.5], [True, False], 0.99).tolist()
    ['negligible', 'both']
    """
    if not 0.5 < s <= 1.0:
        raise ValueError(f"the dominance threshold s must be in (0.5, 1], got {s}")
    share = np.asarray(share_tran, dtype=float)
    off = np.asarray(negligible, dtype=bool)
    if share.shape != off.shape:
        raise ValueError(f"share_tran has shape {share.shape}, negligible {off.shape}")
    with np.errstate(invalid="ignore"):
        out = np.where(share >= s, "translational",
                       np.where(share <= 1.0 - s, "rotational", "both"))
    return np.where(off | ~np.isfinite(share), "negligible", out).astype(str)


def agreement_against_s(labels: list[str] | tuple[str, ...], share_tran: ArrayLike,
                        negligible: ArrayLike, s_values: tuple[float, ...] = S_VALUES,
                        chapter: dict[str, str] | None = None) -> tuple[NDArray[np.float64],
                                                                         NDArray[np.int_],
                                                                         int]:
    """How many classes agree with the chapter's, at each dominance threshold s.

    Parameters
    ----------
    labels : sequence of str, length M
        Element labels (``"D11"`` .. ``"h6"``).
    share_tran, negligible : array_like, shape (M,)
        As :func:`classify`.
    s_values : tuple of float, optional
        The thresholds, each in (0.5, 1].
    chapter : dict, optional
        Label -> the chapter's class (default :data:`CHAPTER_DOMINANCE`).

    Returns
    -------
    s : ndarray, shape (S,)
    agree : ndarray of int, shape (S,)
        Elements whose class at s equals the chapter's. A negligible element disagrees (the
        chapter has no negligible class).
    compared : int
        The elements the chapter classes.
    """
    chapter = CHAPTER_DOMINANCE if chapter is None else chapter
    keep = [k for k, lab in enumerate(labels) if lab in chapter]
    want = np.array([chapter[labels[k]] for k in keep], dtype=str)
    share = np.asarray(share_tran, dtype=float)[keep]
    off = np.asarray(negligible, dtype=bool)[keep]
    s = np.asarray(s_values, dtype=float)
    agree = np.array([int(np.sum(classify(share, off, float(v)) == want)) for v in s], int)
    return s, agree, len(keep)


@dataclass(frozen=True)
class BlockLeads:
    """Which part leads in the arm block and in the wrist (the chapter's conclusion, counted).

    Attributes
    ----------
    arm : tuple of str
        The arm block's elements ranked (not negligible): D_ij with i, j <= 3 and h_1..h_3.
    arm_translation : tuple of str
        Those whose translational share exceeds 1/2.
    wrist : tuple of str
        The wrist's elements ranked: D_ij with i, j >= 4 and h_4..h_n.
    wrist_rotation : tuple of str
        Those whose translational share is below 1/2.
    """

    arm: tuple[str, ...]
    arm_translation: tuple[str, ...]
    wrist: tuple[str, ...]
    wrist_rotation: tuple[str, ...]


def block_leads(labels: list[str] | tuple[str, ...], share_tran: ArrayLike,
                negligible: ArrayLike, n: int, n_arm: int = 3) -> BlockLeads:
    """Count where translation leads in the arm block and rotation in the wrist.

    Parameters
    ----------
    labels : sequence of str, length M
        Element labels of an n-joint arm.
    share_tran, negligible : array_like, shape (M,)
        As :func:`classify`.
    n : int
        Number of joints.
    n_arm : int, optional
        Joints of the arm block (the PUMA 560's first three); the others are the wrist.

    Returns
    -------
    BlockLeads
        Coupling elements D_ij with i <= n_arm < j belong to neither block.

    Examples
    --------
    >>> b = block_leads(["D11", "D12", "D22", "h1", "h2"], [0.9, 0.8, 0.3, 0.7, 0.2],
    ...                 [False] * 5, n=2, n_arm=1)
    >>> b.arm, b.arm_translation, b.wrist, b.wrist_rotation
    (('D11', 'h1'), ('D11', 'h1'), ('D22', 'h2'), ('D22', 'h2'))
    """
    share = np.asarray(share_tran, dtype=float)
    off = np.asarray(negligible, dtype=bool)
    arm, arm_t, wrist, wrist_r = [], [], [], []
    for k, label in enumerate(labels):
        if off[k] or not np.isfinite(share[k]):
            continue
        _, i, j = parse_element_label(label, n)
        rows = {i} if j is None else {i, j}
        if max(rows) < n_arm:
            arm.append(label)
            if share[k] > 0.5:
                arm_t.append(label)
        elif min(rows) >= n_arm:
            wrist.append(label)
            if share[k] < 0.5:
                wrist_r.append(label)
    return BlockLeads(tuple(arm), tuple(arm_t), tuple(wrist), tuple(wrist_r))
