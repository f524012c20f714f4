"""The chapter's conclusions on its PUMA 560, each stated as this run measured it (Sec. 6).

Sec. 3.4.1 of Fu, Gonzalez & Lee (1987) concludes from Figs. 3.10-3.11 that translation
dominates the arm block and rotation the wrist, classes each element by eye, and builds a
simplified model from those classes. :func:`chapter_conclusions` writes one sentence for each,
from what the analysis counted and stored (``chapter_*`` in ``results.h5``,
:mod:`gd_analyze.ranking.chapter_comparison`): nothing in them is fixed text about the
outcome.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .markup import element, tau
from .numbers import pct

__all__ = ["chapter_conclusions"]


def _names(labels: list[str]) -> str:
    return ", ".join(element(k[0], k[1:]) for k in labels)


def _leads(arm: list[str], arm_t: list[str], wrist: list[str], wrist_r: list[str],
           n: int) -> str:
    block = "elements " + element("D", "ij") + " and " + element("h", "i") + " of joints 1 to 3"
    facts = (f"translation carries more than half of {len(arm_t)} of the {len(arm)} ranked "
             f"{block}, rotation more than half of {len(wrist_r)} of the {len(wrist)} ranked "
             f"elements of joints 4 to {n}")
    missed = [k for k in arm if k not in arm_t] + [k for k in wrist if k not in wrist_r]
    if arm and wrist and not missed:
        return ("The chapter concludes that translation dominates the arm block and rotation "
                f"the wrist; this run agrees: {facts}.")
    return ("The chapter concludes that translation dominates the arm block and rotation the "
            f"wrist; this run agrees only in part: {facts}"
            + (f" (the others: {_names(missed)})." if missed else "."))


def _agreement(grid: ArrayLike, agree: ArrayLike, compared: int, s: float) -> str:
    grid = np.asarray(grid, dtype=float)
    agree = np.asarray(agree, dtype=int)
    best = int(agree.max(initial=0))
    at = [f"{v:g}" for v, a in zip(grid, agree) if a == best]
    parts = [f"{a} at s = {v:g}" + (" (this report's)" if v == float(s) else "")
             for v, a in zip(grid, agree)]
    return (f"The chapter's classes come from reading plots by eye, so its threshold s is not "
            f"known. Agreement with them out of {compared} elements, against s: "
            + "; ".join(parts) + f". The most, {best}, at s = " + " and ".join(at) + ".")


def _own_model(error: ArrayLike, off: ArrayLike, built: ArrayLike, built_off: ArrayLike,
               where: str) -> str:
    err = np.asarray(error, dtype=float)
    off = np.asarray(off, dtype=bool)
    shown = np.where(off | ~np.isfinite(err), 0.0, err)
    worst = int(np.argmax(shown))
    per_joint = "joint " + ", ".join(f"{k + 1}: " + ("\u2261 0" if off[k] else pct(err[k]))
                                     for k in range(err.size))
    mine = np.where(np.asarray(built_off, dtype=bool), 0.0, np.asarray(built, dtype=float))
    return ("The chapter's own simplified model (each element of D and h reduced to the part "
            "the chapter reads as dominant, gravity c unchanged), measured on "
            f"{where}: its peak torque error is up to {pct(shown[worst])} of peak "
            f"|{tau(str(worst + 1))}| at joint {worst + 1} ({per_joint}), against "
            f"{pct(float(mine.max(initial=0.0)))} for the model this run built (Sec. 5). The "
            "chapter's model carries no error bound: its error is what dropping the parts it "
            "reads as dominated costs on this motion.")


def chapter_conclusions(blocks: dict[str, list[str]], grid: ArrayLike, agree: ArrayLike,
                        compared: int, n: int, s: float, chapter_error: ArrayLike,
                        chapter_off: ArrayLike, built_error: ArrayLike, built_off: ArrayLike,
                        where: str = "this trajectory") -> list[str]:
    """The chapter's conclusions on its PUMA 560, each as this run measured it.

    Parameters
    ----------
    blocks : dict
        ``arm``, ``arm_translation``, ``wrist`` and ``wrist_rotation``: element labels, as
        :func:`gd_analyze.ranking.chapter_comparison.block_leads` counts them.
    grid : array_like, shape (S,)
        Dominance thresholds s.
    agree : array_like of int, shape (S,)
        Elements whose class at each s equals the chapter's
        (:func:`gd_analyze.ranking.chapter_comparison.agreement_against_s`).
    compared : int
        The elements the chapter classes.
    n : int
        Number of joints (6).
    s : float
        The dominance threshold of the report's ranking.
    chapter_error, chapter_off : array_like, shape (n,)
        The chapter's own simplified model's peak |tau_s - tau| / peak |tau| per joint, and
        where that is round-off.
    built_error, built_off : array_like, shape (n,)
        The same for the model the run built.
    where : str, optional
        The motion the errors were measured on.

    Returns
    -------
    list of str
        Three sentences: which part leads the arm block and the wrist, agreement against s,
        and the chapter's own model measured.

    Notes
    -----
    Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987), Figs. 3.10-3.11.
    """
    return [_leads(blocks["arm"], blocks["arm_translation"], blocks["wrist"],
                   blocks["wrist_rotation"], n),
            _agreement(grid, agree, compared, s),
            _own_model(chapter_error, chapter_off, built_error, built_off, where)]
