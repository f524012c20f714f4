import math

import numpy as np
import pandas as pd
import pytest

from gd_analyze import InputError
from gd_analyze.trajectory.planning import (
    DEFAULT_GOAL_DEG,
    DEFAULT_START_DEG,
    plan_quintic,
    quintic_plan,
)
from gd_analyze.trajectory.trajectory import (
    JointLimitWarning,
    Trajectory,
    as_trajectory,
    check_joint_limits,
    read_trajectory,
    trajectory_columns,
    write_trajectory,
    write_trajectory_chunks,
)


def _default_plan(puma, n=31):
    return plan_quintic(puma, np.radians(DEFAULT_START_DEG), np.radians(DEFAULT_GOAL_DEG), n)


def test_write_read_round_trip(tmp_path, puma):
    plan = _default_plan(puma)
    path = tmp_path / "traj.csv"
    write_trajectory(plan, path)
    back = read_trajectory(path, 6)
    np.testing.assert_array_equal(back.q, plan.q)
    assert len(back.sha256) == 64
    assert list(tmp_path.iterdir()) == [path]          # no temporary left behind


def test_positions_only_uses_a_cubic_spline(tmp_path, puma):
    plan = _default_plan(puma, n=201)
    path = tmp_path / "pos.csv"
    cols = trajectory_columns(6, derivatives=False)
    rows = [",".join(cols)] + [",".join(f"{v:.17g}" for v in [t, *q])
                               for t, q in zip(plan.t, plan.q)]
    path.write_text("\n".join(rows) + "\n")
    traj = read_trajectory(path, 6)
    assert traj.derivatives == "cubic-spline"
    scale_v, scale_a = np.abs(plan.qd).max(), np.abs(plan.qdd).max()
    assert np.abs(traj.qd - plan.qd).max() < 1e-3 * scale_v
    assert np.abs(traj.qdd[5:-5] - plan.qdd[5:-5]).max() < 1e-2 * scale_a


HEADER = "t,q1,q2"


@pytest.mark.parametrize("text, row, column, match", [
    ("", None, None, "empty file"),
    ("0,1,2\n1,2,3\n", 1, None, "no header"),
    ("t,q1\n0,1\n1,2\n", 1, None, "has 1 joints, the robot has 2"),
    ("t,q1,q2,q3\n0,1,2,3\n1,2,3,4\n", 1, None, "has 3 joints, the robot has 2"),
    ("t,q1,q2,qd1,qd2\n0,1,2,3,4\n1,2,3,4,5\n", 1, "qdd1", "missing column"),
    ("t,q1,q2,qd1,qd2,qdd1,qdd2,x\n" + "0,1,2,3,4,5,6,7\n" * 2, 1, "x", "extra column"),
    ("t,q1,q2\n0,1,2\n1,2\n", 3, None, "ragged row"),
    ("t,q1,q2\n0,1,2\n1,2,3,4\n", 3, None, "ragged row"),
    ("t,q1,q2\n0,1,2\n1,abc,3\n", 3, "q1", "not a number"),
    ("t,q1,q2\n0,1,2\n1,nan,3\n", 3, "q1", "not a finite number"),
    ("t,q1,q2\n0,1,inf\n1,2,3\n", 2, "q2", "not a finite number"),
    ("t,q1,q2\n0,1,2\n0,2,3\n", 3, "t", "not strictly increasing"),
    ("t,q1,q2\n1,1,2\n0.5,2,3\n", 3, "t", "not strictly increasing"),
    ("t,q1,q2\n0,1,2\n", None, None, "fewer than 2 set points"),
    ("x,q1,q2\n0,1,2\n1,2,3\n", 1, "x", "must start with 't'"),
])
def test_bad_input_names_file_row_and_column(tmp_path, text, row, column, match):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(InputError, match=match) as err:
        read_trajectory(path, n_joints=2)
    e = err.value
    assert e.path == str(path) and e.row == row
    if column is not None:
        assert column in str(e.column)
    assert "\n" not in str(e) and str(e).startswith(str(path))


