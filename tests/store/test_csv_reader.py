"""One CSV reader whatever the size, checked against an independent reference parser.

Cases 1, 8 (CSV crashes), 9 (messages) and 10 (1_0, full-width digits) of the defects found, and
a hypothesis fuzz test on small files and on files large enough for the pandas path.
"""

import csv
import hashlib
import io
import os
import re

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, given, note, settings
from hypothesis import strategies as st

from gd_analyze.errors import InputError, InputNote
from gd_analyze.model.limits import LIMITS
from gd_analyze.trajectory.planning import plan_quintic
from gd_analyze.trajectory.trajectory import FAST_PARSE_BYTES, read_trajectory, write_trajectory

PLAIN = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")


def reference_parse(raw):
    """The specification, written independently of the reader: the values or None (refused)."""
    if raw.startswith(b"\xef\xbb\xbf"):
        raw = raw[3:]
    try:
        text = raw.decode("utf-8")
        rows = [r for r in csv.reader(io.StringIO(text, newline="")) if any(c.strip() for c in r)]
    except (UnicodeDecodeError, csv.Error):
        return None
    if "\x00" in text or len(rows) < 3:
        return None
    names = [c.strip() for c in rows[0]]
    n = sum(1 for c in names if re.fullmatch(r"q[0-9]+", c))
    full = ["t"] + [f"q{i}" for i in range(1, n + 1)]
    full3 = full + [f"qd{i}" for i in range(1, n + 1)] + [f"qdd{i}" for i in range(1, n + 1)]
    if n == 0 or names not in (full, full3):
        return None
    out = []
    for row in rows[1:]:
        if len(row) != len(names):
            return None
        cells = [c.strip(" \t") for c in row]
        if not all(PLAIN.fullmatch(c) and len(c) <= 1000 for c in cells):
            return None
        out.append([float(c) for c in cells])
    values = np.array(out)
    if not np.isfinite(values).all() or not (np.diff(values[:, 0]) > 0).all():
        return None
    kinds = ["t"] + ["q"] * n + (["qd"] * n + ["qdd"] * n if len(names) > n + 1 else [])
    if any(np.abs(values[:, j]).max() > LIMITS[k] for j, k in enumerate(kinds)):
        return None
    if len(names) == n + 1:           # positions only: the spline's qd and qdd within limits
        from scipy.interpolate import CubicSpline

        spline = CubicSpline(values[:, 0], values[:, 1:], axis=0)
        t = values[:, 0]
        if np.abs(spline(t, 1)).max() > LIMITS["qd"] or np.abs(spline(t, 2)).max() > \
                LIMITS["qdd"]:
            return None
    return values


def _check_against_reference(tmp_path, raw, name="f.csv"):
    path = tmp_path / name
    path.write_bytes(raw)
    expected = reference_parse(raw)
    before = set(os.listdir(tmp_path))
    try:
        traj = read_trajectory(path)
    except InputError as exc:
        assert expected is None, f"refused a valid file: {exc}"
        assert "\n" not in str(exc) and str(exc).startswith(str(path))
        assert set(os.listdir(tmp_path)) == before
        return None
    assert expected is not None, "accepted a file the specification refuses"
    n = traj.q.shape[1]
    np.testing.assert_array_equal(traj.t, expected[:, 0])
    np.testing.assert_array_equal(traj.q, expected[:, 1:n + 1])
    if expected.shape[1] > n + 1:
        np.testing.assert_array_equal(traj.qd, expected[:, n + 1:2 * n + 1])
        np.testing.assert_array_equal(traj.qdd, expected[:, 2 * n + 1:])
    return traj


# --- the numbered cases -----------------------------------------------------------------------

def _big_plan(two_link, tmp_path, setpoints=5000):
    traj = plan_quintic(two_link, np.radians([-60, -30]), np.radians([60, 30]), setpoints)
    path = tmp_path / "big.csv"
    write_trajectory(traj, path)
    assert path.stat().st_size > FAST_PARSE_BYTES
    return traj, path


def test_case1_extra_cell_per_row_in_a_large_file_is_refused(tmp_path, two_link):
    """Case 1: the pandas path took the first column as an index and shifted every column."""
    _, path = _big_plan(two_link, tmp_path)
    lines = path.read_text().splitlines()
    bad = tmp_path / "x.csv"
    bad.write_text("\n".join([lines[0]] + [ln + ",7.5" for ln in lines[1:]]) + "\n")
    with pytest.raises(InputError, match=r"x.csv: row 2: ragged row: 8 cells, the header has 7"):
        read_trajectory(bad)


def test_large_and_small_files_give_identical_values(tmp_path, two_link):
    traj, path = _big_plan(two_link, tmp_path)
    fast = read_trajectory(path)
    small = tmp_path / "small.csv"
    small.write_text("\n".join(path.read_text().splitlines()[:40]) + "\n")
    slow = read_trajectory(small)
    np.testing.assert_array_equal(fast.q[:39], slow.q)
    np.testing.assert_array_equal(fast.qdd, traj.qdd)


