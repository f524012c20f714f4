"""plan: acceleration limits where the robot has none, --qdd-max, and the provenance file."""

import dataclasses
import json
import math
import subprocess
import sys

import numpy as np
import pytest

from gd_analyze import load_robot
from gd_analyze.cli import main
from gd_analyze.model.limits import DEFAULT_QDD_PER_QD, acceleration_limits
from gd_analyze.trajectory.planning import (
    provenance_path,
    quintic_duration,
)
from gd_analyze.trajectory.trajectory import read_trajectory


@pytest.fixture(scope="module")
def no_qdd():
    """The PUMA 560 without acceleration limits, as a URDF robot comes."""
    puma = load_robot("puma560")
    qdd = np.array(puma.qdd_max)
    qdd[[1, 4]] = np.nan
    return dataclasses.replace(puma, qdd_max=qdd)


def test_robot_limits_kept():
    puma = load_robot("puma560")
    qdd, source = acceleration_limits(puma)
    assert source == "robot" and np.array_equal(qdd, puma.qdd_max)


def test_default_fraction_of_velocity_limits(no_qdd):
    qdd, source = acceleration_limits(no_qdd)
    assert qdd[1] == DEFAULT_QDD_PER_QD * no_qdd.qd_max[1]
    assert qdd[4] == DEFAULT_QDD_PER_QD * no_qdd.qd_max[4]
    assert qdd[0] == no_qdd.qdd_max[0]
    assert "joints 2, 5" in source and "default" in source


def test_given_limits(no_qdd):
    qdd, source = acceleration_limits(no_qdd, np.full(6, 3.0))
    assert source == "--qdd-max" and (qdd == 3.0).all()
    for bad in (np.full(5, 3.0), np.full(6, -1.0), np.full(6, np.inf)):
        with pytest.raises(ValueError):
            acceleration_limits(no_qdd, bad)


def test_no_velocity_limit_either(no_qdd):
    qd = np.array(no_qdd.qd_max)
    qd[1] = np.inf
    with pytest.raises(ValueError, match="joint 2 has neither"):
        acceleration_limits(dataclasses.replace(no_qdd, qd_max=qd))


def test_plan_qdd_max_and_provenance(tmp_path):
    out = tmp_path / "p.csv"
    args = ["plan", "puma560", "-o", str(out), "--qdd-max", "20"]
    assert main(args) == 0
    traj = read_trajectory(out, 6)                       # the existing reader reads it
    prov = json.loads(provenance_path(out).read_text())
    assert prov["qdd_max_source"] == "--qdd-max"
    assert prov["qdd_max"] == pytest.approx([math.radians(20)] * 6)
    assert prov["output"] == "p.csv" and prov["output_sha256"] == traj.sha256
    assert prov["duration_s"] == pytest.approx(traj.t[-1])
    puma = load_robot("puma560")
    limited = dataclasses.replace(puma, qdd_max=np.full(6, math.radians(20)))
    assert traj.t[-1] == pytest.approx(quintic_duration(limited, traj.q[0], traj.q[-1]))
    peak = np.abs(traj.qdd).max(axis=0)
    assert (peak <= math.radians(20) * (1 + 1e-9)).all()


@pytest.mark.parametrize("value, message", [("1,2", "2 values for 6 joints"),
                                            ("0", "must be at least 1e-09"),
                                            ("x", "comma-separated numbers")])
