"""Messages that say what is so (each was wrong before; each test fails on
the code before the fix)."""

import contextlib
import io
import json
import re
import shutil
from importlib import resources
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from conftest import built_once, golden_run

from gd_analyze.cli import main
from gd_analyze.model.robots import builtin_robots

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "data"


def _run(capsys, *args):
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, out, err


# --- one list of built-in robots ---------------------------------------------------------------

def test_one_list_of_builtin_robots_in_help_errors_and_readme(capsys):
    names = builtin_robots()
    assert {"puma560", "two-link", "stanford", "panda", "ur5"} <= set(names)
    text = ", ".join(names)
    with pytest.raises(SystemExit):
        main(["--help"])
    out = capsys.readouterr().out
    assert text in " ".join(out.split())
    code, _, err = _run(capsys, "compare", "no-such-robot", DATA / "puma560_trajectory.csv")
    assert code == 2 and text in err
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    listed = re.search(r"`ROBOT` is a built-in name \(([^)]*)\)", readme).group(1)
    assert re.findall(r"`([^`]+)`", listed) == names


def test_unknown_robot_is_not_a_mistyped_command(capsys):
    code, _, err = _run(capsys, "pand", DATA / "panda_trajectory.csv")
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "unknown robot 'pand': did you mean 'panda'?" in err and "command" not in err
    code, _, err = _run(capsys, "plna", "puma560", "-o", "x.csv")       # a command still is
    assert code == 2 and "unknown command 'plna': did you mean 'plan'?" in err
    code, _, err = _run(capsys, "compare", "pumaa560", DATA / "puma560_trajectory.csv")
    assert code == 2 and "did you mean 'puma560'?" in err


def test_help_prints_the_help(capsys):
    code, out, err = _run(capsys, "help")
    assert code == 0 and out.startswith("usage: gd-analyze") and not err
    code, out, err = _run(capsys, "help", "plan")
    assert code == 0 and out.startswith("usage: gd-analyze plan")


# --- plain numbers ------------------------------------------------------------------------------

def test_numbers_in_messages_are_plain_floats(tmp_path, capsys):
    rows = (DATA / "puma560_trajectory.csv").read_text().splitlines()
    cells = rows[3].split(",")
    cells[1] = "20000.0"
    rows[3] = ",".join(cells)
    bad = tmp_path / "far.csv"
    bad.write_text("\n".join(rows) + "\n")
    code, _, err = _run(capsys, "puma560", bad, "-o", tmp_path / "out")
    assert code == 2 and "row 4, column q1: 20000 is beyond" in err
    assert "np." not in err and "float64" not in err


# --- round-off is "≡ 0", not ranked --------------------------------------------------------------

def _point_wrist(tmp_path):
    """The PUMA 560 with link 6 a point mass on joint 6's axis (its inertia tensor zeroed):
    D_66 = I_zz + m |r_perp|^2 = 0 exactly, and so are D_i6 and h_6 (link 6 turns about its
    own centre of mass); computed, they are rounding (1e-34 .. 1e-17)."""
    text = resources.files("gd_analyze").joinpath("data", "puma560.toml").read_text()
    head, tail = text[:text.rindex("[[link]]")], text[text.rindex("[[link]]"):]
    tail = re.sub(r"\ninertia = [^\n]*", "\ninertia = [0.0, 0.0, 0.0]", tail)
    assert "com = [0.0, 0.0, 0.032]" in tail
    path = tmp_path / "point_wrist.toml"
    path.write_text(head.replace('name = "puma560"', 'name = "point-wrist"') + tail)
    return path


def _point_wrist_run():
    """The main job (no report) on :func:`_point_wrist`'s arm and the shipped trajectory, run
    once a session for both tests that read it (conftest's built_once): the folder holding
    the robot file, the job's output folder ``out`` and what it printed (``printed.txt``).
    Shared: read only."""
    def build(folder):
        path = _point_wrist(folder)
        printed = io.StringIO()
        with contextlib.redirect_stdout(printed):
            code = main([str(path), str(DATA / "puma560_trajectory.csv"), "-o",
                         str(folder / "out"), "--no-report"])
        assert code == 0
        (folder / "printed.txt").write_text(printed.getvalue(), encoding="utf-8")
    return built_once("point-wrist", build)


