"""The identify report (report.html, report.pdf) from stored identification datasets built
here in the identify command's layout: every error and parameter shown is the dataset's
(recomputed here from the torques and parameters, not copied from the report), the figures show
the validation recordings, hostile joint, file and robot names stay text, and a dataset in the
issue's bare layout (role as a variable, no robot file's torque) is reported too."""

import json
import math
import re
from html.parser import HTMLParser

import numpy as np
import pytest
import xarray as xr
from html_checks import html_table, html_text
from pdf_checks import info, text
from table_checks import csv_matches_html

from gd_analyze.errors import InputError
from gd_analyze.report.identify import (
    MAX_POINTS,
    TITLE_CHARS,
    identify_context,
    identify_figures,
    write_identify_report,
)
from gd_analyze.report.numbers import pct

#: Names that would open a script element, end an attribute, run mathtext and Typst markup.
HOSTILE = '<script>alert(1)</script><gdinjected onload="x"> $\\frac{1}{0}$ #panic("x") *b*'
NAMES = ("ZZ1", "MX2", "M2", "viscous_1", "viscous_2", "coulomb_1", "coulomb_2", "offset_1",
         "offset_2")
KINDS = ("base", "base", "base", "viscous", "viscous", "coulomb", "coulomb", "offset", "offset")


def _recording(rng, t0, samples, role, name, joints, prior=True, role_variable=False):
    t = t0 + np.cumsum(rng.uniform(0.005, 0.015, samples))
    measured = np.stack([np.sin(t * (j + 1)) * (5 + j) for j in range(len(joints))], 1)
    predicted = measured + rng.normal(0, 0.05, measured.shape)
    E = measured - predicted
    data = {"q": (("t", "joint"), np.cos(t)[:, None] * np.ones((1, len(joints)))),
            "tau_measured": (("t", "joint"), measured),
            "tau_predicted": (("t", "joint"), predicted),
            "rms_error": (("joint",), np.sqrt((E ** 2).mean(0))),
            "relative_error": (("joint",), np.linalg.norm(E, axis=0)
                               / np.linalg.norm(measured, axis=0))}
    attrs = {"file": f"/data/{name}.csv", "sha256": "ab" * 32,
             "total_relative_error": float(np.linalg.norm(E) / np.linalg.norm(measured)),
             "notes": json.dumps([f"{name}: resampled onto a uniform 10 ms clock"])}
    if prior:
        tau_prior = measured * 1.3
        P = measured - tau_prior
        data["tau_prior"] = (("t", "joint"), tau_prior)
        data["prior_relative_error"] = (("joint",), np.linalg.norm(P, axis=0)
                                        / np.linalg.norm(measured, axis=0))
        attrs["prior_total_relative_error"] = float(np.linalg.norm(P)
                                                    / np.linalg.norm(measured))
    if role_variable:
        data["role"] = ((), role)
    else:
        attrs["role"] = role
    return xr.Dataset(data, coords={"t": t, "joint": list(joints)}, attrs=attrs)


def _root(rng, joints, robot="arm"):
    p = len(NAMES)
    value = rng.uniform(0.5, 2.0, p) * rng.choice([-1, 1], p)
    identifiable = np.ones(p, bool)
    identifiable[2] = False
    return xr.Dataset(
        {"value": (("parameter",), value), "std": (("parameter",), np.abs(value) * 0.03),
         "prior": (("parameter",), value * 1.1), "identifiable": (("parameter",), identifiable),
         "kind": (("parameter",), np.array(KINDS)),
         "noise_std": (("joint",), np.full(len(joints), 0.05)),
         "link_consistent": (("link",), np.array([True, False])),
         "pseudo_inertia_min_eigenvalue": (("link",), np.array([0.01, -0.2]))},
        coords={"parameter": list(NAMES), "joint": list(joints), "link": [1, 2]},
        attrs={"gd_analyze_version": "0.1.0", "robot": robot, "robot_source": "arm.urdf",
               "robot_sha256": "cd" * 32, "condition_number": 123.456, "rank": p - 1,
               "unidentifiable": json.dumps(["M2"]),
               "preprocessing": json.dumps(["low-pass cutoff 2 Hz", "decimated by 1"]),
               "settings": json.dumps({"cutoff_hz": "auto", "drives": ["viscous"]}),
               "inputs": json.dumps({"/data/fit.csv": "ab" * 32}),
               "standard_method": "closest to the robot file", "coulomb_model": "sign(qd)"})


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    rng = np.random.default_rng(4)
    joints = ("shoulder", HOSTILE)
    root = _root(rng, joints, robot=HOSTILE)
    groups = {"fit": _recording(rng, 0.0, 3000, "train", "fit", joints),
              "held_out": _recording(rng, 50.0, 400, "validate", HOSTILE, joints)}
    folder = tmp_path_factory.mktemp("identify")
    files = write_identify_report(root, groups, folder)
    return root, groups, folder, files


