"""The sweep figures' keys and class fractions wrapped from their pieces' widths: the lines
break where measuring each line whole, at every part, breaks them."""

from __future__ import annotations

import functools

import matplotlib
import numpy as np
import pytest
from matplotlib.backends.backend_agg import RendererAgg
from matplotlib.font_manager import FontProperties

from gd_analyze.report.sweep import ROUND_OFF_WORDS, _width, _wrapped

#: A key of the sweep's share figures, its class fractions, and words of other kinds.
TEXTS = [
    ("Box: quartiles; whiskers: min and max over 20 trajectories; dashed lines at s = 0.05 "
     "and 1 - s; an element round-off (" + ROUND_OFF_WORDS + ") on a trajectory is left out "
     "of its box. T: translational, R: rotational, B: both, N: negligible.").split(),
    ["T 94%", "R 3%", "B 2%", "N 0.4%"],
    ["AVAVAV", "T.T.", "(ε)", "≡ 0", "10⁻¹²", "W", "iiii", "WWWW", "—", "m²"],
]


def _whole(text, size):
    """The width [in] of one line measured whole, as the sweep report measured it before."""
    return _measured_whole(text, size, float(matplotlib.rcParams["figure.dpi"]),
                           tuple(matplotlib.rcParams["font.family"]))


@functools.cache
def _measured_whole(text, size, dpi, family):
    width, _, _ = RendererAgg(1, 1, dpi).get_text_width_height_descent(
        text, FontProperties(size=size), ismath=False)
    return width / dpi


def _wrapped_whole(parts, room, size, sep):
    lines: list[str] = []
    for part in parts:
        if lines and _whole(lines[-1] + sep + part, size) <= room:
            lines[-1] += sep + part
        else:
            lines.append(part)
    return "\n".join(lines)


@pytest.mark.parametrize("size", [7.0, 7.5])
def test_the_lines_break_where_whole_lines_measured_break_them(size):
    for parts in TEXTS:
        for sep in (" ", " \u00b7 "):
            for room in np.linspace(0.1, 6.0, 20):
                assert _wrapped(parts, room, size, sep) == _wrapped_whole(parts, room, size, sep)
    assert _width("T 94% \u00b7 N 6%", size) == _whole("T 94% \u00b7 N 6%", size)


def test_a_width_is_measured_anew_where_the_font_changes():
    text = "translational share"
    with matplotlib.rc_context({"figure.dpi": 100.0}):
        at_100 = _width(text, 8.0)
    with matplotlib.rc_context({"figure.dpi": 200.0}):
        at_200 = _width(text, 8.0)
        assert at_200 == _whole(text, 8.0)
    with matplotlib.rc_context({"font.family": "DejaVu Serif", "figure.dpi": 100.0}):
        assert _width(text, 8.0) == _whole(text, 8.0) != at_100