def test_round_off_elements_are_identically_zero_not_ranked():
    folder = _point_wrist_run()
    path = folder / "point_wrist.toml"
    out = (folder / "printed.txt").read_text(encoding="utf-8")
    rows = {line.split()[0]: line for line in out.splitlines()
            if re.match(r"^(D\d\d|h\d) ", line)}
    # the oracle: Pinocchio's D_66 of this arm is zero to rounding too
    from gd_analyze import load_robot
    from gd_analyze.dynamics.pinocchio import pinocchio_model

    model = pinocchio_model(load_robot(str(path)))
    data = model.createData()
    D = pin.crba(model, data, np.linspace(0.1, 0.6, 6))
    assert abs(D[5, 5]) < 1e-15 * abs(D[0, 0])
    for lab in ("D16", "D26", "D36", "D46", "D56", "D66", "h6"):
        assert "\u2261 0" in rows[lab] and "negligible" in rows[lab], rows[lab]
        assert "translational" not in rows[lab]
    assert "\u2261 0" not in rows["D11"] and "\u2261 0" not in rows["D55"]


def _puma_model():
    """The simplified model of golden case puma560's run (gd-analyze puma560 <shipped>
    --no-report, conftest's golden_run): the PUMA 560's main job on its shipped trajectory
    without report, run once a session. Shared: read only."""
    (root, *_), _ = golden_run("puma560")
    return root / "puma560" / "simplified_model.json"


# --- control: singular D, stiffness of every controller --------------------------------------------

def test_control_on_a_singular_D_names_the_joint(tmp_path, capsys):
    model = _point_wrist_run() / "out" / "simplified_model.json"        # shared, read only
    code, _, err = _run(capsys, "control", model,
                        DATA / "puma560_trajectory.csv", "--no-report", "-o", tmp_path / "c")
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "singular" in err and "joint 6 has D_66 = " in err and "Singular matrix" not in err


def test_control_stiffness_check_covers_pd_gravity(tmp_path, capsys):
    """wn = 5000 passes the computed-torque check (5000 x 4.16 s / 3 < 20000 steps) but the
    PD + gravity loop's fastest mode, through D^-1 diag(D), is faster: refused before any run."""
    code, _, err = _run(capsys, "control", _puma_model(),
                        DATA / "puma560_trajectory.csv", "--wn", "5000", "--no-report",
                        "-o", tmp_path / "c")
    assert code == 2 and "pd_gravity" in err and "too stiff" in err and "fastest mode" in err
    assert not (tmp_path / "c").exists()


def test_pd_gravity_rate_is_the_linearised_loop():
    """The rate against the eigenvalues of the closed loop built here from Pinocchio's D."""
    from gd_analyze import load_robot
    from gd_analyze.dynamics.pinocchio import pinocchio_model
    from gd_analyze.jobs.control import closed_loop_rates, control_gains

    robot = load_robot("puma560")
    q = np.array([[0.3, -0.5, 0.8, 0.1, 0.7, -0.2]])
    gains = control_gains(robot, q[0], 50.0, 1.0)
    model = pinocchio_model(robot)
    D = pin.crba(model, model.createData(), q[0])
    D = np.triu(D) + np.triu(D, 1).T
    n = robot.n
    A = np.block([[np.zeros((n, n)), np.eye(n)],
                  [-np.linalg.solve(D, np.diag(gains.Kp_pd)),
                   -np.linalg.solve(D, np.diag(gains.Kv_pd))]])
    rates = closed_loop_rates(robot, gains, D[None])
    assert rates["pd_gravity"] == pytest.approx(np.abs(np.linalg.eigvals(A)).max(), rel=1e-9)
    assert rates["full"] == pytest.approx(50.0, rel=1e-12)
    assert rates["pd_gravity"] > rates["full"]


# --- the sweep's guarantee ------------------------------------------------------------------------

