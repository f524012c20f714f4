"""Golden outputs: the shipped robots' outputs are what tests/golden/ froze.

Each case of :data:`golden.freeze.CASES` (the main job on every built-in robot with a shipped
trajectory, the PUMA 560's sweep and its control command) runs once a session, shared by the
xdist workers (``conftest.golden_run``); its CLI text, HDF5 file, model JSON and emitted
sources are compared with the golden files (tests/golden/freeze.py says how, and with which
tolerance). An intended change is regenerated with ``python tests/golden/regenerate.py`` and
reviewed as a diff (tests/golden/README.md).

The comparison's own tests, below the cases, edit one value, name or line of a real golden
file and check that it is reported.
"""

import copy
import json

import pytest
from conftest import golden_run
from golden.freeze import (
    CASES,
    GOLDEN,
    RTOL,
    _source_difference,
    compare_files,
    compare_frozen,
    frozen_files,
)


@pytest.fixture(scope="module", params=list(CASES))
def case_files(request):
    """(case name, its frozen files from this checkout's run)."""
    name = request.param
    roots, printed = golden_run(name)
    return name, frozen_files(roots[0] / name, roots, printed)


def _select(files, kind):
    return {n: t for n, t in files.items() if kind(n)}


def _check(name, files):
    problems = compare_files(name, files)
    assert not problems, "\n".join(problems[:20]) + (
        f"\n... {len(problems)} differences in all" if len(problems) > 20 else "")


@pytest.mark.slow
def test_cli_text(case_files):
    name, files = case_files
    _check(name, _select(files, lambda n: n == "cli.txt"))


@pytest.mark.slow
def test_datasets(case_files):
    name, files = case_files
    selected = _select(files, lambda n: n.endswith(".h5.frozen.json"))
    assert selected or name not in ("puma560", "puma560-sweep", "puma560-control")
    _check(name, selected)


@pytest.mark.slow
def test_model_json(case_files):
    name, files = case_files
    _check(name, _select(files, lambda n: n.endswith(".json.frozen.json")))


@pytest.mark.slow
def test_emitted_code(case_files):
    name, files = case_files
    _check(name, _select(files, lambda n: n.endswith(".golden")))


@pytest.mark.slow
def test_the_run_writes_every_golden_file_and_no_other(case_files):
    name, files = case_files
    assert sorted(files) == sorted(p.name for p in (GOLDEN / name).iterdir())


def test_every_case_is_frozen_and_nothing_else():
    assert sorted(p.name for p in GOLDEN.iterdir() if p.is_dir()) == sorted(CASES)
    for name in CASES:
        stored = {p.name for p in (GOLDEN / name).iterdir()}
        assert "cli.txt" in stored, name
        assert any(n.endswith(".h5.frozen.json") for n in stored), name


# --- the comparison can fail --------------------------------------------------------------


def _golden(case, name):
    return json.loads((GOLDEN / case / name).read_text(encoding="utf-8"))


def test_a_changed_value_a_renamed_variable_or_attribute_fails():
    golden = _golden("puma560", "results.h5.frozen.json")
    assert compare_frozen(golden, copy.deepcopy(golden)) == []

    changed = copy.deepcopy(golden)
    values = changed["leaves"]["var/D"]["values"]
    values[7] = values[7] * (1 + 1e-4)                  # far above RTOL x scale
    assert any(p.startswith("var/D:") for p in compare_frozen(golden, changed))

    renamed = copy.deepcopy(golden)
    renamed["leaves"]["var/D_total"] = renamed["leaves"].pop("var/D")
    problems = compare_frozen(golden, renamed)
    assert "var/D: missing" in problems and any("var/D_total: new" in p for p in problems)

    attribute = copy.deepcopy(golden)
    attribute["leaves"]["@rule"]["values"] = ["chapter"]
    assert any(p.startswith("@rule:") for p in compare_frozen(golden, attribute))

    dims = copy.deepcopy(golden)
    dims["leaves"]["var/D"]["dims"] = ["t", "joint_k", "joint"]
    assert any(p.startswith("var/D: dims") for p in compare_frozen(golden, dims))


def test_within_tolerance_passes_and_nan_never_passes_for_a_number():
    golden = _golden("ur5", "results.h5.frozen.json")
    leaf = golden["leaves"]["var/tau"]
    scale = max(abs(float(v)) for v in leaf["values"])
    near = copy.deepcopy(golden)
    near["leaves"]["var/tau"]["values"][3] = leaf["values"][3] + 0.1 * RTOL * scale
    assert compare_frozen(golden, near) == []
    for bad in ("nan", "inf"):
        broken = copy.deepcopy(golden)
        broken["leaves"]["var/tau"]["values"][3] = bad
        assert any(p.startswith("var/tau:") for p in compare_frozen(golden, broken)), bad
    # the DH columns of a URDF arm are NaN (not applicable): a number there fails too
    assert golden["leaves"]["var/dh_a"]["values"][0] == "nan"
    filled = copy.deepcopy(golden)
    filled["leaves"]["var/dh_a"]["values"][0] = 0.0
    assert any(p.startswith("var/dh_a:") for p in compare_frozen(golden, filled))


