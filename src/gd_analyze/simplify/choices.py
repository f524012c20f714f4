"""The element-level simplified model of Sec. 3.4.1: which part of each element is kept.

For each ranked element of D (upper triangle, mirrored to the lower) and h, a choice keeps the
translational part, the rotational part, both, or nothing (negligible)::

    tau_s = D_s qdd + h_s + c,   D_s = M_tran * D_tran + M_rot * D_rot,
                                 h_s = m_tran * h_tran + m_rot * h_rot

with 0/1 masks M and m from the choices (Fu, Gonzalez & Lee 1987, Sec. 3.4.1, Eq. (3.4-24)).
The drives' terms (:mod:`gd_analyze.model.drives`) are never dropped: D_s gets + D_arm and
tau_s gets + tau_f.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from types import SimpleNamespace
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
from numpy.typing import ArrayLike

from ..dynamics.dalembert import assemble_tau, gd_terms
from ..ranking.labels import element_index, element_labels
from ..ranking.ranking import arm_scales, is_round_off
from ..ranking.segments import chunk_segments

if TYPE_CHECKING:
    from numpy.typing import NDArray

    from ..dynamics.dalembert import GDTerms
    from .simplified import SimplifiedModel

__all__ = ["CHOICES", "PRUNED", "choice_masks", "simplified_torque", "merge_choices",
           "full_choices", "recursive_choices", "sweep_choices", "Motion"]


class Motion(Protocol):
    """What the model building reads of a trajectory
    (:class:`gd_analyze.trajectory.trajectory.Trajectory` is one).

    Attributes
    ----------
    q, qd, qdd : ndarray, shape (N, n)
        Set points [rad, rad/s, rad/s^2; m, m/s, m/s^2 for a prismatic joint].
    sha256 : str
        Its file's SHA-256, or empty (a planned trajectory).
    """

    @property
    def q(self) -> NDArray[np.float64]: ...          # noqa: D102 - the class lists them

    @property
    def qd(self) -> NDArray[np.float64]: ...         # noqa: D102

    @property
    def qdd(self) -> NDArray[np.float64]: ...        # noqa: D102

    @property
    def sha256(self) -> str: ...                     # noqa: D102

#: What a simplified model keeps of an element: its translational part, its rotational part,
#: both, or nothing.
CHOICES = ("tran", "rot", "both", "none")
#: The choice of an element of a model of the recursive form that the (base parameter, part)
#: pairs it drops change: both parts kept, each less the dropped pairs' terms (not
#: "both", which says the element is exact). Its masks are those of "both".
PRUNED = "pruned"


def choice_masks(choices: dict, n: int
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """0/1 masks that select the kept parts.

    Parameters
    ----------
    choices : dict
        Element label (``"D11"`` .. ``"Dnn"`` with i <= j, ``"h1"`` .. ``"hn"``) -> ``"tran"``,
        ``"rot"``, ``"both"``, ``"none"`` or (a recursive model's) :data:`PRUNED`, masked as
        ``"both"``.
    n : int
        Number of joints.

    Returns
    -------
    D_tran_mask, D_rot_mask : ndarray, shape (n, n)
        Symmetric masks for D_tran and D_rot.
    h_tran_mask, h_rot_mask : ndarray, shape (n,)
        Masks for h_tran and h_rot.

    Raises
    ------
    ValueError
        If an element is missing or a choice is not one of the five.
    """
    Mt, Mr, mt, mr = _masks([choices], n)
    return Mt[0], Mr[0], mt[0], mr[0]


def _masks(choices_list, n):
    """:func:`choice_masks` of K models at once: arrays with a leading axis K."""
    labels = element_labels(n)
    code = {c: k for k, c in enumerate(CHOICES + (PRUNED,))}
    try:
        rows = [[choices[label] for label in labels] for choices in choices_list]
    except KeyError as exc:
        raise ValueError(f"no choice for element {exc.args[0]}") from None
    for row in rows:
        for label, ch in zip(labels, row):
            if not isinstance(ch, str) or ch not in code:
                raise ValueError(f"element {label}: choice must be one of "
                                 f"{CHOICES + (PRUNED,)}, got {ch!r}")
    codes = np.array([[code[ch] for ch in row] for row in rows], int).reshape(len(rows), -1)
    keep_t = np.isin(codes, [code[c] for c in ("tran", "both", PRUNED)]).astype(float)
    keep_r = np.isin(codes, [code[c] for c in ("rot", "both", PRUNED)]).astype(float)
    K, T = codes.shape[0], n * (n + 1) // 2
    i, j = (np.array(v, int) for v in zip(*[(i, j) for kind, i, j in element_index(n)
                                            if kind == "D"]))
    Mt, Mr = np.zeros((K, n, n)), np.zeros((K, n, n))
    for M, keep in ((Mt, keep_t), (Mr, keep_r)):
        M[:, i, j] = keep[:, :T]
        M[:, j, i] = keep[:, :T]
    return Mt, Mr, keep_t[:, T:], keep_r[:, T:]


#: Set points of :func:`simplified_torque` at once.
_BLOCK = 2048


def simplified_torque(terms: GDTerms, choices: dict | Sequence[dict], qdd: ArrayLike,
                      ends: ArrayLike | None = None, at: int = 0) -> np.ndarray:
    """Torques of the simplified model from already computed G-D terms.

    Parameters
    ----------
    terms : GDTerms
        D_tran, D_rot (N, n, n) [kg m^2]; h_tran, h_rot, c (N, n) [N m].
    choices : dict or sequence of dict
        Element label -> ``"tran"``, ``"rot"``, ``"both"`` or ``"none"``; with ``ends``, one
        such dict per trajectory (each trajectory's own model).
    qdd : array_like, shape (N, n)
        Joint accelerations [rad/s^2].
    ends : array_like of int, shape (K,), optional
        Where each of the K trajectories' set points end, laid one after another
        (:mod:`gd_analyze.ranking.segments`): each set point's torque is then that of its
        trajectory's model. Default: one model for every set point.
    at : int, optional
        The first of the N set points among the trajectories'.

    Returns
    -------
    ndarray, shape (N, n)
        tau_s = D_s qdd + h_s + c [N m], plus the drives' Ia qdd and tau_f when the terms
        carry them; each row as it is computed alone.

    Raises
    ------
    ValueError
        As :func:`choice_masks`; if the set points do not fit the trajectories' ends or
        their number is not that of the models
        (:func:`gd_analyze.ranking.segments.chunk_segments`).
    """
    n = terms.c.shape[1]
    qdd = np.asarray(qdd, dtype=float).reshape(terms.c.shape)
    models, owner = [choices], None   # the model of each set point (None: the one model)
    if ends is not None:
        models = list(choices)  # type: ignore[arg-type]
        bounds, each = chunk_segments(len(qdd), ends, at, len(models))
        models = models[each]
        if len(models) > 1:
            owner = np.repeat(np.arange(len(models)), np.diff(bounds))
    Mt, Mr, mt, mr = _masks(models, n)
    tau = np.empty(qdd.shape)
    # block by block: D_s's temporaries stay small (each row is computed alone)
    for a in range(0, len(qdd), _BLOCK):
        rows = slice(a, a + _BLOCK)
        k = 0 if owner is None else owner[rows]
        D_s = Mt[k] * terms.D_tran[rows] + Mr[k] * terms.D_rot[rows]
        h_s = mt[k] * terms.h_tran[rows] + mr[k] * terms.h_rot[rows]
        tau[rows] = assemble_tau(D_s, h_s, terms.c[rows], qdd[rows])
    if terms.armature is not None:
        tau += terms.armature * qdd
    if terms.tau_f is not None:
        tau += terms.tau_f
    return tau


def merge_choices(choices_list: Sequence[dict]) -> dict:
    """Merge simplified models conservatively: drop a part only where every model drops it.

    Parameters
    ----------
    choices_list : sequence of dict
        One dict per trajectory: element label -> ``"tran"``, ``"rot"``, ``"both"`` or
        ``"none"``; all with the same labels.

    Returns
    -------
    dict
        Element label -> merged choice, in the label order of the first dict. With
        keep_tran = any choice in {tran, both} and keep_rot = any choice in {rot, both}:
        ``"both"`` if both are kept, ``"tran"`` or ``"rot"`` if only one, ``"none"`` if
        neither (the element is negligible in every trajectory).

    Raises
    ------
    ValueError
        If the sequence is empty, the dicts have different labels, or a choice is not one of
        the four.

    Notes
    -----
    The merged model keeps every part that any trajectory's own model keeps, so it is the
    smallest model of this form that is, element by element, at least as complete as each of
    them. Source: the simplified model of Sec. 3.4.1 of Fu, Gonzalez & Lee (1987), which
    "depends on the specific trajectory being considered".

    Examples
    --------
    >>> merge_choices([{"D11": "tran", "h1": "none"}, {"D11": "rot", "h1": "none"}])
    {'D11': 'both', 'h1': 'none'}
    """
    choices_list = list(choices_list)
    if not choices_list:
        raise ValueError("no simplified models to merge")
    labels = list(choices_list[0])
    keep_t = dict.fromkeys(labels, False)
    keep_r = dict.fromkeys(labels, False)
    for k, choices in enumerate(choices_list):
        if set(choices) != set(labels):
            diff = sorted(set(choices) ^ set(labels))
            raise ValueError(f"model {k} has other elements than model 0 (e.g. {diff[0]!r})")
        for label, ch in choices.items():
            if ch not in CHOICES:
                raise ValueError(f"model {k}, element {label}: choice must be one of "
                                 f"{CHOICES}, got {ch!r}")
            keep_t[label] |= ch in ("tran", "both")
            keep_r[label] |= ch in ("rot", "both")
    table = {(True, True): "both", (True, False): "tran", (False, True): "rot",
             (False, False): "none"}
    return {label: table[(keep_t[label], keep_r[label])] for label in labels}


def full_choices(n: int) -> dict:
    """Choices that keep every part of every element: the full model.

    Parameters
    ----------
    n : int
        Number of joints.

    Returns
    -------
    dict
        ``{"D11": "both", ..., "hn": "both"}``.

    Examples
    --------
    >>> full_choices(1)
    {'D11': 'both', 'h1': 'both'}
    """
    return {label: "both" for label in element_labels(n)}


def recursive_choices(model: SimplifiedModel, q: NDArray[np.float64], qd: NDArray[np.float64],
                      terms: GDTerms, ranking: Any) -> dict[str, str]:
    """A recursive model's choice per element, as results.h5 stores it: "pruned" where the
    (base parameter, part) pairs it drops change the element, else "both" (never "both"
    for every element although XY2's terms are dropped).

    Parameters
    ----------
    model : SimplifiedModel
        Of the recursive form.
    q, qd : ndarray, shape (N, n)
        Set points to compare on [rad, rad/s; m, m/s].
    terms : GDTerms
        The G-D terms there (the full model's D, with the armature, and h).
    ranking : Ranking
        Its ``labels`` (D's upper triangle, then h) and each element's ``scale`` (any object
        with these two).

    Returns
    -------
    dict of str to str
        "pruned" where max |D_s - D| or max |h_s + friction - h - friction| over the set points
        is not round-off of the element's scale (:func:`gd_analyze.ranking.ranking.is_round_off`,
        with the arm's scale of D or of h), else "both".
    """

    n = model.robot.n
    fns = model.functions().numpy()
    D_s = np.asarray(fns["inertia"](q), float).reshape(-1, n, n)
    h_s = np.asarray(fns["velocity_terms"](q, qd), float).reshape(-1, n)
    h = terms.h + (0.0 if terms.tau_f is None else terms.tau_f)     # h_s holds the friction
    iu = np.triu_indices(n)
    diff = np.concatenate([np.abs(D_s - terms.D).max(axis=0)[iu], np.abs(h_s - h).max(axis=0)])
    scale = np.asarray(ranking.scale, float)
    kind = ["D"] * iu[0].size + ["h"] * n
    off = is_round_off(diff, scale, arm_scale=arm_scales(scale, kind))
    return {lab: "both" if o else "pruned" for lab, o in zip(ranking.labels, off)}


def sweep_choices(model: SimplifiedModel, trajectories: Sequence[Motion],
                  setpoints: int = 64) -> SimplifiedModel:
    """A recursive merged model's choice per element (:func:`recursive_choices`), compared on
    set points spread evenly over the swept trajectories.

    Parameters
    ----------
    model : SimplifiedModel
        The merged model; one of the explicit form is returned as it is.
    trajectories : sequence of Trajectory
        The K swept trajectories (q, qd, qdd of shape (N_k, n)).
    setpoints : int, optional
        How many set points, evenly spread over the trajectories one after the other.

    Returns
    -------
    SimplifiedModel
        With ``choices`` "pruned" where its dropped pairs change D_ij or h_i at those set
        points beyond round-off of the element's scale there (peak sqrt(D_ii D_jj) [kg m^2],
        or peak |tau_i| [N m]), else "both".

    Notes
    -----
    D and h are the G-D terms (Eqs. (3.4-25) to (3.4-33)) at those set points.
    """
    if model.recursive is None or not trajectories:
        return model
    q, qd, qdd = (np.concatenate([np.asarray(getattr(t, k), float) for t in trajectories])
                  for k in ("q", "qd", "qdd"))
    at = np.unique(np.linspace(0, len(q) - 1, min(len(q), setpoints)).round().astype(int))
    q, qd, qdd = q[at], qd[at], qdd[at]
    terms = gd_terms(model.robot, q, qd)
    n = model.robot.n
    diag = np.sqrt(np.abs(np.einsum("kii->ki", terms.D)))
    iu = np.triu_indices(n)
    scale = np.concatenate([(diag[:, iu[0]] * diag[:, iu[1]]).max(axis=0),
                            np.abs(terms.tau(qdd)).max(axis=0)])
    ranking = SimpleNamespace(labels=element_labels(n), scale=scale)
    return dataclasses.replace(model, choices=recursive_choices(model, q, qd, terms, ranking))
