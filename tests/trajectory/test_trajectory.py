"""Trajectory files and plans; reading recordings: irregular, out-of-order and repeated time
stamps; refusals."""

import hashlib
import math
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from identify_recordings import write_echo_log

from gd_analyze import InputError
from gd_analyze.errors import InputNote
from gd_analyze.trajectory.planning import (
    DEFAULT_GOAL_DEG,
    DEFAULT_START_DEG,
    plan_quintic,
    quintic_plan,
)
from gd_analyze.trajectory.trajectory import (
    FAST_PARSE_BYTES,
    JointLimitWarning,
    Trajectory,
    as_trajectory,
    check_joint_limits,
    read_recording,
    read_trajectory,
    recording_from_arrays,
    trajectory_columns,
    trajectory_from_arrays,
    unwrapped,
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


@pytest.mark.parametrize("robot, csv, said", [
    (1, "t,q1,q2\n0,1,2\n1,2,3\n", "the file has 2 joints, the robot has 1 joint"),
    (2, "t,q1\n0,1\n1,2\n", "the file has 1 joint, the robot has 2 joints"),
    (2, "t,q1,tau1\n0,1,2\n1,2,3\n",
     "the file has 1 joint position column, the robot has 2 joints"),
    (1, "t,q1,tau1,tau2\n0,1,2,3\n1,2,3,4\n", "column 'tau2' beyond the 1 joint"),
])
def test_a_count_of_one_is_singular(tmp_path, robot, csv, said):
    """"the file has 1 joints": a count is singular when it is one, plural otherwise."""
    path = tmp_path / "bad.csv"
    path.write_text(csv)
    read = read_recording if "tau1" in csv else read_trajectory
    with pytest.raises(InputError) as e:
        read(path, n_joints=robot)
    assert said in str(e.value) and f"{said}s" not in str(e.value), str(e.value)
    with pytest.raises(InputError, match="the arrays have 1 joint, the robot has 2 joints"):
        trajectory_from_arrays(np.arange(2.0), np.zeros((2, 1)), n_joints=2)
    with pytest.raises(InputError, match="the trajectory has 1 joint, the robot has 2 joints"):
        as_trajectory(trajectory_from_arrays(np.arange(2.0), np.zeros((2, 1))), n_joints=2)


@pytest.mark.parametrize("text, row, column, match", [
    ("", None, None, "empty file"),
    ("0,1,2\n1,2,3\n", 1, None, "no header"),
    ("t,q1\n0,1\n1,2\n", 1, None, "has 1 joint, the robot has 2 joints"),
    ("t,q1,q2,q3\n0,1,2,3\n1,2,3,4\n", 1, None, "has 3 joints, the robot has 2 joints"),
    ("t,q1,q2,qd1,qd2\n0,1,2,3,4\n1,2,3,4,5\n", 1, "qdd1", "missing column"),
    ("t,q1,q2,qd1,qd2,qdd1,qdd2,x\n" + "0,1,2,3,4,5,6,7\n" * 2, 1, "x", "extra column"),
    ("t,q1,q2\n0,1,2\n1,2\n", 3, None, "ragged row"),
    ("t,q1,q2\n0,1,2\n1,2,3,4\n", 3, None, "ragged row"),
    ("t,q1,q2\n0,1,2\n1,abc,3\n", 3, "q1", "not a number"),
    ("t,q1,q2\n0,1,2\n1,nan,3\n", 3, "q1", "not a finite number"),
    ("t,q1,q2\n0,1,inf\n1,2,3\n", 2, "q2", "not a finite number"),
    ("t,q1,q2\n0,1,2\n0,2,3\n", 3, "t", "not strictly increasing"),
    ("t,q1,q2\n1,1,2\n0.5,2,3\n", 3, "t", "not strictly increasing"),
    ("t,q1,q2\n0,1,2\n1e-61,2,3\n", 3, "t", "not strictly increasing, by 1e-60 s or more"),
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


@pytest.mark.parametrize("t1, row, column, match", [
    ("5e-324", 3, "t", "not strictly increasing, by 1e-60 s or more"),
    ("1e-300", 3, "t", "not strictly increasing, by 1e-60 s or more"),
    ("1e-60", 2, "q1", "the qd derived by the cubic spline exceeds"),
])
def test_time_steps_too_short_for_a_spline_are_one_line(tmp_path, recwarn, t1, row, column,
                                                         match):
    """Positions only, a step of the smallest double (5e-324 s): its slope 1 / 5e-324 is
    beyond a float and SciPy's spline raised ValueError ("`dydx` must contain only finite
    values"), exit 4; a step of 1e-300 s gave SciPy's "ill-conditioned matrix" warning beside
    the error. Now one InputError and no warning: a step below the least the tool takes
    (1e-60 s) where it is read; the least step, with a slope beyond the limit of qd, at the row
    where the slope ends."""
    path = tmp_path / "short.csv"
    path.write_text(f"t,q1,q2\n0,0,0\n{t1},1,1\n{2 * float(t1)!r},0,2\n")
    with pytest.raises(InputError, match=match) as err:
        read_trajectory(path, n_joints=2)
    assert (err.value.row, err.value.column) == (row, column) and not recwarn.list


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


@pytest.fixture(scope="module")
def big_plan(puma, tmp_path_factory):
    """The default plan of 12,001 set points and the lines write_trajectory writes of it,
    planned and written once a module (the same for every case of
    :func:`test_large_files_parse_fast_and_errors_stay_exact`, which writes its own file of
    them). Shared: tests must not modify them."""
    plan = _default_plan(puma, n=12001)
    path = tmp_path_factory.mktemp("big") / "big.csv"
    write_trajectory(plan, path)
    return plan, tuple(path.read_text().splitlines())


@pytest.mark.parametrize("defect, row, column", [
    (None, None, None), ("nan", 5002, "q3"), ("ragged", 7002, None), ("text", 9002, "qd2"),
    ("time", 3002, "t")])
@pytest.mark.parametrize("end, blank", [("\n", ""), ("\n", "\n"), ("\r\n", "\r\n\r\n"),
                                        ("\n", " \t\n\t\n  "), ("\r\n", "  \r\n\t \r\n")])
def test_large_files_parse_fast_and_errors_stay_exact(tmp_path, big_plan, monkeypatch, defect,
                                                      row, column, end, blank):
    """Files above FAST_PARSE_BYTES go through pandas, also with LF or CRLF line ends and blank
    lines at the end, empty or of spaces and tabs (as many recorded files have): the
    cell-by-cell parser is not called; a fault is still located exactly (by that parser)."""
    import hashlib

    import gd_analyze.trajectory.trajectory as trajectory
    from gd_analyze.trajectory.trajectory import FAST_PARSE_BYTES

    plan, written = big_plan
    path = tmp_path / "big.csv"
    lines = list(written)
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


def _write(path, text):
    path.write_text(text)
    return path


def test_out_of_order_and_repeated_stamps_are_sorted_and_dropped(tmp_path):
    rows = [(0.0, 0.1, 1.0), (0.02, 0.3, 3.0), (0.01, 0.2, 2.0), (0.02, 9.0, 9.0)]
    rows += [(0.01 * k, 0.1 * k, k) for k in range(3, 15)]
    path = _write(tmp_path / "r.csv", "t,q1,tau1\n" + "".join(f"{a},{b},{c}\n" for a, b, c in rows))
    rec = read_recording(path)
    assert (np.diff(rec.t) > 0).all()
    assert rec.q[:3, 0].tolist() == [0.1, 0.2, 0.3]         # the first of the repeated stamps
    assert rec.rows[:3].tolist() == [2, 4, 3]
    assert any("sorted" in s for s in rec.notes) and any("repeat" in s for s in rec.notes)
    assert rec.qd is None and rec.qdd is None



def test_a_recording_appended_to_another_is_refused_at_the_row_its_time_restarts(tmp_path):
    """Two sessions in one file, the second's clock starting again at 0 (row 52): sorted by
    time, their rows interleaved into one motion jumping between two poses at every sample,
    and identify ended in the consistency solver's failure with the advice to excite the arm
    better. A stamp out of order by a step or two is still sorted (above)."""
    t = np.arange(50) * 0.01
    q = np.sin(t)
    rows = [(float(a), float(b), 2 * float(b)) for a, b in zip(t, q)]
    rows += [(a, b + 1, c) for a, b, c in rows]
    path = _write(tmp_path / "two.csv",
                  "t,q1,tau1\n" + "".join(f"{a!r},{b!r},{c!r}\n" for a, b, c in rows))
    with pytest.raises(InputError) as err:
        read_recording(path)
    assert str(err.value).startswith(f"{path}: row 52, column t: the time goes back from 0.49 s "
                                     "to 0 s, 49 median steps (a recording appended to another?")
    with pytest.raises(InputError, match="row 52, column t: the time goes back"):
        recording_from_arrays(np.concatenate([t, t]), np.concatenate([q, q + 1])[:, None],
                              np.zeros((100, 1)))
    for name in ("time", "__time"):     # the file's own name of its time column
        _write(path, f"{name},q1,tau1\n" + "".join(f"{a!r},{b!r},{c!r}\n" for a, b, c in rows))
        with pytest.raises(InputError, match=f"row 52, column {name}: the time goes back"):
            read_recording(path)

def test_columns_in_any_order_with_derivatives(tmp_path):
    body = "".join(f"{0.01 * k},{k},{2 * k},{3 * k},{4 * k}\n" for k in range(12))
    rec = read_recording(_write(tmp_path / "r.csv", "t,tau1,q1,qdd1,qd1\n" + body))
    assert rec.tau[:, 0].tolist() == list(range(12))
    assert rec.q[1, 0] == 2 and rec.qdd[1, 0] == 3 and rec.qd[1, 0] == 4



def test_the_time_column_may_stand_anywhere(tmp_path):
    """A log that writes its time stamps last (or amid the joints) reads as one that writes
    them first (it was refused: the header had to start with t)."""
    rows = [(0.01 * k, float(np.sin(k)), 2.0 * k) for k in range(12)]
    first = _write(tmp_path / "a.csv", "t,q1,tau1\n" + "".join(f"{a!r},{b!r},{c!r}\n"
                                                              for a, b, c in rows))
    last = _write(tmp_path / "b.csv", "tau1,q1,t\n" + "".join(f"{c!r},{b!r},{a!r}\n"
                                                              for a, b, c in rows))
    a, b = read_recording(first), read_recording(last)
    assert np.array_equal(a.t, b.t) and np.array_equal(a.q, b.q) and np.array_equal(a.tau, b.tau)
    body = "".join(f"{c!r},{b!r},{1e11 if k == 3 else a!r}\n" for k, (a, b, c) in enumerate(rows))
    with pytest.raises(InputError, match="row 5, column t: 1e.11 is beyond the supported"):
        read_recording(_write(tmp_path / "c.csv", "tau1,q1,t\n" + body))

@pytest.mark.parametrize("header, where", [
    ("t,q1,q1,tau1", "column q1"),
    ("t,q1,q2,tau1", "column tau2"),
    ("t,q1,tau1,i1", "column i1"),
    ("x,q1,tau1", "column x"),
    ("q1,tau1", "column t: no time column t"),
    ("t,q1,tau1,t", "column t: column 't' appears twice"),
    ("t1,q1,tau1", "column t1: unknown column"),
    ("t,q0,q2,tau1,tau2", "column q1: missing column 'q1'"),     # from 0: q0, q1, ..
    ("t,q-1,tau1", "column q-1: unknown column"),
])
def test_bad_headers(tmp_path, header, where):
    path = _write(tmp_path / "h.csv", header + "\n")
    with pytest.raises(InputError, match=where) as exc:
        read_recording(path)
    assert "row 1" in str(exc.value) and str(path) in str(exc.value)


def test_currents_need_the_flag(tmp_path):
    body = "".join(f"{0.01 * k},{k},{k}\n" for k in range(12))
    path = _write(tmp_path / "c.csv", "t,q1,i1\n" + body)
    assert read_recording(path, current=True).current


def test_a_huge_torque_is_refused_with_its_row(tmp_path):
    body = "".join(f"{0.01 * k},{k},{1e12 if k == 5 else k}\n" for k in range(12))
    with pytest.raises(InputError, match="row 7, column tau1"):
        read_recording(_write(tmp_path / "b.csv", "t,q1,tau1\n" + body))


def test_too_few_distinct_stamps_name_the_row_and_the_time_column(tmp_path):
    """A log whose clock stalled (every row the same stamp) is refused naming the first row that
    repeats a stamp and the column t (the line said "key t", as of a TOML key)."""
    body = "".join(f"0.5,{0.1 * k},{k}\n" for k in range(12))
    path = _write(tmp_path / "s.csv", "t,q1,tau1\n" + body)
    with pytest.raises(InputError, match=r"row 3, column t: 1 distinct time stamps \(this row "
                                         r"repeats an earlier one, as 10 more do\)") as exc:
        read_recording(path)
    assert str(exc.value).startswith(str(path))

def test_arrays_are_checked():
    t = np.arange(12) * 0.01
    with pytest.raises(InputError, match="not finite"):
        recording_from_arrays(t, np.full((12, 1), np.nan), np.zeros((12, 1)))
    with pytest.raises(InputError, match="shape"):
        recording_from_arrays(t, np.zeros((12, 1)), np.zeros((11, 1)))



@pytest.mark.parametrize("kwargs, where", [
    ({"current": np.ones((12, 1))}, "current: True or False, not a ndarray"),
    ({"current": "no"}, "current: True or False, not a str"),
    ({"current": 1}, "current: True or False, not a int"),
    ({"source": 3}, "source: a name"),
    ({"t": "abc"}, "key t: t must hold real numbers"),
    ({"q": None}, "key q: q must hold real numbers"),
    ({"tau": {}}, "key tau: tau must hold real numbers"),
    ({"t": np.arange(12) * (0.01 + 1j)}, "key t: t must hold real numbers"),
    ({"t": np.zeros((12, 2))}, r"key t: t must have shape \(N,\)"),
    ({"q": np.zeros((12, 1, 1))}, r"key q: q must have shape \(N, n\)"),
    ({"q": np.zeros((12, 0)), "tau": np.zeros((12, 0))}, "key q: q must have shape"),
    ({"qd": np.full((12, 1), np.inf)}, "key qd: inf at sample 0 is not finite"),
    ({"tau": np.full((12, 1), 1e300)}, "key tau: 1e.300 at sample 0 is not finite or beyond"),
])
def test_arrays_of_another_type_shape_or_value_are_one_line_naming_the_argument(kwargs, where):
    """The Python API's arguments are checked as a file's cells are: one InputError line
    naming the argument (before, ``current`` took any value, an array of currents raised
    numpy's ambiguous truth value, text or None in q a ValueError or AttributeError)."""
    args = {"t": 0.01 * np.arange(12), "q": np.zeros((12, 1)), "tau": np.zeros((12, 1))}
    with pytest.raises(InputError, match=where) as err:
        recording_from_arrays(**{**args, **kwargs})
    assert "\n" not in str(err.value)
    assert recording_from_arrays(**args, current=np.True_).current is True

def test_a_large_file_reads_as_a_small_one_and_names_a_bad_cell(tmp_path):
    rows = [f"{0.001 * k},{float(np.sin(k))!r},{k}" for k in range(15_000)]
    good = _write(tmp_path / "big.csv", "t,q1,tau1\n" + "\n".join(rows) + "\n")
    assert good.stat().st_size > FAST_PARSE_BYTES
    rec = read_recording(good)
    assert rec.q.shape == (15_000, 1) and rec.rows[-1] == 15_001
    assert rec.q[7, 0] == np.sin(7)
    rows[12_500] = "12.5,1_0,3"
    bad = _write(tmp_path / "bad.csv", "t,q1,tau1\n" + "\n".join(rows) + "\n")
    with pytest.raises(InputError, match="row 12502, column q1"):
        read_recording(bad)


@pytest.mark.parametrize("defect", [None, "order", "cell", "huge", "blank", "bom crlf",
                                    "spaced header", "unknown column"])
def test_a_large_recording_is_streamed_as_the_cell_by_cell_reading_reads_it(tmp_path,
                                                                             monkeypatch,
                                                                             defect):
    """Above FAST_PARSE_BYTES a regular recording is parsed by pandas a piece at a time; its
    values, rows, notes and SHA-256, or its error, are those of the cell-by-cell reading of the
    same file (the threshold raised above its size); the streamed path is taken where the file
    is regular, and it never holds the file's bytes whole."""
    import hashlib
    import tracemalloc
    import warnings

    import gd_analyze.trajectory.trajectory as trajectory

    rng = np.random.default_rng(3)
    t = np.arange(10_000) * 1e-3
    if defect == "order":
        t[[100, 101]] = t[[101, 100]]
        t[5000] = t[4999]
    x = rng.normal(size=(t.size, 4)) * 10.0 ** rng.integers(-3, 3, (t.size, 4))
    # every double written out exactly (80 decimals): the file is about 10 times its values
    lines = [",".join(f"{float(v):.80f}" for v in (t[k], *x[k])) for k in range(t.size)]
    if defect == "cell":
        lines[7_000] = lines[7_000].replace(",", ",1_0,", 1).replace(",", "", 1)
    elif defect == "huge":
        lines[9000] = f"{float(t[9000]):.80f},0.5,0.5,1e30,2.0"
    elif defect == "blank":
        lines[3000] = ""
    header = {"spaced header": "t, q2 ,q1,tau2 , tau1", "unknown column": "t,q1,q2,tau1,x2"}.get(
        defect, "t,q1,q2,tau1,tau2")
    end = "\r\n" if defect == "bom crlf" else "\n"
    path = tmp_path / "r.csv"
    path.write_bytes((b"\xef\xbb\xbf" if defect == "bom crlf" else b"")
                     + (header + end + end.join(lines) + end).encode())
    assert path.stat().st_size > FAST_PARSE_BYTES
    monkeypatch.setattr(trajectory, "PARSE_PIECE", 1 << 16)
    taken = []
    stream = trajectory.streamed_values
    monkeypatch.setattr(trajectory, "streamed_values",
                        lambda *a: taken.append(stream(*a)) or taken[-1])

    bom_notes = []

    def read():
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            try:
                return read_recording(path, 2)
            except InputError as err:
                return str(err)
            finally:
                bom_notes.append(any("byte-order mark" in str(w.message) for w in said))

    read_recording(tmp_path / "f.csv" if (tmp_path / "f.csv").write_text(
        "t,q1,tau1\n" + "".join(f"{k},0,0\n" for k in range(30_000))) else None)  # imports
    taken.clear()
    tracemalloc.start()
    try:
        streamed = read()
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert (taken[0] is not None) == (defect in (None, "order", "huge", "bom crlf",
                                                 "spaced header"))
    monkeypatch.setattr(trajectory, "FAST_PARSE_BYTES", 1 << 40)
    whole = read()
    assert len(taken) == 1
    assert bom_notes[-2:] == [defect == "bom crlf"] * 2
    if isinstance(whole, str):
        assert streamed == whole and "row" in whole
        return
    for name in ("t", "q", "tau", "rows"):
        np.testing.assert_array_equal(getattr(streamed, name), getattr(whole, name))
    assert streamed.notes == whole.notes and (len(whole.notes) > 0) == (defect == "order")
    assert streamed.sha256 == whole.sha256 == hashlib.sha256(path.read_bytes()).hexdigest()
    if defect is None:        # the values, their copies in time order, pieces: not the bytes
        assert peak < path.stat().st_size / 2, peak


@pytest.mark.parametrize("args, said", [
    ((None,), "path: a CSV file (str or os.PathLike), not a NoneType"),
    (("r.csv", "2"), "n_joints: a whole number >= 1, not str '2'"),
    (("r.csv", 1.5), "n_joints: a whole number >= 1, not float '1.5'"),
    (("r.csv", -1), "n_joints: a whole number >= 1, not int '-1'"),
    # read as True: the torque columns taken for currents
    (("r.csv", None, "no"), "current: True or False, not a str"),
])
def test_arguments_of_another_type_are_one_line_naming_the_argument(tmp_path, monkeypatch,
                                                                     args, said):
    """None read as the file "None" ("None: no such file"), and a joint count "2" gave "the
    file has 1 joint position columns, the robot has 2 joints"; the file here is a good one."""
    monkeypatch.chdir(tmp_path)
    _write(tmp_path / "r.csv", "t,q1,tau1\n" + "".join(f"{0.01 * k},{k},{k}\n" for k in range(12)))
    with pytest.raises(InputError) as e:
        read_recording(*args)
    assert str(e.value) == said
    assert read_recording("r.csv", 1).n == 1


def _named(path, header, rows=12, shift=0.0):
    """A recording whose columns name joints as ROS joint_states exports do ("- " prefix)."""
    cells = ["t"] + [f"- {h}" for h in header]
    body = "".join(",".join([repr(0.01 * k + shift * (k == 7))] + [f"{0.1 * k + c}" for c in
                                                                   range(len(header))]) + "\n"
                   for k in range(rows))
    return _write(path, ",".join(cells) + "\n" + body)


def test_columns_naming_the_robot_s_joints_read_as_numbered_ones(tmp_path):
    """Columns <joint>_position/_velocity/_effort of the chain's joint names (any order, a
    leading "- ", files on one clock joined by '+') read as q, qd and tau; another joint's
    columns are ignored with one note naming it. The old reader refused the name."""
    joints = ["shoulder", "elbow"]
    pos = _named(tmp_path / "pos.csv", ["elbow_position", "head_position", "shoulder_position"])
    eff = _named(tmp_path / "eff.csv", ["shoulder_effort", "elbow_effort", "head_effort"])
    vel = _named(tmp_path / "vel.csv", ["elbow_velocity", "shoulder_velocity"])
    with pytest.warns(InputNote, match=r"columns of joints outside the chain ignored: head$"):
        rec = read_recording(f"{pos}+{vel}+{eff}", 2, joint_names=joints)
    k = 0.1 * np.arange(12)
    np.testing.assert_array_equal(rec.q, np.column_stack([k + 2, k]))
    np.testing.assert_array_equal(rec.tau, np.column_stack([k, k + 1]))
    np.testing.assert_array_equal(rec.qd, np.column_stack([k + 1, k]))
    assert rec.qdd is None and rec.source == f"{pos}+{vel}+{eff}"
    assert [f for f, _ in rec.files] == [str(pos), str(vel), str(eff)]
    assert [h for _, h in rec.files] == [hashlib.sha256(p.read_bytes()).hexdigest()
                                         for p in (pos, vel, eff)]


def test_joint_limit_warnings_name_a_named_recording_s_own_column(tmp_path, two_link):
    """A recording whose columns name the two-link's joints as ROS exports do ("- " prefix,
    positions and efforts in two files on one clock), joint 2's positions in degrees by
    mistake: the warning names the file's column "- joint2_position" and the file's row of the
    first sample beyond +-pi (oracle: the header and the rows the test wrote), where it
    said "column q2", a name the file does not hold."""
    j1, j2 = two_link.joint_names()
    t, q2 = (0.01 * np.arange(12)).tolist(), np.degrees(np.linspace(-0.5, 1.0, 12)).tolist()
    pos, eff = tmp_path / "pos.csv", tmp_path / "eff.csv"
    pos.write_text(f"t,- {j2}_position,- {j1}_position\n" + "".join(
        f"{a!r},{b!r},0.1\n" for a, b in zip(t, q2)))
    eff.write_text(f"t,- {j1}_effort,- {j2}_effort\n" + "".join(f"{a!r},1,2\n" for a in t))
    rec = read_recording(f"{pos}+{eff}", 2, joint_names=[j1, j2])
    with pytest.warns(JointLimitWarning) as caught:
        messages = check_joint_limits(two_link, rec)
    row = 2 + int(np.flatnonzero(np.abs(q2) > math.pi)[0])     # header = row 1
    assert messages == [str(w.message) for w in caught] and len(messages) == 1
    assert messages[0].startswith(f"{pos}+{eff}: row {row}, column - {j2}_position: joint 2 at ")
    assert messages[0].endswith(f"; in degrees? (- {j2}_position read in degrees lies within "
                                f"them)")
    assert [rec.column(k, j) for k in ("q", "tau") for j in (0, 1)] == [
        f"- {j}_{f}" for f in ("position", "effort") for j in (j1, j2)]


@pytest.mark.parametrize("files, said", [
    ({"a.csv": "t,q1,shoulder_position,tau1"}, "a.csv: row 1, column - shoulder_position: "
     "column '- shoulder_position' names a joint, column '- q1' of"),
    ({"a.csv": "t,shoulder_position,elbow_position,shoulder_effort"},
     "a.csv: row 1, column elbow_effort: missing column 'elbow_effort'"),
    ({"a.csv": "t,shoulder_position,elbow_position", "b.csv": "t,shoulder_effort,elbow_position"},
     "b.csv: row 1, column - elbow_position: column '- elbow_position' appears twice, in "),
    ({"a.csv": "t,shoulder_position,elbow_position", "b.csv": "t,q1,q2"},
     "b.csv: row 1, column - q1: column '- q1' numbers a joint, column "),
    ({"a.csv": "t,shoulder_position,elbow_position", "b.csv": "shoulder_effort,elbow_effort"},
     "b.csv: row 1, column t: no time column t"),
])
def test_a_named_or_joined_recording_that_cannot_be_read_is_one_line(tmp_path, files, said):
    paths = []
    for name, header in files.items():
        cells = [c for c in header.split(",") if c != "t"]
        path = _named(tmp_path / name, cells)
        if not header.startswith("t,"):
            lines = path.read_text().splitlines()
            path.write_text("\n".join(",".join(r.split(",")[1:]) for r in lines) + "\n")
        paths.append(str(path))
    with pytest.raises(InputError) as e:
        read_recording("+".join(paths), 2, joint_names=["shoulder", "elbow"])
    assert said in str(e.value) and "\n" not in str(e.value), str(e.value)


@pytest.mark.parametrize("rows", [12, 12_000])
def test_a_header_both_naming_and_numbering_joints_names_its_column_at_any_size(tmp_path, rows):
    """The header's first numbered column after a named one is the one named, whatever the
    file's size: above FAST_PARSE_BYTES the streamed parse's look at the header is the first,
    and the message named column 't' and a column of that look (the cell-by-cell parse checked
    the header again against what the first look had noted)."""
    path = _named(tmp_path / "m.csv", ["shoulder_position", "q2", "tau1", "tau2"], rows=rows)
    assert (path.stat().st_size > FAST_PARSE_BYTES) == (rows > 12)
    with pytest.raises(InputError) as e:
        read_recording(path, 2, joint_names=["shoulder", "elbow"])
    assert str(e.value) == (f"{path}: row 1, column - q2: column '- q2' numbers a joint, column "
                            f"'- shoulder_position' of {path} names one")


def test_joined_files_whose_clocks_differ_are_refused_with_the_row(tmp_path):
    a = _named(tmp_path / "a.csv", ["j_position"])
    b = _named(tmp_path / "b.csv", ["j_effort"], shift=1e-4)
    with pytest.raises(InputError, match=r"b\.csv: row 9, column t: the clock is not .*a\.csv's: "
                                         r"t = 0\.0701 s, there 0\.07 s"):
        read_recording(f"{a}+{b}", joint_names=["j"])
    c = _named(tmp_path / "c.csv", ["j_effort"], rows=11)
    with pytest.raises(InputError, match=r"c\.csv: row 12, column t: .*11 rows, .* has 12"):
        read_recording(f"{a}+{c}", joint_names=["j"])


def test_only_a_continuous_revolute_joint_s_wraps_are_undone_and_only_for_the_spline():
    """Of three joints stepping by more than pi, the continuous revolute one (infinite limits)
    is unwrapped, and its qd and qdd are the not-a-knot spline's through the unwrapped positions
    (oracle: SciPy's CubicSpline on them); a revolute joint with limits and a prismatic one are
    left as they are, as is a trajectory whose qd and qdd were given. One warning line."""
    from types import SimpleNamespace

    from scipy.interpolate import CubicSpline

    from gd_analyze.errors import InputWarning

    robot = SimpleNamespace(q_min=np.array([-np.inf, -np.pi, -np.inf]),
                            q_max=np.array([np.inf, np.pi, np.inf]),
                            prismatic=np.array([False, False, True]))
    t = np.linspace(0.0, 1.0, 41)
    true = np.pi + np.sin(6 * t)                # crosses pi both ways
    q = np.column_stack([true, true, np.where(t < 0.5, 0.0, 4.0)])
    q[:, :2] = (q[:, :2] + np.pi) % (2 * np.pi) - np.pi
    traj = trajectory_from_arrays(t, q)
    with pytest.warns(InputWarning) as caught:
        got = unwrapped(robot, traj)
    assert [str(w.message) for w in caught] == [
        f"trajectory arrays: key q1: joint 1's positions step by "
        f"{abs(np.diff(q[:, 0])).max():.2g} rad (wrapped at +-pi, a continuous joint's log?): "
        f"unwrapped before the cubic spline gives qd and qdd"]
    want = q.copy()
    want[:, 0] = true - true[0] + q[0, 0]      # the motion itself, from the first position
    np.testing.assert_allclose(got.q, want, rtol=0, atol=1e-13)
    spline = CubicSpline(t, want, axis=0, bc_type="not-a-knot")
    np.testing.assert_allclose(got.qd, spline(t, 1), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(got.qdd, spline(t, 2), rtol=1e-12, atol=1e-9)
    assert (got.source, got.sha256, got.derivatives) == (traj.source, traj.sha256, traj.derivatives)
    given = trajectory_from_arrays(t, q, traj.qd, traj.qdd)
    assert unwrapped(robot, given) is given


def test_a_recording_naming_the_joints_is_read_as_a_trajectory(tmp_path):
    """A recording whose columns name the robot's joints ("- joint2_effort", ...; shuffled, as
    a ROS joint_states export), as identify reads it: the main job's reader takes its set
    points as it does those of the same recording numbered (t,q1..,tau1..), its torques
    ignored with a note naming the file's own columns. It was refused ("the header must start
    with 't'")."""
    rng = np.random.default_rng(4)
    t = np.arange(40) * 0.01
    q, tau = rng.normal(size=(40, 2)), rng.normal(size=(40, 2))
    numbered = tmp_path / "numbered.csv"
    named = tmp_path / "named.csv"
    cells = {"t": t, "q1": q[:, 0], "q2": q[:, 1], "tau1": tau[:, 0], "tau2": tau[:, 1]}
    pd.DataFrame(cells).to_csv(numbered, index=False, float_format="%.17g")
    pd.DataFrame({"- joint2_effort": tau[:, 1], "t": t, "- joint1_position": q[:, 0],
                  "- joint2_position": q[:, 1], "- joint1_effort": tau[:, 0]}).to_csv(
        named, index=False, float_format="%.17g")
    with pytest.warns(InputNote) as notes:
        ours = read_trajectory(named, 2, ["joint1", "joint2"])
    with pytest.warns(InputNote):
        theirs = read_trajectory(numbered, 2)
    for key in ("t", "q", "qd", "qdd"):
        assert np.array_equal(getattr(ours, key), getattr(theirs, key)), key
    assert ours.derivatives == "cubic-spline"
    assert any("its torques - joint1_effort..- joint2_effort are ignored" in str(w.message)
               for w in notes), [str(w.message) for w in notes]
    assert np.array_equal(as_trajectory(str(named), 2, ["joint1", "joint2"]).q, theirs.q)
    with pytest.raises(InputError, match="unknown column"):       # without the robot's names
        read_trajectory(named, 2)


def _read_as_named(path, t, fields, joints):
    """(recording read, the same values read from columns naming the joints, the notes) of a
    ROS log ``path`` of the fields written (oracle: ``t,<joint>_position,..`` in the same
    values): each array read from the log equals the named file's."""
    named = path.with_name("named.csv")
    pd.DataFrame({"t": t, **{f"{j}_{k}": v[:, c] for k, v in fields.items()
                             for c, j in enumerate(joints)}}).to_csv(named, index=False,
                                                                     float_format="%.17g")
    with pytest.warns(InputNote) as caught:
        ours = read_recording(path, len(joints), joint_names=joints)
    theirs = read_recording(named, len(joints), joint_names=joints)
    for key in ("t", "q", "qd", "tau"):
        assert np.array_equal(getattr(ours, key), getattr(theirs, key)), key
    return ours, theirs, caught


def test_a_rostopic_echo_log_of_joint_states_reads_as_the_same_recording_named(tmp_path):
    """A ``rostopic echo -p /joint_states`` log (ROS 1's CSV: %time, field.header.stamp in ns,
    the joints named in field.name<k> of each row in any order, their fields by index, a
    gripper joint and another publisher's rows beside the chain's) reads as the recording
    whose columns name the joints (oracle: the same values written as <joint>_position...,
    t = the stamps [ns] / 1e9), with one note; it was refused ("unknown column '%time'"). The
    main job's reader takes its set points alike."""
    rng = np.random.default_rng(5)
    joints = ["shoulder", "elbow"]
    fields = {k: rng.normal(size=(40, 2)) for k in ("position", "velocity", "effort")}
    t = write_echo_log(tmp_path / "echo.csv", 0.01 * np.arange(40), fields, joints, other_rows=(3,))
    ours, theirs, caught = _read_as_named(tmp_path / "echo.csv", t, fields, joints)
    assert ours.rows.tolist() == [2, 3, 4, 5] + list(range(7, 43))     # row 6: the gripper's
    assert [str(w.message) for w in caught] == [
        f"{tmp_path / 'echo.csv'}: a rostopic echo -p log of joint states: t from "
        f"field.header.stamp [ns]; 1 row naming none of the chain's joints left out (first at "
        f"row 6); joints outside the chain ignored: gripper"]
    with pytest.warns(InputNote):
        assert np.array_equal(read_trajectory(tmp_path / "echo.csv", 2, joints).q, theirs.q)


@pytest.mark.parametrize("rows", [40, 20_000])
def test_a_rostopic_echo_log_reads_alike_by_pandas_and_cell_by_cell(tmp_path, monkeypatch, rows):
    """The parse by pandas (a large log: 200,000 rows of 7 joints took 20 s and 1.2 GiB cell by
    cell) and the one cell by cell that names faults give the same recording: values, rows
    and note (oracle: the cell-by-cell reader, forced; the pandas one forced too)."""
    from gd_analyze.trajectory import trajectory as module

    rng = np.random.default_rng(9)
    fields = {k: rng.normal(size=(rows, 3)) for k in ("position", "velocity", "effort")}
    write_echo_log(tmp_path / "log.csv", 0.001 * np.arange(rows), fields, ["a", "b", "c"],
                   other_rows=(2, rows - 3))
    got = []
    for forced in ("_echoed_rows", "_echoed_frame"):       # each reader with the other off
        with monkeypatch.context() as m:
            m.setattr(module, forced, lambda *a, **k: pytest.fail(f"{forced} was called")
                      if forced == "_echoed_rows" else None)
            with pytest.warns(InputNote) as caught:
                got.append((read_recording(tmp_path / "log.csv", 3, joint_names=["a", "b", "c"]),
                            [str(w.message) for w in caught]))
    (fast, fast_notes), (slow, slow_notes) = got
    for key in ("t", "q", "qd", "tau", "rows"):
        assert np.array_equal(getattr(fast, key), getattr(slow, key)), key
    assert fast_notes == slow_notes and "2 rows naming none" in fast_notes[0]
    assert np.array_equal(fast.q, fields["position"])


@pytest.mark.parametrize("row, said", [
    ("shoulder,gripper,1,2", "row 3, column field.name0: joint 'elbow' of the chain is not named "
                             "in this row (it names shoulder, gripper)"),
    ("shoulder,elbow,1,x", "row 3, column field.position1: not a number: 'x'"),
    ("shoulder,elbow,1", "row 3: ragged row: 7 cells, the header has 8"),
])
def test_a_rostopic_echo_log_row_that_cannot_be_read_is_one_line(tmp_path, row, said):
    """Row 3 of a rostopic echo -p log names one joint of the chain and not the other, holds a
    cell that is not a number, or lacks a position: one line with the file, row and column."""
    head = "%time,field.header.seq,field.header.stamp,field.header.frame_id,field.name0," \
        "field.name1,field.position0,field.position1\n"
    rows = [f"{k}0000000,{k},{k}0000000,,shoulder,elbow,0.{k},0.{k}" for k in range(1, 13)]
    rows[1] = f"20000000,2,20000000,,{row}"
    _write(tmp_path / "e.csv", head + "\n".join(rows) + "\n")
    with pytest.raises(InputError) as e:
        read_recording(tmp_path / "e.csv", 2, joint_names=["shoulder", "elbow"])
    assert str(e.value) == f"{tmp_path / 'e.csv'}: {said}"


def _plotjuggler_export(path, t, fields, joints, blank_rows=(), extra=""):
    """PlotJuggler's CSV export of a bag holding a JointState topic (a gripper joint beside the
    chain's, its header stamp) and a second topic whose samples fall between: ``__time`` [s],
    the series in its alphabetical order, a row per stamp of any series, blank cells where a
    series has none; ``blank_rows``: rows (from 0) whose first joint's position is blank."""
    series = {"/joint_states/header/stamp": t}
    for kind, values in fields.items():
        for c, joint in enumerate([*joints, "gripper"]):
            series[f"/joint_states/{joint}/{kind}"] = values[:, c] if c < len(joints) else 0 * t
    names = sorted(series) + ["/wrench/force/x"]
    lines = ["__time," + ",".join(names) + extra]
    for r, stamp in enumerate(t):
        cells = ["" if (r in blank_rows and name == f"/joint_states/{joints[0]}/position")
                 else repr(float(series[name][r])) for name in names[:-1]]
        lines.append(",".join([repr(float(stamp)), *cells, ""]))
        if r % 4 == 1:                     # the other topic's sample, between two joint states
            lines.append(",".join([repr(float(stamp) + 1e-4), *[""] * (len(names) - 1), "2.5"]))
    Path(path).write_text("\n".join(lines) + "\n")


def test_plotjuggler_s_csv_export_of_joint_states_reads_as_the_same_recording_named(tmp_path):
    """PlotJuggler's CSV export (``__time``; ``/joint_states/<joint>/position``, ``/velocity``,
    ``/effort``, in its alphabetical order, a gripper's series, the header stamp and another
    topic's series beside them; the other topic's rows blank in the joint states' series), as
    ROS 1 and ROS 2 users export a bag, reads as the recording whose columns name the joints
    (oracle: the same values written as <joint>_position...), with one note; it was refused
    ("unknown column '__time'"). The main job's reader takes its set points alike."""
    rng = np.random.default_rng(12)
    joints = ["shoulder", "elbow"]
    t = 1.7e9 + 0.01 * np.arange(30)
    fields = {k: rng.normal(size=(30, 2)) for k in ("position", "velocity", "effort")}
    _plotjuggler_export(tmp_path / "pj.csv", t, fields, joints)
    ours, theirs, caught = _read_as_named(tmp_path / "pj.csv", t, fields, joints)
    assert ours.rows[:4].tolist() == [2, 3, 5, 6]          # row 4: the other topic's sample
    assert [str(w.message) for w in caught] == [
        f"{tmp_path / 'pj.csv'}: PlotJuggler's CSV export: t from __time [s]; 5 other columns "
        f"ignored (joints outside the chain: gripper); 8 rows holding none of the chain's "
        f"series left out (first at row 4)"]
    assert ours.column("q", 1) == "/joint_states/elbow/position"
    with pytest.warns(InputNote):
        assert np.array_equal(read_trajectory(tmp_path / "pj.csv", 2, joints).q, theirs.q)


@pytest.mark.parametrize("blank, extra, said", [
    ((5,), "", "row 8, column /joint_states/shoulder/position: a blank cell beside the other "
               "joints' values in this row"),
    ((), ",/arm/joint_states/elbow/position", "row 1, column /arm/joint_states/elbow/position: "
     "columns '/joint_states/elbow/position' and '/arm/joint_states/elbow/position' both hold "
     "joint 'elbow''s position"),
])
def test_a_plotjuggler_export_that_cannot_be_read_is_one_line(tmp_path, blank, extra, said):
    """A PlotJuggler export whose row lacks one joint's position beside the others', or that
    holds a joint's series of two topics: one line with the file, row and column."""
    rng = np.random.default_rng(3)
    fields = {k: rng.normal(size=(12, 2)) for k in ("position", "effort")}
    _plotjuggler_export(tmp_path / "p.csv", 0.01 * np.arange(12), fields, ["shoulder", "elbow"],
                        blank_rows=blank, extra=extra)
    if extra:       # the second topic's series: a cell in each row
        lines = (tmp_path / "p.csv").read_text().splitlines()
        (tmp_path / "p.csv").write_text("\n".join([lines[0], *(x + ",0" for x in lines[1:])]))
    with pytest.raises(InputError) as e:
        read_recording(tmp_path / "p.csv", 2, joint_names=["shoulder", "elbow"])
    assert str(e.value) == f"{tmp_path / 'p.csv'}: {said}"


def _rtde_log(path, t, fields, delimiter=" ", torques=True):
    """A UR RTDE log as the RTDE client's record.py (spaces) or ur_rtde's file recording
    (commas) writes it with a recipe of targets, measurements and others: ``timestamp``, each
    6-vector as ``<field>_0..<field>_5``, an integer field; ``fields``: the measured
    ``actual_q``, ``actual_qd``, ``actual_current`` and (``torques``)
    ``actual_current_as_torque`` [N m], the targets random."""
    rng = np.random.default_rng(1)
    recipe = ["target_q", "target_qd", "target_qdd", "target_current", "target_moment",
              "actual_current", "actual_q", "actual_qd", "actual_TCP_pose", "robot_mode",
              *(["actual_current_as_torque"] if torques else [])]
    head, blocks = ["timestamp"], [t[:, None]]
    for name in recipe:
        width = 1 if name == "robot_mode" else 6
        head += [name] if width == 1 else [f"{name}_{k}" for k in range(6)]
        blocks.append(fields[name] if name in fields else np.round(
            rng.normal(size=(t.size, width)), 1 if width == 1 else 6))
    lines = [delimiter.join(head)] + [delimiter.join(repr(float(v)) for v in row)
                                      for row in np.hstack(blocks)]
    Path(path).write_text("\n".join(lines) + "\n")


@pytest.mark.parametrize("delimiter", [" ", ","])
def test_a_ur_rtde_log_reads_as_the_recording_of_its_measured_fields(tmp_path, delimiter):
    """A UR RTDE log (record.py's spaces, ur_rtde's commas; targets, currents, the TCP pose and
    the robot mode beside the measured fields) reads as the recording t = timestamp, q =
    actual_q, qd = actual_qd, tau = actual_current_as_torque (oracle: the arrays written), its
    joints numbered from 0 counted from 1; with --current, tau holds actual_current. It was
    refused ("unknown column 'timestamp target_q_0 ..'")."""
    rng = np.random.default_rng(4)
    t = 1234.5 + 0.008 * np.arange(25)
    fields = {k: rng.normal(size=(25, 6)) for k in (
        "actual_q", "actual_qd", "actual_current", "actual_current_as_torque")}
    _rtde_log(tmp_path / "ur.csv", t, fields, delimiter)
    for current, tau in ((False, "actual_current_as_torque"), (True, "actual_current")):
        with pytest.warns(InputNote) as caught:
            rec = read_recording(tmp_path / "ur.csv", 6, current=current)
        for key, want in (("t", t), ("q", fields["actual_q"]), ("qd", fields["actual_qd"]),
                          ("tau", fields[tau])):
            assert np.array_equal(getattr(rec, key), want), key
        assert rec.qdd is None and rec.column("tau", 5) == f"{tau}_5"
        said = [str(w.message) for w in caught]
        assert said[0] == f"{tmp_path / 'ur.csv'}: a UR RTDE log: t from timestamp [s], " + (
            "motor currents from actual_current" if current else
            "torques from actual_current_as_torque") + "; 43 other columns ignored"
        kinds = [f"{k}_0..{k}_5" for k in ("actual_q", "actual_qd", tau)]    # the file's order
        kinds = kinds[2:] + kinds[:2] if current else kinds
        assert said[1] == f"{tmp_path / 'ur.csv'}: columns {', '.join(kinds)} number the joints " \
            f"from 0: read as joints from 1"
    with pytest.warns(InputNote):
        assert np.array_equal(read_trajectory(tmp_path / "ur.csv", 6).q, fields["actual_q"])


def test_a_ur_rtde_log_without_torques_says_what_to_record(tmp_path):
    """An RTDE log of a controller before PolyScope 5.23 (no actual_current_as_torque), read
    without --current: one line naming the field to record, or the currents to give."""
    rng = np.random.default_rng(2)
    fields = {k: rng.normal(size=(12, 6)) for k in ("actual_q", "actual_qd", "actual_current")}
    _rtde_log(tmp_path / "old.csv", 0.008 * np.arange(12), fields, torques=False)
    with pytest.raises(InputError) as e:
        read_recording(tmp_path / "old.csv", 6)
    assert str(e.value) == (
        f"{tmp_path / 'old.csv'}: row 1, column actual_current_as_torque_0: a UR RTDE log "
        f"without actual_current_as_torque_0..: record it (PolyScope 5.23 or later), or "
        f"actual_current with --current --drive-gains")


def test_files_of_one_kind_each_naming_the_joints_bare_read_as_one_recording(tmp_path):
    """FIGAROH's SO-101 recordings: one file per kind, ``q.csv``, ``dq.csv``,
    ``current_mA.csv``, each ``t`` and a column per joint by its bare name (the gripper's
    beside the chain's), joined by ``+``: the kind from the file's name, the currents read
    with --current (oracle: the arrays written), the gripper ignored with a note. They were
    refused ("unknown column 'shoulder_pan'"); without --current the currents are refused."""
    rng = np.random.default_rng(8)
    joints = ["shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll"]
    t = 0.02 * np.arange(30)
    arrays = {name: rng.normal(size=(30, 6)) for name in ("q", "dq", "current_mA")}
    for name, values in arrays.items():
        pd.DataFrame({"t": t, **{j: values[:, c] for c, j in enumerate([*joints, "gripper"])}}
                     ).to_csv(tmp_path / f"{name}.csv", index=False, float_format="%.17g")
    joined = "+".join(str(tmp_path / f"{name}.csv") for name in arrays)
    with pytest.warns(InputNote) as caught:
        rec = read_recording(joined, 5, current=True, joint_names=joints)
    for key, name in (("q", "q"), ("qd", "dq"), ("tau", "current_mA")):
        assert np.array_equal(getattr(rec, key), arrays[name][:, :5]), key
    assert [str(w.message) for w in caught] == [
        f"{joined}: columns of joints outside the chain ignored: gripper"]
    with pytest.raises(InputError, match="column 'shoulder_pan' holds a current .by the file's "
                                         "name.: give --current, --drive-gains"):
        read_recording(joined, 5, joint_names=joints)


def test_a_recording_read_as_a_trajectory_says_each_note_once(tmp_path):
    """A recording numbering its joints from 0 (``t,q0,q1,tau0,tau1``) read by the main job's
    reader: the reader's note ("... number the joints from 0") was said twice, by
    read_recording and again by read_trajectory from the recording's notes (seen on
    ``gd-analyze compare``). Oracle: each note once, the recording's note last."""
    t = 0.01 * np.arange(20)
    pd.DataFrame({"t": t, "q0": np.sin(t), "q1": np.cos(t), "tau0": t, "tau1": t}).to_csv(
        tmp_path / "rec.csv", index=False, float_format="%.17g")
    with pytest.warns(InputNote) as caught:
        read_trajectory(tmp_path / "rec.csv", 2)
    said = [str(w.message) for w in caught if issubclass(w.category, InputNote)]
    assert len(said) == len(set(said)) == 2, said
    assert "number the joints from 0" in said[0] and "a recording: its torques" in said[1]


def test_columns_numbered_from_0_and_named_dq_ddq_read_as_numbered_from_1(tmp_path):
    """``t,q0..q2,dq0..dq2,ddq0..ddq2,tau1..tau3``, as FIGAROH's UR10 recordings are written:
    the same recording as ``t,q1..,qd1..,qdd1..,tau1..`` (oracle: the arrays written), with one
    note; it was refused ("unknown column 'q0'"). A time column named ``time`` reads as t."""
    rng = np.random.default_rng(7)
    t = 0.01 * np.arange(20)
    q, qd, qdd, tau = (rng.normal(size=(20, 3)) for _ in range(4))
    cells = {"t": t, **{f"{k}{j}": v[:, j] for k, v in (("q", q), ("dq", qd), ("ddq", qdd))
                        for j in range(3)}, **{f"tau{j + 1}": tau[:, j] for j in range(3)}}
    pd.DataFrame(cells).to_csv(tmp_path / "ur.csv", index=False, float_format="%.17g")
    with pytest.warns(InputNote) as caught:
        rec = read_recording(tmp_path / "ur.csv", 3)
    for key, want in (("q", q), ("qd", qd), ("qdd", qdd), ("tau", tau)):
        assert np.array_equal(getattr(rec, key), want), key
    assert [str(w.message) for w in caught] == [
        f"{tmp_path / 'ur.csv'}: columns q0..q2, dq0..dq2, ddq0..ddq2 number the joints from 0: "
        f"read as joints from 1"]
    assert (rec.column("q", 0), rec.column("qd", 2)) == ("q0", "dq2")
    pd.DataFrame({"time" if k == "t" else k: v for k, v in cells.items()}).to_csv(
        tmp_path / "time.csv", index=False, float_format="%.17g")     # "time" for t
    with pytest.warns(InputNote):
        assert np.array_equal(read_recording(tmp_path / "time.csv", 3).t, t)
    pd.DataFrame({k: v for k, v in cells.items() if k != "q1"}).to_csv(
        tmp_path / "gap.csv", index=False)
    with pytest.raises(InputError, match=r"gap\.csv: row 1, column q1: missing column 'q1'"):
        read_recording(tmp_path / "gap.csv")


@pytest.mark.parametrize("style", [
    "{kind}_{j}",             # q_1, tau_1 (many loggers)
    "{KIND}{j}",              # Q1, TAU1
    "{kind}[{j0}]",           # q[0], tau[0] (an array's index: numbered from 0)
    "{kind}_{j0}",            # q_0 (numbered from 0)
])
@pytest.mark.parametrize("torque", ["tau", "effort", "torque", "Torque"])
def test_numbered_columns_in_any_case_with_separators_and_torque_names_read_alike(tmp_path,
                                                                                style, torque):
    """A recording whose numbered columns are written in another case, with ``_`` or an
    array's brackets before the number, and its torques named ``effort`` or ``torque``: the
    same recording as ``t,q1..,qd1..,tau1..`` (oracle: the arrays written); a column numbered
    from 0 is read from joint 1 with the note, a time column ``Time`` reads as t. They were
    refused ("unknown column 'q_1'")."""
    rng = np.random.default_rng(3)
    t = 0.01 * np.arange(20)
    q, qd, tau = (rng.normal(size=(20, 3)) for _ in range(3))

    def name(kind, j):
        return style.format(kind=kind, KIND=kind.upper(), j=j + 1, j0=j)
    cells = {"Time": t, **{name(k, j): v[:, j] for k, v in (("q", q), ("qd", qd), (torque, tau))
                           for j in range(3)}}
    pd.DataFrame(cells).to_csv(tmp_path / "r.csv", index=False, float_format="%.17g")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        rec = read_recording(tmp_path / "r.csv", 3)
    for key, want in (("t", t), ("q", q), ("qd", qd), ("tau", tau)):
        assert np.array_equal(getattr(rec, key), want), key
    assert rec.column("tau", 2) == name(torque, 2) and not rec.current
    assert [str(w.message) for w in caught] == ([
        f"{tmp_path / 'r.csv'}: columns {name('q', 0)}..{name('q', 2)}, {name('qd', 0)}.."
        f"{name('qd', 2)}, {name(torque, 0)}..{name(torque, 2)} number the joints from 0: "
        "read as joints from 1"] if "{j0}" in style else [])


def test_a_wrap_in_a_recording_naming_the_joints_is_warned_about_at_the_file_s_row_and_column(
        tmp_path):
    """A recording read as a trajectory (columns naming the joints, two rows out of order), its
    continuous joint wrapped at +-pi: the warning names the file's own column ("- wrist_position")
    and the file's row of the first sample after the wrap (oracle: the rows the test wrote),
    where it said "column q2" and the sorted set point's index + 2."""
    from types import SimpleNamespace

    from gd_analyze.errors import InputWarning

    robot = SimpleNamespace(q_min=np.array([-np.pi, -np.inf]), q_max=np.array([np.pi, np.inf]),
                            prismatic=np.array([False, False]))
    t = np.linspace(0.0, 1.0, 30)
    wrist = (np.pi + np.sin(5 * t) + np.pi) % (2 * np.pi) - np.pi
    first = int(np.flatnonzero(np.abs(np.diff(wrist)) > np.pi)[0]) + 1    # set point after it
    order = np.arange(30)
    order[[first - 1, first]] = order[[first, first - 1]]   # swapped: sorted back on reading
    lines = ["t,- wrist_position,- arm_position,- arm_effort,- wrist_effort"] + [
        f"{float(t[k])!r},{float(wrist[k])!r},0.1,1,2" for k in order]
    _write(tmp_path / "log.csv", "\n".join(lines) + "\n")
    with pytest.warns(InputNote):
        traj = read_trajectory(tmp_path / "log.csv", 2, ["arm", "wrist"])
    with pytest.warns(InputWarning) as caught:
        unwrapped(robot, traj)
    row = 2 + int(np.flatnonzero(order == first)[0])
    assert row == first + 1 and [str(w.message).split(": joint")[0] for w in caught] == [
        f"{tmp_path / 'log.csv'}: row {row}, column - wrist_position"]


def test_a_spline_beyond_the_limits_on_a_recording_naming_the_joints_names_its_column(tmp_path):
    """A recording read as a trajectory whose second joint jumps by 3 rad every microsecond:
    the cubic spline's qd beyond its supported magnitude is refused naming the file's column
    ("- wrist_position") and row, where it said "column q2", a name the file does not hold."""
    lines = ["t,- arm_position,- wrist_position,- arm_effort,- wrist_effort"] + [
        f"{k * 1e-6!r},0.1,{3.0 * (k % 2)!r},1,2" for k in range(12)]
    _write(tmp_path / "jumps.csv", "\n".join(lines) + "\n")
    with pytest.raises(InputError) as e:
        read_trajectory(tmp_path / "jumps.csv", 2, ["arm", "wrist"])
    assert str(e.value).startswith(f"{tmp_path / 'jumps.csv'}: row 2, column - wrist_position: "
                                   f"the qd derived by the cubic spline exceeds"), str(e.value)


def test_a_rostopic_echo_log_without_stamps_is_timed_by_its_time_received(tmp_path):
    """A publisher that leaves header.stamp at 0: t is %time [ns] / 1e9 (oracle: the %time the
    test wrote), and the note says so."""
    rows = [f"{(5 + k) * 10_000_000},{k},0,,elbow,shoulder,0.{k},1.{k},2,3" for k in range(12)]
    _write(tmp_path / "e.csv", "%time,field.header.seq,field.header.stamp,field.header.frame_id,"
           "field.name0,field.name1,field.position0,field.position1,field.effort0,field.effort1\n"
           + "\n".join(rows) + "\n")
    with pytest.warns(InputNote, match=r"t from %time \[ns\]$"):
        rec = read_recording(tmp_path / "e.csv", 2, joint_names=["shoulder", "elbow"])
    assert np.array_equal(rec.t, np.array([(5 + k) * 10_000_000 for k in range(12)]) / 1e9)
    assert np.array_equal(rec.q, [[float(f"1.{k}"), float(f"0.{k}")] for k in range(12)])
    assert np.array_equal(rec.tau, np.tile([3.0, 2.0], (12, 1)))
