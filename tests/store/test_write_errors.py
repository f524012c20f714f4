"""A full disk or an HDF5 error while writing is one line (exit 2); a bug is not."""

import errno
import os
import subprocess
import sys

import pytest
from conftest import SHIPPED as SHIPPED_PUMA

from gd_analyze.cli import main
from gd_analyze.errors import InputError
from gd_analyze.store.staging import writing


def _close_after_enospc():
    """What h5py's close raises after a write failed with ENOSPC: another error, chained."""
    try:
        raise OSError(errno.ENOSPC, "No space left on device")
    except OSError:
        raise AttributeError("'FileIO' object has no attribute 'truncate'") from None


def _close_after_enospc_in_context():
    try:
        raise OSError(errno.ENOSPC, "No space left on device")
    except OSError:
        raise AttributeError("flush failed")      # noqa: B904 - the context is the point


def _in_h5py():
    exec(compile("raise RuntimeError(\"Can't decrement id ref count\")",
                 "/site-packages/h5py/_hl/files.py", "exec"))


@pytest.mark.parametrize("fail, expect", [
    (_close_after_enospc_in_context, "out: cannot write the output folder: no space left on the "
                                     "device"),
    (_in_h5py, "out: cannot write the output folder: HDF5 error: Can't decrement id ref count")])
def test_write_failures_are_one_line(fail, expect):
    with pytest.raises(InputError) as err:
        with writing("out"):
            fail()
    assert str(err.value) == expect


@pytest.mark.parametrize("error", [RuntimeError("a bug"), ValueError("a bug"),
                                   KeyError("a bug")])
def test_other_errors_are_not_write_errors(error):
    with pytest.raises(type(error)):
        with writing("out"):
            raise error


def test_an_enospc_under_raise_from_none_is_still_found():
    """``raise ... from None`` keeps the context for the traceback: it is still found."""
    with pytest.raises(InputError, match="no space left on the device"):
        with writing("out"):
            _close_after_enospc()


#: A child that runs the main job in process onto a file size limit (EFBIG: h5py's native driver
#: meets it as it would a full disk) and leaves without the interpreter's teardown, in which
#: HDF5 flushes the objects the failed write could not close (a SIGSEGV of its own).
_LIMITED = """
import os, resource, signal, sys
import gd_analyze.jobs.run
from gd_analyze.cli import main
gd_analyze.jobs.run.check_free_space = lambda *args: None   # past the check of the limit
signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
resource.setrlimit(resource.RLIMIT_FSIZE, (40_000, resource.RLIM_INFINITY))
code = main(sys.argv[1:])
sys.stderr.flush()
os._exit(code)
"""


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="RLIMIT_FSIZE, SIGXFSZ")
def test_hdf5_meeting_a_file_size_limit_is_one_line(tmp_path):
    """results.h5 written by HDF5 itself onto a limit: h5py's finalizers printed a traceback
    each (Cython prints them before reporting them as ignored), the message was HDF5's report."""
    csv = tmp_path / "plan.csv"
    assert main(["plan", "two-link", "-o", str(csv)]) == 0
    out = tmp_path / "out"
    run = subprocess.run([sys.executable, "-c", _LIMITED, "two-link", str(csv), "-o", str(out),
                          "-q", "--no-report"], cwd=tmp_path, capture_output=True, text=True,
                         env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)),
                         timeout=300)
    assert run.returncode == 2, run.stderr[-2000:]
    assert run.stderr == f"gd-analyze: error: {out}: cannot write the output folder: file too " \
                         "large\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["plan.csv", "plan.provenance.json"]


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="RLIMIT_FSIZE, SIGXFSZ")
@pytest.mark.parametrize("limit", [40_000, 200_000])
def test_the_console_script_refuses_a_file_size_limit_below_its_results(tmp_path, limit):
    """Under ``ulimit -f`` below results.h5's estimate and the margin the job stops before
    writing, one line, exit 2: cut short by the limit, HDF5 can end the process by a SIGSEGV
    inside h5netcdf's clean-up (at 200 kB) or at its own shutdown (at 40 kB)."""
    import resource

    out = tmp_path / "out"
    run = subprocess.run([sys.executable, "-m", "gd_analyze.cli", "puma560",
                          str(SHIPPED_PUMA), "-o", str(out), "-q", "--no-report"],
                         cwd=tmp_path, capture_output=True, text=True, timeout=300,
                         env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)),
                         preexec_fn=lambda: resource.setrlimit(
                             resource.RLIMIT_FSIZE, (limit, resource.RLIM_INFINITY)))
    assert run.returncode == 2, run.stderr[-2000:]
    lines = run.stderr.splitlines()
    assert len(lines) == 1 and "the file size limit (ulimit -f)" in lines[0], run.stderr
    assert list(tmp_path.iterdir()) == []


def test_a_full_disk_at_the_lock_file_is_one_line(tmp_path, monkeypatch, capsys):
    """The disk fills as the run writes its process id into the lock file, before the run's
    own writes: exit 2 and one line (it was exit 4, an internal error), nothing left."""
    csv = tmp_path / "plan.csv"
    assert main(["plan", "two-link", "-o", str(csv)]) == 0
    write = os.write

    def full(fd, data):
        if data == f"{os.getpid()}\n".encode():
            raise OSError(errno.ENOSPC, "No space left on device")
        return write(fd, data)

    monkeypatch.setattr(os, "write", full)
    capsys.readouterr()
    code = main(["two-link", str(csv), "-o", str(tmp_path / "out"), "-q", "--no-report"])
    err = capsys.readouterr().err
    assert code == 2, err
    assert err == f"gd-analyze: error: {tmp_path / 'out'}: cannot write the output folder: no " \
                  "space left on the device\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["plan.csv", "plan.provenance.json"]
