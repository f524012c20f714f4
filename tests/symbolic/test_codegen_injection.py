"""Hostile robot names cannot reach the code of the emitted model.

A name from a TOML robot file, a URDF ``<robot name>`` or the API is put into the header of
every emitted file: ``simplified_model.h``, ``.c``, ``.py`` and ``_casadi.py`` (and the sweep's
``merged_model.*``, the same emitters). Oracles: the C compiles under ``-Wall -Wextra
-Werror``, its object defines exactly the eleven prefixed symbols (five functions, their
batch calls and the parameters), and its preprocessed text (comments removed by the compiler itself, the header included) is that of a harmless name; the
two Python modules' syntax trees are those of a harmless name; loading the library and
importing both modules in a child interpreter leaves no marker file behind; every file names
the robot by the SHA-256 of its raw name; the default prefix made of the name is a plain C
identifier.
"""

import ast
import dataclasses
import hashlib
import re
import shutil
import subprocess
import sys
import textwrap
from xml.sax.saxutils import quoteattr

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from gd_analyze import SimplifiedModel, load_robot
from gd_analyze.model.urdf import load_urdf
from gd_analyze.ranking.ranking import element_labels
from gd_analyze.symbolic.safe_text import c_prefix, comment_safe

#: The attacks once reported: a constructor that runs a command when the controller loads
#: the library, a cos that changes the torques, an extra global symbol, Python run on import.
C_CONSTRUCTOR = ('a */ int system(const char*); __attribute__((constructor)) static void '
                 'k(void){system("touch PWNED");} /*')
C_COS = "a */ static double cos(double x){return 0.0*x;} /*"
C_GLOBAL = "a */ int gd_extra(void){return 1;} /*"
PY_DOCSTRING = 'x"""; __import__("os").system("touch PWNED"); """'
# found by hypothesis: a name whose digested comment passes 200 characters lost its SHA-256 to
# the header's second cut
LONG_NAME = '#define cos sin' + '__import__("os").system("touch PWNED")' * 3
PY_SINGLE = "x'''; __import__('os').system('touch PWNED'); '''"

#: Pieces the generated names are made of: comment and string ends, escapes, line breaks
#: (ASCII and Unicode), trigraphs, preprocessor and coding lines, and commands.
PIECES = ["*/", "/*", "//", '"""', "'''", '"', "'", "\\", "??/", "#", "#define cos sin",
          "\n", "\r", "\u2028", "\u2029", "\x85", "\x0c", "\t", " coding: utf-7 ", "+AAo-",
          "<script>", "&amp;", ";", "{", "}", 'system("touch PWNED");',
          '__import__("os").system("touch PWNED")', "int gd_extra(void){return 1;}",
          "static double cos(double x){return 0.0*x;}", "\u00e9", "\u202e", "x", " "]
NAMES = st.lists(st.one_of(st.sampled_from(PIECES), st.text(max_size=3)), min_size=1,
                 max_size=8).map("".join).filter(lambda s: s.strip())
PRINTABLE = st.lists(st.one_of(st.sampled_from([p for p in PIECES if p.isprintable()]),
                               st.text(st.characters(codec="utf-8"), max_size=3)),
                     min_size=1, max_size=8).map("".join).filter(
    lambda s: s.strip() and s.isprintable() and len(s) <= 200)
SETTINGS = settings(max_examples=10, deadline=None,
                    suppress_health_check=[HealthCheck.function_scoped_fixture,
                                           HealthCheck.too_slow, HealthCheck.filter_too_much])

TWO_LINK_URDF = """<?xml version="1.0"?>
<robot name={name}>
  <link name="base"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" velocity="2" effort="10"/></joint>
  <link name="l1"><inertial><origin xyz="0.5 0 0"/><mass value="1"/>
    <inertia ixx="0.001" iyy="0.08" izz="0.08" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="1 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" velocity="2" effort="10"/></joint>
  <link name="l2"><inertial><origin xyz="0.5 0 0"/><mass value="1"/>
    <inertia ixx="0.001" iyy="0.08" izz="0.08" ixy="0" ixz="0" iyz="0"/></inertial></link>
</robot>
"""

