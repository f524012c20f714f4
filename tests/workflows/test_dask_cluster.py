"""workflows/dask_cluster.py: a ``--scheduler`` that is not dask is refused, not waited for
(issue 32). Two tiny servers on 127.0.0.1, each in a thread: one accepts and stays silent, one
answers as an HTTP server does (its first 8 bytes, read as dask's frame count, ask for 3 EiB);
and a real scheduler, which passes."""

import socket
import threading

import pytest

from gd_analyze.cli import main
from gd_analyze.workflows.dask_cluster import HANDSHAKE_TIMEOUT, check_scheduler

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