@pytest.mark.parametrize("text, column, said", [
    ("t,q1,q2,qd1,qd2,qdd1,qdd2,\n" + "0,1,2,3,4,5,6,\n" * 2, 8, "extra column ''"),
    ("t,,q2\n0,1,2\n1,2,3\n", 2, "expected column 'q1', got ''"),
])
def test_an_empty_header_cell_is_named_by_its_number(tmp_path, text, column, said):
    """A header with a trailing comma said "row 1, column : extra column ''": an empty
    name is no column name, so the column is its number (counted from 1, as a spreadsheet)."""
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(InputError) as err:
        read_trajectory(path, n_joints=2)
    assert str(err.value).startswith(f"{path}: row 1, column {column}: {said}")


@pytest.mark.parametrize("t1, row", [("5e-324", 3), ("1e-300", 2)])
def test_time_steps_too_short_for_a_spline_are_one_line(tmp_path, recwarn, t1, row):
    """Positions only, a step of the smallest double (5e-324 s): its slope 1 / 5e-324 is
    beyond a float and SciPy's spline raised ValueError ("`dydx` must contain only finite
    values"), exit 4; a step of 1e-300 s gave SciPy's "ill-conditioned matrix" warning beside
    the error. Now one InputError, the row where the slope ends, and no warning."""
    path = tmp_path / "short.csv"
    path.write_text(f"t,q1,q2\n0,0,0\n{t1},1,1\n{2 * float(t1)!r},0,2\n")
    with pytest.raises(InputError, match=r"the qd derived by the cubic spline exceeds") as err:
        read_trajectory(path, n_joints=2)
    assert (err.value.row, err.value.column) == (row, "q1") and not recwarn.list


def test_a_byte_not_utf8_names_its_row(tmp_path):
    """A Windows-1252 degree sign (byte 0xb0) in the third row: that row and the byte."""
    path = tmp_path / "bad.csv"
    path.write_bytes(b"t,q1,q2\n0,1,2\n1,2,3 \xb0\n2,3,4\n")
    with pytest.raises(InputError, match=r"not a UTF-8 text file \(byte 0xb0\)") as err:
        read_trajectory(path, n_joints=2)
    assert err.value.row == 3


