import numpy as np
import pytest
import xarray as xr
from conftest import ROOT, SHIPPED

from gd_analyze.jobs.analyze import analyze, analyze_to_file, verify
from gd_analyze.jobs.options import AnalysisOptions, SimplifyOptions
from gd_analyze.ranking.ranking import RankingAccumulator, rank_dominance
from gd_analyze.trajectory.planning import plan_quintic
from gd_analyze.trajectory.trajectory import read_trajectory, trajectory_from_arrays


@pytest.mark.slow
def test_streamed_file_equals_the_in_memory_analysis(tmp_path, puma):
    traj = plan_quintic(puma, np.radians([-60, 20, -150, -80, -60, -120]),
                        np.radians([60, 110, -60, 80, 60, 120]), n_setpoints=1001)
    whole = analyze(puma, traj, AnalysisOptions(verify=False, formulations=False)).dataset
    path = tmp_path / "results.h5"
    streamed = analyze_to_file(puma, traj, path, AnalysisOptions(verify=True), chunk=97)   # 11 uneven chunks
    assert streamed.verification["passed"] == 1
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        for name in ("t", "q", "D_tran", "D_rot", "D", "h_tran", "h_rot", "h", "c", "tau",
                     "tau_simplified", "share_tran", "peak_total", "tau_error_rms",
                     "other_rule_error_relative_peak"):
            np.testing.assert_allclose(ds[name].values, whole[name].values, rtol=1e-12,
                                       atol=1e-15, err_msg=name)
            assert ds[name].attrs["units"] == whole[name].attrs["units"]
        assert list(ds.dominance.values) == list(whole.dominance.values)
        assert list(ds.choice.values) == list(whole.choice.values)
        assert ds.sizes["t"] == 1001
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


def test_verification_stores_the_measured_differences(puma):
    """Results.h5 stored the verification errors as exactly 0.0 (the differences
    past the round-off floor). The stored value is the true largest difference against
    Pinocchio's crba, relative to sqrt(D_ii D_jj); the excess past the floor is stored apart."""
    import pinocchio as pin

    from gd_analyze import gd_terms
    from gd_analyze.dynamics.pinocchio import pinocchio_model

    traj = read_trajectory(SHIPPED, 6)
    t = gd_terms(puma, traj.q, traj.qd)
    result = verify(puma, traj.q, traj.qd, t, qdd=traj.qdd)
    model = pinocchio_model(puma)
    data = model.createData()
    crba = []
    for q in traj.q:
        M = pin.crba(model, data, q).copy()
        crba.append(np.triu(M) + np.triu(M, 1).T)
    crba = np.array(crba)
    diag = np.abs(np.diagonal(crba, axis1=1, axis2=2))
    scale = np.max(np.sqrt(diag[:, :, None] * diag[:, None, :]), axis=0)
    oracle = np.max(np.max(np.abs(t.D - crba), axis=0) / scale)
    assert 0 < result["max_rel_error_D"] < 1e-12
    np.testing.assert_allclose(result["max_rel_error_D"], oracle, rtol=1e-6)
    assert result["max_rel_excess_D"] == 0 and result["passed"] == 1


def test_progress_bar_on_request_and_silent_otherwise(tmp_path, puma, capsys, monkeypatch):
    import gd_analyze.jobs.analyze as pipeline

    traj = read_trajectory(SHIPPED, 6)
    monkeypatch.setattr(pipeline, "PROGRESS_DELAY", 0.0)
    # both passes run and report whatever model is built on the ranking: ranked only
    ranked = AnalysisOptions(verify=False, formulations=False, simplify=None)
    analyze_to_file(puma, traj, tmp_path / "a.h5", ranked, progress=True, chunk=8)
    err = capsys.readouterr().err
    # it counts set points, not passes: each pass restarts at 0 of the 31 set points
    assert "set points/s" in err and "/31" in err and "/62" not in err
    assert "G-D terms" in err and "simplified model" in err
    analyze_to_file(puma, traj, tmp_path / "b.h5", ranked, progress=False, chunk=8)
    assert capsys.readouterr().err == ""


class _CountingEngine:
    """Wraps the G-D kernel and counts the trajectory's set points it is asked for (rows of q
    equal to one of the trajectory's positions, once per time asked); attribute access (e.g.
    the kernel's ``py_func``) passes through. States of other positions are not counted: the
    derivation cache's self-check evaluates the engine at check states of its own."""

    def __init__(self, fn, q_arg, positions):
        self.fn, self.q_arg, self.setpoints = fn, q_arg, 0
        self.positions = {np.ascontiguousarray(p, float).tobytes()
                          for p in np.asarray(positions, float)}
        assert len(self.positions) == len(positions)         # each set point its own

    def __call__(self, *args, **kwargs):
        q = np.asarray(args[self.q_arg], float)
        self.setpoints += sum(np.ascontiguousarray(p).tobytes() in self.positions
                              for p in q.reshape(-1, q.shape[-1]))
        return self.fn(*args, **kwargs)

    def __getattr__(self, name):
        return getattr(self.fn, name)


