"""The exact customized recursive Newton-Euler program: Python and compiled C against
Pinocchio's rnea, and its operation count against an independent count of the emitted C."""

import ctypes
import re
import shutil
import subprocess
from functools import cache

import numpy as np
import pytest
from scales import joint_relative_error
from symbolic_helpers import ROBOTS, count_c, rnea, robot, states

from gd_analyze.symbolic.emit import emit_c, python_function
from gd_analyze.symbolic.recursive import recursive_program

TOL = 1e-10


@cache
def program(name):
    arm = robot(name)
    return arm, recursive_program(arm)


@pytest.mark.parametrize("name", ROBOTS)
def test_exact_program_equals_rnea(name):
    """EPS = 0: the program's Python equals rnea to 1e-10 of the peak |tau_i| on 200 states."""
    arm, prog = program(name)
    q, qd, qdd = states(arm, 200, 7)
    assert joint_relative_error(python_function(prog)(q, qd, qdd), rnea(arm, q, qd, qdd)) < TOL


def _compile(tmp_path, prog, n):
    cc = shutil.which("cc")
    assert cc, "the machine's C compiler (cc) is required"
    src = tmp_path / "m.c"
    src.write_text(emit_c(prog, {"robot": "test"}))
    lib = tmp_path / "libm_recursive.so"
    subprocess.run([cc, "-O2", "-shared", "-fPIC", "-std=c99", "-Wall", "-Werror", "-o",
                    str(lib), str(src), "-lm"], check=True)
    fn = ctypes.CDLL(str(lib)).gd_tau
    dp = ctypes.POINTER(ctypes.c_double)
    fn.argtypes, fn.restype = [dp, dp, dp, dp], None

    def tau(q, qd, qdd):
        out, res = np.empty(n), np.empty_like(q)
        for k in range(q.shape[0]):
            args = [np.ascontiguousarray(x[k]) for x in (q, qd, qdd)]
            fn(*(a.ctypes.data_as(dp) for a in args), out.ctypes.data_as(dp))
            res[k] = out
        return res
    return tau


@pytest.mark.parametrize("name", ["puma560", "stanford", "panda", "mixed-chain"])
def test_compiled_c_equals_python_and_rnea(tmp_path, name):
    arm, prog = program(name)
    q, qd, qdd = states(arm, 200, 8)
    tau_c = _compile(tmp_path, prog, arm.n)(q, qd, qdd)
    tau_py = python_function(prog)(q, qd, qdd)
    assert joint_relative_error(tau_c, tau_py) < 1e-13
    assert joint_relative_error(tau_c, rnea(arm, q, qd, qdd)) < TOL


def test_c_counter_counts_what_it_should():
    src = ("const double t0 = -2.5*x + (y*y) - q[1]*4e-05 - (-0.5)*z;\n"
           "tau[0] = -t0 + sin(q[2])*cos(q[0]);")
    assert count_c(src) == {"multiplications": 5, "additions": 4, "sin": 1, "cos": 1}


@pytest.mark.parametrize("name", ROBOTS)
def test_program_cost_equals_count_of_emitted_c(name):
    _, prog = program(name)
    assert count_c(emit_c(prog, {"robot": "test"})) == prog.cost()


def test_costs_within_the_targets():
    """The published targets: PUMA 560 <= 338 operations (no trig of q1: gravity is along its
    axis; none of q6: the AKB wrist is symmetric about its axis), Panda <= 648."""
    cost = program("puma560")[1].cost()
    assert cost["multiplications"] + cost["additions"] <= 338
    assert cost["sin"] == cost["cos"] == 4
    cost = program("panda")[1].cost()
    assert cost["multiplications"] + cost["additions"] <= 648
    src = emit_c(program("puma560")[1], {})
    assert not re.search(r"(sin|cos)\(q\[(0|5)\]\)", src)


