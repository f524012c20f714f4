"""The element-level simplified model (simplify/choices.py): masks, torques and merging.

Oracles: Pinocchio's rnea (every part kept), its generalized gravity (no part kept), its
half-models (translational or rotational parts only, Sec. 3.4.1) and the chapter's two-link
closed forms."""

import itertools

import chapter_two_link
import numpy as np
import pinocchio as pin
import pytest
from conftest import random_states

from gd_analyze.dynamics.dalembert import gd_terms
from gd_analyze.dynamics.pinocchio import pinocchio_model, reference_terms, relative_error
from gd_analyze.ranking.labels import element_labels
from gd_analyze.simplify.choices import (
    CHOICES,
    choice_masks,
    full_choices,
    merge_choices,
    simplified_torque,
)

TOL = 1e-10


def _uniform(n, choice):
    return {label: choice for label in element_labels(n)}


def test_masks_are_symmetric_and_select_what_each_choice_names():
    n = 4
    rng = np.random.default_rng(3)
    choices = {label: CHOICES[k] for label, k in
               zip(element_labels(n), rng.integers(0, 4, len(element_labels(n))))}
    Mt, Mr, mt, mr = choice_masks(choices, n)
    np.testing.assert_array_equal(Mt, Mt.T)
    np.testing.assert_array_equal(Mr, Mr.T)
    for i, j in itertools.product(range(n), repeat=2):
        ch = choices[f"D{min(i, j) + 1}{max(i, j) + 1}"]
        assert Mt[i, j] == (ch in ("tran", "both")) and Mr[i, j] == (ch in ("rot", "both"))
    for i in range(n):
        ch = choices[f"h{i + 1}"]
        assert mt[i] == (ch in ("tran", "both")) and mr[i] == (ch in ("rot", "both"))


def test_full_choices_give_rnea_and_no_choices_give_gravity(puma):
    q, qd, qdd = random_states(puma, 60, 5)
    terms = gd_terms(puma, q, qd)
    model = pinocchio_model(puma)
    data = model.createData()
    rnea = np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])
    grav = np.array([pin.computeGeneralizedGravity(model, data, a) for a in q])
    assert full_choices(puma.n) == _uniform(puma.n, "both")
    assert relative_error(simplified_torque(terms, full_choices(puma.n), qdd), rnea) < TOL
    assert relative_error(simplified_torque(terms, _uniform(puma.n, "none"), qdd), grav) < TOL


def test_one_part_everywhere_is_pinocchios_half_model_plus_gravity(puma):
    q, qd, qdd = random_states(puma, 40, 6)
    terms = gd_terms(puma, q, qd)
    ref = reference_terms(puma, q, qd)
    for part in ("tran", "rot"):
        D, h = getattr(ref, f"D_{part}"), getattr(ref, f"h_{part}")
        want = np.einsum("kij,kj->ki", D, qdd) + h + ref.c
        got = simplified_torque(terms, _uniform(puma.n, part), qdd)
        assert relative_error(got, want) < TOL, part


def test_dropping_one_element_part_removes_exactly_its_chapter_term():
    """Two-link arm, D12 rotational part dropped: tau_1 loses I_2 qdd_2 and tau_2 loses
    I_2 qdd_1 (I_2 = m_2 l^2/12, the closed form's D_rot12)."""
    m1, m2, l = 1.3, 0.7, 0.9
    from gd_analyze.model.robot_spec import robot_from_dict

    robot = robot_from_dict(chapter_two_link.spec(m1, m2, l))
    rng = np.random.default_rng(8)
    q, qd, qdd = rng.uniform(-3, 3, (3, 20, 2))
    choices = full_choices(2) | {"D12": "tran"}
    got = simplified_torque(gd_terms(robot, q, qd), choices, qdd)
    D_tran, D_rot, h_tran, h_rot, c = chapter_two_link.terms(q, qd, m1, m2, l)
    D = D_tran + D_rot
    D[:, 0, 1] -= m2 * l * l / 12
    D[:, 1, 0] -= m2 * l * l / 12
    want = np.einsum("kij,kj->ki", D, qdd) + h_tran + h_rot + c
    assert relative_error(got, want) < TOL


def test_bad_choices_are_named():
    with pytest.raises(ValueError, match="no choice for element D22"):
        choice_masks({"D11": "both", "D12": "both", "h1": "both", "h2": "both"}, 2)
    with pytest.raises(ValueError, match="element h1"):
        choice_masks(full_choices(1) | {"h1": "translational"}, 1)


