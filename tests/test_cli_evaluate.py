"""``gd-analyze evaluate``'s gate and scope, against the URDF's own
Pinocchio model (``pin.rnea``) as the oracle of the reference torque.

The default gate is the model's promise, peak |tau_s - tau_i| <= EPS s_i, with EPS and s_i
read back from the stored model's guarantee; a joint without torque is measured against s_i."""

import importlib.metadata
import json

import numpy as np
import pinocchio as pin
import pytest

from gd_analyze import load_robot
from gd_analyze.cli import main
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.store.model_file import load_model
from gd_analyze.trajectory.trajectory import read_trajectory

UR10 = importlib.metadata.distribution("example-robot-data").locate_file(
    "cmeel.prefix/share/example-robot-data/robots/ur_description/urdf/ur10_robot.urdf")


def _run(capsys, *args):
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture(scope="module")
def ur10(tmp_path_factory):
    """The main job's model of the UR10 on its default plan, and a second plan."""
    folder = tmp_path_factory.mktemp("ur10")
    own, other = folder / "own.csv", folder / "other.csv"
    assert main(["plan", str(UR10), "-o", str(own)]) == 0
    assert main(["plan", str(UR10), "-o", str(other), "--start", "0,-80,170,0,0,0",
                 "--goal", "60,-80,-130,0,0,0"]) == 0
    assert main([str(UR10), str(own), "-o", str(folder / "out"), "--no-report", "-q",
                 "--guarantee", "trajectory"]) == 0
    return folder / "out" / "simplified_model.json", own, other


@pytest.fixture(scope="module")
def puma_slow(tmp_path_factory):
    """The PUMA 560's trajectory model on a slow plan without gravity (its s_i the slow
    motion's torques: the D_s proof keeps the UR10's model nearly exact, so its dropped terms
    cannot show), and the fastest plan within the limits."""
    folder = tmp_path_factory.mktemp("puma")
    own, other = folder / "own.csv", folder / "other.csv"
    assert main(["plan", "puma560", "-o", str(own), "--duration", "12"]) == 0
    assert main(["plan", "puma560", "-o", str(other)]) == 0
    assert main(["puma560", str(own), "-o", str(folder / "out"), "--no-report", "-q",
                 "--guarantee", "trajectory", "--gravity", "0,0,0"]) == 0
    return folder / "out" / "simplified_model.json", own, other


def _oracle_error(model_path, csv, gravity=None, urdf=True):
    """peak |tau_s - tau| per joint, tau from Pinocchio's rnea on the URDF itself (or, with
    ``urdf=False``, on the Pinocchio model of the built-in PUMA 560 without gravity)."""
    model = load_model(model_path)
    traj = read_trajectory(csv, n_joints=model.robot.n)
    if urdf:
        urdf = pin.buildModelFromUrdf(str(UR10))
    else:
        urdf = pinocchio_model(load_robot("puma560"))
        gravity = (0.0, 0.0, 0.0)
    assert urdf.nq == model.robot.n == 6
    if gravity is not None:
        urdf.gravity.linear = np.asarray(gravity, float)
    data = urdf.createData()
    tau = np.array([pin.rnea(urdf, data, q, qd, qdd)
                    for q, qd, qdd in zip(traj.q, traj.qd, traj.qdd)])
    return np.abs(model.torque(traj.q, traj.qd, traj.qdd) - tau).max(axis=0), tau, model


