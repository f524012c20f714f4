"""Every output of the main job states the scope of the model built: the CLI
summary, results.h5, the report's summary, Sec. 5 and provenance, and simplified_model.json,
each compared with ``Guarantee.statement()`` of the model read back from its file."""

import json
import re

import numpy as np
import pytest
from conftest import SHIPPED, printed_by
from html_checks import html_text

from gd_analyze.store.datasets import stored_guarantee
from gd_analyze.store.model_file import load_model
from gd_analyze.store.schema import open_results


def test_the_main_jobs_outputs_state_the_models_scope(shared_main):
    out = shared_main("puma560", SHIPPED)   # the default run and what it printed, read only
    printed = printed_by(out).splitlines()
    g = load_model(out / "simplified_model.json").guarantee
    statement = g.statement()
    # the CLI summary: after the model's cost line, the region (one line per limit kind,
    # as the model's region states it), then the guarantee
    k = next(i for i, line in enumerate(printed) if line.startswith("simplified model ("))
    assert printed[k + 1:k + 4] == g.region.lines()
    assert printed[k + 4] == f"guarantee: {statement}"
    # the JSON
    spec = json.loads((out / "simplified_model.json").read_text())
    assert spec["guarantee"]["statement"] == statement
    # the dataset the report reads
    with open_results(out / "results.h5", lazy=True) as ds:
        stored = stored_guarantee(ds)
        assert stored["statement"] == statement and stored["kind"] == g.kind
        assert stored["tolerance"] == g.tolerance
        np.testing.assert_array_equal(stored["scale"], g.scale)
        np.testing.assert_array_equal(stored["bound"], g.bound)
    # the report: summary, Sec. 5 and provenance (s_i drawn as s with subscript i)
    text = re.sub(r" ([).])", r"\1", html_text((out / "report.html").read_text(), nbsp=True))
    said = statement.replace("s_i", "s i")
    assert f"Its guarantee: {said}." in text                      # the summary
    assert f"The model's guarantee: {said}." in text              # Sec. 5
    assert f"guarantee of the model built {g.kind} kind: {said}" in text
    assert "is guaranteed, on this trajectory only" not in text


@pytest.mark.slow
def test_sec5_says_how_a_region_model_was_pruned(shared_main):
    """A region model's Sec. 5 describes the proved bounds over the region and s_i over the
    region (the scale the table prints), never 'the bound holds on this trajectory' or
    s_i = peak |tau_i| of the trajectory; a trajectory model's says the trajectory."""
    texts = {}
    for kind in ("region", "trajectory"):
        # the region model is the PUMA 560's default (its file gives every limit): the
        # session's default run (shared, read only); the stored kind below checks it
        out = shared_main("puma560", SHIPPED, *(["--guarantee", kind] if kind != "region" else []))
        with open_results(out / "results.h5", lazy=True) as ds:
            assert stored_guarantee(ds)["kind"] == kind
        text = html_text((out / "report.html").read_text(), nbsp=True)
        where = "the joint-limit region" if kind == "region" else "this trajectory"
        assert f"gravity parts of their contributions that act on {where}, it drops" in text
        start = text.index("Recursive model: rule, bound, cost")
        texts[kind] = text[start:text.index("Table 5.3", start)]
    region, trajectory = texts["region"], texts["trajectory"]
    assert "contribute over the joint-limit region" in region
    assert "The error at every state of the region is within that bound" in region
    assert "holds on this trajectory" not in region
    assert "= peak |τ" not in region and "= peak |τ" in trajectory
    assert "contribute on this trajectory" in trajectory
    # a guaranteed bound says the round-off it allows, in the one wording
    assert ("the bound below is guaranteed on this trajectory, up to floating-point "
            "round-off (64 eps of the scale)") in trajectory
