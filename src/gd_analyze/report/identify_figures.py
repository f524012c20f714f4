"""The identify report's figures: measured against predicted torque per joint, and the
residuals, of each recording shown, drawn from the stored identification (``identification.h5``)
at a page's width (7.2 in).

Per joint a panel over the recording's time: the measured torque (after the stated filter),
the identified model's prediction and, where stored, the robot file's as shipped and the
simplified model's. The residual figure shows measured minus identified. Joint names reach the
figures as literal text (``parse_math=False``: a ``$`` never starts mathtext).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np

from ..store.stored_identification import StoredIdentification, StoredRecording
from .common import BASE_RC, grid_shape
from .markup import clean
from .ticks import label_axes, set_ticks

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

__all__ = ["identify_figures", "shown_recordings", "role_of", "figure_key", "PAGE_WIDTH", "MAX_POINTS",
           "MODEL_STYLES", "FIGURE_RC", "stride", "short", "TITLE_CHARS"]

#: Figure width [in]: the text of a page.
PAGE_WIDTH = 7.2
#: The most points drawn of one line: longer recordings are drawn every k-th sample (the
#: caption says which k).
MAX_POINTS = 1500
#: Colour, line style and width [pt] of each torque (Okabe & Ito colours, told apart in black
#: and white by the line style too), with its key label.
MODEL_STYLES = {"tau_measured": ("#000000", "-", 1.3, "measured (filtered)"),
                "tau_predicted": ("#0072B2", (0, (4.0, 1.6)), 1.0, "identified model"),
                "tau_prior": ("#D55E00", (0, (1.0, 1.3)), 1.0, "robot file as shipped"),
                "tau_simplified": ("#009E73", (0, (5.0, 1.5, 1.0, 1.5)), 0.9,
                                   "simplified model")}
#: The residual's style: measured minus identified.
RESIDUAL_STYLE = ("#0072B2", "-", 0.9, "measured \u2212 identified model")
FIGURE_RC = {**BASE_RC, "legend.fontsize": 7.5}


def shown_recordings(groups: Mapping[str, StoredRecording]) -> list[str]:
    """The recordings the figures show: the validation recordings, or, without any, all.

    Parameters
    ----------
    groups : Mapping of str to StoredRecording
        The recordings by group name, in order.

    Returns
    -------
    list of str
        Group names.
    """
    validate = [k for k, ds in groups.items() if role_of(ds) == "validate"]
    return validate or list(groups)


def role_of(rec: StoredRecording) -> str:
    """A recording's role: its ``role`` attribute, or its ``role`` variable.

    Parameters
    ----------
    rec : StoredRecording
        A recording (:class:`gd_analyze.store.stored_identification.StoredRecording`).

    Returns
    -------
    str
        ``train`` or ``validate`` as stored (cleaned of the report's markup characters);
        ``train`` when not stored.
    """
    return "train" if rec.role is None else clean(str(rec.role))


def figure_key(kind: str, k: int) -> str:
    """The key of a figure: ``"torque_2"`` for the torque figure of the third recording shown.

    Parameters
    ----------
    kind : {"torque", "residual"}
    k : int
        The recording's position among :func:`shown_recordings`, from 0.

    Returns
    -------
    str
        Never holds a file or joint name.
    """
    return f"{kind}_{k}"


#: The most characters of a joint's name in a panel title (a longer one is cut, with "...";
#: the tables give it whole).
TITLE_CHARS = 36


def short(name: str) -> str:
    """A joint's name cut to :data:`TITLE_CHARS` characters for a panel title.

    Parameters
    ----------
    name : str

    Returns
    -------
    str
        The name, or its first characters and an ellipsis.

    Examples
    --------
    >>> short("arm_1_joint")
    'arm_1_joint'
    """
    name = str(name)
    return name if len(name) <= TITLE_CHARS else name[:TITLE_CHARS - 1] + "\u2026"


def stride(m: int) -> int:
    """Every how many samples a line of m samples is drawn.

    Parameters
    ----------
    m : int
        Samples of the recording.

    Returns
    -------
    int
        k >= 1: every k-th sample is drawn, at most :data:`MAX_POINTS` of them.
    """
    return max(1, int(math.ceil(m / MAX_POINTS)))


def _panels(t, curves, joints, ylabel, width, prismatic=None):
    """One panel per joint, two a row, the curves (name -> (N, n)) over t, a key below; each
    panel's unit N m (revolute) or N (prismatic), said on the left panel of a row and on any
    panel whose unit differs from it."""
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    n = len(joints)
    rows, cols = grid_shape(n, 2)
    top, bottom = 0.3, 0.85
    height = 1.6 * rows + top + bottom
    fig = Figure(figsize=(width, height))
    fig.subplots_adjust(left=0.75 / width, right=1 - 0.15 / width, top=1 - top / height,
                        bottom=bottom / height, wspace=0.3, hspace=0.45)
    axes = fig.subplots(rows, cols, squeeze=False, sharex=True)
    k = stride(t.size)
    handles = {}
    yaxes = []
    for j in range(rows * cols):
        ax = axes[j // cols, j % cols]
        if j >= n:
            ax.set_visible(False)
            continue
        for name, y in curves.items():
            colour, ls, lw, label = MODEL_STYLES.get(name, RESIDUAL_STYLE)
            ax.plot(t[::k], np.asarray(y, float)[::k, j], color=colour, linestyle=ls,
                    linewidth=lw)
            handles.setdefault(label, Line2D([], [], color=colour, linestyle=ls, linewidth=lw))
        ax.set_title(f"joint {j + 1}: {short(joints[j])}", loc="left", parse_math=False)
        lo, hi = ax.get_ylim()
        set_ticks(ax.yaxis, lo, hi, 4, labels=False)
        yaxes.append(ax.yaxis)
        unit = "N" if prismatic is not None and prismatic[j] else "N m"
        left = j - j % cols
        left_unit = "N" if prismatic is not None and prismatic[left] else "N m"
        if j % cols == 0 or unit != left_unit:
            ax.set_ylabel(f"{ylabel} [{unit}]")
        if j >= n - cols:
            ax.set_xlabel("t [s]")
            ax.tick_params(labelbottom=True)
    label_axes(yaxes)
    fig.legend(list(handles.values()), list(handles), loc="lower center", ncol=len(handles),
               frameon=False, bbox_to_anchor=(0.5, 0.02))
    return fig


def identify_figures(root: StoredIdentification | xr.Dataset,
                     groups: dict[str, xr.Dataset] | None = None,
                     width: float = PAGE_WIDTH) -> dict[str, Figure]:
    """The report's figures from a stored identification.

    Parameters
    ----------
    root : StoredIdentification or xarray.Dataset
        The stored identification
        (:class:`gd_analyze.store.stored_identification.StoredIdentification`), or its root group
        (its ``joint`` coordinate names the joints, if present).
    groups : dict of str to xarray.Dataset, optional
        With a root group: one dataset per recording, ``t`` [s], ``tau_measured`` and
        ``tau_predicted`` (t, joint) [N m or N], optionally ``tau_prior`` and
        ``tau_simplified``.
    width : float, optional
        Figure width [in].

    Returns
    -------
    dict of str to matplotlib.figure.Figure
        ``"torque_k"`` and ``"residual_k"`` for the k-th recording of
        :func:`shown_recordings`.
    """

    ident = StoredIdentification.of(root, groups)
    out = {}
    import matplotlib

    with matplotlib.rc_context(FIGURE_RC):  # type: ignore[arg-type]  # keys typed as literals
        for k, name in enumerate(shown_recordings(ident.recordings)):
            rec = ident.recordings[name]
            t = rec.t
            n = rec.n
            joints = _joint_names(ident, rec, n)
            curves = {v: rec.torques[v] for v in MODEL_STYLES if v in rec.torques}
            prismatic = (np.asarray(ident.prismatic, bool) if ident.prismatic is not None
                         else None)
            out[figure_key("torque", k)] = _panels(t, curves, joints, "\u03c4", width,
                                                   prismatic)
            residual = rec.torques["tau_measured"] - rec.torques["tau_predicted"]
            out[figure_key("residual", k)] = _panels(
                t, {"residual": residual}, joints, "\u03c4 residual", width, prismatic)
    return out


def _joint_names(ident, rec, n):
    for joint in (rec.joint, ident.joint):
        if joint is not None and joint.size == n:
            return [str(v) for v in joint]
    return [str(j + 1) for j in range(n)]
