"""The sweep report's figures as cited and placed: its text cites every figure by number ("Fig.
2 shows ..."), in the HTML and in the PDF's text layer, each figure is set on the page of its
first citation or the next, no page holds a figure alone (the PUMA 560's sweep over two
random trajectories ended on a page holding Fig. 4 and nothing else), and the last page is at
least a third full. The sentences that cite the share figures are checked against the stored
classes of every trajectory (sweep.h5's ``dominance`` and ``round_off``), not against the
report's own tables; Fig. 4's against the stored torque errors.
"""

import re

import numpy as np
import pytest
import xarray as xr
from html_checks import html_text
from pdf_checks import CITATION, figure_pages, last_page_fill, page_lines, text

from gd_analyze.report.typeset import MARGINS, NEAR_EMPTY

#: Over 5 s on an idle machine (the shared sweeps): run on one interpreter in CI.
pytestmark = pytest.mark.slow

#: A sweep whose classes change from one trajectory to another, and whose report ended on a
#: page holding Fig. 4 alone: the PUMA 560 over two random trajectories, all defaults.
_RANDOM = ("sweep", "puma560", "--random", "2")


@pytest.fixture(scope="module", params=["twice", "random"])
def report(request, shared_reports, shared_main):
    """(folder, stem) of a sweep report: the shared PUMA 560 sweep over its shipped trajectory
    twice, and :data:`_RANDOM` (run once a session, shared: read only)."""
    if request.param == "twice":
        return shared_reports["sweep"]
    return shared_main(*_RANDOM), "sweep_report"


def _figure_captions(html):
    """{n: the caption of Figure n, its words one space apart} of a report's HTML."""
    out = {}
    for c in re.findall(r"<figcaption>(.*?)</figcaption>", html, flags=re.S):
        words = " ".join(html_text(c, nbsp=True).split())
        m = re.match(r"Figure (\d+)\. ", words)
        if m:
            out[int(m.group(1))] = words
    return out


def test_every_figure_is_cited_in_the_html_text(report):
    folder, stem = report
    html = (folder / f"{stem}.html").read_text(encoding="utf-8")
    figures = sorted(_figure_captions(html))
    assert figures == [1, 2, 3, 4], figures
    # the text outside the captions cites each figure: "Fig. 2 shows ..."
    words = html_text(re.sub(r"<figcaption>.*?</figcaption>", "", html, flags=re.S))
    assert sorted({int(n) for n in CITATION.findall(words)}) == figures
    for n in figures:
        assert re.search(rf"\bFig\. {n} shows ", words), n


def test_every_figure_is_cited_in_the_pdf_text_layer(report):
    folder, stem = report
    cited, placed = figure_pages(page_lines(folder / f"{stem}.pdf", MARGINS[2]))
    assert sorted(placed) == [1, 2, 3, 4], placed
    assert sorted(cited) == sorted(placed), (cited, placed)
    assert all(re.search(rf"\bFig\. {n}\s+shows ", text(folder / f"{stem}.pdf"))
               for n in placed)


def test_every_figure_on_the_page_of_its_first_citation_or_the_next(report):
    folder, stem = report
    cited, placed = figure_pages(page_lines(folder / f"{stem}.pdf", MARGINS[2]))
    for n, page in placed.items():
        assert cited[n] <= page <= cited[n] + 1, (n, cited[n], page)


def test_no_page_holds_a_figure_alone(report):
    """No page holds a figure and its caption and nothing else: a page that ends with a
    figure's caption (its last lines are the caption's characters) has a heading, a table's
    caption or a citation above the figure."""
    folder, stem = report
    captions = _figure_captions((folder / f"{stem}.html").read_text(encoding="utf-8"))
    pages = page_lines(folder / f"{stem}.pdf", MARGINS[2])
    for k, lines in enumerate(pages, 1):
        starts = [i for i, line in enumerate(lines) if re.match(r"Figure \d+\. ", line)]
        if not starts:
            continue
        i = starts[-1]
        n = int(re.match(r"Figure (\d+)\. ", lines[i]).group(1))
        tail = " ".join(" ".join(lines[i:]).split())
        # the same characters (pdftotext sets a subscript on a line of its own, after its line)
        if sorted(tail.replace(" ", "")) != sorted(captions[n].replace(" ", "")):
            continue                        # text after the caption: not the figure alone
        own = [line for line in lines[:i]
               if re.match(r"(\d+(\.\d+)*\.? [A-Z]|Table \d+\.\d+: )", line)
               or CITATION.search(line)]
        assert own, (k, n, lines[:4])