def test_sweep_says_where_the_floor_voids_the_guarantee():
    import xarray as xr

    from gd_analyze.store.sweep_view import beyond_the_floor

    ds = xr.Dataset({"merged_tau_error_peak": (("trajectory", "joint"),
                                               np.array([[0.01, 0.006], [0.02, 0.001]])),
                     "tau_peak": (("trajectory", "joint"),
                                  np.array([[5.0, 0.01], [4.0, 0.02]]))},
                    attrs={"merged_tolerance": 0.01})
    # joint 1: 0.005 of its peak (guaranteed); joint 2: 0.6 of its peak, below a 1 N m floor
    assert beyond_the_floor(ds) == (pytest.approx(0.6), 2, [2])
    ds["merged_tau_error_peak"][:, 1] = 1e-5
    assert beyond_the_floor(ds) is None


@pytest.mark.slow
@pytest.mark.parametrize("guarantee", ["trajectory", "region"])
def test_sweep_summary_never_claims_a_guarantee_that_does_not_hold(tmp_path, capsys, guarantee):
    csvs = [DATA / "puma560_trajectory.csv"]
    # over the region, D_s's proof keeps the 0.01 model nearly exact: 0.05 lets errors grow
    eps = 0.01 if guarantee == "trajectory" else 0.05
    code, out, err = _run(capsys, "sweep", "puma560", *csvs, "--torque-floor", "1",
                          "--held-out", "0", "--no-report", "-o",
                          tmp_path / "sw", "--guarantee", guarantee, "--tolerance", str(eps))
    assert code == 0, err
    line = next(x for x in out.splitlines() if x.startswith("merged model"))
    import xarray as xr

    with xr.open_dataset(tmp_path / "sw" / "sweep.h5") as ds:
        err = ds["merged_tau_error_peak"]
        own = (err / ds["tau_peak"]).max("trajectory").values
    assert own.max() > eps                    # the floor lets a small joint's error grow
    if guarantee == "trajectory":
        assert "relative to peak |tau_i| itself, where it is below 1 N m, not guaranteed" in line
        return
    # over the region the guarantee is relative to s_i there, never to the trajectory's peak
    scale = np.array(json.loads((tmp_path / "sw" / "merged_model.json").read_text())
                     ["guarantee"]["scale"])
    worst = float((err.values / scale).max())
    assert f"{worst:.2e} of s_i over the joint-limit region (guaranteed <= {eps:g})" in line
    assert worst <= eps and "peak |tau_i|" not in line


# --- evaluate checks the trajectory's provenance --------------------------------------------------

def test_evaluate_warns_when_the_trajectory_was_planned_for_another_robot(tmp_path, capsys):
    model = _puma_model()
    prov = json.loads((DATA / "stanford_trajectory.provenance.json").read_text())
    assert prov["robot"] == "stanford"
    code, out, err = _run(capsys, "evaluate", model, DATA / "stanford_trajectory.csv")
    warnings = [x for x in err.splitlines() if "warning" in x]
    assert code == 0 and len(warnings) == 1
    assert "'stanford'" in warnings[0] and "'puma560'" in warnings[0]
    # a trajectory planned for this robot: no warning
    shutil.copy(DATA / "puma560_trajectory.csv", tmp_path / "p.csv")
    code = main(["plan", "puma560", "-o", str(tmp_path / "p.csv")])
    capsys.readouterr()
    code, out, err = _run(capsys, "evaluate", model, tmp_path / "p.csv")
    assert code == 0 and "warning" not in err


# --- no numpy warning for a motion without torque -------------------------------------------------

def test_all_zero_motion_gives_no_numpy_warning(tmp_path, capsys):
    """At rest without gravity every torque is 0 and every relative error 0/0: the report
    says there is none to measure, and numpy's 'All-NaN slice' never reaches the terminal."""
    csv = tmp_path / "rest.csv"
    csv.write_text("t,q1,q2,qd1,qd2,qdd1,qdd2\n" + "".join(f"{k},0,0,0,0,0,0\n"
                                                       for k in range(4)))
    code, out, err = _run(capsys, "two-link", csv, "-o", tmp_path / "out", "--gravity",
                          "0,0,0")
    assert code == 0, err
    assert "All-NaN" not in err and "warning" not in err
    html = (tmp_path / "out" / "report.html").read_text()
    assert "no relative error (no joint has torque on this trajectory)" in html
