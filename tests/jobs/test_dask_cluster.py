"""jobs/dask_cluster.py: a ``--scheduler`` that is not dask is refused, not waited for.

Two tiny servers on 127.0.0.1, each in a thread: one accepts and stays silent, one answers as
an HTTP server does (its first 8 bytes, read as dask's frame count, ask for 3 EiB); and a real
scheduler, which passes."""

import logging
import os
import socket
import subprocess
import sys
import threading
import time
import warnings

import numpy as np
import pytest
import xarray as xr

from gd_analyze.cli import main
from gd_analyze.jobs.dask_cluster import HANDSHAKE_TIMEOUT, check_scheduler, dask_client

HTTP = b"HTTP/1.1 200 OK\r\nContent-Length: 0\r\n\r\n"


@pytest.fixture
def server():
    """Start a server thread on a free loopback port: ``server(reply)`` sends ``reply`` to
    every connection (nothing: it stays silent) and keeps it open; returns the address."""
    sockets, done = [], threading.Event()

    def start(reply):
        listener = socket.create_server(("127.0.0.1", 0))
        listener.settimeout(0.2)
        sockets.append(listener)

        def serve():
            while not done.is_set():
                try:
                    conn, _ = listener.accept()
                except OSError:
                    continue
                sockets.append(conn)
                if reply:
                    conn.sendall(reply)
        threading.Thread(target=serve, daemon=True).start()
        return f"tcp://127.0.0.1:{listener.getsockname()[1]}"
    yield start
    done.set()
    for s in sockets:
        s.close()


def test_the_handshake_timeout_is_ten_seconds():
    assert HANDSHAKE_TIMEOUT == 10.0


def test_a_silent_server_is_refused_after_the_timeout(server):
    """The same code path with a shorter timeout: the server never answers, so no load makes
    the check pass."""
    with pytest.raises(ConnectionError, match="no dask scheduler answered within 0.5 s"):
        check_scheduler(server(b""), timeout=0.5)


def test_an_address_where_nothing_accepts_is_not_called_a_silent_server(monkeypatch):
    """dask's connect gives up connecting when its timeout runs out (as it does at an address
    where nothing listens, or that no route reaches): that is said, not "the server accepted
    the connection and stayed silent", which a check timed out at the same moment said."""
    import asyncio

    import distributed.comm

    async def nothing_accepts(address, timeout):
        await asyncio.sleep(timeout)
        raise OSError(f"Timed out trying to connect to {address} after {timeout} s")

    monkeypatch.setattr(distributed.comm, "connect", nothing_accepts)
    with pytest.raises(ConnectionError, match="^Timed out trying to connect to tcp://"):
        check_scheduler("tcp://192.0.2.1:9", timeout=0.5)


def test_a_server_that_is_not_dask_is_refused(server):
    with pytest.raises(ConnectionError, match="not a dask scheduler"):
        check_scheduler(server(HTTP * 20))


def test_sweep_at_a_server_that_is_not_dask_exits_2_with_one_line(server, tmp_path, capsys):
    address = server(HTTP * 20)
    code = main(["sweep", "two-link", "--random", "2", "--scheduler", address,
                 "-o", str(tmp_path / "out"), "--no-report", "-q"])
    _, err = capsys.readouterr()
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "not a dask scheduler" in err and "Traceback" not in err
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
def test_a_dask_scheduler_passes(cluster):
    cl, _ = cluster
    check_scheduler(cl.scheduler_address, timeout=HANDSHAKE_TIMEOUT)