def test_merge_keeps_every_part_some_model_keeps():
    """Exhaustive over two models of one element: the merged choice keeps the union."""
    keeps = {"tran": {"tran"}, "rot": {"rot"}, "both": {"tran", "rot"}, "none": set()}
    name = {frozenset(v): k for k, v in keeps.items()}
    for a, b in itertools.product(CHOICES, repeat=2):
        merged = merge_choices([{"D11": a, "h1": "none"}, {"D11": b, "h1": "none"}])
        assert merged == {"D11": name[frozenset(keeps[a] | keeps[b])], "h1": "none"}


def test_merged_masks_cover_each_models_masks(puma):
    """The merged model drops a subset of every model's dropped parts (its masks are >= each
    model's), so it is at least as complete as each of them."""
    rng = np.random.default_rng(9)
    labels = element_labels(puma.n)
    models = [{lab: CHOICES[k] for lab, k in zip(labels, rng.integers(0, 4, len(labels)))}
              for _ in range(3)]
    merged = merge_choices(models)
    Mm = choice_masks(merged, puma.n)
    for own in models:
        for m_merged, m_own in zip(Mm, choice_masks(own, puma.n)):
            assert np.all(m_merged >= m_own)
    with pytest.raises(ValueError, match="no simplified models"):
        merge_choices([])


def test_a_recursive_models_choices_say_pruned_where_its_d_or_h_differ_from_pinocchios(puma,
                                                                                       shipped):
    """recursive_choices and sweep_choices: "pruned" exactly where the model's D_s or h_s
    differs from Pinocchio's crba or nonLinearEffects minus gravity beyond 1e-9 of the
    element's scale at the compared set points, "both" elsewhere; an exact model (EPS = 0) is
    "both" everywhere."""
    from gd_analyze.simplify.choices import recursive_choices, sweep_choices
    from gd_analyze.simplify.deploy import build_recursive

    q, qd, qdd = shipped.q, shipped.qd, shipped.qdd
    pm = pinocchio_model(puma)
    data = pm.createData()
    D = np.array([pin.crba(pm, data, x) for x in q])
    D = np.triu(D) + np.swapaxes(np.triu(D, 1), 1, 2)
    h = np.array([pin.nonLinearEffects(pm, data, a, b) - pin.computeGeneralizedGravity(pm, data, a)
                  for a, b in zip(q, qd)])
    n, iu = puma.n, np.triu_indices(puma.n)
    diag = np.sqrt(np.abs(np.einsum("kii->ki", D)))
    scale = np.concatenate([(diag[:, iu[0]] * diag[:, iu[1]]).max(axis=0),
                            np.abs(h + [pin.computeGeneralizedGravity(pm, data, a) for a in q]
                                   + np.einsum("kij,kj->ki", D, qdd)).max(axis=0)])
    labels = element_labels(n)
    for eps in (0.0, 0.05):
        model = build_recursive(puma, q, qd, qdd, tolerance=eps)[0]
        fns = model.functions().numpy()
        D_s = np.asarray(fns["inertia"](q), float).reshape(-1, n, n)
        h_s = np.asarray(fns["velocity_terms"](q, qd), float).reshape(-1, n)
        diff = np.concatenate([np.abs(D_s - D).max(axis=0)[iu], np.abs(h_s - h).max(axis=0)])
        want = {lab: "pruned" if d > 1e-9 * s else "both"
                for lab, d, s in zip(labels, diff, scale)}
        ranking = type("R", (), {"labels": labels, "scale": scale})
        got = recursive_choices(model, q, qd, gd_terms(puma, q, qd), ranking)
        assert got == want
        assert ("pruned" in got.values()) == (eps > 0)
        swept = sweep_choices(model, [shipped], setpoints=len(q)).choices
        assert swept == want


def test_torque_in_blocks_is_the_masks_on_the_whole_arrays(puma, monkeypatch):
    """simplified_torque runs block by block; every row is computed alone, so the torques are
    bit for bit those of the masks applied to the whole arrays, across uneven blocks."""
    import gd_analyze.simplify.choices as choices_module
    from gd_analyze.dynamics.dalembert import assemble_tau

    q, qd, qdd = random_states(puma, 11, 9)
    terms = gd_terms(puma, q, qd)
    rng = np.random.default_rng(2)
    choices = {label: CHOICES[k] for label, k in
               zip(element_labels(puma.n), rng.integers(0, 4, len(element_labels(puma.n))))}
    Mt, Mr, mt, mr = choice_masks(choices, puma.n)
    whole = assemble_tau(Mt * terms.D_tran + Mr * terms.D_rot,
                         mt * terms.h_tran + mr * terms.h_rot, terms.c, qdd)
    monkeypatch.setattr(choices_module, "_BLOCK", 4)
    got = simplified_torque(terms, choices, qdd)
    assert got.shape == (11, puma.n) and np.array_equal(got, whole)
