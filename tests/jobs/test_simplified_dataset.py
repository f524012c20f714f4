"""What the main job stores about its simplified model (jobs/simplified_dataset.py)."""

from types import SimpleNamespace

import numpy as np

from gd_analyze.jobs.simplified_dataset import cost_rows


def _cost(m, a):
    return {"multiplications": m, "additions": a, "sin": 4, "cos": 4}


def test_cost_table_lists_each_model_once():
    """Table 5.4 listed "explicit, budget ε = 0.01" beside "explicit, budget ε = 0.01
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


def test_choice_of_a_recursive_model_names_the_elements_its_dropped_terms_change(
        puma, shipped, puma_analysis):
    """Results.h5 stored choice "both" for all 27 elements although the model drops
    XY2's inertial and velocity parts. Oracle: the base regressor (Khalil & Kleinfinger;
    Gautier): a dropped inertial part changes D_ij where its column at qdd = e_j moves tau_i,
    a velocity part changes h_i where its column at qdd = 0, g = 0 moves tau_i."""
    import dataclasses

    from gd_analyze.dynamics.base_parameters import base_parameters, base_regressor

    ds = puma_analysis.dataset          # the session's analysis (default options), read only
    dropped = {}
    for pair in str(ds.attrs["simplified_dropped_pairs"]).split(", "):
        name, part = pair[:-1].split(" (")
        dropped.setdefault(name, set()).add(part)
    assert dropped                                                   # the case at hand
    base = base_parameters(puma)          # the columns of the dropped names, g = 0 or not
    names = base.names()
    q, qd = shipped.q[::3], shipped.qd[::3]
    still = dataclasses.replace(puma, gravity=np.zeros(3))
    n, changed = 6, set()
    for name, parts in dropped.items():
        k = names.index(name)
        if "velocity" in parts:
            Y, beta = base_regressor(still, q, qd, np.zeros_like(q), base)
            for i in range(n):
                if np.abs(Y[:, i, k] * beta[k]).max() > 1e-9:
                    changed.add(f"h{i + 1}")
        if "inertial" in parts:
            for j in range(n):
                acc = np.zeros_like(q)
                acc[:, j] = 1.0
                Y, beta = base_regressor(still, q, np.zeros_like(q), acc, base)
                for i in range(j + 1):
                    if np.abs(Y[:, i, k] * beta[k]).max() > 1e-9:
                        changed.add(f"D{i + 1}{j + 1}")
    choice = dict(zip((str(v) for v in ds["element"].values),
                      (str(v) for v in ds["choice"].values)))
    assert {lab for lab, c in choice.items() if c == "pruned"} == changed
    assert {c for lab, c in choice.items() if lab not in changed} == {"both"}
