"""The main report's context states what the stored data hold (issue 31, item 2)."""

import numpy as np

from gd_analyze.reports.main_context import report_context


def test_base_parameter_names_are_defined_with_their_frame(shipped_dataset):
    """Issue 31: the base parameters' names (XX2, MX2, ...) were never defined, so "MY4 = 0"
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
    """Issue 31: d3 = 0.15005 m was printed 0.15. Oracle: the robot file's numbers (the
    loaded robot's), read back from the table's text, exactly."""
    from gd_analyze import load_robot

    ds = shipped_dataset("puma560")
    robot = load_robot("puma560")
    rows = report_context(ds)["dh"]["rows"]
    assert rows[2][1] == "0.15005"
    for row, d, a in zip(rows, robot.d, robot.a):
        assert float(row[1]) == d and float(row[2]) == a, row
