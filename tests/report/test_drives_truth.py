"""The report of an arm with drives says what its data hold.

The PUMA 560 with its drives (``puma560-drives``): Sec. 4 stated the share as
Σ|tran| / (Σ|tran| + Σ|rot|) while the stored share counts the armature; Fig. 2's lead-in
summed D_ij without it; Table 5.2 called the diagonal elements "dropped (negligible)" while the
model keeps their armature; "D^arm" and "τ_f" appeared as literal markup. Oracles: the stored
series (D_tran, D_rot, D_arm), and the model file's own statement that it keeps the armature.
"""

import numpy as np
import pytest
import xarray as xr
from conftest import SHIPPED

from gd_analyze.cli import main
from gd_analyze.report.main import main_outline
from gd_analyze.report.main_context import report_context
from gd_analyze.report.markup import unicode


@pytest.fixture(scope="module")
def drives(tmp_path_factory):
    folder = tmp_path_factory.mktemp("drives")
    assert main(["puma560-drives", str(SHIPPED), "-o", str(folder), "-q", "--no-report",
                 "--form", "explicit"]) == 0
    with xr.open_dataset(folder / "results.h5") as ds:
        ds = ds.load()
    ctx = report_context(ds)
    return ds, ctx, main_outline(ctx, figures=())


def _section(outline, number):
    return next(s for s in outline.sections if s.number == number)


def _paragraphs(section):
    return [unicode(b.content) for b in section.blocks if b.kind == "paragraph"]


def _table(section, index=0):
    return [b.content for b in section.blocks if b.kind == "table"][index]


def _diagonal(ds):
    labels = [str(v) for v in ds["element"].values]
    return {f"D{i}{i}": labels.index(f"D{i}{i}") for i in range(1, ds.sizes["joint"] + 1)}


def test_the_stated_share_is_the_stored_share(drives):
    ds, _, outline = drives
    text = " ".join(_paragraphs(_section(outline, "4")))
    assert "Σ|Xᵗʳᵃⁿ| / (Σ|Xᵗʳᵃⁿ| + Σ|Xʳᵒᵗ + Xᵃʳᵐ|)" in text, text
    tran, rot = ds["D_tran"].values, ds["D_rot"].values
    arm = ds["D_arm"].values
    for lab, k in _diagonal(ds).items():
        i = int(lab[1]) - 1
        t = np.abs(tran[:, i, i]).sum()
        stated = t / (t + np.abs(rot[:, i, i] + arm[i]).sum())      # the formula as stated
        np.testing.assert_allclose(ds["share_tran"].values[k], stated, rtol=1e-9)
        a = np.abs(np.full(tran.shape[0], arm[i])).sum()
        np.testing.assert_allclose(ds["share_arm"].values[k],
                                   a / (t + np.abs(rot[:, i, i] + arm[i]).sum()), rtol=1e-9)


def test_the_armature_has_its_own_share_column(drives):
    ds, _, outline = drives
    table = _table(_section(outline, "4"))
    header = [unicode(h) for h in table["header"]]
    assert "armature share" in header and "peak |Xᵃʳᵐ|" in header
    col = header.index("armature share")
    rows = {unicode(r[0]): r for r in table["rows"]}
    for lab, k in _diagonal(ds).items():
        shown = rows["D" + "".join(chr(0x2080 + int(c)) for c in lab[1:])][col]
        assert abs(float(shown) - ds["share_arm"].values[k]) <= 5e-5, (lab, shown)


def test_elements_whose_armature_is_kept_are_not_called_dropped(drives):
    ds, _, outline = drives
    table = _table(_section(outline, "5.2"))
    header = table["header"]
    assert header[:3] == ["element", "class", "kept part"] and "armature" in header
    diag = {"D" + "".join(chr(0x2080 + int(c)) for c in lab[1:]) for lab in _diagonal(ds)}
    for row in table["rows"]:
        label, cls, meaning = unicode(row[0]), row[1], row[-1]
        if label in diag:
            assert row[header.index("armature")] == "kept"
            assert "negligible" not in meaning or cls == "negligible", row
    assert any(r[2] == "none" and unicode(r[0]) in diag for r in table["rows"])  # the case


def test_fig_2_lead_in_sums_the_armature(drives):
    _, _, outline = drives
    text = " ".join(_paragraphs(_section(outline, "2")))
    assert "Dᵢⱼ = Dᵢⱼᵗʳᵃⁿ + Dᵢⱼʳᵒᵗ + Dᵢⱼᵃʳᵐ" in text, text


def test_no_literal_markup_in_the_text(drives):
    _, _, outline = drives
    for section in outline.sections:
        for text in _paragraphs(section):
            assert "^" not in text and "τ_f" not in text and "D_ii" not in text, text
        for block in section.blocks:
            if block.kind == "table":
                for cell in block.content["header"]:
                    assert "_" not in unicode(cell) and "^" not in unicode(cell), cell


def test_table_6_1_says_each_cause_once(drives):
    """Table 6.1 repeated "peak below e times its scale, so no part is ranked; the
    chapter has no negligible class" in every negligible row. Each cause is written once (in
    the note or in one row); rows refer to it by its mark. Oracle: the stored classes (every
    negligible element disagrees for the same reason)."""
    ds, ctx, _ = drives
    rows = ctx["compare"]["table"]["rows"]
    import re

    words = [re.sub(r" ?\([a-z]\)$", "", r[-1]) for r in rows]      # the mark aside
    clauses = [c for cause in words if cause for c in cause.split("; ")]
    assert len(clauses) == len(set(clauses)), words
    negligible = [r for r in rows if r[1] == "negligible"]
    assert sum(str(v) == "negligible" for v in ds["dominance"].values) == len(negligible) > 2
    marks = {r[-1] for r in negligible if r[-2] != "\u2261 0"}
    assert len(marks) == 1 and marks.pop() in ctx["compare"]["note"]
    assert ctx["compare"]["note"].count("no part is ranked") == 1


def test_torque_offsets_get_a_column_and_the_note_says_so(drives):
    """A robot whose only drive term is a torque offset still has the drives table, with the
    offsets as stored (the dataset's torque_offset), and the note's tau_f names the offset."""
    from gd_analyze.report.main_context import _drives_context

    ds = drives[0].copy()
    n = ds.sizes["joint"]
    for v in ("D_arm", "viscous", "coulomb"):
        ds[v] = ds[v] * 0
    ds["torque_offset"] = ("joint", np.arange(1.0, n + 1))
    ctx = _drives_context(ds, list(ds["element"].values))
    assert ctx is not None and "offset" in ctx["note"]
    assert "offset" in ctx["table"]["header"]
    column = ctx["table"]["header"].index("offset")
    assert [float(r[column]) for r in ctx["table"]["rows"]] == list(np.arange(1.0, n + 1))
    ds["torque_offset"] = ds["torque_offset"] * 0
    assert _drives_context(ds, list(ds["element"].values)) is None
