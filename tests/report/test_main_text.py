"""The report's sentences (gd_analyze.report.main_text): the conclusion's cost clause."""

import re

import numpy as np

from gd_analyze.report.main_text import conclusion

ARGS = (["D11", "h1"], ["translational", "rotational"], np.zeros(2, bool), ["tran", "rot"],
        np.array([0.004]), np.array([0.02]), np.array([5.0]))


def test_cost_against_newton_euler_both_ways_and_without():
    cheaper = conclusion(*ARGS, cost=(348, 260, 1212))
    assert "costs 608 operations per set point" in cheaper
    assert "against Newton-Euler's 1,212" in cheaper and "use Newton-Euler" not in cheaper
    dearer = conclusion(*ARGS, cost=(61149, 93750, 1452))
    assert "costs 154,899 operations" in dearer
    assert "more than Newton-Euler's 1,452: for speed, use Newton-Euler" in dearer
    unknown = conclusion(*ARGS, cost=(10, 5, None))
    assert "costs 15 operations" in unknown and "Newton-Euler" not in unknown
    assert "costs" not in conclusion(*ARGS)
    for text in (cheaper, dearer, unknown):
        assert text.count(". ") == 2 and text.endswith(".")      # still three sentences


def test_a_value_and_its_unit_are_never_split_over_two_lines():
    """The Stanford summary's "(0.0218 N m of 4.9 N m)" broke after "4.9 N" in the PDF: in the
    conclusion every number is joined to its unit, and a unit's words to each other, by
    no-break spaces (Unicode line breaking never breaks at U+00A0)."""
    text = conclusion(["D11", "h1", "h2"], ["translational"] * 3, np.zeros(3, bool),
                      ["tran"] * 3, np.array([0.00445, 0.00239]), np.array([0.0218, 0.157]),
                      np.array([4.9, 92.9]), units=["N m", "N"])
    assert "4.9\u00a0N\u00a0m" in text and "0.0218\u00a0N\u00a0m" in text
    assert not re.search(r"\d (N|m|kg|%)(\W|$)", text), text
    assert "N m" not in text
    small = conclusion(*ARGS[:4], np.array([0.5, 1e-4]), np.array([1e-4, 1e-3]),
                       np.array([2e-4, 10.0]), units=["N m", "N m"])
    assert "(10\u00a0N\u00a0m)" in small and not re.search(r"\d (N|m|%)(\W|$)", small), small


def test_summary_letters_elements_as_mathematics_with_agreeing_verbs():
    """Oracle: the labels and classes given. Each element is D₁₂ (subscript marked, as Table
    4.1 and the figures letter it), never the code name D12; "1 of 6 elements is", "1 needs";
    "≡ 0" stays on the line of its last element (the PUMA summary broke "D56 ≡" / "0")."""
    from gd_analyze.report.markup import html, plain, unicode

    labels = ["D11", "D12", "D22", "h1", "h2"]
    text = conclusion(labels, ["translational", "negligible", "both", "rotational", "both"],
                      np.array([False, False, True, False, False]),
                      ["tran", "none", "none", "rot", "both"], np.array([0.01, 0.02]),
                      np.array([0.1, 0.2]), np.array([1.0, 2.0]))
    shown = unicode(text)
    assert not re.search(r"\b[Dh][0-9]", shown), shown
    for lab in ("D₁₁", "D₁₂", "D₂₂", "h₁"):
        assert lab in shown, (lab, shown)
    assert "D<sub>12</sub>" in str(html(text))
    assert "1 of 3 elements is dominated" in plain(text)
    assert "2 are negligible (D12; D22\u00a0\u2261\u00a00)" in plain(text)
    assert "0 need both" in plain(text)
    assert "0 of 2 elements are dominated" in plain(text) and "1 needs both" in plain(text)
    assert "D₂₂\u00a0\u2261\u00a00" in shown


def test_round_off_threshold_is_written_as_a_power_of_ten():
    """Sec. 4 states the ranking's round-off threshold (core ROUND_OFF) as mathematics,
    10⁻¹², not as the code literal 1e-12."""
    import math

    from gd_analyze.ranking.ranking import ROUND_OFF
    from gd_analyze.report.common import say
    from gd_analyze.report.markup import unicode

    k = round(math.log10(ROUND_OFF))
    power = "10" + "".join("\u207b" if c == "-" else "\u2070\u00b9\u00b2\u00b3\u2074\u2075"
                           "\u2076\u2077\u2078\u2079"[int(c)] for c in str(k))
    for arm in (False, True):
        text = unicode(say("ranking_text", s="0.9", e="0.01", arm=arm))
        assert f"below {power} of its scale" in text, text
        assert not re.search(r"\de-?\d", text), text