class _Tags(HTMLParser):
    def __init__(self):
        super().__init__()
        self.tags = []

    def handle_starttag(self, tag, attrs):
        self.tags.append((tag, attrs))


@pytest.mark.slow
def test_files_and_the_errors_shown_are_the_datasets(report):
    root, groups, folder, files = report
    assert [f.name for f in files[:2]] == ["report.html", "report.pdf"]   # docs: the report files
    assert {f.name for f in files[2:] if f.parent.name == "figures"} == {
        f"fig_identify_{k}_0.{e}" for k in ("torque", "residual") for e in ("pdf", "svg")}
    html = (folder / "report.html").read_text(encoding="utf-8")
    # every table also as CSV, with the HTML table's numbers
    assert {f.parent.name for f in files[2:]} == {"figures", "tables"}
    assert csv_matches_html(folder / "tables", "table_", html) > 10
    rows = html_table(html, "Total relative torque error", nbsp=True)
    assert rows[0] == ["recording", "role", "samples", "duration [s]", "identified model",
                       "robot file as shipped"]
    for row, ds in zip(rows[1:], groups.values()):
        M, P = ds["tau_measured"].values, ds["tau_prior"].values
        total = np.linalg.norm(M - ds["tau_predicted"].values) / np.linalg.norm(M)
        assert row[4] == pct(total) and row[5] == pct(np.linalg.norm(M - P) / np.linalg.norm(M))
        assert row[2] == f"{ds.sizes['t']:,}"
    lead = html_text(html, nbsp=True)
    held = groups["held_out"]
    assert (f"the identified model's total relative torque error ||E||_F / ||T||_F is "
            f"{pct(held.attrs['total_relative_error'])}") in lead
    assert "the robot file's as shipped, 30.00 %" in lead          # tau_prior = 1.3 tau
    joint_rows = html_table(html, "Errors per joint on /data/fit.csv", nbsp=True)
    E = groups["fit"]["tau_measured"].values - groups["fit"]["tau_predicted"].values
    rel = np.linalg.norm(E, axis=0) / np.linalg.norm(groups["fit"]["tau_measured"].values,
                                                     axis=0)
    assert [r[3] for r in joint_rows[1:]] == [pct(v) for v in rel]


@pytest.mark.slow
def test_parameter_table_std_percent_and_identifiability(report):
    root, _, folder, _ = report
    html = (folder / "report.html").read_text(encoding="utf-8")
    rows = html_table(html, "Identified parameters", nbsp=True)
    assert rows[0] == ["parameter", "units", "value", "std", "std [%]", "robot file",
                       "identifiable"]
    assert [r[0] for r in rows[1:]] == list(NAMES)
    for r, v, s, ok in zip(rows[1:], root["value"].values, root["std"].values,
                           root["identifiable"].values):
        assert r[6] == ("yes" if ok else "no")
        assert r[4] == (pct(s / abs(v)) if ok else "\u2014")       # 3.00 %
    units = {r[0]: r[1] for r in rows[1:]}
    assert units["ZZ1"] == "kg m\u00b2" and units["MX2"] == "kg m" and units["M2"] == "kg"
    assert units["viscous_1"] == "N m s/rad" and units["offset_2"] == "N m"
    assert "1 not identifiable on the data: M2" in html_text(html)
    assert "condition number of the column-scaled regressor is 123.5" in html_text(html)
    links = html_table(html, "Physical consistency")
    assert [r[2] for r in links[1:]] == ["yes", "no"]


