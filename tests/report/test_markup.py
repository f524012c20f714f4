"""The markup of the core's plain-text statements in the reports."""

from gd_analyze.report.markup import scope, sub


def test_a_percentage_is_not_broken_from_its_number():
    """"within 1 % of s_i" could break a line between "1" and "%": the space before % is a
    non-breaking one (U+00A0) wherever a statement is set, in HTML and PDF alike."""
    said = scope("within 1 % of s_i at every state of the region; 12.5 % below")
    assert said == ("within 1\u00a0% of s" + sub("i") + " at every state of the region; "
                    "12.5\u00a0% below")