def _count_gd(monkeypatch, positions):
    """The G-D engine, counting the set points of the trajectory of ``positions`` (N, n)."""
    from gd_analyze.dynamics import kernels

    compiled = _CountingEngine(kernels.gd_kernel, 0, positions)     # gd_kernel(q, qd, ...)
    monkeypatch.setattr(kernels, "gd_kernel", compiled)
    return lambda: compiled.setpoints


def test_the_main_job_computes_the_terms_once_per_setpoint(tmp_path, monkeypatch, capsys):
    """Ranking, verification, simplified-model error and the formulations' agreement
    all read the one set of G-D terms; the command computes each set point's terms once."""
    from gd_analyze.cli import main

    counted = _count_gd(monkeypatch, read_trajectory(SHIPPED, n_joints=6).q)
    assert main(["puma560", str(SHIPPED), "-o", str(tmp_path / "out"), "--no-report",
                 "-q"]) == 0
    assert counted() == read_trajectory(SHIPPED, n_joints=6).q.shape[0] == 31


def test_streaming_in_chunks_still_computes_the_terms_once(tmp_path, monkeypatch, puma):
    traj = read_trajectory(SHIPPED, n_joints=6)
    counted = _count_gd(monkeypatch, traj.q)
    result = analyze_to_file(puma, traj, tmp_path / "r.h5", chunk=7)     # 5 chunks
    assert result.verification["passed"] == 1
    assert counted() == 31
    counted_mem = _count_gd(monkeypatch, traj.q)
    analyze(puma, traj, AnalysisOptions(formulations=True))
    assert counted_mem() == 31


def test_a_long_arm_streams_in_chunks_of_a_seven_joint_arm_s_size(tmp_path, monkeypatch, puma):
    """The streamed pass's chunks hold as many D entries per array as a 7-joint arm's
    (STREAM_CHUNK set points of n^2 entries): a 15-joint arm's chunk held 65,536 set points,
    113 MB an array, and its 10^6 set points peaked above 2 GiB. The terms are still computed
    once per set point, and the 6-joint PUMA keeps its chunks of STREAM_CHUNK set points."""
    from model.test_chain import random_chain_spec

    from gd_analyze.dynamics import kernels
    from gd_analyze.jobs.analyze import CHUNK_JOINTS, STREAM_CHUNK
    from gd_analyze.model.robot_spec import robot_from_chain

    robot = robot_from_chain("chain15", random_chain_spec(15, 4), [0.0, 0.0, -9.81],
                             source="<test>")
    sizes = []

    def engine(q, *rest):
        sizes.append(q.shape[0])
        return compiled(q, *rest)
    compiled = kernels.gd_kernel
    monkeypatch.setattr(kernels, "gd_kernel", engine)
    rng = np.random.default_rng(0)
    N = 30_000
    traj = trajectory_from_arrays(np.arange(N) * 1e-3, *(rng.uniform(-1, 1, (N, 15))
                                                         for _ in range(3)), n_joints=15)
    analyze_to_file(robot, traj, tmp_path / "r.h5",
                    AnalysisOptions(verify=False, formulations=False, simplify=None))
    assert sum(sizes) == N and len(sizes) > 1
    assert max(sizes) * 15 ** 2 <= STREAM_CHUNK * CHUNK_JOINTS ** 2
    sizes.clear()
    traj = trajectory_from_arrays(np.arange(N) * 1e-3, *(rng.uniform(-1, 1, (N, 6))
                                                         for _ in range(3)), n_joints=6)
    analyze_to_file(puma, traj, tmp_path / "p.h5",
                    AnalysisOptions(verify=False, formulations=False, simplify=None))
    assert sizes == [N] and N <= STREAM_CHUNK


def test_the_count_can_fail(monkeypatch, puma):
    traj = read_trajectory(SHIPPED, n_joints=6)
    counted = _count_gd(monkeypatch, traj.q)
    verify(puma, traj.q, traj.qd)            # without terms, verify computes its own
    assert counted() == 31


