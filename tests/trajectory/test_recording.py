"""Reading recordings: irregular, out-of-order and repeated time stamps; refusals."""

import numpy as np
import pytest

from gd_analyze.errors import InputError
from gd_analyze.trajectory.recording import read_recording, recording_from_arrays


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


def test_columns_in_any_order_with_derivatives(tmp_path):
    body = "".join(f"{0.01 * k},{k},{2 * k},{3 * k},{4 * k}\n" for k in range(12))
    rec = read_recording(_write(tmp_path / "r.csv", "t,tau1,q1,qdd1,qd1\n" + body))
    assert rec.tau[:, 0].tolist() == list(range(12))
    assert rec.q[1, 0] == 2 and rec.qdd[1, 0] == 3 and rec.qd[1, 0] == 4


@pytest.mark.parametrize("header, where", [
    ("t,q1,q1,tau1", "column q1"),
    ("t,q1,q2,tau1", "column tau2"),
    ("t,q1,tau1,i1", "column i1"),
    ("x,q1,tau1", "column x"),
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


def test_arrays_are_checked():
    t = np.arange(12) * 0.01
    with pytest.raises(InputError, match="not finite"):
        recording_from_arrays(t, np.full((12, 1), np.nan), np.zeros((12, 1)))
    with pytest.raises(InputError, match="shape"):
        recording_from_arrays(t, np.zeros((12, 1)), np.zeros((11, 1)))


def test_a_large_file_reads_as_a_small_one_and_names_a_bad_cell(tmp_path):
    rows = [f"{0.001 * k},{float(np.sin(k))!r},{k}" for k in range(3000)]
    good = _write(tmp_path / "big.csv", "t,q1,tau1\n" + "\n".join(rows) + "\n")
    rec = read_recording(good)
    assert rec.q.shape == (3000, 1) and rec.rows[-1] == 3001
    assert rec.q[7, 0] == np.sin(7)
    rows[2500] = "2.5,1_0,3"
    bad = _write(tmp_path / "bad.csv", "t,q1,tau1\n" + "\n".join(rows) + "\n")
    with pytest.raises(InputError, match="row 2502, column q1"):
        read_recording(bad)
