"""The one reading path of the typed views (gd_analyze.store.schema.View): each field where
its declaration says, a default only where the dataset lacks it, the checks of a malformed
dataset as one line."""

from dataclasses import dataclass

import numpy as np
import pytest
import xarray as xr

from gd_analyze.errors import InputError
from gd_analyze.store.schema import View, derived, require, stored, stored_has_drives, texts


@dataclass(frozen=True, eq=False)
class _Probe(View):
    required, what = ("a",), "probe"
    presence = ("b",)

    a: np.ndarray = stored("a")
    b: tuple[str, ...] = stored("b", texts)
    c: float = stored("c", lambda v: 2.0 * float(v), -1.0, attr=True)
    d: np.ndarray | None = stored("d", default=None)
    n: int = derived(lambda ds: int(ds.sizes["x"]))
    given: str = "none"


def _dataset(**drop):
    ds = xr.Dataset({"a": ("x", [1.0, 2.0, 3.0]), "b": ("y", np.array(["p", "q"]))},
                    attrs={"c": 0.25})
    return ds.drop_vars([k for k in drop if k in ds.variables]) if drop else ds


def test_each_field_is_read_where_its_declaration_says():
    v = _Probe.from_dataset(_dataset())
    assert v.a.tolist() == [1.0, 2.0, 3.0] and v.b == ("p", "q")
    assert v.c == 0.5                       # converted: twice the stored 0.25
    assert v.d is None and v.n == 3 and v.given == "none"


def test_a_default_is_not_converted_and_a_given_field_is_not_read():
    ds = _dataset()
    del ds.attrs["c"]
    v = _Probe.read(ds, given="yes", a=np.zeros(1))
    assert v.c == -1.0 and v.given == "yes" and v.a.tolist() == [0.0]


def test_a_view_absent_from_the_dataset_is_none():
    assert _Probe.from_dataset(_dataset(b=True)) is None


def test_a_missing_required_variable_is_one_line_naming_it():
    with pytest.raises(InputError) as err:
        _Probe.from_dataset(_dataset(a=True))
    assert "\n" not in str(err.value) and "not a gd-analyze probe dataset" in str(err.value)
    assert "a" in str(err.value).split("missing variable(s)")[1]


def test_a_field_without_default_must_be_stored():
    with pytest.raises(KeyError):
        _Probe.read(_dataset(a=True))


def test_drives_are_stored_where_one_of_their_variables_is_nonzero():
    # closed form: an arm has drives iff its armature, friction or torque offset is not 0
    assert not stored_has_drives(xr.Dataset())
    zero = xr.Dataset({name: ("joint", np.zeros(3))
                       for name in ("D_arm", "viscous", "coulomb", "torque_offset")})
    assert not stored_has_drives(zero)
    for name in zero.data_vars:
        one = zero.copy(deep=True)
        one[name].values[1] = 0.5
        assert stored_has_drives(one), name


def test_require_names_every_missing_variable_in_one_line():
    ds = xr.Dataset({"x": ("i", [1.0])})
    require(ds, ["x"], "results")
    with pytest.raises(InputError) as err:
        require(ds, ["x", "y", "z"], "sweep")
    assert str(err.value) == "not a gd-analyze sweep dataset: missing variable(s) y, z"
