"""The control run's typed view (gd_analyze.store.stored_control): a control.h5 without what
the control run always stores (the model's facts, the gains' units, the applied torques'
figures, the initial offset, the control laws) is refused in one line
naming what is missing, never reported through a fallback."""

import numpy as np
import pytest
import xarray as xr

from gd_analyze.errors import InputError
from gd_analyze.store.stored_control import REQUIRED_VARIABLES, ModelFacts, StoredControl


def _control(drop_attr=None, drop_var=None):
    """Every variable and dim the view requires (placeholders), and every model_<fact>."""
    data = {v: (("time",), np.zeros(2)) for v in REQUIRED_VARIABLES if v != drop_var}
    attrs = {f"model_{k}": 0 for k in ModelFacts._fields if f"model_{k}" != drop_attr}
    return xr.Dataset(data, coords={"controller": ["full"], "time": [0.0, 1.0]}, attrs=attrs)


@pytest.mark.parametrize("missing", ["model_scope", "model_form", "model_guarantee_covered"])
def test_a_control_dataset_without_a_model_fact_is_refused_naming_it(missing):
    with pytest.raises(InputError) as err:
        StoredControl.from_dataset(_control(drop_attr=missing), "old/control.h5")
    assert "\n" not in str(err.value) and missing in str(err.value)


@pytest.mark.parametrize("missing", ["Kp_pd_units", "tau_peak", "q0_offset",
                                     "controller_description"])
def test_a_control_dataset_without_a_variable_the_run_stores_is_refused_naming_it(missing):
    with pytest.raises(InputError) as err:
        StoredControl.from_dataset(_control(drop_var=missing), "old/control.h5")
    assert "\n" not in str(err.value) and missing in str(err.value)
