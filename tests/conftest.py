"""Shared fixtures: the built-in robots, random states, the shipped trajectory."""

import os
import shutil
from pathlib import Path

import numpy as np
import pytest

import gd_analyze
from gd_analyze import load_robot

ROOT = Path(__file__).resolve().parents[1]
SHIPPED = ROOT / "data" / "puma560_trajectory.csv"


@pytest.fixture(scope="session")
def puma():
    return load_robot("puma560")


@pytest.fixture(scope="session")
def two_link():
    return load_robot("two-link")


@pytest.fixture
def one_joint_urdf(tmp_path):
    """A URDF of one revolute joint about a horizontal axis (2 kg link, centre of mass 0.1 m
    along it): D11 is constant and h1 = 0 for any motion."""
    path = tmp_path / "one.urdf"
    path.write_text("""<robot name="one"><link name="base"/>
<link name="l1"><inertial><origin xyz="0 0 0.1"/><mass value="2"/>
<inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
<origin xyz="0 0 0.3"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="50" velocity="2"/>
</joint></robot>""")
    return path


@pytest.fixture(scope="session")
def cluster():
    """A dask LocalCluster of 2 worker processes and its client, for the sweep tests: started
    once a session per xdist worker (its start and its workers' warm-up cost seconds), shared
    by the modules that sweep on it (tests/jobs/test_sweep.py, test_sweep_merged.py,
    test_sweep_budget_region.py, test_dask_cluster.py). Tests must not stop it or its
    workers (a test that kills a worker starts a cluster of its own). The client is not made
    dask's default: a later test of the same xdist worker that writes through xarray would
    otherwise be scheduled on the cluster (test_output_folder.py's full-disk writers failed so
    after the sweep tests, pickling the open file)."""
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None,
                                  scheduler_kwargs={"dashboard_address": "127.0.0.1:0"}) as cl:
        with distributed.Client(cl, set_as_default=False) as client:
            yield cl, client


@pytest.fixture(scope="session")
def mixed(puma, shipped):
    """PUMA 560 trajectories whose joint scales differ by orders of magnitude: fast random
    moves, the shipped trajectory and a slow small move."""
    from gd_analyze.trajectory.planning import plan_quintic, random_trajectories

    slow = plan_quintic(puma, np.radians([0, 45, -90, 0, 30, 0]),
                        np.radians([2, 46, -89, 1, 31, 1]), duration=4.0)
    return [*random_trajectories(puma, 3, seed=11), shipped, slow]


@pytest.fixture(scope="session")
def shipped():
    """The shipped PUMA 560 trajectory (31 set points), read from its CSV file."""
    from gd_analyze.trajectory.trajectory import read_trajectory

    return read_trajectory(SHIPPED, n_joints=6)


