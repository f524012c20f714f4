"""``gd-analyze control`` states the model's guarantee, read back from the model file: in
its printout, its JSON and its report, and never "guaranteed" along a motion the guarantee
does not cover."""

import json
import re

import pytest
from conftest import SHIPPED
from html_checks import html_text

from gd_analyze.cli import main
from gd_analyze.store.model_file import load_model


def _run(capsys, *args):
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.slow
def test_control_states_the_models_scope(tmp_path, capsys, shared_main):
    # the main job's trajectory-guarantee run, shared, read only
    model = shared_main("puma560", SHIPPED, "--guarantee", "trajectory") / \
        "simplified_model.json"
    statement = load_model(model).guarantee.statement()
    # its own trajectory: covered
    code, out, err = _run(capsys, "control", model, SHIPPED, "-o", tmp_path / "own",
                          "--no-report")
    assert code == 0, err
    assert f"model's guarantee: {statement}\n" in out
    assert "covers this trajectory: yes" in out
    # a trajectory-kind guarantee holds at its set points, not at the closed loop's states
    # (q, qd and the commanded acceleration differ from them): the verdict does not vouch
    assert "good enough" not in out and "guarantee does not cover this run" in out
    # another motion: not covered, and the report does not say "guaranteed" of it
    other = tmp_path / "other.csv"
    assert _run(capsys, "plan", "puma560", "-o", other, "--start", "0,45,-90,0,30,0",
                "--goal", "90,100,-30,45,-30,90")[0] == 0
    code, out, err = _run(capsys, "control", model, other, "-o", tmp_path / "c", "--json")
    assert code == 0, err
    said = json.loads(out)["guarantee"]
    assert said["statement"] == statement and said["kind"] == "trajectory"
    assert said["covered"] == 0 and "not the trajectory" in said["reason"]
    text = re.sub(r" ([).;])", r"\1",
                  html_text((tmp_path / "c" / "control_report.html").read_text(), nbsp=True))
    assert statement.replace("s_i", "s i") in text     # s_i drawn as s with subscript i
    assert "It does not cover this motion" in text and "is not guaranteed" in text
    assert "is guaranteed" not in text


@pytest.mark.slow
def test_control_prints_the_rtol_floor_when_the_noise_is_not_measured(tmp_path, capsys,
                                                                       monkeypatch,
                                                                       shared_main):
    """When the tighter runs cannot finish, the printout still gives the torque difference
    against the rtol floor, max(rtol, 1e-12) x the full-model controller's peak |tau|, and
    says the noise was not measured (it failed with an internal error before)."""
    import numpy as np

    import gd_analyze.jobs.control as control
    from gd_analyze.store.control_dataset import control_dataset

    def fails(*args, **kwargs):
        raise ValueError("the full controller's run failed: too many steps")

    monkeypatch.setattr(control, "difference_noise", fails)
    # the main job's trajectory-guarantee run, shared, read only (the main job never calls
    # difference_noise)
    model = shared_main("puma560", SHIPPED, "--guarantee", "trajectory") / \
        "simplified_model.json"
    seen = {}
    real = control_dataset

    def keep(result, *args, **kwargs):
        seen["result"] = result
        return real(result, *args, **kwargs)

    monkeypatch.setattr("gd_analyze.store.control_dataset.control_dataset", keep)
    code, out, err = _run(capsys, "control", model, SHIPPED, "-o", tmp_path / "c",
                          "--no-report")
    assert code == 0, err
    line = next(x for x in out.splitlines() if x.startswith("noise floor"))
    assert "not measured: rtol x peak |tau|" in line
    result = seen["result"]
    rtol = max(float(result.provenance["rtol"]), 1e-12)
    expect = rtol * np.max(np.abs(result.runs["full"].tau), axis=0)
    printed = np.array([float(v) for v in line.split()[2:2 + 6]])
    np.testing.assert_allclose(printed, expect, rtol=1e-3)
