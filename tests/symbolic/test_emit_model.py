"""The deployed model's files (symbolic/emit_model.py): C header and source, numpy, CasADi.

Two arms (the PUMA 560, DH, and the Panda, URDF), each at EPS = 0 (the exact model) and at
EPS = 0.01 (pruned), with four prefixes, are compiled into ONE C program (cc -std=c99 -Wall
-Wextra -Werror) and ONE C++ program (g++ -std=c++17, both headers included, the C objects
linked): neither compiles or links unless the headers' include guards, prefixes and
``extern "C"`` keep the four models apart. Oracles: Pinocchio's crba, nonLinearEffects minus
computeGeneralizedGravity, computeGeneralizedGravity, rnea and computeJointTorqueRegressor
(its standard-parameter columns taken at the base parameters' slots, Gautier 1990: Y_b = W_B)
at EPS = 0; at EPS = 0.01 the identities D_s qdd + h_s + c_s = tau_s and Y_s beta_s = tau_s
(Eq. (3.4-24)); the numpy and CasADi files against the C program. No compiler is a failure,
not a skip.
"""

import ast
import ctypes
import dataclasses
import importlib.util
import platform
import re
import shutil
import subprocess
import types
import unicodedata

import numpy as np
import pinocchio as pin
import pytest

from gd_analyze import SimplifiedModel, load_robot
from gd_analyze.dynamics.base_parameters import random_states
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.ranking.labels import element_labels
from gd_analyze.symbolic.emit_model import artefact_names
from gd_analyze.symbolic.recursive_model import recursive_model

#: (robot, EPS, prefix) of the four models of the one program.
MODELS = (("puma560", 0.0, "puma0_"), ("puma560", 0.01, "puma_"),
          ("panda", 0.0, "panda0_"), ("panda", 0.01, "panda_"))
STATES = 200
#: Pinocchio's standard parameters (m, mx, my, mz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz) in our order
#: (XX, XY, XZ, YY, YZ, ZZ, MX, MY, MZ, M).
PIN_ORDER = [4, 5, 7, 6, 8, 9, 1, 2, 3, 0]

DRIVER = """
static int run_{p}(void)
{{
    FILE *in = fopen("in_{p}.bin", "rb");
    FILE *out = fopen("out_{p}.bin", "wb");
    double x[3 * {p}N_JOINTS];
    double tau[{p}N_JOINTS], D[{p}N_JOINTS * {p}N_JOINTS], h[{p}N_JOINTS], c[{p}N_JOINTS];
    static double Y[{p}N_JOINTS * {p}N_BASE_PARAMETERS];
    int j;
    if (!in || !out)
        return 1;
    for (j = 0; j < {p}N_JOINTS; ++j)
        printf("%s%s", j ? " " : "{p}", {p}JOINT_NAMES[j]);
    printf("\\n");
    fwrite({p}base_parameters, sizeof(double), {p}N_BASE_PARAMETERS, out);
    while (fread(x, sizeof(double), 3 * {p}N_JOINTS, in) == 3 * {p}N_JOINTS) {{
        const double *q = x, *qd = x + {p}N_JOINTS, *qdd = x + 2 * {p}N_JOINTS;
        {p}tau(q, qd, qdd, tau);
        {p}inertia(q, D);
        {p}velocity_terms(q, qd, h);
        {p}gravity(q, c);
        {p}regressor(q, qd, qdd, Y);
        fwrite(tau, sizeof(double), {p}N_JOINTS, out);
        fwrite(D, sizeof(double), {p}N_JOINTS * {p}N_JOINTS, out);
        fwrite(h, sizeof(double), {p}N_JOINTS, out);
        fwrite(c, sizeof(double), {p}N_JOINTS, out);
        fwrite(Y, sizeof(double), {p}N_JOINTS * {p}N_BASE_PARAMETERS, out);
    }}
    fclose(in);
    fclose(out);
    return 0;
}}
"""


