"""How the guarantee's scale s_i was found is said as the main job found it.

s_i is the largest |tau_i| found over the joint-limit region by a search (sampled positions,
the best polished by local maximisation on arms of at most ``REFINE_JOINTS`` joints), never the
region's proved largest. The summary's s_i line, ``simplified_model.json``
(``guarantee.scale_positions``, ``guarantee.scale_polished``) and ``results.h5``
(``simplified_guarantee_scale_source``) say which, and call it a lower bound of the region's
largest. Oracle for "lower bound": Pinocchio's rnea of the arm at the stored scale state, which
lies in the region (s_i is reached there, so s_i is at most the region's largest), and a
multi-start maximisation of Pinocchio's |tau_i| over the region (scipy L-BFGS-B, from that
state and random ones), which finds no less, and on the 8-joint arm finds more: s_i is not
the region's largest there. The arms are planar chains but for one
twist; ``--tolerance 0`` deploys the exact recursive model without the region's certification
(its screen), so the runs take seconds.
"""

import json

import h5py
import numpy as np
import pinocchio as pin
import pytest
from html_checks import html_text
from robot_files import chain_toml
from scipy.optimize import minimize

from gd_analyze.certify.region import REFINE_JOINTS
from gd_analyze.cli import main
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.report.sweep import write_sweep_report
from gd_analyze.simplify.guarantee import Guarantee
from gd_analyze.store.model_file import load_model

LOWER = "a lower bound of the region's largest"


def _main_job(n, tmp_path, capsys):
    """The main job on an n-joint chain at --tolerance 0: (summary's s_i line, model JSON's
    guarantee, results.h5's scale source, the model file's robot)."""
    robot_file = tmp_path / "chain.toml"
    robot_file.write_text(chain_toml(n))
    start = ",".join(str(10 * (-1) ** k) for k in range(n))
    goal = ",".join(str(-20 * (-1) ** k) for k in range(n))
    assert main(["plan", str(robot_file), "-o", str(tmp_path / "t.csv"), "--setpoints", "5",
                 f"--start={start}", f"--goal={goal}"]) == 0
    code = main([str(robot_file), str(tmp_path / "t.csv"), "-o", str(tmp_path / "out"),
                 "--no-report", "--tolerance", "0"])
    out, err = capsys.readouterr()
    assert code == 0, err
    line = next(x for x in out.splitlines() if x.startswith("s_i"))
    guarantee = json.loads((tmp_path / "out" / "simplified_model.json").read_text())["guarantee"]
    with h5py.File(tmp_path / "out" / "results.h5", "r") as f:
        stored = f.attrs.get("simplified_guarantee_scale_source")      # None: not stored
    stored = stored.decode() if isinstance(stored, bytes) else stored
    robot = load_model(tmp_path / "out" / "simplified_model.json").robot
    return line, guarantee, stored, robot


def _torque(model, data, x, i):
    n = model.nq
    return pin.rnea(model, data, x[:n], x[n:2 * n], x[2 * n:])[i]


def _oracle_max(robot, guarantee, i, starts=6, seed=0):
    """The largest |tau_i| (Pinocchio's rnea) found over the region by L-BFGS-B from the
    stored scale state of joint i and ``starts`` random states [N m]: at least |tau_i| at a
    state of the region, so at most the region's largest."""
    model = pinocchio_model(robot)
    data = model.createData()
    lo = np.concatenate([guarantee["q_min"], -np.asarray(guarantee["qd_max"]),
                         -np.asarray(guarantee["qdd_max"])])
    hi = np.concatenate([guarantee["q_max"], guarantee["qd_max"], guarantee["qdd_max"]])
    rng = np.random.default_rng(seed)
    best = 0.0
    for x0 in [np.clip(np.asarray(guarantee["scale_state"][i], float), lo, hi),
               *rng.uniform(lo, hi, (starts, lo.size))]:
        sign = np.sign(_torque(model, data, x0, i)) or 1.0
        res = minimize(lambda x: -sign * _torque(model, data, x, i), x0, method="L-BFGS-B",
                       bounds=list(zip(lo, hi)))
        best = max(best, abs(_torque(model, data, np.clip(res.x, lo, hi), i)))
    return best


def _reached_in_the_region(robot, guarantee):
    """Per joint, Pinocchio's |tau_i| at the stored scale state, which lies in the region."""
    model = pinocchio_model(robot)
    data = model.createData()
    n = model.nq
    state = np.asarray(guarantee["scale_state"], float)
    assert np.all(state[:, :n] >= np.asarray(guarantee["q_min"]) - 1e-12)
    assert np.all(state[:, :n] <= np.asarray(guarantee["q_max"]) + 1e-12)
    assert np.all(np.abs(state[:, n:2 * n]) <= np.asarray(guarantee["qd_max"]) * (1 + 1e-12))
    assert np.all(np.abs(state[:, 2 * n:]) <= np.asarray(guarantee["qdd_max"]) * (1 + 1e-12))
    return np.array([abs(_torque(model, data, state[i], i)) for i in range(n)])


