"""The main job's output folder (gd_analyze.jobs.run): the emitted sources' C prefix is
the one the run used, stored, and named by the report."""

import re

import numpy as np
import pytest
from conftest import SHIPPED

import gd_analyze as gd
from gd_analyze.jobs.run import run_analysis
from gd_analyze.report.main import main_outline
from gd_analyze.report.main_context import report_context
from gd_analyze.store.schema import open_results
from gd_analyze.trajectory.trajectory import trajectory_from_arrays

_FUNCTIONS = ("tau", "inertia", "velocity_terms", "gravity", "regressor")


def _run(folder, prefix, outputs=None, report=None):
    robot = gd.load_robot("two-link")
    t = np.linspace(0.0, 2.0, 21)
    q = np.column_stack([np.sin(t), 0.5 * np.cos(t)])
    options = gd.AnalysisOptions(formulations=False,
                                 simplify=gd.SimplifyOptions(guarantee="trajectory"))
    written = run_analysis(robot, trajectory_from_arrays(t, q, n_joints=2), options, folder,
                           report=report, prefix=prefix)
    if outputs is not None:
        outputs.update(q=q, model=written.analysis.model)
    return open_results(folder / "results.h5")


def _files_paragraph(ds):
    outline = main_outline(report_context(ds), ())
    texts = [b.content for s in outline.sections for b in s.blocks
             if b.kind == "paragraph" and b.content.startswith("Emitted source files:")]
    assert len(texts) == 1
    return texts[0]


@pytest.mark.parametrize("prefix, expected", [(None, "two_link_"), ("arm_a_", "arm_a_")])
def test_the_report_names_the_prefix_the_header_uses(tmp_path, prefix, expected):
    ds = _run(tmp_path, prefix)
    header = (tmp_path / "simplified_model.h").read_text()
    declared = set(re.findall(r"void (\w+)\(", header))
    assert declared == {expected + f + batch for f in _FUNCTIONS for batch in ("", "_batch")}
    assert ds.attrs["c_prefix"] == expected
    paragraph = _files_paragraph(ds)
    for f in _FUNCTIONS:
        assert expected + f in paragraph
    assert "PREFIX" not in paragraph


def test_the_stored_inertia_check_is_that_of_the_deployed_model(tmp_path):
    """Results.h5 holds the proof for the deployed D_s (over the trajectory's
    bounding box of q for a trajectory model), and numpy's eigenvalues of D_s at the
    trajectory's positions are never below the proved bound."""
    got = {}
    ds = _run(tmp_path, None, got)
    check = got["model"].inertia_check
    key = "simplified_inertia_check_"
    assert ds.attrs[key + "where"] == check["where"] == "trajectory"
    assert ds.attrs[key + "proved"] == 1 and check["proved"]
    assert ds.attrs[key + "lower_bound"] == check["lower_bound"] > 0
    assert ds.attrs[key + "statement"] == check["statement"]
    assert ds.attrs[key + "statement"].startswith(
        "proved positive definite over the bounding box of the trajectory positions")
    D = got["model"].functions().numpy()["inertia"](got["q"])
    assert np.linalg.eigvalsh(D)[:, 0].min() >= check["lower_bound"]
    header = (tmp_path / "simplified_model.h").read_text()
    assert check["statement"] in header

