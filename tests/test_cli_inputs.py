"""Inputs refused with one line each by the trajectory CSV's number rules: a URDF
whose lower limit is above its upper one, a plan the main job could not read back, a gear ratio
of 0, an effort limit of NaN, ``1_0`` and full-width digits in an option; a value starting with
a minus sign is the option's value; a number just beyond a limit is printed with the digits
that show it; identify's recordings naming the joints in two styles, or joined on clocks that
differ."""

import json
from pathlib import Path

import numpy as np
import pytest

from gd_analyze import load_robot
from gd_analyze.cli import main
from gd_analyze.model.mounting import rpy_matrix

ROOT = Path(__file__).resolve().parents[1]
DATA_DIR = ROOT / "src" / "gd_analyze" / "data"
TWO_LINK = DATA_DIR / "two-link.toml"


def _refused(capsys, args, match):
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("gd-analyze: error: ") and match in lines[0]
    return out


@pytest.fixture(scope="module")
def plan(tmp_path_factory):
    path = tmp_path_factory.mktemp("plan") / "two.csv"
    assert main(["plan", "two-link", "-o", str(path)]) == 0
    return path


@pytest.mark.parametrize("value, said", [("1_0,0,0", "underscore"),
                                         ("\uff11,0,0", "digits other than 0-9"),
                                         ("nan,0,0", "not a finite number"),
                                         ("1e999,0,0", "not a finite number")])
def test_an_option_takes_the_csv_number_rules(plan, capsys, value, said):
    _refused(capsys, ["compare", "two-link", plan, "--gravity", value], said)


@pytest.mark.parametrize("args, said", [(["--setpoints", "1_0"], "underscore"),
                                        (["--setpoints", "\uff11\uff10"], "digits other")])
def test_a_count_takes_the_csv_number_rules(tmp_path, capsys, args, said):
    _refused(capsys, ["plan", "two-link", "-o", tmp_path / "x.csv", *args], said)
    assert not (tmp_path / "x.csv").exists()


def test_a_value_with_a_minus_sign_is_the_options(plan, capsys):
    """--gravity -9.81,0,0 is gravity along -x: the torque of a turned arm (Pinocchio's
    identity: a gravity of R^T g in the base frame)."""
    code = main(["compare", "two-link", str(plan), "--gravity", "-9.81,0,0", "--json"])
    out, err = capsys.readouterr()
    assert code == 0, err
    said = json.loads(out)
    assert said["mounting_gravity_world"] == [-9.81, 0.0, 0.0]
    assert said["mounting_gravity_base"] == (rpy_matrix(0, 0, 0).T @ [-9.81, 0, 0]).tolist()
    code = main(["compare", "two-link", str(plan), "--base-rpy", "-90,0,0", "--json"])
    out, err = capsys.readouterr()
    g = np.asarray(load_robot("two-link").gravity)
    assert code == 0 and np.allclose(json.loads(out)["mounting_gravity_base"],
                                     rpy_matrix(-90, 0, 0, degrees=True).T @ g, atol=1e-15)


def test_held_out_below_zero_is_refused_before_a_cluster_starts(capsys):
    _refused(capsys, ["sweep", "two-link", "--random", "2", "--held-out", "-1",
                      "--scheduler", "tcp://192.0.2.1:9"], "--held-out must be in [0, 1000000]")


def test_held_out_beyond_the_random_limit_is_refused_before_it_is_planned(capsys):
    """--held-out K plans K random trajectories as --random K does, so it takes --random's
    bound, 10^6: 10^6 + 1 is one line naming it, before any trajectory is planned (it planned
    them all, for minutes, then tried the scheduler)."""
    _refused(capsys, ["sweep", "two-link", "--random", "2", "--held-out", str(10**6 + 1),
                      "--scheduler", "tcp://192.0.2.1:9"], "--held-out must be in [0, 1000000]")


def test_a_urdf_with_lower_above_upper_is_refused(tmp_path, plan, capsys):
    text = (DATA_DIR / "ur5.urdf").read_text()
    limit = 'lower="-6.28318530718" upper="6.28318530718"'
    assert limit in text
    bad = tmp_path / "bad.urdf"
    bad.write_text(text.replace(limit, 'lower="1" upper="-1"', 1))
    _refused(capsys, ["plan", bad, "-o", tmp_path / "x.csv"], "lower 1 is above upper -1")
    _refused(capsys, [bad, ROOT / "data" / "ur5_trajectory.csv", "-o",
                      tmp_path / "out"], "lower 1 is above upper -1")
    assert not (tmp_path / "x.csv").exists() and not (tmp_path / "out").exists()


def _robot_file(tmp_path, old, new):
    text = TWO_LINK.read_text()
    assert old in text
    path = tmp_path / "robot.toml"
    path.write_text(text.replace(old, new))
    return path


def test_a_plan_the_main_job_cannot_read_is_not_written(tmp_path, capsys):
    robot = _robot_file(tmp_path, "qdd_max_deg = ", "qdd_max_deg = 1e-300 # ")
    _refused(capsys, ["plan", robot, "-o", tmp_path / "x.csv"], "beyond the supported")
    assert not (tmp_path / "x.csv").exists()
    _refused(capsys, ["plan", "two-link", "-o", tmp_path / "x.csv", "--qdd-max", "1e-300"],
             "--qdd-max")


def test_an_effort_limit_of_nan_is_refused(tmp_path, plan, capsys):
    robot = _robot_file(tmp_path, "qdd_max_deg = ", "tau_max = nan\nqdd_max_deg = ")
    _refused(capsys, ["compare", robot, plan], "tau_max: expected a finite number, got nan")


