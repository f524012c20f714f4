import h5py
import numpy as np
import pytest
import xarray as xr
from conftest import SHIPPED

from gd_analyze.files import atomic_path
from gd_analyze.jobs.analyze import analyze
from gd_analyze.jobs.options import AnalysisOptions
from gd_analyze.store.datasets import units_by_type
from gd_analyze.store.schema import write_dataset
from gd_analyze.trajectory.trajectory import read_trajectory


@pytest.fixture(scope="module")
def written(tmp_path_factory, puma):
    traj = read_trajectory(SHIPPED, 6)
    analysis = analyze(puma, traj, AnalysisOptions(formulations=False))
    path = tmp_path_factory.mktemp("store") / "results.h5"
    write_dataset(analysis.dataset, path)
    return path, analysis, traj


REQUIRED = ["t", "q", "qd", "qdd", "D_tran", "D_rot", "D", "h_tran", "h_rot", "h", "c", "tau",
            "tau_simplified", "share_tran", "dominance", "peak_tran", "peak_rot", "peak_total"]


def test_reads_back_with_xarray(written, puma):
    path, analysis, traj = written
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        assert set(REQUIRED) <= set(ds.variables) and "t" in ds.coords
        from gd_analyze.dynamics.base_parameters import base_parameters

        # cost rows: exact and pruned recursive (this model), explicit full, chapter and
        # budget, 3 formulations, Table 3.5 (3), AKB (2), and the recursive ladder's rungs
        # other than 0 and the model's EPS (2)
        assert ds.sizes == {"t": 31, "joint": 6, "joint_k": 6, "element": 27, "xyz": 3,
                            "xyz_k": 3, "cost_model": 16, "ladder_tolerance": 4,
                            "base_parameter": base_parameters(puma).rank, "torque_part": 3,
                            "chapter_threshold": 6}     # s = 0.6 ... 0.99 (the chapter's PUMA)
        assert ds.D_tran.dims == ("t", "joint", "joint_k")
        assert ds.element.values[0] == "D11" and ds.element.values[-1] == "h6"
        for name, var in ds.variables.items():
            assert "units" in var.attrs and "long_name" in var.attrs, name
        np.testing.assert_array_equal(ds.q.values, traj.q)
        np.testing.assert_allclose(ds.D.values, ds.D_tran.values + ds.D_rot.values)
        np.testing.assert_allclose(
            ds.tau.values,
            np.einsum("kij,kj->ki", ds.D.values, ds.qdd.values) + ds.h.values + ds.c.values)
        a = ds.attrs
        assert a["Conventions"].startswith("CF-")
        assert a["robot"] == "puma560" and a["robot_sha256"] == puma.sha256
        np.testing.assert_allclose(a["gravity"], [0, 0, -9.8062])
        assert a["dominance_threshold"] == 0.9 and a["negligible_threshold"] == 0.01
        assert a["input_file"] == "puma560_trajectory.csv" and a["input_sha256"] == traj.sha256
        assert a["gd_analyze_version"]
        assert a["verification_passed"] == 1
        assert list(ds.dominance.values) == list(analysis.dataset.dominance.values)


def test_reads_back_with_plain_h5py(written):
    path, _, traj = written
    with h5py.File(path, "r") as f:
        np.testing.assert_array_equal(f["q"][()], traj.q)
        assert f["D_rot"].shape == (31, 6, 6)
        assert f["D_rot"].attrs["units"] in (b"kg m2", "kg m2")
        labels = [v.decode() if isinstance(v, bytes) else v for v in f["element"][()]]
        assert labels[:2] == ["D11", "D12"]
        assert f.attrs["robot"] in (b"puma560", "puma560")


def test_atomic_path_leaves_nothing_on_failure(tmp_path):
    target = tmp_path / "out.txt"
    target.write_text("old")
    with pytest.raises(RuntimeError):
        with atomic_path(target) as tmp:
            with open(tmp, "w") as fh:
                fh.write("half")
            raise RuntimeError("boom")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["out.txt"]


def test_atomic_path_can_leave_the_name_free_for_an_exclusive_writer(tmp_path):
    import os

    target = tmp_path / "out.bin"
    with atomic_path(target, create=False) as tmp:
        assert not os.path.lexists(tmp) and os.path.dirname(tmp) == str(tmp_path)
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
        os.write(fd, b"new")
        os.close(fd)
    assert target.read_bytes() == b"new"
    with pytest.raises(RuntimeError):
        with atomic_path(target, create=False):
            raise RuntimeError("boom")               # before the writer created it
    assert [p.name for p in tmp_path.iterdir()] == ["out.bin"]


def test_the_results_file_is_created_new_with_the_usual_mode(tmp_path, puma):
    """results.h5 is created exclusively (never over an existing file or through a link),
    with mode 0666 less the umask as atomic_path gives its files."""
    import os
    import stat

    from gd_analyze.jobs.analyze import analyze_to_file
    from gd_analyze.store.datasets import SetpointWriter

    traj = read_trajectory(SHIPPED, 6)
    path = tmp_path / "results.h5"
    analyze_to_file(puma, traj, path, AnalysisOptions(verify=False, formulations=False))
    with atomic_path(tmp_path / "other.txt"):
        pass
    mode = stat.S_IMODE(os.stat(tmp_path / "other.txt").st_mode)
    assert stat.S_IMODE(os.stat(path).st_mode) == mode
    with pytest.raises(OSError):
        SetpointWriter(path, 3, 6)                  # exists: refused, left as it was
    (tmp_path / "link.h5").symlink_to(tmp_path / "nowhere.h5")
    with pytest.raises(OSError):
        SetpointWriter(tmp_path / "link.h5", 3, 6)
    assert not (tmp_path / "nowhere.h5").exists()
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        assert ds.sizes["t"] == traj.n_setpoints


