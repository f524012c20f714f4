"""A hand-edited simplified_model.json. A huge harmonic is refused by the
schema (it gave a RecursionError), a huge coefficient gives exit 2 with one line (it gave exit 4),
and the cost shown is counted from the terms, never the file's own claim."""

import json

import pytest

from gd_analyze.cli import main
from gd_analyze.store.model_file import load_model


@pytest.fixture(scope="module")
def made(tmp_path_factory):
    """A two-link model made by the main job, its trajectory, and the file's JSON."""
    tmp = tmp_path_factory.mktemp("model")
    traj = tmp / "t.csv"
    assert main(["plan", "two-link", "-o", str(traj), "--start=-60,-30", "--goal=60,30",
                 "--setpoints", "9"]) == 0
    assert main(["two-link", str(traj), "-o", str(tmp / "a"), "--no-report", "-q",
                 "--form", "explicit"]) == 0
    path = tmp / "a" / "simplified_model.json"
    return path, traj, json.loads(path.read_text())


def _edited(tmp_path, doc, edit):
    doc = json.loads(json.dumps(doc))
    edit(doc)
    path = tmp_path / "m.json"
    path.write_text(json.dumps(doc))
    return path


def _refused(args, capsys, match):
    code = main([str(a) for a in args])
    _, err = capsys.readouterr()
    lines = [ln for ln in err.splitlines() if ": warning: " not in ln]
    assert code == 2, err
    assert len(lines) == 1 and lines[0].startswith("gd-analyze: error: ") and match in lines[0]
    assert "Traceback" not in err


@pytest.mark.parametrize("harmonic", [1000, 5000, -1000])
def test_a_huge_harmonic_is_refused_by_the_schema(made, tmp_path, capsys, harmonic):
    path, traj, doc = made

    def edit(d):
        d["explicit_terms"]["K"][-1][-1] = harmonic
    model = _edited(tmp_path, doc, edit)
    _refused(["evaluate", model, traj, "--json"], capsys, "explicit_terms.K[")
    _refused(["control", model, traj, "-o", tmp_path / "c", "--no-report"], capsys,
             "explicit_terms.K[")


def test_a_coefficient_beyond_a_float_gives_exit_2(made, tmp_path, capsys):
    path, traj, doc = made

    def edit(d):
        d["explicit_terms"]["coef"] = [1e308] * len(d["explicit_terms"]["coef"])
        del d["cost"]           # else refused as another program's count
    model = _edited(tmp_path, doc, edit)
    _refused(["evaluate", model, traj, "--json"], capsys, "not finite")
    _refused(["evaluate", model, traj], capsys, "not finite")
    _refused(["control", model, traj, "-o", tmp_path / "c", "--no-report"], capsys,
             "not finite")
    assert not (tmp_path / "c").exists()


def test_the_cost_is_counted_not_read(made, tmp_path, capsys):
    """A stored cost is never shown: one that is not the program's count is refused (the file
    was edited); an edited full_cost is not read."""
    path, traj, doc = made
    counted = load_model(path).program().cost()

    def edit(d):
        d["cost"] = {"multiplications": 1, "additions": 2, "sin": 0, "cos": 0}
    _refused(["control", _edited(tmp_path, doc, edit), traj, "-o", tmp_path / "c",
              "--no-report"], capsys, "not the cost the file states")

    def edit_full(d):
        d["full_cost"] = {"multiplications": 3, "additions": 4, "sin": 0, "cos": 0}
    model = _edited(tmp_path, doc, edit_full)
    assert load_model(model).to_dict()["cost"] == counted
    assert load_model(model).header()["operations"].startswith(
        f"{counted['multiplications']} multiplications, {counted['additions']} additions")
    code = main(["control", str(model), str(traj), "-o", str(tmp_path / "c"), "--no-report",
                 "--json"])
    out, err = capsys.readouterr()
    assert code == 0, err
    cost = json.loads(out)["cost"]
    names = cost["evaluators"]
    simp, full = names.index("simplified model (explicit form)"), names.index("full explicit model")
    assert (cost["multiplications"][simp], cost["additions"][simp]) == \
        (counted["multiplications"], counted["additions"])
    # the full model's count is the one the main job made, not the claim (3, 4)
    assert (cost["multiplications"][full], cost["additions"][full]) == \
        (doc["full_cost"]["multiplications"], doc["full_cost"]["additions"])