def test_default_gate_is_the_models_own_promise(puma_slow, capsys):
    model_path, own, other = puma_slow
    g = load_model(model_path).guarantee
    assert g.kind == "trajectory"
    limit = g.tolerance * g.scale
    # on its own trajectory the model keeps its bound: exit 0, and the printout says so
    err, _, _ = _oracle_error(model_path, own, urdf=False)
    assert np.all(err <= limit * (1 + 1e-9) + 1e-12)
    code, out, stderr = _run(capsys, "evaluate", model_path, own)
    assert code == 0, stderr
    assert f"model's guarantee: {g.statement()}" in out
    assert "covers this trajectory: yes" in out
    # on the other plan it does not: exit 3, one line naming the worst joint
    err, _, _ = _oracle_error(model_path, other, urdf=False)
    ratio = err / limit
    assert ratio.max() > 1.5                  # clearly beyond, not a rounding question
    worst = int(np.argmax(ratio))
    code, out, stderr = _run(capsys, "evaluate", model_path, other)
    assert code == 3
    line = stderr.strip()
    assert len(line.splitlines()) == 1
    assert f"joint {worst + 1}'s torque error {err[worst]:.4g} N m" in line
    assert f"{g.tolerance:g} x {g.scale[worst]:.4g} N m = {limit[worst]:.4g} N m" in line
    assert "covers this trajectory: no" in out and "not the trajectory" in out
    # --max-error overrides the model's gate, both ways
    rel = err / np.abs(_oracle_error(model_path, other, urdf=False)[1]).max(axis=0)
    assert _run(capsys, "evaluate", model_path, other, "--max-error", rel.max() * 2)[0] == 0
    assert _run(capsys, "evaluate", model_path, own, "--max-error", 1e-9)[0] == 3


def test_json_states_scope_coverage_and_gate(puma_slow, capsys):
    model_path, own, other = puma_slow
    g = load_model(model_path).guarantee
    for csv, covered, code_expected in ((own, True, 0), (other, False, 3)):
        code, out, _ = _run(capsys, "evaluate", model_path, csv, "--json")
        assert code == code_expected
        report = json.loads(out)
        assert report["guarantee"]["statement"] == g.statement()
        assert report["guarantee"]["kind"] == "trajectory"
        assert report["guarantee"]["covered"] is covered
        assert report["gate"] == "model" and report["exceeded"] is (code_expected == 3)
        np.testing.assert_allclose(report["gate_limit"], g.tolerance * g.scale, rtol=1e-15)
        np.testing.assert_allclose(report["scale"], g.scale, rtol=1e-15)


def _held_pose_csv(path, q_deg, rows=5):
    q = np.radians(q_deg)
    head = ["t"] + [f"{v}{j}" for v in ("q", "qd", "qdd") for j in range(1, 7)]
    lines = [",".join(head)] + [",".join(repr(float(v)) for v in [0.1 * k, *q, *[0.0] * 12])
                                for k in range(rows)]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_zero_reference_torque_is_measured_against_s_i(ur10, capsys, tmp_path):
    """A held pose without gravity: the reference torque is 0 on every joint; the model (its
    own gravity kept) errs by its gravity torque, which is measured against s_i and gated,
    never 0/0 (before: --json exited 4, --max-error 0.01 passed a 75 N m error)."""
    model_path, _, _ = ur10
    held = _held_pose_csv(tmp_path / "held.csv", [0, -60, 80, 0, 45, 0])
    err, tau, model = _oracle_error(model_path, held, gravity=(0.0, 0.0, 0.0))
    assert np.abs(tau).max() < 1e-12                   # the oracle: no torque at all
    s = model.guarantee.scale
    assert err.max() > 10.0
    code, out, stderr = _run(capsys, "evaluate", model_path, held, "--gravity", "0,0,0",
                             "--json")
    assert code == 3 and len(stderr.strip().splitlines()) == 1
    report = json.loads(out)
    assert report["relative_to"] == ["s_i"] * 6
    moved = err > 1e-9
    np.testing.assert_allclose(np.array(report["relative_peak_error"])[moved],
                               (err / s)[moved], rtol=1e-9)
    assert report["guarantee"]["covered"] is False       # another mounting than the model's
    code, _, stderr = _run(capsys, "evaluate", model_path, held, "--gravity", "0,0,0",
                           "--max-error", "0.01")
    worst = int(np.argmax(err / s))
    assert code == 3 and f"joint {worst + 1}'s relative torque error" in stderr
    assert "(of s_i)" in stderr