def test_case8_first_line_over_the_csv_field_limit(tmp_path):
    path = tmp_path / "long.csv"
    path.write_text("t" + "x" * 140_000 + "\n" + "0,1\n" * 30_000)
    with pytest.raises(InputError, match="longer than 131072 characters"):
        read_trajectory(path)


def test_case8_huge_position_in_a_positions_only_file(tmp_path):
    path = tmp_path / "p.csv"
    path.write_text("t,q1\n0,0\n1,1e308\n2,0\n")
    with pytest.raises(InputError, match=r"row 3, column q1: .*beyond the supported magnitude"):
        read_trajectory(path)


def test_spline_velocity_beyond_the_limits_is_refused(tmp_path):
    path = tmp_path / "p.csv"
    path.write_text("t,q1\n0,0\n1e-9,1000\n2e-9,0\n")
    with pytest.raises(InputError, match="derived by the cubic spline exceeds"):
        read_trajectory(path)


def test_case9_bom_is_stripped_with_a_note(tmp_path):
    path = tmp_path / "bom.csv"
    path.write_bytes(b"\xef\xbb\xbft,q1\n0,0\n1,1\n")
    with pytest.warns(InputNote, match="byte-order mark"):
        traj = read_trajectory(path)
    np.testing.assert_array_equal(traj.q[:, 0], [0.0, 1.0])


@pytest.mark.parametrize("kind, match", [("dir", "is a folder"), ("fifo", "not a regular file"),
                                         ("devnull", "not a regular file"),
                                         ("missing", "no such file")])
def test_case9_folder_fifo_devnull(tmp_path, kind, match):
    path = {"dir": tmp_path, "devnull": os.devnull, "missing": tmp_path / "none.csv"}.get(kind)
    if kind == "fifo":
        path = tmp_path / "fifo"
        os.mkfifo(path)
    with pytest.raises(InputError, match=match):
        read_trajectory(path)


@pytest.mark.parametrize("cell, match", [("1_0", "underscore"), ("\uff11", "digits other than"),
                                         ("١", "digits other than"), ("inf", "not a finite"),
                                         ("nan", "not a finite"), ("0x10", "not a number")])
@pytest.mark.parametrize("large", [False, True])
def test_case10_only_the_plain_float_grammar(tmp_path, cell, match, large):
    rows = [f"{k},{k * 0.001}" for k in range(40_000 if large else 3)]
    rows[2] = f"2,{cell}"
    path = tmp_path / "g.csv"
    path.write_text("t,q1\n" + "\n".join(rows) + "\n", encoding="utf-8")
    assert (path.stat().st_size > FAST_PARSE_BYTES) == large
    with pytest.raises(InputError, match=rf"row 4, column q1: .*{match}"):
        read_trajectory(path)


# --- fuzz: the reader against the reference parser ---------------------------------------------

_NUM = st.one_of(st.floats(-1e3, 1e3, allow_nan=False).map(repr),
                 st.floats(-1e3, 1e3, allow_nan=False).map(lambda v: f"{v:.3e}"),
                 st.integers(-1000, 1000).map(str))
_MUTATIONS = st.sampled_from([
    None, "extra_all", "extra_one", "drop_one", "underscore", "fullwidth", "nan", "inf", "blank",
    "bom", "spaces", "quotes", "reverse_t", "huge", "empty_cell", "crlf", "letters", "semicolon",
    "tab", "plus", "dot_only", "exp_only"])


def _table(data, n, rows, full):
    cols = 1 + n * (3 if full else 1)
    header = ["t"] + [f"q{i}" for i in range(1, n + 1)]
    if full:
        header += [f"qd{i}" for i in range(1, n + 1)] + [f"qdd{i}" for i in range(1, n + 1)]
    body = [[repr(k * 0.5)] + [data.draw(_NUM) for _ in range(cols - 1)] for k in range(rows)]
    return header, body


def _mutate(header, body, mutation, data):
    k = data.draw(st.integers(0, len(body) - 1))
    j = data.draw(st.integers(0, len(header) - 1))
    prefix, newline = b"", "\n"
    if mutation == "extra_all":
        body = [r + ["7.5"] for r in body]
    elif mutation == "extra_one":
        body[k] = body[k] + ["7.5"]
    elif mutation == "drop_one":
        body[k] = body[k][:-1]
    elif mutation in ("underscore", "fullwidth", "nan", "inf", "huge", "empty_cell", "letters",
                      "plus", "dot_only", "exp_only", "spaces"):
        body[k][j] = {"underscore": "1_0", "fullwidth": "\uff11", "nan": "nan", "inf": "-inf",
                      "huge": "1e300", "empty_cell": "", "letters": "1.5x", "plus": "+1.5",
                      "dot_only": ".", "exp_only": "1e", "spaces": f"  {body[k][j]} "}[mutation]
    elif mutation == "blank":
        body.insert(k, [""])
    elif mutation == "bom":
        prefix = b"\xef\xbb\xbf"
    elif mutation == "quotes":
        body[k][j] = f'"{body[k][j]}"'
    elif mutation == "reverse_t":
        body[k][0], body[-1][0] = body[-1][0], body[k][0]
    elif mutation == "crlf":
        newline = "\r\n"
    elif mutation == "semicolon":
        body[k] = [";".join(body[k])]
    elif mutation == "tab":
        body[k][j] = f"\t{body[k][j]}"
    text = newline.join(",".join(r) for r in [header] + body) + newline
    return prefix + text.encode("utf-8")