@pytest.mark.slow
def test_dask_s_advice_and_log_are_kept_from_the_user(cluster):
    """A task carrying more than 10 MB (as each sweep task carries its trajectories, on
    purpose) and a nanny's restart of a lost worker: dask warns and logs; under the client
    neither reaches a warning handler or a log handler, and the warning filters and log
    levels are as before after it."""
    cl, _ = cluster
    logged = []
    handler = logging.Handler()
    handler.emit = logged.append
    logging.getLogger("distributed").addHandler(handler)
    before = [logging.getLogger(n).level for n in ("distributed", "distributed.client")]
    try:
        with warnings.catch_warnings(record=True) as seen:
            warnings.simplefilter("always")       # the CLI shows what reaches it
            filters = list(warnings.filters)
            with dask_client(cl.scheduler_address) as (client, _):
                assert client.submit(len, np.zeros(2_000_000), pure=False).result() == 2_000_000
                logging.getLogger("distributed.nanny").warning("Restarting worker")
                # dask's configuration gives the client's logger a level of its own
                logging.getLogger("distributed.client").error("Failed to reconnect")
            assert list(warnings.filters) == filters
    finally:
        logging.getLogger("distributed").removeHandler(handler)
    assert [str(w.message) for w in seen] == [] and logged == []
    assert [logging.getLogger(n).level for n in ("distributed", "distributed.client")] == before


def _busy_workers(client):
    """Addresses of the workers running a task now."""
    return client.run_on_scheduler(lambda dask_scheduler: [
        w.address for w in dask_scheduler.workers.values() if w.processing])


def _sweep(address, folder):
    """``gd-analyze sweep`` at ``address`` in a child process (its stderr is the tool's own)."""
    return subprocess.Popen([sys.executable, "-c", "import sys; from gd_analyze.cli import main; "
                             "sys.exit(main(sys.argv[1:]))", "sweep", "two-link", "--random",
                             "600", "--scheduler", address, "-o", str(folder), "--no-report",
                             "-q"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _when_busy(client, sweep, timeout=300):
    """Wait until a worker runs one of the sweep's tasks; its address."""
    end = time.monotonic() + timeout
    while time.monotonic() < end and sweep.poll() is None:
        busy = _busy_workers(client)
        if busy:
            return busy[0]
        time.sleep(0.05)
    raise AssertionError(f"the sweep ran no task: {sweep.communicate()}")


@pytest.mark.slow
def test_a_worker_killed_mid_sweep_its_tasks_run_on_the_other(tmp_path):
    """Two worker processes without a nanny (nothing restarts them): the one running a task is
    killed (SIGKILL); the sweep finishes on the other, every trajectory in its dataset."""
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=0, dashboard_address=None,
                                  scheduler_kwargs={"dashboard_address": "127.0.0.1:0"}) as cl, \
            distributed.Client(cl) as client:
        workers = {}
        for _ in range(2):
            proc = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker",
                                     cl.scheduler_address, "--no-nanny", "--nthreads", "1",
                                     "--no-dashboard"], stdout=subprocess.DEVNULL,
                                    stderr=subprocess.DEVNULL)
            workers[proc.pid] = proc
        try:
            client.wait_for_workers(2, timeout=120)
            pids = client.run(os.getpid)                    # worker address -> process id
            sweep = _sweep(cl.scheduler_address, tmp_path / "out")
            victim = workers[pids[_when_busy(client, sweep)]]
            victim.kill()
            out, err = sweep.communicate(timeout=600)
            assert victim.wait(timeout=30) != 0
        finally:
            for proc in workers.values():
                proc.kill()
                proc.wait(timeout=30)
    assert sweep.returncode == 0, err
    assert "Traceback" not in err
    with xr.open_dataset(tmp_path / "out" / "sweep.h5", engine="h5netcdf") as ds:
        assert ds.sizes["trajectory"] == 600


@pytest.mark.slow
def test_the_scheduler_closed_mid_sweep_is_exit_2_on_one_line(tmp_path):
    distributed = pytest.importorskip("distributed")
    cl = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None,
                                  scheduler_kwargs={"dashboard_address": "127.0.0.1:0"})
    try:
        with distributed.Client(cl) as client:
            sweep = _sweep(cl.scheduler_address, tmp_path / "out")
            _when_busy(client, sweep)
            cl.close()
        out, err = sweep.communicate(timeout=300)
    finally:
        cl.close()
    assert sweep.returncode == 2, err
    assert len(err.splitlines()) == 1, err
    assert err.startswith(f"gd-analyze: error: {cl.scheduler_address}: ") and "dask" in err
    assert not (tmp_path / "out").exists()