#: What the child interpreter runs (``-I``: nothing imported from its folder): load the
#: library, call it, import the module, call it.
CHILD = textwrap.dedent("""
    import ctypes, importlib.util, pathlib
    here = pathlib.Path.cwd()
    lib = ctypes.CDLL(str(here / "libmodel.so"))
    n = {n}
    arr = ctypes.c_double * n
    lib.gd_tau(arr(*[0.1] * n), arr(*[0.2] * n), arr(*[0.3] * n), arr())
    for name in ("simplified_model", "simplified_model_casadi"):
        spec = importlib.util.spec_from_file_location(name, here / (name + ".py"))
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)
        if name == "simplified_model":
            mod.tau([[0.1] * n], [[0.2] * n], [[0.3] * n])
        else:
            mod.functions()["tau"]([0.1] * n, [0.2] * n, [0.3] * n)
""")


def _model(robot):
    return SimplifiedModel(robot=robot, choices={lab: "both" for lab in element_labels(robot.n)},
                           dominance_threshold=0.9, negligible_threshold=0.01)


def _cc():
    cc = shutil.which("cc")
    assert cc, "the machine's C compiler (cc) is required"
    return cc


def _preprocessed(cc, path):
    """The C after the preprocessor: comments gone, so only code is compared."""
    out = subprocess.run([cc, "-std=c99", "-E", "-P", str(path)], check=True,
                         capture_output=True, text=True).stdout
    return out


#: The symbols the emitted object defines, with the prefix the test gives.
_FUNCTIONS = ("tau", "inertia", "velocity_terms", "gravity", "regressor")
SYMBOLS = sorted([f"gd_{k}" for k in _FUNCTIONS + ("base_parameters",)]
                 + [f"gd_{k}_batch" for k in _FUNCTIONS])


