"""Units from the joint types in every table, axis, caption and stored attribute.

The Stanford arm's third joint is prismatic. Dimensional analysis is the oracle: q_3 is a
length, so tau_3 = dL/dq_3 is a force [N], D_i3 = dtau_i/dqdd_3 is kg m for a revolute i and
kg for i = 3, and h_3, c_3 are forces. Nothing here is read from the code under test.
"""

import re
from html import unescape

import numpy as np
import pytest
import xarray as xr
from conftest import ROOT
from html_checks import html_tables as tables_of
from html_checks import without_figures as _html_without_svg

from gd_analyze.cli import main

#: Over 5 s on an idle machine (the module's fixtures): run on one interpreter in CI.
pytestmark = pytest.mark.slow

PRISMATIC = [False, False, True, False, False, False]          # Stanford: joint 3 slides
N_JOINTS = len(PRISMATIC)


def _d_units(i, j):
    linear = PRISMATIC[i] + PRISMATIC[j]                      # each prismatic index: one m less
    return ["kg m²", "kg m", "kg"][linear]


def _tau_units(i):
    return "N" if PRISMATIC[i] else "N m"


EXPECTED = ([(f"D{i + 1}{j + 1}", _d_units(i, j)) for i in range(N_JOINTS)
             for j in range(i, N_JOINTS)]
            + [(f"h{i + 1}", _tau_units(i)) for i in range(N_JOINTS)])


@pytest.fixture(scope="module")
def stanford(shared_main):
    """The main job on the Stanford arm's shipped trajectory (shared: read only)."""
    return shared_main("stanford", ROOT / "data" / "stanford_trajectory.csv")


def _svg_texts(svg):
    return [unescape(t).strip() for t in re.findall(r"<text[^>]*>([^<]*)", svg)]


def test_ranking_table_gives_each_element_its_units(stanford):
    html = (stanford / "report.html").read_text()
    table = next(t for t in tables_of(html) if t and t[0][:2] == ["element", "translational share"])
    units = {row[0]: row[table[0].index("units")] for row in table[1:]}
    assert units == dict(EXPECTED)     # D<sub>12</sub> read without its tags


def test_per_joint_torque_tables_give_n_for_the_prismatic_joint(stanford):
    """Every table with a row per joint and a torque column: joint 3's torques are in N."""
    html = (stanford / "report.html").read_text()
    checked = 0
    for table in tables_of(html):
        head = table[0] if table else []
        if not head or head[0] != "joint" or not any("\u03c4" in h for h in head):
            continue
        checked += 1
        assert not any("[N m]" in h for h in head), head     # one unit for a mixed column
        col = head.index("units")
        assert [row[col] for row in table[1:]] == [_tau_units(i) for i in range(N_JOINTS)]
    assert checked >= 2                                       # Sec. 5.1 and Sec. 5.3


def test_report_text_claims_no_single_unit_for_mixed_quantities(stanford):
    """Captions and paragraphs: no "[N m]" or D in "[kg m²]" alone, no "deg/s/s"."""
    text = unescape(_html_without_svg((stanford / "report.html").read_text()))
    text = text.replace("\u00a0", " ")                 # no-break spaces inside units
    assert "[N m]" not in text
    assert "/s/s" not in text and "/s\u00b2/s\u00b2" not in text
    for m in re.finditer(r"\[kg m\u00b2\]", text):
        before = text[max(0, m.start() - 4):m.start()]
        # an inertia tensor's element, or a base parameter's inertia name (XXj .. ZZj)
        assert re.search(r"(I[xyz]{2}|[XYZ]{2}j) $", before), \
            text[max(0, m.start() - 80):m.end()]
    caption = re.search(r"Figure 1\.[^<]*", text).group(0)
    assert "deg/s\u00b2" in caption and "mm/s\u00b2" in caption and "joint 3" in caption


