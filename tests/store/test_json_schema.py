"""The model file is read strictly and validated as a whole;
a hypothesis fuzz test of the loader: right values or one InputError line, nothing written."""

import copy
import json
import os

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, given, note, settings
from hypothesis import strategies as st

from gd_analyze.errors import InputError
from gd_analyze.ranking.ranking import element_labels
from gd_analyze.simplify.simplified import SimplifiedModel, parameters_sha256
from gd_analyze.store.json_schema import MODEL_SCHEMA, load_json
from gd_analyze.store.model_file import load_model


@pytest.fixture(scope="module")
def model_doc(puma):
    choices = {lab: "both" for lab in element_labels(6)}
    choices["D11"] = "tran"
    model = SimplifiedModel(robot=puma, choices=choices, dominance_threshold=0.9,
                            negligible_threshold=0.01, trajectory_sha256="0" * 64,
                            validation={"peak_tau": [1.0] * 6}, provenance={"x": 1})
    return json.loads(json.dumps(model.to_dict()))


def _write(tmp_path, doc, name="m.json"):
    path = tmp_path / name
    path.write_text(doc if isinstance(doc, str) else json.dumps(doc))
    return path


def test_round_trip(tmp_path, model_doc, puma):
    back = load_model(_write(tmp_path, model_doc))
    assert back.robot.sha256 == puma.sha256 and back.choices["D11"] == "tran"
    np.testing.assert_array_equal(back.robot.inertia, puma.inertia)


def test_case7_edited_parameters_are_refused(tmp_path, model_doc):
    doc = copy.deepcopy(model_doc)
    doc["robot"]["parameters"]["link"][2]["mass"] *= 1.01
    with pytest.raises(InputError, match="robot.parameters_sha256: .*do not match"):
        load_model(_write(tmp_path, doc))


@pytest.mark.parametrize("edit, match", [
    (lambda d: d["choices"].update(D77="tran"), "unknown element 'D77'"),
    (lambda d: d["choices"].pop("h3"), "missing element 'h3'"),
    (lambda d: d.update(schema_version=True), "key schema_version: expected 1 or 2, got True"),
    (lambda d: d.update(dominance_threshold=2.0), "key dominance_threshold: expected a number"),
    (lambda d: d.update(negligible_threshold="0.1"), "expected a number, got a string"),
    (lambda d: d["choices"].update(D12="half"), "key choices.D12: expected one of"),
    (lambda d: d.update(extra=1), "key extra: unknown key"),
    (lambda d: d["robot"].update(parameters=[1]), "key robot.parameters: expected an object"),
    (lambda d: d.update(robot=[]), "key robot: expected an object, got a list"),
    (lambda d: d.update(cost={"multiplications": 1.5, "additions": 3}),
     "key cost.multiplications: expected an integer"),
    (lambda d: d.update(tolerance=-1), "key tolerance"),
    # JSON's own types, not Python's: 1.0 is no count, an integer beyond a float no number
    (lambda d: d.update(cost={"multiplications": 1.0, "additions": 3}),
     "key cost.multiplications: expected an integer, got a number"),
    (lambda d: d.update(tolerance=10**400), "key tolerance: number too large for a float"),
    (lambda d: d.pop("choices"), "key choices: missing key"),
    (lambda d: d["robot"].update(parameters_sha256="A" * 64),
     "key robot.parameters_sha256: malformed value"),
    (lambda d: d["robot"].update(sha256="0" * 64 + "\n"), "key robot.sha256: string longer"),
    # a bound is a number per joint (null: none stated), a guarantee states its tolerance
    (lambda d: d.update(bound=["x"] * 6), r"key bound\[0\]: expected a number or null, got a str"),
    (lambda d: d.update(bound=[[]] * 6), r"key bound\[0\]: expected a number or null, got a list"),
    (lambda d: d.update(bound=[-1.0] * 6), r"key bound\[\d\]: expected a number in \[0, "),
    (lambda d: d.update(guarantee={"kind": "trajectory"}), "key tolerance: missing key"),
    (lambda d: d["validation"].update(peak_tau=["x"] * 6),
     r"key validation.peak_tau\[0\]: expected a number or null, got a string"),
])
def test_case7_schema_violations_are_one_line(tmp_path, model_doc, edit, match):
    doc = copy.deepcopy(model_doc)
    edit(doc)
    with pytest.raises(InputError, match=match) as err:
        load_model(_write(tmp_path, doc))
    assert "\n" not in str(err.value) and "list indices" not in str(err.value)