def test_round_off_is_compared_against_its_stated_scale():
    """An error against an exact model is round-off: compared against the torque scale, not
    against its own size, and a real error fails."""
    golden = _golden("ur5", "results.h5.frozen.json")
    # errors of round-off size, as an exact model's (no shipped arm's main job model is exact)
    peak = [1e-14 * (1 + i) for i in range(len(golden["leaves"]["var/tau_error_peak"]["values"]))]
    golden["leaves"]["var/tau_error_peak"]["values"] = peak
    noise = copy.deepcopy(golden)
    noise["leaves"]["var/tau_error_peak"]["values"] = [3 * v for v in peak]
    assert compare_frozen(golden, noise) == []
    real = copy.deepcopy(golden)
    real["leaves"]["var/tau_error_peak"]["values"][0] = 1e-3
    assert any(p.startswith("var/tau_error_peak:") for p in compare_frozen(golden, real))


def test_a_changed_line_of_code_or_text_fails():
    name = "simplified_model.c.golden"
    text = (GOLDEN / "ur5" / name).read_text(encoding="utf-8")
    assert compare_files("ur5", {name: text}) == []
    edited = text.replace("*", "+", 1) if "*" in text else text + "x"
    problems = compare_files("ur5", {name: edited})
    assert len(problems) == 1 and "text differs" in problems[0]
    cli = (GOLDEN / "ur5" / "cli.txt").read_text(encoding="utf-8")
    assert compare_files("ur5", {"cli.txt": cli.replace("D11", "D1l")})


def test_emitted_constants_compare_within_round_off_and_nothing_else_does():
    """A base parameter's last bits (a QR decomposition on another CPU) pass; a constant
    changed beyond the tolerance, an integer or a digit of a name fails."""
    name = "simplified_model.c.golden"
    text = (GOLDEN / "ur5" / name).read_text(encoding="utf-8")
    line = next(x for x in text.split("\n") if x.strip().startswith("0.41784981244275"))
    value = float(line.strip().rstrip(","))

    def with_value(v):
        return text.replace(line, line.replace(line.strip().rstrip(","), repr(v)), 1)

    assert compare_files("ur5", {name: with_value(value * (1 + 4e-15))}) == []
    assert compare_files("ur5", {name: with_value(value * (1 + 1e-5))})
    assert compare_files("ur5", {name: with_value(float("nan"))})
    assert "double q_b[6][8];" in text
    assert compare_files("ur5", {name: text.replace("q_b[6][8]", "q_b[6][9]", 1)})
    assert "qdd[0]" in text
    assert compare_files("ur5", {name: text.replace("qdd[0]", "qdd[1]", 1)})
    # a round-off coefficient whose sign differs between CPUs (seen on the Stanford arm before
    # its base parameters became decimals), in a line added to its emitted C
    tiny = "-1.3877787807814457e-16*t74 + t106"
    c = (GOLDEN / "stanford" / name).read_text(encoding="utf-8")
    c += f"\n    const double t999 = {tiny};"
    assert _source_difference(c, c.replace(tiny, "1.6653345369377348e-16*t74 + t106"), RTOL) == ""
    assert _source_difference(c, c.replace(tiny, "t106 + 1.6653345369377348e-16*t74"), RTOL)
    assert _source_difference(c, c.replace(tiny, "-1.3877787807814457e-3*t74 + t106"), RTOL)
    header = "simplified_model.h.golden"
    h = (GOLDEN / "ur5" / header).read_text(encoding="utf-8")
    assert "ZZ1" in h and compare_files("ur5", {header: h.replace("ZZ1", "ZZ2", 1)})


def test_a_searched_maximum_and_where_it_lies_compare_within_their_tolerances():
    """scale_state is where a local maximisation stopped: it may move by 1e-4 of its scale,
    not more; a maximum found by that search by 1e-6, not more; other values by RTOL."""
    golden = _golden("ur5", "simplified_model.json.frozen.json")
    leaf = "json/guarantee/scale_state"
    values = golden["leaves"][leaf]["values"]
    scale = max(abs(float(v)) for v in values)
    for step, ok in ((1e-5, True), (1e-3, False)):
        moved = copy.deepcopy(golden)
        moved["leaves"][leaf]["values"][1] = float(values[1]) + step * scale
        assert (compare_frozen(golden, moved) == []) == ok, step
    results = _golden("ur5", "results.h5.frozen.json")
    for name, step, ok in (("var/base_parameter_relative_peak", 5e-7, True),
                           ("var/base_parameter_relative_peak", 1e-5, False),
                           ("var/tau", 5e-7, False)):
        vals = results["leaves"][name]["values"]
        k = max(range(len(vals)), key=lambda i: abs(float(vals[i])))
        moved = copy.deepcopy(results)
        scale = 1.0 if "relative" in name else abs(float(vals[k]))
        moved["leaves"][name]["values"][k] = float(vals[k]) + step * scale
        assert (compare_frozen(results, moved) == []) == ok, (name, step)
