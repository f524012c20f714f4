"""docs/robot-file.md documents every key the robot-file parser knows."""

import re
from pathlib import Path

from gd_analyze.model import robot_spec
from gd_analyze.model.drives import DRIVE_KEYS

ROOT = Path(__file__).resolve().parents[1]
DOC = (ROOT / "docs" / "robot-file.md").read_text(encoding="utf-8")


def parser_keys():
    """Every key robot_from_dict accepts: top level, per link (all layouts), drives."""
    keys = set(robot_spec._TOP_KEYS) | set(robot_spec._INERTIAL_KEYS) | set(DRIVE_KEYS) \
        | robot_spec._NAME_KEYS
    for required, optional in robot_spec._KEYS.values():
        keys |= set(required) | set(optional)
    for limit_keys in robot_spec._LIMIT_KEYS.values():
        keys |= set(limit_keys)
    return keys


def documented_keys():
    """The keys in the first column of a table row of the reference."""
    rows = re.findall(r"^\|([^|\n]*\|){0,2}? *`([a-z_]+)` *\|", DOC, re.MULTILINE)
    return {key for _, key in rows}


def test_every_parser_key_is_documented():
    keys = parser_keys()
    assert {"name", "gravity", "link", "d", "tau_max", "armature", "rotation"} <= keys
    missing = sorted(keys - documented_keys())
    assert not missing, f"docs/robot-file.md lacks {missing}"


def test_no_documented_key_is_unknown_to_the_parser():
    extra = sorted(documented_keys() - parser_keys())
    assert not extra, f"docs/robot-file.md documents keys the parser does not know: {extra}"


def test_the_mounting_options_are_documented_and_the_readme_links_here():
    for option in ("--gravity", "--base-rpy"):
        assert f"`{option} " in DOC
    assert "](docs/robot-file.md)" in (ROOT / "README.md").read_text(encoding="utf-8")
