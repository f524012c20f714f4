"""Every public function and class is documented, and every parameter appears in its
docstring (in the spirit of python-control's control/tests/docstrings_test.py)."""

import importlib
import inspect
import pkgutil
import re

import gd_analyze

MODULES = sorted(m.name[len("gd_analyze."):]
                 for m in pkgutil.walk_packages(gd_analyze.__path__, "gd_analyze.")
                 if not m.ispkg and not m.name.rsplit(".", 1)[-1].startswith("_")
                 and m.name != "gd_analyze.cli")


def _public(module):
    names = getattr(module, "__all__", None)
    assert names is not None, f"{module.__name__} has no __all__"
    for name in names:
        obj = getattr(module, name)
        if (inspect.isfunction(obj) or inspect.isclass(obj)) and \
                getattr(obj, "__module__", "") == module.__name__:
            yield name, obj


def _documented(doc, param):
    # numpydoc: "name : type", possibly grouped as "a, b : type"
    return re.search(rf"^\s*(\w+\s*,\s*)*\*{{0,2}}{re.escape(param)}(\s*,\s*\w+)*\s*(:|$)", doc,
                     re.M) is not None


def test_public_api_is_documented():
    """One check over every module (a structural check is one test, listing every
    miss, not one test per module)."""
    missing = [m for modname in MODULES for m in _undocumented(modname)]
    assert not missing, "\n".join(missing)


def _undocumented(modname):
    module = importlib.import_module(f"gd_analyze.{modname}")
    if not module.__doc__:
        return [f"{modname} has no module docstring"]
    missing = []
    for name, obj in _public(module):
        doc = inspect.getdoc(obj) or ""
        if not doc:
            missing.append(f"{name}: no docstring")
            continue
        targets = [obj]
        if inspect.isclass(obj):
            targets = [m for m_name, m in vars(obj).items()
                       if inspect.isfunction(m) and not m_name.startswith("_")]
            init = vars(obj).get("__init__")        # its own, not one typing put there
            if init is not None and inspect.isfunction(init) and \
                    init.__qualname__.startswith(f"{obj.__qualname__}."):
                targets.append(("__init__", init))
        for target in targets:
            func = target[1] if isinstance(target, tuple) else target
            fdoc = doc if isinstance(target, tuple) or func is obj else inspect.getdoc(func) or ""
            if not fdoc:
                missing.append(f"{name}.{func.__name__}: no docstring")
                continue
            for param in inspect.signature(func).parameters:
                if param in ("self", "cls"):
                    continue
                if not _documented(fdoc, param.lstrip("*")):
                    missing.append(f"{modname}: {name}.{func.__name__}: parameter {param!r} "
                                   "undocumented")
    return [m if m.startswith(modname) else f"{modname}: {m}" for m in missing]


def test_the_check_can_fail():
    def f(alpha, beta):
        """Do it.

        Parameters
        ----------
        alpha : float
            A [m].
        """

    doc = inspect.getdoc(f)
    assert _documented(doc, "alpha") and not _documented(doc, "beta")
