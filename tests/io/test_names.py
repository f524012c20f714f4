"""The names of results.h5 (gd_analyze.io.names): every name the main job writes is a constant,
and each constant is spelt as the name it stands for."""

import pytest

from gd_analyze.io import names
from gd_analyze.io.names import ATTRIBUTES, VARIABLES, Attr, Var


@pytest.mark.parametrize("namespace", [Var, Attr])
def test_each_constant_is_its_name_upper_cased(namespace):
    constants = {k: v for k, v in vars(namespace).items() if k.isupper()}
    assert constants
    assert all(k == v.upper() for k, v in constants.items()), constants


@pytest.mark.parametrize("robot", ["puma560", "stanford"])
def test_every_stored_name_is_a_constant(shipped_dataset, robot):
    # the main job's results.h5, read back (a writer that adds a name must add it here)
    ds = shipped_dataset(robot)
    assert set(map(str, ds.variables)) - VARIABLES == set()
    assert set(ds.attrs) - ATTRIBUTES == set()


def test_verification_attributes_are_constants(shipped_dataset):
    ds = shipped_dataset("puma560")
    for term in names.VERIFIED_TERMS:
        assert names.verification_attribute(term) in ds.attrs
        assert names.verification_attribute(term, excess=True) in ds.attrs