def _model(robot, eps):
    """The recursive model pruned within EPS on random states (exact at EPS = 0)."""
    q, qd, qdd = random_states(robot, 60, 4)
    rec = recursive_model(robot, q, qd, qdd, eps)
    return SimplifiedModel(robot=robot, choices={k: "both" for k in element_labels(robot.n)},
                           dominance_threshold=0.9, negligible_threshold=0.01, rule="budget",
                           tolerance=eps, recursive=rec)


def _tool(name):
    path = shutil.which(name)
    assert path, f"the machine's {name} is required (a missing compiler fails this test)"
    return path


def _read(path, n, b, count):
    raw = np.fromfile(path, dtype=float)
    beta, rest = raw[:b], raw[b:].reshape(count, -1)
    sizes = np.cumsum([n, n * n, n, n, n * b])[:-1]
    tau, D, h, c, Y = np.split(rest, sizes, axis=1)
    return {"beta": beta, "tau": tau, "inertia": D.reshape(count, n, n), "velocity_terms": h,
            "gravity": c, "regressor": Y.reshape(count, n, b)}


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """The four models' files, one C and one C++ program of them, and what each computed."""
    cc, cxx = _tool("cc"), _tool("g++")
    root = tmp_path_factory.mktemp("emitted")
    models, objects, includes, drivers, states = {}, [], [], [], {}
    for name, eps, prefix in MODELS:
        robot = load_robot(name)
        model = _model(robot, eps)
        folder = root / prefix.rstrip("_")
        folder.mkdir()
        for file, text in model.sources(prefix=prefix).items():
            (folder / file).write_text(text, encoding="utf-8")
        objects.append(folder / "simplified_model.o")
        subprocess.run([cc, "-std=c99", "-Wall", "-Wextra", "-Werror", "-O1", "-c",
                        str(folder / "simplified_model.c"), "-o", str(objects[-1])], check=True)
        includes.append(f'#include "{folder.name}/simplified_model.h"')
        drivers.append(DRIVER.format(p=prefix))
        q, qd, qdd = random_states(robot, STATES, 11)
        states[prefix] = (q, qd, qdd)
        np.concatenate([q, qd, qdd], axis=1).tofile(root / f"in_{prefix}.bin")
        models[prefix] = (robot, model, folder)
    calls = " | ".join(f"run_{p}()" for _, _, p in MODELS)
    main = "\n".join(["#include <stdio.h>"] + includes + drivers
                     + [f"int main(void)\n{{\n    return {calls};\n}}\n"])
    (root / "main.c").write_text(main)
    (root / "main.cpp").write_text(main)
    objs = [str(o) for o in objects]
    subprocess.run([cc, "-std=c99", "-Wall", "-Wextra", "-Werror", "-o", str(root / "prog_c"),
                    str(root / "main.c"), *objs, "-lm"], check=True, cwd=root)
    subprocess.run([cxx, "-std=c++17", "-Wall", "-Wextra", "-Werror", "-o",
                    str(root / "prog_cpp"), str(root / "main.cpp"), *objs, "-lm"], check=True,
                   cwd=root)
    out = {}
    for program in ("prog_c", "prog_cpp"):
        names = subprocess.run([str(root / program)], check=True, cwd=root, capture_output=True,
                               text=True).stdout
        out[program] = {"names": names.split("\n")[:-1]}
        for _, _, p in MODELS:
            robot, model, _ = models[p]
            f = model.functions()
            out[program][p] = _read(root / f"out_{p}.bin", robot.n, len(f.parameter_names),
                                    STATES)
    return {"models": models, "states": states, "results": out, "root": root}


