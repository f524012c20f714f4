"""Mounting (--gravity, --base-rpy) against Pinocchio, and limits only
where they are needed (real URDFs and TOML robots without them analyse a given trajectory)."""

import importlib.metadata
import json

import numpy as np
import pinocchio as pin
import pytest
import xarray as xr
from robot_files import toml_without_limits
from urdf_oracle import UrdfOracle, worst_relative

from gd_analyze.cli import main
from gd_analyze.dynamics.dalembert import gd_terms
from gd_analyze.model.robots import load_robot as load_any
from gd_analyze.model.urdf import builtin_urdf_path

TOL = 1e-10


def _run(capsys, *args):
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, out, err


def _states(n, count, seed):
    rng = np.random.default_rng(seed)
    return (rng.uniform(-np.pi, np.pi, (count, n)), rng.uniform(-2, 2, (count, n)),
            rng.uniform(-2, 2, (count, n)))


def _smooth_csv(path, n, setpoints=41):
    """A smooth trajectory (sines), with its derivatives, in the format of data/*.csv."""
    t = np.linspace(0.0, 2.0, setpoints)
    w = 2 * np.pi / 2.0
    amp = 0.2 + 0.1 * np.arange(n)
    q = amp * np.sin(w * t[:, None] + np.arange(n))
    qd = amp * w * np.cos(w * t[:, None] + np.arange(n))
    qdd = -amp * w**2 * np.sin(w * t[:, None] + np.arange(n))
    head = ",".join(["t"] + [f"{k}{j + 1}" for k in ("q", "qd", "qdd") for j in range(n)])
    np.savetxt(path, np.column_stack([t, q, qd, qdd]), delimiter=",", header=head,
               comments="", fmt="%.17g")
    return path


# --- item 2: mounting ------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["puma560", "ur5", "stanford"])
def test_zero_gravity_gives_c_identically_zero(name):
    from gd_analyze.model.mounting import with_mounting

    robot = with_mounting(load_any(name), gravity=(0.0, 0.0, 0.0))
    q, qd, _ = _states(robot.n, 20, seed=3)
    c = gd_terms(robot, q, qd).c
    assert np.isfinite(c).all() and not c.any()          # exactly 0, not round-off
    assert not with_mounting(load_any(name), gravity=(0, 0, 0),
                             base_rpy=(10, 20, 30)).gravity.any()


@pytest.mark.parametrize("rpy", [(0, 90, 0), (180, 0, 0), (30, -45, 120)])
def test_base_rpy_matches_pinocchio_with_rotated_gravity(rpy):
    """ur5 on a wall (0, 90, 0), a ceiling, and any pose: tau and c of the mounted robot against
    Pinocchio's URDF model whose gravity is R^T g (R from pinocchio.rpy.rpyToMatrix)."""
    from gd_analyze.model.mounting import with_mounting

    path = builtin_urdf_path("ur5")
    base = load_any("ur5")
    robot = with_mounting(base, base_rpy=rpy)
    oracle = UrdfOracle(path, list(base.metadata["urdf_joints"]))
    g_world = np.array(oracle.model.gravity.linear)
    R = pin.rpy.rpyToMatrix(*np.radians(rpy))
    oracle.model.gravity.linear = R.T @ g_world
    q, qd, qdd = _states(robot.n, 40, seed=5)
    terms = gd_terms(robot, q, qd)
    tau = np.einsum("kij,kj->ki", terms.D, qdd) + terms.h_tran + terms.h_rot + terms.c
    taur = np.array([oracle.rnea(q[k], qd[k], qdd[k]) for k in range(len(q))])
    cr = np.array([oracle.gravity(q[k]) for k in range(len(q))])
    assert worst_relative(tau, taur, "tau") < TOL
    scale = np.maximum(np.abs(taur).max(axis=0), np.abs(cr).max(axis=0))
    assert worst_relative(terms.c, cr, "tau", scale=scale) < TOL
    if rpy == (0, 90, 0):       # on a wall gravity turns the first (upright) joint's axis
        assert np.abs(cr[:, 0]).max() > 1.0


def test_gravity_and_base_rpy_reach_the_provenance(tmp_path, capsys):
    csv = _smooth_csv(tmp_path / "tl.csv", 2)
    out = tmp_path / "out"
    code, _, err = _run(capsys, "two-link", csv, "-o", out, "--no-report", "-q",
                        "--gravity", "0,0,-9.81", "--base-rpy", "90,0,0")
    assert code == 0, err
    with xr.open_dataset(out / "results.h5") as ds:
        assert list(ds.attrs["mounting_gravity_world"]) == [0.0, 0.0, -9.81]
        assert list(ds.attrs["mounting_base_rpy_deg"]) == [90.0, 0.0, 0.0]
        # Rx(90)^T (0, 0, -9.81) = (0, -9.81, 0): the robot file's own gravity
        assert np.allclose(ds.attrs["mounting_gravity_base"], [0, -9.81, 0], atol=1e-15)
    html_free = json.loads((out / "simplified_model.json").read_text())
    assert html_free["provenance"]["mounting_base_rpy_deg"] == [90.0, 0.0, 0.0]
    code, _, err = _run(capsys, "two-link", csv, "-o", tmp_path / "zero", "--no-report",
                        "-q", "--gravity", "0,0,0")
    assert code == 0, err
    with xr.open_dataset(tmp_path / "zero" / "results.h5") as ds:
        assert not ds["c"].values.any()


