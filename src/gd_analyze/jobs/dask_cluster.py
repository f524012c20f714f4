"""The dask.distributed cluster of a sweep, its child interpreters kept off the current folder.

:func:`dask_client` connects to a running scheduler or starts a LocalCluster (one process and
one thread per worker, no dashboard, no statistical profiler) on which
:func:`gd_analyze.jobs.sweep.run_sweep` and
:func:`gd_analyze.jobs.payload.sweep_payloads` run their tasks. The interpreters that
multiprocessing starts for the LocalCluster (workers, resource tracker) would put the current
folder first on their ``sys.path``; ``PYTHONSAFEPATH`` and :func:`_working_folder` keep
it off, so that a ``pickle.py`` where the sweep starts cannot run in them. On Linux the
workers are forked, not spawned (:func:`dask_client`): they start without importing
anything again.
"""

from __future__ import annotations

import concurrent.futures
import contextlib
import logging
import os
import signal
import sys
import tempfile
import warnings
from collections.abc import Iterator
from typing import Any

from ..errors import InputError
from ..store.signals import SIGNALS

__all__ = ["dask_client", "check_scheduler", "cluster_failures", "ClusterLost",
           "HANDSHAKE_TIMEOUT", "TASK_RETRIES"]

#: Times a task is run again after it failed (``retries=`` of ``Client.submit``); a task whose
#: worker was lost is run again on the workers that remain by the scheduler itself (up to its
#: ``distributed.scheduler.allowed-failures``, 3).
TASK_RETRIES = 3


class ClusterLost(InputError):
    """The dask cluster failed under a sweep: its scheduler went away, or its workers were
    lost more often than the scheduler allows. An operational failure, not a bug: the command
    line prints it on one line and exits 2.

    Parameters
    ----------
    message : str
        What failed, in one line.
    path : str, optional
        Where: the scheduler's address, or how the cluster was started.
    row, column : None
        As :class:`~gd_analyze.errors.InputError` (a cluster has neither).
    """


@contextlib.contextmanager
def cluster_failures(where: str) -> Iterator[None]:
    """Turn the dask cluster's failures inside the block into one :class:`ClusterLost`.

    Parameters
    ----------
    where : str
        The scheduler's address (or how the cluster was started), for the message.

    Raises
    ------
    ClusterLost
        For a closed connection to the scheduler or a worker (``OSError``, of which
        ``distributed.comm.CommClosedError`` and ``TimeoutError``), futures cancelled when the
        scheduler went away (``concurrent.futures.CancelledError``), and a task whose workers
        died too often (``distributed.KilledWorker``). Other errors, those of the tasks' own
        code, pass unchanged.
    """
    from distributed import KilledWorker

    try:
        yield
    except KilledWorker as exc:
        raise ClusterLost(f"the dask workers running a task were lost too often "
                          f"({' '.join(str(exc).split())[:160]})", where) from None
    except concurrent.futures.CancelledError:
        raise ClusterLost("the dask scheduler went away during the sweep (its tasks were "
                          "cancelled)", where) from None
    except OSError as exc:
        text = " ".join(str(exc).split())[:160] or type(exc).__name__
        raise ClusterLost(f"lost the connection to the dask cluster during the sweep "
                          f"({type(exc).__name__}: {text})", where) from None

#: Seconds a scheduler at ``--scheduler`` has to answer the connection's handshake: a server
#: that accepts and stays silent is refused after it, not waited for.
HANDSHAKE_TIMEOUT = 10.0
#: Seconds the client and the local cluster have to close after an interruption or an error.
CLOSE_TIMEOUT = 2.0

#: Scheduler options of the local cluster: no dashboard, and its small HTTP server (health
#: checks) on a free loopback port rather than the shared default 8787.
_NO_DASHBOARD = {"dashboard": False, "dashboard_address": "127.0.0.1:0"}