def _oracle(robot, q, qd, qdd):
    """Pinocchio's D, h, c, tau and base regressor at each state."""
    from gd_analyze.dynamics.base_parameters import base_parameters

    model = pinocchio_model(robot)
    data = model.createData()
    independent = base_parameters(robot).independent.reshape(-1)
    out = {k: [] for k in ("tau", "inertia", "velocity_terms", "gravity", "regressor")}
    for x, v, a in zip(q, qd, qdd):
        D = pin.crba(model, data, x)
        out["inertia"].append(np.triu(D) + np.triu(D, 1).T)
        g = pin.computeGeneralizedGravity(model, data, x).copy()
        out["gravity"].append(g)
        out["velocity_terms"].append(pin.nonLinearEffects(model, data, x, v) - g)
        out["tau"].append(pin.rnea(model, data, x, v, a).copy())
        W = pin.computeJointTorqueRegressor(model, data, x, v, a)
        W = np.concatenate([W[:, 10 * j:10 * j + 10][:, PIN_ORDER] for j in range(robot.n)],
                           axis=1)
        out["regressor"].append(W[:, independent])
    return {k: np.array(v) for k, v in out.items()}


def _err(got, want, scale):
    return float((np.abs(got - want) / scale).max())


@pytest.mark.parametrize("prefix", ["puma0_", "panda0_"])
def test_every_c_function_equals_pinocchio_at_eps_0(built, prefix):
    """EPS = 0: tau, D, h, c equal rnea, crba, nle - g, g and Y equals Pinocchio's regressor
    at the base parameters' columns, each to 1e-10 of its scale, on 200 random states."""
    robot, model, _ = built["models"][prefix]
    q, qd, qdd = built["states"][prefix]
    got = built["results"]["prog_c"][prefix]
    want = _oracle(robot, q, qd, qdd)
    peak = np.abs(want["tau"]).max(axis=0)                     # peak |tau_i| per joint
    diag = np.abs(np.diagonal(want["inertia"], axis1=1, axis2=2)).max(axis=0)
    for key in ("tau", "velocity_terms", "gravity"):
        assert _err(got[key], want[key], peak) < 1e-10, key
    assert _err(got["inertia"], want["inertia"], np.sqrt(np.outer(diag, diag))) < 1e-10
    col = np.abs(want["regressor"]).max(axis=(0, 1))
    assert _err(got["regressor"], want["regressor"], np.where(col > 0, col, 1.0)) < 1e-10
    assert _err(np.einsum("kib,b->ki", got["regressor"], got["beta"]), want["tau"], peak) < 1e-10
    assert np.array_equal(got["beta"], model.functions().parameters)


@pytest.mark.parametrize("prefix", ["puma_", "panda_"])
def test_identities_hold_for_the_pruned_model(built, prefix):
    """EPS = 0.01: D_s qdd + h_s + c_s = tau_s and Y_s beta_s = tau_s to 1e-12 of peak |tau_s,i|,
    and the model is pruned indeed (it differs from rnea)."""
    robot, model, _ = built["models"][prefix]
    q, qd, qdd = built["states"][prefix]
    got = built["results"]["prog_c"][prefix]
    tau = got["tau"]
    peak = np.abs(tau).max(axis=0)
    dqdd = np.einsum("kij,kj->ki", got["inertia"], qdd)
    assert _err(dqdd + got["velocity_terms"] + got["gravity"], tau, peak) < 1e-12
    assert _err(np.einsum("kib,b->ki", got["regressor"], got["beta"]), tau, peak) < 1e-12
    assert np.array_equal(got["inertia"], np.swapaxes(got["inertia"], 1, 2))
    assert model.recursive.dropped.any()
    assert _err(tau, _oracle(robot, q, qd, qdd)["tau"], peak) > 1e-8
    assert np.abs(model.torque(q, qd, qdd) - tau).max() <= 1e-13 * peak.max()


def test_cpp_program_computes_what_the_c_program_computes(built):
    """g++ -std=c++17 with both headers: links (extern "C") and gives the same numbers."""
    c, cpp = built["results"]["prog_c"], built["results"]["prog_cpp"]
    assert c["names"] == cpp["names"] and len(c["names"]) == len(MODELS)
    assert c["names"][2] == "panda0_" + " ".join(f"panda_joint{i}" for i in range(1, 8))
    for _, _, p in MODELS:
        for key, value in c[p].items():
            assert np.array_equal(value, cpp[p][key]), (p, key)