@pytest.mark.slow
def test_beyond_refine_joints_s_i_is_said_to_be_the_largest_sampled(tmp_path, capsys):
    """An 8-joint arm: s_i is the largest |tau_i| at the sampled positions, not polished. Before,
    the summary called it "the region's largest |tau_i|"; the oracle finds larger |tau_i| in the
    region, so that was not true, and "a lower bound" is."""
    n = REFINE_JOINTS + 1
    line, guarantee, stored, robot = _main_job(n, tmp_path, capsys)
    assert "the region's largest |tau_i|" not in line
    assert line.startswith("s_i [N m] (the largest |tau_i| at ")
    positions = guarantee["scale_positions"]
    assert guarantee["scale_polished"] is False and positions >= 1000
    said = (f"the largest |tau_i| at {positions:,} sampled positions of the region, not "
            f"polished by local maximisation (done up to {REFINE_JOINTS} joints), {LOWER}")
    assert line.startswith(f"s_i [N m] ({said}): ")
    assert stored == said and said in guarantee["method"]
    scale = np.asarray(guarantee["scale"], float)
    assert _reached_in_the_region(robot, guarantee) == pytest.approx(scale, rel=1e-9)
    found = np.array([_oracle_max(robot, guarantee, i, starts=2) for i in range(n)])
    assert np.all(scale <= found * (1 + 1e-9)), scale / found
    assert np.any(found > scale * (1 + 1e-6)), found / scale    # not the region's largest


@pytest.mark.slow
def test_up_to_refine_joints_s_i_is_said_to_be_polished(tmp_path, capsys):
    """A 7-joint arm: s_i is the largest |tau_i| found at the sampled positions and polished by
    local maximisation: still a search, so said to be a lower bound, not the region's largest."""
    n = REFINE_JOINTS
    line, guarantee, stored, robot = _main_job(n, tmp_path, capsys)
    assert "the region's largest |tau_i|" not in line
    positions = guarantee["scale_positions"]
    assert guarantee["scale_polished"] is True
    said = (f"the largest |tau_i| found at {positions:,} sampled positions of the region and "
            f"polished by local maximisation, {LOWER}")
    assert line.startswith(f"s_i [N m] ({said}): ") and stored == said
    scale = np.asarray(guarantee["scale"], float)
    assert _reached_in_the_region(robot, guarantee) == pytest.approx(scale, rel=1e-9)
    found = np.array([_oracle_max(robot, guarantee, i, starts=2) for i in range(n)])
    assert np.all(scale <= found * (1 + 1e-9)), scale / found


def test_a_model_file_without_the_search_says_only_what_it_knows():
    """A file written before the search was stored: no count and no polish are claimed."""
    g = Guarantee("region", 0.01, np.zeros(1), np.ones(1), q_min=-np.ones(1),
                  q_max=np.ones(1), qd_max=np.ones(1), qdd_max=np.ones(1),
                  scale_state=np.zeros((1, 3)), scale_positions=1014, scale_polished=True)
    spec = g.to_dict()
    assert (spec["scale_positions"], spec["scale_polished"]) == (1014, True)
    assert Guarantee.from_dict(spec, 1, 0.01).scale_source() == g.scale_source()
    del spec["scale_positions"], spec["scale_polished"]
    assert Guarantee.from_dict(spec, 1, 0.01).scale_source() == (
        f"the largest |tau_i| found over the region, {LOWER}")


def test_the_sweep_says_how_s_i_was_found_in_the_main_job_s_words(tmp_path, capsys):
    """``gd-analyze sweep`` over the joint-limit region of a 3-joint arm: sweep.h5 stores how
    its merged model's s_i was found (``merged_guarantee_scale_source``), the main job's
    sentence for the same arm and region (its ``simplified_guarantee_scale_source``), and the
    sweep report says it wherever it defines s_i (the summary's claim and Sec. 5's pruning,
    which drops pairs here). Oracle: the sentence written from the merged model file's
    ``scale_positions`` and ``scale_polished`` in the documented words. Before, sweep.h5 held no
    such attribute and the report said only "the largest |tau_i| found over the region"."""
    robot_file = tmp_path / "chain.toml"
    robot_file.write_text(chain_toml(3))
    out = tmp_path / "sweep"
    assert main(["sweep", str(robot_file), "--random", "2", "--held-out", "0", "-o", str(out),
                 "--no-report", "-q"]) == 0
    guarantee = json.loads((out / "merged_model.json").read_text())["guarantee"]
    assert guarantee["scale_polished"] is True and guarantee["scale_positions"] >= 1000
    found = (f"found at {guarantee['scale_positions']:,} sampled positions of the region and "
             f"polished by local maximisation, {LOWER}")
    with h5py.File(out / "sweep.h5", "r") as f:
        stored = f.attrs.get("merged_guarantee_scale_source")      # None: not stored
        assert f.attrs["merged_pairs_dropped"][0] > 0
    assert stored == f"the largest |tau_i| {found}"
    assert stored == _main_job(3, tmp_path, capsys)[2]
    html = write_sweep_report(out / "sweep.h5", tmp_path / "report", formats=["html"])[0]
    text = html_text(html.read_text())
    assert text.count(f"| {found})") == 2 and "found over the region" not in text, text