def check_scheduler(address: str, timeout: float = HANDSHAKE_TIMEOUT) -> None:
    """Check that a dask scheduler answers at an address: its comm handshake, within a time.

    Parameters
    ----------
    address : str
        E.g. ``"tcp://10.0.0.5:8786"``.
    timeout : float, optional
        Seconds for the connection and the handshake together (default
        :data:`HANDSHAKE_TIMEOUT`).

    Raises
    ------
    ConnectionError
        One line: nothing answers, the server stays silent, or what answers is not a dask
        scheduler (its bytes are not dask's handshake, e.g. an HTTP server whose reply would
        read as a frame of exbibytes).

    Notes
    -----
    ``distributed.Client(address, timeout=...)`` bounds the TCP connection only; its
    handshake waits as long as the server keeps the connection open.
    """
    import asyncio

    from distributed.comm import connect

    async def probe():
        # reads the handshake; gives up connecting before the whole check's time is out, so
        # that an address where nothing accepts is said to be one, not a silent server
        comm = await connect(address, timeout=0.9 * timeout)
        await comm.close()

    try:
        asyncio.run(asyncio.wait_for(probe(), timeout))
    except asyncio.TimeoutError:
        raise ConnectionError(f"no dask scheduler answered within {timeout:g} s (the server "
                              "accepted the connection and stayed silent)") from None
    except OSError as exc:
        raise ConnectionError(" ".join(str(exc).split())[:200]) from None
    except Exception as exc:  # noqa: BLE001 - any answer that is not dask's handshake
        raise ConnectionError(f"what answered is not a dask scheduler ({type(exc).__name__}: "
                              f"{' '.join(str(exc).split())[:120]})") from None


