"""Untrusted inputs at the command line: each case gives the right answer or exit 2 with one
line, no traceback and no file left; exit 4 for an internal error; a fuzz test of the TOML robot
loader."""

import json
import math
import os
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, given, note, settings
from hypothesis import strategies as st

from gd_analyze import load_robot
from gd_analyze.cli import main
from gd_analyze.errors import InputError

TWO_LINK_TOML = (Path(__file__).resolve().parents[1] / "src" / "gd_analyze" / "data"
                 / "two-link.toml").read_text()


@pytest.fixture
def cwd(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


def _run(args, capsys):
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, out, err


def _refused(args, capsys, cwd, match, keep=()):
    """Exit 2, one line on stderr containing `match`, no traceback, nothing new in cwd."""
    before = set(os.listdir(cwd)) | set(keep)
    code, out, err = _run(args, capsys)
    lines = [ln for ln in err.splitlines() if ": warning: " not in ln and ": note: " not in ln]
    assert code == 2, err
    assert len(lines) == 1 and lines[0].startswith("gd-analyze: error: "), err
    assert match in lines[0], err
    assert "Traceback" not in err and lines[0].count("gd-analyze") == 1
    assert set(os.listdir(cwd)) <= before, sorted(set(os.listdir(cwd)) - before)
    return lines[0]


def _toml(cwd, name="arm.toml"):
    path = cwd / name
    path.write_text(TWO_LINK_TOML)
    return path


def _plan(cwd, capsys, robot="two-link", name="p.csv", extra=()):
    code, _, err = _run(["plan", robot, "-o", cwd / name, "--start=-60,-30", "--goal=60,30",
                         *extra], capsys)
    assert code == 0, err
    return cwd / name


# --- case 1 -----------------------------------------------------------------------------------

def test_case1_shifted_columns_are_refused(cwd, capsys):
    big = _plan(cwd, capsys, name="big.csv", extra=["--setpoints", "5000"])
    lines = big.read_text().splitlines()
    (cwd / "x.csv").write_text("\n".join([lines[0]] + [ln + ",7.5" for ln in lines[1:]]))
    _refused(["two-link", "x.csv"], capsys, cwd, "x.csv: row 2: ragged row")


# --- case 2 -----------------------------------------------------------------------------------

def test_case2_huge_payload_mass_velocity(cwd, capsys):
    traj = _plan(cwd, capsys)
    _refused(["two-link", traj, "--payload", "1e200"], capsys, cwd, "--payload")
    heavy = _toml(cwd, "heavy.toml")
    heavy.write_text(heavy.read_text().replace("mass = 1.0", "mass = 1e308", 1))
    _refused([heavy, traj], capsys, cwd, "key link[1].mass: 1e+308 is beyond")
    fast = cwd / "fast.csv"
    fast.write_text("t,q1,q2,qd1,qd2,qdd1,qdd2\n0,0,0,1e160,0,0,0\n1,0,0,0,0,0,0\n")
    _refused(["two-link", fast], capsys, cwd, "row 2, column qd1")


# --- case 3: lock -----------------------------------------------------------------------------

def test_case3_second_run_into_a_locked_folder(cwd, capsys):
    from gd_analyze.store.staging import staged_output

    traj = _plan(cwd, capsys)
    with staged_output(cwd / "out"):
        _refused(["two-link", traj, "-o", "out", "--no-report"], capsys, cwd,
                 "another run is writing here", keep=os.listdir(cwd))


# --- case 4: plan -----------------------------------------------------------------------------

@pytest.mark.parametrize("extra, match", [
    (["--duration", "inf"], "--duration"), (["--duration", "1e-300"], "--duration"),
    (["--duration", "nan"], "--duration"), (["--duration", "0.1"], "joint 1 would exceed its "
                                                                   "velocity limit 180 deg/s"),
    (["--goal=60,200"], "--goal: joint 2 at 200 deg is outside its position limits"),
    (["--setpoints", "1"], "--setpoints"),
    (["--goal=-60,-30"], "--goal: start and goal coincide: give a positive duration"),
])
def test_case4_plan_refuses(cwd, capsys, extra, match):
    args = ["plan", "two-link", "-o", "p.csv", "--start=-60,-30", "--goal=60,30", *extra]
    _refused(args, capsys, cwd, match)


def test_case4_ignore_limits(cwd, capsys):
    code, _, err = _run(["plan", "two-link", "-o", "p.csv", "--start=-60,-30", "--goal=60,30",
                         "--duration", "0.1", "--ignore-limits"], capsys)
    assert code == 0, err
    assert np.isfinite(np.loadtxt(cwd / "p.csv", delimiter=",", skiprows=1)).all()


def test_case8_plan_output_is_a_folder(cwd, capsys):
    (cwd / "d").mkdir()
    _refused(["plan", "two-link", "-o", "d", "--start=-60,-30", "--goal=60,30"], capsys, cwd,
             "is a folder")


# --- case 6: names ----------------------------------------------------------------------------

def test_case6_robot_name_cannot_escape_reports(cwd, capsys):
    arm = _toml(cwd)
    arm.write_text(arm.read_text().replace('name = "two-link"', 'name = "../../x"'))
    traj = _plan(cwd, capsys)
    code, _, err = _run([arm, traj, "--no-report", "-q"], capsys)
    assert code == 0, err
    made = [p for p in (cwd / "reports").iterdir()]
    assert [p.name for p in made] == ["x-p"]
    assert not (cwd.parent / "x-p").exists() and not Path("/x-p").exists()


def test_case6_control_name_from_the_model(cwd, capsys):
    from gd_analyze.simplify.simplified import parameters_sha256

    traj = _plan(cwd, capsys)
    code, _, err = _run(["two-link", traj, "-o", "a", "--no-report", "-q"], capsys)
    assert code == 0, err
    doc = json.loads((cwd / "a" / "simplified_model.json").read_text())
    doc["robot"]["name"] = doc["robot"]["parameters"]["name"] = "/tmp/../../evil"
    doc["robot"]["parameters_sha256"] = parameters_sha256(doc["robot"]["parameters"])
    (cwd / "m.json").write_text(json.dumps(doc))
    code, _, err = _run(["control", "m.json", traj, "--no-report", "-q"], capsys)
    assert code == 0, err
    assert [p.name for p in (cwd / "reports").iterdir()] == ["tmp_evil-p-control"]


# --- case 7 (CLI side) ------------------------------------------------------------------------

def test_case7_edited_model_is_refused_by_control(cwd, capsys):
    traj = _plan(cwd, capsys)
    _run(["two-link", traj, "-o", "a", "--no-report", "-q"], capsys)
    doc = json.loads((cwd / "a" / "simplified_model.json").read_text())
    doc["robot"]["parameters"]["link"][0]["mass"] = 2.0
    (cwd / "m.json").write_text(json.dumps(doc))
    _refused(["control", "m.json", traj, "-o", "c"], capsys, cwd, "do not match")


def test_case7_unequal_bound_lists_are_refused_by_evaluate(cwd, capsys):
    """bound_by_part lists of unequal lengths (a corrupted file) are bad input, not a bug:
    exit 2 with one line naming the key (they made a ragged array: exit 4)."""
    traj = _plan(cwd, capsys)
    code, _, err = _run(["two-link", traj, "-o", "a", "--no-report", "-q", "--form",
                         "recursive"], capsys)
    assert code == 0, err
    doc = json.loads((cwd / "a" / "simplified_model.json").read_text())
    parts = doc["recursive"]["bound_by_part"]
    first = next(iter(parts))
    parts[first] = parts[first] + [0.0]             # one list longer than the others
    (cwd / "m.json").write_text(json.dumps(doc))
    line = _refused(["evaluate", "m.json", traj], capsys, cwd, "recursive.bound_by_part")
    assert "m.json" in line


# --- case 8 -----------------------------------------------------------------------------------

def test_case8_toml_crashes(cwd, capsys):
    traj = _plan(cwd, capsys)
    big = _toml(cwd, "big.toml")
    big.write_text(big.read_text().replace("mass = 1.0", "mass = " + "9" * 400, 1))
    _refused([big, traj], capsys, cwd, "key link[1].mass: number too large for a float")
    deep = cwd / "deep.toml"
    deep.write_text("x = " + "[" * 5000 + "]" * 5000 + "\n")
    _refused([deep, traj], capsys, cwd, "deep.toml")
    nul = _toml(cwd, "nul.toml")
    nul.write_text(nul.read_text().replace('name = "two-link"', 'name = "a\\u0000b"'))
    _refused([nul, traj], capsys, cwd, "key name: expected at most 200 printable characters")


@pytest.mark.parametrize("target, match", [("/proc/no_such_dir/out", "cannot write"),
                                           ("afile/sub", "is a file, not a folder")])
def test_case8_unusable_output_folder(cwd, capsys, target, match):
    traj = _plan(cwd, capsys)
    (cwd / "afile").write_text("x")
    _refused(["two-link", traj, "-o", target, "--no-report"], capsys, cwd, match)


def test_case8_full_disk_before_hdf5(cwd, capsys, monkeypatch):
    import shutil
    from collections import namedtuple

    traj = _plan(cwd, capsys)
    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(shutil, "disk_usage", lambda p: usage(10**9, 10**9, 1000))
    _refused(["two-link", traj, "-o", "out", "--no-report"], capsys, cwd,
             "not enough free space for results.h5")


@pytest.mark.parametrize("args, match", [
    (["--payload-sweep", "0:1:1e-30"], "--payload-sweep"),
    (["--payload-sweep", "0:1e300:1e299"], "--payload-sweep: load masses in [0, 1e+06] kg, got 0 to"),
    # a negative first mass was refused naming --payload, an option not given
    (["--payload-sweep=-5:1:0.5"], "--payload-sweep: load masses in [0, 1e+06] kg, got -5 to 1"),
])
def test_case8_payload_sweep(cwd, capsys, args, match):
    traj = _plan(cwd, capsys)
    _refused(["two-link", traj, "-o", "o", *args], capsys, cwd, match)


@pytest.mark.parametrize("args, match", [
    (["--seed", "-1"], "--seed must be in [0, 2^63)"),
    (["--seed", "1" * 30], "--seed must be in [0, 2^63)"),
    (["--scheduler", "not a url"], "--scheduler"),
    # no port, or a scheme dask has no comm for: refused as an address, not tried
    (["--scheduler", "tcp://localhost"], "--scheduler: not a dask scheduler address"),
    (["--scheduler", "http://127.0.0.1:8786"], "--scheduler: not a dask scheduler address"),
])
def test_case8_sweep_arguments(cwd, capsys, args, match):
    _refused(["sweep", "two-link", "--random", "2", "-o", "o", *args], capsys, cwd, match)


@pytest.mark.parametrize("args, match", [
    (["--wn", "1e4", "--zeta", "100"], "too stiff"), (["--wn", "1e4"], "(pd_gravity) too stiff"),
    (["--wn", "1e6"], "--wn must be in [0.01, 10000.0]"),
    (["--zeta", "1e9"], "--zeta must be in [0.01, 100.0]"),
    (["--offset", "1e308"], "--offset"),
])
def test_case8_control_bounds(cwd, capsys, args, match):
    traj = _plan(cwd, capsys)
    _run(["two-link", traj, "-o", "a", "--no-report", "-q"], capsys)
    _refused(["control", "a/simplified_model.json", traj, "-o", "c", *args], capsys, cwd,
             match)


# --- case 9: messages -------------------------------------------------------------------------

def test_case9_messages(cwd, capsys):
    traj = _plan(cwd, capsys)
    line = _refused(["compre", "two-link", traj], capsys, cwd, "did you mean 'compare'")
    assert "unknown command 'compre'" in line
    # the URDF built-ins are robots, not mistyped commands ('panda' is close to 'plan')
    from gd_analyze.cli import _check_command
    from gd_analyze.model.robots import builtin_robots

    assert {"panda", "ur5"} <= set(builtin_robots())
    for name in builtin_robots():
        _check_command([name])          # no error
    with pytest.raises(InputError, match="did you mean 'plan'"):
        _check_command(["plann"])
    line = _refused(["plan", "two-link"], capsys, cwd, "plan: the following arguments")
    assert line.startswith("gd-analyze: error: plan:")
    _refused(["two-link", cwd], capsys, cwd, "is a folder, not a CSV file")
    _refused(["two-link", os.devnull], capsys, cwd, "not a regular file")
    bad = _toml(cwd, "bad.toml")
    bad.write_text(bad.read_text().replace("mass = 1.0", 'mass = "one"', 1))
    _refused([bad, traj], capsys, cwd, "bad.toml: key link[1].mass: expected a number")
    (cwd / "bom.csv").write_bytes(b"\xef\xbb\xbf" + traj.read_bytes())
    code, _, err = _run(["two-link", "bom.csv", "-o", "b", "--no-report", "-q"], capsys)
    assert code == 0 and "gd-analyze: note: " in err and "byte-order mark" in err


def test_case9_model_json_internals_are_not_shown(cwd, capsys):
    (cwd / "m.json").write_text('{"schema_version": 1, "robot": [1, 2]}')
    traj = _plan(cwd, capsys)
    line = _refused(["evaluate", "m.json", traj], capsys, cwd, "key robot: expected an object")
    assert "list indices" not in line


# --- case 10: accepted with a warning, or refused ---------------------------------------------

def test_case10_warnings_and_refusals(cwd, capsys):
    traj = _plan(cwd, capsys)
    arm = _toml(cwd)
    arm.write_text("gravty = [0.0, 0.0, 0.0]\n" + arm.read_text().replace(
        "alpha_deg = 0.0", "alpha_deg = 1.5708", 1))
    code, _, err = _run([arm, traj, "-o", "w", "--no-report", "-q"], capsys)
    assert code == 0, err
    assert "unknown key 'gravty' ignored" in err
    assert "key link[1].alpha_deg: 1.5708 looks like radians" in err
    rows = traj.read_text().splitlines()
    rows[3] = "1_0" + rows[3][rows[3].index(","):]
    (cwd / "u.csv").write_text("\n".join(rows))
    _refused(["two-link", "u.csv"], capsys, cwd, "row 4, column t: not a number: '1_0'")
    rows = traj.read_text().splitlines()
    rows[3] = rows[3].replace("0", "\uff10")
    (cwd / "w.csv").write_text("\n".join(rows), encoding="utf-8")
    _refused(["two-link", "w.csv"], capsys, cwd, "digits other than 0-9")


# --- exit 4 -----------------------------------------------------------------------------------

def test_internal_error_is_exit_4(cwd, capsys, monkeypatch):
    import gd_analyze.cli as cli

    def boom(args):
        return {}["no such key"]

    monkeypatch.setattr(cli.commands, "cmd_plan", boom)
    code, _, err = _run(["plan", "two-link", "-o", "p.csv"], capsys)
    assert code == 4 and err.count("\n") == 1 and "Traceback" not in err
    assert "internal error: KeyError" in err and "--debug" in err
    code, _, err = _run(["plan", "two-link", "-o", "p.csv", "--debug"], capsys)
    assert code == 4 and "Traceback" in err


# --- fuzz: the TOML robot loader --------------------------------------------------------------

def _toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v) if not isinstance(v, float) or math.isfinite(v) else \
            ("nan" if v != v else ("inf" if v > 0 else "-inf"))
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise TypeError(v)


