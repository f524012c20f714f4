"""``evaluate``'s gate fails closed: at a held pose without gravity the reference
torque is zero, and a model that knows gravity errs by its whole gravity torque. The error is
measured against the model's s_i, never 0/0 dropped as NaN; oracle: Pinocchio's
computeGeneralizedGravity of the model's robot."""

import json

import numpy as np
import pinocchio as pin
import pytest

from gd_analyze.cli import main
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.store.model_file import load_model

POSE = (0.3, -0.4)


@pytest.fixture(scope="module")
def held(tmp_path_factory):
    folder = tmp_path_factory.mktemp("held")
    plan = folder / "plan.csv"
    assert main(["plan", "two-link", "-o", str(plan)]) == 0
    assert main(["two-link", str(plan), "-o", str(folder / "out"), "--no-report", "-q"]) == 0
    csv = folder / "held.csv"
    rows = [f"{k},{POSE[0]},{POSE[1]},0,0,0,0" for k in range(4)]
    csv.write_text("t,q1,q2,qd1,qd2,qdd1,qdd2\n" + "\n".join(rows) + "\n")
    return folder / "out" / "simplified_model.json", csv


@pytest.mark.parametrize("gate", [[], ["--max-error", "0.01"], ["--max-error", "1e300"]])
def test_a_held_pose_without_gravity_fails_the_gate(held, gate, capsys):
    model_path, csv = held
    code = main(["evaluate", str(model_path), str(csv), "--gravity", "0,0,0", "--json", *gate])
    out, err = capsys.readouterr()
    said = json.loads(out)
    model = load_model(model_path)
    pmodel = pinocchio_model(model.robot)
    gravity = np.abs(pin.computeGeneralizedGravity(pmodel, pmodel.createData(),
                                                   np.array(POSE)))
    assert np.all(gravity > 1.0)
    np.testing.assert_allclose(said["peak_abs_error"], gravity, rtol=1e-9)
    assert said["peak_tau"] == [0.0, 0.0] and said["relative_to"] == ["s_i", "s_i"]
    scale = np.asarray(model.guarantee.scale)
    np.testing.assert_allclose(said["relative_peak_error"], gravity / scale, rtol=1e-9)
    assert said["max_relative_peak_error"] == pytest.approx(max(gravity / scale))
    if gate == ["--max-error", "1e300"]:
        assert code == 0                                  # a gate given that wide passes
    else:
        assert code == 3 and said["exceeded"] and "joint" in err
