"""The output folder of the real commands.

A run never deletes what it did not write; the main job, ``control`` and ``sweep`` share a folder
and each replaces only the files its own manifest lists; the manifests' hashes are checked with
hashlib against the files themselves.
"""

import errno
import hashlib
import io
import json
import os
import shutil
import stat
from pathlib import Path

import numpy as np
import pytest

from gd_analyze import __version__
from gd_analyze.cli import main
from gd_analyze.store.manifest import manifest_name


def _run(args, capsys):
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, out, err


def _tree(folder):
    return {p.relative_to(folder).as_posix(): p.read_bytes()
            for p in sorted(Path(folder).rglob("*")) if p.is_file() or p.is_symlink()}


def _manifest(folder, command):
    return json.loads((Path(folder) / manifest_name(command)).read_text())


def _check_manifest(folder, command):
    """The manifest lists files whose SHA-256 (hashlib) and size match; returns their paths."""
    m = _manifest(folder, command)
    assert m["command"] == command and m["version"] == __version__ and m["tool"] == "gd-analyze"
    for path, entry in m["files"].items():
        data = (Path(folder) / path).read_bytes()
        assert entry["sha256"] == hashlib.sha256(data).hexdigest(), path
        assert entry["size"] == len(data), path
    return set(m["files"])


@pytest.fixture(scope="module")
def main_job(tmp_path_factory):
    """One main job's folder (with its report), run once, copied by each test."""
    base = tmp_path_factory.mktemp("main")
    traj = base / "p.csv"
    assert main(["plan", "two-link", "-o", str(traj), "--start=-60,-30", "--goal=60,30"]) == 0
    assert main(["two-link", str(traj), "-o", str(base / "out"), "-q"]) == 0
    return base


