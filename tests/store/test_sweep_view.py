"""The sweep's typed view (gd_analyze.store.sweep_view): what the command line prints and the
report reads, read once and checked as read; the tasks added after the sweep counted without
changing the dataset."""

import numpy as np
import pytest
import xarray as xr

from gd_analyze.errors import InputError
from gd_analyze.store.sweep_view import REQUIRED, StoredSweep, with_more_tasks

CLASSES = ["translational", "rotational", "both", "negligible"]


def _sweep():
    """A sweep of 3 trajectories of a 2-joint arm over two elements, as run_sweep stores its
    summary (the per-trajectory errors zero)."""
    K, n = 3, 2
    data = {"class_fraction": (("element", "class"), [[2 / 3, 1 / 3, 0, 0], [0, 0, 0, 1]]),
            "share_tran_min": ("element", [0.5, 0.1]),
            "share_tran_median": ("element", [0.9, 0.2]),
            "share_tran_max": ("element", [0.99, 0.3]),
            "merged_choice": ("element", ["both", "none"]),
            "share_tran": (("trajectory", "element"), np.full((K, 2), 0.5)),
            "dominance": (("trajectory", "element"), np.full((K, 2), "both")),
            "choice": (("trajectory", "element"), np.full((K, 2), "both")),
            "source": ("trajectory", ["a", "b", "c"]),
            "duration": ("trajectory", [1.0, 2.0, 3.0])}
    for name in (*REQUIRED, "tau_error_peak", "merged_tau_error_peak"):
        if name not in data:                    # the errors: over joint, or per trajectory
            data[name] = ((("joint",), np.zeros(n)) if name.startswith("merged_error")
                          else (("trajectory", "joint"), np.zeros((K, n))))
    return xr.Dataset(data, coords={"element": ["D11", "h1"], "class": CLASSES,
                                    "trajectory": [0, 1, 2]},
                      attrs={"elapsed_s": 1.25, "n_workers": 2,
                             "scheduler_address": "inproc://x", "batch_size": 2, "n_tasks": 2})


def test_the_view_reads_the_summary_as_stored():
    run = StoredSweep.from_dataset(_sweep())
    s = run.settings
    assert (run.trajectories, s.n_workers, s.batch_size, s.n_tasks) == (3, 2, 2, 2)
    assert run.classes == tuple(CLASSES) and run.elements == ("D11", "h1")
    assert run.merged.choice == ("both", "none") and run.share_max[0] == 0.99
    assert run.class_fraction[0, 1] == pytest.approx(1 / 3)
    assert run.sources == ("a", "b", "c") and run.duration.tolist() == [1.0, 2.0, 3.0]


@pytest.mark.parametrize("missing", ["share_tran_median", "merged_choice", "round_off"])
def test_a_missing_variable_is_one_line_naming_it(missing):
    ds = _sweep().drop_vars(missing)
    with pytest.raises(InputError) as err:
        StoredSweep.from_dataset(ds)
    assert "\n" not in str(err.value) and missing in str(err.value)


@pytest.mark.parametrize("missing", ["merged_bound", "merged_covered", "merged_scale"])
def test_a_stored_guarantee_without_what_it_is_checked_on_is_one_line_naming_it(missing):
    """A sweep stores a merged model's region guarantee with each trajectory's bound, scale
    and coverage; a file holding the guarantee but not one of those is refused in one line
    naming it (it was a KeyError from deep in the reading)."""
    ds = _sweep().assign_attrs(merged_guarantee_statement="within 1 % of s_i over the region",
                               merged_guarantee_kind="region")
    K, n = 3, 2
    ds = ds.assign({"merged_bound": (("trajectory", "joint"), np.ones((K, n))),
                    "merged_scale": (("trajectory", "joint"), np.ones((K, n))),
                    "merged_covered": ("trajectory", [1, 1, 0]),
                    "merged_coverage": ("trajectory", ["", "", "q1 outside"])})
    assert StoredSweep.from_dataset(ds).merged.guarantee["outside"] == [("c", "q1 outside", 0.0)]
    with pytest.raises(InputError) as err:
        StoredSweep.from_dataset(ds.drop_vars(missing))
    assert str(err.value) == f"not a gd-analyze sweep dataset: missing variable(s) {missing}"


def test_more_tasks_are_counted_on_a_new_dataset():
    ds = _sweep()
    more = with_more_tasks(ds, 3)
    assert StoredSweep.from_dataset(more).settings.n_tasks == 5
    assert StoredSweep.from_dataset(ds).settings.n_tasks == 2   # the sweep's own count unchanged


def test_a_payload_dataset_stores_each_mass_ranking_with_its_round_off(two_link):
    """Two masses of a two-link arm: the per-mass results stored as given, and an element's
    round_off flag 1 exactly where all its parts are zero (by construction), 0 where any one
    of them (translational, rotational or total) is its scale."""
    from gd_analyze.ranking.labels import element_labels
    from gd_analyze.store.sweep_view import payload_dataset
    from gd_analyze.trajectory.trajectory import Trajectory

    labels = element_labels(two_link.n)
    M = len(labels)
    which = np.arange(M) % 4                     # 0: all parts zero; 1, 2, 3: only that part
    zero = which == 0
    results = []
    for p in range(2):
        part = [np.where(which == k, 1.0 + p, 0.0) for k in (1, 2, 3)]
        results.append({"share_tran": np.full(M, 0.25 * (p + 1)),
                        "classes": ("both",) * M,
                        "choices": {lab: ("tran", "rot")[p] for lab in labels},
                        "peaks": {"peak_tran": part[0], "peak_rot": part[1],
                                  "peak_total": part[2], "scale": np.full(M, 1.0 + p)},
                        "summary": {"tau_peak": np.array([3.0, 4.0 + p]),
                                    "error": {"relative_peak_error": np.array([0.1, 0.2])}}})
    t = np.linspace(0.0, 1.0, 3)
    q = np.zeros((3, two_link.n))
    traj = Trajectory(t=t, q=q, qd=q, qdd=q, source="a.csv")
    ds = payload_dataset(two_link, traj, np.array([0.0, 1.0]), (0, 0, 0), (0, 0, 0),
                         results, 0.9, 0.01)
    assert ds["round_off"].dims == ("payload", "element")
    assert ds["round_off"].values.tolist() == [zero.astype(int).tolist()] * 2
    assert ds["share_tran"].values[:, 0].tolist() == [0.25, 0.5]
    assert ds["choice"].values[:, 0].tolist() == ["tran", "rot"]
    assert ds["tau_peak"].values.tolist() == [[3.0, 4.0], [3.0, 5.0]]
    assert ds["tau_peak"].dims == ("payload", "joint")
    assert ds["peak_total"].values[1].tolist() == np.where(which == 3, 2.0, 0.0).tolist()
    assert "along the trajectory" in ds["round_off"].attrs["long_name"]