@pytest.mark.slow
def test_hostile_names_are_text_in_html_and_pdf(report):
    _, _, folder, _ = report
    html = (folder / "report.html").read_text(encoding="utf-8")
    parser = _Tags()
    parser.feed(html)
    tags = {t for t, _ in parser.tags}
    assert "script" not in tags and "gdinjected" not in tags
    assert not any(a.startswith("on") for _, attrs in parser.tags for a, _ in attrs)
    assert HOSTILE in html_text(html)
    pdf = re.sub(r"\s+", " ", text(folder / "report.pdf"))
    assert "#panic(\"x\") *b*" in pdf and "$\\frac{1}{0}$" in pdf
    assert int(info(folder / "report.pdf")["Pages"]) >= 3
    svg = (folder / "figures" / "fig_identify_torque_0.svg").read_text(encoding="utf-8")
    assert "&lt;script&gt;" in svg and "<script" not in svg


@pytest.mark.slow
def test_figures_show_the_validation_recordings_and_their_curves(report):
    root, groups, _, _ = report
    figs = identify_figures(root, groups)
    assert set(figs) == {"torque_0", "residual_0"}                  # only the held-out one
    held = groups["held_out"]
    ax = figs["torque_0"].axes[1]
    title = ax.title if ax.get_title(loc="left") == "" else ax._left_title
    assert title.get_text() == f"joint 2: {HOSTILE[:TITLE_CHARS - 1]}\u2026"
    assert not title.get_parse_math()
    lines = ax.get_lines()
    assert len(lines) == 3                          # measured, identified, robot file
    np.testing.assert_array_equal(lines[0].get_ydata(), held["tau_measured"].values[:, 1])
    np.testing.assert_array_equal(lines[2].get_ydata(), held["tau_prior"].values[:, 1])
    res = figs["residual_0"].axes[0].get_lines()[0].get_ydata()
    np.testing.assert_allclose(res, held["tau_measured"].values[:, 0]
                               - held["tau_predicted"].values[:, 0], rtol=0, atol=0)


def test_the_issues_layout_without_validation_or_robot_file():
    """Role as a variable, no robot file's torque, no validation recording: the figures show
    the training recordings and the lead says no recording was held out; a long recording is
    drawn one sample in k, and the note says so."""
    rng = np.random.default_rng(5)
    joints = ("a", "b")
    root = _root(rng, joints).drop_vars(["prior", "link_consistent",
                                         "pseudo_inertia_min_eigenvalue"])
    groups = {"run": _recording(rng, 0.0, 2 * MAX_POINTS + 10, "train", "run", joints,
                                prior=False, role_variable=True)}
    ctx = identify_context(root, groups)
    assert "No recording was held out for validation" in ctx["lead"]
    assert ctx["shown"] == ["run"] and "one sample in 3" in ctx["shown_note"]
    assert ctx["links"] is None
    assert ctx["recordings"]["header"][-1] == "identified model"
    figs = identify_figures(root, groups)
    assert len(figs["torque_0"].axes[0].get_lines()) == 2       # measured, identified
    assert len(figs["torque_0"].axes[0].get_lines()[0].get_ydata()) == math.ceil(
        (2 * MAX_POINTS + 10) / 3)


def test_a_dataset_without_the_required_variables_is_refused(tmp_path):
    rng = np.random.default_rng(6)
    root = _root(rng, ("a", "b"))
    with pytest.raises(InputError, match="lacks value"):
        write_identify_report(root.drop_vars("value"), {}, tmp_path)
    with pytest.raises(InputError, match="no recording"):
        write_identify_report(root, {}, tmp_path)
    bad = _recording(rng, 0.0, 10, "train", "x", ("a", "b")).drop_vars("tau_predicted")
    with pytest.raises(InputError, match="lacks tau_predicted"):
        write_identify_report(root, {"x": bad}, tmp_path)
    assert not list(tmp_path.iterdir())