def test_figure_1_separates_revolute_and_prismatic_joints(stanford):
    texts = _svg_texts((stanford / "figures" / "fig_joints_q_qd_qdd.svg").read_text())
    labels = [t for t in texts if re.match(r"^q\S* \[", t)]
    assert sorted(labels) == sorted(["q [deg]", "q\u0307 [deg/s]", "q\u0308 [deg/s\u00b2]",
                                     "q [mm]", "q\u0307 [mm/s]", "q\u0308 [mm/s\u00b2]"])
    assert not any("/s/s" in t or ("deg" in t and "mm" in t) for t in texts)


#: A power of ten written into an axis' units ("[10⁻³ N m]": ticks in units of 10⁻³ N m).
_POWER = re.compile("(?<=\\[)10\u207b?[\u2070\u00b9\u00b2\u00b3\u2074-\u2079]+ ")


def _units_only(texts):
    """The texts with any power of ten taken out of their units: the units themselves."""
    return [_POWER.sub("", t) for t in texts]


def _zero(folder):
    """The elements zero in every part (drawn as no panel), from the stored ranking."""
    from gd_analyze.report.main_context import zero_mask

    with xr.open_dataset(folder / "results.h5") as ds:
        labels, zero = zero_mask(ds.load())
    return {lab for lab, z in zip(labels, zero) if z}


def test_d_and_h_panels_carry_their_units(stanford):
    """One panel per element that is not zero in every part, its axis in its units."""
    zero = _zero(stanford)
    d = _units_only(_svg_texts((stanford / "figures" / "fig_3_10_D.svg").read_text()))
    h = _units_only(_svg_texts((stanford / "figures" / "fig_3_11_h.svg").read_text()))
    assert [t for t in d if re.fullmatch(r"\[.*\]", t)] == [
        f"[{u}]" for lab, u in EXPECTED if lab.startswith("D") and lab not in zero]
    assert [t for t in h if re.fullmatch(r"\[.*\]", t)] == [
        f"[{u}]" for lab, u in EXPECTED if lab.startswith("h") and lab not in zero]
    assert not any("[kg m\u00b2]" in t or "[N m]" in t for t in d + h if "_i" in t)


_JOINT_AXIS = re.compile(r"(?:\u03c4\((\d+)\)|\u0394\u03c4 \(joint (\d+)\)) \[(.*)\]")


def _joint_axes(texts):
    found = [_JOINT_AXIS.fullmatch(t) for t in texts]
    return {m.group(1) or m.group(2): m.group(3) for m in found if m}


def test_torque_axes_give_n_for_the_prismatic_joint(stanford):
    """The torque figure (full vs simplified, or the simplified model's error) and its copy
    inline in the HTML: one axis per joint, in N m or N; no other text claims [N m]."""
    expected = {str(i + 1): _tau_units(i) for i in range(N_JOINTS)}
    for source in (stanford / "figures" / "fig_torque_full_vs_simplified.svg",
                   stanford / "report.html"):
        texts = _units_only(_svg_texts(source.read_text()))
        axes = _joint_axes(texts)
        assert axes and all(expected[j] == u for j, u in axes.items()), source.name
        # a joint without a panel (nothing dropped) is named in the note, with its units
        note = " ".join(t for t in texts if t.startswith(("Nothing dropped", "round-off")))
        assert all(f"{j}: " in " ".join(texts) for j in expected if j not in axes), note
        if source.suffix == ".svg":                 # the HTML also holds Fig. 3's [N m] axes
            assert not [t for t in texts if "[N m]" in t and not _JOINT_AXIS.fullmatch(t)]


def test_stored_attributes_follow_the_joint_types(stanford):
    with xr.open_dataset(stanford / "results.h5") as ds:
        stored = dict(zip([str(v) for v in ds["element"].values],
                          [str(v).replace("m2", "m\u00b2") for v in ds["element_units"].values]))
        assert stored == dict(EXPECTED)
        assert [str(v) for v in ds["tau_units"].values] == [_tau_units(i) for i in range(6)]
        assert [str(v) for v in ds["q_units"].values] == ["m" if p else "rad" for p in PRISMATIC]
        for name in ("tau", "tau_simplified", "h", "c", "tau_peak", "tau_error_peak", "q", "D"):
            assert ds[name].attrs["units"] not in ("N m", "rad", "kg m2"), name
        per_joint = [k for k in ds.variables if "joint" in ds[k].dims
                     and ds[k].attrs.get("units") in ("N m", "N")]
        assert per_joint == []           # a torque of joints 1..6 is N m and N: never one unit
        assert np.isfinite(ds["tau"].values).all()


