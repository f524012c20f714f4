"""The main job on the shipped 31-set-point trajectory never imports numba: every
kernel it runs (G-D terms, ranking, part peaks, atom peaks, regressor contributions, region
channels, the operation count of the compiled engine) takes its array code for short inputs.

The oracle is ``sys.modules`` of a child interpreter, started in an empty folder with the
package's own source on PYTHONPATH and no on-disk caches (every cache path runs); the same
child then runs one compiled kernel, so the probe is shown to see numba when it is there."""

import os
import pathlib
import subprocess
import sys

import pytest
from conftest import SHIPPED

import gd_analyze

CHILD = """
import sys
from gd_analyze.cli import main

status = main([sys.argv[1], sys.argv[2], "-q", "--no-report", "-o", sys.argv[3]])
print("status", status)
print("numba after the main job", "numba" in sys.modules)
import numpy as np
from gd_analyze import gd_terms, load_robot
gd_terms(load_robot("two-link"), np.zeros((1, 2)), np.zeros((1, 2)), engine="compiled")
print("numba after a compiled kernel", "numba" in sys.modules)
"""


@pytest.mark.slow
def test_the_main_job_on_the_shipped_trajectory_never_imports_numba(tmp_path):
    src = pathlib.Path(gd_analyze.__file__).resolve().parent.parent
    env = {**os.environ, "PYTHONPATH": str(src), "MPLBACKEND": "Agg",
           "GD_ANALYZE_NO_CACHE": "1"}
    done = subprocess.run([sys.executable, "-c", CHILD, "puma560", str(SHIPPED),
                           str(tmp_path / "out")], cwd=tmp_path, env=env, capture_output=True,
                          text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert "status 0" in lines, done.stdout
    assert "numba after the main job False" in lines, done.stdout
    assert "numba after a compiled kernel True" in lines, done.stdout
    assert (tmp_path / "out" / "simplified_model.json").is_file()
