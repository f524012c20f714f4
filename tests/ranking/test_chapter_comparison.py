"""The chapter's conclusions, counted (ranking/chapter_comparison.py).

Oracles: the ranking's own rule at each threshold s (rank_dominance, Sec. 3.4.1), Pinocchio's
half-models (translational and rotational parts, Sec. 3.4.1) and rnea for the chapter's own
simplified model, and hand-built shares."""

import numpy as np
import pytest
from conftest import random_states

from gd_analyze.dynamics.dalembert import gd_terms
from gd_analyze.ranking.chapter_comparison import (
    CHAPTER_CHOICES,
    agreement_against_s,
    block_leads,
    classify,
)
from gd_analyze.ranking.labels import element_labels
from gd_analyze.ranking.ranking import CHAPTER_DOMINANCE, rank_dominance


@pytest.mark.parametrize("s", [0.6, 0.75, 0.9, 0.99, 1.0])
def test_classify_is_the_rankings_rule_at_every_threshold(puma, s):
    q, qd, qdd = random_states(puma, 50, 4)
    terms = gd_terms(puma, q, qd)
    tau = terms.tau(qdd)
    ranking = rank_dominance(terms.D_tran, terms.D_rot, terms.h_tran, terms.h_rot, tau,
                             dominance=s)
    negligible = [c == "negligible" for c in ranking.dominance]
    assert classify(ranking.share_tran, negligible, s).tolist() == list(ranking.dominance)


def test_agreement_counts_the_rankings_classes_against_the_chapters(puma, shipped):
    terms = gd_terms(puma, shipped.q, shipped.qd)
    tau = terms.tau(shipped.qdd)
    s_values = (0.6, 0.8, 0.9, 0.99)
    ranked = [rank_dominance(terms.D_tran, terms.D_rot, terms.h_tran, terms.h_rot, tau,
                             dominance=s) for s in s_values]
    negligible = [c == "negligible" for c in ranked[0].dominance]
    grid, agree, compared = agreement_against_s(ranked[0].labels, ranked[0].share_tran,
                                                negligible, s_values)
    assert compared == len(CHAPTER_DOMINANCE) == 27
    want = [sum(c == CHAPTER_DOMINANCE[lab] for lab, c in zip(r.labels, r.dominance))
            for r in ranked]
    assert grid.tolist() == list(s_values) and agree.tolist() == want


def test_block_leads_on_hand_built_shares():
    labels = element_labels(4)          # arm block: joints 1-2, wrist: joints 3-4
    share = dict.fromkeys(labels, 0.5)
    share.update(D11=0.9, D12=0.6, D22=0.4, h1=0.7, h2=np.nan,     # D22 leads by rotation
                 D33=0.1, D34=0.3, D44=0.0, h3=0.8, h4=0.2,        # h3 leads by translation
                 D13=1.0, D24=0.0)                                 # couplings: neither block
    negligible = {lab: lab == "D34" for lab in labels}             # D34 not ranked
    b = block_leads(labels, [share[k] for k in labels], [negligible[k] for k in labels], n=4,
                    n_arm=2)
    assert b.arm == ("D11", "D12", "D22", "h1")
    assert b.arm_translation == ("D11", "D12", "h1")
    assert b.wrist == ("D33", "D44", "h3", "h4")
    assert b.wrist_rotation == ("D33", "D44", "h4")


def test_the_chapters_own_model_is_its_classes_on_pinocchios_half_models(puma):
    """tau_s from Pinocchio's translational and rotational half-models, each element of D and
    h reduced to the part the chapter names, c whole."""
    from gd_analyze.dynamics.pinocchio import reference_terms, relative_error
    from gd_analyze.simplify.choices import choice_masks, simplified_torque

    assert set(CHAPTER_CHOICES) == set(element_labels(6))
    q, qd, qdd = random_states(puma, 30, 9)
    ref = reference_terms(puma, q, qd)
    keep = {"translational": (1, 0), "rotational": (0, 1), "both": (1, 1)}
    Mt, Mr = np.zeros((6, 6)), np.zeros((6, 6))
    mt, mr = np.zeros(6), np.zeros(6)
    for label, cls in CHAPTER_DOMINANCE.items():
        t, r = keep[cls]
        i = int(label[1]) - 1
        j = int(label[2]) - 1 if label[0] == "D" else None
        if j is None:
            mt[i], mr[i] = t, r
        else:
            Mt[i, j] = Mt[j, i] = t
            Mr[i, j] = Mr[j, i] = r
    want = (np.einsum("kij,kj->ki", Mt * ref.D_tran + Mr * ref.D_rot, qdd)
            + mt * ref.h_tran + mr * ref.h_rot + ref.c)
    got = simplified_torque(gd_terms(puma, q, qd), CHAPTER_CHOICES, qdd)
    assert relative_error(got, want) < 1e-10
    assert np.array_equal(choice_masks(CHAPTER_CHOICES, 6)[0], Mt.astype(bool))


def test_bad_thresholds_are_refused():
    with pytest.raises(ValueError, match="must be in"):
        classify([0.5], [False], 0.5)
    with pytest.raises(ValueError, match="shape"):
        classify([0.5, 0.2], [False], 0.9)


def test_the_main_job_stores_what_the_chapter_comparison_counts(shipped_dataset):
    """results.h5 of the chapter's PUMA 560: the agreement at each s is the number of stored
    classes equal to the chapter's at the ranking's own s, and the block leads follow the
    stored shares; another arm stores none."""
    ds = shipped_dataset("puma560")
    labels = [str(v) for v in ds["element"].values]
    dominance = [str(v) for v in ds["dominance"].values]
    s = float(ds.attrs["dominance_threshold"])
    at = {float(v): int(a) for v, a in zip(ds["chapter_threshold"].values,
                                           ds["chapter_agreement"].values)}
    assert at[s] == sum(d == CHAPTER_DOMINANCE[lab] for lab, d in zip(labels, dominance))
    assert ds.attrs["chapter_elements_compared"] == 27
    share = dict(zip(labels, ds["share_tran"].values))
    arm = ds.attrs["chapter_arm_ranked"].split(", ")
    assert set(arm) == {lab for lab, d in zip(labels, dominance) if d != "negligible"
                        and max(int(c) for c in lab[1:]) <= 3}
    assert ds.attrs["chapter_arm_translation_leads"].split(", ") == [
        k for k in arm if share[k] > 0.5]
    assert "chapter_agreement" not in shipped_dataset("ur5").variables