def test_sweep_report_and_dataset_give_n_for_the_prismatic_joint(tmp_path):
    out = tmp_path / "sweep"
    assert main(["sweep", "stanford", str(ROOT / "data" / "stanford_trajectory.csv"),
                 str(ROOT / "data" / "stanford_trajectory.csv"), "-o", str(out),
                 "--held-out", "0", "-q"]) == 0
    html = (out / "sweep_report.html").read_text()
    table = next(t for t in tables_of(html) if t and t[0][:2] == ["joint", "peak |\u03c4|"])
    assert [row[table[0].index("units")] for row in table[1:]] == [
        _tau_units(i) for i in range(N_JOINTS)]
    assert "[N m]" not in unescape(_html_without_svg(html)).replace("\u00a0", " ")
    with xr.open_dataset(out / "sweep.h5") as ds:
        stored = dict(zip([str(v) for v in ds["element"].values],
                          [str(v).replace("m2", "m\u00b2") for v in ds["element_units"].values]))
        assert stored == dict(EXPECTED)
        assert [k for k in ds.variables if "joint" in ds[k].dims
                and ds[k].attrs.get("units") in ("N m", "N")] == []
        # the start and goal positions were stored in "rad", joint 3's in m
        assert [k for k in ds.variables if "joint" in ds[k].dims
                and ds[k].attrs.get("units") in ("rad", "m")] == []
        for k in ("q_start", "q_goal"):
            assert ds[k].attrs["units"] == "rad or m by joint type (per joint: joint_type)"
            assert [str(v) for v in ds["joint_type"].values] == [
                "prismatic" if p else "revolute" for p in PRISMATIC]


def _gain_units(i):
    """PD gains tau_i = Kp e_i + Kv de_i/dt: generalized force over q_i and over qd_i."""
    return ("N/m", "N s/m") if PRISMATIC[i] else ("N m/rad", "N m s/rad")


@pytest.fixture(scope="module")
def stanford_control(shared_control):
    """The control run, with its report, on the model of the Stanford arm's default run
    (conftest's shared_control: shared with test_sweep_control_tables, read only)."""
    return shared_control("stanford")[0] / "control"


def test_control_gains_carry_the_units_of_their_joint(stanford_control):
    """Stored per joint (HDF5 ``<name>_units``), never one unit for the mixed arm, and printed
    in the gains table joint by joint: Kp_pd in N m/rad or N/m, Kv_pd in N m s/rad or N s/m,
    D_ii (their scale) in kg m² or kg."""
    with xr.open_dataset(stanford_control / "control.h5") as ds:
        for name, k in (("Kp_pd", 0), ("Kv_pd", 1)):
            stored = [str(u).replace(" rad-1", "/rad").replace(" m-1", "/m")
                      for u in ds[f"{name}_units"].values]
            assert stored == [_gain_units(i)[k] for i in range(N_JOINTS)], name
            assert "by joint type" in ds[name].attrs["units"], ds[name].attrs["units"]
        assert [str(u).replace("m2", "m\u00b2") for u in ds["inertia_scale_units"].values] == [
            _d_units(i, i) for i in range(N_JOINTS)]
        assert [k for k in ds.variables if "joint" in ds[k].dims
                and ds[k].attrs.get("units") in ("N m", "N", "N m rad-1", "N m s rad-1",
                                                 "kg m2", "rad", "m")] == []
    html = (stanford_control / "control_report.html").read_text(encoding="utf-8")
    gains = next(t for t in tables_of(html) if t and t[0][0] == "joint" and len(t[0]) == 8)
    for i, row in enumerate(gains[1:]):
        row = [c.replace("\u00a0", " ") for c in row]
        assert row[5].endswith(" " + _d_units(i, i)), row
        assert row[6].endswith(" " + _gain_units(i)[0]), row
        assert row[7].endswith(" " + _gain_units(i)[1]), row