@pytest.mark.slow
def test_the_main_job_s_memory_is_flat_in_the_set_points(tmp_path, puma):
    """analyze_to_file streams everything to the file in chunks (the G-D terms, verification,
    ranking, the simplified model's D_s check, ladder and error, results.h5): its largest
    allocation for 10^5 set points is less than twice that for 10^4, both beyond the chunk
    (the D_s check and the ladder held (N, n, n) and (N, n) arrays at once).

    The model is pruned on the trajectory (``guarantee="trajectory"``: its bounds are the
    trajectory's peaks, gathered in the same chunks): the region model's search and proofs
    do not depend on N, and their allocations (about 160 MB, against 26 MB for the rest)
    would hide a leak of the terms of 10^5 set points (144 MB) under the factor 2."""
    import tracemalloc

    def planned(N):
        return plan_quintic(puma, np.radians([-60, 20, -150, -80, -60, -120]),
                            np.radians([60, 110, -60, 80, 60, 120]), n_setpoints=N)

    options = AnalysisOptions(simplify=SimplifyOptions(guarantee="trajectory"))
    analyze_to_file(puma, planned(500), tmp_path / "warm.h5", options,
                    chunk=4096)   # caches, imports
    peaks = []
    for N in (10_000, 100_000):
        traj = planned(N)
        tracemalloc.start()
        analyze_to_file(puma, traj, tmp_path / f"r{N}.h5", options, chunk=4096)
        peaks.append(tracemalloc.get_traced_memory()[1])
        tracemalloc.stop()
    assert peaks[1] < 2 * peaks[0], peaks
    with xr.open_dataset(tmp_path / "r100000.h5", engine="h5netcdf") as ds:
        assert ds.sizes["t"] == 100_000 and ds["D"].encoding["chunksizes"][0] == 4096


def test_the_chapters_own_model_is_measured_on_its_puma_only(shipped_dataset, puma, shipped):
    """The stored error of the chapter's own simplified model (its classes of Figs.
    3.10-3.11): peak |tau_s - tau| / peak |tau| per joint, tau_s from Pinocchio's half-models
    reduced to the chapter's parts, tau from rnea (oracle). Another arm stores none."""
    import pinocchio as pin

    from gd_analyze.dynamics.pinocchio import pinocchio_model, reference_terms
    from gd_analyze.ranking.ranking import CHAPTER_DOMINANCE

    ds = shipped_dataset("puma560")
    ref = reference_terms(puma, shipped.q, shipped.qd)
    keep = {"translational": (1.0, 0.0), "rotational": (0.0, 1.0), "both": (1.0, 1.0)}
    D_s = np.zeros_like(ref.D_tran)
    h_s = ref.c.copy()
    for label, cls in CHAPTER_DOMINANCE.items():
        t, r = keep[cls]
        i = int(label[1]) - 1
        if label[0] == "h":
            h_s[:, i] += t * ref.h_tran[:, i] + r * ref.h_rot[:, i]
        else:
            j = int(label[2]) - 1
            D_s[:, i, j] = D_s[:, j, i] = t * ref.D_tran[:, i, j] + r * ref.D_rot[:, i, j]
    tau_s = np.einsum("kij,kj->ki", D_s, shipped.qdd) + h_s
    model = pinocchio_model(puma)
    data = model.createData()
    tau = np.array([pin.rnea(model, data, a, b, c)
                    for a, b, c in zip(shipped.q, shipped.qd, shipped.qdd)])
    want = np.abs(tau_s - tau).max(axis=0) / np.abs(tau).max(axis=0)
    got = ds["chapter_model_error_relative_peak"].values
    assert np.all(np.isfinite(got))
    np.testing.assert_allclose(got, want, rtol=1e-8, atol=1e-10)
    assert want.max() > 0.01                  # the chapter's model does drop real parts
    assert "chapter_model_error_relative_peak" not in shipped_dataset("ur5").variables


