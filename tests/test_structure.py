"""Every core module has a test module of its own: the tests mirror the
core's concepts, so src/gd_analyze/core/<concept>/<module>.py is tested in
tests/core/<concept>/test_<module>.py."""

import pathlib

import gd_analyze

CORE = pathlib.Path(gd_analyze.__file__).parent / "core"
TESTS = pathlib.Path(__file__).resolve().parent / "core"


def missing_tests(core, tests):
    """The core modules (relative paths) without tests/core/<concept>/test_<module>.py."""
    out = []
    for path in sorted(core.rglob("*.py")):
        if path.name == "__init__.py":
            continue
        rel = path.relative_to(core)
        if not (tests / rel.parent / f"test_{rel.name}").is_file():
            out.append(str(rel))
    return out


def test_every_core_module_has_its_test_module():
    assert len(list(CORE.rglob("*.py"))) > 20          # the scan sees the core
    missing = missing_tests(CORE, TESTS)
    assert not missing, "core modules without a test module: " + ", ".join(missing)


def test_the_check_finds_a_module_without_tests(tmp_path):
    core, tests = tmp_path / "core", tmp_path / "tests"
    for rel in ("model/__init__.py", "model/a.py", "model/b.py", "dynamics/c.py"):
        (core / rel).parent.mkdir(parents=True, exist_ok=True)
        (core / rel).write_text("")
    (tests / "model").mkdir(parents=True)
    (tests / "model" / "test_a.py").write_text("")
    (tests / "test_c.py").write_text("")                 # not in its concept's folder
    assert missing_tests(core, tests) == ["dynamics/c.py", "model/b.py"]