def test_every_unit_of_the_control_report_follows_the_joint_types(stanford_control):
    """Every per-joint unit of the control report's tables: q and the tracking error of joint
    3 in m, its torques in N; the rest in rad and N m. No sentence gives the mixed arm's
    largest error or torque difference in the units of another joint."""
    html = (stanford_control / "control_report.html").read_text(encoding="utf-8")
    text = unescape(re.sub(r"<[^>]+>", " ", _html_without_svg(html))).replace("\u00a0", " ")
    for t in tables_of(html):
        head = [c.replace("\u00a0", " ") for c in t[0]] if t else []
        cols = [c for c in head if re.match(r"J\d+ \[", c)]
        if not cols:
            continue
        units = [c.split("[", 1)[1].rstrip("]") for c in cols]
        torque = units[0] in ("N m", "N")
        assert units == ([_tau_units(i) for i in range(N_JOINTS)] if torque else
                         ["m" if p else "rad" for p in PRISMATIC]), head
    with xr.open_dataset(stanford_control / "control.h5") as ds:
        peak = ds["error_peak_grid"].values                  # (controller, joint)
        names = [str(c) for c in ds["controller"].values]
    for c, row in zip(names, peak):
        j = int(np.nanargmax(row))
        label = {"full": "full model", "simplified": "simplified model",
                 "pd_gravity": "PD + gravity"}[c]
        unit = "m" if PRISMATIC[j] else "rad"
        if c == "full":                 # integrator noise on every joint: no number, no unit
            assert f"{label}: peak |e| \u2261 0 (integrator noise)" in text
            continue
        # each joint type apart, in its own unit: never one maximum across rad and m
        assert re.search(rf"{re.escape(label)}: peak \|e\| \S+ rad, \S+ m\b", text), (c, unit)
    setup = dict(r for t in tables_of(html) if t and t[0] == ["item", "value"] for r in t[1:])
    offset = next(v for k, v in setup.items() if k.startswith("initial offset"))
    assert [u.split()[-1] for u in offset.replace("\u00a0", " ").split(", ")] == [
        "m" if p else "rad" for p in PRISMATIC]


def test_payload_figure_gives_n_for_the_prismatic_joint():
    """The payload sweep's peak |tau| axes: joint 3 of the Stanford arm on an axis in N, the
    others on one in N m (a load changes forces and torques alike); the dataset says which
    joint is which."""
    from gd_analyze import load_robot
    from gd_analyze.jobs.payload import payload_sweep
    from gd_analyze.report.main_figures import payload_figure
    from gd_analyze.trajectory.trajectory import read_trajectory

    robot = load_robot("stanford")
    traj = read_trajectory(ROOT / "data" / "stanford_trajectory.csv", robot.n)
    ds = payload_sweep(robot, traj, [0.0, 1.0])
    assert [str(t) for t in ds["joint_type"].values] == [
        "prismatic" if p else "revolute" for p in PRISMATIC]
    fig = payload_figure(ds)
    by_unit = {}
    for ax in fig.axes:
        if ax.get_ylabel().startswith("peak |\u03c4|"):
            unit = ax.get_ylabel().split("[")[1].rstrip("]")
            by_unit[unit] = sorted(int(ln.get_label().split()[1]) - 1 for ln in ax.lines)
    assert by_unit == {u: [i for i in range(N_JOINTS) if _tau_units(i) == u]
                       for u in {_tau_units(i) for i in range(N_JOINTS)}}