def test_main_job_stores_the_formulations(tmp_path, puma):
    from gd_analyze.dynamics.opcount import book_counts
    from gd_analyze.jobs.analyze import analyze_to_file

    traj = read_trajectory(SHIPPED, 6)
    path = tmp_path / "results.h5"
    # the formulations are counted and compared in the analysis pass, whatever model is built
    # on its ranking: ranked only (no model), not verified
    analyze_to_file(puma, traj, path, AnalysisOptions(verify=False, simplify=None))
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        assert ds.sizes["formulation_pair"] == 6 and ds.sizes["dof"] == 10
        assert float(ds.formulation_disagreement.max()) < 1e-10
        book = book_counts(6)
        for method in ("lagrange-euler", "newton-euler", "gd"):
            stored = ds.op_multiplications_table_3_5.sel(dof=6, formulation=method).item()
            assert stored == pytest.approx(book[method]["multiplications"])
        # N-E cost grows linearly in n, L-E as n^4: the measured counts show it (n = 1 has
        # no inner links, so the line starts at n = 2)
        ne = ds.op_multiplications.sel(formulation="newton-euler").values
        assert np.allclose(np.diff(ne[1:], 2), 0)     # linear for n >= 2
        le = ds.op_multiplications.sel(formulation="lagrange-euler").values
        assert le[9] / le[4] > 8


def test_no_share_is_stored_for_an_element_zero_in_every_part(shipped_dataset):
    """Results.h5 stored shares of 0.40 and 0.78 for D45 and D56 of the PUMA 560,
    ratios of round-off. Oracle: the stored series themselves (every part of the element
    within 1e-12 of sqrt(D_44 D_55) at every set point)."""
    ds = shipped_dataset("puma560")
    labels = [str(v) for v in ds["element"].values]
    share = ds["share_tran"].values
    for lab in ("D45", "D56"):
        i, j = int(lab[1]) - 1, int(lab[2]) - 1
        scale = np.sqrt(np.abs(ds["D"].values[:, i, i] * ds["D"].values[:, j, j])).max()
        for part in ("D_tran", "D_rot"):
            assert np.abs(ds[part].values[:, i, j]).max() <= 1e-12 * scale
        assert np.isnan(share[labels.index(lab)]), lab
    assert np.isfinite(np.delete(share, [labels.index("D45"), labels.index("D56")])).all()


def test_round_off_torque_errors_are_marked_as_such(shipped_dataset):
    """Results.h5 stored joints 3 to 6's torque errors (1e-16 to 4e-15 N m) as
    numbers like any other. They are flagged round-off (the report's "≡ 0"): at most 1e-12 of
    the joint's peak |tau| or 64 eps of the arm's largest."""
    ds = shipped_dataset("puma560")
    peak, tau = ds["tau_error_peak"].values, ds["tau_peak"].values
    oracle = peak <= np.maximum(1e-12 * tau, 64 * np.finfo(float).eps * tau.max())
    flags = ds["tau_error_round_off"].values.astype(bool)
    assert oracle.any() and not oracle.all()                     # the case at hand
    np.testing.assert_array_equal(flags, oracle)
    assert ds["tau_error_round_off"].attrs["flag_meanings"] == "data round_off"


def test_a_dataset_is_written_as_to_netcdf_writes_it_without_importing_distributed(
        written, tmp_path):
    """write_dataset writes the file xarray's to_netcdf (h5netcdf, the same encoding) writes,
    object for object, attribute for attribute, with the same compression; and, in a fresh
    interpreter, without importing dask.distributed (to_netcdf asks dask for its scheduler)."""
    import subprocess
    import sys

    path = written[0]
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        ds = ds.load()
    for var in ds.variables.values():
        var.encoding = {}
    mine, theirs = tmp_path / "mine.h5", tmp_path / "theirs.h5"
    write_dataset(ds, mine)
    ds.to_netcdf(theirs, engine="h5netcdf", invalid_netcdf=False, encoding={
        name: {"zlib": True, "complevel": 4} for name, var in ds.data_vars.items()
        if var.dtype.kind == "f" and var.ndim >= 2})

    def contents(name):
        out = {}
        with h5py.File(name) as f:
            def visit(key, obj):
                attrs = {k: str(v) for k, v in obj.attrs.items()
                         if k not in ("DIMENSION_LIST", "REFERENCE_LIST")}
                if isinstance(obj, h5py.Dataset):
                    attrs.update(dtype=str(obj.dtype), shape=str(obj.shape),
                                 filters=str((obj.compression, obj.compression_opts,
                                              obj.shuffle, obj.chunks)),
                                 data=str(obj[()].tolist()))
                out[key] = attrs
            f.visititems(visit)
            out["/"] = {k: str(v) for k, v in f.attrs.items()}
        return out

    assert contents(mine) == contents(theirs)
    code = ("import sys, xarray as xr\n"
            "from gd_analyze.store.schema import write_dataset\n"
            f"write_dataset(xr.Dataset({{'a': (('x',), [1.0, 2.0])}}), {str(tmp_path / 'x.h5')!r})\n"
            "print('distributed' in sys.modules)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    assert done.stdout.split() == ["False"], done.stdout + done.stderr


def test_units_by_type_name_one_unit_or_both_and_where_to_read_them():
    # closed forms: a revolute joint's torque is in N m, a prismatic joint's in N
    assert units_by_type([False, False], "tau") == "N m"
    assert units_by_type([True], "q") == "m"
    assert units_by_type([False, True], "tau") == "N m or N by joint type (per joint: tau_units)"
    assert (units_by_type([True, False], "qd", "joint_type")
            == "m s-1 or rad s-1 by joint type (per joint: joint_type)")
