"""Figures shared by more than one report.

:func:`payload_figure` draws a payload sweep; the main report (``--payload-sweep``) and the sweep
report both show it. Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987).
"""

from __future__ import annotations

import textwrap
from typing import TYPE_CHECKING

import numpy as np

from ..ranking.ranking import joint_torque_units
from ..store.sweep_view import PAYLOAD_REQUIRED as _PAYLOAD_REQUIRED
from ..store.sweep_view import PayloadSweep
from .common import CLASS_COLOURS, SUPTITLE_RC, joint_style
from .figure_style import joint_key
from .markup import label

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

__all__ = ["payload_figure", "PAYLOAD_REQUIRED", "CLASS_LETTER", "PAGE_WIDTH", "COLUMN_WIDTH"]

#: Width of the figures: the text of a page [in] (the reports' figures go into papers unscaled).
PAGE_WIDTH = 7.2
#: Width of a one-column figure [in].
COLUMN_WIDTH = 3.5

#: The variables :func:`payload_figure` reads.
PAYLOAD_REQUIRED = _PAYLOAD_REQUIRED

#: One letter per dominance class, drawn in the heat map's cells.
CLASS_LETTER = {"translational": "T", "rotational": "R", "both": "B", "negligible": "N"}


def payload_figure(ds: PayloadSweep | xr.Dataset, width: float = PAGE_WIDTH) -> Figure:
    """Translational share and dominance class of every element vs payload, and peak |tau| vs
    payload.

    Parameters
    ----------
    ds : xarray.Dataset
        A payload sweep from :func:`gd_analyze.jobs.payload.payload_sweep`: coordinate ``payload``
        (P,) [kg]; ``share_tran`` and ``dominance`` (payload, element); ``tau_peak``
        (payload, joint) [N m].
    width : float, optional
        :data:`PAGE_WIDTH` (payload down, elements across) or :data:`COLUMN_WIDTH` [in]
        (elements down, payload across: a row of 7-pt element labels per element).

    Returns
    -------
    matplotlib.figure.Figure
        ``width`` wide, type of at least 7 pt. Top: a heat map of the translational share
        over (payload, element) from rotational (0, orange) through 0.5 (white) to
        translational (1, blue), each cell marked with its class (T, R, B or N) and with a
        bold frame where the class differs from that at the first payload; grey where the
        element is round-off in every part (``round_off``: its share is noise); elements
        written D(1,2) (:func:`gd_analyze.report.markup.label`: no subscript under 8 pt).
        Bottom: peak |tau| per joint vs payload [N m, N for a prismatic joint]. A plain
        Figure (no pyplot state).

    Raises
    ------
    InputError
        If a variable the figure needs is missing.

    Notes
    -----
    The dominance of Sec. 3.4.1 of Fu, Gonzalez & Lee (1987) depends on the load the arm
    carries through link n's inertial parameters.
    """
    from matplotlib.colors import LinearSegmentedColormap
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    part = PayloadSweep.of(ds)
    column = width < PAGE_WIDTH
    import matplotlib

    with matplotlib.rc_context(SUPTITLE_RC):  # type: ignore[arg-type]  # keys typed as literals
        masses = part.masses
        labels = [label(lab) for lab in part.elements]
        share = part.share_tran
        if part.round_off is not None:         # a share of round-off is noise: not drawn
            share = np.where(part.round_off, np.nan, share)
        dom = part.dominance.reshape(share.shape)
        P, M = share.shape
        n = len(part.prismatic)
        W = width
        s, e = (float(np.nan if v is None else v)
                for v in (part.dominance_threshold, part.negligible_threshold))
        title = (f"Dominance against the payload on the last link (s = {s:g}, e = {e:g})\n"
                 "T/R/B/N = translational/rotational/both/negligible; framed: class "
                 "differs from the first payload\ngrey: \u2261 0 (round-off in every part), no "
                 "share drawn")
        if column:          # bold 8 pt: about 44 characters a line; elements down, 7 pt a row
            title = textwrap.fill(title.replace("\n", "; "), 44)
            heat_h, top, left = 0.15 * M, 0.22 + 0.15 * (title.count("\n") + 1), 0.5
            tau_h, legend_h = 1.5, 0.2 + 0.16 * -(-n // 3)
            H = top + heat_h + 0.5 + tau_h + 0.42 + legend_h
            heat_w = W - left - 1.0
        else:
            heat_h, top, left = max(1.4, 0.3 * P), 0.75, 0.9
            tau_h = 2.6
            H = heat_h + 4.6
            heat_w = W - 2.0
        fig = Figure(figsize=(W, H))
        ax = fig.add_axes((left / W, (H - top - heat_h) / H, heat_w / W, heat_h / H))
        cmap = LinearSegmentedColormap.from_list(
            "rot_tran", [CLASS_COLOURS["rotational"], "#FFFFFF",
                         CLASS_COLOURS["translational"]]).with_extremes(bad="0.8")
        grid = share.T if column else share
        im = ax.imshow(np.ma.masked_invalid(grid), aspect="auto", cmap=cmap, vmin=0, vmax=1,
                       interpolation="nearest")
        for p in range(P):
            for k in range(M):
                v = share[p, k]
                dark = np.isfinite(v) and abs(v - 0.5) > 0.33
                x, y = (p, k) if column else (k, p)
                ax.text(x, y, CLASS_LETTER.get(dom[p, k], "?"), ha="center", va="center",
                        fontsize=7, color="white" if dark else "black")
                if dom[p, k] != dom[0, k]:
                    ax.add_patch(Rectangle((x - 0.5, y - 0.5), 1, 1, fill=False, lw=1.4,
                                           ec="black"))
        mass_ticks = [f"{m:g}" for m in masses]
        if column:
            ax.set_yticks(np.arange(M), labels, fontsize=7)
            ax.set_xticks(np.arange(P), mass_ticks, fontsize=7)
            ax.set_xlabel("payload [kg]", labelpad=1.0)
        else:
            ax.set_xticks(np.arange(M), labels, rotation=90, fontsize=7)
            ax.set_yticks(np.arange(P), mass_ticks, fontsize=7)
            ax.set_ylabel("payload [kg]")
        ax.tick_params(length=2.0, pad=1.5)
        ax.grid(False)
        cax = fig.add_axes(((left + heat_w + 0.12 if column else W - 0.95) / W,
                            (H - top - heat_h) / H, 0.12 / W, heat_h / H))
        cb = fig.colorbar(im, cax=cax)
        cb.set_label("translational share [1]")
        cb.ax.tick_params(labelsize=7)
        cb.ax.grid(False)                   # no grid lines across the colour scale
        bottom = 0.42 + legend_h if column else 0.6
        tau = part.tau_peak
        units = [joint_torque_units(p) for p in part.prismatic]
        kinds = list(dict.fromkeys(units))  # one panel per unit: never N m and N on one axis
        gap = 0.3
        each = (tau_h - gap * (len(kinds) - 1)) / len(kinds)
        for k, unit in enumerate(kinds):
            y0 = bottom + (len(kinds) - 1 - k) * (each + gap)
            bx = fig.add_axes((left / W, y0 / H, (heat_w if column else W - 2.0) / W, each / H))
            for j in (j for j in range(n) if units[j] == unit):    # style and marker differ
                bx.plot(masses, tau[:, j], label=f"joint {j + 1}", linewidth=0.9,
                        **joint_style(j, len(masses), sum(u == unit for u in units)))
            if k == len(kinds) - 1:
                bx.set_xlabel("payload [kg]", labelpad=1.0)
            else:
                bx.tick_params(labelbottom=False)
            bx.set_ylabel(f"peak |\u03c4| [{unit}]")
            bx.tick_params(labelsize=7)
        handles, names = joint_key(fig.axes[2:])      # the heat map and its colour bar first
        if column:
            fig.legend(handles, names, loc="upper center", ncol=3, frameon=False, fontsize=7,
                       handlelength=2.6, bbox_to_anchor=(0.5, legend_h / H))
        else:
            fig.legend(handles, names, loc="center left", frameon=False, fontsize=7,
                       bbox_to_anchor=((W - 1.05) / W, (bottom + tau_h / 2) / H))
        fig.suptitle(title, y=1 - 0.08 / H, va="top", fontsize=8 if column else 8.5)
        return fig

