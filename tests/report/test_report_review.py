"""Defects a reader of the rendered reports found in a review, each checked on the reports
as written for the PUMA 560, the Stanford arm (joint 3 prismatic) and the UR5, and on the sweep
and control reports:

- every count prints with a thousands separator, in the text and the tables alike (the
  formulation table printed "22911" while the text wrote "1,212");
- a translational share that is not exactly 1 (or 0) never prints as "1" (or "0");
- Fig. 1's caption names the joints whose curves coincide (oracle: the trajectory file's own
  columns);
- a prismatic joint's q is given in one unit, mm, in Table 1.5 and Fig. 1 alike (oracle: the
  trajectory file);
- no robot-file key (``tau_max``) stands in plain type in the text.
"""

import re
from html import unescape

import numpy as np
import pytest
import xarray as xr
from conftest import ROOT
from pdf_checks import page_texts

#: Over 5 s on an idle machine (the module's fixtures): run on one interpreter in CI.
pytestmark = pytest.mark.slow

DATA = ROOT / "data"
MAIN = {"puma": ("puma560", "puma560_trajectory.csv"),
        "stanford": ("stanford", "stanford_trajectory.csv"),
        "ur5": ("ur5", "ur5_trajectory.csv")}


@pytest.fixture(scope="module")
def reports(shared_main, shared_reports, shared_puma):
    """The main report of the three robots (all shared); the sweep and the control report on
    the PUMA (shared)."""
    out = {k: (shared_main(robot, DATA / csv), "report")
           for k, (robot, csv) in MAIN.items() if k not in ("ur5", "puma")}
    out["ur5"], out["sweep"] = shared_reports["ur5"], shared_reports["sweep"]
    out["puma"], out["control"] = shared_puma["puma"], shared_puma["control"]
    return out