def test_a_gear_ratio_of_zero_is_refused(tmp_path, plan, capsys):
    robot = _robot_file(tmp_path, "qdd_max_deg = ",
                        "rotor_inertia = 1e-4\ngear_ratio = 0\nqdd_max_deg = ")
    _refused(capsys, ["compare", robot, plan], "gear_ratio: a gear ratio of 0")


def test_a_number_just_beyond_a_limit_shows_its_digits(tmp_path, capsys):
    csv = tmp_path / "fast.csv"
    csv.write_text("t,q1,q2,qd1,qd2,qdd1,qdd2\n0,0,0,0,0,1.0000001e8,0\n1,0,0,0,0,0,0\n")
    _refused(capsys, ["compare", "two-link", csv],
             "1.0000001e+08 is beyond the supported magnitude 1e+08")


def test_an_excitation_beyond_the_set_point_limit_is_refused_before_it_is_planned(tmp_path,
                                                                                 capsys):
    """One set point per 10 ms over --duration 1e9 s are 10^11 set points, beyond the 10^8 a
    trajectory may hold: one line naming --duration, exit 2 (not an array of 745 GiB, exit 4),
    nothing written."""
    _refused(capsys, ["plan", "two-link", "--excitation", "-o", tmp_path / "x.csv",
                      "--duration", "1e9"], "--duration: 100,000,000,001 set points")
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("args, said", [
    (["--goal", "1e308,0"], "--goal: joint 1 at 1e+308 "),
    (["--goal", "0,1e6", "--duration", "1e9"], "--goal: joint 2 at 1e+06 "),
    (["--start", "-1e6,0", "--duration", "1e9"], "--start: joint 1 at -1e+06 ")])
def test_a_plan_from_or_to_a_position_no_trajectory_may_hold_is_refused(tmp_path, capsys, args,
                                                                         said):
    """With --ignore-limits, a start or goal beyond 1e4 rad (a position the CSV reader
    refuses; 1e6 deg is 1.7e4 rad) is one line naming that option and the joint: not an
    overflow warning beside the error, nor the advice to choose a longer --duration, which no
    duration could follow; nothing is written."""
    _refused(capsys, ["plan", "two-link", "-o", tmp_path / "x.csv", "--ignore-limits", *args],
             said)
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("command", [[], ["sweep"]])
def test_negligible_of_one_is_refused_as_the_option(plan, tmp_path, capsys, command):
    """--negligible E calls an element negligible below E times its scale: the ranking takes E
    in [0, 1) (at E = 1 an element at its own scale would be negligible), so 1 is one line
    naming the option, exit 2, and no output folder; it passed the parser and ended in exit 4
    (an internal error) when the ranking refused it."""
    _refused(capsys, [*command, "two-link", plan, "-o", tmp_path / "o", "--no-report",
                      "--negligible", "1"], "--negligible must be in [0.0, 1.0), got 1.0")
    assert not (tmp_path / "o").exists()


def test_a_torque_floor_whose_budget_overflows_is_refused(plan, tmp_path, capsys):
    """The budget of a joint is EPS times its scale, at least TAU: --tolerance 1000 with
    --torque-floor 1e308 is 1e311, beyond a float (numpy's overflow warnings, one line each,
    then a run on an infinite budget). TAU is bounded at 1e30 N m, far above the largest torque
    an accepted input can make (about 1e20 N m): one line, exit 2, no output folder."""
    _refused(capsys, ["two-link", plan, "-o", tmp_path / "o", "--no-report", "--tolerance",
                      "1000", "--torque-floor", "1e308"], "--torque-floor must be in [0, 1e+30]")
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("command", [[], ["sweep"]])
def test_quiet_and_verbose_together_are_refused(plan, tmp_path, capsys, command):
    """-q prints nothing but errors (and warnings), -v lists every file written: asked for
    both, the run said nothing and -v was dropped unsaid. They are one or the other: one line
    naming both, exit 2, no output folder."""
    _refused(capsys, [*command, "two-link", plan, "-o", tmp_path / "o", "--no-report", "-q",
                      "-v"], "argument -v/--verbose: not allowed with argument -q/--quiet")
    assert not (tmp_path / "o").exists()


def test_workers_with_a_scheduler_are_refused(capsys):
    """--workers N sizes the LocalCluster started when no --scheduler is given; a running
    cluster has its own workers, so --workers beside --scheduler was dropped unsaid (the sweep
    ran on that cluster's workers). They are one or the other: one line naming both, exit 2,
    before any connection."""
    _refused(capsys, ["sweep", "two-link", "--random", "2", "--workers", "4", "--scheduler",
                      "tcp://192.0.2.1:9"], "argument --scheduler: not allowed with argument "
                                            "--workers")


@pytest.mark.parametrize("case, match", [
    ("mixed", "a.csv: row 1, column q1: column 'q1' numbers a joint, column '- joint1_position' of"),
    ("clock", "b.csv: row 3, column t: the clock is not "),
])
def test_identify_refuses_a_recording_it_cannot_join_in_one_line(tmp_path, capsys, case, match):
    """Joint names are the URDF's (the two-link built-in's ``joint1``, ``joint2``)."""
    rows = range(12)
    a, b = tmp_path / "a.csv", tmp_path / "b.csv"
    a.write_text("t,- joint1_position,- joint2_position,joint1_effort,joint2_effort"
                 + (",q1" if case == "mixed" else "") + "\n"
                 + "".join(f"{k / 100},{k},{k},{k},{k}" + (",0" if case == "mixed" else "")
                           + "\n" for k in rows))
    b.write_text("t,- joint1_velocity,- joint2_velocity\n"
                 + "".join(f"{(k + (k == 1)) / 100},0,0\n" for k in rows))
    _refused(capsys, ["identify", "two-link", f"{a}+{b}", "-o", tmp_path / "out"], match)
    assert not (tmp_path / "out").exists()