def test_missing_file(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        read_trajectory(tmp_path / "nope.csv")


@pytest.mark.parametrize("args, said", [
    ((None,), "path: a CSV file (str or os.PathLike), not a NoneType"),
    ((3,), "path: a CSV file (str or os.PathLike), not a int"),
    ((b"t.csv",), "path: a CSV file (str or os.PathLike), not a bytes"),
    (("t.csv", "2"), "n_joints: a whole number >= 1, not str '2'"),
    (("t.csv", 2.0), "n_joints: a whole number >= 1, not float '2.0'"),
    (("t.csv", True), "n_joints: a whole number >= 1, not bool 'True'"),
    (("t.csv", 0), "n_joints: a whole number >= 1, not int '0'"),
])
def test_arguments_of_another_type_are_one_line_naming_the_argument(tmp_path, monkeypatch,
                                                                     args, said):
    """None read as the file "None" ("None: no such file"), and a joint count "2" as 2
    ("the file has 6 joints, the robot has 2"); the file here is a good one."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "t.csv").write_text("t,q1,q2\n0,0,0\n1,1,0\n")
    with pytest.raises(InputError) as e:
        read_trajectory(*args)
    assert str(e.value) == said
    assert read_trajectory("t.csv", np.int64(2)).n_setpoints == 2


def test_joint_limit_warning(tmp_path, two_link):
    path = tmp_path / "wide.csv"
    path.write_text("t,q1,q2\n0,0,0\n1,4,0\n2,0,0\n")      # 4 rad > 180 deg on joint 1
    traj = read_trajectory(path, 2)
    with pytest.warns(JointLimitWarning, match="column q1"):
        msgs = check_joint_limits(two_link, traj)
    assert len(msgs) == 1


def test_joint_limit_warning_shows_a_narrow_range(tmp_path, two_link):
    """Limits were printed to whole degrees (millimetres for a prismatic joint): a range of
    [0, 0.0005] rad read 'outside its limits [0, 0] deg (1 set points)'. Oracle: the limits
    set, in deg, and the one row beyond them."""
    import dataclasses

    narrow = dataclasses.replace(two_link, q_min=np.array([0.0, -3.0]),
                                 q_max=np.array([0.0005, 3.0]))
    path = tmp_path / "narrow.csv"
    path.write_text("t,q1,q2\n0,0,0\n1,0.06,0\n2,0,0\n")
    with pytest.warns(JointLimitWarning) as caught:
        check_joint_limits(narrow, read_trajectory(path, 2))
    assert (f"joint 1 at {math.degrees(0.06):.4g} deg is outside its limits "
            f"[0, {math.degrees(0.0005):.4g}] deg (1 set point)" in str(caught[0].message))


@pytest.mark.parametrize("defect, row, column", [
    (None, None, None), ("nan", 5002, "q3"), ("ragged", 7002, None), ("text", 9002, "qd2"),
    ("time", 3002, "t")])
@pytest.mark.parametrize("end, blank", [("\n", ""), ("\n", "\n"), ("\r\n", "\r\n\r\n"),
                                        ("\n", " \t\n\t\n  "), ("\r\n", "  \r\n\t \r\n")])
def test_large_files_parse_fast_and_errors_stay_exact(tmp_path, puma, monkeypatch, defect, row,
                                                      column, end, blank):
    """Files above FAST_PARSE_BYTES go through pandas, also with LF or CRLF line ends and blank
    lines at the end, empty or of spaces and tabs (as many recorded files have): the
    cell-by-cell parser is not called; a fault is still located exactly (by that parser)."""
    import hashlib

    import gd_analyze.trajectory.trajectory as trajectory
    from gd_analyze.trajectory.trajectory import FAST_PARSE_BYTES

    plan = _default_plan(puma, n=12001)
    path = tmp_path / "big.csv"
    write_trajectory(plan, path)
    lines = path.read_text().splitlines()
    cells = {r: lines[r - 1].split(",") for r in (3002, 5002, 7002, 9002)}
    if defect == "nan":
        cells[5002][3] = "nan"
    elif defect == "ragged":
        cells[7002] = cells[7002][:-1]
    elif defect == "text":
        cells[9002][8] = "1.0x"
    elif defect == "time":
        cells[3002][0] = "0"
    for r, c in cells.items():
        lines[r - 1] = ",".join(c)
    path.write_bytes((end.join(lines) + end + blank).encode())
    assert path.stat().st_size > FAST_PARSE_BYTES
    if defect is None:
        monkeypatch.setattr(trajectory, "_validated_values", None)   # the fall-back: not called
        back = read_trajectory(path, 6)
        np.testing.assert_array_equal(back.q, plan.q)      # round-trip float parsing
        assert back.sha256 == hashlib.sha256(path.read_bytes()).hexdigest()
        return
    with pytest.raises(InputError) as err:
        read_trajectory(path, 6)
    assert err.value.row == row
    if column:
        assert err.value.column == column


def test_a_large_file_is_read_without_holding_its_bytes(tmp_path, puma, monkeypatch):
    """A regular large file is parsed a piece at a time: the reading allocates its values and a
    few pieces, not the file's bytes (which the reader held whole before). The values and the
    SHA-256 are those of the whole file."""
    import hashlib
    import tracemalloc

    import gd_analyze.trajectory.trajectory as trajectory

    plan = _default_plan(puma, n=40_000)
    path = tmp_path / "big.csv"
    write_trajectory(plan, path)
    size = path.stat().st_size
    monkeypatch.setattr(trajectory, "PARSE_PIECE", 1 << 18)
    read_trajectory(path, 6)                            # pandas' imports, not counted
    tracemalloc.start()
    try:
        back = read_trajectory(path, 6)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    values = back.t.nbytes + back.q.nbytes + back.qd.nbytes + back.qdd.nbytes
    assert size > 3 * values / 2
    assert peak < values + size / 2, (peak, values, size)
    np.testing.assert_array_equal(back.q, plan.q)
    np.testing.assert_array_equal(back.qdd, plan.qdd)
    assert back.sha256 == hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.mark.parametrize("block", [1, 7, 4096, 1 << 24])
def test_the_block_count_of_a_byte_is_bytes_count(block):
    """_byte_count (numpy, block by block) equals bytes.count on random bytes, every value."""
    from gd_analyze.trajectory.trajectory import _byte_count

    raw = np.random.default_rng(block).integers(0, 256, 20_011, dtype=np.uint8).tobytes()
    for byte in (b"\n", b",", b"\r", b"\x00", b"\xff"):
        assert _byte_count(raw, byte, block=block) == raw.count(byte)
    assert _byte_count(b"", b",") == 0


def test_written_in_pieces_the_file_is_the_whole_table(tmp_path, puma):
    """Piece by piece, the same bytes as the whole table written by pandas at once (17
    significant digits, -0.0 as 0); a write that fails halfway leaves nothing."""
    plan = quintic_plan(puma, np.radians(DEFAULT_START_DEG), np.radians(DEFAULT_GOAL_DEG), 1001)
    whole = plan.rows(0, 1001)
    table = np.column_stack([whole.t, whole.q, whole.qd, whole.qdd]) + 0.0
    oracle = tmp_path / "oracle.csv"
    pd.DataFrame(table, columns=trajectory_columns(6, True)).to_csv(
        oracle, index=False, float_format="%.17g")
    path = tmp_path / "traj.csv"
    write_trajectory_chunks(plan.chunks(64), 6, path)
    assert path.read_bytes() == oracle.read_bytes()
    write_trajectory(whole, tmp_path / "once.csv")
    assert (tmp_path / "once.csv").read_bytes() == oracle.read_bytes()

    def full_after_two(pieces):
        for i, piece in enumerate(pieces):
            if i == 2:
                raise OSError(28, "No space left on device")
            yield piece

    with pytest.raises(OSError):
        write_trajectory_chunks(full_after_two(plan.chunks(64)), 6, tmp_path / "full.csv")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["once.csv", "oracle.csv", "traj.csv"]


def test_written_values_are_pandas_to_csv_of_any_float(tmp_path):
    """Over more rows than are formatted at once, values of every magnitude, zeros of both
    signs, infinities and NaN of both signs are the bytes pandas writes (``%.17g``, NaN as an
    empty field, -0.0 as 0)."""
    rng = np.random.default_rng(3)
    rows, n = 2**14 + 37, 2
    table = rng.standard_normal((rows, 1 + 3 * n)) * 10.0 ** rng.integers(-320, 300,
                                                                          (rows, 1 + 3 * n))
    table[::5, 1] = np.round(rng.standard_normal(len(table[::5])) * 1e6)
    table[1::7, 2] = -0.0
    table[3, :] = [np.inf, -np.inf, np.nan, -np.nan, 5e-324, 1e16, -123456789012345678.0]
    table[-1, :] = [np.nan, 0.1, 1 / 3, 1e-5, 1e21, 2.0**-1074, -1.7976931348623157e308]
    oracle = tmp_path / "oracle.csv"
    pd.DataFrame(table + 0.0, columns=trajectory_columns(n, True)).to_csv(
        oracle, index=False, float_format="%.17g")
    path = tmp_path / "traj.csv"
    write_trajectory(Trajectory(t=table[:, 0], q=table[:, 1:3], qd=table[:, 3:5],
                                qdd=table[:, 5:], derivatives="arrays", source="test"), path)
    assert path.read_bytes() == oracle.read_bytes()


@pytest.mark.parametrize("value, kind", [((np.arange(3.0),) * 3, "tuple of 3"),
                                         ([np.arange(3.0)], "list of 1"), (3.0, "float")])
def test_a_sequence_of_another_length_says_its_length(value, kind):
    """as_trajectory((t, q, qd)) said "... or a sequence (t, q[, qd, qdd]), not a tuple", as
    if a tuple were not a sequence: it is one of the wrong length."""
    with pytest.raises(InputError, match=rf"or a sequence \(t, q\[, qd, qdd\]\), not a {kind}$"):
        as_trajectory(value)