def _html_text(reports, which):
    folder, stem = reports[which]
    html = (folder / f"{stem}.html").read_text(encoding="utf-8")
    html = re.sub(r"<(svg|style|script)\b.*?</\1>", "", html, flags=re.S)
    return unescape(re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", html))).replace("\u00a0", " ")


def _pdf_text(reports, which):
    folder, stem = reports[which]
    return "\n".join(page_texts(folder / f"{stem}.pdf"))


def _bare_integers(text):
    """Integers of four digits or more written without a thousands separator; hashes, dates
    and years (1950-2030) are not counts."""
    text = re.sub(r"\b[0-9a-f]{16,}\b", " ", text)                    # SHA-256 digests
    text = re.sub(r"\d{4}-\d\d-\d\dT[\d:+\-]+", " ", text)             # ISO times
    text = re.sub(r"\b\d+\.\d+\.\d+\.\d+:\d+\b", " ", text)             # host:port
    found = re.findall(r"(?<![\w.,+\-\u2212/])\d{4,}(?![\w,]|\.\d)", text)
    return [f for f in found if not (len(f) == 4 and 1950 <= int(f) <= 2030)]


@pytest.mark.parametrize("which", [*MAIN, "sweep", "control"])
def test_counts_have_thousands_separators(reports, which):
    for text in (_html_text(reports, which), _pdf_text(reports, which)):
        assert _bare_integers(text) == []


def test_operation_counts_are_printed_as_stored(reports):
    """Oracle: the counts stored in the results file, each printed as 12,744 in Table 7.2."""
    folder = reports["puma"][0]
    with xr.open_dataset(folder / "results.h5") as ds:
        counts = [int(v) for v in np.ravel(ds["op_multiplications_arm"].values)]
    text = _html_text(reports, "puma")
    big = [c for c in counts if c >= 1000]
    assert big                                          # Lagrange-Euler's thousands
    for c in big:
        assert f"{c:,}" in text


def test_a_share_below_one_never_prints_as_one(reports):
    """A share 1 - 3e-5 printed "1" in Table 4.1; a share in (0, 1) must print as neither 0
    nor 1, and as a number that is true of it."""
    from gd_analyze.report.main_context import report_context

    with xr.open_dataset(reports["puma"][0] / "results.h5") as ds:
        ds = ds.load()
    labels = [str(v) for v in ds["element"].values]
    peaks = ds["peak_tran"].values, ds["peak_rot"].values
    both = [k for k in range(len(labels))
            if min(peaks[0][k], peaks[1][k]) > 1e-6 * ds["peak_total"].values[k]]
    assert len(both) >= 4
    shares = {both[0]: 1 - 3e-5, both[1]: 0.99962, both[2]: 2e-5, both[3]: 0.0004}
    for k, v in shares.items():
        ds["share_tran"].values[k] = v
    ctx = report_context(ds)
    cells = {row[0]: row[1] for row in ctx["ranking"]["rows"]}
    from gd_analyze.report.markup import plain

    by_label = {plain(k).translate(str.maketrans("\u2080\u2081\u2082\u2083\u2084\u2085\u2086"
                                                 "\u2087\u2088\u2089", "0123456789")): c
                for k, c in cells.items()}
    for k, v in shares.items():
        cell = by_label[labels[k]]
        assert cell not in ("0", "1"), (labels[k], v, cell)
        if cell.startswith(">"):
            assert v > float(cell[1:])
        elif cell.startswith("<"):
            assert v < float(cell[1:])
        else:
            assert 0 < float(cell) < 1 and abs(float(cell) - v) <= 5e-4 * max(v, 1e-3)


def _alike_in_file(csv):
    """Groups of joints whose q, qd and qdd columns in the trajectory file are equal (to
    1e-12 of their peak): the oracle."""
    d = np.genfromtxt(DATA / csv, delimiter=",", names=True)
    n = sum(1 for name in d.dtype.names if re.fullmatch(r"q\d+", name))
    same = {}
    for i in range(1, n + 1):
        for j in range(i + 1, n + 1):
            if all(np.max(np.abs(d[f"{a}{i}"] - d[f"{a}{j}"]))
                   <= 1e-12 * max(np.max(np.abs(d[f"{a}{i}"])), np.max(np.abs(d[f"{a}{j}"])))
                   for a in ("q", "qd", "qdd")):
                same.setdefault(i, [i]).append(j)
    return [g for g in same.values()]


@pytest.mark.parametrize("which", list(MAIN))
def test_fig1_caption_names_the_joints_whose_curves_coincide(reports, which):
    groups = _alike_in_file(MAIN[which][1])
    if which == "puma":
        assert groups == [[1, 5]]                 # the shipped trajectories
    if which == "ur5":
        assert groups == [[1, 6]]
    for text in (_html_text(reports, which), re.sub(r"\s+", " ", _pdf_text(reports, which))):
        caption = text[text.index("Figure 1."):text.index("Figure 2.")]
        assert caption.count("move alike") == len(groups)
        for g in groups:
            names = ", ".join(map(str, g[:-1])) + f" and {g[-1]}"
            assert f"Joints {names} move alike: their curves coincide" in caption


def test_prismatic_q_in_one_unit_in_table_and_figure(reports):
    """Stanford joint 3: Table 1.5 gave m, Fig. 1 mm. Oracle: the file's q3 [m] x 1000."""
    d = np.genfromtxt(DATA / "stanford_trajectory.csv", delimiter=",", names=True)
    folder = reports["stanford"][0]
    svg = (folder / "figures" / "fig_joints_q_qd_qdd.svg").read_text(encoding="utf-8")
    labels = re.findall(r"q[\u0307\u0308]? \[(mm[^\]]*|m[^\]m]*)\]", unescape(svg))
    assert labels and set(labels) == {"mm", "mm/s", "mm/s\u00b2"}
    for text in (_html_text(reports, "stanford"), _pdf_text(reports, "stanford")):
        row = re.search(r"\b3 prismatic (\S+) (\S+) (\S+) (\S+) (.*?\u00b2)", text)
        assert row, text[:2000]
        assert row.group(5) == "mm, mm/s, mm/s\u00b2"
        lo, hi = (float(row.group(k).replace("\u2212", "-").replace(",", "")) for k in (1, 2))
        assert lo == pytest.approx(1000 * d["q3"].min(), rel=1e-3)
        assert hi == pytest.approx(1000 * d["q3"].max(), rel=1e-3)


@pytest.mark.parametrize("which", list(MAIN))
def test_no_robot_file_key_in_plain_type(reports, which):
    for text in (_html_text(reports, which), _pdf_text(reports, which)):
        assert not re.search(r"\btau_max\b|<limit effort>", text)


@pytest.mark.parametrize("which", ["puma", "stanford", "ur5", "sweep", "control"])
def test_a_percentage_keeps_its_sign_on_the_numbers_line(reports, which):
    """In the HTML, the space between a number and its "%" does not break ("1.23" at a line's
    end, "% of s_i" starting the next): it is a no-break space, in the text and the tables
    (the PDF template keeps them together by its own rule, tests/report/test_typeset.py)."""
    folder, stem = reports[which]
    html = (folder / f"{stem}.html").read_text(encoding="utf-8")
    html = re.sub(r"<(svg|style|script)\b.*?</\1>", "", html, flags=re.S)
    text = unescape(re.sub(r"<[^>]+>", "", html))
    kept = re.findall(r"\d\u00a0%", text)
    broken = re.findall(r"[^\n]{0,30}\d[ \t\n]+%[^\n]{0,10}", text)
    assert kept and not broken, broken[:5]
