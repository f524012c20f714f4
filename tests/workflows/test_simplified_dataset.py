"""What the main job stores about its simplified model (workflows/simplified_dataset.py)."""

from types import SimpleNamespace

from gd_analyze.workflows.simplified_dataset import cost_rows


def _cost(m, a):
    return {"multiplications": m, "additions": a, "sin": 4, "cos": 4}


def test_cost_table_lists_each_model_once():
    """Issue 31: Table 5.4 listed "explicit, budget ε = 0.01" beside "explicit, budget ε = 0.01
    (this model)", and the ladder's ε = 0 beside the full model, the same counts twice. A rung
    that is the deployed model or the full one is listed once, as such; a rung that differs
    stays."""
    counts = {k: _cost(1, 1) for k in ("gd", "newton-euler", "lagrange-euler")}
    model = SimpleNamespace(costs={}, tolerance=0.01, form="explicit", rule="budget",
                            full_cost=_cost(473, 397), cost=_cost(142, 92),
                            robot=SimpleNamespace(name="arm"))
    ladder = [{"tolerance": t, **c} for t, c in ((0.0, _cost(473, 397)), (0.001, _cost(309, 218)),
                                                 (0.01, _cost(142, 92)), (0.05, _cost(59, 34)))]
    rows = cost_rows(6, model, ladder_rows=ladder, formulation_counts=counts)
    explicit = {k: v for k, v in rows.items() if k.startswith("explicit")}
    assert list(explicit) == ["explicit, full", "explicit, budget EPS=0.001",
                              "explicit, budget EPS=0.05", "explicit, budget EPS=0.01 (this model)"]
    assert len(set(explicit.values())) == len(explicit)
    ladder[2] = {"tolerance": 0.01, **_cost(150, 92)}          # a rung of other counts stays
    rows = cost_rows(6, model, ladder_rows=ladder, formulation_counts=counts)
    assert "explicit, budget EPS=0.01" in rows