@pytest.fixture
def job(main_job, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    shutil.copy2(main_job / "p.csv", tmp_path / "p.csv")
    shutil.copytree(main_job / "out", tmp_path / "out")        # copy2: same bytes and times
    return tmp_path


@pytest.fixture(scope="module")
def short_plan(main_job, tmp_path_factory):
    """The first 3 set points of :func:`main_job`'s plan, in a folder of its own: a closed
    loop of 0.09 s instead of 1.4 s for the control runs whose writing is what is tested (the
    control dataset still holds the fine grid's 2,001 samples, beyond a full disk's 20 kB)."""
    path = tmp_path_factory.mktemp("short") / "p3.csv"
    path.write_text("".join((main_job / "p.csv").read_text().splitlines(keepends=True)[:4]))
    return path


def test_the_main_jobs_manifest_lists_exactly_its_files(job):
    listed = _check_manifest(job / "out", "analyze")
    files = {k for k in _tree(job / "out") if not k.startswith(".gd-analyze-manifest-")}
    assert listed == files
    assert {"results.h5", "report.html", "simplified_model.json"} <= listed
    assert any(p.startswith("figures/") for p in listed)


@pytest.mark.parametrize("how", ["-o DIR", "--no-report", "-o ."])
def test_case2_a_users_files_are_refused_and_kept(job, capsys, monkeypatch, how):
    user = job / "thesis"
    (user / "figures").mkdir(parents=True)
    (user / "figures" / "thesis_fig1.png").write_bytes(b"\x89PNG the user's figure")
    (user / "report.html").write_text("<p>the user's own report</p>")
    before = _tree(user)
    args = ["two-link", job / "p.csv", "-o", user]
    shown = str(user)
    if how == "--no-report":
        args.append("--no-report")
    if how == "-o .":
        monkeypatch.chdir(user)
        args[-1], shown = ".", "."
    code, _, err = _run(args, capsys)
    assert code == 2, err
    assert err.strip() == (f"gd-analyze: error: {shown} holds files gd-analyze did not write: "
                           "figures/thesis_fig1.png, report.html; use an empty or new folder")
    assert _tree(user) == before
    assert sorted(os.listdir(job)) == ["out", "p.csv", "thesis"]


def test_case2_control_into_a_main_jobs_folder_keeps_the_main_jobs_files(job, short_plan,
                                                                        capsys):
    out = job / "out"
    main_files = {k: v for k, v in _tree(out).items()}
    # the plan's first 3 set points (short_plan): the files control writes do not depend on
    # how long its closed loop runs
    code, _, err = _run(["control", out / "simplified_model.json", short_plan, "-o", out,
                         "-q"], capsys)
    assert code == 0, err
    after = _tree(out)
    assert {k: after[k] for k in main_files} == main_files     # not one byte changed
    control = _check_manifest(out, "control")
    assert {"control.h5", "control_report.html"} <= control
    assert any(p.startswith("figures/") for p in control)
    assert set(after) == set(main_files) | control | {manifest_name("control")}
    # the main job again, without its report: its own report and figures go, control's stay
    code, _, err = _run(["two-link", job / "p.csv", "-o", out, "-q", "--no-report"], capsys)
    assert code == 0, err
    final = _tree(out)
    assert {k: final[k] for k in control} == {k: after[k] for k in control}
    ours = _check_manifest(out, "analyze")
    assert "report.html" not in final and not any(
        p.startswith("figures/fig_3") for p in final)
    assert set(final) == ours | control | {manifest_name("analyze"), manifest_name("control")}


def test_case2_sweep_into_a_main_jobs_folder_keeps_the_main_jobs_files(job, capsys):
    out = job / "out"
    main_files = _tree(out)
    code, _, err = _run(["sweep", "two-link", "--random", "2", "--no-report",
                         "-o", out, "-q"], capsys)
    assert code == 0, err
    after = _tree(out)
    assert {k: after[k] for k in main_files} == main_files
    sweep = _check_manifest(out, "sweep")
    assert {"sweep.h5", "merged_model.json"} <= sweep
    assert set(after) == set(main_files) | sweep | {manifest_name("sweep")}


def test_case7_an_alias_of_a_folder_being_written_is_refused(job, capsys):
    from gd_analyze.store.staging import staged_output

    (job / "alias").symlink_to(job / "out")
    before = _tree(job / "out")
    with staged_output(job / "out"):
        code, _, err = _run(["two-link", job / "p.csv", "-o", job / "alias", "-q"], capsys)
        assert _tree(job / "out") == before
    assert code == 2 and "another run is writing here" in err and err.count("\n") == 1, err


@pytest.mark.parametrize("error, expect", [
    (FileNotFoundError(errno.ENOENT, "No such file or directory", "/nonexistent/font.ttf"),
     "/nonexistent/font.ttf"),
    (OSError(errno.ENOSPC, "No space left on device", "STAGE/results.h5"),
     "cannot write the output folder: no space left on the device")])
def test_case10_only_write_errors_are_write_errors(job, capsys, monkeypatch, error, expect):
    """A read error inside the output stage surfaces as what it is."""
    import gd_analyze.jobs.run as run

    def fail(robot, trajectory, path, *args, **kw):
        if error.filename.startswith("STAGE"):
            error.filename = str(Path(path).parent / "results.h5")
        raise error

    monkeypatch.setattr(run, "analyze_to_file", fail)
    before = _tree(job / "out")
    code, _, err = _run(["two-link", job / "p.csv", "-o", job / "out", "-q"], capsys)
    assert expect in err and err.count("\n") == 1, err
    if "font" in expect:
        assert "cannot write the output folder" not in err and code != 0
    else:
        assert code == 2
    assert _tree(job / "out") == before


def _special(job, kind):
    """A FIFO (never the real /dev), a link to one, or a link to a regular file."""
    os.mkfifo(job / "pipe")
    (job / "file.csv").write_text("the user's\n")
    if kind == "fifo":
        return job / "pipe"
    link = job / "link"
    link.symlink_to(job / ("pipe" if kind == "link_to_fifo" else "file.csv"))
    return link


@pytest.mark.parametrize("kind", ["fifo", "link_to_fifo", "link_to_file"])
@pytest.mark.parametrize("command", ["plan", "main", "control", "sweep"])
def test_an_output_that_is_a_special_file_or_link_is_refused(job, capsys, command,
                                                                     kind):
    """plan -o /dev/null made /dev/null a regular file: only regular files are written; -o
    FILE as a symbolic link is refused too (never written through, never replaced)."""
    out = _special(job, kind)
    args = {"plan": ["plan", "two-link", "-o", out],
            "main": ["two-link", job / "p.csv", "-o", out, "-q"],
            "control": ["control", job / "out" / "simplified_model.json", job / "p.csv", "-o",
                        out, "-q"],
            "sweep": ["sweep", "two-link", job / "p.csv", "-o", out, "-q"]}[command]
    before = sorted(os.listdir(job))
    code, _, err = _run(args, capsys)
    assert code == 2 and err.count("\n") == 1, err
    assert str(out) in err
    assert os.path.islink(out) == (kind != "fifo")
    assert stat.S_ISFIFO(os.stat(job / "pipe").st_mode)
    assert (job / "file.csv").read_text() == "the user's\n"
    assert sorted(os.listdir(job)) == before               # no sidecar, no temporary


class _FullDisk(io.FileIO):
    """A file on a disk that fills after 20 kB (ENOSPC), as h5py's file-object driver sees it."""

    def write(self, data):
        if self.tell() + len(data) > 20_000:
            raise OSError(errno.ENOSPC, "No space left on device")
        return super().write(data)


def _hdf5_error(result, path, settings=None):
    """A RuntimeError raised inside h5py's code, as HDF5's "Can't decrement id ref count"."""
    exec(compile("raise RuntimeError(\"Can't decrement id ref count (unable to flush file)\")",
                 "/site-packages/h5py/_hl/files.py", "exec"))


def _full_disk(result, path, settings=None):
    """The real control dataset written through h5py onto a disk that fills."""
    from gd_analyze.store.control_dataset import control_dataset

    control_dataset(result, settings).to_netcdf(_FullDisk(path, "w+"), engine="h5netcdf")


def _enospc(result, path, settings=None):
    raise OSError(errno.ENOSPC, "No space left on device", str(path))


@pytest.mark.parametrize("writer, expect", [
    (_enospc, "no space left on the device"), (_full_disk, "no space left on the device"),
    (_hdf5_error, "HDF5 error: Can't decrement id ref count")])
@pytest.mark.parametrize("existing", [False, True])
def test_control_on_a_full_disk_is_one_line_and_leaves_nothing(job, short_plan, capsys,
                                                                      monkeypatch, writer, expect,
                                                                      existing):
    """control -o on a nearly full disk segfaulted after 450 lines of h5py tracebacks, leaving
    the lock, the staging folder and a partial control.h5."""
    import gd_analyze.store.control_dataset as control_dataset

    out = job / "out" if existing else job / "new" / "ctl"
    before = _tree(job)
    monkeypatch.setattr(control_dataset, "write_control_dataset", writer)
    code, printed, err = _run(["control", job / "out" / "simplified_model.json", short_plan,
                               "-o", out, "-q"], capsys)
    assert code == 2 and err.count("\n") == 1 and expect in err, err
    assert f"{out}: cannot write the output folder" in err
    assert _tree(job) == before                           # no lock, stage or control.h5
    assert sorted(os.listdir(job)) == ["out", "p.csv"]


@pytest.mark.parametrize("writer", [_hdf5_error, _full_disk])
def test_the_main_job_on_a_full_disk_is_one_line_and_leaves_nothing(job, capsys,
                                                                            monkeypatch, writer):
    import gd_analyze.jobs.run as run

    def analyze_to_file(robot, trajectory, path, *args, **kw):
        if writer is _full_disk:                # any dataset, through h5py onto a full disk
            import xarray as xr

            xr.Dataset({"x": (("t", "j"), np.ones((5000, 6)))}).to_netcdf(
                _FullDisk(path, "w+"), engine="h5netcdf")
        _hdf5_error(None, path)

    monkeypatch.setattr(run, "analyze_to_file", analyze_to_file)
    before = _tree(job)
    code, _, err = _run(["two-link", job / "p.csv", "-o", job / "out", "-q"], capsys)
    assert code == 2 and err.count("\n") == 1 and "cannot write the output folder" in err, err
    assert _tree(job) == before and sorted(os.listdir(job)) == ["out", "p.csv"]


# --- a folder name as long as the file system allows ----------------------------------------------

def test_a_folder_name_as_long_as_the_file_system_allows(tmp_path, capsys):
    """245 characters were refused: the lock and staging names beside the folder add their
    suffixes to its name; they now shorten it (with its SHA-256) where that would not fit.
    One byte beyond the file system's limit is refused with one line."""
    limit = os.pathconf(tmp_path, "PC_NAME_MAX")
    csv = tmp_path / "plan.csv"
    assert main(["plan", "two-link", "-o", str(csv)]) == 0
    for length in (245, limit):
        out = tmp_path / ("f" * length)
        for _ in range(2):                          # a first run, and a rerun that replaces
            assert main(["two-link", str(csv), "-o", str(out), "-q", "--no-report"]) == 0
        assert (out / "results.h5").is_file()
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(".")) == \
        sorted(p.name for p in tmp_path.iterdir() if p.name.endswith(".gd-lock"))
    capsys.readouterr()
    code = main(["two-link", str(csv), "-o", str(tmp_path / ("f" * (limit + 1))), "-q"])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and "longer than the file" in err