def test_files_and_header(built):
    """One table of files; the header: guard, extern "C", constants, six defined symbols."""
    robot, model, folder = built["models"]["puma_"]
    assert sorted(p.name for p in folder.iterdir() if p.suffix != ".o") == sorted(
        artefact_names("simplified_model"))
    h = (folder / "simplified_model.h").read_text()
    (kind1, guard), (kind2, guard2) = re.findall(r"^#(\w+) (\S+)", h, re.M)[:2]
    assert (kind1, kind2) == ("ifndef", "define") and guard == guard2
    assert re.fullmatch(r"PUMA_SIMPLIFIED_MODEL_H_[0-9A-F]{8}", guard)
    assert 'extern "C" {' in h and "#define puma_N_JOINTS 6\n" in h
    assert f"#define puma_N_BASE_PARAMETERS {len(model.functions().parameter_names)}\n" in h
    nm = subprocess.run(["nm", "-g", "--defined-only", str(folder / "simplified_model.o")],
                        check=True, capture_output=True, text=True).stdout.split()
    functions = ("tau", "inertia", "velocity_terms", "gravity", "regressor")
    assert sorted(nm[2::3]) == sorted([f"puma_{k}" for k in functions + ("base_parameters",)]
                                      + [f"puma_{k}_batch" for k in functions])
    for name, allowed in (("simplified_model.py", ["numpy"]),
                          ("simplified_model_casadi.py", ["casadi"])):
        tree = ast.parse((folder / name).read_text())
        assert [a.name for node in ast.walk(tree) if isinstance(node, (ast.Import,
                ast.ImportFrom)) for a in node.names] == allowed, name
    assert re.findall(r"#include\s*(\S+)", (folder / "simplified_model.c").read_text()) == [
        "<math.h>", '"simplified_model.h"']
    assert dataclasses.replace(model, robot=dataclasses.replace(robot, name="x y")).sources()[
        "simplified_model.h"].count("void x_y_tau(") == 1              # the default prefix


def _against_c(key, value, got):
    """A function's values against the C program's: each entry by its peak over the states
    (D and Y), a vector's by peak |tau_i| (tau, h, c)."""
    scale = np.abs(got[key]).max(axis=0) if key in ("inertia", "regressor") else \
        np.abs(got["tau"]).max(axis=0)
    return _err(value, got[key], np.where(scale > 0, scale, 1.0))