def test_last_page_is_not_near_empty(report):
    folder, stem = report
    assert last_page_fill(folder / f"{stem}.pdf", MARGINS) >= NEAR_EMPTY


def _sentence(words, n):
    """The sentence that cites Fig. n."""
    return re.search(rf"Fig\. {n} shows (.*?\.)(?= [A-Z]|$)", words).group(1)


def test_share_figures_sentences_say_the_stored_classes(report, request):
    """The sentences of Figs. 1 and 2 name the elements that change class from one
    trajectory to another, and count those of one class on every trajectory, as sweep.h5's
    classes per trajectory give them (round-off on every trajectory counted apart)."""
    folder, stem = report
    words = html_text((folder / f"{stem}.html").read_text(encoding="utf-8"), nbsp=True)
    with xr.open_dataset(folder / "sweep.h5") as ds:
        labels = [str(x) for x in ds["element"].values]
        dominance = ds["dominance"].values.astype(str)          # (K, M)
        zero = ds["round_off"].values.astype(bool).all(axis=0)
    changing_anywhere = False
    for n, symbol in ((1, "D"), (2, "h")):
        said = _sentence(words, n)
        mine = [k for k, lab in enumerate(labels) if lab.startswith(symbol) and not zero[k]]
        varying = [labels[k] for k in mine if len(set(dominance[:, k])) > 1]
        steady = len(mine) - len(varying)
        changing_anywhere |= bool(varying)
        assert f"of each of the {sum(lab.startswith(symbol) for lab in labels)} elements" in said
        if varying:
            m = re.search(r"(\d+) changes? class from one trajectory to another \(([^)]*)\)",
                          said)
            assert m and int(m.group(1)) == len(varying), said
            named = [re.sub(r"\s", "", x) for x in re.split(r", | and ", m.group(2))]
            if "more" not in m.group(2):
                assert sorted(named) == sorted(varying), (named, varying)
        else:
            assert "none changes class" in said, said
        if steady:
            assert re.search(rf"\b{steady} (is|are) of one class on every trajectory", said), said
        off = [labels[k] for k in range(len(labels)) if zero[k] and labels[k].startswith(symbol)]
        assert ("round-off on every trajectory" in said) == bool(off), said
    if request.node.callspec.params["report"] == "random":     # its classes do change
        assert changing_anywhere


def test_error_figure_sentence_names_the_joints_where_the_merged_error_is_round_off(report):
    """Fig. 4's sentence: the merged model's largest relative peak error, as a percentage, and
    the joints on which it is round-off on every trajectory, from sweep.h5 (at most 1e-12 of the
    joint's or the arm's peak |tau| on every trajectory: nothing drawn there)."""
    folder, stem = report
    words = html_text((folder / f"{stem}.html").read_text(encoding="utf-8"), nbsp=True)
    said = _sentence(words, 4)
    with xr.open_dataset(folder / "sweep.h5") as ds:
        err = ds["merged_tau_error_peak"].values
        tau = ds["tau_peak"].values
    arm = tau.max(axis=1, keepdims=True)               # the PUMA 560: revolute joints only
    quiet = [j + 1 for j in range(err.shape[1])
             if np.all(err[:, j] <= 1e-12 * np.maximum(tau[:, j:j + 1], arm)[:, 0])]
    m = re.search(r"on joints? ([\d, ]+) the merged model's error is round-off", said)
    assert (sorted(map(int, m.group(1).split(", "))) if m else []) == \
        (quiet if len(quiet) < err.shape[1] else []), said
    assert re.search(r"the merged model's is at most [\d.]+ % of ", said), said