@contextlib.contextmanager
def dask_client(scheduler: str | None = None, n_workers: int | None = None,
                timeout: float = HANDSHAKE_TIMEOUT) -> Iterator[tuple[Any, str]]:
    """A dask.distributed client: connected to ``scheduler``, or on a new LocalCluster.

    Parameters
    ----------
    scheduler : str, optional
        Address of a running scheduler, e.g. ``"tcp://10.0.0.5:8786"``.
    n_workers : int, optional
        Workers of the LocalCluster started when no scheduler is given (one process and one
        thread each); default ``os.cpu_count() or 2``.
    timeout : float, optional
        Seconds the scheduler has to answer (:func:`check_scheduler`).

    Yields
    ------
    (distributed.Client, str)
        The client and what it runs on, as the provenance says it ("a LocalCluster of 2
        worker processes started by gd-analyze on this machine", "the running scheduler at
        tcp://10.0.0.5:8786"); the client, and a cluster started here, are closed on exit.

    Notes
    -----
    The LocalCluster's processes (workers, multiprocessing's resource tracker) start without
    the current folder on ``sys.path``.

    Raises
    ------
    ImportError
        If dask.distributed is missing from the environment (it is a dependency).
    OSError
        If the scheduler cannot be reached, stays silent or is not a dask scheduler
        (:func:`check_scheduler`: ConnectionError).
    """
    from distributed import Client, LocalCluster

    cluster = None
    with contextlib.ExitStack() as env:
        # dask's own log (the client's tracebacks of a lost connection, the nanny's restart of
        # a lost worker) kept off stderr: a cluster failure is told in one line (ClusterLost);
        # and its advice on a large graph: each task carries its data on purpose (sweep.py).
        # dask's configuration gives the client's logger a level of its own.
        for logger in map(logging.getLogger, ("distributed", "distributed.client")):
            env.callback(logger.setLevel, logger.level)
            logger.setLevel(logging.CRITICAL + 1)
        env.enter_context(warnings.catch_warnings())
        warnings.filterwarnings("ignore", "Sending large graph", UserWarning)
        if scheduler is not None:
            check_scheduler(scheduler, timeout)
            client, how = Client(scheduler, timeout=timeout), f"the running scheduler at {scheduler}"
        else:
            import dask

            workers = int(n_workers) if n_workers else (os.cpu_count() or 2)
            # multiprocessing starts dask's workers and its resource tracker as
            # ``python -c ...``, which puts the current folder first on sys.path and imports
            # pickle, socket and more before the parent's path is restored: a pickle.py where
            # the sweep starts would run in each of them. PYTHONSAFEPATH=1 (Python >= 3.11, a
            # value set already kept) leaves that entry out for the cluster's whole life
            # (workers the nanny restarts too), restored when the stack closes.
            before = os.environ.get("PYTHONSAFEPATH")
            os.environ["PYTHONSAFEPATH"] = before or "1"
            if before is None:
                env.callback(os.environ.pop, "PYTHONSAFEPATH", None)
            else:
                env.callback(os.environ.__setitem__, "PYTHONSAFEPATH", before)
            # On Linux the worker processes are forked, not spawned: a spawned worker is a new
            # interpreter that imports dask, distributed and then this package before its
            # first task (about 1-2 s each, the two in parallel on two cores); a forked one has
            # them already (multiprocessing's fork method, which distributed supports through
            # distributed.worker.multiprocessing-method). The children run no interpreter of
            # their own, so no folder is put on their sys.path; their signal handlers are
            # reset (_default_signals). Elsewhere (macOS, Windows, where fork is unsafe or
            # absent) they are spawned.
            if sys.platform.startswith("linux"):
                _FORKING.append(True)
                env.callback(_FORKING.pop)
                env.enter_context(dask.config.set(
                    {"distributed.worker.multiprocessing-method": "fork"}))
            # The workers' statistical profiler samples every thread's stack every 10 ms while
            # holding the GIL; for these many short numpy calls it costs about 40 % of the
            # time, so the cluster started here runs without it.
            empty = env.enter_context(tempfile.TemporaryDirectory(prefix="gd-analyze-dask-"))
            with dask.config.set({"distributed.worker.profile.enabled": False}), \
                    _working_folder(empty):
                cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                       dashboard_address=None, scheduler_kwargs=_NO_DASHBOARD)
            client = Client(cluster)
            how = (f"a LocalCluster of {workers} worker process{'es' if workers != 1 else ''} "
                   "started by gd-analyze on this machine")
        try:
            yield client, how
        except BaseException:
            # interrupted or failed: close without waiting on the workers' graceful exit (it
            # took 44 s after a SIGTERM); the nanny processes are ended by their cluster. The
            # client, then the cluster, each within CLOSE_TIMEOUT s; their errors give way to
            # the one being raised
            with contextlib.suppress(Exception):
                client.close(timeout=CLOSE_TIMEOUT)
            if cluster is not None:
                with contextlib.suppress(Exception):
                    cluster.close(timeout=CLOSE_TIMEOUT)
            raise
        client.close()
        if cluster is not None:
            cluster.close()


#: One item per LocalCluster of this process whose worker processes are forked
#: (:func:`dask_client`, on Linux).
_FORKING: list = []


def _default_signals():
    """In a child forked while :data:`_FORKING` (a worker process of a LocalCluster started
    here): SIGINT, SIGTERM and SIGHUP handled as in a new interpreter, not by the command
    line's handler (:mod:`gd_analyze.store.signals`) inherited from the parent."""
    if _FORKING:
        for sig in SIGNALS:
            signal.signal(sig, signal.default_int_handler if sig == signal.SIGINT
                          else signal.SIG_DFL)


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_default_signals)


@contextlib.contextmanager
def _working_folder(folder):
    """Run the block in ``folder`` (an empty private one), then return to the current folder.

    The interpreters that multiprocessing starts inside the block (dask's workers and its
    resource tracker, as ``python -c ...``) put their working folder first on ``sys.path``
    before anything else runs; started here, that is an empty folder on every Python version
    (the ``PYTHONSAFEPATH`` :func:`dask_client` sets needs Python >= 3.11). The block only
    starts the cluster: the parent uses no relative path inside it.

    Parameters
    ----------
    folder : str
        An existing folder that lives at least as long as the processes started here.

    Yields
    ------
    None
    """
    with contextlib.ExitStack() as undo:
        back = os.open(".", os.O_RDONLY)
        undo.callback(os.close, back)
        os.chdir(folder)
        undo.callback(os.fchdir, back)
        yield
