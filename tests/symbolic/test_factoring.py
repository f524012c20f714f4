"""The rewrites of the straight-line program (symbolic/factoring.py): each keeps the value (checked by
evaluating both forms at random points) and never adds operations; the PUMA 560 programs built
with them, in both orders (factoring before and after cse), against Pinocchio rnea and the
independent count of the emitted C; the full PUMA model against the hand-made one of Armstrong,
Khatib & Burdick (ICRA 1986, 1165 operations)."""

import numpy as np
import pytest
import symengine as se
from conftest import random_states
from hypothesis import given, settings
from hypothesis import strategies as st
from symbolic.test_explicit import _c_operator_count, natural_error, python_tau, rnea

from gd_analyze import load_robot
from gd_analyze.symbolic import codegen
from gd_analyze.symbolic.codegen import build_program
from gd_analyze.symbolic.emit import emit_c
from gd_analyze.symbolic.explicit import derive, model_terms
from gd_analyze.symbolic.factoring import (
    expand_pairs,
    factor_sum,
    private_products,
    prune_dead,
    sum_to_product,
)
from gd_analyze.symbolic.operation_count import count_operations

SYMS = se.symbols("a b c d e f")


def _value(expr, point):
    return float(expr.xreplace({s: se.RealDouble(v) for s, v in zip(SYMS, point)}))


def _ops(expr):
    c = count_operations([], [expr])
    return c["multiplications"] + c["additions"]


term = st.tuples(st.sampled_from([1.0, -1.0, 0.5, -0.5, 2.25, 3.0]),
                 st.lists(st.sampled_from(range(len(SYMS))), min_size=0, max_size=3))


@settings(max_examples=200, deadline=None)
@given(st.lists(term, min_size=1, max_size=12), st.integers(0, 2**32 - 1))
def test_factor_sum_keeps_the_value_and_never_costs_more(spec, seed):
    terms = [se.Mul(se.RealDouble(c), *[SYMS[k] for k in ks]) for c, ks in spec]
    plain = se.Add(*terms)
    factored = factor_sum(terms)
    point = np.random.default_rng(seed).uniform(-2, 2, len(SYMS))
    want = _value(plain, point)
    assert abs(_value(factored, point) - want) <= 1e-12 * max(1.0, abs(want))
    assert _ops(factored) <= _ops(plain)


def test_factor_sum_takes_out_symbols_and_equal_coefficients():
    a, b, c, d = SYMS[:4]
    terms = [0.3 * a * b, 0.3 * a * c, -0.3 * a * d, 0.7 * b]
    # a out of 3 terms saves 2 multiplications, 0.3 out of the 3 in the bracket 2 more
    assert _ops(factor_sum(terms)) == _ops(se.Add(*terms)) - 4


def test_expand_pairs_uses_cos_of_sum_and_difference():
    """a cos(x + y) + b cos(x - y) with the products cx cy, sx sy, checked numerically."""
    cxcy, sxsy = se.symbols("cxcy sxsy")
    recipe = {"plus": ((1, cxcy), (-1, sxsy)), "minus": ((1, cxcy), (1, sxsy))}
    rng = np.random.default_rng(5)
    for a, b in [(0.7, -1.3), (2.0, 2.0), (2.0, -2.0)]:
        out = dict(expand_pairs([("plus", a), ("minus", b), ("other", 1.0)], recipe))
        assert out["other"] == 1.0
        x, y = rng.uniform(-3, 3, 2)
        got = (out.get(("p", cxcy), 0.0) * np.cos(x) * np.cos(y)
               + out.get(("p", sxsy), 0.0) * np.sin(x) * np.sin(y))
        assert got == pytest.approx(a * np.cos(x + y) + b * np.cos(x - y), abs=1e-14)
        assert len(out) == 1 + (a != b) + (a != -b)          # equal magnitudes: one product
    # one member alone stays a harmonic
    assert expand_pairs([("plus", 1.0)], recipe) == [("plus", 1.0)]


