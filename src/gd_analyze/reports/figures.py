"""Figures shared by more than one report.

:func:`payload_figure` draws a payload sweep; the main report (``--payload-sweep``) and the sweep
report both show it. Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987).
"""

from __future__ import annotations

import numpy as np

from .common import (
    CLASS_COLOURS,
    SUPTITLE_RC,
    check,
    joint_style,
    strings,
    style,
    thresholds,
    torque_units,
)

__all__ = ["payload_figure", "PAYLOAD_REQUIRED", "CLASS_LETTER", "PAGE_WIDTH"]

#: Width of the figures: the text of a page [in] (the reports' figures go into papers unscaled).
PAGE_WIDTH = 7.2

#: The variables :func:`payload_figure` reads.
PAYLOAD_REQUIRED = ("share_tran", "dominance", "choice", "tau_peak")

#: One letter per dominance class, drawn in the heat map's cells.
CLASS_LETTER = {"translational": "T", "rotational": "R", "both": "B", "negligible": "N"}


def payload_figure(ds):
    """share_tran and dominance class of every element vs payload, and peak |tau| vs payload.

    Parameters
    ----------
    ds : xarray.Dataset
        A payload sweep from :func:`gd_analyze.workflows.payload.payload_sweep`: coordinate ``payload``
        (P,) [kg]; ``share_tran`` and ``dominance`` (payload, element); ``tau_peak``
        (payload, joint) [N m or N] and ``joint_type`` (joint; all revolute if absent).

    Returns
    -------
    matplotlib.figure.Figure
        Top: a heat map of share_tran over (payload, element) from rotational (0, orange)
        through 0.5 (white) to translational (1, blue), each cell marked with its class (T, R,
        B or N) and with a bold frame where the class differs from that at the first payload.
        Bottom: peak |tau| per joint vs payload [N m, or N for a prismatic joint: in the key
        when the joints differ]. A plain Figure (no pyplot state).

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

    check(ds, PAYLOAD_REQUIRED, "payload sweep")
    with style(SUPTITLE_RC):
        masses = ds["payload"].values
        labels = strings(ds["element"].values)
        share = ds["share_tran"].values
        dom = np.array(strings(ds["dominance"].values)).reshape(share.shape)
        P, M = share.shape
        n = ds.sizes["joint"]
        W = PAGE_WIDTH
        heat_h = max(1.4, 0.3 * P)
        H = heat_h + 4.6
        fig = Figure(figsize=(W, H))
        ax = fig.add_axes((0.9 / W, (H - 0.75 - heat_h) / H, (W - 2.0) / W, heat_h / H))
        cmap = LinearSegmentedColormap.from_list(
            "rot_tran", [CLASS_COLOURS["rotational"], "#FFFFFF",
                         CLASS_COLOURS["translational"]]).with_extremes(bad="0.8")
        im = ax.imshow(np.ma.masked_invalid(share), aspect="auto", cmap=cmap, vmin=0, vmax=1,
                       interpolation="nearest")
        for p in range(P):
            for k in range(M):
                v = share[p, k]
                dark = np.isfinite(v) and abs(v - 0.5) > 0.33
                ax.text(k, p, CLASS_LETTER.get(dom[p, k], "?"), ha="center", va="center",
                        fontsize=7, color="white" if dark else "black")
                if dom[p, k] != dom[0, k]:
                    ax.add_patch(Rectangle((k - 0.5, p - 0.5), 1, 1, fill=False, lw=1.4,
                                           ec="black"))
        ax.set_xticks(np.arange(M), labels, rotation=90, fontsize=7)
        ax.set_yticks(np.arange(P), [f"{m:g}" for m in masses], fontsize=7)
        ax.set_ylabel("payload [kg]")
        ax.grid(False)
        cax = fig.add_axes(((W - 0.95) / W, (H - 0.75 - heat_h) / H, 0.12 / W, heat_h / H))
        cb = fig.colorbar(im, cax=cax)
        cb.set_label("translational share [1]")
        bx = fig.add_axes((0.9 / W, 0.6 / H, (W - 2.0) / W, 2.6 / H))
        tau = ds["tau_peak"].values
        units = torque_units(ds)            # N m, N on a prismatic joint
        mixed = len(set(units)) > 1
        for j in range(n):                  # told apart by line style and marker too
            bx.plot(masses, tau[:, j], linewidth=0.9, **joint_style(j, len(masses)),
                    label=f"joint {j + 1}" + (f" [{units[j]}]" if mixed else ""))
        bx.set_xlabel("payload [kg]")
        bx.set_ylabel("peak |\u03c4|" + ("" if mixed else f" [{units[0]}]"))
        bx.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), frameon=False, fontsize=7)
        s, e = thresholds(ds)
        fig.suptitle(f"Dominance against the payload on the last link (s = {s:g}, e = {e:g})\n"
                     "T/R/B/N = translational/rotational/both/negligible; framed: class "
                     "differs from the first payload", y=1 - 0.08 / H, va="top", fontsize=8.5)
        return fig