def built_once(name, build):
    """A folder that ``build(folder)`` fills once a test session, shared by the xdist workers.

    The folder lies in the session's cache folder (:func:`pytest_configure`), which every
    worker inherits. A worker that asks while another builds it waits on the build's lock (an
    event, not a time) and then uses the finished folder; a failed build leaves no marker, so
    the next worker builds it again. Shared: tests must not modify what is in it.
    """
    import fcntl

    root = Path(os.environ["XDG_CACHE_HOME"]) / "shared-fixtures"
    root.mkdir(exist_ok=True)
    folder, done = root / name, root / f"{name}.done"
    with open(root / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not done.is_file():
            shutil.rmtree(folder, ignore_errors=True)
            folder.mkdir()
            build(folder)
            done.touch()
    return folder


def golden_run(name):
    """The output folder of golden case ``name`` (``golden.freeze.CASES``) and its printed
    text, run once a session (:func:`built_once`), with the folders the text and files may
    name (to be masked): ``([folder, *roots], printed)``, the case's output in
    ``folder / name``. Read by tests/test_golden.py, and by the tests that read the PUMA 560's
    main job without report and what it printed (its golden case). Shared: read only."""
    from golden.freeze import CASES, run_case

    case = CASES[name]
    roots = []
    model_folder = {}
    if case.after:
        after_root, _ = golden_run(case.after)
        roots += after_root
        model_folder[case.after] = after_root[0] / case.after

    def build(folder):
        printed = run_case(case, folder / name, model_folder)
        (folder / "printed.txt").write_text(printed, encoding="utf-8")

    folder = built_once(f"golden-{name}", build)
    return [folder, *roots], (folder / "printed.txt").read_text(encoding="utf-8")


@pytest.fixture(scope="session")
def puma_analysis(puma, shipped):
    """The PUMA 560's analysis of its shipped trajectory in memory, default simplification,
    without verification and formulations (``analyze``'s :class:`Analysis`): once a session
    per xdist worker, for the tests that read its model or dataset. Shared: tests must not
    modify it."""
    from gd_analyze.jobs.analyze import analyze
    from gd_analyze.jobs.options import AnalysisOptions

    return analyze(puma, shipped, AnalysisOptions(verify=False, formulations=False))


@pytest.fixture(scope="session")
def shipped_dataset():
    """The stored dataset of a built-in robot's shipped trajectory, by robot name.

    A function of the name: the main analysis (without the formulations) written by
    ``analyze_to_file`` and read back from its results.h5, loaded; one analysis per robot a
    session (:func:`built_once`). Shared: tests must not modify it. The model is pruned on the
    trajectory (``guarantee="trajectory"``), so that the figures and tables have errors to
    draw on every arm (a region model may drop nothing).
    """
    from gd_analyze.jobs.analyze import analyze_to_file
    from gd_analyze.jobs.options import AnalysisOptions, SimplifyOptions
    from gd_analyze.store.schema import open_results
    from gd_analyze.trajectory.trajectory import read_trajectory

    stored = {}

    def analysed(name, folder):
        robot = load_robot(name)
        traj = read_trajectory(ROOT / "data" / f"{name}_trajectory.csv", robot.n)
        options = AnalysisOptions(formulations=False,
                                  simplify=SimplifyOptions(guarantee="trajectory"))
        analyze_to_file(robot, traj, folder / "results.h5", options)

    def get(name):
        if name not in stored:
            folder = built_once(f"dataset-{name}", lambda f: analysed(name, f))
            with open_results(folder / "results.h5", lazy=True) as ds:
                stored[name] = ds.load()
        return stored[name]
    return get


@pytest.fixture(scope="session")
def shared_main():
    """A main job run by its arguments, built once a session (:func:`built_once`) for every
    test that reads the same run: the same arguments, the same outputs.

    ``shared_main(robot, trajectory, *options)`` runs ``gd-analyze robot trajectory -o
    <folder> *options`` (with its report unless ``--no-report`` is among the options) the
    first time any xdist worker asks for those arguments, and returns its output folder; a
    command's arguments likewise (``shared_main("sweep", robot, *options)``). What the run
    printed is kept beside its folder (:func:`printed_by`), for the tests of the printed
    summary; the command line it records is the one given, without ``-q``. Shared:
    tests must not modify it; a test that writes next to a run writes in its own ``tmp_path``
    (a symbolic link to the run where it needs the run in its folder).
    """
    import contextlib
    import hashlib
    import io

    from gd_analyze.cli import main

    def get(*args):
        args = [str(a) for a in args]
        key = hashlib.sha256("\0".join(args).encode()).hexdigest()[:16]

        def build(folder):
            printed = io.StringIO()
            with contextlib.redirect_stdout(printed):
                code = main([*args, "-o", str(folder / "out")])
            assert code == 0
            (folder / "printed.txt").write_text(printed.getvalue(), encoding="utf-8")
        return built_once(f"main-{key}", build) / "out"
    return get


#: The PUMA 560's main job with a payload sweep and every figure's column twin, no
#: verification (:func:`column_run`).
COLUMN_RUN = ("puma560", SHIPPED, "--payload-sweep", "0:1:0.5", "--no-verify",
              "--column-figures")


def column_run(shared_main):
    """The output folder of :data:`COLUMN_RUN` (:func:`shared_main`), for the tests of the
    column figures (tests/report/test_figure_print.py, test_main_figures.py). Shared: read
    only."""
    return shared_main(*COLUMN_RUN)


def printed_by(run):
    """What the shared run ``run`` (an output folder :func:`shared_main` returned) printed."""
    return (run.parent / "printed.txt").read_text(encoding="utf-8")


@pytest.fixture(scope="session")
def shared_reports():
    """The UR5's main report and the PUMA 560's sweep report, for the report tests that read
    both (tests/report/test_report_review.py, test_report_text.py): built once a session
    (:func:`built_once`).

    ``{"ur5": (folder, "report"), "sweep": (folder, "sweep_report")}``: the main job on the
    UR5's shipped trajectory, and the sweep of the PUMA 560 over its shipped trajectory twice
    (ranked in the command's own process, none held out), each with its report, all
    defaults. Shared: tests must not modify them.
    """
    from gd_analyze.cli import main

    csv = str(SHIPPED)

    def build(tmp):
        assert main(["ur5", str(ROOT / "data" / "ur5_trajectory.csv"), "-o", str(tmp / "ur5"),
                     "-q"]) == 0
        assert main(["sweep", "puma560", csv, csv, "--held-out", "0", "-o",
                     str(tmp / "sweep"), "-q"]) == 0
    tmp = built_once("shared_reports", build)
    return {"ur5": (tmp / "ur5", "report"), "sweep": (tmp / "sweep", "sweep_report")}


@pytest.fixture(scope="session")
def shared_puma(shared_main, shared_control):
    """The PUMA 560's main job on its shipped trajectory and the control command on its model,
    each with its report, all defaults: built once a session (:func:`built_once`) for the
    tests that only read them (tests/report/test_report_review.py, test_report_text.py,
    tests/jobs/test_recursive_ladder.py). The control run is :func:`shared_control`'s of the
    PUMA 560 (the same command on the same model), not a second one. Shared: tests must not
    modify them.

    ``{"puma": (folder, "report"), "control": (folder, "control_report")}``.
    """
    puma = shared_main("puma560", str(SHIPPED))     # the default run (:func:`shared_main`)
    folder, _ = shared_control("puma560")           # its model, linked as folder / "main"
    return {"puma": (puma, "report"), "control": (folder / "control", "control_report")}


@pytest.fixture(scope="session")
def shared_control(shared_main):
    """The control command, with its report, on the model of a built-in robot's default run
    (:func:`shared_main` on its shipped trajectory), all defaults: built once a session
    (:func:`built_once`) for the tests that read it (tests/report/test_sweep_control_tables.py,
    test_units.py). Shared: tests must not modify it.

    ``shared_control(name)`` -> ``(folder, argv)``: ``folder / "main"`` links to the run,
    ``folder / "control"`` holds the control run's output; ``argv`` is its command line as
    given (with ``-q``).
    """
    from gd_analyze.cli import main

    def get(name):
        csv = str(ROOT / "data" / f"{name}_trajectory.csv")
        run = shared_main(name, csv)

        def argv(folder):
            return ["control", str(folder / "main" / "simplified_model.json"), csv,
                    "-o", str(folder / "control"), "-q"]

        def build(folder):
            (folder / "main").symlink_to(run, target_is_directory=True)
            assert main(argv(folder)) == 0
        folder = built_once(f"control-{name}", build)
        return folder, argv(folder)
    return get


def random_boxes(robot, count, width, seed):
    """Random boxes of joint positions (lo, hi), each (count, n): centres uniform within the
    robot's limits (+-pi where it has none), half-widths ``width`` times the limits' range
    times a factor uniform in [0.1, 1]."""
    rng = np.random.default_rng(seed)
    lo_q = np.where(np.isfinite(robot.q_min), robot.q_min, -np.pi)
    hi_q = np.where(np.isfinite(robot.q_max), robot.q_max, np.pi)
    centre = rng.uniform(lo_q, hi_q, (count, robot.n))
    half = width * (hi_q - lo_q) * rng.uniform(0.1, 1.0, (count, robot.n))
    return centre - half, centre + half


def random_states(robot, count, seed):
    """Random (q, qd, qdd), shape (count, n): q within [-pi, pi], qd, qdd within +-3."""
    rng = np.random.default_rng(seed)
    n = robot.n
    return (rng.uniform(-np.pi, np.pi, (count, n)), rng.uniform(-3, 3, (count, n)),
            rng.uniform(-3, 3, (count, n)))


def two_link_control(folder, setpoints):
    """Plan a two-link trajectory of ``setpoints`` set points, build its simplified model
    (main job, no report) and run the control command on it, in ``folder``; the control
    dataset, loaded."""
    import xarray as xr

    from gd_analyze.cli import main

    csv = folder / "two.csv"
    assert main(["plan", "two-link", "-o", str(csv), "--setpoints", str(setpoints)]) == 0
    assert main(["two-link", str(csv), "-o", str(folder / "main"), "-q", "--no-report"]) == 0
    assert main(["control", str(folder / "main" / "simplified_model.json"), str(csv),
                 "-o", str(folder / "control"), "-q"]) == 0
    with xr.open_dataset(folder / "control" / "control.h5") as ds:
        return ds.load()


@pytest.fixture(scope="session")
def shared_two_link_control():
    """:func:`two_link_control`'s runs, each built once a session (:func:`built_once`) for the
    tests that read them (tests/report/test_control_text.py).

    ``shared_two_link_control(setpoints)`` -> ``(folder, dataset)``: the folder of the plan
    (``two.csv``), the main job (``main``) and the control run (``control``), shared: read
    only; the control dataset loaded afresh on each call (a test may change its own copy).
    """
    import xarray as xr

    def get(setpoints):
        folder = built_once(f"two-link-control-{setpoints}",
                            lambda f: two_link_control(f, setpoints))
        with xr.open_dataset(folder / "control" / "control.h5") as ds:
            return folder, ds.load()
    return get


def pytest_configure(config):
    """One derivation cache for the whole test session, shared by the xdist workers.

    The controller (or the only process, without xdist) makes an empty temporary folder and
    points ``XDG_CACHE_HOME`` at it before the workers start, so that every worker and every
    command a test runs in a child process inherits it: the derivation cache
    (``<folder>/gd-analyze``: the explicit models, :mod:`gd_analyze.store.explicit_cache`, and the
    region certifications, :mod:`gd_analyze.store.certification_cache`, each derived once a
    session instead of once a test) lives there, never in the user's own cache, and the folder is removed when the session ends. ``GD_ANALYZE_NO_CACHE`` and
    ``GD_ANALYZE_CACHE_DIR`` are cleared, so a developer's settings do not change the suite.

    Still safe: an entry is a pure function of the robot, the settings and the source of the
    code that computes it (its name is the SHA-256 of that key), written by this session's code,
    atomically (a private temporary name renamed over the entry, so concurrent workers never
    see half a file), and checked before use: its stored key and checksum, then its content
    against an independent computation (the explicit terms against the G-D engine at fixed
    states; a certification's boxes, bounds and scales against the torques at its sampled
    positions). Tests about a cache itself, or that need a cold one, set their own folder
    (``tests/conftest.py``'s ``cache``) or ``GD_ANALYZE_NO_CACHE``. The tests that count the
    G-D engine's set points (``tests/jobs/test_analyze.py``) count only the trajectory's, not
    the states of a cache read's self-check.

    The controller also compiles the package's bytecode once (``compileall``, as pip does for an
    installed package): with ``PYTHONDONTWRITEBYTECODE`` set, every command a test runs in a
    child process (some hundreds) would otherwise compile the package's source again. Before
    xdist workers start, it runs :data:`WARM_UP` too (:func:`warm_up`).
    """
    import compileall
    import tempfile

    if hasattr(config, "workerinput"):          # an xdist worker: the controller's folder
        return
    compileall.compile_dir(Path(gd_analyze.__file__).parent, quiet=2)
    folder = tempfile.mkdtemp(prefix="gd-analyze-tests-")
    config._gd_cache_folder = folder
    os.environ["XDG_CACHE_HOME"] = folder
    for name in ("GD_ANALYZE_NO_CACHE", "GD_ANALYZE_CACHE_DIR"):
        os.environ.pop(name, None)
    if getattr(config.option, "numprocesses", None) and not kernels_cached():
        warm_up(Path(folder))                               # the suite on xdist workers, cold


#: Kernels whose numba cache index tells whether the package's kernels are compiled for this
#: interpreter (:func:`kernels_cached`): the G-D pass's and the region proof's.
KEY_KERNELS = ("dynamics/__pycache__/kernels.gd_kernel-*",
               "certify/__pycache__/ball_kernels.forward_kernel-*",
               "certify/__pycache__/box_kernels.box_forward_kernel-*")


def kernels_cached():
    """Whether numba's cache in the package holds an index of every :data:`KEY_KERNELS` kernel
    for this interpreter (``*.py310.nbi`` for Python 3.10, and so on)."""
    import sys

    tag = f"py{sys.version_info.major}{sys.version_info.minor}.nbi"
    package = Path(gd_analyze.__file__).parent
    return all(any(package.glob(pattern + tag)) for pattern in KEY_KERNELS)


#: The main jobs :func:`warm_up` runs: the PUMA 560's shipped trajectory, its model proved over
#: the region (the dynamics, ranking and region proof's kernels) and on the trajectory (the
#: pruning's peak kernels).
WARM_UP = (("--guarantee", "region"), ("--guarantee", "trajectory"))


def warm_up(folder):
    """Run :data:`WARM_UP` in child processes, one after the other, before xdist's workers start.

    On a fresh clone or a new interpreter (CI: each Python its own), numba's cache in ``src`` is
    empty, and every process that first calls a kernel compiles it: the two workers, the dask
    workers of the sweep tests and the commands run in child processes, many at once, each
    compiling the same kernels until one has written them (on four test modules, 508 s of CPU
    cold, 406 s cold with this warm-up, 251 s warm: docs/performance.md). Run once here, the
    compiles are paid once; the region certification they derive lands in the session's
    derivation cache, where the tests read it. A failing warm-up is not reported here: the tests
    that run the same command fail. Skipped where :func:`kernels_cached`.
    """
    import subprocess
    import sys

    for n, options in enumerate(WARM_UP):
        subprocess.run([sys.executable, "-m", "gd_analyze.cli", "puma560", str(SHIPPED), "-q",
                        "--no-report", "-o", str(folder / f"warm-up-{n}"), *options],
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)


def pytest_unconfigure(config):
    """Remove the session's cache folder (:func:`pytest_configure`)."""

    folder = getattr(config, "_gd_cache_folder", None)
    if folder is not None:
        shutil.rmtree(folder, ignore_errors=True)



#: The module of the longest test (every command on a 10-joint chain with its reports, about
#: 2 min alone on an idle machine): it starts first.
LONGEST = "tests/jobs/test_many_joints.py"


def pytest_collection_modifyitems(config, items):
    """:data:`LONGEST` first, then the modules holding a test marked ``slow``, then the rest;
    each module's tests together and in their order.

    pytest-xdist hands the tests to its workers in this order; a long test collected last
    would otherwise leave one worker alone with it at the end while the other waits. Every test
    still runs.
    """
    slow = {item.path for item in items if item.get_closest_marker("slow")}
    items.sort(key=lambda item: (item.nodeid.split("::")[0] != LONGEST, item.path not in slow))

# the derivation cache's tests
@pytest.fixture
def cache(tmp_path, monkeypatch):
    """An empty derivation cache folder of the test's own, caching enabled."""
    monkeypatch.delenv("GD_ANALYZE_NO_CACHE", raising=False)
    folder = tmp_path / "cache"
    monkeypatch.setenv("GD_ANALYZE_CACHE_DIR", str(folder))
    return folder
