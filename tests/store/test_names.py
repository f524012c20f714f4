"""The names of results.h5 (gd_analyze.store.names): every name the main job writes is a constant,
and each constant is spelt as the name it stands for."""

import json
from pathlib import Path

import numpy as np
import pytest

from gd_analyze.store import names
from gd_analyze.store.names import (
    ATTRIBUTES,
    CONTROL_VARIABLES,
    ELEMENT_UNITS_RULE,
    RANKING_COLUMNS,
    SWEEP_VARIABLES,
    VARIABLES,
    Attr,
    ControlVar,
    SweepAttr,
    SweepVar,
    Var,
)
from gd_analyze.store.results_view import Results
from gd_analyze.store.schema import MIXED_UNITS, strings

GOLDEN = Path(__file__).resolve().parents[1] / "golden"


@pytest.mark.parametrize("namespace", [Var, Attr, ControlVar, SweepVar, SweepAttr])
def test_each_constant_is_its_name_upper_cased(namespace):
    # with the constants of its bases (the names two or three files share)
    constants = {k: v for c in namespace.__mro__ for k, v in vars(c).items() if k.isupper()}
    assert constants
    assert all(k == v.upper() for k, v in constants.items()), constants


@pytest.mark.parametrize("robot", ["puma560", "stanford"])
def test_every_stored_name_is_a_constant(shipped_dataset, robot):
    # the main job's results.h5, read back (a writer that adds a name must add it here)
    ds = shipped_dataset(robot)
    assert set(map(str, ds.variables)) - VARIABLES == set()
    assert set(ds.attrs) - ATTRIBUTES == set()


@pytest.mark.parametrize("frozen, variables", [
    ("puma560-control/control.h5.frozen.json", CONTROL_VARIABLES),
    ("puma560-sweep/sweep.h5.frozen.json", SWEEP_VARIABLES)])
def test_every_variable_of_control_and_sweep_files_is_a_constant(frozen, variables):
    # the golden files freeze what the writers wrote (tests/test_golden.py keeps them equal)
    d = json.loads((GOLDEN / frozen).read_text())
    stored = set(d["dims"]) | set(d["coords"]) | {
        k.split("/")[1] for k in d["leaves"] if k.startswith("var/")}
    assert stored - variables - VARIABLES == set()     # the joints' units, the region: Var's


def test_verification_attributes_are_constants(shipped_dataset):
    ds = shipped_dataset("puma560")
    for term in names.VERIFIED_TERMS:
        assert names.verification_attribute(term) in ds.attrs
        assert names.verification_attribute(term, excess=True) in ds.attrs
        assert names.verification_attribute(term) in ATTRIBUTES
        assert names.verification_attribute(term, excess=True) in ATTRIBUTES


def test_the_ranking_columns_are_stored_and_read_as_declared(shipped_dataset):
    # one declaration: each ranking column is in results.h5 with its declared units and
    # long_name, the view reads it as stored, and the CLI shows the columns it declares
    ds = shipped_dataset("puma560")
    table = Results.from_dataset(ds).ranking
    for column in RANKING_COLUMNS:
        if column.source == "armature":
            continue
        if column.name not in ds.variables:
            assert not column.required and column.field not in table.columns
            continue
        if column.stored:
            attrs = ds[column.name].attrs
            assert attrs["long_name"] == column.long_name
            assert attrs["units"] == (MIXED_UNITS if column.units == ELEMENT_UNITS_RULE
                                      else column.units)
        stored = ds[column.name].values
        if column.text:
            assert list(table.column(column.field)) == strings(stored)
        else:
            np.testing.assert_array_equal(table.column(column.field), stored)
        if column.round_off is not None:
            np.testing.assert_array_equal(table.off(column.field),
                                          ds[column.round_off].values.astype(bool))
    header = table.text()[0].split()
    assert header == [c.cli.header for c in RANKING_COLUMNS if c.cli is not None]
    assert [r.label for r in table.rows] == strings(ds[Var.ELEMENT].values)
