"""Every domain module has a test module of its own: the tests mirror the packages, so
src/gd_analyze/<package>/<module>.py is tested in tests/<package>/test_<module>.py."""

import pathlib

from test_layers import DOMAIN

import gd_analyze

SRC = pathlib.Path(gd_analyze.__file__).parent
TESTS = pathlib.Path(__file__).resolve().parent


def missing_tests(core, tests):
    """The domain modules (relative paths) without tests/<package>/test_<module>.py."""
    out = []
    for path in sorted(p for p in core.rglob("*.py") if p.relative_to(core).parts[0] in DOMAIN):
        if path.name == "__init__.py":
            continue
        rel = path.relative_to(core)
        if not (tests / rel.parent / f"test_{rel.name}").is_file():
            out.append(str(rel))
    return out


def test_every_domain_module_has_its_test_module():
    assert len(list(SRC.rglob("*.py"))) > 20          # the scan sees the package
    missing = missing_tests(SRC, TESTS)
    assert not missing, "domain modules without a test module: " + ", ".join(missing)


def test_the_check_finds_a_module_without_tests(tmp_path):
    core, tests = tmp_path / "gd_analyze", tmp_path / "tests"
    for rel in ("model/__init__.py", "model/a.py", "model/b.py", "dynamics/c.py"):
        (core / rel).parent.mkdir(parents=True, exist_ok=True)
        (core / rel).write_text("")
    (tests / "model").mkdir(parents=True)
    (tests / "model" / "test_a.py").write_text("")
    (tests / "test_c.py").write_text("")                 # not in its package's folder
    assert missing_tests(core, tests) == ["dynamics/c.py", "model/b.py"]