def test_a_prismatic_joints_torque_is_in_newtons():
    """A prismatic joint's panel says N, a revolute one's N m (the TIAGo's torso said N m)."""
    rng = np.random.default_rng(6)
    joints = ("torso", "arm")
    root = _root(rng, joints).assign(prismatic=("joint", np.array([True, False])))
    groups = {"run": _recording(rng, 0.0, 200, "validate", "run", joints)}
    figs = identify_figures(root, groups)
    for key, word in (("torque_0", "\u03c4"), ("residual_0", "\u03c4 residual")):
        labels = [ax.get_ylabel() for ax in figs[key].axes if ax.get_visible()]
        assert labels[:2] == [f"{word} [N]", f"{word} [N m]"], labels


def test_every_panel_states_its_own_scaled_unit_beside_it_and_no_offset_text():
    """A prismatic first joint (N) and seven revolute ones (N m), three a row, residuals of
    0.8 to 0.004 as the TIAGo's: each panel says its quantity and its unit, scaled by the power
    of ten its ticks are written in, in its own y label (before, a panel whose unit read as its
    left neighbour's was unlabelled but for a bare "×10⁻¹" in place of a label, so that a
    reader combined two conventions). Oracles: each drawn tick label times the label's power
    is the tick's value; the labels stand clear of every other text and panel."""
    from figure_checks import collisions, tick_texts

    from gd_analyze.report.identify import FIGURE_RC

    rng = np.random.default_rng(7)
    joints = tuple(f"j{k}" for k in range(8))
    prismatic = np.array([True] + [False] * 7)
    root = _root(rng, joints).assign(prismatic=("joint", prismatic))
    run = _recording(rng, 0.0, 300, "validate", "run", joints)
    size = np.array([0.8, 0.15, 0.8, 0.25, 0.3, 0.02, 0.008, 0.004])
    residual = size * np.sin(np.outer(run.t, np.arange(1, 9)))
    run["tau_predicted"] = run.tau_measured - residual
    digits = str.maketrans("⁻⁰¹²³⁴⁵⁶⁷⁸⁹", "-0123456789")
    for key, fig in identify_figures(root, {"run": run}).items():
        found = collisions(fig, FIGURE_RC)         # drawn: the tick labels are written
        axes = [ax for ax in fig.axes if ax.get_visible()]
        assert len(axes) == 8
        for ax, p in zip(axes, prismatic):
            said = re.fullmatch(r"τ( residual)? \[(?:10([⁻⁰-⁹¹²³]+) )?(N m|N)\]", ax.get_ylabel())
            assert said and said[3] == ("N" if p else "N m"), (key, ax.get_ylabel())
            offset = ax.yaxis.get_offset_text()
            assert not (offset.get_visible() and offset.get_text().strip()), key
            power = 10.0 ** int((said[2] or "0").translate(digits))
            for at, label in tick_texts(ax):
                written = float(label.get_text().replace("\u2212", "-"))
                assert written * power == pytest.approx(at, rel=1e-6, abs=1e-12), (key, at)
        scaled = [ax.get_ylabel() for ax in axes if "10" in ax.get_ylabel()]
        assert key.startswith("torque") or len(scaled) == 8, scaled   # every residual < 1
        assert not found, found[:4]


def test_the_preprocessing_notes_are_sentences_with_s_i_typeset():
    """The job's notes are stored as clauses ("low-pass cutoff 2 Hz", "simplified model ...:
    within 1 % of s_i ..."); the report sets each as a sentence, capital first and a full
    stop last, with s_i as s with subscript i, not the letters "s_i"."""
    from gd_analyze.report.markup import sub

    rng = np.random.default_rng(6)
    joints = ("a", "b")
    root = _root(rng, joints)
    root.attrs["preprocessing"] = json.dumps(
        ["low-pass cutoff 2 Hz", "simplified model of the identified robot: within 1 % of s_i"])
    groups = {"run": _recording(rng, 0.0, 300, "train", "run", joints)}
    said = identify_context(root, groups)["preprocessing"]
    assert said == ["Low-pass cutoff 2 Hz.",
                    "Simplified model of the identified robot: within 1\u00a0% of s" + sub("i")
                    + "."]                                      # no line break before %