def test_chapter_disagreement_causes_state_true_inequalities():
    """Table 6.1's causes: every share they quote is the element's own (four decimals, as the
    table), every inequality they state holds for it, and the PUMA 560's disagreements are put
    down to its parameters and trajectory not being the chapter's (the old 'rotor-side
    inertias lumped into the links' was refuted by the puma560-drives run, README)."""
    from gd_analyze.report.main_text import disagreement_cause
    from gd_analyze.report.numbers import share as share_text

    s = 0.9
    cases = [("D11", "both", "translational", 0.7462), ("D24", "translational", "both", 0.9709),
             ("D46", "rotational", "both", 0.0123), ("D55", "both", "rotational", 0.1435),
             ("h1", "both", "translational", 0.8717)]
    ops = {">": lambda a, b: a > b, "\u2265": lambda a, b: a >= b,
           "\u2264": lambda a, b: a <= b}
    for label, ours, theirs, sh in cases:
        text = disagreement_cause(label, ours, theirs, sh, False, s, "puma560")
        m = re.match(r"(translational|rotational) share (\S+) (\S) (?:1 \u2212 )?s = (\S+);",
                     text)
        assert m, text
        part, shown, op, bound = m.groups()
        value = sh if part == "translational" else 1.0 - sh
        assert shown == share_text(value), text
        threshold = 1 - s if "1 \u2212 s" in text.split(";")[0] else s
        assert abs(float(bound) - threshold) < 1e-12
        assert ops[op](value, threshold), text
        if label.startswith("D"):
            assert "not the chapter's" in text and "rotor" not in text, text


def test_an_error_that_is_round_off_everywhere_is_said_so_not_ranked():
    """A 15-joint chain's exact model read "Its largest open-loop torque error ... is ≡ 0 of
    peak |τ| at joint 5 (≡ 0 N m of 6.043 N m); every other joint is within ≡ 0": where the
    stored round-off marks cover every joint, no joint is named as the largest."""
    labels, dom, zero, choice = (["D11", "h1", "h2", "h3"], ["translational"] * 4,
                                 np.zeros(4, bool), ["tran"] * 4)
    rel, err, tau = np.array([3e-17, 1e-16, 2e-17]), np.array([1e-16, 3e-16, 1e-16]), \
        np.array([4.0, 3.0, 6.0])
    exact = conclusion(labels, dom, zero, choice, rel, err, tau, round_off=[True] * 3)
    assert "is \u2261\u00a00 at every joint (round-off only)" in exact
    assert "largest" not in exact and "every other joint" not in exact
    assert exact.count(". ") == 2 and exact.endswith(".")
    one = conclusion(labels, dom, zero, choice, np.array([3e-17, 0.004, 2e-17]), err, tau,
                     round_off=[True, False, True])
    assert "at joint 2" in one and "every other joint's is \u2261\u00a00" in one
    plain = conclusion(labels, dom, zero, choice, np.array([0.001, 0.004, 0.002]), err, tau,
                       round_off=[False] * 3)
    assert "at joint 2" in plain and "every other joint is within 0.2" in plain
    assert plain == conclusion(labels, dom, zero, choice, np.array([0.001, 0.004, 0.002]), err,
                               tau)


def test_the_leading_part_is_named_only_when_it_leads():
    """Oracle: the counts of the classes given. A class leads when it holds more ranked
    elements than each other class; on a tie none is named (h below: 1 rotational, 1 both, which
    read "rotational effects lead"), nor when every element is negligible or ≡ 0 (an arm without
    inertia read "translational effects lead" with no element translational). Elements that
    need both parts are "most" only where they are more than half of those ranked (one ranked
    element read "most ranked elements need both parts")."""
    from gd_analyze.report.markup import plain

    def lead(labels, classes, zero):
        text = plain(conclusion(labels, classes, np.array(zero), ["none"] * len(labels),
                                np.array([0.01]), np.array([0.1]), np.array([1.0])))
        return [part.split(" — ")[1] for part in text.split(".")[0].split(";") if " — " in part]

    assert lead(["D11", "D12", "D22", "h1", "h2"],
                ["translational", "negligible", "rotational", "rotational", "both"],
                [False] * 5) == ["no part leads: the classes translational and rotational tie at 1 each",
                                 "no part leads: the classes rotational and both tie at 1 each"]
    assert lead(["D11", "h1"], ["negligible", "negligible"], [True, False]) == [
        "no part leads, for no element is ranked"] * 2
    assert lead(["D11", "D12", "D22", "h1"], ["both", "both", "rotational", "translational"],
                [False] * 4) == ["most ranked elements need both parts", "translational effects lead"]
    # "most" only where more than half the ranked elements need both parts
    assert lead(["D11", "D12", "D22", "h1", "h2"], ["both", "negligible", "negligible", "both",
                                                     "both"], [False] * 5) == [
        "its one ranked element needs both parts", "every ranked element needs both parts"]
    assert lead(["D11", "D12", "D21", "D22", "D31", "D32", "D33", "h1"],
                ["both", "both", "both", "translational", "translational", "rotational",
                 "rotational", "translational"], [False] * 8) == [
        "more ranked elements need both parts than either part alone",
        "translational effects lead"]
    assert lead(["D11", "D12", "D22", "h1", "h2"],
                ["rotational", "translational", "rotational", "rotational", "rotational"],
                [False] * 5) == ["rotational effects lead", "rotational effects lead"]


