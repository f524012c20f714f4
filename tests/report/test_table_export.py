"""Every report table as CSV (and LaTeX with --latex): the same numbers as the HTML report's
tables, hostile text neutralised (CSV formula injection, LaTeX's special characters)."""

import csv
import io
import re

from table_checks import csv_matches_html

from gd_analyze.report import markup
from gd_analyze.report.drawing import csv_cell, latex_text, table_files
from gd_analyze.report.sections import Outline

#: Robot and joint names a file may hold: formulas a spreadsheet would run, LaTeX commands.
HOSTILE = ['=HYPERLINK("http://x","y")', "+cmd|' /C calc'!A0", "-2+3", "@SUM(A1)",
           "\tTAB", "\\input{/etc/passwd} & 100% $x$ #1 _a ^b ~c {d}", "name <b>|"]


def _outline():
    o = Outline("t")
    o.section("1", "One")
    o.table({"header": ["joint", "peak |D" + markup.sub("ij") + "| [kg m²]"],
             "rows": [[h, "\u22121.5e\u221203"] for h in HOSTILE] + [["j", "0.25"]],
             "align": ["left", "right"]}, "Hostile names " + HOSTILE[5])
    o.section("2", "Two")
    o.table({"header": ["a", "b"], "rows": [["1", "2"]], "align": ["left", "left"]}, "Second.")
    return o


def test_csv_cells_never_start_a_formula():
    for h in HOSTILE[:5]:
        assert csv_cell(h) == "'" + h, h
    assert csv_cell("\u22121.5e\u221203") == "-1.5e-03"     # a number stays a number
    assert csv_cell("-0.25") == "-0.25" and csv_cell("12.5 %") == "12.5 %"
    assert csv_cell("D" + markup.sub("12")) == "D\u2081\u2082"


def test_tables_are_numbered_as_the_report_and_read_back():
    files = table_files(_outline())
    assert list(files) == ["table_1_1.csv", "table_2_1.csv"]
    rows = list(csv.reader(io.StringIO(files["table_1_1.csv"])))
    assert rows[0] == ["joint", "peak |Dᵢⱼ| [kg m²]"]          # header with its units
    assert [r[0] for r in rows[1:-1]] == ["'" + h for h in HOSTILE[:5]] + HOSTILE[5:]
    assert all(float(r[1]) == -1.5e-3 for r in rows[1:-1]) and rows[-1] == ["j", "0.25"]


def _balanced(tex):
    depth = 0
    for c in re.sub(r"\\[{}]", "", tex):
        depth += {"{": 1, "}": -1}.get(c, 0)
        if depth < 0:
            return False
    return depth == 0


def test_latex_escapes_every_special_character():
    files = table_files(_outline(), latex=True)
    assert list(files) == ["table_1_1.csv", "table_1_1.tex", "table_2_1.csv", "table_2_1.tex"]
    tex = files["table_1_1.tex"]
    assert _balanced(tex)
    assert r"\label{tab:gd-1.1}" in tex and r"\textsubscript{ij}" in tex
    for h in HOSTILE:
        body = latex_text(h)
        assert _balanced(body), h
        # no special character left bare: each is escaped or a command of the escape table
        bare = re.sub(r"\\(textbackslash|textasciitilde|textasciicircum|textless|textgreater|"
                      r"textbar)\{\}|\\[&%$#_{}]", "", body)
        assert not re.search(r"[\\&%$#_^~{}<>|]", bare), (h, body)
    # the rows: cells separated by & and ended by \\ , as many cells as header columns
    rows = [ln for ln in tex.splitlines() if ln.endswith(r" \\")]
    assert len(rows) == 1 + len(HOSTILE) + 1
    assert all(len(re.split(r"(?<!\\)&", r)) == 2 for r in rows)


def test_csv_files_hold_the_html_tables_numbers(shared_puma):
    folder, _ = shared_puma["puma"]
    html = (folder / "report.html").read_text(encoding="utf-8")
    assert csv_matches_html(folder / "tables", "table_", html) > 100


def test_reports_sharing_a_folder_name_their_tables_apart():
    files = table_files(_outline(), latex=True, prefix="control")
    assert list(files) == ["control_table_1_1.csv", "control_table_1_1.tex",
                           "control_table_2_1.csv", "control_table_2_1.tex"]
    assert r"\label{tab:gd-control-1.1}" in files["control_table_1_1.tex"]
    assert files["control_table_1_1.csv"] == table_files(_outline())["table_1_1.csv"]