@pytest.mark.parametrize("command", ["analyze", "plan", "evaluate", "compare", "control",
                                     "sweep"])
@pytest.mark.parametrize("option, value", [("--gravity", "0,0"), ("--gravity", "0,nan,0"),
                                           ("--base-rpy", "1,2,3,4"), ("--base-rpy", "x,0,0")])
def test_bad_mounting_exits_2_with_one_line(tmp_path, capsys, command, option, value):
    csv = str(_smooth_csv(tmp_path / "tl.csv", 2))
    first = {"analyze": ["two-link", csv], "plan": ["plan", "two-link", "-o", "x.csv"],
             "evaluate": ["evaluate", "m.json", csv], "compare": ["compare", "two-link", csv],
             "control": ["control", "m.json", csv], "sweep": ["sweep", "two-link", csv]}
    code, out, err = _run(capsys, *first[command], option, value)
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and option in err and "Traceback" not in err
    assert "numbers" in err                  # the value is refused, not the option


def test_evaluate_with_another_mounting_measures_the_model_there(tmp_path, capsys):
    csv = _smooth_csv(tmp_path / "tl.csv", 2)
    code, _, err = _run(capsys, "two-link", csv, "-o", tmp_path / "m", "--no-report", "-q")
    assert code == 0, err
    model = tmp_path / "m" / "simplified_model.json"
    code, out, _ = _run(capsys, "evaluate", model, csv, "--json")
    same = json.loads(out)
    code, out, _ = _run(capsys, "evaluate", model, csv, "--json", "--base-rpy", "0,0,90")
    turned = json.loads(out)
    # within the model's budget (--tolerance 0.01) on its own robot, far beyond it turned
    assert same["max_relative_peak_error"] <= 0.01 < 0.1 < turned["max_relative_peak_error"]
    assert turned["mounting_base_rpy_deg"] == [0.0, 0.0, 90.0]


# --- item 4: limits only where they are needed -----------------------------------------------

def _erd_double_pendulums():
    root = importlib.metadata.distribution("example-robot-data").locate_file(
        "cmeel.prefix/share/example-robot-data/robots/double_pendulum_description/urdf")
    files = sorted(root.glob("double_pendulum*.urdf"))
    assert [f.name for f in files] == ["double_pendulum.urdf",
                                       "double_pendulum_continuous.urdf",
                                       "double_pendulum_simple.urdf"]
    return files


@pytest.mark.parametrize("urdf", _erd_double_pendulums(), ids=lambda p: p.name)
def test_double_pendulums_analyse_a_given_trajectory(tmp_path, capsys, urdf):
    """velocity="0", effort="0", lower = upper = 0: "not given", not an error."""
    csv = _smooth_csv(tmp_path / "dp.csv", 2)
    code, _, err = _run(capsys, urdf, csv, "-o", tmp_path / "out", "--no-report", "-q")
    assert code == 0, err
    robot = load_any(str(urdf))
    assert np.isnan(robot.qd_max).all() and np.isnan(robot.tau_max).all()
    assert np.isinf(robot.q_min).all() and np.isinf(robot.q_max).all()
    code, _, err = _run(capsys, "compare", urdf, csv)
    assert code == 0, err
    code, _, err = _run(capsys, "evaluate", tmp_path / "out" / "simplified_model.json", csv)
    assert code == 0, err
    # planning needs the limits: one line naming the joint and the missing limit
    code, _, err = _run(capsys, "plan", urdf, "-o", tmp_path / "p.csv")
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "joint 1 ('joint1') has no velocity limit" in err


def test_toml_robot_without_velocity_limits_analyses_a_given_trajectory(tmp_path, capsys):
    path = toml_without_limits(tmp_path)
    csv = _smooth_csv(tmp_path / "tl.csv", 2)
    code, _, err = _run(capsys, path, csv, "-o", tmp_path / "out", "--no-report", "-q")
    assert code == 0, err
    code, _, err = _run(capsys, "evaluate", tmp_path / "out" / "simplified_model.json", csv)
    assert code == 0, err
    code, _, err = _run(capsys, "plan", path, "-o", tmp_path / "p.csv")
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "joint 1 has no velocity limit" in err and "qd_max_deg" in err


def test_plan_warns_about_placeholder_velocity_limits(tmp_path, capsys):
    """velocity="1000" (finger_edu, solo12): planned, with one warning line."""
    urdf = builtin_urdf_path("ur5").read_text()
    fake = tmp_path / "fast.urdf"
    fake.write_text(urdf.replace('velocity="3.15"', 'velocity="1000"'))
    assert 'velocity="1000"' in fake.read_text()
    code, _, err = _run(capsys, "plan", fake, "-o", tmp_path / "p.csv")
    assert code == 0
    warnings = [line for line in err.splitlines() if "warning" in line]
    assert len(warnings) == 1 and "placeholder" in warnings[0] and "1000 rad/s" in warnings[0]
    code, _, err = _run(capsys, "plan", "ur5", "-o", tmp_path / "q.csv")
    assert code == 0 and "warning" not in err