def _to_toml(spec):
    tables = isinstance(spec.get("link"), list) and spec["link"] and \
        all(isinstance(lk, dict) for lk in spec["link"])
    lines = [f"{k} = {_toml_value(v)}" for k, v in spec.items() if k != "link" or not tables]
    for link in spec["link"] if tables else []:
        lines.append("[[link]]")
        lines += [f"{k} = {_toml_value(v)}" for k, v in link.items()]
    return "\n".join(lines) + "\n"


_SCALARS = st.one_of(st.integers(-10**400, 10**400), st.floats(), st.booleans(),
                     st.text(max_size=4), st.just([1.0, 2.0]), st.just([]))


@settings(max_examples=60, deadline=None, suppress_health_check=list(HealthCheck),
          phases=[Phase.explicit, Phase.reuse, Phase.generate])
@given(data=st.data(), where=st.sampled_from(["top", "link"]), action=st.sampled_from(
    ["replace", "delete", "add"]), value=_SCALARS)
def test_fuzz_toml_loader(tmp_path_factory, data, where, action, value):
    tmp = tmp_path_factory.mktemp("toml")
    spec = load_robot("two-link").to_dict()
    table = spec if where == "top" else spec["link"][data.draw(st.integers(0, 1))]
    key = data.draw(st.sampled_from(sorted(table)))
    if action == "replace":
        table[key] = value
    elif action == "delete":
        del table[key]
    else:
        table[data.draw(st.from_regex(r"[a-z_]{1,8}", fullmatch=True))] = value
    text = _to_toml(spec)
    note(text)
    path = tmp / "arm.toml"
    path.write_text(text)
    before = set(os.listdir(tmp))
    try:
        robot = load_robot(path)
    except InputError as exc:
        assert "\n" not in str(exc) and str(exc).startswith(str(path))
    else:
        assert robot.name == spec["name"]
        np.testing.assert_array_equal(robot.mass, [lk["mass"] for lk in spec["link"]])
        np.testing.assert_array_equal(robot.a, [lk["a"] for lk in spec["link"]])
        np.testing.assert_allclose(np.degrees(robot.alpha), [lk["alpha_deg"] for lk in
                                                             spec["link"]], rtol=1e-15)
    assert set(os.listdir(tmp)) == before