def test_operation_counts_agree_in_number_with_their_words():
    """Oracle: the counts given. A count of one is singular (a one-joint arm's model of
    2 multiplications and 1 addition read "1 additions"); the plural text is kept."""
    from gd_analyze.report.markup import plain

    one = plain(conclusion(*ARGS, cost=(1, 1, None)))
    assert "costs 2 operations per set point (1 multiplication, 1 addition)" in one
    single = plain(conclusion(*ARGS, cost=(1, 0, None)))
    assert "costs 1 operation per set point (1 multiplication, 0 additions)" in single
    assert "(348 multiplications, 260 additions)" in plain(conclusion(*ARGS, cost=(348, 260, 1212)))


def test_a_model_with_no_contribution_is_not_said_to_drop_none_of_zero():
    """Oracle: the counts given. An arm without inertia has no (parameter, part) pair acting:
    it read "of the 0 inertial, velocity and gravity parts ..., it drops none"."""
    from gd_analyze.report.main_text import model_sentence
    from gd_analyze.report.markup import plain

    assert plain(model_sentence(recursive=(8, 0, 0))) == (
        "The simplified model is the recursive Newton-Euler model on 8 base parameters; no "
        "inertial, velocity or gravity part of their contributions acts on this trajectory, so "
        "it drops none: it is exact.")
    assert plain(model_sentence(recursive=(8, 0, 4))) == (
        "The simplified model is the recursive Newton-Euler model on 8 base parameters; of the "
        "4 inertial, velocity and gravity parts of their contributions that act on this "
        "trajectory, it drops none: it is exact.")


def test_a_small_joint_torque_is_compared_only_with_torques_of_its_units():
    """Oracle: the peaks and units given. A prismatic joint's 0.5 N read "under 1 % of the
    largest joint's (100 N m)": a force against a torque; between joints of one unit the
    clause stays."""
    from gd_analyze.report.markup import plain

    def text(units):
        return plain(conclusion(["D11", "D12", "D22", "h1", "h2"], ["both"] * 5,
                                np.zeros(5, bool), ["both"] * 5, np.array([1e-4, 0.2]),
                                np.array([1e-2, 0.1]), np.array([100.0, 0.5]), units=units))

    assert "under 1" not in text(["N m", "N"])
    assert "that joint's own torque is under 1\u00a0% of the largest joint's (100\u00a0N\u00a0m)" \
        in text(["N m", "N m"])


def test_none_of_the_elements_takes_the_verb_of_their_count():
    """Oracle: the counts given. "0 of 1 element is dominated", "0 of 3 elements are", "1 of
    3 elements is" (a one-joint arm read "0 of 1 element are dominated")."""
    from gd_analyze.report.markup import plain

    def said(labels, classes):
        return plain(conclusion(labels, classes, np.zeros(len(labels), bool),
                                ["none"] * len(labels), np.array([0.01]), np.array([0.1]),
                                np.array([1.0])))

    assert "in D, 0 of 1 element is dominated" in said(["D11", "h1"], ["both", "both"])
    assert "in h, 0 of 1 element is dominated" in said(["D11", "h1"], ["both", "both"])
    three = said(["D11", "D12", "D22", "h1"], ["both", "rotational", "both", "translational"])
    assert "in D, 0 of 3 elements are dominated" in three
    assert "in h, 1 of 1 element is dominated" in three


def test_fig_1_names_the_joints_that_move_alike_and_sec_5_keeps_c_whole():
    """Fig. 1's caption says which joints' curves coincide, one sentence per group; the
    intro of Sec. 5 of an explicit chapter-rule model says it keeps c whole."""
    from gd_analyze.report.common import say
    from gd_analyze.report.main_text import gravity_clause
    from gd_analyze.report.markup import plain

    assert say("alike_sentence", groups=[]) == ""
    assert (say("alike_sentence", groups=[[1, 5]])
            == " Joints 1 and 5 move alike: their curves coincide.")
    assert (say("alike_sentence", groups=[[1, 3, 6]])
            == " Joints 1, 3 and 6 move alike: their curves coincide.")
    intro = say("simplified_intro", form="explicit", gravity=gravity_clause("chapter"),
                weightless=False)
    assert plain(intro.split("; ")[-1]) == "it keeps c whole: \u03c4s = Ds q\u0308 + hs + c."