def test_plan_bad_qdd_max(tmp_path, capsys, value, message):
    out = tmp_path / "p.csv"
    assert main(["plan", "puma560", "-o", str(out), f"--qdd-max={value}"]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert not out.exists() and not provenance_path(out).exists()


def test_quintic_duration_uses_the_default_where_no_limit(no_qdd):
    q0, q1 = np.zeros(6), np.full(6, 1.0)
    filled = dataclasses.replace(no_qdd, qdd_max=acceleration_limits(no_qdd)[0])
    T = quintic_duration(no_qdd, q0, q1)
    assert np.isfinite(T) and T == quintic_duration(filled, q0, q1)
    slow = dataclasses.replace(no_qdd, qd_max=np.full(6, 100.0))   # acceleration-bound
    fast = dataclasses.replace(slow, qdd_max=np.array(slow.qdd_max) * 0 + 1e6)
    assert quintic_duration(slow, q0, q1) > quintic_duration(fast, q0, q1)


def test_plan_without_velocity_limits_writes_null_not_nan(tmp_path):
    """``plan --duration T --ignore-limits`` on a robot without velocity limits wrote
    the CSV, then failed (exit 4) on NaN in its provenance; JSON writes no limit as null."""
    from conftest import ROOT

    text = (ROOT / "data" / "robots" / "two-link.toml").read_text()
    robot = tmp_path / "nolim.toml"
    robot.write_text("\n".join(line for line in text.splitlines()
                               if not line.startswith("qd_max_deg")) + "\n")
    out = tmp_path / "t.csv"
    assert main(["plan", str(robot), "-o", str(out), "--duration", "2", "--ignore-limits"]) == 0
    prov = json.loads(provenance_path(out).read_text())
    assert prov["qd_max"] == [None, None]
    assert "null: no limit" in prov["limits_units"]
    assert read_trajectory(out, 2).t[-1] == pytest.approx(2.0)


#: ``plan --setpoints 100000000`` with a disk that fills after three pieces, in a child
#: process whose address space is limited to 3 GB (the whole table of the two-link arm's 10^8
#: set points is 5.6 GB: sampled at once it is a MemoryError, exit 4).
_FULL_DISK = """
import errno, resource, sys
resource.setrlimit(resource.RLIMIT_AS, (3 * 2**30, 3 * 2**30))
import gd_analyze.trajectory.trajectory as trajectory
real = trajectory.write_trajectory_chunks
def full_disk(pieces, n, path):
    def three(pieces):
        for i, piece in enumerate(pieces):
            if i == 3:
                raise OSError(errno.ENOSPC, "No space left on device")
            yield piece
    real(three(pieces), n, path)
trajectory.write_trajectory_chunks = full_disk
from gd_analyze.cli import main
sys.exit(main(sys.argv[1:]))
"""


@pytest.mark.slow
def test_plan_of_10_to_the_8_set_points_in_bounded_memory(tmp_path):
    """10^8 set points (the documented maximum) are checked and written piece by piece in
    bounded memory; a full disk is exit 2 on one line, leaving no file."""
    out = tmp_path / "big.csv"
    done = subprocess.run([sys.executable, "-c", _FULL_DISK, "plan", "two-link", "-o", str(out),
                           "--setpoints", "100000000"], capture_output=True, text=True,
                          timeout=900)
    assert done.returncode == 2, done.stderr
    assert done.stderr == f"gd-analyze: error: {out}: cannot write: No space left on device\n"
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("to_stdout", [False, True])
def test_a_plan_beyond_the_readers_magnitudes_writes_nothing(tmp_path, capsys, monkeypatch,
                                                             to_stdout):
    """A plan whose accelerations exceed what the CSV reader accepts is exit 2 on one line and
    writes nothing: no file, though the pieces before the first offending one were within the
    limits (pieces of 4 set points; |qdd| <= 1e8 for u < 1/60), and nothing on standard
    output."""
    from gd_analyze.trajectory import planning

    monkeypatch.setattr(planning, "CHUNK_SETPOINTS", 4)
    out = "-" if to_stdout else str(tmp_path / "fast.csv")
    # 0.5 deg in 1e-5 s: peak |qd| 1.6e3 rad/s, peak |qdd| 5.0e8 rad/s^2
    assert main(["plan", "two-link", "-o", out, "--setpoints", "1001", "--duration", "1e-5",
                 "--ignore-limits", "--start=0,0", "--goal=0.5,0.5"]) == 2
    printed, err = capsys.readouterr()
    assert err == ("gd-analyze: error: --duration: the planned qdd exceeds the supported "
                   "magnitude 1e+08: choose a longer --duration\n")
    assert printed == "" and list(tmp_path.iterdir()) == []