def test_six_joints_are_drawn_three_a_row_at_page_width():
    """Two a row, six joints' panels made each figure 6 in tall, so that it left half a page
    empty before it and after it (5 pages, measured on a PUMA 560 run; 4 now): from five
    joints on, three a row at page width; two a row in a column, and for fewer joints."""
    from gd_analyze.report.identify import PAGE_WIDTH

    rng = np.random.default_rng(6)
    for n, width, cols in ((6, PAGE_WIDTH, 3), (5, PAGE_WIDTH, 3), (4, PAGE_WIDTH, 2),
                           (6, 3.4, 2)):
        joints = tuple(f"j{k}" for k in range(n))
        groups = {"run": _recording(rng, 0.0, 200, "train", "run", joints)}
        figs = identify_figures(_root(rng, joints), groups, width=width)
        for fig in figs.values():
            panels = [ax for ax in fig.axes if ax.get_title(loc="left")]
            lefts = {round(ax.get_position().x0, 3) for ax in panels}
            assert len(panels) == n and len(lefts) == cols, (n, width, sorted(lefts))
            assert fig.get_size_inches()[1] <= 1.6 * math.ceil(n / cols) + 1.2


def test_float_settings_are_shown_to_six_significant_digits_and_stored_whole():
    """The provenance table showed a float setting as the JSON stores it, 17 digits
    (cutoff_hz_used 12.345678901234567); it shows 6 significant digits (oracle: Python's
    "%.6g" of the stored number), a list of them joined by ", ", other settings as before;
    the stored JSON keeps every digit."""
    rng = np.random.default_rng(7)
    joints = ("a", "b")
    root = _root(rng, joints)
    cutoff, idle = 12.345678901234567, [0.027290053386426198, 3.4567890123456e-05]
    settings = {"cutoff_hz_used": cutoff, "idle_threshold": idle, "decimate": 1,
                "drives": ["viscous"], "drive_gains": None, "cutoff_hz": "auto"}
    root.attrs["settings"] = json.dumps(settings)
    groups = {"run": _recording(rng, 0.0, 300, "train", "run", joints)}
    rows = dict(identify_context(root, groups)["provenance"]["rows"])
    assert rows["setting cutoff_hz_used"] == f"{cutoff:.6g}" == "12.3457"
    assert rows["setting idle_threshold"] == ", ".join(f"{x:.6g}" for x in idle)
    assert [rows[f"setting {k}"] for k in ("decimate", "drives", "drive_gains", "cutoff_hz")] \
        == ["1", '["viscous"]', "null", "auto"]
    assert json.loads(root.attrs["settings"])["idle_threshold"] == idle


def test_a_reader_s_note_names_its_file_once():
    """The reader's notes start with the file ("/data/run.csv: 2 rows repeat an earlier time
    stamp ..."), and the report names the file before a recording's notes: the file stood twice
    ("run.csv: run.csv: ..."). Oracle: the stored notes and the file's name."""
    rng = np.random.default_rng(8)
    rec = _recording(rng, 0.0, 300, "train", "run", ("a", "b"))
    rec.attrs["notes"] = json.dumps(["/data/run.csv: 2 rows repeat an earlier time stamp (first "
                                     "at row 9): the first row of each stamp kept",
                                     "run: resampled onto a uniform 10 ms clock"])
    ctx = identify_context(_root(rng, ("a", "b")), {"run": rec})
    assert ctx["files"]["run"] == "/data/run.csv"
    assert ctx["notes"]["run"] == ["2 rows repeat an earlier time stamp (first at row 9): the "
                                   "first row of each stamp kept.",
                                   "run: resampled onto a uniform 10 ms clock."]


def test_the_robot_file_stands_once_in_the_provenance():
    """identification.h5's inputs hold the recordings' files and the robot file; the provenance
    table showed the robot file twice, as "robot file" with its SHA-256 and again as an "input"
    row. Oracle: the stored inputs and robot_source."""
    rng = np.random.default_rng(9)
    root = _root(rng, ("a", "b"))
    root.attrs["inputs"] = json.dumps({"/data/fit.csv": "ab" * 32, "arm.urdf": "cd" * 32})
    rows = identify_context(root, {"run": _recording(rng, 0.0, 300, "train", "run", ("a", "b"))}
                            )["provenance"]["rows"]
    assert [k for k, _ in rows if "arm.urdf" in k or k.startswith("input")] == [
        "input /data/fit.csv"]
    assert dict(rows)["robot file"] == "arm.urdf"