def test_the_model_schema_is_a_valid_draft_2020_12_schema():
    from jsonschema import Draft202012Validator

    Draft202012Validator.check_schema(MODEL_SCHEMA.document)
    assert MODEL_SCHEMA.document["$schema"].endswith("/draft/2020-12/schema")


def test_error_budget_keys_are_accepted(tmp_path, model_doc):
    doc = copy.deepcopy(model_doc)
    n = len(doc["robot"]["parameters"]["link"])
    terms = {"kind": ["c"], "part": ["grav"], "i": [0], "j": [-1], "k": [-1],
             "K": [[1] + [0] * (n - 1)], "sin": [False], "coef": [2.5]}
    doc.update(schema_version=2, tolerance=0.01, rule="budget", torque_floor=0.0,
               cost={"multiplications": 1, "additions": 0, "sin": 0, "cos": 1},   # its count
               full_cost={"multiplications": 20, "additions": 16}, bound=[0.1] * n,
               explicit_terms=terms)
    with pytest.raises(InputError, match="key guarantee: missing key"):   # a budget's promise
        load_model(_write(tmp_path, doc))
    with pytest.raises(InputError, match="key explicit_terms: are not the chapter's model"):
        load_model(_write(tmp_path, {**doc, "rule": "chapter"}))    # nor the chapter's model
    # s_i the torque floor, not reached at rest (the PUMA's gravity torques are below 1e6 N m)
    doc.update(torque_floor=1e6, guarantee={
        "kind": "trajectory", "bound": [0.1] * n, "scale": [1e6] * n, "method": "",
        "trajectory_sha256": "0" * 64, "scale_state": [[0.0] * (3 * n)] * n})
    model = load_model(_write(tmp_path, doc))
    assert model.torque([0.0] * n, [0.0] * n, [0.0] * n)[0, 0] == 2.5    # 2.5 cos(q1)
    bad = copy.deepcopy(doc)
    bad["explicit_terms"]["i"] = [n]
    with pytest.raises(InputError, match="explicit"):
        load_model(_write(tmp_path, bad))


@pytest.mark.parametrize("text, match", [
    ('{"a": 1, "a": 2}', "duplicate key 'a'"),
    ('{"a": NaN}', "NaN is not a number"),
    ('{"a": 1e400}', "too large for a float"),
    ('{"a": Infinity}', "Infinity is not a number"),
    ("[" * 5000 + "]" * 5000, "nested too deeply"),
    ('{"a": ' + "9" * 5000 + "}", "not a model JSON file"),
    ("\xff", "not a model JSON file"),
])
def test_case7_and_8_strict_json(tmp_path, text, match):
    path = tmp_path / "x.json"
    path.write_bytes(text.encode("utf-8", "surrogateescape") if text != "\xff" else b"\xff")
    with pytest.raises(InputError, match=match):
        load_json(path, "model JSON")


def test_duplicate_choice_key_is_refused(tmp_path, model_doc):
    text = json.dumps(model_doc).replace('"D11": "tran"', '"D11": "tran", "D11": "rot"')
    with pytest.raises(InputError, match="duplicate key 'D11'"):
        load_model(_write(tmp_path, text))


def test_huge_integer_in_the_robot_is_refused(tmp_path, model_doc):
    doc = copy.deepcopy(model_doc)
    doc["robot"]["parameters"]["link"][0]["mass"] = 10**400
    doc["robot"]["parameters_sha256"] = parameters_sha256(doc["robot"]["parameters"])
    with pytest.raises(InputError, match="number too large for a float"):
        load_model(_write(tmp_path, doc))


def test_folder_as_model(tmp_path):
    with pytest.raises(InputError, match="is a folder, not a simplified-model JSON file$"):
        load_model(tmp_path)


# --- fuzz -------------------------------------------------------------------------------------

_VALUES = st.one_of(st.none(), st.booleans(), st.integers(-10**30, 10**30),
                    st.floats(allow_nan=False, allow_infinity=False), st.text(max_size=5),
                    st.just([]), st.just({}), st.just([1, "a"]))


def _paths(doc, prefix=()):
    if isinstance(doc, dict):
        for k, v in doc.items():
            yield prefix + (k,)
            yield from _paths(v, prefix + (k,))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            yield prefix + (i,)
            yield from _paths(v, prefix + (i,))


@settings(max_examples=80, deadline=None, suppress_health_check=list(HealthCheck),
          phases=[Phase.explicit, Phase.reuse, Phase.generate])
@given(data=st.data(), action=st.sampled_from(["replace", "delete", "add"]), value=_VALUES,
       rehash=st.booleans())