def test_standard_parameters_give_the_same_torques_with_more_operations():
    """tau is linear in the parameters: the standard parameters give the torques of the
    base parameters, and folding the base parameters' zeros saves operations."""
    from gd_analyze.dynamics.base_parameters import standard_parameters

    arm, prog = program("stanford")
    full = recursive_program(arm, standard_parameters(arm))
    q, qd, qdd = states(arm, 100, 12)
    ref = rnea(arm, q, qd, qdd)
    assert joint_relative_error(python_function(full)(q, qd, qdd), ref) < TOL
    total = [p.cost()["multiplications"] + p.cost()["additions"] for p in (prog, full)]
    assert total[0] < total[1]
    with pytest.raises(ValueError, match="shape"):
        recursive_program(arm, standard_parameters(arm)[:-1])


# ------------------------------------------------------------------------------------------
# The programs kept in this process (recursive.PROGRAMS, recursive.COUNTS)
# ------------------------------------------------------------------------------------------

def _spec_with(arm, **link1):
    from gd_analyze.model.robot_spec import robot_from_dict

    spec = arm.to_dict()
    spec["link"][1] = {**spec["link"][1], **link1}
    return robot_from_dict(spec)


def test_a_kept_program_is_the_one_a_fresh_build_gives():
    """The second request is answered from the memo (the same object), and it is the program
    a build in an empty memo gives: the same temporaries and outputs, text for text."""
    from gd_analyze.symbolic import recursive

    arm = robot("puma560")
    first = recursive_program(arm)
    assert recursive_program(arm) is first
    recursive.PROGRAMS.clear()
    fresh = recursive_program(arm)
    assert fresh is not first
    assert [str(e) for e in fresh.outputs] == [str(e) for e in first.outputs]
    assert [(str(s), str(e)) for s, e in fresh.assignments] == \
        [(str(s), str(e)) for s, e in first.assignments]
    assert fresh.forms == first.forms


@pytest.mark.parametrize("change", [{"a": 0.4318 + 1e-9}, {"mass": 17.4 + 1e-6},
                                    {"alpha_deg": 1e-9}])
def test_another_arm_never_gets_a_kept_program(change):
    """An arm that differs in one number of its second link (a length by 1 nm, a mass by
    1 mg, a twist by 1e-9 deg) gets its own program, with other constants, that equals
    Pinocchio's rnea of that arm."""
    arm = robot("puma560")
    kept = recursive_program(arm)
    other = _spec_with(arm, **change)
    prog = recursive_program(other)
    assert [str(e) for e in prog.assignments] != [str(e) for e in kept.assignments]
    q, qd, qdd = states(other, 100, 3)
    assert joint_relative_error(python_function(prog)(q, qd, qdd), rnea(other, q, qd, qdd)) \
        < TOL


def test_searched_forms_given_back_return_the_searched_program():
    """parts_program with the forms its search chose is the searched program (kept under
    both keys); parts_count is the count of the quick program, built afresh."""
    from gd_analyze.dynamics.base_parameters import base_parameters
    from gd_analyze.symbolic import recursive
    from gd_analyze.symbolic.pruning import part_values

    arm = robot("stanford")
    base = base_parameters(arm)
    dropped = np.zeros((base.rank, 3), bool)
    dropped[0, 1] = True
    values = part_values(base, dropped)
    searched = recursive.parts_program(arm, values)
    assert recursive.parts_program(arm, values, forms=searched.forms) is searched
    recursive.COUNTS.clear()
    quick = recursive.parts_program(arm, values, cse=False, search=False).cost()
    assert recursive.parts_count(arm, values) == quick["multiplications"] + quick["additions"]
    with pytest.raises(ValueError, match="shape"):
        recursive.parts_count(arm, values[:2])


def test_a_memo_of_size_0_is_refused():
    from gd_analyze.symbolic.recursive import ProgramMemo

    with pytest.raises(ValueError, match="at least 1"):
        ProgramMemo(size=0)
