import numpy as np
import xarray as xr

from conftest import SHIPPED
from gd_analyze.workflows.analyze import analyze, analyze_to_file, verify
from gd_analyze.core.ranking import RankingAccumulator, rank_dominance
from gd_analyze.io.trajectory import plan_quintic, read_trajectory


def test_streamed_file_equals_the_in_memory_analysis(tmp_path, puma):
    traj = plan_quintic(puma, np.radians([-60, 20, -150, -80, -60, -120]),
                        np.radians([60, 110, -60, 80, 60, 120]), n_setpoints=1001)
    whole = analyze(puma, traj, check=False).dataset
    path = tmp_path / "results.h5"
    streamed = analyze_to_file(puma, traj, path, check=True, chunk=97)   # 11 uneven chunks
    assert streamed.verification["passed"] == 1
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        for name in ("t", "q", "D_tran", "D_rot", "D", "h_tran", "h_rot", "h", "c", "tau",
                     "tau_simplified", "share_tran", "peak_total", "tau_error_rms"):
            np.testing.assert_allclose(ds[name].values, whole[name].values, rtol=1e-12,
                                       atol=1e-15, err_msg=name)
            assert ds[name].attrs["units"] == whole[name].attrs["units"]
        assert list(ds.dominance.values) == list(whole.dominance.values)
        assert list(ds.choice.values) == list(whole.choice.values)
        assert ds.sizes["setpoint"] == 1001
    assert [p.name for p in tmp_path.iterdir()] == ["results.h5"]


def test_ranking_accumulated_in_chunks_equals_the_whole(puma):
    from gd_analyze import gd_terms

    traj = read_trajectory(SHIPPED, 6)
    t = gd_terms(puma, traj.q, traj.qd)
    tau = t.tau(traj.qdd)
    whole = rank_dominance(t.D_tran, t.D_rot, t.h_tran, t.h_rot, tau)
    acc = RankingAccumulator(6)
    for a in range(0, 31, 4):
        s = slice(a, a + 4)
        acc.update(t.D_tran[s], t.D_rot[s], t.h_tran[s], t.h_rot[s], tau[s])
    parts = acc.result()
    np.testing.assert_allclose(parts.share_tran, whole.share_tran, rtol=1e-13)
    assert parts.dominance == whole.dominance


def test_verify_flags_a_wrong_term(puma):
    """The check can fail: perturb one term and it no longer passes."""
    from dataclasses import replace

    from gd_analyze import gd_terms

    traj = read_trajectory(SHIPPED, 6)
    t = gd_terms(puma, traj.q, traj.qd)
    assert verify(puma, traj.q, traj.qd, t)["passed"] == 1
    bad = replace(t, h_rot=t.h_rot * (1 + 1e-6))
    result = verify(puma, traj.q, traj.qd, bad)
    assert result["passed"] == 0 and result["max_rel_error_h_rot"] > 1e-7


def test_progress_bar_on_request_and_silent_otherwise(tmp_path, puma, capsys, monkeypatch):
    import gd_analyze.workflows.analyze as pipeline

    traj = read_trajectory(SHIPPED, 6)
    monkeypatch.setattr(pipeline, "PROGRESS_DELAY", 0.0)
    analyze_to_file(puma, traj, tmp_path / "a.h5", check=False, formulations=False,
                    progress=True, chunk=8)
    err = capsys.readouterr().err
    assert "setpoint/s" in err and "/62" in err       # rate; two passes over 31 set points
    analyze_to_file(puma, traj, tmp_path / "b.h5", check=False, formulations=False,
                    progress=False, chunk=8)
    assert capsys.readouterr().err == ""