def test_fuzz_model_loader(tmp_path_factory, model_doc, data, action, value, rehash):
    tmp = tmp_path_factory.mktemp("js")
    doc = copy.deepcopy(model_doc)
    paths = sorted(_paths(doc), key=str)
    path = data.draw(st.sampled_from(paths))
    parent = doc
    for key in path[:-1]:
        parent = parent[key]
    last = path[-1]
    if action == "replace":
        parent[last] = value
    elif action == "delete":
        del parent[last]
    elif isinstance(parent, dict):
        parent[data.draw(st.text(min_size=1, max_size=4))] = value
    else:
        parent.append(value)
    if rehash and isinstance(doc.get("robot"), dict) and "parameters" in doc["robot"]:
        try:
            doc["robot"]["parameters_sha256"] = parameters_sha256(doc["robot"]["parameters"])
        except (TypeError, ValueError, OverflowError):
            pass
    note(f"{action} {path} -> {value!r}")
    file = _write(tmp, doc)
    before = set(os.listdir(tmp))
    try:
        model = load_model(file)
    except InputError as exc:
        assert "\n" not in str(exc) and str(exc).startswith(str(file))
    else:
        # accepted: the values are those of the document
        MODEL_SCHEMA.check(doc, str(file))
        assert model.choices == doc["choices"]
        assert model.dominance_threshold == doc["dominance_threshold"]
        assert model.robot.name == doc["robot"]["parameters"]["name"]
        np.testing.assert_array_equal(model.robot.mass, [lk["mass"] for lk in
                                                         doc["robot"]["parameters"]["link"]])
    assert set(os.listdir(tmp)) == before


@pytest.mark.parametrize("body", ['"' + '\\"' * 500_000, '["' + '\\\\' * 500_000 + '"]'])
def test_the_nesting_check_is_linear_on_1_mb(tmp_path, body):
    """A run of escaped quotes with no closing quote made the nesting check's regex quadratic
    (48 KB: 30 s; 1 MB: hours)."""
    path = tmp_path / "m.json"
    path.write_text(body)
    assert path.stat().st_size > 1_000_000
    if body.endswith("]"):
        assert load_json(path) == ["\\" * 500_000]
    else:
        with pytest.raises(InputError, match="not a JSON file: Unterminated string"):
            load_json(path)


def test_the_nesting_check_s_memory_is_bounded_in_the_file_s_size(tmp_path):
    """The nesting check made its arrays over the whole text at once, 48 bytes a byte: a
    50 MB model file took 2.4 GB. Counted on the parsed document, its memory does not grow
    with the file: 6 MB more of file costs less than six times that (the text, read and
    parsed)."""
    import tracemalloc

    peaks = []
    for megabytes in (2, 8):
        path = tmp_path / f"m{megabytes}.json"
        path.write_text('{"pad": "' + "x" * (megabytes << 20) + '"}')
        tracemalloc.start()
        assert len(load_json(path)["pad"]) == megabytes << 20
        peaks.append(tracemalloc.get_traced_memory()[1])
        tracemalloc.stop()
    assert peaks[1] - peaks[0] < 6 * (6 << 20), peaks


@pytest.mark.parametrize("seed", [1, 2, 3, 7])
def test_the_nesting_limit_counts_objects_and_lists_not_brackets_in_strings(tmp_path, seed):
    """A document nested exactly MAX_DEPTH deep is read whole, one level deeper is refused:
    objects and lists mixed, strings full of brackets, quotes and backslashes that are no
    nesting, the levels built here (the oracle), not counted by the reader."""
    import random

    from gd_analyze.store.json_schema import MAX_DEPTH

    rng = random.Random(seed)

    def text():
        return "".join(rng.choice('[]{}"\\a é') for _ in range(rng.randint(0, 12)))

    def nested(levels):
        doc = text()
        for k in range(levels):         # empty containers beside, but for the deepest
            siblings = [text(), rng.random(), *([[], {}] if k else [])]
            doc = ({text(): doc, **{f"{i}{text()}": v for i, v in enumerate(siblings)}}
                   if rng.random() < 0.5
                   else [*siblings[:rng.randint(0, 3)], doc])
        return doc

    for levels in (MAX_DEPTH - 1, MAX_DEPTH, MAX_DEPTH + 1, 3 * MAX_DEPTH):
        doc = nested(levels)
        path = tmp_path / f"d{levels}.json"
        path.write_text(json.dumps(doc))
        if levels <= MAX_DEPTH:
            assert load_json(path) == doc
        else:
            with pytest.raises(InputError, match="nested too deeply"):
                load_json(path)
