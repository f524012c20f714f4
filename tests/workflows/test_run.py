"""The main job's output folder (gd_analyze.workflows.run): the emitted sources' C prefix is
the one the run used, stored, and named by the report."""

import re

import numpy as np
import pytest

import gd_analyze as gd
from gd_analyze.io.schema import open_results
from gd_analyze.io.trajectory import trajectory_from_arrays
from gd_analyze.reports.main_context import report_context
from gd_analyze.reports.main_outline import main_outline
from gd_analyze.workflows.run import run_analysis

_FUNCTIONS = ("tau", "inertia", "velocity_terms", "gravity", "regressor")


def _run(folder, prefix, outputs=None):
    robot = gd.load_robot("two-link")
    t = np.linspace(0.0, 2.0, 21)
    q = np.column_stack([np.sin(t), 0.5 * np.cos(t)])
    options = gd.AnalysisOptions(formulations=False,
                                 simplify=gd.SimplifyOptions(guarantee="trajectory"))
    written = run_analysis(robot, trajectory_from_arrays(t, q, n_joints=2), options, folder,
                           report=None, prefix=prefix)
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
    """Issue 40 item 1: results.h5 holds the proof for the deployed D_s (over the trajectory's
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