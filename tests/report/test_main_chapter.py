"""Sec. 6's conclusions (report/main_chapter.py): each sentence says what was counted.

Oracles: hand-built counts; the PUMA 560 report's own dataset, counted here from its stored
shares and classes, and Pinocchio's rnea for the chapter's model error
(tests/jobs/test_analyze.py checks the stored error against it)."""

import re

import numpy as np
import pytest
from html_checks import html_text

from gd_analyze.ranking.ranking import CHAPTER_DOMINANCE
from gd_analyze.report.main_context import chapter_conclusions
from gd_analyze.report.markup import plain
from gd_analyze.store.schema import open_results


def _blocks(arm_t=9, wrist_r=7):
    arm = ["D11", "D12", "D13", "D22", "D23", "D33", "h1", "h2", "h3"]
    wrist = ["D44", "D46", "D55", "D66", "h4", "h5", "h6"]
    return {"arm": arm, "arm_translation": arm[:arm_t], "wrist": wrist,
            "wrist_rotation": wrist[:wrist_r]}


def _say(blocks, **kw):
    args = dict(grid=[0.6, 0.9], agree=[13, 11], compared=27, n=6, s=0.9,
                chapter_error=np.array([0.2424, 0.0096, 0.0108, 0.0763, 0.0025, 1e-17]),
                chapter_off=[0, 0, 0, 0, 0, 1], built_error=np.full(6, 0.0036),
                built_off=np.zeros(6, bool))
    return [plain(t) for t in chapter_conclusions(blocks, **(args | kw))]


def test_the_arm_and_wrist_sentence_follows_the_counts():
    text = _say(_blocks())[0]
    assert "this run agrees:" in text and "9 of the 9" in text and "7 of the 7" in text
    text = _say(_blocks(wrist_r=5))[0]
    assert "agrees only in part" in text and "5 of the 7" in text and "others: h5, h6" in text


def test_the_agreement_sentence_gives_every_threshold_and_the_most():
    text = _say(_blocks(), grid=[0.6, 0.7, 0.9], agree=[13, 14, 11])[1]
    assert "13 at s = 0.6; 14 at s = 0.7; 11 at s = 0.9 (this report's)" in text
    assert "out of 27 elements" in text and "The most, 14, at s = 0.7." in text


def test_the_own_model_sentence_quotes_the_errors():
    text = _say(_blocks())[2]
    assert "up to 24.24 % of peak |τ1| at joint 1" in text
    assert "6: ≡ 0" in text and "against 0.36 %" in text


@pytest.mark.slow
def test_the_puma_report_states_what_its_dataset_holds(shared_puma):
    folder, stem = shared_puma["puma"]
    text = html_text((folder / f"{stem}.html").read_text(), nbsp=True)
    with open_results(folder / "results.h5", lazy=True) as ds:
        labels = [str(v) for v in ds["element"].values]
        share = ds["share_tran"].values
        dominance = [str(v) for v in ds["dominance"].values]
        chapter_err = ds["chapter_model_error_relative_peak"].values
    arm = [k for k, lab in enumerate(labels) if dominance[k] != "negligible"
           and max(int(c) for c in lab[1:]) <= 3]
    wrist = [k for k, lab in enumerate(labels) if dominance[k] != "negligible"
             and min(int(c) for c in lab[1:]) >= 4]
    n_arm_t = sum(share[k] > 0.5 for k in arm)
    n_wrist_r = sum(share[k] < 0.5 for k in wrist)
    assert (f"more than half of {n_arm_t} of the {len(arm)} ranked" in text)
    assert (f"more than half of {n_wrist_r} of the {len(wrist)} ranked" in text)
    agree = sum(d == CHAPTER_DOMINANCE[lab] for lab, d in zip(labels, dominance))
    assert f"{agree} at s = 0.9 (this report's)" in text
    worst = int(np.argmax(chapter_err))
    m = re.search(r"up to ([0-9.]+) % of peak \|τ\s*(\d)\s*\| at joint (\d)", text)
    assert m is not None and int(m.group(3)) == worst + 1
    assert abs(float(m.group(1)) - 100 * chapter_err[worst]) < 0.006