def test_private_products_and_dead_code():
    x, y, z, p, q, h = se.symbols("x y z p q h")
    factors = {p: (x, y), q: (y, z)}
    # p used by one sum only; q by two sums: only p is private
    assert private_products([[("p", p), ("p", q)], [("p", q)]], {}, factors) == {p}
    # a needed harmonic built from p makes p shared
    assert private_products([[("p", p)], [h]], {h: ((1, p), (1, q))}, factors) == set()
    kept = prune_dead([(p, x * y), (q, y * z), (h, p + 1)], [2 * h])
    assert [s for s, _ in kept] == [p, h]


@pytest.mark.parametrize("late", [False, True])
@pytest.mark.parametrize("name", ["puma560", "stanford"])
def test_factored_program_equals_rnea_and_the_c_count(name, late, monkeypatch):
    """Both orders (factoring before cse, and after it as for large programs), revolute and
    prismatic joints: EPS = 0 equals rnea to 1e-10 on 100 random states; the count equals the
    operators of the emitted C."""
    if late:
        monkeypatch.setattr(codegen, "LATE_FACTORING", 0)
    robot = load_robot(name)
    program = build_program(model_terms(derive(robot)), robot.n, np.zeros(robot.n),
                            prismatic=robot.prismatic)
    q, qd, qdd = random_states(robot, 100, 8)
    err = natural_error(python_tau(program)(q, qd, qdd), rnea(robot, q, qd, qdd))
    assert err.max() < 1e-10, err
    cost = program.cost()
    assert _c_operator_count(emit_c(program, {})) == (
        cost["multiplications"], cost["additions"], cost["sin"] + cost["cos"])


def test_full_puma_model_costs_less_than_the_hand_made_one_of_akb_1986():
    """Armstrong, Khatib & Burdick (ICRA 1986) wrote the full explicit PUMA 560 model by hand
    in 1165 operations (739 multiplications, 426 additions)."""
    robot = load_robot("puma560")
    cost = build_program(model_terms(derive(robot)), robot.n, np.zeros(robot.n)).cost()
    assert cost["multiplications"] + cost["additions"] < 1165


def test_sum_to_product_identities_hold_numerically():
    """cos/sin K1 +- cos/sin K2 with equal magnitudes, every sign case, on random angles: the
    products returned equal the pair they replace (A, B put in canonical form)."""
    rng = np.random.default_rng(9)
    theta = rng.uniform(-3, 3, (20, 3))

    def trig(key):
        arg = theta @ np.array(key[1:])
        return np.sin(arg) if key[0] else np.cos(arg)

    ks = [(1, 0, 1), (1, -2, 1), (0, 1, 1), (2, 1, -1), (1, 1, 0), (0, 0, 2)]
    count = 0
    for is_sin in (False, True):
        for i, k1 in enumerate(ks):
            for k2 in ks[i + 1:]:
                for c2 in (0.75, -0.75):
                    items = [((is_sin,) + k1, 0.75), ((is_sin,) + k2, c2)]
                    rest, prods = sum_to_product(items, lambda key: True)
                    want = sum(c * trig(k) for k, c in items)
                    got = sum(c * trig(k) for k, c in rest) + sum(
                        c * trig(ka) * trig(kb) for c, ka, kb in prods)
                    np.testing.assert_allclose(got, want, atol=1e-13)
                    count += len(prods)
    # every pair with K1 + K2 even is paired: both types, both signs
    even = sum(all((x + y) % 2 == 0 for x, y in zip(k1, k2))
               for i, k1 in enumerate(ks) for k2 in ks[i + 1:])
    assert even > 0 and count == 4 * even
    # nothing paired where A or B is not formed, or magnitudes differ
    items = [((False, 0, 1, 0), 0.5), ((False, 2, 1, 0), 0.5)]
    assert sum_to_product(items, lambda key: False) == (items, [])
    items = [((False, 0, 1, 0), 0.5), ((False, 2, 1, 0), 0.25)]
    assert sum_to_product(items, lambda key: True) == (items, [])