def _check_emitted(robot, folder):
    """The emitted files of ``robot``'s model carry its name only as comment text."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "ref").mkdir(exist_ok=True)
    cc = _cc()
    model = _model(robot)
    reference = _model(dataclasses.replace(robot, name="reference"))
    files, ref = model.sources(prefix="gd_"), reference.sources(prefix="gd_")
    for name, text in files.items():
        (folder / name).write_text(text, encoding="utf-8")
        (folder / "ref" / name).write_text(ref[name], encoding="utf-8")
    # every file still names the robot: its sanitised name and the SHA-256 of the raw name
    digest = hashlib.sha256(robot.name.encode("utf-8", "backslashreplace")).hexdigest()
    for src in files.values():
        assert comment_safe(robot.name, digest=True) in src and digest in src
    # C: compiles strictly, exactly the eleven prefixed symbols
    c_file = folder / "simplified_model.c"
    subprocess.run([cc, "-std=c99", "-Wall", "-Wextra", "-Werror", "-fPIC", "-c",
                    str(c_file), "-o", str(folder / "model.o")], check=True)
    for flags in (["--defined-only"], ["-g", "--defined-only"]):
        nm = subprocess.run(["nm", *flags, str(folder / "model.o")], check=True,
                            capture_output=True, text=True).stdout.split()
        kinds = dict(zip(nm[2::3], nm[1::3]))
        assert sorted(s for s, k in kinds.items() if k.isupper()) == SYMBOLS, nm
        assert {s for s, k in kinds.items() if k.islower()} <= {"gd_JOINT_NAMES"}, nm
    subprocess.run([cc, "-shared", "-o", str(folder / "libmodel.so"),
                    str(folder / "model.o"), "-lm"], check=True)
    # loading and importing in a child interpreter runs nothing planted in the name
    proc = subprocess.run([sys.executable, "-I", "-c", CHILD.format(n=robot.n)], cwd=folder,
                          capture_output=True, text=True)
    assert not (folder / "PWNED").exists()
    assert proc.returncode == 0, proc.stderr
    # the code is that of a harmless name: C after the preprocessor (header included), the
    # Python modules' syntax trees
    assert _preprocessed(cc, c_file) == _preprocessed(cc, folder / "ref" / c_file.name)
    for name in ("simplified_model.py", "simplified_model_casadi.py"):
        assert ast.dump(ast.parse(files[name])) == ast.dump(ast.parse(ref[name]))
    # the default prefix, made of the name, is a plain C identifier
    assert re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*_", c_prefix(robot.name))
    assert model.sources()["simplified_model.h"].count(f"void {c_prefix(robot.name)}tau(") == 1


@pytest.fixture(scope="module")
def two_link_toml():
    from importlib import resources

    return resources.files("gd_analyze").joinpath("data/two-link.toml").read_text("utf-8")


@SETTINGS
@given(name=NAMES)
@example(name=C_CONSTRUCTOR)
@example(name=C_COS)
@example(name=C_GLOBAL)
@example(name=PY_DOCSTRING)
@example(name="x\n#define cos sin\n\u2028*/ ??/\n\"\"\"\\")
@example(name=LONG_NAME)
def test_api_robot_name_stays_in_comments(tmp_path_factory, two_link, name):
    """Any name, line breaks included (the API does not check names)."""
    _check_emitted(dataclasses.replace(two_link, name=name), tmp_path_factory.mktemp("api"))


@SETTINGS
@given(name=PRINTABLE)
@example(name=C_CONSTRUCTOR)
@example(name=C_COS)
@example(name=PY_DOCSTRING)
@example(name=PY_SINGLE)
def test_toml_robot_name_stays_in_comments(tmp_path_factory, two_link_toml, name):
    import json

    folder = tmp_path_factory.mktemp("toml")
    text = two_link_toml.replace('name = "two-link"',
                                 f"name = {json.dumps(name, ensure_ascii=False)}", 1)
    assert text != two_link_toml
    (folder / "robot.toml").write_text(text, encoding="utf-8")
    robot = load_robot(folder / "robot.toml")
    assert robot.name == name
    _check_emitted(robot, folder / "out")


@SETTINGS
@given(name=PRINTABLE)
@example(name=C_GLOBAL)
@example(name=C_CONSTRUCTOR)
@example(name=PY_DOCSTRING)
@example(name=LONG_NAME)
def test_urdf_robot_name_stays_in_comments(tmp_path_factory, name):
    folder = tmp_path_factory.mktemp("urdf")
    (folder / "robot.urdf").write_text(TWO_LINK_URDF.format(name=quoteattr(name)),
                                       encoding="utf-8")
    robot = load_urdf(folder / "robot.urdf")
    _check_emitted(robot, folder / "out")


def test_sweep_model_uses_the_same_header(two_link):
    """merged_model.* come from the same SimplifiedModel emitters: one hostile sweep model."""
    from gd_analyze.simplify.sweep_model import sweep_model
    from gd_analyze.trajectory.planning import plan_quintic

    robot = dataclasses.replace(two_link, name=C_CONSTRUCTOR)
    traj = plan_quintic(robot, [0.0, 0.0], [1.0, 0.5], n_setpoints=11)
    model, _ = sweep_model(robot, [traj])
    files = model.sources("merged_model", "gd_merged_")
    ref = dataclasses.replace(model, robot=dataclasses.replace(robot, name="reference")).sources(
        "merged_model", "gd_merged_")
    for name in ("merged_model.c", "merged_model.h"):
        assert files[name].count("/*") == files[name].count("*/") == ref[name].count("*/")
    for name in ("merged_model.py", "merged_model_casadi.py"):
        assert ast.dump(ast.parse(files[name])) == ast.dump(ast.parse(ref[name]))
    for src in files.values():
        assert '"touch PWNED"' not in src and comment_safe(C_CONSTRUCTOR, digest=True) in src


@settings(max_examples=200, deadline=None)
@given(text=st.one_of(NAMES, st.text()))
@example(text="a??/\n*/ '''\"\"\"\u2028\r\\ # -*- coding: utf-7 -*-")
def test_comment_safe_keeps_only_inert_ascii(text):
    """Printable ASCII only, none of the characters that end or extend a comment or string,
    idempotent, and the digest is the raw text's SHA-256."""
    import string

    safe = comment_safe(text)
    assert set(safe) <= set(string.printable) - set("*\\\"'#?`\t\n\r\x0b\x0c")
    for bad in ("*/", "/*", '"""', "'''", "\\", "??/", "#"):
        assert bad not in safe
    assert len(safe) <= 200 and comment_safe(safe) == safe
    raw = text.encode("utf-8", "backslashreplace")
    assert comment_safe(text, digest=True) == f"{safe} (sha256 {hashlib.sha256(raw).hexdigest()})"


@pytest.mark.parametrize("name", [C_CONSTRUCTOR, PY_DOCSTRING, LONG_NAME])
@pytest.mark.parametrize("given_as", ["URDF text", "pinocchio.Model"])
def test_urdf_text_and_pinocchio_model_name_stays_in_comments(tmp_path_factory, name, given_as):
    """A robot given to load_robot as URDF text or a pinocchio.Model."""
    import pinocchio

    text = TWO_LINK_URDF.format(name=quoteattr(name))
    if given_as == "URDF text":
        robot = load_robot(text)
    else:
        model = pinocchio.buildModelFromXML(TWO_LINK_URDF.format(name=quoteattr("x")))
        model.name = name
        robot = load_robot(model)
    assert robot.name == name and robot.source == given_as
    _check_emitted(robot, tmp_path_factory.mktemp("given"))
