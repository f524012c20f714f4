"""store/signals.py: one handler for SIGINT and SIGTERM, no signal lost.

Each test starts a child interpreter that prints a line when it reaches the phase under test
and waits there; the signal is sent on that line (an event, not a time): inside a gc callback
(distributed's GC diagnosis is one), during the interpreter's shutdown after "wrote", and
during a sweep on its LocalCluster."""

import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
#: A guard against a hang only: every child ends as soon as it has the signal.
HANG = 120


def _start(script, *args):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    return subprocess.Popen([sys.executable, "-c", textwrap.dedent(script), *map(str, args)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env, text=True)


def _wait_for(proc, line):
    for got in proc.stdout:
        if got.strip() == line:
            return
    raise AssertionError(f"the child ended before {line!r}: {proc.stderr.read()}")


GC_CALLBACK = """
    import gc, time
    from gd_analyze.store.signals import install, pending
    install()

    def callback(phase, info):           # as distributed's GC diagnosis: Python code run by gc
        if phase != "start" or info["generation"] != 2:
            return
        print("in gc", flush=True)
        t0 = time.monotonic()
        while time.monotonic() - t0 < 60 and not pending():
            time.sleep(0.001)            # the signal arrives here

    gc.callbacks.append(callback)
    try:
        gc.collect()
        gc.callbacks.remove(callback)
        print("after gc", flush=True)
        while True:
            time.sleep(0.001)
    except KeyboardInterrupt:
        raise SystemExit(130)
    except BaseException as exc:
        raise SystemExit(128 + int(exc.args[0]))
"""


WEAKREF_CALLBACK = """
    import time, weakref
    from gd_analyze.store.signals import install, pending
    install()

    class Thing:
        pass

    def remove(ref):                     # as WeakValueDictionary's: run when a value dies
        print("in callback", flush=True)
        t0 = time.monotonic()
        while time.monotonic() - t0 < 60 and not pending():
            time.sleep(0.001)            # the signal arrives here

    try:
        thing = Thing()
        ref = weakref.ref(thing, remove)
        del thing
        print("after callback", flush=True)
        while True:
            time.sleep(0.001)
    except KeyboardInterrupt:
        raise SystemExit(130)
    except BaseException as exc:
        raise SystemExit(128 + int(exc.args[0]))
"""


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
@pytest.mark.parametrize(("script", "inside"), [(GC_CALLBACK, "in gc"),
                                                (WEAKREF_CALLBACK, "in callback")],
                         ids=["gc", "weakref"])
def test_a_signal_inside_a_callback_is_not_swallowed(script, inside, sig):
    """An exception raised in a gc callback or a weakref callback is reported as ignored
    (sys.unraisablehook): the signal raised there is delivered again, not lost (a SIGINT
    during the 10^6 main job landed in a WeakValueDictionary's callback and the job ran to
    its end)."""
    proc = _start(script)
    _wait_for(proc, inside)
    proc.send_signal(sig)
    code = proc.wait(timeout=HANG)
    err = proc.stderr.read()
    assert code == 128 + sig and "Exception ignored" not in err, err


AFTER_WROTE = """
    import signal, sys, threading
    from gd_analyze import cli

    def shutdown_blocker():              # the interpreter's shutdown waits for this thread
        signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
        threading.main_thread().join()   # returns once the command has returned
        print("shutting down", flush=True)
        threading.Event().wait()

    threading.Thread(target=shutdown_blocker).start()
    sys.argv = ["gd-analyze", "plan", "two-link", "-o", sys.argv[1]]
    cli.run()
"""


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_after_wrote_exits_with_its_status_and_no_traceback(tmp_path, sig):
    proc = _start(AFTER_WROTE, tmp_path / "plan.csv")
    _wait_for(proc, "shutting down")
    # a signal that comes just before the main thread blocks in its join is handled only once
    # the join returns (CPython): send it until the process ends, as a user presses Ctrl-C
    for _ in range(HANG * 10):
        proc.send_signal(sig)
        try:
            code = proc.wait(timeout=0.1)
            break
        except subprocess.TimeoutExpired:
            continue
    err = proc.stderr.read()
    assert code == 128 + sig and "Traceback" not in err and "KeyboardInterrupt" not in err, err
    assert err.strip().splitlines()[-1] == ("gd-analyze: interrupted after the run had finished "
                                            "(its files are complete)")
    assert (tmp_path / "plan.csv").is_file()


SWEEP = """
    import sys
    from gd_analyze import cli
    from gd_analyze.jobs import sweep

    original = sweep.run_sweep

    def announced(*args, **kwargs):
        print("sweeping", flush=True)
        return original(*args, **kwargs)

    sweep.run_sweep = announced
    import gd_analyze.cli.commands as command
    command.run_sweep = announced
    # 20,000 trajectories: minutes of sweeping after "sweeping", which the signal follows at
    # once (planning 100,000 took 5 s before it)
    sys.argv = ["gd-analyze", "sweep", "puma560", "--random", "20000", "--workers", "1",
                "-o", sys.argv[1], "--no-report", "-q"]
    cli.run()
"""


@pytest.mark.slow
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_a_signal_during_a_sweep_ends_it_with_its_status(tmp_path, sig):
    proc = _start(SWEEP, tmp_path / "out")
    _wait_for(proc, "sweeping")
    proc.send_signal(sig)
    code = proc.wait(timeout=HANG)
    err = proc.stderr.read()
    assert code == 128 + sig, err
    assert "Traceback" not in err and err.strip().splitlines()[-1] in (
        "gd-analyze: interrupted", "gd-analyze: terminated"), err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("torn", [False, True])
def test_exit_with_skips_the_teardown_only_after_a_torn_write(torn):
    """exit_with: the status either way; the interpreter's teardown (atexit) only where no
    write was torn (without_teardown), and the output flushed either way."""
    code = textwrap.dedent(f"""
        import atexit, sys
        from gd_analyze.store import signals
        atexit.register(lambda: print("teardown"))
        print("output", end="")
        if {torn}:
            signals.without_teardown()
        signals.exit_with(3)
    """)
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)), timeout=60)
    assert run.returncode == 3, run.stderr
    assert run.stdout == ("output" if torn else "outputteardown\n")
