"""cli/__init__.py: no control character of an input reaches the terminal, even
with -q: an ESC in a file name, or in a robot file's key, is written as ``\\x1b``."""

from pathlib import Path

from gd_analyze.cli import escape_control, main

ESC = "\x1b"
TWO_LINK = Path(__file__).resolve().parents[2] / "src" / "gd_analyze" / "data" / "two-link.toml"


def test_control_characters_are_escaped_and_text_kept():
    assert escape_control(f"a{ESC}[2Jb\x07\x9b\u00e9\n\t") == "a\\x1b[2Jb\\x07\\x9b\u00e9\n\t"


def test_an_esc_in_a_file_name_is_escaped(tmp_path, capsys):
    code = main(["compare", "two-link", str(tmp_path / f"no{ESC}[2J.csv")])
    out, err = capsys.readouterr()
    assert code == 2 and ESC not in out + err and "no\\x1b[2J.csv" in err


def test_an_esc_in_a_robot_file_is_escaped_with_q(tmp_path, capsys):
    robot = tmp_path / "robot.toml"
    robot.write_text('"evil\\u001b[31m" = 1\n' + TWO_LINK.read_text())
    plan = tmp_path / "plan.csv"
    assert main(["plan", str(robot), "-o", str(plan)]) == 0
    capsys.readouterr()
    code = main([str(robot), str(plan), "-o", str(tmp_path / "out"), "-q", "--no-report"])
    out, err = capsys.readouterr()
    assert code == 0 and ESC not in out + err and "evil\\x1b[31m" in err


def test_a_file_name_that_is_not_utf8_is_bad_input(tmp_path, capsys):
    """A byte that is not UTF-8 in a file name (Python keeps it as a lone surrogate, which no
    UTF-8 provenance can hold): one line naming the argument, exit 2, nothing written."""
    plan = tmp_path / "plan.csv"
    assert main(["plan", "two-link", "-o", str(plan)]) == 0
    odd = tmp_path / "tl\udcff.csv"
    odd.write_bytes(plan.read_bytes())
    capsys.readouterr()
    for argv in (["two-link", str(odd), "-o", str(tmp_path / "out"), "-q", "--no-report"],
                 ["identify", "two-link", str(odd), "-o", str(tmp_path / "id"), "--no-report"]):
        code = main(argv)
        err = capsys.readouterr().err
        lines = err.strip().splitlines()
        assert code == 2, err
        assert len(lines) == 1 and lines[0].startswith("gd-analyze: error: ") and "UTF-8" in err
        assert "tl\\xff.csv" in err
    assert not (tmp_path / "out").exists() and not (tmp_path / "id").exists()


def test_a_closed_stdout_or_stderr_is_no_internal_error(tmp_path, monkeypatch):
    """Run with standard output or error closed (``>&-``, ``2>&-``: Python then sets
    sys.stdout or sys.stderr to None, as the oracle below does): compare exited 4, "internal
    error: AttributeError: 'NoneType' object has no attribute 'write'", and a missing file
    exited 1, the status of a failed verification. What would be printed goes nowhere, as
    print() does with no stream; the status is the run's."""
    plan = tmp_path / "plan.csv"
    assert main(["plan", str(TWO_LINK), "-o", str(plan), "--setpoints", "5"]) == 0
    monkeypatch.setattr("sys.stdout", None)
    assert main(["compare", str(TWO_LINK), str(plan)]) == 0
    monkeypatch.setattr("sys.stderr", None)
    assert main(["compare", str(TWO_LINK), str(tmp_path / "missing.csv")]) == 2