def _case(built, prefix, file):
    """(robot, states, the C program's results, the emitted module ``file`` imported)."""
    robot, _, folder = built["models"][prefix]
    path = folder / file
    spec = importlib.util.spec_from_file_location(path.stem, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return robot, built["states"][prefix], built["results"]["prog_c"][prefix], mod


@pytest.mark.parametrize("prefix", ["puma_", "panda0_"])
def test_numpy_functions_equal_the_c_functions(built, prefix):
    robot, (q, qd, qdd), got, mod = _case(built, prefix, "simplified_model.py")
    values = {"tau": mod.tau(q, qd, qdd), "inertia": mod.inertia(q),
              "velocity_terms": mod.velocity_terms(q, qd), "gravity": mod.gravity(q),
              "regressor": mod.regressor(q, qd, qdd)}
    for key, value in values.items():
        assert value.shape == got[key].shape, key
        assert _against_c(key, value, got) < 1e-12, key
    assert np.array_equal(mod.BASE_PARAMETERS, got["beta"])
    assert len(mod.JOINT_NAMES) == mod.N_JOINTS == robot.n
    assert len(mod.BASE_PARAMETER_NAMES) == mod.N_BASE_PARAMETERS == got["beta"].size
    with pytest.raises(ValueError, match=f"expected {robot.n} joints"):
        mod.inertia(np.zeros((2, robot.n + 1)))


@pytest.mark.parametrize("prefix", ["puma_", "panda_"])
def test_casadi_functions_equal_the_c_functions(built, prefix):
    import casadi as ca

    _, (q, qd, qdd), got, mod = _case(built, prefix, "simplified_model_casadi.py")
    fns = mod.functions()
    assert sorted(fns) == sorted(["tau", "inertia", "velocity_terms", "gravity", "regressor"])
    assert all(isinstance(f, ca.Function) and f.name() == prefix + k for k, f in fns.items())
    args = {"q": q, "qd": qd, "qdd": qdd}
    mapped = mod.batch_functions(STATES)
    for key, fn in fns.items():
        batch = mapped[key]
        assert batch.name() == f"map{STATES}_{fn.name()}"
        value = np.asarray(batch(*(args[fn.name_in(i)].T for i in range(fn.n_in()))))
        rows = got[key].shape[1]                 # map: blocks of (rows, cols) side by side
        value = value.reshape(rows, STATES, -1).transpose(1, 0, 2).reshape(got[key].shape)
        assert _against_c(key, value, got) < 1e-12, key
    assert np.array_equal(np.array(mod.BASE_PARAMETERS), got["beta"])


#: States of the batch test: 24 blocks of 8 and a tail of 5 (the batch loops' blocks).
BATCH_STATES = 197


def _batch_library(built, prefix):
    """The model's C compiled as the header's comment says for the batch functions (cc -O3
    -march=native, no -ffast-math), as a shared library: (library, its undefined symbols)."""
    cc = _tool("cc")
    _, _, folder = built["models"][prefix]
    h = (folder / "simplified_model.h").read_text()
    line = re.search(r"^ \*     (cc .*) \(link with -lm\)$", h, re.M).group(1).split()
    assert line[-2:] == ["-c", "simplified_model.c"]
    obj, lib = folder / "batch.o", folder / "libbatch.so"
    subprocess.run([cc, *line[1:-2], "-pedantic", "-Wall", "-Wextra", "-Werror", "-fPIC", "-c",
                    str(folder / "simplified_model.c"), "-o", str(obj)], check=True)
    subprocess.run([cc, "-shared", "-o", str(lib), str(obj), "-lm"], check=True)
    undefined = subprocess.run(["nm", "-u", str(obj)], check=True, capture_output=True,
                               text=True).stdout.split()
    return ctypes.CDLL(str(lib)), undefined


@pytest.mark.parametrize("prefix", ["puma0_", "panda0_", "panda_"])
def test_batch_functions_equal_the_single_state_functions_and_pinocchio(built, prefix):
    """Each PREFIX<f>_batch on 197 states (a tail block of 5) equals PREFIX<f> called state by
    state in the same library to 1e-13 of its scale (peak |tau_i| for tau, h, c; sqrt(D_ii D_jj)
    for D_ij; a column's peak for Y), and at EPS = 0 Pinocchio's rnea, crba, nle - g, g to 1e-10; on x86-64
    the vectoriser called glibc's libmvec (a _ZGV symbol)."""
    robot, model, _ = built["models"][prefix]
    lib, undefined = _batch_library(built, prefix)
    if platform.machine() == "x86_64":
        assert any(s.startswith("_ZGV") and s.endswith("_sin") for s in undefined), undefined
    n, b = robot.n, len(model.functions().parameter_names)
    q, qd, qdd = (np.ascontiguousarray(x[:BATCH_STATES]) for x in built["states"][prefix])
    args = {"q": q, "qd": qd, "qdd": qdd}
    shapes = {"tau": (n,), "inertia": (n, n), "velocity_terms": (n,), "gravity": (n,),
              "regressor": (n, b)}
    inputs = {"tau": "q qd qdd", "inertia": "q", "velocity_terms": "q qd", "gravity": "q",
              "regressor": "q qd qdd"}
    dp = ctypes.POINTER(ctypes.c_double)
    single, batch = {}, {}
    for key, shape in shapes.items():
        xs = [args[a] for a in inputs[key].split()]
        one = getattr(lib, prefix + key)
        one.argtypes, one.restype = [dp] * (len(xs) + 1), None
        single[key] = np.empty((BATCH_STATES, *shape))
        for k in range(BATCH_STATES):
            out = np.empty(shape)
            one(*(np.ascontiguousarray(x[k]).ctypes.data_as(dp) for x in xs),
                out.ctypes.data_as(dp))
            single[key][k] = out
        many = getattr(lib, prefix + key + "_batch")
        many.argtypes, many.restype = [ctypes.c_long] + [dp] * (len(xs) + 1), None
        batch[key] = np.full((BATCH_STATES, *shape), np.nan)
        many(BATCH_STATES, *(x.ctypes.data_as(dp) for x in xs), batch[key].ctypes.data_as(dp))
    peak = np.abs(single["tau"]).max(axis=0)
    diag = np.abs(np.diagonal(single["inertia"], axis1=1, axis2=2)).max(axis=0)
    col = np.abs(single["regressor"]).max(axis=(0, 1))
    scales = {"inertia": np.sqrt(np.outer(diag, diag)), "regressor": np.where(col > 0, col, 1.0)}
    for key in shapes:
        assert np.isfinite(batch[key]).all(), key
        assert _err(batch[key], single[key], scales.get(key, peak)) < 1e-13, key
    assert not np.array_equal(batch["tau"], np.zeros_like(batch["tau"]))
    if not model.recursive.dropped.any():
        want = _oracle(robot, q, qd, qdd)
        for key in ("tau", "velocity_terms", "gravity"):
            assert _err(batch[key], want[key], peak) < 1e-10, key
        diag = np.abs(np.diagonal(want["inertia"], axis1=1, axis2=2)).max(axis=0)
        assert _err(batch["inertia"], want["inertia"], np.sqrt(np.outer(diag, diag))) < 1e-10


#: Joint names that a sanitising label made equal ("a_b" three times), a quote, a backslash, a
#: trigraph, a printf format, and format characters (U+202E right-to-left override, U+200B
#: zero width space).
HOSTILE_JOINTS = ("a b", "a_b", "a+b", 'j"4??/\\', "%s\u202e5", "j\u200b6")


def test_prefixes_differing_in_case_and_distinct_joint_names(tmp_path):
    """Models emitted with the prefixes arm_ and ARM_ compile into one program (their include
    guards differ); JOINT_NAMES holds each joint's exact name, in C (its UTF-8 bytes) and in
    the numpy module; no format character reaches any emitted file, comments included."""
    cc = _tool("cc")
    robot = load_robot("puma560")
    robot = dataclasses.replace(robot, name="arm\u202etxt.exe", metadata=types.MappingProxyType(
        {**robot.metadata, "urdf_joints": list(HOSTILE_JOINTS)}))
    model = _model(robot, 0.0)
    includes, objects = [], []
    for prefix in ("arm_", "ARM_"):
        folder = tmp_path / prefix.lower().rstrip("_") if prefix == "arm_" else tmp_path / "up"
        folder.mkdir()
        for file, text in model.sources(prefix=prefix).items():
            assert not any(unicodedata.category(c) == "Cf" for c in text), file
            (folder / file).write_text(text, encoding="utf-8")
        objects.append(str(folder / "simplified_model.o"))
        subprocess.run([cc, "-std=c99", "-Wall", "-Wextra", "-Werror", "-O0", "-c",
                        str(folder / "simplified_model.c"), "-o", objects[-1]], check=True)
        includes.append(f'#include "{folder.name}/simplified_model.h"')
    (tmp_path / "names.c").write_text("\n".join(["#include <stdio.h>", *includes, """
int main(void)
{
    int j;
    for (j = 0; j < arm_N_JOINTS; ++j)
        printf("%s\\n%s\\n", arm_JOINT_NAMES[j], ARM_JOINT_NAMES[j]);
    return 0;
}
"""]))
    subprocess.run([cc, "-std=c99", "-Wall", "-Wextra", "-Werror", "-o", str(tmp_path / "names"),
                    str(tmp_path / "names.c"), *objects, "-lm"], check=True, cwd=tmp_path)
    printed = subprocess.run([str(tmp_path / "names")], check=True, capture_output=True).stdout
    assert printed == b"".join(2 * (n.encode() + b"\n") for n in HOSTILE_JOINTS)
    spec = importlib.util.spec_from_file_location("emitted_names",
                                                  tmp_path / "arm" / "simplified_model.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    assert mod.JOINT_NAMES == HOSTILE_JOINTS
