"""The sweep's typed view (gd_analyze.store.sweep_view): what the command line prints, read once
and checked as read; the tasks added after the sweep counted without changing the dataset."""

import pytest
import xarray as xr

from gd_analyze.errors import InputError
from gd_analyze.store.sweep_view import SweepRun, with_more_tasks

CLASSES = ["translational", "rotational", "both", "negligible"]


def _sweep():
    """A sweep of 3 trajectories over two elements, as run_sweep stores its summary."""
    return xr.Dataset(
        {"class_fraction": (("element", "class"), [[2 / 3, 1 / 3, 0, 0], [0, 0, 0, 1]]),
         "share_tran_min": ("element", [0.5, 0.1]), "share_tran_median": ("element", [0.9, 0.2]),
         "share_tran_max": ("element", [0.99, 0.3]), "merged_choice": ("element", ["both", "none"])},
        coords={"element": ["D11", "h1"], "class": CLASSES, "trajectory": [0, 1, 2]},
        attrs={"elapsed_s": 1.25, "n_workers": 2, "scheduler_address": "inproc://x",
               "batch_size": 2, "n_tasks": 2})


def test_the_view_reads_the_summary_as_stored():
    run = SweepRun.from_dataset(_sweep())
    assert (run.trajectories, run.n_workers, run.batch_size, run.n_tasks) == (3, 2, 2, 2)
    assert run.classes == tuple(CLASSES) and run.elements == ("D11", "h1")
    assert run.merged_choice == ("both", "none") and run.share_max[0] == 0.99
    assert run.class_fraction[0, 1] == pytest.approx(1 / 3)


@pytest.mark.parametrize("missing", ["share_tran_median", "n_workers"])
def test_a_missing_entry_is_one_line_naming_it(missing):
    ds = _sweep()
    if missing in ds.variables:
        ds = ds.drop_vars(missing)
    else:
        del ds.attrs[missing]
    with pytest.raises(InputError) as err:
        SweepRun.from_dataset(ds, source="sweep.h5")
    assert "\n" not in str(err.value) and repr(missing) in str(err.value)
    assert "sweep.h5" in str(err.value)


def test_more_tasks_are_counted_on_a_new_dataset():
    ds = _sweep()
    more = with_more_tasks(ds, 3)
    assert SweepRun.from_dataset(more).n_tasks == 5
    assert SweepRun.from_dataset(ds).n_tasks == 2          # the sweep's own count unchanged
