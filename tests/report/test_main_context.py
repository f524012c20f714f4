"""The main report's context states what the stored data hold."""

import numpy as np

from gd_analyze.report.main_context import report_context


def test_base_parameter_names_are_defined_with_their_frame(shipped_dataset):
    """The base parameters' names (XX2, MX2, ...) were never defined, so "MY4 = 0"
    sat unexplained beside a link-4 centre of mass y of 0.019 m. The note defines them in the
    joint frame, cites the grouping, and its example holds in the stored data."""
    ds = shipped_dataset("puma560")
    assert str(ds.attrs["simplified_form"]) == "recursive"
    note = report_context(ds)["choices_note"]
    for words in ("Khalil & Kleinfinger 1987", "Gautier 1990", "joint frame j",
                  "not the link frame of Table 1.3", "MXj, MYj [kg m]"):
        assert words in note, words
    values = dict(zip((str(v) for v in ds["base_parameter"].values),
                      ds["base_parameter_value"].values))
    assert values["MY4"] == 0 and np.isclose(ds["link_com"].values[3, 1], 0.019)
    assert "So MY4 = 0 beside a centre of mass y of 0.019 m of link 4 in Table 1.3" in note


def test_dh_table_prints_the_parameters_as_the_robot_file_gives_them(shipped_dataset):
    """d3 = 0.15005 m was printed 0.15. Oracle: the robot file's numbers (the
    loaded robot's), read back from the table's text, exactly."""
    from gd_analyze import load_robot

    ds = shipped_dataset("puma560")
    robot = load_robot("puma560")
    rows = report_context(ds)["dh"]["rows"]
    assert rows[2][1] == "0.15005"
    for row, d, a in zip(rows, robot.d, robot.a):
        assert float(row[1]) == d and float(row[2]) == a, row


def test_one_format_per_quantity_in_table_5_1_and_the_summary(shipped_dataset):
    """"0.001857 beside 2.369e+00" (errors and peak |tau|, one quantity, in two
    notations) and "0.078 % beside 0.0784 %" (the summary and the table rounding one number
    differently). The torque columns share one notation, the two percentage columns one
    number of decimals, and the summary quotes the table's cells. Oracle: the stored errors."""
    from gd_analyze.report.markup import plain

    ds = shipped_dataset("puma560")
    ctx = report_context(ds)
    rows = [r for r in ctx["error"]["rows"] if "\u2261" not in r[1]]
    torque = [c for r in rows for c in r[1:4]]
    assert len({"e" in c for c in torque}) == 1, torque                 # one notation
    decimals = {len(c.split(" ")[0].split(".")[1]) for r in rows for c in r[4:6]}
    assert len(decimals) == 1, rows
    worst = int(np.nanargmax(ds["tau_error_relative_peak"].values))
    row = ctx["error"]["rows"][worst]
    summary = plain(ctx["summary"]).replace("\u00a0", " ")
    assert (f"is {row[4]} of peak |τ| at joint {worst + 1} ({row[1]} N m of {row[3]} N m)"
            in summary), summary
    np.testing.assert_allclose(float(row[1]), ds["tau_error_peak"].values[worst], rtol=1e-3)


def test_an_arm_beyond_the_counted_joints_gets_no_empty_count_table():
    """The operation counts are tabulated for n = 1..10: for a 12-joint arm the formulations
    section gives no table with a header and no rows, and its note says why; an arm within
    the counts gets its row per formulation."""
    from types import SimpleNamespace

    from gd_analyze.report.main_context import _formulations_context

    dof = np.arange(1, 11)
    counts = np.arange(30).reshape(10, 3) + 1

    def view(n):
        return SimpleNamespace(
            quantities=("D", "h", "c", "tau"), pairs=("lagrange-euler vs gd",),
            disagreement=np.full((1, 4), 1e-15), names=("lagrange-euler", "newton-euler", "gd"),
            dof=dof, multiplications=counts, additions=counts,
            multiplications_table_3_5=counts, additions_table_3_5=counts, arm=None, n=n,
            setpoints=31, joint_types="R" * n)

    beyond = _formulations_context(view(12))
    assert beyond["costs"]["rows"] == []
    assert "tabulated for n = 1 to 10 only" in beyond["note"] and "n = 12" in beyond["note"]
    within = _formulations_context(view(6))
    assert len(within["costs"]["rows"]) == 3
    assert "tabulated for" not in within["note"]