def _without_times(ctx):
    """The report's context as text, its clock times left out (the two are made apart)."""
    stamp = re.compile(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d[+\d:Z]*")
    return {k: stamp.sub("", repr(v)) for k, v in ctx.items()}


def test_the_report_is_built_from_the_result_in_memory(tmp_path, monkeypatch):
    """The main job hands its report the typed result in memory, with the
    per-set-point series, not results.h5 to open again; it reads as the file does."""
    import gd_analyze.store.schema as schema
    from gd_analyze.store.names import Var
    from gd_analyze.store.results_view import Results

    got = []

    def report(results, folder, progress):
        got.append(results)
        return []

    opened = []
    real_open = schema.open_results
    monkeypatch.setattr(schema, "open_results", lambda *a, **k: opened.append(a) or
                        real_open(*a, **k))
    ds = _run(tmp_path, None, report=report)
    assert not opened                      # results.h5 was not read while the job ran
    assert len(got) == 1 and isinstance(got[0], Results) and got[0].source == "<memory>"
    memory = got[0].dataset
    for name in (Var.T, Var.Q, Var.D_TRAN, Var.D_ROT, Var.H_TRAN, Var.TAU, Var.TAU_SIMPLIFIED):
        np.testing.assert_array_equal(memory[name].values, ds[name].values)
        assert memory[name].dims == ds[name].dims
    assert got[0].ranking.text() == Results.from_dataset(ds).ranking.text()
    assert got[0].torque_error.text() == Results.from_dataset(ds).torque_error.text()
    # one report time for both contexts: each states the analysis time apart from the report
    # time only when the two differ, so a second ticking over between them is no difference
    import gd_analyze.report.main_context as main_context
    fixed = main_context.utc_now()
    monkeypatch.setattr(main_context, "utc_now", lambda: fixed)
    in_memory, from_file = (_without_times(report_context(got[0])),
                            _without_times(report_context(ds)))
    assert in_memory.keys() == from_file.keys()
    for key in from_file:
        assert in_memory[key] == from_file[key], key


@pytest.mark.parametrize("streamed", [False, True])
def test_a_streamed_job_s_report_runs_without_the_kept_certifications(tmp_path, monkeypatch,
                                                                      streamed):
    """The certifications a job keeps in its process (for a later model of the same arm)
    are released before the report of a trajectory streamed in chunks: a 15-joint arm's hold
    about 530 MB. A job held in memory keeps them (the other case: the test can fail)."""
    import gc

    from gd_analyze.certify.certify import PairBounds
    from gd_analyze.jobs import analyze as job

    if streamed:
        monkeypatch.setattr(job, "stream_chunk", lambda n: 16)
    alive = []

    def report(results, folder, progress):
        gc.collect()
        alive.append(sum(isinstance(o, PairBounds) for o in gc.get_objects()))
        return []
    robot = gd.load_robot("puma560")
    traj = gd.read_trajectory(SHIPPED, 6)
    run_analysis(robot, traj, gd.AnalysisOptions(formulations=False), tmp_path / "out",
                 report=report)
    assert (alive == [0]) if streamed else (alive[0] > 0)


def test_no_room_is_refused_before_the_payload_sweep(tmp_path, monkeypatch):
    """Too little free space for results.h5 is refused before the payload sweep is computed
    (it ran first, then the run was refused): nothing is computed, nothing is written."""
    import shutil
    from collections import namedtuple

    import gd_analyze.jobs.run as run
    from gd_analyze.errors import InputError

    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(shutil, "disk_usage", lambda path: usage(1 << 30, 1 << 30, 1 << 20))

    def computed(*args, **kwargs):
        raise AssertionError("the payload sweep ran before the free-space check")

    monkeypatch.setattr(run, "payload_sweep", computed)
    robot = gd.load_robot("two-link")
    t = np.linspace(0.0, 2.0, 21)
    trajectory = trajectory_from_arrays(t, np.column_stack([np.sin(t), np.cos(t)]), n_joints=2)
    with pytest.raises(InputError, match="not enough free space for results.h5"):
        run_analysis(robot, trajectory, gd.AnalysisOptions(), tmp_path / "out",
                     payload_masses=[0.0, 1.0])
    assert not (tmp_path / "out").exists()


def test_the_api_analyses_without_a_model_when_simplify_is_none():
    """AnalysisOptions(simplify=None), "no model (the ranking's choices alone)" as its
    docstring says, raised TypeError ("asdict() should be called on dataclass instances")
    while writing the provenance. Oracle: the terms are Pinocchio's (crba), and no model's
    guarantee or cost is recorded."""
    from gd_analyze.dynamics.pinocchio import reference_terms

    robot = gd.load_robot("two-link")
    t = np.linspace(0.0, 1.0, 6)
    q = np.outer(t, [1.0, -0.5])
    ds = gd.analyze(robot, (t, q), gd.AnalysisOptions(simplify=None, formulations=False))
    ref = reference_terms(robot, ds.q.values, ds.qd.values)
    np.testing.assert_allclose(ds.D.values, ref.D, rtol=0, atol=1e-12)
    assert int(ds.attrs["verification_passed"]) == 1
    assert "guarantee" not in ds.attrs and "cost_total" not in ds.data_vars
