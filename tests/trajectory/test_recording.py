"""Reading recordings: irregular, out-of-order and repeated time stamps; refusals."""

import numpy as np
import pytest

from gd_analyze.errors import InputError
from gd_analyze.trajectory.recording import read_recording, recording_from_arrays
from gd_analyze.trajectory.trajectory import FAST_PARSE_BYTES


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
    ("t,q0,tau1", "column q0: unknown column"),
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
