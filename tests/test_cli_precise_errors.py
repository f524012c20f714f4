"""Precise errors of the sweep and the provenance's command.

Only the connection to the scheduler is reported as "cannot reach the dask scheduler"; an error
of the sweep itself keeps its own message (bad input: exit 2; a bug: exit 4). The provenance
records the arguments that main() was given, not sys.argv.
"""

import contextlib
import json
import shlex

import pytest

from gd_analyze.cli import main
from gd_analyze.errors import InputError
from gd_analyze.jobs import dask_cluster
from gd_analyze.jobs import sweep as sweep_module


@contextlib.contextmanager
def _no_cluster(scheduler=None, n_workers=None):
    yield None, "no cluster"


def _sweep(tmp_path, capsys):
    code = main(["sweep", "puma560", "--random", "2", "--no-report", "-o", str(tmp_path / "o")])
    return code, capsys.readouterr().err


@pytest.mark.parametrize("raised, code, shown", [
    (ValueError("a bug in the ranking"), 4, "internal error: ValueError: a bug in the ranking"),
    (InputError("trajectory 2 is bad"), 2, "error: trajectory 2 is bad"),
])
def test_an_error_of_the_sweep_is_not_a_scheduler_error(tmp_path, capsys, monkeypatch,
                                                        raised, code, shown):
    def failing(*args, **kwargs):
        raise raised

    monkeypatch.setattr(dask_cluster, "dask_client", _no_cluster)
    monkeypatch.setattr(sweep_module, "run_sweep", failing)
    got, err = _sweep(tmp_path, capsys)
    assert got == code, err
    assert shown in err and "scheduler" not in err and err.count("\n") == 1


def test_an_unreachable_scheduler_is_still_named(tmp_path, capsys, monkeypatch):
    @contextlib.contextmanager
    def refused(scheduler=None, n_workers=None):
        raise OSError("connection refused")
        yield

    monkeypatch.setattr(dask_cluster, "dask_client", refused)
    code = main(["sweep", "puma560", "--random", "2", "--no-report", "--scheduler",
                 "tcp://127.0.0.1:1", "-o", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2 and "cannot reach the dask scheduler: connection refused" in err
    assert "tcp://127.0.0.1:1" in err and err.count("\n") == 1


def test_provenance_records_the_given_arguments_not_sys_argv(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr("sys.argv", ["pytest", "-k", "something else"])
    out = tmp_path / "a plan.csv"
    argv = ["plan", "two-link", "-o", str(out), "--setpoints", "11"]
    assert main(argv) == 0, capsys.readouterr().err
    from gd_analyze.trajectory.planning import provenance_path

    record = json.loads(provenance_path(out).read_text())
    assert record["command"] == shlex.join(["gd-analyze"] + argv)
    assert shlex.split(record["command"])[1:] == argv