def test_dh_table_gives_the_joint_variable_per_joint_type(stanford):
    """A revolute joint turns (theta = q + offset, d fixed); a prismatic one slides (d = q +
    offset, theta fixed): the Stanford file gives joint 3 theta_deg = -90 and no d."""
    html = (stanford / "report.html").read_text()
    dh = next(t for t in tables_of(html) if t and t[0][:4] == ["joint", "d [m]", "a [m]",
                                                                "\u03b1 [deg]"])
    assert dh[0][4] == "\u03b8 [deg]"
    for k, row in enumerate(dh[1:]):
        d, theta = row[1], row[4]
        if PRISMATIC[k]:
            assert d.startswith("q") and float(theta.replace("\u2212", "-")) == -90.0
        else:
            assert theta.startswith("q") and not d.startswith("q")
    assert "offset [deg]" not in html and "\u03b8 = q + offset" not in html
    assert "the offset d of a prismatic one" in unescape(html)


def test_stored_drive_and_limit_units_follow_the_joint_types(stanford):
    with xr.open_dataset(stanford / "results.h5") as ds:
        assert ds["D_arm"].attrs["units"] == "kg m2 or kg by joint type (per joint: joint_type)"
        assert ds["viscous"].attrs["units"] == (
            "N m s rad-1 or N s m-1 by joint type (per joint: joint_type)")
        for name, per_joint in (("q_min", "q_units"), ("qd_max", "qd_units"),
                                ("qdd_max", "qdd_units")):
            assert ds[name].attrs["units"].endswith(f"(per joint: {per_joint})"), name
        assert "prismatic" in ds["dh_offset"].attrs["long_name"]


def test_newton_euler_count_is_the_arms_own(stanford):
    """The costs set against Newton-Euler use the count of this arm (joint 3 prismatic), the
    count the control report uses: the arm itself counted directly, not an all-revolute chain."""
    from gd_analyze import load_robot
    from gd_analyze.dynamics.opcount import count_operations

    mul, add = count_operations(load_robot("stanford"), "newton-euler")[:2]
    with xr.open_dataset(stanford / "results.h5") as ds:
        k = [str(v) for v in ds["cost_model"].values].index("project N-E as implemented")
        assert (ds["cost_multiplications"].values[k], ds["cost_additions"].values[k]) == (
            mul, add)
        j = [str(v) for v in ds["formulation"].values].index("newton-euler")
        assert (ds["op_multiplications_arm"].values[j], ds["op_additions_arm"].values[j]) == (
            mul, add)
    text = unescape((stanford / "report.html").read_text())
    assert f"{mul + add:,}" in text and "joint 3 is prismatic" in text


def test_joint_6_round_off_is_never_tabulated(stanford):
    """Joint 6's tau_s - tau (nothing dropped there) is round-off of the arm's torques
    (ranking.ranking.is_round_off, tested against Pinocchio): the tables, the CLI
    summary and Fig. 4 all say so, none prints its digits."""
    from gd_analyze.cli.commands import _format_summary
    from gd_analyze.store.results_view import Results

    html = (stanford / "report.html").read_text()
    tables = tables_of(html)
    err = next(t for t in tables if t and t[0][0] == "joint" and t[0][2].startswith("RMS"))
    assert err[6][1].startswith("\u2261 0") and err[6][4] == "\u2261 0", err[6]
    ranking = next(t for t in tables if t and t[0][:2] == ["element", "translational share"])
    h6 = next(r for r in ranking if r[0] == "h6")        # h<sub>6</sub> without its tags
    assert h6[1] in ("0", "\u2261 0") and h6[3] == "\u2261 0", h6
    bound = next(t for t in tables if t and t[0][0] == "joint" and t[0][3] == "bound")
    assert bound[6][-1] == "\u2261 0" and bound[6][-2] == "\u2261 0", bound[6]
    with xr.open_dataset(stanford / "results.h5") as ds:
        summary = _format_summary(Results.from_dataset(ds)).splitlines()
    row = next(line for line in summary[summary.index(
        "simplified model torque error per joint:") + 2:] if line.startswith("6 "))
    assert row.split()[1] == "\u2261" and "e-16" not in row, row
