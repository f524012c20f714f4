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