@pytest.mark.parametrize(("n", "width"), [(6, 7.2), (15, 7.2), (6, 3.5), (15, 3.5)])
def test_the_error_figures_joint_labels_and_notes_never_touch(n, width, monkeypatch):
    """Fig. 4 across a page for an arm of 15 joints read "joint 9joint 10oint 11": with its
    text raised to the printed minimum as the report draws it, and "round-off only" forced on
    every joint, it has no collision (tests/figure_checks.py); where even the note on its
    side is wider than a joint's room, the key names the joints instead. The golden PUMA 560
    sweep, its joints repeated to n."""
    import matplotlib
    from conftest import golden_run
    from figure_checks import collisions

    from gd_analyze.report import sweep
    from gd_analyze.report.figure_style import SUPTITLE_RC, raise_small_text
    from gd_analyze.report.typeset import MIN_PRINTED_PT, printed_scale
    from gd_analyze.store.schema import open_sweep

    roots, _ = golden_run("puma560-sweep")
    with open_sweep(roots[0] / "puma560-sweep" / "sweep.h5") as ds:
        ds = ds.load()
    ds = ds.isel(joint=np.arange(n) % ds.sizes["joint"]).assign_coords(
        joint=[f"j{k + 1}" for k in range(n)])
    monkeypatch.setattr(sweep, "ERROR_FLOOR", np.inf)        # every joint round-off only
    with matplotlib.rc_context(SUPTITLE_RC):
        fig = sweep._fig_error(sweep.StoredSweep.of(ds), width=width)
    raise_small_text(fig, MIN_PRINTED_PT / printed_scale(fig.get_size_inches()))
    found = [c for c in collisions(fig, SUPTITLE_RC) if "figure's edge" not in c]
    assert not found, found[:4]             # (a key past the edge makes the drawing taller)
    ax = fig.axes[0]
    notes = [t for t in ax.texts if "round-off" in t.get_text()]
    key = [t.get_text().replace("\n", " ") for t in ax.get_legend().get_texts()]
    listed = "round-off only at joints " + ", ".join(map(str, range(1, n + 1)))
    assert len(notes) == n or (not notes and listed in key), (n, width)
    assert (listed in key) == (not notes) and (notes or (n, width) == (15, 3.5))
    labels = [t.get_text() for t in ax.get_xticklabels()]
    assert labels == ([f"joint {k}" for k in range(1, n + 1)] if width == 7.2 and n == 6
                      else [str(k) for k in range(1, n + 1)])


