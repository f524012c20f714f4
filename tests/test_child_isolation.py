"""Child interpreters never import from the current folder.

A ``pickle.py`` planted in the folder where ``gd-analyze`` starts appends its process's id to a
marker file (and then hands over to the real pickle, so that a child that imported it still
works). The program is started as its console script is: from a launcher in another folder,
so that only a child interpreter could put the current folder on ``sys.path``. The oracle is
the marker file: it must not exist after a sweep on a local dask cluster.
"""

import os
import subprocess
import sys

import pytest

PLANTED = '''
import os, sys
with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "MARKER"), "a") as f:
    f.write(f"{os.getpid()} {sys.argv!r}\\n")
here = os.path.dirname(os.path.abspath(__file__))
del sys.modules["pickle"]
sys.path[:] = [p for p in sys.path if p not in ("", ".", here)]
import pickle as _real
sys.modules[__name__] = _real
'''


@pytest.fixture
def planted(tmp_path):
    """(folder with pickle.py, command that runs gd-analyze as its console script does)."""
    cwd = tmp_path / "cwd"
    cwd.mkdir()
    (cwd / "pickle.py").write_text(PLANTED)
    launcher = tmp_path / "bin" / "gd-analyze-launcher.py"
    launcher.parent.mkdir()
    launcher.write_text("from gd_analyze.cli import run\n\nif __name__ == '__main__':\n"
                        "    run()\n")
    return cwd, [sys.executable, str(launcher)]


def _run(planted, args, **env):
    cwd, command = planted
    environ = {**os.environ, "MPLBACKEND": "Agg", **env}
    environ.pop("PYTHONSAFEPATH", None)
    done = subprocess.run(command + args, cwd=cwd, env=environ, capture_output=True, text=True,
                          timeout=600)
    marker = cwd / "MARKER"
    return done, marker.read_text() if marker.exists() else ""


@pytest.mark.slow
def test_planted_pickle_does_not_run_in_the_sweeps_dask_workers(planted):
    done, marker = _run(planted, ["sweep", "puma560", "--random", "2", "--workers", "1",
                                  "--no-report", "-o", "out", "-q"])
    assert done.returncode == 0, done.stderr
    assert marker == "", f"pickle.py of the current folder ran in: {marker}"
    assert (planted[0] / "out" / "sweep.h5").is_file()