def test_joints_alike_are_found_in_blocks_as_on_the_whole_motion(shipped_dataset, monkeypatch):
    """alike_joints reads the motion block by block; its groups are those of the definition
    on the whole columns (ALIKE), here with joints 2 and 5 given the same motion, joint 6
    within ALIKE of it, and blocks of 4 set points."""
    from gd_analyze.report.main_context import ALIKE, alike_joints
    from gd_analyze.store.results_view import Results, StoredTrajectory

    ds = shipped_dataset("puma560").copy(deep=True)
    for v in ("q", "qd", "qdd"):
        x = ds[v].values
        x[:, 4] = x[:, 1]
        x[:, 5] = x[:, 1] * (1 + ALIKE / 4)
        ds[v].values = x
    blocks = StoredTrajectory.motion_blocks
    monkeypatch.setattr(StoredTrajectory, "motion_blocks", lambda self, rows: blocks(self, 4))
    results = Results.from_dataset(ds)
    series = [results.dataset[v].values for v in ("q", "qd", "qdd")]

    def alike(i, j):
        return all(np.max(np.abs(x[:, i] - x[:, j])) <= ALIKE * max(
            np.max(np.abs(x[:, i])), np.max(np.abs(x[:, j]))) for x in series)
    want = []
    for i in range(6):
        group = [i + 1] + [j + 1 for j in range(i + 1, 6) if alike(i, j)]
        if len(group) > 1 and not any(i + 1 in g for g in want):
            want.append(group)
    assert want == [[2, 5, 6]]
    assert alike_joints(results) == want


def test_the_zero_base_parameters_are_counted_in_number():
    """Oracle: the values given. One base parameter of 0 is said in the singular (an arm with
    one centre of mass on its joint's axis read "1 are 0 ... and are not listed")."""
    from types import SimpleNamespace

    from gd_analyze.report.main_context import zero_parameters

    def said(values):
        bp = SimpleNamespace(names=[f"P{i}" for i in range(len(values))], value=values)
        return zero_parameters(SimpleNamespace(base_parameters=bp))

    assert said([1.0, 0.0, 2.0]) == (" Of the 3 base parameters, 1 is 0 for this robot and is "
                                     "not listed: P1.")
    assert said([0.0, 0.0, 2.0]) == (" Of the 3 base parameters, 2 are 0 for this robot and are "
                                     "not listed: P0, P1.")
    assert said([1.0]) == ""


def test_a_one_joint_arm_is_said_in_the_singular(tmp_path, one_joint_urdf):
    """Oracle: the arm's one joint, hence one element of D and one of h. Its report read
    "one, 1 joints" and "in D, 0 of 1 elements are dominated"."""
    from gd_analyze.cli import main
    from gd_analyze.report.markup import plain
    from gd_analyze.store.schema import open_results

    urdf = one_joint_urdf
    csv, out = tmp_path / "one.csv", tmp_path / "out"
    assert main(["plan", str(urdf), "-o", str(csv)]) == 0
    assert main([str(urdf), str(csv), "-o", str(out), "--no-report", "-q"]) == 0
    with open_results(out / "results.h5") as ds:
        context = report_context(ds.load())
    assert context["facts"].startswith("one, 1 joint, 31 set points")
    summary = plain(context["summary"])
    assert "in D, 0 of 1 element is dominated" in summary
    assert "in h, 0 of 1 element is dominated" in summary


def test_the_payload_note_lists_below_only_the_elements_that_change():
    """Oracle: the classes given per load mass. None changing read "0 of 2 elements change
    class with the load; they are listed below" over no table."""
    from types import SimpleNamespace

    from gd_analyze.report.main_context import _payload_context
    from gd_analyze.report.markup import plain

    def note(dominance):
        part = SimpleNamespace(masses=[0.0, 1.0], elements=["D11", "h1"],
                               dominance=np.array(dominance))
        context = _payload_context(SimpleNamespace(
            payload=part, provenance=SimpleNamespace(payload_com="[0, 0, 0]")))
        return len(context["table"]["rows"]), plain(context["note"])

    rows, text = note([["both", "rotational"], ["both", "rotational"]])
    assert rows == 0 and "0 of 2 elements change class with the load. The load" in text
    rows, text = note([["both", "rotational"], ["both", "translational"]])
    assert rows == 1 and "1 of 2 elements changes class with the load; it is listed below." in text
    rows, text = note([["both", "rotational"], ["rotational", "translational"]])
    assert rows == 2 and "2 of 2 elements change class with the load; they are listed below." in text


def test_the_summary_sets_the_units_of_a_trajectory_leaving_the_region_with_powers():
    """The summary's coverage clause gives the limit in deg/s with a superscript, as the region
    section does, never "deg/s^2" with a caret (the summary printed the core's plain text)."""
    import gd_analyze as gd
    from gd_analyze.report.markup import html

    robot = gd.load_robot("two-link")
    t = np.linspace(0.0, 1.0, 21)
    q = np.column_stack([np.radians(50) * t ** 2, 0.1 * t])      # joint 1 at 100 deg/s^2
    region = gd.RegionLimits(q_limits=((np.radians(-30), np.radians(60)), (-np.pi, np.pi)),
                             qd_max=(np.radians(400),), qdd_max=(np.radians(40),))
    options = gd.AnalysisOptions(formulations=False, verify=False,
                                 simplify=gd.SimplifyOptions(region=region))
    summary = html(report_context(gd.analyze(robot, (t, q), options))["summary"])
    assert "it leaves the region (joint 1 q\u0308 reaches" in summary
    assert "deg/s<sup>2</sup>" in summary and "^" not in summary