@settings(max_examples=60, deadline=None, suppress_health_check=list(HealthCheck),
          phases=[Phase.explicit, Phase.reuse, Phase.generate])
@given(data=st.data(), n=st.integers(1, 3), rows=st.integers(2, 6), full=st.booleans(),
       mutation=_MUTATIONS)
def test_fuzz_small_files_match_the_reference(tmp_path_factory, data, n, rows, full, mutation):
    tmp = tmp_path_factory.mktemp("fz")
    header, body = _table(data, n, rows, full)
    raw = _mutate(header, body, mutation, data)
    note(f"mutation {mutation}: {raw!r}")
    _check_against_reference(tmp, raw)


@settings(max_examples=12, deadline=None, suppress_health_check=list(HealthCheck),
          phases=[Phase.explicit, Phase.reuse, Phase.generate])
@given(data=st.data(), mutation=_MUTATIONS)
def test_fuzz_large_files_match_the_reference(tmp_path_factory, data, mutation):
    """Files over FAST_PARSE_BYTES take the pandas path when regular; same answers."""
    tmp = tmp_path_factory.mktemp("fzl")
    header, body = _table(data, 2, 6, True)
    body = [[repr(k * 0.001)] + body[k % 6][1:] for k in range(12_000)]
    raw = _mutate(header, body, mutation, data)
    note(f"mutation {mutation}: {raw[:300]!r}")
    assert len(raw) > FAST_PARSE_BYTES
    _check_against_reference(tmp, raw)


@pytest.mark.slow
@settings(max_examples=12, deadline=None, suppress_health_check=list(HealthCheck),
          phases=[Phase.explicit, Phase.reuse, Phase.generate])
@given(data=st.data(), mutation=_MUTATIONS, piece=st.sampled_from([509, 4099, 65521]))
def test_fuzz_large_files_parsed_in_pieces_match_the_reference(tmp_path_factory, data,
                                                               mutation, piece):
    """pandas parses a large file piece by piece (whole lines each; memory: the file and its
    values once): with pieces of 509 to 65,521 bytes, every mutated file gives the reference's
    values or error, as whole."""
    import gd_analyze.trajectory.trajectory as trajectory

    tmp = tmp_path_factory.mktemp("fzp")
    header, body = _table(data, 2, 6, True)
    body = [[repr(k * 0.001)] + body[k % 6][1:] for k in range(12_000)]
    raw = _mutate(header, body, mutation, data)
    note(f"mutation {mutation}, piece {piece}: {raw[:300]!r}")
    saved = trajectory.PARSE_PIECE
    trajectory.PARSE_PIECE = piece
    try:
        _check_against_reference(tmp, raw)
    finally:
        trajectory.PARSE_PIECE = saved


@pytest.fixture(scope="module")
def regular_file():
    """A regular file of 3,000 random rows and the reference's values of it (reference_parse),
    made once for the cases of
    :func:`test_the_fast_path_itself_gives_the_reference_values_in_pieces`; read only."""
    rng = np.random.default_rng(5)
    rows = [[repr(k * 0.001)] + [repr(float(v)) for v in
                                 rng.normal(size=6) * 10.0 ** rng.integers(-3, 3, 6)]
            for k in range(3000)]
    raw = ("t,q1,q2,qd1,qd2,qdd1,qdd2\n" + "\n".join(",".join(r) for r in rows)
           + "\n").encode()
    expected = reference_parse(raw)
    expected.setflags(write=False)
    return raw, expected


@pytest.mark.parametrize("threads", [1, 3])
@pytest.mark.parametrize("piece", [509, 4099, 1 << 25])
def test_the_fast_path_itself_gives_the_reference_values_in_pieces(monkeypatch, piece, threads,
                                                                   regular_file):
    """The pandas path, not its cell-by-cell fall-back (which hides a fault of the fast path
    behind the same answer): a regular file in many pieces, parsed on one or three threads,
    gives the reference's values, in order."""
    import gd_analyze.trajectory.trajectory as trajectory

    raw, expected = regular_file
    monkeypatch.setattr(trajectory, "PARSE_PIECE", piece)
    monkeypatch.setattr(trajectory, "PARSE_THREADS", threads)
    parsed = trajectory.streamed_values(io.BytesIO(raw), "f.csv",
                                        lambda fields: [c.strip() for c in fields])
    assert parsed is not None
    values, names, sha256 = parsed
    np.testing.assert_array_equal(values, expected)
    assert sha256 == hashlib.sha256(raw).hexdigest()
    assert names == ["t", "q1", "q2", "qd1", "qd2", "qdd1", "qdd2"]
