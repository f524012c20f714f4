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