def test_region_model_covers_planned_motions_and_keeps_its_promise(ur10, tmp_path, capsys):
    """The default (region) model of the UR10: a plan within the limits lies in its region,
    its error there is within EPS s_i against the oracle and evaluate exits 0; a motion
    faster than the velocity limit is named as outside."""
    _, own, other = ur10
    out = tmp_path / "region"
    assert main([str(UR10), str(own), "-o", str(out), "--no-report", "-q"]) == 0
    model_path = out / "simplified_model.json"
    g = load_model(model_path).guarantee
    assert g.kind == "region"
    err, _, _ = _oracle_error(model_path, other)
    assert np.all(err <= g.tolerance * g.scale * (1 + 1e-9) + 1e-12)
    code, out_text, stderr = _run(capsys, "evaluate", model_path, other, "--json")
    report = json.loads(out_text)
    assert code == 0, stderr
    assert report["guarantee"]["covered"] and report["guarantee"]["statement"] == g.statement()
    fast = tmp_path / "fast.csv"
    assert main(["plan", str(UR10), "-o", str(fast), "--duration", "0.5",
                 "--ignore-limits"]) == 0
    traj = read_trajectory(fast, n_joints=6)
    over = np.abs(traj.qd).max(axis=0) > g.qd_max           # the oracle: the limits as given
    assert over.any()
    code, out_text, _ = _run(capsys, "evaluate", model_path, fast, "--json")
    said = json.loads(out_text)["guarantee"]
    assert not said["covered"] and "outside the model's region" in said["reason"]


def test_a_recording_with_measured_torques_is_evaluated_on_its_set_points(ur10, capsys,
                                                                          tmp_path):
    """A recording for identify along the UR10's second plan (t, q, tau and qd, qdd, in the
    recordings' order), its torques measured: Pinocchio's rnea of the URDF plus viscous and
    Coulomb friction and noise. evaluate compares the model with the full model, not with
    measurements: it reads the set points, ignores the torques with a note, and gives the same
    errors as on the trajectory (the oracle's, rnea on the URDF); with positions only, those
    of the trajectory of positions only. It was refused ("expected column 'qd1', got 'tau1'")."""
    model_path, _, other = ur10
    traj = read_trajectory(other, n_joints=6)
    err, tau, _ = _oracle_error(model_path, other)
    rng = np.random.default_rng(3)
    tau = tau + 0.8 * traj.qd + 0.5 * np.sign(traj.qd) + 0.01 * rng.normal(size=tau.shape)
    names = ["t", *(f"{v}{j}" for v in ("q", "tau", "qd", "qdd") for j in range(1, 7))]
    for cols, arrays in ((names, (traj.q, tau, traj.qd, traj.qdd)), (names[:13], (traj.q, tau))):
        recorded, plain = tmp_path / f"rec{len(cols)}.csv", tmp_path / f"traj{len(cols)}.csv"
        values = np.column_stack([traj.t, *arrays])
        np.savetxt(recorded, values, delimiter=",", header=",".join(cols), comments="", fmt="%.17g")
        keep = [k for k, c in enumerate(cols) if not c.startswith("tau")]
        np.savetxt(plain, values[:, keep], delimiter=",", header=",".join(cols[k] for k in keep),
                   comments="", fmt="%.17g")
        said = [_run(capsys, "evaluate", model_path, f, "--json") for f in (recorded, plain)]
        assert said[0][0] == said[1][0]
        a, b = (json.loads(out) for _, out, _ in said)
        for key in ("peak_abs_error", "rms_error", "relative_peak_error", "peak_tau"):
            assert a[key] == b[key], key
        assert a["setpoints"] == traj.n_setpoints
        assert "its torques tau1..tau6 are ignored" in said[0][2], said[0][2]
        if len(cols) == len(names):     # the planned set points: the oracle's errors
            np.testing.assert_allclose(a["peak_abs_error"], err, rtol=1e-9, atol=1e-9)