def test_an_arm_without_mass_and_inertia_is_refused(tmp_path, capsys):
    """A robot file whose links all have zero mass and zero inertia (every mass and inertia 0
    in TOML, a URDF without any <inertial>) ran the whole main job to a ranking of zeros:
    now one line naming the file, exit 2, no output folder; the Python API raises the same."""
    from gd_analyze import InputError, load_robot
    from gd_analyze.cli import main

    text = (ROOT / "src" / "gd_analyze" / "data" / "two-link.toml").read_text()
    toml = tmp_path / "zero.toml"
    toml.write_text(text.replace("mass = 1.0", "mass = 0.0").replace(
        "inertia = [0.0, 0.08333333333333333, 0.08333333333333333]", "inertia = [0.0, 0.0, 0.0]"))
    joints = "".join(
        f'<link name="l{i}"/><joint name="j{i}" type="revolute"><parent link="l{i - 1}"/>'
        f'<child link="l{i}"/><origin xyz="0.2 0 0" rpy="0 {0.3 * i} 0"/><axis xyz="0 0 1"/>'
        '<limit lower="-2" upper="2" effort="10" velocity="2"/></joint>' for i in (1, 2))
    urdf = tmp_path / "zero.urdf"
    urdf.write_text(f'<robot name="zero"><link name="l0"/>{joints}</robot>')
    t = np.linspace(0.0, 1.0, 11)
    csv = tmp_path / "two.csv"
    csv.write_text("t,q1,q2\n" + "".join(f"{a},{0.3 * a},{-0.2 * a}\n" for a in t))
    for robot in (toml, urdf):
        assert not load_robot(str(robot)).mass.any()
        out = tmp_path / f"out-{robot.suffix[1:]}"
        assert main([str(robot), str(csv), "-o", str(out), "-q"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert err == [f"gd-analyze: error: {robot}: every link has zero mass and inertia: "
                       "no dynamics"]
        assert not out.exists()
        with pytest.raises(InputError, match="every link has zero mass and inertia"):
            analyze(load_robot(str(robot)), read_trajectory(csv, n_joints=2))


def test_a_continuous_joint_wrapped_at_pi_is_analysed_unwrapped(tmp_path):
    """A continuous joint (a robot file without position limits) logged within [-pi, pi), as
    ROS joint_states holds it, its file with positions only: the spline took each 2 pi jump for
    motion, and D qdd + h + c was garbage there, silently. Now the positions are unwrapped
    first, with one warning naming the file, the row and the column; oracle: Pinocchio's rnea
    on the unwrapped positions and their own not-a-knot spline's qd and qdd."""
    import pinocchio as pin
    from robot_files import toml_without_limits
    from scipy.interpolate import CubicSpline

    import gd_analyze as gd
    from gd_analyze.dynamics.pinocchio import pinocchio_model
    from gd_analyze.errors import InputWarning

    robot = gd.load_robot(str(toml_without_limits(tmp_path)))      # both joints turn freely
    t = np.linspace(0.0, 2.0, 81)
    q = np.column_stack([np.pi + 1.2 * np.sin(np.pi * t), 0.5 * np.cos(t)])
    wrapped = q.copy()
    wrapped[:, 0] = (q[:, 0] + np.pi) % (2 * np.pi) - np.pi
    assert (np.abs(np.diff(wrapped[:, 0])) > np.pi).sum() >= 2
    path = tmp_path / "traj.csv"
    path.write_text("t,q1,q2\n" + "".join(f"{s!r},{a!r},{b!r}\n" for s, (a, b) in
                                          zip(t.tolist(), wrapped.tolist())))
    with pytest.warns(InputWarning) as caught:
        ds = gd.analyze(robot, str(path), AnalysisOptions(simplify=None, formulations=False))
    lines = [str(w.message) for w in caught if "wrapped at +-pi" in str(w.message)]
    steps = np.diff(wrapped[:, 0])
    k = int(np.flatnonzero(np.abs(steps) > np.pi)[0])      # set point k + 1: file row k + 3
    assert lines == [f"{path}: row {k + 3}, column q1: joint 1's positions step by "
                     f"{abs(steps[k]):.2g} rad "
                     f"(wrapped at +-pi, a continuous joint's log?): unwrapped before the cubic "
                     f"spline gives qd and qdd"], lines
    spline = CubicSpline(t, q, axis=0, bc_type="not-a-knot")
    model = pinocchio_model(robot)
    data = model.createData()
    tau = np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, spline(t, 1),
                                                                        spline(t, 2))])
    got = np.einsum("kij,kj->ki", ds.D.values, ds.qdd.values) + ds.h.values + ds.c.values
    np.testing.assert_allclose(got, tau, rtol=0, atol=1e-9 * np.abs(tau).max())
    assert ds.attrs["derivatives"] == "cubic-spline"
    # the streamed entry point alike, from the trajectory as read
    with pytest.warns(InputWarning, match="wrapped at"):
        streamed = analyze_to_file(robot, read_trajectory(path), tmp_path / "r.h5",
                                   AnalysisOptions(simplify=None, formulations=False)).dataset
    got = (np.einsum("kij,kj->ki", streamed.D.values, streamed.qdd.values)
           + streamed.h.values + streamed.c.values)
    np.testing.assert_allclose(got, tau, rtol=0, atol=1e-9 * np.abs(tau).max())
