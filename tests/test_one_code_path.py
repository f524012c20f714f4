"""Frozen values stay frozen and the code path is one.

Every module of the package is read with ``ast``: no ``object.__setattr__`` (a frozen
dataclass mutated behind its back), no assignment into an instance's ``__dict__`` (the same by
another door), and none of the speed machinery that changed the code path from run to run: an
early ``os._exit``, a paused garbage collector, a second figure interpreter, writes into
matplotlib's private state.
"""

import ast
import pathlib

import pytest

import gd_analyze

SRC = pathlib.Path(gd_analyze.__file__).parent
MODULES = sorted(SRC.rglob("*.py"))


def _offences(tree):
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            f = node.func
            if (isinstance(f, ast.Attribute) and f.attr == "__setattr__"
                    and isinstance(f.value, ast.Name) and f.value.id == "object"):
                yield node.lineno, "object.__setattr__"
            if isinstance(f, ast.Attribute) and f.attr in ("_exit", "disable", "freeze",
                                                            "set_threshold") and \
                    isinstance(f.value, ast.Name) and f.value.id in ("os", "gc"):
                yield node.lineno, f"{f.value.id}.{f.attr}"
        elif isinstance(node, (ast.Assign, ast.AugAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            for t in targets:
                if (isinstance(t, ast.Subscript) and isinstance(t.value, ast.Attribute)
                        and t.value.attr == "__dict__"):
                    yield node.lineno, "assignment into __dict__"
                if isinstance(t, ast.Attribute) and t.attr == "_character_tracker":
                    yield node.lineno, "matplotlib's private _character_tracker"
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            names = [a.name for a in node.names] + [getattr(node, "module", None) or ""]
            if any("main_worker" in n for n in names):
                yield node.lineno, "the figure worker"


#: The allowed ``os._exit``, in one module: a signal after the command has returned and flushed
#: its output ends the process with 128 + its number (no KeyboardInterrupt traceback after
#: "wrote"); and the status of a command whose HDF5 write failed, once it has returned and
#: flushed its output, skipping only HDF5's flush at shutdown. Neither skips work, so the code
#: path stays one.
#: The one allowed ``gc.freeze()``: the console script's, after the imports, on every run of
#: every command ("gc.freeze() after the imports is allowed ... documented and
#: unconditional"); no other collector setting anywhere.
ALLOWED = {("store/signals.py", "os._exit"), ("cli/__init__.py", "gc.freeze")}


def offences(modules, root=SRC):
    """Every offence of the modules (under ``root``) but the :data:`ALLOWED` ones, as
    ``path:line: what``."""
    out = []
    for path in modules:
        where = path.relative_to(root).as_posix()
        out += [f"{where}:{line}: {what}"
                for line, what in _offences(ast.parse(path.read_text(encoding="utf-8")))
                if (where, what) not in ALLOWED]
    return out


def test_no_mutation_of_frozen_values_and_no_second_code_path():
    """Every module at once, every offence listed (a structural check is one test,
    not one per module)."""
    assert len(MODULES) > 100                       # the scan sees the package
    bad = offences(MODULES)
    assert bad == [], "\n".join(bad)


def test_the_scan_names_the_module_and_honours_the_allowed(tmp_path):
    """:func:`offences` over files: the allowed pair passes only in its own module."""
    for rel, code in (("store/signals.py", "os._exit(1)\n"), ("io/other.py", "os._exit(1)\n"),
                      ("core/ok.py", "x = 1\n")):
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).write_text(code)
    assert offences(sorted(tmp_path.rglob("*.py")), tmp_path) == ["io/other.py:1: os._exit"]


def test_the_check_finds_what_it_looks_for():
    code = ("object.__setattr__(self, 'x', 1)\nout.__dict__['_p'] = p\nos._exit(0)\n"
            "gc.disable()\nf._character_tracker = t\nfrom .main_worker import draw\n"
            "gc.set_threshold(10**6)\ngc.freeze()\n")
    found = [what for _, what in sorted(_offences(ast.parse(code)))]
    assert found == ["object.__setattr__", "assignment into __dict__", "os._exit",
                     "gc.disable", "matplotlib's private _character_tracker", "the figure worker",
                     "gc.set_threshold", "gc.freeze"]


def test_the_console_script_freezes_after_the_main_job_s_imports(tmp_path):
    """``gc.freeze()`` once, unconditional, after the imports: the console script's
    main job has its libraries imported and the start-up objects frozen before the command
    runs; a library call of ``main`` neither imports ahead nor freezes."""
    import json
    import os
    import subprocess
    import sys

    probe = ("import gc, json, sys\nimport gd_analyze.cli as cli\n"
             "seen = {}\n"
             "def main(argv):\n"
             "    seen['frozen'] = gc.get_freeze_count()\n"
             "    seen['loaded'] = [m for m in cli.MAIN_JOB_IMPORTS + cli.REPORT_IMPORTS\n"
             "                      if m in sys.modules]\n"
             "    return 0\n"
             "cli.main = main\nsys.argv = ['gd-analyze'] + sys.argv[1:]\n"
             "try:\n    cli.run()\nexcept SystemExit:\n    pass\nprint(json.dumps(seen))\n")
    env = {**os.environ, "PYTHONPATH": str(SRC.parent), "MPLBACKEND": "Agg"}
    out = {}
    for args in (["puma560", "x.csv"], ["puma560", "x.csv", "--no-report"], ["plan", "x"]):
        done = subprocess.run([sys.executable, "-c", probe, *args], cwd=tmp_path, env=env,
                              capture_output=True, text=True, check=True)
        out[args[-1]] = json.loads(done.stdout)
    from gd_analyze.cli import MAIN_JOB_IMPORTS, REPORT_IMPORTS

    assert out["x.csv"]["frozen"] > 0 and out["x.csv"]["loaded"] == list(
        MAIN_JOB_IMPORTS + REPORT_IMPORTS)
    assert out["--no-report"]["loaded"] == list(MAIN_JOB_IMPORTS)
    assert out["x"]["frozen"] > 0           # every command: frozen after the CLI's imports


@pytest.fixture
def puma_cached(shared_main):
    """The PUMA 560's default run on its shipped trajectory, shared (tests/conftest.py): once
    it ran, the session's derivation cache holds the arm for every run with its arguments."""
    from conftest import SHIPPED

    return shared_main("puma560", SHIPPED)


@pytest.mark.slow
def test_the_console_script_imports_ahead_only_what_the_job_loads_anyway(tmp_path, puma_cached):
    """The libraries imported ahead of the freeze are ones the main job loads itself, with its
    report and with ``--no-report``, once its derivation cache holds the arm: importing
    anything else ahead only adds start-up time (scipy.linalg, 0.07 s, was; Jinja2 was ahead
    of a run without a report). The oracle is ``sys.modules`` after ``main`` ran the job in a
    child that imported nothing ahead: first without its report (none of the report's
    libraries may be loaded then), then, in the same child, with it (a job with its report
    does the same analysis first, so the libraries the first job loaded are its own too)."""
    import json
    import os
    import subprocess
    import sys

    from conftest import SHIPPED

    from gd_analyze.cli import MAIN_JOB_IMPORTS, REPORT_IMPORTS

    # the derivation cache holds the arm (puma_cached: the child's arguments but -o)
    probe = ("import json, sys\nsys.modules['dask'] = None\n"
             "from gd_analyze.cli import main\n"
             "loaded = []\n"
             "for extra in (['--no-report'], []):\n"
             "    out = sys.argv[1] + str(len(loaded))\n"
             "    assert main([*sys.argv[2:], '-o', out, *extra]) == 0\n"
             "    loaded.append(sorted(sys.modules))\n"
             "print(json.dumps(loaded))\n")
    env = {**os.environ, "PYTHONPATH": str(SRC.parent), "MPLBACKEND": "Agg"}
    env.pop("GD_ANALYZE_NO_CACHE", None)
    done = subprocess.run([sys.executable, "-c", probe, str(tmp_path / "out"), "puma560",
                           str(SHIPPED), "-q"], cwd=tmp_path, env=env, capture_output=True,
                          text=True, check=True)
    without, with_report = (set(names) for names in json.loads(done.stdout))
    assert (tmp_path / "out1" / "report.pdf").is_file() and not (tmp_path / "out0").joinpath(
        "report.pdf").exists()
    assert set(MAIN_JOB_IMPORTS) <= without, set(MAIN_JOB_IMPORTS) - without
    assert not set(REPORT_IMPORTS) & without, set(REPORT_IMPORTS) & without
    assert set(MAIN_JOB_IMPORTS + REPORT_IMPORTS) <= with_report, \
        set(MAIN_JOB_IMPORTS + REPORT_IMPORTS) - with_report