def _tiled_sweep(n):
    """The golden PUMA 560 sweep made an arm of n joints: each element of D or h takes the
    data of one of the same kind, cyclically, each joint one joint's."""
    from conftest import golden_run

    from gd_analyze.ranking.ranking import element_label
    from gd_analyze.store.schema import open_sweep

    roots, _ = golden_run("puma560-sweep")
    with open_sweep(roots[0] / "puma560-sweep" / "sweep.h5") as ds:
        ds = ds.load()
    labels = [str(v) for v in ds["element"].values]
    D = [k for k, lab in enumerate(labels) if lab.startswith("D")]
    h = [k for k, lab in enumerate(labels) if lab.startswith("h")]
    new = [element_label("D", i, j) for i in range(n) for j in range(i, n)] + \
        [element_label("h", i) for i in range(n)]
    idx = [D[k % len(D)] for k in range(n * (n + 1) // 2)] + [h[k % len(h)] for k in range(n)]
    out = ds.isel(element=idx, joint=np.arange(n) % ds.sizes["joint"])
    return out.assign_coords(element=new, joint=[f"j{k + 1}" for k in range(n)])


def test_a_sweep_of_15_joints_is_drawn_in_parts_that_fit_a_page(tmp_path, monkeypatch):
    """The sweep report of a 15-joint arm drew D's 120 panels in one triangle 15.8 in tall
    (at its printed size every title ran into the next) and its class bars 20.4 in tall:
    each share and class figure now goes in parts no taller than MOST_HEIGHT, every element
    in exactly one, with no collision at the printed size; the report captions each part.
    The PUMA 560's keep one figure each, D in the layout of Fig. 3.10. The 15-joint figures
    checked are those the report made and drew (make_sweep_figures watched), not a second
    making of them."""
    import matplotlib
    from figure_checks import collisions

    from gd_analyze.report import sweep
    from gd_analyze.report.figure_style import SUPTITLE_RC, raise_small_text
    from gd_analyze.report.markup import plain
    from gd_analyze.report.typeset import MIN_PRINTED_PT, printed_scale
    from gd_analyze.store.schema import write_dataset

    ds = _tiled_sweep(15)
    path = tmp_path / "sweep.h5"
    write_dataset(ds, path)
    make, made = sweep.make_sweep_figures, []

    def watched(*args, **kwargs):
        made.append(make(*args, **kwargs))
        return made[-1]
    monkeypatch.setattr(sweep, "make_sweep_figures", watched)
    written = sweep.write_sweep_report(path, tmp_path / "out")
    (figs,) = made
    with matplotlib.rc_context(SUPTITLE_RC):
        six = make(_tiled_sweep(6))
    assert {k for k in six if k[0] in "Dhc"} == {"D", "h", "classes"}
    assert len(six["D"].axes) == 21                       # the triangle (its key a text)
    elements = [str(v) for v in ds["element"].values]
    counts = {}
    for key, kind in (("D", "D"), ("h", "h"), ("classes", "")):
        parts = [figs[key]] + [figs[f"{key}_{p}"] for p in range(2, 13) if f"{key}_{p}" in figs]
        assert len(parts) > 1, key
        counts[key] = len(parts)
        if kind:                                          # panel titles "D(3,12): keeps both"
            drawn = [plain(ax.get_title()).split(":")[0] for f in parts for ax in f.axes]
            want = [lab for lab in elements if lab.startswith(kind)]
            assert len(drawn) == len(want) and len(set(drawn)) == len(want), key
        else:
            drawn = [t.get_text() for f in parts for t in f.axes[0].get_yticklabels()]
            assert len(drawn) == len(elements) == len(set(drawn))
        for k, fig in enumerate(parts):
            assert fig.get_size_inches()[1] <= sweep.MOST_HEIGHT, (key, k)
            assert f"part {k + 1} of {len(parts)}" in fig._suptitle.get_text(), (key, k)
            raise_small_text(fig, MIN_PRINTED_PT / printed_scale(fig.get_size_inches()))
            found = [c for c in collisions(fig, SUPTITLE_RC) if "figure's edge" not in c]
            assert not found, (key, k, found[:3])
    names = {p.name for p in written}           # the parts drawn above, each a file
    d, c = counts["D"], counts["classes"]
    assert {f"fig_sweep_share_D_part{d}.pdf", f"fig_sweep_class_fractions_part{c}.svg"} <= names
    assert f"fig_sweep_share_D_part{d + 1}.pdf" not in names
    html = (tmp_path / "out" / "sweep_report.html").read_text(encoding="utf-8")
    assert f"Part 1 of {d}." in html and f"Part {d} of {d}." in html and f"Part {c} of {c}." in html
    # in the PDF each section starts after the last part of the figure before it (Sec. 3
    # was set on page 2, its figures on pages 10-11, D's parts floating past it); the pages'
    # text as poppler's pdftotext gives it (a form feed after each page): pypdf's extraction
    # of this report's 19 pages took longer than the rest of the checks
    pages = [re.sub(r"\s+", " ", t)
             for t in text(tmp_path / "out" / "sweep_report.pdf").split("\f")]

    def first(said):
        return min(k for k, t in enumerate(pages) if said in t)

    def last(said):
        return max(k for k, t in enumerate(pages) if said in t)
    figures = [m for t in pages for m in re.findall(r"Figure (\d+)\.", t)]
    assert figures == sorted(figures, key=int)                 # the figures in order
    assert first("3. Translational share of the elements of h") >= last(
        "Translational share of the elements of D over the sweep")      # the parts' titles
    assert first("4. Envelope per element") >= last(
        "Translational share of the elements of h over the sweep")
    assert first("5. Merged model") >= last("Dominance class per element over")


@pytest.mark.parametrize("fractions", [None, (0.0, 0.06, 0.9, 0.04), (0.04, 0.06, 0.86, 0.04)])
def test_the_share_figures_of_six_joints_have_no_collision_at_their_printed_size(fractions):
    """D and h at the page's width (D in the layout of Fig. 3.10) and a column's, with the
    golden sweep's class fractions, with three classes in every panel (R 6% \u00b7 B 90% \u00b7
    N 4%, as a 50-trajectory PUMA 560 sweep has: it ran into its neighbour, and the triangle's
    key into the diagonal's tick labels) and, at the page's width, with four: at the printed
    size the fractions go on more lines where one would reach the next panel's or the
    panel's own tick labels, and the key ends clear of them; no two texts overlap."""
    import matplotlib
    from figure_checks import collisions

    from gd_analyze.report import sweep
    from gd_analyze.report.figure_style import SUPTITLE_RC, raise_small_text
    from gd_analyze.report.typeset import MIN_PRINTED_PT, printed_scale

    ds = _tiled_sweep(6)
    if fractions is not None:
        ds["class_fraction"][:] = np.broadcast_to(fractions, ds["class_fraction"].shape)
    w = sweep.StoredSweep.of(ds)
    four = fractions is not None and min(fractions) > 0
    with matplotlib.rc_context(SUPTITLE_RC):
        figs = {f"{key} {width}": f for key in "Dh" for width in (sweep.PAGE_WIDTH, 3.5)
                if not (four and width < sweep.PAGE_WIDTH)
                for f in sweep._share_figures(w, key, width).values()}
    two = 0
    for key, fig in figs.items():
        raise_small_text(fig, MIN_PRINTED_PT / printed_scale(fig.get_size_inches()))
        found = [c for c in collisions(fig, SUPTITLE_RC) if "figure's edge" not in c]
        assert not found, (key, found[:3])
        two += sum("\n" in ax.get_xlabel() for ax in fig.axes)
    assert (two > 0) == (fractions is not None)
